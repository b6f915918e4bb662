#!/usr/bin/env bash
# Tunnelling benchmark: how often a cloth shot at a thin plate ends on its
# far side, for each broad/narrow combination, as V*dt/L_ce grows past 1.
#
# The scene (generated here): a flat 4 x 4 cloth at 5 mm, no gravity, shot
# straight down at speed V onto a [mesh] plate of zero thickness, a 60 mm
# square in the plane y = 0 meshed at the cloth's own 5 mm (so that the chapter's hash, which puts nodes in cubes, has plate
# vertices near every cloth node). The step dt and the cube edge L_ce
# (`cell`) are fixed, V = ratio * L_ce / dt. Each run lasts the time the
# cloth would need to fly as far past the plate as it started above it, so
# a node below y = 0 in the final OBJ went through. BENCH_OFFSETS runs per
# speed and combination shift the cloth sideways (against the cubes) and in
# height (against the steps) by a fraction of a cube and of a step.
#
# Tunnelling rate = nodes below the plate at the end / nodes shot, over the
# offsets. The counts are exact (runs are deterministic): no medians.
# Data go to $BENCH_OUT/tunnel.csv (per speed and combination) and
# tunnel-runs.csv (every run); with gnuplot, the chart to tunnel.png and a
# text chart on stdout. See bench/README.md.
#
# Environment:
#   BENCH_RATIOS    the V*dt/L_ce values (default "0.01 0.03 0.1 0.2 0.3 0.5 0.7 1 1.5 2 3 5 7 10")
#   BENCH_OFFSETS   runs per ratio and combination (default 4)
#   BENCH_POSITION  the position policy of every run (default slide)
#   BENCH_OUT       output directory (default bench/results)
#   BENCH_JOBS      runs at once (default: one a core; bench/sweep.sh -j)
#   BENCH_SWEEP_ARGS  more options for bench/sweep.sh, e.g. "-S 8/node1,:"
#   DRAPE           the binary (default src/drape)
#   BENCH_SRCDIR    the source tree (default: this script's ..)
#   GNUPLOT         the gnuplot to draw the chart with (default gnuplot)
set -u

here=$(cd "$(dirname "$0")" && pwd)
srcdir=${BENCH_SRCDIR:-$(cd "$here/.." && pwd)}
drape=${DRAPE:-$srcdir/src/drape}
out=${BENCH_OUT:-$srcdir/bench/results}
ratios=${BENCH_RATIOS:-0.01 0.03 0.1 0.2 0.3 0.5 0.7 1 1.5 2 3 5 7 10}
noff=${BENCH_OFFSETS:-4}
position=${BENCH_POSITION:-slide}

die() { echo "tunnel.sh: $*" >&2; exit 2; }
case $noff in '' | *[!0-9]* | 0) die "BENCH_OFFSETS must be a whole number > 0, not '$noff'" ;; esac
case $position in keep | q | slide) ;; *) die "BENCH_POSITION is keep, q or slide, not '$position'" ;; esac
for r in $ratios; do
	awk -v t="$r" 'BEGIN { exit !(t + 0 > 0 && t ~ /^[0-9.eE+-]+$/) }' ||
		die "BENCH_RATIOS are numbers > 0, not '$r'"
done
[ -x "$drape" ] || die "no binary at $drape: build first (make), or set DRAPE"
mkdir -p "$out" || die "cannot create $out"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/drape-bench.XXXXXX") || die "mktemp failed"
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM

# geometry, in mm and s
h=5          # cloth spacing
nc=4         # cloth nodes per side
cell=5       # L_ce
dt=0.0001    # the step
np=12        # plate squares per side (60 mm at 5 mm)
combos="seed/seed seed/ccd grid/seed grid/ccd"

# the plate: (np+1)^2 vertices in y = 0, two triangles a square
awk -v n="$np" -v h="$h" 'BEGIN {
	print "# tunnel.sh: a plate of " n " x " n " squares of " h " mm in the plane y = 0"
	o = -n * h / 2
	for (j = 0; j <= n; j++) for (i = 0; i <= n; i++)
		printf "v %.6f 0 %.6f\n", (o + i * h) / 1000, (o + j * h) / 1000
	for (j = 0; j < n; j++) for (i = 0; i < n; i++) {
		a = j * (n + 1) + i + 1
		print "f", a, a + 1, a + n + 2; print "f", a, a + n + 2, a + n + 1
	}
}' >"$tmp/plate.obj"

scene() { # broad narrow v_m_s x0_mm y0_mm
	cat <<EOF
[simulation]
name = tunnel
duration = 10 s
dt = $dt s
integrator = rk4
gravity = 0 0 0 m/s2

[cloth]
nodes = $nc $nc
spacing = $h mm
origin = $4 $5 $4 mm
orientation = +x +z
velocity = 0 -$3 0 m/s
weight = 150 g/m2
thickness = 0.5 mm
modulus_warp = 0.45 MPa
modulus_weft = 0.45 MPa
shear_modulus = 9 kPa
bending_warp = 3 uN*m
bending_weft = 3 uN*m

[mesh]
file = $tmp/plate.obj

[collision]
self = on
broad = $1
narrow = $2
position = $position
cell = $cell mm
EOF
}

version=$("$drape" --version 2>/dev/null | head -n 1)
commit=$(git -C "$srcdir" rev-parse --short HEAD 2>/dev/null || echo "?")
stamp=$(date -u '+%Y-%m-%d %H:%M UTC')
nn=$((nc * nc))

echo "tunnelling benchmark: $version (commit $commit), $stamp"
echo "a $nc x $nc cloth at $h mm shot at a plate meshed at $h mm; dt $dt s, L_ce = cell = $cell mm, position $position;"
echo "$noff offsets per speed; rate = nodes through the plate / nodes shot ($nn a run)"
echo

runf=$out/tunnel-runs.csv
echo "ratio,v_m_s,broad,narrow,offset,x0_mm,y0_mm,until_s,exit,nodes_through,nodes,contacts" >"$runf"
# every run is independent: all of them, as the rows of one sweep through
# bench/sweep.sh (GNU parallel, BENCH_JOBS at a time, default a job a
# core); meta.txt keeps each row's ratio, offset and times
rowsf=$tmp/rows.tsv metaf=$tmp/meta.txt
printf 'collision.broad\tcollision.narrow\tcloth.velocity\tcloth.origin\tsimulation.duration\n' >"$rowsf"
: >"$metaf"
for r in $ratios; do
	v=$(awk -v r="$r" -v c="$cell" -v dt="$dt" 'BEGIN { printf "%.6g", r * c / 1000 / dt }')
	for k in $(seq 0 $((noff - 1))); do
		f=$(awk -v k="$k" -v n="$noff" 'BEGIN { printf "%.6g", k / n }')
		# sideways: 0.3 mm off the plate's vertices, plus f of a cube;
		# height: at least 20 mm and 3 steps' travel above, plus f of a step
		x0=$(awk -v f="$f" -v h="$h" -v n="$nc" -v c="$cell" 'BEGIN { printf "%.6g", -(n - 1) * h / 2 + 0.3 + f * c }')
		y0=$(awk -v f="$f" -v r="$r" -v c="$cell" 'BEGIN { s = r * c; y = 20; if (3 * s > y) y = 3 * s; printf "%.6g", y + f * s }')
		until_t=$(awk -v y="$y0" -v v="$v" 'BEGIN { printf "%.6g", 2 * y / 1000 / v }')
		for bn in $combos; do
			b=${bn%/*} n=${bn#*/}
			printf '%s\t%s\t0 -%s 0 m/s\t%s %s %s mm\t%s s\n' "$b" "$n" "$v" "$x0" "$y0" "$x0" "$until_t" >>"$rowsf"
			echo "$r $v $b $n $k $x0 $y0 $until_t" >>"$metaf"
		done
	done
done
scene grid ccd 1 0 20 >"$tmp/run.scene"
jobs=()
[ -n "${BENCH_JOBS:-}" ] && jobs=(-j "$BENCH_JOBS")
read -r -a more <<<"${BENCH_SWEEP_ARGS:-}"
DRAPE=$drape "$here/sweep.sh" -q -o "$tmp/sweep" -r "$rowsf" "${jobs[@]}" "${more[@]}" \
	"$tmp/run.scene" -- --final-obj '{job}/final.obj'
[ $? -le 1 ] || die "bench/sweep.sh failed"
bad=0
"$here/csvcols.sh" -d $'\037' "$tmp/sweep/results.csv" job exit error collisions.node_node \
	collisions.node_edge collisions.node_face collisions.edge_edge collisions.obstacle |
	paste -d $'\037' - "$metaf" |
while IFS=$'\037' read -r job rc err c1 c2 c3 c4 c5 meta; do
	read -r r v b n k x0 y0 until_t <<<"$meta"
	ct=$(awk -v a="$c1" -v b="$c2" -v c="$c3" -v d="$c4" -v e="$c5" 'BEGIN { if (a != "") print a + b + c + d + e }')
	case $rc in
	0) thr=$(awk '$1 == "v" && $3 < 0 { n++ } END { print n + 0 }' "$tmp/sweep/jobs/$job/final.obj") ;;
	3) thr=- ;;
	*)
		thr=-
		echo "tunnel.sh: ratio $r $b/$n offset $k: drape exited ${rc:-?}: $err" >&2
		;;
	esac
	echo "$r,$v,$b,$n,$k,$x0,$y0,$until_t,${rc:--},$thr,$nn,${ct:--}" >>"$runf"
done
awk -F, 'NR > 1 && $9 != 0 && $9 != 3 { bad = 1 } END { exit !bad }' "$runf" && bad=1

# per ratio and combination: the rate over the offsets that ran through
datf=$out/tunnel.csv
echo "ratio,v_m_s,broad,narrow,runs,blowups,runs_with_tunnelling,nodes_through,nodes_shot,rate" >"$datf"
awk -F, -v combos="$combos" 'NR > 1 {
	key = $1 SUBSEP $3 "/" $4
	if (!(($1) in seenr)) { seenr[$1] = 1; order[++nr] = $1; vel[$1] = $2 }
	runs[key]++
	if ($9 == 3) blow[key]++
	else if ($9 == 0) { thr[key] += $10; shot[key] += $11; if ($10 > 0) any[key]++ }
}
END {
	nb = split(combos, cb, " ")
	for (i = 1; i <= nr; i++) for (c = 1; c <= nb; c++) {
		key = order[i] SUBSEP cb[c]; split(cb[c], bn, "/")
		rate = shot[key] > 0 ? sprintf("%.4f", thr[key] / shot[key]) : "-"
		printf "%s,%s,%s,%s,%d,%d,%d,%d,%d,%s\n", order[i], vel[order[i]], bn[1], bn[2], runs[key], blow[key], any[key], thr[key], shot[key], rate
	}
}' "$runf" >>"$datf"

# text table: one row per ratio, one column per combination
awk -F, -v combos="$combos" 'NR > 1 {
	if (!($1 in seen)) { seen[$1] = 1; order[++n] = $1; vel[$1] = $2 }
	cell[$1, $3 "/" $4] = ($10 == "-" ? "-" : sprintf("%5.1f%%", 100 * $10)) ($6 > 0 ? " (" $6 " blew up)" : "")
}
END {
	nb = split(combos, cb, " ")
	printf "%-12s %8s", "V*dt/L_ce", "V (m/s)"; for (c = 1; c <= nb; c++) printf " %12s", cb[c]; print ""
	for (i = 1; i <= n; i++) {
		printf "%-12s %8s", order[i], vel[order[i]]
		for (c = 1; c <= nb; c++) printf " %12s", cell[order[i], cb[c]]
		print ""
	}
}' "$datf"
cat <<EOF

columns: broad/narrow phase; figures: tunnelling rate, the share of the
  cloth's nodes below the plate at the end, over $noff offsets.
data: $datf (per ratio), $runf (every run)
EOF

prog=tunnel.sh
. "$here/plot.sh"
plot tunnel.gp "$datf" "$out/tunnel.png" "noff='$noff'; position='$position'; stamp='$stamp'" || bad=1
exit $bad

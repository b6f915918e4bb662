#!/usr/bin/env bash
# Scaling: wall time per simulated second and peak memory of the tablecloth
# scene at N x N nodes (default 25, 50, 100, 200), with self-collision on
# (grid + ccd, the scene's own setting) and off (self = off: the box and
# the floor only), and the least-squares slope of log time against log
# nodes.
#
# The scenes are the tablecloth made bigger at the same 10 mm spacing: the
# same material, the same dt (set by the spacing and the stiffness), the
# cloth's origin and the box's horizontal extents scaled by (N - 1) / 24,
# their heights kept, so that the cloth meets the box at the same time
# (about 0.08 s) whatever its size. Writes scaling.csv, scaling-fit.csv and
# scaling.png under BENCH_RESULTS; prints the table and a dumb-terminal
# chart. See bench/README.md.
#
# Environment:
#   BENCH_RUNS     runs per size and mode (default 3); the figures are medians
#   BENCH_SCALING_SIZES    nodes per side (default "25 50 100 200")
#   BENCH_SCALING_UNTIL    simulated seconds of each run (default 0.1)
#   BENCH_RESULTS  output directory (default bench/results)
#   DRAPE, BENCH_SRCDIR, GNUPLOT
set -u
prog=scaling.sh
. "$(cd "$(dirname "$0")" && pwd)/lib.sh"
sizes=${BENCH_SCALING_SIZES:-25 50 100 200}
until_t=${BENCH_SCALING_UNTIL:-0.1}
check_seconds "$until_t" BENCH_SCALING_UNTIL
timebin=/usr/bin/time
[ -x "$timebin" ] || die "$timebin not found (it gives the peak memory): sudo apt-get install -y time"
src=$srcdir/scenes/tablecloth.scene
[ -r "$src" ] || die "no scene $src"

echo "scaling: $version (commit $commit), $stamp"
echo "machine: $ncpu cores, ${cpu:-unknown cpu}; load $(load)"
echo "tablecloth at N x N nodes, 10 mm spacing; median of $runs runs of $until_t s simulated"
echo

for n in $sizes; do
	case $n in '' | *[!0-9]* | 0 | 1) die "BENCH_SCALING_SIZES are whole numbers > 1, not '$n'" ;; esac
	k=$(awk -v n="$n" 'BEGIN { printf "%.6g", (n - 1) / 24 }')
	o=$(awk -v k="$k" 'BEGIN { printf "%.6g 0.15 %.6g m", -0.12 * k, -0.12 * k }')
	bmin=$(awk -v k="$k" 'BEGIN { printf "0 0 %.6g m", -0.08 * k }')
	bmax=$(awk -v k="$k" 'BEGIN { printf "%.6g 0.12 %.6g m", 0.14 * k, 0.06 * k }')
	for self in on off; do
		edit_scene "$src" "cloth.nodes=$n $n" "cloth.origin=$o" "box.min=$bmin" "box.max=$bmax" \
			"collision.self=$self" >"$tmp/$n-$self.scene"
	done
done

rawf=$tmp/runs
: >"$rawf"
bad=0
for r in $(seq 1 "$runs"); do
	for n in $sizes; do
		for self in on off; do
			[ -t 2 ] && printf '\r  run %d: %s^2 self %s          ' "$r" "$n" "$self" >&2
			"$timebin" -f %M -o "$tmp/mem" "$drape" run --headless --until "$until_t" "$tmp/$n-$self.scene" \
				>"$tmp/out" 2>"$tmp/err"
			rc=$?
			case $rc in 0 | 3) ;; *) bad=1; { echo "$prog: $n $self: drape run exited $rc:"; cat "$tmp/err"; } >&2 ;; esac
			mem=$(awk '/^[0-9]+$/ { m = $1 } END { print (m == "" ? "-" : m) }' "$tmp/mem")
			echo "$n $self $r $rc $mem $(parse_summary <"$tmp/out")" >>"$rawf"
		done
	done
done
[ -t 2 ] && printf '\r%50s\r' '' >&2

csv=$results/scaling.csv
echo "side,nodes,self,status,dt_s,steps,wall_per_sim,ms_per_step,ns_per_step_node,peak_mib" >"$csv"
printf '%6s %7s %4s %-7s %10s %7s %10s %9s %12s %9s\n' side nodes self status dt steps wall/sim ms/step ns/step/node peak-MiB
for self in on off; do
	for n in $sizes; do
		rows=$(awk -v n="$n" -v s="$self" '$1 == n && $2 == s' "$rawf")
		status=ok
		awk '$4 == 3 { f = 1 } END { exit !f }' <<<"$rows" && status=blowup
		awk '$4 != 0 && $4 != 3 { f = 1 } END { exit !f }' <<<"$rows" && status=error
		dt=$(awk 'NR == 1 { print $9 }' <<<"$rows")
		steps=$(awk 'NR == 1 { print $8 }' <<<"$rows")
		wps=$(awk '$4 == 0 && $6 > 0 { printf "%.6g\n", $7 / $6 }' <<<"$rows" | median)
		mps=$(awk '$4 == 0 && $8 > 0 { printf "%.6g\n", 1000 * $7 / $8 }' <<<"$rows" | median)
		npn=$(awk -v n="$n" '$4 == 0 && $8 > 0 { printf "%.6g\n", 1e9 * $7 / $8 / (n * n) }' <<<"$rows" | median)
		mem=$(awk '$5 != "-" { printf "%.4g\n", $5 / 1024 }' <<<"$rows" | median)
		echo "$n,$((n * n)),$self,$status,$dt,$steps,$wps,$mps,$npn,$mem" >>"$csv"
		printf '%6s %7s %4s %-7s %10s %7s %10s %9s %12s %9s\n' "$n" $((n * n)) "$self" "$status" "$dt" "$steps" "$wps" "$mps" "$npn" "$mem"
	done
done

# least squares of log(wall/sim) on log(nodes), per mode
fitf=$results/scaling-fit.csv
echo "self,slope,intercept,points" >"$fitf"
for self in on off; do
	awk -F, -v s="$self" 'NR > 1 && $3 == s && $4 == "ok" && $7 > 0 {
		x = log($2); y = log($7); n++; sx += x; sy += y; sxx += x * x; sxy += x * y
	}
	END {
		if (n < 2) { print s ",-,-," n + 0; exit }
		b = (n * sxy - sx * sy) / (n * sxx - sx * sx); a = (sy - b * sx) / n
		printf "%s,%.4f,%.6g,%d\n", s, b, a, n
	}' "$csv" >>"$fitf"
done
slope_on=$(awk -F, '$1 == "on" { print $2 }' "$fitf"); int_on=$(awk -F, '$1 == "on" { print $3 }' "$fitf")
slope_off=$(awk -F, '$1 == "off" { print $2 }' "$fitf"); int_off=$(awk -F, '$1 == "off" { print $3 }' "$fitf")
nan() { case $1 in '' | -) echo NaN ;; *) echo "$1" ;; esac; }
t100=$(awk -F, '$1 == 100 && $3 == "on" { print $7 }' "$csv")
cat <<EOF

slope of log(wall s per simulated s) against log(nodes), least squares:
  self on:  $slope_on     self off: $slope_off     (1 = time per step linear in nodes; dt is the same at every size)
target: 100 x 100 at most 5 s of wall time per simulated second: ${t100:-not measured} s (self on)
wall/sim: wall seconds per simulated second; ms/step and ns/step/node: wall
  time over steps (over steps and nodes); peak-MiB: maximum resident set
  (/usr/bin/time -f %M), medians of $runs runs of $until_t s simulated.
load average at the end: $(load) ($ncpu cores)
data: $csv, $fitf
EOF
plot scaling.gp "$csv" "$results/scaling.png" \
	"stamp='$stamp'; runs='$runs'; until_t='$until_t'; s_on=$(nan "$slope_on"); a_on=$(nan "$int_on"); s_off=$(nan "$slope_off"); a_off=$(nan "$int_off")" || bad=1
exit $bad

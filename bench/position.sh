#!/usr/bin/env bash
# Position policy benchmark: the chapter's method on its Fig. 11 strip
# (scenes/strip.scene with broad = seed, narrow = seed) with
# position = keep (back to step k's position) against position = q (moved
# to the contact point Q), and the scene's own grid/ccd/slide as the
# reference: the total energy over time, and where each blows up.
#
# For each policy it runs `drape run --headless --until T` for T = STEP,
# 2 STEP, ... UNTIL (runs are deterministic: one run per point) and reads
# the summary's energy line; a run that blows up (exit 3) gives the
# blow-up time from drape's message and the energy of the last good state,
# and the later points of that policy are not run. Data go to
# $BENCH_OUT/position.csv; with gnuplot, the chart to position.png and a
# text chart on stdout. See bench/README.md.
#
# Environment:
#   BENCH_POSITION_UNTIL  the last time (default 1 s; the strip folds from 0.5 s)
#   BENCH_POSITION_STEP   the spacing of the times (default 0.05 s)
#   BENCH_POLICIES  which of keep q slide ref to run (default "keep q ref";
#                   slide = seed/seed/slide, ref = grid/ccd/slide)
#   BENCH_OUT       output directory (default bench/results)
#   BENCH_JOBS      runs at once (default: one a core; bench/sweep.sh -j)
#   BENCH_SWEEP_ARGS  more options for bench/sweep.sh, e.g. "-S 8/node1,:"
#   DRAPE           the binary (default src/drape)
#   BENCH_SRCDIR    the source tree, for scenes/ (default: this script's ..)
#   GNUPLOT         the gnuplot to draw the chart with (default gnuplot)
set -u

here=$(cd "$(dirname "$0")" && pwd)
srcdir=${BENCH_SRCDIR:-$(cd "$here/.." && pwd)}
drape=${DRAPE:-$srcdir/src/drape}
out=${BENCH_OUT:-$srcdir/bench/results}
until_t=${BENCH_POSITION_UNTIL:-1}
step=${BENCH_POSITION_STEP:-0.05}
policies=${BENCH_POLICIES:-keep q ref}

die() { echo "position.sh: $*" >&2; exit 2; }
for v in "$until_t" "$step"; do
	awk -v t="$v" 'BEGIN { exit !(t + 0 > 0 && t ~ /^[0-9.eE+-]+$/) }' ||
		die "BENCH_POSITION_UNTIL and BENCH_POSITION_STEP are seconds > 0, not '$v'"
done
[ -x "$drape" ] || die "no binary at $drape: build first (make), or set DRAPE"
[ -r "$srcdir/scenes/strip.scene" ] || die "no scene $srcdir/scenes/strip.scene"
mkdir -p "$out" || die "cannot create $out"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/drape-bench.XXXXXX") || die "mktemp failed"
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM
# the chapter's integrator: the shipped strip runs the fast path (issue 14)
src=$tmp/strip.scene
sed -e 's/^integrator = fast$/integrator = rk4/' -e 's/^broad = bvh$/broad = grid/' \
	"$srcdir/scenes/strip.scene" >"$src" || die "cannot write $src"
grep -q "^integrator = rk4" "$src" || die "could not set rk4 in $src"

settings() { # policy -> broad narrow position
	case $1 in
	keep) echo seed seed keep ;;
	q) echo seed seed q ;;
	slide) echo seed seed slide ;;
	ref) echo grid ccd slide ;;
	*) die "BENCH_POLICIES are keep, q, slide and ref, not '$1'" ;;
	esac
}
for p in $policies; do
	read -r b n pos <<<"$(settings "$p")"
	awk -v b="$b" -v n="$n" -v p="$pos" '
	/^[ \t]*\[/ { sec = $0; sub(/^[ \t]*\[/, "", sec); sub(/\].*/, "", sec) }
	sec == "collision" && /^[ \t]*broad[ \t]*=/ { print "broad = " b; next }
	sec == "collision" && /^[ \t]*narrow[ \t]*=/ { print "narrow = " n; next }
	sec == "collision" && /^[ \t]*position[ \t]*=/ { print "position = " p; next }
	{ print }' "$src" >"$tmp/$p.scene"
	grep -q "^broad = $b" "$tmp/$p.scene" && grep -q "^narrow = $n" "$tmp/$p.scene" &&
		grep -q "^position = $pos" "$tmp/$p.scene" || die "could not edit $src for $p"
done

version=$("$drape" --version 2>/dev/null | head -n 1)
commit=$(git -C "$srcdir" rev-parse --short HEAD 2>/dev/null || echo "?")
stamp=$(date -u '+%Y-%m-%d %H:%M UTC')
times=$(awk -v u="$until_t" -v s="$step" 'BEGIN { for (k = 1; k * s <= u * (1 + 1e-9); k++) printf "%.6g\n", k * s }')

echo "position policy benchmark on scenes/strip.scene: $version (commit $commit), $stamp"
echo "energy at t = $step, $(awk -v s="$step" 'BEGIN { printf "%.6g", 2 * s }'), ... $until_t s, one run each"
echo

datf=$out/position.csv
echo "policy,broad,narrow,position,t_s,status,energy_J,kinetic_J,wall_s" >"$datf"
# Each point is its own run, through bench/sweep.sh (GNU parallel,
# BENCH_JOBS at a time; default a job a core), in two sweeps so that no run
# is made that the loop of one run after another would not make: first the
# last time of each policy, which says whether and when it blows up; then
# the earlier times, of a policy that blows up only those before its
# blow-up (a run is deterministic: a later one would stop at the same
# step, and its row is the first sweep's).
jobs=()
[ -n "${BENCH_JOBS:-}" ] && jobs=(-j "$BENCH_JOBS")
read -r -a more <<<"${BENCH_SWEEP_ARGS:-}"
last=$(printf '%s\n' $times | tail -n 1)
sweep_rows() { # dir rows: the sweep, then its rows as
	# "broad narrow position t exit total kinetic wall failure_t error" (\037)
	DRAPE=$drape "$here/sweep.sh" -q -o "$1" -r "$2" "${jobs[@]}" "${more[@]}" "$src"
	[ $? -le 1 ] || die "bench/sweep.sh failed"
	"$here/csvcols.sh" -d $'\037' "$1/results.csv" collision.broad collision.narrow \
		collision.position simulation.duration exit energy.total energy.kinetic time.wall \
		failure.t error
}
header=$(printf 'collision.broad\tcollision.narrow\tcollision.position\tsimulation.duration')
{ echo "$header"; for p in $policies; do read -r b n pos <<<"$(settings "$p")"; printf '%s\t%s\t%s\t%s s\n' "$b" "$n" "$pos" "$last"; done; } >"$tmp/last.tsv"
sweep_rows "$tmp/last" "$tmp/last.tsv" >"$tmp/last.rows"
echo "$header" >"$tmp/early.tsv"
i=0
for p in $policies; do
	i=$((i + 1))
	read -r b n pos <<<"$(settings "$p")"
	IFS=$'\037' read -r _ _ _ _ rc _ _ _ ft _ <<<"$(sed -n "${i}p" "$tmp/last.rows")"
	for t in $times; do
		[ "$t" = "$last" ] && continue
		case $rc in
		0) ;;
		3) awk -v t="$t" -v f="$ft" 'BEGIN { exit !(t <= f) }' || continue ;;
		*) continue ;;
		esac
		printf '%s\t%s\t%s\t%s s\n' "$b" "$n" "$pos" "$t" >>"$tmp/early.tsv"
	done
done
if [ "$(wc -l <"$tmp/early.tsv")" -gt 1 ]; then sweep_rows "$tmp/early" "$tmp/early.tsv" >"$tmp/early.rows"
else : >"$tmp/early.rows"; fi
bad=0
# the rows in the loop's order: each policy's times, then its last or its blow-up
for p in $policies; do
	read -r b n pos <<<"$(settings "$p")"
	cat "$tmp/early.rows" "$tmp/last.rows" |
	while IFS=$'\037' read -r rb rn rpos t rc et ek wall ft err; do
		[ "$rb $rn $rpos" = "$b $n $pos" ] || continue
		t=${t% s}	# the grid's duration, with its unit
		# the summary's figures: total %.6e, kinetic %.4e
		en=$(awk -v e="$et" -v k="$ek" 'BEGIN { if (e == "") print "-,-"; else printf "%.6e,%.4e\n", e, k }')
		wall=$(awk -v w="$wall" 'BEGIN { printf "%.2f", w }')
		case $rc in
		0) echo "$p,$b,$n,$pos,$t,ok,$en,$wall" >>"$datf" ;;
		3)
			tb=$(printf '%s\n' "$err" | sed -n 's/.*blow-up at step [0-9]* (t = \([0-9.eE+-]*\) s).*/\1/p')
			printf '%s\n' "$err" | sed "s|$src|$p.scene|" >"$tmp/$p.blowup"
			echo "$p,$b,$n,$pos,${tb:-$t},blowup,$en,$wall" >>"$datf"
			;;
		*)
			echo "position.sh: $p t=$t: drape exited ${rc:-?}: $err" >&2
			echo 1 >"$tmp/bad"
			;;
		esac
	done
done
[ -e "$tmp/bad" ] && bad=1
[ -t 2 ] && printf '\r%60s\r' '' >&2

# text table: one row per time, one column per policy
awk -F, -v pols="$policies" 'NR > 1 {
	if (!($5 in seen)) { seen[$5] = 1; ts[++n] = $5 }
	v[$5, $1] = ($6 == "ok" ? sprintf("%.4e", $7) : "BLEW UP")
}
END {
	np = split(pols, pl, " ")
	printf "%-8s", "t (s)"; for (c = 1; c <= np; c++) printf " %14s", pl[c]; print ""
	for (i = 1; i <= n; i++) { t = ts[i]; printf "%-8s", t; for (c = 1; c <= np; c++) printf " %14s", ((t, pl[c]) in v ? v[t, pl[c]] : ""); print "" }
}' <(head -n 1 "$datf"; tail -n +2 "$datf" | sort -t, -k5,5g)
echo
for p in $policies; do
	read -r b n pos <<<"$(settings "$p")"
	if [ -r "$tmp/$p.blowup" ]; then
		echo "$p ($b/$n/$pos): BLEW UP: $(cat "$tmp/$p.blowup")"
	else
		echo "$p ($b/$n/$pos): ran to $until_t s"
	fi
done
cat <<EOF

energy: the summary's total (kinetic + gravity + stretch + shear + bend +
  load) in J; the feeders lower the strip, so it falls slowly without a
  blow-up. keep and q: broad seed, narrow seed (the chapter's method);
  ref: the scene's own grid/ccd/slide.
data: $datf
EOF

prog=position.sh
. "$here/plot.sh"
plot position.gp "$datf" "$out/position.png" "pols='$policies'; stamp='$stamp'" || bad=1
exit $bad

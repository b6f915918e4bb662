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
src=$srcdir/scenes/strip.scene
[ -r "$src" ] || die "no scene $src"
mkdir -p "$out" || die "cannot create $out"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/drape-bench.XXXXXX") || die "mktemp failed"
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM

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
bad=0
for p in $policies; do
	read -r b n pos <<<"$(settings "$p")"
	for t in $times; do
		[ -t 2 ] && printf '\r  %s: t = %s s          ' "$p" "$t" >&2
		s0=$(date +%s.%N)
		"$drape" run --headless --until "$t" "$tmp/$p.scene" >"$tmp/stdout" 2>"$tmp/stderr"
		rc=$?
		wall=$(awk -v a="$s0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
		en=$(awk '/^energy / { e = $2; k = $5; sub(/,$/, "", k); print e "," k }' "$tmp/stdout")
		[ -n "$en" ] || en="-,-"
		case $rc in
		0) echo "$p,$b,$n,$pos,$t,ok,$en,$wall" >>"$datf" ;;
		3)
			tb=$(sed -n 's/.*blow-up at step [0-9]* (t = \([0-9.eE+-]*\) s).*/\1/p' "$tmp/stderr" | head -n 1)
			sed "s|$tmp/||" "$tmp/stderr" | head -n 1 >"$tmp/$p.blowup"
			echo "$p,$b,$n,$pos,${tb:-$t},blowup,$en,$wall" >>"$datf"
			break
			;;
		*)
			bad=1
			{ echo; echo "position.sh: $p t=$t: drape exited $rc:"; sed 's/^/  /' "$tmp/stderr"; } >&2
			break
			;;
		esac
	done
done
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

#!/usr/bin/env bash
# Collision accuracy against cost: broad seed / grid / brute x narrow
# seed / ccd on the strip and the tablecloth, over a short --until (brute
# is slow), against brute + ccd as the ground truth.
#
# Per scene and mode: `drape check --every N` on a copy of the scene edited
# to the mode (its duration cut to the run's T) counts the intersecting
# triangle pairs per audited frame; `drape run --headless --until T` gives
# the time per step (wall time / steps, median of BENCH_RUNS runs, the modes
# interleaved) and the contacts found. The audits run on the second core
# while the timed runs run on the first. Writes accuracy.csv and
# accuracy.png under BENCH_RESULTS; prints the table and a dumb-terminal
# chart. See bench/README.md.
#
# Environment:
#   BENCH_RUNS        timed runs per scene and mode (default 3)
#   BENCH_BRUTE_RUNS  timed runs of the brute modes (default 1: they are slow)
#   BENCH_ACCURACY_SCENES      "scene:T ..." (default "strip:0.53 tablecloth:0.2")
#   BENCH_ACCURACY_EVERY       audit every Nth output frame (default 2: 25 audits/s)
#   BENCH_RESULTS     output directory (default bench/results)
#   DRAPE, BENCH_SRCDIR, GNUPLOT
set -u
prog=accuracy.sh
. "$(cd "$(dirname "$0")" && pwd)/lib.sh"
brute_runs=${BENCH_BRUTE_RUNS:-1}
scenes=${BENCH_ACCURACY_SCENES:-strip:0.53 tablecloth:0.2}
every=${BENCH_ACCURACY_EVERY:-2}
case $brute_runs in '' | *[!0-9]* | 0) die "BENCH_BRUTE_RUNS must be a whole number > 0" ;; esac
case $every in '' | *[!0-9]* | 0) die "BENCH_ACCURACY_EVERY must be a whole number > 0" ;; esac

modes="seed-seed seed-ccd grid-seed grid-ccd brute-seed brute-ccd"

echo "collision accuracy against cost: $version (commit $commit), $stamp"
echo "machine: $ncpu cores, ${cpu:-unknown cpu}; load $(load)"
echo "timed runs: median of $runs (brute: $brute_runs); audit every $every output frames"
echo

# scene copies, and the audits in the background (one at a time)
: >"$tmp/checks"
for st in $scenes; do
	sc=${st%%:*}; t=${st#*:}
	check_seconds "$t" "the T of $sc"
	src=$(chapter_scene "$sc")
	[ -r "$src" ] || die "no scene $srcdir/scenes/$sc.scene"
	for m in $modes; do
		edit_scene "$src" "simulation.duration=$t s" "collision.self=on" \
			"collision.broad=${m%-*}" "collision.narrow=${m#*-}" "collision.position=slide" \
			>"$tmp/$sc-$m.scene"
		echo "$sc-$m" >>"$tmp/checks"
	done
done
(
	while read -r f; do
		"$drape" check --every "$every" "$tmp/$f.scene" >"$tmp/$f.check" 2>"$tmp/$f.checkerr"
		echo $? >"$tmp/$f.checkrc"
	done <"$tmp/checks"
) &
checker=$!

rawf=$tmp/runs
: >"$rawf"
bad=0
maxr=$runs; [ "$brute_runs" -gt "$maxr" ] && maxr=$brute_runs
for r in $(seq 1 "$maxr"); do
	for st in $scenes; do
		sc=${st%%:*}; t=${st#*:}
		for m in $modes; do
			n=$runs; case $m in brute-*) n=$brute_runs ;; esac
			[ "$r" -le "$n" ] || continue
			run_once "$sc" "$m" "$t" "$r"
		done
	done
done
[ -t 2 ] && printf '\r  waiting for the audits...          ' >&2
wait "$checker"
[ -t 2 ] && printf '\r%50s\r' '' >&2

csv=$results/accuracy.csv
echo "scene,mode,broad,narrow,until_s,status,ms_per_step,steps,contacts,self_contacts,contacts_vs_truth,frames,bad_frames,pairs_per_frame,max_pairs,blowup_t_s" >"$csv"
printf '%-10s %-10s %5s %-8s %9s %9s %9s %7s %6s %8s %8s\n' scene broad-nrw T status ms/step contacts /truth frames bad pairs/fr max
for st in $scenes; do
	sc=${st%%:*}; t=${st#*:}
	truth=$(awk -v s="$sc" '$1 == s && $2 == "brute-ccd" && $4 == 0 { print $9; exit }' "$rawf")
	for m in $modes; do
		rows=$(awk -v s="$sc" -v m="$m" '$1 == s && $2 == m' "$rawf")
		status=ok
		awk '$4 == 3 { f = 1 } END { exit !f }' <<<"$rows" && status=blowup
		awk '$4 != 0 && $4 != 3 { f = 1 } END { exit !f }' <<<"$rows" && status=error
		mps=$(awk '$4 == 0 && $7 > 0 { printf "%.6g\n", 1000 * $6 / $7 }' <<<"$rows" | median)
		steps=$(awk 'NR == 1 { print $7 }' <<<"$rows")
		ct=$(awk 'NR == 1 { print $9 }' <<<"$rows")
		sct=$(awk 'NR == 1 { print $10 }' <<<"$rows")
		bt=-
		if [ $status = blowup ]; then
			bt=$(sed -n 's/.*(t = \([0-9.eE+-]*\) s).*/\1/p' "$tmp/$sc-$m.blowup" | head -n 1)
			[ -n "$bt" ] || bt=$(awk 'NR == 1 { print $5 }' <<<"$rows")
			mps=-; ct=-; sct=-
		fi
		vs=-
		[ "$ct" != - ] && [ -n "$truth" ] && [ "$truth" != 0 ] && vs=$(awk -v a="$ct" -v b="$truth" 'BEGIN { printf "%.4g", a / b }')
		# the audit: frames audited (last line), pairs summed over the frames that found some
		crc=$(cat "$tmp/$sc-$m.checkrc" 2>/dev/null || echo 9)
		read -r frames badf maxp < <(awk -F'\t' '$2 == "scene" { print $3, $4, $5 }' "$tmp/$sc-$m.check")
		sump=$(awk -F'\t' '$2 ~ /^t=/ { s += $5 } END { print s + 0 }' "$tmp/$sc-$m.check")
		ppf=-
		[ -n "${frames:-}" ] && [ "$frames" -gt 0 ] && ppf=$(awk -v a="$sump" -v b="$frames" 'BEGIN { printf "%.4g", a / b }')
		case $crc in 0 | 4) ;; 3) [ $status = ok ] && status=blowup ;; *) status=error; bad=1 ;; esac
		echo "$sc,$m,${m%-*},${m#*-},$t,$status,$mps,$steps,$ct,$sct,$vs,${frames:--},${badf:--},$ppf,${maxp:--},$bt" >>"$csv"
		printf '%-10s %-10s %5s %-8s %9s %9s %9s %7s %6s %8s %8s%s\n' "$sc" "$m" "$t" "$status" "$mps" "$ct" "$vs" \
			"${frames:--}" "${badf:--}" "$ppf" "${maxp:--}" "$([ "$bt" = - ] || echo "  blew up at t = $bt s")"
		frames=; badf=; maxp=
	done
done
cat <<EOF

modes: broad-narrow, position slide, self on. ms/step: wall ms per step,
  median of $runs timed runs (brute: $brute_runs). contacts: the run's summary
  (self and obstacle); /truth: over brute-ccd's of the same scene and T.
frames: frames audited by drape check --every $every (over the same T); bad:
  those with intersecting triangle pairs (or nodes inside an obstacle);
  pairs/fr: intersecting pairs summed over the frames / frames; max: most in
  one frame. A blow-up stops the run and its audit (its frames are those
  before it).
load average at the end: $(load) ($ncpu cores)
data: $csv
EOF
ntruth=$(awk -F, 'NR > 1 && $6 == "ok" && $11 != "-"' "$csv" | wc -l)
plot accuracy.gp "$csv" "$results/accuracy.png" "stamp='$stamp'; runs='$runs'; every='$every'; ntruth=$ntruth" || bad=1
exit $bad

#!/usr/bin/env bash
# Model no more than a scene needs: the strip and the tablecloth with
# bending, shear, self-collision or friction switched off, one at a time
# and all together, against the full scene: what each costs (the wall time
# over the full scene's in the same round, median over the rounds) and what
# it changes (the final gravitational energy, the contacts, and the
# intersecting triangle pairs drape check finds).
#
# Writes needs.csv and needs.png under BENCH_RESULTS; prints the table and
# a dumb-terminal chart. See bench/README.md.
#
# Environment:
#   BENCH_RUNS     timed runs per scene and variant (default 3)
#   BENCH_NEEDS_SCENES   "scene:T ..." (default "strip:1 tablecloth:1")
#   BENCH_NEEDS_EVERY    audit every Nth output frame (default 5: every 0.1 s)
#   BENCH_RESULTS  output directory (default bench/results)
#   DRAPE, BENCH_SRCDIR, GNUPLOT
set -u
prog=needs.sh
. "$(cd "$(dirname "$0")" && pwd)/lib.sh"
scenes=${BENCH_NEEDS_SCENES:-strip:1 tablecloth:1}
every=${BENCH_NEEDS_EVERY:-5}
case $every in '' | *[!0-9]* | 0) die "BENCH_NEEDS_EVERY must be a whole number > 0" ;; esac

variants="full no-bending no-shear self-off no-friction all-off"
edits() { # variant -> the edit_scene arguments
	case $1 in
	full) ;;
	no-bending) echo "cloth.bending_warp=0 uN*m"; echo "cloth.bending_weft=0 uN*m" ;;
	no-shear) echo "cloth.shear_modulus=0 kPa" ;;
	self-off) echo "collision.self=off" ;;
	no-friction) echo "collision.friction=0"; echo "plane.friction=0" ;;
	all-off) for v in no-bending no-shear self-off no-friction; do edits $v; done ;;
	esac
}

echo "what a scene needs: $version (commit $commit), $stamp"
echo "machine: $ncpu cores, ${cpu:-unknown cpu}; load $(load)"
echo "timed runs: median of $runs, variants interleaved; audit every $every output frames"
echo

: >"$tmp/checks"
for st in $scenes; do
	sc=${st%%:*}; t=${st#*:}
	check_seconds "$t" "the T of $sc"
	src=$(chapter_scene "$sc")
	[ -r "$src" ] || die "no scene $srcdir/scenes/$sc.scene"
	for v in $variants; do
		mapfile -t e < <(edits $v)
		edit_scene "$src" "simulation.duration=$t s" ${e[@]+"${e[@]}"} >"$tmp/$sc-$v.scene"
		echo "$sc-$v" >>"$tmp/checks"
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
for r in $(seq 1 "$runs"); do
	for st in $scenes; do
		sc=${st%%:*}; t=${st#*:}
		for v in $variants; do
			run_once "$sc" "$v" "$t" "$r"
		done
	done
done
[ -t 2 ] && printf '\r  waiting for the audits...          ' >&2
wait "$checker"
[ -t 2 ] && printf '\r%50s\r' '' >&2

csv=$results/needs.csv
echo "scene,variant,until_s,status,wall_per_sim,ratio_to_full,dt_s,steps,gravity_j,gravity_change_pct,contacts,self_contacts,frames,bad_frames,max_pairs" >"$csv"
printf '%-10s %-11s %-7s %9s %7s %10s %11s %8s %9s %7s %6s %6s\n' scene variant status wall/sim ratio dt gravity-J change contacts frames bad maxpr
for st in $scenes; do
	sc=${st%%:*}; t=${st#*:}
	gfull=$(awk -v s="$sc" '$1 == s && $2 == "full" && $4 == 0 { print $11; exit }' "$rawf")
	for v in $variants; do
		rows=$(awk -v s="$sc" -v m="$v" '$1 == s && $2 == m' "$rawf")
		status=ok
		awk '$4 == 3 { f = 1 } END { exit !f }' <<<"$rows" && status=blowup
		awk '$4 != 0 && $4 != 3 { f = 1 } END { exit !f }' <<<"$rows" && status=error
		wps=$(awk '$4 == 0 && $5 > 0 { printf "%.6g\n", $6 / $5 }' <<<"$rows" | median)
		ratio=$(awk -v s="$sc" -v m="$v" '
			$1 == s && $2 == "full" && $4 == 0 && $5 > 0 { base[$3] = $6 / $5 }
			$1 == s && $2 == m && $4 == 0 && $5 > 0 { this[$3] = $6 / $5 }
			END { for (r in this) if ((r in base) && base[r] > 0) printf "%.6g\n", this[r] / base[r] }' "$rawf" | median)
		dt=$(awk 'NR == 1 { print $8 }' <<<"$rows")
		steps=$(awk 'NR == 1 { print $7 }' <<<"$rows")
		g=$(awk 'NR == 1 { print $11 }' <<<"$rows")
		ct=$(awk 'NR == 1 { print $9 }' <<<"$rows")
		sct=$(awk 'NR == 1 { print $10 }' <<<"$rows")
		gc=-
		[ $status = ok ] && [ -n "$gfull" ] && [ "$g" != - ] &&
			gc=$(awk -v a="$g" -v b="$gfull" 'BEGIN { printf "%+.3g", 100 * (a - b) / b }')
		[ $status = ok ] || { wps=-; ratio=-; }
		read -r frames badf maxp < <(awk -F'\t' '$2 == "scene" { print $3, $4, $5 }' "$tmp/$sc-$v.check")
		crc=$(cat "$tmp/$sc-$v.checkrc" 2>/dev/null || echo 9)
		case $crc in 0 | 4) ;; 3) [ $status = ok ] && status=blowup ;; *) status=error; bad=1 ;; esac
		echo "$sc,$v,$t,$status,$wps,$ratio,$dt,$steps,$g,$gc,$ct,$sct,${frames:--},${badf:--},${maxp:--}" >>"$csv"
		printf '%-10s %-11s %-7s %9s %7s %10s %11s %8s %9s %7s %6s %6s%s\n' "$sc" "$v" "$status" "$wps" "$ratio" \
			"$dt" "$g" "$gc" "$ct" "${frames:--}" "${badf:--}" "${maxp:--}" \
			"$([ $status = blowup ] && echo "  $(cat "$tmp/$sc-$v.blowup" 2>/dev/null)")"
		frames=; badf=; maxp=
	done
done
cat <<EOF

variants: no-bending = bending_warp = bending_weft = 0; no-shear =
  shear_modulus = 0; self-off = [collision] self = off (obstacles kept);
  no-friction = friction 0 in [collision] and [plane]; all-off = all four.
wall/sim: wall s per simulated s, median of $runs; ratio: over the full
  scene's in the same round, median over the rounds. dt: the automatic step.
gravity-J: the final gravitational energy (the cloth's height), change: over
  the full scene's; contacts: over the run. frames, bad, maxpr: drape check
  --every $every: frames audited, frames with intersecting triangle pairs or
  nodes in an obstacle, the most intersecting pairs in one frame.
load average at the end: $(load) ($ncpu cores)
data: $csv
EOF
plot needs.gp "$csv" "$results/needs.png" "stamp='$stamp'; runs='$runs'" || bad=1
exit $bad

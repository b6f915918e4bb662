#!/usr/bin/env bash
# Collision speed benchmark: what each broad/narrow phase costs, on the
# chapter's two scenes, against the same scene with no collisions at all.
#
# For each scene and mode it runs `drape run --headless --until T` on a
# temporary copy of the scene, edited to the mode, BENCH_RUNS times (the
# modes interleaved, so that a slow spell of this shared machine hits them
# all alike), and prints the medians. Writes collide.csv (medians),
# collide-runs.csv (every run) and collide.png under BENCH_RESULTS; prints
# the table and a dumb-terminal chart. See bench/README.md.
#
# Environment:
#   BENCH_RUNS        runs per scene and mode (default 3)
#   BENCH_UNTIL       simulated time of each run (default 1 s: both scenes
#                     are in self-contact by then)
#   BENCH_BRUTE_UNTIL simulated time of the brute runs (default 0.1 s)
#   BENCH_SCENES      scene names under scenes/ (default "tablecloth strip")
#   BENCH_RESULTS     output directory (default bench/results)
#   DRAPE, BENCH_SRCDIR, GNUPLOT
set -u
prog=collide.sh
. "$(cd "$(dirname "$0")" && pwd)/lib.sh"
until_t=${BENCH_UNTIL:-1}
brute_t=${BENCH_BRUTE_UNTIL:-0.1}
scenes=${BENCH_SCENES:-tablecloth strip}
check_seconds "$until_t" BENCH_UNTIL
check_seconds "$brute_t" BENCH_BRUTE_UNTIL
[ -n "${scenes// /}" ] || die "BENCH_SCENES is empty"

modes="none self-off chapter seed grid brute"
edits() { # mode -> the edit_scene arguments
	case $1 in
	# nothing to collide with: the forces and the integrator alone
	none) for s in collision plane box sphere disc mesh icosahedron; do echo "$s.=drop"; done ;;
	self-off) echo "collision.self=off" ;;
	chapter) printf '%s\n' collision.self=on collision.broad=seed collision.narrow=seed collision.position=keep ;;
	*) printf '%s\n' collision.self=on "collision.broad=$1" collision.narrow=ccd collision.position=slide ;;
	esac
}
mode_t() { if [ "$1" = brute ]; then echo "$brute_t"; else echo "$until_t"; fi; }

echo "collision benchmark: $version (commit $commit), $stamp"
echo "machine: $ncpu cores, ${cpu:-unknown cpu}; load $(load)"
echo "runs: median of $runs per scene and mode; simulated $until_t s (brute: the first $brute_t s only, it is slow)"
echo

for sc in $scenes; do
	src=$(chapter_scene "$sc")
	[ -r "$src" ] || die "no scene $srcdir/scenes/$sc.scene"
	for m in $modes; do
		mapfile -t e < <(edits "$m")
		edit_scene "$src" ${e[@]+"${e[@]}"} >"$tmp/$sc-$m.scene"
	done
done

rawf=$tmp/runs
: >"$rawf"
bad=0
for r in $(seq 1 "$runs"); do
	for sc in $scenes; do
		for m in $modes; do
			run_once "$sc" "$m" "$(mode_t "$m")" "$r"
		done
	done
done
[ -t 2 ] && printf '\r%60s\r' '' >&2

# rawf: 1 scene 2 mode 3 round 4 exit 5 simulated 6 wall 7 steps 8 dt
# 9 contacts 10 self 11 gravity 12 steps/s 13 node 14 vt 15 ee 16 narrow 17 cpu
runsf=$results/collide-runs.csv
echo "scene,mode,round,until_s,exit,simulated_s,wall_s,cpu_s,steps,steps_per_s,node_pairs,vt_pairs,ee_pairs,narrow_tests,contacts,self_contacts,obstacle_contacts" >"$runsf"
awk -v ut="$until_t" -v bt="$brute_t" '{
	ob = ($9 == "-" || $10 == "-") ? "-" : $9 - $10
	print $1, $2, $3, ($2 == "brute" ? bt : ut), $4, $5, $6, $17, $7, $12, $13, $14, $15, $16, $9, $10, ob
}' OFS=, "$rawf" >>"$runsf"

# ratio: median over the rounds of (this mode's time / simulated) over the
# none run's of the same round
ratio_of() { # scene mode column-of-the-time
	awk -v s="$1" -v m="$2" -v c="$3" '
	$1 == s && $2 == "none" && $4 == 0 && $5 > 0 && $c != "-" { base[$3] = $c / $5 }
	$1 == s && $2 == m && $4 == 0 && $5 > 0 && $c != "-" { this[$3] = $c / $5 }
	END { for (r in this) if ((r in base) && base[r] > 0) printf "%.6g\n", this[r] / base[r] }
	' "$rawf" | median
}
csv=$results/collide.csv
echo "scene,mode,until_s,status,wall_per_sim,ratio,cpu_per_sim,cpu_ratio,steps_per_s,node_pairs,vt_pairs,ee_pairs,narrow_tests,contacts,self_contacts,obstacle_contacts,blowup_t_s" >"$csv"
hdr='%-10s %-9s %5s %9s %7s %8s %7s %8s %10s %10s %10s %8s %8s\n'
printf "$hdr" scene mode T wall/sim ratio cpu/sim ratio steps/s vt/step ee/step narrow/st self obstacle
printf "$hdr" '' '' '(s)' '(s/s)' /none '(s/s)' /none '' pairs pairs tests contacts contacts
for sc in $scenes; do
	for m in $modes; do
		t=$(mode_t "$m")
		rows=$(awk -v s="$sc" -v m="$m" '$1 == s && $2 == m' "$rawf")
		nrc=$(awk '$4 != 0' <<<"$rows" | wc -l)
		status=ok
		awk '$4 == 3 { f = 1 } END { exit !f }' <<<"$rows" && status=blowup
		awk '$4 != 0 && $4 != 3 { f = 1 } END { exit !f }' <<<"$rows" && status=error
		# the counts of one run: the runs are bit-identical, only the times vary
		col() { awk -v c="$1" '$4 == 0 { print $c; exit }' <<<"$rows"; }
		bt=-
		if [ $status = ok ]; then
			wps=$(awk '$5 > 0 { printf "%.6g\n", $6 / $5 }' <<<"$rows" | median)
			cps=$(awk '$5 > 0 && $17 != "-" { printf "%.6g\n", $17 / $5 }' <<<"$rows" | median)
			ratio=$(ratio_of "$sc" "$m" 6)
			cratio=$(ratio_of "$sc" "$m" 17)
			sps=$(awk '$4 == 0 { print $12 }' <<<"$rows" | median)
			np=$(col 13); vt=$(col 14); ee=$(col 15); nt=$(col 16)
			ct=$(col 9); sct=$(col 10)
			oct=$(awk '$4 == 0 { print $9 - $10; exit }' <<<"$rows")
		else
			wps=-; ratio=-; cps=-; cratio=-; sps=-; np=-; vt=-; ee=-; nt=-; ct=-; sct=-; oct=-
			[ $status = blowup ] &&
				bt=$(sed -n 's/.*(t = \([0-9.eE+-]*\) s).*/\1/p' "$tmp/$sc-$m.blowup" 2>/dev/null | head -n 1)
		fi
		echo "$sc,$m,$t,$status,$wps,$ratio,$cps,$cratio,$sps,$np,$vt,$ee,$nt,$ct,$sct,$oct,${bt:--}" >>"$csv"
		case $status in
		ok)
			printf '%-10s %-9s %5s %9.4g %6.3gx %8.4g %6.3gx %8.0f %10.1f %10.1f %10.1f %8s %8s\n' \
				"$sc" "$m" "$t" "$wps" "$ratio" "$cps" "$cratio" "$sps" "$vt" "$ee" "$nt" "$sct" "$oct"
			;;
		blowup)
			printf '%-10s %-9s %5s BLEW UP (exit 3) in %d of %d runs: %s\n' "$sc" "$m" "$t" \
				"$nrc" "$runs" "$(cat "$tmp/$sc-$m.blowup" 2>/dev/null)"
			;;
		*)
			printf '%-10s %-9s %5s FAILED (drape exit status other than 0 or 3; see above)\n' "$sc" "$m" "$t"
			;;
		esac
	done
done
cat <<EOF

modes: none = no [collision] and no obstacles (forces and integrator alone);
  self-off = obstacles only (self = off); chapter = broad seed, narrow seed,
  position keep (the chapter's method); seed, grid, brute = that broad phase
  with narrow ccd and position slide, self on.
wall/sim: wall seconds per simulated second (lower is faster); ratio: that
  over the none run of the same round, median over the rounds; cpu/sim and
  its ratio: the same with the run's CPU time (user + system), which other
  jobs on a busy machine inflate less than the wall time.
vt, ee, narrow: vertex-triangle and edge-edge candidate pairs and narrow tests
  per step (averages over a run); contacts: over the whole run (they grow with
  T, so brute's, over its shorter T, are not comparable with the others').
brute ran only the first $brute_t s of each scene (the others $until_t s).
load average at the end: $(load) ($ncpu cores)
data: $csv, $runsf
EOF
plot collide.gp "$csv" "$results/collide.png" \
	"stamp='$stamp'; runs='$runs'; ncpu='$ncpu'; until_t='$until_t'; brute_t='$brute_t'" || bad=1
exit $bad

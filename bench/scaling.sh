#!/usr/bin/env bash
# Scaling: wall time per simulated second and peak memory of the tablecloth
# scene at N x N nodes (default 25, 50, 100, 200), with self-collision on
# (grid + ccd, the scene's own setting) and off (self = off: the box and
# the floor only), and the least-squares slope of log time against log
# nodes; for each integrator of BENCH_SCALING_INTEGRATORS (the chapter's
# rk4, whose step stiffness sets, implicit-euler, whose step is half a
# spacing at the scene's speed scale, and fast, the one the tablecloth
# ships with: leaving it out charted every integrator but the one a user
# runs).
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
#   BENCH_SCALING_INTEGRATORS  (default "rk4 implicit-euler fast"; bdf2 may be added)
#   BENCH_RESULTS  output directory (default bench/results)
#   DRAPE, BENCH_SRCDIR, GNUPLOT
set -u
prog=scaling.sh
. "$(cd "$(dirname "$0")" && pwd)/lib.sh"
sizes=${BENCH_SCALING_SIZES:-25 50 100 200}
until_t=${BENCH_SCALING_UNTIL:-0.1}
integs=${BENCH_SCALING_INTEGRATORS:-rk4 implicit-euler fast}
for m in $integs; do
	case $m in euler | symplectic-euler | rk2 | rk4 | dopri5 | implicit-euler | fast | bdf2) ;;
	*) die "BENCH_SCALING_INTEGRATORS: no integrator '$m'" ;; esac
done
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
	for self in on off; do
		scaled_tablecloth "$n" "collision.self=$self" >"$tmp/$n-$self.scene"
	done
done

# Every size at the step its smallest size takes: the explicit methods'
# depends on the spacing and stiffness only, but implicit-euler's on the
# scene's speed scale, which grows with the cloth's diagonal; at one step
# the slope measures the cost of a step alone.
first=${sizes%% *}
dtargs=""
for m in $integs; do
	dt=$("$drape" run --headless --integrator "$m" --until 1e-9 "$tmp/$first-on.scene" 2>/dev/null |
		awk '/^integrator / { for (i = 2; i <= NF; i++) if ($i == "dt") print $(i + 1) }')
	[ -n "$dt" ] || die "cannot read $m's automatic dt at $first^2"
	dtargs="$dtargs $m=$dt"
done
dt_of() { for a in $dtargs; do [ "${a%%=*}" = "$1" ] && echo "${a#*=}"; done; }

rawf=$tmp/runs
: >"$rawf"
bad=0
for r in $(seq 1 "$runs"); do
	for n in $sizes; do
		for m in $integs; do
			for self in on off; do
				[ -t 2 ] && printf '\r  run %d: %s^2 %s self %s          ' "$r" "$n" "$m" "$self" >&2
				"$timebin" -f %M -o "$tmp/mem" "$drape" run --headless --integrator "$m" \
					--dt "$(dt_of "$m")" --until "$until_t" "$tmp/$n-$self.scene" >"$tmp/out" 2>"$tmp/err"
				rc=$?
				case $rc in 0 | 3) ;; *) bad=1; { echo "$prog: $n $m $self: drape run exited $rc:"; cat "$tmp/err"; } >&2 ;; esac
				mem=$(awk '/^[0-9]+$/ { m = $1 } END { print (m == "" ? "-" : m) }' "$tmp/mem")
				echo "$n $m/$self $r $rc $mem $(parse_summary <"$tmp/out")" >>"$rawf"
			done
		done
	done
done
[ -t 2 ] && printf '\r%50s\r' '' >&2

csv=$results/scaling.csv
echo "side,nodes,integrator,self,status,dt_s,steps,wall_per_sim,ms_per_step,ns_per_step_node,peak_mib" >"$csv"
printf '%6s %7s %-14s %4s %-7s %10s %7s %10s %9s %12s %9s\n' side nodes integrator self status dt steps wall/sim ms/step ns/step/node peak-MiB
modes=$(for m in $integs; do echo "$m/on $m/off"; done)
for mode in $modes; do
	m=${mode%/*} self=${mode#*/}
	for n in $sizes; do
		rows=$(awk -v n="$n" -v s="$mode" '$1 == n && $2 == s' "$rawf")
		status=ok
		awk '$4 == 3 { f = 1 } END { exit !f }' <<<"$rows" && status=blowup
		awk '$4 != 0 && $4 != 3 { f = 1 } END { exit !f }' <<<"$rows" && status=error
		dt=$(awk 'NR == 1 { print $9 }' <<<"$rows")
		steps=$(awk 'NR == 1 { print $8 }' <<<"$rows")
		wps=$(awk '$4 == 0 && $6 > 0 { printf "%.6g\n", $7 / $6 }' <<<"$rows" | median)
		mps=$(awk '$4 == 0 && $8 > 0 { printf "%.6g\n", 1000 * $7 / $8 }' <<<"$rows" | median)
		npn=$(awk -v n="$n" '$4 == 0 && $8 > 0 { printf "%.6g\n", 1e9 * $7 / $8 / (n * n) }' <<<"$rows" | median)
		mem=$(awk '$5 != "-" { printf "%.4g\n", $5 / 1024 }' <<<"$rows" | median)
		echo "$n,$((n * n)),$m,$self,$status,$dt,$steps,$wps,$mps,$npn,$mem" >>"$csv"
		printf '%6s %7s %-14s %4s %-7s %10s %7s %10s %9s %12s %9s\n' "$n" $((n * n)) "$m" "$self" "$status" "$dt" "$steps" "$wps" "$mps" "$npn" "$mem"
	done
done

# least squares of log(wall/sim) on log(nodes), per mode
fitf=$results/scaling-fit.csv
echo "integrator,self,slope,intercept,points" >"$fitf"
for mode in $modes; do
	awk -F, -v m="${mode%/*}" -v s="${mode#*/}" 'NR > 1 && $3 == m && $4 == s && $5 == "ok" && $8 > 0 {
		x = log($2); y = log($8); n++; sx += x; sy += y; sxx += x * x; sxy += x * y
	}
	END {
		if (n < 2) { print m "," s ",-,-," n + 0; exit }
		b = (n * sxy - sx * sy) / (n * sxx - sx * sx); a = (sy - b * sx) / n
		printf "%s,%s,%.4f,%.6g,%d\n", m, s, b, a, n
	}' "$csv" >>"$fitf"
done
echo
echo "slope of log(wall s per simulated s) against log(nodes), least squares"
echo "(1 = time per step linear in nodes; every size at the smallest's automatic step):"
awk -F, 'NR > 1 { printf "  %-14s self %-3s  slope %s (%s sizes)\n", $1, $2, $3, $5 }' "$fitf"
echo "targets, self on: 25 x 25 at most 0.05 s and 100 x 100 at most 5 s of wall time per simulated second:"
awk -F, 'NR > 1 && $4 == "on" && ($1 == 25 || $1 == 100) { printf "  %3d^2 %-14s %s s\n", $1, $3, $8 }' "$csv"
cat <<EOF
wall/sim: wall seconds per simulated second; ms/step and ns/step/node: wall
  time over steps (over steps and nodes); peak-MiB: maximum resident set
  (/usr/bin/time -f %M), medians of $runs runs of $until_t s simulated.
load average at the end: $(load) ($ncpu cores)
data: $csv, $fitf
EOF
plot scaling.gp "$csv" "$results/scaling.png" \
	"stamp='$stamp'; runs='$runs'; until_t='$until_t'" || bad=1
exit $bad

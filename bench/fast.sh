#!/usr/bin/env bash
# The fast path's targets (issue 14), each printed as measured against its
# target, with the ratio to RK4 measured in the same round:
#   1. the shipped tablecloth (2 s) and strip (3 s), whole, with rk4,
#      implicit-euler and fast taken in turn in each round: wall time,
#      times real time, the ratio to RK4 of that round; targets 20x and
#      10x real time for fast;
#   2. fast audited on every output frame (drape check --every 1):
#      intersecting pairs and nodes inside obstacles, target 0;
#   3. what speed costs in shape: the final cloth against RK4's (centroid,
#      top of the pile, spread over the floor), charted as wall time
#      against the distance from RK4's centroid;
#   4. the tablecloth at 25^2 .. 200^2 nodes (10 mm spacing, box scaled as
#      bench/scaling.sh does) with fast, with the grid (as measured before
#      the scenes shipped bvh) and with bvh (as they ship): wall per
#      simulated second (targets 5 s at 100^2 and 25 s at 200^2) and the
#      log-log slope of time per step against nodes (target at most 1.1);
#   5. refinement at fixed size: the peers' 0.24 m table
#      (../shared/reference/peers.md) at 25^2, 50^2, 100^2 over its first
#      0.25 s: the growth of wall time per 4x nodes (target at most 4x),
#      fast and implicit-euler;
#   6. soft fabrics: the tablecloth and the peers' table with bending 0.1,
#      1 and 10 uN*m and no damping, to the end with fast: finished,
#      blew up or hung (BENCH_FAST_HANG seconds);
#   7. numerical damping: the energy the undamped hanging strip keeps
#      above rest after 1 s, fast and implicit-euler against RK4;
#   8. the step: fast (bvh) at 5 to 160 ms on both scenes, timed and
#      audited on every frame: the largest step before it misbehaves.
#   9. the TUI on the shipped tablecloth at 80 x 24 (tmux): the speed its
#      status line shows once the run has ended; target at least real time.
#  10. the floor: both scenes with fast as shipped and with self-contact
#      off (the substeps and the analytic obstacles alone), against the
#      wall time the speed targets allow.
# The side-by-side runs of Blender and Bullet are not measured here
# (bench/peers.sh).
# Timing runs one job at a time.
#
# Writes fast.csv (whole runs), fast-scaling.csv, fast-refine.csv,
# fast-steps.csv and
# fast.png (wall per simulated second against the shape's distance from
# RK4) under BENCH_RESULTS.
#
# Environment:
#   BENCH_RUNS        rounds (default 3); the figures are medians
#   BENCH_FAST_SIZES  nodes per side for 4 (default "25 50 100 200")
#   BENCH_FAST_UNTIL  simulated seconds for 4 and 5 (default 0.25)
#   BENCH_FAST_HANG   seconds after which a run of 6 counts as hung
#                     (default 600)
#   BENCH_FAST_SKIP   parts to leave out, e.g. "4 5 6 7"
#   BENCH_RESULTS, DRAPE, BENCH_SRCDIR, GNUPLOT
set -u
prog=fast.sh
. "$(cd "$(dirname "$0")" && pwd)/lib.sh"
sizes=${BENCH_FAST_SIZES:-25 50 100 200}
until_t=${BENCH_FAST_UNTIL:-0.25}
hang=${BENCH_FAST_HANG:-600}
skip=" ${BENCH_FAST_SKIP:-} "
check_seconds "$until_t" BENCH_FAST_UNTIL
check_seconds "$hang" BENCH_FAST_HANG
for n in $sizes; do
	case $n in '' | *[!0-9]* | 0 | 1) die "BENCH_FAST_SIZES are whole numbers > 1, not '$n'" ;; esac
done
command -v timeout >/dev/null || die "timeout(1) not found (coreutils)"
integs="rk4 implicit-euler fast"
# the whole runs also take fast with the tree broad phase, which the
# shipped scenes (broad = grid, the chapter's kind) do not choose
whole="$integs fast+bvh"
opts_of() { case $1 in *+bvh) echo "--set collision.broad=bvh" ;; *) echo "--set collision.broad=grid" ;; esac; }
want() { case $skip in *" $1 "*) return 1 ;; esac; return 0; }

echo "fast: $version (commit $commit), $stamp"
echo "machine: $ncpu cores, ${cpu:-unknown cpu}; load $(load)"
echo "median of $runs rounds; in each round the integrators run one after another"
echo

# centroid x y z, top y, rms horizontal radius about the centroid, of an OBJ
shape_of() {
	awk '$1 == "v" { n++; x[n] = $2; y[n] = $3; z[n] = $4; sx += $2; sy += $3; sz += $4
		if (n == 1 || $3 > top) top = $3 }
	END { cx = sx / n; cy = sy / n; cz = sz / n
		for (i = 1; i <= n; i++) r += (x[i] - cx) ^ 2 + (z[i] - cz) ^ 2
		printf "%.6f %.6f %.6f %.6f %.6f\n", cx, cy, cz, top, sqrt(r / n) }' "$1"
}

# ---- 1 and 3: whole runs ----
csv=$results/fast.csv
if want 1; then
	raw=$tmp/whole.txt
	: >"$raw"
	for r in $(seq 1 "$runs"); do
		for s in tablecloth strip; do
			for m in $whole; do
				[ -t 2 ] && printf '\r  round %d: %s %s          ' "$r" "$s" "$m" >&2
				"$drape" run --headless --integrator "${m%+bvh}" $(opts_of "$m") \
					--final-obj "$tmp/$s-$m.obj" "$srcdir/scenes/$s.scene" >"$tmp/out" 2>"$tmp/err"
				rc=$?
				w=$(wall_of <"$tmp/out")
				sim=$(awk '/^simulated / { print $2 }' "$tmp/out")
				echo "$s $m $r $rc ${w:--} ${sim:--}" >>"$raw"
				[ $rc = 0 ] && [ "$r" = 1 ] && shape_of "$tmp/$s-$m.obj" >"$tmp/$s-$m.shape"
				[ $rc = 0 ] || { echo "$prog: $s $m exited $rc:"; head -n 3 "$tmp/err"; } >&2
			done
		done
	done
	[ -t 2 ] && printf '\r%60s\r' '' >&2
	echo "scene,integrator,wall_s,sim_s,x_real,ratio_rk4,centroid_dist_mm,top_mm,spread_mm,status" >"$csv"
	printf '%-11s %-15s %9s %8s %10s %12s %8s %9s\n' scene integrator "wall s" "x real" \
		"rk4/this" "centroid mm" "top mm" "spread mm"
	for s in tablecloth strip; do
		for m in $whole; do
			w=$(awk -v s=$s -v m=$m '$1 == s && $2 == m && $4 == 0 { print $5 }' "$raw" | median)
			sim=$(awk -v s=$s -v m=$m '$1 == s && $2 == m { print $6; exit }' "$raw")
			# the ratio to RK4 in each round, then its median
			ratio=$(awk -v s=$s -v m=$m '$1 == s && $4 == 0 { w[$3, $2] = $5 }
				END { for (k in w) { split(k, p, SUBSEP); if (p[2] == m && ((p[1], "rk4") in w))
					print w[p[1], "rk4"] / w[k] } }' "$raw" | median)
			st=$(awk -v s=$s -v m=$m '$1 == s && $2 == m && $4 != 0 { bad = $4 } END { print bad == "" ? "ok" : "exit " bad }' "$raw")
			xr=$(awk -v w="$w" -v t="$sim" 'BEGIN { if (w == "-" || w + 0 == 0) print "-"; else printf "%.3g", t / w }')
			if [ -r "$tmp/$s-$m.shape" ] && [ -r "$tmp/$s-rk4.shape" ]; then
				read -r dist top spread < <(awk 'NR == FNR { rx = $1; ry = $2; rz = $3; next }
					{ printf "%.2f %.2f %.2f\n", 1e3 * sqrt(($1 - rx) ^ 2 + ($2 - ry) ^ 2 + ($3 - rz) ^ 2),
						1e3 * $4, 1e3 * $5 }' "$tmp/$s-rk4.shape" "$tmp/$s-$m.shape")
			else
				dist=- top=- spread=-
			fi
			ratio=$(awk -v r="$ratio" 'BEGIN { if (r == "-") print r; else printf "%.3g", r }')
			printf '%-11s %-15s %9s %8s %10s %12s %8s %9s %s\n' "$s" "$m" "$w" "$xr" "$ratio" \
				"$dist" "$top" "$spread" "$([ "$st" = ok ] || echo "$st")"
			echo "$s,$m,$w,$sim,$xr,$ratio,$dist,$top,$spread,$st" >>"$csv"
		done
	done
	echo
	target() { # scene goal
		awk -F, -v s="$1" -v g="$2" '$1 == s && $2 ~ /^fast/ {
			printf "target: %s with %s at least %gx real time: %sx (%s s for %s s; %sx RK4'"'"'s speed in the same rounds): %s\n",
				s, $2, g, $5, $3, $4, $6, ($5 != "-" && $5 + 0 >= g) ? "met" : "missed" }' "$csv"
	}
	target tablecloth 20
	target strip 10
	awk -F, 'NR > 1 && $2 != "rk4" && $7 != "-" { printf "shape: %s %s ends %s mm from RK4'"'"'s centroid; top of the pile %s mm (RK4 %s), spread %s mm (RK4 %s)\n",
		$1, $2, $7, $8, rk[$1, 8], $9, rk[$1, 9] } $2 == "rk4" { rk[$1, 8] = $8; rk[$1, 9] = $9 }' "$csv"
	plot fast.gp "$csv" "$results/fast.png" "stamp='$stamp'; runs='$runs'"
	echo
fi

# ---- 2: the audit of every frame ----
if want 2; then
	for s in tablecloth strip; do
		"$drape" check --every 1 --set simulation.integrator=fast "$srcdir/scenes/$s.scene" \
			>"$tmp/check" 2>"$tmp/err"
		rc=$?
		awk -v s=$s -v rc=$rc -F'\t' '$2 == "scene" {
			printf "target: %s with fast, every frame audited: %s frames, %s with a pair, %s pairs, %s nodes inside obstacles (exit %s): %s\n",
				s, $3, $4, $5, $6, rc, (rc == 0 && $5 == 0 && $6 == 0) ? "met" : "missed"; found = 1 }
			END { if (!found) printf "target: %s with fast, audit: drape check exited %s\n", s, rc }' "$tmp/check"
	done
	echo
fi

# ---- 4: scaling ----
if want 4; then
	scsv=$results/fast-scaling.csv
	echo "nodes,broad,wall_per_sim_s,steps_per_s" >"$scsv"
	for broad in grid bvh; do
		for n in $sizes; do
			scaled_tablecloth "$n" "simulation.integrator=fast" "collision.broad=$broad" \
				>"$tmp/scale-$n.scene"
			: >"$tmp/scale-$n.w"
			for r in $(seq 1 "$runs"); do
				[ -t 2 ] && printf '\r  round %d: %d^2 %s          ' "$r" "$n" "$broad" >&2
				"$drape" run --headless --until "$until_t" "$tmp/scale-$n.scene" >"$tmp/out" \
					2>"$tmp/err" ||
					{ echo "$prog: $n^2 $broad: exit $?: $(head -n 1 "$tmp/err")" >&2; continue; }
				wall_of <"$tmp/out" >>"$tmp/scale-$n.w"
			done
			w=$(median <"$tmp/scale-$n.w")
			awk -v n="$n" -v b="$broad" -v w="$w" -v t="$until_t" 'BEGIN {
				if (w == "-") print n * n "," b ",-,-";
				else printf "%d,%s,%.4g,%.4g\n", n * n, b, w / t, t / 0.01 / w }' >>"$scsv"
		done
	done
	[ -t 2 ] && printf '\r%60s\r' '' >&2
	for broad in grid bvh; do
		echo "tablecloth with fast and $broad at N x N nodes, first $until_t s, median of $runs:"
		awk -F, -v b="$broad" 'NR > 1 && $2 == b { printf "  %7d nodes: %s s per simulated second\n", $1, $3 }' "$scsv"
		awk -F, -v b="$broad" 'NR > 1 && $2 == b && $3 != "-" {
				x = log($1); y = log($3); n++; sx += x; sy += y; sxx += x * x; sxy += x * y
				w[$1] = $3 }
			END {
				if (n >= 2) { s = (n * sxy - sx * sy) / (n * sxx - sx * sx)
					printf "target: %s: time per step linear in nodes, log-log slope at most 1.1: %.3f: %s\n", b, s, s <= 1.1 ? "met" : "missed" }
				if (10000 in w) printf "target: %s: 100^2 at most 5 s per simulated second: %s: %s\n", b, w[10000], w[10000] <= 5 ? "met" : "missed"
				if (40000 in w) printf "target: %s: 200^2 at most 25 s per simulated second: %s: %s\n", b, w[40000], w[40000] <= 25 ? "met" : "missed"
			}' "$scsv"
	done
	echo
fi

# ---- 5 and 6: the peers' table ----
if want 5; then
	rcsv=$results/fast-refine.csv
	echo "integrator,nodes,wall_s" >"$rcsv"
	for m in fast implicit-euler; do
		for n in 25 50 100; do
			peers_table "$n" 1 "$m" >"$tmp/peers-$n-$m.scene"
			: >"$tmp/peers-$n-$m.w"
			for r in $(seq 1 "$runs"); do
				[ -t 2 ] && printf '\r  round %d: peers %d^2 %s          ' "$r" "$n" "$m" >&2
				"$drape" run --headless --until "$until_t" "$tmp/peers-$n-$m.scene" >"$tmp/out" \
					2>"$tmp/err" || { echo "$prog: peers $n^2 $m: exit $?: $(head -n 1 "$tmp/err")" >&2; continue; }
				wall_of <"$tmp/out" >>"$tmp/peers-$n-$m.w"
			done
			echo "$m,$((n * n)),$(median <"$tmp/peers-$n-$m.w")" >>"$rcsv"
		done
	done
	[ -t 2 ] && printf '\r%60s\r' '' >&2
	awk -F, -v t="$until_t" 'NR > 1 { w[$1, $2] = $3; if (!($1 in seen)) { seen[$1] = 1; order[++k] = $1 } }
		END { for (i = 1; i <= k; i++) { m = order[i]
			printf "peers'"'"' table, first %s s, %s: %s / %s / %s s at 25^2 / 50^2 / 100^2\n", t, m, w[m, 625], w[m, 2500], w[m, 10000]
			if (w[m, 625] != "-" && w[m, 2500] != "-" && w[m, 10000] != "-") {
				g1 = w[m, 2500] / w[m, 625]; g2 = w[m, 10000] / w[m, 2500]
				printf "target: refinement at most 4x per 4x nodes (%s): %.1fx and %.1fx: %s\n", m, g1, g2,
					(g1 <= 4 && g2 <= 4) ? "met" : "missed" } } }' "$rcsv"
	echo
fi
if want 6; then
	for b in 0.1 1 10; do
		edit_scene "$srcdir/scenes/tablecloth.scene" "cloth.bending_warp=$b uN*m" \
			"cloth.bending_weft=$b uN*m" "cloth.damping=0 /s" "simulation.integrator=fast" \
			>"$tmp/soft-table-$b.scene"
		peers_table 25 "$b" fast >"$tmp/soft-peers-$b.scene"
		for s in table peers; do
			timeout "$hang" "$drape" run --headless "$tmp/soft-$s-$b.scene" >"$tmp/out" 2>"$tmp/err"
			rc=$?
			case $rc in
			0) what="finished, $(wall_of <"$tmp/out") s" ;;
			3) what="blew up: $(head -n 1 "$tmp/err" | sed "s|$tmp/||")" ;;
			124) what="hung (over $hang s)" ;;
			*) what="exit $rc: $(head -n 1 "$tmp/err" | sed "s|$tmp/||")" ;;
			esac
			echo "soft fabric: $s, bending $b uN*m, no damping, fast: $what"
		done
	done
	echo
fi
# ---- 7: numerical damping ----
# The hanging strip (its right end brought in over the first 0.3 s) with
# no damping: the energy above its rest (the shipped, damped scene's at
# its end) that each method keeps at 1 s, against RK4's.
if want 7; then
	energy_of() { awk '/^energy / { print $2 }'; }
	"$drape" run --headless --integrator implicit-euler "$srcdir/scenes/hanging.scene" >"$tmp/out" 2>"$tmp/err" ||
		die "hanging, at rest: $(head -n 1 "$tmp/err")"
	rest=$(energy_of <"$tmp/out")
	for m in $integs; do
		"$drape" run --headless --integrator "$m" --set 'cloth.damping=0 /s' --until 1 \
			"$srcdir/scenes/hanging.scene" >"$tmp/out" 2>"$tmp/err" ||
			{ echo "$prog: hanging $m: $(head -n 1 "$tmp/err")" >&2; continue; }
		echo "$m $(energy_of <"$tmp/out")"
	done | awk -v rest="$rest" '{ e[$1] = $2 - rest; order[++n] = $1 }
		END { for (i = 1; i <= n; i++) if (order[i] != "rk4" && e["rk4"] > 0)
			printf "numerical damping: the undamped hanging strip at 1 s keeps %.3g J above rest with %s, %.1f %% of RK4'"'"'s %.3g J\n",
				e[order[i]], order[i], 100 * e[order[i]] / e["rk4"], e["rk4"] }'
	echo
fi
# ---- 8: the step ----
# fast at steps from a half to sixteen times its own (dt = auto, 10 ms),
# with bvh: wall time, corrections, how it ends, and the audit of every
# frame: the largest step before it misbehaves, and how.
if want 8; then
	stcsv=$results/fast-steps.csv
	echo "scene,dt,status,wall_s,corrections,frames,bad_frames,pairs,inside" >"$stcsv"
	for s in tablecloth strip; do
		for dt in 0.005 0.01 0.02 0.04 0.08 0.16; do
			[ -t 2 ] && printf '\r  %s at dt %s          ' "$s" "$dt" >&2
			set -- --set simulation.integrator=fast --set collision.broad=bvh --set "simulation.dt=$dt s"
			"$drape" run --headless "$@" "$srcdir/scenes/$s.scene" >"$tmp/out" 2>"$tmp/err"
			rc=$?
			w=$(wall_of <"$tmp/out")
			corr=$(awk '/^corrections / { print $2 }' "$tmp/out")
			"$drape" check --every 1 "$@" "$srcdir/scenes/$s.scene" >"$tmp/check" 2>/dev/null
			aud=$(awk -F'\t' '$2 == "scene" { print $3 "," $4 "," $5 "," $6 }' "$tmp/check")
			case $rc in 0) st=ok ;; 3) st="blew up" ;; *) st="exit $rc" ;; esac
			echo "$s,$dt,$st,${w:--},${corr:--},${aud:--,-,-,-}" >>"$stcsv"
		done
	done
	[ -t 2 ] && printf '\r%60s\r' '' >&2
	echo "fast (bvh) by step: wall s, corrections, every frame audited"
	awk -F, 'NR > 1 { printf "  %-10s dt %-6s %-8s %8s s %8s corrections, %s frames: %s with a pair, %s pairs, %s inside\n",
		$1, $2, $3, $4, $5, $6, $7, $8, $9 }' "$stcsv"
	echo
fi
# ---- 9: the terminal interface at 80 x 24 ----
# The shipped tablecloth in the TUI, in a tmux pane of 80 x 24 on a
# private server: the status line's speed against real time once the
# run has ended (the TUI caps nothing: it shows the speed it ran at).
if want 9; then
	if command -v tmux >/dev/null 2>&1; then
		sock=drape-bench-$$
		tmux -L "$sock" new-session -d -s tui -x 80 -y 24 \
			"'$drape' '$srcdir/scenes/tablecloth.scene'" 2>/dev/null
		line=
		for i in $(seq 600); do
			line=$(tmux -L "$sock" capture-pane -p -t tui 2>/dev/null | head -n 1)
			case $line in *" end "*) break ;; esac
			sleep 0.1
		done
		tmux -L "$sock" kill-server 2>/dev/null
		x=$(printf '%s\n' "$line" | sed -n 's/.* \([0-9.]*\)x real .*/\1/p')
		echo "status line: $line"
		if [ -n "$x" ]; then
			printf 'target: the TUI on the tablecloth at 80 x 24 at least real time: %sx: %s\n' \
				"$x" "$(awk -v x="$x" 'BEGIN { print (x >= 1 ? "met" : "missed") }')"
		else
			echo "target: the TUI at 80 x 24: the run did not end within 60 s, or its status line did not read"
		fi
	else
		echo "the TUI at 80 x 24: not measured (no tmux)"
	fi
	echo
fi
# ---- 10: what bounds the speed ----
# The shipped scenes with fast as shipped and with self-contact off: the
# substeps and the analytic obstacles alone (the cloth passes through
# itself, so that run's shape means nothing), against the wall time the
# speed target allows (the scene's duration over 20 or 10). The run's
# "collision stages" is the exact check at the end of each step, and its
# "contacts found in the steps" the search for each step's (or window's)
# contacts inside the integration; holding them is in the substeps.
if want 10; then
	for s in tablecloth strip; do
		: >"$tmp/floor-$s"
		for r in $(seq 1 "$runs"); do
			for v in on off; do
				[ -t 2 ] && printf '\r  round %d: %s self %s          ' "$r" "$s" "$v" >&2
				"$drape" run --headless --set "collision.self=$v" "$srcdir/scenes/$s.scene" \
					>"$tmp/out" 2>"$tmp/err" ||
					{ echo "$prog: $s self $v: exit $?: $(head -n 1 "$tmp/err")" >&2; continue; }
				awk -v v=$v '/^wall time / { c = "-"
					if (match($0, /contacts found in the steps [0-9.eE+-]+/))
						c = substr($0, RSTART + 28, RLENGTH - 28)
					print v, $3, $7, c }' "$tmp/out" >>"$tmp/floor-$s"
			done
		done
	done
	[ -t 2 ] && printf '\r%60s\r' '' >&2
	for s in tablecloth strip; do
		case $s in tablecloth) goal=20 dur=2 ;; *) goal=10 dur=3 ;; esac
		on=$(awk '$1 == "on" { print $2 }' "$tmp/floor-$s" | median)
		chk=$(awk '$1 == "on" { print $3 }' "$tmp/floor-$s" | median)
		found=$(awk '$1 == "on" { print $4 }' "$tmp/floor-$s" | median)
		off=$(awk '$1 == "off" { print $2 }' "$tmp/floor-$s" | median)
		awk -v s=$s -v g=$goal -v d=$dur -v on="$on" -v c="$chk" -v k="$found" -v off="$off" 'BEGIN {
			b = d / g
			if (on == "-" || off == "-") { printf "floor: %s: not measured\n", s; exit }
			printf "floor: %s with fast: %s s as shipped (the check at each step'"'"'s end %s s, finding the contacts %s s); self-contact off %s s, %.0f %% of the %g s that %gx real time allows\n",
				s, on, c, k, off, 100 * off / b, b, g }'
	done
	echo
fi
echo "not measured here: Blender and Bullet side by side on the peers' scenes"
echo "(bench/peers.sh: make bench-peers)"

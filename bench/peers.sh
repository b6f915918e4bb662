#!/usr/bin/env bash
# drape beside its peers (issue 14): Blender's cloth modifier and Bullet's
# classic soft body on the same scenes (../shared/reference/peers.md):
#   - the peers' table: 25 x 25 nodes over 0.24 m falling 0.2 m onto a
#     0.1 m cube off its centre and the floor, 2 s;
#   - the strip: 125 x 3 nodes at 5 mm standing on its short edge 1 cm
#     above the floor, tilted 10 degrees, falling over, 2 s;
# both 100 g/m2, E*t = 50 N/m, G*t = 5 N/m, B = 1 uN*m, collision
# thickness a quarter of the spacing, friction 0.1, self-collision on, no
# drag. drape runs rk4, implicit-euler, fast and fast with
# collision.broad = bvh, and bdf2 with bvh (issue 28). Every timed process is pinned to one core
# (taskset; Blender's -t 1 still runs a second busy thread); each reports
# the wall time of its stepping alone (not its start-up, nor the writing
# of frames); the figure is the median over BENCH_RUNS rounds, and the
# ratio is drape rk4's time over the method's in the same round (median
# over the rounds). Every frame each peer exports (OBJ, drape's node order
# and triangles) is audited by `drape check` (intersecting pairs of
# triangles sharing no node), and its nodes inside the cube or under the
# floor are counted here; drape's own frames are audited by
# `drape check --every 1` on the scene (every 20 ms).
# The table's drop changes from round to round (BENCH_PEERS_DROPS, in
# turn): a tenth of a millimetre decides whether a cloth comes to rest on
# the cube's edge or slides off it, and so what its rest costs, and a
# figure from one drop is one draw of that (bench/bdf2.sh part 2). Every
# method of a round falls from the same height; the audits are of the
# first round's.
# Then the refinement: the table's first 0.25 s at 25^2, 50^2 and 100^2
# (the same 0.24 m, finer), Blender, Bullet, and drape's bdf2 and fast
# (both with bvh) in the same rounds, BENCH_PEERS_REFINE_RUNS rounds, the
# drop again in turn: how many Newton iterations bdf2's landing takes
# moves by 15 % either way with its path's last bits, so one drop is one
# draw (bench/README.md, bdf2.sh, stop 47).
#
# Skips (exit 0, saying why) without blender, without Bullet's float64
# build (pkg-config bullet-float64; Debian's libbullet-dev), without g++
# or taskset. Writes peers.csv, peers-refine.csv and peers.png under
# BENCH_RESULTS.
#
# Environment:
#   BENCH_RUNS               rounds (default 3)
#   BENCH_PEERS_DROPS        the table's starting heights, m, one a round in
#                            turn (default "0.2 0.2001 0.2002")
#   BENCH_PEERS_CORE         the core every timed run is pinned to (default 1)
#   BENCH_PEERS_SKIP         parts to leave out: "table strip refine"
#   BENCH_PEERS_REFINE_RUNS  rounds of the refinement (default 3)
#   BENCH_PEERS_SIZES        refinement sizes (default "25 50 100")
#   BENCH_PEERS_BULLET_DT    Bullet's fixed step, s (default 0.001)
#   BENCH_PEERS_BULLET_ITER  Bullet's position iterations (default 4)
#   BLENDER, CXX             the programs (default blender, g++)
#   BENCH_RESULTS, DRAPE, BENCH_SRCDIR, GNUPLOT
set -u
prog=peers.sh
blender=${BLENDER:-blender}
cxx=${CXX:-g++}
skipped() { echo "$prog: skipped: $*"; exit 0; }
command -v "$blender" >/dev/null 2>&1 ||
	skipped "no $blender (apt-get install -y --no-install-recommends blender, about 630 MB)"
pkg-config --exists bullet-float64 2>/dev/null ||
	skipped "no Bullet float64 build (pkg-config bullet-float64: apt-get install -y libbullet-dev)"
command -v "$cxx" >/dev/null 2>&1 || skipped "no C++ compiler ($cxx) to build bench/peers/bullet-cloth.cpp"
command -v taskset >/dev/null 2>&1 || skipped "no taskset (util-linux) to pin the runs to one core"
. "$(cd "$(dirname "$0")" && pwd)/lib.sh"
core=${BENCH_PEERS_CORE:-1}
rruns=${BENCH_PEERS_REFINE_RUNS:-3}
drops=${BENCH_PEERS_DROPS:-0.2 0.2001 0.2002}
sizes=${BENCH_PEERS_SIZES:-25 50 100}
bdt=${BENCH_PEERS_BULLET_DT:-0.001}
biter=${BENCH_PEERS_BULLET_ITER:-4}
skip=" ${BENCH_PEERS_SKIP:-} "
want() { case $skip in *" $1 "*) return 1 ;; esac; return 0; }
check_seconds "$bdt" BENCH_PEERS_BULLET_DT
case $rruns in '' | *[!0-9]* | 0) die "BENCH_PEERS_REFINE_RUNS must be a whole number > 0" ;; esac
for n in $sizes; do
	case $n in '' | *[!0-9]* | 0 | 1) die "BENCH_PEERS_SIZES are whole numbers > 1, not '$n'" ;; esac
done
check_heights "$drops" BENCH_PEERS_DROPS
ndrops=$(echo $drops | wc -w)
taskset -c "$core" true 2>/dev/null || die "cannot pin to core $core (BENCH_PEERS_CORE)"
pin() { taskset -c "$core" "$@"; }

echo "peers: $version (commit $commit), $stamp"
echo "machine: $ncpu cores, ${cpu:-unknown cpu}; load $(load); runs pinned to core $core"
echo "blender: $("$blender" --version 2>/dev/null | head -n 1); bullet: $(pkg-config --modversion bullet-float64) (float64)"
echo "median of $runs rounds; in each round the methods run one after another"
echo "the table's drop, round by round in turn: $drops m"
echo

"$cxx" -O2 -o "$tmp/bullet-cloth" "$here/peers/bullet-cloth.cpp" \
	$(pkg-config --cflags --libs bullet-float64) 2>"$tmp/cxx.err" ||
	{ cat "$tmp/cxx.err" >&2; die "cannot build bench/peers/bullet-cloth.cpp"; }

# ---- the scenes ----
# peers_strip INTEGRATOR > DST: the strip in drape's frame. drape's cloth
# starts along the axes, so the strip stands straight up (the warp, 125
# nodes, along +y; 3 along +x) and the world is turned instead: the floor
# and gravity tilted 10 degrees about x, the floor 1 cm below its lower
# edge.
peers_strip() {
	awk -v m="$1" 'BEGIN {
		h = 0.005; t = 0.25 * h; a = 10 * atan2(0, -1) / 180; c = cos(a); s = sin(a); g = 9.80665
		printf "[simulation]\nduration = 2 s\ndt = auto\nintegrator = %s\noutput_rate = 50 Hz\n", m
		printf "gravity = 0 %.9g %.9g m/s2\n", -g * c, g * s
		printf "[cloth]\nnodes = 125 3\nspacing = %.9g m\norigin = -0.005 0 0 m\n", h
		printf "orientation = +y +x\nweight = 100 g/m2\nthickness = %.9g m\n", t
		printf "modulus_warp = %.9g Pa\nmodulus_weft = %.9g Pa\nshear_modulus = %.9g Pa\n", 50 / t, 50 / t, 5 / t
		printf "bending_warp = 1 uN*m\nbending_weft = 1 uN*m\n"
		printf "[plane]\npoint = 0 %.9g %.9g m\nnormal = 0 %.9g %.9g\nfriction = 0.1\n", -0.01 * c, 0.01 * s, c, -s
		printf "[collision]\nself = on\nbroad = grid\nnarrow = ccd\nposition = slide\nfriction = 0.1\n" }'
}
# first_obj KIND N SCENE [Y] > OBJ: the cloth's first frame in the world
# (y up: the table as drape has it, at height Y (0.2 m), the strip
# tilted), drape's node order (u fastest) and drape's own triangles (from
# a run of one step)
first_obj() {
	"$drape" run --headless --until 1e-6 --final-obj "$tmp/faces.obj" "$3" >/dev/null 2>"$tmp/err" ||
		die "$3: $(head -n 1 "$tmp/err")"
	awk -v kind="$1" -v n="$2" -v y="${4:-0.2}" 'BEGIN { a = 10 * atan2(0, -1) / 180
		if (kind == "table") { h = 0.24 / (n - 1)
			for (j = 0; j < n; j++) for (i = 0; i < n; i++)
				printf "v %.9g %s %.9g\n", -0.12 + i * h, y, -0.12 + j * h }
		else { h = 0.005
			for (j = 0; j < 3; j++) for (i = 0; i < 125; i++)
				printf "v %.9g %.9g %.9g\n", -0.005 + j * h, 0.01 + i * h * cos(a), i * h * sin(a) } }'
	grep '^f ' "$tmp/faces.obj"
}
# the figures each peer needs: nodes, spacing, mass per node (kg)
table_h() { awk -v n="$1" 'BEGIN { printf "%.9g", 0.24 / (n - 1) }'; }
node_mass() { awk -v a="$1" -v n="$2" 'BEGIN { printf "%.9g", 0.1 * a / n }'; } # 100 g/m2

# Blender: one cloth frame is sqrt(0.001) s; its stiffnesses are forces
# per unit strain in its frame units (0.001 x N), so k*h x 0.001 for
# a link of stiffness k (N/m, = E*t on a square grid) and length h. At the
# true vertex masses (a few ug) its solver blows up in the first frames,
# so masses and stiffnesses are scaled alike to 0.3 kg a vertex (its
# default): the same motion.
run_blender() { # obj outdir|- frames quality mass_kg h cube
	awk -v m="$5" -v h="$6" 'BEGIN { S = 0.3 / m
		printf "%.9g %.9g %.9g %.9g", 0.3, S * 1e-3 * 50 * h, S * 1e-3 * 5 * h, S * 1e-3 * 1e-6 / h }' >"$tmp/bargs"
	read -r bm bk bs bb <"$tmp/bargs"
	pin "$blender" --background --factory-startup -t 1 --python "$here/peers/blender-cloth.py" -- \
		"$1" "$2" "$3" "$4" "$bm" "$bk" "$bs" "$bb" "$(awk -v h="$6" 'BEGIN { print 0.25 * h }')" 0.1 "$7" \
		>"$tmp/out" 2>"$tmp/err"
}
run_bullet() { # obj outdir|- T frames mass_kg h cube
	pin "$tmp/bullet-cloth" "$1" "$2" "$3" "$4" "$bdt" "$5" "$(awk -v h="$6" 'BEGIN { print 0.25 * h }')" \
		0.1 "$7" "$biter" >"$tmp/out" 2>"$tmp/err"
}
run_drape() { # scene method until
	local o=
	case $2 in *+bvh) o="--set collision.broad=bvh" ;; esac
	pin "$drape" run --headless --integrator "${2%+bvh}" $o --until "$3" "$1" >"$tmp/out" 2>"$tmp/err"
}
sim_of() { awk '/^simulated / { print $2 }'; }

# audit_frames DIR KIND -> "pairs_end pairs_worst inside_end inside_worst frames"
# (inside: nodes under the floor or inside the cube, in drape's y-up world)
audit_frames() {
	local f
	"$drape" check "$1"/frame-*.obj >"$tmp/check" 2>"$tmp/check.err"
	case $? in 0 | 4) ;; *) echo "- - - - -"; return ;; esac
	for f in "$1"/frame-*.obj; do
		awk -v kind="$2" '$1 == "v" { y = $3 - 0
			if (y < 0) n++
			else if (kind == "table" && $2 > 0.02 && $2 < 0.12 && y < 0.1 && $4 > -0.1 && $4 < 0) n++ }
			END { print n + 0 }' "$f"
	done >"$tmp/inside"
	awk -F'\t' '$2 == "obj" { p = $5; if (p > w) w = p; e = p; k++ } END { printf "%d %d ", e, w }' "$tmp/check"
	awk '{ if ($1 > w) w = $1; e = $1; k++ } END { printf "%d %d %d\n", e, w, k }' "$tmp/inside"
}
# audit_drape SCENE METHOD -> the same, from drape check --every 1
audit_drape() {
	local o=
	case $2 in *+bvh) o="--set collision.broad=bvh" ;; esac
	"$drape" check --every 1 --set "simulation.integrator=${2%+bvh}" $o "$1" >"$tmp/check" 2>"$tmp/check.err"
	awk -F'\t' '$2 ~ /^t=/ { t = $2; sub(/^t=/, "", t); sub(/ .*/, "", t); if (t + 0 >= 1.999) { pe = $5; ie = $6 } }
		$2 == "scene" { pw = $5; iw = $6; fr = $3; found = 1 }
		END { if (!found) print "- - - - -"; else printf "%d %d %d %d %d\n", pe, pw, ie, iw, fr }' "$tmp/check" |
		# a run that blew up has no end to audit
		if grep -q 'blow-up' "$tmp/check.err"; then awk '{ $1 = "-"; $3 = "-"; print }'; else cat; fi
}

# ---- table and strip, whole ----
methods="blender bullet rk4 implicit-euler fast fast+bvh bdf2+bvh"
csv=$results/peers.csv
raw=$tmp/raw.txt
: >"$raw"
scenes=
want table && scenes="$scenes table"
want strip && scenes="$scenes strip"
for s in $scenes; do
	if [ "$s" = table ]; then
		peers_table 25 1 rk4 >"$tmp/$s.scene"; n=625; area=0.0576; h=$(table_h 25); cube=1
	else
		peers_strip rk4 >"$tmp/$s.scene"; n=375; area=0.0062; h=0.005; cube=0
	fi
	first_obj "$s" 25 "$tmp/$s.scene" >"$tmp/$s-0.obj"
	echo "$n $(node_mass "$area" "$n") $h $cube" >"$tmp/$s.par"
	if [ "$s" = table ]; then	# each drop's scene and first frame
		k=0
		for y in $drops; do
			k=$((k + 1))
			edit_scene "$tmp/$s.scene" "cloth.origin=-0.12 $y -0.12 m" >"$tmp/$s-d$k.scene"
			first_obj "$s" 25 "$tmp/$s-d$k.scene" "$y" >"$tmp/$s-d$k-0.obj"
		done
	fi
done
for r in $(seq 1 "$runs"); do
	for s in $scenes; do
		read -r n mass h cube <"$tmp/$s.par"
		sc=$tmp/$s.scene obj=$tmp/$s-0.obj
		if [ "$s" = table ]; then	# this round's drop
			k=$(( (r - 1) % ndrops + 1 ))
			sc=$tmp/$s-d$k.scene obj=$tmp/$s-d$k-0.obj
		fi
		for m in $methods; do
			[ -t 2 ] && printf '\r  round %d: %s %s          ' "$r" "$s" "$m" >&2
			out=-
			[ "$r" = 1 ] && { out=$tmp/frames-$s-$m; mkdir -p "$out"; }
			case $m in
			blender) run_blender "$obj" "$out" 63 5 "$mass" "$h" "$cube" ;;
			bullet) run_bullet "$obj" "$out" 2 63 "$mass" "$h" "$cube" ;;
			*) run_drape "$sc" "$m" 2 ;;
			esac
			rc=$?
			w=$(wall_of <"$tmp/out")
			sim=$(sim_of <"$tmp/out")
			echo "$s $m $r $rc ${w:--} ${sim:--}" >>"$raw"
			[ $rc = 0 ] || { echo "$prog: $s $m exited $rc:"; tail -n 3 "$tmp/err"; } >&2
		done
	done
done
[ -t 2 ] && printf '\r%60s\r' '' >&2
if [ -n "$scenes" ]; then
	echo "scene,method,wall_per_sim_s,ratio_rk4,pairs_end,pairs_worst,status,inside_end,inside_worst,frames" >"$csv"
	for s in $scenes; do
		line=
		for m in $methods; do
			wps=$(awk -v s=$s -v m=$m '$1 == s && $2 == m && $4 == 0 && $6 > 0 { print $5 / $6 }' "$raw" | median)
			ratio=$(awk -v s=$s -v m=$m '$1 == s && $4 == 0 && $6 > 0 { w[$3, $2] = $5 / $6 }
				END { for (k in w) { split(k, p, SUBSEP); if (p[2] == m && ((p[1], "rk4") in w))
					print w[p[1], "rk4"] / w[k] } }' "$raw" | median)
			st=$(awk -v s=$s -v m=$m '$1 == s && $2 == m && $4 != 0 { bad = $4 } END { print bad == "" ? "ok" : "exit " bad }' "$raw")
			case $m in
			blender | bullet) read -r pe pw ie iw fr < <(audit_frames "$tmp/frames-$s-$m" "$s") ;;
			*) read -r pe pw ie iw fr < <(audit_drape "$tmp/$s.scene" "$m") ;;
			esac
			wps=$(awk -v x="$wps" 'BEGIN { if (x == "-") print x; else printf "%.3g", x }')
			ratio=$(awk -v x="$ratio" 'BEGIN { if (x == "-") print x; else printf "%.3g", x }')
			echo "$s,$m,$wps,$ratio,$pe,$pw,$st,$ie,$iw,$fr" >>"$csv"
			case $m in blender | bullet) name=$m ;; *) name="drape $m" ;; esac
			line="$line${line:+, }$name $wps s/sim-s ($pe pairs at end, $pw worst; $ie/$iw nodes inside$([ "$st" = ok ] || echo "; $st"))"
		done
		case $s in table) label="peers' table 25^2, 2 s" ;; *) label="strip 125x3, 2 s" ;; esac
		echo "$label: $line"
		echo
	done
	printf '%-6s %-15s %12s %9s %10s %11s %12s %8s\n' scene method "wall/sim s" "rk4/this" "pairs end" "pairs worst" \
		"inside e/w" frames
	awk -F, 'NR > 1 { printf "%-6s %-15s %12s %9s %10s %11s %12s %8s %s\n", $1, $2, $3, $4, $5, $6, $8 "/" $9, $10,
		($7 == "ok" ? "" : $7) }' "$csv"
	echo "(ratio: drape rk4's wall time over the method's in the same round; frames: audited, the"
	echo " peers' every exported frame (31.6 ms apart in Blender, Bullet's the same), drape's every 20 ms)"
	plot peers.gp "$csv" "$results/peers.png" "stamp='$stamp'; runs='$runs'"
	echo
fi

# ---- refinement: the table's first 0.25 s ----
if want refine; then
	rcsv=$results/peers-refine.csv
	echo "method,nodes,quality,wall_s,wall_per_sim_s,pairs_end,pairs_worst,status" >"$rcsv"
	frames=8 # 8 x 31.6 ms = 0.253 s
	for n in $sizes; do
		peers_table "$n" 1 rk4 >"$tmp/r$n.scene"
		k=0
		for y in $drops; do	# each drop's scene and first frame, as the table's
			k=$((k + 1))
			edit_scene "$tmp/r$n.scene" "cloth.origin=-0.12 $y -0.12 m" >"$tmp/r$n-d$k.scene"
			first_obj table "$n" "$tmp/r$n-d$k.scene" "$y" >"$tmp/r$n-d$k.obj"
		done
		h=$(table_h "$n")
		mass=$(node_mass 0.0576 $((n * n)))
		q=$(awk -v n="$n" 'BEGIN { q = int(n / 5 + 0.5); print q < 5 ? 5 : q }')
		for m in blender bullet bdf2+bvh fast+bvh; do
			: >"$tmp/rw"
			rc=0
			for r in $(seq 1 "$rruns"); do
				[ -t 2 ] && printf '\r  refinement round %d: %d^2 %s          ' "$r" "$n" "$m" >&2
				k=$(( (r - 1) % ndrops + 1 ))	# this round's drop
				out=-
				[ "$r" = 1 ] && { out=$tmp/rframes-$n-$m; mkdir -p "$out"; }
				case $m in
				blender) run_blender "$tmp/r$n-d$k.obj" "$out" "$frames" "$q" "$mass" "$h" 1 ;;
				bullet) run_bullet "$tmp/r$n-d$k.obj" "$out" 0.25 "$frames" "$mass" "$h" 1 ;;
				*) run_drape "$tmp/r$n-d$k.scene" "$m" 0.25 ;;
				esac
				rc=$?
				[ $rc = 0 ] || { echo "$prog: refinement $n^2 $m exited $rc:"; tail -n 3 "$tmp/err"; } >&2
				[ $rc = 0 ] && echo "$(wall_of <"$tmp/out") $(sim_of <"$tmp/out")" >>"$tmp/rw"
			done
			w=$(awk '{ print $1 }' "$tmp/rw" | median)
			wps=$(awk '{ print $1 / $2 }' "$tmp/rw" | median)
			case $m in
			blender | bullet) read -r pe pw ie iw fr < <(audit_frames "$tmp/rframes-$n-$m" table) ;;
			*) edit_scene "$tmp/r$n-d1.scene" "simulation.duration=0.25 s" >"$tmp/r$n-a.scene"
				read -r pe pw ie iw fr < <(audit_drape "$tmp/r$n-a.scene" "$m") ;;
			esac
			[ "$m" = blender ] || q=-
			echo "$m,$((n * n)),$q,$w,$(awk -v x="$wps" 'BEGIN { if (x == "-") print x; else printf "%.3g", x }'),$pe,$pw,$([ $rc = 0 ] && echo ok || echo "exit $rc")" >>"$rcsv"
			q=$(awk -v n="$n" 'BEGIN { q = int(n / 5 + 0.5); print q < 5 ? 5 : q }')
		done
	done
	[ -t 2 ] && printf '\r%60s\r' '' >&2
	echo "refinement: the peers' table, first 0.25 s (Blender 8 frames, 0.253 s), median of $rruns, the drop in turn:"
	awk -F, 'NR > 1 { printf "  %-8s %6d nodes%s: %s s/sim-s (%s s), %s pairs at end, %s worst%s\n", $1, $2,
		($3 == "-" ? "" : " q" $3), $5, $4, $6, $7, ($8 == "ok" ? "" : " " $8) }' "$rcsv"
	awk -F, 'NR > 1 && $5 != "-" { w[$1] = w[$1] (w[$1] == "" ? "" : " ") $5 }
		END { for (m in w) { n = split(w[m], v, " "); g = ""
			for (i = 2; i <= n; i++) g = g (i > 2 ? ", " : "") sprintf("%.1fx", v[i] / v[i - 1])
			if (g != "") printf "  growth per 4x nodes, %s: %s\n", m, g } }' "$rcsv"
	echo
fi
echo "load at the end: $(load)"

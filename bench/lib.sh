# Shared by the bench scripts that write to BENCH_RESULTS (sourced, not
# run): the paths, the scene editor, one timed run, the summary parser,
# medians, wall_of, the peers' table, the chart.
#
# Environment (see bench/README.md): DRAPE, BENCH_SRCDIR, BENCH_RESULTS,
# BENCH_RUNS, GNUPLOT.

here=$(cd "$(dirname "$0")" && pwd)
srcdir=${BENCH_SRCDIR:-$(cd "$here/.." && pwd)}
drape=${DRAPE:-$srcdir/src/drape}
results=${BENCH_RESULTS:-$srcdir/bench/results}
runs=${BENCH_RUNS:-3}

die() { echo "$prog: $*" >&2; exit 2; }
case $runs in '' | *[!0-9]* | 0) die "BENCH_RUNS must be a whole number > 0, not '$runs'" ;; esac
[ -x "$drape" ] || die "no binary at $drape: build first (make), or set DRAPE"
mkdir -p "$results" || die "cannot create $results"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/drape-bench.XXXXXX") || die "mktemp failed"
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM

version=$("$drape" --version 2>/dev/null | head -n 1)
commit=$(git -C "$srcdir" rev-parse --short HEAD 2>/dev/null || echo "?")
cpu=$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo 2>/dev/null)
ncpu=$(nproc 2>/dev/null || echo "?")
stamp=$(date -u '+%Y-%m-%d %H:%M UTC')
load() { cut -d' ' -f1-3 /proc/loadavg 2>/dev/null; }

check_seconds() { # value name
	awk -v t="$1" 'BEGIN { exit !(t + 0 > 0 && t ~ /^[0-9.eE+-]+$/) }' ||
		die "$2 must be seconds > 0, not '$1'"
}
check_heights() { # "values" name: each a height in m > 0
	local y
	[ -n "$1" ] || die "$2 is empty"
	for y in $1; do
		awk -v t="$y" 'BEGIN { exit !(t + 0 > 0 && t ~ /^[0-9.eE+-]+$/) }' ||
			die "$2 are heights in m > 0, not '$y'"
	done
}

# edit_scene SRC 'section.key=value' ... > DST
# Sets each key in its section (replacing the scene's line, or adding it at
# the section's start; a missing section is added at the end). A value of
# "-" deletes the key; 'section.=drop' drops the whole section (every one of
# that name).
edit_scene() {
	local src=$1; shift
	printf '%s\n' "$@" | awk '
	NR == FNR {
		i = index($0, "="); sk = substr($0, 1, i - 1); v = substr($0, i + 1)
		j = index(sk, "."); s = substr(sk, 1, j - 1); k = substr(sk, j + 1)
		if (k == "") { dropsec[s] = 1; next }
		val[s, k] = v; keys[s] = keys[s] " " k; want[s] = 1
		next
	}
	function emit(s,   n, a, q) {
		n = split(keys[s], a, " ")
		for (q = 1; q <= n; q++) if (val[s, a[q]] != "-") print a[q] " = " val[s, a[q]]
		done[s] = 1
	}
	/^[ \t]*\[/ {
		sec = $0; sub(/^[ \t]*\[/, "", sec); sub(/\].*/, "", sec)
		drop = (sec in dropsec)
		if (drop) next
		print
		if (sec in want) emit(sec)
		next
	}
	drop { next }
	{
		line = $0; sub(/#.*/, "", line)
		if (line ~ /=/) {
			k = line; sub(/[ \t]*=.*/, "", k); sub(/^[ \t]*/, "", k)
			if ((sec, k) in val) next
		}
		print
	}
	END { for (s in want) if (!(s in done)) { print ""; print "[" s "]"; emit(s) } }
	' - "$src"
}

# chapter_scene NAME: the path of a copy (in $tmp) of the shipped scene
# NAME with the chapter's method, RK4 at its automatic step and the grid.
# The shipped tablecloth and strip run the fast path with bvh (issue 14);
# the benches that start from them were made on, and compare methods
# against, the chapter's settings. Other scenes are copied as they are.
chapter_scene() {
	local f=$tmp/chapter-$1.scene
	[ -r "$srcdir/scenes/$1.scene" ] || die "no scene $srcdir/scenes/$1.scene"
	sed -e 's/^integrator = fast$/integrator = rk4/' -e 's/^broad = bvh$/broad = grid/' \
		"$srcdir/scenes/$1.scene" >"$f" || die "cannot write $f"
	echo "$f"
}

# scaled_tablecloth N 'section.key=value' ... > DST
# The shipped tablecloth at N x N nodes, 10 mm apart: the cloth's origin
# and the box's horizontal extents scaled by (N - 1) / 24, their heights
# kept, so that every size meets the box at the same time, with the
# chapter's settings (chapter_scene); further edits as edit_scene's
# (scaling.sh, fast.sh).
scaled_tablecloth() {
	local n=$1 k o bmin bmax
	shift
	k=$(awk -v n="$n" 'BEGIN { printf "%.6g", (n - 1) / 24 }')
	o=$(awk -v k="$k" 'BEGIN { printf "%.6g 0.15 %.6g m", -0.12 * k, -0.12 * k }')
	bmin=$(awk -v k="$k" 'BEGIN { printf "0 0 %.6g m", -0.08 * k }')
	bmax=$(awk -v k="$k" 'BEGIN { printf "%.6g 0.12 %.6g m", 0.14 * k, 0.06 * k }')
	edit_scene "$(chapter_scene tablecloth)" "cloth.nodes=$n $n" "cloth.origin=$o" \
		"box.min=$bmin" "box.max=$bmax" "$@"
}

# One run of $tmp/SCENE-LABEL.scene to T, appended to $rawf as
# "SCENE LABEL ROUND STATUS summary-fields CPU" (CPU: user + system
# seconds, which other jobs inflate less than the wall time); a blow-up
# (exit 3) keeps its message in $tmp/SCENE-LABEL.blowup, any other failure
# sets bad=1.
run_once() { # scene label until round
	local rc cpu_s TIMEFORMAT='%3U %3S'
	[ -t 2 ] && printf '\r  round %d: %s %s          ' "$4" "$1" "$2" >&2
	{ time "$drape" run --headless --until "$3" "$tmp/$1-$2.scene" >"$tmp/out" 2>"$tmp/err"; } 2>"$tmp/time"
	rc=$?
	case $rc in 0 | 3) ;; *) bad=1; { echo "$prog: $1 $2: drape run exited $rc:"; cat "$tmp/err"; } >&2 ;; esac
	[ $rc = 3 ] && head -n 1 "$tmp/err" | sed "s|$tmp/||" >"$tmp/$1-$2.blowup"
	cpu_s=$(awk 'NF == 2 { printf "%.3f", $1 + $2 }' "$tmp/time")
	echo "$1 $2 $4 $rc $(parse_summary <"$tmp/out") ${cpu_s:--}" >>"$rawf"
}

# summary on stdin -> "simulated wall steps dt contacts self_contacts
# gravity_energy steps_per_s node_pairs vt_pairs ee_pairs narrow_tests"
# (the last five: the speed and per step lines; 0 when collisions are off)
parse_summary() {
	awk '
	function num(s) { gsub(/[^0-9.eE+-]/, "", s); return s }
	/^simulated / { sim = $2 }
	/^wall time / { wall = $3 }
	/^steps / { steps = $2 }
	/^speed / { for (i = 2; i <= NF; i++) if ($i ~ /^steps\/s/) sps = num($(i - 1)) }
	/^per step / {
		for (i = 2; i < NF; i++) {
			if ($(i + 1) == "node") np = num($i)
			if ($(i + 1) == "vertex-triangle") vt = num($i)
			if ($(i + 1) == "edge-edge") ee = num($i)
			if ($(i + 1) == "narrow") nt = num($i)
		}
	}
	/^integrator / { for (i = 2; i <= NF; i++) if ($i == "dt") { dt = $(i + 1); break } }
	/^energy / { for (i = 2; i <= NF; i++) if ($i == "gravity") { g = $(i + 1); gsub(/[,()]/, "", g) } }
	/^contacts / {
		line = $0; sub(/^contacts[ \t]*/, "", line)
		n = split(line, part, ","); tot = 0; ob = 0
		for (k = 1; k <= n; k++) {
			m = split(part[k], w, " ")
			if (m < 2) continue
			tot += w[m]; if (w[1] == "obstacle") ob += w[m]
		}
		ct = tot; sc = tot - ob
	}
	END {
		if (ct == "") { ct = 0; sc = 0 }
		if (g == "") g = "-"
		print (sim == "" ? "-" : sim), (wall == "" ? "-" : wall), (steps == "" ? "-" : steps), \
			(dt == "" ? "-" : dt), ct, sc, g, (sps == "" ? "-" : sps), \
			(np == "" ? 0 : np), (vt == "" ? 0 : vt), (ee == "" ? 0 : ee), (nt == "" ? 0 : nt)
	}'
}

median() { # numbers on stdin, one a line, "-" skipped; prints "-" if none
	grep -v '^-$' | sort -g | awk '{ v[NR] = $1 }
	END {
		if (NR == 0) { print "-"; exit }
		if (NR % 2) m = v[(NR + 1) / 2]; else m = (v[NR / 2] + v[NR / 2 + 1]) / 2
		printf "%.6g\n", m
	}'
}

# wall seconds of a summary on stdin
wall_of() { awk '/^wall time / { print $3 }'; }

# peers_table N BENDING_uNm INTEGRATOR > DST: the peers' table
# (../shared/reference/peers.md; fast.sh, peers.sh): n x n nodes over
# 0.24 m at y = 0.20 m, the 0.1 m cube at (0.07, 0.05, -0.05) (peers.md's
# z-up figures turned to drape's y up), E*t = 50 N/m, thickness a quarter
# of the spacing, 100 g/m2, friction 0.1, no drag.
peers_table() { # n bending_uNm integrator
	awk -v n="$1" -v b="$2" -v m="$3" 'BEGIN {
		h = 0.24 / (n - 1); t = 0.25 * h
		printf "[simulation]\nduration = 2 s\ndt = auto\nintegrator = %s\noutput_rate = 50 Hz\n", m
		printf "[cloth]\nnodes = %d %d\nspacing = %.9g m\norigin = -0.12 0.2 -0.12 m\n", n, n, h
		printf "orientation = +x +z\nweight = 100 g/m2\nthickness = %.9g m\n", t
		printf "modulus_warp = %.9g Pa\nmodulus_weft = %.9g Pa\nshear_modulus = %.9g Pa\n", 50 / t, 50 / t, 5 / t
		printf "bending_warp = %g uN*m\nbending_weft = %g uN*m\n", b, b
		printf "[box]\nmin = 0.02 0 -0.1 m\nmax = 0.12 0.1 0 m\nfriction = 0.1\n"
		printf "[plane]\npoint = 0 0 0 m\nfriction = 0.1\n"
		printf "[collision]\nself = on\nbroad = grid\nnarrow = ccd\nposition = slide\nfriction = 0.1\n" }'
}
. "$here/plot.sh"

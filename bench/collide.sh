#!/usr/bin/env bash
# Collision speed benchmark: what each broad/narrow phase costs, on the
# chapter's two scenes, against the same scene with no collisions at all.
#
# For each scene and mode it runs `drape run --headless --until T` on a
# temporary copy of the scene, edited to the mode, BENCH_RUNS times (the
# modes interleaved, so that a slow spell of this shared machine hits them
# all alike), and prints the medians. Data go to $BENCH_OUT/collide.dat
# (medians) and collide-runs.dat (every run); with gnuplot, the chart to
# collide.png. See bench/README.md.
#
# Environment:
#   BENCH_RUNS        runs per scene and mode (default 3)
#   BENCH_UNTIL       simulated time of each run (default 1 s: both scenes
#                     are in self-contact by then)
#   BENCH_BRUTE_UNTIL simulated time of the brute runs (default 0.1 s)
#   BENCH_SCENES      scene names under scenes/ (default "tablecloth strip")
#   BENCH_OUT         output directory (default bench/out)
#   DRAPE             the binary (default src/drape)
#   BENCH_SRCDIR      the source tree, for scenes/ (default: this script's ..)
#   GNUPLOT           the gnuplot to draw the chart with (default gnuplot)
set -u

here=$(cd "$(dirname "$0")" && pwd)
srcdir=${BENCH_SRCDIR:-$(cd "$here/.." && pwd)}
drape=${DRAPE:-$srcdir/src/drape}
out=${BENCH_OUT:-$srcdir/bench/out}
runs=${BENCH_RUNS:-3}
until_t=${BENCH_UNTIL:-1}
brute_t=${BENCH_BRUTE_UNTIL:-0.1}
scenes=${BENCH_SCENES:-tablecloth strip}

die() { echo "collide.sh: $*" >&2; exit 2; }
case $runs in '' | *[!0-9]* | 0) die "BENCH_RUNS must be a whole number > 0, not '$runs'" ;; esac
for v in "$until_t" "$brute_t"; do
	awk -v t="$v" 'BEGIN { exit !(t + 0 > 0 && t ~ /^[0-9.eE+-]+$/) }' ||
		die "BENCH_UNTIL and BENCH_BRUTE_UNTIL are seconds > 0, not '$v'"
done
[ -x "$drape" ] || die "no binary at $drape: build first (make), or set DRAPE"
mkdir -p "$out" || die "cannot create $out"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/drape-bench.XXXXXX") || die "mktemp failed"
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM

# mode: label broad narrow position self obstacles
# "-" keeps the scene's own value; obstacles "no" removes every obstacle
# section and the [collision] section (nothing to collide with: the
# force computation and the integrator alone).
modes="none      -     -    -     off no
self-off  -     -    -     off yes
chapter   seed  seed keep  on  yes
seed      seed  ccd  slide on  yes
grid      grid  ccd  slide on  yes
brute     brute ccd  slide on  yes"

# edit SRC > DST for a mode: set the given keys in [collision] (adding the
# section if there is none), or drop [collision] and the obstacles.
edit_scene() { # src broad narrow position self obstacles
	awk -v broad="$2" -v narrow="$3" -v position="$4" -v self="$5" -v obst="$6" '
	function keys() {
		print "self = " self
		if (broad != "-") print "broad = " broad
		if (narrow != "-") print "narrow = " narrow
		if (position != "-") print "position = " position
	}
	/^[ \t]*\[/ {
		sec = $0; sub(/^[ \t]*\[/, "", sec); sub(/\].*/, "", sec)
		drop = (obst == "no" && sec ~ /^(collision|plane|box|sphere|disc|mesh|icosahedron)$/)
		if (drop) next
		print
		if (sec == "collision") { keys(); seen = 1 }
		next
	}
	drop { next }
	sec == "collision" && /^[ \t]*(self|broad|narrow|position)[ \t]*=/ { next }
	{ print }
	END { if (obst != "no" && !seen) { print ""; print "[collision]"; keys() } }
	' "$1"
}

# parse a summary on stdin into one line of figures:
# simulated wall steps_per_s node_pairs vt ee narrow contacts self_contacts obstacle
parse_summary() {
	awk '
	function num(s) { gsub(/[^0-9.eE+-]/, "", s); return s }
	/^simulated / { sim = $2 }
	/^wall time / { wall = $3 }
	/^speed / { for (i = 2; i <= NF; i++) if ($i ~ /^steps\/s/) sps = num($(i - 1)) }
	/^per step / {
		for (i = 2; i < NF; i++) {
			if ($(i + 1) == "node") np = num($i)
			if ($(i + 1) == "vertex-triangle") vt = num($i)
			if ($(i + 1) == "edge-edge") ee = num($i)
			if ($(i + 1) == "narrow") nt = num($i)
		}
	}
	/^contacts / {
		line = $0; sub(/^contacts[ \t]*/, "", line)
		n = split(line, part, ",")
		tot = 0; ob = 0
		for (k = 1; k <= n; k++) {
			m = split(part[k], w, " ")
			if (m < 2) continue
			tot += w[m]
			if (w[1] == "obstacle") ob += w[m]
		}
		ct = tot; oc = ob; sc = tot - ob
	}
	END {
		if (np == "") np = 0; if (vt == "") vt = 0; if (ee == "") ee = 0
		if (nt == "") nt = 0; if (ct == "") { ct = 0; sc = 0; oc = 0 }
		print sim, wall, sps, np, vt, ee, nt, ct, sc, oc
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

version=$("$drape" --version 2>/dev/null | head -n 1)
commit=$(git -C "$srcdir" rev-parse --short HEAD 2>/dev/null || echo "?")
cpu=$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo 2>/dev/null)
ncpu=$(nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo "?")
stamp=$(date -u '+%Y-%m-%d %H:%M UTC')

echo "collision benchmark: $version (commit $commit), $stamp"
echo "machine: $ncpu cores, ${cpu:-unknown cpu}; load $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)"
echo "runs: median of $runs per scene and mode; simulated $until_t s (brute: the first $brute_t s only, it is slow)"
echo

# prepare the scene copies
for sc in $scenes; do
	src=$srcdir/scenes/$sc.scene
	[ -r "$src" ] || die "no scene $src"
	while read -r label broad narrow position self obst; do
		edit_scene "$src" "$broad" "$narrow" "$position" "$self" "$obst" >"$tmp/$sc-$label.scene"
	done <<<"$modes"
done

rawf=$out/collide-runs.dat
{
	echo "# drape collision benchmark, every run: $version (commit $commit), $stamp"
	echo "# machine: $ncpu cores, ${cpu:-unknown cpu}"
	echo "# scene mode run until exit simulated wall steps_per_s node_pairs vt_pairs ee_pairs narrow_tests contacts self_contacts obstacle_contacts cpu"
} >"$rawf"
TIMEFORMAT='%3U %3S'

bad=0
nmodes=$(wc -l <<<"$modes")
total=$((runs * nmodes * $(wc -w <<<"$scenes")))
done_n=0
for r in $(seq 1 "$runs"); do
	for sc in $scenes; do
		while read -r label _; do
			t=$until_t
			[ "$label" = brute ] && t=$brute_t
			f=$tmp/$sc-$label.scene
			done_n=$((done_n + 1))
			[ -t 2 ] && printf '\r  run %d/%d: %s %s (%s s)          ' "$done_n" "$total" "$sc" "$label" "$t" >&2
			# bash's time: the CPU seconds (user + system) of the run, which a
			# busy machine inflates less than the wall time
			{ time "$drape" run --headless --until "$t" "$f" >"$tmp/stdout" 2>"$tmp/stderr"; } 2>"$tmp/time"
			rc=$?
			cpu_s=$(awk 'NF == 2 { printf "%.3f", $1 + $2 }' "$tmp/time")
			fig=$(parse_summary <"$tmp/stdout")
			case $rc in
			0) ;;
			3) sed "s|$tmp/||" "$tmp/stderr" | head -n 1 >"$tmp/$sc-$label.blowup" ;;
			*)
				bad=1
				{ echo; echo "collide.sh: $sc $label: drape exited $rc:"; sed 's/^/  /' "$tmp/stderr"; } >&2
				;;
			esac
			echo "$sc $label $r $t $rc $fig ${cpu_s:--}" >>"$rawf"
		done <<<"$modes"
	done
done
[ -t 2 ] && printf '\r%60s\r' '' >&2

# medians; ratio = median over the runs of (this mode's wall/simulated) /
# (the none mode's wall/simulated in the same round)
datf=$out/collide.dat
{
	echo "# drape collision benchmark: $version (commit $commit), $stamp"
	echo "# machine: $ncpu cores, ${cpu:-unknown cpu}; medians of $runs runs; until $until_t s, brute $brute_t s"
	echo "# wall_per_sim: wall seconds per simulated second; ratio: that over the no-collision (none) run of the same round"
	echo "# cpu_per_sim, cpu_ratio: the same with the run's CPU time (user + system) in place of its wall time"
	echo "# per-step figures are averages over the steps of a run; contacts are over the run (they grow with until)"
	echo "# '-' is missing: the mode blew up (exit 3) or failed (status column)"
	echo "# idx scene mode until status wall_per_sim ratio steps_per_s node_pairs vt_pairs ee_pairs narrow_tests contacts self_contacts obstacle_contacts cpu_per_sim cpu_ratio"
} >"$datf"

hdr='%-10s %-9s %5s %9s %7s %8s %7s %8s %10s %10s %10s %8s %8s\n'
printf "$hdr" scene mode T wall/sim ratio cpu/sim ratio steps/s vt/step ee/step narrow/st self obstacle
printf "$hdr" '' '' '(s)' '(s/s)' /none '(s/s)' /none '' pairs pairs tests contacts contacts
first=1
for sc in $scenes; do
	[ $first = 1 ] || printf '\n\n' >>"$datf"
	first=0
	idx=0
	while read -r label _; do
		idx=$((idx + 1))
		rows=$(awk -v s="$sc" -v m="$label" '$1 == s && $2 == m' "$rawf")
		t=$(awk 'NR == 1 { print $4 }' <<<"$rows")
		nrc=$(awk '$5 != 0' <<<"$rows" | wc -l)
		status=ok
		if [ "$nrc" -gt 0 ]; then
			if awk '$5 != 0 && $5 != 3 { f = 1 } END { exit !f }' <<<"$rows"; then
				status=error
			else
				status=blowup
			fi
		fi
		if [ $status = ok ]; then
			col() { awk -v c="$1" '{ print $c }' <<<"$rows" | median; }
			wps=$(awk '$6 > 0 { printf "%.6g\n", $7 / $6 }' <<<"$rows" | median)
			sps=$(col 8); np=$(col 9); vt=$(col 10); ee=$(col 11); nt=$(col 12)
			ct=$(col 13); sct=$(col 14); oct=$(col 15)
			cps=$(awk '$6 > 0 && $16 != "-" { printf "%.6g\n", $16 / $6 }' <<<"$rows" | median)
			ratio_of() { # column of the time
				awk -v s="$sc" -v m="$label" -v c="$1" '
				$1 == s && $2 == "none" && $5 == 0 && $6 > 0 && $c != "-" { base[$3] = $c / $6 }
				$1 == s && $2 == m && $5 == 0 && $6 > 0 && $c != "-" { this[$3] = $c / $6 }
				END { for (r in this) if ((r in base) && base[r] > 0) printf "%.6g\n", this[r] / base[r] }
				' "$rawf" | median
			}
			ratio=$(ratio_of 7)
			cratio=$(ratio_of 16)
		else
			wps=-; ratio=-; sps=-; np=-; vt=-; ee=-; nt=-; ct=-; sct=-; oct=-; cps=-; cratio=-
		fi
		echo "$idx $sc $label $t $status $wps $ratio $sps $np $vt $ee $nt $ct $sct $oct $cps $cratio" >>"$datf"
		case $status in
		ok)
			printf '%-10s %-9s %5s %9.4g %6.3gx %8.4g %6.3gx %8.0f %10.1f %10.1f %10.1f %8s %8s\n' \
				"$sc" "$label" "$t" "$wps" "$ratio" "$cps" "$cratio" "$sps" "$vt" "$ee" "$nt" "$sct" "$oct"
			;;
		blowup)
			printf '%-10s %-9s %5s BLEW UP (exit 3) in %d of %d runs: %s\n' "$sc" "$label" "$t" \
				"$nrc" "$runs" "$(cat "$tmp/$sc-$label.blowup" 2>/dev/null)"
			;;
		*)
			printf '%-10s %-9s %5s FAILED (drape exit status other than 0 or 3; see above)\n' \
				"$sc" "$label" "$t"
			;;
		esac
	done <<<"$modes"
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
load average at the end: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null) ($ncpu cores)
data: $datf
EOF

gnuplot=${GNUPLOT:-gnuplot}
if command -v "$gnuplot" >/dev/null 2>&1; then
	if "$gnuplot" -e "datf='$datf'; outf='$out/collide.png'; runs='$runs'; until_t='$until_t'; brute_t='$brute_t'; stamp='$stamp'; ncpu='$ncpu'" \
		"$here/collide.gp" 2>"$tmp/gp.err"; then
		echo "chart: $out/collide.png"
	else
		echo "collide.sh: gnuplot failed, no chart:" >&2
		cat "$tmp/gp.err" >&2
		bad=1
	fi
else
	echo "gnuplot not found: no chart drawn (the figures above are the whole result)."
	echo "  To draw $out/collide.png, install it:  sudo apt-get install -y gnuplot-nox"
	echo "  (Debian/Ubuntu; gnuplot elsewhere), then run make bench again."
fi
exit $bad

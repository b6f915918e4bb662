#!/usr/bin/env bash
# Stability benchmark: the largest stable step of each explicit integrator,
# and of implicit-euler, fast and bdf2, as the cloth's stretch stiffness grows,
# against the limit theory gives.
#
# For each stiffness factor s of BENCH_ST_FACTORS it writes a copy of the
# scene with modulus_warp and modulus_weft multiplied by s, reads omega (the
# Gershgorin bound on the highest angular frequency, from the run summary),
# and for each of euler, symplectic-euler, rk2 and rk4 finds by bisection
# (on log dt) the largest dt at which `drape run --until T` does not blow up
# (exit status 3) within T = BENCH_ST_UNTIL simulated seconds. The search
# runs between dt = T / BENCH_ST_MAXSTEPS (the smallest step it can afford)
# and 8 / omega, down to a ratio of 1 + BENCH_ST_REL between the stable and
# the unstable step.
#
# fast (position-based substeps, the stretch solved along the yarns) and
# bdf2 (a Newton solve over the whole cloth a step) are searched as
# implicit-euler is: neither has a limit of the explicit kind to find.
#
# implicit-euler is stable at any step for a linear system, so 8 / omega (its
# first probe there) would not blow up and the search would end at once,
# "above". Its search goes up to T instead, the longest step a run of T can
# take (one step for the whole run; a longer --dt is cut to T): it probes
# dt = T, T / sqrt(10), T / 10, ... down to the last one >= 1 / omega (the
# explicit methods' limits are a few / omega), from the smallest up, and
# bisects between the last stable and the first that blows up, if one does;
# if none does, it is written "above": no limit found up to T. The CG
# counts of its largest stable probe (iterations a solve, unconverged
# solves; the scene's tolerance) are in the CSV, with the total energy at T
# of that run and of the smallest step scanned: a run that does not blow up
# (drape's check is on the speed and on springs torn past ten times their
# length) may still end far off.
#
# Data go to $BENCH_RESULTS/stability.csv; with gnuplot, the chart to
# stability.png and a text chart on stdout. See bench/README.md.
#
# Theory, for the fastest mode, omega, with mass-proportional damping c
# (eigenvalues -c/2 +- i sqrt(omega^2 - c^2/4), of modulus omega):
#   rk4               dt < 2 sqrt(2) / omega  (its interval on the imaginary axis)
#   symplectic-euler  dt < 2 / omega
#   euler             dt < c / omega^2        (unstable undamped; |1 + dt lambda| < 1)
#   rk2               dt < (4 c)^(1/3) / omega^(4/3)  (|R|^2 = 1 - c dt + (omega dt)^4 / 4 + ...)
#   implicit-euler    any dt (A-stable: |1 / (1 - dt lambda)| < 1 when Re lambda <= 0;
#                     the cloth is not linear, and one Newton step a step is not exact)
# A run of finite length T only blows up once its fastest mode has grown
# past the blow-up threshold, so euler's and rk2's measured limits sit above
# these, by a margin that shrinks as T grows (see bench/README.md).
#
# Environment:
#   BENCH_ST_SCENE     scene name under scenes/ (default hanging)
#   BENCH_ST_FACTORS   stiffness factors (default 1 4 16 64 256)
#   BENCH_ST_UNTIL     simulated time T of each run (default 0.05 s)
#   BENCH_ST_MAXSTEPS  the most steps a run may take (default 1e6)
#   BENCH_ST_REL       bisection stops when unstable / stable < 1 + this (default 0.01)
#   BENCH_RESULTS      output directory (default bench/results)
#   DRAPE, BENCH_SRCDIR, GNUPLOT  the binary, the source tree, the gnuplot
set -u

here=$(cd "$(dirname "$0")" && pwd)
srcdir=${BENCH_SRCDIR:-$(cd "$here/.." && pwd)}
drape=${DRAPE:-$srcdir/src/drape}
out=${BENCH_RESULTS:-$srcdir/bench/results}
scene_name=${BENCH_ST_SCENE:-hanging}
factors=${BENCH_ST_FACTORS:-1 4 16 64 256}
until_t=${BENCH_ST_UNTIL:-0.05}
maxsteps=${BENCH_ST_MAXSTEPS:-1e6}
rel=${BENCH_ST_REL:-0.01}
methods="euler symplectic-euler rk2 rk4 implicit-euler fast bdf2"

die() { echo "stability.sh: $*" >&2; exit 2; }
isnum() { awk -v t="$1" 'BEGIN { exit !(t + 0 > 0 && t ~ /^[0-9.eE+-]+$/) }'; }
for v in $factors $until_t $maxsteps $rel; do isnum "$v" || die "not a number > 0: '$v'"; done
[ -x "$drape" ] || die "no binary at $drape: build first (make), or set DRAPE"
src=$srcdir/scenes/$scene_name.scene
[ -r "$src" ] || die "no scene $src"
mkdir -p "$out" || die "cannot create $out"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/drape-st.XXXXXX") || die "mktemp failed"
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM

# the scene with modulus_warp and modulus_weft times s (number, then unit)
scale_scene() { # src factor
	awk -v s="$2" '
	/^[ \t]*modulus_(warp|weft)[ \t]*=/ {
		line = $0; sub(/#.*/, "", line)
		key = line; sub(/[ \t]*=.*/, "", key); sub(/^[ \t]*/, "", key)
		val = line; sub(/^[^=]*=[ \t]*/, "", val)
		num = val; sub(/[^0-9.eE+-].*/, "", num)
		unit = substr(val, length(num) + 1)
		printf "%s = %.10g%s\n", key, num * s, unit
		next
	}
	{ print }' "$1"
}

# damping c (/s) of the scene, 0 if none
damping=$(awk '/^[ \t]*damping[ \t]*=/ { v = $0; sub(/^[^=]*=[ \t]*/, "", v); sub(/[^0-9.eE+-].*/, "", v); print v + 0; f = 1 } END { if (!f) print 0 }' "$src")

# probe SCENE METHOD DT: 0 stable (completed T), 1 blew up (exit 3), else
# die; the summary of the last stable probe is kept in $tmp/stable.out, and
# implicit-euler's unconverged solves are added up in unc_all
probe() {
	"$drape" run --headless --until "$until_t" --integrator "$2" --dt "$3" "$1" >"$tmp/stdout" 2>"$tmp/stderr"
	case $? in
	0)
		cp "$tmp/stdout" "$tmp/stable.out"
		unc_all=$((unc_all + $(cg_of "$tmp/stdout" unconverged)))
		return 0
		;;
	3) return 1 ;;
	*) die "$2 at dt $3: drape failed: $(head -n 1 "$tmp/stderr")" ;;
	esac
}

# energy_of SUMMARY: the total energy (J) at the end, "-" if no summary
energy_of() {
	[ -f "$1" ] || { echo -; return; }
	awk '/^energy / { e = $2 } END { print (e == "" ? "-" : e) }' "$1"
}

# cg_of SUMMARY iters|unconverged: from implicit-euler's "steps N (N solves,
# M CG iterations each, K unconverged)"; "-" (iters) or 0 for the others
cg_of() {
	awk -v w="$2" '/^steps / {
		for (i = 2; i <= NF; i++) {
			if (w == "iters" && $i == "CG") r = $(i - 1)
			if (w == "unconverged" && $i ~ /^unconverged/) r = $(i - 1)
		}
	} END { print (r == "" ? (w == "iters" ? "-" : 0) : r) }' "$1"
}

version=$("$drape" --version 2>/dev/null | head -n 1)
commit=$(git -C "$srcdir" rev-parse --short HEAD 2>/dev/null || echo "?")
ncpu=$(nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo "?")
stamp=$(date -u '+%Y-%m-%d %H:%M UTC')
echo "stability benchmark: $version (commit $commit), $stamp"
echo "machine: $ncpu cores; load $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)"
echo "scene $scene_name (damping c = $damping /s), stretch moduli times $factors; T = $until_t s; bisection to $rel"
echo

csv=$out/stability.csv
echo "factor,omega_rad_s,damping_per_s,method,status,dt_stable_s,dt_unstable_s,dt_theory_s,stable_over_theory,stable_times_omega,probes,until_s,cap_s,cg_iters,unconverged,unconverged_all,energy_J,dt_smallest_s,energy_smallest_J,result" >"$csv"
hdr='%7s %11s %-16s %-6s %12s %12s %12s %9s %8s %6s %s\n'
printf "$hdr" factor omega method status 'stable dt' 'unstable dt' 'theory dt' meas/th 'dt*omega' probes ''
tol=$(awk '/^[ \t]*tolerance[ \t]*=/ { v = $0; sub(/^[^=]*=[ \t]*/, "", v); sub(/[ \t#].*/, "", v); print v; f = 1 } END { if (!f) print "default" }' "$src")
for s in $factors; do
	f=$tmp/s$s.scene
	scale_scene "$src" "$s" >"$f"
	"$drape" run --headless --until 1e-6 "$f" >"$tmp/probe" 2>&1 || die "factor $s: probe run failed: $(cat "$tmp/probe")"
	omega=$(sed -n 's/^integrator .*omega <= \([0-9.eE+-]*\) rad\/s.*/\1/p' "$tmp/probe")
	isnum "$omega" || die "factor $s: no omega in the run summary"
	for m in $methods; do
		th=$(awk -v m="$m" -v w="$omega" -v c="$damping" 'BEGIN {
			if (m == "implicit-euler" || m == "fast" || m == "bdf2") { print "-"; exit }
			if (m == "rk4") t = 2 * sqrt(2) / w
			else if (m == "symplectic-euler") t = 2 / w
			else if (m == "euler") t = c / (w * w)
			else t = (4 * c) ^ (1 / 3) / w ^ (4 / 3)
			printf "%.6e", t }')
		lo=$(awk -v u="$until_t" -v n="$maxsteps" 'BEGIN { printf "%.6e", u / n }')
		if [ $m = implicit-euler ] || [ $m = fast ] || [ $m = bdf2 ]; then
			hi=$(awk -v u="$until_t" 'BEGIN { printf "%.6e", u }')
		else
			hi=$(awk -v w="$omega" 'BEGIN { printf "%.6e", 8 / w }')
		fi
		cap=$hi
		n=0 status=ok unc_all=0
		rm -f "$tmp/stable.out" "$tmp/smallest.out"
		dsmall=-
		[ -t 2 ] && printf '\r  factor %s %s ...          ' "$s" "$m" >&2
		if [ $m = implicit-euler ] || [ $m = fast ] || [ $m = bdf2 ]; then
			# the scan, from the smallest step up: T / 10^(k/2) >= 1 / omega
			scan=$(awk -v u="$until_t" -v w="$omega" -v lo="$lo" 'BEGIN {
				for (k = 0; u / 10 ^ (k / 2) >= 1 / w && u / 10 ^ (k / 2) >= lo; k++) d[k] = u / 10 ^ (k / 2)
				for (k--; k >= 0; k--) printf "%.6e\n", d[k] }')
			status=above lo=- hi=-
			for d in $scan; do
				n=$((n + 1))
				if probe "$f" "$m" "$d"; then lo=$d; else hi=$d status=ok; break; fi
				if [ $n = 1 ]; then cp "$tmp/stable.out" "$tmp/smallest.out"; dsmall=$d; fi
			done
			if [ $status = ok ] && [ "$lo" = - ]; then
				# the smallest of the scan blew up: search below it
				lo=$(awk -v u="$until_t" -v n="$maxsteps" 'BEGIN { printf "%.6e", u / n }')
				n=$((n + 1))
				probe "$f" "$m" "$lo" || status=below lo=- hi=$lo
			fi
			if [ $status = ok ]; then
				while awk -v a="$lo" -v b="$hi" -v r="$rel" 'BEGIN { exit !(b / a > 1 + r) }'; do
					mid=$(awk -v a="$lo" -v b="$hi" 'BEGIN { printf "%.6e", sqrt(a * b) }')
					n=$((n + 1))
					if probe "$f" "$m" "$mid"; then lo=$mid; else hi=$mid; fi
				done
			fi
		else
			n=$((n + 1))
			if probe "$f" "$m" "$hi"; then
				status=above lo=$hi hi=-
			else
				n=$((n + 1))
				if ! probe "$f" "$m" "$lo"; then
					status=below hi=$lo lo=-
				else
					while awk -v a="$lo" -v b="$hi" -v r="$rel" 'BEGIN { exit !(b / a > 1 + r) }'; do
						mid=$(awk -v a="$lo" -v b="$hi" 'BEGIN { printf "%.6e", sqrt(a * b) }')
						n=$((n + 1))
						if probe "$f" "$m" "$mid"; then lo=$mid; else hi=$mid; fi
					done
				fi
			fi
		fi
		ratio=$(awk -v a="$lo" -v t="$th" 'BEGIN { if (a == "-" || t == "-") print "-"; else printf "%.4g", a / t }')
		dw=$(awk -v a="$lo" -v w="$omega" 'BEGIN { if (a == "-") print "-"; else printf "%.4g", a * w }')
		cgi=- unc=-
		if [ $m = implicit-euler ] && [ -f "$tmp/stable.out" ]; then
			cgi=$(cg_of "$tmp/stable.out" iters) unc=$(cg_of "$tmp/stable.out" unconverged)
		fi
		[ $m = implicit-euler ] || unc_all=-
		en=$(energy_of "$tmp/stable.out") ensmall=$(energy_of "$tmp/smallest.out")
		case $status in
		ok) result=$(printf '%.3e s' "$lo") ;;
		below) result=$(printf 'below %.3g s' "$hi") ;;
		above) result=$(printf 'no limit found up to %.3g s' "$cap") ;;
		esac
		echo "$s,$omega,$damping,$m,$status,$lo,$hi,$th,$ratio,$dw,$n,$until_t,$cap,$cgi,$unc,$unc_all,$en,$dsmall,$ensmall,$result" >>"$csv"
		note=
		[ $status = above ] && note="$result"
		[ $m = implicit-euler ] && note="${note:+$note; }at the largest stable dt: $cgi CG it./solve, $unc unconverged ($unc_all over all probes), energy at T $en J ($ensmall J at dt $dsmall)"
		case $m in fast | bdf2) note="${note:+$note; }energy at T $en J ($ensmall J at dt $dsmall)" ;; esac
		[ -t 2 ] && printf '\r%60s\r' '' >&2
		printf "$hdr" "$s" "$omega" "$m" "$status" "$lo" "$hi" "$th" "$ratio" "$dw" "$n" "$note"
	done
done
cat <<EOF

stable dt: the largest step found that ran T = $until_t s without blowing up;
  unstable dt: the smallest that blew up (status below: even dt = T / $maxsteps
  blew up, the limit is under it; above: the top of the search, 8 / omega, or
  T for implicit-euler, did not: no limit found up to there).
theory dt: rk4 2 sqrt(2) / omega, symplectic-euler 2 / omega, euler c / omega^2,
  rk2 (4 c)^(1/3) / omega^(4/3), omega the Gershgorin bound, c = $damping /s;
  implicit-euler: any dt (for a linear system). It is searched up to T,
  probing T / 10^(k/2) from the smallest >= 1 / omega up (CG tolerance: $tol);
  fast and bdf2 are searched the same way;
  energy at T: the total energy at the end of the run at the largest stable dt,
  and of the smallest dt scanned (drape's blow-up check is on the speed and on
  springs torn past 10x their length: a run that does not blow up may still
  end far off).
meas/th: stable dt over theory dt; dt*omega: the stable dt times omega.
dopri5 is not searched: its step is adaptive (--dt is only its first and
  largest step) and its error control rejects the steps that would blow up.
data: $csv
EOF

prog=stability.sh
. "$here/plot.sh"
plot stability.gp "$csv" "$out/stability.png" \
	"stamp='$stamp'; until_t='$until_t'; scene='$scene_name'; damping='$damping'" || exit 1
exit 0

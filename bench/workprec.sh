#!/usr/bin/env bash
# Work-precision benchmark: error against a converged reference against CPU
# time, for each integrator over a range of steps (and dopri5 over a range
# of tolerances), on the hanging strip and the cantilever.
#
# For each scene it runs a reference (RK4 at a step far below the others',
# BENCH_WP_REF / omega, omega the Gershgorin bound drape prints), then every
# explicit method at dt = f / omega for each factor f of BENCH_WP_FACTORS
# (euler also at BENCH_WP_EULER_FACTORS: it needs far smaller steps), dopri5
# at each tolerance of BENCH_WP_TOLS (the scene's `tolerance` key, on a copy
# of the scene, its largest step BENCH_WP_DOPRI_DT), and implicit-euler at
# dt = f / omega for each f of BENCH_WP_IMPLICIT_FACTORS (stable at any step:
# they reach far above the others') once for each CG tolerance of
# BENCH_WP_IMPLICIT_TOLS (the same `tolerance` key, which for implicit-euler
# is the relative residual of its linear solve), and fast (the
# position-based fast path) at BENCH_WP_FAST_FACTORS, and bdf2 at
# BENCH_WP_BDF2_FACTORS. Each run goes to the same end
# time (--until) and writes its final mesh (--final-obj); the error is the
# largest distance between a node there and the same node of the
# reference's final mesh. The CPU time (user + system, bash's time) is the
# median of BENCH_RUNS timings; a run faster than BENCH_WP_MINCPU is timed
# as a batch of repeats that lasts about BENCH_WP_MINCPU, over the number of
# repeats (bash's time counts whole milliseconds, and an implicit-euler run
# of a few steps takes less than one). A run that blows up (exit status 3)
# is recorded as such, not as a point. Data go to $BENCH_RESULTS/workprec.csv;
# with gnuplot, the chart to workprec.png and a text chart on stdout. See
# bench/README.md.
#
# Environment:
#   BENCH_RUNS             timings per point (default 3); the CPU time is their median
#   BENCH_WP_SCENES        scene:until pairs (default "hanging:0.02 cantilever:0.02")
#   BENCH_WP_FACTORS       dt * omega of the explicit fixed-step runs (default 4 2 1 0.5 0.25 0.125 0.0625)
#   BENCH_WP_EULER_FACTORS further dt * omega for euler only (default 1/32 .. 1/256)
#   BENCH_WP_TOLS          dopri5 tolerances (default 1e-2 .. 1e-9)
#   BENCH_WP_DOPRI_DT      dopri5's first and largest step (default 1e-3 s)
#   BENCH_WP_IMPLICIT_FACTORS  dt * omega of the implicit-euler runs (default 1024 512 ... 0.0625)
#   BENCH_WP_IMPLICIT_TOLS     implicit-euler CG tolerances (default "1e-8 1e-3")
#   BENCH_WP_FAST_FACTORS  dt * omega of the fast runs (default: implicit-euler's)
#   BENCH_WP_BDF2_FACTORS  dt * omega of the bdf2 runs (default: implicit-euler's)
#   BENCH_WP_REF           dt * omega of the RK4 reference (default 1/64)
#   BENCH_WP_MAXSTEPS      skip a fixed-step run of more steps than this (default 1e6)
#   BENCH_WP_TARGET        error (m) for the cost-ratio table (default 1e-5)
#   BENCH_WP_MINCPU        a run under this many CPU seconds is timed in a batch (default 0.1)
#   BENCH_RESULTS          output directory (default bench/results)
#   DRAPE, BENCH_SRCDIR, GNUPLOT  the binary, the source tree, the gnuplot
set -u

here=$(cd "$(dirname "$0")" && pwd)
srcdir=${BENCH_SRCDIR:-$(cd "$here/.." && pwd)}
drape=${DRAPE:-$srcdir/src/drape}
out=${BENCH_RESULTS:-$srcdir/bench/results}
runs=${BENCH_RUNS:-3}
scenes=${BENCH_WP_SCENES:-hanging:0.02 cantilever:0.02}
factors=${BENCH_WP_FACTORS:-4 2 1 0.5 0.25 0.125 0.0625}
efactors=${BENCH_WP_EULER_FACTORS:-0.03125 0.015625 0.0078125 0.00390625}
tols=${BENCH_WP_TOLS:-1e-2 1e-3 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9}
dopri_dt=${BENCH_WP_DOPRI_DT:-1e-3}
# implicit-euler is stable at any step, so its list starts far above the
# explicit methods' limits (RK4's is 2 sqrt(2) / omega): 1024 / omega is 2.6
# decades above RK4's (on the hanging strip, until * omega = 684 caps it:
# the largest factors there are one and two steps for the whole run), and
# it ends where the explicit methods' list ends.
ifactors=${BENCH_WP_IMPLICIT_FACTORS:-1024 512 256 128 64 32 16 8 4 2 1 0.5 0.25 0.125 0.0625}
# Its CG tolerances (the residual relative to the right-hand side). 1e-8
# is tight enough for the solve's error not to show: in a trial at every
# other factor of the list (1024, 256, ... 1/16), 1e-6, 1e-8 and 1e-10 gave
# the same error to 3-4 digits on both scenes; so the 1e-8 line is the
# method's own error. 1e-3 is run too: it is the default (what a run gets
# unless its scene sets `tolerance`); it gives 1e-8's error to 5 % from
# dt * omega = 1/2 up, for the same or up to 2.2x less CPU time, but below
# that on the cantilever its error is up to 1.9x 1e-8's: there the solve's
# error shows (results/workprec.csv of 2026-12-01, bench/README.md).
itols=${BENCH_WP_IMPLICIT_TOLS:-1e-8 1e-3}
# The fast path (position-based substeps, pbd.h): its step is cut into
# substeps for its soft forces, so it too runs at any step; the same
# factors as implicit-euler's.
ffactors=${BENCH_WP_FAST_FACTORS:-$ifactors}
# bdf2 (the implicit step over the whole cloth, bdf2.h): stable at any
# step too, at its default Newton tolerance; the same factors.
bfactors=${BENCH_WP_BDF2_FACTORS:-$ifactors}
ref_f=${BENCH_WP_REF:-0.015625}
maxsteps=${BENCH_WP_MAXSTEPS:-1e6}
target=${BENCH_WP_TARGET:-1e-5}
mincpu=${BENCH_WP_MINCPU:-0.1}

die() { echo "workprec.sh: $*" >&2; exit 2; }
case $runs in '' | *[!0-9]* | 0) die "BENCH_RUNS must be a whole number > 0, not '$runs'" ;; esac
isnum() { awk -v t="$1" 'BEGIN { exit !(t + 0 > 0 && t ~ /^[0-9.eE+-]+$/) }'; }
for v in $factors $efactors $tols $dopri_dt $ifactors $itols $ffactors $ref_f $maxsteps $target $mincpu; do
	isnum "$v" || die "not a number > 0: '$v'"
done
for p in $scenes; do
	case $p in *:*) isnum "${p#*:}" || die "bad until in '$p'" ;; *) die "BENCH_WP_SCENES: scene:until, not '$p'" ;; esac
done
[ -x "$drape" ] || die "no binary at $drape: build first (make), or set DRAPE"
mkdir -p "$out" || die "cannot create $out"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/drape-wp.XXXXXX") || die "mktemp failed"
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM

median() { # numbers on stdin, one a line; prints "-" if none
	sort -g | awk '{ v[NR] = $1 }
	END {
		if (NR == 0) { print "-"; exit }
		if (NR % 2) m = v[(NR + 1) / 2]; else m = (v[NR / 2] + v[NR / 2 + 1]) / 2
		printf "%.6g\n", m
	}'
}

# largest distance between the vertices of two OBJ files, in node order
objdist() {
	awk '
	FNR == 1 { f++ }
	$1 == "v" { n[f]++; x[f, n[f]] = $2; y[f, n[f]] = $3; z[f, n[f]] = $4 }
	END {
		if (n[1] != n[2] || n[1] == 0) { print "-"; exit }
		m = 0
		for (i = 1; i <= n[1]; i++) {
			dx = x[1, i] - x[2, i]; dy = y[1, i] - y[2, i]; dz = z[1, i] - z[2, i]
			d = sqrt(dx * dx + dy * dy + dz * dz); if (d > m) m = d
		}
		printf "%.6e\n", m
	}' "$1" "$2"
}

# the step for a factor f: until / n with n = ceil(until * omega / f) steps,
# so that every run ends at the same time (dt * omega is f or a little
# less; less by up to half when f > until * omega / 2, the last few factors
# of implicit-euler on the hanging strip: dt_omega in the CSV is the actual)
stepof() {
	awk -v f="$1" -v w="$omega" -v u="$until_t" 'BEGIN {
		n = u * w / f; if (n > int(n)) n = int(n) + 1; else n = int(n)
		printf "%.15e", u / n
	}'
}

TIMEFORMAT='%3U %3S'
# run SCENE UNTIL INTEGRATOR DT OBJ: one run; sets rc, cpu_s, steps, evals,
# wall, and, from implicit-euler's "steps N (N solves, M CG iterations each,
# K unconverged)", cg (M) and unconv (K); evals is then the solves (one
# force evaluation each)
run1() {
	{ time "$drape" run --headless --until "$2" --integrator "$3" --dt "$4" \
		--final-obj "$5" "$1" >"$tmp/stdout" 2>"$tmp/stderr"; } 2>"$tmp/time"
	rc=$?
	cpu_s=$(awk 'NF == 2 { printf "%.3f", $1 + $2 }' "$tmp/time")
	steps=$(awk '/^steps / { print $2 }' "$tmp/stdout")
	evals=$(awk '/^steps / { s = $3; sub(/^\(/, "", s); print s }' "$tmp/stdout")
	wall=$(awk '/^wall time / { print $3 }' "$tmp/stdout")
	cg=$(awk '/^steps .* CG iterations/ { for (i = 2; i <= NF; i++) if ($i == "CG") print $(i - 1) }' "$tmp/stdout")
	unconv=$(awk '/^steps .* unconverged/ { for (i = 2; i <= NF; i++) if ($i ~ /^unconverged/) print $(i - 1) }' "$tmp/stdout")
}

# batch SCENE UNTIL INTEGRATOR DT N: N runs timed together; sets rc (0 if
# every run exited 0), cpu_s and wall (the summaries' wall times), each over N
batch() {
	local i r
	rc=0
	: >"$tmp/walls"
	{ time for ((i = 0; i < $5; i++)); do
		"$drape" run --headless --until "$2" --integrator "$3" --dt "$4" "$1" >"$tmp/bstdout" 2>"$tmp/stderr"
		r=$?
		[ $r = 0 ] || rc=$r
		awk '/^wall time / { print $3 }' "$tmp/bstdout" >>"$tmp/walls"
	done; } 2>"$tmp/time"
	cpu_s=$(awk -v n="$5" 'NF == 2 { printf "%.6f", ($1 + $2) / n }' "$tmp/time")
	wall=$(awk -v n="$5" '{ s += $1 } END { printf "%.6f", s / n }' "$tmp/walls")
}

version=$("$drape" --version 2>/dev/null | head -n 1)
commit=$(git -C "$srcdir" rev-parse --short HEAD 2>/dev/null || echo "?")
cpu=$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo 2>/dev/null)
ncpu=$(nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo "?")
stamp=$(date -u '+%Y-%m-%d %H:%M UTC')

echo "work-precision benchmark: $version (commit $commit), $stamp"
echo "machine: $ncpu cores, ${cpu:-unknown cpu}; load $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)"
echo "CPU time: median of $runs timings per point (a run under $mincpu s: a batch of repeats over their number)"
echo "error: max node distance to RK4 at dt = $ref_f/omega; implicit-euler: CG tolerance $itols"
echo

csv=$out/workprec.csv
echo "scene,until_s,omega_rad_s,method,param,dt_s,tolerance,status,runs,cpu_s,wall_s,steps,force_evals,error_m,dt_omega,reps,cg_iters,unconverged" >"$csv"

bad=0
hdr='%-10s %-16s %9s %10s %8s %9s %9s %11s %s\n'
printf "$hdr" scene method 'dt*omega' dt/tol status 'cpu (s)' steps 'error (m)' ''
for p in $scenes; do
	sc=${p%%:*}
	until_t=${p#*:}
	src=$srcdir/scenes/$sc.scene
	[ -r "$src" ] || die "no scene $src"
	# omega from a probe run (the Gershgorin bound; it does not depend on dt)
	"$drape" run --headless --until 1e-6 "$src" >"$tmp/probe" 2>&1 || die "$sc: probe run failed: $(cat "$tmp/probe")"
	omega=$(sed -n 's/^integrator .*omega <= \([0-9.eE+-]*\) rad\/s.*/\1/p' "$tmp/probe")
	isnum "$omega" || die "$sc: no omega in the run summary"
	ref_dt=$(stepof "$ref_f")
	[ -t 2 ] && printf '\r  %s: reference (rk4, dt %s)          ' "$sc" "$ref_dt" >&2
	run1 "$src" "$until_t" rk4 "$ref_dt" "$tmp/ref.obj"
	[ $rc = 0 ] || die "$sc: the reference run failed (exit $rc): $(head -n 1 "$tmp/stderr")"
	echo "$sc,$until_t,$omega,reference,$ref_f,$ref_dt,,ok,1,$cpu_s,$wall,$steps,$evals,0,$ref_f,1,," >>"$csv"

	# the list of points: method kind param [CG tolerance]
	{
		for m in euler symplectic-euler rk2 rk4; do
			for f in $factors; do echo "$m dt $f"; done
			[ $m = euler ] && for f in $efactors; do echo "$m dt $f"; done
		done
		for t in $tols; do echo "dopri5 tol $t"; done
		for t in $itols; do
			for f in $ifactors; do echo "implicit-euler dt $f $t"; done
		done
		for f in $ffactors; do echo "fast dt $f"; done
		for f in $bfactors; do echo "bdf2 dt $f"; done
	} >"$tmp/points"
	sed "/^[ \t]*\[simulation\]/,/^[ \t]*\[/{/^[ \t]*tolerance[ \t]*=/d}" "$src" >"$tmp/base.scene"
	while read -r m kind par itol; do
		scene=$src tol= dw=
		if [ $kind = dt ]; then
			dt=$(stepof "$par")
			dw=$(awk -v d="$dt" -v w="$omega" 'BEGIN { printf "%.6g", d * w }')
			tol=$itol
			if awk -v u="$until_t" -v d="$dt" -v mx="$maxsteps" 'BEGIN { exit !(u / d > mx) }'; then
				echo "$sc,$until_t,$omega,$m,$par,$dt,$tol,skipped,0,,,,,,$dw,,," >>"$csv"
				printf "$hdr" "$sc" "$m" "$par" "$(printf '%.4e' "$dt")" skipped - - - "${tol:+CG tol $tol}"
				continue
			fi
		else
			dt=$dopri_dt tol=$par
		fi
		if [ -n "$tol" ]; then
			scene=$tmp/tol.scene
			sed "/^[ \t]*\[simulation\]/a tolerance = $tol" "$tmp/base.scene" >"$scene"
		fi
		[ -t 2 ] && printf '\r  %s: %s %s %s %s          ' "$sc" "$m" "$kind" "$par" "$itol" >&2
		# the first run gives the status, the error and the counts, and
		# the first timing, or, if it is under mincpu, the size of a batch
		cpus= walls= reps=1 n=0
		run1 "$scene" "$until_t" "$m" "$dt" "$tmp/run.obj"
		case $rc in
		0) status=ok ;;
		3) status=blowup ;;
		*)
			status=error bad=1
			{ echo; echo "workprec.sh: $sc $m $kind $par: drape exited $rc:"; sed 's/^/  /' "$tmp/stderr"; } >&2
			;;
		esac
		if [ $status = ok ]; then
			err=$(objdist "$tmp/run.obj" "$tmp/ref.obj")
			reps=$(awk -v c="$cpu_s" -v m="$mincpu" 'BEGIN {
				if (c >= m) { print 1; exit }
				if (c < 0.001) c = 0.001
				n = m / c; n = (n > int(n)) ? int(n) + 1 : int(n)
				print (n > 1000 ? 1000 : n) }')
			for r in $(seq 1 "$runs"); do
				if [ "$reps" = 1 ]; then
					if [ $r -gt 1 ]; then
						run1 "$scene" "$until_t" "$m" "$dt" "$tmp/run.obj"
					fi
				else
					batch "$scene" "$until_t" "$m" "$dt" "$reps"
				fi
				if [ $rc != 0 ]; then
					status=error bad=1
					echo "workprec.sh: $sc $m $kind $par: a timed run exited $rc" >&2
					break
				fi
				n=$((n + 1))
				cpus="$cpus$cpu_s
"
				walls="$walls$wall
"
			done
		fi
		if [ $kind = dt ]; then
			pcol=$par dcol=$(printf '%.4e' "$dt")
		else
			pcol=- dcol="tol $tol"
		fi
		note=
		[ $m = implicit-euler ] && note="CG tol $tol"
		if [ $status = ok ]; then
			cmed=$(printf '%s' "$cpus" | median)
			wmed=$(printf '%s' "$walls" | median)
			echo "$sc,$until_t,$omega,$m,$par,$dt,$tol,ok,$n,$cmed,$wmed,$steps,$evals,$err,$dw,$reps,$cg,$unconv" >>"$csv"
			[ -n "$cg" ] && note="$note, $cg CG it./solve, $unconv unconverged"
			[ "$reps" != 1 ] && note="${note:+$note, }timed x$reps"
			[ -t 2 ] && printf '\r%60s\r' '' >&2
			printf "$hdr" "$sc" "$m" "$pcol" "$dcol" ok "$cmed" "$steps" "$err" "$note"
		else
			echo "$sc,$until_t,$omega,$m,$par,$dt,$tol,$status,0,,,$steps,,,$dw,,$cg,$unconv" >>"$csv"
			[ -t 2 ] && printf '\r%60s\r' '' >&2
			printf "$hdr" "$sc" "$m" "$pcol" "$dcol" \
				"$([ $status = blowup ] && echo "BLEW UP" || echo FAILED)" - "$steps" - "$note"
		fi
	done <"$tmp/points"
	printf '%-10s reference: rk4 at dt %s s (%s/omega, omega <= %s rad/s), until %s s\n\n' "$sc" "$ref_dt" "$ref_f" "$omega" "$until_t"
done

# cost ratio: the cheapest point of each method (implicit-euler: of each CG
# tolerance) within the target error, over rk4's, per scene (all the times
# of one run of this script)
echo "cheapest CPU time to an error <= $target m, and its ratio to rk4's (this run):"
awk -F, -v tgt="$target" -v itols="$itols" '
function label(m, t) { return m == "implicit-euler" ? m " tol " t : m }
NR > 1 && $8 == "ok" && $4 != "reference" && $14 + 0 <= tgt {
	k = $1 SUBSEP label($4, $7)
	if (!(k in best) || $10 + 0 < best[k]) {
		best[k] = $10 + 0
		at[k] = ($4 == "dopri5" ? "tol " $7 : "dt*omega " $5) (($4 == "implicit-euler" && $15 + 0 < 0.99 * $5) ? " (" $15 ")" : "")
	}
}
NR > 1 && !($1 in seen) { seen[$1] = 1; order[++ns] = $1 }
END {
	nm = split("euler symplectic-euler rk2 rk4 dopri5", ms, " ")
	nt = split(itols, ts, " ")
	for (i = 1; i <= nt; i++) ms[++nm] = label("implicit-euler", ts[i])
	ms[++nm] = "fast"
	ms[++nm] = "bdf2"
	for (s = 1; s <= ns; s++) {
		sc = order[s]; r = ((sc, "rk4") in best) ? best[sc, "rk4"] : 0
		for (i = 1; i <= nm; i++) {
			k = sc SUBSEP ms[i]
			if (k in best)
				printf "  %-10s %-24s %9.4f s at %-18s %s\n", sc, ms[i], best[k], at[k], \
					(r > 0 ? sprintf("%.2fx rk4", best[k] / r) : "")
			else
				printf "  %-10s %-24s none within %s m (blew up, skipped or too coarse)\n", sc, ms[i], tgt
		}
	}
}' "$csv"
echo
echo "load average at the end: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null) ($ncpu cores)"
echo "data: $csv"

prog=workprec.sh
. "$here/plot.sh"
plot workprec.gp "$csv" "$out/workprec.png" \
	"runs='$runs'; stamp='$stamp'; ncpu='$ncpu'; itols='$itols'; scenes='$(for p in $scenes; do printf '%s ' "${p%%:*}"; done)'" || bad=1
exit $bad

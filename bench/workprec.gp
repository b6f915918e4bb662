# Chart of bench/workprec.sh's points (workprec.csv): gnuplot -e "csv=...;
# term='png'|'dumb'; outf=...; scenes=...; runs=...; stamp=...; ncpu=...; itols=..." workprec.gp
# term = 'dumb' draws it as text on stdout instead of the PNG outf.
#
# One panel per scene: error against the reference (max node distance, m)
# against CPU seconds, log-log, one line per method (implicit-euler: one per
# CG tolerance of itols); the runs that blew up are counted in the key, not
# drawn.
#
# workprec.csv columns: 1 scene, 2 until_s, 3 omega_rad_s, 4 method, 5 param
# (dt*omega or tolerance), 6 dt_s, 7 tolerance, 8 status, 9 runs, 10 cpu_s,
# 11 wall_s, 12 steps, 13 force_evals, 14 error_m, 15 dt_omega, 16 reps,
# 17 cg_iters, 18 unconverged

if (!exists("csv")) csv = "workprec.csv"
if (!exists("outf")) outf = "workprec.png"
if (!exists("term")) term = "png"
if (!exists("scenes")) scenes = "hanging cantilever"
if (!exists("runs")) runs = "?"
if (!exists("stamp")) stamp = ""
if (!exists("ncpu")) ncpu = "?"
if (!exists("itols")) itols = "1e-8 1e-3"

nsc = words(scenes)
# the series: the five explicit methods, fast and bdf2, then implicit-euler
# once per CG tolerance (ntol at most 2)
nexp = 7
ntol = words(itols) > 2 ? 2 : words(itols)
nser = nexp + ntol
methods = "euler symplectic-euler rk2 rk4 dopri5 fast bdf2"
array col[9] = ["#9467bd", "#2ca02c", "#ff7f0e", "#1f77b4", "#d62728", "#8c564b", "#000000", "#e377c2", "#17becf"]
array pt[9] = [4, 6, 8, 7, 5, 9, 11, 13, 3]
meth(i) = i <= nexp ? word(methods, i) : "implicit-euler"
tolof(i) = i <= nexp ? "" : word(itols, i - nexp)

# the points of one scene and series that ran: cpu error (t: the CG
# tolerance of implicit-euler, "" for the others)
pts(s, m, t) = sprintf("< awk -F, '$1 == \"%s\" && $4 == \"%s\" && (\"%s\" == \"\" || $7 == \"%s\") && $8 == \"ok\" && $10 > 0 && $14 > 0 { print $10, $14 }' '%s'", s, m, t, t, csv)
cnt(s, m, t, st) = int(system(sprintf("awk -F, '$1 == \"%s\" && $4 == \"%s\" && (\"%s\" == \"\" || $7 == \"%s\") && $8 == \"%s\"' '%s' | wc -l", s, m, t, t, st, csv)))
name(i) = meth(i) . (i > nexp ? " (CG tol " . tolof(i) . ")" : "")
title(s, i) = name(i) . (meth(i) eq "dopri5" ? " (tolerance)" : "") . \
	(cnt(s, meth(i), tolof(i), "blowup") > 0 ? sprintf(": %d of %d blew up", cnt(s, meth(i), tolof(i), "blowup"), \
		cnt(s, meth(i), tolof(i), "blowup") + cnt(s, meth(i), tolof(i), "ok")) : "")
until_of(s) = system(sprintf("awk -F, '$1 == \"%s\" { print $2; exit }' '%s'", s, csv))

set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set grid xtics ytics mxtics mytics
set xlabel "CPU seconds (user + system, median)"
set ylabel "max node distance to reference (m)"
set key outside right top

if (term eq "dumb") {
	set terminal dumb size 120,34
	set format x "%.0e"
	set format y "%.0e"
	set key outside right top
	do for [s = 1:nsc] {
		sc = word(scenes, s)
		set title sprintf("work-precision, %s, until %s s", sc, until_of(sc))
		plot for [i = 1:nser] pts(sc, meth(i), tolof(i)) using 1:2 with linespoints title name(i)
	}
} else {
	set terminal pngcairo size 1100, 500 * nsc font "Sans,11"
	set output outf
	set multiplot layout nsc,1 title sprintf("drape work-precision (CPU: median of %s timings, %s cores, %s)", runs, ncpu, stamp) font ",13"
	do for [s = 1:nsc] {
		sc = word(scenes, s)
		set title sprintf("%s, until %s s: error against RK4 at a far smaller dt, against CPU time", sc, until_of(sc))
		# the second and third implicit-euler tolerances dashed
		plot for [i = 1:nexp + 1] pts(sc, meth(i), tolof(i)) using 1:2 with linespoints \
			lc rgb col[i] pt pt[i] ps 1.2 lw 2 title title(sc, i), \
			for [i = nexp + 2:nser] pts(sc, meth(i), tolof(i)) using 1:2 with linespoints \
			lc rgb col[i] pt pt[i] ps 1.2 lw 2 dt 2 title title(sc, i)
	}
	unset multiplot
}

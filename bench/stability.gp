# Chart of bench/stability.sh's results (stability.csv): gnuplot -e "csv=...;
# term='png'|'dumb'; outf=...; stamp=...; until_t=...; scene=...; damping=..." stability.gp
# term = 'dumb' draws it as text on stdout instead of the PNG outf.
#
# Largest stable dt against the stiffness factor, log-log: measured points
# (bisection on blow-up within until_t) joined by solid lines, the theory
# limit of each method from the Gershgorin omega as a dashed line; a method
# whose limit is below the smallest step searched is drawn at that step
# with a down-pointing triangle, one that did not blow up at the top of the
# search (implicit-euler: T, one step for the whole run) at that step with an
# up-pointing triangle: no limit found up to there. implicit-euler has no
# theory line (any dt, for a linear system); the dotted line is T.
#
# stability.csv columns: 1 factor, 2 omega_rad_s, 3 damping_per_s, 4 method,
# 5 status, 6 dt_stable_s, 7 dt_unstable_s, 8 dt_theory_s,
# 9 stable_over_theory, 10 stable_times_omega, 11 probes, 12 until_s,
# 13 cap_s, 14 cg_iters, 15 unconverged, 16 unconverged_all, 17 energy_J,
# 18 dt_smallest_s, 19 energy_smallest_J, 20 result

if (!exists("csv")) csv = "stability.csv"
if (!exists("outf")) outf = "stability.png"
if (!exists("term")) term = "png"
if (!exists("stamp")) stamp = ""
if (!exists("until_t")) until_t = "?"
if (!exists("scene")) scene = "?"
if (!exists("damping")) damping = "?"

methods = "euler symplectic-euler rk2 rk4 implicit-euler fast bdf2"
nm = 4	# the methods with a theory limit; implicit-euler, fast and bdf2 follow
array col[7] = ["#9467bd", "#2ca02c", "#ff7f0e", "#1f77b4", "#8c564b", "#d62728", "#000000"]
array pt[7] = [4, 6, 8, 7, 9, 5, 13]
array thname[4] = ["c/omega^2", "2/omega", "(4c)^{1/3}/omega^{4/3}", "2 sqrt(2)/omega"]
T = until_t + 0
if (T > 0) set yrange [*:4 * T]

sel(m, st, cols) = sprintf("< awk -F, '$4 == \"%s\" && $5 ~ /%s/ { print %s }' '%s'", m, st, cols, csv)

set logscale xy
set grid xtics ytics mytics
set xlabel "stiffness factor (modulus_warp and modulus_weft times)" noenhanced
set ylabel "largest stable dt (s)"
set xtics (1, 4, 16, 64, 256)
set xrange [0.7:370]

if (term eq "dumb") {
	set terminal dumb size 100,34
	set format y "%.0e"
	set title sprintf("largest stable dt, %s, T = %s s (points: measured, lines: theory)", scene, until_t)
	set key outside right top
	plot for [i = 1:4] sel(word(methods, i), "ok", "$1, $6") using 1:2 with points pt (i + 64) title word(methods, i), \
		sel("implicit-euler", "above", "$1, $6") using 1:2 with points pt "^" title "implicit-euler: no limit up to T", \
		sel("fast", "ok", "$1, $6") using 1:2 with points pt "f" title "fast", \
		sel("fast", "above", "$1, $6") using 1:2 with points pt "F" title "fast: no limit up to T", \
		sel("bdf2", "ok", "$1, $6") using 1:2 with points pt "b" title "bdf2", \
		sel("bdf2", "above", "$1, $6") using 1:2 with points pt "B" title "bdf2: no limit up to T", \
		for [i = 1:4] sel(word(methods, i), ".", "$1, $8") using 1:2 with lines title "theory ". word(methods, i)
} else {
	set terminal pngcairo size 1100, 750 font "Sans,11"
	set output outf
	set format y "10^{%L}"
	set title sprintf("drape: largest stable dt by bisection on blow-up within T = %s s, %s (damping c = %s /s)\n%s; solid: measured; dashed: theory from the Gershgorin omega\ndown triangle: limit below the smallest dt searched; up triangle: no blow-up up to the largest", \
		until_t, scene, damping, stamp)
	set key outside right top spacing 1.2
	plot for [i = 1:7] sel(word(methods, i), "ok", "$1, $6") using 1:2 with linespoints \
			lc rgb col[i] pt pt[i] ps 1.4 lw 2 title word(methods, i) . " (measured)", \
		for [i = 1:7] sel(word(methods, i), "below", "$1, $7") using 1:2 with points \
			lc rgb col[i] pt 11 ps 1.6 notitle, \
		for [i = 1:4] sel(word(methods, i), "above", "$1, $6") using 1:2 with points \
			lc rgb col[i] pt 9 ps 1.8 notitle, \
		sel("implicit-euler", "above", "$1, $6") using 1:2 with points \
			lc rgb col[5] pt 9 ps 1.8 title "implicit-euler: no limit up to T", \
		sel("fast", "above", "$1, $6") using 1:2 with points \
			lc rgb col[6] pt 9 ps 1.3 title "fast: no limit up to T", \
		sel("bdf2", "above", "$1, $6") using 1:2 with points \
			lc rgb col[7] pt 9 ps 1.0 title "bdf2: no limit up to T", \
		for [i = 1:4] sel(word(methods, i), ".", "$1, $8") using 1:2 with lines \
			lc rgb col[i] dt 2 lw 1.5 title word(methods, i) . ": " . thname[i], \
		T lc rgb "#8c564b" dt 3 lw 1.5 title sprintf("T = %s s (one step)", until_t)
}

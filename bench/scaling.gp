# Chart of bench/scaling.sh's scaling.csv: gnuplot -e "csv=...; term='png'|'dumb';
# outf=...; stamp=...; runs=...; until_t=..." scaling.gp
# Log-log wall seconds per simulated second against nodes, self-collision
# on and off, for rk4, implicit-euler and fast (the shipped tablecloth's;
# bdf2 too when measured), with the targets (25 x 25 at 0.05 s and
# 100 x 100 at 5 s per simulated s).
# csv columns: 1 side, 2 nodes, 3 integrator, 4 self, 5 status, 8 wall_per_sim
if (!exists("csv")) csv = "scaling.csv"
if (!exists("term")) term = "png"
if (!exists("stamp")) stamp = ""
if (!exists("runs")) runs = "?"
if (!exists("until_t")) until_t = "?"
set datafile separator ","
set datafile missing "-"
# bdf2 is charted only when measured (BENCH_SCALING_INTEGRATORS)
stats csv skip 1 using (strcol(3) eq "bdf2" ? 1 : 0) nooutput
has_bdf2 = STATS_max > 0
if (term eq "png") {
	set terminal pngcairo size 900,650 font "Sans,11"
	set output outf
	ps = 1.5
} else {
	set terminal dumb size 100,32
	ps = 1
}
set logscale xy
if (term eq "png") { set grid xtics ytics mxtics mytics } else { set grid xtics ytics }
set xlabel "nodes (log)"
set ylabel "wall s per simulated s (log)"
set key top left
set xrange [400:60000]
set yrange [0.02:*]
set title sprintf("tablecloth at 25^2 .. 200^2 nodes, 10 mm spacing (medians of %s runs of %s s; %s)", runs, until_t, stamp)
sel(m, s) = (strcol(3) eq m && strcol(4) eq s && strcol(5) eq "ok") ? $8 : NaN
set label 1 "target: 100^2 at 5 s" at 10000, 5 point pt 6 ps 2 offset 1.5,0
set label 2 "target: 25^2 at 0.05 s" at 625, 0.05 point pt 6 ps 2 offset 1.5,0
plot csv skip 1 using 2:(sel("rk4", "on")) with linespoints pt 7 ps ps lc rgb "#d62728" title "rk4, self-collision on", \
	csv skip 1 using 2:(sel("rk4", "off")) with linespoints pt 5 ps ps lc rgb "#1f77b4" title "rk4, self off (box, floor)", \
	csv skip 1 using 2:(sel("implicit-euler", "on")) with linespoints pt 9 ps ps lc rgb "#ff7f0e" dt 2 title "implicit-euler, self on", \
	csv skip 1 using 2:(sel("implicit-euler", "off")) with linespoints pt 11 ps ps lc rgb "#2ca02c" dt 2 title "implicit-euler, self off", \
	csv skip 1 using 2:(sel("fast", "on")) with linespoints pt 13 ps ps lc rgb "#9467bd" lw 2 title "fast (shipped), self on", \
	csv skip 1 using 2:(sel("fast", "off")) with linespoints pt 15 ps ps lc rgb "#8c564b" lw 2 title "fast (shipped), self off", \
	csv skip 1 using 2:(has_bdf2 ? sel("bdf2", "on") : NaN) with linespoints pt 3 ps ps lc rgb "#17becf" dt 3 title (has_bdf2 ? "bdf2, self on" : ""), \
	csv skip 1 using 2:(has_bdf2 ? sel("bdf2", "off") : NaN) with linespoints pt 1 ps ps lc rgb "#7f7f7f" dt 3 title (has_bdf2 ? "bdf2, self off" : "")

# Chart of bench/scaling.sh's scaling.csv: gnuplot -e "csv=...; term='png'|'dumb';
# outf=...; stamp=...; runs=...; until_t=...; s_on=...; a_on=...; s_off=...;
# a_off=..." scaling.gp
# Log-log wall seconds per simulated second against nodes, self-collision
# on and off, with the least-squares lines (slope s, intercept a of
# log t = a + s log n) and the target (100 x 100 at 5 s per simulated s).
# csv columns: 1 side, 2 nodes, 3 self, 4 status, 7 wall_per_sim
if (!exists("csv")) csv = "scaling.csv"
if (!exists("term")) term = "png"
if (!exists("stamp")) stamp = ""
if (!exists("runs")) runs = "?"
if (!exists("until_t")) until_t = "?"
set datafile separator ","
set datafile missing "-"
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
set title sprintf("tablecloth at 25^2 .. 200^2 nodes, 10 mm spacing (medians of %s runs of %s s; %s)", runs, until_t, stamp)
sel(s) = (strcol(3) eq s && strcol(4) eq "ok") ? $7 : NaN
fon(x) = exp(a_on) * x ** s_on
foff(x) = exp(a_off) * x ** s_off
set label 1 "target: 100^2 at 5 s" at 10000, 5 point pt 6 ps 2 offset 1.5,0
plot csv skip 1 using 2:(sel("on")) with points pt 7 ps ps lc rgb "#d62728" title "self-collision on (grid + ccd)", \
	fon(x) with lines lc rgb "#d62728" dt 2 title sprintf("fit, slope %.2f", s_on), \
	csv skip 1 using 2:(sel("off")) with points pt 5 ps ps lc rgb "#1f77b4" title "self-collision off (box, floor)", \
	foff(x) with lines lc rgb "#1f77b4" dt 2 title sprintf("fit, slope %.2f", s_off)

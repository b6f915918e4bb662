# Chart of bench/fast.sh's fast.csv: gnuplot -e "csv=...; term='png'|'dumb';
# outf=...; stamp=...; runs=..." fast.gp
# Speed against accuracy: wall seconds per simulated second (log) against
# how far each integrator's final cloth ends from RK4's (the distance
# between the centroids, mm), one point per scene and integrator; RK4 sits
# at 0 by definition (drawn at 0.01 mm on the log axis).
# csv columns: 1 scene, 2 integrator, 3 wall_s, 4 sim_s, 7 centroid_dist_mm
if (!exists("csv")) csv = "fast.csv"
if (!exists("term")) term = "png"
if (!exists("stamp")) stamp = ""
if (!exists("runs")) runs = "?"
set datafile separator ","
set datafile missing "-"
if (term eq "png") {
	set terminal pngcairo size 900,600 font "Sans,11"
	set output outf
	ps = 2
} else {
	set terminal dumb size 100,30
	ps = 1
}
set logscale xy
set grid xtics ytics
set xlabel "wall s per simulated s (log)"
set ylabel "final centroid's distance from RK4's, mm (log; RK4 at 0.01)"
set key top right
set yrange [0.005:*]
set title sprintf("speed against accuracy, whole shipped scenes (medians of %s rounds; %s)", runs, stamp)
sel(s, m) = (strcol(1) eq s && strcol(2) eq m) ? $3 / $4 : NaN
d(x) = x < 0.01 ? 0.01 : x
plot for [m in "rk4 implicit-euler fast fast+bvh"] csv skip 1 using (sel("tablecloth", m)):(d($7)) \
	with points pt 7 ps ps title "tablecloth, ".m, \
	for [m in "rk4 implicit-euler fast fast+bvh"] csv skip 1 using (sel("strip", m)):(d($7)) \
	with points pt 5 ps ps title "strip, ".m

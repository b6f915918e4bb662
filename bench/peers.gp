# Chart of bench/peers.sh's peers.csv: gnuplot -e "csv=...; term='png'|'dumb';
# outf=...; stamp=...; runs=..." peers.gp
# Speed against intersections: wall seconds per simulated second (log)
# against the most intersecting pairs of triangles in one audited frame
# (log; 0 drawn at 0.5), one point per scene and method, labelled: on the
# floor of 0.5 upright, the table's up and the strip's down, so that the
# labels of points a few pixels apart do not run into each other (level,
# 'fast', 'implicit-euler' and 'rk4' were printed over one another).
# csv columns: 1 scene, 2 method, 3 wall_per_sim_s, 5 pairs_end, 6 pairs_worst
if (!exists("csv")) csv = "peers.csv"
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
set xlabel "wall s per simulated s, one core (log)"
set ylabel "intersecting pairs, worst frame (log; 0 at 0.5)"
set key top left
# room under the floor of 0.5 for the strip's labels there, which run down
set yrange [0.03:*]
set offsets graph 0.05, graph 0.15, graph 0.05, graph 0.05
set title sprintf("drape, Blender and Bullet on the peers' scenes (medians of %s rounds; %s)", runs, stamp)
sel(s) = strcol(1) eq s ? $3 : NaN
p(x) = x < 0.5 ? 0.5 : x
# the points on the floor, labelled upright; the others level (the
# table's to the left, clear of the upright labels to their right)
floor0(x) = x < 0.5 ? 0.5 : NaN
above0(x) = x < 0.5 ? NaN : x
plot csv skip 1 using (sel("table")):(p($6)) with points pt 7 ps ps title "table 25^2, 2 s", \
	csv skip 1 using (sel("strip")):(p($6)) with points pt 5 ps ps title "strip 125x3, 2 s", \
	csv skip 1 using (sel("table")):(floor0($6)):2 with labels rotate by 90 offset 1,1 left font ",9" notitle, \
	csv skip 1 using (sel("strip")):(floor0($6)):2 with labels rotate by -90 offset 1,-1 left font ",9" notitle, \
	csv skip 1 using (sel("table")):(above0($6)):2 with labels offset -1,0.6 right font ",9" notitle, \
	csv skip 1 using (sel("strip")):(above0($6)):2 with labels offset 1,0.6 left font ",9" notitle

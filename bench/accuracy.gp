# Chart of bench/accuracy.sh's accuracy.csv: gnuplot -e "csv=...; term='png'|'dumb';
# outf=...; stamp=...; runs=...; every=..." accuracy.gp
# Top: intersecting triangle pairs per audited frame against wall ms per
# step, one point per mode, one colour per scene. Bottom: contacts found
# over brute-ccd's (the ground truth) against the same time.
# csv columns: 1 scene, 2 mode, 5 until_s, 6 status, 7 ms_per_step,
# 11 contacts_vs_truth, 14 pairs_per_frame
if (!exists("csv")) csv = "accuracy.csv"
if (!exists("term")) term = "png"
if (!exists("stamp")) stamp = ""
if (!exists("runs")) runs = "?"
if (!exists("every")) every = "?"
set datafile separator ","
set datafile missing "-"
if (term eq "png") {
	set terminal pngcairo size 1000,900 font "Sans,11"
	set output outf
	ps = 1.5; lf = ",9"
} else {
	set terminal dumb size 100,50
	ps = 1; lf = ""
}
scenes = system("awk -F, 'NR > 1 && !seen[$1]++ { printf \"%s \", $1 }' '" . csv . "'")
nsc = words(scenes)
array col[4] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
set key top right
set logscale x
set grid
set xlabel "wall ms per step (log)"
set multiplot layout 2,1 title sprintf("collision accuracy against cost (%s)", stamp)
set title sprintf("intersecting triangle pairs per audited frame (drape check --every %s); blown-up runs omitted", every)
set ylabel "pairs per frame"
set offsets graph 0.05, graph 0.05, graph 0.1, graph 0.1
ok(s, c) = (strcol(1) eq word(scenes, s) && strcol(6) eq "ok") ? column(c) : NaN
plot for [s = 1:nsc] csv skip 1 using (ok(s, 7)):(ok(s, 14)) with points pt 7 ps ps lc rgb col[s] title word(scenes, s), \
	for [s = 1:nsc] csv skip 1 using (ok(s, 7)):(ok(s, 14)):(strcol(2)) with labels offset 0,0.8 font lf tc rgb col[s] notitle
if (!exists("ntruth")) ntruth = 1
if (ntruth == 0) { set label 9 "no contacts in brute-ccd's run: nothing to compare" at graph 0.5, graph 0.5 center; set xrange [0.01:1000]; set yrange [0:2] }
set title "contacts found over brute-ccd's (ground truth, 1 = as many)"
set ylabel "contacts / truth"
plot for [s = 1:nsc] csv skip 1 using (ok(s, 7)):(ok(s, 11)) with points pt 7 ps ps lc rgb col[s] title word(scenes, s), \
	for [s = 1:nsc] csv skip 1 using (ok(s, 7)):(ok(s, 11)):(strcol(2)) with labels offset 0,0.8 font lf tc rgb col[s] notitle, \
	1 with lines dt 2 lc rgb "#555555" notitle
unset multiplot

# Chart of bench/needs.sh's needs.csv: gnuplot -e "csv=...; term='png'|'dumb';
# outf=...; stamp=...; runs=..." needs.gp
# Wall time over the full scene's, by variant, one bar per scene; the bar
# is labelled with the ratio, "blew up" when the run did.
# csv columns: 1 scene, 2 variant, 4 status, 6 ratio_to_full, 15 max_pairs
if (!exists("csv")) csv = "needs.csv"
if (!exists("term")) term = "png"
if (!exists("stamp")) stamp = ""
if (!exists("runs")) runs = "?"
set datafile separator ","
set datafile missing "-"
if (term eq "png") {
	set terminal pngcairo size 1000,600 font "Sans,11"
	set output outf
	lf = ",9"
} else {
	set terminal dumb size 100,30
	lf = ""
}
scenes = system("awk -F, 'NR > 1 && !seen[$1]++ { printf \"%s \", $1 }' '" . csv . "'")
variants = system("awk -F, 'NR > 1 { if (seen[$2]++) exit; printf \"%s \", $2 }' '" . csv . "'")
nsc = words(scenes)
nv = words(variants)
array col[4] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
bw = 0.8 / nsc
set style fill solid 0.85 border -1
set boxwidth bw
set xrange [0.4:nv + 0.6]
set yrange [0:*]
set grid ytics
set ylabel "wall time / full scene's (same round)"
set key top right
set xtics nomirror scale 0 ()
set for [i = 1:nv] xtics add (word(variants, i) i)
set title sprintf("what each part of the model costs (medians of %s rounds; %s); label: ratio, max intersecting pairs", runs, stamp)
idx(v) = sum [i = 1:nv] (word(variants, i) eq v ? i : 0)
off(s) = (s - 1 - (nsc - 1) / 2.0) * bw
row(s) = strcol(1) eq word(scenes, s)
plot for [s = 1:nsc] csv skip 1 using (row(s) ? idx(strcol(2)) + off(s) : NaN):6 with boxes lc rgb col[s] title word(scenes, s), \
	for [s = 1:nsc] csv skip 1 using (row(s) ? idx(strcol(2)) + off(s) : NaN):(strcol(4) eq "ok" ? $6 + 0.06 : 0.1):\
		(strcol(4) eq "ok" ? sprintf("%.2f|%s", $6, strcol(15)) : "blew up") with labels font lf notitle, \
	1 with lines dt 2 lc rgb "#555555" notitle

# Chart of bench/ccd.sh's ccd.csv: gnuplot -e "csv=...; term='png'|'dumb';
# outf=...; stamp=...; runs=..." ccd.gp
#
# Top: per query file, each method's false negatives (dark) and false
# positives (light), inside an outline as high as the file's true contacts,
# each pair labelled FN/FP ("n/a": seed has no edge-edge test).
# Bottom: ns per query by file and method, log scale.
#
# csv columns: 1 file, 3 method, 4 status, 6 true_contacts, 9 false_neg,
# 10 false_pos, 12 ns_per_query
if (!exists("csv")) csv = "ccd.csv"
if (!exists("term")) term = "png"
if (!exists("stamp")) stamp = ""
if (!exists("runs")) runs = "?"
set datafile separator ","
set datafile missing "-"
if (term eq "png") {
	set terminal pngcairo size 1000,900 font "Sans,11"
	set output outf
	lf = ",9"
} else {
	set terminal dumb size 110,56
	lf = ""
}

files = system("awk -F, 'NR > 1 && !seen[$1]++ { printf \"%s \", $1 }' '" . csv . "'")
trues = system("awk -F, 'NR > 1 && !seen[$1]++ { printf \"%s \", $6 }' '" . csv . "'")
queries = system("awk -F, 'NR > 1 && !seen[$1]++ { printf \"%s \", $5 }' '" . csv . "'")
methods = system("awk -F, 'NR > 1 && !seen[$3]++ { printf \"%s \", $3 }' '" . csv . "'")
nf = words(files)
nm = words(methods)
fidx(f) = sum [i = 1:nf] (word(files, i) eq f ? i : 0)
row(m) = strcol(3) eq word(methods, m)
ok = '(strcol(4) eq "ok")'

array col[4] = ["#1f77b4", "#d62728", "#ff7f0e", "#9467bd"]
array lite[4] = ["#9ecae1", "#fc9f9f", "#fdd0a2", "#cbb6e0"]

set multiplot layout 2,1 title sprintf("drape ccd on the CCD benchmark's sample queries (Wang et al.; %s)", stamp)

# ---- top: false negatives and false positives ----
bw = 0.8 / (2 * nm)
off(m, k) = ((m - 1) * 2 + k - (2 * nm - 1) / 2.0) * bw
set style fill solid 0.85 border -1
set xrange [0.4:nf + 0.6]
stats csv skip 1 using 6 nooutput prefix "N"
ytop = exists("N_max") ? N_max * 1.25 + 1 : 10
set yrange [0:ytop]
set grid ytics
set ylabel "queries"
set key top left
set xtics nomirror noenhanced scale 0 ()
set for [i = 1:nf] xtics add (sprintf("%s\n%s true of %s", word(files, i), word(trues, i), word(queries, i)) i)
set title "contacts missed (false negatives, dark) and false alarms (false positives, light); label: FN/FP"
# a missing value drops the row even from a ternary's unused branch, so
# the n/a rows get their own labels
plot csv skip 1 using (row(1) ? fidx(strcol(1)) : NaN):6:(0.86) \
		with boxes fs empty border lc rgb "#555555" lc rgb "#555555" dt 2 title "true contacts", \
	for [m = 1:nm] csv skip 1 using (row(m) ? fidx(strcol(1)) + off(m, 0) : NaN):9:(bw) \
		with boxes lc rgb col[m] title word(methods, m), \
	for [m = 1:nm] csv skip 1 using (row(m) ? fidx(strcol(1)) + off(m, 1) : NaN):10:(bw) \
		with boxes lc rgb lite[m] notitle, \
	for [m = 1:nm] csv skip 1 using (row(m) ? fidx(strcol(1)) + off(m, 0.5) : NaN):\
		(($9 > $10 ? $9 : $10) + ytop * 0.04):(sprintf("%d/%d", $9, $10)) with labels font lf notitle, \
	for [m = 1:nm] csv skip 1 using (row(m) && !@ok ? fidx(strcol(1)) + off(m, 0.5) : NaN):(ytop * 0.04):("n/a") \
		with labels font lf notitle

# ---- bottom: time per query ----
bw2 = 0.8 / nm
off2(m) = (m - 1 - (nm - 1) / 2.0) * bw2
set xtics nomirror noenhanced scale 0 ()
set for [i = 1:nf] xtics add (word(files, i) i)
set title sprintf("time per query (median of %s runs); n/a: no edge-edge test", runs)
set ylabel "ns per query (log)"
set logscale y
set yrange [*:*]
set grid ytics
stats csv skip 1 using 12 nooutput prefix "Q"
# room above the bars for the key
if (exists("Q_min")) set yrange [10 ** floor(log10(Q_min / 2)):10 ** ceil(log10(Q_max * 30))]
qlo = exists("Q_min") ? 10 ** floor(log10(Q_min / 2)) : 1
# the dumb terminal's bars are a few characters wide
fmt(v) = term ne "png" ? sprintf("%.0f", v) : v < 1000 ? sprintf("%.3g ns", v) : sprintf("%.3g us", v / 1000)
set key top left
plot for [m = 1:nm] csv skip 1 using (row(m) ? fidx(strcol(1)) + off2(m) : NaN):12:(bw2) \
		with boxes lc rgb col[m] title word(methods, m), \
	for [m = 1:nm] csv skip 1 using (row(m) ? fidx(strcol(1)) + off2(m) : NaN):($12 * 1.5):(fmt($12)) \
		with labels font lf notitle, \
	for [m = 1:nm] csv skip 1 using (row(m) && !@ok ? fidx(strcol(1)) + off2(m) : NaN):(qlo * 1.5):("n/a") \
		with labels font lf notitle
unset multiplot

# Chart of bench/collide.sh's collide.csv: gnuplot -e "csv=...; term='png'|'dumb';
# outf=...; stamp=...; runs=...; ncpu=...; until_t=...; brute_t=..." collide.gp
#
# Top: wall seconds per simulated second by mode, one bar per scene, log
# scale, each bar labelled with its ratio to the no-collision run.
# Bottom: candidate pairs per step that the broad phase passes to the narrow
# phase, vertex-triangle and edge-edge, by mode with self-collision on.
#
# csv columns: 1 scene, 2 mode, 4 status, 5 wall_per_sim, 6 ratio,
# 11 vt_pairs, 12 ee_pairs, 17 blowup_t_s
if (!exists("csv")) csv = "collide.csv"
if (!exists("term")) term = "png"
if (!exists("stamp")) stamp = ""
if (!exists("runs")) runs = "?"
if (!exists("ncpu")) ncpu = "?"
if (!exists("until_t")) until_t = "?"
if (!exists("brute_t")) brute_t = "?"
set datafile separator ","
set datafile missing "-"
if (term eq "png") {
	set terminal pngcairo size 1100,1000 font "Sans,11"
	set output outf
	lf = ",8"
} else {
	set terminal dumb size 110,60
	lf = ""
}

scenes = system("awk -F, 'NR > 1 && !seen[$1]++ { printf \"%s \", $1 }' '" . csv . "'")
modes = system("awk -F, 'NR > 1 { if (seen[$2]++) exit; printf \"%s \", $2 }' '" . csv . "'")
nsc = words(scenes)
nmodes = words(modes)
idx(m) = sum [i = 1:nmodes] (word(modes, i) eq m ? i : 0)
row(s) = strcol(1) eq word(scenes, s)

# one colour per scene; light/dark pair per scene in the bottom panel
array col[4] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
array lite[4] = ["#9ecae1", "#fc9f9f", "#a1d99b", "#cbb6e0"]

set multiplot layout 2,1 title sprintf("drape collision cost (medians of %s runs, %s cores, %s)", runs, ncpu, stamp)

# ---- top: wall time per simulated second ----
bw = 0.8 / nsc
set style fill solid 0.85 border -1
set boxwidth bw
set logscale y
if (term eq "png") { set format y "10^{%L}"; set grid ytics mytics } else { set grid ytics }
set ylabel "wall s per simulated s (log)"
set xrange [0.4:nmodes + 0.6]
# no valid row (every mode blew up) leaves T_min undefined: an empty chart
stats csv skip 1 using 5 nooutput prefix "T"
ylo = exists("T_min") ? 10 ** floor(log10(T_min / 2)) : 0.1
set yrange [ylo:exists("T_max") ? 10 ** ceil(log10(T_max * 2)) : 10]
set key top left
set title sprintf("time per simulated second by mode, %s s simulated (brute: first %s s); label = ratio to none", until_t, brute_t)
set xtics nomirror scale 0 ()
set for [i = 1:nmodes] xtics add (word(modes, i) i)
off(s) = (s - 1 - (nsc - 1) / 2.0) * bw
# the blow-up time only where there is room for it; one scene's label above
# the other's (the dumb terminal does not rotate them)
blew(s) = strcol(4) eq "ok" ? "" : strcol(4) ne "blowup" ? "failed" : \
	"blew up" . (strcol(17) eq "-" || term ne "png" ? "" : sprintf(" at %.3g s", column(17)))
plot for [s = 1:nsc] csv skip 1 using (row(s) ? idx(strcol(2)) + off(s) : NaN):5 \
		with boxes lc rgb col[s] title word(scenes, s), \
	for [s = 1:nsc] csv skip 1 using (row(s) ? idx(strcol(2)) + off(s) : NaN):($5 * 1.3):(sprintf("%.3gx", $6)) \
		with labels font lf notitle, \
	for [s = 1:nsc] csv skip 1 using (row(s) && strcol(4) ne "ok" ? idx(strcol(2)) + off(s) : NaN):(ylo * 1.3 * 3 ** (s - 1)):(blew(s)) \
		with labels rotate left font lf tc rgb "#b00000" notitle, \
	1 with lines lc rgb "#555555" dt 2 title "real time"

# ---- bottom: candidate pairs per step, self-collision modes only ----
set title "candidate pairs per step passed to the narrow phase (self-collision on; chapter = seed/seed/keep)"
set ylabel "pairs per step (log)"
first = idx("chapter") > 0 ? idx("chapter") : 3
set xrange [first - 0.6:nmodes + 0.6]
bw2 = 0.8 / (2 * nsc)
set boxwidth bw2
off2(s, k) = ((s - 1) * 2 + k - (2 * nsc - 1) / 2.0) * bw2
# bar k = 0, 1, ...: scene k/2 + 1, vertex-triangle (column 11) or edge-edge (12)
ks(k) = int(k / 2) + 1
kc(k) = 11 + k % 2
kcol(k) = k % 2 ? lite[ks(k)] : col[ks(k)]
kname(k) = word(scenes, ks(k)) . (k % 2 ? " edge-edge" : " vertex-triangle")
fmt(v) = v < 1e4 ? sprintf("%.0f", v) : sprintf("%.1fe%d", v / 10 ** floor(log10(v)), floor(log10(v)))
pairs(k) = row(ks(k)) && idx(strcol(2)) >= first && column(kc(k)) > 0 ? column(kc(k)) : NaN
stats csv skip 1 using ($11 > 0 ? $11 : NaN) nooutput prefix "P"
ylo = exists("P_min") ? 10 ** floor(log10(P_min)) : 1
set yrange [ylo:*]
plot for [k = 0:2 * nsc - 1] csv skip 1 using (idx(strcol(2)) + off2(ks(k), k % 2)):(pairs(k)) \
		with boxes lc rgb kcol(k) title kname(k), \
	for [k = 0:2 * nsc - 1] csv skip 1 using (idx(strcol(2)) + off2(ks(k), k % 2)):(pairs(k) * 1.4):(fmt(pairs(k))) \
		with labels font lf notitle, \
	for [s = 1:nsc] csv skip 1 using (row(s) && strcol(4) ne "ok" && idx(strcol(2)) >= first ? \
		idx(strcol(2)) + off2(s, 0.5) : NaN):(ylo * 1.3 * 3 ** (s - 1)):(blew(s)) with labels rotate left font lf tc rgb "#b00000" notitle
unset multiplot

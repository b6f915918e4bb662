# Chart of bench/collide.sh's medians (collide.dat): gnuplot -e "datf=...;
# outf=...; runs=...; until_t=...; brute_t=...; stamp=...; ncpu=..." collide.gp
#
# Top: wall seconds per simulated second by mode, one bar per scene, log
# scale, each bar labelled with its ratio to the no-collision run.
# Bottom: candidate pairs per step that the broad phase passes to the narrow
# phase, vertex-triangle and edge-edge, by mode with self-collision on.
#
# collide.dat columns: 1 idx, 2 scene, 3 mode, 4 until, 5 status,
# 6 wall_per_sim, 7 ratio, 8 steps_per_s, 9 node_pairs, 10 vt_pairs,
# 11 ee_pairs, 12 narrow_tests; one block per scene.

if (!exists("datf")) datf = "collide.dat"
if (!exists("outf")) outf = "collide.png"
if (!exists("runs")) runs = "?"
if (!exists("until_t")) until_t = "?"
if (!exists("brute_t")) brute_t = "?"
if (!exists("stamp")) stamp = ""
if (!exists("ncpu")) ncpu = "?"

set terminal pngcairo size 1100,1000 font "Sans,11"
set output outf
set datafile missing "-"

stats datf using 1 nooutput
nsc = STATS_blocks
nmodes = int(STATS_max)

# scene names (one block each, in order) and mode names (of the first block)
scenes = system("awk '!/^#/ && NF { print $2 }' '" . datf . "' | uniq | tr '\\n' ' '")
modes = system("awk '!/^#/ && NF { if (seen[$3]++) exit; print $3 }' '" . datf . "' | tr '\\n' ' '")

# one colour per scene; light/dark pair per scene in the bottom panel
array col[4] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
array lite[4] = ["#9ecae1", "#fc9f9f", "#a1d99b", "#cbb6e0"]

set multiplot layout 2,1 title sprintf("drape collision cost (medians of %s runs, %s cores, %s)", runs, ncpu, stamp) font ",13"

# ---- top: wall time per simulated second ----
bw = 0.8 / nsc
set style fill solid 0.85 border -1
set boxwidth bw
set logscale y
set format y "10^{%L}"
set grid ytics mytics
set ylabel "wall s per simulated s (log)"
set xrange [0.4:nmodes + 0.6]
stats datf using 6 nooutput
ylo = 10 ** floor(log10(STATS_min / 2))
set yrange [ylo:10 ** ceil(log10(STATS_max * 2))]
set key top left
set title sprintf("time per simulated second by mode, %s s simulated (brute: first %s s); label = ratio to none", until_t, brute_t)
set xtics nomirror scale 0 ()
set for [i = 1:nmodes] xtics add (word(modes, i) i)
off(s) = (s - 1 - (nsc - 1) / 2.0) * bw
plot for [s = 1:nsc] datf index (s - 1) using ($1 + off(s)):6 \
		with boxes lc rgb col[s] title word(scenes, s), \
	for [s = 1:nsc] datf index (s - 1) using ($1 + off(s)):($6 * 1.25):(sprintf("%.3gx", $7)) \
		with labels font ",8" notitle, \
	for [s = 1:nsc] datf index (s - 1) using ($1 + off(s)):(ylo * 1.2):(stringcolumn(5) eq "ok" ? "" : \
		stringcolumn(5) eq "blowup" ? "blew up" : "failed") with labels rotate left font ",9" tc rgb "#b00000" notitle, \
	1 with lines lc rgb "#555555" dt 2 title "real time"

# ---- bottom: candidate pairs per step, self-collision modes only ----
set title "candidate pairs per step passed to the narrow phase (self-collision on; chapter = seed/seed/keep)"
set ylabel "pairs per step (log)"
set xrange [2.4:nmodes + 0.6]
bw2 = 0.8 / (2 * nsc)
set boxwidth bw2
off2(s, k) = ((s - 1) * 2 + k - (2 * nsc - 1) / 2.0) * bw2
scname(s) = word(scenes, s)
# bar k = 0, 1, ... : scene k/2 + 1, vertex-triangle (column 10) or edge-edge (11)
ks(k) = int(k / 2) + 1
kc(k) = 10 + k % 2
kcol(k) = k % 2 ? lite[ks(k)] : col[ks(k)]
kname(k) = word(scenes, ks(k)) . (k % 2 ? " edge-edge" : " vertex-triangle")
fmt(v) = v < 1e4 ? sprintf("%.0f", v) : sprintf("%.1fe%d", v / 10 ** floor(log10(v)), floor(log10(v)))
set yrange [*:*]
plot for [k = 0:2 * nsc - 1] datf index (ks(k) - 1) \
		using ($1 + off2(ks(k), k % 2)):($1 >= 3 && column(kc(k)) > 0 ? column(kc(k)) : NaN) \
		with boxes lc rgb kcol(k) title kname(k), \
	for [k = 0:2 * nsc - 1] datf index (ks(k) - 1) \
		using ($1 + off2(ks(k), k % 2)):($1 >= 3 && column(kc(k)) > 0 ? column(kc(k)) * 1.3 : NaN):(fmt(column(kc(k)))) \
		with labels font ",8" notitle
unset multiplot

# Chart of bench/tunnel.sh's rates (tunnel.csv): gnuplot -e "csv=...;
# outf=...; term='png'|'dumb'; noff=...; position=...; stamp=..." tunnel.gp
#
# Tunnelling rate (share of the cloth's nodes that ended beyond the plate)
# against V*dt/L_ce, log x, one line per broad/narrow combination.
# tunnel.csv columns: 1 ratio, 2 v_m_s, 3 broad, 4 narrow, 5 runs,
# 6 blowups, 7 runs_with_tunnelling, 8 nodes_through, 9 nodes_shot, 10 rate.

if (!exists("csv")) csv = "tunnel.csv"
if (!exists("outf")) outf = "tunnel.png"
if (!exists("term")) term = "png"
if (!exists("noff")) noff = "?"
if (!exists("position")) position = "?"
if (!exists("stamp")) stamp = ""

set datafile separator ","
set datafile missing "-"
if (term eq "dumb") {
	set terminal dumb size 79,26
	set output
} else {
	set terminal pngcairo size 900,560 font "Sans,11"
	set output outf
}
set title sprintf("drape tunnelling: 4x4 cloth shot at a plate (%s offsets, position %s, %s)", noff, position, stamp)
set xlabel (term eq "dumb" ? "V dt / L_ce (log)" : "V dt / L_{ce} (log)")
set ylabel "tunnelling rate (% of nodes through)"
set logscale x
set xrange [*:*]
set yrange [-5:105]
set grid
set key top left
set arrow from 1, graph 0 to 1, graph 1 nohead dt 2 lc rgb "#777777"
combos = "seed/seed seed/ccd grid/seed grid/ccd"
array col[4] = ["#d62728", "#ff7f0e", "#1f77b4", "#2ca02c"]
array pt[4] = [7, 5, 9, 13]
# one combination's rows, in ratio order (a filter, so that the lines join)
rows(c) = sprintf("< awk -F, 'NR > 1 && $3 \"/\" $4 == \"%s\" && $10 != \"-\"' '%s' | sort -t, -k1,1g", word(combos, c), csv)
if (term eq "dumb") {
	plot for [c = 1:4] rows(c) using 1:(100 * $10) with linespoints pt (c + 0) title word(combos, c)
} else {
	plot for [c = 1:4] rows(c) using 1:(100 * $10) with linespoints lw 2 pt pt[c] ps 1.2 lc rgb col[c] \
		title "broad/narrow " . word(combos, c)
}

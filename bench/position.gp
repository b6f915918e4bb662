# Chart of bench/position.sh's energies (position.csv): gnuplot -e "csv=...;
# outf=...; term='png'|'dumb'; pols='keep q ref'; stamp=..." position.gp
#
# Total energy of the strip against time, one line per position policy;
# a blow-up is marked by a cross at its time (at the energy of the last
# good state) and a label.
# position.csv columns: 1 policy, 2 broad, 3 narrow, 4 position, 5 t_s,
# 6 status (ok or blowup), 7 energy_J, 8 kinetic_J, 9 wall_s.

if (!exists("csv")) csv = "position.csv"
if (!exists("outf")) outf = "position.png"
if (!exists("term")) term = "png"
if (!exists("pols")) pols = "keep q ref"
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
np = words(pols)
label(p) = p eq "keep" ? "seed/seed/keep" : p eq "q" ? "seed/seed/q" : p eq "slide" ? "seed/seed/slide" : "grid/ccd/slide (shipped)"
# the policy's rows with status st ("ok|blowup": the line runs to the blow-up)
rows(p, st) = sprintf("< awk -F, 'NR > 1 && $1 == \"%s\" && $6 ~ /^(%s)$/ && $7 != \"-\"' '%s' | sort -t, -k5,5g", p, st, csv)
set title sprintf("drape strip (Fig. 11): total energy by position policy (%s)", stamp)
set xlabel "simulated time (s)"
set ylabel "total energy (J, log)"
set logscale y
set grid
set key top left
array col[4] = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd"]
if (term eq "dumb") {
	plot for [c = 1:np] rows(word(pols, c), "ok|blowup") using 5:7 with linespoints pt (c + 0) title label(word(pols, c)), \
		for [c = 1:np] rows(word(pols, c), "blowup") using 5:7 with points pt "X" notitle, \
		for [c = 1:np] rows(word(pols, c), "blowup") using 5:7:(sprintf("%s blew up %.3gs", word(pols, c), $5)) with labels left offset 1,0 notitle
} else {
	plot for [c = 1:np] rows(word(pols, c), "ok|blowup") using 5:7 with linespoints lw 2 pt 7 ps 0.8 lc rgb col[c] title label(word(pols, c)), \
		for [c = 1:np] rows(word(pols, c), "blowup") using 5:7 with points pt 2 ps 3 lw 3 lc rgb col[c] notitle, \
		for [c = 1:np] rows(word(pols, c), "blowup") using 5:7:(sprintf("%s: blew up at %.3g s", word(pols, c), $5)) \
			with labels left offset 1.5,0 tc rgb col[c] font ",10" notitle
}

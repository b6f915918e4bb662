# Chart of bench/chapter.sh's results: gnuplot -e "csv=...; summary=...;
# vars='...'; term='png'|'dumb'; outf=...; stamp=..." chapter.gp
# term = 'dumb' draws a text chart on stdout instead of the PNG outf.
#
# csv (chapter-series.csv): 1 variant, 2 scene, 3 t_s, 4 energy_J,
# 5 kinetic_J, 6 locked, 7 locked_kinetic_J, 8 pairs.
# summary (chapter.csv): 1 variant, 2 scene, 3 status, 4 t_end_s,
# 5 duration_s, 6 wall_s, 7 stepping_s, 8 collisions_s,
# 9 collision_share_pct, ...
#
# Per scene (tablecloth left, strip right): the total energy over time
# (a variant's line ends where it blew up), the intersecting triangle pairs
# of each output frame; and per variant, the time reached as a share of the
# scene's duration (100 %: finished) and the collision stages' share of
# the step time.

if (!exists("csv")) csv = "chapter-series.csv"
if (!exists("summary")) summary = "chapter.csv"
if (!exists("outf")) outf = "chapter.png"
if (!exists("term")) term = "png"
if (!exists("stamp")) stamp = ""
if (!exists("vars")) vars = "literal edges s4 q s4-path surface shared damped slide shipped"
nv = words(vars)
array col[10] = ["#d62728", "#ff7f0e", "#9467bd", "#8c564b", "#1f77b4", "#e377c2", "#bcbd22", "#17becf", "#7f7f7f", "#2ca02c"]

sel(v, s, cols) = sprintf("< awk -F, '$1 == \"%s\" && $2 == \"%s\" { print %s }' '%s'", v, s, cols, csv)
bars(s, cols) = sprintf("< awk -F, 'NR > 1 && $2 == \"%s\" { print %s }' '%s'", s, cols, summary)

if (term eq "dumb") {
	set terminal dumb size 110,30
	set multiplot layout 1,2
	set logscale y
	set format y "%.0e"
	set key off
	do for [s in "tablecloth strip"] {
		set title sprintf("%s: total energy (J) against t (s)", s)
		plot for [i = 1:nv] sel(word(vars, i), s, "$3, $4") using 1:2 with lines
	}
	unset multiplot
	exit
}

set terminal pngcairo size 1300, 1250 font "Sans,10"
set output outf
set multiplot layout 3,2 title sprintf("drape: the chapter's collision method, its readings on its scenes (seed broad and narrow phases, RK4; shipped: grid/ccd/slide)\n%s", stamp) noenhanced
set grid
set key top left font "Sans,8" noenhanced
do for [s in "tablecloth strip"] {
	set title sprintf("%s: total energy; a line ends where the run blew up", s) noenhanced
	set xlabel "t (s)"
	set ylabel "energy (J)"
	set logscale y
	set format y "10^{%L}"
	plot for [i = 1:nv] sel(word(vars, i), s, "$3, $4") using 1:2 with lines lw 1.5 lc rgb col[i] title word(vars, i)
}
unset logscale y
set format y "%g"
do for [s in "tablecloth strip"] {
	set title sprintf("%s: intersecting triangle pairs in each output frame (drape check --every 1)", s) noenhanced
	set ylabel "pairs"
	set key top left
	plot for [i = 1:nv] sel(word(vars, i), s, "$3, $8") using 1:2 with lines lw 1.5 lc rgb col[i] title word(vars, i)
}
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set boxwidth 0.9
set xtics rotate by -30 noenhanced
set xlabel ""
set key outside top center horizontal
set yrange [0:*]
set title "time reached, % of the duration (100: finished)"
set ylabel "%"
plot bars("tablecloth", "100 * $4 / $5, $1") using 1:xtic(2) lc rgb "#1f77b4" title "tablecloth (2 s)", \
	bars("strip", "100 * $4 / $5, $1") using 1 lc rgb "#ff7f0e" title "strip (3 s)"
set title "collision stages' share of the step time"
set ylabel "%"
plot bars("tablecloth", "$9, $1") using 1:xtic(2) lc rgb "#1f77b4" title "tablecloth", \
	bars("strip", "$9, $1") using 1 lc rgb "#ff7f0e" title "strip"
unset multiplot

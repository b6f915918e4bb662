# Chart of bench/bdf2.sh's bdf2-refine.csv: gnuplot -e "csv=...; term='png'|'dumb';
# outf=...; stamp=...; peers=..." bdf2.gp
# Refinement at fixed size: wall seconds per simulated second (log)
# against nodes (log) on the peers' 0.24 m table's first 0.25 s, drape's
# bdf2 and fast, and Blender and Bullet from bench/peers.sh's
# peers-refine.csv when there. A line's slope is the growth: 1 is linear.
# csv columns: 1 method, 2 nodes, 3 until_s, 5 wall_per_sim_s
if (!exists("csv")) csv = "bdf2-refine.csv"
if (!exists("term")) term = "png"
if (!exists("stamp")) stamp = ""
if (!exists("peers")) peers = ""
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
set xlabel "nodes (log)"
set ylabel "wall s per simulated s (log)"
set key top left
set title sprintf("refinement: the peers' 0.24 m table, first 0.25 s (%s)", stamp)
# the rows of one method, for lines (ours: the refinement's, under a
# second; the peers' file has no whole runs)
rows(f, m) = sprintf("< awk -F, '$1 == \"%s\" && $5 != \"-\"' '%s'", m, f)
ours(m) = sprintf("< awk -F, '$1 == \"%s\" && $3 + 0 < 1 && $5 != \"-\"' '%s'", m, csv)
have_peers = (peers ne "" && system("test -r '".peers."' && echo 1") eq "1")
if (have_peers) {
	plot ours("bdf2") using 2:5 with linespoints pt 7 ps ps lw 2 title "drape bdf2", \
	     ours("fast") using 2:5 with linespoints pt 5 ps ps title "drape fast (bvh)", \
	     rows(peers, "blender") using 2:5 with linespoints pt 9 ps ps title "Blender", \
	     rows(peers, "bullet") using 2:5 with linespoints pt 11 ps ps title "Bullet classic"
} else {
	plot ours("bdf2") using 2:5 with linespoints pt 7 ps ps lw 2 title "drape bdf2", \
	     ours("fast") using 2:5 with linespoints pt 5 ps ps title "drape fast (bvh)"
}

# Chart of bench/bdf2.sh's bdf2-drape.csv: gnuplot -e "csv=...; term='png'|'dumb';
# outf=...; stamp=..." bdf2-drape.gp
# The Cusick drape coefficient of scenes/drape.scene against the squares'
# spacing: bdf2's at each spacing, RK4's at 10 mm (a dashed level, with
# the target's band of 0.01 about it), and RK4's at a finer step when the
# csv has it (rk4-fine, dotted: how far the reference moves with its step).
# csv columns: 1 method, 2 spacing_mm, 3 nodes, 4 drape_coefficient
if (!exists("csv")) csv = "bdf2-drape.csv"
if (!exists("term")) term = "png"
if (!exists("stamp")) stamp = ""
set datafile separator ","
set datafile missing "-"
if (term eq "png") {
	set terminal pngcairo size 800,500 font "Sans,11"
	set output outf
	ps = 2
} else {
	set terminal dumb size 90,26
	ps = 1
}
set grid xtics ytics
set xlabel "spacing, mm"
set ylabel "drape coefficient"
set key top right
set xrange [0:*]
set title sprintf("the Cusick drape: converged under refinement? (%s)", stamp)
stats csv skip 1 using (strcol(1) eq "rk4" ? $4 : NaN) name "R" nooutput
stats csv skip 1 using (strcol(1) eq "rk4-fine" ? $4 : NaN) name "F" nooutput
fine = exists("F_mean") ? F_mean : NaN
plot csv skip 1 using 2:(strcol(1) eq "bdf2" ? $4 : NaN) with linespoints pt 7 ps ps lw 2 title "bdf2", \
     R_mean with lines dt 2 lc rgb "black" title "RK4 at 10 mm", \
     R_mean - 0.01 with lines dt 3 lc rgb "gray" notitle, \
     R_mean + 0.01 with lines dt 3 lc rgb "gray" notitle, \
     fine with lines dt 4 lc rgb "dark-red" title "RK4 at 10 mm, finer step"

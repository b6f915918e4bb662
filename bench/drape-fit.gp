# Chart of bench/drape-fit.sh's drape-fit.csv: gnuplot -e "csv=...; term='png'|'dumb';
# outf=...; target=...; fit=...; integ=...; stamp=..." drape-fit.gp
# The drape coefficient against the bending rigidity B = sqrt(B_warp B_weft)
# (log scale): the sweep's runs, then the fit's, each labelled with its
# number; the target as a horizontal line, the fitted B as a vertical one.
# csv columns: 1 phase, 2 run, 3 B_Nm, 4 B_warp_Nm, 5 B_weft_Nm, 6 dc, 7 exit, 8 wall_s
if (!exists("csv")) csv = "drape-fit.csv"
if (!exists("term")) term = "png"
if (!exists("target")) target = 0
if (!exists("fit")) fit = "-"
if (!exists("integ")) integ = "?"
if (!exists("stamp")) stamp = ""
set datafile separator ","
set datafile missing "-"
if (term eq "png") {
	set terminal pngcairo size 900,560 font "Sans,11"
	set output outf
} else {
	set terminal dumb size 90,28
}
set logscale x
set grid
set xlabel "bending rigidity B = sqrt(B_warp B_weft), uN*m" noenhanced
set ylabel "Cusick drape coefficient"
set key top left
set title sprintf("scenes/drape.scene, %s: DC against B (%s)", integ, stamp) noenhanced
set arrow from graph 0, first target to graph 1, first target nohead dt 2 lc rgb "#555555"
# The labels keep clear of the points: the target's at the left end of its
# line (the fit lands on that line, near the right, where its run number
# goes), the fitted B's left of its line (to the right it ran off the
# chart when the fit is near the largest B swept).
set label 1 sprintf("target %.3g", target) at graph 0.01, first target left offset 0, 0.7
if (fit ne "-") {
	set arrow from first fit * 1e6, graph 0 to first fit * 1e6, graph 1 nohead dt 3 lc rgb "#d62728"
	set label 2 sprintf("fitted B %.3g uN*m", fit * 1e6) at first fit * 1e6, graph 0.06 right offset -0.5, 0 tc rgb "#d62728"
}
sweep(p) = p eq "sweep"
plot csv skip 1 using (sweep(strcol(1)) ? $3 * 1e6 : NaN):6 with linespoints pt 7 ps 1.2 lc rgb "#1f77b4" title "sweep", \
	csv skip 1 using (sweep(strcol(1)) ? NaN : $3 * 1e6):6 with points pt 2 ps 1.6 lw 2 lc rgb "#d62728" title "fit (regula falsi)", \
	csv skip 1 using (sweep(strcol(1)) ? NaN : $3 * 1e6):6:(sprintf("%d", $2)) with labels offset 1.2, 0.6 notitle

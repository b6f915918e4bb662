# plot.sh: sourced by the bench scripts (by lib.sh, or on its own). It needs
# $here (this folder), $tmp (a scratch folder) and $prog (the script's
# name for messages); GNUPLOT names the gnuplot (default gnuplot). A chart
# script takes csv, term ('png' or 'dumb') and outf (the PNG) and its own
# variables.
gnuplot=${GNUPLOT:-gnuplot}

# plot GP CSV PNG 'var=value; ...': the PNG, then the same chart on the
# dumb terminal to stdout
plot() {
	local gp=$1 csv=$2 png=$3 vars=$4
	if ! command -v "$gnuplot" >/dev/null 2>&1; then
		echo "gnuplot not found: no chart (sudo apt-get install -y gnuplot-nox); the figures above are the result."
		return 0
	fi
	if "$gnuplot" -e "csv='$csv'; term='png'; outf='$png'; $vars" "$here/$gp" 2>"$tmp/gp.err" &&
		"$gnuplot" -e "csv='$csv'; term='dumb'; $vars" "$here/$gp" 2>>"$tmp/gp.err"; then
		echo "chart: $png"
	else
		echo "$prog: gnuplot failed:" >&2
		cat "$tmp/gp.err" >&2
		return 1
	fi
}

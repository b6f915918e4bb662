#!/usr/bin/env bash
# csvcols.sh [-d SEP] FILE COLUMN...: the named columns of a CSV file with
# a header line (a sweep's results.csv, or drape run --summary csv), one
# line a row, separated by tabs (or SEP), quotes taken off. A column the
# header lacks is an error (exit 2). Any awk will do (Debian's is mawk).
# Reading the lines with `IFS=$'\t' read`, an empty field vanishes (a tab
# is white space to read): give a SEP that is not, such as $'\037'.
set -u
sep=$'\t'
if [ "${1:-}" = -d ]; then sep=${2:-}; shift 2; fi
[ $# -ge 2 ] || { echo "usage: csvcols.sh [-d SEP] FILE COLUMN..." >&2; exit 2; }
file=$1
shift
[ -r "$file" ] || { echo "csvcols.sh: cannot read $file" >&2; exit 2; }
awk -v want="$*" -v sep="$sep" '
# the fields of one line into f[1..n], RFC 4180 quoting (no line breaks)
function split_csv(line, f,   n, i, c, q, cur) {
	n = 0; cur = ""; q = 0
	for (i = 1; i <= length(line); i++) {
		c = substr(line, i, 1)
		if (q) {
			if (c == "\"") {
				if (substr(line, i + 1, 1) == "\"") { cur = cur "\""; i++ }
				else q = 0
			} else cur = cur c
		} else if (c == "\"") q = 1
		else if (c == ",") { f[++n] = cur; cur = "" }
		else cur = cur c
	}
	f[++n] = cur
	return n
}
{ sub(/\r$/, "") }
NR == 1 {
	n = split_csv($0, h)
	for (i = 1; i <= n; i++) at[h[i]] = i
	nw = split(want, w, " ")
	for (k = 1; k <= nw; k++)
		if (!(w[k] in at)) { printf "csvcols.sh: no column %s\n", w[k] > "/dev/stderr"; bad = 1; exit 2 }
	next
}
{
	split_csv($0, f)
	for (k = 1; k <= nw; k++) printf "%s%s", (k > 1 ? sep : ""), f[at[w[k]]]
	printf "\n"
}
END { if (bad) exit 2 }' "$file"

#!/usr/bin/env bash
# Narrow-phase accuracy and speed on the CCD benchmark sample queries of
# Wang et al. (tests/data/ccd-sample-queries): `drape ccd` with the
# continuous test (--method ccd) and the chapter's node-triangle test
# (--method seed, with its angle-sum and crossing inside tests), per file:
# queries, false negatives (missed contacts), false positives, queries/s.
# The counts are exact; queries/s is the median of BENCH_RUNS runs.
# Writes ccd.csv and ccd.png under BENCH_RESULTS; prints the table and a
# dumb-terminal chart. See bench/README.md.
#
# Environment: BENCH_RUNS (default 3), BENCH_RESULTS (default
# bench/results), DRAPE, BENCH_SRCDIR, GNUPLOT.
set -u
prog=ccd.sh
. "$(cd "$(dirname "$0")" && pwd)/lib.sh"

qdir=tests/data/ccd-sample-queries/unit-tests
files=$(cd "$srcdir" && ls $qdir/*/*.csv 2>/dev/null)
[ -n "$files" ] || die "no query files under $srcdir/$qdir"

# method label and its drape ccd options
methods="ccd        --method ccd
seed-angle --method seed --inside angle
seed-cross --method seed --inside crossing"

echo "narrow-phase accuracy: $version (commit $commit), $stamp"
echo "machine: $ncpu cores, ${cpu:-unknown cpu}; load $(load)"
echo "drape ccd on $qdir; queries/s: median of $runs runs"
echo

: >"$tmp/all"
while read -r label opts; do
	for r in $(seq 1 "$runs"); do
		# shellcheck disable=SC2086 # opts are words
		(cd "$srcdir" && "$drape" ccd $opts $files) >"$tmp/out" 2>"$tmp/err"
		rc=$?
		[ $rc -eq 0 ] || { echo "$prog: drape ccd $opts exited $rc:"; cat "$tmp/err"; } >&2
		[ $rc -eq 0 ] || exit 1
		# method run file queries positives true_pos false_neg false_pos queries_per_s
		awk -F'\t' -v m="$label" -v r="$r" 'NR > 1 { print m, r, $1, $3, $4, $5, $6, $7, $8 }' "$tmp/out" >>"$tmp/all"
	done
done <<<"$methods"

# the true contacts of a file: true_pos + false_neg of any method that
# tested it (seed has no edge-edge test)
csv=$results/ccd.csv
echo "file,kind,method,status,queries,true_contacts,positives,true_pos,false_neg,false_pos,queries_per_s,ns_per_query" >"$csv"
printf '%-22s %-10s %7s %7s %9s %9s %9s %12s %9s\n' file method queries true positives false_neg false_pos queries/s ns/query
while read -r label _; do
	for f in $files; do
		truth=$(awk -v f="$f" '$3 == f && $6 != "n/a" { print $6 + $7; exit }' "$tmp/all")
		read -r _ _ _ q pos tp fn fp _ < <(awk -v m="$label" -v f="$f" '$1 == m && $3 == f' "$tmp/all" | head -n 1)
		qps=$(awk -v m="$label" -v f="$f" '$1 == m && $3 == f && $9 != "n/a" { print $9 }' "$tmp/all" | median)
		short=${f#"$qdir"/}
		short=${short%.csv}
		kind=${short%%/*}
		if [ "$qps" = - ]; then
			echo "$short,$kind,$label,n/a,$q,${truth:--},-,-,-,-,-,-" >>"$csv"
			printf '%-22s %-10s %7s %7s %9s\n' "$short" "$label" "$q" "${truth:--}" "n/a (no edge-edge test)"
		else
			nsq=$(awk -v v="$qps" 'BEGIN { printf "%.4g", 1e9 / v }')
			echo "$short,$kind,$label,ok,$q,$truth,$pos,$tp,$fn,$fp,$qps,$nsq" >>"$csv"
			printf '%-22s %-10s %7s %7s %9s %9s %9s %12.3g %9s\n' "$short" "$label" "$q" "$truth" "$pos" "$fn" "$fp" "$qps" "$nsq"
		fi
	done
done <<<"$methods"
cat <<EOF

true: the file's contacts (its truth column); positives: those the method
  reports. false_neg: contacts missed (the cloth would pass through);
  false_pos: contacts reported that are not there (they only cost time).
  seed tests the vertex's path against the triangle at time 0, as the
  chapter does, so it misses contacts that the triangle's own motion makes.
queries/s: each run times as many passes over the file as fill 0.05 s;
  median of $runs runs. ns/query: 1e9 over it.
load average at the end: $(load) ($ncpu cores)
data: $csv
EOF
bad=0
plot ccd.gp "$csv" "$results/ccd.png" "stamp='$stamp'; runs='$runs'" || bad=1
exit $bad

#!/usr/bin/env bash
# Narrow-phase accuracy and speed on the CCD benchmark sample queries of
# Wang et al. (tests/data/ccd-sample-queries): `drape ccd` with the
# continuous test (--method ccd) and the chapter's node-triangle test
# (--method seed, with its angle-sum and crossing inside tests), per file:
# queries, false negatives (missed contacts), false positives, queries/s.
# The counts are exact; queries/s is the median of BENCH_RUNS runs.
# Data go to $BENCH_OUT/ccd.dat. See bench/README.md.
#
# Environment: BENCH_RUNS (default 3), BENCH_OUT (default bench/out),
# DRAPE (default src/drape), BENCH_SRCDIR (default: this script's ..).
set -u

here=$(cd "$(dirname "$0")" && pwd)
srcdir=${BENCH_SRCDIR:-$(cd "$here/.." && pwd)}
drape=${DRAPE:-$srcdir/src/drape}
out=${BENCH_OUT:-$srcdir/bench/out}
runs=${BENCH_RUNS:-3}

die() { echo "ccd.sh: $*" >&2; exit 2; }
case $runs in '' | *[!0-9]* | 0) die "BENCH_RUNS must be a whole number > 0, not '$runs'" ;; esac
[ -x "$drape" ] || die "no binary at $drape: build first (make), or set DRAPE"
mkdir -p "$out" || die "cannot create $out"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/drape-bench.XXXXXX") || die "mktemp failed"
trap 'rm -rf "$tmp"' EXIT
trap 'exit 130' INT TERM

qdir=tests/data/ccd-sample-queries/unit-tests
files=$(cd "$srcdir" && ls $qdir/*/*.csv 2>/dev/null)
[ -n "$files" ] || die "no query files under $srcdir/$qdir"

# method label and its drape ccd options
methods="ccd        --method ccd
seed-angle --method seed --inside angle
seed-cross --method seed --inside crossing"

: >"$tmp/all"
while read -r label opts; do
	for r in $(seq 1 "$runs"); do
		# shellcheck disable=SC2086 # opts are words
		(cd "$srcdir" && "$drape" ccd $opts $files) >"$tmp/out" 2>"$tmp/err"
		rc=$?
		if [ $rc -ne 0 ]; then
			echo "ccd.sh: drape ccd $opts exited $rc:" >&2
			cat "$tmp/err" >&2
			exit 1
		fi
		# file method queries positives true_pos false_neg false_pos queries_per_s
		awk -F'\t' -v m="$label" -v r="$r" 'NR > 1 { print m, r, $1, $3, $4, $5, $6, $7, $8 }' "$tmp/out" >>"$tmp/all"
	done
done <<<"$methods"

version=$("$drape" --version 2>/dev/null | head -n 1)
commit=$(git -C "$srcdir" rev-parse --short HEAD 2>/dev/null || echo "?")
ncpu=$(nproc 2>/dev/null || echo "?")
stamp=$(date -u '+%Y-%m-%d %H:%M UTC')
datf=$out/ccd.dat
{
	echo "# drape ccd on $qdir: $version (commit $commit), $stamp, $ncpu cores"
	echo "# counts are exact; queries_per_s is the median of $runs runs; n/a: seed has no edge-edge test"
	echo "# file kind method queries positives true_pos false_neg false_pos queries_per_s"
} >"$datf"

echo "narrow-phase accuracy: drape ccd on $qdir (queries/s: median of $runs runs)"
printf '%-28s %-10s %7s %9s %9s %9s %12s\n' file method queries positives false_neg false_pos queries/s
while read -r label _; do
	for f in $files; do
		rows=$(awk -v m="$label" -v f="$f" '$1 == m && $3 == f' "$tmp/all")
		set -- $(head -n 1 <<<"$rows")
		q=$4 pos=$5 tp=$6 fn=$7 fp=$8
		qps=$(awk '{ print $9 }' <<<"$rows" | grep -v '^n/a$' | sort -g |
			awk '{ v[NR] = $1 } END { if (!NR) print "n/a"; else if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }')
		short=${f#"$qdir"/}
		kind=${short%%/*}
		echo "$short $kind $label $q $pos $tp $fn $fp $qps" >>"$datf"
		if [ "$qps" = n/a ]; then
			printf '%-28s %-10s %7s %9s %9s %9s %12s\n' "$short" "$label" "$q" n/a n/a n/a "n/a (no edge-edge test)"
		else
			printf '%-28s %-10s %7s %9s %9s %9s %12.3g\n' "$short" "$label" "$q" "$pos" "$fn" "$fp" "$qps"
		fi
	done
done <<<"$methods"
cat <<EOF
false_neg: contacts missed (the cloth would pass through); false_pos:
contacts reported that are not there (they only cost time). seed tests the
vertex's path against the triangle at time 0, as the chapter does, so it
misses contacts that the triangle's own motion makes.
data: $datf
EOF

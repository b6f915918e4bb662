#!/usr/bin/env bash
# Replays whose events are a digest (issue 16; drape-replay(5), EVENTS
# RECOMPUTED), each figure printed against its target:
#   1. the size of each part of the file (drape info) for the shipped
#      tablecloth's whole run (the fast path), with the events' digest and
#      stored, and for the same 2 s under rk4 (about 20 s to record;
#      skipped with BENCH_EVENTS_RK4=0); target at most 2 MB;
#   2. drape events --node N on the digest tablecloth, nodes 0, 312 and
#      624, and on the whole file: wall time, median of BENCH_RUNS runs
#      each; target at most 1 s; the output byte for byte the stored
#      file's;
#   3. recording overhead: the tablecloth run without --record and with
#      it, back to back (BENCH_EVENTS_PAIRS pairs, default 21), the
#      digest's pairs then --events stored's: the median of the pairs'
#      ratios; target at most 5 %.
# Timing runs one job at a time; the machine's load is printed.
#
# Environment: BENCH_RUNS (default 3), BENCH_EVENTS_PAIRS (default 21),
# BENCH_EVENTS_RK4 (default 1), DRAPE, BENCH_SRCDIR.
set -u
prog=events.sh
. "$(cd "$(dirname "$0")" && pwd)/lib.sh"

pairs=${BENCH_EVENTS_PAIRS:-21}
rk4=${BENCH_EVENTS_RK4:-1}
scene=scenes/tablecloth.scene

echo "replay events by digest: $version (commit $commit), $stamp"
echo "machine: $ncpu cores, ${cpu:-unknown cpu}; load $(load)"
echo

wall() { # command...: its wall time in seconds, its output discarded
	local t0 t1
	t0=$(date +%s.%N)
	"$@" >/dev/null 2>&1 || { echo "$prog: $* failed" >&2; exit 1; }
	t1=$(date +%s.%N)
	awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.4f\n", b - a }'
}

sizes() { # file label
	"$drape" info "$1" | awk -v l="$2" '
	/^events / { ev = $2 }
	/^file size / {
		gsub(/,/, "")
		printf "  %-26s %10d bytes: scene %d, frames %d, keyframes %d, steps %d, index %d; %s events\n",
		    l, $3, $6, $8, $10, $15, $17, ev
	}'
}

echo "1. file sizes (drape info), target: the whole 2 s tablecloth at most 2 MB"
(cd "$srcdir" && "$drape" run --headless --keyframe-every 50 --record "$tmp/d.drr" $scene &&
	"$drape" run --headless --keyframe-every 50 --events stored --record "$tmp/s.drr" $scene) \
	>/dev/null || die "recording the tablecloth failed"
sizes "$tmp/d.drr" "tablecloth, digest"
sizes "$tmp/s.drr" "tablecloth, stored"
if [ "$rk4" != 0 ]; then
	(cd "$srcdir" && "$drape" run --headless --integrator rk4 --record "$tmp/r.drr" $scene) \
		>/dev/null || die "recording the rk4 tablecloth failed"
	sizes "$tmp/r.drr" "tablecloth rk4, digest"
	rm -f "$tmp/r.drr"
fi
echo

echo "2. drape events on the digest tablecloth, median of $runs runs; target at most 1 s"
"$drape" events "$tmp/d.drr" >"$tmp/ev-d" && "$drape" events "$tmp/s.drr" >"$tmp/ev-s" ||
	die "drape events failed"
if cmp -s "$tmp/ev-d" "$tmp/ev-s"; then
	echo "  output: the same $(wc -l <"$tmp/ev-d") lines as the stored file's, byte for byte"
else
	echo "  output: DIFFERS from the stored file's"
fi
for what in "--node 0" "--node 312" "--node 624" ""; do
	# shellcheck disable=SC2086 # what is words
	t=$(for r in $(seq 1 "$runs"); do wall "$drape" events $what "$tmp/d.drr"; done | median)
	printf "  drape events %-11s %6.3f s (stored file: %s s)\n" "$what" "$t" \
	    "$(for r in $(seq 1 "$runs"); do wall "$drape" events $what "$tmp/s.drr"; done | median)"
done
echo

echo "3. recording overhead, $pairs back-to-back pairs of runs without and with --record;"
echo "   target at most 5 %"
cd "$srcdir" || exit 1
for how in digest stored; do
	: >"$tmp/pairs"
	for r in $(seq 1 "$pairs"); do
		a=$(wall "$drape" run --headless $scene)
		b=$(wall "$drape" run --headless --events "$how" --record "$tmp/o.drr" $scene)
		echo "$a $b" >>"$tmp/pairs"
	done
	printf "  %-6s median wall %s s without, %s s with; median of the pairs' ratios %+.1f %%\n" \
	    "$how" "$(awk '{ print $1 }' "$tmp/pairs" | median)" \
	    "$(awk '{ print $2 }' "$tmp/pairs" | median)" \
	    "$(awk '{ print 100 * ($2 / $1 - 1) }' "$tmp/pairs" | median)"
done
echo "load $(load)"

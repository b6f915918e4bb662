#!/usr/bin/env bash
# mg: the multigrid preconditioner (src/mg.h) inside PCG on the implicit
# step's Newton matrices, as tests/test_mg builds them: iterations to a
# relative residual of 1e-6, the least times of mg_setup, mg_update_fine,
# mg_apply and one product A x over BENCH_RUNS calls, and mg's memory a
# node, for the shipped cloths and the peers' 0.24 m square at 25^2, 50^2
# and 100^2, at rest, crumpled and crumpled with held nodes and contacts.
# The crumpled state is the test's (a 150 degree fold round 3 spacings
# plus noise of 0.1 spacing), then the fold alone at radii of 3 and 6
# spacings (no noise), where bilinear interpolation's counts grew most
# with refinement.
#
# Environment:
#   BENCH_RUNS    calls per timing (default 20); the least is shown
#   TEST_MG       the test binary (default tests/test_mg: make it first)
#   BENCH_SRCDIR  the source tree (default this script's parent)
set -u
here=$(cd "$(dirname "$0")" && pwd)
srcdir=${BENCH_SRCDIR:-$(cd "$here/.." && pwd)}
bin=${TEST_MG:-$srcdir/tests/test_mg}
runs=${BENCH_RUNS:-20}
case $runs in '' | *[!0-9]* | 0) echo "mg.sh: BENCH_RUNS must be a whole number > 0" >&2; exit 2 ;; esac
[ -x "$bin" ] || { echo "mg.sh: no $bin: make tests/test_mg first, or set TEST_MG" >&2; exit 2; }

echo "mg.sh: $(git -C "$srcdir" rev-parse --short HEAD 2>/dev/null || echo '?'), $(nproc) cpus," \
	"$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo 2>/dev/null)," \
	"load $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null), $(date -u '+%Y-%m-%d %H:%M UTC')"
run() { # title, then environment assignments
	echo "== $1"
	shift
	env MG_REPS="$runs" "$@" "$bin" 2>&1 | grep -E ' nodes |spacing:|B r' || {
		echo "mg.sh: $bin failed" >&2
		exit 1
	}
}
run "as tested: fold 150 degrees round 3 spacings, noise 0.1 spacing"
run "the fold alone, radius 3 spacings" MG_NOISE=0
run "the fold alone, radius 6 spacings" MG_NOISE=0 MG_RADIUS=6

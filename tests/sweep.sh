#!/usr/bin/env bash
# sweep.sh: bench/sweep.sh through GNU parallel on this machine, 2 jobs at
# a time: a grid of 4 jobs over the step, one of them too long on purpose,
# gives results.csv with 4 rows in job order: the blow-up as a row with its
# exit status (3), drape's message and its record, the others with the
# record of the run each asked for (the same state hash as that run
# alone); --resume then runs nothing and leaves the CSV as it was;
# --retry-failed runs the failure again. A value drape refuses is a row
# with exit 2 and the message; rows cross with a grid; the Slurm job array,
# its tasks run by hand here, collects to the same rows as parallel.
# bench/drape-fit.sh run by hand writes to ./drape-fit/, not bench/results.
# Skipped (77) without GNU parallel (.ci/setup installs it).
set -u

DRAPE=${DRAPE:-src/drape}
srcdir=${srcdir:-.}
sweep=$srcdir/bench/sweep.sh
cols=$srcdir/bench/csvcols.sh
command -v parallel >/dev/null 2>&1 && parallel --version 2>/dev/null | grep -q 'GNU parallel' ||
	{ echo "GNU parallel not found: skipped (Debian: apt-get install -y parallel)"; exit 77; }

tmp=$(mktemp -d /tmp/drape-sweep-XXXXXX) || exit 1
trap 'rm -rf "$tmp"' EXIT
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
ok() { echo "ok: $*"; }

cat >"$tmp/fall.scene" <<'SCENE'
[simulation]
duration = 10 ms
[cloth]
nodes = 6 6
spacing = 10 mm
origin = -0.025 0.01 -0.025 m
weight = 100 g/m2
thickness = 0.3 mm
modulus_warp = 0.5 MPa
modulus_weft = 0.5 MPa
shear_modulus = 0
bending_warp = 1 uN*m
bending_weft = 1 uN*m
[plane]
point = 0 0 0
SCENE
# 4 jobs over the step; 1 ms blows up (exit 3) on purpose
printf 'simulation.dt\tauto\t100 us\t1 ms\t50 us\n# a comment, and a blank line\n\n' >"$tmp/grid.tsv"
out=$tmp/out
run_sweep() { DRAPE=$DRAPE "$sweep" -j 2 -o "$out" -g "$tmp/grid.tsv" "$@" "$tmp/fall.scene" -- \
	--final-obj '{job}/final.obj'; }

run_sweep -q
rc=$?
[ $rc = 1 ] && ok "a sweep with a failed job exits 1" || fail "sweep exit $rc, expected 1"
res=$out/results.csv
[ -r "$res" ] || { fail "no $res"; exit 1; }
rows=$(($(wc -l <"$res") - 1))
[ "$rows" = 4 ] && ok "4 rows" || fail "$rows rows, expected 4"
got=$("$cols" "$res" job exit simulation.dt outcome exit_status | tr '\t' ' ')
want="1 0 auto completed 0
2 0 100 us completed 0
3 3 1 ms blowup 3
4 0 50 us completed 0"
[ "$got" = "$want" ] && ok "rows in job order, their values, exits and outcomes" ||
	fail "rows: '$got', expected '$want'"
err3=$("$cols" "$res" error | sed -n 3p)
case $err3 in
*"blow-up at step"*) ok "the failure's row says why: $err3" ;;
*) fail "job 3's error: '$err3'" ;;
esac
[ -n "$("$cols" "$res" failure.step | sed -n 3p)" ] && ok "and has the record of its last good step" ||
	fail "job 3 has no failure.step"
[ -z "$("$cols" "$res" error | sed -n 1p)" ] && ok "no error on a job that ran" || fail "job 1 has an error"
# each job's record is the run it asked for
h2=$("$cols" "$res" state_hash | sed -n 2p)
alone=$("$DRAPE" run --summary csv --set 'simulation.dt=100 us' "$tmp/fall.scene" 2>/dev/null |
	"$cols" /dev/stdin state_hash)
[ -n "$h2" ] && [ "$h2" = "$alone" ] && ok "job 2's hash $h2 is that run's alone" ||
	fail "job 2's hash '$h2', the run alone '$alone'"
[ -s "$out/jobs/1/final.obj" ] && ok "{job} in drape's options is the job's directory" ||
	fail "no $out/jobs/1/final.obj"
[ "$("$cols" "$res" scene.overrides | sed -n 2p)" = "simulation.dt=100 us" ] &&
	ok "the record lists the job's overrides" || fail "overrides: $("$cols" "$res" scene.overrides | sed -n 2p)"

# --resume: nothing to run, the same CSV
cp "$res" "$tmp/first.csv"
cp "$out/joblog" "$tmp/joblog"
msg=$(run_sweep --resume 2>&1)
case $msg in
*"4 jobs, 0 to run (4 done already)"*) ok "--resume runs nothing" ;;
*) fail "--resume said: $msg" ;;
esac
cmp -s "$tmp/joblog" "$out/joblog" && ok "parallel not started again" || fail "the joblog changed"
cmp -s "$tmp/first.csv" "$res" && ok "the same results.csv" || fail "results.csv changed"
# a sweep there without --resume is refused
run_sweep -q 2>"$tmp/err"
rc=$?
[ $rc = 2 ] && grep -q "already holds a sweep" "$tmp/err" && ok "no second sweep over a first" ||
	fail "a second sweep: exit $rc, $(cat "$tmp/err")"
# --retry-failed runs the failure again
msg=$(run_sweep --resume --retry-failed 2>&1)
case $msg in
*"4 jobs, 1 to run"*) ok "--retry-failed runs the failed job" ;;
*) fail "--retry-failed said: $msg" ;;
esac
[ "$("$cols" "$tmp/first.csv" job exit state_hash failure.message)" = \
	"$("$cols" "$res" job exit state_hash failure.message)" ] && ok "and it fails the same way" ||
	fail "the failure's row changed"

# a value drape refuses: a row with exit 2 and drape's message, no record
DRAPE=$DRAPE "$sweep" -q -j1 -o "$tmp/o1" --set 'cloth.spacing=10 mm' --set 'cloth.spacing=0 mm' \
	"$tmp/fall.scene"
got=$("$cols" "$tmp/o1/results.csv" exit outcome error | sed -n 2p)
case $got in
"2		drape: --set cloth.spacing=0 mm: spacing: expected a length"*) ok "a refused value is a row: $got" ;;
*) fail "a refused value: '$got'" ;;
esac
# usage errors
DRAPE=$DRAPE "$sweep" -q -o "$tmp/o2" --set 'cloth spacing=1' "$tmp/fall.scene" 2>"$tmp/err"
rc=$?
[ $rc = 2 ] && grep -q "expected a key SECTION.KEY" "$tmp/err" && ok "a bad key: exit 2" ||
	fail "a bad key: exit $rc, $(cat "$tmp/err")"
DRAPE=$DRAPE "$sweep" -q -jx -o "$tmp/o5" --set 'cloth.spacing=10 mm' "$tmp/fall.scene" 2>"$tmp/err"
rc=$?
[ $rc = 2 ] && grep -q -- "--jobs 'x': expected a whole number" "$tmp/err" && ok "-jx: exit 2" ||
	fail "-jx: exit $rc, $(cat "$tmp/err")"
printf 'cloth.spacing\n' >"$tmp/bad.tsv"
DRAPE=$DRAPE "$sweep" -q -o "$tmp/o3" -g "$tmp/bad.tsv" "$tmp/fall.scene" 2>"$tmp/err"
rc=$?
[ $rc = 2 ] && grep -q "bad.tsv:1: expected KEY<TAB>VALUE" "$tmp/err" && ok "a bad grid line: FILE:LINE, exit 2" ||
	fail "a bad grid: exit $rc, $(cat "$tmp/err")"

# rows: values that go together, crossed with a grid
printf 'cloth.spacing\tcloth.bending_weft\n9 mm\t2 uN*m\n11 mm\t4 uN*m\n' >"$tmp/rows.tsv"
DRAPE=$DRAPE "$sweep" -q -o "$tmp/o4" -r "$tmp/rows.tsv" --set 'cloth.bending_warp=1 uN*m' \
	--set 'cloth.bending_warp=2 uN*m' "$tmp/fall.scene"
rc=$?
got=$("$cols" "$tmp/o4/results.csv" cloth.spacing cloth.bending_weft cloth.bending_warp exit | tr '\t' ' ')
want="9 mm 2 uN*m 1 uN*m 0
9 mm 2 uN*m 2 uN*m 0
11 mm 4 uN*m 1 uN*m 0
11 mm 4 uN*m 2 uN*m 0"
[ $rc = 0 ] && [ "$got" = "$want" ] && ok "rows crossed with the grid, exit 0" ||
	fail "rows x grid: exit $rc, '$got'"

# Slurm: the array script, its tasks run here by hand, then --collect
DRAPE=$DRAPE "$sweep" -q --slurm -o "$tmp/slurm" -g "$tmp/grid.tsv" "$tmp/fall.scene" -- \
	--final-obj '{job}/final.obj' >"$tmp/array.sh"
grep -q '^#SBATCH --array=1,2,3,4$' "$tmp/array.sh" && ok "a Slurm array of the 4 jobs" ||
	fail "the array script: $(grep SBATCH "$tmp/array.sh")"
for n in 1 2 3 4; do SLURM_ARRAY_TASK_ID=$n bash "$tmp/array.sh"; done
DRAPE=$DRAPE "$sweep" -q --collect -o "$tmp/slurm"
a=$("$cols" "$tmp/slurm/results.csv" job exit simulation.dt state_hash failure.message)
b=$("$cols" "$res" job exit simulation.dt state_hash failure.message)
[ "$a" = "$b" ] && ok "the array's rows are parallel's" || fail "slurm rows '$a', parallel's '$b'"

# issue 30: bench/drape-fit.sh run by hand wrote over the shipped, tracked
# bench/results/drape-fit.csv and .png, unsaid; it writes to ./drape-fit/
# now and says where (a fit of two 1 ms runs: too short to bracket the
# target, which it says, exit 1; what matters is where it wrote)
top=$(cd "$srcdir" && pwd)
drape_abs=$(cd "$(dirname "$DRAPE")" && pwd)/$(basename "$DRAPE")
shipped=$top/bench/results/drape-fit.csv
before=$(cksum <"$shipped")
mkdir "$tmp/fit" && (cd "$tmp/fit" && env -u BENCH_RESULTS DRAPE="$drape_abs" BENCH_SRCDIR="$top" \
	BENCH_FIT_SCALES="1 2" BENCH_FIT_UNTIL=0.001 BENCH_FIT_MAXRUNS=0 BENCH_FIT_JOBS=2 \
	GNUPLOT=false bash "$top/bench/drape-fit.sh") >"$tmp/fit.out" 2>&1
[ "$(cksum <"$shipped")" = "$before" ] && ok "drape-fit.sh left the shipped results alone" ||
	fail "drape-fit.sh changed $shipped"
[ -s "$tmp/fit/drape-fit/drape-fit.csv" ] && grep -q "^writing to $tmp/fit/drape-fit\$" "$tmp/fit.out" &&
	ok "drape-fit.sh wrote to ./drape-fit/ and said so" ||
	fail "drape-fit.sh did not write to ./drape-fit/: $(head -n 8 "$tmp/fit.out")"

[ $fails = 0 ] || { echo "$fails failed"; exit 1; }
echo "all passed"

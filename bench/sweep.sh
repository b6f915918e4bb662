#!/usr/bin/env bash
# sweep.sh: runs a scene over a grid of values through GNU parallel, one
# `drape run --summary csv` a job, and collects one CSV with a row per job.
# See bench/README.md ("sweep.sh") and `bench/sweep.sh --help`.
set -u

prog=sweep.sh
here=$(cd "$(dirname "$0")" && pwd)
srcdir=${BENCH_SRCDIR:-$(cd "$here/.." && pwd)}

usage() {
	cat <<'EOF'
usage: bench/sweep.sh [options] SCENE [-- DRAPE-RUN-OPTIONS...]
       bench/sweep.sh --collect [-o DIR]

Runs `drape run --headless --summary csv --set KEY=VALUE... SCENE` for every
job of a grid, through GNU parallel, and writes DIR/results.csv: one row a
job (job, exit, host, error, the job's values, then drape's record).

The grid (the jobs are every combination of what is given):
  -g, --grid FILE      a TSV file: each line KEY<TAB>VALUE<TAB>VALUE...
  -s, --set KEY=VALUE  one value of KEY; given again for the same KEY, another
  -r, --rows FILE      a TSV file: a line of KEYs, then one line of values a job
                       (for values that go together), crossed with the rest
  KEY is drape's SECTION.KEY or SECTION#N.KEY (drape(1), --set); '#' starts
  a comment line in the grid file, and blank lines are skipped.

Where and how:
  -o, --out DIR        the sweep's directory (default: sweep): jobs.tsv,
                       jobs.cmd, jobs/N/ (stdout, stderr, the job's files),
                       joblog, results.csv
  -j, --jobs N, -jN    jobs at once on each machine (parallel -j; default: a
                       job a core)
  -S, --sshlogin LIST  also or instead run on these machines (parallel -S,
                       e.g. 8/node1,node2,: where : is this one)
      --sshloginfile F the machines in a file (parallel --sshloginfile)
      --basefile F     copy F to the other machines first (the scene is
                       copied anyway; add the meshes it reads)
      --return NAME    bring back the file NAME of each job's directory from
                       the other machines
      --drape PATH     the binary (default: $DRAPE, else src/drape of this
                       tree), at the same path on every machine
      --slurm          run nothing: print a Slurm job-array script for the
                       jobs not done (e.g. bench/sweep.sh --slurm ... | sbatch),
                       then collect with --collect
      --collect        run nothing: make DIR/results.csv from DIR's jobs
      --resume         keep the jobs already done with the same values, run
                       the others (a failed job is done: its row says how)
      --retry-failed   with --resume, run the failed jobs again too
  -n, --dry-run        print the jobs' commands, run nothing
  -q, --quiet          no progress
  -h, --help

In DRAPE-RUN-OPTIONS, {job} is the job's directory (DIR/jobs/N), e.g.
-- --final-obj {job}/final.obj. Exit status: 0 if every job exited 0, 1 if
one did not (its row says how) or was lost, 2 on a usage error.
EOF
}

die() { echo "$prog: $*" >&2; exit 2; }

grid_files=() rows_file="" sets=() out=sweep jobs="" sshlogin="" sshloginfile=""
basefiles=() returns=() drape=${DRAPE:-$srcdir/src/drape} slurm=0 collect=0
resume=0 retry=0 dry=0 quiet=0 scene="" extra=()
while [ $# -gt 0 ]; do
	case $1 in
	-g | --grid) [ $# -ge 2 ] || die "$1 needs a file"; grid_files+=("$2"); shift 2 ;;
	-s | --set) [ $# -ge 2 ] || die "$1 needs KEY=VALUE"; sets+=("$2"); shift 2 ;;
	-r | --rows) [ $# -ge 2 ] || die "$1 needs a file"; rows_file=$2; shift 2 ;;
	-o | --out) [ $# -ge 2 ] || die "$1 needs a directory"; out=$2; shift 2 ;;
	-j | --jobs) [ $# -ge 2 ] || die "$1 needs a number"; jobs=$2; shift 2 ;;
	-j?*) jobs=${1#-j}; shift ;;	# -j2, as make and parallel take it
	-S | --sshlogin) [ $# -ge 2 ] || die "$1 needs machines"; sshlogin=$2; shift 2 ;;
	--sshloginfile) [ $# -ge 2 ] || die "$1 needs a file"; sshloginfile=$2; shift 2 ;;
	--basefile) [ $# -ge 2 ] || die "$1 needs a file"; basefiles+=("$2"); shift 2 ;;
	--return) [ $# -ge 2 ] || die "$1 needs a file name"; returns+=("$2"); shift 2 ;;
	--drape) [ $# -ge 2 ] || die "$1 needs a path"; drape=$2; shift 2 ;;
	--slurm) slurm=1; shift ;;
	--collect) collect=1; shift ;;
	--resume) resume=1; shift ;;
	--retry-failed) retry=1; shift ;;
	-n | --dry-run) dry=1; shift ;;
	-q | --quiet) quiet=1; shift ;;
	-h | --help) usage; exit 0 ;;
	--) shift; extra=("$@"); break ;;
	-*) die "unknown option '$1' (--help lists them)" ;;
	*) [ -z "$scene" ] || die "one scene, not '$scene' and '$1'"; scene=$1; shift ;;
	esac
done
case $jobs in '' | [1-9] | [1-9][0-9] | [1-9][0-9][0-9] | *%) ;; *) die "--jobs '$jobs': expected a whole number from 1 (or N%)" ;; esac
[ $retry = 0 ] || [ $resume = 1 ] || die "--retry-failed goes with --resume"
if [ $dry = 1 ]; then	# nothing made: the commands only
	case $out in /*) ;; *) out=$PWD/$out ;; esac
	work=$(mktemp -d "${TMPDIR:-/tmp}/sweep.XXXXXX") || die "mktemp failed"
	trap 'rm -rf "$work"' EXIT
else
	mkdir -p "$out" || die "cannot create $out"
	out=$(cd "$out" && pwd)
	work=$out
fi
tab=$(printf '\t')

# ---- the results, from the jobs' directories ----

# DIR/results.csv from DIR/jobs.tsv and DIR/jobs/N/{stdout,stderr}: the
# exit status and host from the job's last "sweep-exit: STATUS HOST" line
# on stderr (none: the job was lost or never ran), the error from its
# first other line, drape's record from its stdout (header, row).
collect_results() {
	local tmpf=$out/results.csv.tmp
	awk -F'\t' -v out="$out" '
	function csvq(s) {
		if (s ~ /[,"\r]/ || s ~ /^ / || s ~ / $/) { gsub(/"/, "\"\"", s); return "\"" s "\"" }
		return s
	}
	NR == 1 { nk = NF - 1; for (k = 2; k <= NF; k++) key[k - 1] = $k; next }
	{
		n++; job[n] = $1
		for (k = 2; k <= NF; k++) val[n, k - 1] = $k
		d = out "/jobs/" $1
		st[n] = ""; host[n] = ""; err[n] = ""
		while ((getline line < (d "/stderr")) > 0) {
			if (line ~ /^sweep-exit: /) { split(line, w, " "); st[n] = w[2]; host[n] = w[3] }
			else if (err[n] == "" && line != "") err[n] = line
		}
		close(d "/stderr")
		h = ""; row[n] = ""
		if ((getline h < (d "/stdout")) > 0 && (getline r < (d "/stdout")) > 0) {
			if (head == "") head = h
			if (h == head) row[n] = r
			else err[n] = "its summary fields differ from those of the other jobs"
		}
		close(d "/stdout")
		if (st[n] == "") err[n] = "no exit status: the job was lost (killed, or its machine failed) or never ran"
		else if (st[n] == 0) err[n] = ""
	}
	END {
		nf = head == "" ? 0 : split(head, hf, ",")
		pad = ""; for (k = 1; k <= nf; k++) pad = pad ","
		printf "job,exit,host,error"
		for (k = 1; k <= nk; k++) printf ",%s", csvq(key[k])
		print (head == "" ? "" : "," head)
		for (i = 1; i <= n; i++) {
			printf "%s,%s,%s,%s", job[i], st[i], csvq(host[i]), csvq(err[i])
			for (k = 1; k <= nk; k++) printf ",%s", csvq(val[i, k])
			print (row[i] != "" ? "," row[i] : pad)
		}
	}' "$out/jobs.tsv" >"$tmpf" && mv "$tmpf" "$out/results.csv" || die "cannot write $out/results.csv"
}

# The counts of results.csv: "jobs ok failed lost".
tally() {
	awk -F, 'NR > 1 { n++; if ($2 == "") l++; else if ($2 == 0) o++; else f++ }
	END { print n + 0, o + 0, f + 0, l + 0 }' "$out/results.csv"
}

report() {
	local n ok failed lost
	read -r n ok failed lost <<<"$(tally)"
	[ $quiet = 1 ] || echo "$prog: $n jobs: $ok ran to exit 0, $failed failed, $lost lost; $out/results.csv" >&2
	[ $((failed + lost)) = 0 ]
}

if [ $collect = 1 ]; then
	[ -r "$out/jobs.tsv" ] || die "no $out/jobs.tsv: nothing to collect"
	collect_results
	report
	exit $?
fi

# ---- the grid ----

[ -n "$scene" ] || { usage >&2; exit 2; }
[ -r "$scene" ] || die "cannot read the scene '$scene'"
scene=$(cd "$(dirname "$scene")" && pwd)/$(basename "$scene")
[ $slurm = 1 ] || [ $dry = 1 ] || [ -x "$drape" ] || [ -n "$sshlogin$sshloginfile" ] ||
	die "no drape at '$drape': build it (make), or give --drape or DRAPE"

check_key() { # key where
	case $1 in
	*[!A-Za-z0-9_.#-]* | .* | *. | *.*.* | '') die "$2: '$1': expected a key SECTION.KEY or SECTION#N.KEY" ;;
	*.*) ;;
	*) die "$2: '$1': expected a key SECTION.KEY or SECTION#N.KEY" ;;
	esac
}
check_value() { # value where
	case $1 in
	'' | *"$tab"* | *'#'*) die "$2: '$1': expected a value, without a tab or '#'" ;;
	esac
}

# The axes: keys, and each key's values joined by a newline.
keys=()
declare -A axis=()
add_value() { # key value where
	check_key "$1" "$3"
	check_value "$2" "$3"
	if [ -z "${axis[$1]+x}" ]; then keys+=("$1"); axis[$1]=$2; else axis[$1]+=$'\n'$2; fi
}
for f in "${grid_files[@]}"; do
	[ -r "$f" ] || die "cannot read the grid '$f'"
	ln=0
	while IFS= read -r line || [ -n "$line" ]; do
		ln=$((ln + 1))
		line=${line%$'\r'}
		case $line in '' | '#'*) continue ;; *$'\t\t'* | *$'\t') die "$f:$ln: an empty value" ;; esac
		IFS=$'\t' read -r -a fields <<<"$line"
		[ ${#fields[@]} -ge 2 ] || die "$f:$ln: expected KEY<TAB>VALUE<TAB>..., got '$line'"
		[ -z "${axis[${fields[0]}]+x}" ] || die "$f:$ln: ${fields[0]}: already given"
		for v in "${fields[@]:1}"; do add_value "${fields[0]}" "$v" "$f:$ln"; done
	done <"$f"
done
for s in "${sets[@]}"; do
	case $s in *=*) ;; *) die "--set '$s': expected KEY=VALUE" ;; esac
	add_value "${s%%=*}" "${s#*=}" "--set $s"
done

# The rows: a header of keys, then a line of values a job.
row_keys=() rows=()
if [ -n "$rows_file" ]; then
	[ -r "$rows_file" ] || die "cannot read the rows '$rows_file'"
	ln=0
	while IFS= read -r line || [ -n "$line" ]; do
		ln=$((ln + 1))
		line=${line%$'\r'}
		case $line in '' | '#'*) continue ;; $'\t'* | *$'\t\t'* | *$'\t') die "$rows_file:$ln: an empty field" ;; esac
		IFS=$'\t' read -r -a fields <<<"$line"
		if [ ${#row_keys[@]} = 0 ]; then
			for k in "${fields[@]}"; do
				check_key "$k" "$rows_file:$ln"
				[ -z "${axis[$k]+x}" ] || die "$rows_file:$ln: $k: also in the grid"
			done
			row_keys=("${fields[@]}")
			continue
		fi
		[ ${#fields[@]} = ${#row_keys[@]} ] ||
			die "$rows_file:$ln: expected ${#row_keys[@]} values (one per key), got ${#fields[@]}"
		for v in "${fields[@]}"; do check_value "$v" "$rows_file:$ln"; done
		rows+=("$line")
	done <"$rows_file"
	[ ${#rows[@]} -gt 0 ] || die "$rows_file: expected a line of keys and at least one of values"
fi
[ ${#keys[@]} -gt 0 ] || [ ${#rows[@]} -gt 0 ] || die "no grid: give --grid, --set or --rows"

# Every combination, as TSV lines of values in the order of all_keys: the
# rows outermost, then the grid's keys, the first slowest.
all_keys=("${row_keys[@]}" "${keys[@]}")
if [ ${#rows[@]} -gt 0 ]; then combos=("${rows[@]}"); else combos=(""); fi
for k in "${keys[@]}"; do
	mapfile -t values <<<"${axis[$k]}"
	next=()
	for c in "${combos[@]}"; do
		for v in "${values[@]}"; do
			if [ -z "$c" ]; then next+=("$v"); else next+=("$c$tab$v"); fi
		done
	done
	combos=("${next[@]}")
done

# ---- the jobs: jobs.tsv (numbers and values) and jobs.cmd (commands) ----

q() { printf '%q' "$1"; }
if [ -e "$out/jobs.tsv" ] && [ $resume = 0 ] && [ $dry = 0 ]; then
	die "$out already holds a sweep: --resume to keep its jobs, or another --out"
fi
{
	printf 'job'; for k in "${all_keys[@]}"; do printf '\t%s' "$k"; done; printf '\n'
	n=0
	for c in "${combos[@]}"; do n=$((n + 1)); printf '%s\t%s\n' "$n" "$c"; done
} >"$work/jobs.tsv.new" || die "cannot write $out/jobs.tsv"
njobs=${#combos[@]}

: >"$work/jobs.cmd.new"
n=0
for c in "${combos[@]}"; do
	n=$((n + 1))
	dir=$out/jobs/$n
	IFS=$'\t' read -r -a vals <<<"$c"
	cmd="mkdir -p $(q "$dir") && $(q "$drape") run --headless --summary csv"
	for ((i = 0; i < ${#all_keys[@]}; i++)); do
		cmd+=" --set $(q "${all_keys[i]}=${vals[i]}")"
	done
	for a in "${extra[@]}"; do cmd+=" $(q "${a//\{job\}/$dir}")"; done
	cmd+=" $(q "$scene"); echo \"sweep-exit: \$? \$(uname -n)\" >&2"
	printf '%s\t%s\n' "$n" "$cmd" >>"$work/jobs.cmd.new"
done

if [ $dry = 1 ]; then
	cut -f2- "$work/jobs.cmd.new"
	exit 0
fi

# Which to run: all, or (--resume) those whose directory does not hold a
# finished run of the same values.
todo=()
n=0
for c in "${combos[@]}"; do
	n=$((n + 1))
	d=$out/jobs/$n
	if [ $resume = 1 ] && [ -r "$d/values" ] && [ "$(cat "$d/values")" = "$c" ] &&
		st=$(sed -n 's/^sweep-exit: \([0-9]*\).*/\1/p' "$d/stderr" 2>/dev/null | tail -n 1) &&
		[ -n "$st" ] && { [ $retry = 0 ] || [ "$st" = 0 ]; }; then
		continue
	fi
	todo+=("$n")
done
mv "$out/jobs.tsv.new" "$out/jobs.tsv" && mv "$out/jobs.cmd.new" "$out/jobs.cmd" ||
	die "cannot write $out/jobs.tsv"
mkdir -p "$out/jobs" || die "cannot create $out/jobs"
for n in "${todo[@]}"; do
	mkdir -p "$out/jobs/$n" && rm -f "$out/jobs/$n/stdout" "$out/jobs/$n/stderr" &&
		printf '%s\n' "${combos[n - 1]}" >"$out/jobs/$n/values" || die "cannot write $out/jobs/$n"
done

[ $quiet = 1 ] || echo "$prog: $njobs jobs, ${#todo[@]} to run ($((njobs - ${#todo[@]})) done already); $out" >&2

if [ $slurm = 1 ]; then
	list=$(printf '%s\n' "${todo[@]}" | paste -sd, -)
	cat <<EOF
#!/bin/bash
# A Slurm job array of the drape sweep in $out: one job a task.
# Submit with sbatch; when all have run: bench/sweep.sh --collect -o $out
#SBATCH --job-name=drape-sweep
#SBATCH --array=${list:-0}
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=1
#SBATCH --output=/dev/null
n=\$SLURM_ARRAY_TASK_ID
cmd=\$(awk -F'\\t' -v n="\$n" '\$1 == n { sub(/^[^\\t]*\\t/, ""); print; exit }' $(q "$out/jobs.cmd"))
[ -n "\$cmd" ] || { echo "no job \$n in $out/jobs.cmd" >&2; exit 2; }
mkdir -p $(q "$out")/jobs/"\$n"
eval "\$cmd" >$(q "$out")/jobs/"\$n"/stdout 2>$(q "$out")/jobs/"\$n"/stderr
EOF
	[ ${#todo[@]} -gt 0 ] || echo "$prog: every job is done: nothing to submit" >&2
	exit 0
fi

# ---- run them through GNU parallel ----

if [ ${#todo[@]} -gt 0 ]; then
	command -v parallel >/dev/null 2>&1 && parallel --version 2>/dev/null | grep -q 'GNU parallel' ||
		die "GNU parallel not found (Debian: sudo apt-get install -y parallel)"
	popts=(--colsep '\t' --results "$out/jobs/{1}/" --joblog "$out/joblog")
	[ -z "$jobs" ] || popts+=(-j "$jobs")
	if [ -n "$sshlogin$sshloginfile" ]; then
		[ -z "$sshlogin" ] || popts+=(-S "$sshlogin")
		[ -z "$sshloginfile" ] || popts+=(--sshloginfile "$sshloginfile")
		popts+=(--basefile "$scene")
		for f in "${basefiles[@]}"; do popts+=(--basefile "$(cd "$(dirname "$f")" && pwd)/$(basename "$f")"); done
		for f in "${returns[@]}"; do popts+=(--return "$out/jobs/{1}/$f"); done
	fi
	[ $quiet = 1 ] || ! [ -t 2 ] || popts+=(--bar)
	t0=$(date +%s.%N)
	awk -F'\t' -v todo=" ${todo[*]} " 'index(todo, " " $1 " ") > 0' "$out/jobs.cmd" |
		parallel "${popts[@]}" 'eval {2}'
	t1=$(date +%s.%N)
	[ $quiet = 1 ] || awk -v a="$t0" -v b="$t1" -v n="${#todo[@]}" \
		'BEGIN { printf "%s: ran %d jobs in %.1f s of wall time\n", "'"$prog"'", n, b - a }' >&2
fi
collect_results
report

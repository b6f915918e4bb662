#!/usr/bin/env bash
# Reproducing the chapter (issue 15): each reading of the chapter's
# collision method on its two scenes, the tablecloth (Fig. 12, 2 s) and
# the strip (Fig. 11, 3 s), all with the seed broad and narrow phases and
# RK4 but the reference (the shipped grid/ccd/slide).
#
# For each variant and scene it runs `drape run --headless --trace` (the
# energy, and the locked nodes, at every output frame; the summary's record
# for the time reached, the wall time and the share of the step time spent
# in the collision stages) and `drape check --every 1` (the intersecting
# triangle pairs of every output frame, by an audit apart from the narrow
# phase). A run is one run: they are deterministic, and the collision
# share is a ratio of two times of the same run.
#
# Data go to $BENCH_RESULTS/chapter.csv (a row a variant and scene) and
# chapter-series.csv (a row a frame: energy, locked nodes, pairs); with
# gnuplot, the chart to chapter.png and a text chart on stdout. See
# bench/README.md.
#
# It fails (exit 1) if the shipped chapter scenes (variant s4-path, run
# from scenes/chapter-*.scene) do not run to the end.
#
# Environment:
#   BENCH_CHAPTER_VARIANTS  which to run (default: all, in the order below)
#   BENCH_CHAPTER_SCENES    which of tablecloth strip (default both)
#   DRAPE, BENCH_SRCDIR, BENCH_RESULTS, GNUPLOT  as lib.sh says
set -u
prog=chapter.sh
here=$(cd "$(dirname "$0")" && pwd)
. "$here/lib.sh"

# label: the [collision] keys over the shipped scene's (drape-scene(5))
all="literal edges s4 q s4-path surface shared damped slide shipped"
variants=${BENCH_CHAPTER_VARIANTS:-$all}
scenes=${BENCH_CHAPTER_SCENES:-tablecloth strip}
seed="collision.broad=seed collision.narrow=seed"
settings() { # variant -> its edits, one a word
	case $1 in
	literal) echo "$seed collision.position=keep" ;;
	edges) echo "$seed collision.position=keep collision.segments=edges" ;;
	s4) echo "$seed collision.position=keep collision.obstacle_position=q" ;;
	q) echo "$seed collision.position=q" ;;
	s4-path) echo "$seed collision.position=keep collision.obstacle_position=q collision.segments=path" ;;
	surface) echo "$seed collision.position=keep collision.keep_velocity=surface" ;;
	shared) echo "$seed collision.position=keep collision.obstacle_position=q collision.seed_response=shared" ;;
	damped) echo "$seed collision.position=keep cloth.damping=20/s" ;;
	slide) echo "$seed collision.position=slide" ;;
	shipped) echo "" ;;
	*) die "BENCH_CHAPTER_VARIANTS are among '$all', not '$1'" ;;
	esac
}
describe() {
	case $1 in
	literal) echo "keep, eq. 16, lines r: path and edges (the chapter as drape read it)" ;;
	edges) echo "keep, lines r: the edges F-D only (eq. 5-6)" ;;
	s4) echo "keep; obstacles projected onto the surface (section 4)" ;;
	q) echo "the node at Q (the chapter's first try, section 3.2)" ;;
	s4-path) echo "keep; section 4; lines r: paths only (scenes/chapter-*.scene)" ;;
	surface) echo "keep, the kept node at the surface's velocity (departs from eq. 17)" ;;
	shared) echo "keep; section 4; impact shared with the triangle (departs from M >> m)" ;;
	damped) echo "literal, damping 20 /s (the scenes': 2 /s)" ;;
	slide) echo "drape's slide policy with the seed phases" ;;
	shipped) echo "rk4 with grid/ccd/slide, as the scenes shipped before the fast path (reference)" ;;
	esac
}
for v in $variants; do settings "$v" >/dev/null; done
for s in $scenes; do
	case $s in tablecloth | strip) ;; *) die "BENCH_CHAPTER_SCENES are tablecloth and strip, not '$s'" ;; esac
done

echo "the chapter's readings on its scenes: $version (commit $commit), $stamp"
echo "cpu: ${cpu:-?} x $ncpu, load $(load)"
echo

datf=$results/chapter.csv
serf=$results/chapter-series.csv
echo "variant,scene,status,t_end_s,duration_s,wall_s,stepping_s,collisions_s,collision_share_pct,frames,bad_frames,median_pairs,worst_pairs,locked_node_steps,lock_longest_steps,locked_kinetic_most_J,gravity_end_J" >"$datf"
echo "variant,scene,t_s,energy_J,kinetic_J,locked,locked_kinetic_J,pairs" >"$serf"
bad=0
for s in $scenes; do
	for v in $variants; do
		sets=()
		for e in $(settings "$v"); do sets+=(--set "$e"); done
		# s4-path is the shipped chapter scene itself (the same settings,
		# the same state hash as the --set edits of the scene); the others
		# edit the shipped scene taken with the chapter's rk4 and the grid
		# (chapter_scene: the shipped scenes run the fast path)
		scene=$(chapter_scene "$s")
		if [ "$v" = s4-path ]; then scene=$srcdir/scenes/chapter-$s.scene; sets=(); fi
		[ -t 2 ] && printf '\r  %s %s          ' "$s" "$v" >&2
		"$drape" run --headless --summary csv --trace "$tmp/trace.tsv" "${sets[@]}" \
			"$scene" >"$tmp/rec.csv" 2>"$tmp/err"
		rc=$?
		case $rc in 0 | 3) ;; *) bad=1; { echo "$prog: $s $v: drape run exited $rc:"; cat "$tmp/err"; } >&2; continue ;; esac
		"$drape" check --every 1 "${sets[@]}" "$scene" >"$tmp/check.tsv" 2>/dev/null
		crc=$?
		case $crc in 0 | 3 | 4) ;; *) bad=1; echo "$prog: $s $v: drape check exited $crc" >&2; continue ;; esac
		IFS=$'\037' read -r outcome tsim tdur wall stepping coll lns llong lke grav <<<"$("$here/csvcols.sh" -d $'\037' "$tmp/rec.csv" \
			outcome time.simulated time.end time.wall time.stepping time.collisions \
			locks.node_steps locks.longest locks.kinetic_most energy.gravity)"
		# pairs per audited frame: check lists the frames with any, and the
		# count of frames audited; the others had none
		frames=$(awk -F'\t' '$2 == "scene" { print $3 }' "$tmp/check.tsv")
		awk -F'\t' '$2 ~ /^t=/ { t = substr($2, 3); printf "%d %s\n", int(t * 50 + 0.5), $5 }' \
			"$tmp/check.tsv" >"$tmp/pairs"
		read -r badf med worst <<<"$(awk -v n="${frames:-0}" '{ v[++k] = $2 } END {
			for (i = k + 1; i <= n; i++) v[i] = 0
			# median of n values (k listed, n - k zeros)
			for (i = 1; i <= n; i++) a[i] = v[i]
			for (i = 2; i <= n; i++) { x = a[i]; j = i - 1; while (j >= 1 && a[j] > x) { a[j + 1] = a[j]; j-- } a[j + 1] = x }
			md = n == 0 ? 0 : (n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2)
			w = 0; for (i = 1; i <= n; i++) if (a[i] > w) w = a[i]
			print k + 0, md, w }' "$tmp/pairs")"
		status=finished
		[ "$outcome" = completed ] || status=failed
		# the chapter scenes must run to the end (issue 15; README,
		# "Reproducing the chapter")
		if [ "$v" = s4-path ] && [ $status != finished ]; then
			echo "$prog: scenes/chapter-$s.scene did not run to the end: $(head -n 1 "$tmp/err")" >&2
			bad=1
		fi
		share=$(awk -v c="$coll" -v s="$stepping" 'BEGIN { if (s > 0 && c != "") printf "%.1f", 100 * c / s; else print "-" }')
		echo "$v,$s,$status,$tsim,$tdur,$wall,$stepping,$coll,$share,${frames:-0},$badf,$med,$worst,${lns:-0},${llong:-0},${lke:-0},$grav" >>"$datf"
		# the series: the trace's rows, with the audit's pairs of that frame
		awk -v v="$v" -v s="$s" -v pf="$tmp/pairs" 'FILENAME == pf { p[$1] = $2; next }
		FNR > 1 { f = int($1 * 50 + 0.5); printf "%s,%s,%s,%s,%s,%s,%s,%d\n", v, s, $1, $3, $4, $5, $6, (f in p ? p[f] : 0) }' \
			"$tmp/pairs" "$tmp/trace.tsv" >>"$serf"
	done
done
[ -t 2 ] && printf '\r%60s\r' '' >&2

awk -F, 'NR > 1 {
	end = $3 == "finished" ? "finished" : sprintf("fails %.3g s", $4)
	printf "%-11s %-8s %-13s %7.1f %7s %8s %6s/%-5s %7s %10s %8s %10.3g\n", $2, $1, end, $6 / $4, $9, $12, $11, $10, $13, $14, $15, $17
}' "$datf" | { printf "%-11s %-8s %-13s %7s %7s %8s %12s %7s %10s %8s %10s\n" scene variant outcome "wall/s" "coll%" "median" "bad/frames" worst "locked" "longest" "gravity J"; cat; }
echo
for v in $variants; do printf '  %-8s %s\n' "$v" "$(describe "$v")"; done
cat <<EOF

outcome: finished, or the time of the blow-up; wall/s: wall seconds per
  simulated second; coll%: the collision stages' share of the step time;
  median, bad/frames, worst: intersecting triangle pairs per output frame
  (drape check --every 1: the median frame, the frames with any of those
  audited, the worst); locked: node-steps put back exactly at step k;
  longest: the most steps in a row one node stayed locked; gravity J:
  the cloth's gravitational energy at the end (relative to y = 0; the
  tablecloth's is about 7e-3 J resting on the box, under 1e-3 J once it
  has slid off onto the floor).
data: $datf, $serf
EOF

plot chapter.gp "$serf" "$results/chapter.png" "summary='$datf'; vars='$variants'; stamp='$stamp'" || bad=1
exit $bad

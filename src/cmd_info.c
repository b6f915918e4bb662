/* cmd_info.c: `drape info FILE`: what a replay holds and whether it is whole. */
#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include "cmd.h"
#include "integrate.h"
#include "replay.h"

/* Events and the last step's time, from every readable steps chunk's
 * statistics: its head, not its events, which are most of a long run's
 * file (the 166 MB tablecloth: 4.1 s to inflate them all, 0.3 s not). A
 * chunk whose events do not decode despite its CRC is found by events,
 * export and replay, which read them. */
static void
count_events(const struct replay *r, long *nev, double *t_end, size_t *unreadable)
{
	struct replay_steps ss;
	struct drape_err err;
	size_t i;

	*nev = 0;
	*t_end = 0;
	*unreadable = 0;
	for (i = 0; i < r->nchunks; i++) {
		if (!replay_is_steps(r->chunk[i].kind))
			continue;
		if (replay_read_step_stats(r, i, &ss, &err) != 0) {
			(*unreadable)++;
			continue;
		}
		*nev += (long)ss.nev;
		if (ss.count > 0 && ss.s[ss.count - 1].t > *t_end)
			*t_end = ss.s[ss.count - 1].t;
		replay_steps_free(&ss);
	}
}

/* The grid step of the first lossy frames chunk that reads, or 0: a
 * recording has one --precision for all its chunks (those that did not
 * fit the grid are exact). */
static double
lossy_precision(const struct replay *r)
{
	struct replay_frames fr;
	struct drape_err err;
	size_t i;

	for (i = 0; i < r->nchunks; i++)
		if (replay_frames_lossy(r->chunk[i].kind) && replay_read_frames(r, i, &fr, &err) == 0) {
			double p = fr.precision;

			replay_frames_free(&fr);
			return p;
		}
	return 0;
}

/* How the recorded run ended, when the header says it stopped early. */
static const char *
run_end(uint32_t flags)
{
	if (!(flags & REPLAY_CLOSED))
		return "";
	if (flags & REPLAY_END_ERROR)
		return "; the run ended there on an error";
	if (flags & REPLAY_END_BLOWUP)
		return "; the run ended there in a blow-up";
	if (flags & REPLAY_END_INTERRUPTED)
		return "; the run ended there on a signal";
	return "";
}

int
cmd_info(int argc, char **argv)
{
	struct replay r;
	struct drape_err err;
	const struct replay_meta *m;
	uint64_t bytes[REPLAY_KIND_MAX + 1] = { 0 }, frame_bytes, step_bytes;
	size_t i, unreadable;
	int k;
	long nev;
	double t_end, node_frames, precision;

	if (argc == 2 && strcmp(argv[1], "--help") == 0) {
		usage(stdout);
		return EXIT_OK;
	}
	if (argc >= 2 && argv[1][0] == '-')
		return cmd_usage_error("info", "unknown option '%s'", argv[1]);
	if (argc != 2) {
		return cmd_usage_error("info", "expected one replay file");
	}
	if (replay_open(&r, argv[1], &err) != 0) {
		fprintf(stderr, "drape info: %s\n", err.msg);
		return EXIT_USAGE;
	}
	m = &r.meta;
	for (i = 0; i < r.nchunks; i++)
		if (r.chunk[i].kind <= REPLAY_KIND_MAX)
			bytes[r.chunk[i].kind] += sizeof(struct replay_chunk_header) +
			    r.chunk[i].comp_len;
	count_events(&r, &nev, &t_end, &unreadable);
	frame_bytes = bytes[REPLAY_FRAMES] + bytes[REPLAY_FRAMES_Q] + bytes[REPLAY_FRAMES_GRID] +
	    bytes[REPLAY_FRAMES_GRID_Q];
	step_bytes = bytes[REPLAY_STEPS] + bytes[REPLAY_STEPS_DIGEST];
	precision = lossy_precision(&r);
	node_frames = (double)m->nodes * (double)(r.nframes > 0 ? r.nframes : 1);

	printf("replay       %s (version %u, %s%s)\n", argv[1], r.hdr.version,
	    !(r.hdr.flags & REPLAY_CLOSED) ? "not closed: the run was cut short" :
	    r.cut ? "closed cleanly, then cut short" : "closed cleanly", run_end(r.hdr.flags));
	printf("scene        %s (recorded from %s by drape %s)\n", m->name, m->path, m->version);
	printf("nodes        %u (%u triangles)\n", m->nodes, m->triangles);
	printf("options      --until %.9g --integrator %s --dt ", m->duration,
	    m->integrator >= 0 && m->integrator < INTEG_COUNT ?
	    integrator_name((enum integrator_kind)m->integrator) : "?");
	if (m->dt == 0)
		printf("auto (%.9g s)\n", m->dt_set);
	else
		printf("%.9g\n", m->dt);
	printf("steps        %ld\n", r.last_step + 1);
	printf("frames       %zu at %.9g per second", r.nframes, m->output_rate);
	if (precision > 0)
		printf(", rounded to %.9g m (within %.9g m of the run)", precision, precision / 2);
	printf("\n");
	printf("keyframes    %zu (every %ld steps)\n", r.nkeyframes, m->keyframe_every);
	printf("events       %ld", nev);
	/* how they are held: drape events recomputes the digests' */
	for (i = 0, k = 0; i < r.nchunks; i++)
		k |= r.chunk[i].kind == REPLAY_STEPS ? 1 :
		    r.chunk[i].kind == REPLAY_STEPS_DIGEST ? 2 : 0;
	printf("%s\n", k == 1 ? " (stored)" : k == 2 ? " (a digest: recomputed when read)" :
	    k == 3 ? " (some stored, some a digest)" : "");
	printf("simulated    %.9g s\n", t_end);
	printf("file size    %" PRIu64 " bytes: scene %" PRIu64 ", frames %" PRIu64 ", keyframes %"
	    PRIu64 ", steps (statistics and events) %" PRIu64 ", index %" PRIu64 "\n", r.len,
	    bytes[REPLAY_META], frame_bytes, bytes[REPLAY_KEYFRAME], step_bytes,
	    bytes[REPLAY_INDEX]);
	printf("bytes/node/frame %.3f in all, %.3f for the frames alone, %.3f without the steps "
	    "chunks (raw float32: 12)\n", (double)r.len / node_frames,
	    (double)frame_bytes / node_frames,
	    (double)(r.len - step_bytes) / node_frames);
	printf("integrity    ");
	if (r.nbad == 0 && !r.cut && unreadable == 0)
		printf("whole: %zu chunks\n", r.nchunks);
	else {
		printf("%zu whole chunks", r.nchunks);
		if (r.cut)
			printf("; cut at chunk %zu (byte %" PRIu64 ")", r.seen, r.cut_offset);
		if (r.nbad > 0) {
			printf("; %zu chunks with a bad CRC (", r.nbad);
			for (i = 0; i < r.nbad && i < sizeof r.bad_ordinal / sizeof r.bad_ordinal[0]; i++)
				printf("%s%" PRIu64, i ? ", " : "", r.bad_ordinal[i]);
			printf("%s)", r.nbad > i ? ", ..." : "");
		}
		if (unreadable > 0)
			printf("; %zu chunks that do not decode", unreadable);
		printf("\n");
	}
	replay_close(&r);
	if (fflush(stdout) != 0) {
		perror("drape info: stdout");
		return EXIT_RUNTIME;
	}
	return EXIT_OK;
}

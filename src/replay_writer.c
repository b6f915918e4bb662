/* replay_writer.c: writes a replay file (drape-replay(5)): the header,
 * the metadata, frames, keyframes and steps in chunks deflated on worker
 * threads, and the index at the close. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>
#include <zlib.h>

#include "clock.h"
#include "frame_codec.h"
#include "grow.h"
#include "outfile.h"
#include "replay_impl.h"

static int
write_fail(struct replay_writer *w, struct drape_err *err)
{
	err_set(err, "%s: write failed: %s", w->path, errno ? strerror(errno) : "I/O error");
	w->failed = true;
	return -1;
}

static int
put_bytes(struct replay_writer *w, const void *p, size_t n, struct drape_err *err)
{
	errno = 0;
	if (n > 0 && fwrite(p, 1, n, w->f) != n)
		return write_fail(w, err);
	w->bytes += n;
	return 0;
}

/* One zlib stream of raw into out (*out_len bytes, compressBound's). */
static int
deflate_all(unsigned char *out, uLongf *out_len, const unsigned char *raw, size_t raw_len,
    int level, int strategy)
{
	z_stream z;
	int rc;

	memset(&z, 0, sizeof z);
	if (deflateInit2(&z, level, Z_DEFLATED, 15, 8, strategy) != Z_OK)
		return -1;
	z.next_in = (Bytef *)(uintptr_t)raw;	/* zlib does not write through it */
	z.avail_in = (uInt)raw_len;
	z.next_out = out;
	z.avail_out = (uInt)*out_len;
	rc = deflate(&z, Z_FINISH);
	*out_len = z.total_out;
	deflateEnd(&z);
	return rc == Z_STREAM_END ? 0 : -1;
}

/*
 * A chunk is deflated on a thread of its own while the run goes on, and
 * written when JOBS later chunks have come, at a flush or at close, in the
 * order they came, so that every offset stays the caller's and the file is
 * the same as if it were written at once. Deflating was most of what
 * recording cost (the shipped tablecloth: +9.4 % of the run's
 * instructions, 86 % of them in deflate), and a run has a second core to
 * spare for it. A frames chunk and a keyframe come at the same step, so a
 * single chunk in flight would be waited for at once; JOBS chunks in
 * flight bound the memory to JOBS more chunks. Where no thread can be
 * made, a chunk is deflated at once.
 */
#define JOBS 4

struct replay_job {
	bool busy, threaded, provisional;
	pthread_t thread;
	uint32_t kind, count;
	uint64_t first_step;
	int level, strategy;
	long key;		/* the keyframe (w->koff) this chunk is, or -1 */
	unsigned char *raw, *z;
	size_t rawcap, zcap, raw_len;
	uLongf zlen;
	int rc;
};

struct replay_jobs {
	struct replay_job job[JOBS];
	size_t first, n;	/* in flight: job[first], then on, wrapping */
};

static void *
job_deflate(void *arg)
{
	struct replay_job *j = arg;

	/* the buffer may have doubled past what deflate_all's uInt holds */
	j->zlen = (uLongf)(j->zcap < UINT_MAX ? j->zcap : UINT_MAX);
	j->rc = deflate_all(j->z, &j->zlen, j->raw, j->raw_len, j->level, j->strategy);
	return NULL;
}

/* Waits for a job's thread, if it has one. */
static void
job_wait(struct replay_job *j)
{
	if (j->busy && j->threaded)
		pthread_join(j->thread, NULL);
	j->threaded = false;
}

/* Back to the start of the provisional chunks, if any, to write over
 * them; the file is cut after the next chunk (cut_if_due). */
static int
rewind_provisional(struct replay_writer *w, struct drape_err *err)
{
	if (w->prov_at == 0)
		return 0;
	errno = 0;
	if (fflush(w->f) != 0 || fseeko(w->f, (off_t)w->prov_at, SEEK_SET) != 0)
		return write_fail(w, err);
	w->bytes = w->prov_at;
	w->prov_at = 0;
	w->cut_due = true;
	return 0;
}

/* What is left of longer provisional chunks after the file's position
 * goes. */
static int
cut_if_due(struct replay_writer *w, struct drape_err *err)
{
	if (!w->cut_due)
		return 0;
	w->cut_due = false;
	errno = 0;
	if (fflush(w->f) != 0 || ftruncate(fileno(w->f), (off_t)w->bytes) != 0)
		return write_fail(w, err);
	return 0;
}

/* The oldest chunk in flight, deflated, appended and flushed to the file. */
static int
job_finish_one(struct replay_writer *w, struct drape_err *err)
{
	struct replay_jobs *q = w->jobs;
	struct replay_job *j = &q->job[q->first];
	struct replay_chunk_header h;
	uint32_t crc;

	job_wait(j);
	j->busy = false;
	q->first = (q->first + 1) % JOBS;
	q->n--;
	if (w->failed) {
		err_set(err, "%s: not written after an earlier write error", w->path);
		return -1;
	}
	if (j->rc != 0) {
		err_set(err, "%s: deflate failed", w->path);
		return -1;
	}
	/* a chunk of the run's data goes over the provisional ones */
	if (!j->provisional && rewind_provisional(w, err) != 0)
		return -1;
	if (j->key >= 0)
		w->koff[j->key] = w->bytes;
	memcpy(h.magic, chunk_magic, 4);
	h.kind = j->kind;
	h.first_step = j->first_step;
	h.count = j->count;
	h.comp_len = (uint32_t)j->zlen;
	h.raw_len = (uint32_t)j->raw_len;
	crc = replay_crc((uint32_t)crc32(0, Z_NULL, 0), &h, offsetof(struct replay_chunk_header, crc));
	h.crc = replay_crc(crc, j->z, j->zlen);
	if (put_bytes(w, &h, sizeof h, err) != 0 || put_bytes(w, j->z, j->zlen, err) != 0)
		return -1;
	errno = 0;
	if (fflush(w->f) != 0)
		return write_fail(w, err);
	return cut_if_due(w, err);
}

/* Every chunk in flight in the file (or, after an error, given up). */
static int
job_finish(struct replay_writer *w, struct drape_err *err)
{
	int rc = 0;

	while (w->jobs != NULL && w->jobs->n > 0)
		if (job_finish_one(w, rc == 0 ? err : NULL) != 0)
			rc = -1;
	return rc;
}

/* Appends raw as one chunk, deflated beside the run (see struct
 * replay_jobs); w->next_key says which keyframe it is. */
static int
write_chunk(struct replay_writer *w, uint32_t kind, uint64_t first_step, uint32_t count,
    const unsigned char *raw, size_t raw_len, int level, struct drape_err *err)
{
	struct replay_jobs *q = w->jobs;
	struct replay_job *j;
	long key = w->next_key;
	size_t zcap;

	w->next_key = -1;
	if (w->failed) {
		w->next_provisional = false;
		err_set(err, "%s: not written after an earlier write error", w->path);
		return -1;
	}
	if (raw_len > UINT32_MAX) {
		err_set(err, "%s: a chunk of %zu bytes is too large", w->path, raw_len);
		return -1;
	}
	if (q->n == JOBS && job_finish_one(w, err) != 0)
		return -1;
	j = &q->job[(q->first + q->n) % JOBS];
	zcap = compressBound((uLong)raw_len);
	if (grow_array((void **)&j->raw, &j->rawcap, raw_len + 1, 1) != 0 ||
	    grow_array((void **)&j->z, &j->zcap, zcap, 1) != 0) {
		err_set(err, "%s: out of memory", w->path);
		return -1;
	}
	if (raw_len > 0)
		memcpy(j->raw, raw, raw_len);
	j->raw_len = raw_len;
	j->kind = kind;
	j->first_step = first_step;
	j->count = count;
	j->level = level;
	j->strategy = replay_is_steps(kind) ? STEPS_STRATEGY :
	    replay_is_frames(kind) ? FRAMES_STRATEGY : Z_DEFAULT_STRATEGY;
	j->key = key;
	j->provisional = w->next_provisional;
	w->next_provisional = false;
	j->busy = true;
	q->n++;
	j->threaded = pthread_create(&j->thread, NULL, job_deflate, j) == 0;
	if (!j->threaded)
		job_deflate(j);
	return 0;
}

static void
jobs_free(struct replay_jobs *q)
{
	size_t k;

	if (q == NULL)
		return;
	for (k = 0; k < JOBS; k++) {
		job_wait(&q->job[k]);
		free(q->job[k].raw);
		free(q->job[k].z);
	}
	free(q);
}

/* write_chunk, and the chunk in the file before it returns. */
static int
write_chunk_now(struct replay_writer *w, uint32_t kind, uint64_t first_step, uint32_t count,
    const unsigned char *raw, size_t raw_len, int level, struct drape_err *err)
{
	if (write_chunk(w, kind, first_step, count, raw, raw_len, level, err) != 0)
		return -1;
	return job_finish(w, err);
}

static int
write_header(struct replay_writer *w, uint32_t flags, uint64_t index_offset,
    struct drape_err *err)
{
	struct replay_file_header h;

	memset(&h, 0, sizeof h);
	memcpy(h.magic, file_magic, 8);
	h.version = REPLAY_VERSION;
	h.flags = flags;
	h.nodes = w->nodes;
	h.triangles = w->triangles;
	h.index_offset = index_offset;
	h.crc = replay_header_crc(&h);
	errno = 0;
	if (fwrite(&h, sizeof h, 1, w->f) != 1 || fflush(w->f) != 0)
		return write_fail(w, err);
	return 0;
}

static int
write_meta(struct replay_writer *w, const struct replay_meta *m, struct drape_err *err)
{
	size_t ln = strlen(m->name), lp = strlen(m->path), lt = strlen(m->text);
	size_t lv = strlen(m->version);
	size_t len = META_FIXED + ln + lp + lt + lv + 12 * (size_t)m->triangles, o = META_FIXED;
	unsigned char *p;

	if (ln + lp + lt + lv > MAX_META_RAW / 2) {
		err_set(err, "%s: the scene text is too long to record", w->path);
		return -1;
	}
	if (grow_array((void **)&w->buf, &w->bufcap, len, 1) != 0) {
		err_set(err, "%s: out of memory", w->path);
		return -1;
	}
	p = w->buf;
	memset(p, 0, META_FIXED);
	put32(p, m->nodes);
	put32(p + 4, m->triangles);
	put32(p + 8, (uint32_t)m->integrator);
	put64(p + 16, dbits(m->duration));
	put64(p + 24, dbits(m->dt));
	put64(p + 32, dbits(m->dt_set));
	put64(p + 40, dbits(m->output_rate));
	put64(p + 48, (uint64_t)m->keyframe_every);
	put32(p + 56, (uint32_t)ln);
	put32(p + 60, (uint32_t)lp);
	put32(p + 64, (uint32_t)lt);
	put32(p + 68, (uint32_t)lv);
	memcpy(p + o, m->name, ln);
	o += ln;
	memcpy(p + o, m->path, lp);
	o += lp;
	memcpy(p + o, m->text, lt);
	o += lt;
	memcpy(p + o, m->version, lv);
	o += lv;
	memcpy(p + o, m->tri, 12 * (size_t)m->triangles);
	return write_chunk_now(w, REPLAY_META, 0, 1, p, len, Z_BEST_COMPRESSION, err);
}

/* Everything the writer holds but its file, freed; the writer zeroed. */
static void
writer_release(struct replay_writer *w)
{
	free(w->path);
	free(w->fx);
	free(w->fq);
	free(w->fstep);
	free(w->ft);
	free(w->steps);
	free(w->ev);
	free(w->kstep);
	free(w->koff);
	free(w->buf);
	jobs_free(w->jobs);
	memset(w, 0, sizeof *w);
}

int
replay_writer_open(struct replay_writer *w, const char *path, const struct replay_meta *m,
    struct drape_err *err)
{
	size_t n3 = 3 * (size_t)m->nodes;
	const char *what;

	memset(w, 0, sizeof *w);
	w->nodes = m->nodes;
	w->width = m->width >= 1 && m->width <= m->nodes ? m->width : m->nodes;
	w->triangles = m->triangles;
	w->keyframe_every = m->keyframe_every;
	w->events_stored = m->events_stored;
	w->digest = REPLAY_DIGEST_SEED;
	w->precision = m->precision > 0 && isfinite(m->precision) ? m->precision : 0;
	w->q_fits = true;
	w->frames_per_chunk = FRAMES_PER_CHUNK;
	w->steps_per_chunk = STEPS_PER_CHUNK;
	w->flush_every = REPLAY_FLUSH_SECONDS;
	w->clock = clock_seconds;
	w->last_flush = w->clock();
	if ((w->path = malloc(strlen(path) + 1)) == NULL ||
	    (w->fx = malloc(FRAMES_PER_CHUNK * n3 * sizeof *w->fx)) == NULL ||
	    (w->precision > 0 &&
	    (w->fq = malloc(FRAMES_PER_CHUNK * n3 * sizeof *w->fq)) == NULL) ||
	    (w->fstep = malloc(FRAMES_PER_CHUNK * sizeof *w->fstep)) == NULL ||
	    (w->ft = malloc(FRAMES_PER_CHUNK * sizeof *w->ft)) == NULL ||
	    (w->steps = malloc(STEPS_PER_CHUNK * sizeof *w->steps)) == NULL ||
	    (w->jobs = calloc(1, sizeof *w->jobs)) == NULL) {
		err_set(err, "%s: out of memory", path);
		goto fail;
	}
	w->next_key = -1;
	strcpy(w->path, path);
	/* the header is written again at the close, at the file's start */
	if ((what = outfile_unseekable(path)) != NULL) {
		err_set(err, "%s: %s cannot hold a replay, whose header is written last, at its "
		    "start; expected a regular file", path, what);
		goto fail;
	}
	if ((w->f = fopen(path, "wb")) == NULL) {
		err_set(err, "%s: cannot create: %s", path, strerror(errno));
		goto fail;
	}
	if (!outfile_seeks(w->f)) {
		err_set(err, "%s: cannot seek in it (%s), and a replay's header is written last, "
		    "at its start; expected a regular file", path, strerror(errno));
		goto fail;
	}
	if (write_header(w, 0, 0, err) != 0)
		goto fail;
	/* offsets count from the file's start (the index's and the
	 * header's; they were 64 short, the header's own length, before
	 * replay version 3's writer) */
	w->bytes = sizeof(struct replay_file_header);
	if (write_meta(w, m, err) != 0)
		goto fail;
	return 0;
fail:
	if (w->f != NULL) {
		/* what it made, not /dev/full or a FIFO it was given */
		struct stat sb;
		bool made = fstat(fileno(w->f), &sb) == 0 && S_ISREG(sb.st_mode);

		fclose(w->f);
		if (made)
			remove(path);
	}
	writer_release(w);
	return -1;
}

static int flush_steps(struct replay_writer *w, bool keep, struct drape_err *err);
static int flush_if_due(struct replay_writer *w, struct drape_err *err);

/*
 * Lossy frames (--precision p): each coordinate as the whole number of
 * grid steps nearest it, so that a frame read back is within p/2 of the
 * run's position (and float32's own rounding of that). Moving cloth fills
 * float32's mantissa with bits no predictor guesses (about 7 bytes a node
 * a frame are left after frames_encode on the tablecloth); on a grid of a
 * few micrometres the residuals are a byte or two. A chunk with a value
 * that does not fit in an int32 of grid steps (a cloth thrown kilometres,
 * a step of a nanometre) is written exact instead: nothing is lost.
 */
static int
flush_frames(struct replay_writer *w, bool keep, struct drape_err *err)
{
	size_t n3 = 3 * (size_t)w->nodes, k = w->nframes, i;
	bool lossy = w->precision > 0 && w->q_fits;
	size_t head = lossy ? 16 : 8, len = head + k * (16 + 4 * n3);
	unsigned char *p;
	uint32_t *tmp;
	int rc;

	if (k == 0)
		return 0;
	if (grow_array((void **)&w->buf, &w->bufcap, len, 1) != 0 || (tmp = malloc(k * n3 * 4)) == NULL) {
		err_set(err, "%s: out of memory", w->path);
		return -1;
	}
	p = w->buf;
	if (lossy)
		put64(p, dbits(w->precision));
	put32(p + head - 8, w->width);
	put32(p + head - 4, 0);
	for (i = 0; i < k; i++) {
		put64(p + head + 8 * i, w->fstep[i]);
		put64(p + head + 8 * (k + i), dbits(w->ft[i]));
	}
	if (lossy)
		frames_encode_grid_q(w->fq, k, w->nodes, w->width, tmp, p + head + 16 * k);
	else
		frames_encode_grid(w->fx, k, w->nodes, w->width, tmp, p + head + 16 * k);
	free(tmp);
	w->next_provisional = keep;
	rc = write_chunk(w, lossy ? REPLAY_FRAMES_GRID_Q : REPLAY_FRAMES_GRID, w->fstep[0],
	    (uint32_t)k, p, len, FRAMES_LEVEL, err);
	if (!keep) {
		w->nframes = 0;
		w->q_fits = true;
	}
	return rc;
}

static int
write_frame_once(struct replay_writer *w, long step, double t, const double *x,
    struct drape_err *err)
{
	size_t n3 = 3 * (size_t)w->nodes, i;
	float *f = w->fx + w->nframes * n3;

	for (i = 0; i < n3; i++)
		f[i] = (float)x[i];
	if (w->precision > 0) {
		int32_t *q = w->fq + w->nframes * n3;

		for (i = 0; i < n3; i++) {
			double g = nearbyint(x[i] / w->precision);

			/* a NaN fails both tests */
			if (!(g >= -2147483647.0 && g <= 2147483647.0)) {
				w->q_fits = false;
				g = 0;
			}
			q[i] = (int32_t)g;
		}
	}
	w->fstep[w->nframes] = (uint64_t)step;
	w->ft[w->nframes] = t;
	/* a full frames chunk takes the steps so far along: a run of long
	 * steps (the fast path's 50 a chunk of frames) would otherwise leave
	 * them all to one chunk deflated as the run closes, after it (the
	 * shipped tablecloth's 2.1 MB of events: 22 ms, a run's 3 %); short
	 * steps fill their chunks first */
	if (++w->nframes == w->frames_per_chunk)
		return flush_frames(w, false, err) != 0 ? -1 : flush_steps(w, false, err);
	return flush_if_due(w, err);
}

static int
write_keyframe_once(struct replay_writer *w, long step, double t, double dt, const double *y,
    const double *hist, uint64_t hash, struct drape_err *err)
{
	size_t n6 = 6 * (size_t)w->nodes, len = 32 + 8 * n6 * (hist != NULL ? 2 : 1);
	size_t kcap;

	if (grow_array((void **)&w->buf, &w->bufcap, len, 1) != 0) {
		err_set(err, "%s: out of memory", w->path);
		return -1;
	}
	/* kstep and koff grow together: koff's capacity is the one kept */
	kcap = w->keycap;
	if (grow_array((void **)&w->kstep, &kcap, w->nkey + 1, sizeof *w->kstep) != 0 ||
	    grow_array((void **)&w->koff, &w->keycap, w->nkey + 1, sizeof *w->koff) != 0) {
		err_set(err, "%s: out of memory", w->path);
		return -1;
	}
	put64(w->buf, (uint64_t)step);
	put64(w->buf + 8, dbits(t));
	put64(w->buf + 16, dbits(dt));
	put64(w->buf + 24, hash);
	codec_shuffle((const unsigned char *)y, w->buf + 32, n6, 8);
	if (hist != NULL)
		codec_shuffle((const unsigned char *)hist, w->buf + 32 + 8 * n6, n6, 8);
	/* its offset is known when it is written (job_finish) */
	w->next_key = (long)w->nkey;
	if (write_chunk(w, REPLAY_KEYFRAME, (uint64_t)step, 1, w->buf, len, Z_DEFAULT_COMPRESSION,
	    err) != 0)
		return -1;
	w->kstep[w->nkey] = (uint64_t)step;
	w->koff[w->nkey++] = UINT64_MAX;
	return 0;
}

_Static_assert(NSTAT == 11 + HASH_HIST + STAT_COUNT, "NSTAT counts replay_stat_words");

static void
pack_events(const struct contact_event *ev, size_t nev, uint64_t first_step, unsigned char *out,
    uint32_t *tmp32, uint64_t *tmp64)
{
	size_t i, c;

	for (c = 0; c < 2; c++) {
		for (i = 0; i < nev; i++)
			tmp32[i] = c == 0 ? (uint32_t)((uint64_t)ev[i].step - first_step) :
			    (uint32_t)ev[i].node;
		codec_delta_u32(tmp32, nev);
		codec_shuffle((const unsigned char *)tmp32, out, nev, 4);
		out += 4 * nev;
	}
	for (i = 0; i < nev; i++)
		*out++ = (unsigned char)ev[i].type;
	for (c = 0; c < EVENT_WORDS; c++) {
		size_t size = c < 2 ? 4 : 8;

		for (i = 0; i < nev; i++) {
			uint64_t w = replay_event_word(&ev[i], c);

			if (size == 4)
				tmp32[i] = (uint32_t)w;
			else
				tmp64[i] = w;
		}
		if (size == 4)
			codec_shuffle((const unsigned char *)tmp32, out, nev, 4);
		else
			codec_shuffle((const unsigned char *)tmp64, out, nev, 8);
		out += size * nev;
	}
}

static int
flush_steps(struct replay_writer *w, bool keep, struct drape_err *err)
{
	uint32_t kind = w->events_stored ? REPLAY_STEPS : REPLAY_STEPS_DIGEST;
	size_t k = w->nsteps, nev = w->nev, i, head = replay_steps_head(kind);
	size_t nstored = w->events_stored ? nev : 0;
	size_t len = head + 8 * NSTAT * k + EVENT_BYTES * nstored;
	uint64_t *words = NULL, *tmp64 = NULL, first;
	uint32_t *tmp32 = NULL;
	int rc = -1, c;

	if (k == 0)
		return 0;
	first = (uint64_t)w->steps[0].step;
	if (grow_array((void **)&w->buf, &w->bufcap, len, 1) != 0 ||
	    (words = malloc(k * NSTAT * sizeof *words)) == NULL ||
	    (tmp32 = malloc((nstored + 1) * sizeof *tmp32)) == NULL ||
	    (tmp64 = malloc((nstored > k ? nstored : k) * sizeof *tmp64)) == NULL) {
		err_set(err, "%s: out of memory", w->path);
		goto out;
	}
	put32(w->buf, (uint32_t)nev);
	put32(w->buf + 4, 0);
	if (!w->events_stored)
		put64(w->buf + 8, w->digest);
	for (i = 0; i < k; i++) {
		uint64_t row[NSTAT];

		replay_stat_words(&w->steps[i], row);
		for (c = 0; c < NSTAT; c++)
			words[(size_t)c * k + i] = row[c];
	}
	for (c = 0; c < NSTAT; c++)
		replay_pack_col64(words + (size_t)c * k, k, w->buf + head + 8 * (size_t)c * k);
	if (w->events_stored)
		pack_events(w->ev, nev, first, w->buf + head + 8 * NSTAT * k, tmp32, tmp64);
	w->next_provisional = keep;
	rc = write_chunk(w, kind, first, (uint32_t)k, w->buf, len, STEPS_LEVEL, err);
out:
	free(words);
	free(tmp32);
	free(tmp64);
	if (!keep) {
		w->nsteps = 0;
		w->nev = 0;
		w->digest = REPLAY_DIGEST_SEED;
	}
	return rc;
}

static int
write_step_once(struct replay_writer *w, const struct replay_step *s,
    const struct contact_event *ev, struct drape_err *err)
{
	size_t nev = (size_t)s->nev;

	if (!w->events_stored)
		w->digest = replay_digest_events(w->digest, ev, nev);
	else if (grow_array((void **)&w->ev, &w->evcap, w->nev + nev, sizeof *w->ev) != 0) {
		err_set(err, "%s: out of memory", w->path);
		return -1;
	}
	if (nev > 0 && w->events_stored)
		memcpy(w->ev + w->nev, ev, nev * sizeof *ev);
	w->nev += nev;
	w->steps[w->nsteps++] = *s;
	if (w->nsteps == w->steps_per_chunk || w->nev >= EVENTS_PER_CHUNK)
		return flush_steps(w, false, err);
	return flush_if_due(w, err);
}

static int
writer_flush_once(struct replay_writer *w, struct drape_err *err)
{
	if (w->failed) {
		err_set(err, "%s: not written after an earlier write error", w->path);
		return -1;
	}
	if (w->clock != NULL)
		w->last_flush = w->clock();
	return flush_frames(w, false, err) != 0 || flush_steps(w, false, err) != 0 ||
	    job_finish(w, err) != 0 ? -1 : 0;
}

/* The wall-clock flush: what is pending goes out once flush_every seconds
 * have passed since the last time, as provisional chunks (struct
 * replay_writer): the chunks in flight first, then the pending frames
 * and steps, deflated here and kept pending. Once a second at most. */
static int
flush_if_due(struct replay_writer *w, struct drape_err *err)
{
	if (w->clock == NULL || w->nframes + w->nsteps == 0 ||
	    !(w->clock() - w->last_flush >= w->flush_every))
		return 0;
	w->last_flush = w->clock();
	/* over the last provisional chunks, if the run's chunks have not
	 * gone over them yet */
	if (job_finish(w, err) != 0 || rewind_provisional(w, err) != 0)
		return -1;
	w->prov_at = w->bytes;
	w->cut_due = true;
	if (flush_frames(w, true, err) != 0 || flush_steps(w, true, err) != 0 ||
	    job_finish(w, err) != 0)
		return -1;
	return cut_if_due(w, err);	/* no provisional chunk did */
}

/* After any error the writer is failed: it writes nothing more, and its
 * close does not mark the file closed cleanly (frames or steps may be
 * missing from it, which a clean close would hide). */
static int
failed_if(struct replay_writer *w, int rc)
{
	if (rc != 0)
		w->failed = true;
	return rc;
}

int
replay_write_frame(struct replay_writer *w, long step, double t, const double *x,
    struct drape_err *err)
{
	return failed_if(w, write_frame_once(w, step, t, x, err));
}

int
replay_write_keyframe(struct replay_writer *w, long step, double t, double dt, const double *y,
    const double *hist, uint64_t hash, struct drape_err *err)
{
	return failed_if(w, write_keyframe_once(w, step, t, dt, y, hist, hash, err));
}

int
replay_write_step(struct replay_writer *w, const struct replay_step *s,
    const struct contact_event *ev, struct drape_err *err)
{
	return failed_if(w, write_step_once(w, s, ev, err));
}

int
replay_writer_flush(struct replay_writer *w, struct drape_err *err)
{
	return failed_if(w, writer_flush_once(w, err));
}

int
replay_writer_close(struct replay_writer *w, struct drape_err *err)
{
	struct drape_err e2;
	uint64_t index_off;
	size_t i;
	int rc = 0;

	if (w->f == NULL)
		return 0;
	if (!w->failed) {
		if (flush_frames(w, false, err) != 0 || flush_steps(w, false, err) != 0 || job_finish(w, err) != 0)
			rc = -1;
	}
	job_finish(w, NULL);	/* given up after an error: the threads joined */
	if (rc == 0 && !w->failed) {
		index_off = w->bytes;
		if (grow_array((void **)&w->buf, &w->bufcap, 16 * w->nkey + 1, 1) != 0) {
			err_set(err, "%s: out of memory", w->path);
			rc = -1;
		} else {
			for (i = 0; i < w->nkey; i++) {
				put64(w->buf + 16 * i, w->kstep[i]);
				put64(w->buf + 16 * i + 8, w->koff[i]);
			}
			errno = 0;
			if (write_chunk_now(w, REPLAY_INDEX, 0, (uint32_t)w->nkey, w->buf, 16 * w->nkey,
			    Z_BEST_COMPRESSION, err) != 0)
				rc = -1;
			else if (fseek(w->f, 0, SEEK_SET) != 0)
				rc = write_fail(w, err);
			else if (write_header(w, REPLAY_CLOSED | (w->end & REPLAY_END_MASK), index_off,
			    err) != 0)
				rc = -1;
		}
	}
	errno = 0;
	if (fclose(w->f) != 0 && rc == 0) {
		err_set(&e2, "%s: write failed: %s", w->path, errno ? strerror(errno) : "I/O error");
		if (err != NULL)
			*err = e2;
		rc = -1;
	}
	writer_release(w);
	return rc;
}

void
replay_writer_discard(struct replay_writer *w)
{
	struct stat sb;
	char *path;
	bool made;

	if (w->f == NULL)
		return;
	made = fstat(fileno(w->f), &sb) == 0 && S_ISREG(sb.st_mode);
	path = made ? malloc(strlen(w->path) + 1) : NULL;
	if (path != NULL)
		strcpy(path, w->path);
	w->failed = true;	/* nothing more written, the header not marked */
	replay_writer_close(w, NULL);
	if (path != NULL)
		remove(path);
	free(path);
}

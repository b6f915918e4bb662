/* replay.c: the replay file format: chunk framing and CRCs, the payloads'
 * packing, the writer and the hostile-file reader (drape-replay(5)). */
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
#include "outfile.h"
#include "replay.h"

#define FRAMES_PER_CHUNK 25	/* half a second at 50 frames/s */
#define STEPS_PER_CHUNK 256
#define EVENTS_PER_CHUNK (1u << 16)	/* flush the steps early past this: a chunk
					 * decoded (about 12 MB at most) is what the
					 * replay viewer holds */
/* Steps chunks are most of a file with contacts, and their columns' low
 * bytes are noise: run-length deflate is faster and smaller than level 1,
 * and level 6 saves only 2 % more for three times the overhead (the whole
 * tablecloth, a 17 s run: 166 MB and +3.6 s with run lengths, 170 MB and
 * +4.6 s at level 1, 163 MB and +11 s at level 6). */
#define STEPS_LEVEL 1
#define STEPS_STRATEGY Z_RLE
/* Frames chunks' residuals are runs of zero high bytes and noisy low ones,
 * where level 9's long match searches find little: on the shipped
 * tablecloth's frames (kind 7), zlib from Python on the same chunks, run
 * lengths take 6.2 ms and 371,097 bytes, level 9 164 ms and 370,902,
 * level 6 filtered 21 ms and 372,525. */
#define FRAMES_LEVEL 1
#define FRAMES_STRATEGY Z_RLE

/* Bounds a reader holds a file to, before it allocates anything. */
#define MAX_NODES (1u << 22)
#define MAX_TRIANGLES (1u << 23)
#define MAX_FRAMES_CHUNK 4096u
#define MAX_STEPS_CHUNK 65536u
#define MAX_META_RAW (64u << 20)
#define MAX_STEPS_RAW (512u << 20)
#define MAX_INDEX (1u << 24)

#define META_FIXED 72		/* bytes before the strings */
#define NSTAT 33		/* 8-byte words of statistics per step */
#define EVENT_BYTES 81		/* one event's columns: 4 * 4 + 1 + 8 * 8 */

static const char file_magic[REPLAY_MAGIC_LEN] = { 'D', 'R', 'A', 'P', 'E', 'R', 'P', 'L' };
static const char chunk_magic[4] = { 'C', 'H', 'N', 'K' };

/* ---- little helpers ---- */

static void put32(unsigned char *p, uint32_t v) { memcpy(p, &v, 4); }
static void put64(unsigned char *p, uint64_t v) { memcpy(p, &v, 8); }
static uint32_t get32(const unsigned char *p) { uint32_t v; memcpy(&v, p, 4); return v; }
static uint64_t get64(const unsigned char *p) { uint64_t v; memcpy(&v, p, 8); return v; }
static uint64_t dbits(double d) { uint64_t v; memcpy(&v, &d, 8); return v; }
static double bitsd(uint64_t v) { double d; memcpy(&d, &v, 8); return d; }

static uint32_t
crc_of(uint32_t crc, const void *p, size_t n)
{
	const unsigned char *b = p;

	while (n > 0) {	/* zlib takes uInt lengths */
		uInt k = n > (1u << 30) ? 1u << 30 : (uInt)n;

		crc = (uint32_t)crc32(crc, b, k);
		b += k;
		n -= k;
	}
	return crc;
}

static uint32_t
header_crc(const struct replay_file_header *h)
{
	return crc_of((uint32_t)crc32(0, Z_NULL, 0), h, offsetof(struct replay_file_header, crc));
}

static int
grow(unsigned char **buf, size_t *cap, size_t need)
{
	unsigned char *p;

	if (need <= *cap)
		return 0;
	if ((p = realloc(*buf, need)) == NULL)
		return -1;
	*buf = p;
	*cap = need;
	return 0;
}

static uint64_t zz64(uint64_t d) { return (d << 1) ^ (uint64_t)-(int64_t)(d >> 63); }
static uint64_t unzz64(uint64_t z) { return (z >> 1) ^ (uint64_t)-(int64_t)(z & 1); }

/* A column of n 8-byte words, delta-coded down the column, shuffled. */
static void
pack_col64(uint64_t *w, size_t n, unsigned char *out)
{
	uint64_t prev = 0, cur;
	size_t i;

	for (i = 0; i < n; i++) {
		cur = w[i];
		w[i] = zz64(cur - prev);
		prev = cur;
	}
	codec_shuffle((const unsigned char *)w, out, n, 8);
}

static void
unpack_col64(const unsigned char *in, size_t n, uint64_t *w)
{
	uint64_t prev = 0;
	size_t i;

	codec_unshuffle(in, (unsigned char *)w, n, 8);
	for (i = 0; i < n; i++) {
		prev += unzz64(w[i]);
		w[i] = prev;
	}
}

/* ---- writer ---- */

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

	j->zlen = (uLongf)j->zcap;
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
	crc = crc_of((uint32_t)crc32(0, Z_NULL, 0), &h, offsetof(struct replay_chunk_header, crc));
	h.crc = crc_of(crc, j->z, j->zlen);
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
	if (grow(&j->raw, &j->rawcap, raw_len + 1) != 0 || grow(&j->z, &j->zcap, zcap) != 0) {
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
	h.crc = header_crc(&h);
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
	if (grow(&w->buf, &w->bufcap, len) != 0) {
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
	free(w->path);
	free(w->fx);
	free(w->fq);
	free(w->fstep);
	free(w->ft);
	free(w->steps);
	free(w->buf);
	jobs_free(w->jobs);
	memset(w, 0, sizeof *w);
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
	if (grow(&w->buf, &w->bufcap, len) != 0 || (tmp = malloc(k * n3 * 4)) == NULL) {
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

	if (grow(&w->buf, &w->bufcap, len) != 0) {
		err_set(err, "%s: out of memory", w->path);
		return -1;
	}
	if (w->nkey == w->keycap) {
		size_t cap = w->keycap ? 2 * w->keycap : 16;
		uint64_t *a = realloc(w->kstep, cap * sizeof *a), *b;

		if (a == NULL) {
			err_set(err, "%s: out of memory", w->path);
			return -1;
		}
		w->kstep = a;
		if ((b = realloc(w->koff, cap * sizeof *b)) == NULL) {
			err_set(err, "%s: out of memory", w->path);
			return -1;
		}
		w->koff = b;
		w->keycap = cap;
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

/* The statistics of step s as NSTAT words, in the order drape-replay(5) lists. */
static void
stat_words(const struct replay_step *s, uint64_t *w)
{
	const struct collide_stats *c = &s->col;
	const struct hash_stats *h = &c->hash;
	int k, i = 0;

	w[i++] = (uint64_t)s->step;
	w[i++] = dbits(s->t);
	w[i++] = dbits(s->dt);
	w[i++] = dbits(c->cell);
	w[i++] = (uint64_t)h->entries;
	w[i++] = (uint64_t)h->cubes;
	w[i++] = (uint64_t)h->shared;
	w[i++] = dbits(h->load);
	w[i++] = dbits(h->probe_mean);
	w[i++] = (uint64_t)h->probe_max;
	for (k = 0; k < HASH_HIST; k++)
		w[i++] = (uint64_t)h->hist[k];
	for (k = 0; k < STAT_COUNT; k++)	/* in stat_field's order */
		w[i++] = (uint64_t)c->n[k];
	w[i++] = (uint64_t)s->nev;
}

static void
stat_from_words(const uint64_t *w, struct replay_step *s)
{
	struct collide_stats *c = &s->col;
	struct hash_stats *h = &c->hash;
	int k, i = 0;

	memset(s, 0, sizeof *s);
	s->step = (long)w[i++];
	s->t = bitsd(w[i++]);
	s->dt = bitsd(w[i++]);
	c->cell = bitsd(w[i++]);
	h->entries = (long)w[i++];
	h->cubes = (long)w[i++];
	h->shared = (long)w[i++];
	h->load = bitsd(w[i++]);
	h->probe_mean = bitsd(w[i++]);
	h->probe_max = (int)w[i++];
	for (k = 0; k < HASH_HIST; k++)
		h->hist[k] = (long)w[i++];
	for (k = 0; k < STAT_COUNT; k++)
		c->n[k] = (long)w[i++];
	s->nev = (long)w[i++];
}

_Static_assert(NSTAT == 11 + HASH_HIST + STAT_COUNT, "NSTAT counts stat_words");

/* Event columns: step offset and node (u32, delta-coded down the column),
 * type (u8), other and obstacle (u32, as they are), then q, n, vn_before,
 * vn_after (f64 bit patterns): EVENT_BYTES in all, each column byte-shuffled.
 * (Predicting a value from the same node's previous event was tried: the
 * doubles' low bytes are noise either way, and signs flipping made it 30 %
 * larger.) */
static uint64_t
event_word(const struct contact_event *e, size_t c)
{
	switch (c) {
	case 0: return (uint64_t)(uint32_t)e->other;
	case 1: return (uint64_t)(uint32_t)e->obstacle;
	case 2: return dbits(e->q.x);
	case 3: return dbits(e->q.y);
	case 4: return dbits(e->q.z);
	case 5: return dbits(e->n.x);
	case 6: return dbits(e->n.y);
	case 7: return dbits(e->n.z);
	case 8: return dbits(e->vn_before);
	default: return dbits(e->vn_after);
	}
}

static void
set_event_word(struct contact_event *e, size_t c, uint64_t w)
{
	switch (c) {
	case 0: e->other = (int32_t)(uint32_t)w; break;
	case 1: e->obstacle = (int32_t)(uint32_t)w; break;
	case 2: e->q.x = bitsd(w); break;
	case 3: e->q.y = bitsd(w); break;
	case 4: e->q.z = bitsd(w); break;
	case 5: e->n.x = bitsd(w); break;
	case 6: e->n.y = bitsd(w); break;
	case 7: e->n.z = bitsd(w); break;
	case 8: e->vn_before = bitsd(w); break;
	default: e->vn_after = bitsd(w); break;
	}
}

#define EVENT_WORDS 10	/* columns after step, node and type */

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
			uint64_t w = event_word(&ev[i], c);

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

/* A steps chunk's head: the events' count and a zero, then, in a digest
 * chunk, the digest; the statistics' columns follow. */
static size_t
steps_head(uint32_t kind)
{
	return kind == REPLAY_STEPS_DIGEST ? 16 : 8;
}

static int
flush_steps(struct replay_writer *w, bool keep, struct drape_err *err)
{
	uint32_t kind = w->events_stored ? REPLAY_STEPS : REPLAY_STEPS_DIGEST;
	size_t k = w->nsteps, nev = w->nev, i, head = steps_head(kind);
	size_t nstored = w->events_stored ? nev : 0;
	size_t len = head + 8 * NSTAT * k + EVENT_BYTES * nstored;
	uint64_t *words = NULL, *tmp64 = NULL, first;
	uint32_t *tmp32 = NULL;
	int rc = -1, c;

	if (k == 0)
		return 0;
	first = (uint64_t)w->steps[0].step;
	if (grow(&w->buf, &w->bufcap, len) != 0 ||
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

		stat_words(&w->steps[i], row);
		for (c = 0; c < NSTAT; c++)
			words[(size_t)c * k + i] = row[c];
	}
	for (c = 0; c < NSTAT; c++)
		pack_col64(words + (size_t)c * k, k, w->buf + head + 8 * (size_t)c * k);
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

/* Each event as 11 words (step; node and type; other and obstacle; then
 * the eight doubles' bit patterns), each mixed in by a xor, a
 * multiplication by an odd constant and a shift xor: each is a bijection
 * of h, so one word changed changes the digest; a word at a time, not a
 * byte (FNV-1a's), since the rk4 tablecloth digests 6 million events. */
uint64_t
replay_digest_events(uint64_t h, const struct contact_event *ev, size_t nev)
{
	size_t i, c;

	for (i = 0; i < nev; i++) {
		const struct contact_event *e = &ev[i];
		uint64_t wd[EVENT_WORDS + 1];

		wd[0] = (uint64_t)e->step;
		wd[1] = (uint64_t)(uint32_t)e->node << 8 | (uint64_t)(uint8_t)e->type;
		wd[2] = (uint64_t)(uint32_t)e->other << 32 | (uint64_t)(uint32_t)e->obstacle;
		for (c = 2; c < EVENT_WORDS; c++)
			wd[c + 1] = event_word(e, c);
		for (c = 0; c < EVENT_WORDS + 1; c++) {
			h ^= wd[c];
			h *= UINT64_C(0x9e3779b97f4a7c15);
			h ^= h >> 29;
		}
	}
	return h;
}

bool
replay_step_same(const struct replay_step *a, const struct replay_step *b)
{
	int k;

	if (a->step != b->step || dbits(a->t) != dbits(b->t) || dbits(a->dt) != dbits(b->dt) ||
	    a->nev != b->nev)
		return false;
	for (k = STAT_CONTACTS; k < STAT_COUNT; k++)
		if (a->col.n[k] != b->col.n[k])
			return false;
	return true;
}

static int
write_step_once(struct replay_writer *w, const struct replay_step *s,
    const struct contact_event *ev, struct drape_err *err)
{
	size_t nev = (size_t)s->nev;

	if (!w->events_stored)
		w->digest = replay_digest_events(w->digest, ev, nev);
	else if (nev > 0 && w->nev + nev > w->evcap) {
		size_t cap = w->evcap ? w->evcap : 1024;
		struct contact_event *p;

		while (cap < w->nev + nev)
			cap *= 2;
		if ((p = realloc(w->ev, cap * sizeof *p)) == NULL) {
			err_set(err, "%s: out of memory", w->path);
			return -1;
		}
		w->ev = p;
		w->evcap = cap;
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
		if (grow(&w->buf, &w->bufcap, 16 * w->nkey + 1) != 0) {
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

/* ---- reader ---- */

/* Reads n bytes at off; 0, or -1 past the end or on an I/O error. */
static int
read_at(const struct replay *r, uint64_t off, void *buf, size_t n)
{
	if (off > r->len || n > r->len - off)
		return -1;
	if (r->mem != NULL) {
		memcpy(buf, r->mem + off, n);
		return 0;
	}
	if (fseeko(r->f, (off_t)off, SEEK_SET) != 0 || fread(buf, 1, n, r->f) != n)
		return -1;
	return 0;
}

/* The bytes a frames chunk of kind has before its steps: the grid step
 * (lossy), then the grid's width and a zero (version 3's kinds). */
static uint64_t
frames_head(uint32_t kind)
{
	return (replay_frames_lossy(kind) ? 8 : 0) +
	    (kind == REPLAY_FRAMES_GRID || kind == REPLAY_FRAMES_GRID_Q ? 8 : 0);
}

/* The payload size a chunk header must have, checked before anything is
 * allocated for it: 0 if it is acceptable. */
static int
check_chunk_header(const struct replay *r, const struct replay_chunk_header *h)
{
	uint64_t n = r->hdr.nodes, raw = h->raw_len, need;

	if (memcmp(h->magic, chunk_magic, 4) != 0)
		return -1;
	switch (h->kind) {
	case REPLAY_META:
		if (h->count != 1 || raw < META_FIXED || raw > MAX_META_RAW)
			return -1;
		break;
	case REPLAY_FRAMES:
	case REPLAY_FRAMES_Q:
	case REPLAY_FRAMES_GRID:
	case REPLAY_FRAMES_GRID_Q:
		if (h->count < 1 || h->count > MAX_FRAMES_CHUNK ||
		    raw != frames_head(h->kind) + (uint64_t)h->count * (16 + 12 * n))
			return -1;
		break;
	case REPLAY_KEYFRAME:	/* with the state one step back from version 5 */
		if (h->count != 1 || (raw != 32 + 48 * n &&
		    (r->hdr.version < 5 || raw != 32 + 96 * n)))
			return -1;
		break;
	case REPLAY_STEPS:
		need = 8 + 8 * NSTAT * (uint64_t)h->count;
		if (h->count < 1 || h->count > MAX_STEPS_CHUNK || raw < need ||
		    (raw - need) % EVENT_BYTES != 0 || raw > MAX_STEPS_RAW)
			return -1;
		break;
	case REPLAY_STEPS_DIGEST:
		if (h->count < 1 || h->count > MAX_STEPS_CHUNK ||
		    raw != 16 + 8 * NSTAT * (uint64_t)h->count)
			return -1;
		break;
	case REPLAY_INDEX:
		if (h->count > MAX_INDEX || raw != 16 * (uint64_t)h->count)
			return -1;
		break;
	default:
		return -1;
	}
	/* deflate output never exceeds compressBound; more is not deflate */
	if (h->comp_len > compressBound(h->raw_len) + 64)
		return -1;
	return 0;
}

/* The CRC of a chunk whose header is at off: 0 if it matches. A fuzzing
 * build (the libFuzzer convention's macro) takes every CRC as good, so
 * that the fuzzer reaches the decoders behind them. */
static int
check_chunk_crc(const struct replay *r, uint64_t off, const struct replay_chunk_header *h)
{
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
	(void)r;
	(void)off;
	(void)h;
	return 0;
#else
	unsigned char buf[65536];
	uint32_t crc = crc_of((uint32_t)crc32(0, Z_NULL, 0), h,
	    offsetof(struct replay_chunk_header, crc));
	uint64_t pos = off + sizeof *h, end = pos + h->comp_len;

	while (pos < end) {
		size_t k = end - pos > sizeof buf ? sizeof buf : (size_t)(end - pos);

		if (read_at(r, pos, buf, k) != 0)
			return -1;
		crc = crc_of(crc, buf, k);
		pos += k;
	}
	return crc == h->crc ? 0 : -1;
#endif
}

/* 0 if a whole, intact chunk starts at off. */
static int
chunk_at(const struct replay *r, uint64_t off, struct replay_chunk_header *h)
{
	if (off > r->len || r->len - off < sizeof *h || read_at(r, off, h, sizeof *h) != 0)
		return -1;
	if (check_chunk_header(r, h) != 0 || h->comp_len > r->len - off - sizeof *h)
		return -1;
	return check_chunk_crc(r, off, h);
}

/* The next offset after `from` where an intact chunk starts, or 0. */
static uint64_t
resync(const struct replay *r, uint64_t from)
{
	unsigned char buf[65536];
	struct replay_chunk_header h;
	uint64_t pos = from;

	while (pos + sizeof h <= r->len) {
		size_t k = r->len - pos > sizeof buf ? sizeof buf : (size_t)(r->len - pos), i;

		if (read_at(r, pos, buf, k) != 0)
			return 0;
		for (i = 0; i + 4 <= k; i++)
			if (memcmp(buf + i, chunk_magic, 4) == 0 && chunk_at(r, pos + i, &h) == 0)
				return pos + i;
		if (k < sizeof buf)
			break;
		pos += k - 3;
	}
	return 0;
}

static int
add_chunk(struct replay *r, const struct replay_chunk_header *h, uint64_t off, size_t *cap)
{
	struct replay_chunk *c;

	if (r->nchunks == *cap) {
		size_t ncap = *cap ? 2 * *cap : 64;

		if ((c = realloc(r->chunk, ncap * sizeof *c)) == NULL)
			return -1;
		r->chunk = c;
		*cap = ncap;
	}
	c = &r->chunk[r->nchunks++];
	c->kind = h->kind;
	c->first_step = h->first_step;
	c->count = h->count;
	c->comp_len = h->comp_len;
	c->raw_len = h->raw_len;
	c->offset = off;
	c->ordinal = r->seen;
	return 0;
}

static void
note_bad(struct replay *r)
{
	if (r->nbad < sizeof r->bad_ordinal / sizeof r->bad_ordinal[0])
		r->bad_ordinal[r->nbad] = r->seen;
	r->nbad++;
}

/* Walks the chunks after the header: whole ones are kept, damaged ones
 * counted and skipped, a cut noted. */
static int
scan(struct replay *r)
{
	struct replay_chunk_header h;
	uint64_t off = sizeof r->hdr, next;
	size_t cap = 0;

	while (off < r->len) {
		if (chunk_at(r, off, &h) == 0) {
			if (add_chunk(r, &h, off, &cap) != 0)
				return -1;
			r->seen++;
			off += sizeof h + h.comp_len;
			continue;
		}
		if ((next = resync(r, off + 1)) == 0) {
			/* nothing whole after it: the file was cut here */
			r->cut = true;
			break;
		}
		note_bad(r);
		r->seen++;
		off = next;
	}
	/* the writer puts the scene chunk right after the header: a file
	 * that ends with its header was cut there */
	if (r->seen == 0 && off == r->len)
		r->cut = true;
	r->cut_offset = off;
	return 0;
}

/* Inflates chunk c into a new buffer of c->raw_len bytes. */
static int
inflate_chunk(const struct replay *r, const struct replay_chunk *c, unsigned char **out,
    struct drape_err *err)
{
	struct replay_chunk_header h;
	unsigned char *z, *raw;
	uLongf len = c->raw_len;

	*out = NULL;
	if (chunk_at(r, c->offset, &h) != 0 || h.kind != c->kind || h.raw_len != c->raw_len) {
		err_set(err, "chunk %zu: changed or unreadable since the file was opened", c->ordinal);
		return -1;
	}
	if ((z = malloc(c->comp_len + 1)) == NULL || (raw = malloc((size_t)c->raw_len + 1)) == NULL) {
		free(z);
		err_set(err, "chunk %zu: out of memory", c->ordinal);
		return -1;
	}
	if (read_at(r, c->offset + sizeof h, z, c->comp_len) != 0 ||
	    uncompress(raw, &len, z, c->comp_len) != Z_OK || len != c->raw_len) {
		free(z);
		free(raw);
		err_set(err, "chunk %zu: does not inflate to its stated %u bytes", c->ordinal,
		    c->raw_len);
		return -1;
	}
	free(z);
	*out = raw;
	return 0;
}

/* The first want bytes (at most its raw length) that chunk c inflates to,
 * into a new buffer: the statistics at the head of a steps chunk without
 * reading or inflating the events behind them. The compressed bytes are
 * read a block at a time, as inflate asks for them; the chunk's CRC was
 * checked at the open (and is again when the whole chunk is read). */
static int
inflate_head(const struct replay *r, const struct replay_chunk *c, size_t want,
    unsigned char **out, struct drape_err *err)
{
	enum { BLOCK = 65536 };
	struct replay_chunk_header h;
	unsigned char *z, *raw;
	uint64_t off = c->offset + sizeof h, left = c->comp_len;
	z_stream zs;
	int rc = Z_OK;

	*out = NULL;
	if (want > c->raw_len)
		want = c->raw_len;
	if (read_at(r, c->offset, &h, sizeof h) != 0 || h.kind != c->kind ||
	    h.raw_len != c->raw_len || h.comp_len != c->comp_len) {
		err_set(err, "chunk %zu: changed or unreadable since the file was opened", c->ordinal);
		return -1;
	}
	if ((z = malloc(BLOCK)) == NULL || (raw = malloc(want + 1)) == NULL) {
		free(z);
		err_set(err, "chunk %zu: out of memory", c->ordinal);
		return -1;
	}
	memset(&zs, 0, sizeof zs);
	if (inflateInit(&zs) != Z_OK) {
		free(z);
		free(raw);
		err_set(err, "chunk %zu: out of memory", c->ordinal);
		return -1;
	}
	zs.next_out = raw;
	zs.avail_out = (uInt)want;
	while (zs.avail_out > 0 && rc == Z_OK) {
		if (zs.avail_in == 0) {
			size_t n = left < BLOCK ? (size_t)left : BLOCK;

			if (n == 0 || read_at(r, off, z, n) != 0)
				break;
			off += n;
			left -= n;
			zs.next_in = z;
			zs.avail_in = (uInt)n;
		}
		rc = inflate(&zs, Z_NO_FLUSH);
	}
	inflateEnd(&zs);
	free(z);
	if (zs.avail_out > 0) {
		free(raw);
		err_set(err, "chunk %zu: does not inflate to its stated %u bytes", c->ordinal,
		    c->raw_len);
		return -1;
	}
	*out = raw;
	return 0;
}

static char *
take_string(const unsigned char *p, size_t n)
{
	char *s = malloc(n + 1);

	if (s != NULL) {
		memcpy(s, p, n);
		s[n] = '\0';
	}
	return s;
}

static int
read_meta(struct replay *r, const struct replay_chunk *c, struct drape_err *err)
{
	struct replay_meta *m = &r->meta;
	unsigned char *p;
	uint64_t ln, lp, lt, lv, ntri, o = META_FIXED;
	size_t i;

	if (inflate_chunk(r, c, &p, err) != 0)
		return -1;
	m->nodes = get32(p);
	m->triangles = get32(p + 4);
	m->integrator = (int)get32(p + 8);
	m->duration = bitsd(get64(p + 16));
	m->dt = bitsd(get64(p + 24));
	m->dt_set = bitsd(get64(p + 32));
	m->output_rate = bitsd(get64(p + 40));
	m->keyframe_every = (long)(get64(p + 48) & 0x7fffffffffffffffULL);
	ln = get32(p + 56);
	lp = get32(p + 60);
	lt = get32(p + 64);
	lv = get32(p + 68);
	ntri = m->triangles;
	if (!(m->duration > 0) || !isfinite(m->duration) || !(m->dt >= 0) || !isfinite(m->dt) ||
	    !(m->dt_set > 0) || !isfinite(m->dt_set) || !(m->output_rate > 0) ||
	    !isfinite(m->output_rate)) {
		err_set(err, "the scene chunk holds a duration, step or output rate that is not "
		    "a finite number greater than 0");
		free(p);
		return -1;
	}
	if (m->nodes != r->hdr.nodes || m->triangles != r->hdr.triangles ||
	    META_FIXED + ln + lp + lt + lv + 12 * ntri != c->raw_len) {
		err_set(err, "the scene chunk disagrees with the header or its own length");
		free(p);
		return -1;
	}
	if ((m->name = take_string(p + o, ln)) == NULL ||
	    (m->path = take_string(p + o + ln, lp)) == NULL ||
	    (m->text = take_string(p + o + ln + lp, lt)) == NULL ||
	    (m->version = take_string(p + o + ln + lp + lt, lv)) == NULL ||
	    (m->tri = malloc(12 * ntri + 1)) == NULL) {
		err_set(err, "out of memory");
		free(p);
		return -1;
	}
	o += ln + lp + lt + lv;
	memcpy(m->tri, p + o, 12 * ntri);
	free(p);
	for (i = 0; i < 3 * ntri; i++)
		if (m->tri[i] < 0 || (uint32_t)m->tri[i] >= m->nodes) {
			err_set(err, "the scene chunk has a triangle with node %d of %u", m->tri[i],
			    m->nodes);
			return -1;
		}
	if (strlen(m->text) != lt || strlen(m->name) != ln || strlen(m->path) != lp ||
	    strlen(m->version) != lv) {
		err_set(err, "the scene chunk holds a NUL byte in its text");
		return -1;
	}
	return 0;
}

static int
open_common(struct replay *r, const char *name, struct drape_err *err)
{
	struct drape_err e;
	size_t i;
	long meta = -1;

	if (r->len < sizeof r->hdr || read_at(r, 0, &r->hdr, sizeof r->hdr) != 0) {
		err_set(err, "%s: not a drape replay: shorter than its %zu-byte header", name,
		    sizeof r->hdr);
		return -1;
	}
	if (memcmp(r->hdr.magic, file_magic, 8) != 0) {
		err_set(err, "%s: not a drape replay: expected the magic 'DRAPERPL'", name);
		return -1;
	}
#ifndef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
	if (r->hdr.crc != header_crc(&r->hdr)) {
		err_set(err, "%s: the replay header fails its CRC", name);
		return -1;
	}
#endif
	if (r->hdr.version < 1 || r->hdr.version > REPLAY_VERSION) {
		err_set(err, "%s: replay version %u; this drape reads versions 1 to %d", name,
		    r->hdr.version, REPLAY_VERSION);
		return -1;
	}
	if (r->hdr.nodes < 1 || r->hdr.nodes > MAX_NODES || r->hdr.triangles > MAX_TRIANGLES) {
		err_set(err, "%s: %u nodes and %u triangles: expected 1 to %u nodes", name,
		    r->hdr.nodes, r->hdr.triangles, MAX_NODES);
		return -1;
	}
	if (scan(r) != 0) {
		err_set(err, "%s: out of memory", name);
		return -1;
	}
	r->last_step = -1;
	for (i = 0; i < r->nchunks; i++) {
		const struct replay_chunk *c = &r->chunk[i];

		if (c->kind == REPLAY_META && meta < 0)
			meta = (long)i;
		else if (replay_is_frames(c->kind))
			r->nframes += c->count;
		else if (c->kind == REPLAY_KEYFRAME)
			r->nkeyframes++;
		else if (replay_is_steps(c->kind)) {
			r->nstep_chunks++;
			if (c->first_step < (uint64_t)LONG_MAX - c->count &&
			    (long)(c->first_step + c->count - 1) > r->last_step)
				r->last_step = (long)(c->first_step + c->count - 1);
		}
	}
	if (meta < 0) {
		err_set(err, "%s: no intact scene chunk: %s", name,
		    r->len == sizeof r->hdr ? "the file was cut short after its 64-byte header" :
		    r->cut ? "the file was cut before it" : "it is damaged");
		return -1;
	}
	if (read_meta(r, &r->chunk[meta], &e) != 0) {
		err_set(err, "%s: %s", name, e.msg);
		return -1;
	}
	return 0;
}

int
replay_open(struct replay *r, const char *path, struct drape_err *err)
{
	memset(r, 0, sizeof *r);
	if ((r->f = fopen(path, "rb")) == NULL) {
		err_set(err, "%s: cannot open: %s", path, strerror(errno));
		return -1;
	}
	if (fseeko(r->f, 0, SEEK_END) != 0 || ftello(r->f) < 0) {
		err_set(err, "%s: cannot read: %s", path, strerror(errno));
		replay_close(r);
		return -1;
	}
	r->len = (uint64_t)ftello(r->f);
	if (open_common(r, path, err) != 0) {
		replay_close(r);
		return -1;
	}
	return 0;
}

int
replay_open_mem(struct replay *r, const void *buf, size_t len, struct drape_err *err)
{
	static const unsigned char empty[1];

	memset(r, 0, sizeof *r);
	r->mem = buf != NULL ? buf : empty;
	r->len = buf != NULL ? len : 0;
	if (open_common(r, "replay", err) != 0) {
		replay_close(r);
		return -1;
	}
	return 0;
}

void
replay_close(struct replay *r)
{
	if (r->f != NULL)
		fclose(r->f);
	free(r->chunk);
	free(r->meta.name);
	free(r->meta.path);
	free(r->meta.text);
	free(r->meta.version);
	free(r->meta.tri);
	memset(r, 0, sizeof *r);
}

int
replay_read_frames(const struct replay *r, size_t i, struct replay_frames *fr,
    struct drape_err *err)
{
	const struct replay_chunk *c = &r->chunk[i];
	size_t k = c->count, n3 = 3 * (size_t)r->hdr.nodes, j, head;
	unsigned char *p;
	uint32_t *tmp, width;
	bool grid;

	memset(fr, 0, sizeof *fr);
	if (!replay_is_frames(c->kind)) {
		err_set(err, "chunk %zu: not frames", c->ordinal);
		return -1;
	}
	if (inflate_chunk(r, c, &p, err) != 0)
		return -1;
	head = (size_t)frames_head(c->kind);
	grid = c->kind == REPLAY_FRAMES_GRID || c->kind == REPLAY_FRAMES_GRID_Q;
	width = grid ? get32(p + head - 8) : 0;
	if (grid && (width < 1 || width > r->hdr.nodes || get32(p + head - 4) != 0)) {
		free(p);
		err_set(err, "chunk %zu: frames of a grid %u nodes wide: expected 1 to %u, then "
		    "a zero word", c->ordinal, (unsigned)width, (unsigned)r->hdr.nodes);
		return -1;
	}
	if (replay_frames_lossy(c->kind)) {
		fr->precision = bitsd(get64(p));
		if (!(fr->precision > 0) || !isfinite(fr->precision)) {
			free(p);
			err_set(err, "chunk %zu: lossy frames with a grid step of %g m: expected a "
			    "length greater than 0", c->ordinal, fr->precision);
			return -1;
		}
	}
	fr->count = k;
	if ((fr->step = malloc(k * sizeof *fr->step)) == NULL ||
	    (fr->t = malloc(k * sizeof *fr->t)) == NULL ||
	    (fr->x = malloc(k * n3 * sizeof *fr->x)) == NULL ||
	    (tmp = malloc(k * n3 * sizeof *tmp)) == NULL) {
		free(p);
		replay_frames_free(fr);
		err_set(err, "chunk %zu: out of memory", c->ordinal);
		return -1;
	}
	for (j = 0; j < k; j++) {
		fr->step[j] = (long)(get64(p + head + 8 * j) & 0x7fffffffffffffffULL);
		fr->t[j] = bitsd(get64(p + head + 8 * (k + j)));
	}
	if (replay_frames_lossy(c->kind)) {
		int32_t *q = malloc(k * n3 * sizeof *q);

		if (q == NULL) {
			free(tmp);
			free(p);
			replay_frames_free(fr);
			err_set(err, "chunk %zu: out of memory", c->ordinal);
			return -1;
		}
		if (grid)
			frames_decode_grid_q(p + head + 16 * k, k, r->hdr.nodes, width, tmp, q);
		else
			frames_decode_q(p + head + 16 * k, k, n3, tmp, q);
		for (j = 0; j < k * n3; j++)
			fr->x[j] = (float)((double)q[j] * fr->precision);
		free(q);
	} else if (grid) {
		frames_decode_grid(p + head + 16 * k, k, r->hdr.nodes, width, tmp, fr->x);
	} else {
		frames_decode(p + 16 * k, k, n3, tmp, fr->x);
	}
	free(tmp);
	free(p);
	return 0;
}

int
replay_read_keyframe(const struct replay *r, size_t i, struct replay_keyframe *kf,
    struct drape_err *err)
{
	const struct replay_chunk *c = &r->chunk[i];
	size_t n6 = 6 * (size_t)r->hdr.nodes;
	unsigned char *p;

	memset(kf, 0, sizeof *kf);
	if (c->kind != REPLAY_KEYFRAME) {
		err_set(err, "chunk %zu: not a keyframe", c->ordinal);
		return -1;
	}
	if (inflate_chunk(r, c, &p, err) != 0)
		return -1;
	if ((kf->y = malloc(n6 * sizeof *kf->y)) == NULL ||
	    (c->raw_len > 32 + 8 * n6 && (kf->hist = malloc(n6 * sizeof *kf->hist)) == NULL)) {
		free(p);
		replay_keyframe_free(kf);
		err_set(err, "chunk %zu: out of memory", c->ordinal);
		return -1;
	}
	kf->step = (long)(get64(p) & 0x7fffffffffffffffULL);
	kf->t = bitsd(get64(p + 8));
	kf->dt = bitsd(get64(p + 16));
	kf->hash = get64(p + 24);
	codec_unshuffle(p + 32, (unsigned char *)kf->y, n6, 8);
	if (kf->hist != NULL)
		codec_unshuffle(p + 32 + 8 * n6, (unsigned char *)kf->hist, n6, 8);
	free(p);
	return 0;
}

static int
unpack_events(const unsigned char *in, size_t nev, uint64_t first_step, uint64_t nsteps,
    uint32_t nodes, struct contact_event *ev, uint32_t *tmp32, uint64_t *tmp64)
{
	size_t i, c;

	for (c = 0; c < 2; c++) {
		codec_unshuffle(in, (unsigned char *)tmp32, nev, 4);
		codec_undelta_u32(tmp32, nev);
		for (i = 0; i < nev; i++) {
			if (tmp32[i] >= (c == 0 ? nsteps : nodes))
				return -1;
			if (c == 0)
				ev[i].step = (long)(first_step + tmp32[i]);
			else
				ev[i].node = (int)tmp32[i];
		}
		in += 4 * nev;
	}
	for (i = 0; i < nev; i++) {
		if (in[i] >= CONTACT_NTYPES)
			return -1;
		ev[i].type = (enum contact_type)in[i];
	}
	in += nev;
	for (c = 0; c < EVENT_WORDS; c++) {
		size_t size = c < 2 ? 4 : 8;

		if (size == 4)
			codec_unshuffle(in, (unsigned char *)tmp32, nev, 4);
		else
			codec_unshuffle(in, (unsigned char *)tmp64, nev, 8);
		for (i = 0; i < nev; i++)
			set_event_word(&ev[i], c, size == 4 ? tmp32[i] : tmp64[i]);
		in += size * nev;
	}
	return 0;
}

/* Whether chunk c is not a steps chunk one can number (with a message). */
static bool
not_steps(const struct replay_chunk *c, struct drape_err *err)
{
	if (replay_is_steps(c->kind) && c->first_step <= (uint64_t)LONG_MAX - c->count)
		return false;
	err_set(err, "chunk %zu: not steps", c->ordinal);
	return true;
}

/* The events a steps chunk's head p says it holds, checked against its
 * length: 0, or -1 with a message. */
static int
events_in(const struct replay_chunk *c, const unsigned char *p, size_t *nev,
    struct drape_err *err)
{
	*nev = get32(p);
	/* a digest chunk's length is its head's (check_chunk_header); its
	 * steps' counts are held to nev (decode_step_stats) */
	if (c->kind == REPLAY_STEPS_DIGEST)
		return 0;
	if (8 + 8 * NSTAT * (uint64_t)c->count + EVENT_BYTES * (uint64_t)*nev == c->raw_len)
		return 0;
	err_set(err, "chunk %zu: %zu events do not fill its %u bytes", c->ordinal, *nev,
	    c->raw_len);
	return -1;
}

/* Steps chunk c's statistics from its inflated head p (nev events in all)
 * into ss->s, each step checked against the chunk: 0, or -1 with a
 * message. */
static int
decode_step_stats(const struct replay_chunk *c, const unsigned char *p, size_t nev,
    struct replay_steps *ss, struct drape_err *err)
{
	size_t k = c->count, j, col, total = 0;
	uint64_t *words = malloc(k * NSTAT * sizeof *words);

	if (words == NULL) {
		err_set(err, "chunk %zu: out of memory", c->ordinal);
		return -1;
	}
	for (col = 0; col < NSTAT; col++)
		unpack_col64(p + steps_head(c->kind) + 8 * col * k, k, words + col * k);
	for (j = 0; j < k; j++) {
		uint64_t row[NSTAT];

		for (col = 0; col < NSTAT; col++)
			row[col] = words[col * k + j];
		stat_from_words(row, &ss->s[j]);
		if (ss->s[j].step != (long)(c->first_step + j) || ss->s[j].nev < 0 ||
		    (uint64_t)ss->s[j].nev > nev - total) {
			err_set(err, "chunk %zu: step %zu's record is inconsistent", c->ordinal, j);
			free(words);
			return -1;
		}
		total += (size_t)ss->s[j].nev;
	}
	free(words);
	if (total != nev) {
		err_set(err, "chunk %zu: its events do not match its steps", c->ordinal);
		return -1;
	}
	return 0;
}

int
replay_read_steps(const struct replay *r, size_t i, struct replay_steps *ss,
    struct drape_err *err)
{
	const struct replay_chunk *c = &r->chunk[i];
	size_t k = c->count, nev;
	unsigned char *p;
	uint64_t *tmp64 = NULL;
	uint32_t *tmp32 = NULL;
	int rc = -1;

	memset(ss, 0, sizeof *ss);
	if (not_steps(c, err))
		return -1;
	if (c->kind != REPLAY_STEPS) {
		err_set(err, "chunk %zu: its events are not stored, only their digest", c->ordinal);
		return -1;
	}
	if (inflate_chunk(r, c, &p, err) != 0)
		return -1;
	if (events_in(c, p, &nev, err) != 0)
		goto out;
	ss->count = k;
	ss->nev = nev;
	if ((ss->s = malloc(k * sizeof *ss->s)) == NULL ||
	    (ss->ev = malloc((nev + 1) * sizeof *ss->ev)) == NULL ||
	    (tmp32 = malloc((nev + 1) * sizeof *tmp32)) == NULL ||
	    (tmp64 = malloc((nev + 1) * sizeof *tmp64)) == NULL) {
		err_set(err, "chunk %zu: out of memory", c->ordinal);
		goto out;
	}
	if (decode_step_stats(c, p, nev, ss, err) != 0)
		goto out;
	if (unpack_events(p + 8 + 8 * NSTAT * k, nev, c->first_step, k, r->hdr.nodes, ss->ev,
	    tmp32, tmp64) != 0) {
		err_set(err, "chunk %zu: its events do not match its steps", c->ordinal);
		goto out;
	}
	rc = 0;
out:
	free(p);
	free(tmp32);
	free(tmp64);
	if (rc != 0)
		replay_steps_free(ss);
	return rc;
}

int
replay_read_step_stats(const struct replay *r, size_t i, struct replay_steps *ss,
    struct drape_err *err)
{
	const struct replay_chunk *c = &r->chunk[i];
	size_t k = c->count, nev;
	unsigned char *p;
	int rc = -1;

	memset(ss, 0, sizeof *ss);
	if (not_steps(c, err))
		return -1;
	/* check_chunk_header bounded raw_len from below by the head */
	if (inflate_head(r, c, steps_head(c->kind) + 8 * NSTAT * k, &p, err) != 0)
		return -1;
	if (events_in(c, p, &nev, err) != 0)
		goto out;
	ss->count = k;
	ss->nev = nev;
	if (c->kind == REPLAY_STEPS_DIGEST) {
		ss->has_digest = true;
		ss->digest = get64(p + 8);
	}
	if ((ss->s = malloc(k * sizeof *ss->s)) == NULL) {
		err_set(err, "chunk %zu: out of memory", c->ordinal);
		goto out;
	}
	rc = decode_step_stats(c, p, nev, ss, err);
out:
	free(p);
	if (rc != 0)
		replay_steps_free(ss);
	return rc;
}

void
replay_frames_free(struct replay_frames *fr)
{
	free(fr->step);
	free(fr->t);
	free(fr->x);
	memset(fr, 0, sizeof *fr);
}

void
replay_keyframe_free(struct replay_keyframe *kf)
{
	free(kf->y);
	free(kf->hist);
	memset(kf, 0, sizeof *kf);
}

void
replay_steps_free(struct replay_steps *ss)
{
	free(ss->s);
	free(ss->ev);
	memset(ss, 0, sizeof *ss);
}

long
replay_find_keyframe(const struct replay *r, long step)
{
	long best = -1;
	size_t i;

	for (i = 0; i < r->nchunks; i++) {
		const struct replay_chunk *c = &r->chunk[i];

		if (c->kind != REPLAY_KEYFRAME || c->first_step > (uint64_t)LONG_MAX)
			continue;
		if (step >= 0 && (long)c->first_step > step)
			continue;
		if (best < 0 || c->first_step >= r->chunk[best].first_step)
			best = (long)i;
	}
	return best;
}

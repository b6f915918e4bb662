/* replay_reader.c: reads a replay file, hostile or cut short
 * (drape-replay(5)): every chunk's framing and CRC checked and the bounds
 * held before anything is allocated; a damaged chunk is skipped and the
 * scan resyncs on the next. */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>
#include <zlib.h>

#include "frame_codec.h"
#include "grow.h"
#include "outfile.h"
#include "replay_impl.h"

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
		    raw != replay_frames_head(h->kind) + (uint64_t)h->count * (16 + 12 * n))
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
	uint32_t crc = replay_crc((uint32_t)crc32(0, Z_NULL, 0), h,
	    offsetof(struct replay_chunk_header, crc));
	uint64_t pos = off + sizeof *h, end = pos + h->comp_len;

	while (pos < end) {
		size_t k = end - pos > sizeof buf ? sizeof buf : (size_t)(end - pos);

		if (read_at(r, pos, buf, k) != 0)
			return -1;
		crc = replay_crc(crc, buf, k);
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

	if (grow_array((void **)&r->chunk, cap, r->nchunks + 1, sizeof *r->chunk) != 0)
		return -1;
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
	if (r->hdr.crc != replay_header_crc(&r->hdr)) {
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
	head = (size_t)replay_frames_head(c->kind);
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
			replay_set_event_word(&ev[i], c, size == 4 ? tmp32[i] : tmp64[i]);
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
		replay_unpack_col64(p + replay_steps_head(c->kind) + 8 * col * k, k, words + col * k);
	for (j = 0; j < k; j++) {
		uint64_t row[NSTAT];

		for (col = 0; col < NSTAT; col++)
			row[col] = words[col * k + j];
		replay_stat_from_words(row, &ss->s[j]);
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
	if (inflate_head(r, c, replay_steps_head(c->kind) + 8 * NSTAT * k, &p, err) != 0)
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

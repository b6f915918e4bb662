/* replay.c: the replay file format's packing, shared by the writer
 * (replay_writer.c) and the reader (replay_reader.c): CRCs, the columns'
 * delta coding, a step's statistics and an event as words, and the
 * events' digest (drape-replay(5)). */
#include <zlib.h>

#include "frame_codec.h"
#include "replay_impl.h"

uint32_t
replay_crc(uint32_t crc, const void *p, size_t n)
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

uint32_t
replay_header_crc(const struct replay_file_header *h)
{
	return replay_crc((uint32_t)crc32(0, Z_NULL, 0), h, offsetof(struct replay_file_header, crc));
}

/* A column of n 8-byte words, delta-coded down the column, shuffled. */
void
replay_pack_col64(uint64_t *w, size_t n, unsigned char *out)
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

void
replay_unpack_col64(const unsigned char *in, size_t n, uint64_t *w)
{
	uint64_t prev = 0;
	size_t i;

	codec_unshuffle(in, (unsigned char *)w, n, 8);
	for (i = 0; i < n; i++) {
		prev += unzz64(w[i]);
		w[i] = prev;
	}
}

/* The statistics of step s as NSTAT words, in the order drape-replay(5) lists. */
void
replay_stat_words(const struct replay_step *s, uint64_t *w)
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

void
replay_stat_from_words(const uint64_t *w, struct replay_step *s)
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

/* Event columns: step offset and node (u32, delta-coded down the column),
 * type (u8), other and obstacle (u32, as they are), then q, n, vn_before,
 * vn_after (f64 bit patterns): EVENT_BYTES in all, each column byte-shuffled.
 * (Predicting a value from the same node's previous event was tried: the
 * doubles' low bytes are noise either way, and signs flipping made it 30 %
 * larger.) */
uint64_t
replay_event_word(const struct contact_event *e, size_t c)
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

void
replay_set_event_word(struct contact_event *e, size_t c, uint64_t w)
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

/* A steps chunk's head: the events' count and a zero, then, in a digest
 * chunk, the digest; the statistics' columns follow. */
size_t
replay_steps_head(uint32_t kind)
{
	return kind == REPLAY_STEPS_DIGEST ? 16 : 8;
}

/* The bytes a frames chunk of kind has before its steps: the grid step
 * (lossy), then the grid's width and a zero (version 3's kinds). */
uint64_t
replay_frames_head(uint32_t kind)
{
	return (replay_frames_lossy(kind) ? 8 : 0) +
	    (kind == REPLAY_FRAMES_GRID || kind == REPLAY_FRAMES_GRID_Q ? 8 : 0);
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
			wd[c + 1] = replay_event_word(e, c);
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

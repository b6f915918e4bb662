/* replay_impl.h: what the replay file's writer (replay_writer.c) and
 * reader (replay_reader.c) share, inside the replay module only: the
 * format's sizes and bounds, its magics, and the packing of its columns,
 * statistics and events (replay.c), so that what one writes the other
 * reads by the same code. */
#ifndef DRAPE_REPLAY_IMPL_H
#define DRAPE_REPLAY_IMPL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

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
#define EVENT_WORDS 10	/* columns after step, node and type */

static const char file_magic[REPLAY_MAGIC_LEN] = { 'D', 'R', 'A', 'P', 'E', 'R', 'P', 'L' };
static const char chunk_magic[4] = { 'C', 'H', 'N', 'K' };

/* Words to and from their bytes, doubles as their bit patterns, and the
 * zigzag coding of deltas. */
static inline void put32(unsigned char *p, uint32_t v) { memcpy(p, &v, 4); }
static inline void put64(unsigned char *p, uint64_t v) { memcpy(p, &v, 8); }
static inline uint32_t get32(const unsigned char *p) { uint32_t v; memcpy(&v, p, 4); return v; }
static inline uint64_t get64(const unsigned char *p) { uint64_t v; memcpy(&v, p, 8); return v; }
static inline uint64_t dbits(double d) { uint64_t v; memcpy(&v, &d, 8); return v; }
static inline double bitsd(uint64_t v) { double d; memcpy(&d, &v, 8); return d; }
static inline uint64_t zz64(uint64_t d) { return (d << 1) ^ (uint64_t)-(int64_t)(d >> 63); }
static inline uint64_t unzz64(uint64_t z) { return (z >> 1) ^ (uint64_t)-(int64_t)(z & 1); }

/* CRC-32 of n bytes after crc (zlib's, in pieces that fit a uInt), and
 * that of a file header up to its crc field. */
uint32_t replay_crc(uint32_t crc, const void *p, size_t n);
uint32_t replay_header_crc(const struct replay_file_header *h);
/* A column of n 8-byte words, delta-coded down the column and shuffled
 * into out (w is overwritten), and back. */
void replay_pack_col64(uint64_t *w, size_t n, unsigned char *out);
void replay_unpack_col64(const unsigned char *in, size_t n, uint64_t *w);
/* A step's statistics as NSTAT words, and back. */
void replay_stat_words(const struct replay_step *s, uint64_t *w);
void replay_stat_from_words(const uint64_t *w, struct replay_step *s);
/* Column c (2 .. EVENT_WORDS) of an event as a word, and back. */
uint64_t replay_event_word(const struct contact_event *e, size_t c);
void replay_set_event_word(struct contact_event *e, size_t c, uint64_t w);
/* The bytes before a steps (frames) chunk's columns. */
size_t replay_steps_head(uint32_t kind);
size_t replay_frames_head(uint32_t kind);

#endif

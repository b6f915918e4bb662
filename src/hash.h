/* hash.h: the chapter's spatial enumeration (§3.3): space is cut into cubes
 * of edge L_ce, each cube has a key K (eq. 18), and only the cubes that hold
 * something are stored, in an open-addressed table of N_array slots indexed
 * by h = K mod N_array (eq. 19) with quadratic probing (eq. 20).
 *
 * The items are integers (node or triangle numbers). A fill is one
 * hash_begin followed by hash_inserts; the next hash_begin forgets it.
 * To visit every non-empty cube and its items, in insertion order:
 *
 *	for (i = 0; i < h->nfilled; i++) {
 *		const struct hash_cube *c = &h->slot[h->filled[i]];
 *
 *		for (e = c->head; e >= 0; e = h->next[e])
 *			use(h->item[e]);
 *	}
 */
#ifndef DRAPE_HASH_H
#define DRAPE_HASH_H

#include <stddef.h>
#include <stdint.h>

#include "vec3.h"

#define HASH_HIST 8	/* histogram buckets: cubes holding 1, 2, ..., 7, and >= 8 entries */

/* One slot of the table: a cube and the chain of its entries. */
struct hash_cube {
	int64_t key;		/* K; -1: empty slot */
	int count;		/* entries in this cube */
	int head, tail;		/* first and last entry (index into item/next), -1: none */
};

struct hash_stats {
	long entries;		/* items inserted this fill (nodes hashed) */
	long cubes;		/* non-empty cubes */
	long shared;		/* cubes with >= 2 entries */
	double load;		/* cubes / N_array */
	double probe_mean;	/* slots examined per insertion, >= 1; 0 with no insertion */
	int probe_max;
	long hist[HASH_HIST];	/* hist[k-1] = cubes with k entries, last bucket >= HASH_HIST */
};

struct spatial_hash {
	double cell;		/* L_ce */
	vec3 lo;		/* lower corner of cube (0,0,0) */
	int nx, ny, nz;		/* cubes along x, y, z */
	int64_t ncpl, ncpp, nbox;	/* N_cpl = nx, N_cpp = nx*nz, N_box = nx*ny*nz (eq. 18) */
	size_t narray;		/* N_array, a prime (eq. 19); 0: no fill */
	struct hash_cube *slot;	/* slotcap slots, all empty outside this fill's */
	size_t slotcap;
	int *filled;		/* slot indices in the order they were first filled, so
				 * clearing and scanning cost O(cubes), not O(N_array) */
	size_t nfilled;
	int *item, *next;	/* entry e holds item[e]; next[e] is the cube's next entry, -1: last */
	size_t nitems, itemcap;
	size_t maxitems;	/* this fill's max_items */
	long probes, inserts;	/* slots examined, insertions, this fill */
	int probe_max;
};

/* All empty, nothing allocated. */
void hash_init(struct spatial_hash *h);

/*
 * Starts a fill over the box [lo, hi] with cube edge cell, for at most
 * max_items insertions: sets nx, ny, nz (at least 1 each; an empty box,
 * lo > hi, gives one cube), N_cpl, N_cpp, N_box, and N_array, the smallest
 * prime >= 2*min(N_box, max_items) (and >= 2). Empties the previous fill.
 * Returns 0, or -1 if out of memory, if cell is not positive and finite, or
 * if the cube counts do not fit (nx, ny or nz over INT_MAX, N_box over
 * int64): then the caller must take a bigger cell. After -1 the table holds
 * no fill (hash_find finds nothing, hash_insert fails) until a hash_begin
 * succeeds.
 */
int hash_begin(struct spatial_hash *h, double cell, vec3 lo, vec3 hi, size_t max_items);

/* hash_cube_of, hash_key and hash_index describe the box of the current
 * fill: they need a successful hash_begin. */

/* The cube of p: dx = (x - lo.x) div L_ce etc. (eq. 18), clamped to
 * [0, nx-1] etc. so that a point slightly outside the box (rounding), or
 * NaN, lands in a border cube. */
void hash_cube_of(const struct spatial_hash *h, vec3 p, int d[3]);

/* eq. 18: K = dx + N_cpl*dz + N_cpp*dy, in [0, N_box) for a cube in range. */
int64_t hash_key(const struct spatial_hash *h, int dx, int dy, int dz);

/* eq. 19: h = K mod N_array. Needs a fill and K >= 0. */
size_t hash_index(const struct spatial_hash *h, int64_t key);

/*
 * eq. 20: probes h_{i+1} = h_i + d_i, d_{i+1} = d_i + 2, d_0 = 1,
 * h_0 = H(K) (mod N_array) until the slot with this key or an empty slot,
 * and appends item to that cube. Returns 0, or -1 if out of memory growing
 * the item arrays, if this would be more than max_items insertions, or if
 * the key is outside [0, N_box).
 */
int hash_insert(struct spatial_hash *h, int64_t key, int item);

/* The cube with this key, or NULL when no such cube this fill. */
const struct hash_cube *hash_find(const struct spatial_hash *h, int64_t key);

void hash_stats(const struct spatial_hash *h, struct hash_stats *s);
/* sum += s, for means over fills (probe_max: the largest). */
void hash_stats_add(struct hash_stats *sum, const struct hash_stats *s);

/* Frees everything; h is as after hash_init. */
void hash_free(struct spatial_hash *h);

#endif

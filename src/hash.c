/* hash.c: the spatial enumeration hash table of §3.3 (eq. 18-20): cube keys,
 * K mod N_array, quadratic probing, and per-cube chains of items. */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hash.h"

void
hash_init(struct spatial_hash *h)
{
	memset(h, 0, sizeof *h);
}

void
hash_free(struct spatial_hash *h)
{
	free(h->slot);
	free(h->filled);
	free(h->item);
	free(h->next);
	hash_init(h);
}

static int
is_prime(size_t n)
{
	size_t i;

	if (n < 4)
		return n >= 2;
	if (n % 2 == 0 || n % 3 == 0)
		return 0;
	for (i = 5; i * i <= n; i += 6)
		if (n % i == 0 || n % (i + 2) == 0)
			return 0;
	return 1;
}

/* Smallest prime >= n, n <= INT_MAX; 2^31 - 1 is prime, so it fits an int. */
static size_t
next_prime(size_t n)
{
	if (n <= 2)
		return 2;
	for (n |= 1; !is_prime(n); n += 2)
		;
	return n;
}

/* Cubes along one axis: (hi - lo) div L_ce + 1; one for an empty box. */
static int
axis_cubes(double lo, double hi, double cell, int *n)
{
	double ext = (hi - lo) / cell;

	if (!(ext >= 0))
		*n = 1;
	else if (ext >= INT_MAX)
		return -1;
	else
		*n = (int)ext + 1;
	return 0;
}

/* Room for narray slots; grows with a quarter to spare so that a box
 * creeping outwards step by step does not reallocate every step. */
static int
grow_slots(struct spatial_hash *h, size_t narray)
{
	struct hash_cube *s;
	int *f;
	size_t cap = narray + narray / 4, i;

	if (narray <= h->slotcap)
		return 0;
	if (cap > SIZE_MAX / sizeof *s)
		return -1;
	s = malloc(cap * sizeof *s);
	/* cubes <= N_array / 2 (see hash_begin) */
	f = malloc((cap / 2 + 1) * sizeof *f);
	if (s == NULL || f == NULL) {
		free(s);
		free(f);
		return -1;
	}
	for (i = 0; i < cap; i++)
		s[i].key = -1;
	free(h->slot);
	free(h->filled);
	h->slot = s;
	h->filled = f;
	h->slotcap = cap;
	return 0;
}

int
hash_begin(struct spatial_hash *h, double cell, vec3 lo, vec3 hi, size_t max_items)
{
	size_t i, m, narray;
	int nx, ny, nz;
	int64_t ncpp, nbox;

	/* forget the previous fill: only its cubes need emptying */
	for (i = 0; i < h->nfilled; i++)
		h->slot[h->filled[i]].key = -1;
	h->nfilled = h->nitems = 0;
	h->narray = h->maxitems = 0;
	h->nbox = 0;
	h->probes = h->inserts = 0;
	h->probe_max = 0;

	if (!(cell > 0) || !isfinite(cell))
		return -1;
	if (axis_cubes(lo.x, hi.x, cell, &nx) != 0 ||
	    axis_cubes(lo.y, hi.y, cell, &ny) != 0 ||
	    axis_cubes(lo.z, hi.z, cell, &nz) != 0)
		return -1;
	/* nx*nz < 2^62 cannot overflow; times ny can */
	ncpp = (int64_t)nx * nz;
	if (ncpp > INT64_MAX / ny)
		return -1;
	nbox = ncpp * ny;

	/*
	 * Each non-empty cube holds an item, so there are at most
	 * min(N_box, max_items) cubes. With N_array a prime p >= twice that,
	 * the load stays <= 1/2, and the first (p+1)/2 probes of eq. 20
	 * (h_0 + i^2, i = 0 .. (p-1)/2) are distinct: more than there are
	 * cubes, so a probe always meets the key or an empty slot. Entries and
	 * slots are numbered by int.
	 */
	m = max_items < INT_MAX ? max_items : INT_MAX;
	if ((uint64_t)nbox < m)
		m = (size_t)nbox;
	if (m > INT_MAX / 2)
		return -1;
	narray = next_prime(2 * m);
	if (grow_slots(h, narray) != 0)
		return -1;

	h->cell = cell;
	h->lo = lo;
	h->nx = nx;
	h->ny = ny;
	h->nz = nz;
	h->ncpl = nx;
	h->ncpp = ncpp;
	h->nbox = nbox;
	h->narray = narray;
	h->maxitems = max_items < INT_MAX ? max_items : INT_MAX;
	return 0;
}

/* eq. 18's div, clamped to the box; NaN goes to cube 0. */
static inline int
axis_cube(double t, int n)
{
	if (!(t >= 0))
		return 0;
	if (t >= n)
		return n - 1;
	return (int)t;
}

void
hash_cube_of(const struct spatial_hash *h, vec3 p, int d[3])
{
	d[0] = axis_cube((p.x - h->lo.x) / h->cell, h->nx);
	d[1] = axis_cube((p.y - h->lo.y) / h->cell, h->ny);
	d[2] = axis_cube((p.z - h->lo.z) / h->cell, h->nz);
}

int64_t
hash_key(const struct spatial_hash *h, int dx, int dy, int dz)
{
	return dx + h->ncpl * dz + h->ncpp * dy;	/* eq. 18 */
}

size_t
hash_index(const struct spatial_hash *h, int64_t key)
{
	return (size_t)((uint64_t)key % h->narray);	/* eq. 19 */
}

/*
 * eq. 20: the slot holding key, or the empty slot it would go in; *n is the
 * number of slots examined. h_i and d_i are kept reduced below N_array, so
 * h_i + d_i < 2 N_array never overflows.
 */
static inline size_t
probe(const struct spatial_hash *h, int64_t key, int *n)
{
	size_t i = hash_index(h, key), d = 1, na = h->narray;
	int k = 1;

	while (h->slot[i].key != key && h->slot[i].key != -1) {
		if ((i += d) >= na)
			i -= na;
		if ((d += 2) >= na)
			d -= na;
		k++;
	}
	*n = k;
	return i;
}

/* Doubles the entry arrays, up to this fill's max_items. */
static int
grow_items(struct spatial_hash *h)
{
	size_t cap = h->itemcap ? 2 * h->itemcap : 256;
	int *p;

	if (cap > h->maxitems)
		cap = h->maxitems;
	if (cap > SIZE_MAX / sizeof *p)
		return -1;
	if ((p = realloc(h->item, cap * sizeof *p)) == NULL)
		return -1;
	h->item = p;
	if ((p = realloc(h->next, cap * sizeof *p)) == NULL)
		return -1;
	h->next = p;
	h->itemcap = cap;
	return 0;
}

int
hash_insert(struct spatial_hash *h, int64_t key, int item)
{
	struct hash_cube *c;
	size_t i;
	int n, e;

	/* more cubes than min(N_box, max_items) would break the load bound */
	if (h->nitems >= h->maxitems || key < 0 || key >= h->nbox)
		return -1;
	if (h->nitems == h->itemcap && grow_items(h) != 0)
		return -1;
	i = probe(h, key, &n);
	c = &h->slot[i];
	if (c->key == -1) {
		c->key = key;
		c->count = 0;
		c->head = c->tail = -1;
		h->filled[h->nfilled++] = (int)i;
	}
	e = (int)h->nitems++;
	h->item[e] = item;
	h->next[e] = -1;
	if (c->tail >= 0)
		h->next[c->tail] = e;
	else
		c->head = e;
	c->tail = e;
	c->count++;
	h->probes += n;
	h->inserts++;
	if (n > h->probe_max)
		h->probe_max = n;
	return 0;
}

const struct hash_cube *
hash_find(const struct spatial_hash *h, int64_t key)
{
	size_t i;
	int n;

	/* -1 would match an empty slot */
	if (h->narray == 0 || key < 0 || key >= h->nbox)
		return NULL;
	i = probe(h, key, &n);
	return h->slot[i].key == key ? &h->slot[i] : NULL;
}

void
hash_stats(const struct spatial_hash *h, struct hash_stats *s)
{
	size_t i;
	int k;

	memset(s, 0, sizeof *s);
	s->entries = (long)h->nitems;
	s->cubes = (long)h->nfilled;
	for (i = 0; i < h->nfilled; i++) {
		k = h->slot[h->filled[i]].count;
		if (k >= 2)
			s->shared++;
		s->hist[(k < HASH_HIST ? k : HASH_HIST) - 1]++;
	}
	s->load = h->narray ? (double)s->cubes / (double)h->narray : 0;
	s->probe_mean = h->inserts ? (double)h->probes / (double)h->inserts : 0;
	s->probe_max = h->probe_max;
}

void
hash_stats_add(struct hash_stats *sum, const struct hash_stats *s)
{
	int k;

	sum->entries += s->entries;
	sum->cubes += s->cubes;
	sum->shared += s->shared;
	sum->load += s->load;
	sum->probe_mean += s->probe_mean;
	if (s->probe_max > sum->probe_max)
		sum->probe_max = s->probe_max;
	for (k = 0; k < HASH_HIST; k++)
		sum->hist[k] += s->hist[k];
}

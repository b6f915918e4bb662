/* test_hash.c: the spatial enumeration hash table (§3.3, eq. 18-20). */
#include "testutil.h"

#include <limits.h>

#include "hash.h"

static int
prime(size_t n)
{
	size_t i;

	if (n < 2)
		return 0;
	for (i = 2; i * i <= n; i++)
		if (n % i == 0)
			return 0;
	return 1;
}

static void
begin_ok(struct spatial_hash *h, double cell, vec3 lo, vec3 hi, size_t max_items)
{
	if (hash_begin(h, cell, lo, hi, max_items) != 0)
		fail_msg("hash_begin(cell %g, max_items %zu) failed", cell, max_items);
}

static void
insert_ok(struct spatial_hash *h, int64_t key, int item)
{
	if (hash_insert(h, key, item) != 0)
		fail_msg("hash_insert(key %lld, item %d) failed", (long long)key, item);
}

/* Does item sit in cube c's chain? */
static int
in_cube(const struct spatial_hash *h, const struct hash_cube *c, int item)
{
	int e;

	for (e = c->head; e >= 0; e = h->next[e])
		if (h->item[e] == item)
			return 1;
	return 0;
}

/* hash_stats against a count of its own over the filled cubes. */
static void
check_stats(const struct spatial_hash *h)
{
	struct hash_stats s;
	long hist[HASH_HIST] = { 0 }, shared = 0, entries = 0, sum = 0, big = 0;
	size_t i;
	int k, e, n;

	hash_stats(h, &s);
	for (i = 0; i < h->nfilled; i++) {
		const struct hash_cube *c = &h->slot[h->filled[i]];

		assert_true(c->key >= 0 && c->key < h->nbox);
		assert_ptr_equal(hash_find(h, c->key), c);
		for (n = 0, e = c->head; e >= 0; e = h->next[e])
			n++;
		assert_int_equal(n, c->count);
		assert_true(c->count >= 1);
		assert_int_equal(h->next[c->tail], -1);
		entries += c->count;
		shared += c->count >= 2;
		hist[(c->count < HASH_HIST ? c->count : HASH_HIST) - 1]++;
		if (c->count >= HASH_HIST)
			big += c->count;
	}
	assert_int_equal(s.entries, (long)h->nitems);
	assert_int_equal(s.entries, entries);
	assert_int_equal(s.cubes, (long)h->nfilled);
	assert_int_equal(s.shared, shared);
	for (k = 0; k < HASH_HIST; k++) {
		assert_int_equal(s.hist[k], hist[k]);
		sum += s.hist[k];
	}
	assert_int_equal(sum, s.cubes);
	/* sum of k*hist[k-1] over the exact buckets, plus the >= HASH_HIST cubes */
	for (sum = 0, k = 1; k < HASH_HIST; k++)
		sum += k * s.hist[k - 1];
	assert_int_equal(sum + big, s.entries);
	if (s.hist[HASH_HIST - 1] == 0)
		assert_int_equal(sum, s.entries);
	assert_double_equal(s.load, (double)s.cubes / (double)h->narray, 1e-15);
	assert_true(s.load <= 0.5);
	if (s.entries > 0) {
		assert_true(s.probe_mean >= 1);
		assert_true(s.probe_max >= 1);
		assert_true(s.probe_max >= s.probe_mean);
	}
}

static void
test_init_free(void **state)
{
	struct spatial_hash h;
	struct hash_stats s;

	(void)state;
	hash_init(&h);
	assert_null(hash_find(&h, 0));
	assert_int_equal(hash_insert(&h, 0, 1), -1);
	hash_stats(&h, &s);
	assert_int_equal(s.entries, 0);
	assert_int_equal(s.cubes, 0);
	assert_double_equal(s.load, 0, 0);
	assert_double_equal(s.probe_mean, 0, 0);
	hash_free(&h);
	hash_free(&h);
}

/* eq. 18 on hand-computed cubes: lo (1,2,3), cell 1, 4 x 2 x 3 cubes. */
static void
test_keys(void **state)
{
	static const struct {
		double p[3];
		int d[3];
		int64_t key;
	} t[] = {
		{ { 1, 2, 3 }, { 0, 0, 0 }, 0 },
		{ { 2.5, 3.2, 4.9 }, { 1, 1, 1 }, 1 + 4 * 1 + 12 * 1 },
		{ { 3.999, 2.999, 4.0 }, { 2, 0, 1 }, 2 + 4 * 1 + 12 * 0 },
		{ { 1.5, 3.0, 3.5 }, { 0, 1, 0 }, 0 + 4 * 0 + 12 * 1 },
		/* hi itself is in the last cube */
		{ { 4.5, 3.5, 5.2 }, { 3, 1, 2 }, 3 + 4 * 2 + 12 * 1 },
		/* clamped: below lo, beyond hi */
		{ { 0.9, 1.0, 100 }, { 0, 0, 2 }, 0 + 4 * 2 + 12 * 0 },
		{ { 4.5 + 1e-12, 3.5 + 1e-12, 5.2 + 1e-12 }, { 3, 1, 2 }, 23 },
		{ { -1e300, 1e300, 3.5 }, { 0, 1, 0 }, 12 },
		{ { NAN, 2.5, 3.5 }, { 0, 0, 0 }, 0 },
	};
	struct spatial_hash h;
	size_t i;
	int d[3];

	(void)state;
	hash_init(&h);
	begin_ok(&h, 1, v3(1, 2, 3), v3(4.5, 3.5, 5.2), 10);
	assert_int_equal(h.nx, 4);
	assert_int_equal(h.ny, 2);
	assert_int_equal(h.nz, 3);
	assert_int_equal(h.ncpl, 4);
	assert_int_equal(h.ncpp, 12);
	assert_int_equal(h.nbox, 24);
	for (i = 0; i < sizeof t / sizeof t[0]; i++) {
		hash_cube_of(&h, v3(t[i].p[0], t[i].p[1], t[i].p[2]), d);
		if (d[0] != t[i].d[0] || d[1] != t[i].d[1] || d[2] != t[i].d[2])
			fail_msg("point %zu: cube (%d,%d,%d), expected (%d,%d,%d)", i,
			    d[0], d[1], d[2], t[i].d[0], t[i].d[1], t[i].d[2]);
		assert_int_equal(hash_key(&h, d[0], d[1], d[2]), t[i].key);
	}
	hash_free(&h);
}

/* Negative coordinates, and the keys of all cubes are 0 .. N_box-1, once each. */
static void
test_keys_cover(void **state)
{
	struct spatial_hash h;
	unsigned char seen[5 * 3 * 7] = { 0 };
	int dx, dy, dz, d[3];
	int64_t k;

	(void)state;
	hash_init(&h);
	begin_ok(&h, 0.5, v3(-2, -1, -3), v3(0.4, 0.2, 0.1), 1000);
	assert_int_equal(h.nx, 5);
	assert_int_equal(h.ny, 3);
	assert_int_equal(h.nz, 7);
	assert_int_equal(h.nbox, 105);
	hash_cube_of(&h, v3(-1.6, -0.1, -0.01), d);
	assert_int_equal(d[0], 0);
	assert_int_equal(d[1], 1);
	assert_int_equal(d[2], 5);
	for (dy = 0; dy < h.ny; dy++)
		for (dz = 0; dz < h.nz; dz++)
			for (dx = 0; dx < h.nx; dx++) {
				k = hash_key(&h, dx, dy, dz);
				assert_int_equal(k, dx + 5 * dz + 35 * dy);
				assert_true(k >= 0 && k < h.nbox);
				assert_int_equal(seen[k], 0);
				seen[k] = 1;
			}
	hash_free(&h);
}

/* eq. 19 */
static void
test_index(void **state)
{
	struct spatial_hash h;
	int64_t k;

	(void)state;
	hash_init(&h);
	begin_ok(&h, 1, v3(0, 0, 0), v3(99.5, 99.5, 99.5), 500);
	assert_int_equal(h.narray, 1009);
	for (k = 0; k < h.nbox; k += 37) {
		assert_int_equal(hash_index(&h, k), (size_t)(k % 1009));
		assert_true(hash_index(&h, k) < h.narray);
	}
	hash_free(&h);
}

/*
 * eq. 20: eleven keys with one h_0 = 20 in a table of N_array = 23 land in
 * h_0, h_0+1, h_0+1+3, h_0+1+3+5, ... (mod 23), the j-th after j+1 probes.
 */
static void
test_probe_sequence(void **state)
{
	static const size_t want[] = { 20, 21, 1, 6, 13, 22, 10, 0, 15, 9, 5 };
	struct spatial_hash h;
	struct hash_stats s;
	size_t slot, d, j;
	int64_t key;

	(void)state;
	hash_init(&h);
	begin_ok(&h, 1, v3(0, 0, 0), v3(99.5, 99.5, 99.5), 11);
	assert_int_equal(h.narray, 23);
	for (j = 0, slot = 20, d = 1; j < 11; j++) {
		assert_int_equal(slot, want[j]);
		key = 20 + 23 * (int64_t)j;
		assert_int_equal(hash_index(&h, key), 20);
		insert_ok(&h, key, (int)j);
		assert_int_equal(h.filled[j], (int)want[j]);
		assert_int_equal(h.slot[want[j]].key, key);
		assert_int_equal(h.probe_max, (int)j + 1);
		slot = (slot + d) % 23;
		d += 2;
	}
	for (j = 0; j < 11; j++)
		assert_ptr_equal(hash_find(&h, 20 + 23 * (int64_t)j), &h.slot[want[j]]);
	/* a key with the same h_0 that is not there: found absent */
	assert_null(hash_find(&h, 20 + 23 * 11));
	hash_stats(&h, &s);
	assert_int_equal(s.probe_max, 11);
	assert_double_equal(s.probe_mean, 66.0 / 11, 1e-15);
	check_stats(&h);
	hash_free(&h);
}

/* Items come back in their cube, in insertion order. */
static void
test_found_in_order(void **state)
{
	static const struct {
		int d[3], item;
	} t[] = {
		{ { 1, 2, 3 }, 10 }, { { 9, 9, 9 }, 11 }, { { 1, 2, 3 }, 12 },
		{ { 0, 0, 0 }, 13 }, { { 9, 9, 9 }, 14 }, { { 1, 2, 3 }, 15 },
		{ { 4, 0, 7 }, 16 },
	};
	static const int chain[] = { 10, 12, 15 };
	struct spatial_hash h;
	const struct hash_cube *c;
	size_t i;
	int e, n;

	(void)state;
	hash_init(&h);
	begin_ok(&h, 0.1, v3(0, 0, 0), v3(0.95, 0.95, 0.95), 100);
	assert_int_equal(h.nbox, 1000);
	for (i = 0; i < sizeof t / sizeof t[0]; i++)
		insert_ok(&h, hash_key(&h, t[i].d[0], t[i].d[1], t[i].d[2]), t[i].item);
	for (i = 0; i < sizeof t / sizeof t[0]; i++) {
		c = hash_find(&h, hash_key(&h, t[i].d[0], t[i].d[1], t[i].d[2]));
		assert_non_null(c);
		assert_true(in_cube(&h, c, t[i].item));
	}
	c = hash_find(&h, hash_key(&h, 1, 2, 3));
	assert_int_equal(c->count, 3);
	for (n = 0, e = c->head; e >= 0; e = h.next[e], n++)
		assert_int_equal(h.item[e], chain[n]);
	assert_int_equal(n, 3);
	assert_int_equal(h.item[c->tail], 15);
	assert_int_equal(hash_find(&h, hash_key(&h, 9, 9, 9))->count, 2);
	assert_null(hash_find(&h, hash_key(&h, 1, 2, 4)));
	/* filled: in order of first insertion */
	assert_int_equal(h.nfilled, 4);
	assert_int_equal(h.slot[h.filled[0]].key, hash_key(&h, 1, 2, 3));
	assert_int_equal(h.slot[h.filled[1]].key, hash_key(&h, 9, 9, 9));
	assert_int_equal(h.slot[h.filled[2]].key, hash_key(&h, 0, 0, 0));
	assert_int_equal(h.slot[h.filled[3]].key, hash_key(&h, 4, 0, 7));
	check_stats(&h);
	hash_free(&h);
}

/* N_array: the smallest prime >= 2*min(N_box, max_items), at least 2. */
static void
test_narray(void **state)
{
	static const double cells[] = { 10, 1, 0.25, 0.01 };
	struct spatial_hash h;
	size_t m, need, p, ci;

	(void)state;
	hash_init(&h);
	for (ci = 0; ci < sizeof cells / sizeof cells[0]; ci++)
		for (m = 0; m < 3000; m += m < 40 ? 1 : 97) {
			begin_ok(&h, cells[ci], v3(0, 0, 0), v3(1, 2, 3), m);
			need = 2 * ((size_t)h.nbox < m ? (size_t)h.nbox : m);
			assert_true(prime(h.narray));
			assert_true(h.narray >= need);
			assert_true(h.narray >= 2);
			for (p = need; p < h.narray; p++)
				assert_false(prime(p));
		}
	/* one cube: N_array 2 whatever max_items */
	begin_ok(&h, 10, v3(0, 0, 0), v3(1, 2, 3), 1000000);
	assert_int_equal(h.nbox, 1);
	assert_int_equal(h.narray, 2);
	/* an empty box (lo > hi, as from no points) is one cube */
	begin_ok(&h, 1, v3(INFINITY, INFINITY, INFINITY), v3(-INFINITY, -INFINITY, -INFINITY), 5);
	assert_int_equal(h.nbox, 1);
	insert_ok(&h, 0, 7);
	assert_int_equal(hash_find(&h, 0)->count, 1);
	hash_free(&h);
}

/* Hand-filled cubes of 1, 1, 2, 3 and 9 entries. */
static void
test_stats(void **state)
{
	static const int counts[] = { 1, 1, 2, 3, 9 };
	struct spatial_hash h;
	struct hash_stats s;
	size_t i;
	int j, item = 0;

	(void)state;
	hash_init(&h);
	begin_ok(&h, 1, v3(0, 0, 0), v3(9, 9, 9), 100);
	assert_int_equal(h.narray, 211);
	for (i = 0; i < 5; i++)
		for (j = 0; j < counts[i]; j++)
			insert_ok(&h, hash_key(&h, (int)i, (int)i, 2), item++);
	hash_stats(&h, &s);
	assert_int_equal(s.entries, 16);
	assert_int_equal(s.cubes, 5);
	assert_int_equal(s.shared, 3);
	assert_int_equal(s.hist[0], 2);
	assert_int_equal(s.hist[1], 1);
	assert_int_equal(s.hist[2], 1);
	for (j = 3; j < HASH_HIST - 1; j++)
		assert_int_equal(s.hist[j], 0);
	assert_int_equal(s.hist[HASH_HIST - 1], 1);
	assert_double_equal(s.load, 5.0 / 211, 1e-15);
	/* no collisions in the table: one probe each */
	assert_double_equal(s.probe_mean, 1, 0);
	assert_int_equal(s.probe_max, 1);
	check_stats(&h);

	/* without a cube of >= HASH_HIST: sum of k*hist == entries */
	begin_ok(&h, 1, v3(0, 0, 0), v3(9, 9, 9), 100);
	for (i = 0, item = 0; i < 4; i++)
		for (j = 0; j < counts[i]; j++)
			insert_ok(&h, hash_key(&h, 3, (int)i, 1), item++);
	hash_stats(&h, &s);
	assert_int_equal(s.hist[HASH_HIST - 1], 0);
	assert_int_equal(1 * s.hist[0] + 2 * s.hist[1] + 3 * s.hist[2], s.entries);
	check_stats(&h);
	hash_free(&h);
}

/* A second fill forgets the first; same-size fills reuse the slots. */
static void
test_refill(void **state)
{
	struct spatial_hash h;
	struct hash_stats s;
	struct hash_cube *slot;
	size_t i;
	int k;

	(void)state;
	hash_init(&h);
	begin_ok(&h, 1, v3(0, 0, 0), v3(9, 9, 9), 50);
	for (k = 0; k < 50; k++)
		insert_ok(&h, 7 * k, k);
	check_stats(&h);
	slot = h.slot;

	begin_ok(&h, 1, v3(0, 0, 0), v3(9, 9, 9), 50);
	assert_ptr_equal(h.slot, slot);
	assert_int_equal(h.nfilled, 0);
	assert_int_equal(h.nitems, 0);
	for (i = 0; i < h.slotcap; i++)
		assert_int_equal(h.slot[i].key, -1);
	for (k = 0; k < 50; k++)
		assert_null(hash_find(&h, 7 * k));
	hash_stats(&h, &s);
	assert_int_equal(s.entries, 0);
	assert_int_equal(s.cubes, 0);
	assert_int_equal(s.probe_max, 0);
	for (k = 0; k < 20; k++)
		insert_ok(&h, 3 + 11 * k, 100 + k);
	for (k = 0; k < 20; k++) {
		assert_non_null(hash_find(&h, 3 + 11 * k));
		assert_int_equal(hash_find(&h, 3 + 11 * k)->count, 1);
		assert_int_equal(h.item[hash_find(&h, 3 + 11 * k)->head], 100 + k);
	}
	assert_null(hash_find(&h, 7));
	check_stats(&h);

	/* a bigger fill grows the table, then a smaller one */
	begin_ok(&h, 0.1, v3(0, 0, 0), v3(9, 9, 9), 5000);
	assert_true(h.slotcap >= h.narray);
	for (k = 0; k < 5000; k++)
		insert_ok(&h, 131 * (int64_t)k, k);
	for (k = 0; k < 5000; k++)
		assert_true(in_cube(&h, hash_find(&h, 131 * (int64_t)k), k));
	check_stats(&h);
	begin_ok(&h, 1, v3(0, 0, 0), v3(9, 9, 9), 50);
	for (i = 0; i < h.slotcap; i++)
		assert_int_equal(h.slot[i].key, -1);
	insert_ok(&h, 999, 1);
	assert_int_equal(hash_find(&h, 999)->count, 1);
	check_stats(&h);
	hash_free(&h);
}

/* More than max_items insertions, and keys outside [0, N_box), fail. */
static void
test_limits(void **state)
{
	struct spatial_hash h;

	(void)state;
	hash_init(&h);
	begin_ok(&h, 1, v3(0, 0, 0), v3(9, 9, 9), 3);
	insert_ok(&h, 5, 0);
	insert_ok(&h, 5, 1);
	insert_ok(&h, 6, 2);
	assert_int_equal(hash_insert(&h, 5, 3), -1);
	assert_int_equal(hash_insert(&h, 7, 3), -1);
	assert_int_equal(h.nitems, 3);
	assert_int_equal(hash_find(&h, 5)->count, 2);
	check_stats(&h);

	begin_ok(&h, 1, v3(0, 0, 0), v3(9, 9, 9), 3);
	assert_int_equal(hash_insert(&h, -1, 0), -1);
	assert_int_equal(hash_insert(&h, h.nbox, 0), -1);
	assert_int_equal(h.nitems, 0);
	insert_ok(&h, h.nbox - 1, 0);
	assert_null(hash_find(&h, -1));
	assert_null(hash_find(&h, h.nbox));
	assert_non_null(hash_find(&h, h.nbox - 1));
	hash_free(&h);
}

static uint64_t
xorshift(uint64_t *s)
{
	*s ^= *s << 13;
	*s ^= *s >> 7;
	*s ^= *s << 17;
	return *s;
}

static double
uniform(uint64_t *s)
{
	return (double)(xorshift(s) >> 11) / 9007199254740992.0;
}

/*
 * n random points in [-1,2] x [0,0.5] x [3,4], hashed by their cube in
 * their bounding box as the broad phase does; each item is in exactly one
 * cube, that cube is the one of its point, and hash_find finds it.
 */
static void
random_fill(double cell, int n)
{
	struct spatial_hash h;
	double *x = malloc((size_t)3 * n * sizeof *x);
	const struct hash_cube **where = calloc((size_t)n, sizeof *where);
	uint64_t rng = 0x9e3779b97f4a7c15ULL;
	vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
	size_t i;
	int d[3], k, e;
	int64_t key;

	assert_non_null(x);
	assert_non_null(where);
	for (k = 0; k < n; k++) {
		x[3 * k] = -1 + 3 * uniform(&rng);
		x[3 * k + 1] = 0.5 * uniform(&rng);
		x[3 * k + 2] = 3 + uniform(&rng);
		lo = v3(fmin(lo.x, x[3 * k]), fmin(lo.y, x[3 * k + 1]), fmin(lo.z, x[3 * k + 2]));
		hi = v3(fmax(hi.x, x[3 * k]), fmax(hi.y, x[3 * k + 1]), fmax(hi.z, x[3 * k + 2]));
	}
	hash_init(&h);
	begin_ok(&h, cell, lo, hi, (size_t)n);
	assert_true(prime(h.narray));
	assert_true(h.narray >= 2 * (size_t)(h.nbox < n ? h.nbox : n));
	for (k = 0; k < n; k++) {
		hash_cube_of(&h, v3_load(x + 3 * k), d);
		insert_ok(&h, hash_key(&h, d[0], d[1], d[2]), k);
	}
	for (i = 0; i < h.nfilled; i++) {
		const struct hash_cube *c = &h.slot[h.filled[i]];

		for (e = c->head; e >= 0; e = h.next[e]) {
			k = h.item[e];
			assert_true(k >= 0 && k < n);
			assert_null(where[k]);
			where[k] = c;
		}
	}
	for (k = 0; k < n; k++) {
		hash_cube_of(&h, v3_load(x + 3 * k), d);
		key = hash_key(&h, d[0], d[1], d[2]);
		if (where[k] == NULL || where[k]->key != key || hash_find(&h, key) != where[k])
			fail_msg("point %d not found in its cube", k);
	}
	check_stats(&h);
	hash_free(&h);
	free(x);
	free(where);
}

/* 10^5 points in ~1.5e6 small cubes: mostly one per cube. */
static void
test_random_sparse(void **state)
{
	struct spatial_hash h;

	(void)state;
	random_fill(0.01, 100000);
	/* N_box ~ 300*50*100 > max_items: N_array = the prime after 2*10^5 */
	hash_init(&h);
	begin_ok(&h, 0.01, v3(-1, 0, 3), v3(2, 0.5, 4), 100000);
	assert_true(h.nbox > 100000);
	assert_int_equal(h.narray, 200003);
	hash_free(&h);
}

/* 10^5 points in a few big cubes: every cube crowded, N_array from N_box. */
static void
test_random_crowded(void **state)
{
	(void)state;
	random_fill(0.5, 100000);
	random_fill(0.05, 100000);
}

/* N_box over int64 fails cleanly; the table works after a good hash_begin. */
static void
test_overflow(void **state)
{
	struct spatial_hash h;
	struct hash_stats s;

	(void)state;
	hash_init(&h);
	begin_ok(&h, 1, v3(0, 0, 0), v3(9, 9, 9), 10);
	insert_ok(&h, 42, 1);

	/* 3e6 cubes a side: each fits an int, 2.7e19 cubes do not fit int64 */
	assert_int_equal(hash_begin(&h, 1, v3(0, 0, 0), v3(3e6, 3e6, 3e6), 10), -1);
	assert_int_equal(h.narray, 0);
	assert_null(hash_find(&h, 42));
	assert_int_equal(hash_insert(&h, 42, 1), -1);
	hash_stats(&h, &s);
	assert_int_equal(s.entries, 0);
	assert_int_equal(s.cubes, 0);
	/* one side over INT_MAX cubes, infinite sides, bad cells */
	assert_int_equal(hash_begin(&h, 1, v3(0, 0, 0), v3(1e10, 1, 1), 10), -1);
	assert_int_equal(hash_begin(&h, 1, v3(0, 0, 0), v3(INFINITY, 1, 1), 10), -1);
	assert_int_equal(hash_begin(&h, 1, v3(-INFINITY, 0, 0), v3(1, 1, 1), 10), -1);
	assert_int_equal(hash_begin(&h, 0, v3(0, 0, 0), v3(1, 1, 1), 10), -1);
	assert_int_equal(hash_begin(&h, -1, v3(0, 0, 0), v3(1, 1, 1), 10), -1);
	assert_int_equal(hash_begin(&h, NAN, v3(0, 0, 0), v3(1, 1, 1), 10), -1);
	assert_int_equal(hash_begin(&h, INFINITY, v3(0, 0, 0), v3(1, 1, 1), 10), -1);

	/* 2e6 cubes a side: 8e18 fits; the largest key hashes and is found */
	begin_ok(&h, 1, v3(0, 0, 0), v3(2e6 - 0.5, 2e6 - 0.5, 2e6 - 0.5), 10);
	assert_int_equal(h.nbox, INT64_C(8000000000000000000));
	assert_int_equal(h.narray, 23);
	insert_ok(&h, h.nbox - 1, 1);
	insert_ok(&h, hash_key(&h, 1999999, 1999999, 0), 2);
	insert_ok(&h, 42, 3);
	assert_int_equal(hash_index(&h, h.nbox - 1), (size_t)((h.nbox - 1) % 23));
	assert_int_equal(h.item[hash_find(&h, h.nbox - 1)->head], 1);
	assert_int_equal(h.item[hash_find(&h, 42)->head], 3);
	check_stats(&h);

	/* and after a failure, a normal fill */
	assert_int_equal(hash_begin(&h, 1e-9, v3(0, 0, 0), v3(1e3, 1e3, 1e3), 10), -1);
	begin_ok(&h, 1, v3(0, 0, 0), v3(9, 9, 9), 10);
	insert_ok(&h, 42, 5);
	assert_int_equal(hash_find(&h, 42)->count, 1);
	assert_int_equal(h.item[hash_find(&h, 42)->head], 5);
	check_stats(&h);
	hash_free(&h);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_init_free),
		cmocka_unit_test(test_keys),
		cmocka_unit_test(test_keys_cover),
		cmocka_unit_test(test_index),
		cmocka_unit_test(test_probe_sequence),
		cmocka_unit_test(test_found_in_order),
		cmocka_unit_test(test_narray),
		cmocka_unit_test(test_stats),
		cmocka_unit_test(test_refill),
		cmocka_unit_test(test_limits),
		cmocka_unit_test(test_random_sparse),
		cmocka_unit_test(test_random_crowded),
		cmocka_unit_test(test_overflow),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}

/* broad.c: the broad phase's search: the pair lists and their order, the
 * errors, and the state each mode keeps (broad_impl.h); the modes' own
 * searches are broad_brute.c, broad_seed.c, broad_grid.c and broad_bvh.c. */
#include <stdlib.h>
#include <string.h>

#include "broad_impl.h"

const char *const broad_mode_name[] = { "seed", "grid", "brute", "bvh", NULL };

bool
broad_uses_hash(enum broad_mode mode)
{
	return mode == BROAD_SEED || mode == BROAD_GRID;
}

bool
broad_boxes_exact(enum broad_mode mode)
{
	return mode == BROAD_BVH;
}

struct broad *
broad_new(enum broad_mode mode)
{
	struct broad *b = calloc(1, sizeof *b);

	if (b == NULL)
		return NULL;
	b->mode = mode;
	hash_init(&b->seed.hash);
	hash_init(&b->grid.hash);
	hash_init(&b->grid.hash_edges);
	return b;
}

void
broad_free(struct broad *b)
{
	if (b == NULL)
		return;
	hash_free(&b->seed.hash);
	broad_grid_free(b);
	broad_bvh_free(b);
	free(b->vt);
	free(b->ee);
	free(b->allowed);
	free(b);
}

void
broad_set_memory_limit(struct broad *b, double bytes)
{
	b->memory_limit = bytes;
}

void
broad_set_stop(struct broad *b, const volatile sig_atomic_t *flag)
{
	b->stop = flag;
}

const struct vt_pair *
broad_vt(const struct broad *b, size_t *n)
{
	*n = b->nvt;
	return b->vt;
}

const struct ee_pair *
broad_ee(const struct broad *b, size_t *n)
{
	*n = b->nee;
	return b->ee;
}

void
broad_clear(struct broad *b)
{
	b->nvt = b->nee = 0;
}

bool
broad_stopped(const struct broad *b)
{
	return b->stopped;
}

const struct broad_stats *
broad_stats(const struct broad *b)
{
	return &b->st;
}

static int
cmp_vt(const void *pa, const void *pb)
{
	const struct vt_pair *a = pa, *b = pb;

	if (a->v != b->v)
		return a->v < b->v ? -1 : 1;
	return (a->t > b->t) - (a->t < b->t);
}

static int
cmp_ee(const void *pa, const void *pb)
{
	const struct ee_pair *a = pa, *b = pb;

	if (a->a != b->a)
		return a->a < b->a ? -1 : 1;
	return (a->b > b->b) - (a->b < b->b);
}

/* Pairs sorted between two polls of the stop flag: a few milliseconds. */
#define SORT_POLL_PAIRS 16384

/* Sorts the pairs of each run of one vertex (edge) by triangle (edge):
 * grid finds them vertex by vertex, in a few pairs a run, so insertion sort
 * beats a global sort. -1 when a signal asks to stop: a fast cloth's
 * millions of pairs take a quarter of a second to sort, too long to wait
 * for. */
static int
sort_runs(struct broad *b)
{
	size_t i, j, k, poll = 0;

	for (i = 0; i < b->nvt; i = j) {
		if (i >= poll) {
			if (stop_set(b->stop))
				return -1;
			poll = i + SORT_POLL_PAIRS;
		}
		for (j = i + 1; j < b->nvt && b->vt[j].v == b->vt[i].v; j++)
			;
		if (j - i > 32) {	/* a fast node's run: no quadratic sort */
			qsort(b->vt + i, j - i, sizeof *b->vt, cmp_vt);
			continue;
		}
		for (k = i + 1; k < j; k++) {
			struct vt_pair x = b->vt[k];
			size_t m = k;

			for (; m > i && b->vt[m - 1].t > x.t; m--)
				b->vt[m] = b->vt[m - 1];
			b->vt[m] = x;
		}
	}
	for (i = 0, poll = 0; i < b->nee; i = j) {
		if (i >= poll) {
			if (stop_set(b->stop))
				return -1;
			poll = i + SORT_POLL_PAIRS;
		}
		for (j = i + 1; j < b->nee && b->ee[j].a == b->ee[i].a; j++)
			;
		if (j - i > 32) {
			qsort(b->ee + i, j - i, sizeof *b->ee, cmp_ee);
			continue;
		}
		for (k = i + 1; k < j; k++) {
			struct ee_pair x = b->ee[k];
			size_t m = k;

			for (; m > i && b->ee[m - 1].b > x.b; m--)
				b->ee[m] = b->ee[m - 1];
			b->ee[m] = x;
		}
	}
	return 0;
}

/* Sorted and without repeats, so that the narrow phase's order, and with it
 * the run, does not depend on how the pairs were found. */
static void
canonical(struct broad *b)
{
	size_t i, k;

	if (b->nvt > 0)		/* qsort may not take a null array */
		qsort(b->vt, b->nvt, sizeof *b->vt, cmp_vt);
	for (i = k = 0; i < b->nvt; i++)
		if (k == 0 || b->vt[i].v != b->vt[k - 1].v || b->vt[i].t != b->vt[k - 1].t)
			b->vt[k++] = b->vt[i];
	b->nvt = k;
	if (b->nee > 0)
		qsort(b->ee, b->nee, sizeof *b->ee, cmp_ee);
	for (i = k = 0; i < b->nee; i++)
		if (k == 0 || b->ee[i].a != b->ee[k - 1].a || b->ee[i].b != b->ee[k - 1].b)
			b->ee[k++] = b->ee[i];
	b->nee = k;
}



int
broad_find(struct broad *b, const struct geom *g, double cell, const struct broad_want *want,
    struct drape_err *err)
{
	bool too_small = false;
	int rc;

	if (b->mode == BROAD_GRID && broad_grid_holds(b, g, cell, want)) {
		b->st.rebuilt = false;
		return 0;
	}
	b->grid.valid = false;
	b->stopped = b->over_memory = false;
	b->nvt = b->nee = 0;
	memset(&b->st, 0, sizeof b->st);
	b->st.rebuilt = true;
	b->st.cell = b->mode == BROAD_BRUTE ? 0 : cell;
	switch (b->mode) {
	case BROAD_SEED:
		rc = broad_find_seed(b, g, cell, want, &too_small);
		break;
	case BROAD_GRID:
		rc = broad_find_grid(b, g, cell, want);
		break;
	case BROAD_BVH:
		rc = broad_find_bvh(b, g, cell, want);
		break;
	default:
		rc = broad_find_brute(b, g, want);
		break;
	}
	if (rc == 0 && b->mode == BROAD_GRID)
		rc = sort_runs(b);	/* found vertex by vertex, each triangle once */
	if (rc != 0) {
		b->nvt = b->nee = 0;
		if (stop_set(b->stop)) {
			b->stopped = true;
			err_set(err, "broad phase: stopped by a signal");
		} else if (b->over_memory) {
			err_set(err, "broad phase: this step needs more than the %.0f MB that "
			    "[collision] memory allows (the scene's motion spans too much space "
			    "for its cubes, or the memory limit is too low)", b->memory_limit / 1e6);
		} else if (too_small) {
			err_set(err, "spatial hash: out of memory, or %g m cubes are too small for "
			    "the scene's extent", cell);
		} else {
			err_set(err, "broad phase: out of memory");
		}
		return -1;
	}
	if (b->mode == BROAD_SEED)
		canonical(b);
	b->st.vt_pairs = (long)b->nvt;
	b->st.ee_pairs = (long)b->nee;
	if (b->mode == BROAD_GRID)
		broad_grid_keep(b, g, cell, want);
	return 0;
}


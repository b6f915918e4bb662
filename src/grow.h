/* grow.h: an array grown by doubling, its size arithmetic checked */
#ifndef DRAPE_GROW_H
#define DRAPE_GROW_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

/* An empty array's first capacity, in items: no realloc for each of the
 * first few hundred, a few kilobytes at most. */
#define GROW_FIRST 256

/* Room at *p for need items of size bytes, *cap there now: the capacity
 * doubled from *cap (GROW_FIRST if 0) until it holds need, so that n
 * appends cost log n reallocs. Returns 0, or -1 out of memory or past
 * SIZE_MAX bytes, *p and *cap then as they were. Call it as
 * grow_array((void **)&a, &cap, n + 1, sizeof *a). */
static inline int
grow_array(void **p, size_t *cap, size_t need, size_t size)
{
	size_t n = *cap ? *cap : GROW_FIRST;
	void *np;

	if (need <= *cap)
		return 0;
	while (n < need) {
		if (n > SIZE_MAX / 2)
			return -1;
		n *= 2;
	}
	if (size == 0 || n > SIZE_MAX / size || (np = realloc(*p, n * size)) == NULL)
		return -1;
	*p = np;
	*cap = n;
	return 0;
}

#endif

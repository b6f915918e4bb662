/* evlog.c: per-node rings of contact events. */
#include <stdlib.h>
#include <string.h>

#include "evlog.h"

int
evlog_init(struct evlog *log, int nodes)
{
	memset(log, 0, sizeof *log);
	if (nodes < 1)
		return 0;
	log->ev = calloc((size_t)nodes * EVLOG_PER_NODE, sizeof *log->ev);
	log->count = calloc((size_t)nodes, sizeof *log->count);
	if (log->ev == NULL || log->count == NULL) {
		evlog_free(log);
		return -1;
	}
	log->n = nodes;
	return 0;
}

void
evlog_free(struct evlog *log)
{
	free(log->ev);
	free(log->count);
	memset(log, 0, sizeof *log);
}

void
evlog_clear(struct evlog *log)
{
	if (log->n > 0)
		memset(log->count, 0, (size_t)log->n * sizeof *log->count);
	log->total = 0;
}

void
evlog_copy(struct evlog *dst, const struct evlog *src)
{
	if (dst->n != src->n || src->n < 1)
		return;
	memcpy(dst->ev, src->ev, (size_t)src->n * EVLOG_PER_NODE * sizeof *dst->ev);
	memcpy(dst->count, src->count, (size_t)src->n * sizeof *dst->count);
	dst->total = src->total;
}

void
evlog_add(struct evlog *log, const struct contact_event *ev, size_t nev)
{
	size_t k;

	for (k = 0; k < nev; k++) {
		int p = ev[k].node;

		if (p < 0 || p >= log->n)
			continue;
		log->ev[(size_t)p * EVLOG_PER_NODE + (size_t)(log->count[p] % EVLOG_PER_NODE)] = ev[k];
		log->count[p]++;
		log->total++;
	}
}

const struct contact_event *
evlog_get(const struct evlog *log, int node, int k)
{
	long at;

	if (node < 0 || node >= log->n || k < 0 || k >= EVLOG_PER_NODE || k >= log->count[node])
		return NULL;
	at = (log->count[node] - 1 - k) % EVLOG_PER_NODE;
	return &log->ev[(size_t)node * EVLOG_PER_NODE + (size_t)at];
}

/* evlog.h: the latest contact events of every node, kept across steps (a
 * step's own events are gone at the next step), for the node inspector
 * and for finding a node's next event. */
#ifndef DRAPE_EVLOG_H
#define DRAPE_EVLOG_H

#include <stddef.h>

#include "event.h"

#define EVLOG_PER_NODE 4

struct evlog {
	int n;			/* nodes */
	struct contact_event *ev;	/* EVLOG_PER_NODE per node, a ring each */
	long *count;		/* per node: events ever logged */
	long total;
};

/* Returns 0, or -1 if out of memory (then the log is empty). */
int evlog_init(struct evlog *log, int nodes);
void evlog_free(struct evlog *log);

/* Forgets every event (a replay going back). */
void evlog_clear(struct evlog *log);

/* dst (of as many nodes) becomes a copy of src. */
void evlog_copy(struct evlog *dst, const struct evlog *src);

/* Logs a step's events (those of nodes out of range are skipped). */
void evlog_add(struct evlog *log, const struct contact_event *ev, size_t nev);

/* The node's k-th latest event (k = 0 the latest), or NULL. */
const struct contact_event *evlog_get(const struct evlog *log, int node, int k);

#endif

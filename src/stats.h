/* stats.h: the collision statistics of a step and of a run. The counters
 * are one table (stat_field): the accumulation, the replay codec, the run
 * summary and the TUI's panel all read it, so a new counter is one line
 * there and one name in enum stat_id. */
#ifndef DRAPE_STATS_H
#define DRAPE_STATS_H

#include <stdbool.h>

#include "hash.h"
#include "narrow.h"

/* In the order of the table, which is the replay codec's (drape-replay(5)). */
enum stat_id {
	STAT_NODE_PAIRS,	/* seed: pairs of nodes sharing a cube */
	STAT_VT_PAIRS,		/* vertex-triangle pairs the narrow phase got */
	STAT_EE_PAIRS,		/* edge-edge pairs */
	STAT_FILLS,		/* broad phase fills (grid keeps its pairs while they hold) */
	STAT_NARROW_TESTS,
	STAT_CONTACTS,		/* CONTACT_NTYPES of them, by enum contact_type */
	STAT_CORRECTIONS = STAT_CONTACTS + CONTACT_NTYPES,	/* node corrections */
	STAT_PASSES,		/* ccd: detect-and-correct passes (a run: the most) */
	STAT_FROZEN,		/* ccd: nodes put back to step k (fast: its window's start) as a last resort */
	STAT_UNRESOLVED,	/* steps with contacts left at the pass limit */
	STAT_COUNT
};

enum stat_add {
	STAT_SUM,		/* a run's is the sum of its steps' */
	STAT_MAX,		/* a run's is the largest of its steps' */
};

struct stat_field {
	const char *name;	/* stable, for machine-readable output */
	const char *label;	/* for people: the summary and the panel */
	enum stat_add add;
	bool panel;		/* shown in the TUI's collision panel */
};

extern const struct stat_field stat_field[STAT_COUNT];

struct collide_stats {
	long n[STAT_COUNT];
	double cell;		/* L_ce of the broad phase's latest fill, m */
	/* a step's: the latest fill's; a run's: the sum over its fills (the
	 * largest probe_max), for means per fill */
	struct hash_stats hash;
};

/* total += step, by each counter's rule; the hash statistics are added
 * when the step filled the hash. */
void stats_add(struct collide_stats *total, const struct collide_stats *step);

#endif

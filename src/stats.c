/* stats.c: the table of collision counters. */
#include "stats.h"

_Static_assert(CONTACT_NODE_NODE == 0 && CONTACT_OBSTACLE == CONTACT_NTYPES - 1,
    "STAT_CONTACTS + type indexes the contact counters");

const struct stat_field stat_field[STAT_COUNT] = {
	[STAT_NODE_PAIRS] = { "node_pairs", "node pairs", STAT_SUM, false },
	[STAT_VT_PAIRS] = { "vt_pairs", "vt pairs", STAT_SUM, true },
	[STAT_EE_PAIRS] = { "ee_pairs", "ee pairs", STAT_SUM, true },
	[STAT_FILLS] = { "fills", "fills", STAT_SUM, false },
	[STAT_NARROW_TESTS] = { "narrow_tests", "narrow tests", STAT_SUM, true },
	[STAT_CONTACTS + CONTACT_NODE_NODE] = { "node_node", "node-node", STAT_SUM, true },
	[STAT_CONTACTS + CONTACT_NODE_EDGE] = { "node_edge", "node-edge", STAT_SUM, true },
	[STAT_CONTACTS + CONTACT_NODE_FACE] = { "node_face", "node-face", STAT_SUM, true },
	[STAT_CONTACTS + CONTACT_EDGE_EDGE] = { "edge_edge", "edge-edge", STAT_SUM, true },
	[STAT_CONTACTS + CONTACT_OBSTACLE] = { "obstacle", "obstacle", STAT_SUM, true },
	[STAT_CORRECTIONS] = { "corrections", "corrections", STAT_SUM, true },
	[STAT_PASSES] = { "passes", "passes", STAT_MAX, true },
	[STAT_FROZEN] = { "frozen", "frozen", STAT_SUM, true },
	[STAT_UNRESOLVED] = { "unresolved", "unresolved", STAT_SUM, false },
};

void
stats_add(struct collide_stats *total, const struct collide_stats *step)
{
	int k;

	for (k = 0; k < STAT_COUNT; k++)
		if (stat_field[k].add == STAT_MAX)
			total->n[k] = step->n[k] > total->n[k] ? step->n[k] : total->n[k];
		else
			total->n[k] += step->n[k];
	if (step->n[STAT_FILLS] > 0)
		hash_stats_add(&total->hash, &step->hash);
}

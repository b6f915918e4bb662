/* event.h: a contact of a step, as the collision stages keep it and the
 * stepper reports it: which node, against what, where, and its velocity
 * along the normal before and after. Its own header so that the stepper's
 * callers see an event without the collision stages' state. */
#ifndef DRAPE_EVENT_H
#define DRAPE_EVENT_H

#include "vec3.h"

/* Its kind; the names are narrow.c's (the chapter's test gives the first
 * three). */
enum contact_type {
	CONTACT_NODE_NODE,	/* Q on a vertex of the triangle */
	CONTACT_NODE_EDGE,	/* Q on an edge: an angle about Q is pi */
	CONTACT_NODE_FACE,	/* Q inside the face */
	CONTACT_EDGE_EDGE,	/* r is an edge F-D and D did not cross itself */
	CONTACT_OBSTACLE,	/* a node in an analytic obstacle */
};
#define CONTACT_NTYPES 5

extern const char *const contact_type_name[CONTACT_NTYPES];

/* A step's number as drape shows it. A step record's and an event's step k
 * (in memory and in replay files) is the step from state k to state k + 1;
 * it is shown as k + 1, the state it led to, which the status line then
 * shows ("step 37"): shown as k, an event appeared one step before its
 * own in the inspector, and a replay's "step 36" listed none of the
 * events drape events gave for step 36. */
static inline long
step_shown(long step)
{
	return step + 1;
}

struct contact_event {
	long step;		/* from 0: shown as step_shown(step) */
	int node;		/* the corrected cloth node */
	enum contact_type type;
	int other;		/* triangle or edge (by type) of the geometry, or -1 */
	int obstacle;		/* the scene's obstacle, or -1 for the cloth itself */
	vec3 q, n;		/* contact point and unit normal */
	double vn_before, vn_after;	/* the node's velocity along n */
};

#endif

/* network.h: the spring network a scene defines, built once and never
 * changed by a run: the cloth (nodes, masses, elements, triangles), the
 * nodes on prescribed motion, and the force model over them. A run (the
 * stepper) advances a state on it; a replay's viewer needs it alone, to
 * draw frames and to tell the forces at a keyframe. */
#ifndef DRAPE_NETWORK_H
#define DRAPE_NETWORK_H

#include "cloth.h"
#include "err.h"
#include "forces.h"
#include "prescribed.h"
#include "scene.h"

struct network {
	struct cloth cl;
	struct prescribed pr;	/* pr.held: per node, 1 if on prescribed motion */
	struct forces fo;
};

/* From a checked scene, which must outlive the network; the network must
 * not move once built (its parts point at each other). Returns 0, or -1
 * with a message. */
int network_build(struct network *net, const struct scene *sc, struct drape_err *err);
void network_free(struct network *net);

#endif

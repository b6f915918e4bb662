/* response.h: the collision response of the chapter's §3.2 (eq. 11-17):
 * a central, oblique impact of a node on a much heavier triangle, along
 * the triangle's normal at the contact point Q. */
#ifndef DRAPE_RESPONSE_H
#define DRAPE_RESPONSE_H

#include "vec3.h"

/* Where a corrected node goes (§3.2). */
enum position_policy {
	POSITION_KEEP,		/* the node stays where it was at step k (the chapter) */
	POSITION_Q,		/* the node moves to Q */
	POSITION_SLIDE,		/* step k's normal offset, this step's tangential motion */
};
extern const char *const position_policy_name[];	/* NULL-terminated, for the parser */

/* What a node put back at step k by keep moves at (§3.2). eq16 is the
 * chapter's: the velocity of eq. 16, whose tangential part the impact
 * leaves (eq. 17), although the position the node is given did not move
 * along the surface; in a resting contact the node is put back at every
 * step, and its velocity then gathers the forces on it while it cannot move
 * (the chapter's locking). surface gives it the contact point's velocity
 * instead, all of it, so that a node that stays where it was also moves
 * with the surface: what "no tangential displacement is allowed" means
 * for its velocity. */
enum keep_velocity { KEEP_VELOCITY_EQ16, KEEP_VELOCITY_SURFACE };
extern const char *const keep_velocity_name[];	/* NULL-terminated, for the parser */

/* Who takes a self-contact's impact with narrow = seed. node is the
 * chapter's: "M >> m forces the triangle to keep its velocity" (§3.2),
 * only the node is corrected. shared: the triangle is another part of the
 * same cloth, as heavy as the node, so the inelastic impulse is shared by
 * mass between the node and the triangle's vertices at Q (as ccd does),
 * momentum kept; with keep the triangle's vertices go back to step k as
 * well, so that the four nodes of the pair are where the network was
 * consistent. */
enum seed_response { SEED_RESPONSE_NODE, SEED_RESPONSE_SHARED };
extern const char *const seed_response_name[];	/* NULL-terminated, for the parser */

/* The one place that says what the policies mean: keep puts the node back
 * at x0, its position at step k (the chapter's choice, after Volino et
 * al.); q puts it where it touches the surface; slide restores step k's
 * clearance along the normal and keeps this step's tangential motion (the
 * chapter notes that keeping the whole position can lock a node that
 * should slide). touch and slid depend on the kind of contact, so the
 * caller computes them. */
vec3 response_position(enum position_policy p, vec3 x0, vec3 touch, vec3 slid);

/* What acts on the tangential part (eq. 17), which the impact leaves as it
 * is unless the scene asks for friction. */
struct friction {
	double mu;		/* Coulomb: the tangential speed falls by mu |dv_n| */
	double viscous;		/* 1/s: the tangential speed decays at this rate */
};

/* eq. 13-15: the velocity of the point Q of triangle ABC (positions a, b, c,
 * velocities va, vb, vc) from its moving frame and angular velocity. */
vec3 response_point_velocity(vec3 a, vec3 b, vec3 c, vec3 va, vec3 vb, vec3 vc, vec3 q);

/* eq. 11-12 and 16-17: the node's velocity after the impact, given its
 * velocity before (vd), the unit normal n and Q's velocity vq; e is the
 * restitution coefficient (0: perfectly inelastic). Friction acts on the
 * velocity relative to Q's over a step of length dt. */
vec3 response_node_velocity(vec3 vd, vec3 n, vec3 vq, double e, const struct friction *fr,
    double dt);

/*
 * The ccd response between two bodies of alike mass (two parts of the
 * cloth), as a perfectly inelastic impact (with restitution e) shared by
 * both sides: the contact is the point sum w[k] x[k] of nvert vertices,
 * weights positive on one side and negative on the other (barycentric
 * coordinates, or an edge's parameters), n the unit normal from the
 * negative side to the positive one. The impulse along n that makes the
 * relative normal velocity -e times what it was, if they approach, is
 * shared by inverse mass (0: a vertex nothing can move) and weight, so
 * that momentum is kept; Coulomb and viscous friction act on the relative
 * sliding velocity the same way. v is updated in place. Returns the normal
 * impulse per unit of relative velocity change (the j of the impact, >= 0),
 * or -1 when no vertex can move.
 */
double response_shared(int nvert, const double *w, const double *inv_mass, vec3 *v, vec3 n,
    double e, const struct friction *fr, double dt);

#endif

/* scene.h: a scene file parsed and checked; every value in SI units. */
#ifndef DRAPE_SCENE_H
#define DRAPE_SCENE_H

#include <stdbool.h>
#include <stddef.h>

#include "err.h"
#include "integrate.h"
#include "narrow.h"
#include "obstacle.h"

/* A block of grid nodes, i along the warp, j along the weft, inclusive. */
struct node_block {
	int i0, i1, j0, j1;
};

struct node_set {
	struct node_block *b;
	size_t n;
};

enum motion_kind {
	MOTION_PIN,		/* held where it starts */
	MOTION_VELOCITY,	/* constant velocity between start and stop */
	MOTION_PATH,		/* piecewise-linear displacement through (t, d) points */
};

struct scene_motion {
	int line;
	enum motion_kind kind;
	struct node_set nodes;
	double velocity[3];
	double start, stop;	/* stop = INFINITY when never */
	double *path;		/* npath points of t, dx, dy, dz; (0, 0) is implied */
	size_t npath;
};

struct scene_load {
	int line;
	struct node_set nodes;
	double force[3];	/* N, on each node of the set */
	double start, stop;
};

/* The outline of the cloth cut from its nu x nv grid of squares. */
enum cloth_shape {
	SHAPE_SQUARE,		/* the whole grid */
	SHAPE_DISC,		/* the squares inside the grid's inscribed circle */
};

extern const char *const cloth_shape_name[];

struct material {
	double weight;		/* kg/m2 */
	double thickness;	/* m */
	double modulus[2];	/* Pa, warp and weft */
	double shear_modulus;	/* Pa */
	double bending[2];	/* N*m, warp and weft, after derivation */
	bool bending_derived[2];	/* from modulus*thickness^3/12 */
	double damping;		/* 1/s, on absolute velocity */
	double spring_damping;	/* s, dashpot c = spring_damping * k */
};

enum broad_mode { BROAD_SEED, BROAD_GRID, BROAD_BRUTE };
enum narrow_mode { NARROW_SEED, NARROW_CCD };
enum position_policy {
	POSITION_KEEP,		/* the node stays where it was at step k (the chapter) */
	POSITION_Q,		/* the node moves to Q */
	POSITION_SLIDE,		/* step k's normal offset, this step's tangential motion */
};

extern const char *const broad_mode_name[], *const narrow_mode_name[],
    *const position_policy_name[];

/* [collision]: how contacts are found and answered. */
struct collision_opts {
	bool self;		/* cloth against cloth */
	enum broad_mode broad;
	enum narrow_mode narrow;
	enum inside_test inside;
	double cell;		/* L_ce in m; 0 for auto (eq. 21 and the triangle size) */
	double restitution;	/* e of eq. 11 */
	double friction;	/* Coulomb mu, cloth on cloth */
	double viscous;		/* 1/s, viscous friction on sliding */
	enum position_policy position;
};

struct scene {
	char *path;
	char *name;
	char *text;		/* the source, verbatim */

	double duration;
	double dt;		/* 0 when auto */
	enum integrator_kind integrator;
	double tolerance;	/* 0 when not given: the integrator's default */
	double gravity[3];
	double output_rate;

	int nu, nv;
	enum cloth_shape shape;
	double spacing;
	double origin[3];
	double warp_axis[3], weft_axis[3];
	double velocity[3];	/* initial, of every node */
	struct material mat;

	struct scene_motion *motions;
	size_t nmotions;
	struct scene_load *loads;
	size_t nloads;

	struct collision_opts col;
	struct obstacle *obstacles;
	size_t nobstacles;
};

/* 1 if every block of the set lies on an nu x nv grid. */
int node_set_fits(const struct node_set *set, int nu, int nv);

/* Both return 0, or -1 with "FILE:LINE: what was expected" in err. */
int scene_load(struct scene *sc, const char *path, struct drape_err *err);
int scene_parse(struct scene *sc, const char *path, const char *text, struct drape_err *err);
void scene_free(struct scene *sc);

#endif

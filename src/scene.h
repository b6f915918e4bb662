/* scene.h: a scene file parsed and checked; every value in SI units. */
#ifndef DRAPE_SCENE_H
#define DRAPE_SCENE_H

#include <stdbool.h>
#include <stddef.h>

#include "broad.h"
#include "err.h"
#include "integrate.h"
#include "narrow.h"
#include "obstacle.h"
#include "response.h"

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
	/* the analytic obstacles' (§4): a position policy, or -1 for position's */
	int obstacle_position;
	enum seed_segments segments;	/* narrow = seed: the lines r it tests */
	enum keep_velocity keep_velocity;	/* of a node put back by keep */
	enum seed_response seed_response;	/* narrow = seed: who takes a self-contact */
	double memory;		/* bytes the collision stages may take; 0 for auto */
};

/* Bounds that keep a run finite and its numbers in range. */
#define SCENE_MAX_STEPS 1e9	/* duration / dt */
#define SCENE_MAX_FRAMES 1e9	/* duration * output_rate */
#define SCENE_MAX_COORD 1e6	/* m: every length and coordinate, either way */
#define SCENE_MAX_CELLS (1 << 24)	/* spatial hash cubes along an axis (scene.c) */
#define SCENE_MAX_BOX_CELLS 9007199254740992.0	/* 2^53: and in its whole box */

struct scene {
	char *path;
	char *name;
	char *text;		/* the source, verbatim */

	double duration;
	double dt;		/* 0 when auto */
	int dt_line;		/* of dt, else of [simulation], for messages */
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

/* All return 0, or -1 with "FILE:LINE: what was expected" in err. A file,
 * or bytes read from one, is refused if it is a replay, holds a NUL byte
 * (at its line) or is over 16 MiB; text that begins with a byte order mark
 * is refused with a hint. */
int scene_load(struct scene *sc, const char *path, struct drape_err *err);
int scene_parse_bytes(struct scene *sc, const char *path, const void *data, size_t len,
    struct drape_err *err);
int scene_parse(struct scene *sc, const char *path, const char *text, struct drape_err *err);
/* A scene a replay recorded: as scene_parse, but a number without its unit
 * is in SI units, as drape read it before units were required, and a cloth
 * that started inside an obstacle is left as it ran: a replay replays what
 * was run. */
int scene_parse_recorded(struct scene *sc, const char *path, const char *text,
    struct drape_err *err);

/* The steps a duration takes at dt, and the frames it holds at an output
 * rate; a scene keeps them to SCENE_MAX_STEPS and SCENE_MAX_FRAMES, and so
 * must the options that change duration or dt. */
double scene_steps(double duration, double dt);
double scene_frames(double duration, double output_rate);
/* The same with the command line's overrides, "SECTION[#N].KEY=VALUE"
 * each (override.h says how they apply): every value goes through the
 * file's checks, an error on one is "--set SPEC: what was expected", and
 * sc->text is the text that was read, overrides included. */
int scene_load_set(struct scene *sc, const char *path, const char *const *sets, size_t nsets,
    struct drape_err *err);
int scene_parse_set(struct scene *sc, const char *path, const char *text, const char *const *sets,
    size_t nsets, struct drape_err *err);
int scene_parse_bytes_set(struct scene *sc, const char *path, const void *data, size_t len,
    const char *const *sets, size_t nsets, struct drape_err *err);
void scene_free(struct scene *sc);

/* Anything for the collision stages to do in this scene (an obstacle, or
 * the cloth against itself); whether their broad phase runs (the cloth
 * against itself, or a mesh), and whether it fills a spatial hash. From
 * the scene alone (scene.c), so that a replay's viewer says the same as
 * the run. */
bool collide_active(const struct scene *sc);
bool collide_broad_runs(const struct scene *sc);
bool collide_uses_hash(const struct scene *sc);

#endif

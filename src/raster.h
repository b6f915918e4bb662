/* raster.h: a camera and a character grid with a z-buffer: triangles and
 * points projected orthographically or in perspective, shaded in ASCII by
 * how they face a light. It knows nothing of scenes or of ncurses: the
 * view module feeds it the cloth and obstacles, snapshot prints its grid
 * and the TUI copies it to the screen.
 *
 * World space is the scene's (y up). View space: x to the right, y up, z
 * towards the viewer (larger is nearer). A terminal cell is about twice as
 * tall as it is wide, so a metre covers half as many rows as columns. */
#ifndef DRAPE_RASTER_H
#define DRAPE_RASTER_H

#include <stdbool.h>

#include "vec3.h"

#define RASTER_ASPECT 2.0	/* cell height over cell width */
#define RASTER_RAMP ".:-=+*#%@"	/* dim to bright: the cloth */
/* The obstacles' own characters, none of the cloth's nor the floor's '.',
 * so that without colour the cloth and a box it lies on do not merge */
#define RASTER_SOLID_RAMP "',;!|lIH"

enum view_preset { VIEW_FRONT, VIEW_SIDE, VIEW_TOP, VIEW_ISO, VIEW_NPRESETS };

/* "front", "side", "top", "iso", by preset. */
extern const char *const view_preset_name[VIEW_NPRESETS];
/* The preset of that name, or -1. */
int view_preset_from_name(const char *name);

struct camera {
	double yaw, pitch;	/* radians: about world y, then about view x */
	double zoom;		/* 1: the framed sphere fills the grid's smaller side */
	double pan_x, pan_y;	/* m, in view space */
	bool perspective;
	vec3 target;		/* the centre of what is framed */
	double radius;		/* m, the radius of what is framed, > 0 */
};

/* What a cell shows, so that a front end may colour it. */
enum cell_kind {
	CELL_EMPTY,
	CELL_CLOTH,
	CELL_SOLID,		/* an obstacle */
	CELL_FLOOR,		/* a plane's grid */
	CELL_CONTACT,		/* a node in contact this step */
	CELL_SELECTED,		/* the selected node */
};

struct raster {
	int w, h;
	char *ch;		/* w*h characters, row by row, no terminator */
	unsigned char *kind;	/* w*h enum cell_kind */
	double *depth;		/* w*h view-space z, -INFINITY where nothing */
};

/* Looks at the sphere (target, radius) from a preset direction, zoom 1,
 * no pan, orthographic. */
void camera_preset(struct camera *cam, enum view_preset preset, vec3 target, double radius);

/* A point in view space (before projection). */
vec3 camera_view(const struct camera *cam, vec3 p);

/* Projects p onto a w x h grid of cells aspect times as tall as they are
 * wide (RASTER_ASPECT for a terminal, 1 for square pixels): *col and *row
 * (may fall outside it) and the view-space depth *z. Returns false when p
 * is behind the perspective camera. The centre of the grid is at
 * (w/2, h/2); the framed sphere fills its smaller side at zoom 1. */
bool camera_project(const struct camera *cam, vec3 p, int w, int h, double aspect, double *col,
    double *row, double *z);

/* The raster starts empty (w = h = 0). */
void raster_init(struct raster *r);
/* Resizes (w, h >= 1) and clears. Returns 0, or -1 if out of memory (then
 * the raster is empty). */
int raster_resize(struct raster *r, int w, int h);
void raster_clear(struct raster *r);
void raster_free(struct raster *r);

/* camera_project onto the raster's grid of terminal cells. */
bool raster_project(const struct raster *r, const struct camera *cam, vec3 p, double *col,
    double *row, double *z);

/* The light, in view space, from the viewer's upper left (not of unit
 * length): the terminal's shading and the pictures' (paint.c) take it,
 * so that both light a scene alike. */
#define RASTER_LIGHT v3(-0.35, 0.6, 0.72)

/* Fills the cells whose centres the triangle covers and that it is nearer
 * in, with the ramp character of its lighting (two-sided: a cloth has no
 * outside); CELL_FLOOR fills with blanks, which hide what is under a floor
 * whose grid is drawn with raster_point. */
void raster_triangle(struct raster *r, const struct camera *cam, vec3 a, vec3 b, vec3 c,
    enum cell_kind kind);

/* Puts ch at p if nothing nearer than p by more than slack (m) covers it.
 * always: regardless of depth (marks that must be seen). */
void raster_point(struct raster *r, const struct camera *cam, vec3 p, char ch,
    enum cell_kind kind, double slack, bool always);

/* The character at (col, row), ' ' outside the grid. */
char raster_at(const struct raster *r, int col, int row);

#endif

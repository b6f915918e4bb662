/* mesh.h: triangle meshes for obstacles: read from a Wavefront OBJ file or
 * built (the icosahedron of the chapter's Fig. 6), moved into place, and
 * asked whether a point is inside. */
#ifndef DRAPE_MESH_H
#define DRAPE_MESH_H

#include <stddef.h>
#include <stdio.h>

#include "err.h"
#include "vec3.h"

struct mesh {
	double *x;		/* 3 per vertex */
	int nverts;
	int *tri;		/* 3 vertex indices per triangle, counter-clockwise
				 * seen from outside */
	size_t ntri;
};

/* What an OBJ file may hold: anything larger is refused with its line. */
#define OBJ_MAX_LINE 65536		/* bytes in a line, its newline aside */
#define OBJ_MAX_BYTES (256 << 20)	/* bytes in the file */
#define OBJ_MAX_VERTICES (1 << 22)
#define OBJ_MAX_TRIANGLES (1 << 23)	/* after cutting polygons into triangles */

/*
 * Reads the v and f lines of a Wavefront OBJ file. Faces may be written
 * v, v/vt, v//vn or v/vt/vn; a negative index counts back from the last
 * vertex read; a polygon is cut into a fan of triangles about its first
 * vertex. Every other line (vn, vt, o, g, s, usemtl, mtllib, #) is skipped.
 * An index must name a vertex read before it.
 *
 * Returns 0, or -1 with err set and nothing allocated: "PATH:LINE: expected
 * ..." for a malformed number, an index out of range or zero, a face of
 * fewer than 3 vertices, a NUL byte, a byte order mark, and a line, a file
 * or a count over the bounds above; "PATH: cannot open: ..."; "PATH:
 * expected ..." for a file with no faces (saying so when it is not text).
 */
int mesh_load_obj(struct mesh *m, const char *path, struct drape_err *err);
/* The same from an open stream, named name in messages. */
int mesh_read_obj(struct mesh *m, FILE *f, const char *name, struct drape_err *err);

/* The regular icosahedron with the given centre and circumradius: 12
 * vertices, 20 faces oriented outward. Returns 0, or -1 if out of memory. */
int mesh_icosahedron(struct mesh *m, vec3 centre, double radius);

/* x -> scale * x + offset for every vertex. */
void mesh_transform(struct mesh *m, double scale, vec3 offset);

/* The generalized winding number of p: the sum of the signed solid angles of
 * the triangles (van Oosterom and Strackee) over 4 pi. 1 inside a closed,
 * outward oriented mesh, 0 outside, and in between near the holes of an
 * open one. Costs one atan2 per triangle. */
double mesh_winding_number(const struct mesh *m, vec3 p);

/* The vertices' bounding box; lo = +INFINITY, hi = -INFINITY if none. */
void mesh_bounds(const struct mesh *m, vec3 *lo, vec3 *hi);

/* Frees the arrays and leaves an empty mesh; an empty mesh may be freed. */
void mesh_free(struct mesh *m);

#endif

/* obj.h: Wavefront OBJ output of triangle meshes. */
#ifndef DRAPE_OBJ_H
#define DRAPE_OBJ_H

#include <stddef.h>

#include "err.h"

/* One mesh of an OBJ file: its vertices, and if not NULL its texture
 * coordinates (2 per vertex, `vt`) and normals (3 per vertex, `vn`), each
 * the vertex's own (a face's corner k refers to vertex, vt and vn k
 * alike); name, if not NULL, begins it with an `o` line. */
struct obj_mesh {
	const char *name;
	const double *x;
	int n;
	const int *tri;		/* 3 per triangle, from 0 */
	size_t ntri;
	const double *uv, *normal;
};

/* Writes the meshes in order, through a temporary file renamed into place,
 * so a failed write leaves nothing half-written at path. Returns 0, or -1
 * with a message in err. */
int obj_write_meshes(const char *path, const struct obj_mesh *m, size_t count,
    struct drape_err *err);

/* One mesh's `v` per node in node order and `f` per triangle (1-based). */
int obj_write(const char *path, const double *x, int n, const int *tri, size_t ntri,
    struct drape_err *err);

/* The unit normal at each of n vertices: the sum of its triangles'
 * normals weighted by their areas (0 0 0 for a vertex of none). */
void obj_vertex_normals(const double *x, int n, const int *tri, size_t ntri, double *normal);

#endif

/* obstacle_mesh.h: a scene's obstacles as triangle meshes, for export. */
#ifndef DRAPE_OBSTACLE_MESH_H
#define DRAPE_OBSTACLE_MESH_H

#include "mesh.h"
#include "obstacle.h"

#define OBSTACLE_MESH_SLICES 32	/* around a sphere or a disc */
#define OBSTACLE_MESH_STACKS 16	/* pole to pole on a sphere */

/* The surface of o as triangles, counter-clockwise seen from outside, into
 * out (freed with mesh_free): a box's 12, a sphere's latitude-longitude
 * grid, a disc's cylinder with both faces, a mesh's own; a plane, which
 * has no end, as a square of side 2 half centred on the point of it
 * nearest to near. 0, or -1 when out of memory. */
int obstacle_mesh(const struct obstacle *o, vec3 near, double half, struct mesh *out);

#endif

/* obj.h: Wavefront OBJ output of a triangle mesh. */
#ifndef DRAPE_OBJ_H
#define DRAPE_OBJ_H

#include <stddef.h>

#include "err.h"

/* Writes `v` per node in node order and `f` per triangle (1-based), through
 * a temporary file renamed into place, so a failed write leaves nothing
 * half-written at path. Returns 0, or -1 with a message in err. */
int obj_write(const char *path, const double *x, int n, const int *tri, size_t ntri,
    struct drape_err *err);

#endif

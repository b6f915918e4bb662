/* obj.c: OBJ writer. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "obj.h"
#include "outfile.h"

/* One mesh's lines, its indices after the first vertex's number base. */
static int
write_mesh(FILE *f, const struct obj_mesh *m, long base)
{
	size_t t;
	int p, k;

	if (m->name != NULL && fprintf(f, "o %s\n", m->name) < 0)
		return -1;
	for (p = 0; p < m->n; p++)
		if (fprintf(f, "v %.17g %.17g %.17g\n", m->x[3 * p], m->x[3 * p + 1],
		    m->x[3 * p + 2]) < 0)
			return -1;
	for (p = 0; m->uv != NULL && p < m->n; p++)
		if (fprintf(f, "vt %.17g %.17g\n", m->uv[2 * p], m->uv[2 * p + 1]) < 0)
			return -1;
	for (p = 0; m->normal != NULL && p < m->n; p++)
		if (fprintf(f, "vn %.17g %.17g %.17g\n", m->normal[3 * p], m->normal[3 * p + 1],
		    m->normal[3 * p + 2]) < 0)
			return -1;
	for (t = 0; t < m->ntri; t++) {
		if (fputc('f', f) == EOF)
			return -1;
		for (k = 0; k < 3; k++) {
			long v = base + m->tri[3 * t + (size_t)k];
			int rc;

			if (m->uv != NULL && m->normal != NULL)
				rc = fprintf(f, " %ld/%ld/%ld", v, v, v);
			else if (m->uv != NULL)
				rc = fprintf(f, " %ld/%ld", v, v);
			else if (m->normal != NULL)
				rc = fprintf(f, " %ld//%ld", v, v);
			else
				rc = fprintf(f, " %ld", v);
			if (rc < 0)
				return -1;
		}
		if (fputc('\n', f) == EOF)
			return -1;
	}
	return 0;
}

int
obj_write_meshes(const char *path, const struct obj_mesh *m, size_t count,
    struct drape_err *err)
{
	size_t len = strlen(path) + 8, i, ntri = 0;
	char *tmp = malloc(len);
	FILE *f;
	int bad = 0;
	long nv = 0;
	bool direct = outfile_is_special(path);	/* /dev/null: no rename over it */

	if (tmp == NULL) {
		err_set(err, "%s: out of memory", path);
		return -1;
	}
	snprintf(tmp, len, "%s", path);
	if (!direct)
		snprintf(tmp, len, "%s.tmp", path);
	if ((f = fopen(tmp, "w")) == NULL) {
		err_set(err, "%s: cannot create: %s", tmp, strerror(errno));
		free(tmp);
		return -1;
	}
	for (i = 0; i < count; i++) {
		nv += m[i].n;
		ntri += m[i].ntri;
	}
	if (fprintf(f, "# drape mesh: %ld vertices, %zu triangles\n", nv, ntri) < 0)
		bad = 1;
	/* OBJ numbers vertices from 1, across the whole file */
	for (i = 0, nv = 1; i < count && !bad; nv += m[i].n, i++)
		if (write_mesh(f, &m[i], nv) != 0)
			bad = 1;
	if (fflush(f) != 0 || ferror(f))
		bad = 1;
	if (fclose(f) != 0)
		bad = 1;
	if (bad || (!direct && rename(tmp, path) != 0)) {
		err_set(err, "%s: write failed: %s", path, strerror(errno));
		if (!direct)
			remove(tmp);
		free(tmp);
		return -1;
	}
	free(tmp);
	return 0;
}

int
obj_write(const char *path, const double *x, int n, const int *tri, size_t ntri,
    struct drape_err *err)
{
	struct obj_mesh m = { NULL, x, n, tri, ntri, NULL, NULL };

	return obj_write_meshes(path, &m, 1, err);
}

void
obj_vertex_normals(const double *x, int n, const int *tri, size_t ntri, double *normal)
{
	size_t t;
	int p, k;

	memset(normal, 0, 3 * (size_t)n * sizeof *normal);
	for (t = 0; t < ntri; t++) {
		const double *a = x + 3 * tri[3 * t], *b = x + 3 * tri[3 * t + 1],
		    *c = x + 3 * tri[3 * t + 2];
		double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
		double w[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
		/* the cross product's length is twice the area: the weight */
		double cr[3] = { u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
			u[0] * w[1] - u[1] * w[0] };

		for (k = 0; k < 3; k++) {
			double *nv = normal + 3 * tri[3 * t + (size_t)k];

			nv[0] += cr[0];
			nv[1] += cr[1];
			nv[2] += cr[2];
		}
	}
	for (p = 0; p < n; p++) {
		double *nv = normal + 3 * p, l = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);

		if (l > 0) {
			nv[0] /= l;
			nv[1] /= l;
			nv[2] /= l;
		}
	}
}

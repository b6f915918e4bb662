/* obj.c: OBJ writer. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "obj.h"
#include "outfile.h"

int
obj_write(const char *path, const double *x, int n, const int *tri, size_t ntri,
    struct drape_err *err)
{
	size_t len = strlen(path) + 8, t;
	char *tmp = malloc(len);
	FILE *f;
	int p, bad = 0;
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
	if (fprintf(f, "# drape mesh: %d vertices, %zu triangles\n", n, ntri) < 0)
		bad = 1;
	for (p = 0; p < n && !bad; p++)
		if (fprintf(f, "v %.17g %.17g %.17g\n", x[3 * p], x[3 * p + 1], x[3 * p + 2]) < 0)
			bad = 1;
	for (t = 0; t < ntri && !bad; t++)
		if (fprintf(f, "f %d %d %d\n", tri[3 * t] + 1, tri[3 * t + 1] + 1,
		    tri[3 * t + 2] + 1) < 0)
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

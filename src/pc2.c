/* pc2.c: the PC2 writer. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "outfile.h"
#include "pc2.h"

static void
release(struct pc2_writer *w)
{
	free(w->path);
	free(w->tmp);
	memset(w, 0, sizeof *w);
}

int
pc2_open(struct pc2_writer *w, const char *path, int points, float start, float rate,
    struct drape_err *err)
{
	size_t len = strlen(path) + 8;
	const char *what;

	memset(w, 0, sizeof *w);
	if ((w->path = malloc(len)) == NULL || (w->tmp = malloc(len)) == NULL) {
		err_set(err, "%s: out of memory", path);
		release(w);
		return -1;
	}
	strcpy(w->path, path);
	w->direct = outfile_is_special(path);	/* /dev/null: no rename over it */
	snprintf(w->tmp, len, w->direct ? "%s" : "%s.tmp", path);
	memcpy(w->h.magic, "POINTCACHE2\0", 12);
	w->h.version = 1;
	w->h.points = points;
	w->h.start = start;
	w->h.rate = rate;
	w->h.samples = 0;
	/* the sample count is written last, at the start */
	if ((what = outfile_unseekable(path)) != NULL) {
		err_set(err, "%s: %s cannot hold a PC2 file, whose header is written last, at its "
		    "start; expected a regular file", path, what);
		release(w);
		return -1;
	}
	if ((w->f = fopen(w->tmp, "wb")) == NULL) {
		err_set(err, "%s: cannot create: %s", w->tmp, strerror(errno));
		release(w);
		return -1;
	}
	if (!outfile_seeks(w->f)) {
		err_set(err, "%s: cannot seek in it (%s), and a PC2 file's header is written last, "
		    "at its start; expected a regular file", path, strerror(errno));
		pc2_abort(w);
		return -1;
	}
	if (fwrite(&w->h, sizeof w->h, 1, w->f) != 1) {
		err_set(err, "%s: write failed: %s", w->tmp, strerror(errno));
		pc2_abort(w);
		return -1;
	}
	return 0;
}

int
pc2_append(struct pc2_writer *w, const float *x, struct drape_err *err)
{
	size_t n = 3 * (size_t)w->h.points;

	if (fwrite(x, sizeof *x, n, w->f) != n) {
		err_set(err, "%s: write failed: %s", w->tmp, strerror(errno));
		return -1;
	}
	w->h.samples++;
	return 0;
}

int
pc2_close(struct pc2_writer *w, struct drape_err *err)
{
	int bad = fseek(w->f, 0, SEEK_SET) != 0 || fwrite(&w->h, sizeof w->h, 1, w->f) != 1 ||
	    fflush(w->f) != 0 || ferror(w->f);

	if (fclose(w->f) != 0)
		bad = 1;
	w->f = NULL;
	if (bad || (!w->direct && rename(w->tmp, w->path) != 0)) {
		err_set(err, "%s: write failed: %s", w->path, strerror(errno));
		if (!w->direct)
			remove(w->tmp);
		release(w);
		return -1;
	}
	release(w);
	return 0;
}

void
pc2_abort(struct pc2_writer *w)
{
	if (w->f != NULL)
		fclose(w->f);
	if (w->tmp != NULL && !w->direct)
		remove(w->tmp);
	release(w);
}

/* outfile.c: regular files and the others, for the writers. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include "outfile.h"

bool
outfile_is_special(const char *path)
{
	struct stat sb;

	return stat(path, &sb) == 0 && !S_ISREG(sb.st_mode);
}

bool
outfile_same(const char *out, const char *in)
{
	struct stat so, si;

	return stat(out, &so) == 0 && stat(in, &si) == 0 && S_ISREG(si.st_mode) &&
	    so.st_dev == si.st_dev && so.st_ino == si.st_ino;
}

const char *
outfile_unseekable(const char *path)
{
	struct stat sb;

	if (stat(path, &sb) != 0)
		return NULL;	/* made as a regular file, or the open says why not */
	if (S_ISFIFO(sb.st_mode))
		return "a FIFO";
	if (S_ISSOCK(sb.st_mode))
		return "a socket";
	return NULL;
}

bool
outfile_seeks(FILE *f)
{
	return lseek(fileno(f), 0, SEEK_CUR) >= 0;
}

static void
outfile_release(struct outfile *o)
{
	free(o->path);
	if (o->tmp != o->path)
		free(o->tmp);
	memset(o, 0, sizeof *o);
}

int
outfile_open(struct outfile *o, const char *path, struct drape_err *err)
{
	size_t len = strlen(path) + 5;

	memset(o, 0, sizeof *o);
	o->direct = outfile_is_special(path);	/* /dev/null: no rename over it */
	if ((o->path = malloc(len)) == NULL || (!o->direct && (o->tmp = malloc(len)) == NULL)) {
		err_set(err, "%s: out of memory", path);
		outfile_release(o);
		return -1;
	}
	strcpy(o->path, path);
	if (o->direct)
		o->tmp = o->path;
	else
		snprintf(o->tmp, len, "%s.tmp", path);
	if ((o->f = fopen(o->tmp, "w")) == NULL) {
		err_set(err, "%s: cannot create: %s", o->tmp, strerror(errno));
		outfile_release(o);
		return -1;
	}
	return 0;
}

int
outfile_close(struct outfile *o, struct drape_err *err)
{
	int e = 0;

	errno = 0;
	if (fflush(o->f) != 0 || ferror(o->f))
		e = errno != 0 ? errno : EIO;
	if (fclose(o->f) != 0 && e == 0)
		e = errno != 0 ? errno : EIO;
	o->f = NULL;
	if (e == 0 && !o->direct && rename(o->tmp, o->path) != 0)
		e = errno;
	if (e != 0) {
		err_set(err, "%s: write failed: %s", o->path, strerror(e));
		if (!o->direct)
			remove(o->tmp);
		outfile_release(o);
		return -1;
	}
	outfile_release(o);
	return 0;
}

void
outfile_abort(struct outfile *o)
{
	if (o->f != NULL)
		fclose(o->f);
	if (o->tmp != NULL && !o->direct)
		remove(o->tmp);
	outfile_release(o);
}

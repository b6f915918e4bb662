/* outfile.c: regular files and the others, for the writers. */
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

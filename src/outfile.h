/* outfile.h: where an output file goes. The writers publish a file whole
 * or not at all, through a temporary file renamed over the path; a path
 * that names something else than a regular file (/dev/null, /dev/stdout,
 * a FIFO) is written directly instead: renamed over, a device node would
 * be replaced by a regular file, and as root /dev/null would be gone. */
#ifndef DRAPE_OUTFILE_H
#define DRAPE_OUTFILE_H

#include <stdbool.h>
#include <stdio.h>

#include "err.h"

/* true if path exists and is not a regular file (a directory counts: the
 * direct write then fails with the reason). */
bool outfile_is_special(const char *path);

/* true if out and in both name one existing regular file, by device and
 * inode (another name, a hard link or a symbolic link to it counts):
 * writing out would destroy in. A device or a FIFO is not stored, so
 * naming it twice destroys nothing. */
bool outfile_same(const char *out, const char *in);

/* For the formats that go back to write a header once the rest is
 * written (replays, PC2): NULL if path can be written so (it is not
 * there yet, or a regular file or a device), else what it is ("a FIFO",
 * "a socket"), which is not opened: a FIFO would block until a reader
 * came, and then give it a file with no header. */
const char *outfile_unseekable(const char *path);

/* Whether an opened output seeks (a terminal does not). */
bool outfile_seeks(FILE *f);

/* A text or binary output written whole or not at all: into PATH.tmp,
 * renamed over path at the close, or in place when path is special. */
struct outfile {
	FILE *f;
	char *path, *tmp;	/* tmp is path itself when direct */
	bool direct;
};

/* 0, or -1 with "TMP: cannot create: why" (nothing made). */
int outfile_open(struct outfile *o, const char *path, struct drape_err *err);
/* Every write checked (the stream's error flag), closed, renamed into
 * place: 0, or -1 with "PATH: write failed: why", the temporary file
 * removed and path as it was. */
int outfile_close(struct outfile *o, struct drape_err *err);
/* Closes and removes the temporary file; path is as it was. */
void outfile_abort(struct outfile *o);

#endif

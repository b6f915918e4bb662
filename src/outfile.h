/* outfile.h: where an output file goes. The writers publish a file whole
 * or not at all, through a temporary file renamed over the path; a path
 * that names something else than a regular file (/dev/null, /dev/stdout,
 * a FIFO) is written directly instead: renamed over, a device node would
 * be replaced by a regular file, and as root /dev/null would be gone. */
#ifndef DRAPE_OUTFILE_H
#define DRAPE_OUTFILE_H

#include <stdbool.h>

/* true if path exists and is not a regular file (a directory counts: the
 * direct write then fails with the reason). */
bool outfile_is_special(const char *path);

#endif

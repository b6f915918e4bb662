/* outfile.c: regular files and the others, for the writers. */
#include <sys/stat.h>

#include "outfile.h"

bool
outfile_is_special(const char *path)
{
	struct stat sb;

	return stat(path, &sb) == 0 && !S_ISREG(sb.st_mode);
}

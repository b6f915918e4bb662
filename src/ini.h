/* ini.h: splits INI-like text into sections and key = value entries, each
 * with its line number. Meaning is the caller's (scene.c); this only checks
 * the shape of lines. */
#ifndef DRAPE_INI_H
#define DRAPE_INI_H

#include <stddef.h>

#include "err.h"

struct ini_entry {
	int line;
	char *section;	/* section name (shared by its entries) */
	int section_line;
	char *key;	/* NULL for the section header itself */
	char *value;
};

struct ini {
	struct ini_entry *e;
	size_t n;
	int last_line;
	char *store;	/* one allocation holding every string above */
};

/* Returns 0, or -1 with "NAME:LINE: ..." in err. */
int ini_parse(struct ini *ini, const char *name, const char *text, struct drape_err *err);
void ini_free(struct ini *ini);

#endif

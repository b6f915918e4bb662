/* ini.h: splits INI-like text into sections and key = value entries, each
 * with its line number. Meaning is the caller's (scene.c); this only checks
 * the shape of lines. */
#ifndef DRAPE_INI_H
#define DRAPE_INI_H

#include <stdbool.h>
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

/* s without its leading and trailing white space (cut in place), and
 * whether s is a section or key name (letters, digits, '_' and '-'):
 * the rules of the file, shared with --set (override.c). */
char *ini_trim(char *s);
bool ini_valid_name(const char *s);
void ini_free(struct ini *ini);

#endif

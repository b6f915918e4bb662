/* ini.c: line tokenizer for scene files. */
#include <ctype.h>
#include <stdlib.h>
#include <string.h>

#include "grow.h"
#include "ini.h"

char *
ini_trim(char *s)
{
	char *end;

	while (isspace((unsigned char)*s))
		s++;
	end = s + strlen(s);
	while (end > s && isspace((unsigned char)end[-1]))
		*--end = '\0';
	return s;
}

bool
ini_valid_name(const char *s)
{
	if (*s == '\0')
		return false;
	for (; *s != '\0'; s++)
		if (!isalnum((unsigned char)*s) && *s != '_' && *s != '-')
			return false;
	return true;
}

int
ini_parse(struct ini *ini, const char *name, const char *text, struct drape_err *err)
{
	size_t len = strlen(text), cap = 0;
	char *p, *section = NULL;
	int line = 0, section_line = 0;

	memset(ini, 0, sizeof *ini);
	if ((ini->store = malloc(len + 1)) == NULL) {
		err_set(err, "%s: out of memory", name);
		return -1;
	}
	memcpy(ini->store, text, len + 1);

	for (p = ini->store;;) {
		char *nl = strchr(p, '\n'), *s, *hash, *eq;

		if (*p == '\0' && line > 0)
			break;	/* text ended with a newline */
		line++;
		if (nl != NULL)
			*nl = '\0';
		if ((hash = strchr(p, '#')) != NULL)
			*hash = '\0';
		s = ini_trim(p);
		p = nl != NULL ? nl + 1 : p + strlen(p);

		if (*s == '\0')
			goto next;
		if (grow_array((void **)&ini->e, &cap, ini->n + 1, sizeof *ini->e) != 0) {
			err_set(err, "%s:%d: out of memory", name, line);
			goto fail;
		}
		if (*s == '[') {
			char *close = strchr(s, ']');

			if (close == NULL || ini_trim(close + 1)[0] != '\0') {
				err_set(err, "%s:%d: expected a section header like [cloth]", name, line);
				goto fail;
			}
			*close = '\0';
			section = ini_trim(s + 1);
			if (!ini_valid_name(section)) {
				err_set(err, "%s:%d: expected a section name of letters, digits, '_' or '-'",
				    name, line);
				goto fail;
			}
			section_line = line;
			ini->e[ini->n++] = (struct ini_entry){ line, section, line, NULL, NULL };
			goto next;
		}
		if ((eq = strchr(s, '=')) == NULL) {
			err_set(err, "%s:%d: expected 'key = value' or a [section] header", name, line);
			goto fail;
		}
		*eq = '\0';
		if (section == NULL) {
			err_set(err, "%s:%d: expected a [section] header before the first key", name, line);
			goto fail;
		}
		if (!ini_valid_name(ini_trim(s))) {
			err_set(err, "%s:%d: expected a key name before '='", name, line);
			goto fail;
		}
		if (ini_trim(eq + 1)[0] == '\0') {
			err_set(err, "%s:%d: %s: expected a value after '='", name, line, ini_trim(s));
			goto fail;
		}
		ini->e[ini->n++] = (struct ini_entry){ line, section, section_line, ini_trim(s),
		    ini_trim(eq + 1) };
next:
		if (nl == NULL)
			break;
	}
	ini->last_line = line;
	return 0;
fail:
	ini_free(ini);
	return -1;
}

void
ini_free(struct ini *ini)
{
	free(ini->e);
	free(ini->store);
	memset(ini, 0, sizeof *ini);
}

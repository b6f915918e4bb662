/* override.c: --set SECTION[#N].KEY=VALUE applied to a scene's text. */
#include <ctype.h>
#include <errno.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "grow.h"
#include "ini.h"
#include "override.h"

struct spec {
	const char *raw;	/* as given */
	char *buf;		/* a copy of raw, cut into the three below */
	const char *section, *key, *value;
	long inst;		/* #N, or 0 when not given */
	/* where it goes */
	size_t header;		/* the section's header in the ini, or SIZE_MAX: added */
	int line;		/* the file's line it replaces, or 0 */
	int after;		/* else the file's line it follows, or 0: in an added section */
	const char *old;	/* the file's value it replaces */
};

/* The new text being built, line by line. */
struct out {
	char *p;
	size_t n, cap;
	int *from;
	int nl, capl;
	bool oom;
};

/* raw with its control characters but tabs written as C escapes (\n,
 * \x1b), for a message on one line. */
static void
escaped(const char *raw, char *buf, size_t len)
{
	size_t o = 0;

	for (; *raw != '\0' && o + 5 < len; raw++) {
		unsigned char ch = (unsigned char)*raw;

		if (ch == '\n')
			o += (size_t)snprintf(buf + o, len - o, "\\n");
		else if (ch == '\r')
			o += (size_t)snprintf(buf + o, len - o, "\\r");
		else if ((ch < 0x20 && ch != '\t') || ch == 0x7f)
			o += (size_t)snprintf(buf + o, len - o, "\\x%02x", ch);
		else
			buf[o++] = (char)ch;
	}
	buf[o] = '\0';
}

static int
parse_spec(struct spec *s, const char *raw, struct drape_err *err)
{
	char *eq, *dot, *hash, *sec, *end;
	const char *v;

	memset(s, 0, sizeof *s);
	s->raw = raw;
	s->header = SIZE_MAX;
	/* the spec goes whole into the scene's text, as a comment on the line
	 * it makes: a newline in it (a value pasted with its line's end) would
	 * cut that line and shift every line after it */
	for (v = raw; *v != '\0'; v++)
		if (((unsigned char)*v < 0x20 && *v != '\t') || *v == 0x7f) {
			char shown[300];

			escaped(raw, shown, sizeof shown);
			err_set(err, "--set %s: expected SECTION.KEY=VALUE on one line, without "
			    "control characters (found one at byte %zu)", shown, (size_t)(v - raw) + 1);
			return -1;
		}
	if ((s->buf = malloc(strlen(raw) + 1)) == NULL) {
		err_set(err, "--set %s: out of memory", raw);
		return -1;
	}
	strcpy(s->buf, raw);
	if ((eq = strchr(s->buf, '=')) == NULL)
		goto malformed;
	*eq = '\0';
	sec = ini_trim(s->buf);
	if ((dot = strchr(sec, '.')) == NULL)
		goto malformed;
	*dot = '\0';
	s->key = dot + 1;
	if ((hash = strchr(sec, '#')) != NULL) {
		*hash = '\0';
		errno = 0;
		s->inst = strtol(hash + 1, &end, 10);
		if (!isdigit((unsigned char)hash[1]) || *end != '\0' || errno != 0 || s->inst < 1) {
			err_set(err, "--set %s: expected the section's place among those of its kind "
			    "after '#', a whole number from 1 (plane#2 for the second [plane])", raw);
			return -1;
		}
	}
	s->section = sec;
	if (!ini_valid_name(s->section) || !ini_valid_name(s->key))
		goto malformed;
	s->value = ini_trim(eq + 1);
	if (s->value[0] == '\0') {
		err_set(err, "--set %s: expected a value after '='", raw);
		return -1;
	}
	for (v = s->value; *v != '\0'; v++)
		if (*v == '#') {
			err_set(err, "--set %s: expected a value without '#' (in a scene it starts "
			    "a comment)", raw);
			return -1;
		}
	return 0;
malformed:
	err_set(err, "--set '%s': expected SECTION.KEY=VALUE, such as cloth.bending_warp=5uN*m "
	    "or plane#2.friction=0.3 (letters, digits, '_' and '-' in the names)", raw);
	return -1;
}

/* The place of s in the file: its section's header, and the key's line
 * or the line it follows. */
static int
place(struct spec *s, const struct ini *ini, struct drape_err *err)
{
	size_t i, found = SIZE_MAX;
	long count = 0;
	char lines[120];
	size_t off = 0;
	int repeats;

	lines[0] = '\0';
	for (i = 0; i < ini->n; i++) {
		const struct ini_entry *e = &ini->e[i];

		if (e->key != NULL || strcmp(e->section, s->section) != 0)
			continue;
		count++;
		if (off < sizeof lines)
			off += (size_t)snprintf(lines + off, sizeof lines - off, "%s%d",
			    count > 1 ? ", " : "", e->line);
		if (count == (s->inst > 0 ? s->inst : 1))
			found = i;
	}
	if (count == 0) {
		repeats = scene_section_repeats(s->section);
		if (repeats == 1) {
			err_set(err, "--set %s: the scene has no [%s] section; expected a section it "
			    "has (--set adds no [%s])", s->raw, s->section, s->section);
			return -1;
		}
		if (s->inst > 1) {
			err_set(err, "--set %s: the scene has no [%s] section; expected %s.%s",
			    s->raw, s->section, s->section, s->key);
			return -1;
		}
		return 0;	/* added at the end; an unknown section fails there */
	}
	if (s->inst == 0 && count > 1) {
		err_set(err, "--set %s: the scene has %ld [%s] sections (lines %s); expected "
		    "%s#1.%s to %s#%ld.%s to say which", s->raw, count, s->section, lines,
		    s->section, s->key, s->section, count, s->key);
		return -1;
	}
	if (found == SIZE_MAX && count == 1) {
		err_set(err, "--set %s: the scene has one [%s] section (line %s); expected %s.%s "
		    "or %s#1.%s", s->raw, s->section, lines, s->section, s->key, s->section, s->key);
		return -1;
	}
	if (found == SIZE_MAX) {
		err_set(err, "--set %s: the scene has %ld [%s] sections (lines %s); expected "
		    "%s#1.%s to %s#%ld.%s", s->raw, count, s->section, lines, s->section, s->key,
		    s->section, count, s->key);
		return -1;
	}
	s->header = found;
	s->after = ini->e[found].line;
	for (i = found + 1; i < ini->n && ini->e[i].key != NULL; i++) {
		s->after = ini->e[i].line;
		if (strcmp(ini->e[i].key, s->key) == 0) {
			s->line = ini->e[i].line;
			s->old = ini->e[i].value;
		}
	}
	if (s->line != 0)
		s->after = 0;
	return 0;
}

static bool
same_target(const struct spec *a, const struct spec *b)
{
	if (a->header != b->header)
		return false;
	return a->header != SIZE_MAX || strcmp(a->section, b->section) == 0;
}

static void
put(struct out *o, const char *s, size_t len, int from)
{
	if (o->oom)
		return;
	if (grow_array((void **)&o->p, &o->cap, o->n + len + 2, 1) != 0) {
		o->oom = true;
		return;
	}
	if (o->nl == o->capl) {
		int capl = o->capl ? 2 * o->capl : 256;
		int *f = realloc(o->from, (size_t)capl * sizeof *f);

		if (f == NULL) {
			o->oom = true;
			return;
		}
		o->from = f;
		o->capl = capl;
	}
	memcpy(o->p + o->n, s, len);
	o->n += len;
	o->p[o->n++] = '\n';
	o->p[o->n] = '\0';
	o->from[o->nl++] = from;
}

/* A line made by the overrides: "KEY = VALUE  # --set ...". */
static void
put_set(struct out *o, const struct spec *s, int k)
{
	const char *fmt = s->old != NULL ? "%s = %s\t# --set %s (the file had: %s)" :
	    "%s = %s\t# --set %s";
	int len = snprintf(NULL, 0, fmt, s->key, s->value, s->raw, s->old);
	char *line;

	if (len < 0 || (line = malloc((size_t)len + 1)) == NULL) {
		o->oom = true;
		return;
	}
	snprintf(line, (size_t)len + 1, fmt, s->key, s->value, s->raw, s->old);
	put(o, line, (size_t)len, -(k + 1));
	free(line);
}

/* The sections the file lacks, at its end, each with its keys. */
static void
put_added(struct out *o, const struct spec *s, size_t n)
{
	size_t k, j;

	for (k = 0; k < n; k++) {
		size_t len;
		char *head;

		if (s[k].header != SIZE_MAX)
			continue;
		for (j = 0; j < k; j++)
			if (same_target(&s[j], &s[k]))
				break;
		if (j < k)
			continue;	/* added with the first of its section */
		len = strlen(s[k].section) + 10;
		if ((head = malloc(len + 1)) == NULL) {
			o->oom = true;
			return;
		}
		snprintf(head, len + 1, "[%s]\t# --set", s[k].section);
		put(o, "", 0, -(int)(k + 1));
		put(o, head, strlen(head), -(int)(k + 1));
		free(head);
		for (j = k; j < n; j++)
			if (same_target(&s[j], &s[k]))
				put_set(o, &s[j], (int)j);
	}
}

static int
build(struct override_text *o, const char *text, const struct spec *s, size_t n)
{
	struct out out = { 0 };
	const char *p = text;
	int line = 0;
	size_t k;

	while (*p != '\0') {
		const char *nl = strchr(p, '\n');
		size_t len = nl != NULL ? (size_t)(nl - p) : strlen(p);
		bool replaced = false;

		line++;
		for (k = 0; k < n; k++)
			if (s[k].line == line) {
				put_set(&out, &s[k], (int)k);
				replaced = true;
			}
		if (!replaced)
			put(&out, p, len, line);
		for (k = 0; k < n; k++)
			if (s[k].after == line && s[k].header != SIZE_MAX)
				put_set(&out, &s[k], (int)k);
		p += len + (nl != NULL);
	}
	put_added(&out, s, n);
	if (out.oom || out.p == NULL) {
		free(out.p);
		free(out.from);
		return -1;
	}
	o->text = out.p;
	o->from = out.from;
	o->nlines = out.nl;
	return 0;
}

int
override_apply(struct override_text *o, const char *path, const char *text,
    const char *const *sets, size_t nsets, struct drape_err *err)
{
	struct spec *s;
	struct ini ini;
	size_t k, j;
	int rc = -1;

	memset(o, 0, sizeof *o);
	o->sets = sets;
	if (ini_parse(&ini, path, text, err) != 0)
		return -1;
	if ((s = calloc(nsets ? nsets : 1, sizeof *s)) == NULL) {
		err_set(err, "%s: out of memory", path);
		ini_free(&ini);
		return -1;
	}
	for (k = 0; k < nsets; k++)
		if (parse_spec(&s[k], sets[k], err) != 0 || place(&s[k], &ini, err) != 0)
			goto out;
	for (k = 0; k < nsets; k++)
		for (j = 0; j < k; j++)
			if (same_target(&s[j], &s[k]) && strcmp(s[j].key, s[k].key) == 0) {
				err_set(err, "--set %s: %s.%s is already set by --set %s; expected "
				    "each key once", s[k].raw, s[k].section, s[k].key, s[j].raw);
				goto out;
			}
	if (build(o, text, s, nsets) != 0) {
		err_set(err, "%s: out of memory", path);
		goto out;
	}
	rc = 0;
out:
	for (k = 0; k < nsets; k++)
		free(s[k].buf);
	free(s);
	ini_free(&ini);
	return rc;
}

void
override_free(struct override_text *o)
{
	free(o->text);
	free(o->from);
	memset(o, 0, sizeof *o);
}

void
override_where(const struct override_text *o, const char *path, int line, char *buf,
    size_t len)
{
	int from = line >= 1 && line <= o->nlines ? o->from[line - 1] : line > 0 ? line : 1;

	if (from > 0)
		snprintf(buf, len, "%s:%d", path, from);
	else
		snprintf(buf, len, "--set %s", o->sets[-from - 1]);
}

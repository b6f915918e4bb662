/* json.h: a strict JSON reader (RFC 8259) for the tests: the grammar and
 * nothing more (no comments, trailing commas, NaN, single quotes, leading
 * zeros or unescaped control characters), well-formed UTF-8 and escapes
 * (surrogates in pairs), no repeated key in an object, nothing after the
 * value but white space. Objects keep their keys in order. */
#ifndef DRAPE_TEST_JSON_H
#define DRAPE_TEST_JSON_H

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum jtype { J_NULL, J_BOOL, J_NUM, J_STR, J_ARR, J_OBJ };

struct jval {
	enum jtype t;
	bool b;
	double num;
	char *s;		/* J_STR */
	size_t n;		/* J_ARR, J_OBJ: items */
	struct jval *items;
	char **keys;		/* J_OBJ */
};

struct jparse {
	const char *p;
	const char *why;
	int depth;
};

static void json_free(struct jval *v);

static inline void
jp_ws(struct jparse *j)
{
	while (*j->p == ' ' || *j->p == '\t' || *j->p == '\n' || *j->p == '\r')
		j->p++;
}

static inline int
jp_fail(struct jparse *j, const char *why)
{
	if (j->why == NULL)
		j->why = why;
	return -1;
}

/* Appends code point c as UTF-8. */
static inline void
jp_put_utf8(char *out, size_t *len, unsigned long c)
{
	if (c < 0x80) {
		out[(*len)++] = (char)c;
	} else if (c < 0x800) {
		out[(*len)++] = (char)(0xc0 | c >> 6);
		out[(*len)++] = (char)(0x80 | (c & 0x3f));
	} else if (c < 0x10000) {
		out[(*len)++] = (char)(0xe0 | c >> 12);
		out[(*len)++] = (char)(0x80 | (c >> 6 & 0x3f));
		out[(*len)++] = (char)(0x80 | (c & 0x3f));
	} else {
		out[(*len)++] = (char)(0xf0 | c >> 18);
		out[(*len)++] = (char)(0x80 | (c >> 12 & 0x3f));
		out[(*len)++] = (char)(0x80 | (c >> 6 & 0x3f));
		out[(*len)++] = (char)(0x80 | (c & 0x3f));
	}
}

static inline int
jp_hex4(struct jparse *j, unsigned long *c)
{
	int k;

	*c = 0;
	for (k = 0; k < 4; k++) {
		char h = *j->p++;

		*c <<= 4;
		if (h >= '0' && h <= '9')
			*c |= (unsigned long)(h - '0');
		else if (h >= 'a' && h <= 'f')
			*c |= (unsigned long)(h - 'a' + 10);
		else if (h >= 'A' && h <= 'F')
			*c |= (unsigned long)(h - 'A' + 10);
		else
			return jp_fail(j, "\\u needs four hex digits");
	}
	return 0;
}

/* A well-formed UTF-8 sequence at s: its length, or 0. */
static inline size_t
jp_utf8(const unsigned char *s)
{
	size_t n, k;
	unsigned long c;

	if (s[0] < 0x80)
		return 1;
	if (s[0] >= 0xc2 && s[0] <= 0xdf)
		n = 2, c = s[0] & 0x1f;
	else if (s[0] >= 0xe0 && s[0] <= 0xef)
		n = 3, c = s[0] & 0x0f;
	else if (s[0] >= 0xf0 && s[0] <= 0xf4)
		n = 4, c = s[0] & 0x07;
	else
		return 0;
	for (k = 1; k < n; k++) {
		if ((s[k] & 0xc0) != 0x80)
			return 0;
		c = c << 6 | (s[k] & 0x3f);
	}
	if ((n == 3 && c < 0x800) || (n == 4 && (c < 0x10000 || c > 0x10ffff)) ||
	    (c >= 0xd800 && c <= 0xdfff))
		return 0;
	return n;
}

static inline int
jp_string(struct jparse *j, char **out)
{
	const char *start = ++j->p;	/* after the quote */
	char *s = malloc(strlen(start) + 1);	/* never longer than the source */
	size_t len = 0, n;
	unsigned long c, lo;

	if (s == NULL)
		return jp_fail(j, "out of memory");
	for (;;) {
		unsigned char ch = (unsigned char)*j->p;

		if (ch == '"') {
			j->p++;
			break;
		}
		if (ch == '\0') {
			free(s);
			return jp_fail(j, "unterminated string");
		}
		if (ch < 0x20) {
			free(s);
			return jp_fail(j, "control character in a string");
		}
		if (ch == '\\') {
			j->p++;
			switch (*j->p++) {
			case '"': s[len++] = '"'; break;
			case '\\': s[len++] = '\\'; break;
			case '/': s[len++] = '/'; break;
			case 'b': s[len++] = '\b'; break;
			case 'f': s[len++] = '\f'; break;
			case 'n': s[len++] = '\n'; break;
			case 'r': s[len++] = '\r'; break;
			case 't': s[len++] = '\t'; break;
			case 'u':
				if (jp_hex4(j, &c) != 0) {
					free(s);
					return -1;
				}
				if (c >= 0xdc00 && c <= 0xdfff) {
					free(s);
					return jp_fail(j, "lone low surrogate");
				}
				if (c >= 0xd800 && c <= 0xdbff) {
					if (j->p[0] != '\\' || j->p[1] != 'u') {
						free(s);
						return jp_fail(j, "high surrogate without its pair");
					}
					j->p += 2;
					if (jp_hex4(j, &lo) != 0 || lo < 0xdc00 || lo > 0xdfff) {
						free(s);
						return jp_fail(j, "bad surrogate pair");
					}
					c = 0x10000 + ((c - 0xd800) << 10) + (lo - 0xdc00);
				}
				if (c == 0) {
					free(s);
					return jp_fail(j, "\\u0000 in a string");
				}
				jp_put_utf8(s, &len, c);
				break;
			default:
				free(s);
				return jp_fail(j, "bad escape");
			}
			continue;
		}
		if ((n = jp_utf8((const unsigned char *)j->p)) == 0) {
			free(s);
			return jp_fail(j, "bad UTF-8");
		}
		memcpy(s + len, j->p, n);
		len += n;
		j->p += n;
	}
	s[len] = '\0';
	*out = s;
	return 0;
}

static inline int
jp_number(struct jparse *j, double *out)
{
	const char *start = j->p;
	char *end;

	if (*j->p == '-')
		j->p++;
	if (*j->p == '0')
		j->p++;
	else if (*j->p >= '1' && *j->p <= '9')
		while (*j->p >= '0' && *j->p <= '9')
			j->p++;
	else
		return jp_fail(j, "bad number");
	if (*j->p == '.') {
		j->p++;
		if (!(*j->p >= '0' && *j->p <= '9'))
			return jp_fail(j, "bad fraction");
		while (*j->p >= '0' && *j->p <= '9')
			j->p++;
	}
	if (*j->p == 'e' || *j->p == 'E') {
		j->p++;
		if (*j->p == '+' || *j->p == '-')
			j->p++;
		if (!(*j->p >= '0' && *j->p <= '9'))
			return jp_fail(j, "bad exponent");
		while (*j->p >= '0' && *j->p <= '9')
			j->p++;
	}
	*out = strtod(start, &end);
	if (end != j->p)
		return jp_fail(j, "bad number");
	return 0;
}

static inline int jp_value(struct jparse *j, struct jval *v);

static inline int
jp_push(struct jval *v, char *key, struct jval *item)
{
	struct jval *ni = realloc(v->items, (v->n + 1) * sizeof *ni);
	char **nk;

	if (ni == NULL)
		return -1;
	v->items = ni;
	if (v->t == J_OBJ) {
		if ((nk = realloc(v->keys, (v->n + 1) * sizeof *nk)) == NULL)
			return -1;
		v->keys = nk;
		v->keys[v->n] = key;
	}
	v->items[v->n++] = *item;
	return 0;
}

static inline int
jp_container(struct jparse *j, struct jval *v, char close)
{
	struct jval item;
	char *key = NULL;
	size_t k;

	if (++j->depth > 64)
		return jp_fail(j, "nested too deep");
	j->p++;
	jp_ws(j);
	if (*j->p == close) {
		j->p++;
		j->depth--;
		return 0;
	}
	for (;;) {
		jp_ws(j);
		if (close == '}') {
			if (*j->p != '"')
				return jp_fail(j, "expected a key");
			if (jp_string(j, &key) != 0)
				return -1;
			for (k = 0; k < v->n; k++)
				if (strcmp(v->keys[k], key) == 0) {
					free(key);
					return jp_fail(j, "repeated key");
				}
			jp_ws(j);
			if (*j->p++ != ':') {
				free(key);
				return jp_fail(j, "expected ':'");
			}
		}
		memset(&item, 0, sizeof item);
		if (jp_value(j, &item) != 0 || jp_push(v, key, &item) != 0) {
			json_free(&item);
			free(key);
			return jp_fail(j, "bad value");
		}
		key = NULL;
		jp_ws(j);
		if (*j->p == ',') {
			j->p++;
			continue;
		}
		if (*j->p == close) {
			j->p++;
			j->depth--;
			return 0;
		}
		return jp_fail(j, close == '}' ? "expected ',' or '}'" : "expected ',' or ']'");
	}
}

static inline int
jp_value(struct jparse *j, struct jval *v)
{
	memset(v, 0, sizeof *v);
	jp_ws(j);
	switch (*j->p) {
	case '{': v->t = J_OBJ; return jp_container(j, v, '}');
	case '[': v->t = J_ARR; return jp_container(j, v, ']');
	case '"': v->t = J_STR; return jp_string(j, &v->s);
	case 't':
		if (strncmp(j->p, "true", 4) != 0)
			return jp_fail(j, "bad literal");
		j->p += 4;
		v->t = J_BOOL;
		v->b = true;
		return 0;
	case 'f':
		if (strncmp(j->p, "false", 5) != 0)
			return jp_fail(j, "bad literal");
		j->p += 5;
		v->t = J_BOOL;
		return 0;
	case 'n':
		if (strncmp(j->p, "null", 4) != 0)
			return jp_fail(j, "bad literal");
		j->p += 4;
		v->t = J_NULL;
		return 0;
	default:
		v->t = J_NUM;
		return jp_number(j, &v->num);
	}
}

/* 0, or -1 with why (and where) set. */
static inline int
json_parse(const char *text, struct jval *v, const char **why, size_t *at)
{
	struct jparse j = { text, NULL, 0 };
	int rc = jp_value(&j, v);

	if (rc == 0) {
		jp_ws(&j);
		if (*j.p != '\0')
			rc = jp_fail(&j, "text after the value");
	}
	if (rc != 0) {
		json_free(v);
		*why = j.why;
		*at = (size_t)(j.p - text);
	}
	return rc;
}

static void
json_free(struct jval *v)
{
	size_t k;

	for (k = 0; k < v->n; k++) {
		json_free(&v->items[k]);
		if (v->keys != NULL)
			free(v->keys[k]);
	}
	free(v->items);
	free(v->keys);
	free(v->s);
	memset(v, 0, sizeof *v);
}

/* The member at a dotted path ("energy.total"), or NULL. */
static inline const struct jval *
json_get(const struct jval *v, const char *path)
{
	char part[128];
	const char *dot;
	size_t len, k;

	while (v != NULL && *path != '\0') {
		dot = strchr(path, '.');
		len = dot != NULL ? (size_t)(dot - path) : strlen(path);
		if (v->t != J_OBJ || len >= sizeof part)
			return NULL;
		memcpy(part, path, len);
		part[len] = '\0';
		for (k = 0; k < v->n && strcmp(v->keys[k], part) != 0; k++)
			;
		v = k < v->n ? &v->items[k] : NULL;
		path = dot != NULL ? dot + 1 : path + len;
	}
	return v;
}

#endif

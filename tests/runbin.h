/* runbin.h: runs the built drape binary with its output captured, for the
 * tests that check it from the outside. */
#ifndef DRAPE_RUNBIN_H
#define DRAPE_RUNBIN_H

#include <stdio.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include "testutil.h"

#define DRAPE TOP_BUILDDIR "/src/drape"

struct result {
	int status;
	char out[16384];
	char err[4096];
};

static inline void
slurp(const char *path, char *buf, size_t len)
{
	FILE *f = fopen(path, "r");
	size_t n = 0;

	if (f != NULL) {
		n = fread(buf, 1, len - 1, f);
		fclose(f);
	}
	buf[n] = '\0';
}

/* A fresh directory per test program, for captured output and the files a
 * test writes; the cmocka group setup and teardown make and remove it. */
static char dir[] = "/tmp/drape-test-XXXXXX";

/* Writes len bytes of data to dir/name and returns its path, which stays
 * good for the next 7 files written. */
static inline const char *
dir_write(const char *name, const void *data, size_t len)
{
	static char path[8][700];
	static int k;
	char *p = path[k++ % 8];
	FILE *f;

	snprintf(p, sizeof path[0], "%s/%s", dir, name);
	f = fopen(p, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite(data, 1, len, f), len);
	assert_int_equal(fclose(f), 0);
	return p;
}

static inline const char *
dir_write_text(const char *name, const char *text)
{
	return dir_write(name, text, strlen(text));
}

static inline int
setup(void **state)
{
	(void)state;
	return mkdtemp(dir) == NULL ? -1 : 0;
}

static inline int
teardown(void **state)
{
	char cmd[600];

	(void)state;
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	return system(cmd) == 0 ? 0 : -1;
}

/* Runs "drape ARGS" with stdout and stderr captured in files under dir. */
static inline void
drape(struct result *r, const char *args)
{
	char cmd[4096], out[64], err[64];
	int st;

	snprintf(out, sizeof out, "%s/out", dir);
	snprintf(err, sizeof err, "%s/err", dir);
	snprintf(cmd, sizeof cmd, "'%s' %s >'%s' 2>'%s' </dev/null", DRAPE, args, out, err);
	st = system(cmd);
	assert_true(st != -1 && WIFEXITED(st));
	r->status = WEXITSTATUS(st);
	slurp(out, r->out, sizeof r->out);
	slurp(err, r->err, sizeof r->err);
}

#endif

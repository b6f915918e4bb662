/* testutil.h: helpers shared by the cmocka test programs. */
#ifndef DRAPE_TESTUTIL_H
#define DRAPE_TESTUTIL_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "scene.h"
#include "stepper.h"

#define SCENE_DIR TOP_SRCDIR "/scenes/"

/* cmocka 1.1 compares floats only. */
#define assert_double_equal(a, b, eps) do { \
	double a_ = (a), b_ = (b), e_ = (eps); \
	if (!(fabs(a_ - b_) <= e_)) \
		fail_msg("%s = %.17g, expected %.17g within %g", #a, a_, b_, e_); \
} while (0)

/* Parses scene text, failing the test with the parser's message. */
static inline void
parse_text(struct scene *sc, const char *text)
{
	struct drape_err err;

	if (scene_parse(sc, "test.scene", text, &err) != 0)
		fail_msg("scene_parse: %s", err.msg);
}

static inline void
load_shipped(struct scene *sc, const char *name)
{
	struct drape_err err;

	if (scene_load(sc, name, &err) != 0)
		fail_msg("scene_load: %s", err.msg);
}

/* A shipped scene with the first occurrence of `from` replaced by `to`. */
static inline void
load_shipped_with(struct scene *sc, const char *path, const char *from, const char *to)
{
	struct drape_err err;
	char text[16384], out[16384], *at;
	size_t n;
	FILE *f = fopen(path, "r");

	if (f == NULL)
		fail_msg("cannot open %s", path);
	n = fread(text, 1, sizeof text - 1, f);
	fclose(f);
	text[n] = '\0';
	if ((at = strstr(text, from)) == NULL)
		fail_msg("%s has no '%s'", path, from);
	snprintf(out, sizeof out, "%.*s%s%s", (int)(at - text), text, to, at + strlen(from));
	if (scene_parse(sc, path, out, &err) != 0)
		fail_msg("scene_parse: %s", err.msg);
}

static inline void
init_stepper(struct stepper *st, const struct scene *sc)
{
	struct drape_err err;

	if (stepper_init(st, sc, &err) != 0)
		fail_msg("stepper_init: %s", err.msg);
}

/* Runs to the scene's end; fails the test on a blow-up. */
static inline void
run_to_end(struct stepper *st)
{
	struct blowup bl;

	while (!stepper_done(st))
		if (stepper_step(st, &bl) != 0)
			fail_msg("blow-up at step %ld node %d: %s", bl.step, bl.node, bl.why);
}

static inline void
step_n(struct stepper *st, long n)
{
	struct blowup bl;

	while (n-- > 0)
		if (stepper_step(st, &bl) != 0)
			fail_msg("blow-up at step %ld node %d: %s", bl.step, bl.node, bl.why);
}

#endif

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

#include "cloth.h"
#include "network.h"
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

/* Scene text (read from path) with the first occurrence of `from`
 * replaced by `to`. */
static inline void
parse_text_with(struct scene *sc, const char *path, const char *text, const char *from,
    const char *to)
{
	struct drape_err err;
	char out[16384];
	const char *at;

	if ((at = strstr(text, from)) == NULL)
		fail_msg("%s has no '%s'", path, from);
	snprintf(out, sizeof out, "%.*s%s%s", (int)(at - text), text, to, at + strlen(from));
	if (scene_parse(sc, path, out, &err) != 0)
		fail_msg("scene_parse: %s", err.msg);
}

/* A shipped scene with the first occurrence of `from` replaced by `to`. */
static inline void
load_shipped_with(struct scene *sc, const char *path, const char *from, const char *to)
{
	char text[16384];
	size_t n;
	FILE *f = fopen(path, "r");

	if (f == NULL)
		fail_msg("cannot open %s", path);
	n = fread(text, 1, sizeof text - 1, f);
	fclose(f);
	text[n] = '\0';
	parse_text_with(sc, path, text, from, to);
}

static inline struct stepper *
new_stepper(const struct scene *sc)
{
	struct drape_err err;
	struct stepper *st = stepper_new(sc, &err);

	if (st == NULL)
		fail_msg("stepper_new: %s", err.msg);
	return st;
}

/* The run's report, as a value. */
static inline struct stepper_report
report_of(const struct stepper *st)
{
	struct stepper_report r;

	stepper_report(st, &r);
	return r;
}

/* The network's cloth. */
static inline const struct cloth *
cloth_of(const struct stepper *st)
{
	return &stepper_network(st)->cl;
}

/* The whole state: positions (3n) then velocities (3n). */
static inline const double *
state_y(const struct stepper *st)
{
	struct stepper_state s;

	stepper_save(st, &s);
	return s.y;
}

/* Puts a copy of st's state through edit(ctx, y, n) and st into it. */
static inline void
edit_state(struct stepper *st, void (*edit)(void *ctx, double *y, int n), void *ctx)
{
	struct stepper_state s;
	struct drape_err err;
	int n = cloth_of(st)->n;
	double *y = malloc(6 * (size_t)n * sizeof *y);

	assert_non_null(y);
	stepper_save(st, &s);
	memcpy(y, s.y, 6 * (size_t)n * sizeof *y);
	edit(ctx, y, n);
	s.y = y;
	s.hash = stepper_state_hash(y, s.hist, (size_t)n, s.t);
	if (stepper_restore(st, &s, &err) != 0)
		fail_msg("stepper_restore: %s", err.msg);
	free(y);
}

/* One step; fails the test on a blow-up or an error. */
static inline void
step_once(struct stepper *st)
{
	struct step_failure f;
	char msg[600];

	if (stepper_step(st, &f) != STEP_OK) {
		step_failure_format(&f, msg, sizeof msg);
		fail_msg("%s", msg);
	}
}

/* Runs to the scene's end; fails the test on a blow-up. */
static inline void
run_to_end(struct stepper *st)
{
	while (!stepper_done(st))
		step_once(st);
}

static inline void
step_n(struct stepper *st, long n)
{
	while (n-- > 0)
		step_once(st);
}

#endif

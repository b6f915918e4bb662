/* test_screen.c: the TUI's screen model without a terminal: the layout at
 * 80 x 24 (one panel under tabs), 200 x 60 (all panels) and too small; the
 * per-node event rings; the status line and the panels fitting their
 * width and saying what they should. */
#include "testutil.h"
#include "evlog.h"
#include "screen.h"
#include "tui.h"

static void
layout_by_size(void **state)
{
	struct layout lo;
	int k;

	(void)state;
	screen_layout(&lo, 80, 24, PANEL_HASH);
	assert_false(lo.too_small);
	assert_false(lo.stacked);
	assert_int_equal(lo.view.w + 1 + lo.side.w, 80);
	assert_int_equal(lo.side.w, 30);
	assert_int_equal(lo.view.h, 22);
	assert_int_equal(lo.keys.y, 23);
	assert_int_equal(lo.tabs_y, 1);
	for (k = 0; k < PANEL_COUNT; k++)
		assert_int_equal(lo.panel[k].h > 0, k == PANEL_HASH);
	screen_layout(&lo, 200, 60, PANEL_HASH);
	assert_true(lo.stacked);
	assert_int_equal(lo.view.w + 1 + lo.side.w, 200);
	for (k = 0; k < PANEL_COUNT; k++) {
		assert_true(lo.panel[k].h > 0);
		assert_true(lo.panel[k].y + lo.panel[k].h <= 59);
		if (k > 0)
			assert_int_equal(lo.panel[k].y, lo.panel[k - 1].y + lo.panel[k - 1].h);
	}
	screen_layout(&lo, 39, 24, PANEL_NODE);
	assert_true(lo.too_small);
	screen_layout(&lo, 80, 11, PANEL_NODE);
	assert_true(lo.too_small);
}

static struct contact_event
event(long step, int node)
{
	struct contact_event e;

	memset(&e, 0, sizeof e);
	e.step = step;
	e.node = node;
	e.type = CONTACT_NODE_FACE;
	e.other = 7;
	e.obstacle = -1;
	e.vn_before = -0.5;
	e.vn_after = 0.1;
	return e;
}

static void
event_rings(void **state)
{
	struct evlog log;
	struct contact_event ev[3];
	long s;

	(void)state;
	assert_int_equal(evlog_init(&log, 5), 0);
	assert_null(evlog_get(&log, 2, 0));
	for (s = 0; s < 10; s++) {
		ev[0] = event(s, 2);
		ev[1] = event(s, 4);
		ev[2] = event(s, 99);	/* out of range: skipped */
		evlog_add(&log, ev, s < 3 ? 2 : 1);
	}
	assert_int_equal(log.count[2], 10);
	assert_int_equal(log.count[4], 3);
	assert_int_equal(log.total, 13);
	for (s = 0; s < EVLOG_PER_NODE; s++)
		assert_int_equal(evlog_get(&log, 2, (int)s)->step, 9 - s);
	assert_null(evlog_get(&log, 2, EVLOG_PER_NODE));
	assert_int_equal(evlog_get(&log, 4, 0)->step, 2);
	assert_null(evlog_get(&log, 4, 3));
	assert_null(evlog_get(&log, 0, 0));
	evlog_free(&log);
}

#define SCENE_TEXT "[simulation]\nname = small\nduration = 0.01 s\n[cloth]\nnodes = 4 4\n" \
	"spacing = 10 mm\nweight = 100 g/m2\nthickness = 0.3 mm\nmodulus_warp = 1 MPa\n" \
	"modulus_weft = 1 MPa\nshear_modulus = 0\nbending_warp = 0\nbending_weft = 0\n" \
	"[plane]\npoint = 0 -1 0 m\n[collision]\nself = on\nbroad = grid\nnarrow = ccd\n"

static void
status_and_panels(void **state)
{
	struct scene sc;
	struct stepper *st;
	struct drape_err err;
	struct source src;
	struct source_live lv;
	struct source_state s;
	struct source_stats ss;
	struct status_info si;
	struct evlog log;
	struct contact_event ev = event(6, 5);
	struct text t;
	char line[TEXT_WIDTH];
	vec3 f;
	int k;

	(void)state;
	parse_text(&sc, SCENE_TEXT);
	assert_non_null(st = stepper_new(&sc, &err));
	source_live(&src, &lv, st);
	for (k = 0; k < 7; k++)
		assert_int_equal(src.step(src.ctx, line, sizeof line), SOURCE_STEPPED);
	src.state(src.ctx, &s);
	assert_int_equal(s.step, 7);
	si = (struct status_info){ &s, 0.25, "paused", 256, "no", NULL };
	screen_status(line, 80, &si);
	assert_true(strlen(line) <= 80);
	assert_non_null(strstr(line, "step 7 "));
	assert_non_null(strstr(line, "paused"));
	assert_non_null(strstr(line, "0.25x"));
	screen_status(line, 150, &si);
	assert_non_null(strstr(line, "small  t "));
	assert_non_null(strstr(line, "256 steps/frame"));

	src.stats(src.ctx, &ss);
	assert_true(ss.active);
	text_init(&t, 30);
	screen_collisions(&t, &ss);
	assert_string_equal(t.line[0], "collisions     step      total");
	text_init(&t, 30);
	screen_hash(&t, &ss);
	assert_int_equal(t.n, 5 + HASH_HIST);
	for (k = 0; k < t.n; k++)
		assert_true(strlen(t.line[k]) <= 30);

	/* the node inspector: force known, one event */
	assert_int_equal(evlog_init(&log, s.cl->n), 0);
	evlog_add(&log, &ev, 1);
	assert_true(src.force(src.ctx, 5, &f));
	/* at rest on nothing, a free node's force is its weight */
	text_init(&t, 30);
	screen_node(&t, &s, 5, &f, &log);
	assert_string_equal(t.line[0], "node 5 (i 1, j 1)");
	assert_non_null(strstr(t.line[3], "f N"));
	assert_non_null(strstr(t.line[4], "events: 1"));
	assert_non_null(strstr(t.line[6], "6 n-f     7 -0.500 +0.100"));
	for (k = 0; k < t.n; k++)
		if (strlen(t.line[k]) > 30 || strchr(t.line[k], '\n') != NULL)
			fail_msg("node line %d is '%s'", k, t.line[k]);
	text_init(&t, 30);
	screen_node(&t, &s, 3, NULL, &log);
	assert_non_null(strstr(t.line[3], "not known"));
	assert_non_null(strstr(t.line[6], "none yet"));
	text_init(&t, 60);
	tui_help(&t, false);
	assert_true(t.n > 10);

	evlog_free(&log);
	source_live_free(&lv);
	stepper_free(st);
	scene_free(&sc);
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(layout_by_size),
		cmocka_unit_test(event_rings),
		cmocka_unit_test(status_and_panels),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}

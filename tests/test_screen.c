/* test_screen.c: the TUI's screen model without a terminal: the layout at
 * 80 x 24 (one panel under tabs), 200 x 60 (all panels) and too small; the
 * per-node event rings; the status line and the panels fitting their
 * width and saying what they should. */
#include "testutil.h"
#include "evlog.h"
#include "pace.h"
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
	si = (struct status_info){ &s, 0.25, "paused", "1x", "no", NULL };
	screen_status(line, 80, &si);
	assert_true(strlen(line) <= 80);
	assert_non_null(strstr(line, "step 7 "));
	assert_non_null(strstr(line, " 1x (0.25x) paused"));
	screen_status(line, 150, &si);
	assert_non_null(strstr(line, "small  t "));
	assert_non_null(strstr(line, "plays at 1x (0.25x) of real time  paused"));

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
	/* the event of step 6 (from state 6 to 7) is shown as step 7's */
	assert_non_null(strstr(t.line[6], "7 n-f     7 -0.500 +0.100"));
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

/* Issue 30: the TUI plays at real time by default (the tablecloth was
 * over in 1.5 s), twice or half as fast by + and -, flat out by *; a run
 * that cannot keep up goes on from where it is. */
static void
pace_of_play(void **state)
{
	struct pace p;
	char label[16];
	int k;

	(void)state;
	pace_init(&p, 100, 0);
	pace_label(&p, label, sizeof label);
	assert_string_equal(label, "1x");
	assert_double_equal(pace_target(&p, 100.5), 0.5, 0);	/* real time */
	assert_true(pace_change(&p, 1));
	pace_anchor(&p, 101, 0.6);
	pace_label(&p, label, sizeof label);
	assert_string_equal(label, "2x");
	assert_double_equal(pace_target(&p, 102), 2.6, 1e-15);
	for (k = 0; k < 3; k++)
		assert_true(pace_change(&p, -1));
	pace_label(&p, label, sizeof label);
	assert_string_equal(label, "1/4x");
	for (k = 0; k < 4; k++)
		assert_true(pace_change(&p, -1));
	assert_false(pace_change(&p, -1));	/* 1/64x is the slowest */
	pace_toggle_flat_out(&p);
	pace_label(&p, label, sizeof label);
	assert_string_equal(label, "max");
	assert_true(isinf(pace_target(&p, 200)));
	assert_true(pace_change(&p, 1));	/* back to its multiple */
	pace_label(&p, label, sizeof label);
	assert_string_equal(label, "1/64x");
	/* 1x, two seconds behind at 0.1 s a frame: anchored where it is */
	pace_init(&p, 0, 0);
	pace_keep_up(&p, 2, 0.05, 0.1);
	assert_double_equal(pace_target(&p, 2), 0.05, 0);
	pace_keep_up(&p, 2.05, 0.05, 0.1);	/* within a frame: kept */
	assert_double_equal(pace_target(&p, 2.05), 0.1, 1e-15);
}

/* Issue 30: the key line was cut mid-word at 80 columns ("v v"): items
 * fit whole or are left out. */
static void
key_line_fits(void **state)
{
	static const char *const items[] = { "? help", "q quit", "space run/pause", "+/- speed",
		"* max", "n step", "arrows rotate", "z/Z zoom", "v view", "Tab panel", "[/] node" };
	char line[TEXT_WIDTH + 1];
	size_t i;
	int w;

	(void)state;
	for (w = 10; w <= 120; w++) {
		screen_keys(line, w, items, sizeof items / sizeof items[0]);
		assert_true((int)strlen(line) <= w);
		/* every item in it whole, two spaces apart */
		{
			char copy[TEXT_WIDTH + 1], *p = copy, *sep;

			snprintf(copy, sizeof copy, "%s", line);
			while (*p != '\0') {
				sep = strstr(p, "  ");
				if (sep != NULL)
					*sep = '\0';
				for (i = 0; i < sizeof items / sizeof items[0]; i++)
					if (strcmp(p, items[i]) == 0)
						break;
				if (i == sizeof items / sizeof items[0])
					fail_msg("width %d: '%s' is no item of '%s'", w, p, line);
				if (sep == NULL)
					break;
				p = sep + 2;
			}
		}
	}
	screen_keys(line, 80, items, sizeof items / sizeof items[0]);
	assert_string_equal(line, "? help  q quit  space run/pause  +/- speed  * max  n step  "
	    "arrows rotate  v view");	/* z/Z zoom left out, a shorter one after it in */
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(layout_by_size),
		cmocka_unit_test(event_rings),
		cmocka_unit_test(status_and_panels),
		cmocka_unit_test(pace_of_play),
		cmocka_unit_test(key_line_fits),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}

/* screen.c: layout and text of the TUI's parts. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "screen.h"

const char *const panel_name[PANEL_COUNT] = { "collisions", "hash", "node" };

/* Lines each panel needs, title included. */
static const int panel_height[PANEL_COUNT] = { 11, 5 + HASH_HIST, 6 + EVLOG_PER_NODE + 1 };

static const char *const short_type[CONTACT_NTYPES] = { "n-n", "n-e", "n-f", "e-e", "obs" };

void
text_init(struct text *t, int width)
{
	t->n = 0;
	t->width = width < 1 ? 1 : width >= TEXT_WIDTH ? TEXT_WIDTH - 1 : width;
}

void
text_add(struct text *t, const char *fmt, ...)
{
	va_list ap;
	char buf[512];

	if (t->n >= TEXT_LINES)
		return;
	va_start(ap, fmt);
	vsnprintf(buf, sizeof buf, fmt, ap);
	va_end(ap);
	snprintf(t->line[t->n++], (size_t)t->width + 1, "%s", buf);
}

void
screen_layout(struct layout *lo, int cols, int rows, enum panel focus)
{
	int side_w, body_h, need = 0, y, k;

	memset(lo, 0, sizeof *lo);
	lo->too_small = cols < SCREEN_MIN_COLS || rows < SCREEN_MIN_ROWS;
	if (lo->too_small)
		return;
	side_w = cols >= 160 ? 48 : cols >= 120 ? 40 : 30;
	body_h = rows - 2;
	lo->status = (struct rect){ 0, 0, cols, 1 };
	lo->keys = (struct rect){ 0, rows - 1, cols, 1 };
	/* the view, a separator column, the panels */
	lo->view = (struct rect){ 0, 1, cols - side_w - 1, body_h };
	lo->side = (struct rect){ cols - side_w, 1, side_w, body_h };
	for (k = 0; k < PANEL_COUNT; k++)
		need += panel_height[k];
	lo->stacked = need <= body_h;
	if (lo->stacked) {
		lo->tabs_y = -1;
		for (k = 0, y = lo->side.y; k < PANEL_COUNT; k++) {
			lo->panel[k] = (struct rect){ lo->side.x, y, side_w, panel_height[k] };
			y += panel_height[k];
		}
		return;
	}
	lo->tabs_y = lo->side.y;
	lo->panel[focus] = (struct rect){ lo->side.x, lo->side.y + 1, side_w, body_h - 1 };
}

/* A replay's: its file, where it is, and how its frame stands to it. */
static void
replay_status(char *buf, int width, const struct status_info *si)
{
	const struct source_state *s = si->s;
	const struct source_position *p = si->pos;
	const char *base = strrchr(p->file, '/');

	base = base != NULL && base[1] != '\0' ? base + 1 : p->file;
	if (width >= 110)
		snprintf(buf, (size_t)width + 1, "%s  %s  step %ld of %ld  t %.5f s  frame %ld/%ld "
		    "(step %ld)  %s  dt %.3g s  E %.4e J  plays at %s", base, si->mode, s->step,
		    p->last, s->t, p->frame, p->frames, p->frame_step, s->sc->name, s->dt,
		    energy_total(&s->energy), si->pace);
	else
		snprintf(buf, (size_t)width + 1, "%s %s step %ld t %.4fs frame %ld/%ld@%ld E %.3eJ "
		    "%s", base, si->mode, s->step, s->t, p->frame, p->frames, p->frame_step,
		    energy_total(&s->energy), si->pace);
}

void
screen_status(char *buf, int width, const struct status_info *si)
{
	const struct source_state *s = si->s;
	char speed[32];

	if (si->pos != NULL) {
		replay_status(buf, width, si);
		return;
	}
	/* the pace asked for, and the speed measured (which falls short of
	 * it where the run cannot keep up) */
	if (si->speed > 0)
		snprintf(speed, sizeof speed, " (%.2gx)", si->speed);
	else
		speed[0] = '\0';
	if (width >= 110)
		snprintf(buf, (size_t)width + 1, "%s  t %.5f s  step %ld  dt %.3g s  %s  "
		    "E %.4e J  plays at %s%s of real time  %s  recording: %s", s->sc->name, s->t,
		    s->step, s->dt, s->integrator, energy_total(&s->energy), si->pace, speed,
		    si->mode, si->recording);
	else	/* 80 columns: the same facts, tighter */
		snprintf(buf, (size_t)width + 1, "t %.4fs step %ld dt %.2gs %s E %.3eJ %s%s %s%s",
		    s->t, s->step, s->dt, s->integrator, energy_total(&s->energy), si->pace, speed,
		    si->mode, strcmp(si->recording, "no") == 0 ? "" : " rec");
}

void
screen_keys(char *buf, int width, const char *const *items, size_t n)
{
	size_t i, len = 0, want;

	buf[0] = '\0';
	for (i = 0; i < n; i++) {
		want = len + (len > 0 ? 2 : 0) + strlen(items[i]);
		if (want > (size_t)width)
			continue;	/* a shorter one further on may fit */
		snprintf(buf + len, (size_t)width + 1 - len, "%s%s", len > 0 ? "  " : "", items[i]);
		len = want;
	}
}

void
screen_collisions(struct text *t, const struct source_stats *ss)
{
	const struct collide_stats *a = ss->step, *b = ss->total;
	int k;

	text_add(t, "%-12s %6s %10s", "collisions", "step", "total");
	if (!ss->active) {
		text_add(t, "nothing to collide with");
		return;
	}
	/* the run's column of a STAT_MAX counter is its largest */
	for (k = 0; k < STAT_COUNT; k++)
		if (stat_field[k].panel)
			text_add(t, "%-12s %6ld %10ld", stat_field[k].label, a->n[k], b->n[k]);
}

void
screen_hash(struct text *t, const struct source_stats *ss)
{
	const struct hash_stats *h = ss->hash;
	long most = 1;
	int k, bar = t->width - 12;

	text_add(t, "hash (latest fill)");
	if (!ss->active || !ss->has_hash) {
		text_add(t, ss->active ? "no spatial hash (broad = %s)" : "no collisions", ss->broad);
		return;
	}
	text_add(t, "cubes %ld, %ld with >= 2", h->cubes, h->shared);
	text_add(t, "load %.3f  items %ld", h->load, h->entries);
	text_add(t, "probes mean %.3f max %d", h->probe_mean, h->probe_max);
	text_add(t, "items per cube:");
	for (k = 0; k < HASH_HIST; k++)
		if (h->hist[k] > most)
			most = h->hist[k];
	for (k = 0; k < HASH_HIST; k++) {
		char bars[TEXT_WIDTH];
		int len = bar > 0 ? (int)((h->hist[k] * bar + most - 1) / most) : 0;

		memset(bars, '#', (size_t)len);
		bars[len] = '\0';
		text_add(t, "%d%s %-*s %ld", k + 1, k + 1 == HASH_HIST ? "+" : " ", bar > 0 ? bar : 0,
		    bars, h->hist[k]);
	}
}

void
screen_node(struct text *t, const struct source_state *s, int node, const vec3 *f,
    const struct evlog *log)
{
	vec3 x, v;
	int i, j, k;

	if (node < 0 || node >= s->cl->n) {
		text_add(t, "node: none");
		return;
	}
	x = v3_load(s->x + 3 * node);
	v = v3_load(s->v + 3 * node);
	cloth_grid_ij(s->cl, node, &i, &j);
	text_add(t, "node %d (i %d, j %d)%s", node, i, j,
	    s->held != NULL && s->held[node] ? " held" : "");
	/* 30 columns each */
	text_add(t, "x m  %8.4f%8.4f%8.4f", x.x, x.y, x.z);
	if (s->v_note != NULL)	/* estimated: marked, and said why below */
		text_add(t, "v~   %8.4f%8.4f%8.4f", v.x, v.y, v.z);
	else
		text_add(t, "v m/s%8.4f%8.4f%8.4f", v.x, v.y, v.z);
	if (f != NULL)
		text_add(t, "f N%9.1e%9.1e%9.1e", f->x, f->y, f->z);
	else
		text_add(t, "f N  not known here");
	if (s->v_note != NULL)	/* the spare line */
		text_add(t, "%s", s->v_note);
	text_add(t, "events: %ld (latest first)", log->n > node ? log->count[node] : 0);
	text_add(t, "%6s %3s %5s %6s %6s", "step", "typ", "with", "vn in", "out");
	for (k = 0; k < EVLOG_PER_NODE; k++) {
		const struct contact_event *e = evlog_get(log, node, k);
		char with[16];

		if (e == NULL)
			break;
		if (e->type == CONTACT_OBSTACLE || e->other < 0)
			snprintf(with, sizeof with, "ob%d", e->obstacle);
		else
			snprintf(with, sizeof with, "%d", e->other);
		text_add(t, "%6ld %3s %5s %+6.3f %+6.3f", step_shown(e->step), short_type[e->type], with,
		    e->vn_before, e->vn_after);
	}
	if (k == 0)
		text_add(t, "  none yet");
}

void
screen_help(struct text *t, bool replay, const struct screen_key *keys, size_t n)
{
	size_t i;

	text_add(t, "drape: keys%s", replay ? " (a replay)" : "");
	text_add(t, " ");
	for (i = 0; i < n; i++)
		text_add(t, "  %-13s %s", keys[i].names, keys[i].what);
	text_add(t, " ");
	text_add(t, "In the view: X the selected node, o a node in contact this step.");
	if (replay)
		text_add(t, "Frames hold positions: v~ is their difference; keyframes are exact.");
	text_add(t, "Any key closes this help.");
}

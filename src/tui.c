/* tui.c: the ncurses front end: one werase and one doupdate per frame,
 * redraws capped by the delay, ASCII (or braille), colour optional. On a replay
 * (a source that seeks) the arrows, PgUp/PgDn, Home/End and g move in it;
 * on a live run r records. c cycles the colouring (colouring.h) where
 * there is colour, u the glyphs: ASCII, or in a UTF-8 locale braille and
 * half blocks (glyphs.h). */
#include <ctype.h>
#include <curses.h>
#include <errno.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "clock.h"
#include "colouring.h"
#include "evlog.h"
#include "glyphs.h"
#include "pace.h"
#include "paint.h"
#include "raster.h"
#include "screen.h"
#include "tui.h"
#include "view.h"

#define ROTATE_STEP (15 * V3_PI / 180)
#define ZOOM_STEP 1.25
#define PAN_STEP 0.1		/* of the framed radius */
#define EVENT_SEEK_WALL 3.0	/* s: how long `e` may run looking for an event */
#define BUSY_FRACTION 0.8	/* of a frame spent stepping */

/* The one piece of global state: the signal that asks the TUI to end,
 * set by the handler (or by the loop when the terminal is gone, as a
 * SIGHUP), read by the loop. */
static volatile sig_atomic_t quit_signal;

static void
on_signal(int signo)
{
	quit_signal = signo;
}

const volatile sig_atomic_t *
tui_stop_flag(void)
{
	return &quit_signal;
}

enum colour_pair { PAIR_CLOTH = 1, PAIR_SOLID, PAIR_FLOOR, PAIR_CONTACT, PAIR_SELECTED };
/* The colouring's palette: pairs from here, made when first used (the
 * 6x6x6 cube of a 256-colour terminal, else the 8 basic colours). */
#define PAIR_PALETTE 16
#define PALETTE_SIZE 216

struct tui {
	struct source *src;
	struct tui_opts opt;
	bool colour;
	struct camera cam;
	int preset;
	bool follow;		/* f: the camera frames the cloth as it is, each redraw */
	struct raster r;
	struct evlog log;
	bool log_stale;		/* a replay's log is to be gathered again (log_now) */
	int selected;
	enum panel focus;
	bool running, ended, help, quit, dirty;
	struct pace pace;	/* real time, a multiple of it, or flat out */
	double speed;		/* simulated over wall time, measured */
	double mark_wall, mark_t;
	bool replay;		/* the source seeks */
	/* A replay's keys move a target and one seek goes there when the
	 * keys typed so far are read: a seek takes up to half a second the
	 * first time (a digest's events are recomputed), and keys typed
	 * meanwhile each made another, landing late. */
	bool seek_pending;
	long seek_to;
	bool prompt;
	bool prompt_step;	/* the prompt asks for a step, else a node */
	char input[16];
	char msg[300];
	struct tui_result *res;
	/* colouring and glyphs */
	enum colouring colouring;
	double range;		/* of its scale: the largest seen since chosen */
	double *field;		/* n: the colouring's value per node */
	enum glyphs glyphs;	/* ASCII, braille or blocks */
	bool utf8;		/* the locale is */
	struct glyphs_grid g;	/* the Unicode view */
	struct render cells;	/* the ASCII view's colours, a pixel a cell */
	bool palette256;
	unsigned char pair_made[PALETTE_SIZE];
};

static void
say(struct tui *ui, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static void
say(struct tui *ui, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(ui->msg, sizeof ui->msg, fmt, ap);
	va_end(ap);
}

/* A replay moved: the inspector's events are those before it, gathered
 * when the node panel shows them or `e` looks at them (log_now), not at
 * every move. A replay whose events are a digest gathers them by running
 * the recorded run again up to the cursor (replay_events.h): a jump to
 * the end of an rk4 tablecloth took the run's seconds, inspector shown
 * or not. */
static void
rebuild_log(struct tui *ui)
{
	ui->log_stale = true;
	ui->ended = ui->src->done(ui->src->ctx);
}

/* The inspector's events, gathered if the replay moved since (and the
 * message line says so when some of them are unavailable). */
static void
log_now(struct tui *ui)
{
	struct source_state s;

	if (!ui->log_stale)
		return;
	ui->log_stale = false;
	evlog_clear(&ui->log);
	ui->src->history(ui->src->ctx, &ui->log);
	ui->src->state(ui->src->ctx, &s);
	if (s.ev_note != NULL)
		say(ui, "%s", s.ev_note);
}

/* The events the selected node has had so far, its log gathered. */
static long
selected_events(struct tui *ui)
{
	log_now(ui);
	return ui->selected >= 0 && ui->selected < ui->log.n ? ui->log.count[ui->selected] : 0;
}

/* A replay's move, from where the keys before it lead: none is said when
 * it cannot move. The seek itself waits for flush_seek. */
static void
seek(struct tui *ui, enum source_seek how, long step, const char *none)
{
	struct source_state s;
	long from, to;

	ui->running = false;
	ui->src->state(ui->src->ctx, &s);
	from = ui->seek_pending ? ui->seek_to : s.step;
	if ((to = ui->src->target(ui->src->ctx, how, step, from)) < 0) {
		say(ui, "%s", none);
		return;
	}
	ui->seek_pending = true;
	ui->seek_to = to;
}

/* The one seek to where the keys read so far lead. */
static void
flush_seek(struct tui *ui)
{
	if (!ui->seek_pending)
		return;
	ui->seek_pending = false;
	if (!ui->src->seek(ui->src->ctx, SOURCE_GOTO, ui->seek_to)) {
		say(ui, "out of memory for step %ld", ui->seek_to);
		return;
	}
	rebuild_log(ui);
	if (ui->ended)
		say(ui, "end of the replay");
}

/* One step; false when there is none (the end, or a blow-up). */
static bool
step_once(struct tui *ui)
{
	size_t nev;
	const struct contact_event *ev;
	enum source_step r;

	if (ui->ended || ui->res->blown_up) {
		say(ui, "%s", ui->ended ? (ui->replay ? "end of the replay" : "end of the run") :
		    ui->res->why);
		return false;
	}
	switch ((r = ui->src->step(ui->src->ctx, ui->res->why, sizeof ui->res->why))) {
	case SOURCE_STEPPED:
		if (ui->replay) {	/* a frame on: every step in between */
			rebuild_log(ui);
		} else {
			ev = ui->src->events(ui->src->ctx, &nev);
			evlog_add(&ui->log, ev, nev);
		}
		if (ui->src->done(ui->src->ctx)) {
			ui->ended = true;
			ui->running = false;
			say(ui, "%s", ui->replay ? "end of the replay" : "end of the run");
		}
		return true;
	case SOURCE_END:
		ui->ended = true;
		ui->running = false;
		say(ui, "%s", ui->replay ? "end of the replay" : "end of the run");
		return false;
	case SOURCE_STOPPED:
		return false;	/* the loop sees the signal */
	case SOURCE_FAILED:
	case SOURCE_ERROR:
		ui->res->blown_up = true;
		ui->res->run_error = r == SOURCE_ERROR;
		ui->running = false;
		say(ui, "%s", ui->res->why);
		return false;
	}
	return false;
}

/* Steps up to the simulated time the pace asks for now, as far as the
 * frame's time allows; a run that cannot keep up goes on from where it
 * is, not racing ahead later. */
static void
run_frame(struct tui *ui, double budget, double period)
{
	double start = clock_seconds(), target = pace_target(&ui->pace, start), t;
	struct source_state s;

	ui->src->state(ui->src->ctx, &s);
	while (ui->running && s.t < target) {
		if (!step_once(ui))
			break;
		ui->src->state(ui->src->ctx, &s);
		if (clock_seconds() - start > budget || quit_signal)
			break;
	}
	t = clock_seconds();
	pace_keep_up(&ui->pace, t, s.t, period);
	if (t - ui->mark_wall >= 0.5) {
		ui->speed = (s.t - ui->mark_t) / (t - ui->mark_wall);
		ui->mark_wall = t;
		ui->mark_t = s.t;
	}
}

/* `e`: steps until the selected node has a new event. */
static void
seek_event(struct tui *ui)
{
	long before = selected_events(ui);
	double start = clock_seconds();
	long steps = 0;
	const char *unit = ui->replay ? "frames" : "steps";	/* a replay steps by frames */
	struct source_state s;

	if (ui->selected < 0 || ui->selected >= ui->log.n)
		return;
	ui->running = false;
	while (selected_events(ui) == before && !quit_signal &&
	    clock_seconds() - start < EVENT_SEEK_WALL && step_once(ui))
		steps++;
	ui->src->state(ui->src->ctx, &s);
	if (selected_events(ui) > before)
		say(ui, "node %d: an event at step %ld (%ld %s on)", ui->selected,
		    step_shown(evlog_get(&ui->log, ui->selected, 0)->step), steps, unit);
	else if (!ui->ended && !ui->res->blown_up)
		say(ui, "node %d: no event in %ld %s (to step %ld); e again goes on",
		    ui->selected, steps, unit, s.step);
}

static void
reset_camera(struct tui *ui)
{
	struct source_state s;
	bool persp = ui->cam.perspective;
	vec3 target;
	double radius;

	ui->src->state(ui->src->ctx, &s);
	view_frame(s.sc, s.cl->x0, s.cl->n, &target, &radius);
	camera_preset(&ui->cam, (enum view_preset)ui->preset, target, radius);
	ui->cam.perspective = persp;
}

/* r: starts or stops recording into drape-YYYYMMDD-HHMMSS.drr here. */
static void
toggle_recording(struct tui *ui)
{
	char name[64], why[600];
	const char *now_rec = ui->src->recording(ui->src->ctx, NULL);
	time_t t = time(NULL);
	struct tm tm;
	int k;

	if (now_rec != NULL) {
		snprintf(name, sizeof name, "%s", now_rec);
		if (ui->src->record(ui->src->ctx, NULL, why, sizeof why) != 0)
			say(ui, "recording: %s", why);
		else
			say(ui, "recorded %s", name);
		return;
	}
	if (localtime_r(&t, &tm) == NULL) {
		say(ui, "recording: no local time for its name");
		return;
	}
	for (k = 1; k < 100; k++) {
		char stamp[32];
		FILE *f;

		strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
		if (k == 1)
			snprintf(name, sizeof name, "drape-%s.drr", stamp);
		else
			snprintf(name, sizeof name, "drape-%s-%d.drr", stamp, k);
		if ((f = fopen(name, "rb")) == NULL)
			break;	/* not there: ours */
		fclose(f);
	}
	if (k == 100) {
		say(ui, "recording: 99 drape-*.drr files named for this second exist already");
		return;
	}
	if (ui->src->record(ui->src->ctx, name, why, sizeof why) != 0)
		say(ui, "recording: %s", why);
	else
		say(ui, "recording into %s (r stops)", name);
}

/* c: the next colouring, where there is colour. */
static void
next_colouring(struct tui *ui)
{
	if (!ui->colour) {
		say(ui, "colouring needs a colour terminal: the view shows the shading only");
		return;
	}
	ui->colouring = (enum colouring)((ui->colouring + 1) % COLOUR_COUNT);
	ui->range = 0;
	if (ui->colouring == COLOUR_SHADE)
		say(ui, "colour: by what it is (cloth, solid, floor, contact)");
	else if (ui->colouring == COLOUR_CONTACT)
		say(ui, "colour: contact (orange an obstacle, red the cloth)");
	else
		say(ui, "colour: %s, %s (blue to red; the scale grows with the run)",
		    colouring_title[ui->colouring], colouring_is_signed(ui->colouring) ?
		    "from compressed to stretched" : "from none to the largest");
}

/* u: ASCII, braille, half blocks; Unicode only in a UTF-8 locale. */
static void
next_glyphs(struct tui *ui)
{
	if (!ui->utf8) {
		say(ui, "braille and half blocks need a UTF-8 locale (LANG, LC_ALL): ASCII only");
		return;
	}
	ui->glyphs = ui->glyphs == GLYPHS_ASCII ? GLYPHS_BRAILLE :
	    ui->glyphs == GLYPHS_BRAILLE ? GLYPHS_BLOCKS : GLYPHS_ASCII;
	say(ui, "view: %s", ui->glyphs == GLYPHS_ASCII ? "ASCII" :
	    ui->glyphs == GLYPHS_BRAILLE ? "braille, 2 x 4 dots a cell" : "half blocks");
}

static void
prompt_key(struct tui *ui, int ch)
{
	size_t len = strlen(ui->input);
	struct source_state s;

	if (ch == 27) {
		ui->prompt = false;
		ui->msg[0] = '\0';
	} else if (ch == KEY_BACKSPACE || ch == 127 || ch == 8) {
		if (len > 0)
			ui->input[len - 1] = '\0';
	} else if (ch >= '0' && ch <= '9' && len + 1 < sizeof ui->input) {
		ui->input[len] = (char)ch;
		ui->input[len + 1] = '\0';
	} else if (ch == '\n' || ch == '\r' || ch == KEY_ENTER) {
		long id = strtol(ui->input, NULL, 10);

		ui->src->state(ui->src->ctx, &s);
		ui->prompt = false;
		if (ui->prompt_step) {
			struct source_position p;

			ui->src->position(ui->src->ctx, &p);
			if (len > 0 && id >= p.first && id <= p.last)
				seek(ui, SOURCE_GOTO, id, "out of memory");
			else
				say(ui, "no step '%s': the replay has steps %ld to %ld", ui->input,
				    p.first, p.last);
		} else if (len > 0 && id >= 0 && id < s.cl->n) {
			ui->selected = (int)id;
			ui->msg[0] = '\0';
		} else {
			say(ui, "no node '%s': nodes are 0 to %d", ui->input, s.cl->n - 1);
		}
	}
}

/* ---- keys: one table, read by the dispatch and by the help screen ---- */

enum key_when { KEYS_BOTH, KEYS_LIVE, KEYS_REPLAY };

struct binding {
	enum key_when when;
	int keys[9];		/* the codes, 0-terminated */
	const char *names;	/* as the help shows them; NULL: no line of its own */
	const char *what;
	void (*act)(struct tui *ui, int ch);
};

static void act_quit(struct tui *ui, int ch) { (void)ch; ui->quit = true; }
static void act_help(struct tui *ui, int ch) { (void)ch; ui->help = true; }
static void act_redraw(struct tui *ui, int ch) { (void)ui; (void)ch; clearok(curscr, TRUE); }
static void act_event(struct tui *ui, int ch) { (void)ch; seek_event(ui); }
static void act_record(struct tui *ui, int ch) { (void)ch; toggle_recording(ui); }

static void
act_no_record(struct tui *ui, int ch)
{
	(void)ch;
	say(ui, "a replay does not record (drape run --record does)");
}

static void
act_run(struct tui *ui, int ch)
{
	struct source_state s;

	(void)ch;
	ui->src->state(ui->src->ctx, &s);
	ui->running = !ui->running && !ui->ended && !ui->res->blown_up;
	if (ui->replay && ui->ended)
		say(ui, "end of the replay (Home goes back to the first step)");
	ui->mark_wall = clock_seconds();
	ui->mark_t = s.t;
	pace_anchor(&ui->pace, ui->mark_wall, s.t);
}

static void
act_step(struct tui *ui, int ch)
{
	(void)ch;
	ui->running = false;
	step_once(ui);
}

/* + and - twice or half as fast, * as fast as it can (and back); the
 * measured speed restarts from here. */
static void
act_speed(struct tui *ui, int ch)
{
	struct source_state s;
	char label[16];
	bool moved = true;

	if (ch == '*')
		pace_toggle_flat_out(&ui->pace);
	else
		moved = pace_change(&ui->pace, ch == '-' ? -1 : 1);
	ui->src->state(ui->src->ctx, &s);
	ui->mark_wall = clock_seconds();
	ui->mark_t = s.t;
	ui->speed = 0;
	pace_anchor(&ui->pace, ui->mark_wall, s.t);
	pace_label(&ui->pace, label, sizeof label);
	if (ui->pace.flat_out)
		say(ui, "as fast as it can (* again: %s)", label);
	else if (!moved)
		say(ui, "%s real time is the %s", label, ch == '-' ? "slowest" : "fastest");
	else
		say(ui, "%s real time%s", label, ui->pace.log2 == 0 ? " (the default)" : "");
}

static void
act_rotate(struct tui *ui, int ch)
{
	if (ch == KEY_LEFT || ch == 'h')
		ui->cam.yaw -= ROTATE_STEP;
	else if (ch == KEY_RIGHT || ch == 'l')
		ui->cam.yaw += ROTATE_STEP;
	else if (ch == KEY_UP || ch == 'k')
		ui->cam.pitch = fmin(ui->cam.pitch + ROTATE_STEP, V3_PI / 2);
	else
		ui->cam.pitch = fmax(ui->cam.pitch - ROTATE_STEP, -V3_PI / 2);
}

static void
act_pan(struct tui *ui, int ch)
{
	double d = PAN_STEP * ui->cam.radius / ui->cam.zoom;

	if (ch == 'H')
		ui->cam.pan_x += d;
	else if (ch == 'L')
		ui->cam.pan_x -= d;
	else if (ch == 'K')
		ui->cam.pan_y -= d;
	else
		ui->cam.pan_y += d;
}

static void
act_zoom(struct tui *ui, int ch)
{
	if (ch == 'z')
		ui->cam.zoom *= ZOOM_STEP;
	else
		ui->cam.zoom /= ZOOM_STEP;
}

static void
act_view(struct tui *ui, int ch)
{
	(void)ch;
	ui->preset = (ui->preset + 1) % VIEW_NPRESETS;
	reset_camera(ui);
	say(ui, "view: %s", view_preset_name[ui->preset]);
}

/* The cloth as it is now, framed: its box's sphere, the view's direction,
 * zoom and pan kept. */
static void
frame_cloth(struct tui *ui, const struct source_state *s)
{
	vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);

	view_cloth_box(s->x, s->cl->n, &lo, &hi);
	view_frame_cloth(s->sc, s->cl->x0, s->cl->n, lo, hi, &ui->cam.target, &ui->cam.radius);
}

/* f: the view follows the cloth (at the strip's end its pile was a speck
 * in the scene's framing), or frames the whole scene again. */
static void
act_follow(struct tui *ui, int ch)
{
	(void)ch;
	ui->follow = !ui->follow;
	if (!ui->follow)
		reset_camera(ui);
	say(ui, "%s", ui->follow ? "view: following the cloth (f again: the whole scene)" :
	    "view: the whole scene");
}

static void
act_perspective(struct tui *ui, int ch)
{
	(void)ch;
	ui->cam.perspective = !ui->cam.perspective;
	say(ui, "%s", ui->cam.perspective ? "perspective" : "orthographic");
}

static void
act_look(struct tui *ui, int ch)
{
	if (ch == 'c')
		next_colouring(ui);
	else
		next_glyphs(ui);
}

static void
act_panel(struct tui *ui, int ch)
{
	(void)ch;
	ui->focus = (enum panel)((ui->focus + 1) % PANEL_COUNT);
}

static void
act_node(struct tui *ui, int ch)
{
	struct source_state s;
	int n;

	ui->src->state(ui->src->ctx, &s);
	n = s.cl->n;
	ui->selected = ch == '[' ? (ui->selected + n - 1) % n : (ui->selected + 1) % n;
}

static void
act_prompt(struct tui *ui, int ch)
{
	ui->prompt = true;
	ui->prompt_step = ch == 'g';	/* a step (replays), else a node */
	ui->input[0] = '\0';
}

static void
act_frame(struct tui *ui, int ch)
{
	if (ch == KEY_LEFT)
		seek(ui, SOURCE_FRAME_PREV, 0, "at the first frame");
	else
		seek(ui, SOURCE_FRAME_NEXT, 0, "end of the replay");
}

static void
act_keyframe(struct tui *ui, int ch)
{
	if (ch == KEY_NPAGE)
		seek(ui, SOURCE_KEY_NEXT, 0, "no keyframe after this step");
	else
		seek(ui, SOURCE_KEY_PREV, 0, "no keyframe before this step");
}

static void
act_ends(struct tui *ui, int ch)
{
	if (ch == KEY_HOME)
		seek(ui, SOURCE_FIRST, 0, "at the first step");
	else
		seek(ui, SOURCE_LAST, 0, "at the last step");
}

/* The first binding of the source's kind that holds a key wins, so a
 * replay's arrows move in time before they rotate. */
static const struct binding bindings[] = {
	{ KEYS_LIVE, { ' ' }, "space", "run / pause", act_run },
	{ KEYS_REPLAY, { ' ' }, "space", "play / pause", act_run },
	{ KEYS_LIVE, { 'n', '.' }, "n or .", "one step (pauses)", act_step },
	{ KEYS_REPLAY, { 'n', '.', KEY_RIGHT, KEY_LEFT }, "n . or Right",
	    "next frame; Left previous frame", act_frame },
	{ KEYS_REPLAY, { KEY_NPAGE, KEY_PPAGE }, "PgDn / PgUp",
	    "next / previous keyframe; Home / End first / last step", act_keyframe },
	{ KEYS_REPLAY, { KEY_HOME, KEY_END }, NULL, NULL, act_ends },
	{ KEYS_REPLAY, { 'g' }, "g", "go to a step (Enter, Esc cancels)", act_prompt },
	{ KEYS_BOTH, { '+', '=', '-', '*' }, "+ / -  *", "twice / half as fast (1x real time), "
	    "as fast as it can", act_speed },
	{ KEYS_LIVE, { KEY_LEFT, KEY_RIGHT, KEY_UP, KEY_DOWN, 'h', 'j', 'k', 'l' },
	    "arrows, h j k l", "rotate (yaw, pitch); H J K L pan", act_rotate },
	{ KEYS_REPLAY, { KEY_UP, KEY_DOWN, 'h', 'j', 'k', 'l' }, "h j k l, Up Down",
	    "rotate (yaw, pitch); H J K L pan", act_rotate },
	{ KEYS_BOTH, { 'H', 'J', 'K', 'L' }, NULL, NULL, act_pan },
	{ KEYS_BOTH, { 'z', 'Z' }, "z / Z", "zoom in / out", act_zoom },
	{ KEYS_BOTH, { 'v' }, "v", "next view: front, side, top, iso", act_view },
	{ KEYS_BOTH, { 'f' }, "f", "follow the cloth, framed as it goes; again: the whole scene",
	    act_follow },
	{ KEYS_BOTH, { 'o' }, "o", "orthographic / perspective", act_perspective },
	{ KEYS_BOTH, { 'c', 'u' }, "c  u", "next colouring (strain, contact) / glyphs (braille, blocks)",
	    act_look },
	{ KEYS_BOTH, { '\t' }, "Tab", "next panel", act_panel },
	{ KEYS_BOTH, { '[', ']' }, "[ / ]  /", "previous / next node; go to a node id (Enter, "
	    "Esc cancels)", act_node },
	{ KEYS_BOTH, { '/' }, NULL, NULL, act_prompt },
	{ KEYS_LIVE, { 'e' }, "e", "run to the selected node's next event", act_event },
	{ KEYS_REPLAY, { 'e' }, "e", "play to the selected node's next event", act_event },
	{ KEYS_LIVE, { 'r' }, "r", "start / stop recording (drape-DATE-TIME.drr here)",
	    act_record },
	{ KEYS_REPLAY, { 'r' }, NULL, NULL, act_no_record },
	{ KEYS_BOTH, { 12 }, NULL, NULL, act_redraw },
	{ KEYS_BOTH, { '?', KEY_F(1) }, "? or F1", "this help (Ctrl-L redraws the screen)",
	    act_help },
	{ KEYS_BOTH, { 'q' }, "q", "quit", act_quit },
};

/* The keys that move in a replay, whose seeks wait for flush_seek. */
static bool
moves(void (*act)(struct tui *, int))
{
	return act == act_frame || act == act_keyframe || act == act_ends;
}

static bool
applies(const struct binding *b, bool replay)
{
	return b->when == KEYS_BOTH || b->when == (replay ? KEYS_REPLAY : KEYS_LIVE);
}

void
tui_help(struct text *t, bool replay)
{
	struct screen_key keys[sizeof bindings / sizeof bindings[0]];
	size_t i, n = 0;

	for (i = 0; i < sizeof bindings / sizeof bindings[0]; i++)
		if (applies(&bindings[i], replay) && bindings[i].names != NULL)
			keys[n++] = (struct screen_key){ bindings[i].names, bindings[i].what };
	screen_help(t, replay, keys, n);
}

static void
key(struct tui *ui, int ch)
{
	size_t i;
	int k;

	if (ui->prompt) {
		prompt_key(ui, ch);
		return;
	}
	if (ui->help) {
		ui->help = false;
		return;
	}
	ui->msg[0] = '\0';	/* a message lasts until the next key */
	for (i = 0; i < sizeof bindings / sizeof bindings[0]; i++) {
		if (!applies(&bindings[i], ui->replay))
			continue;
		for (k = 0; bindings[i].keys[k] != 0; k++)
			if (bindings[i].keys[k] == ch) {
				/* a key that is no move sees the place the moves
				 * before it lead to */
				if (!moves(bindings[i].act))
					flush_seek(ui);
				bindings[i].act(ui, ch);
				return;
			}
	}
}

static chtype
cell_attr(const struct tui *ui, int kind)
{
	static const short pair[] = { 0, PAIR_CLOTH, PAIR_SOLID, PAIR_FLOOR, PAIR_CONTACT,
		PAIR_SELECTED };
	chtype a = kind == CELL_SELECTED || kind == CELL_CONTACT ? A_BOLD : A_NORMAL;

	if (ui->colour && kind > CELL_EMPTY && kind <= CELL_SELECTED)
		a |= COLOR_PAIR(pair[kind]);
	return a;
}

/* Text lines into a rectangle, the first bold (reversed when focused). */
static void
draw_text(const struct text *t, struct rect at, bool focused)
{
	int k;

	for (k = 0; k < t->n && k < at.h; k++) {
		chtype a = k == 0 ? (focused ? A_REVERSE : A_BOLD) : A_NORMAL;

		attrset(a);
		mvaddnstr(at.y + k, at.x, t->line[k], at.w);
	}
	attrset(A_NORMAL);
}

/* The pair of a palette colour near c. */
static chtype
palette_attr(struct tui *ui, struct rgb c)
{
	static const unsigned char basic[8][3] = {
		{ 0, 0, 0 }, { 205, 0, 0 }, { 0, 205, 0 }, { 205, 205, 0 },
		{ 0, 0, 238 }, { 205, 0, 205 }, { 0, 205, 205 }, { 229, 229, 229 },
	};
	int k, best = 7;

	if (ui->palette256) {
		k = 36 * ((c.r * 5 + 127) / 255) + 6 * ((c.g * 5 + 127) / 255) +
		    (c.b * 5 + 127) / 255;
		if (!ui->pair_made[k] && init_pair((short)(PAIR_PALETTE + k), (short)(16 + k), -1) == OK)
			ui->pair_made[k] = 1;
		return ui->pair_made[k] ? COLOR_PAIR(PAIR_PALETTE + k) : A_NORMAL;
	}
	for (k = 1, best = 7; k < 8; k++) {	/* not black: the background may be */
		long d = 0, e = 0;
		int j;

		for (j = 0; j < 3; j++) {
			int q = j == 0 ? c.r : j == 1 ? c.g : c.b;

			d += (long)(q - basic[k][j]) * (q - basic[k][j]);
			e += (long)(q - basic[best][j]) * (q - basic[best][j]);
		}
		if (d < e)
			best = k;
	}
	if (!ui->pair_made[best] && init_pair((short)(PAIR_PALETTE + best), (short)best, -1) == OK)
		ui->pair_made[best] = 1;
	return ui->pair_made[best] ? COLOR_PAIR(PAIR_PALETTE + best) : A_NORMAL;
}

/* The colouring's field for this state, and its scale; false for the
 * plain colours by kind. */
static bool
colour_field(struct tui *ui, const struct source_state *s, const struct contact_event *ev,
    size_t nev)
{
	double m = 0;
	int p;

	if (!ui->colour || ui->colouring == COLOUR_SHADE || ui->field == NULL ||
	    colouring_field(ui->colouring, s->cl, s->x, ev, nev, ui->field) != 0)
		return false;
	for (p = 0; p < s->cl->n; p++)
		m = fmax(m, fabs(ui->field[p]));
	ui->range = fmax(ui->range, colouring_range(ui->colouring, m));
	return true;
}

/* The colouring's legend on the view's last row, at its right: the scale
 * with its numbers (it grows with the run, so the colours alone cannot be
 * read), or what contact's two colours mean. Each swatch is a reversed
 * blank in its colour. Left out where the view is too narrow for it. */
static void
draw_legend(struct tui *ui, const struct layout *lo)
{
	enum colouring c = ui->colouring;
	char lo_s[32], hi_s[32];
	int bar = 10, y = lo->view.y + lo->view.h - 1, x, k, len;

	if (c == COLOUR_CONTACT) {
		static const char *const name[2] = { " obstacle ", " cloth" };
		static const int touch[2] = { TOUCH_OBSTACLE, TOUCH_CLOTH };

		len = (int)strlen(" contact: ") + 2 + (int)strlen(name[0]) + 1 + 2 +
		    (int)strlen(name[1]) + 1;
		if (len > lo->view.w)
			return;
		x = lo->view.x + lo->view.w - len;
		attrset(A_NORMAL);
		mvaddstr(y, x, " contact: ");
		for (k = 0; k < 2; k++) {
			float f[3];

			colouring_colour(c, touch[k], 1, f);
			attrset(palette_attr(ui, render_rgb(f)) | A_REVERSE);
			addstr("  ");
			attrset(A_NORMAL);
			addstr(name[k]);
		}
		addch(' ');
		return;
	}
	colouring_label(c, colouring_is_signed(c) ? -ui->range : 0, lo_s, sizeof lo_s);
	colouring_label(c, ui->range, hi_s, sizeof hi_s);
	len = 1 + (int)strlen(colouring_title[c]) + 1 + (int)strlen(lo_s) + 1 + bar + 1 +
	    (int)strlen(hi_s) + 1;
	if (len > lo->view.w)
		return;
	x = lo->view.x + lo->view.w - len;
	attrset(A_NORMAL);
	mvprintw(y, x, " %s %s ", colouring_title[c], lo_s);
	for (k = 0; k < bar; k++) {
		double lo_v = colouring_is_signed(c) ? -1 : 0;
		float f[3];

		colouring_colour(c, ui->range * (lo_v + (1 - lo_v) * (k + 0.5) / bar), ui->range, f);
		attrset(palette_attr(ui, render_rgb(f)) | A_REVERSE);
		addch(' ');
	}
	attrset(A_NORMAL);
	printw(" %s ", hi_s);
}

static int
draw_view(struct tui *ui, const struct layout *lo, const struct source_state *s)
{
	size_t nev;
	const struct contact_event *ev = ui->src->events(ui->src->ctx, &nev);
	struct paint_opts po = { ui->colouring, 1, 0, true };
	bool coloured;
	int i, j;

	if (s->step == 0) {
		ev = NULL;
		nev = 0;
	}
	coloured = colour_field(ui, s, ev, nev);
	po.range = ui->range > 0 ? ui->range : 1;
	if (ui->glyphs != GLYPHS_ASCII) {
		if ((ui->g.w != lo->view.w || ui->g.h != lo->view.h || ui->g.mode != ui->glyphs) &&
		    glyphs_resize(&ui->g, ui->glyphs, lo->view.w, lo->view.h) != 0)
			return -1;
		if (!coloured)
			po.colouring = COLOUR_SHADE;
		if (glyphs_draw(&ui->g, &ui->cam, s->sc, s->cl, s->x, coloured ? ui->field : NULL,
		    &po, ev, nev, ui->selected) != 0)
			return -1;
		for (j = 0; j < ui->g.h; j++) {
			move(lo->view.y + j, lo->view.x);
			for (i = 0; i < ui->g.w; i++) {
				size_t at = (size_t)j * (size_t)ui->g.w + (size_t)i;
				char u[4];

				glyphs_utf8(ui->g.cp[at], u);
				attrset(coloured && ui->g.kind[at] == CELL_CLOTH ?
				    palette_attr(ui, ui->g.colour[at]) : cell_attr(ui, ui->g.kind[at]));
				addstr(u);
			}
		}
		attrset(A_NORMAL);
		if (coloured)
			draw_legend(ui, lo);
		return 0;
	}
	if ((ui->r.w != lo->view.w || ui->r.h != lo->view.h) &&
	    raster_resize(&ui->r, lo->view.w, lo->view.h) != 0)
		return -1;
	view_draw(&ui->r, &ui->cam, s->sc, s->x, s->cl->n, s->cl->tri, s->cl->ntri, ev, nev,
	    ui->selected);
	if (coloured) {
		/* the colours of the same view, a pixel a cell */
		if ((ui->cells.w != lo->view.w || ui->cells.h != lo->view.h) &&
		    render_resize(&ui->cells, lo->view.w, lo->view.h, RASTER_ASPECT) != 0)
			return -1;
		if (paint_scene(&ui->cells, &ui->cam, s->sc, s->cl, s->x, ui->field, &po) != 0)
			return -1;
	}
	for (j = 0; j < ui->r.h; j++) {
		move(lo->view.y + j, lo->view.x);
		for (i = 0; i < ui->r.w; i++) {
			size_t at = (size_t)j * (size_t)ui->r.w + (size_t)i;
			chtype a = coloured && ui->r.kind[at] == CELL_CLOTH &&
			    ui->cells.kind[at] == CELL_CLOTH ?
			    palette_attr(ui, render_at(&ui->cells, i, j)) : cell_attr(ui, ui->r.kind[at]);

			addch((chtype)(unsigned char)ui->r.ch[at] | a);
		}
	}
	if (coloured)
		draw_legend(ui, lo);
	return 0;
}

static void
draw_panel(struct tui *ui, enum panel p, struct rect at, const struct source_state *s)
{
	struct text t;
	struct source_stats ss;
	vec3 f;

	text_init(&t, at.w);
	ui->src->stats(ui->src->ctx, &ss);
	switch (p) {
	case PANEL_COLLISIONS:
		screen_collisions(&t, &ss);
		break;
	case PANEL_HASH:
		screen_hash(&t, &ss);
		break;
	case PANEL_NODE:
		log_now(ui);
		screen_node(&t, s, ui->selected, ui->src->force(ui->src->ctx, ui->selected, &f) ?
		    &f : NULL, &ui->log);
		break;
	case PANEL_COUNT:
		break;
	}
	draw_text(&t, at, false);
}

/* The key line, most needed first, as much as the width holds. */
static void
key_line(const struct tui *ui, char *line, int width, const char *rec)
{
	static const char *const live[] = { "? help", "q quit", "space run/pause",
		"+/- speed", "* max", "n step", "f follow", "arrows rotate", "z/Z zoom",
		"v view", "Tab panel", "[/] node" };
	static const char *const replay[] = { "? help", "q quit", "space play",
		"+/- speed", "Left/Right frame", "PgUp/PgDn keyframe", "g step", "f follow",
		"Home/End", "Tab panel", "/ node" };
	const char *items[16];
	char recording[TEXT_WIDTH];
	size_t n = 0, i;

	_Static_assert(1 + sizeof live / sizeof live[0] <= sizeof items / sizeof items[0] &&
	    sizeof replay / sizeof replay[0] <= sizeof items / sizeof items[0], "items holds them");
	if (rec != NULL) {
		snprintf(recording, sizeof recording, "recording into %s (r stops)", rec);
		items[n++] = recording;
	}
	if (ui->replay)
		for (i = 0; i < sizeof replay / sizeof replay[0]; i++)
			items[n++] = replay[i];
	else
		for (i = 0; i < sizeof live / sizeof live[0]; i++)
			items[n++] = live[i];
	screen_keys(line, width, items, n);
}

static int
draw(struct tui *ui)
{
	struct layout lo;
	struct source_state s;
	struct status_info si;
	struct source_position pos;
	const char *rec;
	char line[TEXT_WIDTH * 2], pace[16];
	int rows, cols, k;

	getmaxyx(stdscr, rows, cols);
	werase(stdscr);
	screen_layout(&lo, cols, rows, ui->focus);
	ui->src->state(ui->src->ctx, &s);
	if (lo.too_small) {
		mvprintw(0, 0, "terminal too small: %dx%d, drape needs %dx%d", cols, rows,
		    SCREEN_MIN_COLS, SCREEN_MIN_ROWS);
	} else if (ui->help) {
		struct text t;

		text_init(&t, cols - 2);
		tui_help(&t, ui->replay);
		draw_text(&t, (struct rect){ 2, 1, cols - 2, rows - 1 }, false);
	} else {
		if (ui->follow)
			frame_cloth(ui, &s);
		si.s = &s;
		si.speed = ui->speed;	/* the latest measured, kept while paused */
		if (ui->replay) {
			ui->src->position(ui->src->ctx, &pos);
			si.mode = ui->ended ? "replay end" : ui->running ? "replay playing" : "replay";
			si.recording = "no";
			si.pos = &pos;
		} else {
			rec = ui->src->recording(ui->src->ctx, NULL);
			/* a run that cannot go on (out of memory) did not blow up */
			si.mode = ui->res->run_error ? "error" : ui->res->blown_up ? "blown up" :
			    ui->ended ? "end" : ui->running ? "running" : "paused";
			si.recording = rec != NULL ? rec : "no";
			si.pos = NULL;
		}
		pace_label(&ui->pace, pace, sizeof pace);
		si.pace = pace;
		screen_status(line, cols < (int)sizeof line - 1 ? cols : (int)sizeof line - 1, &si);
		attrset(A_REVERSE);
		mvhline(0, 0, ' ', cols);
		mvaddnstr(0, 0, line, cols);
		attrset(A_NORMAL);
		if (draw_view(ui, &lo, &s) != 0)
			return -1;
		mvvline(lo.view.y, lo.view.x + lo.view.w, '|', lo.view.h);
		if (!lo.stacked) {
			move(lo.tabs_y, lo.side.x);
			for (k = 0; k < PANEL_COUNT; k++) {
				attrset(k == (int)ui->focus ? A_REVERSE : A_NORMAL);
				printw("%s", panel_name[k]);
				attrset(A_NORMAL);
				addch(k + 1 < PANEL_COUNT ? ' ' : ' ');
			}
			attrset(A_DIM);
			printw("(Tab)");
			attrset(A_NORMAL);
		}
		for (k = 0; k < PANEL_COUNT; k++)
			if (lo.panel[k].h > 0)
				draw_panel(ui, (enum panel)k, lo.panel[k], &s);
		rec = ui->replay ? NULL : ui->src->recording(ui->src->ctx, NULL);
		if (ui->prompt)
			snprintf(line, sizeof line, "go to %s: %s_", ui->prompt_step ? "step" : "node",
			    ui->input);
		else if (ui->msg[0] != '\0')
			snprintf(line, sizeof line, "%s", ui->msg);
		else
			key_line(ui, line, cols < (int)sizeof line ? cols : (int)sizeof line - 1, rec);
		mvaddnstr(lo.keys.y, 0, line, cols);
	}
	wnoutrefresh(stdscr);
	doupdate();
	return 0;
}

static void
colours(struct tui *ui)
{
	const char *no = getenv("NO_COLOR");

	ui->colour = ui->opt.color && (no == NULL || no[0] == '\0') && has_colors();
	if (!ui->colour || start_color() == ERR) {
		ui->colour = false;
		return;
	}
	use_default_colors();
	init_pair(PAIR_CLOTH, COLOR_CYAN, -1);
	init_pair(PAIR_SOLID, COLOR_YELLOW, -1);
	init_pair(PAIR_FLOOR, COLOR_BLUE, -1);
	init_pair(PAIR_CONTACT, COLOR_RED, -1);
	init_pair(PAIR_SELECTED, COLOR_MAGENTA, -1);
	ui->palette256 = COLORS >= 256 && COLOR_PAIRS >= PAIR_PALETTE + PALETTE_SIZE;
}

/* The terminal went away without a SIGHUP reaching us (a parent that
 * ignores it, tmux kill-session): poll says so, and read gives 0 at once,
 * forever; getch's ERR then came back without its wait, a loop at 100 %
 * CPU. */
static bool
terminal_gone(void)
{
	struct pollfd p = { .fd = STDIN_FILENO, .events = POLLIN };

	return poll(&p, 1, 0) > 0 && (p.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0;
}

static void
loop(struct tui *ui)
{
	double period = 0.1 * ui->opt.delay, next = clock_seconds();
	int ch;

	while (!ui->quit && !quit_signal) {
		double t = clock_seconds();

		if (ui->running && t >= next) {
			run_frame(ui, BUSY_FRACTION * period, period);
			next = t + period;
			ui->dirty = true;
		}
		if (!ui->replay) {
			const char *error;

			ui->src->recording(ui->src->ctx, &error);
			if (error != NULL)
				say(ui, "%s", error);
		}
		if (ui->dirty) {
			if (draw(ui) != 0) {
				ui->res->end = TUI_ERROR;
				snprintf(ui->res->why, sizeof ui->res->why, "out of memory for the view");
				return;
			}
			ui->dirty = false;
		}
		t = clock_seconds();
		timeout(ui->running ? (int)fmax(0, ceil(1000 * (next - t))) : 250);
		if ((ch = getch()) == ERR) {
			if (terminal_gone())
				quit_signal = SIGHUP;	/* ends as a hangup would */
			continue;
		}
		/* every key already typed, one seek to where they lead, then
		 * one redraw */
		do {
			if (ch != KEY_RESIZE)
				key(ui, ch);
			timeout(0);
		} while (!ui->quit && (ch = getch()) != ERR);
		flush_seek(ui);
		ui->dirty = true;
	}
}

void
tui_run(struct source *src, const struct tui_opts *opt, struct tui_result *res)
{
	static const int sigs[] = { SIGINT, SIGTERM, SIGHUP };
	struct sigaction sa, old[3];
	struct source_state s;
	struct tui ui;
	SCREEN *scr;
	size_t k;

	memset(res, 0, sizeof *res);
	memset(&ui, 0, sizeof ui);
	ui.src = src;
	ui.opt = *opt;
	ui.res = res;
	ui.replay = src->seek != NULL;
	ui.running = !opt->paused;
	ui.preset = VIEW_ISO;
	raster_init(&ui.r);
	glyphs_init(&ui.g);
	render_init(&ui.cells);
	/* the locale's character set, for ncurses too (LC_CTYPE only: numbers
	 * stay as C prints them) */
	ui.utf8 = glyphs_locale_utf8();
	ui.glyphs = glyphs_resolve(opt->glyphs, ui.utf8);
	if (!ui.utf8 && ui.glyphs != GLYPHS_ASCII) {
		ui.glyphs = GLYPHS_ASCII;
		say(&ui, "braille and half blocks need a UTF-8 locale (LANG, LC_ALL): ASCII");
	}
	src->state(src->ctx, &s);
	ui.field = malloc((s.cl->n > 0 ? (size_t)s.cl->n : 1) * sizeof *ui.field);
	ui.selected = cloth_node(s.cl, s.cl->nu / 2, s.cl->nv / 2);
	if (ui.selected < 0)
		ui.selected = s.cl->n / 2;
	if (evlog_init(&ui.log, s.cl->n) != 0) {
		res->end = TUI_ERROR;
		snprintf(res->why, sizeof res->why, "out of memory for the event log");
		free(ui.field);
		return;
	}
	reset_camera(&ui);
	ui.mark_wall = clock_seconds();
	ui.mark_t = s.t;
	pace_init(&ui.pace, ui.mark_wall, s.t);	/* real time: what it looks like */

	/* ours before ncurses', which then leaves them alone */
	quit_signal = 0;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	for (k = 0; k < 3; k++)
		sigaction(sigs[k], &sa, &old[k]);
	if ((scr = newterm(NULL, stdout, stdin)) == NULL) {
		res->end = TUI_ERROR;
		snprintf(res->why, sizeof res->why, "cannot use the terminal (TERM=%s)",
		    getenv("TERM") != NULL ? getenv("TERM") : "");
	} else {
		cbreak();
		noecho();
		nonl();
		keypad(stdscr, TRUE);
		curs_set(0);
		set_escdelay(25);
		colours(&ui);
		ui.dirty = true;
		loop(&ui);
		endwin();
		delscreen(scr);
		if (quit_signal && res->end != TUI_ERROR) {
			res->end = TUI_SIGNAL;
			res->signo = quit_signal;
		}
	}
	for (k = 0; k < 3; k++)
		sigaction(sigs[k], &old[k], NULL);
	raster_free(&ui.r);
	glyphs_free(&ui.g);
	render_free(&ui.cells);
	free(ui.field);
	evlog_free(&ui.log);
}

int
tui_parse_delay(const char *s, int *delay)
{
	char *end;
	long d;

	if (!isdigit((unsigned char)s[0]))	/* strtol would skip blanks, take a sign */
		return -1;
	errno = 0;
	d = strtol(s, &end, 10);
	if (errno != 0 || *end != '\0' || d < 1 || d > TUI_DELAY_MAX)
		return -1;
	*delay = (int)d;
	return 0;
}

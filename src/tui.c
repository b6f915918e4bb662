/* tui.c: the ncurses front end: one werase and one doupdate per frame,
 * redraws capped by the delay, ASCII only, colour optional. On a replay
 * (a source that seeks) the arrows, PgUp/PgDn, Home/End and g move in it;
 * on a live run r records. */
#include <curses.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "clock.h"
#include "evlog.h"
#include "raster.h"
#include "screen.h"
#include "tui.h"
#include "view.h"

#define STEPS_PER_FRAME_MAX (1L << 16)
#define ROTATE_STEP (15 * V3_PI / 180)
#define ZOOM_STEP 1.25
#define PAN_STEP 0.1		/* of the framed radius */
#define EVENT_SEEK_WALL 3.0	/* s: how long `e` may run looking for an event */
#define BUSY_FRACTION 0.8	/* of a frame spent stepping */

/* The one piece of global state: the signal that asks the TUI to end,
 * set by the handler, read by the loop. */
static volatile sig_atomic_t quit_signal;

static void
on_signal(int signo)
{
	quit_signal = signo;
}

enum colour_pair { PAIR_CLOTH = 1, PAIR_SOLID, PAIR_FLOOR, PAIR_CONTACT, PAIR_SELECTED };

struct tui {
	struct source *src;
	struct tui_opts opt;
	bool colour;
	struct camera cam;
	int preset;
	struct raster r;
	struct evlog log;
	int selected;
	enum panel focus;
	bool running, ended, help, quit, dirty;
	long spf;		/* steps per frame, at most */
	double speed;		/* simulated over wall time */
	double mark_wall, mark_t;
	bool replay;		/* the source seeks */
	bool prompt;
	bool prompt_step;	/* the prompt asks for a step, else a node */
	char input[16];
	char msg[300];
	struct tui_result *res;
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

/* A replay moved: the inspector's events are those before it. */
static void
rebuild_log(struct tui *ui)
{
	evlog_clear(&ui->log);
	ui->src->history(ui->src->ctx, &ui->log);
	ui->ended = ui->src->done(ui->src->ctx);
}

static void
seek(struct tui *ui, enum source_seek how, long step, const char *none)
{
	ui->running = false;
	if (!ui->src->seek(ui->src->ctx, how, step)) {
		say(ui, "%s", none);
		return;
	}
	rebuild_log(ui);
}

/* One step; false when there is none (the end, or a blow-up). */
static bool
step_once(struct tui *ui)
{
	size_t nev;
	const struct contact_event *ev;

	if (ui->ended || ui->res->blown_up) {
		say(ui, "%s", ui->ended ? (ui->replay ? "end of the replay" : "end of the run") :
		    ui->res->why);
		return false;
	}
	switch (ui->src->step(ui->src->ctx, ui->res->why, sizeof ui->res->why)) {
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
	case SOURCE_FAILED:
		ui->res->blown_up = true;
		ui->running = false;
		say(ui, "%s", ui->res->why);
		return false;
	}
	return false;
}

/* As many steps as spf and the frame's time allow. */
static void
run_frame(struct tui *ui, double budget)
{
	double start = clock_seconds(), t;
	long k;
	struct source_state s;

	for (k = 0; k < ui->spf && ui->running; k++) {
		if (!step_once(ui))
			break;
		if (clock_seconds() - start > budget || quit_signal)
			break;
	}
	t = clock_seconds();
	ui->src->state(ui->src->ctx, &s);
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
	long before = ui->selected >= 0 && ui->selected < ui->log.n ? ui->log.count[ui->selected] : 0;
	double start = clock_seconds();
	long steps = 0;
	const char *unit = ui->replay ? "frames" : "steps";	/* a replay steps by frames */
	struct source_state s;

	if (ui->selected < 0 || ui->selected >= ui->log.n)
		return;
	ui->running = false;
	while (ui->log.count[ui->selected] == before && !quit_signal &&
	    clock_seconds() - start < EVENT_SEEK_WALL && step_once(ui))
		steps++;
	ui->src->state(ui->src->ctx, &s);
	if (ui->log.count[ui->selected] > before)
		say(ui, "node %d: an event at step %ld (%ld %s on)", ui->selected,
		    evlog_get(&ui->log, ui->selected, 0)->step, steps, unit);
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

static void
key(struct tui *ui, int ch)
{
	struct source_state s;

	if (ui->prompt) {
		prompt_key(ui, ch);
		return;
	}
	if (ui->help) {
		ui->help = false;
		return;
	}
	ui->msg[0] = '\0';	/* a message lasts until the next key */
	ui->src->state(ui->src->ctx, &s);
	if (ui->replay) {
		switch (ch) {
		case KEY_RIGHT:
			ch = 'n';	/* as n: one frame, or the end */
			break;
		case KEY_LEFT:
			seek(ui, SOURCE_FRAME_PREV, 0, "at the first frame");
			return;
		case KEY_NPAGE:
			seek(ui, SOURCE_KEY_NEXT, 0, "no keyframe after this step");
			return;
		case KEY_PPAGE:
			seek(ui, SOURCE_KEY_PREV, 0, "no keyframe before this step");
			return;
		case KEY_HOME:
			seek(ui, SOURCE_FIRST, 0, "at the first step");
			return;
		case KEY_END:
			seek(ui, SOURCE_LAST, 0, "at the last step");
			return;
		case 'g':
			ui->prompt = true;
			ui->prompt_step = true;
			ui->input[0] = '\0';
			return;
		case 'r':
			say(ui, "a replay does not record (drape run --record does)");
			return;
		default:
			break;
		}
	}
	switch (ch) {
	case 'q':
		ui->quit = true;
		break;
	case ' ':
		ui->running = !ui->running && !ui->ended && !ui->res->blown_up;
		if (ui->replay && ui->ended)
			say(ui, "end of the replay (Home goes back to the first step)");
		ui->mark_wall = clock_seconds();
		ui->mark_t = s.t;
		break;
	case 'n':
	case '.':
		ui->running = false;
		step_once(ui);
		break;
	case '+':
	case '=':
		if (ui->spf < STEPS_PER_FRAME_MAX)
			ui->spf *= 2;
		say(ui, "at most %ld %s a frame", ui->spf, ui->replay ? "replay frames" : "steps");
		break;
	case '-':
		if (ui->spf > 1)
			ui->spf /= 2;
		say(ui, "at most %ld %s a frame", ui->spf, ui->replay ? "replay frames" : "steps");
		break;
	case KEY_LEFT:
	case 'h':
		ui->cam.yaw -= ROTATE_STEP;
		break;
	case KEY_RIGHT:
	case 'l':
		ui->cam.yaw += ROTATE_STEP;
		break;
	case KEY_UP:
	case 'k':
		ui->cam.pitch = fmin(ui->cam.pitch + ROTATE_STEP, V3_PI / 2);
		break;
	case KEY_DOWN:
	case 'j':
		ui->cam.pitch = fmax(ui->cam.pitch - ROTATE_STEP, -V3_PI / 2);
		break;
	case 'H':
		ui->cam.pan_x += PAN_STEP * ui->cam.radius / ui->cam.zoom;
		break;
	case 'L':
		ui->cam.pan_x -= PAN_STEP * ui->cam.radius / ui->cam.zoom;
		break;
	case 'K':
		ui->cam.pan_y -= PAN_STEP * ui->cam.radius / ui->cam.zoom;
		break;
	case 'J':
		ui->cam.pan_y += PAN_STEP * ui->cam.radius / ui->cam.zoom;
		break;
	case 'z':
		ui->cam.zoom *= ZOOM_STEP;
		break;
	case 'Z':
		ui->cam.zoom /= ZOOM_STEP;
		break;
	case 'v':
		ui->preset = (ui->preset + 1) % VIEW_NPRESETS;
		reset_camera(ui);
		say(ui, "view: %s", view_preset_name[ui->preset]);
		break;
	case 'o':
		ui->cam.perspective = !ui->cam.perspective;
		say(ui, "%s", ui->cam.perspective ? "perspective" : "orthographic");
		break;
	case '\t':
		ui->focus = (enum panel)((ui->focus + 1) % PANEL_COUNT);
		break;
	case '[':
		ui->selected = (ui->selected + s.cl->n - 1) % s.cl->n;
		break;
	case ']':
		ui->selected = (ui->selected + 1) % s.cl->n;
		break;
	case '/':
		ui->prompt = true;
		ui->prompt_step = false;
		ui->input[0] = '\0';
		break;
	case 'e':
		seek_event(ui);
		break;
	case 'r':
		toggle_recording(ui);
		break;
	case '?':
	case KEY_F(1):
		ui->help = true;
		break;
	case 12:	/* Ctrl-L */
		clearok(curscr, TRUE);
		break;
	default:
		break;
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

static int
draw_view(struct tui *ui, const struct layout *lo, const struct source_state *s)
{
	size_t nev;
	const struct contact_event *ev = ui->src->events(ui->src->ctx, &nev);
	int i, j;

	if ((ui->r.w != lo->view.w || ui->r.h != lo->view.h) &&
	    raster_resize(&ui->r, lo->view.w, lo->view.h) != 0)
		return -1;
	view_draw(&ui->r, &ui->cam, s->sc, s->x, s->cl->n, s->cl->tri, s->cl->ntri,
	    s->step > 0 ? ev : NULL, s->step > 0 ? nev : 0, ui->selected);
	for (j = 0; j < ui->r.h; j++) {
		move(lo->view.y + j, lo->view.x);
		for (i = 0; i < ui->r.w; i++) {
			size_t at = (size_t)j * (size_t)ui->r.w + (size_t)i;

			addch((chtype)(unsigned char)ui->r.ch[at] | cell_attr(ui, ui->r.kind[at]));
		}
	}
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
		screen_node(&t, s, ui->selected, ui->src->force(ui->src->ctx, ui->selected, &f) ?
		    &f : NULL, &ui->log);
		break;
	case PANEL_COUNT:
		break;
	}
	draw_text(&t, at, false);
}

static int
draw(struct tui *ui)
{
	struct layout lo;
	struct source_state s;
	struct status_info si;
	struct source_position pos;
	const char *rec;
	char line[TEXT_WIDTH * 2];
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
		screen_help(&t, ui->replay);
		draw_text(&t, (struct rect){ 2, 1, cols - 2, rows - 1 }, false);
	} else {
		si.s = &s;
		si.speed = ui->speed;	/* the latest measured, kept while paused */
		if (ui->replay) {
			ui->src->position(ui->src->ctx, &pos);
			si.mode = ui->ended ? "replay end" : ui->running ? "replay playing" : "replay";
			si.recording = "no";
			si.pos = &pos;
		} else {
			rec = ui->src->recording(ui->src->ctx, NULL);
			si.mode = ui->res->blown_up ? "blown up" : ui->ended ? "end" :
			    ui->running ? "running" : "paused";
			si.recording = rec != NULL ? rec : "no";
			si.pos = NULL;
		}
		si.steps_per_frame = ui->spf;
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
		else if (ui->replay)
			snprintf(line, sizeof line, "? help  q quit  space play  Left/Right frame  "
			    "PgUp/PgDn keyframe  g step  Home/End  Tab panel  / node");
		else if (rec != NULL)
			snprintf(line, sizeof line, "recording into %s (r stops)  ? help  q quit  "
			    "space run/pause", rec);
		else
			snprintf(line, sizeof line, "? help  q quit  space run/pause  n step  +/- speed  "
			    "arrows rotate  z/Z zoom  v view  Tab panel  [/] node");
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
}

static void
loop(struct tui *ui)
{
	double period = 0.1 * ui->opt.delay, next = clock_seconds();
	int ch;

	while (!ui->quit && !quit_signal) {
		double t = clock_seconds();

		if (ui->running && t >= next) {
			run_frame(ui, BUSY_FRACTION * period);
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
		if ((ch = getch()) == ERR)
			continue;
		/* every key already typed, then one redraw */
		do {
			if (ch != KEY_RESIZE)
				key(ui, ch);
			timeout(0);
		} while (!ui->quit && (ch = getch()) != ERR);
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
	ui.spf = ui.replay ? 1 : 256;	/* a replay plays a frame a redraw */
	ui.running = !opt->paused;
	ui.preset = VIEW_ISO;
	raster_init(&ui.r);
	src->state(src->ctx, &s);
	ui.selected = cloth_node(s.cl, s.cl->nu / 2, s.cl->nv / 2);
	if (ui.selected < 0)
		ui.selected = s.cl->n / 2;
	if (evlog_init(&ui.log, s.cl->n) != 0) {
		res->end = TUI_ERROR;
		snprintf(res->why, sizeof res->why, "out of memory for the event log");
		return;
	}
	reset_camera(&ui);
	ui.mark_wall = clock_seconds();
	ui.mark_t = s.t;

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
	evlog_free(&ui.log);
}

int
tui_parse_delay(const char *s, int *delay)
{
	char *end;
	long d = strtol(s, &end, 10);

	if (end == s || *end != '\0' || d < 1 || d > TUI_DELAY_MAX)
		return -1;
	*delay = (int)d;
	return 0;
}

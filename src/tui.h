/* tui.h: the ncurses front end on a source (a live run, or a replay that
 * it seeks in; see source.h): the view, the status line, the collision,
 * hash and node panels and the help screen, driven by keys. The screen model is
 * screen.h; this draws it and reads the keys. It restores the terminal
 * (endwin) before it returns, whatever the reason. */
#ifndef DRAPE_TUI_H
#define DRAPE_TUI_H

#include <signal.h>
#include <stdbool.h>

#include "glyphs.h"
#include "source.h"

#define TUI_DELAY_MAX 100	/* tenths of a second */

struct tui_opts {
	bool color;		/* colour if the terminal has it */
	int delay;		/* between redraws, tenths of a second, 1..TUI_DELAY_MAX */
	bool paused;		/* start paused */
	enum glyphs glyphs;	/* the view's characters: GLYPHS_AUTO (0) follows the
				 * locale; Unicode needs a UTF-8 one */
};

enum tui_end {
	TUI_QUIT,		/* q */
	TUI_SIGNAL,		/* SIGINT, SIGTERM or SIGHUP: signo */
	TUI_ERROR,		/* the terminal could not be used, or out of memory: why */
};

struct tui_result {
	enum tui_end end;
	int signo;
	bool blown_up;		/* the run stopped: why */
	bool run_error;		/* and not by a blow-up (out of memory) */
	char why[600];
};

/* Runs the front end on stdin and stdout until it ends; fills *res. */
void tui_run(struct source *src, const struct tui_opts *opt, struct tui_result *res);

/* The flag the TUI's SIGINT, SIGTERM and SIGHUP handler sets, for a
 * stepper to poll within a step (stepper_set_stop). */
const volatile sig_atomic_t *tui_stop_flag(void);

struct text;
/* The help screen, from the table the keys are dispatched by. */
void tui_help(struct text *t, bool replay);

/* -d/--delay's value: a whole number of tenths from 1 to TUI_DELAY_MAX.
 * Returns 0 with *delay set, or -1. */
int tui_parse_delay(const char *s, int *delay);

#endif

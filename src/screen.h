/* screen.h: the TUI's screen model: where each part goes for a terminal
 * size, and the text of the status line, the panels and the help, from
 * plain data. Nothing here draws (tui.c does, with ncurses), so the model
 * can be tested and a size change is only a new layout. */
#ifndef DRAPE_SCREEN_H
#define DRAPE_SCREEN_H

#include <stdbool.h>

#include "event.h"
#include "evlog.h"
#include "hash.h"
#include "source.h"

#define SCREEN_MIN_COLS 40
#define SCREEN_MIN_ROWS 12
#define TEXT_LINES 48
#define TEXT_WIDTH 160

enum panel { PANEL_COLLISIONS, PANEL_HASH, PANEL_NODE, PANEL_COUNT };

/* "collisions", "hash", "node", by panel. */
extern const char *const panel_name[PANEL_COUNT];

/* Lines of text, each cut to the width it was made for. */
struct text {
	int n, width;
	char line[TEXT_LINES][TEXT_WIDTH];
};

void text_init(struct text *t, int width);
void text_add(struct text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

struct rect {
	int x, y, w, h;
};

struct layout {
	bool too_small;		/* below SCREEN_MIN_COLS x SCREEN_MIN_ROWS */
	struct rect status, view, side, keys;
	bool stacked;		/* every panel at once; else tabs and the focused one */
	int tabs_y;		/* the tabs' row, when not stacked */
	struct rect panel[PANEL_COUNT];	/* h = 0: not shown */
};

void screen_layout(struct layout *lo, int cols, int rows, enum panel focus);

/* The status line's facts. */
struct status_info {
	const struct source_state *s;
	double speed;		/* simulated over wall time, measured; 0: not yet */
	const char *mode;	/* "running", "paused", "end", "blown up" */
	const char *pace;	/* what it plays at: "1x", "1/2x", "max" (pace.h) */
	const char *recording;	/* its file, or "no" */
	const struct source_position *pos;	/* a replay's, or NULL */
};

void screen_status(char *buf, int width, const struct status_info *si);

/* The key line: as many of the items (most needed first) as fit in
 * width, two spaces apart; an item is never cut (one cut mid-word at 80
 * columns). */
void screen_keys(char *buf, int width, const char *const *items, size_t n);
void screen_collisions(struct text *t, const struct source_stats *ss);
void screen_hash(struct text *t, const struct source_stats *ss);

/* The node inspector; f NULL when the force is not known. */
void screen_node(struct text *t, const struct source_state *s, int node, const vec3 *f,
    const struct evlog *log);

/* A line of the help screen: keys and what they do. */
struct screen_key {
	const char *names, *what;
};

/* The help screen of a replay's or a live run's keys (tui.c's table). */
void screen_help(struct text *t, bool replay, const struct screen_key *keys, size_t n);

#endif

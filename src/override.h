/* override.h: the command line's --set SECTION[#N].KEY=VALUE applied to a
 * scene's text, so that the scene parser reads it as if the file said so
 * (every check and message the same) and a replay records the text that
 * was run.
 *
 * A key the section has is replaced on its line; one it lacks is added
 * after the section's last key; a section the file lacks is added at the
 * end when a scene may have it once ([simulation], [cloth], [collision]).
 * A repeated section ([pin], [plane], ...) is named by its place among
 * those of its kind, plane#2 for the second [plane]; plain `plane` is the
 * only one, and an error when there are several. Each line of the new
 * text knows where it came from, so that an error names the file's line
 * or the option. */
#ifndef DRAPE_OVERRIDE_H
#define DRAPE_OVERRIDE_H

#include <stddef.h>

#include "err.h"

struct override_text {
	char *text;		/* the scene text with the overrides applied */
	int *from;		/* per line of text (from[0] is line 1): the line of
				 * the file it is, or -(k + 1) for the k-th override */
	int nlines;
	const char *const *sets;	/* the overrides as given, for messages */
};

/* Whether a section may appear more than once in a scene: 1 if so, 0 if
 * once, -1 if it is not a section of scenes (scene.c says). */
int scene_section_repeats(const char *name);

/* 0, or -1 with "--set SPEC: what was expected" (or the file's
 * "PATH:LINE: ..." if its text does not split into lines) in err. */
int override_apply(struct override_text *o, const char *path, const char *text,
    const char *const *sets, size_t nsets, struct drape_err *err);
void override_free(struct override_text *o);

/* Where line `line` of o->text came from: "PATH:LINE" or "--set SPEC". */
void override_where(const struct override_text *o, const char *path, int line, char *buf,
    size_t len);

#endif

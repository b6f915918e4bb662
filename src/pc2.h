/* pc2.h: Blender's Mesh Cache format (PC2), little-endian: "POINTCACHE2\0",
 * int32 version 1, int32 points, float32 start frame, float32 sample rate,
 * int32 samples, then float32 x y z per point per sample; frame k begins
 * at byte 32 + 12 * points * k. Written through a temporary file renamed
 * into place at the end, so nothing half-written is left at the path. */
#ifndef DRAPE_PC2_H
#define DRAPE_PC2_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "err.h"

struct pc2_header {
	char magic[12];
	int32_t version, points;
	float start, rate;
	int32_t samples;
};

_Static_assert(sizeof(struct pc2_header) == 32, "the PC2 header is 32 bytes");

struct pc2_writer {
	FILE *f;
	char *path, *tmp;	/* tmp is path itself when direct */
	bool direct;		/* not a regular file (outfile.h): written in place */
	struct pc2_header h;
};

int pc2_open(struct pc2_writer *w, const char *path, int points, float start, float rate,
    struct drape_err *err);
/* One sample: 3 * points floats. */
int pc2_append(struct pc2_writer *w, const float *x, struct drape_err *err);
/* Sets the sample count and renames into place; 0, or -1 with a message. */
int pc2_close(struct pc2_writer *w, struct drape_err *err);
/* Removes the temporary file without publishing it. */
void pc2_abort(struct pc2_writer *w);

#endif

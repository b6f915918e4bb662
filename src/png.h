/* png.h: an RGB image as a PNG file (ISO/IEC 15948): the signature, IHDR,
 * one IDAT of the filtered rows deflated by zlib, IEND, each chunk with
 * zlib's CRC-32. No other dependency; the same image gives the same bytes
 * (with the same zlib). A file is written whole or not at all: into a
 * temporary file beside it, then renamed. */
#ifndef DRAPE_PNG_H
#define DRAPE_PNG_H

#include <stdbool.h>
#include <stddef.h>

#include "err.h"

#define PNG_MAX_SIDE 65536

/* The PNG of a w x h image, 3 bytes a pixel, row by row from the top, into
 * *out (malloc'd, *len bytes). Returns 0, or -1 (bad size, out of memory)
 * with a message. */
int png_encode(const unsigned char *rgb, int w, int h, unsigned char **out, size_t *len,
    struct drape_err *err);

/* png_encode written to path. Returns 0, or -1 with "path: why" in err
 * (then path is as it was). */
int png_write(const char *path, const unsigned char *rgb, int w, int h, struct drape_err *err);

/* Whether len bytes are a whole PNG file as far as its ends tell: the
 * signature first and the IEND chunk last (a write cut short by a full
 * disk keeps the first and loses the second). */
bool png_is_whole(const unsigned char *buf, size_t len);

/* Writes len bytes to path through a temporary file in its directory and a
 * rename, so that path is whole or untouched. Returns 0, or -1 with
 * "path: why". */
int file_write_atomic(const char *path, const void *buf, size_t len, struct drape_err *err);

#endif

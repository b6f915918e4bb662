/* png.c: the PNG encoder: rows filtered (each by whichever of the five
 * filters gives the smallest sum of absolute differences, the usual
 * heuristic), deflated at level 9, chunked and CRC'd. */
#include <errno.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "outfile.h"
#include "png.h"

static void
be32(unsigned char *p, uint32_t v)
{
	p[0] = (unsigned char)(v >> 24);
	p[1] = (unsigned char)(v >> 16);
	p[2] = (unsigned char)(v >> 8);
	p[3] = (unsigned char)v;
}

/* A chunk at p: length, type, data, CRC of type and data; returns its size. */
static size_t
chunk(unsigned char *p, const char *type, const unsigned char *data, size_t len)
{
	uLong crc;

	be32(p, (uint32_t)len);
	memcpy(p + 4, type, 4);
	if (len > 0)
		memcpy(p + 8, data, len);
	crc = crc32(0L, Z_NULL, 0);
	crc = crc32(crc, p + 4, (uInt)(len + 4));
	be32(p + 8 + len, (uint32_t)crc);
	return len + 12;
}

static int
paeth(int a, int b, int c)
{
	int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);

	if (pa <= pb && pa <= pc)
		return a;
	return pb <= pc ? b : c;
}

/* Row y filtered into out (1 + stride bytes). */
static void
filter_row(const unsigned char *rgb, size_t stride, int y, unsigned char *out,
    unsigned char *trial)
{
	const unsigned char *row = rgb + (size_t)y * stride;
	const unsigned char *up = y > 0 ? row - stride : NULL;
	unsigned long best = ULONG_MAX;
	int f;
	size_t i;

	for (f = 0; f < 5; f++) {
		unsigned long sum = 0;

		trial[0] = (unsigned char)f;
		for (i = 0; i < stride; i++) {
			int a = i >= 3 ? row[i - 3] : 0, b = up != NULL ? up[i] : 0;
			int c = i >= 3 && up != NULL ? up[i - 3] : 0, pred = 0;
			unsigned char v;

			switch (f) {
			case 1:
				pred = a;
				break;
			case 2:
				pred = b;
				break;
			case 3:
				pred = (a + b) / 2;
				break;
			case 4:
				pred = paeth(a, b, c);
				break;
			}
			v = (unsigned char)(row[i] - pred);
			trial[1 + i] = v;
			sum += v < 128 ? v : 256u - v;
		}
		if (sum < best) {
			best = sum;
			memcpy(out, trial, stride + 1);
		}
	}
}

int
png_encode(const unsigned char *rgb, int w, int h, unsigned char **out, size_t *len,
    struct drape_err *err)
{
	static const unsigned char sig[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
	unsigned char ihdr[13], *raw = NULL, *z = NULL, *trial = NULL, *p = NULL;
	size_t stride, rawlen;
	uLongf zlen;
	int y;

	*out = NULL;
	*len = 0;
	if (w < 1 || h < 1 || w > PNG_MAX_SIDE || h > PNG_MAX_SIDE) {
		err_set(err, "a PNG of %d x %d pixels: each side must be 1 to %d", w, h,
		    PNG_MAX_SIDE);
		return -1;
	}
	stride = 3 * (size_t)w;
	rawlen = (stride + 1) * (size_t)h;
	if (rawlen > 0x7fffffffu) {
		err_set(err, "a PNG of %d x %d pixels is too large", w, h);
		return -1;
	}
	raw = malloc(rawlen);
	trial = malloc(stride + 1);
	zlen = compressBound((uLong)rawlen);
	z = malloc(zlen);
	if (raw == NULL || trial == NULL || z == NULL)
		goto oom;
	for (y = 0; y < h; y++)
		filter_row(rgb, stride, y, raw + (size_t)y * (stride + 1), trial);
	if (compress2(z, &zlen, raw, (uLong)rawlen, 9) != Z_OK)
		goto oom;
	if ((p = malloc(sizeof sig + 25 + (zlen + 12) + 12)) == NULL)
		goto oom;
	be32(ihdr, (uint32_t)w);
	be32(ihdr + 4, (uint32_t)h);
	ihdr[8] = 8;		/* bits per sample */
	ihdr[9] = 2;		/* truecolour */
	ihdr[10] = 0;		/* deflate */
	ihdr[11] = 0;		/* adaptive filtering */
	ihdr[12] = 0;		/* no interlace */
	memcpy(p, sig, sizeof sig);
	*len = sizeof sig;
	*len += chunk(p + *len, "IHDR", ihdr, sizeof ihdr);
	*len += chunk(p + *len, "IDAT", z, zlen);
	*len += chunk(p + *len, "IEND", NULL, 0);
	*out = p;
	free(raw);
	free(trial);
	free(z);
	return 0;
oom:
	free(raw);
	free(trial);
	free(z);
	err_set(err, "out of memory for a PNG of %d x %d pixels", w, h);
	return -1;
}

bool
png_is_whole(const unsigned char *buf, size_t len)
{
	static const unsigned char sig[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
	/* length 0, "IEND", its CRC */
	static const unsigned char iend[12] = { 0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60,
		0x82 };

	return len >= sizeof sig + sizeof iend && memcmp(buf, sig, sizeof sig) == 0 &&
	    memcmp(buf + len - sizeof iend, iend, sizeof iend) == 0;
}

int
file_write_atomic(const char *path, const void *buf, size_t len, struct drape_err *err)
{
	size_t plen = strlen(path);
	char *tmp = malloc(plen + 16);
	mode_t mask;
	FILE *f;
	int fd, e;

	if (tmp == NULL) {
		err_set(err, "%s: out of memory", path);
		return -1;
	}
	if (outfile_is_special(path)) {	/* /dev/null: written in place, no rename over it */
		free(tmp);
		if ((f = fopen(path, "wb")) == NULL) {
			err_set(err, "%s: %s", path, strerror(errno));
			return -1;
		}
		e = fwrite(buf, 1, len, f) != len || fflush(f) != 0 ? errno : 0;
		if (fclose(f) != 0 && e == 0)
			e = errno != 0 ? errno : EIO;
		if (e != 0) {
			err_set(err, "%s: %s", path, strerror(e));
			return -1;
		}
		return 0;
	}
	snprintf(tmp, plen + 16, "%s.tmp-XXXXXX", path);
	if ((fd = mkstemp(tmp)) < 0) {
		err_set(err, "%s: %s", path, strerror(errno));
		free(tmp);
		return -1;
	}
	/* as fopen would make it, not mkstemp's 0600 */
	mask = umask(0);
	umask(mask);
	if (fchmod(fd, 0666 & ~mask) != 0 || (f = fdopen(fd, "wb")) == NULL) {
		err_set(err, "%s: %s", path, strerror(errno));
		close(fd);
		unlink(tmp);
		free(tmp);
		return -1;
	}
	if (fwrite(buf, 1, len, f) != len || fflush(f) != 0) {
		e = errno;
		fclose(f);
		goto fail;
	}
	if (fclose(f) != 0) {
		e = errno;
		goto fail;
	}
	if (rename(tmp, path) != 0) {
		e = errno;
		goto fail;
	}
	free(tmp);
	return 0;
fail:
	err_set(err, "%s: %s", path, strerror(e != 0 ? e : EIO));
	unlink(tmp);
	free(tmp);
	return -1;
}

int
png_write(const char *path, const unsigned char *rgb, int w, int h, struct drape_err *err)
{
	unsigned char *png;
	size_t len;
	int rc;

	if (png_encode(rgb, w, h, &png, &len, err) != 0)
		return -1;
	rc = file_write_atomic(path, png, len, err);
	free(png);
	return rc;
}

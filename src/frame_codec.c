/* frame_codec.c: prediction residuals and byte shuffling (see the header). */
#include <string.h>

#include "frame_codec.h"

void
codec_shuffle(const unsigned char *in, unsigned char *out, size_t nelem, size_t elsize)
{
	size_t i, b;

	for (i = 0; i < nelem; i++)
		for (b = 0; b < elsize; b++)
			out[b * nelem + i] = in[i * elsize + b];
}

void
codec_unshuffle(const unsigned char *in, unsigned char *out, size_t nelem, size_t elsize)
{
	size_t i, b;

	for (i = 0; i < nelem; i++)
		for (b = 0; b < elsize; b++)
			out[i * elsize + b] = in[b * nelem + i];
}

static uint32_t
zigzag(uint32_t d)
{
	return (d << 1) ^ (uint32_t)-(int32_t)(d >> 31);
}

static uint32_t
unzigzag(uint32_t z)
{
	return (z >> 1) ^ (uint32_t)-(int32_t)(z & 1);
}

void
codec_delta_u32(uint32_t *w, size_t n)
{
	uint32_t prev = 0, cur;
	size_t i;

	for (i = 0; i < n; i++) {
		cur = w[i];
		w[i] = zigzag(cur - prev);
		prev = cur;
	}
}

void
codec_undelta_u32(uint32_t *w, size_t n)
{
	uint32_t prev = 0;
	size_t i;

	for (i = 0; i < n; i++) {
		prev += unzigzag(w[i]);
		w[i] = prev;
	}
}

/* The temporal difference of word k of frame f (frame -1 is all zero). */
static uint32_t
tdiff(const uint32_t *bits, size_t f, size_t ncoord, size_t k)
{
	return bits[f * ncoord + k] - (f > 0 ? bits[(f - 1) * ncoord + k] : 0);
}

/* The residuals of words bits (in place) and their shuffle into out. */
static void
encode_words(uint32_t *bits, size_t nframes, size_t ncoord, unsigned char *out)
{
	size_t f, k, n = nframes * ncoord;

	/* Residuals are computed back to front so that bits can hold the
	 * words the earlier residuals still need. */
	for (f = nframes; f-- > 0;)
		for (k = ncoord; k-- > 0;) {
			uint32_t d = tdiff(bits, f, ncoord, k);

			if (k >= 3)
				d -= tdiff(bits, f, ncoord, k - 3);
			bits[f * ncoord + k] = zigzag(d);
		}
	codec_shuffle((const unsigned char *)bits, out, n, 4);
}

/* Words back from in into bits. */
static void
decode_words(const unsigned char *in, size_t nframes, size_t ncoord, uint32_t *bits)
{
	size_t f, k, n = nframes * ncoord;

	codec_unshuffle(in, (unsigned char *)bits, n, 4);
	for (f = 0; f < nframes; f++)
		for (k = 0; k < ncoord; k++) {
			uint32_t d = unzigzag(bits[f * ncoord + k]);

			if (k >= 3)
				d += tdiff(bits, f, ncoord, k - 3);
			bits[f * ncoord + k] = d + (f > 0 ? bits[(f - 1) * ncoord + k] : 0);
		}
}

void
frames_encode(const float *x, size_t nframes, size_t ncoord, uint32_t *tmp, unsigned char *out)
{
	memcpy(tmp, x, nframes * ncoord * sizeof *tmp);
	encode_words(tmp, nframes, ncoord, out);
}

void
frames_decode(const unsigned char *in, size_t nframes, size_t ncoord, uint32_t *tmp, float *x)
{
	decode_words(in, nframes, ncoord, tmp);
	memcpy(x, tmp, nframes * ncoord * sizeof *tmp);
}

/* Integers go through as their two's complement words: the differences
 * wrap modulo 2^32 both ways, so any int32 comes back. */
void
frames_encode_q(const int32_t *q, size_t nframes, size_t ncoord, uint32_t *tmp,
    unsigned char *out)
{
	memcpy(tmp, q, nframes * ncoord * sizeof *tmp);
	encode_words(tmp, nframes, ncoord, out);
}

void
frames_decode_q(const unsigned char *in, size_t nframes, size_t ncoord, uint32_t *tmp,
    int32_t *q)
{
	decode_words(in, nframes, ncoord, tmp);
	memcpy(q, tmp, nframes * ncoord * sizeof *tmp);
}

/* ---- frames of a grid ---- */

/* Word i of a frames array of 4-byte words (float or int32 bits). */
static uint32_t
word_at(const unsigned char *w, size_t i)
{
	uint32_t u;

	memcpy(&u, w + 4 * i, 4);
	return u;
}

/* LOCO-I's median edge detector on the neighbours' temporal differences
 * left a, up b and up-left c, compared as int32 (the xor maps their
 * order to unsigned order); a + b - c wraps modulo 2^32 both ways. */
static uint32_t
med(uint32_t a, uint32_t b, uint32_t c, int left, int up)
{
	uint32_t sa = a ^ 0x80000000u, sb = b ^ 0x80000000u, sc = c ^ 0x80000000u;
	uint32_t hi = sa > sb ? sa : sb, lo = sa < sb ? sa : sb;

	if (!left)
		return up ? b : 0;
	if (!up)
		return a;
	if (sc >= hi)
		return lo ^ 0x80000000u;
	if (sc <= lo)
		return hi ^ 0x80000000u;
	return a + b - c;
}

/* The temporal difference of coordinate k of node i in frame f of words
 * w (frame -1 is all zero). */
static uint32_t
grid_tdiff(const unsigned char *w, size_t f, size_t nodes, size_t i, size_t k)
{
	size_t at = (f * nodes + i) * 3 + k;

	return word_at(w, at) - (f > 0 ? word_at(w, at - 3 * nodes) : 0);
}

/* The prediction of node i's difference from its decoded neighbours. */
static uint32_t
grid_predict(const unsigned char *w, size_t f, size_t nodes, size_t width, size_t i, size_t k)
{
	int left = i % width > 0, up = i >= width;

	return med(left ? grid_tdiff(w, f, nodes, i - 1, k) : 0,
	    up ? grid_tdiff(w, f, nodes, i - width, k) : 0,
	    left && up ? grid_tdiff(w, f, nodes, i - width - 1, k) : 0, left, up);
}

/* The words as decode_grid's order needs them, computed the cheap way: a
 * frame's temporal differences first, each once (grid_predict would
 * take each four times, with a division for the column), then each
 * node's residual from the last backwards, its neighbours' differences
 * being at lower indices and so not yet replaced. The same words as
 * zigzag(grid_tdiff - grid_predict) node by node; the run's thread
 * spent 1.3 % of a recorded tablecloth's instructions on that. */
static void
encode_grid(const unsigned char *w, size_t nframes, size_t nodes, size_t width, uint32_t *tmp,
    unsigned char *out)
{
	size_t f, i, k;

	for (k = 0; k < 3; k++)
		for (f = 0; f < nframes; f++) {
			uint32_t *d = tmp + (k * nframes + f) * nodes;

			for (i = 0; i < nodes; i++)
				d[i] = grid_tdiff(w, f, nodes, i, k);
			for (i = nodes; i-- > 0;) {
				int left = i % width > 0, up = i >= width;

				d[i] = zigzag(d[i] - med(left ? d[i - 1] : 0, up ? d[i - width] : 0,
				    left && up ? d[i - width - 1] : 0, left, up));
			}
		}
	codec_shuffle((const unsigned char *)tmp, out, 3 * nframes * nodes, 4);
}

/* Frame by frame, node by node, so that a node's neighbours and its own
 * word of the frame before are decoded before it. */
static void
decode_grid(const unsigned char *in, size_t nframes, size_t nodes, size_t width, uint32_t *tmp,
    unsigned char *w)
{
	size_t f, i, k;

	codec_unshuffle(in, (unsigned char *)tmp, 3 * nframes * nodes, 4);
	for (f = 0; f < nframes; f++)
		for (i = 0; i < nodes; i++)
			for (k = 0; k < 3; k++) {
				size_t at = (f * nodes + i) * 3 + k;
				uint32_t d = unzigzag(tmp[(k * nframes + f) * nodes + i]) +
				    grid_predict(w, f, nodes, width, i, k);

				d += f > 0 ? word_at(w, at - 3 * nodes) : 0;
				memcpy(w + 4 * at, &d, 4);
			}
}

void
frames_encode_grid(const float *x, size_t nframes, size_t nodes, size_t width, uint32_t *tmp,
    unsigned char *out)
{
	encode_grid((const unsigned char *)x, nframes, nodes, width > 0 ? width : 1, tmp, out);
}

void
frames_decode_grid(const unsigned char *in, size_t nframes, size_t nodes, size_t width,
    uint32_t *tmp, float *x)
{
	decode_grid(in, nframes, nodes, width > 0 ? width : 1, tmp, (unsigned char *)x);
}

void
frames_encode_grid_q(const int32_t *q, size_t nframes, size_t nodes, size_t width,
    uint32_t *tmp, unsigned char *out)
{
	encode_grid((const unsigned char *)q, nframes, nodes, width > 0 ? width : 1, tmp, out);
}

void
frames_decode_grid_q(const unsigned char *in, size_t nframes, size_t nodes, size_t width,
    uint32_t *tmp, int32_t *q)
{
	decode_grid(in, nframes, nodes, width > 0 ? width : 1, tmp, (unsigned char *)q);
}

/* frame_codec.h: lossless packing of numbers for deflate. Float32 position
 * frames become residuals of a prediction (each coordinate's bit pattern
 * minus the previous frame's, minus the same for the previous node: cloth
 * nodes move together), zigzagged so that small residuals of either sign
 * have zero high bytes; a byte shuffle then groups the bytes of all words
 * by significance, so deflate sees long runs of near-zero high bytes. */
#ifndef DRAPE_FRAME_CODEC_H
#define DRAPE_FRAME_CODEC_H

#include <stddef.h>
#include <stdint.h>

/* out[b * nelem + i] = byte b of element i (elements of elsize bytes). */
void codec_shuffle(const unsigned char *in, unsigned char *out, size_t nelem, size_t elsize);
void codec_unshuffle(const unsigned char *in, unsigned char *out, size_t nelem, size_t elsize);

/* Words of consecutive differences (zigzagged) and back, in place. */
void codec_delta_u32(uint32_t *w, size_t n);
void codec_undelta_u32(uint32_t *w, size_t n);

/* nframes frames of ncoord floats (x y z per node) into 4 * nframes *
 * ncoord bytes, and back; tmp holds nframes * ncoord words. Each frame is
 * predicted from the one before it in the same call only, so a chunk
 * decodes on its own. */
void frames_encode(const float *x, size_t nframes, size_t ncoord, uint32_t *tmp,
    unsigned char *out);
void frames_decode(const unsigned char *in, size_t nframes, size_t ncoord, uint32_t *tmp,
    float *x);

/* Lossy frames (replay --precision): nframes frames of ncoord positions,
 * each already rounded to a whole number q of the grid step (q = x / p),
 * coded as frames_encode codes bit patterns (the same prediction on the
 * integers) into 4 * nframes * ncoord bytes, and back to the integers. */
void frames_encode_q(const int32_t *q, size_t nframes, size_t ncoord, uint32_t *tmp,
    unsigned char *out);
void frames_decode_q(const unsigned char *in, size_t nframes, size_t ncoord, uint32_t *tmp,
    int32_t *q);

/*
 * Frames of a cloth grid, as written since replay version 3: node i's
 * neighbours are i - 1 to its left (none at a row's start, every width
 * nodes) and i - width above. The words are laid out by coordinate (every
 * x of the frames, then every y, then every z: one plane's words are
 * alike), and each word's temporal difference (as above) is predicted
 * from its left, upper and upper-left neighbours' in the same frame by
 * LOCO-I's median edge detector (Weinberger, Seroussi and Sapiro, 2000):
 * the cloth's motion is smooth across it. Residuals are zigzagged and
 * shuffled as above. On the shipped tablecloth's frames, deflated: 5.89
 * bytes a node a frame, against 6.61 with frames_encode (measured offline
 * with the same chunks of 25 frames); the layout alone gives 6.23. The
 * _q forms code int32 grid steps the same way.
 */
void frames_encode_grid(const float *x, size_t nframes, size_t nodes, size_t width,
    uint32_t *tmp, unsigned char *out);
void frames_decode_grid(const unsigned char *in, size_t nframes, size_t nodes, size_t width,
    uint32_t *tmp, float *x);
void frames_encode_grid_q(const int32_t *q, size_t nframes, size_t nodes, size_t width,
    uint32_t *tmp, unsigned char *out);
void frames_decode_grid_q(const unsigned char *in, size_t nframes, size_t nodes, size_t width,
    uint32_t *tmp, int32_t *q);

#endif

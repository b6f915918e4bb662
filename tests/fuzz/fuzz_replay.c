/* fuzz_replay.c: the replay reader on arbitrary bytes: open, then decode
 * every chunk it found intact. libFuzzer's entry point; tests/fuzz/driver.c
 * runs the seed corpus through it in make check.
 *
 * The seeds in corpus/: whole.drr from
 *	cd tests/fuzz && drape run --record whole.drr --keyframe-every 20 seed.scene
 * and from it cut.drr (its first 1500 bytes), flipped.drr (bit 4 of byte
 * 700 flipped) and header-only.drr (its first 64 bytes); lossy.drr the
 * same with --precision 10um. Those are version 1 and 2 files; the same
 * two recorded by version 3 (frames of the grid, kinds 7 and 8) are
 * whole-v3.drr and lossy-v3.drr, and bad-width.drr is whole-v3.drr with
 * its first frames chunk saying a grid 0 nodes wide (its CRC made
 * again). whole-v4.drr is whole.drr recorded by version 4: its steps
 * chunks hold their events' digest (kind 9). Recomputing those events
 * runs the scene the file holds, which is the simulator's to be fuzzed,
 * not the reader's: here a digest chunk's statistics are read, and its
 * events refused. */
#include <stddef.h>
#include <stdint.h>

#include "replay.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct replay r;
	struct drape_err err;
	size_t i;

	if (replay_open_mem(&r, data, size, &err) != 0)
		return 0;
	for (i = 0; i < r.nchunks; i++) {
		struct replay_frames fr;
		struct replay_keyframe kf;
		struct replay_steps ss;

		switch (r.chunk[i].kind) {
		case REPLAY_FRAMES:
		case REPLAY_FRAMES_Q:
		case REPLAY_FRAMES_GRID:
		case REPLAY_FRAMES_GRID_Q:
			if (replay_read_frames(&r, i, &fr, &err) == 0)
				replay_frames_free(&fr);
			break;
		case REPLAY_KEYFRAME:
			if (replay_read_keyframe(&r, i, &kf, &err) == 0)
				replay_keyframe_free(&kf);
			break;
		case REPLAY_STEPS:
		case REPLAY_STEPS_DIGEST:
			if (replay_read_step_stats(&r, i, &ss, &err) == 0)
				replay_steps_free(&ss);
			if (replay_read_steps(&r, i, &ss, &err) == 0)
				replay_steps_free(&ss);
			break;
		default:
			break;
		}
	}
	(void)replay_find_keyframe(&r, -1);
	replay_close(&r);
	return 0;
}

/* cmd_export.c: `drape export FILE [--pc2 OUT.pc2] [--obj REST.obj]
 * [--obj-seq DIR]`: a replay's frames for Blender: a Mesh Cache (PC2), the
 * mesh it deforms (the first frame, in the same vertex order) and OBJs. */
#include <errno.h>
#include <float.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cmd.h"
#include "obj.h"
#include "outfile.h"
#include "pc2.h"
#include "replay.h"

/* One frame's floats as doubles, for the OBJ writer. */
static int
write_obj_frame(const char *path, const float *x, const struct replay_meta *m,
    struct drape_err *err)
{
	size_t n3 = 3 * (size_t)m->nodes, i;
	double *d = malloc(n3 * sizeof *d);
	int rc;

	if (d == NULL) {
		err_set(err, "%s: out of memory", path);
		return -1;
	}
	for (i = 0; i < n3; i++)
		d[i] = x[i];
	rc = obj_write(path, d, (int)m->nodes, m->tri, m->triangles, err);
	free(d);
	return rc;
}

/* The frames of replay r (read from in) into the outputs. An exit status:
 * EXIT_USAGE when the replay holds no frame that can be exported (none
 * intact, a chunk that passes its CRC but does not decode, a frame time
 * out of range) or a frame of --obj-seq would overwrite in, EXIT_RUNTIME
 * when an output cannot be written, EXIT_INTERRUPTED when a signal came
 * (cmd_signal); what was being written is then removed. */
static int
export(const struct replay *r, const char *in, const char *pc2, const char *obj,
    const char *seq, struct drape_err *err)
{
	struct pc2_writer pw;
	struct replay_frames fr;
	const struct replay_meta *m = &r->meta;
	size_t i, k, frame = 0, n3 = 3 * (size_t)m->nodes;
	bool open_pc2 = false, first = true;
	char path[4096];
	int rc = EXIT_RUNTIME;

	for (i = 0; i < r->nchunks; i++) {
		if (!replay_is_frames(r->chunk[i].kind))
			continue;
		if (replay_read_frames(r, i, &fr, err) != 0) {
			rc = EXIT_USAGE;
			goto fail;
		}
		for (k = 0; k < fr.count; k++, frame++) {
			const float *x = fr.x + k * n3;

			/* a signal: the PC2 begun is removed, the whole files
			 * written so far stay */
			if (cmd_signal) {
				err_set(err, "%s at frame %zu: the files begun were removed",
				    cmd_signal_word(cmd_signal), frame);
				rc = EXIT_INTERRUPTED;
				goto fail_fr;
			}

			if (first) {
				double start = fr.t[k] * m->output_rate;

				first = false;
				if (!(fabs(start) <= FLT_MAX)) {
					err_set(err, "its first frame's time, %g s, is out of range", fr.t[k]);
					rc = EXIT_USAGE;
					goto fail_fr;
				}
				if (obj != NULL && write_obj_frame(obj, x, m, err) != 0)
					goto fail_fr;
				if (pc2 != NULL) {
					if (pc2_open(&pw, pc2, (int)m->nodes, (float)start, 1.0f, err) != 0)
						goto fail_fr;
					open_pc2 = true;
				}
			}
			if (open_pc2 && pc2_append(&pw, x, err) != 0)
				goto fail_fr;
			if (seq != NULL) {
				if ((size_t)snprintf(path, sizeof path, "%s/frame_%05zu.obj", seq, frame) >=
				    sizeof path) {
					err_set(err, "%s: path too long", seq);
					goto fail_fr;
				}
				if (outfile_same(path, in)) {
					err_set(err, "--obj-seq %s would overwrite it: expected another "
					    "directory", path);
					rc = EXIT_USAGE;
					goto fail_fr;
				}
				if (write_obj_frame(path, x, m, err) != 0)
					goto fail_fr;
			}
		}
		replay_frames_free(&fr);
	}
	if (first) {
		err_set(err, "no intact frame to export");
		return EXIT_USAGE;
	}
	if (cmd_signal) {
		rc = EXIT_INTERRUPTED;
		err_set(err, "%s after the last frame: the files begun were removed",
		    cmd_signal_word(cmd_signal));
		goto fail;
	}
	if (open_pc2 && pc2_close(&pw, err) != 0)
		return EXIT_RUNTIME;
	return EXIT_OK;
fail_fr:
	replay_frames_free(&fr);
fail:
	if (open_pc2)
		pc2_abort(&pw);
	/* a write a signal cut (a FIFO's open) is the signal's doing */
	if (cmd_signal && rc != EXIT_INTERRUPTED) {
		err_set(err, "%s at frame %zu: the files begun were removed",
		    cmd_signal_word(cmd_signal), frame);
		rc = EXIT_INTERRUPTED;
	}
	return rc;
}

int
cmd_export(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "pc2", required_argument, NULL, 'p' },
		{ "obj", required_argument, NULL, 'o' },
		{ "obj-seq", required_argument, NULL, 's' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *pc2 = NULL, *obj = NULL, *seq = NULL;
	struct replay r;
	struct drape_err err;
	int c, rc = EXIT_OK;

	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "h", longopts, NULL)) != -1) {
		switch (c) {
		case 'p':
			pc2 = optarg;
			break;
		case 'o':
			obj = optarg;
			break;
		case 's':
			seq = optarg;
			break;
		case 'h':
			usage(stdout);
			return EXIT_OK;
		default:
			return cmd_option_error("export", argv);
		}
	}
	if (optind != argc - 1) {
		return cmd_usage_error("export", "expected one replay file");
	}
	if (pc2 == NULL && obj == NULL && seq == NULL) {
		fprintf(stderr, "drape export: expected --pc2 OUT.pc2, --obj REST.obj or "
		    "--obj-seq DIR\n");
		return EXIT_USAGE;
	}
	/* before anything is written */
	if (cmd_output_seeks("export", "--pc2", pc2) != EXIT_OK ||
	    cmd_output_spares("export", "--pc2", pc2, argv[optind], "the replay being exported") !=
	    EXIT_OK ||
	    cmd_output_spares("export", "--obj", obj, argv[optind], "the replay being exported") !=
	    EXIT_OK)
		return EXIT_USAGE;
	if (seq != NULL && mkdir(seq, 0777) != 0 && errno != EEXIST) {
		fprintf(stderr, "drape export: %s: cannot create: %s\n", seq, strerror(errno));
		return EXIT_RUNTIME;
	}
	/* from here, temporary files (the PC2's, each OBJ's) exist: a signal
	 * is let out once they are gone */
	cmd_catch_signals();
	if (replay_open(&r, argv[optind], &err) != 0) {
		fprintf(stderr, "drape export: %s\n", err.msg);
		return EXIT_USAGE;
	}
	if (r.cut || r.nbad > 0)
		fprintf(stderr, "drape export: %s: %s; exporting the %zu intact frames\n",
		    argv[optind], r.cut ? "cut short" : "some chunks have a bad CRC", r.nframes);
	if ((rc = export(&r, argv[optind], pc2, obj, seq, &err)) != EXIT_OK)
		fprintf(stderr, "drape export: %s: %s\n", argv[optind], err.msg);
	replay_close(&r);
	return rc;
}

/* cmd_export.c: `drape export FILE [--pc2 OUT.pc2] [--obj REST.obj]
 * [--obj-seq DIR] [--obstacles OUT.obj] [--fps F]`: a replay's frames for
 * Blender: a Mesh Cache (PC2), the mesh it deforms (the first frame, in
 * the same vertex order), OBJs with texture coordinates from the grid,
 * the obstacles, at the recorded rate or resampled to F a second. */
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
#include "obstacle_mesh.h"
#include "outfile.h"
#include "pc2.h"
#include "replay.h"
#include "replay_run.h"

/* What the OBJs are written with: the cloth's texture coordinates (NULL
 * when its scene could not be built) and room for one frame's doubles and
 * normals. */
struct obj_out {
	const struct replay_meta *m;
	double *uv, *x, *normal;
};

/* Texture coordinates from the grid: node (i, j) of an nu x nv grid at
 * (i / (nu - 1), j / (nv - 1)), so that a texture covers the cloth. */
static double *
grid_uv(const struct cloth *cl)
{
	double *uv = malloc(2 * (size_t)(cl->n > 0 ? cl->n : 1) * sizeof *uv);
	int p, i, j;

	if (uv == NULL)
		return NULL;
	for (p = 0; p < cl->n; p++) {
		cloth_grid_ij(cl, p, &i, &j);
		uv[2 * p] = cl->nu > 1 ? (double)i / (cl->nu - 1) : 0;
		uv[2 * p + 1] = cl->nv > 1 ? (double)j / (cl->nv - 1) : 0;
	}
	return uv;
}

/* One frame as OBJ: with texture coordinates, and normals if asked (not
 * the rest mesh's: a Mesh Cache moves its vertices, and Blender would keep
 * the first frame's normals as custom ones). */
static int
write_obj_frame(const char *path, const float *x, struct obj_out *o, bool normals,
    struct drape_err *err)
{
	size_t n3 = 3 * (size_t)o->m->nodes, i;
	struct obj_mesh mesh = { NULL, o->x, (int)o->m->nodes, o->m->tri, o->m->triangles,
		o->uv, NULL };

	for (i = 0; i < n3; i++)
		o->x[i] = x[i];
	if (normals) {
		obj_vertex_normals(o->x, (int)o->m->nodes, o->m->tri, o->m->triangles, o->normal);
		mesh.normal = o->normal;
	}
	return obj_write_meshes(path, &mesh, 1, err);
}

/* The scene's obstacles in one OBJ, an object each ("box_47": its kind and
 * the line of its section); a plane as a square under the cloth's first
 * frame x, ten times the cloth's size across. 0, or -1. */
static int
write_obstacles(const char *path, const struct scene *sc, const float *x, size_t nodes,
    struct drape_err *err)
{
	struct obj_mesh *om = calloc(sc->nobstacles > 0 ? sc->nobstacles : 1, sizeof *om);
	struct mesh *ms = calloc(sc->nobstacles > 0 ? sc->nobstacles : 1, sizeof *ms);
	char (*name)[48] = calloc(sc->nobstacles > 0 ? sc->nobstacles : 1, sizeof *name);
	vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY), c;
	double half;
	size_t i, k;
	int rc = -1;

	if (om == NULL || ms == NULL || name == NULL) {
		err_set(err, "%s: out of memory", path);
		goto done;
	}
	for (i = 0; i < nodes; i++) {
		vec3 p = v3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);

		v3_box_grow(&lo, &hi, p);
	}
	c = v3_scale(v3_add(lo, hi), 0.5);
	half = fmax(5 * v3_len(v3_sub(hi, lo)), 0.1);
	for (k = 0; k < sc->nobstacles; k++) {
		const struct obstacle *o = &sc->obstacles[k];

		if (obstacle_mesh(o, c, half, &ms[k]) != 0) {
			err_set(err, "%s: out of memory", path);
			goto done;
		}
		snprintf(name[k], sizeof name[k], "%s_%d", obstacle_kind_name[o->kind], o->line);
		om[k] = (struct obj_mesh){ name[k], ms[k].x, ms[k].nverts, ms[k].tri, ms[k].ntri,
			NULL, NULL };
	}
	rc = obj_write_meshes(path, om, sc->nobstacles, err);
done:
	for (k = 0; ms != NULL && k < sc->nobstacles; k++)
		mesh_free(&ms[k]);
	free(ms);
	free(om);
	free(name);
	return rc;
}

/* What to export: the outputs (NULL: not asked) and the rate. */
struct export_opts {
	const char *pc2, *obj, *seq, *obstacles;
	double fps;		/* samples a second of simulated time, 0: as recorded */
};

/* The samples written so far, and the frame before the current one. */
struct sampler {
	size_t count;
	float *prev, *mix;
	double t_prev, t0;
	bool have_prev;
};

/* One sample into the PC2 and the OBJ sequence. */
static int
emit(const struct export_opts *eo, struct pc2_writer *pw, bool open_pc2, struct obj_out *oo,
    const char *in, const float *x, size_t sample, int *rc, struct drape_err *err)
{
	char path[4096];

	if (open_pc2 && pc2_append(pw, x, err) != 0)
		return -1;
	if (eo->seq == NULL)
		return 0;
	if ((size_t)snprintf(path, sizeof path, "%s/frame_%05zu.obj", eo->seq, sample) >=
	    sizeof path) {
		err_set(err, "%s: path too long", eo->seq);
		return -1;
	}
	if (outfile_same(path, in)) {
		err_set(err, "--obj-seq %s would overwrite it: expected another directory", path);
		*rc = EXIT_USAGE;
		return -1;
	}
	return write_obj_frame(path, x, oo, true, err);
}

/* The frames of replay r (read from in) into the outputs, the obstacles of
 * sc (NULL: its scene could not be built) too. An exit status: EXIT_USAGE
 * when the replay holds no frame that can be exported (none intact, a
 * chunk that passes its CRC but does not decode, a frame time out of
 * range) or a frame of --obj-seq would overwrite in, EXIT_RUNTIME when an
 * output cannot be written, EXIT_INTERRUPTED when a signal came
 * (cmd_signal); what was being written is then removed. */
static int
export(const struct replay *r, const char *in, const struct export_opts *eo,
    const struct scene *sc, struct obj_out *oo, struct drape_err *err)
{
	struct pc2_writer pw;
	struct replay_frames fr;
	struct sampler sm = { 0 };
	const struct replay_meta *m = &r->meta;
	size_t i, k, j, frame = 0, n3 = 3 * (size_t)m->nodes;
	bool open_pc2 = false, first = true;
	double rate = eo->fps > 0 ? eo->fps : m->output_rate;
	int rc = EXIT_RUNTIME;

	if (eo->fps > 0 && ((sm.prev = malloc((n3 > 0 ? n3 : 1) * sizeof *sm.prev)) == NULL ||
	    (sm.mix = malloc((n3 > 0 ? n3 : 1) * sizeof *sm.mix)) == NULL)) {
		free(sm.prev);
		err_set(err, "out of memory");
		return EXIT_RUNTIME;
	}
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
				double start = fr.t[k] * rate;

				first = false;
				sm.t0 = fr.t[k];
				if (!(fabs(start) <= FLT_MAX)) {
					err_set(err, "its first frame's time, %g s, is out of range", fr.t[k]);
					rc = EXIT_USAGE;
					goto fail_fr;
				}
				if (eo->obj != NULL && write_obj_frame(eo->obj, x, oo, false, err) != 0)
					goto fail_fr;
				if (eo->obstacles != NULL && write_obstacles(eo->obstacles, sc, x,
				    m->nodes, err) != 0)
					goto fail_fr;
				if (eo->pc2 != NULL) {
					if (pc2_open(&pw, eo->pc2, (int)m->nodes, (float)start, 1.0f,
					    err) != 0)
						goto fail_fr;
					open_pc2 = true;
				}
			}
			if (eo->fps <= 0) {
				if (emit(eo, &pw, open_pc2, oo, in, x, frame, &rc, err) != 0)
					goto fail_fr;
				continue;
			}
			/* the samples up to this frame's time, each between the frame
			 * before and this one (at either, exactly that frame) */
			for (;;) {
				double ts = sm.t0 + (double)sm.count / eo->fps, w;
				const float *out = x;

				if (ts > fr.t[k] + 1e-6 / eo->fps)
					break;
				w = sm.have_prev && fr.t[k] > sm.t_prev ?
				    (ts - sm.t_prev) / (fr.t[k] - sm.t_prev) : 1;
				if (w < 1e-6)
					out = sm.prev;
				else if (w < 1 - 1e-6) {
					for (j = 0; j < n3; j++)
						sm.mix[j] = (float)(sm.prev[j] + w * (x[j] - sm.prev[j]));
					out = sm.mix;
				}
				if (emit(eo, &pw, open_pc2, oo, in, out, sm.count, &rc, err) != 0)
					goto fail_fr;
				sm.count++;
			}
			memcpy(sm.prev, x, n3 * sizeof *x);
			sm.t_prev = fr.t[k];
			sm.have_prev = true;
		}
		replay_frames_free(&fr);
	}
	free(sm.prev);
	free(sm.mix);
	sm.prev = sm.mix = NULL;
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
	free(sm.prev);
	free(sm.mix);
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

/* The replay's scene and cloth, for the texture coordinates and the
 * obstacles: 0, or -1 with why in err (a mesh's OBJ gone, say). */
static int
build_scene(const struct replay *r, const char *file, struct scene *sc, struct network *net,
    struct drape_err *err)
{
	if (replay_scene(r, file, 0, sc, err) != 0)
		return -1;
	if (replay_network(r, file, sc, net, err) != 0) {
		scene_free(sc);
		return -1;
	}
	return 0;
}

int
cmd_export(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "pc2", required_argument, NULL, 'p' },
		{ "obj", required_argument, NULL, 'o' },
		{ "obj-seq", required_argument, NULL, 's' },
		{ "obstacles", required_argument, NULL, 'b' },
		{ "fps", required_argument, NULL, 'f' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct export_opts eo = { NULL, NULL, NULL, NULL, 0 };
	struct obj_out oo = { NULL, NULL, NULL, NULL };
	struct replay r;
	struct scene sc;
	struct network net;
	struct drape_err err, serr;
	bool built = false;
	char *end;
	int c, rc = EXIT_OK;

	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "h", longopts, NULL)) != -1) {
		switch (c) {
		case 'p':
			eo.pc2 = optarg;
			break;
		case 'o':
			eo.obj = optarg;
			break;
		case 's':
			eo.seq = optarg;
			break;
		case 'b':
			eo.obstacles = optarg;
			break;
		case 'f':
			eo.fps = strtod(optarg, &end);
			if (end == optarg || *end != '\0' || !(eo.fps > 0 && eo.fps <= 1000))
				return cmd_usage_error("export", "--fps '%s': expected frames a second "
				    "of simulated time, above 0 and at most 1000 (Blender's default "
				    "is 24)", optarg);
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
	if (eo.pc2 == NULL && eo.obj == NULL && eo.seq == NULL && eo.obstacles == NULL) {
		fprintf(stderr, "drape export: expected --pc2 OUT.pc2, --obj REST.obj, "
		    "--obj-seq DIR or --obstacles OUT.obj\n");
		return EXIT_USAGE;
	}
	/* before anything is written */
	if (cmd_output_seeks("export", "--pc2", eo.pc2) != EXIT_OK ||
	    cmd_output_spares("export", "--pc2", eo.pc2, argv[optind],
	    "the replay being exported") != EXIT_OK ||
	    cmd_output_spares("export", "--obj", eo.obj, argv[optind],
	    "the replay being exported") != EXIT_OK ||
	    cmd_output_spares("export", "--obstacles", eo.obstacles, argv[optind],
	    "the replay being exported") != EXIT_OK)
		return EXIT_USAGE;
	if (replay_open(&r, argv[optind], &err) != 0) {
		fprintf(stderr, "drape export: %s\n", err.msg);
		return EXIT_USAGE;
	}
	/* the grid's texture coordinates and the obstacles need the scene; a
	 * PC2 alone (positions only) does not */
	if (eo.obj != NULL || eo.seq != NULL || eo.obstacles != NULL) {
		if (build_scene(&r, argv[optind], &sc, &net, &serr) == 0)
			built = true;
		else if (eo.obstacles != NULL) {
			fprintf(stderr, "drape export: --obstacles: %s\n", serr.msg);
			replay_close(&r);
			return EXIT_USAGE;
		} else
			fprintf(stderr, "drape export: %s; the OBJs go without texture "
			    "coordinates\n", serr.msg);
	}
	/* nor over a mesh the scene reads */
	if (built && (cmd_output_spares_scene("export", "--obstacles", eo.obstacles, &sc,
	    false) != EXIT_OK || cmd_output_spares_scene("export", "--obj", eo.obj, &sc,
	    false) != EXIT_OK)) {
		rc = EXIT_USAGE;
		goto done;
	}
	oo.m = &r.meta;
	if ((built && (oo.uv = grid_uv(&net.cl)) == NULL) ||
	    (oo.x = malloc(3 * (size_t)(r.meta.nodes > 0 ? r.meta.nodes : 1) * sizeof *oo.x)) ==
	    NULL || (oo.normal = malloc(3 * (size_t)(r.meta.nodes > 0 ? r.meta.nodes : 1) *
	    sizeof *oo.normal)) == NULL) {
		fprintf(stderr, "drape export: out of memory\n");
		rc = EXIT_RUNTIME;
		goto done;
	}
	if (eo.seq != NULL && mkdir(eo.seq, 0777) != 0 && errno != EEXIST) {
		fprintf(stderr, "drape export: %s: cannot create: %s\n", eo.seq, strerror(errno));
		rc = EXIT_RUNTIME;
		goto done;
	}
	/* from here, temporary files (the PC2's, each OBJ's) exist: a signal
	 * is let out once they are gone */
	cmd_catch_signals();
	if (r.cut || r.nbad > 0)
		fprintf(stderr, "drape export: %s: %s; exporting the %zu intact frames\n",
		    argv[optind], r.cut ? "cut short" : "some chunks have a bad CRC", r.nframes);
	if ((rc = export(&r, argv[optind], &eo, built ? &sc : NULL, &oo, &err)) != EXIT_OK)
		fprintf(stderr, "drape export: %s: %s\n", argv[optind], err.msg);
done:
	free(oo.uv);
	free(oo.x);
	free(oo.normal);
	if (built) {
		network_free(&net);
		scene_free(&sc);
	}
	replay_close(&r);
	return rc;
}

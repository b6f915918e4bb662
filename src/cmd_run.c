/* cmd_run.c: `drape run` and `drape SCENE`: the TUI on a live run when on a
 * terminal, else a headless run with progress and a summary; a run may
 * record a replay (--record, in the TUI too), and a headless one continue
 * one from a keyframe (--resume). */
#include <errno.h>
#include <getopt.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "config.h"
#include "clock.h"
#include "cmd.h"
#include "obj.h"
#include "record.h"
#include "replay.h"
#include "scene.h"
#include "shadow.h"
#include "source.h"
#include "stepper.h"
#include "tui.h"
#include "units.h"

#define DRAPE_RASTER 0.5e-3	/* m: the shadow's cells, 1/600 of a 30 cm specimen */

/* Set by SIGINT and SIGTERM: the run stops after its step and closes its
 * replay properly. */
static volatile sig_atomic_t interrupted;

static void
on_signal(int sig)
{
	interrupted = sig;
}

static void
catch_signals(void)
{
	struct sigaction sa;

	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sa.sa_flags = SA_RESTART;	/* a replay's write is not cut by the signal */
	sigemptyset(&sa.sa_mask);
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
}

static void
progress(const struct stepper *st, double wall)
{
	double rate = wall > 0 ? st->t / wall : 0;

	fprintf(stderr, "\r  t %.4f / %.4f s   step %ld   %.0f steps/s   ETA %.0f s   ",
	    st->t, st->t_end, st->step, wall > 0 ? (double)st->step / wall : 0,
	    rate > 0 ? (st->t_end - st->t) / rate : 0);
}

/* The spatial hash's statistics of every fill (seed fills it every step;
 * grid when its pairs no longer hold): sums for the means, the largest
 * probe, the histograms added up. */
struct hash_totals {
	long steps;
	double entries, cubes, shared, load, probe_mean;
	int probe_max;
	long hist[HASH_HIST];
};

static bool
uses_hash(const struct stepper *st)
{
	return st->col.active && st->col.pairs &&
	    (st->sc->col.broad == BROAD_SEED || st->sc->col.broad == BROAD_GRID);
}

static void
hash_add(struct hash_totals *ht, const struct hash_stats *hs)
{
	int k;

	ht->steps++;
	ht->entries += (double)hs->entries;
	ht->cubes += (double)hs->cubes;
	ht->shared += (double)hs->shared;
	ht->load += hs->load;
	ht->probe_mean += hs->probe_mean;
	if (hs->probe_max > ht->probe_max)
		ht->probe_max = hs->probe_max;
	for (k = 0; k < HASH_HIST; k++)
		ht->hist[k] += hs->hist[k];
}

static void
hash_summary(const struct hash_totals *ht, long steps)
{
	double n = ht->steps > 0 ? (double)ht->steps : 1;
	int k;

	printf("hash         per fill %.1f items, %.1f cubes (%.1f with >= 2), load %.3f, "
	    "probes mean %.3f max %d; %ld fills in %ld steps\n", ht->entries / n, ht->cubes / n,
	    ht->shared / n, ht->load / n, ht->probe_mean / n, ht->probe_max, ht->steps, steps);
	printf("hash histogram");
	for (k = 0; k < HASH_HIST; k++)
		printf(" %d%s:%ld", k + 1, k + 1 == HASH_HIST ? "+" : "", ht->hist[k]);
	printf(" (cubes by items, all fills)\n");
}

/* The Cusick drape test's coefficient, for a disc-shaped specimen on the
 * scene's first [disc]. */
static void
drape_summary(const struct stepper *st)
{
	const struct scene *sc = st->sc;
	const struct cloth *cl = &st->cl;
	const struct obstacle *disc = NULL;
	double shadow, support, flat, cell;
	size_t o;

	for (o = 0; o < sc->nobstacles && disc == NULL; o++)
		if (sc->obstacles[o].kind == OBSTACLE_DISC)
			disc = &sc->obstacles[o];
	if (disc == NULL || cl->shape != SHAPE_DISC)
		return;
	if (shadow_area(stepper_x(st), cl->tri, cl->ntri, DRAPE_RASTER, &shadow, &cell) != 0) {
		fprintf(stderr, "drape: no drape coefficient: out of memory for its shadow\n");
		return;
	}
	support = V3_PI * disc->radius * disc->radius;
	flat = mesh_area(cl->x0, cl->tri, cl->ntri);
	printf("drape coefficient %.4f (shadow %.6f m2, support disc %.6f m2, flat specimen "
	    "%.6f m2; %.2g mm raster)\n", drape_coefficient(shadow, support, flat), shadow,
	    support, flat, cell * 1e3);
}

static void
summary(const struct stepper *st, double wall, const struct hash_totals *ht)
{
	const struct scene *sc = st->sc;
	const struct cloth *cl = &st->cl;
	struct energy e;
	static const char *dir[2] = { "warp", "weft" };
	int d;

	stepper_energy(st, &e);
	printf("scene        %s (%s)\n", sc->name, sc->path);
	if (cl->shape == SHAPE_SQUARE)
		printf("network      %d x %d nodes", cl->nu, cl->nv);
	else
		printf("network      %s of %d nodes in a %d x %d grid", cloth_shape_name[cl->shape],
		    cl->n, cl->nu, cl->nv);
	printf(", %zu springs, %zu shear corners, %zu bending hinges, %zu triangles\n",
	    cl->nsprings, cl->ncorners, cl->nhinges, cl->ntri);
	for (d = 0; d < 2; d++)
		printf("bending %s %.4g N*m (%s)\n", dir[d], sc->mat.bending[d],
		    sc->mat.bending_derived[d] ? "derived: modulus*thickness^3/12" : "given");
	printf("integrator   %s, dt %.4g s (%s; omega <= %.4g rad/s)\n",
	    integrator_name(sc->integrator), st->dt_set, st->dt_auto ? "auto" : "given",
	    st->omega);
	if (sc->integrator == INTEG_IMPLICIT_EULER)
		printf("steps        %ld (%ld solves, %.1f CG iterations each, %ld unconverged",
		    st->step, st->im.solves, st->im.solves > 0 ?
		    (double)st->im.iters / (double)st->im.solves : 0.0, st->im.unconverged);
	else
		printf("steps        %ld (%ld force evaluations", st->step, st->in.nfev);
	if (sc->integrator == INTEG_DOPRI5)
		printf(", %ld steps rejected", st->in.rejected);
	printf(")\n");
	printf("simulated    %.6g s\n", st->t);
	printf("wall time    %.3f s\n", wall);
	printf("speed        %.4g x real time, %.0f steps/s\n", wall > 0 ? st->t / wall : 0,
	    wall > 0 ? (double)st->step / wall : 0);
	printf("energy       %.6e J (kinetic %.4e, gravity %.4e, stretch %.4e, shear %.4e, "
	    "bend %.4e, load %.4e)\n", energy_total(&e), e.kinetic, e.gravity, e.stretch,
	    e.shear, e.bend, e.load);
	if (st->col.active) {
		const struct collide_stats *c = &st->col.total;
		double steps = st->step > 0 ? (double)st->step : 1;
		int k;

		printf("collisions   broad %s, narrow %s, position %s, self %s, cell %.4g m\n",
		    broad_mode_name[sc->col.broad], narrow_mode_name[sc->col.narrow],
		    position_policy_name[sc->col.position], sc->col.self ? "on" : "off",
		    st->col.cell);
		printf("per step     %.1f node pairs, %.1f vertex-triangle and %.1f edge-edge "
		    "pairs, %.1f narrow tests\n", (double)c->broad.node_pairs / steps,
		    (double)c->broad.vt_pairs / steps, (double)c->broad.ee_pairs / steps,
		    (double)c->narrow_tests / steps);
		printf("contacts     ");
		for (k = 0; k < CONTACT_NTYPES; k++)
			printf("%s%s %ld", k ? ", " : "", contact_type_name[k], c->contacts[k]);
		printf("\n");
		printf("corrections  %ld (%ld put back to step k; at most %d passes in a step; "
		    "%ld steps unresolved)\n", c->corrections, c->frozen, c->passes, c->unresolved);
		if (uses_hash(st))
			hash_summary(ht, st->step);
	}
	drape_summary(st);
	printf("state hash   %016" PRIx64 "\n", stepper_hash(st));
}

static int
write_final(const struct stepper *st, const char *path)
{
	struct drape_err err;

	if (path == NULL)
		return EXIT_OK;
	if (obj_write(path, stepper_x(st), st->cl.n, st->cl.tri, st->cl.ntri, &err) != 0) {
		fprintf(stderr, "drape: %s\n", err.msg);
		return EXIT_RUNTIME;
	}
	return EXIT_OK;
}

/* The front end on the live run, recording into record from the start if
 * not NULL; its messages once the terminal is back. A recording still on
 * at the end (q, a signal) is closed here. */
static int
run_tui(struct stepper *st, const struct tui_opts *opt, const char *record,
    long keyframe_every)
{
	struct source src;
	struct source_live lv;
	struct tui_result res;
	char why[600], *name = NULL;
	const char *rec;
	int rc = EXIT_OK;

	source_live(&src, &lv, st);
	lv.keyframe_every = keyframe_every;
	if (record != NULL && src.record(src.ctx, record, why, sizeof why) != 0) {
		fprintf(stderr, "drape: --record: %s\n", why);
		source_live_free(&lv);
		return EXIT_RUNTIME;
	}
	tui_run(&src, opt, &res);
	if ((rec = src.recording(src.ctx, NULL)) != NULL && (name = strdup(rec)) == NULL)
		rc = EXIT_RUNTIME;
	if (rec != NULL && src.record(src.ctx, NULL, why, sizeof why) != 0) {
		fprintf(stderr, "drape: %s\n", why);
		rc = EXIT_RUNTIME;
	} else if (name != NULL) {
		fprintf(stderr, "drape: recorded %s (to step %ld)\n", name, st->step);
	}
	free(name);
	source_live_free(&lv);
	switch (res.end) {
	case TUI_ERROR:
		fprintf(stderr, "drape: %s\n", res.why);
		return EXIT_RUNTIME;
	case TUI_SIGNAL:
		return 128 + res.signo;
	case TUI_QUIT:
		break;
	}
	if (rc != EXIT_OK)
		return rc;
	if (res.blown_up) {
		fprintf(stderr, "drape: %s: %s\n", st->sc->path, res.why);
		return EXIT_BLOWUP;
	}
	return EXIT_OK;
}

static int
bad_option(const char *opt, const char *val, const char *what)
{
	fprintf(stderr, "drape run: %s '%s': expected %s\n", opt, val, what);
	return EXIT_USAGE;
}

/* FILE or FILE@STEP. */
static int
parse_resume(const char *arg, char **file, long *step)
{
	const char *at = strrchr(arg, '@');
	char *end;
	size_t len = strlen(arg);

	*step = -1;
	if (at != NULL && at[1] != '\0') {
		errno = 0;
		*step = strtol(at + 1, &end, 10);
		if (errno == 0 && *end == '\0' && *step >= 0)
			len = (size_t)(at - arg);
		else
			*step = -1;
	}
	if ((*file = malloc(len + 1)) == NULL)
		return -1;
	memcpy(*file, arg, len);
	(*file)[len] = '\0';
	return 0;
}

/* 1 if both paths name one existing file. */
static int
same_file(const char *a, const char *b)
{
	struct stat sa, sb;

	return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev &&
	    sa.st_ino == sb.st_ino;
}

/* The scene and options of a replay, and the state of its last keyframe
 * at or before the step asked for. */
static int
resume_run(struct stepper *st, struct scene *sc, const char *arg, double until,
    long *keyframe_every)
{
	struct replay rp;
	struct replay_keyframe kf;
	struct drape_err err;
	char *file;
	long step, k;
	int rc = EXIT_USAGE;

	if (parse_resume(arg, &file, &step) != 0) {
		fprintf(stderr, "drape run: out of memory\n");
		return EXIT_RUNTIME;
	}
	if (replay_open(&rp, file, &err) != 0) {
		fprintf(stderr, "drape run: --resume: %s\n", err.msg);
		free(file);
		return EXIT_USAGE;
	}
	if ((k = replay_find_keyframe(&rp, step)) < 0) {
		fprintf(stderr, "drape run: --resume: %s: no intact keyframe at or before step %ld\n",
		    file, step);
		goto out;
	}
	if (replay_read_keyframe(&rp, (size_t)k, &kf, &err) != 0) {
		fprintf(stderr, "drape run: --resume: %s: %s\n", file, err.msg);
		goto out;
	}
	if (scene_parse(sc, rp.meta.path, rp.meta.text, &err) != 0) {
		fprintf(stderr, "drape run: --resume: %s: its scene: %s\n", file, err.msg);
		replay_keyframe_free(&kf);
		goto out;
	}
	sc->duration = until > 0 ? until : rp.meta.duration;
	sc->dt = rp.meta.dt;
	if (rp.meta.integrator < 0 || rp.meta.integrator >= INTEG_COUNT) {
		fprintf(stderr, "drape run: --resume: %s: unknown integrator %d\n", file,
		    rp.meta.integrator);
		goto fail_scene;
	}
	sc->integrator = (enum integrator_kind)rp.meta.integrator;
	if (stepper_init(st, sc, &err) != 0) {
		fprintf(stderr, "drape: %s\n", err.msg);
		goto fail_scene;
	}
	if ((uint32_t)st->cl.n != rp.meta.nodes || st->dt_set != rp.meta.dt_set) {
		fprintf(stderr, "drape run: --resume: %s: its scene now gives %d nodes and dt %.17g, "
		    "expected the recorded %u and %.17g\n", file, st->cl.n, st->dt_set,
		    rp.meta.nodes, rp.meta.dt_set);
		stepper_free(st);
		goto fail_scene;
	}
	memcpy(st->y, kf.y, 6 * (size_t)st->cl.n * sizeof *st->y);
	st->t = kf.t;
	st->step = kf.step;
	st->dt = kf.dt;
	if (stepper_hash(st) != kf.hash) {
		fprintf(stderr, "drape run: --resume: %s: the keyframe at step %ld does not match "
		    "its hash\n", file, kf.step);
		stepper_free(st);
		goto fail_scene;
	}
	if (strcmp(rp.meta.version, PACKAGE_VERSION) != 0)
		fprintf(stderr, "drape run: --resume: %s was recorded by drape %s, this is %s: "
		    "the continuation may differ from the recorded run\n", file, rp.meta.version,
		    PACKAGE_VERSION);
	if (*keyframe_every == 0)
		*keyframe_every = rp.meta.keyframe_every > 0 ? rp.meta.keyframe_every : 0;
	printf("resumed      from %s at step %ld (t = %.9g s)\n", file, kf.step, kf.t);
	replay_keyframe_free(&kf);
	rc = EXIT_OK;
	goto out;
fail_scene:
	replay_keyframe_free(&kf);
	scene_free(sc);
out:
	replay_close(&rp);
	free(file);
	return rc;
}

int
cmd_run(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "headless", no_argument, NULL, 'H' },
		{ "until", required_argument, NULL, 'u' },
		{ "integrator", required_argument, NULL, 'i' },
		{ "dt", required_argument, NULL, 'T' },
		{ "no-color", no_argument, NULL, 'C' },
		{ "delay", required_argument, NULL, 'd' },
		{ "paused", no_argument, NULL, 'p' },
		{ "final-obj", required_argument, NULL, 'o' },
		{ "record", required_argument, NULL, 'r' },
		{ "resume", required_argument, NULL, 'R' },
		{ "keyframe-every", required_argument, NULL, 'k' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *final_obj = NULL, *record = NULL, *resume = NULL;
	double until = -1, dt = -1;
	int integ = -1, c, tty = isatty(STDERR_FILENO), rc = EXIT_OK;
	bool headless = false;
	struct tui_opts topt = { .color = true, .delay = 1, .paused = false };
	long keyframe_every = 0;
	struct scene sc;
	struct stepper st;
	struct drape_err err;
	struct blowup bl;
	struct hash_totals ht;
	struct recorder rec;
	bool recording = false;
	double t0, last;
	char why[200], *end;

	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "+hCd:", longopts, NULL)) != -1) {
		switch (c) {
		case 'H':
			headless = true;
			break;
		case 'C':
			topt.color = false;
			break;
		case 'd':
			if (tui_parse_delay(optarg, &topt.delay) != 0)
				return bad_option("--delay", optarg,
				    "tenths of a second, a whole number from 1 to 100");
			break;
		case 'p':
			topt.paused = true;
			break;
		case 'u':
			if (units_parse(optarg, DIM_TIME, &until, 1, why, sizeof why) != 0 ||
			    !(until > 0))
				return bad_option("--until", optarg, "a time greater than 0");
			break;
		case 'i': {
			enum integrator_kind k;

			if (integrator_from_name(optarg, &k) != 0)
				return bad_option("--integrator", optarg,
				    "rk4, euler, symplectic-euler, rk2 or dopri5");
			integ = (int)k;
			break;
		}
		case 'T':
			if (strcmp(optarg, "auto") == 0)
				dt = 0;
			else if (units_parse(optarg, DIM_TIME, &dt, 1, why, sizeof why) != 0 ||
			    !(dt > 0))
				return bad_option("--dt", optarg, "'auto' or a time greater than 0");
			break;
		case 'o':
			final_obj = optarg;
			break;
		case 'r':
			record = optarg;
			break;
		case 'R':
			resume = optarg;
			break;
		case 'k':
			errno = 0;
			keyframe_every = strtol(optarg, &end, 10);
			if (errno != 0 || end == optarg || *end != '\0' || keyframe_every < 1)
				return bad_option("--keyframe-every", optarg, "a whole number of steps from 1");
			break;
		case 'h':
			usage(stdout);
			return EXIT_OK;
		default:
			return cmd_option_error("run", argv);
		}
	}
	if (resume != NULL) {
		if (optind != argc) {
			fprintf(stderr, "drape run: --resume takes no scene file: the replay holds it\n");
			return EXIT_USAGE;
		}
		if (dt >= 0 || integ >= 0) {
			fprintf(stderr, "drape run: --resume runs with the recorded --dt and "
			    "--integrator; only --until may change\n");
			return EXIT_USAGE;
		}
		if (record != NULL) {
			char *file;
			long step;
			int same;

			if (parse_resume(resume, &file, &step) != 0) {
				fprintf(stderr, "drape run: out of memory\n");
				return EXIT_RUNTIME;
			}
			same = same_file(file, record);
			free(file);
			if (same) {
				fprintf(stderr, "drape run: --record '%s' would overwrite the replay "
				    "being resumed: expected another file\n", record);
				return EXIT_USAGE;
			}
		}
		if ((rc = resume_run(&st, &sc, resume, until, &keyframe_every)) != EXIT_OK)
			return rc;
	} else {
		if (optind != argc - 1) {
			fprintf(stderr, "drape run: expected one scene file\n");
			usage(stderr);
			return EXIT_USAGE;
		}
		if (scene_load(&sc, argv[optind], &err) != 0) {
			fprintf(stderr, "drape: %s\n", err.msg);
			return EXIT_USAGE;
		}
		if (until > 0)
			sc.duration = until;
		if (dt >= 0)
			sc.dt = dt;
		if (integ >= 0)
			sc.integrator = (enum integrator_kind)integ;
		if (stepper_init(&st, &sc, &err) != 0) {
			fprintf(stderr, "drape: %s\n", err.msg);
			scene_free(&sc);
			return EXIT_USAGE;
		}
	}
	/* a resumed run is headless: its summary is the point */
	if (resume != NULL)
		headless = true;
	if (!headless && !(isatty(STDIN_FILENO) && isatty(STDOUT_FILENO))) {
		fprintf(stderr, "drape: not a terminal: running headless\n");
		headless = true;
	}
	if (!headless) {
		rc = run_tui(&st, &topt, record, keyframe_every);
		goto done;
	}
	if (record != NULL) {
		if (keyframe_every == 0)
			keyframe_every = record_default_keyframes(&st);
		if (record_open(&rec, record, &st, keyframe_every, &err) != 0) {
			fprintf(stderr, "drape: --record: %s\n", err.msg);
			stepper_free(&st);
			scene_free(&sc);
			return EXIT_RUNTIME;
		}
		recording = true;
	}

	catch_signals();
	memset(&ht, 0, sizeof ht);
	t0 = last = clock_seconds();
	while (!stepper_done(&st) && !interrupted) {
		if (stepper_step(&st, &bl) != 0) {
			if (tty)
				fputc('\n', stderr);
			fprintf(stderr, "drape: %s: blow-up at step %ld (t = %.6g s)", sc.path,
			    bl.step, bl.t);
			if (bl.node >= 0)
				fprintf(stderr, ": node %d (i %d, j %d)", bl.node, bl.i, bl.j);
			fprintf(stderr, ": %s\n", bl.why);
			rc = EXIT_BLOWUP;
			break;
		}
		if (uses_hash(&st) && st.col.st.broad.rebuilt)
			hash_add(&ht, &st.col.st.broad.hash);
		if (recording && record_step(&rec, &st, &err) != 0) {
			if (tty)
				fputc('\n', stderr);
			fprintf(stderr, "drape: %s; the run stops at step %ld, and the replay holds "
			    "what was written\n", err.msg, st.step);
			rc = EXIT_RUNTIME;
			break;
		}
		if (tty && (st.step & 255) == 0 && clock_seconds() - last > 0.25) {
			last = clock_seconds();
			progress(&st, last - t0);
		}
	}
	if (tty)
		fputs("\r\033[K", stderr);
	if (interrupted && rc == EXIT_OK) {
		fprintf(stderr, "drape: %s at step %ld (t = %.6g s)\n",
		    interrupted == SIGINT ? "interrupted" : "terminated", st.step, st.t);
		rc = EXIT_INTERRUPTED;
	}
	if (recording && record_close(&rec, &st, &err) != 0) {
		fprintf(stderr, "drape: %s\n", err.msg);
		if (rc == EXIT_OK)
			rc = EXIT_RUNTIME;
	}
	summary(&st, clock_seconds() - t0, &ht);
done:
	if (rc == EXIT_OK)
		rc = write_final(&st, final_obj);
	if (fflush(stdout) != 0 && rc == EXIT_OK) {
		perror("drape: stdout");
		rc = EXIT_RUNTIME;
	}
	stepper_free(&st);
	scene_free(&sc);
	return rc;
}

/* cmd_run.c: `drape run` and `drape SCENE`: the TUI on a live run when on a
 * terminal, else a headless run with progress and a summary; a run may
 * record a replay (--record, in the TUI too), and a headless one continue
 * one from a keyframe (--resume). --set changes the scene's values as its
 * file would (override.h). The summary is the run's record (run_record.h),
 * as text (run_summary.c), JSON or CSV. */
#include <errno.h>
#include <math.h>
#include <getopt.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "config.h"
#include "clock.h"
#include "cmd.h"
#include "obj.h"
#include "outfile.h"
#include "record.h"
#include "replay.h"
#include "replay_run.h"
#include "run_record.h"
#include "run_summary.h"
#include "scene.h"
#include "source.h"
#include "stepper.h"
#include "tui.h"
#include "units.h"

/* Set by SIGINT, SIGTERM and SIGHUP (an SSH session dropped): the run
 * gives up the step it is in (the stepper polls this within a step), closes
 * its replay properly and writes what it was asked to. */
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
	sigaction(SIGHUP, &sa, NULL);
	/* a terminal gone with the session: writes fail, they do not kill */
	signal(SIGPIPE, SIG_IGN);
}

struct run_opts {
	const char *scene, *final_obj, *record, *resume;
	const char *trace;	/* --trace: a TSV row per output frame */
	double until, dt;	/* < 0: not given; dt 0: auto */
	int integrator;		/* < 0: not given */
	bool headless;
	struct tui_opts tui;
	long keyframe_every;	/* 0: the default */
	double precision;	/* of recorded frames, m; 0: exact */
	bool events_stored;	/* --events stored: every event, not their digest */
	const char **sets;	/* --set, in order (room for argc of them) */
	size_t nsets;
	enum run_format summary;
};

/* How a headless run's stepping ended, for its record. */
struct run_end {
	enum run_outcome outcome;
	bool failed;
	bool given_up;		/* a signal stopped a step half-way: it was dropped */
	struct step_failure f;
	double wall;
};

static int
bad_option(const char *opt, const char *val, const char *what)
{
	fprintf(stderr, "drape run: %s '%s': expected %s\n", opt, val, what);
	return EXIT_USAGE;
}

/* One option's value into o; an exit status. */
static int
take_option(struct run_opts *o, int c, const char *arg)
{
	char why[200];
	enum integrator_kind k;

	switch (c) {
	case 'H': o->headless = true; break;
	case 'C': o->tui.color = false; break;
	case 'p': o->tui.paused = true; break;
	case 'A': o->tui.glyphs = GLYPHS_ASCII; break;
	case 'U': o->tui.glyphs = GLYPHS_BRAILLE; break;
	case 'B': o->tui.glyphs = GLYPHS_BLOCKS; break;
	case 'o': o->final_obj = arg; break;
	case 'r': o->record = arg; break;
	case 't': o->trace = arg; o->headless = true; break;
	case 'R': o->resume = arg; break;
	case 's': o->sets[o->nsets++] = arg; break;
	case 'S':
		if (strcmp(arg, "text") == 0)
			o->summary = RUN_TEXT;
		else if (strcmp(arg, "json") == 0)
			o->summary = RUN_JSON;
		else if (strcmp(arg, "csv") == 0)
			o->summary = RUN_CSV;
		else
			return bad_option("--summary", arg, "text, json or csv");
		if (o->summary != RUN_TEXT)
			o->headless = true;	/* a record is for a program, not a screen */
		break;
	case 'd':
		if (tui_parse_delay(arg, &o->tui.delay) != 0)
			return bad_option("--delay", arg,
			    "tenths of a second, a whole number from 1 to 100");
		break;
	case 'u':
		if (units_parse(arg, DIM_TIME, &o->until, 1, why, sizeof why) != 0 || !(o->until > 0))
			return bad_option("--until", arg, "a time greater than 0");
		break;
	case 'i':
		if (integrator_from_name(arg, &k) != 0) {
			char names[200];

			integrator_names(names, sizeof names);
			return bad_option("--integrator", arg, names);
		}
		o->integrator = (int)k;
		break;
	case 'T':
		if (strcmp(arg, "auto") == 0)
			o->dt = 0;
		else if (units_parse(arg, DIM_TIME, &o->dt, 1, why, sizeof why) != 0 || !(o->dt > 0))
			return bad_option("--dt", arg, "'auto' or a time greater than 0");
		break;
	case 'k':
		if (cmd_parse_long(arg, 1, (long)SCENE_MAX_STEPS, &o->keyframe_every) != 0)
			return bad_option("--keyframe-every", arg, "a whole number of steps from 1 "
			    "to 1000000000");
		break;
	case 'E':
		if (strcmp(arg, "stored") == 0 || strcmp(arg, "digest") == 0)
			o->events_stored = strcmp(arg, "stored") == 0;
		else
			return bad_option("--events", arg, "stored or digest");
		break;
	case 'P':
		/* a grid step under a nanometre would not fit a frame's
		 * coordinates in 32 bits anyway (replay.c writes those exact) */
		if (units_parse(arg, DIM_LENGTH, &o->precision, 1, why, sizeof why) != 0 ||
		    !(o->precision >= 1e-9) || !(o->precision <= 1))
			return bad_option("--precision", arg, "a length from 1 nm to 1 m");
		break;
	}
	return EXIT_OK;
}

/* Fills o from the command line; an exit status, or -1 after --help. */
static int
parse_options(int argc, char **argv, struct run_opts *o)
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
		{ "trace", required_argument, NULL, 't' },
		{ "resume", required_argument, NULL, 'R' },
		{ "keyframe-every", required_argument, NULL, 'k' },
		{ "precision", required_argument, NULL, 'P' },
		{ "events", required_argument, NULL, 'E' },
		{ "ascii", no_argument, NULL, 'A' },
		{ "unicode", no_argument, NULL, 'U' },
		{ "blocks", no_argument, NULL, 'B' },
		{ "set", required_argument, NULL, 's' },
		{ "summary", required_argument, NULL, 'S' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	int c, rc;

	*o = (struct run_opts){ .until = -1, .dt = -1, .integrator = -1,
	    .tui = { .color = true, .delay = 1, .paused = false } };
	if ((o->sets = calloc((size_t)argc, sizeof *o->sets)) == NULL) {
		fprintf(stderr, "drape run: out of memory\n");
		return EXIT_RUNTIME;
	}
	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "+hCd:", longopts, NULL)) != -1) {
		if (c == 'h') {
			usage(stdout);
			return -1;
		}
		if (c == '?' || c == ':')
			return cmd_option_error("run", argv);
		if ((rc = take_option(o, c, optarg)) != EXIT_OK)
			return rc;
	}
	/* before anything is read or run: a FIFO would block, then get a
	 * replay with no header */
	if (cmd_output_seeks("run", "--record", o->record) != EXIT_OK)
		return EXIT_USAGE;
	if (o->resume == NULL) {
		if (optind != argc - 1) {
			return cmd_usage_error("run", "expected one scene file");
		}
		o->scene = argv[optind];
	} else if (optind != argc) {
		fprintf(stderr, "drape run: --resume takes no scene file: the replay holds it\n");
		return EXIT_USAGE;
	} else if (o->nsets > 0) {
		fprintf(stderr, "drape run: --set '%s': --resume runs the recorded scene; expected "
		    "no --set (its values are in the replay)\n", o->sets[0]);
		return EXIT_USAGE;
	}
	return EXIT_OK;
}

/* FILE or FILE@STEP. */
static int
parse_resume(const char *arg, char **file, long *step)
{
	const char *at = strrchr(arg, '@');
	size_t len = strlen(arg);

	*step = -1;
	if (at != NULL && cmd_parse_long(at + 1, 0, LONG_MAX, step) == 0)
		len = (size_t)(at - arg);
	if ((*file = malloc(len + 1)) == NULL)
		return -1;
	memcpy(*file, arg, len);
	(*file)[len] = '\0';
	return 0;
}

/* The scene and options of a replay, and the run at its last keyframe at
 * or before the step asked for; an exit status. */
static int
open_resumed(const struct run_opts *o, const char *file, long step, struct scene *sc,
    struct stepper **st, long *keyframe_every)
{
	struct replay rp;
	struct stepper_report r;
	struct drape_err err;
	int rc = EXIT_USAGE;

	if (replay_open(&rp, file, &err) != 0) {
		fprintf(stderr, "drape run: --resume: %s\n", err.msg);
		return EXIT_USAGE;
	}
	if (replay_scene(&rp, file, o->until, sc, &err) != 0) {
		fprintf(stderr, "drape run: --resume: %s\n", err.msg);
	} else if (cmd_check_run_length("run", sc, o->until, rp.meta.dt_set, false) != EXIT_OK) {
		scene_free(sc);
	} else if ((*st = replay_resume(&rp, file, sc, step, &err)) == NULL) {
		fprintf(stderr, "drape run: --resume: %s\n", err.msg);
		scene_free(sc);
	} else {
		if (strcmp(rp.meta.version, PACKAGE_VERSION) != 0)
			fprintf(stderr, "drape run: --resume: %s was recorded by drape %s, this is "
			    "%s: the continuation may differ from the recorded run\n", file,
			    rp.meta.version, PACKAGE_VERSION);
		if (*keyframe_every == 0 && rp.meta.keyframe_every > 0)
			*keyframe_every = rp.meta.keyframe_every;
		stepper_report(*st, &r);
		/* on stdout with the text summary; a record is alone there */
		fprintf(o->summary == RUN_TEXT ? stdout : stderr,
		    "resumed      from %s at step %ld (t = %.9g s)\n", file, r.step, r.t);
		rc = EXIT_OK;
	}
	replay_close(&rp);
	return rc;
}

/* The outputs against one input, said as what (cmd_output_spares). */
static int
outputs_spare(const struct run_opts *o, const char *in, const char *what)
{
	if (cmd_output_spares("run", "--record", o->record, in, what) != EXIT_OK ||
	    cmd_output_spares("run", "--final-obj", o->final_obj, in, what) != EXIT_OK ||
	    cmd_output_spares("run", "--trace", o->trace, in, what) != EXIT_OK)
		return EXIT_USAGE;
	return EXIT_OK;
}

/* The outputs against what the scene reads (a resumed run's scene is the
 * replay's text: its file is not read). */
static int
outputs_spare_scene(const struct run_opts *o, const struct scene *sc)
{
	bool file = o->resume == NULL;

	if (cmd_output_spares_scene("run", "--record", o->record, sc, file) != EXIT_OK ||
	    cmd_output_spares_scene("run", "--final-obj", o->final_obj, sc, file) != EXIT_OK ||
	    cmd_output_spares_scene("run", "--trace", o->trace, sc, file) != EXIT_OK)
		return EXIT_USAGE;
	return EXIT_OK;
}

/* --resume: its own checks on the options, then open_resumed. */
static int
resume(struct run_opts *o, struct scene *sc, struct stepper **st)
{
	char *file;
	long step;
	int rc;

	if (o->dt >= 0 || o->integrator >= 0) {
		fprintf(stderr, "drape run: --resume runs with the recorded --dt and --integrator; "
		    "only --until may change\n");
		return EXIT_USAGE;
	}
	if (parse_resume(o->resume, &file, &step) != 0) {
		fprintf(stderr, "drape run: out of memory\n");
		return EXIT_RUNTIME;
	}
	if (outputs_spare(o, file, "the replay being resumed") != EXIT_OK) {
		free(file);
		return EXIT_USAGE;
	}
	rc = open_resumed(o, file, step, sc, st, &o->keyframe_every);
	free(file);
	o->headless = true;	/* a resumed run is headless: its summary is the point */
	return rc;
}

/* The scene with the command line's overrides, and its run; an exit status. */
static int
open_scene(const struct run_opts *o, struct scene *sc, struct stepper **st)
{
	struct drape_err err;

	if (scene_load_set(sc, o->scene, o->sets, o->nsets, &err) != 0) {
		fprintf(stderr, "drape: %s\n", err.msg);
		return EXIT_USAGE;
	}
	if (cmd_check_run_length("run", sc, o->until, o->dt, true) != EXIT_OK) {
		scene_free(sc);
		return EXIT_USAGE;
	}
	if (o->until > 0)
		sc->duration = o->until;
	if (o->dt >= 0)
		sc->dt = o->dt;
	if (o->integrator >= 0)
		sc->integrator = (enum integrator_kind)o->integrator;
	if ((*st = cmd_stepper_new(sc, &err)) == NULL) {
		fprintf(stderr, "drape: %s\n", err.msg);
		scene_free(sc);
		return EXIT_USAGE;
	}
	return EXIT_OK;
}

/* The TUI's end, as an exit status, with its messages once the terminal
 * is back. */
static int
tui_status(const struct tui_result *res, const char *path)
{
	switch (res->end) {
	case TUI_ERROR:
		fprintf(stderr, "drape: %s\n", res->why);
		return EXIT_RUNTIME;
	case TUI_SIGNAL:
		return 128 + res->signo;
	case TUI_QUIT:
		break;
	}
	if (res->blown_up) {
		fprintf(stderr, "drape: %s: %s\n", path, res->why);
		return res->run_error ? EXIT_RUNTIME : EXIT_BLOWUP;
	}
	return EXIT_OK;
}

/* The front end on the live run, recording into o->record from the start
 * if given. A recording still on at the end (q, a signal) is closed here. */
static int
run_tui(struct stepper *st, const struct run_opts *o)
{
	struct source src;
	struct source_live lv;
	struct tui_result res;
	struct stepper_report r;
	char why[600], *name = NULL;
	const char *rec;
	int rc = EXIT_OK, end;

	source_live(&src, &lv, st);
	stepper_set_stop(st, tui_stop_flag());
	lv.keyframe_every = o->keyframe_every;
	lv.precision = o->precision;
	lv.events_stored = o->events_stored;
	if (o->record != NULL && src.record(src.ctx, o->record, why, sizeof why) != 0) {
		fprintf(stderr, "drape: --record: %s\n", why);
		source_live_free(&lv);
		return EXIT_RUNTIME;
	}
	tui_run(&src, &o->tui, &res);
	if ((rec = src.recording(src.ctx, NULL)) != NULL && (name = strdup(rec)) == NULL)
		rc = EXIT_RUNTIME;
	/* the replay's header says how the run ended, if it did early */
	if (rec != NULL)
		record_set_end(&lv.rec, res.blown_up ? (res.run_error ? REPLAY_END_ERROR :
		    REPLAY_END_BLOWUP) : res.end == TUI_SIGNAL ? REPLAY_END_INTERRUPTED :
		    res.end == TUI_ERROR ? REPLAY_END_ERROR : 0);
	if (rec != NULL && src.record(src.ctx, NULL, why, sizeof why) != 0) {
		fprintf(stderr, "drape: %s\n", why);
		rc = EXIT_RUNTIME;
	} else if (name != NULL) {
		stepper_report(st, &r);
		fprintf(stderr, "drape: recorded %s (to step %ld)\n", name, r.step);
	}
	free(name);
	if (lv.rec_failed) {	/* shown in the TUI, and said again once it is gone */
		fprintf(stderr, "drape: %s\n", lv.rec_error);
		rc = EXIT_RUNTIME;
	}
	source_live_free(&lv);
	end = tui_status(&res, stepper_scene(st)->path);
	return end != EXIT_OK ? end : rc;
}

static void
progress(const struct stepper *st, double wall)
{
	struct stepper_report r;
	double rate;

	stepper_report(st, &r);
	rate = wall > 0 ? r.t / wall : 0;
	fprintf(stderr, "\r  t %.4f / %.4f s   step %ld   %.0f steps/s   ETA %.0f s   ", r.t,
	    r.t_end, r.step, wall > 0 ? (double)r.step / wall : 0,
	    rate > 0 ? (r.t_end - r.t) / rate : 0);
}

/* --trace: a row per output frame (and one at the end) of the energy and of
 * the locked nodes (stepper.h, struct lock_stats), the most and the
 * corrections since the row before, for charts of a run's course. */
struct trace {
	struct outfile out;	/* written whole or not at all */
	FILE *f;		/* out's */
	double frame, next;	/* s: the output interval, and the next row's time */
	long k;			/* rows written */
	int most;		/* the most nodes locked at a step since the last row */
	double ke_most;		/* J: and the most kinetic energy they held */
	long corrections;	/* since the last row */
};

static void
trace_row(struct trace *tr, const struct stepper *st)
{
	struct stepper_report r;
	struct energy e;

	stepper_report(st, &r);
	stepper_energy(st, &e);
	fprintf(tr->f, "%.9g\t%ld\t%.6e\t%.6e\t%d\t%.6e\t%d\t%.6e\t%ld\t%ld\n", r.t, r.step,
	    energy_total(&e), e.kinetic, r.locks->now, r.locks->ke_now, tr->most, tr->ke_most,
	    r.locks->run_now, tr->corrections);
	tr->most = 0;
	tr->ke_most = 0;
	tr->corrections = 0;
	tr->k++;
	tr->next = (double)tr->k * tr->frame;
}

/* After each step: the step's figures into the row's, and the row when its
 * frame is reached. */
static void
trace_step(struct trace *tr, const struct stepper *st)
{
	struct stepper_report r;

	stepper_report(st, &r);
	tr->most = r.locks->now > tr->most ? r.locks->now : tr->most;
	tr->ke_most = r.locks->ke_now > tr->ke_most ? r.locks->ke_now : tr->ke_most;
	tr->corrections += r.last->n[STAT_CORRECTIONS];
	if (r.t >= tr->next - 1e-12 * tr->frame || stepper_done(st))
		trace_row(tr, st);
}

/* 0, or -1 after saying why, also in err. */
static int
trace_open(struct trace *tr, const char *path, const struct stepper *st, struct drape_err *err)
{
	struct stepper_report r;

	memset(tr, 0, sizeof *tr);
	if (outfile_open(&tr->out, path, err) != 0) {
		fprintf(stderr, "drape: --trace: %s\n", err->msg);
		return -1;
	}
	tr->f = tr->out.f;
	stepper_report(st, &r);
	tr->frame = 1 / stepper_scene(st)->output_rate;
	tr->k = (long)floor(r.t / tr->frame + 1e-9);
	fprintf(tr->f, "t\tstep\tenergy\tkinetic\tlocked\tlocked_kinetic\tlocked_most"
	    "\tlocked_kinetic_most\tlock_run\tcorrections\n");
	trace_row(tr, st);
	return 0;
}

/* The trace into place, whole; 0, or -1 after saying why, also in err
 * (the file at the path is then as it was: a full disk left it empty). */
static int
trace_close(struct trace *tr, struct drape_err *err)
{
	if (tr->f == NULL)
		return 0;
	tr->f = NULL;
	if (outfile_close(&tr->out, err) != 0) {
		fprintf(stderr, "drape: --trace: %s\n", err->msg);
		return -1;
	}
	return 0;
}

/* An output that failed (the replay, the trace, the final OBJ), for the
 * run's record: an error at the step the run is at, with msg as its
 * reason (cut to fit), unless the run had failed already. */
static void
output_failed(struct run_end *end, const struct stepper *st, const char *msg)
{
	struct stepper_report r;
	size_t n = strlen(msg);

	if (end->failed)
		return;
	stepper_report(st, &r);
	end->f = (struct step_failure){ STEP_ERROR, r.step, r.t, -1, -1, -1, "" };
	if (n >= sizeof end->f.why)
		n = sizeof end->f.why - 1;
	memcpy(end->f.why, msg, n);
	end->f.why[n] = '\0';
	end->failed = true;
	end->outcome = RUN_ERROR;
}

/* The replay's header says how the run ended (replay.h REPLAY_END_*). */
static uint32_t
replay_end_of(enum run_outcome outcome)
{
	switch (outcome) {
	case RUN_COMPLETED: return 0;
	case RUN_BLOWUP: return REPLAY_END_BLOWUP;
	case RUN_ERROR: return REPLAY_END_ERROR;
	case RUN_INTERRUPTED: return REPLAY_END_INTERRUPTED;
	}
	return 0;
}

/* Steps to the end (or a failure, or a signal), recording into rec if not
 * NULL; an exit status, and in *end how it ended. */
static int
step_headless(struct stepper *st, struct recorder *rec, struct trace *tr, bool tty,
    struct run_end *end)
{
	struct step_failure *f = &end->f;
	struct drape_err err;
	struct stepper_report r;
	double t0 = clock_seconds(), last = t0;
	const char *path = stepper_scene(st)->path;

	while (!stepper_done(st) && !interrupted) {
		enum step_status s = stepper_step(st, f);

		if (s == STEP_STOPPED) {
			end->given_up = true;
			break;
		}
		if (s != STEP_OK) {
			if (tty)
				fputc('\n', stderr);
			if (tr != NULL)	/* the last good step, where the runaway ended */
				trace_row(tr, st);
			end->failed = true;
			end->outcome = f->status == STEP_BLOWUP ? RUN_BLOWUP : RUN_ERROR;
			return cmd_step_failed(NULL, path, f);
		}
		if (tr != NULL)
			trace_step(tr, st);
		if (rec != NULL && record_step(rec, st, &err) != 0) {
			stepper_report(st, &r);
			if (tty)
				fputc('\n', stderr);
			fprintf(stderr, "drape: %s; the run stops at step %ld, and the replay holds "
			    "what was written\n", err.msg, r.step);
			output_failed(end, st, err.msg);
			return EXIT_RUNTIME;
		}
		if (tty && clock_seconds() - last > 0.25) {
			last = clock_seconds();
			progress(st, last - t0);
		}
	}
	return EXIT_OK;
}

/* A headless run: progress on a terminal, the replay; how it ended in
 * *end, for the summary. */
static int
run_headless(struct stepper *st, const struct run_opts *o, struct run_end *end)
{
	bool tty = isatty(STDERR_FILENO);
	struct recorder rec;
	struct trace tr = { 0 };
	struct drape_err err;
	struct stepper_report r;
	double t0;
	int rc;

	/* the run's record says an output that could not be opened: no
	 * step was taken, and the outcome is an error, not "completed" */
	if (o->trace != NULL && trace_open(&tr, o->trace, st, &err) != 0) {
		output_failed(end, st, err.msg);
		return EXIT_RUNTIME;
	}
	if (o->record != NULL && record_open(&rec, o->record, st, o->keyframe_every > 0 ?
	    o->keyframe_every : record_default_keyframes(st), o->precision, o->events_stored,
	    &err) != 0) {
		fprintf(stderr, "drape: --record: %s\n", err.msg);
		output_failed(end, st, err.msg);
		if (o->trace != NULL)
			outfile_abort(&tr.out);
		return EXIT_RUNTIME;
	}
	catch_signals();
	stepper_set_stop(st, &interrupted);
	t0 = clock_seconds();
	rc = step_headless(st, o->record != NULL ? &rec : NULL, o->trace != NULL ? &tr : NULL,
	    tty, end);
	if (trace_close(&tr, &err) != 0 && rc == EXIT_OK) {
		output_failed(end, st, err.msg);
		rc = EXIT_RUNTIME;
	}
	if (tty)
		fputs("\r\033[K", stderr);
	if (interrupted && rc == EXIT_OK) {
		stepper_report(st, &r);
		/* say whether a step was under way, so that a user (and test_cli,
		 * without a clock) can tell it was given up, not finished */
		fprintf(stderr, "drape: %s at step %ld (t = %.6g s)%s\n", cmd_signal_word(interrupted),
		    r.step, r.t, end->given_up ? "; the step under way was given up" : "");
		rc = EXIT_INTERRUPTED;
		end->outcome = RUN_INTERRUPTED;
	}
	if (o->record != NULL) {
		record_set_end(&rec, replay_end_of(end->outcome));
		if (record_close(&rec, st, &err) != 0) {
			fprintf(stderr, "drape: %s\n", err.msg);
			if (rc == EXIT_OK) {
				output_failed(end, st, err.msg);
				rc = EXIT_RUNTIME;
			}
		}
	}
	end->wall = clock_seconds() - t0;
	return rc;
}

/* The headless run's summary in its format, rc its exit status so far;
 * the exit status. */
static int
print_summary(const struct stepper *st, const struct run_opts *o, const struct run_end *end,
    int rc)
{
	struct run_record rec;
	int wrc = 0;

	run_record_fill(&rec, st, end->wall);
	rec.sets = o->sets;
	rec.nsets = o->nsets;
	rec.outcome = end->outcome;
	rec.failed = end->failed;
	rec.failure = end->f;
	rec.exit_status = rc;
	switch (o->summary) {
	case RUN_TEXT: run_summary(stdout, &rec); break;
	case RUN_JSON: wrc = run_record_json(stdout, &rec); break;
	case RUN_CSV: wrc = run_record_csv(stdout, &rec, true); break;
	}
	if (wrc != 0 && rc == EXIT_OK)
		rc = EXIT_RUNTIME;	/* said by cmd_run's check of stdout */
	return rc;
}

/* --final-obj; an exit status, said and in err when it fails. */
static int
write_final(const struct stepper *st, const char *path, struct drape_err *err)
{
	const struct cloth *cl = &stepper_network(st)->cl;

	if (path == NULL)
		return EXIT_OK;
	if (obj_write(path, stepper_x(st), cl->n, cl->tri, cl->ntri, err) != 0) {
		fprintf(stderr, "drape: %s\n", err->msg);
		return EXIT_RUNTIME;
	}
	return EXIT_OK;
}

int
cmd_run(int argc, char **argv)
{
	struct run_opts o;
	struct run_end end = { RUN_COMPLETED, false, false, { STEP_OK, 0, 0, -1, -1, -1, "" }, 0 };
	struct scene sc;
	struct stepper *st;
	int rc;

	if ((rc = parse_options(argc, argv, &o)) != EXIT_OK) {
		free(o.sets);
		return rc < 0 ? EXIT_OK : rc;
	}
	rc = o.resume != NULL ? resume(&o, &sc, &st) : open_scene(&o, &sc, &st);
	if (rc != EXIT_OK) {
		free(o.sets);
		return rc;
	}
	/* an output over an input: refused before anything is written */
	if (outputs_spare_scene(&o, &sc) != EXIT_OK) {
		stepper_free(st);
		scene_free(&sc);
		free(o.sets);
		return EXIT_USAGE;
	}
	if (!o.headless && !(isatty(STDIN_FILENO) && isatty(STDOUT_FILENO))) {
		fprintf(stderr, "drape: not a terminal: running headless\n");
		o.headless = true;
	}
	rc = o.headless ? run_headless(st, &o, &end) : run_tui(st, &o);
	/* a run stopped by a signal is at a consistent step too */
	if (rc == EXIT_OK || rc == EXIT_INTERRUPTED || rc > 128) {
		struct drape_err err;
		int w = write_final(st, o.final_obj, &err);

		if (rc == EXIT_OK && w != EXIT_OK) {
			output_failed(&end, st, err.msg);
			rc = w;
		}
	}
	if (o.headless)
		rc = print_summary(st, &o, &end, rc);
	if (fflush(stdout) != 0 && rc == EXIT_OK) {
		perror("drape: stdout");
		rc = EXIT_RUNTIME;
	}
	stepper_free(st);
	scene_free(&sc);
	free(o.sets);
	return rc;
}

/* cmd_setup.c: what the commands that build a run share: the options
 * that change its length checked against the scene's bounds, and the
 * setup of a large cloth shown on a terminal as it goes. */
#include <stdio.h>
#include <unistd.h>

#include "clock.h"
#include "cmd.h"

struct setup_shown {
	double t0;
	long nodes;
};

static void
show_stage(void *ctx, const char *what)
{
	const struct setup_shown *s = ctx;

	fprintf(stderr, "\r  setting up %ld nodes: %s (%.1f s)\033[K", s->nodes, what,
	    clock_seconds() - s->t0);
	fflush(stderr);
}

struct stepper *
cmd_stepper_new(const struct scene *sc, struct drape_err *err)
{
	struct setup_shown s = { clock_seconds(), (long)sc->nu * sc->nv };
	struct stepper_progress pg = { show_stage, &s };
	struct stepper *st;

	if (s.nodes < CMD_SETUP_SHOWN_NODES || !isatty(STDERR_FILENO))
		return stepper_new(sc, err);
	st = stepper_new_progress(sc, &pg, err);
	fputs("\r\033[K", stderr);
	return st;
}

int
cmd_check_run_length(const char *cmd, const struct scene *sc, double until, double dt,
    bool dt_given)
{
	double duration = until > 0 ? until : sc->duration, step = dt > 0 ? dt : sc->dt;

	if (step > 0 && !(scene_steps(duration, step) <= SCENE_MAX_STEPS)) {
		if (dt_given && dt > 0)
			fprintf(stderr, "drape %s: --dt %g s: expected a step that covers the "
			    "duration (%g s) in at most %.0e steps (it takes %.3g)\n", cmd, dt,
			    duration, SCENE_MAX_STEPS, scene_steps(duration, step));
		else if (until > 0)
			fprintf(stderr, "drape %s: --until %g s: expected at most %.0e steps of "
			    "%g s%s (it takes %.3g)\n", cmd, until, SCENE_MAX_STEPS, step,
			    dt > 0 ? ", the recorded step" : "", scene_steps(duration, step));
		else	/* a replay's own duration and step, which its writer kept in bounds */
			fprintf(stderr, "drape %s: the recorded step of %g s takes %.3g steps to "
			    "cover the duration (%g s); expected at most %.0e\n", cmd, step,
			    scene_steps(duration, step), duration, SCENE_MAX_STEPS);
		return EXIT_USAGE;
	}
	if (until > 0 && !(scene_frames(until, sc->output_rate) <= SCENE_MAX_FRAMES)) {
		fprintf(stderr, "drape %s: --until %g s: expected at most %.0e frames at the "
		    "scene's output rate of %g per second (it holds %.3g)\n", cmd, until,
		    SCENE_MAX_FRAMES, sc->output_rate, scene_frames(until, sc->output_rate));
		return EXIT_USAGE;
	}
	return EXIT_OK;
}

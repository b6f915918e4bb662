/* replay_run.c: a replay made into a run again. */
#include "replay_run.h"

int
replay_scene(const struct replay *rp, const char *file, double until, struct scene *sc,
    struct drape_err *err)
{
	const struct replay_meta *m = &rp->meta;
	struct drape_err perr;

	if (m->integrator < 0 || m->integrator >= INTEG_COUNT) {
		err_set(err, "%s: unknown integrator %d", file, m->integrator);
		return -1;
	}
	if (scene_parse_recorded(sc, m->path, m->text, &perr) != 0) {
		err_set(err, "%s: its scene: %s", file, perr.msg);
		return -1;
	}
	sc->duration = until > 0 ? until : m->duration;
	sc->dt = m->dt;
	sc->integrator = (enum integrator_kind)m->integrator;
	return 0;
}

int
replay_network(const struct replay *rp, const char *file, const struct scene *sc,
    struct network *net, struct drape_err *err)
{
	struct drape_err nerr;

	if (network_build(net, sc, &nerr) != 0) {
		err_set(err, "%s: its scene: %s", file, nerr.msg);
		return -1;
	}
	if ((uint32_t)net->cl.n != rp->meta.nodes) {
		err_set(err, "%s: its scene now gives %d nodes, expected the recorded %u", file,
		    net->cl.n, rp->meta.nodes);
		network_free(net);
		return -1;
	}
	return 0;
}

struct stepper *
replay_resume(const struct replay *rp, const char *file, const struct scene *sc, long step,
    struct drape_err *err)
{
	struct replay_keyframe kf;
	struct stepper_state s;
	struct stepper *st;
	struct drape_err kerr;
	long k;
	int rc;

	if ((k = replay_find_keyframe(rp, step)) < 0) {
		if (step < 0)	/* the last one was asked for */
			err_set(err, "%s: no intact keyframe", file);
		else
			err_set(err, "%s: no intact keyframe at or before step %ld", file, step);
		return NULL;
	}
	if (replay_read_keyframe(rp, (size_t)k, &kf, &kerr) != 0) {
		err_set(err, "%s: %s", file, kerr.msg);
		return NULL;
	}
	if ((st = stepper_new(sc, &kerr)) == NULL) {
		err_set(err, "%s: its scene: %s", file, kerr.msg);
		replay_keyframe_free(&kf);
		return NULL;
	}
	s = (struct stepper_state){ .step = kf.step, .t = kf.t, .dt = kf.dt, .y = kf.y,
	    .hist = kf.hist, .hash = kf.hash, .nodes = rp->meta.nodes, .dt_set = rp->meta.dt_set };
	if ((rc = stepper_restore(st, &s, &kerr)) != 0) {
		/* -1: the scene's run is not the recorded one; -2: the keyframe */
		if (rc == -1)
			err_set(err, "%s: %s", file, kerr.msg);
		else
			err_set(err, "%s: the keyframe at step %ld: %s", file, kf.step, kerr.msg);
		goto fail;
	}
	replay_keyframe_free(&kf);
	return st;
fail:
	stepper_free(st);
	replay_keyframe_free(&kf);
	return NULL;
}

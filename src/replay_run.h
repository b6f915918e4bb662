/* replay_run.h: a replay made into a run again, in one place: its scene
 * with the options it was recorded with, its network (for a viewer), and a
 * stepper restored at one of its keyframes (for --resume, and whatever
 * else continues a recorded run). Every check of a replay against the
 * scene it holds is made here. */
#ifndef DRAPE_REPLAY_RUN_H
#define DRAPE_REPLAY_RUN_H

#include "network.h"
#include "replay.h"
#include "scene.h"
#include "stepper.h"

/* The replay's scene, with its recorded duration (or until, if > 0), dt
 * and integrator. 0, or -1 with "FILE: ...: why" in err. */
int replay_scene(const struct replay *rp, const char *file, double until, struct scene *sc,
    struct drape_err *err);

/* The network of sc (from replay_scene), checked against the replay's
 * node count. */
int replay_network(const struct replay *rp, const char *file, const struct scene *sc,
    struct network *net, struct drape_err *err);

/* A stepper on sc (from replay_scene) restored at the replay's last intact
 * keyframe at or before step (< 0: the last of all); stepper_restore checks
 * it against the replay's node count and dt_set and the keyframe's hash.
 * NULL with a message. */
struct stepper *replay_resume(const struct replay *rp, const char *file, const struct scene *sc,
    long step, struct drape_err *err);

#endif

/* cmd.h: the subcommands; each returns the process exit status. */
#ifndef DRAPE_CMD_H
#define DRAPE_CMD_H

#include <signal.h>
#include <stdbool.h>
#include <stdio.h>

#include "scene.h"
#include "stepper.h"

/* Exit statuses shared by every subcommand. */
enum {
	EXIT_OK = 0,
	EXIT_RUNTIME = 1,	/* an output file or stdout could not be written */
	EXIT_USAGE = 2,		/* bad arguments, bad scene or replay */
	EXIT_BLOWUP = 3,	/* the simulation diverged */
	EXIT_FOUND = 4,		/* drape check found intersections */
	EXIT_INTERRUPTED = 130,	/* SIGINT or SIGTERM stopped a run */
};

int cmd_run(int argc, char **argv);
int cmd_ccd(int argc, char **argv);
int cmd_check(int argc, char **argv);
int cmd_snapshot(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_events(int argc, char **argv);
int cmd_export(int argc, char **argv);
int cmd_replay(int argc, char **argv);
int cmd_plot(int argc, char **argv);
void usage(FILE *f);

struct step_failure;
/* Says on stderr that a run of path stopped ("drape CMD: PATH: ...") and
 * returns the exit status it calls for: EXIT_BLOWUP, or EXIT_RUNTIME for an
 * error that is not the simulation's. */
int cmd_step_failed(const char *cmd, const char *path, const struct step_failure *f);

/* After getopt_long returned '?' for command cmd: says on one line which
 * option was unknown or lacked its value, and where the usage is (30 lines
 * of it pushed the one that mattered off the screen); returns EXIT_USAGE. */
int cmd_option_error(const char *cmd, char **argv);

/* "drape CMD: MESSAGE; see drape --help" on stderr; returns EXIT_USAGE.
 * For the command line's mistakes: the usage is one option away. */
int cmd_usage_error(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* The command nearest name (a typing slip away), or NULL. */
const char *cmd_nearest(const char *name, const char *const *names, size_t n);

/* The signal (SIGINT, SIGTERM, SIGHUP) that asked a command which calls
 * cmd_catch_signals to stop, or 0. */
extern volatile sig_atomic_t cmd_signal;
/* From here on those signals set cmd_signal instead of killing the
 * process, so that a command removes its temporary files on the way out
 * (it checks cmd_signal between its writes); a blocking call they
 * interrupt, such as opening a FIFO, fails with EINTR rather than go on. */
void cmd_catch_signals(void);
/* "interrupted", "hung up" or "terminated", for a message. */
const char *cmd_signal_word(int sig);

/* s as a whole number from lo to hi: decimal digits with an optional sign
 * and nothing after them, within long's range (strtol's errno) and the
 * bounds. 0 with *out set, or -1 (*out unchanged). */
int cmd_parse_long(const char *s, long lo, long hi, long *out);

/* An output named by option opt (out NULL: not given) that is the same
 * file as an input (outfile_same) would destroy it: EXIT_USAGE after
 * saying "drape CMD: OPT 'OUT' would overwrite WHAT: expected another
 * file", else EXIT_OK. what names the input ("the replay being
 * exported"). */
int cmd_output_spares(const char *cmd, const char *opt, const char *out, const char *in,
    const char *what);
/* The same against what a scene reads: its file (when scene_file: a
 * resumed run's scene is the replay's text) and its meshes' OBJ files. */
int cmd_output_spares_scene(const char *cmd, const char *opt, const char *out,
    const struct scene *sc, bool scene_file);
/* An output opt that a format writes by seeking back (replays, PC2) and
 * that cannot be (outfile_unseekable): EXIT_USAGE after saying so, else
 * EXIT_OK. */
int cmd_output_seeks(const char *cmd, const char *opt, const char *out);

/* stepper_new, showing the stages of the setup on the standard error
 * when it is a terminal and the cloth has CMD_SETUP_SHOWN_NODES nodes or
 * more (the line is cleared when setup ends). */
#define CMD_SETUP_SHOWN_NODES (1L << 18)
struct stepper *cmd_stepper_new(const struct scene *sc, struct drape_err *err);

/* The run length that --until T (> 0 when given) and a step make of the
 * scene: at most SCENE_MAX_STEPS steps and SCENE_MAX_FRAMES frames. The
 * step is --dt DT when dt_given (DT > 0; 0 or less: the scene's), else dt
 * is a step the user did not give (a replay's recorded one, > 0) or 0 for
 * the scene's. EXIT_OK, or EXIT_USAGE after saying which option is out
 * of range. */
int cmd_check_run_length(const char *cmd, const struct scene *sc, double until, double dt,
    bool dt_given);

#endif

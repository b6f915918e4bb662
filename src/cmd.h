/* cmd.h: the subcommands; each returns the process exit status. */
#ifndef DRAPE_CMD_H
#define DRAPE_CMD_H

#include <stdio.h>

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
void usage(FILE *f);

/* After getopt_long returned '?' for command cmd: says which option was
 * unknown or lacked its value, then the usage; returns EXIT_USAGE. */
int cmd_option_error(const char *cmd, char **argv);

#endif

/* cmd_util.c: what the subcommands share. */
#include <stdio.h>

#include "cmd.h"
#include "stepper.h"

int
cmd_step_failed(const char *cmd, const char *path, const struct step_failure *f)
{
	char msg[600];

	step_failure_format(f, msg, sizeof msg);
	fprintf(stderr, "drape%s%s: %s: %s\n", cmd != NULL ? " " : "", cmd != NULL ? cmd : "", path,
	    msg);
	return f->status == STEP_BLOWUP ? EXIT_BLOWUP : EXIT_RUNTIME;
}

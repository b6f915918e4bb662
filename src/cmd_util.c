/* cmd_util.c: what the subcommands share. */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

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

int
cmd_parse_long(const char *s, long lo, long hi, long *out)
{
	char *end;
	long v;

	/* strtol takes leading white space, which an option should not have */
	if (!(isdigit((unsigned char)s[0]) || ((s[0] == '-' || s[0] == '+') &&
	    isdigit((unsigned char)s[1]))))
		return -1;
	errno = 0;
	v = strtol(s, &end, 10);
	if (errno != 0 || *end != '\0' || v < lo || v > hi)
		return -1;
	*out = v;
	return 0;
}

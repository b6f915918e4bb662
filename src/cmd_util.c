/* cmd_util.c: what the subcommands share. */
#include <ctype.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmd.h"
#include "outfile.h"
#include "stepper.h"

volatile sig_atomic_t cmd_signal;

static void
on_signal(int sig)
{
	cmd_signal = sig;
}

void
cmd_catch_signals(void)
{
	static const int sigs[] = { SIGINT, SIGTERM, SIGHUP };
	struct sigaction sa;
	size_t k;

	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sa.sa_flags = 0;	/* no SA_RESTART: a blocked open gives up */
	sigemptyset(&sa.sa_mask);
	for (k = 0; k < sizeof sigs / sizeof sigs[0]; k++)
		sigaction(sigs[k], &sa, NULL);
}

const char *
cmd_signal_word(int sig)
{
	return sig == SIGINT ? "interrupted" : sig == SIGHUP ? "hung up" : "terminated";
}

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

int
cmd_output_spares(const char *cmd, const char *opt, const char *out, const char *in,
    const char *what)
{
	if (out == NULL || in == NULL || !outfile_same(out, in))
		return EXIT_OK;
	fprintf(stderr, "drape %s: %s '%s' would overwrite %s: expected another file\n", cmd,
	    opt, out, what);
	return EXIT_USAGE;
}

int
cmd_output_spares_scene(const char *cmd, const char *opt, const char *out,
    const struct scene *sc, bool scene_file)
{
	char what[64];
	size_t i;

	if (scene_file && cmd_output_spares(cmd, opt, out, sc->path, "the scene") != EXIT_OK)
		return EXIT_USAGE;
	for (i = 0; i < sc->nobstacles; i++) {
		snprintf(what, sizeof what, "the mesh of [mesh] at line %d", sc->obstacles[i].line);
		if (cmd_output_spares(cmd, opt, out, sc->obstacles[i].file, what) != EXIT_OK)
			return EXIT_USAGE;
	}
	return EXIT_OK;
}

int
cmd_output_seeks(const char *cmd, const char *opt, const char *out)
{
	const char *what = out != NULL ? outfile_unseekable(out) : NULL;

	if (what == NULL)
		return EXIT_OK;
	fprintf(stderr, "drape %s: %s '%s' is %s, which cannot be written in this format: it "
	    "goes back to the file's start at the end; expected a regular file\n", cmd, opt, out,
	    what);
	return EXIT_USAGE;
}

/* cmd_util.c: what the subcommands share. */
#include <ctype.h>
#include <errno.h>
#include <signal.h>
#include <stdarg.h>
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
cmd_usage_error(const char *cmd, const char *fmt, ...)
{
	va_list ap;

	fprintf(stderr, "drape%s%s: ", cmd != NULL ? " " : "", cmd != NULL ? cmd : "");
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputs("; see drape --help\n", stderr);
	return EXIT_USAGE;
}

/* Edits from a to b: insertions, deletions, substitutions and swaps of
 * two neighbours (the optimal string alignment distance); past 3, 3. */
static int
edits(const char *a, const char *b)
{
	enum { MAX = 24 };
	int d[MAX + 1][MAX + 1], i, j;
	int la = (int)strlen(a), lb = (int)strlen(b);

	if (la > MAX || lb > MAX)
		return 3;
	for (i = 0; i <= la; i++)
		d[i][0] = i;
	for (j = 0; j <= lb; j++)
		d[0][j] = j;
	for (i = 1; i <= la; i++)
		for (j = 1; j <= lb; j++) {
			int c = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);

			if (d[i - 1][j] + 1 < c)
				c = d[i - 1][j] + 1;
			if (d[i][j - 1] + 1 < c)
				c = d[i][j - 1] + 1;
			if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
			    d[i - 2][j - 2] + 1 < c)
				c = d[i - 2][j - 2] + 1;
			d[i][j] = c;
		}
	return d[la][lb] < 3 ? d[la][lb] : 3;
}

const char *
cmd_nearest(const char *name, const char *const *names, size_t n)
{
	const char *best = NULL;
	int best_d = 3, d;
	size_t i;

	for (i = 0; i < n; i++)
		/* two slips in a word of 6 letters or more, one in a shorter */
		if ((d = edits(name, names[i])) < best_d && d <= (strlen(names[i]) >= 6 ? 2 : 1)) {
			best = names[i];
			best_d = d;
		}
	return best;
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

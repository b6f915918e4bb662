/* cmd_plot.c: `drape plot FILE.drr [--png OUT.png]`: charts of a recorded
 * run through gnuplot: the energy by kind over time (from the frames and
 * the scene's network: kinetic from the frame differences, exact at
 * keyframes), the contacts of each step by type, and each step's
 * corrections and detect-and-correct passes; as text (gnuplot's dumb
 * terminal) on stdout and, with --png, as a PNG (pngcairo), written whole
 * or not at all. gnuplot is needed at run time only (GNUPLOT names it). */
#include <errno.h>
#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cmd.h"
#include "png.h"
#include "replay.h"
#include "source.h"

/* The gnuplot program: $GNUPLOT, else gnuplot; found on PATH (or given as a
 * path), into buf. */
static bool
find_gnuplot(char *buf, size_t len)
{
	const char *name = getenv("GNUPLOT"), *path = getenv("PATH"), *p;

	if (name == NULL || name[0] == '\0')
		name = "gnuplot";
	if (strchr(name, '/') != NULL) {
		snprintf(buf, len, "%s", name);
		return access(buf, X_OK) == 0;
	}
	for (p = path != NULL ? path : "/usr/bin:/bin"; *p != '\0';) {
		size_t n = strcspn(p, ":");

		snprintf(buf, len, "%.*s/%s", (int)(n > 0 ? n : 1), n > 0 ? p : ".", name);
		if (access(buf, X_OK) == 0)
			return true;
		p += n;
		if (*p == ':')
			p++;
	}
	return false;
}

/* A gnuplot string in single quotes ('' for a quote). */
static void
quoted(FILE *f, const char *s)
{
	fputc('\'', f);
	for (; *s != '\0'; s++) {
		if (*s == '\'')
			fputc('\'', f);
		fputc(*s, f);
	}
	fputc('\'', f);
}

/* The energies of every frame, as the datablock $E. */
static int
energy_block(FILE *f, const char *path, char *title, size_t tlen)
{
	struct source src;
	struct source_replay sr;
	struct source_state s;
	struct source_position p;
	struct drape_err err;
	long last = -1;
	double g0 = 0, e0 = 0;
	bool first = true;

	if (source_replay_open(&src, &sr, path, &err) != 0) {
		fprintf(stderr, "drape plot: %s\n", err.msg);
		return EXIT_USAGE;
	}
	src.state(src.ctx, &s);
	snprintf(title, tlen, "%s", s.sc->name != NULL ? s.sc->name : path);
	fputs("$E << EOD\n", f);
	src.seek(src.ctx, SOURCE_FIRST, 0);
	do {
		src.state(src.ctx, &s);
		src.position(src.ctx, &p);
		if (p.frame_step != last) {
			const struct energy *e = &s.energy;
			double total = energy_total(e);

			if (first) {
				g0 = e->gravity;
				e0 = total;
				first = false;
			}
			fprintf(f, "%.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", s.t, e->kinetic,
			    e->gravity - g0, e->stretch, e->shear, e->bend, total - e0);
			last = p.frame_step;
		}
	} while (src.seek(src.ctx, SOURCE_FRAME_NEXT, 0));
	fputs("EOD\n", f);
	source_replay_close(&sr);
	return EXIT_OK;
}

/* Every step's statistics, as the datablock $S; *n gets how many, *passes
 * the most passes in a step. */
static int
steps_block(FILE *f, const char *path, long *n, long *passes)
{
	struct replay rp;
	struct drape_err err;
	size_t i, j;
	int k;

	*n = 0;
	*passes = 0;
	if (replay_open(&rp, path, &err) != 0) {
		fprintf(stderr, "drape plot: %s\n", err.msg);
		return EXIT_USAGE;
	}
	fputs("$S << EOD\n", f);
	for (i = 0; i < rp.nchunks; i++) {
		struct replay_steps ss;

		/* the statistics alone: a digest chunk's events are not needed */
		if (!replay_is_steps(rp.chunk[i].kind) ||
		    replay_read_step_stats(&rp, i, &ss, &err) != 0)
			continue;
		for (j = 0; j < ss.count; j++) {
			const struct collide_stats *c = &ss.s[j].col;

			fprintf(f, "%.9g", ss.s[j].t);
			for (k = 0; k < CONTACT_NTYPES; k++)
				fprintf(f, " %ld", c->n[STAT_CONTACTS + k]);
			fprintf(f, " %ld %ld\n", c->n[STAT_CORRECTIONS], c->n[STAT_PASSES]);
			if (c->n[STAT_PASSES] > *passes)
				*passes = c->n[STAT_PASSES];
			(*n)++;
		}
		replay_steps_free(&ss);
	}
	fputs("EOD\n", f);
	replay_close(&rp);
	return EXIT_OK;
}

/* The charts, for terminal term (png: into out); passes is the most in a
 * step. */
static void
charts(FILE *f, bool png, const char *out, const char *title, long nsteps, long passes)
{
	int k;

	if (png) {
		fputs("set terminal pngcairo size 1000,1100 font \"Sans,10\"\nset output ", f);
		quoted(f, out);
		fputs("\n", f);
	} else {
		fputs("set terminal dumb size 100,66\nset output\n", f);
	}
	fputs("set multiplot layout 3,1 title ", f);
	quoted(f, title);
	/* the same margins for the three charts, so that their time axes line
	 * up (each key's width would set its own) */
	fputs("\nset lmargin at screen 0.09\nset rmargin at screen 0.72\n", f);
	fputs("set xlabel 't (s)'\nset key outside right top\nset grid\n"
	    "set title 'energy (J)'\n"
	    "plot $E using 1:2 with lines title 'kinetic', "
	    "$E using 1:3 with lines title 'gravity (from t0)', "
	    "$E using 1:4 with lines title 'stretch', "
	    "$E using 1:5 with lines title 'shear', "
	    "$E using 1:6 with lines title 'bending', "
	    "$E using 1:7 with lines title 'total (from t0)'\n", f);
	if (nsteps > 0) {
		fputs("set title 'contacts per step, by type'\nplot ", f);
		for (k = 0; k < CONTACT_NTYPES; k++)
			fprintf(f, "%s$S using 1:%d with lines title '%s'", k > 0 ? ", " : "", 2 + k,
			    contact_type_name[k]);
		/* passes from 0 to one above the most: autoscaled, the most (often
		 * every step's) lay on the chart's top border, unseen */
		fprintf(f, "\nset title 'corrections per step (left) and detect-and-correct "
		    "passes (right)'\n"
		    "set ytics nomirror\nset y2range [0:%ld]\nset y2tics%s\n", passes + 1,
		    passes + 1 <= 10 ? " 1" : "");
		fprintf(f, "plot $S using 1:%d with lines title 'corrections', "
		    "$S using 1:%d axes x1y2 with lines title 'passes'\n"
		    "unset y2tics\nset ytics mirror\n",
		    2 + CONTACT_NTYPES, 3 + CONTACT_NTYPES);
	}
	fputs("unset multiplot\nset output\n", f);
}

/* Runs gnuplot on the script in buf; its output goes to ours. An exit
 * status. */
static int
run_gnuplot(const char *prog, const char *script, size_t len)
{
	int fd[2], st;
	pid_t pid;
	size_t at = 0;
	void (*old)(int);

	if (pipe(fd) != 0) {
		fprintf(stderr, "drape plot: %s\n", strerror(errno));
		return EXIT_RUNTIME;
	}
	fflush(stdout);
	if ((pid = fork()) < 0) {
		fprintf(stderr, "drape plot: %s\n", strerror(errno));
		close(fd[0]);
		close(fd[1]);
		return EXIT_RUNTIME;
	}
	if (pid == 0) {
		close(fd[1]);
		if (dup2(fd[0], STDIN_FILENO) < 0)
			_exit(127);
		close(fd[0]);
		execl(prog, "gnuplot", (char *)NULL);
		_exit(127);
	}
	close(fd[0]);
	old = signal(SIGPIPE, SIG_IGN);
	while (at < len) {
		ssize_t n = write(fd[1], script + at, len - at);

		if (n < 0 && errno == EINTR)
			continue;
		if (n <= 0)
			break;
		at += (size_t)n;
	}
	close(fd[1]);
	signal(SIGPIPE, old);
	while (waitpid(pid, &st, 0) < 0)
		if (errno != EINTR) {
			fprintf(stderr, "drape plot: %s\n", strerror(errno));
			return EXIT_RUNTIME;
		}
	if (!WIFEXITED(st) || WEXITSTATUS(st) != 0 || at < len) {
		fprintf(stderr, "drape plot: %s failed (%s %d)\n", prog,
		    WIFEXITED(st) ? "exit status" : "signal",
		    WIFEXITED(st) ? WEXITSTATUS(st) : WTERMSIG(st));
		return EXIT_RUNTIME;
	}
	return EXIT_OK;
}

/* An empty file of ours in $TMPDIR (else /tmp) for gnuplot's PNG, its
 * name malloc'd; NULL with errno. */
static char *
plot_tmp_name(void)
{
	const char *d = getenv("TMPDIR");
	size_t n;
	char *tmp;
	int fd;

	if (d == NULL || d[0] == '\0')
		d = "/tmp";
	n = strlen(d) + 32;
	if ((tmp = malloc(n)) == NULL)
		return NULL;
	snprintf(tmp, n, "%s/drape-plot-XXXXXX", d);
	if ((fd = mkstemp(tmp)) < 0) {
		free(tmp);
		return NULL;
	}
	close(fd);
	return tmp;
}

/* gnuplot's PNG in tmp, checked whole and written to png (whole or not at
 * all, file_write_atomic). gnuplot exits 0 when its own write fails (a
 * full disk): a file cut short shows it, its IEND chunk gone. An exit
 * status. */
static int
publish(const char *tmp, const char *png)
{
	struct drape_err err;
	unsigned char *buf = NULL;
	size_t len = 0, cap = 0, got;
	FILE *f = fopen(tmp, "rb");
	int rc = EXIT_OK;

	if (f == NULL) {
		fprintf(stderr, "drape plot: %s: %s\n", tmp, strerror(errno));
		return EXIT_RUNTIME;
	}
	do {
		if (len == cap) {
			unsigned char *nb = realloc(buf, cap = cap ? 2 * cap : 1 << 17);

			if (nb == NULL) {
				fprintf(stderr, "drape plot: out of memory\n");
				free(buf);
				fclose(f);
				return EXIT_RUNTIME;
			}
			buf = nb;
		}
		got = fread(buf + len, 1, cap - len, f);
		len += got;
	} while (got > 0);
	if (ferror(f)) {
		fprintf(stderr, "drape plot: %s: read error\n", tmp);
		rc = EXIT_RUNTIME;
	} else if (!png_is_whole(buf, len)) {
		fprintf(stderr, "drape plot: --png %s: gnuplot wrote %zu bytes, not a whole PNG "
		    "(its end, the IEND chunk, is missing: a full disk?); %s is as it was\n", png,
		    len, png);
		rc = EXIT_RUNTIME;
	} else if (file_write_atomic(png, buf, len, &err) != 0) {
		fprintf(stderr, "drape plot: --png %s\n", err.msg);
		rc = EXIT_RUNTIME;
	}
	fclose(f);
	free(buf);
	return rc;
}

int
cmd_plot(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "png", required_argument, NULL, 'o' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *png = NULL, *path;
	char prog[4096], title[300], *script = NULL, *tmp = NULL;
	size_t len = 0;
	long nsteps = 0, passes = 0;
	FILE *f;
	int c, rc;

	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "+h", longopts, NULL)) != -1) {
		switch (c) {
		case 'o':
			if (*optarg == '\0') {
				fprintf(stderr, "drape plot: --png '': expected a file name\n");
				return EXIT_USAGE;
			}
			png = optarg;
			break;
		case 'h':
			usage(stdout);
			return EXIT_OK;
		default:
			return cmd_option_error("plot", argv);
		}
	}
	if (optind != argc - 1) {
		return cmd_usage_error("plot", "expected one replay file");
	}
	path = argv[optind];
	if (cmd_output_spares("plot", "--png", png, path, "the replay being plotted") != EXIT_OK)
		return EXIT_USAGE;
	if (!find_gnuplot(prog, sizeof prog)) {
		fprintf(stderr, "drape plot: gnuplot not found (%s): drape plot draws its charts "
		    "with it (on Debian: apt-get install gnuplot-nox)\n",
		    getenv("GNUPLOT") != NULL && getenv("GNUPLOT")[0] != '\0' ? getenv("GNUPLOT") :
		    "not on PATH");
		return EXIT_RUNTIME;
	}
	if ((f = open_memstream(&script, &len)) == NULL) {
		fprintf(stderr, "drape plot: out of memory\n");
		return EXIT_RUNTIME;
	}
	if ((rc = energy_block(f, path, title, sizeof title)) == EXIT_OK)
		rc = steps_block(f, path, &nsteps, &passes);
	if (rc == EXIT_OK && png != NULL) {
		/* gnuplot draws into a file of ours, checked before it is
		 * published; a signal lets it out only once it is removed */
		cmd_catch_signals();
		if ((tmp = plot_tmp_name()) == NULL) {
			fprintf(stderr, "drape plot: --png %s: a temporary file: %s\n", png,
			    strerror(errno));
			rc = EXIT_RUNTIME;
		} else {
			charts(f, true, tmp, title, nsteps, passes);
		}
	}
	if (rc == EXIT_OK)
		charts(f, false, NULL, title, nsteps, passes);
	if (fclose(f) != 0 && rc == EXIT_OK) {
		fprintf(stderr, "drape plot: out of memory\n");
		rc = EXIT_RUNTIME;
	}
	if (rc == EXIT_OK)
		rc = run_gnuplot(prog, script, len);
	if (tmp != NULL) {
		if (cmd_signal) {
			fprintf(stderr, "drape plot: %s: --png %s not written\n",
			    cmd_signal_word(cmd_signal), png);
			rc = EXIT_INTERRUPTED;
		}
		if (rc == EXIT_OK)
			rc = publish(tmp, png);
		unlink(tmp);
		free(tmp);
	}
	if (rc == EXIT_OK && png != NULL)
		fprintf(stderr, "drape plot: wrote %s\n", png);
	free(script);
	return rc;
}

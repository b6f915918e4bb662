/* main.c: dispatch to a subcommand. */
#include <getopt.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "config.h"
#include "cmd.h"

void
usage(FILE *f)
{
	fputs("usage: drape [--help | --version]\n"
	    "       drape SCENE\n"
	    "       drape run [--headless] [--until T] [--integrator NAME] [--dt DT]\n"
	    "                 [--final-obj FILE] [--record FILE.drr] [--keyframe-every N]\n"
	    "                 [--precision LENGTH] [--events stored|digest]\n"
	    "                 [-C | --no-color] [-d | --delay TENTHS]\n"
	    "                 [--paused] [--ascii | --unicode | --blocks]\n"
	    "                 [--set SECTION.KEY=VALUE]... [--summary text|json|csv]\n"
	    "                 [--trace FILE.tsv] SCENE\n"
	    "       drape run --resume FILE.drr[@STEP] [--until T] [--record FILE.drr]\n"
	    "                 [--precision LENGTH] [--events stored|digest]\n"
	    "                 [--summary text|json|csv]\n"
	    "       drape replay [-C | --no-color] [-d | --delay TENTHS]\n"
	    "                 [--ascii | --unicode | --blocks] FILE.drr\n"
	    "       drape info FILE.drr\n"
	    "       drape events [--node N] [--type T] [--from STEP] [--to STEP] FILE.drr\n"
	    "       drape export [--pc2 OUT.pc2] [--obj REST.obj] [--obj-seq DIR]\n"
	    "                 [--obstacles OUT.obj] [--fps F] FILE.drr\n"
	    "       drape check [--every N] [--set SECTION.KEY=VALUE]... SCENE|OBJ...\n"
	    "       drape snapshot [--step N | --time T] [--view front|side|top|iso]\n"
	    "                 [--size WxH] [--perspective] [--zoom Z] [--centre X,Y,Z]\n"
	    "                 [--frame cloth|scene] [--ascii | --unicode | --blocks]\n"
	    "                 [--set SECTION.KEY=VALUE]... SCENE|FILE.drr\n"
	    "       drape snapshot --png OUT.png [--step N | --time T | --strip T1,T2,...]\n"
	    "                 [--frames K] [--color shade|strain|warp|weft|shear|contact]\n"
	    "                 [--range R] [--size WxH] [--view ...] [--perspective]\n"
	    "                 [--zoom Z] [--centre X,Y,Z] [--frame cloth|scene]\n"
	    "                 [--set SECTION.KEY=VALUE]... SCENE|FILE.drr\n"
	    "       drape plot [--png OUT.png] FILE.drr\n"
	    "       drape ccd [--method seed|ccd] [--inside angle|crossing] [--kind vf|ee] FILE.csv...\n"
	    "\n"
	    "Integrators: rk4 (default), euler, symplectic-euler, rk2, dopri5,\n"
	    "implicit-euler, fast, bdf2.\n"
	    "T and DT are times in seconds, or with a unit (ms, us); DT may be 'auto'.\n"
	    "--set changes a scene's value as its file would (plane#2.friction for the\n"
	    "second [plane]); --summary json|csv prints the run's record for programs.\n"
	    "See drape(1) and drape-scene(5).\n", f);
}

int
cmd_option_error(const char *cmd, char **argv)
{
	const char *arg = argv[optind - 1];

	if (optopt != 0 && strncmp(arg, "--", 2) == 0)
		return cmd_usage_error(cmd, "option '%s' needs a value", arg);
	if (optopt != 0)
		return cmd_usage_error(cmd, "option '-%c' needs a value or is unknown", optopt);
	return cmd_usage_error(cmd, "unknown option '%s'", arg);
}

/* The subcommands, by name; `drape SCENE` is `drape run SCENE`. */
static const struct command {
	const char *name;
	int (*run)(int argc, char **argv);
} commands[] = {
	{ "run", cmd_run },
	{ "replay", cmd_replay },
	{ "info", cmd_info },
	{ "events", cmd_events },
	{ "export", cmd_export },
	{ "snapshot", cmd_snapshot },
	{ "check", cmd_check },
	{ "ccd", cmd_ccd },
	{ "plot", cmd_plot },
};
#define NCOMMANDS (sizeof commands / sizeof commands[0])

/* `drape SCENE`: a word that is not a command is a scene if it is a file
 * or looks like a path ("a.scene", "dir/x"); else a mistyped command,
 * which "cannot open" would not have said. */
static bool
names_a_file(const char *arg)
{
	return access(arg, F_OK) == 0 || strchr(arg, '/') != NULL || strchr(arg, '.') != NULL;
}

int
main(int argc, char **argv)
{
	size_t i;

	if (argc < 2) {
		usage(stderr);
		return EXIT_USAGE;
	}
	if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
		usage(stdout);
		return EXIT_OK;
	}
	if (strcmp(argv[1], "--version") == 0 || strcmp(argv[1], "-V") == 0) {
		printf("drape %s\n", PACKAGE_VERSION);
		return EXIT_OK;
	}
	for (i = 0; i < NCOMMANDS; i++)
		if (strcmp(argv[1], commands[i].name) == 0)
			return commands[i].run(argc - 1, argv + 1);
	if (argv[1][0] == '-')
		return cmd_usage_error(NULL, "unknown option '%s'", argv[1]);
	if (!names_a_file(argv[1])) {
		const char *names[NCOMMANDS], *near;

		for (i = 0; i < NCOMMANDS; i++)
			names[i] = commands[i].name;
		if ((near = cmd_nearest(argv[1], names, NCOMMANDS)) != NULL) {
			fprintf(stderr, "drape: unknown command '%s'; did you mean '%s'? See drape "
			    "--help\n", argv[1], near);
			return EXIT_USAGE;
		}
		return cmd_usage_error(NULL, "'%s' is neither a command nor a scene file",
		    argv[1]);
	}
	return cmd_run(argc, argv);
}

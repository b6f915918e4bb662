/* main.c: dispatch to a subcommand. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

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
	    "       drape export [--pc2 OUT.pc2] [--obj REST.obj] [--obj-seq DIR] FILE.drr\n"
	    "       drape check [--every N] [--set SECTION.KEY=VALUE]... SCENE|OBJ...\n"
	    "       drape snapshot [--step N | --time T] [--view front|side|top|iso]\n"
	    "                 [--size WxH] [--perspective] [--zoom Z] [--centre X,Y,Z]\n"
	    "                 [--ascii | --unicode | --blocks] [--set SECTION.KEY=VALUE]...\n"
	    "                 SCENE|FILE.drr\n"
	    "       drape snapshot --png OUT.png [--step N | --time T | --strip T1,T2,...]\n"
	    "                 [--frames K] [--color shade|strain|warp|weft|shear|contact]\n"
	    "                 [--range R] [--size WxH] [--view ...] [--perspective]\n"
	    "                 [--zoom Z] [--centre X,Y,Z] [--set SECTION.KEY=VALUE]...\n"
	    "                 SCENE|FILE.drr\n"
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
	if (optopt != 0)
		fprintf(stderr, "drape %s: option '-%c' needs a value or is unknown\n", cmd, optopt);
	else
		fprintf(stderr, "drape %s: unknown option '%s'\n", cmd, argv[optind - 1]);
	usage(stderr);
	return EXIT_USAGE;
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
	for (i = 0; i < sizeof commands / sizeof commands[0]; i++)
		if (strcmp(argv[1], commands[i].name) == 0)
			return commands[i].run(argc - 1, argv + 1);
	if (argv[1][0] == '-') {
		fprintf(stderr, "drape: unknown option '%s'\n", argv[1]);
		usage(stderr);
		return EXIT_USAGE;
	}
	return cmd_run(argc, argv);
}

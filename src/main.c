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
	    "                 [-C | --no-color] [-d | --delay TENTHS] [--paused] SCENE\n"
	    "       drape run --resume FILE.drr[@STEP] [--until T] [--record FILE.drr]\n"
	    "       drape replay [-C | --no-color] [-d | --delay TENTHS] FILE.drr\n"
	    "       drape info FILE.drr\n"
	    "       drape events [--node N] [--type T] [--from STEP] [--to STEP] FILE.drr\n"
	    "       drape export [--pc2 OUT.pc2] [--obj REST.obj] [--obj-seq DIR] FILE.drr\n"
	    "       drape check [--every N] SCENE|OBJ...\n"
	    "       drape snapshot [--step N] [--view front|side|top|iso] [--size WxH]\n"
	    "                 [--perspective] SCENE|FILE.drr\n"
	    "       drape ccd [--method seed|ccd] [--inside angle|crossing] [--kind vf|ee] FILE.csv...\n"
	    "\n"
	    "Integrators: rk4 (default), euler, symplectic-euler, rk2, dopri5, implicit-euler.\n"
	    "T and DT are times in seconds, or with a unit (ms, us); DT may be 'auto'.\n"
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

int
main(int argc, char **argv)
{
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
	if (strcmp(argv[1], "run") == 0)
		return cmd_run(argc - 1, argv + 1);
	if (strcmp(argv[1], "ccd") == 0)
		return cmd_ccd(argc - 1, argv + 1);
	if (strcmp(argv[1], "check") == 0)
		return cmd_check(argc - 1, argv + 1);
	if (strcmp(argv[1], "snapshot") == 0)
		return cmd_snapshot(argc - 1, argv + 1);
	if (strcmp(argv[1], "replay") == 0)
		return cmd_replay(argc - 1, argv + 1);
	if (strcmp(argv[1], "info") == 0)
		return cmd_info(argc - 1, argv + 1);
	if (strcmp(argv[1], "events") == 0)
		return cmd_events(argc - 1, argv + 1);
	if (strcmp(argv[1], "export") == 0)
		return cmd_export(argc - 1, argv + 1);
	if (argv[1][0] == '-') {
		fprintf(stderr, "drape: unknown option '%s'\n", argv[1]);
		usage(stderr);
		return EXIT_USAGE;
	}
	/* `drape SCENE` is `drape run SCENE`: the TUI on a terminal. */
	return cmd_run(argc, argv);
}

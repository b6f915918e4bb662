/* cmd_replay.c: `drape replay [-C] [-d TENTHS] FILE.drr`: the terminal
 * interface on a replay, paused at its first frame. There is nothing to
 * run headless: off a terminal it says so and points to drape info. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "cmd.h"
#include "source.h"
#include "tui.h"

int
cmd_replay(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "no-color", no_argument, NULL, 'C' },
		{ "delay", required_argument, NULL, 'd' },
		{ "ascii", no_argument, NULL, 'A' },
		{ "unicode", no_argument, NULL, 'U' },
		{ "blocks", no_argument, NULL, 'B' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct tui_opts topt = { .color = true, .delay = 1, .paused = true };
	struct source src;
	struct source_replay sr;
	struct tui_result res;
	struct drape_err err;
	int c, rc = EXIT_OK;

	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "+hCd:", longopts, NULL)) != -1) {
		switch (c) {
		case 'C':
			topt.color = false;
			break;
		case 'A':
			topt.glyphs = GLYPHS_ASCII;
			break;
		case 'U':
			topt.glyphs = GLYPHS_BRAILLE;
			break;
		case 'B':
			topt.glyphs = GLYPHS_BLOCKS;
			break;
		case 'd':
			if (tui_parse_delay(optarg, &topt.delay) != 0) {
				fprintf(stderr, "drape replay: --delay '%s': expected tenths of a second, "
				    "a whole number from 1 to 100\n", optarg);
				return EXIT_USAGE;
			}
			break;
		case 'h':
			usage(stdout);
			return EXIT_OK;
		default:
			return cmd_option_error("replay", argv);
		}
	}
	if (optind != argc - 1) {
		return cmd_usage_error("replay", "expected one replay file");
	}
	if (!(isatty(STDIN_FILENO) && isatty(STDOUT_FILENO))) {
		fprintf(stderr, "drape replay: not a terminal: a replay plays only in the terminal "
		    "interface (try drape info %s, drape events or drape export)\n", argv[optind]);
		return EXIT_USAGE;
	}
	if (source_replay_open(&src, &sr, argv[optind], &err) != 0) {
		fprintf(stderr, "drape replay: %s\n", err.msg);
		return EXIT_USAGE;
	}
	tui_run(&src, &topt, &res);
	switch (res.end) {
	case TUI_ERROR:
		fprintf(stderr, "drape replay: %s\n", res.why);
		rc = EXIT_RUNTIME;
		break;
	case TUI_SIGNAL:
		rc = 128 + res.signo;
		break;
	case TUI_QUIT:
		break;
	}
	if (sr.nskipped > 0 || sr.rp.nbad > 0 || sr.rp.cut)
		fprintf(stderr, "drape replay: %s: showed what was intact (%zu chunks damaged or "
		    "undecodable%s)\n", argv[optind], sr.nskipped + sr.rp.nbad,
		    sr.rp.cut ? ", the file cut short" : "");
	source_replay_close(&sr);
	return rc;
}

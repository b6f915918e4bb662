/* cmd_events.c: `drape events FILE [--node N] [--type T] [--from S] [--to S]`:
 * a replay's collision events, one per line, tab-separated, for awk and sort.
 * Those a replay holds as a digest are recomputed (replay_events.h); steps
 * whose events are unavailable are named on stderr, and the exit status
 * is then 1, the other steps' events listed all the same. */
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "cmd.h"
#include "replay.h"
#include "replay_events.h"

static int
bad(const char *opt, const char *val, const char *what)
{
	fprintf(stderr, "drape events: %s '%s': expected %s\n", opt, val, what);
	return EXIT_USAGE;
}

/* Steps whose events are unavailable, said once for each run of chunks
 * with the same reason (a scene that does not run here is every chunk's). */
struct gap {
	bool open;
	unsigned long first, last;
	char why[512];
};

static void
gap_say(struct gap *g, const char *file)
{
	if (g->open)
		fprintf(stderr, "drape events: %s: the events of steps %lu to %lu are unavailable: "
		    "%s\n", file, g->first, g->last, g->why);
	g->open = false;
}

static void
gap_add(struct gap *g, const char *file, const struct replay_chunk *c, const char *why)
{
	unsigned long first = (unsigned long)step_shown((long)c->first_step),
	    last = first + c->count - 1;

	if (g->open && first == g->last + 1 && strcmp(why, g->why) == 0) {
		g->last = last;
		return;
	}
	gap_say(g, file);
	*g = (struct gap){ .open = true, .first = first, .last = last };
	snprintf(g->why, sizeof g->why, "%s", why);
}

int
cmd_events(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "node", required_argument, NULL, 'n' },
		{ "type", required_argument, NULL, 't' },
		{ "from", required_argument, NULL, 'f' },
		{ "to", required_argument, NULL, 'T' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	long node = -1, from = 0, to = LONG_MAX;
	int type = -1, c, k, rc = EXIT_OK;
	struct replay r;
	struct replay_events re;
	struct gap gap = { .open = false };
	struct replay_steps ss;
	struct drape_err err;
	size_t i, e;

	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "h", longopts, NULL)) != -1) {
		switch (c) {
		case 'n':
			if (cmd_parse_long(optarg, 0, INT_MAX, &node) != 0)
				return bad("--node", optarg, "a node number from 0");
			break;
		case 't':
			for (k = 0; k < CONTACT_NTYPES; k++)
				if (strcmp(optarg, contact_type_name[k]) == 0)
					type = k;
			if (type < 0)
				return bad("--type", optarg, "node-node, node-edge, node-face, "
				    "edge-edge or obstacle");
			break;
		case 'f':
			if (cmd_parse_long(optarg, 0, LONG_MAX, &from) != 0)
				return bad("--from", optarg, "a step number from 0");
			break;
		case 'T':
			if (cmd_parse_long(optarg, 0, LONG_MAX, &to) != 0)
				return bad("--to", optarg, "a step number from 0");
			break;
		case 'h':
			usage(stdout);
			return EXIT_OK;
		default:
			return cmd_option_error("events", argv);
		}
	}
	if (optind != argc - 1) {
		return cmd_usage_error("events", "expected one replay file");
	}
	if (replay_open(&r, argv[optind], &err) != 0) {
		fprintf(stderr, "drape events: %s\n", err.msg);
		return EXIT_USAGE;
	}
	if (node >= (long)r.meta.nodes) {
		fprintf(stderr, "drape events: --node %ld: expected a node below %u\n", node,
		    r.meta.nodes);
		replay_close(&r);
		return EXIT_USAGE;
	}
	if (r.cut || r.nbad > 0)
		fprintf(stderr, "drape events: %s: %zu whole chunks%s%s; listing what they hold\n",
		    argv[optind], r.nchunks, r.cut ? ", cut short" : "",
		    r.nbad > 0 ? ", some with a bad CRC" : "");
	replay_events_init(&re, &r, argv[optind]);
	printf("step\tnode\ttype\tother\tobstacle\tqx\tqy\tqz\tnx\tny\tnz\tvn_before\tvn_after\n");
	for (i = 0; i < r.nchunks; i++) {
		const struct replay_chunk *ch = &r.chunk[i];
		int got;

		/* the chunk's steps as shown: first_step + 1 to first_step + count */
		if (!replay_is_steps(ch->kind) || step_shown((long)ch->first_step) > to ||
		    (long)(ch->first_step + ch->count) < from)
			continue;
		if ((got = replay_events_read(&re, i, &ss, &err)) != 0) {
			if (got == REPLAY_EVENTS_UNAVAILABLE) {
				gap_add(&gap, argv[optind], ch, re.why);
				replay_steps_free(&ss);
				rc = EXIT_RUNTIME;
			} else
				fprintf(stderr, "drape events: %s: %s; skipped\n", argv[optind],
				    err.msg);
			continue;
		}
		for (e = 0; e < ss.nev; e++) {
			const struct contact_event *ev = &ss.ev[e];

			if (step_shown(ev->step) < from || step_shown(ev->step) > to ||
			    (node >= 0 && ev->node != node) ||
			    (type >= 0 && (int)ev->type != type))
				continue;
			printf("%ld\t%d\t%s\t%d\t%d\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t"
			    "%.17g\t%.17g\n", step_shown(ev->step), ev->node, contact_type_name[ev->type],
			    ev->other, ev->obstacle, ev->q.x, ev->q.y, ev->q.z,
			    ev->n.x, ev->n.y, ev->n.z, ev->vn_before, ev->vn_after);
		}
		replay_steps_free(&ss);
	}
	gap_say(&gap, argv[optind]);
	replay_events_free(&re);
	replay_close(&r);
	if (fflush(stdout) != 0 || ferror(stdout)) {
		perror("drape events: stdout");
		rc = EXIT_RUNTIME;
	}
	return rc;
}

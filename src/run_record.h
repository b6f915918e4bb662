/* run_record.h: what a headless run ends with, gathered once: the figures
 * of its summary, how it ended and its exit status. run_summary.c prints
 * it for people; run_record.c as one JSON object or one CSV row (with its
 * header), under field names that stay (drape(1) lists them). The
 * collision counters come from the statistics table (stats.h), so a new
 * counter is a new field without a line here. */
#ifndef DRAPE_RUN_RECORD_H
#define DRAPE_RUN_RECORD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "forces.h"
#include "stepper.h"

/* How the stepping ended. */
enum run_outcome {
	RUN_COMPLETED,		/* to its end time */
	RUN_BLOWUP,		/* the simulation diverged (exit 3) */
	RUN_ERROR,		/* it could not go on: memory, the broad phase, the replay (exit 1) */
	RUN_INTERRUPTED,	/* SIGINT, SIGTERM or SIGHUP (exit 130) */
};

extern const char *const run_outcome_name[];

enum run_format { RUN_TEXT, RUN_JSON, RUN_CSV };

struct run_record {
	/* from the run, by run_record_fill */
	const struct scene *sc;
	const struct cloth *cl;
	struct stepper_report r;
	struct energy e;
	double wall;		/* s */
	uint64_t hash;
	/* the Cusick drape test, for a disc-shaped cloth over a [disc] */
	int drape;		/* 0: not one; 1: computed; -1: out of memory for the shadow */
	double dc, shadow, support, flat, raster;
	int folds;		/* the outline's lobes (shadow.h), -1: not counted */

	/* from the caller */
	const char *const *sets;	/* the --set overrides as given */
	size_t nsets;
	enum run_outcome outcome;
	bool failed;		/* failure holds the failed step (blow-up or error) */
	struct step_failure failure;
	int exit_status;
};

/* Fills rec from a run that has stopped, wall its wall time in seconds;
 * the caller's part is left as a completed run with no overrides. */
void run_record_fill(struct run_record *rec, const struct stepper *st, double wall);

/* One JSON object and a newline. 0, or -1 when f could not be written. */
int run_record_json(FILE *f, const struct run_record *rec);
/* The CSV header line (with header) and one row. 0 or -1. */
int run_record_csv(FILE *f, const struct run_record *rec, bool header);

#endif

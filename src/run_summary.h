/* run_summary.h: what a headless run prints at its end, for people: the
 * network, the integrator's counts, time and speed, energy by kind, the
 * collision statistics, the drape coefficient of a Cusick test, the state
 * hash; from the run's record (run_record.h), which --summary json and csv
 * print instead. */
#ifndef DRAPE_RUN_SUMMARY_H
#define DRAPE_RUN_SUMMARY_H

#include <stdio.h>

#include "run_record.h"

void run_summary(FILE *f, const struct run_record *rec);

#endif

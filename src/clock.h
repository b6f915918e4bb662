/* clock.h: seconds on the monotonic clock, for wall times and rate caps
 * (never for anything a run's result depends on). */
#ifndef DRAPE_CLOCK_H
#define DRAPE_CLOCK_H

#include <time.h>

static inline double
clock_seconds(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#endif

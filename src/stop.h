/* stop.h: the stop flag a signal sets, as the long loops of a step poll
 * it: so that a signal is honoured within a step, each loop looks at the
 * flag once every STOP_POLL_EVERY items, and one rule says how. */
#ifndef DRAPE_STOP_H
#define DRAPE_STOP_H

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>

/* Items between two looks: a look is a load and a branch, and the
 * heaviest item polled (a box's fill of the hash, a tree query) takes
 * microseconds, so a stop waits a millisecond at most. */
#define STOP_POLL_EVERY 256

/* The flag is set (NULL: never). */
static inline bool
stop_set(const volatile sig_atomic_t *flag)
{
	return flag != NULL && *flag;
}

/* Item i of a loop looks at the flag, and it is set. */
static inline bool
stop_poll(size_t i, const volatile sig_atomic_t *flag)
{
	return i % STOP_POLL_EVERY == 0 && stop_set(flag);
}

#endif

/* pace.c: a multiple of real time, and the simulated time it asks for. */
#include <math.h>
#include <stdio.h>

#include "pace.h"

void
pace_init(struct pace *p, double wall, double t)
{
	p->log2 = 0;
	p->flat_out = false;
	pace_anchor(p, wall, t);
}

void
pace_anchor(struct pace *p, double wall, double t)
{
	p->anchor_wall = wall;
	p->anchor_t = t;
}

double
pace_factor(const struct pace *p)
{
	return p->flat_out ? 0 : ldexp(1, p->log2);
}

double
pace_target(const struct pace *p, double wall)
{
	if (p->flat_out)
		return INFINITY;
	return p->anchor_t + pace_factor(p) * (wall - p->anchor_wall);
}

void
pace_keep_up(struct pace *p, double wall, double t, double slack)
{
	if (!p->flat_out && pace_target(p, wall) - t > pace_factor(p) * slack)
		pace_anchor(p, wall, t);
}

bool
pace_change(struct pace *p, int dir)
{
	if (p->flat_out) {	/* back to the multiple, whichever way */
		p->flat_out = false;
		return true;
	}
	if ((dir > 0 && p->log2 >= PACE_MAX_LOG2) || (dir < 0 && p->log2 <= PACE_MIN_LOG2))
		return false;
	p->log2 += dir > 0 ? 1 : -1;
	return true;
}

void
pace_toggle_flat_out(struct pace *p)
{
	p->flat_out = !p->flat_out;
}

void
pace_label(const struct pace *p, char *buf, size_t len)
{
	if (p->flat_out)
		snprintf(buf, len, "max");
	else if (p->log2 >= 0)
		snprintf(buf, len, "%ldx", 1L << p->log2);
	else
		snprintf(buf, len, "1/%ldx", 1L << -p->log2);
}

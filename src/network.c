/* network.c: a scene's network, built in the order its parts need. */
#include <string.h>

#include "network.h"

/* Whether the method steps the forces explicitly (the stepper's
 * integrate.c), and so needs their fold limiter. */
static int
explicit_method(enum integrator_kind k)
{
	switch (k) {
	case INTEG_RK4:
	case INTEG_EULER:
	case INTEG_SYMPLECTIC_EULER:
	case INTEG_RK2:
	case INTEG_DOPRI5:
		return 1;
	default:
		return 0;
	}
}

int
network_build(struct network *net, const struct scene *sc, struct drape_err *err)
{
	memset(net, 0, sizeof *net);
	if (cloth_build(&net->cl, sc, err) != 0)
		return -1;
	if (prescribed_build(&net->pr, sc, &net->cl, err) != 0 ||
	    forces_init(&net->fo, sc, &net->cl, err) != 0) {
		network_free(net);
		return -1;
	}
	cloth_clamp_hinges(&net->cl, net->pr.held);
	if (explicit_method(sc->integrator))	/* after the clamps: their stiffness counts */
		net->fo.fold = forces_explicit_fold(&net->cl);
	return 0;
}

void
network_free(struct network *net)
{
	forces_free(&net->fo);
	prescribed_free(&net->pr);
	cloth_free(&net->cl);
	memset(net, 0, sizeof *net);
}

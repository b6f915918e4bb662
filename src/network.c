/* network.c: a scene's network, built in the order its parts need. */
#include <string.h>

#include "network.h"

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
	/* the explicit methods' fold limiter, after the clamps: their
	 * stiffness counts */
	if (!integrator_is_implicit(sc->integrator))
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

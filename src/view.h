/* view.h: what the view shows of a scene: its obstacles (a plane as a floor
 * grid), the cloth, and marks on the nodes in contact this step and on the
 * selected node, drawn into a raster through a camera. */
#ifndef DRAPE_VIEW_H
#define DRAPE_VIEW_H

#include <stddef.h>

#include "event.h"
#include "raster.h"
#include "scene.h"

#define VIEW_MARK_CONTACT 'o'
#define VIEW_MARK_SELECTED 'X'

/* The sphere a camera frames: the cloth at x (n nodes) and the scene's
 * bounded obstacles, and where the cloth would land on its planes. */
void view_frame(const struct scene *sc, const double *x, int n, vec3 *target, double *radius);

/* The box of the cloth at x (n nodes), grown into *lo, *hi (start them
 * at +infinity and -infinity), for view_frame_cloth over one frame or
 * many. */
void view_cloth_box(const double *x, int n, vec3 *lo, vec3 *hi);

/* The sphere that frames the cloth in that box, a tenth larger and at
 * least a tenth of the scene's (view_frame of the cloth as it starts:
 * a pile is not blown up past what is around it; a one-node cloth gets
 * the scene's), for a view that follows the cloth (at the strip's end the
 * scene's framing showed its pile as a speck). */
void view_frame_cloth(const struct scene *sc, const double *x0, int n, vec3 lo, vec3 hi,
    vec3 *target, double *radius);

/* Clears r and draws the scene with the cloth at x (n nodes, ntri
 * triangles in tri); ev (nev events) marks the nodes in contact, selected
 * (or -1) the selected node. */
void view_draw(struct raster *r, const struct camera *cam, const struct scene *sc,
    const double *x, int n, const int *tri, size_t ntri,
    const struct contact_event *ev, size_t nev, int selected);

#endif

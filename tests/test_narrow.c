/* test_narrow.c: the chapter's node-triangle test (eq. 1-10) and its
 * response (eq. 11-17) on cases with known answers. */
#include "testutil.h"

#include "narrow.h"
#include "response.h"

/* A horizontal triangle at y = 0 with its normal up. */
static const vec3 A = { 0, 0, 0 }, B = { 0, 0, 1 }, C = { 1, 0, 0 };

static void
test_seed_through_face(void **state)
{
	enum inside_test how;

	(void)state;
	for (how = INSIDE_ANGLE; how <= INSIDE_CROSSING; how++) {
		struct seed_hit h;

		assert_int_equal(narrow_seed_segment(v3(0.25, 0.5, 0.25), v3(0.25, -0.5, 0.25),
		    A, B, C, how, &h), 1);
		assert_int_equal(h.type, CONTACT_NODE_FACE);
		assert_double_equal(h.tq, 0.5, 1e-15);
		assert_double_equal(h.q.x, 0.25, 1e-15);
		assert_double_equal(h.q.y, 0, 1e-15);
		assert_double_equal(h.q.z, 0.25, 1e-15);
		assert_double_equal(fabs(h.n.y), 1, 1e-15);
		/* landing exactly on the plane counts (eq. 1-2: D on the plane) */
		assert_int_equal(narrow_seed_segment(v3(0.2, 0.1, 0.2), v3(0.2, 0, 0.2),
		    A, B, C, how, &h), 1);
		assert_double_equal(h.tq, 1, 1e-15);
	}
}

static void
test_seed_misses(void **state)
{
	enum inside_test how;
	struct seed_hit h;

	(void)state;
	for (how = INSIDE_ANGLE; how <= INSIDE_CROSSING; how++) {
		/* through the plane, well outside the triangle */
		assert_int_equal(narrow_seed_segment(v3(1, 0.5, 1), v3(1, -0.5, 1), A, B, C, how,
		    &h), 0);
		/* both ends on one side */
		assert_int_equal(narrow_seed_segment(v3(0.2, 0.5, 0.2), v3(0.2, 0.1, 0.2), A, B, C,
		    how, &h), 0);
		/* in the plane: no single Q (eq. 7 divides by s = 0) */
		assert_int_equal(narrow_seed_segment(v3(0.1, 0, 0.1), v3(0.2, 0, 0.2), A, B, C, how,
		    &h), 0);
	}
	/* a degenerate triangle has no normal */
	assert_int_equal(narrow_seed_segment(v3(0, 1, 0), v3(0, -1, 0), A, A, C, INSIDE_ANGLE,
	    &h), 0);
}

static void
test_seed_vertex_and_edge(void **state)
{
	struct seed_hit h;

	(void)state;
	/* Q on vertex B: node-node */
	assert_int_equal(narrow_seed_segment(v3(0, 1, 1), v3(0, -1, 1), A, B, C, INSIDE_ANGLE,
	    &h), 1);
	assert_int_equal(h.type, CONTACT_NODE_NODE);
	assert_int_equal(h.feature, 1);
	/* Q on the middle of edge CA (y = 0, z = 0): gamma = pi */
	assert_int_equal(narrow_seed_segment(v3(0.5, 1, 0), v3(0.5, -1, 0), A, B, C, INSIDE_ANGLE,
	    &h), 1);
	assert_int_equal(h.type, CONTACT_NODE_EDGE);
	assert_int_equal(h.feature, 2);
	assert_int_equal(narrow_seed_segment(v3(0.5, 1, 0), v3(0.5, -1, 0), A, B, C,
	    INSIDE_CROSSING, &h), 1);
	assert_int_equal(h.type, CONTACT_NODE_EDGE);
	assert_int_equal(h.feature, 2);
}

/* eq. 10's tolerance reaches outside the triangle: a Q just past edge CA
 * still makes an angle within 2 pi / 100 of pi. The crossing test does not
 * have that slack. This is the chapter's method, measured, not a bug. */
static void
test_seed_angle_tolerance(void **state)
{
	struct seed_hit h;

	(void)state;
	assert_int_equal(narrow_seed_segment(v3(0.5, 1, -0.005), v3(0.5, -1, -0.005), A, B, C,
	    INSIDE_ANGLE, &h), 1);
	assert_int_equal(h.type, CONTACT_NODE_EDGE);
	assert_int_equal(narrow_seed_segment(v3(0.5, 1, -0.005), v3(0.5, -1, -0.005), A, B, C,
	    INSIDE_CROSSING, &h), 0);
	/* far enough out, both say no */
	assert_int_equal(narrow_seed_segment(v3(0.5, 1, -0.1), v3(0.5, -1, -0.1), A, B, C,
	    INSIDE_ANGLE, &h), 0);
}

/* An inelastic hit on a resting plane: the normal velocity goes to zero,
 * the tangential velocity stays, and the kinetic energy lost is exactly
 * m v_n^2 / 2. */
static void
test_inelastic_on_plane(void **state)
{
	vec3 vd = v3(1.5, -2, 0.5), n = v3(0, 1, 0), out;
	double m = 0.003, ke0, ke1;

	(void)state;
	out = response_node_velocity(vd, n, v3(0, 0, 0), 0, NULL, 1e-3);
	assert_double_equal(out.y, 0, 0);
	assert_double_equal(out.x, 1.5, 0);
	assert_double_equal(out.z, 0.5, 0);
	ke0 = 0.5 * m * v3_dot(vd, vd);
	ke1 = 0.5 * m * v3_dot(out, out);
	assert_double_equal(ke0 - ke1, 0.5 * m * 4, 1e-18);
	/* the normal need not be upward: the same answer along -n */
	out = response_node_velocity(vd, v3_neg(n), v3(0, 0, 0), 0, NULL, 1e-3);
	assert_double_equal(out.y, 0, 0);
	/* eq. 11 with e = 0.5 */
	out = response_node_velocity(vd, n, v3(0, 0, 0), 0.5, NULL, 1e-3);
	assert_double_equal(out.y, 1, 1e-15);
	/* a plane moving up at 0.3 m/s: the node takes its normal velocity */
	out = response_node_velocity(vd, n, v3(7, 0.3, 0), 0, NULL, 1e-3);
	assert_double_equal(out.y, 0.3, 1e-15);
	assert_double_equal(out.x, 1.5, 0);
}

static void
test_friction(void **state)
{
	vec3 vd = v3(1, -2, 0), n = v3(0, 1, 0), out;
	struct friction fr = { 0.25, 0 };

	(void)state;
	/* Coulomb: |dv_t| = mu |dv_n| = 0.5 */
	out = response_node_velocity(vd, n, v3(0, 0, 0), 0, &fr, 1e-3);
	assert_double_equal(out.x, 0.5, 1e-15);
	assert_double_equal(out.y, 0, 1e-15);
	/* it stops the sliding, never reverses it */
	fr.mu = 10;
	out = response_node_velocity(vd, n, v3(0, 0, 0), 0, &fr, 1e-3);
	assert_double_equal(out.x, 0, 1e-15);
	/* relative to a surface sliding along with the node: no change */
	out = response_node_velocity(vd, n, v3(1, 0, 0), 0, &fr, 1e-3);
	assert_double_equal(out.x, 1, 1e-15);
	/* viscous: exp(-c dt) of the sliding speed */
	fr.mu = 0;
	fr.viscous = 100;
	out = response_node_velocity(vd, n, v3(0, 0, 0), 0, &fr, 1e-3);
	assert_double_equal(out.x, exp(-0.1), 1e-15);
}

/* eq. 13-15 on a rigidly moving triangle: v_Q = v_A + omega x (Q - A). */
static void
test_rotating_triangle(void **state)
{
	vec3 a = v3(0.1, 0.2, -0.3), b = v3(1.1, 0.4, 0.1), c = v3(-0.2, 0.9, 0.5);
	vec3 omega = v3(0.7, -1.3, 2.1), v0 = v3(0.3, -0.2, 0.05), ctr = v3(0.2, 0.1, 0);
	vec3 va, vb, vc, q, vq, want;

	(void)state;
	va = v3_add(v0, v3_cross(omega, v3_sub(a, ctr)));
	vb = v3_add(v0, v3_cross(omega, v3_sub(b, ctr)));
	vc = v3_add(v0, v3_cross(omega, v3_sub(c, ctr)));
	q = v3_add(v3_add(v3_scale(a, 0.2), v3_scale(b, 0.5)), v3_scale(c, 0.3));
	vq = response_point_velocity(a, b, c, va, vb, vc, q);
	want = v3_add(va, v3_cross(omega, v3_sub(q, a)));
	assert_double_equal(vq.x, want.x, 1e-13);
	assert_double_equal(vq.y, want.y, 1e-13);
	assert_double_equal(vq.z, want.z, 1e-13);
	/* a pure translation */
	vq = response_point_velocity(a, b, c, v0, v0, v0, q);
	assert_double_equal(vq.x, v0.x, 1e-15);
	assert_double_equal(vq.y, v0.y, 1e-15);
	assert_double_equal(vq.z, v0.z, 1e-15);
}

/* The shared (ccd) response: a node of mass 1 falls at 1 m/s on the middle
 * of a resting free triangle of three nodes of mass 1. */
static void
test_shared_impulse(void **state)
{
	const double w[4] = { 1, -1.0 / 3, -1.0 / 3, -1.0 / 3 }, im[4] = { 1, 1, 1, 1 };
	const double fixed[4] = { 1, 0, 0, 0 };
	vec3 n = v3(0, 1, 0), v[4];
	double p_before, p_after, ke_before, ke_after, j;
	int k;

	(void)state;
	for (k = 0; k < 4; k++)
		v[k] = v3(0, 0, 0);
	v[0] = v3(0, -1, 0);
	p_before = v[0].y;
	ke_before = 0.5;
	j = response_shared(4, w, im, v, n, 0, NULL, 1e-3);
	/* den = 1 + 3/9, j = 1/den */
	assert_double_equal(j, 0.75, 1e-15);
	p_after = ke_after = 0;
	for (k = 0; k < 4; k++) {
		p_after += v[k].y;
		ke_after += 0.5 * v3_dot(v[k], v[k]);
		assert_double_equal(v[k].y, -0.25, 1e-15);	/* they move on together */
		assert_double_equal(v[k].x, 0, 0);
	}
	assert_double_equal(p_after, p_before, 1e-15);	/* momentum kept */
	/* the loss of a perfectly inelastic impact: 1/2 (1/den) vr^2 */
	assert_double_equal(ke_before - ke_after, 0.5 * 0.75 * 1, 1e-15);

	/* e = 1: the relative velocity reverses and no energy is lost */
	for (k = 0; k < 4; k++)
		v[k] = v3(0, 0, 0);
	v[0] = v3(0, -1, 0);
	response_shared(4, w, im, v, n, 1, NULL, 1e-3);
	assert_double_equal(v[0].y - v[1].y, 1, 1e-15);
	for (k = 0, ke_after = 0; k < 4; k++)
		ke_after += 0.5 * v3_dot(v[k], v[k]);
	assert_double_equal(ke_after, 0.5, 1e-15);

	/* a triangle nothing can move (an obstacle mesh): eq. 12, the node
	 * takes its normal velocity, 0; Coulomb mu = 0.5 takes mu |dv_n| = 0.5
	 * off the sliding speed of 2 */
	{
		struct friction fr = { 0.5, 0 };

		for (k = 0; k < 4; k++)
			v[k] = v3(0, 0, 0);
		v[0] = v3(2, -1, 0);
		j = response_shared(4, w, fixed, v, n, 0, &fr, 1e-3);
		assert_double_equal(j, 1, 1e-15);
		assert_double_equal(v[0].y, 0, 1e-15);
		assert_double_equal(v[0].x, 1.5, 1e-15);
		assert_double_equal(v[1].x, 0, 0);
		/* mu = 5 stops the sliding, and no more */
		fr.mu = 5;
		v[0] = v3(2, -1, 0);
		response_shared(4, w, fixed, v, n, 0, &fr, 1e-3);
		assert_double_equal(v[0].x, 0, 1e-15);
	}

	/* parting sides are left alone */
	for (k = 0; k < 4; k++)
		v[k] = v3(0, 0, 0);
	v[0] = v3(0.3, 1, 0);
	assert_double_equal(response_shared(4, w, im, v, n, 0, NULL, 1e-3), 0, 0);
	assert_double_equal(v[0].y, 1, 0);
	assert_double_equal(v[0].x, 0.3, 0);

	/* nothing can move */
	{
		const double none[4] = { 0, 0, 0, 0 };

		assert_double_equal(response_shared(4, w, none, v, n, 0, NULL, 1e-3), -1, 0);
	}
}

int
main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_seed_through_face),
		cmocka_unit_test(test_seed_misses),
		cmocka_unit_test(test_seed_vertex_and_edge),
		cmocka_unit_test(test_seed_angle_tolerance),
		cmocka_unit_test(test_inelastic_on_plane),
		cmocka_unit_test(test_friction),
		cmocka_unit_test(test_rotating_triangle),
		cmocka_unit_test(test_shared_impulse),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}

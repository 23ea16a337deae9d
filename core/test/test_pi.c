/*
 * Speed PI with output limit and anti-windup.
 *
 * Hand values below; every quantity is O(10) and results of 2-3 roundings, so
 * the tolerance 8 eps * 10 covers them. A missing proportional or integral
 * term, or an integral without T_s, is an error of >= 0.01.
 */
#include "smd_test.h"
#include "smodrive/smd_pi.h"

#define TOL (80 * SMDT_EPS)

static void test_init_rejects(void)
{
    smd_pi_params p;
    CHECK_INT(smd_pi_init(&p, R(2.0), R(10.0), R(0.01), R(5.0)), SMD_OK);
    CHECK_INT(smd_pi_init(&p, R(0.0), R(0.0), R(0.01), R(5.0)), SMD_OK);
    CHECK_INT(smd_pi_init(&p, R(-1.0), R(10.0), R(0.01), R(5.0)), SMD_ERR_KP);
    CHECK_INT(smd_pi_init(&p, R(NAN), R(10.0), R(0.01), R(5.0)), SMD_ERR_KP);
    CHECK_INT(smd_pi_init(&p, R(2e6), R(10.0), R(0.01), R(5.0)), SMD_ERR_KP);
    CHECK_INT(smd_pi_init(&p, R(2.0), R(-1.0), R(0.01), R(5.0)), SMD_ERR_KI);
    CHECK_INT(smd_pi_init(&p, R(2.0), R(INFINITY), R(0.01), R(5.0)), SMD_ERR_KI);
    CHECK_INT(smd_pi_init(&p, R(2.0), R(10.0), R(0.0), R(5.0)), SMD_ERR_TS);
    CHECK_INT(smd_pi_init(&p, R(2.0), R(10.0), R(-0.01), R(5.0)), SMD_ERR_TS);
    CHECK_INT(smd_pi_init(&p, R(2.0), R(10.0), R(2.0), R(5.0)), SMD_ERR_TS);
    CHECK_INT(smd_pi_init(&p, R(2.0), R(10.0), R(0.01), R(0.0)), SMD_ERR_LIMIT);
    CHECK_INT(smd_pi_init(&p, R(2.0), R(10.0), R(0.01), R(INFINITY)), SMD_ERR_LIMIT);
    CHECK_INT(smd_pi_init(0, R(2.0), R(10.0), R(0.01), R(5.0)), SMD_ERR_NULL);
}

/* k_p = 2, k_i = 10 /s, T_s = 0.01 s, y_max = 100 (no saturation):
 *   e = 3  : x_i = 0 + 10*0.01*3 = 0.3,   y = 2*3 + 0.3 = 6.3
 *   e = -1 : x_i = 0.3 - 0.1 = 0.2,       y = -2 + 0.2 = -1.8
 *   e = 0  : x_i = 0.2,                   y = 0.2
 * and from x_i0 = 1.5 with e = 0.5: x_i = 1.55, y = 2.55. */
static void test_proportional_integral(void)
{
    smd_pi_params p;
    smd_pi_state s;
    CHECK_INT(smd_pi_init(&p, R(2.0), R(10.0), R(0.01), R(100.0)), SMD_OK);
    smd_pi_reset(&s, R(0.0));
    CHECK_CLOSE(smd_pi_step(&p, &s, R(3.0)), 6.3, TOL);
    CHECK_CLOSE(s.x_i, 0.3, TOL);
    CHECK_CLOSE(smd_pi_step(&p, &s, R(-1.0)), -1.8, TOL);
    CHECK_CLOSE(smd_pi_step(&p, &s, R(0.0)), 0.2, TOL);
    CHECK_CLOSE(s.y, 0.2, TOL);
    smd_pi_reset(&s, R(1.5));
    CHECK_CLOSE(smd_pi_step(&p, &s, R(0.5)), 2.55, TOL);
    /* a constant error integrates linearly: after 100 steps of e = 1 from 0,
     * x_i = 100 * 0.1 = 10, y = 2 + 10 = 12 */
    {
        int k;
        smd_real y = R(0.0);
        smd_pi_reset(&s, R(0.0));
        for (k = 0; k < 100; k++) {
            y = smd_pi_step(&p, &s, R(1.0));
        }
        CHECK_CLOSE(y, 12.0, 100 * TOL);
    }
}

/* Anti-windup, k_p = 0.2, k_i = 10, T_s = 0.01, y_max = 5.
 * 1000 steps of e = +10 (k_i T_s e = 1 per step: y = 3, 4, then 5 from the
 * third step k = 2 on): the unlimited law would integrate to 1000 A and the
 * output would stay saturated for ~1000 more steps after the error reverses.
 * Here the output stays exactly at +5 and the integrator is held at the
 * realisable value x_i = y_max - k_p e = 5 - 2 = 3. At the first step with
 * e = -0.1: x_i = 3 - 0.01 = 2.99, y = -0.02 + 2.99 = 2.97 (below the limit
 * right after the sign change). Mirror test on the negative side. */
static void test_anti_windup(void)
{
    smd_pi_params p;
    smd_pi_state s;
    int k, at_limit = 1;
    CHECK_INT(smd_pi_init(&p, R(0.2), R(10.0), R(0.01), R(5.0)), SMD_OK);
    smd_pi_reset(&s, R(0.0));
    for (k = 0; k < 1000; k++) {
        smd_real y = smd_pi_step(&p, &s, R(10.0));
        if (k >= 2 && y != R(5.0)) {
            at_limit = 0;
        }
    }
    CHECK(at_limit);
    CHECK_CLOSE(s.x_i, 3.0, TOL);
    CHECK_CLOSE(smd_pi_step(&p, &s, R(-0.1)), 2.97, TOL);
    CHECK_CLOSE(smd_pi_step(&p, &s, R(-0.1)), 2.97 - 0.01, TOL);

    smd_pi_reset(&s, R(0.0));
    at_limit = 1;
    for (k = 0; k < 1000; k++) {
        smd_real y = smd_pi_step(&p, &s, R(-10.0));
        if (k >= 2 && y != R(-5.0)) {
            at_limit = 0;
        }
    }
    CHECK(at_limit);
    CHECK_CLOSE(smd_pi_step(&p, &s, R(0.1)), -2.97, TOL);

    /* pure integrator (k_p = 0): saturated at 5, recovers to 5 - 0.1 = 4.9 at
     * the first step of e = -1 */
    CHECK_INT(smd_pi_init(&p, R(0.0), R(10.0), R(0.01), R(5.0)), SMD_OK);
    smd_pi_reset(&s, R(0.0));
    for (k = 0; k < 1000; k++) {
        (void)smd_pi_step(&p, &s, R(10.0));
    }
    CHECK_CLOSE(s.y, 5.0, 0.0);
    CHECK_CLOSE(smd_pi_step(&p, &s, R(-1.0)), 4.9, TOL);
}

/* A non-finite error must not leave a non-finite output or state. */
static void test_nonfinite_error(void)
{
    smd_pi_params p;
    smd_pi_state s;
    smd_real y;
    CHECK_INT(smd_pi_init(&p, R(2.0), R(10.0), R(0.01), R(5.0)), SMD_OK);
    smd_pi_reset(&s, R(1.0));
    y = smd_pi_step(&p, &s, R(NAN));
    CHECK(isfinite(y) && isfinite(s.x_i));
    CHECK(fabs((double)y) <= 5.0);
    y = smd_pi_step(&p, &s, R(1.0));
    CHECK(isfinite(y) && fabs((double)y) <= 5.0);
}

int main(void)
{
    RUN_TEST(test_init_rejects);
    RUN_TEST(test_proportional_integral);
    RUN_TEST(test_anti_windup);
    RUN_TEST(test_nonfinite_error);
    return smdt_summary("test_pi");
}

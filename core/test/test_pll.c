/*
 * Third-order PLL, yao2022 eq. (48)-(50).
 *
 * Hand values are O(100) after 2-3 roundings: tolerance 1e3 eps. The
 * stability verdicts are compared with the roots of the closed-loop
 * polynomial (z - 1)^3 + N(z) computed offline (numpy.roots), quoted here.
 */
#include "smd_test.h"
#include "smodrive/smd_pll.h"

static void test_recursion_hand_values(void)
{
    /* theta = 0.1, w = 100, a = 0, e = 0.2, T = 1e-3, gains 0.1, 10, 10:
     *   theta' = 0.1 + 100e-3 + 0.1*0.2 = 0.22
     *   w'     = 100 + 0 + 10*0.2       = 102
     *   a'     = 0 + 10*0.2             = 2
     * then with e = 0: theta'' = 0.22 + 0.102 = 0.322, w'' = 102.002, a'' = 2 */
    smd_pll_params p;
    smd_pll_state s;
    CHECK_INT(smd_pll_init(&p, R(1e-3), R(0.1), R(10.0), R(10.0)), SMD_OK);
    CHECK_CLOSE(p.T_sp, R(1e-3), 0.0); /* the sampling period is kept as T_sp */
    smd_pll_reset(&s, R(0.1), R(100.0));
    smd_pll_step(&p, &s, R(0.2));
    CHECK_CLOSE(s.theta, 0.22, 1e3 * SMDT_EPS);
    CHECK_CLOSE(s.w, 102.0, 1e3 * SMDT_EPS);
    CHECK_CLOSE(s.a, 2.0, 1e3 * SMDT_EPS);
    smd_pll_step(&p, &s, R(0.0));
    CHECK_CLOSE(s.theta, 0.322, 1e3 * SMDT_EPS);
    CHECK_CLOSE(s.w, 102.002, 1e3 * SMDT_EPS);
    /* NaN error: ignored (treated as 0) */
    smd_pll_step(&p, &s, R(NAN));
    CHECK(isfinite(s.theta) && isfinite(s.w) && isfinite(s.a));
}

static void test_stability_verdicts(void)
{
    /* T = 50 us; max |root| from numpy: (0.1, 10, 10) 0.99995 stable (the
     * paper's eq. (50)); (1.5, 10, 10) 0.99994 stable; (0.1, 10, 0) 1.0
     * marginal; (0.1, 1e4, 10) 1.18; (0.1, 10, 1e7) 1.14 unstable. */
    smd_pll_params p;
    const smd_real T = R(50e-6);
    CHECK_INT(smd_pll_init(&p, T, R(0.1), R(10.0), R(10.0)), SMD_OK);
    CHECK_INT(smd_pll_init(&p, T, R(1.5), R(10.0), R(10.0)), SMD_OK);
    CHECK_INT(smd_pll_init(&p, T, R(0.1), R(10.0), R(0.0)), SMD_ERR_STABILITY);
    CHECK_INT(smd_pll_init(&p, T, R(0.1), R(1e4), R(10.0)), SMD_ERR_STABILITY);
    CHECK_INT(smd_pll_init(&p, T, R(0.1), R(10.0), R(1e7)), SMD_ERR_STABILITY);
    CHECK_INT(smd_pll_init(&p, T, R(2.5), R(10.0), R(10.0)), SMD_ERR_KP);
    CHECK_INT(smd_pll_init(&p, R(0.0), R(0.1), R(10.0), R(10.0)), SMD_ERR_TS);
    CHECK_INT(smd_pll_init(0, T, R(0.1), R(10.0), R(10.0)), SMD_ERR_NULL);
}

/* A type-3 loop tracks constant acceleration with zero steady-state error.
 * Gains (0.5, 500, 2e4) at T = 50 us: slowest root 0.99791 (numpy), so after
 * 20000 samples the transient is down by 0.99791^20000 ~ 1e-18. The angle
 * error is then limited by float rounding of theta (|theta| <= pi): 1e3 eps. */
static void test_tracks_constant_acceleration(void)
{
    smd_pll_params p;
    smd_pll_state s;
    const double T = 50e-6, w0 = 3000.0, acc = 2e4;
    double th = 0.3;
    double w = w0;
    int k;
    CHECK_INT(smd_pll_init(&p, R(T), R(0.5), R(500.0), R(2e4)), SMD_OK);
    smd_pll_reset(&s, R(0.0), R(0.0));
    for (k = 0; k < 20000; k++) {
        double e = smdt_wrap(th - (double)s.theta);
        smd_pll_step(&p, &s, R(e));
        th = smdt_wrap(th + w * T + 0.5 * acc * T * T);
        w += acc * T;
    }
    CHECK_CLOSE(smdt_wrap(th - (double)s.theta), 0.0, 2e3 * SMDT_EPS);
    /* speed to the rounding of theta increments: (1e3 eps) / T */
    /* eq. (48) makes w the mean speed over the next period: w_k + acc T / 2 */
    CHECK_CLOSE((double)s.w, w + 0.5 * acc * T, 2e3 * SMDT_EPS / T * 4.0);
}

int main(void)
{
    RUN_TEST(test_recursion_hand_values);
    RUN_TEST(test_stability_verdicts);
    RUN_TEST(test_tracks_constant_acceleration);
    return smdt_summary("pll");
}

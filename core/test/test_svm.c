/*
 * Space-vector modulation (min-max injection) and its voltage limits.
 *
 * The realised vector is computed independently from the duties, for ideal
 * switches: u = (2/3) u_dc (d_a + d_b a + d_c a^2), a = e^{j 2 pi / 3}
 * (the common mode of the three phase voltages d_x u_dc cancels since
 * 1 + a + a^2 = 0).
 *
 * Tolerances: a duty is 0.5 + (u_x + u_0)/u_dc with u_x, u_0 computed in <= 4
 * roundings from |u| <= (2/3) u_dc, so each duty is within ~4 eps; the
 * reconstruction multiplies by (2/3) u_dc * 3, i.e. an error below ~8 eps u_dc.
 * We allow 16 eps u_dc (1e-3 V at 540 V in float). A wrong limit radius or a
 * rotated vector is an error of volts.
 */
#include "smd_test.h"
#include "smodrive/smd_svm.h"

#define UDC 540.0
#define INV_SQRT3_D 0.57735026918962576451

static double complex realised(const smd_real d[3], double u_dc)
{
    double complex a = cexp(JD * 2.0 * PI_D / 3.0);
    return (2.0 / 3.0) * u_dc * ((double)d[0] + (double)d[1] * a + (double)d[2] * a * a);
}

/* distance from the origin to the hexagon boundary along direction phi:
 * the inscribed radius u_dc/sqrt3 is reached at phi = pi/6 + k pi/3 */
static double hexagon_radius(double phi, double u_dc)
{
    double p = phi - (PI_D / 3.0) * floor(phi / (PI_D / 3.0)); /* [0, pi/3) */
    return u_dc * INV_SQRT3_D / cos(p - PI_D / 6.0);
}

static int duties_in(const smd_real d[3], double lo, double hi)
{
    int k;
    for (k = 0; k < 3; k++) {
        if (!((double)d[k] >= lo && (double)d[k] <= hi)) {
            return 0;
        }
    }
    return 1;
}

static void test_init(void)
{
    smd_svm_params p;
    CHECK_INT(smd_svm_init(&p, SMD_SVM_LIMIT_CIRCLE, R(0.0)), SMD_OK);
    CHECK_INT(smd_svm_init(&p, SMD_SVM_LIMIT_HEXAGON, R(0.1)), SMD_OK);
    CHECK_INT(smd_svm_init(&p, 2, R(0.0)), SMD_ERR_MODE);
    CHECK_INT(smd_svm_init(&p, -1, R(0.0)), SMD_ERR_MODE);
    CHECK_INT(smd_svm_init(&p, SMD_SVM_LIMIT_CIRCLE, R(0.5)), SMD_ERR_DMIN);
    CHECK_INT(smd_svm_init(&p, SMD_SVM_LIMIT_CIRCLE, R(-0.01)), SMD_ERR_DMIN);
    CHECK_INT(smd_svm_init(&p, SMD_SVM_LIMIT_CIRCLE, R(NAN)), SMD_ERR_DMIN);
    CHECK_INT(smd_svm_init(0, SMD_SVM_LIMIT_CIRCLE, R(0.0)), SMD_ERR_NULL);
}

/* Linear range (|u| <= u_dc/sqrt3): the duties realise the reference exactly,
 * the applied vector is the reference, duties are in [0, 1] and centred
 * (symmetric SVPWM: d_max + d_min = 1). Same in both limit modes. */
static void test_linear_range(void)
{
    unsigned long st = 11;
    int mode, n;
    for (mode = 0; mode < 2; mode++) {
        smd_svm_params p;
        CHECK_INT(smd_svm_init(&p, mode, R(0.0)), SMD_OK);
        for (n = 0; n < 500; n++) {
            double mag = smdt_rand(&st, 0.0, 0.999 * UDC * INV_SQRT3_D);
            double phi = smdt_rand(&st, -PI_D, PI_D);
            double complex ref = mag * cexp(JD * phi);
            smd_real d[3];
            smd_cplx ua;
            double dmax, dmin;
            smd_svm_step(&p, smdt_c(ref), R(UDC), d, &ua);
            CHECK_CPLX(ua, ref, 16 * SMDT_EPS * UDC);
            CHECK_CPLX(smdt_c(realised(d, UDC)), ref, 16 * SMDT_EPS * UDC);
            CHECK(duties_in(d, 0.0, 1.0));
            dmax = fmax(fmax((double)d[0], (double)d[1]), (double)d[2]);
            dmin = fmin(fmin((double)d[0], (double)d[1]), (double)d[2]);
            CHECK_CLOSE(dmax + dmin, 1.0, 8 * SMDT_EPS);
        }
    }
}

/* Circle limit: a reference beyond the inscribed circle is scaled to
 * |u| = u_dc/sqrt3 keeping its direction; the duties realise it. */
static void test_circle_limit(void)
{
    unsigned long st = 5;
    smd_svm_params p;
    int n;
    CHECK_INT(smd_svm_init(&p, SMD_SVM_LIMIT_CIRCLE, R(0.0)), SMD_OK);
    for (n = 0; n < 500; n++) {
        double mag = smdt_rand(&st, 1.001 * UDC * INV_SQRT3_D, 10.0 * UDC);
        double phi = smdt_rand(&st, -PI_D, PI_D);
        double complex ref = mag * cexp(JD * phi);
        double complex expect = UDC * INV_SQRT3_D * cexp(JD * phi);
        smd_real d[3];
        smd_cplx ua;
        smd_svm_step(&p, smdt_c(ref), R(UDC), d, &ua);
        CHECK_CPLX(ua, expect, 16 * SMDT_EPS * UDC);
        CHECK_CPLX(smdt_c(realised(d, UDC)), expect, 16 * SMDT_EPS * UDC);
        CHECK(duties_in(d, 0.0, 1.0));
    }
    /* with d_min: radius (1 - 2 d_min) u_dc / sqrt3, duties in [d_min, 1 - d_min] */
    CHECK_INT(smd_svm_init(&p, SMD_SVM_LIMIT_CIRCLE, R(0.05)), SMD_OK);
    for (n = 0; n < 100; n++) {
        double phi = smdt_rand(&st, -PI_D, PI_D);
        double complex ref = 2.0 * UDC * cexp(JD * phi);
        smd_real d[3];
        smd_cplx ua;
        smd_svm_step(&p, smdt_c(ref), R(UDC), d, &ua);
        CHECK_CPLX(ua, 0.9 * UDC * INV_SQRT3_D * cexp(JD * phi), 16 * SMDT_EPS * UDC);
        CHECK_CPLX(smdt_c(realised(d, UDC)), 0.9 * UDC * INV_SQRT3_D * cexp(JD * phi),
                   16 * SMDT_EPS * UDC);
        CHECK(duties_in(d, 0.05 - 4 * SMDT_EPS, 0.95 + 4 * SMDT_EPS));
    }
}

/* Hexagon limit: a reference beyond the hexagon lands on the hexagon boundary
 * along its own direction (|u| = r_hex(phi), one duty 1 and one 0); a
 * reference between circle and hexagon passes unchanged. */
static void test_hexagon_limit(void)
{
    unsigned long st = 9;
    smd_svm_params p;
    int n;
    CHECK_INT(smd_svm_init(&p, SMD_SVM_LIMIT_HEXAGON, R(0.0)), SMD_OK);
    /* hand values: r_hex(0) = 2/3 u_dc (vertex), r_hex(pi/6) = u_dc/sqrt3 */
    CHECK_CLOSE(hexagon_radius(0.0, UDC), 360.0, 1e-9);
    CHECK_CLOSE(hexagon_radius(PI_D / 6.0, UDC), 311.76914536239791, 1e-9);
    for (n = 0; n < 500; n++) {
        double phi = smdt_rand(&st, -PI_D, PI_D);
        double mag = smdt_rand(&st, 1.01, 10.0) * hexagon_radius(phi, UDC);
        double complex expect = hexagon_radius(phi, UDC) * cexp(JD * phi);
        smd_real d[3];
        smd_cplx ua;
        double dmax, dmin;
        smd_svm_step(&p, smdt_c(mag * cexp(JD * phi)), R(UDC), d, &ua);
        CHECK_CPLX(ua, expect, 16 * SMDT_EPS * UDC);
        CHECK_CPLX(smdt_c(realised(d, UDC)), expect, 16 * SMDT_EPS * UDC);
        dmax = fmax(fmax((double)d[0], (double)d[1]), (double)d[2]);
        dmin = fmin(fmin((double)d[0], (double)d[1]), (double)d[2]);
        CHECK_CLOSE(dmax, 1.0, 8 * SMDT_EPS);
        CHECK_CLOSE(dmin, 0.0, 8 * SMDT_EPS);
        CHECK(duties_in(d, 0.0, 1.0));
    }
    /* inside the hexagon but outside the circle: not limited (the circle mode
     * would have shortened it to 311.8 V) */
    {
        smd_real d[3];
        smd_cplx ua;
        smd_svm_step(&p, smd_c(R(350.0), R(0.0)), R(UDC), d, &ua);
        CHECK_CPLX(ua, 350.0, 16 * SMDT_EPS * UDC);
        CHECK_CPLX(smdt_c(realised(d, UDC)), 350.0, 16 * SMDT_EPS * UDC);
    }
}

/* A finite reference whose phase values overflow the real type (found by
 * fuzz/fuzz_blocks: -FLT_MAX - j FLT_MAX gave NaN duties, the limit factor
 * u_dc / inf = 0 times the infinite phase values): beyond the hexagon of any
 * finite u_dc, so it lands on the hexagon along its own direction, with
 * finite duties. The largest value of the real type, whichever it is. */
static void test_hexagon_huge_reference(void)
{
#ifdef SMD_REAL_DOUBLE
    const double big = DBL_MAX;
#else
    const double big = (double)FLT_MAX;
#endif
    const double dirs[4][2] = {{-1.0, -1.0}, {1.0, 0.0}, {0.25, -1.0}, {-1.0, 0.5}};
    smd_svm_params p;
    int n;
    CHECK_INT(smd_svm_init(&p, SMD_SVM_LIMIT_HEXAGON, R(0.0)), SMD_OK);
    for (n = 0; n < 4; n++) {
        double phi = atan2(dirs[n][1], dirs[n][0]);
        double complex expect = hexagon_radius(phi, UDC) * cexp(JD * phi);
        smd_real d[3];
        smd_cplx ua;
        smd_svm_step(&p, smd_c(R(dirs[n][0] * big), R(dirs[n][1] * big)), R(UDC), d, &ua);
        CHECK(duties_in(d, 0.0, 1.0));
        CHECK_CPLX(ua, expect, 16 * SMDT_EPS * UDC);
        CHECK_CPLX(smdt_c(realised(d, UDC)), expect, 16 * SMDT_EPS * UDC);
    }
}

/* No DC link or a non-finite reference: zero vector (all duties 1/2). */
static void test_zero_vector_fallback(void)
{
    smd_svm_params p;
    smd_real udc_bad[4];
    smd_cplx ref_bad[3];
    int i;
    udc_bad[0] = R(0.0);
    udc_bad[1] = R(-100.0);
    udc_bad[2] = R(NAN);
    udc_bad[3] = R(-INFINITY);
    ref_bad[0] = smd_c(R(NAN), R(0.0));
    ref_bad[1] = smd_c(R(0.0), R(INFINITY));
    ref_bad[2] = smd_c(R(-INFINITY), R(NAN));
    CHECK_INT(smd_svm_init(&p, SMD_SVM_LIMIT_HEXAGON, R(0.0)), SMD_OK);
    for (i = 0; i < 7; i++) {
        smd_real d[3] = {R(-1.0), R(-1.0), R(-1.0)};
        smd_cplx ua = smd_c(R(99.0), R(99.0));
        if (i < 4) {
            smd_svm_step(&p, smd_c(R(100.0), R(50.0)), udc_bad[i], d, &ua);
        } else {
            smd_svm_step(&p, ref_bad[i - 4], R(UDC), d, &ua);
        }
        CHECK_CLOSE(d[0], 0.5, 0.0);
        CHECK_CLOSE(d[1], 0.5, 0.0);
        CHECK_CLOSE(d[2], 0.5, 0.0);
        CHECK_CPLX(ua, 0.0, 0.0);
    }
}

/* Dead-time compensation d_x += (t_dead/T) sat(i_x / i_lin), kept in [0, 1].
 * Hand values with t_dead/T = 0.02, i_lin = 1 A:
 *   d = 0.5,  i = 10 A   -> 0.5 + 0.02          = 0.52
 *   d = 0.2,  i = -0.5 A -> 0.2 - 0.02 * 0.5    = 0.19  (linear zone)
 *   d = 0.99, i = 3 A    -> min(1, 1.01)        = 1
 * and d = 0.01, i = -2 A -> max(0, -0.01) = 0. Tolerance: 2 roundings of 1. */
static void test_deadtime_comp(void)
{
    smd_real d[3] = {R(0.5), R(0.2), R(0.99)};
    smd_real i[3] = {R(10.0), R(-0.5), R(3.0)};
    smd_real d2[3] = {R(0.01), R(0.5), R(0.5)};
    smd_real i2[3] = {R(-2.0), R(0.0), R(1.0)};
    smd_svm_deadtime_comp(d, i, R(0.02), R(1.0));
    CHECK_CLOSE(d[0], 0.52, 4 * SMDT_EPS);
    CHECK_CLOSE(d[1], 0.19, 4 * SMDT_EPS);
    CHECK_CLOSE(d[2], 1.0, 0.0);
    smd_svm_deadtime_comp(d2, i2, R(0.02), R(1.0));
    CHECK_CLOSE(d2[0], 0.0, 0.0);
    CHECK_CLOSE(d2[1], 0.5, 0.0);
    CHECK_CLOSE(d2[2], 0.52, 4 * SMDT_EPS);
}

/* The compensation that returns what its clipping leaves out
 * (smd_svm_deadtime_comp_lost). Hand values with t_dead/T = 0.02,
 * i_lin = 1 A, u_dc = 540 V:
 *   d = (0.5, 0.2, 0.5), i = (10, -0.5, 0) A: duties as smd_svm_deadtime_comp
 *     gives them, nothing clipped                      -> exactly 0
 *   d = (0.01, 0.5, 0.99), i = (-2, 0, 3) A, compensated to (0, 0.5, 1):
 *     leg a at 0 switches nothing: 0 - 0.01 = -0.01
 *     leg c at 1 keeps its rising edge's dead time: 1 - 0.02 - 0.99 = -0.01
 *     u = 540 (2/3 (-0.01 - (0 - 0.01)/2), (0 + 0.01)/sqrt 3)
 *       = (-1.8, 3.1176914536) V
 *   d = (0.5, 0.5, 0.999), i = (0, 0, 0.25) A (the linear zone): leg c at 1,
 *     1 - 0.02 * 0.25 - 0.999 = -0.004
 * Tolerance: 16 eps u_dc, as the reconstruction above. */
static void test_deadtime_comp_lost(void)
{
    smd_real d[3] = {R(0.5), R(0.2), R(0.5)}, d_ref[3] = {R(0.5), R(0.2), R(0.5)};
    const smd_real i[3] = {R(10.0), R(-0.5), R(0.0)};
    smd_real d2[3] = {R(0.01), R(0.5), R(0.99)};
    const smd_real i2[3] = {R(-2.0), R(0.0), R(3.0)};
    smd_real d3[3] = {R(0.5), R(0.5), R(0.999)};
    const smd_real i3[3] = {R(0.0), R(0.0), R(0.25)};
    smd_cplx u = smd_svm_deadtime_comp_lost(d, i, R(0.02), R(1.0), R(1.0), R(UDC));
    smd_svm_deadtime_comp(d_ref, i, R(0.02), R(1.0));
    CHECK_CPLX(u, 0.0, 0.0);
    CHECK_CLOSE(d[0], d_ref[0], 0.0);
    CHECK_CLOSE(d[1], d_ref[1], 0.0);
    CHECK_CLOSE(d[2], d_ref[2], 0.0);
    u = smd_svm_deadtime_comp_lost(d2, i2, R(0.02), R(1.0), R(1.0), R(UDC));
    CHECK_CLOSE(d2[0], 0.0, 0.0);
    CHECK_CLOSE(d2[2], 1.0, 0.0);
    CHECK_CLOSE(u.re, -1.8, 16 * SMDT_EPS * UDC);
    CHECK_CLOSE(u.im, 0.01 * INV_SQRT3_D * UDC, 16 * SMDT_EPS * UDC);
    u = smd_svm_deadtime_comp_lost(d3, i3, R(0.02), R(1.0), R(1.0), R(UDC));
    CHECK_CLOSE(d3[2], 1.0, 0.0);
    CHECK_CLOSE(u.re, 2.0 / 3.0 * 0.002 * UDC, 16 * SMDT_EPS * UDC);
    CHECK_CLOSE(u.im, 0.004 * INV_SQRT3_D * UDC, 16 * SMDT_EPS * UDC);
}

int main(void)
{
    RUN_TEST(test_init);
    RUN_TEST(test_linear_range);
    RUN_TEST(test_circle_limit);
    RUN_TEST(test_hexagon_limit);
    RUN_TEST(test_hexagon_huge_reference);
    RUN_TEST(test_zero_vector_fallback);
    RUN_TEST(test_deadtime_comp);
    RUN_TEST(test_deadtime_comp_lost);
    return smdt_summary("test_svm");
}

/*
 * The fast build's own shortcuts in the core's headers (SMD_FAST, defined
 * for this file with the fast math hooks, as the fast build compiles the
 * core): smd_cexpj_small (a rotation by one sample's turn by its series),
 * smd_cexpj_unit (the same below a radian, to x^10) and smd_wrap_pi (a product by 1/(2 pi) instead of the division), against
 * double libm and against the exact forms.
 */
#include <float.h>
#include <stdint.h>
#include <string.h>

#include "smd_test.h"
#include "smodrive/smd_types.h"

static uint32_t g_x = 88172645u;
static double urand(double lo, double hi) { return smdt_urand(&g_x, lo, hi); }

/* |x| < 1/8: within 1.2e-7 of cos x, sin x (the series' 3e-10 and float
 * rounding of values near 1); beyond: smd_cexpj's bits (the fast sincos) */
static void test_cexpj_small(void)
{
    double worst = 0.0;
    int k, other = 0;
    for (k = 0; k < 1000000; k++) {
        float x = (float)urand(-0.3, 0.3);
        smd_cplx z = smd_cexpj_small(x);
        if (fabsf(x) < 0.125f) {
            double e = fabs((double)z.re - cos((double)x)) + fabs((double)z.im - sin((double)x));
            if (e > worst) worst = e;
        } else {
            smd_cplx r = smd_cexpj(x);
            other += !(memcmp(&z, &r, sizeof z) == 0);
        }
    }
    printf("    cexpj_small worst %.3g (bound 1.2e-7)\n", worst);
    CHECK(worst <= 1.2e-7);
    CHECK_INT(other, 0);
}

/* |x| < 1: within 2e-7 of cos x, sin x (the series' 2.6e-8 at |x| = 1 and
 * the float rounding of the Horner steps); beyond: smd_cexpj's bits */
static void test_cexpj_unit(void)
{
    double worst = 0.0;
    int k, other = 0;
    for (k = 0; k < 1000000; k++) {
        float x = (float)urand(-1.5, 1.5);
        smd_cplx z = smd_cexpj_unit(x);
        if (fabsf(x) < 1.0f) {
            double e = fabs((double)z.re - cos((double)x)) + fabs((double)z.im - sin((double)x));
            if (e > worst) worst = e;
        } else {
            smd_cplx r = smd_cexpj(x);
            other += !(memcmp(&z, &r, sizeof z) == 0);
        }
    }
    printf("    cexpj_unit worst %.3g (bound 2e-7)\n", worst);
    CHECK(worst <= 2e-7);
    CHECK_INT(other, 0);
}

/* the wrap: the exact wrap's value within 1e-6 |x| + 1e-6, or 2 pi from it
 * at the edge, where the product's rounding (an ulp or two of
 * y = (x + pi) / (2 pi), at most 2.4e-7 |y|) can floor one turn off: then
 * it lands outside [-pi, pi) by at most 2 pi times that, 2.3e-4 at |x| =
 * 1000 (the drive wraps angles below 10 rad: a few 1e-6 there) */
static void test_wrap_fast(void)
{
    int k, bad = 0, off_turn = 0;
    for (k = 0; k < 1000000; k++) {
        float x = (float)urand(-1000.0, 1000.0);
        float w = smd_wrap_pi(x);
        double exact = remainder((double)x, 6.283185307179586);
        double d = fabs((double)w - exact);
        double out = 1.5e-6 * (1.0 + fabs((double)x) / 6.283185307179586);
        if (d > 3.0) {
            d = fabs(d - 6.283185307179586);
            off_turn++;
        }
        bad += !(fabs((double)w) <= 3.141592653589793 + out &&
                 d <= 1e-6 * fabs((double)x) + 1e-6);
    }
    printf("    %d of 1e6 wrapped a turn off (at the edge)\n", off_turn);
    CHECK_INT(bad, 0);
    CHECK(off_turn < 100);
}

/* the near wrap (smd_wrap_pi_near, |x| < 3 pi: a difference or a sum of two
 * wrapped angles): in [-pi, pi) for every x, within an ulp of 2 pi (the
 * turn's own rounding, 5e-7) of the exact remainder, and the same value as
 * the exact build's wrap where the turn is not in doubt (|x| away from the
 * ends of a turn by 1e-5) */
static void test_wrap_near(void)
{
    int k, bad = 0, differ = 0;
    for (k = 0; k < 1000000; k++) {
        float x = (float)urand(-3.0 * 3.141592653589793 + 1e-6, 3.0 * 3.141592653589793 - 1e-6);
        float w = smd_wrap_pi_near(x);
        double exact = remainder((double)x, 6.283185307179586);
        double d = fabs((double)w - exact);
        if (d > 3.0) {
            d = fabs(d - 6.283185307179586); /* (at the edge: -pi against pi) */
        }
        bad += !((double)w >= -3.1415927410125732 && (double)w < 3.1415927410125732 &&
                 d <= 5e-7);
        if (fabs(fabs((double)x) - 3.141592653589793) > 1e-5 &&
            fabs(fabs((double)x) - 3.0 * 3.141592653589793) > 1e-5) {
            differ += w != smd_wrap_pi(x) && fabs((double)w - (double)smd_wrap_pi(x)) > 1e-6;
        }
    }
    CHECK_INT(bad, 0);
    CHECK_INT(differ, 0);
}

/* The fast build's finiteness sum (smd_nfs): a state of finite values
 * passes, one infinite or NaN value among them (either sign, any place)
 * fails, as with the exact build's sum of x - x; an infinity and its
 * negative together still fail (inf - inf is NaN). */
static void test_finite_sum(void)
{
    const smd_real big = SMD_R(1e30), inf = (smd_real)INFINITY, nan = (smd_real)NAN;
    const smd_real bad[3] = {inf, -inf, nan};
    smd_real x[6] = {SMD_R(3.1), SMD_R(-2.0e4), SMD_R(0.0), big, -big, SMD_R(1e-30)};
    smd_real nf = SMD_R(0.0);
    int k, j, b;
    for (k = 0; k < 6; k++) nf += smd_nfs(x[k]);
    CHECK(smd_nf(nf) == SMD_R(0.0));
    for (b = 0; b < 3; b++) {
        for (j = 0; j < 6; j++) {
            smd_real y[6];
            for (k = 0; k < 6; k++) y[k] = x[k];
            y[j] = bad[b];
            nf = smd_cnfs(smd_c(y[0], y[1])) + smd_nfs(y[2]) + smd_nfs(y[3]) + smd_nfs(y[4]) +
                 smd_nfs(y[5]);
            CHECK(!(smd_nf(nf) == SMD_R(0.0)));
        }
    }
    nf = smd_nfs(inf) + smd_nfs(-inf);
    CHECK(!(smd_nf(nf) == SMD_R(0.0)));
}

int main(void)
{
    RUN_TEST(test_cexpj_small);
    RUN_TEST(test_cexpj_unit);
    RUN_TEST(test_wrap_fast);
    RUN_TEST(test_wrap_near);
    RUN_TEST(test_finite_sum);
    return smdt_summary("fastbuild");
}

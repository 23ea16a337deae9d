/*
 * Accuracy of the portable float math (smd_fmath.h) against double libm, in
 * ulp of the float result: |f(x) - F(x)| / ulp(F(x)) with F the double
 * function rounded to float. The bounds are those the header states; each
 * test sweeps a dense grid plus random arguments over the range the core
 * uses (angles, ratios of currents, exponents of -w T).
 */
#include <float.h>
#include <stdint.h>
#include <string.h>

#include "smd_test.h"
#include "smodrive/smd_fastmath.h"
#include "smodrive/smd_fmath.h"
#include "smodrive/smd_types.h"

/* ulp of the float nearest to r (r finite) */
static double ulp_of(double r)
{
    float f = (float)r;
    float n = nextafterf(fabsf(f), INFINITY);
    if (f == 0.0f) return 1.401298464324817e-45; /* the smallest subnormal float */
    return (double)n - (double)fabsf(f);
}

static double err_ulp(float got, double ref)
{
    return fabs((double)got - ref) / ulp_of(ref);
}

static uint32_t g_x = 2463534242u;
static double urand(double lo, double hi) { return smdt_urand(&g_x, lo, hi); }

static void test_sin_cos(void)
{
    double worst_s = 0.0, worst_c = 0.0;
    int k;
    for (k = 0; k < 500000; k++) {
        /* half within +-8 rad, half over the whole accurate range +-8192 rad */
        float x = (float)(k < 250000 ? urand(-8.0, 8.0) : urand(-8192.0, 8192.0));
        /* absolute error in units of 2^-24, the ulp of [0.5, 1) */
        double es = fabs((double)smd_sinf(x) - sin((double)x)) * 16777216.0;
        double ec = fabs((double)smd_cosf(x) - cos((double)x)) * 16777216.0;
        if (es > worst_s) worst_s = es;
        if (ec > worst_c) worst_c = ec;
    }
    printf("    sin worst %.3f, cos worst %.3f x 2^-24 absolute\n", worst_s, worst_c);
    CHECK(worst_s <= 1.5);
    CHECK(worst_c <= 1.5);
    /* exact points and non-finite arguments */
    CHECK(smd_sinf(0.0f) == 0.0f && smd_cosf(0.0f) == 1.0f);
    CHECK(isnan(smd_sinf(NAN)) && isnan(smd_cosf(INFINITY)) && isnan(smd_sinf(-INFINITY)));
    CHECK(isfinite(smd_sinf(1e30f)) && fabsf(smd_sinf(1e30f)) <= 1.0f);
}

static void test_atan2(void)
{
    double worst = 0.0;
    int k;
    for (k = 0; k < 500000; k++) {
        float y = (float)urand(-300.0, 300.0), x = (float)urand(-300.0, 300.0);
        double e;
        if (k % 3 == 0) x *= 1e-3f;
        e = err_ulp(smd_atan2f(y, x), atan2((double)y, (double)x));
        if (e > worst) worst = e;
    }
    printf("    atan2 worst %.3f ulp\n", worst);
    CHECK(worst <= 4.0);
    /* C99 special values */
    CHECK(smd_atan2f(0.0f, 1.0f) == 0.0f);
    CHECK(fabsf(smd_atan2f(0.0f, -1.0f) - 3.14159265f) < 1e-6f);
    CHECK(fabsf(smd_atan2f(1.0f, 0.0f) - 1.5707963f) < 1e-6f);
    CHECK(fabsf(smd_atan2f(-1.0f, INFINITY)) == 0.0f);
    CHECK(fabsf(smd_atan2f(INFINITY, INFINITY) - 0.78539816f) < 1e-6f);
    CHECK(isnan(smd_atan2f(NAN, 1.0f)) && isnan(smd_atan2f(1.0f, NAN)));
    /* the sign of a zero y against an infinite x (found by fuzz/fuzz_math:
     * atan2f(-0, -inf) gave +pi) */
    CHECK(smd_atan2f(-0.0f, -INFINITY) == -3.14159265f);
    CHECK(smd_atan2f(0.0f, -INFINITY) == 3.14159265f);
    CHECK(smd_atan2f(-0.0f, INFINITY) == 0.0f && signbit(smd_atan2f(-0.0f, INFINITY)));
}

static void test_exp(void)
{
    double worst = 0.0, worst_m1 = 0.0;
    int k;
    for (k = 0; k < 500000; k++) {
        float x = (float)(k % 2 ? urand(-80.0, 80.0) : urand(-2.0, 0.5));
        float z = (float)(k % 2 ? urand(-1e-3, 1e-3) : urand(-3.0, 3.0));
        double e = err_ulp(smd_expf(x), exp((double)x));
        double em = err_ulp(smd_expm1f(z), expm1((double)z));
        if (e > worst) worst = e;
        if (em > worst_m1) worst_m1 = em;
    }
    printf("    exp worst %.3f ulp, expm1 worst %.3f ulp\n", worst, worst_m1);
    CHECK(worst <= 1.0);
    CHECK(worst_m1 <= 2.0);
    CHECK(smd_expf(0.0f) == 1.0f && smd_expm1f(0.0f) == 0.0f);
    CHECK(isinf(smd_expf(100.0f)) && smd_expf(-200.0f) == 0.0f && isnan(smd_expf(NAN)));
}

/* The largest finite floats are not infinities (found by fuzz/fuzz_math:
 * the tests for an infinite argument were "above 3.4e38f", which takes
 * 3.4e38 < |x| <= FLT_MAX for infinite: atan2f(-99.3, FLT_MAX) gave -0 for
 * -2.9e-37, atan2f(FLT_MAX, 1e38) pi/2 for 1.28, and sinf, cosf both 0). */
static void test_huge_finite(void)
{
    const float big = FLT_MAX;
    const float ys[4] = {-99.3041916f, big, 1e38f, -big};
    const float xs[4] = {big, 1e38f, big, -3.39e38f};
    float r = fmodf(big, 6.28318530717958647692f); /* the documented reduction */
    int k;
    for (k = 0; k < 4; k++) {
        double want = atan2((double)ys[k], (double)xs[k]);
        double e = err_ulp(smd_atan2f(ys[k], xs[k]), want);
        if (!(e <= 4.0)) {
            printf("    atan2f(%.9g, %.9g) = %.9g, want %.9g\n", (double)ys[k], (double)xs[k],
                   (double)smd_atan2f(ys[k], xs[k]), want);
        }
        CHECK(e <= 4.0);
    }
    CHECK(fabs((double)smd_sinf(big) - sin((double)r)) <= 1.5 / 16777216.0);
    CHECK(fabs((double)smd_cosf(big) - cos((double)r)) <= 1.5 / 16777216.0);
    CHECK(fabs((double)smd_sinf(-big) + sin((double)r)) <= 1.5 / 16777216.0);
    CHECK(fabs((double)smd_cosf(3.4e38f) - cos((double)fmodf(3.4e38f, 6.28318530717958647692f))) <=
          1.5 / 16777216.0);
}

static int same_bits(float a, float b)
{
    uint32_t ua, ub;
    memcpy(&ua, &a, sizeof ua);
    memcpy(&ub, &b, sizeof ub);
    return ua == ub;
}

/* smd_sincosf gives the bits of smd_sinf and smd_cosf (the core's
 * e^{j theta} uses it through SMD_SINCOSF): every quadrant, both signs,
 * zeros of both signs, the huge-argument path, subnormals and non-finite
 * arguments (NaN payloads compared as NaN). */
static void test_sincos_same_bits(void)
{
    const float special[] = {0.0f, -0.0f, 1e-40f, -1e-40f, 0.7853982f, -0.7853982f,
                             1.5707964f, 3.1415927f, -3.1415927f, 4.712389f, 8191.9f, 8192.5f,
                             -1e30f, 1e30f, FLT_MAX, -FLT_MAX};
    const float nonfinite[] = {NAN, INFINITY, -INFINITY};
    int k, bad = 0;
    for (k = 0; k < 300000; k++) {
        float x, s, c;
        if (k < (int)(sizeof special / sizeof special[0])) {
            x = special[k];
        } else {
            x = (float)(k % 2 ? urand(-20.0, 20.0) : urand(-1e5, 1e5));
        }
        smd_sincosf(x, &s, &c);
        bad += !(same_bits(s, smd_sinf(x)) && same_bits(c, smd_cosf(x)));
    }
    CHECK(bad == 0);
    for (k = 0; k < 3; k++) {
        float s, c;
        smd_sincosf(nonfinite[k], &s, &c);
        CHECK(isnan(s) && isnan(c));
    }
}

/* The fast build's math (smd_fastmath.h) within its stated bounds: sin,
 * cos 1.5e-6 absolute for |x| <= 8192 rad, atan2 2.5e-6 rad, over 5e5
 * arguments each (dense near zero, whole range, the quadrant edges k pi/4
 * where the reduction switches); sincos the bits of sin and cos; beyond the
 * range and the special values the exact functions' results. A fast
 * function that is not near the bound would be hiding accuracy it does not
 * need to, so the worst error must also exceed a tenth of it (a check that
 * these are the short polynomials, not the exact ones). */
static void test_fast(void)
{
    double ws = 0.0, wc = 0.0, wa = 0.0;
    int k, bad = 0;
    for (k = 0; k < 500000; k++) {
        float x, s, c;
        double es, ec;
        if (k % 4 == 0) {
            x = (float)urand(-8.0, 8.0);
        } else if (k % 4 == 1) {
            x = (float)urand(-8192.0, 8192.0);
        } else if (k % 4 == 2) { /* the switch points of the reduction */
            x = (float)((double)((int)urand(-10000.0, 10000.0)) * 0.78539816339744831 +
                        urand(-1e-3, 1e-3));
        } else {
            x = (float)urand(-0.01, 0.01);
        }
        smd_fast_sincosf(x, &s, &c);
        bad += !(same_bits(s, smd_fast_sinf(x)) && same_bits(c, smd_fast_cosf(x)));
        es = fabs((double)s - sin((double)x));
        ec = fabs((double)c - cos((double)x));
        if (es > ws) ws = es;
        if (ec > wc) wc = ec;
    }
    for (k = 0; k < 500000; k++) {
        float y = (float)urand(-300.0, 300.0), x = (float)urand(-300.0, 300.0);
        double e;
        if (k % 3 == 0) x *= 1e-3f;
        if (k % 5 == 0) y *= 1e-4f;
        e = fabs((double)smd_fast_atan2f(y, x) - atan2((double)y, (double)x));
        if (e > wa) wa = e;
    }
    printf("    fast sin worst %.3g, cos %.3g, atan2 %.3g (bounds 1.5e-6, 1.5e-6, 2.5e-6)\n",
           ws, wc, wa);
    CHECK(ws <= 1.5e-6 && wc <= 1.5e-6 && wa <= 2.5e-6);
    CHECK(ws > 1.5e-7 && wa > 2.5e-7);
    CHECK(bad == 0);
    /* outside the range and the special values: the exact functions' */
    CHECK(same_bits(smd_fast_sinf(1e5f), smd_sinf(1e5f)));
    CHECK(same_bits(smd_fast_cosf(-9000.0f), smd_cosf(-9000.0f)));
    CHECK(isnan(smd_fast_sinf(NAN)) && isnan(smd_fast_cosf(INFINITY)));
    CHECK(smd_fast_sinf(0.0f) == 0.0f && smd_fast_cosf(0.0f) == 1.0f);
    CHECK(same_bits(smd_fast_atan2f(-0.0f, -1.0f), smd_atan2f(-0.0f, -1.0f)));
    CHECK(same_bits(smd_fast_atan2f(-0.0f, 0.0f), smd_atan2f(-0.0f, 0.0f)));
    CHECK(same_bits(smd_fast_atan2f(1.0f, -INFINITY), smd_atan2f(1.0f, -INFINITY)));
    CHECK(isnan(smd_fast_atan2f(NAN, 1.0f)));
    CHECK(fabsf(smd_fast_atan2f(-1.0f, -1.0f) + 2.3561945f) < 2.5e-6f);
}

/* smd_floor_small and smd_floor (smd_types.h, the angle wrap's floor; the
 * first is what smd_floor takes on the Cortex-M4F, tested here on the host
 * too) give floorf's bits: integers and half-integers of both signs, +-0,
 * values next to integers, the 2^23 edge, 3e5 random arguments within +-1e4
 * and +-1e8 (smd_floor_small within its range +-2^23), and the non-finite
 * ones. */
static void test_floor_same_bits(void)
{
#ifdef SMD_REAL_DOUBLE
    CHECK(smd_floor(-2.5) == -3.0 && smd_floor(2.5) == 2.0); /* the double build: SMD_FLOOR */
#else
    const float special[] = {0.0f, -0.0f, 0.5f, -0.5f, 1.0f, -1.0f, 1.5f, -1.5f, 2.0f, -2.0f,
                             0.99999994f, -0.99999994f, 1.0000001f, -1.0000001f, 8388607.5f,
                             -8388607.5f, 8388608.0f, -8388608.0f, 8388609.0f, -8388609.0f,
                             1e-40f, -1e-40f, FLT_MAX, -FLT_MAX, 3e9f, -3e9f};
    int k, bad = 0;
    for (k = 0; k < (int)(sizeof special / sizeof special[0]); k++) {
        bad += !same_bits(smd_floor(special[k]), floorf(special[k]));
        if (fabsf(special[k]) < 8388608.0f) {
            bad += !same_bits(smd_floor_small(special[k]), floorf(special[k]));
        }
    }
    for (k = 0; k < 300000; k++) {
        float x = (float)(k % 2 ? urand(-1e4, 1e4) : urand(-1e8, 1e8));
        bad += !same_bits(smd_floor(x), floorf(x));
        if (fabsf(x) < 8388608.0f) {
            bad += !same_bits(smd_floor_small(x), floorf(x));
        }
    }
    CHECK(bad == 0);
    CHECK(isnan(smd_floor(NAN)) && smd_floor(INFINITY) == INFINITY &&
          smd_floor(-INFINITY) == -INFINITY);
#endif
}

int main(void)
{
    RUN_TEST(test_sin_cos);
    RUN_TEST(test_sincos_same_bits);
    RUN_TEST(test_atan2);
    RUN_TEST(test_exp);
    RUN_TEST(test_huge_finite);
    RUN_TEST(test_fast);
    RUN_TEST(test_floor_same_bits);
    return smdt_summary("fmath");
}

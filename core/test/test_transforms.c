/*
 * Clarke / Park transforms (amplitude invariant, yang2018 Sec. II-A).
 *
 * Tolerances: every output is a short expression (<= 4 roundings) of O(1)
 * inputs, plus one sin/cos of |theta| <= pi for Park (glibc sinf/cosf are
 * within 1 ulp). The error is therefore below ~4 eps |x|; we allow 8 eps |x|.
 * A wrong factor (e.g. 2/3 vs 1, sqrt3 vs 1/sqrt3) or a wrong sign gives an
 * error of O(|x|), 10^5..10^14 times larger.
 */
#include "smd_test.h"
#include "smodrive/smd_transforms.h"

static void test_clarke_known_values(void)
{
    /* a = 1, b = c = -1/2: the vector on the alpha axis with amplitude 1 */
    smd_real x1[3] = {R(1.0), R(-0.5), R(-0.5)};
    /* a = 0, b = sqrt3/2, c = -sqrt3/2: amplitude 1 on the beta axis */
    smd_real x2[3] = {R(0.0), R(0.86602540378443864676), R(-0.86602540378443864676)};
    CHECK_CPLX(smd_abc_to_ab(x1), 1.0, 4 * SMDT_EPS);
    CHECK_CPLX(smd_abc_to_ab(x2), 1.0 * JD, 4 * SMDT_EPS);
    /* two-phase measurement: i_a = 1, i_b = -1/2 -> (1, 0); i_a = 0, i_b = sqrt3/2 -> j */
    CHECK_CPLX(smd_ab2_to_ab(R(1.0), R(-0.5)), 1.0, 4 * SMDT_EPS);
    CHECK_CPLX(smd_ab2_to_ab(R(0.0), R(0.86602540378443864676)), 1.0 * JD, 4 * SMDT_EPS);
}

/* A balanced three-phase set A cos(phi - k 2pi/3) maps to A e^{j phi}
 * (amplitude invariance), whatever zero sequence x0 is added. */
static void test_clarke_balanced_set(void)
{
    unsigned long st = 1;
    int n;
    for (n = 0; n < 200; n++) {
        double A = smdt_rand(&st, 0.1, 300.0);
        double phi = smdt_rand(&st, -PI_D, PI_D);
        double x0 = smdt_rand(&st, -100.0, 100.0);
        double complex ref = A * cexp(JD * phi);
        smd_real x[3];
        smd_real y[3];
        int k;
        for (k = 0; k < 3; k++) {
            x[k] = R(A * cos(phi - 2.0 * PI_D * k / 3.0));
            y[k] = R(A * cos(phi - 2.0 * PI_D * k / 3.0) + x0);
        }
        /* scale: inputs up to A + |x0|, two roundings of the inputs themselves */
        CHECK_CPLX(smd_abc_to_ab(x), ref, 8 * SMDT_EPS * A);
        CHECK_CPLX(smd_abc_to_ab(y), ref, 8 * SMDT_EPS * (A + fabs(x0)));
        CHECK_CPLX(smd_ab2_to_ab(x[0], x[1]), ref, 8 * SMDT_EPS * A);
    }
}

/* Three sensors: smd_abc_to_ab2 gives the two inputs whose two-phase Clarke
 * is the three-phase one (zero sequence rejected), and per-phase gains
 * then leave the vector's positive sequence unturned, where two sensors
 * turn it by -(g_b - g_a) / (2 sqrt 3). The positive sequence is the mean of
 * x_ab e^{-j phi} / A over a turn of phi (200 points: the negative sequence,
 * e^{-j 2 phi}, sums to zero exactly up to the roundings, 8 eps). With
 * g_b - g_a = 0.01 the two-sensor turn is 2.9e-3 rad: a swap of the two paths,
 * or a sign error, misses by that, 10^4 times the tolerance. */
static void test_three_sensors(void)
{
    const double g[3] = {-0.004, 0.006, 0.003};
    const double d = g[1] - g[0];
    double complex p2 = 0.0, p3 = 0.0;
    int n;
    for (n = 0; n < 200; n++) {
        double phi = 2.0 * PI_D * n / 200.0;
        smd_real x[3], xa, xb;
        int k;
        for (k = 0; k < 3; k++) {
            x[k] = R((1.0 + g[k]) * 10.0 * cos(phi - 2.0 * PI_D * k / 3.0) + 3.0);
        }
        smd_abc_to_ab2(x, &xa, &xb);
        CHECK_CPLX(smd_ab2_to_ab(xa, xb), (double complex)smd_abc_to_ab(x).re +
                   JD * (double)smd_abc_to_ab(x).im, 16 * SMDT_EPS * 13.0);
        CHECK_CLOSE((double)xa + (double)xb + (double)(-xa - xb), 0.0, 4 * SMDT_EPS * 13.0);
        {
            smd_cplx v2 = smd_ab2_to_ab(x[0] - R(3.0), x[1] - R(3.0));
            smd_cplx v3 = smd_ab2_to_ab(xa, xb);
            p2 += ((double)v2.re + JD * (double)v2.im) * cexp(-JD * phi) / 2000.0;
            p3 += ((double)v3.re + JD * (double)v3.im) * cexp(-JD * phi) / 2000.0;
        }
    }
    CHECK_CLOSE(cimag(p3), 0.0, 8 * SMDT_EPS);
    CHECK_CLOSE(creal(p3), 1.0 + (g[0] + g[1] + g[2]) / 3.0, 8 * SMDT_EPS);
    CHECK_CLOSE(cimag(p2), -d / (2.0 * sqrt(3.0)), 8 * SMDT_EPS);
    CHECK_CLOSE(creal(p2), 1.0 + g[0] + d / 2.0, 8 * SMDT_EPS);
}

/* ab -> abc: known values, zero sum and the round trip back to ab. */
static void test_inverse_clarke(void)
{
    unsigned long st = 7;
    smd_real abc[3];
    int n;
    smd_ab_to_abc(smd_c(R(2.0), R(0.0)), abc);
    CHECK_CLOSE(abc[0], 2.0, 4 * SMDT_EPS);
    CHECK_CLOSE(abc[1], -1.0, 4 * SMDT_EPS);
    CHECK_CLOSE(abc[2], -1.0, 4 * SMDT_EPS);
    smd_ab_to_abc(smd_c(R(0.0), R(1.0)), abc);
    CHECK_CLOSE(abc[0], 0.0, 4 * SMDT_EPS);
    CHECK_CLOSE(abc[1], 0.86602540378443864676, 4 * SMDT_EPS);
    CHECK_CLOSE(abc[2], -0.86602540378443864676, 4 * SMDT_EPS);
    for (n = 0; n < 200; n++) {
        double complex z = smdt_rand(&st, -500, 500) + smdt_rand(&st, -500, 500) * JD;
        double m = cabs(z);
        int k;
        smd_ab_to_abc(smdt_c(z), abc);
        for (k = 0; k < 3; k++) {
            /* x_k = Re(z e^{-j 2 pi k / 3}) */
            CHECK_CLOSE(abc[k], creal(z * cexp(-JD * 2.0 * PI_D * k / 3.0)), 8 * SMDT_EPS * m);
        }
        CHECK_CLOSE((double)abc[0] + (double)abc[1] + (double)abc[2], 0.0, 8 * SMDT_EPS * m);
        CHECK_CPLX(smd_abc_to_ab(abc), z, 8 * SMDT_EPS * m);
    }
}

/* Park: x_dq = x_ab e^{-j theta}; known values, round trip, magnitude kept. */
static void test_park(void)
{
    unsigned long st = 3;
    int n;
    /* alpha-axis vector seen from a frame at +90 degrees lies on -q */
    CHECK_CPLX(smd_ab_to_dq(smd_c(R(1.0), R(0.0)), R(1.57079632679489661923)), -1.0 * JD,
               8 * SMDT_EPS);
    /* d-axis vector at theta = pi/3 -> (1/2, sqrt3/2) */
    CHECK_CPLX(smd_dq_to_ab(smd_c(R(1.0), R(0.0)), R(1.04719755119659774615)),
               0.5 + 0.86602540378443864676 * JD, 8 * SMDT_EPS);
    for (n = 0; n < 200; n++) {
        double complex z = smdt_rand(&st, -50, 50) + smdt_rand(&st, -50, 50) * JD;
        double th = smdt_rand(&st, -PI_D, PI_D);
        double m = cabs(z);
        smd_cplx dq = smd_ab_to_dq(smdt_c(z), R(th));
        CHECK_CPLX(dq, z * cexp(-JD * th), 8 * SMDT_EPS * m);
        CHECK_CPLX(smd_dq_to_ab(dq, R(th)), z, 16 * SMDT_EPS * m);
        CHECK_CLOSE(smd_cabs(dq), m, 8 * SMDT_EPS * m);
    }
}

/* smd_table_interp (the observers' speed tables): every field, for field
 * counts that leave 0-3 values after the four-at-a-time part, is exactly
 * a + f (b - a) of its two neighbouring rows (the same operations as the
 * plain loop, so bit for bit), clamped to the first and last rows outside
 * the table. A field skipped, a row off by one or a wrong remainder loop
 * differs by a table step (>= 1 here). */
static void test_table_interp(void)
{
    enum { NR = 4, NF_MAX = 13 };
    smd_real table[NR * NF_MAX];
    smd_real out[NF_MAX + 1];
    const smd_real w_min = R(100.0), dw = R(50.0);
    const smd_real ws[6] = {R(-1e4), R(100.0), R(137.5), R(220.0), R(250.0), R(1e6)};
    int nf, i, j;
    for (nf = 1; nf <= NF_MAX; nf++) {
        for (i = 0; i < NR * nf; i++) {
            table[i] = (smd_real)(i * i % 17) + R(0.25) * (smd_real)i;
        }
        for (j = 0; j < 6; j++) {
            smd_real x = (ws[j] - w_min) / dw, f;
            int k;
            if (!(x > R(0.0))) x = R(0.0);
            if (x > (smd_real)(NR - 1)) x = (smd_real)(NR - 1);
            k = (int)x;
            if (k > NR - 2) k = NR - 2;
            f = x - (smd_real)k;
            out[nf] = R(-7.0); /* sentinel: written beyond nf is an error */
            smd_table_interp(table, nf, NR, w_min, dw, ws[j], out);
            for (i = 0; i < nf; i++) {
                smd_real a = table[k * nf + i], b = table[(k + 1) * nf + i];
                CHECK(out[i] == a + f * (b - a));
            }
            CHECK(out[nf] == R(-7.0));
        }
    }
}

int main(void)
{
    RUN_TEST(test_clarke_known_values);
    RUN_TEST(test_clarke_balanced_set);
    RUN_TEST(test_three_sensors);
    RUN_TEST(test_inverse_clarke);
    RUN_TEST(test_park);
    RUN_TEST(test_table_interp);
    return smdt_summary("test_transforms");
}

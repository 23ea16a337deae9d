/*
 * libFuzzer target: the portable float math (smd_sinf, smd_cosf,
 * smd_sincosf, smd_atan2f, smd_expf, smd_expm1f), the transforms (smd_abc_to_ab, smd_ab2_to_ab,
 * smd_ab_to_abc, smd_ab_to_dq, smd_dq_to_ab), the inline helpers of
 * smd_types.h (smd_wrap_pi, smd_cabs, smd_cexpj, smd_table_interp, the range
 * checks, smd_check_model) and smd_status_str, on values decoded from the
 * input (fuzz.h): op byte, then the operands.
 *
 * Checked besides the sanitizers: the documented accuracy of smd_fmath.h
 * against the double C library (loosened: sin, cos 2^-22 absolute for
 * |x| <= 8192; atan2 8 ulp; exp, expm1 4 ulp where the result is normal),
 * the ranges (|sin|, |cos| <= 1, atan2 in [-pi, pi], exp >= 0, expm1 >= -1),
 * NaN in gives NaN out, smd_sincosf gives the bits of smd_sinf and
 * smd_cosf, and the interpolation stays between its rows.
 */
#include "fuzz.h"

#include "smodrive/smd_fmath.h"
#include "smodrive/smd_transforms.h"


/* |got - want| within k ulp of want (float), for a normal want */
static int near_ulp(float got, double want, double k)
{
    double ulp;
    if (!(fabs(want) >= (double)FLT_MIN) || !(fabs(want) <= (double)FLT_MAX)) {
        return 1; /* subnormal, zero or overflowing: not checked */
    }
    ulp = ldexp(1.0, ilogb(want) - 23);
    return fabs((double)got - want) <= k * ulp;
}

static void check_fmath(fz *f)
{
    float x = (float)fz_real(f, -100.0, 100.0);
    float y = (float)fz_real(f, -100.0, 100.0);
    float s = smd_sinf(x), c = smd_cosf(x), a = smd_atan2f(y, x);
    float e = smd_expf(x), m = smd_expm1f(x);
    float s2, c2;
    smd_sincosf(x, &s2, &c2);
    /* the same bits (NaN compared as NaN) */
    FZ_CHECK(isnan(s) ? isnan(s2) : memcmp(&s, &s2, sizeof s) == 0);
    FZ_CHECK(isnan(c) ? isnan(c2) : memcmp(&c, &c2, sizeof c) == 0);
    if (isnan(x)) {
        FZ_CHECK(isnan(s) && isnan(c) && isnan(e) && isnan(m) && isnan(a));
        return;
    }
    if (isinf(x)) {
        FZ_CHECK(isnan(s) && isnan(c));
    } else {
        FZ_CHECK(fabsf(s) <= 1.0f && fabsf(c) <= 1.0f);
        /* a unit vector whatever the argument (beyond 8192 rad the angle is
         * not accurate, but e^{jx} stays on the unit circle) */
        FZ_CHECK(fabs((double)s * (double)s + (double)c * (double)c - 1.0) < 1e-6);
        if (fabsf(x) <= 8192.0f) {
            FZ_CHECK(fabs((double)s - sin((double)x)) <= 2.4e-7);
            FZ_CHECK(fabs((double)c - cos((double)x)) <= 2.4e-7);
        }
    }
    if (isnan(y)) {
        FZ_CHECK(isnan(a));
    } else {
        double want = atan2((double)y, (double)x);
        FZ_CHECK(a >= -3.1415927f && a <= 3.1415927f);
        if (!near_ulp(a, want, 8.0)) {
            fprintf(stderr, "atan2f(%.9g, %.9g) = %.9g, want %.17g\n", (double)y, (double)x,
                    (double)a, want);
        }
        FZ_CHECK(near_ulp(a, want, 8.0));
    }
    FZ_CHECK(e >= 0.0f && m >= -1.0f);
    FZ_CHECK(near_ulp(e, exp((double)x), 4.0));
    FZ_CHECK(near_ulp(m, expm1((double)x), 4.0));
}

static void check_transforms(fz *f)
{
    smd_real abc[3], back[3];
    smd_cplx z, dq, ab;
    smd_real th;
    abc[0] = fz_r(f, -1e3, 1e3);
    abc[1] = fz_r(f, -1e3, 1e3);
    abc[2] = fz_r(f, -1e3, 1e3);
    th = fz_r(f, -10.0, 10.0);
    z = smd_abc_to_ab(abc);
    fz_use_c(z);
    fz_use_c(smd_ab2_to_ab(abc[0], abc[1]));
    smd_ab_to_abc(z, back);
    fz_use((double)(back[0] + back[1] + back[2]));
    dq = smd_ab_to_dq(z, th);
    ab = smd_dq_to_ab(dq, th);
    fz_use_c(ab);
    fz_use((double)smd_cabs(z));
    fz_use_c(smd_cexpj(th));
    fz_use_c(smd_cmul(z, dq));
    fz_use((double)smd_wrap_pi(th));
    fz_use((double)smd_wrap_pi(abc[0]));
}

static void check_helpers(fz *f)
{
    smd_real x = fz_r(f, -10.0, 10.0), lo = fz_r(f, -10.0, 10.0), hi = fz_r(f, -10.0, 10.0);
    smd_status st;
    int r = smd_in_range(x, lo, hi);
    FZ_CHECK(!r || (isfinite(x) && x >= lo && x <= hi));
    FZ_CHECK(!smd_in_pos_range(x, hi) || x > SMD_R(0.0));
    {
        smd_real T = fz_r(f, 0.0, 2.0), L = fz_r(f, 0.0, 20.0), Rs = fz_r(f, -1.0, 2000.0);
        st = smd_check_model(T, L, Rs);
    }
    fz_use((double)st);
    {
        const char *txt = smd_status_str((smd_status)fz_int(f, -1, 40));
        FZ_CHECK(txt != 0 && txt[0] != 0);
    }
}

/* smd_table_interp on an n x nf table of the input's values, malloc'ed to
 * its exact size: the output stays between the rows it interpolates. */
static void check_interp(fz *f)
{
    int n = fz_int(f, 2, 9), nf = fz_int(f, 1, 6), k, i;
    smd_real w_min, dw, w, out[6];
    smd_real *t;
    if (n < 2 || n > 9 || nf < 1 || nf > 6) {
        return; /* the callers' contract: n >= 2 rows exist */
    }
    t = (smd_real *)malloc((size_t)(n * nf) * sizeof(smd_real));
    for (k = 0; k < n * nf; k++) {
        t[k] = fz_r(f, -10.0, 10.0);
    }
    w_min = fz_r(f, -1e3, 1e3);
    dw = fz_r(f, 0.0, 1e3);
    w = fz_r(f, -1e4, 1e4);
    if (!(dw > SMD_R(0.0) && isfinite(dw) && isfinite(w_min))) {
        free(t);
        return;
    }
    smd_table_interp(t, nf, n, w_min, dw, w, out);
    for (i = 0; i < nf; i++) {
        smd_real lo = t[i], hi = t[i];
        int all_finite = 1;
        for (k = 0; k < n; k++) {
            smd_real v = t[k * nf + i];
            all_finite = all_finite && isfinite(v);
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
        /* between the smallest and largest value of the column (with a
         * rounding margin), when the column is finite and not huge */
        if (all_finite && fabsf((float)lo) < 1e30f && fabsf((float)hi) < 1e30f) {
            smd_real tol = SMD_R(1e-5) * (SMD_R(1.0) + hi - lo);
            FZ_CHECK(out[i] >= lo - tol && out[i] <= hi + tol);
        }
    }
    free(t);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz f = {data, size};
    int ops = 0;
    while (fz_more(&f) && ops < 256) {
        switch (fz_u8(&f) % 4) {
        case 0: check_fmath(&f); break;
        case 1: check_transforms(&f); break;
        case 2: check_helpers(&f); break;
        default: check_interp(&f); break;
        }
        ops++;
    }
    return 0;
}

/*
 * Portable single-precision math (smd_fmath.h): the same bits on every
 * IEEE-754 float unit, built only from +, -, *, /, conversions to and from
 * integers, fmodf and ldexpf, which IEEE 754 and C99 define exactly.
 */
#include "smodrive/smd_fmath.h"

#include <float.h>
#include <math.h>

/* pi/4 in three parts (Cody-Waite): DP1 + DP2 + DP3 = pi/4 to ~2^-60, DP1
 * and DP2 with trailing zeros so that j * DPi is exact for j < 2^13. */
#define SMD_DP1 0.78515625f
#define SMD_DP2 2.4187564849853515625e-4f
#define SMD_DP3 3.77489497744594108e-8f
#define SMD_FOPI 1.27323954473516f /* 4/pi */
#define SMD_TWO_PI_F 6.28318530717958647692f
#define SMD_REDUCE_MAX 8192.0f

/* floor(x) for |x| < 2^23 through the integer conversion (VCVT on a
 * Cortex-M4F: one cycle, where newlib's floorf is a bit-twiddling call) */
static float floor_small(float x)
{
    float f = (float)(long)x;
    return f > x ? f - 1.0f : f;
}

/* sin(r) and cos(r) for |r| <= pi/4 (Cephes sinf/cosf minimax fits). */
static float sin_poly(float r)
{
    float z = r * r;
    return ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * r + r;
}

static float cos_poly(float r)
{
    float z = r * r;
    return ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) *
               z * z -
           0.5f * z + 1.0f;
}

/* x = j pi/4 + r with j even (octant pair), |r| <= pi/4; returns r and the
 * quadrant q = (j / 2) mod 4 of |x|. */
static float reduce(float ax, int *q)
{
    float j;
    int ji;
    if (ax > SMD_REDUCE_MAX) {
        ax = fmodf(ax, SMD_TWO_PI_F); /* exact remainder of a float 2 pi */
    }
    j = floor_small(ax * SMD_FOPI); /* ax <= 8192: the product < 2^14 */
    ji = (int)j;
    if (ji & 1) {
        ji += 1;
        j += 1.0f;
    }
    *q = (ji >> 1) & 3;
    return ((ax - j * SMD_DP1) - j * SMD_DP2) - j * SMD_DP3;
}

float smd_sinf(float x)
{
    float ax = x < 0.0f ? -x : x;
    float r, y;
    int q, neg = x < 0.0f;
    if (!(ax <= FLT_MAX)) {
        return x - x; /* NaN for NaN and +-inf */
    }
    r = reduce(ax, &q);
    switch (q) {
    case 0: y = sin_poly(r); break;
    case 1: y = cos_poly(r); break;
    case 2: y = -sin_poly(r); break;
    default: y = -cos_poly(r); break;
    }
    return neg ? -y : y;
}

float smd_cosf(float x)
{
    float ax = x < 0.0f ? -x : x;
    float r;
    int q;
    if (!(ax <= FLT_MAX)) {
        return x - x;
    }
    r = reduce(ax, &q);
    switch (q) {
    case 0: return cos_poly(r);
    case 1: return -sin_poly(r);
    case 2: return -cos_poly(r);
    default: return sin_poly(r);
    }
}

void smd_sincosf(float x, float *s, float *c)
{
    float ax = x < 0.0f ? -x : x;
    float r, sp, cp;
    int q;
    if (!(ax <= FLT_MAX)) {
        *s = x - x;
        *c = x - x;
        return;
    }
    r = reduce(ax, &q);
    sp = sin_poly(r);
    cp = cos_poly(r);
    switch (q) {
    case 0: *s = sp; *c = cp; break;
    case 1: *s = cp; *c = -sp; break;
    case 2: *s = -sp; *c = -cp; break;
    default: *s = -cp; *c = sp; break;
    }
    if (x < 0.0f) {
        *s = -*s;
    }
}

/* atan(t) for t >= 0 (Cephes atanf): reduced to |t| <= tan(pi/8). */
static float atan_pos(float t)
{
    float y, z;
    if (t > 2.414213562373095f) {
        y = 1.5707963267948966f;
        t = -1.0f / t;
    } else if (t > 0.4142135623730950f) {
        y = 0.7853981633974483f;
        t = (t - 1.0f) / (t + 1.0f);
    } else {
        y = 0.0f;
    }
    z = t * t;
    return y + (((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z -
                3.33329491539e-1f) *
                   z * t +
           t;
}

float smd_atan2f(float y, float x)
{
    const float pi = 3.14159265358979f, pi_2 = 1.5707963267948966f;
    float ay = y < 0.0f ? -y : y, ax = x < 0.0f ? -x : x, a;
    if (y != y || x != x) {
        return x + y;
    }
    if (ax == 0.0f && ay == 0.0f) {
        a = 0.0f; /* atan2(+-0, +-0): 0 or pi by the sign of x, as C99 */
        if (signbit(x)) a = pi;
        return signbit(y) ? -a : a;
    }
    if (ax > FLT_MAX || ay > FLT_MAX) { /* an infinity */
        if (ax > FLT_MAX && ay > FLT_MAX) {
            a = x > 0.0f ? 0.7853981633974483f : 2.356194490192345f;
        } else if (ax > FLT_MAX) {
            a = x > 0.0f ? 0.0f : pi;
        } else {
            a = pi_2;
        }
        return signbit(y) ? -a : a; /* atan2(-0, -inf) = -pi, as C99 */
    }
    if (ay <= ax) {
        a = atan_pos(ay / ax);
    } else {
        a = pi_2 - atan_pos(ax / ay);
    }
    if (x < 0.0f || (x == 0.0f && signbit(x))) {
        a = pi - a;
    }
    return (y < 0.0f || (y == 0.0f && signbit(y))) ? -a : a;
}

float smd_expf(float x)
{
    float z, p, xx;
    int n;
    if (x != x) {
        return x;
    }
    if (x > 88.72283905206835f) {
        return x * 1e30f * 1e30f; /* +inf */
    }
    if (x < -103.972084f) {
        return 0.0f;
    }
    /* x = n ln2 + r, |r| <= ln2/2; ln2 = C1 + C2 with C1 exact in 9 bits */
    z = floor_small(1.44269504088896341f * x + 0.5f); /* |.| < 151 */
    n = (int)z;
    x = (x - z * 0.693359375f) - z * -2.12194440e-4f;
    xx = x * x;
    p = ((((( 1.9875691500e-4f * x + 1.3981999507e-3f) * x + 8.3334519073e-3f) * x +
           4.1665795894e-2f) * x + 1.6666665459e-1f) * x + 5.0000001201e-1f) * xx + x + 1.0f;
    return ldexpf(p, n);
}

float smd_expm1f(float x)
{
    float ax = x < 0.0f ? -x : x;
    if (ax < 0.7f) {
        /* Taylor to x^10: the first omitted term is < 0.7^10 / 11! < 2^-30 of x */
        float s = 1.0f / 3628800.0f;
        s = s * x + 1.0f / 362880.0f;
        s = s * x + 1.0f / 40320.0f;
        s = s * x + 1.0f / 5040.0f;
        s = s * x + 1.0f / 720.0f;
        s = s * x + 1.0f / 120.0f;
        s = s * x + 1.0f / 24.0f;
        s = s * x + 1.0f / 6.0f;
        s = s * x + 0.5f;
        return x + x * x * s;
    }
    return smd_expf(x) - 1.0f;
}

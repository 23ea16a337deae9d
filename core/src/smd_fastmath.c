/*
 * Fast portable single-precision sin, cos and atan2 (smd_fastmath.h): the
 * error bounds and their reasons are in the header.
 */
#include "smodrive/smd_fastmath.h"
#include "smodrive/smd_types.h" /* (SMD_FIXED_INLINE) */

#include <math.h>
#include <stdint.h>

#define SMD_FAST_REDUCE_MAX 8192.0f
#define SMD_TWO_OVER_PI 0.636619772367581343f
#define SMD_PIO2_HI 1.5703125f          /* 201/128: k x it is exact for |k| < 2^16 */
#define SMD_PIO2_LO 4.83826794896619e-4f /* pi/2 - SMD_PIO2_HI */

/* x = k pi/2 + r, |r| <= pi/4 (plus rounding); k mod 4 in *q. |x| <= 8192. */
static float reduce_fast(float x, int *q)
{
    const float y = x * SMD_TWO_OVER_PI;
    const int k = (int)(y + (y >= 0.0f ? 0.5f : -0.5f));
    const float fk = (float)k;
    *q = k & 3; /* two's complement: -1 -> 3 */
    return (x - fk * SMD_PIO2_HI) - fk * SMD_PIO2_LO;
}

/* near-minimax on |r| <= pi/4 (fit errors 9.4e-7 and 6.7e-8) */
static float sin_fast(float r)
{
    const float z = r * r;
    return (8.15299e-3f * z - 1.6662834e-1f) * z * r + r;
}

static float cos_fast(float r)
{
    const float z = r * r;
    return (-1.36524e-3f * z + 4.166128e-2f) * z * z - 0.5f * z + 1.0f;
}

float smd_fast_sinf(float x)
{
    float r;
    int q;
    if (!(x <= SMD_FAST_REDUCE_MAX && x >= -SMD_FAST_REDUCE_MAX)) {
        return smd_sinf(x); /* NaN, inf, or an angle too large to be a good one */
    }
    r = reduce_fast(x, &q);
    switch (q) {
    case 0: return sin_fast(r);
    case 1: return cos_fast(r);
    case 2: return -sin_fast(r);
    default: return -cos_fast(r);
    }
}

float smd_fast_cosf(float x)
{
    float r;
    int q;
    if (!(x <= SMD_FAST_REDUCE_MAX && x >= -SMD_FAST_REDUCE_MAX)) {
        return smd_cosf(x);
    }
    r = reduce_fast(x, &q);
    switch (q) {
    case 0: return cos_fast(r);
    case 1: return -sin_fast(r);
    case 2: return -cos_fast(r);
    default: return sin_fast(r);
    }
}

SMD_FIXED_INLINE void smd_fast_sincosf(float x, float *s, float *c)
{
    float r, sp, cp;
    int q;
    if (!(x <= SMD_FAST_REDUCE_MAX && x >= -SMD_FAST_REDUCE_MAX)) {
        *s = smd_sinf(x);
        *c = smd_cosf(x);
        return;
    }
    r = reduce_fast(x, &q);
    sp = sin_fast(r);
    cp = cos_fast(r);
    switch (q) {
    case 0: *s = sp; *c = cp; break;
    case 1: *s = cp; *c = -sp; break;
    case 2: *s = -sp; *c = -cp; break;
    default: *s = -cp; *c = sp; break;
    }
}

/* A float's bits and back (C99: through a union). */
static uint32_t f2u(float x)
{
    union {
        float f;
        uint32_t u;
    } v;
    v.f = x;
    return v.u;
}

static float u2f(uint32_t u)
{
    union {
        float f;
        uint32_t u;
    } v;
    v.u = u;
    return v.f;
}

/* The tests on the bit patterns: doubled (the sign shifted out) they are in
 * the order of the magnitudes, infinity's is 0xff000000 and the NaNs' above
 * it; the signs are the top bits (x < 0 or x = -0 is signbit(x) when x is
 * not a NaN). The values are those of the tests in floats, without a VMRS
 * and a branch each. */
float smd_fast_atan2f(float y, float x)
{
    const float pi = 3.14159265358979f, pi_2 = 1.5707963267948966f;
    const uint32_t ux = f2u(x), uy = f2u(y);
    const uint32_t ax2 = ux << 1, ay2 = uy << 1;
    const int swap = ay2 > ax2;
    const float ax = u2f(ux & 0x7fffffffu), ay = u2f(uy & 0x7fffffffu);
    float t, z, a;
    if ((swap ? ay2 : ax2) - 1u >= 0xfeffffffu) {
        return smd_atan2f(y, x); /* NaN, inf, both zero: C99's special cases */
    }
    t = swap ? ax / ay : ay / ax; /* in [0, 1] */
    z = t * t;
    /* near-minimax on [0, 1] (fit error 1.7e-6) */
    a = t * (9.999772e-1f +
             z * (-3.326228e-1f +
                  z * (1.935403e-1f + z * (-1.164264e-1f + z * (5.264724e-2f - 1.171909e-2f * z)))));
    if (swap) {
        a = pi_2 - a;
    }
    if (ux >> 31) {
        a = pi - a;
    }
    return u2f(f2u(a) ^ (uy & 0x80000000u));
}

/*
 * smodrive fast float math: sin, cos and atan2 for the fast firmware build
 * (docs/firmware.md, "Fast build"), portable like smd_fmath.h (+, -, *, /
 * and integer conversions only: the same bits on every IEEE-754 target) but
 * with shorter polynomials and a one-step argument reduction instead of
 * being accurate to the last bit. Mapped into the core with the math hooks
 * of smd_types.h,
 *
 *   -DSMD_MATH_HEADER='"smodrive/smd_fastmath.h"' -DSMD_SINF=smd_fast_sinf
 *   -DSMD_COSF=smd_fast_cosf -DSMD_SINCOSF=smd_fast_sincosf
 *   -DSMD_ATAN2F=smd_fast_atan2f -DSMD_EXPF=smd_expf -DSMD_EXPM1F=smd_expm1f
 *
 * Error bounds (core/test/test_fmath.c checks each over 5e5 arguments
 * against double libm, the quadrant edges among them):
 *   sin, cos   |error| <= 1.5e-6 absolute for |x| <= 8192 rad: x = k pi/2 + r
 *              with k the nearest integer and pi/2 in two parts (the first
 *              exact in 8 bits, so k pi/2_hi is exact for |k| < 2^16), then
 *              r - r^3/6 + ... of degree 5 and 1 - r^2/2 + ... of degree 6,
 *              near-minimax on |r| <= pi/4 (fit errors 9.4e-7 and 6.7e-8;
 *              the rest is float rounding); beyond 8192 rad, NaN and inf
 *              they are smd_sinf, smd_cosf (an angle that large is a fault)
 *   atan2      |error| <= 2.5e-6 rad: the smaller of |y|, |x| over the larger
 *              (one division), atan of it by an odd polynomial of degree 11
 *              (fit error 1.7e-6 on [0, 1]), then the octant; zeros, NaN and
 *              inf are smd_atan2f's (C99's special cases)
 * The angle a drive uses carries far more error than this: a 12-bit ADC's
 * quantum is 2.4e-4 of its full scale, and the estimators' noise is larger
 * still. exp and expm1 (the init's filter coefficients) stay smd_fmath's.
 */
#ifndef SMD_FASTMATH_H
#define SMD_FASTMATH_H

#include "smodrive/smd_fmath.h"

#ifdef __cplusplus
extern "C" {
#endif

float smd_fast_sinf(float x);
float smd_fast_cosf(float x);
/* *s = smd_fast_sinf(x) and *c = smd_fast_cosf(x), bit for bit. */
void smd_fast_sincosf(float x, float *s, float *c);
float smd_fast_atan2f(float y, float x);

#ifdef __cplusplus
}
#endif

#endif

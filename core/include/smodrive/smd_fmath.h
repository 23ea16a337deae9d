/*
 * smodrive portable float math: sin, cos, atan2, exp and expm1 in single
 * precision from +, -, *, / and integer conversions alone, so that every IEEE-754 target
 * computes the same bits (no libm, no double, no FMA: the core is built with
 * -ffp-contract=off).
 *
 * Why: the C libraries differ. glibc's and newlib's sinf, cosf, atan2f, expf
 * and expm1f disagree by 1 ulp on a few percent of arguments (measured:
 * tests/test_target.py), so a controller built against newlib on a
 * Cortex-M4F cannot reproduce the simulator's run bit for bit. Mapped into
 * the core with the math hooks of smd_types.h,
 *
 *   -DSMD_SINF=smd_sinf -DSMD_COSF=smd_cosf -DSMD_SINCOSF=smd_sincosf
 *   -DSMD_ATAN2F=smd_atan2f -DSMD_EXPF=smd_expf -DSMD_EXPM1F=smd_expm1f
 *
 * the firmware and the host agree bit for bit, and on a Cortex-M4F these
 * are several times cheaper than newlib's (which evaluate in soft-float
 * double). Accuracy against double libm (core/test/test_fmath.c, 2e6
 * arguments each): sin, cos within 1.5 x 2^-24 absolute for |x| <= 8192 rad
 * (Cody-Waite reduction with a 3-part pi/4; near a zero of the result the
 * error is absolute, not relative); atan2 <= 4 ulp; exp <= 1 ulp; expm1 <= 2
 * ulp. The
 * polynomials are the classical minimax fits of Cephes' single-precision
 * library (S. L. Moshier). Beyond |x| = 8192 the angle is first reduced
 * modulo a float 2 pi (fmodf, exact): deterministic, not accurate, and an
 * angle that large is a fault anyway.
 */
#ifndef SMD_FMATH_H
#define SMD_FMATH_H

#ifdef __cplusplus
extern "C" {
#endif

float smd_sinf(float x);
float smd_cosf(float x);
/* *s = smd_sinf(x) and *c = smd_cosf(x), bit for bit, with one argument
 * reduction (the core's e^{j theta}, through SMD_SINCOSF). */
void smd_sincosf(float x, float *s, float *c);
float smd_atan2f(float y, float x);
float smd_expf(float x);
float smd_expm1f(float x);

#ifdef __cplusplus
}
#endif

#endif

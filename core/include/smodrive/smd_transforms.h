/*
 * Clarke and Park transforms (amplitude-invariant), yang2018 Sec. II-A.
 */
#ifndef SMD_TRANSFORMS_H
#define SMD_TRANSFORMS_H

#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Phase quantities a, b, c to the stationary vector x_ab (amplitude invariant,
 * the zero-sequence part is rejected). */
smd_cplx smd_abc_to_ab(const smd_real x_abc[3]);

/* Two measured phases a, b to x_ab, assuming a + b + c = 0. */
smd_cplx smd_ab2_to_ab(smd_real x_a, smd_real x_b);

/* Three measured phases to the two inputs the drive takes (smd_drive_in's
 * i_a, i_b, which assume a + b + c = 0): the readings' zero sequence
 * removed, x_a = a - m, x_b = b - m with m = (a + b + c) / 3, so that
 * smd_ab2_to_ab(x_a, x_b) = smd_abc_to_ab(x_abc). With two sensors, per-
 * phase gains 1 + g_a, 1 + g_b turn the measured vector by about
 * -(g_b - g_a) / (2 sqrt 3) rad; with three, the gains' mean is a real
 * factor and the rest a negative sequence: the vector is not turned
 * (docs/commissioning.md, "The tracker and the current sensors"). */
void smd_abc_to_ab2(const smd_real x_abc[3], smd_real *x_a, smd_real *x_b);

/* Stationary vector to phase quantities (no zero sequence). */
void smd_ab_to_abc(smd_cplx x_ab, smd_real x_abc[3]);

/* Park: x_dq = x_ab e^{-j theta}. */
static inline smd_cplx smd_ab_to_dq(smd_cplx x_ab, smd_real theta)
{
    return smd_cmul(x_ab, smd_cconj(smd_cexpj(theta)));
}

/* Inverse Park: x_ab = x_dq e^{j theta}. */
static inline smd_cplx smd_dq_to_ab(smd_cplx x_dq, smd_real theta)
{
    return smd_cmul(x_dq, smd_cexpj(theta));
}

#ifdef __cplusplus
}
#endif

#endif

/*
 * Second-order band-pass filter, yao2022 eq. (45)-(46):
 *   G_bp(z) = (1 - a2)/2 (1 - z^-2) / (1 - a1 z^-1 + a2 z^-2),
 *   a1 = 2 cos(w_n T) / (1 + tan(Omega T/2)),  a2 = (1 - tan(Omega T/2)) / (1 + tan(Omega T/2)),
 * unity gain and zero phase at w_n, -3 dB bandwidth Omega. Two channels
 * (gamma, delta) share the coefficients. The centre frequency follows the
 * speed, so the coefficients can be set every sample.
 */
#ifndef SMD_BANDPASS_H
#define SMD_BANDPASS_H

#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct smd_bandpass {
    smd_real b0;       /* (1 - a2)/2 */
    smd_real a1, a2;
    smd_cplx x1, x2;   /* past inputs */
    smd_cplx y1, y2;   /* past outputs */
} smd_bandpass;

/* Coefficients for centre w_n (rad/s) and bandwidth Omega (rad/s) at period
 * T; requires 0 < w_n < pi/T and 0 < Omega < pi/T. */
smd_status smd_bandpass_set(smd_bandpass *f, smd_real w_n, smd_real Omega, smd_real T);
void smd_bandpass_reset(smd_bandpass *f);
smd_cplx smd_bandpass_step(smd_bandpass *f, smd_cplx x);

#ifdef __cplusplus
}
#endif

#endif

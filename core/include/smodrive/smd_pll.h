/*
 * Third-order phase-locked loop on a position error, yao2022 eq. (48):
 *   theta(k+1) = theta(k) + w(k) T + k_theta e(k)
 *   w(k+1)     = w(k) + a(k) T + k_omega e(k)
 *   a(k+1)     = a(k) + k_a e(k)
 * with e the position error of eq. (47). Open loop from e to theta: eq. (49).
 */
#ifndef SMD_PLL_H
#define SMD_PLL_H

#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct smd_pll_params {
    smd_real T_sp;     /* sampling period, s */
    smd_real k_theta;  /* eq. (50): 0.1 */
    smd_real k_omega;  /* eq. (50): 10, 1/s */
    smd_real k_a;      /* eq. (50): 10, 1/s^2 */
} smd_pll_params;

typedef struct smd_pll_state {
    smd_real theta;    /* estimated electrical angle, rad, wrapped to [-pi, pi) */
    smd_real w;        /* estimated electrical speed, rad/s */
    smd_real a;        /* estimated acceleration, rad/s^2 */
} smd_pll_state;

/* Rejects gains that make the discrete loop (closed around eq. (49) with
 * unity feedback) unstable: SMD_ERR_STABILITY. */
smd_status smd_pll_init(smd_pll_params *p, smd_real T_sp, smd_real k_theta, smd_real k_omega,
                        smd_real k_a);
void smd_pll_reset(smd_pll_state *s, smd_real theta0, smd_real w0);
/* One update with the position error e (rad); non-finite e is ignored. */
void smd_pll_step(const smd_pll_params *p, smd_pll_state *s, smd_real e);

#ifdef __cplusplus
}
#endif

#endif

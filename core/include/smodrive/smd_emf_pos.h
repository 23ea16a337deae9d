/*
 * Position and speed from the estimated disturbance (back EMF), yang2018
 * eq. (43)-(45), with a first-order low-pass filter on the speed.
 *
 * Negative speed: u_d = -j w psi e^{j theta} = |w| psi e^{j(theta - sgn(w) pi/2)},
 * so the arctan of eq. (44) gives theta + pi when w < 0. The angle phi of u_d
 * itself rotates at w whatever the sign, so the speed is taken from the
 * difference of phi (eq. (45) applied to phi, which has the same increments as
 * theta), and theta_hat = phi + sgn(w_hat) pi/2, i.e. eq. (44) with both
 * components multiplied by sgn(w_hat). The sign has a hysteresis band w_hys so
 * that noise at standstill does not toggle it. The sign is taken from the
 * speed filtered 8 times slower than w_hat, so that speed-estimate noise at
 * low speed does not flip the angle by pi.
 */
#ifndef SMD_EMF_POS_H
#define SMD_EMF_POS_H

#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct smd_emf_pos_params {
    smd_real T_sp;  /* s */
    smd_real w_lpf; /* speed low-pass bandwidth, rad/s */
    smd_real a_lpf; /* derived: 1 - exp(-w_lpf T_sp) */
    smd_real a_dir; /* derived: 1 - exp(-w_lpf T_sp / 8), the direction filter */
    smd_real w_hys; /* sign hysteresis half-band, electrical rad/s, >= 0 */
    smd_real w_max; /* the speed estimate is limited to +-w_max, rad/s */
    smd_real inv_T; /* derived: 1 / T_sp (the fast build's, for a division) */
} smd_emf_pos_params;

typedef struct smd_emf_pos_state {
    smd_real phi_prev; /* angle of u_d_hat at k-1, rad */
    smd_real w_r_raw;  /* eq. (45) before filtering, rad/s */
    smd_real w_r_hat;  /* filtered speed, rad/s */
    smd_real w_r_dir;  /* slowly filtered speed that decides the direction, rad/s */
    smd_real theta_r_hat; /* rad, in [-pi, pi) */
    int dir;           /* +1 or -1: assumed sign of rotation */
    int primed;        /* 0 until phi_prev holds a sample */
} smd_emf_pos_state;

smd_status smd_emf_pos_init(smd_emf_pos_params *p, smd_real T_sp, smd_real w_lpf, smd_real w_hys,
                            smd_real w_max);
/* w_r0: initial speed estimate (its sign sets the initial direction). */
void smd_emf_pos_reset(smd_emf_pos_state *s, smd_real w_r0);
void smd_emf_pos_step(const smd_emf_pos_params *p, smd_emf_pos_state *s, smd_cplx u_d_hat);

#ifdef __cplusplus
}
#endif

#endif

/*
 * Sliding-mode disturbance observer (SMDO) with embedded complex-coefficient
 * filter, discrete form of yang2018 eq. (34)-(39).
 *
 * Model (15): L_hat di/dt = u_s + u_d - R_hat i, with u_d rotating at w_r (17).
 * One step takes the sample i_s^k and the applied u_s^k and returns the
 * predictions i_hat^{k+1}, u_d_hat^{k+1} used by the robust DBPC (42).
 */
#ifndef SMD_SMDO_H
#define SMD_SMDO_H

#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct smd_smdo_params {
    smd_real T_sp;       /* sampling period, s */
    smd_real L_s_hat;    /* H */
    smd_real R_s_hat;    /* ohm */
    smd_real lambda_min; /* minimum switching gain, A/s, eq. (37) */
    smd_real l;          /* proportional reaching gain, 1/s, eq. (21) */
    smd_real w_c;        /* complex-filter adaption gain omega_c, rad/s, eq. (19) */
    smd_real rho;        /* smoothing of sgn(), A, eq. (39) */
    int euler;           /* 1: rotate u_d_hat by (1 + j w T) as printed in eq. (36);
                            0: by e^{j w T}, the exact discrete rotation (default) */
    smd_real L_T, T_L;   /* derived: L_s_hat / T_sp, T_sp / L_s_hat (the step's quotients,
                            once) */
    smd_real inv_L;      /* derived: 1 / L_s_hat (the fast build's, for a division) */
} smd_smdo_params;

typedef struct smd_smdo_state {
    smd_cplx i_s_hat;    /* i_hat^k (before step), i_hat^{k+1} (after) */
    smd_cplx u_d_hat;    /* u_d_hat^k (before step), u_d_hat^{k+1} (after) */
    smd_cplx e_i_prev;   /* e_i^{k-1} */
    smd_cplx u_smo_prev; /* u_smo^{k-1} */
    smd_cplx u_smo;      /* u_smo^k (read-only view) */
    smd_real lambda;     /* adapted gain used at k, eq. (37) */
} smd_smdo_state;

/* Select the discretisation of the rotation in eq. (36) (see docs/errata.md):
 * the forward-Euler factor (1 + j w T) leaves a steady-state sliding residual
 * of |u_d| (w T)^2 / (2 w_c T) that biases the current prediction. */
smd_status smd_smdo_set_euler(smd_smdo_params *p, int euler);

/* Rejects a parameter set whose discrete loops are unstable
 * (SMD_ERR_STABILITY): near e_i = 0 the linear part of (34)-(35) with the
 * smoothed sign (39) gives e_i^{k+1} = (1 - (l + lambda_min/rho) T_sp) e_i^k,
 * so (l + lambda_min/rho) T_sp must be below 2; and the filter (36) needs
 * w_c T_sp < 1. */
smd_status smd_smdo_init(smd_smdo_params *p, smd_real T_sp, smd_real L_s_hat, smd_real R_s_hat,
                         smd_real lambda_min, smd_real l, smd_real w_c, smd_real rho);

void smd_smdo_reset(smd_smdo_state *s, smd_cplx i_s_hat0, smd_cplx u_d_hat0);

/* One sample: i_s_ab = i_s^k (measured), u_s_ab = u_s^k (applied during
 * [k, k+1)), w_r = electrical speed used to rotate u_d (measured or estimated).
 * Returns SMD_ERR_NONFINITE (and resets the state) if NaN/Inf appeared. */
smd_status smd_smdo_step(const smd_smdo_params *p, smd_smdo_state *s, smd_cplx i_s_ab,
                         smd_cplx u_s_ab, smd_real w_r);
/* The same step with the model's R_s given (ohm) in place of R_s_hat: a
 * drive whose R_s tracker feeds it (smd_rls.h, smd_drive.c). */
smd_status smd_smdo_step_r(const smd_smdo_params *p, smd_smdo_state *s, smd_cplx i_s_ab,
                           smd_cplx u_s_ab, smd_real w_r, smd_real R);
/* The same step with e^{j w_r T_sp} of eq. (19)'s rotation given too (a
 * drive that has it from its own rotations: smd_drive.c); the forward-Euler
 * filter (36) reads w_r. */
smd_status smd_smdo_step_rot(const smd_smdo_params *p, smd_smdo_state *s, smd_cplx i_s_ab,
                             smd_cplx u_s_ab, smd_real w_r, smd_real R, smd_cplx rot);

#ifdef __cplusplus
}
#endif

#endif

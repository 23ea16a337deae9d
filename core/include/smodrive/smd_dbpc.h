/*
 * Deadbeat predictive current control (DBPC) in the stationary frame,
 * yang2018 Sec. II-B and III, and its robust form with the SMDO, eq. (42).
 *
 * Delay convention (shared by every controller of smodrive): the voltage
 * u_s^{k+1} computed from the samples of instant k is applied during
 * [k+1, k+2) T_sp. The voltage u_s^k applied during [k, k+1) was computed at
 * k-1 and is known to the controller (after the modulator's limit).
 */
#ifndef SMD_DBPC_H
#define SMD_DBPC_H

#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct smd_dbpc_params {
    smd_real T_sp;      /* sampling period, s */
    smd_real L_s_hat;   /* estimated stator inductance, H */
    smd_real R_s_hat;   /* estimated stator resistance, ohm */
    smd_real psi_r_hat; /* estimated PM flux, Wb */
    smd_real L_T, T_L;  /* derived: L_s_hat / T_sp, T_sp / L_s_hat (the same quotients the
                           step took each sample, once) */
} smd_dbpc_params;

smd_status smd_dbpc_init(smd_dbpc_params *p, smd_real T_sp, smd_real L_s_hat,
                         smd_real R_s_hat, smd_real psi_r_hat);

/* Reference two samples ahead, eq. (6)-(7) (i_dref kept, not forced to zero):
 * i_ref^{k+2} = (i_dref + j i_qref) e^{j(theta_r^k + 2 omega_r^k T_sp)}. */
smd_cplx smd_dbpc_ref_k2(const smd_dbpc_params *p, smd_cplx i_dq_ref, smd_real theta_r,
                         smd_real w_r);

/* One-step prediction with the estimated model, eq. (8):
 * i^{k+1} = i^k + T/L (u^k - R i^k - j w psi e^{j theta^k}). */
smd_cplx smd_dbpc_predict(const smd_dbpc_params *p, smd_cplx i_s_ab, smd_cplx u_s_ab,
                          smd_real theta_r, smd_real w_r);

/* Conventional DBPC, eq. (8)-(9): voltage u_s^{k+1} from the sample i_s^k,
 * the applied u_s^k and the position and speed at k. */
smd_cplx smd_dbpc_conventional(const smd_dbpc_params *p, smd_cplx i_s_ab, smd_cplx u_s_ab,
                               smd_cplx i_dq_ref, smd_real theta_r, smd_real w_r);

/* Robust DBPC, eq. (42): u^{k+1} = L (i_ref^{k+2} - i^{k+1})/T + R i^{k+1} - u_d^{k+1}
 * with i^{k+1} and u_d^{k+1} the SMDO predictions of eq. (35)-(36). */
smd_cplx smd_dbpc_robust(const smd_dbpc_params *p, smd_cplx i_s_ab_k1, smd_cplx u_d_ab_k1,
                         smd_cplx i_ref_ab_k2);
/* The same with the model's R_s given (ohm) in place of R_s_hat: the SMDO's,
 * when a drive's R_s tracker feeds it (smd_drive.c). */
smd_cplx smd_dbpc_robust_r(const smd_dbpc_params *p, smd_cplx i_s_ab_k1, smd_cplx u_d_ab_k1,
                           smd_cplx i_ref_ab_k2, smd_real R);

#ifdef __cplusplus
}
#endif

#endif

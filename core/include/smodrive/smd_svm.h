/*
 * Space-vector modulation by min-max zero-sequence injection (equivalent to
 * symmetric SVPWM), with the DC-link voltage limit handled.
 *
 * The reference u_s_ab_ref is limited either to the inscribed circle of the
 * voltage hexagon (|u| <= u_dc / sqrt(3), linear region) or to the hexagon
 * itself (overmodulation along the reference direction). The limited vector is
 * returned as the applied voltage, so the controller knows what it applied.
 */
#ifndef SMD_SVM_H
#define SMD_SVM_H

#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum smd_svm_limit {
    SMD_SVM_LIMIT_CIRCLE = 0,
    SMD_SVM_LIMIT_HEXAGON = 1
} smd_svm_limit;

typedef struct smd_svm_params {
    int limit;          /* smd_svm_limit */
    smd_real d_min;     /* minimum duty (e.g. for bootstrap or sampling windows), [0, 0.5) */
} smd_svm_params;

smd_status smd_svm_init(smd_svm_params *p, int limit, smd_real d_min);

/* Dead-time compensation: d_x += (t_dead / T_sw) sat(i_x / i_lin), the
 * average volt-seconds a dead time t_dead removes in the direction of the
 * phase current i_x (use the current expected during the period, e.g. the
 * reference, to stay clear of sampling noise). Duties are kept in [0, 1]. */
void smd_svm_deadtime_comp(smd_real d_abc[3], const smd_real i_abc[3], smd_real t_ratio,
                           smd_real i_lin);
/* The same with 1 / i_lin given (a caller that keeps it: the fast build's
 * drive), i_x * inv_i_lin in place of i_x / i_lin. */
void smd_svm_deadtime_comp_r(smd_real d_abc[3], const smd_real i_abc[3], smd_real t_ratio,
                             smd_real inv_i_lin);

/* Duty ratios d_abc in [d_min, 1 - d_min] realising u_s_ab_ref as closely as
 * the limit allows; *u_s_ab_applied receives the realised vector (the
 * switching-cycle average of the inverter output for ideal switches). */
void smd_svm_step(const smd_svm_params *p, smd_cplx u_s_ab_ref, smd_real u_dc,
                  smd_real d_abc[3], smd_cplx *u_s_ab_applied);

#ifdef __cplusplus
}
#endif

#endif

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
/* The compensation of smd_svm_deadtime_comp (i_x / i_lin; the fast build:
 * i_x * inv_i_lin, inv_i_lin = 1 / i_lin), returning what an inverter with
 * that dead time applies of the given duties d_abc, less them, where the
 * compensated duty was clipped, as a voltage vector (u_dc times the
 * amplitude-invariant Clarke transform of the duties' differences): a duty
 * clipped to 0 switches nothing, so the leg's mean is 0, not d_x (no dead
 * time to compensate); a duty clipped to 1 keeps its rising edge's dead
 * time (a positive current's), which the compensation could not add, so the
 * leg's mean is 1 - t_ratio sat(i_x inv_i_lin), sat to [0, 1]. Zero where no
 * duty was clipped. */
smd_cplx smd_svm_deadtime_comp_lost(smd_real d_abc[3], const smd_real i_abc[3],
                                    smd_real t_ratio, smd_real i_lin, smd_real inv_i_lin,
                                    smd_real u_dc);

/* Duty ratios d_abc in [d_min, 1 - d_min] realising u_s_ab_ref as closely as
 * the limit allows; *u_s_ab_applied receives the realised vector (the
 * switching-cycle average of the inverter output for ideal switches). */
void smd_svm_step(const smd_svm_params *p, smd_cplx u_s_ab_ref, smd_real u_dc,
                  smd_real d_abc[3], smd_cplx *u_s_ab_applied);
/* smd_svm_step of a reference the caller has found finite (smd_drive's
 * modulate, which has replaced a non-finite one already: the check not made
 * twice a sample), with inv_u_dc = smd_svm_inv_dc(u_dc): the fast build's
 * 1 / u_dc, which a caller that divides early lets run beside its integer
 * work; the exact build divides by u_dc and does not read it. */
void smd_svm_step_finite_r(const smd_svm_params *p, smd_cplx u_s_ab_ref, smd_real u_dc,
                           smd_real inv_u_dc, smd_real d_abc[3], smd_cplx *u_s_ab_applied);

/* inv_u_dc of smd_svm_step_finite_r: 1 / u_dc in the fast build, 0 (not
 * read, no division) in the exact one. */
static inline smd_real smd_svm_inv_dc(smd_real u_dc)
{
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    return SMD_R(1.0) / u_dc;
#else
    (void)u_dc;
    return SMD_R(0.0);
#endif
}

#ifdef __cplusplus
}
#endif

#endif

/*
 * Sensorless drive of an LCL-filtered high-speed SPMSM, yao2022 Fig. 1: what
 * a firmware interrupt calls once per sample.
 *
 *  - position and speed: the sliding-mode back-EMF observer (smd_lcl_smo)
 *    and the third-order PLL of eq. (47)-(48); or the encoder (sensored);
 *  - motor-current control in the estimated rotor frame: PI with
 *    cross-coupling decoupling over the total inductance and EMF feed-forward,
 *    plus active damping of the LCL resonance by a virtual resistance on the
 *    capacitor current i_1 - i_2 (the paper's ref. [20]);
 *  - speed PI (or a torque-current reference);
 *  - start-up: current vector of fixed magnitude on a forced synchronous
 *    angle ("I/f", torque-controlled), accelerated open loop until the speed
 *    reaches w_handover; then the PLL takes over from the observer's angle.
 *
 * Delay convention: samples at k; the voltage computed at k is applied
 * during [k+1, k+2), so it is rotated to the stationary frame at the angle
 * the rotor has in the middle of that period, theta_hat + 1.5 w_hat T.
 */
#ifndef SMD_LCL_DRIVE_H
#define SMD_LCL_DRIVE_H

#include "smd_lcl_linobs.h"
#include "smd_lcl_smo.h"
#include "smd_pi.h"
#include "smd_pll.h"
#include "smd_svm.h"
#include "smd_types.h"

typedef enum smd_lcl_mode {
    SMD_LCL_SENSORLESS = 0, /* observer + PLL */
    SMD_LCL_SENSORED = 1    /* encoder angle; the observer runs alongside */
} smd_lcl_mode;

typedef enum smd_lcl_phase {
    SMD_LCL_PHASE_OPENLOOP = 0, /* forced angle start */
    SMD_LCL_PHASE_CLOSED = 1    /* speed/torque control on the estimated angle */
} smd_lcl_phase;

typedef struct smd_lcl_drive_config {
    int mode;             /* smd_lcl_mode */
    smd_real T;           /* sampling period, s */
    smd_real k_p_i;       /* current PI proportional gain, V/A */
    smd_real k_i_i;       /* current PI integral gain, V/(A s) */
    smd_real L_dec;       /* inductance for decoupling, L1 + L2, H */
    smd_real R_v;         /* active-damping virtual resistance on i_1 - i_2, V/A */
    int emf_ff;           /* 1: feed the estimated EMF forward */
    smd_real k_p_w;       /* speed PI, A per electrical rad/s */
    smd_real k_i_w;       /* A per electrical rad */
    smd_real i_max;       /* current reference limit, A */
    int speed_loop;       /* 1: i_delta reference from the speed PI; 0: from the input */
    smd_real k_theta, k_omega, k_a; /* PLL, eq. (50) */
    smd_real i_start;     /* start-up current magnitude, A (0: no start-up phase) */
    smd_real a_start;     /* start-up acceleration of the forced angle, electrical rad/s^2 */
    smd_real w_handover;  /* speed at which the PLL takes over, electrical rad/s */
    int svm_limit;        /* smd_svm_limit */
    int pos_source;       /* 0: sliding-mode observer; 1: linear observer (64)-(65) */
} smd_lcl_drive_config;

typedef struct smd_lcl_drive_params {
    int mode;
    smd_real T;
    smd_real k_p_i, k_i_i, L_dec, R_v;
    int emf_ff;
    int speed_loop;
    smd_real i_max;
    smd_real i_start, a_start, w_handover;
    smd_pi_params speed_pi;
    smd_pll_params pll;
    smd_svm_params svm;
    smd_lcl_smo_params smo; /* set by smd_lcl_drive_init from the caller's */
    int use_lin;            /* the linear observer runs (alongside, or as the source) */
    int pos_source;
    smd_linobs_params lin;
} smd_lcl_drive_params;

typedef struct smd_lcl_drive_in {
    smd_real i1_a, i1_b;  /* inverter-side phase currents, A */
    smd_real i2_a, i2_b;  /* motor phase currents, A */
    smd_real theta_enc;   /* encoder angle (sensored mode), rad */
    smd_real w_enc;       /* encoder speed (sensored mode), rad/s */
    smd_real u_dc;        /* V */
    smd_real w_ref;       /* electrical speed reference, rad/s */
    smd_cplx i_ref;       /* current reference (gamma, delta), A: gamma always used,
                             delta when the speed loop is off */
} smd_lcl_drive_in;

typedef struct smd_lcl_drive_out {
    smd_real d_abc[3];
} smd_lcl_drive_out;

typedef struct smd_lcl_drive_state {
    int phase;            /* smd_lcl_phase */
    smd_real theta;       /* frame angle used at k, rad */
    smd_real w;           /* frame speed used at k, rad/s */
    smd_real theta_f;     /* forced angle (start-up), rad */
    smd_real w_f;         /* forced speed (start-up), rad/s */
    smd_real theta_err;   /* eq. (47) at k, rad */
    smd_cplx i_ref;       /* current reference at k, gamma-delta */
    smd_cplx i2_gd;       /* measured motor current, gamma-delta */
    smd_cplx x_i;         /* current PI integrators, V */
    smd_cplx u_ab;        /* voltage applied during [k, k+1), stationary frame */
    smd_cplx u_ab_next;   /* voltage for [k+1, k+2) */
    smd_pi_state speed_pi;
    smd_pll_state pll;
    smd_lcl_smo_state smo;
    smd_linobs_state lin;
    int status;
} smd_lcl_drive_state;

/* smo: the observer's parameters (table, law, gains) prepared by the caller
 * with smd_lcl_smo_init. */
/* lin: the linear observer's parameters, or NULL (then pos_source must be 0). */
smd_status smd_lcl_drive_init(smd_lcl_drive_params *p, const smd_lcl_drive_config *c,
                              const smd_lcl_smo_params *smo, const smd_linobs_params *lin);
/* theta0, w0: the drive's knowledge at start (a flying start, or 0, 0 with
 * the start-up phase); phase: where to begin. */
void smd_lcl_drive_reset(const smd_lcl_drive_params *p, smd_lcl_drive_state *s, smd_real theta0,
                         smd_real w0, int phase, smd_real i_delta0);
smd_status smd_lcl_drive_step(const smd_lcl_drive_params *p, smd_lcl_drive_state *s,
                              const smd_lcl_drive_in *in, smd_lcl_drive_out *out);

#endif

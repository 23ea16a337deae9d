/*
 * Top-level drive controller: what a firmware interrupt calls once per sample.
 *
 * Modes (yang2018 Fig. 3):
 *   SMD_DRIVE_CONVENTIONAL  sensored, conventional DBPC eq. (8)-(9)
 *   SMD_DRIVE_ROBUST        sensored, SMDO eq. (34)-(39) + robust DBPC eq. (42)
 *   SMD_DRIVE_SENSORLESS    SMDO + robust DBPC, position and speed from the
 *                           estimated disturbance, eq. (44)-(45)
 *
 * Per sample k: measure i_s^k (two phases a, b), optionally the encoder angle
 * and speed; run the speed PI (every speed_decimation samples); compute
 * u_s^{k+1}; modulate. The returned duties are to be applied during the next
 * sampling period (the one-sample computational delay of yang2018 Sec. II-B).
 */
#ifndef SMD_DRIVE_H
#define SMD_DRIVE_H

#include "smd_dbpc.h"
#include "smd_emf_pos.h"
#include "smd_pi.h"
#include "smd_smdo.h"
#include "smd_svm.h"
#include "smd_types.h"

typedef enum smd_drive_mode {
    SMD_DRIVE_CONVENTIONAL = 0,
    SMD_DRIVE_ROBUST = 1,
    SMD_DRIVE_SENSORLESS = 2
} smd_drive_mode;

/* Everything init needs, in SI units (electrical angles and speeds). */
typedef struct smd_drive_config {
    int mode;              /* smd_drive_mode */
    smd_real T_sp;         /* sampling period, s */
    smd_real L_s_hat;      /* H */
    smd_real R_s_hat;      /* ohm */
    smd_real psi_r_hat;    /* Wb (conventional DBPC only) */
    smd_real lambda_min;   /* SMDO, A/s */
    smd_real l;            /* SMDO, 1/s */
    smd_real w_c;          /* SMDO, rad/s */
    smd_real rho;          /* SMDO, A */
    smd_real k_p;          /* speed PI, A/(rad/s) electrical */
    smd_real k_i;          /* speed PI, A/rad */
    smd_real i_max;        /* q-axis current reference limit, A */
    int speed_decimation;  /* speed loop runs every this many samples */
    int speed_loop;        /* 1: i_q reference from the speed PI; 0: from the input */
    smd_real w_lpf;        /* sensorless speed LPF bandwidth, rad/s */
    smd_real w_hys;        /* sensorless direction hysteresis, rad/s */
    int svm_limit;         /* smd_svm_limit */
    smd_real w_max;        /* sensorless: speed estimate limit, electrical rad/s (> 0) */
    int handover;          /* sensorless: samples run on the encoder while the observer
                              converges (0: sensorless from the first sample) */
    smd_real t_dead_comp;  /* dead time to compensate in the modulator, s (0: off) */
    smd_real i_dtc;        /* current below which the compensation is linear, A (> 0) */
    int smdo_euler;        /* 1: eq. (36) as printed (forward Euler); 0: exact rotation */
} smd_drive_config;

typedef struct smd_drive_params {
    int mode;
    int speed_decimation;
    int speed_loop;
    int handover;
    smd_real dtc_ratio;    /* t_dead_comp / T_sp */
    smd_real i_dtc;
    smd_dbpc_params dbpc;
    smd_smdo_params smdo;
    smd_pi_params pi;
    smd_emf_pos_params pos;
    smd_svm_params svm;
} smd_drive_params;

typedef struct smd_drive_in {
    smd_real i_a;        /* phase currents from the ADC, A */
    smd_real i_b;
    smd_real theta_r;    /* encoder electrical angle, rad (sensored modes) */
    smd_real w_r;        /* encoder electrical speed, rad/s (sensored modes) */
    smd_real u_dc;       /* DC-link voltage, V */
    smd_real w_r_ref;    /* electrical speed reference, rad/s (speed loop on) */
    smd_cplx i_dq_ref;   /* current reference; only i_d used when the speed loop is on */
} smd_drive_in;

typedef struct smd_drive_out {
    smd_real d_abc[3];   /* duty ratios to apply during the next period */
} smd_drive_out;

typedef struct smd_drive_state {
    smd_cplx u_s_ab;      /* u_s^k: the voltage applied during [k, k+1) (after limiting) */
    smd_cplx u_s_ab_ref;  /* last unlimited voltage reference u_s^{k+1} */
    smd_cplx i_s_ab;      /* last measured current i_s^k */
    smd_cplx i_dq_ref;    /* last current reference (controller frame) */
    smd_real theta_r;     /* angle used at k (measured or estimated) */
    smd_real w_r;         /* speed used at k (measured or estimated) */
    int count;            /* sample counter for the speed-loop decimation */
    int primed;           /* 0 until the first sample has initialised the SMDO */
    int samples;          /* samples since reset, saturating at handover */
    smd_smdo_state smdo;
    smd_emf_pos_state pos;
    smd_pi_state pi;
} smd_drive_state;

/* Read-only view of the controller's internals for logging. */
typedef struct smd_drive_view {
    smd_cplx i_s_ab;
    smd_cplx i_dq_ref;
    smd_cplx u_s_ab;
    smd_cplx u_s_ab_ref;
    smd_cplx i_s_hat;
    smd_cplx u_d_hat;
    smd_real theta_r;
    smd_real w_r;
    smd_real lambda;
} smd_drive_view;

smd_status smd_drive_init(smd_drive_params *p, const smd_drive_config *cfg);
/* Start from rest or, for the sensorless mode, from a known running state:
 * w_r0 seeds the speed estimate (and the direction), theta_r0 the angle. */
void smd_drive_reset(const smd_drive_params *p, smd_drive_state *s, smd_real theta_r0,
                     smd_real w_r0);
/* Warm start of the speed loop: set the PI integrator (the q-axis current
 * reference it holds), e.g. when taking over a drive running under load. */
void smd_drive_set_speed_integrator(smd_drive_state *s, smd_real i_q0);
smd_status smd_drive_step(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in,
                          smd_drive_out *out);
smd_drive_view smd_drive_get_view(const smd_drive_state *s);

#endif

/*
 * Engine: couples the plant (double) with the firmware controller (smd_drive,
 * float) with one sample of computational delay, and logs true and estimated
 * signals into a caller-owned buffer. One call runs many samples in C.
 *
 * Timeline of sample k (t_k = k T_sp, the carrier peak):
 *   1. the ADC samples the phase currents; the encoder gives theta_r, w_r;
 *   2. the controller computes the duties d^{k+1};
 *   3. the plant advances over [t_k, t_{k+1}) with d^k (computed at k-1);
 *   4. one log row is written (values at t_k, controller outputs of step 2).
 */
#ifndef SMD_ENGINE_H
#define SMD_ENGINE_H

#include "smdsim/smd_plant.h"
#include "smodrive/smd_drive.h"

#define SMD_PWL_MAX 64

/* Piecewise-linear profile y(t), held constant outside [t[0], t[n-1]]. */
typedef struct smd_pwl {
    int n;
    double t[SMD_PWL_MAX];
    double y[SMD_PWL_MAX];
} smd_pwl;

typedef struct smd_profiles {
    smd_pwl w_M_ref;   /* mechanical speed reference, rad/s */
    smd_pwl T_ext;     /* signed external load torque, N m */
    smd_pwl T_brake;   /* brake torque magnitude (opposes rotation), N m */
    smd_pwl i_d_ref;   /* d-axis current reference, A */
    smd_pwl i_q_ref;   /* q-axis current reference (speed loop off), A */
    double i_d_sin_amp;  /* sinusoid added to i_d_ref (frequency-response tests), A */
    double i_d_sin_freq; /* its frequency, Hz */
} smd_profiles;

enum smd_log_channel {
    SMD_LOG_T = 0,       /* time t_k, s */
    SMD_LOG_W_M,         /* true mechanical speed, rad/s */
    SMD_LOG_THETA_R,     /* true electrical angle, rad */
    SMD_LOG_I_ALPHA,     /* true stator current, A */
    SMD_LOG_I_BETA,
    SMD_LOG_I_D,         /* true current in the true rotor frame, A */
    SMD_LOG_I_Q,
    SMD_LOG_T_E,         /* mean electromagnetic torque over [t_k, t_k+1), N m */
    SMD_LOG_T_L,         /* load torque over [t_k, t_k+1), N m */
    SMD_LOG_W_M_REF,     /* speed reference, rad/s (mechanical) */
    SMD_LOG_I_D_REF,     /* controller's current reference, A */
    SMD_LOG_I_Q_REF,
    SMD_LOG_THETA_HAT,   /* angle used by the controller at k, rad */
    SMD_LOG_W_HAT,       /* speed used by the controller at k, electrical rad/s */
    SMD_LOG_UD_ALPHA,    /* SMDO disturbance estimate u_d_hat^{k+1}, V */
    SMD_LOG_UD_BETA,
    SMD_LOG_U_ALPHA,     /* mean inverter voltage applied over [t_k, t_k+1), V */
    SMD_LOG_U_BETA,
    SMD_LOG_UCMD_ALPHA,  /* voltage commanded for the next period (after the limit), V */
    SMD_LOG_UCMD_BETA,
    SMD_LOG_I_A_MEAS,    /* ADC phase currents, A */
    SMD_LOG_I_B_MEAS,
    SMD_LOG_IHAT_ALPHA,  /* SMDO current prediction i_hat^{k+1}, A */
    SMD_LOG_IHAT_BETA,
    SMD_LOG_LAMBDA,      /* SMDO adapted gain, A/s */
    SMD_LOG_STATUS,      /* controller status code */
    SMD_LOG_N
};

typedef struct smd_engine {
    smd_plant plant;
    smd_drive_params ctrl_p;
    smd_drive_state ctrl_s;
    smd_profiles prof;
    double d_abc[3];     /* duties applied during the current period */
    long k;              /* samples done */
    double T_sp;
    int last_status;
} smd_engine;

/* Returns 0 on success; 1000 + plant field code, or 2000 + smd_status. */
int smd_engine_init(smd_engine *e, const smd_plant_config *plant, const smd_drive_config *ctrl,
                    const smd_profiles *prof);
/* Run n samples; write a row of SMD_LOG_N doubles every `stride` samples
 * into log (which must hold ceil(n / stride) rows). Returns the number of
 * rows written. */
long smd_engine_run(smd_engine *e, long n, double *log, long stride);

const char *smd_log_channel_name(int ch);
unsigned long smd_sizeof_engine(void);
unsigned long smd_sizeof_plant_config(void);
unsigned long smd_sizeof_drive_config(void);
unsigned long smd_sizeof_profiles(void);
/* 0 dbpc params, 1 smdo params, 2 smdo state, 3 pi params, 4 pi state,
 * 5 svm params, 6 emf_pos params, 7 emf_pos state */
unsigned long smd_sizeof_block(int which);
double smd_pwl_eval(const smd_pwl *p, double t);

#endif

/*
 * Engine: couples the plant (double) with the firmware drive (smd_drive,
 * float) with one sample of computational delay, and logs true and estimated
 * signals into a caller-owned buffer. One call runs many samples in C. One
 * engine for every plant (with or without the LCL filter) and every
 * composition of the drive.
 *
 * Timeline of sample k (t_k = k T_sp, the carrier peak):
 *   1. the ADC samples the currents; the encoder gives theta_r, n_p w_M;
 *      the profiles are evaluated at t_k;
 *   2. the controller computes the duties d^{k+1};
 *   3. the log row is filled with the values at t_k and the controller's
 *      outputs of step 2;
 *   4. the plant advances over [t_k, t_{k+1}) with d^k (computed at k-1); the
 *      period means T_e, T_L, u_alpha, u_beta complete the row.
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

/* What the controller knows at t = 0 (smd_drive_reset). */
typedef struct smd_engine_start {
    double theta0;     /* electrical angle, rad */
    double w0;         /* electrical speed, rad/s */
    double i_q0;       /* speed-loop integrator (the current that carries the load), A */
} smd_engine_start;

enum smd_log_channel {
    SMD_LOG_T = 0,       /* time t_k, s */
    SMD_LOG_W_M,         /* true mechanical speed, rad/s */
    SMD_LOG_THETA_R,     /* true electrical angle, rad */
    SMD_LOG_I_ALPHA,     /* true motor current (i_2 with the filter), A */
    SMD_LOG_I_BETA,
    SMD_LOG_I_D,         /* true motor current in the true rotor frame, A */
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
    SMD_LOG_I_A_MEAS,    /* ADC motor phase currents, A */
    SMD_LOG_I_B_MEAS,
    SMD_LOG_IHAT_ALPHA,  /* SMDO current prediction i_hat^{k+1}, A */
    SMD_LOG_IHAT_BETA,
    SMD_LOG_LAMBDA,      /* SMDO adapted gain, A/s */
    SMD_LOG_I_G,         /* PI: measured motor current in its frame, A (0 with DBPC) */
    SMD_LOG_I_DL,
    SMD_LOG_THETA_ERR,   /* LCL sources: angle error of yao2022 eq. (47), rad */
    SMD_LOG_E_G,         /* LCL sliding-mode observer: EMF estimate, controller frame, V */
    SMD_LOG_E_DL,
    SMD_LOG_S_G,         /* its switching function s(k), eq. (18) */
    SMD_LOG_S_DL,
    SMD_LOG_DHAT_G,      /* its periodic-disturbance compensation, eq. (35) */
    SMD_LOG_DHAT_DL,
    SMD_LOG_V_G,         /* its disturbance part v(k-1) */
    SMD_LOG_V_DL,
    SMD_LOG_I1_ALPHA,    /* true inverter-side current (= motor current without filter), A */
    SMD_LOG_I1_BETA,
    SMD_LOG_UC_ALPHA,    /* true capacitor voltage (LCL), V */
    SMD_LOG_UC_BETA,
    SMD_LOG_LIN_E_ALPHA, /* linear observer's EMF estimate, stationary frame, V */
    SMD_LOG_LIN_E_BETA,
    SMD_LOG_PHASE,       /* start-up phase: 0 forced, 1 encoder, 2 position source */
    SMD_LOG_STATUS,      /* controller status code */
    SMD_LOG_FAULT,       /* controller fault word (smd_drive_out.fault) */
    SMD_LOG_N
};

/* A sample between smd_engine_ext_inputs and smd_engine_ext_apply. */
typedef struct smd_engine_sample {
    double t, w_ref, T_ext, T_brake;
    double i_meas[3];
} smd_engine_sample;

typedef struct smd_engine {
    smd_plant plant;
    smd_drive_params ctrl_p;
    smd_drive_state ctrl_s;
    smd_profiles prof;
    double d_abc[3];     /* duties applied during the current period */
    long k;              /* samples done */
    int seg[5];          /* last segment of each profile (time only grows) */
    double T_sp;
    int last_status;
    smd_engine_sample ext; /* the sample of the split step (PIL) */
    long first_fault_k;    /* sample of the first non-zero fault word, -1: none */
    unsigned first_fault;  /* that fault word */
    unsigned fault;        /* the last sample's fault word */
} smd_engine;

/* Returns 0 on success; 1000 + plant field code (smd_plant_field),
 * 2000 + smd_status of the drive, 3000 a malformed profile. */
int smd_engine_init(smd_engine *e, const smd_plant_config *plant, const smd_drive_config *ctrl,
                    const smd_profiles *prof, const smd_engine_start *start);
/* Run n samples; write a row of SMD_LOG_N doubles every `stride` samples
 * into log (which must hold ceil(n / stride) rows; NULL: no logging). Returns
 * the number of rows written. */
long smd_engine_run(smd_engine *e, long n, double *log, long stride);

/* One sample split in two, for a controller outside the engine (processor
 * in the loop: src/smodrive/target.py). ext_inputs forms the controller's
 * inputs at t_k; ext_apply takes its answer (duties, status and view) and
 * runs the plant over [t_k, t_k+1), writing a log row of SMD_LOG_N doubles
 * into `row` when v and row are not NULL. host_step is the engine's own
 * controller on the same inputs (the host-only reference). A run of
 * ext_inputs, host_step, ext_apply is identical to smd_engine_run. */
void smd_engine_ext_inputs(smd_engine *e, smd_drive_in *in);
void smd_engine_ext_apply(smd_engine *e, const smd_drive_out *out, int status,
                          const smd_drive_view *v, double *row);
int smd_engine_host_step(smd_engine *e, const smd_drive_in *in, smd_drive_out *out,
                         smd_drive_view *v);

/* The first sample with a fault (-1: none) and its fault word, and the
 * last sample's fault word. */
long smd_engine_fault(const smd_engine *e, unsigned *first, unsigned *now);

const char *smd_log_channel_name(int ch);
unsigned long smd_sizeof_engine(void);
double smd_pwl_eval(const smd_pwl *p, double t);
/* Closed-loop impulse response of the firmware PLL (yao2022 eq. (48)). */
int smd_pll_impulse(double T_sp, double k_theta, double k_omega, double k_a, double amp, long n,
                    double *out);

#endif

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
#include "smodrive/smd_ident.h"

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
    smd_pwl R_s_scale; /* the motor's R_s over time as a multiple of its configured
                        * value (winding heating); n = 0: constant */
} smd_profiles;

/* What the controller knows at t = 0 (smd_drive_reset). */
typedef struct smd_engine_start {
    double theta0;     /* electrical angle, rad */
    double w0;         /* electrical speed, rad/s */
    double i_q0;       /* speed-loop integrator (the current that carries the load), A */
} smd_engine_start;

/* The log channels: one double each in a row, in this order. Each entry's
 * comment is the channel's schema, @log(name, unit) and its meaning;
 * tools/gen_layout.py generates from it the names smd_log_channel_name gives
 * (sim/src/smd_log_names.h) and the Python names, units and meanings
 * (src/smodrive/engine/_codes.py). */
enum smd_log_channel {
    SMD_LOG_T = 0,       /* @log(t, s) time of sample k */
    SMD_LOG_W_M,         /* @log(w_M, rad/s) true mechanical speed */
    SMD_LOG_THETA_R,     /* @log(theta_r, rad) true electrical angle */
    SMD_LOG_I_ALPHA,     /* @log(i_alpha, A) true motor current (i_2 with the filter), alpha */
    SMD_LOG_I_BETA,      /* @log(i_beta, A) true motor current, beta */
    SMD_LOG_I_D,         /* @log(i_d, A) true motor current in the true rotor frame, d */
    SMD_LOG_I_Q,         /* @log(i_q, A) true motor current in the true rotor frame, q */
    SMD_LOG_T_E,         /* @log(T_e, N m) mean electromagnetic torque over [t_k, t_k+1) */
    SMD_LOG_T_L,         /* @log(T_L, N m) mean load torque over [t_k, t_k+1) (friction B w
                          * excluded) */
    SMD_LOG_W_M_REF,     /* @log(w_M_ref, rad/s) mechanical speed reference */
    SMD_LOG_I_D_REF,     /* @log(i_d_ref, A) controller's current reference, d */
    SMD_LOG_I_Q_REF,     /* @log(i_q_ref, A) controller's current reference, q */
    SMD_LOG_THETA_HAT,   /* @log(theta_hat, rad) angle the controller uses at k */
    SMD_LOG_W_HAT,       /* @log(w_hat, rad/s) electrical speed the controller uses at k */
    SMD_LOG_UD_ALPHA,    /* @log(u_d_hat_alpha, V) SMDO disturbance estimate u_d_hat^{k+1},
                          * alpha */
    SMD_LOG_UD_BETA,     /* @log(u_d_hat_beta, V) SMDO disturbance estimate, beta */
    SMD_LOG_U_ALPHA,     /* @log(u_alpha, V) mean inverter voltage over [t_k, t_k+1), alpha */
    SMD_LOG_U_BETA,      /* @log(u_beta, V) mean inverter voltage, beta */
    SMD_LOG_D_A,         /* @log(d_a, 1) duty of phase a applied during [t_k, t_k+1) (after the
                          * dead-time compensation) */
    SMD_LOG_D_B,         /* @log(d_b, 1) duty of phase b */
    SMD_LOG_D_C,         /* @log(d_c, 1) duty of phase c */
    SMD_LOG_UCMD_ALPHA,  /* @log(u_cmd_alpha, V) voltage commanded for the next period (after
                          * the limit), alpha */
    SMD_LOG_UCMD_BETA,   /* @log(u_cmd_beta, V) voltage commanded for the next period, beta */
    SMD_LOG_I_A_MEAS,    /* @log(i_a_meas, A) ADC motor phase current a */
    SMD_LOG_I_B_MEAS,    /* @log(i_b_meas, A) ADC motor phase current b */
    SMD_LOG_IHAT_ALPHA,  /* @log(i_hat_alpha, A) SMDO current prediction i_hat^{k+1}, alpha */
    SMD_LOG_IHAT_BETA,   /* @log(i_hat_beta, A) SMDO current prediction, beta */
    SMD_LOG_LAMBDA,      /* @log(lambda, A/s) SMDO adapted gain, eq. (37) */
    SMD_LOG_I_G,         /* @log(i_g, A) PI current control: measured motor current in its
                          * frame, gamma (d); 0 with DBPC */
    SMD_LOG_I_DL,        /* @log(i_dl, A) PI current control: measured motor current in its
                          * frame, delta (q) */
    SMD_LOG_THETA_ERR,   /* @log(theta_err_est, rad) LCL sources: estimated angle error,
                          * yao2022 eq. (47) */
    SMD_LOG_E_G,         /* @log(e_hat_g, V) LCL sliding-mode observer: EMF estimate, gamma */
    SMD_LOG_E_DL,        /* @log(e_hat_dl, V) LCL sliding-mode observer: EMF estimate, delta */
    SMD_LOG_S_G,         /* @log(s_g, A) LCL sliding-mode observer: switching function s(k),
                          * eq. (18), gamma */
    SMD_LOG_S_DL,        /* @log(s_dl, A) switching function s(k), delta */
    SMD_LOG_DHAT_G,      /* @log(d_hat_g, A) periodic-disturbance compensation, eq. (35),
                          * gamma */
    SMD_LOG_DHAT_DL,     /* @log(d_hat_dl, A) periodic-disturbance compensation, delta */
    SMD_LOG_V_G,         /* @log(v_g, A) disturbance part v(k-1) of the attraction function,
                          * gamma */
    SMD_LOG_V_DL,        /* @log(v_dl, A) disturbance part v(k-1), delta */
    SMD_LOG_I1_ALPHA,    /* @log(i1_alpha, A) true inverter-side current (motor current
                          * without filter), alpha */
    SMD_LOG_I1_BETA,     /* @log(i1_beta, A) true inverter-side current, beta */
    SMD_LOG_UC_ALPHA,    /* @log(uc_alpha, V) true filter-capacitor voltage (0 without
                          * filter), alpha */
    SMD_LOG_UC_BETA,     /* @log(uc_beta, V) true filter-capacitor voltage, beta */
    SMD_LOG_LIN_E_ALPHA, /* @log(lin_e_alpha, V) linear observer's EMF estimate, eq. (65),
                          * alpha */
    SMD_LOG_LIN_E_BETA,  /* @log(lin_e_beta, V) linear observer's EMF estimate, beta */
    SMD_LOG_R_S_RLS,     /* @log(R_s_rls, ohm) the drive's online R_s estimate (smd_rls.h;
                          * 0 without the tracker) */
    SMD_LOG_PSI_RLS,     /* @log(psi_r_rls, Wb) its psi_r estimate (0 without the tracker) */
    SMD_LOG_PHASE,       /* @log(phase) start-up phase: 0 forced (I/f), 1 encoder handover,
                          * 2 position source */
    SMD_LOG_STATUS,      /* @log(status) controller status code of the step (smd_status) */
    SMD_LOG_FAULT,       /* @log(fault) controller fault word of the step
                          * (smd_drive_out.fault, FAULT_BITS) */
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
    int pwm_off;         /* ... and the drive's pwm_off with them (smd_plant.off) */
    long k;              /* samples done */
    int seg[6];          /* last segment of each profile (time only grows) */
    double R_s0;         /* the plant's configured R_s (R_s_scale multiplies it) */
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

/* Commissioning against the plant (issue 23): the identification of R_s and
 * the inverter's drop (smd_ident.h) in place of the drive, sample by sample
 * with the same ADC, PWM and plant, from where the engine is, until the
 * test ends or n samples; returns the samples run. With log != 0 every
 * stride-th sample writes t, the true current i_alpha and the applied alpha
 * voltage command (3 doubles a row). */
long smd_engine_run_ident_rs(smd_engine *e, const smd_ident_rs_params *p, smd_ident_rs_state *s,
                             long n, double *log, long stride);
/* The same for step 2, the inductance (no log). */
long smd_engine_run_ident_ls(smd_engine *e, const smd_ident_ls_params *p, smd_ident_ls_state *s,
                             long n);
/* Step 4, J and B: the drive runs (its configuration from smd_engine_init)
 * on the test's speed reference, the test takes its torque current, speed
 * estimate and fault word each sample; until the test ends or n samples
 * (the samples run). With log != 0 every stride-th sample writes a row of
 * the log (SMD_LOG_N doubles), as smd_engine_run does. */
long smd_engine_run_ident_mech(smd_engine *e, const smd_ident_mech_params *p,
                               smd_ident_mech_state *s, long n, double *log, long stride);
/* Step 3, the PM flux (no log). */
long smd_engine_run_ident_psi(smd_engine *e, const smd_ident_psi_params *p,
                              smd_ident_psi_state *s, long n);
/* The plant's true mechanical speed, rad/s. */
double smd_engine_rotor_speed(const smd_engine *e);
/* The plant's true electrical rotor angle, rad (how far a test moved it). */
double smd_engine_rotor_angle(const smd_engine *e);

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

/*
 * Host-only plant, double precision: a two-level inverter (carrier-comparison
 * PWM with regular sampling at the carrier peak, or its switching-cycle
 * average; dead time), an optional LCL filter between inverter and machine,
 * an SPMSM, mechanics with brake, fan and external loads, and the ADC model.
 *
 *   inverter -> [LCL filter: L1, C1, L2o | none] -> SPMSM (R_s, L_s, psi_r)
 *
 * Without the filter the machine's electrical equation is yang2018 eq. (1),
 * solved in closed form per carrier period (smd_spmsm.c); with it, the
 * three-state filter-machine system of yao2022 eq. (1)-(3) is solved exactly
 * in modal coordinates (smd_lcl.c). Both hold the electrical speed at its
 * predicted mid-period value for the electrical solution and advance the
 * mechanics exactly with the period's mean torque (smd_mech.c). See
 * docs/architecture.md.
 *
 * Space vectors are amplitude-invariant (alpha + j beta); angles electrical.
 */
#ifndef SMD_PLANT_H
#define SMD_PLANT_H

#include <complex.h>
#include <stdint.h>

#include "smdsim/smd_adc.h"

typedef enum smd_pwm_mode {
    SMD_PWM_AVERAGED = 0,   /* switching-cycle average */
    SMD_PWM_CARRIER = 1     /* carrier comparison, regular sampling */
} smd_pwm_mode;

/* How the dead time acts on a leg (docs/architecture.md, Plant). */
typedef enum smd_dead_time_model {
    SMD_DT_SIGN = 0,  /* the diode by the sign of the current at the period start */
    SMD_DT_CLAMP = 1  /* zero-current clamping: the diode by the current at each commanded
                       * edge; a current that reaches zero within the dead time stays there
                       * and the open leg floats at the voltage that holds it there
                       * (the machine's phase, or behind the LCL filter the
                       * inverter-side current against the capacitor voltage) */
} smd_dead_time_model;

/* Everything the plant needs (true values), SI units. */
typedef struct smd_plant_config {
    /* machine */
    double R_s;        /* stator resistance, ohm, > 0 */
    double L_s;        /* stator inductance, H */
    double psi_r;      /* PM flux, Wb */
    double n_p;        /* pole pairs */
    double J;          /* inertia, kg m^2 */
    double B;          /* viscous friction, N m s/rad */
    /* LCL filter section (lcl = 0: the inverter feeds the machine directly) */
    int lcl;
    double L1;         /* inverter-side inductance, H */
    double L2o;        /* machine-side filter inductance, H (>= 0; in series with L_s) */
    double C1;         /* filter capacitance, F */
    /* inverter */
    double u_dc;       /* DC-link voltage, V */
    double T_sw;       /* carrier period = sampling period, s */
    int pwm_mode;      /* smd_pwm_mode */
    int dead_time_model; /* smd_dead_time_model */
    double t_dead;     /* dead time, s (diode by the dead_time_model) */
    /* ADC: the motor-current channels, and the inverter-side ones (LCL) */
    double adc_gain[3];      /* per-phase gain (1 = exact) */
    double adc_offset[3];    /* per-phase offset, A */
    double adc_gain_i1[3];
    double adc_offset_i1[3];
    double adc_noise;        /* white-noise standard deviation (every channel), A */
    int adc_bits;            /* 0: no quantisation */
    int adc_n_oversample;    /* conversions averaged a sample, 1..64 (0 is taken as 1) */
    int adc_sensors;         /* current sensors a channel set: 2 (a, b; c = -a - b) or 3
                              * (the engine removes the zero sequence, smd_abc_to_ab2);
                              * 0 is taken as 2 */
    double adc_full_scale;   /* +- range, A */
    uint64_t seed;           /* noise generator seed */
    /* load */
    double w_brake_eps; /* speed (rad/s) below which a brake's torque tapers linearly to 0 */
    double k_fan;       /* fan load coefficient, N m s^2/rad^2 (T = k w_M |w_M|) */
    /* initial state, rotor frame */
    double w_M0;        /* mechanical speed, rad/s */
    double theta_r0;    /* electrical angle, rad */
    double i_d0, i_q0;  /* motor current, A */
    double uc_d0, uc_q0; /* capacitor voltage, V (LCL) */
    double i1_d0, i1_q0; /* inverter-side current, A (LCL) */
} smd_plant_config;

/* Solver data of the LCL section: the filter-machine matrix diagonalised. */
typedef struct smd_lcl_modes {
    double complex lam[3];   /* eigenvalues, 1/s: [0] real, [1], [2] a pair or real */
    double complex v[3][3];  /* right eigenvectors, v[state][mode] */
    double complex w[3][3];  /* rows of V^{-1}, w[mode][state] */
    double complex beta[3];  /* modal input gains (V^{-1} b) */
    double complex phi[3];   /* modal EMF gains (V^{-1} f) */
    double complex eT[3];    /* e^{lambda T} */
    double complex gT[3];    /* (e^{lambda T} - 1) / lambda */
    int kind;                /* 1: modes 1, 2 complex conjugate; 0: all real */
} smd_lcl_modes;

typedef struct smd_plant {
    smd_plant_config c;
    /* --- state, stationary frame --- */
    double i_re, i_im;    /* motor current i_s (= i_2 with the filter), A */
    double i1_re, i1_im;  /* inverter-side current i_1 (= i_s without the filter), A */
    double uc_re, uc_im;  /* capacitor voltage u_c (0 without the filter), V */
    double theta_r;       /* electrical angle, wrapped to [-pi, pi) */
    double w_M;           /* mechanical speed, rad/s */
    double T_e_mean;      /* mean electromagnetic torque over the last period, N m */
    double T_L_mean;      /* mean load torque over the last period (viscous B w excluded), N m */
    double u_re, u_im;    /* mean applied inverter voltage over the last period, V */
    int off;              /* 1: every switch open over the next period (the drive's pwm_off):
                           * the legs on their diodes, or floating at zero current (the
                           * clamping model's walk, whatever dead_time_model); 2: every
                           * lower switch on, forced (an MCU's forced output level): nothing
                           * switches, so no dead time (the commissioning's shorted coast) */
    /* --- private --- */
    double a;             /* R_s / (L2o + L_s), 1/s */
    double L2;            /* L2o + L_s, H */
    smd_lcl_modes m;      /* LCL only */
    smd_rng rng;          /* ADC noise generator */
    int solver;           /* 0: smd_spmsm_step, 1: smd_spmsm_step_clamp, 2: smd_lcl_step */
    int leg_open[3];      /* with the switches off: the legs floating at the last period's end */
} smd_plant;

/* The codes of smd_plant_init: 0 or the first bad field, in the order it
 * checks them. Each entry's comment is the code's schema: the name
 * smd_plant_field gives (the string) and @scenario(...), the fields of a
 * smodrive scenario behind it; tools/gen_layout.py generates the names table
 * (sim/src/smd_plant_fields.h) and the binding's map from them. */
typedef enum smd_plant_field_code {
    SMD_PF_OK = 0,                /* "ok" */
    SMD_PF_R_S = 1,               /* "R_s" @scenario(motor.R_s) */
    SMD_PF_L_S = 2,               /* "L_s" @scenario(motor.L_s) */
    SMD_PF_PSI_R = 3,             /* "psi_r" @scenario(motor.psi_r) */
    SMD_PF_N_P = 4,               /* "n_p" @scenario(motor.n_p) */
    SMD_PF_J = 5,                 /* "J" @scenario(motor.J) */
    SMD_PF_B = 6,                 /* "B" @scenario(motor.B) */
    SMD_PF_LCL = 7,               /* "lcl" @scenario(lcl) */
    SMD_PF_L1 = 8,                /* "L1" @scenario(lcl.L1) */
    SMD_PF_L2O = 9,               /* "L2o" @scenario(lcl.L2o) */
    SMD_PF_C1 = 10,               /* "C1" @scenario(lcl.C1) */
    SMD_PF_U_DC = 11,             /* "u_dc" @scenario(inverter.u_dc) */
    SMD_PF_T_SW = 12,             /* "T_sw" @scenario(T_sp) */
    SMD_PF_PWM_MODE = 13,         /* "pwm_mode" @scenario(inverter.pwm) */
    SMD_PF_T_DEAD = 14,           /* "t_dead" @scenario(inverter.t_dead) */
    SMD_PF_ADC_GAIN = 15,         /* "adc_gain" @scenario(adc.gain) */
    SMD_PF_ADC_OFFSET = 16,       /* "adc_offset" @scenario(adc.offset) */
    SMD_PF_ADC_GAIN_I1 = 17,      /* "adc_gain_i1" @scenario(adc.gain_i1) */
    SMD_PF_ADC_OFFSET_I1 = 18,    /* "adc_offset_i1" @scenario(adc.offset_i1) */
    SMD_PF_ADC_NOISE = 19,        /* "adc_noise" @scenario(adc.noise) */
    SMD_PF_ADC_BITS = 20,         /* "adc_bits" @scenario(adc.bits) */
    SMD_PF_ADC_FULL_SCALE = 21,   /* "adc_full_scale" @scenario(adc.full_scale) */
    SMD_PF_W_BRAKE_EPS = 22,      /* "w_brake_eps" @scenario(load.w_brake_eps) */
    SMD_PF_K_FAN = 23,            /* "k_fan" @scenario(load.k_fan) */
    SMD_PF_W_M0 = 24,             /* "w_M0" @scenario(w_M0) */
    SMD_PF_THETA_R0 = 25,         /* "theta_r0" @scenario(theta_r0) */
    SMD_PF_I_DQ0 = 26,            /* "i_d0/i_q0": a warm start's q current, T_L(0) / k_t
                                   * @scenario(warm_start, w_M0, load.T_ext, load.T_brake,
                                   * load.k_fan, motor.B, motor.psi_r, motor.n_p) */
    SMD_PF_UC_DQ0 = 27,           /* "uc_d0/uc_q0": a warm start's capacitor voltage
                                   * @scenario(warm_start, w_M0, load.T_ext, load.T_brake,
                                   * load.k_fan, motor.B, motor.psi_r, motor.n_p, motor.R_s,
                                   * motor.L_s, lcl.L2o) */
    SMD_PF_I1_DQ0 = 28,           /* "i1_d0/i1_q0": a warm start's inverter-side current
                                   * @scenario(warm_start, w_M0, load.T_ext, load.T_brake,
                                   * load.k_fan, motor.B, motor.psi_r, motor.n_p, motor.R_s,
                                   * motor.L_s, lcl.L2o, lcl.C1) */
    SMD_PF_MODES = 29,            /* "R_s/L1/L2o/L_s/C1 (repeated or unstable filter modes)"
                                   * (smd_lcl_setup) @scenario(motor.R_s, motor.L_s,
                                   * lcl.L1, lcl.L2o, lcl.C1) */
    SMD_PF_DEAD_TIME_MODEL = 30,  /* "dead_time_model" (sign or clamp)
                                   * @scenario(inverter.dead_time_model) */
    SMD_PF_ADC_N_OVERSAMPLE = 31, /* "adc_n_oversample" @scenario(adc.n_oversample) */
    SMD_PF_ADC_SENSORS = 32,      /* "adc_sensors" (2 or 3) @scenario(adc.sensors) */
    SMD_PF_N                      /* the number of codes */
} smd_plant_field_code;

/* Returns 0 or a positive code naming the first bad field (smd_plant_field,
 * smd_plant_field_code). */
int smd_plant_init(smd_plant *p, const smd_plant_config *c);
/* The motor's resistance from now on (winding heating), its state kept:
 * 0, or the code of the field smd_plant_init would refuse (SMD_PF_R_S out of
 * [1e-6, 1e3] ohm, SMD_PF_MODES with the filter), the plant unchanged. */
int smd_plant_set_resistance(smd_plant *p, double R_s);
const char *smd_plant_field(int code);

/* Advance one carrier period with duties d_abc, external load torque T_ext
 * (signed, N m) and brake torque magnitude T_brake (opposes rotation). */
void smd_plant_step(smd_plant *p, const double d_abc[3], double T_ext, double T_brake);

/* ADC samples at the carrier peak: the motor phase currents, and (LCL) the
 * inverter-side ones (noise drawn i_1 a, b, c first, then i_s a, b, c);
 * i1_abc may be NULL without the filter. */
void smd_plant_sample(smd_plant *p, double i_abc[3], double i1_abc[3]);

/* True phase currents (motor; inverter side, may be NULL). */
void smd_plant_phase_currents(const smd_plant *p, double i_abc[3], double i1_abc[3]);

/* Eigenvalues of the LCL filter-machine matrix (0 without the filter). */
void smd_plant_eigenvalues(const smd_plant *p, double re[3], double im[3]);

/* Open-loop V/f-style driver for benchmarks and steady-state runs: n steps
 * with duties d_x = 0.5 + 0.5 m cos(theta_r + delta - 2 pi x / 3) (theta_r
 * the plant's angle at each period start) and external torque T_ext. */
void smd_plant_run_open(smd_plant *p, long n, double m, double delta, double T_ext);

unsigned long smd_sizeof_plant(void);
unsigned long smd_sizeof_plant_config(void);

/* The two exact solvers (smd_spmsm.c, smd_lcl.c); their shared mechanics are
 * in sim/src/smd_mech.h. */
void smd_spmsm_step(smd_plant *p, const double d_abc[3], double T_ext, double T_brake);
/* the same with zero-current clamping (dead_time_model SMD_DT_CLAMP, t_dead > 0) */
void smd_spmsm_step_clamp(smd_plant *p, const double d_abc[3], double T_ext, double T_brake);
int smd_lcl_setup(smd_plant *p); /* 0 or the field code of repeated/unstable modes */
void smd_lcl_step(smd_plant *p, const double d_abc[3], double T_ext, double T_brake);

#endif

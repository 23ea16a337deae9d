/*
 * Host-only plant: SPMSM in the stationary frame (yang2018 eq. (1)), mechanics
 * with inertia, viscous friction and load, a two-level inverter with
 * carrier-comparison PWM (symmetric triangle, regular sampling at the carrier
 * peak) or its switching-cycle average, optional dead time, and an ADC model.
 * Double precision throughout.
 *
 * Integration: over one carrier period the electrical equation is linear with
 * piecewise-constant voltage; it is solved in closed form (homogeneous decay,
 * rotating-EMF particular solution, and one exact step response per switching
 * edge). The speed is held at its predicted mid-period value for the
 * electrical solution; the mechanics are then advanced exactly with the
 * period's exact mean electromagnetic torque. See docs/architecture.md.
 */
#ifndef SMD_PLANT_H
#define SMD_PLANT_H

#include <stdint.h>

#include "smdsim/smd_adc.h"

typedef enum smd_pwm_mode {
    SMD_PWM_AVERAGED = 0,   /* switching-cycle average */
    SMD_PWM_CARRIER = 1     /* carrier comparison, regular sampling */
} smd_pwm_mode;

/* Everything the plant needs (true values), SI units. */
typedef struct smd_plant_config {
    double R_s;        /* stator resistance, ohm, > 0 */
    double L_s;        /* stator inductance, H */
    double psi_r;      /* PM flux, Wb */
    double n_p;        /* pole pairs */
    double J;          /* inertia, kg m^2 */
    double B;          /* viscous friction, N m s/rad */
    double u_dc;       /* DC-link voltage, V */
    double T_sw;       /* carrier period = sampling period, s */
    int pwm_mode;      /* smd_pwm_mode */
    double t_dead;     /* dead time, s */
    double adc_gain[3];   /* per-phase gain (1 = exact) */
    double adc_offset[3]; /* per-phase offset, A */
    double adc_noise;     /* white-noise standard deviation, A */
    int adc_bits;         /* 0: no quantisation */
    double adc_full_scale; /* +- range, A */
    uint64_t seed;        /* noise generator seed */
    double w_brake_eps;   /* mechanical speed (rad/s) below which a brake's torque tapers linearly to 0 */
    double k_fan;         /* fan load coefficient, N m s^2/rad^2 (T = k w_M |w_M|) */
    double w_M0;          /* initial mechanical speed, rad/s */
    double theta_r0;      /* initial electrical angle, rad */
    double i_d0;          /* initial current in the rotor frame, A */
    double i_q0;
} smd_plant_config;

typedef struct smd_plant {
    smd_plant_config c;
    double a;            /* R/L, 1/s */
    double i_re, i_im;   /* stator current i_s (alpha, beta), A */
    double theta_r;      /* electrical angle, wrapped to [-pi, pi) */
    double w_M;          /* mechanical speed, rad/s */
    double T_e_mean;     /* mean electromagnetic torque over the last period, N m */
    double T_L_mean;     /* load torque applied over the last period, N m */
    double u_re, u_im;   /* mean applied stator voltage over the last period, V */
    smd_rng rng;         /* ADC noise generator */
} smd_plant;

/* Returns 0 or a positive code naming the first bad field (see smd_plant_field). */
int smd_plant_init(smd_plant *p, const smd_plant_config *c);
/* Field name of an init error code (for messages). */
const char *smd_plant_field(int code);

/* Advance one carrier period with duties d_abc, external load torque T_ext
 * (signed, N m) and brake torque magnitude T_brake (opposes rotation). */
void smd_plant_step(smd_plant *p, const double d_abc[3], double T_ext, double T_brake);

/* ADC sample of the three phase currents at the carrier peak. */
void smd_plant_sample(smd_plant *p, double i_abc_meas[3]);

/* Leg-high interval [t_on, t_off) within a carrier period for duty d and
 * phase current i_x (dead-time direction), as used by the plant: see
 * smd_pwm_edges (smdsim/smd_pwm.h) with the config's T_sw and t_dead. */
void smd_pwm_leg_edges(const smd_plant_config *c, double d, double i_x, double *t_on,
                       double *t_off);

unsigned long smd_sizeof_plant(void);

/* Phase currents (true). */
void smd_plant_phase_currents(const smd_plant *p, double i_abc[3]);

#endif

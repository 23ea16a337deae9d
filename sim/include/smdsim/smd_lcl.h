/*
 * Host-only plant: two-level inverter -> LCL filter -> high-speed SPMSM
 * (yao2022, Sec. II eq. (1)-(3), Table II), in the stationary frame with
 * complex space vectors x = alpha + j beta (amplitude-invariant Clarke):
 *
 *   C1 du_c/dt = i_1 - i_2
 *   L1 di_1/dt = u - u_c
 *   L2 di_2/dt = u_c - R i_2 - e,     L2 = L2o + Ls,
 *   e = j w psi_m e^{j theta}         (rotating at the electrical speed w)
 *
 * (the paper prints the first row of A_s with the wrong signs; the equations
 * above are the circuit's). Torque T_e = 1.5 n_p psi_m Im{i_2 e^{-j theta}};
 * mechanics J dw_M/dt = T_e - B w_M - k_fan w_M |w_M| - T_ext.
 *
 * Integration over one carrier period, exact for piecewise-constant inverter
 * voltage and a rotating EMF at constant speed: the real 3x3 matrix A of
 * d[u_c, i_1, i_2]/dt = A x + b u + f e is diagonalised once at init (closed
 * form eigenvectors, cubic roots by Newton), and each mode
 * dz/dt = lambda z + beta u + phi e is solved in closed form: homogeneous
 * decay e^{lambda t}, rotating-EMF particular solution phi e / (j w - lambda),
 * and the exact response (e^{lambda tau} - 1) / lambda to each switching edge.
 * The torque's frame-weighted integral int i_2 e^{-j theta} dt is integrated
 * exactly the same way. As in smd_plant, the electrical speed is held at its
 * predicted mid-period value for the electrical solution; the mechanics are
 * advanced exactly with the period's mean torque and the load held at its
 * period-start value.
 *
 * PWM (regular-sampled carrier or switching-cycle average, dead time by the
 * sign of the inverter-side current i_1) and the ADC model are shared with
 * smd_plant (smdsim/smd_pwm.h, smdsim/smd_adc.h). Both i_1 and i_2 are
 * measured, each phase with its own gain and offset; u_c is not measured.
 */
#ifndef SMD_LCL_H
#define SMD_LCL_H

#include <complex.h>
#include <stdint.h>

#include "smdsim/smd_adc.h"

/* pwm_mode: 0 = switching-cycle average, 1 = carrier (as smd_pwm_mode) */

typedef struct smd_lcl_config {
    double R;        /* motor winding resistance, ohm, > 0 */
    double L1;       /* inverter-side filter inductance, H */
    double L2o;      /* machine-side filter inductance, H (>= 0) */
    double Ls;       /* machine inductance, H */
    double C1;       /* filter capacitance, F */
    double psi_m;    /* PM flux, Wb */
    double n_p;      /* pole pairs */
    double J;        /* inertia, kg m^2 */
    double B;        /* viscous friction, N m s/rad */
    double k_fan;    /* fan load, N m s^2/rad^2 (T = k_fan w_M |w_M|) */
    double u_dc;     /* DC-link voltage, V */
    double T_sw;     /* carrier period = sampling period, s */
    int pwm_mode;    /* 0 averaged, 1 carrier */
    double t_dead;   /* dead time, s */
    double adc_gain_i1[3];   /* per-phase gain of the i_1 channels (1 = exact) */
    double adc_offset_i1[3]; /* per-phase offset of the i_1 channels, A */
    double adc_gain_i2[3];   /* per-phase gain of the i_2 channels */
    double adc_offset_i2[3]; /* per-phase offset of the i_2 channels, A */
    double adc_noise;        /* white-noise standard deviation (all channels), A */
    int adc_bits;            /* 0: no quantisation */
    double adc_full_scale;   /* +- range, A */
    uint64_t seed;           /* noise generator seed */
    double w_M0;             /* initial mechanical speed, rad/s */
    double theta_r0;         /* initial electrical angle, rad */
    double uc_d0, uc_q0;     /* initial capacitor voltage in the rotor frame, V */
    double i1_d0, i1_q0;     /* initial inverter-side current in the rotor frame, A */
    double i2_d0, i2_q0;     /* initial motor current in the rotor frame, A */
} smd_lcl_config;

typedef struct smd_lcl_plant {
    smd_lcl_config c;
    /* --- public state (stationary frame), mirrored by src/smodrive/lcl_plant.py --- */
    double uc_re, uc_im;  /* capacitor voltage u_c, V */
    double i1_re, i1_im;  /* inverter-side current i_1, A */
    double i2_re, i2_im;  /* motor current i_2, A */
    double theta_r;       /* electrical angle, wrapped to [-pi, pi) */
    double w_M;           /* mechanical speed, rad/s */
    double T_e_mean;      /* mean electromagnetic torque over the last period, N m */
    double T_L_mean;      /* load torque T_ext + fan held over the last period (viscous B w excluded, as smd_plant), N m */
    double u_re, u_im;    /* mean applied inverter voltage over the last period, V */
    double lam_re[3], lam_im[3]; /* eigenvalues of A, 1/s: [0] real, [1],[2] the pair */
    double L2;            /* L2o + Ls, H */
    /* --- private: modal data --- */
    double complex lam[3];   /* eigenvalues */
    double complex v[3][3];  /* right eigenvectors, v[state][mode] */
    double complex w[3][3];  /* rows of V^{-1}, w[mode][state] */
    double complex beta[3];  /* modal input gains (V^{-1} b) */
    double complex phi[3];   /* modal EMF gains (V^{-1} f) */
    double complex eT[3];    /* e^{lambda T} */
    double complex gT[3];    /* (e^{lambda T} - 1) / lambda */
    int kind;                /* 1: modes 1, 2 complex conjugate; 0: all real */
    smd_rng rng;
} smd_lcl_plant;

/* Returns 0 or a positive code naming the first bad field (smd_lcl_field). */
int smd_lcl_init(smd_lcl_plant *p, const smd_lcl_config *c);
const char *smd_lcl_field(int code);

/* Advance one carrier period with duties d_abc and external load torque T_ext
 * (signed, N m, opposing positive rotation when positive). */
void smd_lcl_step(smd_lcl_plant *p, const double d_abc[3], double T_ext);

/* ADC samples of the three phases of i_1 and of i_2 (noise drawn i_1 a, b, c
 * then i_2 a, b, c). */
void smd_lcl_sample(smd_lcl_plant *p, double i1_abc[3], double i2_abc[3]);

/* Open-loop V/f-style driver for benchmarks and steady-state runs: n steps
 * with duties d_x = 0.5 + 0.5 m cos(theta_r + delta - 2 pi x / 3) (theta_r
 * the plant's angle at each period start) and external torque T_ext. */
void smd_lcl_run_open(smd_lcl_plant *p, long n, double m, double delta, double T_ext);

/* True phase values. */
void smd_lcl_phase_currents(const smd_lcl_plant *p, double i1_abc[3], double i2_abc[3]);

unsigned long smd_sizeof_lcl_plant(void);
unsigned long smd_sizeof_lcl_config(void);

#endif

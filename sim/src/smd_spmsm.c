/* SPMSM without filter: yang2018 eq. (1) solved in closed form over one
 * carrier period (see smd_plant.h and docs/architecture.md). */
#include "smdsim/smd_plant.h"
#include "smd_mech.h"
#include "smdsim/smd_pwm.h"
#include "smd_dtc.h"

#include <complex.h>
#include <math.h>


/* a = e^{j 2 pi / 3}: phase b and c unit vectors */
static const double A_RE = -0.5;
static const double A_IM = 0.86602540378443864676;

/* phi1(x) = (1 - e^{-x}) / x, accurate for small |x| (complex) */
static double complex phi1(double complex x)
{
    if (cabs(x) < 1e-4) {
        return 1.0 - x / 2.0 + x * x / 6.0 - x * x * x / 24.0;
    }
    return (1.0 - cexp(-x)) / x;
}

/* Integral over [0, tau] of the unit step response g(s) = (1 - e^{-a s}) / R
 * weighted by e^{-j w s}:  (1/R) [E(jw) - E(a + jw)],  E(z) = tau phi1(z tau). */
static double complex step_weighted_integral(double a, double R, double w, double tau)
{
    double complex z1 = I * w * tau;
    double complex z2 = (a + I * w) * tau;
    return tau * (phi1(z1) - phi1(z2)) / R;
}

/* Per-period constants for the response to a voltage step at instant t. */
typedef struct edge_kernel {
    double a, R, L, w, T;
    double complex e_mwT;  /* e^{-j w T} */
    double complex den;    /* R j w (a + j w) */
    int slow;              /* |w T| small: use the series forms */
} edge_kernel;

static void edge_kernel_init(edge_kernel *k, double a, double R, double L, double w, double T)
{
    k->a = a;
    k->R = R;
    k->L = L;
    k->w = w;
    k->T = T;
    k->slow = fabs(w * T) < 1e-3;
    k->e_mwT = cos(w * T) - I * sin(w * T);
    k->den = R * I * w * (a + I * w);
}

/* A unit voltage step applied at t in [0, T]: g = its current at T,
 * (1 - e^{-a tau}) / R with tau = T - t, and s = the integral over [t, T] of
 * its current weighted by e^{-j w t'}:
 *   s = e^{-j w t} [a (1 - q) + j w q (e^{-a tau} - 1)] / (R j w (a + j w)),
 * q = e^{-j w tau}; one expm1 and one sine/cosine pair per edge. */
static void edge_response(const edge_kernel *k, double t, double *g, double complex *s)
{
    double tau = k->T - t;
    double em = expm1(-k->a * tau);
    *g = -em / k->R;
    if (k->slow) {
        *s = cexp(-I * k->w * t) * step_weighted_integral(k->a, k->R, k->w, tau);
    } else {
        double complex E = cos(k->w * t) - I * sin(k->w * t);
        double complex q = k->e_mwT * conj(E);
        *s = E * (k->a * (1.0 - q) + I * k->w * q * em) / k->den;
    }
}

/* ---- dead time with zero-current clamping (carrier PWM): smd_dtc.h ----
 * The circuit: the phase current through R_s, L_s against the back EMF,
 * exact between events (homogeneous + rotating-EMF particular + the
 * constant leg voltages). */
typedef struct spmsm_dtc {
    const smd_plant *p;
    double w_e;
    double complex ejth0, C, i;
} spmsm_dtc;

static inline void spmsm_dtc_advance(void *ctx, double t, double tn, const double v[3])
{
    spmsm_dtc *s = ctx;
    const smd_plant_config *c = &s->p->c;
    const double a = s->p->a, R = c->R_s, udc = c->u_dc, w_e = s->w_e;
    double complex U = 2.0 / 3.0 * udc * (v[0] + v[1] * (A_RE + I * A_IM) + v[2] * (A_RE - I * A_IM));
    double h = tn - t, em = expm1(-a * h);
    double complex e0 = s->ejth0 * cexp(I * w_e * t), e1 = s->ejth0 * cexp(I * w_e * tn);
    s->i = (s->i - s->C * e0) * (1.0 + em) + s->C * e1 - U * em / R;
}

static inline void spmsm_dtc_probe(void *ctx, double t, double i_x[3], double ex[3])
{
    spmsm_dtc *s = ctx;
    const smd_plant_config *c = &s->p->c;
    double complex ejth = s->ejth0 * cexp(I * s->w_e * t);
    double complex e = I * s->w_e * c->psi_r * ejth; /* back EMF, L di/dt = u - R i - e */
    int x;
    for (x = 0; x < 3; x++) {
        i_x[x] = smd_dtc_phase(s->i, x);
        ex[x] = smd_dtc_phase(e, x) / c->u_dc;
    }
}

static void dtc_legs(smd_plant *p, const double d[3], double T, double w_e,
                     double complex ejth0, double complex C, dtc_leg legs[3])
{
    spmsm_dtc s;
    dtc_circuit circ;
    s.p = p;
    s.w_e = w_e;
    s.ejth0 = ejth0;
    s.C = C;
    s.i = p->i_re + I * p->i_im;
    circ.R = p->c.R_s;
    circ.L = p->c.L_s;
    circ.u_dc = p->c.u_dc;
    circ.ctx = &s;
    circ.open = p->leg_open;
    circ.advance = spmsm_dtc_advance;
    circ.probe = spmsm_dtc_probe;
    if (p->off) { /* (two copies of the walk, each with off a constant) */
        smd_dtc_legs(&circ, d, T, p->c.t_dead, 1, legs);
    } else {
        smd_dtc_legs(&circ, d, T, p->c.t_dead, 0, legs);
    }
}

/* The leg voltages of the period with zero-current clamping (carrier:
 * dtc_legs; averaged: smd_pwm_avg_duty_clamp) added to i1, i_int and u_mean.
 * A leg whose steps are one pulse of full height is taken exactly as in the
 * sign model (the same arithmetic, so without clamping the result is the
 * sign model's bit for bit). */
typedef struct period_sums {
    double complex i1, i_int, u_mean; /* i(T), int i e^{-j theta} dt, mean voltage */
} period_sums;

/* kept out of smd_spmsm_step (its stack arrays and code would slow the
 * default path) */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static void clamp_step(smd_plant *p, const double d_abc[3], double complex ejth0,
                       double w_e, double complex C, const edge_kernel *ek,
                       const double complex leg_dir[3], const double i_abc[3], period_sums *sums)
{
    double complex *i1 = &sums->i1, *i_int = &sums->i_int, *u_mean = &sums->u_mean;
    const smd_plant_config *c = &p->c;
    const double T = c->T_sw, a = p->a, R = c->R_s, L = c->L_s;
    double d[3];
    int x, k;
    for (x = 0; x < 3; x++) d[x] = smd_pwm_clamp(d_abc[x]);
    if (c->pwm_mode == SMD_PWM_CARRIER || p->off) {
        dtc_leg legs[3];
        dtc_legs(p, d, T, w_e, ejth0, C, legs);
        for (x = 0; x < 3; x++) {
            const dtc_leg *lg = &legs[x];
            if ((lg->n == 1 && lg->dv[0] == 1.0) ||
                (lg->n == 2 && lg->dv[0] == 1.0 && lg->dv[1] == -1.0)) {
                double t_on = lg->t[0], t_off = lg->n == 2 ? lg->t[1] : T;
                if (t_off > t_on) {
                    double g_on, g_off;
                    double complex s_on, s_off;
                    edge_response(ek, t_on, &g_on, &s_on);
                    edge_response(ek, t_off, &g_off, &s_off);
                    *i1 += leg_dir[x] * (g_on - g_off);
                    *i_int += leg_dir[x] * conj(ejth0) * (s_on - s_off);
                    *u_mean += leg_dir[x] * (t_off - t_on) / T;
                }
            } else if (lg->n > 0) {
                double G = 0.0, Um = 0.0;
                double complex S = 0.0;
                for (k = 0; k < lg->n; k++) {
                    double g;
                    double complex s;
                    edge_response(ek, lg->t[k], &g, &s);
                    G += lg->dv[k] * g;
                    S += lg->dv[k] * s;
                    Um += lg->dv[k] * (T - lg->t[k]) / T;
                }
                *i1 += leg_dir[x] * G;
                *i_int += leg_dir[x] * conj(ejth0) * S;
                *u_mean += leg_dir[x] * Um;
            }
        }
    } else {
        /* averaged: the clamp's mean loss at the period-start current, with
         * the other legs high at this leg's edges when their duty is larger
         * (half when equal) and the EMF of the period start */
        double complex e = I * w_e * c->psi_r * ejth0;
        double k_rate = 2.0 / 3.0 * c->u_dc / L;
        for (x = 0; x < 3; x++) {
            int y = (x + 1) % 3, z = (x + 2) % 3;
            double hy = d[y] > d[x] ? 1.0 : (d[y] == d[x] ? 0.5 : 0.0);
            double hz = d[z] > d[x] ? 1.0 : (d[z] == d[x] ? 0.5 : 0.0);
            double v_f = 0.5 * (hy + hz) + 1.5 * smd_dtc_phase(e, x) / c->u_dc;
            double de = smd_pwm_avg_duty_clamp(T, c->t_dead, d[x], i_abc[x], v_f, k_rate);
            *i1 += leg_dir[x] * de * T * creal(phi1(a * T)) / L;
            *i_int += leg_dir[x] * de * conj(ejth0) * step_weighted_integral(a, R, w_e, T);
            *u_mean += leg_dir[x] * de;
        }
    }
}

/* One period; clamp: zero-current clamping (clamp_step), else the sign
 * model. Specialised into the two entry points below, so that the default
 * one carries no test of the option. */
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void spmsm_step(smd_plant *p, const double d_abc[3], double T_ext, double T_brake,
                              int clamp)
{
    const smd_plant_config *c = &p->c;
    const double T = c->T_sw;
    const double R = c->R_s;
    const double L = c->L_s;
    const double a = p->a;
    const double Kt = 1.5 * c->n_p * c->psi_r;
    double complex i0 = p->i_re + I * p->i_im;
    double complex leg_dir[3];
    double complex i1, i_int, u_mean, C, Ap;
    double i_abc[3];
    double T_e0, T_L, T_e_mean, w_mid, w_e;
    double complex ejth0 = cexp(I * p->theta_r);
    edge_kernel ek;
    int x;

    leg_dir[0] = 2.0 / 3.0 * c->u_dc;
    leg_dir[1] = 2.0 / 3.0 * c->u_dc * (A_RE + I * A_IM);
    leg_dir[2] = 2.0 / 3.0 * c->u_dc * (A_RE - I * A_IM);

    /* Load torque over this period: external + brake (opposes rotation,
     * linear taper inside +-w_brake_eps) + fan. Held over the period. */
    T_L = smd_load_torque(c, p->w_M, T_ext, T_brake);

    /* Mid-period speed prediction for the electrical solution. */
    T_e0 = Kt * cimag(i0 * conj(ejth0));
    w_mid = p->w_M + 0.5 * T * (T_e0 - T_L - c->B * p->w_M) / c->J;
    w_e = c->n_p * w_mid;
    edge_kernel_init(&ek, a, R, L, w_e, T);

    /* Rotating-EMF particular solution i_p(t) = C e^{j theta(t)}, yang2018 eq. (1):
     * L di/dt = u - R i - j w psi e^{j theta}. */
    C = -I * w_e * c->psi_r / (R + I * w_e * L);
    Ap = i0 - C * ejth0; /* homogeneous amplitude */
    /* i(T) and the frame-weighted integral of i over the period (for torque). */
    i1 = Ap * cexp(-a * T) + C * ejth0 * cexp(I * w_e * T);
    /* int_0^T i(t) e^{-j theta(t)} dt, homogeneous + particular parts */
    i_int = Ap * conj(ejth0) * T * phi1((a + I * w_e) * T) + C * T;
    u_mean = 0.0;

    smd_ab_to_abc_d(p->i_re, p->i_im, i_abc);
    if (clamp) {
        /* zero-current clamping (dtc_legs, smd_pwm_avg_duty_clamp) */
        period_sums sums;
        sums.i1 = i1;
        sums.i_int = i_int;
        sums.u_mean = u_mean;
        clamp_step(p, d_abc, ejth0, w_e, C, &ek, leg_dir, i_abc, &sums);
        i1 = sums.i1;
        i_int = sums.i_int;
        u_mean = sums.u_mean;
    } else {
        for (x = 0; x < 3; x++) {
            double d = smd_pwm_clamp(d_abc[x]);
            double t_on, t_off;
            if (c->pwm_mode == SMD_PWM_CARRIER) {
                smd_pwm_edges(T, c->t_dead, d, i_abc[x], &t_on, &t_off);
                if (t_off > t_on) {
                    double g_on, g_off;
                    double complex s_on, s_off;
                    edge_response(&ek, t_on, &g_on, &s_on);
                    edge_response(&ek, t_off, &g_off, &s_off);
                    /* exact step responses at T of a pulse on [t_on, t_off) ... */
                    i1 += leg_dir[x] * (g_on - g_off);
                    /* ... and their frame-weighted integrals over the period */
                    i_int += leg_dir[x] * conj(ejth0) * (s_on - s_off);
                    u_mean += leg_dir[x] * (t_off - t_on) / T;
                }
            } else {
                /* Switching-cycle average: leg voltage d u_dc over the whole period
                 * (dead time as the average volt-second loss). */
                double de = smd_pwm_avg_duty(T, c->t_dead, d, i_abc[x]);
                i1 += leg_dir[x] * de * T * creal(phi1(a * T)) / L;
                i_int += leg_dir[x] * de * conj(ejth0) * step_weighted_integral(a, R, w_e, T);
                u_mean += leg_dir[x] * de;
            }
        }
    }

    /* Mean torque over the period, 1.5 n_p psi Im{i e^{-j theta}}. */
    T_e_mean = Kt * cimag(i_int) / T;

    p->i_re = creal(i1);
    p->i_im = cimag(i1);
    smd_mech_end_period(p, T_e_mean, T_L, T_brake, u_mean);
}

void smd_spmsm_step(smd_plant *p, const double d_abc[3], double T_ext, double T_brake)
{
    spmsm_step(p, d_abc, T_ext, T_brake, 0);
}

void smd_spmsm_step_clamp(smd_plant *p, const double d_abc[3], double T_ext, double T_brake)
{
    spmsm_step(p, d_abc, T_ext, T_brake, 1);
}

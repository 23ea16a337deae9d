#include "smdsim/smd_plant.h"
#include "smdsim/smd_pwm.h"

#include <complex.h>
#include <math.h>

#define TWO_PI 6.283185307179586476925
#define PI 3.141592653589793238463

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

/* phi2(x) = (x - 1 + e^{-x}) / x^2 (real) */
static double phi2r(double x)
{
    if (fabs(x) < 1e-3) {
        return 0.5 - x / 6.0 + x * x / 24.0 - x * x * x / 120.0 + x * x * x * x / 720.0;
    }
    return (x + expm1(-x)) / (x * x);
}

static double wrap_pi(double x)
{
    return x - TWO_PI * floor((x + PI) / TWO_PI);
}

void smd_pwm_leg_edges(const smd_plant_config *c, double d, double i_x, double *t_on,
                       double *t_off)
{
    smd_pwm_edges(c->T_sw, c->t_dead, d, i_x, t_on, t_off);
}

static int bad(double x, double lo, double hi) { return !(isfinite(x) && x >= lo && x <= hi); }

static const char *FIELDS[] = {
    "ok", "R_s", "L_s", "psi_r", "n_p", "J", "B", "u_dc", "T_sw", "pwm_mode", "t_dead",
    "adc_gain", "adc_offset", "adc_noise", "adc_bits", "adc_full_scale", "w_brake_eps",
    "k_fan", "w_M0", "theta_r0", "i_d0", "i_q0"};

const char *smd_plant_field(int code)
{
    if (code < 0 || code >= (int)(sizeof(FIELDS) / sizeof(FIELDS[0]))) {
        return "unknown";
    }
    return FIELDS[code];
}

int smd_plant_init(smd_plant *p, const smd_plant_config *c)
{
    int k;
    if (bad(c->R_s, 1e-6, 1e3)) return 1;
    if (bad(c->L_s, 1e-7, 10.0)) return 2;
    if (bad(c->psi_r, 0.0, 100.0)) return 3;
    if (bad(c->n_p, 1.0, 100.0)) return 4;
    if (bad(c->J, 1e-9, 1e4)) return 5;
    if (bad(c->B, 0.0, 1e3)) return 6;
    if (bad(c->u_dc, 1e-9, 1e5)) return 7;
    if (bad(c->T_sw, 1e-7, 1.0)) return 8;
    if (c->pwm_mode != SMD_PWM_AVERAGED && c->pwm_mode != SMD_PWM_CARRIER) return 9;
    if (bad(c->t_dead, 0.0, 0.25 * c->T_sw)) return 10;
    for (k = 0; k < 3; k++) {
        if (bad(c->adc_gain[k], 0.5, 2.0)) return 11;
        if (bad(c->adc_offset[k], -1e3, 1e3)) return 12;
    }
    if (bad(c->adc_noise, 0.0, 1e3)) return 13;
    if (c->adc_bits < 0 || c->adc_bits > 24) return 14;
    if (bad(c->adc_full_scale, 1e-6, 1e6)) return 15;
    if (bad(c->w_brake_eps, 1e-9, 1e3)) return 16;
    if (bad(c->k_fan, 0.0, 1e3)) return 17;
    if (bad(c->w_M0, -1e5, 1e5)) return 18;
    if (bad(c->theta_r0, -1e3, 1e3)) return 19;
    if (bad(c->i_d0, -1e5, 1e5)) return 20;
    if (bad(c->i_q0, -1e5, 1e5)) return 21;
    p->c = *c;
    p->a = c->R_s / c->L_s;
    p->theta_r = wrap_pi(c->theta_r0);
    p->i_re = c->i_d0 * cos(p->theta_r) - c->i_q0 * sin(p->theta_r);
    p->i_im = c->i_d0 * sin(p->theta_r) + c->i_q0 * cos(p->theta_r);
    p->w_M = c->w_M0;
    p->T_e_mean = 0.0;
    p->T_L_mean = 0.0;
    p->u_re = 0.0;
    p->u_im = 0.0;
    smd_rng_seed(&p->rng, c->seed);
    return 0;
}

void smd_plant_phase_currents(const smd_plant *p, double i_abc[3])
{
    /* amplitude-invariant: i_x = Re(i_s e^{-j 2 pi x / 3}) */
    smd_ab_to_abc_d(p->i_re, p->i_im, i_abc);
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

/* Exact solution of J dw/dt = F - B w over tau from w0: end speed and the
 * integral of w. */
static void lin_mech(double F, double Bv, double J, double w0, double tau, double *w1,
                     double *th)
{
    double b = Bv / J;
    double acc = F / J - b * w0;
    *w1 = w0 + acc * tau * creal(phi1(b * tau));
    *th = w0 * tau + acc * tau * tau * phi2r(b * tau);
}

/* Advance the mechanics over T with electromagnetic torque T_e and load T_L
 * (which includes the brake term evaluated at w0). Outside the brake's taper
 * band |w| < eps the brake torque is constant; inside it is T_brake w / eps, a
 * viscous term, solved exactly. A period that enters the band is split at the
 * crossing instant, so the speed settles at rest without ringing (an explicit
 * hold of the taper rings when T T_brake / (J eps) > 2). Returns the end
 * speed, the integral of w, and the mean load torque. */
static void mech_advance(const smd_plant_config *c, double T_e, double T_L, double T_brake,
                         double w0, double T, double *w1, double *th, double *T_L_mean)
{
    const double eps = c->w_brake_eps;
    double s0 = w0 / eps;
    double T_other, Bb, t_c = 0.0, th1 = 0.0, wc;
    if (s0 > 1.0) s0 = 1.0;
    if (s0 < -1.0) s0 = -1.0;
    T_other = T_L - T_brake * s0; /* load without the brake */
    Bb = c->B + T_brake / eps;    /* viscous coefficient inside the band */
    if (T_brake <= 0.0 || fabs(w0) < eps) {
        if (T_brake <= 0.0) {
            lin_mech(T_e - T_L, c->B, c->J, w0, T, w1, th);
            *T_L_mean = T_L;
        } else {
            lin_mech(T_e - T_other, Bb, c->J, w0, T, w1, th);
            *T_L_mean = T_other + T_brake / eps * (*th / T);
        }
        return;
    }
    /* outside the band: constant brake torque */
    lin_mech(T_e - T_L, c->B, c->J, w0, T, w1, th);
    if (fabs(*w1) >= eps && (*w1) * w0 > 0.0) {
        *T_L_mean = T_L;
        return;
    }
    /* the speed reaches the band edge w_c = sign(w0) eps at t_c: bisection on
     * the exact solution (monotonic in t over the period) */
    {
        double lo = 0.0, hi = T, w_edge = w0 > 0.0 ? eps : -eps;
        int k;
        for (k = 0; k < 60; k++) {
            double mid = 0.5 * (lo + hi), wm, tm;
            lin_mech(T_e - T_L, c->B, c->J, w0, mid, &wm, &tm);
            if ((wm - w_edge) * (w0 - w_edge) > 0.0) lo = mid; else hi = mid;
        }
        t_c = hi;
        lin_mech(T_e - T_L, c->B, c->J, w0, t_c, &wc, &th1);
        wc = w_edge;
    }
    {
        double w2, th2;
        lin_mech(T_e - T_other, Bb, c->J, wc, T - t_c, &w2, &th2);
        *w1 = w2;
        *th = th1 + th2;
        *T_L_mean = (T_L * t_c + T_other * (T - t_c) + T_brake / eps * th2) / T;
    }
}

void smd_plant_step(smd_plant *p, const double d_abc[3], double T_ext, double T_brake)
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
    double T_e0, T_L, T_e_mean, w_mid, w_e, w1, th_int;
    double complex ejth0 = cexp(I * p->theta_r);
    edge_kernel ek;
    int x;

    leg_dir[0] = 2.0 / 3.0 * c->u_dc;
    leg_dir[1] = 2.0 / 3.0 * c->u_dc * (A_RE + I * A_IM);
    leg_dir[2] = 2.0 / 3.0 * c->u_dc * (A_RE - I * A_IM);

    /* Load torque over this period: external + brake (opposes rotation,
     * linear taper inside +-w_brake_eps) + fan. Held over the period. */
    {
        double s = p->w_M / c->w_brake_eps;
        if (s > 1.0) s = 1.0;
        if (s < -1.0) s = -1.0;
        T_L = T_ext + T_brake * s + c->k_fan * p->w_M * fabs(p->w_M);
    }

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

    smd_plant_phase_currents(p, i_abc);
    for (x = 0; x < 3; x++) {
        double d = smd_pwm_clamp(d_abc[x]);
        double t_on, t_off;
        if (c->pwm_mode == SMD_PWM_CARRIER) {
            smd_pwm_leg_edges(c, d, i_abc[x], &t_on, &t_off);
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

    /* Mean torque over the period, 1.5 n_p psi Im{i e^{-j theta}}. */
    T_e_mean = Kt * cimag(i_int) / T;

    /* Mechanics: J dw/dt = T_e - T_L - B w, exact for the period's torque. */
    mech_advance(c, T_e_mean, T_L, T_brake, p->w_M, T, &w1, &th_int, &T_L);

    p->i_re = creal(i1);
    p->i_im = cimag(i1);
    p->theta_r = wrap_pi(p->theta_r + c->n_p * th_int);
    p->w_M = w1;
    p->T_e_mean = T_e_mean;
    p->T_L_mean = T_L;
    p->u_re = creal(u_mean);
    p->u_im = cimag(u_mean);
}

void smd_plant_sample(smd_plant *p, double i_abc_meas[3])
{
    const smd_plant_config *c = &p->c;
    double i_abc[3];
    smd_plant_phase_currents(p, i_abc);
    smd_adc_sample3(i_abc, c->adc_gain, c->adc_offset, c->adc_noise, c->adc_bits,
                    c->adc_full_scale, &p->rng, i_abc_meas);
}

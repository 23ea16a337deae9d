/* SPMSM without filter: yang2018 eq. (1) solved in closed form over one
 * carrier period (see smd_plant.h and docs/architecture.md). */
#include "smdsim/smd_plant.h"
#include "smd_mech.h"
#include "smdsim/smd_pwm.h"

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

void smd_spmsm_step(smd_plant *p, const double d_abc[3], double T_ext, double T_brake)
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

    /* Mean torque over the period, 1.5 n_p psi Im{i e^{-j theta}}. */
    T_e_mean = Kt * cimag(i_int) / T;

    p->i_re = creal(i1);
    p->i_im = cimag(i1);
    smd_plant_end_period(p, T_e_mean, T_L, T_brake, u_mean);
}

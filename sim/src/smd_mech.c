/*
 * The plant's mechanics (smd_mech.h): J dw/dt = T_e - T_L - B w solved
 * exactly over a period with the period's mean torque, the brake's taper
 * band included, and the end of a solver's period. Called by both solvers
 * (smd_spmsm.c, smd_lcl.c); it uses the plant's state, never its functions.
 */
#include "smd_mech.h"

#include <complex.h>
#include <math.h>

/* (1 - e^{-x}) / x, accurate for small |x| */
static inline double phi1r(double x)
{
    if (fabs(x) < 1e-4) return 1.0 - x / 2.0 + x * x / 6.0 - x * x * x / 24.0;
    return (1.0 - exp(-x)) / x;
}

/* phi2(x) = (x - 1 + e^{-x}) / x^2 (real) */
static inline double phi2r(double x)
{
    if (fabs(x) < 1e-3) {
        return 0.5 - x / 6.0 + x * x / 24.0 - x * x * x / 120.0 + x * x * x * x / 720.0;
    }
    return (x + expm1(-x)) / (x * x);
}

/* Exact solution of J dw/dt = F - B w over tau from w0: end speed and the
 * integral of w. */
static inline void lin_mech(double F, double Bv, double J, double w0, double tau, double *w1,
                            double *th)
{
    double b = Bv / J;
    double acc = F / J - b * w0;
    *w1 = w0 + acc * tau * phi1r(b * tau);
    *th = w0 * tau + acc * tau * tau * phi2r(b * tau);
}

/* Advance the mechanics over T with electromagnetic torque T_e and load T_L
 * (which includes the brake term evaluated at w0). Outside the brake's taper
 * band |w| < eps the brake torque is constant; inside it is T_brake w / eps, a
 * viscous term, solved exactly. A period that enters the band is split at the
 * crossing instant, so the speed settles at rest without ringing (an explicit
 * hold of the taper rings when T T_brake / (J eps) > 2). Returns the end
 * speed, the integral of w, and the mean load torque. */
void smd_mech_advance(const smd_plant_config *c, double T_e, double T_L, double T_brake,
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

void smd_mech_end_period(smd_plant *p, double T_e_mean, double T_L, double T_brake,
                         double complex u_mean)
{
    double w1, th_int;
    /* J dw/dt = T_e - T_L - B w, exact for the period's mean torque */
    smd_mech_advance(&p->c, T_e_mean, T_L, T_brake, p->w_M, p->c.T_sw, &w1, &th_int, &T_L);
    p->theta_r = smd_wrap_pi_d(p->theta_r + p->c.n_p * th_int);
    p->w_M = w1;
    p->T_e_mean = T_e_mean;
    p->T_L_mean = T_L;
    p->u_re = creal(u_mean);
    p->u_im = cimag(u_mean);
}

/*
 * The plant's mechanics and load, shared by both solvers (smd_spmsm.c,
 * smd_lcl.c): static functions in a private header, so that each solver's
 * period step inlines them.
 *
 * Load: external torque (signed), a brake opposing rotation with a linear
 * taper inside +-w_brake_eps, a fan k_fan w |w|. Mechanics: J dw/dt = T_e -
 * T_L - B w solved exactly over the period with the period's mean torque; a
 * period that enters the brake's taper band is split at the crossing.
 */
#ifndef SMD_MECH_H
#define SMD_MECH_H

#include <complex.h>
#include <math.h>

#include "smdsim/smd_plant.h"

/* x wrapped to [-pi, pi) */
static inline double smd_wrap_pi_d(double x)
{
    return x - 6.283185307179586476925 * floor((x + 3.141592653589793238463) / 6.283185307179586476925);
}


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

static inline double smd_load_torque(const smd_plant_config *c, double w_M, double T_ext, double T_brake)
{
    double s = w_M / c->w_brake_eps;
    if (s > 1.0) s = 1.0;
    if (s < -1.0) s = -1.0;
    return T_ext + T_brake * s + c->k_fan * w_M * fabs(w_M);
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

/* Exact mechanics over T with mean electromagnetic torque T_e and load T_L
 * (smd_load_torque at w0): end speed, integral of w, mean load torque
 * (smd_plant.c). */
void smd_mech_advance(const smd_plant_config *c, double T_e, double T_L, double T_brake,
                      double w0, double T, double *w1, double *th, double *T_L_mean);
/* End of a solver's period: the mechanics over it, the angle, the period
 * means; the solver has written the electrical state (smd_plant.c). */
void smd_plant_end_period(smd_plant *p, double T_e_mean, double T_L, double T_brake,
                          double complex u_mean);

#endif

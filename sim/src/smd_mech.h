/*
 * The plant's mechanics and load, shared by both solvers (smd_spmsm.c,
 * smd_lcl.c): the load torque a solver's period step needs (static inline,
 * so that it inlines), and the mechanics over the period in smd_mech.c,
 * which the solvers call at the end of their period (smd_plant.c dispatches
 * to the solvers; nothing here calls back into it).
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


static inline double smd_load_torque(const smd_plant_config *c, double w_M, double T_ext, double T_brake)
{
    double s = w_M / c->w_brake_eps;
    if (s > 1.0) s = 1.0;
    if (s < -1.0) s = -1.0;
    return T_ext + T_brake * s + c->k_fan * w_M * fabs(w_M);
}

/* Exact mechanics over T with mean electromagnetic torque T_e and load T_L
 * (smd_load_torque at w0): end speed, integral of w, mean load torque
 * (smd_mech.c). */
void smd_mech_advance(const smd_plant_config *c, double T_e, double T_L, double T_brake,
                      double w0, double T, double *w1, double *th, double *T_L_mean);
/* End of a solver's period: the mechanics over it, the angle, the period
 * means; the solver has written the electrical state (smd_mech.c). */
void smd_mech_end_period(smd_plant *p, double T_e_mean, double T_L, double T_brake,
                         double complex u_mean);

#endif

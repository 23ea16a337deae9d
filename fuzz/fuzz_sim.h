/*
 * The plant's configuration decoded from the fuzz input (fuzz_plant.c,
 * fuzz_engine.c), every field in the order of smd_plant_config (fuzz.h's
 * reals, double precision), and a piecewise-linear profile.
 */
#ifndef SMD_FUZZ_SIM_H
#define SMD_FUZZ_SIM_H

#include "fuzz.h"

#include "smdsim/smd_engine.h"
#include "smdsim/smd_plant.h"

static inline void fz_plant_config(fz *f, smd_plant_config *c)
{
    int k;
    memset(c, 0, sizeof *c);
    c->R_s = fz_real(f, 0.0, 10.0);
    c->L_s = fz_real(f, 0.0, 0.1);
    c->psi_r = fz_real(f, 0.0, 1.0);
    c->n_p = fz_real(f, 1.0, 10.0);
    c->J = fz_real(f, 0.0, 1.0);
    c->B = fz_real(f, 0.0, 0.1);
    c->lcl = fz_int(f, 0, 1);
    c->L1 = fz_real(f, 0.0, 1e-2);
    c->L2o = fz_real(f, 0.0, 1e-2);
    c->C1 = fz_real(f, 0.0, 1e-3);
    c->u_dc = fz_real(f, 0.0, 1000.0);
    c->T_sw = fz_real(f, 0.0, 1e-3);
    c->pwm_mode = fz_int(f, 0, 1);
    c->dead_time_model = fz_int(f, 0, 1);
    c->t_dead = fz_real(f, 0.0, 1e-5);
    for (k = 0; k < 3; k++) {
        c->adc_gain[k] = fz_real(f, 0.5, 2.0);
        c->adc_offset[k] = fz_real(f, -10.0, 10.0);
        c->adc_gain_i1[k] = fz_real(f, 0.5, 2.0);
        c->adc_offset_i1[k] = fz_real(f, -10.0, 10.0);
    }
    c->adc_noise = fz_real(f, 0.0, 1.0);
    c->adc_bits = fz_int(f, 0, 24);
    c->adc_n_oversample = fz_int(f, 0, 64);
    c->adc_sensors = fz_int(f, 0, 3);
    c->adc_full_scale = fz_real(f, 0.0, 1000.0);
    c->seed = fz_u32(f);
    c->w_brake_eps = fz_real(f, 0.0, 10.0);
    c->k_fan = fz_real(f, 0.0, 1e-3);
    c->w_M0 = fz_real(f, -1e4, 1e4);
    c->theta_r0 = fz_real(f, -4.0, 4.0);
    c->i_d0 = fz_real(f, -100.0, 100.0);
    c->i_q0 = fz_real(f, -100.0, 100.0);
    c->uc_d0 = fz_real(f, -500.0, 500.0);
    c->uc_q0 = fz_real(f, -500.0, 500.0);
    c->i1_d0 = fz_real(f, -100.0, 100.0);
    c->i1_q0 = fz_real(f, -100.0, 100.0);
}

/* n points (n from the input, SMD_PWL_MAX + 1 and others to be refused),
 * times increasing by steps in [0, dt_max] (an input can break the order). */
static inline void fz_pwl(fz *f, smd_pwl *p, double dt_max, double y_lim)
{
    int k, m;
    double t = 0.0;
    memset(p, 0, sizeof *p);
    p->n = fz_int(f, 0, 4);
    m = p->n < 0 ? 0 : (p->n > SMD_PWL_MAX ? SMD_PWL_MAX : p->n);
    for (k = 0; k < m; k++) {
        t += fz_real(f, 0.0, dt_max);
        p->t[k] = t;
        p->y[k] = fz_real(f, -y_lim, y_lim);
    }
}

#endif

#include "smdsim/smd_plant.h"
#include "smdsim/smd_pwm.h"
#include "smd_mech.h"

#include <math.h>

#define TWO_PI 6.283185307179586476925


static int bad(double x, double lo, double hi) { return !(isfinite(x) && x >= lo && x <= hi); }

#include "smd_plant_fields.h" /* FIELDS[]: the names of smd_plant_field_code */

const char *smd_plant_field(int code)
{
    if (code < 0 || code >= (int)(sizeof(FIELDS) / sizeof(FIELDS[0]))) return "unknown";
    return FIELDS[code];
}

unsigned long smd_sizeof_plant(void) { return sizeof(smd_plant); }
unsigned long smd_sizeof_plant_config(void) { return sizeof(smd_plant_config); }

static int check(const smd_plant_config *c)
{
    int k;
    if (bad(c->R_s, 1e-6, 1e3)) return SMD_PF_R_S;
    if (bad(c->L_s, 1e-8, 10.0)) return SMD_PF_L_S;
    if (bad(c->psi_r, 0.0, 100.0)) return SMD_PF_PSI_R;
    if (bad(c->n_p, 1.0, 100.0)) return SMD_PF_N_P;
    if (bad(c->J, 1e-9, 1e4)) return SMD_PF_J;
    if (bad(c->B, 0.0, 1e3)) return SMD_PF_B;
    if (c->lcl != 0 && c->lcl != 1) return SMD_PF_LCL;
    if (c->lcl) {
        if (bad(c->L1, 1e-8, 10.0)) return SMD_PF_L1;
        if (bad(c->L2o, 0.0, 10.0)) return SMD_PF_L2O;
        if (bad(c->C1, 1e-10, 1.0)) return SMD_PF_C1;
    }
    if (bad(c->u_dc, 1e-9, 1e5)) return SMD_PF_U_DC;
    if (bad(c->T_sw, 1e-8, 1.0)) return SMD_PF_T_SW;
    if (c->pwm_mode != SMD_PWM_AVERAGED && c->pwm_mode != SMD_PWM_CARRIER) return SMD_PF_PWM_MODE;
    if (bad(c->t_dead, 0.0, 0.25 * c->T_sw)) return SMD_PF_T_DEAD;
    for (k = 0; k < 3; k++) {
        if (bad(c->adc_gain[k], 0.5, 2.0)) return SMD_PF_ADC_GAIN;
        if (bad(c->adc_offset[k], -1e3, 1e3)) return SMD_PF_ADC_OFFSET;
        if (c->lcl && bad(c->adc_gain_i1[k], 0.5, 2.0)) return SMD_PF_ADC_GAIN_I1;
        if (c->lcl && bad(c->adc_offset_i1[k], -1e3, 1e3)) return SMD_PF_ADC_OFFSET_I1;
    }
    if (bad(c->adc_noise, 0.0, 1e3)) return SMD_PF_ADC_NOISE;
    if (c->adc_bits < 0 || c->adc_bits > 24) return SMD_PF_ADC_BITS;
    if (bad(c->adc_full_scale, 1e-6, 1e6)) return SMD_PF_ADC_FULL_SCALE;
    if (bad(c->w_brake_eps, 1e-9, 1e3)) return SMD_PF_W_BRAKE_EPS;
    if (bad(c->k_fan, 0.0, 1e3)) return SMD_PF_K_FAN;
    if (bad(c->w_M0, -1e5, 1e5)) return SMD_PF_W_M0;
    if (bad(c->theta_r0, -1e3, 1e3)) return SMD_PF_THETA_R0;
    if (bad(c->i_d0, -1e5, 1e5) || bad(c->i_q0, -1e5, 1e5)) return SMD_PF_I_DQ0;
    if (c->lcl && (bad(c->uc_d0, -1e5, 1e5) || bad(c->uc_q0, -1e5, 1e5))) return SMD_PF_UC_DQ0;
    if (c->lcl && (bad(c->i1_d0, -1e5, 1e5) || bad(c->i1_q0, -1e5, 1e5))) return SMD_PF_I1_DQ0;
    /* (SMD_PF_MODES: smd_lcl_setup) the options added later, checked last */
    if (c->dead_time_model != SMD_DT_SIGN && c->dead_time_model != SMD_DT_CLAMP) {
        return SMD_PF_DEAD_TIME_MODEL;
    }
    if (c->adc_n_oversample < 0 || c->adc_n_oversample > 64) return SMD_PF_ADC_N_OVERSAMPLE;
    if (c->adc_sensors != 0 && c->adc_sensors != 2 && c->adc_sensors != 3)
        return SMD_PF_ADC_SENSORS;
    return SMD_PF_OK;
}

int smd_plant_init(smd_plant *p, const smd_plant_config *c)
{
    int rc = check(c);
    double cs, sn;
    if (rc != 0) return rc;
    p->c = *c;
    p->L2 = c->L_s + (c->lcl ? c->L2o : 0.0);
    p->a = c->R_s / p->L2;
    p->theta_r = smd_wrap_pi_d(c->theta_r0);
    cs = cos(p->theta_r);
    sn = sin(p->theta_r);
    /* x_ab = x_dq e^{j theta} */
    p->i_re = c->i_d0 * cs - c->i_q0 * sn;
    p->i_im = c->i_d0 * sn + c->i_q0 * cs;
    if (c->lcl) {
        p->uc_re = c->uc_d0 * cs - c->uc_q0 * sn;
        p->uc_im = c->uc_d0 * sn + c->uc_q0 * cs;
        p->i1_re = c->i1_d0 * cs - c->i1_q0 * sn;
        p->i1_im = c->i1_d0 * sn + c->i1_q0 * cs;
        rc = smd_lcl_setup(p);
        if (rc != 0) return rc;
    } else {
        p->uc_re = p->uc_im = 0.0;
        p->i1_re = p->i_re;
        p->i1_im = p->i_im;
    }
    p->off = 0;
    p->leg_open[0] = p->leg_open[1] = p->leg_open[2] = 0;
    p->solver = c->lcl ? 2 : (c->dead_time_model == SMD_DT_CLAMP && c->t_dead > 0.0) ? 1 : 0;
    p->w_M = c->w_M0;
    p->T_e_mean = 0.0;
    p->T_L_mean = 0.0;
    p->u_re = 0.0;
    p->u_im = 0.0;
    smd_rng_seed(&p->rng, c->seed);
    return 0;
}

int smd_plant_set_resistance(smd_plant *p, double R_s)
{
    const double R_old = p->c.R_s;
    if (!(R_s >= 1e-6 && R_s <= 1e3)) return SMD_PF_R_S;
    p->c.R_s = R_s;
    p->a = R_s / p->L2;
    if (p->c.lcl) {
        const smd_lcl_modes m = p->m;
        const int rc = smd_lcl_setup(p);
        if (rc != 0) {
            p->c.R_s = R_old;
            p->a = R_old / p->L2;
            p->m = m;
            return rc;
        }
    }
    return 0;
}

void smd_plant_step(smd_plant *p, const double d_abc[3], double T_ext, double T_brake)
{
    if (p->off == 2) {
        /* every lower switch on, forced: the legs low the whole period with no
         * edge, so no dead time: the sign model's exact step with duties 0 and
         * no dead time is that (behind a filter, its step likewise) */
        static const double low[3] = {0.0, 0.0, 0.0};
        const double t_dead = p->c.t_dead;
        const int solver = p->solver;
        p->c.t_dead = 0.0;
        p->off = 0;
        p->solver = solver == 2 ? 2 : 0;
        smd_plant_step(p, low, T_ext, T_brake);
        p->c.t_dead = t_dead;
        p->solver = solver;
        p->off = 2;
        return;
    }
    if (p->solver == 2) {
        smd_lcl_step(p, d_abc, T_ext, T_brake);
    } else {
        if (p->solver == 0 && !p->off) {
            smd_spmsm_step(p, d_abc, T_ext, T_brake);
        } else {
            smd_spmsm_step_clamp(p, d_abc, T_ext, T_brake);
        }
        p->i1_re = p->i_re;
        p->i1_im = p->i_im;
    }
}

void smd_plant_phase_currents(const smd_plant *p, double i_abc[3], double i1_abc[3])
{
    /* amplitude-invariant: i_x = Re(i e^{-j 2 pi x / 3}) */
    smd_ab_to_abc_d(p->i_re, p->i_im, i_abc);
    if (i1_abc != 0) smd_ab_to_abc_d(p->i1_re, p->i1_im, i1_abc);
}

void smd_plant_sample(smd_plant *p, double i_abc[3], double i1_abc[3])
{
    const smd_plant_config *c = &p->c;
    double t[3], t1[3];
    if (c->lcl) {
        double dummy[3];
        smd_plant_phase_currents(p, t, t1);
        if (c->adc_n_oversample > 1) {
            smd_adc_sample3_avg(t1, c->adc_gain_i1, c->adc_offset_i1, c->adc_noise, c->adc_bits,
                                c->adc_full_scale, c->adc_n_oversample, &p->rng,
                                i1_abc != 0 ? i1_abc : dummy);
        } else {
            smd_adc_sample3(t1, c->adc_gain_i1, c->adc_offset_i1, c->adc_noise, c->adc_bits,
                            c->adc_full_scale, &p->rng, i1_abc != 0 ? i1_abc : dummy);
        }
    } else {
        smd_plant_phase_currents(p, t, 0);
        if (i1_abc != 0) i1_abc[0] = i1_abc[1] = i1_abc[2] = 0.0;
    }
    if (c->adc_n_oversample > 1) {
        smd_adc_sample3_avg(t, c->adc_gain, c->adc_offset, c->adc_noise, c->adc_bits,
                            c->adc_full_scale, c->adc_n_oversample, &p->rng, i_abc);
    } else {
        smd_adc_sample3(t, c->adc_gain, c->adc_offset, c->adc_noise, c->adc_bits,
                        c->adc_full_scale, &p->rng, i_abc);
    }
}

void smd_plant_eigenvalues(const smd_plant *p, double re[3], double im[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        re[k] = p->c.lcl ? creal(p->m.lam[k]) : 0.0;
        im[k] = p->c.lcl ? cimag(p->m.lam[k]) : 0.0;
    }
}

void smd_plant_run_open(smd_plant *p, long n, double m, double delta, double T_ext)
{
    long k;
    for (k = 0; k < n; k++) {
        double d[3], th = p->theta_r + delta;
        int x;
        for (x = 0; x < 3; x++) {
            d[x] = 0.5 + 0.5 * m * cos(th - TWO_PI / 3.0 * x);
        }
        smd_plant_step(p, d, T_ext, 0.0);
    }
}

#include "smdsim/smd_lcl_engine.h"

#include <math.h>

static const char *CHANNELS[SMD_LL_N] = {
    "t", "w_M", "theta_r", "theta_hat", "w_hat", "theta_err_est", "i2_d", "i2_q", "i2_g",
    "i2_dl", "i_ref_g", "i_ref_dl", "e_hat_g", "e_hat_dl", "s_g", "s_dl", "d_hat_g", "d_hat_dl",
    "u_alpha", "u_beta", "uc_alpha", "uc_beta", "i1_alpha", "i1_beta", "i2_alpha", "i2_beta",
    "T_e", "T_L", "w_M_ref", "phase", "lin_e_alpha", "lin_e_beta", "v_g", "v_dl", "status"};

const char *smd_lcl_log_channel_name(int ch)
{
    return (ch >= 0 && ch < SMD_LL_N) ? CHANNELS[ch] : "";
}

unsigned long smd_sizeof_lcl_engine(void) { return sizeof(smd_lcl_engine); }
unsigned long smd_sizeof_lcl_drive_config(void) { return sizeof(smd_lcl_drive_config); }
unsigned long smd_sizeof_lcl_obs_config(void) { return sizeof(smd_lcl_obs_config); }
unsigned long smd_sizeof_lcl_model(void) { return sizeof(smd_lcl_model); }
unsigned long smd_sizeof_linobs_model(void) { return sizeof(smd_linobs_model); }

int smd_lcl_engine_init(smd_lcl_engine *e, const smd_lcl_config *plant,
                        const smd_lcl_drive_config *ctrl, const smd_lcl_obs_config *obs,
                        const smd_profiles *prof, const smd_lcl_start *start)
{
    int rc = smd_lcl_init(&e->plant, plant);
    smd_status st;
    if (rc != 0) return 1000 + rc;
    st = smd_lcl_smo_init(&e->smo_p, (smd_real)plant->T_sw, obs->law, obs->table, obs->n,
                          obs->w_min, obs->dw, obs->Q1, obs->Q2, obs->bw_rel2, obs->bw_rel3,
                          obs->w_bp_min);
    if (st != SMD_OK) return 2000 + (int)st;
    e->lin_on = obs->lin_table != 0;
    if (e->lin_on) {
        st = smd_linobs_init(&e->lin_p, obs->lin_table, obs->lin_n, obs->lin_w_min, obs->lin_dw);
        if (st != SMD_OK) return 4000 + (int)st;
    }
    st = smd_lcl_drive_init(&e->ctrl_p, ctrl, &e->smo_p, e->lin_on ? &e->lin_p : 0);
    if (st != SMD_OK) return 3000 + (int)st;
    if (prof->w_M_ref.n < 0 || prof->w_M_ref.n > SMD_PWL_MAX || prof->T_ext.n < 0 ||
        prof->T_ext.n > SMD_PWL_MAX || prof->i_d_ref.n < 0 || prof->i_d_ref.n > SMD_PWL_MAX ||
        prof->i_q_ref.n < 0 || prof->i_q_ref.n > SMD_PWL_MAX) {
        return 5000;
    }
    e->prof = *prof;
    smd_lcl_drive_reset(&e->ctrl_p, &e->ctrl_s, (smd_real)start->theta0, (smd_real)start->w0,
                        start->phase, (smd_real)start->i_delta0);
    e->d_abc[0] = e->d_abc[1] = e->d_abc[2] = 0.5;
    e->k = 0;
    e->T = plant->T_sw;
    e->last_status = 0;
    return 0;
}

long smd_lcl_engine_run(smd_lcl_engine *e, long n, double *log, long stride)
{
    long j, rows = 0;
    const double n_p = e->plant.c.n_p;
    if (stride < 1) stride = 1;
    for (j = 0; j < n; j++) {
        const double t = (double)e->k * e->T;
        double i1m[3], i2m[3], d_now[3];
        smd_lcl_drive_in in;
        smd_lcl_drive_out out;
        smd_status st;
        double w_ref = smd_pwl_eval(&e->prof.w_M_ref, t);
        double T_ext = smd_pwl_eval(&e->prof.T_ext, t);
        smd_cplx u_applied;
        int x;

        /* 1. measurements at t_k */
        smd_lcl_sample(&e->plant, i1m, i2m);
        in.i1_a = (smd_real)i1m[0];
        in.i1_b = (smd_real)i1m[1];
        in.i2_a = (smd_real)i2m[0];
        in.i2_b = (smd_real)i2m[1];
        in.theta_enc = (smd_real)e->plant.theta_r;
        in.w_enc = (smd_real)(n_p * e->plant.w_M);
        in.u_dc = (smd_real)e->plant.c.u_dc;
        in.w_ref = (smd_real)(n_p * w_ref);
        in.i_ref.re = (smd_real)smd_pwl_eval(&e->prof.i_d_ref, t);
        in.i_ref.im = (smd_real)smd_pwl_eval(&e->prof.i_q_ref, t);
        u_applied = e->ctrl_s.u_ab_next; /* what is applied during [k, k+1) */
        /* the frame the controller uses at k */
        double th_k = e->ctrl_p.mode == SMD_LCL_SENSORED ? (double)in.theta_enc
                                                         : (double)e->ctrl_s.theta;
        double w_k = e->ctrl_p.mode == SMD_LCL_SENSORED ? (double)in.w_enc : (double)e->ctrl_s.w;

        /* 2. controller */
        st = smd_lcl_drive_step(&e->ctrl_p, &e->ctrl_s, &in, &out);
        if (st != SMD_OK) e->last_status = (int)st;
        (void)u_applied;

        /* 3. plant over [t_k, t_k+1) with the duties computed at k-1 */
        for (x = 0; x < 3; x++) {
            d_now[x] = e->d_abc[x];
            e->d_abc[x] = (double)out.d_abc[x];
        }
        if (log != 0 && (j % stride) == 0) {
            double *r = log + rows * SMD_LL_N;
            const smd_lcl_drive_state *c = &e->ctrl_s;
            double th = e->plant.theta_r;
            double cs = cos(th), sn = sin(th);
            r[SMD_LL_T] = t;
            r[SMD_LL_W_M] = e->plant.w_M;
            r[SMD_LL_THETA_R] = th;
            r[SMD_LL_THETA_HAT] = th_k;
            r[SMD_LL_W_HAT] = w_k;
            r[SMD_LL_THETA_ERR_EST] = (double)c->theta_err;
            r[SMD_LL_I2_D] = cs * e->plant.i2_re + sn * e->plant.i2_im;
            r[SMD_LL_I2_Q] = -sn * e->plant.i2_re + cs * e->plant.i2_im;
            r[SMD_LL_I2_G] = (double)c->i2_gd.re;
            r[SMD_LL_I2_DL] = (double)c->i2_gd.im;
            r[SMD_LL_IREF_G] = (double)c->i_ref.re;
            r[SMD_LL_IREF_DL] = (double)c->i_ref.im;
            r[SMD_LL_E_G] = (double)c->smo.e_hat[0];
            r[SMD_LL_E_DL] = (double)c->smo.e_hat[1];
            r[SMD_LL_S_G] = (double)c->smo.s[0];
            r[SMD_LL_S_DL] = (double)c->smo.s[1];
            r[SMD_LL_DHAT_G] = (double)c->smo.d_hat[0];
            r[SMD_LL_DHAT_DL] = (double)c->smo.d_hat[1];
            r[SMD_LL_UC_ALPHA] = e->plant.uc_re;
            r[SMD_LL_UC_BETA] = e->plant.uc_im;
            r[SMD_LL_I1_ALPHA] = e->plant.i1_re;
            r[SMD_LL_I1_BETA] = e->plant.i1_im;
            r[SMD_LL_I2_ALPHA] = e->plant.i2_re;
            r[SMD_LL_I2_BETA] = e->plant.i2_im;
            r[SMD_LL_W_M_REF] = w_ref;
            r[SMD_LL_PHASE] = (double)c->phase;
            r[SMD_LL_LIN_E_ALPHA] = e->lin_on ? (double)c->lin.x2[2] : 0.0;
            r[SMD_LL_LIN_E_BETA] = e->lin_on ? (double)c->lin.x2[3] : 0.0;
            r[SMD_LL_V_G] = (double)c->smo.v_prev[0];
            r[SMD_LL_V_DL] = (double)c->smo.v_prev[1];
            r[SMD_LL_STATUS] = (double)st;
        }
        smd_lcl_step(&e->plant, d_now, T_ext);
        if (log != 0 && (j % stride) == 0) {
            double *r = log + rows * SMD_LL_N;
            r[SMD_LL_T_E] = e->plant.T_e_mean;
            r[SMD_LL_T_L] = e->plant.T_L_mean;
            r[SMD_LL_U_ALPHA] = e->plant.u_re;
            r[SMD_LL_U_BETA] = e->plant.u_im;
            rows++;
        }
        e->k++;
    }
    return rows;
}

/* Closed-loop impulse response of the firmware PLL (eq. (48)) with unity
 * feedback e = theta - theta_hat: theta = amp at k = 0 and 0 after; writes
 * theta_hat(k) / amp for k = 1..n into out (analysis of Fig. 7). */
int smd_pll_impulse(double T, double k_theta, double k_omega, double k_a, double amp, long n,
                    double *out)
{
    smd_pll_params p;
    smd_pll_state s;
    long k;
    smd_status st = smd_pll_init(&p, (smd_real)T, (smd_real)k_theta, (smd_real)k_omega,
                                 (smd_real)k_a);
    if (st != SMD_OK) return (int)st;
    smd_pll_reset(&s, SMD_R(0.0), SMD_R(0.0));
    for (k = 0; k < n; k++) {
        double theta = (k == 0) ? amp : 0.0;
        smd_pll_step(&p, &s, (smd_real)(theta - (double)s.theta));
        out[k] = (double)s.theta / amp;
    }
    return 0;
}

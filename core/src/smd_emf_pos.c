#include "smodrive/smd_emf_pos.h"

smd_status smd_emf_pos_init(smd_emf_pos_params *p, smd_real T_sp, smd_real w_lpf, smd_real w_hys,
                            smd_real w_max)
{
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_pos_range(T_sp, SMD_R(1.0))) {
        return SMD_ERR_TS;
    }
    if (!(smd_in_range(w_lpf, SMD_R(0.0), SMD_PI / T_sp) && w_lpf > SMD_R(0.0) &&
          w_lpf < SMD_PI / T_sp)) {
        return SMD_ERR_WLPF;
    }
    if (!smd_in_range(w_hys, SMD_R(0.0), SMD_R(1e5))) {
        return SMD_ERR_WHYS;
    }
    if (!(smd_in_range(w_max, SMD_R(0.0), SMD_PI / T_sp) && w_max > w_hys)) {
        return SMD_ERR_WMAX;
    }
    p->w_max = w_max;
    p->T_sp = T_sp;
    p->inv_T = SMD_R(1.0) / T_sp;
    p->w_lpf = w_lpf;
    p->a_lpf = -SMD_EXPM1(-w_lpf * T_sp);
    p->a_dir = -SMD_EXPM1(SMD_R(-0.125) * w_lpf * T_sp);
    p->w_hys = w_hys;
    return SMD_OK;
}

void smd_emf_pos_reset(smd_emf_pos_state *s, smd_real w_r0)
{
    s->phi_prev = SMD_R(0.0);
    s->w_r_raw = w_r0;
    s->w_r_hat = w_r0;
    s->w_r_dir = w_r0;
    s->theta_r_hat = SMD_R(0.0);
    s->dir = w_r0 < SMD_R(0.0) ? -1 : 1;
    s->primed = 0;
}

SMD_FIXED_INLINE void smd_emf_pos_step(const smd_emf_pos_params *p, smd_emf_pos_state *s, smd_cplx u_d_hat)
{
    smd_real phi = SMD_ATAN2(u_d_hat.im, u_d_hat.re);
    smd_real d_sign;
    if (!isfinite(phi)) {
        return; /* keep the previous estimates */
    }
    if (s->primed) {
        /* eq. (45) on the EMF angle (same increments as theta_r) */
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
        s->w_r_raw = smd_wrap_pi_near(phi - s->phi_prev) * p->inv_T; /* (no division) */
#else
        s->w_r_raw = smd_wrap_pi(phi - s->phi_prev) / p->T_sp;
#endif
        s->w_r_hat += p->a_lpf * (s->w_r_raw - s->w_r_hat);
        /* Limit: a speed estimate beyond the drive's range is noise, and it
         * would feed the rotation of the observer's filter (36). */
        if (s->w_r_hat > p->w_max) {
            s->w_r_hat = p->w_max;
        } else if (s->w_r_hat < -p->w_max) {
            s->w_r_hat = -p->w_max;
        }
    }
    s->phi_prev = phi;
    s->primed = 1;
    s->w_r_dir += p->a_dir * (s->w_r_hat - s->w_r_dir);
    if (s->w_r_dir > p->w_hys) {
        s->dir = 1;
    } else if (s->w_r_dir < -p->w_hys) {
        s->dir = -1;
    }
    d_sign = s->dir > 0 ? SMD_R(1.0) : SMD_R(-1.0);
    /* eq. (44), sign-corrected: theta = atan2(s u_alpha, -s u_beta) */
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    /* (the fast build: the same angle is phi + s pi/2, without a second
     * atan2; the wrap below brings it into (-pi, pi]) */
    s->theta_r_hat = phi + d_sign * SMD_R(1.5707963);
#else
    s->theta_r_hat = SMD_ATAN2(d_sign * u_d_hat.re, -d_sign * u_d_hat.im);
#endif
    /* The Euler model (35) identifies the disturbance averaged over
     * [t_k, t_k+1), i.e. at t_k + T_sp/2: step back half a sample so that the
     * angle belongs to the sampling instant (docs/errata.md, yang2018 E4). */
    s->theta_r_hat = smd_wrap_pi_near(s->theta_r_hat - SMD_R(0.5) * s->w_r_hat * p->T_sp);
}

#include "smodrive/smd_lcl_drive.h"

#include "smodrive/smd_transforms.h"

smd_status smd_lcl_drive_init(smd_lcl_drive_params *p, const smd_lcl_drive_config *c,
                              const smd_lcl_smo_params *smo, const smd_linobs_params *lin)
{
    smd_status st;
    if (p == 0 || c == 0 || smo == 0) {
        return SMD_ERR_NULL;
    }
    if (c->mode != SMD_LCL_SENSORLESS && c->mode != SMD_LCL_SENSORED) {
        return SMD_ERR_MODE;
    }
    if (c->speed_loop != 0 && c->speed_loop != 1) {
        return SMD_ERR_MODE;
    }
    if (c->emf_ff != 0 && c->emf_ff != 1) {
        return SMD_ERR_MODE;
    }
    if (c->pos_source != 0 && !(c->pos_source == 1 && lin != 0)) {
        return SMD_ERR_MODE;
    }
    if (!smd_in_pos_range(c->T, SMD_R(1.0))) {
        return SMD_ERR_TS;
    }
    if (!smd_in_range(c->k_p_i, SMD_R(0.0), SMD_R(1e4)) ||
        !smd_in_range(c->k_i_i, SMD_R(0.0), SMD_R(1e9)) ||
        !smd_in_range(c->L_dec, SMD_R(0.0), SMD_R(10.0)) ||
        !smd_in_range(c->R_v, SMD_R(0.0), SMD_R(1e4))) {
        return SMD_ERR_KP;
    }
    if (!smd_in_range(c->i_start, SMD_R(0.0), SMD_R(1e5)) ||
        !smd_in_range(c->a_start, SMD_R(0.0), SMD_R(1e9)) ||
        !smd_in_range(c->w_handover, SMD_R(0.0), SMD_PI / c->T)) {
        return SMD_ERR_LIMIT;
    }
    st = smd_pi_init(&p->speed_pi, c->k_p_w, c->k_i_w, c->T, c->i_max);
    if (st != SMD_OK) {
        return st;
    }
    st = smd_pll_init(&p->pll, c->T, c->k_theta, c->k_omega, c->k_a);
    if (st != SMD_OK) {
        return st;
    }
    st = smd_svm_init(&p->svm, c->svm_limit, SMD_R(0.0));
    if (st != SMD_OK) {
        return st;
    }
    p->mode = c->mode;
    p->T = c->T;
    p->k_p_i = c->k_p_i;
    p->k_i_i = c->k_i_i;
    p->L_dec = c->L_dec;
    p->R_v = c->R_v;
    p->emf_ff = c->emf_ff;
    p->speed_loop = c->speed_loop;
    p->i_max = c->i_max;
    p->i_start = c->i_start;
    p->a_start = c->a_start;
    p->w_handover = c->w_handover;
    p->smo = *smo;
    p->use_lin = lin != 0;
    p->pos_source = c->pos_source;
    if (lin != 0) {
        p->lin = *lin;
    }
    return SMD_OK;
}

void smd_lcl_drive_reset(const smd_lcl_drive_params *p, smd_lcl_drive_state *s, smd_real theta0,
                         smd_real w0, int phase, smd_real i_delta0)
{
    smd_cplx z = smd_c(SMD_R(0.0), SMD_R(0.0));
    (void)p;
    s->phase = phase == SMD_LCL_PHASE_OPENLOOP ? SMD_LCL_PHASE_OPENLOOP : SMD_LCL_PHASE_CLOSED;
    s->theta = smd_wrap_pi(theta0);
    s->w = w0;
    s->theta_f = s->theta;
    s->w_f = w0;
    s->theta_err = SMD_R(0.0);
    s->i_ref = smd_c(SMD_R(0.0), i_delta0);
    s->i2_gd = z;
    s->x_i = z;
    s->u_ab = z;
    s->u_ab_next = z;
    smd_pi_reset(&s->speed_pi, i_delta0);
    smd_pll_reset(&s->pll, theta0, w0);
    smd_lcl_smo_reset(&s->smo, theta0);
    smd_linobs_reset(&s->lin);
    s->status = 0;
}

static smd_real clampr(smd_real x, smd_real lim)
{
    return x > lim ? lim : (x < -lim ? -lim : x);
}

smd_status smd_lcl_drive_step(const smd_lcl_drive_params *p, smd_lcl_drive_state *s,
                              const smd_lcl_drive_in *in, smd_lcl_drive_out *out)
{
    const smd_real T = p->T;
    smd_cplx i1_ab = smd_ab2_to_ab(in->i1_a, in->i1_b);
    smd_cplx i2_ab = smd_ab2_to_ab(in->i2_a, in->i2_b);
    smd_cplx i1, i2, e_hat, u, u_ab, u_lim;
    smd_real theta_k = s->theta, w_k = s->w, theta_next, w_next;
    smd_status st;

    /* the voltage computed last time is the one applied now */
    s->u_ab = s->u_ab_next;

    /* observer over the frame of sample k */
    st = smd_lcl_smo_step(&p->smo, &s->smo, i1_ab, i2_ab, s->u_ab, theta_k, w_k);
    s->theta_err = smd_lcl_smo_theta_err(&s->smo, w_k);
    if (p->use_lin) {
        smd_status sl = smd_linobs_step(&p->lin, &s->lin, i1_ab, i2_ab, s->u_ab, w_k);
        if (p->pos_source == 1) {
            /* angle of the linear observer's EMF, e = j w psi e^{j theta} */
            smd_real sg = w_k < SMD_R(0.0) ? SMD_R(-1.0) : SMD_R(1.0);
            smd_real th = SMD_ATAN2(-sg * s->lin.x2[2], sg * s->lin.x2[3]);
            s->theta_err = smd_wrap_pi(th - theta_k);
            if (sl != SMD_OK) {
                st = sl;
            }
        }
    }

    /* frame for the next sample */
    if (p->mode == SMD_LCL_SENSORED) {
        theta_next = in->theta_enc + in->w_enc * T;
        w_next = in->w_enc;
        theta_k = in->theta_enc;
        w_k = in->w_enc;
    } else if (s->phase == SMD_LCL_PHASE_OPENLOOP) {
        /* forced synchronous angle, accelerated at a_start */
        s->w_f += p->a_start * T;
        s->theta_f = smd_wrap_pi(s->theta_f + s->w_f * T);
        theta_next = s->theta_f;
        w_next = s->w_f;
        if (s->w_f >= p->w_handover) {
            /* handover: the PLL starts on the observer's angle (forced angle
             * plus the measured angle error) at the forced speed, and the speed
             * loop on the current that was flowing */
            s->phase = SMD_LCL_PHASE_CLOSED;
            smd_pll_reset(&s->pll, theta_k + s->theta_err + w_k * T, w_k);
            smd_pi_reset(&s->speed_pi, s->i_ref.im);
            theta_next = s->pll.theta;
            w_next = s->pll.w;
        }
    } else {
        /* eq. (48) on the error of eq. (47) */
        smd_pll_step(&p->pll, &s->pll, s->theta_err);
        theta_next = s->pll.theta;
        w_next = s->pll.w;
    }
    if (p->mode == SMD_LCL_SENSORED) {
        /* the observer's frame for k+1 follows the encoder */
        smd_lcl_smo_reframe(&s->smo, smd_wrap_pi(theta_next - s->theta - s->w * T));
    } else {
        smd_lcl_smo_reframe(&s->smo, smd_wrap_pi(theta_next - theta_k - w_k * T));
    }

    /* currents in the frame of sample k */
    i1 = smd_ab_to_dq(i1_ab, theta_k);
    i2 = smd_ab_to_dq(i2_ab, theta_k);
    s->i2_gd = i2;
    e_hat = smd_c(s->smo.e_hat[0], s->smo.e_hat[1]);

    /* current reference */
    if (p->mode != SMD_LCL_SENSORED && s->phase == SMD_LCL_PHASE_OPENLOOP) {
        s->i_ref = smd_c(SMD_R(0.0), p->i_start);
    } else if (p->speed_loop) {
        s->i_ref.re = in->i_ref.re;
        s->i_ref.im = smd_pi_step(&p->speed_pi, &s->speed_pi, in->w_ref - w_k);
    } else {
        s->i_ref = in->i_ref;
    }
    s->i_ref.re = clampr(s->i_ref.re, p->i_max);
    s->i_ref.im = clampr(s->i_ref.im, p->i_max);

    /* motor-current PI in the rotor frame with decoupling and active
     * damping (virtual resistance R_v on the capacitor current i_1 - i_2) */
    {
        smd_cplx e = smd_csub(s->i_ref, i2);
        smd_cplx x_i = smd_cadd(s->x_i, smd_cscale(e, p->k_i_i * T));
        u = smd_cadd(smd_cscale(e, p->k_p_i), x_i);
        u = smd_cadd(u, smd_cscale(smd_cj(i2), w_k * p->L_dec));
        if (p->emf_ff && (p->mode == SMD_LCL_SENSORED || s->phase == SMD_LCL_PHASE_CLOSED)) {
            u = smd_cadd(u, e_hat);
        }
        u = smd_csub(u, smd_cscale(smd_csub(i1, i2), p->R_v));
        /* to the stationary frame at the middle of the application period */
        u_ab = smd_dq_to_ab(u, theta_k + SMD_R(1.5) * w_k * T);
        smd_svm_step(&p->svm, u_ab, in->u_dc, out->d_abc, &u_lim);
        /* anti-windup: keep the integrator where the limited voltage is what
         * the law would have given */
        if (smd_cabs(smd_csub(u_lim, u_ab)) > SMD_R(1e-6) * (SMD_R(1.0) + smd_cabs(u_ab))) {
            smd_cplx du = smd_ab_to_dq(smd_csub(u_lim, u_ab), theta_k + SMD_R(1.5) * w_k * T);
            x_i = smd_cadd(x_i, du);
        }
        s->x_i = x_i;
        s->u_ab_next = u_lim;
    }

    s->theta = theta_next;
    s->w = w_next;
    if (!smd_cfinite(s->u_ab_next) || !isfinite(s->theta) || !isfinite(s->w)) {
        s->u_ab_next = smd_c(SMD_R(0.0), SMD_R(0.0));
        s->x_i = smd_c(SMD_R(0.0), SMD_R(0.0));
        out->d_abc[0] = out->d_abc[1] = out->d_abc[2] = SMD_R(0.5);
        st = SMD_ERR_NONFINITE;
    }
    s->status = (int)st;
    return st;
}

#include "smodrive/smd_drive.h"
#include "smodrive/smd_transforms.h"

smd_status smd_drive_init(smd_drive_params *p, const smd_drive_config *c)
{
    smd_status st;
    if (p == 0 || c == 0) {
        return SMD_ERR_NULL;
    }
    if (c->mode < SMD_DRIVE_CONVENTIONAL || c->mode > SMD_DRIVE_SENSORLESS) {
        return SMD_ERR_MODE;
    }
    if (c->speed_decimation < 1 || c->speed_decimation > 1000) {
        return SMD_ERR_DECIMATION;
    }
    if (c->speed_loop != 0 && c->speed_loop != 1) {
        return SMD_ERR_MODE;
    }
    p->mode = c->mode;
    p->speed_decimation = c->speed_decimation;
    p->speed_loop = c->speed_loop;
    if (c->handover < 0) {
        return SMD_ERR_HANDOVER;
    }
    p->handover = c->handover;
    if (!smd_in_range(c->t_dead_comp, SMD_R(0.0), SMD_R(0.25) * c->T_sp) ||
        !(smd_in_range(c->i_dtc, SMD_R(0.0), SMD_R(1e5)) && c->i_dtc > SMD_R(0.0))) {
        return SMD_ERR_DEADTIME;
    }
    p->dtc_ratio = c->t_dead_comp / c->T_sp;
    p->i_dtc = c->i_dtc;
    st = smd_dbpc_init(&p->dbpc, c->T_sp, c->L_s_hat, c->R_s_hat, c->psi_r_hat);
    if (st != SMD_OK) {
        return st;
    }
    if (c->mode != SMD_DRIVE_CONVENTIONAL) {
        st = smd_smdo_init(&p->smdo, c->T_sp, c->L_s_hat, c->R_s_hat, c->lambda_min, c->l,
                           c->w_c, c->rho);
        if (st != SMD_OK) {
            return st;
        }
        st = smd_smdo_set_euler(&p->smdo, c->smdo_euler);
        if (st != SMD_OK) {
            return st;
        }
    }
    if (c->mode == SMD_DRIVE_SENSORLESS) {
        st = smd_emf_pos_init(&p->pos, c->T_sp, c->w_lpf, c->w_hys, c->w_max);
        if (st != SMD_OK) {
            return st;
        }
        /* The Euler filter (36) rotates u_d_hat by (1 + j w T) and pulls it by
         * w_c T: |1 - w_c T + j w T| < 1 must hold for every speed the
         * estimate can take, or u_d_hat grows without bound. */
        {
            smd_real a = SMD_R(1.0) - c->w_c * c->T_sp;
            smd_real b = c->w_max * c->T_sp;
            if (a * a + b * b >= SMD_R(1.0)) {
                return SMD_ERR_STABILITY;
            }
        }
    }
    st = smd_pi_init(&p->pi, c->k_p, c->k_i, c->T_sp * (smd_real)c->speed_decimation, c->i_max);
    if (st != SMD_OK) {
        return st;
    }
    return smd_svm_init(&p->svm, c->svm_limit, SMD_R(0.0));
}

void smd_drive_reset(const smd_drive_params *p, smd_drive_state *s, smd_real theta_r0,
                     smd_real w_r0)
{
    smd_cplx zero = smd_c(SMD_R(0.0), SMD_R(0.0));
    s->u_s_ab = zero;
    s->u_s_ab_ref = zero;
    s->i_s_ab = zero;
    s->i_dq_ref = zero;
    s->theta_r = theta_r0;
    s->w_r = w_r0;
    s->count = 0;
    s->primed = 0;
    s->samples = 0;
    /* The disturbance of a running machine with an exact model is its back
     * EMF, eq. (43); starting from it is what a flying start would do. */
    smd_smdo_reset(&s->smdo, zero,
                   smd_cj(smd_cscale(smd_cexpj(theta_r0), -w_r0 * p->dbpc.psi_r_hat)));
    smd_emf_pos_reset(&s->pos, w_r0);
    smd_pi_reset(&s->pi, SMD_R(0.0));
}

smd_status smd_drive_step(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in,
                          smd_drive_out *out)
{
    smd_status st = SMD_OK;
    smd_cplx u_ref;
    smd_cplx i_s_ab = smd_ab2_to_ab(in->i_a, in->i_b);
    s->i_s_ab = i_s_ab;
    if (!s->primed) {
        /* The observer's current starts at the first sample, so that a start
         * under load does not begin with a large sliding error. */
        s->smdo.i_s_hat = i_s_ab;
        s->primed = 1;
    }

    if (p->mode == SMD_DRIVE_SENSORLESS) {
        /* eq. (44)-(45) from u_d_hat^k, before the observer's update */
        smd_emf_pos_step(&p->pos, &s->pos, s->smdo.u_d_hat);
        if (s->samples < p->handover) {
            /* sensored start: the observer converges on the encoder's angle */
            s->samples++;
            s->theta_r = in->theta_r;
            s->w_r = in->w_r;
        } else {
            s->theta_r = s->pos.theta_r_hat;
            s->w_r = s->pos.w_r_hat;
        }
    } else {
        s->theta_r = in->theta_r;
        s->w_r = in->w_r;
    }

    s->i_dq_ref.re = in->i_dq_ref.re;
    if (p->speed_loop) {
        if (s->count == 0) {
            s->i_dq_ref.im = smd_pi_step(&p->pi, &s->pi, in->w_r_ref - s->w_r);
        }
        s->count = (s->count + 1) % p->speed_decimation;
    } else {
        s->i_dq_ref.im = in->i_dq_ref.im;
    }

    if (p->mode == SMD_DRIVE_CONVENTIONAL) {
        u_ref = smd_dbpc_conventional(&p->dbpc, i_s_ab, s->u_s_ab, s->i_dq_ref, s->theta_r,
                                      s->w_r);
    } else {
        smd_cplx i_ref_k2;
        st = smd_smdo_step(&p->smdo, &s->smdo, i_s_ab, s->u_s_ab, s->w_r);
        i_ref_k2 = smd_dbpc_ref_k2(&p->dbpc, s->i_dq_ref, s->theta_r, s->w_r);
        u_ref = smd_dbpc_robust(&p->dbpc, s->smdo.i_s_hat, s->smdo.u_d_hat, i_ref_k2);
    }

    if (!smd_cfinite(u_ref)) {
        st = SMD_ERR_NONFINITE;
        u_ref = smd_c(SMD_R(0.0), SMD_R(0.0));
    }
    s->u_s_ab_ref = u_ref;
    smd_svm_step(&p->svm, u_ref, in->u_dc, out->d_abc, &s->u_s_ab);
    if (p->dtc_ratio > SMD_R(0.0)) {
        /* current expected in the middle of the next period, t_k + 1.5 T_sp */
        smd_real i_abc[3];
        smd_cplx i_mid = smd_dq_to_ab(s->i_dq_ref, s->theta_r + SMD_R(1.5) * s->w_r * p->dbpc.T_sp);
        smd_ab_to_abc(i_mid, i_abc);
        smd_svm_deadtime_comp(out->d_abc, i_abc, p->dtc_ratio, p->i_dtc);
    }
    return st;
}

void smd_drive_set_speed_integrator(smd_drive_state *s, smd_real i_q0)
{
    smd_pi_reset(&s->pi, i_q0);
    s->i_dq_ref.im = i_q0;
}

smd_drive_view smd_drive_get_view(const smd_drive_state *s)
{
    smd_drive_view v;
    v.i_s_ab = s->i_s_ab;
    v.i_dq_ref = s->i_dq_ref;
    v.u_s_ab = s->u_s_ab;
    v.u_s_ab_ref = s->u_s_ab_ref;
    v.i_s_hat = s->smdo.i_s_hat;
    v.u_d_hat = s->smdo.u_d_hat;
    v.theta_r = s->theta_r;
    v.w_r = s->w_r;
    v.lambda = s->smdo.lambda;
    return v;
}

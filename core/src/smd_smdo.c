#include "smodrive/smd_smdo.h"

smd_status smd_smdo_init(smd_smdo_params *p, smd_real T_sp, smd_real L_s_hat, smd_real R_s_hat,
                         smd_real lambda_min, smd_real l, smd_real w_c, smd_real rho)
{
    smd_status st;
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    st = smd_check_model(T_sp, L_s_hat, R_s_hat);
    if (st != SMD_OK) {
        return st;
    }
    if (!smd_in_range(lambda_min, SMD_R(0.0), SMD_R(1e7))) {
        return SMD_ERR_LAMBDA;
    }
    if (!smd_in_pos_range(l, SMD_R(1e7))) {
        return SMD_ERR_L_GAIN;
    }
    if (!smd_in_pos_range(w_c, SMD_R(1e7))) {
        return SMD_ERR_WC;
    }
    if (!smd_in_pos_range(rho, SMD_R(1000.0))) {
        return SMD_ERR_RHO;
    }
    /* Linear part of the error loop: e^{k+1} = (1 - (l + lambda/rho) T) e^k at
     * small errors; both the proportional and the smoothed switching terms
     * must keep the factor inside (-1, 1). */
    if ((l + lambda_min / rho) * T_sp >= SMD_R(2.0) || w_c * T_sp >= SMD_R(1.0)) {
        return SMD_ERR_STABILITY;
    }
    p->T_sp = T_sp;
    p->L_s_hat = L_s_hat;
    p->R_s_hat = R_s_hat;
    p->lambda_min = lambda_min;
    p->l = l;
    p->w_c = w_c;
    p->rho = rho;
    p->euler = 0;
    p->L_T = L_s_hat / T_sp;
    p->T_L = T_sp / L_s_hat;
    p->inv_L = SMD_R(1.0) / L_s_hat;
    return SMD_OK;
}

smd_status smd_smdo_set_euler(smd_smdo_params *p, int euler)
{
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    if (euler != 0 && euler != 1) {
        return SMD_ERR_MODE;
    }
    p->euler = euler;
    return SMD_OK;
}

void smd_smdo_reset(smd_smdo_state *s, smd_cplx i_s_hat0, smd_cplx u_d_hat0)
{
    smd_cplx zero = smd_c(SMD_R(0.0), SMD_R(0.0));
    s->i_s_hat = i_s_hat0;
    s->u_d_hat = u_d_hat0;
    s->e_i_prev = zero;
    s->u_smo_prev = zero;
    s->u_smo = zero;
    s->lambda = SMD_R(0.0);
}

/* A value of the step was not finite: restart from the sample if it is
 * usable, else from the last estimate, else from zero; never keep a NaN in
 * the state (out of line: the step keeps no registers for it). */
#if defined(__GNUC__)
__attribute__((noinline, cold))
#endif
static smd_status restart(smd_smdo_state *s, smd_cplx i_s_ab)
{
    smd_cplx i0 = smd_cfinite(i_s_ab) ? i_s_ab
                  : (smd_cfinite(s->i_s_hat) ? s->i_s_hat : smd_c(SMD_R(0.0), SMD_R(0.0)));
    smd_smdo_reset(s, i0, smd_c(SMD_R(0.0), SMD_R(0.0)));
    return SMD_ERR_NONFINITE;
}

/* (out of line in smd_smdo_step, GCC and Clang: one copy of the step in a
 * firmware, whose core fills a 32 kB CCM SRAM: core/target/stm32g4) */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
smd_status smd_smdo_step_rot(const smd_smdo_params *p, smd_smdo_state *s, smd_cplx i_s_ab,
                             smd_cplx u_s_ab, smd_real w_r, smd_real R, smd_cplx rot)
{
    const smd_real T = p->T_sp;
    const smd_real L = p->L_s_hat;
    smd_cplx e_i = smd_csub(i_s_ab, s->i_s_hat); /* eq. (20) */
    smd_cplx e_u, sgn, u_smo, di, du, i_hat, u_d;
    smd_real lambda;

    /* eq. (38): e_u from the discrete error dynamics (23) */
    e_u = smd_cscale(smd_csub(e_i, s->e_i_prev), p->L_T);
    e_u = smd_cadd(e_u, s->u_smo_prev);
    e_u = smd_cadd(e_u, smd_cscale(s->e_i_prev, R));
    /* eq. (37): adaptive switching gain */
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    lambda = p->lambda_min + smd_cabs(e_u) * p->inv_L; /* (the fast build: no division) */
#else
    lambda = p->lambda_min + smd_cabs(e_u) / L;
#endif
    /* eq. (39): smoothed sign */
    sgn = smd_cscale(e_i, SMD_R(1.0) / (smd_cabs(e_i) + p->rho));
    /* eq. (34) */
    u_smo = smd_cadd(smd_cscale(sgn, L * lambda), smd_cscale(e_i, L * p->l - R));
    /* eq. (35), with R_hat (the paper prints R_s; see docs/errata.md) */
    di = smd_cadd(smd_cadd(u_s_ab, s->u_d_hat), u_smo);
    di = smd_csub(di, smd_cscale(s->i_s_hat, R));
    i_hat = smd_cadd(s->i_s_hat, smd_cscale(di, p->T_L));
    if (p->euler) {
        /* eq. (36) as printed: forward-Euler complex-coefficient filter */
        du = smd_cadd(smd_cscale(smd_cj(s->u_d_hat), w_r), smd_cscale(u_smo, p->w_c));
        u_d = smd_cadd(s->u_d_hat, smd_cscale(du, T));
    } else {
        /* eq. (19) discretised with the exact rotation e^{j w T} of (17) */
        du = smd_cmul(s->u_d_hat, rot);
        u_d = smd_cadd(du, smd_cscale(u_smo, p->w_c * T));
    }
    /* (checked before the state is written: a restart reads the last
     * estimate there, and the step keeps no copy of it) */
    if (!(smd_nf(smd_cnfs(i_hat) + smd_cnfs(u_d) + smd_nfs(lambda)) == SMD_R(0.0))) {
        return restart(s, i_s_ab);
    }
    s->i_s_hat = i_hat;
    s->u_d_hat = u_d;
    s->e_i_prev = e_i;
    s->u_smo_prev = u_smo;
    s->u_smo = u_smo;
    s->lambda = lambda;
    return SMD_OK;
}

smd_status smd_smdo_step_r(const smd_smdo_params *p, smd_smdo_state *s, smd_cplx i_s_ab,
                           smd_cplx u_s_ab, smd_real w_r, smd_real R)
{
    return smd_smdo_step_rot(p, s, i_s_ab, u_s_ab, w_r, R, smd_cexpj_small(w_r * p->T_sp));
}

smd_status smd_smdo_step(const smd_smdo_params *p, smd_smdo_state *s, smd_cplx i_s_ab,
                         smd_cplx u_s_ab, smd_real w_r)
{
    return smd_smdo_step_r(p, s, i_s_ab, u_s_ab, w_r, p->R_s_hat);
}

#include "smodrive/smd_dbpc.h"

smd_status smd_dbpc_init(smd_dbpc_params *p, smd_real T_sp, smd_real L_s_hat,
                         smd_real R_s_hat, smd_real psi_r_hat)
{
    smd_status st;
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    st = smd_check_model(T_sp, L_s_hat, R_s_hat);
    if (st != SMD_OK) {
        return st;
    }
    if (!smd_in_range(psi_r_hat, SMD_R(0.0), SMD_R(100.0))) {
        return SMD_ERR_PSI;
    }
    p->T_sp = T_sp;
    p->L_s_hat = L_s_hat;
    p->R_s_hat = R_s_hat;
    p->psi_r_hat = psi_r_hat;
    p->L_T = L_s_hat / T_sp;
    p->T_L = T_sp / L_s_hat;
    return SMD_OK;
}

smd_cplx smd_dbpc_ref_k2(const smd_dbpc_params *p, smd_cplx i_dq_ref, smd_real theta_r,
                         smd_real w_r)
{
    /* yang2018 eq. (7) */
    return smd_cmul(i_dq_ref, smd_cexpj(theta_r + SMD_R(2.0) * w_r * p->T_sp));
}

smd_cplx smd_dbpc_predict(const smd_dbpc_params *p, smd_cplx i_s_ab, smd_cplx u_s_ab,
                          smd_real theta_r, smd_real w_r)
{
    /* yang2018 eq. (8): back EMF j w psi e^{j theta} */
    smd_cplx e = smd_cj(smd_cscale(smd_cexpj(theta_r), w_r * p->psi_r_hat));
    smd_cplx di = smd_csub(smd_csub(u_s_ab, smd_cscale(i_s_ab, p->R_s_hat)), e);
    return smd_cadd(i_s_ab, smd_cscale(di, p->T_L));
}

smd_cplx smd_dbpc_conventional(const smd_dbpc_params *p, smd_cplx i_s_ab, smd_cplx u_s_ab,
                               smd_cplx i_dq_ref, smd_real theta_r, smd_real w_r)
{
    smd_cplx i_k1 = smd_dbpc_predict(p, i_s_ab, u_s_ab, theta_r, w_r);
    smd_cplx i_ref_k2 = smd_dbpc_ref_k2(p, i_dq_ref, theta_r, w_r);
    /* yang2018 eq. (9): EMF at theta^k + w^k T_sp */
    smd_cplx e = smd_cj(smd_cscale(smd_cexpj(theta_r + w_r * p->T_sp), w_r * p->psi_r_hat));
    smd_cplx u = smd_cscale(smd_csub(i_ref_k2, i_k1), p->L_T);
    u = smd_cadd(u, smd_cscale(i_k1, p->R_s_hat));
    return smd_cadd(u, e);
}

smd_cplx smd_dbpc_robust_r(const smd_dbpc_params *p, smd_cplx i_s_ab_k1, smd_cplx u_d_ab_k1,
                           smd_cplx i_ref_ab_k2, smd_real R)
{
    /* yang2018 eq. (42) */
    smd_cplx u = smd_cscale(smd_csub(i_ref_ab_k2, i_s_ab_k1), p->L_T);
    u = smd_cadd(u, smd_cscale(i_s_ab_k1, R));
    return smd_csub(u, u_d_ab_k1);
}

smd_cplx smd_dbpc_robust(const smd_dbpc_params *p, smd_cplx i_s_ab_k1, smd_cplx u_d_ab_k1,
                         smd_cplx i_ref_ab_k2)
{
    return smd_dbpc_robust_r(p, i_s_ab_k1, u_d_ab_k1, i_ref_ab_k2, p->R_s_hat);
}

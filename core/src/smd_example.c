#include "smodrive/smd_example.h"

/* yang2018 Table I, and alpha of the current PI (smd_example.h) */
#define EX_L_S 23.45e-3
#define EX_ALPHA 2000.0

void smd_example_drive_config(smd_drive_config *c)
{
    const smd_drive_config zero = {0};
    *c = zero;
    c->current = SMD_CC_DBPC;
    c->position = SMD_POS_ENCODER;
    c->start = SMD_START_RUNNING;
    c->lcl = 0;
    c->T_sp = SMD_R(1e-4);
    c->L_s_hat = SMD_R(EX_L_S);
    c->R_s_hat = SMD_R(2.25);
    c->psi_r_hat = SMD_R(0.4);
    c->lambda_min = SMD_R(800.0);
    c->l = SMD_R(1200.0);
    c->w_c = SMD_R(1500.0);
    c->rho = SMD_R(0.2);
    c->smdo_euler = 0;
    c->w_lpf = SMD_R(200.0);
    c->w_hys = SMD_R(20.0);
    c->w_max = SMD_R(2000.0);
    c->k_p_i = SMD_R(EX_L_S * EX_ALPHA);
    c->k_i_i = SMD_R(EX_L_S * EX_ALPHA * EX_ALPHA / 4.0);
    c->L_dec = SMD_R(EX_L_S);
    c->dec_ref = 0;
    c->R_v = SMD_R(0.0);
    c->emf_ff = 1;
    c->speed_loop = 0;
    c->k_p_w = SMD_R(0.05);
    c->k_i_w = SMD_R(2.0);
    c->i_max = SMD_R(15.0);
    c->speed_decimation = 1;
    c->supervise_every = 1;
    c->k_theta = SMD_R(0.1);
    c->k_omega = SMD_R(10.0);
    c->k_a = SMD_R(10.0);
    c->handover = 0;
    c->i_start = SMD_R(8.0);
    c->a_start = SMD_R(2e4);
    c->w_handover = SMD_R(201.0);
    c->svm_limit = SMD_SVM_LIMIT_HEXAGON;
    c->t_dead_comp = SMD_R(0.0);
    c->i_dtc = SMD_R(1.0);
}

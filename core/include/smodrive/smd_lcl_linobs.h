/*
 * Linear reduced-order observer of the capacitor voltage and back EMF of an
 * LCL-filtered SPMSM in the stationary frame, yao2022 eq. (64)-(65) (the
 * baseline of the robustness comparison, Fig. 23):
 *   x2_hat(k) = z(k) + L y(k)
 *   z(k+1)    = Theta x2_hat(k) + Ky y(k) + Ku u(k)
 * with y = [i_1; i_2] (4), x2 = [u_c; e] (4), Theta = G22 - L G12,
 * Ky = G21 - L G11, Ku = H2 - L H1 (matrices of the ZOH model at the speed w,
 * designed offline on a speed grid and interpolated here).
 */
#ifndef SMD_LCL_LINOBS_H
#define SMD_LCL_LINOBS_H

#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Matrices at one speed, row-major; @design(...) as for smd_lcl_model. */
typedef struct smd_linobs_model {
    smd_real L[16];     /* 4x4 @design(L_s) */
    smd_real Theta[16]; /* 4x4 @design(Theta) */
    smd_real Ky[16];    /* 4x4 @design(Theta_y) */
    smd_real Ku[8];     /* 4x2 @design(Theta_u) */
} smd_linobs_model;

/* The table is owned by the caller and must outlive the params. */
typedef struct smd_linobs_config {
    const smd_linobs_model *table; /* n models at w = w_min + k dw (electrical rad/s) */
    int n;                         /* >= 2 */
    smd_real w_min, dw;            /* rad/s; dw > 0 */
} smd_linobs_config;

typedef struct smd_linobs_params {
    const smd_linobs_model *table;
    int n;
    smd_real w_min, dw;
} smd_linobs_params;

typedef struct smd_linobs_state {
    smd_real z[4];
    smd_real x2[4];     /* [u_c_alpha, u_c_beta, e_alpha, e_beta] estimate at k */
    int primed;
} smd_linobs_state;

smd_status smd_linobs_init(smd_linobs_params *p, const smd_linobs_config *c);
void smd_linobs_reset(smd_linobs_state *s);
/* One sample: y = [i1_ab, i2_ab] at k, u_ab applied over [k, k+1), w the
 * speed used to pick the model. Returns SMD_ERR_NONFINITE (and resets) if
 * the estimate blew up. */
smd_status smd_linobs_step(const smd_linobs_params *p, smd_linobs_state *s, smd_cplx i1_ab,
                           smd_cplx i2_ab, smd_cplx u_ab, smd_real w);

#ifdef __cplusplus
}
#endif

#endif

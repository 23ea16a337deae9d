/*
 * Engine for the LCL-filtered drive (yao2022): couples smd_lcl_plant (double)
 * with the firmware controller smd_lcl_drive (float) with one sample of
 * computational delay and logs into a caller-owned buffer. Same timeline as
 * smd_engine.h. Given a table for it, the drive also runs the linear
 * reduced-order observer (64)-(65), alongside or as its position source.
 */
#ifndef SMD_LCL_ENGINE_H
#define SMD_LCL_ENGINE_H

#include "smdsim/smd_engine.h"
#include "smdsim/smd_lcl.h"
#include "smodrive/smd_lcl_drive.h"
#include "smodrive/smd_lcl_linobs.h"

/* Observer configuration (the table is owned by the caller and must outlive
 * the engine). */
typedef struct smd_lcl_obs_config {
    int law;                       /* smd_lcl_smo_law */
    const smd_lcl_model *table;
    int n;
    float w_min, dw;               /* table grid, electrical rad/s */
    float Q1, Q2, bw_rel2, bw_rel3, w_bp_min;
    const smd_linobs_model *lin_table; /* NULL: no linear observer */
    int lin_n;
    float lin_w_min, lin_dw;
} smd_lcl_obs_config;

typedef struct smd_lcl_start {
    int phase;        /* smd_lcl_phase to begin with */
    double theta0;    /* controller's initial angle and speed (flying start) */
    double w0;
    double i_delta0;  /* speed-PI integrator (warm start) */
} smd_lcl_start;

enum smd_lcl_log_channel {
    SMD_LL_T = 0, SMD_LL_W_M, SMD_LL_THETA_R, SMD_LL_THETA_HAT, SMD_LL_W_HAT,
    SMD_LL_THETA_ERR_EST, SMD_LL_I2_D, SMD_LL_I2_Q, SMD_LL_I2_G, SMD_LL_I2_DL,
    SMD_LL_IREF_G, SMD_LL_IREF_DL, SMD_LL_E_G, SMD_LL_E_DL, SMD_LL_S_G, SMD_LL_S_DL,
    SMD_LL_DHAT_G, SMD_LL_DHAT_DL, SMD_LL_U_ALPHA, SMD_LL_U_BETA, SMD_LL_UC_ALPHA,
    SMD_LL_UC_BETA, SMD_LL_I1_ALPHA, SMD_LL_I1_BETA, SMD_LL_I2_ALPHA, SMD_LL_I2_BETA,
    SMD_LL_T_E, SMD_LL_T_L, SMD_LL_W_M_REF, SMD_LL_PHASE, SMD_LL_LIN_E_ALPHA,
    SMD_LL_LIN_E_BETA, SMD_LL_V_G, SMD_LL_V_DL, SMD_LL_STATUS, SMD_LL_N
};

typedef struct smd_lcl_engine {
    smd_lcl_plant plant;
    smd_lcl_smo_params smo_p;
    smd_lcl_drive_params ctrl_p;
    smd_lcl_drive_state ctrl_s;
    smd_linobs_params lin_p;
    int lin_on;
    smd_profiles prof;
    double d_abc[3];
    long k;
    double T;
    int last_status;
} smd_lcl_engine;

/* 0 on success; 1000 + plant field code; 2000 + observer status;
 * 3000 + drive status; 4000 + linear observer status; 5000 bad profile. */
int smd_lcl_engine_init(smd_lcl_engine *e, const smd_lcl_config *plant,
                        const smd_lcl_drive_config *ctrl, const smd_lcl_obs_config *obs,
                        const smd_profiles *prof, const smd_lcl_start *start);
long smd_lcl_engine_run(smd_lcl_engine *e, long n, double *log, long stride);
const char *smd_lcl_log_channel_name(int ch);
unsigned long smd_sizeof_lcl_engine(void);
unsigned long smd_sizeof_lcl_drive_config(void);
unsigned long smd_sizeof_lcl_obs_config(void);
unsigned long smd_sizeof_lcl_model(void);
unsigned long smd_sizeof_linobs_model(void);
int smd_pll_impulse(double T, double k_theta, double k_omega, double k_a, double amp, long n,
                    double *out);

#endif

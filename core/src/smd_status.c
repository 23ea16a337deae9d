#include "smodrive/smd_types.h"

const char *smd_status_str(smd_status s)
{
    switch (s) {
    case SMD_OK: return "ok";
    case SMD_ERR_NULL: return "NULL pointer argument";
    case SMD_ERR_TS: return "T_sp: sampling period must be in (0, 1] s";
    case SMD_ERR_L: return "L_s_hat: inductance estimate must be in (0, 10] H";
    case SMD_ERR_R: return "R_s_hat: resistance estimate must be in [0, 1000] ohm";
    case SMD_ERR_PSI: return "psi_r_hat: PM flux estimate must be in [0, 100] Wb";
    case SMD_ERR_LAMBDA: return "lambda_min: must be in [0, 1e7] A/s";
    case SMD_ERR_L_GAIN: return "l: SMDO proportional gain must be in (0, 1e7] 1/s";
    case SMD_ERR_WC: return "omega_c: SMDO filter gain must be in (0, 1e7] rad/s";
    case SMD_ERR_RHO: return "rho: boundary layer must be in (0, 1000] A";
    case SMD_ERR_KP: return "k_p: proportional gain must be in [0, 1e6]";
    case SMD_ERR_KI: return "k_i: integral gain must be in [0, 1e9]";
    case SMD_ERR_LIMIT: return "y_max: output limit must be in (0, 1e9]";
    case SMD_ERR_MODE: return "mode: unknown value";
    case SMD_ERR_STABILITY: return "gains make the discrete loop unstable";
    case SMD_ERR_WLPF: return "w_lpf: low-pass bandwidth must be in (0, pi/T_sp) rad/s";
    case SMD_ERR_NONFINITE: return "a step produced NaN or Inf; outputs were zeroed";
    case SMD_ERR_DECIMATION:
        return "speed_decimation: must be in [1, 1000]; smo.decimation, supervise_every: [0, 64]";
    case SMD_ERR_WHYS: return "w_hys: direction hysteresis must be in [0, 1e5] rad/s";
    case SMD_ERR_WMAX: return "w_max: speed-estimate limit must be in (w_hys, pi/T_sp] rad/s";
    case SMD_ERR_DEADTIME:
        return "t_dead_comp: must be in [0, T_sp/4] s, and i_dtc > 0 A";
    case SMD_ERR_HANDOVER: return "handover: must be >= 0 samples";
    case SMD_ERR_DMIN: return "d_min: minimum duty must be in [0, 0.49]";
    case SMD_ERR_TABLE:
        return "observer table: at least 2 models on a grid w_min + k dw with dw > 0";
    case SMD_ERR_COMBINATION:
        return "parts: lcl_smo_pll, lcl_linear and active damping need the LCL filter "
               "(lcl = 1), and the LCL filter needs pi current control";
    case SMD_ERR_CURRENT_PI:
        return "current PI: k_p_i in [0, 1e4] V/A, k_i_i in [0, 1e9] V/(A s), "
               "L_dec in [0, 10] H, R_v in [0, 1e4] V/A";
    case SMD_ERR_START:
        return "start-up: i_start in [0, 1e5] A, a_start in [0, 1e9] rad/s^2, "
               "w_handover in [0, pi/T_sp] rad/s";
    case SMD_ERR_PROTECTION:
        return "protection: i_trip >= 0 A, 0 <= u_dc_min < u_dc_max (or 0) V, safe_state 0 or 1, "
               "lock_samples in [0, 1e6], lock_ratio > 1, w_lock_min >= 0 rad/s, "
               "0 <= w_if_enter < w_handover rad/s";
    case SMD_ERR_FAULT: return "a fault is active: the outputs are the safe state (see the fault word)";
    case SMD_ERR_IDENT:
        return "identification: T_sp in (0, 1] s, i_test in (0, 1e5] A, u_max in (0, 1e5] V, "
               "t_win in [10 T_sp, 10] s, t_level_max in [2 t_win, 100] s and at most 1e8 T_sp, "
               "levels in [8, 32]";
    case SMD_ERR_RLS:
        return "R_s / psi_r tracker: i_inj in (0, 1e5] A, tau in [10 T_sp, 1e3] s, n_half in "
               "[2, 1e6] samples, w_min in [0, 1e7] rad/s, L_s_hat in (0, 10] H, R_s_hat in "
               "[0, 1e3] ohm, psi_r_hat in [0, 100] Wb";
    default: return "unknown status";
    }
}

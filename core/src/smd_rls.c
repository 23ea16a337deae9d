/* Online tracking of R_s and psi_r by recursive least squares
 * (smodrive/smd_rls.h: the model, yang2018 eq. (1), and the fit). */
#include "smodrive/smd_rls.h"

smd_status smd_rls_init(smd_rls_params *p, smd_real T_sp, smd_real L_s_hat, smd_real i_inj,
                        smd_real tau, int n_half, smd_real w_min, smd_real R0, smd_real psi0)
{
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_pos_range(T_sp, SMD_R(1.0)) || !smd_in_pos_range(L_s_hat, SMD_R(10.0)) ||
        !smd_in_pos_range(i_inj, SMD_R(1e5)) || !smd_in_range(tau, SMD_R(10.0) * T_sp,
                                                             SMD_R(1e3)) ||
        n_half < 2 || n_half > 1000000 || !smd_in_range(w_min, SMD_R(0.0), SMD_R(1e7)) ||
        !smd_in_range(R0, SMD_R(0.0), SMD_R(1e3)) || !smd_in_range(psi0, SMD_R(0.0),
                                                                  SMD_R(100.0))) {
        return SMD_ERR_RLS;
    }
    p->T_sp = T_sp;
    p->L_s_hat = L_s_hat;
    p->i_inj = i_inj;
    p->alpha = T_sp / tau;
    p->w_min = w_min;
    p->R0 = R0;
    p->psi0 = psi0;
    p->n_half = n_half;
    p->k_td = SMD_R(0.0);
    {
        /* 2 tau in samples, within an int (tau / T_sp <= 1e3 / T_sp) */
        const smd_real n = SMD_R(2.0) * tau / T_sp;
        p->n_stale = n < SMD_R(1e9) ? (int)n : 1000000000;
    }
    return SMD_OK;
}

smd_status smd_rls_set_dead_time(smd_rls_params *p, smd_real t_dc)
{
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_range(t_dc, SMD_R(0.0), p->T_sp)) {
        return SMD_ERR_RLS;
    }
    p->k_td = t_dc / (SMD_R(2.0) * p->L_s_hat);
    return SMD_OK;
}

void smd_rls_reset(const smd_rls_params *p, smd_rls_state *s)
{
    const smd_cplx zero = smd_c(SMD_R(0.0), SMD_R(0.0));
    s->i_prev = zero;
    s->u_prev = zero;
    s->have_prev = 0;
    s->k_half = 0;
    s->sgn = 1;
    s->W = SMD_R(0.0);
    s->M_i = s->M_y = s->S_ii = s->S_iy = s->S_yy = SMD_R(0.0);
    s->R_se = SMD_R(-1.0);
    s->S_ww = s->S_wy = s->S_wi = SMD_R(0.0);
    s->R_hat = p->R0;
    s->R_slope = p->R0;
    s->psi_hat = p->psi0;
    s->age = 0;
}

smd_real smd_rls_injection(const smd_rls_params *p, const smd_rls_state *s)
{
    return s->sgn > 0 ? p->i_inj : -p->i_inj;
}

/* The weighted means of the d-axis line and of the q axis, one sample on. */
static void update(const smd_rls_params *p, smd_rls_state *s, smd_cplx y, smd_cplx i_m,
                   smd_real w)
{
    const smd_real a = p->alpha;
    s->W += a * (SMD_R(1.0) - s->W);
    s->M_i += a * (i_m.re - s->M_i);
    s->M_y += a * (y.re - s->M_y);
    s->S_ii += a * (i_m.re * i_m.re - s->S_ii);
    s->S_iy += a * (i_m.re * y.re - s->S_iy);
    s->S_yy += a * (y.re * y.re - s->S_yy);
    if (SMD_FABS(w) >= p->w_min && w != SMD_R(0.0)) {
        s->S_ww += a * (w * w - s->S_ww);
        s->S_wy += a * (w * y.im - s->S_wy);
        s->S_wi += a * (w * i_m.im - s->S_wi);
    }
}

/* R_s from the d-axis line once it has about 0.7 tau of data and the
 * injection's variance (i_inj^2 for the square wave) at least a quarter of
 * it; psi_r from the q axis with that R_s. */
static void solve(const smd_rls_params *p, smd_rls_state *s)
{
    const smd_real den = s->W * s->S_ii - s->M_i * s->M_i;
    const smd_real need = SMD_R(0.25) * p->i_inj * p->i_inj * s->W * s->W;
    if (s->W >= SMD_R(0.5) && den >= need) {
        /* the line's slope, and its standard error: residual variance
         * var(y) - R cov(i, y) over n = 2 / alpha samples and var(i) */
        const smd_real cov = s->W * s->S_iy - s->M_i * s->M_y;
        const smd_real R = cov / den;
        const smd_real res = (s->W * s->S_yy - s->M_y * s->M_y) - R * cov;
        const smd_real se2 = (res > SMD_R(0.0) ? res : SMD_R(0.0)) * SMD_R(0.5) * p->alpha / den;
        if (isfinite(R) && isfinite(se2)) {
            s->R_se = SMD_SQRT(se2);
            if (se2 <= SMD_R(0.0625) * R * R) {
                /* the slope corrected for where the current is sampled
                 * (smd_rls_set_dead_time) */
                const smd_real k = R * p->k_td;
                s->R_hat = (k > SMD_R(0.0) && k <= SMD_R(0.1)) ? R / (SMD_R(1.0) - k) : R;
                s->R_slope = R;
                s->age = 0;
            }
        }
    }
    if (s->S_ww > SMD_R(0.0)) {
        /* (with the slope: the q axis's currents are sampled as the d axis's) */
        const smd_real psi = (s->S_wy - s->R_slope * s->S_wi) / s->S_ww;
        if (isfinite(psi)) {
            s->psi_hat = psi;
        }
    }
}

void smd_rls_step(const smd_rls_params *p, smd_rls_state *s, smd_cplx i_ab, smd_cplx u_next,
                  int u_ok, smd_real theta_k, smd_real w_k, int valid)
{
    const smd_real T = p->T_sp;
    int ok = valid && smd_cnf(i_ab) + smd_cnf(u_next) + smd_nf(theta_k) + smd_nf(w_k) ==
                          SMD_R(0.0);
    if (s->age <= p->n_stale) {
        s->age++;
    }
    if (ok && s->have_prev) {
        /* the interval [k-1, k): its middle, its mean current, eq. (1) */
        const smd_cplx r = smd_cconj(smd_cexpj(theta_k - SMD_R(0.5) * w_k * T));
        const smd_cplx di = smd_cscale(smd_csub(i_ab, s->i_prev), p->L_s_hat / T);
        const smd_cplx i_m = smd_cmul(smd_cscale(smd_cadd(i_ab, s->i_prev), SMD_R(0.5)), r);
        const smd_cplx y = smd_cmul(smd_csub(s->u_prev, di), r);
        if (smd_cnf(y) + smd_cnf(i_m) == SMD_R(0.0)) {
            update(p, s, y, i_m, w_k);
            solve(p, s);
        } else {
            ok = 0;
        }
    }
    s->have_prev = ok && u_ok;
    s->i_prev = i_ab;
    s->u_prev = u_next;
    if (++s->k_half >= p->n_half) {
        s->k_half = 0;
        s->sgn = -s->sgn;
    }
}

int smd_rls_stale(const smd_rls_params *p, const smd_rls_state *s)
{
    return s->age > p->n_stale;
}

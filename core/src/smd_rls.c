/* Online tracking of R_s and psi_r by recursive least squares
 * (smodrive/smd_rls.h: the model, yang2018 eq. (1), and the fit). */
#include "smodrive/smd_rls.h"

/* the fit and the observer's frame out of line (GCC, Clang): the tracker is
 * not the control law's hot path, and inlined they doubled its code (a
 * firmware's core fills a 32 kB CCM SRAM: core/target/stm32g4) */
#if defined(__GNUC__)
#define RLS_OUT_OF_LINE __attribute__((noinline))
#else
#define RLS_OUT_OF_LINE
#endif

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
    p->observer = 0;
    p->i_band = SMD_R(0.0);
    p->R_lo = SMD_R(0.0);
    p->R_hi = SMD_R(1e30);
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

smd_status smd_rls_set_range(smd_rls_params *p, smd_real lo, smd_real hi)
{
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_range(lo, SMD_R(0.0), SMD_R(1e30)) || !smd_in_range(hi, lo, SMD_R(1e30))) {
        return SMD_ERR_RLS;
    }
    p->R_lo = lo;
    p->R_hi = hi;
    return SMD_OK;
}

smd_status smd_rls_set_band(smd_rls_params *p, smd_real i_band)
{
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_range(i_band, SMD_R(0.0), SMD_R(1e5))) {
        return SMD_ERR_RLS;
    }
    p->i_band = i_band;
    return SMD_OK;
}

/* 1 when every phase current of i_ab is at least b from zero */
static int clear_of_zero(smd_cplx i_ab, smd_real b)
{
    const smd_real x = SMD_R(0.5) * i_ab.re, y = SMD_R(0.8660254) * i_ab.im;
    return SMD_FABS(i_ab.re) >= b && SMD_FABS(x - y) >= b && SMD_FABS(x + y) >= b;
}

smd_status smd_rls_set_observer(smd_rls_params *p, int on)
{
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    p->observer = on != 0;
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
    s->M_z = s->S_zy = s->S_zi = s->Wt = SMD_R(0.0);
    s->z_sgn = 1;
    s->R_hat = p->R0;
    s->R_slope = p->R0;
    s->psi_hat = p->psi0;
    s->age = 0;
    s->th_f = s->w_f = s->dev = s->A_prev = SMD_R(0.0);
    s->n_dev = s->n_per = 0;
}

/* The frame of an observer's angle theta (smd_rls_set_observer): a line
 * th_f + w_f t corrected once a period of the injection (2 n_half samples)
 * from the angle's mean over it, which a periodic response to the square
 * wave does not move. The mean sits at the period's middle; two means give
 * the speed (unwrapped with the last speed). Returns 1 once three whole
 * periods have made it (the first mean, the speed from the second, once
 * refined). */
RLS_OUT_OF_LINE static int frame(const smd_rls_params *p, smd_rls_state *s, smd_real theta,
                                 smd_real w)
{
    const smd_real T = p->T_sp;
    const int n = 2 * p->n_half;
    if (s->n_per == 0 && s->n_dev == 0) {
        s->th_f = theta;
        s->w_f = w;
        s->dev = SMD_R(0.0);
    } else {
        s->th_f = smd_wrap_pi(s->th_f + s->w_f * T);
    }
    s->dev += smd_wrap_pi(theta - s->th_f);
    if (++s->n_dev >= n) {
        /* the period's mean angle, at its middle (n - 1) / 2 samples back */
        const smd_real half = SMD_R(0.5) * (smd_real)(n - 1) * T;
        const smd_real A = smd_wrap_pi(s->th_f - s->w_f * half + s->dev / (smd_real)n);
        if (s->n_per >= 1) {
            const smd_real span = (smd_real)n * T;
            s->w_f += smd_wrap_pi(A - s->A_prev - s->w_f * span) / span;
        }
        s->th_f = smd_wrap_pi(A + s->w_f * half);
        s->A_prev = A;
        s->dev = SMD_R(0.0);
        s->n_dev = 0;
        if (s->n_per < 3) {
            s->n_per++;
        }
    }
    return s->n_per >= 3;
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
    if (p->observer) {
        const smd_real z = s->z_sgn > 0 ? p->i_inj : -p->i_inj;
        s->Wt += a * (SMD_R(1.0) - s->Wt);
        s->M_z += a * (z - s->M_z);
        s->S_zy += a * (z * y.re - s->S_zy);
        s->S_zi += a * (z * i_m.re - s->S_zi);
    }
    if (SMD_FABS(w) >= p->w_min && w != SMD_R(0.0)) {
        s->S_ww += a * (w * w - s->S_ww);
        s->S_wy += a * (w * y.im - s->S_wy);
        s->S_wi += a * (w * i_m.im - s->S_wi);
    }
}

/* A sample that does not count forgets as one that does (with an
 * observer's angle, whose band leaves out about half of them: the
 * forgetting's time constant stays tau, the weight sum W says how much
 * counted) */
RLS_OUT_OF_LINE static void forget(const smd_rls_params *p, smd_rls_state *s)
{
    const smd_real f = SMD_R(1.0) - p->alpha;
    s->Wt += p->alpha * (SMD_R(1.0) - s->Wt);
    s->W *= f;
    s->M_i *= f;
    s->M_y *= f;
    s->S_ii *= f;
    s->S_iy *= f;
    s->S_yy *= f;
    s->M_z *= f;
    s->S_zy *= f;
    s->S_zi *= f;
    s->S_ww *= f;
    s->S_wy *= f;
    s->S_wi *= f;
}

/* R_s from the d-axis line once it has about 0.7 tau of data and the
 * injection's variance (i_inj^2 for the square wave) at least a quarter of
 * it; psi_r from the q axis with that R_s. */
RLS_OUT_OF_LINE static void solve(const smd_rls_params *p, smd_rls_state *s)
{
    const smd_real den = s->W * s->S_ii - s->M_i * s->M_i;
    const smd_real need = SMD_R(0.25) * p->i_inj * p->i_inj * s->W * s->W;
    if ((p->observer ? s->Wt : s->W) >= SMD_R(0.5) && den >= need) {
        /* the line's slope, and its standard error: residual variance
         * var(y) - R cov(i, y) over n = 2 / alpha samples and var(i) */
        const smd_real cov = s->W * s->S_iy - s->M_i * s->M_y;
        smd_real R = cov / den;
        smd_real res = (s->W * s->S_yy - s->M_y * s->M_y) - R * cov;
        smd_real se2 = (res > SMD_R(0.0) ? res : SMD_R(0.0)) * SMD_R(0.5) * p->alpha / den;
        int fits = 1;
        if (p->observer) {
            /* the instrument's slope cov(z, y) / cov(z, i), and its standard
             * error: var(y - R i) var(z) / cov(z, i)^2 over n (the header) */
            const smd_real cz = s->W * s->S_zi - s->M_z * s->M_i;
            const smd_real vz = s->W * s->W * p->i_inj * p->i_inj - s->M_z * s->M_z;
            R = (s->W * s->S_zy - s->M_z * s->M_y) / cz;
            res = (s->W * s->S_yy - s->M_y * s->M_y) - SMD_R(2.0) * R * cov + R * R * den;
            se2 = (res > SMD_R(0.0) ? res : SMD_R(0.0)) * vz * SMD_R(0.5) * p->alpha /
                  (cz * cz * s->W); /* (n = 2 W / alpha samples counted) */
            fits = cz >= need; /* (the current follows the square wave) */
        }
        if (fits && isfinite(R) && isfinite(se2)) {
            s->R_se = SMD_SQRT(se2);
            /* the slope corrected for where the current is sampled
             * (smd_rls_set_dead_time) */
            const smd_real k = R * p->k_td;
            const smd_real Rc = (k > SMD_R(0.0) && k <= SMD_R(0.1)) ? R / (SMD_R(1.0) - k) : R;
            if (se2 <= SMD_R(0.0625) * R * R && Rc >= p->R_lo && Rc <= p->R_hi) {
                s->R_hat = Rc;
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
    if (p->observer) {
        if (!ok) {
            s->n_per = s->n_dev = 0;
        } else {
            ok = frame(p, s, theta_k, w_k);
            theta_k = s->th_f;
            w_k = s->w_f;
        }
    }
    int counted = 0;
    if (ok && s->have_prev && (!p->observer || s->k_half >= SMD_RLS_SKIP) &&
        (p->i_band <= SMD_R(0.0) || (clear_of_zero(i_ab, p->i_band) &&
                                     clear_of_zero(s->i_prev, p->i_band)))) {
        /* the interval [k-1, k): its middle, its mean current, eq. (1) */
        const smd_cplx r = smd_cconj(smd_cexpj(theta_k - SMD_R(0.5) * w_k * T));
        const smd_cplx di = smd_cscale(smd_csub(i_ab, s->i_prev), p->L_s_hat / T);
        const smd_cplx i_m = smd_cmul(smd_cscale(smd_cadd(i_ab, s->i_prev), SMD_R(0.5)), r);
        const smd_cplx y = smd_cmul(smd_csub(s->u_prev, di), r);
        if (smd_cnf(y) + smd_cnf(i_m) == SMD_R(0.0)) {
            update(p, s, y, i_m, w_k);
            solve(p, s);
            counted = 1;
        } else {
            ok = 0;
        }
    }
    if (p->observer && ok && !counted) {
        forget(p, s);
    }
    s->have_prev = ok && u_ok;
    s->i_prev = i_ab;
    s->u_prev = u_next;
    s->z_sgn = s->sgn;
    if (++s->k_half >= p->n_half) {
        s->k_half = 0;
        s->sgn = -s->sgn;
    }
}

int smd_rls_edge(const smd_rls_state *s)
{
    return s->k_half < SMD_RLS_SKIP;
}

int smd_rls_stale(const smd_rls_params *p, const smd_rls_state *s)
{
    return s->age > p->n_stale;
}

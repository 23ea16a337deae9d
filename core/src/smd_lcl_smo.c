#include "smodrive/smd_lcl_smo.h"

#include "smodrive/smd_transforms.h"

smd_status smd_lcl_smo_init(smd_lcl_smo_params *p, smd_real T_sp, const smd_lcl_smo_config *c)
{
    if (p == 0 || c == 0 || c->table == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_pos_range(T_sp, SMD_R(1.0))) {
        return SMD_ERR_TS;
    }
    if (c->law < SMD_LCL_SMO_PROPOSED || c->law > SMD_LCL_SMO_TDE18) {
        return SMD_ERR_MODE;
    }
    if (c->n < 2 || !smd_in_range(c->w_min, SMD_R(-1e7), SMD_R(1e7)) ||
        !smd_in_pos_range(c->dw, SMD_R(1e7))) {
        return SMD_ERR_TABLE;
    }
    /* Q must be convergent (eigenvalues inside the unit circle), eq. (33) */
    if (!smd_in_range(c->Q1, SMD_R(-0.999), SMD_R(0.999)) ||
        !smd_in_range(c->Q2, SMD_R(-0.999), SMD_R(0.999))) {
        return SMD_ERR_STABILITY;
    }
    if (!smd_in_pos_range(c->bw_rel2, SMD_R(2.0)) || !smd_in_pos_range(c->bw_rel3, SMD_R(2.0)) ||
        !smd_in_range(c->w_bp_min, SMD_R(0.0), SMD_R(1e7))) {
        return SMD_ERR_LIMIT;
    }
    if (c->decimation < 0 || c->decimation > 64) {
        return SMD_ERR_DECIMATION;
    }
    p->T_sp = T_sp;
    p->law = c->law;
    p->table = c->table;
    p->n = c->n;
    p->w_min = c->w_min;
    p->dw = c->dw;
    p->Q1 = c->Q1;
    p->Q2 = c->Q2;
    p->bw_rel2 = c->bw_rel2;
    p->bw_rel3 = c->bw_rel3;
    p->w_bp_min = c->w_bp_min;
    p->decimation = c->decimation < 1 ? 1 : c->decimation;
    return SMD_OK;
}

void smd_lcl_smo_reset(smd_lcl_smo_state *s, smd_real theta0)
{
    int k;
    for (k = 0; k < 6; k++) {
        s->x_hat[k] = SMD_R(0.0);
    }
    for (k = 0; k < 4; k++) {
        s->y[k] = SMD_R(0.0);
    }
    for (k = 0; k < 2; k++) {
        s->x_c[k] = s->s[k] = s->s_prev[k] = s->w_att[k] = s->v_prev[k] = SMD_R(0.0);
        s->D1[k] = s->D2[k] = s->e_hat[k] = s->d_hat[k] = SMD_R(0.0);
    }
    for (k = 0; k < SMD_LCL_SMO_DELAY; k++) {
        s->v_hist[k] = smd_c(SMD_R(0.0), SMD_R(0.0));
    }
    s->v_head = 0;
    s->theta_prev = theta0;
    smd_bandpass_reset(&s->bp2);
    smd_bandpass_reset(&s->bp3);
    s->primed = 0;
    for (k = 0; k < (int)(sizeof(smd_lcl_model) / sizeof(smd_real)); k++) {
        ((smd_real *)&s->m)[k] = SMD_R(0.0); /* (recomputed before its first use) */
    }
    s->taps2.a = s->taps2.b = s->taps3.a = s->taps3.b = SMD_R(0.0);
    s->taps2.n = s->taps3.n = 0;
    s->taps2.ok = s->taps3.ok = 0;
    s->age = 0;
    s->w_m = SMD_R(0.0);
    s->m_ok = 0;
    s->defer = 0;
}

void smd_lcl_smo_model(const smd_lcl_smo_params *p, smd_real w, smd_lcl_model *m)
{
    smd_table_interp((const smd_real *)p->table, (int)(sizeof(smd_lcl_model) / sizeof(smd_real)),
                     p->n, p->w_min, p->dw, w, (smd_real *)m);
}

/* y = M x for a 2x2 row-major M */
static void mv2(const smd_real M[4], const smd_real x[2], smd_real y[2])
{
    y[0] = M[0] * x[0] + M[1] * x[1];
    y[1] = M[2] * x[0] + M[3] * x[1];
}

/* One harmonic channel of eq. (35): band-pass at h |w| of v delayed by N - 1
 * samples, N = 2 pi / (h |w| T) the samples per harmonic period (fractional
 * in general), read from the delay line with a two-tap interpolation exact
 * for a sinusoid of W rad/sample: v(k - D) = a v(k - n) + b v(k - n - 1),
 * n = floor(D), a = sin(W (1 - f)) / sin W, b = sin(W f) / sin W, f = D - n.
 * The band-pass coefficients (SMD_HARM_BP) and the taps (SMD_HARM_TAPS) are
 * recomputed as `what` says (both every sample unless the config decimates;
 * a decimation of 8 or more does each on its own sample) and kept in *bp,
 * *tap between. Returns 0 when the delay does not fit the line. */
#define SMD_HARM_BP 1
#define SMD_HARM_TAPS 2
/* The refresh of one channel (what: SMD_HARM_BP, SMD_HARM_TAPS); 0 (and
 * tap->ok = 0) when the delay does not fit the line. */
#if defined(__GNUC__)
__attribute__((always_inline)) /* (in the step as before the prime shared it) */
#endif
static inline int harm_refresh(const smd_lcl_smo_params *p, smd_bandpass *bp,
                               smd_lcl_smo_taps *tap, smd_real h, smd_real bw, smd_real w_abs,
                               int what)
{
    smd_real W = h * w_abs * p->T_sp;
    smd_real D, f, sw;
    if (!(W < SMD_R(0.95) * SMD_PI)) {
        tap->ok = 0;
        return 0;
    }
    D = SMD_TWO_PI / W - SMD_R(1.0);
    if (!(D < (smd_real)(SMD_LCL_SMO_DELAY - 2)) || D < SMD_R(0.0)) {
        tap->ok = 0;
        return 0;
    }
    if ((what & SMD_HARM_BP) && smd_bandpass_set(bp, h * w_abs, bw, p->T_sp) != SMD_OK) {
        tap->ok = 0;
        return 0;
    }
    if (what & SMD_HARM_TAPS) {
        tap->n = (int)D;
        f = D - (smd_real)tap->n;
        sw = SMD_SIN(W);
        tap->a = SMD_SIN(W * (SMD_R(1.0) - f)) / sw;
        tap->b = SMD_SIN(W * f) / sw;
        tap->ok = 1;
    }
    return 1;
}

static smd_cplx harmonic(const smd_lcl_smo_params *p, smd_lcl_smo_state *s, smd_bandpass *bp,
                         smd_lcl_smo_taps *tap, smd_real h, smd_real bw, smd_real w_abs,
                         int what)
{
    int i0, i1;
    if (what && !harm_refresh(p, bp, tap, h, bw, w_abs, what)) {
        return smd_c(SMD_R(0.0), SMD_R(0.0));
    }
    if (!tap->ok) {
        return smd_c(SMD_R(0.0), SMD_R(0.0));
    }
    /* (non-negative operands: the remainder of the unsigned value, a mask
     * for the power-of-two line) */
    i0 = (int)((unsigned)(s->v_head - tap->n + 2 * SMD_LCL_SMO_DELAY) %
               (unsigned)SMD_LCL_SMO_DELAY);
    i1 = (int)((unsigned)(i0 - 1 + SMD_LCL_SMO_DELAY) % (unsigned)SMD_LCL_SMO_DELAY);
    return smd_bandpass_step(bp, smd_cadd(smd_cscale(s->v_hist[i0], tap->a),
                                          smd_cscale(s->v_hist[i1], tap->b)));
}

void smd_lcl_smo_prime(const smd_lcl_smo_params *p, smd_lcl_smo_state *s, smd_real w_hat)
{
    const smd_real w_abs = SMD_FABS(w_hat);
    if (p == 0 || s == 0 || p->table == 0 || !isfinite(w_hat)) {
        return; /* (the first step refreshes everything, as without it) */
    }
    smd_lcl_smo_model(p, w_hat, &s->m);
    s->m_ok = 1;
    s->w_m = w_hat;
    if (p->law == SMD_LCL_SMO_PROPOSED && w_abs > p->w_bp_min) {
        (void)harm_refresh(p, &s->bp2, &s->taps2, SMD_R(2.0), p->bw_rel2 * w_abs, w_abs,
                           SMD_HARM_BP | SMD_HARM_TAPS);
        (void)harm_refresh(p, &s->bp3, &s->taps3, SMD_R(3.0), p->bw_rel3 * w_abs, w_abs,
                           SMD_HARM_BP | SMD_HARM_TAPS);
    }
}

void smd_lcl_smo_reframe(smd_lcl_smo_state *s, smd_real dth)
{
    smd_cplx r = smd_cexpj_small(-dth);
    int i;
    smd_cplx e;
    for (i = 0; i < 3; i++) {
        smd_cplx z = smd_cmul(smd_c(s->x_hat[2 * i], s->x_hat[2 * i + 1]), r);
        s->x_hat[2 * i] = z.re;
        s->x_hat[2 * i + 1] = z.im;
    }
    e = smd_cmul(smd_c(s->e_hat[0], s->e_hat[1]), r);
    s->e_hat[0] = e.re;
    s->e_hat[1] = e.im;
}

/* (m restrict: the state's own model, which neither writes, so that the
 * state's writes do not make the compiler load the model again) */
static void reach(const smd_lcl_smo_params *p, smd_lcl_smo_state *s,
                  const smd_lcl_model *restrict mp, smd_cplx i1, smd_cplx i2, smd_real w_hat,
                  int refresh);
static void predict(const smd_lcl_model *restrict m, smd_lcl_smo_state *s, smd_cplx u);

/* what to refresh: each harmonic channel's band-pass coefficients and taps
 * (SMD_HARM_BP, SMD_HARM_TAPS), the 2 f_e channel's in bits 0-1, the 3 f_e
 * channel's in bits 2-3 */
#define SMD_REFRESH_H2 (SMD_HARM_BP | SMD_HARM_TAPS)
#define SMD_REFRESH_H3 ((SMD_HARM_BP | SMD_HARM_TAPS) << 2)

void smd_lcl_smo_reach(const smd_lcl_smo_params *p, smd_lcl_smo_state *s,
                       const smd_lcl_model *mp, smd_cplx i1, smd_cplx i2, smd_real w_hat)
{
    reach(p, s, mp, i1, i2, w_hat, SMD_REFRESH_H2 | SMD_REFRESH_H3);
}

/* smd_lcl_smo_reach, the harmonic channels whose bit `refresh` holds
 * refreshed */
static void reach(const smd_lcl_smo_params *p, smd_lcl_smo_state *s,
                  const smd_lcl_model *restrict mp, smd_cplx i1, smd_cplx i2, smd_real w_hat,
                  int refresh)
{
    const smd_lcl_model *m = mp;
    smd_real err[4], t1[2], t2[2], t3[2], D0[2], Qs[2];
    smd_real *y = s->y;
    smd_real w_abs = SMD_FABS(w_hat);
    int i, j;

    if (!s->primed) {
        /* start the current estimates at the first sample */
        s->x_hat[2] = i1.re;
        s->x_hat[3] = i1.im;
        s->x_hat[4] = i2.re;
        s->x_hat[5] = i2.im;
        s->primed = 1;
    }
    /* estimation error of the measured states, eq. (12), and the outputs of
     * the canonical form, eq. (13)-(15) */
    err[0] = s->x_hat[2] - i1.re;
    err[1] = s->x_hat[3] - i1.im;
    err[2] = s->x_hat[4] - i2.re;
    err[3] = s->x_hat[5] - i2.im;
    for (i = 0; i < 4; i++) {
        y[i] = SMD_R(0.0);
        for (j = 0; j < 4; j++) {
            y[i] += m->Ft[4 * i + j] * err[j];
        }
    }
    /* switching function, eq. (18) */
    mv2(m->Gam_c, s->x_c, t1);
    mv2(m->Gam_1, &y[0], t2);
    mv2(m->Gam_2, &y[2], t3);
    s->s[0] = t1[0] + t2[0] + t3[0];
    s->s[1] = t1[1] + t2[1] + t3[1];
    /* s(k) - Q s(k-1), and the lumped disturbance of the reaching mode one
     * sample back, D(k-1) = s(k) - Q s(k-1) - v(k-1) (eq. (30) with the
     * equivalent control below) */
    Qs[0] = s->s[0] - p->Q1 * s->s_prev[0];
    Qs[1] = s->s[1] - p->Q2 * s->s_prev[1];
    D0[0] = Qs[0] - s->v_prev[0];
    D0[1] = Qs[1] - s->v_prev[1];

    /* (-Gs + Q) s(k) minus the equivalent-control terms built from the known
     * x_c, y1 and the reduced-order estimate x_u_hat = x_c - L y1 of (23):
     * without them the state coupling G_c x_c + G_y y1 + G_u x_u that eq. (29)
     * lumps into d(k) makes the observer unstable (docs/yao2022_design.md) */
    mv2(m->Gs, s->s, t2);
    t2[0] = -t2[0] + p->Q1 * s->s[0];
    t2[1] = -t2[1] + p->Q2 * s->s[1];
    mv2(m->Kc, s->x_c, t1);
    mv2(m->Ky, &y[0], t3);
    t2[0] -= t1[0] + t3[0];
    t2[1] -= t1[1] + t3[1];
    if (p->law == SMD_LCL_SMO_PROPOSED) {
        smd_cplx v = smd_c(Qs[0] + s->d_hat[0], Qs[1] + s->d_hat[1]);
        smd_cplx d = smd_c(SMD_R(0.0), SMD_R(0.0));
        s->v_head = (int)((unsigned)(s->v_head + 1) % (unsigned)SMD_LCL_SMO_DELAY);
        s->v_hist[s->v_head] = v;
        /* eq. (34) with the sign that converges: s(k) - Q s(k-1) is
         * e_hat(k-1) - e(k-1) + (d - d_hat), so e_hat must move against it
         * (docs/yao2022_design.md, erratum 5) */
        s->e_hat[0] -= m->k * Qs[0];
        s->e_hat[1] -= m->k * Qs[1];
        /* eq. (35): periodic disturbance at 2 f_e and 3 f_e */
        if (w_abs > p->w_bp_min) {
            d = smd_cadd(harmonic(p, s, &s->bp2, &s->taps2, SMD_R(2.0), p->bw_rel2 * w_abs,
                                  w_abs, s->taps2.ok ? (refresh & SMD_REFRESH_H2)
                                                     : (SMD_HARM_BP | SMD_HARM_TAPS)),
                         harmonic(p, s, &s->bp3, &s->taps3, SMD_R(3.0), p->bw_rel3 * w_abs,
                                  w_abs, s->taps3.ok ? (refresh & SMD_REFRESH_H3) >> 2
                                                     : (SMD_HARM_BP | SMD_HARM_TAPS)));
        } else {
            smd_bandpass_reset(&s->bp2);
            smd_bandpass_reset(&s->bp3);
            s->taps2.ok = s->taps3.ok = 0;
        }
        s->d_hat[0] = d.re;
        s->d_hat[1] = d.im;
        /* eq. (33): v = e_hat - d_hat */
        s->v_prev[0] = s->e_hat[0] - s->d_hat[0];
        s->v_prev[1] = s->e_hat[1] - s->d_hat[1];
    } else {
        /* time-delay estimation: [17] compensates D(k) by D(k-1), eq. (31),
         * (61)-(62) (with the sign of the increment that makes s converge);
         * [18] by 2 D(k-1) - D(k-2), eq. (32). The EMF is the low-pass (63)
         * of the compensation (which carries -D = e - d). */
        smd_real c0 = D0[0], c1 = D0[1];
        if (p->law == SMD_LCL_SMO_TDE18) {
            c0 = SMD_R(2.0) * D0[0] - s->D1[0];
            c1 = SMD_R(2.0) * D0[1] - s->D1[1];
        }
        s->v_prev[0] = -c0;
        s->v_prev[1] = -c1;
        s->e_hat[0] += m->k * (s->v_prev[0] - s->e_hat[0]);
        s->e_hat[1] += m->k * (s->v_prev[1] - s->e_hat[1]);
    }
    s->w_att[0] = t2[0] + s->v_prev[0];
    s->w_att[1] = t2[1] + s->v_prev[1];
    s->D2[0] = s->D1[0];
    s->D2[1] = s->D1[1];
    s->D1[0] = D0[0];
    s->D1[1] = D0[1];

}

void smd_lcl_smo_predict(const smd_lcl_model *m, smd_lcl_smo_state *s, smd_cplx u)
{
    predict(m, s, u);
}

static void predict(const smd_lcl_model *restrict m, smd_lcl_smo_state *s, smd_cplx u)
{
    smd_real x_next[6], t1[2], t2[2], t3[2];
    int i, j;
    /* observer, eq. (9): x(k+1) = G x + H u + F w */
    for (i = 0; i < 6; i++) {
        smd_real acc = m->H[2 * i] * u.re + m->H[2 * i + 1] * u.im;
        acc += m->F[2 * i] * s->w_att[0] + m->F[2 * i + 1] * s->w_att[1];
        for (j = 0; j < 6; j++) {
            acc += m->G[6 * i + j] * s->x_hat[j];
        }
        x_next[i] = acc;
    }
    for (i = 0; i < 6; i++) {
        s->x_hat[i] = x_next[i];
    }
    /* augmented state, eq. (16) */
    mv2(m->Hc, s->x_c, t1);
    mv2(m->D1, &s->y[0], t2);
    mv2(m->D2, &s->y[2], t3);
    s->x_c[0] = t1[0] + t2[0] + t3[0];
    s->x_c[1] = t1[1] + t2[1] + t3[1];
    s->s_prev[0] = s->s[0];
    s->s_prev[1] = s->s[1];
}

smd_status smd_lcl_smo_step(const smd_lcl_smo_params *p, smd_lcl_smo_state *s, smd_cplx i1_ab,
                            smd_cplx i2_ab, smd_cplx u_ab, smd_real theta_hat, smd_real w_hat)
{
    /* e^{-j theta_hat} once for the three Park transforms (the bits of
     * smd_ab_to_dq, which would take it three times) */
    return smd_lcl_smo_step_r(p, s, i1_ab, i2_ab, u_ab, smd_cconj(smd_cexpj(theta_hat)),
                              theta_hat, w_hat);
}

/* Every estimate finite (a sum of x - x, smd_nf: 0 exactly then), else the
 * observer reset. */
static inline smd_status lcl_smo_finite(smd_lcl_smo_state *s, smd_real theta_hat)
{
    smd_real fin = smd_nf(s->e_hat[0]) + smd_nf(s->e_hat[1]) + smd_nf(s->x_c[0]) +
                   smd_nf(s->x_c[1]);
    int i;
    for (i = 0; i < 6; i++) {
        fin += smd_nf(s->x_hat[i]);
    }
    if (fin != SMD_R(0.0)) {
        smd_lcl_smo_reset(s, theta_hat);
        return SMD_ERR_NONFINITE;
    }
    return SMD_OK;
}

smd_status smd_lcl_smo_step_r(const smd_lcl_smo_params *p, smd_lcl_smo_state *s,
                              smd_cplx i1_ab, smd_cplx i2_ab, smd_cplx u_ab, smd_cplx r,
                              smd_real theta_hat, smd_real w_hat)
{
    const int age = s->age;
    int refresh = 0;
    if (p->decimation < 4 || !s->m_ok) {
        /* everything at once, every decimation-th sample (every sample: the
         * method as published) */
        if (age == 0 || !s->m_ok) {
            smd_lcl_smo_model(p, w_hat, &s->m);
            refresh = SMD_REFRESH_H2 | SMD_REFRESH_H3;
            s->m_ok = 1;
            s->w_m = w_hat; /* (a spread refresh's second half uses it) */
        }
        s->defer = 0;
        s->age = age + 1 >= p->decimation ? 0 : age + 1;
    } else if (s->defer) {
        /* a held sample: the spread refresh waits a sample (its piece would
         * come on top of the caller's holding), the age stays */
        s->defer = 0;
    } else {
        /* the model in parts at the speed of the first (2 parts for a
         * decimation of 4-5, 4 from 6 on: a worst call of that share of the
         * interpolation), then each channel on its own sample; the parts'
         * bounds are multiples of 4 (smd_table_interp_range: one call's bits) */
        const int nf = (int)(sizeof(smd_lcl_model) / sizeof(smd_real));
        const int parts = p->decimation >= 6 ? 4 : 2;
        if (age < parts) {
            const int step = 112 / parts; /* 28 or 56 */
            const int i0 = age * step, i1 = age == parts - 1 ? nf : i0 + step;
            if (age == 0) {
                s->w_m = w_hat;
            }
            smd_table_interp_range((const smd_real *)p->table, nf, p->n, p->w_min, p->dw, s->w_m,
                                   (smd_real *)&s->m, i0, i1);
        } else if (p->decimation < 8) {
            refresh = age == parts ? SMD_REFRESH_H2 : (age == parts + 1 ? SMD_REFRESH_H3 : 0);
        } else {
            /* from 8 on, each channel's band-pass and taps on samples of
             * their own: four pieces of about a model part's size */
            const int k = age - parts; /* 0-3: H2's band-pass, H2's taps, H3's, H3's */
            refresh = k < 4 ? ((k & 1) ? SMD_HARM_TAPS : SMD_HARM_BP) << (2 * (k >> 1)) : 0;
        }
        s->age = age + 1 >= p->decimation ? 0 : age + 1;
    }
    reach(p, s, &s->m, smd_cmul(i1_ab, r), smd_cmul(i2_ab, r), w_hat, refresh);
    predict(&s->m, s, smd_cmul(u_ab, r));
    s->theta_prev = theta_hat;
    return lcl_smo_finite(s, theta_hat);
}

smd_real smd_lcl_smo_theta_err(const smd_lcl_smo_state *s, smd_real w_hat)
{
    /* eq. (47): e = j w psi e^{j theta_err} in the estimated frame, so
     * e_gamma = -w psi sin, e_delta = w psi cos */
    smd_real sg = w_hat < SMD_R(0.0) ? SMD_R(-1.0) : SMD_R(1.0);
    return SMD_ATAN2(-sg * s->e_hat[0], sg * s->e_hat[1]);
}

#include "smodrive/smd_ident.h"

#include "smodrive/smd_transforms.h"

/* The zero vector (duties 0.5), what every test applies once it ended. */
static void zero_vector(smd_real d_abc[3], smd_cplx *u_applied)
{
    d_abc[0] = d_abc[1] = d_abc[2] = SMD_R(0.5);
    *u_applied = smd_c(SMD_R(0.0), SMD_R(0.0));
}

/* Why a sample ends a test before it starts (0: it does not): a non-finite
 * current or DC link, or a phase current (c = -a - b) beyond `trip`. */
static int input_fault(smd_real i_a, smd_real i_b, smd_real u_dc, smd_real trip)
{
    const smd_real i_c = -i_a - i_b;
    if (!(isfinite(i_a) && isfinite(i_b) && isfinite(u_dc) && u_dc > SMD_R(0.0))) {
        return SMD_IDENT_BAD_INPUT;
    }
    if (SMD_FABS(i_a) > trip || SMD_FABS(i_b) > trip || SMD_FABS(i_c) > trip) {
        return SMD_IDENT_OVERCURRENT;
    }
    return 0;
}

smd_status smd_ident_rs_init(smd_ident_rs_params *p, const smd_ident_rs_config *c)
{
    smd_status st;
    if (p == 0 || c == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_pos_range(c->T_sp, SMD_R(1.0)) || !smd_in_pos_range(c->i_test, SMD_R(1e5)) ||
        !smd_in_pos_range(c->u_max, SMD_R(1e5)) ||
        !smd_in_range(c->t_win, SMD_R(10.0) * c->T_sp, SMD_R(10.0)) ||
        !smd_in_range(c->t_level_max, SMD_R(2.0) * c->t_win, SMD_R(100.0)) ||
        !(c->t_level_max <= SMD_R(1e8) * c->T_sp) || c->levels < 8 ||
        c->levels > SMD_IDENT_MAX_LEVELS) {
        return SMD_ERR_IDENT;
    }
    st = smd_svm_init(&p->svm, SMD_SVM_LIMIT_HEXAGON, SMD_R(0.0));
    if (st != SMD_OK) {
        return st;
    }
    p->i_test = c->i_test;
    p->u_max = c->u_max;
    p->du = c->u_max * SMD_R(0.001);
    p->n_win = (int)(c->t_win / c->T_sp + SMD_R(0.5));
    p->n_level_max = (int)(c->t_level_max / c->T_sp + SMD_R(0.5));
    p->levels = c->levels;
    return SMD_OK;
}

static void new_window(smd_ident_rs_state *s)
{
    s->n = 0;
    s->acc_i = s->acc_i2 = s->acc_u = SMD_R(0.0);
}

void smd_ident_rs_reset(smd_ident_rs_state *s)
{
    int k;
    s->phase = SMD_IDENT_RAMP;
    s->outcome = SMD_IDENT_RUNNING;
    s->u = SMD_R(0.0);
    s->u_lo = s->u_hi = SMD_R(0.0);
    s->u_prev_pt = s->i_prev_pt = s->i_lo = SMD_R(0.0);
    s->u_rise = s->i_rise = s->slope = SMD_R(0.0);
    s->du_cur = SMD_R(0.0);
    s->backoffs = 0;
    s->level = 0;
    s->n_level = 0;
    new_window(s);
    s->prev_i = SMD_R(0.0);
    s->have_prev = 0;
    for (k = 0; k < SMD_IDENT_MAX_LEVELS; k++) {
        s->i_lv[k] = s->u_lv[k] = SMD_R(0.0);
    }
    s->u_applied = smd_c(SMD_R(0.0), SMD_R(0.0));
    s->samples = 0;
    s->R_s = s->u_0 = s->r2 = s->resid = SMD_R(0.0);
}

/* The voltage of level k: from u_lo (i_test / 10) to u_hi (i_test) in
 * equal steps. */
static smd_real level_voltage(const smd_ident_rs_params *p, const smd_ident_rs_state *s, int k)
{
    return s->u_lo + (s->u_hi - s->u_lo) * (smd_real)k / (smd_real)(p->levels - 1);
}

/* The least-squares line u = R i + u_0 through the levels (two passes about
 * the means, for float precision), its R^2 and residual RMS. */
static void fit(const smd_ident_rs_params *p, smd_ident_rs_state *s)
{
    const int n = p->levels;
    smd_real mi = SMD_R(0.0), mu = SMD_R(0.0), sii = SMD_R(0.0), siu = SMD_R(0.0),
             suu = SMD_R(0.0), ss = SMD_R(0.0);
    int k;
    for (k = 0; k < n; k++) {
        mi += s->i_lv[k];
        mu += s->u_lv[k];
    }
    mi /= (smd_real)n;
    mu /= (smd_real)n;
    for (k = 0; k < n; k++) {
        const smd_real di = s->i_lv[k] - mi, du = s->u_lv[k] - mu;
        sii += di * di;
        siu += di * du;
        suu += du * du;
    }
    s->R_s = siu / sii;
    s->u_0 = mu - s->R_s * mi;
    for (k = 0; k < n; k++) {
        const smd_real e = s->u_lv[k] - (s->R_s * s->i_lv[k] + s->u_0);
        ss += e * e;
    }
    s->r2 = suu > SMD_R(0.0) ? SMD_R(1.0) - ss / suu : SMD_R(0.0);
    s->resid = SMD_SQRT(ss / (smd_real)n);
    s->outcome = (isfinite(s->R_s) && s->r2 >= SMD_R(0.999)) ? SMD_IDENT_OK : SMD_IDENT_POOR_FIT;
    s->phase = SMD_IDENT_DONE;
}

static smd_status stop(smd_ident_rs_state *s, int outcome, smd_real d_abc[3])
{
    s->phase = SMD_IDENT_FAILED;
    s->outcome = outcome;
    s->u = SMD_R(0.0);
    zero_vector(d_abc, &s->u_applied);
    return SMD_ERR_FAULT;
}

/* One window of a level: the window's mean current against the last one's;
 * settled when they agree within 0.2 % of i_test plus three standard errors
 * of the difference (the ADC's noise averaged over the window). */
static void level_window(const smd_ident_rs_params *p, smd_ident_rs_state *s)
{
    const smd_real nw = (smd_real)s->n;
    const smd_real mean = s->acc_i / nw;
    smd_real var = s->acc_i2 / nw - mean * mean;
    var = var > SMD_R(0.0) ? var : SMD_R(0.0);
    if (s->have_prev &&
        SMD_FABS(mean - s->prev_i) <=
            SMD_R(0.002) * p->i_test + SMD_R(3.0) * SMD_SQRT(SMD_R(2.0) * var / nw)) {
        s->i_lv[s->level] = mean;
        s->u_lv[s->level] = s->acc_u / nw;
        s->level++;
        s->n_level = 0;
        s->have_prev = 0;
        if (s->level < p->levels) {
            s->u = level_voltage(p, s, s->level);
        }
    } else {
        s->prev_i = mean;
        s->have_prev = 1;
    }
    new_window(s);
}

/* A window of the search: 1 when the current has settled at this voltage
 * (two windows agree as in level_window), its mean in *mean; else the
 * window is kept for the next comparison. */
static int ramp_window(const smd_ident_rs_params *p, smd_ident_rs_state *s, smd_real *mean)
{
    const smd_real nw = (smd_real)s->n;
    const smd_real m = s->acc_i / nw;
    smd_real var = s->acc_i2 / nw - m * m;
    int settled;
    var = var > SMD_R(0.0) ? var : SMD_R(0.0);
    settled = s->have_prev && SMD_FABS(m - s->prev_i) <= SMD_R(0.002) * p->i_test +
                                  SMD_R(3.0) * SMD_SQRT(SMD_R(2.0) * var / nw);
    new_window(s);
    if (!settled) {
        s->prev_i = m;
        s->have_prev = 1;
        return 0;
    }
    *mean = m;
    s->have_prev = 0;
    s->n_level = 0;
    return 1;
}

/* The search's next voltage after a settled point (u, i): steps of du_cur
 * (u_max / 1000 at first, growing by half a step to u_max / 200 while no
 * current flows and nothing was backed off, halved at each back-off) until
 * the current reaches i_test / 10 (the first such point is kept: u_lo, i_lo); from
 * there steps of a quarter of i_test at the slope of the last two points,
 * at most four times the last step, at least u_max / 1e5. */
static smd_real next_voltage(const smd_ident_rs_params *p, smd_ident_rs_state *s, smd_real i,
                             smd_real u_lim)
{
    smd_real step = s->du_cur;
    if (i < SMD_R(0.02) * p->i_test && s->backoffs == 0) {
        /* no current yet (the inverter's drop, or no motor): the step grows
         * by half each time, to u_max / 200 */
        s->du_cur = SMD_R(1.5) * s->du_cur < SMD_R(5.0) * p->du ? SMD_R(1.5) * s->du_cur
                                                                : SMD_R(5.0) * p->du;
    } else if (i >= SMD_R(0.1) * p->i_test) {
        if (s->u_lo == SMD_R(0.0)) {
            s->u_lo = s->u;
            s->i_lo = i;
        }
        if (s->i_rise == SMD_R(0.0) || i - s->i_rise > SMD_R(0.01) * p->i_test) {
            s->u_rise = s->u; /* (the current follows the voltage: sensor_stalled) */
            s->i_rise = i;
        }
        if (s->i_prev_pt >= SMD_R(0.1) * p->i_test &&
            i - s->i_prev_pt > SMD_R(0.01) * p->i_test) {
            const smd_real slope = (s->u - s->u_prev_pt) / (i - s->i_prev_pt);
            const smd_real last = s->u - s->u_prev_pt;
            s->slope = (s->slope > SMD_R(0.0) && s->slope < slope) ? s->slope : slope;
            step = slope * SMD_R(0.25) * p->i_test;
            step = step < SMD_R(4.0) * last ? step : SMD_R(4.0) * last;
        }
        step = step > SMD_R(0.01) * p->du ? step : SMD_R(0.01) * p->du;
    }
    s->u_prev_pt = s->u;
    s->i_prev_pt = i;
    return s->u + step < u_lim ? s->u + step : u_lim;
}

/* Whether the measured current stopped following the voltage, past
 * i_test / 10 where the stator is a line (u = R_s i + u_0, the drop
 * constant): a step of the voltage that should have added over 2 % of i_test
 * added under half of what it should, or the voltage rose by what half of
 * i_test takes above the last point whose current rose by 1 % of i_test, and
 * the current did not. "Should" at the smallest slope the search measured
 * (R_s or more: a clipped reading's slope is larger, and takes the search's
 * steps up with it), or the secant u / i of the first point before one (at
 * least R_s, the drop being >= 0). A clipped sensor's reading stays at its
 * full scale while the true current follows the voltage. */
static int sensor_stalled(const smd_ident_rs_params *p, const smd_ident_rs_state *s,
                          smd_real i)
{
    smd_real r, du;
    if (s->i_rise <= SMD_R(0.0)) {
        return 0;
    }
    r = s->slope > SMD_R(0.0) ? s->slope : s->u_rise / s->i_rise;
    du = s->u - s->u_prev_pt;
    if (s->i_prev_pt >= SMD_R(0.1) * p->i_test && du > SMD_R(0.02) * r * p->i_test &&
        i - s->i_prev_pt < SMD_R(0.5) * du / r) {
        return 1;
    }
    return i - s->i_rise <= SMD_R(0.01) * p->i_test &&
           s->u - s->u_rise > SMD_R(0.5) * r * p->i_test;
}

/* The end of the search at (u_hi, i_hi), with a point (u_lo, i_lo) between
 * i_test / 10 and i_test: the staircase from the voltage the line through
 * the two gives for i_test / 10 (u_lo itself when they are too close for a
 * slope) up to u_hi. */
static void begin_levels(const smd_ident_rs_params *p, smd_ident_rs_state *s, smd_real i_hi)
{
    s->u_hi = s->u;
    if (s->u_lo > SMD_R(0.0) && i_hi - s->i_lo > SMD_R(0.2) * p->i_test) {
        const smd_real slope = (s->u_hi - s->u_lo) / (i_hi - s->i_lo);
        const smd_real u = s->u_hi - slope * (i_hi - SMD_R(0.1) * p->i_test);
        s->u_lo = u > SMD_R(0.0) ? u : s->u_lo;
    }
    s->phase = SMD_IDENT_LEVEL;
    s->level = 0;
    s->n_level = 0;
    s->have_prev = 0;
    new_window(s);
    s->u = level_voltage(p, s, 0);
}

smd_status smd_ident_rs_step(const smd_ident_rs_params *p, smd_ident_rs_state *s, smd_real i_a,
                             smd_real i_b, smd_real u_dc, smd_real d_abc[3])
{
    const smd_real i = i_a; /* alpha = a (amplitude-invariant Clarke) */
    smd_real u_lim;
    int bad;
    if (s->phase == SMD_IDENT_DONE || s->phase == SMD_IDENT_FAILED) {
        zero_vector(d_abc, &s->u_applied);
        return s->phase == SMD_IDENT_DONE ? SMD_OK : SMD_ERR_FAULT;
    }
    bad = input_fault(i_a, i_b, u_dc, SMD_R(1.5) * p->i_test);
    if (bad) {
        return stop(s, bad, d_abc);
    }
    s->samples++;
    /* the alpha axis's reach: 2/3 u_dc along a phase, 0.95 of it */
    u_lim = SMD_R(0.95) * SMD_R(2.0) / SMD_R(3.0) * u_dc;
    u_lim = u_lim < p->u_max ? u_lim : p->u_max;
    if (s->phase == SMD_IDENT_RAMP) {
        /* the search: a voltage held until the current settles (the same
         * windows as a level), then the next one */
        if (s->du_cur == SMD_R(0.0)) {
            s->du_cur = p->du;
        }
        if (i > SMD_R(1.2) * p->i_test && s->n > 0 && i * (smd_real)s->n > s->acc_i) {
            /* beyond i_test by a fifth and still rising (above the window's
             * mean so far) while settling: back off to half the last step,
             * and smaller steps from there (a low R_s, whose current a step
             * of du takes beyond the trip). Once: a current that falls after
             * the cut is not cut again (backing off on every sample of its
             * decay, 11 times on a 20 mohm stator behind an 8 V drop, left a
             * step of 1 mV and a search of 7 s through the drop) */
            s->u = s->u_prev_pt + SMD_R(0.5) * (s->u - s->u_prev_pt);
            s->du_cur *= SMD_R(0.5);
            s->have_prev = 0;
            new_window(s);
            if (++s->backoffs > 40) {
                return stop(s, SMD_IDENT_OVERCURRENT, d_abc);
            }
        }
        s->acc_i += i;
        s->acc_i2 += i * i;
        s->n++;
        s->n_level++;
        if (s->n >= p->n_win) {
            smd_real mean;
            if (ramp_window(p, s, &mean)) {
                if (mean >= p->i_test && s->u_lo > SMD_R(0.0)) {
                    begin_levels(p, s, mean);
                } else if (mean >= p->i_test) {
                    /* past i_test with no point between i_test / 10 and
                     * i_test yet: back to half the last step, smaller steps */
                    s->u = s->u_prev_pt + SMD_R(0.5) * (s->u - s->u_prev_pt);
                    s->du_cur *= SMD_R(0.5);
                    if (++s->backoffs > 40) {
                        return stop(s, SMD_IDENT_OVERCURRENT, d_abc);
                    }
                } else if (sensor_stalled(p, s, mean)) {
                    return stop(s, SMD_IDENT_SENSOR_RANGE, d_abc);
                } else if (s->u >= u_lim) {
                    return stop(s, SMD_IDENT_NO_CURRENT, d_abc);
                } else {
                    s->u = next_voltage(p, s, mean, u_lim);
                }
            }
        }
        if (s->n_level > p->n_level_max) {
            return stop(s, SMD_IDENT_NOT_SETTLED, d_abc);
        }
    } else {
        /* the sample measures the voltage applied over the last period */
        s->acc_i += i;
        s->acc_i2 += i * i;
        s->acc_u += s->u_applied.re;
        s->n++;
        s->n_level++;
        if (s->n >= p->n_win) {
            level_window(p, s);
            if (s->level >= p->levels) {
                fit(p, s);
                zero_vector(d_abc, &s->u_applied);
                return SMD_OK;
            }
        }
        if (s->n_level > p->n_level_max) {
            return stop(s, SMD_IDENT_NOT_SETTLED, d_abc);
        }
    }
    smd_svm_step(&p->svm, smd_c(s->u, SMD_R(0.0)), u_dc, d_abc, &s->u_applied);
    return SMD_OK;
}

/* ---- step 2: the inductance (smd_ident.h) ---- */

smd_status smd_ident_ls_init(smd_ident_ls_params *p, const smd_ident_ls_config *c)
{
    smd_status st;
    if (p == 0 || c == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_pos_range(c->T_sp, SMD_R(1.0)) || !smd_in_range(c->R_s, SMD_R(0.0), SMD_R(1e3)) ||
        !smd_in_range(c->u_0, SMD_R(0.0), SMD_R(1e4)) ||
        !smd_in_pos_range(c->i_bias, SMD_R(1e5)) || !smd_in_pos_range(c->u_max, SMD_R(1e5)) ||
        !smd_in_range(c->t_win, SMD_R(10.0) * c->T_sp, SMD_R(10.0)) ||
        !(c->t_win <= SMD_R(1e7) * c->T_sp) || (c->axis != 0 && c->axis != 1) ||
        c->n_half < 4 || c->n_half > SMD_IDENT_MAX_HALF || c->periods < 10 || c->periods > 100000) {
        return SMD_ERR_IDENT;
    }
    st = smd_svm_init(&p->svm, SMD_SVM_LIMIT_HEXAGON, SMD_R(0.0));
    if (st != SMD_OK) {
        return st;
    }
    p->T_sp = c->T_sp;
    p->R_s = c->R_s;
    p->u_0 = c->u_0;
    p->i_bias = c->i_bias;
    p->u_max = c->u_max;
    p->n_win = (int)(c->t_win / c->T_sp + SMD_R(0.5));
    p->axis = c->axis;
    p->n_half = c->n_half;
    p->periods = c->periods;
    return SMD_OK;
}

static void ls_clear_slopes(smd_ident_ls_state *s)
{
    int h;
    for (h = 0; h < 2; h++) {
        s->sj_i[h] = s->s_i[h] = s->slope_sum[h] = SMD_R(0.0);
        s->halves[h] = 0;
    }
    for (h = 0; h < SMD_IDENT_MAX_PERIOD; h++) {
        s->acc_w[h] = SMD_R(0.0);
    }
    s->period = 0;
}

/* ln(1/a) for a in (0, 1): 2 atanh((1 - a) / (1 + a)) by its series (the
 * core has no log hook; once, at the end of the test) */
static smd_real ln_inv(smd_real a)
{
    const smd_real z = (SMD_R(1.0) - a) / (SMD_R(1.0) + a), z2 = z * z;
    smd_real term = z, sum = SMD_R(0.0);
    int k;
    for (k = 1; k < 400 && term > SMD_R(1e-9) * sum; k += 2) {
        sum += term / (smd_real)k;
        term *= z2;
    }
    return SMD_R(2.0) * sum;
}

/* The fit of w(k+1) = a w(k) + b v(k-1) + c over the averaged period (the
 * waveform about its mean, for float precision), then L and R (smd_ident.h);
 * 0 when the fit is singular or a is not in (0, 1). */
static int ls_fit(const smd_ident_ls_params *p, smd_ident_ls_state *s)
{
    const int n2 = 2 * p->n_half;
    const smd_real per = (smd_real)s->period;
    smd_real mean = SMD_R(0.0), A[3][3] = {{0}}, y[3] = {0}, det, a, b;
    int k, r, c;
    for (k = 0; k < n2; k++) {
        mean += s->acc_w[k] / per;
    }
    mean /= (smd_real)n2;
    for (k = 0; k < n2; k++) {
        const smd_real w0 = s->acc_w[k] / per - mean;
        const smd_real w1 = s->acc_w[(k + 1) % n2] / per - mean;
        const int kv = (k + n2 - 1) % n2;
        const smd_real x[3] = {w0, kv < p->n_half ? s->du : -s->du, SMD_R(1.0)};
        for (r = 0; r < 3; r++) {
            for (c = 0; c < 3; c++) {
                A[r][c] += x[r] * x[c];
            }
            y[r] += x[r] * w1;
        }
    }
    det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
          A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
          A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
    if (!(SMD_FABS(det) > SMD_R(0.0))) {
        return 0;
    }
    /* Cramer's rule for a and b */
    a = (y[0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
         A[0][1] * (y[1] * A[2][2] - A[1][2] * y[2]) +
         A[0][2] * (y[1] * A[2][1] - A[1][1] * y[2])) / det;
    b = (A[0][0] * (y[1] * A[2][2] - A[1][2] * y[2]) -
         y[0] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
         A[0][2] * (A[1][0] * y[2] - y[1] * A[2][0])) / det;
    if (!(a > SMD_R(0.0) && a < SMD_R(1.0) && b > SMD_R(0.0))) {
        return 0;
    }
    s->L = p->T_sp * (SMD_R(1.0) - a) / (b * ln_inv(a));
    s->R_ac = (SMD_R(1.0) - a) / b;
    return isfinite(s->L) && s->L > SMD_R(0.0);
}

void smd_ident_ls_reset(smd_ident_ls_state *s)
{
    s->phase = SMD_IDENT_LS_BIAS;
    s->outcome = SMD_IDENT_RUNNING;
    s->du = SMD_R(0.0);
    s->k = 0;
    s->n = 0;
    s->acc_i = s->acc_i2 = s->prev_i = SMD_R(0.0);
    s->have_prev = 0;
    ls_clear_slopes(s);
    s->i_bias_meas = SMD_R(0.0);
    s->u_applied = smd_c(SMD_R(0.0), SMD_R(0.0));
    s->samples = 0;
    s->L = s->swing = SMD_R(0.0);
}

static smd_status ls_stop(smd_ident_ls_state *s, int outcome, smd_real d_abc[3])
{
    s->phase = SMD_IDENT_LS_FAILED;
    s->outcome = outcome;
    zero_vector(d_abc, &s->u_applied);
    return SMD_ERR_FAULT;
}

/* The sample's current on the tested axis into its half period's sums (the
 * current at sample k follows the commands up to k - 2: the half period
 * commanded at k0 .. k0 + n - 1 shapes the samples k0 + 1 .. k0 + n); a
 * complete half period's least-squares slope (A a sample) into the sums of
 * its sign, except in the first period of a phase. */
static void ls_accumulate(const smd_ident_ls_params *p, smd_ident_ls_state *s, smd_real i)
{
    const int n = p->n_half;
    const int km = (s->k + 2 * n - 1) % (2 * n);
    const int h = km < n ? 0 : 1, j = km - h * n;
    if (s->period > 0) {
        s->acc_w[s->k] += i; /* the waveform by command index */
    }
    s->sj_i[h] += (smd_real)j * i;
    s->s_i[h] += i;
    if (j == n - 1) {
        const smd_real nn = (smd_real)n, jm = SMD_R(0.5) * (nn - SMD_R(1.0));
        const smd_real sxx = nn * (nn * nn - SMD_R(1.0)) / SMD_R(12.0);
        if (s->period > 0) {
            s->slope_sum[h] += (s->sj_i[h] - jm * s->s_i[h]) / sxx;
            s->halves[h]++;
        }
        s->sj_i[h] = s->s_i[h] = SMD_R(0.0);
    }
}

smd_status smd_ident_ls_step(const smd_ident_ls_params *p, smd_ident_ls_state *s, smd_real i_a,
                             smd_real i_b, smd_real u_dc, smd_real d_abc[3])
{
    const smd_real u_bias = p->R_s * p->i_bias + p->u_0;
    smd_real i_ax, u_sq = SMD_R(0.0);
    int bad;
    if (s->phase == SMD_IDENT_LS_DONE || s->phase == SMD_IDENT_LS_FAILED) {
        zero_vector(d_abc, &s->u_applied);
        return s->phase == SMD_IDENT_LS_DONE ? SMD_OK : SMD_ERR_FAULT;
    }
    bad = input_fault(i_a, i_b, u_dc, SMD_R(3.0) * p->i_bias);
    if (bad) {
        return ls_stop(s, bad, d_abc);
    }
    s->samples++;
    i_ax = p->axis == 0 ? i_a : (i_a + SMD_R(2.0) * i_b) * SMD_INV_SQRT3;
    if (s->phase == SMD_IDENT_LS_BIAS) {
        s->acc_i += i_a;
        s->acc_i2 += i_a * i_a;
        if (++s->n >= p->n_win) {
            const smd_real nw = (smd_real)s->n, m = s->acc_i / nw;
            smd_real var = s->acc_i2 / nw - m * m;
            var = var > SMD_R(0.0) ? var : SMD_R(0.0);
            if (s->have_prev && SMD_FABS(m - s->prev_i) <= SMD_R(0.002) * p->i_bias +
                                    SMD_R(3.0) * SMD_SQRT(SMD_R(2.0) * var / nw)) {
                s->i_bias_meas = m;
                s->phase = SMD_IDENT_LS_AMPLITUDE;
                s->du = SMD_R(0.0005) * p->u_max;
                s->k = 0;
                ls_clear_slopes(s);
            } else {
                s->prev_i = m;
                s->have_prev = 1;
            }
            s->n = 0;
            s->acc_i = s->acc_i2 = SMD_R(0.0);
            if (s->samples > 1000 * p->n_win) {
                return ls_stop(s, SMD_IDENT_NOT_SETTLED, d_abc);
            }
        }
    } else {
        ls_accumulate(p, s, i_ax);
        if (s->k == 2 * p->n_half - 1) {
            s->period++;
            if (s->phase == SMD_IDENT_LS_AMPLITUDE && s->period == 5) {
                const smd_real m = (s->slope_sum[0] / (smd_real)s->halves[0] -
                                    s->slope_sum[1] / (smd_real)s->halves[1]);
                s->swing = SMD_R(0.5) * m * (smd_real)p->n_half;
                if (s->swing < SMD_R(0.1) * p->i_bias && s->du < SMD_R(0.1) * p->u_max) {
                    s->du *= SMD_R(2.0);
                } else {
                    s->phase = SMD_IDENT_LS_MEASURE;
                }
                ls_clear_slopes(s);
            } else if (s->phase == SMD_IDENT_LS_MEASURE && s->period > p->periods) {
                const smd_real m = (s->slope_sum[0] / (smd_real)s->halves[0] -
                                    s->slope_sum[1] / (smd_real)s->halves[1]);
                s->swing = SMD_R(0.5) * m * (smd_real)p->n_half;
                s->period--; /* the first period was not summed */
                s->outcome = ls_fit(p, s) ? SMD_IDENT_OK : SMD_IDENT_POOR_FIT;
                s->phase = SMD_IDENT_LS_DONE;
                zero_vector(d_abc, &s->u_applied);
                return SMD_OK;
            }
        }
        u_sq = s->k < p->n_half ? s->du : -s->du;
        s->k = s->k + 1 >= 2 * p->n_half ? 0 : s->k + 1;
    }
    smd_svm_step(&p->svm,
                 smd_c(u_bias + (p->axis == 0 ? u_sq : SMD_R(0.0)),
                       p->axis == 1 ? u_sq : SMD_R(0.0)),
                 u_dc, d_abc, &s->u_applied);
    return SMD_OK;
}

/* ---- step 3: the PM flux (smd_ident.h) ---- */

smd_status smd_ident_psi_init(smd_ident_psi_params *p, const smd_ident_psi_config *c)
{
    smd_status st;
    if (p == 0 || c == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_pos_range(c->T_sp, SMD_R(1.0)) || !smd_in_range(c->R_s, SMD_R(0.0), SMD_R(1e3)) ||
        !smd_in_pos_range(c->L_s, SMD_R(10.0)) || !smd_in_range(c->u_0, SMD_R(0.0), SMD_R(1e4)) ||
        !smd_in_pos_range(c->i_spin, SMD_R(1e5)) || !smd_in_pos_range(c->w1, SMD_R(1e7)) ||
        !(c->w2 > c->w1 && c->w2 < SMD_PI / (SMD_R(4.0) * c->T_sp)) ||
        !smd_in_pos_range(c->a_spin, SMD_R(1e7)) ||
        !smd_in_range(c->t_hold, SMD_R(0.01), SMD_R(100.0)) ||
        !smd_in_range(c->t_coast, SMD_R(0.01), SMD_R(100.0)) ||
        !(c->t_hold <= SMD_R(1e8) * c->T_sp && c->t_coast <= SMD_R(1e8) * c->T_sp) ||
        !(c->w_cc > SMD_R(0.0) && c->w_cc <= SMD_PI / (SMD_R(10.0) * c->T_sp)) ||
        !smd_in_range(c->L1, SMD_R(0.0), SMD_R(10.0)) ||
        !smd_in_range(c->L2o, SMD_R(0.0), SMD_R(10.0)) ||
        !(c->L1 == SMD_R(0.0) || smd_in_pos_range(c->C1, SMD_R(10.0))) ||
        !(c->L1 == SMD_R(0.0) || c->w2 * c->w2 * c->L1 * c->C1 < SMD_R(0.5)) ||
        !(c->share_max > SMD_R(0.0) && c->share_max <= SMD_R(1.0)) ||
        !smd_in_range(c->w_damp, SMD_R(0.0), SMD_R(1e5)) ||
        !(c->w_damp * c->T_sp <= SMD_R(0.5))) {
        /* (the spin below the filter's resonance, w2^2 L1 C1 < 1/2) */
        return SMD_ERR_IDENT;
    }
    st = smd_svm_init(&p->svm, SMD_SVM_LIMIT_HEXAGON, SMD_R(0.0));
    if (st != SMD_OK) {
        return st;
    }
    p->T_sp = c->T_sp;
    p->R_s = c->R_s;
    p->L_s = c->L_s;
    p->u_drop = SMD_R(3.0) / SMD_PI * c->u_0;
    p->i_spin = c->i_spin;
    p->w1 = c->w1;
    p->w2 = c->w2;
    p->a_spin = c->a_spin;
    /* the current loop's inductance: behind a filter, its inductances in
     * series with the motor's (the capacitor aside, far below resonance) */
    if (c->L1 > SMD_R(0.0)) {
        p->L_s = c->L_s + c->L1 + c->L2o;
    }
    p->k_p = p->L_s * c->w_cc;
    p->k_i = c->R_s * c->w_cc;
    p->n_hold = (int)(c->t_hold / c->T_sp + SMD_R(0.5));
    p->n_coast = (int)(c->t_coast / c->T_sp + SMD_R(0.5));
    p->L1 = c->L1;
    p->C1 = c->L1 > SMD_R(0.0) ? c->C1 : SMD_R(0.0);
    p->a_cap = c->w_cc * c->T_sp;
    p->L2 = c->L1 > SMD_R(0.0) ? c->L2o + c->L_s : c->L_s;
    p->share_max = c->share_max;
    p->w_gov = SMD_R(0.2) * c->w1;
    p->a_share = SMD_R(10.0) * c->T_sp < SMD_R(1.0) ? SMD_R(10.0) * c->T_sp : SMD_R(1.0);
    p->k_g = SMD_R(4.0);
    p->w_damp = c->w_damp;
    p->a_hp = SMD_R(0.1) * c->w_damp * c->T_sp;
    return SMD_OK;
}

void smd_ident_psi_reset(smd_ident_psi_state *s)
{
    const smd_cplx z = smd_c(SMD_R(0.0), SMD_R(0.0));
    s->phase = SMD_IDENT_PSI_RAMP1;
    s->outcome = SMD_IDENT_RUNNING;
    s->theta_f = SMD_R(0.0);
    s->w_f = SMD_R(0.0);
    s->x_i = s->u_ab = s->u_prev = s->u_applied = s->i_cap = s->i_prev = z;
    s->pwm_off = 0;
    s->n = 0;
    s->acc_e = s->acc_n = s->acc_w = SMD_R(0.0);
    s->e1 = s->e2 = s->w1m = s->w2m = SMD_R(0.0);
    s->psi = s->psi1 = s->psi2 = s->psi_coast = s->psi_slope = SMD_R(0.0);
    s->shorted = 0;
    s->w_coast = SMD_R(0.0);
    s->acc_sh = s->acc_a = s->acc_r = s->share_ramp = s->a_ramp = SMD_R(0.0);
    s->phi_lpf = s->w_c = s->share = SMD_R(0.0);
    s->g = SMD_R(1.0);
    s->gov_on = 0;
    s->samples = 0;
    s->n_lim = 0;
    s->w_lim = SMD_R(0.0);
}

/* |R_s + j w L_s|, ohm: the stator's impedance at electrical speed w */
static smd_real stator_z(const smd_ident_psi_params *p, smd_real w)
{
    const smd_real wl = w * p->L_s;
    return SMD_SQRT(p->R_s * p->R_s + wl * wl);
}

static smd_status psi_stop(smd_ident_psi_state *s, int outcome, smd_real d_abc[3])
{
    s->phase = SMD_IDENT_PSI_FAILED;
    s->pwm_off = 0;
    s->outcome = outcome;
    zero_vector(d_abc, &s->u_applied);
    return SMD_ERR_FAULT;
}

static void psi_next_phase(smd_ident_psi_state *s, int phase)
{
    s->phase = phase;
    s->n = 0;
    s->acc_e = s->acc_n = s->acc_w = SMD_R(0.0);
}

smd_status smd_ident_psi_step(const smd_ident_psi_params *p, smd_ident_psi_state *s,
                              smd_real i_a, smd_real i_b, smd_real i1_a, smd_real i1_b,
                              smd_real u_dc, smd_real d_abc[3])
{
    const smd_real T = p->T_sp;
    const smd_cplx i_ab = smd_ab2_to_ab(i_a, i_b);
    smd_cplx i_ref, i_dq, i1_dq, err, u_dq, r;
    int bad;
    if (s->phase == SMD_IDENT_PSI_DONE || s->phase == SMD_IDENT_PSI_FAILED) {
        zero_vector(d_abc, &s->u_applied);
        return s->phase == SMD_IDENT_PSI_DONE ? SMD_OK : SMD_ERR_FAULT;
    }
    bad = input_fault(i_a, i_b, u_dc, SMD_R(3.0) * p->i_spin);
    if (!bad && p->L1 > SMD_R(0.0)) {
        bad = input_fault(i1_a, i1_b, u_dc, SMD_R(3.0) * p->i_spin);
    }
    if (bad) {
        return psi_stop(s, bad, d_abc);
    }
    s->samples++;
    s->n++;
    /* the forced frame's speed: the ramp, which waits while the rotor takes
     * more than share_max of the current's torque (the header) */
    if (s->phase == SMD_IDENT_PSI_RAMP1 || s->phase == SMD_IDENT_PSI_RAMP2) {
        const smd_real w_to = s->phase == SMD_IDENT_PSI_RAMP1 ? p->w1 : p->w2;
        s->w_f += s->g * p->a_spin * T;
        if (s->w_f >= w_to) {
            s->w_f = w_to;
            psi_next_phase(s, s->phase + 1);
        }
    }
    r = smd_cexpj(s->theta_f);
    i_dq = smd_cmul(i_ab, smd_cconj(r));
    i1_dq = i_dq;
    if (p->L1 > SMD_R(0.0)) {
        /* the capacitor's current i_1 - i, low-passed at w_cc */
        i1_dq = smd_cmul(smd_ab2_to_ab(i1_a, i1_b), smd_cconj(r));
        s->i_cap = smd_cadd(s->i_cap, smd_cscale(smd_csub(smd_csub(i1_dq, i_dq), s->i_cap),
                                                 p->a_cap));
    }
    /* coasting, i = 0; behind a filter, i = -i_cap, so that i_1 = 0 (the header) */
    i_ref = s->phase == SMD_IDENT_PSI_COAST ? smd_cscale(s->i_cap, SMD_R(-1.0))
                                            : smd_c(SMD_R(0.0), p->i_spin);
    err = smd_csub(i_ref, i_dq);
    u_dq = smd_cadd(smd_cadd(smd_cscale(err, p->k_p), s->x_i),
                    smd_cj(smd_cscale(i_ref, s->w_f * p->L_s)));
    s->x_i = smd_cadd(s->x_i, smd_cscale(err, p->k_i * T));
    if (s->phase != SMD_IDENT_PSI_COAST) {
        /* e = u - (R + j w L) i - the inverter's drop along the current;
         * behind a filter, the drop along i_1 and through the capacitor's
         * voltage (the header) */
        const smd_real ia = smd_cabs(i_dq), w = s->w_f + s->w_c;
        const smd_real ia1 = p->L1 > SMD_R(0.0) ? smd_cabs(i1_dq) : ia;
        smd_cplx v = u_dq, e;
        if (ia1 > SMD_R(0.0)) {
            v = smd_csub(v, smd_cscale(i1_dq, p->u_drop / ia1));
        }
        if (p->L1 > SMD_R(0.0)) {
            v = smd_csub(v, smd_cj(smd_cscale(i1_dq, w * p->L1)));
        }
        e = smd_csub(v, smd_cmul(smd_c(p->R_s, w * p->L2), i_dq));
        if (s->w_f >= p->w_gov && ia > SMD_R(0.0) && smd_cabs(e) > SMD_R(0.0)) {
            /* the stabiliser and the governor (the header) */
            const smd_real phi = SMD_ATAN2(e.im, e.re),
                           share = (e.re * i_dq.re + e.im * i_dq.im) / (smd_cabs(e) * ia);
            smd_real d;
            if (!s->gov_on) {
                s->phi_lpf = phi;
                s->share = share;
                s->gov_on = 1;
            }
            d = smd_wrap_pi(phi - s->phi_lpf);
            s->phi_lpf = smd_wrap_pi(s->phi_lpf + p->a_hp * d);
            /* (at most half the ramp's speed: a rotor that slipped does not
             * turn the frame back) */
            s->w_c = p->w_damp * d;
            if (s->w_c > SMD_R(0.5) * s->w_f) {
                s->w_c = SMD_R(0.5) * s->w_f;
            } else if (s->w_c < SMD_R(-0.5) * s->w_f) {
                s->w_c = SMD_R(-0.5) * s->w_f;
            }
            s->share += p->a_share * (share - s->share);
            if (s->phase == SMD_IDENT_PSI_RAMP2) {
                s->acc_sh += s->share;
                s->acc_a += s->g * p->a_spin;
                s->acc_r += SMD_R(1.0);
            }
            if (s->share > p->share_max) {
                s->g -= p->k_g * T * (s->share - p->share_max);
                if (s->g < SMD_R(0.01)) {
                    s->g = SMD_R(0.01);
                }
            }
        }
        if ((s->phase == SMD_IDENT_PSI_HOLD1 || s->phase == SMD_IDENT_PSI_HOLD2) &&
            2 * s->n > p->n_hold) {
            s->acc_e += smd_cabs(e);
            s->acc_w += w;
            s->acc_n += SMD_R(1.0);
        }
    }
    if (s->phase == SMD_IDENT_PSI_HOLD1 || s->phase == SMD_IDENT_PSI_HOLD2) {
        if (s->n >= p->n_hold) {
            /* mean |e| and the frame's mean speed (the rotor's, on average) */
            const smd_real em = s->acc_e / s->acc_n, wm = s->acc_w / s->acc_n;
            if (s->phase == SMD_IDENT_PSI_HOLD1) {
                s->e1 = em;
                s->w1m = wm;
                psi_next_phase(s, SMD_IDENT_PSI_RAMP2);
            } else {
                s->e2 = em;
                s->w2m = wm;
                /* the coast shorts the stator where the inverter's drop is more
                 * than a fifth of the EMF and the short's current, |e2| / |R_s
                 * + j w L_s|, within the spin's (the header) */
                s->shorted = p->L1 == SMD_R(0.0) && p->u_drop > SMD_R(0.2) * em &&
                             em <= p->i_spin * stator_z(p, wm);
                s->pwm_off = s->shorted ? 2 : 0;
                psi_next_phase(s, SMD_IDENT_PSI_COAST);
            }
        }
    } else if (s->phase == SMD_IDENT_PSI_COAST) {
        /* the PI holds i = 0: the voltage it applies is the back EMF; its
         * turn from the last sample's is the rotor's electrical speed, which
         * the frame follows (low-passed at 1/(20 T_sp)): a rotor that slows
         * (a fan load) would otherwise turn against the frame, and the PI's
         * integral would lag the EMF's turn in it */
        const smd_cplx rot = s->shorted ? smd_cmul(i_ab, smd_cconj(s->i_prev))
                                        : smd_cmul(s->u_ab, smd_cconj(s->u_prev));
        const smd_real turn = SMD_ATAN2(rot.im, rot.re);
        s->w_c = SMD_R(0.0);
        if (s->n > 1) {
            s->w_f += SMD_R(0.05) * (turn / T - s->w_f);
        }
        if (s->shorted) {
            /* the stator shorted (the header): the back EMF is -(R_s + j w
             * L_s) i, and i turns with the rotor; no device switches, so no
             * dead time */
            s->i_prev = i_ab;
            if (10 * s->n > p->n_coast) {
                s->acc_e += smd_cabs(i_ab) * stator_z(p, s->w_f);
                s->acc_w += turn;
                s->acc_n += SMD_R(1.0);
            }
        } else if (p->L1 > SMD_R(0.0)) {
            /* behind a filter: the PI holds i_1 near 0 for a tenth of the
             * coast, then every switch opens; from a fifth on, the motor's
             * current is the capacitor's, i = -j w C1 u_c, its magnitude and
             * turn measured (the header) */
            const smd_cplx ri = smd_cmul(i_ab, smd_cconj(s->i_prev));
            s->i_prev = i_ab;
            if (10 * s->n > p->n_coast) {
                s->pwm_off = 1;
            }
            if (5 * s->n > p->n_coast) {
                s->acc_e += smd_cabs(i_ab);
                s->acc_w += SMD_ATAN2(ri.im, ri.re);
                s->acc_n += SMD_R(1.0);
            }
        } else if (10 * s->n > p->n_coast) {
            s->acc_e += smd_cabs(s->u_ab);
            /* (signed: a mean of absolute turns would grow with the
             * noise the current loop puts on the voltage) */
            s->acc_w += turn;
            s->acc_n += SMD_R(1.0);
        }
        if (s->n >= p->n_coast) {
            const smd_real w = SMD_FABS(s->acc_w) / (s->acc_n * T);
            /* behind a filter, |u_c| = |i| / (w C1) and e = u_c (1 - w^2 C1 L2
             * + j w R_s C1) (the header) */
            const smd_real k_re = SMD_R(1.0) - w * w * p->C1 * p->L2, k_im = w * p->R_s * p->C1;
            s->psi_coast = p->L1 > SMD_R(0.0)
                               ? (s->acc_e / s->acc_n) * SMD_SQRT(k_re * k_re + k_im * k_im) /
                                     (w * w * p->C1)
                               : (s->acc_e / s->acc_n) / w;
            s->pwm_off = 0;
            s->psi1 = s->e1 / s->w1m;
            s->psi2 = s->e2 / s->w2m;
            s->psi_slope = (s->e2 - s->e1) / (s->w2m - s->w1m);
            /* each hold within 5 % and a tenth of the drop's share of its EMF
             * (the drop's model, 3/pi u_0, taken as 10 % uncertain; the header) */
            const smd_real m1 = SMD_R(0.05) + SMD_R(0.1) * p->u_drop / s->e1,
                           m2 = SMD_R(0.05) + SMD_R(0.1) * p->u_drop / s->e2;
            s->psi = s->shorted ? s->psi_coast : s->psi2;
            s->w_coast = w;
            s->share_ramp = s->acc_r > SMD_R(0.0) ? s->acc_sh / s->acc_r : SMD_R(0.0);
            s->a_ramp = s->acc_r > SMD_R(0.0) ? s->acc_a / s->acc_r : SMD_R(0.0);
            s->outcome = !(SMD_FABS(w / s->w2m - SMD_R(1.0)) <= SMD_R(0.5)) ? SMD_IDENT_SLIPPED
                         : (isfinite(s->psi) && s->psi > SMD_R(0.0) && isfinite(s->psi_coast) &&
                          SMD_FABS(s->psi_coast / s->psi - SMD_R(1.0)) <= m2 &&
                          SMD_FABS(s->psi2 / s->psi - SMD_R(1.0)) <= m2 &&
                          SMD_FABS(s->psi1 / s->psi - SMD_R(1.0)) <= m1)
                             ? SMD_IDENT_OK
                             : SMD_IDENT_POOR_FIT;
            if (s->outcome != SMD_IDENT_OK && s->n_lim > p->n_hold / 20) {
                /* no result, and the voltage was limited for more than a
                 * twentieth of a hold: the EMF the spin met was beyond the
                 * DC link's reach, and the rotor slipped for that, not for
                 * a load (the header) */
                s->outcome = SMD_IDENT_VOLTAGE_LIMIT;
            }
            s->phase = SMD_IDENT_PSI_DONE;
            zero_vector(d_abc, &s->u_applied);
            return SMD_OK;
        }
    }
    s->u_prev = s->u_ab;
    if (s->pwm_off == 2) {
        /* every lower switch on, forced (pwm_off = 2, set as the shorted
         * coast began: a PWM unit's forced output level, no edge and so no
         * dead time; the duties 0 for a gate driver without one) */
        d_abc[0] = d_abc[1] = d_abc[2] = SMD_R(0.0);
        s->u_applied = smd_c(SMD_R(0.0), SMD_R(0.0));
        return SMD_OK;
    }
    if (s->pwm_off) {
        zero_vector(d_abc, &s->u_applied); /* (the duties if the switches stay on) */
        return SMD_OK;
    }
    {
        const smd_real w = s->w_f + s->w_c;
        s->u_ab = smd_cmul(u_dq, smd_cexpj(s->theta_f + SMD_R(1.5) * w * T));
        s->theta_f = smd_wrap_pi(s->theta_f + w * T);
    }
    smd_svm_step(&p->svm, s->u_ab, u_dc, d_abc, &s->u_applied);
    /* (n_lim stays below n_hold <= 1e8: the spin stops there) */
    if (s->phase != SMD_IDENT_PSI_COAST &&
        (s->u_applied.re != s->u_ab.re || s->u_applied.im != s->u_ab.im)) {
        if (s->w_lim == SMD_R(0.0) && s->w_f >= p->w_gov) {
            s->w_lim = s->w_f; /* (above the start's current step: the EMF's limit) */
        }
        s->n_lim++; /* (the ramps and holds: the coast applies the EMF it reads) */
        if (s->n_lim >= p->n_hold) {
            /* limited for a hold's length: the governor would hold the ramp
             * at the EMF the DC link reaches, without end (the header) */
            return psi_stop(s, SMD_IDENT_VOLTAGE_LIMIT, d_abc);
        }
    }
    return SMD_OK;
}

/* ------------------------------------------------------------ step 4 */

smd_status smd_ident_mech_init(smd_ident_mech_params *p, const smd_ident_mech_config *c)
{
    smd_real T, n_total;
    if (p == 0 || c == 0) {
        return SMD_ERR_NULL;
    }
    T = c->T_sp;
    if (!smd_in_pos_range(T, SMD_R(1.0)) || !smd_in_pos_range(c->k_t, SMD_R(1e3)) ||
        c->n_p < 1 || c->n_p > 100 || !smd_in_pos_range(c->w1, SMD_R(1e6)) ||
        !smd_in_pos_range(c->w2, SMD_R(1e6)) || !(c->w1 < c->w2) ||
        !smd_in_range(c->t_bin, SMD_R(10.0) * T, SMD_R(1.0)) ||
        !smd_in_range(c->t_fit, SMD_R(4.0) * c->t_bin, SMD_R(0.5) * c->t_step) ||
        !smd_in_range(c->t_step, SMD_R(2.0) * c->t_fit, SMD_R(100.0)) ||
        !smd_in_range(c->t_ramp, SMD_R(4.0) * c->t_bin, SMD_R(100.0)) ||
        !smd_in_range(c->t_hold, SMD_R(4.0) * c->t_bin, SMD_R(100.0)) ||
        !smd_in_range(c->w_lpf, SMD_R(0.0), SMD_PI / T) ||
        !(c->w_lpf == SMD_R(0.0) || c->w_lpf * c->t_step >= SMD_R(5.0)) ||
        (c->fan != 0 && c->fan != 1) ||
        !(c->t_coast == SMD_R(0.0) ||
          (smd_in_range(c->t_coast, SMD_R(0.0), SMD_R(100.0)) &&
           c->t_coast * (c->w_lpf > SMD_R(0.0) ? c->w_lpf : SMD_R(1.0) / T) >=
               SMD_R(5.0) + SMD_R(4.0) * c->t_bin * (c->w_lpf > SMD_R(0.0) ? c->w_lpf
                                                                          : SMD_R(1.0) / T)))) {
        /* (a coast: 0, or long enough for the filter to forget the drive's
         * torque and 4 bins after it) */
        return SMD_ERR_IDENT;
    }
    n_total = (c->t_step + c->t_ramp + c->t_hold + c->t_coast) / T;
    if (!(n_total <= SMD_R(1e8))) {
        return SMD_ERR_IDENT; /* (the sample counts are ints) */
    }
    p->k_t = c->k_t;
    p->inv_np = SMD_R(1.0) / (smd_real)c->n_p;
    p->w1 = c->w1;
    p->w2 = c->w2;
    p->dw = c->w2 - c->w1;
    p->t_bin = c->t_bin;
    p->a_lpf = c->w_lpf > SMD_R(0.0) ? -SMD_EXPM1(-c->w_lpf * T) : SMD_R(1.0);
    p->fan = c->fan;
    p->inv_w2 = (smd_real)c->n_p / c->w2; /* (the fit's speeds are mechanical) */
    /* 5 time constants of the filter: then a closed drive's signals count
     * (1 sample without one) */
    p->n_settle = c->w_lpf > SMD_R(0.0) ? (int)(SMD_R(5.0) / (c->w_lpf * T) + SMD_R(0.5)) : 1;
    p->n_step = (int)(c->t_step / T + SMD_R(0.5));
    p->n_ramp = (int)(c->t_ramp / T + SMD_R(0.5));
    p->n_end = p->n_step + p->n_ramp + (int)(c->t_hold / T + SMD_R(0.5));
    p->n_fit0 = p->n_step - (int)(c->t_fit / T + SMD_R(0.5));
    p->n_bin = (int)(c->t_bin / T + SMD_R(0.5));
    p->n_coast = (int)(c->t_coast / T + SMD_R(0.5));
    return SMD_OK;
}

void smd_ident_mech_reset(smd_ident_mech_state *s)
{
    s->k = 0;
    s->outcome = SMD_IDENT_RUNNING;
    s->bins = 0;
    s->nb = 0;
    s->acc_T = s->acc_w = SMD_R(0.0);
    s->T_f = SMD_R(0.0);
    s->w_b[0] = s->w_b[1] = s->T_b[0] = s->T_b[1] = SMD_R(0.0);
    s->saa = s->saw = s->sww = s->sat = s->swt = SMD_R(0.0);
    s->saq = s->swq = s->sqq = s->sqt = SMD_R(0.0);
    s->cww = s->cwq = s->cqq = s->cwa = s->cqa = SMD_R(0.0);
    s->crows = 0;
    s->B_ramp = SMD_R(0.0);
    s->caa = SMD_R(0.0);
    s->B_se = SMD_R(-1.0);
    s->rows = 0;
    s->wait = 0;
    s->n_closed = 0;
    s->J = s->B = s->K = SMD_R(0.0);
}

smd_real smd_ident_mech_ref(const smd_ident_mech_params *p, const smd_ident_mech_state *s)
{
    if (s->k < p->n_step) {
        return p->w1;
    }
    if (s->k < p->n_step + p->n_ramp) {
        return p->w1 + p->dw * (smd_real)(s->k - p->n_step) / (smd_real)p->n_ramp;
    }
    return p->w2;
}

/* A completed bin: the one before it, now with neighbours on both sides,
 * joins the normal equations of T = J a + B w: a the neighbours' central
 * difference, which weighs the acceleration over the three bins with a
 * trapezoid (rising over the first, flat over the middle one, falling over
 * the last), and T and w weighted alike, (x0 + 2 x1 + x2) / 4 of the bins'
 * means, so that the equation holds for the weighted means (the middle
 * bin's T and w alone put B 28 % off on a rotor 10 times Table I's with its
 * true torque and speed; with the weights, 2 %). */
static void mech_bin(const smd_ident_mech_params *p, smd_ident_mech_state *s)
{
    const smd_real n = (smd_real)s->nb;
    const smd_real T_new = s->acc_T / n, w_new = s->acc_w / n;
    if (s->bins >= 2) {
        const smd_real a = (w_new - s->w_b[0]) / (SMD_R(2.0) * p->t_bin);
        const smd_real w = SMD_R(0.25) * (s->w_b[0] + SMD_R(2.0) * s->w_b[1] + w_new);
        const smd_real T = SMD_R(0.25) * (s->T_b[0] + SMD_R(2.0) * s->T_b[1] + T_new);
        const smd_real q = w * SMD_FABS(w) * p->inv_w2;
        if (s->k >= p->n_end) {
            /* the coast: J a = -(B w + K w |w|), no torque */
            s->cww += w * w;
            s->cwa += w * a;
            s->caa += a * a;
            if (p->fan) {
                s->cwq += w * q;
                s->cqq += q * q;
                s->cqa += q * a;
            }
            s->crows++;
        } else {
            s->saa += a * a;
            s->saw += a * w;
            s->sww += w * w;
            s->sat += a * T;
            s->swt += w * T;
            if (p->fan) {
                s->saq += a * q;
                s->swq += w * q;
                s->sqq += q * q;
                s->sqt += q * T;
            }
            s->rows++;
        }
    }
    s->w_b[0] = s->w_b[1];
    s->w_b[1] = w_new;
    s->T_b[0] = s->T_b[1];
    s->T_b[1] = T_new;
    s->bins++;
    s->nb = 0;
    s->acc_T = s->acc_w = SMD_R(0.0);
}

/* The coast's deceleration, -(beta w + kappa q) (q = w |w| / w2), gives
 * B / J and K / J with no torque to measure; then the ramp's equations,
 * T = J (a + beta w + kappa q), give J by least squares. */
static void mech_coast(const smd_ident_mech_params *p, smd_ident_mech_state *s)
{
    smd_real beta = -s->cwa / s->cww, kappa = SMD_R(0.0), num, den;
    if (p->fan) {
        const smd_real det = s->cww * s->cqq - s->cwq * s->cwq;
        if (det > SMD_R(1e-6) * s->cww * s->cqq) {
            beta = (-s->cwa * s->cqq + s->cqa * s->cwq) / det;
            kappa = (-s->cqa * s->cww + s->cwa * s->cwq) / det;
        }
        /* (non-negative, as the ramp's) */
        if (beta < SMD_R(0.0) && s->cqq > SMD_R(0.0)) {
            beta = SMD_R(0.0);
            kappa = -s->cqa / s->cqq;
        } else if (kappa < SMD_R(0.0)) {
            kappa = SMD_R(0.0);
            beta = -s->cwa / s->cww;
        }
    }
    num = s->sat + beta * s->swt + kappa * s->sqt;
    den = s->saa + SMD_R(2.0) * beta * s->saw + SMD_R(2.0) * kappa * s->saq +
          beta * beta * s->sww + SMD_R(2.0) * beta * kappa * s->swq + kappa * kappa * s->sqq;
    s->J = num / den;
    s->B = s->J * beta;
    s->K = s->J * kappa * p->inv_w2;
    if (!p->fan && s->crows > 1) {
        /* B's standard error from the coast's line a = -beta w: its residual
         * over crows - 1 degrees of freedom (the bins' accelerations are
         * central differences, so neighbours share a bin: an estimate, not
         * a bound) */
        const smd_real res = s->caa + SMD_R(2.0) * beta * s->cwa + beta * beta * s->cww;
        s->B_se = s->J * SMD_SQRT((res > SMD_R(0.0) ? res : SMD_R(0.0)) /
                                  ((smd_real)(s->crows - 1) * s->cww));
    }
}

static void mech_solve(const smd_ident_mech_params *p, smd_ident_mech_state *s)
{
    s->outcome = SMD_IDENT_POOR_FIT;
    if (!p->fan) {
        const smd_real det = s->saa * s->sww - s->saw * s->saw;
        if (s->rows >= 2 && det > SMD_R(1e-6) * s->saa * s->sww) {
            s->J = (s->sat * s->sww - s->swt * s->saw) / det;
            s->B = (s->saa * s->swt - s->saw * s->sat) / det;
        }
    } else {
        /* the 3 x 3 normal equations [saa saw saq; saw sww swq; saq swq sqq]
         * x = [sat swt sqt] by their adjugate (q = w |w| / w2: the same scale
         * as w) */
        const smd_real c11 = s->sww * s->sqq - s->swq * s->swq;
        const smd_real c12 = s->saq * s->swq - s->saw * s->sqq;
        const smd_real c13 = s->saw * s->swq - s->saq * s->sww;
        const smd_real c22 = s->saa * s->sqq - s->saq * s->saq;
        const smd_real c23 = s->saw * s->saq - s->saa * s->swq;
        const smd_real c33 = s->saa * s->sww - s->saw * s->saw;
        const smd_real det = s->saa * c11 + s->saw * c12 + s->saq * c13;
        if (s->rows >= 3 && det > SMD_R(1e-6) * s->saa * s->sww * s->sqq) {
            s->J = (c11 * s->sat + c12 * s->swt + c13 * s->sqt) / det;
            s->B = (c12 * s->sat + c22 * s->swt + c23 * s->sqt) / det;
            s->K = (c13 * s->sat + c23 * s->swt + c33 * s->sqt) / det;
            /* B and K from speeds within a factor of 2 or so lean on each
             * other: one that comes out negative is 0, and the others are
             * the least squares without it (non-negative least squares) */
            if (s->B < SMD_R(0.0) && c22 > SMD_R(0.0)) {
                s->B = SMD_R(0.0);
                s->J = (s->sat * s->sqq - s->sqt * s->saq) / c22;
                s->K = (s->saa * s->sqt - s->saq * s->sat) / c22;
            } else if (s->K < SMD_R(0.0) && c33 > SMD_R(0.0)) {
                s->K = SMD_R(0.0);
                s->J = (s->sat * s->sww - s->swt * s->saw) / c33;
                s->B = (s->saa * s->swt - s->saw * s->sat) / c33;
            }
            if (s->B < SMD_R(0.0) || s->K < SMD_R(0.0)) {
                s->B = s->K = SMD_R(0.0);
                s->J = s->sat / s->saa;
            }
            s->K *= p->inv_w2;
        }
    }
    s->B_ramp = s->B;
    if (s->crows > 0 && s->rows > 0 && s->saa > SMD_R(0.0) && s->cww > SMD_R(0.0)) {
        mech_coast(p, s);
    }
    if (isfinite(s->J) && isfinite(s->B) && isfinite(s->K) && s->J > SMD_R(0.0) &&
        s->B >= SMD_R(0.0) && s->K >= SMD_R(0.0) && s->rows > 0 &&
        /* with a coast, its B (no torque in it) and the ramp's (the drive's
         * torque k_t i_q) agree: their friction torques at w2 differ by at
         * most a twentieth of the torque the ramp's acceleration takes (the
         * header) */
        !(s->crows > 0 && SMD_FABS(s->B - s->B_ramp) * p->w2 * p->inv_np >
                              SMD_R(0.05) * s->J * p->dw * p->inv_np * (smd_real)p->n_bin /
                                  ((smd_real)p->n_ramp * p->t_bin))) {
        s->outcome = SMD_IDENT_OK;
    }
}

int smd_ident_mech_step(const smd_ident_mech_params *p, smd_ident_mech_state *s,
                        smd_real i_q, smd_real w_hat, int closed, uint32_t fault)
{
    if (s->outcome != SMD_IDENT_RUNNING) {
        return 1;
    }
    if (fault != 0u) {
        s->outcome = SMD_IDENT_FAULT;
        return 1;
    }
    if (smd_nf(i_q) + smd_nf(w_hat) != SMD_R(0.0)) {
        s->outcome = SMD_IDENT_BAD_INPUT;
        return 1;
    }
    /* (from the test's start: the filter has settled by the fit's) */
    s->T_f += p->a_lpf * (p->k_t * i_q - s->T_f);
    if (!closed) {
        s->n_closed = 0;
    } else if (s->n_closed < p->n_settle) {
        s->n_closed++;
    }
    if (s->n_closed < p->n_settle && s->k >= p->n_fit0) {
        /* the drive's torque is not k_t i_q (its forced start), or has
         * not been for 5 / w_lpf (the filters still hold the start): the fit
         * waits for its source (the header), or starts its bins again */
        s->bins = 0;
        s->nb = 0;
        s->acc_T = s->acc_w = SMD_R(0.0);
        if (s->k == p->n_fit0) {
            if (++s->wait >= p->n_end) {
                s->outcome = SMD_IDENT_NOT_SETTLED;
                return 1;
            }
            return 0;
        }
    }
    if (s->k == p->n_end) {
        /* the coast begins: its bins stand apart from the ramp's */
        s->bins = 0;
        s->nb = 0;
        s->acc_T = s->acc_w = SMD_R(0.0);
    }
    /* (the coast's bins once the speed estimate's filter has forgotten the
     * drive's torque) */
    if (s->k >= p->n_fit0 && (s->k < p->n_end || s->k >= p->n_end + p->n_settle)) {
        s->acc_T += s->T_f;
        s->acc_w += w_hat * p->inv_np;
        if (++s->nb >= p->n_bin) {
            mech_bin(p, s);
        }
    }
    if (++s->k >= p->n_end + p->n_coast) {
        mech_solve(p, s);
        return 1;
    }
    return 0;
}

int smd_ident_mech_coasting(const smd_ident_mech_params *p, const smd_ident_mech_state *s)
{
    return s->outcome == SMD_IDENT_RUNNING && s->k >= p->n_end;
}

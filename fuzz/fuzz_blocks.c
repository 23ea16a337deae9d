/*
 * libFuzzer target: the blocks of the core one at a time, each through its
 * init (or setter), reset and step functions on parameters and input
 * sequences decoded from the input (fuzz.h):
 *   block 0  smd_svm_init, smd_svm_step, smd_svm_deadtime_comp(_lost)
 *   block 1  smd_pi_init, smd_pi_reset, smd_pi_step
 *   block 2  smd_dbpc_init, smd_dbpc_ref_k2, smd_dbpc_predict,
 *            smd_dbpc_conventional, smd_dbpc_robust
 *   block 3  smd_smdo_init, smd_smdo_set_euler, smd_smdo_reset, smd_smdo_step
 *   block 4  smd_emf_pos_init, smd_emf_pos_reset, smd_emf_pos_step
 *   block 5  smd_pll_init, smd_pll_reset, smd_pll_step
 *   block 6  smd_bandpass_set, smd_bandpass_reset, smd_bandpass_step
 *   ident    smd_ident_rs_init, smd_ident_rs_reset, smd_ident_rs_step (a first
 *            byte of 0xF0-0xF5; issue 23's R_s test: its duties in [0, 1],
 *            0.5 once ended; a result's values finite), the inductance
 *            test's smd_ident_ls_* (0xF6-0xFA: duties in [0, 1], a result
 *            finite and positive) and the flux test's smd_ident_psi_*
 *            (0xFB-0xFF: duties in [0, 1], the forced frame finite); step 4's
 *            smd_ident_mech_* (0xEC-0xEF: its reference finite, a result's J
 *            positive and B not negative)
 * Input: the block (u8 % 7), its parameters, then steps until the input
 * ends (op byte: even a step on new values, odd a run of 1 + u8 steps on a
 * rotating vector or, for the PI and the PLL, a constant error).
 *
 * Checked besides the sanitizers: the modulator's duties are in
 * [d_min, 1 - d_min] (finite) for a finite reference and DC link, the
 * applied vector is finite and no longer than the reference; the dead-time
 * compensation keeps finite duties in [0, 1]; the PI's output is finite and
 * within +-y_max; the SMDO and the PLL keep a finite state (they reset on
 * non-finite values); the emf_pos speed stays within +-w_max.
 */
#include "fuzz.h"

#include "smodrive/smd_bandpass.h"
#include "smodrive/smd_dbpc.h"
#include "smodrive/smd_emf_pos.h"
#include "smodrive/smd_ident.h"
#include "smodrive/smd_pi.h"
#include "smodrive/smd_pll.h"
#include "smodrive/smd_smdo.h"
#include "smodrive/smd_svm.h"

#define FZ_MAX_STEPS 4000

/* A rotating vector for the runs: amplitude, angle, increment per step. */
typedef struct rot {
    double amp, th, dth;
} rot;

static smd_cplx rot_next(rot *r)
{
    smd_cplx z = smd_c((smd_real)(r->amp * cos(r->th)), (smd_real)(r->amp * sin(r->th)));
    r->th += r->dth;
    if (isfinite(r->th)) {
        r->th = remainder(r->th, 6.283185307179586);
    }
    return z;
}

static void rot_read(fz *f, rot *r, double amp)
{
    r->amp = fz_real(f, -amp, amp);
    r->th = fz_real(f, -4.0, 4.0);
    r->dth = fz_real(f, -3.2, 3.2);
}

static int is_finite_duty(smd_real d, smd_real lo, smd_real hi)
{
    return isfinite(d) && d >= lo && d <= hi;
}

static void fuzz_svm(fz *f)
{
    smd_svm_params p;
    int limit = fz_int(f, 0, 1);
    smd_real d_min = fz_r(f, 0.0, 0.5);
    int steps = 0;
    if (smd_svm_init(&p, limit, d_min) != SMD_OK) {
        return;
    }
    FZ_CHECK(smd_svm_init(0, limit, d_min) == SMD_ERR_NULL);
    while (fz_more(f) && steps < FZ_MAX_STEPS) {
        uint8_t op = fz_u8(f);
        smd_real u_dc = fz_r(f, -100.0, 1000.0);
        int n = (op & 1) ? 1 + fz_u8(f) : 1, k;
        rot r;
        smd_cplx one = smd_c(SMD_R(0.0), SMD_R(0.0));
        if (op & 1) {
            rot_read(f, &r, 1e3);
        } else {
            one = fz_c(f, 1e3);
        }
        for (k = 0; k < n && steps < FZ_MAX_STEPS; k++, steps++) {
            smd_cplx u = (op & 1) ? rot_next(&r) : one, ua;
            smd_real d[3];
            int j;
            smd_svm_step(&p, u, u_dc, d, &ua);
            fz_use_c(ua);
            if (smd_cfinite(u) && isfinite(u_dc)) {
                if (!(is_finite_duty(d[0], p.d_min, SMD_R(1.0) - p.d_min) &&
                      is_finite_duty(d[1], p.d_min, SMD_R(1.0) - p.d_min) &&
                      is_finite_duty(d[2], p.d_min, SMD_R(1.0) - p.d_min))) {
                    fprintf(stderr, "svm(limit %d, d_min %.9g): u = %.9g%+.9gj, u_dc = %.9g -> "
                            "d = %.9g %.9g %.9g\n", p.limit, (double)p.d_min, (double)u.re,
                            (double)u.im, (double)u_dc, (double)d[0], (double)d[1], (double)d[2]);
                }
                for (j = 0; j < 3; j++) {
                    FZ_CHECK(is_finite_duty(d[j], p.d_min, SMD_R(1.0) - p.d_min));
                }
                FZ_CHECK(smd_cfinite(ua));
                FZ_CHECK(smd_cabs(ua) <= smd_cabs(u) * SMD_R(1.00001) || !isfinite(smd_cabs(u)));
            }
            if (op & 2) {
                smd_real i_abc[3];
                smd_real t_ratio = fz_r(f, 0.0, 0.25), i_lin = fz_r(f, 0.0, 10.0);
                int finite = 1;
                for (j = 0; j < 3; j++) {
                    i_abc[j] = fz_r(f, -100.0, 100.0);
                    finite = finite && isfinite(i_abc[j]) && isfinite(d[j]);
                }
                if (op & 4) {
                    /* the drive's: the same duties, and the voltage the
                     * clipping leaves out; with t_ratio in the drive's range
                     * [0, 0.25] each leg's share is within 1 of u_dc, so the
                     * vector within 2 u_dc */
                    const smd_cplx lost = smd_svm_deadtime_comp_lost(
                        d, i_abc, t_ratio, i_lin, SMD_R(1.0) / i_lin, SMD_R(540.0));
                    if (finite && t_ratio >= SMD_R(0.0) && t_ratio <= SMD_R(0.25) &&
                        isfinite(i_lin) && i_lin > SMD_R(0.0)) {
                        FZ_CHECK(smd_cfinite(lost));
                        FZ_CHECK(smd_cabs(lost) <= SMD_R(2.0) * SMD_R(540.0));
                    }
                } else {
                    smd_svm_deadtime_comp(d, i_abc, t_ratio, i_lin);
                }
                if (finite && isfinite(t_ratio) && isfinite(i_lin) && i_lin > SMD_R(0.0)) {
                    for (j = 0; j < 3; j++) {
                        FZ_CHECK(is_finite_duty(d[j], SMD_R(0.0), SMD_R(1.0)));
                    }
                }
                for (j = 0; j < 3; j++) {
                    fz_use((double)d[j]);
                }
            }
        }
    }
}

static void fuzz_pi(fz *f)
{
    smd_pi_params p;
    smd_pi_state s;
    smd_real k_p = fz_r(f, 0.0, 10.0), k_i = fz_r(f, 0.0, 1e4);
    smd_real T_s = fz_r(f, 0.0, 1e-2), y_max = fz_r(f, 0.0, 100.0);
    int steps = 0;
    if (smd_pi_init(&p, k_p, k_i, T_s, y_max) != SMD_OK) {
        return;
    }
    smd_pi_reset(&s, fz_r(f, -100.0, 100.0));
    while (fz_more(f) && steps < FZ_MAX_STEPS) {
        uint8_t op = fz_u8(f);
        smd_real e = fz_r(f, -1e3, 1e3);
        int n = (op & 1) ? 1 + fz_u8(f) : 1, k;
        if (op & 2) {
            smd_pi_reset(&s, fz_r(f, -100.0, 100.0));
        }
        for (k = 0; k < n && steps < FZ_MAX_STEPS; k++, steps++) {
            smd_real y = smd_pi_step(&p, &s, e);
            FZ_CHECK(isfinite(y) && y <= p.y_max && y >= -p.y_max);
            FZ_CHECK(isfinite(s.x_i));
        }
    }
}

static void fuzz_dbpc(fz *f)
{
    smd_dbpc_params p;
    smd_real T = fz_r(f, 0.0, 1e-3), L = fz_r(f, 0.0, 0.1), R = fz_r(f, 0.0, 10.0);
    smd_real psi = fz_r(f, 0.0, 1.0);
    int steps = 0;
    if (smd_dbpc_init(&p, T, L, R, psi) != SMD_OK) {
        return;
    }
    while (fz_more(f) && steps < FZ_MAX_STEPS) {
        smd_cplx i = fz_c(f, 100.0), u = fz_c(f, 1e3), iref = fz_c(f, 100.0);
        smd_real th = fz_r(f, -4.0, 4.0), w = fz_r(f, -3e4, 3e4);
        smd_cplx k2 = smd_dbpc_ref_k2(&p, iref, th, w);
        fz_use_c(k2);
        fz_use_c(smd_dbpc_predict(&p, i, u, th, w));
        fz_use_c(smd_dbpc_conventional(&p, i, u, iref, th, w));
        fz_use_c(smd_dbpc_robust(&p, i, u, k2));
        steps++;
    }
}

static void fuzz_smdo(fz *f)
{
    smd_smdo_params p;
    smd_smdo_state s;
    smd_real T = fz_r(f, 0.0, 1e-3), L = fz_r(f, 0.0, 0.1), R = fz_r(f, 0.0, 10.0);
    smd_real lam = fz_r(f, 0.0, 1e4), l = fz_r(f, 0.0, 1e4), w_c = fz_r(f, 0.0, 1e4);
    smd_real rho = fz_r(f, 0.0, 10.0);
    int euler = fz_int(f, 0, 1), steps = 0;
    if (smd_smdo_init(&p, T, L, R, lam, l, w_c, rho) != SMD_OK) {
        return;
    }
    if (smd_smdo_set_euler(&p, euler) != SMD_OK) {
        return;
    }
    {
        smd_cplx i0 = fz_c(f, 100.0);
        smd_smdo_reset(&s, i0, fz_c(f, 1e3));
    }
    while (fz_more(f) && steps < FZ_MAX_STEPS) {
        uint8_t op = fz_u8(f);
        smd_real w = fz_r(f, -3e4, 3e4);
        int n = (op & 1) ? 1 + fz_u8(f) : 1, k;
        rot ri, ru;
        smd_cplx i1 = smd_c(SMD_R(0.0), SMD_R(0.0)), u1 = i1;
        if (op & 1) {
            rot_read(f, &ri, 100.0);
            rot_read(f, &ru, 1e3);
        } else {
            i1 = fz_c(f, 100.0);
            u1 = fz_c(f, 1e3);
        }
        if (op & 2) {
            smd_cplx i0 = fz_c(f, 100.0);
            smd_smdo_reset(&s, i0, fz_c(f, 1e3));
        }
        for (k = 0; k < n && steps < FZ_MAX_STEPS; k++, steps++) {
            smd_cplx i = (op & 1) ? rot_next(&ri) : i1, u = (op & 1) ? rot_next(&ru) : u1;
            smd_status st = smd_smdo_step(&p, &s, i, u, w);
            FZ_CHECK(st == SMD_OK || st == SMD_ERR_NONFINITE);
            if (st == SMD_OK) {
                FZ_CHECK(smd_cfinite(s.i_s_hat) && smd_cfinite(s.u_d_hat) && isfinite(s.lambda));
            }
            fz_use_c(s.u_smo);
        }
    }
}

static void fuzz_emf_pos(fz *f)
{
    smd_emf_pos_params p;
    smd_emf_pos_state s;
    smd_real T = fz_r(f, 0.0, 1e-3), w_lpf = fz_r(f, 0.0, 2000.0);
    smd_real w_hys = fz_r(f, 0.0, 100.0), w_max = fz_r(f, 0.0, 3e4);
    int steps = 0, since_reset = 0;
    if (smd_emf_pos_init(&p, T, w_lpf, w_hys, w_max) != SMD_OK) {
        return;
    }
    smd_emf_pos_reset(&s, fz_r(f, -3e4, 3e4));
    while (fz_more(f) && steps < FZ_MAX_STEPS) {
        uint8_t op = fz_u8(f);
        int n = (op & 1) ? 1 + fz_u8(f) : 1, k;
        rot r;
        smd_cplx one = smd_c(SMD_R(0.0), SMD_R(0.0));
        if (op & 1) {
            rot_read(f, &r, 1e3);
        } else {
            one = fz_c(f, 1e3);
        }
        if (op & 2) {
            smd_emf_pos_reset(&s, fz_r(f, -3e4, 3e4));
            since_reset = 0;
        }
        for (k = 0; k < n && steps < FZ_MAX_STEPS; k++, steps++) {
            smd_cplx u = (op & 1) ? rot_next(&r) : one;
            /* the speed is updated (and limited) once primed, on a finite angle */
            since_reset += s.primed && isfinite(SMD_ATAN2(u.im, u.re));
            smd_emf_pos_step(&p, &s, u);
            /* limited from the first speed update on (the reset's w_r0 is
             * the caller's) */
            if (since_reset > 0 && isfinite(s.w_r_hat)) {
                FZ_CHECK(s.w_r_hat <= p.w_max && s.w_r_hat >= -p.w_max);
            }
            fz_use((double)s.theta_r_hat + (double)s.w_r_raw + (double)s.dir);
        }
    }
}

static void fuzz_pll(fz *f)
{
    smd_pll_params p;
    smd_pll_state s;
    smd_real T = fz_r(f, 0.0, 1e-3), kt = fz_r(f, 0.0, 2.0), kw = fz_r(f, 0.0, 1e3);
    smd_real ka = fz_r(f, 0.0, 1e4);
    int steps = 0;
    if (smd_pll_init(&p, T, kt, kw, ka) != SMD_OK) {
        return;
    }
    {
        smd_real th0 = fz_r(f, -4.0, 4.0);
        smd_pll_reset(&s, th0, fz_r(f, -3e4, 3e4));
    }
    while (fz_more(f) && steps < FZ_MAX_STEPS) {
        uint8_t op = fz_u8(f);
        smd_real e = fz_r(f, -3.2, 3.2);
        int n = (op & 1) ? 1 + fz_u8(f) : 1, k;
        if (op & 2) {
            smd_real th0 = fz_r(f, -4.0, 4.0);
            smd_pll_reset(&s, th0, fz_r(f, -3e4, 3e4));
        }
        for (k = 0; k < n && steps < FZ_MAX_STEPS; k++, steps++) {
            smd_pll_step(&p, &s, e);
            fz_use((double)s.theta + (double)s.w + (double)s.a);
        }
    }
}

static void fuzz_bandpass(fz *f)
{
    smd_bandpass bp;
    int steps = 0;
    memset(&bp, 0, sizeof bp);
    smd_bandpass_reset(&bp);
    FZ_CHECK(smd_bandpass_set(0, SMD_R(1.0), SMD_R(1.0), SMD_R(1e-4)) == SMD_ERR_NULL);
    while (fz_more(f) && steps < FZ_MAX_STEPS) {
        uint8_t op = fz_u8(f);
        int n = (op & 1) ? 1 + fz_u8(f) : 1, k;
        rot r;
        smd_cplx one = smd_c(SMD_R(0.0), SMD_R(0.0));
        if (op & 2) {
            smd_real T = fz_r(f, 0.0, 1e-3), w_n = fz_r(f, 0.0, 3e4), Om = fz_r(f, 0.0, 3e4);
            smd_status st = smd_bandpass_set(&bp, w_n, Om, T);
            fz_use((double)st);
        }
        if (op & 4) {
            smd_bandpass_reset(&bp);
        }
        if (op & 1) {
            rot_read(f, &r, 1e3);
        } else {
            one = fz_c(f, 1e3);
        }
        for (k = 0; k < n && steps < FZ_MAX_STEPS; k++, steps++) {
            fz_use_c(smd_bandpass_step(&bp, (op & 1) ? rot_next(&r) : one));
        }
    }
}

/* One of commissioning's tests (smd_ident.h) on the decoded input sequence
 * (op byte: bit 1 a reset first, odd a run of 1 + u8 steps on the same
 * currents and DC link), its status and duties checked after every step,
 * then its own checks (check, with the duties). */
typedef struct ident_fz {
    smd_status (*step)(void *t, smd_real ia, smd_real ib, smd_real u_dc, smd_real d[3]);
    void (*reset)(void *t);
    void (*check)(const void *t, const smd_real d[3]);
    void *t;
} ident_fz;

static void ident_run(fz *f, const ident_fz *x)
{
    int steps = 0;
    x->reset(x->t);
    while (fz_more(f) && steps < FZ_MAX_STEPS) {
        uint8_t op = fz_u8(f);
        smd_real ia = fz_r(f, -300.0, 300.0), ib = fz_r(f, -300.0, 300.0);
        smd_real u_dc = fz_r(f, -10.0, 1000.0);
        int n = (op & 1) ? 1 + fz_u8(f) : 1, k;
        if (op & 2) {
            x->reset(x->t);
        }
        for (k = 0; k < n && steps < FZ_MAX_STEPS; k++, steps++) {
            smd_real d[3];
            smd_status st = x->step(x->t, ia, ib, u_dc, d);
            int j;
            FZ_CHECK(st == SMD_OK || st == SMD_ERR_FAULT);
            for (j = 0; j < 3; j++) {
                FZ_CHECK(d[j] >= SMD_R(0.0) && d[j] <= SMD_R(1.0));
            }
            x->check(x->t, d);
        }
    }
}

typedef struct rs_t { smd_ident_rs_params p; smd_ident_rs_state s; } rs_t;
typedef struct ls_t { smd_ident_ls_params p; smd_ident_ls_state s; } ls_t;
typedef struct psi_t { smd_ident_psi_params p; smd_ident_psi_state s; } psi_t;
typedef struct mech_t { smd_ident_mech_params p; smd_ident_mech_state s; } mech_t;

/* step 4 through the same loop: i_a is the drive's torque current, i_b its
 * speed estimate, a negative u_dc its fault word, u_dc = 0 a drive not on its
 * source; no duties (0.5) */
static smd_status mech_step(void *t, smd_real ia, smd_real ib, smd_real u_dc, smd_real d[3])
{
    mech_t *x = (mech_t *)t;
    const smd_real ref = smd_ident_mech_ref(&x->p, &x->s);
    FZ_CHECK(isfinite(ref));
    (void)smd_ident_mech_step(&x->p, &x->s, ia, ib, u_dc != SMD_R(0.0),
                              u_dc < SMD_R(0.0) ? 1u : 0u);
    d[0] = d[1] = d[2] = SMD_R(0.5);
    return SMD_OK;
}
static void mech_reset(void *t) { smd_ident_mech_reset(&((mech_t *)t)->s); }
static void mech_check(const void *t, const smd_real d[3])
{
    const mech_t *x = (const mech_t *)t;
    (void)d;
    FZ_CHECK(x->s.k >= 0 && x->s.k <= x->p.n_end + x->p.n_coast && x->s.nb >= 0 &&
             x->s.nb < x->p.n_bin && x->s.crows >= 0 && x->s.rows >= 0);
    if (x->s.outcome == SMD_IDENT_OK) {
        FZ_CHECK(isfinite(x->s.J) && x->s.J > SMD_R(0.0) && isfinite(x->s.B) &&
                 x->s.B >= SMD_R(0.0) && isfinite(x->s.K) && x->s.K >= SMD_R(0.0));
    }
    FZ_CHECK(x->s.n_closed >= 0 && x->s.n_closed <= x->p.n_settle && x->s.wait >= 0 &&
             x->s.wait <= x->p.n_end);
    fz_use((double)x->s.J + (double)x->s.B + (double)x->s.K);
}

static smd_status rs_step(void *t, smd_real ia, smd_real ib, smd_real u_dc, smd_real d[3])
{
    rs_t *x = (rs_t *)t;
    return smd_ident_rs_step(&x->p, &x->s, ia, ib, u_dc, d);
}
static void rs_reset(void *t) { smd_ident_rs_reset(&((rs_t *)t)->s); }
static void rs_check(const void *t, const smd_real d[3])
{
    const rs_t *x = (const rs_t *)t;
    if (x->s.phase == SMD_IDENT_DONE || x->s.phase == SMD_IDENT_FAILED) {
        FZ_CHECK(d[0] == SMD_R(0.5) && d[1] == SMD_R(0.5) && d[2] == SMD_R(0.5));
    }
    FZ_CHECK(x->s.level >= 0 && x->s.level <= x->p.levels);
    if (x->s.phase == SMD_IDENT_DONE && x->s.outcome == SMD_IDENT_OK) {
        FZ_CHECK(isfinite(x->s.R_s) && isfinite(x->s.u_0));
    }
    fz_use((double)x->s.u + (double)x->s.R_s);
}

static smd_status ls_step(void *t, smd_real ia, smd_real ib, smd_real u_dc, smd_real d[3])
{
    ls_t *x = (ls_t *)t;
    return smd_ident_ls_step(&x->p, &x->s, ia, ib, u_dc, d);
}
static void ls_reset(void *t) { smd_ident_ls_reset(&((ls_t *)t)->s); }
static void ls_check(const void *t, const smd_real d[3])
{
    const ls_t *x = (const ls_t *)t;
    (void)d;
    FZ_CHECK(x->s.k >= 0 && x->s.k < 2 * x->p.n_half);
    if (x->s.phase == SMD_IDENT_LS_DONE && x->s.outcome == SMD_IDENT_OK) {
        FZ_CHECK(isfinite(x->s.L) && x->s.L > SMD_R(0.0));
    }
    fz_use((double)x->s.du + (double)x->s.L);
}

static smd_status psi_step(void *t, smd_real ia, smd_real ib, smd_real u_dc, smd_real d[3])
{
    psi_t *x = (psi_t *)t;
    return smd_ident_psi_step(&x->p, &x->s, ia, ib, ia, ib, u_dc, d);
}
static void psi_reset(void *t) { smd_ident_psi_reset(&((psi_t *)t)->s); }
static void psi_check(const void *t, const smd_real d[3])
{
    const psi_t *x = (const psi_t *)t;
    FZ_CHECK(isfinite(x->s.theta_f) && isfinite(x->s.w_f));
    FZ_CHECK(x->s.pwm_off >= 0 && x->s.pwm_off <= 2);
    if (x->s.pwm_off == 2) {
        /* the shorted coast: every lower switch on, the duties 0, no filter */
        FZ_CHECK(x->s.shorted && x->s.phase == SMD_IDENT_PSI_COAST && x->p.L1 == SMD_R(0.0));
        FZ_CHECK(d[0] == SMD_R(0.0) && d[1] == SMD_R(0.0) && d[2] == SMD_R(0.0));
    }
    fz_use((double)x->s.psi + (double)x->s.x_i.re);
}

static void fuzz_ident(fz *f)
{
    rs_t x;
    smd_ident_rs_config c;
    ident_fz run = {rs_step, rs_reset, rs_check, &x};
    c.T_sp = fz_r(f, 0.0, 1e-3);
    c.i_test = fz_r(f, -1.0, 200.0);
    c.u_max = fz_r(f, -1.0, 1000.0);
    c.t_win = fz_r(f, 0.0, 0.05);
    c.t_level_max = fz_r(f, 0.0, 0.5);
    c.levels = fz_int(f, 0, 40);
    if (smd_ident_rs_init(&x.p, &c) != SMD_OK) {
        return;
    }
    FZ_CHECK(smd_ident_rs_init(0, &c) == SMD_ERR_NULL);
    ident_run(f, &run);
}

static void fuzz_ident_ls(fz *f)
{
    ls_t x;
    smd_ident_ls_config c;
    ident_fz run = {ls_step, ls_reset, ls_check, &x};
    c.T_sp = fz_r(f, 0.0, 1e-3);
    c.R_s = fz_r(f, -1.0, 100.0);
    c.u_0 = fz_r(f, -1.0, 50.0);
    c.i_bias = fz_r(f, -1.0, 100.0);
    c.u_max = fz_r(f, -1.0, 1000.0);
    c.t_win = fz_r(f, 0.0, 0.05);
    c.axis = fz_int(f, -1, 2);
    c.n_half = fz_int(f, 0, 80);
    c.periods = fz_int(f, 0, 200);
    if (smd_ident_ls_init(&x.p, &c) != SMD_OK) {
        return;
    }
    FZ_CHECK(smd_ident_ls_init(0, &c) == SMD_ERR_NULL);
    ident_run(f, &run);
}

static void fuzz_ident_psi(fz *f)
{
    psi_t x;
    smd_ident_psi_config c;
    ident_fz run = {psi_step, psi_reset, psi_check, &x};
    c.T_sp = fz_r(f, 0.0, 1e-3);
    c.R_s = fz_r(f, -1.0, 100.0);
    c.L_s = fz_r(f, -1e-3, 0.1);
    c.u_0 = fz_r(f, -1.0, 50.0);
    c.i_spin = fz_r(f, -1.0, 100.0);
    c.w1 = fz_r(f, -10.0, 3000.0);
    c.w2 = fz_r(f, -10.0, 6000.0);
    c.a_spin = fz_r(f, -1.0, 1e5);
    c.t_hold = fz_r(f, 0.0, 0.2);
    c.t_coast = fz_r(f, 0.0, 0.2);
    c.w_cc = fz_r(f, -1.0, 1e4);
    c.L1 = fz_r(f, -1e-5, 1e-3);
    c.C1 = fz_r(f, -1e-6, 1e-4);
    c.L2o = fz_r(f, -1e-5, 1e-3);
    c.w_damp = fz_r(f, -1.0, 2e3);
    c.share_max = fz_r(f, -0.1, 1.2);
    if (smd_ident_psi_init(&x.p, &c) != SMD_OK) {
        return;
    }
    FZ_CHECK(smd_ident_psi_init(0, &c) == SMD_ERR_NULL);
    ident_run(f, &run);
}

static void fuzz_ident_mech(fz *f)
{
    mech_t x;
    smd_ident_mech_config c;
    ident_fz run = {mech_step, mech_reset, mech_check, &x};
    c.T_sp = fz_r(f, 0.0, 1e-3);
    c.k_t = fz_r(f, -1.0, 10.0);
    c.n_p = fz_int(f, 0, 120);
    c.w1 = fz_r(f, -10.0, 3000.0);
    c.w2 = fz_r(f, -10.0, 6000.0);
    c.t_step = fz_r(f, 0.0, 0.1);
    c.t_ramp = fz_r(f, 0.0, 0.1);
    c.t_hold = fz_r(f, 0.0, 0.1);
    c.t_fit = fz_r(f, 0.0, 0.05);
    c.t_bin = fz_r(f, 0.0, 0.01);
    c.w_lpf = fz_r(f, -1.0, 1e4);
    c.fan = fz_int(f, -1, 2);
    c.t_coast = fz_r(f, -0.01, 0.05);
    if (smd_ident_mech_init(&x.p, &c) != SMD_OK) {
        return;
    }
    FZ_CHECK(smd_ident_mech_init(0, &c) == SMD_ERR_NULL);
    ident_run(f, &run);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz f = {data, size};
    const uint8_t b = fz_u8(&f);
    if (b >= 0xFB) {
        fuzz_ident_psi(&f);
        return 0;
    }
    if (b >= 0xF6) {
        fuzz_ident_ls(&f);
        return 0;
    }
    if (b >= 0xF0) {
        fuzz_ident(&f);
        return 0;
    }
    if (b >= 0xEC) {
        fuzz_ident_mech(&f);
        return 0;
    }
    switch (b % 7) {
    case 0: fuzz_svm(&f); break;
    case 1: fuzz_pi(&f); break;
    case 2: fuzz_dbpc(&f); break;
    case 3: fuzz_smdo(&f); break;
    case 4: fuzz_emf_pos(&f); break;
    case 5: fuzz_pll(&f); break;
    default: fuzz_bandpass(&f); break;
    }
    return 0;
}

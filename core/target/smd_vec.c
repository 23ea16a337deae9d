/*
 * Test-vector and processor-in-the-loop runner (smd_vec.h). The same C on
 * the host and on the Cortex-M4F: what it writes is compared bit for bit.
 */
#include "smd_vec.h"

#include <string.h>

#include "smodrive/smd_bandpass.h"
#include "smodrive/smd_dbpc.h"
#include "smodrive/smd_drive.h"
#include "smodrive/smd_emf_pos.h"
#include "smodrive/smd_ident.h"
#include "smodrive/smd_lcl_linobs.h"
#include "smodrive/smd_lcl_smo.h"
#include "smodrive/smd_pi.h"
#include "smodrive/smd_pll.h"
#include "smodrive/smd_smdo.h"
#include "smodrive/smd_svm.h"
#include "smodrive/smd_transforms.h"

/* ------------------------------------------------------------ buffered I/O */

#define SMD_BUF 4096

typedef struct smd_reader {
    int h;
    int pos, len;
    int eof;
    unsigned char buf[SMD_BUF];
} smd_reader;

#define SMD_CASE_MAX (1 << 20)

/* Output: a case's outputs are collected (capture) and written behind their
 * length, so that a reader can split the file into cases; a streamed drive
 * case (PIL) writes each sample at once. */
typedef struct smd_writer {
    int h;
    int len;
    int err;
    int capture;
    int cap_len;
    unsigned char buf[SMD_BUF];
    unsigned char cap[SMD_CASE_MAX];
} smd_writer;

/* n bytes; returns the number read (< n only at the end of the stream). A
 * FIFO may deliver fewer bytes than asked: read again until n or the end. */
static int rd_bytes(smd_reader *r, void *dst, int n)
{
    unsigned char *d = (unsigned char *)dst;
    int got = 0;
    while (got < n) {
        if (r->pos == r->len) {
            int m;
            if (r->eof) break;
            m = smd_io_read(r->h, r->buf, SMD_BUF);
            if (m <= 0) {
                r->eof = 1;
                break;
            }
            r->pos = 0;
            r->len = m;
        }
        {
            int k = r->len - r->pos;
            if (k > n - got) k = n - got;
            memcpy(d + got, r->buf + r->pos, (size_t)k);
            r->pos += k;
            got += k;
        }
    }
    return got;
}

static void smd_rd_reals(smd_reader *r, smd_real *x, unsigned long n)
{
    if (rd_bytes(r, x, (int)(n * sizeof(smd_real))) != (int)(n * sizeof(smd_real))) {
        memset(x, 0, n * sizeof(smd_real));
    }
}

static void smd_rd_ints(smd_reader *r, int *x, unsigned long n)
{
    int32_t v;
    unsigned long k;
    for (k = 0; k < n; k++) {
        x[k] = rd_bytes(r, &v, 4) == 4 ? (int)v : 0;
    }
}

static int32_t rd_i32(smd_reader *r, int *ok)
{
    int32_t v = 0;
    if (rd_bytes(r, &v, 4) != 4) *ok = 0;
    return v;
}

static void wr_flush(smd_writer *w)
{
    if (w->len > 0 && smd_io_write(w->h, w->buf, w->len) != w->len) w->err = 1;
    w->len = 0;
}

static void wr_bytes(smd_writer *w, const void *src, int n)
{
    const unsigned char *s = (const unsigned char *)src;
    if (w->capture) {
        if (w->cap_len + n > SMD_CASE_MAX) {
            w->err = 1;
            return;
        }
        memcpy(w->cap + w->cap_len, s, (size_t)n);
        w->cap_len += n;
        return;
    }
    while (n > 0) {
        int k = SMD_BUF - w->len;
        if (k > n) k = n;
        memcpy(w->buf + w->len, s, (size_t)k);
        w->len += k;
        s += k;
        n -= k;
        if (w->len == SMD_BUF) wr_flush(w);
    }
}

static void wr_i32(smd_writer *w, int v)
{
    int32_t x = (int32_t)v;
    wr_bytes(w, &x, 4);
}

static void wr_real(smd_writer *w, smd_real v) { wr_bytes(w, &v, (int)sizeof v); }
static void wr_cplx(smd_writer *w, smd_cplx v)
{
    wr_real(w, v.re);
    wr_real(w, v.im);
}
static void wr_reals(smd_writer *w, const smd_real *v, int n) { wr_bytes(w, v, n * (int)sizeof *v); }

static void wr_case_begin(smd_writer *w)
{
    w->capture = 1;
    w->cap_len = 0;
}

/* kind, length in bytes, then the captured outputs */
static void wr_case_end(smd_writer *w, int kind)
{
    int32_t head[2];
    w->capture = 0;
    head[0] = (int32_t)kind;
    head[1] = (int32_t)w->cap_len;
    wr_bytes(w, head, 8);
    wr_bytes(w, w->cap, w->cap_len);
}

#include "smd_cfg_read.h"

/* ------------------------------------------------------------- the cases */

#define SMD_VEC_MAX_MODELS 512

/* The harness's storage (the core itself has none): observer tables and the
 * reader/writer buffers. */
static smd_lcl_model g_models[SMD_VEC_MAX_MODELS];
static smd_linobs_model g_lins[SMD_VEC_MAX_MODELS];
static int g_n_models, g_n_lins;
static smd_real g_w_min, g_dw;
static smd_reader g_rd;
static smd_writer g_wr;
static smd_drive_params g_dp;
static smd_drive_state g_ds;

typedef char smd_in_is_10_reals[(sizeof(smd_drive_in) == 10 * sizeof(smd_real)) ? 1 : -1];
typedef char smd_model_words[(sizeof(smd_lcl_model) % 4 == 0) ? 1 : -1];

static void __attribute__((noinline)) mark_sink(int id)
{
    __asm__ volatile("" : : "r"(id) : "memory");
}
void __attribute__((noinline)) smd_mark_begin(int id) { mark_sink(id); }
void __attribute__((noinline)) smd_mark_end(void) { mark_sink(-1); }

static int read_tables(smd_reader *r)
{
    int ok = 1;
    int n = (int)rd_i32(r, &ok);
    if (!ok || n < 0 || n > SMD_VEC_MAX_MODELS) return 0;
    g_n_models = n;
    if (n > 0) smd_rd_reals(r, (smd_real *)g_models, (unsigned long)n * sizeof(smd_lcl_model) / sizeof(smd_real));
    n = (int)rd_i32(r, &ok);
    if (!ok || n < 0 || n > SMD_VEC_MAX_MODELS) return 0;
    g_n_lins = n;
    if (n > 0) smd_rd_reals(r, (smd_real *)g_lins, (unsigned long)n * sizeof(smd_linobs_model) / sizeof(smd_real));
    return 1;
}

static int run_drive(smd_reader *r, smd_writer *w)
{
    smd_drive_config c;
    smd_real start[3];
    smd_status st;
    int ok = 1;
    int32_t n, k;
    memset(&c, 0, sizeof c);
    smd_rd_smd_drive_config(r, &c);
    if (!read_tables(r)) return 0;
    c.smo.table = g_n_models > 0 ? g_models : 0;
    c.lin.table = g_n_lins > 0 ? g_lins : 0;
    smd_rd_reals(r, start, 3);
    n = rd_i32(r, &ok);
    if (!ok) return 0;
    st = smd_drive_init(&g_dp, &c);
    if (n < 0) {
        wr_i32(w, SMD_CASE_DRIVE); /* streamed: no length */
        wr_i32(w, -1);
    } else {
        wr_case_begin(w);
    }
    wr_i32(w, (int)st);
    if (n < 0) wr_flush(w);
    if (st != SMD_OK) {
        /* the inputs are still in the file: skip them */
        smd_drive_in in;
        for (k = 0; n < 0 || k < n; k++) {
            if (rd_bytes(r, &in, (int)sizeof in) != (int)sizeof in) break;
        }
        if (n >= 0) wr_case_end(w, SMD_CASE_DRIVE);
        return 1;
    }
    smd_drive_reset(&g_dp, &g_ds, start[0], start[1], start[2]);
    for (k = 0; n < 0 || k < n; k++) {
        smd_drive_in in;
        smd_drive_out out;
        smd_drive_view v;
        if (rd_bytes(r, &in, (int)sizeof in) != (int)sizeof in) {
            if (n < 0) break; /* PIL: the host closed the stream */
            return 0;
        }
        if (k == 0) {
            /* the period before the first sample applied the steady state of
             * the start (smd_drive_start_duties, as the engine's plant did):
             * the drive records it, from the first measured DC link */
            smd_real d0[3];
            smd_drive_start_duties(&g_dp, &g_ds, in.u_dc, d0);
        }
        smd_mark_begin(1000 + g_dp.current * 100 + g_dp.position * 10 + g_dp.start);
        st = smd_drive_step(&g_dp, &g_ds, &in, &out);
        smd_mark_end();
        v = smd_drive_get_view(&g_dp, &g_ds);
        wr_i32(w, (int)st);
        wr_reals(w, out.d_abc, 3);
        wr_i32(w, (int)out.fault);
        wr_i32(w, out.pwm_off);
        wr_bytes(w, &v, (int)sizeof v);
        if (n < 0) wr_flush(w);
    }
    if (n >= 0) wr_case_end(w, SMD_CASE_DRIVE);
    return 1;
}

/* Portable PRNG (xorshift32): the same sequence on every target. */
typedef struct rng {
    uint32_t x;
} rng;

static uint32_t rnext(rng *g)
{
    uint32_t x = g->x;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    g->x = x;
    return x;
}

/* Uniform in [lo, hi): an exact 24-bit integer scaled in float. */
static smd_real urand(rng *g, smd_real lo, smd_real hi)
{
    smd_real u = (smd_real)(rnext(g) >> 8) * SMD_R(5.9604644775390625e-08);
    return lo + (hi - lo) * u;
}

/* Edge values in the last tenth of a run: NaN, inf, 1e30 and 0 in turn. */
static smd_real edge(rng *g, int k, int n, smd_real x)
{
    if (k * 10 < n * 9) return x;
    switch (rnext(g) % 8u) {
    case 0: return SMD_R(NAN);
    case 1: return SMD_R(INFINITY);
    case 2: return -SMD_R(INFINITY);
    case 3: return SMD_R(1e30);
    case 4: return SMD_R(0.0);
    default: return x;
    }
}

static smd_cplx crand(rng *g, smd_real a)
{
    smd_real re = urand(g, -a, a);
    return smd_c(re, urand(g, -a, a));
}

static void blk_transforms(smd_writer *w, rng *g, int n)
{
    int k;
    for (k = 0; k < n; k++) {
        smd_real x[3], y[3], th;
        smd_cplx c;
        x[0] = edge(g, k, n, urand(g, SMD_R(-100.0), SMD_R(100.0)));
        x[1] = urand(g, SMD_R(-100.0), SMD_R(100.0));
        x[2] = urand(g, SMD_R(-100.0), SMD_R(100.0));
        th = edge(g, k, n, urand(g, SMD_R(-20.0), SMD_R(20.0)));
        smd_mark_begin(SMD_BLK_TRANSFORMS);
        c = smd_abc_to_ab(x);
        smd_mark_end();
        wr_cplx(w, c);
        wr_cplx(w, smd_ab2_to_ab(x[0], x[1]));
        smd_ab_to_abc(c, y);
        wr_reals(w, y, 3);
        wr_cplx(w, smd_ab_to_dq(c, th));
        wr_cplx(w, smd_dq_to_ab(c, th));
        wr_real(w, smd_wrap_pi(th));
    }
}

static void blk_svm(smd_writer *w, rng *g, int n)
{
    smd_svm_params pc, ph;
    int k;
    wr_i32(w, (int)smd_svm_init(&pc, SMD_SVM_LIMIT_CIRCLE, SMD_R(0.0)));
    wr_i32(w, (int)smd_svm_init(&ph, SMD_SVM_LIMIT_HEXAGON, SMD_R(0.02)));
    for (k = 0; k < n; k++) {
        smd_real d[3], i_abc[3];
        smd_cplx u_app;
        smd_cplx u = crand(g, SMD_R(450.0)); /* beyond 540/sqrt(3) at times: saturation */
        smd_real u_dc = (k % 50 == 7) ? SMD_R(0.0) : urand(g, SMD_R(100.0), SMD_R(600.0));
        u.re = edge(g, k, n, u.re);
        smd_mark_begin(SMD_BLK_SVM);
        smd_svm_step(&ph, u, u_dc, d, &u_app);
        smd_mark_end();
        wr_reals(w, d, 3);
        wr_cplx(w, u_app);
        smd_svm_step(&pc, u, u_dc, d, &u_app);
        wr_reals(w, d, 3);
        wr_cplx(w, u_app);
        i_abc[0] = urand(g, SMD_R(-20.0), SMD_R(20.0));
        i_abc[1] = urand(g, SMD_R(-2.0), SMD_R(2.0));
        i_abc[2] = edge(g, k, n, -i_abc[0] - i_abc[1]);
        smd_svm_deadtime_comp(d, i_abc, SMD_R(0.02), SMD_R(1.0));
        wr_reals(w, d, 3);
    }
}

static void blk_pi(smd_writer *w, rng *g, int n)
{
    smd_pi_params p;
    smd_pi_state s;
    int k;
    wr_i32(w, (int)smd_pi_init(&p, SMD_R(0.05), SMD_R(2.0), SMD_R(1e-4), SMD_R(15.0)));
    smd_pi_reset(&s, SMD_R(1.0));
    for (k = 0; k < n; k++) {
        smd_real e = edge(g, k, n, urand(g, SMD_R(-500.0), SMD_R(500.0)));
        smd_real y;
        smd_mark_begin(SMD_BLK_PI);
        y = smd_pi_step(&p, &s, e);
        smd_mark_end();
        wr_real(w, y);
        wr_real(w, s.x_i);
    }
}

static void blk_dbpc(smd_writer *w, rng *g, int n)
{
    smd_dbpc_params p;
    int k;
    wr_i32(w, (int)smd_dbpc_init(&p, SMD_R(1e-4), SMD_R(23.45e-3), SMD_R(2.25), SMD_R(0.4)));
    for (k = 0; k < n; k++) {
        smd_cplx i = crand(g, SMD_R(15.0)), u = crand(g, SMD_R(300.0));
        smd_cplx ref = crand(g, SMD_R(10.0)), ud = crand(g, SMD_R(100.0));
        smd_real th = urand(g, -SMD_PI, SMD_PI);
        smd_real wr = edge(g, k, n, urand(g, SMD_R(-1000.0), SMD_R(1000.0)));
        smd_cplx y;
        smd_mark_begin(SMD_BLK_DBPC);
        y = smd_dbpc_conventional(&p, i, u, ref, th, wr);
        smd_mark_end();
        wr_cplx(w, y);
        wr_cplx(w, smd_dbpc_ref_k2(&p, ref, th, wr));
        wr_cplx(w, smd_dbpc_predict(&p, i, u, th, wr));
        wr_cplx(w, smd_dbpc_robust(&p, i, ud, ref));
    }
}

static void blk_smdo(smd_writer *w, rng *g, int n, int euler)
{
    smd_smdo_params p;
    smd_smdo_state s;
    smd_real th = SMD_R(0.0), wr = SMD_R(300.0);
    int k;
    wr_i32(w, (int)smd_smdo_init(&p, SMD_R(1e-4), SMD_R(23.45e-3), SMD_R(2.25), SMD_R(800.0),
                                 SMD_R(1200.0), SMD_R(1500.0), SMD_R(0.2)));
    wr_i32(w, (int)smd_smdo_set_euler(&p, euler));
    smd_smdo_reset(&s, smd_c(SMD_R(0.0), SMD_R(0.0)), smd_c(SMD_R(0.0), SMD_R(0.0)));
    for (k = 0; k < n; k++) {
        smd_cplx e = smd_cexpj(th);
        smd_cplx i = smd_cadd(smd_cscale(smd_cj(e), SMD_R(5.0)), crand(g, SMD_R(0.05)));
        smd_cplx u = smd_cscale(smd_cmul(e, smd_cexpj(SMD_R(1.8))), SMD_R(0.4) * wr + SMD_R(20.0));
        smd_status st;
        /* speed: a random walk through zero and both signs */
        wr += urand(g, SMD_R(-8.0), SMD_R(8.0)) - SMD_R(0.002) * wr;
        th = smd_wrap_pi(th + wr * SMD_R(1e-4));
        i.re = edge(g, k, n, i.re);
        smd_mark_begin(SMD_BLK_SMDO);
        st = smd_smdo_step(&p, &s, i, u, wr);
        smd_mark_end();
        wr_i32(w, (int)st);
        wr_cplx(w, s.i_s_hat);
        wr_cplx(w, s.u_d_hat);
        wr_cplx(w, s.u_smo);
        wr_real(w, s.lambda);
    }
}

static void blk_emf_pos(smd_writer *w, rng *g, int n)
{
    smd_emf_pos_params p;
    smd_emf_pos_state s;
    smd_real th = SMD_R(0.5), wr = SMD_R(-200.0);
    int k;
    wr_i32(w, (int)smd_emf_pos_init(&p, SMD_R(1e-4), SMD_R(200.0), SMD_R(20.0), SMD_R(2000.0)));
    smd_emf_pos_reset(&s, wr);
    for (k = 0; k < n; k++) {
        smd_cplx ud;
        wr += urand(g, SMD_R(-6.0), SMD_R(6.5));
        if (k % 400 == 399) wr = SMD_R(0.0); /* zero speed now and then */
        th = smd_wrap_pi(th + wr * SMD_R(1e-4));
        ud = smd_cadd(smd_cscale(smd_cexpj(th + SMD_R(1.5707963)), SMD_R(0.4) * wr),
                      crand(g, SMD_R(0.5)));
        ud.im = edge(g, k, n, ud.im);
        smd_mark_begin(SMD_BLK_EMF_POS);
        smd_emf_pos_step(&p, &s, ud);
        smd_mark_end();
        wr_real(w, s.theta_r_hat);
        wr_real(w, s.w_r_hat);
        wr_real(w, s.w_r_raw);
        wr_real(w, s.w_r_dir);
        wr_i32(w, s.dir);
    }
}

static void blk_pll(smd_writer *w, rng *g, int n)
{
    smd_pll_params p;
    smd_pll_state s;
    int k;
    wr_i32(w, (int)smd_pll_init(&p, SMD_R(5e-5), SMD_R(0.1), SMD_R(10.0), SMD_R(10.0)));
    smd_pll_reset(&s, SMD_R(0.3), SMD_R(-5000.0));
    for (k = 0; k < n; k++) {
        smd_real e = edge(g, k, n, urand(g, SMD_R(-0.5), SMD_R(0.5)));
        smd_mark_begin(SMD_BLK_PLL);
        smd_pll_step(&p, &s, e);
        smd_mark_end();
        wr_real(w, s.theta);
        wr_real(w, s.w);
        wr_real(w, s.a);
    }
}

/* Commissioning's R_s test (smd_ident.h) on a stator at standstill along
 * alpha (yang2018 Table I: 2.25 ohm, 23.45 mH; 14.4 V of inverter drop
 * against the current, clamped at zero), solved exactly in float each sample
 * with the duties of the sample before, +-0.05 A of noise on the current;
 * the test's windows shortened (2 ms) so that the search, the staircase and
 * the fit all happen within a few thousand samples. */
static void blk_ident(smd_writer *w, rng *g, int n)
{
    smd_ident_rs_config c;
    smd_ident_rs_params p;
    smd_ident_rs_state s;
    const smd_real Rs = SMD_R(2.25), U0 = SMD_R(14.4), udc = SMD_R(540.0);
    const smd_real e = SMD_EXP(-Rs / SMD_R(23.45e-3) * SMD_R(1e-4));
    smd_real i = SMD_R(0.0), u_now = SMD_R(0.0);
    int k;
    c.T_sp = SMD_R(1e-4);
    c.i_test = SMD_R(4.0);
    c.u_max = SMD_R(311.0);
    c.t_win = SMD_R(2e-3);
    c.t_level_max = SMD_R(0.2);
    c.levels = 8;
    wr_i32(w, (int)smd_ident_rs_init(&p, &c));
    smd_ident_rs_reset(&s);
    for (k = 0; k < n; k++) {
        smd_real d[3], ia, u, sg;
        smd_status st;
        ia = edge(g, k, n, i + urand(g, SMD_R(-0.05), SMD_R(0.05)));
        smd_mark_begin(SMD_BLK_IDENT);
        st = smd_ident_rs_step(&p, &s, ia, SMD_R(-0.5) * ia, udc, d);
        smd_mark_end();
        wr_i32(w, (int)st);
        wr_i32(w, s.phase);
        wr_i32(w, s.outcome);
        wr_reals(w, d, 3);
        /* the plant over [t_k, t_k+1), with the voltage computed at k - 1 */
        sg = i > SMD_R(0.0) ? SMD_R(1.0) : (i < SMD_R(0.0) ? SMD_R(-1.0)
                                                          : (u_now > SMD_R(0.0) ? SMD_R(1.0)
                                                                                : SMD_R(-1.0)));
        u = u_now - U0 * sg;
        i = e * (i - u / Rs) + u / Rs;
        i = i * sg < SMD_R(0.0) ? SMD_R(0.0) : i;
        u_now = SMD_R(2.0) / SMD_R(3.0) * udc * (d[0] - SMD_R(0.5) * (d[1] + d[2]));
    }
    wr_real(w, s.R_s);
    wr_real(w, s.u_0);
    wr_real(w, s.r2);
}

/* Commissioning's steps 2 and 3 (smd_ident.h) on a stimulus, for the
 * host-against-target comparison and the cycle table (their accuracy is
 * tested against the simulator's plant, tests/test_commission.py): the
 * inductance test on the d axis of a float stator (Table I, 2.25 ohm,
 * 23.45 mH, 14.4 V of drop against the current), solved by forward Euler
 * over ten sub-steps a sample; the flux test on a stator whose rotor turns
 * with the forced frame, 20 deg behind it (EMF j w psi e^{j theta_r}, psi 0.4
 * Wb), the same way. Noise of +-0.05 A on the currents. */
static void stator_euler(smd_cplx *i, smd_cplx u, smd_cplx e, smd_real U0)
{
    int j;
    for (j = 0; j < 10; j++) {
        const smd_real m = smd_cabs(*i);
        smd_cplx drop = m > SMD_R(1e-6) ? smd_cscale(*i, U0 / m) : smd_c(SMD_R(0.0), SMD_R(0.0));
        smd_cplx v = smd_csub(smd_csub(smd_csub(u, smd_cscale(*i, SMD_R(2.25))), e), drop);
        *i = smd_cadd(*i, smd_cscale(v, SMD_R(1e-5) / SMD_R(23.45e-3)));
    }
}

static void blk_ident_ls(smd_writer *w, rng *g, int n)
{
    smd_ident_ls_config c;
    smd_ident_ls_params p;
    smd_ident_ls_state s;
    smd_cplx i = smd_c(SMD_R(0.0), SMD_R(0.0)), u_now = i;
    const smd_real udc = SMD_R(540.0);
    int k;
    c.T_sp = SMD_R(1e-4);
    c.R_s = SMD_R(2.25);
    c.u_0 = SMD_R(14.4);
    c.i_bias = SMD_R(2.0);
    c.u_max = SMD_R(311.0);
    c.t_win = SMD_R(2e-3);
    c.axis = (int)(g->x % 2u);
    c.n_half = 8;
    c.periods = 20;
    wr_i32(w, (int)smd_ident_ls_init(&p, &c));
    smd_ident_ls_reset(&s);
    for (k = 0; k < n; k++) {
        smd_real d[3], ia, ib;
        smd_status st;
        smd_real abc[3];
        smd_ab_to_abc(i, abc);
        ia = edge(g, k, n, abc[0] + urand(g, SMD_R(-0.05), SMD_R(0.05)));
        ib = abc[1] + urand(g, SMD_R(-0.05), SMD_R(0.05));
        smd_mark_begin(SMD_BLK_IDENT_LS);
        st = smd_ident_ls_step(&p, &s, ia, ib, udc, d);
        smd_mark_end();
        wr_i32(w, (int)st);
        wr_i32(w, s.phase);
        wr_reals(w, d, 3);
        stator_euler(&i, u_now, smd_c(SMD_R(0.0), SMD_R(0.0)), SMD_R(14.4));
        u_now = s.u_applied;
    }
    wr_real(w, s.L);
    wr_real(w, s.R_ac);
}

static void blk_ident_psi(smd_writer *w, rng *g, int n)
{
    smd_ident_psi_config c;
    smd_ident_psi_params p;
    smd_ident_psi_state s;
    smd_cplx i = smd_c(SMD_R(0.0), SMD_R(0.0)), u_now = i;
    const smd_real udc = SMD_R(540.0);
    /* an even seed: behind an LCL filter (the inverter's current the
     * motor's plus a capacitor's, from the applied voltage) */
    const int lcl = (int)(g->x % 2u) == 0;
    /* a seed 1 mod 3 without a filter: an inverter's drop over a fifth of the
     * EMF, the coast shorted (pwm_off = 2) */
    const int shorted = !lcl && g->x % 3u == 1u;
    /* (behind the filter a rotor of its own, which keeps the frame's speed
     * from the coast on: the rotor tied to the frame, as without one, runs
     * away with a frame that follows its voltage, and the coast would end
     * before its switches open) */
    smd_real th_rotor = SMD_R(0.0), w_rotor = SMD_R(0.0);
    int k;
    c.T_sp = SMD_R(1e-4);
    c.R_s = SMD_R(2.25);
    c.L_s = SMD_R(23.45e-3);
    c.u_0 = SMD_R(14.4);
    c.i_spin = SMD_R(4.0);
    c.w1 = SMD_R(100.0);
    c.w2 = SMD_R(200.0);
    c.a_spin = SMD_R(2000.0);
    c.t_hold = SMD_R(0.05);
    c.t_coast = SMD_R(0.02);
    c.w_cc = SMD_R(1500.0);
    c.L1 = c.C1 = c.L2o = SMD_R(0.0); /* no filter */
    if (shorted) {
        c.u_0 = SMD_R(40.0);
        c.i_spin = SMD_R(20.0);
    }
    if (lcl) {
        c.L1 = SMD_R(2e-3);
        c.C1 = SMD_R(5e-6);
        c.L2o = SMD_R(1e-3);
    }
    c.w_damp = SMD_R(125.7);
    c.share_max = SMD_R(0.7);
    wr_i32(w, (int)smd_ident_psi_init(&p, &c));
    smd_ident_psi_reset(&s);
    for (k = 0; k < n; k++) {
        smd_real d[3], ia, ib, i1a = SMD_R(0.0), i1b = SMD_R(0.0), abc[3];
        smd_status st;
        smd_real th_r = s.theta_f - SMD_R(0.349), w_r = s.w_f;
        smd_cplx e;
        if (lcl) {
            if (s.phase < SMD_IDENT_PSI_COAST) {
                w_rotor = s.w_f;
                th_rotor = th_r;
            } else {
                th_rotor = smd_wrap_pi(th_rotor + w_rotor * c.T_sp);
            }
            th_r = th_rotor;
            w_r = w_rotor;
        }
        e = smd_cscale(smd_cj(smd_cexpj(th_r)), w_r * SMD_R(0.4));
        smd_ab_to_abc(i, abc);
        ia = edge(g, k, n, abc[0] + urand(g, SMD_R(-0.05), SMD_R(0.05)));
        ib = abc[1] + urand(g, SMD_R(-0.05), SMD_R(0.05));
        if (lcl) {
            const smd_cplx i1 = smd_cadd(i, smd_cscale(smd_cj(u_now), s.w_f * c.C1));
            smd_ab_to_abc(i1, abc);
            i1a = abc[0] + urand(g, SMD_R(-0.05), SMD_R(0.05));
            i1b = abc[1] + urand(g, SMD_R(-0.05), SMD_R(0.05));
        } else {
            i1a = ia;
            i1b = ib;
        }
        smd_mark_begin(SMD_BLK_IDENT_PSI);
        st = smd_ident_psi_step(&p, &s, ia, ib, i1a, i1b, udc, d);
        smd_mark_end();
        wr_i32(w, (int)st);
        wr_i32(w, s.phase);
        wr_i32(w, s.pwm_off);
        wr_reals(w, d, 3);
        if (lcl && s.pwm_off) {
            /* every switch open: the capacitor's current, -j w C1 e */
            i = smd_cscale(smd_cj(e), -w_r * c.C1);
        } else {
            stator_euler(&i, u_now, e, SMD_R(14.4));
        }
        u_now = s.u_applied;
    }
    wr_real(w, s.psi);
    wr_real(w, s.psi_coast);
}

/* Step 4 on a rotor the test drives through a first-order speed loop: its
 * torque current tracks the reference's rate and a noisy speed; a short
 * sequence (8 + 4 + 4 ms and a 10 ms coast, 1 ms bins, the drive on its
 * source from sample 40 and its filter settled 50 later: the fit ends at
 * sample 310, within the vector case's 800), with a fan (the 3 x 3 fit) (no
 * edge values: a non-finite input ends the test, core/test/test_ident.c
 * checks it). */
static void blk_ident_mech(smd_writer *w, rng *g, int n)
{
    smd_ident_mech_config c;
    smd_ident_mech_params p;
    smd_ident_mech_state s;
    smd_real wr = SMD_R(0.0);
    int k;
    c.T_sp = SMD_R(1e-4);
    c.k_t = SMD_R(2.4);
    c.n_p = 4;
    c.w1 = SMD_R(250.0);
    c.w2 = SMD_R(500.0);
    c.t_step = SMD_R(0.008);
    c.t_ramp = SMD_R(0.004);
    c.t_hold = SMD_R(0.004);
    c.t_fit = SMD_R(0.004);
    c.t_bin = SMD_R(0.001);
    c.w_lpf = SMD_R(1000.0);
    c.fan = 1;
    c.t_coast = SMD_R(0.01);
    wr_i32(w, (int)smd_ident_mech_init(&p, &c));
    smd_ident_mech_reset(&s);
    for (k = 0; k < n; k++) {
        const smd_real ref = smd_ident_mech_ref(&p, &s);
        smd_real iq, wh;
        int done;
        wr += SMD_R(0.05) * (ref - wr);
        iq = SMD_R(0.5) + SMD_R(1e-3) * (ref - wr) + urand(g, SMD_R(-0.05), SMD_R(0.05));
        wh = wr + urand(g, SMD_R(-1.0), SMD_R(1.0));
        smd_mark_begin(SMD_BLK_IDENT_MECH);
        done = smd_ident_mech_step(&p, &s, iq, wh, k >= 40, 0u); /* (a start first) */
        smd_mark_end();
        wr_i32(w, done);
        wr_i32(w, s.outcome);
        wr_real(w, ref);
    }
    wr_real(w, s.J);
    wr_real(w, s.B);
    wr_real(w, s.K);
}

static void blk_bandpass(smd_writer *w, rng *g, int n)
{
    smd_bandpass f;
    smd_real th = SMD_R(0.0);
    int k;
    wr_i32(w, (int)smd_bandpass_set(&f, SMD_R(12566.37), SMD_R(2513.27), SMD_R(5e-5)));
    smd_bandpass_reset(&f);
    for (k = 0; k < n; k++) {
        smd_cplx x, y;
        th = smd_wrap_pi(th + SMD_R(0.6283185));
        x = smd_cadd(smd_cexpj(th), crand(g, SMD_R(0.3)));
        x.re = edge(g, k, n, x.re);
        smd_mark_begin(SMD_BLK_BANDPASS);
        y = smd_bandpass_step(&f, x);
        smd_mark_end();
        wr_cplx(w, y);
        if (k % 500 == 250) {
            /* one draw a statement: the order of evaluation of arguments is
             * unspecified in C (and differs between gcc for x86-64 and ARM) */
            smd_real w_n = urand(g, SMD_R(100.0), SMD_R(20000.0));
            smd_real Om = urand(g, SMD_R(10.0), SMD_R(2000.0));
            wr_i32(w, (int)smd_bandpass_set(&f, w_n, Om, SMD_R(5e-5)));
        }
    }
}

/* The LCL observers on the tables of the last TABLES case, at a speed that
 * sweeps the table (and beyond it) in both directions. */
static void blk_lcl_smo(smd_writer *w, rng *g, int n, int law)
{
    smd_lcl_smo_config c;
    smd_lcl_smo_params p;
    static smd_lcl_smo_state s;
    smd_lcl_model m;
    smd_real th = SMD_R(0.0);
    smd_real w_top = g_w_min + g_dw * (smd_real)(g_n_models - 1);
    smd_status st;
    int k;
    memset(&c, 0, sizeof c);
    c.law = law;
    c.table = g_models;
    c.n = g_n_models;
    c.w_min = g_w_min;
    c.dw = g_dw;
    c.Q1 = SMD_R(0.6);
    c.Q2 = SMD_R(0.6);
    c.bw_rel2 = SMD_R(0.2);
    c.bw_rel3 = SMD_R(0.2);
    c.w_bp_min = SMD_R(1000.0);
    st = smd_lcl_smo_init(&p, SMD_R(5e-5), &c);
    wr_i32(w, (int)st);
    if (st != SMD_OK) return;
    smd_lcl_smo_reset(&s, SMD_R(0.0));
    for (k = 0; k < n; k++) {
        /* electrical speed from w_top down to -1.2 w_top over the run */
        smd_real wr = w_top * (SMD_R(1.0) - SMD_R(2.2) * (smd_real)k / (smd_real)n);
        smd_cplx e, i1, i2, u;
        smd_real w_hat = wr + urand(g, SMD_R(-50.0), SMD_R(50.0));
        th = smd_wrap_pi(th + wr * SMD_R(5e-5));
        e = smd_cexpj(th);
        i2 = smd_cadd(smd_cscale(smd_cj(e), SMD_R(2.0)), crand(g, SMD_R(0.1)));
        i1 = smd_cadd(i2, crand(g, SMD_R(0.5)));
        u = smd_cscale(smd_cj(e), SMD_R(0.0012) * wr + SMD_R(1.0));
        i1.re = edge(g, k, n, i1.re);
        smd_mark_begin(SMD_BLK_LCL_SMO);
        st = smd_lcl_smo_step(&p, &s, i1, i2, u, th + urand(g, SMD_R(-0.05), SMD_R(0.05)), w_hat);
        smd_mark_end();
        wr_i32(w, (int)st);
        wr_reals(w, s.e_hat, 2);
        wr_reals(w, s.s, 2);
        wr_reals(w, s.d_hat, 2);
        wr_reals(w, s.x_hat, 6);
        wr_real(w, smd_lcl_smo_theta_err(&s, w_hat));
        if (k % 500 == 499) {
            /* a frame jump, as a start-up handover makes one */
            smd_lcl_smo_reframe(&s, urand(g, SMD_R(-1.0), SMD_R(1.0)));
            wr_reals(w, s.x_hat, 6);
        }
        if (k % 200 == 0) {
            smd_lcl_smo_model(&p, w_hat, &m);
            wr_reals(w, (const smd_real *)&m, (int)(sizeof m / sizeof(smd_real)));
        }
    }
}

static void blk_linobs(smd_writer *w, rng *g, int n)
{
    smd_linobs_config c;
    smd_linobs_params p;
    smd_linobs_state s;
    smd_real th = SMD_R(0.0);
    smd_real w_top = g_w_min + g_dw * (smd_real)(g_n_lins - 1);
    smd_status st;
    int k;
    c.table = g_lins;
    c.n = g_n_lins;
    c.w_min = g_w_min;
    c.dw = g_dw;
    st = smd_linobs_init(&p, &c);
    wr_i32(w, (int)st);
    if (st != SMD_OK) return;
    smd_linobs_reset(&s);
    for (k = 0; k < n; k++) {
        smd_real wr = w_top * (SMD_R(1.0) - SMD_R(2.2) * (smd_real)k / (smd_real)n);
        smd_cplx e, i1, i2, u;
        th = smd_wrap_pi(th + wr * SMD_R(5e-5));
        e = smd_cexpj(th);
        i2 = smd_cadd(smd_cscale(smd_cj(e), SMD_R(2.0)), crand(g, SMD_R(0.1)));
        i1 = smd_cadd(i2, crand(g, SMD_R(0.5)));
        u = smd_cscale(smd_cj(e), SMD_R(0.0012) * wr + SMD_R(1.0));
        i2.im = edge(g, k, n, i2.im);
        smd_mark_begin(SMD_BLK_LINOBS);
        st = smd_linobs_step(&p, &s, i1, i2, u, wr + urand(g, SMD_R(-50.0), SMD_R(50.0)));
        smd_mark_end();
        wr_i32(w, (int)st);
        wr_reals(w, s.x2, 4);
    }
}

/* The math the core calls (smd_types.h hooks), on the arguments it sees:
 * angles to +-40 rad, exponents of -w_lpf T_sp and the like, ratios. Per
 * step: sin, cos, atan2, exp, expm1, floor, sqrt, fabs. */
static void blk_math(smd_writer *w, rng *g, int n)
{
    int k;
    for (k = 0; k < n; k++) {
        smd_real x = (k % 4 == 0) ? urand(g, SMD_R(-40.0), SMD_R(40.0))
                                  : urand(g, SMD_R(-3.5), SMD_R(3.5));
        smd_real y = urand(g, SMD_R(-300.0), SMD_R(300.0));
        smd_real z = (k % 2 == 0) ? urand(g, SMD_R(-2.0), SMD_R(0.0)) : urand(g, SMD_R(-1e-3), SMD_R(1e-3));
        smd_real o[8];
        o[0] = SMD_SIN(x);
        o[1] = SMD_COS(x);
        o[2] = SMD_ATAN2(y, x * SMD_R(80.0));
        o[3] = SMD_EXP(z);
        o[4] = SMD_EXPM1(z);
        o[5] = SMD_FLOOR(x);
        o[6] = SMD_SQRT(SMD_FABS(y));
        o[7] = SMD_FABS(x);
        wr_reals(w, o, 8);
    }
}

/* yao2022 Table VI's three parts, each between its own markers, on the
 * tables of the last TABLES case at 100 kr/min (both band-pass channels
 * active): prediction (model interpolation, observer (9), augmented state
 * (16)), reaching law ((18), (33)-(35)) and PLL (position error (47), PLL
 * (48)). Same split as benchmarks/cost/obs_cost.c. */
static void blk_table6(smd_writer *w, rng *g, int n)
{
    smd_lcl_smo_config c;
    smd_lcl_smo_params p;
    static smd_lcl_smo_state s;
    smd_pll_params pp;
    smd_pll_state ps;
    smd_lcl_model m;
    const smd_real wr = SMD_R(10471.98); /* 100 kr/min, one pole pair */
    smd_real th = SMD_R(0.0);
    int k;
    memset(&c, 0, sizeof c);
    c.law = SMD_LCL_SMO_PROPOSED;
    c.table = g_models;
    c.n = g_n_models;
    c.w_min = g_w_min;
    c.dw = g_dw;
    c.Q1 = SMD_R(0.6);
    c.Q2 = SMD_R(0.6);
    c.bw_rel2 = SMD_R(0.2);
    c.bw_rel3 = SMD_R(0.2);
    c.w_bp_min = SMD_R(1000.0);
    wr_i32(w, (int)smd_lcl_smo_init(&p, SMD_R(5e-5), &c));
    wr_i32(w, (int)smd_pll_init(&pp, SMD_R(5e-5), SMD_R(0.1), SMD_R(10.0), SMD_R(10.0)));
    smd_lcl_smo_reset(&s, SMD_R(0.0));
    smd_pll_reset(&ps, SMD_R(0.0), wr);
    for (k = 0; k < n; k++) {
        smd_cplx e, i1, i2, u;
        smd_real w_hat = wr + urand(g, SMD_R(-20.0), SMD_R(20.0));
        th = smd_wrap_pi(th + wr * SMD_R(5e-5));
        e = smd_cexpj(th);
        i2 = smd_cadd(smd_cscale(smd_cj(e), SMD_R(30.0)), crand(g, SMD_R(0.3)));
        i1 = smd_cadd(i2, crand(g, SMD_R(1.0)));
        u = smd_cscale(smd_cj(e), SMD_R(32.0));
        smd_mark_begin(SMD_BLK_TABLE6 * 10 + 1);
        smd_lcl_smo_model(&p, w_hat, &m);
        smd_lcl_smo_predict(&m, &s, u);
        smd_mark_end();
        smd_mark_begin(SMD_BLK_TABLE6 * 10 + 2);
        smd_lcl_smo_reach(&p, &s, &m, i1, i2, w_hat);
        smd_mark_end();
        smd_mark_begin(SMD_BLK_TABLE6 * 10 + 3);
        smd_pll_step(&pp, &ps, smd_lcl_smo_theta_err(&s, w_hat));
        smd_mark_end();
        wr_reals(w, s.e_hat, 2);
        wr_real(w, ps.theta);
    }
}

/* Table VI's three parts as the drive calls them with the decimated refresh
 * of the fast build (smd_lcl_smo_config.decimation = 8, spread): one window
 * over the observer's step (model piece, prediction, reaching law, the
 * Park transforms with the drive's e^{-j theta}) and the PLL (47)-(48), at
 * 100 kr/min on the tables of the last TABLES case, as blk_table6. */
static void blk_table6_dec(smd_writer *w, rng *g, int n)
{
    smd_lcl_smo_config c;
    smd_lcl_smo_params p;
    static smd_lcl_smo_state s;
    smd_pll_params pp;
    smd_pll_state ps;
    const smd_real wr = SMD_R(10471.98); /* 100 kr/min, one pole pair */
    smd_real th = SMD_R(0.0);
    int k;
    memset(&c, 0, sizeof c);
    c.law = SMD_LCL_SMO_PROPOSED;
    c.table = g_models;
    c.n = g_n_models;
    c.w_min = g_w_min;
    c.dw = g_dw;
    c.Q1 = SMD_R(0.6);
    c.Q2 = SMD_R(0.6);
    c.bw_rel2 = SMD_R(0.2);
    c.bw_rel3 = SMD_R(0.2);
    c.w_bp_min = SMD_R(1000.0);
    c.decimation = 8;
    wr_i32(w, (int)smd_lcl_smo_init(&p, SMD_R(5e-5), &c));
    wr_i32(w, (int)smd_pll_init(&pp, SMD_R(5e-5), SMD_R(0.1), SMD_R(10.0), SMD_R(10.0)));
    smd_lcl_smo_reset(&s, SMD_R(0.0));
    smd_pll_reset(&ps, SMD_R(0.0), wr);
    for (k = 0; k < n; k++) {
        smd_cplx e, i1, i2, u, r;
        smd_real w_hat = wr + urand(g, SMD_R(-20.0), SMD_R(20.0));
        smd_status st;
        th = smd_wrap_pi(th + wr * SMD_R(5e-5));
        e = smd_cexpj(th);
        i2 = smd_cadd(smd_cscale(smd_cj(e), SMD_R(30.0)), crand(g, SMD_R(0.3)));
        i1 = smd_cadd(i2, crand(g, SMD_R(1.0)));
        u = smd_cscale(smd_cj(e), SMD_R(32.0));
        /* the frame's e^{-j theta}: the drive takes it for its own transforms
         * and hands it to the observer (smd_lcl_smo_step_r) */
        r = smd_cconj(smd_cexpj(ps.theta));
        smd_mark_begin(SMD_BLK_TABLE6_DEC);
        st = smd_lcl_smo_step_r(&p, &s, i1, i2, u, r, ps.theta, w_hat);
        smd_pll_step(&pp, &ps, smd_lcl_smo_theta_err(&s, w_hat));
        smd_mark_end();
        wr_i32(w, (int)st);
        wr_reals(w, s.e_hat, 2);
        wr_real(w, ps.theta);
    }
}

static int run_block(smd_reader *r, smd_writer *w)
{
    int ok = 1;
    int id = (int)rd_i32(r, &ok);
    int n = (int)rd_i32(r, &ok);
    rng g;
    g.x = (uint32_t)rd_i32(r, &ok);
    if (!ok || n < 0 || g.x == 0u) return 0;
    wr_case_begin(w);
    wr_i32(w, id);
    switch (id) {
    case SMD_BLK_TRANSFORMS: blk_transforms(w, &g, n); break;
    case SMD_BLK_SVM: blk_svm(w, &g, n); break;
    case SMD_BLK_PI: blk_pi(w, &g, n); break;
    case SMD_BLK_DBPC: blk_dbpc(w, &g, n); break;
    case SMD_BLK_SMDO:
        blk_smdo(w, &g, n, 0);
        blk_smdo(w, &g, n, 1);
        break;
    case SMD_BLK_EMF_POS: blk_emf_pos(w, &g, n); break;
    case SMD_BLK_PLL: blk_pll(w, &g, n); break;
    case SMD_BLK_BANDPASS: blk_bandpass(w, &g, n); break;
    case SMD_BLK_IDENT: blk_ident(w, &g, n); break;
    case SMD_BLK_IDENT_LS: blk_ident_ls(w, &g, n); break;
    case SMD_BLK_IDENT_PSI: blk_ident_psi(w, &g, n); break;
    case SMD_BLK_IDENT_MECH: blk_ident_mech(w, &g, n); break;
    case SMD_BLK_MATH: blk_math(w, &g, n); break;
    case SMD_BLK_TABLE6:
        if (g_n_models < 2) return 0;
        blk_table6(w, &g, n);
        break;
    case SMD_BLK_TABLE6_DEC:
        if (g_n_models < 2) return 0;
        blk_table6_dec(w, &g, n);
        break;
    case SMD_BLK_LCL_SMO:
        if (g_n_models < 2) return 0;
        blk_lcl_smo(w, &g, n, (int)(g.x % 3u));
        break;
    case SMD_BLK_LINOBS:
        if (g_n_lins < 2) return 0;
        blk_linobs(w, &g, n);
        break;
    default: return 0;
    }
    wr_case_end(w, SMD_CASE_BLOCK);
    return 1;
}

int smd_vec_main(int argc, char **argv)
{
    smd_reader *r = &g_rd;
    smd_writer *w = &g_wr;
    int ok = 1, cases = 0;
    if (argc < 3) {
        smd_io_log("usage: smd_vec IN OUT");
        return 2;
    }
    memset(r, 0, sizeof *r);
    memset(w, 0, sizeof *w);
    r->h = smd_io_open(argv[1], 0);
    if (r->h < 0) {
        smd_io_log("smd_vec: cannot open the input");
        return 3;
    }
    w->h = smd_io_open(argv[2], 1);
    if (w->h < 0) {
        smd_io_log("smd_vec: cannot open the output");
        return 3;
    }
    if ((uint32_t)rd_i32(r, &ok) != SMD_VEC_MAGIC || rd_i32(r, &ok) != SMD_VEC_VERSION || !ok) {
        smd_io_log("smd_vec: not a vector file of this version");
        return 4;
    }
    wr_i32(w, (int)SMD_VEC_MAGIC);
    wr_flush(w);
    for (;;) {
        int kind = (int)rd_i32(r, &ok);
        if (!ok || kind == SMD_CASE_END) break;
        if (kind == SMD_CASE_DRIVE) {
            ok = run_drive(r, w);
        } else if (kind == SMD_CASE_TABLES) {
            smd_real wg[2];
            ok = read_tables(r);
            smd_rd_reals(r, wg, 2);
            g_w_min = wg[0];
            g_dw = wg[1];
            wr_case_begin(w);
            wr_case_end(w, SMD_CASE_TABLES);
        } else if (kind == SMD_CASE_BLOCK) {
            ok = run_block(r, w);
        } else {
            ok = 0;
        }
        if (!ok) {
            smd_io_log("smd_vec: malformed case");
            wr_flush(w);
            return 5;
        }
        cases++;
    }
    wr_i32(w, SMD_CASE_END);
    wr_i32(w, cases);
    wr_i32(w, w->err);
    wr_flush(w);
    smd_io_close(w->h);
    smd_io_close(r->h);
    return w->err ? 6 : 0;
}

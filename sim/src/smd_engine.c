#include "smdsim/smd_engine.h"

#include <math.h>

#include "smodrive/smd_transforms.h"

#include "smd_log_names.h" /* CHANNELS[], generated from enum smd_log_channel */

const char *smd_log_channel_name(int ch)
{
    return (ch >= 0 && ch < SMD_LOG_N) ? CHANNELS[ch] : "";
}

unsigned long smd_sizeof_engine(void) { return sizeof(smd_engine); }

double smd_pwl_eval(const smd_pwl *p, double t)
{
    int lo = 0, hi;
    if (p->n <= 0) return 0.0;
    if (t <= p->t[0] || p->n == 1) return p->y[0];
    if (t >= p->t[p->n - 1]) return p->y[p->n - 1];
    hi = p->n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (p->t[mid] <= t) lo = mid; else hi = mid;
    }
    if (p->t[hi] == p->t[lo]) return p->y[hi];
    return p->y[lo] + (p->y[hi] - p->y[lo]) * (t - p->t[lo]) / (p->t[hi] - p->t[lo]);
}

/* smd_pwl_eval for a time that only grows: the segment found last time is
 * tried first (*seg), then the following ones. It returns exactly what the
 * bisection of smd_pwl_eval gives: the last index lo with t[lo] <= t, and the
 * same interpolation. */
static double pwl_eval_seq(const smd_pwl *p, double t, int *seg)
{
    int lo = *seg;
    if (p->n <= 0) return 0.0;
    if (t <= p->t[0] || p->n == 1) return p->y[0];
    if (t >= p->t[p->n - 1]) return p->y[p->n - 1];
    if (lo < 0 || lo > p->n - 2 || p->t[lo] > t) lo = 0;
    while (p->t[lo + 1] <= t) lo++;
    *seg = lo;
    return p->y[lo] + (p->y[lo + 1] - p->y[lo]) * (t - p->t[lo]) / (p->t[lo + 1] - p->t[lo]);
}

static int pwl_ok(const smd_pwl *p)
{
    int k;
    if (p->n < 0 || p->n > SMD_PWL_MAX) return 0;
    for (k = 0; k < p->n; k++) {
        if (!isfinite(p->t[k]) || !isfinite(p->y[k])) return 0;
        if (k > 0 && p->t[k] < p->t[k - 1]) return 0;
    }
    return 1;
}

int smd_engine_init(smd_engine *e, const smd_plant_config *plant, const smd_drive_config *ctrl,
                    const smd_profiles *prof, const smd_engine_start *start)
{
    int rc = smd_plant_init(&e->plant, plant);
    smd_status st;
    if (rc != 0) return 1000 + rc;
    st = smd_drive_init(&e->ctrl_p, ctrl);
    if (st != SMD_OK) return 2000 + (int)st;
    if (!pwl_ok(&prof->w_M_ref) || !pwl_ok(&prof->T_ext) || !pwl_ok(&prof->T_brake) ||
        !pwl_ok(&prof->i_d_ref) || !pwl_ok(&prof->i_q_ref) || !pwl_ok(&prof->R_s_scale)) {
        return 3000;
    }
    for (rc = 0; rc < prof->R_s_scale.n; rc++) {
        /* the plant's own range of R_s at every value of the profile */
        const double R = plant->R_s * prof->R_s_scale.y[rc];
        if (!(R >= 1e-6 && R <= 1e3)) return 3000;
    }
    if (!isfinite(prof->i_d_sin_amp) || !isfinite(prof->i_d_sin_freq) ||
        !isfinite(start->theta0) || !isfinite(start->w0) || !isfinite(start->i_q0)) {
        return 3000;
    }
    e->prof = *prof;
    smd_drive_reset(&e->ctrl_p, &e->ctrl_s, (smd_real)start->theta0, (smd_real)start->w0,
                    (smd_real)start->i_q0);
    {
        /* the period before the first sample applies the steady state of
         * the initial condition (a warm or flying start; the zero vector
         * from standstill) */
        smd_real d[3];
        smd_drive_start_duties(&e->ctrl_p, &e->ctrl_s, (smd_real)plant->u_dc, d);
        e->d_abc[0] = (double)d[0];
        e->d_abc[1] = (double)d[1];
        e->d_abc[2] = (double)d[2];
    }
    e->pwm_off = 0;
    e->plant.off = 0;
    e->k = 0;
    e->seg[0] = e->seg[1] = e->seg[2] = e->seg[3] = e->seg[4] = e->seg[5] = 0;
    e->R_s0 = plant->R_s;
    e->T_sp = plant->T_sw;
    e->last_status = 0;
    e->first_fault_k = -1;
    e->first_fault = 0u;
    e->fault = 0u;
    return 0;
}

long smd_engine_fault(const smd_engine *e, unsigned *first, unsigned *now)
{
    *first = e->first_fault;
    *now = e->fault;
    return e->first_fault_k;
}

/* A channel set's readings as the drive's two inputs: two sensors, a and b
 * (the drive takes c = -a - b); three, their zero sequence removed
 * (smd_abc_to_ab2). */
static inline void in_currents(int sensors, const double meas[3], smd_real *x_a, smd_real *x_b)
{
    if (sensors == 3) {
        const smd_real abc[3] = {(smd_real)meas[0], (smd_real)meas[1], (smd_real)meas[2]};
        smd_abc_to_ab2(abc, x_a, x_b);
    } else {
        *x_a = (smd_real)meas[0];
        *x_b = (smd_real)meas[1];
    }
}

/* The sample's inputs at t_k (step 1): measurements, references and the
 * profile values the plant needs over [t_k, t_k+1). */
typedef smd_engine_sample engine_sample;

static inline void engine_inputs(smd_engine *e, engine_sample *x, smd_drive_in *in)
{
    const double t = (double)e->k * e->T_sp;
    double i1_meas[3];
    double i_d_ref;
    x->t = t;
    x->w_ref = pwl_eval_seq(&e->prof.w_M_ref, t, &e->seg[0]);
    x->T_ext = pwl_eval_seq(&e->prof.T_ext, t, &e->seg[1]);
    x->T_brake = pwl_eval_seq(&e->prof.T_brake, t, &e->seg[2]);
    i_d_ref = pwl_eval_seq(&e->prof.i_d_ref, t, &e->seg[3]);
    if (e->prof.R_s_scale.n > 0) {
        /* winding heating: R_s over [t_k, t_k+1) from the profile at t_k */
        const double R = e->R_s0 * pwl_eval_seq(&e->prof.R_s_scale, t, &e->seg[5]);
        if (R != e->plant.c.R_s) smd_plant_set_resistance(&e->plant, R);
    }
    if (e->plant.c.lcl) {
        smd_plant_sample(&e->plant, x->i_meas, i1_meas);
        in_currents(e->plant.c.adc_sensors, i1_meas, &in->i1_a, &in->i1_b);
    } else {
        smd_plant_sample(&e->plant, x->i_meas, 0);
        in->i1_a = in->i1_b = SMD_R(0.0);
    }
    in_currents(e->plant.c.adc_sensors, x->i_meas, &in->i_a, &in->i_b);
    in->theta_enc = (smd_real)e->plant.theta_r;
    in->w_enc = (smd_real)(e->plant.c.n_p * e->plant.w_M);
    in->u_dc = (smd_real)e->plant.c.u_dc;
    in->w_ref = (smd_real)(e->plant.c.n_p * x->w_ref);
    if (e->prof.i_d_sin_amp != 0.0) {
        i_d_ref += e->prof.i_d_sin_amp * sin(6.283185307179586 * e->prof.i_d_sin_freq * t);
    }
    in->i_dq_ref.re = (smd_real)i_d_ref;
    in->i_dq_ref.im = (smd_real)pwl_eval_seq(&e->prof.i_q_ref, t, &e->seg[4]);
}

/* Steps 2 to 3 of a sample once the controller has answered: the duties for
 * the next period, the log row (r != 0, with the controller's view v) and
 * the plant over [t_k, t_k+1) with the duties computed at k-1. */
static inline void engine_apply(smd_engine *e, const engine_sample *x, const smd_drive_out *out,
                                smd_status st, const smd_drive_view *v, double *r)
{
    double d_now[3];
    int j;
    if (st != SMD_OK) e->last_status = (int)st;
    if (out->fault != 0u && e->first_fault_k < 0) {
        e->first_fault_k = e->k;
        e->first_fault = out->fault;
    }
    e->fault = out->fault;
    for (j = 0; j < 3; j++) {
        d_now[j] = e->d_abc[j];
        e->d_abc[j] = (double)out->d_abc[j];
    }
    /* (pwm_off as the duties: from the next period on) */
    e->plant.off = e->pwm_off;
    e->pwm_off = out->pwm_off == 2 ? 2 : out->pwm_off != 0;
    if (r != 0) {
        const smd_plant *pl = &e->plant;
        double c = cos(pl->theta_r), s = sin(pl->theta_r);
        r[SMD_LOG_T] = x->t;
        r[SMD_LOG_W_M] = pl->w_M;
        r[SMD_LOG_THETA_R] = pl->theta_r;
        r[SMD_LOG_I_ALPHA] = pl->i_re;
        r[SMD_LOG_I_BETA] = pl->i_im;
        r[SMD_LOG_I_D] = c * pl->i_re + s * pl->i_im;
        r[SMD_LOG_I_Q] = -s * pl->i_re + c * pl->i_im;
        r[SMD_LOG_W_M_REF] = x->w_ref;
        r[SMD_LOG_I_D_REF] = (double)v->i_dq_ref.re;
        r[SMD_LOG_I_Q_REF] = (double)v->i_dq_ref.im;
        r[SMD_LOG_THETA_HAT] = (double)v->theta;
        r[SMD_LOG_W_HAT] = (double)v->w;
        r[SMD_LOG_UD_ALPHA] = (double)v->u_d_hat.re;
        r[SMD_LOG_UD_BETA] = (double)v->u_d_hat.im;
        r[SMD_LOG_D_A] = d_now[0];
        r[SMD_LOG_D_B] = d_now[1];
        r[SMD_LOG_D_C] = d_now[2];
        r[SMD_LOG_UCMD_ALPHA] = (double)v->u_ab.re;
        r[SMD_LOG_UCMD_BETA] = (double)v->u_ab.im;
        r[SMD_LOG_I_A_MEAS] = x->i_meas[0];
        r[SMD_LOG_I_B_MEAS] = x->i_meas[1];
        r[SMD_LOG_IHAT_ALPHA] = (double)v->i_s_hat.re;
        r[SMD_LOG_IHAT_BETA] = (double)v->i_s_hat.im;
        r[SMD_LOG_LAMBDA] = (double)v->lambda;
        r[SMD_LOG_I_G] = (double)v->i_dq.re;
        r[SMD_LOG_I_DL] = (double)v->i_dq.im;
        r[SMD_LOG_THETA_ERR] = (double)v->theta_err;
        r[SMD_LOG_E_G] = (double)v->e_hat.re;
        r[SMD_LOG_E_DL] = (double)v->e_hat.im;
        r[SMD_LOG_S_G] = (double)v->s.re;
        r[SMD_LOG_S_DL] = (double)v->s.im;
        r[SMD_LOG_DHAT_G] = (double)v->d_hat.re;
        r[SMD_LOG_DHAT_DL] = (double)v->d_hat.im;
        r[SMD_LOG_V_G] = (double)v->v.re;
        r[SMD_LOG_V_DL] = (double)v->v.im;
        r[SMD_LOG_I1_ALPHA] = pl->i1_re;
        r[SMD_LOG_I1_BETA] = pl->i1_im;
        r[SMD_LOG_UC_ALPHA] = pl->uc_re;
        r[SMD_LOG_UC_BETA] = pl->uc_im;
        r[SMD_LOG_LIN_E_ALPHA] = (double)v->e_lin.re;
        r[SMD_LOG_LIN_E_BETA] = (double)v->e_lin.im;
        r[SMD_LOG_R_S_RLS] = (double)v->R_s_rls;
        r[SMD_LOG_PSI_RLS] = (double)v->psi_rls;
        r[SMD_LOG_PHASE] = (double)v->phase;
        r[SMD_LOG_STATUS] = (double)st;
        r[SMD_LOG_FAULT] = (double)out->fault;
    }
    smd_plant_step(&e->plant, d_now, x->T_ext, x->T_brake);
    if (r != 0) {
        r[SMD_LOG_T_E] = e->plant.T_e_mean;
        r[SMD_LOG_T_L] = e->plant.T_L_mean;
        r[SMD_LOG_U_ALPHA] = e->plant.u_re;
        r[SMD_LOG_U_BETA] = e->plant.u_im;
    }
    e->k++;
}

long smd_engine_run(smd_engine *e, long n, double *log, long stride)
{
    long j, rows = 0;
    if (stride < 1) stride = 1;
    for (j = 0; j < n; j++) {
        engine_sample x;
        smd_drive_in in;
        smd_drive_out out;
        smd_status st;
        engine_inputs(e, &x, &in);
        st = smd_drive_step(&e->ctrl_p, &e->ctrl_s, &in, &out);
        if (log != 0 && (j % stride) == 0) {
            smd_drive_view v = smd_drive_get_view(&e->ctrl_p, &e->ctrl_s);
            engine_apply(e, &x, &out, st, &v, log + rows * SMD_LOG_N);
            rows++;
        } else {
            engine_apply(e, &x, &out, st, 0, 0);
        }
    }
    return rows;
}

/* Commissioning's tests in place of the drive (smd_ident.h): one loop, each
 * test a step through its context (its params and state); the step returns
 * 1 once the test ended. With log != 0 every stride-th sample writes t, the
 * true alpha current and the test's applied alpha voltage. */
typedef int (*ident_step)(void *ctx, const smd_drive_in *in, smd_drive_out *out, smd_status *st);

static long run_ident(smd_engine *e, ident_step step, void *ctx, const smd_cplx *u_applied,
                      long n, double *log, long stride)
{
    long j, rows = 0;
    if (stride < 1) stride = 1;
    for (j = 0; j < n; j++) {
        engine_sample x;
        smd_drive_in in;
        smd_drive_out out;
        smd_status st;
        int ended;
        engine_inputs(e, &x, &in);
        out.pwm_off = 0;
        ended = step(ctx, &in, &out, &st);
        out.fault = 0u;
        if (log != 0 && (j % stride) == 0) {
            double *r = log + 3 * rows;
            r[0] = x.t;
            r[1] = e->plant.i_re;
            r[2] = (double)u_applied->re;
            rows++;
        }
        engine_apply(e, &x, &out, st, 0, 0);
        if (ended) {
            return j + 1;
        }
    }
    return n;
}

typedef struct rs_ctx { const smd_ident_rs_params *p; smd_ident_rs_state *s; } rs_ctx;
typedef struct ls_ctx { const smd_ident_ls_params *p; smd_ident_ls_state *s; } ls_ctx;
typedef struct psi_ctx { const smd_ident_psi_params *p; smd_ident_psi_state *s; } psi_ctx;

static int rs_step(void *ctx, const smd_drive_in *in, smd_drive_out *out, smd_status *st)
{
    rs_ctx *c = (rs_ctx *)ctx;
    *st = smd_ident_rs_step(c->p, c->s, in->i_a, in->i_b, in->u_dc, out->d_abc);
    return c->s->phase == SMD_IDENT_DONE || c->s->phase == SMD_IDENT_FAILED;
}

static int ls_step(void *ctx, const smd_drive_in *in, smd_drive_out *out, smd_status *st)
{
    ls_ctx *c = (ls_ctx *)ctx;
    *st = smd_ident_ls_step(c->p, c->s, in->i_a, in->i_b, in->u_dc, out->d_abc);
    return c->s->phase == SMD_IDENT_LS_DONE || c->s->phase == SMD_IDENT_LS_FAILED;
}

static int psi_step(void *ctx, const smd_drive_in *in, smd_drive_out *out, smd_status *st)
{
    psi_ctx *c = (psi_ctx *)ctx;
    *st = smd_ident_psi_step(c->p, c->s, in->i_a, in->i_b, in->i1_a, in->i1_b, in->u_dc, out->d_abc);
    out->pwm_off = c->s->pwm_off;
    return c->s->phase == SMD_IDENT_PSI_DONE || c->s->phase == SMD_IDENT_PSI_FAILED;
}

long smd_engine_run_ident_rs(smd_engine *e, const smd_ident_rs_params *p, smd_ident_rs_state *s,
                             long n, double *log, long stride)
{
    rs_ctx c;
    c.p = p;
    c.s = s;
    return run_ident(e, rs_step, &c, &s->u_applied, n, log, stride);
}

long smd_engine_run_ident_ls(smd_engine *e, const smd_ident_ls_params *p, smd_ident_ls_state *s,
                             long n)
{
    ls_ctx c;
    c.p = p;
    c.s = s;
    return run_ident(e, ls_step, &c, &s->u_applied, n, 0, 1);
}

long smd_engine_run_ident_psi(smd_engine *e, const smd_ident_psi_params *p,
                              smd_ident_psi_state *s, long n)
{
    psi_ctx c;
    c.p = p;
    c.s = s;
    return run_ident(e, psi_step, &c, &s->u_applied, n, 0, 1);
}

long smd_engine_run_ident_mech(smd_engine *e, const smd_ident_mech_params *p,
                               smd_ident_mech_state *s, long n, double *log, long stride)
{
    long j, rows = 0;
    if (stride < 1) stride = 1;
    for (j = 0; j < n; j++) {
        engine_sample x;
        smd_drive_in in;
        smd_drive_out out;
        smd_status st;
        smd_drive_view v;
        smd_real i_q;
        int done, coast;
        engine_inputs(e, &x, &in);
        in.w_ref = smd_ident_mech_ref(p, s); /* the test's reference, not the profile's */
        /* the coast: zero current in torque mode */
        coast = smd_ident_mech_coasting(p, s);
        smd_drive_set_torque_in(&e->ctrl_s, coast);
        if (coast) {
            in.i_dq_ref = smd_c(SMD_R(0.0), SMD_R(0.0));
        }
        x.w_ref = (double)in.w_ref / e->plant.c.n_p;
        st = smd_drive_step(&e->ctrl_p, &e->ctrl_s, &in, &out);
        v = smd_drive_get_view(&e->ctrl_p, &e->ctrl_s);
        /* the torque current: the measured current in the drive's frame
         * (the reference is not what flows at the voltage limit) */
        i_q = smd_cmul(smd_ab2_to_ab(in.i_a, in.i_b), smd_cconj(smd_cexpj(v.theta))).im;
        done = smd_ident_mech_step(p, s, i_q, v.w, v.phase == SMD_PHASE_SOURCE,
                                   out.fault & (uint32_t)SMD_FAULT_LATCHED); /* (not warnings) */
        if (log != 0 && (j % stride) == 0) {
            engine_apply(e, &x, &out, st, &v, log + rows * SMD_LOG_N);
            rows++;
        } else {
            engine_apply(e, &x, &out, st, 0, 0);
        }
        if (done) return j + 1;
    }
    return n;
}

double smd_engine_rotor_speed(const smd_engine *e) { return e->plant.w_M; }

double smd_engine_rotor_angle(const smd_engine *e) { return e->plant.theta_r; }

void smd_engine_ext_inputs(smd_engine *e, smd_drive_in *in)
{
    engine_inputs(e, &e->ext, in);
}

void smd_engine_ext_apply(smd_engine *e, const smd_drive_out *out, int status,
                          const smd_drive_view *v, double *row)
{
    engine_apply(e, &e->ext, out, (smd_status)status, v, v != 0 ? row : 0);
}

int smd_engine_host_step(smd_engine *e, const smd_drive_in *in, smd_drive_out *out,
                         smd_drive_view *v)
{
    smd_status st = smd_drive_step(&e->ctrl_p, &e->ctrl_s, in, out);
    *v = smd_drive_get_view(&e->ctrl_p, &e->ctrl_s);
    return (int)st;
}

/* Closed-loop impulse response of the firmware PLL (eq. (48)) with unity
 * feedback e = theta - theta_hat: theta = amp at k = 0 and 0 after; writes
 * theta_hat(k) / amp for k = 1..n into out (analysis of yao2022 Fig. 7). */
int smd_pll_impulse(double T_sp, double k_theta, double k_omega, double k_a, double amp, long n,
                    double *out)
{
    smd_pll_params p;
    smd_pll_state s;
    long k;
    smd_status st = smd_pll_init(&p, (smd_real)T_sp, (smd_real)k_theta, (smd_real)k_omega,
                                 (smd_real)k_a);
    if (st != SMD_OK) return (int)st;
    smd_pll_reset(&s, SMD_R(0.0), SMD_R(0.0));
    for (k = 0; k < n; k++) {
        double theta = (k == 0) ? amp : 0.0;
        smd_pll_step(&p, &s, (smd_real)(theta - (double)s.theta));
        out[k] = (double)s.theta / amp;
    }
    return 0;
}

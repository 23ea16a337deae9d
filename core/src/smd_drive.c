#include "smodrive/smd_drive.h"

#include "smodrive/smd_transforms.h"

/* loss of lock: an implausible sample counts this many plausible ones (check_lock) */
#define SMD_LOCK_UP 4

/* the supervision's functions out of line (GCC, Clang): it runs every
 * sample but is not the control law's hot path, and inlined it made the
 * step's code too large for the host engine's loop (the logged simulation
 * ran 6 % slower); the return to I/f, a start-up transition, too;
 * elsewhere a plain static function */
#if defined(__GNUC__)
#define SMD_COLD __attribute__((noinline))
#else
#define SMD_COLD
#endif

/* A fixed composition (smd_drive.h, "A composition fixed at compile time"):
 * each SMD_FIX_* a firmware defines makes its part of the configuration a
 * constant of the step, which the compiler then prunes; smd_drive_init
 * refuses any other value. Undefined, each is the configuration's. */
#ifdef SMD_FIX_CURRENT
#define D_CURRENT(p) ((void)(p), SMD_FIX_CURRENT)
#else
#define D_CURRENT(p) ((p)->current)
#endif
#ifdef SMD_FIX_POSITION
#define D_POSITION(p) ((void)(p), SMD_FIX_POSITION)
#else
#define D_POSITION(p) ((p)->position)
#endif
#ifdef SMD_FIX_LCL
#define D_LCL(p) ((void)(p), SMD_FIX_LCL)
#else
#define D_LCL(p) ((p)->lcl)
#endif
#ifdef SMD_FIX_RLS
#define D_USE_RLS(p) ((void)(p), SMD_FIX_RLS)
#else
#define D_USE_RLS(p) ((p)->use_rls)
#endif
#ifdef SMD_FIX_SPEED_LOOP
#define D_SPEED_LOOP(p) ((void)(p), SMD_FIX_SPEED_LOOP)
#else
#define D_SPEED_LOOP(p) ((p)->speed_loop)
#endif
#if defined(SMD_FIX_CURRENT) && defined(SMD_FIX_POSITION)
#define D_USE_SMDO(p) \
    ((void)(p), SMD_FIX_CURRENT == SMD_CC_ROBUST_DBPC || SMD_FIX_POSITION == SMD_POS_SMDO_EMF)
#else
#define D_USE_SMDO(p) ((p)->use_smdo)
#endif
#ifdef SMD_FIX_SUPERVISE_EVERY
#define D_SUP_N(p) ((void)(p), SMD_FIX_SUPERVISE_EVERY > 1 ? SMD_FIX_SUPERVISE_EVERY : 1)
#define D_SUP_FIN(p) (2 % D_SUP_N(p))
#define D_SUP_RIP(p) (3 % D_SUP_N(p))
#else
#define D_SUP_N(p) ((p)->sup_n)
#define D_SUP_FIN(p) ((p)->sup_fin)
#define D_SUP_RIP(p) ((p)->sup_rip)
#endif

static int is_flag(int x) { return x == 0 || x == 1; }

/* ------------------------------------------------------------ position source */

/* The position source (SMD_POS_*): its kind is looked at here and nowhere
 * else; the rest of the drive asks these source_* functions. */

static int source_is_lcl(int position)
{
    return position == SMD_POS_LCL_SMO_PLL || position == SMD_POS_LCL_LINEAR;
}

/* A sensorless source (every one but the encoder). */
static int source_sensorless(int position) { return position != SMD_POS_ENCODER; }

/* The SMDO runs for the source (smdo_emf: the angle of its disturbance). */
static int source_uses_smdo(int position) { return position == SMD_POS_SMDO_EMF; }

/* Whether the source fits the filter (SMD_ERR_COMBINATION otherwise). */
static int source_fits(const smd_drive_config *c)
{
    if (source_is_lcl(c->position)) {
        return c->lcl; /* the LCL observers model the filter */
    }
    return !(c->lcl && c->position == SMD_POS_SMDO_EMF); /* the SMDO's model (15) has no filter */
}

/* The largest |w| a sensorless source can estimate: w_max of smdo_emf, the
 * end of the LCL observers' speed table (0 for the encoder). */
static smd_real source_speed_limit(const smd_drive_config *c)
{
    smd_real a, b;
    switch (c->position) {
    case SMD_POS_SMDO_EMF: return c->w_max;
    case SMD_POS_LCL_SMO_PLL:
        a = c->smo.w_min;
        b = c->smo.w_min + c->smo.dw * (smd_real)(c->smo.n - 1);
        break;
    case SMD_POS_LCL_LINEAR:
        a = c->lin.w_min;
        b = c->lin.w_min + c->lin.dw * (smd_real)(c->lin.n - 1);
        break;
    default: return SMD_R(0.0);
    }
    a = SMD_FABS(a);
    b = SMD_FABS(b);
    return a > b ? a : b;
}

/* The source's blocks from the config (smd_drive_init). */
static smd_status source_init(smd_drive_params *p, const smd_drive_config *c)
{
    smd_status st = SMD_OK;
    switch (c->position) {
    case SMD_POS_SMDO_EMF:
        st = smd_emf_pos_init(&p->emf, c->T_sp, c->w_lpf, c->w_hys, c->w_max);
        if (st == SMD_OK) {
            /* The Euler filter (36) rotates u_d_hat by (1 + j w T) and pulls
             * it by w_c T: |1 - w_c T + j w T| < 1 must hold for every speed
             * the estimate can take, or u_d_hat grows without bound. */
            smd_real a = SMD_R(1.0) - c->w_c * c->T_sp;
            smd_real b = c->w_max * c->T_sp;
            if (a * a + b * b >= SMD_R(1.0)) {
                st = SMD_ERR_STABILITY;
            }
        }
        break;
    case SMD_POS_LCL_SMO_PLL:
        st = smd_pll_init(&p->pll, c->T_sp, c->k_theta, c->k_omega, c->k_a);
        if (st == SMD_OK) {
            st = smd_lcl_smo_init(&p->smo, c->T_sp, &c->smo);
        }
        break;
    case SMD_POS_LCL_LINEAR:
        st = smd_pll_init(&p->pll, c->T_sp, c->k_theta, c->k_omega, c->k_a);
        if (st == SMD_OK) {
            st = smd_linobs_init(&p->lin, &c->lin);
        }
        break;
    default: break;
    }
    return st;
}

/* The source's state at (theta0, w0) (smd_drive_reset). */
static void source_reset(const smd_drive_params *p, smd_drive_state *s, smd_real theta0,
                         smd_real w0)
{
    s->pos.theta_err = SMD_R(0.0);
    smd_pll_reset(&s->pos.pll, theta0, w0);
    switch (D_POSITION(p)) {
    case SMD_POS_SMDO_EMF: smd_emf_pos_reset(&s->pos.u.emf, w0); break;
    case SMD_POS_LCL_SMO_PLL:
        smd_lcl_smo_reset(&s->pos.u.smo, theta0);
        if (p->smo.decimation >= 4) {
            /* the decimated refresh's first step: a piece, not the whole */
            smd_lcl_smo_prime(&p->smo, &s->pos.u.smo, w0);
        }
        break;
    case SMD_POS_LCL_LINEAR: smd_linobs_reset(&s->pos.u.lin); break;
    default: break;
    }
}

/* The LCL observers in the frame predicted for k (theta_o, w_o): the angle
 * error of eq. (47) into s->pos.theta_err. */
static smd_status observe_lcl(const smd_drive_params *p, smd_drive_state *s, smd_cplx i1_ab,
                              smd_cplx i2_ab, smd_real theta_o, smd_real w_o, smd_cplx *ej_o,
                              int *ej_ok)
{
    smd_status st;
    if (D_POSITION(p) == SMD_POS_LCL_SMO_PLL) {
        /* e^{j theta_o} once: the observer's transforms and, when the
         * frame of k is theta_o (on the source), the drive's (rotations()) */
        *ej_o = smd_cexpj(theta_o);
        *ej_ok = 1;
        st = smd_lcl_smo_step_r(&p->smo, &s->pos.u.smo, i1_ab, i2_ab, s->u_ab, smd_cconj(*ej_o),
                                theta_o, w_o);
        s->pos.theta_err = smd_lcl_smo_theta_err(&s->pos.u.smo, w_o);
    } else {
        /* angle of the linear observer's EMF, e = j w psi e^{j theta} */
        const smd_linobs_state *l = &s->pos.u.lin;
        smd_real sg;
        st = smd_linobs_step(&p->lin, &s->pos.u.lin, i1_ab, i2_ab, s->u_ab, w_o);
        sg = w_o < SMD_R(0.0) ? SMD_R(-1.0) : SMD_R(1.0);
        s->pos.theta_err = smd_wrap_pi(SMD_ATAN2(-sg * l->x2[2], sg * l->x2[3]) - theta_o);
        if (st != SMD_OK) {
            /* the observer was reset (non-finite data): its zero EMF has no
             * angle, and atan2(0, 0) - theta_o would kick the PLL by up to
             * pi; no correction this sample, as from the sliding-mode
             * observer after its reset */
            s->pos.theta_err = SMD_R(0.0);
        }
    }
    return st;
}

/* The source's estimates at k. smdo_emf: eq. (44)-(45) from u_d_hat^k,
 * before the SMDO's update; the LCL observers in the frame predicted for k
 * (theta_o, w_o): the angle error of eq. (47) into s->pos.theta_err. The
 * currents by pointer: a smd_cplx argument is copied where the call is, and
 * only the LCL sources read them. */
static smd_status source_observe(const smd_drive_params *p, smd_drive_state *s,
                                 const smd_cplx *i1_ab, const smd_cplx *i2_ab, smd_real theta_o,
                                 smd_real w_o, smd_cplx *ej_o, int *ej_ok)
{
    smd_status st = SMD_OK;
    if (D_POSITION(p) == SMD_POS_SMDO_EMF) {
        smd_emf_pos_step(&p->emf, &s->pos.u.emf, s->smdo.u_d_hat);
    } else if (source_is_lcl(D_POSITION(p))) {
        st = observe_lcl(p, s, *i1_ab, *i2_ab, theta_o, w_o, ej_o, ej_ok);
    }
    return st;
}

/* The frame of sample k on the source: the encoder's; the SMDO's estimate;
 * for the PLL sources the one predicted at k-1 (theta_o, w_o). */
static void source_frame(const smd_drive_params *p, const smd_drive_state *s,
                         const smd_drive_in *in, smd_real theta_o, smd_real w_o,
                         smd_real *theta_k, smd_real *w_k)
{
    if (D_POSITION(p) == SMD_POS_ENCODER) {
        *theta_k = in->theta_enc;
        *w_k = in->w_enc;
    } else if (D_POSITION(p) == SMD_POS_SMDO_EMF) {
        *theta_k = s->pos.u.emf.theta_r_hat;
        *w_k = s->pos.u.emf.w_r_hat;
    } else {
        *theta_k = theta_o;
        *w_k = w_o;
    }
}

/* Whether the source agrees to take over from the forced frame theta_k (the
 * forced speed w_f, the forced current's direction sg): the source's angle
 * on the stable side of the forced one (with the forced current +-i_start on
 * the forced q axis the torque is sg K cos(theta_f - theta), stable where
 * the rotor is ahead of the forced frame in the current's direction, by
 * less than half a turn; 30 deg behind allowed for a swing) and, for the
 * SMDO, its speed of the forced speed's sign (a low-speed estimate whose
 * direction has flipped puts the angle half a turn off). */
static int source_agrees(const smd_drive_params *p, const smd_drive_state *s, smd_real sg,
                         smd_real theta_k, smd_real w_f)
{
    const smd_real th_src = D_POSITION(p) == SMD_POS_SMDO_EMF ? s->pos.u.emf.theta_r_hat
                                                             : theta_k + s->pos.theta_err;
    const smd_real lead = sg * smd_wrap_pi(th_src - theta_k);
    return lead > -SMD_PI / SMD_R(6.0) && lead < SMD_PI &&
           (D_POSITION(p) != SMD_POS_SMDO_EMF || s->pos.u.emf.w_r_hat * w_f > SMD_R(0.0));
}

/* The forced frame's angle theta_k seen from the source's frame. */
static smd_real source_offset(const smd_drive_params *p, const smd_drive_state *s,
                              smd_real theta_k)
{
    switch (D_POSITION(p)) {
    case SMD_POS_SMDO_EMF: return smd_wrap_pi(theta_k - s->pos.u.emf.theta_r_hat);
    case SMD_POS_LCL_SMO_PLL:
    case SMD_POS_LCL_LINEAR: return -s->pos.theta_err;
    default: return SMD_R(0.0);
    }
}

/* The source takes over from the forced frame (theta_k, w_k): the PLL starts
 * on the observer's angle (forced angle plus the measured angle error) one
 * sample (T) on, at the forced speed; the PLL sources' frame of k+1 is the
 * PLL's. */
static void source_take_over(const smd_drive_params *p, smd_drive_state *s, smd_real theta_k,
                             smd_real w_k, smd_real T, smd_real *theta_next, smd_real *w_next)
{
    smd_pll_reset(&s->pos.pll, theta_k + s->pos.theta_err + w_k * T, w_k);
    if (source_is_lcl(D_POSITION(p))) {
        *theta_next = s->pos.pll.theta;
        *w_next = s->pos.pll.w;
    }
}

/* The source takes over from the encoder (the end of a handover): the PLL
 * starts on the encoder's frame of k+1. */
static void source_take_over_encoder(smd_drive_state *s, smd_real theta_next, smd_real w_next)
{
    smd_pll_reset(&s->pos.pll, theta_next, w_next);
}

/* The frame of k+1 on the source: the PLL sources run eq. (48) on the error
 * of eq. (47); the others keep the frame of k. */
static void source_next(const smd_drive_params *p, smd_drive_state *s, smd_real theta_k,
                        smd_real w_k, smd_real *theta_next, smd_real *w_next)
{
    if (source_is_lcl(D_POSITION(p))) {
        smd_pll_step(&p->pll, &s->pos.pll, s->pos.theta_err);
        *theta_next = s->pos.pll.theta;
        *w_next = s->pos.pll.w;
    } else {
        *theta_next = theta_k;
        *w_next = w_k;
    }
}

/* The sliding-mode observer's state reframed by the frame's correction:
 * theta_next against the prediction theta_o + w_o T. */
static void source_reframe(const smd_drive_params *p, smd_drive_state *s, smd_real theta_next,
                           smd_real theta_o, smd_real w_o, smd_real T)
{
    if (D_POSITION(p) == SMD_POS_LCL_SMO_PLL) {
        smd_lcl_smo_reframe(&s->pos.u.smo, smd_wrap_pi(theta_next - theta_o - w_o * T));
    }
}

/* The source's back-EMF estimate in the frame of sample k (feed-forward of
 * the current PI). */
static smd_cplx source_emf_dq(const smd_drive_params *p, const smd_drive_state *s,
                              smd_cplx ej_k, smd_cplx ej_15, smd_real w_k)
{
    switch (D_POSITION(p)) {
    case SMD_POS_LCL_SMO_PLL:
        return smd_c(s->pos.u.smo.e_hat[0], s->pos.u.smo.e_hat[1]);
    case SMD_POS_LCL_LINEAR:
        return smd_cmul(smd_c(s->pos.u.lin.x2[2], s->pos.u.lin.x2[3]), smd_cconj(ej_k));
    case SMD_POS_SMDO_EMF:
        /* u_d_hat^{k+1} belongs to the middle of [t_{k+1}, t_{k+2}) (the
         * frame ej_15); the disturbance of model (15) is minus the EMF,
         * u_d = -j w psi e^{j theta} (eq. (43)), so the EMF estimate is
         * -u_d_hat */
        return smd_cmul(smd_cscale(s->smdo.u_d_hat, SMD_R(-1.0)), smd_cconj(ej_15));
    default:
        return smd_c(SMD_R(0.0), w_k * p->psi_r_hat); /* e = j w psi, rotor frame */
    }
}

/* The source's EMF estimate magnitude, V (0 for the encoder). */
static smd_cplx source_emf_vector(const smd_drive_params *p, const smd_drive_state *s)
{
    switch (D_POSITION(p)) {
    case SMD_POS_SMDO_EMF: return s->smdo.u_d_hat;
    case SMD_POS_LCL_SMO_PLL: return smd_c(s->pos.u.smo.e_hat[0], s->pos.u.smo.e_hat[1]);
    case SMD_POS_LCL_LINEAR: return smd_c(s->pos.u.lin.x2[2], s->pos.u.lin.x2[3]);
    default: return smd_c(SMD_R(0.0), SMD_R(0.0));
    }
}

static smd_real source_emf(const smd_drive_params *p, const smd_drive_state *s)
{
    return smd_cabs(source_emf_vector(p, s));
}

/* Whether the angle the source gives can jump (SMD_FAULT_ANGLE_JUMP): the
 * SMDO's (the LCL sources' PLL filters their observer's angle: no jump to
 * see there). */
static int source_can_jump(const smd_drive_params *p) { return D_POSITION(p) == SMD_POS_SMDO_EMF; }

/* Whether the source restarts on I/f after a lost lock or a failed start
 * (SMD_FAULT_RESTART): the SMDO's. */
static int source_can_restart(const smd_drive_params *p)
{
    return D_POSITION(p) == SMD_POS_SMDO_EMF;
}

/* The source from rest at a restart: the SMDO's speed estimate from zero. */
static void source_restart(const smd_drive_params *p, smd_drive_state *s)
{
    if (D_POSITION(p) == SMD_POS_SMDO_EMF) {
        smd_emf_pos_reset(&s->pos.u.emf, SMD_R(0.0));
    }
}

/* Every value of the source's state finite. */
static int source_finite(const smd_drive_params *p, const smd_drive_state *s)
{
    /* a sum of smd_nfs (smd_types.h): finite exactly when every value is */
    smd_real nf = SMD_R(0.0);
    int k;
    switch (D_POSITION(p)) {
    case SMD_POS_SMDO_EMF: {
        const smd_emf_pos_state *e = &s->pos.u.emf;
        nf = smd_nfs(e->theta_r_hat) + smd_nfs(e->w_r_hat) + smd_nfs(e->w_r_dir) +
             smd_nfs(e->phi_prev) + smd_nfs(e->w_r_raw);
        break;
    }
    case SMD_POS_LCL_SMO_PLL:
        /* (x_hat, e_hat and x_c: smd_lcl_smo_step_r checked them this sample
         * and reset the observer otherwise; the reframe after it turns them
         * by the PLL's correction, whose values the PLL check below covers) */
        for (k = 0; k < 2; k++) {
            nf += smd_nfs(s->pos.u.smo.d_hat[k]) + smd_nfs(s->pos.u.smo.v_prev[k]);
        }
        break;
    case SMD_POS_LCL_LINEAR:
        for (k = 0; k < 4; k++) nf += smd_nfs(s->pos.u.lin.z[k]) + smd_nfs(s->pos.u.lin.x2[k]);
        break;
    default: break;
    }
    if (source_is_lcl(D_POSITION(p))) {
        nf += smd_nfs(s->pos.pll.theta) + smd_nfs(s->pos.pll.w) + smd_nfs(s->pos.pll.a) +
              smd_nfs(s->pos.theta_err);
    }
    return smd_nf(nf) == SMD_R(0.0);
}

/* The source's internals in the view (the LCL observers'). */
static void source_view(const smd_drive_params *p, const smd_drive_state *s, smd_drive_view *v)
{
    if (D_POSITION(p) == SMD_POS_LCL_SMO_PLL) {
        const smd_lcl_smo_state *o = &s->pos.u.smo;
        v->e_hat = smd_c(o->e_hat[0], o->e_hat[1]);
        v->s = smd_c(o->s[0], o->s[1]);
        v->d_hat = smd_c(o->d_hat[0], o->d_hat[1]);
        v->v = smd_c(o->v_prev[0], o->v_prev[1]);
    } else if (D_POSITION(p) == SMD_POS_LCL_LINEAR) {
        v->e_lin = smd_c(s->pos.u.lin.x2[2], s->pos.u.lin.x2[3]);
    }
}

/* ------------------------------------------------------------ init */

/* Which parts fit together (SMD_ERR_COMBINATION otherwise). */
/* 1 if the configuration is the composition the core was built for (each
 * SMD_FIX_* defined; none: any) */
static int fixed_fits(const smd_drive_config *c)
{
    int ok = 1;
    (void)c;
#ifdef SMD_FIX_CURRENT
    ok = ok && c->current == SMD_FIX_CURRENT;
#endif
#ifdef SMD_FIX_POSITION
    ok = ok && c->position == SMD_FIX_POSITION;
#endif
#ifdef SMD_FIX_LCL
    ok = ok && c->lcl == SMD_FIX_LCL;
#endif
#ifdef SMD_FIX_RLS
    ok = ok && (c->rls_i_inj > SMD_R(0.0)) == (SMD_FIX_RLS != 0);
#endif
#ifdef SMD_FIX_SPEED_LOOP
    ok = ok && c->speed_loop == SMD_FIX_SPEED_LOOP;
#endif
#ifdef SMD_FIX_SUPERVISE_EVERY
    ok = ok && (c->supervise_every > 1 ? c->supervise_every : 1) ==
                   (SMD_FIX_SUPERVISE_EVERY > 1 ? SMD_FIX_SUPERVISE_EVERY : 1);
#endif
    return ok;
}

static smd_status check_parts(const smd_drive_config *c)
{
    if (c->current < SMD_CC_PI || c->current > SMD_CC_ROBUST_DBPC ||
        c->position < SMD_POS_ENCODER || c->position > SMD_POS_LCL_LINEAR ||
        c->start < SMD_START_RUNNING || c->start > SMD_START_IF || !is_flag(c->lcl) ||
        !is_flag(c->speed_loop) || !is_flag(c->emf_ff) || !is_flag(c->smdo_euler)) {
        return SMD_ERR_MODE;
    }
    if (!source_fits(c) || !fixed_fits(c)) {
        return SMD_ERR_COMBINATION;
    }
    if (c->lcl && c->current != SMD_CC_PI) {
        return SMD_ERR_COMBINATION; /* DBPC of i_2 through the filter is not designed */
    }
    if (!c->lcl && c->R_v > SMD_R(0.0)) {
        return SMD_ERR_COMBINATION; /* active damping needs the filter current i_1 */
    }
    return SMD_OK;
}

static smd_status check_protection(const smd_drive_config *c)
{
    if (!smd_in_range(c->i_trip, SMD_R(0.0), SMD_R(1e5)) ||
        !smd_in_range(c->u_dc_min, SMD_R(0.0), SMD_R(1e5)) ||
        !smd_in_range(c->u_dc_max, SMD_R(0.0), SMD_R(1e5)) ||
        (c->u_dc_max > SMD_R(0.0) && !(c->u_dc_max > c->u_dc_min)) ||
        (c->safe_state != SMD_SAFE_ZERO_VECTOR && c->safe_state != SMD_SAFE_PWM_OFF) ||
        c->lock_samples < 0 || c->lock_samples > 1000000 ||
        !smd_in_range(c->w_if_enter, SMD_R(0.0), SMD_R(1e7))) {
        return SMD_ERR_PROTECTION;
    }
    if (c->lock_samples > 0 &&
        (!smd_in_range(c->lock_ratio, SMD_R(1.0), SMD_R(1e3)) || !(c->lock_ratio > SMD_R(1.0)) ||
         !smd_in_range(c->w_lock_min, SMD_R(0.0), SMD_R(1e7)))) {
        return SMD_ERR_PROTECTION;
    }
    if (c->w_if_enter > SMD_R(0.0) && !(c->w_if_enter < c->w_handover)) {
        return SMD_ERR_PROTECTION;
    }
    if (c->w_if_enter > SMD_R(0.0) && !source_sensorless(c->position)) {
        return SMD_ERR_COMBINATION; /* the return to I/f is for sensorless sources */
    }
    if (!smd_in_range(c->a_ref, SMD_R(0.0), SMD_R(1e9)) || c->dwell < 0 || c->dwell > 10000000 ||
        c->chatter_max < 0 || c->chatter_max > 1000 || c->chatter_window < 0 ||
        c->chatter_window > 100000000 || (c->chatter_max > 0 && c->chatter_window < 1) ||
        c->hunt_max < 0 || c->hunt_max > 1000 || c->hunt_window < 0 ||
        c->hunt_window > 100000000 || (c->hunt_max > 0 && c->hunt_window < 1) ||
        c->track_samples < 0 || c->track_samples > 100000000 ||
        !smd_in_range(c->w_track, SMD_R(0.0), SMD_R(1e7)) ||
        (c->track_samples > 0 && !(c->w_track > SMD_R(0.0))) ||
        c->forced_samples < 0 || c->forced_samples > 100000000 ||
        !smd_in_range(c->osc_i, SMD_R(0.0), SMD_R(1e5)) ||
        !smd_in_range(c->osc_rel, SMD_R(0.0), SMD_R(100.0)) ||
        c->osc_samples < 0 || c->osc_samples > 10000000 ||
        (c->osc_samples > 0 && !(c->osc_i > SMD_R(0.0))) ||
        c->restart_max < 0 || c->restart_max > 100 || c->restart_window < 0 ||
        c->restart_window > 100000000 || (c->restart_max > 0 && c->restart_window < 1)) {
        return SMD_ERR_PROTECTION;
    }
    return SMD_OK;
}

#if !defined(SMD_REAL_DOUBLE)
/* A float's bits (C99: through a union). */
static uint32_t fbits(smd_real x)
{
    union {
        smd_real f;
        uint32_t u;
    } v;
    v.f = x;
    return v.u;
}
#endif

/* The bounds of inputs_plain: the phase currents within min(1e5, i_trip)
 * (a trip of 0 is off), the DC link within [max(u_dc_min, the smallest
 * positive float), min(1e5, u_dc_max)]: the positive floats' bit patterns
 * are in the order of their values. */
static void plain_bounds(smd_drive_params *p)
{
#if !defined(SMD_REAL_DOUBLE)
    const smd_real i_lim = p->i_trip > SMD_R(0.0) ? p->i_trip : SMD_R(1e5);
    const smd_real u_hi = p->u_dc_max > SMD_R(0.0) ? p->u_dc_max : SMD_R(1e5);
    const uint32_t lo = p->u_dc_min > SMD_R(0.0) ? fbits(p->u_dc_min) : 1u;
    p->plain_i2 = fbits(i_lim) << 1;
    p->plain_ulo = lo;
    p->plain_uspan = fbits(u_hi) - lo;
#else
    (void)p;
#endif
}

smd_status smd_drive_init(smd_drive_params *p, const smd_drive_config *c)
{
    smd_status st;
    if (p == 0 || c == 0) {
        return SMD_ERR_NULL;
    }
    st = check_parts(c);
    if (st != SMD_OK) {
        return st;
    }
    if (!smd_in_pos_range(c->T_sp, SMD_R(1.0))) {
        return SMD_ERR_TS;
    }
    if (c->speed_decimation < 1 || c->speed_decimation > 1000) {
        return SMD_ERR_DECIMATION;
    }
    if (c->handover < 0) {
        return SMD_ERR_HANDOVER;
    }
    if (c->supervise_every < 0 || c->supervise_every > 64) {
        return SMD_ERR_DECIMATION;
    }
    if (!smd_in_range(c->t_dead_comp, SMD_R(0.0), SMD_R(0.25) * c->T_sp) ||
        !(smd_in_range(c->i_dtc, SMD_R(0.0), SMD_R(1e5)) && c->i_dtc > SMD_R(0.0)) ||
        !isfinite(SMD_R(1.0) / c->i_dtc)) {
        /* (an i_dtc whose reciprocal overflows, below 2.9e-39 A in single
         * precision: the compensation's current over it would be 0 x inf) */
        return SMD_ERR_DEADTIME;
    }
    if (!smd_in_range(c->psi_r_hat, SMD_R(0.0), SMD_R(100.0))) {
        return SMD_ERR_PSI;
    }
    p->current = c->current;
    p->position = c->position;
    p->start = c->start;
    p->lcl = c->lcl;
    p->T_sp = c->T_sp;
    p->use_smdo = c->current == SMD_CC_ROBUST_DBPC || source_uses_smdo(c->position);
    p->speed_loop = c->speed_loop;
    p->speed_decimation = c->speed_decimation;
    p->handover = c->handover;
    p->emf_ff = c->emf_ff;
    p->psi_r_hat = c->psi_r_hat;
    p->dtc_ratio = c->t_dead_comp / c->T_sp;
    p->i_dtc = c->i_dtc;
    p->inv_i_dtc = SMD_R(1.0) / c->i_dtc;

    if (c->current != SMD_CC_PI) {
        st = smd_dbpc_init(&p->dbpc, c->T_sp, c->L_s_hat, c->R_s_hat, c->psi_r_hat);
        if (st != SMD_OK) {
            return st;
        }
    }
    if (c->current == SMD_CC_PI) {
        if (!smd_in_range(c->k_p_i, SMD_R(0.0), SMD_R(1e4)) ||
            !smd_in_range(c->k_i_i, SMD_R(0.0), SMD_R(1e9)) ||
            !smd_in_range(c->L_dec, SMD_R(0.0), SMD_R(10.0)) ||
            !smd_in_range(c->R_v, SMD_R(0.0), SMD_R(1e4)) || !is_flag(c->dec_ref)) {
            return SMD_ERR_CURRENT_PI;
        }
    }
    p->dec_ref = c->current == SMD_CC_PI ? c->dec_ref : 0;
    p->k_p_i = c->k_p_i;
    p->k_i_i = c->k_i_i;
    p->L_dec = c->L_dec;
    p->R_v = c->lcl ? c->R_v : SMD_R(0.0);
    if (D_USE_SMDO(p)) {
        st = smd_smdo_init(&p->smdo, c->T_sp, c->L_s_hat, c->R_s_hat, c->lambda_min, c->l,
                           c->w_c, c->rho);
        if (st != SMD_OK) {
            return st;
        }
        st = smd_smdo_set_euler(&p->smdo, c->smdo_euler);
        if (st != SMD_OK) {
            return st;
        }
    }
    st = source_init(p, c);
    if (st != SMD_OK) {
        return st;
    }
    if (c->start == SMD_START_IF || c->w_if_enter > SMD_R(0.0)) {
        if (!smd_in_range(c->i_start, SMD_R(0.0), SMD_R(1e5)) ||
            !smd_in_range(c->a_start, SMD_R(0.0), SMD_R(1e9)) ||
            !smd_in_range(c->w_handover, SMD_R(0.0), SMD_PI / c->T_sp)) {
            return SMD_ERR_START;
        }
    }
    st = check_protection(c);
    if (st != SMD_OK) {
        return st;
    }
    /* the R_s / psi_r tracker: off at rls_i_inj = 0; its model has no filter */
    p->use_rls = 0;
    if (!smd_in_range(c->rls_i_inj, SMD_R(0.0), SMD_R(1e5)) ||
        (c->rls_i_inj > SMD_R(0.0) && (c->lcl || (c->position != SMD_POS_ENCODER &&
                                                  c->position != SMD_POS_SMDO_EMF)))) {
        return SMD_ERR_RLS;
    }
    if (c->rls_i_inj > SMD_R(0.0)) {
        st = smd_rls_init(&p->rls, c->T_sp, c->current == SMD_CC_PI ? c->L_dec : c->L_s_hat,
                          c->rls_i_inj, c->rls_tau, c->rls_half, c->rls_w_min, c->R_s_hat,
                          c->psi_r_hat);
        if (st == SMD_OK && c->t_dead_comp > SMD_R(0.0)) {
            st = smd_rls_set_dead_time(&p->rls, c->t_dead_comp);
        }
        if (st == SMD_OK) {
            /* a winding 250 K colder or 390 K warmer than the model's: not a
             * resistance, a fit gone wrong (smd_rls_set_range) */
            st = smd_rls_set_range(&p->rls, SMD_R(0.5) * c->R_s_hat, SMD_R(2.5) * c->R_s_hat);
        }
        if (st == SMD_OK && c->position == SMD_POS_SMDO_EMF) {
            /* the SMDO's angle: the fit in its means' frame (smd_rls.h), and
             * the SMDO's R_s from the fit up to 2.5 R_s_hat, and as far as
             * its error loop stays 1.2 times faster than the stator's pole
             * (l + lambda_min / rho >= 1.2 R / L_s_hat, the design's rule:
             * docs/design_from_motor.md; on the 1 ohm, 50 uH micro motor,
             * designed at it, a fed R_s 40 % higher turned the angle 36 deg) */
            const smd_real r_loop = (c->l + c->lambda_min / c->rho) * c->L_s_hat / SMD_R(1.2);
            p->R_fb_max = r_loop < SMD_R(2.5) * c->R_s_hat ? r_loop : SMD_R(2.5) * c->R_s_hat;
            if (p->R_fb_max < c->R_s_hat) {
                p->R_fb_max = c->R_s_hat;
            }
            st = smd_rls_set_observer(&p->rls, 1);
            if (st == SMD_OK && c->t_dead_comp > SMD_R(0.0)) {
                st = smd_rls_set_band(&p->rls, c->i_dtc);
            }
        }
        if (st != SMD_OK) {
            return st;
        }
        p->use_rls = 1;
    }
    p->i_trip = c->i_trip;
    p->u_dc_min = c->u_dc_min;
    p->u_dc_max = c->u_dc_max;
    plain_bounds(p);
    p->safe_state = c->safe_state;
    p->lock_samples = c->lock_samples;
    p->lock_ratio = c->lock_ratio;
    p->w_lock_min = c->w_lock_min;
    p->w_if_enter = c->w_if_enter;
    p->w_src_max = source_speed_limit(c);
    p->R_hat = c->R_s_hat;
    p->L_hat = c->current == SMD_CC_PI ? c->L_dec : c->L_s_hat;
    p->a_ref = c->a_ref;
    p->if_lag = source_uses_smdo(c->position) && c->a_ref > SMD_R(0.0) ? c->a_ref / c->w_lpf
                                                                       : SMD_R(0.0);
    p->dwell = c->dwell;
    p->chatter_max = c->chatter_max;
    p->chatter_decay = c->chatter_max > 0 ? (smd_real)c->chatter_max / (smd_real)c->chatter_window
                                          : SMD_R(0.0);
    p->hunt_max = c->hunt_max;
    p->hunt_decay = c->hunt_max > 0 ? (smd_real)c->hunt_max / (smd_real)c->hunt_window
                                    : SMD_R(0.0);
    p->track_samples = c->track_samples;
    p->w_track = c->w_track;
    p->forced_samples = c->forced_samples;
    p->osc_i = c->osc_i;
    p->osc_rel = c->osc_rel;
    p->osc_samples = c->osc_samples;
    p->osc_k = c->osc_samples > 0 ? SMD_R(1.0) / (smd_real)c->osc_samples : SMD_R(0.0);
    p->restart_max = c->restart_max;
    /* the supervision's pieces every sup_n samples: their counts go up by
     * sup_n, the leaky counts leak sup_n samples' worth and the ripple's
     * filter takes sup_n samples' step, 1 - (1 - osc_k)^sup_n (sup_n = 1:
     * the values as before, bit for bit) */
    p->sup_n = c->supervise_every > 1 ? c->supervise_every : 1;
    p->sup_fin = 2 % D_SUP_N(p);
    p->sup_rip = 3 % D_SUP_N(p);
    if (D_SUP_N(p) > 1) {
        smd_real q = SMD_R(1.0);
        int k;
        for (k = 0; k < D_SUP_N(p); k++) {
            q *= SMD_R(1.0) - p->osc_k;
        }
        p->osc_k = SMD_R(1.0) - q;
        p->chatter_decay *= (smd_real)D_SUP_N(p);
        p->hunt_decay *= (smd_real)D_SUP_N(p);
    }
    p->restart_decay = c->restart_max > 0 && c->restart_window > 0
                           ? (smd_real)c->restart_max / (smd_real)c->restart_window
                           : SMD_R(0.0);
    p->i_start = c->i_start;
    p->a_start = c->a_start;
    p->w_handover = c->w_handover;
    p->i_max = c->i_max;
    st = smd_pi_init(&p->speed_pi, c->k_p_w, c->k_i_w, c->T_sp * (smd_real)c->speed_decimation,
                     c->i_max);
    if (st != SMD_OK) {
        return st;
    }
    return smd_svm_init(&p->svm, c->svm_limit, SMD_R(0.0));
}

void smd_drive_reset(const smd_drive_params *p, smd_drive_state *s, smd_real theta0,
                     smd_real w0, smd_real i_q0)
{
    smd_cplx zero = smd_c(SMD_R(0.0), SMD_R(0.0));
    if (p->start == SMD_START_IF) {
        s->phase = SMD_PHASE_FORCED;
    } else if (p->start == SMD_START_HANDOVER && p->handover > 0) {
        s->phase = SMD_PHASE_ENCODER;
    } else {
        s->phase = SMD_PHASE_SOURCE;
    }
    s->samples = 0;
    s->count = 0;
    s->torque_in = 0;
    s->primed = 0;
    s->theta = smd_wrap_pi(theta0);
    s->w = w0;
    s->theta_k = s->theta;
    s->w_k = w0;
    s->theta_f = s->theta;
    s->w_f = w0;
    s->start_dir = 0; /* an I/f start's direction: the reference's at its first sample */
    s->fault = 0u;
    s->lock_count = 0;
    s->dir_f = 0; /* the start ramps up; a return to I/f follows the reference */
    s->have_last = 0;
    s->i_s_ab = zero;
    s->i_dq = zero;
    s->i_dq_ref = smd_c(SMD_R(0.0), i_q0);
    s->x_i = zero;
    s->u_ab = zero;
    s->u_ab_next = zero;
    s->u_ab_ref = zero;
    smd_pi_reset(&s->speed_pi, i_q0);
    /* The disturbance of a running machine with an exact model is its back
     * EMF, yang2018 eq. (43); starting from it is what a flying start does. */
    smd_smdo_reset(&s->smdo, zero, smd_cj(smd_cscale(smd_cexpj(theta0), -w0 * p->psi_r_hat)));
    source_reset(p, s, theta0, w0);
    s->w_ref_r = w0;
    s->phase_samples = 0;
    s->chatter = SMD_R(0.0);
    s->hunt = SMD_R(0.0);
    s->hunt_rail = 0;
    s->track_count = 0;
    s->forced_count = 0;
    s->start_count = 0;
    s->osc_count = 0;
    s->osc_n = 0;
    s->osc_ms = SMD_R(0.0);
    s->i_prev1 = zero;
    s->warn = 0u;
    s->warn_rls = 0u;
    s->R_smdo = D_USE_SMDO(p) ? p->smdo.R_s_hat : SMD_R(0.0);
    s->restarts = SMD_R(0.0);
    s->jumped = 0;
    s->sup_k = 0;
    s->u_whole = 0;
    s->du_clip = zero;
    if (D_USE_RLS(p)) {
        smd_rls_reset(&p->rls, &s->rls);
    }
}

void smd_drive_start_duties(const smd_drive_params *p, smd_drive_state *s, smd_real u_dc,
                            smd_real d_abc[3])
{
    /* steady state of the machine model in the frame of theta0 (rotor
     * frame, i = j i_q0): u = (R + j w L) j i_q0 + j w psi */
    const smd_real w = s->w_k, iq = s->i_dq_ref.im;
    smd_cplx u_dq = smd_c(-w * p->L_hat * iq, p->R_hat * iq + w * p->psi_r_hat);
    smd_cplx u_ab = smd_dq_to_ab(u_dq, s->theta_k + SMD_R(0.5) * w * p->T_sp);
    if (!(smd_cfinite(u_ab) && u_dc > SMD_R(0.0) && isfinite(u_dc))) {
        u_ab = smd_c(SMD_R(0.0), SMD_R(0.0));
        u_dc = SMD_R(1.0);
    }
    smd_svm_step(&p->svm, u_ab, u_dc, d_abc, &s->u_ab_next);
    if (D_CURRENT(p) == SMD_CC_PI) {
        /* the PI's integrator holds what the steady state needs beyond the
         * decoupling (and the EMF feed-forward, when on) */
        s->x_i = smd_c(SMD_R(0.0), p->R_hat * iq + (p->emf_ff ? SMD_R(0.0) : w * p->psi_r_hat));
    }
}

static smd_real clampr(smd_real x, smd_real lim)
{
    return x > lim ? lim : (x < -lim ? -lim : x);
}

/* A switch of the start-up supervisor (counted for SMD_FAULT_CHATTER). */
static void switch_phase(smd_drive_state *s, int phase)
{
    s->phase = phase;
    s->phase_samples = 0;
    s->chatter += SMD_R(1.0);
}

/* ------------------------------------------------------------ the step */

/* One sample's values, passed from each step of control() to the next (the
 * measured currents stay in control() and go by pointer to the steps that
 * read them: a smd_cplx argument is copied where the call is). */
typedef struct sample {
    smd_real T;                   /* the sampling period T_sp */
    smd_real w_ref;               /* the speed reference, slew-limited */
    int settled;                  /* dwell samples since the last start-up switch */
    smd_real theta_o;             /* the frame predicted for k */
    smd_real w_o;
    smd_real theta_k;             /* the frame of k */
    smd_real w_k;
    smd_real theta_next;          /* the frame of k+1 */
    smd_real w_next;
    /* e^{j theta_k} and e^{j (theta_k + 1.5 w_k T)} (the middle of the
     * period the voltage is applied in), each taken once for the transforms
     * of steps 6 that need them (rotations()): the bits smd_ab_to_dq and
     * smd_dq_to_ab give with the angle */
    smd_cplx ej_k;
    smd_cplx ej_15;
    /* e^{j theta_ej}, taken by step 1 for the LCL sliding-mode observer's
     * Park transforms (ej_ok); step 6 reuses it when theta_k is theta_ej */
    smd_cplx ej_o;
    smd_real theta_ej;
    int ej_ok;
    /* the fast build's e^{j w_k T / 2} (step 5, observe_disturbance): the
     * SMDO's rotation of eq. (19) is its square, and the robust DBPC's
     * reference of eq. (7) turns by it */
    smd_cplx ej_half;
    smd_real inv_u_dc;            /* 1 / u_dc (the fast build's modulator) */
} sample;

/* The speed reference of the sample: the input, or slew-limited at a_ref. */
static smd_real slew_reference(const smd_drive_params *p, smd_drive_state *s, smd_real w_ref,
                               smd_real T)
{
    if (p->a_ref > SMD_R(0.0)) {
        smd_real dw = w_ref - s->w_ref_r, step = p->a_ref * T;
        s->w_ref_r += dw > step ? step : (dw < -step ? -step : dw);
    } else {
        s->w_ref_r = w_ref;
    }
    return s->w_ref_r;
}

/* 0. The sample: the measured current i_s_ab kept, the voltage applied now
 * (computed last time), the frame predicted for k, the speed reference. */
static void take_sample(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in,
                        const smd_cplx *i_s_ab, sample *x)
{
    x->T = p->T_sp;
    x->ej_ok = 0;
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    x->ej_half = smd_c(SMD_R(1.0), SMD_R(0.0)); /* (step 5 sets it where it is used) */
#endif
    x->theta_o = s->theta;
    x->w_o = s->w;
    x->settled = s->phase_samples >= p->dwell;
    s->i_prev1 = s->i_s_ab; /* (the ripple's measure: supervise) */
    s->i_s_ab = *i_s_ab;
    s->u_ab = s->u_ab_next; /* the voltage computed last time is the one applied now */
    x->w_ref = slew_reference(p, s, in->w_ref, x->T);
    if (!s->primed) {
        /* The SMDO's current starts at the first sample, so that a start
         * under load does not begin with a large sliding error. */
        s->smdo.i_s_hat = *i_s_ab;
        s->primed = 1;
    }
}

/* The direction of the forced current: dir_f, or the start's (0: a start
 * waiting for its reference). */
static int forced_dir(const smd_drive_state *s) { return s->dir_f != 0 ? s->dir_f : s->start_dir; }

/* An I/f start begins when the reference asks for a speed (no current
 * before), toward its sign; from rest the forced current (q axis of the
 * forced frame) starts 60 deg behind theta0 in that direction, where it
 * gives half its torque: loaded or not, the rotor's equilibrium on the
 * stable side is at most 30 deg away (0.5 of the torque either way), and it
 * swings by that at most, not by the 90 deg a start at full torque gives a
 * light rotor (smd_drive.h). */
static void begin_start(smd_drive_state *s, smd_real w_ref, sample *x)
{
    s->start_dir = w_ref < SMD_R(0.0) ? -1 : 1;
    if (s->w_f == SMD_R(0.0) && s->i_dq_ref.im == SMD_R(0.0)) {
        s->theta_f = smd_wrap_pi(s->theta_f - (smd_real)s->start_dir * SMD_PI / SMD_R(3.0));
        x->theta_o = s->theta_f;
    }
}

/* 2. The frame of sample k: forced (I/f), the encoder's during a handover,
 * or the source's. */
static void frame_now(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in,
                      sample *x)
{
    if (s->phase == SMD_PHASE_FORCED) {
        if (s->dir_f == 0 && s->start_dir == 0 && in->w_ref != SMD_R(0.0)) {
            begin_start(s, in->w_ref, x);
        }
        x->theta_k = x->theta_o;
        x->w_k = x->w_o;
    } else if (s->phase == SMD_PHASE_ENCODER) {
        x->theta_k = in->theta_enc;
        x->w_k = in->w_enc;
    } else {
        source_frame(p, s, in, x->theta_o, x->w_o, &x->theta_k, &x->w_k);
    }
}

/* Sensorless below w_if_enter on the way through zero: back to the forced
 * frame, from where the source is now, driven toward the reference's target
 * (w_ref, the input); the forced current i_start (q axis of the forced
 * frame, sign dir_f) is placed so that its q component in the source's
 * frame is the current that was flowing, on the stable side (dir_f
 * sin(theta_f - theta) < 0): the torque does not step, and the rotor does
 * not swing about the forced angle. The forced speed starts at the source's
 * plus lag: from the SMDO's speed, the rotor's, not the estimate's: the
 * estimate, low-passed at w_lpf, lags a rotor that follows the slewed
 * reference at a_ref by a_ref / w_lpf, a quarter of w_if_enter as the
 * derived a_ref allows it (an invented 30,000 r/min spindle: the frame
 * started 33 % faster than its light rotor, which slipped, start_failed on
 * every seed). */
SMD_COLD static void return_to_forced(const smd_drive_params *p, smd_drive_state *s, smd_real w_ref,
                             const sample *x, smd_real lag)
{
    smd_real c, sn;
    switch_phase(s, SMD_PHASE_FORCED);
    s->dir_f = (w_ref - x->w_k) < SMD_R(0.0) ? -1 : 1;
    c = p->i_start > SMD_R(0.0) ? (smd_real)s->dir_f * s->i_dq_ref.im / p->i_start
                                : SMD_R(1.0);
    c = c > SMD_R(1.0) ? SMD_R(1.0) : (c < SMD_R(-1.0) ? SMD_R(-1.0) : c);
    sn = SMD_SQRT(SMD_R(1.0) - c * c);
    s->theta_f = smd_wrap_pi(x->theta_k - (smd_real)s->dir_f * SMD_ATAN2(sn, c));
    s->w_f = x->w_k + lag;
}

/* The forced speed: the start from standstill ramps at a_start in the
 * reference's direction (0: waiting), no farther than the reference (the
 * input w_in) asks (below the handover speed the drive stays on I/f there);
 * a return to I/f follows the reference w_ref at a_start, through zero. */
static void ramp_forced(const smd_drive_params *p, smd_drive_state *s, smd_real w_in,
                        smd_real w_ref, smd_real T)
{
    if (p->start == SMD_START_IF && s->dir_f == 0) {
        const smd_real lim = SMD_FABS(w_in);
        s->w_f += (smd_real)s->start_dir * p->a_start * T;
        if ((smd_real)s->start_dir * s->w_f > lim) {
            s->w_f = (smd_real)s->start_dir * lim;
        }
    } else {
        smd_real dw = w_ref - s->w_f;
        smd_real step = p->a_start * T;
        s->w_f += dw > step ? step : (dw < -step ? -step : dw);
    }
}

/* Whether the source takes over from the forced phase: it agrees, and the
 * start reached the handover speed, or a return to I/f, settled, did in the
 * reference's direction. */
static int handover_due(const smd_drive_params *p, const smd_drive_state *s, const sample *x)
{
    const smd_real sg = forced_dir(s) < 0 ? SMD_R(-1.0) : SMD_R(1.0);
    const int agree = source_agrees(p, s, sg, x->theta_k, s->w_f);
    return agree && ((s->dir_f == 0 && (smd_real)s->start_dir * s->w_f >= p->w_handover) ||
                     (s->dir_f != 0 && x->settled && SMD_FABS(s->w_f) >= p->w_handover &&
                      s->w_f * x->w_ref > SMD_R(0.0)));
}

/* The handover from the forced phase: the source takes over (its PLL on the
 * observer's angle at the forced speed), the speed loop on the current that
 * was flowing, seen in the source's frame (the forced current's q component
 * there). */
static void hand_over(const smd_drive_params *p, smd_drive_state *s, sample *x)
{
    smd_real d_src = source_offset(p, s, x->theta_k);
    switch_phase(s, SMD_PHASE_SOURCE);
    source_take_over(p, s, x->theta_k, x->w_k, x->T, &x->theta_next, &x->w_next);
    smd_pi_reset(&s->speed_pi, s->i_dq_ref.im * SMD_COS(d_src));
    s->count = 0;
}

/* The frame of k+1 in the forced phase: the forced angle turned at the
 * forced speed, until the source takes over. */
static void forced_next(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in,
                        sample *x)
{
    if (p->start == SMD_START_IF && s->dir_f == 0 && s->start_dir != 0 &&
        in->w_ref * (smd_real)s->start_dir < SMD_R(0.0)) {
        /* a start whose reference turned the other way before the handover:
         * the forced frame follows it through zero as a return to I/f does,
         * placed so that the torque does not step (the start ramp only ran
         * up to |w_ref| in the start's direction: a reference of +100 then
         * -100 r/min below the handover ended at +133 r/min, no fault) */
        return_to_forced(p, s, in->w_ref, x, SMD_R(0.0));
    }
    ramp_forced(p, s, in->w_ref, x->w_ref, x->T);
    s->theta_f = smd_wrap_pi(s->theta_f + s->w_f * x->T);
    x->theta_next = s->theta_f;
    x->w_next = s->w_f;
    if (p->a_ref > SMD_R(0.0)) {
        /* the slew-limited reference goes on from the forced speed: at the
         * handover from where the rotor is, not from where a ramp that the
         * forced phase did not follow would be */
        s->w_ref_r = s->w_f;
    }
    if (handover_due(p, s, x)) {
        hand_over(p, s, x);
    }
}

/* The frame of k+1 during a handover: the encoder's one sample on; after
 * `handover` samples the source takes over (a non-finite encoder sample
 * would stay in the PLL for good: the handover waits for a finite one). */
static void encoder_next(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in,
                         sample *x)
{
    x->theta_next = smd_wrap_pi(in->theta_enc + in->w_enc * x->T);
    x->w_next = in->w_enc;
    s->samples++;
    if (s->samples >= p->handover && isfinite(x->theta_next) && isfinite(x->w_next)) {
        switch_phase(s, SMD_PHASE_SOURCE);
        source_take_over_encoder(s, x->theta_next, x->w_next);
    }
}

/* 3. The frame of sample k+1 (forced angle, encoder, PLL) and the start-up
 * transitions. */
static void frame_next(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in,
                       sample *x)
{
    if (s->phase == SMD_PHASE_SOURCE && p->w_if_enter > SMD_R(0.0) && x->settled &&
        SMD_FABS(x->w_k) < p->w_if_enter &&
        (SMD_FABS(x->w_ref) < p->w_handover || x->w_ref * x->w_k < SMD_R(0.0))) {
        /* (the SMDO's lag, while the slewed reference still moves toward
         * w_ref: p->if_lag is 0 with another source; computed here, as a
         * value: the sample's w_ref read inside return_to_forced cost the
         * Cortex-M4F step 24 cycles every sample, the sample no longer kept
         * in registers) */
        return_to_forced(p, s, in->w_ref, x,
                         x->w_ref == in->w_ref ? SMD_R(0.0)
                                               : (x->w_ref < in->w_ref ? p->if_lag : -p->if_lag));
    }
    if (s->phase == SMD_PHASE_FORCED) {
        forced_next(p, s, in, x);
    } else if (s->phase == SMD_PHASE_ENCODER) {
        encoder_next(p, s, in, x);
    } else {
        source_next(p, s, x->theta_k, x->w_k, &x->theta_next, &x->w_next);
    }
    source_reframe(p, s, x->theta_next, x->theta_o, x->w_o, x->T);
}

/* 4. The current reference: forced, from the speed loop or the input; each
 * axis clamped to +-i_max. */
static void current_reference(const smd_drive_params *p, smd_drive_state *s,
                              const smd_drive_in *in, const sample *x)
{
    if (s->phase == SMD_PHASE_FORCED) {
        /* on the q axis of the forced frame, in the direction the forced
         * speed is driven (the start: the reference's) */
        s->i_dq_ref = smd_c(SMD_R(0.0), (s->dir_f < 0 || (s->dir_f == 0 && s->start_dir < 0))
                                            ? -p->i_start : p->i_start);
        if (s->dir_f == 0 && s->start_dir == 0) {
            s->i_dq_ref.im = SMD_R(0.0); /* a start waiting for its reference */
        }
    } else {
        s->i_dq_ref.re = in->i_dq_ref.re;
        if (D_USE_RLS(p)) {
            /* the tracker's excitation (smd_rls.h) */
            s->i_dq_ref.re += smd_rls_injection(&p->rls, &s->rls);
        }
        if (D_SPEED_LOOP(p) && !s->torque_in) {
#if defined(SMD_PROBE_NO_SPEED_PI)
            /* (a measurement: the input's q current, no speed PI) */
            (void)x;
            s->i_dq_ref.im = in->i_dq_ref.im;
#else
            if (s->count == 0) {
                s->i_dq_ref.im = smd_pi_step(&p->speed_pi, &s->speed_pi, x->w_ref - x->w_k);
            }
#endif
            /* (count + 1) mod speed_decimation, without the division */
            s->count = s->count + 1 >= p->speed_decimation ? 0 : s->count + 1;
        } else {
            s->i_dq_ref.im = in->i_dq_ref.im;
        }
    }
    s->i_dq_ref.re = clampr(s->i_dq_ref.re, p->i_max);
    s->i_dq_ref.im = clampr(s->i_dq_ref.im, p->i_max);
}

/* 5. The SMDO, eq. (34)-(39), when robust DBPC or the smdo_emf source needs
 * it: i_hat^{k+1}, u_d_hat^{k+1}. Returns st_in, or the SMDO's error. */
static smd_status observe_disturbance(const smd_drive_params *p, smd_drive_state *s,
                                      const smd_cplx *i_s_ab, sample *x, smd_status st_in)
{
    smd_status st = st_in;
    if (D_USE_SMDO(p)) { /* (with the robust DBPC, always) */
        /* the voltage the inverter applies during [k-1, k): u_ab, less what
         * a clipped compensation left out (du_clip, of the last sample); the
         * model's R_s: R_s_hat, or the tracker's (rls_feed); the rotation
         * e^{j w_k T} (the fast build: the square of e^{j w_k T / 2}, one
         * series for both of its uses) */
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
        smd_cplx rot;
        x->ej_half = smd_cexpj_small(SMD_R(0.5) * x->w_k * x->T);
        rot = smd_cmul(x->ej_half, x->ej_half);
#else
        const smd_cplx rot = smd_cexpj_small(x->w_k * x->T);
#endif
        smd_status ss = smd_smdo_step_rot(&p->smdo, &s->smdo, *i_s_ab,
                                          smd_cadd(s->u_ab, s->du_clip), x->w_k, s->R_smdo, rot);
        if (ss != SMD_OK) {
            st = ss;
        }
    }
    return st;
}

/* The current PI in the frame of k with cross-coupling decoupling, EMF
 * feed-forward and (LCL) active damping by a virtual resistance on the
 * capacitor current i_1 - i_2; its voltage in the stationary frame at the
 * middle of the application period. */
static smd_cplx current_pi(const smd_drive_params *p, smd_drive_state *s, const smd_cplx *i_s_ab,
                           const smd_cplx *i1_ab, const sample *x)
{
    const smd_real T = x->T;
    const smd_real w_k = x->w_k;
    const smd_cplx ej_k_c = smd_cconj(x->ej_k);
    const smd_cplx i2 = s->i_dq = smd_cmul(*i_s_ab, ej_k_c);
    const smd_cplx e = smd_csub(s->i_dq_ref, i2);
    const smd_cplx x_i = smd_cadd(s->x_i, smd_cscale(e, p->k_i_i * T));
    smd_cplx u = smd_cadd(smd_cscale(e, p->k_p_i), x_i);
    /* the decoupling: with the measured current (its delay and, behind a
     * filter, the filter's dynamics inside a loop of gain w L_dec), or with
     * the reference (no loop: yao2022's motor at 100 kr/min and no load
     * oscillated at 2.3 kHz, 15 A, with the measured one, w L_dec 1.1 ohm
     * against k_p_i 0.35) */
    u = smd_cadd(u, smd_cscale(smd_cj(p->dec_ref ? s->i_dq_ref : i2), w_k * p->L_dec));
    if (p->emf_ff && s->phase != SMD_PHASE_FORCED) {
        u = smd_cadd(u, source_emf_dq(p, s, x->ej_k, x->ej_15, w_k));
    }
    if (D_LCL(p)) {
        u = smd_csub(u, smd_cscale(smd_csub(smd_cmul(*i1_ab, ej_k_c), i2), p->R_v));
    }
    s->x_i = x_i;
    return smd_cmul(u, x->ej_15);
}

/* The rotations of step 6, each once: e^{j theta_k} for the PI's Park
 * transforms, e^{j (theta_k + 1.5 w_k T)} for its output, its anti-windup
 * and the dead-time compensation (the sines a composition does not use are
 * not taken). */
static void rotations(const smd_drive_params *p, sample *x)
{
    const int pi = D_CURRENT(p) == SMD_CC_PI;
    const smd_cplx one = smd_c(SMD_R(1.0), SMD_R(0.0)); /* (unused: not taken) */
    x->ej_k = pi ? ((x->ej_ok && x->theta_k == x->theta_ej) ? x->ej_o : smd_cexpj(x->theta_k))
                 : one;
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    /* the fast build turns e^{j theta_k} by 1.5 w_k T (smd_cexpj_unit) */
    if (pi) {
        x->ej_15 = smd_cmul(x->ej_k, smd_cexpj_unit(SMD_R(1.5) * x->w_k * x->T));
        return;
    }
#endif
    x->ej_15 = (pi || p->dtc_ratio > SMD_R(0.0))
                   ? smd_cexpj(x->theta_k + SMD_R(1.5) * x->w_k * x->T)
                   : one;
}

/* 6. Current control: DBPC eq. (8)-(9), robust DBPC eq. (7) and (42), or
 * the PI; the voltage reference in the stationary frame. */
static smd_cplx current_control(const smd_drive_params *p, smd_drive_state *s,
                                const smd_cplx *i_s_ab, const smd_cplx *i1_ab, const sample *x)
{
    switch (D_CURRENT(p)) {
    case SMD_CC_DBPC:
        return smd_dbpc_conventional(&p->dbpc, *i_s_ab, s->u_ab, s->i_dq_ref, x->theta_k,
                                     x->w_k);
    case SMD_CC_ROBUST_DBPC: {
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
        /* the fast build: e^{j (theta_k + 2 w_k T)} of eq. (7) as the dead-time
         * compensation's e^{j (theta_k + 1.5 w_k T)} (rotations) turned by
         * 0.5 w_k T (smd_cexpj_small), not a second argument reduction */
        const smd_cplx i_ref_k2 =
            p->dtc_ratio > SMD_R(0.0)
                ? smd_cmul(s->i_dq_ref, smd_cmul(x->ej_15, x->ej_half))
                : smd_dbpc_ref_k2(&p->dbpc, s->i_dq_ref, x->theta_k, x->w_k);
#else
        const smd_cplx i_ref_k2 = smd_dbpc_ref_k2(&p->dbpc, s->i_dq_ref, x->theta_k, x->w_k);
#endif
        /* (with the SMDO's R_s: rls_feed) */
        return smd_dbpc_robust_r(&p->dbpc, s->smdo.i_s_hat, s->smdo.u_d_hat, i_ref_k2,
                                 s->R_smdo);
    }
    default: return current_pi(p, s, i_s_ab, i1_ab, x);
    }
}

/* The duties of the voltage reference u_ref: one that is not finite is
 * replaced by zero (the PI's integrators too) and the status st_in by
 * SMD_ERR_NONFINITE; the modulator's limit with the PI's anti-windup; the
 * dead-time compensation. */
static smd_status modulate(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in,
                           smd_drive_out *out, const sample *x, smd_cplx u_ref, smd_status st_in)
{
    smd_status st = st_in;
    if (!smd_cfinite(u_ref)) {
        st = SMD_ERR_NONFINITE;
        u_ref = smd_c(SMD_R(0.0), SMD_R(0.0));
        s->x_i = u_ref;
    }
    s->u_ab_ref = u_ref;
    smd_svm_step_finite_r(&p->svm, u_ref, in->u_dc, x->inv_u_dc, out->d_abc, &s->u_ab_next);
    if (D_CURRENT(p) == SMD_CC_PI && p->k_i_i > SMD_R(0.0)) {
        /* anti-windup: keep the integrator where the limited voltage is what
         * the law would have given (without integral action there is no
         * integrator to keep: a P law must not remember a saturation) */
        smd_cplx du = smd_csub(s->u_ab_next, u_ref);
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
        /* (the fast build without the square roots: |du|^2 > 1e-12 (1 +
         * |u_ref|^2), a threshold within a factor sqrt 2 of the exact
         * build's 1e-6 (1 + |u_ref|): either only skips rounding noise) */
        const int limited = du.re * du.re + du.im * du.im >
                            SMD_R(1e-12) * (SMD_R(1.0) + u_ref.re * u_ref.re + u_ref.im * u_ref.im);
#else
        const int limited = smd_cabs(du) > SMD_R(1e-6) * (SMD_R(1.0) + smd_cabs(u_ref));
#endif
        if (limited) {
            s->x_i = smd_cadd(s->x_i, smd_cmul(du, smd_cconj(x->ej_15)));
        }
    }
    if (p->dtc_ratio > SMD_R(0.0)) {
        /* current expected in the middle of the next period, t_k + 1.5 T_sp */
        smd_real i_abc[3];
        smd_cplx i_mid = smd_cmul(s->i_dq_ref, x->ej_15);
        smd_ab_to_abc(i_mid, i_abc);
        /* where a compensated duty was clipped at 0 or 1 the inverter does
         * not apply the modulator's voltage; the SMDO is given what it does
         * apply (yang2018 Fig. 7(b) at 75 r/min has 7 % of its duties at 0
         * or 1: given the modulator's voltage, 2 of 10 noise seeds lost the
         * rotor) */
        s->du_clip = smd_svm_deadtime_comp_lost(out->d_abc, i_abc, p->dtc_ratio, p->i_dtc,
                                                p->inv_i_dtc, in->u_dc);
    }
    return st;
}

/* A jump of the source's angle (SMD_FAULT_ANGLE_JUMP): on the source for
 * more than lock_samples, above w_lock_min, the angle used moved by more
 * than 45 deg from the last one turned at the last speed. */
static void check_jump(const smd_drive_params *p, smd_drive_state *s, const sample *x)
{
    s->jumped = 0;
    if (s->phase == SMD_PHASE_SOURCE && source_can_jump(p) && p->lock_samples > 0 &&
        s->phase_samples > p->lock_samples && SMD_FABS(x->w_k) >= p->w_lock_min) {
        const smd_real d = smd_wrap_pi(x->theta_k - s->theta_k - s->w_k * x->T);
        s->jumped = SMD_FABS(d) > SMD_PI / SMD_R(4.0);
    }
}

/* The end of the sample: the frames of k and k+1 kept for the next one. */
static void end_sample(const smd_drive_params *p, smd_drive_state *s, const sample *x)
{
    check_jump(p, s, x);
    s->theta_k = x->theta_k;
    s->w_k = x->w_k;
    s->theta = x->theta_next;
    s->w = x->w_next;
    if (s->phase_samples < 2000000000) {
        s->phase_samples++;
    }
}

/* With the SMDO's angle, the tracker's R_s is the SMDO's model from the next
 * sample on (and the robust DBPC's, whose model must be the SMDO's): its
 * angle then does not take the resistance's change in (smd_rls.h); within
 * [0.5 R_s_hat, R_fb_max], and R_s_hat while the estimate is stale
 * (rls_stale: not a value to steer by). */
static void rls_feed(const smd_drive_params *p, smd_drive_state *s)
{
    const smd_real R0 = p->smdo.R_s_hat;
    const smd_real R = s->warn_rls != 0u ? R0 : s->rls.R_hat;
    s->R_smdo = R > p->R_fb_max ? p->R_fb_max : (R > SMD_R(0.5) * R0 ? R : SMD_R(0.5) * R0);
}

/* One sample of the composed drive on good inputs (smd_drive_step checks
 * them before and the state after), in its steps. */
static smd_status control(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in,
                          smd_drive_out *out, smd_real inv_u_dc)
{
    const smd_cplx i_s_ab = smd_ab2_to_ab(in->i_a, in->i_b);
    const smd_cplx i1_ab = D_LCL(p) ? smd_ab2_to_ab(in->i1_a, in->i1_b) : i_s_ab;
    sample x;
    smd_status st;
    take_sample(p, s, in, &i_s_ab, &x);
    x.inv_u_dc = inv_u_dc;
    /* 1. the position source's estimates at k */
    st = source_observe(p, s, &i1_ab, &i_s_ab, x.theta_o, x.w_o, &x.ej_o, &x.ej_ok);
    x.theta_ej = x.theta_o;
    /* 2. the frame of sample k */
    frame_now(p, s, in, &x);
    /* 3. the frame of k+1, start-up transitions */
    frame_next(p, s, in, &x);
    /* 4. the current reference: forced, speed loop or input */
    current_reference(p, s, in, &x);
    /* 5. the SMDO */
    st = observe_disturbance(p, s, &i_s_ab, &x, st);
    /* 6. current control, and the duties */
    rotations(p, &x);
    st = modulate(p, s, in, out, &x, current_control(p, s, &i_s_ab, &i1_ab, &x), st);
    if (D_USE_RLS(p)) {
        /* the tracker: i(k), the voltage of [k, k+1) and whether the inverter
         * applies it whole (computed last sample), the frame of k, which is the
         * rotor's except in the forced phase; then whether the voltage just
         * computed for [k+1, k+2) is whole: not limited by the modulator, no
         * duty clipped at 0 or 1 */
        int k, whole = s->u_ab_next.re == s->u_ab_ref.re && s->u_ab_next.im == s->u_ab_ref.im;
        smd_rls_step(&p->rls, &s->rls, i_s_ab, s->u_ab, s->u_whole, x.theta_k, x.w_k,
                     s->phase != SMD_PHASE_FORCED);
        for (k = 0; k < 3; k++) {
            whole = whole && out->d_abc[k] > SMD_R(0.0) && out->d_abc[k] < SMD_R(1.0);
        }
        s->u_whole = whole;
        s->warn_rls = smd_rls_stale(&p->rls, &s->rls) ? (uint32_t)SMD_FAULT_RLS_STALE : 0u;
        if (p->rls.observer) {
            rls_feed(p, s);
        }
    }
    end_sample(p, s, &x);
    return st;
}

/* ------------------------------------------------------------ protection */

/* finite and within +-lim (lim finite): a NaN or an infinity fails the
 * compare itself */
static int in_lim(smd_real x, smd_real lim) { return SMD_FABS(x) <= lim; }

/* Whether the inputs are plain: every input check_inputs may look at
 * finite and within its range, the phase currents (the third one too) within
 * the overcurrent trip and the DC link within its trips; then check_inputs
 * finds nothing and protect trips nothing, and neither runs. A float's bits
 * doubled (its sign shifted out) are in the order of its magnitude, with
 * the NaNs above infinity: one integer compare each, no VMRS and no branch.
 * The double build, or inputs beyond these bounds, take the full checks. */
static int inputs_plain(const smd_drive_params *p, const smd_drive_state *s,
                        const smd_drive_in *in)
{
#if !defined(SMD_REAL_DOUBLE)
    const uint32_t i2 = p->plain_i2;
    /* (check_inputs' ranges: constants the compiler folds) */
    const uint32_t R2 = fbits(SMD_R(1e5)) << 1, W2 = fbits(SMD_R(1e7)) << 1,
                   TH2 = fbits(SMD_R(1e4)) << 1;
    uint32_t bad = (uint32_t)(fbits(in->u_dc) - p->plain_ulo > p->plain_uspan) |
                   (uint32_t)((fbits(in->i_a) << 1) > i2) | (uint32_t)((fbits(in->i_b) << 1) > i2) |
                   (uint32_t)((fbits(-in->i_a - in->i_b) << 1) > i2) |
                   (uint32_t)((fbits(in->w_ref) << 1) > W2) |
                   (uint32_t)((fbits(in->i_dq_ref.re) << 1) > R2) |
                   (uint32_t)((fbits(in->i_dq_ref.im) << 1) > R2);
    if (D_LCL(p)) {
        bad |= (uint32_t)((fbits(in->i1_a) << 1) > R2) | (uint32_t)((fbits(in->i1_b) << 1) > R2);
    }
    if (!source_sensorless(D_POSITION(p)) || s->phase == SMD_PHASE_ENCODER) {
        bad |= (uint32_t)((fbits(in->theta_enc) << 1) > TH2) |
               (uint32_t)((fbits(in->w_enc) << 1) > W2);
    }
    return bad == 0u;
#else
    (void)p;
    (void)s;
    (void)in;
    return 0;
#endif
}

/* SMD_FAULT_INPUT if an input the configuration uses is not finite or
 * beyond any physical range (smd_drive.h). */
static uint32_t check_inputs(const smd_drive_params *p, const smd_drive_state *s,
                             const smd_drive_in *in)
{
    const smd_real I_LIM = SMD_R(1e5), TH_LIM = SMD_R(1e4), W_LIM = SMD_R(1e7);
    int ok = in_lim(in->i_a, I_LIM) && in_lim(in->i_b, I_LIM) &&
             in->u_dc > SMD_R(0.0) && in->u_dc <= SMD_R(1e5);
    if (D_LCL(p)) {
        ok = ok && in_lim(in->i1_a, I_LIM) && in_lim(in->i1_b, I_LIM);
    }
    if (!source_sensorless(D_POSITION(p)) || s->phase == SMD_PHASE_ENCODER) {
        ok = ok && in_lim(in->theta_enc, TH_LIM) && in_lim(in->w_enc, W_LIM);
    }
    if (D_SPEED_LOOP(p) || p->w_if_enter > SMD_R(0.0) || s->phase == SMD_PHASE_FORCED) {
        ok = ok && in_lim(in->w_ref, W_LIM);
    }
    if (s->phase != SMD_PHASE_FORCED) {
        /* a current reference beyond any physical range (1e30 A) is as bad
         * as a NaN */
        ok = ok && in_lim(in->i_dq_ref.re, I_LIM) &&
             ((D_SPEED_LOOP(p) && !s->torque_in) || in_lim(in->i_dq_ref.im, I_LIM));
    }
    return ok ? 0u : (uint32_t)SMD_FAULT_INPUT;
}

/* The inputs of a bad sample: the last good ones one sample on, the
 * encoder angle advanced at its speed and the phase currents rotated at the
 * frame's speed (a steady state's currents turn with the rotor); the
 * inputs a composition does not read (the inverter-side currents without
 * the filter, the encoder without one) are left as they were; into *u
 * (not returned: a copy fewer). */
static void hold_inputs(const smd_drive_params *p, const smd_drive_state *s, smd_real T,
                        smd_drive_in *u)
{
    smd_real abc[3];
    /* (one sample's turn: the fast build's series below a radian) */
    smd_cplx r = smd_cexpj_unit(s->w_k * T);
    *u = s->last_in;
    if (!source_sensorless(D_POSITION(p)) || s->phase == SMD_PHASE_ENCODER) {
        u->theta_enc = smd_wrap_pi(u->theta_enc + u->w_enc * T);
    }
    smd_ab_to_abc(smd_cmul(smd_ab2_to_ab(u->i_a, u->i_b), r), abc);
    u->i_a = abc[0];
    u->i_b = abc[1];
    if (D_LCL(p)) {
        smd_ab_to_abc(smd_cmul(smd_ab2_to_ab(u->i1_a, u->i1_b), r), abc);
        u->i1_a = abc[0];
        u->i1_b = abc[1];
    }
}

/* The inputs kept for a bad sample (hold_inputs): the whole sample, or
 * the fields the composition reads: a sensorless drive without the filter
 * reads neither the inverter-side currents nor, outside the encoder's
 * handover (which a reset, clearing have_last, begins), the encoder. */
static void keep_inputs(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in)
{
    if (D_LCL(p) || !source_sensorless(D_POSITION(p)) || s->phase == SMD_PHASE_ENCODER) {
        s->last_in = *in;
    } else {
        s->last_in.i_a = in->i_a;
        s->last_in.i_b = in->i_b;
        s->last_in.u_dc = in->u_dc;
        s->last_in.w_ref = in->w_ref;
        s->last_in.i_dq_ref = in->i_dq_ref;
    }
}

/* Whether every duty is in [0, 1] (a NaN is not). The float build compares
 * bit patterns: those of +0 to 1 are the integers up to 1's, -0 is the sign
 * bit alone, and every other pattern (a negative value, one above 1, a NaN)
 * is neither; three integer compares without a VMRS each. */
static int duties_in_range(const smd_real d[3])
{
#if !defined(SMD_REAL_DOUBLE)
    const uint32_t one = fbits(SMD_R(1.0)), m0 = fbits(SMD_R(-0.0));
    const uint32_t a = fbits(d[0]), b = fbits(d[1]), c = fbits(d[2]);
    return ((uint32_t)(a <= one || a == m0) & (uint32_t)(b <= one || b == m0) &
            (uint32_t)(c <= one || c == m0)) != 0u;
#else
    return d[0] >= SMD_R(0.0) && d[0] <= SMD_R(1.0) && d[1] >= SMD_R(0.0) &&
           d[1] <= SMD_R(1.0) && d[2] >= SMD_R(0.0) && d[2] <= SMD_R(1.0);
#endif
}

/* Overcurrent and DC-link trips (latched into s->fault). */
static void protect(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in)
{
    if (p->i_trip > SMD_R(0.0)) {
        smd_real i_c = -in->i_a - in->i_b;
        smd_real pk = SMD_FABS(in->i_a);
        if (SMD_FABS(in->i_b) > pk) pk = SMD_FABS(in->i_b);
        if (SMD_FABS(i_c) > pk) pk = SMD_FABS(i_c);
        if (pk > p->i_trip) s->fault |= (uint32_t)SMD_FAULT_OVERCURRENT;
    }
    if (p->u_dc_min > SMD_R(0.0) && in->u_dc < p->u_dc_min) {
        s->fault |= (uint32_t)SMD_FAULT_UNDERVOLTAGE;
    }
    if (p->u_dc_max > SMD_R(0.0) && in->u_dc > p->u_dc_max) {
        s->fault |= (uint32_t)SMD_FAULT_OVERVOLTAGE;
    }
}

/* The safe state on the outputs: duties 0.5 (and pwm_off); the zero vector
 * is what the observers will see applied next. */
static smd_status apply_safe(const smd_drive_params *p, smd_drive_state *s, smd_drive_out *out,
                             uint32_t now)
{
    smd_cplx zero = smd_c(SMD_R(0.0), SMD_R(0.0));
    out->d_abc[0] = out->d_abc[1] = out->d_abc[2] = SMD_R(0.5);
    out->pwm_off = p->safe_state == SMD_SAFE_PWM_OFF;
    out->fault = s->fault | now;
    s->u_ab_next = zero;
    s->u_ab_ref = zero;
    s->du_clip = zero;
    return (now & (uint32_t)SMD_FAULT_INTERNAL) ? SMD_ERR_NONFINITE : SMD_ERR_FAULT;
}

/* A sample without control (a latched fault, or no good input yet): the
 * safe state, and the frame moves on at its speed. */
static smd_status hold_safe(const smd_drive_params *p, smd_drive_state *s, smd_drive_out *out,
                            uint32_t now)
{
    const smd_real T = p->T_sp;
    s->u_ab = s->u_ab_next;
    if (s->phase == SMD_PHASE_FORCED) {
        s->theta_f = smd_wrap_pi(s->theta_f + s->w_f * T);
        s->theta = s->theta_f;
        s->w = s->w_f;
    } else if (isfinite(s->theta) && isfinite(s->w)) {
        s->theta = smd_wrap_pi(s->theta + s->w * T);
    }
    return apply_safe(p, s, out, now);
}

static int state_finite(const smd_drive_params *p, const smd_drive_state *s)
{
    smd_real nf = smd_nfs(s->theta) + smd_nfs(s->w) + smd_nfs(s->theta_k) + smd_nfs(s->w_k) +
                  smd_nfs(s->theta_f) + smd_nfs(s->w_f) + smd_cnfs(s->x_i) +
                  smd_cnfs(s->u_ab_next) + smd_cnfs(s->i_dq_ref) + smd_nfs(s->speed_pi.x_i) +
                  smd_nfs(s->speed_pi.y);
    if (D_USE_SMDO(p)) {
        const smd_smdo_state *o = &s->smdo;
        nf += smd_cnfs(o->i_s_hat) + smd_cnfs(o->u_d_hat) + smd_cnfs(o->e_i_prev) +
              smd_cnfs(o->u_smo_prev) + smd_nfs(o->lambda);
    }
    return smd_nf(nf) == SMD_R(0.0) && source_finite(p, s);
}

/* After a non-finite value: every block restarts from the last good frame
 * (a flying start), keeping the supervisor's phase and the latched faults. */
static void recover(const smd_drive_params *p, smd_drive_state *s, smd_real theta0, smd_real w0,
                    smd_real i_q0)
{
    int phase = s->phase, samples = s->samples, count = s->count, dir_f = s->dir_f;
    int torque_in = s->torque_in;
    int start_dir = s->start_dir;
    int have_last = s->have_last;
    smd_drive_in last_in = s->last_in;
    uint32_t fault = s->fault;
    smd_real theta_f = s->theta_f, w_f = s->w_f;
    smd_real w_ref_r = s->w_ref_r, chatter = s->chatter, hunt = s->hunt;
    int phase_samples = s->phase_samples, forced_count = s->forced_count;
    const smd_rls_state rls = s->rls;
    smd_drive_reset(p, s, theta0, w0, i_q0);
    if (D_USE_RLS(p)) {
        /* the tracker's estimates stay (they guard themselves against a
         * non-finite sample); its next sample starts a new interval */
        s->rls = rls;
        s->rls.have_prev = 0;
    }
    if (isfinite(w_ref_r) && isfinite(chatter)) {
        s->w_ref_r = w_ref_r;
        s->chatter = chatter;
    }
    s->hunt = hunt; /* a count, always finite; the last limit is forgotten */
    s->phase_samples = phase_samples;
    s->forced_count = forced_count;
    s->phase = phase;
    s->samples = samples;
    s->count = count;
    s->torque_in = torque_in;
    s->dir_f = dir_f;
    s->start_dir = start_dir;
    s->fault = fault;
    s->have_last = have_last;
    s->last_in = last_in;
    if (isfinite(theta_f) && isfinite(w_f)) {
        s->theta_f = theta_f;
        s->w_f = w_f;
    }
}

/* Loss of lock of a sensorless source (smd_drive.h): its EMF estimate
 * against |w| psi_r_hat, its speed at the limit it can estimate, a jump of
 * its angle. */
static void check_lock(const smd_drive_params *p, smd_drive_state *s)
{
    smd_real e, w = SMD_FABS(s->w_k), e_exp;
    int bad;
    if (p->lock_samples == 0 || !source_sensorless(D_POSITION(p)) ||
        s->phase != SMD_PHASE_SOURCE) {
        s->lock_count = 0;
        return;
    }
    e_exp = w * p->psi_r_hat;
    bad = w >= SMD_R(0.999) * p->w_src_max;
    if (w >= p->w_lock_min && e_exp > SMD_R(0.0)) {
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
        /* (the fast build compares squares: no square root) */
        const smd_cplx ev = source_emf_vector(p, s);
        const smd_real e2 = ev.re * ev.re + ev.im * ev.im, hi = p->lock_ratio * e_exp;
        e = e_exp * e_exp;
        bad = bad || e2 > hi * hi || e2 * p->lock_ratio * p->lock_ratio < e;
#else
        e = source_emf(p, s);
        bad = bad || e > p->lock_ratio * e_exp || e * p->lock_ratio < e_exp;
#endif
    }
    /* a leaky count in quarter samples: an implausible sample adds 4, a
     * plausible one takes 1 away, so lock_samples implausible samples in a
     * row trip as before, and so does a source implausible more than a fifth
     * of the time for longer (an observer whose angle slips round and round,
     * plausible between the slips: issue 21) */
    if (bad) {
        s->lock_count = (s->lock_count < SMD_LOCK_UP * p->lock_samples)
                            ? s->lock_count + SMD_LOCK_UP * D_SUP_N(p) : s->lock_count;
    } else if (s->lock_count > 0) {
        s->lock_count = s->lock_count > D_SUP_N(p) ? s->lock_count - D_SUP_N(p) : 0;
    }
    /* a jump of the angle (check_jump): no rotor moves 45 deg in a sample,
     * so the estimate lost the rotor there, whatever came before (a drive
     * that ran on used an angle up to 180 deg off: issue 21) */
    if (s->jumped) {
        s->lock_count = SMD_LOCK_UP * p->lock_samples;
    }
    if (s->lock_count >= SMD_LOCK_UP * p->lock_samples) {
        s->fault |= (uint32_t)SMD_FAULT_LOST_LOCK;
    }
}

/* Supervision after a good sample (smd_drive.h): speed tracking, hunting,
 * the forced phase's length and its EMF, start-up chatter (latched into s->fault) and
 * current oscillation (s->warn). Every criterion reads signals a drive has:
 * its references, its estimates, its measured currents. */
static void supervise_criteria(const smd_drive_params *p, smd_drive_state *s)
{
    const smd_real i_lim = SMD_R(0.999) * p->i_max;
    /* speed tracking: away from the reference with the speed PI at its limit
     * for track_samples in all while away (a sample the PI leaves its limit
     * holds the count: the ADC's noise takes a PI at its limit off it for a
     * sample now and then, and a count reset by each had never reached
     * t_track on a 700 V motor 31 % below its reference, 94 % of its samples
     * at the limit); back within w_track, the count restarts */
    if (p->track_samples > 0 && D_SPEED_LOOP(p) && s->phase != SMD_PHASE_FORCED &&
        SMD_FABS(s->w_ref_r - s->w_k) > p->w_track) {
        if (SMD_FABS(s->i_dq_ref.im) >= i_lim &&
            (s->track_count += D_SUP_N(p)) >= p->track_samples) {
            s->fault |= (uint32_t)SMD_FAULT_SPEED_TRACKING;
        }
    } else {
        s->track_count = 0;
    }
    /* hunting: a leaky count of the speed PI's swings from one current
     * limit to the other (the forced phase has no speed PI) */
    if (p->hunt_max > 0) {
        if (D_SPEED_LOOP(p) && s->phase != SMD_PHASE_FORCED) {
            const int rail = s->i_dq_ref.im >= i_lim ? 1 : (s->i_dq_ref.im <= -i_lim ? -1 : 0);
            if (rail != 0) {
                if (rail == -s->hunt_rail) {
                    s->hunt += SMD_R(1.0);
                }
                s->hunt_rail = rail;
            }
        } else {
            s->hunt_rail = 0;
        }
        if (s->hunt > SMD_R(0.0)) { /* (most samples: none counted) */
            if (s->hunt > (smd_real)p->hunt_max) {
                s->fault |= (uint32_t)SMD_FAULT_HUNTING;
            }
            s->hunt -= p->hunt_decay;
            if (s->hunt < SMD_R(0.0)) {
                s->hunt = SMD_R(0.0);
            }
        }
    }
    if (s->phase == SMD_PHASE_FORCED) {
        /* the forced phase while the reference asks for the source */
        smd_real w_chk;
        if (SMD_FABS(s->w_f) >= p->w_handover) {
            /* at the handover speed and still forced: the source disagrees */
            if (p->forced_samples > 0 &&
                (s->forced_count += D_SUP_N(p)) >= p->forced_samples) {
                s->fault |= (uint32_t)SMD_FAULT_FORCED;
            }
        }
        /* start-up failed: the source's EMF against the forced speed, where
         * the EMF is large enough to estimate */
        w_chk = p->w_if_enter > SMD_R(0.0) ? p->w_if_enter : SMD_R(0.5) * p->w_handover;
        if (p->lock_samples > 0 && source_sensorless(D_POSITION(p)) && SMD_FABS(s->w_f) >= w_chk) {
            smd_real e = source_emf(p, s), e_exp = SMD_FABS(s->w_f) * p->psi_r_hat;
            if (e > p->lock_ratio * e_exp || e * p->lock_ratio < e_exp) {
                if ((s->start_count += D_SUP_N(p)) >= p->lock_samples) {
                    s->fault |= (uint32_t)SMD_FAULT_START;
                }
            } else {
                s->start_count = 0;
            }
        } else {
            s->start_count = 0;
        }
    } else {
        s->forced_count = 0;
        s->start_count = 0;
    }
    /* chatter: a leaky count of the supervisor's switches (nothing to do at
     * 0, most samples) */
    if (p->chatter_max > 0 && s->chatter > SMD_R(0.0)) {
        if (s->chatter > (smd_real)p->chatter_max) {
            s->fault |= (uint32_t)SMD_FAULT_CHATTER;
        }
        s->chatter -= p->chatter_decay;
        if (s->chatter < SMD_R(0.0)) {
            s->chatter = SMD_R(0.0);
        }
    }
}

/* The current's ripple (s->warn): the supervision's last piece. */
static void supervise_ripple(const smd_drive_params *p, smd_drive_state *s)
{
    /* oscillation: the filtered difference of the measured current from
     * one sample to the next in the frame turning at the drive's speed (the
     * last current turned by w_k T, e^{jx} to third order: a steady state
     * gives 0, white noise of sigma a phase about sigma) */
    s->warn = s->jumped ? (uint32_t)SMD_FAULT_ANGLE_JUMP : 0u;
    if (p->osc_samples > 0) {
        if (D_USE_RLS(p) && smd_rls_edge(&s->rls)) {
            /* (the tracker's square wave steps the current by 2 rls_i_inj: not
             * a ripple; at 21 samples a half it read as one on the 48 V servo;
             * the measure holds, and so does its warning) */
        } else if (s->osc_n >= 1) {
            const smd_real x = s->w_k * p->T_sp, x2 = x * x;
            const smd_cplx rot = smd_c(SMD_R(1.0) - SMD_R(0.5) * x2,
                                       x * (SMD_R(1.0) - x2 * SMD_R(0.16666667)));
            const smd_cplx d1 = smd_csub(s->i_s_ab, smd_cmul(s->i_prev1, rot));
            const smd_real lim = p->osc_i + p->osc_rel * smd_cabs(s->i_dq_ref);
            s->osc_ms += (d1.re * d1.re + d1.im * d1.im - s->osc_ms) * p->osc_k;
            /* ripple = sqrt(osc_ms) / 2 (the amplitude of a limit cycle at
             * half the sampling rate) beyond lim */
            if (s->osc_ms > SMD_R(4.0) * lim * lim) {
                if (s->osc_count < p->osc_samples) {
                    s->osc_count += D_SUP_N(p);
                }
            } else {
                s->osc_count = 0;
            }
        } else {
            s->osc_n++;
        }
        if (s->osc_count >= p->osc_samples) {
            s->warn |= (uint32_t)SMD_FAULT_OSCILLATION;
        }
    }
}

/* Supervision after a good sample, every piece (supervise_every <= 1), and
 * its pieces alone (supervise_piece): each out of line, the pieces inlined
 * in them (one call a sample either way) */
SMD_COLD static void supervise(const smd_drive_params *p, smd_drive_state *s)
{
    supervise_criteria(p, s);
    supervise_ripple(p, s);
}

SMD_COLD static void supervise_criteria_only(const smd_drive_params *p, smd_drive_state *s)
{
    supervise_criteria(p, s);
}

SMD_COLD static void supervise_ripple_only(const smd_drive_params *p, smd_drive_state *s)
{
    supervise_ripple(p, s);
}

/* An automatic restart (SMD_FAULT_RESTART): instead of latching a lost lock
 * or a failed start, the drive starts again on I/f from rest at its last
 * angle, the SMDO's disturbance estimate and speed estimate from zero. */
SMD_COLD static int try_restart(const smd_drive_params *p, smd_drive_state *s)
{
    const uint32_t lost = (uint32_t)(SMD_FAULT_LOST_LOCK | SMD_FAULT_START);
    smd_cplx zero = smd_c(SMD_R(0.0), SMD_R(0.0));
    if (p->restart_decay > SMD_R(0.0) && s->phase == SMD_PHASE_SOURCE) {
        /* (the count leaks while the drive runs on its source: restarts
         * from a forced phase that never hands over add up, and latch; leaking
         * always, a start failing once a second restarted for 28 s) */
        s->restarts -= p->restart_decay;
        if (s->restarts < SMD_R(0.0)) {
            s->restarts = SMD_R(0.0);
        }
    }
    if (!(s->fault & lost) || (s->fault & ~lost) || p->restart_max == 0 ||
        p->start != SMD_START_IF || !source_can_restart(p) ||
        s->restarts + SMD_R(1.0) > (smd_real)p->restart_max) {
        return 0;
    }
    s->warn |= s->fault & lost; /* the cause, reported with the restart */
    s->fault &= ~lost;
    s->restarts += SMD_R(1.0);
    switch_phase(s, SMD_PHASE_FORCED);
    s->dir_f = 0;
    s->start_dir = 0;
    s->theta_f = s->theta_k;
    s->w_f = SMD_R(0.0);
    s->theta = s->theta_k;
    s->w = SMD_R(0.0);
    s->w_ref_r = SMD_R(0.0);
    s->i_dq_ref = zero;
    s->lock_count = 0;
    s->start_count = 0;
    s->forced_count = 0;
    smd_pi_reset(&s->speed_pi, SMD_R(0.0));
    smd_smdo_reset(&s->smdo, s->i_s_ab, zero);
    source_restart(p, s);
    return 1;
}

/* The end of a supervised sample: an automatic restart, and the outputs'
 * fault word. (try_restart does nothing without a restart to count down or
 * a lost lock or failed start to restart from: most samples skip the call.)
 * The sample that latches reports this sample's warnings with it (an angle
 * jump that declared the lost lock: why). */
static smd_status end_supervised(const smd_drive_params *p, smd_drive_state *s,
                                 smd_drive_out *out, smd_status st)
{
    if ((s->restarts > SMD_R(0.0) || (s->fault & (uint32_t)(SMD_FAULT_LOST_LOCK |
                                                             SMD_FAULT_START))) &&
        try_restart(p, s)) {
        s->warn |= (uint32_t)SMD_FAULT_RESTART;
    }
    const uint32_t warn = s->warn | s->warn_rls;
    if (s->fault != 0u) {
        return apply_safe(p, s, out, warn);
    }
    out->fault = warn;
    return st;
}

/* The end of a good sample with the supervision spread (supervise_every >
 * 1): this sample's piece, sup_k: 0 the loss of lock, 1 the criteria, 2 the
 * state's finiteness (smd_drive_step), 3 the ripple, 4.. none (at sup_n = 2
 * or 3, piece i on sup_k = i mod sup_n). An angle jump checks the lock at once. The warnings of an event
 * (the jump, a restart and its cause) are this sample's; the oscillation's
 * holds until its piece runs again. */
static smd_status supervise_piece(const smd_drive_params *p, smd_drive_state *s,
                                  smd_drive_out *out, smd_status st)
{
    const int piece = s->sup_k;
    s->sup_k = piece + 1 >= D_SUP_N(p) ? 0 : piece + 1;
    if (piece == 0 || s->jumped) {
        check_lock(p, s);
    }
    if (piece == 1) {
        supervise_criteria_only(p, s);
    }
    if (piece == D_SUP_RIP(p)) {
        supervise_ripple_only(p, s);
    }
    s->warn &= (uint32_t)SMD_FAULT_OSCILLATION;
    if (s->jumped) {
        s->warn |= (uint32_t)SMD_FAULT_ANGLE_JUMP;
    }
    return end_supervised(p, s, out, st);
}

smd_status smd_drive_step(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in,
                          smd_drive_out *out)
{
    smd_real T, theta0, w0, i_q0, inv_u_dc;
    uint32_t now;
    const smd_drive_in *use = in;
    smd_drive_in held;
    smd_status st;
    int plain;
    if (p == 0 || s == 0 || in == 0 || out == 0) {
        if (out != 0) {
            out->d_abc[0] = out->d_abc[1] = out->d_abc[2] = SMD_R(0.5);
            out->fault = 0u;
            out->pwm_off = 0;
        }
        return SMD_ERR_NULL;
    }
    /* (first: the fast build's divide runs while the integer checks below
     * do, VDIV beside the integer pipeline) */
    inv_u_dc = smd_svm_inv_dc(in->u_dc);
#if defined(SMD_PROBE_CONTROL_ONLY)
    /* A measurement, never a firmware (benchmarks/profile_m4.py --probe):
     * the control law alone, without the input checks, the kept inputs, the
     * duties' check, the state's finiteness and the supervision (issue 22's
     * floor, docs/firmware.md) */
    (void)held, (void)now, (void)plain, (void)theta0, (void)w0, (void)i_q0, (void)use;
    out->fault = 0u;
    out->pwm_off = 0;
    return control(p, s, in, out, inv_u_dc);
#endif
    T = p->T_sp;
    theta0 = s->theta_k;
    w0 = s->w_k;
    i_q0 = s->i_dq_ref.im;
    plain = inputs_plain(p, s, in);
    now = plain ? 0u : check_inputs(p, s, in);
    out->fault = 0u;
    out->pwm_off = 0;
    if (now == 0u) {
        if (!plain) {
            protect(p, s, in);
        }
    } else if (s->have_last) {
        /* a bad sample: run on the last good inputs (the encoder moved on at
         * its speed), so that every block keeps its timeline, and apply the
         * safe state */
        hold_inputs(p, s, T, &held);
        use = &held;
        if (D_POSITION(p) == SMD_POS_LCL_SMO_PLL && p->smo.decimation >= 4) {
            s->pos.u.smo.defer = 1; /* (its spread refresh waits a sample) */
        }
    }
    if (s->fault != 0u || (now != 0u && !s->have_last)) {
        return hold_safe(p, s, out, now);
    }
    st = control(p, s, use, out, use == in ? inv_u_dc : smd_svm_inv_dc(use->u_dc));
    if (!duties_in_range(out->d_abc)) {
        st = SMD_ERR_NONFINITE; /* NaN duties (the dead-time compensation's clamp) */
    }
    /* (the state's finiteness: every sample, or its piece's with the
     * supervision spread, supervise_piece) */
    if (st == SMD_ERR_NONFINITE ||
        ((D_SUP_N(p) == 1 || s->sup_k == D_SUP_FIN(p)) && !state_finite(p, s))) {
        /* a computed value was not finite: restart every block from the last
         * good frame, one step on */
        if (!(isfinite(theta0) && isfinite(w0))) {
            theta0 = SMD_R(0.0);
            w0 = SMD_R(0.0);
        }
        recover(p, s, smd_wrap_pi(theta0 + w0 * T), w0,
                isfinite(i_q0) ? clampr(i_q0, p->i_max) : SMD_R(0.0));
        return apply_safe(p, s, out, now | (uint32_t)SMD_FAULT_INTERNAL);
    }
    keep_inputs(p, s, use);
    s->have_last = 1;
    if (now != 0u) {
        return apply_safe(p, s, out, now);
    }
    if (D_SUP_N(p) > 1) {
        return supervise_piece(p, s, out, st);
    }
    check_lock(p, s);
    supervise(p, s);
    return end_supervised(p, s, out, st);
}

void smd_drive_set_torque_in(smd_drive_state *s, int on)
{
    if (s != 0) {
        s->torque_in = on != 0;
    }
}

void smd_drive_clear_faults(smd_drive_state *s)
{
    s->fault &= ~(uint32_t)SMD_FAULT_LATCHED;
    s->lock_count = 0;
    s->track_count = 0;
    s->forced_count = 0;
    s->start_count = 0;
    s->chatter = SMD_R(0.0);
    s->hunt = SMD_R(0.0);
    s->hunt_rail = 0;
}

smd_drive_view smd_drive_get_view(const smd_drive_params *p, const smd_drive_state *s)
{
    smd_drive_view v;
    smd_cplx zero = smd_c(SMD_R(0.0), SMD_R(0.0));
    v.i_dq_ref = s->i_dq_ref;
    v.i_dq = D_CURRENT(p) == SMD_CC_PI ? s->i_dq : zero; /* DBPC has no Park transform */
    v.u_ab = s->u_ab_next;
    v.u_ab_ref = s->u_ab_ref;
    v.i_s_hat = D_USE_SMDO(p) ? s->smdo.i_s_hat : zero;
    v.u_d_hat = D_USE_SMDO(p) ? s->smdo.u_d_hat : zero;
    v.lambda = D_USE_SMDO(p) ? s->smdo.lambda : SMD_R(0.0);
    v.theta = s->theta_k;
    v.w = s->w_k;
    v.theta_err = s->pos.theta_err;
    v.e_hat = zero;
    v.s = zero;
    v.d_hat = zero;
    v.v = zero;
    v.e_lin = zero;
    source_view(p, s, &v);
    v.R_s_rls = D_USE_RLS(p) ? s->rls.R_hat : SMD_R(0.0);
    v.psi_rls = D_USE_RLS(p) ? s->rls.psi_hat : SMD_R(0.0);
    v.phase = s->phase;
    v.fault = s->fault;
    return v;
}

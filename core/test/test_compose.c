/*
 * The composition of the one drive (smd_drive.h): which parts fit together
 * and which values each part accepts, the synchronous-frame PI on an exact
 * plant, the start-up supervisor (I/f and encoder handover) and the view.
 *
 * Sources used here besides the encoder and the SMDO (yang2018 eq. (44)-(45)):
 * a linear observer (yao2022 eq. (64)-(65)) with an "identity" table, L = the
 * 2x2 unit block from i_2 to e and Theta = Ky = Ku = 0, so that its EMF
 * estimate is the motor-current input itself, x2 = [0, 0, i_2]: feeding
 * i_2 = j e^{j phi} makes it report the angle phi (e = j w psi e^{j theta}),
 * which lets a test set the angle the PLL source sees exactly.
 */
#include "drive_fixture.h"

/* -------------------------------------------------------------- helpers -- */

#define N_TAB 2

static void identity_linobs_table(smd_linobs_model tab[N_TAB])
{
    int n;
    memset(tab, 0, N_TAB * sizeof tab[0]);
    for (n = 0; n < N_TAB; n++) {
        tab[n].L[4 * 2 + 2] = R(1.0);
        tab[n].L[4 * 3 + 3] = R(1.0);
    }
}

/* The LCL drive (PI current control, lcl = 1) with the given source and
 * start; the tables are the caller's (any content: init reads only the
 * pointers and the grid). */
static smd_drive_config lcl_config(int position, int start, const smd_lcl_model *smo_tab,
                                   const smd_linobs_model *lin_tab)
{
    smd_drive_config c = drive_config(SMD_CC_PI, position, start);
    c.lcl = 1;
    c.L_dec = R(LS);
    c.R_v = R(2.0);
    c.smo.law = SMD_LCL_SMO_PROPOSED;
    c.smo.table = smo_tab;
    c.smo.n = N_TAB;
    c.smo.w_min = R(-1e4);
    c.smo.dw = R(2e4);
    c.smo.Q1 = R(0.5);
    c.smo.Q2 = R(0.5);
    c.smo.bw_rel2 = R(0.2);
    c.smo.bw_rel3 = R(0.2);
    c.smo.w_bp_min = R(100.0);
    c.lin.table = lin_tab;
    c.lin.n = N_TAB;
    c.lin.w_min = R(-1e4);
    c.lin.dw = R(2e4);
    return c;
}

static int init_status(const smd_drive_config *c)
{
    smd_drive_params p;
    return (int)smd_drive_init(&p, c);
}

/* -------------------------------------------------- what fits together -- */

/* Every composition the header allows initialises; each that does not fit
 * returns SMD_ERR_COMBINATION whatever its other values, before any of them
 * is looked at (check_parts runs first). */
static void test_combinations(void)
{
    static smd_lcl_model smo_tab[N_TAB];
    smd_linobs_model lin_tab[N_TAB];
    smd_drive_config c;
    int cur, pos, start;
    identity_linobs_table(lin_tab);
    memset(smo_tab, 0, sizeof smo_tab);

    /* no filter: every current control with the encoder and the SMDO source,
     * every start */
    for (cur = SMD_CC_PI; cur <= SMD_CC_ROBUST_DBPC; cur++) {
        for (pos = SMD_POS_ENCODER; pos <= SMD_POS_SMDO_EMF; pos++) {
            for (start = SMD_START_RUNNING; start <= SMD_START_IF; start++) {
                c = drive_config(cur, pos, start);
                CHECK_INT(init_status(&c), SMD_OK);
            }
        }
    }
    /* the filter: PI with the encoder and the two LCL sources, every start */
    for (pos = SMD_POS_ENCODER; pos <= SMD_POS_LCL_LINEAR; pos++) {
        for (start = SMD_START_RUNNING; start <= SMD_START_IF; start++) {
            c = lcl_config(pos, start, smo_tab, lin_tab);
            CHECK_INT(init_status(&c), pos == SMD_POS_SMDO_EMF ? SMD_ERR_COMBINATION : SMD_OK);
        }
    }

    /* an LCL source without the filter, with every current control */
    for (cur = SMD_CC_PI; cur <= SMD_CC_ROBUST_DBPC; cur++) {
        for (pos = SMD_POS_LCL_SMO_PLL; pos <= SMD_POS_LCL_LINEAR; pos++) {
            c = lcl_config(pos, SMD_START_RUNNING, smo_tab, lin_tab);
            c.lcl = 0;
            c.R_v = R(0.0);
            c.current = cur;
            CHECK_INT(init_status(&c), SMD_ERR_COMBINATION);
        }
    }
    /* the filter with deadbeat control (either), for every source */
    for (cur = SMD_CC_DBPC; cur <= SMD_CC_ROBUST_DBPC; cur++) {
        for (pos = SMD_POS_ENCODER; pos <= SMD_POS_LCL_LINEAR; pos++) {
            c = lcl_config(pos, SMD_START_RUNNING, smo_tab, lin_tab);
            c.current = cur;
            CHECK_INT(init_status(&c), SMD_ERR_COMBINATION);
        }
    }
    /* the filter with the SMDO's source (its model (15) has no filter) */
    c = lcl_config(SMD_POS_SMDO_EMF, SMD_START_RUNNING, smo_tab, lin_tab);
    c.R_v = R(0.0);
    CHECK_INT(init_status(&c), SMD_ERR_COMBINATION);
    c.start = SMD_START_HANDOVER;
    CHECK_INT(init_status(&c), SMD_ERR_COMBINATION);
    /* active damping without the filter, with every current control and
     * whatever the magnitude (the smallest float, a valid 2 V/A, beyond the
     * PI's range, +Inf) */
    {
        const smd_real r_v[4] = {R(1e-30), R(2.0), R(2e4), R(INFINITY)};
        int k;
        for (cur = SMD_CC_PI; cur <= SMD_CC_ROBUST_DBPC; cur++) {
            for (k = 0; k < 4; k++) {
                c = drive_config(cur, SMD_POS_ENCODER, SMD_START_RUNNING);
                c.R_v = r_v[k];
                CHECK_INT(init_status(&c), SMD_ERR_COMBINATION);
            }
        }
    }
    /* the combination is judged before the values: a wrong combination with
     * a zero sampling period is still a combination error */
    c = lcl_config(SMD_POS_LCL_LINEAR, SMD_START_RUNNING, smo_tab, lin_tab);
    c.lcl = 0;
    c.R_v = R(0.0);
    c.T_sp = R(0.0);
    CHECK_INT(init_status(&c), SMD_ERR_COMBINATION);
}

/* Unknown enumeration values; the current PI's, the start-up's and the LCL
 * sources' values, each rejected with its own status. */
static void test_values_rejected(void)
{
    static smd_lcl_model smo_tab[N_TAB];
    smd_linobs_model lin_tab[N_TAB];
    smd_drive_config c, c0;
    const smd_real nan = R(NAN);
    int k;
    identity_linobs_table(lin_tab);
    memset(smo_tab, 0, sizeof smo_tab);

    /* unknown part values: one below and one above each enumeration, and a
     * flag that is neither 0 nor 1 */
    c0 = drive_config(SMD_CC_PI, SMD_POS_ENCODER, SMD_START_RUNNING);
    c = c0; c.current = -1;                      CHECK_INT(init_status(&c), SMD_ERR_MODE);
    c = c0; c.current = SMD_CC_ROBUST_DBPC + 1;  CHECK_INT(init_status(&c), SMD_ERR_MODE);
    c = c0; c.position = -1;                     CHECK_INT(init_status(&c), SMD_ERR_MODE);
    c = c0; c.position = SMD_POS_LCL_LINEAR + 1; CHECK_INT(init_status(&c), SMD_ERR_MODE);
    c = c0; c.start = -1;                        CHECK_INT(init_status(&c), SMD_ERR_MODE);
    c = c0; c.start = SMD_START_IF + 1;          CHECK_INT(init_status(&c), SMD_ERR_MODE);
    c = c0; c.lcl = 2;                           CHECK_INT(init_status(&c), SMD_ERR_MODE);
    c = c0; c.lcl = -1;                          CHECK_INT(init_status(&c), SMD_ERR_MODE);
    c = c0; c.emf_ff = 2;                        CHECK_INT(init_status(&c), SMD_ERR_MODE);
    c = c0; c.svm_limit = 2;                     CHECK_INT(init_status(&c), SMD_ERR_MODE);

    /* the R_s / psi_r tracker: with the encoder and with the SMDO's angle it
     * initialises (smd_rls.h), behind the LCL filter (its model has none) it
     * is refused with any position source */
    c = drive_config(SMD_CC_ROBUST_DBPC, SMD_POS_ENCODER, SMD_START_RUNNING);
    c.rls_i_inj = R(1.0); c.rls_tau = R(0.3); c.rls_half = 200;
    CHECK_INT(init_status(&c), SMD_OK);
    c.position = SMD_POS_SMDO_EMF;               CHECK_INT(init_status(&c), SMD_OK);
    for (k = SMD_POS_ENCODER; k <= SMD_POS_LCL_LINEAR; k++) {
        if (k == SMD_POS_SMDO_EMF) {
            continue; /* (refused behind the filter on its own: SMD_ERR_MODE) */
        }
        c = lcl_config(k, SMD_START_RUNNING, smo_tab, lin_tab);
        CHECK_INT(init_status(&c), SMD_OK);
        c.rls_i_inj = R(1.0); c.rls_tau = R(0.3); c.rls_half = 200;
        CHECK_INT(init_status(&c), SMD_ERR_RLS);
    }

    /* current PI: k_p_i in [0, 1e4], k_i_i in [0, 1e9], L_dec in [0, 10],
     * R_v in [0, 1e4] (with the filter), each also NaN; the bounds pass */
    {
        const smd_real bad_kp[3] = {R(-1e-3), R(1.01e4), nan};
        const smd_real bad_ki[3] = {R(-1e-3), R(1.01e9), nan};
        const smd_real bad_ld[3] = {R(-1e-6), R(10.01), nan};
        const smd_real bad_rv[3] = {R(-1e-3), R(1.01e4), nan};
        for (k = 0; k < 3; k++) {
            c = c0; c.k_p_i = bad_kp[k];  CHECK_INT(init_status(&c), SMD_ERR_CURRENT_PI);
            c = c0; c.k_i_i = bad_ki[k];  CHECK_INT(init_status(&c), SMD_ERR_CURRENT_PI);
            c = c0; c.L_dec = bad_ld[k];  CHECK_INT(init_status(&c), SMD_ERR_CURRENT_PI);
            c = lcl_config(SMD_POS_ENCODER, SMD_START_RUNNING, smo_tab, lin_tab);
            c.R_v = bad_rv[k];
            CHECK_INT(init_status(&c), SMD_ERR_CURRENT_PI);
        }
        /* a negative or NaN R_v without the filter is no active damping
         * request, but still not a value the PI accepts */
        c = c0; c.R_v = R(-1.0);  CHECK_INT(init_status(&c), SMD_ERR_CURRENT_PI);
        c = c0; c.R_v = nan;      CHECK_INT(init_status(&c), SMD_ERR_CURRENT_PI);
        c = c0; c.dec_ref = 2;    CHECK_INT(init_status(&c), SMD_ERR_CURRENT_PI);
        c = c0; c.dec_ref = -1;   CHECK_INT(init_status(&c), SMD_ERR_CURRENT_PI);
        c = c0; c.dec_ref = 1;    CHECK_INT(init_status(&c), SMD_OK);
        c = c0; c.k_p_i = R(0.0); c.k_i_i = R(0.0); c.L_dec = R(0.0);
        CHECK_INT(init_status(&c), SMD_OK);
        c = c0; c.k_p_i = R(1e4); c.k_i_i = R(1e9); c.L_dec = R(10.0);
        CHECK_INT(init_status(&c), SMD_OK);
        c = lcl_config(SMD_POS_ENCODER, SMD_START_RUNNING, smo_tab, lin_tab);
        c.R_v = R(1e4);
        CHECK_INT(init_status(&c), SMD_OK);
        /* the PI's values are not read by deadbeat control */
        c = drive_config(SMD_CC_DBPC, SMD_POS_ENCODER, SMD_START_RUNNING);
        c.k_p_i = R(-1.0);
        c.L_dec = nan;
        CHECK_INT(init_status(&c), SMD_OK);
    }

    /* I/f: i_start in [0, 1e5] A, a_start in [0, 1e9] rad/s^2, w_handover
     * in [0, pi/T_sp] = [0, 31416] rad/s, each also NaN; read with the I/f
     * start only */
    {
        const smd_real bad_i[3] = {R(-0.1), R(1.01e5), nan};
        const smd_real bad_a[3] = {R(-0.1), R(1.01e9), nan};
        const smd_real bad_w[3] = {R(-0.1), R(31500.0), nan};
        for (k = 0; k < 3; k++) {
            c = drive_config(SMD_CC_ROBUST_DBPC, SMD_POS_SMDO_EMF, SMD_START_IF);
            c.i_start = bad_i[k];
            CHECK_INT(init_status(&c), SMD_ERR_START);
            c.start = SMD_START_HANDOVER;
            CHECK_INT(init_status(&c), SMD_OK);
            c = drive_config(SMD_CC_ROBUST_DBPC, SMD_POS_SMDO_EMF, SMD_START_IF);
            c.a_start = bad_a[k];
            CHECK_INT(init_status(&c), SMD_ERR_START);
            c = drive_config(SMD_CC_ROBUST_DBPC, SMD_POS_SMDO_EMF, SMD_START_IF);
            c.w_handover = bad_w[k];
            CHECK_INT(init_status(&c), SMD_ERR_START);
            c.start = SMD_START_RUNNING;
            CHECK_INT(init_status(&c), SMD_OK);
        }
        c = drive_config(SMD_CC_PI, SMD_POS_ENCODER, SMD_START_IF);
        c.w_handover = R(31400.0); /* just below pi / T_sp */
        CHECK_INT(init_status(&c), SMD_OK);
    }

    /* the LCL sources' tables: NULL -> SMD_ERR_NULL; fewer than 2 models or
     * a non-positive grid step -> SMD_ERR_TABLE; PLL gains with an unstable loop -> SMD_ERR_STABILITY */
    for (k = SMD_POS_LCL_SMO_PLL; k <= SMD_POS_LCL_LINEAR; k++) {
        const int smo = k == SMD_POS_LCL_SMO_PLL;
        c0 = lcl_config(k, SMD_START_RUNNING, smo_tab, lin_tab);
        CHECK_INT(init_status(&c0), SMD_OK);
        c = c0;
        if (smo) c.smo.table = 0; else c.lin.table = 0;
        CHECK_INT(init_status(&c), SMD_ERR_NULL);
        c = c0;
        if (smo) c.smo.n = 1; else c.lin.n = 1;
        CHECK_INT(init_status(&c), SMD_ERR_TABLE);
        c = c0;
        if (smo) c.smo.n = 0; else c.lin.n = 0;
        CHECK_INT(init_status(&c), SMD_ERR_TABLE);
        c = c0;
        if (smo) c.smo.dw = R(0.0); else c.lin.dw = R(0.0);
        CHECK_INT(init_status(&c), SMD_ERR_TABLE);
        /* the other source's table is not read */
        c = c0;
        if (smo) c.lin.table = 0; else c.smo.table = 0;
        CHECK_INT(init_status(&c), SMD_OK);
        c = c0;
        c.k_omega = R(1e6); /* max |root| > 1 at T_sp = 1e-4 s (test_pll.c) */
        CHECK_INT(init_status(&c), SMD_ERR_STABILITY);
    }
    /* the observer runs at the drive's period (there is no second T_sp to
     * disagree with it): an out-of-range T_sp is refused before it */
    c = lcl_config(SMD_POS_LCL_SMO_PLL, SMD_START_RUNNING, smo_tab, lin_tab);
    c.T_sp = R(2.0);
    CHECK_INT(init_status(&c), SMD_ERR_TS);
    /* the sliding-mode observer's own values (smd_lcl_smo_config): the law,
     * Q inside the unit circle (|Q| <= 0.999), band-pass widths in (0, 2];
     * the grid origin finite, for both observers */
    c0 = lcl_config(SMD_POS_LCL_SMO_PLL, SMD_START_RUNNING, smo_tab, lin_tab);
    c = c0; c.smo.law = SMD_LCL_SMO_TDE18 + 1;  CHECK_INT(init_status(&c), SMD_ERR_MODE);
    c = c0; c.smo.law = SMD_LCL_SMO_TDE18;      CHECK_INT(init_status(&c), SMD_OK);
    c = c0; c.smo.Q2 = R(-1.0);                 CHECK_INT(init_status(&c), SMD_ERR_STABILITY);
    c = c0; c.smo.Q1 = R(0.999);                CHECK_INT(init_status(&c), SMD_OK);
    c = c0; c.smo.bw_rel3 = R(0.0);             CHECK_INT(init_status(&c), SMD_ERR_LIMIT);
    c = c0; c.smo.w_min = nan;                  CHECK_INT(init_status(&c), SMD_ERR_TABLE);
    c = lcl_config(SMD_POS_LCL_LINEAR, SMD_START_RUNNING, smo_tab, lin_tab);
    c.lin.w_min = nan;
    CHECK_INT(init_status(&c), SMD_ERR_TABLE);
    /* tables and PLL are not read without an LCL source */
    c = lcl_config(SMD_POS_ENCODER, SMD_START_RUNNING, 0, 0);
    c.k_omega = R(1e6);
    CHECK_INT(init_status(&c), SMD_OK);
}

/* ------------------------------------------ PI on an exact RL plant ----- */

typedef struct pi_run {
    double e_plant;    /* max |i_dq - i_ref| over samples [400, 600), true current and frame, A */
    double e_ctrl;     /* the same in the controller's frame (view i_dq), A */
    double th_err;     /* max |angle used - true angle| over the same window, rad */
    double e_step;     /* |i_dq - i_ref| at the step sample, A */
    double complex x_i; /* the current PI's integrator at the end, V */
    int bad;           /* samples with a status other than SMD_OK or bad duties */
} pi_run;

/* PI with the given source, no filter, at constant speed w from a flying
 * start; i_dq_ref = 0 for 100 samples, then the step to idq; 600 samples. */
static pi_run run_pi(int position, double w, double complex idq, int emf_ff, double k_i)
{
    smd_drive_params p;
    smd_drive_state s;
    smd_drive_config c = drive_config(SMD_CC_PI, position, SMD_START_RUNNING);
    smd_drive_in in;
    smd_drive_out out;
    plant pl;
    pi_run r;
    double complex u = 0.0;
    int k;
    memset(&r, 0, sizeof r);
    c.emf_ff = emf_ff;
    c.k_i_i = R(k_i);
    if (smd_drive_init(&p, &c) != SMD_OK) {
        r.bad = -1;
        return r;
    }
    pl.i = 0.0;
    pl.th = 0.3;
    pl.w = w;
    smd_drive_reset(&p, &s, R(pl.th), R(w), R(0.0));
    for (k = 0; k < 600; k++) {
        double complex ref = k < 100 ? 0.0 : idq;
        double e = cabs(plant_idq(&pl) - ref);
        smd_drive_view v;
        fill_in(&in, &pl, ref);
        if (smd_drive_step(&p, &s, &in, &out) != SMD_OK || !duties_ok(out.d_abc)) {
            r.bad++;
        }
        v = smd_drive_get_view(&p, &s);
        if (k == 100) {
            r.e_step = e;
        }
        if (k >= 400) {
            double ec = cabs(smdt_z(v.i_dq) - ref);
            double et = fabs(smdt_wrap((double)v.theta - pl.th));
            r.e_plant = e > r.e_plant ? e : r.e_plant;
            r.e_ctrl = ec > r.e_ctrl ? ec : r.e_ctrl;
            r.th_err = et > r.th_err ? et : r.th_err;
        }
        plant_step(&pl, u);      /* [k, k+1) with the voltage decided at k-1 */
        u = realised(out.d_abc); /* applied during [k+1, k+2) */
    }
    r.x_i = smdt_z(s.x_i);
    return r;
}

/* Synchronous-frame PI (k_p = 46.9 V/A, k_i = 23450 V/(A s), drive_fixture.h)
 * with decoupling and EMF feed-forward, on the exact plant with the one-sample
 * delay, encoder at +-400 rad/s; step (0, 0) -> (-2, 5) A.
 *
 * Settling: the slowest closed-loop pole has |z| = 0.9378, so 300 samples
 * after the step the transient is down to 0.9378^300 = 4e-9 of the 5.4 A step
 * (a near-double pole adds a factor < 300): < 1e-5 A. What is left is float
 * resolution (integrator ulp / (k_i T) and duty ulp x u_dc / k_p, ~1e-6 A):
 * the bound 1e-3 A. The integrator is what removes the error: with k_i = 0
 * the loop is proportional with exact decoupling and EMF feed-forward, so in
 * steady state k_p e = R i, |e| = R |i_ref| / (k_p + R) = 0.2465 A; the
 * discrete loop differs from that by O((w T)^2) = 2e-3 relative (voltage
 * averaged over a rotating period, sinc(w T / 2)) and by the 1e-3 A decay
 * bound: allow 1 %. (The step saturates the voltage, k_p 5.4 A + 160 V
 * beyond the hexagon: without integral action nothing may remember it.)
 * The feed-forward: in steady state the PI's output u = x_i + j w L_dec i_ref
 * (+ j w psi_hat with the feed-forward) is what the plant needs, the same with
 * and without it, so x_i(off) - x_i(on) = j w psi_hat = +-160j V, up to
 * what the two residual errors e_on, e_off change in the law and in the
 * voltage the plant needs, (k_p + |R + j w L| + |w| L_dec) (e_on + e_off),
 * and the rounding of the 160 V integrator, 64 eps 160 V. A feed-forward of
 * the wrong sign would give -j w psi: 320 V off. */
static void test_pi_zero_steady_state_error(void)
{
    const double complex idq = -2.0 + 5.0 * JD;
    const double speeds[2] = {400.0, -400.0};
    int n;
    for (n = 0; n < 2; n++) {
        const double w = speeds[n];
        pi_run on = run_pi(SMD_POS_ENCODER, w, idq, 1, KI_I);
        pi_run off = run_pi(SMD_POS_ENCODER, w, idq, 0, KI_I);
        pi_run pp = run_pi(SMD_POS_ENCODER, w, idq, 1, 0.0);
        double e_p_ref = RS * cabs(idq) / ((double)R(KP_I) + RS);
        double complex dx = off.x_i - on.x_i;
        printf("    w = %6.1f: max |i_dq - i_ref| = %.2e A (ff), %.2e A (no ff), P only "
               "%.4f A (expected %.4f A); x_i(off) - x_i(on) = %.6f%+.6fj V\n", w, on.e_plant,
               off.e_plant, pp.e_plant, e_p_ref, creal(dx), cimag(dx));
        CHECK_INT(on.bad, 0);
        CHECK_INT(off.bad, 0);
        CHECK_INT(pp.bad, 0);
        CHECK(on.e_step > 5.0); /* the step happened: |(-2, 5)| = 5.39 A */
        CHECK_CLOSE(on.e_plant, 0.0, 1e-3);
        CHECK_CLOSE(off.e_plant, 0.0, 1e-3);
        CHECK_CLOSE(pp.e_plant, e_p_ref, 0.01 * e_p_ref);
        CHECK_CLOSE(cabs(dx - JD * w * (double)R(PSI)), 0.0,
                    (KP_I + cabs(RS + JD * w * LS) + fabs(w) * LS) * (on.e_plant + off.e_plant) +
                        64 * SMDT_EPS * fabs(w) * PSI);
    }
}

/* The same PI on the SMDO's position (eq. (44)-(45)), whose EMF estimate is
 * the SMDO's disturbance: u_d = -e (model (15): L di/dt = u + u_d - R i), so
 * the feed-forward is -u_d_hat. In the frame it uses the PI has no
 * steady-state error (1e-3 A as above, the estimated frame being steady at
 * constant speed); the true current differs from it by the angle error of
 * the estimate (a few mrad, test_drive.c), 5.4 A x 0.02 rad at most. With and
 * without the feed-forward x_i differs by the EMF j w psi as it appears in
 * the frames of the two runs (|w| psi (dtheta_on + dtheta_off)), by what the
 * errors change (as above), and by the part of u_d_hat that is not the EMF:
 * the Euler model (15) puts its mismatch with the exact plant into u_d,
 * u_d = -e + [L/T (e^{-aT} - 1) + R] i + [(1 - e^{-aT})/(aT) - 1] (u - e)
 *     ~ -e + (aT/2) (R i - (u - e)),  a = R/L, u - e = (R + j w L) i,
 * at most (aT/2) (R + |R + j w L|) |i_ref| = 0.31 V (0.10 V measured).
 * A feed-forward of +u_d_hat (the EMF with the wrong sign) is 320 V off. */
static void test_pi_smdo_feed_forward(void)
{
    const double complex idq = -2.0 + 5.0 * JD;
    const double speeds[2] = {400.0, -400.0};
    int n;
    for (n = 0; n < 2; n++) {
        const double w = speeds[n];
        pi_run on = run_pi(SMD_POS_SMDO_EMF, w, idq, 1, KI_I);
        pi_run off = run_pi(SMD_POS_SMDO_EMF, w, idq, 0, KI_I);
        double complex dx = off.x_i - on.x_i;
        printf("    w = %6.1f: controller frame max |i_dq - i_ref| = %.2e A (ff), %.2e A "
               "(no ff); angle error %.2e, %.2e rad; x_i(off) - x_i(on) = %.6f%+.6fj V\n", w,
               on.e_ctrl, off.e_ctrl, on.th_err, off.th_err, creal(dx), cimag(dx));
        CHECK_INT(on.bad, 0);
        CHECK_INT(off.bad, 0);
        CHECK_CLOSE(on.e_ctrl, 0.0, 1e-3);
        CHECK_CLOSE(off.e_ctrl, 0.0, 1e-3);
        CHECK_CLOSE(on.e_plant, 0.0, 1e-3 + cabs(idq) * 0.02);
        CHECK_CLOSE(on.th_err, 0.0, 0.02);
        CHECK_CLOSE(off.th_err, 0.0, 0.02);
        CHECK_CLOSE(cabs(dx - JD * w * (double)R(PSI)), 0.0,
                    fabs(w) * PSI * (on.th_err + off.th_err) +
                        (KP_I + cabs(RS + JD * w * LS) + fabs(w) * LS) * (on.e_ctrl + off.e_ctrl) +
                        0.5 * RS / LS * TSP * (RS + cabs(RS + JD * w * LS)) * cabs(idq) +
                        64 * SMDT_EPS * fabs(w) * PSI);
    }
}

/* ---------------------------------------------------- start-up: I/f ----- */

#define IF_W0 50.0     /* rad/s, forced speed at reset */
#define IF_TH0 2.9     /* rad: the forced angle crosses +pi within ~3 ms */
#define IF_WREF 250.0  /* speed reference after the handover, rad/s */
#define IF_DELTA 0.1   /* the identity source's angle is the forced one + 0.1 rad */

/* I/f (current i_start = 8 A on a forced angle accelerated at a_start =
 * 2e4 rad/s^2 from w0 = 50 rad/s, handover at w_handover = 201 rad/s; speed
 * loop on, k_p_w = 0.05, k_i_w = 2, w_ref = 250 rad/s), with the encoder as
 * source and with a PLL source (identity linear observer reporting the forced
 * angle + 0.1 rad).
 *
 * - The forced angle and speed follow the double recurrence
 *   w_f(k+1) = w_f(k) + a T, theta_f(k+1) = wrap(theta_f(k) + w_f(k+1) T) on
 *   the drive's own (float) T and a: each float step rounds w_f by at most
 *   half an ulp, eps/2 (w_f + a T), and theta_f by eps/2 |theta| plus the
 *   w_f T product, so after k+1 steps |dw| <= (k+1) eps (w_max + a T) and
 *   |dtheta| <= (k+1) (2 pi + T (k+1)(w_max + a T)) eps (twice the bound).
 * - Handover: w_f(k+1) = 50 + 2 (k+1) >= 201 first at k + 1 = 76, sample
 *   k_h = 75 (1 rad/s from the threshold: rounding cannot move it). The view
 *   reports the supervisor's phase after the step (the phase of the next
 *   sample): 0 for k < 75, 2 from k = 75 on. The frame of sample k (view
 *   theta, w) is the forced one up to and including k_h, then the source's.
 * - Current reference (0, i_start) exactly while forced (whatever the input
 *   asks); at k_h the speed PI starts from its integrator reset to the forced
 *   current seen in the source's frame, i0 = i_start cos(d) (d the source's
 *   angle from the forced one): i_q = i0 + (k_p_w + k_i_w T) e, x_i = i0 + k_i_w T e with
 *   e = w_ref - w_f(k_h); i_d from the input again. O(10) values after 3
 *   roundings: 64 eps x 10.
 * - PLL source: at the handover the PLL restarts on the observer's angle,
 *   forced angle + angle error + w T: the frame at k_h + 1 is
 *   wrap(theta_f(k_h) + 0.1 + w_f(k_h) T), at the PLL's speed w_f(k_h); the
 *   identity source's angle costs a few roundings of the currents and of
 *   atan2 (~8 eps), the sum 3 more: 64 eps pi. */
static void run_if_start(int position)
{
    static smd_lcl_model smo_tab[N_TAB];
    smd_linobs_model lin_tab[N_TAB];
    smd_drive_params p;
    smd_drive_state s;
    smd_drive_config c;
    smd_drive_in in;
    smd_drive_out out;
    smd_drive_view v, v_h;
    const int k_h_hand = 75;
    const int lcl_src = position == SMD_POS_LCL_LINEAR;
    double T, aT, w_d, th_d, w_max = 201.0 + 2.0;
    int k, k_h = -1, k_h_d = -1, n_forced_ref = 0, n_frame = 0;
    identity_linobs_table(lin_tab);
    memset(smo_tab, 0, sizeof smo_tab);
    memset(&v_h, 0, sizeof v_h);
    if (lcl_src) {
        c = lcl_config(position, SMD_START_IF, smo_tab, lin_tab);
    } else {
        c = drive_config(SMD_CC_PI, position, SMD_START_IF);
    }
    c.speed_loop = 1;
    CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
    T = (double)p.T_sp;
    aT = (double)p.a_start * T;
    smd_drive_reset(&p, &s, R(IF_TH0), R(IF_W0), R(0.0));
    CHECK_INT(s.phase, SMD_PHASE_FORCED);
    w_d = IF_W0;
    th_d = smdt_wrap(IF_TH0);
    for (k = 0; k < 120; k++) {
        const int forced_before = s.phase == SMD_PHASE_FORCED;
        double tol_w, tol_th;
        memset(&in, 0, sizeof in);
        in.u_dc = R(UDC);
        in.w_ref = R(IF_WREF);
        in.i_dq_ref = smd_c(R(-0.5), R(3.0)); /* ignored while forced (i_q always) */
        in.theta_enc = R(smdt_wrap(-1.0 + 150.0 * T * k)); /* an encoder unlike theta_f */
        in.w_enc = R(150.0);
        {
            /* identity source: i_2 = j e^{j(theta_f + 0.1)} on the drive's
             * frame of this sample (the one predicted at k-1) */
            double phi = (double)s.theta + IF_DELTA;
            phase_ab(JD * cexp(JD * phi), &in.i_a, &in.i_b);
            in.i1_a = in.i_a;
            in.i1_b = in.i_b;
        }
        CHECK_INT(smd_drive_step(&p, &s, &in, &out), SMD_OK);
        v = smd_drive_get_view(&p, &s);
        /* the double recurrence: (th_d, w_d) = (theta_f, w_f)(k) here */
        tol_w = (k + 1) * SMDT_EPS * (w_max + aT);
        tol_th = (k + 1) * (2.0 * PI_D + T * (k + 1) * (w_max + aT)) * SMDT_EPS;
        if (forced_before) {
            n_frame += fabs(smdt_wrap((double)v.theta - th_d)) <= tol_th &&
                       fabs((double)v.w - w_d) <= tol_w;
            n_forced_ref += v.i_dq_ref.re == R(0.0) && v.i_dq_ref.im == p.i_start;
        }
        w_d += aT;
        th_d = smdt_wrap(th_d + w_d * T);
        if (forced_before) {
            /* theta_f(k+1), w_f(k+1) as the drive holds them after step k */
            CHECK_CLOSE(smdt_wrap((double)s.theta_f - th_d), 0.0,
                        tol_th + (2.0 * PI_D + T * w_max) * SMDT_EPS);
            CHECK_CLOSE((double)s.w_f, w_d, tol_w + SMDT_EPS * (w_max + aT));
            if (w_d >= (double)p.w_handover && k_h_d < 0) {
                k_h_d = k;
            }
        }
        if (forced_before && v.phase == SMD_PHASE_SOURCE) {
            k_h = k;
            v_h = v;
            /* the speed PI starts from the forced current's q component
             * in the source's frame, i_start cos(d), d the source's angle
             * from the forced one (issue 18: the torque that was flowing) */
            {
                double e = IF_WREF - (double)v.w;
                double d = lcl_src ? -(double)s.pos.theta_err
                           : position == SMD_POS_SMDO_EMF
                               ? smdt_wrap((double)v.theta - (double)s.pos.u.emf.theta_r_hat)
                               : 0.0;
                double i0 = (double)p.i_start * cos(d);
                double i_q = i0 + (0.05 + 2.0 * T) * e;
                CHECK_CLOSE(v.i_dq_ref.im, i_q, 64 * SMDT_EPS * 10.0);
                CHECK_CLOSE(s.speed_pi.x_i, i0 + 2.0 * T * e, 64 * SMDT_EPS * 10.0);
                CHECK(fabs(e) > 40.0); /* so that the PI's terms are visible */
                CHECK_CLOSE(v.i_dq_ref.re, -0.5, 0.0);
            }
        }
        CHECK_INT(v.phase, k < k_h_hand ? SMD_PHASE_FORCED : SMD_PHASE_SOURCE);
        if (k == k_h_hand + 1) {
            if (lcl_src) {
                /* the PLL restarted on the observer's angle */
                double th_pll = smdt_wrap((double)v_h.theta + IF_DELTA + (double)v_h.w * T);
                CHECK_CLOSE(smdt_wrap((double)v.theta - th_pll), 0.0, 64 * SMDT_EPS * PI_D);
                CHECK_CLOSE(v.w, v_h.w, 0.0);
                CHECK_CLOSE(v_h.theta_err, IF_DELTA, 64 * SMDT_EPS * PI_D);
            } else {
                CHECK_CLOSE(v.theta, in.theta_enc, 0.0);
                CHECK_CLOSE(v.w, in.w_enc, 0.0);
            }
        }
        if (k > k_h_hand && !lcl_src) {
            n_frame += v.theta == in.theta_enc && v.w == in.w_enc;
        }
    }
    printf("    source %d: handover at sample %d (double recurrence: %d)\n", position, k_h,
           k_h_d);
    CHECK_INT(k_h_d, k_h_hand);
    CHECK_INT(k_h, k_h_hand);
    CHECK_INT(n_forced_ref, k_h_hand); /* samples 0..74 */
    /* forced frame at 0..75, then (encoder) the encoder's at 76..119 */
    CHECK_INT(n_frame, lcl_src ? k_h_hand + 1 : 120);
}

static void test_if_start(void)
{
    run_if_start(SMD_POS_ENCODER);
    run_if_start(SMD_POS_LCL_LINEAR);
}

/* ------------------------------------------ start-up: encoder handover -- */

/* yang2018 sensorless (robust DBPC + SMDO source) with `handover` = 50 in
 * closed loop on the exact plant at 300 rad/s; the encoder reads the true
 * angle + 0.25 rad, so that its frame and the SMDO's (within a few mrad of
 * the truth, test_drive.c) are told apart. The frame of sample k (view theta,
 * w) is the encoder's, bit for bit, for exactly k = 0..49 while the phase the
 * sample ran in is 1; from k = 50 on it is the SMDO source's own estimate, bit
 * for bit, phase 2, at least 0.2 rad from the encoder's. The view after step k
 * shows the phase of sample k + 1: 1 up to k = 48, 2 from k = 49 on. */
static void test_handover_smdo(void)
{
    const int handover = 50;
    smd_drive_params p;
    smd_drive_state s;
    smd_drive_config c = mode_config(MODE_SENSORLESS);
    smd_drive_in in;
    smd_drive_out out;
    plant pl;
    double complex u = 0.0;
    int k, n_enc = 0, n_src = 0, n_apart = 0;
    c.handover = handover;
    CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
    start_at(&p, &s, &pl, 300.0);
    CHECK_INT(s.phase, SMD_PHASE_ENCODER);
    for (k = 0; k < 300; k++) {
        const int phase_k = s.phase;
        smd_drive_view v;
        fill_in(&in, &pl, 5.0 * JD);
        in.theta_enc = R(smdt_wrap(pl.th + 0.25));
        CHECK_INT(smd_drive_step(&p, &s, &in, &out), SMD_OK);
        v = smd_drive_get_view(&p, &s);
        CHECK_INT(phase_k, k < handover ? SMD_PHASE_ENCODER : SMD_PHASE_SOURCE);
        CHECK_INT(v.phase, k + 1 < handover ? SMD_PHASE_ENCODER : SMD_PHASE_SOURCE);
        if (k < handover) {
            n_enc += v.theta == in.theta_enc && v.w == in.w_enc;
        } else {
            n_src += v.theta == s.pos.u.emf.theta_r_hat && v.w == s.pos.u.emf.w_r_hat;
            n_apart += fabs(smdt_wrap((double)v.theta - (double)in.theta_enc)) > 0.2;
        }
        plant_step(&pl, u);
        u = realised(out.d_abc);
    }
    CHECK_INT(n_enc, handover);
    CHECK_INT(n_src, 300 - handover);
    CHECK_INT(n_apart, 300 - handover);
}

/* The LCL drive with a PLL source (identity linear observer reporting the
 * encoder angle + 0.3 rad) and `handover` = 20: the frame is the encoder's,
 * bit for bit, at k = 0..19; at k = 20 the PLL, restarted at the handover on
 * the encoder's prediction wrap(theta_enc(19) + w_enc T) at w_enc, gives the
 * frame; at k = 21 the frame is the PLL's step from there, eq. (48):
 * theta(20) + w(20) T + k_theta e(20), speed w(20) + k_omega e(20), with the
 * angle error e(20) ~ 0.3 rad as the view reports it (theta_err): 0.03 rad
 * ahead of the encoder. Tolerance: a few roundings of O(pi) values, 16 eps pi
 * (16 eps w for the speed). */
static void test_handover_pll(void)
{
    static smd_lcl_model smo_tab[N_TAB];
    smd_linobs_model lin_tab[N_TAB];
    const int handover = 20;
    const double w_enc = 300.0;
    smd_drive_params p;
    smd_drive_state s;
    smd_drive_config c;
    smd_drive_in in;
    smd_drive_out out;
    smd_drive_view v, v_prev;
    double T, th_enc_prev = 0.0;
    int k, n_enc = 0;
    identity_linobs_table(lin_tab);
    memset(smo_tab, 0, sizeof smo_tab);
    memset(&v_prev, 0, sizeof v_prev);
    c = lcl_config(SMD_POS_LCL_LINEAR, SMD_START_HANDOVER, smo_tab, lin_tab);
    c.handover = handover;
    CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
    T = (double)p.T_sp;
    smd_drive_reset(&p, &s, R(0.5), R(w_enc), R(0.0));
    for (k = 0; k < 40; k++) {
        const int phase_k = s.phase;
        double th_enc = smdt_wrap(0.5 + w_enc * T * k);
        memset(&in, 0, sizeof in);
        in.u_dc = R(UDC);
        in.theta_enc = R(th_enc);
        in.w_enc = R(w_enc);
        phase_ab(JD * cexp(JD * (th_enc + 0.3)), &in.i_a, &in.i_b);
        in.i1_a = in.i_a;
        in.i1_b = in.i_b;
        CHECK_INT(smd_drive_step(&p, &s, &in, &out), SMD_OK);
        v = smd_drive_get_view(&p, &s);
        CHECK_INT(phase_k, k < handover ? SMD_PHASE_ENCODER : SMD_PHASE_SOURCE);
        if (k < handover) {
            n_enc += v.theta == in.theta_enc && v.w == in.w_enc;
        } else if (k == handover) {
            double th = smdt_wrap((double)R(th_enc_prev) + (double)R(w_enc) * T);
            CHECK_CLOSE(smdt_wrap((double)v.theta - th), 0.0, 16 * SMDT_EPS * PI_D);
            CHECK_CLOSE(v.w, w_enc, 0.0);
            /* the source's angle is the encoder's + 0.3 */
            CHECK_CLOSE(v.theta_err, smdt_wrap(th_enc + 0.3 - (double)v.theta),
                        16 * SMDT_EPS * PI_D);
        } else if (k == handover + 1) {
            double th = smdt_wrap((double)v_prev.theta + (double)v_prev.w * T +
                                  (double)p.pll.k_theta * (double)v_prev.theta_err);
            CHECK_CLOSE(smdt_wrap((double)v.theta - th), 0.0, 16 * SMDT_EPS * PI_D);
            CHECK_CLOSE(v.w, (double)v_prev.w + (double)p.pll.k_omega * (double)v_prev.theta_err,
                        16 * SMDT_EPS * w_enc);
            CHECK(fabs((double)v.theta - (double)in.theta_enc) > 0.02); /* not the encoder */
        }
        th_enc_prev = th_enc;
        v_prev = v;
    }
    CHECK_INT(n_enc, handover);
}

/* Non-finite samples around the PLL source (identity linear observer): the
 * PLL keeps whatever angle it starts from (its step ignores a non-finite
 * error, not a non-finite state), and the linear observer resets itself on
 * non-finite data (its estimate then zero, whose "angle" atan2(0, 0) = 0
 * would give the error -theta_o: a kick of up to pi).
 * - Encoder handover (20 samples), theta_enc or w_enc NaN or Inf at sample
 *   19: that sample reports SMD_ERR_FAULT with SMD_FAULT_INPUT and runs on
 *   the last good inputs one sample on (the encoder angle advanced at its
 *   speed: here exactly the true one), so the handover comes on schedule
 *   (from sample 20 the PLL's frame); every later sample is SMD_OK, and 20
 *   samples after the handover the PLL is on the source (the encoder angle
 *   itself here): the PLL error shrinks at least as 0.9^k (k_theta = 0.1)
 *   from at most one sample of rotation, 0.03 rad: 0.9^20 x 0.03 = 4e-3,
 *   bound 5e-3.
 * - Then, on the source, the motor current NaN at sample 40: SMD_ERR_FAULT
 *   there; the held currents turned at the frame's speed are the true ones
 *   (a steady rotating current), so the angle error stays that of a good
 *   sample (|theta_err| < 1e-3 rad) and the frame of sample 41 is the PLL's
 *   wrap(theta(40) + w(40) T) within the PLL's correction k_theta x 1e-3;
 *   SMD_OK after.
 * - I/f, the motor current NaN at the handover sample 75: SMD_ERR_FAULT;
 *   the held current turned at the forced speed is the true one, so the
 *   angle error is the offset a good sample shows (IF_DELTA, 1e-3) and the
 *   PLL restarts on the observer's angle, wrap(theta_f + theta_err + w_f T)
 *   (1e-3), as in test_if_start; every later sample is SMD_OK with a finite
 *   frame. */
static void test_pll_source_nonfinite_sample(void)
{
    static smd_lcl_model smo_tab[N_TAB];
    smd_linobs_model lin_tab[N_TAB];
    const int handover = 20;
    const double w_enc = 300.0;
    int field;
    identity_linobs_table(lin_tab);
    memset(smo_tab, 0, sizeof smo_tab);
    for (field = 0; field < 4; field++) {
        smd_drive_params p;
        smd_drive_state s;
        smd_drive_config c = lcl_config(SMD_POS_LCL_LINEAR, SMD_START_HANDOVER, smo_tab, lin_tab);
        smd_drive_in in;
        smd_drive_out out;
        smd_drive_view v, v_prev;
        const smd_real bad = field < 2 ? R(NAN) : R(INFINITY);
        double T;
        int k, n_ok = 0, n_enc = 0;
        c.handover = handover;
        CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
        T = (double)p.T_sp;
        smd_drive_reset(&p, &s, R(0.5), R(w_enc), R(0.0));
        memset(&v_prev, 0, sizeof v_prev);
        for (k = 0; k < 60; k++) {
            const int phase_k = s.phase;
            double th_enc = smdt_wrap(0.5 + w_enc * T * k);
            smd_status st;
            memset(&in, 0, sizeof in);
            in.u_dc = R(UDC);
            in.theta_enc = R(th_enc);
            in.w_enc = R(w_enc);
            phase_ab(JD * cexp(JD * th_enc), &in.i_a, &in.i_b);
            if (k == handover - 1) {
                if (field % 2 == 0) {
                    in.theta_enc = bad;
                } else {
                    in.w_enc = bad;
                }
            }
            if (k == 40) {
                in.i_a = bad;
            }
            in.i1_a = in.i_a;
            in.i1_b = in.i_b;
            st = smd_drive_step(&p, &s, &in, &out);
            v = smd_drive_get_view(&p, &s);
            if (k == handover - 1 || k == 40) {
                CHECK_INT(st, SMD_ERR_FAULT);
                CHECK_INT(out.fault, SMD_FAULT_INPUT);
                CHECK(duties_ok(out.d_abc));
            } else {
                n_ok += st == SMD_OK && isfinite(v.theta) && isfinite(v.w) && duties_ok(out.d_abc);
            }
            if (k == handover - 1) {
                CHECK_INT(v.phase, SMD_PHASE_SOURCE);
                n_enc += fabs(smdt_wrap((double)v.theta - th_enc)) < 8 * SMDT_EPS * PI_D;
            }
            CHECK_INT(phase_k, k <= handover - 1 ? SMD_PHASE_ENCODER : SMD_PHASE_SOURCE);
            if (k == handover + 20) {
                CHECK_CLOSE(smdt_wrap((double)v.theta - th_enc), 0.0, 5e-3);
            }
            if (k == 40) {
                CHECK_CLOSE(v.theta_err, 0.0, 1e-3);
            }
            if (k == 41) {
                double th = smdt_wrap((double)v_prev.theta + (double)v_prev.w * T);
                CHECK_CLOSE(smdt_wrap((double)v.theta - th), 0.0, 0.1 * 1e-3 + 16 * SMDT_EPS * PI_D);
            }
            v_prev = v;
        }
        CHECK_INT(n_ok, 58);
        CHECK_INT(n_enc, 1);
    }
    {
        smd_drive_params p;
        smd_drive_state s;
        smd_drive_config c = lcl_config(SMD_POS_LCL_LINEAR, SMD_START_IF, smo_tab, lin_tab);
        smd_drive_in in;
        smd_drive_out out;
        smd_drive_view v, v_h;
        double T;
        int k, n_ok = 0;
        c.speed_loop = 1;
        CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
        T = (double)p.T_sp;
        smd_drive_reset(&p, &s, R(IF_TH0), R(IF_W0), R(0.0));
        memset(&v_h, 0, sizeof v_h);
        for (k = 0; k < 120; k++) {
            smd_status st;
            memset(&in, 0, sizeof in);
            in.u_dc = R(UDC);
            in.w_ref = R(IF_WREF);
            phase_ab(JD * cexp(JD * ((double)s.theta + IF_DELTA)), &in.i_a, &in.i_b);
            if (k == 75) {
                in.i_a = R(NAN);
            }
            in.i1_a = in.i_a;
            in.i1_b = in.i_b;
            st = smd_drive_step(&p, &s, &in, &out);
            v = smd_drive_get_view(&p, &s);
            if (k == 75) {
                CHECK_INT(st, SMD_ERR_FAULT);
                CHECK_INT(out.fault, SMD_FAULT_INPUT);
                CHECK(duties_ok(out.d_abc));
                /* the held current turned at the forced speed is the true one:
                 * the observer measures the angle offset as from a good sample */
                CHECK_CLOSE(v.theta_err, IF_DELTA, 1e-3); /* 0.0998 from a good sample too */
                v_h = v;
            } else {
                n_ok += st == SMD_OK && isfinite(v.theta) && isfinite(v.w) && duties_ok(out.d_abc);
            }
            if (k == 76) {
                /* the PLL restarted on the observer's angle, forced + error */
                double th = smdt_wrap((double)v_h.theta + (double)v_h.theta_err + (double)v_h.w * T);
                CHECK_CLOSE(smdt_wrap((double)v.theta - th), 0.0, 1e-3);
            }
            CHECK_INT(v.phase, k < 75 ? SMD_PHASE_FORCED : SMD_PHASE_SOURCE);
        }
        CHECK_INT(n_ok, 119);
        CHECK(isfinite(s.pos.pll.theta) && isfinite(s.pos.pll.w) && isfinite(s.pos.pll.a));
    }
}

/* ------------------------------------------------------------ the view -- */

static int cplx_zero(smd_cplx z) { return z.re == R(0.0) && z.im == R(0.0); }

/* Run a drive 200 samples on the exact plant (300 rad/s, 5 A on q, from a
 * flying start, which sets the SMDO's state to the back EMF even where it
 * does not run) and return its view; *smdo_state_nonzero: the raw SMDO state
 * holds a non-zero disturbance (what the view must not show without SMDO). */
static smd_drive_view run_view(const smd_drive_config *c, int *ok, int *smdo_state_nonzero,
                               smd_drive_state *s)
{
    smd_drive_params p;
    smd_drive_in in;
    smd_drive_out out;
    plant pl;
    double complex u = 0.0;
    int k;
    *ok = smd_drive_init(&p, c) == SMD_OK;
    start_at(&p, s, &pl, 300.0);
    for (k = 0; k < 200 && *ok; k++) {
        fill_in(&in, &pl, 5.0 * JD);
        in.i1_a = in.i_a; /* the drives with a filter see i_1 = i_2 */
        in.i1_b = in.i_b;
        *ok = smd_drive_step(&p, s, &in, &out) == SMD_OK;
        plant_step(&pl, u);
        u = realised(out.d_abc);
    }
    *smdo_state_nonzero = !cplx_zero(s->smdo.u_d_hat);
    return smd_drive_get_view(&p, s);
}

/* The view reports zeros for the SMDO fields (i_s_hat, u_d_hat, lambda)
 * when no SMDO runs, although the state holds the flying start's EMF; with
 * the SMDO they are its state, non-zero. The LCL fields (theta_err, e_hat, s,
 * d_hat, v, e_lin) are zero without an LCL source, also on the drive with the
 * filter on the encoder; with the linear source e_lin is its EMF estimate
 * (the identity table: the motor current, ~5 A) and the SMO's fields stay
 * zero. */
static void test_view_fields(void)
{
    static smd_lcl_model smo_tab[N_TAB];
    smd_linobs_model lin_tab[N_TAB];
    smd_drive_config cfgs[7];
    const int has_smdo[7] = {0, 1, 1, 0, 1, 0, 0};
    int n;
    identity_linobs_table(lin_tab);
    memset(smo_tab, 0, sizeof smo_tab);
    cfgs[0] = mode_config(MODE_CONVENTIONAL);
    cfgs[1] = mode_config(MODE_ROBUST);
    cfgs[2] = mode_config(MODE_SENSORLESS);
    cfgs[3] = mode_config(MODE_PI);
    cfgs[4] = drive_config(SMD_CC_PI, SMD_POS_SMDO_EMF, SMD_START_RUNNING);
    cfgs[5] = lcl_config(SMD_POS_ENCODER, SMD_START_RUNNING, smo_tab, lin_tab);
    cfgs[6] = lcl_config(SMD_POS_LCL_LINEAR, SMD_START_RUNNING, smo_tab, lin_tab);
    for (n = 0; n < 7; n++) {
        smd_drive_state s;
        int ok, nz;
        smd_drive_view v = run_view(&cfgs[n], &ok, &nz, &s);
        CHECK(ok);
        CHECK(nz); /* the raw state is not zero: the view's zeros are its own */
        if (has_smdo[n]) {
            CHECK(smd_cabs(v.u_d_hat) > R(50.0)); /* |w psi| = 120 V */
            CHECK(smd_cabs(v.i_s_hat) > R(1.0));
            CHECK(v.lambda > R(0.0));
            CHECK(v.u_d_hat.re == s.smdo.u_d_hat.re && v.u_d_hat.im == s.smdo.u_d_hat.im);
        } else {
            CHECK(cplx_zero(v.u_d_hat) && cplx_zero(v.i_s_hat) && v.lambda == R(0.0));
        }
        CHECK(cplx_zero(v.e_hat) && cplx_zero(v.s) && cplx_zero(v.d_hat) && cplx_zero(v.v));
        if (cfgs[n].position == SMD_POS_LCL_LINEAR) {
            CHECK(smd_cabs(v.e_lin) > R(1.0));
            CHECK(v.e_lin.re == s.pos.u.lin.x2[2] && v.e_lin.im == s.pos.u.lin.x2[3]);
        } else {
            CHECK(cplx_zero(v.e_lin) && v.theta_err == R(0.0));
        }
        CHECK_INT(v.phase, SMD_PHASE_SOURCE);
    }
}

/* smd_lcl_smo_prime (issue 22): a decimated observer primed at reset at w
 * and stepped once at w is the unprimed observer after its first step, bit
 * for bit (that step refreshed everything at w: the prime moves that work
 * out of the step, not changes it); and its first step is a piece: the
 * model's first part, no band-pass coefficient or tap (checked: the primed
 * state's coefficients before the step are the ones after it). The table's
 * models differ from grid point to grid point, so an interpolation at
 * another speed would show. */
static void test_lcl_smo_prime(void)
{
    static smd_lcl_model tab[N_TAB];
    smd_lcl_smo_config c;
    smd_lcl_smo_params p;
    smd_lcl_smo_state a, b;
    smd_bandpass bp2;
    smd_lcl_smo_taps taps3;
    const smd_real w = R(5000.0), th = R(0.3);
    const smd_cplx i1 = smd_c(R(1.0), R(-2.0)), i2 = smd_c(R(0.9), R(-2.1)),
                   u = smd_c(R(30.0), R(12.0));
    int k, j;
    for (k = 0; k < N_TAB; k++) {
        smd_real *m = (smd_real *)&tab[k];
        for (j = 0; j < (int)(sizeof(smd_lcl_model) / sizeof(smd_real)); j++) {
            m[j] = R(1e-3) * (smd_real)((j * 7 + k * 3) % 11) - R(5e-3);
        }
    }
    memset(&c, 0, sizeof c);
    c.law = SMD_LCL_SMO_PROPOSED;
    c.table = tab;
    c.n = N_TAB;
    c.w_min = R(-1e4);
    c.dw = R(2e4);
    c.Q1 = c.Q2 = R(0.5);
    c.bw_rel2 = c.bw_rel3 = R(0.2);
    c.w_bp_min = R(100.0);
    c.decimation = 8;
    CHECK_INT(smd_lcl_smo_init(&p, R(5e-5), &c), SMD_OK);
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    smd_lcl_smo_reset(&a, th);
    smd_lcl_smo_reset(&b, th);
    smd_lcl_smo_prime(&p, &a, w);
    CHECK(a.m_ok && a.taps2.ok && a.taps3.ok);
    bp2 = a.bp2;
    taps3 = a.taps3;
    CHECK_INT(smd_lcl_smo_step(&p, &a, i1, i2, u, th, w), SMD_OK);
    CHECK_INT(smd_lcl_smo_step(&p, &b, i1, i2, u, th, w), SMD_OK);
    CHECK(memcmp(&a, &b, sizeof a) == 0);
    CHECK(bp2.a1 == a.bp2.a1 && bp2.a2 == a.bp2.a2);
    CHECK(taps3.a == a.taps3.a && taps3.b == a.taps3.b && taps3.n == a.taps3.n);
    /* a non-finite speed or no table: nothing primed, the first step
     * refreshes all */
    smd_lcl_smo_reset(&a, th);
    smd_lcl_smo_prime(&p, &a, R(NAN));
    CHECK_INT(a.m_ok, 0);
    /* a held sample (defer, smd_drive_step sets it): that step does no
     * piece of the spread refresh and leaves its age; the next does the
     * piece the held one would have: the model's second part (its floats
     * 28-55, at decimation 8), zeroed here to see it recomputed */
    smd_lcl_smo_reset(&a, th);
    smd_lcl_smo_prime(&p, &a, w);
    CHECK_INT(smd_lcl_smo_step(&p, &a, i1, i2, u, th, w), SMD_OK);
    CHECK_INT(a.age, 1);
    b = a;
    for (k = 28; k < 56; k++) {
        ((smd_real *)&a.m)[k] = R(0.0);
    }
    a.defer = 1;
    CHECK_INT(smd_lcl_smo_step(&p, &a, i1, i2, u, th, w), SMD_OK);
    CHECK_INT(a.age, 1);
    CHECK_INT(a.defer, 0);
    CHECK(((smd_real *)&a.m)[40] == R(0.0));
    CHECK_INT(smd_lcl_smo_step(&p, &a, i1, i2, u, th, w), SMD_OK);
    CHECK_INT(a.age, 2);
    CHECK(memcmp(&a.m, &b.m, sizeof a.m) == 0);
}

int main(void)
{
    RUN_TEST(test_lcl_smo_prime);
    RUN_TEST(test_combinations);
    RUN_TEST(test_values_rejected);
    RUN_TEST(test_pi_zero_steady_state_error);
    RUN_TEST(test_pi_smdo_feed_forward);
    RUN_TEST(test_if_start);
    RUN_TEST(test_handover_smdo);
    RUN_TEST(test_handover_pll);
    RUN_TEST(test_pll_source_nonfinite_sample);
    RUN_TEST(test_view_fields);
    return smdt_summary("test_compose");
}

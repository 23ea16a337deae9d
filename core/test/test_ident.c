/*
 * Commissioning, R_s and the inverter's drop (smd_ident.h), against a plant
 * the test does not see: a stator at standstill along the alpha axis, solved
 * exactly over each sample (i(T) = e^{-RT/L} (i - u/R) + u/R), fed over
 * [t_k, t_k+1) with the voltage the duties of sample k - 1 realise (the
 * engine's timing), less the inverter's drop u_0
 * against the current's direction, with zero-current clamping (a current
 * that would cross zero stays there); the ADC adds uniform noise and a
 * 12-bit quantiser over +-25 A, and reads at most +-clip when clip > 0 (a
 * sensor whose range ends there).
 */
#include <math.h>
#include <stdint.h>

#include "smd_test.h"
#include "smodrive/smd_ident.h"

typedef struct rl_plant {
    double R, L, u_0, T, u_dc, noise, i;
    uint32_t seed;
    double clip;   /* the sensor's range, A (0: none) */
    double i_peak; /* the largest |i| the plant carried, A */
} rl_plant;

static double adc(rl_plant *pl)
{
    double q = 50.0 / 4096.0;
    double x = pl->i + pl->noise * smdt_urand(&pl->seed, -1.7320508, 1.7320508);
    if (pl->clip > 0.0) {
        x = x > pl->clip ? pl->clip : (x < -pl->clip ? -pl->clip : x);
    }
    return q * floor(x / q + 0.5);
}

static void rl_step(rl_plant *pl, double u_cmd)
{
    double e = exp(-pl->R / pl->L * pl->T);
    double sg = pl->i > 0.0 ? 1.0 : (pl->i < 0.0 ? -1.0 : (u_cmd > 0.0 ? 1.0 : -1.0));
    double u = u_cmd - pl->u_0 * sg;
    double i = e * (pl->i - u / pl->R) + u / pl->R;
    pl->i = (i * sg < 0.0) ? 0.0 : i; /* clamped at zero */
    pl->i_peak = fabs(pl->i) > pl->i_peak ? fabs(pl->i) : pl->i_peak;
}

static double realised_alpha(const smd_real d[3], double u_dc)
{
    return (2.0 / 3.0) * u_dc * ((double)d[0] - 0.5 * ((double)d[1] + (double)d[2]));
}

static smd_ident_rs_config config(double i_test)
{
    smd_ident_rs_config c;
    c.T_sp = R(1e-4);
    c.i_test = (smd_real)i_test;
    c.u_max = R(311.0);
    c.t_win = R(0.02);
    c.t_level_max = R(2.0);
    c.levels = 10;
    return c;
}

/* Runs the test on `pl` for at most 30 s; returns the samples run. */
static int run(const smd_ident_rs_params *p, smd_ident_rs_state *s, rl_plant *pl, int *bad_duty)
{
    double u_next = 0.0;
    int k;
    *bad_duty = 0;
    smd_ident_rs_reset(s);
    for (k = 0; k < 300000; k++) {
        smd_real d[3];
        int j;
        double ia = adc(pl);
        (void)smd_ident_rs_step(p, s, (smd_real)ia, (smd_real)(-0.5 * ia), (smd_real)pl->u_dc, d);
        for (j = 0; j < 3; j++) {
            *bad_duty += !(d[j] >= R(0.0) && d[j] <= R(1.0));
        }
        rl_step(pl, u_next); /* over [t_k, t_k+1): the command of k - 1 */
        u_next = realised_alpha(d, pl->u_dc);
        if (s->phase == SMD_IDENT_DONE || s->phase == SMD_IDENT_FAILED) {
            return k + 1;
        }
    }
    return k;
}

/* The two stators of step 1's tests: yang2018's Table I (2.25 ohm, 23.45 mH)
 * and a 50 mohm, 0.5 mH one, behind 14.4 V and 2 V of inverter drop, at
 * 100 us on 540 V, with `noise` A of ADC noise. */
static const double R1[2] = {2.25, 0.05}, L1[2] = {23.45e-3, 0.5e-3}, U01[2] = {14.4, 2.0};

static rl_plant stator(int c, double noise, uint32_t seed)
{
    rl_plant pl = {0};
    pl.R = R1[c];
    pl.L = L1[c];
    pl.u_0 = U01[c];
    pl.T = 1e-4;
    pl.u_dc = 540.0;
    pl.noise = noise;
    pl.seed = seed;
    return pl;
}

/* yang2018's Table I stator (2.25 ohm, 23.45 mH) on 540 V with 2 us of dead
 * time (u_0 = 4/3 t_d / T u_dc = 14.4 V), 0.02 A of noise, i_test 4 A; and a
 * 50 mohm, 0.5 mH stator with 2 V of drop and 0.05 A, i_test 20 A. R_s within
 * 0.5 % (the levels' means carry the noise's standard error, 0.02 / sqrt(200)
 * A, over currents of 0.4-4 A: 0.1 % of the slope; the quantiser's 12 mA
 * steps average out under the noise), u_0 within 1 % of the drop (its
 * intercept's error: R_s's error times the levels' mean current, 0.5 % of
 * 14.4 V at most), the fit's R^2 above 0.9999, within 10 s. */
static void test_rs_and_drop(void)
{
    const double noise[2] = {0.02, 0.05}, it[2] = {4.0, 20.0};
    int c;
    for (c = 0; c < 2; c++) {
        smd_ident_rs_params p;
        smd_ident_rs_state s;
        smd_ident_rs_config cfg = config(it[c]);
        rl_plant pl = stator(c, noise[c], 12345u + (uint32_t)c);
        int n, bad;
        CHECK_INT(smd_ident_rs_init(&p, &cfg), SMD_OK);
        n = run(&p, &s, &pl, &bad);
        printf("    R %.3f ohm: R_s %.5f (%+.3f %%), u_0 %.3f V (%+.2f %%), R^2 %.7f, %.2f s, peak %.2f A\n",
               R1[c], (double)s.R_s, 100.0 * ((double)s.R_s / R1[c] - 1.0), (double)s.u_0,
               100.0 * ((double)s.u_0 / U01[c] - 1.0), (double)s.r2, n * 1e-4, pl.i_peak);
        CHECK_INT(s.outcome, SMD_IDENT_OK);
        CHECK(fabs((double)s.R_s / R1[c] - 1.0) < 0.005);
        CHECK(fabs((double)s.u_0 / U01[c] - 1.0) < 0.01);
        CHECK((double)s.r2 > 0.9999);
        CHECK(n * 1e-4 < 10.0);
        CHECK_INT(bad, 0);
    }
}

/* The outcomes that say why there is no result: an open phase (1 Mohm: no
 * current at any voltage) ends in NO_CURRENT at the voltage limit; a NaN
 * current in BAD_INPUT at once; both with the zero vector and SMD_ERR_FAULT
 * from then on. A finished test holds the zero vector with SMD_OK. */
static void test_outcomes(void)
{
    smd_ident_rs_params p;
    smd_ident_rs_state s;
    smd_ident_rs_config cfg = config(4.0);
    rl_plant pl = {0};
    smd_real d[3];
    int n, bad;
    pl.R = 1e6;
    pl.L = 1e-3;
    pl.T = 1e-4;
    pl.u_dc = 540.0;
    pl.seed = 7u;
    CHECK_INT(smd_ident_rs_init(&p, &cfg), SMD_OK);
    n = run(&p, &s, &pl, &bad);
    printf("    open phase: outcome %d after %.2f s\n", s.outcome, n * 1e-4);
    CHECK_INT(s.outcome, SMD_IDENT_NO_CURRENT);
    CHECK_INT(s.phase, SMD_IDENT_FAILED);
    CHECK_INT(smd_ident_rs_step(&p, &s, R(0.0), R(0.0), R(540.0), d), SMD_ERR_FAULT);
    CHECK(d[0] == R(0.5) && d[1] == R(0.5) && d[2] == R(0.5));
    smd_ident_rs_reset(&s);
    CHECK_INT(smd_ident_rs_step(&p, &s, R(0.0), R(0.0), R(540.0), d), SMD_OK);
    CHECK_INT(smd_ident_rs_step(&p, &s, (smd_real)NAN, R(0.0), R(540.0), d), SMD_ERR_FAULT);
    CHECK_INT(s.outcome, SMD_IDENT_BAD_INPUT);
    CHECK(d[0] == R(0.5) && d[1] == R(0.5) && d[2] == R(0.5));
    /* a phase current beyond 1.5 i_test stops the test */
    smd_ident_rs_reset(&s);
    CHECK_INT(smd_ident_rs_step(&p, &s, R(-3.0), R(6.5), R(540.0), d), SMD_ERR_FAULT);
    CHECK_INT(s.outcome, SMD_IDENT_OVERCURRENT);
}

/* A current sensor whose range ends below i_test, at 0.7 i_test (it reads
 * its full scale while the true current grows): the search's voltage would
 * rise to the limit, 311 V across the stator (132 A in Table I's 2.25 ohm
 * past its 14.4 V drop, 6,200 A in the 50 mohm one), with the trip at
 * 1.5 i_test blind to it. The test stops with SENSOR_RANGE at the first step
 * the reading does not follow: the clip hides at most three of the search's
 * steps (the one that crosses the range, one still partly seen, the one that
 * stalls), each at most u_max / 200 = 1.56 V, so the true current stays
 * within the clip plus 3 x 1.56 V / R_s (Table I: 4.9 A, and under 2 i_test;
 * the 50 mohm stator, whose search steps 1.5 i_test at a time even with a
 * sensor that sees it, 107 A); the zero vector after. */
static void test_sensor_range(void)
{
    const double it[2] = {4.0, 20.0};
    int c;
    for (c = 0; c < 2; c++) {
        smd_ident_rs_params p;
        smd_ident_rs_state s;
        smd_ident_rs_config cfg = config(it[c]);
        rl_plant pl = stator(c, 0.02, 99u + (uint32_t)c);
        smd_real d[3];
        int n, bad;
        pl.clip = 0.7 * it[c];
        CHECK_INT(smd_ident_rs_init(&p, &cfg), SMD_OK);
        n = run(&p, &s, &pl, &bad);
        printf("    R %.3f ohm, sensor range %.1f A, i_test %.0f A: outcome %d after %.2f s, "
               "true current at most %.2f A\n", R1[c], pl.clip, it[c], s.outcome, n * 1e-4,
               pl.i_peak);
        CHECK_INT(s.outcome, SMD_IDENT_SENSOR_RANGE);
        CHECK_INT(s.phase, SMD_IDENT_FAILED);
        CHECK(pl.i_peak < pl.clip + 3.0 * (311.0 / 200.0) / R1[c]);
        CHECK(c == 1 || pl.i_peak < 2.0 * it[c]);
        CHECK_INT(bad, 0);
        CHECK_INT(smd_ident_rs_step(&p, &s, R(0.0), R(0.0), R(540.0), d), SMD_ERR_FAULT);
        CHECK(d[0] == R(0.5) && d[1] == R(0.5) && d[2] == R(0.5));
    }
}

/* Step 2 on the d axis (alpha) of the same plant after step 1: the Table I
 * stator (L/R = 10 ms, a hundred samples: the wave is a triangle) and a
 * 1 ohm, 50 uH one (L/R = 50 us, half a sample: the wave is almost square,
 * where the slopes of a triangle would be 2 x off), each on the R_s and u_0
 * step 1 measured: L within 2 % (the averaged wave's noise, 0.02 A over
 * sqrt(400) periods, against a swing of 10 % of the bias), within 2 s. */
static void test_inductance(void)
{
    const double Rs[2] = {2.25, 1.0}, Ls[2] = {23.45e-3, 50e-6}, U0[2] = {14.4, 0.5};
    int c;
    for (c = 0; c < 2; c++) {
        smd_ident_rs_params p;
        smd_ident_rs_state s;
        smd_ident_rs_config cfg = config(c == 0 ? 4.0 : 2.0);
        smd_ident_ls_config lc;
        smd_ident_ls_params lp;
        smd_ident_ls_state ls;
        rl_plant pl = {0};
        double u_next = 0.0;
        int bad, k;
        pl.R = Rs[c];
        pl.L = Ls[c];
        pl.u_0 = U0[c];
        pl.T = 1e-4;
        pl.u_dc = c == 0 ? 540.0 : 48.0;
        pl.noise = 0.02;
        pl.seed = 99u + (uint32_t)c;
        cfg.u_max = (smd_real)(pl.u_dc / 1.7320508);
        CHECK_INT(smd_ident_rs_init(&p, &cfg), SMD_OK);
        (void)run(&p, &s, &pl, &bad);
        CHECK_INT(s.outcome, SMD_IDENT_OK);
        lc.T_sp = R(1e-4);
        lc.R_s = s.R_s;
        lc.u_0 = s.u_0;
        lc.i_bias = R(0.5) * cfg.i_test;
        lc.u_max = cfg.u_max;
        lc.t_win = R(0.02);
        lc.axis = 0;
        lc.n_half = 8;
        lc.periods = 400;
        CHECK_INT(smd_ident_ls_init(&lp, &lc), SMD_OK);
        smd_ident_ls_reset(&ls);
        for (k = 0; k < 100000; k++) {
            smd_real d[3];
            double ia = adc(&pl);
            (void)smd_ident_ls_step(&lp, &ls, (smd_real)ia, (smd_real)(-0.5 * ia),
                                    (smd_real)pl.u_dc, d);
            rl_step(&pl, u_next);
            u_next = realised_alpha(d, pl.u_dc);
            if (ls.phase == SMD_IDENT_LS_DONE || ls.phase == SMD_IDENT_LS_FAILED) {
                break;
            }
        }
        printf("    R %.2f ohm, L %.3g H: L %.5g H (%+.2f %%), R_ac %.4g ohm, +-%.3g V, %.2f s\n",
               Rs[c], Ls[c], (double)ls.L, 100.0 * ((double)ls.L / Ls[c] - 1.0), (double)ls.R_ac,
               (double)ls.du, k * 1e-4);
        CHECK_INT(ls.outcome, SMD_IDENT_OK);
        CHECK(fabs((double)ls.L / Ls[c] - 1.0) < 0.02);
        CHECK(k * 1e-4 < 2.0);
    }
}

/* Settings out of range name the test's (SMD_ERR_IDENT). */
static void test_settings(void)
{
    smd_ident_rs_params p;
    smd_ident_rs_config c = config(4.0);
    c.levels = 7;
    CHECK_INT(smd_ident_rs_init(&p, &c), SMD_ERR_IDENT);
    c = config(4.0);
    c.i_test = R(0.0);
    CHECK_INT(smd_ident_rs_init(&p, &c), SMD_ERR_IDENT);
    c = config(4.0);
    c.t_win = R(5e-4); /* below 10 T_sp */
    CHECK_INT(smd_ident_rs_init(&p, &c), SMD_ERR_IDENT);
    c = config(4.0);
    c.T_sp = R(1e-9); /* 1e11 samples a level: beyond an int's count (fuzz_blocks found it) */
    c.t_win = R(1e-3);
    c.t_level_max = R(100.0);
    CHECK_INT(smd_ident_rs_init(&p, &c), SMD_ERR_IDENT);
    c = config(4.0);
    c.u_max = (smd_real)NAN;
    CHECK_INT(smd_ident_rs_init(&p, &c), SMD_ERR_IDENT);
    CHECK_INT(smd_ident_rs_init(0, &c), SMD_ERR_NULL);
}

/* Step 4's synthetic rig: a rotor that follows the test's reference through
 * a lag of tau = 20 ms, the torque its motion needs, T = J dw/dt + B w
 * (+ K w |w|, a fan), given as i_q = T / k_t; the speed estimate the
 * rotor's, or passed through a first-order low-pass of w_est (a drive's
 * speed estimate); before open_to the drive is on its forced start. */
typedef struct mech_rig {
    smd_real J, B, K;     /* the rotor's */
    int fan;              /* the test's config */
    double w_est;         /* the speed estimate's low-pass, rad/s (0: none) */
    smd_real w_lpf;       /* the test's config */
    smd_real t_coast;     /* the test's config; coasting, the rotor runs down on B and K */
    double i_off;         /* a torque current the coast's zero does not remove, A */
    int fault_at, nan_at, open_to;
} mech_rig;

static mech_rig rig(smd_real J, smd_real B)
{
    mech_rig r;
    r.J = J;
    r.B = B;
    r.K = SMD_R(0.0);
    r.fan = 0;
    r.w_est = 0.0;
    r.w_lpf = SMD_R(0.0);
    r.t_coast = SMD_R(0.0);
    r.i_off = 0.0;
    r.fault_at = r.nan_at = -1;
    r.open_to = 0;
    return r;
}

static void mech_run_rig(const mech_rig *r, smd_ident_mech_state *s)
{
    smd_ident_mech_config c;
    smd_ident_mech_params p;
    const double T = 1e-4, tau = 0.02, k_t = 2.4;
    const double a_est = r->w_est > 0.0 ? 1.0 - exp(-r->w_est * T) : 1.0;
    double w = 0.0, w_f;
    int k;
    c.T_sp = SMD_R(1e-4);
    c.k_t = SMD_R(2.4);
    c.n_p = 4;
    c.w1 = SMD_R(250.0);
    c.w2 = SMD_R(500.0);
    c.t_step = SMD_R(0.2);
    c.t_ramp = SMD_R(0.1);
    c.t_hold = SMD_R(0.1);
    c.t_fit = SMD_R(0.05);
    c.t_bin = SMD_R(0.002);
    c.w_lpf = r->w_lpf;
    c.fan = r->fan;
    c.t_coast = r->t_coast;
    CHECK_INT(smd_ident_mech_init(&p, &c), SMD_OK);
    smd_ident_mech_reset(s);
    w = 250.0 / 4.0; /* the rotor at w1 already (a start the drive made) */
    w_f = w;
    for (k = 0; k < 100000; k++) {
        const double ref = (double)smd_ident_mech_ref(&p, s) / 4.0;
        const int coast = smd_ident_mech_coasting(&p, s);
        double w_next = w + (T / tau) * (ref - w);
        double w_mid, torque;
        smd_real iq, wh = (smd_real)(4.0 * w_f);
        if (coast) {
            /* no torque but the offset's: the rotor runs down on its losses */
            const double load = (double)r->B * w + (double)r->K * w * fabs(w);
            w_next = w + T * (k_t * r->i_off - load) / (double)r->J;
        }
        /* the torque over the sample, at its middle speed */
        w_mid = 0.5 * (w + w_next);
        torque = (double)r->J * (w_next - w) / T + (double)r->B * w_mid +
                 (double)r->K * w_mid * fabs(w_mid);
        iq = (smd_real)(coast ? 0.0 : torque / k_t);
        if (k == r->nan_at) {
            wh = (smd_real)NAN;
        }
        if (k < r->open_to) {
            iq = (smd_real)(3.0 * torque / k_t + 1.0); /* a forced start: not k_t i_q */
        }
        if (smd_ident_mech_step(&p, s, iq, wh, k >= r->open_to, k == r->fault_at ? 1u : 0u)) {
            break;
        }
        w = w_next;
        w_f += a_est * (w - w_f);
    }
}

static void mech_run_open(smd_real J, smd_real B, int fault_at, int nan_at, int open_to,
                          smd_ident_mech_state *s)
{
    mech_rig r = rig(J, B);
    r.fault_at = fault_at;
    r.nan_at = nan_at;
    r.open_to = open_to;
    mech_run_rig(&r, s);
}

static void mech_run(smd_real J, smd_real B, int fault_at, int nan_at, smd_ident_mech_state *s)
{
    mech_run_open(J, B, fault_at, nan_at, 0, s);
}

static void test_mech(void)
{
    smd_ident_mech_state s;
    smd_ident_mech_config c;
    smd_ident_mech_params p;
    mech_run(SMD_R(0.012), SMD_R(0.002), -1, -1, &s);
    CHECK_INT(s.outcome, SMD_IDENT_OK);
    CHECK_CLOSE(s.J, 0.012, 0.01 * 0.012);
    /* B's share of the torque on the ramp is 1/30 of J's (0.25 against 7.5
     * N m), so J's binning error moves it 30 times as much: within 5 % */
    CHECK_CLOSE(s.B, 0.002, 0.05 * 0.002);
    CHECK_INT(s.k, 4000); /* the whole test: 0.2 + 0.1 + 0.1 s */
    /* the torque current with the wrong sign (a phase swapped, the flux's
     * sign): J < 0 is a poor fit, not a result */
    mech_run(SMD_R(-0.012), SMD_R(0.002), -1, -1, &s);
    CHECK_INT(s.outcome, SMD_IDENT_POOR_FIT);
    mech_run(SMD_R(0.012), SMD_R(0.002), 2500, -1, &s);
    CHECK_INT(s.outcome, SMD_IDENT_FAULT);
    CHECK_INT(s.k, 2500);
    mech_run(SMD_R(0.012), SMD_R(0.002), -1, 3000, &s);
    CHECK_INT(s.outcome, SMD_IDENT_BAD_INPUT);
    /* a drive still on its forced start 0.25 s in (its torque not k_t
     * i_q_ref, here 3 times it): the fit waits at its first sample (0.15 s)
     * for 0.1 s, then J and B as before; without the wait (closed given
     * as 1 throughout, the start's torque in the fit) J is 71 % off */
    mech_run_open(SMD_R(0.012), SMD_R(0.002), -1, -1, 2500, &s);
    CHECK_INT(s.outcome, SMD_IDENT_OK);
    CHECK_INT(s.wait, 1000);
    CHECK_CLOSE(s.J, 0.012, 0.01 * 0.012);
    CHECK_CLOSE(s.B, 0.002, 0.05 * 0.002);
    /* a speed estimate through a low-pass of 100 rad/s (the SMDO's): with
     * the torque passed through the same filter (w_lpf), J within 1 % and B
     * within 5 %; without it B comes out negative (measured -0.0011) */
    {
        mech_rig r = rig(SMD_R(0.012), SMD_R(0.002));
        r.w_est = 100.0;
        r.w_lpf = SMD_R(100.0);
        mech_run_rig(&r, &s);
        CHECK_INT(s.outcome, SMD_IDENT_OK);
        CHECK_CLOSE(s.J, 0.012, 0.01 * 0.012);
        CHECK_CLOSE(s.B, 0.002, 0.05 * 0.002);
        r.w_lpf = SMD_R(0.0);
        mech_run_rig(&r, &s);
        CHECK(s.B < SMD_R(0.0));
    }
    /* a fan's torque besides (K w|w|, 0.6 of B w at w1): with fan = 1, J
     * within 1 %, B and K within 15 %; without, B takes the fan (measured
     * +112 %).
     * (B and K come from speeds 1:2 apart, where w and w|w| correlate at
     * 0.996: the bins' small error (J's 0.2 %) splits between them
     * unevenly, measured B +9 %, K -9 %; their sum at w2 within 1 %.) */
    {
        mech_rig r = rig(SMD_R(0.012), SMD_R(0.002));
        r.K = SMD_R(0.002 * 0.6 / 62.5);
        r.fan = 1;
        mech_run_rig(&r, &s);
        CHECK_INT(s.outcome, SMD_IDENT_OK);
        CHECK_CLOSE(s.J, 0.012, 0.01 * 0.012);
        CHECK_CLOSE(s.B, 0.002, 0.15 * 0.002);
        CHECK_CLOSE(s.K, 0.002 * 0.6 / 62.5, 0.15 * 0.002 * 0.6 / 62.5);
        CHECK_CLOSE((double)s.B * 125.0 + (double)s.K * 125.0 * 125.0,
                    0.002 * 125.0 * (1.0 + 0.6 * 2.0), 0.01 * 0.002 * 125.0 * (1.0 + 0.6 * 2.0));
        r.fan = 0;
        mech_run_rig(&r, &s);
        CHECK((double)s.B > 1.5 * 0.002);
        /* no fan where the test fits one: K is 0 or small, B as before */
        r = rig(SMD_R(0.012), SMD_R(0.002));
        r.fan = 1;
        mech_run_rig(&r, &s);
        CHECK_INT(s.outcome, SMD_IDENT_OK);
        CHECK_CLOSE(s.J, 0.012, 0.01 * 0.012);
        CHECK_CLOSE(s.B, 0.002, 0.1 * 0.002);
    }
    /* a coast of 0.1 s at zero current after the hold: B from the
     * deceleration (2 % of the rotor's speed in 0.1 s), J from the ramp with
     * it: within 1 % and 5 %, and the ramp's own B kept aside (B_ramp); a
     * torque current of 0.05 A the coast's zero leaves (a sensor's offset)
     * moves B by its share, 0.12 N m of B w's 0.25 at w2, and the ramp's B
     * not: the coast's B is what the test gives */
    {
        mech_rig r = rig(SMD_R(0.012), SMD_R(0.002));
        r.t_coast = SMD_R(0.1);
        mech_run_rig(&r, &s);
        CHECK_INT(s.outcome, SMD_IDENT_OK);
        CHECK_INT(s.k, 5000);
        CHECK_CLOSE(s.J, 0.012, 0.01 * 0.012);
        CHECK_CLOSE(s.B, 0.002, 0.05 * 0.002);
        CHECK_CLOSE(s.B_ramp, 0.002, 0.05 * 0.002);
        r.i_off = -0.05;
        mech_run_rig(&r, &s);
        CHECK((double)s.B > 1.3 * 0.002);
        CHECK_CLOSE(s.B_ramp, 0.002, 0.05 * 0.002);
    }
    /* never on its source: NOT_SETTLED after waiting as long as the test */
    mech_run_open(SMD_R(0.012), SMD_R(0.002), -1, -1, 1000000, &s);
    CHECK_INT(s.outcome, SMD_IDENT_NOT_SETTLED);
    CHECK_INT(s.wait, 4000);
    /* settings */
    c.T_sp = SMD_R(1e-4);
    c.k_t = SMD_R(2.4);
    c.n_p = 4;
    c.w1 = SMD_R(500.0);
    c.w2 = SMD_R(250.0); /* w2 below w1 */
    c.t_step = SMD_R(0.2);
    c.t_ramp = SMD_R(0.1);
    c.t_hold = SMD_R(0.1);
    c.t_fit = SMD_R(0.05);
    c.t_bin = SMD_R(0.002);
    c.w_lpf = SMD_R(0.0);
    c.fan = 0;
    c.t_coast = SMD_R(0.0);
    CHECK_INT(smd_ident_mech_init(&p, &c), SMD_ERR_IDENT);
    c.w2 = SMD_R(1000.0);
    c.t_fit = SMD_R(0.15); /* more than half the step */
    CHECK_INT(smd_ident_mech_init(&p, &c), SMD_ERR_IDENT);
    c.t_fit = SMD_R(0.05);
    c.t_step = SMD_R(1e5);
    CHECK_INT(smd_ident_mech_init(&p, &c), SMD_ERR_IDENT);
    c.t_step = SMD_R(0.2);
    c.w_lpf = SMD_R(20.0); /* 5 time constants beyond the step (fuzz_blocks found it) */
    CHECK_INT(smd_ident_mech_init(&p, &c), SMD_ERR_IDENT);
    c.w_lpf = SMD_R(25.0);
    CHECK_INT(smd_ident_mech_init(&p, &c), SMD_OK);
    c.fan = 2;
    CHECK_INT(smd_ident_mech_init(&p, &c), SMD_ERR_IDENT);
    c.fan = 0;
    /* a coast: 5 time constants of the filter and 4 bins at least (0.2 + 0.008 s
     * at 25 rad/s), 100 s at most */
    c.t_coast = SMD_R(0.2);
    CHECK_INT(smd_ident_mech_init(&p, &c), SMD_ERR_IDENT);
    c.t_coast = SMD_R(0.21);
    CHECK_INT(smd_ident_mech_init(&p, &c), SMD_OK);
    c.t_coast = SMD_R(101.0);
    CHECK_INT(smd_ident_mech_init(&p, &c), SMD_ERR_IDENT);
    c.t_coast = (smd_real)NAN;
    CHECK_INT(smd_ident_mech_init(&p, &c), SMD_ERR_IDENT);
    CHECK_INT(smd_ident_mech_init(0, &c), SMD_ERR_NULL);
}

int main(void)
{
    RUN_TEST(test_rs_and_drop);
    RUN_TEST(test_outcomes);
    RUN_TEST(test_sensor_range);
    RUN_TEST(test_inductance);
    RUN_TEST(test_settings);
    RUN_TEST(test_mech);
    return smdt_summary("ident");
}

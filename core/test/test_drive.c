/*
 * The one drive (smd_drive) in its yang2018 compositions, the former modes:
 * conventional = (dbpc, encoder), robust = (robust_dbpc, encoder),
 * sensorless = (robust_dbpc, smdo_emf, handover); and synchronous-frame PI on
 * the encoder and on the SMDO's angle. Configuration checks, each in closed
 * loop with the exact plant (drive_fixture.h), the speed loop and its
 * decimation, non-finite inputs.
 * The compositions themselves (wrong combinations, PI steady state, start-up
 * supervisor, view) are in test_compose.c.
 */
#include "drive_fixture.h"

/* Every status has a text of its own, through the last one (SMD_ERR_START);
 * the next value is unknown. */
static void test_status_strings(void)
{
    int a, b;
    for (a = 0; a <= SMD_ERR_RLS; a++) {
        CHECK(strcmp(smd_status_str((smd_status)a), "unknown status") != 0);
        for (b = 0; b < a; b++) {
            CHECK(strcmp(smd_status_str((smd_status)a), smd_status_str((smd_status)b)) != 0);
        }
    }
    CHECK(strcmp(smd_status_str((smd_status)(SMD_ERR_RLS + 1)), "unknown status") == 0);
}

static void test_init_rejects(void)
{
    smd_drive_params p;
    smd_drive_config c;
    int mode;
    for (mode = 0; mode < 5; mode++) {
        c = mode_config(mode);
        CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
    }
    /* the former mode 3 and -1: unknown part values */
    c = mode_config(MODE_ROBUST);
    c.current = 3;
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_MODE);
    c = mode_config(MODE_ROBUST);
    c.current = -1;
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_MODE);
    c = mode_config(MODE_ROBUST);
    c.speed_decimation = 0;
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_DECIMATION);
    c.speed_decimation = 1001;
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_DECIMATION);
    c = mode_config(MODE_ROBUST);
    c.speed_loop = 2;
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_MODE);
    c = mode_config(MODE_ROBUST);
    c.svm_limit = 7;
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_MODE);
    c = mode_config(MODE_ROBUST);
    c.smdo_euler = 2;
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_MODE);
    c = mode_config(MODE_ROBUST);
    c.T_sp = R(0.0);
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_TS);
    /* SMDO parameters are checked in the observer drives only */
    c = mode_config(MODE_ROBUST);
    c.rho = R(0.0);
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_RHO);
    c.current = SMD_CC_DBPC;
    CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
    c.current = SMD_CC_PI;
    CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
    c.position = SMD_POS_SMDO_EMF; /* the source needs the SMDO */
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_RHO);
    /* sensorless: |1 - w_c T + j w_max T| < 1 needs w_max T < 0.527 here */
    c = mode_config(MODE_SENSORLESS);
    c.w_max = R(6000.0);
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_STABILITY);
    c = mode_config(MODE_SENSORLESS);
    c.handover = -1;
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_HANDOVER);
    c = mode_config(MODE_ROBUST);
    CHECK_INT(smd_drive_init(0, &c), SMD_ERR_NULL);
    CHECK_INT(smd_drive_init(&p, 0), SMD_ERR_NULL);
}

/* Closed loop at constant speed w with i_dq_ref = idq; returns the max dq
 * current error over the last 50 ms of 0.3 s, and the max angle error of the
 * controller (sensorless: estimate vs plant) over the same window. */
static double run_mode(int mode, int euler, double w, double complex idq, double *th_err,
                       int *bad_duty)
{
    smd_drive_params p;
    smd_drive_state s;
    smd_drive_config c = mode_config(mode);
    smd_drive_in in;
    smd_drive_out out;
    plant pl;
    double complex u = 0.0;
    double worst = 0.0, worst_th = 0.0;
    c.smdo_euler = euler;
    int k, n = 3000, tail = 500;
    pl.i = 0.0;
    pl.th = 0.3;
    pl.w = w;
    *bad_duty = 0;
    if (smd_drive_init(&p, &c) != SMD_OK) {
        *th_err = INFINITY;
        return INFINITY;
    }
    smd_drive_reset(&p, &s, R(pl.th), R(w), R(0.0));
    for (k = 0; k < n; k++) {
        smd_drive_view v;
        fill_in(&in, &pl, idq);
        (void)smd_drive_step(&p, &s, &in, &out);
        if (!duties_ok(out.d_abc)) {
            (*bad_duty)++;
        }
        v = smd_drive_get_view(&p, &s);
        if (k >= n - tail) {
            double e = cabs(pl.i * cexp(-JD * pl.th) - idq);
            double et = fabs(smdt_wrap((double)v.theta - pl.th));
            worst = e > worst ? e : worst;
            worst_th = et > worst_th ? et : worst_th;
        }
        plant_step(&pl, u);        /* [k, k+1) with the voltage decided at k-1 */
        u = realised(out.d_abc);   /* applied during [k+1, k+2) */
    }
    *th_err = worst_th;
    return worst;
}

/* Each mode runs and tracks the current reference at +-400 rad/s (|i| = 5 A,
 * with i_d = -1 A to check that i_dref is kept), with exact parameters.
 * Error budget: the controllers use the Euler model (3)/(15); against the
 * exact plant one step mispredicts the EMF integral by about
 * (T/L) w psi (w T / 2) = 0.014 A, and the deadbeat law spans two steps, so
 * ~0.03 A (conventional); the SMDO absorbs that mismatch but leaves
 * (T/L) w psi |G - 1| with |G - 1| ~ w^2 T / (2 w_c) = 0.5 % -> 0.004 A
 * with (36) as printed (smdo_euler = 1), ~0 with the exact rotation
 * (default); the sensorless angle error is a few mrad -> 5 A x 3e-3. The PI
 * on the encoder (mode 3) has integral action: no steady-state error at all
 * (test_compose.c bounds it at 1e-3 A); on the SMDO's angle (mode 4) none in
 * its own frame, so the angle error's 5 A x 3e-3 again. We allow 0.1 A (2 %
 * of the reference): a wrong sign, a missing EMF term, a missing delay
 * compensation or a pi angle error give errors of amperes. */
static void test_modes_track(void)
{
    const double speeds[2] = {400.0, -400.0};
    const double complex idq = -1.0 + 5.0 * JD;
    int mode, n, euler;
    for (mode = 0; mode < 5; mode++) {
        for (n = 0; n < 4; n++) {
            double th_err;
            int bad;
            double e;
            euler = n / 2;
            if ((mode == MODE_CONVENTIONAL || mode == MODE_PI) && euler) {
                continue; /* no observer */
            }
            e = run_mode(mode, euler, speeds[n % 2], idq, &th_err, &bad);
            printf("    mode %d, smdo_euler %d, w = %6.1f: max |i_dq - i_ref| = %.2e A,"
                   " max angle error = %.2e rad\n", mode, euler, speeds[n % 2], e, th_err);
            CHECK_CLOSE(e, 0.0, 0.1);
            if (mode == MODE_ROBUST && !euler) {
                /* exact rotation: the SMDO's fixed point is exact for this
                 * LTI plant (its disturbance seen through model (15) rotates
                 * at w in steady state), so only rounding is left: ~16 eps of
                 * the L/T-amplified voltage per step, forgotten within ~7
                 * samples (1/(w_c T)) -> < ~200 eps |i|; allow 1000 eps |i| */
                CHECK_CLOSE(e, 0.0, 1000 * SMDT_EPS * cabs(idq));
            }
            CHECK_INT(bad, 0);
            /* sensored modes use the encoder angle; sensorless: the estimate
             * must be within 0.02 rad (half a sample of rotation at 400 rad/s) */
            CHECK_CLOSE(th_err, 0.0,
                        mode == MODE_SENSORLESS || mode == MODE_PI_SMDO ? 0.02
                                                                        : 8 * SMDT_EPS * PI_D);
        }
    }
}

/* Speed PI in the loop and its decimation (robust mode, N = 10, k_p = 0.05,
 * k_i = 2, loop period 10 T = 1 ms), speed error 20 rad/s held constant:
 *   sample 0 : x_i = 2 * 1e-3 * 20 = 0.04, i_qref = 0.05 * 20 + 0.04 = 1.04
 *   samples 1..9 hold 1.04; sample 10: x_i = 0.08, i_qref = 1.08;
 *   sample 20: 1.12. i_dref still comes from the input (-0.5). */
static void test_speed_loop_decimation(void)
{
    smd_drive_params p;
    smd_drive_state s;
    smd_drive_config c = mode_config(MODE_ROBUST);
    smd_drive_in in;
    smd_drive_out out;
    plant pl;
    int k;
    c.speed_loop = 1;
    c.speed_decimation = 10;
    CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
    pl.i = 0.0;
    pl.th = 0.0;
    pl.w = 100.0;
    smd_drive_reset(&p, &s, R(0.0), R(100.0), R(0.0));
    for (k = 0; k <= 20; k++) {
        smd_drive_view v;
        fill_in(&in, &pl, -0.5 + 3.0 * JD);
        in.w_ref = R(120.0);
        (void)smd_drive_step(&p, &s, &in, &out);
        v = smd_drive_get_view(&p, &s);
        if (k < 10) {
            CHECK_CLOSE(v.i_dq_ref.im, 1.04, 64 * SMDT_EPS);
        } else if (k < 20) {
            CHECK_CLOSE(v.i_dq_ref.im, 1.08, 64 * SMDT_EPS);
        } else {
            CHECK_CLOSE(v.i_dq_ref.im, 1.12, 64 * SMDT_EPS);
        }
        CHECK_CLOSE(v.i_dq_ref.re, -0.5, 0.0);
        plant_step(&pl, realised(out.d_abc));
    }
}

/* Non-finite inputs (each field in turn, NaN and Inf) never give non-finite
 * or out-of-range duties, in every mode (and the PI on the encoder and on
 * the SMDO), and every mode is back on the reference (0.1 A, as above) 20 ms
 * after the bad sample. */
static void test_nonfinite_inputs(void)
{
    int mode, field, kind;
    for (mode = 0; mode < 5; mode++) {
        for (field = 0; field < 7; field++) {
            for (kind = 0; kind < 2; kind++) {
                smd_drive_params p;
                smd_drive_state s;
                smd_drive_config c = mode_config(mode);
                smd_drive_in in;
                smd_drive_out out;
                plant pl;
                double complex u = 0.0, idq = 5.0 * JD;
                smd_real bad = kind ? R(INFINITY) : R(NAN);
                double worst_after = 0.0;
                int k, bad_duty = 0;
                c.speed_loop = (field == 5);
                CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
                start_at(&p, &s, &pl, 300.0);
                for (k = 0; k < 1500; k++) {
                    fill_in(&in, &pl, idq);
                    if (k == 1000) {
                        switch (field) {
                        case 0: in.i_a = bad; break;
                        case 1: in.i_b = bad; break;
                        case 2: in.theta_enc = bad; break;
                        case 3: in.w_enc = bad; break;
                        case 4: in.u_dc = bad; break;
                        case 5: in.w_ref = bad; break;
                        default: in.i_dq_ref = smd_c(bad, bad); break;
                        }
                    }
                    (void)smd_drive_step(&p, &s, &in, &out);
                    if (!duties_ok(out.d_abc)) {
                        bad_duty++;
                    }
                    if (k >= 1200 && field != 5) {
                        double e = cabs(pl.i * cexp(-JD * pl.th) - idq);
                        worst_after = e > worst_after ? e : worst_after;
                    }
                    plant_step(&pl, u);
                    u = realised(out.d_abc);
                }
                CHECK_INT(bad_duty, 0);
                if (field != 5) {
                    CHECK_CLOSE(worst_after, 0.0, 0.1);
                }
            }
        }
    }
}

/* A single non-finite current sample costs one sample: that sample reports
 * SMD_ERR_FAULT with SMD_FAULT_INPUT and applies the zero vector (duties
 * 0.5), and the next finite sample is processed normally (SMD_OK, no fault,
 * finite observer state), in every mode. */
static void test_nonfinite_sample_costs_one_sample(void)
{
    int mode;
    for (mode = 0; mode < 5; mode++) {
        smd_drive_params p;
        smd_drive_state s;
        smd_drive_config c = mode_config(mode);
        smd_drive_in in;
        smd_drive_out out;
        plant pl;
        double complex u = 0.0, idq = 5.0 * JD;
        int k;
        CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
        start_at(&p, &s, &pl, 300.0);
        for (k = 0; k < 502; k++) {
            smd_status st;
            fill_in(&in, &pl, idq);
            if (k == 500) {
                in.i_a = R(NAN);
            }
            st = smd_drive_step(&p, &s, &in, &out);
            if (k == 500) {
                CHECK_INT(st, SMD_ERR_FAULT);
                CHECK_INT(out.fault, SMD_FAULT_INPUT);
                CHECK(out.d_abc[0] == R(0.5) && out.d_abc[1] == R(0.5) && out.d_abc[2] == R(0.5));
            }
            if (k == 501) {
                CHECK_INT(st, SMD_OK);
                CHECK_INT(out.fault, 0);
                CHECK(smd_cfinite(s.smdo.i_s_hat) && smd_cfinite(s.u_ab_ref));
                CHECK(smd_cfinite(s.x_i) && smd_cfinite(s.u_ab_next));
            }
            plant_step(&pl, u);
            u = realised(out.d_abc);
        }
    }
}

int main(void)
{
    RUN_TEST(test_status_strings);
    RUN_TEST(test_init_rejects);
    RUN_TEST(test_modes_track);
    RUN_TEST(test_speed_loop_decimation);
    RUN_TEST(test_nonfinite_inputs);
    RUN_TEST(test_nonfinite_sample_costs_one_sample);
    return smdt_summary("test_drive");
}

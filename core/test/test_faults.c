/*
 * Faults of the one drive (smd_drive.h): finite duties whatever the inputs,
 * recovery after a bad sample, latched trips (overcurrent, DC link, loss of
 * lock) and their clearing, and the protection settings' checks.
 *
 * The plant is drive_fixture.h's exact discrete SPMSM at 300 rad/s
 * electrical with the current reference 5 A on q; the drives have dead-time
 * compensation on (t_dead_comp = 2 us), the part whose clamp let NaN through
 * before.
 */
#include <math.h>
#include <stdint.h>

#include "drive_fixture.h"

#define N_FIELDS 10
static const char *FIELD[N_FIELDS] = {"i_a", "i_b", "i1_a", "i1_b", "theta_enc",
                                      "w_enc", "u_dc", "w_ref", "i_d_ref", "i_q_ref"};

static void set_field(smd_drive_in *in, int field, smd_real v)
{
    switch (field) {
    case 0: in->i_a = v; break;
    case 1: in->i_b = v; break;
    case 2: in->i1_a = v; break;
    case 3: in->i1_b = v; break;
    case 4: in->theta_enc = v; break;
    case 5: in->w_enc = v; break;
    case 6: in->u_dc = v; break;
    case 7: in->w_ref = v; break;
    case 8: in->i_dq_ref.re = v; break;
    default: in->i_dq_ref.im = v; break;
    }
}

/* Whether the mode reads the field (smd_drive.h: an unused input is not a
 * fault): no filter, so i1 unused; the encoder only with the encoder
 * source; w_ref only with the speed loop (on for field 7), i_q_ref only
 * without it. */
static int used(int mode, int field, int speed_loop)
{
    if (field == 2 || field == 3) return 0;
    if (field == 4 || field == 5) return mode == MODE_CONVENTIONAL || mode == MODE_ROBUST ||
                                         mode == MODE_PI;
    if (field == 7) return speed_loop;
    if (field == 9) return !speed_loop;
    return 1;
}

static smd_drive_config fault_config(int mode)
{
    smd_drive_config c = mode_config(mode);
    c.t_dead_comp = R(2e-6);
    c.i_dtc = R(0.3);
    return c;
}

/* Every input of every mode replaced by NaN, +inf or 1e30 at sample 1000
 * (and, in a second pass, at about 20 samples spread over the run): every
 * duty of every sample is finite and in [0, 1]; the bad sample reports
 * SMD_ERR_FAULT with SMD_FAULT_INPUT when the mode reads that input (a
 * current reference of 1e30 A included: beyond any physical range, it is as
 * bad as a NaN) and runs normally when it does not; afterwards the drive returns to the run
 * without the bad samples (a twin in lockstep): the plant currents agree
 * within 0.05 A again within 20 samples for the DBPC modes (2 ms; the held
 * sample applied the zero vector for 100 us, a current error of about
 * u T / L ~ 1 A, which the deadbeat laws remove in 2 samples and the SMDO
 * in about 1 / (l T) = 8) and within 100 samples for the PI modes (its
 * double pole at 1000 rad/s: an error decays as (1 + t/tau) e^{-t/tau},
 * 1 A to 0.05 A in 4.7 tau = 47 samples; on the SMDO's angle the angle
 * error recovers too) and stay so. Prints the worst recovery per mode: the
 * fault-injection table of the notes. */
static void test_bad_inputs(void)
{
    const smd_real bad[3] = {R(NAN), R(INFINITY), R(1e30)};
    int mode, field, kind, pass;
    printf("    fault-injection table (NaN at sample 1000): status / samples back within "
           "0.05 A of the undisturbed run\n      mode");
    for (field = 0; field < N_FIELDS; field++) {
        printf(" %10s", FIELD[field]);
    }
    printf("\n");
    for (mode = 0; mode < 5; mode++) {
        int worst_rec = 0;
        int tab_st[N_FIELDS], tab_rec[N_FIELDS];
        for (pass = 0; pass < 2; pass++) {
            for (field = 0; field < N_FIELDS; field++) {
                for (kind = 0; kind < 3; kind++) {
                    smd_drive_params p;
                    smd_drive_state s, s2;
                    smd_drive_config c = fault_config(mode);
                    smd_drive_in in, in2;
                    smd_drive_out out, out2;
                    plant pl, pl2;
                    double complex u = 0.0, u2 = 0.0, idq = 5.0 * JD;
                    int k, bad_duty = 0, n_fault = 0, n_inject = 0, last_bad = -100000;
                    int rec = 0, late = 0;
                    uint32_t x = 12345u + (uint32_t)(field * 7 + kind);
                    c.speed_loop = field == 7;
                    CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
                    pl.i = 0.0;
                    pl.th = 1.0;
                    pl.w = 300.0;
                    pl2 = pl;
                    smd_drive_reset(&p, &s, R(pl.th), R(pl.w), R(0.0));
                    s2 = s;
                    for (k = 0; k < 3000; k++) {
                        smd_status st;
                        int inject;
                        double e;
                        fill_in(&in, &pl, idq);
                        fill_in(&in2, &pl2, idq);
                        if (pass == 0) {
                            inject = k == 1000;
                        } else {
                            x ^= x << 13;
                            x ^= x >> 17;
                            x ^= x << 5;
                            inject = k > 500 && k < 2800 && x % 115u == 0u;
                        }
                        if (inject) {
                            set_field(&in, field, bad[kind]);
                        }
                        st = smd_drive_step(&p, &s, &in, &out);
                        (void)smd_drive_step(&p, &s2, &in2, &out2);
                        if (pass == 0 && kind == 0 && inject) {
                            tab_st[field] = (int)st;
                        }
                        bad_duty += !duties_ok(out.d_abc);
                        if (inject) {
                            int reads = used(mode, field, c.speed_loop);
                            n_inject++;
                            n_fault += reads ? (st == SMD_ERR_FAULT &&
                                                out.fault == (uint32_t)SMD_FAULT_INPUT)
                                             : (st == SMD_OK && out.fault == 0u);
                            last_bad = k;
                        }
                        plant_step(&pl, u);
                        u = realised(out.d_abc);
                        plant_step(&pl2, u2);
                        u2 = realised(out2.d_abc);
                        e = cabs(pl.i - pl2.i);
                        if (e > 0.05) {
                            if (k - last_bad > (mode >= MODE_PI ? 100 : 20)) late++;
                            if (k - last_bad > rec) rec = k - last_bad;
                        }
                    }
                    CHECK_INT(bad_duty, 0);
                    CHECK_INT(n_fault, n_inject); /* each bad sample as stated */
                    if (n_fault != n_inject) {
                        printf("      mode %d, %s = %g: %d of %d bad samples not as stated\n", mode,
                               FIELD[field], (double)bad[kind], n_inject - n_fault, n_inject);
                    }
                    CHECK(n_inject >= 1);
                    CHECK_INT(late, 0);
                    if (late != 0) {
                        printf("      mode %d, %s = %g: %d samples off the undisturbed run "
                               "later than 20 samples after a bad one\n",
                               mode, FIELD[field], (double)bad[kind], late);
                    }
                    worst_rec = rec > worst_rec ? rec : worst_rec;
                    if (pass == 0 && kind == 0) {
                        tab_rec[field] = rec;
                    }
                }
            }
        }
        printf("      %4d", mode);
        for (field = 0; field < N_FIELDS; field++) {
            printf("    %2d / %3d", tab_st[field], tab_rec[field]);
        }
        printf("\n");
        printf("    mode %d: back within 0.05 A of the undisturbed run at most %d samples "
               "after a bad input\n", mode, worst_rec);
    }
}

/* An overcurrent sample latches SMD_FAULT_OVERCURRENT: the safe state
 * (duties 0.5; pwm_off with SMD_SAFE_PWM_OFF) for every later sample, good
 * ones included, until smd_drive_clear_faults; then a reset restarts the
 * drive and it tracks again (within 0.15 A from 20 ms after the restart,
 * from the zero vector's short-circuit current of ~20 A: the dead-time
 * compensation on this plant without dead time leaves a 0.1 A ripple). Undervoltage and overvoltage latch the same
 * way, each its own bit. */
static void test_latched_trips(void)
{
    int trip;
    for (trip = 0; trip < 3; trip++) {
        smd_drive_params p;
        smd_drive_state s;
        smd_drive_config c = fault_config(MODE_ROBUST);
        smd_drive_in in;
        smd_drive_out out;
        plant pl;
        double complex u = 0.0, idq = 5.0 * JD;
        const uint32_t bit = trip == 0 ? (uint32_t)SMD_FAULT_OVERCURRENT
                             : trip == 1 ? (uint32_t)SMD_FAULT_UNDERVOLTAGE
                                         : (uint32_t)SMD_FAULT_OVERVOLTAGE;
        int k, n_safe = 0, n_ok_after = 0;
        c.i_trip = R(20.0);
        c.u_dc_min = R(300.0);
        c.u_dc_max = R(700.0);
        c.safe_state = SMD_SAFE_PWM_OFF;
        CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
        start_at(&p, &s, &pl, 300.0);
        for (k = 0; k < 2000; k++) {
            smd_status st;
            fill_in(&in, &pl, idq);
            if (k == 500) {
                if (trip == 0) in.i_a = R(25.0);
                if (trip == 1) in.u_dc = R(250.0);
                if (trip == 2) in.u_dc = R(750.0);
            }
            if (k == 1000) {
                smd_drive_clear_faults(&s);
                smd_drive_reset(&p, &s, R(pl.th), R(pl.w), R(0.0)); /* flying restart */
            }
            st = smd_drive_step(&p, &s, &in, &out);
            if (k < 500) {
                CHECK(k < 400 || (st == SMD_OK && out.fault == 0u && out.pwm_off == 0));
            } else if (k < 1000) {
                /* (the zero vector short-circuits the spinning machine: its
                 * current may trip the overcurrent too) */
                n_safe += st == SMD_ERR_FAULT && (out.fault & bit) == bit && out.pwm_off == 1 &&
                          out.d_abc[0] == R(0.5) && out.d_abc[1] == R(0.5) &&
                          out.d_abc[2] == R(0.5) &&
                          (smd_drive_get_view(&p, &s).fault & bit) == bit;
            } else if (k >= 1200) {
                n_ok_after += st == SMD_OK && out.fault == 0u && cabs(plant_idq(&pl) - idq) < 0.15;
            }
            plant_step(&pl, u);
            u = realised(out.d_abc);
        }
        CHECK_INT(n_safe, 500);
        CHECK_INT(n_ok_after, 800); /* 20 ms after the restart from ~20 A */
    }
}

/* Loss of lock (sensorless, SMDO position), two ways (lock_samples = 50):
 * - a rotor that stops dead at sample 3000 (the plant's speed set to 0):
 *   its EMF vanishes while the estimate still says 300 rad/s; the angle
 *   derived from the EMF that is left, noise and the decaying estimate,
 *   jumps by more than 45 deg in a sample within the SMDO's filter time
 *   (w_c T = 0.15 a sample, ~20 samples to a third), which latches at once
 *   (issue 21; before it, the 50 implausible samples of the EMF check:
 *   ~60 samples); within 200 samples, with SMD_FAULT_ANGLE_JUMP reported;
 * - an estimate that stays smooth but implausible (psi_r_hat, which only
 *   the check reads in this mode, raised 4x at sample 3000: the EMF estimate
 *   a quarter of |w_hat| psi_r_hat, below 1/lock_ratio): after exactly
 *   lock_samples samples in a row, 3049 (the count of quarter samples
 *   reaches 4 x 50 on the 50th), with no jump.
 * No false alarm before, while the drive tracks. */
static void run_lost_lock(int stop, int *first, int *jump, int *false_alarm,
                          uint32_t *latched)
{
    smd_drive_params p;
    smd_drive_state s;
    smd_drive_config c = fault_config(MODE_SENSORLESS);
    smd_drive_in in;
    smd_drive_out out;
    plant pl;
    double complex u = 0.0, idq = 5.0 * JD;
    int k;
    c.lock_samples = 50;
    c.lock_ratio = R(3.0);
    c.w_lock_min = R(30.0);
    CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
    pl.i = 0.0;
    pl.th = 1.0;
    pl.w = 300.0;
    *first = -1;
    *jump = 0;
    *false_alarm = 0;
    smd_drive_reset(&p, &s, R(pl.th), R(pl.w), R(0.0));
    for (k = 0; k < 4000; k++) {
        if (k == 3000 && !stop) p.psi_r_hat *= R(4.0);
        fill_in(&in, &pl, idq);
        (void)smd_drive_step(&p, &s, &in, &out);
        if (k < 3000 && out.fault != 0u) (*false_alarm)++;
        if (k >= 3000 && *first < 0 && (out.fault & (uint32_t)SMD_FAULT_LOST_LOCK)) {
            *first = k;
            *jump = (out.fault & (uint32_t)SMD_FAULT_ANGLE_JUMP) != 0u;
        }
        if (k == 3000 && stop) pl.w = 0.0;
        plant_step(&pl, u);
        u = realised(out.d_abc);
    }
    *latched = smd_drive_get_view(&p, &s).fault;
}

static void test_lost_lock(void)
{
    int first, jump, false_alarm;
    uint32_t latched;
    run_lost_lock(1, &first, &jump, &false_alarm, &latched);
    printf("    rotor stopped: loss of lock declared %d samples after (angle jump: %d)\n",
           first - 3000, jump);
    CHECK_INT(false_alarm, 0);
    CHECK(first > 3000 && first <= 3200);
    CHECK_INT(jump, 1);
    CHECK(latched == (uint32_t)SMD_FAULT_LOST_LOCK);
    run_lost_lock(0, &first, &jump, &false_alarm, &latched);
    printf("    EMF implausible: loss of lock declared %d samples after (angle jump: %d)\n",
           first - 3000, jump);
    CHECK_INT(false_alarm, 0);
    CHECK_INT(first, 3049);
    CHECK_INT(jump, 0);
    CHECK(latched == (uint32_t)SMD_FAULT_LOST_LOCK);
}

/* Protection settings out of range name themselves (SMD_ERR_PROTECTION),
 * and the return to I/f needs a sensorless source (SMD_ERR_COMBINATION). */
/* the next value of the real type up and down */
#ifdef SMD_REAL_DOUBLE
#define NEXT_UP(x) nextafter((x), HUGE_VAL)
#define NEXT_DOWN(x) nextafter((x), -HUGE_VAL)
#else
#define NEXT_UP(x) nextafterf((x), HUGE_VALF)
#define NEXT_DOWN(x) nextafterf((x), -HUGE_VALF)
#endif

/* The sample a drive at 300 rad/s (robust DBPC, encoder) gives after 20
 * good ones, with one input of the last set to v: its fault bits. */
static uint32_t edge_fault(smd_drive_config c, int field, smd_real v, smd_real v2)
{
    smd_drive_params p;
    smd_drive_state s;
    smd_drive_in in;
    smd_drive_out out;
    plant pl;
    double complex u = 0.0, idq = 5.0 * JD;
    int k;
    CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
    start_at(&p, &s, &pl, 300.0);
    for (k = 0; k <= 20; k++) {
        fill_in(&in, &pl, idq);
        if (k == 20) {
            set_field(&in, field, v);
            if (field == 0) {
                in.i_b = v2; /* (i_c = -i_a - i_b) */
            }
        }
        (void)smd_drive_step(&p, &s, &in, &out);
        CHECK(k == 20 || out.fault == 0u);
        plant_step(&pl, u);
        u = realised(out.d_abc);
    }
    return out.fault;
}

/* The trips and the input ranges at their edges (the step tests its inputs
 * as bit patterns first, inputs_plain, and runs the full checks only beyond
 * them): a phase current at i_trip does not trip and the next float up
 * does, the third phase's too (i_a and i_b each below the trip); the DC
 * link at u_dc_min and u_dc_max does not and the next floats out do; with
 * the trips off, a current at the range's 1e5 A passes and the next float
 * up is an input fault, while a third phase's 1.2e5 A from two in range is
 * neither; a DC link of +0 or -0 is an input fault. */
static void test_trip_edges(void)
{
    smd_drive_config c = fault_config(MODE_ROBUST);
    const uint32_t OC = (uint32_t)SMD_FAULT_OVERCURRENT, UV = (uint32_t)SMD_FAULT_UNDERVOLTAGE,
                   OV = (uint32_t)SMD_FAULT_OVERVOLTAGE, IN = (uint32_t)SMD_FAULT_INPUT;
    c.i_trip = R(20.0);
    c.u_dc_min = R(300.0);
    c.u_dc_max = R(700.0);
    CHECK_INT(edge_fault(c, 0, R(20.0), R(0.0)), 0);
    CHECK_INT(edge_fault(c, 0, NEXT_UP(R(20.0)), R(0.0)), OC);
    CHECK_INT(edge_fault(c, 0, R(-20.0), R(0.0)), 0);
    CHECK_INT(edge_fault(c, 0, NEXT_DOWN(R(-20.0)), R(0.0)), OC);
    CHECK_INT(edge_fault(c, 0, R(10.0), R(10.0)), 0);
    CHECK_INT(edge_fault(c, 0, NEXT_UP(R(10.0)), NEXT_UP(R(10.0))), OC); /* (i_c: 20 + its ulp) */
    CHECK_INT(edge_fault(c, 6, R(300.0), R(0.0)), 0);
    CHECK_INT(edge_fault(c, 6, NEXT_DOWN(R(300.0)), R(0.0)), UV);
    CHECK_INT(edge_fault(c, 6, R(700.0), R(0.0)), 0);
    CHECK_INT(edge_fault(c, 6, NEXT_UP(R(700.0)), R(0.0)), OV);
    c.i_trip = R(0.0);
    c.u_dc_min = R(0.0);
    c.u_dc_max = R(0.0);
    CHECK_INT(edge_fault(c, 0, R(1e5), R(0.0)), 0);
    CHECK_INT(edge_fault(c, 0, NEXT_UP(R(1e5)), R(0.0)), IN);
    CHECK_INT(edge_fault(c, 0, R(6e4), R(6e4)), 0);
    CHECK_INT(edge_fault(c, 6, R(1e5), R(0.0)), 0);
    CHECK_INT(edge_fault(c, 6, NEXT_UP(R(1e5)), R(0.0)), IN);
    CHECK_INT(edge_fault(c, 6, R(0.0), R(0.0)), IN);
    CHECK_INT(edge_fault(c, 6, R(-0.0), R(0.0)), IN);
}

static void test_protection_settings(void)
{
    smd_drive_params p;
    smd_drive_config c;
    c = fault_config(MODE_SENSORLESS);
    c.i_trip = R(-1.0);
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_PROTECTION);
    c = fault_config(MODE_SENSORLESS);
    c.u_dc_min = R(600.0);
    c.u_dc_max = R(500.0);
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_PROTECTION);
    c = fault_config(MODE_SENSORLESS);
    c.safe_state = 2;
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_PROTECTION);
    c = fault_config(MODE_SENSORLESS);
    c.lock_samples = 10;
    c.lock_ratio = R(1.0);
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_PROTECTION);
    c = fault_config(MODE_SENSORLESS);
    c.w_if_enter = R(300.0); /* not below w_handover = 201 */
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_PROTECTION);
    c = fault_config(MODE_CONVENTIONAL);
    c.w_if_enter = R(100.0);
    CHECK_INT(smd_drive_init(&p, &c), SMD_ERR_COMBINATION);
    c = fault_config(MODE_SENSORLESS);
    c.w_if_enter = R(100.0);
    CHECK_INT(smd_drive_init(&p, &c), SMD_OK);
}

int main(void)
{
    RUN_TEST(test_bad_inputs);
    RUN_TEST(test_latched_trips);
    RUN_TEST(test_trip_edges);
    RUN_TEST(test_lost_lock);
    RUN_TEST(test_protection_settings);
    return smdt_summary("test_faults");
}

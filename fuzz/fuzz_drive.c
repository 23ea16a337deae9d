/*
 * libFuzzer target: the drive (smd_drive_init, smd_drive_reset,
 * smd_drive_step, smd_drive_get_view; smd_drive_clear_faults when the header
 * has it) on a configuration and an input sequence decoded from the fuzz
 * input (fuzz.h).
 *
 * Input: the configuration (fz_drive_config), the reset (theta0, w0, i_q0),
 * then operations until the input ends (at most FZ_MAX_STEPS steps):
 *   op % 5 == 0  one step on raw inputs (10 reals)
 *   op % 5 == 1  set one parameter of the synthetic source (below)
 *   op % 5 == 2  1 + u8 steps of the synthetic source
 *   op % 5 == 3  reset again (theta0, w0, i_q0)
 *   op % 5 == 4  clear the latched faults (when the drive has them); torque
 *                mode (smd_drive_set_torque_in) on when the op's bit 3 is set
 * The synthetic source is a machine turning at w with current i_d + j i_q
 * in its rotor frame: theta advances by w T_sp each step, the phase currents
 * follow (i_1 = (1 + k1) i_2 with the LCL filter), the encoder reads theta
 * and w, the DC link u_dc; references w_ref and i_dq_ref.
 *
 * Checked: no crash, no undefined behaviour, no out-of-bounds access (the
 * observer tables are malloc'ed to their exact size), the status is one the
 * core knows, every step's duties are finite and in [0, 1], and (with the
 * fault word) a step reports a fault exactly when it returns an error, with
 * the safe state's duties 0.5.
 */
#include "fuzz.h"

#define FZ_MAX_STEPS 4000

typedef struct synth {
    double theta, w, i_d, i_q, k1, u_dc, w_ref, id_ref, iq_ref;
} synth;

static void synth_set(synth *y, fz *f)
{
    switch (fz_u8(f) % 9) {
    case 0: y->theta = fz_real(f, -4.0, 4.0); break;
    case 1: y->w = fz_real(f, -3e4, 3e4); break;
    case 2: y->i_d = fz_real(f, -100.0, 100.0); break;
    case 3: y->i_q = fz_real(f, -100.0, 100.0); break;
    case 4: y->k1 = fz_real(f, -1.0, 1.0); break;
    case 5: y->u_dc = fz_real(f, -100.0, 1000.0); break;
    case 6: y->w_ref = fz_real(f, -3e4, 3e4); break;
    case 7: y->id_ref = fz_real(f, -100.0, 100.0); break;
    default: y->iq_ref = fz_real(f, -100.0, 100.0); break;
    }
}

static void synth_inputs(synth *y, double T, smd_drive_in *in)
{
    const double a = 2.0943951023931957; /* 2 pi / 3 */
    double c = cos(y->theta), s = sin(y->theta);
    double re = y->i_d * c - y->i_q * s, im = y->i_d * s + y->i_q * c;
    double ib = re * cos(a) + im * sin(a); /* Re(i e^{-j 2pi/3}) */
    in->i_a = (smd_real)re;
    in->i_b = (smd_real)ib;
    in->i1_a = (smd_real)((1.0 + y->k1) * re);
    in->i1_b = (smd_real)((1.0 + y->k1) * ib);
    in->theta_enc = (smd_real)y->theta;
    in->w_enc = (smd_real)y->w;
    in->u_dc = (smd_real)y->u_dc;
    in->w_ref = (smd_real)y->w_ref;
    in->i_dq_ref = smd_c((smd_real)y->id_ref, (smd_real)y->iq_ref);
    y->theta += y->w * T;
    if (isfinite(y->theta)) {
        y->theta = remainder(y->theta, 6.283185307179586);
    }
}

static void check_out(smd_status st, const smd_drive_out *out)
{
    int k;
    FZ_CHECK((int)st >= 0 && (int)st <= 64); /* a status of the core */
    /* The lead's fault handling has landed (commit 290ff95, "every step
     * returns finite duties in [0, 1]"): the duties are checked. */
    for (k = 0; k < 3; k++) {
        FZ_CHECK(isfinite(out->d_abc[k]) && out->d_abc[k] >= SMD_R(0.0) &&
                 out->d_abc[k] <= SMD_R(1.0));
    }
#if FZ_FAULT_API
    /* smd_drive.h: a step with a fault bit returns SMD_ERR_FAULT (or
     * SMD_ERR_NONFINITE for an internal one) and the safe state (duties
     * 0.5); one without returns SMD_OK; the warnings and events
     * (SMD_FAULT_WARNINGS) are reported by a step that runs normally; so is
     * the cause (lost lock, failed start) that the sample of an automatic
     * restart reports with SMD_FAULT_RESTART: the drive runs on, restarted */
    uint32_t stops = out->fault & ~(uint32_t)SMD_FAULT_WARNINGS;
    if (out->fault & (uint32_t)SMD_FAULT_RESTART) {
        stops &= ~(uint32_t)(SMD_FAULT_LOST_LOCK | SMD_FAULT_START);
    }
    FZ_CHECK((stops != 0u) == (st != SMD_OK));
    if (stops != 0u) {
        FZ_CHECK(st == SMD_ERR_FAULT || st == SMD_ERR_NONFINITE);
        for (k = 0; k < 3; k++) {
            FZ_CHECK(out->d_abc[k] == SMD_R(0.5));
        }
    } else {
        FZ_CHECK(out->pwm_off == 0);
    }
#endif
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz f = {data, size};
    smd_drive_config cfg;
    fz_tables tab;
    smd_drive_params p;
    smd_drive_state s;
    smd_drive_in in;
    smd_drive_out out;
    synth y;
    smd_status st;
    int steps = 0;
    smd_real theta0, w0, i_q0;

    fz_drive_config(&f, &cfg, &tab);
    memset(&p, 0, sizeof p);
    st = smd_drive_init(&p, &cfg);
    fz_use((double)st);
    FZ_TRACEF("drive: current %d position %d start %d lcl %d: init %d\n", cfg.current,
              cfg.position, cfg.start, cfg.lcl, (int)st);
    if (st != SMD_OK) {
        fz_tables_free(&tab);
        return 0;
    }
    theta0 = fz_r(&f, -4.0, 4.0);
    w0 = fz_r(&f, -3e4, 3e4);
    i_q0 = fz_r(&f, -50.0, 50.0);
    memset(&s, 0, sizeof s);
    smd_drive_reset(&p, &s, theta0, w0, i_q0);
    memset(&y, 0, sizeof y);
    y.theta = (double)theta0;
    y.w = (double)w0;
    y.w_ref = (double)w0;
    y.u_dc = 540.0;
#if FZ_FAULT_API
    {
        /* the start duties (the steady state of the start): finite, in [0, 1] */
        smd_real d0[3];
        int j;
        smd_drive_start_duties(&p, &s, (smd_real)y.u_dc, d0);
        for (j = 0; j < 3; j++) {
            FZ_CHECK(d0[j] >= SMD_R(0.0) && d0[j] <= SMD_R(1.0));
        }
    }
#endif

    while (fz_more(&f) && steps < FZ_MAX_STEPS) {
        uint8_t op = fz_u8(&f);
        switch (op % 5) {
        case 0:
            memset(&in, 0, sizeof in);
            in.i_a = fz_r(&f, -100.0, 100.0);
            in.i_b = fz_r(&f, -100.0, 100.0);
            in.i1_a = fz_r(&f, -100.0, 100.0);
            in.i1_b = fz_r(&f, -100.0, 100.0);
            in.theta_enc = fz_r(&f, -4.0, 4.0);
            in.w_enc = fz_r(&f, -3e4, 3e4);
            in.u_dc = fz_r(&f, -100.0, 1000.0);
            in.w_ref = fz_r(&f, -3e4, 3e4);
            in.i_dq_ref = fz_c(&f, 100.0);
            memset(&out, 0, sizeof out);
            st = smd_drive_step(&p, &s, &in, &out);
            check_out(st, &out);
            steps++;
            break;
        case 1:
            synth_set(&y, &f);
            break;
        case 2: {
            int n = 1 + fz_u8(&f), k;
            for (k = 0; k < n && steps < FZ_MAX_STEPS; k++) {
                memset(&in, 0, sizeof in);
                synth_inputs(&y, (double)p.T_sp, &in);
                memset(&out, 0, sizeof out);
                st = smd_drive_step(&p, &s, &in, &out);
                check_out(st, &out);
                steps++;
            }
            break;
        }
        case 3:
            theta0 = fz_r(&f, -4.0, 4.0);
            w0 = fz_r(&f, -3e4, 3e4);
            i_q0 = fz_r(&f, -50.0, 50.0);
            smd_drive_reset(&p, &s, theta0, w0, i_q0);
            break;
        default:
#if FZ_FAULT_API
            smd_drive_clear_faults(&s);
#endif
            /* torque mode on or off (step 4's coast), by the op's bit 3 */
            smd_drive_set_torque_in(&s, (op >> 3) & 1);
            break;
        }
        {
            smd_drive_view v = smd_drive_get_view(&p, &s);
            fz_use_view(&v);
        }
    }
    FZ_TRACEF("drive: %d steps, last status %d, d = %g %g %g, phase %d\n", steps, (int)st,
              (double)out.d_abc[0], (double)out.d_abc[1], (double)out.d_abc[2], s.phase);
    fz_tables_free(&tab);
    return 0;
}

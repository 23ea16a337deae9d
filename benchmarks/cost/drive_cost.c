/*
 * Host harness for benchmarks/vs_motulator.py: instructions per control step
 * of smd_drive_step in each mode, counted with valgrind's callgrind (inclusive
 * cost of the noinline wrappers / N, as benchmarks/cost/obs_cost.c does for
 * yao2022 Table VI), and sizeof of the controller structs.
 *
 *   drive_cost        run N steps of each mode (under callgrind)
 *   drive_cost sizes  print "name bytes" for the parameter and state structs
 *
 * Configuration: the yang2018 defaults of smodrive (ControllerCfg() with the
 * Table I motor, T_sp = 100 us, speed PI at 60 rad/s, dead-time compensation
 * 2 us): the example configuration (smodrive/smd_example.h) with those
 * changed. Inputs: a steady state at 1500 r/min (628.3 electrical rad/s) with
 * the rated-load current 6.4 A on the q axis, a little ripple, so that every
 * block of the mode runs its normal path (the sensorless mode after handover).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "smodrive/smd_drive.h"
#include "smodrive/smd_example.h"

#define N 1000

static smd_drive_config config(int mode)
{
    smd_drive_config c;
    const float b = 1.5f * 16.0f * 0.4f / 0.012f; /* 1.5 n_p^2 psi / J */
    /* yang2018's conventional, robust and sensorless drives */
    static const int current[3] = {SMD_CC_DBPC, SMD_CC_ROBUST_DBPC, SMD_CC_ROBUST_DBPC};
    static const int position[3] = {SMD_POS_ENCODER, SMD_POS_ENCODER, SMD_POS_SMDO_EMF};
    smd_example_drive_config(&c); /* Table I machine, T_sp = 100 us, the SMDO of Table I */
    c.current = current[mode];
    c.position = position[mode];
    c.k_p_w = 2.0f * 60.0f / b;
    c.k_i_w = 60.0f * 60.0f / b;
    c.speed_loop = 1;
    c.w_lpf = 100.0f;
    c.w_hys = 5.0f;
    c.w_max = 3000.0f * 0.10471976f * 4.0f;
    c.t_dead_comp = 2e-6f;
    c.i_dtc = 0.3f;
    return c;
}

/* The inputs are computed before the counted calls, so the wrappers' inclusive
 * counts hold smd_drive_step alone (plus a call). */
static smd_drive_in inputs[N];

static void make_inputs(void)
{
    const float w = 628.3185f, T = 100e-6f;
    int k;
    for (k = 0; k < N; k++) {
        const float th = w * T * (float)k;
        const float iq = 6.37f + 0.05f * (float)(k % 7);
        /* i_ab = j iq e^{j theta}: i_alpha = -iq sin, i_beta = iq cos */
        const float ia = -iq * sinf(th), i_beta = iq * cosf(th);
        inputs[k].i_a = ia;
        inputs[k].i_b = -0.5f * ia + 0.8660254f * i_beta;
        inputs[k].theta_enc = smd_wrap_pi(th);
        inputs[k].w_enc = w;
        inputs[k].u_dc = 540.0f;
        inputs[k].w_ref = w;
        inputs[k].i_dq_ref = smd_c(0.0f, 0.0f);
    }
}

/* One wrapper a mode so that callgrind reports each separately. */
__attribute__((noinline)) smd_status cost_conventional(const smd_drive_params *p,
                                                        smd_drive_state *s,
                                                        const smd_drive_in *in, smd_drive_out *o)
{
    return smd_drive_step(p, s, in, o);
}
__attribute__((noinline)) smd_status cost_robust(const smd_drive_params *p, smd_drive_state *s,
                                                  const smd_drive_in *in, smd_drive_out *o)
{
    return smd_drive_step(p, s, in, o);
}
__attribute__((noinline)) smd_status cost_sensorless(const smd_drive_params *p,
                                                      smd_drive_state *s,
                                                      const smd_drive_in *in, smd_drive_out *o)
{
    return smd_drive_step(p, s, in, o);
}

static int sizes(void)
{
#define SZ(t) printf("%s %u\n", #t, (unsigned)sizeof(t))
    SZ(smd_drive_params);
    SZ(smd_drive_state);
    SZ(smd_drive_config);
    SZ(smd_smdo_state);
    SZ(smd_emf_pos_state);
    SZ(smd_pi_state);
    SZ(smd_lcl_smo_params);
    SZ(smd_lcl_smo_state);
    SZ(smd_lcl_model);
    SZ(smd_pll_state);
#undef SZ
    return 0;
}

int main(int argc, char **argv)
{
    typedef smd_status (*fn)(const smd_drive_params *, smd_drive_state *, const smd_drive_in *,
                             smd_drive_out *);
    static const fn wrappers[3] = {cost_conventional, cost_robust, cost_sensorless};
    smd_real sink = 0.0f;
    int mode, k, bad = 0;
    if (argc > 1 && strcmp(argv[1], "sizes") == 0) {
        return sizes();
    }
    make_inputs();
    for (mode = 0; mode < 3; mode++) {
        smd_drive_params p;
        smd_drive_state s;
        smd_drive_config c = config(mode);
        if (smd_drive_init(&p, &c) != SMD_OK) {
            fprintf(stderr, "init failed for mode %d\n", mode);
            return 1;
        }
        smd_drive_reset(&p, &s, 0.0f, 628.3185f, 6.37f);
        for (k = 0; k < N; k++) {
            smd_drive_out out;
            if (wrappers[mode](&p, &s, &inputs[k], &out) != SMD_OK) {
                bad++;
            }
            sink += out.d_abc[0];
        }
    }
    printf("%g %d\n", (double)sink, bad);
    return 0;
}

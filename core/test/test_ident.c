/*
 * Commissioning, R_s and the inverter's drop (smd_ident.h), against a plant
 * the test does not see: a stator at standstill along the alpha axis, solved
 * exactly over each sample (i(T) = e^{-RT/L} (i - u/R) + u/R), fed with the
 * voltage the duties realise one sample later, less the inverter's drop u_0
 * against the current's direction, with zero-current clamping (a current
 * that would cross zero stays there); the ADC adds uniform noise and a
 * 12-bit quantiser over +-25 A.
 */
#include <math.h>
#include <stdint.h>

#include "smd_test.h"
#include "smodrive/smd_ident.h"

typedef struct rl_plant {
    double R, L, u_0, T, u_dc, noise, i;
    uint32_t seed;
} rl_plant;

static double adc(rl_plant *pl)
{
    double q = 50.0 / 4096.0;
    double x = pl->i + pl->noise * smdt_urand(&pl->seed, -1.7320508, 1.7320508);
    return q * floor(x / q + 0.5);
}

static void rl_step(rl_plant *pl, double u_cmd)
{
    double e = exp(-pl->R / pl->L * pl->T);
    double sg = pl->i > 0.0 ? 1.0 : (pl->i < 0.0 ? -1.0 : (u_cmd > 0.0 ? 1.0 : -1.0));
    double u = u_cmd - pl->u_0 * sg;
    double i = e * (pl->i - u / pl->R) + u / pl->R;
    pl->i = (i * sg < 0.0) ? 0.0 : i; /* clamped at zero */
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
    double u_next = 0.0, u_now = 0.0;
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
        rl_step(pl, u_now);
        u_now = u_next;
        u_next = realised_alpha(d, pl->u_dc);
        if (s->phase == SMD_IDENT_DONE || s->phase == SMD_IDENT_FAILED) {
            return k + 1;
        }
    }
    return k;
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
    const double Rs[2] = {2.25, 0.05}, Ls[2] = {23.45e-3, 0.5e-3}, U0[2] = {14.4, 2.0};
    const double noise[2] = {0.02, 0.05}, it[2] = {4.0, 20.0};
    int c;
    for (c = 0; c < 2; c++) {
        smd_ident_rs_params p;
        smd_ident_rs_state s;
        smd_ident_rs_config cfg = config(it[c]);
        rl_plant pl = {0};
        int n, bad;
        pl.R = Rs[c];
        pl.L = Ls[c];
        pl.u_0 = U0[c];
        pl.T = 1e-4;
        pl.u_dc = 540.0;
        pl.noise = noise[c];
        pl.seed = 12345u + (uint32_t)c;
        CHECK_INT(smd_ident_rs_init(&p, &cfg), SMD_OK);
        n = run(&p, &s, &pl, &bad);
        printf("    R %.3f ohm: R_s %.5f (%+.3f %%), u_0 %.3f V (%+.2f %%), R^2 %.7f, %.2f s\n",
               Rs[c], (double)s.R_s, 100.0 * ((double)s.R_s / Rs[c] - 1.0), (double)s.u_0,
               100.0 * ((double)s.u_0 / U0[c] - 1.0), (double)s.r2, n * 1e-4);
        CHECK_INT(s.outcome, SMD_IDENT_OK);
        CHECK(fabs((double)s.R_s / Rs[c] - 1.0) < 0.005);
        CHECK(fabs((double)s.u_0 / U0[c] - 1.0) < 0.01);
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

int main(void)
{
    RUN_TEST(test_rs_and_drop);
    RUN_TEST(test_outcomes);
    RUN_TEST(test_settings);
    return smdt_summary("ident");
}

/*
 * The online R_s / psi_r tracker (smd_rls.h) on synthetic data: an SPMSM at
 * constant speed w whose d-axis current follows the tracker's square wave
 * (reaching it in two samples) at a constant i_q, with the voltage of each
 * interval [k-1, k) from the model the tracker fits (yang2018 eq. (1) in the
 * stationary frame, currents averaged over the interval, the EMF at its
 * middle). The tracker must recover R_s and psi_r to rounding; with its
 * inductance 10 % wrong, R_s within 1 % (the inductance's share telescopes
 * over each half period, and its constant part at speed, dL w i_q, is the
 * d-axis line's intercept); the samples the drive marks as not applied
 * whole must not count; a square wave lost in the noise must leave R_s.
 * With an observer's angle (smd_rls_set_observer), which the square wave
 * turns back and forth, the fit in the line through the angle's means over
 * whole periods must recover R_s where the fit in the angle given reads it
 * far off; intervals near a phase current's zero crossing, whose voltage
 * the dead-time compensation misses, must not count with the band set
 * (smd_rls_set_band).
 */
#include <math.h>
#include <stdint.h>

#include "smd_test.h"
#include "smodrive/smd_rls.h"

#define T_SP 1e-4
#define R_TRUE 2.25
#define L_TRUE 0.02345
#define PSI_TRUE 0.4
#define W_E 300.0
#define I_Q 3.0
/* (one failure reported, not one a sample) */
#define CHECK_SILENT_INJ(x, ref)                                                          \
    do {                                                                                  \
        if ((double)(x) != (double)(smd_real)(ref)) {                                     \
            CHECK((double)(x) == (double)(smd_real)(ref));                                \
            return;                                                                       \
        }                                                                                 \
    } while (0)

typedef struct run_opts {
    double L_hat, noise, i_inj, bad_u; /* bad_u: voltage error on samples marked not whole */
    int n;
    double t_dc; /* smd_rls_set_dead_time's, s (0: not called) */
    int observer; /* smd_rls_set_observer's */
    double jump;  /* the angle given: the rotor's + jump x the square wave's sign, rad */
    double band, bad_zero; /* smd_rls_set_band's (0: not called); a voltage error along
                            * the current on intervals within 0.3 A of a zero crossing */
    double R_hi; /* smd_rls_set_range(0, R_hi) (0: not called) */
} run_opts;

/* the d-axis current at sample k: it follows the tracker's square wave
 * (n_half samples a half, + first) half-way each sample */
static double current_d(int k, double i_inj, int n_half, double *i_d)
{
    const double target = ((k / n_half) % 2 == 0) ? i_inj : -i_inj;
    *i_d += 0.5 * (target - *i_d);
    return *i_d;
}

/* 1 when a phase current of (i_re, i_im) is within 0.3 A of zero */
static int near_zero(double i_re, double i_im)
{
    const double x = 0.5 * i_re, y = 0.8660254037844386 * i_im;
    return fabs(i_re) < 0.3 || fabs(x - y) < 0.3 || fabs(x + y) < 0.3;
}

static void run(const run_opts *o, smd_rls_state *s)
{
    enum { N_HALF = 200 };
    smd_rls_params p;
    double i_d = 0.0, id_next, th, i_re, i_im;
    uint32_t seed = 7u;
    int k;
    CHECK_INT(smd_rls_init(&p, (smd_real)T_SP, (smd_real)o->L_hat, (smd_real)o->i_inj,
                           SMD_R(0.3), N_HALF, SMD_R(10.0), SMD_R(1.0), SMD_R(0.3)),
              SMD_OK);
    if (o->t_dc > 0.0) {
        CHECK_INT(smd_rls_set_dead_time(&p, (smd_real)o->t_dc), SMD_OK);
    }
    CHECK_INT(smd_rls_set_observer(&p, o->observer), SMD_OK);
    if (o->band > 0.0) {
        CHECK_INT(smd_rls_set_band(&p, (smd_real)o->band), SMD_OK);
    }
    if (o->R_hi > 0.0) {
        CHECK_INT(smd_rls_set_range(&p, SMD_R(0.0), (smd_real)o->R_hi), SMD_OK);
    }
    smd_rls_reset(&p, s);
    id_next = current_d(0, o->i_inj, N_HALF, &i_d);
    for (k = 0; k < o->n; k++) {
        /* i(k) and i(k+1); the voltage of [k, k+1) the model gives */
        const double id_k = id_next, th_k = 0.3 + W_E * T_SP * k;
        const double th_m = th_k + 0.5 * W_E * T_SP;
        double j_re, j_im, u_re, u_im;
        const int whole = (k % 37) != 0;
        id_next = current_d(k + 1, o->i_inj, N_HALF, &i_d);
        th = th_k + W_E * T_SP;
        i_re = id_k * cos(th_k) - I_Q * sin(th_k);
        i_im = id_k * sin(th_k) + I_Q * cos(th_k);
        j_re = id_next * cos(th) - I_Q * sin(th);
        j_im = id_next * sin(th) + I_Q * cos(th);
        u_re = R_TRUE * 0.5 * (i_re + j_re) + L_TRUE * (j_re - i_re) / T_SP -
               W_E * PSI_TRUE * sin(th_m);
        u_im = R_TRUE * 0.5 * (i_im + j_im) + L_TRUE * (j_im - i_im) / T_SP +
               W_E * PSI_TRUE * cos(th_m);
        if (!whole) {
            u_re += o->bad_u;
            u_im -= o->bad_u;
        }
        if (near_zero(i_re, i_im) || near_zero(j_re, j_im)) {
            /* (along the mean current: a clamped phase's residual) */
            const double m_re = 0.5 * (i_re + j_re), m_im = 0.5 * (i_im + j_im);
            const double a = o->bad_zero / sqrt(m_re * m_re + m_im * m_im);
            u_re += a * m_re;
            u_im += a * m_im;
        }
        /* the injection the tracker asks for at k is the one the current follows */
        CHECK_SILENT_INJ(smd_rls_injection(&p, s), ((k / N_HALF) % 2 == 0) ? o->i_inj
                                                                          : -o->i_inj);
        smd_rls_step(&p, s,
                     smd_c((smd_real)(i_re + o->noise * smdt_urand(&seed, -1.7320508,
                                                                   1.7320508)),
                           (smd_real)i_im),
                     smd_c((smd_real)u_re, (smd_real)u_im), whole,
                     (smd_real)(th_k + (((k / N_HALF) % 2 == 0) ? o->jump : -o->jump)),
                     (smd_real)W_E, 1);
    }
}

static void test_exact_model(void)
{
    run_opts o = {L_TRUE, 0.0, 1.0, 0.0, 20000, 0.0, 0, 0.0, 0.0, 0.0, 0.0};
    smd_rls_state s;
    run(&o, &s);
    CHECK_CLOSE(s.R_hat, R_TRUE, 2e-3 * R_TRUE);
    CHECK_CLOSE(s.psi_hat, PSI_TRUE, 2e-3 * PSI_TRUE);
    CHECK((double)s.R_se >= 0.0 && (double)s.R_se < 0.01 * R_TRUE);
}

static void test_wrong_inductance(void)
{
    run_opts o = {1.1 * L_TRUE, 0.0, 1.0, 0.0, 20000, 0.0, 0, 0.0, 0.0, 0.0, 0.0};
    smd_rls_state s;
    run(&o, &s);
    CHECK_CLOSE(s.R_hat, R_TRUE, 0.01 * R_TRUE);
    CHECK_CLOSE(s.psi_hat, PSI_TRUE, 0.01 * PSI_TRUE);
}

static void test_voltage_not_whole_does_not_count(void)
{
    /* 50 V on one sample in 37: counted, it would move R_s by volts per amp */
    run_opts o = {L_TRUE, 0.0, 1.0, 50.0, 20000, 0.0, 0, 0.0, 0.0, 0.0, 0.0};
    smd_rls_state s;
    run(&o, &s);
    CHECK_CLOSE(s.R_hat, R_TRUE, 2e-3 * R_TRUE);
    CHECK_CLOSE(s.psi_hat, PSI_TRUE, 2e-3 * PSI_TRUE);
}

static void test_lost_in_noise(void)
{
    /* a 1 mA square wave under 0.1 A of current noise: R_s stays at R0 */
    run_opts o = {L_TRUE, 0.1, 1e-3, 0.0, 20000, 0.0, 0, 0.0, 0.0, 0.0, 0.0};
    smd_rls_state s;
    run(&o, &s);
    CHECK_CLOSE(s.R_hat, 1.0, 0.0);
    CHECK((double)s.R_se > 0.05 * R_TRUE);
}

/* The dead time the drive compensates: R_hat is the slope over (1 - slope
 * t_dc / (2 L_s_hat)), the slope kept as R_slope, and psi_r fitted with the
 * slope (the same bits as without the correction). The exact model's slope
 * is R_s itself, so the corrected value is off by the factor, 1 + 0.48 %
 * at t_dc = T_SP here: the correction applied, not a value from a plant. */
static void test_dead_time_correction(void)
{
    run_opts o0 = {L_TRUE, 0.0, 1.0, 0.0, 20000, 0.0, 0, 0.0, 0.0, 0.0, 0.0};
    run_opts o1 = {L_TRUE, 0.0, 1.0, 0.0, 20000, T_SP, 0, 0.0, 0.0, 0.0, 0.0};
    smd_rls_state s0, s1;
    double k;
    run(&o0, &s0);
    run(&o1, &s1);
    k = (double)s0.R_hat * T_SP / (2.0 * L_TRUE);
    CHECK((double)s1.R_slope == (double)s0.R_hat);
    CHECK_CLOSE(s1.R_hat, (double)s0.R_hat / (1.0 - k), 1e-5 * R_TRUE);
    CHECK(k > 0.004 && k < 0.006);
    CHECK((double)s1.psi_hat == (double)s0.psi_hat);
}

/* The square wave turns an observer's angle with it (dR i_d / (w psi_r)
 * for a resistance dR above the observer's model): 0.005 rad here. In that
 * frame the d axis's EMF, -w psi_r sin(jump), follows the square wave and
 * the slope takes w psi_r jump / i_inj = 0.6 ohm (27 %) in; in the line
 * through the angle's means over whole periods it does not. */
static void test_observer_frame(void)
{
    run_opts o = {L_TRUE, 0.0, 1.0, 0.0, 20000, 0.0, 1, 0.005, 0.0, 0.0, 0.0};
    smd_rls_state s;
    run(&o, &s);
    CHECK_CLOSE(s.R_hat, R_TRUE, 5e-3 * R_TRUE);
    CHECK_CLOSE(s.psi_hat, PSI_TRUE, 5e-3 * PSI_TRUE);
    o.observer = 0;
    run(&o, &s);
    CHECK((double)s.R_hat > 1.2 * R_TRUE);
    /* the same frame without the jump: the rotor's angle, to rounding */
    o.observer = 1;
    o.jump = 0.0;
    run(&o, &s);
    CHECK_CLOSE(s.R_hat, R_TRUE, 2e-3 * R_TRUE);
}

/* A residual along the current on intervals near a zero crossing (1 V,
 * half of R_s i_inj; about a third of the intervals) reads as resistance
 * (about 0.1 ohm: its d part 1 V i_d / |i| over those intervals); with the
 * band those intervals do not count. */
static void test_band(void)
{
    run_opts o = {L_TRUE, 0.0, 1.0, 0.0, 20000, 0.0, 1, 0.0, 0.0, 1.0, 0.0};
    smd_rls_state s;
    run(&o, &s);
    CHECK(fabs((double)s.R_hat - R_TRUE) > 0.02 * R_TRUE);
    o.band = 0.3;
    run(&o, &s);
    CHECK_CLOSE(s.R_hat, R_TRUE, 2e-3 * R_TRUE);
    CHECK_CLOSE(s.psi_hat, PSI_TRUE, 2e-3 * PSI_TRUE);
}

/* A fit outside the range set is not taken: R_s stays R0 (1 ohm) and the
 * estimate goes stale after 2 tau (0.6 s, 6,000 samples of the 20,000);
 * with the range holding R_s, it is taken. */
static void test_range(void)
{
    run_opts o = {L_TRUE, 0.0, 1.0, 0.0, 20000, 0.0, 0, 0.0, 0.0, 0.0, 2.0};
    smd_rls_state s;
    smd_rls_params p;
    run(&o, &s);
    CHECK((double)s.R_hat == 1.0);
    CHECK_INT(smd_rls_init(&p, (smd_real)T_SP, (smd_real)L_TRUE, SMD_R(1.0), SMD_R(0.3), 200,
                           SMD_R(10.0), SMD_R(1.0), SMD_R(0.3)), SMD_OK);
    CHECK_INT(smd_rls_stale(&p, &s), 1);
    o.R_hi = 2.5;
    run(&o, &s);
    CHECK_CLOSE(s.R_hat, R_TRUE, 2e-3 * R_TRUE);
    CHECK_INT(smd_rls_stale(&p, &s), 0);
}

static void test_settings(void)
{
    smd_rls_params p;
    const smd_real T = SMD_R(1e-4);
    CHECK_INT(smd_rls_init(&p, T, SMD_R(0.01), SMD_R(1.0), SMD_R(0.3), 100, SMD_R(0.0),
                           SMD_R(1.0), SMD_R(0.1)), SMD_OK);
    CHECK_INT(smd_rls_init(&p, T, SMD_R(0.01), SMD_R(0.0), SMD_R(0.3), 100, SMD_R(0.0),
                           SMD_R(1.0), SMD_R(0.1)), SMD_ERR_RLS);
    CHECK_INT(smd_rls_init(&p, T, SMD_R(0.01), SMD_R(1.0), SMD_R(5e-4), 100, SMD_R(0.0),
                           SMD_R(1.0), SMD_R(0.1)), SMD_ERR_RLS); /* tau < 10 T_sp */
    CHECK_INT(smd_rls_init(&p, T, SMD_R(0.01), SMD_R(1.0), SMD_R(0.3), 1, SMD_R(0.0),
                           SMD_R(1.0), SMD_R(0.1)), SMD_ERR_RLS);
    CHECK_INT(smd_rls_init(&p, T, SMD_R(0.0), SMD_R(1.0), SMD_R(0.3), 100, SMD_R(0.0),
                           SMD_R(1.0), SMD_R(0.1)), SMD_ERR_RLS);
    CHECK_INT(smd_rls_init(&p, T, SMD_R(0.01), (smd_real)NAN, SMD_R(0.3), 100, SMD_R(0.0),
                           SMD_R(1.0), SMD_R(0.1)), SMD_ERR_RLS);
    CHECK_INT(smd_rls_init(0, T, SMD_R(0.01), SMD_R(1.0), SMD_R(0.3), 100, SMD_R(0.0),
                           SMD_R(1.0), SMD_R(0.1)), SMD_ERR_NULL);
    CHECK_INT(smd_rls_init(&p, T, SMD_R(0.01), SMD_R(1.0), SMD_R(0.3), 100, SMD_R(0.0),
                           SMD_R(1.0), SMD_R(0.1)), SMD_OK);
    CHECK_INT(smd_rls_set_dead_time(&p, SMD_R(-1e-6)), SMD_ERR_RLS);
    CHECK_INT(smd_rls_set_dead_time(&p, SMD_R(2.0) * T), SMD_ERR_RLS);
    CHECK_INT(smd_rls_set_dead_time(&p, (smd_real)NAN), SMD_ERR_RLS);
    CHECK_INT(smd_rls_set_dead_time(0, SMD_R(1e-6)), SMD_ERR_NULL);
    CHECK_INT(smd_rls_set_dead_time(&p, SMD_R(0.0)), SMD_OK);
    CHECK_INT(smd_rls_set_band(&p, SMD_R(-1.0)), SMD_ERR_RLS);
    CHECK_INT(smd_rls_set_band(&p, (smd_real)NAN), SMD_ERR_RLS);
    CHECK_INT(smd_rls_set_band(0, SMD_R(1.0)), SMD_ERR_NULL);
    CHECK_INT(smd_rls_set_observer(0, 1), SMD_ERR_NULL);
    CHECK_INT(smd_rls_set_range(&p, SMD_R(2.0), SMD_R(1.0)), SMD_ERR_RLS);
    CHECK_INT(smd_rls_set_range(&p, SMD_R(-1.0), SMD_R(1.0)), SMD_ERR_RLS);
    CHECK_INT(smd_rls_set_range(&p, SMD_R(0.0), (smd_real)NAN), SMD_ERR_RLS);
    CHECK_INT(smd_rls_set_range(0, SMD_R(0.0), SMD_R(1.0)), SMD_ERR_NULL);
    CHECK_INT(smd_rls_set_range(&p, SMD_R(1.0), SMD_R(1.0)), SMD_OK);
}

int main(void)
{
    RUN_TEST(test_exact_model);
    RUN_TEST(test_wrong_inductance);
    RUN_TEST(test_voltage_not_whole_does_not_count);
    RUN_TEST(test_lost_in_noise);
    RUN_TEST(test_dead_time_correction);
    RUN_TEST(test_observer_frame);
    RUN_TEST(test_band);
    RUN_TEST(test_range);
    RUN_TEST(test_settings);
    return smdt_summary("rls");
}

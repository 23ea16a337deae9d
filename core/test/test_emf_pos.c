/*
 * Position and speed from the estimated disturbance, yang2018 eq. (43)-(45),
 * with the negative-speed sign fix and the half-sample angle compensation.
 *
 * Synthetic input: u_d = -j w psi e^{j theta_u} (eq. (43)). Eq. (44) with the
 * sign fix returns theta_u for either sign of w; the core then subtracts
 * w_hat T/2 because it takes u_d_hat^k as the disturbance averaged over
 * [t_k, t_k+1), i.e. at t_k + T/2 (smd_emf_pos.c). So we feed
 * theta_u^k = theta^k + w T/2 and expect theta_hat^k = theta^k.
 *
 * Tolerances: phi = atan2 of a vector rounded to smd_real is within ~2 eps pi
 * (1-2 ulp of atan2 plus the input rounding), so the raw speed of eq. (45)
 * is within 4 eps pi / T (+ the rounding of w itself); the low-pass output is
 * a convex combination of raw values, so the same bound holds for w_hat:
 *   tol_w  = 8 eps pi / T + 8 eps |w|   (0.03 rad/s in float at T = 100 us)
 *   tol_th = 8 eps pi + tol_w T / 2     (~4e-6 rad in float)
 * Without the sign fix the negative-speed angle error would be pi; without
 * the half-sample shift it would be |w| T / 2 = 0.02 rad at 400 rad/s.
 */
#include "smd_test.h"
#include "smodrive/smd_emf_pos.h"

#define TSP 1e-4
#define PSI 0.4
#define WLPF 200.0
#define WHYS 50.0
#define WMAX 3000.0

static double tol_w(double w) { return 8 * SMDT_EPS * PI_D / TSP + 8 * SMDT_EPS * fabs(w); }
static double tol_th(double w) { return 8 * SMDT_EPS * PI_D + tol_w(w) * TSP / 2; }

static smd_cplx ud_of(double w, double theta)
{
    /* eq. (43) at the interval midpoint */
    return smdt_c(-JD * w * PSI * cexp(JD * (theta + 0.5 * w * TSP)));
}

static void test_init_rejects(void)
{
    smd_emf_pos_params p;
    CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(WHYS), R(WMAX)), SMD_OK);
    CHECK_CLOSE(p.a_lpf, 1.0 - exp(-WLPF * TSP), 4 * SMDT_EPS);
    CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(0.0), R(WMAX)), SMD_OK);
    CHECK_INT(smd_emf_pos_init(0, R(TSP), R(WLPF), R(WHYS), R(WMAX)), SMD_ERR_NULL);
    CHECK_INT(smd_emf_pos_init(&p, R(0.0), R(WLPF), R(WHYS), R(WMAX)), SMD_ERR_TS);
    CHECK_INT(smd_emf_pos_init(&p, R(NAN), R(WLPF), R(WHYS), R(WMAX)), SMD_ERR_TS);
    CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(0.0), R(WHYS), R(WMAX)), SMD_ERR_WLPF);
    CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(4.0 / TSP), R(WHYS), R(WMAX)), SMD_ERR_WLPF); /* > pi/T */
    CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(NAN), R(WHYS), R(WMAX)), SMD_ERR_WLPF);
    CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(-1.0), R(WMAX)), SMD_ERR_WHYS);
    CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(NAN), R(WMAX)), SMD_ERR_WHYS);
    /* w_max must exceed w_hys and stay below the Nyquist speed pi/T */
    CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(WHYS), R(WHYS)), SMD_ERR_WMAX);
    CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(WHYS), R(4.0 / TSP)), SMD_ERR_WMAX);
    CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(WHYS), R(NAN)), SMD_ERR_WMAX);
}

/* Speed limit: a true speed beyond w_max gives w_hat = +-w_max exactly. */
static void test_speed_limit(void)
{
    const double speeds[2] = {5000.0, -5000.0};
    int n, k;
    for (n = 0; n < 2; n++) {
        double w = speeds[n], th = 0.0, peak = 0.0;
        smd_emf_pos_params p;
        smd_emf_pos_state s;
        CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(WHYS), R(WMAX)), SMD_OK);
        smd_emf_pos_reset(&s, R(0.0));
        for (k = 0; k < 3000; k++) {
            smd_emf_pos_step(&p, &s, ud_of(w, th));
            peak = fmax(peak, fabs((double)s.w_r_hat));
            th = smdt_wrap(th + w * TSP);
        }
        CHECK_CLOSE(peak, WMAX, 0.0);
        CHECK_CLOSE(s.w_r_hat, w > 0 ? WMAX : -WMAX, 0.0);
    }
}

/* Flying start at the true speed: exact angle from the first sample on, for
 * positive and negative speed (the sign fix), and eq. (45) keeps w_hat = w. */
static void test_angle_both_directions(void)
{
    const double speeds[4] = {400.0, -400.0, 2000.0, -2000.0};
    int n, k;
    for (n = 0; n < 4; n++) {
        double w = speeds[n], th = -2.5, worst = 0.0, worst_w = 0.0;
        smd_emf_pos_params p;
        smd_emf_pos_state s;
        CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(WHYS), R(WMAX)), SMD_OK);
        smd_emf_pos_reset(&s, R(w));
        for (k = 0; k < 2000; k++) {
            double e;
            smd_emf_pos_step(&p, &s, ud_of(w, th));
            e = fabs(smdt_wrap((double)s.theta_r_hat - th));
            worst = e > worst ? e : worst;
            e = fabs((double)s.w_r_hat - w);
            worst_w = e > worst_w ? e : worst_w;
            th = smdt_wrap(th + w * TSP);
        }
        CHECK_CLOSE(worst, 0.0, tol_th(w));
        CHECK_CLOSE(worst_w, 0.0, tol_w(w));
        CHECK_INT(s.dir, w > 0 ? 1 : -1);
        /* the half-sample shift is the only difference from eq. (44) */
        CHECK_CLOSE(smdt_wrap((double)s.theta_r_hat + 0.5 * (double)s.w_r_hat * TSP -
                              atan2((w > 0 ? 1 : -1) * (double)ud_of(w, th - w * TSP).re,
                                    -(w > 0 ? 1 : -1) * (double)ud_of(w, th - w * TSP).im)),
                    0.0, tol_th(w));
    }
}

/* Speed from rest (w_r0 = 0): first-order low-pass of eq. (45),
 * w_hat after n updates = w (1 - (1 - a)^n), a = 1 - exp(-w_lpf T) (the first
 * call only primes phi_prev). The direction comes from w_dir, w_hat filtered
 * again by a first-order low-pass 8 times slower (a_dir = 1 - exp(-w_lpf T/8),
 * updated on every call): for w < 0 it starts at +1 (angle off by pi) and
 * flips at the first call with w_dir < -w_hys; then the angle is exact. The
 * expected flip instant is computed from that definition in double (the
 * threshold is crossed with a margin of > 0.05 rad/s per sample, far above the
 * rounding of w_hat). */
static void test_speed_from_rest(void)
{
    const double speeds[2] = {400.0, -400.0};
    const double a = 1.0 - exp(-WLPF * TSP);
    int n, k;
    for (n = 0; n < 2; n++) {
        double w = speeds[n], th = 1.0;
        int flipped_at = -1;
        smd_emf_pos_params p;
        smd_emf_pos_state s;
        CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(WHYS), R(WMAX)), SMD_OK);
        smd_emf_pos_reset(&s, R(0.0));
        for (k = 1; k <= 3000; k++) {
            smd_emf_pos_step(&p, &s, ud_of(w, th));
            if (k == 3) {
                /* two updates: w (1 - (1-a)^2) ~ 0.04 w, below the band */
                CHECK_CLOSE(s.w_r_hat, w * (1.0 - pow(1.0 - a, 2.0)), tol_w(w));
                CHECK_CLOSE(fabs(smdt_wrap((double)s.theta_r_hat - th)), w > 0 ? 0.0 : PI_D,
                            0.05); /* w_hat != w: shift error (w - w_hat) T/2 < 0.02 */
            }
            if (k == 50) {
                CHECK_CLOSE(s.w_r_hat, w * (1.0 - pow(1.0 - a, 49.0)), tol_w(w));
            }
            if (flipped_at < 0 && s.dir < 0) {
                flipped_at = k;
            }
            th = smdt_wrap(th + w * TSP);
        }
        CHECK_CLOSE(s.w_r_hat, w, tol_w(w));
        CHECK_CLOSE(smdt_wrap((double)s.theta_r_hat - (th - w * TSP)), 0.0, tol_th(w));
        if (w < 0) {
            const double a_dir = 1.0 - exp(-WLPF * TSP / 8.0);
            double w_dir = 0.0;
            int k_exp = -1;
            for (k = 1; k <= 3000 && k_exp < 0; k++) {
                double w_hat = w * (1.0 - pow(1.0 - a, (double)(k - 1)));
                w_dir += a_dir * (w_hat - w_dir);
                if (w_dir < -WHYS) {
                    k_exp = k;
                }
            }
            CHECK(k_exp > 50); /* the slow filter really delays the flip */
            CHECK_INT(flipped_at, k_exp);
        } else {
            CHECK_INT(flipped_at, -1);
        }
    }
}

/* Hysteresis: the direction only changes when the (slowly filtered) speed
 * leaves the band [-w_hys, w_hys]. Started with dir = -1 (w_r0 = -100) and fed a slow forward
 * rotation (+30 rad/s, inside the band), w_hat settles at +30 and dir stays
 * -1 (so the angle is pi off: the price of the band); at +100 rad/s
 * (continuous phase) dir becomes +1 and the angle is exact. Mirror case from
 * dir = +1. (A step of w through zero is not used: it flips the phase of u_d
 * by pi within one sample, which no estimator of eq. (45) can follow.) */
static void test_direction_hysteresis(void)
{
    int sgn;
    for (sgn = -1; sgn <= 1; sgn += 2) {
        smd_emf_pos_params p;
        smd_emf_pos_state s;
        double th = 0.7, w_in = -sgn * 30.0, w_out = -sgn * 100.0;
        int k;
        CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(WHYS), R(WMAX)), SMD_OK);
        smd_emf_pos_reset(&s, R(sgn * 100.0));
        CHECK_INT(s.dir, sgn);
        for (k = 0; k < 3000; k++) {
            smd_emf_pos_step(&p, &s, ud_of(w_in, th));
            th = smdt_wrap(th + w_in * TSP);
        }
        CHECK_CLOSE(s.w_r_hat, w_in, tol_w(w_in));
        CHECK_INT(s.dir, sgn);
        CHECK_CLOSE(fabs(smdt_wrap((double)s.theta_r_hat - (th - w_in * TSP))), PI_D,
                    tol_th(w_in));
        for (k = 0; k < 3000; k++) {
            smd_emf_pos_step(&p, &s, ud_of(w_out, th));
            th = smdt_wrap(th + w_out * TSP);
        }
        CHECK_INT(s.dir, -sgn);
        CHECK_CLOSE(smdt_wrap((double)s.theta_r_hat - (th - w_out * TSP)), 0.0, tol_th(w_out));
    }
}

/* A non-finite input keeps the previous estimates. */
static void test_nonfinite_input(void)
{
    smd_emf_pos_params p;
    smd_emf_pos_state s;
    smd_real th0, w0;
    int d0;
    CHECK_INT(smd_emf_pos_init(&p, R(TSP), R(WLPF), R(WHYS), R(WMAX)), SMD_OK);
    smd_emf_pos_reset(&s, R(300.0));
    smd_emf_pos_step(&p, &s, ud_of(300.0, 0.5));
    smd_emf_pos_step(&p, &s, ud_of(300.0, 0.5 + 300.0 * TSP));
    th0 = s.theta_r_hat;
    w0 = s.w_r_hat;
    d0 = s.dir;
    smd_emf_pos_step(&p, &s, smd_c(R(NAN), R(1.0)));
    CHECK_CLOSE(s.theta_r_hat, th0, 0.0);
    CHECK_CLOSE(s.w_r_hat, w0, 0.0);
    CHECK_INT(s.dir, d0);
    smd_emf_pos_step(&p, &s, smd_c(R(INFINITY), R(INFINITY)));
    CHECK(isfinite(s.theta_r_hat) && isfinite(s.w_r_hat));
}

int main(void)
{
    RUN_TEST(test_init_rejects);
    RUN_TEST(test_angle_both_directions);
    RUN_TEST(test_speed_from_rest);
    RUN_TEST(test_direction_hysteresis);
    RUN_TEST(test_speed_limit);
    RUN_TEST(test_nonfinite_input);
    return smdt_summary("test_emf_pos");
}

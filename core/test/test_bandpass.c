/*
 * Band-pass filter, yao2022 eq. (45)-(46).
 *
 * At the centre frequency the filter passes a sinusoid with unity gain and
 * zero phase; at w_n +- Omega/2 (approximately; the exact -3 dB points lie
 * at the warped band edges) the gain is about 1/sqrt(2). Steady state is
 * reached after the transient, whose pole radius sqrt(a2) gives the decay.
 */
#include "smd_test.h"
#include "smodrive/smd_bandpass.h"

static void test_coefficients_hand(void)
{
    /* w_n T = pi/2, Omega T = pi/2: tan(pi/4) = 1 => a2 = 0, a1 = 2 cos(pi/2) / 2 = 0,
     * b0 = 0.5 */
    smd_bandpass f;
    const double T = 1e-4;
    CHECK_INT(smd_bandpass_set(&f, R(PI_D / 2 / T), R(PI_D / 2 / T), R(T)), SMD_OK);
    CHECK_CLOSE(f.a2, 0.0, 10 * SMDT_EPS);
    CHECK_CLOSE(f.a1, 0.0, 10 * SMDT_EPS);
    CHECK_CLOSE(f.b0, 0.5, 10 * SMDT_EPS);
    CHECK_INT(smd_bandpass_set(&f, R(0.0), R(100.0), R(T)), SMD_ERR_LIMIT);
    CHECK_INT(smd_bandpass_set(&f, R(1.01 * PI_D / T), R(100.0), R(T)), SMD_ERR_LIMIT);
    CHECK_INT(smd_bandpass_set(&f, R(100.0), R(-1.0), R(T)), SMD_ERR_LIMIT);
    CHECK_INT(smd_bandpass_set(0, R(100.0), R(10.0), R(T)), SMD_ERR_NULL);
}

/* gain of the filter for a sinusoid at w (after 4000 samples of settling;
 * pole radius sqrt(a2) = 0.92 for Omega = 2 pi 500 rad/s at T = 50 us, so the
 * transient is below 1e-60) measured by correlation over an integer number of
 * samples; returns the complex response */
static double complex response(double w_n, double Om, double T, double w)
{
    smd_bandpass f;
    double complex acc = 0.0;
    int k, n = 0;
    smd_bandpass_set(&f, R(w_n), R(Om), R(T));
    smd_bandpass_reset(&f);
    for (k = 0; k < 8000; k++) {
        double x = cos(w * T * k);
        smd_cplx y = smd_bandpass_step(&f, smd_c(R(x), R(0.0)));
        if (k >= 4000) {
            acc += (double)y.re * cexp(-JD * w * T * k);
            n++;
        }
    }
    return 2.0 * acc / n;
}

static void test_unity_at_centre_and_half_power_at_edges(void)
{
    const double T = 50e-6, w_n = 2 * PI_D * 3333.3, Om = 2 * PI_D * 500.0;
    double complex h = response(w_n, Om, T, w_n);
    /* the correlation over 4000 samples of a non-integer number of periods
     * leaks O(1/(N w T)) of the double-frequency term: 1/(4000 * 1.05) ~ 3e-4 */
    CHECK_CLOSE(cabs(h), 1.0, 1e-3);
    CHECK_CLOSE(carg(h), 0.0, 1e-3);
    /* exact -3 dB edges of this design (Orfanidis' peaking filter): w1, w2
     * with tan(w T/2) pair around the centre; the band is Omega wide to
     * within the warping (Omega T)^2/12 relative = 2e-3 here. Sample at
     * w_n +- Omega/2: gain 1/sqrt(2) within 1 %. */
    CHECK_CLOSE(cabs(response(w_n, Om, T, w_n + 0.5 * Om)), 1.0 / sqrt(2.0), 1e-2);
    CHECK_CLOSE(cabs(response(w_n, Om, T, w_n - 0.5 * Om)), 1.0 / sqrt(2.0), 1e-2);
    /* far from the band: strongly attenuated (one octave up: < 0.2) */
    CHECK(cabs(response(w_n, Om, T, 2.0 * w_n)) < 0.2);
}

int main(void)
{
    RUN_TEST(test_coefficients_hand);
    RUN_TEST(test_unity_at_centre_and_half_power_at_edges);
    return smdt_summary("bandpass");
}

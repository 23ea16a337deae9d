/*
 * Deadbeat predictive current control, yang2018 eq. (7)-(9) and (42).
 *
 * References are computed here in double with C99 complex arithmetic,
 * written directly from the paper's equations.
 *
 * Tolerance of the one-shot comparisons: the output voltage is a sum of terms
 * whose largest magnitude is S = (L/T)(|i_ref| + |i^{k+1}|) + |u| + R|i| +
 * 2|w psi| (the L/T factor amplifies the rounding of the predicted current).
 * Each term carries <= ~8 roundings (plus 1-ulp sin/cos of an argument
 * <= 2 pi), so the error is below ~8 eps S; we allow 16 eps S. With the
 * numbers used, S ~ 5e3 V, i.e. 10 mV in float, while dropping any term of
 * (8)-(9) changes the result by >= R|i| ~ 8 V (the smallest, w T-shift of
 * the EMF angle, 2|w psi| sin(w T/2) ~ 6 V).
 */
#include "smd_test.h"
#include "smodrive/smd_dbpc.h"

/* Table I of yang2018 */
#define LS 23.45e-3
#define RS 2.25
#define PSI 0.4
#define TSP 1e-4

static double complex emf(double w, double psi, double th) { return JD * w * psi * cexp(JD * th); }

static void test_init_rejects(void)
{
    smd_dbpc_params p;
    CHECK_INT(smd_dbpc_init(&p, R(TSP), R(LS), R(RS), R(PSI)), SMD_OK);
    CHECK_INT(smd_dbpc_init(&p, R(TSP), R(LS), R(0.0), R(0.0)), SMD_OK);
    CHECK_INT(smd_dbpc_init(&p, R(0.0), R(LS), R(RS), R(PSI)), SMD_ERR_TS);
    CHECK_INT(smd_dbpc_init(&p, R(1.5), R(LS), R(RS), R(PSI)), SMD_ERR_TS);
    CHECK_INT(smd_dbpc_init(&p, R(NAN), R(LS), R(RS), R(PSI)), SMD_ERR_TS);
    CHECK_INT(smd_dbpc_init(&p, R(TSP), R(0.0), R(RS), R(PSI)), SMD_ERR_L);
    CHECK_INT(smd_dbpc_init(&p, R(TSP), R(11.0), R(RS), R(PSI)), SMD_ERR_L);
    CHECK_INT(smd_dbpc_init(&p, R(TSP), R(NAN), R(RS), R(PSI)), SMD_ERR_L);
    CHECK_INT(smd_dbpc_init(&p, R(TSP), R(LS), R(-0.1), R(PSI)), SMD_ERR_R);
    CHECK_INT(smd_dbpc_init(&p, R(TSP), R(LS), R(INFINITY), R(PSI)), SMD_ERR_R);
    CHECK_INT(smd_dbpc_init(&p, R(TSP), R(LS), R(RS), R(-0.1)), SMD_ERR_PSI);
    CHECK_INT(smd_dbpc_init(&p, R(TSP), R(LS), R(RS), R(NAN)), SMD_ERR_PSI);
    CHECK_INT(smd_dbpc_init(0, R(TSP), R(LS), R(RS), R(PSI)), SMD_ERR_NULL);
}

/* eq. (7), (8), (9) one shot against the double reference, with mismatched
 * estimates (the controller only sees hats) and several operating points. */
static void test_conventional_equations(void)
{
    const double Lh = 0.8 * LS, Rh = 1.3 * RS, psih = 0.9 * PSI;
    unsigned long st = 21;
    smd_dbpc_params p;
    int n;
    CHECK_INT(smd_dbpc_init(&p, R(TSP), R(Lh), R(Rh), R(psih)), SMD_OK);
    for (n = 0; n < 200; n++) {
        double complex i = smdt_rand(&st, -10, 10) + smdt_rand(&st, -10, 10) * JD;
        double complex u = smdt_rand(&st, -300, 300) + smdt_rand(&st, -300, 300) * JD;
        double complex idq = smdt_rand(&st, -5, 5) + smdt_rand(&st, -10, 10) * JD;
        double th = smdt_rand(&st, -PI_D, PI_D);
        double w = smdt_rand(&st, -700, 700);
        /* (8) */
        double complex i1 = i + TSP / Lh * (u - Rh * i - emf(w, psih, th));
        /* (7) with i_dref kept */
        double complex iref2 = idq * cexp(JD * (th + 2.0 * w * TSP));
        /* (9) */
        double complex u1 = Lh * (iref2 - i1) / TSP + Rh * i1 + emf(w, psih, th + w * TSP);
        double S = Lh / TSP * (cabs(iref2) + cabs(i1)) + cabs(u) + Rh * cabs(i) + 2 * fabs(w * psih);
        smd_cplx got_i1 = smd_dbpc_predict(&p, smdt_c(i), smdt_c(u), R(th), R(w));
        smd_cplx got_ref = smd_dbpc_ref_k2(&p, smdt_c(idq), R(th), R(w));
        smd_cplx got_u = smd_dbpc_conventional(&p, smdt_c(i), smdt_c(u), smdt_c(idq), R(th), R(w));
        CHECK_CPLX(got_i1, i1, 16 * SMDT_EPS * (cabs(i) + TSP / Lh * S));
        /* |iref2| = |idq|; angle th + 2wT <= pi + 0.14 rad: 1-ulp sin/cos */
        CHECK_CPLX(got_ref, iref2, 16 * SMDT_EPS * cabs(idq) * 4.0);
        CHECK_CPLX(got_u, u1, 16 * SMDT_EPS * S);
    }
}

/* Steady-state deadbeat property: with the exact Euler plant (3) and exact
 * parameters, the current sampled two instants after a controller step is the
 * reference of that step, i^{k+2} = (i_dref + j i_qref) e^{j(theta^k + 2 w T)},
 * from any initial current, including across reference steps.
 * Tolerance: the controller's voltage error (16 eps S, see above) reaches the
 * current through T/L: 16 eps S T/L ~ 16 eps (|i_ref| + |i|) + ...; the angle
 * theta is handed over wrapped to [-pi, pi) and so carries ~eps*pi of
 * rounding, giving |i_ref| pi eps. Allow 64 eps (2|i_ref|max + |i|max).
 * Negative control: with L_hat = 1.5 L the same error is > 0.1 A. */
static double deadbeat_run(double Lh_factor, double w, int verbose_fail)
{
    smd_dbpc_params p;
    double complex i = 3.0 - 4.0 * JD; /* arbitrary initial current */
    double complex u_k = 0.0;         /* voltage applied during [k, k+1) */
    double complex pending[2] = {0.0, 0.0}; /* reference for k+1 and k+2 */
    double th = 0.3;
    double max_err = 0.0;
    int k;
    (void)verbose_fail;
    if (smd_dbpc_init(&p, R(TSP), R(Lh_factor * LS), R(RS), R(PSI)) != SMD_OK) {
        return INFINITY;
    }
    for (k = 0; k < 400; k++) {
        double complex idq = (k < 100) ? 2.0 * JD : (k < 250 ? -1.0 + 8.0 * JD : 0.5 - 6.0 * JD);
        double th_w = smdt_wrap(th);
        smd_cplx uc = smd_dbpc_conventional(&p, smdt_c(i), smdt_c(u_k), smdt_c(idq), R(th_w), R(w));
        double complex u_next = smdt_z(uc);
        /* check i^k against the reference requested at k-2 */
        if (k >= 2) {
            double e = cabs(i - pending[0]);
            if (e > max_err) {
                max_err = e;
            }
        }
        pending[0] = pending[1];
        pending[1] = idq * cexp(JD * (th + 2.0 * w * TSP));
        /* plant (3), exact parameters: i^{k+1} from u^k */
        i = i + TSP / LS * (u_k - RS * i - emf(w, PSI, th));
        th += w * TSP;
        u_k = u_next;
    }
    return max_err;
}

static void test_conventional_deadbeat(void)
{
    const double tol = 64 * SMDT_EPS * (2 * 8.1 + 8.1);
    CHECK_CLOSE(deadbeat_run(1.0, 400.0, 1), 0.0, tol);
    CHECK_CLOSE(deadbeat_run(1.0, -628.3, 1), 0.0, tol);
    CHECK_CLOSE(deadbeat_run(1.0, 0.0, 1), 0.0, tol);
    /* the check can fail: an inductance mismatch breaks the property */
    CHECK(deadbeat_run(1.5, 400.0, 0) > 0.1);
}

/* eq. (42), by hand: L = 0.01 H, T = 1e-4 s (L/T = 100 ohm), R = 2 ohm,
 * i^{k+1} = 1 + 2j, u_d^{k+1} = 10 - 20j, i_ref^{k+2} = 3 + 1j:
 * 100 (2 - 1j) + 2 (1 + 2j) - (10 - 20j) = 192 - 76j.
 * Tolerance: terms up to 200 V with ~4 roundings (L/T itself is rounded). */
static void test_robust_hand_value(void)
{
    smd_dbpc_params p;
    smd_cplx u;
    CHECK_INT(smd_dbpc_init(&p, R(1e-4), R(0.01), R(2.0), R(0.0)), SMD_OK);
    u = smd_dbpc_robust(&p, smd_c(R(1.0), R(2.0)), smd_c(R(10.0), R(-20.0)),
                        smd_c(R(3.0), R(1.0)));
    CHECK_CPLX(u, 192.0 - 76.0 * JD, 8 * SMDT_EPS * 300.0);
    /* psi_hat does not enter (42) */
    CHECK_INT(smd_dbpc_init(&p, R(1e-4), R(0.01), R(2.0), R(5.0)), SMD_OK);
    u = smd_dbpc_robust(&p, smd_c(R(1.0), R(2.0)), smd_c(R(10.0), R(-20.0)),
                        smd_c(R(3.0), R(1.0)));
    CHECK_CPLX(u, 192.0 - 76.0 * JD, 8 * SMDT_EPS * 300.0);
}

/* eq. (42) is the deadbeat law of model (15): fed the exact i^{k+1} and
 * u_d^{k+1} of an Euler plant L di/dt = u + u_d - R i with
 * u_d = -j w psi e^{j theta}, it gives i^{k+2} = i_ref^{k+2}.
 * Tolerance as for the conventional deadbeat test. */
static void test_robust_deadbeat(void)
{
    smd_dbpc_params p;
    unsigned long st = 5;
    int n;
    CHECK_INT(smd_dbpc_init(&p, R(TSP), R(LS), R(RS), R(0.0)), SMD_OK);
    for (n = 0; n < 200; n++) {
        double complex i1 = smdt_rand(&st, -10, 10) + smdt_rand(&st, -10, 10) * JD;
        double th1 = smdt_rand(&st, -PI_D, PI_D);
        double w = smdt_rand(&st, -700, 700);
        double complex ud1 = -emf(w, PSI, th1);
        double complex iref2 = (smdt_rand(&st, -5, 5) + smdt_rand(&st, -10, 10) * JD) *
                               cexp(JD * (th1 + w * TSP));
        smd_cplx u = smd_dbpc_robust(&p, smdt_c(i1), smdt_c(ud1), smdt_c(iref2));
        double complex i2 = i1 + TSP / LS * (smdt_z(u) + ud1 - RS * i1);
        CHECK_CLOSE(cabs(i2 - iref2), 0.0, 64 * SMDT_EPS * (cabs(iref2) + cabs(i1) + 1.0));
    }
}

int main(void)
{
    RUN_TEST(test_init_rejects);
    RUN_TEST(test_conventional_equations);
    RUN_TEST(test_conventional_deadbeat);
    RUN_TEST(test_robust_hand_value);
    RUN_TEST(test_robust_deadbeat);
    return smdt_summary("test_dbpc");
}

/*
 * Sliding-mode disturbance observer, yang2018 eq. (34)-(39).
 *
 * The reference step is written here in double complex arithmetic directly
 * from the paper (with R_hat in (35), as the header documents):
 *   e_i    = i^k - i_hat^k                                           (20)
 *   e_u    = L (e_i - e_i^{k-1}) / T + u_smo^{k-1} + R e_i^{k-1}      (38)
 *   lambda = lambda_min + |e_u| / L                                  (37)
 *   sgn    = e_i / (|e_i| + rho)                                      (39)
 *   u_smo  = L lambda sgn + (L l - R) e_i                             (34)
 *   i_hat^{k+1} = i_hat + T/L (u + u_d_hat + u_smo - R i_hat)         (35)
 *   u_d_hat^{k+1} = u_d_hat + (j w u_d_hat + w_c u_smo) T             (36)
 * The core runs (36) as printed when smd_smdo_set_euler(p, 1); by default it
 * discretises the rotation of (19) exactly:
 *   u_d_hat^{k+1} = u_d_hat e^{j w T} + w_c T u_smo                    (36')
 * Both are tested.
 */
#include "smd_test.h"
#include "smodrive/smd_smdo.h"

/* Table I of yang2018 (rho = 0.2 A from Sec. IV-C) */
#define LS 23.45e-3
#define RS 2.25
#define PSI 0.4
#define TSP 1e-4
#define LMIN 800.0
#define LGAIN 1200.0
#define WC 1500.0
#define RHO 0.2

typedef struct ref_state {
    double complex i_hat, u_d_hat, e_prev, smo_prev, smo;
    double lambda;
} ref_state;

static void ref_step(ref_state *s, double L, double Rr, double T, double lmin, double l,
                     double wc, double rho, double complex i, double complex u, double w,
                     int euler)
{
    double complex e = i - s->i_hat;
    double complex eu = L * (e - s->e_prev) / T + s->smo_prev + Rr * s->e_prev;
    double lambda = lmin + cabs(eu) / L;
    double complex sgn = e / (cabs(e) + rho);
    double complex smo = L * lambda * sgn + (L * l - Rr) * e;
    double complex i_next = s->i_hat + T / L * (u + s->u_d_hat + smo - Rr * s->i_hat);
    double complex ud_next = euler ? s->u_d_hat + (JD * w * s->u_d_hat + wc * smo) * T
                                   : s->u_d_hat * cexp(JD * w * T) + wc * T * smo;
    s->i_hat = i_next;
    s->u_d_hat = ud_next;
    s->e_prev = e;
    s->smo_prev = smo;
    s->smo = smo;
    s->lambda = lambda;
}

static void test_init_rejects(void)
{
    smd_smdo_params p;
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(LMIN), R(LGAIN), R(WC), R(RHO)), SMD_OK);
    CHECK_INT(smd_smdo_init(0, R(TSP), R(LS), R(RS), R(LMIN), R(LGAIN), R(WC), R(RHO)),
              SMD_ERR_NULL);
    /* each bad parameter with its own status code */
    CHECK_INT(smd_smdo_init(&p, R(0.0), R(LS), R(RS), R(LMIN), R(LGAIN), R(WC), R(RHO)),
              SMD_ERR_TS);
    CHECK_INT(smd_smdo_init(&p, R(NAN), R(LS), R(RS), R(LMIN), R(LGAIN), R(WC), R(RHO)),
              SMD_ERR_TS);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(0.0), R(RS), R(LMIN), R(LGAIN), R(WC), R(RHO)),
              SMD_ERR_L);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(-LS), R(RS), R(LMIN), R(LGAIN), R(WC), R(RHO)),
              SMD_ERR_L);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(-1.0), R(LMIN), R(LGAIN), R(WC), R(RHO)),
              SMD_ERR_R);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(NAN), R(LMIN), R(LGAIN), R(WC), R(RHO)),
              SMD_ERR_R);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(-1.0), R(LGAIN), R(WC), R(RHO)),
              SMD_ERR_LAMBDA);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(INFINITY), R(LGAIN), R(WC), R(RHO)),
              SMD_ERR_LAMBDA);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(LMIN), R(0.0), R(WC), R(RHO)),
              SMD_ERR_L_GAIN);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(LMIN), R(NAN), R(WC), R(RHO)),
              SMD_ERR_L_GAIN);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(LMIN), R(LGAIN), R(0.0), R(RHO)),
              SMD_ERR_WC);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(LMIN), R(LGAIN), R(-WC), R(RHO)),
              SMD_ERR_WC);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(LMIN), R(LGAIN), R(WC), R(0.0)),
              SMD_ERR_RHO);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(LMIN), R(LGAIN), R(WC), R(NAN)),
              SMD_ERR_RHO);
}

/* Stability: the small-error linear loop e^{k+1} = (1 - (l + lambda/rho) T) e^k
 * needs (l + lambda_min/rho) T < 2; the Euler filter needs w_c T < 1. */
static void test_stability_check(void)
{
    smd_smdo_params p;
    /* l T = 1.99 (lambda_min = 0) accepted, 2.01 rejected */
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(0.0), R(19900.0), R(WC), R(RHO)), SMD_OK);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(0.0), R(20100.0), R(WC), R(RHO)),
              SMD_ERR_STABILITY);
    /* lambda_min/rho adds: l = 1200, lambda_min/rho = 20000 -> 2.12 */
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(1000.0), R(LGAIN), R(WC), R(0.05)),
              SMD_ERR_STABILITY);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(1000.0), R(LGAIN), R(WC), R(0.06)),
              SMD_OK); /* (1200 + 16667) 1e-4 = 1.79 */
    /* w_c T = 1.2 rejected, 0.8 accepted */
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(LMIN), R(LGAIN), R(12000.0), R(RHO)),
              SMD_ERR_STABILITY);
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(LMIN), R(LGAIN), R(8000.0), R(RHO)),
              SMD_OK);
}

/* First step by hand: L = 0.01 H, R = 1 ohm, T = 1e-4 s, lambda_min = 100,
 * l = 1000, w_c = 500, rho = 1; i_hat^0 = 0, u_d_hat^0 = 20, w = 1000;
 * i^0 = 3 + 4j, u^0 = 10:
 *   e_i = 3 + 4j (|e_i| = 5), e_u = 100 (3 + 4j) = 300 + 400j, |e_u| = 500
 *   lambda = 100 + 500 / 0.01 = 50100
 *   sgn = (3 + 4j) / 6,  L lambda sgn = 501 (0.5 + 0.6667j) = 250.5 + 334j
 *   u_smo = 250.5 + 334j + (10 - 1)(3 + 4j) = 277.5 + 370j
 *   i_hat^1 = 0.01 (10 + 20 + 277.5 + 370j) = 3.075 + 3.7j
 *   (36) : u_d_hat^1 = 20 + 1e-4 (20000j + 500 (277.5 + 370j)) = 33.875 + 20.5j
 *   (36'): u_d_hat^1 = 20 e^{0.1j} + 0.05 (277.5 + 370j)
 *                    = 19.90008331 + 1.99666833j + 13.875 + 18.5j
 *                    = 33.77508331 + 20.49666833j
 * Tolerance: lambda ~ 5e4 with ~6 roundings -> 8 eps 5e4; voltages ~ 500 V. */
static void test_first_step_by_hand(void)
{
    int euler;
    for (euler = 0; euler < 2; euler++) {
        smd_smdo_params p;
        smd_smdo_state s;
        CHECK_INT(smd_smdo_init(&p, R(1e-4), R(0.01), R(1.0), R(100.0), R(1000.0), R(500.0),
                                R(1.0)),
                  SMD_OK);
        CHECK_INT(p.euler, 0); /* default: exact rotation */
        CHECK_INT(smd_smdo_set_euler(&p, euler), SMD_OK);
        smd_smdo_reset(&s, smd_c(R(0.0), R(0.0)), smd_c(R(20.0), R(0.0)));
        CHECK_INT(smd_smdo_step(&p, &s, smd_c(R(3.0), R(4.0)), smd_c(R(10.0), R(0.0)), R(1000.0)),
                  SMD_OK);
        CHECK_CLOSE(s.lambda, 50100.0, 8 * SMDT_EPS * 5e4);
        CHECK_CPLX(s.u_smo, 277.5 + 370.0 * JD, 8 * SMDT_EPS * 500.0);
        CHECK_CPLX(s.i_s_hat, 3.075 + 3.7 * JD, 8 * SMDT_EPS * 5.0);
        CHECK_CPLX(s.u_d_hat, euler ? 33.875 + 20.5 * JD : 33.77508331 + 20.49666833 * JD,
                   8 * SMDT_EPS * 50.0 + 1e-8);
        CHECK_CPLX(s.e_i_prev, 3.0 + 4.0 * JD, 0.0);
    }
    {
        smd_smdo_params p;
        CHECK_INT(smd_smdo_init(&p, R(1e-4), R(0.01), R(1.0), R(100.0), R(1000.0), R(500.0),
                                R(1.0)),
                  SMD_OK);
        CHECK_INT(smd_smdo_set_euler(&p, 2), SMD_ERR_MODE);
        CHECK_INT(smd_smdo_set_euler(0, 1), SMD_ERR_NULL);
    }
}

/* One step from random states (including the history e_i^{k-1}, u_smo^{k-1}
 * used by (38)) against the double reference, with mismatched estimates.
 * Tolerance (16 eps times the largest term of each equation):
 *   S_u   = (L/T)(|i| + |i_hat| + |e_prev|) + |u_smo_prev| + R |e_prev|  (e_u)
 *   lambda: 16 eps (lambda + S_u / L)
 *   u_smo : 16 eps (S_u + L lambda (1 + (|i| + |i_hat|)/(|e_i| + rho))
 *                   + (L l + R)(|i| + |i_hat|))
 *   i_hat : 16 eps (|i_hat| + T/L (|u| + |u_d_hat| + S_smo + R |i_hat|))
 *   u_d   : 16 eps (|u_d_hat| (1 + |w| T) + T w_c S_smo)
 * (the (|i|+|i_hat|)/(|e_i|+rho) factor is the rounding of e_i = i - i_hat
 * amplified by the smoothed sign). Dropping the history terms of (38), the
 * R_hat term of (35), or the j w rotation in (36) changes the outputs by
 * 10^3..10^6 times these tolerances (float). */
static void test_step_vs_reference(void)
{
    const double L = 1.3 * LS, Rr = 0.7 * RS;
    unsigned long st = 77;
    smd_smdo_params p;
    int n, euler;
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(L), R(Rr), R(LMIN), R(LGAIN), R(WC), R(RHO)), SMD_OK);
    for (n = 0; n < 1000; n++) {
        euler = n % 4 >= 2;
        CHECK_INT(smd_smdo_set_euler(&p, euler), SMD_OK);
        smd_smdo_state s;
        ref_state r;
        double complex i, u;
        double w, S_u, S_smo, ai, ah;
        r.i_hat = smdt_rand(&st, -10, 10) + smdt_rand(&st, -10, 10) * JD;
        r.u_d_hat = smdt_rand(&st, -300, 300) + smdt_rand(&st, -300, 300) * JD;
        r.e_prev = smdt_rand(&st, -2, 2) + smdt_rand(&st, -2, 2) * JD;
        r.smo_prev = smdt_rand(&st, -300, 300) + smdt_rand(&st, -300, 300) * JD;
        /* small and large current errors (inside and outside the layer rho) */
        i = r.i_hat + ((n % 2) ? 0.05 : 2.0) * (smdt_rand(&st, -1, 1) + smdt_rand(&st, -1, 1) * JD);
        u = smdt_rand(&st, -300, 300) + smdt_rand(&st, -300, 300) * JD;
        w = smdt_rand(&st, -700, 700);
        /* the state as the implementation sees it (rounded to smd_real) */
        s.i_s_hat = smdt_c(r.i_hat);
        s.u_d_hat = smdt_c(r.u_d_hat);
        s.e_i_prev = smdt_c(r.e_prev);
        s.u_smo_prev = smdt_c(r.smo_prev);
        s.u_smo = smd_c(R(0.0), R(0.0));
        s.lambda = R(0.0);
        r.i_hat = smdt_z(s.i_s_hat);
        r.u_d_hat = smdt_z(s.u_d_hat);
        r.e_prev = smdt_z(s.e_i_prev);
        r.smo_prev = smdt_z(s.u_smo_prev);
        i = smdt_z(smdt_c(i));
        u = smdt_z(smdt_c(u));
        w = (double)R(w);
        ai = cabs(i);
        ah = cabs(r.i_hat);
        S_u = L / TSP * (ai + ah + cabs(r.e_prev)) + cabs(r.smo_prev) + Rr * cabs(r.e_prev);
        {
            double complex u_d0 = r.u_d_hat, i_h0 = r.i_hat;
            ref_step(&r, L, Rr, TSP, LMIN, LGAIN, WC, RHO, i, u, w, euler);
            S_smo = S_u + L * r.lambda * (1.0 + (ai + ah) / (cabs(r.e_prev) + RHO)) +
                    (L * LGAIN + Rr) * (ai + ah);
            CHECK_INT(smd_smdo_step(&p, &s, smdt_c(i), smdt_c(u), R(w)), SMD_OK);
            CHECK_CLOSE(s.lambda, r.lambda, 16 * SMDT_EPS * (r.lambda + S_u / L));
            CHECK_CPLX(s.u_smo, r.smo, 16 * SMDT_EPS * S_smo);
            CHECK_CPLX(s.i_s_hat, r.i_hat,
                       16 * SMDT_EPS * (ah + TSP / L * (cabs(u) + cabs(u_d0) + S_smo + Rr * cabs(i_h0))));
            CHECK_CPLX(s.u_d_hat, r.u_d_hat,
                       16 * SMDT_EPS * (cabs(u_d0) * (1.0 + fabs(w) * TSP) + TSP * WC * S_smo));
            CHECK_CPLX(s.e_i_prev, r.e_prev, 4 * SMDT_EPS * (ai + ah));
        }
    }
}

/* Euler plant of model (15) with exact L, R and a rotating disturbance
 * u_d^k = -j w psi e^{j theta^k}; returns max |u_d_hat^k / u_d^k - 1| over
 * the last 20 ms of a 0.3 s run, and the max |i^k - i_hat^k| there. */
static double converge_run(double T, double w, int euler, double *i_err)
{
    smd_smdo_params p;
    smd_smdo_state s;
    double complex i = 0.0;
    double th = 0.4;
    double worst = 0.0, worst_i = 0.0;
    int k, n = (int)(0.3 / T + 0.5), n_tail = (int)(0.02 / T + 0.5);
    *i_err = INFINITY;
    if (smd_smdo_init(&p, R(T), R(LS), R(RS), R(LMIN), R(LGAIN), R(WC), R(RHO)) != SMD_OK ||
        smd_smdo_set_euler(&p, euler) != SMD_OK) {
        return INFINITY;
    }
    smd_smdo_reset(&s, smd_c(R(0.0), R(0.0)), smd_c(R(0.0), R(0.0)));
    for (k = 0; k < n; k++) {
        double complex ud = -JD * w * PSI * cexp(JD * th);
        double complex u = 120.0 * cexp(JD * (th + 1.2)); /* any applied voltage */
        if (k >= n - n_tail) {
            double e = cabs(smdt_z(s.u_d_hat) / ud - 1.0);
            double ei = cabs(i - smdt_z(s.i_s_hat));
            worst = e > worst ? e : worst;
            worst_i = ei > worst_i ? ei : worst_i;
        }
        if (smd_smdo_step(&p, &s, smdt_c(i), smdt_c(u), R(w)) != SMD_OK) {
            return INFINITY;
        }
        i = i + T / LS * (u + ud - RS * i);
        th = smdt_wrap(th + w * T);
    }
    *i_err = worst_i;
    return worst;
}

/* G(j w_r) = 1 of eq. (33), discrete limit, eq. (36) as printed. In steady
 * state the filter (36) advances u_d_hat by (1 + j w T) per sample while u_d
 * advances by e^{j w T}; the mismatch F = e^{jwT} - 1 - jwT ~ -(wT)^2/2 must be
 * supplied by u_smo, which enters (36) with gain ~ w_c T, so
 *   |G_discrete(e^{jwT}) - 1| ~ |F| / (w_c T) = w^2 T / (2 w_c).
 * (0.53 % at w = 400 rad/s, 1.3 % at w = 628 rad/s for T = 100 us.)
 * Checks: the error is below twice this leading-order value (the factor 2
 * covers the O(w/(l + lambda/rho)) ~ 10 % correction of the gain), it shrinks
 * ~4x when T is divided by 4 (first order in T: G -> 1 as T -> 0), and the
 * estimated current follows the plant current within the boundary layer rho.
 * Float rounding: |u_d| >= 160 V, errors ~1e-4 V, i.e. < 1e-6 relative. */
static void test_convergence_euler(void)
{
    const double speeds[3] = {400.0, 628.3, -628.3};
    int n;
    for (n = 0; n < 3; n++) {
        double w = speeds[n];
        double ei1, ei4;
        double lead1 = w * w * TSP / (2.0 * WC);
        double e1 = converge_run(TSP, w, 1, &ei1);
        double e4 = converge_run(TSP / 4.0, w, 1, &ei4);
        CHECK_CLOSE(e1, 0.0, 2.0 * lead1);
        CHECK_CLOSE(e4, 0.0, 2.0 * lead1 / 4.0);
        CHECK(e1 > 0.5 * lead1); /* the discretisation error is really there */
        CHECK_CLOSE(e1 / e4, 4.0, 1.0);
        CHECK_CLOSE(ei1, 0.0, RHO);
        printf("    (36)  w = %7.1f rad/s: |G-1| = %.4g (T), %.4g (T/4); w^2 T/(2 w_c) = %.4g;"
               " max|e_i| = %.3g A\n", w, e1, e4, lead1, ei1);
    }
}

/* Exact rotation (36') (the default): for the Euler plant the fixed point is
 * u_d_hat = u_d, u_smo = 0, i_hat = i exactly, i.e. G(e^{jwT}) = 1 at any T.
 * Only rounding remains: each step rounds u_d_hat (~4 eps |u_d|) and the
 * current error e_i = i - i_hat (~eps |i|, |i| < 30 A here), which u_smo
 * turns into ~L (lambda/rho + l) eps |i| ~ 120 ohm * eps |i| of voltage; the
 * loop forgets with time constant 1/(w_c T) ~ 7 samples. So
 * |G - 1| <~ 7 (4 eps + 120 * 30 eps / |u_d|) < 200 eps for |u_d| >= 160 V;
 * we allow 1000 eps (1.2e-4 in float), still 40x below the (36) error. */
static void test_convergence_exact_rotation(void)
{
    const double speeds[4] = {400.0, 628.3, -628.3, 2000.0};
    int n;
    for (n = 0; n < 4; n++) {
        double w = speeds[n], ei;
        double e = converge_run(TSP, w, 0, &ei);
        CHECK_CLOSE(e, 0.0, 1000 * SMDT_EPS);
        CHECK_CLOSE(ei, 0.0, 1000 * SMDT_EPS * 30.0);
        printf("    (36') w = %7.1f rad/s: |G-1| = %.3g, max|e_i| = %.3g A\n", w, e, ei);
    }
}

/* Non-finite data: status SMD_ERR_NONFINITE and, as the header documents,
 * the state is reset, i.e. every state field is finite afterwards, so that the
 * next finite sample is processed normally (status SMD_OK). Checked for a
 * non-finite measurement and for a non-finite speed. */
static int state_finite(const smd_smdo_state *s)
{
    return smd_cfinite(s->i_s_hat) && smd_cfinite(s->u_d_hat) && smd_cfinite(s->e_i_prev) &&
           smd_cfinite(s->u_smo_prev) && smd_cfinite(s->u_smo) && isfinite(s->lambda);
}

static void test_nonfinite_measurement(void)
{
    smd_smdo_params p;
    smd_smdo_state s;
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(LMIN), R(LGAIN), R(WC), R(RHO)), SMD_OK);
    smd_smdo_reset(&s, smd_c(R(1.0), R(0.0)), smd_c(R(10.0), R(0.0)));
    CHECK_INT(smd_smdo_step(&p, &s, smd_c(R(NAN), R(0.0)), smd_c(R(0.0), R(0.0)), R(100.0)),
              SMD_ERR_NONFINITE);
    CHECK(state_finite(&s));
    /* restarted from the last estimate (the measurement is not usable), the
     * disturbance from zero: the step checks before it writes its state */
    CHECK(s.i_s_hat.re == R(1.0) && s.i_s_hat.im == R(0.0));
    CHECK(s.u_d_hat.re == R(0.0) && s.u_d_hat.im == R(0.0));
    CHECK_INT(smd_smdo_step(&p, &s, smd_c(R(1.0), R(0.0)), smd_c(R(0.0), R(0.0)), R(100.0)),
              SMD_OK);
    CHECK(state_finite(&s));
}

static void test_nonfinite_speed(void)
{
    smd_smdo_params p;
    smd_smdo_state s;
    CHECK_INT(smd_smdo_init(&p, R(TSP), R(LS), R(RS), R(LMIN), R(LGAIN), R(WC), R(RHO)), SMD_OK);
    smd_smdo_reset(&s, smd_c(R(1.0), R(0.0)), smd_c(R(10.0), R(0.0)));
    CHECK_INT(smd_smdo_step(&p, &s, smd_c(R(2.0), R(-1.0)), smd_c(R(0.0), R(0.0)), R(INFINITY)),
              SMD_ERR_NONFINITE);
    CHECK(state_finite(&s));
    /* restarted from the measurement, which is usable */
    CHECK(s.i_s_hat.re == R(2.0) && s.i_s_hat.im == R(-1.0));
    CHECK_INT(smd_smdo_step(&p, &s, smd_c(R(1.0), R(0.0)), smd_c(R(0.0), R(0.0)), R(100.0)),
              SMD_OK);
    CHECK(state_finite(&s));
}

int main(void)
{
    RUN_TEST(test_init_rejects);
    RUN_TEST(test_stability_check);
    RUN_TEST(test_first_step_by_hand);
    RUN_TEST(test_step_vs_reference);
    RUN_TEST(test_convergence_euler);
    RUN_TEST(test_convergence_exact_rotation);
    RUN_TEST(test_nonfinite_measurement);
    RUN_TEST(test_nonfinite_speed);
    return smdt_summary("test_smdo");
}

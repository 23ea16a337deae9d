/*
 * libFuzzer target: the LCL-filter observers of yao2022 on a table of models
 * decoded from the input (n rows malloc'ed to their exact size):
 *   sliding-mode observer  smd_lcl_smo_init, smd_lcl_smo_reset,
 *                          smd_lcl_smo_model, smd_lcl_smo_step,
 *                          smd_lcl_smo_reach, smd_lcl_smo_predict,
 *                          smd_lcl_smo_reframe, smd_lcl_smo_theta_err
 *   linear observer        smd_linobs_init, smd_linobs_reset, smd_linobs_step
 * Input (fuzz.h): the sliding-mode config (T_sp, law, Q1, Q2, bw_rel2,
 * bw_rel3, w_bp_min), the grid (n, w_min, dw), the n rows of both tables
 * (113 and 56 reals), then operations until the input ends:
 *   op % 6 == 0  one step of both observers on raw values
 *   op % 6 == 1  1 + u8 steps on rotating currents and voltage at speed w
 *                (the frame follows the rotation)
 *   op % 6 == 2  reframe by an angle
 *   op % 6 == 3  reset both
 *   op % 6 == 4  model + reach + predict (the halves of a step)
 *   op % 6 == 5  set the rotation (amplitudes, speed)
 *
 * Checked besides the sanitizers: a step returns SMD_OK with a finite state
 * or SMD_ERR_NONFINITE (after a reset); the interpolated model of a table
 * of finite values below 1e38 is finite at any speed.
 */
#include "fuzz.h"

#include "smodrive/smd_lcl_linobs.h"
#include "smodrive/smd_lcl_smo.h"
#include "smodrive/smd_transforms.h"

#define FZ_MAX_STEPS 3000

typedef struct rotation {
    double th, w, T, i1, i2, u;
} rotation;

static int smo_finite(const smd_lcl_smo_state *s)
{
    int k, ok = 1;
    for (k = 0; k < 6; k++) {
        ok = ok && isfinite(s->x_hat[k]);
    }
    return ok && isfinite(s->e_hat[0]) && isfinite(s->e_hat[1]) && isfinite(s->x_c[0]) &&
           isfinite(s->x_c[1]);
}

/* Every value finite and below half the float range: the interpolation
 * a + f (b - a) cannot overflow (a table of +-FLT_MAX entries can, and no
 * observer has one). */
static int table_moderate(const smd_real *t, size_t n)
{
    size_t k;
    for (k = 0; k < n; k++) {
        if (!(isfinite(t[k]) && SMD_FABS(t[k]) <= SMD_R(1e38))) {
            return 0;
        }
    }
    return 1;
}

static void step_both(const smd_lcl_smo_params *ps, smd_lcl_smo_state *ss,
                      const smd_linobs_params *pl, smd_linobs_state *sl, int have_smo,
                      int have_lin, smd_cplx i1, smd_cplx i2, smd_cplx u, smd_real th,
                      smd_real w)
{
    if (have_smo) {
        smd_status st = smd_lcl_smo_step(ps, ss, i1, i2, u, th, w);
        FZ_CHECK(st == SMD_OK || st == SMD_ERR_NONFINITE);
        if (st == SMD_OK) {
            FZ_CHECK(smo_finite(ss));
        }
        fz_use((double)smd_lcl_smo_theta_err(ss, w));
    }
    if (have_lin) {
        smd_status st = smd_linobs_step(pl, sl, i1, i2, u, w);
        int k;
        FZ_CHECK(st == SMD_OK || st == SMD_ERR_NONFINITE);
        for (k = 0; k < 4; k++) {
            fz_use((double)sl->x2[k]);
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz f = {data, size};
    smd_lcl_smo_config cs;
    smd_linobs_config cl;
    smd_lcl_smo_params ps;
    smd_linobs_params pl;
    smd_lcl_smo_state ss;
    smd_linobs_state sl;
    fz_tables tab;
    rotation r;
    smd_real T_sp;
    int n, have_smo, have_lin, steps = 0, finite_table;
    const size_t nsmo = sizeof(smd_lcl_model) / sizeof(smd_real);

    memset(&cs, 0, sizeof cs);
    memset(&cl, 0, sizeof cl);
    memset(&tab, 0, sizeof tab);
    T_sp = fz_r(&f, 1e-6, 1e-3);
    fz_smd_lcl_smo_config(&f, &cs);
    fz_lcl_grid(&f, &cs, &cl, &tab);
    n = tab.n;
    FZ_CHECK(smd_lcl_smo_init(&ps, T_sp, 0) == SMD_ERR_NULL);
    FZ_CHECK(smd_linobs_init(&pl, 0) == SMD_ERR_NULL);
    have_smo = smd_lcl_smo_init(&ps, T_sp, &cs) == SMD_OK;
    have_lin = smd_linobs_init(&pl, &cl) == SMD_OK;
    FZ_TRACEF("lcl_obs: n %d: smo %d lin %d\n", n, have_smo, have_lin);
    if (!have_smo && !have_lin) {
        fz_tables_free(&tab);
        return 0;
    }
    finite_table = have_smo && table_moderate((const smd_real *)tab.smo, (size_t)n * nsmo);
    memset(&ss, 0, sizeof ss);
    memset(&sl, 0, sizeof sl);
    smd_lcl_smo_reset(&ss, fz_r(&f, -4.0, 4.0));
    smd_linobs_reset(&sl);
    r.th = 0.0;
    r.w = 1000.0;
    r.T = have_smo ? (double)ps.T_sp : 1e-4;
    r.i1 = 10.0;
    r.i2 = 9.0;
    r.u = 20.0;

    while (fz_more(&f) && steps < FZ_MAX_STEPS) {
        uint8_t op = fz_u8(&f);
        switch (op % 6) {
        case 0: {
            smd_cplx i1 = fz_c(&f, 100.0), i2 = fz_c(&f, 100.0), u = fz_c(&f, 1e3);
            smd_real th = fz_r(&f, -4.0, 4.0), w = fz_r(&f, -2e4, 2e4);
            step_both(&ps, &ss, &pl, &sl, have_smo, have_lin, i1, i2, u, th, w);
            steps++;
            break;
        }
        case 1: {
            int k, m = 1 + fz_u8(&f);
            for (k = 0; k < m && steps < FZ_MAX_STEPS; k++, steps++) {
                smd_cplx e = smd_c((smd_real)cos(r.th), (smd_real)sin(r.th));
                smd_cplx i1 = smd_cscale(smd_cj(e), (smd_real)r.i1);
                smd_cplx i2 = smd_cscale(smd_cj(e), (smd_real)r.i2);
                smd_cplx u = smd_cscale(smd_cj(e), (smd_real)r.u);
                step_both(&ps, &ss, &pl, &sl, have_smo, have_lin, i1, i2, u, (smd_real)r.th,
                          (smd_real)r.w);
                r.th += r.w * r.T;
                if (isfinite(r.th)) {
                    r.th = remainder(r.th, 6.283185307179586);
                }
            }
            break;
        }
        case 2:
            if (have_smo) {
                smd_lcl_smo_reframe(&ss, fz_r(&f, -3.2, 3.2));
            }
            break;
        case 3:
            smd_lcl_smo_reset(&ss, fz_r(&f, -4.0, 4.0));
            smd_linobs_reset(&sl);
            break;
        case 4:
            if (have_smo) {
                smd_lcl_model m;
                smd_real w = fz_r(&f, -3e4, 3e4);
                size_t k;
                smd_lcl_smo_model(&ps, w, &m);
                if (finite_table && !isnan(w)) {
                    const smd_real *a = (const smd_real *)&m;
                    for (k = 0; k < nsmo; k++) {
                        FZ_CHECK(isfinite(a[k]));
                    }
                }
                smd_cplx i1 = fz_c(&f, 100.0), i2 = fz_c(&f, 100.0);
                smd_lcl_smo_reach(&ps, &ss, &m, i1, i2, w);
                smd_lcl_smo_predict(&m, &ss, fz_c(&f, 1e3));
                steps++;
            }
            break;
        default:
            r.w = fz_real(&f, -2e4, 2e4);
            r.i1 = fz_real(&f, -100.0, 100.0);
            r.i2 = fz_real(&f, -100.0, 100.0);
            r.u = fz_real(&f, -1e3, 1e3);
            break;
        }
    }
    FZ_TRACEF("lcl_obs: %d steps, e_hat = %g %g\n", steps, (double)ss.e_hat[0],
              (double)ss.e_hat[1]);
    fz_tables_free(&tab);
    return 0;
}

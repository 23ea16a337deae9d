/*
 * Host harness for yao2022 Table VI: one call of each real-time part per
 * wrapper, repeated N times, so that valgrind's callgrind can report the
 * instructions per call (inclusive cost of the wrappers / N).
 *   cost_prediction: model interpolation + observer (9) + augmented state (16)
 *   cost_reach:      switching function (18) + reaching law (33)-(35)
 *   cost_pll:        position error (47) + PLL (48)
 * The table is synthetic (its values do not change the instruction path);
 * the speed is 100 kr/min so that both band-pass channels are active.
 */
#include <stdio.h>
#include <stdlib.h>

#include "smodrive/smd_lcl_smo.h"
#include "smodrive/smd_pll.h"

#define NTAB 4
#define N 1000

static smd_lcl_model table[NTAB];

__attribute__((noinline)) void cost_prediction(const smd_lcl_smo_params *p, smd_lcl_smo_state *s,
                                               smd_real w, smd_cplx u)
{
    smd_lcl_model m;
    smd_lcl_smo_model(p, w, &m);
    smd_lcl_smo_predict(&m, s, u);
}

__attribute__((noinline)) void cost_reach(const smd_lcl_smo_params *p, smd_lcl_smo_state *s,
                                          const smd_lcl_model *m, smd_cplx i1, smd_cplx i2,
                                          smd_real w)
{
    smd_lcl_smo_reach(p, s, m, i1, i2, w);
}

__attribute__((noinline)) void cost_pll(const smd_pll_params *p, smd_pll_state *ps,
                                        const smd_lcl_smo_state *s, smd_real w)
{
    smd_pll_step(p, ps, smd_lcl_smo_theta_err(s, w));
}

int main(void)
{
    smd_lcl_smo_params p;
    smd_lcl_smo_state s;
    smd_pll_params pp;
    smd_pll_state ps;
    smd_lcl_model m;
    const smd_real w = 10471.98f; /* 100 kr/min, one pole pair */
    smd_lcl_smo_config oc = {50e-6f, SMD_LCL_SMO_PROPOSED, table, NTAB, 0.0f, 4000.0f,
                             0.5f, 0.5f, 0.2f, 0.2f, 500.0f};
    int k, i;
    float *f = (float *)table;
    for (i = 0; i < (int)(sizeof(table) / sizeof(float)); i++) {
        f[i] = 0.01f * (float)((i * 7919) % 13 - 6);
    }
    if (smd_lcl_smo_init(&p, &oc) != SMD_OK ||
        smd_pll_init(&pp, 50e-6f, 0.1f, 10.0f, 10.0f) != SMD_OK) {
        fprintf(stderr, "init failed\n");
        return 1;
    }
    smd_lcl_smo_reset(&s, 0.0f);
    smd_pll_reset(&ps, 0.0f, w);
    smd_lcl_smo_model(&p, w, &m);
    for (k = 0; k < N; k++) {
        smd_cplx i1 = smd_c(0.1f * (float)(k % 7), 30.0f);
        smd_cplx i2 = smd_c(0.05f * (float)(k % 5), 29.0f);
        cost_reach(&p, &s, &m, i1, i2, w);
        cost_prediction(&p, &s, w, smd_c(-30.0f, 15.0f));
        cost_pll(&pp, &ps, &s, w);
    }
    printf("%g %g\n", (double)s.e_hat[0], (double)ps.w);
    return 0;
}

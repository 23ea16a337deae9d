#include "smodrive/smd_lcl_linobs.h"

smd_status smd_linobs_init(smd_linobs_params *p, const smd_linobs_config *c)
{
    if (p == 0 || c == 0 || c->table == 0) {
        return SMD_ERR_NULL;
    }
    if (c->n < 2 || !smd_in_range(c->w_min, SMD_R(-1e7), SMD_R(1e7)) ||
        !smd_in_pos_range(c->dw, SMD_R(1e7))) {
        return SMD_ERR_TABLE;
    }
    p->table = c->table;
    p->n = c->n;
    p->w_min = c->w_min;
    p->dw = c->dw;
    return SMD_OK;
}

void smd_linobs_reset(smd_linobs_state *s)
{
    int k;
    for (k = 0; k < 4; k++) {
        s->z[k] = SMD_R(0.0);
        s->x2[k] = SMD_R(0.0);
    }
    s->primed = 0;
}

smd_status smd_linobs_step(const smd_linobs_params *p, smd_linobs_state *s, smd_cplx i1_ab,
                           smd_cplx i2_ab, smd_cplx u_ab, smd_real w)
{
    smd_linobs_model m;
    smd_real y[4], u[2], zn[4];
    int i, j;
    smd_table_interp((const smd_real *)p->table,
                     (int)(sizeof(smd_linobs_model) / sizeof(smd_real)), p->n, p->w_min, p->dw,
                     w, (smd_real *)&m);
    y[0] = i1_ab.re;
    y[1] = i1_ab.im;
    y[2] = i2_ab.re;
    y[3] = i2_ab.im;
    u[0] = u_ab.re;
    u[1] = u_ab.im;
    /* eq. (65): x2_hat(k) = z(k) + L y(k) */
    for (i = 0; i < 4; i++) {
        smd_real acc = s->z[i];
        for (j = 0; j < 4; j++) {
            acc += m.L[4 * i + j] * y[j];
        }
        s->x2[i] = acc;
    }
    /* z(k+1) = Theta x2_hat + Ky y + Ku u */
    for (i = 0; i < 4; i++) {
        smd_real acc = m.Ku[2 * i] * u[0] + m.Ku[2 * i + 1] * u[1];
        for (j = 0; j < 4; j++) {
            acc += m.Theta[4 * i + j] * s->x2[j] + m.Ky[4 * i + j] * y[j];
        }
        zn[i] = acc;
    }
    for (i = 0; i < 4; i++) {
        if (!isfinite(zn[i]) || SMD_FABS(zn[i]) > SMD_R(1e12)) {
            smd_linobs_reset(s);
            return SMD_ERR_NONFINITE;
        }
        s->z[i] = zn[i];
    }
    s->primed = 1;
    return SMD_OK;
}

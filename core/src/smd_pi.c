#include "smodrive/smd_pi.h"

smd_status smd_pi_init(smd_pi_params *p, smd_real k_p, smd_real k_i, smd_real T_s,
                       smd_real y_max)
{
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_range(k_p, SMD_R(0.0), SMD_R(1e6))) {
        return SMD_ERR_KP;
    }
    if (!smd_in_range(k_i, SMD_R(0.0), SMD_R(1e9))) {
        return SMD_ERR_KI;
    }
    if (!smd_in_pos_range(T_s, SMD_R(1.0))) {
        return SMD_ERR_TS;
    }
    if (!smd_in_pos_range(y_max, SMD_R(1e9))) {
        return SMD_ERR_LIMIT;
    }
    p->k_p = k_p;
    p->k_i = k_i;
    p->T_s = T_s;
    p->y_max = y_max;
    return SMD_OK;
}

void smd_pi_reset(smd_pi_state *s, smd_real x_i0)
{
    s->x_i = x_i0;
    s->y = x_i0;
}

static smd_real clamp(smd_real x, smd_real lim)
{
    return x > lim ? lim : (x < -lim ? -lim : x);
}

smd_real smd_pi_step(const smd_pi_params *p, smd_pi_state *s, smd_real e)
{
    smd_real x_i = s->x_i + p->k_i * p->T_s * e;
    smd_real y = clamp(p->k_p * e + x_i, p->y_max);
    /* Anti-windup: keep the integrator where the limited output is what the
     * unlimited law would give (back-calculation with unity gain), and never
     * beyond the output range itself. */
    x_i = clamp(y - p->k_p * e, p->y_max);
    if (!isfinite(x_i) || !isfinite(y)) {
        x_i = SMD_R(0.0);
        y = SMD_R(0.0);
    }
    s->x_i = x_i;
    s->y = y;
    return y;
}

#include "smodrive/smd_pll.h"

/* Jury test of the closed loop (z - 1)^3 + N(z), N the numerator of eq. (49),
 * written in the gains so that the tiny margins (P(1) = k_a T^2) are not lost
 * to float rounding. With e0 = k_theta - k_omega T + k_a T^2, the
 * polynomial is z^3 + c2 z^2 + c1 z + c0 with c0 = -1 + e0 and the
 * conditions are P(1) > 0, P(-1) < 0, |c0| < 1 and |c0^2 - 1| > |c0 c2 - c1|,
 * where c0^2 - 1 = A = -2 e0 + e0^2 and c0 c2 - c1 = B with
 * A - B = e0 (k_a T^2 - k_omega T) + k_a T^2 and A + B = e0 (e0 + k_theta - 4) - k_a T^2. */
static int pll_stable(smd_real T, smd_real kt, smd_real kw, smd_real ka)
{
    smd_real kaT2 = ka * T * T;
    smd_real kwT = kw * T;
    smd_real e0 = kt - kwT + kaT2;
    smd_real pm1 = SMD_R(-8.0) + SMD_R(4.0) * kt - SMD_R(2.0) * kwT + kaT2;
    smd_real a_minus_b = e0 * (kaT2 - kwT) + kaT2;
    smd_real a_plus_b = e0 * (e0 + kt - SMD_R(4.0)) - kaT2;
    return kaT2 > SMD_R(0.0) && pm1 < SMD_R(0.0) && e0 > SMD_R(0.0) && e0 < SMD_R(2.0) &&
           a_minus_b < SMD_R(0.0) && a_plus_b < SMD_R(0.0);
}

smd_status smd_pll_init(smd_pll_params *p, smd_real T_sp, smd_real k_theta, smd_real k_omega,
                        smd_real k_a)
{
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_pos_range(T_sp, SMD_R(1.0))) {
        return SMD_ERR_TS;
    }
    if (!smd_in_range(k_theta, SMD_R(0.0), SMD_R(2.0)) ||
        !smd_in_range(k_omega, SMD_R(0.0), SMD_R(1e9)) ||
        !smd_in_range(k_a, SMD_R(0.0), SMD_R(1e12))) {
        return SMD_ERR_KP;
    }
    if (!pll_stable(T_sp, k_theta, k_omega, k_a)) {
        return SMD_ERR_STABILITY;
    }
    p->T_sp = T_sp;
    p->k_theta = k_theta;
    p->k_omega = k_omega;
    p->k_a = k_a;
    return SMD_OK;
}

void smd_pll_reset(smd_pll_state *s, smd_real theta0, smd_real w0)
{
    s->theta = smd_wrap_pi(theta0);
    s->w = w0;
    s->a = SMD_R(0.0);
}

void smd_pll_step(const smd_pll_params *p, smd_pll_state *s, smd_real e)
{
    smd_real th;
    if (!isfinite(e)) {
        e = SMD_R(0.0);
    }
    /* yao2022 eq. (48) */
    th = s->theta + s->w * p->T_sp + p->k_theta * e;
    s->w += s->a * p->T_sp + p->k_omega * e;
    s->a += p->k_a * e;
    s->theta = smd_wrap_pi(th);
}

/* Online tracking of R_s and psi_r (issue 23): recursive least squares
 * with exponential forgetting on the stator voltage equation, with the
 * excitation it needs (a d-axis current square wave).
 *
 * The stator model in the stationary frame, over the interval [k-1, k)
 * (voltage u applied then, currents i(k-1), i(k) measured at its ends):
 *
 *     u - L_s (i(k) - i(k-1)) / T_sp = R_s i_m + j w psi_r e^{j theta_m}
 *
 * with i_m = (i(k-1) + i(k)) / 2 and theta_m = theta_k - w_k T_sp / 2 the
 * middle of the interval (yang2018 eq. (1), SPMSM, written in the
 * stationary frame so that the inductance's rotation term is inside
 * d i / d t). Turned into the rotor frame (y = (...) e^{-j theta_m}):
 *
 *     y_d = R_s i_d + c_d        y_q = R_s i_q + w psi_r
 *
 * c_d takes what a small error of L_s leaves on the d axis at speed
 * (dL w i_q) and a constant inverter error: the d-axis fit is a line.
 * In steady state R_s and psi_r cannot be told apart on the q axis alone,
 * so the tracker asks for a d-axis current that alternates between
 * +i_inj and -i_inj every n_half samples (an SPMSM's torque does not
 * depend on i_d): the slope of y_d over i_d is R_s, and psi_r follows from
 * the q axis with that R_s. Over a half period the inductance's share
 * telescopes (sum (i_k - i_{k-1})(i_k + i_{k-1}) = i_end^2 - i_start^2), so
 * an error of L_s and the current's steps do not bias R_s.
 *
 * An estimate not taken for more than 2 tau is stale (smd_rls_stale; the
 * drive's warning SMD_FAULT_RLS_STALE): no sample counted (the modulator at
 * its limit, the rotor's angle not valid) or the fit could not tell R_s (a
 * square wave lost in the noise). It keeps its last value, which a heating
 * winding has left behind: without the warning such an estimate, 40 % off,
 * read like a good one.
 *
 * The least squares are those of exponential forgetting with factor
 * 1 - alpha (alpha = T_sp / tau): their normal equations are weighted
 * means, updated recursively (the information form of RLS), here with a
 * weight sum so that the first tau is not biased toward zero:
 *
 *     R_s = (W S_iy - M_i M_y) / (W S_ii - M_i^2)
 *     psi_r = (S_wy - R_s S_wi) / S_ww            (only |w| >= w_min)
 *
 * R_s is taken when the fit can tell it: its standard error (the residual
 * variance over 2 / alpha samples, the effective count of the forgetting,
 * and the variance of i_d) within 25 % of it. The formula takes the
 * residual as white; its largest part, the current's noise through
 * L_s di/dt, is a difference and telescopes, so the actual error is several
 * times smaller (Table I at rated speed: R_se 4.5 %, error 1 %). A square
 * wave lost in the noise leaves R_s where it was (R_se says how far the fit
 * is).
 *
 * A sample counts when the drive's angle is the rotor's (valid; the drive
 * passes 0 in the forced phase of an I/f start) and so did the one
 * before. C99, no allocation, single precision by default.
 *
 * It needs the rotor's angle (the drive refuses it with another position
 * source). With the SMDO's angle, a resistance dR above the SMDO's model
 * puts dR i on the disturbance, whose d part turns the angle estimate by
 * about dR i_d / (w psi_r); in that frame the fit reads the SMDO's own R_s
 * (y_d = R_s i_d + dR i_d - dR i_d), and a +40 % rise ended 30 % low. An
 * integral loop correcting the SMDO's R_s from the angle's step at the
 * square wave's edges was tried (2026-11-27) and left out: within 2 % on
 * two motors, it ran away on the 48 V servo (R_s read negative) and lost
 * the rotor of the hub motor and of Table I's with 40 ms halves. */
#ifndef SMD_RLS_H
#define SMD_RLS_H

#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct smd_rls_params {
    smd_real T_sp;      /* sampling period, s */
    smd_real L_s_hat;   /* stator inductance the model uses, H */
    smd_real i_inj;     /* injected d-axis current amplitude, A */
    smd_real alpha;     /* T_sp / tau: the forgetting (1 - lambda) */
    smd_real w_min;     /* psi_r is fitted only at |w| >= w_min, rad/s */
    smd_real R0, psi0;  /* the estimates until the fit has data */
    int n_half;         /* samples per half period of the injection */
    int n_stale;        /* R_hat not taken for more than this many samples (2 tau): stale */
    smd_real k_td;      /* t_dc / (2 L_s_hat), 1/ohm: where the current is sampled
                         * (smd_rls_set_dead_time; 0: not corrected) */
} smd_rls_params;

typedef struct smd_rls_state {
    smd_cplx i_prev;    /* i(k-1), stationary frame, A */
    smd_cplx u_prev;    /* voltage applied during [k-1, k), V */
    int have_prev;      /* 1: i_prev belongs to a valid sample, u_prev was whole */
    int k_half;         /* samples into this half period of the injection */
    int sgn;            /* sign of the injection, +1 or -1 */
    smd_real W;         /* weight sum of the d-axis means */
    smd_real M_i, M_y, S_ii, S_iy, S_yy; /* d axis: weighted sums of i_d, y_d, i_d^2,
                                           i_d y_d, y_d^2 */
    smd_real S_ww, S_wy, S_wi;     /* q axis: of w^2, w y_q, w i_q */
    smd_real R_hat;     /* R_s estimate, ohm */
    smd_real R_slope;   /* the d-axis line's slope it was taken from, ohm: what the
                         * sampled currents show, and what the q axis's fit subtracts */
    smd_real R_se;      /* its standard error, ohm (the fit quality; -1: no fit yet) */
    smd_real psi_hat;   /* psi_r estimate, Wb */
    int age;            /* samples since R_hat was last taken (or since reset), at most
                         * n_stale + 1 */
} smd_rls_state;

/* tau: forgetting time constant, s, in [10 T_sp, 1e3]; n_half in
 * [2, 1e6]; i_inj in (0, 1e5] A; L_s_hat in (0, 10] H; w_min in [0, 1e7]
 * rad/s; R0 in [0, 1e3] ohm; psi0 in [0, 100] Wb; T_sp in (0, 1] s.
 * Anything else: SMD_ERR_RLS (a NULL p: SMD_ERR_NULL). */
smd_status smd_rls_init(smd_rls_params *p, smd_real T_sp, smd_real L_s_hat, smd_real i_inj,
                        smd_real tau, int n_half, smd_real w_min, smd_real R0, smd_real psi0);
/* The dead time the drive compensates, t_dc (s, >= 0; 0 after init): the
 * dead time moves each pulse's centre by t_dc / 2 from the carrier's, where
 * the current is sampled, and the fitted slope is R_s (1 - R_s t_dc / (2
 * L_s)) (commissioning's step 1 the same: docs/commissioning.md); R_hat is
 * the slope divided by that factor while R_s t_dc / (2 L_s) <= 0.1 (the
 * first-order model's reach), the slope itself beyond. SMD_ERR_RLS for a
 * t_dc not in [0, T_sp]. */
smd_status smd_rls_set_dead_time(smd_rls_params *p, smd_real t_dc);
void smd_rls_reset(const smd_rls_params *p, smd_rls_state *s);
/* The injected d-axis current for sample k, A: +-i_inj. */
smd_real smd_rls_injection(const smd_rls_params *p, const smd_rls_state *s);
/* One sample: i_ab = i(k) measured, u_next = the voltage applied during
 * [k, k+1) (the model uses it at the next sample) and u_ok = 1 when the
 * inverter applies it whole (the modulator did not limit it, no duty was
 * clipped), theta_k and w_k the rotor frame at k, valid = 1 when they are
 * the rotor's. Advances the injection. A sample whose interval is not
 * valid at both ends, or whose voltage was not whole, does not count;
 * non-finite inputs or results leave the estimates as they were. */
void smd_rls_step(const smd_rls_params *p, smd_rls_state *s, smd_cplx i_ab, smd_cplx u_next,
                  int u_ok, smd_real theta_k, smd_real w_k, int valid);
/* 1 when R_hat was not taken for more than 2 tau (the header), else 0. */
int smd_rls_stale(const smd_rls_params *p, const smd_rls_state *s);

#ifdef __cplusplus
}
#endif

#endif

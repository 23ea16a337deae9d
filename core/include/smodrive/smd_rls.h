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
 * With an observer's angle (smd_rls_set_observer; the drive's SMDO), the
 * square wave turns the angle: a resistance dR above the observer's model
 * puts dR i on its disturbance, whose d part turns the angle by about
 * dR i_d / (w psi_r), and fitted in that frame the d axis's EMF cancels dR
 * i_d: the fit reads the observer's own R_s (a +40 % rise ended 30 % low).
 * Three changes make R_s observable without a position sensor:
 *  - the frame: the line through the angle's means over whole periods of
 *    the square wave (2 n_half samples each; the speed from two means),
 *    which a periodic response of the angle to the wave does not move; a
 *    sample counts from the third period after the angle became valid;
 *  - the instrument: the slope is cov(z, y_d) / cov(z, i_d) with z the
 *    injection (of the sample before), not y_d's regression on i_d: the
 *    frame's own noise eps enters i_d as -i_q eps and y_d as -w psi_r eps,
 *    and the regression read w psi_r i_q var(eps) / var(i_d) more (+3.5 %
 *    on the 48 V servo), which z, uncorrelated with eps, does not; the
 *    first 4 samples of each half (the current's step) do not count;
 *  - with the band (smd_rls_set_band, the drive: its i_dtc), intervals
 *    near a phase current's zero crossing do not count: there a clamped
 *    phase's voltage is the motor's, and the compensation's residual,
 *    correlated with the wave, read +2 % to +5 % on the 600 V motor;
 *    samples that do not count forget as those that do (tau stays a time).
 * The drive then gives the SMDO (and the robust DBPC) the tracker's R_s,
 * so that the wave stops turning the angle: without it the hub motor lost
 * its rotor after the rise. What remains is the rotor's own motion with
 * the wave (the speed loop turns the angle's steps into torque): the drive
 * derives n_half so that the wave is 5 times faster than its speed loop
 * (at 20 ms the 48 V servo's R_s ran 57 % off). An integral loop correcting
 * the SMDO's R_s from the angle's step at the square wave's edges was
 * tried (2026-11-27) and left out: within 2 % on two motors, it ran away on
 * the 48 V servo (R_s read negative). */
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
    smd_real R_lo, R_hi; /* an R_s outside [R_lo, R_hi] is not taken, ohm
                          * (smd_rls_set_range; 0 and 1e30 after init) */
    smd_real i_band;    /* an interval counts only when every phase current at both ends
                         * is at least this far from zero, A (smd_rls_set_dead_time) */
    int observer;       /* 1: the angle given is an observer's, the fit's frame is
                         * its means over the injection's periods (smd_rls_set_observer) */
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
    smd_real M_z, S_zy, S_zi;      /* with an observer's angle: of the instrument z (the
                                    * injection of the sample before), z y_d, z i_d */
    int z_sgn;          /* the injection's sign at the sample before */
    smd_real Wt;        /* with an observer's angle: the weight sum of every sample in
                         * its frame, counted or not (W: of those counted) */
    smd_real R_hat;     /* R_s estimate, ohm */
    smd_real R_slope;   /* the d-axis line's slope it was taken from, ohm: what the
                         * sampled currents show, and what the q axis's fit subtracts */
    smd_real R_se;      /* its standard error, ohm (the fit quality; -1: no fit yet) */
    smd_real psi_hat;   /* psi_r estimate, Wb */
    int age;            /* samples since R_hat was last taken (or since reset), at most
                         * n_stale + 1 */
    /* with an observer's angle (smd_rls_set_observer): the fit's frame */
    smd_real th_f, w_f; /* its angle (rad) and speed (rad/s) at this sample */
    smd_real dev;       /* sum of the observer's angle minus th_f over this period, rad */
    smd_real A_prev;    /* the last period's mean angle, at its middle, rad */
    int n_dev;          /* samples in dev */
    int n_per;          /* whole periods averaged since the angle was last not valid */
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
/* The range of R_s the fit's may take (ohm, 0 <= lo <= hi): one outside is
 * not taken, and the estimate goes stale after 2 tau (the drive: [0.5, 2.5]
 * R_s_hat, a winding 250 K colder or 390 K warmer than at commissioning;
 * with the SMDO's angle a fit that ran away, as one did at 10 ms halves on
 * an invented 400 V motor, R_s 0.09 of its value at status 0, says so).
 * SMD_ERR_RLS for a range not within [0, 1e30]. */
smd_status smd_rls_set_range(smd_rls_params *p, smd_real lo, smd_real hi);
/* Intervals whose phase currents come within i_band of zero at either end
 * do not count (i_band >= 0, A; 0 after init): there a clamped phase's
 * voltage is the motor's, not the inverter's, and the dead-time
 * compensation's residual moves with the operating point
 * (docs/commissioning.md). SMD_ERR_RLS for an i_band not in [0, 1e5]. */
smd_status smd_rls_set_band(smd_rls_params *p, smd_real i_band);
/* The angle smd_rls_step is given is an observer's (on = 1; 0 after init):
 * the fit's frame is the line through the angle's means over the last two
 * whole periods of the injection, so that what the square wave does to the
 * observer's angle does not turn the frame with it (the header). A sample
 * counts from the third whole period after the angle became valid. */
smd_status smd_rls_set_observer(smd_rls_params *p, int on);
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
/* With an observer's angle the first SMD_RLS_SKIP samples of each half of
 * the square wave do not count: the deadbeat current's step (two samples)
 * and the observer's answer to it. */
#define SMD_RLS_SKIP 4
/* 1 during the first SMD_RLS_SKIP samples after an edge of the square wave
 * (the current steps by 2 i_inj: the drive's ripple measure leaves them
 * out), else 0. */
int smd_rls_edge(const smd_rls_state *s);
/* 1 when R_hat was not taken for more than 2 tau (the header), else 0. */
int smd_rls_stale(const smd_rls_params *p, const smd_rls_state *s);

#ifdef __cplusplus
}
#endif

#endif

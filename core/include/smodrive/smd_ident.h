/*
 * Commissioning, step 1 (issue 23): the stator resistance R_s and the
 * inverter's voltage drop, measured by the drive itself before it runs,
 * sample by sample, with no knowledge of the motor.
 *
 * The test drives a DC current along the alpha axis (the rotor aligns to
 * it: a d-axis current, no torque once aligned). A search finds the
 * voltages that give i_test / 10 and i_test: each voltage is held until the
 * current settles (the window means below), then the next is applied, in
 * steps of u_max / 1000 until the current appears (the inverter's drop
 * hides it at first), then in steps of a quarter of i_test at the slope of
 * the last two points; whatever the motor's L/R, the current cannot run
 * ahead of a voltage that waits for it. Then a staircase of `levels`
 * voltages between the two, each held until the current's mean over a
 * window stops moving (two windows agree within 0.2 % of i_test plus three
 * standard errors of their noise), then averaged over the next window. A
 * least-squares line through the
 * levels, u = R_s i + u_0, gives R_s (slope) and the inverter's drop u_0
 * (intercept: dead time and switch drops, which a voltage command does not
 * see), with the fit's R^2 and residual.
 *
 * The applied voltage is the commanded one after the modulator's limit
 * (smd_svm_step), the current the alpha component of the measured phase
 * currents (c = -a - b).
 *
 * Named outcomes (smd_ident_rs_state.outcome) when the result cannot be
 * trusted: the current never reached i_test below the voltage limit
 * (no motor, an open phase, R_s too high for the test current), a phase
 * current beyond 1.5 i_test (the test stops, zero vector), a level that
 * never settled within t_level_max, a fit whose R^2 is below 0.999, a
 * non-finite input, a measured current that stopped following the voltage
 * past i_test / 10 (the sensors' range: a clipped sensor reads its full
 * scale while the true current grows with the voltage, and the trip at
 * 1.5 i_test never sees it; the test stops at a step that added under half
 * the current the search's smallest slope gives, or once the voltage rose
 * by what half of i_test takes with the current up by under 1 % of i_test;
 * a range below i_test / 10 reads as no current).
 */
#ifndef SMD_IDENT_H
#define SMD_IDENT_H

#include "smodrive/smd_svm.h"
#include "smodrive/smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SMD_IDENT_MAX_LEVELS 32
#define SMD_IDENT_MAX_HALF 64
#define SMD_IDENT_MAX_PERIOD 128 /* 2 SMD_IDENT_MAX_HALF */

typedef enum smd_ident_phase {
    SMD_IDENT_RAMP = 0,  /* the voltage ramp toward i_test */
    SMD_IDENT_LEVEL = 1, /* the staircase */
    SMD_IDENT_DONE = 2,  /* a result (outcome OK or POOR_FIT); zero vector */
    SMD_IDENT_FAILED = 3 /* no result (outcome says why); zero vector */
} smd_ident_phase;

typedef enum smd_ident_outcome {
    SMD_IDENT_OK = 0,
    SMD_IDENT_RUNNING = 1,
    SMD_IDENT_NO_CURRENT = 2,   /* i_test not reached at the voltage limit */
    SMD_IDENT_OVERCURRENT = 3,  /* a phase current beyond 1.5 i_test */
    SMD_IDENT_NOT_SETTLED = 4,  /* a level did not settle within t_level_max */
    SMD_IDENT_POOR_FIT = 5,     /* R^2 below 0.999: the values are given, not trusted */
    SMD_IDENT_BAD_INPUT = 6,    /* a non-finite current or DC-link voltage */
    SMD_IDENT_SLIPPED = 7,      /* step 3: the rotor did not follow the spin (it turns at
                                 * under half the frame's speed when it coasts) */
    SMD_IDENT_VOLTAGE_LIMIT = 8, /* step 3: no result, and the modulator limited the spin's
                                  * voltage (the back EMF beyond the DC link's reach) */
    SMD_IDENT_SENSOR_RANGE = 9  /* step 1: the measured current stopped following the
                                 * voltage (a rise that should have added half of i_test
                                 * added under 1 % of it): the current sensors' range
                                 * reached, or their signal lost; the test stops, zero
                                 * vector (a clipped sensor hides the overcurrent check) */
} smd_ident_outcome;

typedef struct smd_ident_rs_config {
    smd_real T_sp;        /* sampling period, s, (0, 1] */
    smd_real i_test;      /* the staircase's top current, A, (0, 1e5] */
    smd_real u_max;       /* the largest test voltage, V, (0, 1e5] (the modulator limits too) */
    smd_real t_win;       /* averaging window, s, [10 T_sp, 10] */
    smd_real t_level_max; /* the longest wait at a level, s, [2 t_win, 100], <= 1e8 T_sp */
    int levels;           /* levels of the staircase, [8, SMD_IDENT_MAX_LEVELS] */
} smd_ident_rs_config;

typedef struct smd_ident_rs_params {
    smd_real i_test;
    smd_real u_max;
    smd_real du;          /* the search's first steps, V (u_max / 1000) */
    int n_win;            /* samples a window */
    int n_level_max;      /* samples a level at most */
    int levels;
    smd_svm_params svm;
} smd_ident_rs_params;

typedef struct smd_ident_rs_state {
    int phase;            /* smd_ident_phase */
    int outcome;          /* smd_ident_outcome */
    smd_real u;           /* the commanded alpha voltage, V */
    smd_real u_lo;        /* the ramp's voltage at i_test / 10, V */
    smd_real u_hi;        /* the ramp's voltage at i_test, V */
    smd_real i_lo;        /* the current at u_lo, A */
    smd_real du_cur;      /* the search's step below i_test / 10, V (0: du) */
    int backoffs;         /* the search's back-offs from 1.2 i_test */
    smd_real u_prev_pt;   /* the search's last settled point: voltage, V */
    smd_real i_prev_pt;   /* and current, A */
    smd_real u_rise;      /* the last point past i_test / 10 whose current rose: voltage, V */
    smd_real i_rise;      /* and current, A (0: none yet) */
    smd_real slope;       /* the search's smallest slope du / di there, ohm (0: none yet) */
    int level;            /* the level being measured */
    int n_level;          /* samples at this level */
    int n;                /* samples in this window */
    smd_real acc_i, acc_i2, acc_u; /* the window's sums: current, its square, voltage */
    smd_real prev_i;      /* the last window's mean current, A */
    int have_prev;
    smd_real i_lv[SMD_IDENT_MAX_LEVELS]; /* each level's mean current, A */
    smd_real u_lv[SMD_IDENT_MAX_LEVELS]; /* and applied voltage, V */
    smd_cplx u_applied;   /* the voltage the modulator gives for the next period */
    int samples;          /* samples since the start */
    /* results (DONE): R_s, ohm; the inverter's drop, V; R^2; residual RMS, V */
    smd_real R_s;
    smd_real u_0;
    smd_real r2;
    smd_real resid;
} smd_ident_rs_state;

smd_status smd_ident_rs_init(smd_ident_rs_params *p, const smd_ident_rs_config *c);
void smd_ident_rs_reset(smd_ident_rs_state *s);
/* One sample: the measured phase currents i_a, i_b (A) and the DC-link
 * voltage (V) in, the duties of the next period out (the zero vector, 0.5
 * each, once done or failed). Returns SMD_OK while the test runs or has a
 * result, SMD_ERR_FAULT once it failed (s->outcome says why). */
smd_status smd_ident_rs_step(const smd_ident_rs_params *p, smd_ident_rs_state *s, smd_real i_a,
                             smd_real i_b, smd_real u_dc, smd_real d_abc[3]);

/*
 * Commissioning, step 2: the stator inductance along the d axis (alpha, where
 * the R_s test aligned the rotor) or the q axis (beta), at standstill. A DC
 * bias current i_bias along alpha (the voltage R_s i_bias + u_0 from step 1,
 * held until the current settles) keeps every phase current away from zero
 * (the inverter's drop stays the constant u_0: no dead-time nonlinearity)
 * and holds the rotor; a square wave of +-du on the tested axis, n_half
 * samples each way, adds a periodic current. Its waveform, averaged sample by
 * sample over `periods` periods (the ADC's noise down by their square root),
 * obeys the exact discrete model of the stator over a sample,
 * w(k+1) = a w(k) + b v(k-1) + c (the command of k-1 is the voltage over
 * [t_k, t_k+1); c carries the bias, the EMF-free standstill and the drop),
 * which a least-squares fit over the 2 n_half samples of the period gives:
 * a = e^{-R T/L}, b = (1 - a) / R, so L = T (1 - a) / (b ln(1/a)) whatever
 * L/R is against T_sp (a triangle when L/R >> T_sp, where L -> T / b; a
 * square wave when L/R is a sample or less), and R = (1 - a) / b. The
 * amplitude du starts at u_max / 2000 and doubles (to u_max / 10) until the
 * wave's swing (the slopes of the two halves, measured as in a triangle) is
 * at least 10 % of i_bias.
 * On the q axis the bias stays on alpha: the injected current alternates
 * the torque at 1 / (2 n_half T_sp) around zero, and the rotor barely moves.
 */
typedef struct smd_ident_ls_config {
    smd_real T_sp;        /* sampling period, s, (0, 1] */
    smd_real R_s;         /* from step 1, ohm, [0, 1e3] */
    smd_real u_0;         /* the inverter's drop from step 1, V, [0, 1e4] */
    smd_real i_bias;      /* the DC bias along alpha, A, (0, 1e5] */
    smd_real u_max;       /* the largest voltage, V, (0, 1e5] */
    smd_real t_win;       /* settling windows of the bias, s, [10 T_sp, 10] */
    int axis;             /* 0: d (alpha), 1: q (beta) */
    int n_half;           /* samples a half period, [4, SMD_IDENT_MAX_HALF] */
    int periods;          /* periods averaged, [10, 100000] */
} smd_ident_ls_config;

typedef struct smd_ident_ls_params {
    smd_real T_sp, R_s, u_0, i_bias, u_max;
    int n_win, axis, n_half, periods;
    smd_svm_params svm;
} smd_ident_ls_params;

typedef enum smd_ident_ls_phase {
    SMD_IDENT_LS_BIAS = 0,    /* the bias current settling */
    SMD_IDENT_LS_AMPLITUDE = 1, /* finding du */
    SMD_IDENT_LS_MEASURE = 2, /* averaging */
    SMD_IDENT_LS_DONE = 3,
    SMD_IDENT_LS_FAILED = 4
} smd_ident_ls_phase;

typedef struct smd_ident_ls_state {
    int phase;            /* smd_ident_ls_phase */
    int outcome;          /* smd_ident_outcome */
    smd_real du;          /* the square wave's amplitude, V */
    int k;                /* sample within the period, [0, 2 n_half) */
    int period;           /* periods done in this phase */
    int n;                /* bias: samples in the window */
    smd_real acc_i, acc_i2, prev_i;
    int have_prev;
    smd_real sj_i[2];     /* this half period's sums: j i */
    smd_real s_i[2];      /* and i, for the + and - halves */
    smd_real slope_sum[2]; /* the sums of the halves' slopes, A/sample */
    int halves[2];
    smd_real acc_w[SMD_IDENT_MAX_PERIOD]; /* the waveform's sums by command index, A */
    smd_real i_bias_meas; /* the settled bias, A */
    smd_cplx u_applied;
    int samples;
    smd_real L;           /* results (DONE): H */
    smd_real R_ac;        /* the resistance the same fit gives, ohm (a check) */
    smd_real swing;       /* the wave's swing, A */
} smd_ident_ls_state;

smd_status smd_ident_ls_init(smd_ident_ls_params *p, const smd_ident_ls_config *c);
void smd_ident_ls_reset(smd_ident_ls_state *s);
/* One sample, as smd_ident_rs_step. */
smd_status smd_ident_ls_step(const smd_ident_ls_params *p, smd_ident_ls_state *s, smd_real i_a,
                             smd_real i_b, smd_real u_dc, smd_real d_abc[3]);

/*
 * Commissioning, step 3: the PM flux psi_r from an I/f spin, on the R_s, the
 * drop and the L_s of steps 1 and 2. A current of i_spin on the q axis of a
 * forced frame (a complex PI in that frame, its bandwidth w_cc: k_p = L_s
 * w_cc, k_i = R_s w_cc) turns at a speed that ramps at a_spin to w1, holds
 * t_hold, ramps to w2, holds t_hold; over the second half of each hold the
 * back EMF in the forced frame, e = u - (R_s + j w L_s) i - (3/pi) u_0 i/|i|
 * (the applied voltage less the stator's drop and the inverter's, whose
 * fundamental is 3/pi of the DC drop u_0 for a current that turns), is
 * averaged: |e| = w psi_r whatever angle the rotor lags by. psi_r is
 * |e2| / w2, at the higher speed, where the drops weigh least against the EMF
 * (the slope (|e2| - |e1|) / (w2 - w1) is kept too: the drops are not
 * collinear with the EMF, so it does not cancel them, and it doubles the
 * noise); |e1| / w1 must agree within a margin (below). Then the current is set to zero
 * (coasting: the PI holds i = 0, so the voltage it applies is the back EMF)
 * and psi_coast = mean |u| / |mean d arg u / dt| over t_coast after 0.1
 * t_coast; it must agree with psi_r within the margin (outcome POOR_FIT otherwise,
 * all given). Where the inverter's drop is more than a fifth of the EMF at
 * w2 ((3/pi) u_0 > |e2| / 5: a coast at zero current then reads the drop,
 * +10 to +41 % on a 12 V, 40 kHz inverter with 1-2 us of dead time) and the
 * short's current |e2| / |R_s + j w2 L_s| is within i_spin, the coast shorts
 * the stator instead (shorted: pwm_off = 2, every lower switch on; no
 * device switches, so no dead time): i = -j w psi_r e^{j theta} / (R_s + j w
 * L_s) turns with the rotor, and psi_coast = mean (|i| |R_s + j w_f L_s|) /
 * |mean d arg i / dt| is the result (psi_r), R_s's error its error where R_s
 * dominates. Each hold must then agree with it. Either way a hold's margin
 * is 5 % plus a tenth of the drop's share of its EMF, (3/pi) u_0 / |e|: the
 * drop's model (its fundamental for a current that turns) taken as 10 %
 * uncertain, which a clamped current's zero crossings make it. The coast also says whether the rotor followed the frame:
 * its EMF's turn is the rotor's speed, and off the frame's by more than
 * half (|w_coast / w2 - 1| > 1/2: a stalled rotor's turn is the noise's)
 * the rotor slipped (outcome SLIPPED: a load heavier than the ramp allows,
 * or a rotor that does not turn; the values are given, not trusted). A spin
 * without a result (slipped or a poor fit) whose voltage the modulator
 * limited for more than a twentieth of a hold ends VOLTAGE_LIMIT instead:
 * the back EMF at the spin's speeds is beyond the DC link's reach (a bench
 * supply below the motor's voltage), and a slower spin would not help; a
 * spin limited for a hold's length in all stops there with that outcome (the
 * governor would otherwise hold its ramp at that EMF without end). The
 * second ramp, where the governor reads the rotor, also gives the mean
 * share of the torque the rotor took and the frame's mean acceleration
 * (share_ramp, a_ramp): the inertia the spin saw is about 1.5 n_p^2 psi_r
 * i_spin share_ramp / a_ramp (friction and a load's torque counted in).
 */
typedef struct smd_ident_psi_config {
    smd_real T_sp;        /* s, (0, 1] */
    smd_real R_s, L_s, u_0; /* from steps 1 and 2: ohm [0, 1e3], H (0, 10], V [0, 1e4] */
    smd_real i_spin;      /* the spin's current, A, (0, 1e5] */
    smd_real w1, w2;      /* the two speeds, electrical rad/s, 0 < w1 < w2 < pi / (4 T_sp) */
    smd_real a_spin;      /* the ramp, rad/s^2, (0, 1e7] */
    smd_real t_hold;      /* each hold, s, [0.01, 100] */
    smd_real t_coast;     /* the coast, s, [0.01, 100] */
    smd_real w_cc;        /* the current loop's bandwidth, rad/s, (0, pi / (10 T_sp)] */
    /* an LCL filter between the inverter and the motor (its data sheet's values;
     * L1 = 0: none): H [0, 10], F (0, 10] with L1 > 0, H [0, 10]. Both currents
     * are measured, the motor's i (i_2) and the inverter's i_1: the inverter's
     * drop is taken along i_1 (the legs carry it), the capacitor's voltage is
     * u_c = u - drop - j w L1 i_1 and the EMF u_c - (R_s + j w (L2o + L_s)) i.
     * The coast does not trust the voltage: holding i = 0, the capacitor's
     * current flows in the legs, and their dead time at such a current put
     * |u| 15 % high at 2 us on yao2022's 65 V (holding i_1 = 0 still 11 %).
     * For a tenth of t_coast the PI holds i = -i_cap, the capacitor's current
     * i_1 - i low-passed at w_cc, so that i_1 is near 0 (a PI on i_1 itself
     * rings the filter); then every switch opens (pwm_off, while the EMF's
     * line peak stays below u_dc): i_1 = 0, the capacitor's current flows in
     * the motor, i = -j w C1 u_c, and from a fifth of t_coast on the mean |i|
     * and its turn give psi_coast = |i| |1 - w^2 C1 (L2o + L_s) + j w R_s C1|
     * / (w^2 C1). It rests on C1's data-sheet value (a C1 5 % off moves it
     * 5 %); the holds do not (u_c from the measured i_1) */
    smd_real L1, C1, L2o;
    /* the I/f rotor is an undamped pendulum without friction, and a ramp
     * that asks most of the current's torque makes it slip; from w1 / 5 on,
     * two loops on the angle of e keep it: the stabiliser (w_damp, rad/s,
     * [0, 1e5], 0: none) adds w_damp times the high-passed angle (corner
     * w_damp / 10) to the frame's speed, which damps the swing; the governor
     * (share_max, (0, 1], 1: none) slows the ramp (by 4 (share - share_max)
     * a second) while the rotor takes more than share_max of the torque the
     * current can give: the share is e's component along the current over
     * its magnitude, the cosine of the rotor's lag behind the frame,
     * low-passed at 10 rad/s */
    smd_real w_damp, share_max;
} smd_ident_psi_config;

typedef struct smd_ident_psi_params {
    smd_real T_sp, R_s, L_s, u_drop, i_spin, w1, w2, a_spin, k_p, k_i;
    smd_real L1, C1, L2;    /* the filter: L1, C1, L2o + L_s (L1 = 0: none) */
    smd_real a_cap;         /* the capacitor current's low-pass, w_cc T_sp */
    smd_real w_damp, a_hp;  /* the stabiliser: its gain, rad/s, and high-pass w_damp T_sp / 10 */
    smd_real share_max, w_gov, a_share, k_g; /* the governor: its share, from w_gov, the
                                              * share's low-pass, the ramp's reduction, 1/s */
    int n_hold, n_coast;
    smd_svm_params svm;
} smd_ident_psi_params;

typedef enum smd_ident_psi_phase {
    SMD_IDENT_PSI_RAMP1 = 0, SMD_IDENT_PSI_HOLD1 = 1, SMD_IDENT_PSI_RAMP2 = 2,
    SMD_IDENT_PSI_HOLD2 = 3, SMD_IDENT_PSI_COAST = 4, SMD_IDENT_PSI_DONE = 5,
    SMD_IDENT_PSI_FAILED = 6
} smd_ident_psi_phase;

typedef struct smd_ident_psi_state {
    int phase;
    int outcome;
    smd_real theta_f, w_f; /* the forced frame, rad, rad/s */
    smd_cplx x_i;         /* the PI's integral, forced frame, V */
    smd_cplx u_ab;        /* the voltage commanded last sample, alpha-beta, V */
    smd_cplx u_prev;      /* the voltage applied over the last period (the sample before's) */
    int n;                /* samples in this phase */
    smd_real acc_e, acc_n; /* sums of |e| (or |u| coasting) and of their samples */
    smd_real acc_w;       /* coasting: sum of d arg u a sample; holding: of the frame's speed */
    smd_real phi_lpf;     /* the stabiliser's low-passed angle of e, rad */
    smd_real w_c;         /* the stabiliser's term of the frame's speed, rad/s */
    smd_real share;       /* the governor's low-passed share */
    smd_cplx i_cap;       /* behind a filter: the capacitor's current, low-passed, A */
    smd_cplx i_prev;      /* behind a filter, coasting: the last sample's current, A */
    int pwm_off;          /* 1: switch every device off (behind a filter, coasting; the
                           * duties are the zero vector); 2: every lower switch on, forced
                           * (shorted, coasting; the duties are 0): no edge, no dead time */
    int shorted;          /* 1: the coast shorts the stator through the lower switches
                           * (the header) */
    smd_real g;           /* the ramp's factor, [0.01, 1] */
    int gov_on;
    smd_real e1, e2;      /* mean |e| at w1, w2, V */
    smd_real w1m, w2m;    /* the frame's mean speed over the same samples, rad/s */
    smd_real psi, psi1, psi2, psi_coast, psi_slope; /* results, Wb */
    smd_real w_coast;     /* the rotor's electrical speed in the coast, rad/s */
    smd_real acc_sh, acc_a, acc_r; /* the second ramp: sums of the share, the frame's
                                    * acceleration and their samples */
    smd_real share_ramp, a_ramp; /* their means (the header), -, rad/s^2 */
    smd_cplx u_applied;
    int samples;
    int n_lim;            /* samples of the ramps and holds whose voltage the modulator
                           * limited */
    smd_real w_lim;       /* the frame's speed at the first of them at or above the
                           * governor's w1 / 5, rad/s (0: none) */
} smd_ident_psi_state;

smd_status smd_ident_psi_init(smd_ident_psi_params *p, const smd_ident_psi_config *c);
void smd_ident_psi_reset(smd_ident_psi_state *s);
/* One sample, as smd_ident_rs_step; i1_a, i1_b: the inverter-side currents
 * behind a filter (ignored without one). */
smd_status smd_ident_psi_step(const smd_ident_psi_params *p, smd_ident_psi_state *s,
                              smd_real i_a, smd_real i_b, smd_real i1_a, smd_real i1_b,
                              smd_real u_dc, smd_real d_abc[3]);

/*
 * Commissioning, step 4: the inertia J and the viscous friction B, with the
 * drive running (issue 23). The block gives the drive its speed reference,
 * w1 for t_step (the start and the settling), a ramp to w2 over t_ramp, w2
 * for t_hold, and takes what the drive knows each sample: its torque
 * current i_q (the measured current in its frame: at the voltage limit the
 * reference is not what flows; the torque k_t i_q, k_t = 1.5 n_p psi_r from
 * step 3) and its estimate of the electrical speed. From t_fit before the
 * ramp on, the samples are averaged in bins of t_bin; each bin with a
 * neighbour on both sides adds a row to the normal equations of
 * T = J a + B w_M: a is the neighbours' central difference, which weighs the
 * acceleration over the three bins with a trapezoid, and T and w_M are
 * weighted alike, (x0 + 2 x1 + x2) / 4 of the bins' means, so that the row
 * holds for the weighted means; at the end J and B solve them (least
 * squares). The torque passes the first-order low-pass (w_lpf) that the
 * drive's speed estimate has passed, so that both sides of the (linear)
 * equation lag alike. The holds need not be steady (a heavy rotor still
 * settles there): the fit uses every bin; with fan = 1 the load's
 * K w_M |w_M| is a third unknown (a fan, a pump). A fit with J <= 0, B < 0
 * or K < 0, or equations without an acceleration, is POOR_FIT (values
 * given); so is one whose coast's B and ramp's B give friction torques at
 * w2 that differ by more than a twentieth of the torque the ramp's
 * acceleration takes, J (w2 - w1) / t_ramp: the coast has no torque in
 * it, so the two disagree when the torque the drive reports, k_t i_q in
 * its frame, is not the rotor's, or when the coast's zero current is not
 * zero torque (a 5 uH multirotor motor at 0.2 rad a sample: its angle
 * lagged 3-5 deg in the ramp, J -28 %, B +450 % by the coast, a difference
 * of 27 % of the ramp's torque; with the speed estimate's filter fast
 * enough, J -4.5 % and B +161 % by the coast, +47 % by the ramp, 9.7 %; on
 * 30 other runs, 10 x their inertia too, at most 2.0 %: on
 * a heavy rotor the ramp's B is loose, so the check is against the ramp's
 * torque, not B). The caller says each sample whether the drive runs on its
 * position source (closed != 0: its torque is k_t i_q); before that (its
 * forced start, slow with a heavy rotor) the fit waits at its first sample,
 * with the reference at w1, until the drive has run on its source for
 * 5 / w_lpf (the filters forget the start), at most as long as the whole
 * test (then NOT_SETTLED); a fall back to the forced phase later starts the
 * bins again. A drive fault (the caller's fault word, non-zero) stops the
 * test with outcome FAULT; a non-finite input is BAD_INPUT.
 */
typedef struct smd_ident_mech_config {
    smd_real T_sp;        /* s, (0, 1] */
    smd_real k_t;         /* torque constant 1.5 n_p psi_r, N m / A, (0, 1e3] */
    int n_p;              /* pole pairs, [1, 100] */
    smd_real w1, w2;      /* the two speeds, electrical rad/s, 0 < w1 < w2 <= 1e6 */
    smd_real t_step;      /* at w1 before the ramp, s, [2 t_fit, 100] */
    smd_real t_ramp;      /* the ramp, s, [4 t_bin, 100] */
    smd_real t_hold;      /* at w2, s, [4 t_bin, 100] */
    smd_real t_fit;       /* the fit begins this long before the ramp, s, [4 t_bin, t_step / 2] */
    smd_real t_bin;       /* the bins, s, [10 T_sp, 1]; the whole test at most 1e8 T_sp */
    smd_real w_lpf;       /* the low-pass of the drive's speed estimate, rad/s, 0 (none) or
                           * [5 / t_step, pi / T_sp]: the torque passes the same filter */
    int fan;              /* 1: the load has a fan's torque K w_M |w_M| besides B w_M, fitted
                           * too (K, N m s^2 / rad^2); 0: not */
    smd_real t_coast;     /* the coast at zero current after the hold, s: 0 (none) or
                           * [5 / w_lpf + 4 t_bin, 100] (5 T_sp without w_lpf) */
} smd_ident_mech_config;

typedef struct smd_ident_mech_params {
    smd_real k_t, inv_np, w1, w2, dw, t_bin;
    smd_real a_lpf;       /* the torque's filter, 1 - e^{-w_lpf T_sp} (1: none) */
    int n_settle;         /* samples on the source before they count: 5 / (w_lpf T_sp), or 1 */
    int fan;
    smd_real inv_w2;      /* the fan regressor's scale, 1 / w2 mechanical */
    int n_step, n_ramp, n_end, n_fit0, n_bin;
    int n_coast;          /* samples of the coast */
} smd_ident_mech_params;

#define SMD_IDENT_FAULT 7 /* step 4: the drive reported a fault (smd_ident_outcome's next) */

typedef struct smd_ident_mech_state {
    int k;                /* samples done */
    int outcome;          /* smd_ident_outcome, or SMD_IDENT_FAULT */
    int bins;             /* bins completed */
    int nb;               /* samples in the bin being filled */
    smd_real acc_T, acc_w; /* its sums: torque, mechanical speed */
    smd_real T_f;         /* the torque through the speed estimate's filter, N m */
    smd_real w_b[2];      /* the last two bins' mean speeds (w_b[1] the latest) */
    smd_real T_b[2];      /* their mean torques */
    smd_real saa, saw, sww, sat, swt; /* the normal equations' sums */
    smd_real saq, swq, sqq, sqt; /* and the fan's, q = w_M |w_M| / w2 (fan = 1) */
    int rows;             /* bins in them */
    int wait;             /* samples the fit waited for the drive's source */
    int n_closed;         /* samples the drive has run on its source, up to n_settle */
    smd_real J, B;        /* results, kg m^2 and N m s / rad */
    smd_real K;           /* the fan's, N m s^2 / rad^2 (fan = 1; 0 otherwise) */
    smd_real cww, cwq, cqq, cwa, cqa; /* the coast's sums (w, q = w |w| / w2, a) */
    int crows;            /* its bins */
    smd_real B_ramp;      /* B from the ramp's equations alone (with a coast: a check) */
    smd_real caa;         /* the coast's sum of a^2 */
    smd_real B_se;        /* B's standard error from the coast, N m s / rad (-1: none) */
} smd_ident_mech_state;

smd_status smd_ident_mech_init(smd_ident_mech_params *p, const smd_ident_mech_config *c);
void smd_ident_mech_reset(smd_ident_mech_state *s);
/* 1 while the test asks for zero current (the coast, t_coast > 0): the
 * caller gives the drive a zero q reference in torque mode
 * (smd_drive_set_torque_in), and its speed estimate as before. */
int smd_ident_mech_coasting(const smd_ident_mech_params *p, const smd_ident_mech_state *s);
/* The electrical speed reference for the sample about to run, rad/s. */
smd_real smd_ident_mech_ref(const smd_ident_mech_params *p, const smd_ident_mech_state *s);
/* One sample: the drive's torque current (measured, in its frame) and
 * electrical speed estimate, whether it runs on its position source,
 * its latched fault bits (a warning, e.g. an oscillation, is no reason to
 * stop). Returns 1 once the test has ended (outcome set). */
int smd_ident_mech_step(const smd_ident_mech_params *p, smd_ident_mech_state *s,
                        smd_real i_q, smd_real w_hat, int closed, uint32_t fault);

#ifdef __cplusplus
}
#endif

#endif

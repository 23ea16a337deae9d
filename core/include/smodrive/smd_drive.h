/*
 * The drive: what a firmware interrupt calls once per sample. One entry
 * point for every drive smodrive knows, composed of parts chosen at init:
 *
 *   current control   SMD_CC_PI           synchronous-frame PI with decoupling
 *                                         and EMF feed-forward; with the LCL
 *                                         filter also active damping by a
 *                                         virtual resistance on i_1 - i_2
 *                     SMD_CC_DBPC         yang2018 eq. (8)-(9)
 *                     SMD_CC_ROBUST_DBPC  SMDO eq. (34)-(39) + eq. (42)
 *   position source   SMD_POS_ENCODER     theta_enc, w_enc of the input
 *                     SMD_POS_SMDO_EMF    yang2018 eq. (44)-(45) on the SMDO's
 *                                         disturbance estimate
 *                     SMD_POS_LCL_SMO_PLL yao2022 sliding-mode observer + PLL
 *                                         eq. (47)-(48) (needs the LCL filter)
 *                     SMD_POS_LCL_LINEAR  yao2022 linear observer (64)-(65) +
 *                                         the same PLL (needs the LCL filter)
 *   start             SMD_START_RUNNING   the source from the first sample
 *                                         (a flying start from theta0, w0)
 *                     SMD_START_HANDOVER  encoder for `handover` samples while
 *                                         the observer converges, then the source
 *                     SMD_START_IF        I/f: current i_start on a forced angle
 *                                         accelerated at a_start up to
 *                                         w_handover, then the source
 *
 * Every part downstream of the position source (Park transforms, speed loop,
 * current control, modulation) sees only (theta, w) of sample k. The parts
 * are selected with enumerations and one switch each; there are no function
 * pointers. A combination that does not fit returns SMD_ERR_COMBINATION:
 * the LCL observers and active damping need the LCL filter (lcl = 1), and the
 * LCL-filtered drive needs SMD_CC_PI (deadbeat control of i_2 through the
 * filter is not what yang2018 designs).
 *
 * A composition fixed at compile time. A firmware runs one composition; it
 * may say which when it compiles smd_drive.c, and the step then carries it
 * as constants, not as fields it reads and branches on (the compiler prunes
 * the other parts: the yang2018 sensorless step with supervise_every = 4,
 * about 135 Cortex-M4F cycles less, docs/firmware.md). Each is optional:
 *   SMD_FIX_CURRENT          an smd_current_ctrl value (config.current)
 *   SMD_FIX_POSITION         an smd_pos_source value (config.position)
 *   SMD_FIX_LCL              0 or 1 (config.lcl)
 *   SMD_FIX_RLS              0 or 1: the tracker off (rls_i_inj = 0) or on
 *   SMD_FIX_SPEED_LOOP       0 or 1 (config.speed_loop)
 *   SMD_FIX_SUPERVISE_EVERY  config.supervise_every (0 and 1 alike)
 * e.g. -DSMD_FIX_CURRENT=SMD_CC_ROBUST_DBPC -DSMD_FIX_POSITION=SMD_POS_SMDO_EMF.
 * smd_drive_init returns SMD_ERR_COMBINATION for a configuration that
 * differs from any of them; a configuration it accepts runs the same step,
 * bit for bit, as the build without them (tests/test_target.py).
 *
 * Delay convention (every part): samples at t_k = k T_sp; the voltage
 * computed at k is applied during [t_{k+1}, t_{k+2}); the one applied during
 * [t_k, t_{k+1}) was computed at k-1 and is what the observers are fed.
 *
 * Faults. Every step returns finite duties in [0, 1]. The fault word of
 * smd_drive_out says why a step applied the safe state (SMD_SAFE_ZERO_VECTOR:
 * duties 0.5, 0.5, 0.5, all phases at the same potential; SMD_SAFE_PWM_OFF:
 * the same duties and pwm_off = 1, for a gate driver that can switch every
 * device off):
 *   not latched (this sample only; the next good sample runs normally)
 *     SMD_FAULT_INPUT      an input the configuration uses is NaN, infinite
 *                          or beyond any physical range (|i| > 1e5 A,
 *                          |theta| > 1e4 rad, |w| > 1e7 rad/s, u_dc not in
 *                          (0, 1e5] V); the sample runs on the last good
 *                          inputs (the encoder angle moved on at its speed),
 *                          so every block keeps its timeline, and the
 *                          observers are told the zero vector is applied
 *     SMD_FAULT_INTERNAL   a computed value was not finite; the blocks that
 *                          held it (current PI, SMDO, speed PI, observers,
 *                          PLL) were reset from the last good frame
 *   latched (the safe state until smd_drive_clear_faults; then restart with
 *   smd_drive_reset, e.g. a flying start from the last speed)
 *     SMD_FAULT_OVERCURRENT  a measured phase current (c = -a - b) above i_trip
 *     SMD_FAULT_UNDERVOLTAGE u_dc below u_dc_min
 *     SMD_FAULT_OVERVOLTAGE  u_dc above u_dc_max
 *     SMD_FAULT_LOST_LOCK    a sensorless source is implausible for
 *                            lock_samples samples in a row, or more than a
 *                            fifth of the time for longer (a leaky count: an
 *                            implausible sample counts four plausible ones):
 *                            its EMF estimate against |w_hat| psi_r_hat
 *                            outside [1/lock_ratio, lock_ratio] above
 *                            w_lock_min, or its speed at the limit it can
 *                            estimate (w_max of smdo_emf, the end of the LCL
 *                            observers' table); or at once, the sample its
 *                            angle jumps (SMD_FAULT_ANGLE_JUMP, reported
 *                            with it): an estimate that moved 45 deg in a
 *                            sample has lost the rotor (issue 21)
 *     SMD_FAULT_SPEED_TRACKING  the speed the drive uses stays farther than
 *                            w_track from its (slew-limited) reference while
 *                            the speed PI is at its current limit, for
 *                            track_samples samples in all while it stays
 *                            away (a sample off the limit holds the count:
 *                            the ADC's noise; back within w_track, it
 *                            restarts) (a stall, an overload, a reference
 *                            beyond the DC link's reach, a rotor the
 *                            estimate has lost)
 *     SMD_FAULT_FORCED       the forced (I/f) phase goes on for
 *                            forced_samples samples at or beyond the
 *                            handover speed (|w_f| >= w_handover): the
 *                            source never agreed to take over
 *     SMD_FAULT_CHATTER      the start-up supervisor switched between the
 *                            forced angle and the source more than
 *                            chatter_max times within about chatter_window
 *                            samples (a leaky count: +1 a switch, -chatter_max
 *                            / chatter_window a sample)
 *     SMD_FAULT_HUNTING      the speed PI's output (the q current reference)
 *                            swings from one limit to the other more than
 *                            hunt_max times within about hunt_window
 *                            samples (a leaky count: +1 a reversal, reaching
 *                            +i_max after -i_max or the other way round;
 *                            -hunt_max / hunt_window a sample): a speed
 *                            loop in a rail-to-rail limit cycle, the torque
 *                            reversing at full current, which a well-damped
 *                            loop does once per reference change; a
 *                            sensorless angle that wobbles beyond 90 deg
 *                            drives it there (issue 21)
 *     SMD_FAULT_START        start-up failed (a locked or pulled-out rotor):
 *                            in the forced phase above w_if_enter (else
 *                            w_handover / 2) the source's EMF estimate
 *                            disagrees with |w_f| psi_r_hat by more than
 *                            lock_ratio for lock_samples samples in a row
 *   warning (reported in the fault word while the condition holds; the drive
 *   runs on; the step returns SMD_OK)
 *     SMD_FAULT_RESTART      (the sample of) an automatic restart: with the
 *                            SMDO's position and an I/f start, a lost lock
 *                            or a failed start does not latch while fewer
 *                            than restart_max restarts were made within
 *                            about restart_window samples (a leaky count,
 *                            which leaks only while the drive runs on its
 *                            source: restarts that never hand over add up);
 *                            the drive restarts on I/f from rest at its last
 *                            angle (a stalled rotor, or one the brake
 *                            stopped, is started again), and latches the
 *                            fault when the count is spent; the sample of a
 *                            restart reports its cause's bit with it
 *     SMD_FAULT_ANGLE_JUMP   (the sample of) a jump of the SMDO's angle
 *                            (smdo_emf): on the source for more than
 *                            lock_samples, above w_lock_min (with the lock
 *                            check on), the angle moved by more than 45 deg
 *                            from the last one turned at the last speed; a
 *                            rotor cannot, an estimate that lost or flipped
 *                            its direction can (the LCL sources' PLL filters
 *                            their observer's angle: nothing jumps there);
 *                            the same sample latches SMD_FAULT_LOST_LOCK
 *                            (or restarts, as a lost lock does)
 *     SMD_FAULT_OSCILLATION  the ripple of the measured current, the RMS of
 *                            its change from one sample to the next in the
 *                            frame turning at the drive's speed, over
 *                            osc_samples samples, halved (the amplitude of a
 *                            limit cycle at half the sampling rate that has
 *                            it; white ADC noise of sigma a phase gives
 *                            about sigma), exceeds
 *                            osc_i + osc_rel |i_ref| for osc_samples samples
 *                            in a row (a deadbeat limit cycle from L_hat >
 *                            1.5 L, a diverging observer)
 *     SMD_FAULT_RLS_STALE    the R_s / psi_r tracker's R_s was not taken for
 *                            more than 2 rls_tau (smd_rls.h): no sample
 *                            counted, the fit could not tell it, or its
 *                            R_s was outside [0.5, 2.5] R_s_hat; the
 *                            estimate is its last (a warning: the drive
 *                            runs on; with the encoder its control law
 *                            does not read it, with the SMDO's angle the
 *                            SMDO and the robust DBPC have R_s_hat)
 * The step returns SMD_ERR_FAULT while any latched bit is set (SMD_ERR_NONFINITE
 * for an INTERNAL one).
 *
 * Speed reference: with a_ref > 0 the speed loop, the forced speed and the
 * return to I/f follow the reference slew-limited at a_ref (rad/s^2),
 * starting from the speed of smd_drive_reset; in the forced phase it is the
 * forced speed (a handover continues from there). An I/f start waits, with
 * no current, until the reference is not zero, and ramps toward its sign.
 * Start-up switches (handover and return to I/f) wait at least dwell
 * samples after the previous one.
 *
 * Through zero speed (sensorless): with w_if_enter > 0, a drive running on
 * a sensorless source whose speed falls below w_if_enter while the speed
 * reference is below w_handover in magnitude (or of the other sign) goes
 * back to the I/f forced mode at the speed it had: the forced speed follows
 * the reference at a_start, through zero, and the source takes over again
 * once |w| reaches w_handover in the reference's direction (hysteresis
 * w_if_enter < w_handover).
 *
 * Config (user-filled, SI units, electrical angles and speeds) is read once
 * by smd_drive_init into params (derived values); state changes every
 * sample. Nothing allocates; the tables of the LCL observers are owned by the
 * caller and must outlive the params.
 */
#ifndef SMD_DRIVE_H
#define SMD_DRIVE_H

#include "smd_dbpc.h"
#include "smd_emf_pos.h"
#include "smd_lcl_linobs.h"
#include "smd_lcl_smo.h"
#include "smd_pi.h"
#include "smd_pll.h"
#include "smd_rls.h"
#include "smd_smdo.h"
#include "smd_svm.h"
#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum smd_current_ctrl {
    SMD_CC_PI = 0,
    SMD_CC_DBPC = 1,
    SMD_CC_ROBUST_DBPC = 2
} smd_current_ctrl;

typedef enum smd_pos_source {
    SMD_POS_ENCODER = 0,
    SMD_POS_SMDO_EMF = 1,
    SMD_POS_LCL_SMO_PLL = 2,
    SMD_POS_LCL_LINEAR = 3
} smd_pos_source;

typedef enum smd_start_mode {
    SMD_START_RUNNING = 0,
    SMD_START_HANDOVER = 1,
    SMD_START_IF = 2
} smd_start_mode;

/* Phase of the start-up supervisor (smd_drive_view.phase). */
typedef enum smd_drive_phase {
    SMD_PHASE_FORCED = 0,  /* I/f: forced angle */
    SMD_PHASE_ENCODER = 1, /* handover: encoder while the observer converges */
    SMD_PHASE_SOURCE = 2   /* the configured position source */
} smd_drive_phase;

typedef struct smd_drive_config {
    /* @fuzz(...) after a field: the range the fuzz decoder draws it from
     * (fuzz/fz_drive_config.h, generated by tools/gen_layout.py) */
    /* parts */
    int current;          /* smd_current_ctrl @fuzz(0, 2) */
    int position;         /* smd_pos_source @fuzz(0, 3) */
    int start;            /* smd_start_mode @fuzz(0, 2) */
    int lcl;              /* 1: LCL filter between inverter and machine; i_1 is measured
                             @fuzz(0, 1) */
    smd_real T_sp;        /* sampling period, s @fuzz(1e-6, 1e-3) */
    /* model estimates (DBPC, SMDO, decoupling and EMF feed-forward of the PI) */
    smd_real L_s_hat;     /* machine inductance, H @fuzz(0, 0.1) */
    smd_real R_s_hat;     /* ohm @fuzz(0, 10) */
    smd_real psi_r_hat;   /* PM flux, Wb @fuzz(0, 1) */
    /* SMDO, yang2018 eq. (34)-(39) (robust_dbpc, smdo_emf) */
    smd_real lambda_min;  /* A/s @fuzz(0, 1e4) */
    smd_real l;           /* 1/s @fuzz(0, 1e4) */
    smd_real w_c;         /* rad/s @fuzz(0, 1e4) */
    smd_real rho;         /* A @fuzz(0, 10) */
    int smdo_euler;       /* 1: eq. (36) as printed (forward Euler); 0: exact rotation
                             @fuzz(0, 1) */
    /* position from the disturbance, eq. (44)-(45) (smdo_emf) */
    smd_real w_lpf;       /* speed LPF bandwidth, rad/s @fuzz(0, 2000) */
    smd_real w_hys;       /* direction hysteresis, rad/s @fuzz(0, 100) */
    smd_real w_max;       /* speed-estimate limit, rad/s (> w_hys) @fuzz(0, 3e4) */
    /* current PI (pi) */
    smd_real k_p_i;       /* V/A @fuzz(0, 10) */
    smd_real k_i_i;       /* V/(A s) @fuzz(0, 1e5) */
    smd_real L_dec;       /* inductance of the decoupling term j w L_dec i, H
                             (L1 + L2o + Ls with the LCL filter) @fuzz(0, 0.1) */
    int dec_ref;          /* 1: the decoupling term takes the current reference,
                             j w L_dec i_ref; 0: the measured current @fuzz(0, 1) */
    smd_real R_v;         /* virtual resistance on i_1 - i_2, V/A (LCL only; else 0)
                             @fuzz(0, 10) */
    int emf_ff;           /* 1: feed the source's EMF estimate forward @fuzz(0, 1) */
    /* speed loop */
    int speed_loop;       /* 1: i_q reference from the speed PI; 0: from the input
                             @fuzz(0, 1) */
    smd_real k_p_w;       /* A per electrical rad/s @fuzz(0, 1) */
    smd_real k_i_w;       /* A per electrical rad @fuzz(0, 100) */
    smd_real i_max;       /* current-reference limit (each axis), A @fuzz(0, 100) */
    int speed_decimation; /* the speed loop runs every this many samples, [1, 1000]
                             @fuzz(1, 1000) */
    /* PLL, yao2022 eq. (48), (50) (lcl_smo_pll, lcl_linear) */
    smd_real k_theta;     /* @fuzz(0, 2) */
    smd_real k_omega;     /* @fuzz(0, 1e3) */
    smd_real k_a;         /* @fuzz(0, 1e4) */
    /* LCL observers (lcl_smo_pll; lcl_linear) */
    smd_lcl_smo_config smo; /* @fuzz(fields): the law and gains; the grid and tables
                               from fz_lcl_tables */
    smd_linobs_config lin;  /* @fuzz(call fz_lcl_tables): one grid and the tables of
                               both observers, for an LCL source */
    /* start */
    int handover;         /* SMD_START_HANDOVER: samples on the encoder, >= 0 @fuzz(0, 2000) */
    smd_real i_start;     /* SMD_START_IF: current magnitude, A @fuzz(0, 100) */
    smd_real a_start;     /* forced acceleration, rad/s^2 @fuzz(0, 1e6) */
    smd_real w_handover;  /* speed at which the source takes over, rad/s @fuzz(0, 3e4) */
    /* modulator */
    int svm_limit;        /* smd_svm_limit @fuzz(0, 1) */
    smd_real t_dead_comp; /* dead time to compensate, s (0: off), [0, T_sp/4] @fuzz(0, 1e-4) */
    smd_real i_dtc;       /* current below which the compensation is linear, A (> 0)
                             @fuzz(0, 10) */
    /* protection (each 0: off) */
    smd_real i_trip;      /* overcurrent: peak phase current, A @fuzz_flag @fuzz(0, 200) */
    smd_real u_dc_min;    /* DC-link undervoltage, V @fuzz(0, 600) */
    smd_real u_dc_max;    /* DC-link overvoltage, V @fuzz(0, 1000) */
    int safe_state;       /* smd_safe_state @fuzz(0, 1) */
    int lock_samples;     /* loss of lock after this many implausible samples, [0, 1e6]
                             @fuzz(0, 2000) */
    smd_real lock_ratio;  /* EMF plausibility band [1/r, r], r > 1 @fuzz(0, 10) */
    smd_real w_lock_min;  /* no EMF check below this |w_hat|, rad/s @fuzz(0, 1000) */
    smd_real w_if_enter;  /* sensorless below this |w| returns to I/f, rad/s (0: never)
                             @fuzz(0, 1000) */
    /* reference shaping and supervision (the header comment; each 0: off) */
    smd_real a_ref;       /* speed-reference slew-rate limit, rad/s^2 @fuzz(0, 1e6) */
    int dwell;            /* least samples in a start-up phase before the next switch
                             @fuzz(0, 2000) */
    int chatter_max;      /* SMD_FAULT_CHATTER: more switches than this ... @fuzz(0, 20) */
    int chatter_window;   /* ... within (about) this many samples @fuzz(0, 20000) */
    int hunt_max;         /* SMD_FAULT_HUNTING: more limit-to-limit reversals of the speed
                             PI than this ... @fuzz(0, 20) */
    int hunt_window;      /* ... within (about) this many samples @fuzz(0, 20000) */
    int track_samples;    /* SMD_FAULT_SPEED_TRACKING after this many samples ...
                             @fuzz(0, 20000) */
    smd_real w_track;     /* ... farther than this from the reference at the current limit, rad/s
                             @fuzz(0, 3e4) */
    int forced_samples;   /* SMD_FAULT_FORCED: forced this long at |w_f| >= w_handover
                             @fuzz(0, 20000) */
    smd_real osc_i;       /* SMD_FAULT_OSCILLATION: ripple beyond osc_i ... , A @fuzz(0, 10) */
    smd_real osc_rel;     /* ... + osc_rel |i_ref| ... @fuzz(0, 1) */
    int osc_samples;      /* ... over this many samples (the filter's time constant)
                             @fuzz(0, 2000) */
    int restart_max;      /* SMDO source with an I/f start: restart from rest on I/f after
                             a lost lock or a failed start, at most this many times ...
                             @fuzz(0, 5) */
    int restart_window;   /* ... within (about) this many samples (0: no restart)
                             @fuzz(0, 20000) */
    int supervise_every;  /* the supervision's three pieces (loss of lock, the criteria
                             above, the state's finiteness) each run once every this many
                             samples, one piece a sample, their counts kept in samples
                             (0 and 1: every piece every sample, as before; [0, 64]; an
                             angle jump, the trips and the duties' finiteness are still
                             checked every sample) @fuzz(0, 64) */
    /* online R_s / psi_r tracker (smd_rls.h; with the encoder only, not with the LCL
     * filter: SMD_ERR_RLS otherwise) */
    smd_real rls_i_inj;   /* injected d-axis current amplitude, A (0: no tracker)
                             @fuzz(0, 10) */
    smd_real rls_tau;     /* forgetting time constant, s @fuzz(0, 10) */
    int rls_half;         /* samples per half period of the injection @fuzz(0, 2000) */
    smd_real rls_w_min;   /* psi_r fitted only at |w| >= this, rad/s @fuzz(0, 1000) */
} smd_drive_config;

typedef enum smd_safe_state {
    SMD_SAFE_ZERO_VECTOR = 0,
    SMD_SAFE_PWM_OFF = 1
} smd_safe_state;

/* Bits of smd_drive_out.fault (see the header comment). */
enum {
    SMD_FAULT_INPUT = 1u << 0,
    SMD_FAULT_INTERNAL = 1u << 1,
    SMD_FAULT_OVERCURRENT = 1u << 2,
    SMD_FAULT_UNDERVOLTAGE = 1u << 3,
    SMD_FAULT_OVERVOLTAGE = 1u << 4,
    SMD_FAULT_LOST_LOCK = 1u << 5,
    SMD_FAULT_SPEED_TRACKING = 1u << 6,
    SMD_FAULT_FORCED = 1u << 7,
    SMD_FAULT_CHATTER = 1u << 8,
    SMD_FAULT_OSCILLATION = 1u << 9,
    SMD_FAULT_START = 1u << 10,
    SMD_FAULT_RESTART = 1u << 11,
    SMD_FAULT_ANGLE_JUMP = 1u << 12,
    SMD_FAULT_HUNTING = 1u << 13,
    SMD_FAULT_RLS_STALE = 1u << 14
};
#define SMD_FAULT_LATCHED (SMD_FAULT_OVERCURRENT | SMD_FAULT_UNDERVOLTAGE | \
                           SMD_FAULT_OVERVOLTAGE | SMD_FAULT_LOST_LOCK | \
                           SMD_FAULT_SPEED_TRACKING | SMD_FAULT_FORCED | SMD_FAULT_CHATTER | \
                           SMD_FAULT_START | SMD_FAULT_HUNTING)
/* warnings: reported while their condition holds, the drive runs on */
#define SMD_FAULT_WARNINGS (SMD_FAULT_OSCILLATION | SMD_FAULT_RESTART | SMD_FAULT_ANGLE_JUMP | \
                            SMD_FAULT_RLS_STALE)

typedef struct smd_drive_params {
    int current, position, start, lcl;
    smd_real T_sp;
    int use_smdo;         /* derived: the SMDO runs (robust_dbpc or smdo_emf) */
    int speed_loop, speed_decimation, handover, emf_ff, dec_ref;
    smd_real k_p_i, k_i_i, L_dec, R_v, psi_r_hat, i_max;
    smd_real i_start, a_start, w_handover;
    smd_real dtc_ratio;   /* t_dead_comp / T_sp */
    smd_real i_dtc;
    smd_real inv_i_dtc;   /* 1 / i_dtc (the fast build's compensation) */
    smd_real i_trip, u_dc_min, u_dc_max, lock_ratio, w_lock_min, w_if_enter;
    /* the inputs' plain case as bit patterns (float build, inputs_plain in
     * smd_drive.c): twice the bits of the phase currents' bound, min(1e5,
     * i_trip); the DC link's lowest pattern and the span of its patterns */
    uint32_t plain_i2, plain_ulo, plain_uspan;
    int safe_state, lock_samples;
    smd_real w_src_max;   /* largest |w| the sensorless source can estimate */
    smd_real R_hat, L_hat; /* the steady state of a (warm) start: R_s_hat, L_dec or L_s_hat */
    smd_real a_ref, w_track, osc_i, osc_rel;
    smd_real if_lag;        /* a_ref / w_lpf with the SMDO's speed (else 0): its estimate's lag
                             * behind a rotor on the slewed reference (return_to_forced) */
    smd_real chatter_decay; /* chatter_max / chatter_window */
    smd_real hunt_decay;  /* hunt_max / hunt_window */
    smd_real osc_k;       /* 1 / osc_samples (0: off) */
    int dwell, chatter_max, hunt_max, track_samples, forced_samples, osc_samples, restart_max;
    smd_real restart_decay; /* restart_max / restart_window */
    int sup_n;            /* supervise_every, at least 1 */
    int sup_fin, sup_rip; /* the finiteness's and the ripple's pieces: 2, 3 mod sup_n */
    smd_dbpc_params dbpc;
    smd_smdo_params smdo;
    smd_emf_pos_params emf;
    smd_pi_params speed_pi;
    smd_pll_params pll;
    smd_lcl_smo_params smo;
    smd_linobs_params lin;
    smd_svm_params svm;
    int use_rls;          /* the R_s / psi_r tracker runs (rls_i_inj > 0) */
    smd_rls_params rls;
    smd_real R_fb_max;    /* with the SMDO's angle: the largest R_s of the tracker's the
                           * SMDO takes, ohm (smd_drive_init) */
} smd_drive_params;

typedef struct smd_drive_in {
    smd_real i_a, i_b;    /* motor phase currents from the ADC, A (i_2 with the filter) */
    smd_real i1_a, i1_b;  /* inverter-side phase currents, A (LCL only) */
    smd_real theta_enc;   /* encoder electrical angle, rad */
    smd_real w_enc;       /* encoder electrical speed, rad/s */
    smd_real u_dc;        /* DC-link voltage, V */
    smd_real w_ref;       /* electrical speed reference, rad/s (speed loop on) */
    smd_cplx i_dq_ref;    /* current reference; only i_d used when the speed loop is on */
} smd_drive_in;

typedef struct smd_drive_out {
    smd_real d_abc[3];    /* duty ratios to apply during the next period, in [0, 1] */
    uint32_t fault;       /* SMD_FAULT_* bits: the latched ones and this sample's */
    int pwm_off;          /* 1: switch every device off (a fault with SMD_SAFE_PWM_OFF) */
} smd_drive_out;

/* Position-source state: a tagged union on params.position (the PLL is
 * shared by the two LCL observers). */
typedef struct smd_pos_state {
    smd_real theta_err;   /* LCL sources: angle error of eq. (47) at k, rad */
    smd_pll_state pll;
    union {
        smd_emf_pos_state emf;
        smd_lcl_smo_state smo;
        smd_linobs_state lin;
    } u;
} smd_pos_state;

typedef struct smd_drive_state {
    int phase;            /* smd_drive_phase */
    int samples;          /* samples run on the encoder (handover) */
    int count;            /* speed-loop decimation counter */
    int torque_in;        /* 1: the q reference from the input with the speed loop on
                             (smd_drive_set_torque_in) */
    int primed;           /* 0 until the first sample has initialised the SMDO */
    smd_real theta;       /* frame angle for sample k (predicted at k-1 for the PLL
                             sources and the forced angle), rad */
    smd_real w;           /* frame speed for sample k, rad/s */
    smd_real theta_k;     /* angle used at the last step, rad */
    smd_real w_k;         /* speed used at the last step, rad/s */
    smd_real theta_f, w_f; /* forced angle and speed (I/f) */
    uint32_t fault;       /* latched fault bits */
    int lock_count;       /* the source's implausible samples, leaky, in quarters */
    int dir_f;            /* forced mode: 0 the start's ramp; +-1 following the reference
                             (a return to I/f), the sign of its current */
    int start_dir;        /* the start's ramp: +-1 the reference's sign at its first
                             sample, 0 before it */
    int have_last;        /* 1 once a sample had good inputs */
    smd_drive_in last_in; /* the last good inputs (a bad sample runs on them) */
    smd_cplx i_s_ab;      /* last measured motor current */
    smd_cplx i_dq;        /* last measured motor current in the frame used (PI only) */
    smd_cplx i_dq_ref;    /* last current reference */
    smd_cplx x_i;         /* current PI integrators, V */
    smd_cplx u_ab;        /* voltage applied during [k, k+1) (after limiting) */
    smd_cplx u_ab_next;   /* voltage for [k+1, k+2) (after limiting) */
    smd_cplx u_ab_ref;    /* last unlimited reference */
    smd_pi_state speed_pi;
    smd_smdo_state smdo;
    smd_pos_state pos;
    /* reference shaping and supervision */
    smd_real w_ref_r;     /* the slew-limited speed reference, rad/s */
    int phase_samples;    /* samples since the last start-up phase switch */
    smd_real chatter;     /* leaky count of phase switches */
    smd_real hunt;        /* leaky count of the speed PI's limit-to-limit reversals */
    int hunt_rail;        /* the limit the speed PI reached last: +1, -1, 0 none yet */
    int track_count;      /* consecutive samples away from the reference at the limit */
    int forced_count;     /* samples forced with |w_ref| >= w_handover */
    int start_count;      /* consecutive forced samples whose EMF disagrees with w_f */
    int osc_count;        /* consecutive samples with the ripple beyond its bound */
    int osc_n;            /* measured currents seen (the difference needs 2) */
    smd_real osc_ms;      /* filtered |difference of the current, turning frame|^2, A^2 */
    smd_cplx i_prev1;     /* measured current of k-1 */
    uint32_t warn;        /* warning bits of the last sample (SMD_FAULT_WARNINGS) */
    uint32_t warn_rls;    /* SMD_FAULT_RLS_STALE while the tracker's R_s is stale (smd_rls.h) */
    smd_real R_smdo;      /* the SMDO's (and the robust DBPC's) R_s, ohm: R_s_hat, or the
                           * tracker's with the SMDO's angle (smd_drive.c) */
    smd_real restarts;    /* leaky count of automatic restarts */
    int jumped;           /* 1: the source's angle jumped this sample */
    int sup_k;            /* the supervision's piece due (supervise_every > 1) */
    smd_rls_state rls;    /* the R_s / psi_r tracker */
    int u_whole;          /* tracker: the voltage of the running period, u_ab, is applied
                             whole (not limited, no duty clipped) */
    smd_cplx du_clip;     /* what the inverter applies of u_ab_next less u_ab_next, where
                             the dead-time compensation's duty was clipped at 0 or 1 (0
                             elsewhere); read with u_ab by the SMDO before it is renewed */
} smd_drive_state;

/* Read-only view of the controller's internals for logging. */
typedef struct smd_drive_view {
    smd_cplx i_dq_ref;
    smd_cplx i_dq;        /* PI: the measured current in its frame (0 with DBPC) */
    smd_cplx u_ab;        /* voltage commanded for the next period (after the limit) */
    smd_cplx u_ab_ref;
    smd_cplx i_s_hat;     /* SMDO current prediction (0 without SMDO) */
    smd_cplx u_d_hat;     /* SMDO disturbance estimate (0 without SMDO) */
    smd_real theta;       /* angle used at k */
    smd_real w;           /* speed used at k */
    smd_real lambda;      /* SMDO adapted gain */
    smd_real theta_err;   /* LCL sources: eq. (47) */
    smd_cplx e_hat;       /* LCL sliding-mode observer: EMF, controller frame */
    smd_cplx s;           /* its switching function s(k), eq. (18) */
    smd_cplx d_hat;       /* its periodic-disturbance compensation, eq. (35) */
    smd_cplx v;           /* its disturbance part v(k-1) */
    smd_cplx e_lin;       /* linear observer: EMF, stationary frame */
    smd_real R_s_rls;     /* the tracker's R_s estimate, ohm (0 without it) */
    smd_real psi_rls;     /* its psi_r estimate, Wb (0 without it) */
    int phase;            /* smd_drive_phase */
    uint32_t fault;       /* latched fault bits */
} smd_drive_view;

smd_status smd_drive_init(smd_drive_params *p, const smd_drive_config *cfg);
/* Start from rest or from a known running state (a flying start): theta0,
 * w0 seed the frame and the observers; i_q0 the speed-loop integrator (the
 * current that carries the load: a warm start). With SMD_START_IF the
 * forced angle starts at theta0 with speed w0. */
void smd_drive_reset(const smd_drive_params *p, smd_drive_state *s, smd_real theta0,
                     smd_real w0, smd_real i_q0);
/* The duties of the period before the first sample, [t_0, t_1): the
 * steady-state voltage of the initial condition smd_drive_reset was given
 * (model estimates: (R_hat + j w L_hat) j i_q0 + j w psi_r_hat in the frame
 * of theta0, at the middle of the period), limited by the modulator at u_dc;
 * the state records it as the voltage applied then (a warm or flying start
 * applies it from t_0 instead of the zero vector; at standstill without
 * current it is the zero vector, duties 0.5). */
void smd_drive_start_duties(const smd_drive_params *p, smd_drive_state *s, smd_real u_dc,
                            smd_real d_abc[3]);
/* One sample. A NULL argument returns SMD_ERR_NULL (a non-NULL out then
 * holds the safe state's duties). */
smd_status smd_drive_step(const smd_drive_params *p, smd_drive_state *s, const smd_drive_in *in,
                          smd_drive_out *out);
smd_drive_view smd_drive_get_view(const smd_drive_params *p, const smd_drive_state *s);
/* Clear the latched faults (SMD_FAULT_LATCHED); the drive stays in the safe
 * state only while a cause persists. Restart with smd_drive_reset. */
void smd_drive_clear_faults(smd_drive_state *s);
/* on != 0: from the next sample the q-axis current reference is the input's
 * i_dq_ref.im even with the speed loop on (torque control, e.g. a coast at
 * zero current: commissioning's step 4); the speed PI holds its integral
 * and takes over again at on = 0. Kept through the drive's recovery from a
 * non-finite value and its restarts; cleared by smd_drive_reset. */
void smd_drive_set_torque_in(smd_drive_state *s, int on);

#ifdef __cplusplus
}
#endif

#endif

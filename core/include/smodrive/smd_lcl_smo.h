/*
 * Discrete-time sliding-mode back-EMF observer for an LCL-filtered SPMSM,
 * yao2022 Sec. III-V: observer (9) in the estimated rotor frame, augmented
 * sliding surface (16), (18), chattering-suppression reaching law (33) with
 * EMF adaption (34) and band-pass periodic-disturbance suppression (35) at
 * 2 f_e and 3 f_e; or, for comparison, the time-delay reaching laws of
 * refs. [17] (eq. (31), (61)-(63)) and [18] (eq. (32)).
 *
 * The speed-dependent matrices are designed offline (smodrive.design.yao2022)
 * on a uniform grid of electrical speed and interpolated linearly here.
 *
 * Timing per sample k (the caller supplies the frame angle theta_hat(k) and
 * speed w_hat(k) it uses, e.g. from the PLL): currents i_1(k), i_2(k) in the
 * stationary frame, the voltage u(k) applied over [k, k+1) in the stationary
 * frame; the step computes e_hat(k) and advances x_hat to k+1 in a frame
 * advanced by w_hat T. If the caller's next frame differs (a PLL correction),
 * it calls smd_lcl_smo_reframe with the difference before the next step.
 */
#ifndef SMD_LCL_SMO_H
#define SMD_LCL_SMO_H

#include "smd_bandpass.h"
#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Matrices at one speed, row-major. @design(...) names the field of the
 * offline design (smodrive.design.observer_layout) each array holds, or its
 * block [rows, cols]; the binding packs the tables by it (tools/gen_layout.py). */
typedef struct smd_lcl_model {
    smd_real G[36];  /* 6x6, eq. (7) @design(G) */
    smd_real H[12];  /* 6x2, eq. (7) (input matrix) @design(H) */
    smd_real F[12];  /* 6x2, eq. (7) (EMF matrix) @design(F) */
    smd_real Ft[16]; /* 4x4: [y1; y2] = Ft [i1_err; i2_err], lower block of T_r, eq. (14)-(15)
                        @design(T_r[2:6, 2:6]) */
    smd_real Hc[4];  /* augmented state matrix H of eq. (16), (21) @design(H_c) */
    smd_real D1[4];  /* eq. (16), (21) @design(D1) */
    smd_real D2[4];  /* @design(D2) */
    smd_real Gam_c[4]; /* eq. (18) @design(Gamma_c) */
    smd_real Gam_1[4]; /* @design(Gamma_1) */
    smd_real Gam_2[4]; /* @design(Gamma_2) */
    smd_real Gs[4];  /* reaching-mode matrix of eq. (28) @design(G_s) */
    smd_real Kc[4];  /* equivalent control G_c x_c + G_y y1 + G_u x_u_hat with @design(K_c) */
    smd_real Ky[4];  /* x_u_hat = x_c - L y1 (eq. (23)): Kc x_c + Ky y1 (errata) @design(K_y) */
    smd_real k;      /* EMF adaption gain of eq. (34), (51); also the low-pass (63) @design(k) */
} smd_lcl_model;

#define SMD_LCL_SMO_DELAY 256 /* longest band-pass delay line, samples */

typedef enum smd_lcl_smo_law {
    SMD_LCL_SMO_PROPOSED = 0, /* eq. (33)-(35) */
    SMD_LCL_SMO_TDE17 = 1,    /* ref. [17]: eq. (61)-(63), compensation error (31) */
    SMD_LCL_SMO_TDE18 = 2     /* ref. [18]: compensation error (32), low-pass (63) */
} smd_lcl_smo_law;

/* What init needs besides the sampling period (the table is owned by the
 * caller and must outlive the params). */
typedef struct smd_lcl_smo_config {
    int law;                    /* smd_lcl_smo_law @fuzz(0, 2) */
    const smd_lcl_model *table; /* n models at w = w_min + k dw (electrical rad/s)
                                   @fuzz(none) */
    int n;                      /* >= 2 @fuzz(none) */
    smd_real w_min;             /* rad/s @fuzz(none) */
    smd_real dw;                /* rad/s, > 0 @fuzz(none) */
    smd_real Q1;                /* diagonal of Q, eq. (33), in [-0.999, 0.999] @fuzz(-1, 1) */
    smd_real Q2;                /* the same @fuzz(-1, 1) */
    smd_real bw_rel2;           /* -3 dB bandwidth of the 2 f_e band-pass as a fraction
                                   of f_e (Omega = bw_rel |w|), in (0, 2] @fuzz(0, 2) */
    smd_real bw_rel3;           /* the same for the 3 f_e band-pass @fuzz(0, 2) */
    smd_real w_bp_min;          /* band-pass suppression active above this |w|, rad/s
                                   @fuzz(0, 5000) */
    int decimation;             /* the model, the band-pass coefficients and the delay
                                   taps are recomputed every this many samples, [0, 64]
                                   (0 and 1: every sample, the method as published; more:
                                   the fast build's option, docs/firmware.md); from 4 on the
                                   work is spread, one piece a sample: the model in two
                                   parts (four from 6 on), then each harmonic channel
                                   (from 8 on its band-pass coefficients and its taps on
                                   samples of their own) @fuzz(-1, 70) */
} smd_lcl_smo_config;

typedef struct smd_lcl_smo_params {
    smd_real T_sp;
    int law;
    const smd_lcl_model *table;
    int n;
    smd_real w_min;
    smd_real dw;
    smd_real Q1, Q2;
    smd_real bw_rel2, bw_rel3;
    smd_real w_bp_min;
    int decimation;              /* >= 1 */
} smd_lcl_smo_params;

/* A harmonic channel's delay-line taps of eq. (35), kept between refreshes. */
typedef struct smd_lcl_smo_taps {
    smd_real a, b; /* v(k - D) = a v(k - n) + b v(k - n - 1) */
    int n;
    int ok;        /* 0: the channel is off (delay out of the line, band-pass refused) */
} smd_lcl_smo_taps;

typedef struct smd_lcl_smo_state {
    smd_real x_hat[6];   /* [u_c, i_1, i_2] estimates, gamma-delta frame */
    smd_real x_c[2];     /* augmented state, eq. (16) */
    smd_real s[2];       /* switching function s(k), eq. (18) */
    smd_real y[4];       /* canonical outputs [y1; y2](k), eq. (13) */
    smd_real s_prev[2];  /* s(k-1) */
    smd_real w_att[2];   /* attraction function w(k), eq. (33) */
    smd_real v_prev[2];  /* disturbance part v(k-1) of w (w = equivalent part + v) */
    smd_real D1[2];      /* lumped disturbance D(k-1) = s(k) - Q s(k-1) - v(k-1) */
    smd_real D2[2];      /* D(k-2) */
    smd_real e_hat[2];   /* EMF estimate, gamma-delta frame, V */
    smd_real d_hat[2];   /* periodic-disturbance compensation, eq. (35) */
    smd_real theta_prev; /* frame angle of the previous call */
    smd_cplx v_hist[SMD_LCL_SMO_DELAY]; /* v(k) = s(k) - Q s(k-1) + d_hat(k-1), eq. (35) */
    int v_head;
    smd_bandpass bp2, bp3;
    int primed;
    smd_lcl_model m;     /* the model at the last refresh */
    smd_lcl_smo_taps taps2, taps3;
    int age;             /* samples since the last refresh began (0: begin now) */
    smd_real w_m;        /* the speed of the refresh under way */
    int m_ok;            /* 0: the next refresh is a whole one (after a reset) */
    int defer;           /* 1: the next step does no piece of a spread refresh and does
                            not move it on (a caller's held sample: smd_drive_step);
                            the step clears it */
} smd_lcl_smo_state;

/* T_sp: the sampling period, s, in (0, 1]. */
smd_status smd_lcl_smo_init(smd_lcl_smo_params *p, smd_real T_sp, const smd_lcl_smo_config *c);
void smd_lcl_smo_reset(smd_lcl_smo_state *s, smd_real theta0);
/* The model and the harmonic channels' band-pass coefficients and taps at
 * w_hat (electrical rad/s), at once: for a reset outside the sampling
 * interrupt, so that a decimated refresh's first step is not a whole one
 * (smd_drive_reset calls it with decimation >= 4). Without a table or with a
 * non-finite w_hat it does nothing, and the first step refreshes all. */
void smd_lcl_smo_prime(const smd_lcl_smo_params *p, smd_lcl_smo_state *s, smd_real w_hat);

/* Interpolate the model at electrical speed w (clamped to the table). */
void smd_lcl_smo_model(const smd_lcl_smo_params *p, smd_real w, smd_lcl_model *m);

/* One sample; returns the EMF estimate e_hat(k) (gamma-delta frame). */
smd_status smd_lcl_smo_step(const smd_lcl_smo_params *p, smd_lcl_smo_state *s, smd_cplx i1_ab,
                            smd_cplx i2_ab, smd_cplx u_ab, smd_real theta_hat, smd_real w_hat);
/* The same with r = e^{-j theta_hat} given (a caller that has e^{j theta_hat}
 * for its own transforms takes the sines once: the bits of
 * smd_lcl_smo_step with r = conj(smd_cexpj(theta_hat))). */
smd_status smd_lcl_smo_step_r(const smd_lcl_smo_params *p, smd_lcl_smo_state *s,
                              smd_cplx i1_ab, smd_cplx i2_ab, smd_cplx u_ab, smd_cplx r,
                              smd_real theta_hat, smd_real w_hat);

/* The two halves of a step (public so that each can be costed, Table VI):
 * the reaching law (switching function (18), law (33)-(35) or the TDE
 * baselines) on the currents in the estimated frame, then the current
 * prediction (observer (9) and augmented state (16)) with the voltage in
 * that frame. smd_lcl_smo_step = model + reach + predict. */
void smd_lcl_smo_reach(const smd_lcl_smo_params *p, smd_lcl_smo_state *s,
                       const smd_lcl_model *m, smd_cplx i1_gd, smd_cplx i2_gd, smd_real w_hat);
void smd_lcl_smo_predict(const smd_lcl_model *m, smd_lcl_smo_state *s, smd_cplx u_gd);

/* The frame of the next sample is advanced by dth beyond w_hat T: express
 * the state estimates (x_hat, e_hat) in it. */
void smd_lcl_smo_reframe(smd_lcl_smo_state *s, smd_real dth);

/* Position error of eq. (47): atan(-e_gamma / e_delta), sign-corrected for
 * negative speed (e_delta < 0 when w < 0). */
smd_real smd_lcl_smo_theta_err(const smd_lcl_smo_state *s, smd_real w_hat);

#ifdef __cplusplus
}
#endif

#endif

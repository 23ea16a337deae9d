/*
 * smodrive real-time core: scalar type, complex space vectors, status codes.
 *
 * C99, no allocation, no stdio, no globals. The real type is float unless the
 * build defines SMD_REAL_DOUBLE (analysis builds); every literal goes through
 * SMD_R() so that the float build is free of implicit double promotion.
 * Every public header can be included from C++ (extern "C").
 *
 * Math hooks (float build). The core calls its elementary functions only
 * through SMD_SIN, SMD_COS, SMD_SQRT, SMD_ATAN2, SMD_FABS, SMD_EXP, SMD_EXPM1
 * and SMD_FLOOR, which the float build maps to SMD_SINF, SMD_COSF, SMD_SQRTF,
 * SMD_ATAN2F, SMD_FABSF, SMD_EXPF, SMD_EXPM1F and SMD_FLOORF: by default the
 * C library's sinf, cosf, ... A firmware may define any of them on the
 * compiler's command line, e.g. for CMSIS-DSP
 *     -DSMD_MATH_HEADER='"arm_math.h"' -DSMD_SINF=arm_sin_f32 -DSMD_COSF=arm_cos_f32
 * or to its own functions (a CORDIC unit, tables); SMD_MATH_HEADER, if
 * defined, is included after <math.h> for their declarations. Each must take
 * and return float with the libm function's meaning (SMD_ATAN2F(y, x)). The
 * same definitions must be seen by the library and by every file that
 * includes these headers (inline helpers below call SMD_SIN, SMD_COS,
 * SMD_SQRT, SMD_FLOOR). The results then differ from the host build (the
 * simulator and the tests use the C library's functions); by how much, for
 * the drive at hand, is the user's to check. See docs/firmware.md.
 *
 * IEEE 754 semantics are required: the drive catches non-finite inputs and
 * internal values (smd_drive.h, faults), and under -ffast-math or
 * -ffinite-math-only the compiler may take every isfinite() as true and
 * remove those checks, so such a build is refused here.
 */
#ifndef SMD_TYPES_H
#define SMD_TYPES_H

#if defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "smodrive core: compile without -ffast-math / -ffinite-math-only (its NaN and inf checks need IEEE 754 semantics)"
#endif

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#ifdef SMD_MATH_HEADER
#include SMD_MATH_HEADER
#endif

#ifdef __cplusplus
extern "C" {
#endif

#ifndef SMD_SINF
#define SMD_SINF sinf
#endif
#ifndef SMD_COSF
#define SMD_COSF cosf
#endif
#ifndef SMD_SQRTF
#define SMD_SQRTF sqrtf
#endif
#ifndef SMD_ATAN2F
#define SMD_ATAN2F atan2f
#endif
#ifndef SMD_FABSF
#define SMD_FABSF fabsf
#endif
#ifndef SMD_EXPF
#define SMD_EXPF expf
#endif
#ifndef SMD_EXPM1F
#define SMD_EXPM1F expm1f
#endif
#ifndef SMD_FLOORF
#define SMD_FLOORF floorf
#endif

#ifdef SMD_REAL_DOUBLE
typedef double smd_real;
#define SMD_R(x) ((smd_real)(x))
#define SMD_SIN sin
#define SMD_COS cos
#define SMD_SQRT sqrt
#define SMD_ATAN2 atan2
#define SMD_FABS fabs
#define SMD_EXP exp
#define SMD_EXPM1 expm1
#define SMD_FLOOR floor
#else
typedef float smd_real;
#define SMD_R(x) ((smd_real)(x))
#define SMD_SIN SMD_SINF
#define SMD_COS SMD_COSF
#define SMD_SQRT SMD_SQRTF
#define SMD_ATAN2 SMD_ATAN2F
#define SMD_FABS SMD_FABSF
#define SMD_EXP SMD_EXPF
#define SMD_EXPM1 SMD_EXPM1F
#define SMD_FLOOR SMD_FLOORF
#endif

#define SMD_PI SMD_R(3.14159265358979323846)
#define SMD_TWO_PI SMD_R(6.28318530717958647692)
#define SMD_SQRT3 SMD_R(1.73205080756887729353)
#define SMD_INV_SQRT3 SMD_R(0.57735026918962576451)

/* A block's step that the drive calls once a sample: inlined into the
 * drive's step where the composition is fixed at compile time (SMD_FIX_*,
 * smd_drive.h; GCC and Clang, the core built as one unit), which then runs
 * the block's code without a call's saved registers and arguments; an
 * ordinary external function elsewhere (one copy for every composition of
 * the generic drive). */
#if defined(__GNUC__) && defined(SMD_FIX_POSITION)
#define SMD_FIXED_INLINE __attribute__((always_inline)) inline
#else
#define SMD_FIXED_INLINE
#endif

/* Status returned by every init and setter. Each parameter error names the
 * offending field so that a caller (or the Python binding) can report it;
 * @scenario(...) lists the fields of a smodrive scenario behind an init's
 * refusal (tools/gen_layout.py writes them into the binding). */
typedef enum smd_status {
    SMD_OK = 0,
    SMD_ERR_NULL = 1,          /* a pointer argument is NULL */
    SMD_ERR_TS = 2,            /* sampling period T_sp not in (0, 1] s @scenario(T_sp) */
    SMD_ERR_L = 3,             /* inductance estimate not in (0, 10] H
                                  @scenario(controller.L_s_hat) */
    SMD_ERR_R = 4,             /* resistance estimate not in [0, 1000] ohm
                                  @scenario(controller.R_s_hat) */
    SMD_ERR_PSI = 5,           /* PM flux estimate not in [0, 100] Wb
                                  @scenario(controller.psi_r_hat) */
    SMD_ERR_LAMBDA = 6,        /* SMDO lambda_min not in [0, 1e7] A/s
                                  @scenario(controller.lambda_min) */
    SMD_ERR_L_GAIN = 7,        /* SMDO proportional gain l not in (0, 1e7] 1/s
                                  @scenario(controller.l) */
    SMD_ERR_WC = 8,            /* SMDO filter gain omega_c not in (0, 1e7] rad/s
                                  @scenario(controller.w_c) */
    SMD_ERR_RHO = 9,           /* SMDO boundary layer rho not in (0, 1e3] A
                                  @scenario(controller.rho) */
    SMD_ERR_KP = 10,           /* PI proportional gain not in [0, 1e6]
                                  @scenario(controller.speed_bw, controller.J_hat,
                                  controller.psi_r_pi, motor.n_p, controller.k_theta,
                                  controller.k_omega, controller.k_a) */
    SMD_ERR_KI = 11,           /* PI integral gain not in [0, 1e9]
                                  @scenario(controller.speed_bw, controller.J_hat,
                                  controller.psi_r_pi, motor.n_p, controller.k_theta,
                                  controller.k_omega, controller.k_a) */
    SMD_ERR_LIMIT = 12,        /* a limit is not positive and finite
                                  @scenario(controller.i_max, controller.bw_rel,
                                  controller.w_M_bp_min) */
    SMD_ERR_MODE = 13,         /* unknown mode or enumeration value
                                  @scenario(controller.current, controller.position,
                                  controller.start, controller.law, inverter.svm_limit) */
    SMD_ERR_STABILITY = 14,    /* the discrete loop would be unstable
                                  @scenario(controller.l, controller.lambda_min,
                                  controller.rho, controller.w_c, controller.w_M_max,
                                  controller.Q, T_sp, controller.k_theta, controller.k_omega,
                                  controller.k_a) */
    SMD_ERR_WLPF = 15,         /* speed low-pass bandwidth not in (0, pi/T_sp)
                                  @scenario(controller.w_lpf, T_sp) */
    SMD_ERR_NONFINITE = 16,    /* a step produced NaN or Inf; outputs were zeroed */
    SMD_ERR_DECIMATION = 17,   /* speed-loop decimation not in [1, 1000], or the LCL
                                  observer's refresh decimation or the supervision's
                                  spread not in [0, 64]
                                  @scenario(controller.speed_decimation,
                                  controller.smo_decimation, controller.supervise_every) */
    SMD_ERR_WHYS = 18,         /* direction hysteresis not in [0, 1e5] rad/s
                                  @scenario(controller.w_hys) */
    SMD_ERR_WMAX = 19,         /* speed-estimate limit not in (w_hys, pi/T_sp] rad/s
                                  @scenario(controller.w_M_max, controller.w_hys, motor.n_p,
                                  T_sp) */
    SMD_ERR_DEADTIME = 20,     /* dead-time compensation not in [0, T_sp/4], or i_dtc <= 0
                                  @scenario(controller.t_dead_comp, controller.i_dtc, T_sp) */
    SMD_ERR_HANDOVER = 21,     /* handover sample count negative
                                  @scenario(controller.t_handover) */
    SMD_ERR_DMIN = 22,         /* minimum duty not in [0, 0.49] */
    SMD_ERR_TABLE = 23,        /* observer table: fewer than 2 entries, or bad grid
                                  @scenario(controller.position, lcl, T_sp) */
    SMD_ERR_COMBINATION = 24,  /* the drive's parts do not fit together (smd_drive.h)
                                  @scenario(controller.current, controller.position,
                                  controller.R_v, lcl) */
    SMD_ERR_CURRENT_PI = 25,   /* current PI: k_p_i, k_i_i, L_dec or R_v out of range
                                  @scenario(controller.current_bw, controller.k_p_i,
                                  controller.k_i_i, controller.L_dec, controller.R_v) */
    SMD_ERR_START = 26,        /* start-up: i_start, a_start or w_handover out of range
                                  @scenario(controller.i_start, controller.a_M_start,
                                  controller.w_M_handover, T_sp) */
    SMD_ERR_PROTECTION = 27,   /* protection or loss-of-lock setting out of range
                                  @scenario(controller.i_trip, controller.u_dc_min_ratio,
                                  controller.u_dc_max_ratio, controller.safe_state,
                                  controller.t_lock, controller.lock_ratio,
                                  controller.w_M_lock_min, controller.w_M_if_enter,
                                  inverter.u_dc) */
    SMD_ERR_FAULT = 28,        /* a step: a fault is active, the outputs are the safe state
                                  (smd_drive_out.fault says which) */
    SMD_ERR_IDENT = 29,        /* commissioning (smd_ident.h): a test setting out of range */
    SMD_ERR_RLS = 30           /* the online R_s / psi_r tracker (smd_rls.h): a setting out of
                                  range @scenario(controller.rls_i_inj, controller.rls_tau,
                                  controller.rls_t_half, controller.rls_w_M_min,
                                  controller.L_s_hat, controller.R_s_hat,
                                  controller.psi_r_hat, T_sp) */
} smd_status;

/* Human-readable text for a status, e.g. for a debugger or a binding. */
const char *smd_status_str(smd_status s);

/* A complex space vector x = x_alpha + j x_beta (or x_d + j x_q). */
typedef struct smd_cplx {
    smd_real re;
    smd_real im;
} smd_cplx;

static inline smd_cplx smd_c(smd_real re, smd_real im)
{
    smd_cplx z;
    z.re = re;
    z.im = im;
    return z;
}
static inline smd_cplx smd_cadd(smd_cplx a, smd_cplx b) { return smd_c(a.re + b.re, a.im + b.im); }
static inline smd_cplx smd_csub(smd_cplx a, smd_cplx b) { return smd_c(a.re - b.re, a.im - b.im); }
static inline smd_cplx smd_cscale(smd_cplx a, smd_real k) { return smd_c(k * a.re, k * a.im); }
static inline smd_cplx smd_cmul(smd_cplx a, smd_cplx b)
{
    return smd_c(a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re);
}
static inline smd_cplx smd_cconj(smd_cplx a) { return smd_c(a.re, -a.im); }
/* j * a */
static inline smd_cplx smd_cj(smd_cplx a) { return smd_c(-a.im, a.re); }
static inline smd_real smd_cabs(smd_cplx a) { return SMD_SQRT(a.re * a.re + a.im * a.im); }
/* e^{j theta} */
/* With SMD_SINCOSF(x, &s, &c) defined (float build), one call gives both:
 * it must give the bits SMD_SINF and SMD_COSF give (smd_fmath's
 * smd_sincosf does, with one argument reduction instead of two). */
static inline smd_cplx smd_cexpj(smd_real theta)
{
#if defined(SMD_SINCOSF) && !defined(SMD_REAL_DOUBLE)
    smd_cplx z;
    SMD_SINCOSF(theta, &z.im, &z.re);
    return z;
#else
    return smd_c(SMD_COS(theta), SMD_SIN(theta));
#endif
}
/* e^{j x} of an angle that is small in the fast build (a rotation by one
 * sample's turn, w T): |x| < 1/8 by the series to x^5 (error below 3e-10,
 * under the fast sines' 1.5e-6) instead of an argument reduction; the exact
 * build takes smd_cexpj. */
static inline smd_cplx smd_cexpj_small(smd_real x)
{
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    if (x > SMD_R(-0.125) && x < SMD_R(0.125)) {
        const smd_real x2 = x * x;
        return smd_c(SMD_R(1.0) - x2 * (SMD_R(0.5) - x2 * SMD_R(0.041666668)),
                     x * (SMD_R(1.0) - x2 * (SMD_R(0.16666667) - x2 * SMD_R(0.008333334))));
    }
#endif
    return smd_cexpj(x);
}
/* e^{j x} of an angle below a radian in the fast build (a rotation by a
 * period and a half's turn, 1.5 w T: 0.79 rad at yao2022's 100 kr/min and
 * 20 kHz): |x| < 1 by the series to x^9 (sine) and x^10 (cosine), error
 * below 2.6e-8 (x^11 / 11!), under the fast sines' 1.5e-6, in ten
 * multiplications instead of an argument reduction; the exact build takes
 * smd_cexpj. */
static inline smd_cplx smd_cexpj_unit(smd_real x)
{
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    if (x > SMD_R(-1.0) && x < SMD_R(1.0)) {
        const smd_real x2 = x * x;
        const smd_real c = SMD_R(1.0) -
            x2 * (SMD_R(0.5) - x2 * (SMD_R(0.041666668) - x2 * (SMD_R(0.0013888889) -
            x2 * (SMD_R(2.4801588e-05) - x2 * SMD_R(2.7557319e-07)))));
        const smd_real sn = x * (SMD_R(1.0) - x2 * (SMD_R(0.16666667) - x2 * (SMD_R(0.008333334) -
            x2 * (SMD_R(0.0001984127) - x2 * SMD_R(2.7557319e-06)))));
        return smd_c(c, sn);
    }
#endif
    return smd_cexpj(x);
}
static inline bool smd_cfinite(smd_cplx a) { return isfinite(a.re) && isfinite(a.im); }
/* x - x: +0 for a finite x, NaN for NaN and +-inf (IEEE 754; no
 * -ffinite-math-only). A sum of these is 0 exactly when every term is
 * finite: a check of n values in 2n additions and one compare, where n
 * isfinite() calls take a compare and a branch each. */
static inline smd_real smd_nf(smd_real x) { return x - x; }
static inline smd_real smd_cnf(smd_cplx a) { return (a.re - a.re) + (a.im - a.im); }
/* A long finiteness check, nf = sum of smd_nfs(x) (smd_cnfs(a)), then
 * smd_nf(nf) == 0: the exact build sums x - x; the fast build sums the
 * values themselves, one addition each instead of two operations, and a
 * sum is finite when every value is (a finite sum beyond FLT_MAX reads as
 * not finite: the drive then recovers, as from a NaN). */
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
static inline smd_real smd_nfs(smd_real x) { return x; }
static inline smd_real smd_cnfs(smd_cplx a) { return a.re + a.im; }
#else
static inline smd_real smd_nfs(smd_real x) { return smd_nf(x); }
static inline smd_real smd_cnfs(smd_cplx a) { return smd_cnf(a); }
#endif

/* floor(y) for |y| < 2^23 through the integer conversion, bit for bit
 * floorf's (every float there is exact as an int32; y itself when it is an
 * integer, so -0 stays -0): one VCVT each way on a Cortex-M4F, where
 * newlib's floorf is a call of some 40 cycles. */
static inline smd_real smd_floor_small(smd_real y)
{
    const smd_real f = (smd_real)(int32_t)y;
    return f > y ? f - SMD_R(1.0) : (f < y ? f : y);
}

/* floor(y): smd_floor_small where it applies on targets whose C library's
 * floorf is a call (x86-64's is one instruction), SMD_FLOOR otherwise (NaN,
 * inf, larger values, the double build). The same bits either way. */
static inline smd_real smd_floor(smd_real y)
{
#if !defined(SMD_REAL_DOUBLE) && !defined(__x86_64__)
    if (y > SMD_R(-8388608.0) && y < SMD_R(8388608.0)) {
        return smd_floor_small(y);
    }
#endif
    return SMD_FLOOR(y);
}

/* Wrap an angle to [-pi, pi). The fast build (SMD_FAST, docs/firmware.md)
 * multiplies by 1/(2 pi) instead of dividing (a VDIV is 14 cycles): the
 * result may differ in its last bit and land on -pi for x just below pi. */
static inline smd_real smd_wrap_pi(smd_real x)
{
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    return x - SMD_TWO_PI * smd_floor((x + SMD_PI) * SMD_R(0.159154943091895336));
#else
    return x - SMD_TWO_PI * smd_floor((x + SMD_PI) / SMD_TWO_PI);
#endif
}

/* smd_wrap_pi of an angle within one turn of the range, |x| < 3 pi (a
 * difference or a sum of two wrapped angles): the fast build adds or takes
 * one turn by two compares (the floor's k is -1, 0 or 1 there, and x - 2 pi k
 * the same expression; at the ends the choice may differ in rounding, as the
 * fast smd_wrap_pi's may); the exact build, smd_wrap_pi. */
static inline smd_real smd_wrap_pi_near(smd_real x)
{
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    return x >= SMD_PI ? x - SMD_TWO_PI : (x < -SMD_PI ? x + SMD_TWO_PI : x);
#else
    return smd_wrap_pi(x);
#endif
}

/* Range check helper: lo <= x <= hi and finite. */
static inline bool smd_in_range(smd_real x, smd_real lo, smd_real hi)
{
    return isfinite(x) && x >= lo && x <= hi;
}

/* Range check helper: 0 < x <= hi and finite. */
static inline bool smd_in_pos_range(smd_real x, smd_real hi)
{
    return smd_in_range(x, SMD_R(0.0), hi) && x > SMD_R(0.0);
}

/* The checks shared by every block built on the model (15): sampling
 * period in (0, 1] s, inductance estimate in (0, 10] H, resistance estimate
 * in [0, 1000] ohm. */
static inline smd_status smd_check_model(smd_real T_sp, smd_real L_s_hat, smd_real R_s_hat)
{
    if (!smd_in_pos_range(T_sp, SMD_R(1.0))) {
        return SMD_ERR_TS;
    }
    if (!smd_in_pos_range(L_s_hat, SMD_R(10.0))) {
        return SMD_ERR_L;
    }
    if (!smd_in_range(R_s_hat, SMD_R(0.0), SMD_R(1000.0))) {
        return SMD_ERR_R;
    }
    return SMD_OK;
}

/* smd_table_interp (below) for the values [i0, i1) of each row only (the
 * others of out untouched): the same operations on each value, so that a
 * row's halves interpolated in two calls give the bits of one call. */
static inline void smd_table_interp_range(const smd_real *table, int nf, int n, smd_real w_min,
                                          smd_real dw, smd_real w, smd_real *out, int i0,
                                          int i1)
{
    smd_real x = (w - w_min) / dw;
    smd_real f;
    int k, i, n4;
    const smd_real *a;
    const smd_real *b;
    if (!(x > SMD_R(0.0))) {
        x = SMD_R(0.0);
    }
    if (x > (smd_real)(n - 1)) {
        x = (smd_real)(n - 1);
    }
    k = (int)x;
    if (k > n - 2) {
        k = n - 2;
    }
    f = x - (smd_real)k;
    a = table + k * nf;
    b = a + nf;
    /* four at a time: the same operations on each value, a quarter of the
     * loop's compare-and-branch (113 values a sample for the LCL observer) */
    n4 = i1 - (i1 - i0) % 4;
    for (i = i0; i < n4; i += 4) {
        smd_real a0 = a[i], a1 = a[i + 1], a2 = a[i + 2], a3 = a[i + 3];
        smd_real b0 = b[i], b1 = b[i + 1], b2 = b[i + 2], b3 = b[i + 3];
        out[i] = a0 + f * (b0 - a0);
        out[i + 1] = a1 + f * (b1 - a1);
        out[i + 2] = a2 + f * (b2 - a2);
        out[i + 3] = a3 + f * (b3 - a3);
    }
    for (i = n4; i < i1; i++) {
        out[i] = a[i] + f * (b[i] - a[i]);
    }
}

/* Linear interpolation in a speed-indexed table of n rows of nf reals each
 * (row k at w_min + k dw), clamped to the table: out = row(w). The yao2022
 * observers' matrices (smd_lcl_smo, smd_lcl_linobs) are such tables. */
static inline void smd_table_interp(const smd_real *table, int nf, int n, smd_real w_min,
                                    smd_real dw, smd_real w, smd_real *out)
{
    smd_table_interp_range(table, nf, n, w_min, dw, w, out, 0, nf);
}

#ifdef __cplusplus
}
#endif

#endif /* SMD_TYPES_H */

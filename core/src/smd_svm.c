#include "smodrive/smd_svm.h"
#include "smodrive/smd_transforms.h"

smd_status smd_svm_init(smd_svm_params *p, int limit, smd_real d_min)
{
    if (p == 0) {
        return SMD_ERR_NULL;
    }
    if (limit != SMD_SVM_LIMIT_CIRCLE && limit != SMD_SVM_LIMIT_HEXAGON) {
        return SMD_ERR_MODE;
    }
    if (!smd_in_range(d_min, SMD_R(0.0), SMD_R(0.49))) {
        return SMD_ERR_DMIN;
    }
    p->limit = limit;
    p->d_min = d_min;
    return SMD_OK;
}

static smd_real max3(const smd_real x[3])
{
    smd_real m = x[0] > x[1] ? x[0] : x[1];
    return m > x[2] ? m : x[2];
}

static smd_real min3(const smd_real x[3])
{
    smd_real m = x[0] < x[1] ? x[0] : x[1];
    return m < x[2] ? m : x[2];
}

SMD_FIXED_INLINE void smd_svm_step_finite_r(const smd_svm_params *p, smd_cplx u_s_ab_ref,
                                            smd_real u_dc, smd_real inv_u_dc,
                                            smd_real d_abc[3], smd_cplx *u_s_ab_applied)
{
    smd_real u_abc[3];
    smd_real span, mx, mn;
    smd_real u_avail = (SMD_R(1.0) - SMD_R(2.0) * p->d_min) * u_dc;
    smd_real u_0;
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    smd_real inv_dc, d_hi, d_lo;
#endif
    int k, overflow;
#if !(defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE))
    (void)inv_u_dc;
#endif

    if (!(u_dc > SMD_R(0.0))) {
        /* No DC link: apply the zero vector. */
        d_abc[0] = d_abc[1] = d_abc[2] = SMD_R(0.5);
        *u_s_ab_applied = smd_c(SMD_R(0.0), SMD_R(0.0));
        return;
    }
    if (p->limit == SMD_SVM_LIMIT_CIRCLE) {
        smd_real mag = smd_cabs(u_s_ab_ref);
        smd_real u_max = SMD_INV_SQRT3 * u_avail;
        if (mag > u_max) {
            u_s_ab_ref = smd_cscale(u_s_ab_ref, u_max / mag);
        }
    }
    smd_ab_to_abc(u_s_ab_ref, u_abc);
    mx = max3(u_abc);
    mn = min3(u_abc);
    span = mx - mn;
    overflow = !isfinite(span);
    if (overflow) {
        /* Phase values beyond the real type (a finite reference near its
         * largest value): beyond the hexagon of any finite u_dc. The same
         * direction 2^-64 times as long (exact) is limited below without
         * an infinite span (whose limit factor 0 would give NaN duties). */
        u_s_ab_ref = smd_cscale(u_s_ab_ref, SMD_R(5.42101086242752217e-20));
        smd_ab_to_abc(u_s_ab_ref, u_abc);
        mx = max3(u_abc);
        mn = min3(u_abc);
        span = mx - mn;
    }
    if (span > u_avail || overflow) {
        /* Hexagon limit: shrink along the reference direction. */
        smd_real k_lim = u_avail / span;
        u_s_ab_ref = smd_cscale(u_s_ab_ref, k_lim);
        for (k = 0; k < 3; k++) {
            u_abc[k] *= k_lim;
        }
        /* (the same products as the phases': their largest and smallest
         * stay theirs, k_lim > 0) */
        mx *= k_lim;
        mn *= k_lim;
    }
    u_0 = SMD_R(-0.5) * (mx + mn);
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    inv_dc = inv_u_dc; /* the fast build: one division, not three (the caller's) */
    /* The duties of the largest and the smallest phase first: every phase's
     * duty lies between them, bit for bit (each operation rounds
     * monotonically), so when both are within [d_min, 1 - d_min], as they
     * are but by rounding, no phase needs the clamps below. */
    d_hi = SMD_R(0.5) + (mx + u_0) * inv_dc;
    d_lo = SMD_R(0.5) + (mn + u_0) * inv_dc;
    if (d_lo >= p->d_min && d_hi <= SMD_R(1.0) - p->d_min) {
        for (k = 0; k < 3; k++) {
            d_abc[k] = SMD_R(0.5) + (u_abc[k] + u_0) * inv_dc;
        }
        *u_s_ab_applied = u_s_ab_ref;
        return;
    }
#endif
    for (k = 0; k < 3; k++) {
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
        smd_real d = SMD_R(0.5) + (u_abc[k] + u_0) * inv_dc;
#else
        smd_real d = SMD_R(0.5) + (u_abc[k] + u_0) / u_dc;
#endif
        if (d < p->d_min) {
            d = p->d_min; /* only by rounding */
        }
        if (d > SMD_R(1.0) - p->d_min) {
            d = SMD_R(1.0) - p->d_min;
        }
        d_abc[k] = d;
    }
    *u_s_ab_applied = u_s_ab_ref;
}

SMD_FIXED_INLINE void smd_svm_step(const smd_svm_params *p, smd_cplx u_s_ab_ref, smd_real u_dc,
                  smd_real d_abc[3], smd_cplx *u_s_ab_applied)
{
    if (!smd_cfinite(u_s_ab_ref)) {
        /* A non-finite reference: apply the zero vector. */
        d_abc[0] = d_abc[1] = d_abc[2] = SMD_R(0.5);
        *u_s_ab_applied = smd_c(SMD_R(0.0), SMD_R(0.0));
        return;
    }
    smd_svm_step_finite_r(p, u_s_ab_ref, u_dc, smd_svm_inv_dc(u_dc), d_abc, u_s_ab_applied);
}

/* One phase of the compensation: its duty moved by t_ratio sat(s), s the
 * current over i_lin, and kept in [0, 1]. */
static smd_real dtc_phase(smd_real d, smd_real s, smd_real t_ratio)
{
    if (s > SMD_R(1.0)) {
        s = SMD_R(1.0);
    } else if (s < SMD_R(-1.0)) {
        s = SMD_R(-1.0);
    }
    d += t_ratio * s;
    return d < SMD_R(0.0) ? SMD_R(0.0) : (d > SMD_R(1.0) ? SMD_R(1.0) : d);
}

void smd_svm_deadtime_comp_r(smd_real d_abc[3], const smd_real i_abc[3], smd_real t_ratio,
                             smd_real inv_i_lin)
{
    int k;
    for (k = 0; k < 3; k++) {
        d_abc[k] = dtc_phase(d_abc[k], i_abc[k] * inv_i_lin, t_ratio);
    }
}

SMD_FIXED_INLINE smd_cplx smd_svm_deadtime_comp_lost(smd_real d_abc[3], const smd_real i_abc[3],
                                    smd_real t_ratio, smd_real i_lin, smd_real inv_i_lin,
                                    smd_real u_dc)
{
    smd_real dd[3];
    int k, clipped = 0;
    for (k = 0; k < 3; k++) {
        const smd_real d = d_abc[k];
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
        /* the fast build: dtc_phase's value, with its clamp's compares
         * shared by the test for a clip below (two compares, not four, for
         * a duty inside (0, 1)) */
        smd_real sat = i_abc[k] * inv_i_lin, dc;
        (void)i_lin;
        sat = sat > SMD_R(1.0) ? SMD_R(1.0) : (sat < SMD_R(-1.0) ? SMD_R(-1.0) : sat);
        dc = d + t_ratio * sat;
        if (dc > SMD_R(0.0) && dc < SMD_R(1.0)) {
            dd[k] = SMD_R(0.0);
        } else if (dc <= SMD_R(0.0)) {
            dc = dc < SMD_R(0.0) ? SMD_R(0.0) : dc;
            dd[k] = -d;
            clipped = 1;
        } else if (dc >= SMD_R(1.0)) {
            dc = dc > SMD_R(1.0) ? SMD_R(1.0) : dc;
            /* (in [0, 1], NaN to 1: see below) */
            sat = i_abc[k] * inv_i_lin;
            sat = sat < SMD_R(1.0) ? (sat > SMD_R(0.0) ? sat : SMD_R(0.0)) : SMD_R(1.0);
            dd[k] = SMD_R(1.0) - t_ratio * sat - d;
            clipped = 1;
        } else {
            dd[k] = SMD_R(0.0); /* NaN: kept, for the caller's check */
        }
#else
        const smd_real dc = dtc_phase(d, i_abc[k] / i_lin, t_ratio);
        dd[k] = SMD_R(0.0);
        if (dc <= SMD_R(0.0)) {
            dd[k] = -d;
            clipped = 1;
        } else if (dc >= SMD_R(1.0)) {
            smd_real sat = i_abc[k] * inv_i_lin;
            /* (in [0, 1], NaN to 1: a zero current over an i_lin whose
             * reciprocal overflowed is 0 x inf; the clip left the duty at 1
             * and the lost voltage stays finite, fuzz_blocks) */
            sat = sat < SMD_R(1.0) ? (sat > SMD_R(0.0) ? sat : SMD_R(0.0)) : SMD_R(1.0);
            dd[k] = SMD_R(1.0) - t_ratio * sat - d;
            clipped = 1;
        }
#endif
        d_abc[k] = dc;
    }
    return clipped ? smd_cscale(smd_abc_to_ab(dd), u_dc) : smd_c(SMD_R(0.0), SMD_R(0.0));
}

void smd_svm_deadtime_comp(smd_real d_abc[3], const smd_real i_abc[3], smd_real t_ratio,
                           smd_real i_lin)
{
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    /* the fast build: one division, not three */
    smd_svm_deadtime_comp_r(d_abc, i_abc, t_ratio, SMD_R(1.0) / i_lin);
#else
    int k;
    for (k = 0; k < 3; k++) {
        d_abc[k] = dtc_phase(d_abc[k], i_abc[k] / i_lin, t_ratio);
    }
#endif
}

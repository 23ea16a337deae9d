#include "smodrive/smd_bandpass.h"

smd_status smd_bandpass_set(smd_bandpass *f, smd_real w_n, smd_real Omega, smd_real T)
{
    smd_real t;
    if (f == 0) {
        return SMD_ERR_NULL;
    }
    if (!smd_in_pos_range(T, SMD_R(1.0)) || !smd_in_pos_range(w_n, SMD_PI / T) ||
        !smd_in_pos_range(Omega, SMD_PI / T) || !(w_n < SMD_PI / T) || !(Omega < SMD_PI / T)) {
        return SMD_ERR_LIMIT;
    }
    /* yao2022 eq. (46); the sine and cosine of one angle from one call
     * (smd_cexpj: one argument reduction, the bits of SMD_SIN and SMD_COS) */
    {
        const smd_cplx z = smd_cexpj(SMD_R(0.5) * Omega * T);
        t = z.im / z.re;
    }
#if defined(SMD_FAST) && !defined(SMD_REAL_DOUBLE)
    {
        /* the fast build divides once */
        const smd_real inv = SMD_R(1.0) / (SMD_R(1.0) + t);
        f->a1 = SMD_R(2.0) * SMD_COS(w_n * T) * inv;
        f->a2 = (SMD_R(1.0) - t) * inv;
    }
#else
    f->a1 = SMD_R(2.0) * SMD_COS(w_n * T) / (SMD_R(1.0) + t);
    f->a2 = (SMD_R(1.0) - t) / (SMD_R(1.0) + t);
#endif
    f->b0 = SMD_R(0.5) * (SMD_R(1.0) - f->a2);
    return SMD_OK;
}

void smd_bandpass_reset(smd_bandpass *f)
{
    smd_cplx z = smd_c(SMD_R(0.0), SMD_R(0.0));
    f->x1 = f->x2 = f->y1 = f->y2 = z;
}

smd_cplx smd_bandpass_step(smd_bandpass *f, smd_cplx x)
{
    /* yao2022 eq. (45), direct form I */
    smd_cplx y = smd_cscale(smd_csub(x, f->x2), f->b0);
    y = smd_cadd(y, smd_cscale(f->y1, f->a1));
    y = smd_csub(y, smd_cscale(f->y2, f->a2));
    f->x2 = f->x1;
    f->x1 = x;
    f->y2 = f->y1;
    f->y1 = y;
    return y;
}

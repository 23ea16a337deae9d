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
    /* yao2022 eq. (46) */
    t = SMD_SIN(SMD_R(0.5) * Omega * T) / SMD_COS(SMD_R(0.5) * Omega * T);
    f->a1 = SMD_R(2.0) * SMD_COS(w_n * T) / (SMD_R(1.0) + t);
    f->a2 = (SMD_R(1.0) - t) / (SMD_R(1.0) + t);
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

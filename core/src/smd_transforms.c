#include "smodrive/smd_transforms.h"

smd_cplx smd_abc_to_ab(const smd_real x_abc[3])
{
    smd_real re = SMD_R(2.0 / 3.0) * (x_abc[0] - SMD_R(0.5) * (x_abc[1] + x_abc[2]));
    smd_real im = SMD_INV_SQRT3 * (x_abc[1] - x_abc[2]);
    return smd_c(re, im);
}

smd_cplx smd_ab2_to_ab(smd_real x_a, smd_real x_b)
{
    return smd_c(x_a, SMD_INV_SQRT3 * (x_a + SMD_R(2.0) * x_b));
}

void smd_abc_to_ab2(const smd_real x_abc[3], smd_real *x_a, smd_real *x_b)
{
    const smd_real m = SMD_R(1.0 / 3.0) * (x_abc[0] + x_abc[1] + x_abc[2]);
    *x_a = x_abc[0] - m;
    *x_b = x_abc[1] - m;
}

void smd_ab_to_abc(smd_cplx x_ab, smd_real x_abc[3])
{
    smd_real h = SMD_R(0.5) * SMD_SQRT3 * x_ab.im;
    x_abc[0] = x_ab.re;
    x_abc[1] = SMD_R(-0.5) * x_ab.re + h;
    x_abc[2] = SMD_R(-0.5) * x_ab.re - h;
}

#include "smdsim/smd_pwm.h"

double smd_pwm_clamp(double d)
{
    if (!(d >= 0.0)) d = 0.0; /* also catches NaN */
    if (d > 1.0) d = 1.0;
    return d;
}

void smd_pwm_edges(double T, double t_dead, double d, double i_x, double *t_on, double *t_off)
{
    d = smd_pwm_clamp(d);
    /* Regular sampling at the carrier peak: the leg is high while the held
     * duty exceeds the triangle, i.e. on [(1-d)T/2, (1+d)T/2). */
    *t_on = 0.5 * (1.0 - d) * T;
    *t_off = 0.5 * (1.0 + d) * T;
    if (t_dead > 0.0) {
        /* During the dead time the diode of the current's direction conducts:
         * a positive phase current delays the rising edge, a negative one the
         * falling edge (current sign at the period start). */
        if (i_x > 0.0) {
            *t_on += t_dead;
        } else if (i_x < 0.0) {
            *t_off += t_dead;
        }
        if (*t_off > T) *t_off = T;
        if (*t_on > *t_off) *t_on = *t_off;
    }
}

double smd_pwm_avg_duty(double T, double t_dead, double d, double i_x)
{
    double de = smd_pwm_clamp(d);
    if (t_dead > 0.0) {
        if (i_x > 0.0) de -= t_dead / T;
        else if (i_x < 0.0) de += t_dead / T;
        if (de < 0.0) de = 0.0;
        if (de > 1.0) de = 1.0;
    }
    return de;
}

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
    if (t_dead > 0.0 && d > 0.0) {
        /* (a duty of 0 switches nothing: the lower device conducts the whole
         * period, no edge and so no dead time) */
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
    if (t_dead > 0.0 && de > 0.0) { /* (no edge at a duty of 0) */
        if (i_x > 0.0) de -= t_dead / T;
        else if (i_x < 0.0) de += t_dead / T;
        if (de < 0.0) de = 0.0;
        if (de > 1.0) de = 1.0;
    }
    return de;
}

double smd_pwm_avg_duty_clamp(double T, double t_dead, double d, double i_x, double v_f,
                              double k_rate)
{
    double tz, vr, vfc, dz, de;
    if (!(t_dead > 0.0 && smd_pwm_clamp(d) > 0.0)) return smd_pwm_avg_duty(T, t_dead, d, i_x);
    /* time for the current to reach zero with the leg on the diode's rail:
     * L di/dt = (2/3) u_dc (v_rail - v_f) (R i neglected), linear */
    if (i_x > 0.0) {
        vr = 0.0;
        tz = v_f > 0.0 ? i_x / (k_rate * v_f) : t_dead;
    } else if (i_x < 0.0) {
        vr = 1.0;
        tz = v_f < 1.0 ? -i_x / (k_rate * (1.0 - v_f)) : t_dead;
    } else {
        vr = 0.0;
        tz = 0.0;
    }
    if (!(tz < t_dead)) return smd_pwm_avg_duty(T, t_dead, d, i_x); /* no clamping */
    vfc = v_f < 0.0 ? 0.0 : (v_f > 1.0 ? 1.0 : v_f);
    /* each edge's dead time: the rail for tz, then the floating level, where
     * the ideal leg is high after the rising and low after the falling edge */
    dz = vr * tz + vfc * (t_dead - tz);
    de = smd_pwm_clamp(d) + ((dz - t_dead) + dz) / T;
    if (de < 0.0) de = 0.0;
    if (de > 1.0) de = 1.0;
    return de;
}

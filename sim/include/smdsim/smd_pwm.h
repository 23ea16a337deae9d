/*
 * Two-level inverter leg switching within one carrier period, shared by the
 * host plants (smd_plant.c, smd_lcl.c).
 *
 * Carrier: symmetric triangle, duty sampled and held at the carrier peak
 * (regular sampling), so the leg is high on [(1-d)T/2, (1+d)T/2). Dead time:
 * during the blanking interval the diode of the current's direction conducts,
 * so a positive leg current delays the rising edge and a negative one the
 * falling edge (current sign at the period start).
 */
#ifndef SMD_PWM_H
#define SMD_PWM_H

/* Duty clamped to [0, 1]; NaN maps to 0. */
double smd_pwm_clamp(double d);

/* Leg-high interval [t_on, t_off) within a carrier period of length T for
 * duty d (clamped) and leg current i_x (dead-time direction). */
void smd_pwm_edges(double T, double t_dead, double d, double i_x, double *t_on, double *t_off);

/* Switching-cycle average of the same leg: the effective duty, i.e. d
 * (clamped) minus/plus the dead-time volt-second loss t_dead/T by the sign of
 * i_x, clamped to [0, 1]. */
double smd_pwm_avg_duty(double T, double t_dead, double d, double i_x);

/* The same with zero-current clamping (dead_time_model SMD_DT_CLAMP): at each
 * of the leg's two edges the diode of i_x's direction holds the leg on its
 * rail until the current reaches zero, after tz = |i_x| / (k_rate |v_rail -
 * v_f|) (linear, R i neglected; never if the rate points away from zero), and
 * the open leg then sits at the floating level v_f (clamped to [0, 1]) for the
 * rest of the dead time. v_f: the floating level as a fraction of u_dc,
 * unclamped, (v_y + v_z)/2 + 1.5 e_x/u_dc with the other legs high or low by
 * their duties at the edges; k_rate = (2/3) u_dc / L, A/s. With tz >= t_dead
 * (a large current) exactly smd_pwm_avg_duty; with i_x = 0 the leg floats the
 * whole dead time. Clamped to [0, 1]. */
double smd_pwm_avg_duty_clamp(double T, double t_dead, double d, double i_x, double v_f,
                              double k_rate);

#endif

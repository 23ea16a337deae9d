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

#endif

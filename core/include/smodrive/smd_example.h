/*
 * An example drive configuration: the yang2018 Table I machine (L_s 23.45
 * mH, R_s 2.25 ohm, psi_r 0.4 Wb) sampled at 10 kHz, every gain of every part
 * set, so that any choice of parts initialises. The unit tests, the
 * consumers of the installed core and the cost benchmark start from it and
 * change the fields they need after the call.
 *
 * Parts: SMD_CC_DBPC on SMD_POS_ENCODER, SMD_START_RUNNING, no filter, no
 * speed loop. Gains: the SMDO of yang2018 Table I (lambda_min 800 A/s, l
 * 1200 1/s, w_c 1500 rad/s, rho 0.2 A, the exact rotation of eq. (36));
 * eq. (44)-(45) with w_lpf 200 rad/s, w_hys 20 rad/s, w_max 2000 rad/s; the
 * current PI k_p = L alpha, k_i = L alpha^2 / 4 with alpha = 2000 rad/s (the
 * double pole s = -alpha/2 without the delay), decoupling with L_s, EMF
 * feed-forward on; the speed PI k_p_w 0.05 A s/rad, k_i_w 2 A/rad, i_max
 * 15 A; the PLL of yao2022 eq. (50) (k_theta 0.1, k_omega 10 1/s, k_a 10
 * 1/s^2), used by the LCL sources only; I/f i_start 8 A, a_start 2e4
 * rad/s^2, w_handover 201 rad/s; the hexagon limit, no dead-time
 * compensation (i_dtc 1 A). Everything else 0: no filter model, no
 * observer tables, protection and supervision off.
 */
#ifndef SMD_EXAMPLE_H
#define SMD_EXAMPLE_H

#include "smd_drive.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fill *c with the example configuration (every field written). */
void smd_example_drive_config(smd_drive_config *c);

#ifdef __cplusplus
}
#endif

#endif

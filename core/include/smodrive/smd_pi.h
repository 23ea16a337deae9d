/*
 * Discrete PI controller with output limit and anti-windup (the integrator is
 * kept at the value that makes the limited output realisable), used as the
 * speed controller: input electrical speed error in rad/s, output the q-axis
 * current reference in A, limited to +-i_max.
 */
#ifndef SMD_PI_H
#define SMD_PI_H

#include "smd_types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct smd_pi_params {
    smd_real k_p;   /* proportional gain, output unit per input unit */
    smd_real k_i;   /* integral gain, output unit per input unit per second */
    smd_real T_s;   /* execution period of the loop, s */
    smd_real y_max; /* output limit (symmetric), > 0 */
} smd_pi_params;

typedef struct smd_pi_state {
    smd_real x_i;   /* integrator state, output unit */
    smd_real y;     /* last (limited) output */
} smd_pi_state;

smd_status smd_pi_init(smd_pi_params *p, smd_real k_p, smd_real k_i, smd_real T_s,
                       smd_real y_max);
void smd_pi_reset(smd_pi_state *s, smd_real x_i0);
/* One execution: returns the limited output for error e = ref - meas. */
smd_real smd_pi_step(const smd_pi_params *p, smd_pi_state *s, smd_real e);

#ifdef __cplusplus
}
#endif

#endif

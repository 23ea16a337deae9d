/* Dead time with zero-current clamping, carrier PWM: the period walked event
 * by event (smd_dtc.c), shared by the SPMSM plant (the phase current through
 * R_s, L_s against the back EMF) and the LCL plant (the inverter-side current
 * through L1 against the capacitor voltage). Internal to the simulator. */
#ifndef SMD_DTC_H
#define SMD_DTC_H

#include <complex.h>

#define DTC_MAX_EVENTS 64  /* events a period before crossings are no longer predicted */
#define DTC_MAX_STEPS (DTC_MAX_EVENTS + 16) /* voltage steps a leg (one an event at most) */

typedef struct dtc_leg {
    int n;                       /* steps */
    double t[DTC_MAX_STEPS];     /* instants, s */
    double dv[DTC_MAX_STEPS];    /* voltage changes, fraction of u_dc */
} dtc_leg;

/* The circuit behind the legs. The leg current x obeys
 * L di_x/dt = u_dc (v_x - mean v) - R i_x - u_dc ex_x, with ex_x the phase
 * voltage the leg works against (back EMF or capacitor voltage) / u_dc. */
typedef struct dtc_circuit {
    double R, L, u_dc;
    /* the legs floating at zero current: in, at the start of a period with
     * the switches off (they stay so; the others take a diode by their
     * current's sign); out, at its end (0 after a switching period) */
    int *open;
    void *ctx;
    /* the state from t0 to t1 > t0 with the leg voltages v (fractions of u_dc) held */
    void (*advance)(void *ctx, double t0, double t1, const double v[3]);
    /* at the state's instant t: the leg currents i_x and ex_x */
    void (*probe)(void *ctx, double t, double i_x[3], double ex[3]);
} dtc_circuit;

/* x_k = Re(z a^{-k}), a = e^{j 2 pi / 3} */
double smd_dtc_phase(double complex z, int k);

/* The legs' voltage steps over one period of duties d (clamped to [0, 1]),
 * period T, dead time t_dead, the state at t = 0 in the circuit's context
 * (left at the last event); off: every switch open the whole period (the
 * legs on their diodes or floating; d and t_dead unused). */
void smd_dtc_legs(const dtc_circuit *c, const double d[3], double T, double t_dead, int off,
                  dtc_leg legs[3]);

#endif

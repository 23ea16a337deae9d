/*
 * Shared by the drive tests (test_drive.c, test_compose.c): the yang2018
 * Table I machine, a configuration of the one drive for any choice of parts,
 * and the exact discrete plant without filter.
 *
 * Plant: the exact solution of eq. (1) over one sample (piecewise-constant
 * voltage, constant speed), written here in double:
 *   i(T) = e^{-aT} (i_k - u/R - C) + u/R + C e^{jwT},
 *   C = -j w psi e^{j theta_k} / (R + j w L),  a = R/L.
 * The voltage applied during [k, k+1) is the vector realised by the duties the
 * drive returned at k-1, (2/3) u_dc (d_a + d_b a + d_c a^2): the voltage
 * computed at k is applied during [k+1, k+2).
 */
#ifndef DRIVE_FIXTURE_H
#define DRIVE_FIXTURE_H

#include <string.h>

#include "smd_test.h"
#include "smodrive/smd_drive.h"
#include "smodrive/smd_example.h"

/* Table I of yang2018 */
#define LS 23.45e-3
#define RS 2.25
#define PSI 0.4
#define TSP 1e-4
#define UDC 540.0

/* Current PI for this machine (SMD_CC_PI): k_p = L alpha, k_i = L alpha^2 / 4
 * with alpha = 2000 rad/s, i.e. the double pole s = -alpha/2 of
 * L s^2 + k_p s + k_i without the delay. With the 1.5-sample delay of the
 * exact discrete loop (rotor frame, decoupling and EMF feed-forward) the
 * slowest closed-loop pole has |z| = 0.9378 at w = 0, +-400 rad/s (numpy,
 * eigenvalues of the 3-state loop [i(k), u(k-1), x_i(k-1)]). */
#define KP_I (LS * 2000.0)
#define KI_I (LS * 2000.0 * 2000.0 / 4.0)

/* The one drive with the given parts: the example configuration
 * (smodrive/smd_example.h: this machine, no filter, every gain set, the
 * current PI's KP_I and KI_I) with its parts changed. */
static inline smd_drive_config drive_config(int current, int position, int start)
{
    smd_drive_config c;
    smd_example_drive_config(&c);
    c.current = current;
    c.position = position;
    c.start = start;
    return c;
}

/* The yang2018 drives of the former `mode`: 0 conventional = (dbpc, encoder),
 * 1 robust = (robust_dbpc, encoder), 2 sensorless = (robust_dbpc, smdo_emf,
 * handover after `handover` samples, 0 here); and the PI on the encoder (3)
 * and on the SMDO's angle (4). */
enum { MODE_CONVENTIONAL = 0, MODE_ROBUST = 1, MODE_SENSORLESS = 2, MODE_PI = 3, MODE_PI_SMDO = 4 };

static inline smd_drive_config mode_config(int mode)
{
    switch (mode) {
    case MODE_CONVENTIONAL:
        return drive_config(SMD_CC_DBPC, SMD_POS_ENCODER, SMD_START_RUNNING);
    case MODE_ROBUST:
        return drive_config(SMD_CC_ROBUST_DBPC, SMD_POS_ENCODER, SMD_START_RUNNING);
    case MODE_SENSORLESS:
        return drive_config(SMD_CC_ROBUST_DBPC, SMD_POS_SMDO_EMF, SMD_START_HANDOVER);
    case MODE_PI_SMDO: /* synchronous-frame PI on the SMDO's position */
        return drive_config(SMD_CC_PI, SMD_POS_SMDO_EMF, SMD_START_RUNNING);
    default: /* synchronous-frame PI on the encoder */
        return drive_config(SMD_CC_PI, SMD_POS_ENCODER, SMD_START_RUNNING);
    }
}

typedef struct plant {
    double complex i; /* stationary frame, A */
    double th, w;     /* electrical angle and speed */
} plant;

static inline void plant_step(plant *pl, double complex u)
{
    double a = RS / LS;
    double complex C = -JD * pl->w * PSI * cexp(JD * pl->th) / (RS + JD * pl->w * LS);
    double e = exp(-a * TSP);
    pl->i = e * (pl->i - u / RS - C) + u / RS + C * cexp(JD * pl->w * TSP);
    pl->th = smdt_wrap(pl->th + pl->w * TSP);
}

static inline double complex realised(const smd_real d[3])
{
    double complex a = cexp(JD * 2.0 * PI_D / 3.0);
    return (2.0 / 3.0) * UDC * ((double)d[0] + (double)d[1] * a + (double)d[2] * a * a);
}

static inline int duties_ok(const smd_real d[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        if (!(isfinite(d[k]) && d[k] >= R(0.0) && d[k] <= R(1.0))) {
            return 0;
        }
    }
    return 1;
}

/* Phase currents a, b of a stationary vector (no zero sequence). */
static inline void phase_ab(double complex x, smd_real *x_a, smd_real *x_b)
{
    *x_a = R(creal(x));
    *x_b = R(creal(x * cexp(-JD * 2.0 * PI_D / 3.0)));
}

/* Inputs from the plant: motor currents, the encoder (true angle and speed),
 * the DC link, the speed reference = the plant's speed, the current reference. */
static inline void fill_in(smd_drive_in *in, const plant *pl, double complex idq_ref)
{
    memset(in, 0, sizeof *in);
    phase_ab(pl->i, &in->i_a, &in->i_b);
    in->theta_enc = R(pl->th);
    in->w_enc = R(pl->w);
    in->u_dc = R(UDC);
    in->w_ref = R(pl->w);
    in->i_dq_ref = smdt_c(idq_ref);
}

/* The tests' usual start: the plant at 1 rad, turning at w rad/s, without
 * current, and the drive reset to that angle and speed (no load torque). */
static inline void start_at(const smd_drive_params *p, smd_drive_state *s, plant *pl, double w)
{
    pl->i = 0.0;
    pl->th = 1.0;
    pl->w = w;
    smd_drive_reset(p, s, R(pl->th), R(pl->w), R(0.0));
}

/* the current in the rotor frame of the plant */
static inline double complex plant_idq(const plant *pl) { return pl->i * cexp(-JD * pl->th); }

#endif

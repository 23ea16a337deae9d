/* Dead time with zero-current clamping, carrier PWM: the period walked event
 * by event (below), shared by the SPMSM plant (the phase current through
 * R_s, L_s against the back EMF) and the LCL plant (the inverter-side current
 * through L1 against the capacitor voltage). Internal to the simulator. */
#ifndef SMD_DTC_H
#define SMD_DTC_H

#include <complex.h>
#include <math.h>

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

/* The walk below is inlined into each solver, its circuit's advance and
 * probe then called directly (called through pointers, from another file or
 * from one copy the link folded the two into, the clamping solver ran 27 %
 * slower). */


#define SMD_DTC_A_RE (-0.5)
#define SMD_DTC_A_IM 0.86602540378443864676

enum { SW_LOW = 0, SW_UP = 1, SW_OFF = 2 };

static inline double smd_dtc_phase(double complex z, int k)
{
    if (k == 0) return creal(z);
    if (k == 1) return SMD_DTC_A_RE * creal(z) + SMD_DTC_A_IM * cimag(z);
    return SMD_DTC_A_RE * creal(z) - SMD_DTC_A_IM * cimag(z);
}

/* Floating levels of the open legs with zero current (fl[x] = 1: open at
 * zero current), v in fractions of u_dc, ex / u_dc; a level outside [0, 1]
 * puts that leg back on the rail's diode (mode). kc != 0 (a period with the
 * switches off, refreshed every h): the level also returns the current's
 * drift ix to zero within h, kc = (R - L/h) / u_dc. */
static inline void dtc_float(const int sw[3], int mode[3], double v[3], const double ex[3],
                      const double ix[3], double kc)
{
    int iter;
    for (iter = 0; iter < 3; iter++) {
        int fl[3], nf = 0, x, worst = -1;
        double vn[3], viol = 0.0;
        for (x = 0; x < 3; x++) {
            fl[x] = sw[x] == SW_OFF && mode[x] == 0;
            nf += fl[x];
        }
        if (nf == 0) return;
        for (x = 0; x < 3; x++) {
            int y = (x + 1) % 3, z = (x + 2) % 3;
            if (!fl[x]) continue;
            if (nf == 1) {
                vn[x] = 0.5 * (v[y] + v[z]) + 1.5 * ex[x];
                if (kc != 0.0) vn[x] += 1.5 * kc * ix[x];
            } else if (nf == 2) {
                int fixed = !fl[y] ? y : z;
                vn[x] = v[fixed] + ex[x] - ex[fixed];
                if (kc != 0.0) vn[x] += kc * (ix[x] - ix[fixed]);
            } else {
                vn[x] = 0.5 + ex[x]; /* no current at all: the common mode is free */
                if (kc != 0.0) vn[x] += kc * ix[x];
            }
        }
        for (x = 0; x < 3; x++) {
            double o;
            if (!fl[x]) continue;
            o = vn[x] < 0.0 ? -vn[x] : (vn[x] > 1.0 ? vn[x] - 1.0 : 0.0);
            if (o > viol) {
                viol = o;
                worst = x;
            }
        }
        if (worst < 0) {
            for (x = 0; x < 3; x++) {
                if (fl[x]) v[x] = vn[x];
            }
            return;
        }
        /* beyond a rail: that rail's diode conducts (the current leaves zero
         * in its direction); the others are solved again */
        mode[worst] = vn[worst] < 0.0 ? 1 : -1;
        v[worst] = vn[worst] < 0.0 ? 0.0 : 1.0;
    }
}

#if defined(__GNUC__)
__attribute__((always_inline))
#endif
static inline void smd_dtc_legs(const dtc_circuit *c, const double d[3], double T, double td, int off,
                  dtc_leg legs[3])
{
    const double R = c->R, L = c->L, udc = c->u_dc;
    double st_t[3][4];
    int st_s[3][4], st_n[3], st_k[3] = {0, 0, 0};
    int sw[3] = {SW_LOW, SW_LOW, SW_LOW}, mode[3] = {0, 0, 0};
    double v[3] = {0.0, 0.0, 0.0}, tz[3] = {INFINITY, INFINITY, INFINITY};
    double t = 0.0;
    /* switches off: the floating levels and the crossings' predictions
     * refreshed every h (the voltage they follow turns; held a whole period,
     * a floating current would drift off zero, and a diode's current, which
     * may now flow for most of the period, is not linear) */
    const double h = T / 48.0, kc = off ? (R - L / h) / udc : 0.0;
    int x, events = 0;

    for (x = 0; x < 3; x++) {
        double r = 0.5 * (1.0 - d[x]) * T, f = 0.5 * (1.0 + d[x]) * T;
        int n = 0;
        if (off || !(d[x] > 0.0)) {
            /* (every leg opens at once: the first event below; a duty of 0
             * switches nothing, the leg stays low with no dead time) */
            st_n[x] = 0;
            legs[x].n = 0;
            continue;
        }
        st_t[x][n] = r;
        st_s[x][n++] = SW_OFF;
        if (r + td < f) {
            st_t[x][n] = r + td;
            st_s[x][n++] = SW_UP;
            st_t[x][n] = f;
            st_s[x][n++] = SW_OFF;
        }
        st_t[x][n] = f + td;
        st_s[x][n++] = SW_LOW;
        st_n[x] = n;
        legs[x].n = 0;
    }

    for (;;) {
        double tn = T, vold[3], ex[3], ix[3], vm;
        int kind = off && events == 0 && t == 0.0 ? 3 : -1, who = -1;
        for (x = 0; x < 3; x++) {
            if (st_k[x] < st_n[x] && st_t[x][st_k[x]] < tn) {
                tn = st_t[x][st_k[x]];
                kind = 0;
                who = x;
            }
        }
        for (x = 0; x < 3; x++) {
            if (sw[x] == SW_OFF && mode[x] != 0 && tz[x] < tn) {
                tn = tz[x];
                kind = 1;
                who = x;
            }
        }
        if (kind == 3) {
            tn = 0.0; /* every switch opens at the period's start */
        } else if (off && t + h < tn) {
            tn = t + h;
            kind = 2; /* a refresh */
            who = -1;
        }
        if (kind < 0) break; /* nothing before the period's end */
        /* the exact state at tn with the leg voltages held since t */
        if (tn > t) {
            c->advance(c->ctx, t, tn, v);
            t = tn;
        }
        c->probe(c->ctx, t, ix, ex);
        for (x = 0; x < 3; x++) vold[x] = v[x];
        if (kind == 0) {
            int s = st_s[who][st_k[who]++];
            sw[who] = s;
            tz[who] = INFINITY;
            if (s == SW_LOW) {
                v[who] = 0.0;
            } else if (s == SW_UP) {
                v[who] = 1.0;
            } else {
                mode[who] = ix[who] > 0.0 ? 1 : (ix[who] < 0.0 ? -1 : 0);
                if (off && c->open[who]) mode[who] = 0; /* it was floating: it still is */
                if (mode[who] != 0) v[who] = mode[who] > 0 ? 0.0 : 1.0;
            }
        } else if (kind == 1) {
            mode[who] = 0; /* the current has reached zero: the leg opens */
            tz[who] = INFINITY;
        } else if (kind == 3) {
            /* all at once (one by one, the first would float against legs
             * still low); a leg floating at the last period's end still is */
            for (x = 0; x < 3; x++) {
                sw[x] = SW_OFF;
                mode[x] = c->open[x] ? 0 : (ix[x] > 0.0 ? 1 : (ix[x] < 0.0 ? -1 : 0));
                if (mode[x] != 0) v[x] = mode[x] > 0 ? 0.0 : 1.0;
            }
        }
        if (kind != 2) events++; /* (a refresh is no event) */
        dtc_float(sw, mode, v, ex, ix, kc);
        for (x = 0; x < 3; x++) {
            if (v[x] != vold[x] && legs[x].n < DTC_MAX_STEPS) {
                legs[x].t[legs[x].n] = t;
                legs[x].dv[legs[x].n++] = v[x] - vold[x];
            }
        }
        /* the next zero crossing of each leg on a diode, linear from now */
        vm = (v[0] + v[1] + v[2]) / 3.0;
        for (x = 0; x < 3; x++) {
            tz[x] = INFINITY;
            if (sw[x] == SW_OFF && mode[x] != 0 && events < DTC_MAX_EVENTS) {
                double rate = (udc * (v[x] - vm) - R * ix[x] - ex[x] * udc) / L;
                if (mode[x] > 0 && rate < 0.0) {
                    tz[x] = t + (ix[x] > 0.0 ? ix[x] : 0.0) / -rate;
                } else if (mode[x] < 0 && rate > 0.0) {
                    tz[x] = t + (ix[x] < 0.0 ? -ix[x] : 0.0) / rate;
                }
            }
        }
    }
    for (x = 0; x < 3; x++) {
        c->open[x] = off && sw[x] == SW_OFF && mode[x] == 0;
    }
}

#endif

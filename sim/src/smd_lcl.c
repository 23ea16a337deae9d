/* Inverter -> LCL filter -> SPMSM (yao2022 Sec. II eq. (1)-(3), Table II),
 * stationary frame, complex space vectors:
 *
 *   C1 du_c/dt = i_1 - i_2
 *   L1 di_1/dt = u - u_c
 *   L2 di_2/dt = u_c - R_s i_2 - e,   L2 = L2o + L_s,  e = j w psi_r e^{j theta}
 *
 * (the paper prints the first row of A_s with the wrong signs; these are the
 * circuit's equations). The real 3x3 matrix A of d[u_c, i_1, i_2]/dt = A x +
 * b u + f e is diagonalised once (closed-form eigenvectors, cubic roots by
 * Newton), and each mode dz/dt = lambda z + beta u + phi e is solved in
 * closed form over a carrier period: homogeneous decay e^{lambda t}, the
 * rotating-EMF particular solution phi e / (j w - lambda), and the exact
 * response (e^{lambda tau} - 1) / lambda to each switching edge. The torque's
 * frame-weighted integral int i_2 e^{-j theta} dt is integrated the same way.
 * Dead time acts by the sign of the inverter-side current i_1. */
#include "smdsim/smd_plant.h"
#include "smd_mech.h"
#include "smdsim/smd_pwm.h"
#include "smd_dtc.h"

#include <complex.h>
#include <math.h>


/* a = e^{j 2 pi / 3}: phase b and c unit vectors */
static const double A_RE = -0.5;
static const double A_IM = 0.86602540378443864676;

/* Below these |arguments| the divided differences use their Taylor series
 * (truncation error ~ x^4 / 120 < 1e-14; the direct forms lose ~1e-16/|x|). */
#define SERIES_EPS 1e-3

/* |z| < SERIES_EPS without a square root */
static int small(double complex z)
{
    double re = creal(z), im = cimag(z);
    return re * re + im * im < SERIES_EPS * SERIES_EPS;
}

/* (e^y - 1) / y for complex y, given ey = e^y */
static double complex dexp1(double complex y, double complex ey)
{
    if (small(y)) {
        return 1.0 + y * (0.5 + y * (1.0 / 6.0 + y * (1.0 / 24.0)));
    }
    return (ey - 1.0) / y;
}

static double complex cubic(const double c[3], double complex s, double complex *ds)
{
    *ds = (3.0 * s + 2.0 * c[2]) * s + c[1];
    return ((s + c[2]) * s + c[1]) * s + c[0];
}

static double complex polish(const double c[3], double complex s)
{
    int k;
    for (k = 0; k < 4; k++) {
        double complex ds, f = cubic(c, s, &ds);
        if (ds == 0.0) break;
        s -= f / ds;
    }
    return s;
}

/* Eigenvalues of A. All coefficients are positive, so f(0) = c0 > 0 and the
 * real root is negative; it is found by Newton safeguarded by bisection on
 * [lo, 0] (lo from the Cauchy bound), the other two from the deflated
 * quadratic s^2 + p s + q (p = c2 + r, q = -c0 / r), polished by Newton on the
 * cubic. Returns 1 for a complex pair, 0 for three real roots. */
static int eigenvalues(const double c[3], double complex lam[3])
{
    double lo = -(1.0 + fmax(c[2], fmax(c[1], c[0]))), hi = 0.0;
    double r = -c[0] / c[1], p, q, disc;
    int k;
    for (k = 0; k < 200; k++) {
        double f = ((r + c[2]) * r + c[1]) * r + c[0];
        double df = (3.0 * r + 2.0 * c[2]) * r + c[1];
        double rn;
        if (f > 0.0) hi = r; else lo = r;   /* f increases through the root from below */
        if (f == 0.0) break;
        rn = r - f / df;
        if (!(rn > lo && rn < hi)) rn = 0.5 * (lo + hi);
        if (fabs(rn - r) <= 1e-15 * fabs(r)) {
            r = rn;
            break;
        }
        r = rn;
    }
    lam[0] = r;
    p = c[2] + r;
    q = -c[0] / r;
    disc = 0.25 * p * p - q;
    if (disc < 0.0) {
        lam[1] = polish(c, -0.5 * p + I * sqrt(-disc));
        lam[2] = conj(lam[1]);
        return 1;
    }
    {
        double s1 = -(0.5 * p + sqrt(disc));
        lam[1] = creal(polish(c, s1));
        lam[2] = creal(polish(c, q / s1));
        return 0;
    }
}

int smd_lcl_setup(smd_plant *p)
{
    const smd_plant_config *c = &p->c;
    smd_lcl_modes *md = &p->m;
    int k, j;
    double L2, a2, cc[3], scale;

    L2 = c->L2o + c->L_s;
    a2 = c->R_s / L2;
    /* det(sI - A) = s^3 + a2 s^2 + (1/L1 + 1/L2)/C1 s + a2/(C1 L1) */
    cc[2] = a2;
    cc[1] = (1.0 / c->L1 + 1.0 / L2) / c->C1;
    cc[0] = a2 / (c->C1 * c->L1);
    md->kind = eigenvalues(cc, md->lam);
    scale = fmax(cabs(md->lam[0]), fmax(cabs(md->lam[1]), cabs(md->lam[2])));
    for (k = 0; k < 3; k++) {
        for (j = k + 1; j < 3; j++) {
            if (!(cabs(md->lam[k] - md->lam[j]) > 1e-7 * scale)) return SMD_PF_MODES;
        }
        if (!(creal(md->lam[k]) < 0.0) || !isfinite(cimag(md->lam[k]))) return SMD_PF_MODES;
    }

    for (k = 0; k < 3; k++) {
        const double complex l = md->lam[k];
        const double complex la = l + a2;
        /* right eigenvector (v_uc = 1): A v = lambda v */
        const double complex v1 = -1.0 / (l * c->L1);
        const double complex v2 = 1.0 / (L2 * la);
        /* left eigenvector (w_uc = 1): w^T A = lambda w^T, normalised w.v = 1 */
        const double complex w1 = 1.0 / (l * c->C1);
        const double complex w2 = -1.0 / (c->C1 * la);
        const double complex n = 1.0 + w1 * v1 + w2 * v2;
        if (!(cabs(n) > 1e-9)) return SMD_PF_MODES;
        md->v[0][k] = 1.0;
        md->v[1][k] = v1;
        md->v[2][k] = v2;
        md->w[k][0] = 1.0 / n;
        md->w[k][1] = w1 / n;
        md->w[k][2] = w2 / n;
        md->beta[k] = md->w[k][1] / c->L1; /* b = [0, 1/L1, 0] */
        md->phi[k] = -md->w[k][2] / L2;    /* f = [0, 0, -1/L2] */
    }
    for (k = 0; k < 3; k++) {
        if (cimag(md->lam[k]) == 0.0) {
            double lr = creal(md->lam[k]);
            double em = expm1(lr * c->T_sw);
            md->eT[k] = 1.0 + em;
            md->gT[k] = em / lr;
        } else {
            md->eT[k] = cexp(md->lam[k] * c->T_sw);
            md->gT[k] = (md->eT[k] - 1.0) / md->lam[k];
        }
    }

    return 0;
}

/* Per-period constants of the edge responses. */
typedef struct lcl_kernel {
    double w, T;
    double complex emjwT;      /* e^{-j w T} */
    double complex inv_d[3];   /* 1 / (lambda_k - j w) */
} lcl_kernel;

/* Accumulate the response to a voltage step dU applied at t in [0, T):
 * G_k += dU (e^{lambda_k tau} - 1) / lambda_k   (modal state at T per unit beta)
 * S_k += dU int_t^T (e^{lambda_k (t'-t)} - 1) / lambda_k e^{-j w t'} dt'
 *      = dU q [Q g_k + h] / (lambda_k - j w),
 * tau = T - t, q = e^{-j w t}, Q = e^{-j w tau}, h = (Q - 1) / (j w).
 * One sine/cosine pair, one exp and (complex pair) one complex exp. */
static void edge(const smd_lcl_modes *md, const lcl_kernel *k, double t, double complex dU,
                 double complex G[3], double complex S[3])
{
    const double tau = k->T - t;
    const double wt = k->w * t, wtau = k->w * tau;
    double complex q, Q, h, g[3];
    int m;
    if (!(tau > 0.0)) return;
    q = cos(wt) - I * sin(wt);
    Q = k->emjwT * conj(q);
    if (fabs(wtau) < SERIES_EPS) {
        double complex x = I * wtau; /* h = -tau (1 - e^{-x}) / x */
        h = -tau * (1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0))));
    } else {
        h = (Q - 1.0) / (I * k->w);
    }
    {
        double l0 = creal(md->lam[0]);
        g[0] = expm1(l0 * tau) / l0;
    }
    if (md->kind) {
        double complex P = cexp(md->lam[1] * tau);
        g[1] = (P - 1.0) / md->lam[1];
        g[2] = conj(P - 1.0) / md->lam[2];
    } else {
        double l1 = creal(md->lam[1]), l2 = creal(md->lam[2]);
        g[1] = expm1(l1 * tau) / l1;
        g[2] = expm1(l2 * tau) / l2;
    }
    for (m = 0; m < 3; m++) {
        double complex d = md->lam[m] - I * k->w;
        double complex s;
        G[m] += dU * g[m];
        if (small(d * tau)) {
            /* near resonance (lambda ~ j w): (tau (e^{d tau} - 1)/(d tau) + h) / lambda */
            double complex y = d * tau;
            s = (tau * (1.0 + y * (0.5 + y * (1.0 / 6.0 + y * (1.0 / 24.0)))) + h) / md->lam[m];
        } else {
            s = (Q * g[m] + h) * k->inv_d[m];
        }
        S[m] += dU * q * s;
    }
}

/* The averaged mode's edge sums: one step of the mean voltage u_mean at t = 0. */
static void averaged_sums(const smd_lcl_modes *md, const lcl_kernel *k, double T,
                          double complex u_mean, double complex G[3], double complex S[3])
{
    const double w_e = k->w;
    double complex h;
    int m;
    if (fabs(w_e * T) < SERIES_EPS) {
        double complex xx = I * w_e * T;
        h = -T * (1.0 - xx * (0.5 - xx * (1.0 / 6.0 - xx * (1.0 / 24.0))));
    } else {
        h = (k->emjwT - 1.0) / (I * w_e);
    }
    for (m = 0; m < 3; m++) {
        double complex d = md->lam[m] - I * w_e, s;
        G[m] = u_mean * md->gT[m];
        if (small(d * T)) {
            double complex y = d * T;
            s = (T * (1.0 + y * (0.5 + y * (1.0 / 6.0 + y * (1.0 / 24.0)))) + h) / md->lam[m];
        } else {
            s = (k->emjwT * md->gT[m] + h) * k->inv_d[m];
        }
        S[m] = u_mean * s;
    }
}

/* ---- dead time with zero-current clamping: smd_dtc.h ----
 * The circuit: the inverter-side current i_1 through L1 against the
 * capacitor voltage u_c (no resistance in L1), the filter's modal state exact
 * between events: dz_k/dt = lambda_k z_k + beta_k U + phi_k E0 e^{j w t}. */
typedef struct lcl_dtc {
    const smd_lcl_modes *md;
    const lcl_kernel *k;
    double complex E0, z[3];
    double u_dc;
} lcl_dtc;

static inline void lcl_dtc_advance(void *ctx, double t0, double t1, const double v[3])
{
    lcl_dtc *s = ctx;
    const smd_lcl_modes *md = s->md;
    const double w = s->k->w;
    double complex U = 2.0 / 3.0 * s->u_dc *
                       (v[0] + v[1] * (A_RE + I * A_IM) + v[2] * (A_RE - I * A_IM));
    double complex r0 = cos(w * t0) + I * sin(w * t0), r1 = cos(w * t1) + I * sin(w * t1);
    int m;
    for (m = 0; m < 3; m++) {
        double complex zp = -md->phi[m] * s->E0 * s->k->inv_d[m]; /* EMF's, at t = 0 */
        double complex zu = -md->beta[m] * U / md->lam[m];         /* the held voltage's */
        double complex eh = cexp(md->lam[m] * (t1 - t0));
        s->z[m] = (s->z[m] - zp * r0 - zu) * eh + zp * r1 + zu;
    }
}

static inline void lcl_dtc_probe(void *ctx, double t, double i_x[3], double ex[3])
{
    lcl_dtc *s = ctx;
    const smd_lcl_modes *md = s->md;
    double complex uc = 0.0, i1 = 0.0;
    int m, x;
    (void)t;
    for (m = 0; m < 3; m++) {
        uc += md->v[0][m] * s->z[m];
        i1 += md->v[1][m] * s->z[m];
    }
    for (x = 0; x < 3; x++) {
        i_x[x] = smd_dtc_phase(i1, x);
        ex[x] = smd_dtc_phase(uc, x) / s->u_dc;
    }
}

/* The period's leg voltages with zero-current clamping added to the modal
 * edge sums G, S (carrier: the event walk; averaged: smd_pwm_avg_duty_clamp
 * with the capacitor voltage of the period start for the floating level and
 * L1 for the rate, as the SPMSM plant with the back EMF and L_s); returns the
 * mean voltage. */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static double complex lcl_clamp_voltage(smd_plant *p, const double d_abc[3],
                                        const lcl_kernel *k, double complex E0,
                                        const double complex z0[3], double complex uc0,
                                        const double complex leg_dir[3],
                                        const double i1_abc[3], double complex G[3],
                                        double complex S[3])
{
    const smd_plant_config *c = &p->c;
    const double T = c->T_sw;
    double complex u_mean = 0.0;
    double d[3];
    int x, j, m;
    for (x = 0; x < 3; x++) d[x] = smd_pwm_clamp(d_abc[x]);
    if (c->pwm_mode == SMD_PWM_CARRIER || p->off) {
        dtc_leg legs[3];
        lcl_dtc s;
        dtc_circuit circ;
        s.md = &p->m;
        s.k = k;
        s.E0 = E0;
        s.u_dc = c->u_dc;
        for (m = 0; m < 3; m++) s.z[m] = z0[m];
        circ.R = 0.0;
        circ.L = c->L1;
        circ.u_dc = c->u_dc;
        circ.ctx = &s;
        circ.open = p->leg_open;
        circ.advance = lcl_dtc_advance;
        circ.probe = lcl_dtc_probe;
        if (p->off) { /* (two copies of the walk, each with off a constant) */
            smd_dtc_legs(&circ, d, T, c->t_dead, 1, legs);
        } else {
            smd_dtc_legs(&circ, d, T, c->t_dead, 0, legs);
        }
        for (x = 0; x < 3; x++) {
            for (j = 0; j < legs[x].n; j++) {
                edge(&p->m, k, legs[x].t[j], legs[x].dv[j] * leg_dir[x], G, S);
                u_mean += leg_dir[x] * legs[x].dv[j] * (T - legs[x].t[j]) / T;
            }
        }
    } else {
        double k_rate = 2.0 / 3.0 * c->u_dc / c->L1;
        for (x = 0; x < 3; x++) {
            int y = (x + 1) % 3, zz = (x + 2) % 3;
            double hy = d[y] > d[x] ? 1.0 : (d[y] == d[x] ? 0.5 : 0.0);
            double hz = d[zz] > d[x] ? 1.0 : (d[zz] == d[x] ? 0.5 : 0.0);
            double v_f = 0.5 * (hy + hz) + 1.5 * smd_dtc_phase(uc0, x) / c->u_dc;
            u_mean += leg_dir[x] * smd_pwm_avg_duty_clamp(T, c->t_dead, d[x], i1_abc[x], v_f,
                                                          k_rate);
        }
        averaged_sums(&p->m, k, T, u_mean, G, S);
    }
    return u_mean;
}

void smd_lcl_step(smd_plant *p, const double d_abc[3], double T_ext, double T_brake)
{
    const smd_plant_config *c = &p->c;
    const smd_lcl_modes *md = &p->m;
    const double T = c->T_sw;
    const double Kt = 1.5 * c->n_p * c->psi_r;
    double complex x[3], z[3], zT[3], Sint[3], G[3] = {0.0, 0.0, 0.0}, S[3] = {0.0, 0.0, 0.0};
    double complex leg_dir[3], ejth0, E0, ejwT, u_mean = 0.0, i2_int;
    double i1_abc[3];
    double T_L, T_e0, w_mid, w_e, T_e_mean;
    lcl_kernel k;
    int m, xl;

    x[0] = p->uc_re + I * p->uc_im;
    x[1] = p->i1_re + I * p->i1_im;
    x[2] = p->i_re + I * p->i_im;
    ejth0 = cos(p->theta_r) + I * sin(p->theta_r);

    leg_dir[0] = 2.0 / 3.0 * c->u_dc;
    leg_dir[1] = 2.0 / 3.0 * c->u_dc * (A_RE + I * A_IM);
    leg_dir[2] = 2.0 / 3.0 * c->u_dc * (A_RE - I * A_IM);

    /* Load (held over the period) and the mid-period speed prediction. */
    T_L = smd_load_torque(c, p->w_M, T_ext, T_brake);
    T_e0 = Kt * cimag(x[2] * conj(ejth0));
    w_mid = p->w_M + 0.5 * T * (T_e0 - T_L - c->B * p->w_M) / c->J;
    w_e = c->n_p * w_mid;

    k.w = w_e;
    k.T = T;
    ejwT = cos(w_e * T) + I * sin(w_e * T);
    k.emjwT = conj(ejwT);
    for (m = 0; m < 3; m++) k.inv_d[m] = 1.0 / (md->lam[m] - I * w_e);

    /* Free response: z_k(t) = c_k e^{lambda t} + Zp_k e^{j w t}, with the
     * rotating-EMF particular solution Zp_k = phi_k E0 / (j w - lambda_k),
     * E0 = e(0) = j w psi e^{j theta_0}; and its frame-weighted integral
     * int_0^T z_k e^{-j w t} dt = c_k T (e^{(lambda-jw)T} - 1)/((lambda-jw)T) + Zp_k T. */
    E0 = I * w_e * c->psi_r * ejth0;
    for (m = 0; m < 3; m++) {
        double complex zp = -md->phi[m] * E0 * k.inv_d[m];
        double complex ck;
        z[m] = md->w[m][0] * x[0] + md->w[m][1] * x[1] + md->w[m][2] * x[2];
        ck = z[m] - zp;
        zT[m] = ck * md->eT[m] + zp * ejwT;
        Sint[m] = ck * T * dexp1((md->lam[m] - I * w_e) * T, md->eT[m] * k.emjwT) + zp * T;
    }

    /* Inverter voltage: dead time by the sign of the inverter-side current,
     * or with zero-current clamping (lcl_clamp_legs). */
    smd_ab_to_abc_d(p->i1_re, p->i1_im, i1_abc);
    if (p->off || (c->dead_time_model == SMD_DT_CLAMP && c->t_dead > 0.0)) {
        u_mean = lcl_clamp_voltage(p, d_abc, &k, E0, z, x[0], leg_dir, i1_abc, G, S);
    } else if (c->pwm_mode == 1) {
        for (xl = 0; xl < 3; xl++) {
            double t_on, t_off;
            smd_pwm_edges(T, c->t_dead, d_abc[xl], i1_abc[xl], &t_on, &t_off);
            if (t_off > t_on) {
                edge(md, &k, t_on, leg_dir[xl], G, S);
                edge(md, &k, t_off, -leg_dir[xl], G, S);
                u_mean += leg_dir[xl] * (t_off - t_on) / T;
            }
        }
    } else {
        /* Switching-cycle average: one step of the mean voltage at t = 0. */
        for (xl = 0; xl < 3; xl++) {
            u_mean += leg_dir[xl] * smd_pwm_avg_duty(T, c->t_dead, d_abc[xl], i1_abc[xl]);
        }
        averaged_sums(md, &k, T, u_mean, G, S);
    }

    for (m = 0; m < 3; m++) {
        zT[m] += md->beta[m] * G[m];
        Sint[m] += md->beta[m] * S[m];
    }
    for (m = 0; m < 3; m++) {
        x[m] = md->v[m][0] * zT[0] + md->v[m][1] * zT[1] + md->v[m][2] * zT[2];
    }
    /* int_0^T i_2 e^{-j theta(t)} dt, theta(t) = theta_0 + w t */
    i2_int = conj(ejth0) * (md->v[2][0] * Sint[0] + md->v[2][1] * Sint[1] + md->v[2][2] * Sint[2]);
    T_e_mean = Kt * cimag(i2_int) / T;

    p->uc_re = creal(x[0]);
    p->uc_im = cimag(x[0]);
    p->i1_re = creal(x[1]);
    p->i1_im = cimag(x[1]);
    p->i_re = creal(x[2]);
    p->i_im = cimag(x[2]);
    smd_mech_end_period(p, T_e_mean, T_L, T_brake, u_mean);
}

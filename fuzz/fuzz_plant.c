/*
 * libFuzzer target: the host plant (smd_plant_init, smd_plant_step,
 * smd_plant_sample, smd_plant_phase_currents, smd_plant_eigenvalues,
 * smd_plant_run_open, smd_plant_field, with both solvers behind them:
 * smd_spmsm_step, smd_lcl_setup, smd_lcl_step) and its inverter and ADC
 * helpers (smd_pwm_clamp, smd_pwm_edges, smd_pwm_avg_duty, smd_rng_*,
 * smd_adc_convert, smd_adc_sample3, smd_ab_to_abc_d), on a configuration and
 * an input sequence decoded from the input (fuzz.h, fuzz_sim.h):
 *   op % 6 == 0  one period on raw duties and load torques, every switch
 *                open (smd_plant.off, the event walk) when op & 16
 *   op % 6 == 1  1 + u8 periods of sinusoidal duties (modulation m, angle
 *                delta to the rotor) through smd_plant_run_open
 *   op % 6 == 2  ADC samples (both channel sets, or i_1 NULL), true phase
 *                currents, eigenvalues
 *   op % 6 == 3  one leg of the inverter: edges and average duty
 *   op % 6 == 4  one ADC channel and the noise generator
 *   op % 6 == 5  smd_plant_field of a code
 *
 * Checked besides the sanitizers: the leg's edges satisfy
 * 0 <= t_on <= t_off <= T, its average duty is in [0, 1], a clamped duty is
 * in [0, 1] (finite T > 0, 0 <= t_dead <= T/4, any duty and current); a
 * quantised ADC value is within [-full_scale, full_scale]; uniform numbers
 * are in [0, 1).
 */
#include "fuzz_sim.h"

#include "smdsim/smd_adc.h"
#include "smdsim/smd_pwm.h"

#define FZ_MAX_STEPS 2000

static void check_leg(fz *f)
{
    double T = fz_real(f, 0.0, 1e-3), t_dead = fz_real(f, 0.0, 1e-5);
    double d = fz_real(f, -0.5, 1.5), i = fz_real(f, -100.0, 100.0);
    double t_on, t_off, da, dc;
    smd_pwm_edges(T, t_dead, d, i, &t_on, &t_off);
    da = smd_pwm_avg_duty(T, t_dead, d, i);
    dc = smd_pwm_clamp(d);
    FZ_CHECK(dc >= 0.0 && dc <= 1.0);
    if (isfinite(T) && T > 0.0 && isfinite(t_dead) && t_dead >= 0.0 && t_dead <= 0.25 * T &&
        !isnan(i)) {
        FZ_CHECK(t_on >= 0.0 && t_on <= t_off && t_off <= T);
        FZ_CHECK(da >= 0.0 && da <= 1.0);
    }
}

static void check_adc(fz *f, smd_rng *r)
{
    double x = fz_real(f, -200.0, 200.0), gain = fz_real(f, 0.5, 2.0);
    double offset = fz_real(f, -10.0, 10.0), noise = fz_real(f, 0.0, 1.0);
    int bits = fz_int(f, 0, 24);
    double fs = fz_real(f, 0.0, 1000.0);
    double v = smd_adc_convert(x, gain, offset, noise, bits, fs, r);
    double u = smd_rng_uniform(r);
    FZ_CHECK(u >= 0.0 && u < 1.0);
    fz_use(smd_rng_normal(r));
    /* the plant's own limits on these fields (smd_plant_init) */
    if (bits > 0 && bits <= 24 && isfinite(fs) && fs >= 1e-6 && fs <= 1e6 && isfinite(x) &&
        isfinite(gain) && isfinite(offset) && isfinite(noise) && noise >= 0.0 && noise <= 1e3) {
        FZ_CHECK(v >= -fs && v <= fs);
    }
    fz_use(v);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz f = {data, size};
    smd_plant_config c;
    smd_plant *p;
    smd_rng rng;
    int rc, steps = 0;

    fz_plant_config(&f, &c);
    p = (smd_plant *)malloc(sizeof *p);
    rc = smd_plant_init(p, &c);
    FZ_TRACEF("plant: lcl %d: init %d (%s)\n", c.lcl, rc, smd_plant_field(rc));
    fz_use((double)smd_plant_field(rc)[0]);
    fz_use((double)(smd_sizeof_plant() + smd_sizeof_plant_config()));
    smd_rng_seed(&rng, c.seed);
    if (rc != 0) {
        /* the helpers still run */
        while (fz_more(&f)) {
            if (fz_u8(&f) & 1) {
                check_leg(&f);
            } else {
                check_adc(&f, &rng);
            }
        }
        free(p);
        return 0;
    }
    while (fz_more(&f) && steps < FZ_MAX_STEPS) {
        uint8_t op = fz_u8(&f);
        switch (op % 6) {
        case 0: {
            double d[3];
            double T_ext, T_brake;
            d[0] = fz_real(&f, 0.0, 1.0);
            d[1] = fz_real(&f, 0.0, 1.0);
            d[2] = fz_real(&f, 0.0, 1.0);
            T_ext = fz_real(&f, -10.0, 10.0);
            T_brake = fz_real(&f, 0.0, 10.0);
            p->off = (op & 16) ? 1 : 0;
            smd_plant_step(p, d, T_ext, T_brake);
            p->off = 0;
            steps++;
            break;
        }
        case 1: {
            long n = 1 + fz_u8(&f);
            double m = fz_real(&f, 0.0, 1.2), delta = fz_real(&f, -4.0, 4.0);
            double T_ext = fz_real(&f, -10.0, 10.0);
            if (steps + n > FZ_MAX_STEPS) {
                n = FZ_MAX_STEPS - steps;
            }
            smd_plant_run_open(p, n, m, delta, T_ext);
            steps += (int)n;
            break;
        }
        case 2: {
            double i[3], i1[3], re[3], im[3];
            smd_plant_sample(p, i, (op & 8) ? 0 : i1);
            smd_plant_phase_currents(p, i, (op & 16) ? 0 : i1);
            smd_plant_eigenvalues(p, re, im);
            fz_use(i[0] + i[1] + i[2] + re[0] + re[1] + re[2] + im[0] + im[1] + im[2]);
            if (!(op & 8) || !(op & 16)) {
                fz_use(i1[0] + i1[1] + i1[2]);
            }
            break;
        }
        case 3: check_leg(&f); break;
        case 4: check_adc(&f, &rng); break;
        default: fz_use((double)smd_plant_field(fz_int(&f, -1, SMD_PF_N))[0]); break;
        }
        fz_use(p->i_re + p->i_im + p->i1_re + p->i1_im + p->uc_re + p->uc_im + p->theta_r +
               p->w_M + p->T_e_mean + p->T_L_mean + p->u_re + p->u_im);
    }
    FZ_TRACEF("plant: %d periods, w_M = %g rad/s, i = %g %g A\n", steps, p->w_M, p->i_re,
              p->i_im);
    free(p);
    return 0;
}

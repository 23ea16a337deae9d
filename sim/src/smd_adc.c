#include "smdsim/smd_adc.h"

#include <math.h>

/* a = e^{j 2 pi / 3}: phase b and c unit vectors */
static const double A_RE = -0.5;
static const double A_IM = 0.86602540378443864676;

static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

static uint64_t splitmix(uint64_t *x)
{
    uint64_t z = (*x += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

void smd_rng_seed(smd_rng *r, uint64_t seed)
{
    int k;
    for (k = 0; k < 4; k++) {
        r->s[k] = splitmix(&seed);
    }
    r->have_spare = 0;
    r->spare = 0.0;
}

/* xoshiro256** */
uint64_t smd_rng_next(smd_rng *r)
{
    uint64_t *s = r->s;
    uint64_t result = rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

double smd_rng_uniform(smd_rng *r)
{
    return (double)(smd_rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

/* Standard normal by the polar method. */
double smd_rng_normal(smd_rng *r)
{
    double u, v, r2, f;
    if (r->have_spare) {
        r->have_spare = 0;
        return r->spare;
    }
    do {
        u = 2.0 * smd_rng_uniform(r) - 1.0;
        v = 2.0 * smd_rng_uniform(r) - 1.0;
        r2 = u * u + v * v;
    } while (r2 >= 1.0 || r2 == 0.0);
    f = sqrt(-2.0 * log(r2) / r2);
    r->spare = v * f;
    r->have_spare = 1;
    return u * f;
}

void smd_ab_to_abc_d(double re, double im, double x_abc[3])
{
    x_abc[0] = re;
    x_abc[1] = A_RE * re + A_IM * im;
    x_abc[2] = A_RE * re - A_IM * im;
}

double smd_adc_convert(double x, double gain, double offset, double noise, int bits,
                       double full_scale, smd_rng *r)
{
    double v = gain * x + offset;
    if (noise > 0.0) {
        v += noise * smd_rng_normal(r);
    }
    if (bits > 0) {
        double lsb = 2.0 * full_scale / ldexp(1.0, bits);
        double q = floor(v / lsb + 0.5) * lsb; /* mid-tread */
        if (q > full_scale - lsb) q = full_scale - lsb;
        if (q < -full_scale) q = -full_scale;
        v = q;
    }
    return v;
}

void smd_adc_sample3(const double x_abc[3], const double gain[3], const double offset[3],
                     double noise, int bits, double full_scale, smd_rng *r, double out[3])
{
    int x;
    for (x = 0; x < 3; x++) {
        out[x] = smd_adc_convert(x_abc[x], gain[x], offset[x], noise, bits, full_scale, r);
    }
}

void smd_adc_sample3_avg(const double x_abc[3], const double gain[3], const double offset[3],
                         double noise, int bits, double full_scale, int n_avg, smd_rng *r,
                         double out[3])
{
    int x, k;
    if (n_avg <= 1) {
        smd_adc_sample3(x_abc, gain, offset, noise, bits, full_scale, r, out);
        return;
    }
    /* oversampling: n_avg conversions of each channel (the burst's duration
     * neglected: the same true value), each with its own noise draw and
     * quantisation, then their mean */
    for (x = 0; x < 3; x++) {
        double sum = 0.0;
        for (k = 0; k < n_avg; k++) {
            sum += smd_adc_convert(x_abc[x], gain[x], offset[x], noise, bits, full_scale, r);
        }
        out[x] = sum / (double)n_avg;
    }
}

/*
 * Current-sensor / ADC model and its noise generator, shared by the host
 * plants (smd_plant.c, smd_lcl.c).
 *
 * Per channel: v = gain * x + offset + noise * N(0, 1), then (if bits > 0)
 * mid-tread quantisation to lsb = 2 full_scale / 2^bits, saturating at
 * [-full_scale, full_scale - lsb]. Noise: xoshiro256** seeded by splitmix64,
 * standard normals by the polar method (the spare value is kept).
 */
#ifndef SMD_ADC_H
#define SMD_ADC_H

#include <stdint.h>

typedef struct smd_rng {
    uint64_t s[4];   /* xoshiro256** state */
    int have_spare;
    double spare;
} smd_rng;

void smd_rng_seed(smd_rng *r, uint64_t seed);
uint64_t smd_rng_next(smd_rng *r);
/* Uniform on [0, 1) with 53 random bits. */
double smd_rng_uniform(smd_rng *r);
/* Standard normal. */
double smd_rng_normal(smd_rng *r);

/* Phase values of a space vector (amplitude-invariant Clarke inverse):
 * x_k = Re((re + j im) e^{-j 2 pi k / 3}). */
void smd_ab_to_abc_d(double re, double im, double x_abc[3]);

/* One ADC channel (noise drawn from r only if noise > 0). */
double smd_adc_convert(double x, double gain, double offset, double noise, int bits,
                       double full_scale, smd_rng *r);

/* Three channels in phase order a, b, c. */
void smd_adc_sample3(const double x_abc[3], const double gain[3], const double offset[3],
                     double noise, int bits, double full_scale, smd_rng *r, double out[3]);

/* The same with oversampling: each channel the mean of n_avg conversions
 * (smd_adc_convert each: own noise draw and quantisation; channel a's n_avg
 * draws first, then b's, c's); n_avg <= 1 is smd_adc_sample3. */
void smd_adc_sample3_avg(const double x_abc[3], const double gain[3], const double offset[3],
                         double noise, int bits, double full_scale, int n_avg, smd_rng *r,
                         double out[3]);

#endif

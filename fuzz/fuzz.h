/*
 * Shared by the libFuzzer targets of fuzz/: a reader that turns the fuzz
 * input into integers and reals, and the decoder of a drive configuration
 * (fuzz_drive.c, fuzz_engine.c; generated, fz_drive_config.h).
 * fuzz/make_seeds.py writes the same format.
 *
 * Format (little endian; past the end every read gives zero bytes):
 *   u8, u16, u32         plain bytes
 *   int  (fz_int)        tag byte t: 0xFF INT_MIN, 0xFE INT_MAX, 0xFD a raw
 *                        int32 (4 bytes), 0xFC lo - 1, 0xFB hi + 1; otherwise
 *                        lo + t mod (hi - lo + 1), or for a range wider than
 *                        0xFB values lo + (t << 16 | u16) mod (hi - lo + 1)
 *   real (fz_real)       tag byte t: below 0xE0 lo + (hi - lo) u16 / 65535;
 *                        0xE0-0xEF a special value (NaN, +-inf, +-0, +-FLT_MAX,
 *                        +-1e30, FLT_MIN, a float denormal, +-DBL_MAX, lo,
 *                        hi, 1e300); 0xF0-0xF7 raw float bits (4 bytes);
 *                        0xF8-0xFF raw double bits (8 bytes)
 * So most values land in the range a field is meant for, and NaN, infinity
 * and huge values come up all the time.
 */
#ifndef SMD_FUZZ_H
#define SMD_FUZZ_H

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "smodrive/smd_drive.h"

/* A property the target checks: a failure prints what and where, and stops
 * the run as a crash (libFuzzer keeps the input). */
#define FZ_CHECK(cond)                                                                  \
    do {                                                                                \
        if (!(cond)) {                                                                  \
            fprintf(stderr, "fuzz check failed: %s at %s:%d\n", #cond, __FILE__, __LINE__); \
            __builtin_trap();                                                           \
        }                                                                               \
    } while (0)

/* -DFZ_TRACE: each target prints what an input decoded to (init results,
 * steps run), to check that a seed does what it was written for. */
#ifdef FZ_TRACE
#define FZ_TRACEF(...) fprintf(stderr, __VA_ARGS__)
#else
#define FZ_TRACEF(...) ((void)0)
#endif

typedef struct fz {
    const uint8_t *p;
    size_t n;
} fz;

static inline uint8_t fz_u8(fz *f)
{
    if (f->n == 0) {
        return 0;
    }
    f->n--;
    return *f->p++;
}

static inline uint32_t fz_u16(fz *f)
{
    uint32_t lo = fz_u8(f);
    return lo | ((uint32_t)fz_u8(f) << 8);
}

static inline uint32_t fz_u32(fz *f)
{
    uint32_t lo = fz_u16(f);
    return lo | (fz_u16(f) << 16);
}

static inline int fz_more(const fz *f) { return f->n > 0; }

static inline int fz_int(fz *f, int lo, int hi)
{
    uint32_t t = fz_u8(f);
    uint32_t span = (uint32_t)((int64_t)hi - (int64_t)lo + 1);
    switch (t) {
    case 0xFF: return INT_MIN;
    case 0xFE: return INT_MAX;
    case 0xFD: {
        uint32_t u = fz_u32(f);
        int32_t v;
        memcpy(&v, &u, sizeof v);
        return v;
    }
    case 0xFC: return lo - 1;
    case 0xFB: return hi + 1;
    default: break;
    }
    if (span < 0xFB) {
        return (int)((int64_t)lo + (int64_t)(t % span));
    }
    return (int)((int64_t)lo + (int64_t)(((t << 16) | fz_u16(f)) % span));
}

static inline double fz_real(fz *f, double lo, double hi)
{
    uint32_t t = fz_u8(f);
    if (t < 0xE0) {
        return lo + (hi - lo) * ((double)fz_u16(f) / 65535.0);
    }
    if (t < 0xF0) {
        switch (t - 0xE0) {
        case 0: return (double)NAN;
        case 1: return (double)INFINITY;
        case 2: return -(double)INFINITY;
        case 3: return 0.0;
        case 4: return -0.0;
        case 5: return (double)FLT_MAX;
        case 6: return -(double)FLT_MAX;
        case 7: return 1e30;
        case 8: return -1e30;
        case 9: return (double)FLT_MIN;
        case 10: return 1e-40; /* a float denormal */
        case 11: return DBL_MAX;
        case 12: return -DBL_MAX;
        case 13: return lo;
        case 14: return hi;
        default: return 1e300;
        }
    }
    if (t < 0xF8) {
        uint32_t u = fz_u32(f);
        float x;
        memcpy(&x, &u, sizeof x);
        return (double)x;
    }
    {
        uint64_t u = fz_u32(f);
        double x;
        u |= (uint64_t)fz_u32(f) << 32;
        memcpy(&x, &u, sizeof x);
        return x;
    }
}

/* A real for the core (float by default). Doubles beyond the float range
 * become infinities (IEEE 754; not undefined under clang's sanitizers). */
static inline smd_real fz_r(fz *f, double lo, double hi) { return (smd_real)fz_real(f, lo, hi); }

static inline smd_cplx fz_c(fz *f, double lim)
{
    smd_real re = fz_r(f, -lim, lim);
    return smd_c(re, fz_r(f, -lim, lim));
}

/* Keeps the compiler from dropping results (and reads them: an
 * uninitialised or out-of-bounds value shows under the sanitizers). */
static volatile double fz_sink;
static inline void fz_use(double x) { fz_sink = fz_sink + x; }
static inline void fz_use_c(smd_cplx z)
{
    fz_use((double)z.re);
    fz_use((double)z.im);
}

/* Observer tables decoded from the input: exactly n rows each, allocated
 * with malloc so that AddressSanitizer sees any read past the last row. */
typedef struct fz_tables {
    smd_lcl_model *smo;
    smd_linobs_model *lin;
    int n;
} fz_tables;

#define FZ_TABLE_MAX 8

/* n rows (at most FZ_TABLE_MAX: a larger n becomes FZ_TABLE_MAX, since the
 * caller's contract is a table of n rows); n < 2, negative included, is kept
 * for the init to refuse. t->n is the count to configure. */
static inline void fz_tables_read(fz *f, fz_tables *t, int n)
{
    size_t rows = n <= 0 ? 0 : (n > FZ_TABLE_MAX ? FZ_TABLE_MAX : (size_t)n);
    size_t k, i;
    const size_t nsmo = sizeof(smd_lcl_model) / sizeof(smd_real);
    const size_t nlin = sizeof(smd_linobs_model) / sizeof(smd_real);
    t->n = n < 2 ? n : (int)rows;
    /* malloc(0) may be NULL: the init must reject n < 2 before the NULL
     * check matters; a one-byte block keeps the pointer valid otherwise */
    t->smo = (smd_lcl_model *)malloc(rows ? rows * sizeof(smd_lcl_model) : 1);
    t->lin = (smd_linobs_model *)malloc(rows ? rows * sizeof(smd_linobs_model) : 1);
    for (k = 0; k < rows; k++) {
        smd_real *a = (smd_real *)&t->smo[k];
        smd_real *b = (smd_real *)&t->lin[k];
        for (i = 0; i < nsmo; i++) {
            a[i] = fz_r(f, -2.0, 2.0);
        }
        for (i = 0; i < nlin; i++) {
            b[i] = fz_r(f, -2.0, 2.0);
        }
    }
}

static inline void fz_tables_free(fz_tables *t)
{
    free(t->smo);
    free(t->lin);
    t->smo = 0;
    t->lin = 0;
}

static inline int fz_lcl_source(int position)
{
    return position == SMD_POS_LCL_SMO_PLL || position == SMD_POS_LCL_LINEAR;
}

/* The lead's fault handling (smd_drive.h: SMD_FAULT_LATCHED,
 * smd_drive_clear_faults): used when the header has it. */
#if defined(SMD_FAULT_LATCHED) && !defined(FZ_NO_FAULT_API)
#define FZ_FAULT_API 1
#else
#define FZ_FAULT_API 0
#endif

/* The grid and tables of both LCL observers: one grid (n models from w_min
 * by dw) for both; *t is zeroed by the caller. */
static inline void fz_lcl_grid(fz *f, smd_lcl_smo_config *smo, smd_linobs_config *lin,
                               fz_tables *t)
{
    int n = fz_int(f, 0, 6);
    smo->w_min = lin->w_min = fz_r(f, -2e4, 2e4);
    smo->dw = lin->dw = fz_r(f, 0.0, 2e4);
    fz_tables_read(f, t, n);
    smo->n = lin->n = t->n;
    smo->table = t->smo;
    lin->table = t->lin;
}

/* The observer tables of a drive configuration (smd_drive_config.lin, the
 * call its @fuzz annotation names): for an LCL source the grid and tables,
 * then a byte that makes both tables NULL (0xFF), which init must refuse. */
static inline void fz_lcl_tables(fz *f, smd_drive_config *c, fz_tables *t)
{
    if (fz_lcl_source(c->position)) {
        fz_lcl_grid(f, &c->smo, &c->lin, t);
        if (fz_u8(f) == 0xFF) {
            c->smo.table = 0;
            c->lin.table = 0;
        }
    }
}

/* A drive configuration, every field from the input in the order of
 * smd_drive_config, the observer tables only for an LCL source:
 * fz_drive_config(f, c, t), generated from the header's @fuzz annotations
 * by tools/gen_layout.py (fuzz/make_seeds.py writes the same format from
 * the same list, fuzz/drive_fields.py). */
#include "fz_drive_config.h"

/* Every field of the view (reads them all). */
static inline void fz_use_view(const smd_drive_view *v)
{
    fz_use_c(v->i_dq_ref);
    fz_use_c(v->i_dq);
    fz_use_c(v->u_ab);
    fz_use_c(v->u_ab_ref);
    fz_use_c(v->i_s_hat);
    fz_use_c(v->u_d_hat);
    fz_use((double)v->theta);
    fz_use((double)v->w);
    fz_use((double)v->lambda);
    fz_use((double)v->theta_err);
    fz_use_c(v->e_hat);
    fz_use_c(v->s);
    fz_use_c(v->d_hat);
    fz_use_c(v->v);
    fz_use_c(v->e_lin);
    fz_use((double)v->phase);
}

#endif

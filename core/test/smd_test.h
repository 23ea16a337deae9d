/*
 * Minimal counted test runner for the smodrive core (host only, C99).
 *
 * Each test is a void function run with RUN_TEST(fn). A test passes when all
 * of its CHECKs pass. The executable prints one line per test and ends with
 * the line "N passed, M failed"; smdt_summary() returns the exit code
 * (non-zero when a test failed or when no check ran at all).
 *
 * References are computed in double; the precision under test is smd_real.
 * SMDT_EPS is the unit roundoff scale of smd_real (FLT_EPSILON or
 * DBL_EPSILON); tolerances are written as multiples of it times the
 * magnitude of the largest term involved (see each test's comment).
 */
#ifndef SMD_TEST_H
#define SMD_TEST_H

#include <complex.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "smodrive/smd_types.h"

#ifdef SMD_REAL_DOUBLE
#define SMDT_EPS DBL_EPSILON
#define SMDT_PREC "double"
#else
#define SMDT_EPS ((double)FLT_EPSILON)
#define SMDT_PREC "float"
#endif

/* double-precision imaginary unit (I itself is float complex in glibc) */
#define JD ((double complex)I)
#define R(x) ((smd_real)(x))
#define PI_D 3.14159265358979323846

static int smdt_passed = 0;
static int smdt_failed = 0;
static int smdt_checks_total = 0;
static int smdt_cur_checks = 0;
static int smdt_cur_failed = 0;

/* A uniform number in [lo, hi) from the xorshift32 state *x (24 bits of
 * it): the tests' reproducible arguments. */
static inline double smdt_urand(uint32_t *x, double lo, double hi)
{
    *x ^= *x << 13;
    *x ^= *x >> 17;
    *x ^= *x << 5;
    return lo + (hi - lo) * (double)(*x >> 8) / 16777216.0;
}

static inline void smdt_report(int ok, const char *what, const char *file, int line)
{
    smdt_cur_checks++;
    smdt_checks_total++;
    if (!ok) {
        smdt_cur_failed++;
        printf("    check failed at %s:%d: %s\n", file, line, what);
    }
}

static inline void smdt_close(double x, double ref, double tol, const char *ex, const char *eref,
                              const char *file, int line)
{
    /* written so that NaN fails */
    int ok = fabs(x - ref) <= tol;
    smdt_report(ok, ex, file, line);
    if (!ok) {
        printf("      %s = %.10g, expected %s = %.10g, |diff| = %.3g > tol %.3g\n", ex, x, eref,
               ref, fabs(x - ref), tol);
    }
}

static inline void smdt_cclose(smd_cplx z, double complex ref, double tol, const char *ex,
                               const char *file, int line)
{
    double complex zz = (double)z.re + (double)z.im * JD;
    double d = cabs(zz - ref);
    int ok = d <= tol;
    smdt_report(ok, ex, file, line);
    if (!ok) {
        printf("      %s = %.10g%+.10gj, expected %.10g%+.10gj, |diff| = %.3g > tol %.3g\n", ex,
               creal(zz), cimag(zz), creal(ref), cimag(ref), d, tol);
    }
}

static inline void smdt_int_eq(long x, long ref, const char *ex, const char *file, int line)
{
    int ok = x == ref;
    smdt_report(ok, ex, file, line);
    if (!ok) {
        printf("      %s = %ld, expected %ld\n", ex, x, ref);
    }
}

/* |x - ref| <= tol (NaN fails) */
#define CHECK_CLOSE(x, ref, tol) \
    smdt_close((double)(x), (double)(ref), (double)(tol), #x, #ref, __FILE__, __LINE__)
/* |z - ref| <= tol for an smd_cplx z and a double complex ref */
#define CHECK_CPLX(z, ref, tol) smdt_cclose((z), (ref), (double)(tol), #z, __FILE__, __LINE__)
#define CHECK_INT(x, ref) smdt_int_eq((long)(x), (long)(ref), #x, __FILE__, __LINE__)
#define CHECK(cond) smdt_report((cond) != 0, #cond, __FILE__, __LINE__)

static inline void smdt_run(void (*fn)(void), const char *name)
{
    smdt_cur_checks = 0;
    smdt_cur_failed = 0;
    fn();
    if (smdt_cur_failed == 0 && smdt_cur_checks > 0) {
        smdt_passed++;
        printf("[PASS] %s (%d checks)\n", name, smdt_cur_checks);
    } else {
        smdt_failed++;
        printf("[FAIL] %s (%d of %d checks failed)\n", name, smdt_cur_failed, smdt_cur_checks);
    }
}
#define RUN_TEST(fn) smdt_run(fn, #fn)

static inline int smdt_summary(const char *suite)
{
    printf("# %s [%s]: %d checks\n", suite, SMDT_PREC, smdt_checks_total);
    printf("%d passed, %d failed\n", smdt_passed, smdt_failed);
    return (smdt_failed == 0 && smdt_passed > 0) ? 0 : 1;
}

/* helpers for references */
static inline double complex smdt_z(smd_cplx a) { return (double)a.re + (double)a.im * JD; }
static inline smd_cplx smdt_c(double complex z) { return smd_c(R(creal(z)), R(cimag(z))); }
static inline double smdt_wrap(double x) { return x - 2.0 * PI_D * floor((x + PI_D) / (2.0 * PI_D)); }

/* deterministic pseudo-random numbers in [lo, hi) (LCG, no libc state) */
static inline double smdt_rand(unsigned long *st, double lo, double hi)
{
    *st = (*st * 1103515245UL + 12345UL) & 0x7fffffffUL;
    return lo + (hi - lo) * (double)*st / 2147483648.0;
}

#endif

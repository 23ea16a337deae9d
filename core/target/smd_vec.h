/*
 * Test-vector and processor-in-the-loop runner of the real-time core, built
 * twice from the same sources: for the host (host_io.c, stdio) and for a
 * Cortex-M4F under QEMU (m4/semihost_io.c, ARM semihosting). Both read the
 * same vector file and write their outputs; src/smodrive/target.py compares
 * the two bit for bit and runs the PIL loop.
 *
 * Not part of the core: this harness has globals and file I/O.
 */
#ifndef SMD_VEC_H
#define SMD_VEC_H

#include <stdint.h>

/* File protocol, every word 4 bytes little-endian (both targets are LE):
 *   in : "SMDV" magic, version; then cases, each a kind word:
 *        SMD_CASE_DRIVE  drive config words (smd_cfg_read.h), n_models +
 *                        models, n_lin + linear models, theta0, w0, i_q0
 *                        (floats), n_samples (-1: until the stream ends),
 *                        then n_samples x smd_drive_in (10 floats)
 *        SMD_CASE_TABLES n_models + models, n_lin + linear models (kept for
 *                        the block cases of the LCL observers)
 *        SMD_CASE_BLOCK  block id, n_steps, seed: a block run on inputs from
 *                        a portable PRNG (smd_vec.c)
 *        SMD_CASE_END
 *   out: the magic; per case kind, length in bytes and the outputs: for DRIVE
 *        the init status, then per sample status, d_abc[3], smd_drive_view;
 *        for BLOCK the block id and the outputs of each step (a streamed
 *        DRIVE case, n_samples = -1, has length -1 and is written sample by
 *        sample); at the end END, the number of cases and an error flag. */
#define SMD_VEC_MAGIC 0x56444d53u /* "SMDV" */
#define SMD_VEC_VERSION 1

enum { SMD_CASE_END = 0, SMD_CASE_DRIVE = 1, SMD_CASE_TABLES = 2, SMD_CASE_BLOCK = 3 };

enum {
    SMD_BLK_TRANSFORMS = 1,
    SMD_BLK_SVM = 2,
    SMD_BLK_PI = 3,
    SMD_BLK_DBPC = 4,
    SMD_BLK_SMDO = 5,
    SMD_BLK_EMF_POS = 6,
    SMD_BLK_PLL = 7,
    SMD_BLK_BANDPASS = 8,
    SMD_BLK_LCL_SMO = 9,
    SMD_BLK_LINOBS = 10,
    SMD_BLK_MATH = 11,
    SMD_BLK_TABLE6 = 12,
    SMD_BLK_TABLE6_DEC = 13,
    SMD_BLK_IDENT = 14,
    SMD_BLK_IDENT_LS = 15,
    SMD_BLK_IDENT_PSI = 16,
    SMD_BLK_IDENT_MECH = 17,
    SMD_BLK_N
};

/* Platform I/O (host_io.c or m4/semihost_io.c). Handles are small ints. */
int smd_io_open(const char *path, int write);     /* < 0 on failure */
int smd_io_read(int h, void *buf, int n);         /* bytes read, < n at end */
int smd_io_write(int h, const void *buf, int n);  /* bytes written */
void smd_io_close(int h);
void smd_io_log(const char *msg);                 /* a line to the console */

/* The runner: argv[1] vector file (or FIFO), argv[2] output file (or FIFO).
 * Returns 0 on success. */
int smd_vec_main(int argc, char **argv);

/* Cycle markers: the cycle counter (src/smodrive/target.py) counts the
 * instructions executed between smd_mark_begin and smd_mark_end. */
void smd_mark_begin(int id);
void smd_mark_end(void);

#endif

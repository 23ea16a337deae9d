/*
 * libFuzzer target: the engine (smd_engine_init, smd_engine_run with a
 * small n and a log buffer of exactly the rows it needs, the split step
 * smd_engine_ext_inputs / smd_engine_host_step / smd_engine_ext_apply,
 * smd_pwl_eval, smd_pll_impulse, smd_log_channel_name, smd_sizeof_engine,
 * the layout table):
 * the plant and the drive in closed loop, on configurations, profiles and a
 * start decoded from the input (fuzz.h, fuzz_sim.h):
 *   plant config, drive config (with its observer tables), five profiles
 *   (w_M_ref, T_ext, T_brake, i_d_ref, i_q_ref), i_d_sin_amp, i_d_sin_freq,
 *   start (theta0, w0, i_q0), then operations until the input ends (at most
 *   FZ_MAX_SAMPLES samples):
 *   op % 4 == 0  run 1 + u8 samples, a log row every 1 + op / 4 % 4 samples
 *   op % 4 == 1  one split sample (a log row when op & 4)
 *   op % 4 == 2  smd_pwl_eval of a profile at a time
 *   op % 4 == 3  smd_pll_impulse (n <= 64), a channel name, a row of the
 *                binding's layout table (smd_layout_row_at, smd_layout_type_at)
 *
 * Checked besides the sanitizers: smd_engine_run returns the number of rows
 * it was asked for; the split sample and smd_engine_run agree on status
 * codes the core knows.
 */
#include "fuzz_sim.h"

#define FZ_MAX_SAMPLES 1500

/* The struct layout table of the binding (sim/src/smd_layout.c; declared
 * by its only user, the Python package). */
int smd_layout_rows(void);
int smd_layout_row_at(int k, const char **strct, const char **field, unsigned long *offset,
                      unsigned long *size);
const char *smd_layout_type_at(int k);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz f = {data, size};
    smd_plant_config pc;
    smd_drive_config dc;
    fz_tables tab;
    smd_profiles prof;
    smd_engine_start start;
    smd_engine *e;
    int rc, samples = 0;

    fz_plant_config(&f, &pc);
    fz_drive_config(&f, &dc, &tab);
    memset(&prof, 0, sizeof prof);
    fz_pwl(&f, &prof.w_M_ref, 0.02, 2e3);
    fz_pwl(&f, &prof.T_ext, 0.02, 10.0);
    fz_pwl(&f, &prof.T_brake, 0.02, 10.0);
    fz_pwl(&f, &prof.i_d_ref, 0.02, 50.0);
    fz_pwl(&f, &prof.i_q_ref, 0.02, 50.0);
    prof.i_d_sin_amp = fz_real(&f, -10.0, 10.0);
    prof.i_d_sin_freq = fz_real(&f, 0.0, 2000.0);
    start.theta0 = fz_real(&f, -4.0, 4.0);
    start.w0 = fz_real(&f, -3e4, 3e4);
    start.i_q0 = fz_real(&f, -50.0, 50.0);

    e = (smd_engine *)malloc(sizeof *e);
    FZ_CHECK(smd_sizeof_engine() == sizeof *e);
    rc = smd_engine_init(e, &pc, &dc, &prof, &start);
    FZ_TRACEF("engine: init %d\n", rc);
    FZ_CHECK(rc == 0 || rc == 3000 || (rc > 1000 && rc < 1100) || (rc > 2000 && rc < 2100));
    if (rc != 0) {
        free(e);
        fz_tables_free(&tab);
        return 0;
    }
    while (fz_more(&f) && samples < FZ_MAX_SAMPLES) {
        uint8_t op = fz_u8(&f);
        switch (op % 4) {
        case 0: {
            long n = 1 + fz_u8(&f), stride = 1 + (op / 4) % 4, rows;
            long want;
            double *log;
            if (samples + n > FZ_MAX_SAMPLES) {
                n = FZ_MAX_SAMPLES - samples;
            }
            want = (n + stride - 1) / stride;
            /* exactly ceil(n / stride) rows: a row too many written shows */
            log = (op & 64) ? 0 : (double *)malloc((size_t)want * SMD_LOG_N * sizeof(double));
            rows = smd_engine_run(e, n, log, stride);
            FZ_CHECK(rows == (log != 0 ? want : 0));
            if (log != 0) {
                long k;
                for (k = 0; k < rows; k++) {
                    fz_use(log[k * SMD_LOG_N + SMD_LOG_STATUS]);
                }
                free(log);
            }
            FZ_CHECK(e->last_status >= 0 && e->last_status <= 64);
            samples += (int)n;
            break;
        }
        case 1: {
            smd_drive_in in;
            smd_drive_out out;
            smd_drive_view v;
            double row[SMD_LOG_N];
            int st;
            memset(&in, 0, sizeof in);
            memset(&out, 0, sizeof out);
            smd_engine_ext_inputs(e, &in);
            st = smd_engine_host_step(e, &in, &out, &v);
            FZ_CHECK(st >= 0 && st <= 64);
            smd_engine_ext_apply(e, &out, st, (op & 4) ? &v : 0, row);
            if (op & 4) {
                int k;
                for (k = 0; k < SMD_LOG_N; k++) {
                    fz_use(row[k]);
                }
            }
            samples++;
            break;
        }
        case 2: {
            const smd_pwl *pw[5];
            pw[0] = &e->prof.w_M_ref;
            pw[1] = &e->prof.T_ext;
            pw[2] = &e->prof.T_brake;
            pw[3] = &e->prof.i_d_ref;
            pw[4] = &e->prof.i_q_ref;
            {
                const smd_pwl *which = pw[fz_u8(&f) % 5];
                fz_use(smd_pwl_eval(which, fz_real(&f, -0.01, 0.2)));
            }
            break;
        }
        default: {
            double out[64];
            long n = fz_u8(&f) % 65, k;
            double T = fz_real(&f, 0.0, 1e-3), kt = fz_real(&f, 0.0, 2.0);
            double kw = fz_real(&f, 0.0, 1e3), ka = fz_real(&f, 0.0, 1e4);
            double amp = fz_real(&f, -1.0, 1.0);
            if (smd_pll_impulse(T, kt, kw, ka, amp, n, out) == 0) {
                for (k = 0; k < n; k++) {
                    fz_use(out[k]);
                }
            }
            fz_use((double)smd_log_channel_name(fz_int(&f, -1, SMD_LOG_N))[0]);
            {
                int row = fz_int(&f, -1, 400);
                const char *st = 0, *fd = 0;
                unsigned long off = 0, sz = 0;
                if (smd_layout_row_at(row, &st, &fd, &off, &sz)) {
                    FZ_CHECK(row >= 0 && row < smd_layout_rows() && st != 0 && fd != 0);
                    fz_use((double)(st[0] + fd[0]) + (double)(off + sz));
                }
                fz_use((double)smd_layout_type_at(row)[0]);
            }
            break;
        }
        }
    }
    FZ_TRACEF("engine: %d samples, t = %g s, w_M = %g rad/s, last status %d\n", samples,
              (double)e->k * e->T_sp, e->plant.w_M, e->last_status);
    free(e);
    fz_tables_free(&tab);
    return 0;
}

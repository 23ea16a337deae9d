/* C consumer of the installed smodrive core, compiled with nothing but the
 * flags of `pkg-config --cflags --libs smodrive`: init the yang2018 drive
 * (SMD_CC_DBPC on the encoder, Table I machine) and run it on a rotating
 * current; exit status 0 only if init and every step return SMD_OK with
 * finite duties in [0, 1]. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <smodrive/smd_drive.h>

int main(void)
{
    smd_drive_config c;
    smd_drive_params p;
    smd_drive_state s;
    smd_status st;
    int k, x;
    memset(&c, 0, sizeof c);
    c.current = SMD_CC_DBPC;
    c.position = SMD_POS_ENCODER;
    c.start = SMD_START_RUNNING;
    c.T_sp = 1e-4f;
    c.L_s_hat = 23.45e-3f;
    c.R_s_hat = 2.25f;
    c.psi_r_hat = 0.4f;
    c.lambda_min = 800.0f;
    c.l = 1200.0f;
    c.w_c = 1500.0f;
    c.rho = 0.2f;
    c.w_lpf = 200.0f;
    c.w_hys = 20.0f;
    c.w_max = 2000.0f;
    c.k_p_i = 46.9f;
    c.k_i_i = 46900.0f;
    c.L_dec = 23.45e-3f;
    c.emf_ff = 1;
    c.k_p_w = 0.05f;
    c.k_i_w = 2.0f;
    c.i_max = 15.0f;
    c.speed_decimation = 1;
    c.k_theta = 0.1f;
    c.k_omega = 10.0f;
    c.k_a = 10.0f;
    c.i_start = 8.0f;
    c.a_start = 2e4f;
    c.w_handover = 201.0f;
    c.svm_limit = SMD_SVM_LIMIT_HEXAGON;
    c.i_dtc = 1.0f;
    st = smd_drive_init(&p, &c);
    if (st != SMD_OK) {
        printf("FAIL: smd_drive_init: %s\n", smd_status_str(st));
        return 1;
    }
    smd_drive_reset(&p, &s, 0.0f, 100.0f, 0.0f);
    for (k = 0; k < 50; k++) {
        smd_drive_in in;
        smd_drive_out out;
        float th = 0.01f * (float)k;
        memset(&in, 0, sizeof in);
        in.i_a = 2.0f * cosf(th);
        in.i_b = 2.0f * cosf(th - 2.0943951f);
        in.theta_enc = th;
        in.w_enc = 100.0f;
        in.u_dc = 540.0f;
        in.w_ref = 100.0f;
        in.i_dq_ref = smd_c(0.0f, 2.0f);
        st = smd_drive_step(&p, &s, &in, &out);
        if (st != SMD_OK) {
            printf("FAIL: smd_drive_step %d: %s\n", k, smd_status_str(st));
            return 1;
        }
        for (x = 0; x < 3; x++) {
            if (!(isfinite(out.d_abc[x]) && out.d_abc[x] >= 0.0f && out.d_abc[x] <= 1.0f)) {
                printf("FAIL: step %d: duty %d = %g\n", k, x, (double)out.d_abc[x]);
                return 1;
            }
        }
    }
    printf("C consumer (pkg-config): 50 steps of SMD_CC_DBPC on the encoder, duties in [0, 1]\n");
    return 0;
}

/* C consumer of the installed smodrive core, compiled with nothing but the
 * flags of `pkg-config --cflags --libs smodrive`: init the yang2018 drive of
 * the example configuration (smd_example.h: SMD_CC_DBPC on the encoder,
 * Table I machine) and run it on a rotating current; exit status 0 only if
 * init and every step return SMD_OK with finite duties in [0, 1]. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <smodrive/smd_drive.h>
#include <smodrive/smd_example.h>

int main(void)
{
    smd_drive_config c;
    smd_drive_params p;
    smd_drive_state s;
    smd_status st;
    int k, x;
    smd_example_drive_config(&c);
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

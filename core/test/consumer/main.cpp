// C++ consumer of the installed smodrive core: the yang2018 Table I machine
// under deadbeat current control on the encoder (SMD_CC_DBPC, SMD_POS_ENCODER,
// SMD_START_RUNNING: the example configuration of smd_example.h), closed
// around the exact discrete RL plant of core/test/drive_fixture.h. Exit status
// 0 only if init returns SMD_OK, every step returns SMD_OK with finite duties
// in [0, 1], and the current follows its reference.
#include <smodrive/smd_drive.h>
#include <smodrive/smd_example.h>

#include <cmath>
#include <complex>
#include <cstdio>

namespace {

typedef std::complex<double> cd;

const double LS = 23.45e-3, RS = 2.25, PSI = 0.4, TSP = 1e-4, UDC = 540.0;
const double PI_D = 3.14159265358979323846;
const cd J(0.0, 1.0);

} // namespace

int main()
{
    smd_drive_config c;
    smd_example_drive_config(&c);
    smd_drive_params p;
    smd_drive_state s;
    const smd_status st = smd_drive_init(&p, &c);
    if (st != SMD_OK) {
        std::printf("FAIL: smd_drive_init: %s\n", smd_status_str(st));
        return 1;
    }
    const double w = 300.0;          // electrical rad/s
    const cd i_ref(-0.5, 3.0);       // A, rotor frame
    const cd a = std::exp(J * (2.0 * PI_D / 3.0));
    cd i(0.0, 0.0), u(0.0, 0.0);
    double th = 0.3, err = 0.0;
    const int n = 400;
    smd_drive_reset(&p, &s, smd_real(th), smd_real(w), 0.0f);
    for (int k = 0; k < n; k++) {
        smd_drive_in in = smd_drive_in();
        smd_drive_out out;
        in.i_a = smd_real(i.real());
        in.i_b = smd_real((i * std::conj(a)).real());
        in.theta_enc = smd_real(th);
        in.w_enc = smd_real(w);
        in.u_dc = smd_real(UDC);
        in.w_ref = smd_real(w);
        in.i_dq_ref = smd_c(smd_real(i_ref.real()), smd_real(i_ref.imag()));
        const smd_status sk = smd_drive_step(&p, &s, &in, &out);
        if (sk != SMD_OK) {
            std::printf("FAIL: smd_drive_step %d: %s\n", k, smd_status_str(sk));
            return 1;
        }
        for (int x = 0; x < 3; x++) {
            const smd_real d = out.d_abc[x];
            if (!(std::isfinite(d) && d >= 0.0f && d <= 1.0f)) {
                std::printf("FAIL: step %d: duty %d = %g\n", k, x, double(d));
                return 1;
            }
        }
        if (k >= n - 100) {
            err = std::fmax(err, std::abs(i * std::exp(-J * th) - i_ref));
        }
        // exact plant over [k, k+1) with the voltage decided at k-1
        const cd C = -J * w * PSI * std::exp(J * th) / (RS + J * w * LS);
        i = std::exp(-RS / LS * TSP) * (i - u / RS - C) + u / RS + C * std::exp(J * w * TSP);
        th = std::remainder(th + w * TSP, 2.0 * PI_D);
        u = (2.0 / 3.0) * UDC *
            (double(out.d_abc[0]) + double(out.d_abc[1]) * a + double(out.d_abc[2]) * a * a);
    }
    std::printf("C++ consumer: %d steps of SMD_CC_DBPC on the encoder, duties in [0, 1], "
                "|i_dq - i_ref| <= %.3g A over the last 100\n", n, err);
    if (!(err < 0.2)) {
        std::printf("FAIL: the current does not follow its reference\n");
        return 1;
    }
    return 0;
}

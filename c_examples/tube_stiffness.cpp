// The thin-tube coupling stiffness from C++17, as a finite-element code would
// use it: the C header included as is, statuses turned into exceptions at the
// call site, results in std::array. Prints the same "name = value" lines as the
// C driver for the same default tube, plus a sweep over the helix angle.
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "rodkit.h"

namespace {

void check(int32_t st, const char *what) {
    if (st < 0)
        throw std::runtime_error(std::string(what) + ": " + rodkit_status_string(st) + ": " +
                                 rodkit_last_error_message());
}

std::array<double, 9> coupling_stiffness(const RodkitThinTubeSpec &spec) {
    std::array<double, 9> k{};
    check(rodkit_thin_tube_coupling_stiffness(&spec, k.data(), 3), "coupling_stiffness");
    return k;
}

}  // namespace

int main() {
    try {
        RodkitThinTubeSpec spec;
        check(rodkit_thin_tube_spec_default(&spec), "spec_default");
        spec.mid_radius = 1.0;
        spec.thickness = 0.4;
        spec.intrinsic_twist = std::tan(M_PI / 3.0);
        spec.e1 = 300.0;
        spec.e2 = 900.0;
        spec.nu12 = 0.3;
        spec.g12 = 100.0;
        std::printf("# rodkit %s from C++17: DNA-like thin tube\n", RODKIT_VERSION_STRING);
        std::printf("intrinsic_twist = %.17g\n", spec.intrinsic_twist);
        const auto k = coupling_stiffness(spec);
        const char *names[3] = {"strain", "twist", "hoop"};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) std::printf("K_%s_%s = %.17g\n", names[i], names[j], k[i + 3 * j]);

        std::printf("# helix angle sweep: angle_deg, K_strain_twist, g, winding\n");
        for (int deg = 0; deg <= 85; deg += 5) {
            spec.intrinsic_twist = std::tan(deg * M_PI / 180.0) / spec.mid_radius;
            std::array<double, 4> s{};
            check(rodkit_thin_tube_stretch_twist(&spec, s.data(), 2), "stretch_twist");
            RodkitFreeTubeResponse r{};
            check(rodkit_thin_tube_free_response(&spec, &r), "free_response");
            std::printf("sweep %2d %+.6e %+.6e %+d\n", deg, coupling_stiffness(spec)[3], s[2], (int)r.winding);
        }

        // A failing call surfaces as an exception carrying rodkit's message.
        spec.e2 = -1.0;
        try {
            coupling_stiffness(spec);
            std::printf("error_caught = 0\n");
            return 1;
        } catch (const std::runtime_error &e) {
            std::printf("# expected failure: %s\nerror_caught = 1\n", e.what());
        }
    } catch (const std::exception &e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}

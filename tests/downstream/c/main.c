/* A downstream C program, built against an installed rodkit by CMake
 * (find_package(rodkit), rodkit::rodkit or rodkit::rodkit_static) and by
 * pkg-config (tests/downstream/run.sh). It checks that the library it
 * loaded is the one its header describes, and one computed number against
 * its closed form: an isotropic thin tube without twist (E = 200, ν = 0.3,
 * R = 1, t = 0.01) in uniaxial stress at zero pressure, S = 2πRt·E, and
 * the reinforcement's helix angle atan(τ0 R) of a twisted one. */
#include <math.h>
#include <rodkit.h>
#include <stdio.h>

int main(void) {
    int32_t major = -1, minor = -1, patch = -1;
    if (rodkit_version(&major, &minor, &patch) != 0 || major != RODKIT_VERSION_MAJOR ||
        minor != RODKIT_VERSION_MINOR || patch != RODKIT_VERSION_PATCH ||
        rodkit_library_abi_version() != RODKIT_ABI_VERSION) {
        fprintf(stderr, "version mismatch: library %d.%d.%d ABI %d, header %s ABI %d\n", major, minor, patch,
                rodkit_library_abi_version(), RODKIT_VERSION_STRING, RODKIT_ABI_VERSION);
        return 1;
    }
    RodkitThinTubeSpec spec;
    rodkit_thin_tube_spec_default(&spec);
    spec.mid_radius = 1.0;
    spec.thickness = 0.01;
    spec.intrinsic_twist = 0.0;
    spec.e1 = spec.e2 = 200.0;
    spec.nu12 = 0.3;
    spec.g12 = 200.0 / (2.0 * 1.3);
    double s[4];
    if (rodkit_thin_tube_stretch_twist(&spec, s, 2) != 0) {
        fprintf(stderr, "stretch_twist: %s\n", rodkit_last_error_message());
        return 1;
    }
    const double pi = acos(-1.0), exact = 2.0 * pi * 1.0 * 0.01 * 200.0;
    spec.intrinsic_twist = 0.5;
    double alpha = -1.0;
    if (rodkit_thin_tube_helix_angle(&spec, &alpha) != 0) return 1;
    printf("rodkit %s (ABI %d): S = %.15g (2 pi R t E = %.15g), helix angle %.15g (atan 0.5 = %.15g)\n",
           RODKIT_VERSION_STRING, RODKIT_ABI_VERSION, s[0], exact, alpha, atan(0.5));
    return fabs(s[0] - exact) <= 1e-12 * exact && fabs(alpha - atan(0.5)) <= 1e-15 ? 0 : 1;
}

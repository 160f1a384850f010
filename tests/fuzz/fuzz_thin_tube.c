/* Fuzz target: the thin tube group (rodkit_thin_tube_*). See fuzz.h. */
#include "fuzz.h"

static const struct fuzz_field fields[] = {
    FUZZ_F(RodkitThinTubeSpec, mid_radius), FUZZ_F(RodkitThinTubeSpec, thickness),
    FUZZ_F(RodkitThinTubeSpec, intrinsic_twist), FUZZ_F(RodkitThinTubeSpec, e1),
    FUZZ_F(RodkitThinTubeSpec, e2), FUZZ_F(RodkitThinTubeSpec, nu12),
    FUZZ_F(RodkitThinTubeSpec, g12),
};

static void matrix(const char *func, int32_t (*f)(const RodkitThinTubeSpec *, double *, int64_t),
                   const RodkitThinTubeSpec *s, int64_t n) {
    int64_t ld = n + fuzz_below(3) - (fuzz_below(8) == 0);
    size_t len = ld > 0 ? (size_t)(ld * (n - 1) + n) : 1;
    double *k = fuzz_buffer(len);
    if (fuzz_status(func, f(s, k, ld)) >= 0) {
        for (int64_t j = 0; j < n; j++) {
            fuzz_finite(func, "matrix", k + ld * j, (size_t)n);
            fuzz_positive(func, "diagonal", k[j + ld * j]);
        }
        fuzz_padding(func, k, ld, n, n);
    }
    fuzz_guard(func, "matrix", k, len);
}

static void fuzz_one(void) {
    RodkitThinTubeSpec s = {1.0, 0.4, 1.7320508075688772, 800.0, 250.0, 0.6, 180.0};
    fuzz_perturb(&s, sizeof s, fields, FUZZ_COUNT(fields));
    switch (fuzz_below(5)) {
    case 0: {
        double a = NAN;
        if (fuzz_status("rodkit_thin_tube_helix_angle", rodkit_thin_tube_helix_angle(&s, &a)) >= 0)
            fuzz_finite("rodkit_thin_tube_helix_angle", "alpha", &a, 1);
        break;
    }
    case 1: {
        RodkitFreeTubeResponse r;
        if (fuzz_status("rodkit_thin_tube_free_response", rodkit_thin_tube_free_response(&s, &r)) >= 0) {
            double v[] = {r.dstrain_dforce, r.dtwist_dforce, r.dhoop_dforce};
            fuzz_finite("rodkit_thin_tube_free_response", "response", v, 3);
            if (r.winding < -1 || r.winding > 1)
                fuzz_violation("rodkit_thin_tube_free_response", "winding", "winding outside -1…1");
        }
        break;
    }
    case 2: matrix("rodkit_thin_tube_coupling_stiffness", rodkit_thin_tube_coupling_stiffness, &s, 3); break;
    case 3: matrix("rodkit_thin_tube_stretch_twist", rodkit_thin_tube_stretch_twist, &s, 2); break;
    default: matrix("rodkit_thin_tube_rod_stiffness", rodkit_thin_tube_rod_stiffness, &s, 6); break;
    }
}

int main(int argc, char **argv) { return fuzz_main("thin_tube", argc, argv); }

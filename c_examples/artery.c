/*
 * A pressurised artery stretched axially (physics.md 1.3): incompressible
 * neo-Hookean matrix with two helical collagen families at +-29 degrees
 * (Holzapfel-Gasser-Ogden media of a rabbit carotid: mu = 3.0 kPa,
 * k1 = 2.3632 kPa, k2 = 0.8393, inner radius 0.71 mm, wall 0.26 mm;
 * Holzapfel, Gasser & Ogden, J. Elasticity 61 (2000), table 1), closed ends,
 * 13.33 kPa (100 mmHg) inside, torsion-free, stretch 1.0 -> 1.3. This is the
 * media alone, stress-free in the reference tube (no adventitia, no opening
 * angle), so it inflates far more than the two-layer artery of the paper.
 *
 * Usage: artery [--values] [out.csv]
 * Units: mm and kPa, so forces are in kPa*mm^2 = mN.
 * Prints a short report (--values: also "name = value" lines for the state
 * at the last stretch, progress and a table); with a path, rodkit writes the
 * whole sweep, loadings and states, as CSV (rodkit_tube_sweep_write_csv).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

#include "rodkit.h"

/* --values (first argument): also print the details, every result as a
 * "name = value" line (the channel rodkit's tests read) and the tables;
 * without it, a short report. */
static int values;
#define DETAIL(...)                      \
    do {                                 \
        if (values) printf(__VA_ARGS__); \
    } while (0)

#define N_STEPS 31

static int fail(int32_t st, const char *what) {
    fprintf(stderr, "%s failed: %s (%d): %s\n", what, rodkit_status_string(st), (int)st,
            rodkit_last_error_message());
    return 1;
}

static int32_t report(const RodkitProgress *p, void *user_data) {
    int *every = (int *)user_data;
    if (p->done % *every == 0 || p->done == p->total)
        DETAIL("# progress %lld/%lld\n", (long long)p->done, (long long)p->total);
    return 0; /* continue */
}

int main(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "--values") == 0) {
        values = 1;
        ++argv;
        --argc;
    }
    const char *out_path = argc > 1 ? argv[1] : NULL;
    const double deg = acos(-1.0) / 180.0;

    RodkitTubeSpec spec;
    rodkit_tube_spec_default(&spec);
    spec.inner_radius = 0.71;
    spec.outer_radius = 0.71 + 0.26;
    spec.material.law = RODKIT_WALL_LAW_KIND_FIBRE_REINFORCED;
    spec.material.incompressible = 1;
    spec.material.shear_modulus = 3.0;
    spec.material.fibre_families = 2;
    spec.material.fibre1_k1 = 2.3632;
    spec.material.fibre1_k2 = 0.8393;
    spec.material.fibre1_angle = 29.0 * deg;
    spec.material.fibre2_k1 = 2.3632;
    spec.material.fibre2_k2 = 0.8393;
    spec.material.fibre2_angle = -29.0 * deg;
    spec.model = RODKIT_TUBE_MODEL_THICK;
    spec.rel_tol = 1e-10;

    RodkitTube *tube = NULL;
    int32_t st = rodkit_tube_new(&spec, &tube);
    if (st < 0) return fail(st, "rodkit_tube_new");

    RodkitTubeLoading loadings[N_STEPS];
    for (int i = 0; i < N_STEPS; ++i) {
        rodkit_tube_loading_default(&loadings[i]);
        loadings[i].axial_control = RODKIT_AXIAL_CONTROL_STRETCH;
        loadings[i].axial = 1.0 + 0.01 * i;
        loadings[i].torsion_control = RODKIT_TORSION_CONTROL_TORQUE;
        loadings[i].torsion = 0.0;
        loadings[i].inner_pressure = 13.33;
        loadings[i].closed_ends = 1;
    }
    RodkitTubeState states[N_STEPS];
    int64_t done = 0;
    int every = 10;
    st = rodkit_tube_sweep(tube, loadings, N_STEPS, states, report, &every, &done);
    if (st < 0) {
        rodkit_tube_free(tube);
        return fail(st, "rodkit_tube_sweep");
    }

    if (out_path && (st = rodkit_tube_sweep_write_csv(loadings, states, done, "mm", "mN", out_path)) < 0) {
        rodkit_tube_free(tube);
        return fail(st, "rodkit_tube_sweep_write_csv");
    }

    const RodkitTubeState *s = &states[done - 1];
    DETAIL("# rodkit %s: HGO artery, p = 13.33 kPa, closed ends, torsion-free stretch\n", RODKIT_VERSION_STRING);
    DETAIL("states = %lld\n", (long long)done);
    DETAIL("stretch = %.17g\napplied_force = %.17g\nwall_force = %.17g\ntwist = %.17g\n", s->stretch,
           s->applied_force, s->wall_force, s->twist);
    DETAIL("inner_radius = %.17g\nouter_radius = %.17g\nerror_estimate = %.3g\nintervals = %lld\n",
           s->deformed_inner_radius, s->deformed_outer_radius, s->error_estimate, (long long)s->intervals);
    DETAIL("# stretch  axial force (mN)  inner radius (mm)\n");
    for (int64_t i = 0; i < done; i += 5)
        DETAIL("# %6.3f  %14.6f  %12.6f\n", states[i].stretch, states[i].applied_force,
               states[i].deformed_inner_radius);
    printf("Artery wall (HGO media, fibres at +-29 deg; 13.33 kPa inside, closed ends) stretched %.2f -> %.2f at zero torque\n",
           states[0].stretch, s->stretch);
    printf("  axial force %.4f -> %.4f mN, lumen radius %.4f -> %.4f mm, twist %.1e rad/mm (balanced fibres)\n",
           states[0].applied_force, s->applied_force, states[0].deformed_inner_radius, s->deformed_inner_radius,
           s->twist);
    if (out_path) printf("  sweep (%lld states, CSV): %s\n", (long long)done, out_path);
    rodkit_tube_free(tube);
    return 0;
}

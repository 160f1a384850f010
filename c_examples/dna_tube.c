/*
 * DNA as a helically reinforced tube (physics.md 1.5), from C.
 *
 * 1. Fit the thin wall (E1, E2, G12 at R = 1 nm, helix angle 60 deg, t and
 *    nu12 fixed) to the single-molecule stretch-twist law S = 1100 pN,
 *    C = 440 pN nm^2, g = -90 pN nm; print the overwinding rate and the same
 *    material evaluated with the thick wall (t/R = 0.4 is not thin).
 * 2. The family of fits over t and nu12 (the fit is not unique).
 * 3. Torsion-free finite stretching of the fitted wall as a thick SVK tube:
 *    twist and radius vs stretch, with the overwind/unwind pattern
 *    detected; with a path, rodkit writes the sweep as CSV
 *    (rodkit_tube_sweep_write_csv).
 * Usage: dna_tube [--values] [stretch.csv]
 * Prints a short report; --values adds every result as a "name = value"
 * line and the family of fits as a table.
 * Units: nm, pN.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rodkit.h"

/* --values (first argument): also print the details, every result as a
 * "name = value" line (the channel rodkit's tests read) and the tables;
 * without it, a short report. */
static int values;
#define DETAIL(...)                      \
    do {                                 \
        if (values) printf(__VA_ARGS__); \
    } while (0)

static int fail(int32_t st, const char *what) {
    fprintf(stderr, "%s failed: %s (%d): %s\n", what, rodkit_status_string(st), (int)st,
            rodkit_last_error_message());
    return 1;
}

int main(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "--values") == 0) {
        values = 1;
        ++argv;
        --argc;
    }
    const char *csv_path = argc > 1 ? argv[1] : NULL;
    const double pi = acos(-1.0), alpha = pi / 3.0, radius = 1.0, t = 0.4, nu12 = 0.3;
    const double S = 1100.0, C = 440.0, g = -90.0;

    RodkitDnaFit fit;
    int32_t st = rodkit_dna_fit_thin_wall(S, C, g, radius, alpha, t, nu12, &fit);
    if (st < 0) return fail(st, "rodkit_dna_fit_thin_wall");
    DETAIL("# rodkit %s: DNA as a helically reinforced tube (pN, nm)\n", RODKIT_VERSION_STRING);
    DETAIL("# 1. thin-wall fit at R = 1 nm, alpha = 60 deg, t = 0.4 nm, nu12 = 0.3\n");
    DETAIL("e1 = %.17g\ne2 = %.17g\ng12 = %.17g\n", fit.spec.e1, fit.spec.e2, fit.spec.g12);
    DETAIL("stretch_S = %.17g\ntwist_C = %.17g\ncoupling_g = %.17g\n", fit.stretch, fit.twist, fit.coupling);
    DETAIL("twist_rate = %.17g\nturns_per_pn_per_10kbp = %.17g\noverwinds = %d\n", fit.twist_rate,
           fit.turns_per_pn_per_10kbp, (int)fit.overwinds);
    if (fit.thick_status < 0) {
        DETAIL("# thick evaluation failed: %s\n", rodkit_status_string(fit.thick_status));
    } else {
        DETAIL("thick_stretch_S = %.17g\nthick_twist_C = %.17g\nthick_coupling_g = %.17g\n", fit.thick_stretch,
               fit.thick_twist, fit.thick_coupling);
        DETAIL("thick_turns_per_pn_per_10kbp = %.17g\n", fit.thick_turns_per_pn_per_10kbp);
        DETAIL("# thick vs thin: S %+.2f %%, C %+.2f %%, g %+.2f %%\n", 100 * (fit.thick_stretch / fit.stretch - 1),
               100 * (fit.thick_twist / fit.twist - 1), 100 * (fit.thick_coupling / fit.coupling - 1));
    }

    DETAIL("# 2. family of fits (E1, E2, G12 in pN/nm^2; rate in turns/pN/10 kbp)\n");
    DETAIL("#    t    nu12        E1        E2       G12   thin rate  thick rate\n");
    const double ts[] = {0.2, 0.3, 0.4, 0.5}, nus[] = {0.0, 0.3, 0.5, 1.0};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            RodkitDnaFit f;
            int32_t s2 = rodkit_dna_fit_thin_wall(S, C, g, radius, alpha, ts[i], nus[j], &f);
            if (s2 < 0)
                DETAIL("# %5.2f %6.2f   no physical fit: %s\n", ts[i], nus[j], rodkit_last_error_message());
            else if (f.thick_status < 0)
                DETAIL("# %5.2f %6.2f %9.2f %9.2f %9.2f %11.5f   (3-D completion not positive definite)\n", ts[i],
                       nus[j], f.spec.e1, f.spec.e2, f.spec.g12, f.turns_per_pn_per_10kbp);
            else
                DETAIL("# %5.2f %6.2f %9.2f %9.2f %9.2f %11.5f %11.5f\n", ts[i], nus[j], f.spec.e1, f.spec.e2,
                       f.spec.g12, f.turns_per_pn_per_10kbp, f.thick_turns_per_pn_per_10kbp);
        }

    /* 3. Finite stretching of the fitted wall as a thick SVK tube. */
    RodkitTubeSpec spec;
    rodkit_tube_spec_default(&spec);
    spec.inner_radius = radius - t / 2;
    spec.outer_radius = radius + t / 2;
    RodkitWallMaterialSpec *m = &spec.material;
    m->law = RODKIT_WALL_LAW_KIND_SAINT_VENANT_KIRCHHOFF;
    m->intrinsic_twist = fit.spec.intrinsic_twist;
    m->e1 = fit.spec.e1;
    m->e2 = fit.spec.e2;
    m->e3 = fit.spec.e2;
    m->nu12 = m->nu13 = m->nu23 = nu12;
    m->g12 = m->g13 = fit.spec.g12;
    m->g23 = fit.spec.e2 / (2 * (1 + nu12));
    spec.model = RODKIT_TUBE_MODEL_THICK;
    spec.rel_tol = 1e-10;
    RodkitTube *tube = NULL;
    if ((st = rodkit_tube_new(&spec, &tube)) < 0) return fail(st, "rodkit_tube_new");
    /* The section as a hemitropic rod for a rod solver: 6x6 in (u1, u2, u3, v1, v2, v3). */
    double rod[36], rod_err;
    if ((st = rodkit_tube_rod_stiffness(tube, rod, 6, &rod_err)) < 0) return fail(st, "rodkit_tube_rod_stiffness");
    DETAIL("# the fitted section as a rod (thick wall; bending and shear layer by layer)\n");
    DETAIL("rod_bending = %.17g\nrod_twist = %.17g\nrod_shear = %.17g\nrod_stretch = %.17g\n", rod[0], rod[2 + 6 * 2],
           rod[3 + 6 * 3], rod[5 + 6 * 5]);
    DETAIL("rod_twist_stretch = %.17g\nrod_bend_shear = %.17g\nrod_error_estimate = %.3g\n", rod[2 + 6 * 5],
           rod[0 + 6 * 3], rod_err);
    DETAIL("# bending persistence length K_b/kT = %.1f nm (DNA: about 50 nm; the tube fit knows only S, C, g)\n",
           rod[0] / 4.114);
    enum { N = 41 };
    RodkitTubeLoading loads[N];
    RodkitTubeState states[N];
    for (int i = 0; i < N; ++i) {
        rodkit_tube_loading_default(&loads[i]);
        loads[i].axial = 1.0 + 0.005 * i;
        loads[i].torsion_control = RODKIT_TORSION_CONTROL_TORQUE;
    }
    int64_t done = 0;
    st = rodkit_tube_sweep(tube, loads, N, states, NULL, NULL, &done);
    rodkit_tube_free(tube);
    if (st < 0) return fail(st, "rodkit_tube_sweep");
    if (csv_path && (st = rodkit_tube_sweep_write_csv(loads, states, done, "nm", "pN", csv_path)) < 0)
        return fail(st, "rodkit_tube_sweep_write_csv");
    int turns_back = 0, radius_turns = 0;
    for (int64_t i = 0; i < done; ++i) {
        if (i >= 2) {
            double d1 = states[i - 1].twist - states[i - 2].twist, d2 = states[i].twist - states[i - 1].twist;
            double r1 = states[i - 1].deformed_outer_radius - states[i - 2].deformed_outer_radius;
            double r2 = states[i].deformed_outer_radius - states[i - 1].deformed_outer_radius;
            turns_back += d1 * d2 < 0;
            radius_turns += r1 * r2 < 0;
        }
    }
    DETAIL("# 3. torsion-free stretching of the fitted wall as a thick SVK tube\n");
    DETAIL("final_stretch = %.17g\nfinal_twist = %.17g\nfinal_force = %.17g\n", states[done - 1].stretch,
           states[done - 1].twist, states[done - 1].applied_force);
    DETAIL("twist_reversals = %d\nradius_reversals = %d\n", turns_back, radius_turns);
    DETAIL("# %s\n", turns_back ? "the twist reverses: overwinding followed by unwinding"
                                : "psi(lambda) is monotone: this wall overwinds throughout (no unwinding)");
    printf("DNA as a helically reinforced tube (R = 1 nm, t = 0.4 nm, helix 60 deg) fitted to S = %g pN, C = %g pN nm^2,\n"
           "  g = %g pN nm: E1 = %.1f, E2 = %.1f, G12 = %.1f pN/nm^2; it %s when pulled, %.4f turns/pN per 10 kbp\n",
           S, C, g, fit.spec.e1, fit.spec.e2, fit.spec.g12, fit.overwinds ? "overwinds" : "unwinds",
           fit.turns_per_pn_per_10kbp);
    if (fit.thick_status >= 0)
        printf("  the same wall as a thick tube: S %+.1f %%, C %+.1f %%, g %+.1f %% from the thin-wall law\n",
               100 * (fit.thick_stretch / fit.stretch - 1), 100 * (fit.thick_twist / fit.twist - 1),
               100 * (fit.thick_coupling / fit.coupling - 1));
    printf("  stretched to %.2f at zero torque (thick SVK wall): force %.1f pN, twist %.4f rad/nm, %s\n",
           states[done - 1].stretch, states[done - 1].applied_force, states[done - 1].twist,
           turns_back ? "the twist reverses" : "overwinding throughout");
    if (csv_path) printf("  sweep (%lld states, CSV): %s\n", (long long)done, csv_path);
    return 0;
}

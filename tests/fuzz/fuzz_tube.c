/* Fuzz target: the tube group (rodkit_tube_*, wall material). See fuzz.h. */
#include "fuzz.h"

static const struct fuzz_field spec_fields[] = {
    FUZZ_F(RodkitTubeSpec, inner_radius),           FUZZ_F(RodkitTubeSpec, outer_radius),
    FUZZ_I(RodkitTubeSpec, model),                  FUZZ_F(RodkitTubeSpec, rel_tol),
    FUZZ_L(RodkitTubeSpec, intervals),              FUZZ_I(RodkitTubeSpec, material.law),
    FUZZ_I(RodkitTubeSpec, material.incompressible), FUZZ_F(RodkitTubeSpec, material.intrinsic_twist),
    FUZZ_F(RodkitTubeSpec, material.e1),            FUZZ_F(RodkitTubeSpec, material.e2),
    FUZZ_F(RodkitTubeSpec, material.e3),            FUZZ_F(RodkitTubeSpec, material.nu12),
    FUZZ_F(RodkitTubeSpec, material.nu13),          FUZZ_F(RodkitTubeSpec, material.nu23),
    FUZZ_F(RodkitTubeSpec, material.g12),           FUZZ_F(RodkitTubeSpec, material.g13),
    FUZZ_F(RodkitTubeSpec, material.g23),           FUZZ_F(RodkitTubeSpec, material.shear_modulus),
    FUZZ_F(RodkitTubeSpec, material.lame_lambda),   FUZZ_L(RodkitTubeSpec, material.fibre_families),
    FUZZ_F(RodkitTubeSpec, material.fibre1_k1),     FUZZ_F(RodkitTubeSpec, material.fibre1_k2),
    FUZZ_F(RodkitTubeSpec, material.fibre1_angle),  FUZZ_F(RodkitTubeSpec, material.fibre1_hand),
    FUZZ_F(RodkitTubeSpec, material.fibre2_k1),     FUZZ_F(RodkitTubeSpec, material.fibre2_k2),
    FUZZ_F(RodkitTubeSpec, material.fibre2_angle),  FUZZ_F(RodkitTubeSpec, material.fibre2_hand),
};
static const struct fuzz_field loading_fields[] = {
    FUZZ_I(RodkitTubeLoading, axial_control),  FUZZ_F(RodkitTubeLoading, axial),
    FUZZ_I(RodkitTubeLoading, torsion_control), FUZZ_F(RodkitTubeLoading, torsion),
    FUZZ_F(RodkitTubeLoading, inner_pressure), FUZZ_F(RodkitTubeLoading, outer_pressure),
    FUZZ_I(RodkitTubeLoading, closed_ends),
};

static RodkitTubeSpec base_spec(int which) {
    RodkitTubeSpec s;
    rodkit_tube_spec_default(&s);
    RodkitWallMaterialSpec *m = &s.material;
    if (which == 0) {
        s.inner_radius = 0.6, s.outer_radius = 1.4;
        m->law = RODKIT_WALL_LAW_KIND_SAINT_VENANT_KIRCHHOFF, m->intrinsic_twist = 1.7;
        m->e1 = 10, m->e2 = 2, m->e3 = 1.5, m->nu12 = 0.35, m->nu13 = 0.3, m->nu23 = 0.4;
        m->g12 = 1.2, m->g13 = 0.8, m->g23 = 0.6;
    } else if (which == 1) {
        s.inner_radius = 1.0, s.outer_radius = 1.2;
        m->law = RODKIT_WALL_LAW_KIND_NEO_HOOKEAN, m->shear_modulus = 1.0, m->lame_lambda = 2.0;
    } else {
        s.inner_radius = 0.8, s.outer_radius = 1.0;
        m->law = RODKIT_WALL_LAW_KIND_FIBRE_REINFORCED, m->shear_modulus = 1.0, m->lame_lambda = 2.0;
        m->fibre_families = 2, m->fibre1_k1 = 1, m->fibre1_k2 = 1, m->fibre1_angle = 0.5, m->fibre1_hand = 1;
        m->fibre2_k1 = 1, m->fibre2_k2 = 1, m->fibre2_angle = -0.5, m->fibre2_hand = -1;
    }
    return s;
}

static void check_state(const char *func, const RodkitTubeState *s) {
    double v[] = {s->stretch,        s->twist,          s->wall_force,           s->applied_force,
                  s->torque,         s->inner_pressure, s->outer_pressure,       s->deformed_inner_radius,
                  s->deformed_outer_radius, s->error_estimate};
    fuzz_finite(func, "state", v, FUZZ_COUNT(v));
    fuzz_positive(func, "deformed_outer_radius", s->deformed_outer_radius);
    fuzz_positive(func, "stretch", s->stretch);
}

/* A square matrix entry point with a random leading dimension. */
static void matrix(const char *func, int32_t (*f)(const RodkitTube *, double *, int64_t, double *),
                   const RodkitTube *t, int64_t n) {
    int64_t ld = n + fuzz_below(3) - (fuzz_below(8) == 0);
    size_t len = ld > 0 ? (size_t)(ld * (n - 1) + n) : 1;
    double *k = fuzz_buffer(len), est = NAN;
    if (fuzz_status(func, f(t, k, ld, fuzz_below(2) ? &est : NULL)) >= 0) {
        for (int64_t j = 0; j < n; j++) {
            fuzz_finite(func, "matrix", k + ld * j, (size_t)n);
            fuzz_positive(func, "diagonal", k[j + ld * j]);
        }
        fuzz_padding(func, k, ld, n, n);
    }
    fuzz_guard(func, "matrix", k, len);
}

static int32_t stretch_twist(const RodkitTube *t, double *s, int64_t lds, double *unused) {
    (void)unused;
    return rodkit_tube_stretch_twist(t, s, lds);
}

static void fuzz_one(void) {
    RodkitTubeSpec spec = base_spec(fuzz_below(3));
    fuzz_perturb(&spec, sizeof spec, spec_fields, FUZZ_COUNT(spec_fields));
    RodkitTube *t = (RodkitTube *)&spec; /* must come back NULL on failure */
    if (fuzz_status("rodkit_tube_new", rodkit_tube_new(&spec, &t)) < 0) {
        if (t) fuzz_violation("rodkit_tube_new", "handle-on-failure", "*out not NULL after a failure");
        return;
    }
    RodkitTubeLoading l;
    rodkit_tube_loading_default(&l);
    l.axial = 1.0 + 0.05 * (fuzz_unit() - 0.3);
    fuzz_perturb(&l, sizeof l, loading_fields, FUZZ_COUNT(loading_fields));
    RodkitTubeState s;
    if (fuzz_status("rodkit_tube_solve", rodkit_tube_solve(t, &l, &s)) >= 0) check_state("rodkit_tube_solve", &s);

    switch (fuzz_below(5)) {
    case 0: {
        int64_t count = -1;
        if (fuzz_status("rodkit_tube_profile", rodkit_tube_profile(t, &l, 0, NULL, NULL, NULL, NULL, NULL, NULL,
                                                                   &count)) < 0 || count <= 0 || count > 100000)
            break;
        size_t cap = (size_t)count + (size_t)fuzz_below(2);
        double *c[6];
        for (int i = 0; i < 6; i++) c[i] = fuzz_buffer(cap);
        if (fuzz_status("rodkit_tube_profile",
                        rodkit_tube_profile(t, &l, (int64_t)cap, c[0], c[1], c[2], c[3], c[4], c[5], &count)) >= 0)
            for (int i = 0; i < 6; i++) fuzz_finite("rodkit_tube_profile", "profile", c[i], (size_t)count);
        for (int i = 0; i < 6; i++) fuzz_guard("rodkit_tube_profile", "profile column", c[i], cap);
        break;
    }
    case 1: {
        RodkitTubeLoading ls[3] = {l, l, l};
        ls[1].axial *= 1.01, ls[2].axial *= 1.02;
        fuzz_perturb(&ls[2], sizeof ls[2], loading_fields, FUZZ_COUNT(loading_fields));
        RodkitTubeState out[4];
        memset(out, 0x5a, sizeof out);
        int64_t done = -1;
        int32_t st = fuzz_status("rodkit_tube_sweep", rodkit_tube_sweep(t, ls, 3, out, NULL, NULL, &done));
        if (st >= 0)
            for (int i = 0; i < 3; i++) check_state("rodkit_tube_sweep", &out[i]);
        unsigned char pat[sizeof out[3]];
        memset(pat, 0x5a, sizeof pat);
        if (memcmp(&out[3], pat, sizeof pat) != 0)
            fuzz_violation("rodkit_tube_sweep", "overflow", "states written past count");
        /* The sweep as CSV: the states written, or all three (the unwritten
         * ones' 0x5a bytes must be refused with a status, not written). */
        int64_t rows = fuzz_below(2) && done > 0 ? done : 3;
        const char *path = "/tmp/rodkit-fuzz-tube-sweep.csv";
        fuzz_status("rodkit_tube_sweep_write_csv", rodkit_tube_sweep_write_csv(ls, out, rows, "mm", "mN", path));
        remove(path);
        break;
    }
    case 2: matrix("rodkit_tube_coupling_stiffness", rodkit_tube_coupling_stiffness, t, 3); break;
    case 3: matrix("rodkit_tube_stretch_twist", stretch_twist, t, 2); break;
    default: matrix("rodkit_tube_rod_stiffness", rodkit_tube_rod_stiffness, t, 6); break;
    }
    rodkit_tube_free(t);
}

int main(int argc, char **argv) { return fuzz_main("tube", argc, argv); }

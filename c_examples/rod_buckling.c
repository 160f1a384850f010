/*
 * Euler buckling and post-buckling of a clamped-free rod from C
 * (physics.md 2.4, 2.6).
 *
 * An extensible, shearable Cosserat rod (K_b = 1, C = 1/1.3, GA = 300,
 * EA = 1000, L = 1; Gauss-Legendre, 4 stages, 16 elements) under an axial
 * dead compressive tip load Lambda*(0, 0, -1):
 *  1. the straight branch by Newton continuation with bifurcation detection:
 *     the double (symmetric) bifurcation point, compared with the extensible
 *     Euler load P(1 + P(1/GA - 1/EA)) = pi^2 K_b/(4 L^2);
 *  2. the buckled branch by the ANM from that point (rodkit chooses a phase
 *     condition for the symmetric rod) until the tip has turned by 170 deg;
 *  3. the buckled branch's records as CSV and its shapes as VTK polydata
 *     for ParaView, written by rodkit (rodkit_branch_write_csv, _vtk) when
 *     their paths are given.
 * Usage: c_rod_buckling [--values] [csv path] [vtk path]
 * Prints a short report; --values adds every result as a "name = value"
 * line and the branch as a table.
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

static int fail(int32_t st, const char *what) {
    fprintf(stderr, "%s failed: %s (%d): %s\n", what, rodkit_status_string(st), (int)st, rodkit_last_error_message());
    return 1;
}

/* Stop the buckled branch once the tip has turned by more than 171
 * degrees; counts the calls in *user_data. */
static int32_t stop_past_171(const RodkitBranchProgress *p, void *user_data) {
    *(int64_t *)user_data += 1;
    return p->tip_rotation * 180.0 / acos(-1.0) > 171.0;
}

int main(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "--values") == 0) {
        values = 1;
        ++argv;
        --argc;
    }
    const char *csv_path = argc > 1 ? argv[1] : NULL;
    const char *vtk_path = argc > 2 ? argv[2] : NULL;
    const double pi = acos(-1.0), ga = 300.0, ea = 1000.0;

    RodkitRodSpec spec;
    rodkit_rod_spec_default(&spec);
    spec.length = 1.0;
    spec.bending1 = spec.bending2 = 1.0;
    spec.twist = 1.0 / 1.3;
    spec.shear1 = spec.shear2 = ga;
    spec.stretch = ea;
    spec.tip_force_frame = RODKIT_LOAD_FRAME_DEAD;
    spec.tip_force_z = -1.0;
    spec.scheme = RODKIT_ROD_SCHEME_GAUSS;
    spec.stages = 4;
    spec.elements = 16;
    RodkitRod *rod = NULL;
    int32_t st = rodkit_rod_new(&spec, &rod);
    if (st < 0) return fail(st, "rodkit_rod_new");
    int64_t n;
    rodkit_rod_unknowns(rod, &n);
    double *x0 = malloc((size_t)n * sizeof(double));
    rodkit_rod_straight_state(rod, x0, n);

    /* 1. Straight branch with detection. */
    RodkitContinuationOptions opts;
    rodkit_continuation_options_default(&opts);
    opts.method = RODKIT_CONTINUATION_METHOD_NEWTON;
    opts.target_lambda = 3.0;
    opts.initial_step = 0.2;
    opts.max_step = 0.5;
    opts.residual_tol = 1e-12;
    opts.detect_bifurcations = 1;
    opts.bifurcation_tol = 1e-11;
    RodkitBranch *straight = NULL;
    st = rodkit_rod_continue(rod, x0, n, 0.0, &opts, NULL, NULL, &straight);
    free(x0);
    if (st < 0) return fail(st, "rodkit_rod_continue (straight)");
    int64_t nbif = 0;
    RodkitBifurcation bif;
    st = rodkit_branch_bifurcations(straight, rod, &bif, 1, &nbif);
    if (st < 0) return fail(st, "rodkit_branch_bifurcations");
    if (nbif < 1) {
        fprintf(stderr, "no bifurcation found on the straight branch\n");
        return 1;
    }
    const double c = 1.0 / ga - 1.0 / ea, pe = pi * pi / 4.0;
    const double formula = (-1.0 + sqrt(1.0 + 4.0 * c * pe)) / (2.0 * c);
    DETAIL("# rodkit %s: Euler buckling and post-buckling of a clamped-free Cosserat rod\n", RODKIT_VERSION_STRING);
    DETAIL("# 1. straight branch (Newton continuation, bifurcation detection)\n");
    DETAIL("bifurcations = %lld\n", (long long)nbif);
    DETAIL("critical_load = %.15g\nmultiplicity = %lld\n", bif.lambda, (long long)bif.multiplicity);
    DETAIL("extensible_euler_formula = %.15g\nrelative_error = %.3e\n", formula, fabs(bif.lambda - formula) / formula);
    DETAIL("inextensible_euler_load = %.15g\n", pe);
    /* Where the point lies on the branch, and what said it is there: the
       record it follows, the evidence (det of the bordered tangent, the
       test function), and no bracket left unresolved. */
    RodkitBifurcationPoint where;
    st = rodkit_branch_bifurcation_points(straight, rod, &where, 1, &nbif);
    if (st < 0) return fail(st, "rodkit_branch_bifurcation_points");
    RodkitBranchRecord around[2];
    int64_t nrec = 0;
    RodkitBranchInfo straight_info;
    rodkit_branch_summary(straight, &straight_info);
    RodkitBranchRecord *all = malloc((size_t)straight_info.records * sizeof *all);
    if (!all) return 1;
    st = rodkit_branch_records(straight, all, straight_info.records, &nrec);
    if (st < 0) return fail(st, "rodkit_branch_records");
    around[0] = all[where.record];
    around[1] = all[where.record + 1];
    free(all);
    int64_t unresolved = -1;
    st = rodkit_branch_unresolved(straight, NULL, 0, &unresolved);
    if (st < 0) return fail(st, "rodkit_branch_unresolved");
    DETAIL("bifurcation_record = %lld\nbracket_lambda_low = %.15g\nbracket_lambda_high = %.15g\n",
           (long long)where.record, around[0].lambda, around[1].lambda);
    DETAIL("det_sign_change = %d\ntest_function_change = %d\nunresolved = %lld\n", where.det_sign_change,
           where.test_function_change, (long long)unresolved);

    /* 2. Buckled branch by the ANM, stopped by the callback past 171 deg. */
    rodkit_continuation_options_default(&opts);
    opts.method = RODKIT_CONTINUATION_METHOD_ANM;
    opts.anm_order = 20;
    opts.anm_epsilon = 1e-10;
    opts.residual_tol = 1e-10;
    opts.max_step = 0.2;
    opts.lambda_min = 0.0;
    opts.lambda_max = 100.0;
    opts.max_steps = 200;
    RodkitBranch *buckled = NULL;
    int64_t calls = 0;
    st = rodkit_branch_switch(rod, straight, 0, 0, 0.05, &opts, stop_past_171, &calls, &buckled);
    if (st < 0) return fail(st, "rodkit_branch_switch");
    RodkitBranchInfo info;
    rodkit_branch_summary(buckled, &info);
    RodkitBranchRecord *rec = malloc((size_t)info.records * sizeof(RodkitBranchRecord));
    int64_t count = 0;
    rodkit_branch_records(buckled, rec, info.records, &count);
    DETAIL("# 2. buckled branch (ANM P = 20, eps = 1e-10, phase condition %s): %lld points, %lld steps, "
           "%lld factorisations, status %s\n",
           info.phase_condition ? "on" : "off", (long long)count, (long long)info.steps,
           (long long)info.factorisations, rodkit_status_string(st));
    DETAIL("#   lambda      tip x       tip z    tip rotation(deg)  unfolding\n");
    int64_t last = 0;
    for (int64_t i = 0; i < count; ++i) {
        if (rec[i].tip_rotation * 180.0 / pi > 171.0) break;
        last = i;
        if (i % 5 == 0) DETAIL("# %9.5f %10.6f %10.6f %12.4f %12.2e\n", rec[i].lambda, rec[i].tip_x, rec[i].tip_z,
                               rec[i].tip_rotation * 180.0 / pi, rec[i].unfolding);
    }
    DETAIL("points_to_170_deg = %lld\ncallback_calls = %lld\n", (long long)(last + 1), (long long)calls);
    DETAIL("final_load = %.15g\nfinal_tip_rotation_deg = %.15g\n", rec[last].lambda, rec[last].tip_rotation * 180.0 / pi);
    DETAIL("final_tip_x = %.15g\nfinal_tip_y = %.15g\nfinal_tip_z = %.15g\n", rec[last].tip_x, rec[last].tip_y, rec[last].tip_z);

    DETAIL("records = %lld\n", (long long)count);

    /* 3. The buckled branch's records as CSV and eight shapes up to 170 deg
     * as VTK polydata (cell data lambda and end_rotation), written by rodkit
     * when paths are given. */
    if (csv_path && (st = rodkit_branch_write_csv(buckled, rod, csv_path)) < 0)
        return fail(st, "rodkit_branch_write_csv");
    int64_t shapes[8], ns = 0;
    for (int64_t k = 0; k < 8; ++k) shapes[ns++] = k * last / 7;
    if (vtk_path && (st = rodkit_branch_write_vtk(buckled, rod, shapes, ns, vtk_path)) < 0)
        return fail(st, "rodkit_branch_write_vtk");

    printf("Euler buckling of a clamped-free Cosserat rod (K_b = 1, GA = %g, EA = %g, L = 1, 16 elements)\n", ga, ea);
    printf("  critical load %.10f (double point), extensible Euler formula %.10f (relative difference %.1e)\n",
           bif.lambda, formula, fabs(bif.lambda - formula) / formula);
    printf("  buckled branch by the ANM: %lld points to a tip rotation of %.1f deg at load %.4f\n", (long long)(last + 1),
           rec[last].tip_rotation * 180.0 / pi, rec[last].lambda);
    if (csv_path) printf("  records (%lld, CSV): %s\n", (long long)count, csv_path);
    if (vtk_path) printf("  %lld shapes (VTK, for ParaView): %s\n", (long long)ns, vtk_path);

    free(rec);
    rodkit_branch_free(buckled);
    rodkit_branch_free(straight);
    rodkit_rod_free(rod);
    return 0;
}

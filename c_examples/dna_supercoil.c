/*
 * DNA supercoiling from C (physics.md 3, issue 5): a charged Kirchhoff rod
 * (the DNA scene: 1 kbp = 340 nm, 1 pN, Debye-Hueckel screening by
 * monovalent salt, effective charge nu = 1/l_B (Manning), radius 1 nm,
 * A = 50 nm, P = 95 nm) clamped at both ends, continued in the end
 * rotation from the straight rod through its first buckling point along
 * the buckled branch - the curves magnetic-tweezers experiments measure.
 *
 * Prints the extension and torque vs turns table with the twist/writhe
 * partition (Tw + Wr = turns), the buckling point and the work, the last
 * point re-solved under the other charge model (continuum <-> base pairs)
 * by Newton-Krylov and by the direct solver (a short report; --values adds
 * the table and every result as a "name = value" line), and has rodkit
 * write, when their paths are given ("-": none)
 *   - the path as CSV (rodkit_supercoil_write_csv),
 *   - the shapes as VTK polydata (one polyline per written point) for ParaView.
 * Usage: c_dna_supercoil [--values] [--model full-rod|thermal] [--kT E] [salt M] [max steps] [csv path] [vtk path]
 *                        [elements] [base pairs] [charges] [control]
 * (defaults full-rod, 0.1, 60, no CSV, no VTK, 100, 1000, continuum, rotation);
 * charges "discrete" uses the base-pair point charges (the thesis's comparison);
 * control "torque" continues in the end torque (a torque clamp) instead of
 * the end rotation: the same equilibria, the turns read from each shape.
 *
 * --model (issue 37): full-rod (the default: this program's reference run,
 * the charged rod at zero temperature, whose values the tests read) or
 * thermal: the thermal two-phase model (rodkit_tweezers_*, physics.md
 * 3.7) at kT (--kT, default 4.11 pN nm; 0: its zero-temperature limit) for
 * the same molecule (base pairs), salt and force (1 pN): 200 points from 0
 * to twice its buckling turns, the curve as CSV when a path is given. It
 * has no shapes (a VTK path is refused), no continuation (steps and
 * elements are not used) and a line charge only (charges "discrete" and
 * control "torque" are refused). Its report names the model; its --values
 * lines are two_phase_buckling_turns / two_phase_buckling_torque_pN_nm
 * (where the buckled population reaches 1/2 and the unbuckled torque
 * there: the equilibrium transition, NOT the full rod's buckling_turns,
 * the straight rod's own instability), extension_jump_nm,
 * plateau_torque_pN_nm, slope_nm_per_turn, superhelix_radius_nm, points,
 * out_of_range_points, and last_turns, last_extension_nm,
 * last_torque_pN_nm, last_writhe (the last point's thermal means).
 */
#include <stdio.h>
#include <stdlib.h>
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
    fprintf(stderr, "%s failed: %s (%d): %s\n", what, rodkit_status_string(st), (int)st, rodkit_last_error_message());
    return 1;
}

static const char *model_name(int32_t m) {
    return m == RODKIT_SUPERCOIL_MODEL_THERMAL_TWO_PHASE           ? "thermal_two_phase"
           : m == RODKIT_SUPERCOIL_MODEL_ZERO_TEMPERATURE_TWO_PHASE ? "zero_temperature_two_phase"
                                                                    : "full_rod";
}

/* --model thermal: the two-phase curve of the scene (positional arguments as
 * for the full rod; those that do not apply are refused or unused). */
static int thermal(int argc, char **argv, double kT) {
    if (argc > 4 && strcmp(argv[4], "-")) {
        fprintf(stderr, "--model thermal has no shapes: give \"-\" as the VTK path\n");
        return 2;
    }
    if ((argc > 7 && argv[7][0] == 'd') || (argc > 8 && argv[8][0] == 't')) {
        fprintf(stderr, "--model thermal: a continuum line charge in the end rotation only (no \"discrete\" charges, no \"torque\" control)\n");
        return 2;
    }
    RodkitTweezersSpec spec;
    RodkitTweezers *h = NULL;
    int32_t st = rodkit_tweezers_spec_default(&spec);
    if (st < 0) return fail(st, "rodkit_tweezers_spec_default");
    RodkitDnaSupercoilSpec rod;
    if ((st = rodkit_dna_supercoil_spec_default(&rod)) < 0) return fail(st, "rodkit_dna_supercoil_spec_default");
    spec.salt = argc > 1 ? atof(argv[1]) : 0.1;
    spec.base_pairs = argc > 6 ? atof(argv[6]) : (double)rod.base_pairs;
    spec.force = rod.tension;
    spec.kt = kT;
    const char *csv_path = argc > 3 && strcmp(argv[3], "-") ? argv[3] : NULL;
    enum { N = 200 };
    double turns[N];
    RodkitTweezersPoint pts[N];
    RodkitTweezersInfo s;
    if ((st = rodkit_tweezers_new(&spec, &h)) < 0) return fail(st, "rodkit_tweezers_new");
    if ((st = rodkit_tweezers_default_turns(h, N, turns)) < 0) return fail(st, "rodkit_tweezers_default_turns");
    if ((st = rodkit_tweezers_curve(h, turns, N, pts)) < 0) return fail(st, "rodkit_tweezers_curve");
    if ((st = rodkit_tweezers_summary(h, pts, N, &s)) < 0) return fail(st, "rodkit_tweezers_summary");
    rodkit_tweezers_free(h);
    int64_t outside = 0;
    for (int i = 0; i < N; ++i) outside += !pts[i].in_range;
    const RodkitTweezersPoint *last = &pts[N - 1];
    DETAIL("# model: %s (kT %g pN nm)\n", model_name(s.model), kT);
    DETAIL("points = %d\nout_of_range_points = %lld\nkT_pN_nm = %.15g\n", N, (long long)outside, kT);
    DETAIL("two_phase_buckling_turns = %.15g\ntwo_phase_buckling_torque_pN_nm = %.15g\nextension_jump_nm = %.15g\n",
           s.buckling_turns, s.buckling_torque, s.extension_jump);
    DETAIL("plateau_torque_pN_nm = %.15g\nslope_nm_per_turn = %.15g\nsuperhelix_radius_nm = %.15g\n", s.plateau_torque, s.slope,
           s.superhelix_radius);
    DETAIL("last_turns = %.15g\nlast_extension_nm = %.15g\nlast_torque_pN_nm = %.15g\nlast_writhe = %.15g\n", last->turns,
           last->extension, last->torque, last->writhe);
    if (csv_path) {
        FILE *f = fopen(csv_path, "w");
        if (!f) {
            perror(csv_path);
            return 1;
        }
        fprintf(f, "turns,extension_nm,torque_pN_nm,twist,writhe,plectoneme_length_nm,plectonemes,buckled_probability,in_range\n");
        for (int i = 0; i < N; ++i)
            fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d\n", pts[i].turns, pts[i].extension, pts[i].torque,
                    pts[i].twist, pts[i].writhe, pts[i].plectoneme_length, pts[i].plectonemes, pts[i].buckled_probability,
                    (int)pts[i].in_range);
        if (fclose(f) != 0) {
            perror(csv_path);
            return 1;
        }
    }
    printf("DNA supercoiling (model %s, kT %g pN nm): %g bp at %.3g pN in %.3g M salt, %d points to twice the buckling turns\n",
           model_name(s.model), kT, spec.base_pairs, spec.force, spec.salt, N);
    printf("  buckles (buckled population 1/2) at %.3f turns (torque %.2f pN nm, the extension jumping by %.1f nm);\n"
           "  plectonemes: plateau torque %.2f pN nm, slope %.2f nm/turn, superhelix radius %.2f nm\n",
           s.buckling_turns, s.buckling_torque, s.extension_jump, s.plateau_torque, s.slope, s.superhelix_radius);
    if (csv_path) printf("  curve (CSV): %s\n", csv_path);
    return 0;
}

int main(int argc, char **argv) {
    int full_rod = 1;
    double kT = 4.11;
    int kT_given = 0;
    for (;;) {
        if (argc > 1 && strcmp(argv[1], "--values") == 0) {
            values = 1;
            ++argv;
            --argc;
        } else if (argc > 2 && strcmp(argv[1], "--model") == 0) {
            if (strcmp(argv[2], "thermal") == 0) full_rod = 0;
            else if (strcmp(argv[2], "full-rod") == 0) full_rod = 1;
            else {
                fprintf(stderr, "--model: full-rod or thermal (got %s)\n", argv[2]);
                return 2;
            }
            argv += 2;
            argc -= 2;
        } else if (argc > 2 && strcmp(argv[1], "--kT") == 0) {
            kT = atof(argv[2]);
            kT_given = 1;
            argv += 2;
            argc -= 2;
        } else
            break;
    }
    if (full_rod && kT_given) {
        fprintf(stderr, "--kT applies to --model thermal only (the full rod is at zero temperature)\n");
        return 2;
    }
    if (!full_rod) return thermal(argc, argv, kT);
    RodkitDnaSupercoilSpec spec;
    int32_t st = rodkit_dna_supercoil_spec_default(&spec);
    if (st < 0) return fail(st, "rodkit_dna_supercoil_spec_default");
    spec.salt = argc > 1 ? atof(argv[1]) : 0.1;
    spec.max_steps = argc > 2 ? atoll(argv[2]) : 60;
    const char *csv_path = argc > 3 && strcmp(argv[3], "-") ? argv[3] : NULL;
    const char *vtk_path = argc > 4 && strcmp(argv[4], "-") ? argv[4] : NULL;
    spec.elements = argc > 5 ? atoll(argv[5]) : 100;
    if (argc > 6) spec.base_pairs = atoll(argv[6]);
    if (argc > 7) spec.discrete_base_pairs = argv[7][0] == 'd';
    if (argc > 8) spec.end_control = argv[8][0] == 't' ? RODKIT_END_CONTROL_TORQUE : RODKIT_END_CONTROL_ROTATION;

    RodkitSupercoil *run = NULL;
    st = rodkit_dna_supercoil_run(&spec, &run);
    if (st < 0) return fail(st, "rodkit_dna_supercoil_run");
    const char *stop = st == RODKIT_STATUS_INFO_STRAND_CROSSING ? "strand crossing"
                     : st == RODKIT_STATUS_INFO_STEP_LIMIT      ? "step limit"
                     : st == RODKIT_STATUS_INFO_STEP_TOO_SMALL  ? "step too small"
                                                                : "turn range";
    RodkitSupercoilInfo info;
    if ((st = rodkit_supercoil_summary(run, &info)) < 0) return fail(st, "rodkit_supercoil_summary");
    RodkitSupercoilPoint *pts = malloc(sizeof *pts * (size_t)info.points);
    double *xyz = malloc(sizeof *xyz * 3 * (size_t)info.nodes);
    if (!pts || !xyz) return 1;
    int64_t count = 0;
    if ((st = rodkit_supercoil_points(run, pts, info.points, &count)) < 0) return fail(st, "rodkit_supercoil_points");

    DETAIL("# DNA supercoiling: %lld bp, %.3g pN, %.3g M salt (Debye length %.4g nm), nu = %.4g e/nm, a = %.3g nm\n",
           (long long)spec.base_pairs, spec.tension, spec.salt, 1.0 / info.kappa, spec.charge_per_length, spec.radius);
    DETAIL("# %lld elements of Gauss(%lld); screening cutoff %.4g..%.4g nm (tolerance %.1e); continued in the end %s\n", (long long)spec.elements,
           (long long)spec.stages, info.cutoff_on, info.cutoff_off, spec.cutoff_tolerance,
           spec.end_control == RODKIT_END_CONTROL_TORQUE ? "torque (torque clamp)" : "rotation");
    if (info.base_pair_charges > 0)
        DETAIL("# model: discrete base pairs, %lld point charges\n", (long long)info.base_pair_charges);
    else
        DETAIL("# model: continuum line charge (near zone regularised)\n");
    DETAIL("base_pair_charges = %lld\n", (long long)info.base_pair_charges);
    DETAIL("bjerrum_length_nm = %.15g\nline_charge_squared_pN = %.15g\n", info.bjerrum_length, info.line_charge_squared);
    DETAIL("points = %lld\nstraight_points = %lld\n", (long long)info.points, (long long)info.straight_points);
    DETAIL("buckling_turns = %.15g\nbuckling_torque_pN_nm = %.15g\n", info.buckling_turns, info.buckling_torque);
    DETAIL("crossing = %d\n", (int)info.crossing);
    if (info.crossing)
        DETAIL("crossing_distance_nm = %.6g\n# strands crossed at s = %.4g and %.4g nm\n", info.crossing_distance, info.crossing_s1, info.crossing_s2);
    DETAIL("# the buckled branch stopped at: %s\n", stop);
    DETAIL("steps = %lld\nfactorisations = %lld\nresiduals = %lld\npair_lists = %lld\nseconds = %.4g\n", (long long)info.steps,
           (long long)info.factorisations, (long long)info.residuals, (long long)info.pair_lists, info.seconds);

    /* The table: every point of the straight branch would repeat the line
     * z = L, so it prints every 4th point, and the last. */
    DETAIL("#  branch    turns   extension(nm)  torque(pN nm)     Tw       Wr    Tw+Wr-turns\n");
    double worst_lk = 0.0;
    for (int64_t i = 0; i < count; ++i) {
        double lk = pts[i].twist + pts[i].writhe - pts[i].turns;
        if (lk < 0) lk = -lk;
        if (lk > worst_lk) worst_lk = lk;
        if (i % 4 == 0 || i == count - 1)
            DETAIL("#  %6s %8.4f %12.4f %14.5f %8.4f %8.4f %10.2e\n", pts[i].branch ? "buckled" : "straight", pts[i].turns,
                   pts[i].extension, pts[i].torque, pts[i].twist, pts[i].writhe, pts[i].twist + pts[i].writhe - pts[i].turns);
    }
    DETAIL("worst_linking_error = %.3e\n", worst_lk);
    DETAIL("last_turns = %.15g\nlast_extension_nm = %.15g\nlast_torque_pN_nm = %.15g\nlast_writhe = %.15g\n", pts[count - 1].turns,
           pts[count - 1].extension, pts[count - 1].torque, pts[count - 1].writhe);

    /* The thesis's comparison on the path's last shape: the same end
     * rotation under the other charge model (base pairs for a continuum
     * run and vice versa), solved by Newton-Krylov and by the direct sparse
     * Newton; the shift is how far the shape moves between the models. */
    RodkitEquilibriumSpec es;
    if ((st = rodkit_equilibrium_spec_default(&es)) < 0) return fail(st, "rodkit_equilibrium_spec_default");
    es.discrete_base_pairs = !spec.discrete_base_pairs;
    es.cutoff_tolerance = spec.cutoff_tolerance;
    /* 1e-9, not the default 1e-10: Newton-Krylov's central-difference
     * products leave the other model's residual a rounding floor near
     * 1e-10 (this scene's last point stalled at 1.15e-10 and the solve
     * failed), and the shift between the models (nm) needs far less. */
    es.residual_tol = 1e-9;
    RodkitEquilibrium eq[2];
    memset(eq, 0, sizeof eq);
    const int32_t solvers[2] = {RODKIT_EQUILIBRIUM_SOLVER_NEWTON_KRYLOV, RODKIT_EQUILIBRIUM_SOLVER_DIRECT};
    int32_t direct_status = 0;
    for (int k = 0; k < 2; ++k) {
        es.solver = solvers[k];
        st = rodkit_supercoil_solve_point(run, count - 1, &es, &eq[k], k == 0 ? xyz : NULL, 3, info.nodes);
        if (st < 0 && k == 0) return fail(st, "rodkit_supercoil_solve_point");
        /* The direct solver's damped Newton can stall where Newton-Krylov
         * converges (the default scene's last point with base pairs: at a
         * scaled residual of 4.4e-7): reported, not fatal. */
        if (st < 0) {
            direct_status = st;
            DETAIL("# the direct solver failed: %s (%d): %s\n", rodkit_status_string(st), (int)st, rodkit_last_error_message());
        }
    }
    DETAIL("# last point under the %s model: Newton-Krylov %lld Newton / %lld GMRES iterations (preconditioner band %lld), direct %lld factorisations\n",
           es.discrete_base_pairs ? "base-pair" : "continuum", (long long)eq[0].newton_iterations, (long long)eq[0].linear_iterations,
           (long long)eq[0].preconditioner_band, (long long)eq[1].factorisations);
    DETAIL("seconds_newton_krylov = %.4g\n", eq[0].seconds);
    DETAIL("other_model_torque_pN_nm = %.15g\nother_model_extension_nm = %.15g\nother_model_shift_nm = %.6g\n", eq[0].torque,
           eq[0].extension, eq[0].shift);
    DETAIL("direct_status = %d\n", (int)direct_status);
    if (direct_status == 0)
        DETAIL("seconds_direct = %.4g\ndirect_torque_pN_nm = %.15g\nsolver_torque_difference = %.3e\n", eq[1].seconds, eq[1].torque,
               eq[0].torque - eq[1].torque);
    DETAIL("other_model_tip_z_nm = %.15g\n", xyz[3 * (info.nodes - 1) + 2]);

    /* rodkit writes the path as CSV (turns, extension, torque, tension,
     * twist, writhe, branch, residual at full precision). */
    if (csv_path && (st = rodkit_supercoil_write_csv(run, csv_path)) < 0) return fail(st, "rodkit_supercoil_write_csv");

    /* Shapes: the buckling point's neighbour on the straight branch and
     * every 10th buckled point (and the last). */
    int64_t shapes[4096], ns = 0;
    shapes[ns++] = info.straight_points - 1;
    for (int64_t i = info.straight_points; i < count && ns < 4095; i += 10) shapes[ns++] = i;
    if (shapes[ns - 1] != count - 1) shapes[ns++] = count - 1;
    /* rodkit writes them (legacy VTK polydata, cell data turns, extension,
     * torque, writhe). */
    if (vtk_path && (st = rodkit_supercoil_write_vtk(run, shapes, ns, vtk_path)) < 0)
        return fail(st, "rodkit_supercoil_write_vtk");

    printf("DNA supercoiling (model full_rod, zero temperature): %lld bp at %.3g pN in %.3g M salt (%s charges), twisted from the straight rod\n",
           (long long)spec.base_pairs, spec.tension, spec.salt, info.base_pair_charges ? "base-pair" : "continuum");
    printf("  the straight rod buckles at %.3f turns (torque %.2f pN nm); the path's last point (%s branch, %lld points):\n"
           "  %.3f turns, extension %.1f nm, torque %.2f pN nm, writhe %.3f\n",
           info.buckling_turns, info.buckling_torque, pts[count - 1].branch ? "buckled" : "straight", (long long)count,
           pts[count - 1].turns, pts[count - 1].extension, pts[count - 1].torque, pts[count - 1].writhe);
    /* The equilibrium curve's summary: every point's stability (its
     * unstable modes counted on its own factorisation), the coexistence
     * of straight rod and plectoneme where their energies cross, and the
     * plateau beyond it, each with its finding. */
    RodkitSupercoilCurveInfo ci;
    if ((st = rodkit_supercoil_curve_summary(run, &ci)) < 0) return fail(st, "rodkit_supercoil_curve_summary");
    const char *finding[] = {"?", "found", "unverified", "undetermined", "not reached"};
#define FINDING(f) ((f) >= 1 && (f) <= 4 ? finding[f] : finding[0])
    if (ci.coexistence_finding == RODKIT_SUMMARY_FINDING_FOUND)
        printf("  coexistence (found): %.3f turns, torque %.2f pN nm straight / %.2f plectoneme, extension jump %.1f nm\n",
               ci.coexistence_turns, ci.coexistence_torque_straight, ci.coexistence_torque_plectoneme, ci.coexistence_extension_jump);
    else
        printf("  coexistence: %s\n", FINDING(ci.coexistence_finding));
    if (ci.plateau_finding == RODKIT_SUMMARY_FINDING_FOUND || ci.plateau_finding == RODKIT_SUMMARY_FINDING_UNVERIFIED)
        printf("  plateau (%s): torque %.2f pN nm (%.2f-%.2f), slope %.1f nm/turn over %.3f-%.3f turns\n", FINDING(ci.plateau_finding),
               ci.plateau_torque, ci.plateau_torque_min, ci.plateau_torque_max, ci.slope, ci.plateau_turns_from, ci.plateau_turns_to);
    else
        printf("  plateau: %s\n", FINDING(ci.plateau_finding));
    DETAIL("coexistence_finding = %d\nplateau_finding = %d\n", (int)ci.coexistence_finding, (int)ci.plateau_finding);
    if (ci.coexistence_finding == RODKIT_SUMMARY_FINDING_FOUND)
        DETAIL("coexistence_turns = %.15g\nextension_jump_nm = %.15g\n", ci.coexistence_turns, ci.coexistence_extension_jump);
    if (ci.plateau_finding == RODKIT_SUMMARY_FINDING_FOUND)
        DETAIL("plateau_torque_pN_nm = %.15g\nslope_nm_per_turn = %.15g\n", ci.plateau_torque, ci.slope);
    if (csv_path) printf("  path (CSV): %s\n", csv_path);
    if (vtk_path) printf("  %lld shapes (VTK, for ParaView): %s\n", (long long)ns, vtk_path);

    free(pts);
    free(xyz);
    rodkit_supercoil_free(run);
    return 0;
}

/*
 * The DNA force x salt map (issue 18, deliverable 5; issue 37): supercoiling
 * curves for every force and salt, each summarised, from one of two models
 * (--model; summary.csv's `model` column and the table's last column name
 * the model behind each row):
 *
 *   thermal (the default): the thermal two-phase model at kT (--kT, 4.11
 *     pN nm = 25 C; --kT 0 is its zero-temperature limit, model
 *     zero_temperature_two_phase) through rodkit_tweezers_*: an extended
 *     worm-like chain, plectonemes and their end loops, averaged over the
 *     number and length of the plectonemes (physics.md 3.7; Rust
 *     rodkit::tweezers). A curve of --points turns evenly from 0 to
 *     --turns (or --turns auto: 0 to twice the buckling turns), milliseconds
 *     a curve; summarised by rodkit_tweezers_summary.
 *   full-rod: the reference at zero temperature - the DNA scene as a
 *     charged Kirchhoff rod (Debye-Hueckel screening, Manning charge nu =
 *     1/l_B, a = 1 nm, A = 50 nm, P = 95 nm), continued in the end rotation
 *     from the straight rod through buckling to the plectoneme (minutes a
 *     curve), summarised by rodkit_supercoil_curve_summary with a finding
 *     per quantity (found, unverified, undetermined, not reached): a
 *     quantity the curve does not determine is reported as such, never as
 *     a number.
 *
 * summary.csv, column by column (an empty cell: nothing of that meaning):
 *   force_pN, salt_M, base_pairs, model, kT_pN_nm (0 for the full rod),
 *   status, points, last_turns, seconds: both models.
 *   hard_core_switched: full rod only (empty for the two-phase models).
 *   instability_{finding,turns,torque_pN_nm}: the straight rod's own
 *     instability (the mechanical buckling point, a limit of the straight
 *     branch): full rod only; the two-phase models have no such point (the
 *     finding is `not_in_model`, the cells empty).
 *   coexistence_{finding,turns}: where the buckled state takes over in
 *     equilibrium. Full rod: the equal-energy point of the straight and
 *     the buckled branch. Two-phase: the buckling turns, where the buckled
 *     population P(m >= 1) reaches 1/2 (at kT 0: where the lowest state
 *     changes - the same definition as the full rod's).
 *   coexistence_torque_straight_pN_nm: the unbuckled state's torque there
 *     (both; the two-phase summary's buckling_torque, the peak before the
 *     plectoneme forms).
 *   coexistence_torque_plectoneme_pN_nm: the buckled state's torque there:
 *     full rod only (the two-phase summary does not give it: empty).
 *   coexistence_extension_jump_nm: unbuckled minus buckled extension there
 *     (both).
 *   plateau_{finding,torque,torque_min,torque_max}, slope_nm_per_turn,
 *   plateau_turns_{from,to}: the torque and dz/dn on the plectonemic range
 *     (both: full rod from coexistence to the run's end; two-phase where
 *     the buckled population is >= 0.99 and the extension >= 0.3 z(0)).
 *   superhelix_{finding,radius_nm}: the plectoneme's superhelix radius
 *     (full rod: measured on a shape; two-phase: at the plateau torque).
 *   superhelix_turns: the turns of the full rod's measured shape (empty
 *     for the two-phase models).
 *   end_loop, out_of_range_points: two-phase only: the end-loop source
 *     (elastic, builtin_table, value) and the curve's points outside the
 *     model's range (in_range 0; not plotted, skipped by the summary).
 * The printed table has the same meaning per column ("not_in_model" under
 * buckling, "-" under tq_p for the two-phase rows).
 *
 * The curve, CSV and plot code is shared with the MPI map (mpi_dna_map.c,
 * full rod only) in dna_map_common.c.
 *
 * Writes into ONE folder (created if missing):
 *   curve_F<force>_S<salt>.csv  per curve. Full rod: turns, extension,
 *                               torque, tension, twist, writhe, energy G,
 *                               branch, stability, negative modes
 *                               (rodkit_supercoil_curve_points). Two-phase:
 *                               the thermal averages of RodkitTweezersPoint
 *                               (extension, torque, twist, writhe,
 *                               plectoneme length and number, buckled
 *                               population, the two levels, superhelix,
 *                               in_range)
 *   summary.csv                 one row per curve (above)
 *   extension_vs_turns.svg,
 *   torque_vs_turns.svg         the families (colour: salt, dash: force;
 *                               full rod: o coexistence, x instability;
 *                               two-phase: o buckling)
 *   plateau_torque_vs_force.svg with --data (two-phase only): the plateau
 *                               torque vs force, one line per salt, with
 *                               the data as points with error bars; the
 *                               table "model vs data" is printed
 *
 * Usage: c_dna_map [options] [output folder (default rodkit-out/dna_map)]
 *   --model M         thermal (default) or full-rod
 *   --forces a,b,..   pN      (default 0.5,1,2)
 *   --salts a,b,..    mol/L   (default 0.01,0.05,0.1,0.2)
 *   --bp N            base pairs (default 1000)
 *   --turns T         full rod: the buckled branch stops past T turns;
 *                     thermal: the curve's last turns; `auto` (thermal
 *                     only): twice each curve's buckling turns (default 12)
 *   --kT E            thermal: kT in pN nm (default 4.11; 0: the
 *                     zero-temperature two-phase model). Refused with
 *                     --model full-rod (the rod is at zero temperature)
 *   --points P        thermal: points per curve (default 200)
 *   --data FILE       thermal: plateau torque vs force against FILE
 *                     (tests/data/tweezers/buckling_torque.csv)
 *   --elements N      full rod only. Default 0: the library's automatic
 *                     mesh, 2 nm elements of Gauss(2) (170 per kbp; at 1
 *                     pN, 0.1 M the torque and extension of the plectoneme
 *                     within ~3e-4 of a converged curve; 0 -> 12 turns at 1
 *                     kbp in 489 s). 100 per kbp (3.4 nm) is 3-5x faster
 *                     and a survey at best: ~3e-3 off at 0.1 M, and at 0.2
 *                     M its path folds at every element the end loop
 *                     crosses (65 folds, stuck at 3 turns after 3000 steps;
 *                     benches/README.md, 2026-11-26)
 *   --steps N         full rod only: continuation steps per branch
 *                     (default 1000)
 *   --values          also print the counts as "name = value" lines
 * Full rod: the plateau torque and slope are measured on the plectonemic
 * leg from coexistence to the run's end: past the turns where the
 * plectoneme has taken most of the rod (1 kbp, 1 pN, 0.1 M: ~9 turns) the
 * torque rises and the extension flattens, which the leg's torque range
 * (min, max in summary.csv) shows; --turns ends the curves earlier.
 */
#define _XOPEN_SOURCE 700
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dna_map_common.h"
#include "rodkit.h"

/* Progress: a line every 100 points (a 1 kbp curve takes minutes). */
static int32_t progress(const RodkitBranchProgress *p, void *user_data) {
    (void)user_data;
    if (p->points % 100 == 0) {
        printf("#   %lld points: %s branch, %.3f turns, %.2f nm, %.3f pN nm\n", (long long)p->points,
               p->branch ? "buckled" : "straight", p->turns, p->extension, p->torque);
        fflush(stdout);
    }
    return 0;
}

int main(int argc, char **argv) {
    double forces[DM_MAX_VALUES] = {0.5, 1.0, 2.0}, salts[DM_MAX_VALUES] = {0.01, 0.05, 0.1, 0.2};
    int nf = 3, ns = 4;
    long long bp = 1000, elements = 0, steps = 1000, points = 200;
    double turns = 12.0, kT = 4.11;
    int thermal = 1, rod_only = 0, thermal_only = 0, auto_turns = 0;
    const char *dir = "rodkit-out/dna_map", *data = NULL, *rod_option = NULL, *thermal_option = NULL;
    int values = 0; /* --values: also the counts as "name = value" lines (the tests read them) */
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--values")) {
            values = 1;
            continue;
        }
        int takes = a[0] == '-' && a[1] == '-';
        if (takes && !v) { fprintf(stderr, "%s needs a value\n", a); return 2; }
        if (!strcmp(a, "--model")) {
            if (!strcmp(v, "thermal")) thermal = 1;
            else if (!strcmp(v, "full-rod")) thermal = 0;
            else { fprintf(stderr, "--model: thermal or full-rod (got %s)\n", v); return 2; }
        } else if (!strcmp(a, "--forces")) nf = dm_parse_list(v, forces);
        else if (!strcmp(a, "--salts")) ns = dm_parse_list(v, salts);
        else if (!strcmp(a, "--bp")) bp = atoll(v);
        else if (!strcmp(a, "--turns")) {
            if (!strcmp(v, "auto")) auto_turns = 1, thermal_only = 1, thermal_option = a;
            else auto_turns = 0, turns = atof(v);
        } else if (!strcmp(a, "--kT")) kT = atof(v), thermal_only = 1, thermal_option = a;
        else if (!strcmp(a, "--points")) points = atoll(v), thermal_only = 1, thermal_option = a;
        else if (!strcmp(a, "--data")) data = v, thermal_only = 1, thermal_option = a;
        else if (!strcmp(a, "--elements")) elements = atoll(v), rod_only = 1, rod_option = a;
        else if (!strcmp(a, "--steps")) steps = atoll(v), rod_only = 1, rod_option = a;
        else if (takes) { fprintf(stderr, "unknown option %s (see the comment at the top of dna_map.c)\n", a); return 2; }
        else { dir = a; continue; }
        ++i;
        if (nf <= 0 || ns <= 0) { fprintf(stderr, "bad list after %s\n", a); return 2; }
    }
    if (thermal && rod_only) {
        fprintf(stderr, "%s applies to --model full-rod only (the thermal model, the default, has no mesh or continuation)\n", rod_option);
        return 2;
    }
    if (!thermal && thermal_only) {
        fprintf(stderr, "%s applies to --model thermal only (the full rod is at zero temperature, continued to --turns)\n",
                thermal_option);
        return 2;
    }
    if (elements < 0) { fprintf(stderr, "--elements must be >= 0 (0: the automatic mesh)\n"); return 2; }
    if (thermal && (!(kT >= 0.0) || points < 2 || (!auto_turns && !(turns > 0.0)))) {
        fprintf(stderr, "--kT must be >= 0, --points >= 2 and --turns > 0 (or auto)\n");
        return 2;
    }
    if (dm_make_dirs(dir) != 0) { perror(dir); return 1; }
    int n = nf * ns;
    DnaCurve *cs = calloc((size_t)n, sizeof *cs);
    if (!cs) return 1;
    if (thermal) {
        char range[64];
        if (auto_turns) snprintf(range, sizeof range, "to twice the buckling turns");
        else snprintf(range, sizeof range, "to %g turns", turns);
        printf("# DNA force x salt map, %s model (kT %g pN nm): %lld bp (%.4g nm), %d forces x %d salts, %lld points %s\n",
               kT > 0.0 ? "thermal two-phase" : "zero-temperature two-phase", kT, bp, 0.34 * (double)bp, nf, ns, points, range);
    } else if (elements == 0)
        printf("# DNA force x salt map, full rod (zero temperature): %lld bp (%.4g nm), %d forces x %d salts, to %g turns, the "
               "automatic mesh (2 nm elements of Gauss(2)), up to %lld steps a branch\n", bp, 0.34 * (double)bp, nf, ns, turns, steps);
    else
        printf("# DNA force x salt map, full rod (zero temperature): %lld bp (%.4g nm), %d forces x %d salts, to %g turns, %lld "
               "elements of Gauss(2) (%.2f nm), up to %lld steps a branch\n", bp, 0.34 * (double)bp, nf, ns, turns, elements,
               0.34 * (double)bp / (double)elements, steps);
    double t0 = dm_now();
    for (int i = 0; i < nf; ++i)
        for (int j = 0; j < ns; ++j) {
            DnaCurve *c = &cs[i * ns + j];
            c->force = forces[i];
            c->salt = salts[j];
            c->bp = bp;
            c->model = RODKIT_SUPERCOIL_MODEL_FULL_ROD;
            if (thermal) {
                c->kT = kT;
                dm_run_two_phase_curve(c, auto_turns ? 0.0 : turns, points);
            } else {
                RodkitDnaSupercoilSpec spec;
                if (rodkit_dna_supercoil_spec_default(&spec) < 0) return 1;
                spec.base_pairs = bp;
                spec.tension = c->force;
                spec.salt = c->salt;
                spec.max_turns = turns;
                spec.elements = elements;
                spec.max_steps = steps;
                dm_run_curve(&spec, c, progress, NULL);
                printf("# curve %d/%d: %g pN, %g M: %lld points to %.3f turns in %.1f s (energies and summary %.1f s; status %s)\n",
                       i * ns + j + 1, n, c->force, c->salt, (long long)c->points, c->points ? c->pts[c->points - 1].turns : 0.0,
                       c->seconds, c->curve_seconds, rodkit_status_string(c->status));
                fflush(stdout);
            }
            char path[4200];
            snprintf(path, sizeof path, "%s/curve_F%g_S%g.csv", dir, c->force, c->salt);
            if (c->status >= 0 && dm_write_curve_csv(path, c) != 0) return 1;
        }
    double seconds = dm_now() - t0;
    dm_print_table(cs, n);
    if (thermal)
        printf("# two-phase rows: buckling at P(buckled) = 1/2 under 'coexistence' (tq_s its unbuckled torque); no straight-rod\n"
               "# instability (not_in_model) and no plectoneme torque there ('-'); s = seconds; %d curves in %.2f s\n", n, seconds);
    else
        printf("# findings: a number only where the curve determines it; '?' = unverified (measured on the computed branch, its\n"
               "# stability undecided); not_reached / undetermined = no number (summary.csv leaves those cells empty)\n");
    char path[4200];
    snprintf(path, sizeof path, "%s/summary.csv", dir);
    if (dm_write_summary_csv(path, cs, n, 1) != 0) return 1;
    snprintf(path, sizeof path, "%s/extension_vs_turns.svg", dir);
    if (dm_write_svg(path, 0, cs, n, forces, nf, salts, ns) != 0) return 1;
    snprintf(path, sizeof path, "%s/torque_vs_turns.svg", dir);
    if (dm_write_svg(path, 1, cs, n, forces, nf, salts, ns) != 0) return 1;
    if (data) {
        snprintf(path, sizeof path, "%s/plateau_torque_vs_force.svg", dir);
        if (dm_plateau_vs_data(path, data, cs, n) != 0) return 1;
    }
    int failed = 0;
    for (int k = 0; k < n; ++k) failed += cs[k].status < 0;
    if (values) printf("curves = %d\nfailed_curves = %d\nseconds_total = %.1f\n", n, failed, dm_now() - t0);
    char *abs = realpath(dir, NULL);
    const char *where = abs ? abs : dir;
    printf("# files in %s/: summary.csv, curve_F<force>_S<salt>.csv (%d), extension_vs_turns.svg, torque_vs_turns.svg%s\n",
           where, n - failed, data ? ", plateau_torque_vs_force.svg" : "");
    free(abs);
    for (int k = 0; k < n; ++k) dm_curve_free(&cs[k]);
    free(cs);
    return failed ? 1 : 0;
}

/*
 * The DNA force x salt map (issue 18, deliverable 5): supercoiling curves
 * of the DNA scene (a charged Kirchhoff rod, Debye-Hueckel screening,
 * Manning charge nu = 1/l_B, a = 1 nm, A = 50 nm, P = 95 nm) for every
 * force and salt, each continued in the end rotation from the straight rod
 * through buckling to the plectoneme, and summarised by
 * rodkit_supercoil_curve_summary: instability (buckling) turns and torque,
 * coexistence turns and torques with the extension jump, plateau torque,
 * slope dz/dn and superhelix radius - each with its finding (found,
 * unverified, undetermined, not reached): a quantity the curve does not
 * determine is reported as such, never as a number.
 *
 * The curve, CSV and plot code is shared with the MPI map (mpi_dna_map.c)
 * in dna_map_common.c.
 *
 * Writes into ONE folder (created if missing):
 *   curve_F<force>_S<salt>.csv  per curve: turns, extension, torque, tension,
 *                               twist, writhe, energy G, branch, stability,
 *                               negative modes (rodkit_supercoil_curve_points)
 *   summary.csv                 one row per curve, the summary with findings
 *                               (empty cells where nothing was determined)
 *   extension_vs_turns.svg,
 *   torque_vs_turns.svg         the families (colour: salt, dash: force;
 *                               o coexistence, x instability)
 *
 * Usage: c_dna_map [options] [output folder (default rodkit-out/dna_map)]
 *   --forces a,b,..   pN      (default 0.5,1,2)
 *   --salts a,b,..    mol/L   (default 0.01,0.05,0.1,0.2)
 *   --bp N            base pairs (default 1000)
 *   --turns T         the buckled branch stops past T turns (default 12)
 *   --elements N      default 0: the library's automatic mesh, 2 nm elements
 *                     of Gauss(2) (170 per kbp; at 1 pN, 0.1 M the torque and
 *                     extension of the plectoneme within ~3e-4 of a converged
 *                     curve; 0 -> 12 turns at 1 kbp in 489 s). 100 per kbp
 *                     (3.4 nm) is 3-5x faster and a survey at best: ~3e-3 off
 *                     at 0.1 M, and at 0.2 M its path folds at every element
 *                     the end loop crosses (65 folds, stuck at 3 turns after
 *                     3000 steps; benches/README.md, 2026-11-26)
 *   --steps N         continuation steps per branch (default 1000)
 *   --values          also print the counts as "name = value" lines
 * The plateau torque and slope are measured on the plectonemic leg from
 * coexistence to the run's end: past the turns where the plectoneme has
 * taken most of the rod (1 kbp, 1 pN, 0.1 M: ~9 turns) the torque rises
 * and the extension flattens, which the leg's torque range (min, max in
 * summary.csv) shows; --turns ends the curves earlier.
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
    long long bp = 1000, elements = 0, steps = 1000;
    double turns = 12.0;
    const char *dir = "rodkit-out/dna_map";
    int values = 0; /* --values: also the counts as "name = value" lines (the tests read them) */
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--values")) {
            values = 1;
            continue;
        }
        int takes = a[0] == '-' && a[1] == '-';
        if (takes && !v) { fprintf(stderr, "%s needs a value\n", a); return 2; }
        if (!strcmp(a, "--forces")) nf = dm_parse_list(v, forces);
        else if (!strcmp(a, "--salts")) ns = dm_parse_list(v, salts);
        else if (!strcmp(a, "--bp")) bp = atoll(v);
        else if (!strcmp(a, "--turns")) turns = atof(v);
        else if (!strcmp(a, "--elements")) elements = atoll(v);
        else if (!strcmp(a, "--steps")) steps = atoll(v);
        else if (takes) { fprintf(stderr, "unknown option %s (see the comment at the top of dna_map.c)\n", a); return 2; }
        else { dir = a; continue; }
        ++i;
        if (nf <= 0 || ns <= 0) { fprintf(stderr, "bad list after %s\n", a); return 2; }
    }
    if (elements < 0) { fprintf(stderr, "--elements must be >= 0 (0: the automatic mesh)\n"); return 2; }
    if (dm_make_dirs(dir) != 0) { perror(dir); return 1; }
    int n = nf * ns;
    DnaCurve *cs = calloc((size_t)n, sizeof *cs);
    if (!cs) return 1;
    if (elements == 0)
        printf("# DNA force x salt map: %lld bp (%.4g nm), %d forces x %d salts, to %g turns, the automatic mesh "
               "(2 nm elements of Gauss(2)), up to %lld steps a branch\n", bp, 0.34 * (double)bp, nf, ns, turns, steps);
    else
        printf("# DNA force x salt map: %lld bp (%.4g nm), %d forces x %d salts, to %g turns, %lld elements of Gauss(2) "
               "(%.2f nm), up to %lld steps a branch\n", bp, 0.34 * (double)bp, nf, ns, turns, elements,
               0.34 * (double)bp / (double)elements, steps);
    double t0 = dm_now();
    for (int i = 0; i < nf; ++i)
        for (int j = 0; j < ns; ++j) {
            DnaCurve *c = &cs[i * ns + j];
            c->force = forces[i];
            c->salt = salts[j];
            c->bp = bp;
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
            char path[4200];
            snprintf(path, sizeof path, "%s/curve_F%g_S%g.csv", dir, c->force, c->salt);
            if (c->status >= 0 && dm_write_curve_csv(path, c) != 0) return 1;
        }
    dm_print_table(cs, n);
    printf("# findings: a number only where the curve determines it; '?' = unverified (measured on the computed branch, its\n"
           "# stability undecided); not_reached / undetermined = no number (summary.csv leaves those cells empty)\n");
    char path[4200];
    snprintf(path, sizeof path, "%s/summary.csv", dir);
    if (dm_write_summary_csv(path, cs, n, 1) != 0) return 1;
    snprintf(path, sizeof path, "%s/extension_vs_turns.svg", dir);
    if (dm_write_svg(path, 0, cs, n, forces, nf, salts, ns) != 0) return 1;
    snprintf(path, sizeof path, "%s/torque_vs_turns.svg", dir);
    if (dm_write_svg(path, 1, cs, n, forces, nf, salts, ns) != 0) return 1;
    int failed = 0;
    for (int k = 0; k < n; ++k) failed += cs[k].status < 0;
    if (values) printf("curves = %d\nfailed_curves = %d\nseconds_total = %.1f\n", n, failed, dm_now() - t0);
    char *abs = realpath(dir, NULL);
    const char *where = abs ? abs : dir;
    printf("# files in %s/: summary.csv, curve_F<force>_S<salt>.csv (%d), extension_vs_turns.svg, torque_vs_turns.svg\n",
           where, n - failed);
    free(abs);
    for (int k = 0; k < n; ++k) dm_curve_free(&cs[k]);
    free(cs);
    return failed ? 1 : 0;
}

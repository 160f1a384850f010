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
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "rodkit.h"

#define MAX_VALUES 16

typedef struct {
    double force, salt;
    int32_t status;
    int64_t points;
    double seconds, curve_seconds; /* the whole curve, and of it the energies and summary */
    RodkitSupercoilInfo info;
    RodkitSupercoilCurveInfo sum;
    RodkitSupercoilPoint *pts;
    RodkitSupercoilCurvePoint *cpts; /* NULL when the curve failed */
} Curve;

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int parse_list(const char *s, double *out) {
    int n = 0;
    char *end;
    while (*s && n < MAX_VALUES) {
        out[n++] = strtod(s, &end);
        if (end == s) return -1;
        s = *end == ',' ? end + 1 : end;
    }
    return n;
}

static int make_dirs(const char *path) {
    char buf[4096];
    size_t n = strlen(path);
    if (n == 0 || n >= sizeof buf) return -1;
    memcpy(buf, path, n + 1);
    for (size_t i = 1; i <= n; ++i) {
        if (buf[i] == '/' || buf[i] == '\0') {
            char c = buf[i];
            buf[i] = '\0';
            if (mkdir(buf, 0777) != 0 && errno != EEXIST) return -1;
            buf[i] = c;
        }
    }
    return 0;
}

static const char *finding(int32_t f) {
    switch (f) {
    case RODKIT_SUMMARY_FINDING_FOUND: return "found";
    case RODKIT_SUMMARY_FINDING_UNVERIFIED: return "unverified";
    case RODKIT_SUMMARY_FINDING_UNDETERMINED: return "undetermined";
    case RODKIT_SUMMARY_FINDING_NOT_REACHED: return "not_reached";
    default: return "failed";
    }
}

static const char *stability(int32_t k) {
    switch (k) {
    case RODKIT_STABILITY_KIND_LOWEST: return "lowest";
    case RODKIT_STABILITY_KIND_METASTABLE: return "metastable";
    case RODKIT_STABILITY_KIND_UNSTABLE: return "unstable";
    default: return "undetermined";
    }
}

static int has_value(int32_t f) { return f == RODKIT_SUMMARY_FINDING_FOUND || f == RODKIT_SUMMARY_FINDING_UNVERIFIED; }

/* One CSV cell: the value when its finding has one, else empty. */
static void cell(FILE *f, int32_t fnd, double v) {
    if (has_value(fnd)) fprintf(f, ",%.10g", v);
    else fprintf(f, ",");
}

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

/* Run one curve; its failure is recorded, not fatal. */
static void run_curve(const RodkitDnaSupercoilSpec *spec, Curve *c) {
    RodkitSupercoil *run = NULL;
    double t0 = now();
    c->status = rodkit_dna_supercoil_run_with(spec, progress, NULL, &run);
    if (c->status < 0) {
        fprintf(stderr, "  F = %g pN, c = %g M: %s: %s\n", c->force, c->salt, rodkit_status_string(c->status),
                rodkit_last_error_message());
        return;
    }
    if (c->status == RODKIT_STATUS_INFO_FAILED_PARTWAY) {
        /* The branch failed partway (e.g. it kept sliding onto the spurious
         * straight family): the curve up to its last good point is kept and
         * summarised, its status (7) says it is partial. */
        char why[512];
        int32_t error = 0;
        rodkit_supercoil_failure(run, &error, why, sizeof why, NULL);
        fprintf(stderr, "  F = %g pN, c = %g M: failed partway (%s), the curve so far is kept: %s\n", c->force,
                c->salt, rodkit_status_string(error), why);
    }
    int32_t st = rodkit_supercoil_summary(run, &c->info);
    if (st >= 0) {
        c->points = c->info.points;
        c->pts = malloc(sizeof *c->pts * (size_t)c->points);
        c->cpts = malloc(sizeof *c->cpts * (size_t)c->points);
        int64_t n = 0;
        if (!c->pts || !c->cpts || rodkit_supercoil_points(run, c->pts, c->points, &n) < 0) st = -1;
    }
    double t1 = now();
    if (st >= 0 && rodkit_supercoil_curve_points(run, c->cpts, c->points, &(int64_t){0}) < 0) {
        fprintf(stderr, "  curve points: %s\n", rodkit_last_error_message());
        free(c->cpts);
        c->cpts = NULL;
    }
    if (st >= 0 && (st = rodkit_supercoil_curve_summary(run, &c->sum)) < 0)
        fprintf(stderr, "  summary: %s\n", rodkit_last_error_message());
    if (st < 0) c->status = st;
    c->seconds = now() - t0;
    c->curve_seconds = now() - t1;
    rodkit_supercoil_free(run);
}

static int write_curve_csv(const char *dir, const Curve *c) {
    char path[4200];
    snprintf(path, sizeof path, "%s/curve_F%g_S%g.csv", dir, c->force, c->salt);
    FILE *f = fopen(path, "w");
    if (!f) { perror(path); return -1; }
    fprintf(f, "turns,extension_nm,torque_pN_nm,tension_pN,twist,writhe,energy_pN_nm,branch,stability,negative_modes\n");
    for (int64_t i = 0; i < c->points; ++i) {
        const RodkitSupercoilPoint *p = &c->pts[i];
        fprintf(f, "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,", p->turns, p->extension, p->torque, p->tension, p->twist, p->writhe);
        if (c->cpts)
            fprintf(f, "%.12g,%d,%s,%lld\n", c->cpts[i].energy, (int)p->branch, stability(c->cpts[i].kind),
                    (long long)c->cpts[i].negative_modes);
        else
            fprintf(f, ",%d,,\n", (int)p->branch);
    }
    return fclose(f);
}

static int write_summary_csv(const char *dir, const Curve *cs, int n, int64_t bp) {
    char path[4200];
    snprintf(path, sizeof path, "%s/summary.csv", dir);
    FILE *f = fopen(path, "w");
    if (!f) { perror(path); return -1; }
    fprintf(f, "force_pN,salt_M,base_pairs,status,points,last_turns,seconds,hard_core_switched,"
               "instability_finding,instability_turns,instability_torque_pN_nm,"
               "coexistence_finding,coexistence_turns,coexistence_torque_straight_pN_nm,"
               "coexistence_torque_plectoneme_pN_nm,coexistence_extension_jump_nm,"
               "plateau_finding,plateau_torque_pN_nm,plateau_torque_min_pN_nm,plateau_torque_max_pN_nm,"
               "slope_nm_per_turn,plateau_turns_from,plateau_turns_to,"
               "superhelix_finding,superhelix_radius_nm,superhelix_turns\n");
    for (int k = 0; k < n; ++k) {
        const Curve *c = &cs[k];
        const RodkitSupercoilCurveInfo *s = &c->sum;
        int ok = c->status >= 0;
        fprintf(f, "%g,%g,%lld,%d,%lld,", c->force, c->salt, (long long)bp, (int)c->status, (long long)c->points);
        if (ok && c->points > 0) fprintf(f, "%.10g,", c->pts[c->points - 1].turns);
        else fprintf(f, ",");
        fprintf(f, "%.4g,%d", c->seconds, ok ? (int)c->info.hard_core_switched : 0);
        fprintf(f, ",%s", ok ? finding(s->instability_finding) : "failed");
        cell(f, s->instability_finding, s->instability_turns);
        cell(f, s->instability_finding, s->instability_torque);
        fprintf(f, ",%s", ok ? finding(s->coexistence_finding) : "failed");
        cell(f, s->coexistence_finding, s->coexistence_turns);
        cell(f, s->coexistence_finding, s->coexistence_torque_straight);
        cell(f, s->coexistence_finding, s->coexistence_torque_plectoneme);
        cell(f, s->coexistence_finding, s->coexistence_extension_jump);
        fprintf(f, ",%s", ok ? finding(s->plateau_finding) : "failed");
        cell(f, s->plateau_finding, s->plateau_torque);
        cell(f, s->plateau_finding, s->plateau_torque_min);
        cell(f, s->plateau_finding, s->plateau_torque_max);
        cell(f, s->plateau_finding, s->slope);
        cell(f, s->plateau_finding, s->plateau_turns_from);
        cell(f, s->plateau_finding, s->plateau_turns_to);
        fprintf(f, ",%s", ok ? finding(s->superhelix_finding) : "failed");
        cell(f, s->superhelix_finding, s->superhelix_radius);
        cell(f, s->superhelix_finding, s->superhelix_turns);
        fprintf(f, "\n");
    }
    return fclose(f);
}

/* A "nice" tick step for a range (1, 2 or 5 times a power of ten). */
static double tick_step(double span) {
    double raw = span / 6.0, p = 1.0;
    while (p * 10.0 <= raw) p *= 10.0;
    while (p > raw) p /= 10.0;
    return raw >= 5.0 * p ? 5.0 * p : raw >= 2.0 * p ? 2.0 * p : p;
}

static const char *COLOURS[] = {"#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d", "#666666"};
static const char *DASHES[] = {"", "6,3", "2,2", "8,3,2,3", "1,3"};

/* A family plot of y (0: extension, 1: torque) vs turns. */
static int write_svg(const char *dir, const char *name, int which, const Curve *cs, int n, const double *forces, int nf,
                     const double *salts, int ns) {
    double x0 = 0.0, x1 = 1e-9, y0 = 1e300, y1 = -1e300;
    for (int k = 0; k < n; ++k)
        for (int64_t i = 0; i < cs[k].points; ++i) {
            double x = cs[k].pts[i].turns, y = which ? cs[k].pts[i].torque : cs[k].pts[i].extension;
            if (x > x1) x1 = x;
            if (x < x0) x0 = x;
            if (y < y0) y0 = y;
            if (y > y1) y1 = y;
        }
    if (y0 > y1) { y0 = 0.0; y1 = 1.0; }
    if (!which || y0 > 0.0) y0 = y0 < 0.0 ? y0 : 0.0;
    double pad = 0.05 * (y1 - y0 + 1e-12);
    y1 += pad;
    char path[4200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f) { perror(path); return -1; }
    const double W = 760, H = 480, L = 70, R = 190, T = 30, B = 50;
    double pw = W - L - R, ph = H - T - B;
#define SX(x) (L + ((x) - x0) / (x1 - x0) * pw)
#define SY(y) (T + ph - ((y) - y0) / (y1 - y0) * ph)
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" font-family=\"sans-serif\" font-size=\"12\">\n", W, H);
    fprintf(f, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
    fprintf(f, "<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"none\" stroke=\"black\"/>\n", L, T, pw, ph);
    double dx = tick_step(x1 - x0), dy = tick_step(y1 - y0);
    for (double t = dx * (double)(long)(x0 / dx); t <= x1 + 1e-9; t += dx) {
        if (t < x0 - 1e-9) continue;
        fprintf(f, "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/>", SX(t), T, SX(t), T + ph);
        fprintf(f, "<text x=\"%.1f\" y=\"%g\" text-anchor=\"middle\">%g</text>\n", SX(t), T + ph + 16, t);
    }
    for (double t = dy * (double)(long)(y0 / dy); t <= y1 + 1e-9; t += dy) {
        if (t < y0 - 1e-9) continue;
        fprintf(f, "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/>", L, SY(t), L + pw, SY(t));
        fprintf(f, "<text x=\"%g\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", L - 5, SY(t) + 4, t);
    }
    fprintf(f, "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">turns</text>\n", L + pw / 2, H - 12);
    fprintf(f, "<text transform=\"translate(16,%g) rotate(-90)\" text-anchor=\"middle\">%s</text>\n", T + ph / 2,
            which ? "torque (pN nm)" : "extension (nm)");
    for (int k = 0; k < n; ++k) {
        const Curve *c = &cs[k];
        if (c->points == 0) continue;
        int fi = 0, si = 0;
        for (int j = 0; j < nf; ++j) if (forces[j] == c->force) fi = j;
        for (int j = 0; j < ns; ++j) if (salts[j] == c->salt) si = j;
        const char *col = COLOURS[si % 8], *dash = DASHES[fi % 5];
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" stroke-dasharray=\"%s\" points=\"", col, dash);
        for (int64_t i = 0; i < c->points; ++i) {
            double y = which ? c->pts[i].torque : c->pts[i].extension;
            fprintf(f, "%.2f,%.2f ", SX(c->pts[i].turns), SY(y));
        }
        fprintf(f, "\"/>\n");
        const RodkitSupercoilCurveInfo *s = &c->sum;
        if (c->status >= 0 && s->coexistence_finding == RODKIT_SUMMARY_FINDING_FOUND) {
            double ys = which ? s->coexistence_torque_straight : s->coexistence_extension_straight;
            double yp = which ? s->coexistence_torque_plectoneme : s->coexistence_extension_plectoneme;
            fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"4\" fill=\"none\" stroke=\"%s\"/>", SX(s->coexistence_turns), SY(ys), col);
            fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"4\" fill=\"%s\"/>\n", SX(s->coexistence_turns), SY(yp), col);
        }
        if (c->status >= 0 && s->instability_finding == RODKIT_SUMMARY_FINDING_FOUND) {
            double y = which ? s->instability_torque : c->pts[0].extension;
            fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" fill=\"%s\" text-anchor=\"middle\">x</text>\n", SX(s->instability_turns),
                    SY(y) + 4, col);
        }
        double ly = T + 14 + 16 * k;
        fprintf(f, "<line x1=\"%g\" y1=\"%g\" x2=\"%g\" y2=\"%g\" stroke=\"%s\" stroke-width=\"1.5\" stroke-dasharray=\"%s\"/>", W - R + 12,
                ly, W - R + 42, ly, col, dash);
        fprintf(f, "<text x=\"%g\" y=\"%g\">%g pN, %g M</text>\n", W - R + 48, ly + 4, c->force, c->salt);
    }
    fprintf(f, "<text x=\"%g\" y=\"%g\">o coexistence, x instability</text>\n", W - R + 12, T + 30 + 16 * n);
    fprintf(f, "</svg>\n");
#undef SX
#undef SY
    return fclose(f);
}

static void print_table(const Curve *cs, int n) {
    printf("#  F/pN  salt/M  pts  last_turns   s  | buckling turns torque | coexistence turns  tq_s   tq_p  jump/nm | plateau tq  "
           "dz/dn nm/turn | radius/nm\n");
    for (int k = 0; k < n; ++k) {
        const Curve *c = &cs[k];
        const RodkitSupercoilCurveInfo *s = &c->sum;
        if (c->status < 0) {
            printf("  %5g %6g  failed (%s)\n", c->force, c->salt, rodkit_status_string(c->status));
            continue;
        }
        printf("  %5g %6g %5lld %8.3f %6.1f |", c->force, c->salt, (long long)c->points, c->pts[c->points - 1].turns, c->seconds);
        if (has_value(s->instability_finding)) printf(" %7.4f %7.3f      |", s->instability_turns, s->instability_torque);
        else printf(" %-21s|", finding(s->instability_finding));
        if (has_value(s->coexistence_finding))
            printf(" %7.4f %6.2f %6.2f %7.2f     |", s->coexistence_turns, s->coexistence_torque_straight,
                   s->coexistence_torque_plectoneme, s->coexistence_extension_jump);
        else printf(" %-33s|", finding(s->coexistence_finding));
        if (has_value(s->plateau_finding))
            printf(" %6.2f%s %8.2f      |", s->plateau_torque, s->plateau_finding == RODKIT_SUMMARY_FINDING_UNVERIFIED ? "?" : " ",
                   s->slope);
        else printf(" %-22s|", finding(s->plateau_finding));
        if (has_value(s->superhelix_finding)) printf(" %6.3f\n", s->superhelix_radius);
        else printf(" %s\n", finding(s->superhelix_finding));
    }
}

int main(int argc, char **argv) {
    double forces[MAX_VALUES] = {0.5, 1.0, 2.0}, salts[MAX_VALUES] = {0.01, 0.05, 0.1, 0.2};
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
        if (!strcmp(a, "--forces")) nf = parse_list(v, forces);
        else if (!strcmp(a, "--salts")) ns = parse_list(v, salts);
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
    if (make_dirs(dir) != 0) { perror(dir); return 1; }
    int n = nf * ns;
    Curve *cs = calloc((size_t)n, sizeof *cs);
    if (!cs) return 1;
    if (elements == 0)
        printf("# DNA force x salt map: %lld bp (%.4g nm), %d forces x %d salts, to %g turns, the automatic mesh "
               "(2 nm elements of Gauss(2)), up to %lld steps a branch\n", bp, 0.34 * (double)bp, nf, ns, turns, steps);
    else
        printf("# DNA force x salt map: %lld bp (%.4g nm), %d forces x %d salts, to %g turns, %lld elements of Gauss(2) "
               "(%.2f nm), up to %lld steps a branch\n", bp, 0.34 * (double)bp, nf, ns, turns, elements,
               0.34 * (double)bp / (double)elements, steps);
    double t0 = now();
    for (int i = 0; i < nf; ++i)
        for (int j = 0; j < ns; ++j) {
            Curve *c = &cs[i * ns + j];
            c->force = forces[i];
            c->salt = salts[j];
            RodkitDnaSupercoilSpec spec;
            if (rodkit_dna_supercoil_spec_default(&spec) < 0) return 1;
            spec.base_pairs = bp;
            spec.tension = c->force;
            spec.salt = c->salt;
            spec.max_turns = turns;
            spec.elements = elements;
            spec.max_steps = steps;
            run_curve(&spec, c);
            printf("# curve %d/%d: %g pN, %g M: %lld points to %.3f turns in %.1f s (energies and summary %.1f s; status %s)\n",
                   i * ns + j + 1, n, c->force, c->salt, (long long)c->points, c->points ? c->pts[c->points - 1].turns : 0.0,
                   c->seconds, c->curve_seconds, rodkit_status_string(c->status));
            fflush(stdout);
            if (c->status >= 0 && write_curve_csv(dir, c) != 0) return 1;
        }
    print_table(cs, n);
    printf("# findings: a number only where the curve determines it; '?' = unverified (measured on the computed branch, its\n"
           "# stability undecided); not_reached / undetermined = no number (summary.csv leaves those cells empty)\n");
    if (write_summary_csv(dir, cs, n, bp) != 0) return 1;
    if (write_svg(dir, "extension_vs_turns.svg", 0, cs, n, forces, nf, salts, ns) != 0) return 1;
    if (write_svg(dir, "torque_vs_turns.svg", 1, cs, n, forces, nf, salts, ns) != 0) return 1;
    int failed = 0;
    for (int k = 0; k < n; ++k) failed += cs[k].status < 0;
    if (values) printf("curves = %d\nfailed_curves = %d\nseconds_total = %.1f\n", n, failed, now() - t0);
    char *abs = realpath(dir, NULL);
    const char *where = abs ? abs : dir;
    printf("# files in %s/: summary.csv, curve_F<force>_S<salt>.csv (%d), extension_vs_turns.svg, torque_vs_turns.svg\n",
           where, n - failed);
    free(abs);
    for (int k = 0; k < n; ++k) { free(cs[k].pts); free(cs[k].cpts); }
    free(cs);
    return failed ? 1 : 0;
}

/*
 * DNA in magnetic tweezers at finite temperature from C (physics.md 3.7):
 * the thermal two-phase model (an extended worm-like chain, plectonemes
 * with their end loops, averaged over the number and length of the
 * plectonemes) gives the extension and torque vs turns curves a tweezers
 * experiment measures, and the numbers it reports: the buckling turns and
 * torque, the extension jump at buckling, the plateau torque, the slope
 * dz/dn of the plectonemic range and the superhelix radius.
 *
 * Usage: c_dna_tweezers [--values] [--force pN] [--salt M] [--bp N] [--kT pN_nm]
 *                       [--points P] [--out DIR] [--family [--threads T]]
 * (defaults 1 pN, 0.1 M, 1000 bp, kT 4.11 pN nm (0: the zero-temperature
 * limit), 200 points from 0 to twice the buckling turns, no files).
 * --values (first argument) prints every result as a "name = value" line
 * (the channel rodkit's tests read); without it, a short report. --out
 * writes the curve as CSV (curve.csv) and an SVG of the extension and
 * torque vs turns (curve.svg) into DIR.
 *
 * --family: the curves of forces {0.5, 1, 2, 4} pN x salts {0.01, 0.1} M x
 * lengths {1, 10} kbp (kT and points from the options; 100 points by
 * default), a table of their summaries, and with --out one CSV per curve,
 * summary.csv and one SVG family per length. Its curves are shared among
 * --threads T threads of this program (default 2; rodkit itself starts
 * none: each thread has its own handles), with the same results for any T.
 */
#define _XOPEN_SOURCE 700 /* realpath */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dna_map_common.h"
#include "rodkit.h"

static int fail(int32_t st, const char *what) {
    fprintf(stderr, "%s failed: %s (%d): %s\n", what, rodkit_status_string(st), (int)st, rodkit_last_error_message());
    return 1;
}

static const char *model_name(int32_t m) {
    switch (m) {
    case RODKIT_SUPERCOIL_MODEL_THERMAL_TWO_PHASE: return "thermal_two_phase";
    case RODKIT_SUPERCOIL_MODEL_ZERO_TEMPERATURE_TWO_PHASE: return "zero_temperature_two_phase";
    case RODKIT_SUPERCOIL_MODEL_FULL_ROD: return "full_rod";
    default: return "unknown";
    }
}

static const char *end_loop_name(int32_t e) {
    switch (e) {
    case RODKIT_TWEEZERS_END_LOOP_BUILTIN_TABLE: return "builtin_table";
    case RODKIT_TWEEZERS_END_LOOP_ELASTIC: return "elastic";
    case RODKIT_TWEEZERS_END_LOOP_VALUE: return "value";
    case RODKIT_TWEEZERS_END_LOOP_COMPUTED: return "computed";
    default: return "unknown";
    }
}

/* One curve: its scene, points and summary (status < 0: it failed, msg says why). */
typedef struct {
    double force, salt, bp, kT;
    int64_t n;
    RodkitTweezersPoint *pts;
    RodkitTweezersInfo sum;
    int32_t status;
    char msg[512];
    double seconds;
} Curve;

static void run_curve(Curve *c, int64_t points) {
    double t0 = dm_now();
    RodkitTweezersSpec spec;
    RodkitTweezers *h = NULL;
    double *turns = NULL;
    const char *what = "rodkit_tweezers_spec_default";
    c->pts = NULL;
    c->n = 0;
    int32_t st = rodkit_tweezers_spec_default(&spec);
    if (st >= 0) {
        spec.force = c->force;
        spec.salt = c->salt;
        spec.base_pairs = c->bp;
        spec.kt = c->kT;
        what = "rodkit_tweezers_new";
        st = rodkit_tweezers_new(&spec, &h);
    }
    if (st >= 0) {
        turns = malloc(sizeof *turns * (size_t)points);
        c->pts = malloc(sizeof *c->pts * (size_t)points);
        if (!turns || !c->pts) {
            fprintf(stderr, "out of memory\n");
            exit(1);
        }
        what = "rodkit_tweezers_default_turns";
        st = rodkit_tweezers_default_turns(h, points, turns);
    }
    if (st >= 0) {
        what = "rodkit_tweezers_curve";
        st = rodkit_tweezers_curve(h, turns, points, c->pts);
    }
    if (st >= 0) {
        c->n = points;
        what = "rodkit_tweezers_summary";
        st = rodkit_tweezers_summary(h, c->pts, points, &c->sum);
    }
    c->status = st;
    if (st < 0) snprintf(c->msg, sizeof c->msg, "%s: %s: %s", what, rodkit_status_string(st), rodkit_last_error_message());
    free(turns);
    rodkit_tweezers_free(h);
    c->seconds = dm_now() - t0;
}

/* The curve as CSV through the library's writer (atomic): one row per point. */
static int write_curve_csv(const char *path, const Curve *c) {
    int32_t st = rodkit_tweezers_write_csv(c->pts, c->n, c->sum.kt, path);
    if (st < 0) {
        fprintf(stderr, "rodkit_tweezers_write_csv(%s): %s: %s\n", path, rodkit_status_string(st), rodkit_last_error_message());
        return -1;
    }
    return 0;
}

/* summary.csv of a family (atomic): one row per curve, empty cells for a failed one. */
static int write_summary_csv(const char *path, const Curve *cs, int n) {
    char tmp[4300];
    FILE *f = dm_open_tmp(path, tmp, sizeof tmp);
    if (!f) return -1;
    fprintf(f, "force_pN,salt_M,base_pairs,kT_pN_nm,status,model,end_loop,buckling_turns,buckling_torque_pN_nm,"
               "plateau_torque_pN_nm,overshoot_pN_nm,coexistence_torque_pN_nm,slope_nm_per_turn,extension_jump_nm,"
               "extension_zero_turns_nm,superhelix_radius_nm,superhelix_angle_rad,end_loop_energy_pN_nm,plateau_points\n");
    for (int k = 0; k < n; ++k) {
        const Curve *c = &cs[k];
        const RodkitTweezersInfo *s = &c->sum;
        fprintf(f, "%g,%g,%g,%g,%d", c->force, c->salt, c->bp, c->kT, (int)c->status);
        if (c->status < 0) {
            fprintf(f, ",,,,,,,,,,,,,,\n");
            continue;
        }
        fprintf(f, ",%s,%s,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%lld\n", model_name(s->model),
                end_loop_name(s->end_loop), s->buckling_turns, s->buckling_torque, s->plateau_torque, s->overshoot,
                s->coexistence_torque, s->slope, s->extension_jump, s->extension_zero_turns, s->superhelix_radius,
                s->superhelix_angle, s->end_loop_energy, (long long)s->plateau_points);
    }
    return dm_commit(f, tmp, path);
}

/* ---- SVG: extension (top) and torque (bottom) vs turns, one polyline per curve ---- */

static double tick_step(double span) {
    double raw = span / 6.0, p = 1.0;
    while (p * 10.0 <= raw) p *= 10.0;
    while (p > raw) p /= 10.0;
    return raw >= 5.0 * p ? 5.0 * p : raw >= 2.0 * p ? 2.0 * p : p;
}

static const char *COLOURS[] = {"#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d", "#666666"};
static const char *DASHES[] = {"", "6,3", "2,2", "8,3,2,3", "1,3"};

/* One panel at vertical offset top: y = extension (which 0) or torque (1). */
static void panel(FILE *f, double top, int which, const Curve *cs, int n, const int *colour, const int *dash) {
    const double L = 70, T = top + 20, pw = 500, ph = 250;
    double x0 = 0.0, x1 = 1e-9, y0 = 0.0, y1 = 1e-9;
    for (int k = 0; k < n; ++k)
        for (int64_t i = 0; i < cs[k].n; ++i) {
            double x = cs[k].pts[i].turns, y = which ? cs[k].pts[i].torque : cs[k].pts[i].extension;
            if (x > x1) x1 = x;
            if (y > y1) y1 = y;
            if (y < y0) y0 = y;
        }
    y1 += 0.05 * (y1 - y0);
#define SX(x) (L + ((x) - x0) / (x1 - x0) * pw)
#define SY(y) (T + ph - ((y) - y0) / (y1 - y0) * ph)
    fprintf(f, "<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"none\" stroke=\"black\"/>\n", L, T, pw, ph);
    double dx = tick_step(x1 - x0), dy = tick_step(y1 - y0);
    for (double t = 0.0; t <= x1 + 1e-9; t += dx) {
        fprintf(f, "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/>", SX(t), T, SX(t), T + ph);
        fprintf(f, "<text x=\"%.1f\" y=\"%g\" text-anchor=\"middle\">%g</text>\n", SX(t), T + ph + 16, t);
    }
    for (double t = dy * (double)(long)(y0 / dy); t <= y1 + 1e-9; t += dy) {
        if (t < y0 - 1e-9) continue;
        fprintf(f, "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/>", L, SY(t), L + pw, SY(t));
        fprintf(f, "<text x=\"%g\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", L - 5, SY(t) + 4, t);
    }
    fprintf(f, "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">turns</text>\n", L + pw / 2, T + ph + 34);
    fprintf(f, "<text transform=\"translate(16,%g) rotate(-90)\" text-anchor=\"middle\">%s</text>\n", T + ph / 2,
            which ? "torque (pN nm)" : "extension (nm)");
    for (int k = 0; k < n; ++k) {
        if (cs[k].n == 0) continue;
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" stroke-dasharray=\"%s\" points=\"",
                COLOURS[colour[k] % 8], DASHES[dash[k] % 5]);
        for (int64_t i = 0; i < cs[k].n; ++i) {
            double y = which ? cs[k].pts[i].torque : cs[k].pts[i].extension;
            fprintf(f, "%.2f,%.2f ", SX(cs[k].pts[i].turns), SY(y));
        }
        fprintf(f, "\"/>\n");
        if (cs[k].status >= 0) {
            /* x: the buckling point on the unbuckled state. */
            const RodkitTweezersInfo *s = &cs[k].sum;
            double y = which ? s->buckling_torque : cs[k].pts[0].extension;
            fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" fill=\"%s\" text-anchor=\"middle\">x</text>\n", SX(s->buckling_turns),
                    SY(y) + 4, COLOURS[colour[k] % 8]);
        }
    }
#undef SX
#undef SY
}

/* The two panels and a legend (atomic). */
static int write_svg(const char *path, const char *title, const Curve *cs, int n, const int *colour, const int *dash) {
    char tmp[4300];
    FILE *f = dm_open_tmp(path, tmp, sizeof tmp);
    if (!f) return -1;
    const double W = 790, H = 640;
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" font-family=\"sans-serif\" font-size=\"12\">\n", W, H);
    fprintf(f, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
    fprintf(f, "<text x=\"70\" y=\"14\">%s</text>\n", title);
    panel(f, 0, 0, cs, n, colour, dash);
    panel(f, 310, 1, cs, n, colour, dash);
    for (int k = 0; k < n; ++k) {
        double ly = 40 + 16 * k;
        fprintf(f, "<line x1=\"590\" y1=\"%g\" x2=\"620\" y2=\"%g\" stroke=\"%s\" stroke-width=\"1.5\" stroke-dasharray=\"%s\"/>", ly, ly,
                COLOURS[colour[k] % 8], DASHES[dash[k] % 5]);
        fprintf(f, "<text x=\"626\" y=\"%g\">%g pN, %g M%s</text>\n", ly + 4, cs[k].force, cs[k].salt, cs[k].status < 0 ? " (failed)" : "");
    }
    fprintf(f, "<text x=\"590\" y=\"%g\">x buckling</text>\n", 40 + 16.0 * n + 10);
    fprintf(f, "</svg>\n");
    return dm_commit(f, tmp, path);
}

/* A directory's absolute name (for the report), or the name as given. */
static const char *absolute(const char *dir, char *buf) {
    return realpath(dir, buf) ? buf : dir;
}

/* The family's curves k = first, first + stride, ... on one thread (each
 * curve has its own handle: rodkit is reentrant, and the results do not
 * depend on which thread computed them). */
typedef struct {
    Curve *cs;
    int n, first, stride;
    int64_t points;
} Share;

static void *run_share(void *arg) {
    Share *w = arg;
    for (int k = w->first; k < w->n; k += w->stride) run_curve(&w->cs[k], w->points);
    return NULL;
}

static int family(int values, double kT, int64_t points, int threads, const char *out) {
    static const double forces[] = {0.5, 1, 2, 4}, salts[] = {0.01, 0.1}, bps[] = {1000, 10000};
    enum { NF = 4, NS = 2, NL = 2, N = NF * NS * NL, MAX_THREADS = 16 };
    Curve cs[N];
    double t0 = dm_now();
    int k = 0, failed = 0;
    for (int l = 0; l < NL; ++l)
        for (int s = 0; s < NS; ++s)
            for (int fi = 0; fi < NF; ++fi, ++k) {
                memset(&cs[k], 0, sizeof cs[k]);
                cs[k].force = forces[fi];
                cs[k].salt = salts[s];
                cs[k].bp = bps[l];
                cs[k].kT = kT;
            }
    if (threads < 1) threads = 1;
    if (threads > MAX_THREADS) threads = MAX_THREADS;
    pthread_t tid[MAX_THREADS];
    Share share[MAX_THREADS];
    int created[MAX_THREADS] = {0};
    for (int t = 0; t < threads; ++t) share[t] = (Share){cs, N, t, threads, points};
    for (int t = 1; t < threads; ++t) created[t] = pthread_create(&tid[t], NULL, run_share, &share[t]) == 0;
    run_share(&share[0]);
    for (int t = 1; t < threads; ++t) {
        if (created[t]) pthread_join(tid[t], NULL);
        else run_share(&share[t]); /* not started: its curves are computed here */
    }
    for (k = 0; k < N; ++k) failed += cs[k].status < 0;
    double seconds = dm_now() - t0;
    printf("DNA in tweezers, a family (thermal two-phase model, kT %g pN nm, %lld points per curve, %d thread%s): %d curves in %.2f s\n",
           kT, (long long)points, threads, threads > 1 ? "s" : "", N, seconds);
    printf("#  F/pN  salt/M   kbp | buckling turns  torque | plateau tq  dz/dn nm/turn | jump/nm    z(0)/nm | R/nm\n");
    for (k = 0; k < N; ++k) {
        const Curve *c = &cs[k];
        const RodkitTweezersInfo *s = &c->sum;
        if (c->status < 0) {
            printf("  %5g %6g %5g   failed: %s\n", c->force, c->salt, c->bp / 1000, c->msg);
            continue;
        }
        printf("  %5g %6g %5g | %8.3f %9.2f    | %6.2f %11.2f      | %7.2f %10.1f | %5.2f\n", c->force, c->salt, c->bp / 1000,
               s->buckling_turns, s->buckling_torque, s->plateau_torque, s->slope, s->extension_jump, s->extension_zero_turns,
               s->superhelix_radius);
    }
    if (values) printf("curves = %d\nfailed_curves = %d\nseconds = %.4g\n", N, failed, seconds);
    if (out) {
        char path[4096], abs[4096];
        if (dm_make_dirs(out) != 0) {
            perror(out);
            return 1;
        }
        for (k = 0; k < N; ++k) {
            if (cs[k].status < 0) continue;
            snprintf(path, sizeof path, "%s/curve_F%g_S%g_%gbp.csv", out, cs[k].force, cs[k].salt, cs[k].bp);
            if (write_curve_csv(path, &cs[k]) != 0) return 1;
        }
        snprintf(path, sizeof path, "%s/summary.csv", out);
        if (write_summary_csv(path, cs, N) != 0) return 1;
        for (int l = 0; l < NL; ++l) {
            int colour[NF * NS], dash[NF * NS];
            for (int j = 0; j < NF * NS; ++j) {
                colour[j] = j / NF;
                dash[j] = j % NF;
            }
            char title[128];
            snprintf(title, sizeof title, "%g kbp, kT %g pN nm: extension and torque vs turns (colour salt, dash force)",
                     bps[l] / 1000, kT);
            snprintf(path, sizeof path, "%s/tweezers_%gkbp.svg", out, bps[l] / 1000);
            if (write_svg(path, title, cs + l * NF * NS, NF * NS, colour, dash) != 0) return 1;
        }
        printf("  one CSV per curve (curve_F<pN>_S<M>_<bp>bp.csv), summary.csv and tweezers_<kbp>kbp.svg: %s/\n",
               absolute(out, abs));
    }
    for (k = 0; k < N; ++k) free(cs[k].pts);
    return 0;
}

int main(int argc, char **argv) {
    int values = 0, fam = 0;
    if (argc > 1 && strcmp(argv[1], "--values") == 0) {
        values = 1;
        ++argv;
        --argc;
    }
    RodkitTweezersSpec defaults;
    int32_t st = rodkit_tweezers_spec_default(&defaults);
    if (st < 0) return fail(st, "rodkit_tweezers_spec_default");
    Curve c;
    memset(&c, 0, sizeof c);
    c.force = defaults.force;
    c.salt = defaults.salt;
    c.bp = defaults.base_pairs;
    c.kT = defaults.kt;
    int64_t points = -1;
    int threads = 2;
    const char *out = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (strcmp(a, "--family") == 0) {
            fam = 1;
            continue;
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "%s: a value is missing (usage: see c_examples/dna_tweezers.c)\n", a);
            return 2;
        }
        const char *v = argv[++i];
        char *end;
        double x = strtod(v, &end);
        int number = *v && !*end;
        if (strcmp(a, "--out") == 0) out = v;
        else if (!number) {
            fprintf(stderr, "%s: not a number: %s\n", a, v);
            return 2;
        } else if (strcmp(a, "--force") == 0) c.force = x;
        else if (strcmp(a, "--salt") == 0) c.salt = x;
        else if (strcmp(a, "--bp") == 0) c.bp = x;
        else if (strcmp(a, "--kT") == 0) c.kT = x;
        else if (strcmp(a, "--points") == 0) points = (int64_t)x;
        else if (strcmp(a, "--threads") == 0) threads = (int)x;
        else {
            fprintf(stderr, "unknown option %s (usage: see c_examples/dna_tweezers.c)\n", a);
            return 2;
        }
    }
    if (fam) return family(values, c.kT, points > 0 ? points : 100, threads, out);
    if (points < 0) points = 200;

    run_curve(&c, points);
    if (c.status < 0) {
        fprintf(stderr, "%s\n", c.msg);
        return 1;
    }
    const RodkitTweezersInfo *s = &c.sum;
    int64_t outside = 0;
    for (int64_t i = 0; i < c.n; ++i) outside += !c.pts[i].in_range;
    if (values) {
        printf("out_of_range_points = %lld\n", (long long)outside);
        printf("force = %.10g\nsalt = %.10g\nbase_pairs = %.10g\nkT = %.10g\npoints = %lld\n", c.force, c.salt, c.bp, c.kT,
               (long long)c.n);
        printf("model = %d\nmodel_name = %s\nend_loop = %d\nend_loop_name = %s\n", (int)s->model, model_name(s->model),
               (int)s->end_loop, end_loop_name(s->end_loop));
        printf("buckling_turns = %.10g\nbuckling_torque = %.10g\nplateau_torque = %.10g\n", s->buckling_turns,
               s->buckling_torque, s->plateau_torque);
        printf("plateau_torque_min = %.10g\nplateau_torque_max = %.10g\novershoot = %.10g\ncoexistence_torque = %.10g\n",
               s->plateau_torque_min, s->plateau_torque_max, s->overshoot, s->coexistence_torque);
        printf("slope = %.10g\nextension_jump = %.10g\nextension_zero_turns = %.10g\n", s->slope, s->extension_jump,
               s->extension_zero_turns);
        printf("superhelix_radius = %.10g\nsuperhelix_angle = %.10g\nend_loop_energy = %.10g\n"
               "end_loop_correction = %.10g\n",
               s->superhelix_radius, s->superhelix_angle, s->end_loop_energy, s->end_loop_correction);
        printf("plateau_turns_from = %.10g\nplateau_turns_to = %.10g\nplateau_points = %lld\ntable_error = %.10g\n",
               s->plateau_turns_from, s->plateau_turns_to, (long long)s->plateau_points, s->table_error);
        const RodkitTweezersPoint *last = &c.pts[c.n - 1];
        printf("last_turns = %.10g\nlast_extension = %.10g\nlast_torque = %.10g\nlast_plectonemes = %.10g\n", last->turns,
               last->extension, last->torque, last->plectonemes);
    }
    printf("DNA in tweezers (%s model, kT %g pN nm, %s end loop): %g bp at %g pN in %g M salt, %lld points to twice the buckling turns\n",
           s->model == RODKIT_SUPERCOIL_MODEL_THERMAL_TWO_PHASE ? "thermal two-phase" : "zero-temperature two-phase", c.kT,
           end_loop_name(s->end_loop), c.bp, c.force, c.salt, (long long)c.n);
    printf("  z(0) = %.1f nm; buckles at %.3f turns (torque %.2f pN nm), the extension jumping by %.2f nm\n",
           s->extension_zero_turns, s->buckling_turns, s->buckling_torque, s->extension_jump);
    printf("  plectonemes: plateau torque %.2f pN nm, slope %.2f nm/turn, superhelix radius %.2f nm (%.2f s)\n", s->plateau_torque,
           s->slope, s->superhelix_radius, c.seconds);
    if (outside)
        printf("  %lld of the points lie outside the model's range (in_range 0 in the CSV; the summary skips them)\n",
               (long long)outside);
    if (out) {
        char path[4096], abs[4096];
        if (dm_make_dirs(out) != 0) {
            perror(out);
            return 1;
        }
        snprintf(path, sizeof path, "%s/curve.csv", out);
        if (write_curve_csv(path, &c) != 0) return 1;
        snprintf(path, sizeof path, "%s/curve.svg", out);
        int zero = 0;
        char title[160];
        snprintf(title, sizeof title, "%g bp, %g pN, %g M, kT %g pN nm: extension and torque vs turns", c.bp, c.force, c.salt, c.kT);
        if (write_svg(path, title, &c, 1, &zero, &zero) != 0) return 1;
        printf("  curve (CSV) and plot (SVG): %s/curve.csv, curve.svg\n", absolute(out, abs));
    }
    free(c.pts);
    return 0;
}

/* The DNA map drivers' shared code: see dna_map_common.h. */
#define _XOPEN_SOURCE 700
#include "dna_map_common.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

double dm_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int dm_parse_list(const char *s, double *out) {
    int n = 0;
    char *end;
    while (*s && n < DM_MAX_VALUES) {
        out[n++] = strtod(s, &end);
        if (end == s) return -1;
        s = *end == ',' ? end + 1 : end;
    }
    return *s ? -1 : n;
}

int dm_make_dirs(const char *path) {
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

const char *dm_finding(int32_t f) {
    switch (f) {
    case RODKIT_SUMMARY_FINDING_FOUND: return "found";
    case RODKIT_SUMMARY_FINDING_UNVERIFIED: return "unverified";
    case RODKIT_SUMMARY_FINDING_UNDETERMINED: return "undetermined";
    case RODKIT_SUMMARY_FINDING_NOT_REACHED: return "not_reached";
    default: return "failed";
    }
}

const char *dm_stability(int32_t k) {
    switch (k) {
    case RODKIT_STABILITY_KIND_LOWEST: return "lowest";
    case RODKIT_STABILITY_KIND_METASTABLE: return "metastable";
    case RODKIT_STABILITY_KIND_UNSTABLE: return "unstable";
    default: return "undetermined";
    }
}

int dm_has_value(int32_t f) { return f == RODKIT_SUMMARY_FINDING_FOUND || f == RODKIT_SUMMARY_FINDING_UNVERIFIED; }

/* One CSV cell: the value when its finding has one, else empty. */
static void cell(FILE *f, int32_t fnd, double v) {
    if (dm_has_value(fnd)) fprintf(f, ",%.10g", v);
    else fprintf(f, ",");
}

void dm_run_curve(const RodkitDnaSupercoilSpec *spec, DnaCurve *c, RodkitBranchCallback progress, void *user_data) {
    RodkitSupercoil *run = NULL;
    double t0 = dm_now();
    c->status = rodkit_dna_supercoil_run_with(spec, progress, user_data, &run);
    if (c->status < 0) {
        fprintf(stderr, "  %lld bp, F = %g pN, c = %g M: %s: %s\n", (long long)c->bp, c->force, c->salt,
                rodkit_status_string(c->status), rodkit_last_error_message());
        c->seconds = dm_now() - t0;
        return;
    }
    if (c->status == RODKIT_STATUS_INFO_FAILED_PARTWAY) {
        /* The branch failed partway (e.g. it kept sliding onto the spurious
         * straight family): the curve up to its last good point is kept and
         * summarised, its status (7) says it is partial. */
        char why[512];
        int32_t error = 0;
        rodkit_supercoil_failure(run, &error, why, sizeof why, NULL);
        fprintf(stderr, "  %lld bp, F = %g pN, c = %g M: failed partway (%s), the curve so far is kept: %s\n",
                (long long)c->bp, c->force, c->salt, rodkit_status_string(error), why);
    }
    int32_t st = rodkit_supercoil_summary(run, &c->info);
    if (st >= 0) {
        c->points = c->info.points;
        c->pts = malloc(sizeof *c->pts * (size_t)c->points);
        c->cpts = malloc(sizeof *c->cpts * (size_t)c->points);
        int64_t n = 0;
        if (!c->pts || !c->cpts || rodkit_supercoil_points(run, c->pts, c->points, &n) < 0) st = -1;
    }
    double t1 = dm_now();
    if (st >= 0 && rodkit_supercoil_curve_points(run, c->cpts, c->points, &(int64_t){0}) < 0) {
        fprintf(stderr, "  curve points: %s\n", rodkit_last_error_message());
        free(c->cpts);
        c->cpts = NULL;
    }
    if (st >= 0 && (st = rodkit_supercoil_curve_summary(run, &c->sum)) < 0)
        fprintf(stderr, "  summary: %s\n", rodkit_last_error_message());
    if (st < 0) c->status = st;
    c->seconds = dm_now() - t0;
    c->curve_seconds = dm_now() - t1;
    rodkit_supercoil_free(run);
}

int dm_two_phase(const DnaCurve *c) {
    return c->model == RODKIT_SUPERCOIL_MODEL_THERMAL_TWO_PHASE || c->model == RODKIT_SUPERCOIL_MODEL_ZERO_TEMPERATURE_TWO_PHASE;
}

const char *dm_model_name(int32_t model) {
    switch (model) {
    case RODKIT_SUPERCOIL_MODEL_THERMAL_TWO_PHASE: return "thermal_two_phase";
    case RODKIT_SUPERCOIL_MODEL_ZERO_TEMPERATURE_TWO_PHASE: return "zero_temperature_two_phase";
    default: return "full_rod";
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

void dm_run_two_phase_curve(DnaCurve *c, double max_turns, int64_t points) {
    double t0 = dm_now();
    RodkitTweezersSpec spec;
    RodkitTweezers *h = NULL;
    double *turns = malloc(sizeof *turns * (size_t)points);
    c->model = c->kT > 0.0 ? RODKIT_SUPERCOIL_MODEL_THERMAL_TWO_PHASE : RODKIT_SUPERCOIL_MODEL_ZERO_TEMPERATURE_TWO_PHASE;
    c->tpts = malloc(sizeof *c->tpts * (size_t)points);
    c->points = 0;
    c->out_of_range = 0;
    if (!turns || !c->tpts) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    const char *what = "rodkit_tweezers_spec_default";
    int32_t st = rodkit_tweezers_spec_default(&spec);
    if (st >= 0) {
        spec.force = c->force;
        spec.salt = c->salt;
        spec.base_pairs = (double)c->bp;
        spec.kt = c->kT;
        what = "rodkit_tweezers_new";
        st = rodkit_tweezers_new(&spec, &h);
    }
    if (st >= 0 && max_turns <= 0.0) {
        what = "rodkit_tweezers_default_turns";
        st = rodkit_tweezers_default_turns(h, points, turns);
    } else if (st >= 0) {
        for (int64_t i = 0; i < points; ++i) turns[i] = max_turns * (double)i / (double)(points - 1);
    }
    if (st >= 0) {
        what = "rodkit_tweezers_curve";
        st = rodkit_tweezers_curve(h, turns, points, c->tpts);
    }
    if (st >= 0) {
        c->points = points;
        for (int64_t i = 0; i < points; ++i) c->out_of_range += !c->tpts[i].in_range;
        what = "rodkit_tweezers_summary";
        st = rodkit_tweezers_summary(h, c->tpts, points, &c->tsum);
    }
    c->status = st;
    if (st < 0) {
        snprintf(c->msg, sizeof c->msg, "%s: %s: %s", what, rodkit_status_string(st), rodkit_last_error_message());
        fprintf(stderr, "  %lld bp, F = %g pN, c = %g M, kT = %g pN nm: %s\n", (long long)c->bp, c->force, c->salt, c->kT, c->msg);
    }
    rodkit_tweezers_free(h);
    free(turns);
    c->seconds = dm_now() - t0;
}

void dm_curve_free(DnaCurve *c) {
    free(c->pts);
    free(c->cpts);
    free(c->tpts);
    c->pts = NULL;
    c->cpts = NULL;
    c->tpts = NULL;
}

FILE *dm_open_tmp(const char *path, char *tmp, size_t tmp_size) {
    int n = snprintf(tmp, tmp_size, "%s.tmp.%ld", path, (long)getpid());
    if (n < 0 || (size_t)n >= tmp_size) {
        fprintf(stderr, "%s: path too long\n", path);
        return NULL;
    }
    FILE *f = fopen(tmp, "w");
    if (!f) perror(tmp);
    return f;
}

int dm_commit(FILE *f, const char *tmp, const char *path) {
    int bad = ferror(f) || fflush(f) != 0 || fsync(fileno(f)) != 0;
    bad |= fclose(f) != 0;
    if (!bad && rename(tmp, path) == 0) return 0;
    perror(path);
    remove(tmp);
    return -1;
}

int dm_write_curve_csv(const char *path, const DnaCurve *c) {
    char tmp[4300];
    FILE *f = dm_open_tmp(path, tmp, sizeof tmp);
    if (!f) return -1;
    if (dm_two_phase(c)) {
        /* The thermal averages at each turns (RodkitTweezersPoint). */
        fprintf(f, "turns,extension_nm,torque_pN_nm,twist,writhe,plectoneme_length_nm,plectonemes,buckled_probability,"
                   "extension_unbuckled_nm,extension_buckled_nm,superhelix_radius_nm,superhelix_angle_rad,in_range\n");
        for (int64_t i = 0; i < c->points; ++i) {
            const RodkitTweezersPoint *p = &c->tpts[i];
            fprintf(f, "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,", p->turns, p->extension, p->torque, p->twist,
                    p->writhe, p->plectoneme_length, p->plectonemes, p->buckled_probability, p->extension_unbuckled);
            if (p->has_buckled) fprintf(f, "%.10g", p->extension_buckled);
            fprintf(f, ",%.10g,%.10g,%d\n", p->superhelix_radius, p->superhelix_angle, (int)p->in_range);
        }
        return dm_commit(f, tmp, path);
    }
    fprintf(f, "turns,extension_nm,torque_pN_nm,tension_pN,twist,writhe,energy_pN_nm,branch,stability,negative_modes\n");
    for (int64_t i = 0; i < c->points; ++i) {
        const RodkitSupercoilPoint *p = &c->pts[i];
        fprintf(f, "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,", p->turns, p->extension, p->torque, p->tension, p->twist, p->writhe);
        if (c->cpts)
            fprintf(f, "%.12g,%d,%s,%lld\n", c->cpts[i].energy, (int)p->branch, dm_stability(c->cpts[i].kind),
                    (long long)c->cpts[i].negative_modes);
        else
            fprintf(f, ",%d,,\n", (int)p->branch);
    }
    return dm_commit(f, tmp, path);
}

int dm_write_summary_csv(const char *path, const DnaCurve *cs, int n, int with_seconds) {
    char tmp[4300];
    FILE *f = dm_open_tmp(path, tmp, sizeof tmp);
    if (!f) return -1;
    fprintf(f, "force_pN,salt_M,base_pairs,model,kT_pN_nm,status,points,last_turns,%shard_core_switched,"
               "instability_finding,instability_turns,instability_torque_pN_nm,"
               "coexistence_finding,coexistence_turns,coexistence_torque_straight_pN_nm,"
               "coexistence_torque_plectoneme_pN_nm,coexistence_extension_jump_nm,"
               "plateau_finding,plateau_torque_pN_nm,plateau_torque_min_pN_nm,plateau_torque_max_pN_nm,"
               "slope_nm_per_turn,plateau_turns_from,plateau_turns_to,"
               "superhelix_finding,superhelix_radius_nm,superhelix_turns,end_loop,out_of_range_points\n",
            with_seconds ? "seconds," : "");
    for (int k = 0; k < n; ++k) {
        const DnaCurve *c = &cs[k];
        const RodkitSupercoilCurveInfo *s = &c->sum;
        int ok = c->status >= 0;
        fprintf(f, "%g,%g,%lld,%s,%g,%d,%lld,", c->force, c->salt, (long long)c->bp, dm_model_name(c->model),
                dm_two_phase(c) ? c->kT : 0.0, (int)c->status, (long long)c->points);
        if (ok && c->points > 0) fprintf(f, "%.10g,", dm_two_phase(c) ? c->tpts[c->points - 1].turns : c->pts[c->points - 1].turns);
        else fprintf(f, ",");
        if (with_seconds) fprintf(f, "%.4g,", c->seconds);
        if (dm_two_phase(c)) {
            /* The two-phase model's columns (dna_map.c's header comment):
             * no straight-rod instability; its buckling (P(buckled) = 1/2)
             * is the coexistence, its unbuckled torque there the straight
             * torque, no plectoneme torque at it; plateau and superhelix
             * radius the same quantities; no hard-core switch, no
             * superhelix turns. */
            const RodkitTweezersInfo *t = &c->tsum;
            if (!ok) {
                fprintf(f, ",failed,,,failed,,,,,failed,,,,,,,failed,,,,%lld\n", (long long)c->out_of_range);
                continue;
            }
            fprintf(f, ",not_in_model,,");
            fprintf(f, ",found,%.10g,%.10g,,%.10g", t->buckling_turns, t->buckling_torque, t->extension_jump);
            fprintf(f, ",found,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g", t->plateau_torque, t->plateau_torque_min,
                    t->plateau_torque_max, t->slope, t->plateau_turns_from, t->plateau_turns_to);
            fprintf(f, ",found,%.10g,,%s,%lld\n", t->superhelix_radius, end_loop_name(t->end_loop), (long long)c->out_of_range);
            continue;
        }
        fprintf(f, "%d", ok ? (int)c->info.hard_core_switched : 0);
        fprintf(f, ",%s", ok ? dm_finding(s->instability_finding) : "failed");
        cell(f, s->instability_finding, s->instability_turns);
        cell(f, s->instability_finding, s->instability_torque);
        fprintf(f, ",%s", ok ? dm_finding(s->coexistence_finding) : "failed");
        cell(f, s->coexistence_finding, s->coexistence_turns);
        cell(f, s->coexistence_finding, s->coexistence_torque_straight);
        cell(f, s->coexistence_finding, s->coexistence_torque_plectoneme);
        cell(f, s->coexistence_finding, s->coexistence_extension_jump);
        fprintf(f, ",%s", ok ? dm_finding(s->plateau_finding) : "failed");
        cell(f, s->plateau_finding, s->plateau_torque);
        cell(f, s->plateau_finding, s->plateau_torque_min);
        cell(f, s->plateau_finding, s->plateau_torque_max);
        cell(f, s->plateau_finding, s->slope);
        cell(f, s->plateau_finding, s->plateau_turns_from);
        cell(f, s->plateau_finding, s->plateau_turns_to);
        fprintf(f, ",%s", ok ? dm_finding(s->superhelix_finding) : "failed");
        cell(f, s->superhelix_finding, s->superhelix_radius);
        cell(f, s->superhelix_finding, s->superhelix_turns);
        fprintf(f, ",,\n");
    }
    return dm_commit(f, tmp, path);
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

/* A curve's point i: turns, and extension (which 0) or torque (1); the
 * two-phase models' points outside their range are not plotted. */
static double pt_x(const DnaCurve *c, int64_t i) { return dm_two_phase(c) ? c->tpts[i].turns : c->pts[i].turns; }
static double pt_y(const DnaCurve *c, int64_t i, int which) {
    if (dm_two_phase(c)) return which ? c->tpts[i].torque : c->tpts[i].extension;
    return which ? c->pts[i].torque : c->pts[i].extension;
}
static int pt_plotted(const DnaCurve *c, int64_t i) { return !dm_two_phase(c) || c->tpts[i].in_range; }

/* The two-phase model's unbuckled extension at the buckling turns (linear
 * between the curve's points). */
static double unbuckled_at(const DnaCurve *c, double turns) {
    for (int64_t i = 1; i < c->points; ++i)
        if (c->tpts[i].turns >= turns) {
            const RodkitTweezersPoint *a = &c->tpts[i - 1], *b = &c->tpts[i];
            double t = (turns - a->turns) / (b->turns - a->turns);
            return a->extension_unbuckled + t * (b->extension_unbuckled - a->extension_unbuckled);
        }
    return c->tpts[c->points - 1].extension_unbuckled;
}

int dm_write_svg(const char *path, int which, const DnaCurve *cs, int n, const double *forces, int nf,
                 const double *salts, int ns) {
    double x0 = 0.0, x1 = 1e-9, y0 = 1e300, y1 = -1e300;
    for (int k = 0; k < n; ++k)
        for (int64_t i = 0; i < cs[k].points; ++i) {
            if (!pt_plotted(&cs[k], i)) continue;
            double x = pt_x(&cs[k], i), y = pt_y(&cs[k], i, which);
            if (x > x1) x1 = x;
            if (x < x0) x0 = x;
            if (y < y0) y0 = y;
            if (y > y1) y1 = y;
        }
    if (y0 > y1) { y0 = 0.0; y1 = 1.0; }
    if (!which || y0 > 0.0) y0 = y0 < 0.0 ? y0 : 0.0;
    double pad = 0.05 * (y1 - y0 + 1e-12);
    y1 += pad;
    char tmp[4300];
    FILE *f = dm_open_tmp(path, tmp, sizeof tmp);
    if (!f) return -1;
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
        const DnaCurve *c = &cs[k];
        if (c->points == 0) continue;
        int fi = 0, si = 0;
        for (int j = 0; j < nf; ++j) if (forces[j] == c->force) fi = j;
        for (int j = 0; j < ns; ++j) if (salts[j] == c->salt) si = j;
        const char *col = COLOURS[si % 8], *dash = DASHES[fi % 5];
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" stroke-dasharray=\"%s\" points=\"", col, dash);
        for (int64_t i = 0; i < c->points; ++i)
            if (pt_plotted(c, i)) fprintf(f, "%.2f,%.2f ", SX(pt_x(c, i)), SY(pt_y(c, i, which)));
        fprintf(f, "\"/>\n");
        const RodkitSupercoilCurveInfo *s = &c->sum;
        if (dm_two_phase(c) && c->status >= 0) {
            /* o at the buckling (P(buckled) = 1/2): the unbuckled level,
             * and (extension only) the buckled one a jump below. */
            const RodkitTweezersInfo *t = &c->tsum;
            double zu = unbuckled_at(c, t->buckling_turns);
            fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"4\" fill=\"none\" stroke=\"%s\"/>", SX(t->buckling_turns),
                    SY(which ? t->buckling_torque : zu), col);
            if (!which)
                fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"4\" fill=\"%s\"/>", SX(t->buckling_turns), SY(zu - t->extension_jump),
                        col);
            fprintf(f, "\n");
        }
        if (!dm_two_phase(c) && c->status >= 0 && s->coexistence_finding == RODKIT_SUMMARY_FINDING_FOUND) {
            double ys = which ? s->coexistence_torque_straight : s->coexistence_extension_straight;
            double yp = which ? s->coexistence_torque_plectoneme : s->coexistence_extension_plectoneme;
            fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"4\" fill=\"none\" stroke=\"%s\"/>", SX(s->coexistence_turns), SY(ys), col);
            fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"4\" fill=\"%s\"/>\n", SX(s->coexistence_turns), SY(yp), col);
        }
        if (!dm_two_phase(c) && c->status >= 0 && s->instability_finding == RODKIT_SUMMARY_FINDING_FOUND) {
            double y = which ? s->instability_torque : c->pts[0].extension;
            fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" fill=\"%s\" text-anchor=\"middle\">x</text>\n", SX(s->instability_turns),
                    SY(y) + 4, col);
        }
        double ly = T + 14 + 16 * k;
        fprintf(f, "<line x1=\"%g\" y1=\"%g\" x2=\"%g\" y2=\"%g\" stroke=\"%s\" stroke-width=\"1.5\" stroke-dasharray=\"%s\"/>", W - R + 12,
                ly, W - R + 42, ly, col, dash);
        fprintf(f, "<text x=\"%g\" y=\"%g\">%g pN, %g M</text>\n", W - R + 48, ly + 4, c->force, c->salt);
    }
    if (n > 0 && dm_two_phase(&cs[0]))
        fprintf(f, "<text x=\"%g\" y=\"%g\">%s, kT %g pN nm</text><text x=\"%g\" y=\"%g\">o buckling (P = 1/2)</text>\n",
                W - R + 12, T + 30 + 16 * n, cs[0].model == RODKIT_SUPERCOIL_MODEL_THERMAL_TWO_PHASE ? "thermal two-phase"
                : "two-phase, kT 0", cs[0].kT, W - R + 12, T + 46 + 16 * n);
    else
        fprintf(f, "<text x=\"%g\" y=\"%g\">o coexistence, x instability</text>\n", W - R + 12, T + 30 + 16 * n);
    fprintf(f, "</svg>\n");
#undef SX
#undef SY
    return dm_commit(f, tmp, path);
}

void dm_print_table(const DnaCurve *cs, int n) {
    printf("#  F/pN  salt/M  pts  last_turns   s  | buckling turns torque | coexistence turns  tq_s   tq_p  jump/nm | plateau tq  "
           "dz/dn nm/turn | radius/nm | model\n");
    for (int k = 0; k < n; ++k) {
        const DnaCurve *c = &cs[k];
        const RodkitSupercoilCurveInfo *s = &c->sum;
        if (c->status < 0) {
            printf("  %5g %6g  failed (%s) | %s\n", c->force, c->salt, rodkit_status_string(c->status), dm_model_name(c->model));
            continue;
        }
        if (dm_two_phase(c)) {
            /* The columns of dna_map.c's header comment: buckling at
             * P(buckled) = 1/2 under "coexistence", its unbuckled torque
             * under tq_s; no instability, no plectoneme torque there. */
            const RodkitTweezersInfo *t = &c->tsum;
            printf("  %5g %6g %5lld %8.3f %6.2f | %-21s| %7.4f %6.2f %6s %7.2f     | %6.2f  %8.2f      | %6.3f    | %s\n", c->force,
                   c->salt, (long long)c->points, c->tpts[c->points - 1].turns, c->seconds, "not_in_model", t->buckling_turns,
                   t->buckling_torque, "-", t->extension_jump, t->plateau_torque, t->slope, t->superhelix_radius,
                   dm_model_name(c->model));
            continue;
        }
        printf("  %5g %6g %5lld %8.3f %6.1f |", c->force, c->salt, (long long)c->points, c->pts[c->points - 1].turns, c->seconds);
        if (dm_has_value(s->instability_finding)) printf(" %7.4f %7.3f      |", s->instability_turns, s->instability_torque);
        else printf(" %-21s|", dm_finding(s->instability_finding));
        if (dm_has_value(s->coexistence_finding))
            printf(" %7.4f %6.2f %6.2f %7.2f     |", s->coexistence_turns, s->coexistence_torque_straight,
                   s->coexistence_torque_plectoneme, s->coexistence_extension_jump);
        else printf(" %-33s|", dm_finding(s->coexistence_finding));
        if (dm_has_value(s->plateau_finding))
            printf(" %6.2f%s %8.2f      |", s->plateau_torque, s->plateau_finding == RODKIT_SUMMARY_FINDING_UNVERIFIED ? "?" : " ",
                   s->slope);
        else printf(" %-22s|", dm_finding(s->plateau_finding));
        if (dm_has_value(s->superhelix_finding)) printf(" %6.3f    |", s->superhelix_radius);
        else printf(" %-10s|", dm_finding(s->superhelix_finding));
        printf(" %s\n", dm_model_name(c->model));
    }
}

/* ---- The plateau torque vs force against tweezers data ---- */

/* One row of tests/data/tweezers/buckling_torque.csv. */
typedef struct {
    double force, salt_lo, salt_hi, kbp, torque, error; /* NAN: empty */
    int sign;
    char error_type[32], kind[32], source[64];
} TorqueDatum;

/* The CSV's cells (empty ones kept) into cell[max]: their count. */
static int split_csv(char *line, char **cell, int max) {
    int n = 0;
    char *p = line;
    while (n < max) {
        cell[n++] = p;
        char *c = strchr(p, ',');
        if (!c) break;
        *c = '\0';
        p = c + 1;
    }
    return n;
}

static double num_or_nan(const char *s) {
    char *end;
    double v = strtod(s, &end);
    return end == s ? NAN : v;
}

/* The data rows (skipping '#' comments and the header): their count, -1
 * when the file cannot be read or a row is malformed. */
static int read_torque_data(const char *path, TorqueDatum *out, int max) {
    FILE *f = fopen(path, "r");
    if (!f) {
        perror(path);
        return -1;
    }
    char line[1024];
    int n = 0, header = 0;
    while (fgets(line, sizeof line, f) && n < max) {
        line[strcspn(line, "\r\n")] = '\0';
        if (line[0] == '#' || line[0] == '\0') continue;
        if (!header) {
            header = 1;
            if (strncmp(line, "force_pN,salt_lo_M,salt_hi_M,length_kbp,sign,torque_pNnm,error,error_type,kind,source_key", 89)) {
                fprintf(stderr, "%s: unexpected header: %s\n", path, line);
                fclose(f);
                return -1;
            }
            continue;
        }
        char *cell[10];
        if (split_csv(line, cell, 10) != 10) {
            fprintf(stderr, "%s: a row without 10 cells\n", path);
            fclose(f);
            return -1;
        }
        TorqueDatum *d = &out[n++];
        d->force = num_or_nan(cell[0]);
        d->salt_lo = num_or_nan(cell[1]);
        d->salt_hi = num_or_nan(cell[2]);
        d->kbp = num_or_nan(cell[3]);
        d->sign = atoi(cell[4]);
        d->torque = num_or_nan(cell[5]);
        d->error = num_or_nan(cell[6]);
        snprintf(d->error_type, sizeof d->error_type, "%s", cell[7]);
        snprintf(d->kind, sizeof d->kind, "%s", cell[8]);
        snprintf(d->source, sizeof d->source, "%s", cell[9]);
        if (isnan(d->force) || isnan(d->torque)) n--;
    }
    fclose(f);
    return n;
}

/* The map's distinct salts of the two-phase curves that succeeded, ascending. */
static int model_salts(const DnaCurve *cs, int n, double *salts) {
    int ns = 0;
    for (int k = 0; k < n; ++k) {
        if (!dm_two_phase(&cs[k]) || cs[k].status < 0) continue;
        int seen = 0;
        for (int j = 0; j < ns; ++j) seen |= salts[j] == cs[k].salt;
        if (!seen && ns < DM_MAX_VALUES) salts[ns++] = cs[k].salt;
    }
    for (int i = 1; i < ns; ++i)
        for (int j = i; j > 0 && salts[j] < salts[j - 1]; --j) {
            double t = salts[j];
            salts[j] = salts[j - 1];
            salts[j - 1] = t;
        }
    return ns;
}

/* The model's (force, plateau torque) at one salt, ascending in force. */
static int model_line(const DnaCurve *cs, int n, double salt, double *f, double *t) {
    int m = 0;
    for (int k = 0; k < n; ++k)
        if (dm_two_phase(&cs[k]) && cs[k].status >= 0 && cs[k].salt == salt && m < DM_MAX_VALUES * DM_MAX_VALUES) {
            int j = m++;
            for (; j > 0 && f[j - 1] > cs[k].force; --j) {
                f[j] = f[j - 1];
                t[j] = t[j - 1];
            }
            f[j] = cs[k].force;
            t[j] = cs[k].tsum.plateau_torque;
        }
    return m;
}

/* Linear in force between the model's forces; NAN outside them. */
static double interpolate(const double *f, const double *t, int m, double x) {
    for (int i = 0; i < m; ++i) {
        if (f[i] == x) return t[i];
        if (i > 0 && f[i - 1] < x && x < f[i]) return t[i - 1] + (x - f[i - 1]) / (f[i] - f[i - 1]) * (t[i] - t[i - 1]);
    }
    return NAN;
}

static const char *source_label(const TorqueDatum *d) {
    if (!strcmp(d->source, "Lee2023")) return "Lee et al., Nat. Commun. 2023 (AOT, 12.7 kb, salt not stated; mean +- s.d.)";
    if (!strcmp(d->kind, "spec_unverified")) return "spec's typical values, UNVERIFIED (0.10-0.15 M; +- half the quoted range)";
    return d->source;
}

/* The data file's name as the report shows it: from "tests/" on, else its base name. */
static const char *shown_path(const char *path) {
    const char *t = strstr(path, "tests/");
    if (t) return t;
    const char *b = strrchr(path, '/');
    return b ? b + 1 : path;
}

int dm_plateau_vs_data(const char *svg_path, const char *data_path, const DnaCurve *cs, int n) {
    TorqueDatum data[64];
    int nd = read_torque_data(data_path, data, 64);
    if (nd < 0) return -1;
    double salts[DM_MAX_VALUES];
    int ns = model_salts(cs, n, salts);
    static double lf[DM_MAX_VALUES][DM_MAX_VALUES * DM_MAX_VALUES], lt[DM_MAX_VALUES][DM_MAX_VALUES * DM_MAX_VALUES];
    int lm[DM_MAX_VALUES];
    for (int j = 0; j < ns; ++j) lm[j] = model_line(cs, n, salts[j], lf[j], lt[j]);
    double kT = 0.0, kbp = 0.0;
    for (int k = 0; k < n; ++k)
        if (dm_two_phase(&cs[k])) kT = cs[k].kT, kbp = (double)cs[k].bp / 1000.0;

    /* The table: each data row against the model at its force, per salt. */
    printf("Plateau torque, model vs data (%s; model: %s, %g kbp, kT %g pN nm, plateau of the curve at each force, linear "
           "between forces):\n",
           shown_path(data_path), kT > 0 ? "thermal two-phase" : "two-phase at kT 0", kbp, kT);
    printf("#  F/pN  data pN nm       salt/M       kind             source  |");
    for (int j = 0; j < ns; ++j) {
        char label[32];
        snprintf(label, sizeof label, "model %g M (diff)", salts[j]);
        printf(" %-19s|", label);
    }
    printf("\n");
    for (int i = 0; i < nd; ++i) {
        const TorqueDatum *d = &data[i];
        char err[32] = "", salt[32] = "not stated";
        if (!isnan(d->error)) snprintf(err, sizeof err, " +- %g", d->error);
        if (!isnan(d->salt_lo)) snprintf(salt, sizeof salt, "%g-%g", d->salt_lo, d->salt_hi);
        char val[48];
        snprintf(val, sizeof val, "%s%g%s", d->sign < 0 ? "-" : "+", d->torque, err);
        printf("  %5g  %-15s %-12s %-16s %-8s |", d->force, val, salt, d->kind, d->source);
        for (int j = 0; j < ns; ++j) {
            double m = interpolate(lf[j], lt[j], lm[j], d->force);
            if (isnan(m)) printf(" %-19s|", "outside the map");
            else printf(" %7.2f (%+5.0f %%)  |", m, 100.0 * (m - d->torque) / d->torque);
        }
        printf("\n");
    }
    printf("# the model is for positive supercoiling (the -7.6 row is Lee 2023's negative plateau, compared by magnitude);\n"
           "# spec_unverified rows are the spec's typical values at 0.10-0.15 M, found in no source we could read\n");
    if (!svg_path) return 0;

    /* The plot: model lines per salt, data points with error bars. */
    double x1 = 0.0, y1 = 0.0;
    for (int j = 0; j < ns; ++j)
        for (int i = 0; i < lm[j]; ++i) {
            if (lf[j][i] > x1) x1 = lf[j][i];
            if (lt[j][i] > y1) y1 = lt[j][i];
        }
    for (int i = 0; i < nd; ++i) {
        if (data[i].force > x1) x1 = data[i].force;
        double top = data[i].torque + (isnan(data[i].error) ? 0.0 : data[i].error);
        if (top > y1) y1 = top;
    }
    x1 *= 1.05;
    y1 = y1 * 1.08 + 1e-9;
    const double x0 = 0.0, y0 = 0.0;
    char tmp[4300];
    FILE *f = dm_open_tmp(svg_path, tmp, sizeof tmp);
    if (!f) return -1;
    const double W = 980, H = 500, L = 70, T = 40, pw = 440, ph = 400;
#define SX(x) (L + ((x) - x0) / (x1 - x0) * pw)
#define SY(y) (T + ph - ((y) - y0) / (y1 - y0) * ph)
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" font-family=\"sans-serif\" font-size=\"12\">\n", W, H);
    fprintf(f, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
    fprintf(f, "<text x=\"%g\" y=\"20\">Plateau torque vs force: %s model (%g kbp, kT %g pN nm) and tweezers data</text>\n", L,
            kT > 0 ? "thermal two-phase" : "two-phase (kT 0)", kbp, kT);
    fprintf(f, "<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"none\" stroke=\"black\"/>\n", L, T, pw, ph);
    double dx = tick_step(x1 - x0), dy = tick_step(y1 - y0);
    for (double t = 0.0; t <= x1 + 1e-9; t += dx) {
        fprintf(f, "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/>", SX(t), T, SX(t), T + ph);
        fprintf(f, "<text x=\"%.1f\" y=\"%g\" text-anchor=\"middle\">%g</text>\n", SX(t), T + ph + 16, t);
    }
    for (double t = 0.0; t <= y1 + 1e-9; t += dy) {
        fprintf(f, "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/>", L, SY(t), L + pw, SY(t));
        fprintf(f, "<text x=\"%g\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n", L - 5, SY(t) + 4, t);
    }
    fprintf(f, "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">force (pN)</text>\n", L + pw / 2, T + ph + 34);
    fprintf(f, "<text transform=\"translate(16,%g) rotate(-90)\" text-anchor=\"middle\">plateau torque (pN nm)</text>\n", T + ph / 2);
    double ly = T + 10;
    for (int j = 0; j < ns; ++j, ly += 18) {
        const char *col = COLOURS[j % 8];
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" points=\"", col);
        for (int i = 0; i < lm[j]; ++i) fprintf(f, "%.2f,%.2f ", SX(lf[j][i]), SY(lt[j][i]));
        fprintf(f, "\"/>\n");
        for (int i = 0; i < lm[j]; ++i)
            fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"2.5\" fill=\"%s\"/>", SX(lf[j][i]), SY(lt[j][i]), col);
        fprintf(f, "\n<line x1=\"%g\" y1=\"%g\" x2=\"%g\" y2=\"%g\" stroke=\"%s\" stroke-width=\"1.5\"/>", L + pw + 15, ly, L + pw + 45,
                ly, col);
        fprintf(f, "<text x=\"%g\" y=\"%g\">model, %g M salt</text>\n", L + pw + 50, ly + 4, salts[j]);
    }
    /* Data: one marker per source (filled square: stated; open diamond:
     * the spec's unverified values; open square: a negative plateau). */
    const char *seen[8];
    int seen_negative[8], nseen = 0;
    for (int i = 0; i < nd; ++i) {
        const TorqueDatum *d = &data[i];
        int spec = !strcmp(d->kind, "spec_unverified");
        double x = SX(d->force) + (d->sign < 0 ? 5.0 : 0.0), y = SY(d->torque);
        if (!isnan(d->error)) {
            fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"black\"/>", x, SY(d->torque - d->error), x,
                    SY(d->torque + d->error));
            fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"black\"/>", x - 3, SY(d->torque - d->error), x + 3,
                    SY(d->torque - d->error));
            fprintf(f, "<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"black\"/>", x - 3, SY(d->torque + d->error), x + 3,
                    SY(d->torque + d->error));
        }
        if (spec)
            fprintf(f, "<path d=\"M %.2f %.2f l 5 5 l -5 5 l -5 -5 z\" fill=\"white\" stroke=\"black\"/>\n", x, y - 5);
        else
            fprintf(f, "<rect x=\"%.2f\" y=\"%.2f\" width=\"7\" height=\"7\" fill=\"%s\" stroke=\"black\"/>\n", x - 3.5, y - 3.5,
                    d->sign < 0 ? "white" : "black");
        int known = 0;
        for (int j = 0; j < nseen; ++j) known |= !strcmp(seen[j], d->source) && seen_negative[j] == (d->sign < 0);
        if (known || nseen >= 8) continue;
        seen[nseen] = d->source;
        seen_negative[nseen++] = d->sign < 0;
        ly += 6;
        double lx = L + pw + 30;
        if (spec)
            fprintf(f, "<path d=\"M %.2f %.2f l 5 5 l -5 5 l -5 -5 z\" fill=\"white\" stroke=\"black\"/>", lx, ly - 5);
        else
            fprintf(f, "<rect x=\"%.2f\" y=\"%.2f\" width=\"7\" height=\"7\" fill=\"%s\" stroke=\"black\"/>", lx - 3.5, ly - 3.5,
                    d->sign < 0 ? "white" : "black");
        const char *label = source_label(d);
        /* The legend's label in two lines: the source, then the details. */
        const char *paren = strchr(label, '(');
        int head = paren ? (int)(paren - label) : (int)strlen(label);
        fprintf(f, "<text x=\"%g\" y=\"%g\">%.*s%s</text>", lx + 12, ly + 4, head, label, d->sign < 0 ? " (negative turns)" : "");
        if (paren) fprintf(f, "<text x=\"%g\" y=\"%g\" font-size=\"10\">%s</text>", lx + 12, ly + 17, paren);
        fprintf(f, "\n");
        ly += 30;
    }
    fprintf(f, "</svg>\n");
#undef SX
#undef SY
    return dm_commit(f, tmp, svg_path);
}

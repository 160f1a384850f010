/* The DNA map drivers' shared code: see dna_map_common.h. */
#define _XOPEN_SOURCE 700
#include "dna_map_common.h"

#include <errno.h>
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

void dm_curve_free(DnaCurve *c) {
    free(c->pts);
    free(c->cpts);
    c->pts = NULL;
    c->cpts = NULL;
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
    fprintf(f, "force_pN,salt_M,base_pairs,status,points,last_turns,%shard_core_switched,"
               "instability_finding,instability_turns,instability_torque_pN_nm,"
               "coexistence_finding,coexistence_turns,coexistence_torque_straight_pN_nm,"
               "coexistence_torque_plectoneme_pN_nm,coexistence_extension_jump_nm,"
               "plateau_finding,plateau_torque_pN_nm,plateau_torque_min_pN_nm,plateau_torque_max_pN_nm,"
               "slope_nm_per_turn,plateau_turns_from,plateau_turns_to,"
               "superhelix_finding,superhelix_radius_nm,superhelix_turns\n",
            with_seconds ? "seconds," : "");
    for (int k = 0; k < n; ++k) {
        const DnaCurve *c = &cs[k];
        const RodkitSupercoilCurveInfo *s = &c->sum;
        int ok = c->status >= 0;
        fprintf(f, "%g,%g,%lld,%d,%lld,", c->force, c->salt, (long long)c->bp, (int)c->status, (long long)c->points);
        if (ok && c->points > 0) fprintf(f, "%.10g,", c->pts[c->points - 1].turns);
        else fprintf(f, ",");
        if (with_seconds) fprintf(f, "%.4g,", c->seconds);
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
        fprintf(f, "\n");
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

int dm_write_svg(const char *path, int which, const DnaCurve *cs, int n, const double *forces, int nf,
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
    return dm_commit(f, tmp, path);
}

void dm_print_table(const DnaCurve *cs, int n) {
    printf("#  F/pN  salt/M  pts  last_turns   s  | buckling turns torque | coexistence turns  tq_s   tq_p  jump/nm | plateau tq  "
           "dz/dn nm/turn | radius/nm\n");
    for (int k = 0; k < n; ++k) {
        const DnaCurve *c = &cs[k];
        const RodkitSupercoilCurveInfo *s = &c->sum;
        if (c->status < 0) {
            printf("  %5g %6g  failed (%s)\n", c->force, c->salt, rodkit_status_string(c->status));
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
        if (dm_has_value(s->superhelix_finding)) printf(" %6.3f\n", s->superhelix_radius);
        else printf(" %s\n", dm_finding(s->superhelix_finding));
    }
}

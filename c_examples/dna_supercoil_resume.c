/*
 * Progress, stop and resume of the DNA supercoiling run from C (issue 18):
 * the scene of c_dna_supercoil (300 bp by default) run once without a
 * callback, then with a progress callback (the rod continuation's
 * RodkitBranchCallback) that prints each point and stops the run after k
 * points - RODKIT_STATUS_INFO_CANCELLED, the path so far in the handle -
 * then rodkit_supercoil_resume completes it. Prints "name = value" lines:
 * the statuses, the points told and kept, and the largest difference
 * between the resumed and the uninterrupted path (0 when the stop was on
 * the buckled branch; the straight branch resumes to the Newton tolerance).
 * Usage: c_dna_supercoil_resume [base pairs] [elements] [max steps] [k]
 * (defaults 300, 30, 25, 20).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "rodkit.h"

static int fail(int32_t st, const char *what) {
    fprintf(stderr, "%s failed: %s (%d): %s\n", what, rodkit_status_string(st), (int)st, rodkit_last_error_message());
    return 1;
}

/* What the callback keeps: points told, when to stop, whether they came
 * in order (progress->points counting 1, 2, ...). */
struct watch {
    int64_t told;
    int64_t stop_after;
    int in_order;
};

static int32_t on_point(const RodkitBranchProgress *p, void *user_data) {
    struct watch *w = user_data;
    w->told += 1;
    if (p->points != w->told) w->in_order = 0;
    printf("# point %lld: branch %d, %.6f turns, extension %.4f nm, torque %.4f pN nm\n", (long long)p->points,
           (int)p->branch, p->turns, p->extension, p->torque);
    return w->told == w->stop_after;
}

static RodkitSupercoilPoint *points_of(const RodkitSupercoil *run, int64_t *count) {
    RodkitSupercoilInfo info;
    if (rodkit_supercoil_summary(run, &info) < 0) return NULL;
    RodkitSupercoilPoint *pts = malloc(sizeof *pts * (size_t)info.points);
    if (pts && rodkit_supercoil_points(run, pts, info.points, count) < 0) {
        free(pts);
        return NULL;
    }
    return pts;
}

int main(int argc, char **argv) {
    RodkitDnaSupercoilSpec spec;
    int32_t st = rodkit_dna_supercoil_spec_default(&spec);
    if (st < 0) return fail(st, "rodkit_dna_supercoil_spec_default");
    spec.base_pairs = argc > 1 ? atoll(argv[1]) : 300;
    spec.elements = argc > 2 ? atoll(argv[2]) : 30;
    spec.max_steps = argc > 3 ? atoll(argv[3]) : 25;
    spec.max_turns = 2.5;
    struct watch w = {0, argc > 4 ? atoll(argv[4]) : 20, 1};

    RodkitSupercoil *whole = NULL, *run = NULL;
    int32_t st_whole = rodkit_dna_supercoil_run(&spec, &whole);
    if (st_whole < 0) return fail(st_whole, "rodkit_dna_supercoil_run");
    st = rodkit_dna_supercoil_run_with(&spec, on_point, &w, &run);
    if (st < 0) return fail(st, "rodkit_dna_supercoil_run_with");
    int32_t stop = -1;
    if (rodkit_supercoil_stop(run, &stop) < 0) return fail(-1, "rodkit_supercoil_stop");
    int64_t kept = 0;
    RodkitSupercoilPoint *part = points_of(run, &kept);
    if (!part) return fail(-1, "rodkit_supercoil_points");
    printf("cancel_status = %d\ncancelled_stop = %d\ncancelled_points = %lld\ncancelled_branch = %d\n", (int)st,
           (int)stop, (long long)kept, kept > 0 ? (int)part[kept - 1].branch : -1);
    free(part);

    w.stop_after = 0; /* never again */
    st = rodkit_supercoil_resume(run, on_point, &w);
    if (st < 0) return fail(st, "rodkit_supercoil_resume");
    if (rodkit_supercoil_stop(run, &stop) < 0) return fail(-1, "rodkit_supercoil_stop");
    int64_t n = 0, n_whole = 0;
    RodkitSupercoilPoint *pts = points_of(run, &n), *ref = points_of(whole, &n_whole);
    if (!pts || !ref) return fail(-1, "rodkit_supercoil_points");
    double worst = n == n_whole ? 0.0 : INFINITY;
    for (int64_t i = 0; i < n && n == n_whole; i++) {
        double d[4][2] = {{pts[i].turns, ref[i].turns},
                          {pts[i].extension, ref[i].extension},
                          {pts[i].torque, ref[i].torque},
                          {pts[i].writhe, ref[i].writhe}};
        for (int k = 0; k < 4; k++) {
            double r = fabs(d[k][0] - d[k][1]) / fmax(fabs(d[k][1]), 1.0);
            /* A NaN difference must show and stay, not read as 0 (`r > worst` is false for NaN). */
            if (isnan(r) || r > worst) worst = r;
        }
    }
    printf("uninterrupted_status = %d\nresumed_status = %d\nresumed_stop = %d\n", (int)st_whole, (int)st, (int)stop);
    printf("uninterrupted_points = %lld\nresumed_points = %lld\ntold_points = %lld\ntold_in_order = %d\n",
           (long long)n_whole, (long long)n, (long long)w.told, w.in_order);
    printf("worst_relative_difference = %.3e\n", worst);
    /* The resumed path itself, in full precision, for a check that does
       not rest on this program's own comparison. */
    for (int64_t i = 0; i < n; i++)
        printf("resumed_turns_%lld = %.17g\nresumed_extension_%lld = %.17g\nresumed_torque_%lld = %.17g\n"
               "resumed_writhe_%lld = %.17g\n",
               (long long)i, pts[i].turns, (long long)i, pts[i].extension, (long long)i, pts[i].torque,
               (long long)i, pts[i].writhe);
    free(pts);
    free(ref);
    rodkit_supercoil_free(run);
    rodkit_supercoil_free(whole);
    return 0;
}

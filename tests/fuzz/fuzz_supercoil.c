/* Fuzz target: the supercoiling and equilibrium group (rodkit_dna_supercoil_*,
 * rodkit_supercoil_*, rodkit_equilibrium_*). See fuzz.h. */
#include "fuzz.h"

#define F(f) FUZZ_F(RodkitDnaSupercoilSpec, f)
#define I(f) FUZZ_I(RodkitDnaSupercoilSpec, f)
#define L(f) FUZZ_L(RodkitDnaSupercoilSpec, f)
static const struct fuzz_field spec_fields[] = {
    L(base_pairs), F(rise), F(tension), F(salt), F(charge_per_length), F(radius), F(bending_persistence),
    F(twist_persistence), F(temperature), F(permittivity), L(elements), L(stages), F(cutoff_tolerance), F(hard_core),
    L(threads), F(max_turns), L(max_steps), F(residual_tol), I(discrete_base_pairs), I(end_control),
};
static const struct fuzz_field eq_fields[] = {
    FUZZ_I(RodkitEquilibriumSpec, discrete_base_pairs), FUZZ_F(RodkitEquilibriumSpec, cutoff_tolerance),
    FUZZ_I(RodkitEquilibriumSpec, solver), FUZZ_F(RodkitEquilibriumSpec, residual_tol),
};

/* Progress callback: stops after *(int64_t *)user_data points (0: never);
 * a point told must be finite where the supercoiling run defines it. */
static int32_t stop_after(const RodkitBranchProgress *p, void *user_data) {
    int64_t *left = user_data;
    double v[] = {p->lambda, p->residual, p->tip_rotation, p->turns, p->extension, p->torque};
    fuzz_finite("rodkit_dna_supercoil_run_with", "progress", v, 6);
    if (p->branch != 0 && p->branch != 1) fuzz_violation("rodkit_dna_supercoil_run_with", "progress", "branch");
    return *left > 0 && --*left == 0;
}

/* Runs the spec, half the time stopped by the callback after a random
 * number of points and resumed: a stop is INFO_CANCELLED with a Cancelled
 * run, its resume neither cancelled nor failed where the run succeeds. */
static int32_t run_spec(const RodkitDnaSupercoilSpec *s, RodkitSupercoil **run) {
    if (fuzz_below(2) == 0) return rodkit_dna_supercoil_run(s, run);
    int64_t left = 1 + fuzz_below(4);
    const char *fn = "rodkit_dna_supercoil_run_with";
    int32_t st = fuzz_status(fn, rodkit_dna_supercoil_run_with(s, stop_after, &left, run));
    if (st != RODKIT_STATUS_INFO_CANCELLED) return st;
    int32_t stop = -1;
    if (fuzz_status("rodkit_supercoil_stop", rodkit_supercoil_stop(*run, &stop)) >= 0 &&
        stop != RODKIT_SUPERCOIL_STOP_CANCELLED)
        fuzz_violation("rodkit_supercoil_stop", "stop", "a cancelled run not reported Cancelled");
    left = 0;
    st = fuzz_status("rodkit_supercoil_resume", rodkit_supercoil_resume(*run, stop_after, &left));
    if (st == RODKIT_STATUS_INFO_CANCELLED)
        fuzz_violation("rodkit_supercoil_resume", "stop", "cancelled by a callback that never stops");
    if (st >= 0 && rodkit_supercoil_stop(*run, &stop) >= 0 && stop != RODKIT_SUPERCOIL_STOP_FINISHED)
        fuzz_violation("rodkit_supercoil_stop", "stop", "a resumed run not reported Finished");
    if (st < 0) { /* the handle stays valid after a failed resume: freed here */
        rodkit_supercoil_free(*run);
        *run = NULL;
    }
    return st;
}

static void fuzz_one(void) {
    RodkitDnaSupercoilSpec s;
    rodkit_dna_supercoil_spec_default(&s);
    s.base_pairs = 200, s.elements = 10, s.max_steps = 4, s.max_turns = 2.0;
    fuzz_perturb(&s, sizeof s, spec_fields, FUZZ_COUNT(spec_fields));
    /* Bound the work (valid but slow values are not findings). */
    if (s.base_pairs > 300 && s.base_pairs <= (1 << 24)) s.base_pairs = 300;
    if (s.elements > 12 && s.elements <= (1 << 18)) s.elements = 12;
    if (s.max_steps > 4 && s.max_steps <= (1 << 24)) s.max_steps = 4;
    if (s.threads > 2 && s.threads <= 256) s.threads = 2;
    if (getenv("FUZZ_TRACE"))
        fprintf(stderr, "  bp %lld rise %g F %g salt %g nu %g a %g A %g C %g T %g eps %g el %lld st %lld cut %g hc %g "
                "thr %lld turns %g steps %lld tol %g disc %d ctl %d\n", (long long)s.base_pairs, s.rise, s.tension,
                s.salt, s.charge_per_length, s.radius, s.bending_persistence, s.twist_persistence, s.temperature,
                s.permittivity, (long long)s.elements, (long long)s.stages, s.cutoff_tolerance, s.hard_core,
                (long long)s.threads, s.max_turns, (long long)s.max_steps, s.residual_tol, s.discrete_base_pairs,
                s.end_control);
    RodkitSupercoil *run = (RodkitSupercoil *)&s;
    if (fuzz_status("rodkit_dna_supercoil_run", run_spec(&s, &run)) < 0) {
        if (run) fuzz_violation("rodkit_dna_supercoil_run", "handle-on-failure", "*out not NULL after a failure");
        return;
    }
    RodkitSupercoilInfo info;
    if (fuzz_status("rodkit_supercoil_summary", rodkit_supercoil_summary(run, &info)) < 0 || info.points < 1) {
        rodkit_supercoil_free(run);
        return;
    }
    double v[] = {info.kappa, info.bjerrum_length, info.line_charge_squared};
    fuzz_finite("rodkit_supercoil_summary", "info", v, 3);
    int64_t count = 0, cap = info.points - fuzz_below(2);
    RodkitSupercoilPoint *pts = calloc((size_t)info.points + 1, sizeof *pts);
    memset(&pts[cap], 0x5a, sizeof *pts);
    if (fuzz_status("rodkit_supercoil_points", rodkit_supercoil_points(run, pts, cap, &count)) >= 0)
        for (int64_t i = 0; i < cap; i++) {
            double p[] = {pts[i].turns, pts[i].extension, pts[i].torque, pts[i].tension, pts[i].twist, pts[i].writhe};
            fuzz_finite("rodkit_supercoil_points", "point", p, 6);
        }
    unsigned char pat[sizeof *pts];
    memset(pat, 0x5a, sizeof pat);
    if (memcmp(&pts[cap], pat, sizeof pat) != 0)
        fuzz_violation("rodkit_supercoil_points", "overflow", "points written past capacity");
    free(pts);
    int64_t k = fuzz_below(3) == 0 ? fuzz_int(info.points - 1) : info.points - 1, ld = 3 + fuzz_below(2);
    size_t len = (size_t)(ld * (info.nodes - 1) + 3);
    double *xyz = fuzz_buffer(len);
    if (fuzz_status("rodkit_supercoil_positions", rodkit_supercoil_positions(run, k, xyz, ld, info.nodes)) >= 0) {
        for (int64_t i = 0; i < info.nodes; i++) fuzz_finite("rodkit_supercoil_positions", "xyz", xyz + ld * i, 3);
        fuzz_padding("rodkit_supercoil_positions", xyz, ld, 3, info.nodes);
    }
    fuzz_guard("rodkit_supercoil_positions", "xyz", xyz, len);
    if (fuzz_below(2) == 0) {
        RodkitEquilibriumSpec e;
        rodkit_equilibrium_spec_default(&e);
        fuzz_perturb(&e, sizeof e, eq_fields, FUZZ_COUNT(eq_fields));
        RodkitEquilibrium q;
        xyz = fuzz_buffer(len);
        const char *fn = "rodkit_supercoil_solve_point";
        if (fuzz_status(fn, rodkit_supercoil_solve_point(run, k, &e, &q, xyz, ld, info.nodes)) >= 0) {
            double o[] = {q.turns, q.extension, q.torque, q.tension, q.twist, q.writhe, q.residual, q.shift};
            fuzz_finite(fn, "equilibrium", o, FUZZ_COUNT(o));
            for (int64_t i = 0; i < info.nodes; i++) fuzz_finite(fn, "xyz", xyz + ld * i, 3);
        }
        fuzz_guard(fn, "xyz", xyz, len);
    }
    /* The equilibrium curve's summary and points (issue 18): every double
     * finite, every finding one of the four, no point past the capacity. */
    RodkitSupercoilCurveInfo ci;
    if (fuzz_status("rodkit_supercoil_curve_summary", rodkit_supercoil_curve_summary(run, &ci)) >= 0) {
        double c[] = {ci.instability_turns, ci.instability_torque, ci.coexistence_turns, ci.coexistence_torque_straight,
                      ci.coexistence_torque_plectoneme, ci.coexistence_extension_straight,
                      ci.coexistence_extension_plectoneme, ci.coexistence_extension_jump, ci.plateau_torque,
                      ci.plateau_torque_min, ci.plateau_torque_max, ci.slope, ci.plateau_turns_from, ci.plateau_turns_to,
                      ci.superhelix_radius, ci.strand_distance, ci.strand_s1, ci.strand_s2, ci.superhelix_turns};
        fuzz_finite("rodkit_supercoil_curve_summary", "summary", c, FUZZ_COUNT(c));
        int32_t f[] = {ci.instability_finding, ci.coexistence_finding, ci.plateau_finding, ci.superhelix_finding};
        for (size_t i = 0; i < FUZZ_COUNT(f); i++)
            if (f[i] < RODKIT_SUMMARY_FINDING_FOUND || f[i] > RODKIT_SUMMARY_FINDING_NOT_REACHED)
                fuzz_violation("rodkit_supercoil_curve_summary", "finding", "a finding outside RodkitSummaryFinding");
    }
    RodkitSupercoilCurvePoint *cp = calloc((size_t)info.points + 1, sizeof *cp);
    memset(&cp[cap], 0x5a, sizeof *cp);
    if (fuzz_status("rodkit_supercoil_curve_points", rodkit_supercoil_curve_points(run, cp, cap, &count)) >= 0)
        for (int64_t i = 0; i < cap; i++) {
            double p[] = {cp[i].turns, cp[i].extension, cp[i].torque, cp[i].energy};
            fuzz_finite("rodkit_supercoil_curve_points", "point", p, 4);
        }
    unsigned char cpat[sizeof *cp];
    memset(cpat, 0x5a, sizeof cpat);
    if (memcmp(&cp[cap], cpat, sizeof cpat) != 0)
        fuzz_violation("rodkit_supercoil_curve_points", "overflow", "points written past capacity");
    free(cp);
    rodkit_supercoil_free(run);
}

int main(int argc, char **argv) { return fuzz_main("supercoil", argc, argv); }

/* Fuzz target: the rod and branch group (rodkit_rod_*, rodkit_branch_*). See fuzz.h. */
#include "fuzz.h"

#define F(f) FUZZ_F(RodkitRodSpec, f)
#define I(f) FUZZ_I(RodkitRodSpec, f)
#define L(f) FUZZ_L(RodkitRodSpec, f)
static const struct fuzz_field spec_fields[] = {
    F(length), I(kirchhoff), F(bending1), F(bending2), F(twist), F(shear1), F(shear2), F(stretch),
    F(twist_stretch), F(bend_shear), F(intrinsic_u1), F(intrinsic_u2), F(intrinsic_u3), F(intrinsic_v1),
    F(intrinsic_v2), F(intrinsic_v3), I(supports), F(end_x), F(end_y), F(end_z), F(end_q0), F(end_q1), F(end_q2),
    F(end_q3), F(end_dx), F(end_dy), F(end_dz), F(end_tension), I(tip_force_frame), F(tip_force_x), F(tip_force_y),
    F(tip_force_z), I(tip_moment_frame), F(tip_moment_x), F(tip_moment_y), F(tip_moment_z),
    I(distributed_force_frame), F(distributed_force_x), F(distributed_force_y), F(distributed_force_z),
    I(distributed_couple_frame), F(distributed_couple_x), F(distributed_couple_y), F(distributed_couple_z), I(scheme),
    L(stages), L(elements), F(diameter),
};
#undef F
#undef I
#undef L
#define F(f) FUZZ_F(RodkitContinuationOptions, f)
#define I(f) FUZZ_I(RodkitContinuationOptions, f)
#define L(f) FUZZ_L(RodkitContinuationOptions, f)
static const struct fuzz_field option_fields[] = {
    I(method), L(anm_order), F(anm_epsilon), F(target_lambda), F(lambda_min), F(lambda_max), L(max_steps),
    F(residual_tol), F(initial_step), F(min_step), F(max_step), I(detect_bifurcations), F(bifurcation_tol),
    I(increasing), I(anm_pade),
};

static RodkitRodSpec base_spec(int which) {
    RodkitRodSpec s;
    rodkit_rod_spec_default(&s);
    s.length = 1.0;
    s.bending1 = 1.0, s.bending2 = 1.2, s.twist = 0.8, s.shear1 = 1e4, s.shear2 = 1e4, s.stretch = 2e4;
    s.stages = 2, s.elements = 3;
    if (which == 0) { /* cantilever, follower moment and dead loads */
        s.tip_moment_frame = RODKIT_LOAD_FRAME_FOLLOWER, s.tip_moment_x = 1.0;
        s.distributed_force_frame = RODKIT_LOAD_FRAME_DEAD, s.distributed_force_y = 0.5;
    } else if (which == 1) { /* clamped, end moving */
        s.supports = RODKIT_ROD_SUPPORTS_CLAMPED;
        s.end_x = 0.0, s.end_y = 0.0, s.end_z = 1.0, s.end_dx = 0.1;
    } else if (which == 2) { /* twisted, Kirchhoff */
        s.supports = RODKIT_ROD_SUPPORTS_TWISTED, s.kirchhoff = 1, s.end_tension = 1.0;
    } else { /* pinned under an axial force, midpoint, with a diameter */
        s.supports = RODKIT_ROD_SUPPORTS_PINNED, s.scheme = RODKIT_ROD_SCHEME_MIDPOINT, s.diameter = 0.01;
        s.tip_force_frame = RODKIT_LOAD_FRAME_DEAD, s.tip_force_z = -1.0;
    }
    return s;
}

static void kernels(RodkitRod *rod, int64_t n) {
    double *x = fuzz_buffer((size_t)n);
    if (fuzz_status("rodkit_rod_straight_state", rodkit_rod_straight_state(rod, x, n)) < 0) {
        fuzz_guard("rodkit_rod_straight_state", "x", x, (size_t)n);
        return;
    }
    fuzz_finite("rodkit_rod_straight_state", "x", x, (size_t)n);
    if (fuzz_below(3) == 0) x[fuzz_below((int)n)] = fuzz_double(0.5);
    double lambda = fuzz_below(4) == 0 ? fuzz_double(0.3) : 0.3;
    double *r = fuzz_buffer((size_t)n);
    if (fuzz_status("rodkit_rod_residual", rodkit_rod_residual(rod, x, n, lambda, r)) >= 0)
        fuzz_finite("rodkit_rod_residual", "r", r, (size_t)n);
    fuzz_guard("rodkit_rod_residual", "r", r, (size_t)n);
    int64_t nnz = 0;
    if (fuzz_status("rodkit_rod_jacobian_pattern", rodkit_rod_jacobian_pattern(rod, NULL, NULL, 0, &nnz)) >= 0 &&
        nnz > 0 && nnz < 10000000) {
        int64_t *cp = malloc((size_t)(n + 1 + FUZZ_GUARD) * sizeof *cp), *ri = malloc((size_t)nnz * sizeof *ri);
        for (int i = 0; i < FUZZ_GUARD; i++) cp[n + 1 + i] = -77;
        if (fuzz_status("rodkit_rod_jacobian_pattern", rodkit_rod_jacobian_pattern(rod, cp, ri, nnz, &nnz)) >= 0)
            for (int i = 0; i < FUZZ_GUARD; i++)
                if (cp[n + 1 + i] != -77) fuzz_violation("rodkit_rod_jacobian_pattern", "overflow", "col_ptr");
        free(cp), free(ri);
        double *v = fuzz_buffer((size_t)nnz), *dl = fuzz_buffer((size_t)n);
        if (fuzz_status("rodkit_rod_jacobian", rodkit_rod_jacobian(rod, x, n, lambda, v, nnz, dl)) >= 0) {
            fuzz_finite("rodkit_rod_jacobian", "values", v, (size_t)nnz);
            fuzz_finite("rodkit_rod_jacobian", "d_lambda", dl, (size_t)n);
        }
        fuzz_guard("rodkit_rod_jacobian", "values", v, (size_t)nnz);
        fuzz_guard("rodkit_rod_jacobian", "d_lambda", dl, (size_t)n);
    }
    double y[13] = {0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0.5, 0, 0};
    if (fuzz_below(3) == 0) y[fuzz_below(13)] = fuzz_double(0.5);
    double *dy = fuzz_buffer(13);
    if (fuzz_status("rodkit_rod_rhs", rodkit_rod_rhs(rod, y, lambda, dy)) >= 0) fuzz_finite("rodkit_rod_rhs", "dy", dy, 13);
    fuzz_guard("rodkit_rod_rhs", "dy", dy, 13);
    fuzz_guard("rodkit_rod_straight_state", "x", x, (size_t)n);
}

static void branch(const RodkitRod *rod, int64_t n, int64_t nodes) {
    RodkitContinuationOptions o;
    rodkit_continuation_options_default(&o);
    o.target_lambda = 0.5, o.max_steps = 20;
    if (fuzz_below(2)) o.method = RODKIT_CONTINUATION_METHOD_NEWTON;
    fuzz_perturb(&o, sizeof o, option_fields, FUZZ_COUNT(option_fields));
    /* Bound the work: the step limit is the caller's (not a finding). */
    if (o.max_steps > 20) o.max_steps = 20;
    if (o.method == RODKIT_CONTINUATION_METHOD_ANM && o.anm_order > 20) o.anm_order = 20;
    RodkitBranch *b = (RodkitBranch *)&o;
    int32_t st = fuzz_status("rodkit_rod_continue", rodkit_rod_continue(rod, NULL, 0, 0.0, &o, NULL, NULL, &b));
    if (st < 0) {
        if (b) fuzz_violation("rodkit_rod_continue", "handle-on-failure", "*out not NULL after a failure");
        return;
    }
    RodkitBranchInfo info;
    if (fuzz_status("rodkit_branch_summary", rodkit_branch_summary(b, &info)) >= 0 && info.records > 0) {
        int64_t cap = info.records - fuzz_below(2), count = 0;
        RodkitBranchRecord *rec = calloc((size_t)info.records + 1, sizeof *rec);
        memset(&rec[cap], 0x5a, sizeof *rec);
        if (fuzz_status("rodkit_branch_records", rodkit_branch_records(b, rec, cap, &count)) >= 0)
            for (int64_t i = 0; i < cap; i++) {
                double v[] = {rec[i].lambda, rec[i].residual, rec[i].tip_x, rec[i].tip_y, rec[i].tip_z,
                              rec[i].base_force_x, rec[i].base_moment_z, rec[i].end_rotation};
                fuzz_finite("rodkit_branch_records", "record", v, FUZZ_COUNT(v));
            }
        unsigned char pat[sizeof *rec];
        memset(pat, 0x5a, sizeof pat);
        if (memcmp(&rec[cap], pat, sizeof pat) != 0)
            fuzz_violation("rodkit_branch_records", "overflow", "records written past capacity");
        free(rec);
        int64_t k = fuzz_below(3) == 0 ? fuzz_int(info.records - 1) : info.records - 1;
        double *x = fuzz_buffer((size_t)info.state_length);
        if (fuzz_status("rodkit_branch_state", rodkit_branch_state(b, k, x, info.state_length)) >= 0)
            fuzz_finite("rodkit_branch_state", "x", x, (size_t)info.state_length);
        fuzz_guard("rodkit_branch_state", "x", x, (size_t)info.state_length);
        int64_t ld = 3 + fuzz_below(2);
        double *xyz = fuzz_buffer((size_t)(ld * (nodes - 1) + 3));
        if (fuzz_status("rodkit_branch_positions", rodkit_branch_positions(b, rod, k, xyz, ld, nodes)) >= 0) {
            for (int64_t i = 0; i < nodes; i++) fuzz_finite("rodkit_branch_positions", "xyz", xyz + ld * i, 3);
            fuzz_padding("rodkit_branch_positions", xyz, ld, 3, nodes);
        }
        fuzz_guard("rodkit_branch_positions", "xyz", xyz, (size_t)(ld * (nodes - 1) + 3));
    }
    (void)n;
    rodkit_branch_free(b);
}

static void fuzz_one(void) {
    RodkitRodSpec s = base_spec(fuzz_below(4));
    fuzz_perturb(&s, sizeof s, spec_fields, FUZZ_COUNT(spec_fields));
    /* Bound the work: more elements are valid but slow (not a finding). */
    if (s.elements > 16 && s.elements <= (1 << 18)) s.elements = 16;
    RodkitRod *rod = (RodkitRod *)&s;
    if (fuzz_status("rodkit_rod_new", rodkit_rod_new(&s, &rod)) < 0) {
        if (rod) fuzz_violation("rodkit_rod_new", "handle-on-failure", "*out not NULL after a failure");
        return;
    }
    int64_t n = 0;
    if (fuzz_status("rodkit_rod_unknowns", rodkit_rod_unknowns(rod, &n)) >= 0 && n > 0) {
        kernels(rod, n);
        if (fuzz_below(4) == 0) branch(rod, n, s.elements + 1);
    }
    rodkit_rod_free(rod);
}

int main(int argc, char **argv) { return fuzz_main("rod", argc, argv); }

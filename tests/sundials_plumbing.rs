//! Plumbing tests of the test-only SUNDIALS wrapper (`tests/support/sundials.rs`)
//! on problems with closed-form answers, before the wrapper is used for the
//! cross-checks of physics.md §4. Nothing here touches rodkit itself.
//!
//! Run with `cargo test --features sundials --test sundials_plumbing`.
#![cfg(feature = "sundials")]

#[path = "support/sundials.rs"]
mod sundials;

use std::cell::RefCell;
use sundials::{
    ida_solve, kinsol_solve, Context, DenseColMajor, IdaOptions, InitialCondition, KinsolOptions, Strategy,
};

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

// ---------------------------------------------------------------------------
// KINSOL
// ---------------------------------------------------------------------------

/// Nonlinear 3×3 system with the exact root x* = (1, 2, 3), built by hand:
///   f1 = x1² + x2² + x3² − 14      (1 + 4 + 9 = 14)
///   f2 = x1 x2 x3 − 6              (1·2·3 = 6)
///   f3 = exp(x1 − 1) + x2 x3 − 7   (e⁰ + 6 = 7)
/// All three vanish exactly in floating point at x* (every term is exact).
/// The permutations of (1, 2, 3) also solve f1 = f2 = 0, but f3 ≠ 0 at all
/// of them except x* (e.g. (2, 1, 3): e + 3 ≠ 7).
fn residual3(x: &[f64], f: &mut [f64]) {
    f[0] = x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - 14.0;
    f[1] = x[0] * x[1] * x[2] - 6.0;
    f[2] = (x[0] - 1.0).exp() + x[1] * x[2] - 7.0;
}

/// Analytic Jacobian of `residual3`. At x*: J = [[2,4,6],[6,3,2],[1,3,2]],
/// det J = 50 and, by cofactors, J⁻¹ = [[0,10,−10],[−10,−2,32],[15,−2,−18]]/50,
/// so ‖J⁻¹‖∞ = 44/50 = 0.88: near x*, |x − x*|∞ ≤ 0.88 ‖F(x)‖∞ to first order.
fn jacobian3(x: &[f64], j: &mut DenseColMajor<'_>) {
    j[(0, 0)] = 2.0 * x[0];
    j[(0, 1)] = 2.0 * x[1];
    j[(0, 2)] = 2.0 * x[2];
    j[(1, 0)] = x[1] * x[2];
    j[(1, 1)] = x[0] * x[2];
    j[(1, 2)] = x[0] * x[1];
    j[(2, 0)] = (x[0] - 1.0).exp();
    j[(2, 1)] = x[2];
    j[(2, 2)] = x[1];
}

const ROOT3: [f64; 3] = [1.0, 2.0, 3.0];
/// A start well away from x* (‖F‖∞ = 2.14) from which plain Newton converges.
const START3: [f64; 3] = [1.3, 1.7, 3.4];
/// Function-norm tolerance: with ‖J⁻¹‖∞ = 0.88 it bounds |x − x*|∞ by
/// ≈ 0.9e−13, so a relative error ≤ 1e−12 on each component (|x*_i| ≥ 1)
/// leaves a margin of ten.
const FTOL3: f64 = 1e-13;
const ROOT_RTOL: f64 = 1e-12;

fn assert_root3(x: &[f64]) {
    for i in 0..3 {
        let rel = (x[i] - ROOT3[i]).abs() / ROOT3[i].abs();
        assert!(rel <= ROOT_RTOL, "component {i}: x = {:.17e}, exact {}, rel. error {rel:e}", x[i], ROOT3[i]);
    }
    let mut f = [0.0; 3];
    residual3(x, &mut f);
    assert!(max_abs(&f) <= FTOL3, "‖F(x)‖∞ = {:e} > {FTOL3:e}", max_abs(&f));
}

fn opts(strategy: Strategy) -> KinsolOptions {
    KinsolOptions {
        strategy,
        func_norm_tol: FTOL3,
        scaled_step_tol: 1e-15,
        max_iters: 50,
        max_setup_calls: 1,
        ..KinsolOptions::default()
    }
}

#[test]
fn kinsol_exact_newton_analytic_jacobian_finds_exact_root() {
    let ctx = Context::new().unwrap();
    println!("SUNDIALS {}", sundials::sundials_version());
    for strategy in [Strategy::None, Strategy::LineSearch] {
        let mut x = START3;
        let mut jac = jacobian3;
        let stats = kinsol_solve(&ctx, &mut x, residual3, Some(&mut jac), &opts(strategy)).unwrap();
        println!("{strategy:?}: x = {x:?}, {stats:?}");
        assert_root3(&x);
        // Exact Newton: one Jacobian per iteration (max setup calls = 1),
        // none by difference quotients.
        assert_eq!(stats.jacobian_evals, stats.iterations);
        assert_eq!(stats.residual_evals_fd, 0);
        // Hand-run Newton from START3 reaches ‖F‖∞ < 1e−15 in 5 steps; a
        // quadratically convergent solver cannot need more than a handful.
        assert!((3..=8).contains(&stats.iterations), "iterations = {}", stats.iterations);
        assert!(stats.func_norm <= FTOL3 * 3f64.sqrt());
    }
}

/// The residual norms along plain Newton (KIN_NONE, analytic Jacobian: one
/// residual call per iterate) must fall quadratically: ‖F_{k+1}‖ ≤ C ‖F_k‖²
/// while above rounding level. The hand-run sequence from START3 is
/// 2.14, 0.272, 1.02e−2, 3.42e−5, 5.79e−10, ~1e−15, i.e. C ≤ 0.5; we allow
/// C = 1. Modified Newton (a stale Jacobian) contracts only linearly and
/// would fail this at the third step.
#[test]
fn kinsol_exact_newton_converges_quadratically() {
    let ctx = Context::new().unwrap();
    let norms = RefCell::new(Vec::new());
    let mut x = START3;
    let mut jac = jacobian3;
    let stats = kinsol_solve(
        &ctx,
        &mut x,
        |u, f| {
            residual3(u, f);
            norms.borrow_mut().push(max_abs(f));
        },
        Some(&mut jac),
        &opts(Strategy::None),
    )
    .unwrap();
    let norms = norms.into_inner();
    println!("‖F‖∞ history: {:?}", norms.iter().map(|r| format!("{r:.3e}")).collect::<Vec<_>>());
    assert_root3(&x);
    assert_eq!(norms.len() as i64, stats.iterations + 1, "one residual call per Newton iterate");
    let mut checked = 0;
    for w in norms.windows(2) {
        if w[1] > 1e-14 {
            assert!(w[1] <= w[0] * w[0], "not quadratic: {:e} -> {:e}", w[0], w[1]);
            checked += 1;
        }
    }
    assert!(checked >= 3, "too few pre-asymptotic steps to judge ({checked})");
}

#[test]
fn kinsol_exact_newton_finite_difference_jacobian_finds_exact_root() {
    let ctx = Context::new().unwrap();
    for strategy in [Strategy::None, Strategy::LineSearch] {
        let mut x = START3;
        let stats = kinsol_solve(&ctx, &mut x, residual3, None, &opts(strategy)).unwrap();
        println!("{strategy:?} (FD): x = {x:?}, {stats:?}");
        assert_root3(&x);
        // KINSOL's dense difference-quotient Jacobian: n = 3 residual calls
        // per Jacobian, one Jacobian per iteration.
        assert_eq!(stats.jacobian_evals, stats.iterations);
        assert_eq!(stats.residual_evals_fd, 3 * stats.jacobian_evals);
        assert_eq!(stats.residual_calls as i64, stats.residual_evals + stats.residual_evals_fd);
        // An O(√ε) Jacobian error only adds an O(√ε)·‖F‖ term per step.
        assert!((3..=8).contains(&stats.iterations), "iterations = {}", stats.iterations);
    }
}

/// `max_setup_calls` reaches KINSOL: with its own default (10, modified
/// Newton) it re-uses Jacobians, hence fewer Jacobians than iterations, and
/// it needs more iterations than exact Newton for the same tolerance.
#[test]
fn kinsol_modified_newton_reuses_the_jacobian() {
    let ctx = Context::new().unwrap();
    let mut jac = jacobian3;
    let mut x = START3;
    let exact = kinsol_solve(&ctx, &mut x, residual3, Some(&mut jac), &opts(Strategy::LineSearch)).unwrap();
    let mut x = START3;
    let modified = kinsol_solve(
        &ctx,
        &mut x,
        residual3,
        Some(&mut jac),
        &KinsolOptions { max_setup_calls: 10, ..opts(Strategy::LineSearch) },
    )
    .unwrap();
    println!("exact {exact:?}\nmodified {modified:?}");
    assert_root3(&x);
    assert!(modified.jacobian_evals < modified.iterations);
    assert!(modified.iterations > exact.iterations);
}

#[test]
fn kinsol_initial_guess_at_root_returns_at_once() {
    let ctx = Context::new().unwrap();
    let mut x = ROOT3;
    let stats = kinsol_solve(&ctx, &mut x, residual3, None, &opts(Strategy::LineSearch)).unwrap();
    assert_eq!(stats.flag_name, "KIN_INITIAL_GUESS_OK");
    assert_eq!(stats.iterations, 0);
    assert_eq!(x, ROOT3);
}

/// x² + 1 = 0 has no real root: the answer must be an `Err` (a status), never
/// a number. Starts: a generic point (Newton's map x ↦ (x² − 1)/(2x) is
/// chaotic, the line search stalls at the minimum of |F| at x = 0), and x = 0
/// itself (singular Jacobian at the start).
#[test]
fn kinsol_without_root_is_an_error() {
    let ctx = Context::new().unwrap();
    let no_root = |x: &[f64], f: &mut [f64]| f[0] = x[0] * x[0] + 1.0;
    let mut jac = |x: &[f64], j: &mut DenseColMajor<'_>| j[(0, 0)] = 2.0 * x[0];
    for strategy in [Strategy::None, Strategy::LineSearch] {
        for x0 in [0.7, 3.0, 0.0] {
            for analytic in [true, false] {
                let mut x = [x0];
                let o = KinsolOptions { max_iters: 100, ..opts(strategy) };
                let res = if analytic {
                    kinsol_solve(&ctx, &mut x, no_root, Some(&mut jac), &o)
                } else {
                    kinsol_solve(&ctx, &mut x, no_root, None, &o)
                };
                println!("{strategy:?}, x0 = {x0}, analytic J = {analytic}: {res:?}");
                let err = res.expect_err("x² + 1 = 0 has no real root");
                assert!(err.contains("KIN"), "error should name the KINSOL flag: {err}");
            }
        }
    }
}

#[test]
fn kinsol_panic_in_residual_is_an_error_not_an_abort() {
    let ctx = Context::new().unwrap();
    let mut calls = 0;
    let mut x = START3;
    let res = kinsol_solve(
        &ctx,
        &mut x,
        |u, f| {
            calls += 1;
            if calls == 3 {
                panic!("residual failed on purpose");
            }
            residual3(u, f);
        },
        None,
        &opts(Strategy::LineSearch),
    );
    let err = res.expect_err("a panicking residual must give Err");
    assert!(err.contains("residual failed on purpose"), "{err}");
    assert_eq!(calls, 3, "no residual call after the panic");
}

#[test]
fn kinsol_rejects_bad_input() {
    let ctx = Context::new().unwrap();
    let mut x: [f64; 0] = [];
    assert!(kinsol_solve(&ctx, &mut x, |_, _| {}, None, &KinsolOptions::default()).is_err());
    let mut x = START3;
    let o = KinsolOptions { u_scale: Some(vec![1.0, -1.0, 1.0]), ..KinsolOptions::default() };
    assert!(kinsol_solve(&ctx, &mut x, residual3, None, &o).is_err());
    let o = KinsolOptions { func_norm_tol: -1.0, ..KinsolOptions::default() };
    let err = kinsol_solve(&ctx, &mut x, residual3, None, &o).unwrap_err();
    assert!(err.contains("KINSetFuncNormTol") && err.contains("KIN_ILL_INPUT"), "{err}");
}

// ---------------------------------------------------------------------------
// IDA
// ---------------------------------------------------------------------------

/// Integration tolerances, and the accepted global error. IDA controls the
/// local error only; the global error of BDF at rtol = 1e−10 on these
/// O(1), non-stiff, stable problems is typically 1e−10–1e−9, so 1e−7 is a
/// safe bound that still catches any plumbing error (wrong sign, wrong time,
/// stale output).
const RTOL: f64 = 1e-10;
const ATOL: f64 = 1e-12;
const GLOBAL_TOL: f64 = 1e-7;
const T_OUT: [f64; 7] = [0.1, 0.5, 1.0, 2.0, 3.7, 5.0, 10.0];

fn ida_opts(ic: InitialCondition) -> IdaOptions {
    IdaOptions { rtol: RTOL, atol: ATOL, initial_condition: ic, ..IdaOptions::default() }
}

/// Linear semi-explicit index-1 DAE (a two-state exchange with conservation):
///   y1' = −a y1 + b y2,   0 = y1 + y2 − 1.
/// Eliminating y2: y1' = b − (a + b) y1, so (closed form)
///   y1(t) = y∞ + (y1(0) − y∞) e^{−(a+b)t},  y∞ = b/(a+b),  y2 = 1 − y1.
const A: f64 = 2.0;
const B: f64 = 1.0;

fn linear_dae(_t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) {
    r[0] = yp[0] + A * y[0] - B * y[1];
    r[1] = y[0] + y[1] - 1.0;
}

/// dF/dy + c_j dF/dy' of `linear_dae`.
fn linear_dae_jac(_t: f64, cj: f64, _y: &[f64], _yp: &[f64], j: &mut DenseColMajor<'_>) {
    j[(0, 0)] = cj + A;
    j[(0, 1)] = -B;
    j[(1, 0)] = 1.0;
    j[(1, 1)] = 1.0;
}

fn linear_exact(t: f64, y10: f64) -> [f64; 2] {
    let yinf = B / (A + B);
    let y1 = yinf + (y10 - yinf) * (-(A + B) * t).exp();
    [y1, 1.0 - y1]
}

fn linear_exact_dot(t: f64, y10: f64) -> [f64; 2] {
    let yinf = B / (A + B);
    let d = -(A + B) * (y10 - yinf) * (-(A + B) * t).exp();
    [d, -d]
}

fn max_error(sol: &sundials::IdaSolution, exact: impl Fn(f64) -> Vec<f64>) -> f64 {
    let mut e: f64 = 0.0;
    for (t, y) in sol.t.iter().zip(&sol.y) {
        let ex = exact(*t);
        for (a, b) in y.iter().zip(&ex) {
            e = e.max((a - b).abs() / b.abs().max(1.0));
        }
    }
    e
}

#[test]
fn ida_linear_dae_matches_closed_form() {
    let ctx = Context::new().unwrap();
    let y10 = 1.0;
    let y0 = linear_exact(0.0, y10);
    let yp0 = linear_exact_dot(0.0, y10);
    let id = [1.0, 0.0];
    for analytic in [true, false] {
        let mut jac = linear_dae_jac;
        let jac_arg: Option<&mut sundials::IdaJacobian<'_>> = if analytic { Some(&mut jac) } else { None };
        let sol =
            ida_solve(&ctx, 0.0, &y0, &yp0, &id, linear_dae, jac_arg, &ida_opts(InitialCondition::AsGiven), &T_OUT)
                .unwrap();
        let err = max_error(&sol, |t| linear_exact(t, y10).to_vec());
        println!("linear DAE, analytic J = {analytic}: max rel. error {err:e}, {:?}", sol.stats);
        assert_eq!(sol.t, T_OUT.to_vec(), "IDA_NORMAL returns at the requested times");
        assert!(err <= GLOBAL_TOL, "max error {err:e}");
        // y' is returned too: check it against the closed form as well.
        for (t, yp) in sol.t.iter().zip(&sol.yp) {
            let ex = linear_exact_dot(*t, y10);
            assert!((yp[0] - ex[0]).abs() <= 1e-6, "y1'({t}) = {} vs {}", yp[0], ex[0]);
        }
        assert!(sol.stats.steps > 0 && sol.stats.residual_evals > 0);
        if analytic {
            assert_eq!(sol.stats.residual_evals_fd, 0);
        } else {
            assert!(sol.stats.residual_evals_fd > 0);
        }
    }
}

/// `IDA_Y_INIT`: given y'(0), IDACalcIC computes y(0). For the linear DAE,
/// y1'(0) = b − (a + b) y1(0) ⇒ y1(0) = (b − y1'(0))/(a + b), y2 = 1 − y1.
#[test]
fn ida_calc_ic_y_init_recovers_y0_from_yp0() {
    let ctx = Context::new().unwrap();
    let y10 = 0.8;
    let yp0 = linear_exact_dot(0.0, y10);
    let wrong_y0 = [0.0, 0.0];
    let mut jac = linear_dae_jac;
    let sol = ida_solve(
        &ctx,
        0.0,
        &wrong_y0,
        &yp0,
        &[1.0, 0.0],
        linear_dae,
        Some(&mut jac),
        &ida_opts(InitialCondition::ComputeY),
        &T_OUT,
    )
    .unwrap();
    let ex0 = linear_exact(0.0, y10);
    println!("IDA_Y_INIT: y0 = {:?} (exact {ex0:?})", sol.y0);
    assert!(max_abs(&[sol.y0[0] - ex0[0], sol.y0[1] - ex0[1]]) <= 1e-9);
    let err = max_error(&sol, |t| linear_exact(t, y10).to_vec());
    assert!(err <= GLOBAL_TOL, "max error {err:e}");
}

/// Nonlinear semi-explicit index-1 DAE with a time-dependent coefficient:
///   y1' = y2,   0 = y2 + y2³ − (c + c³),   c = cos(t) y1.
/// z ↦ z + z³ is strictly increasing (derivative 1 + 3z² ≥ 1), so the
/// constraint has the unique root y2 = c and ∂F2/∂y2 ≠ 0 (index 1). Then
/// y1' = cos(t) y1, so (closed form) y1 = y1(0) e^{sin t}, y2 = cos(t) y1.
fn nonlinear_dae(t: f64, y: &[f64], yp: &[f64], r: &mut [f64]) {
    let c = t.cos() * y[0];
    r[0] = yp[0] - y[1];
    r[1] = y[1] + y[1].powi(3) - (c + c.powi(3));
}

fn nonlinear_dae_jac(t: f64, cj: f64, y: &[f64], _yp: &[f64], j: &mut DenseColMajor<'_>) {
    let c = t.cos() * y[0];
    j[(0, 0)] = cj;
    j[(0, 1)] = -1.0;
    j[(1, 0)] = -(1.0 + 3.0 * c * c) * t.cos();
    j[(1, 1)] = 1.0 + 3.0 * y[1] * y[1];
}

fn nonlinear_exact(t: f64, y10: f64) -> [f64; 2] {
    let y1 = y10 * t.sin().exp();
    [y1, t.cos() * y1]
}

/// Inconsistent start y = (1, 0), y' = (0, 0): the consistent values are
/// y2(0) = cos(0)·1 = 1 and y1'(0) = y2(0) = 1. IDA_YA_YDP_INIT must find
/// them (keeping the differential y1(0) = 1), then IDA must follow the
/// closed form.
#[test]
fn ida_nonlinear_dae_with_inconsistent_start_fixed_by_calc_ic() {
    let ctx = Context::new().unwrap();
    let y10 = 1.0;
    for analytic in [true, false] {
        let mut jac = nonlinear_dae_jac;
        let jac_arg: Option<&mut sundials::IdaJacobian<'_>> = if analytic { Some(&mut jac) } else { None };
        let sol = ida_solve(
            &ctx,
            0.0,
            &[y10, 0.0],
            &[0.0, 0.0],
            &[1.0, 0.0],
            nonlinear_dae,
            jac_arg,
            &ida_opts(InitialCondition::ComputeAlgebraicAndDerivatives),
            &T_OUT,
        )
        .unwrap();
        println!("nonlinear DAE, analytic J = {analytic}: y0 = {:?}, yp0 = {:?}, {:?}", sol.y0, sol.yp0, sol.stats);
        assert_eq!(sol.y0[0], y10, "IDA_YA_YDP_INIT keeps the differential component");
        assert!((sol.y0[1] - 1.0).abs() <= 1e-9, "y2(0) = {}", sol.y0[1]);
        assert!((sol.yp0[0] - 1.0).abs() <= 1e-9, "y1'(0) = {}", sol.yp0[0]);
        let err = max_error(&sol, |t| nonlinear_exact(t, y10).to_vec());
        println!("  max rel. error {err:e}");
        assert!(err <= GLOBAL_TOL, "max error {err:e}");
    }
}

#[test]
fn ida_panic_in_residual_is_an_error_not_an_abort() {
    let ctx = Context::new().unwrap();
    let y0 = linear_exact(0.0, 1.0);
    let yp0 = linear_exact_dot(0.0, 1.0);
    let res = ida_solve(
        &ctx,
        0.0,
        &y0,
        &yp0,
        &[1.0, 0.0],
        |t, y, yp, r| {
            if t > 0.5 {
                panic!("DAE residual failed on purpose");
            }
            linear_dae(t, y, yp, r);
        },
        None,
        &ida_opts(InitialCondition::AsGiven),
        &T_OUT,
    );
    let err = res.expect_err("a panicking residual must give Err");
    println!("{err}");
    assert!(err.contains("DAE residual failed on purpose") && err.contains("IDA_"), "{err}");
}

#[test]
fn ida_rejects_bad_input() {
    let ctx = Context::new().unwrap();
    let y0 = linear_exact(0.0, 1.0);
    let yp0 = linear_exact_dot(0.0, 1.0);
    let o = ida_opts(InitialCondition::AsGiven);
    let run =
        |id: &[f64], t_out: &[f64], o: &IdaOptions| ida_solve(&ctx, 0.0, &y0, &yp0, id, linear_dae, None, o, t_out);
    assert!(run(&[1.0, 0.0], &[1.0, 0.5], &o).is_err(), "non-monotone output times");
    assert!(run(&[1.0, 0.0], &[0.0, 1.0], &o).is_err(), "output at t0");
    assert!(run(&[1.0, 0.5], &[1.0], &o).is_err(), "id not 0/1");
    assert!(run(&[1.0], &[1.0], &o).is_err(), "id length");
    let err = run(&[1.0, 0.0], &[1.0], &IdaOptions { rtol: -1.0, ..o.clone() }).unwrap_err();
    assert!(err.contains("IDASStolerances") && err.contains("IDA_ILL_INPUT"), "{err}");
    // Too few steps allowed: IDA_TOO_MUCH_WORK, reported as Err.
    let err = run(&[1.0, 0.0], &[10.0], &IdaOptions { max_steps: 5, ..o }).unwrap_err();
    assert!(err.contains("IDA_TOO_MUCH_WORK"), "{err}");
}

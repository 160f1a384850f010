//! SUNDIALS cross-check of the Cosserat rod (physics.md §2, §4), of two
//! kinds: the KINSOL tests (1, the band solver, the other validation
//! branches) solve rodkit's own discrete residual with another solver —
//! they show an isolated root, not the right equations; the IDA test (2)
//! integrates the continuous ODEs, whose right-hand side `Rod::rhs` is
//! rodkit's but shares nothing with the collocation residual and its
//! Jacobian (the equations themselves are held to closed forms in
//! tests/rod_accuracy.rs and tests/rod_buckling.rs).
//!
//! 1. KINSOL (exact Newton: a Jacobian every iteration, the rod's own
//!    sparse Jacobian densified; explicit tolerances, scaled by the rod's
//!    equation and unknown scales) on the same discrete residual, from a
//!    perturbed start, at points of the follower-cantilever branch and of the
//!    post-buckled branch (with its phase condition): both sides at a scaled
//!    residual ≤ 1e−12, agreement ≈ the solver tolerance.
//! 2. IDA integrating the 13 ODEs in s (the same right-hand side,
//!    `Rod::rhs`) from the clamp with the base force and moment as shooting
//!    unknowns, KINSOL on the 6 tip conditions: the collocation solution
//!    differs from it by its discretisation error, which falls at the
//!    scheme's order (h⁴ for 2-stage Gauss–Legendre, h² for the midpoint).
//!
//! Run: `cargo test --release --features sundials --test sundials_rod -- --nocapture`
#![cfg(feature = "sundials")]

#[path = "support/rod_band.rs"]
mod rod_band;
#[path = "support/sundials.rs"]
mod sundials;

use rodkit::continuation::{Options, Problem};
use rodkit::rod::branch::Method;
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use sundials::{ida_solve, kinsol_problem_root as kinsol_root, kinsol_solve, Context, IdaOptions, KinsolOptions};

fn follower(scheme: Scheme, n: usize) -> Rod {
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let loads = Loads { tip_force: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
    Rod::new(law, 1.0, loads, Supports::Cantilever, scheme, n).unwrap()
}

/// rodkit's states at the given loads (targets reached in turn).
fn rodkit_states(rod: &Rod, alphas: &[f64]) -> Vec<Vec<f64>> {
    let mut out = vec![];
    let mut branch = None;
    for &a in alphas {
        let opts = Options { target_lambda: Some(a), residual_tol: 1e-12, max_step: 2.0, ..Default::default() };
        let b = match &branch {
            None => rod.continue_branch(None, 0.0, true, &opts, Method::Newton, |_| true).unwrap(),
            Some(b) => rod.resume_branch(b, &opts, Method::Newton, |_| true).unwrap(),
        };
        out.push(b.states.last().unwrap().clone());
        branch = Some(b);
    }
    out
}

fn scaled_difference(a: &[f64], b: &[f64], scales: &[f64]) -> f64 {
    a.iter().zip(b).zip(scales).map(|((p, q), s)| ((p - q) / s).abs()).fold(0.0, f64::max)
}

/// Deterministic perturbation of relative size `eps` in the unknowns' scales.
fn perturbed(x: &[f64], scales: &[f64], eps: f64) -> Vec<f64> {
    x.iter().zip(scales).enumerate().map(|(i, (v, s))| v + eps * s * (((i * 7919) % 97) as f64 / 48.5 - 1.0)).collect()
}

#[test]
fn kinsol_agrees_on_the_discrete_residual() {
    let ctx = Context::new().unwrap();
    // Follower cantilever, Gauss(4) × 8, α = 2, 5, 10.
    let rod = follower(Scheme::Gauss(4), 8);
    let alphas = [2.0, 5.0, 10.0];
    let states = rodkit_states(&rod, &alphas);
    for (x, &a) in states.iter().zip(&alphas) {
        let mut sys = rod.system().unwrap();
        let (us, _) = sys.unknown_scales();
        let root = kinsol_root(&ctx, &mut sys, a, &perturbed(x, &us, 1e-3));
        let d = scaled_difference(&root, x, &us);
        println!("follower α = {a}: KINSOL vs rodkit {d:e}");
        assert!(d < 1e-9, "α = {a}: {d:e}");
    }
    // Post-buckled clamped–free rod (phase condition and unfolding parameter
    // included): points of the branch after the switch.
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 300.0, 1000.0).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(2), 8).unwrap();
    let opts = Options {
        target_lambda: Some(3.0),
        initial_step: 0.2,
        max_step: 0.5,
        residual_tol: 1e-12,
        detect_bifurcations: true,
        ..Default::default()
    };
    let straight = rod.continue_branch(None, 0.0, true, &opts, Method::Newton, |_| true).unwrap();
    let opts = Options { residual_tol: 1e-12, max_step: 0.2, max_steps: 30, ..Default::default() };
    let buckled = rod.switch_branch(&straight, 0, 0, 0.05, &opts, Method::Newton, |_| true).unwrap();
    let (node, azimuth) = buckled.phase.unwrap();
    for k in [10, 20, 29] {
        let x = &buckled.states[k];
        let lambda = buckled.records[k].lambda;
        let mut sys = rod.system_with_phase(node, azimuth).unwrap();
        let (us, _) = sys.unknown_scales();
        let root = kinsol_root(&ctx, &mut sys, lambda, &perturbed(x, &us, 1e-4));
        let d = scaled_difference(&root, x, &us);
        println!("post-buckled Λ = {lambda:.4}: KINSOL vs rodkit {d:e}");
        assert!(d < 1e-9, "Λ = {lambda}: {d:e}");
    }
}

/// IDA shooting: integrate y' = f(y, Λ) from y(0) = (0, q = 1, n0, m0) to
/// s = L; KINSOL finds (n0, m0) so that n_b(L) = Λ(1, 0, 0), m_b(L) = 0.
fn shoot(ctx: &Context, rod: &Rod, lambda: f64, guess: [f64; 6]) -> Vec<f64> {
    let ida = IdaOptions { rtol: 1e-13, atol: 1e-14, ..Default::default() };
    let integrate = |nm: &[f64]| -> Vec<f64> {
        let mut y0 = vec![0.0; 13];
        y0[3] = 1.0;
        y0[7..13].copy_from_slice(nm);
        let yp0 = rod.rhs(&y0, lambda).to_vec();
        let residual = |_t: f64, y: &[f64], yp: &[f64], r: &mut [f64]| {
            let f = rod.rhs(y, lambda);
            for k in 0..13 {
                r[k] = yp[k] - f[k];
            }
        };
        let sol =
            ida_solve(ctx, 0.0, &y0, &yp0, &[1.0; 13], residual, None, &ida, &[rod.length]).expect("IDA integrates");
        sol.y[0].clone()
    };
    let mut u = guess.to_vec();
    let tip_residual = |u: &[f64], f: &mut [f64]| {
        let y = integrate(u);
        f[0] = y[7] - lambda;
        f[1] = y[8];
        f[2] = y[9];
        f[3..6].copy_from_slice(&y[10..13]);
    };
    // IDA's own tolerance (1e−13) bounds what the tip conditions can reach.
    let opts = KinsolOptions { func_norm_tol: 1e-10, scaled_step_tol: 1e-15, max_setup_calls: 1, ..Default::default() };
    kinsol_solve(ctx, &mut u, tip_residual, None, &opts).expect("shooting converges");
    integrate(&u)
}

#[test]
fn ida_shooting_bounds_the_collocation_error_at_the_scheme_order() {
    let ctx = Context::new().unwrap();
    let lambda = 5.0;
    let fine = follower(Scheme::Gauss(4), 16);
    let x = &rodkit_states(&fine, &[lambda])[0];
    let y0 = fine.node_state(x, 0);
    // Start 2 % off the collocation solution's base force and moment, so
    // the shooting root owes nothing to it but the basin.
    let guess = [y0[7] * 1.02, y0[8] + 0.02, y0[9] * 0.98, y0[10] + 0.02, y0[11] * 1.02, y0[12] + 0.02];
    let shot = shoot(&ctx, &fine, lambda, guess);
    let q2: f64 = shot[3..7].iter().map(|v| v * v).sum();
    println!("IDA shooting tip {:?}, |q|² − 1 = {:e}", &shot[0..3], q2 - 1.0);
    let tip_err = |rod: &Rod| {
        let x = &rodkit_states(rod, &[lambda])[0];
        let t = rod.tip(x);
        ((t[0] - shot[0]).powi(2) + (t[1] - shot[1]).powi(2) + (t[2] - shot[2]).powi(2)).sqrt()
    };
    // The converged collocation agrees with shooting to IDA's tolerance.
    let e_fine = tip_err(&fine);
    assert!(e_fine < 1e-9, "Gauss(4) × 16 vs IDA shooting: {e_fine:e}");
    for (scheme, ns, order) in [(Scheme::Gauss(2), [4usize, 8, 16], 4.0), (Scheme::Midpoint, [16, 32, 64], 2.0)] {
        let errs: Vec<f64> = ns.iter().map(|&n| tip_err(&follower(scheme, n))).collect();
        let rate = (errs[1] / errs[2]).log2();
        println!("{scheme:?}: tip differences {errs:?}, rate {rate:.2}");
        assert!((rate - order).abs() < 0.3, "{scheme:?}: rate {rate} ({errs:?})");
    }
}

/// KINSOL with the band solver (the wrapper the rod benchmark times as a
/// peer) on the rod's discrete residual: from the α = 4.75 state to α = 5,
/// agreeing with rodkit's continuation at α = 5 to 1e−9 (scaled max norm).
#[test]
fn kinsol_band_solver_on_the_rod() {
    use sundials::kinsol_solve_band;
    let ctx = Context::new().unwrap();
    let rod = follower(Scheme::Gauss(2), 8);
    let states = rodkit_states(&rod, &[4.75, 5.0]);
    let sys = rod.system().unwrap();
    let n = sys.dim();
    let pattern = sys.pattern().clone();
    let (order, upper, lower) = rod_band::band_layout(&pattern);
    assert!(upper + lower < n / 4, "not banded: {upper} + {lower} of {n}");
    let mut position = vec![0; n];
    for (new, &old) in order.iter().enumerate() {
        position[old] = new;
    }
    let eq = sys.equation_scales();
    let (us, _) = sys.unknown_scales();
    let sys = std::cell::RefCell::new(sys);
    let lambda = 5.0;
    let residual = |u: &[f64], f: &mut [f64]| {
        let mut r = vec![0.0; n];
        sys.borrow_mut().residual(u, lambda, &mut r);
        for i in 0..n {
            f[position[i]] = r[i];
        }
    };
    let mut vals = vec![0.0; pattern.nnz()];
    let mut dl = vec![0.0; n];
    let mut jac = |u: &[f64], m: &mut sundials::BandView| {
        sys.borrow_mut().jacobian(u, lambda, &mut vals, &mut dl);
        for j in 0..n {
            for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                let i = position[pattern.row_idx[k]];
                let inside = (j <= i + upper) && (i <= j + lower);
                if inside {
                    m.set(i, j, vals[k]);
                } else {
                    assert_eq!(vals[k], 0.0, "a non-zero outside the band at ({i}, {j})");
                }
            }
        }
    };
    let opts = KinsolOptions {
        func_norm_tol: 1e-12,
        scaled_step_tol: 1e-16,
        max_setup_calls: 1,
        u_scale: Some(us.iter().map(|s| 1.0 / s).collect()),
        f_scale: Some(order.iter().map(|&i| 1.0 / eq[i]).collect()),
        ..Default::default()
    };
    let mut x = states[0].clone();
    let stats =
        kinsol_solve_band(&ctx, &mut x, residual, &mut jac, upper, lower, &opts).expect("KINSOL band converges");
    let d = scaled_difference(&x, &states[1], &us);
    println!("band KINSOL: {} iterations, difference {d:e}, bandwidths {upper}/{lower} of n = {n}", stats.iterations);
    assert!(d < 1e-9, "{d:e}");
}

/// KINSOL (exact Newton, explicit tolerances, rodkit's Jacobian) on the same
/// discrete residual at points of the other validation branches (physics.md
/// §4): the pure end moment (half ring and closed ring), the transverse dead
/// tip load (α = 1), the hemitropic rod pulled (twist–stretch coupling), the
/// constrained Kirchhoff rod under controlled end rotation past its first
/// bifurcation (a non-planar buckled point) — each started 1e−3 (scaled)
/// off rodkit's point and converging back to it within 1e−9.
#[test]
fn kinsol_on_the_other_validation_branches() {
    let ctx = Context::new().unwrap();
    let check = |label: &str, rod: &Rod, x: &[f64], lambda: f64| {
        let mut sys = rod.system().unwrap();
        let (us, _) = sys.unknown_scales();
        let root = kinsol_root(&ctx, &mut sys, lambda, &perturbed(x, &us, 1e-3));
        let d = scaled_difference(&root, x, &us);
        println!("{label} Λ = {lambda}: KINSOL vs rodkit {d:e}");
        assert!(d < 1e-9, "{label} Λ = {lambda}: {d:e}");
    };
    let iso = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    // Pure end moment M = Λ·K_b/L (follower about d1): Λ = π half ring, 2π ring.
    let loads = Loads { tip_moment: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
    let rod = Rod::new(iso.clone(), 1.0, loads, Supports::Cantilever, Scheme::Gauss(3), 8).unwrap();
    let pi = std::f64::consts::PI;
    for (x, l) in rodkit_states(&rod, &[pi, 2.0 * pi]).iter().zip([pi, 2.0 * pi]) {
        check("pure end moment", &rod, x, l);
    }
    // Transverse dead tip load α = 1.
    let loads = Loads { tip_force: Some(Load::dead([1.0, 0.0, 0.0])), ..Default::default() };
    let rod = Rod::new(iso, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 8).unwrap();
    check("transverse dead load", &rod, &rodkit_states(&rod, &[1.0])[0], 1.0);
    // Hemitropic rod pulled along its axis (g couples stretch and twist).
    let law = RodLaw::hemitropic(200.0, 300.0, 500.0, 1000.0, -90.0, 0.0).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, 10.0])), ..Default::default() };
    let rod = Rod::new(law, 2.0, loads, Supports::Cantilever, Scheme::Gauss(2), 4).unwrap();
    check("hemitropic pulled", &rod, &rodkit_states(&rod, &[1.0])[0], 1.0);
    // Kirchhoff rod, controlled end rotation with tension: a point of the
    // non-planar branch switched onto at the first bifurcation.
    let law = RodLaw::kirchhoff(1.0, 1.3, 4.0).unwrap();
    let rod = Rod::new(law, 1.0, Loads::default(), Supports::Twisted { tension: 1.0 }, Scheme::Gauss(2), 12).unwrap();
    let opts = Options {
        target_lambda: Some(0.99),
        residual_tol: 1e-12,
        initial_step: 0.2,
        max_step: 0.5,
        detect_bifurcations: true,
        ..Default::default()
    };
    let straight = rod.continue_branch(None, 0.0, true, &opts, Method::Newton, |_| true).unwrap();
    let opts = Options { residual_tol: 1e-12, max_step: 0.1, max_steps: 8, ..Default::default() };
    let b = rod.switch_branch(&straight, 0, 0, 0.05, &opts, Method::Newton, |_| true).unwrap();
    let k = b.records.len() - 1;
    check("Kirchhoff, end rotation (buckled)", &rod, &b.states[k], b.records[k].lambda);
}

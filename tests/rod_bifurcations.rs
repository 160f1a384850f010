//! Bifurcations on rod branches: every one located exactly once, none
//! invented, none dropped (issue 19).
//!
//! Greenhill's clamped–clamped rod (K_b = C = L = 1, no tension), turned by
//! its end rotation φ (Supports::Twisted, Λ = sin(φ/2), which returns to
//! every value: a branch's bifurcations cannot be told apart by Λ) or by
//! its end moment M (Supports::Torqued, Λ = M): on the straight branch
//! φ = ML/C, and linearising K_b w'''' − iM w''' = 0 (w = x + iy, w = w' = 0
//! at both ends; derivation in tests/rod_buckling.rs) gives the double
//! points at θ = ML/K_b with tan(θ/2) = θ/2 — θ = 8.987, 15.451, 21.808,
//! 28.132, 34.442, 40.743 below 44, and none at 2π, 4π, … where the
//! records' signed σ_min also turns sign (its singular vectors turn
//! orthogonal; σ_min stays ~1e-3).

use rodkit::continuation::anm::continue_anm;
use rodkit::continuation::bifurcation::Bifurcation;
use rodkit::continuation::newton::{continue_newton, Start};
use rodkit::continuation::{Branch, Options, Problem, Record, SeriesProblem, Stop};
use rodkit::linalg::sparse::Pattern;
use rodkit::rod::model::{unwrap_rotation, Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Loads, RodLaw};
use std::f64::consts::PI;

/// The first `n` roots θ_k = 2x_k of tan x = x (x_k in (kπ, kπ + π/2)),
/// by Newton from just below the asymptote.
fn greenhill_roots(n: usize) -> Vec<f64> {
    (1..=n)
        .map(|k| {
            let mut x = (k as f64 + 0.5) * PI - 0.05;
            for _ in 0..60 {
                x -= (x.tan() - x) / (1.0 / x.cos().powi(2) - 1.0);
            }
            2.0 * x
        })
        .collect()
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Control {
    Rotation,
    Moment,
}

/// The straight branch of Greenhill's rod (bending K_b and `k2`) to
/// φ = `phi_max`, with detection: the branch, its records' continuous
/// end rotations and each located point's.
struct Followed {
    branch: Branch,
    record_phi: Vec<f64>,
    bif_phi: Vec<f64>,
}

fn rod(control: Control, elements: usize, k2: f64) -> Rod {
    let law = RodLaw::kirchhoff(1.0, k2, 1.0).unwrap();
    let supports = match control {
        Control::Rotation => Supports::Twisted { tension: 0.0 },
        Control::Moment => Supports::Torqued { tension: 0.0 },
    };
    Rod::new(law, 1.0, Loads::default(), supports, Scheme::Gauss(4), elements).unwrap()
}

/// The straight branch's options: detection to 1e-9, residual 1e-10, to
/// M = `phi_max` under moment control (rotation control stops by φ).
fn options(control: Control, phi_max: f64) -> Options {
    Options {
        residual_tol: 1e-10,
        initial_step: 0.05,
        max_step: 1.0,
        max_steps: 5000,
        detect_bifurcations: true,
        bifurcation_tol: 1e-9,
        target_lambda: (control == Control::Moment).then_some(phi_max),
        ..Default::default()
    }
}

fn follow_with<P: SeriesProblem>(rod: &Rod, problem: &mut P, control: Control, anm: bool, phi_max: f64) -> Followed {
    straight_branch(rod, problem, &options(control, phi_max), anm, phi_max)
}

/// The straight branch from φ = 0 to φ = `phi_max` with `opts`.
fn straight_branch<P: SeriesProblem>(rod: &Rod, problem: &mut P, opts: &Options, anm: bool, phi_max: f64) -> Followed {
    let start = Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true };
    let observe = |x: &[f64], l: f64| vec![rod.end_rotation(x, l).unwrap()];
    // φ followed by continuity (a step turns the end by less than 2π).
    let mut last = 0.0;
    let progress = |r: &Record| {
        last = unwrap_rotation(last, r.outputs[0]);
        last < phi_max
    };
    let branch = if anm {
        continue_anm(problem, start, opts, &Default::default(), observe, progress).unwrap()
    } else {
        continue_newton(problem, start, opts, observe, progress).unwrap()
    };
    let mut record_phi = vec![];
    for r in &branch.records {
        let previous = record_phi.last().copied().unwrap_or(0.0);
        record_phi.push(unwrap_rotation(previous, r.outputs[0]));
    }
    let bif_phi = branch
        .bifurcations
        .iter()
        .map(|b: &Bifurcation| unwrap_rotation(record_phi[b.record], rod.end_rotation(&b.x, b.lambda).unwrap()))
        .collect();
    Followed { branch, record_phi, bif_phi }
}

fn follow(control: Control, elements: usize, anm: bool, k2: f64, phi_max: f64) -> Followed {
    let rod = rod(control, elements, k2);
    let mut sys = rod.system().unwrap();
    follow_with(&rod, &mut sys, control, anm, phi_max)
}

/// Each located point lies between the records it names (φ is monotone
/// on the straight branch).
fn assert_placed(f: &Followed, name: &str) {
    for (b, phi) in f.branch.bifurcations.iter().zip(&f.bif_phi) {
        let (lo, hi) = (f.record_phi[b.record], f.record_phi[b.record + 1]);
        assert!(
            lo - 1e-9 <= *phi && *phi <= hi + 1e-9,
            "{name}: φ {phi} not between records {} ({lo}, {hi})",
            b.record
        );
    }
}

/// Greenhill's first six double points, under both controls, on 8, 16 and
/// 32 elements, with `anm` or Newton continuation: each found once (no
/// Λ-based merging under rotation control, where Λ repeats), at the
/// closed-form θ within the mesh's error (Gauss(4): 8 elements 5e-3 at the
/// 6th root, 16: 4e-5, 32: 2e-7, relative; the error of the 6th root falls
/// ≥ 100× per halving, the scheme's order 8 — 2⁸ = 256), double, placed
/// between its records, nothing reported at 2πk, nothing unresolved.
fn greenhill_six_roots(control: Control, anm: bool) {
    let roots = greenhill_roots(6);
    let mut errors = vec![];
    for (elements, tol) in [(8, 5e-3), (16, 4e-5), (32, 2e-7)] {
        let f = follow(control, elements, anm, 1.0, 44.0);
        let name = format!("{control:?}, {elements} elements, ANM {anm}");
        let expected_stop = if control == Control::Moment { Stop::Target } else { Stop::Cancelled };
        assert_eq!(f.branch.stop, expected_stop, "{name}");
        assert!(f.branch.unresolved.is_empty(), "{name}: {:?}", f.branch.unresolved);
        assert_eq!(f.bif_phi.len(), 6, "{name}: located at φ = {:?}", f.bif_phi);
        for (phi, theta) in f.bif_phi.iter().zip(&roots) {
            assert!((phi - theta).abs() <= tol * theta, "{name}: φ {phi} against θ {theta}");
        }
        assert!(f.branch.bifurcations.iter().all(|b| b.multiplicity == 2), "{name}");
        for k in 1..=7 {
            let two_pi_k = 2.0 * PI * k as f64;
            assert!(f.bif_phi.iter().all(|p| (p - two_pi_k).abs() > 0.5), "{name}: a point at 2π·{k}");
        }
        assert_placed(&f, &name);
        errors.push((f.bif_phi[5] - roots[5]).abs());
        // Under rotation control the records' test function turned sign near
        // every 2πk too (the spurious changes this test guards against).
        if control == Control::Rotation {
            let flips = f
                .branch
                .records
                .windows(2)
                .filter(|w| w[0].smallest_singular_value.unwrap() * w[1].smallest_singular_value.unwrap() < 0.0)
                .count();
            assert!(flips >= 12, "{name}: {flips} test-function sign changes");
        }
    }
    assert!(errors[0] > 100.0 * errors[1] && errors[1] > 100.0 * errors[2], "{control:?}, ANM {anm}: {errors:?}");
}

#[test]
fn greenhill_rotation_control_newton() {
    greenhill_six_roots(Control::Rotation, false);
}

#[test]
fn greenhill_rotation_control_anm() {
    greenhill_six_roots(Control::Rotation, true);
}

#[test]
fn greenhill_moment_control_newton() {
    greenhill_six_roots(Control::Moment, false);
}

#[test]
fn greenhill_moment_control_anm() {
    greenhill_six_roots(Control::Moment, true);
}

/// Close roots: a rod without rotational symmetry (K_2 = 1.01 K_1, 1.05
/// K_1) splits each double point into two simple ones, 1 % and 5 % apart —
/// often inside one step. det B's signs at a bracket's ends then disagree
/// with the one point located there, and the second is searched beside it.
/// Checked: 12 simple points to φ = 44 with both engines; each pair between
/// the isotropic roots of K_1 and K_2 (θ_k and θ_k·K_2/K_1: the second
/// variation grows with the bending stiffness); every step's det B sign
/// change accounted for by the parity of the points located in it; the
/// engines within 1e-7 of each other and within 1e-4 of 32 elements.
#[test]
fn close_simple_roots_of_an_anisotropic_rod_are_each_found() {
    let roots = greenhill_roots(6);
    for k2 in [1.01, 1.05] {
        let reference = follow(Control::Rotation, 32, false, k2, 44.0);
        let mut engines = vec![];
        for anm in [false, true] {
            let f = follow(Control::Rotation, 16, anm, k2, 44.0);
            let name = format!("K2 {k2}, ANM {anm}");
            assert!(f.branch.unresolved.is_empty(), "{name}: {:?}", f.branch.unresolved);
            assert_eq!(f.bif_phi.len(), 12, "{name}: {:?}", f.bif_phi);
            assert!(f.branch.bifurcations.iter().all(|b| b.multiplicity == 1), "{name}");
            let mut sorted = f.bif_phi.clone();
            sorted.sort_by(f64::total_cmp);
            for (pair, theta) in sorted.chunks(2).zip(&roots) {
                for phi in pair {
                    assert!(
                        *theta - 1e-4 < *phi && *phi < theta * k2 + 1e-4,
                        "{name}: φ {phi} outside [{theta}, {}]",
                        theta * k2
                    );
                }
            }
            for (i, w) in f.branch.records.windows(2).enumerate() {
                let flipped = w[0].bordered_det_sign != w[1].bordered_det_sign;
                let located = f.branch.bifurcations.iter().filter(|b| b.record == i).count();
                assert_eq!(
                    flipped,
                    located % 2 == 1,
                    "{name}: records {i}–{}: det B flip {flipped}, {located} located",
                    i + 1
                );
            }
            assert_placed(&f, &name);
            let mut fine = reference.bif_phi.clone();
            fine.sort_by(f64::total_cmp);
            assert_eq!(fine.len(), 12, "K2 {k2}, 32 elements: {fine:?}");
            for (a, b) in sorted.iter().zip(&fine) {
                assert!((a - b).abs() < 1e-4 * b, "{name}: {a} against 32 elements' {b}");
            }
            engines.push(sorted);
        }
        for (a, b) in engines[0].iter().zip(&engines[1]) {
            assert!((a - b).abs() < 1e-7 * b, "K2 {k2}: Newton {a}, ANM {b}");
        }
    }
}

/// A location that fails is reported, not dropped: the rod's residual is
/// made NaN within 1e-3 of the first Greenhill moment (no record lands
/// there, the location's trial points do). The branch goes on, locates the
/// second point, and reports the first one's bracket as unresolved, with
/// the evidence (the test function's sign change) that asked for it.
#[test]
fn a_failed_location_is_reported_unresolved() {
    struct Poisoned<P: Problem> {
        inner: P,
        window: (f64, f64),
    }
    impl<P: Problem> Problem for Poisoned<P> {
        fn dim(&self) -> usize {
            self.inner.dim()
        }
        fn pattern(&self) -> &Pattern {
            self.inner.pattern()
        }
        fn residual(&mut self, x: &[f64], l: f64, r: &mut [f64]) {
            self.inner.residual(x, l, r);
            if l > self.window.0 && l < self.window.1 {
                r[0] = f64::NAN;
            }
        }
        fn jacobian(&mut self, x: &[f64], l: f64, jx: &mut [f64], jl: &mut [f64]) {
            self.inner.jacobian(x, l, jx, jl);
        }
        fn equation_scales(&self) -> Vec<f64> {
            self.inner.equation_scales()
        }
        fn unknown_scales(&self) -> (Vec<f64>, f64) {
            self.inner.unknown_scales()
        }
    }
    impl<P: SeriesProblem> SeriesProblem for Poisoned<P> {
        fn series_begin(&mut self, x0: &[f64], lambda0: f64, max_order: usize) {
            self.inner.series_begin(x0, lambda0, max_order)
        }
        fn series_order(&mut self, p: usize, xp: &[f64], lambda_p: f64, out: &mut [f64]) {
            self.inner.series_order(p, xp, lambda_p, out)
        }
    }
    let theta = greenhill_roots(2);
    let rod = rod(Control::Moment, 16, 1.0);
    let window = (theta[0] - 1e-3, theta[0] + 1e-3);
    let mut poisoned = Poisoned { inner: rod.system().unwrap(), window };
    let f = follow_with(&rod, &mut poisoned, Control::Moment, false, 20.0);
    assert_eq!(f.branch.stop, Stop::Target);
    assert!(f.branch.records.iter().all(|r| r.lambda <= window.0 || r.lambda >= window.1));
    assert_eq!(f.bif_phi.len(), 1, "{:?}", f.bif_phi);
    assert!((f.bif_phi[0] - theta[1]).abs() < 2e-5 * theta[1]);
    assert_eq!(f.branch.unresolved.len(), 1, "{:?}", f.branch.unresolved);
    let u = &f.branch.unresolved[0];
    assert!(u.lambdas.0 < theta[0] && theta[0] < u.lambdas.1, "{u:?}");
    assert!(u.test_function_change && !u.det_sign_change, "{u:?}");
    assert!(u.reason.contains("location failed"), "{}", u.reason);
}

/// The ANM's series bifurcation indicator μ(a) (continuation::indicator)
/// against today's σ_min monitoring alone, on Greenhill's rod (16
/// elements, both controls, to φ = 44 — six double points): the same six
/// points (within 1e-9 of each other, and of θ_k within the mesh's 4e-5);
/// with the indicator each location started in the short bracket around a
/// root of μ (the root within 1e-3 of the step of the point: the series
/// saw each one), the records' σ_min sign changes near 2πk (no singular
/// point: μ has no root there) dismissed without a search, and the branch
/// costs at most a third of the factorisations (measured: 468 → 123 under
/// rotation control, 455 → 105 under moment control).
#[test]
fn the_series_indicator_finds_greenhill_with_a_third_of_the_factorisations() {
    let roots = greenhill_roots(6);
    for control in [Control::Rotation, Control::Moment] {
        let rod = rod(control, 16, 1.0);
        let run = |indicator: bool| {
            let opts = Options { series_indicator: indicator, ..options(control, 44.0) };
            straight_branch(&rod, &mut rod.system().unwrap(), &opts, true, 44.0)
        };
        let (with, without) = (run(true), run(false));
        let name = format!("{control:?}");
        assert_eq!((with.bif_phi.len(), without.bif_phi.len()), (6, 6), "{name}");
        for (k, ((a, b), phi)) in
            with.branch.bifurcations.iter().zip(&without.branch.bifurcations).zip(&with.bif_phi).enumerate()
        {
            assert!((a.lambda - b.lambda).abs() < 1e-9, "{name}, point {k}: {} against {}", a.lambda, b.lambda);
            assert_eq!(a.multiplicity, 2);
            // The point's φ (continuous) against the closed form.
            assert!((phi - roots[k]).abs() < 4e-5 * roots[k], "{name}, point {k}: φ {phi}, θ {}", roots[k]);
        }
        let (c, c0) = (with.branch.counts, without.branch.counts);
        assert_eq!((c.series_located, c.locations), (6, 6), "{name}: {c:?}");
        assert!(c.series_dismissed >= 6, "{name}: {c:?}");
        assert!(with.branch.unresolved.is_empty(), "{name}: {:?}", with.branch.unresolved);
        assert!(
            3 * c.factorisations <= c0.factorisations,
            "{name}: {} factorisations against {}",
            c.factorisations,
            c0.factorisations
        );
        println!(
            "{name}: factorisations {} → {}, location factorisations {} → {}, dismissed {}",
            c0.factorisations,
            c.factorisations,
            c0.location_factorisations,
            c.location_factorisations,
            c.series_dismissed
        );
    }
}

/// The lean σ_min monitor (`Options::lean_monitor`, the default: σ_1 alone
/// settled, location trials from the last trial's vectors) against the
/// classic one (both Ritz values settled, fixed starts everywhere) on
/// Greenhill's straight branch to φ = 44, 16 elements, ANM, both
/// controls: the same six double points, each at the same φ within twice
/// the location tolerance (1e-9 in scaled arc length, ~1e-9 in φ here), in
/// fewer of the monitor's solves.
#[test]
fn the_lean_monitor_locates_the_classic_monitors_points() {
    for control in [Control::Rotation, Control::Moment] {
        let rod = rod(control, 16, 1.0);
        let run = |lean: bool| {
            let mut sys = rod.system().unwrap();
            let opts = Options { lean_monitor: lean, ..options(control, 44.0) };
            straight_branch(&rod, &mut sys, &opts, true, 44.0)
        };
        let (lean, classic) = (run(true), run(false));
        assert_eq!(lean.bif_phi.len(), 6, "{control:?}: {:?}", lean.bif_phi);
        assert_eq!(classic.bif_phi.len(), 6, "{control:?}: {:?}", classic.bif_phi);
        for (a, b) in lean.bif_phi.iter().zip(&classic.bif_phi) {
            assert!((a - b).abs() <= 2e-9 * b.max(1.0), "{control:?}: φ {a} (lean) against {b} (classic)");
        }
        assert!(lean.branch.bifurcations.iter().all(|b| b.multiplicity == 2), "{control:?}");
        let (ls, cs) = (lean.branch.counts.monitor_solves, classic.branch.counts.monitor_solves);
        println!("{control:?}: monitor solves lean {ls}, classic {cs}");
        assert!(ls < cs, "{control:?}: lean {ls} solves, classic {cs}");
    }
}

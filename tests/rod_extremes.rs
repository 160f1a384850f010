//! Numerical stability at the extremes (issue 4, item 10): stiffness ratios
//! EA/K_b, GA/K_b from 1e2 to 1e10, N = 10⁴ elements, follower loads to
//! α = 100, a start exactly at a bifurcation point, zero load, degenerate
//! stiffness. Every returned number is checked finite (never NaN).

use rodkit::continuation::anm::{continue_anm, AnmOptions};
use rodkit::continuation::newton::{continue_newton, Start};
use rodkit::continuation::{Branch, Options, Stop};
use rodkit::rod::branch::Method;
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use rodkit::Status;
use std::f64::consts::PI;

#[path = "support/euler.rs"]
mod euler;

fn all_finite(b: &Branch) -> bool {
    b.records.iter().all(|r| {
        r.lambda.is_finite() && r.residual.is_finite() && r.step.is_finite() && r.outputs.iter().all(|v| v.is_finite())
    }) && b.samples.iter().all(|s| s.residual.is_finite() && s.outputs.iter().all(|v| v.is_finite()))
        && b.resume.x.iter().all(|v| v.is_finite())
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Independent reference: the planar extensible, shearable cantilever under
/// a transverse dead tip force α (spatial x), K_b = L = 1 — θ' = m,
/// r' = v1 d1 + v3 d3 with n = (α, 0) constant, n1 = n·d1 = v1·GA,
/// n3 = n·d3 = (v3 − 1)·EA, m' = −(r'_z n_x − r'_x n_z), m(L) = 0; shooting
/// on m(0) by RK4 (20000 steps) and the secant method.
fn dead_load_tip(alpha: f64, ga: f64, ea: f64) -> [f64; 3] {
    let integrate = |m0: f64| -> [f64; 4] {
        let f = |y: [f64; 4]| -> [f64; 4] {
            let (s, c) = y[2].sin_cos();
            let (d1, d3) = ([c, -s], [s, c]);
            let (n1, n3) = (alpha * d1[0], alpha * d3[0]);
            let (v1, v3) = (n1 / ga, 1.0 + n3 / ea);
            let rp = [v1 * d1[0] + v3 * d3[0], v1 * d1[1] + v3 * d3[1]];
            [rp[0], rp[1], y[3], -(rp[1] * alpha)]
        };
        let steps = 20000;
        let h = 1.0 / steps as f64;
        let mut y = [0.0, 0.0, 0.0, m0];
        let add =
            |a: [f64; 4], b: [f64; 4], t: f64| [a[0] + t * b[0], a[1] + t * b[1], a[2] + t * b[2], a[3] + t * b[3]];
        for _ in 0..steps {
            let k1 = f(y);
            let k2 = f(add(y, k1, 0.5 * h));
            let k3 = f(add(y, k2, 0.5 * h));
            let k4 = f(add(y, k3, h));
            for i in 0..4 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        y
    };
    let (mut a, mut b) = (alpha * 0.8, alpha * 0.9);
    let (mut fa, mut fb) = (integrate(a)[3], integrate(b)[3]);
    for _ in 0..60 {
        if fb == fa || fb.abs() < 1e-15 {
            break;
        }
        let c = b - fb * (b - a) / (fb - fa);
        (a, fa) = (b, fb);
        b = c;
        fb = integrate(b)[3];
    }
    let y = integrate(b);
    [y[0], 0.0, y[1]]
}

/// EA/K_b = GA/K_b from 1e2 to 1e10 (K_b = 1): the transverse dead tip load
/// α = 1 by the ANM on Gauss(4) × 16 against the shooting reference at the
/// same EA, GA. The scaled formulation (positions by L, forces by K_b/L²)
/// keeps the stiff limit accurate: agreement within 1e-9 at every ratio,
/// with no ill-conditioning status needed; at 1e8 and 1e10 the tip is the
/// inextensible one (0.30172 L, 0.05643 L lateral… as in rod_basic) to
/// O(1/EA).
#[test]
fn stiffness_ratios_from_1e2_to_1e10() {
    for ratio in [1e2, 1e4, 1e6, 1e8, 1e10] {
        let law = RodLaw::isotropic(1.0, 1.0 / 1.3, ratio, ratio).unwrap();
        let loads = Loads { tip_force: Some(Load::dead([1.0, 0.0, 0.0])), ..Default::default() };
        let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 16).unwrap();
        let opts = Options { target_lambda: Some(1.0), residual_tol: 1e-11, max_step: 2.0, ..Default::default() };
        for method in [Method::Anm(AnmOptions::default()), Method::Newton] {
            let b = rod.continue_branch(None, 0.0, true, &opts, method, |_| true).unwrap();
            assert_eq!(b.stop, Stop::Target);
            assert!(b.states.iter().flatten().all(|v| v.is_finite()));
            let tip = rod.tip(b.states.last().unwrap());
            let reference = dead_load_tip(1.0, ratio, ratio);
            let e = dist(tip, reference);
            println!("EA = GA = {ratio:e} {method:?}: tip {tip:?}, shooting {reference:?}, difference {e:e}");
            assert!(e < 1e-9, "EA/K_b = {ratio:e}: {e:e}");
        }
    }
}

/// N = 10⁴ midpoint elements (130 013 unknowns): the pure end moment
/// M = Λ·2πK_b/L bends the cantilever into an arc of curvature 2πΛ/L
/// (n ≡ 0, so no stretch or shear): at Λ = 1/2 a half circle of radius
/// L/π with the tip at (2L/π, 0, 0). The midpoint rule's error is O(h²) ≈ (πh)²/12 ≈ 1e-9 here.
#[test]
fn ten_thousand_elements() {
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let loads = Loads { tip_moment: Some(Load::dead([0.0, 2.0 * PI, 0.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Midpoint, 10_000).unwrap();
    let opts = Options {
        target_lambda: Some(0.5),
        residual_tol: 1e-10,
        initial_step: 0.5,
        max_step: 1.0,
        ..Default::default()
    };
    let t = std::time::Instant::now();
    let b = rod.continue_branch(None, 0.0, true, &opts, Method::Newton, |_| true).unwrap();
    println!("N = 1e4, n = {}: {:?}, {:?}", rod.unknowns(), t.elapsed(), b.counts);
    assert_eq!(b.stop, Stop::Target);
    let tip = rod.tip(b.states.last().unwrap());
    let e = dist([tip[0].abs(), tip[1], tip[2]], [2.0 / PI, 0.0, 0.0]);
    println!("tip {tip:?}, half circle (2/π, 0, 0): difference {e:e}");
    assert!(e < 1e-8 && e.is_finite(), "{e:e}");
}

/// The engines' default step bounds (issue 19): the ANM's step is its
/// series' radius, not capped — the follower cantilever (Gauss(4) × 16,
/// α 0 → 100, P = 20, ε = 1e-10) takes ≤ 25 steps by default, some
/// longer than 5, against 118 under the old cap of 1, and ends at the same
/// tip (within 1e-9: both converged to residual 1e-10 on one
/// discretisation); Newton continuation keeps its bound of 1
/// (`NEWTON_MAX_STEP`) when `max_step` is left at ∞: the same records,
/// bitwise, as with max_step = 1.
#[test]
fn the_anm_steps_as_far_as_its_series_by_default() {
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let loads = Loads { tip_force: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 16).unwrap();
    let anm = AnmOptions { order: 20, epsilon: 1e-10, pade: false };
    let run = |opts: &Options, newton: bool| {
        let mut sys = rod.system().unwrap();
        let start = Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true };
        let b = if newton {
            continue_newton(&mut sys, start, opts, |_, _| vec![], |_| true).unwrap()
        } else {
            continue_anm(&mut sys, start, opts, &anm, |_, _| vec![], |_| true).unwrap()
        };
        assert_eq!(b.stop, Stop::Target);
        b
    };
    let defaults = Options { target_lambda: Some(100.0), residual_tol: 1e-10, max_steps: 3000, ..Default::default() };
    assert!(defaults.max_step.is_infinite());
    let free = run(&defaults, false);
    let capped = run(&Options { max_step: 1.0, ..defaults.clone() }, false);
    let steps = |b: &Branch| b.records.len() - 1;
    let longest = |b: &Branch| b.records.iter().map(|r| r.step).fold(0.0, f64::max);
    println!("ANM: {} steps (longest {:.2}) by default, {} capped at 1", steps(&free), longest(&free), steps(&capped));
    assert!(steps(&free) <= 25 && longest(&free) > 5.0, "{} steps, longest {}", steps(&free), longest(&free));
    assert!(steps(&capped) >= 100, "{} steps capped", steps(&capped));
    let (a, b) = (rod.tip(&free.resume.x), rod.tip(&capped.resume.x));
    assert!(dist(a, b) < 1e-9, "tips {a:?} vs {b:?}");
    // Newton: the default is its bound of 1, bitwise.
    let newton = run(&defaults, true);
    let newton_one = run(&Options { max_step: 1.0, ..defaults.clone() }, true);
    assert_eq!(newton.records, newton_one.records);
}

/// Review findings on the unbounded default: (1) an exactly linear path
/// (the straight cantilever under an axial dead load below buckling: the
/// series' terms past the first vanish, its radius is ∞) is stepped by
/// doubling, not at a = ∞ (which evaluated to NaN and stopped the branch
/// at its first point); the straight state is exact there (r_z = s, n =
/// −Λe3 at every node). (2) Newton with a first step above the default
/// bound of 1 (min 2, first 3) takes that as its bound (it panicked in
/// clamp).
#[test]
fn unbounded_defaults_on_a_linear_path_and_large_first_steps() {
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(2), 4).unwrap();
    let opts = Options { target_lambda: Some(2.0), residual_tol: 1e-12, ..Default::default() };
    let b = rod.continue_branch(None, 0.0, true, &opts, Method::Anm(AnmOptions::default()), |_| true).unwrap();
    assert_eq!(b.stop, Stop::Target, "{:?}", b.records.iter().map(|r| r.lambda).collect::<Vec<_>>());
    assert!(b.records.windows(2).all(|w| w[1].lambda > w[0].lambda));
    let last = b.states.last().unwrap();
    // Axial shortening of the extensible rod: r_z(L) = L(1 − Λ/EA).
    assert!((rod.tip(last)[2] - (1.0 - 2.0 / 2.6e4)).abs() < 1e-12, "{:?}", rod.tip(last));
    let big = Options { min_step: 2.0, initial_step: 3.0, target_lambda: Some(2.0), ..opts.clone() };
    assert_eq!(big.newton_max_step(), 3.0);
    let b = rod.continue_branch(None, 0.0, true, &big, Method::Newton, |_| true).unwrap();
    assert_eq!(b.stop, Stop::Target);
}

/// Follower load to α = 100 (the tip force perpendicular to the tip
/// tangent; the rod curls round on itself): ANM and Newton
/// agree with each other and with the converged finer discretisation
/// (Gauss(4) × 32 vs × 64: the coarse grid's error, printed, is what the
/// tolerance allows); |q| = 1 at every node.
#[test]
fn follower_load_to_alpha_100() {
    let rod = |n: usize| {
        let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
        let loads = Loads { tip_force: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
        Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), n).unwrap()
    };
    let opts = Options {
        target_lambda: Some(100.0),
        residual_tol: 1e-10,
        initial_step: 0.5,
        max_step: 5.0,
        max_steps: 3000,
        ..Default::default()
    };
    let solve = |r: &Rod, method: Method| {
        let mut sys = r.system().unwrap();
        let start = Start::Point { x: r.straight_state(), lambda: 0.0, increasing: true };
        let b = match method {
            Method::Anm(a) => continue_anm(&mut sys, start, &opts, &a, |_, _| vec![], |_| true).unwrap(),
            Method::Newton => continue_newton(&mut sys, start, &opts, |_, _| vec![], |_| true).unwrap(),
        };
        assert_eq!(b.stop, Stop::Target, "{method:?}");
        assert!(all_finite(&b));
        println!("{method:?}: {:?}", b.counts);
        b.resume.x
    };
    let coarse = rod(32);
    let xa = solve(&coarse, Method::Anm(AnmOptions { order: 20, epsilon: 1e-10, pade: false }));
    let xn = solve(&coarse, Method::Newton);
    let fine = rod(64);
    let xf = solve(&fine, Method::Newton);
    let (ta, tn, tf) = (coarse.tip(&xa), coarse.tip(&xn), fine.tip(&xf));
    println!("α = 100: ANM {ta:?}, Newton {tn:?}, × 64 {tf:?}; rotation {:.1}°", coarse.tip_rotation(&xa).to_degrees());
    // Same discrete equations within residual 1e-10: the engines agree to
    // the conditioning times that.
    assert!(dist(ta, tn) < 1e-8, "ANM vs Newton {:e}", dist(ta, tn));
    // Gauss(4) is 8th order: × 64 is 2^8 closer to the exact tip than × 32,
    // so their distance is × 32's error: measured 2.1e-9 at α = 100 (a tip
    // rotation of 145°); bound 1e-8, the measured value with a margin of 5.
    assert!(dist(tn, tf) < 1e-8, "× 32 vs × 64 {:e}", dist(tn, tf));
    for i in 0..=coarse.elements {
        let q = coarse.node_state(&xa, i);
        let norm = (q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6]).sqrt();
        assert!((norm - 1.0).abs() < 1e-12, "|q| − 1 = {:e} at node {i}", norm - 1.0);
    }
}

/// A start exactly at a bifurcation point (the located Euler load of the
/// clamped–free rod, straight state): the start's own correction at fixed Λ
/// meets a singular matrix. Either engine must return a clear result — a
/// branch with finite numbers (here: the straight branch, which stays
/// straight) or an error status — never NaN, never a hang.
#[test]
fn start_exactly_at_a_bifurcation_point() {
    let rod = euler::euler_cantilever(8);
    let opts = Options { target_lambda: Some(3.0), detect_bifurcations: true, max_step: 0.5, ..Default::default() };
    let straight = rod.continue_branch(None, 0.0, true, &opts, Method::Newton, |_| true).unwrap();
    let bif = &straight.bifurcations[0];
    // The discrete critical load: extensible Euler formula (physics §2.6).
    let a = 1.0 / 1e4 - 1.0 / 2.6e4;
    let pe = PI * PI / 4.0;
    let pcr = 2.0 * pe / (1.0 + (1.0 + 4.0 * a * pe).sqrt());
    assert!((bif.lambda - pcr).abs() < 1e-6 * pcr, "located {} vs {pcr}", bif.lambda);
    // A long bracket ending at the target (max step 1): regula falsi on σ_min
    // runs into the singular point itself, where the trial point's corrector
    // cannot converge; the location keeps its best point (regression: the
    // bifurcation was lost). Gauss(4) × 8 is within 1e-9 of the formula.
    for method in [Method::Newton, Method::Anm(AnmOptions::default())] {
        let b = rod.continue_branch(None, 0.0, true, &euler::straight_options(), method, |_| true).unwrap();
        assert_eq!(b.bifurcations.len(), 1, "{method:?}");
        assert!(
            (b.bifurcations[0].lambda - pcr).abs() < 1e-9 * pcr,
            "{method:?}: {} vs {pcr}",
            b.bifurcations[0].lambda
        );
    }
    for method in [Method::Newton, Method::Anm(AnmOptions::default())] {
        for increasing in [true, false] {
            let opts = Options { max_steps: 5, max_step: 0.2, ..Default::default() };
            match rod.continue_branch(Some(&bif.x), bif.lambda, increasing, &opts, method, |_| true) {
                Ok(b) => {
                    assert!(b.states.iter().flatten().all(|v| v.is_finite()));
                    assert!(b.records.iter().all(|r| r.lambda.is_finite() && r.residual.is_finite()));
                    for x in &b.states {
                        let tip = rod.tip(x);
                        assert!(
                            tip[0].hypot(tip[1]) < 1e-8,
                            "{method:?}: left the straight branch at a start on it: {tip:?}"
                        );
                    }
                    println!(
                        "{method:?} increasing {increasing}: {:?}, {} records to Λ {}",
                        b.stop,
                        b.records.len(),
                        b.records.last().unwrap().lambda
                    );
                }
                Err(e) => {
                    assert_eq!(e.status, Status::ErrNotConverged, "{}", e.message);
                    assert!(!e.message.is_empty());
                    println!("{method:?} increasing {increasing}: {}", e.message);
                }
            }
        }
    }
    // Leaving it along its null direction is the switch (Start::Switch):
    // the buckled branch, off the straight one.
    let opts = Options { target_lambda: Some(3.0), max_step: 0.2, ..Default::default() };
    let b = rod.switch_branch(&straight, 0, 0, 0.05, &opts, Method::Anm(AnmOptions::default()), |_| true).unwrap();
    assert_eq!(b.stop, Stop::Target);
    let tip = rod.tip(b.states.last().unwrap());
    assert!(tip[0].hypot(tip[1]) > 0.1, "did not buckle: {tip:?}");
}

/// Zero load: every Λ has the straight, stress-free state as its solution
/// (R_Λ = 0): both engines walk along Λ to the target with the straight state
/// exactly (the tip at (0, 0, L)) and finite records.
#[test]
fn zero_load() {
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let rod = Rod::new(law, 1.0, Loads::default(), Supports::Cantilever, Scheme::Gauss(2), 8).unwrap();
    let opts = Options {
        target_lambda: Some(2.0),
        max_step: 0.5,
        samples: vec![0.5, 1.5],
        detect_bifurcations: true,
        ..Default::default()
    };
    for method in [Method::Anm(AnmOptions::default()), Method::Newton] {
        let b = rod.continue_branch(None, 0.0, true, &opts, method, |_| true).unwrap();
        assert_eq!(b.stop, Stop::Target, "{method:?}");
        assert!(b.bifurcations.is_empty());
        assert_eq!(b.samples.len(), 2);
        for x in b.states.iter().chain(&b.sample_states) {
            assert!(dist(rod.tip(x), [0.0, 0.0, 1.0]) < 1e-14);
        }
        assert!(b.records.iter().all(|r| r.lambda.is_finite() && r.residual <= 1e-14));
    }
}

/// Degenerate stiffness is rejected by name, before any solve.
#[test]
fn degenerate_stiffness_rejected() {
    for (name, result) in [
        ("bending", RodLaw::isotropic(0.0, 1.0, 1.0, 1.0)),
        ("twist", RodLaw::isotropic(1.0, -1.0, 1.0, 1.0)),
        ("shear", RodLaw::isotropic(1.0, 1.0, f64::NAN, 1.0)),
        ("stretch", RodLaw::isotropic(1.0, 1.0, 1.0, f64::INFINITY)),
        ("bending2", RodLaw::kirchhoff(1.0, 0.0, 1.0)),
    ] {
        let e = result.unwrap_err();
        assert!(matches!(e.status, Status::ErrNotPositive | Status::ErrNotFinite), "{name}: {:?}", e.status);
        assert!(e.message.contains(name), "{name}: {}", e.message);
    }
    // Twist–stretch coupling with g² ≥ C·S: the 6×6 law is not positive definite.
    let e = RodLaw::hemitropic(1.0, 2.0, 100.0, 50.0, 10.0, 0.0).unwrap_err();
    assert_eq!(e.status, Status::ErrNotPositiveDefinite, "{}", e.message);
    // Bend–shear c2² ≥ K_b·G likewise.
    let e = RodLaw::hemitropic(1.0, 2.0, 4.0, 50.0, 0.0, 2.0).unwrap_err();
    assert_eq!(e.status, Status::ErrNotPositiveDefinite);
    // A general K that is symmetric but indefinite, and one not symmetric.
    let mut k = nalgebra::Matrix6::<f64>::identity();
    k[(0, 1)] = 2.0;
    k[(1, 0)] = 2.0;
    assert_eq!(
        RodLaw::general(k, nalgebra::Vector3::zeros(), nalgebra::Vector3::z()).unwrap_err().status,
        Status::ErrNotPositiveDefinite
    );
    k[(1, 0)] = 1.0;
    assert_eq!(
        RodLaw::general(k, nalgebra::Vector3::zeros(), nalgebra::Vector3::z()).unwrap_err().status,
        Status::ErrOutOfRange
    );
    // Zero length, zero elements.
    let law = RodLaw::isotropic(1.0, 1.0, 1.0, 1.0).unwrap();
    assert!(Rod::new(law.clone(), 0.0, Loads::default(), Supports::Cantilever, Scheme::Midpoint, 4).is_err());
    assert!(Rod::new(law, 1.0, Loads::default(), Supports::Cantilever, Scheme::Midpoint, 0).is_err());
}

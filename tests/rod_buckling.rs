//! Buckling and post-buckling (physics.md §2.4, §2.6): the double
//! bifurcation of the symmetric clamped–free rod under an axial dead load is
//! detected on the straight branch (σ_min; no determinant changes sign),
//! located, and the buckled branch followed with the phase condition.

use rodkit::continuation::anm::AnmOptions;
use rodkit::continuation::bifurcation::branch_start;
use rodkit::continuation::newton::{continue_newton, Start};
use rodkit::continuation::{Options, Problem, Scaling, Stop};
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use std::f64::consts::PI;

#[path = "support/elastica.rs"]
#[allow(dead_code)]
mod elastica;
#[path = "support/euler.rs"]
mod euler;
use elastica::elliptic;

fn axial_load() -> Loads {
    Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() }
}

/// Run the straight branch of `rod` with detection; return the bifurcation.
/// The first positive root of tan x = x (Greenhill's linearised
/// clamped–clamped problem), by Newton from 4.49.
fn tan_root() -> f64 {
    let mut x = 4.49f64;
    for _ in 0..50 {
        x -= (x.tan() - x) / (1.0 / x.cos().powi(2) - 1.0);
    }
    x
}

fn straight_branch(rod: &Rod, lambda_max: f64) -> rodkit::continuation::bifurcation::Bifurcation {
    straight_branch_with(rod, lambda_max, false)
}

fn straight_branch_with(rod: &Rod, lambda_max: f64, anm: bool) -> rodkit::continuation::bifurcation::Bifurcation {
    let mut sys = rod.system().unwrap();
    let opts = Options {
        target_lambda: Some(lambda_max),
        residual_tol: 1e-12,
        initial_step: 0.2,
        max_step: 0.5,
        detect_bifurcations: true,
        bifurcation_tol: 1e-11,
        ..Default::default()
    };
    let start = Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true };
    let b = if anm {
        rodkit::continuation::anm::continue_anm(&mut sys, start, &opts, &Default::default(), |_, _| vec![], |_| true)
            .unwrap()
    } else {
        continue_newton(&mut sys, start, &opts, |_, _| vec![], |_| true).unwrap()
    };
    assert_eq!(b.stop, Stop::Target);
    // The straight branch is symmetric: no determinant changes sign at the
    // double point; σ_min found it.
    assert!(b.records.windows(2).all(|w| w[0].bordered_det_sign == w[1].bordered_det_sign));
    assert_eq!(
        b.bifurcations.len(),
        1,
        "bifurcations: {:?}",
        b.bifurcations.iter().map(|b| b.lambda).collect::<Vec<_>>()
    );
    b.bifurcations[0].clone()
}

/// Extensible, shearable clamped–free rod: the critical load solves
/// P(1 + P(1/GA − 1/EA)) = π²K_b/(4L²) (physics.md §2.6, EA = 1e3, GA = 3e2,
/// K_b = L = 1). The located load converges at the scheme's order (4 for
/// Gauss(2)) and is within 1e−8 relative on a fine grid (Gauss(4), 16
/// elements); the point is double (two zero singular values).
#[test]
fn euler_load_of_the_extensible_cantilever() {
    let (ea, ga) = (1e3, 3e2);
    let pe = PI * PI / 4.0;
    // Root of P²(1/GA − 1/EA) + P − P_E = 0.
    let c = 1.0 / ga - 1.0 / ea;
    let exact = (-1.0 + (1.0 + 4.0 * c * pe).sqrt()) / (2.0 * c);
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, ga, ea).unwrap();
    let mut errs = vec![];
    for n in [2, 4, 8] {
        let rod = Rod::new(law.clone(), 1.0, axial_load(), Supports::Cantilever, Scheme::Gauss(2), n).unwrap();
        let bif = straight_branch(&rod, 3.0);
        assert_eq!(bif.multiplicity, 2, "N = {n}: σ = {:?}", bif.singular_values);
        let err = (bif.lambda - exact).abs() / exact;
        println!("N = {n}: P_cr = {:.15}, exact {exact:.15}, error {err:e}, σ {:?}", bif.lambda, bif.singular_values);
        errs.push(err);
    }
    let rate = (errs[1] / errs[2]).log2();
    assert!((rate - 4.0).abs() < 0.5, "rate {rate} ({errs:?})");
    let rod = Rod::new(law, 1.0, axial_load(), Supports::Cantilever, Scheme::Gauss(4), 16).unwrap();
    let fine = (straight_branch(&rod, 3.0).lambda - exact).abs() / exact;
    assert!(fine < 1e-8, "Gauss(4), 16 elements: {fine:e}");
    // The ANM finds the same point.
    let by_anm = straight_branch_with(&rod, 3.0, true);
    assert!(
        (by_anm.lambda - exact).abs() < 1e-8 * exact && by_anm.multiplicity == 2,
        "ANM: {} ({:?})",
        by_anm.lambda,
        by_anm.singular_values
    );
    // The extensible load is 0.6 % below Euler's.
    assert!((1.0 - exact / pe - 0.006).abs() < 0.001);
}

/// Post-buckled inextensible elastica (Kirchhoff rod, clamped–free, axial
/// dead load): switch to the buckled branch at the located double point
/// with the phase condition, follow it to a tip rotation θ0 beyond 170°,
/// and compare each point with the elliptic-integral solution (k =
/// sin(θ0/2)): P/P_cr = (2K/π)², axial tip position x/L = 2E/K − 1,
/// deflection y/L = 2k/K. The unfolding parameter stays 0.
#[test]
fn post_buckled_elastica_against_elliptic_integrals() {
    let law = RodLaw::kirchhoff(1.0, 1.0, 1.0 / 1.3).unwrap();
    let rod = Rod::new(law, 1.0, axial_load(), Supports::Cantilever, Scheme::Gauss(4), 16).unwrap();
    let pcr = PI * PI / 4.0;
    let bif = straight_branch(&rod, 3.0);
    assert!((bif.lambda - pcr).abs() < 1e-9 * pcr, "P_cr {} vs {pcr}", bif.lambda);
    // One null direction; its tip deflection sets the phase azimuth.
    let (nx, nl) = &bif.null_vectors[0];
    let tip = rod.node(rod.elements);
    let azimuth = nx[tip + 1].atan2(nx[tip]);
    let mut aug = rod.system_with_phase(rod.elements, azimuth).unwrap();
    let n = rod.unknowns();
    let mut x_aug = bif.x.clone();
    x_aug.push(0.0);
    let mut t_aug = nx.clone();
    t_aug.push(0.0);
    let (sx, sl) = aug.unknown_scales();
    let scaling = Scaling { x: sx, lambda: sl };
    let aug_bif = rodkit::continuation::bifurcation::Bifurcation {
        x: x_aug,
        tangent_x: {
            let mut t = bif.tangent_x.clone();
            t.push(0.0);
            t
        },
        ..bif.clone()
    };
    let start = branch_start(&aug_bif, (&t_aug, *nl), 0.05, &scaling);
    let opts = Options {
        residual_tol: 1e-11,
        initial_step: 0.05,
        max_step: 0.2,
        max_steps: 400,
        lambda_range: (0.0, 40.0),
        ..Default::default()
    };
    let observe = |x: &[f64], _: f64| x.to_vec();
    let mut max_theta: f64 = 0.0;
    let b = continue_newton(&mut aug, Start::Resume(start), &opts, observe, |r| {
        // Stop past 172°.
        let x = &r.outputs;
        let y = &x[tip..tip + 13];
        let d3z = y[3] * y[3] - y[4] * y[4] - y[5] * y[5] + y[6] * y[6];
        d3z.acos().to_degrees() < 172.0
    })
    .unwrap();
    for r in &b.records {
        let x = &r.outputs;
        assert!(x[n].abs() < 1e-9, "unfolding parameter μ = {}", x[n]);
        let y = &x[tip..tip + 13];
        let d3z = y[3] * y[3] - y[4] * y[4] - y[5] * y[5] + y[6] * y[6];
        let theta = d3z.clamp(-1.0, 1.0).acos();
        max_theta = max_theta.max(theta);
        if theta < 0.05 {
            continue; // near the bifurcation the branch is steep in θ0
        }
        let k = (0.5 * theta).sin();
        let (kk, ee) = elliptic(k);
        let p = pcr * (2.0 * kk / PI).powi(2);
        let (axial, lateral) = (2.0 * ee / kk - 1.0, 2.0 * k / kk);
        let defl = (y[0] * y[0] + y[1] * y[1]).sqrt();
        assert!((r.lambda - p).abs() < 1e-8 * p, "θ0 = {:.1}°: P {} vs {p}", theta.to_degrees(), r.lambda);
        assert!(
            (y[2] - axial).abs() < 1e-8 && (defl - lateral).abs() < 1e-8,
            "θ0 = {:.1}°: tip ({defl}, {}) vs ({lateral}, {axial})",
            theta.to_degrees(),
            y[2]
        );
        // The buckled shape stays in the chosen plane.
        assert!((-azimuth.sin() * y[0] + azimuth.cos() * y[1]).abs() < 1e-10);
    }
    assert!(max_theta.to_degrees() > 170.0, "reached only {:.1}°", max_theta.to_degrees());
    println!("{} records, {:?}", b.records.len(), b.counts);
}

/// Beck's column: a cantilever under a tangential follower thrust (the tip
/// force stays along the tip tangent) has no static bifurcation — it loses
/// stability by flutter, which a static solver cannot see (physics.md §2.6;
/// Ziegler 1968). The straight branch is followed far past the dead-load
/// Euler load π²/4 and past Beck's flutter load 20.05 K_b/L² with
/// detection on: no bifurcation, no sign change, the rod stays straight.
#[test]
fn beck_column_has_no_static_bifurcation() {
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let loads = Loads { tip_force: Some(Load::follower([0.0, 0.0, -1.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(2), 8).unwrap();
    let mut sys = rod.system().unwrap();
    let opts = Options {
        target_lambda: Some(30.0),
        residual_tol: 1e-11,
        initial_step: 0.2,
        max_step: 1.0,
        detect_bifurcations: true,
        ..Default::default()
    };
    let b = continue_newton(
        &mut sys,
        Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true },
        &opts,
        |x, _| rod.tip(x).to_vec(),
        |_| true,
    )
    .unwrap();
    assert_eq!(b.stop, Stop::Target);
    assert!(b.bifurcations.is_empty(), "found {:?}", b.bifurcations.iter().map(|b| b.lambda).collect::<Vec<_>>());
    assert!(b
        .records
        .windows(2)
        .all(|w| w[0].det_sign == w[1].det_sign && w[0].bordered_det_sign == w[1].bordered_det_sign));
    for r in &b.records {
        assert!(r.outputs[0].abs() < 1e-12 && r.outputs[1].abs() < 1e-12);
        // Axial shortening by the thrust: (1 − Λ/EA) L.
        assert!((r.outputs[2] - (1.0 - r.lambda / 2.6e4)).abs() < 1e-12);
    }
    // The same rod under a dead thrust does bifurcate (the detection works here).
    let dead = Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() };
    let rod = Rod::new(
        RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap(),
        1.0,
        dead,
        Supports::Cantilever,
        Scheme::Gauss(2),
        8,
    )
    .unwrap();
    let mut sys = rod.system().unwrap();
    let b = continue_newton(
        &mut sys,
        Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true },
        &Options { target_lambda: Some(3.0), ..opts },
        |_, _| vec![],
        |_| true,
    )
    .unwrap();
    assert_eq!(b.bifurcations.len(), 1);
}

/// Pinned–pinned (ball joints, physics.md §2.3) extensible rod: the first
/// bifurcation solves P(1 + P(1/GA − 1/EA)) = π²K_b/L² (physics.md §2.6),
/// located to 1e−8 relative on Gauss(4) × 16; double by symmetry.
#[test]
fn euler_load_pinned_pinned() {
    let (ea, ga) = (1e3, 3e2);
    let pe = PI * PI;
    let c = 1.0 / ga - 1.0 / ea;
    let exact = (-1.0 + (1.0 + 4.0 * c * pe).sqrt()) / (2.0 * c);
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, ga, ea).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Pinned, Scheme::Gauss(4), 16).unwrap();
    let bif = straight_branch(&rod, 12.0);
    let err = (bif.lambda - exact).abs() / exact;
    println!("pinned–pinned: P_cr = {}, exact {exact}, error {err:e}", bif.lambda);
    assert!(err < 1e-8, "{err:e}");
    assert_eq!(bif.multiplicity, 2);
}

/// Greenhill's problem under a controlled end rotation (Supports::Twisted,
/// Λ = sin(φ/2)): an inextensible rod (K_b = 1, C = 4, L = 1) clamped at
/// both ends, the far end kept on the axis and free to slide, turned by φ.
/// The straight twisted state carries M = Cφ/L; linearising K_b w'''' −
/// iM w''' − T w'' = 0 (w = x + iy) with w = w' = 0 at both ends and T = 0
/// gives (derived here) 2i sin(θ/2) − iθ cos(θ/2) = 0, θ = ML/K_b: the
/// first root θ/2 = 4.493409457909064 (tan x = x), so φ_c = 2·4.4934…·K_b/C.
/// The double bifurcation (symmetric) is found at that φ to 1e−8.
#[test]
fn greenhill_controlled_end_rotation() {
    let x = tan_root();
    let (kb, c) = (1.0, 4.0);
    let phi_c = 2.0 * x * kb / c;
    let law = RodLaw::kirchhoff(kb, kb, c).unwrap();
    let rod = Rod::new(law, 1.0, Loads::default(), Supports::Twisted { tension: 0.0 }, Scheme::Gauss(4), 16).unwrap();
    let bif = straight_branch(&rod, 0.99);
    let phi = rod.end_rotation(&bif.x, bif.lambda).unwrap();
    let err = (phi - phi_c).abs() / phi_c;
    println!("Greenhill: φ_c = {phi}, linearised {phi_c}, error {err:e}, σ {:?}", bif.singular_values);
    assert!(err < 1e-8, "{err:e}");
    assert_eq!(bif.multiplicity, 2);
    // The straight twisted state: uniform twist φ/L, torque C φ/L.
    let tip = rod.node_state(&bif.x, rod.elements);
    assert!((tip[12] - c * phi).abs() < 1e-9 * c * phi, "m3 {}", tip[12]);
}

/// Greenhill's problem under a torque clamp (Supports::Torqued: the end
/// moment M is the parameter, φ free): the same straight branch φ = ML/C
/// and the same double bifurcation, now at M_c = 2·4.4934…·K_b/L (the
/// linearisation above), found to 1e-8 by Newton and by the ANM
/// continuation; with tension T the straight branch is unchanged (φ =
/// ML/C) and M_c grows (checked against the φ-controlled rod's buckling
/// torque at the same T, to 1e-8).
#[test]
fn greenhill_controlled_end_moment() {
    let x = tan_root();
    let (kb, c) = (1.0, 4.0);
    let m_c = 2.0 * x * kb;
    let law = RodLaw::kirchhoff(kb, kb, c).unwrap();
    let rod =
        Rod::new(law.clone(), 1.0, Loads::default(), Supports::Torqued { tension: 0.0 }, Scheme::Gauss(4), 16).unwrap();
    assert_eq!(rod.unknowns(), rod.straight_state().len());
    for anm in [false, true] {
        let bif = straight_branch_with(&rod, 10.0, anm);
        let err = (bif.lambda - m_c).abs() / m_c;
        let phi = rod.end_rotation(&bif.x, bif.lambda).unwrap();
        println!(
            "Greenhill, torque clamp (ANM {anm}): M_c = {}, linearised {m_c}, error {err:e}; φ = {phi}",
            bif.lambda
        );
        assert!(err < 1e-8, "ANM {anm}: {err:e}");
        assert_eq!(bif.multiplicity, 2);
        assert!((phi - m_c / c).abs() < 1e-9 * phi, "φ {phi} against ML/C {}", m_c / c);
    }
    // With tension: the rotation-controlled rod's buckling torque.
    let tension = 5.0;
    let twisted =
        Rod::new(law.clone(), 1.0, Loads::default(), Supports::Twisted { tension }, Scheme::Gauss(4), 16).unwrap();
    let b = straight_branch(&twisted, 0.999);
    let m_twisted = twisted.node_state(&b.x, twisted.elements)[12];
    let torqued = Rod::new(law, 1.0, Loads::default(), Supports::Torqued { tension }, Scheme::Gauss(4), 16).unwrap();
    let bif = straight_branch(&torqued, 12.0);
    println!("T = {tension}: M_c {} (torque clamp) vs {m_twisted} (rotation control)", bif.lambda);
    assert!((bif.lambda - m_twisted).abs() < 1e-8 * m_twisted, "{} vs {m_twisted}", bif.lambda);
    assert!(bif.lambda > m_c * 1.05);
}

/// The post-buckled Greenhill branch (T = 1) traced under a torque clamp
/// and under rotation control is one curve in the (φ, M) plane: every
/// torque-clamp point's M against the rotation-controlled branch's M at the
/// same φ (linear interpolation between its points 0.01 apart in Λ: error
/// ≈ h²M''/8, below 1e-4 relative here).
#[test]
fn torque_clamp_and_rotation_control_trace_one_buckled_curve() {
    let law = RodLaw::kirchhoff(1.0, 1.0, 4.0).unwrap();
    let method = rodkit::rod::branch::Method::Newton;
    let curve = |supports: Supports, target: f64, step: f64, steps: usize| -> Vec<(f64, f64)> {
        let rod = Rod::new(law.clone(), 1.0, Loads::default(), supports, Scheme::Gauss(2), 12).unwrap();
        let opts = Options {
            target_lambda: Some(target),
            residual_tol: 1e-12,
            initial_step: 0.2,
            max_step: 0.5,
            detect_bifurcations: true,
            ..Default::default()
        };
        let straight = rod.continue_branch(None, 0.0, true, &opts, method, |_| true).unwrap();
        let opts =
            Options { residual_tol: 1e-11, initial_step: step, max_step: step, max_steps: steps, ..Default::default() };
        let b = rod.switch_branch(&straight, 0, 0, step.min(0.05), &opts, method, |_| true).unwrap();
        let mut phi_prev = rod.end_rotation(&straight.bifurcations[0].x, straight.bifurcations[0].lambda).unwrap();
        b.records
            .iter()
            .zip(&b.states)
            .map(|(r, x)| {
                let phi = rodkit::rod::model::unwrap_rotation(phi_prev, rod.end_rotation(x, r.lambda).unwrap());
                phi_prev = phi;
                let y = rod.node_state(x, rod.elements);
                let q = [y[3], y[4], y[5], y[6]];
                // Spatial moment about e3 at s = L.
                let rot = rodkit::rod::kinematics::rotation(&q);
                (phi, rot[2][0] * y[10] + rot[2][1] * y[11] + rot[2][2] * y[12])
            })
            .collect()
    };
    let torque = curve(Supports::Torqued { tension: 1.0 }, 12.0, 0.1, 12);
    let rotation = curve(Supports::Twisted { tension: 1.0 }, 0.999, 0.01, 60);
    let (lo, hi) = (
        rotation.first().unwrap().0.min(rotation.last().unwrap().0),
        rotation.first().unwrap().0.max(rotation.last().unwrap().0),
    );
    let mut compared = 0;
    for &(phi, m) in &torque {
        if phi <= lo || phi >= hi {
            continue;
        }
        let w = rotation.windows(2).find(|w| (w[0].0 - phi) * (w[1].0 - phi) <= 0.0).unwrap();
        let t = (phi - w[0].0) / (w[1].0 - w[0].0);
        let m_rot = w[0].1 + t * (w[1].1 - w[0].1);
        println!("φ {phi:.5}: M torque clamp {m:.8}, rotation control {m_rot:.8}");
        assert!((m - m_rot).abs() < 1e-4 * m.abs(), "φ {phi}: {m} vs {m_rot}");
        compared += 1;
    }
    assert!(compared >= 5, "only {compared} points overlap: torque {torque:?}, rotation φ in [{lo}, {hi}]");
}

/// Greenhill's post-buckled branch of the symmetric rod (isotropic
/// Kirchhoff, controlled end rotation, T = 0 and 1): non-planar, every
/// rotation about the axis another solution; followed with the phase
/// condition, regular (|σ_min| ≥ 1e−4 after the first point), μ at the
/// scheme's error, supercritical (φ grows).
#[test]
fn greenhill_symmetric_post_buckled_branch() {
    for tension in [0.0, 1.0] {
        let law = RodLaw::kirchhoff(1.0, 1.0, 4.0).unwrap();
        let rod = Rod::new(law, 1.0, Loads::default(), Supports::Twisted { tension }, Scheme::Gauss(2), 12).unwrap();
        let opts = Options {
            target_lambda: Some(0.99),
            residual_tol: 1e-12,
            initial_step: 0.2,
            max_step: 0.5,
            detect_bifurcations: true,
            ..Default::default()
        };
        let straight =
            rod.continue_branch(None, 0.0, true, &opts, rodkit::rod::branch::Method::Newton, |_| true).unwrap();
        let bif_lambda = straight.bifurcations[0].lambda;
        let opts =
            Options { residual_tol: 1e-11, max_step: 0.1, max_steps: 10, track_singular: true, ..Default::default() };
        let b = rod.switch_branch(&straight, 0, 0, 0.05, &opts, rodkit::rod::branch::Method::Newton, |_| true).unwrap();
        assert!(b.phase.is_some());
        let n = rod.unknowns();
        let mut non_planar = 0.0f64;
        for (r, x) in b.records.iter().zip(&b.states).skip(1) {
            assert!(x[n].abs() < 1e-8, "T {tension}: μ = {}", x[n]);
            assert!(r.smallest_singular_value.unwrap().abs() > 1e-4, "T {tension}: σ {:?}", r.smallest_singular_value);
            assert!(r.lambda > bif_lambda);
            let p = rod.positions(x);
            let az = |i: usize| p[i][1].atan2(p[i][0]);
            non_planar = non_planar.max((az(rod.elements / 4) - az(rod.elements / 2)).sin().abs());
        }
        assert!(non_planar > 0.1, "T {tension}: planar ({non_planar})");
    }
}

/// Greenhill's post-buckled branch of a rod WITHOUT rotational symmetry
/// (K_b2 = 1.3 K_b1: the bifurcation is simple, no phase condition): the
/// buckled rod is non-planar and the branch is followed with a regular
/// bordered tangent (|σ_min| ≥ 1e−4 along it, det B flipped across the
/// point), subcritically (φ decreasing).
#[test]
fn non_planar_post_buckled_branch_is_regular() {
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
    let straight = rod.continue_branch(None, 0.0, true, &opts, rodkit::rod::branch::Method::Newton, |_| true).unwrap();
    // Two simple points (one per bending axis) below Λ = 0.99; the first:
    assert!(!straight.bifurcations.is_empty());
    assert_eq!(straight.bifurcations[0].multiplicity, 1);
    assert!(straight.bifurcations[0].det_sign_change);
    let opts =
        Options { residual_tol: 1e-11, max_step: 0.1, max_steps: 12, track_singular: true, ..Default::default() };
    let b = rod.switch_branch(&straight, 0, 0, 0.05, &opts, rodkit::rod::branch::Method::Newton, |_| true).unwrap();
    assert!(b.phase.is_none());
    let mut non_planar = 0.0f64;
    for (r, x) in b.records.iter().zip(&b.states).skip(1) {
        // Regular: |σ_min| ≥ 1e−4 (it is ≥ 1.5e−4 from the first step,
        // against 1e−14 at the bifurcation point itself).
        let s = r.smallest_singular_value.unwrap().abs();
        assert!(s > 1e-4, "|σ_min| {s:e} at Λ {}", r.lambda);
        let p = rod.positions(x);
        let az = |i: usize| p[i][1].atan2(p[i][0]);
        non_planar = non_planar.max((az(rod.elements / 4) - az(rod.elements / 2)).sin().abs());
    }
    assert!(non_planar > 0.1, "the branch stayed planar ({non_planar})");
    // Λ rises with the buckle's amplitude (the first point, at arc length
    // 0.05 along the null direction, is above the critical load): the same
    // branch by the ANM, switched independently, gives the same states at
    // the same loads (dense samples), and Newton's own samples agree.
    let lc = straight.bifurcations[0].lambda;
    let samples = vec![lc + 2e-3, lc + 5e-3, lc + 1e-2];
    let opts = Options { samples: samples.clone(), ..opts };
    let bn = rod.switch_branch(&straight, 0, 0, 0.05, &opts, rodkit::rod::branch::Method::Newton, |_| true).unwrap();
    let ba = rod
        .switch_branch(
            &straight,
            0,
            0,
            0.05,
            &opts,
            rodkit::rod::branch::Method::Anm(AnmOptions { order: 20, epsilon: 1e-8, pade: false }),
            |_| true,
        )
        .unwrap();
    assert_eq!(bn.samples.len(), 3, "Newton samples {:?}", bn.samples.iter().map(|s| s.lambda).collect::<Vec<_>>());
    assert_eq!(ba.samples.len(), 3, "ANM samples {:?}", ba.samples.iter().map(|s| s.lambda).collect::<Vec<_>>());
    for k in 0..3 {
        let (tn, ta) = (rod.tip(&bn.sample_states[k]), rod.tip(&ba.sample_states[k]));
        let mid = |x: &[f64]| rod.positions(x)[rod.elements / 2];
        let (mn, ma) = (mid(&bn.sample_states[k]), mid(&ba.sample_states[k]));
        let d = (0..3).map(|i| (tn[i] - ta[i]).abs().max((mn[i] - ma[i]).abs())).fold(0.0, f64::max);
        // Same discrete equations, both within residual 1e-11: the states
        // agree to the conditioning times that (1e-8 here).
        assert!(d < 1e-8, "Λ {}: Newton and ANM differ by {d:e}", samples[k]);
        assert!(bn.samples[k].residual <= 1e-11 && ba.samples[k].residual <= 1e-11);
        // Off the straight branch: the mid node is displaced sideways.
        assert!(mn[0].hypot(mn[1]) > 1e-3, "sample {k} is straight");
    }
}

/// Hemitropic rod (twist–stretch g, bend–shear c2; physics.md §2.2) under an
/// axial dead load, clamped–free. Linearising about the straight (twisted,
/// torque-free) state with φ = θ2 − iθ1 (derived here: lateral force
/// n = Pφ = i c2 φ' + G V, moment M = i K_b φ' + c2 V, M' = −iP(V + (1+ε)φ),
/// ε = −CP/(CS − g²) the axial strain) gives a φ'' − 2ibφ' + kφ = 0 with
/// a = K_b − c2²/G, b = c2P/G, k = P(1 + ε + P/G); φ(0) = 0 and M(L) = 0
/// give the critical condition k = π²a/(4L²) − b²/a (c2 = g = 0: the
/// extensible Euler formula). The located load agrees to 1e−8; the
/// coupling's effect (lower than the achiral rod's) is shown.
#[test]
fn hemitropic_rod_buckles_earlier() {
    let (kb, c, g_shear, s, g, c2, l) = (1.0, 2.0, 300.0, 1000.0, -20.0, 6.0, 1.0);
    let critical = |g: f64, c2: f64| {
        let a = kb - c2 * c2 / g_shear;
        let f = |p: f64| {
            let eps = -c * p / (c * s - g * g);
            let b = c2 * p / g_shear;
            p * (1.0 + eps + p / g_shear) - PI * PI * a / (4.0 * l * l) + b * b / a
        };
        let (mut lo, mut hi) = (0.1, 5.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if f(lo) * f(mid) <= 0.0 {
                hi = mid
            } else {
                lo = mid
            }
        }
        0.5 * (lo + hi)
    };
    let (chiral, achiral) = (critical(g, c2), critical(0.0, 0.0));
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() };
    let law = RodLaw::hemitropic(kb, c, g_shear, s, g, c2).unwrap();
    let rod = Rod::new(law, l, loads, Supports::Cantilever, Scheme::Gauss(4), 16).unwrap();
    let bif = straight_branch(&rod, 3.0);
    let err = (bif.lambda - chiral).abs() / chiral;
    println!(
        "hemitropic P_cr {} (linearised {chiral}), achiral {achiral}: coupling lowers it by {:.3} %",
        bif.lambda,
        100.0 * (1.0 - chiral / achiral)
    );
    assert!(err < 1e-8, "hemitropic P_cr {} vs {chiral}: {err:e}", bif.lambda);
    assert!(achiral - chiral > 0.01 * achiral, "the coupling should lower the critical load");
    assert_eq!(bif.multiplicity, 2);
    // The straight state before buckling twists under compression:
    // Δu3 = −gF/(CS − g²) with F = −P.
    let tip = rod.node_state(&bif.x, rod.elements);
    let phi = 2.0 * tip[6].atan2(tip[3]);
    assert!((phi - g * bif.lambda / (c * s - g * g) * l).abs() < 1e-10);
}

/// Clamped–clamped rod compressed by a prescribed end displacement
/// (r(L) = (0, 0, L) − Λ·0.01L e3, displacement control): the axial force at
/// the first bifurcation solves P(1 + P(1/GA − 1/EA)) = 4π²K_b/L²
/// (physics.md §2.6 with the clamped–clamped Euler load; the same
/// linearisation as the pinned case with the clamped mode).
#[test]
fn clamped_clamped_under_end_displacement() {
    let (ea, ga) = (1e3, 3e2);
    let pe = 4.0 * PI * PI;
    let c = 1.0 / ga - 1.0 / ea;
    let exact = (-1.0 + (1.0 + 4.0 * c * pe).sqrt()) / (2.0 * c);
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, ga, ea).unwrap();
    let supports = Supports::Clamped {
        end_position: [0.0, 0.0, 1.0],
        end_rotation: [1.0, 0.0, 0.0, 0.0],
        end_displacement: [0.0, 0.0, -0.01],
    };
    let rod = Rod::new(law, 1.0, Loads::default(), supports, Scheme::Gauss(4), 16).unwrap();
    let bif = straight_branch(&rod, 6.0);
    let (force, _) = rod.spatial_force_moment(&bif.x, 0);
    let p = -force[2];
    let err = (p - exact).abs() / exact;
    println!("clamped–clamped: P at the bifurcation {p} (Λ = {}), formula {exact}, error {err:e}", bif.lambda);
    assert!(err < 1e-8, "{err:e}");
    assert_eq!(bif.multiplicity, 2);
}

/// The hemitropic rod's buckled shapes are non-planar (the bend–shear
/// coupling twists the buckling plane along the rod) and, the rod being
/// rotationally symmetric, every rotation about the axis is another one:
/// the branch is followed through `switch_branch` with the phase
/// condition, with a regular bordered tangent (|σ_min| ≥ 1e−4 along it,
/// against ~1e−14 at the double point), μ at the scheme's error, and
/// a deflection whose azimuth varies along the rod. (The unfolding vanishes
/// on straight states, where (straight, any μ) also solves the augmented
/// system; switch_branch's first point fixes the buckle's amplitude rather
/// than the arc length, which keeps it off that family — with twist–stretch
/// coupling an arc-length first step slid onto it.)
#[test]
fn non_planar_symmetric_branch_with_phase_condition() {
    let law = RodLaw::hemitropic(1.0, 2.0, 300.0, 1000.0, -20.0, 12.0).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(2), 12).unwrap();
    let straight = straight_branch(&rod, 3.0);
    let branch = rodkit::rod::branch::RodBranch {
        records: vec![],
        states: vec![],
        bifurcations: vec![straight],
        unresolved: vec![],
        stop: Stop::Target,
        counts: Default::default(),
        resume: rodkit::continuation::Resume {
            x: vec![],
            lambda: 0.0,
            tangent_x: vec![],
            tangent_lambda: 0.0,
            step: 0.0,
            previous: None,
            modes: None,
        },
        phase: None,
        contact: None,
        samples: vec![],
        sample_states: vec![],
        missed_samples: vec![],
        pair_lists: 0,
        failure: None,
    };
    let opts =
        Options { residual_tol: 1e-11, max_step: 0.1, max_steps: 20, track_singular: true, ..Default::default() };
    let b = rod.switch_branch(&branch, 0, 0, 0.05, &opts, rodkit::rod::branch::Method::Newton, |_| true).unwrap();
    assert!(b.phase.is_some());
    let n = rod.unknowns();
    let mut non_planar = 0.0f64;
    for (r, x) in b.records.iter().zip(&b.states).skip(2) {
        // μ is zero for the exact equations; the scheme conserves the cubic
        // invariant J only to its order (h⁴ here), so μ ~ 1e−8.
        assert!(x[n].abs() < 1e-6, "μ = {}", x[n]);
        let s = r.smallest_singular_value.unwrap().abs();
        assert!(s > 1e-4, "|σ_min| {s:e} at Λ {}", r.lambda);
        let p = rod.positions(x);
        let az = |i: usize| p[i][1].atan2(p[i][0]);
        non_planar = non_planar.max((az(rod.elements / 3) - az(rod.elements)).sin().abs());
    }
    println!("azimuth spread {non_planar}");
    assert!(non_planar > 0.05, "the branch stayed planar ({non_planar})");
}

/// A located bifurcation's three singular values (`Bifurcation::
/// singular_values`, what the C branch record reports) against a dense SVD
/// of the same matrix (nalgebra, the independent reference): the monitor's
/// scaled bordered tangent Ã = R B C at the located point, rebuilt from the
/// rod's own Jacobian there — B = [[J_x, J_Λ], [t_x/(n s²), t_Λ/s_Λ²]]
/// with the branch tangent the location bordered by (`tangent_x`), rows
/// scaled by the equations' 1/e_i (√n the border's), columns by the
/// unknowns' scales. Euler's cantilever with K_b1 = 2 K_b2 (a simple
/// point), Gauss(4) × 4, by the ANM and by Newton continuation: σ_2, σ_3
/// to 1e-8, and σ_1 within 5 % + 1e-13 (the SVD's own round-off; both
/// are ~1e-14, below ε‖Ã‖_F = 2e-14). Both locations land on the zero to
/// the last bit (σ_1 1.6e-14 and 6e-16), where the others cannot be
/// resolved by solves with the matrix (Newton's were 4.60 and 4.27): they
/// are then taken 1e-12 of arc length beside the point (1e-3 of the
/// location's tolerance), which moves them by ~1e-12 of themselves.
#[test]
fn a_located_points_singular_values_are_the_dense_svds() {
    let rod = euler::euler_cantilever(4);
    let opts = Options { bifurcation_tol: 1e-10, ..euler::straight_options() };
    for method in [rodkit::rod::branch::Method::Anm(AnmOptions::default()), rodkit::rod::branch::Method::Newton] {
        let branch = rod.continue_branch(None, 0.0, true, &opts, method, |_| true).unwrap();
        assert_eq!(branch.bifurcations.len(), 1, "{method:?}");
        let bif = &branch.bifurcations[0];
        let mut sys = rod.system().unwrap();
        let n = sys.dim();
        let (s, sl) = sys.unknown_scales();
        let e = sys.equation_scales();
        let mut jx = vec![0.0; sys.pattern().nnz()];
        let mut jl = vec![0.0; n];
        sys.jacobian(&bif.x, bif.lambda, &mut jx, &mut jl);
        let mut a = nalgebra::DMatrix::<f64>::zeros(n + 1, n + 1);
        let p = sys.pattern();
        for j in 0..n {
            for q in p.col_ptr[j]..p.col_ptr[j + 1] {
                a[(p.row_idx[q], j)] += jx[q];
            }
        }
        for i in 0..n {
            a[(i, n)] = jl[i];
            a[(n, i)] = bif.tangent_x[i] / (n as f64 * s[i] * s[i]);
        }
        a[(n, n)] = bif.tangent_lambda / (sl * sl);
        let scale = |v: f64| if v > 0.0 && v.is_finite() { v } else { 1.0 };
        for i in 0..=n {
            let r = if i < n { 1.0 / scale(e[i]) } else { (n as f64).sqrt() };
            let c = if i < n { scale(s[i]) } else { scale(sl) };
            for j in 0..=n {
                a[(i, j)] *= r;
                a[(j, i)] *= c;
            }
        }
        let mut svd: Vec<f64> = a.singular_values().iter().copied().collect();
        svd.sort_by(f64::total_cmp);
        let sigma = &bif.singular_values;
        println!("{method:?}: located {sigma:?}, dense SVD {:?}", &svd[..3]);
        assert!(sigma[0] <= 1e-6 * svd[1], "{method:?}: {sigma:?} {:?}", &svd[..3]);
        assert!((sigma[0] - svd[0]).abs() <= 0.05 * svd[0] + 1e-13, "{method:?}: σ0 {} against {}", sigma[0], svd[0]);
        for k in 1..3 {
            assert!((sigma[k] - svd[k]).abs() <= 1e-8 * svd[k], "{method:?}: σ{k} {} against {}", sigma[k], svd[k]);
        }
    }
}

/// The ANM with Padé steps (P = 15, ε = 1e-6, sought up to 8 times the
/// series' step) through detection, location, switch and the post-buckled
/// branch, against closed forms. A Kirchhoff rod with K_b1 = 2 K_b2 = 2
/// (simple bifurcations, planar buckling): the straight branch to Λ = 25
/// (steps up to 1) finds exactly the three critical loads below 25, π²K/(4L²)·{1, 2, 9} for K = K_b2 (2.47, 22.2) and K_b1
/// (4.93), each to 1e-9; the first one's buckled branch, followed by Padé
/// steps to Λ = 14, delivers its samples at Λ = 5, 10, 14 on the elastica
/// (P = P_cr (2K(k)/π)², tip axial 2E/K − 1 and lateral 2k/K, k from P
/// by bisection) to 1e-8, as Newton continuation does in
/// `post_buckled_elastica_against_elliptic_integrals`.
#[test]
fn pade_steps_detect_locate_and_follow_the_elastica() {
    let law = RodLaw::kirchhoff(2.0, 1.0, 1.0 / 1.3).unwrap();
    let rod = Rod::new(law, 1.0, axial_load(), Supports::Cantilever, Scheme::Gauss(4), 16).unwrap();
    let method = rodkit::rod::branch::Method::Anm(AnmOptions { order: 15, epsilon: 1e-6, pade: true });
    let pe = PI * PI / 4.0;
    let opts = Options {
        target_lambda: Some(25.0),
        residual_tol: 1e-11,
        initial_step: 0.2,
        max_step: 1.0,
        detect_bifurcations: true,
        bifurcation_tol: 1e-11,
        ..Default::default()
    };
    let straight = rod.continue_branch(None, 0.0, true, &opts, method, |_| true).unwrap();
    assert_eq!(straight.stop, Stop::Target);
    let found: Vec<f64> = straight.bifurcations.iter().map(|b| b.lambda).collect();
    assert_eq!(found.len(), 3, "bifurcations at {found:?}");
    for (got, exact) in found.iter().zip([pe, 2.0 * pe, 9.0 * pe]) {
        assert!((got - exact).abs() < 1e-9 * exact, "{got} vs {exact} ({found:?})");
    }
    let loads = [5.0, 10.0, 14.0];
    let opts = Options {
        target_lambda: Some(14.0),
        residual_tol: 1e-11,
        max_step: 5.0,
        max_steps: 2000,
        samples: loads.to_vec(),
        ..Default::default()
    };
    let b = rod.switch_branch(&straight, 0, 0, 0.05, &opts, method, |_| true).unwrap();
    assert_eq!(b.stop, Stop::Target);
    assert!(b.missed_samples.is_empty(), "missed {:?}", b.missed_samples);
    assert!(b.counts.pade_steps > 0, "no Padé step taken: {:?}", b.counts);
    assert_eq!(b.sample_states.len(), loads.len());
    for (x, &p) in b.sample_states.iter().zip(&loads) {
        // The elastica of K_b = 1 (the weak plane's): P_cr = π²/4.
        let (_, axial, lateral) = elastica::at_load(p);
        let tip = rod.tip(x);
        let defl = tip[0].hypot(tip[1]);
        assert!(
            (tip[2] - axial).abs() < 1e-8 && (defl - lateral).abs() < 1e-8,
            "Λ = {p}: tip ({defl}, {}) vs ({lateral}, {axial})",
            tip[2]
        );
    }
    println!("straight {:?}\npost {:?}", straight.counts, b.counts);
}

//! SUNDIALS cross-checks of the charged rod (physics.md §3, §4), of two
//! kinds:
//!
//! 1. `kinsol_agrees_on_the_charged_residual` — **the same discrete
//!    equations, another solver.** KINSOL (exact Newton with the charged
//!    rod's own Jacobian densified, its line search, explicit tolerances
//!    scaled by the rod's equation and unknown scales) on rodkit's residual
//!    — rod + near-zone stiffening + far-zone pair forces with the switched
//!    cutoff, parameter the end rotation φ — from a perturbed start, at
//!    points along the supercoiling branch: the straight twisted rod and
//!    points of the buckled branch (phase condition and unfolding parameter
//!    included). Both sides reach a scaled residual ≤ 1e−11 and agree to
//!    1e−8 in the scaled max norm. This shows that rodkit's Newton found an
//!    isolated root of its residual; a wrong residual would pass it.
//! 2. `ida_shooting_of_the_continuous_equations_bounds_the_collocation_error`
//!    — **the equations from the other side.** The continuous charged
//!    Kirchhoff rod written in the test from physics.md
//!    (tests/support/charged_shooting.rs: its own ODEs, near-zone
//!    stiffening and far-zone force integral), integrated by IDA and shot
//!    by KINSOL, with the electrostatic force iterated to a fixed point;
//!    rodkit's collocation solutions converge to it at the scheme's order.
//!    A wrong residual fails it (the line charge off by 0.1 % in the model
//!    breaks the convergence: errors 1.1e-3 and 1.7e-3 nm at 48 and 96
//!    elements).
//!
#![cfg(feature = "sundials")]

#[path = "support/charged_shooting.rs"]
mod charged_shooting;
#[path = "support/sundials.rs"]
mod sundials;

use charged_shooting::{ChargedRodModel, Trajectory};
use rodkit::charged::branch;
use rodkit::charged::dna::{self, DnaScene};
use rodkit::charged::rod::{ChargedRod, RodCharge};
use rodkit::continuation::newton::Start;
use rodkit::continuation::{Options, Problem};
use rodkit::rod::accuracy::transfer;
use rodkit::rod::branch::RodBranch;
use rodkit::rod::model::Rod;
use sundials::{kinsol_problem_root as kinsol_root, Context};

fn perturbed(x: &[f64], scales: &[f64], eps: f64) -> Vec<f64> {
    x.iter().zip(scales).enumerate().map(|(i, (v, s))| v + eps * s * (((i * 7919) % 97) as f64 / 48.5 - 1.0)).collect()
}

/// The straight branch to φ = 8 (its first buckling point located), and
/// the buckled branch switched there: 16 steps of at most 0.3.
fn straight_and_buckled(rod: &Rod, charge: &RodCharge) -> (RodBranch, RodBranch) {
    let opts = Options {
        target_lambda: Some(8.0),
        residual_tol: 1e-12,
        initial_step: 1.0,
        max_step: 2.0,
        detect_bifurcations: true,
        bifurcation_tol: 1e-8,
        ..Default::default()
    };
    let start = Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true };
    let straight = branch::follow(rod, charge, start, None, &opts, |_| true).unwrap();
    assert!(!straight.bifurcations.is_empty(), "no buckling below φ = 8");
    let opts = Options { residual_tol: 1e-12, initial_step: 0.1, max_step: 0.3, max_steps: 16, ..Default::default() };
    let buckled = branch::switch(rod, charge, &straight, 0, 0, 0.02, &opts, |_| true).unwrap().0;
    (straight, buckled)
}

#[test]
fn kinsol_agrees_on_the_charged_residual() {
    let ctx = Context::new().unwrap();
    // 200 bp (68 nm) at 1 pN, 0.1 M, 24 elements of Gauss(2): n ≈ 950.
    let scene = DnaScene { base_pairs: 200, ..Default::default() };
    let rod = scene.rod(24, 2).unwrap();
    let charge = scene.charge();
    let (straight, buckled) = straight_and_buckled(&rod, &charge);
    let k = straight.records.len() / 2;
    let mut points = vec![(None, straight.states[k].clone(), straight.records[k].lambda)];
    for k in [8, buckled.records.len() - 1] {
        points.push((buckled.phase, buckled.states[k].clone(), buckled.records[k].lambda));
    }
    for (phase, x, phi) in points {
        let mut p = ChargedRod::new(&rod, &charge, phase, &x).unwrap();
        let (us, _) = p.unknown_scales();
        let root = kinsol_root(&ctx, &mut p, phi, &perturbed(&x, &us, 1e-4));
        let d = root.iter().zip(&x).zip(&us).map(|((a, b), s)| ((a - b) / s).abs()).fold(0.0, f64::max);
        let o = dna::observables(&rod, &x, phi).unwrap();
        println!(
            "φ = {phi:.5} ({:.4} turns, Wr {:.4}, phase {}): KINSOL vs rodkit {d:e}",
            o.turns,
            o.writhe,
            phase.is_some()
        );
        assert!(d < 1e-8, "φ = {phi}: {d:e}");
    }
}

/// The continuous equations from the other side: the charged Kirchhoff
/// rod's ODEs written in tests/support/charged_shooting.rs from physics.md
/// §3.1–3.2 (rodkit's model: Debye–Hückel without a cutoff, near zone cut
/// at exactly δ = 2a), integrated by IDA and shot by KINSOL, the
/// electrostatic force density recomputed from each trajectory until it is
/// a fixed point. rodkit's collocation solutions on 24, 48 and 96 elements
/// of Gauss(2), at the end rotation of a buckled state (1.06 turns, 9.5 nm
/// off the axis), differ from it by their discretisation error: measured
/// (rotation-invariant shape: height and distance from the axis at the
/// nodes; end torque) 6.0e-4, 6.6e-4, 3.4e-5 nm and 1.2e-4, 4.4e-4, 2.2e-5
/// pN nm — the scheme's h⁴ from 48 to 96 elements (rates 4.3 and 4.3; at 24
/// elements the torque error has the other sign, not yet asymptotic). The
/// shooting's own error: the fixed point's last change ≤ 1e-7 nm, and a
/// twice finer force grid moves it by ≤ 1e-4 nm — along the rotation about
/// the axis only (the buckled states are a family of rotations, which the
/// frozen force barely pins), hence the rotation-invariant comparison.
#[test]
fn ida_shooting_of_the_continuous_equations_bounds_the_collocation_error() {
    let ctx = Context::new().unwrap();
    let scene = DnaScene { base_pairs: 200, ..Default::default() };
    let coarse = scene.rod(24, 2).unwrap();
    let mut charge = scene.charge();
    let a = charge.screening.a;
    (charge.cutoff_tolerance, charge.near_width, charge.exact_near_width) = (None, Some(2.0 * a), true);
    let (_, buckled) = straight_and_buckled(&coarse, &charge);
    let last = buckled.records.len() - 1;
    let (phase, phi) = (buckled.phase, buckled.records[last].lambda);
    // rodkit on three meshes at this φ: the finer ones re-converged by
    // KINSOL on rodkit's residual from the coarser state carried over.
    let mut solutions = vec![(coarse.clone(), buckled.states[last].clone())];
    for k in [2, 4] {
        let (from, x) = solutions.last().unwrap().clone();
        let rod = coarse.subdivided(k).unwrap();
        let dim = x.len() - from.unknowns() + rod.unknowns();
        let x0 = transfer(&from, &rod, &x, dim);
        let mut p = ChargedRod::new(&rod, &charge, phase.map(|(node, azimuth)| (k * node, azimuth)), &x0).unwrap();
        let x = kinsol_root(&ctx, &mut p, phi, &x0);
        solutions.push((rod, x));
    }
    let (finest, x_finest) = solutions.last().unwrap().clone();
    let k = coarse.law.stiffness;
    let model = ChargedRodModel {
        length: coarse.length,
        bending: k[(0, 0)],
        twist: k[(2, 2)],
        tension: scene.tension,
        line_charge: charge.line_charge,
        kappa: charge.screening.kappa,
        a,
        delta: 2.0 * a,
    };
    // The first trajectory: the finest solution's profile, on a 0.1 nm grid
    // (the fixed point owes it nothing else).
    let (s_pts, r_pts): (Vec<f64>, Vec<[f64; 3]>) =
        finest.profile_offsets().into_iter().map(|(s, o)| (s, [x_finest[o], x_finest[o + 1], x_finest[o + 2]])).unzip();
    let cells = (model.length / 0.1).round() as usize;
    let grid: Vec<f64> = (0..=cells).map(|i| model.length * i as f64 / cells as f64).collect();
    let first = Trajectory::from_points(&s_pts, &r_pts, &grid);
    let (n0, m0) = finest.spatial_force_moment(&x_finest, 0);
    let guess = [n0[0], n0[1], n0[2], m0[0], m0[1], m0[2]];
    let nodes = finest.node_positions();
    let shot = model.solve(&ctx, first, guess, phi, 1e-7, &nodes[1..]).unwrap();
    let tip = &shot.states[nodes.len() - 2];
    println!(
        "φ = {phi:.5} ({:.3} turns): fixed point in {} iterations (last change {:e} nm), end torque {}",
        phi / (2.0 * std::f64::consts::PI),
        shot.iterations,
        shot.last_change,
        tip[17]
    );
    let mut errors = vec![];
    for (rod, x) in &solutions {
        let step = finest.elements / rod.elements;
        let mut shape: f64 = 0.0;
        for (i, p) in rod.positions(x).iter().enumerate().skip(1) {
            // Rotation-invariant: the height and the distance from the axis.
            let y = &shot.states[i * step - 1];
            shape = shape.max((p[2] - y[2]).abs().max((p[0].hypot(p[1]) - y[0].hypot(y[1])).abs()));
        }
        let torque = (rod.spatial_force_moment(x, rod.elements).1[2] - tip[17]).abs();
        println!("{:>3} elements: shape {shape:.2e} nm, end torque {torque:.2e} pN nm", rod.elements);
        errors.push((shape, torque));
    }
    let rates = ((errors[1].0 / errors[2].0).log2(), (errors[1].1 / errors[2].1).log2());
    println!("rates 48 → 96 elements: shape {:.2}, torque {:.2}", rates.0, rates.1);
    assert!(shot.last_change < 1e-7, "fixed point: last change {:e}", shot.last_change);
    // At the scheme's order from 48 to 96 elements (h⁴; measured 4.3, 4.3).
    assert!(rates.0 > 3.5 && rates.1 > 3.5, "rates {rates:?} ({errors:?})");
    // And within that discretisation error on the finest mesh (measured
    // 3.4e-5 nm and 2.2e-5 pN nm, 1/20 of the 48-element one).
    assert!(errors[2].0 < 1e-4 && errors[2].1 < 1e-4, "96 elements: {:?}", errors[2]);
}

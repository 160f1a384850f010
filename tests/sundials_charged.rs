//! SUNDIALS cross-check of the charged rod (issue 5, physics.md §3, §4):
//! KINSOL (exact Newton with the charged rod's own Jacobian densified, its
//! line search, explicit tolerances scaled by the rod's equation and
//! unknown scales) on the same discrete residual — rod + near-zone
//! stiffening + far-zone pair forces with the switched cutoff, parameter
//! the end rotation φ — from a perturbed start, at points along the
//! supercoiling branch: the straight twisted rod and points of the buckled
//! branch (phase condition and unfolding parameter included). Both sides
//! reach a scaled residual ≤ 1e−11 and agree to 1e−8 in the scaled max norm.
//!
//! Run: `cargo test --release --features sundials --test sundials_charged -- --nocapture`
#![cfg(feature = "sundials")]

#[path = "support/sundials.rs"]
mod sundials;

use rodkit::charged::branch;
use rodkit::charged::dna::{self, DnaScene};
use rodkit::charged::rod::ChargedRod;
use rodkit::continuation::newton::Start;
use rodkit::continuation::{Options, Problem};
use sundials::{kinsol_problem_root as kinsol_root, Context};

fn perturbed(x: &[f64], scales: &[f64], eps: f64) -> Vec<f64> {
    x.iter().zip(scales).enumerate().map(|(i, (v, s))| v + eps * s * (((i * 7919) % 97) as f64 / 48.5 - 1.0)).collect()
}

#[test]
fn kinsol_agrees_on_the_charged_residual() {
    let ctx = Context::new().unwrap();
    // 200 bp (68 nm) at 1 pN, 0.1 M, 24 elements of Gauss(2): n ≈ 950.
    let scene = DnaScene { base_pairs: 200, ..Default::default() };
    let rod = scene.rod(24, 2).unwrap();
    let charge = scene.charge();
    let opts = Options {
        target_lambda: Some(8.0),
        residual_tol: 1e-12,
        initial_step: 1.0,
        max_step: 2.0,
        detect_bifurcations: true,
        bifurcation_tol: 1e-8,
        ..Default::default()
    };
    let straight = branch::follow(
        &rod,
        &charge,
        Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true },
        None,
        &opts,
        |_| true,
    )
    .unwrap();
    assert!(!straight.bifurcations.is_empty(), "no buckling below φ = 8");
    let opts = Options { residual_tol: 1e-12, initial_step: 0.1, max_step: 0.3, max_steps: 16, ..Default::default() };
    let buckled = branch::switch(&rod, &charge, &straight, 0, 0, 0.02, &opts, |_| true).unwrap().0;
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

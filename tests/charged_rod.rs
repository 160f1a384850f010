//! The charged Kirchhoff rod (issue 5, physics.md §3.1): the electrostatic
//! term in the rod's collocation residual (src/electrostatics/rod.rs) and
//! the supercoiling branch driver (src/electrostatics/supercoil.rs).

use rodkit::continuation::{Options, Problem};
use rodkit::continuation::newton::Start;
use rodkit::electrostatics::rod::{ChargedRod, RodCharge};
use rodkit::electrostatics::supercoil::{self, DnaScene};
use rodkit::electrostatics::Screening;
use rodkit::rod::model::Rod;

/// A non-equilibrium state: stage and node positions on a tight coil
/// (radius 3, rise 3.4 per turn: turns ~3.4 apart, inside the cutoff),
/// quaternions, forces and moments pseudo-random.
fn coiled_state(rod: &Rod, radius: f64, rise: f64) -> Vec<f64> {
    let mut x = rod.straight_state();
    let per_turn = (4.0 * std::f64::consts::PI * std::f64::consts::PI * radius * radius + rise * rise).sqrt();
    let n = rod.unknowns();
    let mut seed = 12345u64;
    let mut rnd = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    };
    let block = 13 * (1 + rod.scheme.stages());
    let h = rod.element_length();
    let tab_c: Vec<f64> = match rod.scheme.stages() {
        2 => vec![0.5 - 3f64.sqrt() / 6.0, 0.5 + 3f64.sqrt() / 6.0],
        _ => unimplemented!(),
    };
    for k in 0..(n / 13) {
        let off = 13 * k;
        if off + 13 > n {
            break;
        }
        let (e, j) = (off / block, (off % block) / 13);
        let s = if j == 0 { e as f64 * h } else { (e as f64 + tab_c[j - 1]) * h };
        let t = 2.0 * std::f64::consts::PI * s / per_turn;
        x[off] = radius * t.cos();
        x[off + 1] = radius * t.sin();
        x[off + 2] = rise * s / per_turn;
        let q: Vec<f64> = (0..4).map(|_| rnd() + if true { 0.0 } else { 1.0 }).collect();
        let nq = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        for i in 0..4 {
            x[off + 3 + i] = q[i] / nq;
        }
        for i in 7..13 {
            x[off + i] = rnd();
        }
    }
    if let Some(c) = rod.end_cosine() {
        x[c] = 0.3;
    }
    x
}

fn small_scene() -> (Rod, RodCharge) {
    let scene = DnaScene { base_pairs: 200, salt: 0.01, ..Default::default() };
    let rod = scene.rod(20, 2).unwrap();
    let mut charge = scene.charge();
    charge.cutoff_tolerance = Some(1e-2);
    charge.screening.a = 1.6;
    charge.hard_core = Some(50.0);
    (rod, charge)
}

/// The Jacobian (rod + near-zone stiffening + far pairs with the cutoff's
/// switch + hard core + the end-rotation parameter) equals central
/// differences of the residual, column by column, to 1e-6 of the largest
/// entry of its row (differences of step 1e-6·scale: error ~1e-10).
#[test]
fn jacobian_matches_finite_differences() {
    let (rod, charge) = small_scene();
    let x = coiled_state(&rod, 3.0, 3.4);
    let mut p = ChargedRod::new(&rod, &charge, None, &x).unwrap();
    assert!(p.pairs() > 100, "pairs {}", p.pairs());
    let n = p.dim();
    let phi = 7.3;
    let pat = p.pattern().clone();
    let mut jx = vec![0.0; pat.nnz()];
    let mut jl = vec![0.0; n];
    p.jacobian(&x, phi, &mut jx, &mut jl);
    // Dense copy of J.
    let mut dense = vec![0.0; n * n];
    for col in 0..n {
        for k in pat.col_ptr[col]..pat.col_ptr[col + 1] {
            dense[pat.row_idx[k] * n + col] = jx[k];
        }
    }
    let row_max: Vec<f64> = (0..n).map(|i| (0..n).map(|j| dense[i * n + j].abs()).fold(jl[i].abs(), f64::max)).collect();
    let (us, _) = p.unknown_scales();
    let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
    let mut worst = 0.0f64;
    for col in 0..=n {
        let eps = 1e-6 * if col < n { us[col] } else { 1.0 };
        let mut xp = x.clone();
        let mut xm = x.clone();
        let (mut lp, mut lm) = (phi, phi);
        if col < n {
            xp[col] += eps;
            xm[col] -= eps;
        } else {
            lp += eps;
            lm -= eps;
        }
        p.residual(&xp, lp, &mut rp);
        p.residual(&xm, lm, &mut rm);
        for i in 0..n {
            let fd = (rp[i] - rm[i]) / (2.0 * eps);
            let an = if col < n { dense[i * n + col] } else { jl[i] };
            let e = (fd - an).abs() / row_max[i].max(1e-300);
            worst = worst.max(e);
            assert!(e < 1e-6, "J[{i}][{col}]: analytic {an:e}, differences {fd:e}");
        }
    }
    println!("worst relative Jacobian error {worst:e}");
}

/// Explore the DNA scene (printing).
#[test]
#[ignore]
fn explore_dna_scene() {
    let scene = DnaScene::default();
    let ne: usize = std::env::var("NE").ok().and_then(|v| v.parse().ok()).unwrap_or(170);
    let rod = scene.rod(ne, 2).unwrap();
    let mut charge = scene.charge();
    if std::env::var("NOCHARGE").is_ok() { charge.line_charge = 0.0; }
    println!("kT {} lB {} kappa {} lambda {} cutoff {:?}", scene.kt(), scene.bjerrum_length(), scene.kappa(), charge.line_charge, charge.cutoff(rod.length));
    let x0 = rod.straight_state();
    let opts = Options { target_lambda: Some(40.0), residual_tol: 1e-10, initial_step: 0.5, max_step: 2.0, detect_bifurcations: true, max_steps: 200, ..Default::default() };
    let t = std::time::Instant::now();
    let b = supercoil::follow(&rod, &charge, Start::Point { x: x0, lambda: 0.0, increasing: true }, None, &opts, |r| { eprintln!("straight φ {:.4} step {:.3e} res {:e} it {} σ {:?} det {}", r.lambda, r.step, r.residual, r.newton_iterations, r.smallest_singular_value, r.bordered_det_sign); true }).unwrap();
    println!("straight: {} records, {:?}, {:?}, {:.2?}", b.records.len(), b.stop, b.counts, t.elapsed());
    for bif in &b.bifurcations {
        println!("bifurcation at φ = {} ({} turns), multiplicity {}", bif.lambda, bif.lambda / (2.0 * std::f64::consts::PI), bif.multiplicity);
    }
    let opts = Options { residual_tol: 1e-10, initial_step: 0.05, max_step: 0.5, max_steps: 400, lambda_range: (0.0, 80.0), ..Default::default() };
    let t = std::time::Instant::now();
    let s = supercoil::switch(&rod, &charge, &b, 0, 0, 0.02, &opts, |r| { eprintln!("φ {:.4} res {:e} it {}", r.lambda, r.residual, r.newton_iterations); true }).unwrap();
    println!("buckled: {} records, {:?}, crossing {:?}, lists {}, {:?}, {:.2?}", s.records.len(), s.stop, s.crossing, s.pair_lists, s.counts, t.elapsed());
    for (r, x) in s.records.iter().zip(&s.states).step_by(5) {
        let o = supercoil::observables(&rod, x, r.lambda).unwrap();
        println!("{:8.4} turns  z {:8.3}  M {:8.3}  Tw {:8.4} Wr {:8.4}  sum-turns {:e}", o.turns, o.extension, o.torque, o.twist, o.writhe, o.twist + o.writhe - o.turns);
    }
}

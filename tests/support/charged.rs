//! Shared by the charged-rod tests: a non-equilibrium coiled state and the
//! Jacobian-against-central-differences check.
#![allow(dead_code)]

use rodkit::charged::dna::DnaScene;
use rodkit::charged::rod::{ChargedRod, RodCharge};
use rodkit::continuation::Problem;
use rodkit::rod::model::Rod;

/// 200 bp at 0.01 M on 20 elements of Gauss(2), cutoff at 1e-2, a = 1.6 nm
/// and a hard core: on [`coiled_state`] its pairs sit inside r_on, in the
/// cutoff's switch and in the hard core's range.
pub fn small_scene() -> (Rod, RodCharge) {
    let scene = DnaScene { base_pairs: 200, salt: 0.01, ..Default::default() };
    let rod = scene.rod(20, 2).unwrap();
    let mut charge = scene.charge();
    charge.cutoff_tolerance = Some(1e-2);
    charge.screening.a = 1.6;
    charge.hard_core = Some(50.0);
    (rod, charge)
}

/// The arc-length parametrised helix of radius `radius` rising `rise` a
/// turn, at arc length s.
pub fn helix(s: f64, radius: f64, rise: f64) -> [f64; 3] {
    let per_turn = (4.0 * std::f64::consts::PI * std::f64::consts::PI * radius * radius + rise * rise).sqrt();
    let t = 2.0 * std::f64::consts::PI * s / per_turn;
    [radius * t.cos(), radius * t.sin(), rise * s / per_turn]
}

/// A non-equilibrium state on any mesh (graded too): stage and node
/// positions on a tight coil (e.g. radius 3, rise 3.4 per turn: turns ~3.4
/// apart, inside the cutoff), quaternions, forces and moments
/// pseudo-random.
pub fn coiled_state(rod: &Rod, radius: f64, rise: f64) -> Vec<f64> {
    let mut x = rod.straight_state();
    let n = rod.unknowns();
    let mut seed = 12345u64;
    let mut rnd = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    };
    let block = 13 * (1 + rod.scheme.stages());
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
        let s = if j == 0 { rod.node_position(e) } else { rod.node_position(e) + tab_c[j - 1] * rod.element_h(e) };
        x[off..off + 3].copy_from_slice(&helix(s, radius, rise));
        let q: Vec<f64> = (0..4).map(|_| rnd()).collect();
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

/// The worst entry-wise error of the analytic Jacobian (x and the
/// parameter column) against central differences of the residual (step
/// 1e-6 of each unknown's scale), relative to the largest entry of its row;
/// panics above 1e-6.
pub fn jacobian_fd_error(p: &mut dyn Problem, x: &[f64], phi: f64) -> f64 {
    let n = p.dim();
    let pat = p.pattern().clone();
    let mut jx = vec![0.0; pat.nnz()];
    let mut jl = vec![0.0; n];
    p.jacobian(x, phi, &mut jx, &mut jl);
    // Dense copy of J.
    let mut dense = vec![0.0; n * n];
    for col in 0..n {
        for k in pat.col_ptr[col]..pat.col_ptr[col + 1] {
            dense[pat.row_idx[k] * n + col] = jx[k];
        }
    }
    let row_max: Vec<f64> =
        (0..n).map(|i| (0..n).map(|j| dense[i * n + j].abs()).fold(jl[i].abs(), f64::max)).collect();
    let (us, _) = p.unknown_scales();
    let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
    let mut worst = 0.0f64;
    for col in 0..=n {
        let eps = 1e-6 * if col < n { us[col] } else { 1.0 };
        let mut xp = x.to_vec();
        let mut xm = x.to_vec();
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
    worst
}

/// max over stages and components of |w_j p_j + ∂(E_far + E_hard)/∂r_j|
/// (central differences, step 1e-5 nm) relative to the component's largest
/// |w p|.
pub fn force_gradient_error(p: &mut ChargedRod, rod: &Rod, x: &[f64]) -> f64 {
    let f = p.force_densities(x);
    let pts = p.stage_points();
    let offsets: Vec<usize> = (0..rod.elements).flat_map(|e| [rod.node(e) + 13, rod.node(e) + 26]).collect();
    let mut worst = 0.0f64;
    for (j, &o) in offsets.iter().enumerate() {
        for c in 0..3 {
            let eps = 1e-5;
            let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
            xp[o + c] += eps;
            xm[o + c] -= eps;
            let (ep, em) = (p.energy(&xp), p.energy(&xm));
            let grad = ((ep.far + ep.hard_core) - (em.far + em.hard_core)) / (2.0 * eps);
            let scale = f.iter().zip(&pts).map(|(v, w)| (v[c] * w.1).abs()).fold(0.0, f64::max);
            worst = worst.max((pts[j].1 * f[j][c] + grad).abs() / scale);
        }
    }
    worst
}

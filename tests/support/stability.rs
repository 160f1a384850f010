//! The dense oracle of the stability count (tests/rod_stability.rs,
//! tests/supercoil_stability.rs): K = E_r A⁻¹ M′ formed with nalgebra's
//! dense LU of the Jacobian and its eigenvalues by the real Schur form.
#![allow(dead_code)]

use nalgebra::{Complex, DMatrix};
use rodkit::charged::rod::ChargedRod;
use rodkit::continuation::Problem;

/// The dense oracle at state x: K = E_r A⁻¹ M′ (A the dense Jacobian, M′
/// the metric's injection applied to unit force densities), its
/// eigenvalues θ, and the skew part ‖WK − (WK)ᵀ‖/‖WK‖ (K is W-self-adjoint
/// up to the scheme's non-variational part).
pub struct Dense {
    pub theta: Vec<Complex<f64>>,
    pub skew: f64,
}

pub fn dense(p: &mut ChargedRod, x: &[f64], phi: f64) -> Dense {
    let n = p.dim();
    let pattern = p.pattern().clone();
    let (mut jx, mut jl) = (vec![0.0; pattern.nnz()], vec![0.0; n]);
    p.jacobian(x, phi, &mut jx, &mut jl);
    let mut a = DMatrix::zeros(n, n);
    for j in 0..n {
        for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
            a[(pattern.row_idx[k], j)] = jx[k];
        }
    }
    let metric = p.stability_metric(x).expect("a charged rod has a stability metric");
    let m = metric.coordinates();
    let mut injected = DMatrix::zeros(n, m);
    let (mut unit, mut column) = (vec![0.0; m], vec![0.0; n]);
    for c in 0..m {
        unit.fill(0.0);
        unit[c] = 1.0;
        metric.inject(&unit, &mut column);
        injected.column_mut(c).copy_from_slice(&column);
    }
    let solved = a.lu().solve(&injected).expect("regular Jacobian");
    let mut k = DMatrix::from_fn(m, m, |i, j| solved[(metric.coords[i / 3] + i % 3, j)]);
    // With a phase condition (the buckled branch) the symmetric problem is
    // K on V₁ = v₀^⊥W (v₀ = e3 × r_j, the rotation about the axis): with
    // the W-orthogonal projector P = I − Σ v₀v₀ᵀW the dense operator is
    // PKP, whose eigenvalues are K's on V₁ and one θ = 0 for v₀ itself
    // (σ = ∞, left out by `Dense::sigma` with the axial directions). The
    // projector is formed here from the zero modes' values, densely,
    // independent of `Metric::project`.
    if !metric.zero_modes.is_empty() {
        let mut proj = DMatrix::<f64>::identity(m, m);
        for v in &metric.zero_modes {
            proj -= DMatrix::from_fn(m, m, |i, j| v[i] * v[j] * metric.weights[j / 3]);
        }
        k = &proj * k * &proj;
    }
    let wk = DMatrix::from_fn(m, m, |i, j| metric.weights[i / 3] * k[(i, j)]);
    let skew = (&wk - wk.transpose()).norm() / wk.norm();
    Dense { theta: k.complex_eigenvalues().iter().copied().collect(), skew }
}

impl Dense {
    /// σ = −1/θ of the eigenvalues the metric sees (|θ| above 1e-10 of the
    /// largest: the axial directions of the inextensible rod have θ = 0 to
    /// rounding, σ = ∞), ascending by real part.
    pub fn sigma(&self) -> Vec<Complex<f64>> {
        let largest = self.theta.iter().fold(0.0f64, |m, t| m.max(t.norm()));
        let mut s: Vec<Complex<f64>> =
            self.theta.iter().filter(|t| t.norm() > 1e-10 * largest).map(|t| -t.inv()).collect();
        s.sort_by(|a, b| a.re.total_cmp(&b.re));
        s
    }

    /// Unstable modes: σ < 0 above `floor` (the physical spectrum's lower
    /// bound: below it only the discretisation's spurious θ ≈ 0⁺, see
    /// `greenhill_counts`), and the count of those below it.
    pub fn unstable(&self, floor: f64) -> (usize, usize) {
        let s = self.sigma();
        let physical = s.iter().filter(|s| s.re < 0.0 && s.re >= floor).count();
        (physical, s.iter().filter(|s| s.re < floor).count())
    }
}

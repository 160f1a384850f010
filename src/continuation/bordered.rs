//! The bordered tangent B = [[R_x, R_Λ], [vᵀW]] of a continuation (W =
//! diag(1/(n s_i²), 1/s_Λ²), the arc-length metric of [`super::Scaling`]),
//! its sparse LU, and what both engines do with it: tangents, Newton
//! corrections, determinant signs, the smallest singular value.
//!
//! B is regular at folds (where R_x is singular) and singular at simple
//! bifurcation points, so det B changes sign exactly at bifurcations, and
//! with the tangent t (R_x t_x + R_Λ t_Λ = 0):
//!   det R_x = det B · t_Λ / ⟨v, t⟩_W,
//! so sign det R_x comes with no second factorisation. The last column and
//! row are stored dense (O(n) fill at most); the pattern is fixed, so the
//! column ordering is computed once.

use super::{Counts, Problem, Scaling};
use crate::error::{Error, Result};
use crate::sparse::{Pattern, SparseLu};
use crate::status::Status;

pub struct Bordered {
    n: usize,
    lu: SparseLu,
    values: Vec<f64>,
    /// Position in `values` of each entry of the problem's pattern.
    map: Vec<usize>,
    /// Positions of (i, n) for i < n, and of (n, j) for j ≤ n.
    last_col: Vec<usize>,
    last_row: Vec<usize>,
    jx: Vec<f64>,
    jl: Vec<f64>,
    /// The border used in the last factorisation.
    border_x: Vec<f64>,
    border_l: f64,
    factorised: bool,
    /// The singular-value monitor works on Ã = R B C (R: 1/equation scale,
    /// √n for the border row; C: unknown and Λ scales), so that σ_min does
    /// not depend on the units of the model: in raw units (pN, nm for DNA)
    /// a mode of a badly scaled row can sit below every buckling mode and
    /// hide their zero crossings. Ones until [`Bordered::set_monitor_scales`].
    row_scale: Vec<f64>,
    col_scale: Vec<f64>,
}

impl Bordered {
    pub fn new(pattern: &Pattern) -> Result<Self> {
        let n = pattern.n;
        let mut entries: Vec<(usize, usize)> = Vec::with_capacity(pattern.nnz() + 2 * n + 1);
        for j in 0..n {
            for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                entries.push((pattern.row_idx[k], j));
            }
        }
        entries.extend((0..=n).map(|i| (i, n)));
        entries.extend((0..n).map(|j| (n, j)));
        let big = Pattern::from_entries(n + 1, entries);
        let mut map = Vec::with_capacity(pattern.nnz());
        for j in 0..n {
            for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                map.push(big.position(pattern.row_idx[k], j).expect("entry kept"));
            }
        }
        let last_col = (0..n).map(|i| big.position(i, n).expect("dense column")).collect();
        let last_row = (0..=n).map(|j| big.position(n, j).expect("dense row")).collect();
        let values = vec![0.0; big.nnz()];
        Ok(Bordered {
            n,
            lu: SparseLu::new(big)?,
            values,
            row_scale: vec![1.0; n + 1],
            col_scale: vec![1.0; n + 1],
            map,
            last_col,
            last_row,
            jx: vec![0.0; pattern.nnz()],
            jl: vec![0.0; n],
            border_x: vec![0.0; n],
            border_l: 0.0,
            factorised: false,
        })
    }

    /// Evaluate the Jacobian at (x, Λ), border it with W·v and factorise.
    pub fn factorise_at<P: Problem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        lambda: f64,
        vx: &[f64],
        vl: f64,
        scaling: &Scaling,
        counts: &mut Counts,
    ) -> Result<()> {
        problem.jacobian(x, lambda, &mut self.jx, &mut self.jl);
        counts.jacobians += 1;
        self.factorise_border(vx, vl, scaling, counts)
    }

    /// Re-factorise the current Jacobian with another border.
    pub fn factorise_border(&mut self, vx: &[f64], vl: f64, scaling: &Scaling, counts: &mut Counts) -> Result<()> {
        self.values.fill(0.0);
        for (&p, &v) in self.map.iter().zip(&self.jx) {
            self.values[p] += v;
        }
        for (i, &p) in self.last_col.iter().enumerate() {
            self.values[p] = self.jl[i];
        }
        let mean = 1.0 / self.n.max(1) as f64;
        for j in 0..self.n {
            self.values[self.last_row[j]] = mean * vx[j] / (scaling.x[j] * scaling.x[j]);
        }
        self.values[self.last_row[self.n]] = vl / (scaling.lambda * scaling.lambda);
        self.border_x.copy_from_slice(vx);
        self.border_l = vl;
        self.factorised = false;
        self.lu.factorise(&self.values)?;
        counts.factorisations += 1;
        self.factorised = true;
        Ok(())
    }

    /// Solve B z = rhs in place (rhs has n + 1 entries).
    pub fn solve(&mut self, rhs: &mut [f64], counts: &mut Counts) {
        self.lu.solve(rhs);
        counts.solves += 1;
    }

    /// The unit tangent (in ⟨·,·⟩_W) from the current factorisation:
    /// B t = (0, 1), normalised, oriented along the border (⟨t, v⟩_W > 0).
    pub fn tangent(&mut self, scaling: &Scaling, counts: &mut Counts) -> Result<(Vec<f64>, f64)> {
        let mut z = vec![0.0; self.n + 1];
        z[self.n] = 1.0;
        self.solve(&mut z, counts);
        let tl = z[self.n];
        let tx = &z[..self.n];
        let norm = scaling.norm(tx, tl);
        if !(norm.is_finite() && norm > 0.0) {
            return Err(Error::new(Status::ErrNotConverged, "continuation: no tangent (singular bordered system)"));
        }
        let sign = if scaling.dot(tx, tl, &self.border_x, self.border_l) < 0.0 { -1.0 } else { 1.0 };
        Ok((tx.iter().map(|v| sign * v / norm).collect(), sign * tl / norm))
    }

    /// (sign det B, sign det R_x) for the current factorisation and the
    /// tangent t computed from it.
    /// Negative pivots of the factorised bordered tangent (see
    /// [`crate::sparse::SparseLu::negative_pivots`]).
    pub fn negative_pivots(&self) -> usize {
        self.lu.negative_pivots()
    }

    pub fn determinant_signs(&self, scaling: &Scaling, tx: &[f64], tl: f64) -> (f64, f64) {
        let (sign_b, _) = self.lu.determinant_sign_and_log();
        let vt = scaling.dot(tx, tl, &self.border_x, self.border_l);
        let sign_j = sign_b * (tl * vt).signum();
        (sign_b, if tl == 0.0 { 0.0 } else { sign_j })
    }

    /// Scale the singular-value monitor by the problem's equation scales
    /// and the continuation's unknown scales (see the field's note).
    pub fn set_monitor_scales(&mut self, equation_scales: &[f64], scaling: &Scaling) {
        let n = self.n;
        for i in 0..n {
            let e = equation_scales[i];
            self.row_scale[i] = if e > 0.0 && e.is_finite() { 1.0 / e } else { 1.0 };
            let s = scaling.x[i];
            self.col_scale[i] = if s > 0.0 && s.is_finite() { s } else { 1.0 };
        }
        self.row_scale[n] = (n.max(1) as f64).sqrt();
        self.col_scale[n] = if scaling.lambda > 0.0 && scaling.lambda.is_finite() { scaling.lambda } else { 1.0 };
    }

    /// (ÃᵀÃ)⁻¹ w = C⁻¹ B⁻¹ R⁻² B⁻ᵀ C⁻¹ w, in place.
    fn inverse_normal(&mut self, w: &mut [f64], counts: &mut Counts) {
        for (a, c) in w.iter_mut().zip(&self.col_scale) {
            *a /= c;
        }
        self.lu.solve_transpose(w);
        for (a, r) in w.iter_mut().zip(&self.row_scale) {
            *a /= r * r;
        }
        self.lu.solve(w);
        for (a, c) in w.iter_mut().zip(&self.col_scale) {
            *a /= c;
        }
        counts.solves += 2;
    }

    /// Ã v into w.
    fn scaled_mul(&self, v: &[f64], w: &mut [f64]) {
        let cv: Vec<f64> = v.iter().zip(&self.col_scale).map(|(a, c)| a * c).collect();
        self.lu.pattern().mul_vec(&self.values, &cv, w);
        for (a, r) in w.iter_mut().zip(&self.row_scale) {
            *a *= r;
        }
    }

    /// Smallest singular value of B by inverse iteration on BᵀB (a few
    /// steps from a fixed start; an estimate, good to a few digits, which
    /// is what a bifurcation monitor needs).
    pub fn smallest_singular_value(&mut self, counts: &mut Counts) -> f64 {
        let m = self.n + 1;
        let mut v: Vec<f64> = (0..m).map(|i| 1.0 + 0.37 * ((i * 7919) % 101) as f64 / 101.0).collect();
        let mut sigma = f64::INFINITY;
        for _ in 0..8 {
            let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
            v.iter_mut().for_each(|a| *a /= norm);
            let mut w = v.clone();
            self.inverse_normal(&mut w, counts);
            // ‖(BᵀB)⁻¹ v‖ → 1/σ_min² for the dominant direction.
            let growth = w.iter().map(|a| a * a).sum::<f64>().sqrt();
            let next = 1.0 / growth.sqrt();
            let converged = (next - sigma).abs() <= 1e-3 * next;
            sigma = next;
            v = w;
            if converged {
                break;
            }
        }
        sigma
    }

    /// The k smallest singular values of B (ascending) and their right
    /// singular vectors (unit in the Euclidean norm, n + 1 long), by
    /// subspace inverse iteration on BᵀB with a Rayleigh–Ritz step.
    pub fn smallest_singular_vectors(&mut self, k: usize, counts: &mut Counts) -> (Vec<f64>, Vec<Vec<f64>>) {
        self.smallest_singular_vectors_to(k, 1e-10, 30, counts)
    }

    /// [`Bordered::smallest_singular_vectors`] with the Ritz values'
    /// relative tolerance and an iteration cap (a monitor needs a few
    /// digits; null vectors of a located point need many).
    pub fn smallest_singular_vectors_to(
        &mut self,
        k: usize,
        tol: f64,
        max_iterations: usize,
        counts: &mut Counts,
    ) -> (Vec<f64>, Vec<Vec<f64>>) {
        let m = self.n + 1;
        let mut v: Vec<Vec<f64>> = (0..k)
            .map(|c| (0..m).map(|i| (((i + 1) * (c + 3) * 7919) % 1009) as f64 / 1009.0 - 0.5).collect())
            .collect();
        orthonormalise(&mut v);
        let mut sigma = vec![f64::INFINITY; k];
        for _ in 0..max_iterations {
            let mut w = v.clone();
            for col in &mut w {
                self.inverse_normal(col, counts);
            }
            // Rayleigh–Ritz on (BᵀB)⁻¹: G = Vᵀ W.
            let g = nalgebra::DMatrix::from_fn(k, k, |a, b| dot(&v[a], &w[b]));
            let eig = nalgebra::SymmetricEigen::new((&g + g.transpose()) * 0.5);
            let mut order: Vec<usize> = (0..k).collect();
            order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
            let next: Vec<f64> = order.iter().map(|&i| 1.0 / eig.eigenvalues[i].max(1e-300).sqrt()).collect();
            // Rotate W into the Ritz basis, then orthonormalise.
            let mut rotated: Vec<Vec<f64>> = order
                .iter()
                .map(|&i| (0..m).map(|r| (0..k).map(|c| w[c][r] * eig.eigenvectors[(c, i)]).sum()).collect())
                .collect();
            orthonormalise(&mut rotated);
            let converged = next.iter().zip(&sigma).all(|(a, b)| (a - b).abs() <= tol * a.max(1e-300));
            sigma = next;
            v = rotated;
            if converged {
                break;
            }
        }
        // The Ritz values of (BᵀB)⁻¹ lose the larger singular values to
        // round-off when the smallest are near zero (entries ~1/σ_min²):
        // measure each converged vector directly, σ_i = ‖B v_i‖.
        let mut w = vec![0.0; m];
        for (s, vi) in sigma.iter_mut().zip(&v) {
            self.scaled_mul(vi, &mut w);
            *s = dot(&w, &w).sqrt();
        }
        // Back to the unknowns' own units (x = C ṽ).
        let v = v.into_iter().map(|vi| vi.iter().zip(&self.col_scale).map(|(a, c)| a * c).collect()).collect();
        (sigma, v)
    }

    /// σ_min signed by the alignment of its left and right singular
    /// vectors: near a real eigenvalue crossing zero, B v ≈ λ v, so the sign
    /// is sign(λ) and the function changes sign at every bifurcation,
    /// double ones included (where det B keeps its sign).
    pub fn signed_smallest_singular_value(&mut self, counts: &mut Counts) -> f64 {
        // Four digits: the monitor looks for sign changes and dips.
        let (sigma, v) = self.smallest_singular_vectors_to(2, 1e-4, 30, counts);
        let mut w = vec![0.0; self.n + 1];
        let scaled: Vec<f64> = v[0].iter().zip(&self.col_scale).map(|(a, c)| a / c).collect();
        self.scaled_mul(&scaled, &mut w);
        let align: f64 = w.iter().zip(&scaled).map(|(a, b)| a * b).sum();
        if align < 0.0 {
            -sigma[0]
        } else {
            sigma[0]
        }
    }

    pub fn factorisations(&self) -> usize {
        self.lu.factorisations
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Modified Gram–Schmidt, in place.
fn orthonormalise(v: &mut [Vec<f64>]) {
    for i in 0..v.len() {
        for j in 0..i {
            let (head, tail) = v.split_at_mut(i);
            let c = dot(&tail[0], &head[j]);
            for (a, b) in tail[0].iter_mut().zip(&head[j]) {
                *a -= c * b;
            }
        }
        let norm = dot(&v[i], &v[i]).sqrt();
        if norm > 0.0 {
            v[i].iter_mut().for_each(|a| *a /= norm);
        }
    }
}

//! The bordered tangent B = [[R_x, R_Λ], [vᵀW, v_Λ/s_Λ²]] of a continuation,
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
    pub fn factorise_at<P: Problem + ?Sized>(&mut self, problem: &mut P, x: &[f64], lambda: f64, vx: &[f64], vl: f64,
                                               scaling: &Scaling, counts: &mut Counts) -> Result<()> {
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
    pub fn determinant_signs(&self, scaling: &Scaling, tx: &[f64], tl: f64) -> (f64, f64) {
        let (sign_b, _) = self.lu.determinant_sign_and_log();
        let vt = scaling.dot(tx, tl, &self.border_x, self.border_l);
        let sign_j = sign_b * (tl * vt).signum();
        (sign_b, if tl == 0.0 { 0.0 } else { sign_j })
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
            self.lu.solve_transpose(&mut w);
            self.lu.solve(&mut w);
            counts.solves += 2;
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

    pub fn factorisations(&self) -> usize {
        self.lu.factorisations
    }
}

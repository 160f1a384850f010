//! The bordered tangent B = [[R_x, R_Λ], [vᵀW]] of a continuation (W =
//! diag(1/(n s_i²), 1/s_Λ²), the arc-length metric of [`super::Scaling`])
//! and what both engines do with it: tangents, Newton corrections,
//! determinant signs, the smallest singular value. The matrix itself is a
//! [`BorderedLu`]; this layer evaluates the problem's Jacobian into it,
//! writes the metric's border and counts the work.
//!
//! B is regular at folds (where R_x is singular) and singular at simple
//! bifurcation points, so det B changes sign exactly at bifurcations, and
//! with the tangent t (R_x t_x + R_Λ t_Λ = 0):
//!   det R_x = det B · t_Λ / ⟨v, t⟩_W,
//! so sign det R_x comes with no second factorisation.

use super::{Counts, Problem, Scaling};
use crate::error::{Error, Result};
use crate::linalg::bordered::{BorderedLu, Settle, Start};
use crate::linalg::Pattern;
use crate::status::Status;
use std::time::Instant;

/// What a factorisation of the bordered matrix is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Factors {
    /// The factorisation of a point whose determinant signs and pivots are
    /// read from it (its tangent, its record, a resume): simplicial
    /// whatever the pattern.
    Exact,
    /// Solves only (the trial points of a bifurcation's location, a point
    /// whose signs are taken elsewhere): the pattern's fastest kind.
    ForSolves,
}

pub struct Bordered {
    n: usize,
    /// Entries of A's pattern (`jx`'s length once sized).
    nnz: usize,
    lu: BorderedLu,
    jx: Vec<f64>,
    jl: Vec<f64>,
    /// The border row W·v of the last factorisation (x part).
    row: Vec<f64>,
    /// The border used in the last factorisation.
    border_x: Vec<f64>,
    border_l: f64,
    /// B⁻¹ e_{n+1} of the current factorisation (computed on demand: a
    /// solve with another border by Sherman–Morrison), and whether it is.
    last_column: Vec<f64>,
    last_column_known: bool,
    /// Scratch: the other border's row.
    other_row: Vec<f64>,
    /// [`super::Options::lean_monitor`].
    lean_monitor: bool,
}

impl Bordered {
    pub fn new(pattern: &Pattern) -> Result<Self> {
        Self::with_trailing(pattern, 0)
    }

    /// As [`Bordered::new`] for a problem whose last `trailing` unknowns
    /// reach across its Jacobian ([`super::Problem::trailing`]).
    pub fn with_trailing(pattern: &Pattern, trailing: usize) -> Result<Self> {
        Self::with_private_blocks(pattern, trailing, &[])
    }

    /// As [`Bordered::with_trailing`], the unknowns of each of `blocks`
    /// private to it ([`super::Problem::private_blocks`]): condensed.
    pub fn with_private_blocks(pattern: &Pattern, trailing: usize, blocks: &[Vec<usize>]) -> Result<Self> {
        let n = pattern.n;
        Ok(Bordered {
            n,
            nnz: pattern.nnz(),
            lu: BorderedLu::with_private_blocks(pattern, trailing, blocks)?,
            // Sized by the first factorisation, which writes it whole.
            jx: Vec::new(),
            jl: vec![0.0; n],
            row: vec![0.0; n],
            border_x: vec![0.0; n],
            border_l: 0.0,
            last_column: vec![0.0; n + 1],
            last_column_known: false,
            other_row: vec![0.0; n + 1],
            lean_monitor: true,
        })
    }

    /// See [`super::Options::lean_monitor`].
    pub fn set_lean_monitor(&mut self, lean: bool) {
        self.lean_monitor = lean;
    }

    /// Whether the monitor is lean ([`super::Options::lean_monitor`]).
    pub fn lean_monitor(&self) -> bool {
        self.lean_monitor
    }

    /// Where a location's singular-vector iterations start, and when the
    /// monitor stops ([`super::Options::lean_monitor`]).
    fn monitor_policy(&self) -> (Start, Settle) {
        if self.lean_monitor {
            (Start::Previous, Settle::First)
        } else {
            (Start::Fixed, Settle::All)
        }
    }

    /// Evaluate the Jacobian at (x, Λ), border it with W·v and factorise
    /// as `factors` asks: simplicial for a point whose determinant signs
    /// and pivots are read (a record, a resume), else the pattern's fastest
    /// kind ([`crate::linalg::LuKind`]).
    #[allow(clippy::too_many_arguments)]
    pub fn factorise_at<P: Problem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        lambda: f64,
        v: (&[f64], f64),
        scaling: &Scaling,
        counts: &mut Counts,
        factors: Factors,
    ) -> Result<()> {
        self.evaluate(problem, x, lambda, counts);
        self.factorise_as(v, scaling, counts, factors == Factors::Exact)
    }

    fn evaluate<P: Problem + ?Sized>(&mut self, problem: &mut P, x: &[f64], lambda: f64, counts: &mut Counts) {
        let t = Instant::now();
        self.size_jacobian();
        problem.jacobian(x, lambda, &mut self.jx, &mut self.jl);
        counts.times.jacobians += t.elapsed();
        counts.jacobians += 1;
    }

    /// The Jacobian's array, sized on first use (the first evaluation
    /// writes it whole: zeroing it at set-up as well was wasted).
    fn size_jacobian(&mut self) {
        if self.jx.len() != self.nnz {
            self.jx = vec![0.0; self.nnz];
        }
    }

    /// Re-factorise the current Jacobian with another border (for solves).
    pub fn factorise_border(&mut self, vx: &[f64], vl: f64, scaling: &Scaling, counts: &mut Counts) -> Result<()> {
        self.factorise_as((vx, vl), scaling, counts, false)
    }

    fn factorise_as(
        &mut self,
        (vx, vl): (&[f64], f64),
        scaling: &Scaling,
        counts: &mut Counts,
        exact: bool,
    ) -> Result<()> {
        // (A border factorised before any Jacobian: a zero matrix, which
        // the LU refuses.)
        self.size_jacobian();
        let mean = 1.0 / self.n.max(1) as f64;
        for j in 0..self.n {
            self.row[j] = mean * vx[j] / (scaling.x[j] * scaling.x[j]);
        }
        self.border_x.copy_from_slice(vx);
        self.border_l = vl;
        self.last_column_known = false;
        let t = Instant::now();
        let corner = vl / (scaling.lambda * scaling.lambda);
        let result = if exact {
            self.lu.factorise_exact(&self.jx, &self.jl, &self.row, corner)
        } else {
            self.lu.factorise(&self.jx, &self.jl, &self.row, corner)
        };
        let dt = t.elapsed();
        counts.times.factorisations += dt;
        result?;
        counts.factorisations += 1;
        if self.lu.block_elimination() {
            counts.block_eliminations += 1;
            counts.block_time += dt;
        }
        if self.lu.last_condensed() {
            counts.condensed += 1;
        }
        Ok(())
    }

    /// See [`crate::linalg::sparse::SparseLu::prefer`].
    pub fn prefer(&mut self, order: crate::linalg::sparse::ColumnOrder) {
        self.lu.prefer(order);
    }

    /// Whether the last factorisation is a block elimination on the
    /// Jacobian's supernodal LU ([`crate::linalg::bordered::BorderedLu::block_elimination`]).
    pub fn block_elimination(&self) -> bool {
        self.lu.block_elimination()
    }

    /// See [`crate::linalg::bordered::BorderedLu::prefer_kind`].
    pub fn prefer_kind(&mut self, kind: crate::linalg::LuKind) {
        self.lu.prefer_kind(kind);
    }

    /// The column order its factorisations take.
    pub fn column_order(&self) -> crate::linalg::sparse::ColumnOrder {
        self.lu.column_order()
    }

    /// Whether a factorisation is in hand (the last one succeeded): a
    /// chord correction starts on it, else factorises.
    pub fn factorised(&self) -> bool {
        self.lu.factorised()
    }

    /// Solve B' z = rhs in place, B' the factorised matrix with its border
    /// row replaced by that of `v` (W·v, as [`Bordered::factorise_border`]
    /// writes it): B' = B + e_{n+1} dᵀ, d the rows' difference, so
    /// z = y − w (dᵀy)/(1 + dᵀw) with y = B⁻¹rhs and w = B⁻¹e_{n+1}
    /// (Sherman–Morrison; w is one more solve, kept for the factorisation).
    /// The chord corrector's step on the last point's factorisation: its
    /// border is the tangent of the point before, the corrector's plane
    /// the new tangent's — a difference of the order of the step that
    /// slowed the chord iterations as much as the Jacobian's change did.
    /// Falls back to B when 1 + dᵀw is not safely away from zero.
    pub fn solve_with_border(&mut self, rhs: &mut [f64], v: (&[f64], f64), scaling: &Scaling, counts: &mut Counts) {
        let n = self.n;
        let mean = 1.0 / n.max(1) as f64;
        let mut differs = v.1 != self.border_l;
        for j in 0..n {
            self.other_row[j] = mean * v.0[j] / (scaling.x[j] * scaling.x[j]) - self.row[j];
            differs |= v.0[j] != self.border_x[j];
        }
        self.other_row[n] = (v.1 - self.border_l) / (scaling.lambda * scaling.lambda);
        if !differs {
            return self.solve(rhs, counts);
        }
        if !self.last_column_known {
            self.last_column.fill(0.0);
            self.last_column[n] = 1.0;
            let t = Instant::now();
            self.lu.solve(&mut self.last_column);
            counts.times.solves += t.elapsed();
            counts.solves += 1;
            self.last_column_known = true;
        }
        self.solve(rhs, counts);
        let d = &self.other_row;
        let dw: f64 = d.iter().zip(&self.last_column).map(|(a, b)| a * b).sum();
        let dy: f64 = d.iter().zip(rhs.iter()).map(|(a, b)| a * b).sum();
        let denominator = 1.0 + dw;
        if !(denominator.abs() > 1e-8 && denominator.is_finite()) {
            return;
        }
        let c = dy / denominator;
        for (z, w) in rhs.iter_mut().zip(&self.last_column) {
            *z -= c * w;
        }
    }

    /// Solve B z = rhs in place (rhs has n + 1 entries).
    pub fn solve(&mut self, rhs: &mut [f64], counts: &mut Counts) {
        let t = Instant::now();
        self.lu.solve(rhs);
        counts.times.solves += t.elapsed();
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

    /// Solve R_x Z = F in place for the k columns of `rhs` (column-major,
    /// n×k) with the current factorisation, unrefined
    /// ([`BorderedLu::solve_inner_many`]): false when R_x is singular to
    /// working precision or nothing is factorised.
    pub fn solve_inner_many(&mut self, rhs: &mut [f64], k: usize, counts: &mut Counts) -> bool {
        let t = Instant::now();
        let solved = self.lu.solve_inner_many(rhs, k);
        counts.times.solves += t.elapsed();
        counts.solves += k;
        solved
    }

    /// Negative pivots of the factorised bordered tangent (see
    /// [`crate::linalg::SparseLu::negative_pivots`]).
    pub fn negative_pivots(&mut self) -> usize {
        self.lu.negative_pivots()
    }

    /// (sign det B, sign det R_x) for the current factorisation and the
    /// tangent t computed from it.
    pub fn determinant_signs(&mut self, scaling: &Scaling, tx: &[f64], tl: f64) -> (f64, f64) {
        let sign_b = self.lu.determinant_sign();
        (sign_b, sign_b * self.orientation(scaling, tx, tl))
    }

    /// sign(t_Λ ⟨v, t⟩_W) for the current factorisation's border v and
    /// the tangent t computed from it (0 when t_Λ = 0): sign det R_x =
    /// sign det B times this.
    pub fn orientation(&self, scaling: &Scaling, tx: &[f64], tl: f64) -> f64 {
        if tl == 0.0 {
            return 0.0;
        }
        (tl * scaling.dot(tx, tl, &self.border_x, self.border_l)).signum()
    }

    /// B's entries of the current matrix (see [`BorderedLu::values`]).
    pub fn values(&self) -> &[f64] {
        self.lu.values()
    }

    /// Whether the tangent is factorised by condensation
    /// ([`BorderedLu::with_private_blocks`]).
    pub fn condensed(&self) -> bool {
        self.lu.condensed()
    }

    /// See [`BorderedLu::signs_in_hand`].
    pub fn signs_in_hand(&self) -> bool {
        self.lu.signs_in_hand()
    }

    /// sign det B of the current factorisation.
    pub fn determinant_sign(&mut self) -> f64 {
        self.lu.determinant_sign()
    }

    /// See [`BorderedLu::exact_twin`].
    pub fn exact_twin(&self) -> Result<crate::linalg::SparseLu> {
        self.lu.exact_twin()
    }

    /// See [`BorderedLu::records_take`].
    pub fn records_take(&mut self, order: crate::linalg::sparse::ColumnOrder) {
        self.lu.records_take(order);
    }

    /// Scale the singular-value monitor by the problem's equation scales
    /// (rows: 1/e_i, √n for the border row) and the continuation's unknown
    /// scales (columns), so that σ_min does not depend on the units of the
    /// model.
    pub fn set_monitor_scales(&mut self, equation_scales: &[f64], scaling: &Scaling) {
        let n = self.n;
        let mut row = vec![1.0; n + 1];
        let mut col = vec![1.0; n + 1];
        for i in 0..n {
            let e = equation_scales[i];
            row[i] = if e > 0.0 && e.is_finite() { 1.0 / e } else { 1.0 };
            let s = scaling.x[i];
            col[i] = if s > 0.0 && s.is_finite() { s } else { 1.0 };
        }
        row[n] = (n.max(1) as f64).sqrt();
        col[n] = if scaling.lambda > 0.0 && scaling.lambda.is_finite() { scaling.lambda } else { 1.0 };
        self.lu.set_scales(&row, &col);
    }

    /// Smallest singular value of the (scaled) bordered tangent.
    pub fn smallest_singular_value(&mut self, counts: &mut Counts) -> f64 {
        let (t, before) = (Instant::now(), counts.solves);
        let sigma = self.lu.smallest_singular_value(&mut counts.solves);
        counts.monitor_solves += counts.solves - before;
        counts.times.monitor += t.elapsed();
        sigma
    }

    /// The k smallest singular values (ascending) and right singular
    /// vectors, to 1e-10 (the null vectors of a located point), started
    /// from the location's last monitor vectors when the monitor is lean.
    pub fn smallest_singular_vectors(&mut self, k: usize, counts: &mut Counts) -> (Vec<f64>, Vec<Vec<f64>>) {
        let (t, before) = (Instant::now(), counts.solves);
        let start = self.monitor_policy().0;
        let out = self.lu.smallest_singular_vectors(k, (1e-10, 30), start, &mut counts.solves);
        counts.monitor_solves += counts.solves - before;
        counts.times.monitor += t.elapsed();
        out
    }

    /// σ_min signed by the alignment of its singular vectors: it changes
    /// sign at every bifurcation, double ones included. From a fixed start
    /// (a record's: its value depends on the matrix alone), or at a
    /// location's trial points (`trial`) from the last trial's vectors
    /// when the monitor is lean.
    pub fn signed_smallest_singular_value(&mut self, trial: bool, counts: &mut Counts) -> f64 {
        let (t, before) = (Instant::now(), counts.solves);
        let (start, settle) = self.monitor_policy();
        let start = if trial { start } else { Start::Fixed };
        let sigma = self.lu.signed_smallest_singular_value((start, settle), &mut counts.solves);
        counts.monitor_solves += counts.solves - before;
        counts.times.monitor += t.elapsed();
        sigma
    }

    /// See [`BorderedLu::singular_floor`].
    pub fn singular_floor(&self) -> f64 {
        self.lu.singular_floor()
    }

    /// Entries of L + U of the last factorisation (0 before the first).
    pub fn fill(&self) -> usize {
        self.lu.fill()
    }

    /// Entries of B (the Jacobian's pattern with the dense border).
    pub fn nnz(&self) -> usize {
        self.lu.nnz()
    }

    /// Whether the LU keeps the natural column order (else COLAMD's).
    pub fn natural_order(&self) -> bool {
        self.lu.natural_order()
    }

    pub fn factorisations(&self) -> usize {
        self.lu.factorisations()
    }
}

//! Sparse systems: equations with a sparse Jacobian of fixed pattern
//! ([`SparseJacobian`]) and the Newton step by its sparse LU, the ordering
//! computed once ([`SparseDirect`]).

use super::{Equations, Iterate, LinearSolve, LinearStep, Work};
use crate::error::Result;
use crate::linalg::{Pattern, SparseLu};

/// Equations with a sparse Jacobian and typical magnitudes.
pub trait SparseJacobian: Equations {
    /// The structure of ∂F/∂x (fixed).
    fn pattern(&self) -> &Pattern;
    /// ∂F/∂x at x, in the pattern's order.
    fn jacobian(&mut self, x: &[f64], values: &mut [f64]);
    /// Typical magnitude of each equation (tolerances are relative to them).
    fn equation_scales(&self) -> Vec<f64>;
    /// Typical magnitude of each unknown.
    fn unknown_scales(&self) -> Vec<f64>;
}

/// The exact Newton step from a fresh Jacobian and its sparse LU at every
/// iteration.
pub struct SparseDirect {
    lu: SparseLu,
    values: Vec<f64>,
    pub work: Work,
}

impl SparseDirect {
    pub fn new(pattern: &Pattern) -> Result<Self> {
        Ok(SparseDirect {
            lu: SparseLu::new(pattern.clone())?,
            values: vec![0.0; pattern.nnz()],
            work: Work::default(),
        })
    }
}

impl<E: SparseJacobian + ?Sized> LinearSolve<E> for SparseDirect {
    fn step(&mut self, eq: &mut E, x: &[f64], f: &[f64], _it: &Iterate, delta: &mut [f64]) -> Result<LinearStep> {
        eq.jacobian(x, &mut self.values);
        self.work.jacobians += 1;
        self.lu.factorise(&self.values)?;
        self.work.factorisations += 1;
        for (d, v) in delta.iter_mut().zip(f) {
            *d = -v;
        }
        self.lu.solve(delta);
        self.work.solves += 1;
        Ok(LinearStep { eta: 0.0, fresh: true })
    }
}

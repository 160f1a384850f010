//! Single equilibria of a continuation problem at a fixed Λ, by the one
//! Newton iteration of [`crate::nonlinear`]: the damped sparse direct
//! Newton ([`damped_newton`]) and Newton–Krylov ([`newton_krylov`]).
//! [`AtFixed`] is the problem at that Λ as the nonlinear solvers see it.

use super::{Counts, Problem};
use crate::error::{self, Result};
use crate::linalg::Pattern;
use crate::nonlinear::krylov::{self, BandPreconditioner, KrylovOptions, KrylovReport};
use crate::nonlinear::sparse::{SparseDirect, SparseJacobian};
use crate::nonlinear::{self, Backtracking, Equations, Norm, ResidualTest};

/// R(·, Λ) = 0 at a fixed Λ, counting its residual evaluations.
pub struct AtFixed<'p, P: ?Sized> {
    problem: &'p mut P,
    lambda: f64,
    jl: Vec<f64>,
    /// Residual evaluations so far.
    pub residuals: usize,
}

impl<'p, P: Problem + ?Sized> AtFixed<'p, P> {
    pub fn new(problem: &'p mut P, lambda: f64) -> Self {
        let n = problem.dim();
        AtFixed { problem, lambda, jl: vec![0.0; n], residuals: 0 }
    }
}

impl<P: Problem + ?Sized> Equations for AtFixed<'_, P> {
    fn dim(&self) -> usize {
        self.problem.dim()
    }

    fn residual(&mut self, x: &[f64], f: &mut [f64]) -> Result<bool> {
        self.problem.residual(x, self.lambda, f);
        self.residuals += 1;
        Ok(true)
    }
}

impl<P: Problem + ?Sized> SparseJacobian for AtFixed<'_, P> {
    fn pattern(&self) -> &Pattern {
        self.problem.pattern()
    }

    fn jacobian(&mut self, x: &[f64], values: &mut [f64]) {
        self.problem.jacobian(x, self.lambda, values, &mut self.jl);
    }

    fn equation_scales(&self) -> Vec<f64> {
        self.problem.equation_scales()
    }

    fn unknown_scales(&self) -> Vec<f64> {
        self.problem.unknown_scales().0
    }
}

/// Newton on R(x, Λ) = 0 at fixed Λ with the exact sparse Jacobian and a
/// full LU (its ordering chosen once), damped: the step is halved (at most
/// 12 times) until the scaled max residual falls by the Armijo factor (an
/// exact Newton step is a descent direction in any norm). The
/// continuation's corrector ([`super::corrector::correct`]) is undamped —
/// it has a predictor and small steps; for one equilibrium from a farther
/// guess it failed next to a buckling point (the DNA scene's point re-solved
/// with base pairs, a 0.9 nm move), where this converges in 6 iterations.
/// Returns (iterations, final max |R_i|/d_i), at most 40 iterations;
/// non-convergence is ErrNotConverged, a non-finite residual
/// ErrNonFiniteResult.
pub fn damped_newton<P: Problem + ?Sized>(
    problem: &mut P,
    x: &mut [f64],
    lambda: f64,
    tol: f64,
    counts: &mut Counts,
) -> Result<(usize, f64)> {
    let n = problem.dim();
    error::dimension("Newton state length", x.len() as i64, n as i64, n as i64)?;
    let d = problem.equation_scales();
    let mut linear = SparseDirect::new(problem.pattern())?;
    let mut eq = AtFixed::new(problem, lambda);
    let mut search = Backtracking::new(d.clone(), Norm::Max, 12);
    let mut test = ResidualTest::new(d, tol, "direct Newton");
    let result = nonlinear::solve(&mut eq, x, &mut linear, &mut search, &mut test, 40);
    counts.residuals += eq.residuals;
    counts.add_work(&linear.work);
    result.map(|r| (r.iterations, r.norm))
}

/// R(x, Λ) = 0 at fixed Λ from `x` (overwritten with the solution) by
/// Newton–Krylov ([`crate::nonlinear::krylov`]) with the lagged band
/// preconditioner `pre`, its Jacobians from `jacobian_source` (None: the
/// problem itself; for a model without a usable Jacobian, a cheaper model
/// on the same pattern). Non-convergence is ErrNotConverged; a non-finite
/// residual is ErrNonFiniteResult.
pub fn newton_krylov<P: Problem + ?Sized>(
    problem: &mut P,
    jacobian_source: Option<&mut dyn Problem>,
    pre: &mut BandPreconditioner,
    x: &mut [f64],
    lambda: f64,
    opts: &KrylovOptions,
) -> Result<KrylovReport> {
    let mut eq = AtFixed::new(problem, lambda);
    let mut source = jacobian_source.map(|q| AtFixed::new(q, lambda));
    let mut report = krylov::solve(&mut eq, source.as_mut().map(|q| q as &mut dyn SparseJacobian), pre, x, opts)?;
    report.counts.residuals = eq.residuals;
    Ok(report)
}

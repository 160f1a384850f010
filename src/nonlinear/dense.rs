//! Small dense systems (tens of unknowns: the tube walls): a dense LU of
//! the caller's Jacobian or of forward differences ([`DenseLu`]), kept
//! while it contracts the residual (chord iterations) when asked, with
//! Armijo backtracking on the 2-norm that also shortens steps leaving the
//! domain. [`solve`] and [`solve_with_jacobian`] are the tube solvers'
//! entry points; scaling is the caller's (unknowns and residuals O(1), the
//! `typical` sizes set the difference steps and the step test).

use super::{Backtracking, Equations, Iterate, LinearSolve, LinearStep, Norm, StepTest};
use crate::error::{Error, Result};
use crate::status::Status;
use nalgebra::{DMatrix, DVector};

#[derive(Clone, Copy, Debug)]
pub struct NewtonOptions {
    /// Converged when max |Δx_k|/typical_k ≤ step_tol …
    pub step_tol: f64,
    /// … and max |F_i| ≤ residual_tol (absolute, on the caller's scaled residual).
    pub residual_tol: f64,
    pub max_iterations: usize,
    /// Keep the factorised Jacobian while it contracts the residual by at
    /// least 4× a step (chord iterations); refresh it otherwise.
    pub reuse_jacobian: bool,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions { step_tol: 1e-12, residual_tol: 1e-11, max_iterations: 60, reuse_jacobian: false }
    }
}

#[derive(Clone, Debug)]
pub struct NewtonReport {
    pub iterations: usize,
    pub residual_evaluations: usize,
    pub jacobian_evaluations: usize,
    pub residual_norm: f64,
}

/// When a [`DenseLu`] takes a fresh Jacobian.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Refresh {
    /// At every iteration.
    Always,
    /// After a full step that contracted ‖F‖₂ by at least 1/`contraction`,
    /// keep it (chord); otherwise refresh.
    Chord { contraction: f64 },
    /// Never after the first (a constant Jacobian).
    Never,
}

/// The dense LU of J = ∂F/∂x: from `jacobian(x, J)` when given and it
/// returns true, else forward differences with steps √ε·max(|x_k|, typical_k).
pub struct DenseLu<J> {
    jacobian: Option<J>,
    typical: Vec<f64>,
    refresh: Refresh,
    lu: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    jac: DMatrix<f64>,
    xv: DVector<f64>,
    trial: Vec<f64>,
    ft: Vec<f64>,
    rhs: DVector<f64>,
    /// Jacobians evaluated (analytic or by differences).
    pub evaluations: usize,
}

impl<J: FnMut(&DVector<f64>, &mut DMatrix<f64>) -> bool> DenseLu<J> {
    pub fn new(typical: Vec<f64>, refresh: Refresh, jacobian: Option<J>) -> Self {
        let n = typical.len();
        DenseLu {
            jacobian,
            typical,
            refresh,
            lu: None,
            jac: DMatrix::zeros(n, n),
            xv: DVector::zeros(n),
            trial: vec![0.0; n],
            ft: vec![0.0; n],
            rhs: DVector::zeros(n),
            evaluations: 0,
        }
    }

    /// J at x (f = F(x)) into `self.jac`.
    fn evaluate<E: Equations + ?Sized>(&mut self, eq: &mut E, x: &[f64], f: &[f64]) -> Result<()> {
        self.evaluations += 1;
        self.xv.copy_from_slice(x);
        if let Some(j) = self.jacobian.as_mut() {
            if j(&self.xv, &mut self.jac) {
                return Ok(());
            }
        }
        // Forward differences, step √ε relative to the typical size; a
        // backward one where the forward point leaves the domain.
        for k in 0..x.len() {
            let h = 1.5e-8 * x[k].abs().max(self.typical[k]);
            self.trial.copy_from_slice(x);
            self.trial[k] += h;
            if eq.residual(&self.trial, &mut self.ft)? {
                for i in 0..x.len() {
                    self.jac[(i, k)] = (self.ft[i] - f[i]) / h;
                }
                continue;
            }
            self.trial[k] = x[k] - h;
            if !eq.residual(&self.trial, &mut self.ft)? {
                return Err(Error::new(Status::ErrNotConverged, "Newton: cannot difference at the domain edge"));
            }
            for i in 0..x.len() {
                self.jac[(i, k)] = (f[i] - self.ft[i]) / h;
            }
        }
        Ok(())
    }
}

impl<E, J> LinearSolve<E> for DenseLu<J>
where
    E: Equations + ?Sized,
    J: FnMut(&DVector<f64>, &mut DMatrix<f64>) -> bool,
{
    fn step(&mut self, eq: &mut E, x: &[f64], f: &[f64], it: &Iterate, delta: &mut [f64]) -> Result<LinearStep> {
        let fresh = self.lu.is_none();
        if fresh {
            self.evaluate(eq, x, f)?;
            self.lu = Some(self.jac.clone().lu());
        }
        for (r, v) in self.rhs.iter_mut().zip(f) {
            *r = -v;
        }
        let step = self.lu.as_ref().expect("factorised above").solve(&self.rhs).ok_or_else(|| {
            Error::new(Status::ErrNotConverged, format!("Newton: singular Jacobian at iteration {}", it.iteration))
        })?;
        delta.copy_from_slice(step.as_slice());
        Ok(LinearStep { eta: 0.0, fresh })
    }

    fn invalidate(&mut self) {
        self.lu = None;
    }

    fn accepted(&mut self, _eq: &mut E, _x: &[f64], _f: &[f64], step: &super::Accepted) -> Result<()> {
        let keep = match self.refresh {
            Refresh::Always => false,
            Refresh::Chord { contraction } => step.t == 1.0 && step.rate <= contraction,
            Refresh::Never => true,
        };
        if !keep {
            self.lu = None;
        }
        Ok(())
    }
}

/// A closure F(x) on nalgebra vectors as [`Equations`], counting its
/// evaluations. `residual(x, f)` returns false outside the domain.
struct Closure<F> {
    residual: F,
    xv: DVector<f64>,
    fv: DVector<f64>,
    evaluations: usize,
}

impl<F: FnMut(&DVector<f64>, &mut DVector<f64>) -> bool> Equations for Closure<F> {
    fn dim(&self) -> usize {
        self.xv.len()
    }

    fn residual(&mut self, x: &[f64], f: &mut [f64]) -> Result<bool> {
        self.evaluations += 1;
        self.xv.copy_from_slice(x);
        let inside = (self.residual)(&self.xv, &mut self.fv);
        f.copy_from_slice(self.fv.as_slice());
        Ok(inside)
    }
}

/// Solve F(x) = 0 from `x` with a forward-difference Jacobian.
/// `residual(x, out)` returns false when x is outside the domain (e.g. a
/// negative stretch): the step is then shortened.
pub fn solve(
    x: &mut DVector<f64>,
    typical: &DVector<f64>,
    opts: &NewtonOptions,
    residual: impl FnMut(&DVector<f64>, &mut DVector<f64>) -> bool,
) -> Result<NewtonReport> {
    solve_with_jacobian(x, typical, opts, residual, None::<fn(&DVector<f64>, &mut DMatrix<f64>) -> bool>)
}

/// As [`solve`], with the caller's Jacobian `jacobian(x, J)` when given
/// (returning false falls back to differences for that iteration).
/// Converged when the last step is below `step_tol` (relative to
/// `typical`) and max |F_i| below `residual_tol`; the line search accepts
/// a sufficient decrease of ‖F‖₂ (Armijo) or any point below the residual
/// tolerance, halving down to t ≈ 1e-6.
pub fn solve_with_jacobian(
    x: &mut DVector<f64>,
    typical: &DVector<f64>,
    opts: &NewtonOptions,
    residual: impl FnMut(&DVector<f64>, &mut DVector<f64>) -> bool,
    jacobian: Option<impl FnMut(&DVector<f64>, &mut DMatrix<f64>) -> bool>,
) -> Result<NewtonReport> {
    let n = x.len();
    let mut eq = Closure { residual, xv: DVector::zeros(n), fv: DVector::zeros(n), evaluations: 0 };
    let refresh = if opts.reuse_jacobian { Refresh::Chord { contraction: 0.25 } } else { Refresh::Always };
    let mut linear = DenseLu::new(typical.as_slice().to_vec(), refresh, jacobian);
    // t = 1, ½, …, 2⁻¹⁹: the last halving above 1e-6.
    let mut search = Backtracking::new(vec![1.0; n], Norm::Two, 20);
    search.accept_below = opts.residual_tol;
    let mut test = StepTest::new(typical.as_slice().to_vec(), opts.step_tol, opts.residual_tol, "Newton");
    let report = super::solve(&mut eq, x.as_mut_slice(), &mut linear, &mut search, &mut test, opts.max_iterations)?;
    Ok(NewtonReport {
        iterations: report.iterations,
        residual_evaluations: eq.evaluations,
        jacobian_evaluations: linear.evaluations,
        residual_norm: report.norm,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_nonlinear_system_with_known_root() {
        // x² + y² = 5, x·y = 2 has the root (2, 1) near (3, 0.5) (by hand).
        for reuse_jacobian in [false, true] {
            let mut x = DVector::from_vec(vec![3.0, 0.5]);
            let opts = NewtonOptions { reuse_jacobian, ..Default::default() };
            let r = solve(&mut x, &DVector::from_element(2, 1.0), &opts, |x, f| {
                f[0] = x[0] * x[0] + x[1] * x[1] - 5.0;
                f[1] = x[0] * x[1] - 2.0;
                true
            })
            .unwrap();
            // Chord iterations converge linearly: the step test (1e-12) then
            // leaves an error of the order of the last step.
            let tol = if reuse_jacobian { 1e-11 } else { 1e-13 };
            assert!((x[0] - 2.0).abs() < tol && (x[1] - 1.0).abs() < tol, "{x}");
            // Newton: quadratic (≤ 10 steps); chord: linear at a rate ≤ ¼
            // per step (the Jacobian is kept only then), fewer Jacobians.
            assert!(r.iterations <= if reuse_jacobian { 30 } else { 10 }, "{r:?}");
            assert!(!reuse_jacobian || r.jacobian_evaluations < r.iterations / 2, "{r:?}");
        }
    }

    #[test]
    fn no_root_is_a_status() {
        let mut x = DVector::from_vec(vec![0.5]);
        let e = solve(&mut x, &DVector::from_element(1, 1.0), &NewtonOptions::default(), |x, f| {
            f[0] = x[0] * x[0] + 1.0;
            true
        })
        .unwrap_err();
        assert_eq!(e.status, Status::ErrNotConverged);
    }

    /// The domain: ln x − ln 4 = 0 (root 4, by hand) from x = 40, whose
    /// full Newton step −40 ln 10 leaves x > 0: it is shortened, not taken.
    #[test]
    fn steps_leaving_the_domain_are_shortened() {
        let mut x = DVector::from_vec(vec![40.0]);
        let r = solve(&mut x, &DVector::from_element(1, 1.0), &NewtonOptions::default(), |x, f| {
            if x[0] <= 0.0 {
                return false;
            }
            f[0] = x[0].ln() - 4f64.ln();
            true
        })
        .unwrap();
        assert!((x[0] - 4.0).abs() < 1e-12 && r.iterations < 20, "{x} {r:?}");
    }
}

//! Newton's method for small dense nonlinear systems (tens of unknowns), with
//! a forward-difference Jacobian and backtracking on the residual norm. The
//! engine of the tube wall solvers; the rod solvers use sparse tangents
//! instead. Scaling is the caller's: unknowns and residuals are expected to
//! be O(1) (the `typical` sizes set the difference steps).

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
pub fn solve_with_jacobian(
    x: &mut DVector<f64>,
    typical: &DVector<f64>,
    opts: &NewtonOptions,
    mut residual: impl FnMut(&DVector<f64>, &mut DVector<f64>) -> bool,
    mut jacobian: Option<impl FnMut(&DVector<f64>, &mut DMatrix<f64>) -> bool>,
) -> Result<NewtonReport> {
    let n = x.len();
    let mut f = DVector::zeros(n);
    let mut evals = 1;
    if !residual(x, &mut f) {
        return Err(Error::new(Status::ErrNotConverged, "Newton: the initial guess is outside the domain"));
    }
    let mut jac = DMatrix::zeros(n, n);
    let mut trial = DVector::zeros(n);
    let mut ft = DVector::zeros(n);
    let mut lu = None;
    let mut jac_evals = 0;
    let mut fresh = false;
    for it in 0..opts.max_iterations {
        if lu.is_none() {
            jac_evals += 1;
            fresh = true;
            let analytic = match jacobian.as_mut() {
                Some(j) => j(x, &mut jac),
                None => false,
            };
            // Otherwise forward differences, step √ε relative to the typical size.
            for k in (0..n).filter(|_| !analytic) {
                let h = 1.5e-8 * x[k].abs().max(typical[k]);
                trial.copy_from(x);
                trial[k] += h;
                evals += 1;
                if !residual(&trial, &mut ft) {
                    trial[k] = x[k] - h;
                    evals += 1;
                    if !residual(&trial, &mut ft) {
                        return Err(Error::new(
                            Status::ErrNotConverged,
                            "Newton: cannot difference at the domain edge",
                        ));
                    }
                    jac.column_mut(k).copy_from(&((&f - &ft) / h));
                } else {
                    jac.column_mut(k).copy_from(&((&ft - &f) / h));
                }
            }
            lu = Some(jac.clone().lu());
        }
        let step = lu.as_ref().unwrap().solve(&(-&f)).ok_or_else(|| {
            Error::new(Status::ErrNotConverged, format!("Newton: singular Jacobian at iteration {it}"))
        })?;
        // Backtracking on the (smooth) 2-norm: accept the first step that
        // stays in the domain and decreases ‖F‖ sufficiently (Armijo).
        let f_norm = f.norm();
        let mut t = 1.0;
        let accepted = loop {
            trial.copy_from(&(&*x + &step * t));
            evals += 1;
            if residual(&trial, &mut ft) && (ft.norm() <= f_norm * (1.0 - 1e-4 * t) || ft.amax() < opts.residual_tol) {
                break true;
            }
            t *= 0.5;
            if t < 1e-6 {
                break false;
            }
        };
        if !accepted {
            if !fresh {
                lu = None; // a stale Jacobian: refresh and try again
                continue;
            }
            return Err(Error::new(
                Status::ErrNotConverged,
                format!("Newton: line search failed at iteration {it} (|F| = {f_norm:e})"),
            ));
        }
        let contraction = ft.norm() / f_norm.max(f64::MIN_POSITIVE);
        x.copy_from(&trial);
        f.copy_from(&ft);
        fresh = false;
        if !opts.reuse_jacobian || t < 1.0 || contraction > 0.25 {
            lu = None;
        }
        let dx = step.iter().zip(typical.iter()).map(|(d, s)| (t * d / s).abs()).fold(0.0, |a: f64, b: f64| {
            if a.is_nan() || b.is_nan() {
                f64::NAN
            } else {
                a.max(b)
            }
        });
        if dx <= opts.step_tol && f.amax() <= opts.residual_tol {
            return Ok(NewtonReport {
                iterations: it + 1,
                residual_evaluations: evals,
                jacobian_evaluations: jac_evals,
                residual_norm: f.amax(),
            });
        }
    }
    Err(Error::new(
        Status::ErrNotConverged,
        format!("Newton: no convergence in {} iterations (max |F| = {:e})", opts.max_iterations, f.amax()),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_nonlinear_system_with_known_root() {
        // x² + y² = 5, x·y = 2 has the root (2, 1) near (3, 0.5) (by hand).
        let mut x = DVector::from_vec(vec![3.0, 0.5]);
        let r = solve(&mut x, &DVector::from_element(2, 1.0), &NewtonOptions::default(), |x, f| {
            f[0] = x[0] * x[0] + x[1] * x[1] - 5.0;
            f[1] = x[0] * x[1] - 2.0;
            true
        })
        .unwrap();
        assert!((x[0] - 2.0).abs() < 1e-13 && (x[1] - 1.0).abs() < 1e-13, "{x}");
        assert!(r.iterations <= 10);
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
}

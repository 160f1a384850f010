//! One Newton iteration for every nonlinear solve in rodkit — the tube
//! walls, the DNA fit, the continuation correctors and single equilibria —
//! built like KINSOL from pluggable parts:
//!
//! * [`Equations`]: F(x) = 0 and its domain;
//! * [`LinearSolve`]: how a step δ with J δ ≈ −F is found and when the
//!   linearisation is refreshed — a dense LU of an analytic or
//!   forward-difference Jacobian ([`dense`]), a sparse LU ([`sparse`]), the
//!   bordered LU of a continuation (in `crate::continuation::corrector`),
//!   or GMRES with a lagged band preconditioner and Eisenstat–Walker forcing
//!   ([`krylov`]);
//! * [`LineSearch`]: the full step ([`FullStep`]) or halving backtracking
//!   with an Armijo test in a chosen norm ([`Backtracking`]);
//! * [`Convergence`]: when to stop — a scaled residual with an optional
//!   stall rule ([`ResidualTest`]) or a step criterion ([`StepTest`]).
//!
//! [`solve`] runs x_{k+1} = x_k + t_k δ_k with them. Work counts are kept
//! by the parts that do the work ([`Work`]).

pub mod dense;
pub mod krylov;
pub mod sparse;

use crate::error::{Error, Result};
use crate::linalg::dense::nan_max;
use crate::status::Status;

/// F(x) = 0, n equations in n unknowns.
pub trait Equations {
    fn dim(&self) -> usize;
    /// F(x) into `f`. Ok(false): x lies outside the domain (a line search
    /// shortens the step); an error stops the solve.
    fn residual(&mut self, x: &[f64], f: &mut [f64]) -> Result<bool>;
}

/// Work done by a solve's parts (what the benchmarks count).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Work {
    pub residuals: usize,
    pub jacobians: usize,
    pub factorisations: usize,
    pub solves: usize,
}

impl Work {
    pub fn add(&mut self, other: &Work) {
        self.residuals += other.residuals;
        self.jacobians += other.jacobians;
        self.factorisations += other.factorisations;
        self.solves += other.solves;
    }
}

/// What the iteration knows at an iterate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iterate {
    pub iteration: usize,
    /// The convergence test's norm of F here.
    pub norm: f64,
    /// … at the previous iterate (∞ at the first).
    pub previous: f64,
    /// ‖F_k‖ / ‖F_{k−1}‖ of the last accepted step, in the norm the line
    /// search accepted it in (NaN before the first).
    pub rate: f64,
    /// Whether the last step was computed on a fresh linearisation (taken
    /// at its own iterate).
    pub fresh: bool,
}

/// A step found by a [`LinearSolve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearStep {
    /// The relative accuracy asked of the linear solve (0: exact).
    pub eta: f64,
    /// Computed on a linearisation taken at this iterate.
    pub fresh: bool,
}

/// How a Newton step is computed.
pub trait LinearSolve<E: ?Sized> {
    /// δ with J(x) δ ≈ −f, f = F(x).
    fn step(&mut self, eq: &mut E, x: &[f64], f: &[f64], it: &Iterate, delta: &mut [f64]) -> Result<LinearStep>;
    /// Drop a kept linearisation (the next step takes a fresh one): after a
    /// line search failed on a stale one.
    fn invalidate(&mut self) {}
    /// A step was accepted: x and f are the new iterate's.
    fn accepted(&mut self, _eq: &mut E, _x: &[f64], _f: &[f64], _step: &Accepted) -> Result<()> {
        Ok(())
    }
}

/// An accepted step: the fraction t of δ taken and the rate it achieved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Accepted {
    pub t: f64,
    pub rate: f64,
}

/// How far along δ to go.
pub trait LineSearch<E: ?Sized> {
    /// Move x ← x + tδ and f ← F there for the first acceptable t; Ok(None)
    /// when none is (x and f unchanged).
    fn search(
        &mut self,
        eq: &mut E,
        x: &mut [f64],
        f: &mut [f64],
        delta: &[f64],
        it: &Iterate,
        eta: f64,
    ) -> Result<Option<Accepted>>;
}

/// A convergence test's decision.
#[derive(Debug)]
pub enum Verdict {
    Continue,
    Converged,
    Fail(Error),
}

/// When to stop.
pub trait Convergence {
    /// The norm of F that [`Iterate::norm`] reports.
    fn norm(&self, f: &[f64]) -> f64;
    /// At an iterate, before a step.
    fn before_step(&mut self, it: &Iterate) -> Verdict;
    /// After an accepted step tδ to x (`it` is the new iterate).
    fn after_step(&mut self, _x: &[f64], _delta: &[f64], _t: f64, _it: &Iterate) -> Verdict {
        Verdict::Continue
    }
    /// The error when the iterations run out at `it`.
    fn exhausted(&self, it: &Iterate) -> Error;
    /// The error when no step along δ was acceptable at `it`.
    fn no_descent(&self, it: &Iterate) -> Error;
}

/// What a solve did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Report {
    /// Newton steps taken.
    pub iterations: usize,
    /// The convergence test's norm of F at the returned x.
    pub norm: f64,
}

/// Newton's method on `eq` from `x` (overwritten with the solution), at
/// most `max_iterations` steps. A line search that fails on a kept (stale)
/// linearisation is retried once on a fresh one.
pub fn solve<E, L, S, C>(
    eq: &mut E,
    x: &mut [f64],
    linear: &mut L,
    search: &mut S,
    test: &mut C,
    max_iterations: usize,
) -> Result<Report>
where
    E: Equations + ?Sized,
    L: LinearSolve<E> + ?Sized,
    S: LineSearch<E> + ?Sized,
    C: Convergence + ?Sized,
{
    let n = eq.dim();
    crate::error::dimension("Newton state length", x.len() as i64, n as i64, n as i64)?;
    let mut f = vec![0.0; n];
    let mut delta = vec![0.0; n];
    if !eq.residual(x, &mut f)? {
        return Err(Error::new(Status::ErrNotConverged, "Newton: the initial guess is outside the domain"));
    }
    let mut it = Iterate { iteration: 0, norm: test.norm(&f), previous: f64::INFINITY, rate: f64::NAN, fresh: false };
    for k in 0..=max_iterations {
        it.iteration = k;
        match test.before_step(&it) {
            Verdict::Converged => return Ok(Report { iterations: k, norm: it.norm }),
            Verdict::Fail(e) => return Err(e),
            Verdict::Continue => {}
        }
        if k == max_iterations {
            break;
        }
        let (accepted, fresh) = loop {
            let step = linear.step(eq, x, &f, &it, &mut delta)?;
            match search.search(eq, x, &mut f, &delta, &it, step.eta)? {
                Some(a) => break (a, step.fresh),
                None if !step.fresh => linear.invalidate(),
                None => return Err(test.no_descent(&it)),
            }
        };
        it = Iterate { iteration: k + 1, norm: test.norm(&f), previous: it.norm, rate: accepted.rate, fresh };
        linear.accepted(eq, x, &f, &accepted)?;
        match test.after_step(x, &delta, accepted.t, &it) {
            Verdict::Converged => return Ok(Report { iterations: k + 1, norm: it.norm }),
            Verdict::Fail(e) => return Err(e),
            Verdict::Continue => {}
        }
    }
    Err(test.exhausted(&it))
}

/// max_i |f_i| / d_i (NaN when any f_i is NaN).
pub fn scaled_max_norm(f: &[f64], scales: &[f64]) -> f64 {
    f.iter().zip(scales).map(|(a, s)| (a / s).abs()).fold(0.0, nan_max)
}

/// The full Newton step, x ← x + δ (refused outside the domain).
pub struct FullStep {
    trial: Vec<f64>,
    ft: Vec<f64>,
}

impl FullStep {
    /// For n unknowns.
    pub fn new(n: usize) -> Self {
        FullStep { trial: vec![0.0; n], ft: vec![0.0; n] }
    }
}

impl<E: Equations + ?Sized> LineSearch<E> for FullStep {
    fn search(
        &mut self,
        eq: &mut E,
        x: &mut [f64],
        f: &mut [f64],
        delta: &[f64],
        _it: &Iterate,
        _eta: f64,
    ) -> Result<Option<Accepted>> {
        for i in 0..x.len() {
            self.trial[i] = x[i] + delta[i];
        }
        if !eq.residual(&self.trial, &mut self.ft)? {
            return Ok(None);
        }
        x.copy_from_slice(&self.trial);
        f.copy_from_slice(&self.ft);
        Ok(Some(Accepted { t: 1.0, rate: f64::NAN }))
    }
}

/// The norm a [`Backtracking`] search must decrease, on the scaled
/// residual F_i / d_i.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Norm {
    Max,
    Two,
}

/// Halving backtracking, t = 1, ½, … (`tries` values): t is accepted when
/// the trial lies in the domain and ‖F̃(x + tδ)‖ ≤ (1 − 10⁻⁴ t (1 − η)) ‖F̃(x)‖
/// (Armijo, with η the linear solve's relative accuracy: an inexact step
/// is a descent direction only to that accuracy) in `norm`, or when
/// `full_step_max_norm` and the full step decreases the max norm so, or
/// when the trial's max norm is below `accept_below`.
pub struct Backtracking {
    /// The equation scales d_i.
    pub scales: Vec<f64>,
    pub norm: Norm,
    pub tries: usize,
    pub full_step_max_norm: bool,
    pub accept_below: f64,
    trial: Vec<f64>,
    ft: Vec<f64>,
}

impl Backtracking {
    pub fn new(scales: Vec<f64>, norm: Norm, tries: usize) -> Self {
        let n = scales.len();
        Backtracking {
            scales,
            norm,
            tries,
            full_step_max_norm: false,
            accept_below: 0.0,
            trial: vec![0.0; n],
            ft: vec![0.0; n],
        }
    }

    /// ‖F̃‖₂ of F̃_i = F_i / d_i.
    fn two_norm(&self, f: &[f64]) -> f64 {
        f.iter().zip(&self.scales).map(|(a, d)| (a / d) * (a / d)).sum::<f64>().sqrt()
    }
}

impl<E: Equations + ?Sized> LineSearch<E> for Backtracking {
    fn search(
        &mut self,
        eq: &mut E,
        x: &mut [f64],
        f: &mut [f64],
        delta: &[f64],
        _it: &Iterate,
        eta: f64,
    ) -> Result<Option<Accepted>> {
        let max0 = scaled_max_norm(f, &self.scales);
        let two0 = self.two_norm(f);
        let mut t = 1.0;
        for _ in 0..self.tries {
            for i in 0..x.len() {
                self.trial[i] = x[i] + t * delta[i];
            }
            if eq.residual(&self.trial, &mut self.ft)? {
                let decrease = 1.0 - 1e-4 * t * (1.0 - eta);
                let max1 = scaled_max_norm(&self.ft, &self.scales);
                // The search norm: finite, and decreased (Armijo).
                let (finite, by_norm, rate) = match self.norm {
                    Norm::Max => (max1.is_finite(), max1 <= decrease * max0, max1 / max0),
                    Norm::Two => {
                        let two1 = self.two_norm(&self.ft);
                        (two1.is_finite(), two1 <= decrease * two0, two1 / two0)
                    }
                };
                let by_max = self.full_step_max_norm && t == 1.0 && max1 <= decrease * max0;
                if finite && (by_norm || by_max || max1 < self.accept_below) {
                    x.copy_from_slice(&self.trial);
                    f.copy_from_slice(&self.ft);
                    // A step accepted on the max norm alone measures its
                    // rate there: the search norm's grew.
                    let rate = if !by_norm && by_max { max1 / max0 } else { rate };
                    return Ok(Some(Accepted { t, rate }));
                }
            }
            t *= 0.5;
        }
        Ok(None)
    }
}

/// How a [`ResidualTest`] treats an iteration that did not halve the residual.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stall {
    /// Never a failure by itself.
    Allowed,
    /// A failure from the third iteration on when the step was computed on
    /// a fresh linearisation (a kept one is refreshed first).
    AfterFresh,
    /// A failure when two steps computed on fresh linearisations in a row
    /// (from the third iteration on) did not halve the residual: chord
    /// iterations, whose first fresh step after a kept one starts from an
    /// iterate the kept one left — on the 1 kbp DNA plectoneme one slow
    /// fresh step rejected 1 step in 3 (46 of 120) that converged with a
    /// second.
    TwiceAfterFresh,
    /// A failure at once.
    Immediate,
}

/// A solver's non-convergence, prefixed by its label.
fn not_converged(label: &str, what: std::fmt::Arguments) -> Error {
    Error::new(Status::ErrNotConverged, format!("{label}: {what}"))
}

/// Converged when max_i |F_i| / d_i ≤ `tol` at an iterate.
pub struct ResidualTest {
    pub scales: Vec<f64>,
    pub tol: f64,
    /// What the messages call the solver ("direct Newton", …).
    pub label: &'static str,
    /// The status of a non-finite residual.
    pub non_finite: Status,
    pub stall: Stall,
    /// Slow steps on fresh linearisations in a row (TwiceAfterFresh).
    slow_fresh: usize,
}

impl ResidualTest {
    pub fn new(scales: Vec<f64>, tol: f64, label: &'static str) -> Self {
        ResidualTest {
            scales,
            tol,
            label,
            non_finite: Status::ErrNonFiniteResult,
            stall: Stall::Allowed,
            slow_fresh: 0,
        }
    }
}

impl Convergence for ResidualTest {
    fn norm(&self, f: &[f64]) -> f64 {
        scaled_max_norm(f, &self.scales)
    }

    fn before_step(&mut self, it: &Iterate) -> Verdict {
        let k = it.iteration;
        if !it.norm.is_finite() {
            return Verdict::Fail(Error::new(
                self.non_finite,
                format!("{}: non-finite residual at iteration {k}", self.label),
            ));
        }
        if it.norm <= self.tol {
            return Verdict::Converged;
        }
        let slow = it.norm > 0.5 * it.previous;
        self.slow_fresh = if slow && it.fresh && k >= 3 { self.slow_fresh + 1 } else { 0 };
        let stalled = match self.stall {
            Stall::Allowed => false,
            Stall::AfterFresh => slow && k >= 3 && it.fresh,
            Stall::TwiceAfterFresh => self.slow_fresh >= 2,
            Stall::Immediate => slow,
        };
        if stalled {
            return Verdict::Fail(self.exhausted(it));
        }
        Verdict::Continue
    }

    fn exhausted(&self, it: &Iterate) -> Error {
        let (norm, tol, k) = (it.norm, self.tol, it.iteration);
        not_converged(self.label, format_args!("residual {norm:.2e} above {tol:.1e} after {k} iterations"))
    }

    fn no_descent(&self, it: &Iterate) -> Error {
        let (k, norm) = (it.iteration, it.norm);
        not_converged(
            self.label,
            format_args!("no decrease of the residual along the step at iteration {k} (residual {norm:.2e})"),
        )
    }
}

/// Converged when, after a step, max_k |t δ_k| / s_k ≤ `step_tol` (s_k:
/// `typical`, or |x_k| of the new iterate when empty) and the residual's
/// max norm is ≤ `residual_tol`.
pub struct StepTest {
    pub typical: Vec<f64>,
    pub step_tol: f64,
    pub residual_tol: f64,
    /// What the messages call the solver.
    pub label: &'static str,
    /// The last step's scaled size.
    pub last_step: f64,
}

impl StepTest {
    pub fn new(typical: Vec<f64>, step_tol: f64, residual_tol: f64, label: &'static str) -> Self {
        StepTest { typical, step_tol, residual_tol, label, last_step: f64::INFINITY }
    }
}

impl Convergence for StepTest {
    fn norm(&self, f: &[f64]) -> f64 {
        f.iter().map(|a| a.abs()).fold(0.0, f64::max)
    }

    fn before_step(&mut self, _it: &Iterate) -> Verdict {
        Verdict::Continue
    }

    fn after_step(&mut self, x: &[f64], delta: &[f64], t: f64, it: &Iterate) -> Verdict {
        self.last_step = if self.typical.is_empty() {
            delta.iter().zip(x).map(|(d, s)| (t * d / s).abs()).fold(0.0, nan_max)
        } else {
            delta.iter().zip(&self.typical).map(|(d, s)| (t * d / s).abs()).fold(0.0, nan_max)
        };
        if self.last_step <= self.step_tol && it.norm <= self.residual_tol {
            Verdict::Converged
        } else {
            Verdict::Continue
        }
    }

    fn exhausted(&self, it: &Iterate) -> Error {
        let (k, norm, step) = (it.iteration, it.norm, self.last_step);
        not_converged(
            self.label,
            format_args!("no convergence in {k} iterations (max |F| = {norm:e}, last step {step:e})"),
        )
    }

    fn no_descent(&self, it: &Iterate) -> Error {
        let (k, norm) = (it.iteration, it.norm);
        not_converged(self.label, format_args!("line search failed at iteration {k} (|F| = {norm:e})"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// F(x) = atan(x), root 0.
    struct Atan;

    impl Equations for Atan {
        fn dim(&self) -> usize {
            1
        }
        fn residual(&mut self, x: &[f64], f: &mut [f64]) -> Result<bool> {
            f[0] = x[0].atan();
            Ok(true)
        }
    }

    /// The exact Newton step times `fraction` (fraction 1: Newton).
    struct Scaled {
        fraction: f64,
    }

    impl LinearSolve<Atan> for Scaled {
        fn step(&mut self, _: &mut Atan, x: &[f64], f: &[f64], _: &Iterate, d: &mut [f64]) -> Result<LinearStep> {
            d[0] = -self.fraction * f[0] * (1.0 + x[0] * x[0]);
            Ok(LinearStep { eta: 0.0, fresh: true })
        }
    }

    /// Newton on atan from x = 3 overshoots (by hand: δ = −10 atan 3 =
    /// −12.49, and |atan(−9.49)| = 1.466 > atan 3 = 1.249; t = ½ gives
    /// x = −3.245, |atan| = 1.272, still no decrease), t = ¼ gives x =
    /// −0.1225: the search takes t = ¼ with the rate |atan(−0.1225)|/atan 3.
    #[test]
    fn backtracking_takes_the_first_armijo_step() {
        let (mut x, mut f) = (vec![3.0], vec![3f64.atan()]);
        let delta = vec![-10.0 * 3f64.atan()];
        let it = Iterate { iteration: 0, norm: f[0], previous: f64::INFINITY, rate: f64::NAN, fresh: true };
        for norm in [Norm::Max, Norm::Two] {
            let (mut x, mut f) = (x.clone(), f.clone());
            let a = Backtracking::new(vec![1.0], norm, 10).search(&mut Atan, &mut x, &mut f, &delta, &it, 0.0);
            let a = a.unwrap().expect("a step");
            let expected = 3.0 + 0.25 * delta[0];
            assert_eq!(a.t, 0.25);
            assert!((x[0] - expected).abs() < 1e-15 && (f[0] - expected.atan()).abs() < 1e-15);
            assert!((a.rate - expected.atan().abs() / 3f64.atan()).abs() < 1e-15);
        }
        // Two halvings allowed: none acceptable, x and f unchanged.
        let none = Backtracking::new(vec![1.0], Norm::Max, 2).search(&mut Atan, &mut x, &mut f, &delta, &it, 0.0);
        assert!(none.unwrap().is_none() && x == [3.0] && f == [3f64.atan()]);
    }

    /// The driver: undamped Newton on atan from 3 diverges (|x| grows past
    /// 1.39, the known divergence threshold x with 2x = (1 + x²) atan x) and
    /// fails on its non-finite or growing residual; damped by backtracking
    /// it converges to the root 0 to the tolerance, quadratically at the end.
    #[test]
    fn damping_turns_a_divergent_newton_into_a_convergent_one() {
        let mut x = vec![3.0];
        let mut test = ResidualTest::new(vec![1.0], 1e-12, "atan");
        let r = solve(&mut Atan, &mut x, &mut Scaled { fraction: 1.0 }, &mut FullStep::new(1), &mut test, 20);
        assert!(r.is_err(), "{r:?}");
        let mut x = vec![3.0];
        let mut search = Backtracking::new(vec![1.0], Norm::Max, 20);
        let r = solve(&mut Atan, &mut x, &mut Scaled { fraction: 1.0 }, &mut search, &mut test, 20).unwrap();
        assert!(x[0].abs() <= 1e-12 && r.norm <= 1e-12 && r.iterations <= 8, "{x:?} {r:?}");
    }

    /// Stall rules on a step a tenth of Newton's (each iteration keeps
    /// ~90 % of the residual, "slow"): Immediate fails at the first slow
    /// iterate (iteration 1), AfterFresh from the third, Allowed runs to the
    /// iteration limit.
    #[test]
    fn stall_rules_fail_where_documented() {
        for (stall, fails_at) in [(Stall::Immediate, 1), (Stall::AfterFresh, 3), (Stall::Allowed, 50)] {
            let mut x = vec![0.5];
            let mut test = ResidualTest::new(vec![1.0], 1e-12, "atan");
            test.stall = stall;
            let e = solve(&mut Atan, &mut x, &mut Scaled { fraction: 0.1 }, &mut FullStep::new(1), &mut test, 50)
                .unwrap_err();
            assert_eq!(e.status, Status::ErrNotConverged);
            assert!(e.message.contains(&format!("after {fails_at} iterations")), "{stall:?}: {}", e.message);
        }
    }
}

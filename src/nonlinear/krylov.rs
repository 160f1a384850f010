//! Newton–Krylov: F(x) = 0 by inexact Newton, each step by
//! right-preconditioned GMRES(m) ([`crate::linalg::gmres`]) — the
//! alternative to the sparse direct Newton for single equilibria of long
//! rods.
//!
//! * Jacobian-free: J v = (F(x + σ v) − F(x − σ v)) / 2σ (or the forward
//!   difference), two residuals per Krylov iteration. The model's own
//!   Jacobian is never factorised, and need not even exist (the all-pairs
//!   base-pair rod, whose exact Jacobian is dense).
//! * Preconditioner ([`BandPreconditioner`]): the LU of a Jacobian's band
//!   and boundary corners ([`crate::linalg::band::BandLu`]), from the
//!   equations' own Jacobian or a cheaper model's on the same pattern. It
//!   is lagged: factorised once and kept while GMRES converges in few
//!   iterations, so a sequence of solves (a continuation) amortises it.
//! * Forcing terms of Eisenstat & Walker (SIAM J. Sci. Comput. 17, 16
//!   (1996), choice 2: η_k = 0.9 (‖F_k‖/‖F_{k−1}‖)², safeguarded, capped
//!   at η_max, floored so that the last step does not oversolve), and a
//!   backtracking line search on ‖F̃‖₂ (Armijo, halving; the full step
//!   may pass in the max norm instead, see [`solve`]).
//!
//! Everything is in scaled variables: x̃ = x / s (unknown scales), F̃ = F / d
//! (equation scales); convergence is max |F̃_i| ≤ tol, the direct solver's
//! test. Buffers are allocated once per solve.

use super::sparse::SparseJacobian;
use super::{Backtracking, Iterate, LinearSolve, LinearStep, Norm, ResidualTest, Work};
use crate::error::{Error, Result};
use crate::linalg::band::BandLu;
use crate::linalg::dense::norm2;
use crate::linalg::gmres::Gmres;
use crate::linalg::Pattern;
use crate::status::Status;

/// Options of a Newton–Krylov solve ([`solve`]).
#[derive(Clone, Debug)]
pub struct KrylovOptions {
    /// Converged when max |R_i| / d_i ≤ residual_tol (as the direct engine).
    pub residual_tol: f64,
    pub max_newton: usize,
    /// GMRES restart length m.
    pub restart: usize,
    /// Krylov iterations allowed per Newton step (over restarts).
    pub max_linear: usize,
    /// Largest forcing term η (relative linear residual of a Newton step).
    pub eta_max: f64,
    /// Refresh the lagged preconditioner after a Newton step that needed
    /// more Krylov iterations than this (10: a fresh band LU costs about as
    /// much as 5–10 iterations on the DNA rod; at 25 the buckled base-pair
    /// rod ran 98 iterations on a stale one where 10 gave 37).
    pub refresh_after: usize,
    /// Jacobian–vector products by central differences (two residuals
    /// each, error O(σ²)) instead of forward ones (one residual, O(σ)).
    pub central: bool,
    /// Rms size of the difference perturbation in the scaled unknowns
    /// (relative to max(1, rms x̃)).
    pub perturbation: f64,
}

impl Default for KrylovOptions {
    fn default() -> Self {
        KrylovOptions {
            residual_tol: 1e-8,
            max_newton: 30,
            restart: 40,
            max_linear: 200,
            eta_max: 0.1,
            refresh_after: 10,
            central: true,
            perturbation: 1e-6,
        }
    }
}

/// What a Newton–Krylov solve did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KrylovReport {
    pub newton_iterations: usize,
    /// Krylov (GMRES) iterations, each one Jacobian–vector product.
    pub linear_iterations: usize,
    /// Final max |F_i| / d_i.
    pub residual: f64,
    /// Residuals, Jacobians (for the preconditioner), factorisations and
    /// preconditioner solves.
    pub counts: Work,
}

/// The lagged preconditioner: the LU of the band of a Jacobian
/// ([`BandLu`]: the rod's band, the boundary corners, an optional border)
/// with the Jacobian buffer it is evaluated into, its numeric
/// factorisation kept until [`BandPreconditioner::refresh`].
pub struct BandPreconditioner {
    lu: BandLu,
    jx: Vec<f64>,
    factorised: bool,
    /// Jacobians, factorisations and solves it did.
    pub work: Work,
}

impl BandPreconditioner {
    /// For Jacobians with `pattern`, keeping |i − j| ≤ `band` and the
    /// boundary corner blocks.
    pub fn new(pattern: &Pattern, band: usize) -> Result<Self> {
        Self::bordered(pattern, band, 0)
    }

    /// As [`BandPreconditioner::new`], also keeping the last `border` rows
    /// and columns whole (see [`BandLu::new`]).
    pub fn bordered(pattern: &Pattern, band: usize, border: usize) -> Result<Self> {
        let lu = BandLu::new(pattern, band, border)?;
        Ok(BandPreconditioner { lu, jx: vec![0.0; pattern.nnz()], factorised: false, work: Work::default() })
    }

    pub fn band(&self) -> usize {
        self.lu.band()
    }

    /// Entries kept of the full pattern's.
    pub fn kept(&self) -> (usize, usize) {
        self.lu.kept()
    }

    /// Entries of the banded matrix's L + U (0 before the first factorisation).
    pub fn fill(&self) -> usize {
        self.lu.fill()
    }

    /// Evaluate `source`'s Jacobian at x (its pattern must be the one
    /// given to [`BandPreconditioner::new`]) and factorise its band.
    pub fn refresh<Q: SparseJacobian + ?Sized>(&mut self, source: &mut Q, x: &[f64]) -> Result<()> {
        if source.dim() != self.lu.dim() || source.pattern().nnz() != self.jx.len() {
            return Err(Error::new(
                Status::ErrInvalidDimension,
                "band preconditioner: the Jacobian's pattern is not the one it was built for",
            ));
        }
        self.factorised = false;
        source.jacobian(x, &mut self.jx);
        self.work.jacobians += 1;
        self.lu.factorise(&self.jx)?;
        self.work.factorisations += 1;
        self.factorised = true;
        Ok(())
    }

    fn apply(&mut self, v: &mut [f64]) {
        self.lu.solve(v);
        self.work.solves += 1;
    }
}

/// The GMRES step of Newton–Krylov as a [`LinearSolve`]: forcing term,
/// preconditioned GMRES on difference products, a refresh of the
/// preconditioner when GMRES fails on a stale one or needed many
/// iterations.
struct KrylovStep<'a> {
    pre: &'a mut BandPreconditioner,
    source: Option<&'a mut dyn SparseJacobian>,
    opts: &'a KrylovOptions,
    d: Vec<f64>,
    s: Vec<f64>,
    gmres: Gmres,
    /// The last forcing term.
    eta: f64,
    /// −F̃ at the iterate, and the product's scratch.
    b: Vec<f64>,
    trial: Vec<f64>,
    rp: Vec<f64>,
    /// Krylov iterations: all, and the last step's (final attempt).
    linear: usize,
    last: usize,
    refreshed: bool,
}

impl KrylovStep<'_> {
    /// rms of x̃ = x / s.
    fn rms(&self, v: &[f64]) -> f64 {
        let mut sum = 0.0;
        for (a, w) in v.iter().zip(&self.s) {
            sum += a * a / (w * w);
        }
        (sum / self.s.len().max(1) as f64).sqrt()
    }

    fn refresh<E: SparseJacobian + ?Sized>(&mut self, eq: &mut E, x: &[f64]) -> Result<()> {
        match self.source.as_deref_mut() {
            Some(q) => self.pre.refresh(q, x),
            None => self.pre.refresh(eq, x),
        }
    }

    /// The forcing term at an iterate (Eisenstat–Walker choice 2,
    /// safeguarded), floored so that the linear residual is not pushed far
    /// below the tolerance.
    fn forcing(&mut self, it: &Iterate) -> f64 {
        let opts = self.opts;
        let mut eta = self.eta;
        if it.rate.is_finite() {
            let candidate = 0.9 * it.rate * it.rate;
            let safeguard = 0.9 * eta * eta;
            eta = if safeguard > 0.1 { candidate.max(safeguard) } else { candidate };
            eta = eta.min(opts.eta_max);
        }
        // A step that barely reduced the residual (rate > 0.9, where choice
        // 2 would return to η_max) is followed by an accurate one: on the
        // DNA rod under a torque clamp, re-solved with base pairs, η = 0.1
        // stalled at 5e-7 (30 Newton steps of 3 GMRES iterations each
        // reducing it by 0.3 %); with η ≤ 1e-3 it converged in 12.
        if it.rate > 0.9 {
            eta = eta.min(1e-3);
        }
        // The floor is relative to the max norm, the convergence test's:
        // GMRES reduces ‖F̃‖₂ by η, and a residual spread over a long rod has
        // ‖F̃‖₂ ≈ √n‖F̃‖∞, so a floor of tol/‖F̃‖₂ asked the last linear solve
        // for √n times more than the test needs — one more GMRES iteration
        // at 10 kbp than at 3 (DNA rod, 7 → 6; the Newton steps unchanged).
        eta = eta.max(0.25 * opts.residual_tol / it.norm).min(opts.eta_max);
        self.eta = eta;
        eta
    }
}

impl<E: SparseJacobian + ?Sized> LinearSolve<E> for KrylovStep<'_> {
    fn step(&mut self, eq: &mut E, x: &[f64], f: &[f64], it: &Iterate, delta: &mut [f64]) -> Result<LinearStep> {
        let n = x.len();
        let eta = self.forcing(it);
        for i in 0..n {
            self.b[i] = -(f[i] / self.d[i]);
        }
        let fnorm = norm2(&self.b);
        // J̃-products along an unscaled direction v, into `out` (scaled):
        // differences of F with a perturbation of rms opts.perturbation·
        // max(1, rms x̃) in the scaled unknowns.
        let opts = self.opts;
        let pert = opts.perturbation * self.rms(x).max(1.0);
        let central = opts.central;
        self.refreshed = false;
        let mut linear = 0;
        loop {
            let KrylovStep { pre, gmres, b, trial, rp, d, s, .. } = &mut *self;
            let mut failure = None;
            let rms = |v: &[f64]| {
                let mut sum = 0.0;
                for (a, w) in v.iter().zip(s.iter()) {
                    sum += a * a / (w * w);
                }
                (sum / s.len().max(1) as f64).sqrt()
            };
            // GMRES(m) on J̃ P y = −F̃ with P v = M⁻¹ D v (M: the band LU),
            // the step δ = P y in the unscaled unknowns.
            let report = gmres.solve(
                b,
                delta,
                eta * fnorm,
                opts.max_linear,
                |v, z| {
                    for i in 0..n {
                        z[i] = v[i] * d[i];
                    }
                    pre.apply(z);
                },
                |v, out| {
                    let vnorm = rms(v);
                    if vnorm == 0.0 || !vnorm.is_finite() {
                        out.fill(0.0);
                        return;
                    }
                    let sigma = pert / vnorm;
                    for i in 0..n {
                        trial[i] = x[i] + sigma * v[i];
                    }
                    if let Err(e) = eq.residual(trial, rp) {
                        failure.get_or_insert(e);
                    }
                    if central {
                        // (F(x + σv) − F(x − σv)) / 2σ: O(σ²), robust along
                        // the soft directions of a long rod where |J v| ≪
                        // |J||v| and a forward difference's O(σ) error is not
                        // small relative to it.
                        for i in 0..n {
                            out[i] = rp[i];
                            trial[i] = x[i] - sigma * v[i];
                        }
                        if let Err(e) = eq.residual(trial, rp) {
                            failure.get_or_insert(e);
                        }
                        for i in 0..n {
                            out[i] = (out[i] - rp[i]) / (2.0 * sigma * d[i]);
                        }
                    } else {
                        for i in 0..n {
                            out[i] = (rp[i] - f[i]) / (sigma * d[i]);
                        }
                    }
                },
            );
            if let Some(e) = failure {
                return Err(e);
            }
            linear += report.iterations;
            if report.converged {
                break;
            }
            if self.refreshed {
                return Err(Error::new(
                    Status::ErrNotConverged,
                    format!(
                        "Newton–Krylov: GMRES did not reach η = {eta:.1e} in {} iterations at Newton iteration {}, even with a fresh preconditioner",
                        opts.max_linear, it.iteration
                    ),
                ));
            }
            self.refresh(eq, x)?;
            self.refreshed = true;
            self.linear += linear;
            linear = 0;
        }
        self.linear += linear;
        self.last = linear;
        Ok(LinearStep { eta, fresh: true })
    }

    fn accepted(&mut self, eq: &mut E, x: &[f64], _f: &[f64], _step: &super::Accepted) -> Result<()> {
        // A preconditioner that has gone stale (many Krylov iterations) is
        // refreshed at the new point.
        if self.last > self.opts.refresh_after && !self.refreshed {
            self.refresh(eq, x)?;
        }
        Ok(())
    }
}

/// Solve F(x) = 0 from `x` (overwritten with the solution) by
/// Newton–Krylov with the lagged band preconditioner `pre`; its Jacobians
/// come from `jacobian_source` (None: the equations themselves; for a model
/// without a usable Jacobian, a cheaper model on the same pattern).
/// The report's `counts.residuals` is left 0: the equations count their
/// own evaluations.
/// Non-convergence (Newton, or a linear solve failing after a refresh) is
/// ErrNotConverged; a non-finite residual is ErrNonFiniteResult.
pub fn solve<'a, E: SparseJacobian + ?Sized>(
    eq: &mut E,
    jacobian_source: Option<&'a mut dyn SparseJacobian>,
    pre: &'a mut BandPreconditioner,
    x: &mut [f64],
    opts: &'a KrylovOptions,
) -> Result<KrylovReport> {
    let n = eq.dim();
    crate::error::dimension("Newton–Krylov state length", x.len() as i64, n as i64, n as i64)?;
    if pre.lu.dim() != n {
        return Err(Error::new(
            Status::ErrInvalidDimension,
            "Newton–Krylov: the preconditioner is for another dimension",
        ));
    }
    crate::error::positive("Newton–Krylov residual tolerance", opts.residual_tol)?;
    crate::error::count_in_range("GMRES restart length", opts.restart as i64, 1, 10_000)?;
    let d = eq.equation_scales();
    let before = pre.work;
    let mut linear = KrylovStep {
        pre,
        source: jacobian_source,
        opts,
        d: d.clone(),
        s: eq.unknown_scales(),
        gmres: Gmres::new(n, opts.restart),
        eta: opts.eta_max,
        b: vec![0.0; n],
        trial: vec![0.0; n],
        rp: vec![0.0; n],
        linear: 0,
        last: 0,
        refreshed: false,
    };
    if !linear.pre.factorised {
        linear.refresh(eq, x)?;
    }
    // Backtracking on ‖F̃‖₂ (Armijo, halving). The full step is also
    // accepted when it gives the same sufficient decrease in the max norm
    // of the convergence test: a long rod's first correction moves an end
    // condition's residual (one large entry) into O(step²) errors on every
    // equation, which lowers max |F̃_i| twentyfold while ‖F̃‖₂, summing n of
    // them, grows — and halving that step costs a Newton iteration (10 kbp
    // DNA rod: 4 iterations instead of 3). Shorter steps are held to ‖F̃‖₂,
    // along which the direction is a descent.
    let mut search = Backtracking::new(d.clone(), Norm::Two, 10);
    search.full_step_max_norm = true;
    let mut test = ResidualTest::new(d, opts.residual_tol, "Newton–Krylov");
    let report = super::solve(eq, x, &mut linear, &mut search, &mut test, opts.max_newton)?;
    let mut counts = linear.pre.work;
    counts.jacobians -= before.jacobians;
    counts.factorisations -= before.factorisations;
    counts.solves -= before.solves;
    counts.residuals = 0;
    Ok(KrylovReport {
        newton_iterations: report.iterations,
        linear_iterations: linear.linear,
        residual: report.norm,
        counts,
    })
}

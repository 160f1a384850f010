//! Newton–Krylov equilibria at fixed Λ, the alternative to the sparse
//! direct Newton of [`super::newton`] that issue 5 asks to measure: R(x, Λ)
//! = 0 by inexact Newton, each step by right-preconditioned GMRES(m).
//!
//! * Jacobian-free: J v = (R(x + σ v) − R(x)) / σ, one residual per Krylov
//!   iteration. The model's own Jacobian is never factorised, and need not
//!   even exist (the all-pairs base-pair rod, whose exact Jacobian is dense).
//! * Preconditioner ([`BandPreconditioner`]): the sparse LU of the banded
//!   part of a Jacobian — entries with |i − j| ≤ w, plus the two corner
//!   blocks (min(i, j) < w, max(i, j) ≥ n − w) where a two-point boundary
//!   value problem's end conditions couple its first and last unknowns. For
//!   a rod ordered along its arc length, w = one element's coupling keeps
//!   the elastic rod whole and drops the electrostatic far pairs, whose
//!   entries widen the band several-fold (the LU's cost grows as n w²).
//!   It is lagged: factorised once and kept while GMRES converges in few
//!   iterations, so a sequence of solves (a continuation) amortises it.
//! * Forcing terms of Eisenstat & Walker (SIAM J. Sci. Comput. 17, 16
//!   (1996), choice 2: η_k = 0.9 (‖F_k‖/‖F_{k−1}‖)², safeguarded, capped
//!   at η_max, floored so that the last step does not oversolve), and a
//!   backtracking line search on ‖F‖₂ (Armijo, halving; the full step
//!   may pass in the max norm instead, see the loop).
//!
//! Everything is in the scaled variables of the direct engine: x̃ = x / s
//! (unknown scales), F̃ = R / d (equation scales); convergence is the same
//! test, max |F̃_i| ≤ tol. Buffers are allocated once per solve.

use super::newton::{backtrack, residual_norm};
use super::{Counts, Problem, Scaling};
use crate::error::{Error, Result};
use crate::linalg::band::BandLu;
use crate::linalg::Pattern;
use crate::status::Status;

/// Options of [`newton_krylov`].
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
    /// Final max |R_i| / d_i.
    pub residual: f64,
    /// Residuals, Jacobians (for the preconditioner), factorisations and
    /// preconditioner solves.
    pub counts: Counts,
}

/// The lagged preconditioner: the LU of the band of a Jacobian
/// ([`BandLu`]: the rod's band, the boundary corners, an optional border)
/// with the Jacobian buffers it is evaluated into, its numeric
/// factorisation kept until [`BandPreconditioner::refresh`].
pub struct BandPreconditioner {
    lu: BandLu,
    jx: Vec<f64>,
    jl: Vec<f64>,
    factorised: bool,
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
        Ok(BandPreconditioner { lu, jx: vec![0.0; pattern.nnz()], jl: vec![0.0; pattern.n], factorised: false })
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

    /// Evaluate `source`'s Jacobian at (x, Λ) (its pattern must be the one
    /// given to [`BandPreconditioner::new`]) and factorise its band.
    pub fn refresh<Q: Problem + ?Sized>(
        &mut self,
        source: &mut Q,
        x: &[f64],
        lambda: f64,
        counts: &mut Counts,
    ) -> Result<()> {
        if source.dim() != self.lu.dim() || source.pattern().nnz() != self.jx.len() {
            return Err(Error::new(
                Status::ErrInvalidDimension,
                "band preconditioner: the Jacobian's pattern is not the one it was built for",
            ));
        }
        self.factorised = false;
        source.jacobian(x, lambda, &mut self.jx, &mut self.jl);
        counts.jacobians += 1;
        self.lu.factorise(&self.jx)?;
        counts.factorisations += 1;
        self.factorised = true;
        Ok(())
    }

    fn apply(&mut self, v: &mut [f64], counts: &mut Counts) {
        self.lu.solve(v);
        counts.solves += 1;
    }
}

/// Scaled 2-norm.
fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// Solve R(x, Λ) = 0 at fixed Λ from `x` (overwritten with the solution)
/// by Newton–Krylov with the lagged band preconditioner `pre`; its
/// Jacobians come from `jacobian_source` (None: the problem itself; for a
/// model without a usable Jacobian, a cheaper model on the same pattern).
/// Non-convergence (Newton or a linear solve failing after a refresh) is
/// ErrNotConverged; a non-finite residual is ErrNonFiniteResult.
pub fn newton_krylov<P: Problem + ?Sized>(
    problem: &mut P,
    mut jacobian_source: Option<&mut dyn Problem>,
    pre: &mut BandPreconditioner,
    x: &mut [f64],
    lambda: f64,
    opts: &KrylovOptions,
) -> Result<KrylovReport> {
    let n = problem.dim();
    crate::error::count_in_range("Newton–Krylov state length", x.len() as i64, n as i64, n as i64)?;
    if pre.lu.dim() != n {
        return Err(Error::new(
            Status::ErrInvalidDimension,
            "Newton–Krylov: the preconditioner is for another dimension",
        ));
    }
    crate::error::positive("Newton–Krylov residual tolerance", opts.residual_tol)?;
    crate::error::count_in_range("GMRES restart length", opts.restart as i64, 1, 10_000)?;
    let d = problem.equation_scales();
    // rms of x̃ = x / s (Λ does not vary here).
    let scaling = Scaling::of(problem);
    let rms = |v: &[f64]| scaling.norm(v, 0.0);
    let m = opts.restart;
    let mut report = KrylovReport::default();
    let refresh = |pre: &mut BandPreconditioner,
                   src: &mut Option<&mut dyn Problem>,
                   problem: &mut P,
                   x: &[f64],
                   counts: &mut Counts| match src {
        Some(q) => pre.refresh(&mut **q, x, lambda, counts),
        None => pre.refresh(problem, x, lambda, counts),
    };
    if !pre.factorised {
        refresh(pre, &mut jacobian_source, problem, x, &mut report.counts)?;
    }
    // Buffers: Krylov basis V (m + 1 vectors), Hessenberg H, Givens.
    let mut basis = vec![0.0; (m + 1) * n];
    let mut h = vec![0.0; (m + 1) * m];
    let (mut cs, mut sn, mut g, mut y) = (vec![0.0; m], vec![0.0; m], vec![0.0; m + 1], vec![0.0; m]);
    let (mut r, mut f, mut rp, mut z, mut step, mut trial) =
        (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let eval = |problem: &mut P, x: &[f64], r: &mut [f64], f: &mut [f64], counts: &mut Counts| {
        problem.residual(x, lambda, r);
        counts.residuals += 1;
        for i in 0..n {
            f[i] = r[i] / d[i];
        }
    };
    eval(problem, x, &mut r, &mut f, &mut report.counts);
    let mut fnorm = norm2(&f);
    // ‖F_k‖ / ‖F_{k−1}‖ of the last accepted step, in the norm that
    // accepted it (NaN before the first).
    let mut rate = f64::NAN;
    let mut eta = opts.eta_max;
    for it in 0..=opts.max_newton {
        let res = residual_norm(&r, &d);
        report.residual = res;
        if !res.is_finite() {
            return Err(Error::new(
                Status::ErrNonFiniteResult,
                format!("Newton–Krylov: non-finite residual at iteration {it}"),
            ));
        }
        if res <= opts.residual_tol {
            report.newton_iterations = it;
            return Ok(report);
        }
        if it == opts.max_newton {
            break;
        }
        // Forcing term (Eisenstat–Walker choice 2, safeguarded), floored so
        // that the linear residual is not pushed far below the tolerance.
        if rate.is_finite() {
            let candidate = 0.9 * rate * rate;
            let safeguard = 0.9 * eta * eta;
            eta = if safeguard > 0.1 { candidate.max(safeguard) } else { candidate };
            eta = eta.min(opts.eta_max);
        }
        // A step that barely reduced the residual (rate > 0.9, where choice
        // 2 would return to η_max) is followed by an accurate one: on the
        // DNA rod under a torque clamp, re-solved with base pairs, η = 0.1
        // stalled at 5e-7 (30 Newton steps of 3 GMRES iterations each
        // reducing it by 0.3 %); with η ≤ 1e-3 it converged in 12.
        if rate > 0.9 {
            eta = eta.min(1e-3);
        }
        // The floor is relative to the max norm, the convergence test's:
        // GMRES reduces ‖F̃‖₂ by η, and a residual spread over a long rod has
        // ‖F̃‖₂ ≈ √n‖F̃‖∞, so a floor of tol/‖F̃‖₂ asked the last linear solve
        // for √n times more than the test needs — one more GMRES iteration
        // at 10 kbp than at 3 (DNA rod, 7 → 6; the Newton steps unchanged).
        eta = eta.max(0.25 * opts.residual_tol / res).min(opts.eta_max);
        // GMRES(m) on J̃ M̃⁻¹ y = −F̃ (x̃ = x / s), the step x̃ ← M̃⁻¹ y.
        let xnorm = rms(x).max(1.0);
        // J̃-products along an unscaled direction v, into `out` (scaled):
        // differences of R with a perturbation of rms opts.perturbation·
        // max(1, rms x̃) in the scaled unknowns.
        let pert = opts.perturbation * xnorm;
        let central = opts.central;
        let xs: &[f64] = x;
        let rs: &[f64] = &r;
        let product =
            |problem: &mut P, v: &[f64], out: &mut [f64], trial: &mut [f64], rp: &mut [f64], counts: &mut Counts| {
                let vnorm = rms(v);
                if vnorm == 0.0 || !vnorm.is_finite() {
                    out.fill(0.0);
                    return;
                }
                let sigma = pert / vnorm;
                for i in 0..n {
                    trial[i] = xs[i] + sigma * v[i];
                }
                problem.residual(trial, lambda, rp);
                counts.residuals += 1;
                if central {
                    // (R(x + σv) − R(x − σv)) / 2σ: O(σ²), robust along the
                    // soft directions of a long rod where |J v| ≪ |J||v| and a
                    // forward difference's O(σ) error is not small relative to it.
                    for i in 0..n {
                        out[i] = rp[i];
                        trial[i] = xs[i] - sigma * v[i];
                    }
                    problem.residual(trial, lambda, rp);
                    counts.residuals += 1;
                    for i in 0..n {
                        out[i] = (out[i] - rp[i]) / (2.0 * sigma * d[i]);
                    }
                } else {
                    for i in 0..n {
                        out[i] = (rp[i] - rs[i]) / (sigma * d[i]);
                    }
                }
            };
        let mut solved = false;
        let mut refreshed = false;
        let mut linear = 0;
        while !solved {
            step.fill(0.0);
            let target = eta * fnorm;
            let mut rnorm = fnorm;
            // Initial residual of the linear system: −F̃ (zero initial step).
            for i in 0..n {
                basis[i] = -f[i] / fnorm;
            }
            while linear < opts.max_linear && !solved {
                g.fill(0.0);
                g[0] = rnorm;
                let mut k_done = 0;
                for k in 0..m {
                    // w = J̃ M̃⁻¹ v_k by a residual difference.
                    let (head, tail) = basis.split_at_mut((k + 1) * n);
                    let vk = &head[k * n..];
                    for i in 0..n {
                        z[i] = vk[i] * d[i];
                    }
                    pre.apply(&mut z, &mut report.counts); // z = M⁻¹ D v (unscaled)
                    let w = &mut tail[..n];
                    product(problem, &z, w, &mut trial, &mut rp, &mut report.counts);
                    linear += 1;
                    // Modified Gram–Schmidt, twice (the FD products are
                    // not exact, orthogonality is kept anyway).
                    for _ in 0..2 {
                        for j in 0..=k {
                            let vj = &head[j * n..(j + 1) * n];
                            let hij: f64 = vj.iter().zip(w.iter()).map(|(a, b)| a * b).sum();
                            h[j * m + k] += hij;
                            for i in 0..n {
                                w[i] -= hij * vj[i];
                            }
                        }
                    }
                    let hk = norm2(w);
                    h[(k + 1) * m + k] = hk;
                    if hk > 0.0 {
                        for v in w.iter_mut() {
                            *v /= hk;
                        }
                    }
                    // Givens rotations on column k.
                    for j in 0..k {
                        let (a, b) = (h[j * m + k], h[(j + 1) * m + k]);
                        h[j * m + k] = cs[j] * a + sn[j] * b;
                        h[(j + 1) * m + k] = -sn[j] * a + cs[j] * b;
                    }
                    let (a, b) = (h[k * m + k], h[(k + 1) * m + k]);
                    let rho = a.hypot(b);
                    (cs[k], sn[k]) = if rho == 0.0 { (1.0, 0.0) } else { (a / rho, b / rho) };
                    h[k * m + k] = rho;
                    h[(k + 1) * m + k] = 0.0;
                    g[k + 1] = -sn[k] * g[k];
                    g[k] *= cs[k];
                    rnorm = g[k + 1].abs();
                    k_done = k + 1;
                    if rnorm <= target || hk == 0.0 || linear >= opts.max_linear {
                        break;
                    }
                }
                // y = H⁻¹ g (upper triangular), step += M̃⁻¹ V y.
                for i in (0..k_done).rev() {
                    let mut acc = g[i];
                    for j in i + 1..k_done {
                        acc -= h[i * m + j] * y[j];
                    }
                    y[i] = if h[i * m + i] != 0.0 { acc / h[i * m + i] } else { 0.0 };
                }
                z.fill(0.0);
                for (j, yj) in y[..k_done].iter().enumerate() {
                    for i in 0..n {
                        z[i] += yj * basis[j * n + i];
                    }
                }
                for i in 0..n {
                    z[i] *= d[i];
                }
                pre.apply(&mut z, &mut report.counts);
                for i in 0..n {
                    step[i] += z[i];
                }
                h.fill(0.0);
                solved = rnorm <= target;
                if !solved && linear < opts.max_linear {
                    // Restart from the true linear residual −F̃ − J̃ step.
                    product(problem, &step, &mut basis[..n], &mut trial, &mut rp, &mut report.counts);
                    for i in 0..n {
                        basis[i] = -(f[i] + basis[i]);
                    }
                    rnorm = norm2(&basis[..n]);
                    if rnorm <= target {
                        solved = true;
                    } else {
                        for v in basis[..n].iter_mut() {
                            *v /= rnorm;
                        }
                    }
                }
            }
            if !solved {
                if refreshed {
                    return Err(Error::new(Status::ErrNotConverged, format!(
                        "Newton–Krylov: GMRES did not reach η = {eta:.1e} in {} iterations at Newton iteration {it}, even with a fresh preconditioner", opts.max_linear)));
                }
                refresh(pre, &mut jacobian_source, problem, x, &mut report.counts)?;
                refreshed = true;
                report.linear_iterations += linear;
                linear = 0;
            }
        }
        report.linear_iterations += linear;
        // Backtracking on ‖F̃‖₂ (Armijo, halving). The full step is also
        // accepted when it gives the same sufficient decrease in the max norm
        // of the convergence test: a long rod's first correction moves an
        // end condition's residual (one large entry) into O(step²) errors on
        // every equation, which lowers max |F̃_i| twentyfold while ‖F̃‖₂,
        // summing n of them, grows — and halving that step costs a Newton
        // iteration (10 kbp DNA rod: 4 iterations instead of 3). Shorter
        // steps are held to ‖F̃‖₂, along which the direction is a descent.
        let mut new_fnorm = fnorm;
        let taken =
            backtrack(problem, x, &step, lambda, &mut r, &mut trial, &mut rp, 10, &mut report.counts, |t, rt| {
                for i in 0..n {
                    z[i] = rt[i] / d[i];
                }
                let trial_norm = norm2(&z);
                let decrease = 1.0 - 1e-4 * t * (1.0 - eta);
                let trial_max = residual_norm(rt, &d);
                let by_two_norm = trial_norm <= decrease * fnorm;
                let ok = trial_norm.is_finite() && (by_two_norm || (t == 1.0 && trial_max <= decrease * res));
                if ok {
                    // A step accepted on the max norm measures its rate there:
                    // the 2-norm's grew, and would cap the next forcing term.
                    rate = if by_two_norm { trial_norm / fnorm } else { trial_max / res };
                    new_fnorm = trial_norm;
                }
                ok
            });
        if taken.is_none() {
            return Err(Error::new(
                Status::ErrNotConverged,
                format!("Newton–Krylov: no decrease of the residual along the step at iteration {it}"),
            ));
        }
        // z holds the accepted point's scaled residual (the last trial).
        std::mem::swap(&mut f, &mut z);
        fnorm = new_fnorm;
        report.newton_iterations = it + 1;
        // A preconditioner that has gone stale (many Krylov iterations) is
        // refreshed at the new point.
        if linear > opts.refresh_after && !refreshed {
            refresh(pre, &mut jacobian_source, problem, x, &mut report.counts)?;
        }
    }
    Err(Error::new(
        Status::ErrNotConverged,
        format!(
            "Newton–Krylov: residual {:.2e} above {:.1e} after {} iterations",
            report.residual, opts.residual_tol, opts.max_newton
        ),
    ))
}

//! The asymptotic numerical method (physics.md §2.4): at a regular point X0
//! of the branch, expand X(a) = Σ_{p≤P} a^p X_p in the pseudo-arc-length
//! a = ⟨X − X0, X1⟩_W and get every X_p from ONE factorisation of the
//! bordered tangent B = [[R_x, R_Λ], [vᵀW]] (v: the previous tangent):
//!
//! * order 1: B y = (0, 1), X1 = y/‖y‖_W (so ‖X1‖_W = 1, oriented along v);
//! * order p ≥ 2: B z = (−F_p, 0), X_p = z − ⟨z, X1⟩_W X1, where F_p is the
//!   order-p coefficient of R along the series with X_p = 0 — computed by
//!   [`SeriesProblem::series_order`] from the stored series of the
//!   intermediate products (O(p) per product, O(P²N) per step; the O(P³)
//!   triple sum is never formed). Adding X1 to z keeps R_x-part unchanged
//!   (R' X1 = 0) and makes ⟨X_p, X1⟩_W = 0, as the arc-length definition
//!   requires.
//! * step a_max = (ε ‖X1‖_W / ‖X_P‖_W)^{1/(P−1)} (ε: the accepted size of
//!   the last term relative to the first);
//! * the end point X(a_max) is Newton-corrected (chord iterations on the
//!   step's factorisation, a fresh one only if they stall; from a fresh one
//!   at X(a_max) when a dense-output sample's correction has replaced the
//!   step's) whenever its residual exceeds the requested tolerance: ε bounds
//!   the series' last term, not the residual, which would otherwise drift
//!   from step to step.
//!
//! The next step's border is the series' own tangent dX/da at a_max. A
//! target Λ inside a step is located on the polynomial Λ(a) and the point
//! corrected at fixed Λ.

use super::bifurcation::{SeriesHint, State};
use super::corrector::{correct, Plane, Reuse};
use super::indicator::Indicator;
use super::newton::Start;
use super::pade::{self, Curve};
use super::run::{resume_step, validate_resume, Factors, Placed, Run};
use super::{Branch, Options, Record, Resume, SeriesProblem, Stop};
use crate::error::{self, Error, Result};
use crate::nonlinear::scaled_max_norm;
use crate::roots::{all_roots, first_root};
use crate::status::Status;

/// ANM settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnmOptions {
    /// Series order P (≥ 2; 15–30 is typical, at most 60).
    pub order: usize,
    /// ε of the step-length rule.
    pub epsilon: f64,
    /// Use the Padé approximants of the series (common denominator) where
    /// they reach further than the polynomial for the same ε
    /// ([`super::pade`]); the polynomial otherwise.
    pub pade: bool,
}

impl Default for AnmOptions {
    fn default() -> Self {
        AnmOptions { order: 20, epsilon: 1e-8, pade: false }
    }
}

/// The Padé step is sought up to this multiple of the series' own step;
/// its ε criterion ([`pade::step`]) decides within. Every point a step
/// reaches is corrected to the residual tolerance: the reach changes how
/// many steps a branch takes (a step too long for its correction is
/// halved), not how accurate its points are (the runs behind the value:
/// benches/README.md).
pub(crate) const PADE_REACH: f64 = 8.0;

/// Continue a branch by the ANM. `opts.max_step` caps a_max (∞, the
/// default: the series' radius alone);
/// `opts.min_step` is the smallest a_max accepted before stopping with
/// StepTooSmall. Records and stops as for [`super::newton::continue_newton`].
pub fn continue_anm<P: SeriesProblem + ?Sized>(
    problem: &mut P,
    start: Start,
    opts: &Options,
    anm: &AnmOptions,
    mut observe: impl FnMut(&[f64], f64) -> Vec<f64>,
    mut progress: impl FnMut(&Record) -> bool,
) -> Result<Branch> {
    let mut run = Run::new(problem, opts)?;
    error::count_in_range("order", anm.order as i64, 2, pade::MAX_ORDER as i64)?;
    error::in_range("epsilon", anm.epsilon, 1e-15, 1e-1)?;
    let (mut x, mut lambda, mut v, first_iterations) = begin(&mut run, problem, start)?;
    let mut expansion = Expansion::new(problem.dim(), anm.order);
    let mut indicator = (opts.detect_bifurcations && opts.series_indicator && problem.has_series_tangent())
        .then(|| Indicator::new(problem.dim(), anm.order, &run.ctx.eq));
    // What the next record reports of the step that reached its point.
    let (mut iterations, mut step_length, mut series_residual) = (first_iterations, 0.0, None);
    let mut last_a = opts.initial_step;
    // Starting on the target: the start is the answer.
    let mut at_target = opts.target_lambda == Some(lambda);
    for step in 0..=opts.max_steps {
        // One factorisation at X0 with the border v.
        if let Err(e) = run.ctx.factorise(problem, &x, lambda, (&v.0, v.1), Factors::Exact) {
            if run.records.is_empty() {
                return Err(e);
            }
            run.deliver_pending(problem, (&v.0, v.1), &mut observe, true);
            return Ok(run.finish(Stop::StepTooSmall, State { x, lambda, tx: v.0, tl: v.1 }, last_a, None));
        }
        let (x1, l1) = run.ctx.tangent()?;
        let here = State { x, lambda, tx: x1, tl: l1 };
        // The record of X0 (its determinant signs need this factorisation).
        let mut rec = run.record(problem, &here, step_length, iterations, &mut observe);
        rec.series_residual = series_residual;
        let go_on = run.push(rec, &mut progress);
        if opts.detect_bifurcations && run.watch(problem, here.clone())? {
            // Locating moved the factorisation: restore this step's.
            run.ctx.factorise(problem, &here.x, lambda, (&v.0, v.1), Factors::Exact)?;
        }
        // The last step's samples its start's factorisation did not reach,
        // on this point's (the series needs it back if they replaced it).
        if run.deliver_pending(problem, (&here.tx, here.tl), &mut observe, false) {
            run.ctx.factorise(problem, &here.x, lambda, (&v.0, v.1), Factors::Exact)?;
        }
        let stop = if at_target {
            Some(Stop::Target)
        } else if !go_on {
            Some(Stop::Cancelled)
        } else {
            (step == opts.max_steps).then_some(Stop::MaxSteps)
        };
        if let Some(stop) = stop {
            return Ok(run.finish(stop, here, last_a, None));
        }
        expansion.compute(&mut run, problem, &here);
        let radius = expansion.radius(&run, anm, last_a);
        // The problem's own limit (a charged rod's pair list).
        let a = problem.series_reach(radius);
        if !(a >= opts.min_step) {
            return Ok(run.finish(Stop::StepTooSmall, here, a, None));
        }
        // Padé: a longer step where the rational form stays within ε.
        // Not past a limit of the problem's own (`series_reach` cut a).
        let (a, denominator) = match anm.pade && a < opts.max_step && a >= radius {
            true => match pade::step(
                &expansion.series,
                &run.ctx.scaling,
                anm.epsilon,
                a,
                (PADE_REACH * a).min(opts.max_step),
            ) {
                Some((t, d)) if t > a => {
                    run.ctx.counts.pade_steps += 1;
                    (t, Some(d))
                }
                _ => (a, None),
            },
            false => (a, None),
        };
        // The series indicator's roots in this step (a polynomial step:
        // the hint's predictor is the series).
        run.series_hint = None;
        if let Some(ind) = indicator.as_mut().filter(|_| denominator.is_none()) {
            if ind.compute(&mut run.ctx, problem) {
                let roots = ind.roots(a);
                let clear = roots.is_empty() && ind.clear_of_roots(a);
                let series = if roots.is_empty() { vec![] } else { expansion.series.clone() };
                run.series_hint = Some(SeriesHint { record: run.records.len() - 1, roots, step: a, series, clear });
            }
        }
        let curve = match &denominator {
            Some(d) => Curve::Pade(&expansion.series, d),
            None => Curve::Series(&expansion.series),
        };
        let (kept, delivered) = samples(&mut run, problem, &curve, a, &here, &mut observe);
        let end = match end_point(&mut run, problem, &curve, a, &here, &v, kept)? {
            End::Reached(end) => {
                // A halved step: the samples past its end are the next
                // step's (delivered from its own start, not twice).
                if end.a < a && !end.target {
                    let past: Vec<Placed> = delivered.iter().filter(|&&(t, _)| t > end.a).map(|&(_, p)| p).collect();
                    run.withdraw(&past);
                }
                end
            }
            End::Stopped(stop, a) => {
                run.deliver_pending(problem, (&here.tx, here.tl), &mut observe, true);
                return Ok(run.finish(stop, here, a, None));
            }
        };
        run.ctx.counts.steps += 1;
        let tnorm = run.ctx.scaling.norm(&end.tangent[..end.x.len()], end.tangent[end.x.len()]);
        v = (end.tangent[..end.x.len()].iter().map(|t| t / tnorm).collect(), end.tangent[end.x.len()] / tnorm);
        let dx: Vec<f64> = here.x.iter().zip(&end.x).map(|(p, q)| q - p).collect();
        step_length = run.ctx.scaling.norm(&dx, end.lambda - here.lambda);
        (iterations, series_residual) = (end.iterations, Some(end.series_residual));
        // A target point is recorded at the loop's top, after its factorisation.
        at_target = end.target;
        (x, lambda, last_a) = (end.x, end.lambda, end.a);
    }
    unreachable!("the loop returns")
}

/// The first point, the border of its first factorisation and the Newton
/// iterations that corrected it.
type Begin = (Vec<f64>, f64, (Vec<f64>, f64), usize);

fn begin<P: SeriesProblem + ?Sized>(run: &mut Run, problem: &mut P, start: Start) -> Result<Begin> {
    match start {
        Start::Point { x, lambda, increasing } => {
            let (x, l, it) = run.corrected_start(problem, x, lambda)?;
            let e_lambda = vec![0.0; x.len()];
            Ok((x, l, (e_lambda, if increasing { 1.0 } else { -1.0 }), it))
        }
        // Exactly singular: a resume at a bifurcation point; leave it as a
        // switch does.
        Start::Resume(r) => {
            run.carry(&r);
            match run.factorise_resume(problem, &r)? {
                true => Ok((r.x, r.lambda, (r.tangent_x, r.tangent_lambda), 0)),
                false => leave_singular(run, problem, &r),
            }
        }
        // A switch at a (near-)singular point: the series needs a regular
        // expansion point and a tangent that is not the nearly singular
        // matrix's arbitrary null mix, so the first step is a Newton
        // predictor–corrector step along the given direction.
        Start::Switch(r) => {
            validate_resume(&r, problem.dim())?;
            leave_singular(run, problem, &r)
        }
    }
}

/// The series X_p, p = 0…P (each n + 1 long, Λ last) at a point, with the
/// buffers of its recursion.
struct Expansion {
    series: Vec<Vec<f64>>,
    rhs: Vec<f64>,
    z: Vec<f64>,
    zeros: Vec<f64>,
}

impl Expansion {
    fn new(n: usize, order: usize) -> Self {
        Expansion {
            series: vec![vec![0.0; n + 1]; order + 1],
            rhs: vec![0.0; n],
            z: vec![0.0; n + 1],
            zeros: vec![0.0; n],
        }
    }

    /// Every order from the current factorisation (module docs): X_0 the
    /// point, X_1 its tangent, X_p (p ≥ 2) from B z = (−F_p, 0) made
    /// W-orthogonal to X_1.
    fn compute<P: SeriesProblem + ?Sized>(&mut self, run: &mut Run, problem: &mut P, here: &State) {
        let n = here.x.len();
        let p_max = self.series.len() - 1;
        let (x1, l1) = (&here.tx, here.tl);
        self.series[0][..n].copy_from_slice(&here.x);
        self.series[0][n] = here.lambda;
        self.series[1][..n].copy_from_slice(x1);
        self.series[1][n] = l1;
        problem.series_begin(&here.x, here.lambda, p_max);
        problem.series_commit(1, x1, l1, &mut self.rhs);
        let z = &mut self.z;
        for p in 2..=p_max {
            problem.series_order(p, &self.zeros, 0.0, &mut self.rhs);
            for i in 0..n {
                z[i] = -self.rhs[i];
            }
            z[n] = 0.0;
            run.ctx.bordered.solve(z, &mut run.ctx.counts);
            let c = run.ctx.scaling.dot(&z[..n], z[n], x1, l1);
            for i in 0..n {
                z[i] -= c * x1[i];
            }
            z[n] -= c * l1;
            self.series[p].copy_from_slice(z);
            problem.series_commit(p, &z[..n], z[n], &mut self.rhs);
            run.ctx.counts.series_orders += 1;
        }
    }

    /// a_max from the last term (and the one before: a series with
    /// vanishing odd or even terms would otherwise overshoot), capped at
    /// the maximal step. A non-finite term (a blown-up evaluation) gives a
    /// zero step.
    fn radius(&self, run: &Run, anm: &AnmOptions, last_a: f64) -> f64 {
        let n = self.rhs.len();
        let p_max = self.series.len() - 1;
        let radius = |p: usize| {
            let t = run.ctx.scaling.norm(&self.series[p][..n], self.series[p][n]);
            if !t.is_finite() {
                0.0
            } else if t > 0.0 {
                (anm.epsilon / t).powf(1.0 / (p - 1) as f64)
            } else {
                f64::INFINITY
            }
        };
        let a = if p_max > 2 { radius(p_max).min(radius(p_max - 1)) } else { radius(p_max) };
        let a = a.min(run.opts.max_step);
        // Last terms exactly zero (an exactly linear stretch, e.g. a
        // straight rod's pre-buckling path) and no bound asked: the series
        // holds anywhere, so the step doubles the last one.
        if a.is_finite() {
            a
        } else {
            (2.0 * last_a).max(run.opts.initial_step)
        }
    }
}

/// Dense output: every requested Λ the step (0, a] crosses, from the curve
/// (corrected on this step's factorisation when its residual is above the
/// tolerance). Returns whether the step's factorisation is still in hand
/// (false when a sample needed a fresh one: the end point's correction then
/// factorises at its own prediction, nearer than the step's start), and
/// where each sample went with its curve parameter (to take back those a
/// halved step does not reach: [`Run::withdraw`]).
fn samples<P: SeriesProblem + ?Sized>(
    run: &mut Run,
    problem: &mut P,
    curve: &Curve,
    a: f64,
    here: &State,
    observe: &mut impl FnMut(&[f64], f64) -> Vec<f64>,
) -> (bool, Vec<(f64, Placed)>) {
    let (lam0, lam1) = (here.lambda, curve.lambda(a));
    let record = run.records.len() - 1;
    let mut refactorised = false;
    let mut delivered = Vec::new();
    let opts = run.opts;
    for &target in &opts.samples {
        if (target - lam0) * (target - lam1) > 0.0 || target == lam0 {
            continue;
        }
        for t in all_roots(|t| curve.lambda(t) - target, a) {
            let mut xs = vec![0.0; here.x.len()];
            curve.evaluate(t, &mut xs, None);
            // After a deferred sample (none wait at a step's start: the
            // loop's top delivered them) the later ones wait too, in order.
            let placed = match run.has_pending() {
                true => run.defer(xs, target, record),
                false => {
                    let (fresh, placed) = run.sample(problem, xs, (target, (&here.tx, here.tl)), record, observe, true);
                    refactorised |= fresh;
                    placed
                }
            };
            delivered.push((t, placed));
        }
    }
    (!refactorised, delivered)
}

/// The corrected end of a step.
struct EndPoint {
    x: Vec<f64>,
    lambda: f64,
    /// dX/da there (n + 1, unnormalised): the next border.
    tangent: Vec<f64>,
    iterations: usize,
    /// The series' residual before the correction.
    series_residual: f64,
    /// The step length taken.
    a: f64,
    /// The point is the target Λ.
    target: bool,
}

enum End {
    Reached(EndPoint),
    /// The run stops (λ range, step too small) with this step length.
    Stopped(Stop, f64),
}

/// The end point X(a), corrected: chord on this step's factorisation
/// (border v; `kept` false: from a fresh one at X(a)), or at fixed Λ for a
/// target Λ inside the step (the first root of Λ(a) − Λ_t on (0, a]). A
/// correction that fails halves the step (a series evaluated too far out)
/// and drops the target.
fn end_point<P: SeriesProblem + ?Sized>(
    run: &mut Run,
    problem: &mut P,
    curve: &Curve,
    mut a: f64,
    here: &State,
    v: &(Vec<f64>, f64),
    mut kept: bool,
) -> Result<End> {
    let opts = run.opts;
    let n = here.x.len();
    let mut target = None;
    if let Some(t) = opts.target_lambda {
        if let Some(at) = first_root(|s| curve.lambda(s) - t, a) {
            a = at;
            target = Some(t);
        }
    }
    let mut x = vec![0.0; n];
    let mut tangent = vec![0.0; n + 1];
    let mut r = vec![0.0; n];
    loop {
        curve.evaluate(a, &mut x, Some(&mut tangent));
        let mut lambda = target.unwrap_or_else(|| curve.lambda(a));
        // Λ range: stop before leaving it.
        if target.is_none() && !(lambda >= opts.lambda_range.0 && lambda <= opts.lambda_range.1) {
            return Ok(End::Stopped(Stop::LambdaRange, a));
        }
        problem.residual(&x, lambda, &mut r);
        run.ctx.counts.residuals += 1;
        let series_residual = scaled_max_norm(&r, &run.ctx.eq);
        let end = |x, lambda, iterations| {
            End::Reached(EndPoint {
                x,
                lambda,
                tangent: tangent.clone(),
                iterations,
                series_residual,
                a,
                target: target.is_some(),
            })
        };
        if series_residual <= opts.residual_tol {
            return Ok(end(x, lambda, 0));
        }
        let anchor = x.clone();
        let result = match target {
            Some(t) => correct(
                problem,
                &mut run.ctx,
                &mut x,
                &mut lambda,
                Plane::fixed(&anchor, t),
                opts.residual_tol,
                Reuse::No,
            ),
            None => {
                let plane = Plane::new((&anchor, lambda), (&v.0, v.1));
                let reuse = if kept { Reuse::Chord } else { Reuse::ChordFromFresh };
                correct(problem, &mut run.ctx, &mut x, &mut lambda, plane, opts.residual_tol, reuse)
            }
        };
        if let Ok((it, _)) = result {
            let lambda = target.unwrap_or(lambda);
            return Ok(end(x, lambda, it));
        }
        // Back to this step's factorisation, half the step, no target
        // inside it any more.
        a *= 0.5;
        target = None;
        if !(a >= opts.min_step) {
            return Ok(End::Stopped(Stop::StepTooSmall, a));
        }
        run.ctx.factorise(problem, &here.x, here.lambda, (&v.0, v.1), Factors::Exact)?;
        kept = true;
    }
}

/// The first point off a singular point `r` along its direction: a Newton
/// predictor–corrector step of length r.step (halved until it converges),
/// with the secant as the next border.
fn leave_singular<P: SeriesProblem + ?Sized>(run: &mut Run, problem: &mut P, r: &Resume) -> Result<Begin> {
    let opts = run.opts;
    let mut ds = resume_step(r.step, opts, opts.max_step);
    loop {
        let mut x: Vec<f64> = r.x.iter().zip(&r.tangent_x).map(|(a, t)| a + ds * t).collect();
        let mut l = r.lambda + ds * r.tangent_lambda;
        let anchor = x.clone();
        let plane = Plane::new((&anchor, l), (&r.tangent_x, r.tangent_lambda));
        if let Ok((it, _)) = correct(problem, &mut run.ctx, &mut x, &mut l, plane, opts.residual_tol, Reuse::No) {
            let dx: Vec<f64> = x.iter().zip(&r.x).map(|(a, b)| a - b).collect();
            let norm = run.ctx.scaling.norm(&dx, l - r.lambda);
            if norm > 0.0 && norm.is_finite() {
                let vx = dx.iter().map(|v| v / norm).collect();
                return Ok((x, l, (vx, (l - r.lambda) / norm), it));
            }
        }
        ds *= 0.5;
        if !(ds >= opts.min_step) {
            return Err(Error::new(
                Status::ErrNotConverged,
                "ANM: no regular point found along the start direction (singular start)",
            ));
        }
    }
}

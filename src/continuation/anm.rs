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
//!   step's factorisation, a fresh one only if they stall) whenever its
//!   residual exceeds the requested tolerance: ε bounds the series' last
//!   term, not the residual, which would otherwise drift from step to step.
//!
//! The next step's border is the series' own tangent dX/da at a_max. A
//! target Λ inside a step is located on the polynomial Λ(a) and the point
//! corrected at fixed Λ.

use super::bifurcation::{Bifurcation, State};
use super::corrector::correct;
use super::corrector::deliver_sample;
use super::newton::{detect, make_record, validate, validate_resume, Start};
use super::pade::{self, Curve};
use super::tangent::Bordered;
use super::{Branch, Counts, Options, Record, Resume, Sample, Scaling, SeriesProblem, Stop};
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

/// Continue a branch by the ANM. `opts.max_step` caps a_max;
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
    validate(problem, opts)?;
    error::count_in_range("order", anm.order as i64, 2, pade::MAX_ORDER as i64)?;
    error::in_range("epsilon", anm.epsilon, 1e-15, 1e-1)?;
    let n = problem.dim();
    let p_max = anm.order;
    let scaling = opts.scaling.clone().unwrap_or_else(|| {
        let (x, lambda) = problem.unknown_scales();
        Scaling { x, lambda }
    });
    let eq = problem.equation_scales();
    let mut bordered = Bordered::new(problem.pattern())?;
    bordered.set_monitor_scales(&eq, &scaling);
    let mut counts = Counts::default();
    let e_lambda = vec![0.0; n];

    let (mut x, mut lambda, mut vx, mut vl, first_iterations) = match start {
        Start::Point { x, lambda, increasing } => {
            error::count_in_range("start point length", x.len() as i64, n as i64, n as i64)?;
            let mut x = x;
            let mut l = lambda;
            let anchor = x.clone();
            let (it, _) = correct(
                problem,
                &mut bordered,
                &scaling,
                &eq,
                &mut x,
                &mut l,
                (&anchor, lambda),
                (&e_lambda, 1.0),
                opts.residual_tol,
                false,
                &mut counts,
            )
            .map_err(|e| Error::new(e.status, format!("continuation start: {}", e.message)))?;
            (x, l, e_lambda.clone(), if increasing { 1.0 } else { -1.0 }, it)
        }
        Start::Resume(r) => {
            validate_resume(&r, n)?;
            match bordered.factorise_at(problem, &r.x, r.lambda, &r.tangent_x, r.tangent_lambda, &scaling, &mut counts)
            {
                Ok(()) => (r.x, r.lambda, r.tangent_x, r.tangent_lambda, 0),
                // Exactly singular: a resume at a bifurcation point; leave it
                // as a switch does.
                Err(e) if e.status == Status::ErrNotConverged => {
                    leave_singular(problem, &mut bordered, &scaling, &eq, &r, opts, &mut counts)?
                }
                Err(e) => return Err(e),
            }
        }
        // A switch at a (near-)singular point: the series needs a regular
        // expansion point and a tangent that is not the nearly singular
        // matrix's arbitrary null mix, so the first step is a Newton
        // predictor–corrector step along the given direction.
        Start::Switch(r) => {
            validate_resume(&r, n)?;
            leave_singular(problem, &mut bordered, &scaling, &eq, &r, opts, &mut counts)?
        }
    };
    let mut records: Vec<Record> = Vec::new();
    let mut pending_iterations = first_iterations;
    let mut pending_step = 0.0;
    let mut pending_series_residual: Option<f64> = None;
    // Series storage: X_p for p = 0..=P, each n + 1 long (Λ last).
    let mut series: Vec<Vec<f64>> = vec![vec![0.0; n + 1]; p_max + 1];
    let mut rhs = vec![0.0; n];
    let mut z = vec![0.0; n + 1];
    let mut last_a = opts.initial_step;
    let mut at_target = false;
    let mut bifurcations: Vec<Bifurcation> = Vec::new();
    let mut history: Vec<State> = Vec::new();
    let mut samples: Vec<Sample> = Vec::new();
    let mut missed: Vec<f64> = Vec::new();
    let mut refactorised = false;
    let mut r = vec![0.0; n];
    if opts.target_lambda == Some(lambda) {
        // Starting on the target: the start is the answer.
        at_target = true;
    }

    for step in 0..=opts.max_steps {
        // One factorisation at X0 with the border v.
        if let Err(e) = bordered.factorise_at(problem, &x, lambda, &vx, vl, &scaling, &mut counts) {
            if records.is_empty() {
                return Err(e);
            }
            return Ok(finish(
                Stop::StepTooSmall,
                x,
                lambda,
                vx,
                vl,
                last_a,
                records,
                counts,
                std::mem::take(&mut bifurcations),
            )
            .with_samples(samples, missed));
        }
        let (x1, l1) = bordered.tangent(&scaling, &mut counts)?;
        // The record of X0 (its determinant signs need this factorisation).
        let mut rec = make_record(
            problem,
            &mut bordered,
            &scaling,
            &eq,
            &x,
            lambda,
            &x1,
            l1,
            pending_step,
            pending_iterations,
            opts,
            &mut observe,
            &mut counts,
        );
        rec.series_residual = pending_series_residual;
        let go_on = progress(&rec);
        records.push(rec);
        if opts.detect_bifurcations {
            history.push(State { x: x.clone(), lambda, tx: x1.clone(), tl: l1 });
            if history.len() > 3 {
                history.remove(0);
            }
            let before = bordered.factorisations();
            if let Some(b) =
                detect(problem, &mut bordered, &scaling, &eq, opts, &records, &history, &bifurcations, &mut counts)?
            {
                bifurcations.push(b);
            }
            if bordered.factorisations() != before {
                // Locating moved the factorisation: restore this step's.
                bordered.factorise_at(problem, &x, lambda, &vx, vl, &scaling, &mut counts)?;
            }
        }
        if at_target {
            return Ok(finish(
                Stop::Target,
                x,
                lambda,
                x1,
                l1,
                last_a,
                records,
                counts,
                std::mem::take(&mut bifurcations),
            )
            .with_samples(samples, missed));
        }
        if !go_on {
            return Ok(finish(
                Stop::Cancelled,
                x,
                lambda,
                x1,
                l1,
                last_a,
                records,
                counts,
                std::mem::take(&mut bifurcations),
            )
            .with_samples(samples, missed));
        }
        if step == opts.max_steps {
            return Ok(finish(
                Stop::MaxSteps,
                x,
                lambda,
                x1,
                l1,
                last_a,
                records,
                counts,
                std::mem::take(&mut bifurcations),
            )
            .with_samples(samples, missed));
        }

        // The series.
        series[0][..n].copy_from_slice(&x);
        series[0][n] = lambda;
        series[1][..n].copy_from_slice(&x1);
        series[1][n] = l1;
        problem.series_begin(&x, lambda, p_max);
        problem.series_order(1, &x1, l1, &mut rhs);
        for p in 2..=p_max {
            problem.series_order(p, &e_lambda, 0.0, &mut rhs);
            for i in 0..n {
                z[i] = -rhs[i];
            }
            z[n] = 0.0;
            bordered.solve(&mut z, &mut counts);
            let c = scaling.dot(&z[..n], z[n], &x1, l1);
            for i in 0..n {
                z[i] -= c * x1[i];
            }
            z[n] -= c * l1;
            series[p].copy_from_slice(&z);
            problem.series_order(p, &z[..n], z[n], &mut rhs);
            counts.series_orders += 1;
        }
        // Step length from the last term (and the one before: a series with
        // vanishing odd or even terms would otherwise overshoot). A
        // non-finite term (a blown-up evaluation) gives a zero step.
        let norm_of = |v: &[f64]| scaling.norm(&v[..n], v[n]);
        let radius = |p: usize| {
            let t = norm_of(&series[p]);
            if !t.is_finite() {
                0.0
            } else if t > 0.0 {
                (anm.epsilon / t).powf(1.0 / (p - 1) as f64)
            } else {
                f64::INFINITY
            }
        };
        let mut a = if p_max > 2 { radius(p_max).min(radius(p_max - 1)) } else { radius(p_max) };
        a = a.min(opts.max_step);
        if !(a >= opts.min_step) {
            return Ok(finish(
                Stop::StepTooSmall,
                x,
                lambda,
                x1,
                l1,
                a,
                records,
                counts,
                std::mem::take(&mut bifurcations),
            )
            .with_samples(samples, missed));
        }
        // Padé: a longer step where the rational form stays within ε.
        let mut denominator = None;
        if anm.pade && a < opts.max_step {
            if let Some((t, d)) = pade::step(&series, &scaling, anm.epsilon, a, (4.0 * a).min(opts.max_step)) {
                if t > a {
                    a = t;
                    denominator = Some(d);
                    counts.pade_steps += 1;
                }
            }
        }
        let curve = match &denominator {
            Some(d) => Curve::Pade(&series, d),
            None => Curve::Series(&series),
        };
        let lam_at = |t: f64| curve.lambda(t);
        // Dense output: every requested Λ the step crosses, from the series
        // (corrected on this step's factorisation when its residual is
        // above the tolerance).
        if !opts.samples.is_empty() {
            let lam0 = lambda;
            let lam1 = lam_at(a);
            for &target in &opts.samples {
                if (target - lam0) * (target - lam1) > 0.0 || target == lam0 {
                    continue;
                }
                for t in all_roots(|t| lam_at(t) - target, a) {
                    let mut xs = vec![0.0; n];
                    curve.evaluate(t, &mut xs, None);
                    let sample = deliver_sample(
                        problem,
                        &mut bordered,
                        &scaling,
                        &eq,
                        &mut xs,
                        target,
                        (&x1, l1),
                        opts.residual_tol,
                        &mut counts,
                        &mut refactorised,
                    );
                    match sample {
                        Ok((iterations, residual)) => samples.push(Sample {
                            lambda: target,
                            record: records.len() - 1,
                            outputs: observe(&xs, target),
                            residual,
                            newton_iterations: iterations,
                        }),
                        Err(_) => missed.push(target),
                    }
                }
            }
            if refactorised {
                // A sample needed a fresh factorisation: restore the step's.
                bordered.factorise_at(problem, &x, lambda, &vx, vl, &scaling, &mut counts)?;
                refactorised = false;
            }
        }
        // A target Λ inside the step: the first root of Λ(a) − Λt on (0, a].
        let mut stop = None;
        if let Some(target) = opts.target_lambda {
            if let Some(at) = first_root(|t| lam_at(t) - target, a) {
                a = at;
                stop = Some(Stop::Target);
            }
        }
        // The end point, corrected: chord on this step's factorisation
        // (border v), or at fixed Λ for a target point. A correction that
        // fails halves the step (a series evaluated too far out).
        let mut xn = vec![0.0; n];
        let mut tn = vec![0.0; n + 1];
        let (mut ln, iterations, series_residual) = loop {
            curve.evaluate(a, &mut xn, Some(&mut tn));
            let mut ln = if stop == Some(Stop::Target) {
                opts.target_lambda.expect("a target stop has a target")
            } else {
                lam_at(a)
            };
            // Λ range: stop before leaving it.
            if stop.is_none() && !(ln >= opts.lambda_range.0 && ln <= opts.lambda_range.1) {
                return Ok(finish(
                    Stop::LambdaRange,
                    x,
                    lambda,
                    x1,
                    l1,
                    a,
                    records,
                    counts,
                    std::mem::take(&mut bifurcations),
                )
                .with_samples(samples, missed));
            }
            problem.residual(&xn, ln, &mut r);
            counts.residuals += 1;
            let series_residual = scaled_max_norm(&r, &eq);
            if series_residual <= opts.residual_tol {
                break (ln, 0, series_residual);
            }
            let anchor = xn.clone();
            let anchor_l = ln;
            let result = if stop == Some(Stop::Target) {
                correct(
                    problem,
                    &mut bordered,
                    &scaling,
                    &eq,
                    &mut xn,
                    &mut ln,
                    (&anchor, anchor_l),
                    (&e_lambda, 1.0),
                    opts.residual_tol,
                    false,
                    &mut counts,
                )
            } else {
                correct(
                    problem,
                    &mut bordered,
                    &scaling,
                    &eq,
                    &mut xn,
                    &mut ln,
                    (&anchor, anchor_l),
                    (&vx, vl),
                    opts.residual_tol,
                    true,
                    &mut counts,
                )
            };
            match result {
                Ok((it, _)) => break (ln, it, series_residual),
                Err(_) => {
                    // Back to this step's factorisation, half the step, no
                    // target inside it any more.
                    a *= 0.5;
                    stop = None;
                    if !(a >= opts.min_step) {
                        return Ok(finish(
                            Stop::StepTooSmall,
                            x,
                            lambda,
                            x1,
                            l1,
                            a,
                            records,
                            counts,
                            std::mem::take(&mut bifurcations),
                        )
                        .with_samples(samples, missed));
                    }
                    bordered.factorise_at(problem, &x, lambda, &vx, vl, &scaling, &mut counts)?;
                }
            }
        };
        pending_series_residual = Some(series_residual);
        counts.steps += 1;
        let tnorm = scaling.norm(&tn[..n], tn[n]);
        vx = tn[..n].iter().map(|v| v / tnorm).collect();
        vl = tn[n] / tnorm;
        pending_step = scaling.norm(&x.iter().zip(&xn).map(|(p, q)| q - p).collect::<Vec<_>>(), ln - lambda);
        pending_iterations = iterations;
        if stop == Some(Stop::Target) {
            // Recorded at the loop's top, after its factorisation.
            at_target = true;
            ln = opts.target_lambda.expect("a target stop has a target");
        }
        x = xn;
        lambda = ln;
        last_a = a;
    }
    unreachable!("the loop returns")
}

/// The first point off a singular point `r` along its direction: a Newton
/// predictor–corrector step of length r.step (halved until it converges),
/// with the secant as the next border.
#[allow(clippy::too_many_arguments)]
fn leave_singular<P: SeriesProblem + ?Sized>(
    problem: &mut P,
    bordered: &mut Bordered,
    scaling: &Scaling,
    eq: &[f64],
    r: &Resume,
    opts: &Options,
    counts: &mut Counts,
) -> Result<(Vec<f64>, f64, Vec<f64>, f64, usize)> {
    let mut ds = super::newton::resume_step(r.step, opts);
    loop {
        let mut x: Vec<f64> = r.x.iter().zip(&r.tangent_x).map(|(a, t)| a + ds * t).collect();
        let mut l = r.lambda + ds * r.tangent_lambda;
        let anchor = x.clone();
        let al = l;
        if let Ok((it, _)) = correct(
            problem,
            bordered,
            scaling,
            eq,
            &mut x,
            &mut l,
            (&anchor, al),
            (&r.tangent_x, r.tangent_lambda),
            opts.residual_tol,
            false,
            counts,
        ) {
            let dx: Vec<f64> = x.iter().zip(&r.x).map(|(a, b)| a - b).collect();
            let norm = scaling.norm(&dx, l - r.lambda);
            if norm > 0.0 && norm.is_finite() {
                let vx = dx.iter().map(|v| v / norm).collect();
                return Ok((x, l, vx, (l - r.lambda) / norm, it));
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

#[allow(clippy::too_many_arguments)]
fn finish(
    stop: Stop,
    x: Vec<f64>,
    lambda: f64,
    tx: Vec<f64>,
    tl: f64,
    step: f64,
    records: Vec<Record>,
    counts: Counts,
    bifurcations: Vec<Bifurcation>,
) -> Branch {
    Branch {
        records,
        bifurcations,
        stop,
        resume: Resume { x, lambda, tangent_x: tx, tangent_lambda: tl, step },
        counts,
        samples: Vec::new(),
        missed_samples: Vec::new(),
    }
}

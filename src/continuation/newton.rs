//! Newton pseudo-arc-length continuation (Keller): Euler predictor along the
//! unit tangent, Newton corrector on [R = 0, ⟨X − X_pred, t⟩_W = 0] with a
//! factorisation per iteration, step length adapted to the iteration count.
//! The baseline the ANM is measured against, and the engine the charged rod
//! reuses. Also the corrections both engines share.

use super::bifurcation::{self, Bifurcation, State};
use super::corrector::{correct, deliver_sample};
use super::tangent::Bordered;
use super::{Branch, Counts, Options, Problem, Record, Resume, Sample, Scaling, Stop};
use crate::error::{self, Error, Result};
use crate::nonlinear::scaled_max_norm;
use crate::roots::all_roots;
use crate::status::Status;

/// Where a continuation starts.
#[derive(Clone, Debug)]
pub enum Start {
    /// A solution (or a good guess, corrected at fixed Λ first), leaving in
    /// the direction of increasing Λ (`increasing`) or decreasing.
    Point { x: Vec<f64>, lambda: f64, increasing: bool },
    /// Where an earlier continuation stopped.
    Resume(Resume),
    /// Leave a (near-)singular point, a located bifurcation, along the
    /// given direction (`tangent_*`, first step `step`): the first point is
    /// a predictor–corrector step along it, halved until it converges. The
    /// tangent is never recomputed at the start: next to a bifurcation the
    /// bordered matrix is nearly singular and its "tangent" is an arbitrary
    /// mix of the two branches' (usually the old one's).
    Switch(Resume),
}

/// Cubic Hermite interpolation between two branch points X0, X1 with unit
/// tangents t0, t1 over the arc length h: X(θ), θ ∈ [0, 1] (Λ last).
fn hermite(
    x0: &[f64],
    l0: f64,
    t0: (&[f64], f64),
    x1: &[f64],
    l1: f64,
    t1: (&[f64], f64),
    h: f64,
    theta: f64,
    out: &mut [f64],
) -> f64 {
    // (Empty slices: the Λ part alone.)
    let (t2, t3) = (theta * theta, theta * theta * theta);
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + theta;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    for i in 0..out.len() {
        out[i] = h00 * x0[i] + h10 * h * t0.0[i] + h01 * x1[i] + h11 * h * t1.0[i];
    }
    h00 * l0 + h10 * h * t0.1 + h01 * l1 + h11 * h * t1.1
}

/// Newton pseudo-arc-length continuation. `observe(x, Λ)` chooses each
/// record's outputs; `progress(record)` returning false stops the run
/// (Stop::Cancelled).
pub fn continue_newton<P: Problem + ?Sized>(
    problem: &mut P,
    start: Start,
    opts: &Options,
    mut observe: impl FnMut(&[f64], f64) -> Vec<f64>,
    mut progress: impl FnMut(&Record) -> bool,
) -> Result<Branch> {
    validate(problem, opts)?;
    let n = problem.dim();
    let scaling = opts.scaling.clone().unwrap_or_else(|| {
        let (x, lambda) = problem.unknown_scales();
        Scaling { x, lambda }
    });
    let eq = problem.equation_scales();
    let mut bordered = Bordered::new(problem.pattern())?;
    bordered.set_monitor_scales(&eq, &scaling);
    let mut counts = Counts::default();
    let e_lambda = vec![0.0; n];

    // The first point and tangent.
    let mut singular_start = false;
    let (mut x, mut lambda, mut tx, mut tl, mut ds, first_iterations) = match start {
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
            let dir = if increasing { 1.0 } else { -1.0 };
            bordered.factorise_at(problem, &x, l, &e_lambda, dir, &scaling, &mut counts)?;
            let (tx, tl) = bordered.tangent(&scaling, &mut counts)?;
            (x, l, tx, tl, opts.initial_step, it)
        }
        Start::Resume(r) => {
            validate_resume(&r, n)?;
            let step = resume_step(r.step, opts);
            match bordered.factorise_at(problem, &r.x, r.lambda, &r.tangent_x, r.tangent_lambda, &scaling, &mut counts)
            {
                Ok(()) => {
                    let (tx, tl) = bordered.tangent(&scaling, &mut counts)?;
                    (r.x, r.lambda, tx, tl, step, 0)
                }
                // Exactly singular (a resume at a bifurcation point): keep
                // the given tangent, as a switch does.
                Err(e) if e.status == Status::ErrNotConverged => {
                    singular_start = true;
                    (r.x, r.lambda, r.tangent_x, r.tangent_lambda, step, 0)
                }
                Err(e) => return Err(e),
            }
        }
        Start::Switch(r) => {
            validate_resume(&r, n)?;
            singular_start = true;
            let step = resume_step(r.step, opts);
            (r.x, r.lambda, r.tangent_x, r.tangent_lambda, step, 0)
        }
    };
    let mut records = Vec::new();
    let first = if singular_start {
        let mut r = vec![0.0; n];
        problem.residual(&x, lambda, &mut r);
        counts.residuals += 1;
        Record {
            lambda,
            outputs: observe(&x, lambda),
            residual: scaled_max_norm(&r, &eq),
            step: 0.0,
            det_sign: 0.0,
            bordered_det_sign: 0.0,
            smallest_singular_value: Some(0.0),
            negative_pivots: None,
            newton_iterations: 0,
            series_residual: None,
        }
    } else {
        make_record(
            problem,
            &mut bordered,
            &scaling,
            &eq,
            &x,
            lambda,
            &tx,
            tl,
            0.0,
            first_iterations,
            opts,
            &mut observe,
            &mut counts,
        )
    };
    let go_on = progress(&first);
    records.push(first);
    let mut bifurcations: Vec<Bifurcation> = Vec::new();
    let mut history: Vec<State> = vec![State { x: x.clone(), lambda, tx: tx.clone(), tl }];
    let finish = |stop, x: Vec<f64>, lambda, tx, tl, ds, records, counts: Counts, bifurcations| Branch {
        records,
        bifurcations,
        stop,
        resume: Resume { x, lambda, tangent_x: tx, tangent_lambda: tl, step: ds },
        counts,
        samples: Vec::new(),
        missed_samples: Vec::new(),
    };
    let mut samples: Vec<Sample> = Vec::new();
    let mut missed: Vec<f64> = Vec::new();
    for &target in &opts.samples {
        if target == lambda {
            let rec = &records[0];
            samples.push(Sample {
                lambda,
                record: 0,
                outputs: observe(&x, lambda),
                residual: rec.residual,
                newton_iterations: 0,
            });
        }
    }
    if !go_on {
        return Ok(
            finish(Stop::Cancelled, x, lambda, tx, tl, ds, records, counts, bifurcations).with_samples(samples, missed)
        );
    }
    if opts.target_lambda == Some(lambda) {
        return Ok(
            finish(Stop::Target, x, lambda, tx, tl, ds, records, counts, bifurcations).with_samples(samples, missed)
        );
    }

    for _ in 0..opts.max_steps {
        // Predictor and corrector, halving the step on failure.
        let (mut xn, mut ln, iterations) = loop {
            let mut xn: Vec<f64> = x.iter().zip(&tx).map(|(a, t)| a + ds * t).collect();
            let mut ln = lambda + ds * tl;
            let anchor = xn.clone();
            let anchor_l = ln;
            match correct(
                problem,
                &mut bordered,
                &scaling,
                &eq,
                &mut xn,
                &mut ln,
                (&anchor, anchor_l),
                (&tx, tl),
                opts.residual_tol,
                false,
                &mut counts,
            ) {
                Ok((it, _)) => break (xn, ln, it),
                Err(_) => {
                    ds *= 0.5;
                    if ds < opts.min_step {
                        return Ok(finish(Stop::StepTooSmall, x, lambda, tx, tl, ds, records, counts, bifurcations)
                            .with_samples(samples, missed));
                    }
                }
            }
        };
        counts.steps += 1;
        // Target Λ crossed: interpolate and correct at fixed Λ.
        let mut stop = None;
        if let Some(target) = opts.target_lambda {
            if (ln - target) * (lambda - target) <= 0.0 && ln != lambda {
                let s = (target - lambda) / (ln - lambda);
                let mut xt: Vec<f64> = x.iter().zip(&xn).map(|(a, b)| a + s * (b - a)).collect();
                let mut lt = target;
                let anchor = xt.clone();
                if correct(
                    problem,
                    &mut bordered,
                    &scaling,
                    &eq,
                    &mut xt,
                    &mut lt,
                    (&anchor, target),
                    (&e_lambda, 1.0),
                    opts.residual_tol,
                    false,
                    &mut counts,
                )
                .is_err()
                {
                    return Ok(finish(Stop::StepTooSmall, x, lambda, tx, tl, ds, records, counts, bifurcations)
                        .with_samples(samples, missed));
                }
                (xn, ln) = (xt, target);
                stop = Some(Stop::Target);
            }
        }
        if stop.is_none() && !(ln >= opts.lambda_range.0 && ln <= opts.lambda_range.1) {
            return Ok(finish(Stop::LambdaRange, x, lambda, tx, tl, ds, records, counts, bifurcations)
                .with_samples(samples, missed));
        }
        // The tangent at the new point (one factorisation; its determinant
        // signs go into the record).
        // An exactly singular matrix there ends the branch with its records.
        let tangent = bordered
            .factorise_at(problem, &xn, ln, &tx, tl, &scaling, &mut counts)
            .and_then(|_| bordered.tangent(&scaling, &mut counts));
        let Ok((txn, tln)) = tangent else {
            return Ok(finish(Stop::StepTooSmall, x, lambda, tx, tl, ds, records, counts, bifurcations)
                .with_samples(samples, missed));
        };
        let step = scaling.norm(&x.iter().zip(&xn).map(|(a, b)| b - a).collect::<Vec<_>>(), ln - lambda);
        let rec = make_record(
            problem,
            &mut bordered,
            &scaling,
            &eq,
            &xn,
            ln,
            &txn,
            tln,
            step,
            iterations,
            opts,
            &mut observe,
            &mut counts,
        );
        let go_on = progress(&rec);
        records.push(rec);
        // Dense output: requested loads crossed by the step, predicted by
        // the cubic Hermite interpolant and corrected on the new point's
        // factorisation (as the ANM does on its series).
        let mut refactorised = false;
        for &target in &opts.samples {
            if (target - lambda) * (target - ln) > 0.0 || target == lambda {
                continue;
            }
            let mut xs = vec![0.0; n];
            for theta in
                all_roots(|t| hermite(&[], lambda, (&[], tl), &[], ln, (&[], tln), step, t, &mut []) - target, 1.0)
            {
                hermite(&x, lambda, (&tx, tl), &xn, ln, (&txn, tln), step, theta, &mut xs);
                match deliver_sample(
                    problem,
                    &mut bordered,
                    &scaling,
                    &eq,
                    &mut xs,
                    target,
                    (&txn, tln),
                    opts.residual_tol,
                    &mut counts,
                    &mut refactorised,
                ) {
                    Ok((it, res)) => samples.push(Sample {
                        lambda: target,
                        record: records.len() - 2,
                        outputs: observe(&xs, target),
                        residual: res,
                        newton_iterations: it,
                    }),
                    Err(_) => missed.push(target),
                }
            }
        }
        if refactorised && opts.detect_bifurcations {
            bordered.factorise_at(problem, &xn, ln, &txn, tln, &scaling, &mut counts)?;
        }
        if opts.detect_bifurcations {
            history.push(State { x: xn.clone(), lambda: ln, tx: txn.clone(), tl: tln });
            if history.len() > 3 {
                history.remove(0);
            }
            if let Some(b) =
                detect(problem, &mut bordered, &scaling, &eq, opts, &records, &history, &bifurcations, &mut counts)?
            {
                bifurcations.push(b);
            }
        }
        (x, lambda, tx, tl) = (xn, ln, txn, tln);
        // Aim at three corrector iterations.
        let factor = (3.0 / iterations.max(1) as f64).sqrt().clamp(0.5, 2.0);
        ds = (ds * factor).clamp(opts.min_step, opts.max_step);
        if let Some(stop) = stop {
            return Ok(finish(stop, x, lambda, tx, tl, ds, records, counts, bifurcations).with_samples(samples, missed));
        }
        if !go_on {
            return Ok(finish(Stop::Cancelled, x, lambda, tx, tl, ds, records, counts, bifurcations)
                .with_samples(samples, missed));
        }
    }
    Ok(finish(Stop::MaxSteps, x, lambda, tx, tl, ds, records, counts, bifurcations).with_samples(samples, missed))
}

/// A record at (x, Λ) from the current factorisation (taken at that point
/// with a border close to the tangent t).
#[allow(clippy::too_many_arguments)]
pub(crate) fn make_record<P: Problem + ?Sized>(
    problem: &mut P,
    bordered: &mut Bordered,
    scaling: &Scaling,
    eq: &[f64],
    x: &[f64],
    lambda: f64,
    tx: &[f64],
    tl: f64,
    step: f64,
    newton_iterations: usize,
    opts: &Options,
    observe: &mut impl FnMut(&[f64], f64) -> Vec<f64>,
    counts: &mut Counts,
) -> Record {
    let mut r = vec![0.0; x.len()];
    problem.residual(x, lambda, &mut r);
    counts.residuals += 1;
    let (bordered_det_sign, det_sign) = bordered.determinant_signs(scaling, tx, tl);
    let smallest_singular_value =
        (opts.track_singular || opts.detect_bifurcations).then(|| bordered.signed_smallest_singular_value(counts));
    Record {
        lambda,
        outputs: observe(x, lambda),
        residual: scaled_max_norm(&r, eq),
        step,
        det_sign,
        bordered_det_sign,
        smallest_singular_value,
        negative_pivots: Some(bordered.negative_pivots()),
        newton_iterations,
        series_residual: None,
    }
}

/// A resume or switch point: lengths and finiteness (a hand-built or
/// deserialised Resume is user input).
pub(crate) fn validate_resume(r: &Resume, n: usize) -> Result<()> {
    error::count_in_range("resume point length", r.x.len() as i64, n as i64, n as i64)?;
    error::count_in_range("resume tangent length", r.tangent_x.len() as i64, n as i64, n as i64)?;
    error::finite_result("resume point", &r.x)?;
    error::finite_result("resume tangent", &r.tangent_x)?;
    error::finite("resume lambda", r.lambda)?;
    error::finite("resume tangent_lambda", r.tangent_lambda)?;
    Ok(())
}

/// The step a resume asks for, within the options' bounds (the initial
/// step when it is not a positive finite number).
pub(crate) fn resume_step(step: f64, opts: &Options) -> f64 {
    if step.is_finite() && step > 0.0 {
        step.clamp(opts.min_step, opts.max_step)
    } else {
        opts.initial_step
    }
}

pub(crate) fn validate<P: Problem + ?Sized>(problem: &P, opts: &Options) -> Result<()> {
    error::in_range("bifurcation_tol", opts.bifurcation_tol, 1e-15, 1.0)?;
    error::in_range("residual_tol", opts.residual_tol, 1e-15, 1.0)?;
    error::positive("initial_step", opts.initial_step)?;
    error::positive("min_step", opts.min_step)?;
    error::positive("max_step", opts.max_step)?;
    if !(opts.min_step <= opts.initial_step && opts.initial_step <= opts.max_step) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!(
                "steps must satisfy min_step ({:e}) <= initial_step ({:e}) <= max_step ({:e})",
                opts.min_step, opts.initial_step, opts.max_step
            ),
        ));
    }
    if let Some(t) = opts.target_lambda {
        error::finite("target_lambda", t)?;
    }
    if let Some(s) = &opts.scaling {
        if s.x.len() != problem.dim()
            || !s.x.iter().all(|v| v.is_finite() && *v > 0.0)
            || !(s.lambda.is_finite() && s.lambda > 0.0)
        {
            return Err(Error::new(
                Status::ErrOutOfRange,
                "scaling: one positive finite scale per unknown and for the parameter",
            ));
        }
    }
    Ok(())
}

/// After a new record: a det B sign change over the last step, or a local
/// minimum of σ_min at the previous record, is located (once).
#[allow(clippy::too_many_arguments)]
pub(crate) fn detect<P: Problem + ?Sized>(
    problem: &mut P,
    bordered: &mut Bordered,
    scaling: &Scaling,
    eq: &[f64],
    opts: &Options,
    records: &[Record],
    history: &[State],
    found: &[Bifurcation],
    counts: &mut Counts,
) -> Result<Option<Bifurcation>> {
    let k = records.len();
    if k < 2 || history.len() < 2 {
        return Ok(None);
    }
    let (r1, r2) = (&records[k - 2], &records[k - 1]);
    let h = history.len();
    let signed = |r: &Record| r.smallest_singular_value.unwrap_or(1.0);
    // A record with sign 0 is a singular start (a switch): no bracket.
    let bracket =
        if r1.bordered_det_sign != r2.bordered_det_sign && r1.bordered_det_sign != 0.0 && r2.bordered_det_sign != 0.0 {
            Some((&history[h - 2], &history[h - 1], true))
        } else if signed(r1) * signed(r2) < 0.0 {
            Some((&history[h - 2], &history[h - 1], false))
        } else if k >= 3 && h >= 3 {
            let sig = |r: &Record| r.smallest_singular_value.map_or(f64::INFINITY, f64::abs);
            let r0 = &records[k - 3];
            // A dip worth a location: 5 % below both neighbours (a flat σ_min,
            // e.g. a mode far from singular, dips by rounding at every other
            // point, and each false location costs a golden-section search).
            (sig(r1) < 0.95 * sig(r0).min(sig(r2))).then(|| (&history[h - 3], &history[h - 1], false))
        } else {
            None
        };
    let Some((left, right, flip)) = bracket else { return Ok(None) };
    // Already located inside this bracket (a flip seen again as a dip).
    let (lo, hi) = (left.lambda.min(right.lambda), left.lambda.max(right.lambda));
    if found.iter().any(|b| b.lambda >= lo && b.lambda <= hi) {
        return Ok(None);
    }
    // A location that fails (a trial point that does not converge) loses
    // this bifurcation, not the branch.
    Ok(bifurcation::locate(
        problem,
        bordered,
        scaling,
        eq,
        opts.residual_tol,
        left,
        right,
        flip,
        opts.bifurcation_tol,
        counts,
    )
    .unwrap_or(None))
}

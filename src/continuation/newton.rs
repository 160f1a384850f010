//! Newton pseudo-arc-length continuation (Keller): Euler predictor along the
//! unit tangent, Newton corrector on [R = 0, ⟨X − X_pred, t⟩_W = 0] with a
//! factorisation per iteration, step length adapted to the iteration count.
//! The baseline the ANM is measured against, and the engine the charged rod
//! uses. What both engines share is [`super::run`]; the corrections are
//! [`super::corrector`].

use super::bifurcation::State;
use super::corrector::{correct, Plane, Reuse};
use super::overlap::Overlap;
use super::run::{resume_step, validate_resume, Factors, Run};
use super::{Branch, Options, Problem, Record, Resume, Sample, Stop, CHORD_AIM};
use crate::error::Result;
use crate::roots::all_roots;

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

/// Cubic Hermite interpolation between two branch points `a` and `b` with
/// their unit tangents over the arc length h: X(θ), θ ∈ [0, 1], its x part
/// into `out` (empty: Λ alone), Λ returned.
fn hermite(a: &State, b: &State, h: f64, theta: f64, out: &mut [f64]) -> f64 {
    let (t2, t3) = (theta * theta, theta * theta * theta);
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + theta;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    for (i, o) in out.iter_mut().enumerate() {
        *o = h00 * a.x[i] + h10 * h * a.tx[i] + h01 * b.x[i] + h11 * h * b.tx[i];
    }
    h00 * a.lambda + h10 * h * a.tl + h01 * b.lambda + h11 * h * b.tl
}

/// Newton pseudo-arc-length continuation. `observe(x, Λ)` chooses each
/// record's outputs; `progress(record)` returning false stops the run
/// (Stop::Cancelled).
pub fn continue_newton<P: Problem + ?Sized>(
    problem: &mut P,
    start: Start,
    opts: &Options,
    observe: impl FnMut(&[f64], f64) -> Vec<f64>,
    progress: impl FnMut(&Record) -> bool,
) -> Result<Branch> {
    continue_newton_hinted(problem, start, opts, observe, progress, |_| false)
}

/// As [`continue_newton`], with `will_stop(record)`: asked of each new
/// point's record before its determinant signs are in (0, 0, no pivots)
/// whether `progress` will stop the run there. With
/// [`Options::overlap_records`] a record is otherwise told after the next
/// step is corrected, and a stop it asks for drops that step: a caller
/// that stops often (a charged rod's stale pair list, every few steps)
/// says so here and the record is told at once. Only a hint: the run
/// stops where `progress` says either way.
pub fn continue_newton_hinted<P: Problem + ?Sized>(
    problem: &mut P,
    start: Start,
    opts: &Options,
    mut observe: impl FnMut(&[f64], f64) -> Vec<f64>,
    mut progress: impl FnMut(&Record) -> bool,
    mut will_stop: impl FnMut(&Record) -> bool,
) -> Result<Branch> {
    let mut run = Run::new(problem, opts)?;
    let (mut at, mut ds, first_iterations, singular, mut previous) = begin(&mut run, problem, start)?;
    // Records whose signs are taken on a second thread are told one step
    // late: the step after them is corrected meanwhile. The first too: B's
    // own LU then never factorises (a new pattern's first factorisation
    // chooses its column order, the cost of several).
    let mut overlap = run.overlapping().then(Overlap::default);
    let (residual, go_on) =
        first_record(&mut run, problem, &at, (first_iterations, singular), &mut overlap, &mut observe, &mut progress)?;
    if opts.detect_bifurcations {
        run.watch(problem, at.clone())?;
    }
    for &target in opts.samples.iter().filter(|&&t| t == at.lambda) {
        let outputs = observe(&at.x, at.lambda);
        run.samples.push(Sample { lambda: target, record: 0, outputs, residual, newton_iterations: 0 });
    }
    if !go_on {
        return Ok(run.finish(Stop::Cancelled, at, ds, previous));
    }
    if opts.target_lambda == Some(at.lambda) {
        // As on one thread: a stop asked at the start wins over the target.
        let stop = if tell_waiting(&mut overlap, &mut run, &mut progress) { Stop::Target } else { Stop::Cancelled };
        return Ok(run.finish(stop, at, ds, previous));
    }
    for _ in 0..opts.max_steps {
        let before = previous.as_ref().filter(|_| opts.hermite_predictor);
        let ds_told = ds;
        let corrected = predict_correct(&mut run, problem, &at, before, &mut ds);
        // The last point's record, told now: a stop it asks for drops this
        // step's point (the run ends where it would have on one thread).
        if !tell_waiting(&mut overlap, &mut run, &mut progress) {
            return Ok(run.finish(Stop::Cancelled, at, ds_told, previous));
        }
        let Some((mut xn, mut ln, iterations)) = corrected else {
            return Ok(run.finish(Stop::StepTooSmall, at, ds, previous));
        };
        run.ctx.counts.steps += 1;
        // Target Λ crossed: interpolate and correct at fixed Λ.
        let mut stop = None;
        if let Some(target) = opts.target_lambda {
            if (ln - target) * (at.lambda - target) <= 0.0 && ln != at.lambda {
                let Some(xt) = at_target(&mut run, problem, &at, &xn, ln, target) else {
                    return Ok(run.finish(Stop::StepTooSmall, at, ds, previous));
                };
                (xn, ln) = (xt, target);
                stop = Some(Stop::Target);
            }
        }
        if stop.is_none() && !(ln >= opts.lambda_range.0 && ln <= opts.lambda_range.1) {
            return Ok(run.finish(Stop::LambdaRange, at, ds, previous));
        }
        // The tangent at the new point (one factorisation; its determinant
        // signs go into the record). An exactly singular matrix there ends
        // the branch with its records.
        let tangent = run.factorise_point(problem, &xn, ln, (&at.tx, at.tl)).and_then(|_| run.ctx.tangent());
        let Ok((txn, tln)) = tangent else {
            return Ok(run.finish(Stop::StepTooSmall, at, ds, previous));
        };
        let next = State { x: xn, lambda: ln, tx: txn, tl: tln };
        let dx: Vec<f64> = at.x.iter().zip(&next.x).map(|(a, b)| b - a).collect();
        let step = run.ctx.scaling.norm(&dx, ln - at.lambda);
        let go_on = match overlap.as_mut() {
            Some(o) => {
                let now = will_stop(record_later(&mut run, o, problem, &next, (step, iterations), &mut observe)?);
                !now || tell_waiting(&mut overlap, &mut run, &mut progress)
            }
            None => {
                let rec = run.record(problem, &next, step, iterations, &mut observe);
                run.push(rec, &mut progress)
            }
        };
        let refactorised = !opts.samples.is_empty() && samples(&mut run, problem, &at, &next, step, &mut observe);
        if opts.detect_bifurcations {
            if refactorised {
                run.ctx.factorise(problem, &next.x, ln, (&next.tx, tln), Factors::Exact)?;
            }
            run.watch(problem, next.clone())?;
            if opts.stop_at_bifurcation && !run.bifurcations.is_empty() {
                return Ok(run.finish(Stop::Bifurcation, next, ds, Some((at, step))));
            }
        }
        previous = Some((std::mem::replace(&mut at, next), step));
        // Aim at `corrector_aim` corrector iterations (Newton), CHORD_AIM (chord).
        let aim = if opts.chord { CHORD_AIM } else { opts.corrector_aim };
        let factor = (aim / iterations.max(1) as f64).sqrt().clamp(0.5, 2.0);
        ds = (ds * factor).clamp(opts.min_step, opts.newton_max_step());
        if let Some(stop) = stop {
            tell_waiting(&mut overlap, &mut run, &mut progress);
            return Ok(run.finish(stop, at, ds, previous));
        }
        if !go_on {
            return Ok(run.finish(Stop::Cancelled, at, ds, previous));
        }
    }
    let stop = if tell_waiting(&mut overlap, &mut run, &mut progress) { Stop::MaxSteps } else { Stop::Cancelled };
    Ok(run.finish(stop, at, ds, previous))
}

/// The start's record: told now (a singular start's, or on one thread),
/// or its signs taken on the second thread and told after the first step.
/// Returns its residual and whether the run goes on.
fn first_record<P: Problem + ?Sized>(
    run: &mut Run,
    problem: &mut P,
    at: &State,
    (iterations, singular): (usize, bool),
    overlap: &mut Option<Overlap>,
    observe: &mut impl FnMut(&[f64], f64) -> Vec<f64>,
    progress: &mut impl FnMut(&Record) -> bool,
) -> Result<(f64, bool)> {
    if let Some(o) = overlap.as_mut().filter(|_| !singular) {
        return Ok((record_later(run, o, problem, at, (0.0, iterations), observe)?.residual, true));
    }
    let first = if singular {
        run.singular_record(problem, &at.x, at.lambda, observe)
    } else {
        run.record(problem, at, 0.0, iterations, observe)
    };
    Ok((first.residual, run.push(first, progress)))
}

/// The record of `at` (`reached` by a step of that arc length and that
/// many corrections) without its signs, which `overlap` takes on
/// the second thread from the factorisation just made at `at`: the
/// record as it waits (signs 0, no pivots).
fn record_later<'o, P: Problem + ?Sized>(
    run: &mut Run,
    overlap: &'o mut Overlap,
    problem: &mut P,
    at: &State,
    reached: (f64, usize),
    observe: &mut impl FnMut(&[f64], f64) -> Vec<f64>,
) -> Result<&'o Record> {
    let rec = run.unsigned_record(problem, at, reached, observe);
    let orientation = run.ctx.bordered.orientation(&run.ctx.scaling, &at.tx, at.tl);
    overlap.start(&mut run.ctx.bordered, rec, orientation, run.opts.overlap_thread)
}

/// Tell the record waiting for its signs, if any ([`Overlap`]): false
/// when the callback asks to stop.
fn tell_waiting(overlap: &mut Option<Overlap>, run: &mut Run, progress: &mut impl FnMut(&Record) -> bool) -> bool {
    let Some(o) = overlap.as_mut() else { return true };
    match o.finish(&mut run.ctx.counts) {
        Some(rec) => {
            // The order B's factors take, as B's own LU would report it
            // (the branch carries it to a resume or the next pair list).
            if let Some(order) = o.column_order() {
                run.ctx.bordered.records_take(order);
            }
            run.push(rec, progress)
        }
        None => true,
    }
}

/// The point before a start and the arc length between them (the Hermite
/// predictor's history).
type Previous = Option<(State, f64)>;

/// The first point, its tangent and step, the Newton iterations that
/// corrected it, whether it is singular (a switch, or a resume at a
/// bifurcation point: there the given tangent is kept), and the point
/// before it (a resume's).
fn begin<P: Problem + ?Sized>(
    run: &mut Run,
    problem: &mut P,
    start: Start,
) -> Result<(State, f64, usize, bool, Previous)> {
    let opts = run.opts;
    match start {
        Start::Point { x, lambda, increasing } => {
            let (x, l, it) = run.corrected_start(problem, x, lambda)?;
            let e_lambda = vec![0.0; x.len()];
            run.factorise_point(problem, &x, l, (&e_lambda, if increasing { 1.0 } else { -1.0 }))?;
            let (tx, tl) = run.ctx.tangent()?;
            Ok((State { x, lambda: l, tx, tl }, opts.initial_step, it, false, None))
        }
        Start::Resume(r) => {
            run.carry(&r);
            let regular = run.factorise_resume(problem, &r)?;
            let step = resume_step(r.step, opts, opts.newton_max_step());
            let (tx, tl) = if regular { run.ctx.tangent()? } else { (r.tangent_x, r.tangent_lambda) };
            let previous = r
                .previous
                .filter(|p| p.x.len() == r.x.len())
                .map(|p| (State { x: p.x, lambda: p.lambda, tx: p.tangent_x, tl: p.tangent_lambda }, p.step));
            Ok((State { x: r.x, lambda: r.lambda, tx, tl }, step, 0, !regular, previous))
        }
        Start::Switch(r) => {
            validate_resume(&r, problem.dim())?;
            let step = resume_step(r.step, opts, opts.newton_max_step());
            Ok((State { x: r.x, lambda: r.lambda, tx: r.tangent_x, tl: r.tangent_lambda }, step, 0, true, None))
        }
    }
}

/// Predictor along the tangent and corrector, halving `ds` on failure:
/// the new point and its corrector iterations, None below the minimum step.
fn predict_correct<P: Problem + ?Sized>(
    run: &mut Run,
    problem: &mut P,
    at: &State,
    previous: Option<&(State, f64)>,
    ds: &mut f64,
) -> Option<(Vec<f64>, f64, usize)> {
    let mut xn = vec![0.0; at.x.len()];
    // A Hermite prediction that failed (or left the course) is retried
    // along the tangent (Euler) before the step is halved.
    let mut euler = false;
    loop {
        let hermite_here = previous.filter(|(_, h)| *h > 0.0 && *ds <= 2.0 * h && !euler);
        let mut ln = match hermite_here {
            // Extrapolated to arc length ds past `at` (θ = 1 + ds/h), the
            // steps not yet long enough for θ > 3 (the cubic's wild side).
            Some((before, h)) => hermite(before, at, *h, 1.0 + *ds / h, &mut xn),
            _ => {
                for ((o, a), t) in xn.iter_mut().zip(&at.x).zip(&at.tx) {
                    *o = a + *ds * t;
                }
                at.lambda + *ds * at.tl
            }
        };
        let (anchor, predicted) = (xn.clone(), ln);
        let plane = Plane::new((&anchor, ln), (&at.tx, at.tl));
        let extrapolated = hermite_here.is_some();
        let result = correct(
            problem,
            &mut run.ctx,
            &mut xn,
            &mut ln,
            plane,
            run.opts.residual_tol,
            Reuse::chord_if(run.opts.chord),
        )
        .and_then(|(it, r)| {
            if extrapolated {
                stays_on_course(run, at, (&anchor, predicted), (&xn, ln), *ds)?;
            }
            Ok((it, r))
        });
        match result {
            Ok((it, _)) => return Some((xn, ln, it)),
            Err(e) => {
                run.ctx.counts.rejected_steps += 1;
                if std::env::var_os("RODKIT_TRACE_REJECTIONS").is_some() {
                    // Part of a run's profile: why steps fail (stderr, opt-in).
                    eprintln!("rodkit: step {ds:.4e} from Λ = {:.6} rejected: {}", at.lambda, e.message);
                }
                if extrapolated {
                    euler = true;
                    continue;
                }
                *ds *= 0.5;
                if *ds < run.opts.min_step {
                    return None;
                }
            }
        }
    }
}

/// A point corrected from a Hermite prediction must lie ahead of `at`
/// along its tangent and within half a step of the prediction: near a
/// sharp fold, where the branch's two legs pass close, a cubic
/// extrapolation can land nearer the other leg and the corrector converge
/// there — the branch then runs back over itself (seen on the 300 bp DNA
/// scene at 0.2 M after its hard core switched on: the path returned to
/// the buckling point). Such a step is retried from the Euler prediction
/// (which is not checked: the engine before the Hermite predictor), as a
/// corrector failure of a Hermite prediction is — next to a bifurcation
/// on the branch, where the tangents are ill-conditioned, the check alone
/// halved the 1 kbp scene's steps to 1e-8 at 2.553 turns.
fn stays_on_course(run: &Run, at: &State, prediction: (&[f64], f64), (x, l): (&[f64], f64), ds: f64) -> Result<()> {
    let scaling = &run.ctx.scaling;
    let ahead: Vec<f64> = x.iter().zip(&at.x).map(|(a, b)| a - b).collect();
    let forward = scaling.dot(&ahead, l - at.lambda, &at.tx, at.tl);
    let d: Vec<f64> = x.iter().zip(prediction.0).map(|(a, b)| a - b).collect();
    let moved = scaling.norm(&d, l - prediction.1);
    if forward > 0.0 && moved <= 0.5 * ds {
        return Ok(());
    }
    Err(crate::error::Error::new(
        crate::status::Status::ErrNotConverged,
        format!(
            "continuation: the corrected point left the branch's course (ahead {forward:.2e}, {moved:.2e} from the \
             prediction, step {ds:.2e})"
        ),
    ))
}

/// The point at Λ = `target` between `at` and (xn, ln): linear
/// interpolation corrected at fixed Λ (None when it does not converge).
fn at_target<P: Problem + ?Sized>(
    run: &mut Run,
    problem: &mut P,
    at: &State,
    xn: &[f64],
    ln: f64,
    target: f64,
) -> Option<Vec<f64>> {
    let s = (target - at.lambda) / (ln - at.lambda);
    let mut xt: Vec<f64> = at.x.iter().zip(xn).map(|(a, b)| a + s * (b - a)).collect();
    let mut lt = target;
    let anchor = xt.clone();
    let plane = Plane::fixed(&anchor, target);
    correct(problem, &mut run.ctx, &mut xt, &mut lt, plane, run.opts.residual_tol, Reuse::No).ok()?;
    Some(xt)
}

/// Dense output: requested loads crossed by the step from `at` to `next`
/// (arc length `step`), predicted by the cubic Hermite interpolant and
/// corrected on the new point's factorisation (as the ANM does on its
/// series). Returns whether a correction refactorised.
fn samples<P: Problem + ?Sized>(
    run: &mut Run,
    problem: &mut P,
    at: &State,
    next: &State,
    step: f64,
    observe: &mut impl FnMut(&[f64], f64) -> Vec<f64>,
) -> bool {
    let mut refactorised = false;
    let (l0, l1) = (at.lambda, next.lambda);
    let record = run.records.len() - 2;
    let opts = run.opts;
    for &target in &opts.samples {
        if (target - l0) * (target - l1) > 0.0 || target == l0 {
            continue;
        }
        let lambda_at = |t: f64| hermite(at, next, step, t, &mut []);
        for theta in all_roots(|t| lambda_at(t) - target, 1.0) {
            let mut xs = vec![0.0; at.x.len()];
            hermite(at, next, step, theta, &mut xs);
            refactorised |= run.sample(problem, xs, (target, (&next.tx, next.tl)), record, observe, false).0;
        }
    }
    refactorised
}

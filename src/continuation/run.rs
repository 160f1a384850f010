//! What both continuation engines share: the correction context (scales,
//! bordered tangent, work counts: [`Context`]) and a run's bookkeeping
//! ([`Run`]: options checked once, the start-up, records with their
//! determinant signs and σ_min, bifurcation detection, dense-output samples,
//! the finished [`Branch`]).

use super::bifurcation::{self, Bifurcation, Evidence, SeriesHint, State, Unresolved};
use super::corrector::{correct, deliver_sample, newton_sample, Plane, Reuse};
use super::stability::{count_unstable, ModeCarry, ModeWork};
use super::tangent::Bordered;
pub(crate) use super::tangent::Factors;
use super::{Branch, Counts, Options, Problem, Record, Resume, Sample, Scaling};
use crate::error::{self, Error, Result};
use crate::linalg::dense::sub;
use crate::nonlinear::scaled_max_norm;
use crate::status::Status;

/// The scales, the bordered tangent and the work counts every correction
/// of a run uses.
pub(crate) struct Context {
    pub scaling: Scaling,
    /// The problem's equation scales.
    pub eq: Vec<f64>,
    pub bordered: Bordered,
    pub counts: Counts,
    /// Newton corrections fail only after two slow steps on fresh
    /// factorisations in a row, not one (runs with the Hermite predictor:
    /// on the 1 kbp DNA scene's buckled branch 150 steps went 2.5× as far
    /// along the path, with 42 rejected attempts instead of 93).
    pub patient: bool,
}

impl Context {
    /// For `problem` with `scaling` (the singular-value monitor scaled by
    /// both).
    pub fn new<P: Problem + ?Sized>(problem: &P, scaling: Scaling) -> Result<Self> {
        let eq = problem.equation_scales();
        let mut bordered =
            Bordered::with_private_blocks(problem.pattern(), problem.trailing(), &problem.private_blocks())?;
        bordered.set_monitor_scales(&eq, &scaling);
        Ok(Context { scaling, eq, bordered, counts: Counts::default(), patient: false })
    }

    /// As [`Context::new`], its LU taking the options' column order and
    /// kind ([`Options::column_order`], [`Options::lu_kind`]).
    pub fn with_options<P: Problem + ?Sized>(problem: &P, scaling: Scaling, opts: &Options) -> Result<Self> {
        let mut ctx = Context::new(problem, scaling)?;
        if let Some(order) = opts.column_order {
            ctx.bordered.prefer(order);
        }
        if let Some(kind) = opts.lu_kind {
            ctx.bordered.prefer_kind(kind);
        }
        ctx.bordered.set_lean_monitor(opts.lean_monitor);
        Ok(ctx)
    }

    /// Evaluate the Jacobian at (x, Λ), border it with v and factorise it
    /// as `factors` asks.
    pub fn factorise<P: Problem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        lambda: f64,
        v: (&[f64], f64),
        factors: Factors,
    ) -> Result<()> {
        self.bordered.factorise_at(problem, x, lambda, v, &self.scaling, &mut self.counts, factors)
    }

    /// The unit tangent from the current factorisation.
    pub fn tangent(&mut self) -> Result<(Vec<f64>, f64)> {
        self.bordered.tangent(&self.scaling, &mut self.counts)
    }

    /// max |R_i| / e_i at (x, Λ) (one residual).
    pub fn residual_norm<P: Problem + ?Sized>(&mut self, problem: &mut P, x: &[f64], lambda: f64) -> f64 {
        let mut r = vec![0.0; x.len()];
        let t = std::time::Instant::now();
        problem.residual(x, lambda, &mut r);
        self.counts.times.residuals += t.elapsed();
        self.counts.residuals += 1;
        scaled_max_norm(&r, &self.eq)
    }
}

/// A resume or switch point: lengths and finiteness (a hand-built or
/// deserialised Resume is user input).
pub(crate) fn validate_resume(r: &Resume, n: usize) -> Result<()> {
    error::dimension("resume point length", r.x.len() as i64, n as i64, n as i64)?;
    error::dimension("resume tangent length", r.tangent_x.len() as i64, n as i64, n as i64)?;
    error::finite_result("resume point", &r.x)?;
    error::finite_result("resume tangent", &r.tangent_x)?;
    error::finite("resume lambda", r.lambda)?;
    error::finite("resume tangent_lambda", r.tangent_lambda)?;
    Ok(())
}

/// The step a resume asks for, within the options' bounds (`max`: the
/// engine's largest step; the initial step when it is not a positive
/// finite number).
pub(crate) fn resume_step(step: f64, opts: &Options, max: f64) -> f64 {
    if step.is_finite() && step > 0.0 {
        step.clamp(opts.min_step, max)
    } else {
        opts.initial_step
    }
}

/// The options against the problem: tolerances, steps, target, scaling.
pub(crate) fn validate<P: Problem + ?Sized>(problem: &P, opts: &Options) -> Result<()> {
    error::in_range("bifurcation_tol", opts.bifurcation_tol, 1e-15, 1.0)?;
    error::in_range("residual_tol", opts.residual_tol, 1e-15, 1.0)?;
    error::positive("initial_step", opts.initial_step)?;
    error::positive("min_step", opts.min_step)?;
    // max_step may be ∞ (the engine's own bound), not NaN or ≤ 0.
    if !(opts.max_step > 0.0) {
        return Err(Error::new(
            Status::ErrNotPositive,
            format!("argument `max_step` must be positive (got {:e})", opts.max_step),
        ));
    }
    // The corrector takes at most 12 iterations (20 chord).
    error::in_range("corrector_aim", opts.corrector_aim, 1.0, 12.0)?;
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

/// A run of either engine: its options, correction context and what it
/// has produced so far.
pub(crate) struct Run<'o> {
    pub opts: &'o Options,
    pub ctx: Context,
    pub records: Vec<Record>,
    pub bifurcations: Vec<Bifurcation>,
    /// Brackets whose location found nothing although a monitored function
    /// changed sign (or failed): reported, not dropped.
    pub unresolved: Vec<Unresolved>,
    /// The last (up to) three points with their tangents and record
    /// indices: detection's brackets.
    history: Vec<(usize, State)>,
    /// The series indicator's roots in the last ANM step ([`SeriesHint`]).
    pub series_hint: Option<SeriesHint>,
    pub samples: Vec<Sample>,
    pub missed: Vec<f64>,
    /// Samples whose chord on their step's factorisation stalled, waiting
    /// for the next point's ([`Run::sample`] with `defer`).
    pending: Vec<Pending>,
    /// The stability count's state along the branch and its scratch
    /// ([`Options::stability`]).
    modes: ModeCarry,
    mode_work: ModeWork,
}

/// Where a sample went: its index in the branch's samples, its missed
/// loads or the pending samples ([`Run::withdraw`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placed {
    Sample(usize),
    Missed(usize),
    Pending(usize),
}

/// A sample deferred by [`Run::sample`]: its load, its prediction on the
/// step's curve, the record of the step's start and the chord iterations
/// spent on it.
struct Pending {
    target: f64,
    prediction: Vec<f64>,
    record: usize,
    spent: usize,
}

impl<'o> Run<'o> {
    /// Options checked, the scaling (the options' or the problem's), the
    /// bordered tangent.
    pub fn new<P: Problem + ?Sized>(problem: &P, opts: &'o Options) -> Result<Self> {
        validate(problem, opts)?;
        let scaling = opts.scaling.clone().unwrap_or_else(|| Scaling::of(problem));
        let t = std::time::Instant::now();
        let mut ctx = Context::with_options(problem, scaling, opts)?;
        ctx.patient = opts.hermite_predictor;
        ctx.counts.times.setup += t.elapsed();
        Ok(Run {
            opts,
            ctx,
            records: Vec::new(),
            bifurcations: Vec::new(),
            unresolved: Vec::new(),
            history: Vec::new(),
            series_hint: None,
            samples: Vec::new(),
            missed: Vec::new(),
            pending: Vec::new(),
            modes: ModeCarry::default(),
            mode_work: ModeWork::new(),
        })
    }

    /// A resumed branch's stability count goes on from where it stopped
    /// (its warm start, reference sign and deepest σ).
    pub fn carry(&mut self, r: &Resume) {
        if let Some(m) = &r.modes {
            self.modes = (**m).clone();
        }
    }

    /// A start point corrected at its fixed Λ: (x, Λ, Newton iterations).
    pub fn corrected_start<P: Problem + ?Sized>(
        &mut self,
        problem: &mut P,
        mut x: Vec<f64>,
        lambda: f64,
    ) -> Result<(Vec<f64>, f64, usize)> {
        let n = problem.dim();
        error::dimension("start point length", x.len() as i64, n as i64, n as i64)?;
        let mut l = lambda;
        let anchor = x.clone();
        let (it, _) = correct(
            problem,
            &mut self.ctx,
            &mut x,
            &mut l,
            Plane::fixed(&anchor, lambda),
            self.opts.residual_tol,
            Reuse::No,
        )
        .map_err(|e| Error::new(e.status, format!("continuation start: {}", e.message)))?;
        Ok((x, l, it))
    }

    /// A resume point checked and factorised with its tangent as border:
    /// Ok(false) when the matrix is exactly singular (a resume at a
    /// bifurcation point, to be left as a switch is).
    pub fn factorise_resume<P: Problem + ?Sized>(&mut self, problem: &mut P, r: &Resume) -> Result<bool> {
        validate_resume(r, problem.dim())?;
        // Bordered by the previous point's tangent when there is one: the
        // factorisation the uninterrupted run had here.
        let border = r.previous.as_deref().filter(|p| p.tangent_x.len() == r.x.len()).unwrap_or(r);
        match self.factorise_point(problem, &r.x, r.lambda, (&border.tangent_x, border.tangent_lambda)) {
            Ok(()) => Ok(true),
            Err(e) if e.status == Status::ErrNotConverged => Ok(false),
            Err(e) => Err(e),
        }
    }

    /// A record at `at` from the current factorisation (taken at that point
    /// with a border close to its tangent), reached by a step of arc length
    /// `step` and `newton_iterations` corrections.
    pub fn record<P: Problem + ?Sized>(
        &mut self,
        problem: &mut P,
        at: &State,
        step: f64,
        newton_iterations: usize,
        observe: &mut impl FnMut(&[f64], f64) -> Vec<f64>,
    ) -> Record {
        let mut rec = self.unsigned_record(problem, at, (step, newton_iterations), observe);
        if self.count_modes(problem, at, &mut rec) {
            return rec;
        }
        let ctx = &mut self.ctx;
        (rec.bordered_det_sign, rec.det_sign) = ctx.bordered.determinant_signs(&ctx.scaling, &at.tx, at.tl);
        rec.negative_pivots = Some(ctx.bordered.negative_pivots());
        rec
    }

    /// With [`Options::stability`] and a problem that gives its metric:
    /// the record's count of unstable modes, on the factorisation in hand
    /// (any of R_x at the point), and its determinant signs derived from
    /// it: sign det R_x = s_ref·(−1)^count with the branch's reference
    /// sign s_ref, sign det B = that × the orientation of the tangent. The
    /// reference is taken once, from an exact (simplicial) factorisation
    /// at the branch's first counted point; a point whose count is not
    /// certified takes its signs that way too (and its count stays None).
    /// Returns whether the record's signs are in.
    fn count_modes<P: Problem + ?Sized>(&mut self, problem: &mut P, at: &State, rec: &mut Record) -> bool {
        let Some(options) = self.opts.stability else { return false };
        let Some(metric) = problem.stability_metric(&at.x) else { return false };
        let t = std::time::Instant::now();
        // The floor: the state's own scale, or twice the deepest σ counted
        // at the last point when that is lower.
        let floor = -(options.floor * metric.scale).max(-2.0 * self.modes.deepest);
        let ctx = &mut self.ctx;
        let s = count_unstable(
            |f, k| ctx.bordered.solve_inner_many(f, k, &mut ctx.counts),
            &metric,
            floor,
            &mut self.modes.basis,
            &mut self.mode_work,
            &options,
        );
        ctx.counts.stability_solves += s.solves;
        let orientation = ctx.bordered.orientation(&ctx.scaling, &at.tx, at.tl);
        let parity = |c: usize| if c.is_multiple_of(2) { 1.0 } else { -1.0 };
        match (s.negative, self.modes.reference_sign) {
            (Some(c), Some(reference)) if orientation != 0.0 => {
                rec.det_sign = reference * parity(c);
                rec.bordered_det_sign = rec.det_sign * orientation;
            }
            _ => {
                // Exact signs: B's own LU at the point (with its tangent
                // as border) unless the factors in hand are that already.
                let exact = ctx.bordered.signs_in_hand()
                    || ctx.factorise(problem, &at.x, at.lambda, (&at.tx, at.tl), Factors::Exact).is_ok();
                if exact {
                    (rec.bordered_det_sign, rec.det_sign) = ctx.bordered.determinant_signs(&ctx.scaling, &at.tx, at.tl);
                    if let Some(c) = s.negative.filter(|_| rec.det_sign != 0.0) {
                        self.modes.reference_sign = Some(rec.det_sign * parity(c));
                    }
                }
            }
        }
        if s.negative.is_some() {
            self.modes.deepest = s.sigma.iter().copied().filter(|v| *v >= s.floor).fold(0.0, f64::min);
        }
        ctx.counts.times.stability += t.elapsed();
        rec.stability = Some(s);
        true
    }

    /// As [`Run::record`] without the determinant signs and pivots (0, 0,
    /// None): [`super::overlap::Overlap`] takes them on a second thread.
    /// The σ_min monitor, when on, is taken here. The step's arc length
    /// and the corrections come paired, as the overlap's caller has them.
    pub fn unsigned_record<P: Problem + ?Sized>(
        &mut self,
        problem: &mut P,
        at: &State,
        (step, newton_iterations): (f64, usize),
        observe: &mut impl FnMut(&[f64], f64) -> Vec<f64>,
    ) -> Record {
        let (x, lambda) = (&at.x[..], at.lambda);
        let residual = self.ctx.residual_norm(problem, x, lambda);
        let ctx = &mut self.ctx;
        let smallest_singular_value = (self.opts.track_singular || self.opts.detect_bifurcations)
            .then(|| ctx.bordered.signed_smallest_singular_value(false, &mut ctx.counts));
        Record {
            lambda,
            outputs: observe(x, lambda),
            residual,
            step,
            det_sign: 0.0,
            bordered_det_sign: 0.0,
            smallest_singular_value,
            negative_pivots: None,
            newton_iterations,
            series_residual: None,
            stability: None,
        }
    }

    /// Whether records take their signs on a second thread
    /// ([`super::Options::overlap_records`]; not with the monitor,
    /// bifurcation detection or samples, which read a point's
    /// factorisation before the next step; not on a condensed tangent,
    /// whose factors for solves give the signs themselves).
    pub fn overlapping(&self) -> bool {
        let o = self.opts;
        o.overlap_records
            && o.stability.is_none()
            && !o.track_singular
            && !o.detect_bifurcations
            && o.samples.is_empty()
            && !self.ctx.bordered.condensed()
    }

    /// Factorise at a new point for its tangent and record: for solves
    /// (the pattern's fastest kind) when its record's signs are taken on
    /// a second thread, else simplicial (its signs read here).
    pub fn factorise_point<P: Problem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        lambda: f64,
        v: (&[f64], f64),
    ) -> Result<()> {
        let factors =
            if self.overlapping() || self.opts.stability.is_some() { Factors::ForSolves } else { Factors::Exact };
        self.ctx.factorise(problem, x, lambda, v, factors)
    }

    /// The record of a singular start (a switch): no determinant signs,
    /// σ_min = 0, no pivots.
    pub fn singular_record<P: Problem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        lambda: f64,
        observe: &mut impl FnMut(&[f64], f64) -> Vec<f64>,
    ) -> Record {
        Record {
            lambda,
            outputs: observe(x, lambda),
            residual: self.ctx.residual_norm(problem, x, lambda),
            step: 0.0,
            det_sign: 0.0,
            bordered_det_sign: 0.0,
            smallest_singular_value: Some(0.0),
            negative_pivots: None,
            newton_iterations: 0,
            series_residual: None,
            stability: None,
        }
    }

    /// Keep `rec` and report it: false when the callback asks to stop.
    pub fn push(&mut self, rec: Record, progress: &mut impl FnMut(&Record) -> bool) -> bool {
        let go_on = progress(&rec);
        self.records.push(rec);
        go_on
    }

    /// After a new record at `state`: with bifurcation detection, a det B
    /// sign change over the last step, or a local minimum of σ_min at the
    /// previous record, is located (once). Returns whether the location
    /// refactorised the bordered tangent.
    pub fn watch<P: Problem + ?Sized>(&mut self, problem: &mut P, state: State) -> Result<bool> {
        if !self.opts.detect_bifurcations {
            return Ok(false);
        }
        self.history.push((self.records.len().saturating_sub(1), state));
        if self.history.len() > 3 {
            self.history.remove(0);
        }
        let before = self.ctx.bordered.factorisations();
        let (t, counted) = (std::time::Instant::now(), self.ctx.counts.factorisations);
        self.detect(problem)?;
        let located = self.ctx.bordered.factorisations() != before;
        if located {
            // Only a search factorises: its work is the location's.
            self.ctx.counts.locations += 1;
            self.ctx.counts.location_factorisations += self.ctx.counts.factorisations - counted;
            self.ctx.counts.times.location += t.elapsed();
        }
        Ok(located)
    }

    /// One bracket per new record: the last step when det B or the signed
    /// σ_min changed sign over it, else the last two steps when |σ_min| dips
    /// at the middle record. A bracket already holding a located point (or
    /// an unresolved report) is not searched again: one report per point,
    /// counted by its place among the records (Λ alone can repeat — a
    /// rotation control's Λ = sin(φ/2) returns to every value).
    fn detect<P: Problem + ?Sized>(&mut self, problem: &mut P) -> Result<()> {
        let (records, history) = (&self.records, &self.history);
        let k = records.len();
        let h = history.len();
        if k < 2 || h < 2 {
            return Ok(());
        }
        let (r1, r2) = (&records[k - 2], &records[k - 1]);
        let signed = |r: &Record| r.smallest_singular_value.unwrap_or(1.0);
        // A record with sign 0 is a singular start (a switch): no bracket.
        let det_sign_change =
            r1.bordered_det_sign != r2.bordered_det_sign && r1.bordered_det_sign != 0.0 && r2.bordered_det_sign != 0.0;
        let test_function_change = signed(r1) * signed(r2) < 0.0;
        let evidence = Evidence { det_sign_change, test_function_change };
        // The ANM's series indicator μ(a) vanishing inside the last step is
        // evidence of its own (two simple points in one step flip det B
        // twice; a double point need not turn σ_min's sign).
        let series_root =
            self.series_hint.as_ref().is_some_and(|s| s.record == history[h - 2].0 && !s.roots.is_empty());
        let (left, right) = if det_sign_change || test_function_change || series_root {
            (h - 2, h - 1)
        } else if k >= 3 && h >= 3 {
            let sig = |r: &Record| r.smallest_singular_value.map_or(f64::INFINITY, f64::abs);
            let r0 = &records[k - 3];
            // A dip worth a location: 5 % below both neighbours (a flat σ_min,
            // e.g. a mode far from singular, dips by rounding at every other
            // point, and each false location costs a golden-section search).
            if sig(r1) < 0.95 * sig(r0).min(sig(r2)) {
                (h - 3, h - 1)
            } else {
                return Ok(());
            }
        } else {
            return Ok(());
        };
        let ((a, left), (b, right)) = (history[left].clone(), history[right].clone());
        let middle = (b - a == 2).then(|| history[h - 2].1.clone());
        let reported = self.bifurcations.iter().any(|f| f.record >= a && f.record < b)
            || self.unresolved.iter().any(|u| u.records.0 < b && u.records.1 > a);
        if reported {
            return Ok(());
        }
        let tols = (self.opts.residual_tol, self.opts.bifurcation_tol);
        let scaling = self.ctx.scaling.clone();
        let arc = |x: &[f64], l: f64| scaling.dot(&sub(x, &left.x), l - left.lambda, &left.tx, left.tl);
        // The record a point follows: with a middle record, by its arc
        // parameter against the middle's.
        let place = |p: &Bifurcation| match &middle {
            Some(m) if arc(&p.x, p.lambda) >= arc(&m.x, m.lambda) => a + 1,
            _ => a,
        };
        let unresolved = |reason: String| Unresolved {
            records: (a, b),
            lambdas: (left.lambda, right.lambda),
            det_sign_change,
            test_function_change,
            reason,
        };
        // The last step's series indicator, when it is this bracket's step.
        let hint = self.series_hint.as_ref().filter(|h| h.record == a && b == a + 1);
        // σ_min's sign change without det B's, where μ certainly has no
        // root: its singular vectors turning orthogonal (a twisted rod's
        // mode pair every 2π), not a singular point — no search.
        if !det_sign_change && hint.is_some_and(|h| h.clear) {
            self.ctx.counts.series_dismissed += 1;
            return Ok(());
        }
        let hint = hint.filter(|h| !h.roots.is_empty());
        match bifurcation::locate(problem, &mut self.ctx, &left, &right, evidence, tols, hint) {
            Ok(Some((mut bif, tau))) => {
                bif.record = place(&bif);
                // Parity: each simple point (multiplicity 1) flips det B,
                // so a bracket whose ends' signs disagree with the count
                // located holds another simple point.
                let ends_differ = records[a].bordered_det_sign * records[b].bordered_det_sign < 0.0;
                let other = ends_differ != (bif.multiplicity % 2 == 1);
                let signed_ends = records[a].bordered_det_sign != 0.0 && records[b].bordered_det_sign != 0.0;
                if other && signed_ends {
                    match bifurcation::locate_beside(problem, &mut self.ctx, (&left, &right), tau, records[a].bordered_det_sign, tols) {
                        Ok(Some((mut second, _))) => {
                            second.record = place(&second);
                            // In branch order.
                            let (first, later) = if arc(&second.x, second.lambda) < arc(&bif.x, bif.lambda) {
                                (second, bif)
                            } else {
                                (bif, second)
                            };
                            self.bifurcations.push(first);
                            self.bifurcations.push(later);
                            return Ok(());
                        }
                        Ok(None) => self.unresolved.push(unresolved(
                            "det B's signs at the bracket's ends call for one more simple bifurcation than was located; σ_min has no zero beside the located one".into(),
                        )),
                        Err(e) => self.unresolved.push(unresolved(format!(
                            "det B's signs at the bracket's ends call for one more simple bifurcation than was located; its location failed: {}",
                            e.message
                        ))),
                    }
                }
                self.bifurcations.push(bif);
            }
            Ok(None) if det_sign_change => self.unresolved.push(unresolved(
                "det B changed sign between the records but σ_min has no zero there (the step may have left the branch)"
                    .into(),
            )),
            // The signed σ_min also turns sign where its left and right
            // singular vectors turn orthogonal (a pair of modes rotating
            // into each other, as on a twisted straight rod every 2π) and
            // dips without a zero: no singular point, nothing to report.
            Ok(None) => {}
            Err(e) => self.unresolved.push(unresolved(format!("location failed: {}", e.message))),
        }
        Ok(())
    }

    /// Dense output at `target` from the prediction `xs` (corrected on the
    /// current factorisation, tangent t): a sample in the step that starts
    /// at record `record`, or a missed load. Returns whether the correction
    /// needed fresh factorisations (the step's is gone).
    ///
    /// With `defer`, a sample whose chord stalls is not corrected by fresh
    /// Newton here but kept for [`Run::deliver_pending`] on the next
    /// point's factorisation (the end of the step, nearer a sample late in
    /// it than its start: a chord there saves the factorisation). It
    /// counts as refactorised: the step's factorisation did not reach it,
    /// so it will not reach the end point either. Also returns where the
    /// sample went.
    pub fn sample<P: Problem + ?Sized>(
        &mut self,
        problem: &mut P,
        mut xs: Vec<f64>,
        (target, t): (f64, (&[f64], f64)),
        record: usize,
        observe: &mut impl FnMut(&[f64], f64) -> Vec<f64>,
        defer: bool,
    ) -> (bool, Placed) {
        let mut refactorised = false;
        let tol = self.opts.residual_tol;
        let mut spent = 0;
        let placed = match deliver_sample(
            problem,
            &mut self.ctx,
            &mut xs,
            target,
            t,
            tol,
            &mut refactorised,
            (defer, &mut spent),
        ) {
            Ok(None) => {
                refactorised = true;
                self.defer_sample(Pending { target, prediction: xs, record, spent })
            }
            result => self.settle(result, &xs, target, record, observe),
        };
        (refactorised, placed)
    }

    /// A corrected sample into the branch's samples; a failed one into its
    /// missed loads.
    fn settle(
        &mut self,
        result: Result<Option<(usize, f64)>>,
        xs: &[f64],
        target: f64,
        record: usize,
        observe: &mut impl FnMut(&[f64], f64) -> Vec<f64>,
    ) -> Placed {
        match result {
            Ok(Some((iterations, residual))) => {
                self.samples.push(Sample {
                    lambda: target,
                    record,
                    outputs: observe(xs, target),
                    residual,
                    newton_iterations: iterations,
                });
                Placed::Sample(self.samples.len() - 1)
            }
            _ => {
                self.missed.push(target);
                Placed::Missed(self.missed.len() - 1)
            }
        }
    }

    /// Take back samples a step delivered past the end it reached (a
    /// halved step: the next step delivers them, from its own start). They
    /// are the last of their lists: taken from each list's end first.
    pub fn withdraw(&mut self, placed: &[Placed]) {
        let index = |p: &Placed| match *p {
            Placed::Sample(i) | Placed::Missed(i) | Placed::Pending(i) => i,
        };
        let mut placed = placed.to_vec();
        placed.sort_unstable_by_key(|p| std::cmp::Reverse(index(p)));
        for p in placed {
            match p {
                Placed::Sample(i) => drop(self.samples.remove(i)),
                Placed::Missed(i) => drop(self.missed.remove(i)),
                Placed::Pending(i) => drop(self.pending.remove(i)),
            }
        }
    }

    /// Whether samples wait for the next point ([`Run::sample`]).
    pub fn has_pending(&self) -> bool {
        !self.pending.is_empty()
    }

    /// Defer a sample without trying the current factorisation: one
    /// after a deferred one in the same step, so that the samples keep
    /// their order along the branch.
    pub fn defer(&mut self, xs: Vec<f64>, target: f64, record: usize) -> Placed {
        self.defer_sample(Pending { target, prediction: xs, record, spent: 0 })
    }

    fn defer_sample(&mut self, p: Pending) -> Placed {
        self.ctx.counts.deferred_samples += 1;
        self.pending.push(p);
        Placed::Pending(self.pending.len() - 1)
    }

    /// The deferred samples ([`Run::sample`]), by chord on the current
    /// factorisation (of the point with tangent t), else by fresh Newton
    /// (`fresh`: at once — no usable factorisation in hand). Returns
    /// whether the factorisation was replaced. A sample's Λ is fixed, so
    /// the factorisation it is corrected on changes its iterations, not
    /// the point (to the residual tolerance).
    pub fn deliver_pending<P: Problem + ?Sized>(
        &mut self,
        problem: &mut P,
        t: (&[f64], f64),
        observe: &mut impl FnMut(&[f64], f64) -> Vec<f64>,
        fresh: bool,
    ) -> bool {
        let mut refactorised = false;
        let tol = self.opts.residual_tol;
        for mut p in std::mem::take(&mut self.pending) {
            let xs = &mut p.prediction;
            let result = match fresh {
                true => {
                    refactorised = true;
                    newton_sample(problem, &mut self.ctx, xs, p.target, tol).map(|(it, r)| Some((p.spent + it, r)))
                }
                false => {
                    let spent = (false, &mut p.spent);
                    deliver_sample(problem, &mut self.ctx, xs, p.target, t, tol, &mut refactorised, spent)
                }
            };
            self.settle(result, xs, p.target, p.record, observe);
        }
        refactorised
    }

    /// The branch, stopped for `stop`, resumable from `at` (a point and
    /// its tangent) with step `step`.
    pub fn finish(self, stop: super::Stop, at: State, step: f64, previous: Option<(State, f64)>) -> Branch {
        let previous = previous.map(|(p, h)| {
            Box::new(Resume {
                x: p.x,
                lambda: p.lambda,
                tangent_x: p.tx,
                tangent_lambda: p.tl,
                step: h,
                previous: None,
                modes: None,
            })
        });
        let modes = self.opts.stability.map(|_| std::sync::Arc::new(self.modes));
        Branch {
            records: self.records,
            bifurcations: self.bifurcations,
            unresolved: self.unresolved,
            stop,
            resume: Resume {
                x: at.x,
                lambda: at.lambda,
                tangent_x: at.tx,
                tangent_lambda: at.tl,
                step,
                previous,
                modes,
            },
            counts: self.ctx.counts,
            samples: self.samples,
            // A deferred sample the run stopped before delivering is a
            // missed load, never dropped (every stop delivers them first).
            missed_samples: self.missed.into_iter().chain(self.pending.iter().map(|p| p.target)).collect(),
            column_order: self.ctx.bordered.column_order(),
        }
    }
}

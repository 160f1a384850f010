//! Branches of charged-rod equilibria: Newton pseudo-arc-length
//! continuation of [`ChargedRod`], or the ANM when its charge asks
//! ([`RodCharge::anm`]) — in the end rotation φ itself for a rod with a
//! controlled end rotation (any number of turns), or in the end torque for
//! a torque clamp ([`super::dna::EndControl`]) — with the pair list rebuilt
//! by its [`crate::charged::rod::ListRule`] (a stage moved half the skin,
//! or, opt-in, a far pair missing from it came within half the skin of the
//! potential's range), the branch continued
//! from the same point and tangent on the new pattern, strand
//! crossing detected (non-neighbouring stage points closer than 2a: the
//! branch stops with its [`RodBranch::contact`]), and branch switching at a
//! located (double) buckling point with the rod's phase condition — the
//! plain rod's [`RodBranch`] and [`crate::rod::branch::switch`], with this
//! model plugged in ([`Charged`]). The DNA scene that runs them:
//! [`super::dna`].

use super::rod::{ChargedRod, RodCharge};
use crate::continuation::anm::continue_anm;
use crate::continuation::corrector::{correct, Plane, Reuse};
use crate::continuation::newton::{continue_newton_hinted, Start};
use crate::continuation::run::Context;
use crate::continuation::{Options, Problem, Record, Resume, Scaling, Stop};
use crate::error::{Error, Result};
use crate::geometry::proximity::closest_pair_within;
use crate::geometry::vec3::distance;
use crate::linalg::sparse::ColumnOrder;
use crate::nonlinear::scaled_max_norm;
use crate::rod::branch::{self, Contact, Followed, RodBranch};
use crate::rod::branch::{Phase, Progress};
use crate::rod::model::Rod;
use crate::status::Status;

/// A charged rod's branch: the rod's branch type.
pub type ChargedBranch = RodBranch;

/// The closest non-neighbouring pair of stage points nearer than 2a:
/// (distance, s1, s2).
pub fn strand_crossing(rod: &Rod, charge: &RodCharge, x: &[f64]) -> Option<(f64, f64, f64)> {
    let a = charge.screening.a;
    let (r, s) = rod.stage_points(x);
    closest_pair_within(&r, &s, 2.0 * a, std::f64::consts::PI * a).map(|(d, i, j)| (d, s[i], s[j]))
}

/// Whether no pair of stage points that a hard core would push apart
/// (farther apart along the rod than (π/2)·2.5a) is within its range
/// 2.5a: there the hard core exerts nothing, and a state of the rod
/// without one is also a state with one.
pub fn hard_core_idle(rod: &Rod, charge: &RodCharge, x: &[f64]) -> bool {
    let a = charge.screening.a;
    let (r, s) = rod.stage_points(x);
    let range = super::rod::HARD_CORE_RANGE * a;
    closest_pair_within(&r, &s, range, 0.5 * std::f64::consts::PI * range).is_none()
}

/// The charged rod as a [`Followed`] model.
pub struct Charged<'a> {
    pub rod: &'a Rod,
    pub charge: &'a RodCharge,
    /// The anchor of the last pair list of the last branch followed.
    pub last_anchor: std::cell::RefCell<Option<ListAnchor>>,
}

impl Followed for Charged<'_> {
    type System = ChargedRod;

    fn rod(&self) -> &Rod {
        self.rod
    }

    fn system(&self, phase: Phase, x: &[f64]) -> Result<ChargedRod> {
        ChargedRod::new(self.rod, self.charge, phase, x)
    }

    fn follow(&self, start: Start, phase: Phase, opts: &Options, progress: Progress<'_>) -> Result<RodBranch> {
        let (b, anchor) = follow_on(self.rod, self.charge, start, None, phase, opts, progress, None)?;
        *self.last_anchor.borrow_mut() = Some(anchor);
        Ok(b)
    }
}

fn start_x(start: &Start) -> &[f64] {
    match start {
        Start::Point { x, .. } => x,
        Start::Resume(r) | Start::Switch(r) => &r.x,
    }
}

/// Follow a branch of the charged rod from `start` (with the rod's phase
/// condition when given), rebuilding the pair list as the shape moves:
/// each list's segment is a branch continued from the previous one's
/// resume point, appended to it. `progress` is told every record once, in
/// order (a point that ends a list's segment is told when the next list
/// has re-converged it; a strand crossing is told, then the branch stops).
/// With a phase condition every point is checked for μ = 0 as it comes; one
/// that left it is never told, but taken again from the point before with
/// half the step (`Options::unfolding_retakes` times). An error once the
/// branch has points — those retakes exhausted, a later list's corrector
/// failing — ends it there: the branch so far is returned with the error in
/// [`RodBranch::failure`] (stop Cancelled); the error alone before that.
pub fn follow(
    rod: &Rod,
    charge: &RodCharge,
    start: Start,
    phase: Phase,
    opts: &Options,
    progress: impl FnMut(&Record) -> bool,
) -> Result<RodBranch> {
    Ok(follow_on(rod, charge, start, None, phase, opts, progress, None)?.0)
}

/// Continue `branch` from its record `record` (its later records dropped)
/// with another charge model — a hard core switched on where the strands
/// crossed: the point is re-converged at its Λ on the new model (it
/// replaces the record and is told to `progress` again; the dropped
/// records were told already) and the branch followed on from it, leaving
/// along the secant of the dropped step (the new model's tangent is
/// computed there, oriented by it). `opts.max_steps` counts the branch's
/// steps before too. Returns the branch and its last list's anchor.
pub fn continue_with(
    rod: &Rod,
    charge: &RodCharge,
    mut branch: RodBranch,
    record: usize,
    opts: &Options,
    progress: impl FnMut(&Record) -> bool,
) -> Result<(RodBranch, ListAnchor)> {
    let k = record.min(branch.records.len().saturating_sub(1));
    let (x, lambda) = (branch.states[k].clone(), branch.records[k].lambda);
    let (tangent_x, tangent_lambda) = match branch.states.get(k + 1) {
        Some(next) => (next.iter().zip(&x).map(|(b, a)| b - a).collect(), branch.records[k + 1].lambda - lambda),
        None => (branch.resume.tangent_x.clone(), branch.resume.tangent_lambda),
    };
    let step = branch.records.get(k + 1).map_or(branch.resume.step, |r| r.step);
    branch.truncate(k + 1);
    branch.contact = None;
    let start = Start::Resume(Resume { x, lambda, tangent_x, tangent_lambda, step, previous: None, modes: None });
    let phase = branch.phase;
    follow_on(rod, charge, start, None, phase, opts, progress, Some(branch))
}

/// Where a charged branch's last pair list was built: the state it was
/// built about, and the state its stages' displacements are measured from
/// (the same, or that point re-converged on the list).
#[derive(Clone, Debug, PartialEq)]
pub struct ListAnchor {
    pub built: Vec<f64>,
    pub reference: Vec<f64>,
    /// The column order the list's factorisations took: the next list
    /// keeps it ([`Options::column_order`]) — once a plectoneme's strands
    /// need reverse Cuthill–McKee, trying the natural order again on every
    /// list cost ~1 s a list at 5–12 turns of the 1 kbp scene (a tenth of
    /// a factorisation each after it).
    pub order: Option<ColumnOrder>,
}

/// [`follow`] with the first pair list built and measured from `anchor`
/// (None: the start), appending to `out` when given (its last record is the
/// start, re-converged on this model when it is not within tolerance);
/// returns the branch and its last list's anchor. A branch resumed with
/// the anchor its stopped part returned continues on the same list as the
/// uninterrupted branch (the same pairs in the same order, rebuilt at the
/// same points).
/// An error raised once the branch has points — a corrector that failed on
/// a later list, a point that kept leaving μ = 0 — ends it there instead:
/// the branch so far is returned with the error in its `failure` (a long
/// run keeps its path; the error alone is returned when there is none).
#[allow(clippy::too_many_arguments)]
pub fn follow_on(
    rod: &Rod,
    charge: &RodCharge,
    start: Start,
    anchor: Option<&ListAnchor>,
    phase: Phase,
    opts: &Options,
    mut progress: impl FnMut(&Record) -> bool,
    mut out: Option<RodBranch>,
) -> Result<(RodBranch, ListAnchor)> {
    let x0 = start_x(&start).to_vec();
    let mut anchor =
        anchor.cloned().unwrap_or(ListAnchor { built: x0.clone(), reference: x0, order: opts.column_order });
    let result = follow_lists(rod, charge, start, &mut anchor, phase, opts, &mut progress, &mut out);
    match (result, out) {
        (Ok(()), Some(b)) => Ok((b, anchor)),
        (Err(e), Some(mut b)) if !b.records.is_empty() => {
            b.stop = Stop::Cancelled;
            b.failure = Some(e);
            Ok((b, anchor))
        }
        (Err(e), _) => Err(e),
        (Ok(()), None) => unreachable!("a followed branch has a segment"),
    }
}

/// The loop of [`follow_on`]: segment after segment, each on a pair
/// list built where the last one ended, appended to `out`; `anchor` is the
/// current list's.
#[allow(clippy::too_many_arguments)]
fn follow_lists(
    rod: &Rod,
    charge: &RodCharge,
    mut start: Start,
    anchor: &mut ListAnchor,
    phase: Phase,
    opts: &Options,
    progress: Progress<'_>,
    out: &mut Option<RodBranch>,
) -> Result<()> {
    // Whether the next segment's start is told (a point reached on the
    // last list), or was told already (a step taken again from it).
    let mut tell_start = true;
    // Retakes of the same point that left μ = 0 (reset by a good point).
    let mut retakes = 0;
    loop {
        let built = std::time::Instant::now();
        let mut problem = ChargedRod::new(rod, charge, phase, &anchor.built)?;
        let setup = built.elapsed();
        let steps_done = out.as_ref().map_or(0, |b| b.counts.steps);
        let seg_opts = Options {
            max_steps: opts.max_steps.saturating_sub(steps_done).max(1),
            column_order: anchor.order,
            ..opts.clone()
        };
        if let (Start::Resume(r), Some(b)) = (&mut start, out.as_mut()) {
            match reconverge(&mut problem, &mut r.x, r.lambda, &seg_opts, b) {
                Ok(()) => anchor.reference = r.x.clone(),
                // The point does not re-converge on this list: taken
                // again from the point before, on a list built there.
                Err(e) => {
                    if !retake(b) {
                        return Err(e);
                    }
                    start = Start::Resume(b.resume.clone());
                    *anchor = ListAnchor::at(start_x(&start), anchor.order);
                    tell_start = false;
                    continue;
                }
            }
        }
        let first = match (out.is_some(), tell_start) {
            (false, _) => SegmentStart::Branch,
            (true, true) => SegmentStart::Reached,
            (true, false) => SegmentStart::Told,
        };
        let (segment, end, order) =
            follow_list(&mut problem, start, &anchor.reference, phase, &seg_opts, first, progress)?;
        tell_start = true;
        anchor.order = Some(order);
        // Points of the segment kept (past its start, without one dropped).
        if segment.records.len() > 1 + (end == SegmentEnd::OffBranch) as usize {
            retakes = 0;
        }
        let out = match out.as_mut() {
            Some(b) => {
                b.append(segment);
                b
            }
            None => out.insert(segment),
        };
        out.counts.times.setup += setup;
        if end == SegmentEnd::OffBranch {
            if retakes < opts.unfolding_retakes && retake(out) {
                retakes += 1;
                start = Start::Resume(out.resume.clone());
                *anchor = ListAnchor::at(start_x(&start), anchor.order);
                tell_start = false;
                continue;
            }
            return Err(left_branch(rod, out, retakes));
        }
        let stale = end == SegmentEnd::Stale;
        if out.contact.is_some() || !(stale && out.counts.steps < opts.max_steps) {
            if stale && out.contact.is_none() {
                // The step limit on a stale list (the branch's stop: the
                // limit, not the list's): its last point, not re-converged
                // on a next list, is told now.
                out.stop = Stop::MaxSteps;
                let mut last = out.records.last().expect("a record").clone();
                last.outputs = [&out.states.last().expect("a state")[..], &[0.0]].concat();
                progress(&last);
            }
            return Ok(());
        }
        start = Start::Resume(out.resume.clone());
        *anchor = ListAnchor::at(start_x(&start), anchor.order);
    }
}

/// The branch's last point left μ = 0 after `retakes` retakes: it is
/// dropped (never told) and the error says where the branch ends. A branch
/// whose only point left μ = 0 has no point to keep (the error alone).
fn left_branch(rod: &Rod, out: &mut RodBranch, retakes: usize) -> Error {
    let mu = out.states.last().map_or(f64::NAN, |x| x[rod.unknowns()]);
    let why = out.states.last().map_or_else(String::new, |x| rod.unfolding_failure(x));
    let lambda = out.records.last().map_or(f64::NAN, |r| r.lambda);
    if !drop_last(out) {
        out.records.clear();
        out.states.clear();
    }
    let kept = out.records.len();
    let tried = match retakes {
        0 => "with no retake allowed".to_string(),
        _ => format!("also after {retakes} retakes from the point before with the step halved each time"),
    };
    Error::new(
        Status::ErrNotConverged,
        format!(
            "the branch left the unfolding parameter at μ = {mu:e} (Λ = {lambda}) {tried}: {why}; the branch \
             ends at its last point on it ({kept} points kept)"
        ),
    )
}

impl ListAnchor {
    /// A list built about `x` and measured from there, keeping `order`.
    fn at(x: &[f64], order: Option<ColumnOrder>) -> Self {
        ListAnchor { built: x.to_vec(), reference: x.to_vec(), order }
    }
}

/// A point reached on the previous pair list (the last of `out`),
/// re-converged at its Λ on `problem`'s new list when a pair it lacked
/// matters (it moved past skin/2).
fn reconverge(problem: &mut ChargedRod, x: &mut [f64], lambda: f64, opts: &Options, out: &mut RodBranch) -> Result<()> {
    let mut res = vec![0.0; x.len()];
    problem.residual(x, lambda, &mut res);
    if scaled_max_norm(&res, &problem.equation_scales()) <= opts.residual_tol {
        return Ok(());
    }
    let scaling = opts.scaling.clone().unwrap_or_else(|| Scaling::of(problem));
    let mut ctx = Context::with_options(problem, scaling, opts)?;
    let anchor = x.to_vec();
    let mut l = lambda;
    let result = correct(problem, &mut ctx, x, &mut l, Plane::fixed(&anchor, lambda), opts.residual_tol, Reuse::No);
    out.counts.add(&ctx.counts);
    result?;
    if let (Some(rec), Some(st)) = (out.records.last_mut(), out.states.last_mut()) {
        st.copy_from_slice(x);
        rec.residual = opts.residual_tol;
    }
    Ok(())
}

/// The segment of a branch on one pair list: Newton continuation (or the
/// ANM, [`RodCharge::anm`]) until the end, a strand crossing (the branch's
/// contact; it stops), a list gone stale by its rule (a stage moved half
/// the skin from `reference`, where the list was built; or by coverage, a
/// missing pair within half the skin of the potential's range,
/// [`ChargedRod::coverage`]: the list is rebuilt and the branch
/// continued), or, with a phase
/// condition, a point that left μ = 0 (not told: it is taken again
/// shorter; the ANM keeps no point before it to retake from, so there the
/// branch ends with its path, [`RodBranch::failure`]). The first record is
/// told as `first` says.
fn follow_list(
    problem: &mut ChargedRod,
    start: Start,
    reference: &[f64],
    phase: Phase,
    opts: &Options,
    first: SegmentStart,
    progress: Progress<'_>,
) -> Result<(RodBranch, SegmentEnd, ColumnOrder)> {
    let (rod, charge) = (&problem.rod().clone(), &problem.charge().clone());
    // How much of the list's margin is left at a state (negative: stale,
    // the list is rebuilt there). Verlet's rule (the default, and the
    // base-pair model's): no stage moved half the skin from where the list
    // was built. By coverage: a far pair missing from the list is still
    // half the skin outside the potential's range.
    let coverage = problem.coverage();
    let half_skin = 0.5 * charge.skin;
    // Verlet's rule for the ANM: its steps stop where a stage reaches half
    // the skin (`series_reach`), so its list is rebuilt once half of that
    // is used, not at a step cut short.
    let verlet = if charge.anm.is_some() { 0.5 * half_skin } else { half_skin };
    let (reference, _) = rod.stage_points(reference);
    let offsets = rod.stage_offsets();
    let margin = |x: &[f64]| -> f64 {
        match &coverage {
            Some(c) => c.gap(x) - half_skin,
            None => {
                verlet
                    - offsets
                        .iter()
                        .zip(&reference)
                        .map(|(&o, r0)| distance(&[x[o], x[o + 1], x[o + 2]], r0))
                        .fold(0.0, f64::max)
            }
        }
    };
    // μ's scale (None: no phase condition). Every accepted point is
    // checked as it comes: on the spurious straight family (straight
    // state, any μ) or a tilted solution with μ ≠ 0 of the discretised
    // equations only, the branch is lost, and a long run that found out at
    // its end lost its whole path (1 kbp, 1 pN, 0.01 M: 433 s).
    let mu_scale = phase.map(|_| *problem.unknown_scales().0.last().expect("μ"));
    // μ of the last point on the branch (the start's, then each told
    // point's): a jump from it is a corrector landing elsewhere.
    let previous_mu = std::cell::Cell::new(start_x(&start).get(rod.unknowns()).copied().unwrap_or(0.0));
    let off =
        |x: &[f64]| mu_scale.is_some_and(|scale| rod.off_branch(x, previous_mu.get(), scale, opts.unfolding_moment));
    let local = problem.list_is_local();
    let mut end = SegmentEnd::Branch;
    let mut crossing: Option<Contact> = None;
    let mut index = 0;
    let observe = |x: &[f64], _: f64| {
        let mut o = x.to_vec();
        o.push(margin(x));
        o
    };
    // A point off the branch or on a stale list ends the segment: told at
    // once, not after a step that would be dropped (records' signs on a
    // second thread).
    let ends = |rec: &Record| {
        let x = &rec.outputs[..rec.outputs.len() - 1];
        off(x) || (local && *rec.outputs.last().expect("margin") < 0.0)
    };
    let tell = |rec: &Record| {
        let x = &rec.outputs[..rec.outputs.len() - 1];
        let k = index;
        index += 1;
        if first == SegmentStart::Told && k == 0 {
            return true;
        }
        if off(x) {
            end = SegmentEnd::OffBranch;
            return false;
        }
        if let Some(&mu) = x.get(rod.unknowns()).filter(|_| mu_scale.is_some()) {
            previous_mu.set(mu);
        }
        if first == SegmentStart::Reached && k == 0 {
            return progress(rec);
        }
        if let Some((distance, s1, s2)) = strand_crossing(rod, charge, x) {
            crossing = Some(Contact { record: k, distance, s1, s2 });
            progress(rec);
            return false;
        }
        if local && *rec.outputs.last().expect("margin") < 0.0 {
            end = SegmentEnd::Stale;
            return false;
        }
        progress(rec)
    };
    let b = match charge.anm {
        Some(anm) => continue_anm(problem, start, opts, &anm, observe, tell)?,
        None => continue_newton_hinted(problem, start, opts, observe, tell, ends)?,
    };
    let order = b.column_order;
    let mut segment = RodBranch::from_engine(b, phase, 1);
    segment.contact = crossing;
    segment.pair_lists = 1;
    Ok((segment, end, order))
}

/// What a segment's first record is, for `progress`.
#[derive(Clone, Copy, PartialEq, Eq)]
enum SegmentStart {
    /// The branch's start: checked and told as any point.
    Branch,
    /// The previous segment's last point, reached on its list: checked
    /// there, told now (re-converged on this list, μ checked again).
    Reached,
    /// A point told already (a step taken again from it, [`retake`]).
    Told,
}

/// Why a segment on one pair list ended.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum SegmentEnd {
    /// The branch's own stop (or a strand crossing: its contact).
    Branch,
    /// The list went stale: it is rebuilt, the branch goes on.
    Stale,
    /// Its last point left μ = 0: dropped and taken again shorter.
    OffBranch,
}

/// A branch whose last point, reached on its pair list by a step that
/// carried stages past the list's skin, does not re-converge on the list
/// rebuilt there (far from an equilibrium with the pairs the old list
/// lacked: long steps, `Options::corrector_aim` 5), or that left μ = 0 (a
/// corrector that slid onto the spurious straight family, or onto a
/// solution with μ ≠ 0 of the discretised equations only): the point is
/// dropped and the branch resumes from the point before (told already;
/// within half the skin of its list, so all its pairs were listed) with
/// half the step, on a list built there. The dropped step counts as a
/// rejected one. Returns whether it was done (the point before is known).
fn retake(segment: &mut RodBranch) -> bool {
    if segment.resume.previous.is_none() || !drop_last(segment) {
        return false;
    }
    segment.resume.step *= 0.5;
    true
}

/// Drop the branch's last point (not its only one): the branch resumes
/// from the point before with that point's step when the engine kept it.
/// The dropped step counts as a rejected one.
fn drop_last(segment: &mut RodBranch) -> bool {
    if segment.records.len() < 2 {
        return false;
    }
    segment.truncate(segment.records.len() - 1);
    // A rejected step, not a step of the branch (steps = records − 1,
    // which the step limit and a resume count on).
    segment.counts.steps = segment.counts.steps.saturating_sub(1);
    segment.counts.rejected_steps += 1;
    if let Some(previous) = segment.resume.previous.take() {
        segment.resume = *previous;
    }
    true
}

/// Leave `branch` at its bifurcation `index` along null direction
/// `direction` (first step `first_step`): at a double point of the
/// symmetric rod (the buckling of a twisted rod under tension) with the
/// rod's phase condition at the node of largest lateral displacement of
/// the null direction, the first point taken at a fixed buckle amplitude
/// ([`crate::rod::branch::switch`]). The new branch is followed as by
/// [`follow`] (μ checked at every point; a failure after its first points
/// kept in [`RodBranch::failure`]). Returns it with the anchor of its last
/// pair list ([`follow_on`]: where a stopped branch resumes on the same
/// list).
// The public entry point, as [`Rod::switch_branch`] with the charge.
#[allow(clippy::too_many_arguments)]
pub fn switch(
    rod: &Rod,
    charge: &RodCharge,
    branch: &RodBranch,
    index: usize,
    direction: usize,
    first_step: f64,
    opts: &Options,
    mut progress: impl FnMut(&Record) -> bool,
) -> Result<(RodBranch, ListAnchor)> {
    let model = Charged { rod, charge, last_anchor: Default::default() };
    let b = branch::switch(&model, branch, index, direction, first_step, opts, &mut progress)?;
    let anchor = model.last_anchor.into_inner().expect("a switch follows a branch");
    Ok((b, anchor))
}

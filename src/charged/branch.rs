//! Branches of charged-rod equilibria: Newton pseudo-arc-length
//! continuation of [`ChargedRod`] — in the end rotation φ itself for a rod
//! with a controlled end rotation (any number of turns), or in the end
//! torque for a torque clamp ([`super::dna::EndControl`]) — with the pair
//! list rebuilt whenever a stage has moved half the skin (the branch is
//! continued from the same point and tangent on the new pattern), strand
//! crossing detected (non-neighbouring stage points closer than 2a: the
//! branch stops with its [`RodBranch::contact`]), and branch switching at a
//! located (double) buckling point with the rod's phase condition — the
//! plain rod's [`RodBranch`] and [`crate::rod::branch::switch`], with this
//! model plugged in ([`Charged`]). The DNA scene that runs them:
//! [`super::dna`].

use super::rod::{ChargedRod, RodCharge};
use crate::continuation::corrector::{correct, Plane};
use crate::continuation::newton::{continue_newton, Start};
use crate::continuation::run::Context;
use crate::continuation::{Options, Problem, Record, Resume, Scaling};
use crate::error::Result;
use crate::geometry::proximity::closest_pair_within;
use crate::geometry::vec3::distance;
use crate::nonlinear::scaled_max_norm;
use crate::rod::branch::{self, Contact, Followed, RodBranch};
use crate::rod::model::Rod;

/// A charged rod's branch: the rod's branch type.
pub type ChargedBranch = RodBranch;

/// The closest non-neighbouring pair of stage points nearer than 2a:
/// (distance, s1, s2).
pub fn strand_crossing(rod: &Rod, charge: &RodCharge, x: &[f64]) -> Option<(f64, f64, f64)> {
    let a = charge.screening.a;
    let (r, s) = rod.stage_points(x);
    closest_pair_within(&r, &s, 2.0 * a, std::f64::consts::PI * a).map(|(d, i, j)| (d, s[i], s[j]))
}

/// The charged rod as a [`Followed`] model.
pub struct Charged<'a> {
    pub rod: &'a Rod,
    pub charge: &'a RodCharge,
}

impl Followed for Charged<'_> {
    type System = ChargedRod;

    fn rod(&self) -> &Rod {
        self.rod
    }

    fn system(&self, phase: Option<(usize, f64)>, x: &[f64]) -> Result<ChargedRod> {
        ChargedRod::new(self.rod, self.charge, phase, x)
    }

    fn follow(
        &self,
        start: Start,
        phase: Option<(usize, f64)>,
        opts: &Options,
        progress: &mut dyn FnMut(&Record) -> bool,
    ) -> Result<RodBranch> {
        follow(self.rod, self.charge, start, phase, opts, progress)
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
/// resume point, appended to it.
pub fn follow(
    rod: &Rod,
    charge: &RodCharge,
    start: Start,
    phase: Option<(usize, f64)>,
    opts: &Options,
    progress: impl FnMut(&Record) -> bool,
) -> Result<RodBranch> {
    follow_into(rod, charge, start, phase, opts, progress, None)
}

/// Continue `branch` from its record `record` (its later records dropped)
/// with another charge model — a hard core switched on where the strands
/// crossed: the point is re-converged at its Λ on the new model (it
/// replaces the record) and the branch followed on from it, leaving along
/// the secant of the dropped step (the new model's tangent is computed
/// there, oriented by it). `opts.max_steps` counts the branch's steps
/// before too.
pub fn continue_with(
    rod: &Rod,
    charge: &RodCharge,
    mut branch: RodBranch,
    record: usize,
    opts: &Options,
    progress: impl FnMut(&Record) -> bool,
) -> Result<RodBranch> {
    let k = record.min(branch.records.len().saturating_sub(1));
    let (x, lambda) = (branch.states[k].clone(), branch.records[k].lambda);
    let (tangent_x, tangent_lambda) = match branch.states.get(k + 1) {
        Some(next) => (next.iter().zip(&x).map(|(b, a)| b - a).collect(), branch.records[k + 1].lambda - lambda),
        None => (branch.resume.tangent_x.clone(), branch.resume.tangent_lambda),
    };
    let step = branch.records.get(k + 1).map_or(branch.resume.step, |r| r.step);
    branch.records.truncate(k + 1);
    branch.states.truncate(k + 1);
    branch.contact = None;
    let start = Start::Resume(Resume { x, lambda, tangent_x, tangent_lambda, step });
    let phase = branch.phase;
    follow_into(rod, charge, start, phase, opts, progress, Some(branch))
}

/// [`follow`], appending to `out` when given (its last record is the
/// start, re-converged on this model when it is not within tolerance).
fn follow_into(
    rod: &Rod,
    charge: &RodCharge,
    mut start: Start,
    phase: Option<(usize, f64)>,
    opts: &Options,
    mut progress: impl FnMut(&Record) -> bool,
    mut out: Option<RodBranch>,
) -> Result<RodBranch> {
    loop {
        let built = std::time::Instant::now();
        let mut problem = ChargedRod::new(rod, charge, phase, start_x(&start))?;
        let setup = built.elapsed();
        if let (Start::Resume(r), Some(out)) = (&mut start, out.as_mut()) {
            reconverge(&mut problem, &mut r.x, r.lambda, opts, out)?;
        }
        let steps_done = out.as_ref().map_or(0, |b| b.counts.steps);
        let seg_opts = Options { max_steps: opts.max_steps.saturating_sub(steps_done).max(1), ..opts.clone() };
        let (segment, stale) = follow_list(&mut problem, start, phase, &seg_opts, out.is_some(), &mut progress)?;
        let out = match out.as_mut() {
            Some(b) => {
                b.append(segment);
                b
            }
            None => out.insert(segment),
        };
        out.counts.times.setup += setup;
        if out.contact.is_some() || !(stale && out.counts.steps < opts.max_steps) {
            break;
        }
        start = Start::Resume(out.resume.clone());
    }
    Ok(out.expect("at least one segment"))
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
    let mut ctx = Context::new(problem, scaling)?;
    let anchor = x.to_vec();
    let mut l = lambda;
    let result = correct(problem, &mut ctx, x, &mut l, Plane::fixed(&anchor, lambda), opts.residual_tol, false);
    out.counts.add(&ctx.counts);
    result?;
    if let (Some(rec), Some(st)) = (out.records.last_mut(), out.states.last_mut()) {
        st.copy_from_slice(x);
        rec.residual = opts.residual_tol;
    }
    Ok(())
}

/// The segment of a branch on one pair list: Newton continuation until
/// the end, a strand crossing (the branch's contact; it stops), or a stage
/// moving half the skin from where the list was built (returned stale: the
/// list is rebuilt and the branch continued). A `resumed` segment's first
/// record is the previous segment's last, already checked and reported.
fn follow_list(
    problem: &mut ChargedRod,
    start: Start,
    phase: Option<(usize, f64)>,
    opts: &Options,
    resumed: bool,
    progress: &mut dyn FnMut(&Record) -> bool,
) -> Result<(RodBranch, bool)> {
    let (rod, charge) = (&problem.rod().clone(), &problem.charge().clone());
    let half_skin = 0.5 * charge.skin;
    let (reference, _) = rod.stage_points(start_x(&start));
    let offsets = rod.stage_offsets();
    // The largest distance a stage has moved from where the list was built.
    let moved = |x: &[f64]| -> f64 {
        offsets.iter().zip(&reference).map(|(&o, r0)| distance(&[x[o], x[o + 1], x[o + 2]], r0)).fold(0.0, f64::max)
    };
    let local = problem.list_is_local();
    let mut stale = false;
    let mut crossing: Option<Contact> = None;
    let mut index = 0;
    let observe = |x: &[f64], _: f64| {
        let mut o = x.to_vec();
        o.push(moved(x));
        o
    };
    let b = continue_newton(problem, start, opts, observe, |rec| {
        let x = &rec.outputs[..rec.outputs.len() - 1];
        let k = index;
        index += 1;
        if resumed && k == 0 {
            return true;
        }
        if let Some((distance, s1, s2)) = strand_crossing(rod, charge, x) {
            crossing = Some(Contact { record: k, distance, s1, s2 });
            return false;
        }
        if local && *rec.outputs.last().expect("displacement") > half_skin {
            stale = true;
            return false;
        }
        progress(rec)
    })?;
    let mut segment = RodBranch::from_engine(b, phase, 1);
    segment.contact = crossing;
    segment.pair_lists = 1;
    Ok((segment, stale))
}

/// Leave `branch` at its bifurcation `index` along null direction
/// `direction` (first step `first_step`): at a double point of the
/// symmetric rod (the buckling of a twisted rod under tension) with the
/// rod's phase condition at the node of largest lateral displacement of
/// the null direction, the first point taken at a fixed buckle amplitude
/// ([`crate::rod::branch::switch`]).
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
) -> Result<RodBranch> {
    branch::switch(&Charged { rod, charge }, branch, index, direction, first_step, opts, &mut progress)
}

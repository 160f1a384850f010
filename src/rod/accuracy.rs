//! Rod branches to a requested accuracy: an a-posteriori
//! estimate of every record's discretisation error in the quantities a
//! user reads — tip position, tip rotation, base force and moment — and
//! the branch recomputed on a finer mesh until the estimates meet a
//! tolerance.
//!
//! The estimate is the difference from the same point re-solved on half
//! the elements: each record's state is carried to the coarse mesh (node
//! values kept, stage values by six-point Lagrange interpolation along
//! the rod) and corrected there by damped Newton at the record's Λ (and
//! the same phase condition). Why it bounds the record's own error: with
//! e_N the error on N elements, |q_N − q_{N/2}| = |e_{N/2} − e_N| ≥
//! |e_N| as soon as |e_{N/2}| ≥ 2|e_N| — the scheme converges at order
//! 2s on Gauss(s) (8 on Gauss(4)), so in its asymptotic range the
//! estimate exceeds the error ~2^{2s}-fold. That margin is the price of
//! honesty here: Richardson's |q_N − q_{N/2}|/(2^{2s} − 1) would be sharp
//! but undershoots wherever the mesh is not yet asymptotic. A record whose
//! coarse re-solve fails (a fold in Λ, a singular point, too coarse a
//! mesh) has no estimate, and a branch with such a record does not meet
//! the tolerance. At a fold in Λ the other mesh's branch may not reach
//! the record's Λ: there the point is re-solved on the plane through the
//! record normal to the branch (its neighbours' secant), as arc-length
//! continuation corrects, and the quantities are compared there.

use super::branch::{Method, RodBranch};
use super::mesh;
use super::model::unwrap_rotation;
use super::model::Rod;
use crate::continuation::bifurcation::{locate, Bifurcation, Evidence, State};
use crate::continuation::corrector::{correct, Plane, Reuse};
use crate::continuation::equilibrium::damped_newton;
use crate::continuation::run::{Context, Factors};
use crate::continuation::{Counts, Options, Problem, Scaling, Stop};
use crate::error::{self, Error, Result};
use crate::geometry::vec3::distance;
use crate::linalg::dense::{norm2, sub};
use crate::rod::branch::Phase;
use crate::status::Status;

/// The estimated error of one record's quantities: absolute (lengths, rad,
/// forces, moments in the rod's units).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RecordError {
    /// |Δr(L)|.
    pub tip_position: f64,
    /// The angle between the two tip frames (rad).
    pub tip_rotation: f64,
    /// |ΔF(0)|, |ΔM(0)| (spatial, the internal force and moment at s = 0).
    pub base_force: f64,
    pub base_moment: f64,
}

impl RecordError {
    /// The error against the tolerance's scales: each quantity relative
    /// to the larger of its magnitude at the point and its scale (L, 1
    /// rad, K_b/L², K_b/L), the largest of the four.
    pub fn scaled(&self, rod: &Rod, x: &[f64]) -> f64 {
        let (l, kb) = (rod.length, rod.law.bending());
        let (f, m) = rod.spatial_force_moment(x, 0);
        let tip = rod.tip(x);
        [
            self.tip_position / norm2(&tip).max(l),
            self.tip_rotation,
            self.base_force / norm2(&f).max(kb / (l * l)),
            self.base_moment / norm2(&m).max(kb / l),
        ]
        .into_iter()
        .fold(0.0, f64::max)
    }
}

/// The estimates of every record of `branch` (followed on `rod`, an even
/// number of elements ≥ 2): None where the coarse re-solve failed.
pub fn estimate_errors(rod: &Rod, branch: &RodBranch, residual_tol: f64) -> Result<Vec<Option<RecordError>>> {
    let coarse = half(rod)?;
    let mut on = Resolver::new(rod, &coarse, branch.phase)?;
    let (records, states) = (&branch.records, &branch.states);
    Ok((0..records.len())
        .map(|k| {
            let (dx, dl) = secant(records, states, k);
            let solved = on.solve(&states[k], records[k].lambda, residual_tol, Some((&dx, dl)));
            solved.ok().map(|(y, _)| difference(rod, &states[k], &coarse, &y))
        })
        .collect())
}

/// What extension and shear do to the branch (to model only what
/// the scene requires): every record re-solved on the rod's Kirchhoff
/// variant (v ≡ v̂: inextensible, unshearable; the same bending and twist,
/// the same mesh and Λ), and the quantities' differences — None where the
/// re-solve fails (the Kirchhoff rod's branch need not reach the record's
/// Λ, e.g. past a fold the extensible rod has moved). Refused for a rod
/// that is already Kirchhoff. rodkit keeps the branch it computed: here
/// the Kirchhoff rod has the same unknowns and costs the same, so the
/// differences say whether the simpler physics would meet a tolerance
/// (each below it, scaled by [`RecordError::scaled`]) rather than buy
/// speed.
pub fn kirchhoff_differences(rod: &Rod, branch: &RodBranch, residual_tol: f64) -> Result<Vec<Option<RecordError>>> {
    if rod.law.kirchhoff {
        return Err(Error::new(
            Status::ErrOutOfRange,
            "the rod is already the Kirchhoff variant (inextensible, unshearable): nothing to compare",
        ));
    }
    let constrained = Rod { law: super::RodLaw { kirchhoff: true, ..rod.law.clone() }, ..rod.clone() };
    let mut on = Resolver::new(rod, &constrained, branch.phase)?;
    let (records, states) = (&branch.records, &branch.states);
    Ok((0..records.len())
        .map(|k| {
            let solved = on.solve(&states[k], records[k].lambda, residual_tol, None);
            solved.ok().map(|(y, _)| difference(rod, &states[k], &constrained, &y))
        })
        .collect())
}

/// The branch's direction at record k: the central difference of its
/// neighbours' states and Λ (one-sided at the ends; zero for a lone point).
pub fn secant(records: &[crate::continuation::Record], states: &[Vec<f64>], k: usize) -> (Vec<f64>, f64) {
    let last = records.len().saturating_sub(1);
    let (a, b) = (k.saturating_sub(1), (k + 1).min(last));
    (sub(&states[b], &states[a]), records[b].lambda - records[a].lambda)
}

/// Points of one rod's branch re-solved on another discretisation of the
/// same rod (coarser for an estimate, finer for a reference): the state
/// carried over by [`transfer`], corrected by damped Newton at its Λ. A
/// branch's phase condition goes to the node at the same arc length (or
/// the nearest), its azimuth taken from the carried state there, so that
/// both solutions have their buckle turned alike at that point — the
/// branch's own azimuth would turn a non-planar buckle, or one whose node
/// moved, by a gauge angle and inflate every lateral difference.
pub struct Resolver<'r> {
    from: &'r Rod,
    to: &'r Rod,
    /// The phase node on `to` and the branch's azimuth (where the carried
    /// state has no lateral displacement there).
    phase: Phase,
    system: crate::continuation::system::AssembledSystem,
    /// The bordered corrector's context, made on the first fold.
    bordered: Option<Context>,
    pub counts: Counts,
    /// Points taken on the plane normal to the branch (a fold in Λ).
    pub planes: usize,
}

impl<'r> Resolver<'r> {
    pub fn new(from: &'r Rod, to: &'r Rod, phase: Phase) -> Result<Self> {
        let phase = phase.map(|(node, azimuth)| {
            let node = if from.breakpoints.is_none() && to.breakpoints.is_none() {
                ((node * to.elements) as f64 / from.elements as f64).round() as usize
            } else {
                // The node of `to` nearest in arc length.
                let s = from.node_position(node.min(from.elements));
                let d = |i: usize| (to.node_position(i) - s).abs();
                (0..=to.elements).fold(0, |best, i| if d(i) < d(best) { i } else { best })
            };
            (node.clamp(1, to.elements), azimuth)
        });
        let system = match phase {
            Some((node, azimuth)) => to.system_with_phase(node, azimuth)?,
            None => to.system()?,
        };
        Ok(Resolver { from, to, phase, system, bordered: None, counts: Counts::default(), planes: 0 })
    }

    /// `x` (a state of `from`) re-solved on `to` at Λ = `lambda`: the
    /// state and its Λ. Where that fails and the branch's direction there
    /// is given (`secant`: a difference of states of `from` and of their
    /// Λ), the point is taken instead on the plane through the carried
    /// state normal to that direction (a fold in Λ, where the other mesh's
    /// branch may not reach Λ): its Λ then differs by O(the error).
    pub fn solve(
        &mut self,
        x: &[f64],
        lambda: f64,
        residual_tol: f64,
        secant: Option<(&[f64], f64)>,
    ) -> Result<(Vec<f64>, f64)> {
        let y = self.carry(x)?;
        self.correct_carried(y, lambda, residual_tol, secant)
    }

    /// `x` (a state of `from`) carried to `to`, and the phase condition
    /// turned to its azimuth at the phase node (later corrections keep it).
    fn carry(&mut self, x: &[f64]) -> Result<Vec<f64>> {
        let y = transfer(self.from, self.to, x, self.system.dim());
        if let Some((node, azimuth)) = self.phase {
            let at = self.to.node(node);
            let (px, py) = (y[at], y[at + 1]);
            let here = if px.hypot(py) > 1e-9 * self.to.length { py.atan2(px) } else { azimuth };
            self.system = self.to.system_with_phase(node, here)?;
        }
        Ok(y)
    }

    /// A carried state `y` corrected under the current phase condition (as
    /// [`Resolver::solve`]).
    fn correct_carried(
        &mut self,
        mut y: Vec<f64>,
        lambda: f64,
        residual_tol: f64,
        secant: Option<(&[f64], f64)>,
    ) -> Result<(Vec<f64>, f64)> {
        let dim = self.system.dim();
        let anchor = y.clone();
        let fixed = damped_newton(&mut self.system, &mut y, lambda, residual_tol, &mut self.counts);
        let (Err(e), Some((dx, dl))) = (&fixed, secant) else {
            return fixed.map(|_| (y, lambda));
        };
        let t = transfer(self.from, self.to, dx, dim);
        if !(dl.is_finite() && t.iter().all(|v| v.is_finite())) {
            return Err(e.clone());
        }
        let ctx = match &mut self.bordered {
            Some(c) => c,
            slot => slot.insert(Context::new(&self.system, Scaling::of(&self.system))?),
        };
        let (mut y, mut l) = (anchor.clone(), lambda);
        correct(
            &mut self.system,
            ctx,
            &mut y,
            &mut l,
            Plane::new((&anchor, lambda), (&t, dl)),
            residual_tol,
            Reuse::No,
        )?;
        self.planes += 1;
        Ok((y, l))
    }
}

/// The estimated error of a located bifurcation (absolute, in the rod's
/// units): its critical Λ, its end rotation where the rod has one (0
/// otherwise), and the quantities of its state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BifurcationError {
    pub lambda: f64,
    pub end_rotation: f64,
    pub at: RecordError,
}

impl BifurcationError {
    /// Against the tolerance's scales: the critical value relative to its
    /// magnitude — the end rotation's (at least 1 rad) under rotation
    /// control, where Λ = sin(φ/2) says little near φ = 2πk, else Λ's —
    /// and the state's quantities as [`RecordError::scaled`]; the largest.
    pub fn scaled(&self, rod: &Rod, bif: &Bifurcation) -> f64 {
        let critical = if rod.twisted() {
            let phi = rod.end_rotation(&bif.x, bif.lambda).unwrap_or(0.0);
            self.end_rotation / phi.abs().max(1.0)
        } else if bif.lambda != 0.0 {
            self.lambda / bif.lambda.abs()
        } else {
            self.lambda
        };
        critical.max(self.at.scaled(rod, &bif.x))
    }
}

/// The estimates of every bifurcation `branch` located (followed on
/// `rod`, an even number of elements ≥ 2): the difference from the same
/// point located again on half the elements. The records around it are
/// re-solved there (as [`estimate_errors`]) and the point is located
/// between them by the branch's own search ([`locate`]); where it is not
/// between them (a coarse mesh moves it more than a step) the bracket is
/// widened by a record on each side, twice. None where no point is found,
/// or where the one found lies nearer another of the branch's points than
/// this one (close roots a coarse mesh cannot tell apart): a branch with
/// such a point does not meet a tolerance.
pub fn estimate_bifurcation_errors(
    rod: &Rod,
    branch: &RodBranch,
    residual_tol: f64,
) -> Result<Vec<Option<BifurcationError>>> {
    let coarse = half(rod)?;
    let mut on = Resolver::new(rod, &coarse, branch.phase)?;
    let (rotations, _) = branch.end_rotations(rod, None);
    Ok((0..branch.bifurcations.len())
        .map(|i| {
            let bif = &branch.bifurcations[i];
            let found = relocate(&mut on, branch, bif, residual_tol).ok().flatten()?;
            // The nearest of the branch's points in Λ and state.
            let apart = |b: &Bifurcation| (b.lambda - found.lambda).abs() + distance_of(&b.x, &found.x, rod, &coarse);
            let nearest = branch.bifurcations.iter().map(apart).fold(f64::INFINITY, f64::min);
            if apart(bif) > nearest {
                return None;
            }
            let end_rotation =
                match (branch.rotation_at_bifurcation(rod, i, &rotations), coarse.end_rotation(&found.x, found.lambda))
                {
                    (Some(fine), Some(raw)) => (fine - unwrap_rotation(fine, raw)).abs(),
                    _ => 0.0,
                };
            Some(BifurcationError {
                lambda: (bif.lambda - found.lambda).abs(),
                end_rotation,
                at: difference(rod, &bif.x, &coarse, &found.x),
            })
        })
        .collect())
}

/// The tip distance between a state of `a` and one of `b` (the measure
/// that tells two bifurcation points apart beside their Λ).
fn distance_of(x: &[f64], y: &[f64], a: &Rod, b: &Rod) -> f64 {
    distance(&a.tip(x), &b.tip(y))
}

/// `bif` (a point of `branch`, on `on.from`) located on `on.to`: the
/// bracket of records around it re-solved there, widened up to twice.
fn relocate(
    on: &mut Resolver,
    branch: &RodBranch,
    bif: &Bifurcation,
    residual_tol: f64,
) -> Result<Option<Bifurcation>> {
    // One phase condition for the whole search: the bifurcation's own
    // azimuth, carried.
    on.carry(&bif.x)?;
    // The resolver's bordered context (its symbolic analysis made once for
    // every point of the branch), back in its slot afterwards.
    let mut ctx = match on.bordered.take() {
        Some(c) => c,
        None => Context::new(&on.system, Scaling::of(&on.system))?,
    };
    let found = search(on, &mut ctx, branch, bif, residual_tol);
    on.bordered = Some(ctx);
    found
}

/// [`relocate`]'s search on the bracket around `bif`, widened up to twice.
fn search(
    on: &mut Resolver,
    ctx: &mut Context,
    branch: &RodBranch,
    bif: &Bifurcation,
    residual_tol: f64,
) -> Result<Option<Bifurcation>> {
    let (records, states) = (&branch.records, &branch.states);
    let last = records.len().saturating_sub(1);
    let dim = on.system.dim();
    for widen in 0..3 {
        let (a, b) = (bif.record.saturating_sub(widen), (bif.record + 1 + widen).min(last));
        if a == b {
            return Ok(None);
        }
        let mut ends = vec![];
        for k in [a, b] {
            let (dx, dl) = secant(records, states, k);
            let y = transfer(on.from, on.to, &states[k], dim);
            let (y, l) = on.correct_carried(y, records[k].lambda, residual_tol, Some((&dx, dl)))?;
            // The tangent there, turned along the branch's direction.
            let t = transfer(on.from, on.to, &dx, dim);
            ctx.factorise(&mut on.system, &y, l, (&t, dl), Factors::Exact)?;
            let (mut tx, mut tl) = ctx.tangent()?;
            if ctx.scaling.dot(&tx, tl, &t, dl) < 0.0 {
                tx.iter_mut().for_each(|v| *v = -*v);
                tl = -tl;
            }
            let (sign, _) = ctx.bordered.determinant_signs(&ctx.scaling, &tx, tl);
            ends.push((State { x: y, lambda: l, tx, tl }, sign));
        }
        let evidence =
            Evidence { det_sign_change: ends[0].1 * ends[1].1 < 0.0, test_function_change: bif.test_function_change };
        if let Some((found, _)) =
            locate(&mut on.system, ctx, &ends[0].0, &ends[1].0, evidence, (residual_tol, 1e-10), None)?
        {
            if found.multiplicity == bif.multiplicity {
                return Ok(Some(found));
            }
        }
    }
    Ok(None)
}

/// `rod` on half its elements (an even count ≥ 2), the estimates' coarse
/// mesh: neighbours merged in pairs (elements 2k and 2k + 1), so that every
/// element is coarsened — an element kept as it is would carry the same
/// error on both meshes and drop out of their difference.
fn half(rod: &Rod) -> Result<Rod> {
    if rod.elements < 2 || !rod.elements.is_multiple_of(2) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!("error estimates need an even number of elements ≥ 2 (got {})", rod.elements),
        ));
    }
    match &rod.breakpoints {
        None => Ok(rod.uniform(rod.elements / 2)),
        Some(t) => rod.clone().graded(&t.iter().copied().step_by(2).collect::<Vec<_>>()),
    }
}

/// How [`refine_until`] places the elements of each new try.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Refinement {
    /// Graded where the branch's solutions vary fast
    /// ([`mesh::graded_mesh`]): the records' and located points' monitor
    /// equidistributed, as AUTO-07p adapts its mesh. Uniform where the
    /// monitor vanishes (a straight branch).
    #[default]
    Graded,
    /// Equal elements.
    Uniform,
}

/// A branch on the rod `template` with its elements chosen so that every
/// record's estimated error, and every located bifurcation's (its
/// critical load), meets a tolerance (see [`RecordError::scaled`],
/// [`BifurcationError::scaled`]).
pub struct Accurate {
    /// The rod as refined (its `elements` and `breakpoints` the mesh chosen).
    pub rod: Rod,
    pub branch: RodBranch,
    /// Per record, as [`estimate_errors`].
    pub estimates: Vec<Option<RecordError>>,
    /// Per located bifurcation, as [`estimate_bifurcation_errors`].
    pub bifurcation_estimates: Vec<Option<BifurcationError>>,
    /// The worst scaled estimate over the records and the bifurcations
    /// (∞ if one has none).
    pub worst: f64,
    /// The element counts tried, in order (the last is `rod.elements`).
    pub tried: Vec<usize>,
}

/// Most elements [`continue_to_tolerance`] tries before saying the
/// tolerance is out of reach.
pub const MAX_ELEMENTS: usize = 1024;

/// Follow the branch from the straight state at Λ = `lambda0` (as
/// [`Rod::continue_branch`]) on `template`'s law, loads, supports and
/// scheme to `tolerance`: [`refine_until`] with that branch.
pub fn continue_to_tolerance(
    template: &Rod,
    tolerance: f64,
    (lambda0, increasing): (f64, bool),
    opts: &Options,
    method: Method,
) -> Result<Accurate> {
    refine_until(template, tolerance, opts.residual_tol, |rod| {
        rod.continue_branch(None, lambda0, increasing, opts, method, |_| true)
    })
}

/// [`refine_with`] on graded meshes.
pub fn refine_until(
    template: &Rod,
    tolerance: f64,
    residual_tol: f64,
    follow: impl FnMut(&Rod) -> Result<RodBranch>,
) -> Result<Accurate> {
    refine_with(template, tolerance, residual_tol, Refinement::Graded, follow)
}

/// The branch `follow` computes on a rod (any path: a straight start, a
/// switch at a located bifurcation, …), on `template`'s law, loads,
/// supports and scheme, starting from its mesh (a uniform one made even,
/// at least 4 elements; a graded one with an even count as it is) and
/// refining until the worst scaled estimate is ≤ `tolerance`. Each new
/// mesh asks for a resolution from the last's estimate and the scheme's
/// order (with a 1.25 margin, at least 1.5× finer): uniformly, N × that
/// factor; graded, the worst element's ω h divided by it
/// ([`mesh::graded_mesh`]) — so a graded mesh never needs more elements
/// than the uniform one would, and fewer where the solution's variation
/// is local. At most [`MAX_ELEMENTS`] (ErrToleranceUnreachable beyond,
/// saying what was reached). A branch that `follow` returns cancelled
/// (`Stop::Cancelled`) ends the refinement as it is, with its estimates.
/// `residual_tol` (≤ the tolerance) is the points' own; the re-solves
/// take it, not below 1e-11 (their rounding floor on fine meshes under
/// large loads: the scaled residual of a 128-element cantilever at α =
/// 100 stalls near 2e-12).
pub fn refine_with(
    template: &Rod,
    tolerance: f64,
    residual_tol: f64,
    refinement: Refinement,
    mut follow: impl FnMut(&Rod) -> Result<RodBranch>,
) -> Result<Accurate> {
    error::in_range("tolerance", tolerance, 1e-12, 1e-1)?;
    // The points' own solver error enters the estimates: it must sit
    // below what is asked of them.
    if !(residual_tol <= tolerance) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!("residual_tol ({residual_tol:e}) must not exceed the tolerance asked for ({tolerance:e})"),
        ));
    }
    let order = template.scheme.order() as f64;
    let mut rod = match &template.breakpoints {
        Some(_) if template.elements >= 4 && template.elements.is_multiple_of(2) => template.clone(),
        _ => template.uniform(template.elements.max(4).div_ceil(2) * 2),
    };
    let mut tried = vec![];
    loop {
        let branch = follow(&rod)?;
        let estimates = estimate_errors(&rod, &branch, residual_tol.max(1e-11))?;
        let bifurcation_estimates = estimate_bifurcation_errors(&rod, &branch, residual_tol.max(1e-11))?;
        let worst = estimates
            .iter()
            .zip(&branch.states)
            .map(|(e, x)| e.map_or(f64::INFINITY, |e| e.scaled(&rod, x)))
            .chain(
                bifurcation_estimates
                    .iter()
                    .zip(&branch.bifurcations)
                    .map(|(e, b)| e.map_or(f64::INFINITY, |e| e.scaled(&rod, b))),
            )
            .fold(0.0, f64::max);
        tried.push(rod.elements);
        // Met — or stopped by its caller (a progress callback's cancel):
        // no further refinement, the estimates say how far it is.
        if worst <= tolerance || branch.stop == Stop::Cancelled {
            return Ok(Accurate { rod, branch, estimates, bifurcation_estimates, worst, tried });
        }
        // The estimate falls as (ω h)^order: the resolution that meets the
        // tolerance, with a margin; an estimate missing (∞) doubles it.
        let factor = if worst.is_finite() { (1.25 * (worst / tolerance).powf(1.0 / order)).max(1.5) } else { 2.0 };
        let uniform = || {
            let next = ((rod.elements as f64 * factor).ceil() as usize).div_ceil(2) * 2;
            if next > MAX_ELEMENTS {
                Err(next)
            } else {
                Ok(rod.uniform(next))
            }
        };
        let next = match refinement {
            Refinement::Uniform => uniform(),
            Refinement::Graded => {
                let states: Vec<&[f64]> =
                    branch.states.iter().map(|x| &x[..]).chain(branch.bifurcations.iter().map(|b| &b.x[..])).collect();
                mesh::graded_mesh(&rod, &states, factor, MAX_ELEMENTS).unwrap_or_else(uniform)
            }
        };
        rod = next.map_err(|next| {
            Error::new(
                Status::ErrToleranceUnreachable,
                format!(
                    "rod branch to tolerance {tolerance:e}: {} elements leave an estimated error {worst:e}, \
                     and the next refinement would need {next} > {MAX_ELEMENTS} elements",
                    rod.elements
                ),
            )
        })?;
    }
}

/// The state `x` of `fine` carried to `coarse` (any two discretisations
/// of one rod; length `dim`): each profile point's 13 values by Lagrange
/// interpolation on the six profile points of `fine` nearest in arc
/// length (exact at shared nodes), the end unknowns and a phase
/// condition's μ copied.
pub fn transfer(fine: &Rod, coarse: &Rod, x: &[f64], dim: usize) -> Vec<f64> {
    let mut y = vec![0.0; dim];
    let from = fine.profile_offsets();
    let profile_end = |r: &Rod| r.node(r.elements) + 13;
    for (s, off) in coarse.profile_offsets() {
        let k = from.partition_point(|p| p.0 < s).min(from.len() - 1);
        let lo = k.saturating_sub(3).min(from.len().saturating_sub(6));
        let window = &from[lo..(lo + 6).min(from.len())];
        for c in 0..13 {
            y[off + c] = lagrange(window.iter().map(|&(t, o)| (t, x[o + c])), s);
        }
    }
    // End-control unknowns (and μ) after the profile, in the same order.
    let (tail_fine, tail_coarse) = (profile_end(fine), profile_end(coarse));
    for (i, v) in x[tail_fine..].iter().enumerate() {
        if let Some(slot) = y.get_mut(tail_coarse + i) {
            *slot = *v;
        }
    }
    y
}

/// The Lagrange polynomial through `points` at `s`.
fn lagrange(points: impl Iterator<Item = (f64, f64)> + Clone, s: f64) -> f64 {
    let mut sum = 0.0;
    for (i, (si, vi)) in points.clone().enumerate() {
        let mut w = 1.0;
        for (j, (sj, _)) in points.clone().enumerate() {
            if i != j {
                w *= (s - sj) / (si - sj);
            }
        }
        sum += w * vi;
    }
    sum
}

/// The quantities' differences between `x` on `a` and `y` on `b`.
pub fn difference(a: &Rod, x: &[f64], b: &Rod, y: &[f64]) -> RecordError {
    let (fa, ma) = a.spatial_force_moment(x, 0);
    let (fb, mb) = b.spatial_force_moment(y, 0);
    let qa = &a.node_state(x, a.elements)[3..7];
    let qb = &b.node_state(y, b.elements)[3..7];
    RecordError {
        tip_position: distance(&a.tip(x), &b.tip(y)),
        tip_rotation: frame_angle(qa, qb),
        base_force: distance(&fa, &fb),
        base_moment: distance(&ma, &mb),
    }
}

/// The rotation angle between the frames of quaternions p and q (not
/// necessarily unit; ±q the same frame): 2 atan2(|vec(p̄q)|, |scalar(p̄q)|).
fn frame_angle(p: &[f64], q: &[f64]) -> f64 {
    let (p0, p1, p2, p3) = (p[0], -p[1], -p[2], -p[3]);
    let (q0, q1, q2, q3) = (q[0], q[1], q[2], q[3]);
    let w = p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3;
    let v = [
        p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
        p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1,
        p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0,
    ];
    2.0 * norm2(&v).atan2(w.abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rotations about e1 by a and b (closed form: the frames differ by
    /// |a − b|), scaled and sign-flipped (the same frames).
    #[test]
    fn frame_angle_is_the_relative_rotation() {
        for (a, b) in [(0.3f64, 0.3f64 + 1e-9), (0.0, 2.0), (1.0, -1.5)] {
            let p = [(0.5 * a).cos(), (0.5 * a).sin(), 0.0, 0.0];
            let q = [-2.0 * (0.5 * b).cos(), -2.0 * (0.5 * b).sin(), 0.0, 0.0];
            let got = frame_angle(&p, &q);
            assert!((got - (a - b).abs()).abs() < 1e-15 * (1.0 + (a - b).abs()), "{a}, {b}: {got}");
        }
    }

    /// Lagrange on six points reproduces a quintic exactly.
    #[test]
    fn lagrange_is_exact_for_quintics() {
        let f = |s: f64| 1.0 - 2.0 * s + 0.5 * s.powi(3) + s.powi(5);
        let pts: Vec<(f64, f64)> = [0.0, 0.1, 0.35, 0.5, 0.8, 1.0].iter().map(|&s| (s, f(s))).collect();
        for s in [0.05, 0.42, 0.97] {
            assert!((lagrange(pts.iter().copied(), s) - f(s)).abs() < 1e-14);
        }
    }
}

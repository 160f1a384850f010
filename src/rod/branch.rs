//! Branches of rod equilibria — plain and charged — in one type
//! ([`RodBranch`]): continuation from a state, resumption, and switching at
//! a located bifurcation with the phase condition chosen for the caller
//! when the point is double (rotational symmetry). [`Followed`] is what a
//! rod model provides to be followed and switched ([`switch`]); the plain
//! rod's is here (either engine), the charged rod's in
//! `crate::charged::branch` (pair lists rebuilt as the shape moves). What
//! the C ABI and the drivers use; the generic engines do the work.

use super::model::{unwrap_rotation, Rod};
use super::scheme::Scheme;
use crate::continuation::anm::{continue_anm, AnmOptions};
use crate::continuation::bifurcation::{branch_start, Bifurcation, Unresolved};
use crate::continuation::corrector::{correct, Plane, Reuse};
use crate::continuation::newton::{continue_newton, Start};
use crate::continuation::run::{validate, Context};
use crate::continuation::system::AssembledSystem;
use crate::continuation::{Branch, Counts, Options, Problem, Record, Resume, Sample, Scaling, Stop};
use crate::error::{self, Error, Result};
use crate::status::Status;

/// A phase condition: the node whose displacement across an azimuth is
/// held at zero, and that azimuth (rad); `None`: no phase condition.
pub type Phase = Option<(usize, f64)>;

/// A run's progress callback, called with each record; `false` stops the run.
pub type Progress<'a> = &'a mut dyn FnMut(&Record) -> bool;

/// Which engine follows the branch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    Anm(AnmOptions),
    Newton,
}

/// A followed branch with the full state at every record.
#[derive(Clone, Debug)]
pub struct RodBranch {
    pub records: Vec<Record>,
    /// x at each record (with the unfolding parameter μ last on a branch
    /// followed with a phase condition).
    pub states: Vec<Vec<f64>>,
    pub bifurcations: Vec<Bifurcation>,
    /// Brackets where a monitored function changed sign but no bifurcation
    /// accounting for it was located (see [`Unresolved`]).
    pub unresolved: Vec<Unresolved>,
    pub stop: Stop,
    pub counts: Counts,
    pub resume: Resume,
    /// The phase condition (node, azimuth) the branch was followed with.
    pub phase: Phase,
    /// Where the rod first touches itself: the first record whose
    /// non-neighbouring points come closer than the contact distance, with
    /// that distance and the pair's arc lengths. A plain rod given a
    /// diameter has no contact model: its records past it pass through
    /// themselves. A charged rod's contact is a strand crossing (stage
    /// points closer than 2a, arc-length gap > πa) and its branch stops
    /// there (`stop` = Cancelled).
    pub contact: Option<Contact>,
    /// Points at the requested loads (`Options::samples`), their outputs
    /// moved into `sample_states`.
    pub samples: Vec<Sample>,
    pub sample_states: Vec<Vec<f64>>,
    /// Requested loads crossed where no point within the tolerance was found.
    pub missed_samples: Vec<f64>,
    /// Electrostatic pair lists built (a charged rod: 1 + rebuilds; 0 for
    /// a plain rod).
    pub pair_lists: usize,
    /// Why a charged branch ended early with its records so far (`stop`
    /// Cancelled): an error raised after it had points — a corrector that
    /// failed, or points that kept leaving μ = 0 however short the step
    /// ([`crate::charged::branch`]). Its records up to there are valid;
    /// a long run keeps them instead of returning only the error. None
    /// for a plain rod (its errors are returned as such).
    pub failure: Option<Error>,
}

/// Where a branch first passes through itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    pub record: usize,
    pub distance: f64,
    pub s1: f64,
    pub s2: f64,
}

impl RodBranch {
    /// An engine's branch whose outputs are the states followed by `extra`
    /// trailing values (dropped): the states moved out of the records and
    /// samples.
    pub(crate) fn from_engine(b: Branch, phase: Phase, extra: usize) -> Self {
        let take = |outputs: &mut Vec<f64>| {
            let mut x = std::mem::take(outputs);
            x.truncate(x.len() - extra);
            x
        };
        let mut records = b.records;
        let states = records.iter_mut().map(|r| take(&mut r.outputs)).collect();
        let mut samples = b.samples;
        let sample_states = samples.iter_mut().map(|s| take(&mut s.outputs)).collect();
        RodBranch {
            records,
            states,
            bifurcations: b.bifurcations,
            unresolved: b.unresolved,
            stop: b.stop,
            counts: b.counts,
            resume: b.resume,
            phase,
            contact: None,
            samples,
            sample_states,
            missed_samples: b.missed_samples,
            pair_lists: 0,
            failure: None,
        }
    }

    /// Append `next`, continued from this branch's resume point (its first
    /// record repeats this branch's last): records, states, samples and
    /// contact renumbered, the stop and resume point taken from `next`,
    /// the work added.
    pub fn append(&mut self, mut next: RodBranch) {
        let offset = self.records.len().saturating_sub(1);
        self.records.extend(next.records.drain(1..));
        self.states.extend(next.states.drain(1..));
        for b in &mut next.bifurcations {
            b.record += offset;
        }
        self.bifurcations.append(&mut next.bifurcations);
        for u in &mut next.unresolved {
            u.records = (u.records.0 + offset, u.records.1 + offset);
        }
        self.unresolved.append(&mut next.unresolved);
        for s in &mut next.samples {
            s.record += offset;
        }
        self.samples.append(&mut next.samples);
        self.sample_states.append(&mut next.sample_states);
        self.missed_samples.append(&mut next.missed_samples);
        if self.contact.is_none() {
            self.contact = next.contact.map(|c| Contact { record: c.record + offset, ..c });
        }
        self.stop = next.stop;
        self.resume = next.resume;
        self.counts.add(&next.counts);
        self.pair_lists += next.pair_lists;
        if next.failure.is_some() {
            self.failure = next.failure;
        }
    }
}

impl RodBranch {
    /// Keep the first `len` records (and states); the bifurcations and
    /// unresolved brackets that reach past them go too (a retaken step's
    /// bracket is searched again by the step that replaces it).
    pub(crate) fn truncate(&mut self, len: usize) {
        self.records.truncate(len);
        self.states.truncate(len);
        self.bifurcations.retain(|b| b.record + 1 < len);
        self.unresolved.retain(|u| u.records.1 < len);
    }

    /// The end rotation φ at every record and at every sample, for a rod
    /// with one (zeros otherwise). φ is known mod 4π from each state (a
    /// torque clamp's, and a rotation control's Λ = sin(φ/2)): it is
    /// followed by continuity along the records (a step turns the end by
    /// less than 2π), from `previous` — the φ of the point a resumed or
    /// switched branch left — when given, and each sample from the record
    /// that starts its step (samples at loads far apart may be turns apart
    /// from each other).
    pub fn end_rotations(&self, rod: &Rod, previous: Option<f64>) -> (Vec<f64>, Vec<f64>) {
        let raw = |x: &[f64], lambda: f64| rod.end_rotation(x, lambda).unwrap_or(0.0);
        let mut records: Vec<f64> = self.records.iter().zip(&self.states).map(|(r, x)| raw(x, r.lambda)).collect();
        let mut samples: Vec<f64> =
            self.samples.iter().zip(&self.sample_states).map(|(s, x)| raw(x, s.lambda)).collect();
        let mut last = previous;
        for phi in records.iter_mut() {
            if let Some(p) = last {
                *phi = unwrap_rotation(p, *phi);
            }
            last = Some(*phi);
        }
        for (phi, s) in samples.iter_mut().zip(&self.samples) {
            if let Some(&from) = records.get(s.record) {
                *phi = unwrap_rotation(from, *phi);
            }
        }
        (records, samples)
    }

    /// The end rotation at bifurcation `index`, followed from the record
    /// it follows (`record_rotations`: the records' continuous φ, from
    /// [`RodBranch::end_rotations`]); None for a rod without one.
    pub fn rotation_at_bifurcation(&self, rod: &Rod, index: usize, record_rotations: &[f64]) -> Option<f64> {
        let bif = self.bifurcations.get(index)?;
        let raw = rod.end_rotation(&bif.x, bif.lambda)?;
        Some(unwrap_rotation(*record_rotations.get(bif.record)?, raw))
    }
}

/// A rod model whose branches can be followed and switched.
pub trait Followed {
    type System: Problem;
    fn rod(&self) -> &Rod;
    /// The model's system (with the phase condition when given), built
    /// about the state x.
    fn system(&self, phase: Phase, x: &[f64]) -> Result<Self::System>;
    /// Follow a branch from `start`.
    fn follow(&self, start: Start, phase: Phase, opts: &Options, progress: Progress<'_>) -> Result<RodBranch>;
}

/// The plain rod followed by `method`.
pub struct Plain<'a> {
    pub rod: &'a Rod,
    pub method: Method,
}

impl Followed for Plain<'_> {
    type System = AssembledSystem;

    fn rod(&self) -> &Rod {
        self.rod
    }

    fn system(&self, phase: Phase, _x: &[f64]) -> Result<AssembledSystem> {
        match phase {
            Some((node, azimuth)) => self.rod.system_with_phase(node, azimuth),
            None => self.rod.system(),
        }
    }

    fn follow(&self, start: Start, phase: Phase, opts: &Options, progress: Progress<'_>) -> Result<RodBranch> {
        let rod = self.rod;
        let mut sys = self.system(phase, &[])?;
        let opts = &options_for(opts, &sys);
        let observe = |x: &[f64], _: f64| x.to_vec();
        let b = match self.method {
            Method::Anm(a) => continue_anm(&mut sys, start, opts, &a, observe, progress)?,
            Method::Newton => continue_newton(&mut sys, start, opts, observe, progress)?,
        };
        let mut branch = RodBranch::from_engine(b, phase, 0);
        branch.contact = rod.diameter.and_then(|d| {
            branch.states.iter().enumerate().find_map(|(k, x)| {
                let (distance, s1, s2) = rod.closest_approach(x)?;
                (distance < d).then_some(Contact { record: k, distance, s1, s2 })
            })
        });
        Ok(branch)
    }
}

/// The options for the system followed: a caller's scaling is for the
/// rod's n unknowns; with a phase condition the unfolding parameter μ is
/// appended with its own scale.
pub(crate) fn options_for<P: Problem + ?Sized>(opts: &Options, sys: &P) -> Options {
    match &opts.scaling {
        Some(s) if s.x.len() + 1 == sys.dim() => {
            let mut x = s.x.clone();
            x.push(*sys.unknown_scales().0.last().expect("a phase system has μ"));
            Options { scaling: Some(Scaling { x, lambda: s.lambda }), ..opts.clone() }
        }
        _ => opts.clone(),
    }
}

/// Leave `branch` of `model` at its bifurcation `index` along null
/// direction `direction` (first step `first_step`). At a double point of
/// a symmetric rod, on a branch followed without a phase condition, the
/// new branch is followed with one: the node of largest deflection in that
/// direction (the tip of a cantilever, the middle node otherwise) keeps no
/// displacement across the direction's azimuth, and the first point is
/// taken at a fixed buckle amplitude ([`Rod::amplitude_start`]); the
/// branch is refused if it slid onto the spurious straight family
/// ([`Rod::check_unfolding`]). Otherwise the start is the bifurcation
/// point itself, left along the direction (a switch start).
pub fn switch<M: Followed + ?Sized>(
    model: &M,
    branch: &RodBranch,
    index: usize,
    direction: usize,
    first_step: f64,
    opts: &Options,
    progress: Progress<'_>,
) -> Result<RodBranch> {
    let rod = model.rod();
    let bif = branch.bifurcations.get(index).ok_or_else(|| {
        Error::new(
            Status::ErrOutOfRange,
            format!(
                "argument `index` out of range: must lie in [0, {}) (the branch has {} bifurcations; got {index})",
                branch.bifurcations.len(),
                branch.bifurcations.len()
            ),
        )
    })?;
    let (nx, nl) = bif.null_vectors.get(direction).ok_or_else(|| {
        Error::new(
            Status::ErrOutOfRange,
            format!(
                "argument `direction` out of range: must lie in [0, {}) (the point's null directions; got {direction})",
                bif.null_vectors.len()
            ),
        )
    })?;
    error::positive("first_step", first_step)?;
    let double = branch.phase.is_none() && bif.multiplicity >= 2;
    let (phase, bif, direction) = if double {
        // The unfolding parameter μ, zero at the point and along the direction.
        let mut aug = bif.clone();
        aug.x.push(0.0);
        aug.tangent_x.push(0.0);
        let mut d = nx.clone();
        d.push(0.0);
        (Some(rod.phase_for(nx)?), aug, d)
    } else {
        (branch.phase, bif.clone(), nx.clone())
    };
    let mut sys = model.system(phase, &bif.x)?;
    validate(&sys, &Options { scaling: None, ..opts.clone() })?;
    let opts = &options_for(opts, &sys);
    let scaling = opts.scaling.clone().unwrap_or_else(|| Scaling::of(&sys));
    let start = branch_start(&bif, (&direction, *nl), first_step, &scaling);
    let Some(phase_condition) = phase.filter(|_| double) else {
        return model.follow(Start::Switch(start), phase, opts, progress);
    };
    let mu_scale = sys.unknown_scales().0.last().copied().unwrap_or(1.0);
    let mut counts = Counts::default();
    let resume = rod.amplitude_start(&mut sys, scaling, &start, phase_condition, opts, &mut counts)?;
    let mut b = model.follow(Start::Resume(resume), phase, opts, progress)?;
    b.counts.add(&counts);
    rod.check_unfolding(&b.states, mu_scale, opts.unfolding_moment)?;
    Ok(b)
}

impl Rod {
    /// A branch from the state `x0` at `lambda0` (None: the straight state),
    /// leaving towards increasing Λ when `increasing`.
    pub fn continue_branch(
        &self,
        x0: Option<&[f64]>,
        lambda0: f64,
        increasing: bool,
        opts: &Options,
        method: Method,
        mut progress: impl FnMut(&Record) -> bool,
    ) -> Result<RodBranch> {
        error::finite("lambda0", lambda0)?;
        let x = match x0 {
            Some(x) => {
                error::dimension("state length", x.len() as i64, self.unknowns() as i64, self.unknowns() as i64)?;
                error::finite_result("x0", x)?;
                x.to_vec()
            }
            None => self.straight_state(),
        };
        let start = Start::Point { x, lambda: lambda0, increasing };
        Plain { rod: self, method }.follow(start, None, opts, &mut progress)
    }

    /// Continue `branch` from where it stopped (same phase condition).
    pub fn resume_branch(
        &self,
        branch: &RodBranch,
        opts: &Options,
        method: Method,
        mut progress: impl FnMut(&Record) -> bool,
    ) -> Result<RodBranch> {
        Plain { rod: self, method }.follow(Start::Resume(branch.resume.clone()), branch.phase, opts, &mut progress)
    }

    /// Leave `branch` at its bifurcation `index` along null direction
    /// `direction` ([`switch`]).
    // The public entry point: the switch's independent inputs (branch,
    // point, direction, first step, options, engine, callback), as the tests
    // and the C boundary call it.
    #[allow(clippy::too_many_arguments)]
    pub fn switch_branch(
        &self,
        branch: &RodBranch,
        index: usize,
        direction: usize,
        first_step: f64,
        opts: &Options,
        method: Method,
        mut progress: impl FnMut(&Record) -> bool,
    ) -> Result<RodBranch> {
        switch(&Plain { rod: self, method }, branch, index, direction, first_step, opts, &mut progress)
    }

    /// The phase condition for leaving a double point along null direction
    /// `nx`: the node where its lateral displacement is largest (the tip of
    /// a cantilever, mid-span between clamps — where the buckle's azimuth
    /// is best determined) and that azimuth.
    pub(crate) fn phase_for(&self, nx: &[f64]) -> Result<(usize, f64)> {
        let lateral = |i: usize| {
            let at = self.node(i);
            nx[at].hypot(nx[at + 1])
        };
        let node = (1..=self.elements).fold(0, |best, i| if lateral(i) > lateral(best) { i } else { best });
        if node == 0 || lateral(node) == 0.0 {
            return Err(Error::new(
                Status::ErrOutOfRange,
                "a phase condition needs a null direction with a lateral displacement (and at least 2 elements)",
            ));
        }
        let at = self.node(node);
        Ok((node, nx[at + 1].atan2(nx[at])))
    }

    /// The first point of a branch switched with a phase condition, taken at
    /// a fixed buckle amplitude instead of the arc length: ⟨X − X_pred, e⟩ =
    /// 0 with e the phase node's displacement along the azimuth, X_pred the
    /// start's step along its direction. Straight states (amplitude 0), where
    /// the unfolding vanishes and μ would be free, are excluded. `problem` is
    /// the rod's system with that phase condition (charged or not); returns
    /// the point with its secant tangent.
    pub(crate) fn amplitude_start<P: Problem + ?Sized>(
        &self,
        problem: &mut P,
        scaling: Scaling,
        start: &Resume,
        (node, azimuth): (usize, f64),
        opts: &Options,
        counts: &mut Counts,
    ) -> Result<Resume> {
        let residual_tol = opts.residual_tol;
        let mut ctx = Context::with_options(problem, scaling, opts)?;
        let mut e = vec![0.0; start.x.len()];
        let at = self.node(node);
        e[at] = azimuth.cos();
        e[at + 1] = azimuth.sin();
        let step = start.step;
        let mut x: Vec<f64> = start.x.iter().zip(&start.tangent_x).map(|(a, t)| a + step * t).collect();
        let mut l = start.lambda + step * start.tangent_lambda;
        let anchor = x.clone();
        let plane = Plane::new((&anchor, l), (&e, 0.0));
        let result = correct(problem, &mut ctx, &mut x, &mut l, plane, residual_tol, Reuse::No);
        counts.add(&ctx.counts);
        result?;
        let dx: Vec<f64> = x.iter().zip(&start.x).map(|(a, b)| a - b).collect();
        let norm = ctx.scaling.norm(&dx, l - start.lambda);
        Ok(Resume {
            tangent_x: dx.iter().map(|v| v / norm).collect(),
            tangent_lambda: (l - start.lambda) / norm,
            x,
            lambda: l,
            step,
            previous: None,
            modes: None,
        })
    }

    /// μ = 0 on every tilted solution, but the unfolding vanishes on the
    /// straight branch, where (straight state, any μ) also solves the
    /// augmented system: a corrector can slide onto that spurious family
    /// (seen with twist–stretch coupling). Refuse such a branch
    /// ([`Rod::off_branch`] at each state, from the state before it; with
    /// `moment_tol` None, μ — the entry after the rod's unknowns — beyond
    /// 1e-6 of its scale).
    pub(crate) fn check_unfolding(&self, states: &[Vec<f64>], mu_scale: f64, moment_tol: Option<f64>) -> Result<()> {
        let n = self.unknowns();
        let off = |k: usize, x: &Vec<f64>| {
            let previous = if k == 0 { 0.0 } else { states[k - 1][n] };
            self.off_branch(x, previous, mu_scale, moment_tol)
        };
        if let Some((k, x)) = states.iter().enumerate().find(|(k, x)| off(*k, x)) {
            return Err(Error::new(
                Status::ErrNotConverged,
                format!(
                    "branch switching with a phase condition left the unfolding parameter at μ = {:e} (point {k}): {}; try another first_step",
                    x[n],
                    self.unfolding_failure(x)
                ),
            ));
        }
        Ok(())
    }

    /// Whether state `x` of a branch with a phase condition has μ beyond
    /// 1e-6 of its scale: the strict check of [`Rod::check_unfolding`] and
    /// of the charged branch's per-point check, and where
    /// [`Rod::off_branch`]'s tolerance starts to matter.
    pub(crate) fn left_unfolding(&self, x: &[f64], mu_scale: f64) -> bool {
        x[self.unknowns()].abs() > 1e-6 * mu_scale
    }

    /// The unfolding couple's whole moment on state `x` of a branch with a
    /// phase condition: |μ| ∫|B| ds (B = Rᵀe3 − e3 at the stage points,
    /// the stage quadrature), in the rod's moment units. The augmented
    /// state solves the rod's equations with the extra couple density μB,
    /// so this bounds how far the point's moments are from those of a
    /// state without it.
    pub fn unfolding_moment(&self, x: &[f64]) -> f64 {
        match self.tilts(x).1 {
            integral if integral.is_finite() => x[self.unknowns()].abs() * integral,
            _ => f64::INFINITY,
        }
    }

    /// Whether state `x` of a charged branch with a phase condition left
    /// it, `previous_mu` the unfolding parameter of the branch's point
    /// before it. With `moment_tol` None as [`Rod::left_unfolding`]. With
    /// it, μ beyond 1e-6 of its scale is allowed on a tilted state that
    /// (a) carries an unfolding moment ([`Rod::unfolding_moment`]) within
    /// the tolerance and (b) has not jumped there: |μ| at most 10× the
    /// point before's (or 1e-7 of the scale, if that is larger). On the
    /// followed branch μ is the scheme's violation of the axial-moment
    /// integral, which grows smoothly with the plectoneme (1 kbp, 1 pN,
    /// 0.1 M at 170 × Gauss(2): from ~1e-15 to 1e-7 pN at 10 turns, a
    /// moment of 6.8e-5 pN nm against a torque of 9 pN nm, where the
    /// strict check ended the run). A corrector that lands on one of the
    /// discretised equations' own solutions with μ ≠ 0 makes μ jump (300
    /// bp, 2 pN, 0.1 M, aim 5: ×1000 in one step, a moment of 1e-4 pN nm,
    /// and a branch of them that strays 5e-3 L in extension from the
    /// reference path within a moment of 6e-4 pN nm: the moment alone
    /// does not see it; tests/supercoil_hard_core.rs). A straight state
    /// (largest tilt below 1e-3: μB vanishes, the spurious straight
    /// family) keeps the strict check.
    pub(crate) fn off_branch(&self, x: &[f64], previous_mu: f64, mu_scale: f64, moment_tol: Option<f64>) -> bool {
        if !self.left_unfolding(x, mu_scale) {
            return false;
        }
        let Some(tol) = moment_tol else { return true };
        let mu = x[self.unknowns()].abs();
        let (largest, integral) = self.tilts(x);
        largest < 1e-3 || !(mu * integral <= tol) || !(mu <= 10.0 * previous_mu.abs().max(1e-7 * mu_scale))
    }

    /// The section tilt |B| = |Rᵀe3 − e3| over the stage points of state
    /// x, in one pass: its largest value and its integral ∫|B| ds by the
    /// stage quadrature (h_e b_j). A scheme without stages (the midpoint
    /// rule) has neither: (0, ∞), so that no moment bound is met.
    fn tilts(&self, x: &[f64]) -> (f64, f64) {
        let Scheme::Gauss(s) = self.scheme else { return (0.0, f64::INFINITY) };
        let b = self.tableau().b;
        let (mut largest, mut integral) = (0.0f64, 0.0);
        for e in 0..self.elements {
            let h = self.element_h(e);
            for (j, w) in b.iter().enumerate().take(s) {
                let o = self.stage_offset(e, j);
                let v = crate::rod::kinematics::unfolding_direction(&[x[o + 3], x[o + 4], x[o + 5], x[o + 6]]);
                let tilt = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                largest = largest.max(tilt);
                integral += h * w * tilt;
            }
        }
        (largest, integral)
    }

    /// Why a state of a branch with a phase condition left μ = 0, for the
    /// error that ends it. The unfolding's couple μB (B = Rᵀe3 − e3, the
    /// section's tilt from the axis) vanishes on a straight state, so there
    /// (largest |B| below 1e-3) the corrector slid onto the spurious
    /// straight family. A tilted state with μ ≠ 0 is no solution of the
    /// undiscretised problem (μ∫|B|² = J(L) − J(0) = 0), but the
    /// discretised one has such solutions, μ∫|B|² being the scheme's
    /// violation of the first integral J: measured on the 300 bp, 2 pN,
    /// 0.1 M scene with corrector aim 5 (largest |B| 1.58 at μ/scale
    /// 3.3e-6, a step that landed on one; retaken with half the step, the
    /// branch goes on with μ/scale ≤ 3.3e-9) and on 1 kbp, 1 pN, 0.1 M with
    /// 80 elements of Gauss(4) (μ growing from ~1e-15 to 1e-7 pN over 55
    /// points past 2.84 turns, not cured by retakes: a branch of them met
    /// the followed one; 100 elements of Gauss(2) or Gauss(3) stay below
    /// 1e-10 pN; benches/README.md).
    pub(crate) fn unfolding_failure(&self, x: &[f64]) -> String {
        let tilt = self.tilts(x).0;
        if tilt < 1e-3 {
            format!(
                "the corrector slid onto the spurious straight family (a straight state: largest section tilt |Rᵀe3 − e3| {tilt:.1e}; any μ solves it)"
            )
        } else {
            format!(
                "the state is not straight (largest section tilt |Rᵀe3 − e3| {tilt:.2}; the unfolding couple's moment μ∫|Rᵀe3 − e3| = {:.3e}): a solution of the discretised equations that the undiscretised ones do not have (μ∫|Rᵀe3 − e3|² is the scheme's violation of the axial-moment integral), reached by a jump of μ from the point before or carrying more moment than the tolerance allows; other elements or stages, or a shorter step, may keep the branch",
                self.unfolding_moment(x)
            )
        }
    }
}

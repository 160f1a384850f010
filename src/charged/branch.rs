//! Branches of charged-rod equilibria: Newton pseudo-arc-length
//! continuation of [`ChargedRod`] — in the end rotation φ itself for a rod
//! with a controlled end rotation (any number of turns), or in the end
//! torque for a torque clamp ([`super::dna::EndControl`]) — with the pair
//! list rebuilt whenever a stage has moved half the skin (the
//! branch is continued from the same point and tangent on the new
//! pattern), strand crossing detected (non-neighbouring stage points
//! closer than 2a: the branch stops with [`ChargedBranch::crossing`]), and
//! branch switching at a located (double) buckling point with the rod's
//! phase condition. The DNA scene that runs them: [`super::dna`].

use super::rod::{ChargedRod, RodCharge};
use crate::continuation::bifurcation::{branch_start, Bifurcation};
use crate::continuation::corrector::correct;
use crate::continuation::newton::{continue_newton, Start};
use crate::continuation::tangent::Bordered;
use crate::continuation::{Counts, Options, Problem, Record, Resume, Scaling, Stop};
use crate::error::{self, Error, Result};
use crate::geometry::proximity::closest_pair_within;
use crate::rod::branch::Contact;
use crate::rod::model::Rod;
use crate::status::Status;

/// A followed branch of a charged rod.
#[derive(Clone, Debug)]
pub struct ChargedBranch {
    /// Records (Λ = φ for rotation-controlled rods); outputs moved to `states`.
    pub records: Vec<Record>,
    pub states: Vec<Vec<f64>>,
    pub bifurcations: Vec<Bifurcation>,
    pub stop: Stop,
    /// Strand crossing: the first record where non-neighbouring stage
    /// points (arc-length gap > πa) came closer than 2a; the branch stops
    /// there (`stop` = Cancelled).
    pub crossing: Option<Contact>,
    pub counts: Counts,
    pub resume: Resume,
    pub phase: Option<(usize, f64)>,
    /// Pair lists built (1 + rebuilds).
    pub pair_lists: usize,
}

/// Stage-point positions and arc lengths of a state.
fn stage_points(rod: &Rod, x: &[f64]) -> (Vec<[f64; 3]>, Vec<f64>) {
    let h = rod.element_length();
    let tab = crate::rod::scheme::Tableau::gauss(rod.scheme.stages().max(1));
    let mut r = Vec::new();
    let mut s = Vec::new();
    for e in 0..rod.elements {
        for j in 0..rod.scheme.stages() {
            let o = rod.node(e) + 13 * (1 + j);
            r.push([x[o], x[o + 1], x[o + 2]]);
            s.push((e as f64 + tab.c[j]) * h);
        }
    }
    (r, s)
}

/// The closest non-neighbouring pair of stage points nearer than 2a:
/// (distance, s1, s2).
pub fn strand_crossing(rod: &Rod, charge: &RodCharge, x: &[f64]) -> Option<(f64, f64, f64)> {
    let a = charge.screening.a;
    let (r, s) = stage_points(rod, x);
    closest_pair_within(&r, &s, 2.0 * a, std::f64::consts::PI * a).map(|(d, i, j)| (d, s[i], s[j]))
}

fn start_x(start: &Start) -> &[f64] {
    match start {
        Start::Point { x, .. } => x,
        Start::Resume(r) | Start::Switch(r) => &r.x,
    }
}

/// Follow a branch of the charged rod from `start` (with the rod's phase
/// condition when given), rebuilding the pair list as the shape moves.
pub fn follow(
    rod: &Rod,
    charge: &RodCharge,
    start: Start,
    phase: Option<(usize, f64)>,
    opts: &Options,
    mut progress: impl FnMut(&Record) -> bool,
) -> Result<ChargedBranch> {
    let mut start = start;
    let mut out = ChargedBranch {
        records: Vec::new(),
        states: Vec::new(),
        bifurcations: Vec::new(),
        stop: Stop::MaxSteps,
        crossing: None,
        counts: Counts::default(),
        resume: Resume { x: Vec::new(), lambda: 0.0, tangent_x: Vec::new(), tangent_lambda: 0.0, step: 0.0 },
        phase,
        pair_lists: 0,
    };
    let half_skin = 0.5 * charge.skin;
    loop {
        let mut problem = ChargedRod::new(rod, charge, phase, start_x(&start))?;
        out.pair_lists += 1;
        if let Start::Resume(r) = &mut start {
            // A point reached on the previous list: re-converge it on the
            // new one when a pair it lacked matters (moved past skin/2).
            let mut res = vec![0.0; r.x.len()];
            problem.residual(&r.x, r.lambda, &mut res);
            let eq = problem.equation_scales();
            let scaled = res.iter().zip(&eq).map(|(v, e)| (v / e).abs()).fold(0.0, f64::max);
            if !(scaled <= opts.residual_tol) {
                let scaling = opts.scaling.clone().unwrap_or_else(|| Scaling::of(&problem));
                let mut bordered = Bordered::new(problem.pattern())?;
                let anchor = r.x.clone();
                let mut l = r.lambda;
                let fix = vec![0.0; r.x.len()];
                correct(
                    &mut problem,
                    &mut bordered,
                    &scaling,
                    &eq,
                    &mut r.x,
                    &mut l,
                    (&anchor, r.lambda),
                    (&fix, 1.0),
                    opts.residual_tol,
                    false,
                    &mut out.counts,
                )?;
                if let (Some(rec), Some(st)) = (out.records.last_mut(), out.states.last_mut()) {
                    st.copy_from_slice(&r.x);
                    rec.residual = opts.residual_tol;
                }
            }
        }
        let reference: Vec<[f64; 3]> = {
            let (r, _) = stage_points(rod, start_x(&start));
            r
        };
        let offsets: Vec<usize> =
            (0..rod.elements).flat_map(|e| (0..rod.scheme.stages()).map(move |j| rod.node(e) + 13 * (1 + j))).collect();
        let moved = |x: &[f64]| -> f64 {
            offsets
                .iter()
                .zip(&reference)
                .map(|(&o, r0)| {
                    ((x[o] - r0[0]).powi(2) + (x[o + 1] - r0[1]).powi(2) + (x[o + 2] - r0[2]).powi(2)).sqrt()
                })
                .fold(0.0, f64::max)
        };
        let local = problem.list_is_local();
        let mut stale = false;
        let mut crossing: Option<Contact> = None;
        let base = out.records.len();
        let mut seg_opts = opts.clone();
        seg_opts.max_steps = opts.max_steps.saturating_sub(out.counts.steps).max(1);
        let mut index = 0;
        let resumed = base > 0;
        let b = continue_newton(
            &mut problem,
            start,
            &seg_opts,
            |x, _| {
                let mut o = x.to_vec();
                o.push(moved(x));
                o
            },
            |rec| {
                let x = &rec.outputs[..rec.outputs.len() - 1];
                let k = index;
                index += 1;
                if resumed && k == 0 {
                    // The previous segment's last point, already checked.
                    return true;
                }
                if let Some((distance, s1, s2)) = strand_crossing(rod, charge, x) {
                    crossing = Some(Contact { record: base + k - resumed as usize, distance, s1, s2 });
                    return false;
                }
                if local && *rec.outputs.last().expect("displacement") > half_skin {
                    stale = true;
                    return false;
                }
                progress(rec)
            },
        )?;
        out.counts.add(&b.counts);
        for (i, mut rec) in b.records.into_iter().enumerate() {
            if resumed && i == 0 {
                // The resumed start point, already recorded.
                continue;
            }
            let mut x = std::mem::take(&mut rec.outputs);
            x.pop();
            out.states.push(x);
            out.records.push(rec);
        }
        out.bifurcations.extend(b.bifurcations);
        out.resume = b.resume;
        out.stop = b.stop;
        if let Some(c) = crossing {
            out.crossing = Some(c);
            break;
        }
        if stale && out.counts.steps < opts.max_steps {
            start = Start::Resume(out.resume.clone());
            continue;
        }
        break;
    }
    Ok(out)
}

/// Leave `branch` at its bifurcation `index` along null direction
/// `direction` (first step `first_step`): at a double point of the
/// symmetric rod (the buckling of a twisted rod under tension) with the
/// rod's phase condition at the node of largest lateral displacement of
/// the null direction, the first point taken at a fixed buckle amplitude.
pub fn switch(
    rod: &Rod,
    charge: &RodCharge,
    branch: &ChargedBranch,
    index: usize,
    direction: usize,
    first_step: f64,
    opts: &Options,
    progress: impl FnMut(&Record) -> bool,
) -> Result<ChargedBranch> {
    let bif = branch.bifurcations.get(index).ok_or_else(|| {
        Error::new(
            Status::ErrOutOfRange,
            format!("bifurcation index {index} out of range (the branch has {})", branch.bifurcations.len()),
        )
    })?;
    let (nx, nl) = bif.null_vectors.get(direction).ok_or_else(|| {
        Error::new(
            Status::ErrOutOfRange,
            format!("direction {direction} out of range (the point has {} null directions)", bif.null_vectors.len()),
        )
    })?;
    error::positive("first_step", first_step)?;
    if branch.phase.is_some() || bif.multiplicity < 2 {
        let scaling = opts.scaling.clone().unwrap_or_else(|| {
            let p = ChargedRod::new(rod, charge, branch.phase, &bif.x).expect("validated on the branch");
            Scaling::of(&p)
        });
        let start = branch_start(bif, (nx, *nl), first_step, &scaling);
        return follow(rod, charge, Start::Switch(start), branch.phase, opts, progress);
    }
    let phase = Some(rod.phase_for(nx)?);
    let mut aug = bif.clone();
    aug.x.push(0.0);
    aug.tangent_x.push(0.0);
    let mut d = nx.clone();
    d.push(0.0);
    let mut problem = ChargedRod::new(rod, charge, phase, &aug.x)?;
    let (sx, sl) = problem.unknown_scales();
    let scaling = Scaling { x: sx, lambda: sl };
    let start = branch_start(&aug, (&d, *nl), first_step, &scaling);
    let mut counts = Counts::default();
    let resume = rod.amplitude_start(
        &mut problem,
        &scaling,
        &start,
        phase.expect("set above"),
        first_step,
        opts.residual_tol,
        &mut counts,
    )?;
    let mut b = follow(rod, charge, Start::Resume(resume), phase, opts, progress)?;
    b.counts.add(&counts);
    rod.check_unfolding(&b.states, problem.unknown_scales().0[rod.unknowns()])?;
    Ok(b)
}

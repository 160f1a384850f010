//! A branch that ends exactly at a given end rotation φ: under
//! rotation control Λ = sin(φ/2) takes every value again each turn, so a
//! target Λ cannot say "stop at φ = 25"; a torque clamp's φ is an output.
//!
//! The branch is followed as asked, its records' φ tracked by continuity
//! (a step turns the end by less than 2π); the first record past the
//! target ends it, and that record is replaced by the point where φ equals
//! the target. That point is found by Newton on the branch's equations
//! with one coordinate of (cos φ/2, sin φ/2) fixed — both are unknowns or
//! Λ, so the condition is a hyperplane, the corrector's own border: the
//! cosine where |sin φ/2| ≥ |cos φ/2| (there the cosine moves fastest
//! along the branch), else the sine (Λ under rotation control, the clamp's
//! s under a torque clamp). The predictor between the two records picks
//! the right one of the two points sharing that coordinate.

use super::branch::{Followed, RodBranch};
use super::model::{unwrap_rotation, Rod};
use crate::continuation::corrector::{correct, Plane, Reuse};
use crate::continuation::run::{Context, Factors};
use crate::continuation::{Record, Resume, Scaling, Stop};
use crate::error::{self, Error, Result};
use crate::linalg::dense::sub;
use crate::rod::branch::Progress;
use crate::status::Status;

/// Follow a branch of `model` with `follow` (handed the progress closure
/// to pass to the engine) and end it where the end rotation reaches
/// `target` (radians, continuous: `start_phi` is the φ of the point the
/// branch leaves, None for φ taken from its first state as it is — a
/// branch from the straight state). `progress` is told every record kept;
/// a stop it asks for ends the branch there (Cancelled) as usual. The
/// branch stops with [`Stop::Target`] on the located point; a branch that
/// ends before (its own target Λ, range, step limit) is returned as it
/// ended. Refused for a rod without end rotation.
pub fn until_rotation<M: Followed + ?Sized>(
    model: &M,
    target: f64,
    start_phi: Option<f64>,
    progress: Progress<'_>,
    follow: impl FnOnce(&mut dyn FnMut(&Record) -> bool) -> Result<RodBranch>,
) -> Result<RodBranch> {
    let rod = model.rod();
    error::finite("target rotation", target)?;
    if !(rod.twisted() || rod.torqued()) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            "a target end rotation needs a rod with end rotation control or a torque clamp (Supports::Twisted, TwistedAtDistance or Torqued)",
        ));
    }
    // φ by continuity along the records: the side of the target the branch
    // starts on, and whether the last record crossed it.
    let mut phi = start_phi;
    let mut side = None;
    let mut crossed = false;
    let mut user_stopped = false;
    let mut watch = |r: &Record| -> bool {
        let raw = rod.end_rotation(&r.outputs, r.lambda).expect("a rod with end rotation");
        let now = phi.map_or(raw, |p| unwrap_rotation(p, raw));
        phi = Some(now);
        let here = (now - target).signum();
        let start_side = *side.get_or_insert(here);
        if now == target || here != start_side {
            crossed = true;
            return false;
        }
        let go_on = progress(r);
        user_stopped |= !go_on;
        go_on
    };
    let mut branch = follow(&mut watch)?;
    if !crossed || user_stopped {
        return Ok(branch);
    }
    let (phis, _) = branch.end_rotations(rod, start_phi);
    let k = branch.records.len() - 1;
    if k == 0 || phis[k] == target {
        branch.stop = Stop::Target;
        return Ok(branch);
    }
    land(model, &mut branch, target, (phis[k - 1], phis[k]))?;
    // What lay past the target in the last step goes.
    let (phis, samples) = branch.end_rotations(rod, start_phi);
    let past = |p: f64| (p - target) * (phis[0] - target) < 0.0;
    let keep: Vec<bool> = samples.iter().map(|&p| !past(p)).collect();
    let mut it = keep.iter();
    branch.samples.retain(|_| *it.next().unwrap());
    let mut it = keep.iter();
    branch.sample_states.retain(|_| *it.next().unwrap());
    let bif_phi: Vec<Option<f64>> =
        (0..branch.bifurcations.len()).map(|i| branch.rotation_at_bifurcation(rod, i, &phis)).collect();
    let mut it = bif_phi.iter();
    branch.bifurcations.retain(|_| !it.next().unwrap().is_some_and(past));
    if branch.contact.is_some_and(|c| c.record == k) {
        branch.contact = None;
    }
    branch.stop = Stop::Target;
    // The caller is told the point it ends on (its state as the outputs,
    // as the engines' records carry it); it is the last either way.
    let told = Record { outputs: branch.states[k].clone(), ..branch.records[k].clone() };
    progress(&told);
    Ok(branch)
}

/// Replace the last record of `branch` (the first past `target`; `phis`:
/// the φ of it and of the record before) by the point at φ = `target`.
fn land<M: Followed + ?Sized>(model: &M, branch: &mut RodBranch, target: f64, phis: (f64, f64)) -> Result<()> {
    let rod = model.rod();
    let k = branch.records.len() - 1;
    let (xa, xb) = (&branch.states[k - 1], &branch.states[k]);
    let (la, lb) = (branch.records[k - 1].lambda, branch.records[k].lambda);
    let mut sys = model.system(branch.phase, xb)?;
    let mut ctx = Context::new(&sys, Scaling::of(&sys))?;
    // The predictor: the records' secant at the target's fraction of φ.
    let s = (target - phis.0) / (phis.1 - phis.0);
    let mut x: Vec<f64> = xa.iter().zip(xb).map(|(a, b)| a + s * (b - a)).collect();
    let mut lambda = la + s * (lb - la);
    let (sin, cos) = (0.5 * target).sin_cos();
    let (cos_at, sin_at) = angle_coordinates(rod);
    let mut normal = vec![0.0; x.len()];
    let mut normal_lambda = 0.0;
    if sin.abs() >= cos.abs() {
        x[cos_at] = cos;
        normal[cos_at] = 1.0;
    } else {
        match sin_at {
            Some(i) => {
                x[i] = sin;
                normal[i] = 1.0;
            }
            None => {
                lambda = sin;
                normal_lambda = 1.0;
            }
        }
    }
    let anchor = x.clone();
    let plane = Plane::new((&anchor, lambda), (&normal, normal_lambda));
    let residual_tol = branch.records[k].residual.max(1e-12);
    let (iterations, residual) =
        correct(&mut sys, &mut ctx, &mut x, &mut lambda, plane, residual_tol.max(1e-10), Reuse::No).map_err(|e| {
            Error::new(
                e.status,
                format!("the point at end rotation {target} (between records {} and {k}): {}", k - 1, e.message),
            )
        })?;
    // The record's signs and test function from the point's factorisation,
    // bordered by the branch's direction there.
    let dx: Vec<f64> = xb.iter().zip(xa).map(|(b, a)| b - a).collect();
    let dl = lb - la;
    ctx.factorise(&mut sys, &x, lambda, (&dx, dl), Factors::Exact)?;
    let (mut tx, mut tl) = ctx.tangent()?;
    if ctx.scaling.dot(&tx, tl, &dx, dl) < 0.0 {
        tx.iter_mut().for_each(|v| *v = -*v);
        tl = -tl;
    }
    let (bordered_det_sign, det_sign) = ctx.bordered.determinant_signs(&ctx.scaling, &tx, tl);
    let old = &branch.records[k];
    let smallest_singular_value =
        old.smallest_singular_value.map(|_| ctx.bordered.signed_smallest_singular_value(false, &mut ctx.counts));
    let step = ctx.scaling.norm(&sub(&x, xa), lambda - la);
    let record = Record {
        lambda,
        outputs: vec![],
        residual,
        step,
        det_sign,
        bordered_det_sign,
        smallest_singular_value,
        negative_pivots: None,
        newton_iterations: iterations,
        series_residual: None,
        stability: None,
    };
    branch.resume =
        Resume { x: x.clone(), lambda, tangent_x: tx, tangent_lambda: tl, step, previous: None, modes: None };
    branch.records[k] = record;
    branch.states[k] = x;
    branch.counts.add(&ctx.counts);
    Ok(())
}

/// The offsets of cos(φ/2) and, under a torque clamp, sin(φ/2) in the
/// state (rotation control: sin(φ/2) is Λ).
fn angle_coordinates(rod: &Rod) -> (usize, Option<usize>) {
    match (rod.end_angle(), rod.end_cosine()) {
        (Some((c, s)), _) => (c, Some(s)),
        (None, Some(c)) => (c, None),
        (None, None) => unreachable!("checked: the rod has end rotation"),
    }
}

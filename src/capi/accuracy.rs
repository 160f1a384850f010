//! Rod branches to a requested accuracy through the C ABI: the
//! library chooses the elements and reports each record's error estimate
//! (see [`crate::rod::accuracy`]).

use super::args::{arg_mut, arg_ref, clear_handle, copy_out};
use super::branch::{options_of, same_rod, with_progress, wrap, Branch, BranchCallback};
use super::guard;
use super::rod::{store_rod, Rod};
use crate::error;
use crate::rod::accuracy::{
    estimate_bifurcation_errors, estimate_errors, kirchhoff_differences, refine_until, RecordError as Estimate,
};
use crate::rod::branch::Plain;
use crate::rod::target::until_rotation;
use std::ffi::c_void;

/// A record's estimated discretisation error (rodkit_branch_error_estimates):
/// the difference from the same point re-solved on half the elements
/// (neighbours merged in pairs, so a graded mesh is coarsened everywhere),
/// which bounds the record's own error wherever halving the mesh at least
/// doubles it (the scheme's order is 2s on Gauss(s)).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct RecordError {
    /// 1 if estimated; 0 where the re-solve on half the elements failed (a
    /// fold in Λ, a singular point, too coarse a mesh): the fields are then 0.
    pub estimated: i32,
    /// |Δr(L)| (length), the angle between the tip frames (rad), |ΔF(0)|,
    /// |ΔM(0)| (the spatial internal force and moment at s = 0).
    pub tip_position: f64,
    pub tip_rotation: f64,
    pub base_force: f64,
    pub base_moment: f64,
    /// The largest of the four, each relative to the larger of its
    /// magnitude and its scale (L, 1 rad, K_b/L², K_b/L): what a tolerance
    /// is compared with.
    pub scaled: f64,
}

/// A located bifurcation's estimated discretisation error
/// (rodkit_branch_bifurcation_errors): the difference from the same point
/// located again on half the elements.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct BifurcationError {
    /// 1 if estimated; 0 where no point was located on half the elements
    /// between the records around it (the bracket widened twice), or the
    /// one found lay nearer another of the branch's points (close roots
    /// the coarse mesh cannot tell apart): the fields are then 0.
    pub estimated: i32,
    /// |ΔΛ| (the critical load), |Δφ| (the critical end rotation, rad; 0
    /// for a rod without end rotation).
    pub lambda: f64,
    pub end_rotation: f64,
    /// The point's state, as RodkitRecordError's.
    pub tip_position: f64,
    pub tip_rotation: f64,
    pub base_force: f64,
    pub base_moment: f64,
    /// The largest of: the critical value's relative error (φ's, against
    /// at least 1 rad, under rotation control; Λ's otherwise) and the
    /// state's scaled one (as RodkitRecordError.scaled).
    pub scaled: f64,
}

/// Follow the branch from the straight state at `lambda0` (as
/// rodkit_rod_continue with x0 NULL) with the elements chosen by rodkit so
/// that every record's scaled error estimate is ≤ `tolerance` (1e-12 …
/// 0.1): `rod`'s law, loads, supports and scheme, its element count as the
/// first try (uniform), then graded meshes: elements placed where the
/// branch's records vary fast (AUTO-07p's equidistribution of the
/// solution's highest derivative; symmetric about the middle for a rod
/// held at both ends), as many as the last estimate and the scheme's order
/// ask — never more than uniform refinement would take (at most 1024
/// elements: RODKIT_STATUS_ERR_TOLERANCE_UNREACHABLE beyond, with what was
/// reached). `*rod_out` receives the refined rod (free it with
/// rodkit_rod_free; rodkit_rod_node_positions gives the mesh chosen),
/// `*out` the branch, of `*rod_out`;
/// rodkit_branch_error_estimates gives each record's estimate,
/// rodkit_branch_bifurcation_errors each located bifurcation's (with
/// options.detect_bifurcations the critical loads meet the tolerance too).
/// A target end rotation set on `rod` (rodkit_rod_set_target_rotation)
/// ends every refinement's branch there. `progress`
/// is told every refinement's points (counted from 1 for each); a stop it
/// asks for ends the refinement there (RODKIT_STATUS_INFO_CANCELLED, the
/// branch and estimates so far). `options.residual_tol` must not exceed
/// `tolerance`. The estimates are honest but not
/// sharp: in the scheme's asymptotic range they exceed the true error by
/// up to 2^(2s) (256 on Gauss(4)).
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_continue_to_tolerance(
    rod: *const Rod,
    tolerance: f64,
    lambda0: f64,
    options: *const super::continuation::ContinuationOptions,
    progress: BranchCallback,
    user_data: *mut c_void,
    rod_out: *mut *mut Rod,
    out: *mut *mut Branch,
) -> i32 {
    guard(|| {
        clear_handle(out);
        clear_handle(rod_out);
        let rod = arg_ref("rod", rod)?;
        arg_mut("rod_out", rod_out)?;
        arg_mut("out", out)?;
        error::finite("tolerance", tolerance)?;
        error::finite("lambda0", lambda0)?;
        let (opts, method, increasing) = options_of(rod, options)?;
        // Each refinement's points told afresh (its own point count and
        // turns from its start); a stop asked for ends the refinement.
        let acc = refine_until(&rod.model, tolerance, opts.residual_tol, |r| {
            let follow = |cb: &mut dyn FnMut(&crate::continuation::Record) -> bool| {
                r.continue_branch(None, lambda0, increasing, &opts, method, cb)
            };
            with_progress(r, (progress, user_data), None, |cb| match rod.target_rotation {
                Some(target) => until_rotation(&Plain { rod: r, method }, target, None, cb, follow),
                None => follow(cb),
            })
        })?;
        let status = super::branch_record::branch_status(&acc.branch);
        let mut wrapped = wrap(&acc.rod, acc.branch, None);
        wrapped.estimates = Some(acc.estimates);
        wrapped.bifurcation_estimates = Some(acc.bifurcation_estimates);
        store_rod(acc.rod, rod_out)?;
        *out = Box::into_raw(Box::new(wrapped));
        Ok(status)
    })
}

/// Copy one row per record of `b` (its quantities' differences, `values`,
/// and their scaled worst; zeros with `estimated` 0 where there is none)
/// to the caller's (out, capacity, count).
///
/// # Safety
/// `out` must be NULL or hold `capacity` writable rows, `count` NULL or writable.
unsafe fn copy_records(
    rod: &Rod,
    b: &Branch,
    values: &[Option<Estimate>],
    (out, capacity, count): (*mut RecordError, i64, *mut i64),
) -> crate::Result<crate::status::Status> {
    let rows: Vec<(Option<Estimate>, &Vec<f64>)> = values.iter().copied().zip(&b.branch.states).collect();
    copy_out("out", out, capacity, count, &rows, |&(e, x)| match e {
        Some(e) => RecordError {
            estimated: 1,
            tip_position: e.tip_position,
            tip_rotation: e.tip_rotation,
            base_force: e.base_force,
            base_moment: e.base_moment,
            scaled: e.scaled(&rod.model, x),
        },
        None => RecordError::default(),
    })
}

/// The re-solves' tolerance for estimates computed on request: the
/// options' default (a branch does not keep its own).
const RESOLVE_TOL: f64 = 1e-10;

/// The estimates a branch kept (from rodkit_rod_continue_to_tolerance), or
/// computed now.
fn kept_or<T: Clone>(
    kept: &Option<Vec<T>>,
    compute: impl FnOnce() -> crate::Result<Vec<T>>,
) -> crate::Result<std::borrow::Cow<'_, [T]>> {
    Ok(match kept {
        Some(e) => std::borrow::Cow::Borrowed(&e[..]),
        None => std::borrow::Cow::Owned(compute()?),
    })
}

/// Copy up to `capacity` records' error estimates (one per record, in
/// record order); `count` receives the number of records. For a branch
/// from rodkit_rod_continue_to_tolerance they are the ones it met the
/// tolerance with; for any other branch they are computed here (one
/// re-solve per record on half the elements: the rod needs an even
/// element count, else RODKIT_STATUS_ERR_OUT_OF_RANGE).
/// cbindgen:fortran-arrays=[out]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_error_estimates(
    branch: *const Branch,
    rod: *const Rod,
    out: *mut RecordError,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let (rod, b) = same_rod(arg_ref("rod", rod)?, arg_ref("branch", branch)?)?;
        let estimates = kept_or(&b.estimates, || estimate_errors(&rod.model, &b.branch, RESOLVE_TOL))?;
        copy_records(rod, b, &estimates, (out, capacity, count))
    })
}

/// Copy up to `capacity` located bifurcations' error estimates (in the
/// order of rodkit_branch_bifurcation_points); `count` receives the number
/// of points. For a branch from rodkit_rod_continue_to_tolerance they are
/// the ones it met the tolerance with; for any other branch they are
/// computed here (each point located again on half the elements: the rod
/// needs an even element count, else RODKIT_STATUS_ERR_OUT_OF_RANGE).
/// cbindgen:fortran-arrays=[out]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_bifurcation_errors(
    branch: *const Branch,
    rod: *const Rod,
    out: *mut BifurcationError,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let (rod, b) = same_rod(arg_ref("rod", rod)?, arg_ref("branch", branch)?)?;
        let estimates =
            kept_or(&b.bifurcation_estimates, || estimate_bifurcation_errors(&rod.model, &b.branch, RESOLVE_TOL))?;
        let rows: Vec<_> = estimates.iter().copied().zip(&b.branch.bifurcations).collect();
        copy_out("out", out, capacity, count, &rows, |&(e, bif)| match e {
            Some(e) => BifurcationError {
                estimated: 1,
                lambda: e.lambda,
                end_rotation: e.end_rotation,
                tip_position: e.at.tip_position,
                tip_rotation: e.at.tip_rotation,
                base_force: e.at.base_force,
                base_moment: e.at.base_moment,
                scaled: e.scaled(&rod.model, bif),
            },
            None => BifurcationError::default(),
        })
    })
}

/// What extension and shear do to `branch` (of `rod`, a Cosserat rod):
/// every record re-solved at its Λ on the rod's Kirchhoff variant
/// (inextensible, unshearable, same bending and twist, same mesh), and the
/// differences of its quantities copied as RodkitRecordError rows
/// (`estimated` 0 where the Kirchhoff rod has no point at that Λ; `scaled`
/// against the same scales as the estimates: below a tolerance, the
/// simpler physics would meet it). rodkit keeps the branch it computed —
/// the Kirchhoff rod has the same unknowns and cost here. A rod that is
/// already Kirchhoff: RODKIT_STATUS_ERR_OUT_OF_RANGE. `count` receives the
/// number of records.
/// cbindgen:fortran-arrays=[out]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_kirchhoff_differences(
    branch: *const Branch,
    rod: *const Rod,
    out: *mut RecordError,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let (rod, b) = same_rod(arg_ref("rod", rod)?, arg_ref("branch", branch)?)?;
        let differences = kirchhoff_differences(&rod.model, &b.branch, RESOLVE_TOL)?;
        copy_records(rod, b, &differences, (out, capacity, count))
    })
}

//! The branch handle `RodkitBranch` (physics.md §2.3–2.4): continuation of
//! a rod by the ANM or Newton from a state, resumption and branch switching,
//! with a progress callback, and the accessors that copy out its records,
//! samples, bifurcations, states and node positions.

use super::args::{arg_mut, arg_ref, check_len, check_nodes, clear_handle, copy_out, free_handle, in_slice};
use super::args::{out_slice, qualify_argument, write_positions};
use super::branch_record::{
    branch_status, record_lists, stop_code, Bifurcation, BifurcationPoint, BranchInfo, BranchRecord,
    UnresolvedBifurcation,
};
use super::continuation::{options_from, ContinuationOptions};
use super::rod::Rod;
use super::{guard, guard_value};
use crate::continuation::Options;
use crate::continuation::Record;
use crate::error::{self, Error, Result};
use crate::rod::branch::{Method, Plain, RodBranch};
use crate::rod::model::{unwrap_rotation, Rod as Model};
use crate::rod::target::until_rotation;
use crate::status::Status;
use std::ffi::c_void;

/// What the branch progress callback is told after each point.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct BranchProgress {
    /// Points so far (the start is point 1).
    pub points: i64,
    pub lambda: f64,
    pub residual: f64,
    /// Angle (radians) between the tip tangent and e3 at the point.
    pub tip_rotation: f64,
    /// Appended for the supercoiling run (rodkit_dna_supercoil_run_with,
    /// rodkit_supercoil_resume; the fields above keep their place and
    /// meaning: `points` counts the run's points, `lambda` is its
    /// continuation parameter). The path's branch: 0 straight, 1 buckled;
    /// −1 for a rod continuation, which sets `extension` and `torque` NaN,
    /// and `turns` to the end rotation φ/2π under rotation control or a
    /// torque clamp (continuous, as the records' end_rotation: a callback
    /// can stop past a given φ, which Λ = sin(φ/2) cannot say), else NaN.
    pub branch: i32,
    /// End rotation (turns), extension z(L) (nm), end torque M_z(L) (pN nm).
    pub turns: f64,
    pub extension: f64,
    pub torque: f64,
}

/// Branch progress callback: return 0 to continue, non-zero to stop
/// cleanly (the branch so far is returned with RODKIT_STATUS_INFO_CANCELLED).
/// It must not unwind into rodkit (no C++ throw, no longjmp); it may call
/// rodkit functions on other handles.
pub type BranchCallback = Option<unsafe extern "C" fn(progress: *const BranchProgress, user_data: *mut c_void) -> i32>;

/// Opaque branch handle (immutable once returned).
pub struct Branch {
    pub(super) branch: RodBranch,
    pub(super) records: Vec<BranchRecord>,
    pub(super) samples: Vec<BranchRecord>,
    state_length: usize,
    /// The rod it was computed with: a branch handed back with another rod
    /// is refused (its states would be misread).
    model: Model,
    /// Each record's error estimate, when the branch was refined to a
    /// tolerance (rodkit_rod_continue_to_tolerance); else computed on
    /// request.
    pub(super) estimates: Option<Vec<Option<crate::rod::accuracy::RecordError>>>,
    /// Each located bifurcation's, likewise.
    pub(super) bifurcation_estimates: Option<Vec<Option<crate::rod::accuracy::BifurcationError>>>,
}

/// Run `f` with a Rust progress closure forwarding to the C callback.
/// `start_phi`: the continuous end rotation of the point a resumed or
/// switched branch leaves (its `turns` continue from there).
pub(super) unsafe fn with_progress<T>(
    model: &Model,
    (cb, user_data): (BranchCallback, *mut c_void),
    start_phi: Option<f64>,
    f: impl FnOnce(&mut dyn FnMut(&Record) -> bool) -> Result<T>,
) -> Result<T> {
    let mut points = 0i64;
    let mut phi = start_phi;
    let mut forward = |r: &Record| -> bool {
        points += 1;
        match cb {
            Some(cb) => {
                // The branch's records carry the state as their outputs.
                let state = (r.outputs.len() >= model.unknowns()).then_some(&r.outputs[..]);
                let tip_rotation = state.map_or(f64::NAN, |x| model.tip_rotation(x));
                // The end rotation, followed by continuity as the records'
                // (a step turns the end by less than 2π).
                let turns = match state.and_then(|x| model.end_rotation(x, r.lambda)) {
                    Some(raw) => {
                        let now = phi.map_or(raw, |p| unwrap_rotation(p, raw));
                        phi = Some(now);
                        now / (2.0 * std::f64::consts::PI)
                    }
                    None => f64::NAN,
                };
                let nan = f64::NAN;
                let p = BranchProgress {
                    points,
                    lambda: r.lambda,
                    residual: r.residual,
                    tip_rotation,
                    branch: -1,
                    turns,
                    extension: nan,
                    torque: nan,
                };
                cb(&p, user_data) == 0
            }
            None => true,
        }
    };
    f(&mut forward)
}

/// Follow a branch of `rod` with `f` (handed the engine's progress
/// closure), forwarding progress to C as [`with_progress`], and ending it
/// at the rod handle's target end rotation when one is set
/// (rodkit_rod_set_target_rotation; `start_phi` as for `with_progress`).
pub(super) unsafe fn follow_rod(
    rod: &Rod,
    method: Method,
    callback: (BranchCallback, *mut c_void),
    start_phi: Option<f64>,
    f: impl FnOnce(&mut dyn FnMut(&Record) -> bool) -> Result<RodBranch>,
) -> Result<RodBranch> {
    with_progress(&rod.model, callback, start_phi, |cb| match rod.target_rotation {
        Some(target) => until_rotation(&Plain { rod: &rod.model, method }, target, start_phi, cb, f),
        None => f(cb),
    })
}

/// The branch for C (`previous` as for [`record_lists`]).
pub(super) fn wrap(model: &Model, branch: RodBranch, previous: Option<f64>) -> Branch {
    let (records, samples) = record_lists(model, &branch, previous);
    let state_length = model.unknowns() + branch.phase.is_some() as usize;
    Branch {
        branch,
        records,
        samples,
        state_length,
        model: model.clone(),
        estimates: None,
        bifurcation_estimates: None,
    }
}

/// The rod and its branch, the branch checked to belong to the rod.
pub(super) fn same_rod<'a>(rod: &'a Rod, branch: &'a Branch) -> Result<(&'a Rod, &'a Branch)> {
    if branch.model != rod.model {
        return Err(Error::new(Status::ErrOutOfRange, "argument `branch` was computed with another rod than `rod`"));
    }
    Ok((rod, branch))
}

/// The C options for continuing `rod` (NULL refused; fields named `options.…`).
///
/// # Safety
/// `options` must be NULL or valid, its arrays as documented on its fields.
pub(super) unsafe fn options_of(rod: &Rod, options: *const ContinuationOptions) -> Result<(Options, Method, bool)> {
    options_from(arg_ref("options", options)?, rod.model.unknowns()).map_err(|e| qualify_argument(e, "options."))
}

/// Hand the branch `b` of `rod` to C in `*out`, with the status of its stop.
///
/// # Safety
/// `out` must be NULL or writable.
unsafe fn store_branch(rod: &Rod, b: RodBranch, previous: Option<f64>, out: *mut *mut Branch) -> Result<Status> {
    let status = branch_status(&b);
    *arg_mut("out", out)? = Box::into_raw(Box::new(wrap(&rod.model, b, previous)));
    Ok(status)
}

/// Copy state `index` of `states` (`index_name` in messages, `count` of
/// them) into the caller's `x` of length `n` (the branch's state length).
///
/// # Safety
/// `x` must be NULL or point to `n` writable doubles.
unsafe fn copy_state(
    b: &Branch,
    index_name: &str,
    index: i64,
    count: usize,
    states: &[Vec<f64>],
    x: *mut f64,
    n: i64,
) -> Result<Status> {
    error::count_in_range(index_name, index, 0, count as i64 - 1)?;
    check_len("n", n, b.state_length as i64)?;
    out_slice("x", x, n)?.copy_from_slice(&states[index as usize]);
    Ok(Status::Ok)
}

/// Follow a branch from the state `x0` (length n; NULL: the straight
/// state) at `lambda0`. Returns 0 when the target was reached, a positive
/// RODKIT_STATUS_INFO_* when the branch ended otherwise (the branch is
/// returned in every non-negative case), a negative status on failure
/// (`*out` NULL). `progress` may be NULL.
/// cbindgen:fortran-arrays=[x0]
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_continue(
    rod: *const Rod,
    x0: *const f64,
    n: i64,
    lambda0: f64,
    options: *const ContinuationOptions,
    progress: BranchCallback,
    user_data: *mut c_void,
    out: *mut *mut Branch,
) -> i32 {
    guard(|| {
        clear_handle(out);
        let rod = arg_ref("rod", rod)?;
        // A NULL `out` is refused before any work (a continuation can be long).
        arg_mut("out", out)?;
        let (opts, method, increasing) = options_of(rod, options)?;
        let x0 = if x0.is_null() {
            None
        } else {
            check_len("n", n, rod.model.unknowns() as i64)?;
            Some(in_slice("x0", x0, n)?)
        };
        let b = follow_rod(rod, method, (progress, user_data), None, |cb| {
            rod.model.continue_branch(x0, lambda0, increasing, &opts, method, cb)
        })?;
        store_branch(rod, b, None, out)
    })
}

/// Continue `branch` (of `rod`) from where it ended, with new options.
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_resume(
    rod: *const Rod,
    branch: *const Branch,
    options: *const ContinuationOptions,
    progress: BranchCallback,
    user_data: *mut c_void,
    out: *mut *mut Branch,
) -> i32 {
    guard(|| {
        clear_handle(out);
        let rod = arg_ref("rod", rod)?;
        // A NULL `out` is refused before any work (a continuation can be long).
        arg_mut("out", out)?;
        let (rod, from) = same_rod(rod, arg_ref("branch", branch)?)?;
        let (opts, method, _) = options_of(rod, options)?;
        let previous = from.records.last().map(|r| r.end_rotation);
        let b = follow_rod(rod, method, (progress, user_data), previous, |cb| {
            rod.model.resume_branch(&from.branch, &opts, method, cb)
        })?;
        store_branch(rod, b, previous, out)
    })
}

/// Leave `branch` at its bifurcation `index` (0-based) along null direction
/// `direction` (0-based, < multiplicity) with first arc-length step
/// `first_step`. A double point of a symmetric rod is followed with a phase
/// condition (the branch's states then carry the unfolding parameter μ
/// last; see RodkitBranchInfo.phase_condition).
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_switch(
    rod: *const Rod,
    branch: *const Branch,
    index: i64,
    direction: i64,
    first_step: f64,
    options: *const ContinuationOptions,
    progress: BranchCallback,
    user_data: *mut c_void,
    out: *mut *mut Branch,
) -> i32 {
    guard(|| {
        clear_handle(out);
        let rod = arg_ref("rod", rod)?;
        // A NULL `out` is refused before any work (a continuation can be long).
        arg_mut("out", out)?;
        let (rod, from) = same_rod(rod, arg_ref("branch", branch)?)?;
        error::count_in_range("index", index, 0, i64::MAX)?;
        error::count_in_range("direction", direction, 0, i64::MAX)?;
        error::finite("first_step", first_step)?;
        let (opts, method, _) = options_of(rod, options)?;
        let phi: Vec<f64> = from.records.iter().map(|r| r.end_rotation).collect();
        let previous = from.branch.rotation_at_bifurcation(&rod.model, index as usize, &phi);
        let b = follow_rod(rod, method, (progress, user_data), previous, |cb| {
            rod.model.switch_branch(&from.branch, index as usize, direction as usize, first_step, &opts, method, cb)
        })?;
        store_branch(rod, b, previous, out)
    })
}

/// Free a branch (NULL is accepted).
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_free(branch: *mut Branch) {
    guard_value((), || free_handle(branch))
}

/// Summary of a branch.
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_summary(branch: *const Branch, info: *mut BranchInfo) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        let c = b.branch.counts;
        *arg_mut("info", info)? = BranchInfo {
            records: b.records.len() as i64,
            bifurcations: b.branch.bifurcations.len() as i64,
            stop: stop_code(b.branch.stop) as i32,
            phase_condition: b.branch.phase.is_some() as i32,
            state_length: b.state_length as i64,
            samples: b.samples.len() as i64,
            missed_samples: b.branch.missed_samples.len() as i64,
            steps: c.steps as i64,
            factorisations: c.factorisations as i64,
            solves: c.solves as i64,
            residuals: c.residuals as i64,
            jacobians: c.jacobians as i64,
            series_orders: c.series_orders as i64,
            contact_record: b.branch.contact.map_or(-1, |c| c.record as i64),
            contact_distance: b.branch.contact.map_or(0.0, |c| c.distance),
            contact_s1: b.branch.contact.map_or(0.0, |c| c.s1),
            contact_s2: b.branch.contact.map_or(0.0, |c| c.s2),
        };
        Ok(Status::Ok)
    })
}

/// Copy up to `capacity` records into `records`; `count` receives the
/// number of records of the branch. Fewer than that copied:
/// RODKIT_STATUS_INFO_TRUNCATED (capacity 0 with records NULL is a size query).
/// cbindgen:fortran-arrays=[records]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_records(
    branch: *const Branch,
    records: *mut BranchRecord,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        copy_out("records", records, capacity, count, &b.records, |r| *r)
    })
}

/// Copy up to `capacity` of the points delivered at the requested sample
/// loads (RodkitContinuationOptions.samples), in branch order, as records
/// (step, determinant signs 0; test_function NaN: not tracked); `count`
/// receives their number. Truncation and size queries as for
/// rodkit_branch_records.
/// cbindgen:fortran-arrays=[samples]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_samples(
    branch: *const Branch,
    samples: *mut BranchRecord,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        copy_out("samples", samples, capacity, count, &b.samples, |r| *r)
    })
}

/// The full state x of sample `sample` (length RodkitBranchInfo.state_length).
/// cbindgen:fortran-arrays=[x]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_sample_state(branch: *const Branch, sample: i64, x: *mut f64, n: i64) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        copy_state(b, "sample", sample, b.samples.len(), &b.branch.sample_states, x, n)
    })
}

/// The branch's located bifurcations for C, with their place, end
/// rotation and evidence (the fields of both copy-out functions).
fn bifurcation_points(rod: &Rod, b: &Branch) -> Vec<BifurcationPoint> {
    let phi: Vec<f64> = b.records.iter().map(|r| r.end_rotation).collect();
    (b.branch.bifurcations.iter().enumerate())
        .map(|(index, bif)| {
            let tip = rod.model.tip(&bif.x);
            let s = |i: usize| bif.singular_values.get(i).copied().unwrap_or(f64::NAN);
            BifurcationPoint {
                lambda: bif.lambda,
                end_rotation: b.branch.rotation_at_bifurcation(&rod.model, index, &phi).unwrap_or(0.0),
                record: bif.record as i64,
                multiplicity: bif.multiplicity as i64,
                sigma1: s(0),
                sigma2: s(1),
                sigma3: s(2),
                det_sign_change: bif.det_sign_change as i32,
                test_function_change: bif.test_function_change as i32,
                tip_x: tip[0],
                tip_y: tip[1],
                tip_z: tip[2],
            }
        })
        .collect()
}

/// Copy up to `capacity` located bifurcations; `count` receives their number.
/// cbindgen:fortran-arrays=[out]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_bifurcations(
    branch: *const Branch,
    rod: *const Rod,
    out: *mut Bifurcation,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let (rod, b) = same_rod(arg_ref("rod", rod)?, arg_ref("branch", branch)?)?;
        let points = bifurcation_points(rod, b);
        copy_out("out", out, capacity, count, &points, |&p| Bifurcation::from(p))
    })
}

/// Copy up to `capacity` located bifurcations with their place on the
/// branch (the record each follows, the end rotation there) and the
/// evidence for each; `count` receives their number. Same order and
/// indices as rodkit_branch_bifurcations and rodkit_branch_switch.
/// cbindgen:fortran-arrays=[out]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_bifurcation_points(
    branch: *const Branch,
    rod: *const Rod,
    out: *mut BifurcationPoint,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let (rod, b) = same_rod(arg_ref("rod", rod)?, arg_ref("branch", branch)?)?;
        let points = bifurcation_points(rod, b);
        copy_out("out", out, capacity, count, &points, |p| *p)
    })
}

/// The full state x at bifurcation `index` (length
/// RodkitBranchInfo.state_length): the point rodkit_branch_switch leaves.
/// cbindgen:fortran-arrays=[x]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_bifurcation_state(
    branch: *const Branch,
    index: i64,
    x: *mut f64,
    n: i64,
) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        let bifs = &b.branch.bifurcations;
        error::count_in_range("index", index, 0, bifs.len() as i64 - 1)?;
        check_len("n", n, b.state_length as i64)?;
        let state = bifs[index as usize].x.get(..b.state_length).ok_or_else(|| {
            Error::new(
                Status::ErrInternal,
                "rodkit_branch_bifurcation_state: the point is shorter than the branch's states",
            )
        })?;
        out_slice("x", x, n)?.copy_from_slice(state);
        Ok(Status::Ok)
    })
}

/// Copy up to `capacity` unresolved brackets (where det of the bordered
/// tangent or the test function changed sign, or σ_min dipped, and no
/// bifurcation accounting for it was located); `count` receives their
/// number. A branch with any returns
/// RODKIT_STATUS_INFO_UNRESOLVED_BIFURCATION where it would return 0.
/// cbindgen:fortran-arrays=[out]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_unresolved(
    branch: *const Branch,
    out: *mut UnresolvedBifurcation,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        copy_out("out", out, capacity, count, &b.branch.unresolved, |u| UnresolvedBifurcation {
            record_first: u.records.0 as i64,
            record_last: u.records.1 as i64,
            lambda_first: u.lambdas.0,
            lambda_last: u.lambdas.1,
            det_sign_change: u.det_sign_change as i32,
            test_function_change: u.test_function_change as i32,
        })
    })
}

/// The full state x at record `record` (length RodkitBranchInfo.state_length).
/// cbindgen:fortran-arrays=[x]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_state(branch: *const Branch, record: i64, x: *mut f64, n: i64) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        copy_state(b, "record", record, b.records.len(), &b.branch.states, x, n)
    })
}

/// Node positions r(s_i), i = 0…N, of record `record`: xyz[k + ld·i]
/// (ld ≥ 3), for `nodes` = N + 1 nodes (the rod's elements + 1).
/// cbindgen:fortran-arrays=[xyz]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_positions(
    branch: *const Branch,
    rod: *const Rod,
    record: i64,
    xyz: *mut f64,
    ld: i64,
    nodes: i64,
) -> i32 {
    guard(|| {
        let (rod, b) = same_rod(arg_ref("rod", rod)?, arg_ref("branch", branch)?)?;
        error::count_in_range("record", record, 0, b.records.len() as i64 - 1)?;
        check_nodes(ld, nodes, rod.model.elements + 1)?;
        write_positions(xyz, ld, &rod.model.positions(&b.branch.states[record as usize]))?;
        Ok(Status::Ok)
    })
}

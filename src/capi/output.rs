//! Files for other tools from C: a branch's shapes as VTK and its
//! records as CSV (its dense-output samples likewise), a supercoiling path's
//! shapes as VTK and its points as CSV, a tube sweep's loadings and states
//! as CSV. Opt-in, the path given by the caller, written whole or not at all
//! (RODKIT_STATUS_ERR_IO names the path and the system's reason).

use super::args::{arg_ref, null_error, path_arg, qualify_argument};
use super::branch::{same_rod, Branch};
use super::branch_record::BranchRecord;
use super::guard;
use super::rod::Rod;
use super::supercoil::Supercoil;
use super::tube::{AxialControl, TorsionControl, TubeLoading, TubeState};
use crate::error::{Error, Result};
use crate::io::{csv, vtk};
use crate::status::Status;
use std::ffi::{c_char, CStr};
use std::path::PathBuf;

/// The arguments every branch writer takes: the rod, its branch (checked to
/// be the rod's) and the path.
///
/// # Safety
/// As rodkit_branch_write_vtk.
unsafe fn branch_args<'a>(
    branch: *const Branch,
    rod: *const Rod,
    path: *const c_char,
) -> Result<(&'a Rod, &'a Branch, PathBuf)> {
    let (rod, b) = same_rod(arg_ref("rod", rod)?, arg_ref("branch", branch)?)?;
    Ok((rod, b, path_arg(path)?))
}

/// The items to write: `selection` (n indices, each in 0..len) in its order,
/// or all of them when it is NULL.
///
/// # Safety
/// `selection` must be NULL or hold `n` readable values.
unsafe fn chosen(selection: *const i64, n: i64, len: usize, what: &str) -> Result<Vec<usize>> {
    if selection.is_null() {
        return Ok((0..len).collect());
    }
    // A selection may repeat items; more than 2^24 of them is a mistake.
    crate::error::count_in_range("n", n, 1, 1 << 24)?;
    std::slice::from_raw_parts(selection, n as usize)
        .iter()
        .map(|&k| {
            crate::error::count_in_range(what, k, 0, len as i64 - 1)?;
            Ok(k as usize)
        })
        .collect()
}

/// Write the shapes of the records `records` (n indices; NULL: every record)
/// of `branch` (computed on `rod`) to `path` as legacy VTK polydata: one
/// polyline per record through the rod's nodes
/// (positions r(s_i)), with the cell data `lambda` (the record's load
/// parameter) and `end_rotation` (φ under an end-rotation or end-moment
/// control, else 0) — for ParaView or VisIt. Coordinates at full precision.
/// Writes nothing on failure.
///
/// # Safety
/// `branch` and `rod` must be NULL or valid handles, `records` NULL or `n`
/// readable values, `path` NULL or a NUL-terminated string.
/// cbindgen:fortran-arrays=[records]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_write_vtk(
    branch: *const Branch,
    rod: *const Rod,
    records: *const i64,
    n: i64,
    path: *const c_char,
) -> i32 {
    guard(|| {
        let (rod, b, path) = branch_args(branch, rod, path)?;
        let chosen = chosen(records, n, b.records.len(), "records")?;
        write_shapes(rod, &b.branch.states, &b.records, &chosen, "rodkit branch shapes", &path)?;
        Ok(Status::Ok)
    })
}

/// The shapes of the chosen items (states with their records) as VTK
/// polylines with the cell data lambda and end_rotation.
fn write_shapes(
    rod: &Rod,
    states: &[Vec<f64>],
    records: &[BranchRecord],
    chosen: &[usize],
    title: &str,
    path: &std::path::Path,
) -> Result<()> {
    let shapes: Vec<Vec<[f64; 3]>> = chosen.iter().map(|&k| rod.model.positions(&states[k])).collect();
    let lambda = chosen.iter().map(|&k| records[k].lambda).collect();
    let phi = chosen.iter().map(|&k| records[k].end_rotation).map(|p| if p.is_finite() { p } else { 0.0 }).collect();
    vtk::write_polylines(path, title, &shapes, &[("lambda", lambda), ("end_rotation", phi)])
}

/// The CSV columns of rodkit_branch_write_csv, in order.
const RECORD_COLUMNS: [&str; 19] = [
    "lambda",
    "end_rotation",
    "tip_x",
    "tip_y",
    "tip_z",
    "tip_rotation",
    "base_force_x",
    "base_force_y",
    "base_force_z",
    "base_moment_x",
    "base_moment_y",
    "base_moment_z",
    "det_sign",
    "bordered_det_sign",
    "test_function",
    "residual",
    "step",
    "newton_iterations",
    "unfolding",
];

/// Write the records of `branch` (computed on `rod`) to `path` as CSV: a
/// header row, then one row per record with the RodkitBranchRecord fields
/// lambda, end_rotation, tip_x, tip_y, tip_z, tip_rotation, base_force_x…z,
/// base_moment_x…z, det_sign, bordered_det_sign, test_function, residual,
/// step, newton_iterations, unfolding (NaN where a field is not tracked).
/// Writes nothing on failure.
///
/// # Safety
/// As rodkit_branch_write_vtk.
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_write_csv(branch: *const Branch, rod: *const Rod, path: *const c_char) -> i32 {
    guard(|| {
        let (_, b, path) = branch_args(branch, rod, path)?;
        csv::write_table(&path, &RECORD_COLUMNS, &record_rows(&b.records))?;
        Ok(Status::Ok)
    })
}

/// The dense-output samples' shapes: as rodkit_branch_write_vtk for the
/// points delivered at the requested sample loads
/// (RodkitContinuationOptions.samples; rodkit_branch_samples gives their
/// records): one polyline per sample `samples` (n indices; NULL: every
/// sample), cell data `lambda` and `end_rotation`. A branch without samples:
/// RODKIT_STATUS_ERR_OUT_OF_RANGE. Writes nothing on failure.
///
/// # Safety
/// As rodkit_branch_write_vtk, with `samples` for `records`.
/// cbindgen:fortran-arrays=[samples]
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_write_samples_vtk(
    branch: *const Branch,
    rod: *const Rod,
    samples: *const i64,
    n: i64,
    path: *const c_char,
) -> i32 {
    guard(|| {
        let (rod, b, path) = branch_args(branch, rod, path)?;
        has_samples(b)?;
        let chosen = chosen(samples, n, b.samples.len(), "samples")?;
        write_shapes(rod, &b.branch.sample_states, &b.samples, &chosen, "rodkit branch samples", &path)?;
        Ok(Status::Ok)
    })
}

/// The dense-output samples as CSV: the columns of rodkit_branch_write_csv,
/// one row per sample as rodkit_branch_samples gives it (step and
/// determinant signs 0, test_function NaN: not tracked). A branch without
/// samples: RODKIT_STATUS_ERR_OUT_OF_RANGE. Writes nothing on failure.
///
/// # Safety
/// As rodkit_branch_write_vtk.
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_write_samples_csv(
    branch: *const Branch,
    rod: *const Rod,
    path: *const c_char,
) -> i32 {
    guard(|| {
        let (_, b, path) = branch_args(branch, rod, path)?;
        has_samples(b)?;
        csv::write_table(&path, &RECORD_COLUMNS, &record_rows(&b.samples))?;
        Ok(Status::Ok)
    })
}

fn has_samples(b: &Branch) -> Result<()> {
    if b.samples.is_empty() {
        return Err(Error::new(
            Status::ErrOutOfRange,
            "the branch has no samples (set RodkitContinuationOptions.samples to ask for them)",
        ));
    }
    Ok(())
}

/// One CSV row per record, in RECORD_COLUMNS' order.
fn record_rows(records: &[BranchRecord]) -> Vec<Vec<f64>> {
    records
        .iter()
        .map(|r| {
            vec![
                r.lambda,
                r.end_rotation,
                r.tip_x,
                r.tip_y,
                r.tip_z,
                r.tip_rotation,
                r.base_force_x,
                r.base_force_y,
                r.base_force_z,
                r.base_moment_x,
                r.base_moment_y,
                r.base_moment_z,
                r.det_sign,
                r.bordered_det_sign,
                r.test_function,
                r.residual,
                r.step,
                r.newton_iterations as f64,
                r.unfolding,
            ]
        })
        .collect()
}

/// Write the shapes of the points `points` (n indices; NULL: every point)
/// of a supercoiling path to `path` as legacy VTK polydata: one polyline
/// per point through the rod's nodes (nm), with the
/// cell data `turns`, `extension`, `torque` and `writhe` of the point.
/// Writes nothing on failure.
///
/// # Safety
/// `run` must be NULL or a valid handle, `points` NULL or `n` readable
/// values, `path` NULL or a NUL-terminated string.
/// cbindgen:fortran-arrays=[points]
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_write_vtk(
    run: *const Supercoil,
    points: *const i64,
    n: i64,
    path: *const c_char,
) -> i32 {
    guard(|| {
        let r = &arg_ref("run", run)?.run;
        let path = path_arg(path)?;
        let chosen = chosen(points, n, r.points.len(), "points")?;
        let shapes: Vec<Vec<[f64; 3]>> = chosen.iter().map(|&k| r.rod.positions(&r.states[k])).collect();
        let column = |f: fn(&crate::charged::dna::PathPoint) -> f64| {
            chosen.iter().map(|&k| f(&r.points[k])).collect::<Vec<f64>>()
        };
        let scalars = [
            ("turns", column(|p| p.observables.turns)),
            ("extension", column(|p| p.observables.extension)),
            ("torque", column(|p| p.observables.torque)),
            ("writhe", column(|p| p.observables.writhe)),
        ];
        vtk::write_polylines(&path, "rodkit supercoiling shapes (nm)", &shapes, &scalars)?;
        Ok(Status::Ok)
    })
}

/// Write the points of a supercoiling path to `path` as CSV: a header row,
/// then one row per point with the RodkitSupercoilPoint fields turns,
/// extension, torque, tension, twist, writhe, branch, residual. Writes
/// nothing on failure.
///
/// # Safety
/// As rodkit_supercoil_write_vtk.
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_write_csv(run: *const Supercoil, path: *const c_char) -> i32 {
    guard(|| {
        let r = &arg_ref("run", run)?.run;
        let path = path_arg(path)?;
        let rows: Vec<Vec<f64>> = r
            .points
            .iter()
            .map(|p| {
                let o = p.observables;
                vec![o.turns, o.extension, o.torque, o.tension, o.twist, o.writhe, p.branch as f64, p.residual]
            })
            .collect();
        let header = ["turns", "extension", "torque", "tension", "twist", "writhe", "branch", "residual"];
        csv::write_table(&path, &header, &rows)?;
        Ok(Status::Ok)
    })
}

/// A unit's name for a CSV header: 1–32 bytes of UTF-8 without commas,
/// quotes, brackets or control characters.
///
/// # Safety
/// `unit` must be NULL or a NUL-terminated string.
unsafe fn unit_arg(name: &str, unit: *const c_char) -> Result<String> {
    if unit.is_null() {
        return Err(Error::new(Status::ErrNullPointer, format!("argument `{name}` is NULL")));
    }
    let bad = |why: &str| Error::new(Status::ErrOutOfRange, format!("argument `{name}` {why}"));
    let text = CStr::from_ptr(unit).to_str().map_err(|_| bad("is not UTF-8"))?;
    if text.is_empty() || text.len() > 32 {
        return Err(bad(&format!("must be 1 to 32 bytes long (got {})", text.len())));
    }
    if text.chars().any(|c| c.is_control() || [',', '"', '[', ']'].contains(&c)) {
        return Err(bad(&format!("`{}` holds a comma, quote, bracket or control character", text.escape_debug())));
    }
    Ok(text.to_string())
}

/// Write a tube sweep to `path` as CSV: the `count` loadings given to
/// rodkit_tube_sweep and the states it returned for them (pass its
/// `completed` count after a cancelled or failed sweep), one row each. The
/// header names every column with its unit in brackets, in the caller's
/// length and force units (`length_unit`, `force_unit`, e.g. "mm" and "mN",
/// or "nm" and "pN"; rodkit itself is unit-free), e.g. `twist [rad/mm]`,
/// `torque [mN*mm]`, `inner_pressure [mN/mm^2]`:
///
/// - the loading: load_stretch [1], load_force [F] (one of them, the other
///   cell empty, as axial_control says), load_twist [rad/L], load_torque
///   [F*L] (likewise), load_inner_pressure, load_outer_pressure [F/L^2],
///   closed_ends (1 or 0);
/// - the state, as RodkitTubeState: stretch [1], twist [rad/L], wall_force,
///   applied_force [F], torque [F*L], inner_pressure, outer_pressure
///   [F/L^2], inner_radius, outer_radius [L] (deformed), error_estimate
///   [1], intervals, newton_iterations, model (RodkitTubeModel).
///
/// Numbers at full precision (they parse back to the same doubles). Every
/// loading is checked as rodkit_tube_sweep checks it, and every state must
/// be finite (else RODKIT_STATUS_ERR_NOT_FINITE) with counts ≥ 0 and a thick
/// or membrane model (else RODKIT_STATUS_ERR_OUT_OF_RANGE), so that a state
/// the sweep did not write is refused rather than written; the message names
/// the entry. Writes nothing on failure.
///
/// # Safety
/// `loadings` and `states` must be NULL or hold `count` readable values,
/// `length_unit`, `force_unit` and `path` NULL or NUL-terminated strings.
/// cbindgen:fortran-arrays=[loadings, states]
#[no_mangle]
pub unsafe extern "C" fn rodkit_tube_sweep_write_csv(
    loadings: *const TubeLoading,
    states: *const TubeState,
    count: i64,
    length_unit: *const c_char,
    force_unit: *const c_char,
    path: *const c_char,
) -> i32 {
    guard(|| {
        crate::error::dimension("count", count, 1, 1 << 40)?;
        if loadings.is_null() {
            return Err(null_error("loadings"));
        }
        if states.is_null() {
            return Err(null_error("states"));
        }
        let (l, f) = (unit_arg("length_unit", length_unit)?, unit_arg("force_unit", force_unit)?);
        let path = path_arg(path)?;
        let n = count as usize;
        let loadings = std::slice::from_raw_parts(loadings, n);
        let states = std::slice::from_raw_parts(states, n);
        for (i, x) in loadings.iter().enumerate() {
            super::tube::loading(x).map_err(|e| qualify_argument(e, &format!("loadings[{i}].")))?;
        }
        for (i, s) in states.iter().enumerate() {
            let fields = [
                ("stretch", s.stretch),
                ("twist", s.twist),
                ("wall_force", s.wall_force),
                ("applied_force", s.applied_force),
                ("torque", s.torque),
                ("inner_pressure", s.inner_pressure),
                ("outer_pressure", s.outer_pressure),
                ("deformed_inner_radius", s.deformed_inner_radius),
                ("deformed_outer_radius", s.deformed_outer_radius),
                ("error_estimate", s.error_estimate),
            ];
            for (name, v) in fields {
                crate::error::finite(&format!("states[{i}].{name}"), v)?;
            }
            crate::error::count_in_range(&format!("states[{i}].intervals"), s.intervals, 0, 1 << 20)?;
            crate::error::count_in_range(&format!("states[{i}].newton_iterations"), s.newton_iterations, 0, 1 << 40)?;
            crate::error::count_in_range(&format!("states[{i}].model"), s.model as i64, 1, 2)?;
        }
        let header = [
            "load_stretch [1]".to_string(),
            format!("load_force [{f}]"),
            format!("load_twist [rad/{l}]"),
            format!("load_torque [{f}*{l}]"),
            format!("load_inner_pressure [{f}/{l}^2]"),
            format!("load_outer_pressure [{f}/{l}^2]"),
            "closed_ends".to_string(),
            "stretch [1]".to_string(),
            format!("twist [rad/{l}]"),
            format!("wall_force [{f}]"),
            format!("applied_force [{f}]"),
            format!("torque [{f}*{l}]"),
            format!("inner_pressure [{f}/{l}^2]"),
            format!("outer_pressure [{f}/{l}^2]"),
            format!("inner_radius [{l}]"),
            format!("outer_radius [{l}]"),
            "error_estimate [1]".to_string(),
            "intervals".to_string(),
            "newton_iterations".to_string(),
            "model".to_string(),
        ];
        let rows: Vec<Vec<Option<f64>>> = loadings
            .iter()
            .zip(states)
            .map(|(x, s)| {
                let stretch = x.axial_control == AxialControl::Stretch as i32;
                let twist = x.torsion_control == TorsionControl::Twist as i32;
                vec![
                    stretch.then_some(x.axial),
                    (!stretch).then_some(x.axial),
                    twist.then_some(x.torsion),
                    (!twist).then_some(x.torsion),
                    Some(x.inner_pressure),
                    Some(x.outer_pressure),
                    Some(x.closed_ends as f64),
                    Some(s.stretch),
                    Some(s.twist),
                    Some(s.wall_force),
                    Some(s.applied_force),
                    Some(s.torque),
                    Some(s.inner_pressure),
                    Some(s.outer_pressure),
                    Some(s.deformed_inner_radius),
                    Some(s.deformed_outer_radius),
                    Some(s.error_estimate),
                    Some(s.intervals as f64),
                    Some(s.newton_iterations as f64),
                    Some(s.model as f64),
                ]
            })
            .collect();
        csv::write_cells(&path, &header, &rows)?;
        Ok(Status::Ok)
    })
}

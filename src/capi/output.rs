//! Files for other tools from C (issue 20): a branch's shapes as VTK and its
//! records as CSV, a supercoiling path's shapes as VTK and its points as
//! CSV. Opt-in, the path given by the caller, written whole or not at all
//! (RODKIT_STATUS_ERR_IO names the path and the system's reason).

use super::args::arg_ref;
use super::branch::{same_rod, Branch};
use super::guard;
use super::rod::Rod;
use super::supercoil::Supercoil;
use crate::error::{Error, Result};
use crate::io::{csv, vtk};
use crate::status::Status;
use std::ffi::{c_char, CStr};
use std::path::PathBuf;

/// A NUL-terminated path from C (bytes as the system takes them).
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string.
unsafe fn path_arg(path: *const c_char) -> Result<PathBuf> {
    if path.is_null() {
        return Err(Error::new(Status::ErrNullPointer, "argument `path` is NULL"));
    }
    let bytes = CStr::from_ptr(path).to_bytes();
    if bytes.is_empty() {
        return Err(Error::new(Status::ErrOutOfRange, "argument `path` is empty"));
    }
    #[cfg(unix)]
    let path = {
        use std::os::unix::ffi::OsStrExt;
        PathBuf::from(std::ffi::OsStr::from_bytes(bytes))
    };
    #[cfg(not(unix))]
    let path = PathBuf::from(
        std::str::from_utf8(bytes).map_err(|_| Error::new(Status::ErrOutOfRange, "argument `path` is not UTF-8"))?,
    );
    Ok(path)
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
        let rod = arg_ref("rod", rod)?;
        let b = same_rod(rod, arg_ref("branch", branch)?)?;
        let path = path_arg(path)?;
        let chosen = chosen(records, n, b.records.len(), "records")?;
        let shapes: Vec<Vec<[f64; 3]>> = chosen.iter().map(|&k| rod.model.positions(&b.branch.states[k])).collect();
        let lambda = chosen.iter().map(|&k| b.records[k].lambda).collect();
        let phi =
            chosen.iter().map(|&k| b.records[k].end_rotation).map(|p| if p.is_finite() { p } else { 0.0 }).collect();
        vtk::write_polylines(&path, "rodkit branch shapes", &shapes, &[("lambda", lambda), ("end_rotation", phi)])?;
        Ok(Status::Ok)
    })
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
        let rod = arg_ref("rod", rod)?;
        let b = same_rod(rod, arg_ref("branch", branch)?)?;
        let path = path_arg(path)?;
        let rows: Vec<Vec<f64>> = b
            .records
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
            .collect();
        csv::write_table(&path, &RECORD_COLUMNS, &rows)?;
        Ok(Status::Ok)
    })
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

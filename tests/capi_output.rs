//! Files for other tools through the C ABI (issue 20): a rod branch's shapes
//! as VTK and its records as CSV, a supercoiling path's shapes and points
//! likewise. Reference: the ABI's own accessors (rodkit_branch_positions,
//! rodkit_branch_records, rodkit_supercoil_positions, _points) — every
//! number in the files parses back to the accessor's value bitwise (they
//! are written in Rust's shortest round-trip form). Failures: a NULL or
//! empty path, and a directory that does not exist, give their statuses,
//! name the path, and leave no file (not even a temporary one) behind.

use rodkit::capi::branch::*;
use rodkit::capi::branch_record::*;
use rodkit::capi::continuation::*;
use rodkit::capi::error::rodkit_last_error_message;
use rodkit::capi::output::*;
use rodkit::capi::rod::*;
use rodkit::capi::rod_spec::*;
use rodkit::capi::supercoil::*;
use rodkit::Status;
use std::ffi::{CStr, CString};
use std::path::{Path, PathBuf};
use std::ptr;

fn last_error() -> String {
    unsafe { CStr::from_ptr(rodkit_last_error_message()) }.to_string_lossy().into_owned()
}

fn c_path(p: &Path) -> CString {
    CString::new(p.to_str().unwrap()).unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rodkit-output-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The numbers of a legacy VTK polydata file: its points, its polylines'
/// point indices, and its cell scalars by name.
struct Vtk {
    points: Vec<[f64; 3]>,
    lines: Vec<Vec<usize>>,
    scalars: Vec<(String, Vec<f64>)>,
}

fn read_vtk(path: &Path) -> Vtk {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("# vtk DataFile Version 3.0"));
    lines.next(); // title
    assert_eq!((lines.next(), lines.next()), (Some("ASCII"), Some("DATASET POLYDATA")));
    let header: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
    assert_eq!((header[0], header[2]), ("POINTS", "double"));
    let n: usize = header[1].parse().unwrap();
    let num = |s: &str| s.parse::<f64>().unwrap();
    let points = (0..n)
        .map(|_| {
            let v: Vec<f64> = lines.next().unwrap().split_whitespace().map(num).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let header: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
    assert_eq!(header[0], "LINES");
    let cells: usize = header[1].parse().unwrap();
    let polylines: Vec<Vec<usize>> = (0..cells)
        .map(|_| {
            let v: Vec<usize> = lines.next().unwrap().split_whitespace().map(|s| s.parse().unwrap()).collect();
            assert_eq!(v[0], v.len() - 1);
            v[1..].to_vec()
        })
        .collect();
    assert_eq!(header[2].parse::<usize>().unwrap(), n + cells);
    let mut scalars = vec![];
    if let Some(l) = lines.next() {
        assert_eq!(l, format!("CELL_DATA {cells}"));
        while let Some(l) = lines.next() {
            let name = l.split_whitespace().nth(1).unwrap().to_string();
            assert_eq!(lines.next(), Some("LOOKUP_TABLE default"));
            scalars.push((name, (0..cells).map(|_| num(lines.next().unwrap())).collect()));
        }
    }
    Vtk { points, lines: polylines, scalars }
}

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    (header, lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect())
}

/// Equal as numbers, NaN equal to NaN (a field not tracked).
fn same(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

/// A follower cantilever curled by its tip moment (K_b = 1, 4 elements,
/// Λ 0 → 3): every record's shape in the VTK file is the one
/// rodkit_branch_positions gives, its lambda the record's; every CSV row
/// the record's fields.
#[test]
fn a_branch_s_shapes_and_records_are_written_whole() {
    let mut s = std::mem::MaybeUninit::<RodSpec>::uninit();
    assert_eq!(unsafe { rodkit_rod_spec_default(s.as_mut_ptr()) }, 0);
    let mut s = unsafe { s.assume_init() };
    s.length = 1.0;
    (s.bending1, s.bending2, s.twist, s.shear1, s.shear2, s.stretch) = (1.0, 1.0, 1.0 / 1.3, 1e4, 1e4, 2.6e4);
    (s.tip_moment_frame, s.tip_moment_x, s.elements) = (LoadFrame::Follower as i32, 1.0, 4);
    let mut rod = ptr::null_mut();
    assert_eq!(unsafe { rodkit_rod_new(&s, &mut rod) }, 0);
    let mut o = std::mem::MaybeUninit::<ContinuationOptions>::uninit();
    assert_eq!(unsafe { rodkit_continuation_options_default(o.as_mut_ptr()) }, 0);
    let mut o = unsafe { o.assume_init() };
    o.target_lambda = 3.0;
    let mut b = ptr::null_mut();
    assert!(unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) } >= 0);
    let mut info = BranchInfo::default();
    unsafe { rodkit_branch_summary(b, &mut info) };
    let mut records = vec![BranchRecord::default(); info.records as usize];
    let mut count = 0;
    unsafe { rodkit_branch_records(b, records.as_mut_ptr(), info.records, &mut count) };
    let dir = scratch("branch");
    let (vtk, csv) = (dir.join("shapes.vtk"), dir.join("records.csv"));
    assert_eq!(
        unsafe { rodkit_branch_write_vtk(b, rod, ptr::null(), 0, c_path(&vtk).as_ptr()) },
        0,
        "{}",
        last_error()
    );
    assert_eq!(unsafe { rodkit_branch_write_csv(b, rod, c_path(&csv).as_ptr()) }, 0, "{}", last_error());

    let file = read_vtk(&vtk);
    let nodes = 5;
    assert_eq!((file.lines.len(), file.points.len()), (records.len(), records.len() * nodes));
    for (k, line) in file.lines.iter().enumerate() {
        let mut xyz = vec![0.0; 3 * nodes];
        assert_eq!(unsafe { rodkit_branch_positions(b, rod, k as i64, xyz.as_mut_ptr(), 3, nodes as i64) }, 0);
        assert_eq!(line, &(k * nodes..(k + 1) * nodes).collect::<Vec<_>>());
        for (i, &p) in line.iter().enumerate() {
            assert_eq!(file.points[p], [xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]], "record {k}, node {i}");
        }
    }
    let lambda = &file.scalars.iter().find(|(n, _)| n == "lambda").unwrap().1;
    assert!(lambda.iter().zip(&records).all(|(a, r)| *a == r.lambda));
    // The curl is real: the last shape is a circle of curvature Λ = 3 about
    // d1 (closed form, to the mesh and the stretch): tip |y| = (1 − cos Λ)/Λ,
    // z = sin Λ/Λ.
    let tip = file.points[file.points.len() - 1];
    assert!(
        (tip[1].abs() - (1.0 - 3f64.cos()) / 3.0).abs() < 1e-3 && (tip[2] - 3f64.sin() / 3.0).abs() < 1e-3,
        "{tip:?}"
    );

    let (header, rows) = read_csv(&csv);
    assert_eq!(header[..6], ["lambda", "end_rotation", "tip_x", "tip_y", "tip_z", "tip_rotation"]);
    assert_eq!(rows.len(), records.len());
    for (row, r) in rows.iter().zip(&records) {
        let want = [r.lambda, r.end_rotation, r.tip_x, r.tip_y, r.tip_z, r.tip_rotation, r.base_force_x];
        assert!(row.iter().zip(want).all(|(a, b)| same(*a, b)), "{row:?} vs {r:?}");
        assert!(same(row[14], r.test_function) && row[17] == r.newton_iterations as f64);
    }

    // A selection, in its order: the last record then the first.
    let last = records.len() as i64 - 1;
    let picked = dir.join("picked.vtk");
    assert_eq!(unsafe { rodkit_branch_write_vtk(b, rod, [last, 0].as_ptr(), 2, c_path(&picked).as_ptr()) }, 0);
    let two = read_vtk(&picked);
    assert_eq!(two.points[..nodes], file.points[file.points.len() - nodes..]);
    assert_eq!(two.points[nodes..], file.points[..nodes]);
    assert_eq!(
        unsafe { rodkit_branch_write_vtk(b, rod, [last + 1].as_ptr(), 1, c_path(&picked).as_ptr()) },
        Status::ErrOutOfRange.code()
    );
    std::fs::remove_file(&picked).unwrap();

    // Failures: statuses, the path named, nothing left behind.
    let missing = dir.join("no such dir").join("x.vtk");
    assert_eq!(
        unsafe { rodkit_branch_write_vtk(b, rod, ptr::null(), 0, c_path(&missing).as_ptr()) },
        Status::ErrIo.code()
    );
    assert!(last_error().contains("no such dir"), "{}", last_error());
    assert_eq!(unsafe { rodkit_branch_write_csv(b, rod, ptr::null()) }, Status::ErrNullPointer.code());
    assert_eq!(unsafe { rodkit_branch_write_csv(b, rod, c"".as_ptr()) }, Status::ErrOutOfRange.code());
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 2, "{left:?}");
    unsafe {
        rodkit_branch_free(b);
        rodkit_rod_free(rod);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A tiny supercoiling run (60 bp, 8 elements, 6 steps): its shapes and
/// points, as rodkit_supercoil_positions and _points give them.
#[test]
fn a_supercoiling_path_is_written_whole() {
    let mut s = std::mem::MaybeUninit::<DnaSupercoilSpec>::uninit();
    assert_eq!(unsafe { rodkit_dna_supercoil_spec_default(s.as_mut_ptr()) }, 0);
    let mut s = unsafe { s.assume_init() };
    (s.base_pairs, s.elements, s.max_steps) = (60, 8, 6);
    let mut run = ptr::null_mut();
    assert!(unsafe { rodkit_dna_supercoil_run(&s, &mut run) } >= 0, "{}", last_error());
    let mut count = 0;
    unsafe { rodkit_supercoil_points(run, ptr::null_mut(), 0, &mut count) };
    let mut points = vec![SupercoilPoint::default(); count as usize];
    unsafe { rodkit_supercoil_points(run, points.as_mut_ptr(), count, &mut count) };
    let dir = scratch("supercoil");
    let (vtk, csv) = (dir.join("shapes.vtk"), dir.join("points.csv"));
    assert_eq!(
        unsafe { rodkit_supercoil_write_vtk(run, ptr::null(), 0, c_path(&vtk).as_ptr()) },
        0,
        "{}",
        last_error()
    );
    assert_eq!(unsafe { rodkit_supercoil_write_csv(run, c_path(&csv).as_ptr()) }, 0, "{}", last_error());
    let file = read_vtk(&vtk);
    let nodes = 9;
    assert_eq!(file.lines.len(), points.len());
    for k in 0..points.len() {
        let mut xyz = vec![0.0; 3 * nodes];
        assert_eq!(unsafe { rodkit_supercoil_positions(run, k as i64, xyz.as_mut_ptr(), 3, nodes as i64) }, 0);
        for i in 0..nodes {
            assert_eq!(file.points[file.lines[k][i]], [xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]]);
        }
    }
    let turns = &file.scalars.iter().find(|(n, _)| n == "turns").unwrap().1;
    assert!(turns.iter().zip(&points).all(|(a, p)| *a == p.turns));
    let (header, rows) = read_csv(&csv);
    assert_eq!(header, ["turns", "extension", "torque", "tension", "twist", "writhe", "branch", "residual"]);
    for (row, p) in rows.iter().zip(&points) {
        let want = [p.turns, p.extension, p.torque, p.tension, p.twist, p.writhe, p.branch as f64, p.residual];
        assert!(row.iter().zip(want).all(|(a, b)| same(*a, b)), "{row:?} vs {p:?}");
    }
    assert_eq!(rows.len(), points.len());
    unsafe { rodkit_supercoil_free(run) };
    let _ = std::fs::remove_dir_all(&dir);
}

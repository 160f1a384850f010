//! Files for other tools through the C ABI (issue 20): a rod branch's shapes
//! as VTK and its records as CSV (its dense-output samples likewise), a
//! supercoiling path's shapes and points likewise, a tube sweep's loadings
//! and states as CSV. Reference: the ABI's own accessors
//! (rodkit_branch_positions, rodkit_branch_records, rodkit_branch_samples
//! with rodkit_branch_sample_state and rodkit_rod_node_state,
//! rodkit_supercoil_positions, _points, and the arrays rodkit_tube_sweep
//! filled) — every
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
use rodkit::capi::tube::*;
use rodkit::capi::wall_material::WallLawKind;
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

/// A follower-moment cantilever (as above) with dense output at Λ = 0.5,
/// 1.5 and 3: the samples' shapes in the VTK file are the nodes
/// rodkit_rod_node_state gives for rodkit_branch_sample_state (bitwise),
/// a selection comes in its order, the CSV rows are rodkit_branch_samples'
/// records; a branch without samples is refused.
#[test]
fn a_branch_s_samples_are_written_whole() {
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
    let loads = [0.5, 1.5, 3.0];
    (o.samples, o.sample_count) = (loads.as_ptr(), 3);
    let mut b = ptr::null_mut();
    assert!(unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) } >= 0);
    let mut info = BranchInfo::default();
    unsafe { rodkit_branch_summary(b, &mut info) };
    assert_eq!((info.samples, info.missed_samples), (3, 0));
    let mut samples = vec![BranchRecord::default(); 3];
    let mut count = 0;
    assert_eq!(unsafe { rodkit_branch_samples(b, samples.as_mut_ptr(), 3, &mut count) }, 0);
    let mut n = 0;
    unsafe { rodkit_rod_unknowns(rod, &mut n) };
    let nodes = 5;
    let shape = |k: i64| {
        let mut x = vec![0.0; n as usize];
        assert_eq!(unsafe { rodkit_branch_sample_state(b, k, x.as_mut_ptr(), n) }, 0);
        (0..nodes)
            .map(|i| {
                let mut r = [0.0; 3];
                let none = ptr::null_mut();
                assert_eq!(
                    unsafe { rodkit_rod_node_state(rod, x.as_ptr(), n, i, r.as_mut_ptr(), none, none, none) },
                    0
                );
                r
            })
            .collect::<Vec<[f64; 3]>>()
    };
    let dir = scratch("samples");
    let (vtk, csv) = (dir.join("samples.vtk"), dir.join("samples.csv"));
    let status = unsafe { rodkit_branch_write_samples_vtk(b, rod, ptr::null(), 0, c_path(&vtk).as_ptr()) };
    assert_eq!(status, 0, "{}", last_error());
    let file = read_vtk(&vtk);
    assert_eq!((file.lines.len(), file.points.len()), (3, 3 * nodes as usize));
    for k in 0..3 {
        let want = shape(k as i64);
        for (i, &p) in file.lines[k].iter().enumerate() {
            assert_eq!(file.points[p], want[i], "sample {k}, node {i}");
        }
    }
    let lambda = &file.scalars.iter().find(|(n, _)| n == "lambda").unwrap().1;
    assert_eq!(lambda, &samples.iter().map(|r| r.lambda).collect::<Vec<_>>());
    // The samples sit at the requested loads (to the residual tolerance's
    // effect on Λ: they are solved at exactly those loads).
    assert_eq!(lambda, &loads.to_vec());
    // The curl at Λ = 1.5: a circle of curvature 1.5 (closed form, to the
    // mesh and the stretch, as above).
    let tip = file.points[2 * nodes as usize - 1];
    assert!((tip[2] - 1.5f64.sin() / 1.5).abs() < 1e-3, "{tip:?}");
    // A selection, in its order.
    let picked = dir.join("picked.vtk");
    assert_eq!(unsafe { rodkit_branch_write_samples_vtk(b, rod, [2, 0].as_ptr(), 2, c_path(&picked).as_ptr()) }, 0);
    let two = read_vtk(&picked);
    assert_eq!(two.points[..nodes as usize], shape(2)[..]);
    assert_eq!(two.points[nodes as usize..], shape(0)[..]);
    assert_eq!(
        unsafe { rodkit_branch_write_samples_vtk(b, rod, [3].as_ptr(), 1, c_path(&picked).as_ptr()) },
        Status::ErrOutOfRange.code()
    );
    assert_eq!(
        unsafe { rodkit_branch_write_samples_vtk(b, rod, [0].as_ptr(), 0, c_path(&picked).as_ptr()) },
        Status::ErrOutOfRange.code(),
        "n = 0 with a selection"
    );
    std::fs::remove_file(&picked).unwrap();

    assert_eq!(unsafe { rodkit_branch_write_samples_csv(b, rod, c_path(&csv).as_ptr()) }, 0, "{}", last_error());
    let (header, rows) = read_csv(&csv);
    assert_eq!(header.len(), 19);
    assert_eq!((header[0].as_str(), header[18].as_str()), ("lambda", "unfolding"));
    assert_eq!(rows.len(), 3);
    for (row, r) in rows.iter().zip(&samples) {
        let want = [r.lambda, r.end_rotation, r.tip_x, r.tip_y, r.tip_z, r.tip_rotation, r.base_force_x];
        assert!(row.iter().zip(want).all(|(a, b)| same(*a, b)), "{row:?} vs {r:?}");
        assert!(same(row[14], r.test_function) && same(row[15], r.residual));
    }

    // A branch without samples, NULL handles.
    let mut plain = ptr::null_mut();
    o.samples = ptr::null();
    o.sample_count = 0;
    assert!(unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut plain) } >= 0);
    let none = dir.join("none.csv");
    assert_eq!(
        unsafe { rodkit_branch_write_samples_csv(plain, rod, c_path(&none).as_ptr()) },
        Status::ErrOutOfRange.code()
    );
    assert!(last_error().contains("no samples"), "{}", last_error());
    assert_eq!(
        unsafe { rodkit_branch_write_samples_vtk(plain, rod, ptr::null(), 0, c_path(&none).as_ptr()) },
        Status::ErrOutOfRange.code()
    );
    assert_eq!(
        unsafe { rodkit_branch_write_samples_csv(ptr::null(), rod, c_path(&none).as_ptr()) },
        Status::ErrNullPointer.code()
    );
    let missing = dir.join("no such dir").join("x.csv");
    assert_eq!(unsafe { rodkit_branch_write_samples_csv(b, rod, c_path(&missing).as_ptr()) }, Status::ErrIo.code());
    assert!(last_error().contains("no such dir"), "{}", last_error());
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 2, "{left:?}");
    unsafe {
        rodkit_branch_free(plain);
        rodkit_branch_free(b);
        rodkit_rod_free(rod);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A CSV cell: a number, or None when empty.
fn cell(v: &str) -> Option<f64> {
    (!v.is_empty()).then(|| v.parse().unwrap())
}

fn read_cells(path: &Path) -> (Vec<String>, Vec<Vec<Option<f64>>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    (header, lines.map(|l| l.split(',').map(cell).collect()).collect())
}

/// A thick neo-Hookean tube (A = 0.8, B = 1.2, μ = 1, incompressible).
fn tube() -> *mut Tube {
    let mut spec = std::mem::MaybeUninit::<TubeSpec>::uninit();
    assert_eq!(unsafe { rodkit_tube_spec_default(spec.as_mut_ptr()) }, 0);
    let mut spec = unsafe { spec.assume_init() };
    (spec.inner_radius, spec.outer_radius) = (0.8, 1.2);
    spec.material.law = WallLawKind::NeoHookean as i32;
    (spec.material.shear_modulus, spec.material.incompressible) = (1.0, 1);
    spec.model = TubeModel::Thick as i32;
    let mut t = ptr::null_mut();
    assert_eq!(unsafe { rodkit_tube_new(&spec, &mut t) }, 0, "{}", last_error());
    t
}

/// The wall's axial force 2π∫σ_zz r dr over the deformed section, from
/// `loading`'s stress profile (rodkit_tube_profile), integrated here: the
/// profile's nodes are a spectral grid in the reference radius R, so r(R)
/// and σ_zz(R) are taken as their polynomial interpolants (barycentric),
/// dr/dR from the interpolant's differentiation matrix, and
/// 2π∫σ_zz r (dr/dR) dR by 40-point Gauss–Legendre (rodkit's rule, itself
/// tested against closed-form integrals). Also returns the
/// profile's (r, σ_rr) at the inner and outer wall.
fn integrated_wall_force(t: *mut Tube, l: &TubeLoading) -> (f64, [(f64, f64); 2]) {
    let mut n = 0i64;
    let null = ptr::null_mut();
    assert_eq!(unsafe { rodkit_tube_profile(t, l, 0, null, null, null, null, null, null, &mut n) }, 0);
    let mut cols = vec![vec![0.0; n as usize]; 6];
    let [big_r, r, srr, stt, szz, stz] = &mut cols[..] else { unreachable!() };
    let st = unsafe {
        rodkit_tube_profile(
            t,
            l,
            n,
            big_r.as_mut_ptr(),
            r.as_mut_ptr(),
            srr.as_mut_ptr(),
            stt.as_mut_ptr(),
            szz.as_mut_ptr(),
            stz.as_mut_ptr(),
            &mut n,
        )
    };
    assert_eq!(st, 0, "{}", last_error());
    let m = n as usize;
    assert!(m >= 4 && big_r.windows(2).all(|w| w[1] > w[0]), "profile nodes {big_r:?}");
    // Barycentric weights and the differentiation matrix of the nodes.
    let w: Vec<f64> =
        (0..m).map(|j| 1.0 / (0..m).filter(|&k| k != j).map(|k| big_r[j] - big_r[k]).product::<f64>()).collect();
    let dr: Vec<f64> = (0..m)
        .map(|i| {
            let mut sum = 0.0;
            let mut diag = 0.0;
            for j in (0..m).filter(|&j| j != i) {
                let d = (w[j] / w[i]) / (big_r[i] - big_r[j]);
                sum += d * r[j];
                diag -= d;
            }
            sum + diag * r[i]
        })
        .collect();
    let f: Vec<f64> = (0..m).map(|j| 2.0 * std::f64::consts::PI * szz[j] * r[j] * dr[j]).collect();
    let interpolate = |x: f64| {
        let (mut num, mut den) = (0.0, 0.0);
        for j in 0..m {
            let c = w[j] / (x - big_r[j]);
            num += c * f[j];
            den += c;
        }
        num / den
    };
    let (lo, hi) = (big_r[0], big_r[m - 1]);
    let (z, weight) = rodkit::quadrature::gauss_legendre(40);
    let force: f64 = z
        .iter()
        .zip(&weight)
        .map(|(z, w)| 0.5 * (hi - lo) * w * interpolate(0.5 * (lo + hi) + 0.5 * (hi - lo) * z))
        .sum();
    (force, [(r[0], srr[0]), (r[m - 1], srr[m - 1])])
}

fn loading() -> TubeLoading {
    let mut l = std::mem::MaybeUninit::<TubeLoading>::uninit();
    assert_eq!(unsafe { rodkit_tube_loading_default(l.as_mut_ptr()) }, 0);
    unsafe { l.assume_init() }
}

/// A tube sweep (closed ends, p = 0.3 inside, zero torque, stretch 1 → 1.2
/// in 5 steps; then force and twist control): every state field in the CSV
/// is the value rodkit_tube_sweep returned and every loading the caller's,
/// bitwise, the uncontrolled quantity's cell empty; the units are in the
/// header. Independent check from the file's own columns: the caps'
/// equilibrium, wall force − applied force = π a² p (a the deformed inner
/// radius; physics.md §1.3), to 1e-12 relative (the solver's tolerance is
/// 1e-8, but this identity is how the applied force is computed). Errors:
/// statuses, the path or entry named, nothing left behind.
#[test]
fn a_tube_sweep_is_written_whole() {
    let t = tube();
    let loadings: Vec<TubeLoading> = (0..5)
        .map(|i| {
            let mut l = loading();
            (l.axial_control, l.axial) = (AxialControl::Stretch as i32, 1.0 + 0.05 * i as f64);
            (l.torsion_control, l.torsion) = (TorsionControl::Torque as i32, 0.0);
            (l.inner_pressure, l.closed_ends) = (0.3, 1);
            l
        })
        .collect();
    let mut states = vec![TubeState::default(); 5];
    let mut done = 0;
    let st =
        unsafe { rodkit_tube_sweep(t, loadings.as_ptr(), 5, states.as_mut_ptr(), None, ptr::null_mut(), &mut done) };
    assert_eq!((st, done), (0, 5), "{}", last_error());
    let dir = scratch("tube");
    let csv = dir.join("sweep.csv");
    let write = |l: &[TubeLoading], s: &[TubeState], n: i64, len: &CStr, force: &CStr, path: &Path| unsafe {
        rodkit_tube_sweep_write_csv(l.as_ptr(), s.as_ptr(), n, len.as_ptr(), force.as_ptr(), c_path(path).as_ptr())
    };
    assert_eq!(write(&loadings, &states, 5, c"mm", c"mN", &csv), 0, "{}", last_error());
    let (header, rows) = read_cells(&csv);
    let want_header = [
        "load_stretch [1]",
        "load_force [mN]",
        "load_twist [rad/mm]",
        "load_torque [mN*mm]",
        "load_inner_pressure [mN/mm^2]",
        "load_outer_pressure [mN/mm^2]",
        "closed_ends",
        "stretch [1]",
        "twist [rad/mm]",
        "wall_force [mN]",
        "applied_force [mN]",
        "torque [mN*mm]",
        "inner_pressure [mN/mm^2]",
        "outer_pressure [mN/mm^2]",
        "inner_radius [mm]",
        "outer_radius [mm]",
        "error_estimate [1]",
        "intervals",
        "newton_iterations",
        "model",
    ];
    assert_eq!(header, want_header);
    assert_eq!(rows.len(), 5);
    for ((row, l), s) in rows.iter().zip(&loadings).zip(&states) {
        let loading = [Some(l.axial), None, None, Some(l.torsion), Some(l.inner_pressure), Some(l.outer_pressure)];
        assert_eq!(row[..6], loading, "{row:?}");
        assert_eq!(row[6], Some(1.0));
        let state = [
            s.stretch,
            s.twist,
            s.wall_force,
            s.applied_force,
            s.torque,
            s.inner_pressure,
            s.outer_pressure,
            s.deformed_inner_radius,
            s.deformed_outer_radius,
            s.error_estimate,
            s.intervals as f64,
            s.newton_iterations as f64,
            s.model as f64,
        ];
        assert_eq!(row[7..], state.map(Some), "{row:?} vs {s:?}");
        // Independent of how rodkit forms its forces: the wall's stresses
        // integrated here over the deformed section give the wall force,
        // the radial tractions are the pressures, and the caps' equilibrium
        // (physics.md §1.3) gives the applied force, wall − π a² p, with a
        // the profile's inner radius. Measured: the wall force within
        // 2.4e-14 relative of 2π∫σ_zz r dr (the profile's 19 spectral nodes
        // integrated exactly; a 4-point local cubic was off by 5e-7),
        // σ_rr within 4.5e-14·p of −p and 0.
        let (wall, applied, a, p) = (row[9].unwrap(), row[10].unwrap(), row[14].unwrap(), row[4].unwrap());
        let (integrated, [(ra, sa), (rb, sb)]) = integrated_wall_force(t, l);
        println!("stretch {}: wall {wall} vs ∫σ_zz dA {integrated}; σ_rr + p {:e}, {sb:e}", l.axial, sa + p);
        assert!((wall - integrated).abs() <= 1e-12 * wall.abs(), "wall force {wall} vs 2π∫σ_zz r dr {integrated}");
        assert!((ra - a).abs() <= 1e-12 * a && (rb - row[15].unwrap()).abs() <= 1e-12 * rb, "{ra} {rb} vs {row:?}");
        assert!((sa + p).abs() <= 1e-12 * p && sb.abs() <= 1e-12 * p, "σ_rr {sa} at a, {sb} at b, p {p}");
        let caps = std::f64::consts::PI * ra * ra * p;
        assert!(
            (integrated - applied - caps).abs() <= 1e-9 * caps,
            "∫σ_zz dA {integrated} − applied {applied} vs π a² p {caps}"
        );
    }
    // The model column: the thick wall asked for.
    assert!(rows.iter().all(|r| r[19] == Some(TubeModel::Thick as i32 as f64)));

    // Force and twist control: the other two cells hold the loading.
    let other: Vec<TubeLoading> = [0.0, 0.5, 1.0]
        .iter()
        .map(|&f| {
            let mut l = loading();
            (l.axial_control, l.axial) = (AxialControl::Force as i32, f);
            (l.torsion_control, l.torsion) = (TorsionControl::Twist as i32, 0.1);
            l
        })
        .collect();
    let mut other_states = vec![TubeState::default(); 3];
    let st =
        unsafe { rodkit_tube_sweep(t, other.as_ptr(), 3, other_states.as_mut_ptr(), None, ptr::null_mut(), &mut done) };
    assert_eq!(st, 0, "{}", last_error());
    let csv2 = dir.join("force.csv");
    assert_eq!(write(&other, &other_states, 3, c"nm", c"pN", &csv2), 0, "{}", last_error());
    let (header, rows) = read_cells(&csv2);
    assert_eq!((header[1].as_str(), header[11].as_str()), ("load_force [pN]", "torque [pN*nm]"));
    for ((row, l), s) in rows.iter().zip(&other).zip(&other_states) {
        assert_eq!(row[..4], [None, Some(l.axial), Some(l.torsion), None]);
        assert_eq!((row[8], row[10]), (Some(s.twist), Some(s.applied_force)));
        // Open ends: the wall carries the applied force alone (physics.md
        // §1.3), and its stresses integrated here give the force the caller
        // asked for (measured within 1.2e-13 of the section's force scale
        // μπ(B² − A²)).
        assert_eq!((row[6], row[9]), (Some(0.0), row[10]));
        let (integrated, _) = integrated_wall_force(t, l);
        let scale = std::f64::consts::PI * (1.2f64 * 1.2 - 0.8 * 0.8);
        println!("force {}: ∫σ_zz dA {integrated}", l.axial);
        assert!((integrated - l.axial).abs() <= 1e-11 * scale, "force {} vs 2π∫σ_zz r dr {integrated}", l.axial);
    }

    // Errors, each with its status; the path or the entry named.
    let missing = dir.join("no such dir").join("x.csv");
    assert_eq!(write(&loadings, &states, 5, c"mm", c"mN", &missing), Status::ErrIo.code());
    assert!(last_error().contains("no such dir"), "{}", last_error());
    let bad = dir.join("bad.csv");
    assert_eq!(write(&loadings, &states, 0, c"mm", c"mN", &bad), Status::ErrInvalidDimension.code());
    assert_eq!(write(&loadings, &states, -1, c"mm", c"mN", &bad), Status::ErrInvalidDimension.code());
    let call = |l: *const TubeLoading, s: *const TubeState, u: *const std::ffi::c_char, p: *const std::ffi::c_char| unsafe {
        rodkit_tube_sweep_write_csv(l, s, 5, u, c"mN".as_ptr(), p)
    };
    let path = c_path(&bad);
    assert_eq!(call(ptr::null(), states.as_ptr(), c"mm".as_ptr(), path.as_ptr()), Status::ErrNullPointer.code());
    assert!(last_error().contains("loadings"), "{}", last_error());
    assert_eq!(call(loadings.as_ptr(), ptr::null(), c"mm".as_ptr(), path.as_ptr()), Status::ErrNullPointer.code());
    assert_eq!(call(loadings.as_ptr(), states.as_ptr(), ptr::null(), path.as_ptr()), Status::ErrNullPointer.code());
    assert!(last_error().contains("length_unit"), "{}", last_error());
    assert_eq!(call(loadings.as_ptr(), states.as_ptr(), c"mm".as_ptr(), ptr::null()), Status::ErrNullPointer.code());
    assert_eq!(call(loadings.as_ptr(), states.as_ptr(), c"mm".as_ptr(), c"".as_ptr()), Status::ErrOutOfRange.code());
    for unit in [c"", c"m,m", c"[mm]", c"m\nm"] {
        assert_eq!(
            call(loadings.as_ptr(), states.as_ptr(), unit.as_ptr(), path.as_ptr()),
            Status::ErrOutOfRange.code()
        );
    }
    // A loading the sweep would refuse, a state it did not write (all
    // zero: no model), a NaN state.
    let mut wrong = loadings.clone();
    wrong[3].axial_control = 7;
    assert_eq!(write(&wrong, &states, 5, c"mm", c"mN", &bad), Status::ErrOutOfRange.code());
    assert!(last_error().contains("loadings[3]"), "{}", last_error());
    let mut unwritten = states.clone();
    unwritten[4] = TubeState::default();
    assert_eq!(write(&loadings, &unwritten, 5, c"mm", c"mN", &bad), Status::ErrOutOfRange.code());
    assert!(last_error().contains("states[4].model"), "{}", last_error());
    let mut nan = states.clone();
    nan[2].twist = f64::NAN;
    assert_eq!(write(&loadings, &nan, 5, c"mm", c"mN", &bad), Status::ErrNotFinite.code());
    assert!(last_error().contains("states[2].twist"), "{}", last_error());
    // The first four of them are fine (a `completed` count).
    assert_eq!(write(&loadings, &unwritten, 4, c"mm", c"mN", &bad), 0);
    assert_eq!(read_cells(&bad).1.len(), 4);
    std::fs::remove_file(&bad).unwrap();
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 2, "{left:?}");
    unsafe { rodkit_tube_free(t) };
    let _ = std::fs::remove_dir_all(&dir);
}

//! DNA in tweezers at finite temperature through the C ABI
//! (src/capi/tweezers.rs): the handle's curve and summary against the Rust
//! API (`rodkit::tweezers`, the reference: the same arithmetic, bitwise),
//! every input checked at the boundary with its status and a message naming
//! the argument, the work sized before anything is computed; then the C
//! driver c_examples/dna_tweezers.c (single curve with --values, the
//! zero-temperature limit, the family) and the Fortran example
//! fortran_examples/dna_tweezers.f90, built through the Makefile, their
//! printed numbers against the Rust API for the same scene (to the printed
//! digits); the force × salt map c_examples/dna_map.c and
//! c_examples/dna_supercoil.c with `--model thermal` (issue 37) against the
//! Rust API too. Needs gcc, gfortran and make (`.ci/deps`).

use rodkit::capi::error::rodkit_last_error_message;
use rodkit::capi::tweezers::*;
use rodkit::tweezers::{Model, Summary, TweezersScene};
use rodkit::Status;
use std::collections::BTreeMap;
use std::ffi::CStr;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::ptr::{null, null_mut};
use std::sync::OnceLock;

#[path = "support/native_build.rs"]
mod native_build;
use native_build::{check, profile, ROOT};

fn last_error() -> String {
    unsafe { CStr::from_ptr(rodkit_last_error_message()) }.to_string_lossy().into_owned()
}

fn spec() -> TweezersSpec {
    let mut s = std::mem::MaybeUninit::<TweezersSpec>::uninit();
    assert_eq!(unsafe { rodkit_tweezers_spec_default(s.as_mut_ptr()) }, 0);
    unsafe { s.assume_init() }
}

fn new(s: &TweezersSpec) -> (i32, *mut Tweezers) {
    let mut h = std::ptr::NonNull::<Tweezers>::dangling().as_ptr(); // not NULL: every failure must clear it
    let st = unsafe { rodkit_tweezers_new(s, &mut h) };
    (st, h)
}

/// The Rust API's curve and summary for a scene (the references).
fn rust_summary(scene: &TweezersScene, points: usize) -> (Vec<rodkit::tweezers::Point>, Summary) {
    let model = Model::new(scene).unwrap();
    let turns = model.default_turns(points).unwrap();
    let curve = model.curve(&turns).unwrap();
    let s = model.summarise(&curve).unwrap();
    (curve, s)
}

/// The default spec is the Rust default scene; its handle's default turns,
/// curve and summary are the Rust API's bitwise (the same arithmetic),
/// every point's `has_buckled` says whether buckled states exist (and
/// `extension_buckled` is 0, not NaN, where none do) and `in_range` is
/// the Rust flag (0 at 40 turns on 1 kbp), the model is the
/// thermal two-phase one with the elastic end loop; the last error is
/// empty after each successful call.
#[test]
fn handle_matches_the_rust_api() {
    let s = spec();
    let d = TweezersScene::default();
    assert_eq!(
        (s.base_pairs, s.force, s.salt, s.kt, s.bending, s.twist),
        (d.base_pairs, d.force, d.salt, d.kt, d.bending, d.twist)
    );
    assert_eq!((s.max_plectonemes, s.hard_core, s.confinement), (d.max_plectonemes as i64, d.hard_core, d.confinement));
    let (st, h) = new(&s);
    assert_eq!(st, 0, "{}", last_error());
    let n = 120;
    let mut turns = vec![0.0; n];
    assert_eq!(unsafe { rodkit_tweezers_default_turns(h, n as i64, turns.as_mut_ptr()) }, 0);
    let mut pts = vec![TweezersPoint::default(); n];
    assert_eq!(unsafe { rodkit_tweezers_curve(h, turns.as_ptr(), n as i64, pts.as_mut_ptr()) }, 0);
    assert_eq!(last_error(), "");
    let mut sum = std::mem::MaybeUninit::<TweezersInfo>::uninit();
    assert_eq!(unsafe { rodkit_tweezers_summary(h, pts.as_ptr(), n as i64, sum.as_mut_ptr()) }, 0, "{}", last_error());
    let sum = unsafe { sum.assume_init() };
    // Far past the plectonemic range (40 turns on 1 kbp): flagged out of range.
    let far = [0.0, 40.0];
    let mut fp = [TweezersPoint::default(); 2];
    assert_eq!(unsafe { rodkit_tweezers_curve(h, far.as_ptr(), 2, fp.as_mut_ptr()) }, 0, "{}", last_error());
    assert_eq!((fp[0].in_range, fp[1].in_range), (1, 0));
    unsafe { rodkit_tweezers_free(h) };

    let (curve, r) = rust_summary(&d, n);
    for (p, q) in pts.iter().zip(&curve) {
        assert_eq!(
            (p.turns, p.extension, p.torque, p.twist, p.writhe),
            (q.turns, q.extension, q.torque, q.twist, q.writhe)
        );
        assert_eq!(
            (p.plectoneme_length, p.plectonemes, p.buckled_probability),
            (q.plectoneme_length, q.plectonemes, q.buckled_probability)
        );
        assert_eq!(
            (p.extension_unbuckled, p.superhelix_radius, p.superhelix_angle),
            (q.extension_unbuckled, q.superhelix_radius, q.superhelix_angle)
        );
        assert_eq!(
            (p.has_buckled == 1, p.extension_buckled),
            (q.extension_buckled.is_some(), q.extension_buckled.unwrap_or(0.0))
        );
        assert_eq!(p.in_range == 1, q.in_range);
    }
    assert!(pts.iter().any(|p| p.has_buckled == 0) && pts.iter().any(|p| p.has_buckled == 1));
    // The default scene (1 pN, 0.1 M) lies in the shipped end-loop table.
    assert_eq!(
        (sum.model, sum.end_loop, sum.kt),
        (SupercoilModel::ThermalTwoPhase, TweezersEndLoop::BuiltinTable, d.kt)
    );
    assert_eq!(
        (sum.buckling_turns, sum.buckling_torque, sum.plateau_torque),
        (r.buckling_turns, r.buckling_torque, r.plateau_torque)
    );
    assert_eq!(
        (sum.plateau_torque_min, sum.plateau_torque_max, sum.overshoot),
        (r.plateau_torque_min, r.plateau_torque_max, r.overshoot)
    );
    assert_eq!(
        (sum.coexistence_torque, sum.slope, sum.extension_jump),
        (r.coexistence_torque, r.slope, r.extension_jump)
    );
    assert_eq!(
        (sum.extension_zero_turns, sum.superhelix_radius, sum.superhelix_angle),
        (r.extension_zero_turns, r.superhelix_radius, r.superhelix_angle)
    );
    assert_eq!(
        (sum.end_loop_energy, sum.plateau_turns_from, sum.plateau_turns_to),
        (r.end_loop_energy, r.plateau_turns.0, r.plateau_turns.1)
    );
    assert_eq!(sum.plateau_points, r.plateau_points as i64);
    assert_eq!(sum.end_loop_correction, r.end_loop_correction);
    assert!(sum.slope < 0.0 && sum.extension_jump > 0.0 && sum.superhelix_radius > 0.0);
}

/// kT = 0 is the zero-temperature limit: the model says so, and the
/// buckled population is 0 or 1 at every point.
#[test]
fn zero_temperature_is_reported() {
    let mut s = spec();
    s.kt = 0.0;
    let (st, h) = new(&s);
    assert_eq!(st, 0, "{}", last_error());
    let n = 60;
    let mut turns = vec![0.0; n];
    let mut pts = vec![TweezersPoint::default(); n];
    let mut sum = std::mem::MaybeUninit::<TweezersInfo>::uninit();
    unsafe {
        assert_eq!(rodkit_tweezers_default_turns(h, n as i64, turns.as_mut_ptr()), 0);
        assert_eq!(rodkit_tweezers_curve(h, turns.as_ptr(), n as i64, pts.as_mut_ptr()), 0);
        assert_eq!(rodkit_tweezers_summary(h, pts.as_ptr(), n as i64, sum.as_mut_ptr()), 0, "{}", last_error());
        rodkit_tweezers_free(h);
    }
    let sum = unsafe { sum.assume_init() };
    assert_eq!((sum.model, sum.kt), (SupercoilModel::ZeroTemperatureTwoPhase, 0.0));
    assert!(pts.iter().all(|p| p.buckled_probability == 0.0 || p.buckled_probability == 1.0));
}

/// A bad spec: what it is, how it is made from the default, its status and
/// the start of its message.
type Case = (&'static str, Box<dyn Fn(&mut TweezersSpec)>, Status, &'static str);

/// Each bad input: its status and a message naming the argument (as the C
/// caller spells it) and the value; a failed rodkit_tweezers_new leaves
/// `*out` NULL. References: the statuses of src/status.rs and the argument
/// names of the header.
#[test]
fn bad_inputs_get_their_status_and_message() {
    unsafe {
        assert_eq!(rodkit_tweezers_spec_default(null_mut()), Status::ErrNullPointer.code());
        assert_eq!(last_error(), "argument `spec` is NULL");
        let mut h = std::ptr::NonNull::<Tweezers>::dangling().as_ptr();
        assert_eq!(rodkit_tweezers_new(null(), &mut h), Status::ErrNullPointer.code());
        assert!(h.is_null() && last_error() == "argument `spec` is NULL");
        assert_eq!(rodkit_tweezers_new(&spec(), null_mut()), Status::ErrNullPointer.code());
        assert_eq!(last_error(), "argument `out` is NULL");
    }
    let cases: Vec<Case> = vec![
        (
            "negative force",
            Box::new(|s| s.force = -1.0),
            Status::ErrNotPositive,
            "argument `spec.force` must be positive (got -1e0)",
        ),
        (
            "salt 0",
            Box::new(|s| s.salt = 0.0),
            Status::ErrNotPositive,
            "argument `spec.salt` must be positive (got 0e0)",
        ),
        ("NaN kT", Box::new(|s| s.kt = f64::NAN), Status::ErrNotFinite, "argument `spec.kt` must be finite (got NaN)"),
        (
            "negative kT",
            Box::new(|s| s.kt = -4.11),
            Status::ErrOutOfRange,
            "argument `spec.kt` must be ≥ 0 (got -4.11e0)",
        ),
        (
            "infinite bending",
            Box::new(|s| s.bending = f64::INFINITY),
            Status::ErrNotFinite,
            "argument `spec.bending` must be finite (got inf)",
        ),
        ("10 bp", Box::new(|s| s.base_pairs = 10.0), Status::ErrOutOfRange, "argument `spec.base_pairs` out of range"),
        (
            "no plectonemes",
            Box::new(|s| s.max_plectonemes = 0),
            Status::ErrOutOfRange,
            "argument `spec.max_plectonemes` out of range: must lie in [1, 64] (got 0)",
        ),
        (
            "end loop 3",
            Box::new(|s| s.end_loop = 4),
            Status::ErrOutOfRange,
            "argument `spec.end_loop` out of range: must be a RodkitTweezersEndLoop 0…3 (got 4)",
        ),
        (
            "end-loop torque 0",
            Box::new(|s| {
                s.end_loop = TweezersEndLoop::Value as i32;
                s.end_loop_torque = 0.0
            }),
            Status::ErrNotPositive,
            "argument `spec.end_loop_torque` must be positive (got 0e0)",
        ),
        (
            "NaN end-loop energy",
            Box::new(|s| s.end_loop_energy = f64::NAN),
            Status::ErrNotFinite,
            "argument `spec.end_loop_energy` must be finite",
        ),
        (
            "twist-stretch without S",
            Box::new(|s| s.twist_stretch = 90.0),
            Status::ErrOutOfRange,
            "a twist–stretch coupling needs a stretch modulus",
        ),
    ];
    for (what, change, status, message) in cases {
        let mut s = spec();
        change(&mut s);
        let (st, h) = new(&s);
        assert_eq!(st, status.code(), "{what}: {}", last_error());
        assert!(h.is_null(), "{what}: a handle on failure");
        assert!(last_error().starts_with(message), "{what}: {}", last_error());
    }

    let (st, h) = new(&spec());
    assert_eq!(st, 0);
    let mut turns = [0.0, 1.0, 2.0];
    let mut pts = [TweezersPoint::default(); 3];
    unsafe {
        // Default turns: the handle, the count, the array.
        assert_eq!(rodkit_tweezers_default_turns(null(), 3, turns.as_mut_ptr()), Status::ErrNullPointer.code());
        assert_eq!(last_error(), "argument `tweezers` is NULL");
        for bad in [0, 1, -5, 1_000_001] {
            assert_eq!(rodkit_tweezers_default_turns(h, bad, turns.as_mut_ptr()), Status::ErrOutOfRange.code());
            assert_eq!(last_error(), format!("argument `points` out of range: must lie in [2, 1000000] (got {bad})"));
        }
        assert_eq!(rodkit_tweezers_default_turns(h, 3, null_mut()), Status::ErrNullPointer.code());
        assert_eq!(last_error(), "argument `turns` is NULL");

        // The curve: sized before its arrays are read (NULL arrays with a
        // huge count give the work limit, not a crash), then the arrays.
        assert_eq!(rodkit_tweezers_curve(h, turns.as_ptr(), 0, pts.as_mut_ptr()), Status::ErrInvalidDimension.code());
        assert!(last_error().starts_with("argument `n` must be in [1, "), "{}", last_error());
        assert_eq!(rodkit_tweezers_curve(h, null(), 1 << 40, null_mut()), Status::ErrWorkLimit.code());
        let e = last_error();
        assert!(
            e.contains("1099511627776 points × 64 plectoneme numbers")
                && e.contains("state evaluations")
                && e.contains("bound 2e8"),
            "{e}"
        );
        assert_eq!(rodkit_tweezers_curve(h, null(), 200_001, null_mut()), Status::ErrWorkLimit.code());
        assert_eq!(rodkit_tweezers_curve(h, null(), 3, pts.as_mut_ptr()), Status::ErrNullPointer.code());
        assert_eq!(last_error(), "argument `turns` is NULL");
        assert_eq!(rodkit_tweezers_curve(h, turns.as_ptr(), 3, null_mut()), Status::ErrNullPointer.code());
        assert_eq!(last_error(), "argument `points` is NULL");
        turns[1] = f64::NAN;
        assert_eq!(rodkit_tweezers_curve(h, turns.as_ptr(), 3, pts.as_mut_ptr()), Status::ErrNotFinite.code());
        assert_eq!(last_error(), "argument `turns[1]` must be finite (got NaN)");
        turns[1] = -1.0;
        assert_eq!(rodkit_tweezers_curve(h, turns.as_ptr(), 3, pts.as_mut_ptr()), Status::ErrOutOfRange.code());
        assert!(
            last_error().starts_with("argument `turns[1]` out of range: must be ≥ 0 (got -1e0)"),
            "{}",
            last_error()
        );
        assert!(pts.iter().all(|p| *p == TweezersPoint::default()), "written on failure");

        // The summary: the handle, the points, their count and values.
        turns[1] = 1.0;
        assert_eq!(rodkit_tweezers_curve(h, turns.as_ptr(), 3, pts.as_mut_ptr()), 0);
        let mut sum = std::mem::MaybeUninit::<TweezersInfo>::uninit();
        assert_eq!(rodkit_tweezers_summary(h, null(), 3, sum.as_mut_ptr()), Status::ErrNullPointer.code());
        assert_eq!(last_error(), "argument `points` is NULL");
        assert_eq!(rodkit_tweezers_summary(h, pts.as_ptr(), 3, null_mut()), Status::ErrNullPointer.code());
        assert_eq!(last_error(), "argument `out` is NULL");
        assert_eq!(rodkit_tweezers_summary(h, pts.as_ptr(), 1, sum.as_mut_ptr()), Status::ErrInvalidDimension.code());
        let mut bad = pts;
        bad[2].has_buckled = 2;
        assert_eq!(rodkit_tweezers_summary(h, bad.as_ptr(), 3, sum.as_mut_ptr()), Status::ErrOutOfRange.code());
        assert_eq!(last_error(), "argument `points[2].has_buckled` out of range: must be 0 or 1 (got 2)");
        let mut bad = pts;
        bad[0].in_range = -1;
        assert_eq!(rodkit_tweezers_summary(h, bad.as_ptr(), 3, sum.as_mut_ptr()), Status::ErrOutOfRange.code());
        assert_eq!(last_error(), "argument `points[0].in_range` out of range: must be 0 or 1 (got -1)");
        let mut bad = pts;
        bad[1].torque = f64::INFINITY;
        assert_eq!(rodkit_tweezers_summary(h, bad.as_ptr(), 3, sum.as_mut_ptr()), Status::ErrNotFinite.code());
        assert_eq!(last_error(), "argument `points[1].torque` must be finite (got inf)");
        let mut bad = pts;
        bad[2].turns = 0.5;
        assert_eq!(rodkit_tweezers_summary(h, bad.as_ptr(), 3, sum.as_mut_ptr()), Status::ErrOutOfRange.code());
        assert!(last_error().contains("`points[2].turns` out of range: the turns must ascend"), "{}", last_error());
        // Three points up to 2 turns do not reach the plectonemic range.
        assert_eq!(rodkit_tweezers_summary(h, pts.as_ptr(), 3, sum.as_mut_ptr()), Status::ErrOutOfRange.code());
        assert!(last_error().contains("points on the plectonemic range"), "{}", last_error());
        rodkit_tweezers_free(h);
        rodkit_tweezers_free(null_mut());
    }
}

// ---------------------------------------------------------------------------
// The drivers, built through the Makefile into this build's target directory
// (CARGO_TARGET_DIR when set: the Makefile's TARGET_DIR).
// ---------------------------------------------------------------------------

fn build_dir() -> PathBuf {
    native_build::test_target_dir().join(profile()).join("native")
}

/// The library, then the tweezers drivers (and the map and supercoil
/// drivers these tests run), in this test build's target directory.
fn drivers() -> &'static PathBuf {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(|| {
        let dir = build_dir();
        let exes: Vec<String> = [
            "c_dna_tweezers_shared",
            "c_dna_tweezers_static",
            "f_dna_tweezers_shared",
            "f_dna_tweezers_static",
            "c_dna_map_shared",
            "c_dna_supercoil_shared",
        ]
        .iter()
        .map(|e| dir.join(e).display().to_string())
        .collect();
        let targets: Vec<&str> = exes.iter().map(String::as_str).collect();
        native_build::build_in_test_target(&targets)
    })
}

fn run(exe: &str, args: &[&str]) -> String {
    let out = Command::new(drivers().join(exe)).args(args).current_dir(ROOT).output().expect(exe);
    check(out, exe)
}

/// Every `name = number` line of a driver's output.
fn values(text: &str) -> BTreeMap<String, f64> {
    text.lines()
        .filter_map(|l| {
            let (k, v) = l.split_once(" = ")?;
            let k = k.trim();
            (!k.starts_with('#')).then_some(())?;
            Some((k.to_string(), v.trim().parse::<f64>().ok()?))
        })
        .collect()
}

/// The summary's values by the drivers' names.
fn named(s: &Summary) -> Vec<(&'static str, f64)> {
    vec![
        ("buckling_turns", s.buckling_turns),
        ("buckling_torque", s.buckling_torque),
        ("plateau_torque", s.plateau_torque),
        ("plateau_torque_min", s.plateau_torque_min),
        ("plateau_torque_max", s.plateau_torque_max),
        ("overshoot", s.overshoot),
        ("coexistence_torque", s.coexistence_torque),
        ("slope", s.slope),
        ("extension_jump", s.extension_jump),
        ("extension_zero_turns", s.extension_zero_turns),
        ("superhelix_radius", s.superhelix_radius),
        ("superhelix_angle", s.superhelix_angle),
        ("end_loop_energy", s.end_loop_energy),
        ("end_loop_correction", s.end_loop_correction),
        ("plateau_turns_from", s.plateau_turns.0),
        ("plateau_turns_to", s.plateau_turns.1),
        ("plateau_points", s.plateau_points as f64),
    ]
}

/// Each printed value equals the Rust one to its printed digits: relative
/// `rel` (%.10g: 5e-10 of the value; es24.16: 1e-15), or `rel` of the
/// scale for values that can be near 0 (the overshoot).
fn assert_values(out: &str, got: &BTreeMap<String, f64>, want: &[(&str, f64)], rel: f64) {
    for (k, w) in want {
        let g = *got.get(*k).unwrap_or_else(|| panic!("`{k}` not printed:\n{out}"));
        assert!((g - w).abs() <= rel * w.abs().max(1.0), "{k} = {g}, Rust {w}\n{out}");
    }
}

/// The C driver with --values on a scene set by every option (2 pN,
/// 0.05 M, 2 kbp, kT 4.11, 150 points): each printed summary value, the
/// scene it echoes, the model and end-loop source, and the curve's last
/// point are the Rust API's for that scene to the printed 10 digits; the
/// static build prints the same; the short report (no --values) has no
/// `name = value` lines; --out writes the curve (CSV, every point) and the
/// SVG.
#[test]
fn c_driver_values_match_rust() {
    let dir = std::env::temp_dir().join(format!("rodkit-tweezers-c-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let args = ["--force", "2", "--salt", "0.05", "--bp", "2000", "--kT", "4.11", "--points", "150"];
    let mut all = vec!["--values"];
    all.extend_from_slice(&args);
    let out_dir = dir.join("a/b");
    all.extend_from_slice(&["--out", out_dir.to_str().unwrap()]);
    let out = run("c_dna_tweezers_shared", &all);
    let got = values(&out);
    let scene = TweezersScene { force: 2.0, salt: 0.05, base_pairs: 2000.0, kt: 4.11, ..Default::default() };
    let (curve, s) = rust_summary(&scene, 150);
    let last = curve.last().unwrap();
    let mut want = named(&s);
    want.extend([("force", 2.0), ("salt", 0.05), ("base_pairs", 2000.0), ("kT", 4.11), ("points", 150.0)]);
    // 2 pN, 0.05 M lies in the shipped end-loop table (builtin_table, 0).
    assert_eq!(rodkit::tweezers::Model::new(&scene).unwrap().end_loop_used(), rodkit::tweezers::EndLoopUsed::Table);
    want.extend([("model", 1.0), ("end_loop", 0.0)]);
    want.extend([("last_turns", last.turns), ("last_extension", last.extension), ("last_torque", last.torque)]);
    want.push(("last_plectonemes", last.plectonemes));
    want.push(("out_of_range_points", curve.iter().filter(|p| !p.in_range).count() as f64));
    assert_values(&out, &got, &want, 1e-9);
    assert!(out.contains("model_name = thermal_two_phase") && out.contains("end_loop_name = builtin_table"), "{out}");
    assert!(got["slope"] < 0.0, "{out}");
    let csv = std::fs::read_to_string(out_dir.join("curve.csv")).unwrap();
    assert_eq!(csv.lines().count(), 151);
    // Written by the library's writer (rodkit_tweezers_write_csv).
    assert!(csv.starts_with(&rodkit::tweezers::CSV_HEADER.join(",")));
    let row: Vec<f64> = csv.lines().last().unwrap().split(',').map(|v| v.parse().unwrap_or(f64::NAN)).collect();
    assert!((row[1] - last.extension).abs() <= 1e-13 * last.extension, "{row:?}");
    let svg = std::fs::read_to_string(out_dir.join("curve.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>") && svg.matches("<polyline").count() == 2);
    let mut no_out = vec!["--values"];
    no_out.extend_from_slice(&args);
    let text = run("c_dna_tweezers_shared", &no_out);
    let strip = |t: &str| t.lines().filter(|l| !l.contains(" s)")).collect::<Vec<_>>().join("\n");
    assert_eq!(strip(&run("c_dna_tweezers_static", &no_out)), strip(&text));
    let report = run("c_dna_tweezers_shared", &args);
    assert!(values(&report).is_empty() && report.contains("plateau torque"), "{report}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The driver's defaults (1 kbp, 1 pN, 0.1 M, kT 4.11, 200 points) and
/// --kT 0 (the zero-temperature model, code 2): the Rust API's values.
#[test]
fn c_driver_defaults_and_zero_temperature_match_rust() {
    for (args, kt, model) in [(&[][..], 4.11, 1.0), (&["--kT", "0", "--points", "80"][..], 0.0, 2.0)] {
        let mut all = vec!["--values"];
        all.extend_from_slice(args);
        let out = run("c_dna_tweezers_shared", &all);
        let got = values(&out);
        let points = got["points"] as usize;
        let (_, s) = rust_summary(&TweezersScene { kt, ..Default::default() }, points);
        let mut want = named(&s);
        want.extend([("model", model), ("kT", kt), ("force", 1.0), ("salt", 0.1), ("base_pairs", 1000.0)]);
        assert_values(&out, &got, &want, 1e-9);
    }
}

/// The family (4 forces × 2 salts × 2 lengths): 16 curves, none failed,
/// a CSV per curve, summary.csv with 16 full rows whose 1 pN, 0.1 M, 1 kbp
/// row is the Rust API's (100 points), and an SVG per length with 8
/// curves in each of its two panels; on 1 thread the same table.
#[test]
fn c_driver_family() {
    let dir = std::env::temp_dir().join(format!("rodkit-tweezers-family-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = run("c_dna_tweezers_shared", &["--values", "--family", "--out", dir.to_str().unwrap()]);
    let got = values(&out);
    assert_eq!((got["curves"], got["failed_curves"]), (16.0, 0.0), "{out}");
    eprintln!("family: {} s", got["seconds"]);
    let summary = std::fs::read_to_string(dir.join("summary.csv")).unwrap();
    let mut lines = summary.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<BTreeMap<&str, &str>> = lines.map(|l| header.iter().copied().zip(l.split(',')).collect()).collect();
    assert_eq!(rows.len(), 16);
    assert!(rows.iter().all(|r| r.len() == header.len() && r["status"] == "0"), "{summary}");
    let row = rows.iter().find(|r| (r["force_pN"], r["salt_M"], r["base_pairs"]) == ("1", "0.1", "1000")).unwrap();
    let (_, s) = rust_summary(&TweezersScene::default(), 100);
    for (k, w) in [
        ("buckling_turns", s.buckling_turns),
        ("buckling_torque_pN_nm", s.buckling_torque),
        ("plateau_torque_pN_nm", s.plateau_torque),
        ("slope_nm_per_turn", s.slope),
        ("extension_jump_nm", s.extension_jump),
        ("extension_zero_turns_nm", s.extension_zero_turns),
        ("superhelix_radius_nm", s.superhelix_radius),
    ] {
        let g: f64 = row[k].parse().unwrap();
        assert!((g - w).abs() <= 1e-9 * w.abs(), "{k} = {g}, Rust {w}");
    }
    assert_eq!(
        std::fs::read_dir(&dir)
            .unwrap()
            .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with("curve_"))
            .count(),
        16
    );
    assert_eq!(std::fs::read_to_string(dir.join("curve_F1_S0.1_1000bp.csv")).unwrap().lines().count(), 101);
    for kbp in [1, 10] {
        let svg = std::fs::read_to_string(dir.join(format!("tweezers_{kbp}kbp.svg"))).unwrap();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert_eq!(svg.matches("<polyline").count(), 16, "{kbp} kbp");
    }
    // One thread: the same table (the numbers do not depend on the threads).
    let table =
        |t: &str| t.lines().filter(|l| !l.contains("curves in") && !l.contains(" = ")).collect::<Vec<_>>().join("\n");
    let one = run("c_dna_tweezers_shared", &["--family", "--threads", "1"]);
    assert_eq!(table(&one), table(&run("c_dna_tweezers_shared", &["--family"])));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Fortran example (default scene, 200 points) prints the Rust API's
/// summary and last point to its printed 16 digits, through the module's
/// types; a negative force is refused (RODKIT_STATUS_ERR_NOT_POSITIVE) with
/// its message. The static build prints the same.
#[test]
fn fortran_example_matches_rust() {
    let out = run("f_dna_tweezers_shared", &[]);
    let got = values(&out);
    let (curve, s) = rust_summary(&TweezersScene::default(), 200);
    let last = curve.last().unwrap();
    let mut want = named(&s);
    // The default scene (1 pN, 0.1 M) lies in the shipped end-loop table (0).
    want.extend([("model", 1.0), ("end_loop", 0.0), ("points", 200.0), ("kT", 4.11)]);
    want.extend([("last_turns", last.turns), ("last_extension", last.extension), ("last_torque", last.torque)]);
    assert_values(&out, &got, &want, 1e-15);
    assert_eq!(got["negative_force_status"], Status::ErrNotPositive.code() as f64, "{out}");
    assert!(out.contains("# negative force: no handle: T"), "{out}");
    assert!(out.contains("argument `spec.force` must be positive (got -1e0)"), "{out}");
    assert_eq!(run("f_dna_tweezers_static", &[]), out);
}

/// The C drivers under valgrind (no invalid access, no definite leak): one
/// curve of 1 kbp, 40 points, written as CSV and SVG, and the thermal map
/// with its data comparison (the threaded family
/// would take minutes there: it runs natively above, on 2 threads, and on
/// 1 thread with the same numbers).
#[test]
fn c_driver_is_clean_under_valgrind() {
    let dir = std::env::temp_dir().join(format!("rodkit-tweezers-vg-{}", std::process::id()));
    let out = Command::new("valgrind")
        .args(["-q", "--error-exitcode=99", "--leak-check=full", "--errors-for-leak-kinds=definite"])
        .args(["--show-leak-kinds=definite"])
        .arg(drivers().join("c_dna_tweezers_shared"))
        .args(["--points", "40", "--out", dir.to_str().unwrap()])
        .current_dir(ROOT)
        .output()
        .expect("run valgrind (.ci/deps installs it)");
    check(out, "valgrind c_dna_tweezers_shared");
    assert!(dir.join("curve.csv").is_file() && dir.join("curve.svg").is_file());
    // The thermal map with the data comparison (issue 37): 2 curves of 30
    // points, the table and every plot (~4 s under valgrind).
    let data = Path::new(ROOT).join("tests/data/tweezers/buckling_torque.csv");
    let map = dir.join("map");
    let out = Command::new("valgrind")
        .args(["-q", "--error-exitcode=99", "--leak-check=full", "--errors-for-leak-kinds=definite"])
        .args(["--show-leak-kinds=definite"])
        .arg(drivers().join("c_dna_map_shared"))
        .args(["--bp", "1000", "--forces", "0.5,1", "--salts", "0.1", "--turns", "auto", "--points", "30", "--data"])
        .args([data.to_str().unwrap(), map.to_str().unwrap()])
        .current_dir(ROOT)
        .output()
        .expect("run valgrind");
    check(out, "valgrind c_dna_map_shared --model thermal");
    assert!(map.join("plateau_torque_vs_force.svg").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Rows of a CSV by its header's names.
fn csv_rows(text: &str) -> Vec<BTreeMap<String, String>> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            assert_eq!(cells.len(), header.len(), "a row of {} cells, header {}: {l}", cells.len(), header.len());
            header.iter().zip(cells).map(|(h, c)| (h.to_string(), c.to_string())).collect()
        })
        .collect()
}

/// The force × salt map (c_examples/dna_map.c, issue 37) with `--model
/// thermal` on a small map (1 kbp, 0.5 and 1 pN × 0.01 and 0.1 M, 60
/// points to 8 turns; and at --kT 0): every summary.csv row names its model
/// (`thermal_two_phase`, `zero_temperature_two_phase`) and kT, and holds
/// the Rust API's values for the same scene and turns (rodkit::tweezers::
/// Model: curve at turns 8 i/59, then summarise) to the CSV's 10 digits
/// under the columns of the same meaning (dna_map.c's header comment):
/// buckling turns and torque under coexistence turns and straight torque,
/// the extension jump, plateau torque/min/max, slope, plateau range,
/// superhelix radius; the columns without a two-phase meaning are empty
/// (instability, plectoneme torque at coexistence, hard-core switch,
/// superhelix turns) and the instability finding is `not_in_model`. The
/// printed table names the model on each row; each curve's CSV has every
/// point with its in_range flag; the SVG families have one polyline per
/// curve. Options of the other model are refused (exit 2, a message).
#[test]
fn c_dna_map_thermal_matches_rust() {
    let dir = std::env::temp_dir().join(format!("rodkit-tweezers-map-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let map = ["--bp", "1000", "--forces", "0.5,1", "--salts", "0.01,0.1", "--turns", "8", "--points", "60"];
    for (kt, model) in [(4.11, "thermal_two_phase"), (0.0, "zero_temperature_two_phase")] {
        let out_dir = dir.join(format!("kT{kt}"));
        let mut args = vec!["--values", "--model", "thermal"];
        let kt_text = format!("{kt}");
        if kt == 0.0 {
            args.extend(["--kT", &kt_text]);
        }
        args.extend(map);
        args.push(out_dir.to_str().unwrap());
        let out = run("c_dna_map_shared", &args);
        let got = values(&out);
        assert_eq!((got["curves"], got["failed_curves"]), (4.0, 0.0), "{out}");
        let table: Vec<&str> = out.lines().filter(|l| l.starts_with("  ") && l.contains('|')).collect();
        assert!(table.len() == 4 && table.iter().all(|l| l.ends_with(&format!("| {model}"))), "{out}");
        let rows = csv_rows(&std::fs::read_to_string(out_dir.join("summary.csv")).unwrap());
        assert_eq!(rows.len(), 4);
        let turns: Vec<f64> = (0..60).map(|i| 8.0 * i as f64 / 59.0).collect();
        for r in &rows {
            let num = |k: &str| r[k].parse::<f64>().unwrap_or_else(|_| panic!("{k} = {:?} in {r:?}", r[k]));
            let scene = TweezersScene {
                force: num("force_pN"),
                salt: num("salt_M"),
                base_pairs: num("base_pairs"),
                kt,
                ..Default::default()
            };
            let m = Model::new(&scene).unwrap();
            // The end loop the Rust model used (the shipped table where it
            // covers the scene, else the elastic loop).
            let end_loop = match m.end_loop_used() {
                rodkit::tweezers::EndLoopUsed::Table => "builtin_table",
                _ => "elastic",
            };
            assert_eq!((r["model"].as_str(), num("kT_pN_nm"), r["end_loop"].as_str()), (model, kt, end_loop), "{r:?}");
            let curve = m.curve(&turns).unwrap();
            let s = m.summarise(&curve).unwrap();
            let close = |k: &str, want: f64| {
                let g = num(k);
                assert!((g - want).abs() <= 1e-9 * want.abs().max(1e-12), "{k} = {g}, Rust {want}: {r:?}");
            };
            assert_eq!((num("status"), num("points")), (0.0, 60.0));
            close("last_turns", 8.0);
            close("out_of_range_points", curve.iter().filter(|p| !p.in_range).count() as f64);
            assert_eq!(r["instability_finding"], "not_in_model");
            for empty in [
                "hard_core_switched",
                "instability_turns",
                "instability_torque_pN_nm",
                "coexistence_torque_plectoneme_pN_nm",
                "superhelix_turns",
            ] {
                assert_eq!(r[empty], "", "{empty} in {r:?}");
            }
            for f in ["coexistence_finding", "plateau_finding", "superhelix_finding"] {
                assert_eq!(r[f], "found", "{f}");
            }
            close("coexistence_turns", s.buckling_turns);
            close("coexistence_torque_straight_pN_nm", s.buckling_torque);
            close("coexistence_extension_jump_nm", s.extension_jump);
            close("plateau_torque_pN_nm", s.plateau_torque);
            close("plateau_torque_min_pN_nm", s.plateau_torque_min);
            close("plateau_torque_max_pN_nm", s.plateau_torque_max);
            close("slope_nm_per_turn", s.slope);
            close("plateau_turns_from", s.plateau_turns.0);
            close("plateau_turns_to", s.plateau_turns.1);
            close("superhelix_radius_nm", s.superhelix_radius);
            // The curve's CSV: every point, its thermal means and in_range.
            let name = format!("curve_F{}_S{}.csv", r["force_pN"], r["salt_M"]);
            let pts = csv_rows(&std::fs::read_to_string(out_dir.join(&name)).unwrap());
            assert_eq!(pts.len(), 60, "{name}");
            for (p, q) in pts.iter().zip(&curve) {
                let ext: f64 = p["extension_nm"].parse().unwrap();
                assert!((ext - q.extension).abs() <= 1e-9 * q.extension.abs().max(1.0), "{name}: {p:?}");
                assert_eq!(p["in_range"] == "1", q.in_range, "{name}: {p:?}");
            }
        }
        for svg in ["extension_vs_turns.svg", "torque_vs_turns.svg"] {
            let text = std::fs::read_to_string(out_dir.join(svg)).unwrap();
            assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"));
            assert_eq!(text.matches("<polyline").count(), 4, "{svg}");
        }
    }
    // Options of the other model: refused, with a message.
    for (args, says) in [
        (vec!["--elements", "40"], "--elements applies to --model full-rod only"),
        (vec!["--model", "full-rod", "--kT", "1"], "--kT applies to --model thermal only"),
        (vec!["--model", "full-rod", "--turns", "auto"], "--turns applies to --model thermal only"),
        (vec!["--model", "rod"], "--model: thermal or full-rod"),
    ] {
        let mut all = args.clone();
        all.push(dir.to_str().unwrap());
        let out = Command::new(drivers().join("c_dna_map_shared")).args(&all).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The map's plateau torque vs force beside the tweezers data (issue 37,
/// `make run`'s report): with --data tests/data/tweezers/buckling_torque.csv
/// the "model vs data" table lists every data row (the two Lee 2023
/// plateaus, the spec's four unverified typical values, labelled so) with
/// the model at its force for each salt - at a force of the map the Rust
/// API's plateau torque (to the printed 2 decimals), between forces the
/// linear interpolation, outside them "outside the map" - and
/// plateau_torque_vs_force.svg has one line per salt, six data points
/// (four with error bars) and a legend naming the sources.
#[test]
fn c_dna_map_plateau_vs_data() {
    let dir = std::env::temp_dir().join(format!("rodkit-tweezers-plateau-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let data = Path::new(ROOT).join("tests/data/tweezers/buckling_torque.csv");
    let args = [
        "--bp",
        "10000",
        "--forces",
        "0.5,1,2",
        "--salts",
        "0.01,0.1",
        "--turns",
        "auto",
        "--points",
        "100",
        "--data",
        data.to_str().unwrap(),
        dir.to_str().unwrap(),
    ];
    let out = run("c_dna_map_shared", &args);
    assert!(out.contains("model vs data (tests/data/tweezers/buckling_torque.csv"), "{out}");
    let rows: Vec<&str> = out.lines().skip_while(|l| !l.contains("model vs data")).skip(2).take(6).collect();
    let model = |force: f64, salt: f64| {
        let scene = TweezersScene { force, salt, base_pairs: 10000.0, ..Default::default() };
        rust_summary(&scene, 100).1.plateau_torque
    };
    let cell = |row: &str, k: usize| row.split('|').nth(k).unwrap().split_whitespace().next().unwrap().to_string();
    // Lee 2023 at 0.5 pN (both signs) and the spec's 0.5 and 1 pN: a map force.
    for (i, force) in [(0, 0.5), (1, 0.5), (2, 0.5), (3, 1.0)] {
        assert!(rows[i].trim_start().starts_with(&format!("{force} ")), "{}", rows[i]);
        assert_eq!(cell(rows[i], 1), format!("{:.2}", model(force, 0.01)), "{}", rows[i]);
        assert_eq!(cell(rows[i], 2), format!("{:.2}", model(force, 0.1)), "{}", rows[i]);
    }
    assert!(rows[0].contains("Lee2023") && rows[0].contains("+7.7 +- 0.2") && rows[1].contains("-7.6 +- 0.3"), "{out}");
    assert!(rows[2..].iter().all(|r| r.contains("spec_unverified")), "{out}");
    assert!(rows[5].trim_start().starts_with("4 ") && rows[5].contains("outside the map"), "{out}");
    let svg = std::fs::read_to_string(dir.join("plateau_torque_vs_force.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert_eq!(svg.matches("<polyline").count(), 2);
    assert!(svg.contains("model, 0.01 M salt") && svg.contains("model, 0.1 M salt"));
    assert!(svg.contains("Lee et al., Nat. Commun. 2023") && svg.contains("UNVERIFIED"));
    // Data markers: 3 squares (Lee 2023 twice in the plot, its legend
    // entries twice) and the spec's diamonds (4 + 1 in the legend).
    assert_eq!(svg.matches("<rect x=").count() - 1, 4, "{svg}");
    assert_eq!(svg.matches("<path d=").count(), 5);
    let _ = std::fs::remove_dir_all(&dir);
}

/// c_examples/dna_supercoil.c with `--model thermal` (issue 37): the same
/// molecule (1 kbp, 1 pN, 0.05 M) in the thermal two-phase model, its
/// --values lines the Rust API's (200 default turns) to the printed 15
/// digits, its report naming the model; a VTK path is refused. The default
/// stays the full rod (tests/native.rs reads its values).
#[test]
fn c_dna_supercoil_thermal_matches_rust() {
    let csv = std::env::temp_dir().join(format!("rodkit-tweezers-supercoil-{}.csv", std::process::id()));
    let out = run("c_dna_supercoil_shared", &["--values", "--model", "thermal", "0.05", "60", csv.to_str().unwrap()]);
    let got = values(&out);
    let scene = TweezersScene { salt: 0.05, ..Default::default() };
    let (curve, s) = rust_summary(&scene, 200);
    let last = curve.last().unwrap();
    let want = [
        ("two_phase_buckling_turns", s.buckling_turns),
        ("two_phase_buckling_torque_pN_nm", s.buckling_torque),
        ("extension_jump_nm", s.extension_jump),
        ("plateau_torque_pN_nm", s.plateau_torque),
        ("slope_nm_per_turn", s.slope),
        ("superhelix_radius_nm", s.superhelix_radius),
        ("last_turns", last.turns),
        ("last_extension_nm", last.extension),
        ("last_torque_pN_nm", last.torque),
        ("points", 200.0),
        ("kT_pN_nm", 4.11),
    ];
    assert_values(&out, &got, &want, 1e-14);
    assert!(!got.contains_key("buckling_turns"), "the full rod's instability is not the two-phase buckling: {out}");
    assert!(out.contains("DNA supercoiling (model thermal_two_phase, kT 4.11 pN nm)"), "{out}");
    assert_eq!(std::fs::read_to_string(&csv).unwrap().lines().count(), 201);
    let _ = std::fs::remove_file(&csv);
    let refused = Command::new(drivers().join("c_dna_supercoil_shared"))
        .args(["--model", "thermal", "0.1", "60", "-", "/tmp/x.vtk"])
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("no shapes"));
}

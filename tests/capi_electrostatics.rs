//! The curve electrostatics/writhe C ABI from Rust: results equal the Rust
//! API's on a ring (and the §3.5 Coulomb ring formula to the near-zone
//! truncation), validation by name, nothing written on failure.

use rodkit::capi::electrostatics::*;
use rodkit::capi::error::rodkit_last_error_message;
use rodkit::Status;
use std::ffi::CStr;
use std::f64::consts::PI;

fn last_error() -> String {
    unsafe { CStr::from_ptr(rodkit_last_error_message()) }.to_string_lossy().into_owned()
}

#[test]
fn ring_energy_writhe_and_validation() {
    // A unit ring through 201 nodes (the last repeats the first), tangents exact.
    let n = 201;
    let s: Vec<f64> = (0..n).map(|k| 2.0 * PI * k as f64 / (n - 1) as f64).collect();
    let xyz: Vec<f64> = s.iter().flat_map(|&v| [v.cos(), v.sin(), 0.0]).collect();
    let tan: Vec<f64> = s.iter().flat_map(|&v| [-v.sin(), v.cos(), 0.0]).collect();
    let mut spec = std::mem::MaybeUninit::<ElectrostaticsSpec>::uninit();
    assert_eq!(unsafe { rodkit_electrostatics_spec_default(spec.as_mut_ptr()) }, 0);
    let mut spec = unsafe { spec.assume_init() };
    let mut out = ElectrostaticEnergy::default();
    // Unset fields are refused by name.
    assert_eq!(unsafe { rodkit_curve_electrostatic_energy(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, n as i64, 1, &spec, &mut out) }, Status::ErrNotFinite.code());
    assert!(last_error().contains("spec.line_charge"), "{}", last_error());
    (spec.line_charge, spec.kappa, spec.a, spec.near_width) = (1.0, 0.0, 0.02, 0.1);
    assert_eq!(unsafe { rodkit_curve_electrostatic_energy(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, n as i64, 1, &spec, &mut out) }, 0, "{}", last_error());
    // §3.5 Coulomb ring 2πR ln cot(a/4R), less the dropped near-zone term
    // 2πR·7δ⁴/(23040R⁴) (tests/electrostatics.rs), Hermite nodes adding O(h⁴).
    let exact = 2.0 * PI * (1.0 / (0.02f64 / 4.0).tan()).ln() - 2.0 * PI * 7.0 * (0.1f64.powi(4) - 0.02f64.powi(4)) / 23040.0;
    assert!((out.total - exact).abs() < 1e-6 * exact, "{} vs {exact}", out.total);
    assert!((out.near + out.far - out.total).abs() < 1e-12 * out.total);
    let mut wr = f64::NAN;
    assert_eq!(unsafe { rodkit_curve_writhe(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, n as i64, 1, 8, &mut wr) }, 0);
    assert!(wr.abs() < 1e-12, "{wr}");
    let mut e_bp = f64::NAN;
    assert_eq!(unsafe { rodkit_curve_base_pair_energy(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, n as i64, 1, &spec, 0.002, &mut e_bp) }, 0);
    // The base-pair sum differs from the continuum at O(b/a) (5 % at b = a/2).
    assert!((e_bp - out.total).abs() < 0.02 * out.total, "{e_bp} vs {}", out.total);
    // Validation: near zone inside the excluded distance, NULL, closed flag,
    // too few nodes, a zero tangent, a short leading dimension; nothing written.
    let before = out;
    spec.near_width = 0.01;
    assert_eq!(unsafe { rodkit_curve_electrostatic_energy(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, n as i64, 1, &spec, &mut out) }, Status::ErrOutOfRange.code());
    assert!(last_error().contains("spec.near_width"), "{}", last_error());
    spec.near_width = 0.1;
    assert_eq!(unsafe { rodkit_curve_electrostatic_energy(std::ptr::null(), xyz.as_ptr(), 3, tan.as_ptr(), 3, n as i64, 1, &spec, &mut out) }, Status::ErrNullPointer.code());
    assert_eq!(unsafe { rodkit_curve_electrostatic_energy(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, n as i64, 2, &spec, &mut out) }, Status::ErrOutOfRange.code());
    assert!(last_error().contains("closed"));
    assert!(unsafe { rodkit_curve_writhe(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, 1, 1, 8, &mut wr) } < 0);
    assert!(last_error().contains("nodes"));
    let mut bad = tan.clone();
    bad[3..6].fill(0.0);
    assert_eq!(unsafe { rodkit_curve_writhe(s.as_ptr(), xyz.as_ptr(), 3, bad.as_ptr(), 3, n as i64, 1, 8, &mut wr) }, Status::ErrOutOfRange.code());
    assert!(last_error().contains("tangents"));
    assert!(unsafe { rodkit_curve_writhe(s.as_ptr(), xyz.as_ptr(), 2, tan.as_ptr(), 3, n as i64, 1, 8, &mut wr) } < 0);
    assert_eq!((out.total, out.near, out.far), (before.total, before.near, before.far));
}

//! The status walk of issue 17 ("no silent wrong answers"): every exported
//! function of include/rodkit.h called from Rust with valid defaults, then
//! with NULL for each pointer argument, NaN and ±Inf in each double field of
//! its input structs (and in each double argument and input array), and
//! out-of-range values of each integer and enum field. References: the
//! header's conventions and the status vocabulary of src/status.rs —
//!
//! - NULL pointer: ERR_NULL_POINTER, the message names the argument;
//! - NaN / ±Inf argument or field: ERR_NOT_FINITE (-3), the message names
//!   the C field exactly (`spec.material.fibre1_k1`);
//! - integer count, index or enum out of range: ERR_OUT_OF_RANGE, the
//!   message says "out of range" and names the field; array lengths,
//!   capacities and leading dimensions: ERR_INVALID_DIMENSION;
//! - success: status ≥ 0, the last-error message empty, every output double
//!   finite; failure: a short message (≤ 400 bytes, no run of 25 digits: no
//!   printed matrix, no 300-digit float).
//!
//! Each deviation is a finding with a stable id; the test fails listing
//! every finding. On the code before issue 17 it found 108. The walk
//! covers every function the header declares, and a second test fails
//! when one is added unwalked (28 were missing before: the writers, the
//! node accessors, the bifurcation lists, the curve summary, the
//! tweezers calls; walking them found nothing to mend).

use rodkit::capi::accuracy::*;
use rodkit::capi::branch::*;
use rodkit::capi::branch_record::*;
use rodkit::capi::continuation::*;
use rodkit::capi::curve::*;
use rodkit::capi::diagnostic::rodkit_diagnostic_panic;
use rodkit::capi::dna_fit::*;
use rodkit::capi::equilibrium::*;
use rodkit::capi::error::{rodkit_last_error_copy, rodkit_last_error_message, rodkit_status_string};
use rodkit::capi::output::*;
use rodkit::capi::rod::*;
use rodkit::capi::rod_spec::*;
use rodkit::capi::supercoil::*;
use rodkit::capi::supercoil_curve::*;
use rodkit::capi::thin_tube::*;
use rodkit::capi::tube::*;
use rodkit::capi::tweezers::*;
use rodkit::capi::version::{rodkit_library_abi_version, rodkit_version};
use rodkit::capi::wall_material::*;
use rodkit::Status;
use std::collections::BTreeMap;
use std::ffi::CStr;
use std::mem::MaybeUninit;
use std::ptr::{null, null_mut};

fn last_error() -> String {
    unsafe { CStr::from_ptr(rodkit_last_error_message()) }.to_string_lossy().into_owned()
}

/// Fill a struct through its `_default` function.
fn filled<T>(f: unsafe extern "C" fn(*mut T) -> i32) -> T {
    let mut v = MaybeUninit::<T>::uninit();
    assert_eq!(unsafe { f(v.as_mut_ptr()) }, 0, "{}", last_error());
    unsafe { v.assume_init() }
}

/// An output struct of plain data, zeroed.
fn zeroed<T>() -> T {
    unsafe { std::mem::zeroed() }
}

/// A field of a C input struct and the values that must be refused.
enum Field<T> {
    /// A double: NaN, +Inf, −Inf → ERR_NOT_FINITE naming it.
    F(&'static str, fn(&mut T) -> &mut f64),
    /// A double whose NaN means "unset" or "none": ±Inf only.
    Inf(&'static str, fn(&mut T) -> &mut f64),
    /// An int32_t enum or flag with values out of its range.
    I32(&'static str, fn(&mut T) -> &mut i32, &'static [i32]),
    /// An int64_t count with values out of its range, and the status
    /// (ERR_OUT_OF_RANGE for counts, ERR_INVALID_DIMENSION for lengths).
    I64(&'static str, fn(&mut T) -> &mut i64, &'static [i64], Status),
}

macro_rules! f {
    ($($p:ident).+) => {
        Field::F(stringify!($($p).+), |s| &mut s.$($p).+)
    };
}
macro_rules! inf {
    ($($p:ident).+) => {
        Field::Inf(stringify!($($p).+), |s| &mut s.$($p).+)
    };
}
macro_rules! i32f {
    ($($p:ident).+, $bad:expr) => {
        Field::I32(stringify!($($p).+), |s| &mut s.$($p).+, $bad)
    };
}
macro_rules! i64f {
    ($($p:ident).+, $bad:expr) => {
        Field::I64(stringify!($($p).+), |s| &mut s.$($p).+, $bad, Status::ErrOutOfRange)
    };
    ($($p:ident).+, $bad:expr, $st:expr) => {
        Field::I64(stringify!($($p).+), |s| &mut s.$($p).+, $bad, $st)
    };
}

const FLAG: &[i32] = &[2, -1];

/// The walk's findings, by id.
#[derive(Default)]
struct Walk {
    findings: BTreeMap<String, String>,
    checks: usize,
}

fn long_digit_run(msg: &str) -> bool {
    msg.split(|c: char| !c.is_ascii_digit()).any(|run| run.len() >= 25)
}

impl Walk {
    /// A finding `id` (`function argument=value`): the values of one
    /// argument are merged into one finding, `function argument`.
    fn finding(&mut self, id: String, text: String) {
        let (key, value) = id.split_once('=').unwrap_or((&id, ""));
        match self.findings.get_mut(key) {
            Some(t) => *t = format!("{t} | {value}"),
            None => {
                let text = if value.is_empty() { text } else { format!("[{value}] {text}") };
                self.findings.insert(key.to_string(), text);
            }
        }
    }

    /// A failure with status `want` whose message holds every needle.
    fn fails(&mut self, id: String, st: i32, want: Status, needles: &[&str]) {
        self.checks += 1;
        let msg = last_error();
        let good = st == want.code()
            && !msg.is_empty()
            && msg.len() <= 400
            && !long_digit_run(&msg)
            && needles.iter().all(|n| msg.contains(n));
        if !good {
            let msg: String = msg.chars().take(300).collect();
            self.finding(id, format!("got {st} {msg:?}; want {} ({want:?}) naming {needles:?}", want.code()));
        }
    }

    /// A success: status ≥ 0, empty last error, every output double finite.
    fn succeeds(&mut self, id: String, st: i32, outputs: &[f64]) {
        self.checks += 1;
        let msg = last_error();
        if st < 0 || !msg.is_empty() {
            self.finding(id, format!("got {st} {msg:?}; want success with an empty message"));
        } else if let Some(i) = outputs.iter().position(|v| !v.is_finite()) {
            self.finding(id, format!("status {st} with output {i} = {:e}", outputs[i]));
        }
    }

    /// NULL for argument `name`: ERR_NULL_POINTER naming it.
    fn null(&mut self, func: &str, name: &str, st: i32) {
        self.fails(format!("{func} {name}=NULL"), st, Status::ErrNullPointer, &[&format!("`{name}`")]);
    }

    /// A double argument `name` through `call`: NaN, ±Inf refused by name.
    fn scalar(&mut self, func: &str, name: &str, call: &dyn Fn(f64) -> i32) {
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let st = call(v);
            self.fails(format!("{func} {name}={v}"), st, Status::ErrNotFinite, &[&format!("`{name}`")]);
        }
    }

    /// An integer argument `name` out of range through `call`.
    fn int_arg(&mut self, func: &str, name: &str, bad: &[i64], want: Status, call: &dyn Fn(i64) -> i32) {
        for &v in bad {
            let st = call(v);
            let needle = format!("`{name}`");
            let mut needles = vec![needle.as_str()];
            if want == Status::ErrOutOfRange {
                needles.push("out of range");
            }
            self.fails(format!("{func} {name}={v}"), st, want, &needles);
        }
    }

    /// Entry 0 of an input array `name` set to NaN, ±Inf through `call`.
    fn array(&mut self, func: &str, name: &str, call: &dyn Fn(f64) -> i32) {
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let st = call(v);
            self.fails(format!("{func} {name}[0]={v}"), st, Status::ErrNotFinite, &[name]);
        }
    }

    /// Every field of `base` (the struct argument `prefix`, e.g. "spec.")
    /// through `call`, which must accept `base` itself.
    fn fields<T: Copy>(&mut self, func: &str, prefix: &str, base: &T, fields: &[Field<T>], call: &dyn Fn(&T) -> i32) {
        let st = call(base);
        self.succeeds(format!("{func} {prefix}* valid"), st, &[]);
        for field in fields {
            let mut s = *base;
            match field {
                Field::F(name, get) | Field::Inf(name, get) => {
                    let nan_too = matches!(field, Field::F(..));
                    for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                        if v.is_nan() && !nan_too {
                            continue;
                        }
                        *get(&mut s) = v;
                        let st = call(&s);
                        let needle = format!("`{prefix}{name}`");
                        self.fails(format!("{func} {prefix}{name}={v}"), st, Status::ErrNotFinite, &[&needle]);
                    }
                }
                Field::I32(name, get, bad) => {
                    for &v in *bad {
                        *get(&mut s) = v;
                        let st = call(&s);
                        let needle = format!("`{prefix}{name}`");
                        self.fails(
                            format!("{func} {prefix}{name}={v}"),
                            st,
                            Status::ErrOutOfRange,
                            &[&needle, "out of range"],
                        );
                    }
                }
                Field::I64(name, get, bad, want) => {
                    for &v in *bad {
                        *get(&mut s) = v;
                        let st = call(&s);
                        let needle = format!("`{prefix}{name}`");
                        let mut needles = vec![needle.as_str()];
                        if *want == Status::ErrOutOfRange {
                            needles.push("out of range");
                        }
                        self.fails(format!("{func} {prefix}{name}={v}"), st, *want, &needles);
                    }
                }
            }
        }
    }
}

// ---------------------------------------------------------------- groups

fn version_and_errors(w: &mut Walk) {
    let (mut a, mut b, mut c) = (0, 0, 0);
    let st = unsafe { rodkit_version(&mut a, &mut b, &mut c) };
    w.succeeds("rodkit_version valid".into(), st, &[]);
    w.null("rodkit_version", "major", unsafe { rodkit_version(null_mut(), &mut b, &mut c) });
    w.null("rodkit_version", "minor", unsafe { rodkit_version(&mut a, null_mut(), &mut c) });
    w.null("rodkit_version", "patch", unsafe { rodkit_version(&mut a, &mut b, null_mut()) });
    // The ABI version is a value, not a status: the header's constant.
    assert_eq!(rodkit_library_abi_version(), rodkit::version::ABI_VERSION);
    for code in [-3, 12345] {
        assert!(!rodkit_status_string(code).is_null());
    }
    let st = rodkit_diagnostic_panic();
    w.fails("rodkit_diagnostic_panic".into(), st, Status::ErrInternal, &["deliberate panic"]);
    let mut buf = [0 as std::ffi::c_char; 8];
    let mut len = 0i64;
    let st = unsafe { rodkit_last_error_copy(buf.as_mut_ptr(), 8, &mut len) };
    // The panic's message does not fit 8 bytes: truncated, still a success.
    assert_eq!(st, Status::InfoTruncated.code());
    w.null("rodkit_last_error_copy", "buffer", unsafe { rodkit_last_error_copy(null_mut(), 8, &mut len) });
    w.int_arg("rodkit_last_error_copy", "capacity", &[0, -1], Status::ErrInvalidDimension, &|c| unsafe {
        rodkit_last_error_copy(buf.as_ptr().cast_mut(), c, &mut 0)
    });
}

fn dna_spec() -> ThinTubeSpec {
    ThinTubeSpec {
        mid_radius: 1.0,
        thickness: 0.4,
        intrinsic_twist: 3f64.sqrt(),
        e1: 800.0,
        e2: 250.0,
        nu12: 0.6,
        g12: 180.0,
    }
}

fn thin_tube(w: &mut Walk) {
    w.null("rodkit_thin_tube_spec_default", "spec", unsafe { rodkit_thin_tube_spec_default(null_mut()) });
    let fields: Vec<Field<ThinTubeSpec>> =
        vec![f!(mid_radius), f!(thickness), f!(intrinsic_twist), f!(e1), f!(e2), f!(nu12), f!(g12)];
    let base = dna_spec();
    let mut alpha = 0.0;
    w.fields("rodkit_thin_tube_helix_angle", "spec.", &base, &fields, &|s| unsafe {
        rodkit_thin_tube_helix_angle(s, &mut 0.0)
    });
    w.null("rodkit_thin_tube_helix_angle", "spec", unsafe { rodkit_thin_tube_helix_angle(null(), &mut alpha) });
    w.null("rodkit_thin_tube_helix_angle", "alpha", unsafe { rodkit_thin_tube_helix_angle(&base, null_mut()) });
    type Matrix = unsafe extern "C" fn(*const ThinTubeSpec, *mut f64, i64) -> i32;
    for (func, m, n, ld) in [
        ("rodkit_thin_tube_coupling_stiffness", rodkit_thin_tube_coupling_stiffness as Matrix, 3, "ldk"),
        ("rodkit_thin_tube_stretch_twist", rodkit_thin_tube_stretch_twist as Matrix, 2, "lds"),
        ("rodkit_thin_tube_rod_stiffness", rodkit_thin_tube_rod_stiffness as Matrix, 6, "ldk"),
    ] {
        let mut k = vec![0.0; n * n];
        let st = unsafe { m(&base, k.as_mut_ptr(), n as i64) };
        w.succeeds(format!("{func} valid"), st, &k);
        if (0..n).any(|i| !(k[i + n * i] > 0.0)) {
            w.finding(format!("{func} diagonal"), format!("diagonal not positive: {k:?}"));
        }
        w.fields(func, "spec.", &base, &fields, &|s| unsafe { m(s, vec![0.0; n * n].as_mut_ptr(), n as i64) });
        w.null(func, "spec", unsafe { m(null(), k.as_mut_ptr(), n as i64) });
        let sym = if ld == "ldk" { "k" } else { "s" };
        w.null(func, sym, unsafe { m(&base, null_mut(), n as i64) });
        w.int_arg(func, ld, &[n as i64 - 1, -1], Status::ErrInvalidDimension, &|v| unsafe {
            m(&base, vec![0.0; n * n].as_mut_ptr(), v)
        });
    }
    let func = "rodkit_thin_tube_free_response";
    w.fields(func, "spec.", &base, &fields, &|s| unsafe {
        let mut r: FreeTubeResponse = zeroed();
        rodkit_thin_tube_free_response(s, &mut r)
    });
    w.null(func, "spec", unsafe { rodkit_thin_tube_free_response(null(), &mut zeroed()) });
    w.null(func, "response", unsafe { rodkit_thin_tube_free_response(&base, null_mut()) });
}

fn dna_fit(w: &mut Walk) {
    let func = "rodkit_dna_fit_thin_wall";
    let pi = std::f64::consts::PI;
    let args = [1100.0, 440.0, -90.0, 1.0, pi / 3.0, 0.4, 0.3];
    let names = ["stretch", "twist", "coupling", "mid_radius", "helix_angle", "thickness", "nu12"];
    let call = |a: &[f64; 7], out: *mut DnaFit| unsafe {
        rodkit_dna_fit_thin_wall(a[0], a[1], a[2], a[3], a[4], a[5], a[6], out)
    };
    let mut fit: DnaFit = zeroed();
    let st = call(&args, &mut fit);
    let s = fit.spec;
    w.succeeds(
        format!("{func} valid"),
        st,
        &[s.mid_radius, s.thickness, s.intrinsic_twist, s.e1, s.e2, s.nu12, s.g12, fit.stretch, fit.twist_rate],
    );
    w.null(func, "out", call(&args, null_mut()));
    for (k, name) in names.iter().enumerate() {
        w.scalar(func, name, &|v| {
            let mut a = args;
            a[k] = v;
            call(&a, &mut zeroed())
        });
    }
}

// ---------------------------------------------------------------- tube

fn svk_spec() -> TubeSpec {
    let mut spec = filled(rodkit_tube_spec_default);
    (spec.inner_radius, spec.outer_radius) = (0.6, 1.4);
    let m = &mut spec.material;
    m.law = WallLawKind::SaintVenantKirchhoff as i32;
    m.intrinsic_twist = 1.7;
    (m.e1, m.e2, m.e3, m.nu12, m.nu13, m.nu23, m.g12, m.g13, m.g23) = (10.0, 2.0, 1.5, 0.35, 0.3, 0.4, 1.2, 0.8, 0.6);
    spec
}

fn fibre_spec() -> TubeSpec {
    let mut spec = filled(rodkit_tube_spec_default);
    (spec.inner_radius, spec.outer_radius) = (0.8, 1.0);
    let m = &mut spec.material;
    m.law = WallLawKind::FibreReinforced as i32;
    (m.shear_modulus, m.lame_lambda, m.fibre_families) = (1.0, 2.0, 2);
    (m.fibre1_k1, m.fibre1_k2, m.fibre1_angle, m.fibre1_hand) = (1.0, 1.0, 0.5, 1.0);
    (m.fibre2_k1, m.fibre2_k2, m.fibre2_angle, m.fibre2_hand) = (1.0, 1.0, -0.5, -1.0);
    spec
}

fn new_tube(spec: &TubeSpec) -> i32 {
    let mut t = null_mut();
    let st = unsafe { rodkit_tube_new(spec, &mut t) };
    unsafe { rodkit_tube_free(t) };
    st
}

fn tube(w: &mut Walk) {
    w.null("rodkit_tube_spec_default", "spec", unsafe { rodkit_tube_spec_default(null_mut()) });
    w.null("rodkit_tube_loading_default", "loading", unsafe { rodkit_tube_loading_default(null_mut()) });
    w.null("rodkit_wall_material_spec_default", "spec", unsafe { rodkit_wall_material_spec_default(null_mut()) });
    let func = "rodkit_tube_new";
    let common: Vec<Field<TubeSpec>> = vec![
        f!(inner_radius),
        f!(outer_radius),
        f!(rel_tol),
        i32f!(model, &[-1, 3]),
        i64f!(intervals, &[-1, 1, 257]),
        i32f!(material.law, &[0, 4]),
        i32f!(material.incompressible, FLAG),
    ];
    let svk: Vec<Field<TubeSpec>> = vec![
        f!(material.intrinsic_twist),
        f!(material.e1),
        f!(material.e2),
        f!(material.e3),
        f!(material.nu12),
        f!(material.nu13),
        f!(material.nu23),
        f!(material.g12),
        f!(material.g13),
        f!(material.g23),
    ];
    let fibre: Vec<Field<TubeSpec>> = vec![
        f!(material.shear_modulus),
        f!(material.lame_lambda),
        i64f!(material.fibre_families, &[-1, 3]),
        f!(material.fibre1_k1),
        f!(material.fibre1_k2),
        inf!(material.fibre1_angle),
        f!(material.fibre1_hand),
        f!(material.fibre2_k1),
        f!(material.fibre2_k2),
        inf!(material.fibre2_angle),
        f!(material.fibre2_hand),
    ];
    w.fields(func, "spec.", &svk_spec(), &common, &|s| new_tube(s));
    w.fields(func, "spec.", &svk_spec(), &svk, &|s| new_tube(s));
    w.fields(func, "spec.", &fibre_spec(), &fibre, &|s| new_tube(s));
    w.null(func, "spec", unsafe { rodkit_tube_new(null(), &mut null_mut()) });
    w.null(func, "out", unsafe { rodkit_tube_new(&svk_spec(), null_mut()) });
    unsafe { rodkit_tube_free(null_mut()) };

    let mut t = null_mut();
    assert_eq!(unsafe { rodkit_tube_new(&svk_spec(), &mut t) }, 0, "{}", last_error());
    let t = t as *const Tube;
    let mut loading = filled(rodkit_tube_loading_default);
    loading.axial = 1.01;
    let lf: Vec<Field<TubeLoading>> = vec![
        i32f!(axial_control, &[-1, 2]),
        f!(axial),
        i32f!(torsion_control, &[-1, 2]),
        f!(torsion),
        f!(inner_pressure),
        f!(outer_pressure),
        i32f!(closed_ends, FLAG),
    ];
    let func = "rodkit_tube_solve";
    w.fields(func, "loading.", &loading, &lf, &|l| unsafe { rodkit_tube_solve(t, l, &mut TubeState::default()) });
    let mut state = TubeState::default();
    let st = unsafe { rodkit_tube_solve(t, &loading, &mut state) };
    let s = state;
    w.succeeds(
        format!("{func} valid"),
        st,
        &[s.stretch, s.twist, s.wall_force, s.torque, s.deformed_inner_radius, s.deformed_outer_radius],
    );
    if !(s.deformed_inner_radius > 0.0 && s.deformed_outer_radius > s.deformed_inner_radius) {
        w.finding(format!("{func} radii"), format!("radii {s:?}"));
    }
    w.null(func, "tube", unsafe { rodkit_tube_solve(null(), &loading, &mut state) });
    w.null(func, "loading", unsafe { rodkit_tube_solve(t, null(), &mut state) });
    w.null(func, "out", unsafe { rodkit_tube_solve(t, &loading, null_mut()) });

    let func = "rodkit_tube_profile";
    let mut count = 0i64;
    let st = unsafe {
        rodkit_tube_profile(
            t,
            &loading,
            0,
            null_mut(),
            null_mut(),
            null_mut(),
            null_mut(),
            null_mut(),
            null_mut(),
            &mut count,
        )
    };
    w.succeeds(format!("{func} size query"), st, &[]);
    let n = count.max(1) as usize;
    let mut cols = vec![vec![0.0; n]; 6];
    let profile = |l: *const TubeLoading, cap: i64, cols: &mut [Vec<f64>], null_col: usize, cnt: *mut i64| unsafe {
        let mut p: Vec<*mut f64> = cols.iter_mut().map(|c| c.as_mut_ptr()).collect();
        if null_col < 6 {
            p[null_col] = null_mut();
        }
        rodkit_tube_profile(t, l, cap, p[0], p[1], p[2], p[3], p[4], p[5], cnt)
    };
    let st = profile(&loading, n as i64, &mut cols, 6, &mut count);
    w.succeeds(format!("{func} valid"), st, &cols.concat());
    w.fields(func, "loading.", &loading, &lf, &|l| profile(l, n as i64, &mut vec![vec![0.0; n]; 6], 6, &mut 0));
    for (k, name) in ["reference_radius", "radius", "sigma_rr", "sigma_tt", "sigma_zz", "sigma_tz"].iter().enumerate() {
        w.null(func, name, profile(&loading, n as i64, &mut cols, k, &mut count));
    }
    w.null(func, "loading", profile(null(), n as i64, &mut cols, 6, &mut count));
    w.null(func, "count", profile(&loading, n as i64, &mut cols, 6, null_mut()));
    w.null(func, "tube", unsafe {
        rodkit_tube_profile(
            null(),
            &loading,
            0,
            null_mut(),
            null_mut(),
            null_mut(),
            null_mut(),
            null_mut(),
            null_mut(),
            &mut count,
        )
    });
    w.int_arg(func, "capacity", &[-1, n as i64 - 1], Status::ErrInvalidDimension, &|c| {
        profile(&loading, c, &mut vec![vec![0.0; n]; 6], 6, &mut 0)
    });

    let func = "rodkit_tube_sweep";
    let loads = [loading, TubeLoading { axial: 1.02, ..loading }];
    let mut states = [TubeState::default(); 2];
    let mut done = 0i64;
    let st = unsafe { rodkit_tube_sweep(t, loads.as_ptr(), 2, states.as_mut_ptr(), None, null_mut(), &mut done) };
    w.succeeds(format!("{func} valid"), st, &[states[1].stretch, states[1].torque, states[1].deformed_outer_radius]);
    w.fields(func, "loadings[0].", &loading, &lf, &|l| unsafe {
        rodkit_tube_sweep(t, l, 1, [TubeState::default()].as_mut_ptr(), None, null_mut(), null_mut())
    });
    w.null(func, "tube", unsafe {
        rodkit_tube_sweep(null(), loads.as_ptr(), 2, states.as_mut_ptr(), None, null_mut(), &mut done)
    });
    w.null(func, "loadings", unsafe {
        rodkit_tube_sweep(t, null(), 2, states.as_mut_ptr(), None, null_mut(), &mut done)
    });
    w.null(func, "states", unsafe { rodkit_tube_sweep(t, loads.as_ptr(), 2, null_mut(), None, null_mut(), &mut done) });
    w.int_arg(func, "count", &[-1], Status::ErrInvalidDimension, &|c| unsafe {
        rodkit_tube_sweep(t, loads.as_ptr(), c, [TubeState::default(); 2].as_mut_ptr(), None, null_mut(), null_mut())
    });

    let func = "rodkit_tube_sweep_write_csv";
    let dir = std::env::temp_dir().join(format!("rodkit_walk_tube_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = std::ffi::CString::new(dir.join("sweep.csv").to_str().unwrap()).unwrap();
    let (mm, mn) = (c"mm", c"mN");
    let write = |l: *const TubeLoading,
                 s: *const TubeState,
                 n: i64,
                 lu: *const std::ffi::c_char,
                 fu: *const std::ffi::c_char,
                 p: *const std::ffi::c_char| unsafe { rodkit_tube_sweep_write_csv(l, s, n, lu, fu, p) };
    w.succeeds(
        format!("{func} valid"),
        write(loads.as_ptr(), states.as_ptr(), 2, mm.as_ptr(), mn.as_ptr(), csv.as_ptr()),
        &[],
    );
    w.null(func, "loadings", write(null(), states.as_ptr(), 2, mm.as_ptr(), mn.as_ptr(), csv.as_ptr()));
    w.null(func, "states", write(loads.as_ptr(), null(), 2, mm.as_ptr(), mn.as_ptr(), csv.as_ptr()));
    w.null(func, "length_unit", write(loads.as_ptr(), states.as_ptr(), 2, null(), mn.as_ptr(), csv.as_ptr()));
    w.null(func, "force_unit", write(loads.as_ptr(), states.as_ptr(), 2, mm.as_ptr(), null(), csv.as_ptr()));
    w.null(func, "path", write(loads.as_ptr(), states.as_ptr(), 2, mm.as_ptr(), mn.as_ptr(), null()));
    w.int_arg(func, "count", &[-1], Status::ErrInvalidDimension, &|n| {
        write(loads.as_ptr(), states.as_ptr(), n, mm.as_ptr(), mn.as_ptr(), csv.as_ptr())
    });
    std::fs::remove_dir_all(&dir).unwrap();

    type Matrix = unsafe extern "C" fn(*const Tube, *mut f64, i64, *mut f64) -> i32;
    unsafe extern "C" fn stretch_twist(t: *const Tube, s: *mut f64, lds: i64, _: *mut f64) -> i32 {
        rodkit_tube_stretch_twist(t, s, lds)
    }
    for (func, m, n, ld, out) in [
        ("rodkit_tube_coupling_stiffness", rodkit_tube_coupling_stiffness as Matrix, 3, "ldk", "k"),
        ("rodkit_tube_stretch_twist", stretch_twist as Matrix, 2, "lds", "s"),
        ("rodkit_tube_rod_stiffness", rodkit_tube_rod_stiffness as Matrix, 6, "ldk", "k"),
    ] {
        let mut k = vec![0.0; n * n];
        let mut est = 0.0;
        let st = unsafe { m(t, k.as_mut_ptr(), n as i64, &mut est) };
        w.succeeds(format!("{func} valid"), st, &k);
        if (0..n).any(|i| !(k[i + n * i] > 0.0)) {
            w.finding(format!("{func} diagonal"), format!("diagonal not positive: {k:?}"));
        }
        w.null(func, "tube", unsafe { m(null(), k.as_mut_ptr(), n as i64, &mut est) });
        w.null(func, out, unsafe { m(t, null_mut(), n as i64, &mut est) });
        w.int_arg(func, ld, &[n as i64 - 1, -1], Status::ErrInvalidDimension, &|v| unsafe {
            m(t, vec![0.0; n * n].as_mut_ptr(), v, null_mut())
        });
    }
    unsafe { rodkit_tube_free(t.cast_mut()) };
}

// ---------------------------------------------------------------- curve

fn curve(w: &mut Walk) {
    use std::f64::consts::PI;
    w.null("rodkit_electrostatics_spec_default", "spec", unsafe { rodkit_electrostatics_spec_default(null_mut()) });
    // A unit ring through 41 nodes (the last repeats the first), tangents exact.
    let n = 41usize;
    let s: Vec<f64> = (0..n).map(|k| 2.0 * PI * k as f64 / (n - 1) as f64).collect();
    let xyz: Vec<f64> = s.iter().flat_map(|&v| [v.cos(), v.sin(), 0.0]).collect();
    let tan: Vec<f64> = s.iter().flat_map(|&v| [-v.sin(), v.cos(), 0.0]).collect();
    let mut spec = filled(rodkit_electrostatics_spec_default);
    (spec.line_charge, spec.kappa, spec.a, spec.near_width) = (1.0, 0.0, 0.02, 0.1);
    let sf: Vec<Field<ElectrostaticsSpec>> =
        vec![f!(line_charge), f!(kappa), f!(a), f!(near_width), i64f!(order, &[1, 33])];
    // One curve call with arrays (s, xyz, tangents) possibly perturbed.
    struct Curve<'a> {
        s: &'a [f64],
        xyz: &'a [f64],
        tan: &'a [f64],
    }
    let c = Curve { s: &s, xyz: &xyz, tan: &tan };
    let n = n as i64;

    let func = "rodkit_curve_electrostatic_energy";
    let energy = |c: &Curve,
                  sp: *const ElectrostaticsSpec,
                  ld: i64,
                  nodes: i64,
                  closed: i32,
                  e: *mut ElectrostaticEnergy| unsafe {
        rodkit_curve_electrostatic_energy(c.s.as_ptr(), c.xyz.as_ptr(), ld, c.tan.as_ptr(), 3, nodes, closed, sp, e)
    };
    let mut e = ElectrostaticEnergy::default();
    let st = energy(&c, &spec, 3, n, 1, &mut e);
    w.succeeds(format!("{func} valid"), st, &[e.total, e.near, e.far]);
    w.fields(func, "spec.", &spec, &sf, &|sp| energy(&c, sp, 3, n, 1, &mut ElectrostaticEnergy::default()));
    w.null(func, "spec", energy(&c, null(), 3, n, 1, &mut e));
    w.null(func, "energy", energy(&c, &spec, 3, n, 1, null_mut()));
    w.null(func, "xyz", unsafe {
        rodkit_curve_electrostatic_energy(s.as_ptr(), null(), 3, tan.as_ptr(), 3, n, 1, &spec, &mut e)
    });
    w.null(func, "tangents", unsafe {
        rodkit_curve_electrostatic_energy(s.as_ptr(), xyz.as_ptr(), 3, null(), 3, n, 1, &spec, &mut e)
    });
    w.int_arg(func, "closed", &[2, -1], Status::ErrOutOfRange, &|v| {
        energy(&c, &spec, 3, n, v as i32, &mut ElectrostaticEnergy::default())
    });
    w.int_arg(func, "nodes", &[1, -1], Status::ErrOutOfRange, &|v| {
        energy(&c, &spec, 3, v, 1, &mut ElectrostaticEnergy::default())
    });
    w.int_arg(func, "ldx", &[2, -1], Status::ErrInvalidDimension, &|v| {
        energy(&c, &spec, v, n, 1, &mut ElectrostaticEnergy::default())
    });
    for (name, which) in [("s", 0), ("xyz", 1), ("tangents", 2)] {
        w.array(func, name, &|v| {
            let (mut s2, mut x2, mut t2) = (s.clone(), xyz.clone(), tan.clone());
            [&mut s2, &mut x2, &mut t2][which][0] = v;
            energy(&Curve { s: &s2, xyz: &x2, tan: &t2 }, &spec, 3, n, 1, &mut ElectrostaticEnergy::default())
        });
    }

    let func = "rodkit_curve_base_pair_energy";
    let bp = |sp: *const ElectrostaticsSpec, spacing: f64, out: *mut f64| unsafe {
        rodkit_curve_base_pair_energy(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, n, 1, sp, spacing, out)
    };
    let mut v = 0.0;
    let st = bp(&spec, 0.01, &mut v);
    w.succeeds(format!("{func} valid"), st, &[v]);
    w.fields(func, "spec.", &spec, &sf, &|sp| bp(sp, 0.01, &mut 0.0));
    w.null(func, "spec", bp(null(), 0.01, &mut v));
    w.null(func, "energy", bp(&spec, 0.01, null_mut()));
    w.scalar(func, "spacing", &|x| bp(&spec, x, &mut 0.0));

    let func = "rodkit_curve_writhe";
    let writhe = |order: i64, out: *mut f64| unsafe {
        rodkit_curve_writhe(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, n, 1, order, out)
    };
    let st = writhe(8, &mut v);
    w.succeeds(format!("{func} valid"), st, &[v]);
    w.null(func, "writhe_out", writhe(8, null_mut()));
    w.int_arg(func, "order", &[1, 33], Status::ErrOutOfRange, &|o| writhe(o, &mut 0.0));
    w.array(func, "xyz", &|x| {
        let mut x2 = xyz.clone();
        x2[0] = x;
        unsafe { rodkit_curve_writhe(s.as_ptr(), x2.as_ptr(), 3, tan.as_ptr(), 3, n, 1, 8, &mut 0.0) }
    });

    let func = "rodkit_curve_electrostatic_energy_within";
    let within = |sp: *const ElectrostaticsSpec, tol: f64, out: *mut EnergyWithin| unsafe {
        rodkit_curve_electrostatic_energy_within(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, n, 1, sp, tol, out)
    };
    let mut o: EnergyWithin = zeroed();
    let st = within(&spec, 1e-4, &mut o);
    w.succeeds(format!("{func} valid"), st, &[o.total, o.near, o.far, o.near_width, o.estimate]);
    // near_width and order are ignored here (chosen by the call).
    let used: Vec<Field<ElectrostaticsSpec>> = vec![f!(line_charge), f!(kappa), f!(a)];
    w.fields(func, "spec.", &spec, &used, &|sp| within(sp, 1e-4, &mut zeroed()));
    w.null(func, "spec", within(null(), 1e-4, &mut o));
    w.null(func, "out", within(&spec, 1e-4, null_mut()));
    w.scalar(func, "tolerance", &|x| within(&spec, x, &mut zeroed()));
}

// ---------------------------------------------------------------- rod

/// A Cosserat cantilever carrying all four loads (every load field used),
/// with a contact diameter; 2 elements of Gauss(2).
fn rod_spec() -> RodSpec {
    let mut s = filled(rodkit_rod_spec_default);
    s.length = 1.0;
    (s.bending1, s.bending2, s.twist, s.shear1, s.shear2, s.stretch) = (1.0, 1.2, 0.8, 1e4, 1e4, 2e4);
    (s.twist_stretch, s.bend_shear) = (0.1, 0.05);
    let dead = LoadFrame::Dead as i32;
    (s.tip_force_frame, s.tip_force_x, s.tip_force_y, s.tip_force_z) = (dead, 0.1, 0.0, 0.0);
    (s.tip_moment_frame, s.tip_moment_x, s.tip_moment_y, s.tip_moment_z) = (dead, 0.0, 0.1, 0.0);
    (s.distributed_force_frame, s.distributed_force_x, s.distributed_force_y, s.distributed_force_z) =
        (dead, 0.0, 0.0, -0.1);
    (s.distributed_couple_frame, s.distributed_couple_x, s.distributed_couple_y, s.distributed_couple_z) =
        (dead, 0.0, 0.0, 0.1);
    (s.stages, s.elements, s.diameter) = (2, 2, 0.01);
    s
}

fn new_rod(s: &RodSpec) -> i32 {
    let mut r = null_mut();
    let st = unsafe { rodkit_rod_new(s, &mut r) };
    unsafe { rodkit_rod_free(r) };
    st
}

fn rod(w: &mut Walk) {
    w.null("rodkit_rod_spec_default", "spec", unsafe { rodkit_rod_spec_default(null_mut()) });
    w.null("rodkit_continuation_options_default", "options", unsafe {
        rodkit_continuation_options_default(null_mut())
    });
    let func = "rodkit_rod_new";
    let cantilever: Vec<Field<RodSpec>> = vec![
        f!(length),
        i32f!(kirchhoff, FLAG),
        f!(bending1),
        f!(bending2),
        f!(twist),
        f!(shear1),
        f!(shear2),
        f!(stretch),
        f!(twist_stretch),
        f!(bend_shear),
        f!(intrinsic_u1),
        f!(intrinsic_u2),
        f!(intrinsic_u3),
        f!(intrinsic_v1),
        f!(intrinsic_v2),
        f!(intrinsic_v3),
        i32f!(supports, &[0, 6]),
        i32f!(tip_force_frame, &[-1, 3]),
        f!(tip_force_x),
        f!(tip_force_y),
        f!(tip_force_z),
        i32f!(tip_moment_frame, &[-1, 3]),
        f!(tip_moment_x),
        f!(tip_moment_y),
        f!(tip_moment_z),
        i32f!(distributed_force_frame, &[-1, 3]),
        f!(distributed_force_x),
        f!(distributed_force_y),
        f!(distributed_force_z),
        i32f!(distributed_couple_frame, &[-1, 3]),
        f!(distributed_couple_x),
        f!(distributed_couple_y),
        f!(distributed_couple_z),
        i32f!(scheme, &[0, 3]),
        i64f!(stages, &[1, 5]),
        i64f!(elements, &[0, -1, 1 << 40]),
        f!(diameter),
    ];
    w.fields(func, "spec.", &rod_spec(), &cantilever, &|s| new_rod(s));
    let mut clamped = rod_spec();
    clamped.supports = RodSupports::Clamped as i32;
    (clamped.tip_force_frame, clamped.tip_moment_frame) = (0, 0);
    (clamped.end_x, clamped.end_y, clamped.end_z) = (0.0, 0.1, 0.9);
    let ends: Vec<Field<RodSpec>> = vec![
        f!(end_x),
        f!(end_y),
        f!(end_z),
        f!(end_q0),
        f!(end_q1),
        f!(end_q2),
        f!(end_q3),
        f!(end_dx),
        f!(end_dy),
        f!(end_dz),
    ];
    w.fields(func, "spec.", &clamped, &ends, &|s| new_rod(s));
    let mut twisted = clamped;
    twisted.supports = RodSupports::Twisted as i32;
    twisted.end_tension = 0.5;
    w.fields(func, "spec.", &twisted, &[f!(end_tension)], &|s| new_rod(s));
    let mut kirchhoff = rod_spec();
    kirchhoff.kirchhoff = 1;
    w.fields(func, "spec.", &kirchhoff, &[f!(bending1), f!(bending2), f!(twist)], &|s| new_rod(s));
    w.null(func, "spec", unsafe { rodkit_rod_new(null(), &mut null_mut()) });
    w.null(func, "out", unsafe { rodkit_rod_new(&rod_spec(), null_mut()) });
    // A length whose scales overflow is refused by name (issue 17).
    let huge = RodSpec { length: f64::MAX, ..rod_spec() };
    w.fails(format!("{func} spec.length=DBL_MAX"), new_rod(&huge), Status::ErrOutOfRange, &["`spec.length`"]);

    let func = "rodkit_rod_new_general";
    let mut k6 = [0.0; 36];
    for (i, d) in [1.0, 1.2, 0.8, 1e4, 1e4, 2e4].iter().enumerate() {
        k6[i * 7] = *d;
    }
    let general = |s: *const RodSpec, k: *const f64, ldk: i64| unsafe {
        let mut r = null_mut();
        let st = rodkit_rod_new_general(s, k, ldk, &mut r);
        rodkit_rod_free(r);
        st
    };
    let st = general(&rod_spec(), k6.as_ptr(), 6);
    w.succeeds(format!("{func} valid"), st, &[]);
    w.null(func, "spec", general(null(), k6.as_ptr(), 6));
    w.null(func, "stiffness", general(&rod_spec(), null(), 6));
    w.null(func, "out", unsafe { rodkit_rod_new_general(&rod_spec(), k6.as_ptr(), 6, null_mut()) });
    w.int_arg(func, "ldk", &[5, -1], Status::ErrInvalidDimension, &|v| general(&rod_spec(), k6.as_ptr(), v));
    w.array(func, "stiffness", &|v| {
        let mut k = k6;
        k[0] = v;
        general(&rod_spec(), k.as_ptr(), 6)
    });
    w.fields(func, "spec.", &rod_spec(), &[f!(length), f!(intrinsic_u1), f!(tip_force_x)], &|s| {
        general(s, k6.as_ptr(), 6)
    });

    // The handle's kernels.
    let mut rod = null_mut();
    assert_eq!(unsafe { rodkit_rod_new(&rod_spec(), &mut rod) }, 0, "{}", last_error());
    let mut n = 0i64;
    let func = "rodkit_rod_unknowns";
    w.succeeds(format!("{func} valid"), unsafe { rodkit_rod_unknowns(rod, &mut n) }, &[]);
    w.null(func, "rod", unsafe { rodkit_rod_unknowns(null(), &mut n) });
    w.null(func, "n", unsafe { rodkit_rod_unknowns(rod, null_mut()) });
    let nu = n as usize;
    let func = "rodkit_rod_straight_state";
    let mut x = vec![0.0; nu];
    w.succeeds(format!("{func} valid"), unsafe { rodkit_rod_straight_state(rod, x.as_mut_ptr(), n) }, &x);
    w.null(func, "rod", unsafe { rodkit_rod_straight_state(null(), x.as_mut_ptr(), n) });
    w.null(func, "x", unsafe { rodkit_rod_straight_state(rod, null_mut(), n) });
    w.int_arg(func, "n", &[n - 1, -1], Status::ErrInvalidDimension, &|v| unsafe {
        rodkit_rod_straight_state(rod, vec![0.0; nu + 1].as_mut_ptr(), v)
    });

    let func = "rodkit_rod_residual";
    let mut r = vec![0.0; nu];
    let st = unsafe { rodkit_rod_residual(rod, x.as_ptr(), n, 0.5, r.as_mut_ptr()) };
    w.succeeds(format!("{func} valid"), st, &r);
    w.null(func, "rod", unsafe { rodkit_rod_residual(null_mut(), x.as_ptr(), n, 0.5, r.as_mut_ptr()) });
    w.null(func, "x", unsafe { rodkit_rod_residual(rod, null(), n, 0.5, r.as_mut_ptr()) });
    w.null(func, "r", unsafe { rodkit_rod_residual(rod, x.as_ptr(), n, 0.5, null_mut()) });
    w.scalar(func, "lambda", &|l| unsafe { rodkit_rod_residual(rod, x.as_ptr(), n, l, vec![0.0; nu].as_mut_ptr()) });
    w.array(func, "x", &|v| {
        let mut x2 = x.clone();
        x2[0] = v;
        unsafe { rodkit_rod_residual(rod, x2.as_ptr(), n, 0.5, vec![0.0; nu].as_mut_ptr()) }
    });
    w.int_arg(func, "n", &[n - 1, -1], Status::ErrInvalidDimension, &|v| unsafe {
        rodkit_rod_residual(rod, x.as_ptr(), v, 0.5, vec![0.0; nu].as_mut_ptr())
    });

    let func = "rodkit_rod_jacobian_pattern";
    let mut nnz = 0i64;
    let st = unsafe { rodkit_rod_jacobian_pattern(rod, null_mut(), null_mut(), 0, &mut nnz) };
    w.succeeds(format!("{func} size query"), st, &[]);
    let mut cp = vec![0i64; nu + 1];
    let mut ri = vec![0i64; nnz as usize];
    let st = unsafe { rodkit_rod_jacobian_pattern(rod, cp.as_mut_ptr(), ri.as_mut_ptr(), nnz, &mut nnz) };
    w.succeeds(format!("{func} valid"), st, &[]);
    w.null(func, "rod", unsafe { rodkit_rod_jacobian_pattern(null(), cp.as_mut_ptr(), ri.as_mut_ptr(), nnz, &mut 0) });
    w.null(func, "nnz", unsafe { rodkit_rod_jacobian_pattern(rod, cp.as_mut_ptr(), ri.as_mut_ptr(), nnz, null_mut()) });
    w.null(func, "col_ptr", unsafe { rodkit_rod_jacobian_pattern(rod, null_mut(), ri.as_mut_ptr(), nnz, &mut 0) });
    w.null(func, "row_idx", unsafe { rodkit_rod_jacobian_pattern(rod, cp.as_mut_ptr(), null_mut(), nnz, &mut 0) });
    w.int_arg(func, "capacity", &[-1], Status::ErrInvalidDimension, &|c| unsafe {
        rodkit_rod_jacobian_pattern(rod, null_mut(), null_mut(), c, &mut 0)
    });

    let func = "rodkit_rod_jacobian";
    let mut vals = vec![0.0; nnz as usize];
    let mut dl = vec![0.0; nu];
    let st = unsafe { rodkit_rod_jacobian(rod, x.as_ptr(), n, 0.5, vals.as_mut_ptr(), nnz, dl.as_mut_ptr()) };
    w.succeeds(format!("{func} valid"), st, &[vals.clone(), dl.clone()].concat());
    w.null(func, "rod", unsafe {
        rodkit_rod_jacobian(null_mut(), x.as_ptr(), n, 0.5, vals.as_mut_ptr(), nnz, null_mut())
    });
    w.null(func, "x", unsafe { rodkit_rod_jacobian(rod, null(), n, 0.5, vals.as_mut_ptr(), nnz, null_mut()) });
    w.null(func, "values", unsafe { rodkit_rod_jacobian(rod, x.as_ptr(), n, 0.5, null_mut(), nnz, null_mut()) });
    w.scalar(func, "lambda", &|l| unsafe {
        rodkit_rod_jacobian(rod, x.as_ptr(), n, l, vec![0.0; nnz as usize].as_mut_ptr(), nnz, null_mut())
    });
    w.array(func, "x", &|v| {
        let mut x2 = x.clone();
        x2[0] = v;
        unsafe { rodkit_rod_jacobian(rod, x2.as_ptr(), n, 0.5, vec![0.0; nnz as usize].as_mut_ptr(), nnz, null_mut()) }
    });
    w.int_arg(func, "nnz", &[nnz - 1, -1], Status::ErrInvalidDimension, &|v| unsafe {
        rodkit_rod_jacobian(rod, x.as_ptr(), n, 0.5, vec![0.0; nnz as usize].as_mut_ptr(), v, null_mut())
    });

    let func = "rodkit_rod_rhs";
    let mut y = [0.0; 13];
    y[3] = 1.0;
    let mut dy = [0.0; 13];
    w.succeeds(format!("{func} valid"), unsafe { rodkit_rod_rhs(rod, y.as_ptr(), 0.5, dy.as_mut_ptr()) }, &dy);
    w.null(func, "rod", unsafe { rodkit_rod_rhs(null(), y.as_ptr(), 0.5, dy.as_mut_ptr()) });
    w.null(func, "y", unsafe { rodkit_rod_rhs(rod, null(), 0.5, dy.as_mut_ptr()) });
    w.null(func, "dy", unsafe { rodkit_rod_rhs(rod, y.as_ptr(), 0.5, null_mut()) });
    w.scalar(func, "lambda", &|l| unsafe { rodkit_rod_rhs(rod, y.as_ptr(), l, [0.0; 13].as_mut_ptr()) });
    w.array(func, "y", &|v| {
        let mut y2 = y;
        y2[0] = v;
        unsafe { rodkit_rod_rhs(rod, y2.as_ptr(), 0.5, [0.0; 13].as_mut_ptr()) }
    });

    let func = "rodkit_rod_node_positions";
    let mut count = 0i64;
    let mut sv = vec![0.0; 64];
    let st = unsafe { rodkit_rod_node_positions(rod, sv.as_mut_ptr(), 64, &mut count) };
    w.succeeds(format!("{func} valid"), st, &sv[..count.clamp(0, 64) as usize]);
    w.null(func, "rod", unsafe { rodkit_rod_node_positions(null(), sv.as_mut_ptr(), 64, &mut count) });
    w.null(func, "count", unsafe { rodkit_rod_node_positions(rod, sv.as_mut_ptr(), 64, null_mut()) });
    w.int_arg(func, "capacity", &[-1], Status::ErrInvalidDimension, &|c| unsafe {
        rodkit_rod_node_positions(rod, null_mut(), c, &mut 0)
    });
    let nodes = count;

    let func = "rodkit_rod_node_rotation";
    let mut rot = [0.0; 3];
    w.succeeds(
        format!("{func} valid"),
        unsafe { rodkit_rod_node_rotation(rod, x.as_ptr(), n, 0, rot.as_mut_ptr()) },
        &rot,
    );
    w.null(func, "rod", unsafe { rodkit_rod_node_rotation(null(), x.as_ptr(), n, 0, rot.as_mut_ptr()) });
    w.null(func, "x", unsafe { rodkit_rod_node_rotation(rod, null(), n, 0, rot.as_mut_ptr()) });
    w.null(func, "rotation", unsafe { rodkit_rod_node_rotation(rod, x.as_ptr(), n, 0, null_mut()) });
    w.int_arg(func, "node", &[-1, nodes], Status::ErrOutOfRange, &|k| unsafe {
        rodkit_rod_node_rotation(rod, x.as_ptr(), n, k, [0.0; 3].as_mut_ptr())
    });
    w.int_arg(func, "n", &[n - 1], Status::ErrInvalidDimension, &|v| unsafe {
        rodkit_rod_node_rotation(rod, x.as_ptr(), v, 0, [0.0; 3].as_mut_ptr())
    });
    w.array(func, "x", &|v| {
        let mut x2 = x.clone();
        x2[0] = v;
        unsafe { rodkit_rod_node_rotation(rod, x2.as_ptr(), n, 0, [0.0; 3].as_mut_ptr()) }
    });

    let func = "rodkit_rod_node_state";
    let (mut pos, mut q, mut f, mut m) = ([0.0; 3], [0.0; 4], [0.0; 3], [0.0; 3]);
    let st = unsafe {
        rodkit_rod_node_state(rod, x.as_ptr(), n, 0, pos.as_mut_ptr(), q.as_mut_ptr(), f.as_mut_ptr(), m.as_mut_ptr())
    };
    w.succeeds(format!("{func} valid"), st, &[&pos[..], &q, &f, &m].concat());
    w.null(func, "rod", unsafe {
        rodkit_rod_node_state(null(), x.as_ptr(), n, 0, pos.as_mut_ptr(), null_mut(), null_mut(), null_mut())
    });
    w.null(func, "x", unsafe {
        rodkit_rod_node_state(rod, null(), n, 0, pos.as_mut_ptr(), null_mut(), null_mut(), null_mut())
    });
    w.int_arg(func, "node", &[-1, nodes], Status::ErrOutOfRange, &|k| unsafe {
        rodkit_rod_node_state(rod, x.as_ptr(), n, k, [0.0; 3].as_mut_ptr(), null_mut(), null_mut(), null_mut())
    });
    w.int_arg(func, "n", &[n - 1], Status::ErrInvalidDimension, &|v| unsafe {
        rodkit_rod_node_state(rod, x.as_ptr(), v, 0, [0.0; 3].as_mut_ptr(), null_mut(), null_mut(), null_mut())
    });

    let func = "rodkit_rod_set_target_rotation";
    w.null(func, "rod", unsafe { rodkit_rod_set_target_rotation(null_mut(), 1.0) });
    // NaN clears the target (documented), so only ±Inf are refused; a
    // finite φ on this cantilever (no end rotation control) is out of range.
    w.succeeds(format!("{func} NaN clears"), unsafe { rodkit_rod_set_target_rotation(rod, f64::NAN) }, &[]);
    for v in [f64::INFINITY, f64::NEG_INFINITY] {
        let st = unsafe { rodkit_rod_set_target_rotation(rod, v) };
        w.fails(format!("{func} phi={v}"), st, Status::ErrNotFinite, &["`phi`"]);
    }
    let st = unsafe { rodkit_rod_set_target_rotation(rod, 1.0) };
    w.fails(format!("{func} cantilever"), st, Status::ErrOutOfRange, &["`rod`"]);

    let func = "rodkit_rod_continue_to_tolerance";
    let mut o = options();
    o.target_lambda = 0.2;
    let tol = |rd: *const Rod,
               t: f64,
               l0: f64,
               o: *const ContinuationOptions,
               ro: *mut *mut Rod,
               out: *mut *mut Branch| unsafe {
        let st = rodkit_rod_continue_to_tolerance(rd, t, l0, o, None, null_mut(), ro, out);
        if !out.is_null() {
            rodkit_branch_free(*out);
        }
        if !ro.is_null() {
            rodkit_rod_free(*ro);
        }
        st
    };
    w.succeeds(format!("{func} valid"), tol(rod, 1e-4, 0.0, &o, &mut null_mut(), &mut null_mut()), &[]);
    w.null(func, "rod", tol(null(), 1e-4, 0.0, &o, &mut null_mut(), &mut null_mut()));
    w.null(func, "options", tol(rod, 1e-4, 0.0, null(), &mut null_mut(), &mut null_mut()));
    w.null(func, "rod_out", tol(rod, 1e-4, 0.0, &o, null_mut(), &mut null_mut()));
    w.null(func, "out", tol(rod, 1e-4, 0.0, &o, &mut null_mut(), null_mut()));
    w.scalar(func, "tolerance", &|t| tol(rod, t, 0.0, &o, &mut null_mut(), &mut null_mut()));
    w.scalar(func, "lambda0", &|l| tol(rod, 1e-4, l, &o, &mut null_mut(), &mut null_mut()));

    branch(w, rod, &x);
    unsafe { rodkit_rod_free(rod) };
    unsafe { rodkit_rod_free(null_mut()) };
}

fn options() -> ContinuationOptions {
    let mut o = filled(rodkit_continuation_options_default);
    (o.target_lambda, o.max_steps) = (0.2, 50);
    o
}

fn branch(w: &mut Walk, rod: *mut Rod, x: &[f64]) {
    let rod = rod as *const Rod;
    let n = x.len() as i64;
    let cont = |x0: *const f64, l0: f64, o: *const ContinuationOptions, out: *mut *mut Branch| unsafe {
        rodkit_rod_continue(rod, x0, n, l0, o, None, null_mut(), out)
    };
    let run = |o: &ContinuationOptions| {
        let mut b = null_mut();
        let st = cont(null(), 0.0, o, &mut b);
        unsafe { rodkit_branch_free(b) };
        st
    };
    let func = "rodkit_rod_continue";
    let of: Vec<Field<ContinuationOptions>> = vec![
        i32f!(method, &[0, 3]),
        i64f!(anm_order, &[1, 61]),
        f!(anm_epsilon),
        inf!(target_lambda),
        f!(lambda_min),
        f!(lambda_max),
        i64f!(max_steps, &[-1]),
        f!(residual_tol),
        f!(initial_step),
        f!(min_step),
        f!(max_step),
        i32f!(detect_bifurcations, FLAG),
        f!(bifurcation_tol),
        i32f!(increasing, FLAG),
        i64f!(sample_count, &[-1]),
        i32f!(anm_pade, FLAG),
        i64f!(scaling_count, &[-1, 1], Status::ErrInvalidDimension),
    ];
    w.fields(func, "options.", &options(), &of, &|o| run(o));
    let mut newton = options();
    newton.method = ContinuationMethod::Newton as i32;
    w.fields(func, "options.", &newton, &[f!(initial_step), f!(residual_tol)], &|o| run(o));
    w.null(func, "rod", unsafe {
        rodkit_rod_continue(null(), null(), 0, 0.0, &options(), None, null_mut(), &mut null_mut())
    });
    w.null(func, "options", cont(null(), 0.0, null(), &mut null_mut()));
    w.null(func, "out", cont(null(), 0.0, &options(), null_mut()));
    w.scalar(func, "lambda0", &|l| {
        let mut b = null_mut();
        let st = cont(null(), l, &options(), &mut b);
        unsafe { rodkit_branch_free(b) };
        st
    });
    w.array(func, "x0", &|v| {
        let mut x2 = x.to_vec();
        x2[0] = v;
        let mut b = null_mut();
        let st = cont(x2.as_ptr(), 0.0, &options(), &mut b);
        unsafe { rodkit_branch_free(b) };
        st
    });
    let samples = [0.05, 0.1];
    let mut so = options();
    (so.samples, so.sample_count) = (samples.as_ptr(), 2);
    w.array(func, "options.samples", &|v| {
        let s2 = [v, 0.1];
        run(&ContinuationOptions { samples: s2.as_ptr(), ..so })
    });
    w.null(func, "options.samples", run(&ContinuationOptions { samples: null(), ..so }));

    let mut b = null_mut();
    let st = cont(null(), 0.0, &so, &mut b);
    w.succeeds(format!("{func} valid"), st, &[]);
    if b.is_null() {
        w.finding(format!("{func} branch"), "no branch returned".into());
        return;
    }
    let b = b as *const Branch;

    let func = "rodkit_branch_summary";
    let mut info = BranchInfo::default();
    w.succeeds(format!("{func} valid"), unsafe { rodkit_branch_summary(b, &mut info) }, &[]);
    w.null(func, "branch", unsafe { rodkit_branch_summary(null(), &mut info) });
    w.null(func, "info", unsafe { rodkit_branch_summary(b, null_mut()) });

    type Copy = unsafe extern "C" fn(*const Branch, *mut BranchRecord, i64, *mut i64) -> i32;
    for (func, f) in [
        ("rodkit_branch_records", rodkit_branch_records as Copy),
        ("rodkit_branch_samples", rodkit_branch_samples as Copy),
    ] {
        let mut count = 0i64;
        let mut recs = vec![BranchRecord::default(); 200];
        let st = unsafe { f(b, recs.as_mut_ptr(), 200, &mut count) };
        let fin: Vec<f64> = recs[..count.clamp(0, 200) as usize]
            .iter()
            .flat_map(|r| [r.lambda, r.residual, r.tip_x, r.tip_z])
            .collect();
        w.succeeds(format!("{func} valid"), st, &fin);
        w.null(func, "branch", unsafe { f(null(), recs.as_mut_ptr(), 200, &mut count) });
        w.null(func, "count", unsafe { f(b, recs.as_mut_ptr(), 200, null_mut()) });
        if count > 0 {
            w.null(func, if func.ends_with("records") { "records" } else { "samples" }, unsafe {
                f(b, null_mut(), 200, &mut count)
            });
        }
        w.int_arg(func, "capacity", &[-1], Status::ErrInvalidDimension, &|c| unsafe { f(b, null_mut(), c, &mut 0) });
    }

    let sl = info.state_length;
    let func = "rodkit_branch_state";
    let mut xs = vec![0.0; sl as usize];
    let st = unsafe { rodkit_branch_state(b, info.records - 1, xs.as_mut_ptr(), sl) };
    w.succeeds(format!("{func} valid"), st, &xs);
    w.null(func, "branch", unsafe { rodkit_branch_state(null(), 0, xs.as_mut_ptr(), sl) });
    w.null(func, "x", unsafe { rodkit_branch_state(b, 0, null_mut(), sl) });
    w.int_arg(func, "record", &[-1, info.records], Status::ErrOutOfRange, &|r| unsafe {
        rodkit_branch_state(b, r, vec![0.0; sl as usize].as_mut_ptr(), sl)
    });
    w.int_arg(func, "n", &[sl - 1], Status::ErrInvalidDimension, &|v| unsafe {
        rodkit_branch_state(b, 0, vec![0.0; sl as usize].as_mut_ptr(), v)
    });
    let func = "rodkit_branch_sample_state";
    if info.samples > 0 {
        let st = unsafe { rodkit_branch_sample_state(b, 0, xs.as_mut_ptr(), sl) };
        w.succeeds(format!("{func} valid"), st, &xs);
    }
    w.null(func, "branch", unsafe { rodkit_branch_sample_state(null(), 0, xs.as_mut_ptr(), sl) });
    w.int_arg(func, "sample", &[-1, info.samples], Status::ErrOutOfRange, &|r| unsafe {
        rodkit_branch_sample_state(b, r, vec![0.0; sl as usize].as_mut_ptr(), sl)
    });

    let func = "rodkit_branch_positions";
    let nodes = 3i64; // 2 elements
    let mut xyz = vec![0.0; 3 * nodes as usize];
    let st = unsafe { rodkit_branch_positions(b, rod, 0, xyz.as_mut_ptr(), 3, nodes) };
    w.succeeds(format!("{func} valid"), st, &xyz);
    w.null(func, "branch", unsafe { rodkit_branch_positions(null(), rod, 0, xyz.as_mut_ptr(), 3, nodes) });
    w.null(func, "rod", unsafe { rodkit_branch_positions(b, null(), 0, xyz.as_mut_ptr(), 3, nodes) });
    w.null(func, "xyz", unsafe { rodkit_branch_positions(b, rod, 0, null_mut(), 3, nodes) });
    w.int_arg(func, "record", &[-1, info.records], Status::ErrOutOfRange, &|r| unsafe {
        rodkit_branch_positions(b, rod, r, vec![0.0; 9].as_mut_ptr(), 3, nodes)
    });
    w.int_arg(func, "ld", &[2, -1], Status::ErrInvalidDimension, &|v| unsafe {
        rodkit_branch_positions(b, rod, 0, vec![0.0; 9].as_mut_ptr(), v, nodes)
    });
    w.int_arg(func, "nodes", &[2, 4], Status::ErrInvalidDimension, &|v| unsafe {
        rodkit_branch_positions(b, rod, 0, vec![0.0; 12].as_mut_ptr(), 3, v)
    });

    let func = "rodkit_branch_bifurcations";
    let mut count = 0i64;
    let mut bifs = vec![zeroed::<Bifurcation>(); 4];
    let st = unsafe { rodkit_branch_bifurcations(b, rod, bifs.as_mut_ptr(), 4, &mut count) };
    w.succeeds(format!("{func} valid"), st, &[]);
    w.null(func, "branch", unsafe { rodkit_branch_bifurcations(null(), rod, bifs.as_mut_ptr(), 4, &mut count) });
    w.null(func, "rod", unsafe { rodkit_branch_bifurcations(b, null(), bifs.as_mut_ptr(), 4, &mut count) });
    w.null(func, "count", unsafe { rodkit_branch_bifurcations(b, rod, bifs.as_mut_ptr(), 4, null_mut()) });
    w.int_arg(func, "capacity", &[-1], Status::ErrInvalidDimension, &|c| unsafe {
        rodkit_branch_bifurcations(b, rod, null_mut(), c, &mut 0)
    });

    // The list getters that take (branch, rod, out, capacity, count).
    macro_rules! listed {
        ($func:ident, $ty:ty) => {{
            let func = stringify!($func);
            let mut out = vec![zeroed::<$ty>(); 64];
            let mut count = 0i64;
            w.succeeds(format!("{func} valid"), unsafe { $func(b, rod, out.as_mut_ptr(), 64, &mut count) }, &[]);
            w.null(func, "branch", unsafe { $func(null(), rod, out.as_mut_ptr(), 64, &mut count) });
            w.null(func, "rod", unsafe { $func(b, null(), out.as_mut_ptr(), 64, &mut count) });
            w.null(func, "count", unsafe { $func(b, rod, out.as_mut_ptr(), 64, null_mut()) });
            w.int_arg(func, "capacity", &[-1], Status::ErrInvalidDimension, &|c| unsafe {
                $func(b, rod, null_mut(), c, &mut 0)
            });
        }};
    }
    listed!(rodkit_branch_bifurcation_points, BifurcationPoint);
    listed!(rodkit_branch_bifurcation_errors, BifurcationError);
    listed!(rodkit_branch_error_estimates, RecordError);
    listed!(rodkit_branch_kirchhoff_differences, RecordError);

    let func = "rodkit_branch_unresolved";
    let mut un = vec![zeroed::<UnresolvedBifurcation>(); 4];
    w.succeeds(format!("{func} valid"), unsafe { rodkit_branch_unresolved(b, un.as_mut_ptr(), 4, &mut count) }, &[]);
    w.null(func, "branch", unsafe { rodkit_branch_unresolved(null(), un.as_mut_ptr(), 4, &mut count) });
    w.null(func, "count", unsafe { rodkit_branch_unresolved(b, un.as_mut_ptr(), 4, null_mut()) });
    w.int_arg(func, "capacity", &[-1], Status::ErrInvalidDimension, &|c| unsafe {
        rodkit_branch_unresolved(b, null_mut(), c, &mut 0)
    });

    let func = "rodkit_branch_bifurcation_state";
    w.null(func, "branch", unsafe { rodkit_branch_bifurcation_state(null(), 0, xs.as_mut_ptr(), sl) });
    w.int_arg(func, "index", &[-1, info.bifurcations], Status::ErrOutOfRange, &|i| unsafe {
        rodkit_branch_bifurcation_state(b, i, vec![0.0; sl as usize].as_mut_ptr(), sl)
    });

    let dir = std::env::temp_dir().join(format!("rodkit_walk_branch_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = |name: &str| std::ffi::CString::new(dir.join(name).to_str().unwrap()).unwrap();
    let (csv, vtk) = (path("branch.csv"), path("branch.vtk"));
    let func = "rodkit_branch_write_csv";
    w.succeeds(format!("{func} valid"), unsafe { rodkit_branch_write_csv(b, rod, csv.as_ptr()) }, &[]);
    w.null(func, "branch", unsafe { rodkit_branch_write_csv(null(), rod, csv.as_ptr()) });
    w.null(func, "rod", unsafe { rodkit_branch_write_csv(b, null(), csv.as_ptr()) });
    w.null(func, "path", unsafe { rodkit_branch_write_csv(b, rod, null()) });
    let func = "rodkit_branch_write_samples_csv";
    w.succeeds(format!("{func} valid"), unsafe { rodkit_branch_write_samples_csv(b, rod, csv.as_ptr()) }, &[]);
    w.null(func, "branch", unsafe { rodkit_branch_write_samples_csv(null(), rod, csv.as_ptr()) });
    w.null(func, "rod", unsafe { rodkit_branch_write_samples_csv(b, null(), csv.as_ptr()) });
    w.null(func, "path", unsafe { rodkit_branch_write_samples_csv(b, rod, null()) });
    for (func, which, last) in [
        ("rodkit_branch_write_vtk", "records", info.records),
        ("rodkit_branch_write_samples_vtk", "samples", info.samples),
    ] {
        let write = |sel: *const i64, n: i64, p: *const std::ffi::c_char| unsafe {
            if which == "records" {
                rodkit_branch_write_vtk(b, rod, sel, n, p)
            } else {
                rodkit_branch_write_samples_vtk(b, rod, sel, n, p)
            }
        };
        w.succeeds(format!("{func} valid"), write([0i64].as_ptr(), 1, vtk.as_ptr()), &[]);
        w.null(func, "path", write([0i64].as_ptr(), 1, null()));
        w.int_arg(func, which, &[-1, last], Status::ErrOutOfRange, &|k| write([k].as_ptr(), 1, vtk.as_ptr()));
        let st = unsafe {
            if which == "records" {
                rodkit_branch_write_vtk(null(), rod, null(), 0, vtk.as_ptr())
            } else {
                rodkit_branch_write_samples_vtk(null(), rod, null(), 0, vtk.as_ptr())
            }
        };
        w.null(func, "branch", st);
    }
    std::fs::remove_dir_all(&dir).unwrap();

    let func = "rodkit_branch_resume";
    let mut more = options();
    more.target_lambda = 0.3;
    let resume = |rod: *const Rod, br: *const Branch, o: *const ContinuationOptions, out: *mut *mut Branch| unsafe {
        let st = rodkit_branch_resume(rod, br, o, None, null_mut(), out);
        if !out.is_null() {
            rodkit_branch_free(*out);
        }
        st
    };
    w.succeeds(format!("{func} valid"), resume(rod, b, &more, &mut null_mut()), &[]);
    w.fields(func, "options.", &more, &[f!(residual_tol), f!(max_step), i64f!(max_steps, &[-1])], &|o| {
        resume(rod, b, o, &mut null_mut())
    });
    w.null(func, "rod", resume(null(), b, &more, &mut null_mut()));
    w.null(func, "branch", resume(rod, null(), &more, &mut null_mut()));
    w.null(func, "options", resume(rod, b, null(), &mut null_mut()));
    w.null(func, "out", resume(rod, b, &more, null_mut()));

    // No bifurcation on this branch: index 0 is out of range.
    let func = "rodkit_branch_switch";
    let switch = |rod: *const Rod,
                  br: *const Branch,
                  i: i64,
                  d: i64,
                  step: f64,
                  o: *const ContinuationOptions,
                  out: *mut *mut Branch| unsafe {
        let st = rodkit_branch_switch(rod, br, i, d, step, o, None, null_mut(), out);
        if !out.is_null() {
            rodkit_branch_free(*out);
        }
        st
    };
    let o = options();
    w.null(func, "rod", switch(null(), b, 0, 0, 0.01, &o, &mut null_mut()));
    w.null(func, "branch", switch(rod, null(), 0, 0, 0.01, &o, &mut null_mut()));
    w.null(func, "options", switch(rod, b, 0, 0, 0.01, null(), &mut null_mut()));
    w.null(func, "out", switch(rod, b, 0, 0, 0.01, &o, null_mut()));
    w.int_arg(func, "index", &[-1, info.bifurcations], Status::ErrOutOfRange, &|i| {
        switch(rod, b, i, 0, 0.01, &o, &mut null_mut())
    });
    w.int_arg(func, "direction", &[-1], Status::ErrOutOfRange, &|d| switch(rod, b, 0, d, 0.01, &o, &mut null_mut()));
    w.scalar(func, "first_step", &|s| switch(rod, b, 0, 0, s, &o, &mut null_mut()));
    unsafe { rodkit_branch_free(b.cast_mut()) };
    unsafe { rodkit_branch_free(null_mut()) };
    switch_valid(w);
}

/// rodkit_branch_switch with valid defaults: Greenhill's double point of a
/// twisted Kirchhoff rod (as tests/capi_rod.rs), left along direction 0;
/// the options walked through the switch too.
fn switch_valid(w: &mut Walk) {
    let mut s = rod_spec();
    (s.kirchhoff, s.twist, s.supports, s.elements) = (1, 4.0, RodSupports::Twisted as i32, 8);
    (s.tip_force_frame, s.tip_moment_frame, s.stages) = (0, 0, 4);
    let mut rod = null_mut();
    assert_eq!(unsafe { rodkit_rod_new(&s, &mut rod) }, 0, "{}", last_error());
    let rod = rod as *const Rod;
    let mut o = options();
    (o.method, o.target_lambda, o.initial_step, o.max_step) = (ContinuationMethod::Newton as i32, 0.99, 0.2, 0.5);
    (o.residual_tol, o.detect_bifurcations) = (1e-12, 1);
    let mut b = null_mut();
    let st = unsafe { rodkit_rod_continue(rod, null(), 0, 0.0, &o, None, null_mut(), &mut b) };
    w.succeeds("rodkit_rod_continue greenhill".into(), st, &[]);
    let mut info = BranchInfo::default();
    unsafe { rodkit_branch_summary(b, &mut info) };
    // The walk's rod has K_2 = 1.2 K_1: Greenhill's double point splits
    // into two simple ones, at φ = 2·4.4934·K/C for K = K_1 and about K_2
    // (Λ = sin(φ/2) = 0.90 and 0.975 < 0.99; tests/rod_bifurcations.rs):
    // both are on this branch (before issue 19 only the first was found).
    assert_eq!(info.bifurcations, 2, "the walk's Greenhill branch must have its two bifurcations");
    // A located point's state (the walk's other branch has none).
    let func = "rodkit_branch_bifurcation_state";
    let sl = info.state_length;
    let mut xs = vec![0.0; sl as usize];
    w.succeeds(format!("{func} valid"), unsafe { rodkit_branch_bifurcation_state(b, 1, xs.as_mut_ptr(), sl) }, &xs);
    w.null(func, "x", unsafe { rodkit_branch_bifurcation_state(b, 0, null_mut(), sl) });
    w.int_arg(func, "n", &[sl - 1], Status::ErrInvalidDimension, &|v| unsafe {
        rodkit_branch_bifurcation_state(b, 0, vec![0.0; sl as usize].as_mut_ptr(), v)
    });
    let func = "rodkit_branch_switch";
    (o.target_lambda, o.max_steps) = (1.5, 3);
    let switch = |o: &ContinuationOptions, step: f64| unsafe {
        let mut out = null_mut();
        let st = rodkit_branch_switch(rod, b, 0, 0, step, o, None, null_mut(), &mut out);
        rodkit_branch_free(out);
        st
    };
    w.succeeds(format!("{func} valid"), switch(&o, 0.05), &[]);
    let of: Vec<Field<ContinuationOptions>> =
        vec![f!(residual_tol), f!(initial_step), f!(max_step), f!(lambda_max), i64f!(max_steps, &[-1])];
    w.fields(func, "options.", &o, &of, &|o| switch(o, 0.05));
    w.scalar(func, "first_step", &|step| switch(&o, step));
    w.int_arg(func, "direction", &[2], Status::ErrOutOfRange, &|d| unsafe {
        let mut out = null_mut();
        let st = rodkit_branch_switch(rod, b, 0, d, 0.05, &o, None, null_mut(), &mut out);
        rodkit_branch_free(out);
        st
    });
    unsafe { rodkit_branch_free(b) };
    unsafe { rodkit_rod_free(rod.cast_mut()) };
}

// ---------------------------------------------------------------- supercoil

fn supercoil(w: &mut Walk) {
    w.null("rodkit_dna_supercoil_spec_default", "spec", unsafe { rodkit_dna_supercoil_spec_default(null_mut()) });
    w.null("rodkit_equilibrium_spec_default", "spec", unsafe { rodkit_equilibrium_spec_default(null_mut()) });
    let mut spec = filled(rodkit_dna_supercoil_spec_default);
    (spec.base_pairs, spec.elements, spec.max_steps, spec.max_turns) = (300, 20, 6, 2.0);
    let run = |s: *const DnaSupercoilSpec, out: *mut *mut Supercoil| unsafe {
        let st = rodkit_dna_supercoil_run(s, out);
        if !out.is_null() {
            rodkit_supercoil_free(*out);
        }
        st
    };
    let func = "rodkit_dna_supercoil_run";
    let sf: Vec<Field<DnaSupercoilSpec>> = vec![
        i64f!(base_pairs, &[9, -1]),
        f!(rise),
        f!(tension),
        f!(salt),
        f!(charge_per_length),
        f!(radius),
        f!(bending_persistence),
        f!(twist_persistence),
        f!(temperature),
        f!(permittivity),
        i64f!(elements, &[1, -1]),
        i64f!(stages, &[0, 5]),
        f!(cutoff_tolerance),
        f!(hard_core),
        i64f!(threads, &[0, 257]),
        f!(max_turns),
        i64f!(max_steps, &[0, -1]),
        f!(residual_tol),
        i32f!(discrete_base_pairs, FLAG),
        i32f!(end_control, &[0, 3]),
        f!(tolerance),
    ];
    w.fields(func, "spec.", &spec, &sf, &|s| run(s, &mut null_mut()));
    w.null(func, "spec", run(null(), &mut null_mut()));
    w.null(func, "out", unsafe { rodkit_dna_supercoil_run(&spec, null_mut()) });
    // The same with a progress callback (NULL: none).
    let func = "rodkit_dna_supercoil_run_with";
    let run_with = |s: *const DnaSupercoilSpec, out: *mut *mut Supercoil| unsafe {
        let st = rodkit_dna_supercoil_run_with(s, None, null_mut(), out);
        if !out.is_null() {
            rodkit_supercoil_free(*out);
        }
        st
    };
    let mut out = null_mut();
    w.succeeds(format!("{func} valid"), run_with(&spec, &mut out), &[]);
    w.fields(func, "spec.", &spec, &sf, &|s| run_with(s, &mut null_mut()));
    w.null(func, "spec", run_with(null(), &mut null_mut()));
    w.null(func, "out", unsafe { rodkit_dna_supercoil_run_with(&spec, None, null_mut(), null_mut()) });

    let mut r = null_mut();
    assert!(unsafe { rodkit_dna_supercoil_run(&spec, &mut r) } >= 0, "{}", last_error());
    let r = r as *const Supercoil;
    let func = "rodkit_supercoil_summary";
    let mut info = SupercoilInfo::default();
    let st = unsafe { rodkit_supercoil_summary(r, &mut info) };
    w.succeeds(format!("{func} valid"), st, &[info.kappa, info.bjerrum_length, info.line_charge_squared]);
    w.null(func, "run", unsafe { rodkit_supercoil_summary(null(), &mut info) });
    w.null(func, "info", unsafe { rodkit_supercoil_summary(r, null_mut()) });

    let func = "rodkit_supercoil_stop";
    let mut stop = -1;
    let st = unsafe { rodkit_supercoil_stop(r, &mut stop) };
    w.succeeds(format!("{func} valid"), st, &[stop as f64]);
    w.null(func, "run", unsafe { rodkit_supercoil_stop(null(), &mut stop) });
    w.null(func, "stop", unsafe { rodkit_supercoil_stop(r, null_mut()) });

    let func = "rodkit_supercoil_resume";
    // A finished run: its status, unchanged.
    let st = unsafe { rodkit_supercoil_resume(r.cast_mut(), None, null_mut()) };
    w.succeeds(format!("{func} valid"), st, &[]);
    w.null(func, "run", unsafe { rodkit_supercoil_resume(null_mut(), None, null_mut()) });

    let func = "rodkit_supercoil_points";
    let mut count = 0i64;
    let mut pts = vec![SupercoilPoint::default(); info.points as usize];
    let st = unsafe { rodkit_supercoil_points(r, pts.as_mut_ptr(), info.points, &mut count) };
    let fin: Vec<f64> = pts.iter().flat_map(|p| [p.turns, p.extension, p.torque, p.twist, p.writhe]).collect();
    w.succeeds(format!("{func} valid"), st, &fin);
    w.null(func, "run", unsafe { rodkit_supercoil_points(null(), pts.as_mut_ptr(), info.points, &mut count) });
    w.null(func, "count", unsafe { rodkit_supercoil_points(r, pts.as_mut_ptr(), info.points, null_mut()) });
    w.null(func, "points", unsafe { rodkit_supercoil_points(r, null_mut(), info.points, &mut count) });
    w.int_arg(func, "capacity", &[-1], Status::ErrInvalidDimension, &|c| unsafe {
        rodkit_supercoil_points(r, null_mut(), c, &mut 0)
    });

    let func = "rodkit_supercoil_positions";
    let nodes = info.nodes;
    let mut xyz = vec![0.0; 3 * nodes as usize];
    let st = unsafe { rodkit_supercoil_positions(r, 0, xyz.as_mut_ptr(), 3, nodes) };
    w.succeeds(format!("{func} valid"), st, &xyz);
    w.null(func, "run", unsafe { rodkit_supercoil_positions(null(), 0, xyz.as_mut_ptr(), 3, nodes) });
    w.null(func, "xyz", unsafe { rodkit_supercoil_positions(r, 0, null_mut(), 3, nodes) });
    w.int_arg(func, "point", &[-1, info.points], Status::ErrOutOfRange, &|p| unsafe {
        rodkit_supercoil_positions(r, p, vec![0.0; 3 * nodes as usize].as_mut_ptr(), 3, nodes)
    });
    w.int_arg(func, "ld", &[2, -1], Status::ErrInvalidDimension, &|v| unsafe {
        rodkit_supercoil_positions(r, 0, vec![0.0; 3 * nodes as usize].as_mut_ptr(), v, nodes)
    });
    w.int_arg(func, "nodes", &[nodes - 1, nodes + 1], Status::ErrInvalidDimension, &|v| unsafe {
        rodkit_supercoil_positions(r, 0, vec![0.0; 3 * nodes as usize + 3].as_mut_ptr(), 3, v)
    });

    let func = "rodkit_supercoil_solve_point";
    let es = filled(rodkit_equilibrium_spec_default);
    let solve = |p: i64, s: *const EquilibriumSpec, out: *mut Equilibrium, xyz: *mut f64, ld: i64, nodes: i64| unsafe {
        rodkit_supercoil_solve_point(r, p, s, out, xyz, ld, nodes)
    };
    let mut eq = Equilibrium::default();
    let st = solve(0, &es, &mut eq, xyz.as_mut_ptr(), 3, nodes);
    w.succeeds(
        format!("{func} valid"),
        st,
        &[&[eq.turns, eq.extension, eq.torque, eq.tension, eq.twist, eq.writhe, eq.residual][..], &xyz].concat(),
    );
    let ef: Vec<Field<EquilibriumSpec>> =
        vec![i32f!(discrete_base_pairs, FLAG), f!(cutoff_tolerance), i32f!(solver, &[0, 3]), f!(residual_tol)];
    w.fields(func, "spec.", &es, &ef, &|s| solve(0, s, &mut Equilibrium::default(), null_mut(), 3, nodes));
    w.null(func, "run", unsafe { rodkit_supercoil_solve_point(null(), 0, &es, &mut eq, null_mut(), 3, nodes) });
    w.null(func, "spec", solve(0, null(), &mut eq, null_mut(), 3, nodes));
    w.null(func, "out", solve(0, &es, null_mut(), null_mut(), 3, nodes));
    w.int_arg(func, "point", &[-1, info.points], Status::ErrOutOfRange, &|p| {
        solve(p, &es, &mut Equilibrium::default(), null_mut(), 3, nodes)
    });
    w.int_arg(func, "ld", &[2], Status::ErrInvalidDimension, &|v| {
        solve(0, &es, &mut Equilibrium::default(), vec![0.0; 3 * nodes as usize].as_mut_ptr(), v, nodes)
    });
    let func = "rodkit_supercoil_curve_points";
    let mut cp = vec![SupercoilCurvePoint::default(); info.points as usize];
    let st = unsafe { rodkit_supercoil_curve_points(r, cp.as_mut_ptr(), info.points, &mut count) };
    w.succeeds(format!("{func} valid"), st, &cp.iter().map(|p| p.energy).collect::<Vec<_>>());
    w.null(func, "run", unsafe { rodkit_supercoil_curve_points(null(), cp.as_mut_ptr(), info.points, &mut count) });
    w.null(func, "count", unsafe { rodkit_supercoil_curve_points(r, cp.as_mut_ptr(), info.points, null_mut()) });
    w.null(func, "points", unsafe { rodkit_supercoil_curve_points(r, null_mut(), info.points, &mut count) });
    w.int_arg(func, "capacity", &[-1], Status::ErrInvalidDimension, &|c| unsafe {
        rodkit_supercoil_curve_points(r, null_mut(), c, &mut 0)
    });

    let func = "rodkit_supercoil_curve_summary";
    let mut ci = MaybeUninit::<SupercoilCurveInfo>::uninit();
    let ci = ci.as_mut_ptr();
    w.succeeds(format!("{func} valid"), unsafe { rodkit_supercoil_curve_summary(r, ci) }, &[]);
    w.null(func, "run", unsafe { rodkit_supercoil_curve_summary(null(), ci) });
    w.null(func, "out", unsafe { rodkit_supercoil_curve_summary(r, null_mut()) });

    let func = "rodkit_supercoil_failure";
    let (mut err, mut len) = (-1i32, -1i64);
    let mut buf = vec![0 as std::ffi::c_char; 64];
    let st = unsafe { rodkit_supercoil_failure(r, &mut err, buf.as_mut_ptr(), 64, &mut len) };
    w.succeeds(format!("{func} valid"), st, &[err as f64, len as f64]);
    w.null(func, "run", unsafe { rodkit_supercoil_failure(null(), &mut err, buf.as_mut_ptr(), 64, &mut len) });
    w.null(func, "error", unsafe { rodkit_supercoil_failure(r, null_mut(), buf.as_mut_ptr(), 64, &mut len) });
    w.null(func, "buffer", unsafe { rodkit_supercoil_failure(r, &mut err, null_mut(), 64, &mut len) });
    w.int_arg(func, "capacity", &[0, -1], Status::ErrInvalidDimension, &|c| unsafe {
        rodkit_supercoil_failure(r, &mut 0, vec![0 as std::ffi::c_char; 64].as_mut_ptr(), c, null_mut())
    });

    let dir = std::env::temp_dir().join(format!("rodkit_walk_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = |name: &str| std::ffi::CString::new(dir.join(name).to_str().unwrap()).unwrap();
    let func = "rodkit_supercoil_write_csv";
    let csv = path("supercoil.csv");
    w.succeeds(format!("{func} valid"), unsafe { rodkit_supercoil_write_csv(r, csv.as_ptr()) }, &[]);
    w.null(func, "run", unsafe { rodkit_supercoil_write_csv(null(), csv.as_ptr()) });
    w.null(func, "path", unsafe { rodkit_supercoil_write_csv(r, null()) });
    let func = "rodkit_supercoil_write_vtk";
    let vtk = path("supercoil.vtk");
    let which = [0i64];
    w.succeeds(format!("{func} valid"), unsafe { rodkit_supercoil_write_vtk(r, which.as_ptr(), 1, vtk.as_ptr()) }, &[]);
    w.null(func, "run", unsafe { rodkit_supercoil_write_vtk(null(), which.as_ptr(), 1, vtk.as_ptr()) });
    w.null(func, "path", unsafe { rodkit_supercoil_write_vtk(r, which.as_ptr(), 1, null()) });
    w.int_arg(func, "points", &[-1, info.points], Status::ErrOutOfRange, &|p| unsafe {
        rodkit_supercoil_write_vtk(r, [p].as_ptr(), 1, vtk.as_ptr())
    });
    std::fs::remove_dir_all(&dir).unwrap();
    unsafe { rodkit_supercoil_free(r.cast_mut()) };
    unsafe { rodkit_supercoil_free(null_mut()) };
}

/// The thermal two-phase model's calls.
fn tweezers(w: &mut Walk) {
    w.null("rodkit_tweezers_spec_default", "spec", unsafe { rodkit_tweezers_spec_default(null_mut()) });
    let spec = filled(rodkit_tweezers_spec_default);
    let func = "rodkit_tweezers_new";
    let new = |s: *const TweezersSpec, out: *mut *mut Tweezers| unsafe {
        let st = rodkit_tweezers_new(s, out);
        if !out.is_null() {
            rodkit_tweezers_free(*out);
        }
        st
    };
    let tf: Vec<Field<TweezersSpec>> = vec![
        f!(base_pairs),
        f!(rise),
        f!(force),
        f!(salt),
        f!(kt),
        f!(bending),
        f!(twist),
        f!(charge_per_length),
        f!(permittivity),
        f!(radius),
        f!(stretch_modulus),
        f!(twist_stretch),
        f!(confinement),
        f!(hard_core),
        i64f!(max_plectonemes, &[0, -1]),
        i32f!(end_loop, &[-1, 9]),
    ];
    w.fields(func, "spec.", &spec, &tf, &|s| new(s, &mut null_mut()));
    w.null(func, "spec", new(null(), &mut null_mut()));
    w.null(func, "out", unsafe { rodkit_tweezers_new(&spec, null_mut()) });
    let mut t = null_mut();
    assert!(unsafe { rodkit_tweezers_new(&spec, &mut t) } >= 0, "{}", last_error());
    let t = t as *const Tweezers;

    let func = "rodkit_tweezers_default_turns";
    let mut turns = vec![0.0; 40];
    w.succeeds(format!("{func} valid"), unsafe { rodkit_tweezers_default_turns(t, 40, turns.as_mut_ptr()) }, &turns);
    w.null(func, "tweezers", unsafe { rodkit_tweezers_default_turns(null(), 40, turns.as_mut_ptr()) });
    w.null(func, "turns", unsafe { rodkit_tweezers_default_turns(t, 40, null_mut()) });
    w.int_arg(func, "points", &[1, -1], Status::ErrOutOfRange, &|n| unsafe {
        rodkit_tweezers_default_turns(t, n, vec![0.0; 4].as_mut_ptr())
    });

    let func = "rodkit_tweezers_curve";
    let mut pts = vec![TweezersPoint::default(); 40];
    let st = unsafe { rodkit_tweezers_curve(t, turns.as_ptr(), 40, pts.as_mut_ptr()) };
    w.succeeds(
        format!("{func} valid"),
        st,
        &pts.iter().flat_map(|p| [p.turns, p.extension, p.torque]).collect::<Vec<_>>(),
    );
    w.null(func, "tweezers", unsafe { rodkit_tweezers_curve(null(), turns.as_ptr(), 40, pts.as_mut_ptr()) });
    w.null(func, "turns", unsafe { rodkit_tweezers_curve(t, null(), 40, pts.as_mut_ptr()) });
    w.null(func, "points", unsafe { rodkit_tweezers_curve(t, turns.as_ptr(), 40, null_mut()) });
    w.array(func, "turns", &|v| unsafe {
        rodkit_tweezers_curve(t, [v, 1.0].as_ptr(), 2, vec![TweezersPoint::default(); 2].as_mut_ptr())
    });

    let func = "rodkit_tweezers_summary";
    let mut info = MaybeUninit::<TweezersInfo>::uninit();
    let info = info.as_mut_ptr();
    w.succeeds(format!("{func} valid"), unsafe { rodkit_tweezers_summary(t, pts.as_ptr(), 40, info) }, &[]);
    w.null(func, "tweezers", unsafe { rodkit_tweezers_summary(null(), pts.as_ptr(), 40, info) });
    w.null(func, "points", unsafe { rodkit_tweezers_summary(t, null(), 40, info) });
    w.null(func, "out", unsafe { rodkit_tweezers_summary(t, pts.as_ptr(), 40, null_mut()) });

    let func = "rodkit_tweezers_write_csv";
    let dir = std::env::temp_dir().join(format!("rodkit_walk_tw_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = std::ffi::CString::new(dir.join("tweezers.csv").to_str().unwrap()).unwrap();
    w.succeeds(
        format!("{func} valid"),
        unsafe { rodkit_tweezers_write_csv(pts.as_ptr(), 40, spec.kt, csv.as_ptr()) },
        &[],
    );
    w.null(func, "points", unsafe { rodkit_tweezers_write_csv(null(), 40, spec.kt, csv.as_ptr()) });
    w.null(func, "path", unsafe { rodkit_tweezers_write_csv(pts.as_ptr(), 40, spec.kt, null()) });
    w.scalar(func, "kt", &|v| unsafe { rodkit_tweezers_write_csv(pts.as_ptr(), 40, v, csv.as_ptr()) });
    std::fs::remove_dir_all(&dir).unwrap();
    unsafe { rodkit_tweezers_free(t.cast_mut()) };
    unsafe { rodkit_tweezers_free(null_mut()) };
}

/// The walk covers the whole header: every function include/rodkit.h
/// declares is called in this file (by name), so a new entry point cannot
/// be added unwalked.
#[test]
fn every_header_function_is_walked() {
    let header = include_str!("../include/rodkit.h");
    // This file without its comments: a function only mentioned in one is
    // not walked.
    let me: String = include_str!("capi_walk.rs")
        .lines()
        .map(|l| l.find("//").map_or(l, |i| &l[..i]))
        .collect::<Vec<_>>()
        .join("\n");
    let mut missing = Vec::new();
    for line in header.lines().filter(|l| !l.trim_start().starts_with("//")) {
        for part in line.split("rodkit_").skip(1) {
            let name: String = part.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
            let after = &part[name.len()..];
            let func = format!("rodkit_{name}");
            // Named in this file as a whole word (a call, or a macro's argument).
            let named = me
                .match_indices(&func)
                .any(|(i, _)| !me[i + func.len()..].starts_with(|c: char| c.is_ascii_alphanumeric() || c == '_'));
            if after.starts_with('(') && !named {
                missing.push(func);
            }
        }
    }
    missing.sort();
    missing.dedup();
    assert!(missing.is_empty(), "header functions the walk never calls: {missing:?}");
}

/// The walk itself: every group, then no finding allowed.
#[test]
fn every_entry_point_refuses_bad_arguments_by_name() {
    let mut w = Walk::default();
    version_and_errors(&mut w);
    thin_tube(&mut w);
    dna_fit(&mut w);
    tube(&mut w);
    curve(&mut w);
    rod(&mut w);
    supercoil(&mut w);
    tweezers(&mut w);
    // Sanity of the walk itself: it made several hundred checks.
    assert!(w.checks > 500, "only {} checks", w.checks);
    eprintln!("{} checks, {} findings", w.checks, w.findings.len());
    let all: Vec<String> = w.findings.iter().map(|(id, t)| format!("{id}: {t}")).collect();
    assert!(all.is_empty(), "{} findings:\n{}", all.len(), all.join("\n"));
}

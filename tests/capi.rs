//! The C ABI exercised from Rust: the panic path, the error channel, argument
//! validation, matrix layout, version queries and the committed header.
//! References: the Rust API (the C functions must return exactly its
//! numbers) and the c-api.md conventions.

use rodkit::capi::diagnostic::rodkit_diagnostic_panic;
use rodkit::capi::error::{rodkit_last_error_copy, rodkit_last_error_message, rodkit_status_string};
use rodkit::capi::thin_tube::*;
use rodkit::capi::version::{rodkit_library_abi_version, rodkit_version};
use rodkit::tube::{OrthotropicSurface, ThinTube};
use rodkit::Status;
use std::ffi::CStr;
use std::ptr;

fn last_error() -> String {
    unsafe { CStr::from_ptr(rodkit_last_error_message()) }.to_string_lossy().into_owned()
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

#[test]
fn panic_becomes_internal_error_status() {
    let st = rodkit_diagnostic_panic();
    assert_eq!(st, Status::ErrInternal.code());
    assert!(last_error().contains("deliberate panic"), "{}", last_error());
    // Where it happened, in the message (the quiet hook keeps the place).
    assert!(last_error().contains("at src/capi/diagnostic.rs:"), "{}", last_error());
    // The library still works on this thread after the caught panic.
    let mut alpha = 0.0;
    assert_eq!(unsafe { rodkit_thin_tube_helix_angle(&dna_spec(), &mut alpha) }, 0);
    assert_eq!(last_error(), "", "a successful call clears the message");
    assert!((alpha - std::f64::consts::FRAC_PI_3).abs() < 1e-15);
}

#[test]
fn version_matches_cargo_and_rejects_null() {
    let (mut a, mut b, mut c) = (-1, -1, -1);
    assert_eq!(unsafe { rodkit_version(&mut a, &mut b, &mut c) }, 0);
    assert_eq!(format!("{a}.{b}.{c}"), env!("CARGO_PKG_VERSION"));
    assert_eq!(rodkit_library_abi_version(), rodkit::version::ABI_VERSION);
    let st = unsafe { rodkit_version(&mut a, ptr::null_mut(), &mut c) };
    assert_eq!(st, Status::ErrNullPointer.code());
    assert!(last_error().contains("`minor`"), "{}", last_error());
}

#[test]
fn status_strings_come_from_the_one_list() {
    for s in Status::ALL {
        let text = unsafe { CStr::from_ptr(rodkit_status_string(s.code())) }.to_str().unwrap();
        assert_eq!(text, s.message());
    }
    let unknown = unsafe { CStr::from_ptr(rodkit_status_string(12345)) }.to_str().unwrap();
    assert!(unknown.contains("unknown"));
}

#[test]
fn last_error_copy_truncates_with_information_status() {
    let mut spec = dna_spec();
    spec.thickness = -0.5;
    let mut k = [0.0; 9];
    let st = unsafe { rodkit_thin_tube_coupling_stiffness(&spec, k.as_mut_ptr(), 3) };
    assert_eq!(st, Status::ErrNotPositive.code());
    let full = last_error();
    assert!(full.contains("`spec.thickness`") && full.contains("-5e-1"), "{full}");

    let mut buf = [0x55u8; 12];
    let mut len = 0i64;
    let st = unsafe { rodkit_last_error_copy(buf.as_mut_ptr().cast(), buf.len() as i64, &mut len) };
    assert_eq!(st, Status::InfoTruncated.code());
    assert_eq!(len as usize, full.len());
    assert_eq!(&buf[..11], &full.as_bytes()[..11]);
    assert_eq!(buf[11], 0);
    // Copying does not consume the message.
    assert_eq!(last_error(), full);
    let mut big = [0u8; 256];
    let st = unsafe { rodkit_last_error_copy(big.as_mut_ptr().cast(), 256, ptr::null_mut()) };
    assert_eq!(st, 0);
    assert_eq!(CStr::from_bytes_until_nul(&big).unwrap().to_str().unwrap(), full);
    let st = unsafe { rodkit_last_error_copy(ptr::null_mut(), 10, ptr::null_mut()) };
    assert_eq!(st, Status::ErrNullPointer.code());
}

/// Each bad input of the issue gets its own negative status and a message
/// naming the argument (and its value, where there is one).
#[test]
fn bad_inputs_get_statuses_naming_the_argument() {
    let mut k = [0.0; 9];
    let call =
        |spec: &ThinTubeSpec, k: &mut [f64; 9]| unsafe { rodkit_thin_tube_coupling_stiffness(spec, k.as_mut_ptr(), 3) };

    let st = unsafe { rodkit_thin_tube_coupling_stiffness(ptr::null(), k.as_mut_ptr(), 3) };
    assert_eq!((st, last_error().contains("`spec`")), (Status::ErrNullPointer.code(), true));

    let mut unset = dna_spec();
    assert_eq!(unsafe { rodkit_thin_tube_spec_default(&mut unset) }, 0);
    assert!(unset.e1.is_nan() && unset.thickness.is_nan());

    // (how the spec is spoiled, the status, a part of the message)
    type Case = (Box<dyn Fn(&mut ThinTubeSpec)>, Status, &'static str);
    let cases: Vec<Case> = vec![
        (Box::new(|s| s.e1 = f64::NAN), Status::ErrNotFinite, "`spec.e1` must be finite (got NaN)"),
        (Box::new(|s| s.thickness = -0.1), Status::ErrNotPositive, "`spec.thickness` must be positive (got -1e-1)"),
        (Box::new(|s| s.e2 = 0.0), Status::ErrNotPositive, "`spec.e2` must be positive (got 0e0)"),
        (Box::new(|s| s.e2 = -3.0), Status::ErrNotPositive, "`spec.e2`"),
        (Box::new(|s| s.intrinsic_twist = f64::INFINITY), Status::ErrNotFinite, "`spec.intrinsic_twist`"),
        (Box::new(|s| s.thickness = 2.5), Status::ErrInvalidGeometry, "thickness 2.5e0"),
        (Box::new(|s| s.nu12 = 2.0), Status::ErrNotPositiveDefinite, "nu12 = 2e0"),
    ];
    for (mutate, status, needle) in cases {
        let mut spec = dna_spec();
        mutate(&mut spec);
        k = [7.0; 9];
        assert_eq!(call(&spec, &mut k), status.code(), "{needle}");
        assert!(last_error().contains(needle), "expected `{needle}` in `{}`", last_error());
        assert_eq!(k, [7.0; 9], "outputs are not written on failure");
    }
    let st = unsafe { rodkit_thin_tube_coupling_stiffness(&dna_spec(), k.as_mut_ptr(), 2) };
    assert_eq!(st, Status::ErrInvalidDimension.code());
    assert!(last_error().contains("`ldk`") && last_error().contains("got 2"));
    let st = unsafe { rodkit_thin_tube_coupling_stiffness(&dna_spec(), ptr::null_mut(), 3) };
    assert_eq!((st, last_error().contains("`k`")), (Status::ErrNullPointer.code(), true));
    let st = unsafe { rodkit_thin_tube_free_response(&dna_spec(), ptr::null_mut()) };
    assert_eq!((st, last_error().contains("`response`")), (Status::ErrNullPointer.code(), true));
}

/// The C functions return exactly the Rust API's numbers, in the documented
/// column-major layout with a leading dimension (padding left untouched).
#[test]
fn c_results_equal_rust_results_in_documented_layout() {
    let spec = dna_spec();
    let tube = ThinTube::new(
        spec.mid_radius,
        spec.thickness,
        spec.intrinsic_twist,
        OrthotropicSurface::new(spec.e1, spec.e2, spec.nu12, spec.g12).unwrap(),
    )
    .unwrap();
    let c = tube.coupling_stiffness().unwrap();

    let mut k = [-1.0; 5 * 2 + 3];
    assert_eq!(unsafe { rodkit_thin_tube_coupling_stiffness(&spec, k.as_mut_ptr(), 5) }, 0);
    for j in 0..3 {
        for i in 0..3 {
            assert_eq!(k[i + 5 * j], c.k[(i, j)], "K[{i},{j}]");
        }
    }
    for j in 0..2 {
        for i in 3..5 {
            assert_eq!(k[i + 5 * j], -1.0, "padding row {i} of column {j} was written");
        }
    }

    let mut s = [0.0; 4];
    assert_eq!(unsafe { rodkit_thin_tube_stretch_twist(&spec, s.as_mut_ptr(), 2) }, 0);
    let law = c.stretch_twist();
    assert_eq!(s, [law.stretch, law.coupling, law.coupling, law.twist]);

    let mut r = FreeTubeResponse { dstrain_dforce: 0.0, dtwist_dforce: 0.0, dhoop_dforce: 0.0, winding: 9 };
    assert_eq!(unsafe { rodkit_thin_tube_free_response(&spec, &mut r) }, 0);
    let rr = c.free_response().unwrap();
    assert_eq!(
        (r.dstrain_dforce, r.dtwist_dforce, r.dhoop_dforce, r.winding),
        (rr.dstrain_dforce, rr.dtwist_dforce, rr.dhoop_dforce, rr.winding as i32)
    );
}

/// The error channel is per thread: a failure on one thread does not leak
/// into another, and concurrent calls give identical results.
#[test]
fn error_channel_is_thread_local() {
    let handles: Vec<_> = (0..4)
        .map(|i| {
            std::thread::spawn(move || {
                let mut spec = dna_spec();
                let mut k = [0.0; 9];
                for _ in 0..200 {
                    if i % 2 == 0 {
                        spec.e2 = -1.0;
                        assert_eq!(
                            unsafe { rodkit_thin_tube_coupling_stiffness(&spec, k.as_mut_ptr(), 3) },
                            Status::ErrNotPositive.code()
                        );
                        assert!(last_error().contains("`spec.e2`"));
                    } else {
                        assert_eq!(unsafe { rodkit_thin_tube_coupling_stiffness(&spec, k.as_mut_ptr(), 3) }, 0);
                        assert_eq!(last_error(), "");
                    }
                }
            })
        })
        .collect();
    for h in handles {
        h.join().unwrap();
    }
}

/// The header's thread statement (cbindgen.toml: "Threads", "MPI"): the
/// same supercoiling runs, their curve summaries and curve points, and a
/// thin-tube call, from 4 threads at once on distinct handles, equal the
/// serial calls bitwise; one of the concurrent runs asks for 2 threads of
/// its own (RodkitDnaSupercoilSpec.threads) and equals its serial
/// 2-thread run. Reference: the serial calls on this thread (every f64
/// compared by its bits). Scenes: 150 bp, 12 elements, at most 20 steps a
/// branch, to 1.5 turns, at 0.05, 0.1 and 0.2 M (buckled, summarised;
/// ~0.3 s each).
#[test]
fn concurrent_calls_on_distinct_handles_equal_serial_ones() {
    use rodkit::capi::supercoil::*;
    use rodkit::capi::supercoil_curve::*;
    fn scene(salt: f64, threads: i64) -> DnaSupercoilSpec {
        let mut s = std::mem::MaybeUninit::<DnaSupercoilSpec>::uninit();
        assert_eq!(unsafe { rodkit_dna_supercoil_spec_default(s.as_mut_ptr()) }, 0);
        let mut s = unsafe { s.assume_init() };
        (s.base_pairs, s.elements, s.max_steps, s.max_turns, s.salt, s.threads) = (150, 12, 20, 1.5, salt, threads);
        s
    }
    /// Every number of a run, as bits: its points, curve points, summary
    /// and a tube's coupling stiffness.
    fn bits(salt: f64, threads: i64) -> Vec<u64> {
        let spec = scene(salt, threads);
        let mut run = ptr::null_mut();
        let st = unsafe { rodkit_dna_supercoil_run(&spec, &mut run) };
        assert!(st >= 0 && !run.is_null(), "status {st}: {}", last_error());
        let mut info = SupercoilInfo::default();
        assert_eq!(unsafe { rodkit_supercoil_summary(run, &mut info) }, 0);
        let n = info.points;
        assert!(info.buckled == 1 && n > 5, "{info:?}");
        let mut pts = vec![SupercoilPoint::default(); n as usize];
        let mut cpts = vec![SupercoilCurvePoint::default(); n as usize];
        let mut sum = SupercoilCurveInfo::default();
        let mut count = 0;
        unsafe {
            assert_eq!(rodkit_supercoil_points(run, pts.as_mut_ptr(), n, &mut count), 0);
            assert_eq!(rodkit_supercoil_curve_points(run, cpts.as_mut_ptr(), n, &mut count), 0);
            assert_eq!(rodkit_supercoil_curve_summary(run, &mut sum), 0);
            rodkit_supercoil_free(run);
        }
        let mut out = vec![];
        for p in &pts {
            out.extend([p.turns, p.extension, p.torque, p.tension, p.twist, p.writhe, p.residual].map(f64::to_bits));
            out.push(p.branch as u64);
        }
        for c in &cpts {
            out.extend([c.turns, c.extension, c.torque, c.energy].map(f64::to_bits));
            out.extend([c.kind as u64, c.negative_modes as u64, c.branch as u64]);
        }
        out.extend(format!("{sum:?}").bytes().map(u64::from));
        let mut k = [0.0; 9];
        assert_eq!(unsafe { rodkit_thin_tube_coupling_stiffness(&dna_spec(), k.as_mut_ptr(), 3) }, 0);
        out.extend(k.map(f64::to_bits));
        out
    }
    let jobs = [(0.1, 1), (0.05, 1), (0.2, 1), (0.1, 2)];
    let serial: Vec<Vec<u64>> = jobs.iter().map(|&(c, t)| bits(c, t)).collect();
    assert_ne!(serial[0], serial[1], "distinct scenes give distinct numbers");
    let barrier = std::sync::Arc::new(std::sync::Barrier::new(jobs.len()));
    let handles: Vec<_> = jobs
        .iter()
        .map(|&(c, t)| {
            let barrier = barrier.clone();
            std::thread::spawn(move || {
                barrier.wait();
                bits(c, t)
            })
        })
        .collect();
    for (k, h) in handles.into_iter().enumerate() {
        assert!(
            h.join().unwrap() == serial[k],
            "job {k} {:?}: the concurrent call differs from the serial one",
            jobs[k]
        );
    }
}

/// The header promises an empty message after a successful call, even when
/// a callback inside it made a failing rodkit call (issue 17: the inner
/// call's message survived a successful `rodkit_tube_sweep` and
/// `rodkit_rod_continue`). Reference: the header's words.
#[test]
fn success_leaves_the_error_channel_empty_after_a_failing_callback() {
    use rodkit::capi::branch::{rodkit_branch_free, rodkit_rod_continue, BranchProgress};
    use rodkit::capi::continuation::{rodkit_continuation_options_default, ContinuationOptions};
    use rodkit::capi::rod::{rodkit_rod_free, rodkit_rod_new};
    use rodkit::capi::rod_spec::{rodkit_rod_spec_default, LoadFrame, RodSpec};
    use rodkit::capi::tube::*;
    use rodkit::capi::wall_material::WallLawKind;
    use std::ffi::c_void;

    /// Makes a failing call (NULL `minor`) and lets the run go on.
    unsafe extern "C" fn failing_tube_callback(_: *const Progress, _: *mut c_void) -> i32 {
        let mut v = 0;
        assert_eq!(rodkit_version(&mut v, ptr::null_mut(), &mut v), Status::ErrNullPointer.code());
        0
    }
    unsafe extern "C" fn failing_branch_callback(_: *const BranchProgress, _: *mut c_void) -> i32 {
        let mut v = 0;
        assert_eq!(rodkit_version(&mut v, ptr::null_mut(), &mut v), Status::ErrNullPointer.code());
        0
    }

    // A neo-Hookean tube stretched in three states.
    let mut spec = std::mem::MaybeUninit::<TubeSpec>::uninit();
    assert_eq!(unsafe { rodkit_tube_spec_default(spec.as_mut_ptr()) }, 0);
    let mut spec = unsafe { spec.assume_init() };
    (spec.inner_radius, spec.outer_radius) = (1.0, 1.2);
    spec.material.law = WallLawKind::NeoHookean as i32;
    (spec.material.shear_modulus, spec.material.lame_lambda) = (1.0, 2.0);
    let mut tube = ptr::null_mut();
    assert_eq!(unsafe { rodkit_tube_new(&spec, &mut tube) }, 0, "{}", last_error());
    let mut loading = std::mem::MaybeUninit::<TubeLoading>::uninit();
    assert_eq!(unsafe { rodkit_tube_loading_default(loading.as_mut_ptr()) }, 0);
    let loading = unsafe { loading.assume_init() };
    let loadings: Vec<TubeLoading> = [1.0, 1.01, 1.02].iter().map(|&axial| TubeLoading { axial, ..loading }).collect();
    let mut states = [TubeState::default(); 3];
    let mut done = 0i64;
    let st = unsafe {
        rodkit_tube_sweep(
            tube,
            loadings.as_ptr(),
            3,
            states.as_mut_ptr(),
            Some(failing_tube_callback),
            ptr::null_mut(),
            &mut done,
        )
    };
    assert_eq!((st, done), (0, 3));
    assert_eq!(last_error(), "", "rodkit_tube_sweep succeeded: the channel must be empty");
    unsafe { rodkit_tube_free(tube) };

    // A cantilever under a follower moment, three steps.
    let mut rs = std::mem::MaybeUninit::<RodSpec>::uninit();
    assert_eq!(unsafe { rodkit_rod_spec_default(rs.as_mut_ptr()) }, 0);
    let mut rs = unsafe { rs.assume_init() };
    rs.length = 1.0;
    (rs.bending1, rs.bending2, rs.twist, rs.shear1, rs.shear2, rs.stretch) = (1.0, 1.0, 1.0, 1e4, 1e4, 1e4);
    (rs.tip_moment_frame, rs.tip_moment_x, rs.elements) = (LoadFrame::Follower as i32, 1.0, 2);
    let mut rod = ptr::null_mut();
    assert_eq!(unsafe { rodkit_rod_new(&rs, &mut rod) }, 0, "{}", last_error());
    let mut o = std::mem::MaybeUninit::<ContinuationOptions>::uninit();
    assert_eq!(unsafe { rodkit_continuation_options_default(o.as_mut_ptr()) }, 0);
    let mut o = unsafe { o.assume_init() };
    o.target_lambda = 0.5;
    let mut b = ptr::null_mut();
    let st = unsafe {
        rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, Some(failing_branch_callback), ptr::null_mut(), &mut b)
    };
    assert_eq!(st, 0);
    assert_eq!(last_error(), "", "rodkit_rod_continue succeeded: the channel must be empty");
    unsafe { rodkit_branch_free(b) };
    unsafe { rodkit_rod_free(rod) };
}

/// c-api.md: the committed header must equal a fresh cbindgen generation.
#[test]
fn header_is_current() {
    let generated = std::fs::read_to_string(env!("RODKIT_GENERATED_HEADER")).unwrap();
    let committed = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/include/rodkit.h")).unwrap();
    assert!(
        generated == committed,
        "include/rodkit.h is stale: regenerate it with `RODKIT_WRITE_HEADER=1 cargo build` and commit it"
    );
}

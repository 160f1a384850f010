//! The rod C ABI exercised from Rust: spec validation by field name, the
//! handles' lifecycle, the double* kernels against the Rust system and
//! finite differences, continuation statuses (target, cancel, step limit),
//! truncating copies.

use rodkit::capi::accuracy::*;
use rodkit::capi::branch::*;
use rodkit::capi::branch_record::*;
use rodkit::capi::continuation::*;
use rodkit::capi::error::rodkit_last_error_message;
use rodkit::capi::rod::*;
use rodkit::capi::rod_spec::*;
use rodkit::Status;
use std::ffi::{c_void, CStr};
use std::ptr;

fn last_error() -> String {
    unsafe { CStr::from_ptr(rodkit_last_error_message()) }.to_string_lossy().into_owned()
}

fn spec() -> RodSpec {
    let mut s = std::mem::MaybeUninit::<RodSpec>::uninit();
    assert_eq!(unsafe { rodkit_rod_spec_default(s.as_mut_ptr()) }, 0);
    let mut s = unsafe { s.assume_init() };
    s.length = 1.0;
    (s.bending1, s.bending2, s.twist, s.shear1, s.shear2, s.stretch) = (1.0, 1.0, 1.0 / 1.3, 1e4, 1e4, 2.6e4);
    s.tip_moment_frame = LoadFrame::Follower as i32;
    s.tip_moment_x = 1.0;
    s.elements = 4;
    s
}

fn options() -> ContinuationOptions {
    let mut o = std::mem::MaybeUninit::<ContinuationOptions>::uninit();
    assert_eq!(unsafe { rodkit_continuation_options_default(o.as_mut_ptr()) }, 0);
    unsafe { o.assume_init() }
}

fn new_rod(s: &RodSpec) -> Result<*mut Rod, (i32, String)> {
    let mut r = ptr::null_mut();
    let st = unsafe { rodkit_rod_new(s, &mut r) };
    if st < 0 {
        assert!(r.is_null());
        Err((st, last_error()))
    } else {
        Ok(r)
    }
}

#[test]
fn specs_are_validated_by_field() {
    let mut s = spec();
    s.length = f64::NAN;
    let (st, msg) = new_rod(&s).unwrap_err();
    assert_eq!(st, Status::ErrNotFinite.code());
    assert!(msg.contains("spec.length"), "{msg}");
    let mut s = spec();
    s.bend_shear = 200.0; // c2² > K_b G
    let (st, msg) = new_rod(&s).unwrap_err();
    assert_eq!(st, Status::ErrNotPositiveDefinite.code(), "{msg}");
    let mut s = spec();
    s.tip_force_frame = 7;
    let (st, msg) = new_rod(&s).unwrap_err();
    assert_eq!(st, Status::ErrOutOfRange.code());
    assert!(msg.contains("spec.tip_force_frame"), "{msg}");
    let mut s = spec();
    s.stages = 9;
    assert!(new_rod(&s).unwrap_err().1.contains("spec.stages"));
    let mut s = spec();
    s.shear1 = -1.0;
    assert_eq!(new_rod(&s).unwrap_err().0, Status::ErrNotPositive.code());
    assert_eq!(unsafe { rodkit_rod_new(ptr::null(), ptr::null_mut()) }, Status::ErrNullPointer.code());
    unsafe { rodkit_rod_free(ptr::null_mut()) };
    // Options too.
    let rod = new_rod(&spec()).unwrap();
    let mut o = options();
    o.anm_order = 1;
    let mut b = ptr::null_mut();
    let st = unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) };
    assert_eq!(st, Status::ErrOutOfRange.code());
    assert!(last_error().contains("options.anm_order"), "{}", last_error());
    assert!(b.is_null());
    unsafe { rodkit_rod_free(rod) };
}

/// The kernels equal the Rust system (same code path) and the Jacobian
/// equals central differences of the residual kernel (reference: the
/// definition); the ODE right-hand side of a straight rod under a moment
/// M about d1 is q' = ½q∘(0, M/K_b, 0, 0) (reference: physics.md §2.1).
#[test]
fn kernels_match_rust_and_differences() {
    let rod = new_rod(&spec()).unwrap();
    let mut n = 0;
    assert_eq!(unsafe { rodkit_rod_unknowns(rod, &mut n) }, 0);
    let mut x = vec![0.0; n as usize];
    assert_eq!(unsafe { rodkit_rod_straight_state(rod, x.as_mut_ptr(), n) }, 0);
    for (i, v) in x.iter_mut().enumerate() {
        *v += 1e-2 * ((i * 37 % 11) as f64 - 5.0) / 5.0;
    }
    let lambda = 0.7;
    let mut r = vec![0.0; n as usize];
    assert_eq!(unsafe { rodkit_rod_residual(rod, x.as_ptr(), n, lambda, r.as_mut_ptr()) }, 0);
    let mut nnz = 0;
    assert_eq!(
        unsafe { rodkit_rod_jacobian_pattern(rod, ptr::null_mut(), ptr::null_mut(), 0, &mut nnz) },
        Status::InfoTruncated.code()
    );
    let mut cp = vec![0i64; n as usize + 1];
    let mut ri = vec![0i64; nnz as usize];
    assert_eq!(unsafe { rodkit_rod_jacobian_pattern(rod, cp.as_mut_ptr(), ri.as_mut_ptr(), nnz, &mut nnz) }, 0);
    let mut vals = vec![0.0; nnz as usize];
    let mut dl = vec![0.0; n as usize];
    assert_eq!(unsafe { rodkit_rod_jacobian(rod, x.as_ptr(), n, lambda, vals.as_mut_ptr(), nnz, dl.as_mut_ptr()) }, 0);
    let h = 1e-6;
    let res = |x: &[f64], l: f64| {
        let mut out = vec![0.0; n as usize];
        assert_eq!(unsafe { rodkit_rod_residual(rod, x.as_ptr(), n, l, out.as_mut_ptr()) }, 0);
        out
    };
    for j in (0..n as usize).step_by(7) {
        let (mut xp, mut xm) = (x.clone(), x.clone());
        xp[j] += h;
        xm[j] -= h;
        let (fp, fm) = (res(&xp, lambda), res(&xm, lambda));
        let mut col = vec![0.0; n as usize];
        for k in cp[j] as usize..cp[j + 1] as usize {
            col[ri[k] as usize] = vals[k];
        }
        for i in 0..n as usize {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            assert!((fd - col[i]).abs() < 1e-6 * (1.0 + fd.abs()), "J[{i}, {j}] = {} vs differences {fd}", col[i]);
        }
    }
    let (fp, fm) = (res(&x, lambda + h), res(&x, lambda - h));
    for i in 0..n as usize {
        assert!(((fp[i] - fm[i]) / (2.0 * h) - dl[i]).abs() < 1e-6);
    }
    // ODE right-hand side.
    let y = [0.0, 0.0, 0.3, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0];
    let mut dy = [0.0; 13];
    assert_eq!(unsafe { rodkit_rod_rhs(rod, y.as_ptr(), 0.0, dy.as_mut_ptr()) }, 0);
    let want = [0.0, 0.0, 1.0, 0.0, 0.25, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    for k in 0..13 {
        assert!((dy[k] - want[k]).abs() < 1e-15, "dy[{k}] = {}", dy[k]);
    }
    // Bad lengths are statuses.
    assert_eq!(
        unsafe { rodkit_rod_residual(rod, x.as_ptr(), n - 1, lambda, r.as_mut_ptr()) },
        Status::ErrInvalidDimension.code()
    );
    unsafe { rodkit_rod_free(rod) };
}

unsafe extern "C" fn stop_after_three(p: *const BranchProgress, _: *mut c_void) -> i32 {
    ((*p).points >= 3) as i32
}

/// Statuses of a continuation: the target (0, the ring closes: tip at the
/// origin, physics.md §2.6), a cancelling callback (INFO_CANCELLED with
/// the points so far), the step limit (INFO_STEP_LIMIT); truncated copies.
#[test]
fn continuation_statuses_and_records() {
    let mut s = spec();
    s.diameter = -1.0;
    assert!(new_rod(&s).unwrap_err().1.contains("spec.diameter"));
    s.diameter = 0.05;
    let rod = new_rod(&s).unwrap();
    let mut o = options();
    o.target_lambda = 2.0 * std::f64::consts::PI;
    o.max_step = 2.0;
    let mut b = ptr::null_mut();
    assert_eq!(unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) }, 0);
    let mut info = BranchInfo::default();
    assert_eq!(unsafe { rodkit_branch_summary(b, &mut info) }, 0);
    assert_eq!(info.stop, BranchStop::Target as i32);
    // The ring closes on itself: contact reported (tests/rod_basic.rs checks
    // the distance against the closed-form chord).
    assert!(info.contact_record >= 0 && info.contact_distance < 0.05, "{info:?}");
    let mut recs = vec![BranchRecord::default(); info.records as usize];
    let mut count = 0;
    assert_eq!(unsafe { rodkit_branch_records(b, recs.as_mut_ptr(), 1, &mut count) }, Status::InfoTruncated.code());
    assert_eq!(unsafe { rodkit_branch_records(b, recs.as_mut_ptr(), info.records, &mut count) }, 0);
    let last = recs[count as usize - 1];
    assert_eq!(last.lambda, 2.0 * std::f64::consts::PI);
    assert!(last.tip_x.abs() < 1e-6 && last.tip_y.abs() < 1e-6 && last.tip_z.abs() < 1e-6, "{last:?}");
    let mut xyz = vec![0.0; 3 * 5];
    assert_eq!(unsafe { rodkit_branch_positions(b, rod, count - 1, xyz.as_mut_ptr(), 3, 5) }, 0);
    assert_eq!([xyz[12], xyz[13], xyz[14]], [last.tip_x, last.tip_y, last.tip_z]);
    unsafe { rodkit_branch_free(b) };
    // Cancelled by the callback after 3 points.
    let mut b = ptr::null_mut();
    let st =
        unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, Some(stop_after_three), ptr::null_mut(), &mut b) };
    assert_eq!(st, Status::InfoCancelled.code());
    unsafe { rodkit_branch_summary(b, &mut info) };
    assert_eq!((info.records, info.stop), (3, BranchStop::Cancelled as i32));
    unsafe { rodkit_branch_free(b) };
    // The step limit.
    o.max_steps = 1;
    o.method = ContinuationMethod::Newton as i32;
    let mut b = ptr::null_mut();
    assert_eq!(
        unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) },
        Status::InfoStepLimit.code()
    );
    unsafe { rodkit_branch_free(b) };
    unsafe { rodkit_rod_free(rod) };
}

/// A Kirchhoff rod (unit K_b and length) with its end rotation or end
/// moment controlled, twist stiffness `twist`, and Newton options to
/// `target` with bifurcation detection (residual 1e-12).
fn end_controlled(supports: RodSupports, twist: f64, elements: i64, target: f64) -> (*mut Rod, ContinuationOptions) {
    let mut s = spec();
    s.kirchhoff = 1;
    s.twist = twist;
    s.tip_moment_frame = LoadFrame::None as i32;
    s.supports = supports as i32;
    s.elements = elements;
    let rod = new_rod(&s).unwrap();
    let mut o = options();
    o.method = ContinuationMethod::Newton as i32;
    o.target_lambda = target;
    o.initial_step = 0.2;
    o.max_step = 0.5;
    o.residual_tol = 1e-12;
    o.detect_bifurcations = 1;
    (rod, o)
}

/// Greenhill through the C ABI (supports = TWISTED): the double point at
/// φ_c = 2·4.4934…·K_b/C (tan x = x, see tests/rod_buckling.rs), records
/// reporting φ in end_rotation.
#[test]
fn greenhill_through_the_c_abi() {
    let (rod, o) = end_controlled(RodSupports::Twisted, 4.0, 16, 0.99);
    let mut b = ptr::null_mut();
    assert_eq!(
        unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) },
        0,
        "{}",
        last_error()
    );
    let mut bif = Bifurcation::default();
    let mut count = 0;
    assert_eq!(unsafe { rodkit_branch_bifurcations(b, rod, &mut bif, 1, &mut count) }, 0);
    assert_eq!((count, bif.multiplicity), (1, 2));
    let phi_c = 2.0 * 4.493409457909064 / 4.0;
    assert!((2.0 * bif.lambda.asin() - phi_c).abs() < 1e-8 * phi_c, "{}", 2.0 * bif.lambda.asin());
    let mut info = BranchInfo::default();
    unsafe { rodkit_branch_summary(b, &mut info) };
    let mut recs = vec![BranchRecord::default(); info.records as usize];
    unsafe { rodkit_branch_records(b, recs.as_mut_ptr(), info.records, &mut count) };
    for r in &recs {
        assert!((r.end_rotation - 2.0 * r.lambda.asin()).abs() < 1e-12);
    }
    unsafe { rodkit_branch_free(b) };
    unsafe { rodkit_rod_free(rod) };
}

/// Greenhill past several turns under rotation control, through the C ABI
/// (C = K_b = 1, 16 elements, Λ = sin(φ/2), continued until φ > 24 by the
/// callback): the double points at θ = 8.987, 15.451, 21.808 (tan(θ/2) =
/// θ/2, see tests/rod_bifurcations.rs) each reported once with its end
/// rotation (continuous past 4π, like the records'), the record it
/// follows, its evidence and its state (whose straight twist gives back
/// φ: m3 = Cφ/L at the tip); no unresolved bracket.
#[test]
fn bifurcation_points_with_their_place_through_the_c_abi() {
    // The progress report's `turns` (φ/2π, continuous): the callback
    // stops past φ = 24, which Λ = sin(φ/2) cannot tell.
    unsafe extern "C" fn until_phi_24(p: *const BranchProgress, _: *mut c_void) -> i32 {
        ((*p).turns * 2.0 * std::f64::consts::PI > 24.0) as i32
    }
    let (rod, mut o) = end_controlled(RodSupports::Twisted, 1.0, 16, 2.0);
    o.residual_tol = 1e-10;
    o.initial_step = 0.05;
    o.max_step = 1.0;
    o.bifurcation_tol = 1e-9;
    let mut b = ptr::null_mut();
    let st = unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, Some(until_phi_24), ptr::null_mut(), &mut b) };
    assert_eq!(st, Status::InfoCancelled.code(), "{}", last_error());
    let mut info = BranchInfo::default();
    unsafe { rodkit_branch_summary(b, &mut info) };
    let mut recs = vec![BranchRecord::default(); info.records as usize];
    let mut count = 0;
    unsafe { rodkit_branch_records(b, recs.as_mut_ptr(), info.records, &mut count) };
    assert!(recs.last().unwrap().end_rotation > 24.0, "φ reached {}", recs.last().unwrap().end_rotation);
    assert!(recs.windows(2).all(|w| w[1].end_rotation > w[0].end_rotation), "φ continuous and increasing");
    let mut points = vec![BifurcationPoint::default(); 8];
    assert_eq!(unsafe { rodkit_branch_bifurcation_points(b, rod, points.as_mut_ptr(), 8, &mut count) }, 0);
    assert_eq!(count, 3, "{:?}", &points[..count as usize]);
    let mut unresolved = UnresolvedBifurcation::default();
    let mut n_unresolved = -1;
    assert_eq!(unsafe { rodkit_branch_unresolved(b, &mut unresolved, 1, &mut n_unresolved) }, 0);
    assert_eq!(n_unresolved, 0);
    let mut x = vec![0.0; info.state_length as usize];
    for (k, (p, theta)) in points.iter().zip([8.986818915818128, 15.450503673875414, 21.808243318857798]).enumerate() {
        assert!((p.end_rotation - theta).abs() < 4e-5 * theta, "point {k}: φ {} against {theta}", p.end_rotation);
        assert_eq!(p.multiplicity, 2);
        assert_eq!((p.test_function_change, p.det_sign_change), (1, 0), "point {k}");
        let (lo, hi) = (recs[p.record as usize].end_rotation, recs[p.record as usize + 1].end_rotation);
        assert!(lo <= p.end_rotation && p.end_rotation <= hi, "point {k}: φ {} not in ({lo}, {hi})", p.end_rotation);
        assert_eq!(unsafe { rodkit_branch_bifurcation_state(b, k as i64, x.as_mut_ptr(), info.state_length) }, 0);
        // The straight twisted state (closed form): the tip at (0, 0, L),
        // its frame turned by φ about e3 — q = ±(cos φ/2, 0, 0, sin φ/2) —
        // and the spatial moment (0, 0, Cφ/L) (C = L = 1), read through the
        // node accessor (the tip is node 16).
        let (mut r, mut q, mut m) = ([0.0; 3], [0.0; 4], [0.0; 3]);
        let st = unsafe {
            rodkit_rod_node_state(
                rod,
                x.as_ptr(),
                info.state_length,
                16,
                r.as_mut_ptr(),
                q.as_mut_ptr(),
                ptr::null_mut(),
                m.as_mut_ptr(),
            )
        };
        assert_eq!(st, 0, "{}", last_error());
        let half = 0.5 * p.end_rotation;
        let sign = q[0].signum() * half.cos().signum();
        let want = [half.cos(), 0.0, 0.0, half.sin()];
        assert!(
            q.iter().zip(&want).all(|(a, b)| (a - sign * b).abs() < 1e-9),
            "point {k}: q {q:?}, φ {}",
            p.end_rotation
        );
        // (z to 1e-7: the collocated twisted rod shortens by the scheme's
        // error, ∝ (φh)⁸ on Gauss(4) — 1.4e-11 at φ = 9 on 16 elements,
        // 1.0e-9 at 15.5.)
        assert!(r[0].abs() + r[1].abs() < 1e-12 && (r[2] - 1.0).abs() < 1e-7, "point {k}: r {r:?}");
        assert!((m[2] - p.end_rotation).abs() < 1e-8 * theta && m[0].abs() + m[1].abs() < 1e-9, "point {k}: m {m:?}");
    }
    // The accessor's arguments: a node past the tip, a wrong length.
    let node = |i: i64, n: i64| unsafe {
        rodkit_rod_node_state(rod, x.as_ptr(), n, i, ptr::null_mut(), ptr::null_mut(), ptr::null_mut(), ptr::null_mut())
    };
    assert_eq!(node(17, info.state_length), Status::ErrOutOfRange.code());
    assert_eq!(node(0, info.state_length - 1), Status::ErrInvalidDimension.code());
    assert_eq!(node(0, info.state_length), 0);
    assert_eq!(
        unsafe { rodkit_branch_bifurcation_state(b, 3, x.as_mut_ptr(), info.state_length) },
        Status::ErrOutOfRange.code()
    );
    unsafe { rodkit_branch_free(b) };
    unsafe { rodkit_rod_free(rod) };
}

/// A torque clamp through the C ABI (supports = TORQUED, Λ the end moment):
/// with a soft twist (C = 0.5) the straight branch turns the end by φ =
/// ML/C, past two turns before the Greenhill double point at M_c =
/// 2·4.4934…·K_b/L (independent of C); end_rotation follows the turns
/// (unwrapped past ±2π) to 1e-9. 32 elements: the frame turns 18 rad along
/// the rod, and on 16 Gauss(4) elements (1.1 rad each) M_c was off by 8e-8.
#[test]
fn torque_clamp_through_the_c_abi() {
    let (rod, mut o) = end_controlled(RodSupports::Torqued, 0.5, 32, 7.0);
    // Samples turns apart (φ = 1, 8, 13): each is unwrapped from the record
    // that starts its step, not from the previous sample (which resolves
    // only ±2π and gave 1, −4.57, −10.13 before).
    let loads = [0.5, 4.0, 6.5];
    o.samples = loads.as_ptr();
    o.sample_count = loads.len() as i64;
    let mut b = ptr::null_mut();
    assert_eq!(
        unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) },
        0,
        "{}",
        last_error()
    );
    // The straight rod's twist: φ = M L / C = 2M (C = 0.5, L = 1), exact.
    let straight = |r: &BranchRecord, what: &str| {
        assert!(
            (r.end_rotation - r.lambda / 0.5).abs() < 1e-9 * (1.0 + r.end_rotation.abs()),
            "{what}: φ {} at M {}",
            r.end_rotation,
            r.lambda
        );
    };
    let records = |b: *mut Branch| {
        let mut info = BranchInfo::default();
        unsafe { rodkit_branch_summary(b, &mut info) };
        let mut recs = vec![BranchRecord::default(); info.records as usize];
        let mut count = 0;
        unsafe { rodkit_branch_records(b, recs.as_mut_ptr(), info.records, &mut count) };
        recs
    };
    let first = records(b);
    first.iter().for_each(|r| straight(r, "record"));
    let mut samples = vec![BranchRecord::default(); 3];
    let mut count = 0;
    assert_eq!(unsafe { rodkit_branch_samples(b, samples.as_mut_ptr(), 3, &mut count) }, 0);
    assert_eq!(count, 3);
    samples.iter().for_each(|r| straight(r, "sample"));
    // Resumed past 4π (φ = 14 at M = 7, its state's angle 14 − 4π): the
    // resumed records continue the turns.
    o.target_lambda = 10.0;
    o.sample_count = 0;
    let mut b2 = ptr::null_mut();
    assert_eq!(unsafe { rodkit_branch_resume(rod, b, &o, None, ptr::null_mut(), &mut b2) }, 0, "{}", last_error());
    let resumed = records(b2);
    assert!(
        resumed.last().unwrap().end_rotation > 4.0 * std::f64::consts::PI,
        "{}",
        resumed.last().unwrap().end_rotation
    );
    resumed.iter().for_each(|r| straight(r, "resumed record"));
    // Greenhill's critical end moment for the clamped Kirchhoff rod.
    let mut bif = Bifurcation::default();
    assert_eq!(unsafe { rodkit_branch_bifurcations(b2, rod, &mut bif, 1, &mut count) }, 0);
    assert_eq!((count, bif.multiplicity), (1, 2));
    let m_c = 2.0 * 4.493409457909064;
    assert!((bif.lambda - m_c).abs() < 1e-8 * m_c, "{}", bif.lambda);
    // The buckled branch leaves at φ = 2M_c = 17.97 (its state's angle
    // 17.97 − 4π): its first point within a first step of it.
    o.target_lambda = 20.0;
    o.max_steps = 3;
    let mut b3 = ptr::null_mut();
    let st = unsafe { rodkit_branch_switch(rod, b2, 0, 0, 0.05, &o, None, ptr::null_mut(), &mut b3) };
    assert!(st >= 0, "{}", last_error());
    let buckled = records(b3);
    assert!(!buckled.is_empty());
    for r in &buckled {
        assert!((r.end_rotation - 2.0 * m_c).abs() < 0.5, "switched branch φ {} (from {})", r.end_rotation, 2.0 * m_c);
    }
    for h in [b, b2, b3] {
        unsafe { rodkit_branch_free(h) };
    }
    unsafe { rodkit_rod_free(rod) };
}

/// Dense samples through the C ABI: the pure follower end moment M = Λ·K_b/L
/// about d1 bends the rod into an arc of curvature Λ/L (n ≡ 0: no stretch),
/// tip closed form below; each requested load
/// comes back as a record within the tolerance, its state retrievable. A
/// branch handed back with another rod is refused; bad sample arrays are
/// refused by name.
#[test]
fn dense_samples_and_branch_ownership() {
    let rod = new_rod(&spec()).unwrap();
    let mut o = options();
    o.target_lambda = 3.0;
    o.max_step = 2.0;
    o.residual_tol = 1e-11;
    let loads = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0];
    o.samples = loads.as_ptr();
    o.sample_count = loads.len() as i64;
    for (method, pade) in [(ContinuationMethod::Anm, 0), (ContinuationMethod::Anm, 1), (ContinuationMethod::Newton, 0)]
    {
        o.method = method as i32;
        o.anm_pade = pade;
        let mut b = ptr::null_mut();
        assert_eq!(
            unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) },
            0,
            "{}",
            last_error()
        );
        let mut info = BranchInfo::default();
        assert_eq!(unsafe { rodkit_branch_summary(b, &mut info) }, 0);
        assert_eq!((info.samples, info.missed_samples), (6, 0));
        let mut out = vec![BranchRecord::default(); 6];
        let mut count = 0;
        assert_eq!(unsafe { rodkit_branch_samples(b, ptr::null_mut(), 0, &mut count) }, Status::InfoTruncated.code());
        assert_eq!(count, 6);
        assert_eq!(unsafe { rodkit_branch_samples(b, out.as_mut_ptr(), 6, &mut count) }, 0);
        for (s, &l) in out.iter().zip(&loads) {
            assert_eq!(s.lambda, l);
            assert!(s.residual <= 1e-11);
            // Arc of curvature κ = Λ bending about d1 = e1: the tip at
            // (0, −(1 − cos κ)/κ, sin κ/κ) (the sign of y from d2 = e2
            // turning towards −e3… checked by magnitude and z).
            let (ty, tz) = ((1.0 - l.cos()) / l, l.sin() / l);
            assert!(
                s.tip_x.abs() < 1e-9 && (s.tip_y.abs() - ty).abs() < 1e-9 && (s.tip_z - tz).abs() < 1e-9,
                "{method:?} Λ {l}: {s:?}"
            );
        }
        let mut x = vec![0.0; info.state_length as usize];
        assert_eq!(unsafe { rodkit_branch_sample_state(b, 5, x.as_mut_ptr(), info.state_length) }, 0);
        assert!(unsafe { rodkit_branch_sample_state(b, 6, x.as_mut_ptr(), info.state_length) } < 0);
        assert!(last_error().contains("sample"), "{}", last_error());
        // Another rod (other stiffness) cannot resume or draw this branch.
        let mut s2 = spec();
        s2.stretch = 3e4;
        let other = new_rod(&s2).unwrap();
        let mut b2 = ptr::null_mut();
        assert_eq!(
            unsafe { rodkit_branch_resume(other, b, &o, None, ptr::null_mut(), &mut b2) },
            Status::ErrOutOfRange.code()
        );
        assert!(last_error().contains("another rod"), "{}", last_error());
        assert!(b2.is_null());
        let mut xyz = vec![0.0; 15];
        assert_eq!(
            unsafe { rodkit_branch_positions(b, other, 0, xyz.as_mut_ptr(), 3, 5) },
            Status::ErrOutOfRange.code()
        );
        unsafe { rodkit_rod_free(other) };
        unsafe { rodkit_branch_free(b) };
    }
    o.method = ContinuationMethod::Anm as i32;
    o.anm_pade = 2;
    let mut b = ptr::null_mut();
    assert_eq!(
        unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) },
        Status::ErrOutOfRange.code()
    );
    assert!(last_error().contains("options.anm_pade"), "{}", last_error());
    o.anm_pade = 0;
    // Sample arrays: NULL with a count, non-finite loads.
    o.samples = ptr::null();
    assert_eq!(
        unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) },
        Status::ErrNullPointer.code()
    );
    assert!(last_error().contains("options.samples"), "{}", last_error());
    let bad = [1.0, f64::NAN];
    o.samples = bad.as_ptr();
    o.sample_count = 2;
    assert!(unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) } < 0);
    assert!(last_error().contains("samples"), "{}", last_error());
    unsafe { rodkit_rod_free(rod) };
}

/// The scaling override: with every scale 1 (instead of the rod's own) the
/// branch still reaches the same target point (the pure follower moment's
/// arc, closed form as above) within the tolerance, along a different path
/// (other step counts); bad scalings are refused by name.
#[test]
fn scaling_override() {
    let rod = new_rod(&spec()).unwrap();
    let mut n = 0;
    assert_eq!(unsafe { rodkit_rod_unknowns(rod, &mut n) }, 0);
    let mut o = options();
    o.target_lambda = 3.0;
    o.residual_tol = 1e-11;
    o.method = ContinuationMethod::Newton as i32;
    let tip_and_steps = |o: &ContinuationOptions| {
        let mut b = ptr::null_mut();
        assert_eq!(
            unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, o, None, ptr::null_mut(), &mut b) },
            0,
            "{}",
            last_error()
        );
        let mut info = BranchInfo::default();
        unsafe { rodkit_branch_summary(b, &mut info) };
        let mut recs = vec![BranchRecord::default(); info.records as usize];
        let mut count = 0;
        unsafe { rodkit_branch_records(b, recs.as_mut_ptr(), info.records, &mut count) };
        unsafe { rodkit_branch_free(b) };
        let last = recs[count as usize - 1];
        ([last.tip_x, last.tip_y, last.tip_z], info.steps)
    };
    let (tip_default, steps_default) = tip_and_steps(&o);
    let ones = vec![1.0; n as usize + 1];
    let mut big = ones.clone();
    big[n as usize] = 100.0; // Λ "typically 100": the arc length is mostly x
    o.scaling = big.as_ptr();
    o.scaling_count = n + 1;
    let (tip_big, steps_big) = tip_and_steps(&o);
    let l: f64 = 3.0;
    let (ty, tz) = ((1.0 - l.cos()) / l, l.sin() / l);
    for tip in [tip_default, tip_big] {
        assert!(tip[0].abs() < 1e-9 && (tip[1].abs() - ty).abs() < 1e-9 && (tip[2] - tz).abs() < 1e-9, "{tip:?}");
    }
    println!("steps: default scaling {steps_default}, Λ scale 100: {steps_big}");
    assert_ne!(steps_default, steps_big, "the scaling changes the arc length, hence the steps");
    o.scaling_count = n;
    assert!(
        unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut ptr::null_mut()) } < 0
    );
    assert!(last_error().contains("options.scaling_count"), "{}", last_error());
    let mut bad = ones.clone();
    bad[3] = 0.0;
    o.scaling = bad.as_ptr();
    o.scaling_count = n + 1;
    assert_eq!(
        unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut ptr::null_mut()) },
        Status::ErrNotPositive.code()
    );
    assert!(last_error().contains("options.scaling[3]"), "{}", last_error());
    unsafe { rodkit_rod_free(rod) };
}

/// Issue 17: a length of DBL_MAX gave `rodkit_rod_straight_state` status OK
/// with infinite entries. Now the rod is refused by name, its scales being
/// unrepresentable (reference: the header's promise that no non-finite
/// result leaves with status OK).
#[test]
fn a_length_whose_scales_overflow_is_refused_by_name() {
    let s = RodSpec { length: f64::MAX, ..spec() };
    let (st, msg) = new_rod(&s).unwrap_err();
    assert_eq!(st, Status::ErrOutOfRange.code(), "{msg}");
    assert!(msg.contains("`spec.length`") && msg.contains("out of range"), "{msg}");
    assert!(msg.len() < 300, "{msg}");
    // The largest accepted lengths still give a finite straight state.
    let rod = new_rod(&RodSpec { length: 1e100, ..spec() }).unwrap();
    let mut n = 0;
    assert_eq!(unsafe { rodkit_rod_unknowns(rod, &mut n) }, 0);
    let mut x = vec![f64::NAN; n as usize];
    assert_eq!(unsafe { rodkit_rod_straight_state(rod, x.as_mut_ptr(), n) }, 0);
    assert!(x.iter().all(|v| v.is_finite()));
    unsafe { rodkit_rod_free(rod) };
}

/// Issue 17: a clamped rod with `end_x` NaN returned ERR_NON_FINITE_RESULT
/// naming "end_position"; a NaN argument is ERR_NOT_FINITE naming the C
/// field (reference: the status vocabulary of src/status.rs). The same for
/// the continuation options, the supercoiling spec and the DNA fit.
#[test]
fn non_finite_fields_are_not_finite_arguments_named_by_c_field() {
    let mut s = spec();
    s.supports = RodSupports::Clamped as i32;
    s.tip_moment_frame = LoadFrame::None as i32;
    (s.end_x, s.end_y, s.end_z) = (f64::NAN, 0.0, 0.9);
    let (st, msg) = new_rod(&s).unwrap_err();
    assert_eq!((st, msg.contains("`spec.end_x`")), (Status::ErrNotFinite.code(), true), "{msg}");
    s.end_x = 0.0;
    s.end_q2 = f64::INFINITY;
    let (st, msg) = new_rod(&s).unwrap_err();
    assert_eq!((st, msg.contains("`spec.end_q2`")), (Status::ErrNotFinite.code(), true), "{msg}");

    let rod = new_rod(&spec()).unwrap();
    let mut b = ptr::null_mut();
    for (field, set) in [
        ("options.residual_tol", (|o: &mut ContinuationOptions| o.residual_tol = f64::NAN) as fn(&mut _)),
        ("options.max_step", |o| o.max_step = f64::INFINITY),
        ("options.target_lambda", |o| o.target_lambda = f64::NEG_INFINITY),
    ] {
        let mut o = options();
        set(&mut o);
        let st = unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) };
        assert_eq!(st, Status::ErrNotFinite.code(), "{field}: {}", last_error());
        assert!(last_error().contains(&format!("`{field}`")), "{}", last_error());
    }
    unsafe { rodkit_rod_free(rod) };

    use rodkit::capi::dna_fit::{rodkit_dna_fit_thin_wall, DnaFit};
    use rodkit::capi::supercoil::{rodkit_dna_supercoil_run, rodkit_dna_supercoil_spec_default, DnaSupercoilSpec};
    let mut sc = std::mem::MaybeUninit::<DnaSupercoilSpec>::uninit();
    assert_eq!(unsafe { rodkit_dna_supercoil_spec_default(sc.as_mut_ptr()) }, 0);
    let mut sc = unsafe { sc.assume_init() };
    sc.max_turns = f64::NAN;
    let mut run = ptr::null_mut();
    assert_eq!(unsafe { rodkit_dna_supercoil_run(&sc, &mut run) }, Status::ErrNotFinite.code());
    assert!(last_error().contains("`spec.max_turns`"), "{}", last_error());
    let mut fit = std::mem::MaybeUninit::<DnaFit>::uninit();
    let pi = std::f64::consts::PI;
    let st =
        unsafe { rodkit_dna_fit_thin_wall(f64::INFINITY, 440.0, -90.0, 1.0, pi / 3.0, 0.4, 0.3, fit.as_mut_ptr()) };
    assert_eq!(st, Status::ErrNotFinite.code(), "{}", last_error());
    assert!(last_error().contains("`stretch`"), "{}", last_error());
}

/// Issue 17: a general stiffness refused for its condition number was
/// reported as "not positive definite" with the whole matrix printed
/// (~1 kB). Now a short message saying what it is, numbers in {:e} style.
/// Reference: diag(1, 1, 1, 1, 1, 3.2e-14) has condition number 3.125e13.
#[test]
fn an_ill_conditioned_stiffness_gets_a_short_message() {
    let mut k = [0.0; 36];
    for (i, d) in [1.0, 1.0, 1.0, 1.0, 1.0, 3.2e-14].iter().enumerate() {
        k[7 * i] = *d;
    }
    let mut r = ptr::null_mut();
    let st = unsafe { rodkit_rod_new_general(&spec(), k.as_ptr(), 6, &mut r) };
    let msg = last_error();
    assert_eq!(st, Status::ErrNotPositiveDefinite.code(), "{msg}");
    assert!(msg.contains("ill-conditioned") && msg.contains("condition number 3.1e13 > 1e13"), "{msg}");
    assert!(msg.len() < 200 && !msg.contains('│') && !msg.contains('┌'), "{msg}");
    // A NaN entry is the caller's argument, named with its index.
    k[7] = f64::NAN;
    let st = unsafe { rodkit_rod_new_general(&spec(), k.as_ptr(), 6, &mut r) };
    assert_eq!(st, Status::ErrNotFinite.code(), "{}", last_error());
    assert!(last_error().contains("`stiffness[7]`"), "{}", last_error());
}

/// Issue 17: integers out of range are ERR_OUT_OF_RANGE saying "out of
/// range" and the valid range (reference: the status vocabulary).
#[test]
fn out_of_range_integers_say_so_with_the_range() {
    for (set, field, range) in [
        ((|s: &mut RodSpec| s.elements = 0) as fn(&mut RodSpec), "`spec.elements`", "[1, 262144]"),
        (|s| s.stages = 5, "`spec.stages`", "[2, 4]"),
        (|s| s.scheme = 3, "`spec.scheme`", "RodkitRodScheme 1…2"),
        (|s| s.kirchhoff = 2, "`spec.kirchhoff`", "0 or 1"),
    ] {
        let mut s = spec();
        set(&mut s);
        let (st, msg) = new_rod(&s).unwrap_err();
        assert_eq!(st, Status::ErrOutOfRange.code(), "{msg}");
        assert!(msg.contains(field) && msg.contains("out of range") && msg.contains(range), "{msg}");
    }
    let rod = new_rod(&spec()).unwrap();
    let mut o = options();
    o.anm_order = 61;
    let mut b = ptr::null_mut();
    let st = unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) };
    assert_eq!(st, Status::ErrOutOfRange.code());
    let msg = last_error();
    assert!(msg.contains("`options.anm_order` out of range") && msg.contains("[2, 60]"), "{msg}");
    unsafe { rodkit_rod_free(rod) };
}

/// Issue 17, found by tests/fuzz/fuzz_supercoil (seed 1, iteration 201): a
/// denormal charge per length (4.9e-324) panicked inside the charged
/// Jacobian (ERR_INTERNAL, "index out of bounds"). Now it is out of range by
/// name (reference: the status vocabulary; 0 stays the uncharged rod).
#[test]
fn a_charge_whose_square_underflows_is_refused_by_name() {
    use rodkit::capi::supercoil::{rodkit_dna_supercoil_run, rodkit_dna_supercoil_spec_default, DnaSupercoilSpec};
    let mut sc = std::mem::MaybeUninit::<DnaSupercoilSpec>::uninit();
    assert_eq!(unsafe { rodkit_dna_supercoil_spec_default(sc.as_mut_ptr()) }, 0);
    let mut sc = unsafe { sc.assume_init() };
    (sc.base_pairs, sc.elements, sc.max_steps, sc.max_turns) = (300, 16, 6, 2.0);
    sc.charge_per_length = 4.9e-324;
    let mut run = ptr::null_mut();
    let st = unsafe { rodkit_dna_supercoil_run(&sc, &mut run) };
    assert_eq!(st, Status::ErrOutOfRange.code(), "{}", last_error());
    assert!(last_error().contains("`spec.charge_per_length` out of range"), "{}", last_error());
    assert!(run.is_null());
}

/// A branch to a requested accuracy through the C ABI (issue 19): the
/// follower cantilever of `spec` (K_b = 1, GA 1e4, EA 2.6e4, tip force Λ
/// d1), α 0 → 20, tolerance 1e-6 from 4 elements. The rod returned has
/// the element count rodkit chose; every record carries an estimate ≤ the
/// tolerance; the last tip agrees with a 64-element branch (reference:
/// Gauss(4) × 64, its own error ~(64/N)⁻⁸ smaller) within the tolerance,
/// and within its estimate. Estimates of an ordinary branch are computed
/// on request (an odd element count is refused by name).
#[test]
fn a_branch_to_a_tolerance_through_the_c_abi() {
    let mut s = spec();
    (s.tip_moment_frame, s.tip_moment_x) = (LoadFrame::None as i32, 0.0);
    (s.tip_force_frame, s.tip_force_x) = (LoadFrame::Follower as i32, 1.0);
    s.elements = 4;
    let rod = new_rod(&s).unwrap();
    let mut o = options();
    o.target_lambda = 20.0;
    o.residual_tol = 1e-12;
    let (mut fine_rod, mut b) = (ptr::null_mut(), ptr::null_mut());
    let st =
        unsafe { rodkit_rod_continue_to_tolerance(rod, 1e-6, 0.0, &o, None, ptr::null_mut(), &mut fine_rod, &mut b) };
    assert_eq!(st, 0, "{}", last_error());
    let mut n = 0;
    unsafe { rodkit_rod_unknowns(fine_rod, &mut n) };
    let elements = (n / 13 - 1) / 5; // Gauss(4) of `spec`: 13 (1 + 4) per element + the tip node
                                     // The mesh chosen: N + 1 node arc lengths from 0 to L = 1, graded
                                     // (finer where the branch bends most), each node where the straight
                                     // state puts it (r = s e3: the accessor and the state layout agree).
    let mut count = 0;
    assert_eq!(unsafe { rodkit_rod_node_positions(fine_rod, ptr::null_mut(), 0, &mut count) }, 1); // truncated: asked
    assert_eq!(count, elements + 1);
    let mut mesh = vec![0.0; count as usize];
    assert_eq!(unsafe { rodkit_rod_node_positions(fine_rod, mesh.as_mut_ptr(), count, &mut count) }, 0);
    assert!(mesh[0] == 0.0 && mesh[elements as usize] == 1.0 && mesh.windows(2).all(|w| w[1] > w[0]), "{mesh:?}");
    let h: Vec<f64> = mesh.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(h.iter().cloned().fold(0.0, f64::max) > 1.05 * h.iter().cloned().fold(1.0, f64::min), "graded: {h:?}");
    let mut straight = vec![0.0; n as usize];
    unsafe { rodkit_rod_straight_state(fine_rod, straight.as_mut_ptr(), n) };
    for (i, s) in mesh.iter().enumerate() {
        let mut r = [0.0; 3];
        let st = unsafe {
            rodkit_rod_node_state(
                fine_rod,
                straight.as_ptr(),
                n,
                i as i64,
                r.as_mut_ptr(),
                ptr::null_mut(),
                ptr::null_mut(),
                ptr::null_mut(),
            )
        };
        assert!(st == 0 && (r[2] - s).abs() < 1e-15, "node {i}: r_z {} vs s {s}", r[2]);
    }
    let mut info = BranchInfo::default();
    unsafe { rodkit_branch_summary(b, &mut info) };
    let mut est = vec![RecordError::default(); info.records as usize];
    let mut count = 0;
    assert_eq!(unsafe { rodkit_branch_error_estimates(b, fine_rod, est.as_mut_ptr(), info.records, &mut count) }, 0);
    assert_eq!(count, info.records);
    assert!(est.iter().all(|e| e.estimated == 1 && e.scaled <= 1e-6), "{est:?}");
    let mut recs = vec![BranchRecord::default(); info.records as usize];
    unsafe { rodkit_branch_records(b, recs.as_mut_ptr(), info.records, &mut count) };
    let last = recs.last().unwrap();
    // The reference: 64 elements, the same options.
    s.elements = 64;
    let reference_rod = new_rod(&s).unwrap();
    let mut rb = ptr::null_mut();
    assert_eq!(
        unsafe { rodkit_rod_continue(reference_rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut rb) },
        0
    );
    let mut rinfo = BranchInfo::default();
    unsafe { rodkit_branch_summary(rb, &mut rinfo) };
    let mut rrecs = vec![BranchRecord::default(); rinfo.records as usize];
    unsafe { rodkit_branch_records(rb, rrecs.as_mut_ptr(), rinfo.records, &mut count) };
    let r = rrecs.last().unwrap();
    let err = ((last.tip_x - r.tip_x).powi(2) + (last.tip_y - r.tip_y).powi(2) + (last.tip_z - r.tip_z).powi(2)).sqrt();
    let bound = est.last().unwrap().tip_position;
    println!("to 1e-6: {elements} elements ({n} unknowns), tip error {err:e}, estimate {bound:e}");
    assert!(err <= 1e-6 && err <= bound, "tip error {err:e}, estimate {bound:e}");
    // On request: the 64-element branch's estimates (32 elements as the
    // coarse mesh), far below the tolerance's.
    let mut rest = vec![RecordError::default(); rinfo.records as usize];
    assert_eq!(
        unsafe { rodkit_branch_error_estimates(rb, reference_rod, rest.as_mut_ptr(), rinfo.records, &mut count) },
        0
    );
    assert!(rest.iter().all(|e| e.estimated == 1 && e.scaled < 1e-8), "{rest:?}");
    // Refusals: a tolerance out of range, no rod_out, an odd element count.
    let (mut r2, mut b2) = (ptr::null_mut(), ptr::null_mut());
    let st = unsafe { rodkit_rod_continue_to_tolerance(rod, 0.0, 0.0, &o, None, ptr::null_mut(), &mut r2, &mut b2) };
    assert_eq!(st, Status::ErrOutOfRange.code(), "{}", last_error());
    assert!(last_error().contains("tolerance"), "{}", last_error());
    assert!(r2.is_null() && b2.is_null());
    let st = unsafe {
        rodkit_rod_continue_to_tolerance(rod, 1e-6, 0.0, &o, None, ptr::null_mut(), ptr::null_mut(), &mut b2)
    };
    assert_eq!(st, Status::ErrNullPointer.code());
    s.elements = 5;
    let odd = new_rod(&s).unwrap();
    o.target_lambda = 1.0;
    let mut ob = ptr::null_mut();
    assert_eq!(unsafe { rodkit_rod_continue(odd, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut ob) }, 0);
    let st = unsafe { rodkit_branch_error_estimates(ob, odd, est.as_mut_ptr(), 1, &mut count) };
    assert_eq!(st, Status::ErrOutOfRange.code());
    assert!(last_error().contains("even number of elements"), "{}", last_error());
    for h in [b, rb, ob] {
        unsafe { rodkit_branch_free(h) };
    }
    for r in [rod, fine_rod, reference_rod, odd] {
        unsafe { rodkit_rod_free(r) };
    }
}

/// A target end rotation through the C ABI (rodkit_rod_set_target_rotation)
/// on Greenhill's rod under rotation control (C = K_b = L = 1, 16
/// elements): the straight branch ends exactly at φ = 24 (status 0, the
/// last record's end_rotation 24, Λ = sin 12, the twisting moment Cφ/L =
/// 24, the callback told φ up to 24), a resume counts on to a new target
/// of 30; the same through rodkit_rod_continue_to_tolerance with detection,
/// whose critical φ (Greenhill's roots θ_k, tan(θ/2) = θ/2) lie within
/// their estimates (rodkit_branch_bifurcation_errors) and the tolerance;
/// NaN clears the target; a cantilever and an infinity are refused.
#[test]
fn a_target_end_rotation_through_the_c_abi() {
    unsafe extern "C" fn max_turns(p: *const BranchProgress, seen: *mut c_void) -> i32 {
        let seen = &mut *(seen as *mut f64);
        *seen = seen.max((*p).turns);
        0
    }
    let (rod, mut o) = end_controlled(RodSupports::Twisted, 1.0, 16, f64::NAN);
    o.residual_tol = 1e-10;
    o.initial_step = 0.05;
    o.max_step = 1.0;
    o.bifurcation_tol = 1e-9;
    assert_eq!(unsafe { rodkit_rod_set_target_rotation(rod, 24.0) }, 0);
    let mut b = ptr::null_mut();
    let mut seen = 0.0f64;
    let st = unsafe {
        rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, Some(max_turns), &mut seen as *mut f64 as *mut c_void, &mut b)
    };
    assert_eq!(st, 0, "{}", last_error());
    let records = |b| {
        let mut info = BranchInfo::default();
        unsafe { rodkit_branch_summary(b, &mut info) };
        let mut recs = vec![BranchRecord::default(); info.records as usize];
        let mut count = 0;
        unsafe { rodkit_branch_records(b, recs.as_mut_ptr(), info.records, &mut count) };
        recs
    };
    let recs = records(b);
    let last = recs.last().unwrap();
    assert!((last.end_rotation - 24.0).abs() < 1e-10, "ends at φ {}", last.end_rotation);
    assert!((last.lambda - 12f64.sin()).abs() < 1e-12);
    // (The moment to the mesh's error: 9e-8 at φ = 24 on 16 elements.)
    assert!((last.base_moment_z - 24.0).abs() < 1e-8 * 24.0, "moment {}", last.base_moment_z);
    assert!((seen * 2.0 * std::f64::consts::PI - 24.0).abs() < 1e-10, "told up to {seen} turns");
    let mut count = 0;
    unsafe { rodkit_branch_bifurcation_points(b, rod, ptr::null_mut(), 0, &mut count) };
    assert_eq!(count, 3);
    // Resumed with a new target: on to φ = 30 from 24.
    assert_eq!(unsafe { rodkit_rod_set_target_rotation(rod, 30.0) }, 0);
    let mut resumed = ptr::null_mut();
    let st = unsafe { rodkit_branch_resume(rod, b, &o, None, ptr::null_mut(), &mut resumed) };
    assert_eq!(st, 0, "{}", last_error());
    let more = records(resumed);
    assert!((more[0].end_rotation - 24.0).abs() < 1e-10 && (more.last().unwrap().end_rotation - 30.0).abs() < 1e-10);

    // To a tolerance, with the critical loads' estimates.
    assert_eq!(unsafe { rodkit_rod_set_target_rotation(rod, 17.0) }, 0);
    let (mut fine_rod, mut fb) = (ptr::null_mut(), ptr::null_mut());
    o.residual_tol = 1e-12;
    let st =
        unsafe { rodkit_rod_continue_to_tolerance(rod, 1e-6, 0.0, &o, None, ptr::null_mut(), &mut fine_rod, &mut fb) };
    assert_eq!(st, 0, "{}", last_error());
    assert!((records(fb).last().unwrap().end_rotation - 17.0).abs() < 1e-10);
    let mut points = vec![BifurcationPoint::default(); 4];
    let mut errors = vec![BifurcationError::default(); 4];
    unsafe { rodkit_branch_bifurcation_points(fb, fine_rod, points.as_mut_ptr(), 4, &mut count) };
    assert_eq!(count, 2);
    assert_eq!(unsafe { rodkit_branch_bifurcation_errors(fb, fine_rod, errors.as_mut_ptr(), 4, &mut count) }, 0);
    assert_eq!(count, 2);
    for (k, (p, theta)) in points.iter().zip([8.986818915818128, 15.450503673875414]).enumerate() {
        let e = errors[k];
        let truth = (p.end_rotation - theta).abs();
        assert!(e.estimated == 1 && e.scaled <= 1e-6, "point {k}: {e:?}");
        assert!(truth <= e.end_rotation.max(1e-10) && truth <= 1e-6 * theta, "point {k}: true {truth:e}, {e:?}");
    }
    // On request for a branch not refined (16 elements: 8 as the coarse mesh).
    assert_eq!(unsafe { rodkit_branch_bifurcation_errors(b, rod, errors.as_mut_ptr(), 4, &mut count) }, 0);
    assert_eq!(count, 3);
    assert!(errors[..3].iter().all(|e| e.estimated == 1 && e.end_rotation > 0.0), "{errors:?}");

    // NaN clears: the branch runs to its target Λ.
    assert_eq!(unsafe { rodkit_rod_set_target_rotation(rod, f64::NAN) }, 0);
    o.target_lambda = 0.5;
    let mut plain = ptr::null_mut();
    assert_eq!(unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut plain) }, 0);
    assert!((records(plain).last().unwrap().lambda - 0.5).abs() < 1e-15);
    // Refusals.
    assert_eq!(unsafe { rodkit_rod_set_target_rotation(rod, f64::INFINITY) }, Status::ErrNotFinite.code());
    let cantilever = new_rod(&spec()).unwrap();
    assert_eq!(unsafe { rodkit_rod_set_target_rotation(cantilever, 1.0) }, Status::ErrOutOfRange.code());
    assert!(last_error().contains("end rotation"), "{}", last_error());
    assert_eq!(unsafe { rodkit_rod_set_target_rotation(ptr::null_mut(), 1.0) }, Status::ErrNullPointer.code());
    for h in [b, resumed, fb, plain] {
        unsafe { rodkit_branch_free(h) };
    }
    for r in [rod, fine_rod, cantilever] {
        unsafe { rodkit_rod_free(r) };
    }
}

/// `spec`'s cantilever on 8 elements under a dead tip force Λ e1 alone.
fn dead_transverse() -> RodSpec {
    let mut s = spec();
    s.tip_moment_frame = LoadFrame::None as i32;
    s.tip_moment_x = 0.0;
    s.tip_force_frame = LoadFrame::Dead as i32;
    s.tip_force_x = 1.0;
    s.elements = 8;
    s
}

/// The signed tip rotation through rodkit_rod_node_rotation: the
/// cantilever of `spec` (K_b = L = 1) under a dead tip force Λ e1 bends in
/// the (e1, e3) plane and its tip frame turns about +e2. At Λ = 1e-7
/// linear theory gives θ = ΛL²/(2K_b) = 5e-8 (shear does not turn the
/// section; the O(Λ²) correction is below 1e-14 relative): rotation[1]
/// equals it to 1e-9 relative, the other components vanish. At Λ = 3 the
/// rotation's size equals the tip tangent's unsigned angle
/// (RodkitBranchRecord.tip_rotation) — the frame turns in the plane.
/// Arguments: a node past the tip, a wrong length, NULL out.
#[test]
fn the_signed_tip_rotation_through_the_c_abi() {
    let s = dead_transverse();
    let rod = new_rod(&s).unwrap();
    let mut n = 0;
    unsafe { rodkit_rod_unknowns(rod, &mut n) };
    let mut o = options();
    o.residual_tol = 1e-13;
    for (load, check) in [(1e-7, 0), (3.0, 1)] {
        o.target_lambda = load;
        let mut b = ptr::null_mut();
        assert_eq!(unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) }, 0);
        let mut info = BranchInfo::default();
        unsafe { rodkit_branch_summary(b, &mut info) };
        let mut x = vec![0.0; n as usize];
        assert_eq!(unsafe { rodkit_branch_state(b, info.records - 1, x.as_mut_ptr(), n) }, 0);
        let mut rec = vec![BranchRecord::default(); info.records as usize];
        let mut count = 0;
        unsafe { rodkit_branch_records(b, rec.as_mut_ptr(), info.records, &mut count) };
        let mut r = [0.0; 3];
        assert_eq!(unsafe { rodkit_rod_node_rotation(rod, x.as_ptr(), n, 8, r.as_mut_ptr()) }, 0, "{}", last_error());
        if check == 0 {
            assert!((r[1] - 5e-8).abs() < 1e-9 * 5e-8, "θ {} against 5e-8", r[1]);
            assert!(r[0].abs() + r[2].abs() < 1e-20, "{r:?}");
        } else {
            let theta = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
            let tangent = rec.last().unwrap().tip_rotation;
            assert!(r[1] > 0.5 && (theta - tangent).abs() < 1e-12, "{r:?} against the tangent's {tangent}");
        }
        // The base does not turn (its clamp to the residual, 1e-13).
        assert_eq!(unsafe { rodkit_rod_node_rotation(rod, x.as_ptr(), n, 0, r.as_mut_ptr()) }, 0);
        assert!(r.iter().all(|v| v.abs() < 1e-13), "{r:?}");
        unsafe { rodkit_branch_free(b) };
    }
    let x = vec![0.0; n as usize];
    let mut r = [0.0; 3];
    assert_eq!(
        unsafe { rodkit_rod_node_rotation(rod, x.as_ptr(), n, 9, r.as_mut_ptr()) },
        Status::ErrOutOfRange.code()
    );
    assert_eq!(
        unsafe { rodkit_rod_node_rotation(rod, x.as_ptr(), n - 1, 0, r.as_mut_ptr()) },
        Status::ErrInvalidDimension.code()
    );
    assert_eq!(
        unsafe { rodkit_rod_node_rotation(rod, x.as_ptr(), n, 0, ptr::null_mut()) },
        Status::ErrNullPointer.code()
    );
    unsafe { rodkit_rod_free(rod) };
}

/// What extension and shear do, through the C ABI
/// (rodkit_branch_kirchhoff_differences): `spec`'s cantilever (K_b = L = 1,
/// GA = 1e4) under a small dead transverse tip force Λ = 1e-3: the tip
/// moves F L/GA = 1e-7 more than the unshearable rod's (Timoshenko's
/// linear theory; 1 % for the nonlinear remainder), every record has a
/// row, the start none; a Kirchhoff rod is refused.
#[test]
fn kirchhoff_differences_through_the_c_abi() {
    let mut s = dead_transverse();
    let rod = new_rod(&s).unwrap();
    let mut o = options();
    o.method = ContinuationMethod::Newton as i32;
    o.target_lambda = 1e-3;
    o.initial_step = 1e-3;
    o.residual_tol = 1e-13;
    let mut b = ptr::null_mut();
    assert_eq!(unsafe { rodkit_rod_continue(rod, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut b) }, 0);
    let mut info = BranchInfo::default();
    unsafe { rodkit_branch_summary(b, &mut info) };
    let mut rows = vec![RecordError::default(); info.records as usize];
    let mut count = 0;
    let st = unsafe { rodkit_branch_kirchhoff_differences(b, rod, rows.as_mut_ptr(), info.records, &mut count) };
    assert_eq!(st, 0, "{}", last_error());
    assert_eq!(count, info.records);
    let last = rows.last().unwrap();
    assert_eq!(last.estimated, 1);
    assert!((last.tip_position - 1e-7).abs() < 1e-9, "{last:?}");
    assert!(rows[0].estimated == 1 && rows[0].tip_position < 1e-15);
    s.kirchhoff = 1;
    let k = new_rod(&s).unwrap();
    let mut kb = ptr::null_mut();
    assert_eq!(unsafe { rodkit_rod_continue(k, ptr::null(), 0, 0.0, &o, None, ptr::null_mut(), &mut kb) }, 0);
    let st = unsafe { rodkit_branch_kirchhoff_differences(kb, k, rows.as_mut_ptr(), 1, &mut count) };
    assert_eq!(st, Status::ErrOutOfRange.code());
    assert!(last_error().contains("Kirchhoff"), "{}", last_error());
    for h in [b, kb] {
        unsafe { rodkit_branch_free(h) };
    }
    for r in [rod, k] {
        unsafe { rodkit_rod_free(r) };
    }
}

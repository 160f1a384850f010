//! The supercoiling run's progress callback and resume through the C ABI
//! (issue 18, deliverable 6): `rodkit_dna_supercoil_run_with` stopped by
//! its callback after k points returns RODKIT_STATUS_INFO_CANCELLED with
//! the path so far, `rodkit_supercoil_resume` completes it to the path of
//! the uninterrupted `rodkit_dna_supercoil_run` (reference: that run), the
//! callback is told every point once, in order; a callback that returns an
//! error code or makes a failing rodkit call follows the branch-callback
//! rules (a non-zero return stops cleanly; a successful call leaves the
//! error channel empty). Scene: 300 bp, 30 elements, 25 steps, 2.5 turns
//! (as tests/supercoil_resume.rs: 8 straight points, 34 in all).

use rodkit::capi::branch::BranchProgress;
use rodkit::capi::error::rodkit_last_error_message;
use rodkit::capi::supercoil::*;
use rodkit::capi::version::rodkit_version;
use rodkit::Status;
use std::ffi::{c_void, CStr};
use std::ptr::{null, null_mut};

fn last_error() -> String {
    unsafe { CStr::from_ptr(rodkit_last_error_message()) }.to_string_lossy().into_owned()
}

fn spec() -> DnaSupercoilSpec {
    let mut s = std::mem::MaybeUninit::<DnaSupercoilSpec>::uninit();
    assert_eq!(unsafe { rodkit_dna_supercoil_spec_default(s.as_mut_ptr()) }, 0);
    let mut s = unsafe { s.assume_init() };
    (s.base_pairs, s.elements, s.max_steps, s.max_turns) = (300, 30, 25, 2.5);
    s
}

/// What the callback saw, and when it stops (`stop_at`: the `points` value
/// after which it returns `answer`).
struct Seen {
    told: Vec<BranchProgress>,
    stop_at: i64,
    answer: i32,
}

unsafe extern "C" fn watch(p: *const BranchProgress, user_data: *mut c_void) -> i32 {
    let seen = &mut *(user_data as *mut Seen);
    seen.told.push(*p);
    if (*p).points == seen.stop_at {
        seen.answer
    } else {
        0
    }
}

/// Also makes a failing rodkit call (NULL `minor`) at each point.
unsafe extern "C" fn failing_call(p: *const BranchProgress, user_data: *mut c_void) -> i32 {
    let mut v = 0;
    assert_eq!(rodkit_version(&mut v, null_mut(), &mut v), Status::ErrNullPointer.code());
    watch(p, user_data)
}

fn points_of(run: *const Supercoil) -> Vec<SupercoilPoint> {
    let mut info = SupercoilInfo::default();
    assert_eq!(unsafe { rodkit_supercoil_summary(run, &mut info) }, 0);
    let mut pts = vec![SupercoilPoint::default(); info.points as usize];
    let mut count = 0;
    assert_eq!(unsafe { rodkit_supercoil_points(run, pts.as_mut_ptr(), info.points, &mut count) }, 0);
    pts
}

fn stop_of(run: *const Supercoil) -> i32 {
    let mut stop = -1;
    assert_eq!(unsafe { rodkit_supercoil_stop(run, &mut stop) }, 0);
    stop
}

fn same(a: &[SupercoilPoint], b: &[SupercoilPoint]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(p, q)| {
            (p.turns, p.extension, p.torque, p.tension, p.twist, p.writhe, p.branch, p.residual)
                == (q.turns, q.extension, q.torque, q.tension, q.twist, q.writhe, q.branch, q.residual)
        })
}

/// Stop after k = 20 points (on the buckled branch), resume: the status,
/// the path so far, then the uninterrupted path bitwise (the buckled
/// branch resumes with its own tangent, step and pair list:
/// tests/supercoil_resume.rs); every point told once, in order, with the
/// numbers the handle returns; a finished run's resume changes nothing.
#[test]
fn cancel_after_k_points_then_resume_completes_the_run() {
    let s = spec();
    let mut whole = null_mut();
    let st_whole = unsafe { rodkit_dna_supercoil_run(&s, &mut whole) };
    assert!(st_whole >= 0, "{}", last_error());
    assert_eq!(stop_of(whole), SupercoilStop::Finished as i32);
    let reference = points_of(whole);
    // Point 20 (the stop below) must lie on the buckled branch, and the
    // run must go on past it.
    assert!(reference.len() > 25 && reference[20].branch == 1, "{} points", reference.len());

    let mut seen = Seen { told: vec![], stop_at: 20, answer: 1 };
    let ud = &mut seen as *mut Seen as *mut c_void;
    let mut run = null_mut();
    let st = unsafe { rodkit_dna_supercoil_run_with(&s, Some(watch), ud, &mut run) };
    assert_eq!(st, Status::InfoCancelled.code(), "{}", last_error());
    assert_eq!(last_error(), "", "a cancelled run is a success");
    assert!(!run.is_null());
    assert_eq!(stop_of(run), SupercoilStop::Cancelled as i32);
    let so_far = points_of(run);
    assert_eq!((so_far.len(), seen.told.len()), (20, 20));
    assert!(same(&so_far, &reference[..20]), "the path so far is the uninterrupted run's first 20 points");

    let st = unsafe { rodkit_supercoil_resume(run, Some(watch), ud) };
    assert_eq!(st, st_whole, "{}", last_error());
    assert_eq!(stop_of(run), SupercoilStop::Finished as i32);
    let all = points_of(run);
    assert!(same(&all, &reference), "the resumed run's path differs from the uninterrupted one");
    assert_eq!(seen.told.len(), all.len());
    for (i, (t, p)) in seen.told.iter().zip(&all).enumerate() {
        assert_eq!(t.points, i as i64 + 1, "told in order, once");
        assert_eq!((t.branch, t.turns, t.extension, t.torque), (p.branch, p.turns, p.extension, p.torque), "point {i}");
        assert!(t.residual == p.residual && t.tip_rotation.is_finite());
    }
    let mut info = SupercoilInfo::default();
    assert_eq!(unsafe { rodkit_supercoil_summary(run, &mut info) }, 0);
    let mut info_whole = SupercoilInfo::default();
    assert_eq!(unsafe { rodkit_supercoil_summary(whole, &mut info_whole) }, 0);
    assert_eq!(
        (info.points, info.straight_points, info.steps),
        (info_whole.points, info_whole.straight_points, info_whole.steps)
    );
    assert_eq!((info.buckling_turns, info.buckling_torque), (info_whole.buckling_turns, info_whole.buckling_torque));

    // A finished run: its status again, the callback not called.
    let told = seen.told.len();
    assert_eq!(unsafe { rodkit_supercoil_resume(run, Some(watch), ud) }, st_whole);
    assert_eq!((seen.told.len(), points_of(run).len()), (told, reference.len()));
    unsafe { rodkit_supercoil_free(run) };
    unsafe { rodkit_supercoil_free(whole) };
}

/// A callback returning an error code (−1) stops the run as any non-zero
/// return does (the rod continuation's rule): INFO_CANCELLED with the path
/// so far, here on the straight branch (after 3 points), an empty error
/// channel; resumed without a callback it completes the run (straight
/// phase: to the Newton tolerance, tests/supercoil_resume.rs; here 1e-8).
/// A callback making a failing rodkit call at every point leaves the error
/// channel empty after the successful run.
#[test]
fn an_error_returning_or_failing_callback_follows_the_branch_rules() {
    let s = spec();
    let mut seen = Seen { told: vec![], stop_at: 3, answer: -1 };
    let ud = &mut seen as *mut Seen as *mut c_void;
    let mut run = null_mut();
    let st = unsafe { rodkit_dna_supercoil_run_with(&s, Some(failing_call), ud, &mut run) };
    assert_eq!(st, Status::InfoCancelled.code());
    assert_eq!(last_error(), "", "the callback's failing call must not leave its message");
    assert_eq!((points_of(run).len(), seen.told.len()), (3, 3));
    assert!(seen.told.iter().all(|t| t.branch == 0));
    let st = unsafe { rodkit_supercoil_resume(run, None, null_mut()) };
    assert!(st >= 0 && st != Status::InfoCancelled.code(), "{st}: {}", last_error());
    let mut whole = null_mut();
    assert!(unsafe { rodkit_dna_supercoil_run(&s, &mut whole) } >= 0);
    let (a, b) = (points_of(run), points_of(whole));
    assert_eq!(a.len(), b.len());
    for (p, q) in a.iter().zip(&b) {
        for (x, y) in [(p.turns, q.turns), (p.extension, q.extension), (p.torque, q.torque), (p.writhe, q.writhe)] {
            assert!((x - y).abs() <= 1e-8 * x.abs().max(1.0), "{x} vs {y}");
        }
    }
    unsafe { rodkit_supercoil_free(run) };
    unsafe { rodkit_supercoil_free(whole) };
}

/// NULL arguments of the new entry points: ERR_NULL_POINTER naming them.
#[test]
fn new_entry_points_refuse_null() {
    let s = spec();
    let null_status = Status::ErrNullPointer.code();
    assert_eq!(unsafe { rodkit_supercoil_resume(null_mut(), None, null_mut()) }, null_status);
    assert!(last_error().contains("run"), "{}", last_error());
    assert_eq!(unsafe { rodkit_supercoil_stop(null(), &mut 0) }, null_status);
    assert_eq!(unsafe { rodkit_dna_supercoil_run_with(null(), None, null_mut(), &mut null_mut()) }, null_status);
    assert!(last_error().contains("spec"), "{}", last_error());
    assert_eq!(unsafe { rodkit_dna_supercoil_run_with(&s, None, null_mut(), null_mut()) }, null_status);
    assert!(last_error().contains("out"), "{}", last_error());
}

/// RodkitBranchProgress's appended fields under the rod continuation (the
/// callback type it shares with the supercoiling run): branch −1 and NaN
/// turns, extension and torque; the original fields as before (points
/// 1, 2, …, the record's Λ).
#[test]
fn rod_continuation_fills_the_appended_fields_as_documented() {
    use rodkit::capi::branch::{rodkit_branch_free, rodkit_rod_continue};
    use rodkit::capi::continuation::{rodkit_continuation_options_default, ContinuationOptions};
    use rodkit::capi::rod::{rodkit_rod_free, rodkit_rod_new};
    use rodkit::capi::rod_spec::{rodkit_rod_spec_default, LoadFrame, RodSpec};
    let mut rs = std::mem::MaybeUninit::<RodSpec>::uninit();
    assert_eq!(unsafe { rodkit_rod_spec_default(rs.as_mut_ptr()) }, 0);
    let mut rs = unsafe { rs.assume_init() };
    rs.length = 1.0;
    (rs.bending1, rs.bending2, rs.twist, rs.shear1, rs.shear2, rs.stretch) = (1.0, 1.0, 1.0, 1e4, 1e4, 1e4);
    (rs.tip_moment_frame, rs.tip_moment_x, rs.elements) = (LoadFrame::Follower as i32, 1.0, 2);
    let mut rod = null_mut();
    assert_eq!(unsafe { rodkit_rod_new(&rs, &mut rod) }, 0, "{}", last_error());
    let mut o = std::mem::MaybeUninit::<ContinuationOptions>::uninit();
    assert_eq!(unsafe { rodkit_continuation_options_default(o.as_mut_ptr()) }, 0);
    let mut o = unsafe { o.assume_init() };
    o.target_lambda = 0.5;
    let mut seen = Seen { told: vec![], stop_at: 0, answer: 0 };
    let mut b = null_mut();
    let ud = &mut seen as *mut Seen as *mut c_void;
    assert_eq!(unsafe { rodkit_rod_continue(rod, null(), 0, 0.0, &o, Some(watch), ud, &mut b) }, 0);
    assert!(seen.told.len() >= 2);
    for (i, t) in seen.told.iter().enumerate() {
        assert_eq!((t.points, t.branch), (i as i64 + 1, -1));
        assert!(t.turns.is_nan() && t.extension.is_nan() && t.torque.is_nan() && t.lambda.is_finite());
    }
    assert_eq!(seen.told.last().unwrap().lambda, 0.5);
    unsafe { rodkit_branch_free(b) };
    unsafe { rodkit_rod_free(rod) };
}

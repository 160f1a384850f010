//! Progress and resume of the supercoiling run (issue 18, deliverable 6):
//! a run stopped by its progress callback and resumed gives the path of
//! the uninterrupted run; the callback is told every point once, in order,
//! with the values the run keeps. Reference: the uninterrupted
//! `run_scene` of the same scene (an independent computation of the same
//! path: one engine run per branch, no stop).
//!
//! Scene: 300 bp (102 nm) at 1 pN and 0.1 M, 30 elements, at most 25 steps
//! per branch, to 2.5 turns: 8 straight points (the straight branch stops
//! at its first buckling point), the buckling point at 1.316 turns, 26
//! buckled points with ~15 pair lists (the list is rebuilt every ~2 steps,
//! so a stop lands between rebuilds); ~2 s a run.

use rodkit::charged::dna::{self, DnaScene, PathPoint, ResumeAt, RunStop, SupercoilRun, SupercoilSettings};
use std::sync::OnceLock;

fn scene() -> (DnaScene, SupercoilSettings) {
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    (scene, SupercoilSettings { elements: 30, max_steps: 25, max_turns: 2.5, ..Default::default() })
}

fn uninterrupted() -> &'static SupercoilRun {
    static RUN: OnceLock<SupercoilRun> = OnceLock::new();
    RUN.get_or_init(|| {
        let (scene, settings) = scene();
        dna::run_scene(&scene, &settings).unwrap()
    })
}

/// Run stopped after point `k` (0-based), then resumed to the end; every
/// told point checked against the run's own (same index, same numbers) and
/// counted. Returns the run, the resume point of the stop, and the points
/// told.
fn stopped_and_resumed(k: usize) -> (SupercoilRun, ResumeAt, Vec<PathPoint>) {
    let (scene, settings) = scene();
    let mut told: Vec<(usize, usize, f64, f64, f64)> = vec![];
    let mut record = |p: &dna::PointProgress| told.push((p.index, p.branch, p.turns, p.extension, p.torque));
    let mut run = dna::run_scene_with(&scene, &settings, |p| {
        record(p);
        p.index != k
    })
    .unwrap();
    assert_eq!(run.stop, RunStop::Cancelled, "stopped after point {k}");
    assert_eq!(run.points.len(), k + 1, "the path so far ends at the stop");
    let at = run.resume_at.clone().expect("a resume point");
    let before = run.points.clone();
    dna::resume(&mut run, |p| {
        record(p);
        true
    })
    .unwrap();
    assert_eq!((run.stop, run.resume_at.is_none()), (RunStop::Finished, true));
    // The points before the stop are kept as they were.
    assert!(run.points[..=k] == before[..], "the resume changed the points before the stop");
    // Every point told once, in order, with the run's numbers (the same
    // state, the same formulas: equal, not close).
    assert_eq!(told.len(), run.points.len(), "told {} points of {}", told.len(), run.points.len());
    for (i, (t, p)) in told.iter().zip(&run.points).enumerate() {
        let o = p.observables;
        assert_eq!(*t, (i, p.branch, o.turns, o.extension, o.torque), "point {i} told");
    }
    let points = run.points.clone();
    (run, at, points)
}

/// The largest difference between two paths' turns, extension, torque,
/// twist and writhe, relative to max(|value|, 1) (turns, nm, pN nm).
fn worst(a: &[PathPoint], b: &[PathPoint]) -> f64 {
    assert_eq!(a.len(), b.len(), "number of points");
    let mut w: f64 = 0.0;
    for (p, q) in a.iter().zip(b) {
        assert_eq!(p.branch, q.branch);
        let (o, r) = (p.observables, q.observables);
        for (x, y) in [
            (o.turns, r.turns),
            (o.extension, r.extension),
            (o.torque, r.torque),
            (o.twist, r.twist),
            (o.writhe, r.writhe),
        ] {
            w = w.max((x - y).abs() / x.abs().max(1.0));
        }
    }
    w
}

/// Stopped on the buckled branch (point 17, between pair-list rebuilds)
/// and resumed: the uninterrupted path bitwise. The buckled branch resumes
/// from its stored point, tangent and step, on the same pair list (built
/// about the same state, measured from the same reference): the resumed
/// engine does the uninterrupted one's arithmetic.
#[test]
fn stopped_on_the_buckled_branch_resumes_bitwise() {
    let r = uninterrupted();
    let straight = r.points.iter().filter(|p| p.branch == 0).count();
    assert!(straight < 17 && r.points.len() > 30, "the scene's path: {straight} straight of {}", r.points.len());
    let (run, at, points) = stopped_and_resumed(17);
    assert!(matches!(at, ResumeAt::Buckled { .. }), "{at:?}");
    assert!(points == r.points, "not bitwise: worst {:.1e}", worst(&points, &r.points));
    assert_eq!(run.buckling, r.buckling);
    let (b, rb) = (run.buckled.as_ref().unwrap(), r.buckled.as_ref().unwrap());
    // The same steps; one list more: the resume builds the stop's list again.
    assert_eq!((b.stop, b.counts.steps, b.pair_lists), (rb.stop, rb.counts.steps, rb.pair_lists + 1));
    assert!(run.states == r.states);
}

/// Stopped at the straight branch's last point (a phase boundary: the
/// buckled branch starts on resume): bitwise.
#[test]
fn stopped_at_the_straight_branchs_end_resumes_bitwise() {
    let r = uninterrupted();
    let last_straight = r.points.iter().filter(|p| p.branch == 0).count() - 1;
    let (_, at, points) = stopped_and_resumed(last_straight);
    assert_eq!(at, ResumeAt::Buckling);
    assert!(points == r.points, "worst {:.1e}", worst(&points, &r.points));
}

/// Stopped inside the straight phase (point 4, inside the first chunk of
/// large steps): the same path within 1e-8 relative (measured 4.4e-10; at
/// the other straight points 0 to 9e-10). Not bitwise: the straight branch
/// resumes by the engine's resume, which factorises at the stop point
/// bordered by that point's own tangent (the uninterrupted engine's was
/// bordered by the previous one) and recomputes the tangent there; its last
/// bits differ, so the next predictor does, and Newton stops at another
/// iterate within the residual tolerance (1e-8, scaled): the later points
/// are other iterates of the same equilibria, as close as Newton's
/// convergence makes them (bounded by the tolerance). The buckling point
/// (located to 1e-7 in arc length) agrees to 1e-12.
#[test]
fn stopped_on_the_straight_branch_resumes_to_the_newton_tolerance() {
    let r = uninterrupted();
    let (run, at, points) = stopped_and_resumed(4);
    assert!(matches!(at, ResumeAt::Straight { chunk: 0, steps: 4, .. }), "{at:?}");
    let w = worst(&points, &r.points);
    println!("stopped at straight point 4: worst relative difference {w:.2e}");
    assert!(w < 1e-8, "worst {w:.2e}");
    let ((p, m), (rp, rm)) = (run.buckling.unwrap(), r.buckling.unwrap());
    assert!((p - rp).abs() < 1e-12 * rp && (m - rm).abs() < 1e-12 * rm, "{:?} vs {:?}", run.buckling, r.buckling);
}

/// Stopped twice: in the second chunk of the straight phase (point 6),
/// then on the buckled branch (point 25) during the resume; resumed again.
#[test]
fn stopped_twice_resumes_to_the_same_end() {
    let (scene, settings) = scene();
    let r = uninterrupted();
    let mut told = 0usize;
    let mut run = dna::run_scene_with(&scene, &settings, |_| {
        told += 1;
        told != 7
    })
    .unwrap();
    assert!(matches!(run.resume_at, Some(ResumeAt::Straight { chunk: 1.., .. })), "{:?}", run.resume_at);
    dna::resume(&mut run, |_| {
        told += 1;
        told != 26
    })
    .unwrap();
    assert_eq!((run.stop, run.points.len()), (RunStop::Cancelled, 26));
    assert!(matches!(run.resume_at, Some(ResumeAt::Buckled { .. })));
    dna::resume(&mut run, |_| {
        told += 1;
        true
    })
    .unwrap();
    assert_eq!((told, run.points.len(), run.stop), (r.points.len(), r.points.len(), RunStop::Finished));
    let w = worst(&run.points, &r.points);
    assert!(w < 1e-8, "worst {w:.2e}");
    // A finished run is left as it is.
    let before = run.points.len();
    dna::resume(&mut run, |_| panic!("a finished run told a point")).unwrap();
    assert_eq!(run.points.len(), before);
}

/// A callback that panics: the panic reaches the caller of the Rust API
/// (Rust semantics; the C entry points' guard turns it into
/// ERR_INTERNAL, tests/capi_supercoil_resume.rs).
#[test]
fn a_panicking_callback_unwinds_to_the_caller() {
    let (scene, settings) = scene();
    let err = std::panic::catch_unwind(|| {
        dna::run_scene_with(&scene, &settings, |p| {
            assert!(p.index < 2, "deliberate panic at point {}", p.index);
            true
        })
    })
    .unwrap_err();
    let msg = err.downcast_ref::<String>().cloned().unwrap_or_default();
    assert!(msg.contains("deliberate panic at point 2"), "{msg}");
}

/// Under a torque clamp (EndControl::Torque: the end torque is the
/// parameter, the turns read from each state and followed by continuity):
/// stopped on the buckled branch and resumed, the uninterrupted path
/// bitwise, the turns continuing across the stop (300 bp, 30 elements, 20
/// steps).
#[test]
fn torque_clamp_stopped_on_the_buckled_branch_resumes_bitwise() {
    let (scene, settings) = scene();
    let settings = SupercoilSettings { control: dna::EndControl::Torque, max_steps: 20, ..settings };
    let r = dna::run_scene(&scene, &settings).unwrap();
    let straight = r.points.iter().filter(|p| p.branch == 0).count();
    let k = straight + 6;
    assert!(r.points.len() > k + 3, "{} points, {straight} straight", r.points.len());
    let mut run = dna::run_scene_with(&scene, &settings, |p| p.index != k).unwrap();
    assert!(matches!(run.resume_at, Some(ResumeAt::Buckled { .. })), "{:?}", run.resume_at);
    let mut told = vec![];
    dna::resume(&mut run, |p| {
        told.push((p.index, p.phi));
        true
    })
    .unwrap();
    assert!(run.points == r.points, "not bitwise: worst {:.1e}", worst(&run.points, &r.points));
    let expected: Vec<(usize, f64)> = r.points.iter().enumerate().skip(k + 1).map(|(i, p)| (i, p.phi)).collect();
    assert_eq!(told, expected, "the resumed points told with the run's turns");
}

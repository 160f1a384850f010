//! Records' determinant signs on a second thread (issue 18:
//! `Options::overlap_records`, taken by the supercoiling run with 2
//! threads) against the same run on one thread (the reference: each
//! record's signs from B's simplicial LU at its point, before the next
//! step). The second thread factorises the same matrix the same way, so
//! the signs and pivots must be equal, not close; the points differ only
//! by the tangents' rounding (taken from the block elimination instead of
//! the simplicial LU), so they agree to the corrector's convergence, as in
//! tests/supercoil_lu.rs: within 1e-7 of their scales.
//!
//! Scene: 300 bp (102 nm) at 1 pN and 0.1 M, 30 elements, at most 25
//! steps per branch, to 2.5 turns (buckling at 1.316 turns, then into the
//! plectoneme), the supernodal kind forced (at 30 elements the structure
//! alone would keep B's simplicial LU and there would be nothing to
//! overlap); ~2 s a run.

use rodkit::charged::dna::{self, DnaScene, RunStop, SupercoilRun, SupercoilSettings};
use rodkit::linalg::LuKind;

#[path = "support/paths.rs"]
mod paths;

fn settings(threads: usize) -> (DnaScene, SupercoilSettings) {
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let settings = SupercoilSettings {
        elements: 30,
        max_steps: 25,
        max_turns: 2.5,
        threads,
        lu_kind: Some(LuKind::Supernodal),
        ..Default::default()
    };
    (scene, settings)
}

fn run(threads: usize) -> SupercoilRun {
    let (scene, settings) = settings(threads);
    dna::run_scene(&scene, &settings).unwrap()
}

#[test]
fn signs_taken_on_a_second_thread_equal_one_threads() {
    let (one, two) = (run(1), run(2));
    let (b1, b2) = (one.buckled.as_ref().unwrap(), two.buckled.as_ref().unwrap());
    assert_eq!(b1.counts.times.overlapped, std::time::Duration::ZERO, "one thread overlaps nothing");
    assert!(b2.counts.times.overlapped > std::time::Duration::ZERO, "no record's signs on the second thread");
    assert!(one.points.len() > 30, "{} points", one.points.len());
    assert_eq!((b1.stop, b1.records.len()), (b2.stop, b2.records.len()));
    paths::assert_same_points(&one, &two, 102.0, 1e-7);
    let mut flips = 0;
    for (k, (r, s)) in b1.records.iter().zip(&b2.records).enumerate() {
        assert_eq!(
            (r.det_sign, r.bordered_det_sign, r.negative_pivots),
            (s.det_sign, s.bordered_det_sign, s.negative_pivots),
            "buckled record {k}: signs and pivots"
        );
        assert!(r.bordered_det_sign != 0.0 || k == 0, "record {k} without a sign");
        flips += usize::from(k > 0 && r.det_sign != b1.records[k - 1].det_sign);
    }
    // The path passes the fold of the buckled branch (sign det R_x flips
    // there): the comparison covers a change, not only a constant sign.
    assert!(flips >= 1, "no det R_x flip on the buckled branch");
}

/// Stopped by the callback on the buckled branch while a record waits for
/// its signs, then resumed: every point told once, in order, the path of
/// the uninterrupted run with 2 threads bitwise (the stop drops the step
/// corrected meanwhile; the resume refactorises the stop point as the
/// uninterrupted run did).
#[test]
fn stopped_with_a_record_waiting_resumes_bitwise() {
    let reference = run(2);
    let (scene, settings) = settings(2);
    let k = 17;
    assert!(reference.points[k].branch == 1, "point {k} is not on the buckled branch");
    let mut told = vec![];
    let mut stopped = dna::run_scene_with(&scene, &settings, |p| {
        told.push((p.index, p.turns));
        p.index != k
    })
    .unwrap();
    assert_eq!((stopped.stop, stopped.points.len()), (RunStop::Cancelled, k + 1));
    dna::resume(&mut stopped, |p| {
        told.push((p.index, p.turns));
        true
    })
    .unwrap();
    assert_eq!(stopped.stop, RunStop::Finished);
    assert_eq!(told.len(), reference.points.len(), "told {} of {} points", told.len(), reference.points.len());
    for (i, ((index, turns), p)) in told.iter().zip(&reference.points).enumerate() {
        assert_eq!((*index, *turns), (i, p.observables.turns), "point {i} told");
    }
    assert!(stopped.points == reference.points, "the resumed path is not the uninterrupted one");
}

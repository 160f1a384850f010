//! Records' determinant signs on a second thread (issue 18:
//! `Options::overlap_thread`, taken by the supercoiling run with 2
//! threads) against the same run on one thread, which takes them on the
//! calling thread from the same factorisation (`Options::overlap_records`,
//! issue 21): the same records, points and stops, bitwise (c-api.md:
//! results bitwise identical for any thread count). That the signs so
//! taken are those read off each point's own factorisation is
//! tests/continuation.rs's `signs_on_a_second_thread_give_the_one_thread_run`
//! (the circle through its fold, closed form); here the path passes the
//! buckled branch's fold, where sign det R_x flips.
//!
//! Scene: 300 bp (102 nm) at 1 pN and 0.1 M, 30 elements, at most 25
//! steps per branch, to 2.5 turns (buckling at 1.316 turns, then into the
//! plectoneme), the supernodal kind forced (at 30 elements the structure
//! alone would keep B's simplicial LU and there would be nothing to
//! overlap) and separate signs asked for at any size
//! (`separate_signs_from` 0; by default they start at 3000 unknowns);
//! ~2 s a run. The default, signs off each point's own LU, is checked
//! for the same thread invariance too.

use rodkit::charged::dna::{self, DnaScene, RunStop, SupercoilRun, SupercoilSettings};
use rodkit::linalg::LuKind;

fn settings(threads: usize) -> (DnaScene, SupercoilSettings) {
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let settings = SupercoilSettings {
        elements: 30,
        max_steps: 25,
        max_turns: 2.5,
        threads,
        lu_kind: Some(LuKind::Supernodal),
        separate_signs_from: 0,
        // The records' signs from their own factorisations (what this
        // file tests), not derived from stability counts.
        stability: None,
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
    assert!(b1.counts.times.overlapped > std::time::Duration::ZERO, "one thread took no record's own signs");
    assert!(b2.counts.times.overlapped > std::time::Duration::ZERO, "no record's signs on the second thread");
    assert!(one.points.len() > 30, "{} points", one.points.len());
    assert_eq!((b1.stop, b1.records.len()), (b2.stop, b2.records.len()));
    assert!(one.points == two.points, "2 threads' points differ from 1 thread's");
    assert!(b1.records == b2.records, "2 threads' records differ from 1 thread's");
    assert!(b1.states == b2.states, "2 threads' states differ from 1 thread's");
    let mut flips = 0;
    for (k, r) in b1.records.iter().enumerate() {
        assert!(r.bordered_det_sign != 0.0 || k == 0, "record {k} without a sign");
        flips += usize::from(k > 0 && r.det_sign != b1.records[k - 1].det_sign);
    }
    // The path passes the fold of the buckled branch (sign det R_x flips
    // there): the comparison covers a change, not only a constant sign.
    assert!(flips >= 1, "no det R_x flip on the buckled branch");
}

/// Below `separate_signs_from` (the default 3000; this rod has 30
/// elements) each point's tangent and signs come from its own simplicial
/// LU, no factorisation of their own: 1 and 2 threads give the same
/// points and records, bitwise, and the signs flip at the fold as with
/// separate signs.
#[test]
fn signs_at_the_points_are_the_same_on_two_threads() {
    let (scene, settings) = settings(1);
    let at_points = |threads| {
        let s = SupercoilSettings {
            threads,
            separate_signs_from: SupercoilSettings::default().separate_signs_from,
            ..settings.clone()
        };
        dna::run_scene(&scene, &s).unwrap()
    };
    let (one, two) = (at_points(1), at_points(2));
    assert!(one.rod.unknowns() < SupercoilSettings::default().separate_signs_from);
    let (b1, b2) = (one.buckled.as_ref().unwrap(), two.buckled.as_ref().unwrap());
    assert_eq!(b1.counts.times.overlapped, std::time::Duration::ZERO, "a record took a factorisation of its own");
    assert!(one.points == two.points && b1.records == b2.records, "2 threads differ from 1");
    let flips = b1.records.windows(2).filter(|w| w[0].det_sign != w[1].det_sign).count();
    assert!(flips >= 1, "no det R_x flip on the buckled branch");
    // The same signs as with separate signs, record by record along the
    // two (equal to rounding) paths.
    let separate = run(1);
    let signs = |b: &rodkit::charged::branch::ChargedBranch| b.records.iter().map(|r| r.det_sign).collect::<Vec<_>>();
    let b3 = separate.buckled.as_ref().unwrap();
    assert!(signs(b1).len().min(signs(b3).len()) > 20, "fewer than 20 buckled records");
    assert_eq!(signs(b1)[..20], signs(b3)[..20], "signs at the points vs separate signs");
}

/// A run stopped on one thread and resumed on two (the handle's threads
/// changed in between, as a restarted job may): the uninterrupted run's
/// points, bitwise.
#[test]
fn stopped_on_one_thread_resumes_on_two_bitwise() {
    let reference = run(1);
    let (scene, settings) = settings(1);
    let k = 21;
    assert!(reference.points[k].branch == 1, "point {k} is not on the buckled branch");
    let mut stopped = dna::run_scene_with(&scene, &settings, |p| p.index != k).unwrap();
    assert_eq!((stopped.stop, stopped.points.len()), (RunStop::Cancelled, k + 1));
    (stopped.settings.threads, stopped.charge.threads) = (2, 2);
    dna::resume(&mut stopped, |_| true).unwrap();
    assert_eq!(stopped.stop, RunStop::Finished);
    assert!(stopped.points == reference.points, "resumed on 2 threads: not the 1-thread path");
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

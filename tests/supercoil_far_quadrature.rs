//! The refined far zone on a whole path (`SupercoilSettings::far_points`):
//! the 300 bp plectoneme (1 pN, 0.1 M) on a coarse mesh
//! is closer to a converged reference with the far zone refined than
//! without. Reference: 30 elements of Gauss(3) with 6 far points an
//! element, the same scene — within 7.2e-5 (torque) and 1.1e-4
//! (extension) of 60 × Gauss(4) with 6 far points (measured, 131 s a run,
//! too slow to repeat here; 40 × Gauss(4) is within 3.6e-5 and 7.4e-5 of it).

use rodkit::charged::dna::{self, DnaScene, SupercoilRun, SupercoilSettings};

/// Torque and extension at `turns` on the path's last leg rising in turns
/// (the plectoneme's, past its fold), linear between points.
fn at_turns(run: &SupercoilRun, turns: f64) -> (f64, f64) {
    let p: Vec<(f64, f64, f64)> = run
        .points
        .iter()
        .filter(|p| p.branch == run.points.last().unwrap().branch)
        .map(|p| (p.observables.turns, p.observables.torque, p.observables.extension))
        .collect();
    let mut i = p.len() - 1;
    while i > 0 && p[i - 1].0 < p[i].0 {
        i -= 1;
    }
    let leg = &p[i..];
    for w in leg.windows(2) {
        if w[0].0 <= turns && turns <= w[1].0 {
            let t = (turns - w[0].0) / (w[1].0 - w[0].0);
            return (w[0].1 + t * (w[1].1 - w[0].1), w[0].2 + t * (w[1].2 - w[0].2));
        }
    }
    panic!("{turns} turns not on the last leg {:?}..{:?}", leg.first(), leg.last());
}

fn run(elements: usize, stages: usize, far_points: usize) -> (f64, f64) {
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let settings =
        SupercoilSettings { elements, stages, far_points, max_turns: 2.6, max_steps: 400, ..Default::default() };
    let r = dna::run_scene(&scene, &settings).unwrap();
    assert_eq!(r.stop, dna::RunStop::Finished, "{elements} × Gauss({stages}), {far_points} far points");
    let v = at_turns(&r, 2.5);
    println!("{elements} × Gauss({stages}), far points {far_points}: torque {:.6} pN nm, extension {:.5} nm at 2.5 turns ({} points, {:.1} s)", v.0, v.1, r.points.len(), r.seconds);
    v
}

/// At 2.5 turns on the plectoneme leg, against the test's reference (30 ×
/// Gauss(3), 6 far points an element, itself within 7.2e-5 and 1.1e-4 of
/// 60 × Gauss(4): module docs), 30 elements of Gauss(2) (3.4 nm, stage
/// points 1.7 nm apart) with the stage points are 6.2e-3 off in torque and
/// 1.7e-2 in extension; with 4 far points an element 9.3e-4 and 2.3e-4
/// (measured; against 60 × Gauss(4) they were 8.6e-4 and 3.4e-4, the
/// reference's own error moving them by ≤ 1.1e-4). Asserted: refined
/// within 1.5e-3 and 1e-3 of the reference (so within 1.6e-3 and 1.1e-3
/// of 60 × Gauss(4)), and at least 4× closer than the stage points in both.
#[test]
fn refined_far_zone_brings_a_coarse_plectoneme_closer() {
    let reference = run(30, 3, 6);
    let relative = |v: (f64, f64)| ((v.0 - reference.0).abs() / reference.0, (v.1 - reference.1).abs() / reference.1);
    let stage = relative(run(30, 2, 0));
    let refined = relative(run(30, 2, 4));
    println!(
        "30 × Gauss(2): stage points torque {:.2e}, extension {:.2e}; 4 far points {:.2e}, {:.2e}",
        stage.0, stage.1, refined.0, refined.1
    );
    assert!(refined.0 < 1.5e-3 && refined.1 < 1e-3, "refined {refined:?}");
    assert!(
        4.0 * refined.0 < stage.0 && 4.0 * refined.1 < stage.1,
        "refined {refined:?} against stage points {stage:?}"
    );
}

//! The supercoiling path with the Newton corrections factorised by block
//! elimination on the Jacobian's supernodal LU (issue 18, step 3:
//! `LuKind::Supernodal`, taken by structure in a plectoneme) against the
//! same path with the bordered matrix's own simplicial LU throughout
//! (`LuKind::Simplicial`, the engine's factorisation before: the
//! reference). Both solve the same equations to the same residual
//! tolerance, and the records' determinant signs come from simplicial
//! factorisations either way, so the two paths are the same points up to
//! the corrector's convergence: as many points, their turns, extension,
//! torque and writhe within 1e-7 of their scales, equal determinant signs.
//!
//! Scene: 300 bp (102 nm) at 1 pN and 0.1 M, 30 elements, at most 30
//! steps per branch, to 2.5 turns (buckling at 1.316 turns, the buckled
//! branch into its plectoneme; the supernodal kind is forced here: at 30
//! elements the structure alone would keep the simplicial LU).

use rodkit::charged::dna::{self, DnaScene, SupercoilRun, SupercoilSettings};
use rodkit::linalg::LuKind;

#[path = "support/paths.rs"]
mod paths;

fn run(kind: LuKind) -> SupercoilRun {
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let settings =
        SupercoilSettings { elements: 30, max_steps: 30, max_turns: 2.5, lu_kind: Some(kind), ..Default::default() };
    dna::run_scene(&scene, &settings).unwrap()
}

#[test]
fn block_elimination_gives_the_simplicial_path() {
    let (reference, fast) = (run(LuKind::Simplicial), run(LuKind::Supernodal));
    let blocks = |r: &SupercoilRun| {
        r.straight.counts.block_eliminations + r.buckled.as_ref().map_or(0, |b| b.counts.block_eliminations)
    };
    assert_eq!(blocks(&reference), 0, "the reference factorises B itself");
    let fast_blocks = blocks(&fast);
    assert!(fast_blocks > 50, "block elimination used {fast_blocks} times only");
    assert_eq!(reference.points.len(), fast.points.len(), "different numbers of points");
    assert!(reference.points.len() > 30, "{} points", reference.points.len());
    let (b0, b1) = (reference.buckling.unwrap(), fast.buckling.unwrap());
    // The buckling point is located to 1e-7 in scaled arc length (φ to ~1e-7 rad).
    assert!((b0.0 - b1.0).abs() < 1e-7, "buckling φ {} vs {}", b0.0, b1.0);
    // The buckled branch leaves a double point (the rod's rotational
    // symmetry) along a null direction whose azimuth depends on the
    // factors' rounding: the two buckled paths are the same shapes turned
    // about the axis, so they are compared in what does not see the turn.
    paths::assert_same_points(&reference, &fast, 102.0, 1e-7);
    for (a, b) in
        [(&reference.straight, &fast.straight)].into_iter().chain(reference.buckled.as_ref().zip(fast.buckled.as_ref()))
    {
        for (k, (r, s)) in a.records.iter().zip(&b.records).enumerate() {
            assert_eq!(
                (r.det_sign, r.bordered_det_sign),
                (s.det_sign, s.bordered_det_sign),
                "record {k}: determinant signs"
            );
        }
    }
}

/// The corrector's aim is an iteration count the corrector can reach
/// (1–12, its iteration limit): outside, the run is refused with a status
/// naming it, before any work.
#[test]
fn corrector_aim_out_of_range_is_refused() {
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    use rodkit::status::Status;
    for (aim, status) in [(0.5, Status::ErrOutOfRange), (13.0, Status::ErrOutOfRange), (f64::NAN, Status::ErrNotFinite)]
    {
        let settings = SupercoilSettings { elements: 30, max_steps: 5, corrector_aim: aim, ..Default::default() };
        let err = dna::run_scene(&scene, &settings).unwrap_err();
        assert_eq!(err.status, status, "aim {aim}: {err:?}");
        assert!(err.message.contains("corrector_aim"), "aim {aim}: {}", err.message);
    }
}

/// Long steps (`corrector_aim` 5) on the 300 bp scene: at 1.17 turns a
/// step carries stages well past the Verlet skin, and the point converged
/// on the old pair list no longer re-converges on the list rebuilt there
/// (scaled residual 0.64: the run used to end with ErrNotConverged). The
/// branch takes that step again from the point before, with half the step,
/// and goes on. Reference: every point's residual re-evaluated on a pair
/// list built at its own state (an independent list, `ChargedRod::new`
/// there) is within twice the run's tolerance 1e-8 (the list's different
/// rounding moves a point's residual a little: measured 8.2e-9 at worst;
/// a point that had not converged would be far above), and the path
/// reaches past the fold at 1.107 turns
/// on the buckled branch as the aim-3 run does.
#[test]
fn a_step_past_the_skin_is_taken_again() {
    use rodkit::charged::rod::ChargedRod;
    use rodkit::continuation::Problem;
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let settings =
        SupercoilSettings { elements: 30, max_steps: 25, max_turns: 2.5, corrector_aim: 5.0, ..Default::default() };
    let run = dna::run_scene(&scene, &settings).unwrap();
    let b = run.buckled.as_ref().unwrap();
    assert_eq!(b.records.len(), 26, "the buckled branch's 25 steps");
    assert!(b.counts.rejected_steps > 0);
    let mut worst = 0.0f64;
    for (k, (rec, x)) in b.records.iter().zip(&b.states).enumerate() {
        let mut problem = ChargedRod::new(&run.rod, &run.charge, b.phase, x).unwrap();
        let mut r = vec![0.0; x.len()];
        problem.residual(x, rec.lambda, &mut r);
        let res = rodkit::nonlinear::scaled_max_norm(&r, &problem.equation_scales());
        worst = worst.max(res);
        assert!(res <= 2e-8, "buckled point {k} (φ {:.4}): residual {res:e} on its own list", rec.lambda);
    }
    println!("worst residual on rebuilt lists {worst:e}");
    let ns = run.straight.records.len();
    let reached = run.points.iter().skip(ns).map(|p| p.observables.turns).fold(f64::INFINITY, f64::min);
    assert!(reached < 1.11, "the buckled branch reached {reached} turns, not the fold at 1.107");
}

//! The buckled branch by the ANM (issue 18: `Engine::Anm`, the charged
//! rod's Taylor series) and the pair lists rebuilt by coverage
//! (`ListRule::Coverage`, src/charged/rod/coverage.rs), against
//! independent references.
//!
//! Scene: 300 bp (102 nm) at 1 pN and 0.1 M, 30 elements, to 2.5 turns:
//! buckling at 1.316 turns, back along the unstable leg to its fold at
//! 1.11 turns, then forward into the plectoneme (2–7 s a run).

use rodkit::charged::dna::{self, DnaScene, Engine, SupercoilRun, SupercoilSettings};
use rodkit::charged::rod::{ChargedRod, ListRule};
use rodkit::continuation::Problem;
use rodkit::nonlinear::scaled_max_norm;

fn scene() -> DnaScene {
    DnaScene { base_pairs: 300, ..Default::default() }
}

fn settings(engine: Engine, aim: f64) -> SupercoilSettings {
    SupercoilSettings {
        elements: 30,
        max_steps: 1500,
        max_turns: 2.5,
        engine,
        corrector_aim: aim,
        ..Default::default()
    }
}

/// The scaled residual of every buckled point on a pair list built at the
/// point itself (every pair within r_off + skin there): the full model's.
fn worst_full_residual(run: &SupercoilRun) -> f64 {
    let b = run.buckled.as_ref().expect("a buckled branch");
    let mut charge = run.charge.clone();
    if let Some(s) = run.hard_core_switch {
        charge.hard_core = Some(s.stiffness);
    }
    let mut worst = 0.0f64;
    for (x, rec) in b.states.iter().zip(&b.records) {
        let mut p = ChargedRod::new(&run.rod, &charge, b.phase, x).unwrap();
        let mut r = vec![0.0; x.len()];
        p.residual(x, rec.lambda, &mut r);
        worst = worst.max(scaled_max_norm(&r, &p.equation_scales()));
    }
    worst
}

/// Reference: the residual tolerance itself. A point converged on a list
/// that missed an interacting pair would carry that pair's force as a
/// residual on the list built at the point. Verlet's rule guarantees this
/// by a bound; the coverage rule must too, with ~5× fewer lists.
#[test]
fn every_point_is_an_equilibrium_of_the_full_model() {
    for rule in [ListRule::Coverage, ListRule::Displacement] {
        let run =
            dna::run_scene(&scene(), &SupercoilSettings { list_rule: rule, ..settings(Engine::Hermite, 3.0) }).unwrap();
        let b = run.buckled.as_ref().unwrap();
        let worst = worst_full_residual(&run);
        println!(
            "{rule:?}: {} buckled points on {} pair lists; worst full-model residual {worst:e}",
            b.records.len(),
            b.pair_lists
        );
        // Re-summed on another list: rounding apart, the tolerance.
        assert!(worst <= 1.001 * run.settings.residual_tol, "{rule:?}: worst {worst:e}");
        assert!(b.records.len() > 40);
    }
}

/// The distance of each of `new`'s buckled points from `reference`'s
/// polyline through its buckled points, in (turns, M/M_b, z/L).
fn deviation(new: &SupercoilRun, reference: &SupercoilRun) -> (f64, f64) {
    let mb = reference.buckling.unwrap().1.abs();
    let l = reference.scene.length();
    let key = |p: &dna::PathPoint| [p.observables.turns, p.observables.torque / mb, p.observables.extension / l];
    let (mut wm, mut wz) = (0.0f64, 0.0f64);
    for p in new.points.iter().filter(|p| p.branch == 1) {
        let q = key(p);
        let mut best = (f64::INFINITY, 0.0, 0.0);
        for w in reference.points.windows(2).filter(|w| w[0].branch == 1 && w[1].branch == 1) {
            let (a, b) = (key(&w[0]), key(&w[1]));
            let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let len2 = ab.iter().map(|v| v * v).sum::<f64>();
            let t = if len2 > 0.0 {
                ((0..3).map(|i| (q[i] - a[i]) * ab[i]).sum::<f64>() / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let c = [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]];
            let d2 = (0..3).map(|i| (q[i] - c[i]).powi(2)).sum::<f64>();
            if d2 < best.0 {
                best = (d2, (q[1] - c[1]).abs(), (q[2] - c[2]).abs());
            }
        }
        wm = wm.max(best.1);
        wz = wz.max(best.2);
    }
    (wm, wz)
}

/// Reference: the Hermite engine with steps sized for two Newton
/// iterations (corrector aim 2: dense points, so its polyline's chord error
/// stays below the tolerance). Each ANM point must lie on that path within
/// 1e-3 of M_b and of L (the "same branch" criterion), be an
/// equilibrium of the full model, and the run reach the same end.
#[test]
fn the_anm_follows_the_newton_branch() {
    let reference = dna::run_scene(&scene(), &settings(Engine::Hermite, 2.0)).unwrap();
    let anm_settings = settings(Engine::Anm, 3.0);
    let anm = dna::run_scene(&scene(), &anm_settings).unwrap();
    let (m, z) = deviation(&anm, &reference);
    let (steps_ref, steps_anm) = (reference.points.len(), anm.points.len());
    let worst = worst_full_residual(&anm);
    println!("reference {steps_ref} points, ANM {steps_anm}; deviation torque {m:e} of M_b, extension {z:e} of L; worst residual {worst:e}");
    assert_eq!(anm.buckling, reference.buckling, "the straight branch is Newton's in both");
    assert!(m < 1e-3 && z < 1e-3, "torque {m:e}, extension {z:e}");
    assert!(worst <= 1.001 * anm.settings.residual_tol, "worst {worst:e}");
    let (ta, tr) = (anm.points.last().unwrap().observables.turns, reference.points.last().unwrap().observables.turns);
    assert!(ta > 2.4 && tr > 2.4, "ends {ta} {tr}");
}

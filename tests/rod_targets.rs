//! Branches that stop exactly at a given end rotation φ
//! (rod::target::until_rotation, issue 19): under rotation control Λ =
//! sin(φ/2) takes every value again each turn, so no target Λ can say
//! "stop at φ = 25".
//!
//! References: the straight twisted rod (K_b = C = L = 1, no tension) is
//! exact in closed form — at end rotation φ its twisting moment is
//! M = Cφ/L and its end frame turned by φ about e3 (Λ = sin(φ/2) under
//! rotation control, Λ = M under end-moment control); its bifurcations are
//! Greenhill's roots θ_k (tan(θ/2) = θ/2).

use rodkit::continuation::{Options, Record, Stop};
use rodkit::rod::branch::{Method, Plain, RodBranch};
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::target::until_rotation;
use rodkit::rod::{Load, Loads, RodLaw};

fn greenhill(supports: Supports) -> Rod {
    Rod::new(RodLaw::kirchhoff(1.0, 1.0, 1.0).unwrap(), 1.0, Loads::default(), supports, Scheme::Gauss(4), 16).unwrap()
}

fn options(target_lambda: Option<f64>) -> Options {
    Options {
        target_lambda,
        residual_tol: 1e-11,
        initial_step: 0.05,
        max_step: 1.0,
        max_steps: 2000,
        detect_bifurcations: true,
        bifurcation_tol: 1e-9,
        ..Default::default()
    }
}

/// The straight branch from φ = 0 towards `increasing`, ended at `target`.
fn straight_to(rod: &Rod, target: f64, method: Method, told: &mut Vec<f64>) -> RodBranch {
    let opts = options(None);
    let plain = Plain { rod, method };
    let mut tell = |r: &Record| {
        told.push(r.lambda);
        true
    };
    until_rotation(&plain, target, None, &mut tell, |cb| {
        rod.continue_branch(None, 0.0, target > 0.0, &opts, method, cb)
    })
    .unwrap()
}

/// The last record at φ = target (to the corrector's residual), the
/// moment there Cφ/L, the branch's φ monotone up to it, no bifurcation
/// past it; the caller told every record, the last one included.
fn assert_ends_at(rod: &Rod, b: &RodBranch, target: f64, told: &[f64], name: &str) {
    assert_eq!(b.stop, Stop::Target, "{name}");
    let (phis, _) = b.end_rotations(rod, None);
    let last = *phis.last().unwrap();
    assert!((last - target).abs() < 1e-10, "{name}: ends at φ {last}");
    let (_, m) = rod.spatial_force_moment(b.states.last().unwrap(), 0);
    assert!((m[2] - target).abs() < 1e-8 * target.abs(), "{name}: moment {} against Cφ/L = {target}", m[2]);
    assert!(phis.windows(2).all(|w| (w[1] - w[0]) * target > 0.0), "{name}: φ {phis:?}");
    for i in 0..b.bifurcations.len() {
        let p = b.rotation_at_bifurcation(rod, i, &phis).unwrap();
        assert!(p.abs() < target.abs(), "{name}: a point at φ {p} past the target");
    }
    assert_eq!(told.len(), b.records.len(), "{name}: records told");
    assert_eq!(*told.last().unwrap(), b.records.last().unwrap().lambda, "{name}");
    // The resume point is the last record.
    assert_eq!(b.resume.x, *b.states.last().unwrap(), "{name}");
}

/// Rotation control, both engines, to φ = 25 (four turns, past Λ's folds
/// at π, 3π, …, 7π) and to φ = −7: exact, with Greenhill's roots 1–3
/// located on the way (|θ_k − φ_k| ≤ 4e-5 θ_k on 16 elements) and the 4th
/// (28.1) not reached.
#[test]
fn rotation_control_stops_at_the_end_rotation_asked() {
    let roots = [8.9868189, 15.4505037, 21.8082433];
    let rod = greenhill(Supports::Twisted { tension: 0.0 });
    for (name, method) in [("Newton", Method::Newton), ("ANM", Method::Anm(Default::default()))] {
        let mut told = vec![];
        let b = straight_to(&rod, 25.0, method, &mut told);
        assert_ends_at(&rod, &b, 25.0, &told, name);
        let (phis, _) = b.end_rotations(&rod, None);
        assert_eq!(b.bifurcations.len(), 3, "{name}");
        for (i, theta) in roots.iter().enumerate() {
            let p = b.rotation_at_bifurcation(&rod, i, &phis).unwrap();
            assert!((p - theta).abs() < 4e-5 * theta, "{name}: root {p} against {theta}");
        }
        // Λ = sin(φ/2) at the end.
        assert!((b.records.last().unwrap().lambda - 12.5f64.sin()).abs() < 1e-12, "{name}");
        let mut told = vec![];
        let b = straight_to(&rod, -7.0, method, &mut told);
        assert_ends_at(&rod, &b, -7.0, &told, &format!("{name}, φ −7"));
    }
}

/// End-moment control (a torque clamp: φ an output, Λ = M): to φ = 12,
/// where M = 12 exactly.
#[test]
fn a_torque_clamp_stops_at_the_end_rotation_asked() {
    let rod = greenhill(Supports::Torqued { tension: 0.0 });
    let mut told = vec![];
    let b = straight_to(&rod, 12.0, Method::Anm(Default::default()), &mut told);
    assert_ends_at(&rod, &b, 12.0, &told, "torque clamp");
    assert!((b.records.last().unwrap().lambda - 12.0).abs() < 1e-8);
}

/// A post-buckled branch (switched at Greenhill's first root, rotation
/// control, C = 4 so that the root is at φ = 2.2467 and Λ folds at π
/// after it) ended at φ = 3.5, counted on from the point it leaves; a
/// branch that ends before the target (its step limit) is returned as it
/// ended; a caller's stop wins; a cantilever is refused.
#[test]
fn switched_branches_count_on_and_other_stops_win() {
    let law = RodLaw::kirchhoff(1.0, 1.0, 4.0).unwrap();
    let rod = Rod::new(law, 1.0, Loads::default(), Supports::Twisted { tension: 0.0 }, Scheme::Gauss(4), 16).unwrap();
    let straight = rod.continue_branch(None, 0.0, true, &options(Some(0.99)), Method::Newton, |_| true).unwrap();
    let (phis, _) = straight.end_rotations(&rod, None);
    let at = straight.rotation_at_bifurcation(&rod, 0, &phis).unwrap();
    assert!((at - 2.2467).abs() < 1e-3, "root at {at}");
    let post = Options { residual_tol: 1e-11, max_step: 0.3, max_steps: 200, ..Default::default() };
    let method = Method::Anm(Default::default());
    let plain = Plain { rod: &rod, method };
    let b = until_rotation(&plain, 3.5, Some(at), &mut |_| true, |cb| {
        rod.switch_branch(&straight, 0, 0, 0.05, &post, method, cb)
    })
    .unwrap();
    assert_eq!(b.stop, Stop::Target);
    let (phis, _) = b.end_rotations(&rod, Some(at));
    assert!((phis.last().unwrap() - 3.5).abs() < 1e-10, "ends at {:?}", phis.last());
    assert!(phis.iter().any(|&p| p > std::f64::consts::PI), "through Λ's fold: {phis:?}");

    // Ends first by its step limit: as it ended.
    let short = Options { max_steps: 3, ..post.clone() };
    let b = until_rotation(&plain, 30.0, Some(at), &mut |_| true, |cb| {
        rod.switch_branch(&straight, 0, 0, 0.05, &short, method, cb)
    })
    .unwrap();
    assert_eq!(b.stop, Stop::MaxSteps);
    // The caller's stop at its third point.
    let mut seen = 0;
    let b = until_rotation(
        &plain,
        30.0,
        Some(at),
        &mut |_| {
            seen += 1;
            seen < 3
        },
        |cb| rod.switch_branch(&straight, 0, 0, 0.05, &post, method, cb),
    )
    .unwrap();
    assert_eq!((b.stop, b.records.len()), (Stop::Cancelled, 3));

    let cantilever = Rod::new(
        RodLaw::kirchhoff(1.0, 1.0, 1.0).unwrap(),
        1.0,
        Loads { tip_force: Some(Load::dead([1.0, 0.0, 0.0])), ..Default::default() },
        Supports::Cantilever,
        Scheme::Gauss(4),
        4,
    )
    .unwrap();
    let err = until_rotation(&Plain { rod: &cantilever, method }, 1.0, None, &mut |_| true, |_| unreachable!())
        .err()
        .unwrap();
    assert_eq!(err.status, rodkit::Status::ErrOutOfRange);
}

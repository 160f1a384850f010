//! Rod branches to a requested accuracy (issue 19): the library chooses
//! the elements, every record carries an error estimate, and the estimate
//! bounds the true error — checked against the same points re-solved on
//! the branch's own mesh with every element cut into ⌈128/N⌉ (at least
//! 128 elements of Gauss(4), every node of the branch's mesh kept, so a
//! phase condition sits at the same arc length: a converged reference,
//! its own error ~(128/N)⁻⁸ below the branch's, under 1e-13 here).

use rodkit::continuation::Options;
use rodkit::rod::accuracy::{continue_to_tolerance, RecordError, Resolver};
use rodkit::rod::branch::Method;
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};

#[path = "support/elastica.rs"]
mod elastica;

/// Each quantity's true error within its estimate (down to `floor`, the
/// residual's level, below which neither is discretisation error).
fn assert_within(truth: &RecordError, estimate: &RecordError, floor: f64, what: &str) {
    let pairs = [
        ("tip position", truth.tip_position, estimate.tip_position),
        ("tip rotation", truth.tip_rotation, estimate.tip_rotation),
        ("base force", truth.base_force, estimate.base_force),
        ("base moment", truth.base_moment, estimate.base_moment),
    ];
    for (name, t, e) in pairs {
        assert!(t <= e.max(floor), "{what}: {name} true {t:e} > estimate {e:e}");
    }
}

/// A post-buckled branch on `rod`: the straight branch to Λ = `straight_to`
/// with detection (Newton, residual 1e-12, located to 1e-11), left at its
/// first bifurcation along null direction 0 and followed by the ANM with
/// `post` (the phase condition chosen by the switch); with the located
/// critical Λ.
fn post_buckled(rod: &Rod, straight_to: f64, post: &Options) -> rodkit::Result<(rodkit::rod::branch::RodBranch, f64)> {
    let straight_opts = Options {
        target_lambda: Some(straight_to),
        residual_tol: 1e-12,
        initial_step: 0.2,
        max_step: 0.5,
        detect_bifurcations: true,
        bifurcation_tol: 1e-11,
        ..Default::default()
    };
    let straight = rod.continue_branch(None, 0.0, true, &straight_opts, Method::Newton, |_| true)?;
    let critical = straight.bifurcations[0].lambda;
    Ok((rod.switch_branch(&straight, 0, 0, 0.05, post, Method::Anm(Default::default()), |_| true)?, critical))
}

fn cantilever(load: Load) -> Rod {
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let loads = Loads { tip_force: Some(load), ..Default::default() };
    Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 4).unwrap()
}

/// The cantilever (K_b = 1, C = 1/1.3, GA = 1e4, EA = 2.6e4, L = 1) under a
/// tip force α e1, follower or dead, α 0 → 100 (the rod curls round),
/// asked for 1e-4, 1e-6 and 1e-8 with the ANM: at every record the true
/// error of each quantity (tip position and rotation, base force and
/// moment) is ≤ its estimate, and the scaled true error ≤ the tolerance;
/// the element count chosen grows with the tolerance.
#[test]
fn cantilevers_to_alpha_100_meet_the_tolerance_and_their_estimates() {
    for (name, load) in [("follower", Load::follower([1.0, 0.0, 0.0])), ("dead", Load::dead([1.0, 0.0, 0.0]))] {
        let template = cantilever(load);
        let mut chosen = vec![];
        for tol in [1e-4, 1e-6, 1e-8] {
            let opts =
                Options { target_lambda: Some(100.0), residual_tol: 1e-12, max_steps: 2000, ..Default::default() };
            let acc =
                continue_to_tolerance(&template, tol, (0.0, true), &opts, Method::Anm(Default::default())).unwrap();
            let rod = &acc.rod;
            let reference_rod = rod.subdivided(128usize.div_ceil(rod.elements)).unwrap();
            let mut reference = Resolver::new(rod, &reference_rod, None).unwrap();
            let mut worst_true: f64 = 0.0;
            for ((record, x), estimate) in acc.branch.records.iter().zip(&acc.branch.states).zip(&acc.estimates) {
                let estimate = estimate.expect("every record has an estimate");
                let (y, _) = reference.solve(x, record.lambda, 1e-11, None).unwrap();
                let truth = rodkit::rod::accuracy::difference(rod, x, &reference_rod, &y);
                // Down to the residual's level (1e-12 of the scales).
                assert_within(&truth, &estimate, 1e-11, &format!("{name}, tol {tol:e}, Λ {}", record.lambda));
                let scaled = truth.scaled(rod, x);
                worst_true = worst_true.max(scaled);
                assert!(scaled <= tol, "{name}, tol {tol:e}, Λ {}: true error {scaled:e}", record.lambda);
            }
            println!(
                "{name}, tol {tol:e}: elements tried {:?}, worst estimate {:.2e}, worst true error {worst_true:.2e}, {} records",
                acc.tried,
                acc.worst,
                acc.branch.records.len()
            );
            assert!(acc.worst <= tol);
            chosen.push(acc.rod.elements);
        }
        assert!(chosen.windows(2).all(|w| w[0] <= w[1]), "{name}: elements {chosen:?}");
    }
}

/// The estimate is zero only where the coarse mesh is exact: on the
/// straight unloaded rod (Λ = 0) every quantity agrees to rounding.
#[test]
fn an_exact_state_has_a_zero_estimate() {
    let rod = Rod { elements: 8, ..cantilever(Load::dead([1.0, 0.0, 0.0])) };
    let opts = Options { target_lambda: Some(0.5), residual_tol: 1e-12, ..Default::default() };
    let b = rod.continue_branch(None, 0.0, true, &opts, Method::Newton, |_| true).unwrap();
    let est = rodkit::rod::accuracy::estimate_errors(&rod, &b, 1e-12).unwrap();
    let first: RecordError = est[0].unwrap();
    assert!(first.tip_position < 1e-14 && first.base_force < 1e-14, "{first:?}");
    // A bent state is not exact on 4 elements: the estimate is not zero.
    let last = est.last().unwrap().unwrap();
    assert!(last.tip_position > 1e-14, "{last:?}");
}

/// Euler's elastica (inextensible Kirchhoff cantilever, K_b = L = 1, axial
/// dead load Λ): detect and locate the buckling load on the straight branch,
/// switch (phase condition), follow the post-buckled branch to Λ = 14 (tip
/// rotation ~168°) — the whole path refined to 1e-4, 1e-6, 1e-8. Reference:
/// the elliptic-integral solution at each record's load (k from P = P_cr
/// (2K(k)/π)² by bisection; tip axial L(2E/K − 1), lateral 2kL/K, tip
/// rotation 2 asin k, base moment P·2kL/K): every quantity's true error ≤
/// its estimate, the scaled one ≤ the tolerance; the critical load within
/// the tolerance of π²/4.
#[test]
fn euler_post_buckling_meets_the_tolerance_against_elliptic_integrals() {
    use rodkit::rod::accuracy::refine_until;
    let pcr = std::f64::consts::PI.powi(2) / 4.0;
    let law = RodLaw::kirchhoff(1.0, 1.0, 1.0 / 1.3).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() };
    let template = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 4).unwrap();
    let post_opts = Options { target_lambda: Some(14.0), residual_tol: 1e-12, max_steps: 500, ..Default::default() };
    for tol in [1e-4, 1e-6, 1e-8] {
        let mut critical = vec![];
        let acc = refine_until(&template, tol, 1e-12, |rod| {
            let (branch, p_c) = post_buckled(rod, 3.0, &post_opts)?;
            critical.push(p_c);
            Ok(branch)
        })
        .unwrap();
        let p_c = *critical.last().unwrap();
        assert!((p_c - pcr).abs() <= tol * pcr, "tol {tol:e}: P_cr {p_c} against {pcr}");
        let rod = &acc.rod;
        let mut worst_true: f64 = 0.0;
        for ((record, x), estimate) in acc.branch.records.iter().zip(&acc.branch.states).zip(&acc.estimates) {
            let estimate = estimate.expect("every record has an estimate");
            let p = record.lambda;
            if p <= pcr * (1.0 + 1e-6) {
                continue; // at the bifurcation itself k → 0: nothing to compare
            }
            let (k, axial, lateral) = elastica::at_load(p);
            let tip = rod.tip(x);
            let defl = tip[0].hypot(tip[1]);
            let truth = RecordError {
                tip_position: (defl - lateral).hypot(tip[2] - axial),
                tip_rotation: (rod.tip_rotation(x) - 2.0 * k.asin()).abs(),
                base_force: 0.0,
                base_moment: {
                    let (_, m) = rod.spatial_force_moment(x, 0);
                    (m[0].hypot(m[1]) - p * lateral).abs()
                },
            };
            // (The base force, −P e3, is exact: its truth is 0.)
            assert_within(&truth, &estimate, 1e-10, &format!("tol {tol:e}, P {p}"));
            let scaled = truth.scaled(rod, x);
            worst_true = worst_true.max(scaled);
            assert!(scaled <= tol, "tol {tol:e}, P {p}: true error {scaled:e}");
        }
        println!(
            "Euler, tol {tol:e}: elements tried {:?}, worst estimate {:.2e}, worst true error {worst_true:.2e}, P_cr error {:.1e}, {} records",
            acc.tried,
            acc.worst,
            (p_c - pcr).abs() / pcr,
            acc.branch.records.len()
        );
    }
}

/// A refinement stopped by its caller ends there (one try, the branch
/// cancelled, its estimates kept); a residual tolerance looser than the
/// tolerance asked for is refused by name.
#[test]
fn a_cancelled_refinement_stops_and_a_loose_residual_is_refused() {
    use rodkit::continuation::Stop;
    use rodkit::rod::accuracy::refine_until;
    let template = cantilever(Load::dead([1.0, 0.0, 0.0]));
    let opts = Options { target_lambda: Some(50.0), residual_tol: 1e-12, ..Default::default() };
    let acc = refine_until(&template, 1e-10, 1e-12, |rod| {
        let mut seen = 0;
        rod.continue_branch(None, 0.0, true, &opts, Method::Newton, |_| {
            seen += 1;
            seen < 5
        })
    })
    .unwrap();
    assert_eq!((acc.branch.stop, acc.tried.len()), (Stop::Cancelled, 1));
    assert_eq!(acc.estimates.len(), acc.branch.records.len());
    let err = refine_until(&template, 1e-8, 1e-6, |_| unreachable!("refused before any work")).err().unwrap();
    assert_eq!(err.status, rodkit::Status::ErrOutOfRange);
    assert!(err.message.contains("residual_tol"), "{}", err.message);
}

/// Greenhill's post-buckled branch under rotation control (K_b = L = 1,
/// C = 4, no tension; Λ = sin(φ/2), which folds at φ = π just after the
/// double point at φ = 2.2467): detected and located on the straight
/// branch, switched with the phase condition, followed 25 steps — the
/// whole path refined to 1e-4, 1e-6, 1e-8. Where Λ folds, the re-solves
/// (the estimate's, on half the elements, and the reference's, on ≥ 128)
/// may take the plane through the record normal to the branch instead of
/// its Λ (none needed it here: fixed-Λ Newton from the carried state
/// converged at every record, the nearest 0.03 rad from φ = π; the plane
/// is checked past the fold, at Λ = 1.001). Every quantity's true error ≤
/// its estimate, the scaled one ≤ the tolerance.
#[test]
fn greenhill_post_buckled_meets_the_tolerance_through_the_fold() {
    use rodkit::rod::accuracy::{refine_until, secant};
    use std::f64::consts::PI;
    let law = RodLaw::kirchhoff(1.0, 1.0, 4.0).unwrap();
    let template =
        Rod::new(law, 1.0, Loads::default(), Supports::Twisted { tension: 0.0 }, Scheme::Gauss(4), 4).unwrap();
    let post_opts = Options { residual_tol: 1e-12, max_step: 0.3, max_steps: 25, ..Default::default() };
    for tol in [1e-4, 1e-6, 1e-8] {
        let acc = refine_until(&template, tol, 1e-12, |rod| Ok(post_buckled(rod, 0.99, &post_opts)?.0)).unwrap();
        let rod = &acc.rod;
        let reference_rod = rod.subdivided(128usize.div_ceil(rod.elements)).unwrap();
        let mut reference = Resolver::new(rod, &reference_rod, acc.branch.phase).unwrap();
        let (records, states) = (&acc.branch.records, &acc.branch.states);
        let phis: Vec<f64> = states.iter().zip(records).map(|(x, r)| rod.end_rotation(x, r.lambda).unwrap()).collect();
        assert!(phis.iter().any(|&p| p > std::f64::consts::PI), "the path passes Λ's fold: φ {phis:?}");
        let mut worst_true: f64 = 0.0;
        for k in 0..records.len() {
            let estimate = acc.estimates[k].expect("every record has an estimate");
            let (dx, dl) = secant(records, states, k);
            let (y, _) = reference.solve(&states[k], records[k].lambda, 1e-11, Some((&dx, dl))).unwrap();
            let truth = rodkit::rod::accuracy::difference(rod, &states[k], &reference_rod, &y);
            assert_within(&truth, &estimate, 1e-10, &format!("tol {tol:e}, φ {}", phis[k]));
            let scaled = truth.scaled(rod, &states[k]);
            worst_true = worst_true.max(scaled);
            assert!(scaled <= tol, "tol {tol:e}, φ {}: true error {scaled:e}", phis[k]);
        }
        // Past Λ's fold (Λ = sin(φ/2) ≤ 1) there is no point at fixed Λ:
        // the re-solve asked at Λ = 1.001 from the record nearest φ = π
        // fails without a direction and, with the branch's secant, finds the
        // branch on the plane (Λ ≤ 1, an equilibrium).
        let k = (0..records.len()).min_by(|&a, &b| (phis[a] - PI).abs().total_cmp(&(phis[b] - PI).abs())).unwrap();
        assert!(reference.solve(&states[k], 1.001, 1e-11, None).is_err());
        let before = reference.planes;
        let (dx, dl) = secant(records, states, k);
        let (y, l) = reference.solve(&states[k], 1.001, 1e-11, Some((&dx, dl))).unwrap();
        assert_eq!(reference.planes, before + 1);
        assert!(l <= 1.0 + 1e-12 && (reference_rod.end_rotation(&y, l).unwrap() - PI).abs() < 0.5, "Λ {l}");
        println!(
            "Greenhill, tol {tol:e}: elements tried {:?}, worst estimate {:.2e}, worst true error {worst_true:.2e}, φ {:.3} → {:.3}, nearest π by {:.1e}, {} records",
            acc.tried,
            acc.worst,
            phis[0],
            phis.last().unwrap(),
            (phis[k] - PI).abs(),
            records.len()
        );
    }
}

/// The first `n` roots θ_k = 2x_k of tan x = x (Greenhill's critical
/// M L/K_b of a clamped–clamped rod without tension).
fn greenhill_roots(n: usize) -> Vec<f64> {
    (1..=n)
        .map(|k| {
            let mut x = (k as f64 + 0.5) * std::f64::consts::PI - 0.05;
            for _ in 0..60 {
                x -= (x.tan() - x) / (1.0 / x.cos().powi(2) - 1.0);
            }
            2.0 * x
        })
        .collect()
}

/// Critical loads to a tolerance: the straight branch with detection,
/// its elements chosen by continue_to_tolerance, every located point's
/// critical value within its estimate and the tolerance of the closed
/// form. Greenhill's rod (K_b = C = L = 1, clamped–clamped, no tension)
/// under end-moment control (Λ = M, critical M = θ_k) to M = 17 and under
/// rotation control (critical φ = θ_k) to φ = 17 exactly (until_rotation):
/// roots 1–2, double points (the straight records are near exact: without
/// the points' own estimates 4 elements would be kept, the second root
/// then ~1e-3 off); Euler's column (the elastica's rod, dead axial load, P_cr =
/// π²/4) to P = 3: one simple point.
#[test]
fn critical_loads_meet_the_tolerance_and_their_estimates() {
    use rodkit::rod::target::until_rotation;
    let detect = |target: Option<f64>| Options {
        target_lambda: target,
        residual_tol: 1e-12,
        initial_step: 0.05,
        max_step: 1.0,
        max_steps: 2000,
        detect_bifurcations: true,
        bifurcation_tol: 1e-11,
        ..Default::default()
    };
    let roots = greenhill_roots(2);
    let greenhill = |supports| {
        Rod::new(RodLaw::kirchhoff(1.0, 1.0, 1.0).unwrap(), 1.0, Loads::default(), supports, Scheme::Gauss(4), 4)
            .unwrap()
    };
    let euler = Rod::new(
        RodLaw::kirchhoff(1.0, 1.0, 1.0 / 1.3).unwrap(),
        1.0,
        Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() },
        Supports::Cantilever,
        Scheme::Gauss(4),
        4,
    )
    .unwrap();
    let cases = [
        ("Greenhill, moment control", greenhill(Supports::Torqued { tension: 0.0 }), Some(17.0), roots.clone()),
        ("Greenhill, rotation control", greenhill(Supports::Twisted { tension: 0.0 }), None, roots.clone()),
        ("Euler", euler, Some(3.0), vec![std::f64::consts::PI.powi(2) / 4.0]),
    ];
    for (name, template, target, truth) in cases {
        for tol in [1e-4, 1e-6, 1e-8] {
            let opts = detect(target);
            let acc = rodkit::rod::accuracy::refine_until(&template, tol, 1e-12, |rod| {
                let follow = |cb: &mut dyn FnMut(&rodkit::continuation::Record) -> bool| {
                    rod.continue_branch(None, 0.0, true, &opts, Method::Newton, cb)
                };
                if rod.twisted() {
                    // Rotation control: to φ = 17 exactly (Λ = sin(φ/2) cannot say it).
                    let plain = rodkit::rod::branch::Plain { rod, method: Method::Newton };
                    until_rotation(&plain, 17.0, None, &mut |_| true, follow)
                } else {
                    follow(&mut |_| true)
                }
            })
            .unwrap();
            if template.twisted() {
                let (phis, _) = acc.branch.end_rotations(&acc.rod, None);
                assert_eq!(acc.branch.stop, rodkit::continuation::Stop::Target);
                assert!((phis.last().unwrap() - 17.0).abs() < 1e-12, "ends at φ {:?}", phis.last());
            }
            let rod = &acc.rod;
            let (rotations, _) = acc.branch.end_rotations(rod, None);
            let bifs = &acc.branch.bifurcations;
            assert_eq!(bifs.len(), truth.len(), "{name}, tol {tol:e}: points {bifs:?}");
            let mut worst: f64 = 0.0;
            for (i, (bif, exact)) in bifs.iter().zip(&truth).enumerate() {
                let estimate = acc.bifurcation_estimates[i].expect("every point has an estimate");
                // The critical value read: φ under rotation control, else Λ.
                let (got, err) = if rod.twisted() {
                    (acc.branch.rotation_at_bifurcation(rod, i, &rotations).unwrap(), estimate.end_rotation)
                } else {
                    (bif.lambda, estimate.lambda)
                };
                let true_err = (got - exact).abs();
                worst = worst.max(true_err / exact);
                // Below 1e-10 the location's own tolerance, not the mesh.
                assert!(
                    true_err <= err.max(1e-10),
                    "{name}, tol {tol:e}, root {exact}: true {true_err:e} > estimate {err:e}"
                );
                assert!(true_err <= tol * exact, "{name}, tol {tol:e}, root {exact}: true {true_err:e}");
                assert!(estimate.scaled(rod, bif) <= tol, "{name}, tol {tol:e}: {estimate:?}");
            }
            println!(
                "{name}, tol {tol:e}: elements tried {:?}, worst estimate {:.2e}, worst true relative error {worst:.2e}, estimates {:?}",
                acc.tried,
                acc.worst,
                acc.bifurcation_estimates.iter().map(|e| e.map(|e| e.lambda.max(e.end_rotation))).collect::<Vec<_>>()
            );
        }
    }
}

/// What extension and shear do, by kirchhoff_differences: the cantilever
/// (K_b = L = 1, GA = 1e4, EA = 2.6e4) under small dead tip forces against
/// linear theory (Timoshenko: a transverse force F moves the tip by F L/GA
/// more than the unshearable rod, and turns the section no more; an axial
/// one stretches it by F L/EA) — at F = 1e-3 the nonlinear corrections are
/// O(F) relative, below 1e-2. A Kirchhoff rod is refused.
#[test]
fn kirchhoff_differences_are_what_extension_and_shear_do() {
    use rodkit::rod::accuracy::kirchhoff_differences;
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    for (direction, expected) in [([1.0, 0.0, 0.0], 1e-3 / 1e4), ([0.0, 0.0, 1.0], 1e-3 / 2.6e4)] {
        let loads = Loads { tip_force: Some(Load::dead(direction)), ..Default::default() };
        let rod = Rod::new(law.clone(), 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 8).unwrap();
        let opts = Options { target_lambda: Some(1e-3), residual_tol: 1e-13, initial_step: 1e-3, ..Default::default() };
        let b = rod.continue_branch(None, 0.0, true, &opts, Method::Newton, |_| true).unwrap();
        let d = kirchhoff_differences(&rod, &b, 1e-13).unwrap();
        let last = d.last().unwrap().expect("the Kirchhoff rod reaches the load");
        assert!((last.tip_position - expected).abs() < 1e-2 * expected, "{direction:?}: {last:?} against {expected:e}");
        assert!(last.tip_rotation < 1e-2 * expected, "{direction:?}: {last:?}");
        // The unloaded start: no difference.
        assert!(d[0].unwrap().tip_position < 1e-15);
    }
    let kirchhoff = Rod::new(
        RodLaw::kirchhoff(1.0, 1.0, 1.0).unwrap(),
        1.0,
        Loads::default(),
        Supports::Cantilever,
        Scheme::Gauss(4),
        4,
    )
    .unwrap();
    let b = kirchhoff
        .continue_branch(None, 0.0, true, &Options { max_steps: 1, ..Default::default() }, Method::Newton, |_| true)
        .unwrap();
    assert_eq!(kirchhoff_differences(&kirchhoff, &b, 1e-10).unwrap_err().status, rodkit::Status::ErrOutOfRange);
}

//! The discrete base-pair model coupled to the rod (issue 5, physics.md
//! §3.3; src/charged/sites.rs): point charges at 0.34 nm on
//! the rod's interpolated centreline, every pair farther apart along the
//! rod than a, the same engine and Jacobian machinery as the continuum.

#[path = "support/charged.rs"]
mod charged;

use charged::coiled_state;
use rodkit::charged::branch;
use rodkit::charged::dna::DnaScene;
use rodkit::charged::rod::{ChargedRod, RodCharge};
use rodkit::continuation::newton::Start;
use rodkit::continuation::Options;
use rodkit::electrostatics::discrete;
use rodkit::rod::model::Rod;

/// 200 bp at 0.01 M on 20 elements (3.4 nm), base pairs at 0.34 nm, a
/// loose cutoff (1e-2) so that the coiled state has pairs in the switch.
fn small_scene() -> (Rod, RodCharge) {
    let scene = DnaScene { base_pairs: 200, salt: 0.01, ..Default::default() };
    let rod = scene.rod(20, 2).unwrap();
    let mut charge = scene.charge();
    charge.cutoff_tolerance = Some(1e-2);
    charge.base_pairs = Some(0.34);
    (rod, charge)
}

/// The base-pair Jacobian (sites interpolated across element ends, pairs
/// with the switch, own-stencil terms, the end-rotation parameter) equals
/// central differences of the residual to 1e-6 of each row's largest entry.
#[test]
fn jacobian_matches_finite_differences() {
    let (rod, charge) = small_scene();
    let x = coiled_state(&rod, 3.0, 3.0);
    let mut p = ChargedRod::new(&rod, &charge, None, &x).unwrap();
    let (sites, b, pairs) = p.base_pairs().unwrap();
    assert_eq!(sites, 200);
    assert!((b - 0.34).abs() < 1e-12, "spacing {b}");
    assert!(pairs > 10_000, "site pairs {pairs}");
    let worst = charged::jacobian_fd_error(&mut p, &x, 7.3);
    println!("base pairs: worst relative Jacobian error {worst:e}");
}

/// The stage forces are minus the gradient of the base-pair energy:
/// w_j p_j = −∂E/∂r_j by central differences (step 1e-5 nm: truncation
/// ~1e-9, rounding of the ~10⁴-pair energy ~1e-9), relative 1e-6.
#[test]
fn force_is_minus_the_energy_gradient() {
    let (rod, charge) = small_scene();
    let x = coiled_state(&rod, 3.0, 3.0);
    let mut p = ChargedRod::new(&rod, &charge, None, &x).unwrap();
    let worst = charged::force_gradient_error(&mut p, &rod, &x);
    assert!(worst < 1e-6, "{worst:e}");
    println!("base pairs: force vs −gradient worst {worst:e}");
}

/// The hard core between base-pair charges (b² k_hc (2.5a − d)³ per pair
/// of sites farther apart along the rod than 1.25πa; a = 1.6 nm so that the
/// coiled state's strands are inside 2.5a): the Jacobian equals central
/// differences of the residual (1e-6 of the row scale, as above), and the
/// stage forces are −∂(E_far + E_hard)/∂r (1e-6), the hard core active.
#[test]
fn hard_core_between_charges_is_consistent() {
    let (rod, mut charge) = small_scene();
    charge.screening.a = 1.6;
    charge.hard_core = Some(50.0);
    let x = coiled_state(&rod, 3.0, 3.0);
    let mut p = ChargedRod::new(&rod, &charge, None, &x).unwrap();
    let e = p.energy(&x);
    let mut soft = charge.clone();
    soft.hard_core = None;
    let e_soft = ChargedRod::new(&rod, &soft, None, &x).unwrap().energy(&x);
    println!("hard-core energy {:e}, far {:e} (without: {:e})", e.hard_core, e.far, e_soft.far);
    assert!(e.hard_core > 1e-3 * e.far.abs(), "the hard core is not active: {e:?}");
    assert_eq!(e_soft.hard_core, 0.0);
    // The electrostatic part is the model's without the hard core (the
    // list is wider, the pairs within the cutoff the same): 1e-12.
    assert!((e.far - e_soft.far).abs() < 1e-12 * e.far.abs(), "{} vs {}", e.far, e_soft.far);
    let worst = charged::jacobian_fd_error(&mut p, &x, 7.3);
    println!("base pairs + hard core: worst relative Jacobian error {worst:e}");
    assert!(worst < 1e-6);
    let worst = charged::force_gradient_error(&mut p, &rod, &x);
    println!("base pairs + hard core: force vs −gradient worst {worst:e}");
    assert!(worst < 1e-6, "{worst:e}");
}

/// On a straight rod the interpolation is exact, so the coupled model's
/// energy is the discrete module's own sum over charges λb at (0, 0, s_k)
/// (electrostatics::discrete::energy, independent code) to 1e-12; with the
/// 1e-4 cutoff it stays within the tolerance of the all-pairs sum (the
/// cutoff's estimator is defined on a straight line).
#[test]
fn straight_rod_energy_is_the_discrete_sum() {
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let rod = scene.rod(30, 2).unwrap();
    let x = rod.straight_state();
    let mut charge = scene.charge();
    charge.base_pairs = Some(0.34);
    charge.cutoff_tolerance = None;
    let all = ChargedRod::new(&rod, &charge, None, &x).unwrap().energy(&x).far;
    charge.cutoff_tolerance = Some(1e-4);
    let cut = ChargedRod::new(&rod, &charge, None, &x).unwrap().energy(&x).far;
    // The rod's axis: z for the straight state.
    let tip = rod.tip(&x);
    assert!((tip[2] - rod.length).abs() < 1e-12 && tip[0].abs() < 1e-12, "straight state along z: {tip:?}");
    let n = 300;
    let b = rod.length / n as f64;
    let s: Vec<f64> = (0..n).map(|k| (k as f64 + 0.5) * b).collect();
    let r: Vec<[f64; 3]> = s.iter().map(|&v| [0.0, 0.0, v]).collect();
    let q = vec![charge.line_charge * b; n];
    let reference = discrete::energy(&r, &q, &s, &charge.screening, None);
    println!(
        "straight 300 bp: rod {all:.12e}, discrete {reference:.12e}, cutoff {cut:.12e} ({:e})",
        (cut - all).abs() / all
    );
    assert!((all - reference).abs() < 1e-12 * reference, "{all} vs {reference}");
    assert!((cut - all).abs() < 1e-4 * all, "cutoff {cut} vs {all}");
}

/// The first buckling point of the 300 bp scene (0.1 M, 60 elements) with
/// the base-pair model converges to the continuum model's as the spacing
/// shrinks (the models differ only by near-field terms, physics.md §3.3):
/// the gap at b = 0.34, 0.17, 0.113 nm must fall, to below half the first
/// and 1e-4 of φ_c (measured 1.5e-4, 6.5e-5, ~4e-5: order ≈ 1.2, the sharp
/// exclusion |s − t| > a of a midpoint sum). Reference: the continuum
/// rod's own buckling point on the same grid.
#[test]
fn buckling_point_converges_to_the_continuum() {
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let rod = scene.rod(60, 2).unwrap();
    let first = |charge: &RodCharge| {
        let opts = Options {
            target_lambda: Some(12.0),
            residual_tol: 1e-11,
            initial_step: 0.5,
            max_step: 1.0,
            detect_bifurcations: true,
            max_steps: 200,
            ..Default::default()
        };
        let b = branch::follow(
            &rod,
            charge,
            Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true },
            None,
            &opts,
            |_| true,
        )
        .unwrap();
        b.bifurcations.first().expect("a buckling point").lambda
    };
    let continuum = first(&scene.charge());
    let mut gaps = vec![];
    for b in [0.34, 0.17, 0.34 / 3.0] {
        let mut charge = scene.charge();
        charge.base_pairs = Some(b);
        let phi = first(&charge);
        let gap = (phi - continuum).abs() / continuum;
        println!("b = {b}: φ_c {phi:.8} (continuum {continuum:.8}), relative gap {gap:e}");
        gaps.push(gap);
    }
    assert!(gaps[1] < gaps[0] && gaps[2] < gaps[1], "gaps do not fall: {gaps:?}");
    assert!(gaps[2] < 0.5 * gaps[0] && gaps[2] < 1e-4, "gap at 0.113 nm: {}", gaps[2]);
}

//! A rod's bordered tangent factorised by static condensation of its
//! elements' stage unknowns (the default: `Problem::private_blocks`,
//! `rodkit::linalg::condensed`) against the same runs on B's own
//! simplicial LU (`LuKind::Simplicial`, the factorisation every result
//! before it was tested with): the same records, determinant signs and
//! bifurcations, and each against its closed form.

use rodkit::continuation::anm::continue_anm;
use rodkit::continuation::newton::{continue_newton, Start};
use rodkit::continuation::{Branch, Options, Problem, Stop};
use rodkit::linalg::LuKind;
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use std::f64::consts::PI;

/// Greenhill's rod under end-moment control (K_b = C = L = 1): double
/// points at θ = ML/K_b with tan(θ/2) = θ/2, θ1 = 8.9868, θ2 = 15.4505
/// (tests/rod_bifurcations.rs derives them).
const GREENHILL: [f64; 2] = [8.986_818_916_281_9, 15.450_503_673_064_9];

fn greenhill(kind: Option<LuKind>, anm: bool, stages: usize) -> Branch {
    let law = RodLaw::kirchhoff(1.0, 1.0, 1.0).unwrap();
    let supports = Supports::Torqued { tension: 0.0 };
    let rod = Rod::new(law, 1.0, Loads::default(), supports, Scheme::Gauss(stages), 16).unwrap();
    let mut sys = rod.system().unwrap();
    assert!(!sys.private_blocks().is_empty(), "a Gauss rod's stage unknowns are private to their element");
    let opts = Options {
        residual_tol: 1e-10,
        initial_step: 0.05,
        max_step: 1.0,
        max_steps: 5000,
        detect_bifurcations: true,
        bifurcation_tol: 1e-9,
        target_lambda: Some(17.0),
        lu_kind: kind,
        ..Default::default()
    };
    let start = Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true };
    let observe = |x: &[f64], l: f64| vec![rod.end_rotation(x, l).unwrap()];
    if anm {
        continue_anm(&mut sys, start, &opts, &Default::default(), observe, |_| true).unwrap()
    } else {
        continue_newton(&mut sys, start, &opts, observe, |_| true).unwrap()
    }
}

/// Both engines, Gauss(2) and Gauss(4): the condensed run took every
/// factorisation by condensation and the simplicial one none; the same
/// records (Λ and φ to 1e-9, every determinant sign and the σ_min sign
/// equal) and the same two double points, each at its closed form within
/// the mesh's error (16 elements: Gauss(4) 1e-6, Gauss(2) 2e-3
/// relative) and at the simplicial run's Λ to 1e-8.
#[test]
fn condensation_follows_greenhill_as_the_whole_lu() {
    for (anm, stages, tol) in [(true, 4, 1e-6), (false, 4, 1e-6), (true, 2, 2e-3)] {
        let name = format!("ANM {anm}, Gauss({stages})");
        let (fast, whole) = (greenhill(None, anm, stages), greenhill(Some(LuKind::Simplicial), anm, stages));
        assert_eq!((fast.stop, whole.stop), (Stop::Target, Stop::Target), "{name}");
        assert!(fast.counts.condensed > 0, "{name}: nothing condensed");
        assert_eq!(fast.counts.condensed, fast.counts.factorisations, "{name}: a factorisation fell back");
        assert_eq!(whole.counts.condensed, 0, "{name}");
        assert_eq!(fast.records.len(), whole.records.len(), "{name}");
        for (k, (a, b)) in fast.records.iter().zip(&whole.records).enumerate() {
            assert!((a.lambda - b.lambda).abs() < 1e-9, "{name} record {k}: Λ {} vs {}", a.lambda, b.lambda);
            assert!((a.outputs[0] - b.outputs[0]).abs() < 1e-9, "{name} record {k}: φ");
            assert_eq!((a.det_sign, a.bordered_det_sign), (b.det_sign, b.bordered_det_sign), "{name} record {k}");
            let (sa, sb) = (a.smallest_singular_value.unwrap(), b.smallest_singular_value.unwrap());
            assert_eq!(sa.signum(), sb.signum(), "{name} record {k}: σ_min {sa:e} vs {sb:e}");
            // Pivots: the counts depend on the factors' pivot order; the
            // parity of neither is compared (permutations differ).
            assert!(a.negative_pivots.is_some(), "{name} record {k}");
        }
        assert_eq!(
            fast.bifurcations.len(),
            2,
            "{name}: {:?}",
            fast.bifurcations.iter().map(|b| b.lambda).collect::<Vec<_>>()
        );
        assert_eq!(whole.bifurcations.len(), 2, "{name}");
        for ((a, b), theta) in fast.bifurcations.iter().zip(&whole.bifurcations).zip(GREENHILL) {
            assert!((a.lambda - theta).abs() <= tol * theta, "{name}: M {} against θ {theta}", a.lambda);
            assert!((a.lambda - b.lambda).abs() <= 1e-8, "{name}: M {} vs whole LU {}", a.lambda, b.lambda);
            assert_eq!(a.multiplicity, b.multiplicity, "{name}");
        }
    }
}

/// Euler's column (clamped–free, dead compressive load, L = 1) on an
/// inextensible, unshearable rod with bending stiffnesses 1 and 2: a
/// simple point at P_cr = π²K1/4 (Euler's closed form; the second, π²K2/4
/// = 4.93, lies past the run), found on the condensed tangent to 1e-8
/// relative (Gauss(4) × 8), at the whole LU's load to 1e-9, with the
/// bordered determinant flipping across it in both runs.
#[test]
fn condensation_finds_euler_s_load() {
    let law = RodLaw::kirchhoff(1.0, 2.0, 1.0 / 1.3).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 8).unwrap();
    let run = |kind: Option<LuKind>| {
        let mut sys = rod.system().unwrap();
        let opts = Options {
            residual_tol: 1e-11,
            detect_bifurcations: true,
            bifurcation_tol: 1e-10,
            target_lambda: Some(3.5),
            lu_kind: kind,
            ..Default::default()
        };
        let start = Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true };
        continue_anm(&mut sys, start, &opts, &Default::default(), |x: &[f64], _| rod.tip(x).to_vec(), |_| true).unwrap()
    };
    let (fast, whole) = (run(None), run(Some(LuKind::Simplicial)));
    let critical = PI * PI / 4.0;
    assert!(fast.counts.condensed > 0 && whole.counts.condensed == 0);
    assert_eq!((fast.bifurcations.len(), whole.bifurcations.len()), (1, 1));
    let (a, b) = (&fast.bifurcations[0], &whole.bifurcations[0]);
    assert!((a.lambda - critical).abs() < 1e-8 * critical, "P_cr {} against π²/4 {critical}", a.lambda);
    assert!((a.lambda - b.lambda).abs() < 1e-9, "P_cr {} vs the whole LU's {}", a.lambda, b.lambda);
    assert_eq!(a.multiplicity, 1);
    for branch in [&fast, &whole] {
        let k = branch.bifurcations[0].record;
        assert_eq!(branch.records[k].bordered_det_sign, -branch.records[k + 1].bordered_det_sign);
    }
}

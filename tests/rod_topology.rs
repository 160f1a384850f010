//! Lk = Tw + Wr along a supercoiling path (physics.md §3.4): a Kirchhoff
//! rod clamped at both ends on the e3 axis, under tension, its end rotated
//! by φ (Supports::Twisted, Λ = sin(φ/2)). The linking number of the
//! ribbon (r, d1), closed by rays along the clamp axis, is φ/2π; twist
//! (from u3) and writhe (Gauss integral with the rays) are computed
//! independently from the state. On the straight branch Wr = 0 and
//! Tw = φ/2π; past the first bifurcation, on the non-planar buckled branch,
//! the writhe grows and the sum still equals φ/2π to the discretisation
//! error (Gauss(4) × 16: ≤ 3e-8 measured with the cubic Hermite
//! centreline through the profile points, O(h⁴); ≤ 1.6e-9 since it is
//! refined by quintic Hermite points, `WRITHE_PARTS`).

use rodkit::continuation::Options;
use rodkit::rod::branch::{Method, RodBranch};
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Loads, RodLaw};
use std::f64::consts::PI;

/// The twisted rod under tension on `elements` elements of Gauss(4) and
/// its straight branch to Λ = 0.99 (through its first buckling point).
fn twisted_rod(elements: usize) -> (Rod, RodBranch) {
    let law = RodLaw::kirchhoff(1.0, 1.3, 4.0).unwrap();
    let rod =
        Rod::new(law, 1.0, Loads::default(), Supports::Twisted { tension: 1.0 }, Scheme::Gauss(4), elements).unwrap();
    let opts = Options {
        target_lambda: Some(0.99),
        residual_tol: 1e-12,
        initial_step: 0.2,
        max_step: 0.5,
        detect_bifurcations: true,
        ..Default::default()
    };
    let straight = rod.continue_branch(None, 0.0, true, &opts, Method::Newton, |_| true).unwrap();
    (rod, straight)
}

#[test]
fn linking_number_is_the_end_rotation_along_a_buckling_path() {
    let (rod, straight) = twisted_rod(16);
    for (r, x) in straight.records.iter().zip(&straight.states) {
        let phi = rod.end_rotation(x, r.lambda).unwrap();
        let (tw, wr) = (rod.twist(x), rod.writhe(x, 10).unwrap());
        assert!(wr.abs() < 1e-10, "straight: Wr {wr:e}");
        assert!((tw - phi / (2.0 * PI)).abs() < 1e-10, "straight: Tw {tw} vs φ/2π {}", phi / (2.0 * PI));
    }
    let opts = Options { residual_tol: 1e-12, max_step: 0.1, max_steps: 10, ..Default::default() };
    let buckled = rod.switch_branch(&straight, 0, 0, 0.05, &opts, Method::Newton, |_| true).unwrap();
    let mut max_wr = 0.0f64;
    for (r, x) in buckled.records.iter().zip(&buckled.states) {
        let phi = rod.end_rotation(x, r.lambda).unwrap();
        let (tw, wr) = (rod.twist(x), rod.writhe(x, 10).unwrap());
        let lk = phi / (2.0 * PI);
        println!("Λ {:.6}: φ/2π {lk:.9}, Tw {tw:.9}, Wr {wr:.9}, Tw + Wr − Lk {:e}", r.lambda, tw + wr - lk);
        assert!((tw + wr - lk).abs() < 1e-6, "Λ {}: Tw + Wr = {} vs {lk}", r.lambda, tw + wr);
        max_wr = max_wr.max(wr.abs());
    }
    assert!(max_wr > 1e-3, "the branch did not writhe ({max_wr:e})");
}

/// The writhe's centreline refined by quintic Hermite points
/// (`Rod::writhe_within`, `WRITHE_PARTS` = 2; issue 18 step 7): on a
/// coarse mesh the cubic Hermite through the profile points alone limits
/// Tw + Wr − Lk (the twist is the scheme's, O(h^2s)); refined, the sum
/// meets φ/2π far closer. Measured on the buckled branch of the rod above
/// on 4 elements of Gauss(4): worst |Tw + Wr − Lk| parts 1: 1.0e-5, 2:
/// 1.2e-8 (3: 5.6e-7). Asserted: parts 2 within 1e-7 and ≥ 100× closer
/// than parts 1.
#[test]
fn refined_writhe_centreline_keeps_the_linking_number_on_a_coarse_mesh() {
    let (rod, straight) = twisted_rod(4);
    let opts = Options { residual_tol: 1e-12, max_step: 0.1, max_steps: 12, ..Default::default() };
    let buckled = rod.switch_branch(&straight, 0, 0, 0.05, &opts, Method::Newton, |_| true).unwrap();
    let (mut worst1, mut worst2, mut max_wr) = (0.0f64, 0.0f64, 0.0f64);
    for (r, x) in buckled.records.iter().zip(&buckled.states) {
        let lk = rod.end_rotation(x, r.lambda).unwrap() / (2.0 * PI);
        let tw = rod.twist(x);
        let wr1 = rod.writhe_within_parts(x, 1e-12, 1).unwrap().value;
        let wr2 = rod.writhe_within_parts(x, 1e-12, 2).unwrap().value;
        assert_eq!(wr2, rod.writhe_within(x, 1e-12).unwrap().value, "the default is 2 parts");
        println!("Λ {:.6}: Wr {wr2:.9}, Tw + Wr − Lk: parts 1 {:e}, 2 {:e}", r.lambda, tw + wr1 - lk, tw + wr2 - lk);
        worst1 = worst1.max((tw + wr1 - lk).abs());
        worst2 = worst2.max((tw + wr2 - lk).abs());
        max_wr = max_wr.max(wr2.abs());
    }
    println!("worst |Tw + Wr − Lk|: parts 1 {worst1:e}, parts 2 {worst2:e}; largest Wr {max_wr:e}");
    assert!(max_wr > 1e-2, "the branch did not writhe ({max_wr:e})");
    assert!(worst2 < 1e-7 && 100.0 * worst2 < worst1, "parts 2 {worst2:e} against parts 1 {worst1:e}");
}

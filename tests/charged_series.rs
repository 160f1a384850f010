//! The charged rod's Taylor series along a path (issue 18: the ANM for
//! the charged rod, src/charged/rod/series.rs) against its own residual.
//!
//! Reference: for a polynomial path X(a) = X0 + a X1 + a² X2 (any state,
//! not only equilibria: the series is algebra), the coefficients R_p that
//! `series_order` returns make Σ_{p≤P} a^p R_p the Taylor polynomial of
//! R(X(a)); so the remainder |R(X(a)) − Σ a^p R_p| is O(a^{P+1}) — halving a
//! divides it by ~2^{P+1}. One wrong coefficient R_m (m ≤ P) would leave an
//! O(a^m) remainder and a ratio ≤ 2^m. Scene: 200 bp at 0.01 M on 20
//! elements, coiled so that pairs sit inside r_on, in the cutoff's switch
//! and in the hard core's range (tests/charged_rod.rs's scene), under
//! rotation control (Λ = sin(φ/2) and the row c − cos(φ/2) take the
//! sine–cosine recurrence).

#[path = "support/charged.rs"]
mod charged;

use charged::{coiled_state, small_scene};
use rodkit::charged::rod::{ChargedRod, RodCharge};
use rodkit::continuation::{Problem, SeriesProblem};
use rodkit::rod::model::Rod;

fn max_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// Each row in its equation's scale (force, moment and kinematic rows
/// alike: a wrong coefficient in a small row is not hidden by the large).
fn scaled(p: &ChargedRod, v: &[f64]) -> Vec<f64> {
    v.iter().zip(p.equation_scales()).map(|(x, e)| x / e).collect()
}

/// The remainder of the order-`order` series at a, with the ANM's two
/// calls per order (X_p = 0 first: the known part; then the solved X_p).
fn remainder(p: &mut ChargedRod, x0: &[f64], dirs: &[Vec<f64>; 2], phi: [f64; 3], order: usize, a: f64) -> f64 {
    let n = x0.len();
    p.series_begin(x0, phi[0], order);
    let mut coef = vec![vec![0.0; n]; order + 1];
    p.residual(x0, phi[0], &mut coef[0]);
    let zeros = vec![0.0; n];
    for k in 1..=order {
        let (xk, lk) = match k {
            1 | 2 => (&dirs[k - 1], phi[k]),
            _ => (&zeros, 0.0),
        };
        let mut known = vec![0.0; n];
        p.series_order(k, &zeros, 0.0, &mut known);
        p.series_order(k, xk, lk, &mut coef[k]);
        assert!(known.iter().all(|v| v.is_finite()));
    }
    let xa: Vec<f64> = (0..n).map(|i| x0[i] + a * dirs[0][i] + a * a * dirs[1][i]).collect();
    let phia = phi[0] + a * phi[1] + a * a * phi[2];
    let mut r = vec![0.0; n];
    p.residual(&xa, phia, &mut r);
    for (k, c) in coef.iter().enumerate() {
        for i in 0..n {
            r[i] -= a.powi(k as i32) * c[i];
        }
    }
    max_norm(&scaled(p, &r))
}

/// Both near zones: element-aligned, and cut at exactly δ (the gap's
/// terms through the stage interpolant: RodCharge::exact_near_width).
#[test]
fn the_series_of_the_residual_is_its_taylor_polynomial_along_a_path() {
    let (rod, charge) = small_scene();
    for exact in [false, true] {
        println!("exact near zone: {exact}");
        series_matches_the_residual(&rod, &RodCharge { exact_near_width: exact, ..charge.clone() }, exact);
    }
    // A graded mesh (per-element row coefficients in the series too).
    let t: Vec<f64> = (0..=rod.elements)
        .map(|i| {
            let u = i as f64 / rod.elements as f64;
            u + 0.5 * (std::f64::consts::TAU * u).sin() / std::f64::consts::TAU
        })
        .collect();
    println!("graded mesh, exact near zone");
    series_matches_the_residual(
        &rod.clone().graded(&t).unwrap(),
        &RodCharge { exact_near_width: true, ..charge },
        true,
    );
}

fn series_matches_the_residual(rod: &Rod, charge: &RodCharge, exact: bool) {
    let x0 = coiled_state(rod, 3.0, 3.0);
    let mut p = ChargedRod::new(rod, charge, None, &x0).unwrap();
    assert!(p.pairs() > 100, "pairs {}", p.pairs());
    assert_eq!(p.gap_points() > 0, exact);
    // Directions: every unknown moved, smoothly in the index (positions by
    // ~0.3 nm, quaternions and the rest by ~0.03 of their size).
    let n = x0.len();
    let dirs = [
        (0..n).map(|i| 0.05 * (0.37 * i as f64).sin() * (1.0 + x0[i].abs())).collect::<Vec<_>>(),
        (0..n).map(|i| 0.02 * (0.11 * i as f64 + 1.0).cos() * (1.0 + x0[i].abs())).collect::<Vec<_>>(),
    ];
    let phi = [7.3, 0.4, -0.1];
    let scale = {
        let mut r = vec![0.0; n];
        p.residual(&x0, phi[0], &mut r);
        max_norm(&scaled(&p, &r)).max(1.0)
    };
    for order in [3, 6] {
        let (e1, e2) = (remainder(&mut p, &x0, &dirs, phi, order, 0.2), remainder(&mut p, &x0, &dirs, phi, order, 0.1));
        let ratio = e1 / e2;
        println!(
            "order {order}: remainder {e1:e} at a = 0.2, {e2:e} at 0.1, ratio {ratio:.1} (2^(P+1) = {})",
            1 << (order + 1)
        );
        // The O(a^{P+1}) remainder: ratio ≈ 2^{P+1} (within the next
        // term's share); a wrong order-m coefficient would give ≤ 2^m.
        assert!(ratio > 0.6 * (1 << (order + 1)) as f64, "order {order}: ratio {ratio}");
        assert!(e2 < 1e-3 * scale, "order {order}: remainder {e2:e} of residual scale {scale:e}");
    }
}

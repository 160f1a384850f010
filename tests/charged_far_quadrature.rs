//! The continuum's far zone on a refined quadrature (`RodCharge::far_points`,
//! src/charged/sites.rs; issue 18 step 7): M Gauss–Legendre points per
//! element on the cubic stage interpolant instead of the s stage points.
//! Checked against an independent reference — the far double integral on
//! the exact curve by a fine composite Gauss rule — and for consistency:
//! the Jacobian against differences of the residual, the stage forces
//! against the energy's gradient.

#[path = "support/charged.rs"]
mod charged;

use charged::{coiled_state, helix};
use rodkit::charged::dna::DnaScene;
use rodkit::charged::rod::{ChargedRod, RodCharge};
use rodkit::quadrature::gauss_legendre;
use rodkit::rod::model::Rod;

/// 200 bp (68 nm) at 0.1 M (1/κ ≈ 0.96 nm) on 20 elements of Gauss(2)
/// (3.4 nm: stage points ~1.7 nm apart, the spacing whose error the
/// refinement removes), every pair (no cutoff: the reference integrates
/// e^{−κd}/d itself).
fn scene() -> (Rod, RodCharge) {
    let scene = DnaScene { base_pairs: 200, salt: 0.1, ..Default::default() };
    let rod = scene.rod(20, 2).unwrap();
    let mut charge = scene.charge();
    charge.cutoff_tolerance = None;
    (rod, charge)
}

/// The helix of `coiled_state` (arc-length parametrised): radius 5 nm,
/// 4.5 nm between turns — strands at a plectoneme's distance.
const RADIUS: f64 = 5.0;
const RISE: f64 = 4.5;

/// ½λ² ∫∫ e^{−κd}/d over pairs of elements more than `near` apart, on the
/// exact helix: 16 panels of 8 Gauss–Legendre points per element (0.21 nm
/// panels; the integrand's scale is ≥ 1/κ ≈ 1 nm, so ~1e-12 relative).
fn reference_far_energy(rod: &Rod, charge: &RodCharge) -> f64 {
    let (z, w) = gauss_legendre(8);
    let h = rod.element_length();
    let panels = 16;
    let mut pts: Vec<(usize, [f64; 3], f64)> = Vec::new();
    for e in 0..rod.elements {
        for p in 0..panels {
            let a = e as f64 * h + p as f64 * h / panels as f64;
            let half = 0.5 * h / panels as f64;
            for (zi, wi) in z.iter().zip(&w) {
                pts.push((e, helix(a + half * (1.0 + zi), RADIUS, RISE), half * wi));
            }
        }
    }
    let (kappa, l2) = (charge.screening.kappa, charge.line_charge * charge.line_charge);
    let mut sum = 0.0;
    for (ei, ri, wi) in &pts {
        for (ej, rj, wj) in &pts {
            if ei.abs_diff(*ej) > charge.near_elements_for(h, rod.elements) {
                let d = ((ri[0] - rj[0]).powi(2) + (ri[1] - rj[1]).powi(2) + (ri[2] - rj[2]).powi(2)).sqrt();
                sum += wi * wj * (-kappa * d).exp() / d;
            }
        }
    }
    0.5 * l2 * sum
}

/// The refined far energy (sites on both sides) converges to the exact
/// double integral as M grows, down to the six-point interpolant's own
/// error, below the stage quadrature's: measured on this helix (relative)
/// stage points 3.4e-5; M = 4: 3.6e-6, 8: 3.6e-6, 16: 3.7e-6 (the
/// interpolant's plateau; a cubic stencil gave 2.5e-4). Asserted: M = 8
/// within 1e-5 and ≥ 5× better than the stage points, M = 16 within 10 %
/// of M = 8 (converged in M).
#[test]
fn refined_far_energy_converges_to_the_double_integral() {
    let (rod, charge) = scene();
    let x = coiled_state(&rod, RADIUS, RISE);
    let exact = reference_far_energy(&rod, &charge);
    let far = |m: usize| {
        let c = RodCharge { far_points: m, ..charge.clone() };
        let mut p = ChargedRod::new(&rod, &c, None, &x).unwrap();
        if m > 0 {
            let (sites, pairs) = p.far_sites().unwrap();
            assert_eq!(sites, 20 * m);
            // Every pair (no cutoff): each site with the m sites of every
            // element more than near_elements from its own.
            let far_elements: usize = (0..20usize)
                .map(|e| (0..20usize).filter(|f| f.abs_diff(e) > c.near_elements_for(rod.element_length(), 20)).count())
                .sum();
            assert_eq!(pairs, far_elements * m * m, "directed site pairs");
            assert!(pairs > 0);
            assert!(p.base_pairs().is_none());
        } else {
            assert!(p.far_sites().is_none());
        }
        p.energy(&x).far
    };
    let errors: Vec<(usize, f64)> = [0, 4, 8, 16].iter().map(|&m| (m, (far(m) - exact).abs() / exact.abs())).collect();
    for (m, e) in &errors {
        println!("far points {m}: relative error {e:.2e} (exact {exact:.10e})");
    }
    let (stage, m8, m16) = (errors[0].1, errors[2].1, errors[3].1);
    assert!(m8 < 1e-5, "M = 8: {m8:e}");
    assert!(m8 * 5.0 < stage, "M = 8 {m8:e} against the stage points {stage:e}");
    assert!(m16 <= 1.1 * m8, "M = 16 {m16:e} against M = 8 {m8:e}");
}

/// The stage forces are minus the gradient of the refined energy,
/// w_j p_j = −∂E_far/∂r_j by central differences (step 1e-5 nm), relative
/// to the largest |w p| within 1e-6: the residual is the gradient of one
/// discrete energy (action and reaction exact), as for the stage points.
#[test]
fn refined_far_forces_are_the_energy_gradient() {
    let (rod, mut charge) = scene();
    charge.far_points = 6;
    let x = coiled_state(&rod, RADIUS, RISE);
    let mut p = ChargedRod::new(&rod, &charge, None, &x).unwrap();
    let worst = charged::force_gradient_error(&mut p, &rod, &x);
    println!("refined far zone: force vs −gradient worst {worst:e}");
    assert!(worst < 1e-6, "{worst:e}");
}

/// The refined model's Jacobian (sites interpolated across element ends,
/// the switch, the end-rotation parameter) equals central differences of
/// its residual to 1e-6 of each row's largest entry (asserted inside).
#[test]
fn refined_far_jacobian_matches_differences() {
    let (rod, mut charge) = scene();
    charge.cutoff_tolerance = Some(1e-2);
    charge.far_points = 5;
    let x = coiled_state(&rod, RADIUS, RISE);
    let mut p = ChargedRod::new(&rod, &charge, None, &x).unwrap();
    let worst = charged::jacobian_fd_error(&mut p, &x, 7.3);
    println!("refined far zone: worst relative Jacobian error {worst:e}");
    assert!(worst < 1e-6);
}

/// The refinement is refused where it has no meaning: with the base-pair
/// model or the ANM (whose series are the stage points'), and beyond 32
/// points an element.
#[test]
fn refined_far_zone_refuses_other_models() {
    let (rod, charge) = scene();
    let x = rod.straight_state();
    for bad in [
        RodCharge { far_points: 4, base_pairs: Some(0.34), ..charge.clone() },
        RodCharge { far_points: 4, anm: Some(Default::default()), ..charge.clone() },
        RodCharge { far_points: 33, ..charge.clone() },
    ] {
        let e = ChargedRod::new(&rod, &bad, None, &x).err().expect("refused");
        assert_eq!(e.status, rodkit::status::Status::ErrOutOfRange, "{e}");
        println!("refused: {e}");
    }
}

//! Thick-tube linear theory (physics.md §1.4) against independent references:
//! the isotropic generalized-plane-strain Lamé solution (compressible and
//! incompressible, derived by hand in the comments), mirror symmetry, and
//! convergence to the thin-tube closed form as t/R → 0.

use nalgebra::{Matrix2, Matrix3, Vector2};
use rodkit::tube::{Compressibility, Orthotropic, ThickTube, ThinTube};
use std::f64::consts::PI;

/// Compressible isotropic tube, u = C1 R + C2/R (generalized plane strain):
///   σ_RR = 2(λ+μ)C1 − 2μC2/R² + λε,  σ_ZZ = 2λC1 + (λ+2μ)ε,
///   u(A) = Aε_A, σ_RR(B) = 0;  F = π(B²−A²)σ_ZZ, T = πμψ(B⁴−A⁴)/2,
///   2πA²p = −2πA²σ_RR(A).
fn lame_compressible(a: f64, b: f64, e: f64, nu: f64) -> Matrix3<f64> {
    let lam = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = e / (2.0 * (1.0 + nu));
    let mut k = Matrix3::zeros();
    for (col, (eps, psi, eps_a)) in [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)].into_iter().enumerate() {
        let m = Matrix2::new(a, 1.0 / a, 2.0 * (lam + mu), -2.0 * mu / (b * b));
        let c = m.lu().solve(&Vector2::new(a * eps_a, -lam * eps)).unwrap();
        let szz = 2.0 * lam * c[0] + (lam + 2.0 * mu) * eps;
        let srr_a = 2.0 * (lam + mu) * c[0] - 2.0 * mu * c[1] / (a * a) + lam * eps;
        k[(0, col)] = PI * (b * b - a * a) * szz;
        k[(1, col)] = PI * mu * psi * (b.powi(4) - a.powi(4)) / 2.0;
        k[(2, col)] = -2.0 * PI * a * a * srr_a;
    }
    k
}

/// Incompressible isotropic tube: u = −εR/2 + D/R, D = A²(ε_A + ε/2),
/// σ̂ = 2μ ε; integrating R σ_RR' = 4μD/R² with σ_RR(B) = 0 gives
/// p = 2μD(1/A² − 1/B²) and σ_ZZ = 3με + 2μD/B².
fn lame_incompressible(a: f64, b: f64, mu: f64) -> Matrix3<f64> {
    let mut k = Matrix3::zeros();
    for (col, (eps, psi, eps_a)) in [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)].into_iter().enumerate() {
        let d = a * a * (eps_a + 0.5 * eps);
        k[(0, col)] = PI * (b * b - a * a) * (3.0 * mu * eps + 2.0 * mu * d / (b * b));
        k[(1, col)] = PI * mu * psi * (b.powi(4) - a.powi(4)) / 2.0;
        k[(2, col)] = 2.0 * PI * a * a * 2.0 * mu * d * (1.0 / (a * a) - 1.0 / (b * b));
    }
    k
}

#[test]
fn isotropic_compressible_matches_lame_at_any_helix_angle() {
    for (a, b, nu, tau0) in [(1.0, 2.0, 0.3, 0.0), (0.3, 1.0, 0.45, 2.0), (5.0, 5.5, -0.5, -0.4), (1.0, 10.0, 0.1, 1.0)]
    {
        let mat = Orthotropic::isotropic(7.0, nu).unwrap();
        let tube = ThickTube::new(a, b, tau0, mat, Compressibility::Compressible).unwrap();
        let k = tube.coupling_stiffness(1e-12).unwrap();
        assert!(k.error_estimate <= 1e-12);
        let exact = lame_compressible(a, b, 7.0, nu);
        let err = (k.value.k - exact).amax() / exact.amax();
        assert!(err < 1e-11, "A {a} B {b} nu {nu}: rel err {err:e}\n{}\n{exact}", k.value.k);
        // No extension–twist or twist–inflation coupling for isotropy.
        assert!(k.value.k[(0, 1)].abs() < 1e-12 * exact.amax() && k.value.k[(1, 2)].abs() < 1e-12 * exact.amax());
    }
}

#[test]
fn isotropic_incompressible_matches_closed_form() {
    for (a, b, tau0) in [(1.0, 2.0, 0.0), (0.3, 1.0, 3.0), (5.0, 5.5, -0.4)] {
        // λ_L plays no role under tr ε = 0: any compressible ν gives the same K.
        for nu in [0.0, 0.3, 0.49] {
            let e = 2.0 * 1.5 * (1.0 + nu); // μ = 1.5
            let mat = Orthotropic::isotropic(e, nu).unwrap();
            let tube = ThickTube::new(a, b, tau0, mat, Compressibility::Incompressible).unwrap();
            let k = tube.coupling_stiffness(1e-12).unwrap().value.k;
            let exact = lame_incompressible(a, b, 1.5);
            let err = (k - exact).amax() / exact.amax();
            assert!(err < 1e-11, "A {a} B {b} nu {nu}: rel err {err:e}\n{k}\n{exact}");
        }
    }
}

#[test]
fn solid_cylinder_stretch_twist_is_ea_and_gj() {
    // Uniaxial stress in a solid isotropic cylinder: S = Eπb², C = μπb⁴/2, g = 0;
    // incompressible: S = 3μπb².
    let (b, e, nu) = (0.8, 3.0, 0.3);
    let mat = Orthotropic::isotropic(e, nu).unwrap();
    let mu = e / (2.0 * (1.0 + nu));
    // (Compressible: solved with a 1e−6·b traction-free pinhole on a grid in
    // ln R, whose O(1e−12) effect the tolerance covers; 40 intervals.)
    let st = ThickTube::new(0.0, b, 1.0, mat, Compressibility::Compressible).unwrap().stretch_twist_at(40).unwrap();
    assert!((st.stretch - e * PI * b * b).abs() < 1e-12 * st.stretch, "{st:?}");
    assert!((st.twist - mu * PI * b.powi(4) / 2.0).abs() < 1e-12 * st.twist);
    assert!(st.coupling.abs() < 1e-12 * st.stretch);
    let st = ThickTube::new(0.0, b, 1.0, mat, Compressibility::Incompressible).unwrap().stretch_twist_at(24).unwrap();
    assert!((st.stretch - 3.0 * mu * PI * b * b).abs() < 1e-12 * st.stretch, "{st:?}");
}

fn helical_material() -> Orthotropic {
    // A fibre-like wall: stiff along the helix, soft across.
    Orthotropic::new(10.0, 2.0, 1.5, 0.35, 0.3, 0.4, 1.2, 0.8, 0.6).unwrap()
}

#[test]
fn reversing_intrinsic_twist_flips_twist_couplings() {
    let m = helical_material();
    for comp in [Compressibility::Compressible, Compressibility::Incompressible] {
        let k = ThickTube::new(0.6, 1.4, 1.3, m, comp).unwrap().coupling_stiffness_at(24).unwrap().k;
        let l = ThickTube::new(0.6, 1.4, -1.3, m, comp).unwrap().coupling_stiffness_at(24).unwrap().k;
        let s = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, -1.0, 1.0));
        assert!((l - s * k * s).amax() < 1e-12 * k.amax(), "{comp:?}\n{k}\n{l}");
        assert!(k[(0, 1)].abs() > 1e-3 * k.amax(), "the helical wall must couple extension and twist");
    }
}

/// Thick → thin: with A = R − t/2, B = R + t/2, the thick K (inner-radius
/// variables) approaches the thin closed form converted to the same variables
/// (ε_θ = (A/R)ε_A, 2πR²p → 2πA²p: K_inner = P K_mid P, P = diag(1, 1, A/R)).
/// Each entry's error, relative to √(K_ii K_jj), falls at rate ≥ 1 in t/R.
#[test]
fn thick_converges_to_thin_at_rate_at_least_one() {
    let m = helical_material();
    let r = 1.0;
    let tau0 = 1.7;
    let errors: Vec<Matrix3<f64>> = [0.08, 0.04, 0.02, 0.01]
        .iter()
        .map(|&t| {
            let a = r - t / 2.0;
            let thick = ThickTube::new(a, r + t / 2.0, tau0, m, Compressibility::Compressible)
                .unwrap()
                .coupling_stiffness(1e-12)
                .unwrap()
                .value
                .k;
            let thin = ThinTube::new(r, t, tau0, m.surface()).unwrap().coupling_stiffness().unwrap().k;
            let p = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 1.0, a / r));
            let thin = p * thin * p;
            Matrix3::from_fn(|i, j| (thick[(i, j)] - thin[(i, j)]).abs() / (thin[(i, i)] * thin[(j, j)]).sqrt())
        })
        .collect();
    for i in 0..3 {
        for j in i..3 {
            for w in errors.windows(2) {
                let rate = (w[0][(i, j)] / w[1][(i, j)]).log2();
                assert!(
                    rate >= 0.95,
                    "entry ({i},{j}): errors {:e} → {:e}, rate {rate:.3}",
                    w[0][(i, j)],
                    w[1][(i, j)]
                );
            }
            assert!(errors[3][(i, j)] < 0.05, "entry ({i},{j}) error {:e} at t/R = 0.01", errors[3][(i, j)]);
        }
    }
}

/// The error estimate (1.5× finer grid, floored at round-off) bounds the true
/// error against a converged 96-interval reference (whose own round-off is
/// ~1e−14).
#[test]
fn error_estimate_bounds_true_error() {
    let m = helical_material();
    let tube = ThickTube::new(0.2, 1.5, 2.0, m, Compressibility::Compressible).unwrap();
    let reference = tube.coupling_stiffness_at(96).unwrap().k;
    for tol in [1e-4, 1e-7, 1e-10] {
        let est = tube.coupling_stiffness(tol).unwrap();
        let truth = (est.value.k - reference).amax() / reference.amax();
        assert!(est.error_estimate <= tol, "{est:?}");
        assert!(truth <= est.error_estimate, "tol {tol:e}: true {truth:e} > estimate {:e}", est.error_estimate);
    }
}

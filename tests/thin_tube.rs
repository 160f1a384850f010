//! Validation of the thin-tube linear theory (physics.md §1.4) against
//! independent references: closed forms of isotropic elasticity, exact
//! symmetries of the helix, and a direct 4th-order tensor rotation.

use nalgebra::Matrix3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rodkit::tube::{OrthotropicSurface, ThinTube, Winding};
use rodkit::Status;
use std::f64::consts::PI;

fn random_material(rng: &mut impl Rng) -> OrthotropicSurface {
    loop {
        let e1 = 10f64.powf(rng.random_range(-1.0..1.0));
        let e2 = e1 * 10f64.powf(rng.random_range(-1.5..1.5));
        let g12 = e1 * 10f64.powf(rng.random_range(-1.5..0.5));
        let nu12 = rng.random_range(-0.9..0.9) * (e1 / e2).sqrt();
        if let Ok(m) = OrthotropicSurface::new(e1, e2, nu12, g12) {
            return m;
        }
    }
}

fn scale(k: &Matrix3<f64>) -> f64 {
    k.amax()
}

/// Isotropic wall: no extension–twist nor twist–inflation coupling at any
/// helix angle (the material has no preferred direction). Reference:
/// isotropic plane-stress elasticity, Q̄ = E/(1−ν²)[[1,ν,0],[ν,1,0],[0,0,(1−ν)/2]],
/// so K11 = 2πRt·E/(1−ν²), K13 = ν·K11, K22 = 2πR³t·G (thin-walled J = 2πR³t),
/// and the condensed stretch modulus is S = 2πRt·E (uniaxial hoop-free stress).
#[test]
fn isotropic_wall_has_no_twist_coupling_at_any_angle() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for _ in 0..200 {
        let e = 10f64.powf(rng.random_range(-3.0..3.0));
        let nu = rng.random_range(-0.9..0.5);
        let r = rng.random_range(0.1..10.0);
        let t = r * rng.random_range(1e-4..1.0);
        let tau0 = rng.random_range(-20.0..20.0) / r;
        let tube = ThinTube::new(r, t, tau0, OrthotropicSurface::isotropic(e, nu).unwrap()).unwrap();
        let k = tube.coupling_stiffness().unwrap().k;
        let tol = 1e-13 * scale(&k);
        assert!(k[(0, 1)].abs() <= tol && k[(1, 2)].abs() <= tol, "alpha = {}: K = {k}", tube.helix_angle());
        let a = 2.0 * PI * r * t;
        let k11 = a * e / (1.0 - nu * nu);
        let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(1e-300);
        assert!(rel(k[(0, 0)], k11) < 1e-13);
        assert!((k[(0, 2)] - nu * k11).abs() < 1e-13 * k11);
        assert!(rel(k[(1, 1)], 2.0 * PI * r.powi(3) * t * e / (2.0 * (1.0 + nu))) < 1e-13);
        assert!(rel(tube.coupling_stiffness().unwrap().stretch_twist().stretch, a * e) < 1e-12);
        let resp = tube.coupling_stiffness().unwrap().free_response().unwrap();
        assert_eq!(resp.winding, Winding::Neither);
        // Poisson contraction of the hoop: dε_θ/dF = −ν/(E·2πRt).
        assert!(rel(resp.dhoop_dforce, -nu / (e * a)) < 1e-11 || nu.abs() < 1e-3);
    }
}

/// Reinforcement along the axis (α = 0) or along the hoop (α → 90°) is a
/// mirror-symmetric layout: the extension–twist couplings K_εψ and g vanish.
#[test]
fn axial_and_hoop_reinforcement_have_no_extension_twist() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    for _ in 0..100 {
        let mat = random_material(&mut rng);
        for tau0 in [0.0, 1e20, -1e20] {
            let tube = ThinTube::new(1.0, 0.1, tau0, mat).unwrap();
            let c = tube.coupling_stiffness().unwrap();
            let tol = 1e-13 * scale(&c.k);
            assert!(c.k[(0, 1)].abs() <= tol, "tau0 = {tau0}: K = {}", c.k);
            assert!(c.k[(1, 2)].abs() <= tol);
            assert!(c.stretch_twist().coupling.abs() <= tol);
            assert_eq!(c.free_response().unwrap().winding, Winding::Neither);
        }
    }
}

/// Mirror image: τ0 → −τ0 maps α → −α (m n → −m n), which flips the sign of
/// the two twist couplings and keeps every other entry, exactly.
#[test]
fn reversing_intrinsic_twist_flips_twist_couplings_only() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for _ in 0..200 {
        let mat = random_material(&mut rng);
        let tau0 = rng.random_range(0.01..5.0);
        let k = ThinTube::new(1.3, 0.2, tau0, mat).unwrap().coupling_stiffness().unwrap().k;
        let m = ThinTube::new(1.3, 0.2, -tau0, mat).unwrap().coupling_stiffness().unwrap().k;
        let tol = 1e-14 * scale(&k);
        for (i, j, sign) in [(0, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0), (0, 2, 1.0), (0, 1, -1.0), (1, 2, -1.0)] {
            assert!((m[(i, j)] - sign * k[(i, j)]).abs() <= tol, "entry ({i},{j}): {} vs {}", m[(i, j)], k[(i, j)]);
        }
    }
}

/// Independent reference for the rotation: build the 2-D compliance tensor
/// S_ijkl in the material axes, rotate it with four direction cosines, and
/// read the engineering Voigt entries (S̄16 = 2 S_1112, S̄66 = 4 S_1212, ...).
fn tensor_rotated_compliance(mat: &OrthotropicSurface, alpha: f64) -> Matrix3<f64> {
    let mut s = [[[[0.0f64; 2]; 2]; 2]; 2];
    s[0][0][0][0] = 1.0 / mat.e1;
    s[1][1][1][1] = 1.0 / mat.e2;
    s[0][0][1][1] = -mat.nu12 / mat.e1;
    s[1][1][0][0] = -mat.nu12 / mat.e1;
    for (i, j, k, l) in [(0, 1, 0, 1), (0, 1, 1, 0), (1, 0, 0, 1), (1, 0, 1, 0)] {
        s[i][j][k][l] = 1.0 / (4.0 * mat.g12);
    }
    // r[a][i]: global (Z, Θ) component a of material axis i.
    let (n, m) = alpha.sin_cos();
    let r = [[m, -n], [n, m]];
    let mut g = [[[[0.0f64; 2]; 2]; 2]; 2];
    for a in 0..2 {
        for b in 0..2 {
            for c in 0..2 {
                for d in 0..2 {
                    let mut acc = 0.0;
                    for i in 0..2 {
                        for j in 0..2 {
                            for k in 0..2 {
                                for l in 0..2 {
                                    acc += r[a][i] * r[b][j] * r[c][k] * r[d][l] * s[i][j][k][l];
                                }
                            }
                        }
                    }
                    g[a][b][c][d] = acc;
                }
            }
        }
    }
    Matrix3::new(
        g[0][0][0][0],
        g[0][0][1][1],
        2.0 * g[0][0][0][1],
        g[1][1][0][0],
        g[1][1][1][1],
        2.0 * g[1][1][0][1],
        2.0 * g[0][1][0][0],
        2.0 * g[0][1][1][1],
        4.0 * g[0][1][0][1],
    )
}

#[test]
fn closed_form_s16_equals_tensor_rotation() {
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    for _ in 0..500 {
        let mat = random_material(&mut rng);
        let alpha = rng.random_range(-PI / 2.0..PI / 2.0);
        let reference = tensor_rotated_compliance(&mat, alpha);
        let lib = mat.rotated_compliance(alpha);
        let tol = 1e-13 * reference.amax();
        assert!((lib - reference).amax() <= tol, "alpha {alpha}: {lib} vs {reference}");
        assert!((mat.s16_closed_form(alpha) - reference[(0, 2)]).abs() <= tol);
    }
}

/// K = 2πRt·D Q̄ D is a congruence of an SPD matrix: symmetric positive
/// definite. Reference: eigenvalues of the symmetric eigen-decomposition.
/// Also the free-tube response equals the membrane closed forms
/// dψ/dF = S̄16/(2πR²t), dε_θ/dF = S̄12/(2πRt) (§1.4).
#[test]
fn stiffness_is_spd_and_free_response_matches_closed_form() {
    let mut rng = ChaCha8Rng::seed_from_u64(15);
    for _ in 0..300 {
        let mat = random_material(&mut rng);
        let r = rng.random_range(0.5..2.0);
        let t = r * rng.random_range(1e-3..0.5);
        let tau0 = rng.random_range(-3.0..3.0);
        let tube = ThinTube::new(r, t, tau0, mat).unwrap();
        let c = tube.coupling_stiffness().unwrap();
        assert_eq!(c.k, c.k.transpose());
        let eig = c.k.symmetric_eigen().eigenvalues;
        assert!(eig.min() > 0.0, "eigenvalues {eig}");
        let sb = mat.rotated_compliance(tube.helix_angle());
        let resp = c.free_response().unwrap();
        // Tolerance: the solve loses a factor of cond(K) (at most ~1e6 here).
        let cond = eig.max() / eig.min();
        let tol = 1e-14 * cond;
        let psi = sb[(0, 2)] / (2.0 * PI * r * r * t);
        let bound = (sb[(0, 0)] * sb[(2, 2)]).sqrt() / (2.0 * PI * r * r * t);
        assert!((resp.dtwist_dforce - psi).abs() <= tol * bound, "{} vs {psi}", resp.dtwist_dforce);
        let hoop = sb[(0, 1)] / (2.0 * PI * r * t);
        assert!((resp.dhoop_dforce - hoop).abs() <= tol * sb[(0, 0)] / (2.0 * PI * r * t));
        let strain = sb[(0, 0)] / (2.0 * PI * r * t);
        assert!((resp.dstrain_dforce - strain).abs() <= tol * strain);
    }
}

/// The winding flag follows the sign of the condensed coupling g
/// (overwinds ⇔ sign(τ0)·g < 0), not of K_εψ alone; the sample must contain
/// materials where the two disagree, or this test would prove nothing.
#[test]
fn winding_follows_condensed_coupling_not_stiffness_entry() {
    let mut rng = ChaCha8Rng::seed_from_u64(16);
    let (mut disagreements, mut over, mut under) = (0, 0, 0);
    for _ in 0..2000 {
        let mat = random_material(&mut rng);
        let tau0 = rng.random_range(-3.0..3.0);
        let c = ThinTube::new(1.0, 0.3, tau0, mat).unwrap().coupling_stiffness().unwrap();
        let g = c.stretch_twist().coupling;
        let w = c.free_response().unwrap().winding;
        if g.abs() < 1e-9 * c.k.amax() {
            continue;
        }
        let expected = if tau0.signum() * g < 0.0 { Winding::Overwinds } else { Winding::Unwinds };
        assert_eq!(w, expected, "tau0 {tau0}, g {g}, K {}", c.k);
        if c.k[(0, 1)].signum() != g.signum() {
            disagreements += 1;
        }
        match w {
            Winding::Overwinds => over += 1,
            Winding::Unwinds => under += 1,
            Winding::Neither => {}
        }
    }
    assert!(disagreements >= 10, "only {disagreements} cases where sign(K_eps_psi) != sign(g)");
    assert!(over >= 100 && under >= 100, "over {over}, under {under}");
}

#[test]
fn invalid_inputs_are_rejected_with_named_arguments() {
    let iso = OrthotropicSurface::isotropic(1.0, 0.3).unwrap();
    let e = ThinTube::new(1.0, -0.1, 0.0, iso).unwrap_err();
    assert_eq!(e.status, Status::ErrNotPositive);
    assert!(e.message.contains("`thickness`"));
    let e = ThinTube::new(1.0, 2.0, 0.0, iso).unwrap_err();
    assert_eq!(e.status, Status::ErrInvalidGeometry);
    let e = ThinTube::new(f64::INFINITY, 0.1, 0.0, iso).unwrap_err();
    assert_eq!(e.status, Status::ErrNotFinite);
    let e = OrthotropicSurface::new(1.0, 4.0, 0.6, 1.0).unwrap_err();
    assert_eq!(e.status, Status::ErrNotPositiveDefinite);
    let e = OrthotropicSurface::isotropic(1.0, 0.7).unwrap_err();
    assert_eq!(e.status, Status::ErrOutOfRange);
    assert!(e.message.contains("`nu`"));
}

/// Extremes: moduli spanning 1e±150 and ratios 1e±4, helix angles near 0 and
/// 90°, t/R = 1e−6. Every case is answered (measured: all four; a refusal
/// would be a capability lost), and held against an exact property rather
/// than finiteness alone: K is homogeneous of degree 1 in the moduli (every
/// stiffness of §1.4 is a modulus times geometry), so K(E1) = E1·K(1) with
/// the same ratios, and the free response scales as 1/E1 — to 1e-12
/// relative (a few roundings per entry).
#[test]
fn extremes_give_finite_results() {
    for (e1, ratio, tau0, t) in
        [(1e150, 1e4, 1e-8, 1e-6), (1e-150, 1e-4, 1e8, 1.0), (1.0, 1e4, 1.732, 1e-6), (1.0, 1e-4, -1.732, 1.9)]
    {
        let tube =
            |e: f64| ThinTube::new(1.0, t, tau0, OrthotropicSurface::new(e, e * ratio, 0.0, e * 0.1).unwrap()).unwrap();
        let what = format!("E1 {e1:e}, ratio {ratio:e}, τ0 {tau0:e}, t {t:e}");
        let c = tube(e1).coupling_stiffness().unwrap_or_else(|e| panic!("{what}: {e}"));
        let unit = tube(1.0).coupling_stiffness().unwrap();
        let scale = unit.k.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (got, one) in c.k.iter().zip(unit.k.iter()) {
            assert!(got.is_finite() && (got / e1 - one).abs() <= 1e-12 * scale, "{what}: {got:e} vs {e1:e}·{one:e}");
        }
        let (r, r1) = (c.free_response().unwrap(), unit.free_response().unwrap());
        for (got, one) in [
            (r.dstrain_dforce, r1.dstrain_dforce),
            (r.dtwist_dforce, r1.dtwist_dforce),
            (r.dhoop_dforce, r1.dhoop_dforce),
        ] {
            assert!(
                got.is_finite() && (got * e1 - one).abs() <= 1e-12 * r1.dstrain_dforce.abs().max(one.abs()),
                "{what}: {got:e}·{e1:e} vs {one:e}"
            );
        }
    }
    // Overflow to infinity is reported, not returned.
    let huge = OrthotropicSurface::new(1e307, 1e307, 0.0, 1e307).unwrap();
    let e = ThinTube::new(1e10, 1.0, 0.0, huge).unwrap().coupling_stiffness().unwrap_err();
    assert_eq!(e.status, Status::ErrNonFiniteResult);
}

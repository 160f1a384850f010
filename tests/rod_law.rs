//! The tube section as a hemitropic rod (src/tube/rod_law.rs) against
//! independent references: textbook section constants of isotropic tubes
//! (EA, EI, GJ, the thin-tube shear coefficient 1/2), the condensed
//! stretch–twist law of the 3×3 coupling stiffness (a separate code path),
//! the straight-rod response of physics.md §2.2, handedness, and the
//! thick → thin limit.

use rodkit::rod::Moduli;
use rodkit::tube::{Compressibility, Orthotropic, OrthotropicSurface, RodStiffness, ThickTube, ThinTube};
use std::f64::consts::PI;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn helical() -> Orthotropic {
    Orthotropic::new(12.0, 2.5, 1.8, 0.32, 0.28, 0.41, 1.1, 0.7, 0.55).unwrap()
}

/// Isotropic thin tube (E, ν, radius R, wall t): EA = 2πRtE, EI = πR³tE,
/// GJ = 2πR³tG, shear GπRt (Timoshenko coefficient 1/2 of a thin circular
/// tube), no couplings. Reference: any strength-of-materials text.
#[test]
fn thin_isotropic_tube_has_textbook_section_constants() {
    let (e, nu, r, t) = (3.0, 0.3, 1.4, 0.01);
    let g = e / (2.0 * (1.0 + nu));
    for tau0 in [0.0, 0.8, -3.0] {
        let k =
            ThinTube::new(r, t, tau0, OrthotropicSurface::isotropic(e, nu).unwrap()).unwrap().rod_stiffness().unwrap();
        assert!(rel(k.stretch(), 2.0 * PI * r * t * e) < 1e-14);
        assert!(rel(k.bending(), PI * r.powi(3) * t * e) < 1e-14);
        assert!(rel(k.twist(), 2.0 * PI * r.powi(3) * t * g) < 1e-14);
        assert!(rel(k.shear(), PI * r * t * g) < 1e-14);
        assert!(k.twist_stretch().abs() < 1e-14 * k.stretch() * r);
        assert!(k.bend_shear().abs() < 1e-14 * k.stretch() * r);
        assert_eq!(k.k, k.k.transpose());
    }
}

/// Helical thin tube: the (u3, v3) block is the condensed stretch–twist law
/// of ThinTube::coupling_stiffness (reference: the 3×3 K condensed at p = 0,
/// computed independently), the straight rod pulled by F twists by
/// Δu3 = −gF/(CS − g²) (physics.md §2.2; also the 3×3 free response), and
/// the thin-wall relations K_b = R²S/2, G = C/(2R²), c2 = −g/2 hold.
#[test]
fn thin_helical_tube_is_a_hemitropic_rod() {
    let (r, t) = (1.0, 0.02);
    for (tau0, surface) in [(1.7, helical().surface()), (-0.6, OrthotropicSurface::new(1.0, 7.0, 0.05, 0.4).unwrap())] {
        let tube = ThinTube::new(r, t, tau0, surface).unwrap();
        let k = tube.rod_stiffness().unwrap();
        let cs = tube.coupling_stiffness().unwrap();
        let st = cs.stretch_twist();
        assert!(rel(k.stretch(), st.stretch) < 1e-13);
        assert!(rel(k.twist(), st.twist) < 1e-13);
        assert!(rel(k.twist_stretch(), st.coupling) < 1e-12);
        assert!(k.twist_stretch().abs() > 1e-3 * (k.stretch() * k.twist()).sqrt(), "the case must be chiral");
        let inv = k.k.try_inverse().unwrap();
        let (s, c, g) = (st.stretch, st.twist, st.coupling);
        let du3 = -g / (c * s - g * g);
        assert!(rel(inv[(2, 5)], du3) < 1e-12);
        assert!(rel(inv[(2, 5)], cs.free_response().unwrap().dtwist_dforce) < 1e-12);
        assert!(rel(inv[(5, 5)], c / (c * s - g * g)) < 1e-12);
        assert!(rel(k.bending(), r * r * s / 2.0) < 1e-13);
        assert!(rel(k.shear(), c / (2.0 * r * r)) < 1e-13);
        assert!(rel(k.bend_shear(), -g / 2.0) < 1e-12);
        // Hemitropic form: nothing else is coupled.
        let moduli =
            Moduli::symmetric(k.bending(), k.twist(), k.shear(), k.stretch(), k.twist_stretch(), k.bend_shear());
        let pattern = RodStiffness::from_moduli(&moduli).unwrap();
        assert_eq!(pattern.k, k.k);
    }
}

/// Reversing the helix (τ0 → −τ0) is a reflection: it flips g and c2 and
/// leaves the achiral moduli unchanged (reference: symmetry), thin and thick.
#[test]
fn reversing_the_helix_flips_the_chiral_couplings() {
    let chiral = |k: &RodStiffness| [k.twist_stretch(), k.bend_shear()];
    let achiral = |k: &RodStiffness| [k.bending(), k.twist(), k.shear(), k.stretch()];
    let thin = |tau0: f64| ThinTube::new(1.0, 0.1, tau0, helical().surface()).unwrap().rod_stiffness().unwrap();
    let thick = |tau0: f64| {
        ThickTube::new(0.5, 1.0, tau0, helical(), Compressibility::Compressible)
            .unwrap()
            .rod_stiffness(1e-12)
            .unwrap()
            .value
    };
    for (plus, minus) in [(thin(1.3), thin(-1.3)), (thick(1.3), thick(-1.3))] {
        for (p, m) in chiral(&plus).iter().zip(chiral(&minus)) {
            assert!(p.abs() > 0.0 && rel(-m, *p) < 1e-10, "{p} vs {m}");
        }
        for (p, m) in achiral(&plus).iter().zip(achiral(&minus)) {
            assert!(rel(m, *p) < 1e-10);
        }
    }
}

/// Isotropic thick tube and solid cylinder: EA = Eπ(B² − A²) (uniaxial
/// stress is exact), GJ = Gπ(B⁴ − A⁴)/2, EI = Eπ(B⁴ − A⁴)/4, shear
/// Gπ(B² − A²)/2 (the stated thin-wall coefficient); incompressible:
/// E = 3G. Reference: strength of materials.
#[test]
fn thick_isotropic_section_constants() {
    let (e, nu) = (2.0, 0.27);
    for (a, b) in [(0.3, 1.0), (0.0, 0.8)] {
        for comp in [Compressibility::Compressible, Compressibility::Incompressible] {
            let (mat, e_eff, g) = match comp {
                Compressibility::Compressible => (Orthotropic::isotropic(e, nu).unwrap(), e, e / (2.0 * (1.0 + nu))),
                Compressibility::Incompressible => (Orthotropic::isotropic(e, 0.25).unwrap(), 3.0 * e / 2.5, e / 2.5),
            };
            let est = ThickTube::new(a, b, 0.9, mat, comp).unwrap().rod_stiffness(1e-11).unwrap();
            let k = est.value;
            let tol = 1e-9;
            assert!(rel(k.stretch(), e_eff * PI * (b * b - a * a)) < tol, "{comp:?} A = {a}: S {}", k.stretch());
            assert!(rel(k.twist(), g * PI * (b.powi(4) - a.powi(4)) / 2.0) < tol, "{comp:?} A = {a}: C");
            assert!(rel(k.bending(), e_eff * PI * (b.powi(4) - a.powi(4)) / 4.0) < tol, "{comp:?} A = {a}: K_b");
            assert!(rel(k.shear(), g * PI * (b * b - a * a) / 2.0) < tol, "{comp:?} A = {a}: G");
            assert!(k.twist_stretch().abs() < 1e-9 * k.stretch() * b && k.bend_shear().abs() < 1e-9 * k.stretch() * b);
            assert!(est.error_estimate <= 1e-11);
        }
    }
}

/// Thick → thin as t/R → 0 (same material, plane-stress surface, compressible):
/// every one of the six moduli converges with an observed rate ≥ 1 between
/// t/R = 0.04 and 0.01 (reference: the thin closed form is the t/R → 0 limit).
#[test]
fn thick_rod_law_converges_to_thin() {
    let r = 1.0;
    let moduli = |k: &RodStiffness| [k.bending(), k.twist(), k.shear(), k.stretch(), k.twist_stretch(), k.bend_shear()];
    let diff = |t: f64| {
        let thin = ThinTube::new(r, t, 1.4, helical().surface()).unwrap().rod_stiffness().unwrap();
        let thick = ThickTube::new(r - t / 2.0, r + t / 2.0, 1.4, helical(), Compressibility::Compressible)
            .unwrap()
            .rod_stiffness(1e-12)
            .unwrap()
            .value;
        let (a, b) = (moduli(&thin), moduli(&thick));
        [0, 1, 2, 3, 4, 5].map(|i| rel(b[i], a[i]))
    };
    let (coarse, fine) = (diff(0.04), diff(0.01));
    for i in 0..6 {
        let rate = (coarse[i] / fine[i]).log(4.0);
        assert!(
            fine[i] < 0.05 && (rate >= 0.95 || fine[i] < 1e-9),
            "modulus {i}: differences {:e} → {:e}, rate {rate}",
            coarse[i],
            fine[i]
        );
    }
}

/// The estimate bounds the true error: a loose request against a converged
/// one (reference: the 1e−12 answer), helical thick wall.
#[test]
fn thick_rod_law_estimate_bounds_error() {
    let tube = ThickTube::new(0.2, 1.5, 2.0, helical(), Compressibility::Compressible).unwrap();
    let reference = tube.rod_stiffness(1e-12).unwrap().value;
    for tol in [1e-4, 1e-7] {
        let est = tube.rod_stiffness(tol).unwrap();
        let scale = reference.k.amax();
        let err = (est.value.k - reference.k).amax() / scale;
        assert!(
            est.error_estimate <= tol && err <= est.error_estimate.max(1e-13),
            "tol {tol:e}: error {err:e}, estimate {:e}",
            est.error_estimate
        );
    }
}

//! Tube scenes: the cheapest model that meets the tolerance, reported, with
//! its answer checked against the converged thick solution; the rod law of a
//! section.

use rodkit::tube::finite::{FiniteTube, Loading, SolveOptions};
use rodkit::tube::material::fibre::{FibreAngle, FibreFamily};
use rodkit::tube::material::{FibreReinforced, NeoHookean, SaintVenantKirchhoff};
use rodkit::tube::scene::{TubeModel, TubeScene, WallLaw};
use rodkit::tube::Orthotropic;
use rodkit::Status;
use std::f64::consts::PI;

fn helical_svk() -> WallLaw {
    WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(
        Orthotropic::new(10.0, 2.0, 1.5, 0.35, 0.3, 0.4, 1.2, 0.8, 0.6).unwrap(),
        1.7,
        false,
    ))
}

/// Reference: the thick solver at 1e−12. The scene's answer must be within
/// its tolerance (in the scaled measures: ψR and radii per R) whichever model
/// it picked, and it must pick the membrane when that suffices.
#[test]
fn auto_picks_the_cheapest_model_that_meets_the_tolerance() {
    let loading = Loading::torsion_free_stretch(1.1);
    for (a, b, tol, expect) in [
        (0.995, 1.005, 1e-4, TubeModel::Membrane),
        (0.995, 1.005, 1e-9, TubeModel::Thick),
        (0.6, 1.4, 1e-4, TubeModel::Thick),
    ] {
        let scene = TubeScene::new(a, b, helical_svk(), TubeModel::Auto, tol, None).unwrap();
        let (state, used) = scene.solve(&loading).unwrap();
        assert_eq!(used, expect, "A {a} B {b} tol {tol:e}");
        let law = helical_svk();
        let WallLaw::SaintVenantKirchhoff(m) = &law else { unreachable!() };
        let reference = FiniteTube::new(a, b, m)
            .unwrap()
            .solve(&loading, &SolveOptions { rel_tol: 1e-12, intervals: None })
            .unwrap();
        let err = ((state.twist - reference.twist) * b)
            .abs()
            .max((state.deformed_outer_radius - reference.deformed_outer_radius).abs() / b);
        assert!(err <= tol, "A {a} B {b} tol {tol:e} ({used:?}): true error {err:e}");
        assert!(state.error_estimate <= tol);
    }
}

#[test]
fn section_rod_law() {
    // Solid isotropic neo-Hookean cylinder: S = Eπb², C = μπb⁴/2, g = 0 with
    // E = μ(3λ+2μ)/(λ+μ) (linear elasticity of the law at rest).
    let (mu, lam, b) = (1.0, 4.0, 0.5);
    let nh = WallLaw::NeoHookean(NeoHookean { shear_modulus: mu, lame_lambda: lam, incompressible: false });
    let st = TubeScene::new(0.0, b, nh, TubeModel::Thick, 1e-10, None).unwrap().stretch_twist().unwrap();
    let e = mu * (3.0 * lam + 2.0 * mu) / (lam + mu);
    assert!((st.stretch - e * PI * b * b).abs() < 1e-10 * st.stretch, "{st:?}");
    assert!((st.twist - mu * PI * b.powi(4) / 2.0).abs() < 1e-10 * st.twist);
    assert!(st.coupling.abs() < 1e-12 * st.stretch);
    // A hollow helical tube: the rod law is the condensed K.
    let scene = TubeScene::new(0.6, 1.4, helical_svk(), TubeModel::Auto, 1e-10, None).unwrap();
    let k = scene.coupling_stiffness().unwrap().value;
    assert_eq!(scene.stretch_twist().unwrap(), k.stretch_twist());
    assert!(k.stretch_twist().coupling.abs() > 1e-3 * k.stretch_twist().stretch);
}

#[test]
fn fibre_walls_have_no_linear_stiffness_and_bad_laws_are_rejected() {
    let fam = |hand| FibreFamily { angle: FibreAngle::Helix { hand }, k1: 2.0, k2: 1.0 };
    let hgo = WallLaw::FibreReinforced(FibreReinforced {
        matrix: NeoHookean { shear_modulus: 0.1, lame_lambda: 10.0, incompressible: false },
        families: vec![fam(1.0), fam(-1.0)],
        intrinsic_twist: 0.8,
    });
    let scene = TubeScene::new(0.9, 1.1, hgo, TubeModel::Auto, 1e-6, None).unwrap();
    assert_eq!(scene.coupling_stiffness().unwrap_err().status, Status::ErrOutOfRange);
    // But it solves finite states.
    let (s, _) = scene.solve(&Loading::torsion_free_stretch(1.2)).unwrap();
    assert!(s.applied_force > 0.0 && s.torque.abs() < 1e-9);

    let bad = WallLaw::NeoHookean(NeoHookean { shear_modulus: 1.0, lame_lambda: -1.0, incompressible: false });
    assert_eq!(
        TubeScene::new(0.5, 1.0, bad, TubeModel::Auto, 1e-6, None).unwrap_err().status,
        Status::ErrNotPositiveDefinite
    );
    let bad = WallLaw::NeoHookean(NeoHookean { shear_modulus: -1.0, lame_lambda: 1.0, incompressible: false });
    assert_eq!(TubeScene::new(0.5, 1.0, bad, TubeModel::Auto, 1e-6, None).unwrap_err().status, Status::ErrNotPositive);
    assert_eq!(
        TubeScene::new(1.0, 0.5, helical_svk(), TubeModel::Auto, 1e-6, None).unwrap_err().status,
        Status::ErrInvalidGeometry
    );
}

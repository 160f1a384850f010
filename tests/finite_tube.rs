//! Finite-strain tube solver (physics.md §1.2–1.3) against independent
//! references: the linear theory (the finite response differentiated at the
//! stress-free state), exact neo-Hookean results, and limits.

use rodkit::tube::finite::{Axial, Ends, FiniteTube, Loading, SolveOptions, Torsion};
use rodkit::tube::material::{NeoHookean, SaintVenantKirchhoff};
use rodkit::tube::{Compressibility, Orthotropic, ThickTube};
use rodkit::Status;
use std::f64::consts::PI;

fn helical() -> Orthotropic {
    Orthotropic::new(10.0, 2.0, 1.5, 0.35, 0.3, 0.4, 1.2, 0.8, 0.6).unwrap()
}

fn load(axial: Axial, torsion: Torsion, p: f64) -> Loading {
    Loading { axial, torsion, inner_pressure: p, outer_pressure: 0.0, ends: Ends::Open }
}

/// Central differences of the finite-strain solver at the stress-free state
/// reproduce the linear thick-tube K (reference: ThickTube, an independent
/// linear collocation code). With e = (ε, ψ, ε_A) and f = (F, T, 2πA²p):
/// prescribing λ = 1 ± h gives ε_A = −K31 h/K33, F = (K11 − K13K31/K33) h, …
#[test]
fn linearisation_at_rest_equals_linear_stiffness() {
    let (a, b, tau0) = (0.6, 1.4, 1.7);
    for incompressible in [false, true] {
        let svk = SaintVenantKirchhoff::new(helical(), tau0, incompressible);
        let tube = FiniteTube::new(a, b, &svk).unwrap();
        let comp = if incompressible { Compressibility::Incompressible } else { Compressibility::Compressible };
        let k = ThickTube::new(a, b, tau0, helical(), comp).unwrap().coupling_stiffness(1e-12).unwrap().value.k;
        let opts = SolveOptions { rel_tol: 1e-12, intervals: None };
        let h = 1e-5;
        let d = |plus: Loading, minus: Loading| {
            let (p, m) = (tube.solve(&plus, &opts).unwrap(), tube.solve(&minus, &opts).unwrap());
            let ea = ((p.deformed_inner_radius - m.deformed_inner_radius) / a) / (2.0 * h);
            (ea, (p.wall_force - m.wall_force) / (2.0 * h), (p.torque - m.torque) / (2.0 * h))
        };
        // Stretch at ψ = 0, p = 0.
        let (ea, df, dt) = d(
            load(Axial::Stretch(1.0 + h), Torsion::Twist(0.0), 0.0),
            load(Axial::Stretch(1.0 - h), Torsion::Twist(0.0), 0.0),
        );
        let ea_lin = -k[(2, 0)] / k[(2, 2)];
        let tol = 1e-7;
        assert!((ea - ea_lin).abs() < tol, "{incompressible}: dε_A/dε {ea} vs {ea_lin}");
        assert!((df - (k[(0, 0)] + k[(0, 2)] * ea_lin)).abs() < tol * k.amax(), "dF/dε {df}");
        assert!((dt - (k[(1, 0)] + k[(1, 2)] * ea_lin)).abs() < tol * k.amax(), "dT/dε {dt}");
        // Twist at λ = 1, p = 0.
        let (ea, df, dt) =
            d(load(Axial::Stretch(1.0), Torsion::Twist(h), 0.0), load(Axial::Stretch(1.0), Torsion::Twist(-h), 0.0));
        let ea_lin = -k[(2, 1)] / k[(2, 2)];
        assert!((ea - ea_lin).abs() < tol, "dε_A/dψ {ea} vs {ea_lin}");
        assert!((df - (k[(0, 1)] + k[(0, 2)] * ea_lin)).abs() < tol * k.amax(), "dF/dψ {df}");
        assert!((dt - (k[(1, 1)] + k[(1, 2)] * ea_lin)).abs() < tol * k.amax(), "dT/dψ {dt}");
        // Inner pressure at λ = 1, ψ = 0: 2πA²p = K33 ε_A.
        let (ea, df, dt) =
            d(load(Axial::Stretch(1.0), Torsion::Twist(0.0), h), load(Axial::Stretch(1.0), Torsion::Twist(0.0), -h));
        let ea_lin = 2.0 * PI * a * a / k[(2, 2)];
        assert!((ea - ea_lin).abs() < tol * ea_lin.abs(), "dε_A/dp {ea} vs {ea_lin}");
        assert!((df - k[(0, 2)] * ea_lin).abs() < tol * k.amax() * ea_lin.abs(), "dF/dp {df}");
        assert!((dt - k[(1, 2)] * ea_lin).abs() < tol * k.amax() * ea_lin.abs(), "dT/dp {dt}");
    }
}

/// Poynting effect, exact for an incompressible neo-Hookean solid cylinder
/// twisted at fixed length (Rivlin 1948; physics.md §1.5): T = πμψb⁴/2 and the
/// axial force needed to keep the length is N = −πμψ²b⁴/4.
#[test]
fn neo_hookean_poynting_effect() {
    let (mu, b) = (1.3, 0.7);
    let nh = NeoHookean { shear_modulus: mu, lame_lambda: 0.0, incompressible: true };
    let tube = FiniteTube::new(0.0, b, &nh).unwrap();
    for psi in [0.1, 1.0, 3.0] {
        let s = tube.solve(&load(Axial::Stretch(1.0), Torsion::Twist(psi), 0.0), &SolveOptions::default()).unwrap();
        let t = PI * mu * psi * b.powi(4) / 2.0;
        let n = -PI * mu * psi * psi * b.powi(4) / 4.0;
        assert!((s.torque - t).abs() < 1e-10 * t, "psi {psi}: T {} vs {t}", s.torque);
        assert!((s.wall_force - n).abs() < 1e-10 * n.abs(), "psi {psi}: N {} vs {n}", s.wall_force);
    }
}

/// Incompressible kinematics conserve volume: π(b² − a²)λ = π(B² − A²).
#[test]
fn incompressible_tube_conserves_volume() {
    let svk = SaintVenantKirchhoff::new(helical(), 1.2, true);
    let (a, b) = (0.8, 1.0);
    let tube = FiniteTube::new(a, b, &svk).unwrap();
    let s = tube.solve(&load(Axial::Force(0.4), Torsion::Torque(0.0), 0.05), &SolveOptions::default()).unwrap();
    let vol = (s.deformed_outer_radius.powi(2) - s.deformed_inner_radius.powi(2)) * s.stretch;
    assert!((vol - (b * b - a * a)).abs() < 1e-13, "{vol}");
    assert!(s.torque.abs() < 1e-12 && (s.applied_force - 0.4).abs() < 1e-12);
}

/// The solid cylinder is the A → 0 limit of the hollow one: the resultants
/// differ by O(A²) (a regular field loses an O(A²) core), so halving A
/// divides the difference by about 4.
#[test]
fn solid_cylinder_is_the_limit_of_a_thin_hole() {
    let nh = NeoHookean { shear_modulus: 1.0, lame_lambda: 3.0, incompressible: false };
    let loading = load(Axial::Stretch(1.3), Torsion::Twist(0.8), 0.0);
    let solid = FiniteTube::new(0.0, 1.0, &nh).unwrap().solve(&loading, &SolveOptions::default()).unwrap();
    assert_eq!(solid.deformed_inner_radius, 0.0);
    let diffs: Vec<f64> = [0.04, 0.02, 0.01]
        .iter()
        .map(|&a| {
            let h = FiniteTube::new(a, 1.0, &nh).unwrap().solve(&loading, &SolveOptions::default()).unwrap();
            (h.wall_force - solid.wall_force).abs() / solid.wall_force.abs()
                + (h.torque - solid.torque).abs() / solid.torque.abs()
        })
        .collect();
    for w in diffs.windows(2) {
        let rate = (w[0] / w[1]).log2();
        assert!(rate > 1.8, "differences {diffs:?}: rate {rate}");
    }
    assert!(diffs[2] < 1e-3, "{diffs:?}");
}

/// Compressible neo-Hookean converges to the incompressible law as λ_L/μ → ∞
/// (§1.3), the difference falling like μ/λ_L.
#[test]
fn compressible_neo_hookean_tends_to_incompressible() {
    let loading = Loading {
        axial: Axial::Stretch(1.5),
        torsion: Torsion::Twist(0.6),
        inner_pressure: 0.2,
        outer_pressure: 0.0,
        ends: Ends::Closed,
    };
    let inc = NeoHookean { shear_modulus: 1.0, lame_lambda: 0.0, incompressible: true };
    let reference = FiniteTube::new(0.5, 1.0, &inc).unwrap().solve(&loading, &SolveOptions::default()).unwrap();
    let mut last = f64::INFINITY;
    for ratio in [1e2, 1e3, 1e4] {
        let nh = NeoHookean { shear_modulus: 1.0, lame_lambda: ratio, incompressible: false };
        let s = FiniteTube::new(0.5, 1.0, &nh).unwrap().solve(&loading, &SolveOptions::default()).unwrap();
        let diff = (s.applied_force - reference.applied_force).abs() / reference.applied_force.abs()
            + (s.deformed_inner_radius - reference.deformed_inner_radius).abs();
        assert!(diff < 20.0 / ratio, "λ/μ = {ratio:e}: difference {diff:e}");
        assert!(diff < 0.2 * last, "not converging: {diff:e} after {last:e}");
        last = diff;
    }
}

/// Prescribing the force found at a prescribed stretch returns that stretch
/// (and the same for torque and twist), closed ends with pressure.
#[test]
fn force_and_torque_control_invert_stretch_and_twist_control() {
    let svk = SaintVenantKirchhoff::new(helical(), 1.7, false);
    let tube = FiniteTube::new(0.6, 1.4, &svk).unwrap();
    let mut l = load(Axial::Stretch(1.15), Torsion::Twist(0.2), 0.1);
    l.ends = Ends::Closed;
    let direct = tube.solve(&l, &SolveOptions::default()).unwrap();
    let mut inv = l;
    inv.axial = Axial::Force(direct.applied_force);
    inv.torsion = Torsion::Torque(direct.torque);
    let back = tube.solve(&inv, &SolveOptions::default()).unwrap();
    assert!((back.stretch - 1.15).abs() < 1e-9 && (back.twist - 0.2).abs() < 1e-9, "{} {}", back.stretch, back.twist);
    let caps = PI * direct.deformed_inner_radius.powi(2) * 0.1;
    assert!((direct.wall_force - direct.applied_force - caps).abs() < 1e-12 * direct.wall_force.abs());
}

#[test]
fn svk_in_strong_compression_is_a_clear_status() {
    let svk = SaintVenantKirchhoff::new(Orthotropic::isotropic(1.0, 0.3).unwrap(), 0.0, false);
    let tube = FiniteTube::new(0.5, 1.0, &svk).unwrap();
    let e = tube.solve(&load(Axial::Stretch(0.3), Torsion::Twist(0.0), 0.0), &SolveOptions::default()).unwrap_err();
    assert!(matches!(e.status, Status::ErrMaterialInstability | Status::ErrNotConverged), "{e}");
    assert!(!e.message.is_empty());
}

/// A sweep returns the same states as independent solves (reference: each
/// point solved from rest on the same grid), and can be cancelled.
#[test]
fn sweep_matches_independent_solves_and_cancels() {
    let svk = SaintVenantKirchhoff::new(helical(), 1.7, false);
    let tube = FiniteTube::new(0.6, 1.4, &svk).unwrap();
    let loadings: Vec<Loading> = (0..=20).map(|i| Loading::torsion_free_stretch(1.0 + 0.01 * i as f64)).collect();
    let sweep = tube.sweep(&loadings, &SolveOptions::default(), |_, _| true).unwrap();
    assert!(!sweep.cancelled && sweep.states.len() == 21);
    let n = sweep.states[0].intervals;
    for (l, s) in loadings.iter().zip(&sweep.states).step_by(5) {
        let direct = tube.solve(l, &SolveOptions { rel_tol: 1e-10, intervals: Some(n) }).unwrap();
        assert!(
            (direct.twist - s.twist).abs() < 1e-11
                && (direct.deformed_outer_radius - s.deformed_outer_radius).abs() < 1e-11
        );
        assert!(s.torque.abs() < 1e-10, "torque-free: T = {}", s.torque);
    }
    // The helical wall twists monotonically under torque-free stretching here.
    assert!(sweep.states.windows(2).all(|w| (w[1].twist - w[0].twist) * (sweep.states[20].twist) > 0.0));
    let mut seen = 0;
    let cut = tube
        .sweep(&loadings, &SolveOptions::default(), |i, _| {
            seen = i;
            i < 2
        })
        .unwrap();
    assert!(cut.cancelled && cut.states.len() == 3 && seen == 2);
    let mixed = [Loading::torsion_free_stretch(1.1), Loading::inflation(0.1, Axial::Force(0.0), Ends::Closed)];
    assert_eq!(tube.sweep(&mixed, &SolveOptions::default(), |_, _| true).unwrap_err().status, Status::ErrOutOfRange);
}

/// Incompressible neo-Hookean tube stretched with free surfaces deforms
/// homogeneously (exact): r = R/√λ, ψ = 0, F = πμ(B² − A²)(λ − 1/λ²).
#[test]
fn neo_hookean_stretch_sweep_is_homogeneous() {
    let nh = NeoHookean { shear_modulus: 2.0, lame_lambda: 0.0, incompressible: true };
    let (a, b) = (0.5, 1.0);
    let tube = FiniteTube::new(a, b, &nh).unwrap();
    let loadings: Vec<Loading> = (0..=10).map(|i| Loading::torsion_free_stretch(1.0 + 0.2 * i as f64)).collect();
    let sweep = tube.sweep(&loadings, &SolveOptions::default(), |_, _| true).unwrap();
    for s in &sweep.states {
        let l = s.stretch;
        assert!((s.deformed_outer_radius - b / l.sqrt()).abs() < 1e-12, "λ {l}");
        assert!((s.deformed_inner_radius - a / l.sqrt()).abs() < 1e-12);
        assert!(s.twist.abs() < 1e-12);
        let f = PI * 2.0 * (b * b - a * a) * (l - 1.0 / (l * l));
        assert!((s.applied_force - f).abs() < 1e-11 * f.abs().max(1.0), "λ {l}: F {} vs {f}", s.applied_force);
    }
}

/// Pressure sweeps with and without axial restraint (closed ends): the free
/// tube lengthens under the cap load, the restrained one does not, and the
/// restrained one needs the axial force the caps would otherwise supply.
#[test]
fn inflation_sweeps_with_and_without_axial_restraint() {
    let nh = NeoHookean { shear_modulus: 1.0, lame_lambda: 10.0, incompressible: false };
    let tube = FiniteTube::new(0.8, 1.0, &nh).unwrap();
    let pressures: Vec<f64> = (0..=8).map(|i| 0.02 * i as f64).collect();
    let free: Vec<Loading> =
        pressures.iter().map(|&p| Loading::inflation(p, Axial::Force(0.0), Ends::Closed)).collect();
    let held: Vec<Loading> =
        pressures.iter().map(|&p| Loading::inflation(p, Axial::Stretch(1.0), Ends::Closed)).collect();
    let free = tube.sweep(&free, &SolveOptions::default(), |_, _| true).unwrap().states;
    let held = tube.sweep(&held, &SolveOptions::default(), |_, _| true).unwrap().states;
    for (f, h) in free.iter().zip(&held).skip(1) {
        assert!(f.stretch > 1.0 && (h.stretch - 1.0).abs() < 1e-15);
        assert!(f.applied_force.abs() < 1e-10);
        // Closed ends: the wall of the free tube carries the cap load πa²p.
        let caps = PI * f.deformed_inner_radius.powi(2) * f.inner_pressure;
        assert!((f.wall_force - caps).abs() < 1e-10 * caps);
        assert!(f.deformed_inner_radius > free[0].deformed_inner_radius);
    }
}

/// A fibre family that turns on inside the wall (I4 = 1 at an interior
/// radius; helix angle 55°→61° through the wall with τ0 = 1.8, stretched
/// 1.2 at zero torque): the stress is only C⁰ there. With breakpoints at the
/// switch radii the solver stays spectral. References: the law itself
/// (I4 = 1 at every reported switch radius), and a converged finer solution
/// (140 fixed intervals on the same pieces) for the error of the adaptive
/// answer, which must lie within its own two-grid estimate (×10 margin).
/// Independently, tests/sundials_tube.rs checks the state against IDA.
#[test]
fn fibre_switch_inside_the_wall_is_resolved() {
    use rodkit::tube::material::{FibreAngle, FibreFamily, FibreReinforced, WallMaterial, WallStrain};
    for incompressible in [false, true] {
        let fam = |hand: f64, k1: f64| FibreFamily { angle: FibreAngle::Helix { hand }, k1, k2: 0.8 };
        let material = FibreReinforced {
            matrix: NeoHookean { shear_modulus: 0.3, lame_lambda: 3.0, incompressible },
            families: vec![fam(1.0, 2.3), fam(-1.0, 1.2)],
            intrinsic_twist: 1.8,
        };
        let tube = FiniteTube::new(0.8, 1.0, &material).unwrap();
        let loading = load(Axial::Stretch(1.2), Torsion::Torque(0.0), 0.0);
        let reference = tube.solve(&loading, &SolveOptions { rel_tol: 1e-10, intervals: Some(140) }).unwrap();
        for tol in [1e-6, 1e-9, 1e-12] {
            let s = tube.solve(&loading, &SolveOptions { rel_tol: tol, intervals: None }).unwrap();
            assert!(!s.switch_radii.is_empty(), "incompressible {incompressible}: no switch found");
            assert!(
                s.intervals <= 80,
                "incompressible {incompressible}, tol {tol:e}: {} intervals (not spectral)",
                s.intervals
            );
            // Every switch radius is a zero of some family's I4 − 1.
            let p = &s.profile;
            for &rs in &s.switch_radii {
                let j = p.reference_radius.iter().position(|&x| x == rs).expect("switch radius is a node");
                let strain =
                    WallStrain { radial: 1.0, hoop: p.radius[j] / rs, axial: s.stretch, shear: p.radius[j] * s.twist };
                let c = strain.right_cauchy_green();
                let g = (0..2).map(|k| material.switch_value(k, rs, &c).abs()).fold(f64::INFINITY, f64::min);
                assert!(g < 1e-9, "I4 − 1 = {g:e} at the switch radius {rs}");
            }
            let err = ((s.twist - reference.twist) * 1.0)
                .abs()
                .max((s.deformed_outer_radius - reference.deformed_outer_radius).abs())
                .max((s.wall_force - reference.wall_force).abs() / (0.3 * PI));
            assert!(
                err <= (10.0 * s.error_estimate).max(1e-12),
                "incompressible {incompressible}, tol {tol:e}: error {err:e}, estimate {:e}",
                s.error_estimate
            );
            assert!(err <= 10.0 * tol, "incompressible {incompressible}, tol {tol:e}: error {err:e}");
        }
    }
}

/// The stability check near fibre activation. Reference: the HGO law is
/// polyconvex (Holzapfel, Gasser & Ogden 2000), and at this state (found by
/// benches/tube_search.rs, probe [1]) the energy's Hessian in (r', r/R, λ,
/// rψ) is positive definite by differences that do not cross I4 = 1
/// (eigenvalues ≈ 1.2…24 with h = 1e−5 and 1e−3). Differences with h = 1e−4
/// straddle the switch of family 1 and gave a spurious negative eigenvalue
/// (−7.7), so solves on 24–48 intervals stopped with
/// ErrMaterialInstability at the first stretch increment.
#[test]
fn fibre_activation_is_not_taken_for_instability() {
    use rodkit::tube::material::{FibreAngle, FibreFamily, FibreReinforced};
    let material = FibreReinforced {
        matrix: NeoHookean { shear_modulus: 1.0, lame_lambda: 5.855910559423526, incompressible: false },
        families: vec![
            FibreFamily { angle: FibreAngle::Helix { hand: 1.0 }, k1: 2.6088376707683727, k2: 21.002361248274067 },
            FibreFamily { angle: FibreAngle::Helix { hand: -1.0 }, k1: 151.91698839742577, k2: 0.20165343980056927 },
        ],
        intrinsic_twist: 0.49026229463897925,
    };
    let tube = FiniteTube::new(0.3212767093624407, 1.0, &material).unwrap();
    let loadings: Vec<Loading> = (1..=8).map(|i| Loading::torsion_free_stretch(1.0 + 0.0025 * i as f64)).collect();
    for n in [24, 32, 48] {
        let sweep = tube.sweep(&loadings, &SolveOptions { rel_tol: 1e-8, intervals: Some(n) }, |_, _| true);
        let states = sweep.unwrap_or_else(|e| panic!("n = {n}: {:?} {}", e.status, e.message)).states;
        assert_eq!(states.len(), 8);
    }
    // Still a real check: SVK in strong compression is flagged (physics.md §1.3).
    let svk = SaintVenantKirchhoff::new(Orthotropic::isotropic(1.0, 0.3).unwrap(), 0.0, false);
    let tube = FiniteTube::new(0.5, 1.0, &svk).unwrap();
    let err = tube.solve(&load(Axial::Stretch(0.45), Torsion::Twist(0.0), 0.0), &SolveOptions::default()).unwrap_err();
    assert_eq!(err.status, Status::ErrMaterialInstability);
}

/// The two-grid estimate against the true error (reference: the same solve
/// on a fixed 96-interval grid, converged to round-off), for loose and tight tolerances, a thick helical SVK
/// wall under stretch, torque and pressure. The answer must meet the
/// tolerance, and the estimate must not understate the error by more than
/// 10× (it usually overstates it: the coarser grid's error is reported).
#[test]
fn finite_error_estimate_tracks_true_error() {
    for incompressible in [false, true] {
        let svk = SaintVenantKirchhoff::new(helical(), 1.7, incompressible);
        let tube = FiniteTube::new(0.3, 1.4, &svk).unwrap();
        let loading = load(Axial::Stretch(1.15), Torsion::Torque(0.05), 0.02);
        let reference = tube.solve(&loading, &SolveOptions { rel_tol: 1e-13, intervals: Some(96) }).unwrap();
        let b = 1.4;
        for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
            let s = tube.solve(&loading, &SolveOptions { rel_tol: tol, intervals: None }).unwrap();
            let err = ((s.twist - reference.twist) * b)
                .abs()
                .max((s.deformed_outer_radius - reference.deformed_outer_radius).abs() / b)
                .max((s.deformed_inner_radius - reference.deformed_inner_radius).abs() / b);
            assert!(s.error_estimate <= tol, "inc {incompressible} tol {tol:e}: estimate {:e}", s.error_estimate);
            assert!(
                err <= tol && err <= 10.0 * s.error_estimate.max(1e-14),
                "inc {incompressible} tol {tol:e}: true {err:e}, estimate {:e}, n {}",
                s.error_estimate,
                s.intervals
            );
        }
    }
}

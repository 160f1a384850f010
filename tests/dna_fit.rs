//! The DNA wall fit of physics.md §1.5 against independent references:
//! the thin-tube model itself (ThinTube, which goes through Q̄ = TᵀQT and a
//! Schur complement, not through the fit's compliance expansion), known
//! constants recovered by a round trip, the exact t-scaling of the membrane
//! stiffness, mirror symmetry, the free-rod closed form dψ/dF = −g/(SC − g²),
//! the isotropic thick-tube closed forms (Lamé) and thick → thin convergence.
//! Units: pN, nm.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rodkit::tube::dna::{
    fit_family, fit_thin_wall, helix_angle_from_pitch, thick_comparison, DnaTargets, OutOfPlane, DNA_HELIX_ANGLE,
    DNA_MID_RADIUS, REL_TOL,
};
use rodkit::tube::{OrthotropicSurface, StretchTwist, ThinTube, Winding};
use rodkit::Status;
use std::f64::consts::PI;

const R: f64 = DNA_MID_RADIUS;
const ALPHA: f64 = DNA_HELIX_ANGLE;

fn rel(x: f64, y: f64) -> f64 {
    (x - y).abs() / y.abs()
}

/// (S, C, g) of a thin tube, straight from ThinTube.
fn thin_law(r: f64, t: f64, alpha: f64, mat: OrthotropicSurface) -> StretchTwist {
    ThinTube::new(r, t, alpha.tan() / r, mat).unwrap().coupling_stiffness().unwrap().stretch_twist()
}

/// Recompute S, C, g with ThinTube from the fitted constants alone (a fresh
/// OrthotropicSurface built from the four numbers) and compare to the targets.
/// Tolerance 1e-10 relative: the fit converges to REL_TOL = 1e-12 in the
/// moduli and the maps involved have condition numbers ≲ 10.
#[test]
fn fit_reproduces_targets() {
    let targets = DnaTargets::literature();
    for t in [0.1, 0.4, 1.0] {
        for nu in [-0.1, 0.0, 0.2, 0.3, 0.5, 1.0] {
            let fit = fit_thin_wall(targets, R, ALPHA, t, nu).unwrap();
            let m = fit.material;
            assert_eq!(m.nu12, nu);
            let mat = OrthotropicSurface::new(m.e1, m.e2, m.nu12, m.g12).unwrap();
            let law = thin_law(R, t, ALPHA, mat);
            assert!(rel(law.stretch, targets.stretch) < 1e-10, "t {t} nu {nu}: S {}", law.stretch);
            assert!(rel(law.twist, targets.twist) < 1e-10, "t {t} nu {nu}: C {}", law.twist);
            assert!(rel(law.coupling, targets.coupling) < 1e-10, "t {t} nu {nu}: g {}", law.coupling);
            // The reported achieved values are the same numbers.
            assert!(rel(fit.achieved.coupling, law.coupling) < 1e-14);
            // Linear map, exact Jacobian: one step to the solution, one to confirm.
            assert!(fit.iterations <= 3 && fit.last_step <= REL_TOL, "iterations {}", fit.iterations);
            // Free rod (T = 0): dψ/dF = −g/(SC − g²) (invert [[S,g],[g,C]]).
            let rate = -targets.coupling / (targets.stretch * targets.twist - targets.coupling.powi(2));
            assert!(rel(fit.response.dtwist_dforce, rate) < 1e-10, "{} vs {rate}", fit.response.dtwist_dforce);
            // Conversions by hand: 10 kbp = 3400 nm of contour; 0.34 nm per bp.
            assert!(rel(fit.twist_rate.turns_per_pn_per_10kbp, rate * 3400.0 / (2.0 * PI)) < 1e-10);
            assert!(rel(fit.twist_rate.degrees_per_pn_per_bp, rate * 0.34 * 180.0 / PI) < 1e-10);
        }
    }
}

/// Known constants → (S, C, g) by ThinTube → fit → the same constants.
/// Reference: the constants we started from. Tolerance 1e-9 relative.
#[test]
fn round_trip_recovers_known_constants() {
    let (t, nu) = (0.4, 0.3);
    let known = OrthotropicSurface::new(800.0, 300.0, nu, 100.0).unwrap();
    let targets = DnaTargets::from(thin_law(R, t, ALPHA, known));
    let fit = fit_thin_wall(targets, R, ALPHA, t, nu).unwrap();
    println!("round trip: {targets:?} -> {:?} in {} iterations", fit.material, fit.iterations);
    assert!(rel(fit.material.e1, known.e1) < 1e-9, "{:?}", fit.material);
    assert!(rel(fit.material.e2, known.e2) < 1e-9, "{:?}", fit.material);
    assert!(rel(fit.material.g12, known.g12) < 1e-9, "{:?}", fit.material);

    // Random materials, angles of either hand, radii and thicknesses, away
    // from the degenerate ν12 = −cot²α (det 2mn³(m² + ν12 n²)).
    let mut rng = ChaCha8Rng::seed_from_u64(51);
    let mut checked = 0;
    while checked < 300 {
        let e1 = 10f64.powf(rng.random_range(-1.0..3.0));
        let e2 = e1 * 10f64.powf(rng.random_range(-1.0..1.0));
        let g12 = e1 * 10f64.powf(rng.random_range(-1.0..0.3));
        let nu = rng.random_range(-0.9..0.9) * (e1 / e2).sqrt();
        let alpha = rng.random_range(0.2..1.4) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
        let (n, m) = f64::sin_cos(alpha);
        if (m * m + nu * n * n).abs() < 0.1 * (m * m + nu.abs() * n * n) {
            continue;
        }
        let Ok(mat) = OrthotropicSurface::new(e1, e2, nu, g12) else { continue };
        let r = rng.random_range(0.5..2.0);
        let t = r * rng.random_range(0.01..1.0);
        let fit = fit_thin_wall(DnaTargets::from(thin_law(r, t, alpha, mat)), r, alpha, t, nu).unwrap();
        for (got, want) in [(fit.material.e1, e1), (fit.material.e2, e2), (fit.material.g12, g12)] {
            assert!(rel(got, want) < 1e-9, "alpha {alpha} {mat:?} -> {:?}", fit.material);
        }
        checked += 1;
    }
}

/// K = 2πRt·P Q̄ Pᵀ: at fixed targets the product t·Q is fixed, so doubling
/// t halves every modulus (ν12 fixed). Reference: that formula. 1e-10.
#[test]
fn moduli_scale_inversely_with_thickness() {
    for nu in [0.0, 0.3, 0.5] {
        for t in [0.05, 0.2, 0.4] {
            let a = fit_thin_wall(DnaTargets::literature(), R, ALPHA, t, nu).unwrap().material;
            let b = fit_thin_wall(DnaTargets::literature(), R, ALPHA, 2.0 * t, nu).unwrap().material;
            for (x, y) in [(a.e1, b.e1), (a.e2, b.e2), (a.g12, b.g12)] {
                assert!((x / y - 2.0).abs() < 1e-10, "t {t} nu {nu}: {a:?} vs {b:?}");
            }
        }
    }
}

/// The DNA fit at t/R = 0.4 with the literature targets, over ν12.
/// Existence: the fit is unique (det ≠ 0), so it either is physical or no
/// physical fit exists. References for the failures: an independent
/// Cramer's-rule solution of the same thin-wall equations, done in Python
/// while writing this test (not with this code): at 60°, t = 0.4,
/// ν12 = −0.5 → E1 = −122.96; ν12 = −0.3 → G12 = −22.617; ν12 = 2 →
/// E1 = 1615, E2 = 570, ν12² E2/E1 = 1.41 > 1; ν12 = −1/3 = −cot²60°
/// makes the system singular. Overwinding: τ0 > 0 (right-handed) and
/// g = −90 < 0, so sign(τ0)·g < 0 ⇒ overwinds (physics.md §1.4), and
/// dψ/dF = −g/(SC − g²) > 0.
#[test]
fn dna_fit_at_t_over_r_0_4() {
    let targets = DnaTargets::literature();
    let t = 0.4;
    let nus = [-0.5, -1.0 / 3.0, -0.3, -0.1, 0.0, 0.2, 0.3, 0.4, 0.5, 1.0, 1.5, 2.0];
    println!("DNA thin-wall fit, R = {R} nm, alpha = 60 deg, S = 1100 pN, C = 440 pN nm^2, g = -90 pN nm");
    println!(
        "{:>5} {:>7} {:>10} {:>10} {:>10} {:>8} {:>14} {:>14}",
        "t", "nu12", "E1", "E2", "G12", "E2/E1", "turns/pN/10kbp", "deg/pN/bp"
    );
    for (tt, nu, res) in fit_family(targets, R, ALPHA, &[t], &nus) {
        assert_eq!(tt, t);
        match res {
            Ok(fit) => {
                let m = fit.material;
                println!(
                    "{tt:5.2} {nu:7.3} {:10.3} {:10.3} {:10.3} {:8.4} {:14.6} {:14.6}",
                    m.e1,
                    m.e2,
                    m.g12,
                    m.e2 / m.e1,
                    fit.twist_rate.turns_per_pn_per_10kbp,
                    fit.twist_rate.degrees_per_pn_per_bp
                );
                assert!((-0.16..1.6).contains(&nu), "nu12 = {nu}: unexpected physical fit {m:?}");
                assert!(fit.intrinsic_twist > 0.0);
                assert_eq!(fit.response.winding, Winding::Overwinds);
                assert!(fit.overwinds && fit.response.dtwist_dforce > 0.0);
                assert!(rel(fit.achieved.stretch, 1100.0) < 1e-10);
                assert!(rel(fit.achieved.twist, 440.0) < 1e-10);
                assert!(rel(fit.achieved.coupling, -90.0) < 1e-10);
                assert!(m.e1.is_finite() && m.e2.is_finite() && m.g12.is_finite());
            }
            Err(e) => {
                println!("{tt:5.2} {nu:7.3}   no fit: {:?}: {}", e.status, e.message);
                let (status, names) = if nu == -1.0 / 3.0 {
                    (Status::ErrOutOfRange, "cot^2")
                } else if nu == -0.5 {
                    (Status::ErrNotPositiveDefinite, "E1 =")
                } else if nu == -0.3 {
                    (Status::ErrNotPositiveDefinite, "G12 =")
                } else if nu == 2.0 {
                    (Status::ErrNotPositiveDefinite, "nu12^2 < E1/E2")
                } else {
                    panic!("nu12 = {nu}: expected a physical fit, got {e}");
                };
                assert_eq!(e.status, status, "nu12 = {nu}: {e}");
                assert!(e.message.contains(names), "nu12 = {nu}: {}", e.message);
                assert!(!e.message.contains("NaN"));
            }
        }
    }
    // The physical ν12 window, located by bisection on the outcome (printed
    // for the record; asserted only against the Python scan, ±0.01).
    let ok = |nu: f64| fit_thin_wall(targets, R, ALPHA, t, nu).is_ok();
    let bisect = |mut bad: f64, mut good: f64| {
        for _ in 0..50 {
            let mid = 0.5 * (bad + good);
            if ok(mid) {
                good = mid
            } else {
                bad = mid
            }
        }
        good
    };
    let (lo, hi) = (bisect(-0.3, 0.0), bisect(2.0, 1.0));
    println!("physical nu12 window at 60 deg: ({lo:.5}, {hi:.5})");
    assert!((lo + 0.1525).abs() < 0.01 && (hi - 1.5875).abs() < 0.01, "({lo}, {hi})");
}

/// Mirror image (exact symmetry, physics.md §1.1: τ0 → −τ0 flips the sign of
/// the twist couplings and nothing else): the fit at (−α, −g) is the fit at
/// (α, g), and since sign(τ0)·g is unchanged it still overwinds; at (−α, g)
/// the same g on a left-handed wall unwinds.
#[test]
fn mirror_image_fits() {
    let dna = DnaTargets::literature();
    let right = fit_thin_wall(dna, R, ALPHA, 0.4, 0.3).unwrap();
    let mirror = fit_thin_wall(DnaTargets { coupling: 90.0, ..dna }, R, -ALPHA, 0.4, 0.3).unwrap();
    for (x, y) in [
        (right.material.e1, mirror.material.e1),
        (right.material.e2, mirror.material.e2),
        (right.material.g12, mirror.material.g12),
    ] {
        assert!(rel(x, y) < 1e-12, "{:?} vs {:?}", right.material, mirror.material);
    }
    assert!(mirror.overwinds && mirror.response.dtwist_dforce < 0.0);
    let left = fit_thin_wall(dna, R, -ALPHA, 0.4, 0.3).unwrap();
    assert_eq!(left.response.winding, Winding::Unwinds);
}

#[test]
fn invalid_arguments_give_clear_statuses() {
    let dna = DnaTargets::literature();
    let status = |r: rodkit::Result<_>| r.map(|_: rodkit::tube::dna::FitResult| ()).unwrap_err().status;
    assert_eq!(status(fit_thin_wall(dna, R, 0.0, 0.4, 0.3)), Status::ErrOutOfRange);
    assert_eq!(status(fit_thin_wall(dna, R, PI / 2.0, 0.4, 0.3)), Status::ErrOutOfRange);
    assert_eq!(status(fit_thin_wall(dna, R, ALPHA, 2.0, 0.3)), Status::ErrInvalidGeometry);
    assert_eq!(status(fit_thin_wall(dna, R, ALPHA, -0.4, 0.3)), Status::ErrNotPositive);
    assert_eq!(status(fit_thin_wall(dna, R, f64::NAN, 0.4, 0.3)), Status::ErrNotFinite);
    // g² ≥ SC: no stable rod, let alone a wall.
    let e = DnaTargets::new(1100.0, 440.0, 700.0).unwrap_err();
    assert_eq!(e.status, Status::ErrNotPositiveDefinite);
    assert_eq!(
        status(fit_thin_wall(DnaTargets { coupling: 700.0, ..dna }, R, ALPHA, 0.4, 0.3)),
        Status::ErrNotPositiveDefinite
    );
    // Pitch → angle: tan α = 2πR/p; 3.4 nm and 3.6 nm at R = 1 nm.
    assert!((helix_angle_from_pitch(1.0, 3.4).to_degrees() - 61.58).abs() < 0.01);
    assert!((helix_angle_from_pitch(1.0, 3.6).to_degrees() - 60.19).abs() < 0.01);
}

/// Isotropic wall through the whole chain. Targets S = 2πRtE, C = 2πR³tG,
/// g = 0 (thin isotropic closed forms) must fit back to (E, E, ν, E/(2(1+ν)))
/// by uniqueness; the default completion is then the isotropic 3-D material,
/// and the thick tube has, by the generalized-plane-strain Lamé solution
/// (σ_RR = σ_ΘΘ = 0 under free stretch), S = Eπ(B² − A²) = 2πRtE exactly and
/// C = Gπ(B⁴ − A⁴)/2 = 2πR³tG(1 + t²/(4R²)), g = 0. Tolerance 1e-9.
#[test]
fn isotropic_wall_thick_comparison_matches_lame() {
    let (e, nu, t) = (500.0, 0.3, 0.4);
    let g = e / (2.0 * (1.0 + nu));
    let targets = DnaTargets::new(2.0 * PI * R * t * e, 2.0 * PI * R.powi(3) * t * g, 0.0).unwrap();
    let fit = fit_thin_wall(targets, R, ALPHA, t, nu).unwrap();
    assert!(
        rel(fit.material.e1, e) < 1e-10 && rel(fit.material.e2, e) < 1e-10 && rel(fit.material.g12, g) < 1e-10,
        "{:?}",
        fit.material
    );
    assert_eq!(fit.response.winding, Winding::Neither);
    let cmp = thick_comparison(&fit, OutOfPlane::default_for(&fit.material)).unwrap();
    let iso = rodkit::tube::Orthotropic::isotropic(e, nu).unwrap();
    for (a, b) in [
        (cmp.material.e3, iso.e3),
        (cmp.material.nu23, iso.nu23),
        (cmp.material.g23, iso.g23),
        (cmp.material.g13, iso.g13),
    ] {
        assert!(rel(a, b) < 1e-12, "{:?}", cmp.material);
    }
    println!("isotropic thick vs thin at t/R = 0.4: {:?}", cmp.relative_difference);
    assert!(cmp.relative_difference.stretch.abs() < 1e-9);
    assert!((cmp.relative_difference.twist - t * t / (4.0 * R * R)).abs() < 1e-9);
    assert!(cmp.relative_difference.coupling.abs() < 1e-9);
}

/// The DNA fit as a thick wall at t/R = 0.4 (default completion). The size
/// of the difference is measured (printed), not predicted: asserted only to
/// be finite and below 100%, with a converged thick solve. Then thick → thin
/// as t/R → 0 (refitting at each t so the thin law stays on target): within
/// 3% at t/R = 0.01, and converging at rate ≥ 1.9 in t/R. Why 2 and not
/// the rate 1 of physics.md §1.4: the O(t/R) of the individual K entries
/// comes from reporting the hoop strain at the inner rather than the mid
/// radius, and the condensed law at p = 0 does not depend on that choice;
/// what is left is the midpoint-rule error of replacing ∫_A^B (…) dr by
/// t·(…)(R), plus the through-thickness σ_RR that vanishes on both faces,
/// both O((t/R)²) relative. Measured: 2.000.
#[test]
fn thick_versus_thin() {
    let dna = DnaTargets::literature();
    for nu in [-0.1, 0.0, 0.2, 0.3, 0.4, 0.5, 1.0] {
        let fit = fit_thin_wall(dna, R, ALPHA, 0.4, nu).unwrap();
        // Transversely isotropic material (E3 = E2, ν13 = ν12, ν23): positive
        // definite iff ν23 > −1 and 1 − ν23 − 2ν12²E2/E1 > 0 (Lempriere 1968:
        // |ν_ij| < √(E_i/E_j) and 1 − ν12ν21 − ν23ν32 − ν13ν31 − 2ν21ν32ν13 > 0,
        // which factors as (1 + ν23)(1 − ν23 − 2ν12ν21)); here ν23 = ν12.
        let m = fit.material;
        let pd = nu > -1.0 && 1.0 - nu - 2.0 * nu * nu * m.e2 / m.e1 > 0.0;
        let result = thick_comparison(&fit, OutOfPlane::default_for(&fit.material));
        assert_eq!(result.is_ok(), pd, "nu12 {nu}: {result:?}");
        match result {
            Ok(cmp) => {
                let d = cmp.relative_difference;
                println!(
                    "t/R 0.4 nu12 {nu}: thick S {:.2} C {:.2} g {:.3} | rel diff S {:+.4} C {:+.4} g {:+.4} | thick {:.5} turns/pN/10kbp ({:?}), est {:.1e}, {} intervals",
                    cmp.thick.stretch, cmp.thick.twist, cmp.thick.coupling, d.stretch, d.twist, d.coupling,
                    cmp.thick_twist_rate.turns_per_pn_per_10kbp, cmp.thick_response.winding, cmp.thick_error_estimate, cmp.intervals
                );
                assert!(cmp.thick_error_estimate <= 1e-10);
                for x in [d.stretch, d.twist, d.coupling] {
                    assert!(x.is_finite() && x.abs() < 1.0, "{d:?}");
                }
            }
            Err(e) => {
                println!("t/R 0.4 nu12 {nu}: no 3-D completion: {e}");
                assert_eq!(e.status, Status::ErrNotPositiveDefinite);
            }
        }
    }

    let nu = 0.3;
    let mut prev: Option<(f64, f64)> = None;
    for t_over_r in [0.04, 0.02, 0.01, 0.005] {
        let fit = fit_thin_wall(dna, R, ALPHA, t_over_r * R, nu).unwrap();
        let cmp = thick_comparison(&fit, OutOfPlane::default_for(&fit.material)).unwrap();
        let d = cmp.relative_difference;
        let worst = d.stretch.abs().max(d.twist.abs()).max(d.coupling.abs());
        println!("t/R {t_over_r}: rel diff S {:+.3e} C {:+.3e} g {:+.3e}", d.stretch, d.twist, d.coupling);
        if t_over_r == 0.01 {
            assert!(worst < 0.03, "{d:?}");
        }
        if let Some((tp, wp)) = prev {
            let rate = (wp / worst).ln() / (tp / t_over_r).ln();
            println!("  rate {rate:.3}");
            assert!(rate >= 1.9, "rate {rate}");
        }
        prev = Some((t_over_r, worst));
    }
}

//! The end loop's thermal correction (src/tweezers/loop_fluct.rs): the
//! discrete loop against the closed-form homoclinic, its spectrum against
//! the symmetries, and the shipped table against direct computation.

use rodkit::tweezers::loop_fluct::{fluctuation, table_csv, table_row, LnG, M_MAX, M_MIN};

/// Writes the shipped table src/tweezers/loop_fluct.csv (about 10 s).
#[test]
#[ignore]
fn regenerate_loop_table() {
    let csv = table_csv().unwrap();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/tweezers/loop_fluct.csv");
    std::fs::write(path, csv).unwrap();
}

/// The discrete loop converges at second order to the closed-form
/// homoclinic loop of a rod under tension and torque (Thompson & Champneys,
/// Proc. R. Soc. A 452, 117 (1996)): grand energy 8√(1 − m²) − 8m arccos m
/// and writhe (2/π) arccos m in units √(K_b F). Measured errors at m = 0.5:
/// 7.7e-4 and 1.9e-4 (energy) at h = 0.02, 0.01; the bounds allow 30 %.
#[test]
fn discrete_loop_is_the_homoclinic_loop() {
    for m in [0.3f64, 0.5, 0.8] {
        let k = (1.0 - m * m).sqrt();
        let (e, w) = (8.0 * k - 8.0 * m * m.acos(), 2.0 / std::f64::consts::PI * m.acos());
        let a = fluctuation(m, 0.02, 24.0 / k).unwrap();
        let b = fluctuation(m, 0.01, 24.0 / k).unwrap();
        let (ea, eb) = ((a.energy - e).abs(), (b.energy - e).abs());
        let (wa, wb) = ((a.writhe - w).abs(), (b.writhe - w).abs());
        assert!(eb < 1.3 * 1.9e-4 * (1.0 + 8.0 * (0.5 - m).abs()), "m {m}: energy error {eb:e}");
        assert!((ea / eb - 4.0).abs() < 0.4, "m {m}: energy order {}", (ea / eb).log2());
        assert!((wa / wb - 4.0).abs() < 0.4, "m {m}: writhe order {}", (wa / wb).log2());
    }
}

/// The spectrum the correction rests on: the two zero modes (translation
/// along the chain, rotation about the force) are zero to rounding, the
/// loop at fixed torque is a nucleus with exactly one unstable direction
/// (Sylvester's inertia of the block LDLᵀ), and the kept spectrum is
/// positive. Reference: the symmetries of (1) and the saddle character of
/// the homoclinic at fixed torque.
#[test]
fn loop_spectrum_has_two_zero_modes_and_one_growth_mode() {
    for m in [0.2f64, 0.45, 0.7, 0.95] {
        let k = (1.0 - m * m).sqrt();
        let f = fluctuation(m, 0.02, 24.0 / k).unwrap();
        assert!(f.zero_modes.iter().all(|z| z.abs() < 1e-10), "m {m}: zero modes {:?}", f.zero_modes);
        assert!(f.growth < -1e-3, "m {m}: growth {}", f.growth);
        assert_eq!(f.unstable, 0, "m {m}");
        assert!(f.smallest_kept > 1e-4, "m {m}: kept {}", f.smallest_kept);
    }
}

/// ln g converges at first order in h (what the table's Richardson
/// extrapolation assumes): successive differences halve (measured ratios
/// 2.0 at m = 0.5, 1.97 at 0.7).
#[test]
fn loop_factor_converges_at_first_order() {
    for m in [0.5f64, 0.7] {
        let k = (1.0 - m * m).sqrt();
        let g = |h: f64| fluctuation(m, h, 24.0 / k).unwrap().ln_g;
        let (g4, g2, g1) = (g(0.04), g(0.02), g(0.01));
        let r = (g4 - g2) / (g2 - g1);
        assert!((r - 2.0).abs() < 0.15, "m {m}: ratio {r}");
    }
}

/// The shipped table against a direct computation between its nodes (the
/// interpolation and the table must agree within the row's own error
/// estimate plus the table's largest).
#[test]
fn shipped_loop_table_matches_direct_computation() {
    let t = LnG::shipped().unwrap();
    for m in [0.4f64, 0.62, 0.93] {
        let (_, direct, err) = table_row(m).unwrap();
        let (v, _) = t.eval(m);
        assert!((v - direct).abs() <= err + 1e-3, "m {m}: table {v}, direct {direct} ± {err}");
    }
    // The derivative is the series' own: against a central difference.
    let (a, b) = (t.eval(0.55 - 1e-5).0, t.eval(0.55 + 1e-5).0);
    assert!(((b - a) / 2e-5 - t.eval(0.55).1).abs() < 1e-6);
    // Outside the range: constant below, continued towards −∞ at m → 1.
    assert_eq!(t.eval(0.05).0, t.eval(M_MIN).0);
    assert!(t.eval(0.995).0 < t.eval(M_MAX).0);
}

/// The model applies (3) at the coexistence torque: kT ln Φ recomputed here
/// from the superhelix's own writhe at τ* (not the model's grids) and the
/// table; off at kT = 0 and with a caller's counting length.
#[test]
fn model_uses_the_loop_correction_at_coexistence() {
    use rodkit::tweezers::{Model, TweezersScene};
    for (force, salt) in [(1.0, 0.1), (0.5, 0.05), (4.0, 0.15)] {
        let scene = TweezersScene { force, salt, ..Default::default() };
        let m = Model::new(&scene).unwrap();
        let star = &m.coexistence;
        let sk = (scene.bending * force).sqrt();
        let xi = (scene.bending / force).sqrt();
        let (lg, _) = LnG::shipped().unwrap().eval(star.torque / (2.0 * sk));
        let expect = scene.kt
            * (lg + (star.writhe * xi).ln() - 1.5 * (scene.kt / sk).ln() - 0.5 * (2.0 * std::f64::consts::PI).ln());
        let got = m.end_loop_correction();
        // The model reads w from its Chebyshev table of the superhelix in τ,
        // whose interpolation error is ~1e-5 relative (measured 1.4e-5 in
        // kT ln Φ at 1 pN, 0.1 M): held at 1e-4.
        assert!((got - expect).abs() < 1e-4 * expect.abs(), "F {force}, c {salt}: {got} vs {expect}");
        assert!(got > 0.0);
        let cold = Model::new(&TweezersScene { kt: 0.0, ..scene.clone() }).unwrap();
        assert_eq!(cold.end_loop_correction(), 0.0);
        let b = Model::new(&TweezersScene { counting_length: 10.0, ..scene.clone() }).unwrap();
        assert_eq!(b.end_loop_correction(), 0.0);
    }
}

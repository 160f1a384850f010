//! Thin tube at finite strain (membrane, algebraic) against: the thin linear
//! theory (its derivative at rest), an exact neo-Hookean inflation result,
//! and the thick solver as t/R → 0, whose difference its error estimate must
//! bound.

use rodkit::tube::finite::{Axial, Ends, FiniteTube, Loading, SolveOptions, Torsion};
use rodkit::tube::material::{NeoHookean, SaintVenantKirchhoff};
use rodkit::tube::membrane::MembraneTube;
use rodkit::tube::{Orthotropic, ThinTube};
use std::f64::consts::PI;

fn helical() -> Orthotropic {
    Orthotropic::new(10.0, 2.0, 1.5, 0.35, 0.3, 0.4, 1.2, 0.8, 0.6).unwrap()
}

fn pull(force: f64) -> Loading {
    Loading {
        axial: Axial::Force(force),
        torsion: Torsion::Torque(0.0),
        inner_pressure: 0.0,
        outer_pressure: 0.0,
        ends: Ends::Open,
    }
}

/// d(ψ, ε_θ, ε)/dF of the free membrane at rest equals the thin linear
/// response of §1.4 (reference: ThinTube with the plane-stress constants).
#[test]
fn linearisation_equals_thin_linear_theory() {
    let (r, t, tau0) = (1.0, 0.05, 1.7);
    let svk = SaintVenantKirchhoff::new(helical(), tau0, false);
    let tube = MembraneTube::new(r, t, &svk).unwrap();
    let lin =
        ThinTube::new(r, t, tau0, helical().surface()).unwrap().coupling_stiffness().unwrap().free_response().unwrap();
    let h = 1e-6;
    let (p, m) = (tube.solve(&pull(h)).unwrap(), tube.solve(&pull(-h)).unwrap());
    let dpsi = (p.twist - m.twist) / (2.0 * h);
    let deps = (p.stretch - m.stretch) / (2.0 * h);
    let dhoop = (p.profile.radius[0] - m.profile.radius[0]) / r / (2.0 * h);
    for (got, want, what) in
        [(dpsi, lin.dtwist_dforce, "dψ/dF"), (deps, lin.dstrain_dforce, "dε/dF"), (dhoop, lin.dhoop_dforce, "dε_θ/dF")]
    {
        assert!((got - want).abs() < 1e-6 * lin.dstrain_dforce.abs(), "{what}: {got} vs {want}");
    }
}

/// Incompressible neo-Hookean membrane at fixed stretch λ: with a = 1/(bλ)
/// and σ = μ(B − I) − p̂I, σ_rr = 0, the hoop balance on the deformed inner
/// face, σ_θθ·at = p(bR − at/2), gives exactly p = μ(b² − a²)·at/(bR − at/2).
/// Prescribe that p, recover b.
#[test]
fn neo_hookean_membrane_inflation_is_exact() {
    let (mu, r, t) = (0.7, 2.0, 0.02);
    let nh = NeoHookean { shear_modulus: mu, lame_lambda: 0.0, incompressible: true };
    let tube = MembraneTube::new(r, t, &nh).unwrap();
    for (b, lambda) in [(1.1, 1.0), (1.5, 1.2), (0.9, 0.95)] {
        let a: f64 = 1.0 / (b * lambda);
        let p = mu * (b * b - a * a) * a * t / (b * r - 0.5 * a * t);
        let s = tube
            .solve(&Loading {
                axial: Axial::Stretch(lambda),
                torsion: Torsion::Twist(0.0),
                inner_pressure: p,
                outer_pressure: 0.0,
                ends: Ends::Closed,
            })
            .unwrap();
        assert!((s.profile.radius[0] / r - b).abs() < 1e-12, "b {b}: got {}", s.profile.radius[0] / r);
        // Axial: σ_zz = μ(λ² − a²), plus nothing else: F_wall = 2π r (a t) σ_zz.
        let f = 2.0 * PI * b * r * a * t * mu * (lambda * lambda - a * a);
        assert!((s.wall_force - f).abs() < 1e-12 * f.abs().max(1e-3), "F {} vs {f}", s.wall_force);
    }
}

/// Finite strain: the membrane agrees with the thick solver as t/R → 0, the
/// difference falling at rate ≥ 1 in t/R (rate 2 without pressure; with
/// pressure at a fixed hoop stress pR/t, rate 1 from the neglected σ_rr);
/// the membrane's error estimate bounds the true difference within 50×.
#[test]
fn membrane_converges_to_thick_wall_and_estimate_bounds_error() {
    let r = 1.0;
    for (tau0, lambda, hoop_stress) in [(1.7, 1.15, 0.0), (0.5, 1.3, 0.0), (1.7, 1.0, 0.25), (3.0, 1.1, 0.125)] {
        let svk = SaintVenantKirchhoff::new(helical(), tau0, false);
        let mut diffs = vec![];
        for t in [0.04, 0.02, 0.01] {
            let loading = Loading {
                axial: Axial::Stretch(lambda),
                torsion: Torsion::Torque(0.0),
                inner_pressure: hoop_stress * t / r,
                outer_pressure: 0.0,
                ends: Ends::Closed,
            };
            let thin = MembraneTube::new(r, t, &svk).unwrap().solve(&loading).unwrap();
            let thick = FiniteTube::new(r - t / 2.0, r + t / 2.0, &svk)
                .unwrap()
                .solve(&loading, &SolveOptions::default())
                .unwrap();
            let diff = ((thin.twist - thick.twist) * r).abs().max(
                (thin.deformed_inner_radius + thin.deformed_outer_radius
                    - thick.deformed_inner_radius
                    - thick.deformed_outer_radius)
                    .abs()
                    / (2.0 * r),
            );
            let case = format!("τ0 {tau0}, λ {lambda}, hoop stress {hoop_stress}, t {t}");
            assert!(thin.error_estimate >= diff, "{case}: estimate {:e} < true {diff:e}", thin.error_estimate);
            assert!(thin.error_estimate < 50.0 * diff, "{case}: estimate {:e} ≫ true {diff:e}", thin.error_estimate);
            diffs.push(diff);
        }
        for w in diffs.windows(2) {
            assert!((w[0] / w[1]).log2() > 0.9, "τ0 {tau0}: {diffs:?}");
        }
    }
}

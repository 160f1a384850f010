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

/// Independent membrane reference for a free wall (no pressure, open ends,
/// zero torque) at prescribed stretch λ, written here from the energy rather
/// than from the library's Cauchy stresses. With F = [[a,0,0],[0,b,γ],[0,0,λ]]
/// (physics.md §1.2), σ_rr = 0 ⇔ ∂W/∂a = 0, σ_θz = 0 ⇔ ∂W/∂γ = 0 and then
/// σ_θθ = 0 ⇔ ∂W/∂b = 0 (J σ_θθ = b ∂W/∂b + γ ∂W/∂γ): the state is a
/// stationary point of W(a, b, γ; λ). W = ½ ε'ᵀ ℂ ε' with ε' the Green
/// strain in the material axes (1 along the helix at α from e_Z towards
/// e_Θ, 2 across it in the surface, 3 radial; engineering shears) and ℂ the
/// inverse of the nine-constant compliance.
struct SvkMembraneReference {
    stiffness: nalgebra::Matrix6<f64>,
    /// Material axes as rows, components in (R, Θ, Z).
    axes: nalgebra::Matrix3<f64>,
}

impl SvkMembraneReference {
    #[allow(clippy::too_many_arguments)]
    fn new(e: [f64; 3], nu12: f64, nu13: f64, nu23: f64, g: [f64; 3], alpha: f64) -> Self {
        let [e1, e2, e3] = e;
        let [g12, g13, g23] = g;
        let mut s = nalgebra::Matrix6::zeros();
        s[(0, 0)] = 1.0 / e1;
        s[(1, 1)] = 1.0 / e2;
        s[(2, 2)] = 1.0 / e3;
        s[(0, 1)] = -nu12 / e1;
        s[(0, 2)] = -nu13 / e1;
        s[(1, 2)] = -nu23 / e2;
        s[(1, 0)] = s[(0, 1)];
        s[(2, 0)] = s[(0, 2)];
        s[(2, 1)] = s[(1, 2)];
        // Voigt order 11, 22, 33, 23, 13, 12.
        s[(3, 3)] = 1.0 / g23;
        s[(4, 4)] = 1.0 / g13;
        s[(5, 5)] = 1.0 / g12;
        let (sa, ca) = alpha.sin_cos();
        let axes = nalgebra::Matrix3::new(0.0, sa, ca, 0.0, ca, -sa, 1.0, 0.0, 0.0);
        SvkMembraneReference { stiffness: s.try_inverse().unwrap(), axes }
    }

    /// Green strain in (R, Θ, Z) and its derivatives in (a, b, γ).
    fn strain(q: [f64; 3], lambda: f64) -> [nalgebra::Matrix3<f64>; 4] {
        let [a, b, g] = q;
        let m = |rr: f64, tt: f64, tz: f64, zz: f64| nalgebra::Matrix3::new(rr, 0.0, 0.0, 0.0, tt, tz, 0.0, tz, zz);
        [
            m(0.5 * (a * a - 1.0), 0.5 * (b * b - 1.0), 0.5 * b * g, 0.5 * (g * g + lambda * lambda - 1.0)),
            m(a, 0.0, 0.0, 0.0),
            m(0.0, b, 0.5 * g, 0.0),
            m(0.0, 0.0, 0.5 * b, g),
        ]
    }

    fn voigt(&self, e: &nalgebra::Matrix3<f64>) -> nalgebra::Vector6<f64> {
        let m = self.axes * e * self.axes.transpose();
        nalgebra::Vector6::new(m[(0, 0)], m[(1, 1)], m[(2, 2)], 2.0 * m[(1, 2)], 2.0 * m[(0, 2)], 2.0 * m[(0, 1)])
    }

    /// ∇W in (a, b, γ): Σ S'·dε' with S' = ℂ ε' (the energy's exact gradient).
    fn gradient(&self, q: [f64; 3], lambda: f64) -> nalgebra::Vector3<f64> {
        let [e, da, db, dg] = Self::strain(q, lambda);
        let stress = self.stiffness * self.voigt(&e);
        nalgebra::Vector3::new(stress.dot(&self.voigt(&da)), stress.dot(&self.voigt(&db)), stress.dot(&self.voigt(&dg)))
    }

    /// Hessian by central differences of the exact gradient.
    fn hessian(&self, q: [f64; 3], lambda: f64) -> nalgebra::Matrix3<f64> {
        let h = 1e-6;
        let mut out = nalgebra::Matrix3::zeros();
        for k in 0..3 {
            let (mut p, mut m) = (q, q);
            p[k] += h;
            m[k] -= h;
            out.set_column(k, &((self.gradient(p, lambda) - self.gradient(m, lambda)) / (2.0 * h)));
        }
        (out + out.transpose()) * 0.5
    }

    /// Newton from `q` to a root of ∇W at λ (to round-off).
    fn solve(&self, mut q: [f64; 3], lambda: f64) -> [f64; 3] {
        for _ in 0..50 {
            let g = self.gradient(q, lambda);
            let step = self.hessian(q, lambda).lu().solve(&g).unwrap();
            for k in 0..3 {
                q[k] -= step[k];
            }
            if step.amax() < 1e-15 {
                break;
            }
        }
        assert!(self.gradient(q, lambda).amax() < 1e-13, "reference Newton did not converge at λ = {lambda}");
        q
    }
}

/// A torque-free stretch of auxetic and strongly anisotropic SVK membranes to
/// λ = 1.5 stays on the branch from rest. The reference: the stationary
/// points of the wall's energy, written in this test and continued in the
/// sweep's own steps from rest (SvkMembraneReference). Before the load
/// homotopy refused far roots, the thick wall the membrane's estimate is
/// checked against, solved from rest, landed on a collapsed root (hoop
/// stretch 0.017 at λ = 1.0575 for the first wall below) and the sweep
/// stopped with ErrMaterialInstability. Each wall's energy Hessian stays
/// positive definite on the reference path (asserted), so the whole sweep
/// must succeed. Tolerance 1e-10: both sides solve the same equations to
/// ~1e-13; the library's state carries the round-off of its stresses.
#[test]
fn torque_free_stretch_of_anisotropic_auxetic_walls_stays_on_the_branch() {
    let deg = std::f64::consts::PI / 180.0;
    // (E1, E2, E3, ν12, ν13, ν23, G12, G13, G23, α)
    type Wall = ([f64; 3], f64, f64, f64, [f64; 3], f64);
    let walls: [Wall; 6] = [
        ([1.0, 18.6, 18.6], -0.19, 0.0, 0.0, [0.075, 0.075, 9.3], 61.0),
        ([1.0, 18.6, 18.6], -0.19, 0.0, 0.0, [0.075, 0.075, 9.3], 40.0),
        ([1.0, 30.0, 10.0], -0.15, 0.1, -0.2, [0.05, 0.2, 4.0], 70.0),
        ([20.0, 1.0, 1.0], -0.6, 0.3, 0.1, [0.1, 0.4, 0.5], 35.0),
        ([1.0, 1.0, 1.0], -0.5, -0.3, -0.3, [0.8, 0.8, 0.8], 55.0),
        ([50.0, 1.0, 2.0], 0.45, 0.3, 0.3, [0.02, 0.5, 0.3], 20.0),
    ];
    let (inner, outer) = (0.995, 1.005);
    let (r0, t) = (0.5 * (inner + outer), outer - inner);
    for (k, &(e, nu12, nu13, nu23, g, alpha_deg)) in walls.iter().enumerate() {
        let alpha = alpha_deg * deg;
        let m = Orthotropic::new(e[0], e[1], e[2], nu12, nu13, nu23, g[0], g[1], g[2]).unwrap();
        let svk = SaintVenantKirchhoff::new(m, alpha.tan() / r0, false);
        let tube = MembraneTube::new(r0, t, &svk).unwrap();
        let reference = SvkMembraneReference::new(e, nu12, nu13, nu23, g, alpha);
        let stretches: Vec<f64> = (0..=200).map(|i| 1.0 + 0.0025 * i as f64).collect();
        let loadings: Vec<Loading> = stretches
            .iter()
            .map(|&l| Loading {
                axial: Axial::Stretch(l),
                torsion: Torsion::Torque(0.0),
                inner_pressure: 0.0,
                outer_pressure: 0.0,
                ends: Ends::Open,
            })
            .collect();
        let sweep = tube.sweep(&loadings, |_, _| true).unwrap_or_else(|e| panic!("wall {k}: {}", e.message));
        assert_eq!(sweep.states.len(), stretches.len());
        let mut q = [1.0, 1.0, 0.0];
        let mut worst = 0.0f64;
        for (s, &lambda) in sweep.states.iter().zip(&stretches) {
            q = reference.solve(q, lambda);
            assert!(
                reference.hessian(q, lambda).cholesky().is_some(),
                "wall {k} is not stable at λ = {lambda}: pick another wall"
            );
            let [a, b, gamma] = q;
            let hoop = s.profile.radius[0] / r0;
            let thickness = (s.deformed_outer_radius - s.deformed_inner_radius) / t;
            let shear = s.twist * s.profile.radius[0];
            for (got, want) in [(hoop, b), (thickness, a), (shear, gamma)] {
                worst = worst.max((got - want).abs());
            }
        }
        assert!(worst < 1e-10, "wall {k}: membrane sweep off the energy's stationary branch by {worst:e}");
        // The thick wall solved straight from rest at λ = 1.5 (its own load
        // homotopy) lands on the same branch: within the membrane's estimate.
        let last = sweep.states.last().unwrap();
        let thick = FiniteTube::new(inner, outer, &svk)
            .unwrap()
            .solve(loadings.last().unwrap(), &SolveOptions { rel_tol: 1e-10, intervals: None })
            .unwrap_or_else(|e| panic!("wall {k}: thick wall at λ = 1.5: {}", e.message));
        let off = ((thick.deformed_inner_radius + thick.deformed_outer_radius) / 2.0 - s_mid(last)).abs() / outer;
        assert!(
            off <= last.error_estimate,
            "wall {k}: thick mid radius off by {off:e}, estimate {:e}",
            last.error_estimate
        );
        eprintln!(
            "wall {k}: worst {worst:.1e}, b(1.5) = {:.6}, thick off {off:.1e} (estimate {:.1e})",
            q[1], last.error_estimate
        );
    }
}

fn s_mid(s: &rodkit::tube::finite::TubeState) -> f64 {
    0.5 * (s.deformed_inner_radius + s.deformed_outer_radius)
}

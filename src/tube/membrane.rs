//! Thin tube at finite strain (§1.5, issue item "thin tube at finite strain"):
//! the wall is a membrane at the mid radius R with thickness t, in plane
//! stress (σ_rr = 0 through the thin wall), so the radial ODE of
//! [`crate::tube::finite`] becomes algebraic:
//!
//! - compressible: unknowns the thickness stretch a and the hoop stretch
//!   b = r/R, equations σ_rr(a, b, λ, γ) = 0 and the hoop balance
//!   σ_θθ·(a t) = p·r_in − p_o·r_out with the deformed faces r ∓ at/2 (two
//!   equations; the balance is the exact ∫σ_θθ dr of the wall);
//! - incompressible: a = 1/(bλ) and the multiplier p̂ = σ̂_rr (so σ_rr = 0);
//!   one equation, (σ̂_θθ − σ̂_rr)·(a t) = p·r_in − p_o·r_out.
//!
//! Resultants F = 2πr(at)σ_zz, T = 2πr²(at)σ_θz, γ = rψ; closed ends carry
//! πr²(p − p_o) on the caps. With λ or ψ unprescribed, F or T close the system.
//!
//! Error estimate (defined estimator): the membrane is also evaluated at the
//! inner and outer radii R ∓ t/2; the symmetric second difference of the
//! three states estimates the through-thickness correction the membrane
//! neglects (see [`MembraneTube::solve`]).

use crate::error::{self, Error, Result};
use crate::nonlinear::dense::{self as newton, NewtonOptions};
use crate::status::Status;
use crate::tube::finite::{
    load_homotopy, load_unknowns, stress_scale, stretch_and_twist, validate, validate_sweep, Axial, Ends, Loading,
    Sweep, Torsion, TubeState, WallProfile,
};
use crate::tube::material::{WallMaterial, WallStrain};
use nalgebra::{DVector, Matrix3};
use std::f64::consts::PI;

/// Positions of the unknowns [a (compressible only), b, λ?, ψ?]: λ where
/// the force is prescribed, ψ where the torque is; `len` of them.
struct Layout {
    stretch: Option<usize>,
    twist: Option<usize>,
    len: usize,
}

/// A thin tube of mid radius R and wall thickness t made of `material`.
pub struct MembraneTube<'m> {
    pub mid_radius: f64,
    pub thickness: f64,
    pub material: &'m dyn WallMaterial,
    modulus: f64,
}

impl<'m> MembraneTube<'m> {
    pub fn new(mid_radius: f64, thickness: f64, material: &'m dyn WallMaterial) -> Result<Self> {
        error::positive("mid_radius", mid_radius)?;
        error::positive("thickness", thickness)?;
        if thickness >= 2.0 * mid_radius {
            return Err(Error::new(
                Status::ErrInvalidGeometry,
                format!("impossible tube: thickness {thickness:e} must be below twice the mid radius {mid_radius:e}"),
            ));
        }
        let modulus = stress_scale(material, mid_radius)?;
        Ok(MembraneTube { mid_radius, thickness, material, modulus })
    }

    /// Equilibrium under `loading`, with the bracketing error estimate.
    pub fn solve(&self, loading: &Loading) -> Result<TubeState> {
        validate(loading)?;
        let mut starts = self.rest_starts(loading);
        self.solve_from(&loading.rest(), &mut starts, loading)
    }

    /// The unknowns at rest for the mid radius and the two bracket radii.
    fn rest_starts(&self, loading: &Loading) -> [DVector<f64>; 3] {
        let layout = self.layout(loading);
        let mut x = DVector::from_element(layout.len, 1.0);
        if let Some(i) = layout.twist {
            x[i] = 0.0;
        }
        [x.clone(), x.clone(), x]
    }

    /// The state at `to`, continued from the solutions `starts` (mid, inner,
    /// outer radius) at `from`; `starts` are updated. The bracket radii give
    /// the error estimate (INFINITY if they fail).
    fn solve_from(&self, from: &Loading, starts: &mut [DVector<f64>; 3], to: &Loading) -> Result<TubeState> {
        let half = 0.5 * self.thickness;
        let [mid, inner, outer] = starts;
        let mut state = self.solve_at(self.mid_radius, from, mid, to)?;
        let inner = self.solve_at(self.mid_radius - half, from, inner, to);
        let outer = self.solve_at(self.mid_radius + half, from, outer, to);
        state.error_estimate = match (inner, outer) {
            (Ok(i), Ok(o)) => self.curvature_estimate(&i, &state, &o),
            _ => f64::INFINITY, // the bracket itself failed: no estimate can be trusted
        };
        Ok(state)
    }

    /// Positions of the unknowns: [a (compressible only), b, λ?, ψ?].
    fn layout(&self, loading: &Loading) -> Layout {
        let base = if self.material.incompressible() { 1 } else { 2 };
        let (stretch, twist) = load_unknowns(loading, base);
        Layout { stretch, twist, len: base + stretch.is_some() as usize + twist.is_some() as usize }
    }

    /// |(s(R − t/2) + s(R + t/2))/2 − s(R)| over the state's strain-like
    /// measures, each normalised by its own reference radius (moving the
    /// radius by t must not count): hoop stretch, λ, ψR, and the mean wall
    /// stresses F/(2πRt), T/(2πR²t) per modulus. The symmetric second
    /// difference is the through-thickness curvature the membrane (a midpoint
    /// rule across the wall) neglects; first-order variations cancel in the
    /// wall as they do here, so it tracks the O((t/R)²) error.
    fn curvature_estimate(&self, inner: &TubeState, mid: &TubeState, outer: &TubeState) -> f64 {
        let t = self.thickness;
        let norm = |s: &TubeState| {
            let r0 = s.profile.reference_radius[0];
            [
                s.profile.radius[0] / r0,
                s.stretch,
                s.twist * r0,
                s.wall_force / (2.0 * PI * r0 * t * self.modulus),
                s.torque / (2.0 * PI * r0 * r0 * t * self.modulus),
            ]
        };
        let (a, m, b) = (norm(inner), norm(mid), norm(outer));
        let curvature = (0..5).fold(0.0, |acc: f64, k| acc.max((0.5 * (a[k] + b[k]) - m[k]).abs()));
        // Plane stress neglects σ_rr, which runs from −p to −p_o through the
        // wall: a strain defect of order (|p| + |p_o|)/modulus.
        let plane_stress = (mid.inner_pressure.abs() + mid.outer_pressure.abs()) / self.modulus;
        // Safety factor 4 on the curvature term: measured true/estimate
        // ratios 0.8–1.6 without pressure (tests/membrane_tube.rs).
        4.0 * curvature + plane_stress
    }

    /// The membrane at radius `r0` (the mid radius, or a bracket radius),
    /// continued from the solution `x` at `from` along the straight load
    /// path (bisected on failure, as for the thick wall); `x` is updated.
    fn solve_at(&self, r0: f64, from: &Loading, x: &mut DVector<f64>, loading: &Loading) -> Result<TubeState> {
        let layout = self.layout(loading);
        let typical = DVector::from_fn(layout.len, |k, _| if Some(k) == layout.twist { 1.0 / r0 } else { 1.0 });
        let opts = NewtonOptions { step_tol: 1e-13, residual_tol: 1e-13, max_iterations: 50, reuse_jacobian: false };
        let iterations = load_homotopy(x, from, loading, "membrane tube", |part, trial| {
            let report = newton::solve(trial, &typical, &opts, |x, f| self.residual(r0, part, &layout, x, f))?;
            Ok(report.iterations)
        })?;
        let mut state = self.state(r0, loading, &layout, x)?;
        state.newton_iterations = iterations;
        Ok(state)
    }

    /// (a, b, λ, ψ) from the unknowns and the prescribed values.
    fn kinematics(&self, loading: &Loading, layout: &Layout, x: &DVector<f64>) -> [f64; 4] {
        let b = if self.material.incompressible() { x[0] } else { x[1] };
        let (lambda, psi) = stretch_and_twist(loading, layout.stretch, layout.twist, x);
        let a = if self.material.incompressible() { 1.0 / (b * lambda) } else { x[0] };
        [a, b, lambda, psi]
    }

    /// Plane-stress Cauchy stress (σ_rr = 0 enforced by the multiplier for
    /// incompressible laws; for compressible ones it is an equation).
    fn stress(&self, r0: f64, k: [f64; 4]) -> Option<Matrix3<f64>> {
        let [a, b, lambda, psi] = k;
        if !(a > 0.0 && b > 0.0 && lambda > 0.0) {
            return None;
        }
        let mut s = self.material.cauchy(r0, &WallStrain { radial: a, hoop: b, axial: lambda, shear: b * r0 * psi });
        if self.material.incompressible() {
            let p_hat = s[(0, 0)];
            for i in 0..3 {
                s[(i, i)] -= p_hat;
            }
        }
        s.iter().all(|v| v.is_finite()).then_some(s)
    }

    fn resultants(&self, r0: f64, k: [f64; 4], s: &Matrix3<f64>, loading: &Loading) -> (f64, f64, f64) {
        let [a, b, _, _] = k;
        let (r, t) = (b * r0, a * self.thickness);
        let wall = 2.0 * PI * r * t * s[(2, 2)];
        let torque = 2.0 * PI * r * r * t * s[(1, 2)];
        let (r_in, r_out) = (r - 0.5 * t, r + 0.5 * t);
        let applied = match loading.ends {
            Ends::Open => wall,
            Ends::Closed => wall - PI * (r_in * r_in * loading.inner_pressure - r_out * r_out * loading.outer_pressure),
        };
        (wall, applied, torque)
    }

    fn residual(&self, r0: f64, loading: &Loading, layout: &Layout, x: &DVector<f64>, f: &mut DVector<f64>) -> bool {
        let k = self.kinematics(loading, layout, x);
        let Some(s) = self.stress(r0, k) else { return false };
        let [a, b, _, _] = k;
        let mu = self.modulus;
        // Exact hoop balance of the wall, ∫σ_θθ dr = p r_in − p_o r_out, with
        // the membrane's uniform σ_θθ and deformed faces r ∓ at/2.
        let (r, half) = (b * r0, 0.5 * a * self.thickness);
        let pressure_load = loading.inner_pressure * (r - half) - loading.outer_pressure * (r + half);
        let hoop = (s[(1, 1)] * a * self.thickness - pressure_load) / (mu * self.thickness);
        if self.material.incompressible() {
            f[0] = hoop;
        } else {
            f[0] = s[(0, 0)] / mu;
            f[1] = hoop;
        }
        let (_, applied, torque) = self.resultants(r0, k, &s, loading);
        let force_scale = mu * 2.0 * PI * r0 * self.thickness;
        if let (Axial::Force(target), Some(i)) = (loading.axial, layout.stretch) {
            f[i] = (applied - target) / force_scale;
        }
        if let (Torsion::Torque(target), Some(i)) = (loading.torsion, layout.twist) {
            f[i] = (torque - target) / (force_scale * r0);
        }
        true
    }

    fn state(&self, r0: f64, loading: &Loading, layout: &Layout, x: &DVector<f64>) -> Result<TubeState> {
        let k = self.kinematics(loading, layout, x);
        let s = self.stress(r0, k).ok_or_else(|| {
            Error::new(Status::ErrNonFiniteResult, "membrane tube: converged state is outside the domain")
        })?;
        let [a, b, lambda, psi] = k;
        let (wall, applied, torque) = self.resultants(r0, k, &s, loading);
        let (r, t) = (b * r0, a * self.thickness);
        let state = TubeState {
            stretch: lambda,
            twist: psi,
            wall_force: wall,
            applied_force: applied,
            torque,
            inner_pressure: loading.inner_pressure,
            outer_pressure: loading.outer_pressure,
            deformed_inner_radius: r - 0.5 * t,
            deformed_outer_radius: r + 0.5 * t,
            intervals: 0,
            error_estimate: 0.0,
            newton_iterations: 0,
            switch_radii: Vec::new(),
            profile: WallProfile {
                reference_radius: vec![r0],
                radius: vec![r],
                sigma_rr: vec![s[(0, 0)]],
                sigma_tt: vec![s[(1, 1)]],
                sigma_zz: vec![s[(2, 2)]],
                sigma_tz: vec![s[(1, 2)]],
            },
        };
        error::finite_result("membrane tube state", &[lambda, psi, wall, torque, r, t])?;
        Ok(state)
    }
}

impl MembraneTube<'_> {
    /// States along `loadings` (all of one kind), each continued from the
    /// previous one, so the sweep follows one branch of equilibria (solving
    /// each point from rest could land on another where several exist);
    /// `progress(i, state)` returning false stops the sweep cleanly.
    pub fn sweep(&self, loadings: &[Loading], progress: impl FnMut(usize, &TubeState) -> bool) -> Result<Sweep> {
        let Some(first) = loadings.first() else {
            return Ok(Sweep { states: Vec::new(), cancelled: false });
        };
        validate_sweep(loadings, first, "first", |_| Ok(()))?;
        let mut starts = self.rest_starts(first);
        let mut from = first.rest();
        Sweep::run(loadings, progress, |l| {
            let s = self.solve_from(&from, &mut starts, l)?;
            from = *l;
            Ok(s)
        })
    }
}

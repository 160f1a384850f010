//! Thin tube at finite strain (§1.5):
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
//! Error estimate ("no silent wrong answers"): the thick wall of the same
//! section, A = R − t/2, B = R + t/2, solved by the finite-strain
//! collocation of [`crate::tube::finite`] on two fixed coarse grids of
//! [`CHECK_COARSE`] and [`CHECK_FINE`] Chebyshev intervals (cheap: a wall
//! this thin is resolved by a few intervals). The estimate is
//! SAFETY·(|membrane − fine| + |coarse − fine|) in the thick model's own
//! measure (radii per B, λ, ψB, F per μπB², T per μπB³), so AUTO compares
//! like with like. The first term sees every neglected effect at its true
//! order (the through-thickness variation of the stress, the radial stress
//! of plane stress, the fibres of a fixed-angle wall); the second bounds the
//! coarse thick wall's own error (spectral convergence: the fine grid is
//! closer to the exact wall than the coarse one). The estimator it replaces
//! (membranes at R ∓ t/2 differenced) was blind to any law that does not
//! depend on R: it reported 1e−16 for a fixed-angle fibre wall that was
//! 1.5e−3 off at t/R = 0.1 (tests/membrane_tube.rs).

use crate::error::{self, Error, Result};
use crate::nonlinear::dense::{self as newton, NewtonOptions};
use crate::status::Status;
use crate::tube::finite::{
    limit_of_law, load_homotopy, load_unknowns, local_stability, state_difference, stress_scale, stretch_and_twist,
    validate, validate_sweep, Axial, Ends, FiniteTube, Loading, Sweep, Torsion, TubeState, WallProfile,
};
use crate::tube::material::{WallMaterial, WallStrain};
use nalgebra::{DVector, Matrix3};
use std::f64::consts::PI;

/// Chebyshev intervals of the two thick walls the membrane is checked
/// against (see the module docs).
pub const CHECK_COARSE: usize = 4;
pub const CHECK_FINE: usize = 6;

/// Safety factor on the membrane's estimate: the triangle inequality alone
/// gives 1 (true ≤ |membrane − fine| + |fine − exact| and |fine − exact| ≤
/// |coarse − fine| when converging); 2 covers a coarse pair that is not yet
/// in its spectral regime (thick walls, t/R ≈ 0.5). Measured true/estimate
/// over the grid of tests/tube_honesty.rs (10 laws, t/R 1e−4…0.5, four
/// loadings): at most 0.52, 0.50 for all but the thickest fibre wall.
pub const SAFETY: f64 = 2.0;

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

    /// Equilibrium under `loading`, with its error estimate against the
    /// thick wall (module docs).
    pub fn solve(&self, loading: &Loading) -> Result<TubeState> {
        validate(loading)?;
        let mut start = self.rest_start(loading);
        self.solve_from(&loading.rest(), &mut start, loading)
    }

    /// The unknowns at rest.
    fn rest_start(&self, loading: &Loading) -> DVector<f64> {
        let layout = self.layout(loading);
        let mut x = DVector::from_element(layout.len, 1.0);
        if let Some(i) = layout.twist {
            x[i] = 0.0;
        }
        x
    }

    /// The state at `to`, continued from the solution `start` at `from`
    /// (updated), with its error estimate.
    fn solve_from(&self, from: &Loading, start: &mut DVector<f64>, to: &Loading) -> Result<TubeState> {
        let mut state = self.solve_at(self.mid_radius, from, start, to)?;
        state.error_estimate = self.thick_estimate(to, &state)?;
        error::finite_result("membrane tube error estimate", &[state.error_estimate])?;
        Ok(state)
    }

    /// SAFETY·(|membrane − thick on CHECK_FINE| + |thick on CHECK_COARSE −
    /// thick on CHECK_FINE|) in the thick model's measure, floored at the
    /// thick wall's round-off (n ε B/t). A thick wall that cannot be solved
    /// leaves the membrane without an estimate: that is an error (never an
    /// infinite estimate with OK), material instability passed on as such.
    fn thick_estimate(&self, loading: &Loading, state: &TubeState) -> Result<f64> {
        let half = 0.5 * self.thickness;
        let wall = FiniteTube::new(self.mid_radius - half, self.mid_radius + half, self.material)?;
        let solve = |n: usize| {
            wall.solve_on_grid(loading, n).map_err(|e| {
                if e.status == Status::ErrMaterialInstability {
                    e
                } else {
                    Error::new(
                        Status::ErrNotConverged,
                        format!(
                            "membrane tube: no error estimate, the thick wall it is checked against ({n} intervals) \
                             was not solved ({})",
                            e.message
                        ),
                    )
                }
            })
        };
        let (coarse, fine) = (solve(CHECK_COARSE)?, solve(CHECK_FINE)?);
        let (b, mu) = (wall.outer_radius, wall.modulus());
        let model = state_difference(state, &fine, b, mu);
        let grid = state_difference(&coarse, &fine, b, mu);
        let roundoff = CHECK_FINE as f64 * f64::EPSILON * b / self.thickness;
        Ok(SAFETY * (model + grid) + roundoff)
    }

    /// Positions of the unknowns: [a (compressible only), b, λ?, ψ?].
    fn layout(&self, loading: &Loading) -> Layout {
        let base = if self.material.incompressible() { 1 } else { 2 };
        let (stretch, twist) = load_unknowns(loading, base);
        Layout { stretch, twist, len: base + stretch.is_some() as usize + twist.is_some() as usize }
    }

    /// The membrane at radius `r0`, continued from the solution `x` at `from` along the straight load
    /// path (bisected on failure, as for the thick wall); `x` is updated.
    fn solve_at(&self, r0: f64, from: &Loading, x: &mut DVector<f64>, loading: &Loading) -> Result<TubeState> {
        let layout = self.layout(loading);
        let typical = DVector::from_fn(layout.len, |k, _| if Some(k) == layout.twist { 1.0 / r0 } else { 1.0 });
        let opts = NewtonOptions { step_tol: 1e-13, residual_tol: 1e-13, max_iterations: 50, reuse_jacobian: false };
        let iterations = load_homotopy(
            x,
            from,
            loading,
            "membrane tube",
            |part, trial| {
                let report = newton::solve(trial, &typical, &opts, |x, f| self.residual(r0, part, &layout, x, f))?;
                Ok(report.iterations)
            },
            // a and b are stretches; λ too, ψ per 1/r0.
            |a, b| (a - b).component_div(&typical).amax(),
            |part, x, s| {
                let [a, b, lambda, psi] = self.kinematics(part, &layout, x);
                limit_of_law(self.material, r0, &[a, b, lambda, b * r0 * psi], s)
            },
        )?;
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
        error::finite_result("membrane tube state", &[lambda, psi, wall, applied, torque, r, t])?;
        // The algebraic membrane has solutions with the deformed wall through
        // the axis (r − at/2 ≤ 0: measured −0.21 … −1e8 under strong outer or
        // inner pressure): the section has collapsed, no physical state of
        // this model exists there.
        if !(r - 0.5 * t > 0.0) {
            return Err(Error::new(
                Status::ErrMaterialInstability,
                format!(
                    "membrane tube collapsed: the deformed inner radius r - at/2 = {:e} is not positive (mid radius \
                     {r:e}, wall {t:e}); the membrane does not apply here, use the thick model",
                    r - 0.5 * t
                ),
            ));
        }
        // As for the thick wall: a compressible law must be locally stable
        // (Saint Venant-Kirchhoff past its stretch limit is not).
        if !self.material.incompressible() {
            local_stability(self.material, r0, &[a, b, lambda, b * r0 * psi])?;
        }
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
        let mut start = self.rest_start(first);
        let mut from = first.rest();
        Sweep::run(loadings, progress, |l| {
            let s = self.solve_from(&from, &mut start, l)?;
            from = *l;
            Ok(s)
        })
    }
}

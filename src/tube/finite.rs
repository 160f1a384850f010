//! Finite-strain extension–torsion–inflation of a thick tube (§1.2–1.3):
//! r = r(R), θ = Θ + ψZ, z = λZ, any hyperelastic [`WallMaterial`], any mix
//! of prescribed (λ or F), (ψ or T) and inner/outer pressure, open or closed
//! ends, hollow or solid.
//!
//! Compressible: Chebyshev collocation of the radial equilibrium in Cauchy
//! form with R as the variable, dσ_rr/dR = (σ_θθ − σ_rr)·r'/r, with σ_rr(A) =
//! −p (or r(0) = 0 for a solid) and σ_rr(B) = −p_o, solved by Newton for r at
//! the nodes and the unprescribed λ, ψ. Incompressible: J = 1 gives
//! r² = a² + (R² − A²)/λ, so the unknowns are the deformed inner radius a and
//! the unprescribed λ, ψ; the pressure multiplier follows from integrating
//! equilibrium, σ_rr(B) − σ_rr(A) = ∫ (σ̂_θθ − σ̂_rr) r'/r dR.
//!
//! Forces: `wall_force` = 2π∫σ_zz r dr is what the wall carries;
//! `applied_force` is what the loading device applies besides the pressure on
//! the caps: equal for open ends, wall_force − πa²p + πb²p_o for closed ends.
//! Torque T = 2π∫σ_θz r² dr.

use crate::chebyshev::PiecewiseGrid;
use crate::error::{self, Error, Result};
use crate::nonlinear::dense::{self as newton, NewtonOptions};
use crate::status::Status;
use crate::tube::material::{WallMaterial, WallStrain};
use crate::tube::thick::PINHOLE;
use nalgebra::{DMatrix, DVector, Matrix3};
use std::f64::consts::PI;

/// Axial loading: prescribed stretch λ or applied force F.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Axial {
    Stretch(f64),
    Force(f64),
}

/// Torsional loading: prescribed twist per reference length ψ or torque T.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Torsion {
    Twist(f64),
    Torque(f64),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ends {
    /// The wall alone carries the applied force.
    Open,
    /// Capped: the pressure on the caps loads the wall axially too.
    Closed,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Loading {
    pub axial: Axial,
    pub torsion: Torsion,
    pub inner_pressure: f64,
    pub outer_pressure: f64,
    pub ends: Ends,
}

impl Loading {
    /// Torsionally relaxed stretching: stretch λ, zero torque, no pressure,
    /// open ends.
    pub fn torsion_free_stretch(stretch: f64) -> Self {
        Loading {
            axial: Axial::Stretch(stretch),
            torsion: Torsion::Torque(0.0),
            inner_pressure: 0.0,
            outer_pressure: 0.0,
            ends: Ends::Open,
        }
    }

    /// Inflation by an inner pressure p, torque-free, with the axial
    /// condition given (Axial::Stretch(λ): restrained; Axial::Force(F): free
    /// to lengthen under F).
    pub fn inflation(inner_pressure: f64, axial: Axial, ends: Ends) -> Self {
        Loading { axial, torsion: Torsion::Torque(0.0), inner_pressure, outer_pressure: 0.0, ends }
    }

    /// The unloaded state with the same prescribed quantities (λ = 1 or
    /// F = 0, ψ = 0 or T = 0, no pressure).
    pub fn rest(&self) -> Self {
        Loading {
            axial: match self.axial {
                Axial::Stretch(_) => Axial::Stretch(1.0),
                Axial::Force(_) => Axial::Force(0.0),
            },
            torsion: match self.torsion {
                Torsion::Twist(_) => Torsion::Twist(0.0),
                Torsion::Torque(_) => Torsion::Torque(0.0),
            },
            inner_pressure: 0.0,
            outer_pressure: 0.0,
            ends: self.ends,
        }
    }

    /// Whether two loadings prescribe the same quantities (so one can be
    /// continued into the other).
    pub fn same_kind(&self, other: &Loading) -> bool {
        std::mem::discriminant(&self.axial) == std::mem::discriminant(&other.axial)
            && std::mem::discriminant(&self.torsion) == std::mem::discriminant(&other.torsion)
            && self.ends == other.ends
    }

    /// (1 − s)·self + s·to, for loadings of the same kind.
    pub(crate) fn lerp(&self, to: &Loading, s: f64) -> Loading {
        debug_assert!(self.same_kind(to));
        let mix = |a: f64, b: f64| a + s * (b - a);
        Loading {
            axial: match (self.axial, to.axial) {
                (Axial::Stretch(a), Axial::Stretch(b)) => Axial::Stretch(mix(a, b)),
                (Axial::Force(a), Axial::Force(b)) => Axial::Force(mix(a, b)),
                _ => to.axial,
            },
            torsion: match (self.torsion, to.torsion) {
                (Torsion::Twist(a), Torsion::Twist(b)) => Torsion::Twist(mix(a, b)),
                (Torsion::Torque(a), Torsion::Torque(b)) => Torsion::Torque(mix(a, b)),
                _ => to.torsion,
            },
            inner_pressure: mix(self.inner_pressure, to.inner_pressure),
            outer_pressure: mix(self.outer_pressure, to.outer_pressure),
            ends: to.ends,
        }
    }
}

/// The result of a sweep: the states reached, in order, and whether the
/// progress callback stopped it early.
#[derive(Clone, Debug, PartialEq)]
pub struct Sweep {
    pub states: Vec<TubeState>,
    pub cancelled: bool,
}

/// Stresses through the wall at the collocation nodes (Cauchy, in the
/// deformed cylindrical basis).
#[derive(Clone, Debug, PartialEq)]
pub struct WallProfile {
    pub reference_radius: Vec<f64>,
    pub radius: Vec<f64>,
    pub sigma_rr: Vec<f64>,
    pub sigma_tt: Vec<f64>,
    pub sigma_zz: Vec<f64>,
    pub sigma_tz: Vec<f64>,
}

/// An equilibrium state of the tube.
#[derive(Clone, Debug, PartialEq)]
pub struct TubeState {
    pub stretch: f64,
    pub twist: f64,
    pub wall_force: f64,
    pub applied_force: f64,
    pub torque: f64,
    pub inner_pressure: f64,
    pub outer_pressure: f64,
    pub deformed_inner_radius: f64,
    pub deformed_outer_radius: f64,
    /// Chebyshev intervals of the returned solution.
    pub intervals: usize,
    /// Change of (a, b, λ, ψ, F, T) against the next coarser grid, in the
    /// tube's scales: radii per outer radius B, λ, ψB, F per μπB², T per μπB³
    /// with μ the material's small-strain modulus (the two-grid estimator;
    /// 0 when a fixed grid was requested).
    pub error_estimate: f64,
    pub newton_iterations: usize,
    /// Reference radii where the wall law switches inside the wall (a fibre
    /// family turning on at I4 = 1), ascending: the wall was solved in
    /// Chebyshev pieces between them and the profile repeats each one.
    pub switch_radii: Vec<f64>,
    pub profile: WallProfile,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// Requested relative accuracy of the state (two-grid estimate).
    pub rel_tol: f64,
    /// Fixed number of intervals instead of the adaptive choice.
    pub intervals: Option<usize>,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions { rel_tol: 1e-10, intervals: None }
    }
}

/// A tube of inner radius A ≥ 0 and outer radius B > A made of `material`.
pub struct FiniteTube<'m> {
    pub inner_radius: f64,
    pub outer_radius: f64,
    pub material: &'m dyn WallMaterial,
    /// Stress scale used to make the residual dimensionless.
    modulus: f64,
}

/// The fields of a solution at the nodes (see [`FiniteTube::fields`]).
struct Fields {
    lambda: f64,
    psi: f64,
    /// Deformed radius r and its derivative r' = dr/dR.
    r: DVector<f64>,
    dr: DVector<f64>,
    /// Cauchy stress (multiplier-free for incompressible laws).
    sigma: Vec<Matrix3<f64>>,
}

/// The chain rule from the local stress derivatives ∂σ/∂(a, b, λ, γ) at
/// each node to the unknown radii r_k (a = Dr, b = r/R, γ = rψ).
struct StressChain<'g> {
    ds: Vec<[Matrix3<f64>; 4]>,
    nodes: &'g DVector<f64>,
    diff: &'g DMatrix<f64>,
    psi: f64,
}

impl StressChain<'_> {
    /// ∂(stress component c at node j)/∂r_k.
    fn dsig_dr(&self, j: usize, c: (usize, usize), k: usize) -> f64 {
        let (rr, d, ds) = (self.nodes, self.diff, &self.ds);
        let db = if rr[j] > 0.0 {
            if j == k {
                1.0 / rr[j]
            } else {
                0.0
            }
        } else {
            d[(j, k)]
        };
        let dg = if j == k { self.psi } else { 0.0 };
        ds[j][0][c] * d[(j, k)] + ds[j][1][c] * db + ds[j][3][c] * dg
    }
}

/// Unknowns of one solve and how to read them.
struct Layout {
    n: usize,
    /// Index of λ in x, if the force is prescribed.
    stretch: Option<usize>,
    /// Index of ψ in x, if the torque is prescribed.
    twist: Option<usize>,
}

impl<'m> FiniteTube<'m> {
    pub fn new(inner_radius: f64, outer_radius: f64, material: &'m dyn WallMaterial) -> Result<Self> {
        error::finite("inner_radius", inner_radius)?;
        error::positive("outer_radius", outer_radius)?;
        if !(inner_radius >= 0.0 && inner_radius < outer_radius) {
            return Err(Error::new(
                Status::ErrInvalidGeometry,
                format!("impossible tube: need 0 <= inner radius ({inner_radius:e}) < outer radius ({outer_radius:e})"),
            ));
        }
        let modulus = stress_scale(material, 0.5 * (inner_radius + outer_radius))?;
        Ok(FiniteTube { inner_radius, outer_radius, material, modulus })
    }

    /// Equilibrium under `loading`, to `opts.rel_tol` (or on a fixed grid).
    pub fn solve(&self, loading: &Loading, opts: &SolveOptions) -> Result<TubeState> {
        validate(loading)?;
        self.check_solid(loading)?;
        if let Some(n) = opts.intervals {
            error::count_in_range("intervals", n as i64, 4, 256)?;
            return self.solve_with_homotopy(loading, n);
        }
        error::in_range("rel_tol", opts.rel_tol, 1e-14, 1.0)?;
        // Grids growing by 1.5×; each solution is compared with the previous
        // one. A failure on a coarse grid (an under-resolved wall) is not
        // final: the next grid tries again. Material instability is final.
        // Loose tolerances start coarser: two grids of 8 and 12 intervals
        // already resolve a smooth wall to ~1e−6.
        let mut n = if opts.rel_tol >= 1e-7 { 8 } else { 12 };
        // The estimate's round-off floor grows with n: below the floor of the
        // second grid no grid can meet the tolerance, so say so at once (a
        // thin wall with a tight tolerance is not "not converged", it is
        // asking for more digits than the wall has).
        let first_floor = self.roundoff_floor(n + n / 2);
        if first_floor > opts.rel_tol {
            return Err(self.unreachable(opts.rel_tol, first_floor));
        }
        let mut previous: Option<TubeState> = None;
        let mut last_diff: Option<f64> = None;
        loop {
            match self.solve_with_homotopy(loading, n) {
                Ok(mut fine) => {
                    if let Some(coarse) = &previous {
                        let diff = state_difference(coarse, &fine, self.outer_radius, self.modulus);
                        let floor = self.roundoff_floor(n);
                        // |coarse − fine| bounds the fine grid's error when
                        // the error contracts fast between grids (spectral).
                        // Where it contracts by q per grid, the tail is
                        // diff·q/(1 − q): use that when q is observed (q
                        // capped at 0.9). A law with switches (fibres turning
                        // on) has breakpoints placed from each grid's own
                        // solution, so its error does not contract smoothly:
                        // factor 2 at least (measured true/diff 1.44 for the
                        // helical fibre wall in torsion at t/R = 0.5 with
                        // q ≈ 0.01, tests/tube_honesty.rs).
                        let base = if self.material.switches() > 0 { 2.0 } else { 1.0 };
                        let factor = match last_diff {
                            Some(prev) if prev > floor => {
                                let q = (diff / prev).min(0.9);
                                (q / (1.0 - q)).max(base)
                            }
                            _ => base,
                        };
                        last_diff = Some(diff);
                        let est = (factor * diff).max(floor);
                        fine.error_estimate = est;
                        if est <= opts.rel_tol {
                            return Ok(fine);
                        }
                        // Two grids agreeing to round-off that is itself
                        // above the tolerance: finer grids only add round-off.
                        if diff <= floor {
                            return Err(self.unreachable(opts.rel_tol, floor));
                        }
                    }
                    previous = Some(fine);
                }
                Err(e) if e.status == Status::ErrMaterialInstability => return Err(e),
                Err(e) => {
                    if n >= 128 {
                        return Err(e);
                    }
                    previous = None;
                    last_diff = None;
                }
            }
            if n >= 128 {
                let message = match previous.filter(|p| p.error_estimate > 0.0) {
                    Some(p) => format!(
                        "finite-strain tube: estimated error {:e} above rel_tol {:e} at {n} intervals",
                        p.error_estimate, opts.rel_tol
                    ),
                    None => format!(
                        "finite-strain tube: no two consecutive grids up to {n} intervals both solved, so no error \
                         estimate for rel_tol {:e}",
                        opts.rel_tol
                    ),
                };
                return Err(Error::new(Status::ErrNotConverged, message));
            }
            n += n / 2;
        }
    }

    /// Round-off floor of the two-grid estimate on `n` intervals, as for
    /// the linear solver (thick.rs): 32nε, growing like nε·B/t for very thin
    /// walls (the derivative across a wall of thickness t amplifies the
    /// radii's round-off by B/t).
    fn roundoff_floor(&self, n: usize) -> f64 {
        let thinness = self.outer_radius / (self.outer_radius - self.inner_radius);
        (32.0 * n as f64 * f64::EPSILON).max(n as f64 * f64::EPSILON * thinness)
    }

    fn unreachable(&self, rel_tol: f64, best: f64) -> Error {
        Error::new(
            Status::ErrToleranceUnreachable,
            format!(
                "finite-strain tube: rel_tol {rel_tol:e} is below the round-off of this wall (t/B = {:e}); the best \
                 reachable is about {best:.1e}",
                (self.outer_radius - self.inner_radius) / self.outer_radius
            ),
        )
    }

    /// The state on a fixed grid of `n` intervals, continued from rest (no
    /// error estimate: 0). The membrane's estimator compares with it.
    pub(crate) fn solve_on_grid(&self, loading: &Loading, n: usize) -> Result<TubeState> {
        validate(loading)?;
        self.check_solid(loading)?;
        self.solve_with_homotopy(loading, n)
    }

    /// The stress scale of the residuals (see [`stress_scale`]).
    pub(crate) fn modulus(&self) -> f64 {
        self.modulus
    }

    /// A solid cylinder has no inner surface to press on.
    fn check_solid(&self, loading: &Loading) -> Result<()> {
        if self.inner_radius == 0.0 && loading.inner_pressure != 0.0 {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!(
                    "a solid cylinder has no inner surface: inner_pressure must be 0 (got {:e})",
                    loading.inner_pressure
                ),
            ));
        }
        Ok(())
    }

    /// Newton from the free state, continued to the load (see [`Self::continue_to`]).
    fn solve_with_homotopy(&self, loading: &Loading, n: usize) -> Result<TubeState> {
        let mut grid = self.grid(n, &[]);
        let mut layout = self.layout(loading, &grid);
        let mut x = self.initial_guess(&grid, &layout);
        let mut iterations = self.continue_to(&grid, &layout, &mut x, &loading.rest(), loading)?;
        self.resolve_switches(n, &mut grid, &mut layout, loading, &mut x, &mut iterations)?;
        let mut state = self.state(&grid, &layout, loading, &x)?;
        state.newton_iterations = iterations;
        self.check_stability(&grid, &state)?;
        Ok(state)
    }

    /// Where the law switches inside the wall (a fibre family turning on at
    /// I4 = 1: the stress is only C⁰ in the strain there), re-solve with a
    /// breakpoint at each switch radius of the solution until the breakpoints
    /// stop moving (fixed-point iteration: a breakpoint off by δ costs O(δ²)
    /// in the fields, so the radii settle in a few rounds). Each round starts
    /// Newton from the previous solution interpolated onto the new pieces.
    fn resolve_switches(
        &self,
        n: usize,
        grid: &mut PiecewiseGrid,
        layout: &mut Layout,
        loading: &Loading,
        x: &mut DVector<f64>,
        iterations: &mut usize,
    ) -> Result<()> {
        if self.material.switches() == 0 {
            return Ok(());
        }
        let settle = 1e-9 * (self.outer_radius - self.inner_radius);
        for _ in 0..16 {
            let found = self.switch_radii(grid, layout, loading, x);
            let current = grid.breaks();
            if found.len() == current.len() && found.iter().zip(&current).all(|(a, b)| (a - b).abs() <= settle) {
                return Ok(());
            }
            let new_grid = self.grid(n, &found);
            let new_layout = self.layout(loading, &new_grid);
            let mut new_x = self.transfer(grid, layout, x, &new_grid, &new_layout);
            match self.newton(&new_grid, &new_layout, loading, &mut new_x) {
                Ok(it) => *iterations += it,
                Err(_) => {
                    new_x = self.initial_guess(&new_grid, &new_layout);
                    *iterations += self.continue_to(&new_grid, &new_layout, &mut new_x, &loading.rest(), loading)?;
                }
            }
            (*grid, *layout, *x) = (new_grid, new_layout, new_x);
        }
        Err(Error::new(
            Status::ErrNotConverged,
            format!("finite-strain tube: the radii where the wall law switches (e.g. fibres turning on) did not settle; last {:?}", grid.breaks()),
        ))
    }

    /// Radii where a switching function of the law changes sign in the
    /// solution `x`, ascending; a function that stays within 1e−9 of zero
    /// through the wall is ignored (its kink is below round-off in the stress).
    fn switch_radii(&self, grid: &PiecewiseGrid, layout: &Layout, loading: &Loading, x: &DVector<f64>) -> Vec<f64> {
        let Some(Fields { lambda, psi, r, dr, .. }) = self.fields(grid, layout, loading, x) else {
            return grid.breaks();
        };
        let g = |k: usize, big: f64| {
            let (rv, drv) = (grid.interpolate(&r, big), grid.interpolate(&dr, big));
            let hoop = if big > 0.0 { rv / big } else { drv };
            let strain = WallStrain { radial: drv, hoop, axial: lambda, shear: rv * psi };
            self.material.switch_value(k, big, &strain.right_cauchy_green())
        };
        let nodes = &grid.nodes;
        let interfaces = grid.interfaces();
        let mut roots = Vec::new();
        for k in 0..self.material.switches() {
            let values: Vec<f64> = nodes.iter().map(|&big| g(k, big)).collect();
            let scale = values.iter().fold(0.0f64, |acc, v| acc.max(v.abs()));
            if scale < 1e-9 {
                continue;
            }
            for &i in &interfaces {
                // A settled breakpoint sits on the switch: g ≈ 0 there.
                if values[i].abs() <= 1e-12 * scale {
                    roots.push(nodes[i]);
                }
            }
            for j in 0..nodes.len() - 1 {
                if values[j] * values[j + 1] < 0.0 && nodes[j] < nodes[j + 1] {
                    roots.push(crate::roots::bracketed_root(
                        |big| g(k, big),
                        nodes[j],
                        nodes[j + 1],
                        values[j],
                        values[j + 1],
                    ));
                }
            }
        }
        roots.sort_by(f64::total_cmp);
        let (a, b) = (nodes[0], nodes[nodes.len() - 1]);
        let close = 1e-6 * (b - a);
        let mut out: Vec<f64> = Vec::with_capacity(roots.len());
        for root in roots {
            if root - a > close && b - root > close && out.last().is_none_or(|&last| root - last > close) {
                out.push(root);
            }
        }
        out
    }

    /// `x` on `from` carried to the nodes of `to` (interpolated r and σ_rr;
    /// λ, ψ and the incompressible inner radius copied).
    fn transfer(
        &self,
        from: &PiecewiseGrid,
        from_layout: &Layout,
        x: &DVector<f64>,
        to: &PiecewiseGrid,
        to_layout: &Layout,
    ) -> DVector<f64> {
        if self.material.incompressible() {
            return x.clone();
        }
        let (m_old, m_new) = (from_layout.n + 1, to_layout.n + 1);
        let extra = x.len() - 2 * m_old;
        let r = x.rows(0, m_old).into_owned();
        let s = x.rows(m_old, m_old).into_owned();
        let mut y = DVector::zeros(2 * m_new + extra);
        for j in 0..m_new {
            y[j] = from.interpolate(&r, to.nodes[j]);
            y[m_new + j] = from.interpolate(&s, to.nodes[j]);
        }
        for e in 0..extra {
            y[2 * m_new + e] = x[2 * m_old + e];
        }
        y
    }

    /// From the solution `x` at `from`, reach `to`: Newton straight there,
    /// and on failure along the straight load path in bisected increments
    /// (load homotopy, at most 2⁸ increments). Returns Newton iterations.
    fn continue_to(
        &self,
        grid: &PiecewiseGrid,
        layout: &Layout,
        x: &mut DVector<f64>,
        from: &Loading,
        to: &Loading,
    ) -> Result<usize> {
        load_homotopy(
            x,
            from,
            to,
            "finite-strain tube",
            |loading, x| self.newton(grid, layout, loading, x),
            |a, b| self.kinematic_change(layout, a, b),
            |loading, x, s| {
                let f = self.fields(grid, layout, loading, x)?;
                (0..grid.nodes.len()).find_map(|j| {
                    let big = grid.nodes[j];
                    let hoop = if big > 0.0 { f.r[j] / big } else { f.dr[j] };
                    limit_of_law(self.material, big, &[f.dr[j], hoop, f.lambda, f.r[j] * f.psi], s)
                })
            },
        )
    }

    /// A sequence of equilibria along `loadings` (all of the same kind, e.g.
    /// stretches at zero torque, or pressures), each started from the
    /// previous one. The grid is chosen once, by the adaptive solve of the
    /// last loading (normally the most deformed) or `opts.intervals`, and
    /// every state reports that solve's error estimate. `progress(i, state)`
    /// is called after each state; returning false stops the sweep cleanly
    /// (`cancelled` is set and the states so far are returned).
    pub fn sweep(
        &self,
        loadings: &[Loading],
        opts: &SolveOptions,
        progress: impl FnMut(usize, &TubeState) -> bool,
    ) -> Result<Sweep> {
        let Some(last) = loadings.last() else {
            return Ok(Sweep { states: vec![], cancelled: false });
        };
        validate_sweep(loadings, last, "last", |l| self.check_solid(l))?;
        let (n, estimate) = match opts.intervals {
            Some(n) => (n, 0.0),
            None => {
                let end = self.solve(last, opts)?;
                (end.intervals, end.error_estimate)
            }
        };
        let mut grid = self.grid(n, &[]);
        let mut layout = self.layout(last, &grid);
        let mut x = self.initial_guess(&grid, &layout);
        let mut from = last.rest();
        Sweep::run(loadings, progress, |loading| {
            let mut iterations = self.continue_to(&grid, &layout, &mut x, &from, loading)?;
            // Switch radii move along the sweep: the pieces follow them.
            self.resolve_switches(n, &mut grid, &mut layout, loading, &mut x, &mut iterations)?;
            let mut state = self.state(&grid, &layout, loading, &x)?;
            state.newton_iterations = iterations;
            state.error_estimate = estimate;
            self.check_stability(&grid, &state)?;
            from = *loading;
            Ok(state)
        })
    }

    /// Chebyshev in ln R for a hollow tube (spectral even when A ≪ B). A
    /// solid compressible cylinder is a tube with a traction-free pinhole of
    /// radius [`PINHOLE`]·B on the same kind of grid (near the axis an
    /// anisotropic field goes like R^k, non-integer k, which only ln R
    /// resolves spectrally; the pinhole's core is added back to the
    /// resultants); a solid incompressible one uses a grid in R with the
    /// explicit r = R/√λ.
    /// With `breaks`, one piece between each pair of consecutive breakpoints
    /// (at least 6 intervals each; see [`Self::resolve_switches`]).
    fn grid(&self, n: usize, breaks: &[f64]) -> PiecewiseGrid {
        let b = self.outer_radius;
        if self.inner_radius > 0.0 {
            PiecewiseGrid::new(n, self.inner_radius, b, breaks, true, 6)
        } else if self.material.incompressible() {
            PiecewiseGrid::new(n, 0.0, b, breaks, false, 6)
        } else {
            PiecewiseGrid::new(n, PINHOLE * b, b, breaks, true, 6)
        }
    }

    /// `n` in the layout is the node count − 1 (interface nodes counted twice).
    fn layout(&self, loading: &Loading, grid: &PiecewiseGrid) -> Layout {
        let n = grid.nodes.len() - 1;
        let base = if self.material.incompressible() { 1 } else { 2 * (n + 1) };
        let (stretch, twist) = load_unknowns(loading, base);
        Layout { n, stretch, twist }
    }

    fn initial_guess(&self, grid: &PiecewiseGrid, layout: &Layout) -> DVector<f64> {
        let mut x = if self.material.incompressible() {
            DVector::from_element(1, self.inner_radius)
        } else {
            // r = R and σ_rr = 0: the stress-free state.
            grid.nodes.clone().resize_vertically(2 * (layout.n + 1), 0.0)
        };
        let extra = layout.stretch.is_some() as usize + layout.twist.is_some() as usize;
        let len = x.len();
        x = x.resize_vertically(len + extra, 0.0);
        if let Some(i) = layout.stretch {
            x[i] = 1.0;
        }
        x
    }

    /// How far the kinematic unknowns moved from `a` to `b` (see
    /// [`MAX_INCREMENT_CHANGE`]): the radii per B, λ and ψB; the stresses of
    /// a compressible wall follow from them and are left out.
    fn kinematic_change(&self, layout: &Layout, a: &DVector<f64>, b: &DVector<f64>) -> f64 {
        let big = self.outer_radius;
        let radii = if self.material.incompressible() { 1 } else { layout.n + 1 };
        let mut moved = (0..radii).map(|k| (a[k] - b[k]).abs() / big).fold(0.0, f64::max);
        if let Some(i) = layout.stretch {
            moved = moved.max((a[i] - b[i]).abs());
        }
        if let Some(i) = layout.twist {
            moved = moved.max((a[i] - b[i]).abs() * big);
        }
        moved
    }

    fn newton(&self, grid: &PiecewiseGrid, layout: &Layout, loading: &Loading, x: &mut DVector<f64>) -> Result<usize> {
        let b = self.outer_radius;
        let m = layout.n + 1;
        let incompressible = self.material.incompressible();
        let typical = DVector::from_fn(x.len(), |k, _| {
            if Some(k) == layout.stretch {
                1.0
            } else if Some(k) == layout.twist {
                1.0 / b
            } else if !incompressible && k >= m {
                self.modulus
            } else {
                b
            }
        });
        // The residual's round-off grows like n²ε (first derivatives only),
        // times B/t for a thin wall (r' = Dr differences radii ~B across t):
        // without that factor Newton failed on walls of t/R = 1e−3 with
        // max |F| ≈ 2e−10 at its best (measured).
        let thinness = b / (b - self.inner_radius);
        let opts = NewtonOptions {
            step_tol: 1e-12,
            residual_tol: (64.0 * (m * m) as f64 * f64::EPSILON * thinness).max(1e-11),
            max_iterations: 60,
            reuse_jacobian: true,
        };
        let residual = |x: &DVector<f64>, f: &mut DVector<f64>| self.residual(grid, layout, loading, x, f);
        let report = if incompressible {
            // At most three unknowns: differences are cheap and accurate.
            newton::solve(x, &typical, &opts, residual)?
        } else {
            let jacobian = |x: &DVector<f64>, j: &mut DMatrix<f64>| self.jacobian(grid, layout, loading, x, j);
            newton::solve_with_jacobian(x, &typical, &opts, residual, Some(jacobian))?
        };
        Ok(report.iterations)
    }

    /// Jacobian of the compressible residual, assembled from the local
    /// derivatives ∂σ/∂(a, b, λ, γ) at each node (central differences of the
    /// law, 8 evaluations a node) and the chain rule through a = Dr, b = r/R,
    /// γ = rψ: O(n) law evaluations instead of O(n²) for differencing the
    /// whole residual, and no n²-amplified round-off in the columns.
    fn jacobian(
        &self,
        grid: &PiecewiseGrid,
        layout: &Layout,
        loading: &Loading,
        x: &DVector<f64>,
        jac: &mut DMatrix<f64>,
    ) -> bool {
        let Some(fields) = self.fields(grid, layout, loading, x) else { return false };
        let Some(ds) = self.stress_derivatives(grid, &fields) else { return false };
        let chain = StressChain { ds, nodes: &grid.nodes, diff: &grid.diff, psi: fields.psi };
        jac.fill(0.0);
        self.collocation_rows(grid, layout, x, &fields, &chain, jac);
        self.resultant_rows(grid, layout, loading, &fields, &chain, jac);
        true
    }

    /// ∂σ/∂q at every node for the local deformation modes q = (a, b, λ, γ)
    /// (a = r', b = r/R or r' on the axis, γ = rψ), by central differences
    /// of the law with steps 1e−6·max(|q|, 1); None where a derivative is not
    /// finite.
    fn stress_derivatives(&self, grid: &PiecewiseGrid, f: &Fields) -> Option<Vec<[Matrix3<f64>; 4]>> {
        let (rr, r, dr) = (&grid.nodes, &f.r, &f.dr);
        let mut ds = Vec::with_capacity(rr.len());
        for j in 0..rr.len() {
            let hoop = if rr[j] > 0.0 { r[j] / rr[j] } else { dr[j] };
            let x0 = [dr[j], hoop, f.lambda, r[j] * f.psi];
            let mut dj = [Matrix3::zeros(); 4];
            for (q, dq) in dj.iter_mut().enumerate() {
                let h = 1e-6 * x0[q].abs().max(1.0);
                let at = |t: f64| {
                    let mut y = x0;
                    y[q] += t;
                    self.material.cauchy(rr[j], &WallStrain::from_modes(y))
                };
                *dq = (at(h) - at(-h)) / (2.0 * h);
            }
            if !dj.iter().all(|m| m.iter().all(|v| v.is_finite())) {
                return None;
            }
            ds.push(dj);
        }
        Some(ds)
    }

    /// The constitutive rows (0..m) and equilibrium rows (m..2m) of the
    /// Jacobian: the derivatives of the residual's collocation rows (see
    /// [`Self::residual`]) with respect to r_k, s_k = σ_rr and λ, ψ.
    fn collocation_rows(
        &self,
        grid: &PiecewiseGrid,
        layout: &Layout,
        x: &DVector<f64>,
        f: &Fields,
        chain: &StressChain,
        jac: &mut DMatrix<f64>,
    ) {
        let (n, m) = (layout.n, layout.n + 1);
        let (r, dr, sigma, ds) = (&f.r, &f.dr, &f.sigma, &chain.ds);
        let d = &grid.diff;
        let (mu, b_out, len) = (self.modulus, self.outer_radius, self.outer_radius - self.inner_radius);
        let solid = grid.nodes[0] == 0.0; // a grid through the axis (not a pinhole)
        let (rr_c, tt_c) = ((0, 0), (1, 1));
        let interfaces = grid.interfaces();
        let srr = x.rows(m, m);
        let dsrr = d * srr;
        for j in 0..m {
            // Constitutive rows.
            if j == 0 && solid {
                jac[(0, 0)] = 1.0 / b_out;
            } else {
                for k in 0..m {
                    jac[(j, k)] = chain.dsig_dr(j, rr_c, k) / mu;
                }
                jac[(j, m + j)] = -1.0 / mu;
                if let Some(i) = layout.stretch {
                    jac[(j, i)] = ds[j][2][rr_c] / mu;
                }
                if let Some(i) = layout.twist {
                    jac[(j, i)] = ds[j][3][rr_c] * r[j] / mu;
                }
            }
            // Equilibrium rows (continuity across breakpoints).
            let row = m + j;
            if interfaces.contains(&j) {
                jac[(row, j)] = 1.0 / b_out;
                jac[(row, j + 1)] = -1.0 / b_out;
            } else if j > 0 && interfaces.contains(&(j - 1)) {
                jac[(row, m + j - 1)] = 1.0 / mu;
                jac[(row, m + j)] = -1.0 / mu;
            } else if j == n || (j == 0 && !solid) {
                jac[(row, m + j)] = 1.0 / mu;
            } else if j == 0 {
                for k in 0..m {
                    jac[(row, m + k)] = d[(0, k)] * len / mu;
                }
            } else {
                let jump = sigma[j][(1, 1)] - srr[j];
                for k in 0..m {
                    let dr_k = if j == k { dsrr[j] } else { 0.0 };
                    jac[(row, k)] = (dr_k - chain.dsig_dr(j, tt_c, k) * dr[j] - jump * d[(j, k)]) / mu;
                    jac[(row, m + k)] = r[j] * d[(j, k)] / mu;
                }
                jac[(row, m + j)] += dr[j] / mu;
                if let Some(i) = layout.stretch {
                    jac[(row, i)] = -ds[j][2][tt_c] * dr[j] / mu;
                }
                if let Some(i) = layout.twist {
                    jac[(row, i)] = -ds[j][3][tt_c] * r[j] * dr[j] / mu;
                }
            }
        }
    }

    /// The rows of the prescribed force and torque: F = 2π Σ w σ_zz r a
    /// (with the cap pressures for closed ends), T = 2π Σ w σ_θz r² a,
    /// differentiated in r_k (through σ, r and a = Dr) and in λ, ψ.
    fn resultant_rows(
        &self,
        grid: &PiecewiseGrid,
        layout: &Layout,
        loading: &Loading,
        f: &Fields,
        chain: &StressChain,
        jac: &mut DMatrix<f64>,
    ) {
        let (n, m) = (layout.n, layout.n + 1);
        let (r, dr, sigma, ds) = (&f.r, &f.dr, &f.sigma, &chain.ds);
        let (d, w) = (&grid.diff, &grid.weights);
        let (mu, b_out) = (self.modulus, self.outer_radius);
        let (zz_c, tz_c) = ((2, 2), (1, 2));
        let resultant_row = |i: usize, c: (usize, usize), power: i32, scale: f64, jac: &mut DMatrix<f64>| {
            for k in 0..m {
                let mut v = 0.0;
                for j in 0..m {
                    let rp = r[j].powi(power);
                    v += w[j] * (chain.dsig_dr(j, c, k) * rp * dr[j] + sigma[j][c] * rp * d[(j, k)]);
                }
                v += w[k] * sigma[k][c] * power as f64 * r[k].powi(power - 1) * dr[k];
                jac[(i, k)] = 2.0 * PI * v / scale;
            }
            if let Some(l) = layout.stretch {
                jac[(i, l)] =
                    2.0 * PI * (0..m).map(|j| w[j] * ds[j][2][c] * r[j].powi(power) * dr[j]).sum::<f64>() / scale;
            }
            if let Some(t) = layout.twist {
                jac[(i, t)] =
                    2.0 * PI * (0..m).map(|j| w[j] * ds[j][3][c] * r[j].powi(power + 1) * dr[j]).sum::<f64>() / scale;
            }
        };
        if let Some(i) = layout.stretch {
            let scale = mu * PI * b_out * b_out;
            resultant_row(i, zz_c, 1, scale, jac);
            if loading.ends == Ends::Closed {
                jac[(i, 0)] -= 2.0 * PI * r[0] * loading.inner_pressure / scale;
                jac[(i, n)] += 2.0 * PI * r[n] * loading.outer_pressure / scale;
            }
        }
        if let Some(i) = layout.twist {
            resultant_row(i, tz_c, 2, mu * PI * b_out * b_out * b_out, jac);
        }
    }

    fn prescribed(&self, layout: &Layout, loading: &Loading, x: &DVector<f64>) -> (f64, f64) {
        stretch_and_twist(loading, layout.stretch, layout.twist, x)
    }

    /// λ, ψ, the deformed radius r, its derivative r' and the Cauchy stress
    /// at each node of the solution `x`; `None` outside the domain (r or
    /// r' ≤ 0, λ ≤ 0, non-finite).
    fn fields(&self, grid: &PiecewiseGrid, layout: &Layout, loading: &Loading, x: &DVector<f64>) -> Option<Fields> {
        let (lambda, psi) = self.prescribed(layout, loading, x);
        if !(lambda > 0.0) {
            return None;
        }
        let rr = &grid.nodes;
        let m = layout.n + 1;
        let (r, dr) = if self.material.incompressible() {
            let a = x[0];
            if a < 0.0 {
                return None;
            }
            let a2 = if self.inner_radius > 0.0 { a * a } else { 0.0 };
            let r = rr.map(|big| (a2 + (big * big - self.inner_radius * self.inner_radius) / lambda).sqrt());
            let dr = DVector::from_fn(m, |j, _| if r[j] > 0.0 { rr[j] / (lambda * r[j]) } else { 1.0 / lambda.sqrt() });
            (r, dr)
        } else {
            let r = x.rows(0, m).into_owned();
            let dr = &grid.diff * &r;
            (r, dr)
        };
        let mut sigma = Vec::with_capacity(m);
        for j in 0..m {
            let hoop = if rr[j] > 0.0 { r[j] / rr[j] } else { dr[j] };
            if !(dr[j] > 0.0 && hoop > 0.0) {
                return None;
            }
            let strain = WallStrain { radial: dr[j], hoop, axial: lambda, shear: r[j] * psi };
            let s = self.material.cauchy(rr[j], &strain);
            if !s.iter().all(|v| v.is_finite()) {
                return None;
            }
            sigma.push(s);
        }
        Some(Fields { lambda, psi, r, dr, sigma })
    }

    /// Radial stress through the wall for an incompressible law (the
    /// multiplier eliminated): σ_rr(A) = −p plus the integral of equilibrium;
    /// for a solid cylinder, anchored at σ_rr(B) = −p_o instead.
    fn incompressible_radial_stress(
        &self,
        grid: &PiecewiseGrid,
        r: &DVector<f64>,
        dr: &DVector<f64>,
        sigma: &[Matrix3<f64>],
        loading: &Loading,
    ) -> DVector<f64> {
        let m = r.len();
        let g =
            DVector::from_fn(
                m,
                |j, _| if r[j] > 0.0 { (sigma[j][(1, 1)] - sigma[j][(0, 0)]) * dr[j] / r[j] } else { 0.0 },
            );
        let cum = grid.cumulative_integral(&g);
        if self.inner_radius > 0.0 {
            cum.map(|c| c - loading.inner_pressure)
        } else {
            let total = cum[m - 1];
            cum.map(|c| -loading.outer_pressure - (total - c))
        }
    }

    fn residual(
        &self,
        grid: &PiecewiseGrid,
        layout: &Layout,
        loading: &Loading,
        x: &DVector<f64>,
        f: &mut DVector<f64>,
    ) -> bool {
        let Some(Fields { r, dr, sigma, .. }) = self.fields(grid, layout, loading, x) else { return false };
        let (a_len, b) = (self.outer_radius - self.inner_radius, self.outer_radius);
        let mu = self.modulus;
        let n = layout.n;
        let resultants = if self.material.incompressible() {
            let srr = self.incompressible_radial_stress(grid, &r, &dr, &sigma, loading);
            // Hollow: σ_rr(B) = −p_o closes the problem for a.
            f[0] = if self.inner_radius > 0.0 { (srr[n] + loading.outer_pressure) / mu } else { x[0] / b };
            self.resultants(grid, &r, &dr, &sigma, Some(&srr))
        } else {
            // First-order collocation in (r, s = σ_rr): the residual holds
            // first derivatives only, so its round-off grows like n²ε, not n⁴ε.
            // Rows 0..m: s_j = σ_rr(r'_j, …) (r(0) = 0 at a solid's axis).
            // Rows m..2m: s' = (σ_θθ − s) r'/r inside, s(A) = −p (s'(0) = 0 at
            // a solid's axis) and s(B) = −p_o at the ends.
            // Across a breakpoint (left copy i, right copy i + 1): r and s
            // continuous, in place of the two copies' equilibrium rows.
            let m = n + 1;
            let srr = x.rows(m, m);
            let dsrr = &grid.diff * srr;
            let interfaces = grid.interfaces();
            for j in 0..m {
                let axis = grid.nodes[0] == 0.0;
                f[j] = if j == 0 && axis { r[0] / b } else { (sigma[j][(0, 0)] - srr[j]) / mu };
                f[m + j] = if interfaces.contains(&j) {
                    (r[j] - r[j + 1]) / b
                } else if j > 0 && interfaces.contains(&(j - 1)) {
                    (srr[j - 1] - srr[j]) / mu
                } else if j == n {
                    (srr[n] + loading.outer_pressure) / mu
                } else if j == 0 && !axis {
                    (srr[0] + loading.inner_pressure) / mu
                } else if j == 0 {
                    dsrr[0] * a_len / mu // s'(0) = 0
                } else {
                    // Multiplied by r: well scaled near a small hole.
                    (r[j] * dsrr[j] - (sigma[j][(1, 1)] - srr[j]) * dr[j]) / mu
                };
            }
            self.resultants(grid, &r, &dr, &sigma, None)
        };
        let (wall_force, torque) = resultants;
        if let (Axial::Force(target), Some(i)) = (loading.axial, layout.stretch) {
            let applied = self.applied_force(wall_force, r[0], r[n], loading);
            f[i] = (applied - target) / (mu * PI * b * b);
        }
        if let (Torsion::Torque(target), Some(i)) = (loading.torsion, layout.twist) {
            f[i] = (torque - target) / (mu * PI * b * b * b);
        }
        true
    }

    fn applied_force(&self, wall_force: f64, a: f64, b: f64, loading: &Loading) -> f64 {
        match loading.ends {
            Ends::Open => wall_force,
            Ends::Closed => wall_force - PI * a * a * loading.inner_pressure + PI * b * b * loading.outer_pressure,
        }
    }

    /// (F_wall, T) = (2π∫σ_zz r r' dR, 2π∫σ_θz r² r' dR); for incompressible
    /// laws σ_zz = σ̂_zz − p̂ with p̂ = σ̂_rr − σ_rr.
    fn resultants(
        &self,
        grid: &PiecewiseGrid,
        r: &DVector<f64>,
        dr: &DVector<f64>,
        sigma: &[Matrix3<f64>],
        srr: Option<&DVector<f64>>,
    ) -> (f64, f64) {
        let m = r.len();
        let szz = |j: usize| match srr {
            Some(s) => sigma[j][(2, 2)] - (sigma[j][(0, 0)] - s[j]),
            None => sigma[j][(2, 2)],
        };
        let mut f = 2.0 * PI * grid.integrate(&DVector::from_fn(m, |j, _| szz(j) * r[j] * dr[j]));
        let mut t = 2.0 * PI * grid.integrate(&DVector::from_fn(m, |j, _| sigma[j][(1, 2)] * r[j] * r[j] * dr[j]));
        if self.inner_radius == 0.0 && grid.nodes[0] > 0.0 {
            // The pinhole's core (deformed radius r_0) with the axis field:
            // σ_zz uniform, σ_θz ∝ r: adds πr_0²σ_zz and πr_0³σ_θz/2.
            f += PI * r[0] * r[0] * szz(0);
            t += 0.5 * PI * r[0].powi(3) * sigma[0][(1, 2)];
        }
        (f, t)
    }

    fn state(&self, grid: &PiecewiseGrid, layout: &Layout, loading: &Loading, x: &DVector<f64>) -> Result<TubeState> {
        let Fields { lambda, psi, r, dr, sigma } = self.fields(grid, layout, loading, x).ok_or_else(|| {
            Error::new(Status::ErrNonFiniteResult, "finite-strain tube: converged state is outside the domain")
        })?;
        let n = layout.n;
        let (srr, p_hat) = if self.material.incompressible() {
            let srr = self.incompressible_radial_stress(grid, &r, &dr, &sigma, loading);
            let p_hat: Vec<f64> = (0..=n).map(|j| sigma[j][(0, 0)] - srr[j]).collect();
            (srr, p_hat)
        } else {
            (DVector::from_fn(n + 1, |j, _| sigma[j][(0, 0)]), vec![0.0; n + 1])
        };
        let (wall_force, torque) =
            self.resultants(grid, &r, &dr, &sigma, self.material.incompressible().then_some(&srr));
        let profile = WallProfile {
            reference_radius: grid.nodes.iter().copied().collect(),
            radius: r.iter().copied().collect(),
            sigma_rr: srr.iter().copied().collect(),
            sigma_tt: (0..=n).map(|j| sigma[j][(1, 1)] - p_hat[j]).collect(),
            sigma_zz: (0..=n).map(|j| sigma[j][(2, 2)] - p_hat[j]).collect(),
            sigma_tz: (0..=n).map(|j| sigma[j][(1, 2)]).collect(),
        };
        let state = TubeState {
            stretch: lambda,
            twist: psi,
            wall_force,
            applied_force: self.applied_force(wall_force, r[0], r[n], loading),
            torque,
            inner_pressure: loading.inner_pressure,
            outer_pressure: loading.outer_pressure,
            deformed_inner_radius: if self.inner_radius > 0.0 { r[0] } else { 0.0 },
            deformed_outer_radius: r[n],
            intervals: grid.intervals(),
            error_estimate: 0.0,
            newton_iterations: 0,
            switch_radii: grid.breaks(),
            profile,
        };
        let scalars = [
            state.stretch,
            state.twist,
            state.wall_force,
            state.torque,
            state.deformed_inner_radius,
            state.deformed_outer_radius,
        ];
        error::finite_result("finite-strain tube state", &scalars)?;
        Ok(state)
    }

    /// Local stability of a compressible law: the strain energy must be
    /// convex in the four local deformation modes (a, b, λ, γ) at every node
    /// (second differences of W, Cholesky). Saint Venant–Kirchhoff fails this
    /// in strong compression (its nominal stress turns back below stretch
    /// 1/√3), where the "equilibrium" is not physical.
    fn check_stability(&self, grid: &PiecewiseGrid, state: &TubeState) -> Result<()> {
        if self.material.incompressible() {
            return Ok(());
        }
        let p = &state.profile;
        let n = p.radius.len() - 1;
        let r = DVector::from_vec(p.radius.clone());
        let dr = &grid.diff * &r;
        for j in 0..=n {
            let big = p.reference_radius[j];
            let x0 = [dr[j], if big > 0.0 { r[j] / big } else { dr[j] }, state.stretch, r[j] * state.twist];
            local_stability(self.material, big, &x0)?;
        }
        Ok(())
    }
}

/// Local stability of a compressible law at reference radius `big` and the
/// local modes `x0` = (a, b, λ, γ): the strain energy must be convex in them
/// (second differences of W, Cholesky); ErrMaterialInstability otherwise.
/// Shared by the thick wall (every node) and the membrane (its one layer).
pub(crate) fn local_stability(material: &dyn WallMaterial, big: f64, x0: &[f64; 4]) -> Result<()> {
    let Some(hess) = local_hessian(material, big, x0) else { return Ok(()) };
    if hess.cholesky().is_none() {
        return Err(Error::new(
            Status::ErrMaterialInstability,
            format!(
                "the wall material lost stability at R = {big:e} (stretches radial {:.4}, hoop {:.4}, axial {:.4}, \
                 shear {:.4}): its energy is not convex there. Saint Venant-Kirchhoff does this in strong \
                 compression; use a neo-Hookean law",
                x0[0], x0[1], x0[2], x0[3]
            ),
        ));
    }
    Ok(())
}

/// Hessian of W in the local modes (a, b, λ, γ) at (R, x0), by second
/// differences; None where no stencil avoids a switch of the law.
fn local_hessian(material: &dyn WallMaterial, big: f64, x0: &[f64; 4]) -> Option<nalgebra::Matrix4<f64>> {
    let w = |x: &[f64; 4]| {
        let strain = WallStrain::from_modes(*x);
        material.energy(big, &strain.right_cauchy_green())
    };
    // Differences must not straddle a switch of the law (a fibre family
    // turning on): across that kink the difference Hessian of a convex
    // energy can be indefinite. Shrink the step until no stencil point
    // changes a switch's sign; a point on the switch itself is left alone.
    let h = stencil_step(material, big, x0)?;
    let x0 = *x0;
    // The lower triangle (k ≥ l), mirrored: 40 evaluations of W instead of
    // 64, and the triangle Cholesky and the symmetric eigensolver read.
    let mut hess = nalgebra::Matrix4::zeros();
    for k in 0..4 {
        for l in 0..=k {
            let at = |dk: f64, dl: f64| {
                let mut x = x0;
                x[k] += dk;
                x[l] += dl;
                w(&x)
            };
            hess[(k, l)] = (at(h, h) - at(h, -h) - at(-h, h) + at(-h, -h)) / (4.0 * h * h);
            hess[(l, k)] = hess[(k, l)];
        }
    }
    Some(hess)
}

/// Smallest over largest eigenvalue of the local Hessian (negative when
/// indefinite); None where it cannot be differenced.
fn stiffness_ratio(material: &dyn WallMaterial, big: f64, x0: &[f64; 4]) -> Option<f64> {
    let e = local_hessian(material, big, x0)?.symmetric_eigenvalues();
    let (lo, hi) = (e.min(), e.amax());
    (hi > 0.0 && lo.is_finite()).then_some(lo / hi)
}

/// A load path that stops (Newton fails) where the local stiffness of a
/// compressible law has fallen below [`LIMIT_RATIO`] of its value at rest
/// has met a limit of the law, not a solver weakness: Saint
/// Venant-Kirchhoff's lateral Green strain cannot pass −1/2 (a radial
/// stretch a → 0 at λ = √(1 + 1/ν) in uniaxial tension, where ∂²W/∂a² =
/// a²C_rr → 0) and its compressive force has a maximum. Reported as
/// ErrMaterialInstability with the last state reached, not
/// ErrNotConverged.
pub(crate) fn limit_of_law(material: &dyn WallMaterial, big: f64, x0: &[f64; 4], s: f64) -> Option<Error> {
    if material.incompressible() {
        return None;
    }
    let now = stiffness_ratio(material, big, x0)?;
    let rest = stiffness_ratio(material, big, &[1.0, 1.0, 1.0, 0.0])?;
    (now < LIMIT_RATIO * rest).then(|| {
        Error::new(
            Status::ErrMaterialInstability,
            format!(
                "the wall law reaches its limit on the way to this loading: past load fraction {s:.4} no equilibrium \
                 was found, and there the wall's local stiffness is {:.1e} of its value at rest (R = {big:e}, \
                 stretches radial {:.4}, hoop {:.4}, axial {:.4}, shear {:.4}). Saint Venant-Kirchhoff does this \
                 past its stretch limit (a lateral stretch going to zero) or its compressive force maximum; use a \
                 neo-Hookean law",
                now / rest,
                x0[0],
                x0[1],
                x0[2],
                x0[3]
            ),
        )
    })
}

/// See [`limit_of_law`]. Measured at the last state reached (SVK, isotropic
/// and helical, t/R 0.1 and 0.8, membrane and thick): 2e−3…3e−2 before the
/// stretch limit (λ = 3 asked), 3e−2…5e−2 before the compressive force
/// maximum of a thin wall, negative where the path had already crossed
/// unstable states; 0.15…0.9 where Newton failed for other reasons (fibre
/// walls under outer pressure, strong inflation). Limits found with a ratio
/// above 0.05 stay ErrNotConverged.
pub(crate) const LIMIT_RATIO: f64 = 0.05;

/// Step ≤ 1e−4 of the stability check's differences at (R, x0) such that
/// no stencil point x0 ± h e_k ± h e_l changes the sign of a switching
/// function of the law; None if none ≥ 1e−7 does.
fn stencil_step(material: &dyn WallMaterial, big: f64, x0: &[f64; 4]) -> Option<f64> {
    {
        let switches = material.switches();
        let value = |k: usize, x: &[f64; 4]| {
            let strain = WallStrain::from_modes(*x);
            material.switch_value(k, big, &strain.right_cauchy_green())
        };
        let mut h = 1e-4;
        'shrink: while h >= 1e-7 {
            for s in 0..switches {
                let sign = value(s, x0).signum();
                for k in 0..4 {
                    for l in 0..4 {
                        for (dk, dl) in [(h, h), (h, -h), (-h, h), (-h, -h)] {
                            let mut x = *x0;
                            x[k] += dk;
                            x[l] += dl;
                            if value(s, &x).signum() != sign {
                                h *= 0.25;
                                continue 'shrink;
                            }
                        }
                    }
                }
            }
            return Some(h);
        }
        None
    }
}

pub(crate) fn validate(loading: &Loading) -> Result<()> {
    match loading.axial {
        Axial::Stretch(l) => {
            error::positive("stretch", l)?;
        }
        Axial::Force(f) => {
            error::finite("force", f)?;
        }
    }
    match loading.torsion {
        Torsion::Twist(p) => error::finite("twist", p)?,
        Torsion::Torque(t) => error::finite("torque", t)?,
    };
    error::finite("inner_pressure", loading.inner_pressure)?;
    error::finite("outer_pressure", loading.outer_pressure)?;
    Ok(())
}

/// Every loading of a sweep valid (and passing the solver's own `check`) and
/// of the same kind as `reference` (the `which` loading: "first" or "last"):
/// a sweep varies values, not kinds.
pub(crate) fn validate_sweep(
    loadings: &[Loading],
    reference: &Loading,
    which: &str,
    check: impl Fn(&Loading) -> Result<()>,
) -> Result<()> {
    for (i, l) in loadings.iter().enumerate() {
        validate(l)?;
        check(l)?;
        if !l.same_kind(reference) {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!("sweep loading {i} prescribes other quantities than the {which} one: a sweep varies values, not kinds"),
            ));
        }
    }
    Ok(())
}

impl Sweep {
    /// The states of `solve` at each loading in order; `progress(i, state)`
    /// after each, and false from it stops the sweep cleanly (`cancelled`,
    /// the states so far returned).
    pub(crate) fn run(
        loadings: &[Loading],
        mut progress: impl FnMut(usize, &TubeState) -> bool,
        mut solve: impl FnMut(&Loading) -> Result<TubeState>,
    ) -> Result<Sweep> {
        let mut states = Vec::with_capacity(loadings.len());
        for (i, loading) in loadings.iter().enumerate() {
            let state = solve(loading)?;
            let go_on = progress(i, &state);
            states.push(state);
            if !go_on {
                return Ok(Sweep { states, cancelled: true });
            }
        }
        Ok(Sweep { states, cancelled: false })
    }
}

/// Largest change of a kinematic unknown (a stretch, a radius per B, ψB) that
/// one increment of [`load_homotopy`] may make. Newton started far from the
/// answer can converge to another root of the same equations: from rest
/// straight to λ = 1.0575 at zero torque, an auxetic helical SVK wall
/// (ν12 = −0.19, E2/E1 = 18.6) lands on a collapsed root with hoop stretch
/// 0.017 where the branch has 0.947, a change of 0.98 against 0.053. A
/// root that far from where the increment started is not taken: the
/// increment is halved, so the path stays on the branch it starts on. A
/// legitimate increment that moves more is only split (a stretch that changes
/// by 2 takes at least 8 increments).
pub(crate) const MAX_INCREMENT_CHANGE: f64 = 0.25;

/// From the solution `x` at the loading `from`, reach `to`: `newton(loading,
/// x)` (returning its iterations) straight there, and on failure along the
/// straight load path in bisected increments (load homotopy, at most 2⁸
/// increments); `x` is updated. Returns the Newton iterations. `what` names
/// the solver in the error. `change(x, trial)` measures how far an
/// increment moved the kinematic unknowns (in stretch units); an increment
/// that converges more than [`MAX_INCREMENT_CHANGE`] away is refused as a
/// jump to another root and halved like a failed one.
pub(crate) fn load_homotopy(
    x: &mut DVector<f64>,
    from: &Loading,
    to: &Loading,
    what: &str,
    mut newton: impl FnMut(&Loading, &mut DVector<f64>) -> Result<usize>,
    change: impl Fn(&DVector<f64>, &DVector<f64>) -> f64,
    diagnose: impl Fn(&Loading, &DVector<f64>, f64) -> Option<Error>,
) -> Result<usize> {
    let (mut s_done, mut ds, mut iterations) = (0.0f64, 1.0f64, 0);
    while s_done < 1.0 {
        let s = (s_done + ds).min(1.0);
        let mut trial = x.clone();
        let step = newton(&from.lerp(to, s), &mut trial).and_then(|it| {
            let moved = change(x, &trial);
            if moved <= MAX_INCREMENT_CHANGE {
                Ok(it)
            } else {
                Err(Error::new(
                    Status::ErrNotConverged,
                    format!(
                        "the increment to load fraction {s:.4} converged to a state {moved:.2} away (stretch units), \
                         another root than the branch followed"
                    ),
                ))
            }
        });
        match step {
            Ok(it) => {
                iterations += it;
                *x = trial;
                s_done = s;
                ds = (2.0 * ds).min(1.0);
            }
            Err(e) => {
                ds *= 0.5;
                if ds < 1.0 / 256.0 {
                    // Why the path stops, judged at the last state reached.
                    if let Some(limit) = diagnose(&from.lerp(to, s_done), x, s_done) {
                        return Err(limit);
                    }
                    return Err(Error::new(
                        e.status,
                        format!("{what}: no equilibrium reached at load fraction {s:.4} ({})", e.message),
                    ));
                }
            }
        }
    }
    Ok(iterations)
}

/// The positions of the unprescribed λ (force given) and ψ (torque given)
/// among the unknowns, after `base` others.
pub(crate) fn load_unknowns(loading: &Loading, base: usize) -> (Option<usize>, Option<usize>) {
    let stretch = matches!(loading.axial, Axial::Force(_)).then_some(base);
    let twist = matches!(loading.torsion, Torsion::Torque(_)).then_some(base + stretch.is_some() as usize);
    (stretch, twist)
}

/// (λ, ψ): the prescribed values, or the unknowns at `stretch` and `twist`
/// where the force or the torque is prescribed instead.
pub(crate) fn stretch_and_twist(
    loading: &Loading,
    stretch: Option<usize>,
    twist: Option<usize>,
    x: &DVector<f64>,
) -> (f64, f64) {
    let lambda = match (loading.axial, stretch) {
        (Axial::Stretch(l), _) => l,
        (_, Some(i)) => x[i],
        _ => unreachable!("force prescribed without a stretch unknown"),
    };
    let psi = match (loading.torsion, twist) {
        (Torsion::Twist(p), _) => p,
        (_, Some(i)) => x[i],
        _ => unreachable!("torque prescribed without a twist unknown"),
    };
    (lambda, psi)
}

/// The stress scale that makes a tube's residual dimensionless: the
/// small-strain response at `radius` (compressible laws) or the
/// multiplier-free stress at rest (incompressible ones).
pub fn stress_scale(material: &dyn WallMaterial, radius: f64) -> Result<f64> {
    let h = 1e-6;
    let c = Matrix3::identity() * (1.0 + 2.0 * h);
    let modulus = (material.pk2(radius, &c).amax() / h).max(material.pk2(radius, &Matrix3::identity()).amax());
    error::positive("material stiffness scale", modulus)
}

/// Largest change of the state's scalars between two grids, in the tube's
/// own scales: radii per B, stretch, twist × B, force per μπB², torque per
/// μπB³ (so a state near rest is not judged by the relative change of tiny
/// resultants).
pub fn state_difference(a: &TubeState, b: &TubeState, outer: f64, modulus: f64) -> f64 {
    let force = modulus * PI * outer * outer;
    let pairs = [
        (a.deformed_inner_radius - b.deformed_inner_radius) / outer,
        (a.deformed_outer_radius - b.deformed_outer_radius) / outer,
        a.stretch - b.stretch,
        (a.twist - b.twist) * outer,
        (a.wall_force - b.wall_force) / force,
        (a.torque - b.torque) / (force * outer),
    ];
    pairs.iter().map(|v| v.abs()).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tube::material::NeoHookean;

    /// The assembled Jacobian equals central differences of the residual
    /// (reference: the definition), at a deformed non-equilibrium state with
    /// force and torque prescribed, closed ends, hollow and solid.
    #[test]
    fn analytic_jacobian_matches_differences() {
        let nh = NeoHookean { shear_modulus: 1.3, lame_lambda: 2.0, incompressible: false };
        // The hollow tube also on two pieces (continuity rows at the break).
        for (inner, breaks) in [(0.4, &[][..]), (0.4, &[0.75][..]), (0.0, &[][..])] {
            let tube = FiniteTube::new(inner, 1.1, &nh).unwrap();
            let p_in = if inner > 0.0 { 0.2 } else { 0.0 };
            let loading = Loading {
                axial: Axial::Force(0.3),
                torsion: Torsion::Torque(0.1),
                inner_pressure: p_in,
                outer_pressure: 0.05,
                ends: Ends::Closed,
            };
            // The solid's pinhole grid spans 14 e-folds of R: more nodes.
            let n = if inner > 0.0 { 10 } else { 32 };
            let grid = tube.grid(n, breaks);
            let layout = tube.layout(&loading, &grid);
            let m = grid.nodes.len();
            let mut x = DVector::zeros(2 * m + 2);
            for j in 0..m {
                let big = grid.nodes[j];
                x[j] = big * (1.05 + 0.1 * big * big); // r
                x[m + j] = 0.1 * (big - 0.5); // s
            }
            x[2 * m] = 1.2; // λ
            x[2 * m + 1] = 0.3; // ψ
            let mut jac = DMatrix::zeros(x.len(), x.len());
            assert!(tube.jacobian(&grid, &layout, &loading, &x, &mut jac));
            let (mut fp, mut fm) = (DVector::zeros(x.len()), DVector::zeros(x.len()));
            for k in 0..x.len() {
                // Steps that move every strain by ~1e-6: through a = Dr an r
                // column is amplified by max|D_jk| (up to 1e7 at the pinhole,
                // where the rows also sum terms of 1e5 that cancel, so the
                // differences there are good to ~1e-5 only).
                let h = if k < m {
                    1e-6 / (0..m).map(|j| grid.diff[(j, k)].abs()).fold(1.0, f64::max)
                } else {
                    1e-6 * x[k].abs().max(1.0)
                };
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[k] += h;
                xm[k] -= h;
                assert!(tube.residual(&grid, &layout, &loading, &xp, &mut fp));
                assert!(tube.residual(&grid, &layout, &loading, &xm, &mut fm));
                let col = (&fp - &fm) / (2.0 * h);
                let err = (&col - jac.column(k)).amax();
                // The differences are noisier across the pinhole (D ~ 1e7 there).
                let tol = if inner > 0.0 { 1e-6 } else { 1e-4 };
                let worst = (0..col.len())
                    .max_by(|&a, &b| (col[a] - jac[(a, k)]).abs().partial_cmp(&(col[b] - jac[(b, k)]).abs()).unwrap())
                    .unwrap();
                assert!(
                    err < tol * col.amax().max(1.0),
                    "inner {inner}: column {k}: error {err:e} of {:e} at row {worst}: {} vs {}",
                    col.amax(),
                    col[worst],
                    jac[(worst, k)]
                );
            }
        }
    }
}

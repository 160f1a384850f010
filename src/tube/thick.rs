//! Thick-walled tube, linear theory about the stress-free state
//! (`physics.md` §1.4 "Thick tube"): the radial equilibrium ODE with
//! R-dependent coefficients (the helix angle α(R) = atan(τ0 R) varies through
//! the wall), solved by Chebyshev collocation ([`crate::chebyshev`]).
//!
//! Displacement u_R = u(R), u_Θ = ψZR, u_Z = εZ, so the only strains are
//! ε_ZZ = ε, ε_ΘΘ = u/R, ε_RR = u', γ_ZΘ = ψR and the stresses follow from
//! the rotated stiffness ℂ̄(R). Equilibrium (R σ_RR)' = σ_ΘΘ on A < R < B.
//!
//! Reported in the inner-radius variables of §1.4: e = (ε, ψ, ε_A = u(A)/A),
//! f = (F, T, 2πA²p) with p the inner pressure, open ends, free outer
//! surface; K is computed column by column from three unit cases with u(A)
//! prescribed and σ_RR(B) = 0, and p = −σ_RR(A).
//!
//! Incompressible: W restricted to tr ε = 0 with a pressure multiplier. Then
//! u = −εR/2 + D/R is explicit, D = A²(ε_A + ε/2), and the multiplier follows
//! from integrating equilibrium: no ODE is left, only quadrature.

use crate::chebyshev::ChebyshevGrid;
use crate::error::{self, Error, Result};
use crate::status::Status;
use crate::tube::coupling::{CouplingStiffness, StretchTwist};
use crate::tube::orthotropic::{voigt, Orthotropic};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix4};
use std::f64::consts::PI;

/// Whether the wall material is compressible or constrained to tr ε = 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compressibility {
    Compressible,
    Incompressible,
}

/// A thick helically reinforced tube (or solid cylinder when A = 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThickTube {
    /// Inner radius A ≥ 0 (0: solid cylinder).
    pub inner_radius: f64,
    /// Outer radius B > A.
    pub outer_radius: f64,
    /// Intrinsic twist τ0: reinforcement at α(R) = atan(τ0 R).
    pub intrinsic_twist: f64,
    pub material: Orthotropic,
    pub compressibility: Compressibility,
}

/// A result with the resolution used and an error estimate: the difference
/// between grids of n and 1.5n intervals, relative to the largest entry
/// (spectral convergence makes the coarse grid's error a safe, pessimistic
/// upper bound for the fine one's), floored at a round-off level 32·(1.5n)·ε.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimated<T> {
    pub value: T,
    pub intervals: usize,
    pub error_estimate: f64,
}

/// The incompressible wall's displacement u = −εR/2 + D/R with the twist ψ
/// (`dd` = D; D = 0 for a solid cylinder, regular at the axis).
struct IncompressibleField {
    eps: f64,
    psi: f64,
    dd: f64,
}

impl IncompressibleField {
    /// Stress component `row` without the multiplier at radius r, σ̂ =
    /// ℂ̄ (ε, u/R, u', ψR) with u/R = −ε/2 + D/R² and u' = −ε/2 − D/R².
    fn hat(&self, c: &Matrix4<f64>, r: f64, row: usize) -> f64 {
        let (eps, psi, dd) = (self.eps, self.psi, self.dd);
        let w = if dd == 0.0 { 0.0 } else { dd / (r * r) };
        let (hoop, radial) = (-0.5 * eps + w, -0.5 * eps - w);
        c[(row, ZZ)] * eps + c[(row, TT)] * hoop + c[(row, RR)] * radial + c[(row, ZT)] * psi * r
    }

    /// (σ̂_ΘΘ − σ̂_RR)/R at the nodes (0 on the axis): equilibrium gives
    /// σ_RR' = that, so its integral over the wall is the inner pressure p
    /// (σ_RR(B) = 0), linear in D.
    fn jump(&self, grid: &ChebyshevGrid, c: &[Matrix4<f64>]) -> DVector<f64> {
        let r = &grid.nodes;
        DVector::from_fn(r.len(), |j, _| {
            if r[j] > 0.0 {
                (self.hat(&c[j], r[j], TT) - self.hat(&c[j], r[j], RR)) / r[j]
            } else {
                0.0
            }
        })
    }
}

/// Stiffness block excited by the tube kinematics, ordered (ZZ, ΘΘ, RR, ZΘ).
fn tube_block(m: &Orthotropic, alpha: f64) -> Matrix4<f64> {
    let c = m.rotated_stiffness(alpha);
    let k = [voigt::ZZ, voigt::TT, voigt::RR, voigt::ZT];
    Matrix4::from_fn(|i, j| c[(k[i], k[j])])
}
const ZZ: usize = 0;
const TT: usize = 1;

/// Radius of the traction-free pinhole that stands in for the axis of a
/// solid compressible cylinder, relative to the outer radius.
pub const PINHOLE: f64 = 1e-6;

/// Condition on the inner surface of the linear problem.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Inner {
    /// u(A) = A ε_A (columns of K).
    Displacement,
    /// σ_RR(A) = 0 (p = 0: the condensed stretch–twist law).
    TractionFree,
}

/// The wall set up for the linear problem: its collocation grid, the
/// stiffness block at each node, and the inner surface's condition (what
/// the compressible and the incompressible solves share).
struct Collocation {
    grid: ChebyshevGrid,
    c: Vec<Matrix4<f64>>,
    inner: Inner,
}

const RR: usize = 2;
const ZT: usize = 3;

impl ThickTube {
    pub fn new(
        inner_radius: f64,
        outer_radius: f64,
        intrinsic_twist: f64,
        material: Orthotropic,
        compressibility: Compressibility,
    ) -> Result<Self> {
        error::finite("inner_radius", inner_radius)?;
        if inner_radius < 0.0 {
            return Err(Error::new(
                Status::ErrInvalidGeometry,
                format!("impossible tube: inner radius {inner_radius:e} is negative"),
            ));
        }
        error::positive("outer_radius", outer_radius)?;
        error::finite("intrinsic_twist", intrinsic_twist)?;
        if !(inner_radius < outer_radius) {
            return Err(Error::new(
                Status::ErrInvalidGeometry,
                format!(
                    "impossible tube: inner radius {inner_radius:e} must be below the outer radius {outer_radius:e}"
                ),
            ));
        }
        Ok(ThickTube { inner_radius, outer_radius, intrinsic_twist, material, compressibility })
    }

    /// Coupling stiffness K in (ε, ψ, ε_A) ↔ (F, T, 2πA²p), computed on
    /// `intervals` Chebyshev intervals (symmetrised: collocation is not a
    /// Galerkin method, and the asymmetry is within the discretisation error).
    pub fn coupling_stiffness_at(&self, intervals: usize) -> Result<CouplingStiffness> {
        if self.inner_radius == 0.0 {
            return Err(Error::new(
                Status::ErrInvalidGeometry,
                "a solid cylinder (inner radius 0) has no inner hoop strain: use stretch_twist",
            ));
        }
        error::count_in_range("intervals", intervals as i64, 4, 512)?;
        let cols = self.unit_responses(intervals, &[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])?;
        let k = Matrix3::from_fn(|i, j| cols[j][i]);
        CouplingStiffness::new((k + k.transpose()) * 0.5, self.intrinsic_twist)
    }

    /// K to a relative tolerance: doubles the grid from 8 intervals until the
    /// estimate (difference from a 1.5× finer grid, relative to max |K|)
    /// is below `rel_tol`; returns the finer result.
    pub fn coupling_stiffness(&self, rel_tol: f64) -> Result<Estimated<CouplingStiffness>> {
        error::in_range("rel_tol", rel_tol, 1e-15, 1.0)?;
        let mut n = 8;
        loop {
            let coarse = self.coupling_stiffness_at(n)?;
            let fine_n = n + n / 2;
            let fine = self.coupling_stiffness_at(fine_n)?;
            // Floor: the round-off level. Measured ≈ 200ε flat in n for walls
            // of t/R ≳ 0.01 (bounded by 32nε), and growing like ε·n·B/t for
            // thinner ones (the ln R interval shrinks with t: 1e-10…1e-9 at
            // t/R = 1e-6, benches/tube.rs), bounded by n·ε·B/t.
            let thinness = self.outer_radius / (self.outer_radius - self.inner_radius);
            let roundoff = (32.0 * fine_n as f64 * f64::EPSILON).max(fine_n as f64 * f64::EPSILON * thinness);
            let diff = (fine.k - coarse.k).amax() / fine.k.amax();
            let est = diff.max(roundoff);
            // Converged to round-off that is itself above the tolerance: more
            // intervals cannot help, say so now.
            let stuck = diff <= roundoff && roundoff > rel_tol;
            if est <= rel_tol || fine_n >= 384 || stuck {
                if stuck {
                    // Not a failure to converge but a tolerance below what
                    // round-off allows; say the best reachable.
                    return Err(Error::new(
                        Status::ErrToleranceUnreachable,
                        format!(
                            "thick-tube stiffness: rel_tol {rel_tol:e} is below the round-off of this thin wall; the \
                             best reachable is about {est:.1e} (its thin-tube limit is the better model)"
                        ),
                    ));
                }
                if est > rel_tol {
                    return Err(Error::new(
                        Status::ErrNotConverged,
                        format!(
                            "thick-tube stiffness: estimated error {est:e} above rel_tol {rel_tol:e} at {fine_n} intervals"
                        ),
                    ));
                }
                return Ok(Estimated { value: fine, intervals: fine_n, error_estimate: est });
            }
            n *= 2;
        }
    }

    /// Condensed stretch–twist law at zero pressure. For a solid cylinder
    /// (A = 0) it is computed directly with regularity u(0) = 0.
    pub fn stretch_twist_at(&self, intervals: usize) -> Result<StretchTwist> {
        error::count_in_range("intervals", intervals as i64, 4, 512)?;
        // Solved directly with a traction-free inner surface (p = 0) rather
        // than by condensing K, whose inflation column degenerates as A → 0.
        let cols = self.unit_responses_with(intervals, &[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], Inner::TractionFree)?;
        let g = 0.5 * (cols[0][1] + cols[1][0]);
        Ok(StretchTwist { stretch: cols[0][0], coupling: g, twist: cols[1][1] })
    }

    /// (F, T, 2πA²p) for each prescribed e = (ε, ψ, ε_A), with u(A) = Aε_A.
    fn unit_responses(&self, intervals: usize, cases: &[[f64; 3]]) -> Result<Vec<[f64; 3]>> {
        self.unit_responses_with(intervals, cases, Inner::Displacement)
    }

    /// As [`Self::unit_responses`] with the inner condition given. A solid
    /// compressible cylinder is solved as a tube with a traction-free pinhole
    /// of radius [`PINHOLE`]·B on a grid uniform in ln R: near the axis an
    /// anisotropic wall's field goes like R^k with non-integer k, which a
    /// polynomial in R resolves only algebraically but e^{kξ}, ξ = ln R,
    /// spectrally; the pinhole changes the resultants by O((δ/B)²) ≈ 1e−12.
    /// (A solid incompressible cylinder has the explicit u = −εR/2.)
    fn unit_responses_with(&self, intervals: usize, cases: &[[f64; 3]], inner: Inner) -> Result<Vec<[f64; 3]>> {
        let (a, b) = (self.inner_radius, self.outer_radius);
        let incompressible = self.compressibility == Compressibility::Incompressible;
        let (grid, inner) = if a > 0.0 {
            (ChebyshevGrid::logarithmic(intervals, a, b), inner)
        } else if incompressible {
            (ChebyshevGrid::new(intervals, 0.0, b), inner)
        } else {
            (ChebyshevGrid::logarithmic(intervals, PINHOLE * b, b), Inner::TractionFree)
        };
        let c = grid.nodes.iter().map(|&ri| tube_block(&self.material, (self.intrinsic_twist * ri).atan())).collect();
        let wall = Collocation { grid, c, inner };
        let out = if incompressible { self.incompressible(&wall, cases)? } else { self.compressible(&wall, cases)? };
        for f in &out {
            error::finite_result("thick-tube resultants", f)?;
        }
        Ok(out)
    }

    /// First-order collocation in (u, s = σ_RR), which keeps the conditioning
    /// at O(n²) (the second-order form in u alone is O(n⁴) and loses digits):
    ///   c_rr u' + c_rθ u/R − s = −(c_rz ε + c_r6 ψR)         (constitutive)
    ///   R s' + s − c_θr u' − c_θθ u/R = c_θz ε + c_θ6 ψR      (equilibrium)
    /// with u(A) = Aε_A replacing the first at R = A and s(B) = 0 replacing
    /// the second at R = B. Solid cylinder: u(0) = 0 and s'(0) = 0 (fields
    /// even in R) at the axis.
    fn compressible(&self, wall: &Collocation, cases: &[[f64; 3]]) -> Result<Vec<[f64; 3]>> {
        let (grid, c, inner) = (&wall.grid, &wall.c[..], wall.inner);
        let n = grid.intervals();
        let m = n + 1;
        let (r, d) = (&grid.nodes, &grid.diff);
        let a = r[0];
        let traction_free = inner == Inner::TractionFree;
        let mut l = DMatrix::zeros(2 * m, 2 * m);
        for i in 0..m {
            // Rows 0..m: constitutive relation at nodes 1..n (and at node 0
            // when the inner surface is traction-free); u(A) = Aε_A at node 0
            // otherwise.
            if i == 0 && !traction_free {
                l[(0, 0)] = 1.0;
            } else {
                for j in 0..m {
                    l[(i, j)] = c[i][(RR, RR)] * d[(i, j)];
                }
                l[(i, i)] += c[i][(RR, TT)] / r[i];
                l[(i, m + i)] = -1.0;
            }
            // Rows m..2m: equilibrium at nodes 0..n−1 (1..n−1 with a
            // traction-free inner surface, whose row is σ_RR(A) = 0);
            // σ_RR(B) = 0 at node n.
            let row = m + i;
            if i == n || (i == 0 && traction_free) {
                l[(row, m + i)] = 1.0;
            } else {
                for j in 0..m {
                    l[(row, m + j)] = r[i] * d[(i, j)];
                    l[(row, j)] = -c[i][(TT, RR)] * d[(i, j)];
                }
                l[(row, m + i)] += 1.0;
                l[(row, i)] -= c[i][(TT, TT)] / r[i];
            }
        }
        let lu = l.lu();

        let mut out = Vec::with_capacity(cases.len());
        for &[eps, psi, eps_a] in cases {
            // Parts of the stresses not involving u.
            let loaded = |j: usize, row: usize| c[j][(row, ZZ)] * eps + c[j][(row, ZT)] * psi * r[j];
            let mut rhs = DVector::zeros(2 * m);
            for i in 0..m {
                rhs[i] = if i == 0 && !traction_free { a * eps_a } else { -loaded(i, RR) };
                rhs[m + i] = if i == n || (i == 0 && traction_free) { 0.0 } else { loaded(i, TT) };
            }
            let sol = lu
                .solve(&rhs)
                .ok_or_else(|| Error::new(Status::ErrNotConverged, "thick-tube collocation matrix is singular"))?;
            let u = sol.rows(0, m).into_owned();
            let du = d * &u;
            let stress =
                |j: usize, row: usize| c[j][(row, TT)] * u[j] / r[j] + c[j][(row, RR)] * du[j] + loaded(j, row);
            out.push(self.resultants(grid, |j| stress(j, ZZ), |j| stress(j, ZT), -sol[m]));
        }
        Ok(out)
    }

    fn incompressible(&self, wall: &Collocation, cases: &[[f64; 3]]) -> Result<Vec<[f64; 3]>> {
        let (grid, c, inner) = (&wall.grid, &wall.c[..], wall.inner);
        let (r, a, n) = (&grid.nodes, self.inner_radius, grid.intervals());
        let mut out = Vec::with_capacity(cases.len());
        for &[eps, psi, eps_a] in cases {
            // Solid cylinder: D = 0 (regularity), u = −εR/2. A traction-free
            // inner surface fixes D by σ_RR(A) = 0 instead of by ε_A: the
            // response is linear in D, so solve for it from two evaluations.
            let dd = if a == 0.0 {
                0.0
            } else if inner == Inner::Displacement {
                a * a * (eps_a + 0.5 * eps)
            } else {
                let p_of = |dd: f64| grid.integrate(&IncompressibleField { eps, psi, dd }.jump(grid, c));
                let (p0, p1) = (p_of(0.0), p_of(1.0));
                -p0 / (p1 - p0)
            };
            let field = IncompressibleField { eps, psi, dd };
            let hat = |j: usize, row: usize| field.hat(&c[j], r[j], row);
            // R σ_RR' = σ̂_ΘΘ − σ̂_RR; σ_RR(B) = 0 fixes the constant.
            let cum = grid.cumulative_integral(&field.jump(grid, c));
            let sigma_rr = cum.map(|v| v - cum[n]);
            // Multiplier p̂ = σ̂_RR − σ_RR; σ_ZZ = σ̂_ZZ − p̂.
            let szz = |j: usize| hat(j, ZZ) - (hat(j, RR) - sigma_rr[j]);
            out.push(self.resultants(grid, szz, |j| hat(j, ZT), -sigma_rr[0]));
        }
        Ok(out)
    }

    /// (F, T, 2πA²p) = (2π∫σ_ZZ R dR, 2π∫τ_ZΘ R² dR, 2πA²p).
    fn resultants(
        &self,
        grid: &ChebyshevGrid,
        szz: impl Fn(usize) -> f64,
        szt: impl Fn(usize) -> f64,
        p: f64,
    ) -> [f64; 3] {
        let r = &grid.nodes;
        let mut f = 2.0 * PI * grid.integrate(&DVector::from_fn(r.len(), |j, _| szz(j) * r[j]));
        let mut t = 2.0 * PI * grid.integrate(&DVector::from_fn(r.len(), |j, _| szt(j) * r[j] * r[j]));
        if self.inner_radius == 0.0 && r[0] > 0.0 {
            // The pinhole's core, 0 ≤ R ≤ δ, with the axis values of the
            // field (σ_ZZ uniform, τ_ZΘ ∝ R): adds πδ²σ_ZZ and πδ³τ_ZΘ/2.
            let d = r[0];
            f += PI * d * d * szz(0);
            t += 0.5 * PI * d * d * d * szt(0);
        }
        let a = self.inner_radius;
        [f, t, 2.0 * PI * a * a * p]
    }
}

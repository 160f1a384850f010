//! A tube section as a rod: the 6×6 stiffness of the hemitropic rod law
//! (`physics.md` §2.2) for a helically reinforced tube, ready for the rod
//! solver.
//!
//! Thin-walled beam kinematics on the wall circle of radius R: a rod strain
//! (u, v) (curvature/twist u, shear/stretch v, body frame) strains the wall at
//! angle θ by
//!
//!   ε_zz = ε + R(u1 sin θ − u2 cos θ),   γ_zθ = R u3 − v1 sin θ + v2 cos θ
//!
//! (the in-plane components of v + u × X, X = R(cos θ, sin θ, 0); the radial
//! one is a rotation of the wall normal, free in a membrane). With the hoop
//! stress resultant zero (a rod carries no pressure) the wall's surface law
//! condenses to [N_zz, N_zθ] = t[[a, b], [b, c]][ε_zz, γ_zθ], and integrating
//! the energy over θ gives, with c1 = 0,
//!
//!   S = 2πRt a,  g = 2πR²t b,  C = 2πR³t c       (the condensed §1.4 law)
//!   K_b = πR³t a = R²S/2,  G = πRt c = C/(2R²),  c2 = −πR²t b = −g/2.
//!
//! So the bend–shear coupling c2 of a hemitropic rod is fixed by its
//! twist–stretch coupling: a helically wound tube is chiral in both. G is the
//! thin-wall shear-flow value (shear coefficient 1/2 of a thin circular tube).
//!
//! Thick walls: the stretch–twist block comes from the thick linear theory
//! (exact for these axisymmetric modes), the bending and shear entries from
//! the same kinematics layer by layer with each layer free of radial and hoop
//! stress (K_b = π∫a R³ dR, G = π∫c R dR, c2 = −π∫b R² dR): exact
//! Euler–Bernoulli bending (K_b = Eπ(B⁴ − A⁴)/4 for an isotropic wall), but
//! the shear entries keep the thin-wall shear coefficient 1/2, which
//! underestimates a thick wall's shear stiffness (Cowper's coefficient of a
//! solid isotropic section is 6(1 + ν)/(7 + 6ν) ≈ 0.88). Shear stiffness is
//! rarely what a rod model is sensitive to; the error is stated here.

use crate::chebyshev::ChebyshevGrid;
use crate::error::{self, Error, Result};
use crate::rod::Moduli;
use crate::status::Status;
use crate::tube::coupling::StretchTwist;
use crate::tube::orthotropic::{voigt, Orthotropic};
use crate::tube::thick::{Compressibility, Estimated, ThickTube};
use crate::tube::thin::ThinTube;
use nalgebra::{DMatrix, Matrix2, Matrix6};
use std::f64::consts::PI;

/// Symmetric positive-definite 6×6 rod stiffness in the order of §2.1,
/// (u1, u2, u3, v1, v2, v3) ↔ (m1, m2, m3, n1, n2, n3), of the hemitropic
/// form of §2.2 (c1 = 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RodStiffness {
    pub k: Matrix6<f64>,
}

impl RodStiffness {
    /// The hemitropic form of `moduli` ([`Moduli::stiffness`]); rejects a law
    /// that is not positive definite.
    pub fn from_moduli(moduli: &Moduli) -> Result<Self> {
        let k = moduli.stiffness();
        error::finite_result("rod stiffness", k.as_slice())?;
        if k.cholesky().is_none() {
            return Err(Error::new(
                Status::ErrNotPositiveDefinite,
                // Short: the printed 6×6 matrix made a 1 kB message.
                format!(
                    "rod stiffness is not positive definite: {}",
                    error::eigen_range(k.symmetric_eigenvalues().as_slice())
                ),
            ));
        }
        Ok(RodStiffness { k })
    }

    /// Bending stiffness K_b (force·length²).
    pub fn bending(&self) -> f64 {
        self.k[(0, 0)]
    }
    /// Twist stiffness C (force·length²).
    pub fn twist(&self) -> f64 {
        self.k[(2, 2)]
    }
    /// Shear stiffness G (force).
    pub fn shear(&self) -> f64 {
        self.k[(3, 3)]
    }
    /// Stretch stiffness S (force).
    pub fn stretch(&self) -> f64 {
        self.k[(5, 5)]
    }
    /// Twist–stretch coupling g (force·length).
    pub fn twist_stretch(&self) -> f64 {
        self.k[(2, 5)]
    }
    /// Bend–shear coupling c2 (force·length).
    pub fn bend_shear(&self) -> f64 {
        self.k[(0, 3)]
    }
    /// Column-major entries, ready for a C caller.
    pub fn column_major(&self) -> [f64; 36] {
        let mut out = [0.0; 36];
        out.copy_from_slice(self.k.as_slice());
        out
    }
}

/// Condense a symmetric stiffness onto the `keep` strains with the stresses
/// of the others zero (Schur complement).
/// A block that does not solve (singular to round-off: constants many orders
/// of magnitude apart, or denormal) is ErrNotPositiveDefinite, not a panic
/// (a denormal g13 used to panic here).
fn condense(c: &DMatrix<f64>, keep: &[usize], free: &[usize]) -> Result<Matrix2<f64>> {
    let sub = |rows: &[usize], cols: &[usize]| DMatrix::from_fn(rows.len(), cols.len(), |i, j| c[(rows[i], cols[j])]);
    let (kk, kf, ff) = (sub(keep, keep), sub(keep, free), sub(free, free));
    let solved = ff.lu().solve(&kf.transpose()).filter(|x| x.iter().all(|v| v.is_finite())).ok_or_else(|| {
        Error::new(
            Status::ErrNotPositiveDefinite,
            "wall stiffness is singular to round-off: its constants span too many orders of magnitude",
        )
    })?;
    let schur = kk - &kf * solved;
    error::finite_result("condensed wall stiffness", schur.as_slice())?;
    Ok(Matrix2::new(
        schur[(0, 0)],
        0.5 * (schur[(0, 1)] + schur[(1, 0)]),
        0.5 * (schur[(0, 1)] + schur[(1, 0)]),
        schur[(1, 1)],
    ))
}

/// (a, b, c) of a wall layer at helix angle α: the law in (ε_zz, γ_zθ) with
/// the radial, hoop and transverse-shear stresses zero (incompressible: the
/// radial strain follows from tr ε = 0 and the multiplier takes σ_rr = 0).
fn layer_moduli(material: &Orthotropic, alpha: f64, compressibility: Compressibility) -> Result<Matrix2<f64>> {
    let c6 = material.rotated_stiffness(alpha);
    let c = DMatrix::from_fn(6, 6, |i, j| c6[(i, j)]);
    let (zz, tt, rr, zt) = (voigt::ZZ, voigt::TT, voigt::RR, voigt::ZT);
    let (tr, zr) = (3, 4); // ΘR, ZR
    match compressibility {
        Compressibility::Compressible => condense(&c, &[zz, zt], &[tt, rr, tr, zr]),
        Compressibility::Incompressible => {
            // Strains (ZZ, ΘΘ, ΘR, ZR, ZΘ) with ε_RR = −ε_ZZ − ε_ΘΘ.
            let cols = [zz, tt, tr, zr, zt];
            let mut t = DMatrix::zeros(6, 5);
            for (k, &i) in cols.iter().enumerate() {
                t[(i, k)] = 1.0;
            }
            t[(rr, 0)] = -1.0;
            t[(rr, 1)] = -1.0;
            let reduced = t.transpose() * c * t;
            condense(&reduced, &[0, 4], &[1, 2, 3])
        }
    }
}

impl ThinTube {
    /// The 6×6 rod law of the section (thin-walled beam theory, module docs):
    /// closed form, consistent with [`ThinTube::coupling_stiffness`]'s
    /// condensed stretch–twist law.
    pub fn rod_stiffness(&self) -> Result<RodStiffness> {
        let q = self.material.rotated_stiffness(self.helix_angle());
        let c = DMatrix::from_fn(3, 3, |i, j| q[(i, j)]);
        // Surface axes (Z, Θ, ZΘ): keep Z and ZΘ, free Θ.
        let m = condense(&c, &[0, 2], &[1])?;
        let (r, t) = (self.mid_radius, self.thickness);
        let (a, b, cc) = (m[(0, 0)], m[(0, 1)], m[(1, 1)]);
        RodStiffness::from_moduli(&Moduli::symmetric(
            PI * r.powi(3) * t * a,
            2.0 * PI * r.powi(3) * t * cc,
            PI * r * t * cc,
            2.0 * PI * r * t * a,
            2.0 * PI * r * r * t * b,
            -PI * r * r * t * b,
        ))
    }
}

impl ThickTube {
    /// The 6×6 rod law of a thick section to `rel_tol` (module docs: the
    /// stretch–twist block from the thick theory, bending and shear layer
    /// by layer). The estimate is the larger of the stretch–twist block's
    /// two-grid estimate and the layer quadrature's (two rules compared),
    /// relative to each entry's own scale.
    pub fn rod_stiffness(&self, rel_tol: f64) -> Result<Estimated<RodStiffness>> {
        error::in_range("rel_tol", rel_tol, 1e-14, 1.0)?;
        let st = self.stretch_twist_estimated(rel_tol)?;
        let (a, b) = (self.inner_radius, self.outer_radius);
        let layered = |n: usize| -> Result<[f64; 3]> {
            // Clenshaw–Curtis on [A, B]: the moduli are analytic in R
            // (α = atan(τ0 R) has its poles at ±i/τ0).
            let grid = ChebyshevGrid::new(n, a, b);
            let mut out = [0.0; 3];
            for (j, &r) in grid.nodes.iter().enumerate() {
                let m = layer_moduli(&self.material, (self.intrinsic_twist * r).atan(), self.compressibility)?;
                let w = PI * grid.weights[j];
                out[0] += w * m[(0, 0)] * r.powi(3);
                out[1] += w * m[(1, 1)] * r;
                out[2] -= w * m[(0, 1)] * r * r;
            }
            Ok(out)
        };
        let mut n = 8;
        let mut coarse = layered(n)?;
        loop {
            let fine_n = n * 2;
            let fine = layered(fine_n)?;
            // Scales: K_b, G, and √(K_b G) for the coupling.
            let scale = [fine[0].abs(), fine[1].abs(), (fine[0] * fine[1]).abs().sqrt()];
            let est = (0..3)
                .map(|i| (fine[i] - coarse[i]).abs() / scale[i])
                .fold(32.0 * fine_n as f64 * f64::EPSILON, f64::max);
            if est <= rel_tol || fine_n >= 512 {
                if est > rel_tol {
                    return Err(Error::new(
                        Status::ErrNotConverged,
                        format!("rod law of a thick tube: layer quadrature estimate {est:e} above rel_tol {rel_tol:e}"),
                    ));
                }
                let s = &st.value;
                let law = RodStiffness::from_moduli(&Moduli::symmetric(
                    fine[0], s.twist, fine[1], s.stretch, s.coupling, fine[2],
                ))?;
                return Ok(Estimated {
                    value: law,
                    intervals: st.intervals,
                    error_estimate: est.max(st.error_estimate),
                });
            }
            (n, coarse) = (fine_n, fine);
        }
    }

    /// The condensed stretch–twist law to `rel_tol`: grids growing 1.5×
    /// from 24 intervals until two agree (entries in the scales S, C/B²,
    /// g/B); hollow and solid alike (the traction-free inner surface is
    /// solved directly, see [`ThickTube::stretch_twist_at`]).
    pub fn stretch_twist_estimated(&self, rel_tol: f64) -> Result<Estimated<StretchTwist>> {
        error::in_range("rel_tol", rel_tol, 1e-14, 1.0)?;
        let b = self.outer_radius;
        let thinness = b / (b - self.inner_radius);
        let mut coarse = self.stretch_twist_at(16)?;
        let mut n = 24;
        loop {
            let fine = self.stretch_twist_at(n)?;
            let scale = fine.stretch.abs().max(fine.twist.abs() / (b * b));
            let diff = (fine.matrix() - coarse.matrix()).abs();
            let roundoff = (32.0 * n as f64 * f64::EPSILON).max(n as f64 * f64::EPSILON * thinness);
            let est = (diff[(0, 0)] / scale)
                .max(diff[(0, 1)] / (scale * b))
                .max(diff[(1, 1)] / (scale * b * b))
                .max(roundoff);
            if est <= rel_tol {
                return Ok(Estimated { value: fine, intervals: n, error_estimate: est });
            }
            if roundoff > rel_tol {
                return Err(Error::new(
                    Status::ErrToleranceUnreachable,
                    format!(
                        "thick-tube stretch-twist law: rel_tol {rel_tol:e} is below the round-off of this wall; the \
                         best reachable is about {roundoff:.1e}"
                    ),
                ));
            }
            if n >= 384 {
                return Err(Error::new(
                    Status::ErrNotConverged,
                    format!("thick-tube stretch-twist law: estimated error {est:e} above rel_tol {rel_tol:e} at {n} intervals"),
                ));
            }
            coarse = fine;
            n += n / 2;
        }
    }
}

//! In-surface (plane-stress) orthotropic elasticity of a tube wall and its
//! rotation from the reinforcement axes to the tube's (Z, Θ) axes
//! (`physics.md` §1.1, §1.4).
//!
//! Voigt order (1, 2, 6) = (along the reinforcement, across it, in-plane
//! engineering shear); rotated order (Z, Θ, ZΘ) with γ_zθ engineering shear.
//! The helix angle α is measured from e_Z towards e_Θ.

use crate::error::{self, Error, Result};
use crate::status::Status;
use nalgebra::{Matrix3, Matrix6};

/// Orthotropic constants of the wall in its own surface: Young's moduli along
/// (E1) and across (E2) the reinforcement, the major Poisson ratio ν12
/// (contraction across per extension along), and the in-surface shear
/// modulus G12. Units are the caller's (stress).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrthotropicSurface {
    pub e1: f64,
    pub e2: f64,
    pub nu12: f64,
    pub g12: f64,
}

impl OrthotropicSurface {
    /// Validated constructor: E1, E2, G12 > 0 and the plane-stress compliance
    /// positive definite, i.e. ν12² < E1/E2 (equivalently ν12·ν21 < 1).
    pub fn new(e1: f64, e2: f64, nu12: f64, g12: f64) -> Result<Self> {
        error::positive("e1", e1)?;
        error::positive("e2", e2)?;
        error::finite("nu12", nu12)?;
        error::positive("g12", g12)?;
        // det of the normal block of S: (1 − ν12² E2/E1)/(E1 E2) > 0.
        let margin = 1.0 - nu12 * nu12 * (e2 / e1);
        if !(margin > 0.0) {
            return Err(Error::new(
                Status::ErrNotPositiveDefinite,
                format!(
                    "material is not positive definite: need nu12^2 < e1/e2, got nu12 = {nu12:e}, \
                     e1/e2 = {:e} (nu12*nu21 = {:e} must be < 1)",
                    e1 / e2,
                    nu12 * nu12 * e2 / e1
                ),
            ));
        }
        Ok(OrthotropicSurface { e1, e2, nu12, g12 })
    }

    /// Isotropic wall (E, ν): E1 = E2 = E, G12 = E/(2(1 + ν)).
    pub fn isotropic(e: f64, nu: f64) -> Result<Self> {
        // 3-D isotropy of the wall material: −1 < ν ≤ 1/2 (G12 finite).
        error::finite("nu", nu)?;
        if !(nu > -1.0 && nu <= 0.5) {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!("argument `nu` must lie in (-1, 0.5] for an isotropic material (got {nu:e})"),
            ));
        }
        Self::new(e, e, nu, e / (2.0 * (1.0 + nu)))
    }

    /// The Poisson excess δ = ν12 − (E1/(2 G12) − 1) of §1.4 (zero for isotropy).
    pub fn poisson_excess(&self) -> f64 {
        self.nu12 - (self.e1 / (2.0 * self.g12) - 1.0)
    }

    /// Compliance in the material axes, S (Voigt 1, 2, 6).
    pub fn compliance(&self) -> Matrix3<f64> {
        let s12 = -self.nu12 / self.e1;
        Matrix3::new(1.0 / self.e1, s12, 0.0, s12, 1.0 / self.e2, 0.0, 0.0, 0.0, 1.0 / self.g12)
    }

    /// Plane-stress stiffness in the material axes, Q = S⁻¹ in closed form:
    /// Q11 = E1/D, Q22 = E2/D, Q12 = ν12·E2/D, Q66 = G12 with D = 1 − ν12²E2/E1.
    pub fn stiffness(&self) -> Matrix3<f64> {
        let d = 1.0 - self.nu12 * self.nu12 * (self.e2 / self.e1);
        let q12 = self.nu12 * self.e2 / d;
        Matrix3::new(self.e1 / d, q12, 0.0, q12, self.e2 / d, 0.0, 0.0, 0.0, self.g12)
    }

    /// Stiffness Q̄ in the tube axes (Z, Θ, ZΘ): Q̄ = T(α)ᵀ Q T(α) (work
    /// invariance with ε_material = T ε_tube). Computed without an inverse, so
    /// it stays accurate for moduli near the ends of the floating-point range.
    pub fn rotated_stiffness(&self, alpha: f64) -> Matrix3<f64> {
        let t = strain_rotation(alpha);
        let q = t.transpose() * self.stiffness() * t;
        (q + q.transpose()) * 0.5
    }

    /// Compliance S̄ in the tube axes (Z, Θ, ZΘ) for reinforcement at helix
    /// angle α: S̄ = T(−α) S T(−α)ᵀ with T the engineering-strain rotation.
    pub fn rotated_compliance(&self, alpha: f64) -> Matrix3<f64> {
        let t_inv = strain_rotation(-alpha);
        t_inv * self.compliance() * t_inv.transpose()
    }

    /// Closed form of S̄16 (§1.4): (2/E1)·m·n·[δ(m² − n²) − (E1/E2 − 1)·n²].
    /// It alone decides whether a free thin tube over- or unwinds on stretching.
    pub fn s16_closed_form(&self, alpha: f64) -> f64 {
        let (n, m) = alpha.sin_cos();
        let delta = self.poisson_excess();
        2.0 / self.e1 * m * n * (delta * (m * m - n * n) - (self.e1 / self.e2 - 1.0) * n * n)
    }
}

/// Engineering-strain rotation T(α): (ε_11, ε_22, γ_12) = T (ε_zz, ε_θθ, γ_zθ)
/// for material axis 1 at angle α from e_Z towards e_Θ. T(α)⁻¹ = T(−α).
pub fn strain_rotation(alpha: f64) -> Matrix3<f64> {
    let (n, m) = alpha.sin_cos();
    let (mm, nn, mn) = (m * m, n * n, m * n);
    Matrix3::new(mm, nn, mn, nn, mm, -mn, -2.0 * mn, 2.0 * mn, mm - nn)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_inverse_is_negative_angle() {
        // Exact identity of plane rotations: T(α)T(−α) = I.
        for &a in &[0.0, 0.3, 1.0, -1.2, std::f64::consts::FRAC_PI_2] {
            let p = strain_rotation(a) * strain_rotation(-a);
            assert!((p - Matrix3::identity()).amax() < 1e-15, "alpha = {a}");
        }
    }

    #[test]
    fn stiffness_inverts_compliance_in_any_axes() {
        // Reference: S̄ Q̄ = I (Q̄ and S̄ are computed independently).
        let m = OrthotropicSurface::new(2.0, 0.5, 0.3, 0.7).unwrap();
        for &a in &[0.0, 0.4, -1.1, 1.5] {
            let p = m.rotated_compliance(a) * m.rotated_stiffness(a);
            assert!((p - Matrix3::identity()).amax() < 1e-14, "alpha = {a}: {p}");
        }
    }

    #[test]
    fn rejects_non_positive_definite() {
        // ν12² E2/E1 = 0.81·4 > 1: the compliance has a negative eigenvalue.
        let e = OrthotropicSurface::new(1.0, 4.0, 0.9, 1.0).unwrap_err();
        assert_eq!(e.status, Status::ErrNotPositiveDefinite);
        assert!(e.message.contains("nu12"), "{}", e.message);
        assert_eq!(OrthotropicSurface::new(1.0, 0.0, 0.3, 1.0).unwrap_err().status, Status::ErrNotPositive);
        assert!(OrthotropicSurface::new(1.0, 4.0, 0.49, 1.0).is_ok());
    }
}

/// Three-dimensional orthotropic material with the nine engineering constants
/// of `physics.md` §1.1, in its principal axes (1 along the reinforcement,
/// 2 across it in the tube surface, 3 radial). ν_ij is the contraction along
/// j per extension along i (ν_ji = ν_ij E_j / E_i).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orthotropic {
    pub e1: f64,
    pub e2: f64,
    pub e3: f64,
    pub nu12: f64,
    pub nu13: f64,
    pub nu23: f64,
    pub g12: f64,
    pub g13: f64,
    pub g23: f64,
}

/// Voigt order of the tube axes used by [`Orthotropic::rotated_stiffness`]:
/// (ZZ, ΘΘ, RR, ΘR, ZR, ZΘ), engineering shears. (Crate-private: cbindgen
/// would export public constants into the C header.)
pub(crate) mod voigt {
    pub(crate) const ZZ: usize = 0;
    pub(crate) const TT: usize = 1;
    pub(crate) const RR: usize = 2;
    pub(crate) const ZT: usize = 5;
}

/// Smallest ratio of two of the six moduli an [`Orthotropic`] accepts: the
/// stiffness's condition number is at least the inverse, and at 1e12 the
/// condensed laws keep ~4 significant digits.
pub const MODULUS_RATIO_LIMIT: f64 = 1e-12;

impl Orthotropic {
    /// Validated constructor: moduli positive and the 6×6 compliance positive
    /// definite (Cholesky), so the strain energy is positive for every strain.
    // The nine engineering constants of §1.1 in their conventional order, as
    // the C API and the tests pass them: a parameter struct would be this
    // struct itself, its fields named the same.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        e1: f64,
        e2: f64,
        e3: f64,
        nu12: f64,
        nu13: f64,
        nu23: f64,
        g12: f64,
        g13: f64,
        g23: f64,
    ) -> Result<Self> {
        for (name, v) in [("e1", e1), ("e2", e2), ("e3", e3), ("g12", g12), ("g13", g13), ("g23", g23)] {
            error::positive(name, v)?;
        }
        for (name, v) in [("nu12", nu12), ("nu13", nu13), ("nu23", nu23)] {
            error::finite(name, v)?;
        }
        // Conditioning: moduli more than 12 orders of magnitude apart leave a
        // stiffness whose condensations keep ~4 digits at best, and a
        // denormal one makes it singular (a tiny g13 panicked in the rod
        // law). Refused by name, with both values.
        let moduli = [("e1", e1), ("e2", e2), ("e3", e3), ("g12", g12), ("g13", g13), ("g23", g23)];
        let (lo, hi) = (
            moduli.iter().fold(moduli[0], |a, &b| if b.1 < a.1 { b } else { a }),
            moduli.iter().fold(moduli[0], |a, &b| if b.1 > a.1 { b } else { a }),
        );
        if !(lo.1 >= MODULUS_RATIO_LIMIT * hi.1) || !lo.1.is_normal() || !(1.0 / lo.1).is_finite() {
            return Err(Error::new(
                Status::ErrNotPositiveDefinite,
                format!(
                    "argument `{}` = {:e} makes the material ill-conditioned: it is below {MODULUS_RATIO_LIMIT:e} \
                     times the largest modulus ({} = {:e})",
                    lo.0, lo.1, hi.0, hi.1
                ),
            ));
        }
        let m = Orthotropic { e1, e2, e3, nu12, nu13, nu23, g12, g13, g23 };
        // Scale-free test: the compliance with rows/columns scaled by √E.
        let s = m.compliance();
        let d = nalgebra::Vector6::new(e1, e2, e3, g23, g13, g12).map(f64::sqrt);
        let scaled = Matrix6::from_fn(|i, j| s[(i, j)] * d[i] * d[j]);
        let invertible = s.try_inverse().is_some_and(|c| c.iter().all(|v| v.is_finite()));
        if !invertible || scaled.cholesky().is_none() {
            return Err(Error::new(
                Status::ErrNotPositiveDefinite,
                format!(
                    "material is not positive definite: Poisson ratios nu12 = {nu12:e}, nu13 = {nu13:e}, \
                     nu23 = {nu23:e} are incompatible with e1 = {e1:e}, e2 = {e2:e}, e3 = {e3:e}"
                ),
            ));
        }
        Ok(m)
    }

    /// Isotropic material (E, ν), −1 < ν < 1/2.
    pub fn isotropic(e: f64, nu: f64) -> Result<Self> {
        error::finite("nu", nu)?;
        if !(nu > -1.0 && nu < 0.5) {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!("argument `nu` must lie in (-1, 0.5) for a compressible isotropic material (got {nu:e})"),
            ));
        }
        let g = e / (2.0 * (1.0 + nu));
        Self::new(e, e, e, nu, nu, nu, g, g, g)
    }

    /// Compliance in the material axes, Voigt (11, 22, 33, 23, 13, 12).
    pub fn compliance(&self) -> Matrix6<f64> {
        let (s12, s13, s23) = (-self.nu12 / self.e1, -self.nu13 / self.e1, -self.nu23 / self.e2);
        let mut s = Matrix6::zeros();
        s[(0, 0)] = 1.0 / self.e1;
        s[(1, 1)] = 1.0 / self.e2;
        s[(2, 2)] = 1.0 / self.e3;
        s[(0, 1)] = s12;
        s[(1, 0)] = s12;
        s[(0, 2)] = s13;
        s[(2, 0)] = s13;
        s[(1, 2)] = s23;
        s[(2, 1)] = s23;
        s[(3, 3)] = 1.0 / self.g23;
        s[(4, 4)] = 1.0 / self.g13;
        s[(5, 5)] = 1.0 / self.g12;
        s
    }

    /// Stiffness ℂ = S⁻¹ in the material axes.
    pub fn stiffness(&self) -> Matrix6<f64> {
        let c = self.compliance().try_inverse().expect("validated compliance is invertible");
        (c + c.transpose()) * 0.5
    }

    /// Stiffness in the tube axes (ZZ, ΘΘ, RR, ΘR, ZR, ZΘ) for reinforcement
    /// at helix angle α (axis 1 = cos α e_Z + sin α e_Θ, axis 3 = e_R):
    /// ℂ̄ = M ℂ Mᵀ with M the Bond stress transformation of that rotation.
    pub fn rotated_stiffness(&self, alpha: f64) -> Matrix6<f64> {
        let m = bond_about_radius(alpha);
        let c = m * self.stiffness() * m.transpose();
        (c + c.transpose()) * 0.5
    }

    /// The in-surface (plane-stress, σ_33 = 0) constants: exactly the
    /// (1, 2, 12) block of the compliance.
    pub fn surface(&self) -> OrthotropicSurface {
        OrthotropicSurface { e1: self.e1, e2: self.e2, nu12: self.nu12, g12: self.g12 }
    }
}

/// Bond stress-transformation matrix for the rotation taking the material
/// axes (1, 2, 3) to the tube axes (Z, Θ, R): a_ij = (material e_j)·(tube
/// axis i), with e1 = (m, n, 0), e2 = (−n, m, 0), e3 = (0, 0, 1).
pub(crate) fn bond_about_radius(alpha: f64) -> Matrix6<f64> {
    let (n, m) = alpha.sin_cos();
    let a = Matrix3::new(m, -n, 0.0, n, m, 0.0, 0.0, 0.0, 1.0);
    let idx = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];
    Matrix6::from_fn(|p, q| {
        let (i, j) = idx[p];
        let (k, l) = idx[q];
        if q < 3 {
            a[(i, k)] * a[(j, l)]
        } else {
            a[(i, k)] * a[(j, l)] + a[(i, l)] * a[(j, k)]
        }
    })
}

#[cfg(test)]
mod tests3d {
    use super::*;

    /// Reference: direct rotation of the 4th-order stiffness tensor,
    /// C'_ijkl = a_ip a_jq a_kr a_ls C_pqrs.
    #[test]
    fn bond_rotation_equals_tensor_rotation() {
        let m = Orthotropic::new(3.0, 1.5, 0.8, 0.3, 0.25, 0.4, 0.9, 0.5, 0.3).unwrap();
        let c = m.stiffness();
        let idx = |i: usize, j: usize| match (i.min(j), i.max(j)) {
            (0, 0) => 0,
            (1, 1) => 1,
            (2, 2) => 2,
            (1, 2) => 3,
            (0, 2) => 4,
            _ => 5,
        };
        for &alpha in &[0.0, 0.7, -1.2] {
            let (n, mm) = f64::sin_cos(alpha);
            let a = [[mm, -n, 0.0], [n, mm, 0.0], [0.0, 0.0, 1.0]];
            let rotated = m.rotated_stiffness(alpha);
            for i in 0..3 {
                for j in 0..3 {
                    for k in 0..3 {
                        for l in 0..3 {
                            let mut acc = 0.0;
                            for p in 0..3 {
                                for q in 0..3 {
                                    for r in 0..3 {
                                        for s in 0..3 {
                                            acc += a[i][p] * a[j][q] * a[k][r] * a[l][s] * c[(idx(p, q), idx(r, s))];
                                        }
                                    }
                                }
                            }
                            let got = rotated[(idx(i, j), idx(k, l))];
                            assert!(
                                (got - acc).abs() < 1e-13 * c.amax(),
                                "alpha {alpha}: C{i}{j}{k}{l} {got} vs {acc}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn plane_stress_reduction_is_the_surface_material() {
        // Reference: σ_33 = 0 condensation of ℂ̄ equals the in-surface Q̄ of §1.4.
        let m = Orthotropic::new(3.0, 1.5, 0.8, 0.3, 0.25, 0.4, 0.9, 0.5, 0.3).unwrap();
        for &alpha in &[0.0, 0.5, 1.3] {
            let c = m.rotated_stiffness(alpha);
            let keep = [voigt::ZZ, voigt::TT, voigt::ZT];
            let q = Matrix3::from_fn(|i, j| {
                let (a, b) = (keep[i], keep[j]);
                c[(a, b)] - c[(a, voigt::RR)] * c[(voigt::RR, b)] / c[(voigt::RR, voigt::RR)]
            });
            let q_surface = m.surface().rotated_stiffness(alpha);
            assert!((q - q_surface).amax() < 1e-13 * q.amax(), "{q} vs {q_surface}");
        }
    }

    #[test]
    fn rejects_non_positive_definite_3d() {
        // ν12 = ν13 = ν23 = 0.6 isotropic-like: 1 − 2ν < 0 violates PD.
        let e = Orthotropic::new(1.0, 1.0, 1.0, 0.6, 0.6, 0.6, 0.3, 0.3, 0.3).unwrap_err();
        assert_eq!(e.status, Status::ErrNotPositiveDefinite);
        assert_eq!(Orthotropic::isotropic(1.0, 0.5).unwrap_err().status, Status::ErrOutOfRange);
    }
}

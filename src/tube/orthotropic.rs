//! In-surface (plane-stress) orthotropic elasticity of a tube wall and its
//! rotation from the reinforcement axes to the tube's (Z, Θ) axes
//! (`physics.md` §1.1, §1.4).
//!
//! Voigt order (1, 2, 6) = (along the reinforcement, across it, in-plane
//! engineering shear); rotated order (Z, Θ, ZΘ) with γ_zθ engineering shear.
//! The helix angle α is measured from e_Z towards e_Θ.

use crate::error::{self, Error, Result};
use crate::status::Status;
use nalgebra::Matrix3;

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
        Matrix3::new(
            1.0 / self.e1, s12, 0.0,
            s12, 1.0 / self.e2, 0.0,
            0.0, 0.0, 1.0 / self.g12,
        )
    }

    /// Plane-stress stiffness in the material axes, Q = S⁻¹ in closed form:
    /// Q11 = E1/D, Q22 = E2/D, Q12 = ν12·E2/D, Q66 = G12 with D = 1 − ν12²E2/E1.
    pub fn stiffness(&self) -> Matrix3<f64> {
        let d = 1.0 - self.nu12 * self.nu12 * (self.e2 / self.e1);
        let q12 = self.nu12 * self.e2 / d;
        Matrix3::new(
            self.e1 / d, q12, 0.0,
            q12, self.e2 / d, 0.0,
            0.0, 0.0, self.g12,
        )
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
    Matrix3::new(
        mm, nn, mn,
        nn, mm, -mn,
        -2.0 * mn, 2.0 * mn, mm - nn,
    )
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

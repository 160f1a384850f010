//! Thin-tube (membrane) linear theory, `physics.md` §1.4.
//!
//! Plane stress in a wall of mid radius R and thickness t ≪ R, reinforcement
//! at the helix angle α = atan(τ0 R) of the mid surface. With Q̄ = S̄⁻¹ the
//! in-surface stiffness in the tube axes (Z, Θ, ZΘ):
//!
//!   F      = 2πRt [ Q̄11 ε + Q̄16 Rψ + Q̄12 ε_θ ]
//!   T      = 2πR²t[ Q̄16 ε + Q̄66 Rψ + Q̄26 ε_θ ]
//!   2πR²p  = 2πRt [ Q̄12 ε + Q̄26 Rψ + Q̄22 ε_θ ]   (hoop balance N_θθ = pR)
//!
//! so K = 2πRt · D Q̄ D with D = diag(1, R, 1). All variables are at the mid
//! radius (ε_θ = u(R)/R, p the inner pressure, open ends); the thick model
//! reports in inner-radius variables, and converting between the two is the
//! thick model's business.

use crate::error::{self, Error, Result};
use crate::status::Status;
use crate::tube::coupling::CouplingStiffness;
use crate::tube::orthotropic::OrthotropicSurface;
use nalgebra::Matrix3;
use std::f64::consts::PI;

/// A thin helically reinforced tube in its stress-free state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinTube {
    /// Mid-surface radius R (length).
    pub mid_radius: f64,
    /// Wall thickness t (length), 0 < t < 2R.
    pub thickness: f64,
    /// Intrinsic twist τ0 (1/length): the reinforcement helix has pitch 2π/τ0;
    /// its sign is the handedness.
    pub intrinsic_twist: f64,
    pub material: OrthotropicSurface,
}

impl ThinTube {
    /// Validated constructor. The material is validated by
    /// [`OrthotropicSurface::new`]; here the geometry: R > 0, t > 0, and the
    /// inner radius R − t/2 positive.
    pub fn new(mid_radius: f64, thickness: f64, intrinsic_twist: f64, material: OrthotropicSurface) -> Result<Self> {
        error::positive("mid_radius", mid_radius)?;
        error::positive("thickness", thickness)?;
        error::finite("intrinsic_twist", intrinsic_twist)?;
        if thickness >= 2.0 * mid_radius {
            return Err(Error::new(
                Status::ErrInvalidGeometry,
                format!(
                    "impossible tube: thickness {thickness:e} must be below twice the mid radius \
                     {mid_radius:e} (the inner radius would be {:e})",
                    mid_radius - 0.5 * thickness
                ),
            ));
        }
        Ok(ThinTube { mid_radius, thickness, intrinsic_twist, material })
    }

    /// Helix angle of the reinforcement at the mid surface, α = atan(τ0 R),
    /// in radians, measured from the axis towards e_Θ.
    pub fn helix_angle(&self) -> f64 {
        (self.intrinsic_twist * self.mid_radius).atan()
    }

    /// The 3×3 coupling stiffness K of §1.4.
    pub fn coupling_stiffness(&self) -> Result<CouplingStiffness> {
        // Q̄ is ordered (ε_zz, ε_θθ, γ_zθ); K is ordered (ε, ψ, ε_θ) with
        // γ_zθ = Rψ, so K = 2πRt · P Q̄ Pᵀ with P mapping (zz, θθ, zθ) to
        // (ε, ψ, ε_θ) and scaling the shear row and column by R.
        let q = self.material.rotated_stiffness(self.helix_angle());
        let r = self.mid_radius;
        let p = Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, r, 0.0, 1.0, 0.0);
        let k = (p * q * p.transpose()) * (2.0 * PI * r * self.thickness);
        CouplingStiffness::new(k, self.intrinsic_twist)
    }
}

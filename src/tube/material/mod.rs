//! Finite-strain constitutive laws of the tube wall (`physics.md` §1.3) and
//! the kinematics they are evaluated on (§1.2).
//!
//! The semi-inverse deformation r = r(R), θ = Θ + ψZ, z = λZ has, in the
//! orthonormal bases (e_r, e_θ, e_z) ⊗ (E_R, E_Θ, E_Z), the gradient
//!
//!   F = [[a, 0, 0], [0, b, γ], [0, 0, λ]],  a = r', b = r/R, γ = rψ,
//!
//! so every law only ever sees C = FᵀF = [[a², 0, 0], [0, b², bγ], [0, bγ, γ² + λ²]].
//! Laws return the second Piola–Kirchhoff stress S in the reference frame
//! ordered (R, Θ, Z); for incompressible laws S is the part without the
//! pressure multiplier (σ = F S Fᵀ − p̂ I with J = 1).

pub mod fibre;
pub mod neo_hookean;
pub mod svk;

pub use fibre::{FibreAngle, FibreFamily, FibreReinforced};
pub use neo_hookean::NeoHookean;
pub use svk::SaintVenantKirchhoff;

use nalgebra::Matrix3;

/// Index of the reference-frame axes in the 3×3 tensors of this module.
pub const R: usize = 0;
pub const THETA: usize = 1;
pub const Z: usize = 2;

/// Local deformation of the tube wall at one radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallStrain {
    /// Radial stretch a = dr/dR.
    pub radial: f64,
    /// Hoop stretch b = r/R.
    pub hoop: f64,
    /// Axial stretch λ.
    pub axial: f64,
    /// Torsional shear γ = rψ.
    pub shear: f64,
}

impl WallStrain {
    /// From the four local modes [a, b, λ, γ] (the order the wall solvers
    /// difference them in).
    pub fn from_modes(m: [f64; 4]) -> Self {
        WallStrain { radial: m[0], hoop: m[1], axial: m[2], shear: m[3] }
    }

    /// The undeformed state.
    pub fn identity() -> Self {
        WallStrain { radial: 1.0, hoop: 1.0, axial: 1.0, shear: 0.0 }
    }

    /// Deformation gradient F, rows (r, θ, z), columns (R, Θ, Z).
    pub fn gradient(&self) -> Matrix3<f64> {
        Matrix3::new(self.radial, 0.0, 0.0, 0.0, self.hoop, self.shear, 0.0, 0.0, self.axial)
    }

    /// Right Cauchy–Green tensor C = FᵀF.
    pub fn right_cauchy_green(&self) -> Matrix3<f64> {
        let f = self.gradient();
        f.transpose() * f
    }

    /// J = det F = a·b·λ.
    pub fn jacobian(&self) -> f64 {
        self.radial * self.hoop * self.axial
    }
}

/// A hyperelastic law of the wall. `radius` is the reference radius R: the
/// reinforcement direction of helically reinforced walls depends on it
/// (α(R) = atan(τ0 R)).
pub trait WallMaterial {
    /// Strain energy per reference volume, W(C; R).
    fn energy(&self, radius: f64, c: &Matrix3<f64>) -> f64;

    /// Second Piola–Kirchhoff stress S = 2 ∂W/∂C (for incompressible laws,
    /// without the multiplier term).
    fn pk2(&self, radius: f64, c: &Matrix3<f64>) -> Matrix3<f64>;

    /// Whether the law is constrained to J = 1.
    fn incompressible(&self) -> bool;

    /// Number of switching functions g_k(R, C): where one changes sign the
    /// law is only C¹ (a fibre family turning on), and the wall solver puts a
    /// breakpoint there to keep its spectral rate. Smooth laws have none.
    fn switches(&self) -> usize {
        0
    }

    /// Value of switching function `k` (< [`Self::switches`]).
    fn switch_value(&self, _k: usize, _radius: f64, _c: &Matrix3<f64>) -> f64 {
        0.0
    }

    /// Cauchy stress σ = F S Fᵀ / J in (e_r, e_θ, e_z); for incompressible
    /// laws, without the multiplier (J = 1 assumed).
    fn cauchy(&self, radius: f64, strain: &WallStrain) -> Matrix3<f64> {
        let f = strain.gradient();
        let s = self.pk2(radius, &strain.right_cauchy_green());
        let j = if self.incompressible() { 1.0 } else { strain.jacobian() };
        f * s * f.transpose() / j
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// S = 2 ∂W/∂C by central differences of the energy (reference: the
    /// definition), on strains with all four kinematic quantities active.
    pub(crate) fn check_pk2_is_energy_gradient(m: &dyn WallMaterial, radius: f64, tol: f64) {
        for strain in [
            WallStrain { radial: 0.93, hoop: 1.04, axial: 1.07, shear: 0.11 },
            WallStrain { radial: 1.2, hoop: 0.9, axial: 0.95, shear: -0.3 },
        ] {
            let c = strain.right_cauchy_green();
            let s = m.pk2(radius, &c);
            let h = 1e-6;
            for i in 0..3 {
                for j in i..3 {
                    let mut e = Matrix3::zeros();
                    e[(i, j)] = 1.0;
                    e[(j, i)] = 1.0; // symmetric perturbation: dW = S : dC / 2
                    let dw = (m.energy(radius, &(c + e * h)) - m.energy(radius, &(c - e * h))) / (2.0 * h);
                    let expect = if i == j { 0.5 * s[(i, i)] } else { s[(i, j)] };
                    assert!((dw - expect).abs() < tol * s.amax().max(1.0), "S[{i},{j}]: {expect} vs dW {dw}");
                }
            }
            assert!((s - s.transpose()).amax() < 1e-14 * s.amax().max(1.0));
        }
    }

    #[test]
    fn kinematics() {
        // Reference: C = FᵀF by hand for F = [[a,0,0],[0,b,γ],[0,0,λ]].
        let w = WallStrain { radial: 1.1, hoop: 0.9, axial: 1.2, shear: 0.3 };
        let c = w.right_cauchy_green();
        assert!((c[(THETA, Z)] - 0.9 * 0.3).abs() < 1e-15);
        assert!((c[(Z, Z)] - (0.09 + 1.44)).abs() < 1e-15);
        assert!((c.determinant().sqrt() - w.jacobian()).abs() < 1e-14);
    }
}

//! Orthotropic Saint Venant–Kirchhoff wall (§1.3 default): W = ½ E:ℂ̄(R):E
//! with the Green–Lagrange strain E = (C − I)/2 and ℂ̄(R) the nine-constant
//! stiffness rotated to the helix angle α(R) = atan(τ0 R). It reduces exactly
//! to the linear theory at small strain. Incompressible variant: the same W
//! restricted to J = 1 (a different model from ν → ½, see §1.3).

use super::{WallMaterial, R, THETA, Z};
use crate::tube::orthotropic::{bond_about_radius, Orthotropic};
use nalgebra::{Matrix3, Matrix6, Vector6};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SaintVenantKirchhoff {
    pub material: Orthotropic,
    pub intrinsic_twist: f64,
    pub incompressible: bool,
    /// ℂ in the material axes, inverted once here rather than per evaluation.
    stiffness: Matrix6<f64>,
}

/// (R,Θ,Z) tensor index pairs in the Voigt order of
/// [`Orthotropic::rotated_stiffness`]: (ZZ, ΘΘ, RR, ΘR, ZR, ZΘ).
const PAIRS: [(usize, usize); 6] = [(Z, Z), (THETA, THETA), (R, R), (THETA, R), (Z, R), (Z, THETA)];

impl SaintVenantKirchhoff {
    pub fn new(material: Orthotropic, intrinsic_twist: f64, incompressible: bool) -> Self {
        SaintVenantKirchhoff { material, intrinsic_twist, incompressible, stiffness: material.stiffness() }
    }

    fn voigt_strain(c: &Matrix3<f64>) -> Vector6<f64> {
        // Engineering shears: 2E_ij = C_ij for i ≠ j.
        Vector6::from_fn(|k, _| {
            let (i, j) = PAIRS[k];
            if i == j {
                0.5 * (c[(i, i)] - 1.0)
            } else {
                c[(i, j)]
            }
        })
    }
}

impl WallMaterial for SaintVenantKirchhoff {
    fn energy(&self, radius: f64, c: &Matrix3<f64>) -> f64 {
        // eᵀ(M ℂ Mᵀ)e = (Mᵀe)ᵀ ℂ (Mᵀe): the strain rotated to the material
        // axes, one 6×6 product with a vector instead of two with matrices
        // (the thick wall's stability check differences W 64 times a node:
        // 56 % of a thick solve went to rotating ℂ).
        let m = bond_about_radius((self.intrinsic_twist * radius).atan());
        let e = m.tr_mul(&Self::voigt_strain(c));
        0.5 * e.dot(&(self.stiffness * e))
    }

    fn pk2(&self, radius: f64, c: &Matrix3<f64>) -> Matrix3<f64> {
        // M ℂ Mᵀ e as three products with a vector (see `energy`).
        let m = bond_about_radius((self.intrinsic_twist * radius).atan());
        let s = m * (self.stiffness * m.tr_mul(&Self::voigt_strain(c)));
        let mut out = Matrix3::zeros();
        for (k, &(i, j)) in PAIRS.iter().enumerate() {
            out[(i, j)] = s[k];
            out[(j, i)] = s[k];
        }
        out
    }

    fn incompressible(&self) -> bool {
        self.incompressible
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tube::material::tests::check_pk2_is_energy_gradient;
    use crate::tube::material::WallStrain;

    fn wall() -> SaintVenantKirchhoff {
        let m = Orthotropic::new(10.0, 2.0, 1.5, 0.35, 0.3, 0.4, 1.2, 0.8, 0.6).unwrap();
        SaintVenantKirchhoff::new(m, 1.7, false)
    }

    #[test]
    fn stress_is_energy_gradient() {
        check_pk2_is_energy_gradient(&wall(), 0.8, 1e-8);
    }

    /// Small strain: the Cauchy stress equals the linear law ℂ̄ ε of the
    /// thick-tube theory to first order (reference: Orthotropic::rotated_stiffness).
    #[test]
    fn small_strain_reduces_to_linear_theory() {
        let w = wall();
        let (r, h) = (0.8, 1e-7);
        let strain = WallStrain { radial: 1.0 + 0.3 * h, hoop: 1.0 - 0.5 * h, axial: 1.0 + h, shear: 0.7 * h };
        let sigma = w.cauchy(r, &strain) / h;
        let eps = Vector6::new(1.0, -0.5, 0.3, 0.0, 0.0, 0.7);
        let lin = w.material.rotated_stiffness((1.7f64 * r).atan()) * eps;
        for (k, &(i, j)) in PAIRS.iter().enumerate() {
            assert!(
                (sigma[(i, j)] - lin[k]).abs() < 1e-5 * lin.amax(),
                "component {k}: {} vs {}",
                sigma[(i, j)],
                lin[k]
            );
        }
    }
}

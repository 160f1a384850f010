//! Isotropic neo-Hookean wall (§1.3): compressible
//! W = μ/2 (I1 − 3) − μ ln J + λ_L/2 (ln J)², incompressible W = μ/2 (I1 − 3).
//! Its compressible form converges to the incompressible one as λ_L/μ → ∞,
//! and it has exact solutions used as tests (Poynting effect, volume
//! conservation).

use super::WallMaterial;
use nalgebra::Matrix3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NeoHookean {
    /// Shear modulus μ > 0.
    pub shear_modulus: f64,
    /// Lamé λ_L (ignored when incompressible).
    pub lame_lambda: f64,
    pub incompressible: bool,
}

impl WallMaterial for NeoHookean {
    fn energy(&self, _radius: f64, c: &Matrix3<f64>) -> f64 {
        let mu = self.shear_modulus;
        let w = 0.5 * mu * (c.trace() - 3.0);
        if self.incompressible {
            return w;
        }
        let ln_j = 0.5 * c.determinant().ln();
        w - mu * ln_j + 0.5 * self.lame_lambda * ln_j * ln_j
    }

    fn pk2(&self, _radius: f64, c: &Matrix3<f64>) -> Matrix3<f64> {
        let mu = self.shear_modulus;
        if self.incompressible {
            return Matrix3::identity() * mu;
        }
        let c_inv = c.try_inverse().unwrap_or_else(|| Matrix3::from_element(f64::NAN));
        let ln_j = 0.5 * c.determinant().ln();
        (Matrix3::identity() - c_inv) * mu + c_inv * (self.lame_lambda * ln_j)
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

    #[test]
    fn stress_is_energy_gradient() {
        for incompressible in [false, true] {
            let m = NeoHookean { shear_modulus: 2.0, lame_lambda: 5.0, incompressible };
            check_pk2_is_energy_gradient(&m, 1.0, 1e-8);
        }
    }

    /// Simple shear-free uniaxial check against the textbook Cauchy stress
    /// σ = μ/J (B − I) + λ_L ln J / J · I (reference: Holzapfel 2000, §6.5).
    #[test]
    fn cauchy_matches_spatial_form() {
        let m = NeoHookean { shear_modulus: 1.5, lame_lambda: 4.0, incompressible: false };
        let w = WallStrain { radial: 0.9, hoop: 1.1, axial: 1.3, shear: 0.2 };
        let f = w.gradient();
        let b = f * f.transpose();
        let j = w.jacobian();
        let expect = (b - Matrix3::identity()) * (1.5 / j) + Matrix3::identity() * (4.0 * j.ln() / j);
        assert!((m.cauchy(1.0, &w) - expect).amax() < 1e-13);
    }
}

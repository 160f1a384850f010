//! Fibre-reinforced wall of Holzapfel–Gasser–Ogden type (§1.3): a
//! neo-Hookean matrix plus helical fibre families with exponential stiffening,
//! W_f = k1/(2k2)·(exp(k2(I4 − 1)²) − 1) per family, active only in tension
//! (I4 > 1, fibres do not carry compression). I4 = M·CM with the reference
//! fibre direction M = cos β E_Z + sin β E_Θ. The standard arterial model.

use super::{NeoHookean, WallMaterial, THETA, Z};
use nalgebra::{Matrix3, Vector3};

/// Direction of a fibre family, as an angle β from the axis towards e_Θ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FibreAngle {
    /// Follows the intrinsic twist: β(R) = hand · atan(τ0 R), hand = ±1
    /// (two families of opposite hand: +1 and −1).
    Helix { hand: f64 },
    /// A constant angle (radians) through the wall.
    Fixed(f64),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FibreFamily {
    pub angle: FibreAngle,
    /// Stiffness k1 > 0 (stress units).
    pub k1: f64,
    /// Dimensionless exponential stiffening k2 > 0.
    pub k2: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct FibreReinforced {
    pub matrix: NeoHookean,
    pub families: Vec<FibreFamily>,
    pub intrinsic_twist: f64,
}

impl FibreReinforced {
    fn direction(&self, family: &FibreFamily, radius: f64) -> Vector3<f64> {
        let beta = match family.angle {
            FibreAngle::Helix { hand } => hand * (self.intrinsic_twist * radius).atan(),
            FibreAngle::Fixed(b) => b,
        };
        let mut m = Vector3::zeros();
        m[Z] = beta.cos();
        m[THETA] = beta.sin();
        m
    }

    /// A family's reference direction M at `radius` and its I4 − 1 =
    /// M·CM − 1 (the fibre's squared stretch minus one).
    fn fibre_strain(&self, family: &FibreFamily, radius: f64, c: &Matrix3<f64>) -> (Vector3<f64>, f64) {
        let m = self.direction(family, radius);
        let x = m.dot(&(c * m)) - 1.0;
        (m, x)
    }

    /// The families in tension (I4 > 1: fibres carry no compression) with
    /// their M and I4 − 1.
    fn stretched<'a>(
        &'a self,
        radius: f64,
        c: &'a Matrix3<f64>,
    ) -> impl Iterator<Item = (&'a FibreFamily, Vector3<f64>, f64)> + 'a {
        self.families.iter().filter_map(move |f| {
            let (m, x) = self.fibre_strain(f, radius, c);
            (x > 0.0).then_some((f, m, x))
        })
    }
}

impl WallMaterial for FibreReinforced {
    fn energy(&self, radius: f64, c: &Matrix3<f64>) -> f64 {
        let mut w = self.matrix.energy(radius, c);
        for (f, _, x) in self.stretched(radius, c) {
            w += f.k1 / (2.0 * f.k2) * (f.k2 * x * x).exp_m1();
        }
        w
    }

    fn pk2(&self, radius: f64, c: &Matrix3<f64>) -> Matrix3<f64> {
        let mut s = self.matrix.pk2(radius, c);
        for (f, m, x) in self.stretched(radius, c) {
            // S_f = 2 W_f'(I4) M⊗M, W_f' = k1 (I4 − 1) exp(k2 (I4 − 1)²).
            s += m * m.transpose() * (2.0 * f.k1 * x * (f.k2 * x * x).exp());
        }
        s
    }

    fn incompressible(&self) -> bool {
        self.matrix.incompressible
    }

    /// I4 − 1 of each family: the fibres carry load only where it is > 0.
    fn switches(&self) -> usize {
        self.families.len()
    }

    fn switch_value(&self, k: usize, radius: f64, c: &Matrix3<f64>) -> f64 {
        self.fibre_strain(&self.families[k], radius, c).1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tube::material::tests::check_pk2_is_energy_gradient;
    use crate::tube::material::WallStrain;

    fn artery() -> FibreReinforced {
        let fam = |hand| FibreFamily { angle: FibreAngle::Helix { hand }, k1: 2.3, k2: 0.8 };
        FibreReinforced {
            matrix: NeoHookean { shear_modulus: 0.3, lame_lambda: 30.0, incompressible: false },
            families: vec![fam(1.0), fam(-1.0)],
            intrinsic_twist: 0.9,
        }
    }

    #[test]
    fn stress_is_energy_gradient() {
        check_pk2_is_energy_gradient(&artery(), 1.2, 1e-7);
    }

    /// Fibres carry no compression: under axial compression with no twist and
    /// shrinking hoop, the stress is the matrix's alone.
    #[test]
    fn fibres_are_inactive_in_compression() {
        let a = artery();
        let w = WallStrain { radial: 1.05, hoop: 0.97, axial: 0.95, shear: 0.0 };
        let c = w.right_cauchy_green();
        assert_eq!(a.pk2(1.2, &c), a.matrix.pk2(1.2, &c));
        // Two families of opposite hand under pure stretch: no net ΘZ stress.
        let w = WallStrain { radial: 0.95, hoop: 1.0, axial: 1.1, shear: 0.0 };
        let s = a.pk2(1.2, &w.right_cauchy_green());
        assert!(s[(THETA, Z)].abs() < 1e-14 * s.amax());
    }
}

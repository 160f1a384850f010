//! Special Cosserat rods in quaternion form (physics.md §2): the law
//! ([`RodLaw`], general symmetric positive-definite 6×6 with intrinsic
//! strains, hemitropic couplings, or the constrained Kirchhoff variant),
//! loads scaled by Λ (end force and moment, distributed force and couple,
//! each dead or follower), supports, and the discretised rod ([`model::Rod`])
//! as a cubic system for the continuation engines.

pub mod accuracy;
pub mod branch;
pub(crate) mod compiled;
pub mod kinematics;
pub mod mesh;
pub mod model;
pub mod outputs;
pub mod scheme;
pub mod target;
pub mod topology;

use crate::error::{self, Error, Result};
use crate::status::Status;
use nalgebra::{Matrix3, Matrix6, Vector3};

/// Constitutive law [m_b; n_b] = K([u; v] − [û; v̂]), K symmetric positive
/// definite, ordered (u1, u2, u3, v1, v2, v3) ↔ (m1, m2, m3, n1, n2, n3).
#[derive(Clone, Debug, PartialEq)]
pub struct RodLaw {
    pub stiffness: Matrix6<f64>,
    pub intrinsic_u: Vector3<f64>,
    pub intrinsic_v: Vector3<f64>,
    /// Constrained rod: v ≡ v̂ (inextensible, unshearable); only the
    /// bending–twist block of the stiffness is used.
    pub kirchhoff: bool,
}

impl RodLaw {
    /// Straight, isotropic section: bending K_b (both axes), twist C, shear
    /// G (both axes) and stretch S.
    pub fn isotropic(bending: f64, twist: f64, shear: f64, stretch: f64) -> Result<Self> {
        Self::hemitropic(bending, twist, shear, stretch, 0.0, 0.0)
    }

    /// The hemitropic law of §2.2 (twist–stretch g, bend–shear c2), straight.
    pub fn hemitropic(
        bending: f64,
        twist: f64,
        shear: f64,
        stretch: f64,
        twist_stretch: f64,
        bend_shear: f64,
    ) -> Result<Self> {
        for (name, v) in [("bending", bending), ("twist", twist), ("shear", shear), ("stretch", stretch)] {
            error::positive(name, v)?;
        }
        let moduli = Moduli::symmetric(bending, twist, shear, stretch, twist_stretch, bend_shear);
        Self::from_moduli(&moduli, Vector3::zeros(), Vector3::new(0.0, 0.0, 1.0))
    }

    /// The hemitropic law of §2.2 from its moduli (two bending and two
    /// shear axes may differ) with intrinsic strains û, v̂:
    /// K = diag(K1, K2, C, G1, G2, S) plus the couplings K(u3, v3) = g and
    /// K(u1, v1) = K(u2, v2) = c2, symmetric. The six principal moduli must
    /// be positive, the couplings finite, and K positive definite (e.g.
    /// g² < C·S); errors name the [`Moduli`] field.
    pub fn from_moduli(m: &Moduli, intrinsic_u: Vector3<f64>, intrinsic_v: Vector3<f64>) -> Result<Self> {
        for (name, v) in [
            ("bending1", m.bending1),
            ("bending2", m.bending2),
            ("twist", m.twist),
            ("shear1", m.shear1),
            ("shear2", m.shear2),
            ("stretch", m.stretch),
        ] {
            error::positive(name, v)?;
        }
        error::finite("twist_stretch", m.twist_stretch)?;
        error::finite("bend_shear", m.bend_shear)?;
        Self::general(m.stiffness(), intrinsic_u, intrinsic_v)
    }

    /// Inextensible, unshearable rod with bending stiffnesses K1, K2 and
    /// twist C (straight).
    pub fn kirchhoff(bending1: f64, bending2: f64, twist: f64) -> Result<Self> {
        for (name, v) in [("bending1", bending1), ("bending2", bending2), ("twist", twist)] {
            error::positive(name, v)?;
        }
        // The (v, n) block is unused; identity keeps the matrix invertible.
        let k = Matrix6::from_diagonal(&nalgebra::Vector6::new(bending1, bending2, twist, 1.0, 1.0, 1.0));
        let mut law = Self::general(k, Vector3::zeros(), Vector3::new(0.0, 0.0, 1.0))?;
        law.kirchhoff = true;
        Ok(law)
    }

    /// Any symmetric positive-definite K with intrinsic strains.
    pub fn general(stiffness: Matrix6<f64>, intrinsic_u: Vector3<f64>, intrinsic_v: Vector3<f64>) -> Result<Self> {
        error::finite_result("stiffness", stiffness.as_slice())?;
        error::finite_result("intrinsic strains", &[intrinsic_u.as_slice(), intrinsic_v.as_slice()].concat())?;
        let asym = stiffness - stiffness.transpose();
        if asym.amax() > 1e-12 * stiffness.amax() {
            let (i, j) = asym.iamax_full();
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!(
                    "rod stiffness must be symmetric: K({i},{j}) = {:e} but K({j},{i}) = {:e} (0-based)",
                    stiffness[(i, j)],
                    stiffness[(j, i)]
                ),
            ));
        }
        // Positive definite with a condition number a double can carry:
        // Cholesky alone accepts a singular (semi-definite) K whose rounding
        // leaves a tiny positive pivot, e.g. g² = C·S exactly. The messages
        // stay short (printing the matrix itself took ~1 kB): the caller
        // has it.
        let eig = stiffness.symmetric_eigenvalues();
        let (lo, hi) = (eig.min(), eig.max());
        if !(lo > 0.0) || !(hi > 0.0) || stiffness.cholesky().is_none() {
            return Err(Error::new(
                Status::ErrNotPositiveDefinite,
                format!("rod stiffness is not positive definite: eigenvalues from {lo:.3e} to {hi:.3e}"),
            ));
        }
        if !(lo > 1e-13 * hi) {
            // Still ErrNotPositiveDefinite: at this condition number round-off
            // cannot tell K from a semi-definite matrix.
            return Err(Error::new(
                Status::ErrNotPositiveDefinite,
                format!(
                    "rod stiffness ill-conditioned: condition number {:.1e} > 1e13 (eigenvalues from {lo:.3e} to {hi:.3e})",
                    hi / lo
                ),
            ));
        }
        Ok(RodLaw { stiffness, intrinsic_u, intrinsic_v, kirchhoff: false })
    }

    /// K⁻¹ as used by the equations: the full inverse, or for a Kirchhoff
    /// rod the inverse of the bending–twist block (zeros elsewhere).
    pub fn compliance(&self) -> Matrix6<f64> {
        if self.kirchhoff {
            let kb: Matrix3<f64> = self.stiffness.fixed_view::<3, 3>(0, 0).into_owned();
            let inv = kb.try_inverse().expect("validated positive definite");
            let mut c = Matrix6::zeros();
            c.fixed_view_mut::<3, 3>(0, 0).copy_from(&inv);
            c
        } else {
            self.stiffness.try_inverse().expect("validated positive definite")
        }
    }

    /// Bending stiffness about the first axis (the force and length scales
    /// of the rod come from it).
    pub fn bending(&self) -> f64 {
        self.stiffness[(0, 0)]
    }
}

/// The moduli of a hemitropic section (physics.md §2.2), for
/// [`RodLaw::from_moduli`]: bending about d1 and d2, twist, shear along d1
/// and d2, stretch, and the chiral couplings twist–stretch g (u3·v3) and
/// bend–shear c2 (u1·v1 and u2·v2; −g/2 for a thin helically reinforced
/// tube). The C spec `RodkitRodSpec` has the same fields.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moduli {
    pub bending1: f64,
    pub bending2: f64,
    pub twist: f64,
    pub shear1: f64,
    pub shear2: f64,
    pub stretch: f64,
    pub twist_stretch: f64,
    pub bend_shear: f64,
}

impl Moduli {
    /// A section symmetric about its axis: equal bending stiffnesses and
    /// equal shear stiffnesses about d1 and d2 (the hemitropic law of §2.2).
    pub fn symmetric(bending: f64, twist: f64, shear: f64, stretch: f64, twist_stretch: f64, bend_shear: f64) -> Self {
        Moduli {
            bending1: bending,
            bending2: bending,
            twist,
            shear1: shear,
            shear2: shear,
            stretch,
            twist_stretch,
            bend_shear,
        }
    }

    /// The 6×6 stiffness K of these moduli, unchecked (see
    /// [`RodLaw::from_moduli`] for the checks): diag(K1, K2, C, G1, G2, S)
    /// in the order (u1, u2, u3, v1, v2, v3), g between u3 and v3, c2
    /// between u1, v1 and between u2, v2.
    pub fn stiffness(&self) -> Matrix6<f64> {
        let m = self;
        let mut k = Matrix6::from_diagonal(&nalgebra::Vector6::new(
            m.bending1, m.bending2, m.twist, m.shear1, m.shear2, m.stretch,
        ));
        for (i, j, v) in [(2, 5, m.twist_stretch), (0, 3, m.bend_shear), (1, 4, m.bend_shear)] {
            k[(i, j)] = v;
            k[(j, i)] = v;
        }
        k
    }
}

/// How a load follows the rod.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Frame {
    /// Fixed in space (given in spatial components).
    Dead,
    /// Turns with the cross-section (given in body components).
    Follower,
}

/// A load vector, multiplied by Λ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Load {
    pub frame: Frame,
    pub vector: [f64; 3],
}

impl Load {
    pub fn dead(vector: [f64; 3]) -> Self {
        Load { frame: Frame::Dead, vector }
    }
    pub fn follower(vector: [f64; 3]) -> Self {
        Load { frame: Frame::Follower, vector }
    }
}

/// All loads of a rod, each scaled by Λ.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Loads {
    pub tip_force: Option<Load>,
    pub tip_moment: Option<Load>,
    /// Per unit reference length.
    pub distributed_force: Option<Load>,
    pub distributed_couple: Option<Load>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn moduli() -> Moduli {
        Moduli {
            bending1: 2.0,
            bending2: 3.0,
            twist: 5.0,
            shear1: 70.0,
            shear2: 110.0,
            stretch: 130.0,
            twist_stretch: -7.0,
            bend_shear: 1.5,
        }
    }

    /// Reference: physics.md §2.2 written out entry by entry (the matrix
    /// the C spec's moduli have always produced): diagonal (K1, K2, C, G1,
    /// G2, S), g at (u3, v3), c2 at (u1, v1) and (u2, v2), symmetric, zero
    /// elsewhere; the intrinsic strains kept.
    #[test]
    fn from_moduli_places_each_modulus() {
        let (u, v) = (Vector3::new(0.1, -0.2, 0.3), Vector3::new(0.01, 0.02, 1.1));
        let law = RodLaw::from_moduli(&moduli(), u, v).unwrap();
        #[rustfmt::skip]
        let expected = Matrix6::new(
            2.0, 0.0, 0.0,  1.5,   0.0,    0.0,
            0.0, 3.0, 0.0,  0.0,   1.5,    0.0,
            0.0, 0.0, 5.0,  0.0,   0.0,   -7.0,
            1.5, 0.0, 0.0, 70.0,   0.0,    0.0,
            0.0, 1.5, 0.0,  0.0, 110.0,    0.0,
            0.0, 0.0, -7.0, 0.0,   0.0,  130.0,
        );
        assert_eq!(law.stiffness, expected);
        assert_eq!((law.intrinsic_u, law.intrinsic_v, law.kirchhoff), (u, v, false));
    }

    /// Reference: the closed-form inverses of the coupled 2×2 blocks,
    /// [[C, g], [g, S]]⁻¹ = [[S, −g], [−g, C]]/(CS − g²) and
    /// [[K1, c2], [c2, G1]]⁻¹ = [[G1, −c2], [−c2, K1]]/(K1·G1 − c2²).
    #[test]
    fn from_moduli_compliance_matches_closed_form() {
        let m = moduli();
        let c = RodLaw::from_moduli(&m, Vector3::zeros(), Vector3::z()).unwrap().compliance();
        let det_ts = m.twist * m.stretch - m.twist_stretch * m.twist_stretch;
        let det_bs = m.bending1 * m.shear1 - m.bend_shear * m.bend_shear;
        for (got, want) in [
            (c[(2, 2)], m.stretch / det_ts),
            (c[(2, 5)], -m.twist_stretch / det_ts),
            (c[(5, 5)], m.twist / det_ts),
            (c[(0, 0)], m.shear1 / det_bs),
            (c[(0, 3)], -m.bend_shear / det_bs),
        ] {
            assert!((got - want).abs() <= 1e-14 * want.abs(), "{got} vs {want}");
        }
    }

    #[test]
    fn from_moduli_refuses_bad_moduli() {
        let bad = Moduli { bending2: 0.0, ..moduli() };
        let e = RodLaw::from_moduli(&bad, Vector3::zeros(), Vector3::z()).unwrap_err();
        assert_eq!(e.status, Status::ErrNotPositive);
        assert!(e.message.contains("`bending2`"), "{}", e.message);
        // g² = C·S: semi-definite.
        let singular = Moduli { twist_stretch: (5.0f64 * 130.0).sqrt(), ..moduli() };
        let e = RodLaw::from_moduli(&singular, Vector3::zeros(), Vector3::z()).unwrap_err();
        assert_eq!(e.status, Status::ErrNotPositiveDefinite);
    }

    /// The symmetric section is the special case with equal pairs.
    #[test]
    fn hemitropic_is_from_moduli_with_equal_axes() {
        let law = RodLaw::hemitropic(2.0, 5.0, 70.0, 130.0, -7.0, 1.5).unwrap();
        let m = Moduli { bending2: 2.0, shear2: 70.0, ..moduli() };
        assert_eq!(law, RodLaw::from_moduli(&m, Vector3::zeros(), Vector3::z()).unwrap());
    }
}

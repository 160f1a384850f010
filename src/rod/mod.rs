//! Special Cosserat rods in quaternion form (physics.md §2): the law
//! ([`RodLaw`], general symmetric positive-definite 6×6 with intrinsic
//! strains, hemitropic couplings, or the constrained Kirchhoff variant),
//! loads scaled by Λ (end force and moment, distributed force and couple,
//! each dead or follower), supports, and the discretised rod ([`model::Rod`])
//! as a cubic system for the continuation engines.

pub mod branch;
pub mod kinematics;
pub mod model;
pub mod outputs;
pub mod scheme;
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
        error::finite("twist_stretch", twist_stretch)?;
        error::finite("bend_shear", bend_shear)?;
        let mut k = Matrix6::from_diagonal(&nalgebra::Vector6::new(bending, bending, twist, shear, shear, stretch));
        for (i, j, v) in [(2, 5, twist_stretch), (0, 3, bend_shear), (1, 4, bend_shear)] {
            k[(i, j)] = v;
            k[(j, i)] = v;
        }
        Self::general(k, Vector3::zeros(), Vector3::new(0.0, 0.0, 1.0))
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
        if (stiffness - stiffness.transpose()).amax() > 1e-12 * stiffness.amax() {
            return Err(Error::new(Status::ErrOutOfRange, "rod stiffness must be symmetric"));
        }
        // Positive definite with a condition number a double can carry:
        // Cholesky alone accepts a singular (semi-definite) K whose rounding
        // leaves a tiny positive pivot, e.g. g² = C·S exactly.
        let eig = stiffness.symmetric_eigenvalues();
        let (lo, hi) = (eig.min(), eig.max());
        if !(lo > 1e-13 * hi) || stiffness.cholesky().is_none() {
            return Err(Error::new(
                Status::ErrNotPositiveDefinite,
                format!("rod stiffness is not positive definite (eigenvalues from {lo:e} to {hi:e}; condition number above 1e13 is refused): {stiffness}"),
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

//! The linear coupling stiffness of a tube about its stress-free state and
//! what follows from it (`physics.md` §1.4): f = K e with generalised strains
//! e = (ε, ψ, ε_θ) and work-conjugate forces f = (F, T, 2πR²p), K symmetric.
//! Thin and thick models both report through [`CouplingStiffness`].

use crate::error::{self, Error, Result};
use crate::status::Status;
use nalgebra::{Matrix2, Matrix3};

/// Symmetric positive-definite 3×3 coupling stiffness, ordered
/// (extension ε, twist per length ψ, hoop strain ε_θ) ↔ (axial force F,
/// torque T, 2πR²p). Off-diagonals: K[0,1] extension–twist, K[1,2]
/// twist–inflation, K[0,2] extension–inflation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CouplingStiffness {
    pub k: Matrix3<f64>,
    /// Intrinsic twist τ0 of the tube: its sign is the sense "overwinding"
    /// refers to.
    pub intrinsic_twist: f64,
}

/// The condensed 2×2 stretch–twist law at p = 0 (inflation eliminated):
/// (F, T) = [[S, g], [g, C]] (ε, ψ). Exactly the hemitropic rod coupling of §2.2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StretchTwist {
    /// Stretch modulus S (force).
    pub stretch: f64,
    /// Twist–stretch coupling g (force·length).
    pub coupling: f64,
    /// Twist modulus C (force·length²).
    pub twist: f64,
}

/// How a free tube (T = 0, p = 0) twists when pulled, relative to the sense
/// of its intrinsic twist τ0.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Winding {
    /// Twists against τ0 (the usual response of a helical structure).
    Unwinds = -1,
    /// No extension–twist coupling (τ0 = 0, or |coupling| at round-off level).
    Neither = 0,
    /// Twists further in the sense of τ0 (DNA's counter-intuitive response).
    Overwinds = 1,
}

/// Response of a free tube (T = 0, p = 0) to an axial force, per unit force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeTubeResponse {
    /// dε/dF (1/force).
    pub dstrain_dforce: f64,
    /// dψ/dF (1/(force·length)).
    pub dtwist_dforce: f64,
    /// dε_θ/dF (1/force): > 0 means the tube inflates when stretched.
    pub dhoop_dforce: f64,
    /// Sign of τ0·dψ/dF, with round-off treated as zero.
    pub winding: Winding,
}

/// Couplings smaller than this fraction of their Cauchy–Schwarz bound
/// |K⁻¹_εψ| ≤ √(K⁻¹_εε K⁻¹_ψψ) are round-off (exact zeros in exact arithmetic).
const COUPLING_ROUNDOFF: f64 = 1e-12;

impl CouplingStiffness {
    /// Wraps K after checking it is finite, symmetric to round-off and positive
    /// definite (Cholesky).
    pub fn new(k: Matrix3<f64>, intrinsic_twist: f64) -> Result<Self> {
        error::finite_result("coupling stiffness", k.as_slice())?;
        let scale = k.amax();
        if (k - k.transpose()).amax() > 1e-12 * scale {
            return Err(Error::new(
                Status::ErrInternal,
                format!(
                    "coupling stiffness is not symmetric: largest asymmetry {:.3e} for entries up to {scale:.3e}",
                    (k - k.transpose()).amax()
                ),
            ));
        }
        if k.cholesky().is_none() {
            return Err(Error::new(
                Status::ErrNotPositiveDefinite,
                // Short (the printed matrix made a 1–5 kB message).
                format!(
                    "coupling stiffness is not positive definite: {}",
                    crate::error::eigen_range(k.symmetric_eigenvalues().as_slice())
                ),
            ));
        }
        Ok(CouplingStiffness { k, intrinsic_twist })
    }

    /// Column-major entries, ready for a C caller.
    pub fn column_major(&self) -> [f64; 9] {
        let mut out = [0.0; 9];
        out.copy_from_slice(self.k.as_slice()); // nalgebra stores column-major
        out
    }

    /// Condense ε_θ out at p = 0 (Schur complement of K[2,2]). Each product
    /// is formed as k_i3·(k_j3/k33) so that entries near 1e154 and above do
    /// not overflow in k_i3·k_j3 (formed directly, moduli of 1e187…1e198
    /// gave −Inf with status OK).
    pub fn stretch_twist(&self) -> StretchTwist {
        let k = &self.k;
        let k33 = k[(2, 2)];
        StretchTwist {
            stretch: k[(0, 0)] - k[(0, 2)] * (k[(0, 2)] / k33),
            coupling: k[(0, 1)] - k[(0, 2)] * (k[(1, 2)] / k33),
            twist: k[(1, 1)] - k[(1, 2)] * (k[(1, 2)] / k33),
        }
    }

    /// [`Self::stretch_twist`], refused unless finite and positive definite
    /// (S > 0, C > 0, SC > g², as the Schur complement of a positive-definite
    /// K must be): what the C functions return.
    pub fn stretch_twist_checked(&self) -> Result<StretchTwist> {
        let law = self.stretch_twist();
        law.check()?;
        Ok(law)
    }

    /// Free-tube response: solve K e = (1, 0, 0).
    pub fn free_response(&self) -> Result<FreeTubeResponse> {
        let chol = self
            .k
            .cholesky()
            .ok_or_else(|| Error::new(Status::ErrNotPositiveDefinite, "coupling stiffness is not positive definite"))?;
        // K⁻¹ e_1 is the response; the rest of K⁻¹ bounds the coupling.
        let cinv = chol.inverse();
        let e = cinv.column(0);
        error::finite_result("free-tube response", cinv.as_slice())?;
        let bound = (cinv[(0, 0)] * cinv[(1, 1)]).sqrt();
        let sense = self.intrinsic_twist.signum() * e[1];
        let winding = if self.intrinsic_twist == 0.0 || sense.abs() <= COUPLING_ROUNDOFF * bound {
            Winding::Neither
        } else if sense > 0.0 {
            Winding::Overwinds
        } else {
            Winding::Unwinds
        };
        // Compliances of 1e−300 and below underflow to 0: a response of zero
        // to a force is not a physical answer either.
        if !(e[0] > 0.0) {
            return Err(Error::new(
                Status::ErrNonFiniteResult,
                format!("free-tube response: axial compliance dε/dF = {:e} is not positive (underflow)", e[0]),
            ));
        }
        Ok(FreeTubeResponse { dstrain_dforce: e[0], dtwist_dforce: e[1], dhoop_dforce: e[2], winding })
    }
}

impl StretchTwist {
    /// [[S, g], [g, C]].
    pub fn matrix(&self) -> Matrix2<f64> {
        Matrix2::new(self.stretch, self.coupling, self.coupling, self.twist)
    }

    /// Finite and positive definite, else ErrNonFiniteResult (overflow) or
    /// ErrNotPositiveDefinite (round-off of constants many orders apart).
    pub fn check(&self) -> Result<()> {
        let (s, g, c) = (self.stretch, self.coupling, self.twist);
        error::finite_result("stretch-twist law [S, g, C]", &[s, g, c])?;
        // SC > g² compared as |g|/(√S·√C) < 1, without overflow.
        if !(s > 0.0 && c > 0.0 && g.abs() / (s.sqrt() * c.sqrt()) < 1.0) {
            return Err(Error::new(
                Status::ErrNotPositiveDefinite,
                format!(
                    "stretch-twist law [S, g, C] = [{s:e}, {g:e}, {c:e}] is not positive definite: round-off of \
                     constants too many orders of magnitude apart"
                ),
            ));
        }
        Ok(())
    }
}

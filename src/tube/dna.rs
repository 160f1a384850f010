//! DNA as a helically reinforced thin tube (physics.md §1.5 "DNA scene"): fit
//! the wall constants so that the condensed stretch–twist law of the thin
//! tube reproduces the measured DNA moduli, and compare the same material in
//! the thick-wall model.
//!
//! **This is a phenomenological membrane model.** The wall constants it
//! returns are not measured properties of the double helix; they are whatever
//! makes a plane-stress orthotropic wall of thickness t reproduce three
//! numbers (S, C, g). The fit is not unique: see "The family" below.
//!
//! # Units
//! pN for forces, nm for lengths, so moduli of the wall (E1, E2, G12) come out
//! in pN/nm² (1 pN/nm² = 1 MPa), S in pN, g in pN·nm, C in pN·nm², twist per
//! length ψ in rad/nm. Nothing in the code depends on the unit system except
//! the conversions of [`TwistRate`] (rise 0.34 nm/bp).
//!
//! # Handedness convention
//! The tube axes (e_R, e_Θ, e_Z) are a right-handed frame and the helix angle
//! α is measured from e_Z towards e_Θ (physics.md §1.4). A reinforcement line
//! with α > 0 advances in +Θ as it advances in +Z, Θ = τ0 Z with
//! τ0 = tan(α)/R > 0: that is a **right-handed** helix (like (cos s, sin s, cs)
//! with c > 0, an ordinary screw thread). Likewise ψ > 0 in θ = Θ + ψZ is a
//! right-handed twist. So:
//!
//! * **τ0 > 0 (α > 0) means right-handed; B-DNA is right-handed, so DNA uses
//!   α = +60°.** τ0 < 0 is left-handed (Z-DNA-like).
//! * ψ is measured in a fixed sense (positive = right-handed), which is the
//!   sign convention of the single-molecule literature: the linking and twist
//!   numbers of B-DNA are positive, and g < 0 means that stretching adds
//!   right-handed twist.
//! * "Overwinds" = twists further in the sense of τ0, i.e.
//!   sign(τ0)·dψ/dF > 0 ([`Winding::Overwinds`]). The free-rod response is
//!   dψ/dF = −g/(SC − g²), so overwinding ⇔ sign(τ0)·g < 0, exactly the rule
//!   of physics.md §1.4. With τ0 > 0 and the measured g ≈ −90 pN·nm, DNA
//!   overwinds, consistent with experiment. (Had we taken τ0 < 0 for
//!   right-handed, the literature's g < 0 would have meant unwinding.)
//!
//! # The fit is linear in the compliances (closed-form reduction)
//! Eliminating inflation at p = 0 is hoop balance N_θθ = 0, i.e. σ_θθ = 0 in
//! the wall. With σ_θθ = 0 the in-surface strains are the (Z, ZΘ) block of the
//! rotated compliance S̄, and F = 2πRt σ_zz, T = 2πR²t τ_zθ, ε = ε_zz,
//! ψ = γ_zθ/R give the condensed compliance
//!
//!   [[S, g], [g, C]]⁻¹ = 1/(2πRt) · [[S̄11, S̄16/R], [S̄16/R, S̄66/R²]],
//!
//! so, with Δ = SC − g² > 0, the targets fix three rotated compliances:
//!
//!   S̄11 = 2πRt·C/Δ,   S̄16 = −2πR²t·g/Δ,   S̄66 = 2πR³t·S/Δ.       (1)
//!
//! (g < 0 ⇔ S̄16 > 0, the equivalence stated in §1.4.) With m = cos α,
//! n = sin α and the unknown compliances x = (x1, x2, x3) = (1/E1, 1/E2,
//! 1/G12) at fixed ν12 (S12 = −ν12·x1), the rotated compliances are *linear*
//! in x:
//!
//!   S̄11 = (m⁴ − 2ν12 m²n²) x1 + n⁴ x2 + m²n² x3
//!   S̄16 = mn[(2(1+ν12)m² − 2ν12 n²) x1 − 2n² x2 − (m² − n²) x3]
//!   S̄66 = 4m²n²(1 + 2ν12) x1 + 4m²n² x2 + (m² − n²)² x3             (2)
//!
//! whose determinant is 2mn³(m² + ν12 n²). So for 0 < |α| < 90° and
//! ν12 ≠ −cot²α the fit is **unique and closed-form**: one 3×3 linear solve.
//! The solver is nevertheless written as Newton's method on (2) with the
//! residual evaluated by [`ThinTube::coupling_stiffness`] (the model being
//! fitted, not the closed form), started from an isotropic guess: the first
//! step lands on the solution (the map is linear, the Jacobian (2) exact) and
//! the following ones polish it against round-off and prove that what is
//! returned satisfies the thin model to [`REL_TOL`]. Typically 2 iterations.
//!
//! Because the solution of (1)–(2) is unique, a non-physical solution
//! (some modulus ≤ 0 or ν12² ≥ E1/E2) means **no** physical fit exists for
//! that (t, ν12): [`Status::ErrNotPositiveDefinite`], with a message naming the
//! violated constraint. At 60° the fit is degenerate at ν12 = −1/3
//! ([`Status::ErrOutOfRange`]). With the literature targets at 60° the
//! solution is physical for ν12 in about (−0.153, 1.587), whatever t: below,
//! G12 blows up and turns negative; above, ν12² < E1/E2 fails (measured in
//! `tests/dna_fit.rs`).
//!
//! # The family
//! K = 2πRt·P Q̄ Pᵀ depends on the wall only through t·Q (four numbers
//! t·Q11, t·Q22, t·Q12, t·Q66) and three targets fix three of them, so the
//! fits form a **two-parameter** family: the thickness t (moduli ∝ 1/t) and
//! ν12 (which trades between the other three). [`fit_thin_wall`] fixes both;
//! [`fit_family`] sweeps them.

use crate::error::{self, Error, Result};
use crate::nonlinear::dense::{DenseLu, Refresh};
use crate::nonlinear::{self, Equations, FullStep, StepTest};
use crate::status::Status;
use crate::tube::coupling::{CouplingStiffness, FreeTubeResponse, StretchTwist, Winding};
use crate::tube::orthotropic::{Orthotropic, OrthotropicSurface};
use crate::tube::thick::{Compressibility, ThickTube};
use crate::tube::thin::ThinTube;
use nalgebra::{Matrix2, Matrix3, Vector3};
use std::f64::consts::PI;

/// Mid-wall radius of the DNA tube, nm (physics.md §1.5: R ≈ 1 nm).
pub const DNA_MID_RADIUS: f64 = 1.0;
/// Helix angle of the DNA wall, rad: 60° (physics.md §1.5), positive for
/// right-handed B-DNA (see the module docs). At R = 1 nm it is a pitch
/// 2πR/tan α = 3.63 nm; the pitches 3.4–3.6 nm give 61.6°–60.2°
/// ([`helix_angle_from_pitch`]).
pub const DNA_HELIX_ANGLE: f64 = PI / 3.0;
/// Rise per base pair of B-DNA, nm (physics.md §3.6).
pub const RISE_PER_BP: f64 = 0.34;
/// Relative tolerance on the fitted moduli: Newton stops when the last step
/// changed each of 1/E1, 1/E2, 1/G12 by at most this fraction.
pub const REL_TOL: f64 = 1e-12;
/// Newton iteration cap (the method needs 2: see the module docs).
pub const MAX_ITERATIONS: usize = 20;
/// Relative accuracy asked of the thick-wall stiffness in [`thick_comparison`].
pub const THICK_REL_TOL: f64 = 1e-10;

/// Target condensed stretch–twist law (F, T) = [[S, g], [g, C]] (ε, ψ) at
/// zero pressure, with ψ positive in the right-handed sense.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DnaTargets {
    /// Stretch modulus S, pN.
    pub stretch: f64,
    /// Twist modulus C, pN·nm².
    pub twist: f64,
    /// Twist–stretch coupling g, pN·nm (negative: overwinds when pulled).
    pub coupling: f64,
}

impl DnaTargets {
    /// Single-molecule values for B-DNA (physics.md §1.5, §3.6): S = 1100 pN,
    /// C = 440 pN·nm², g = −90 pN·nm (Gore et al. 2006, Lionnet et al. 2006;
    /// C from the 410–440 pN·nm² range).
    pub fn literature() -> DnaTargets {
        DnaTargets { stretch: 1100.0, twist: 440.0, coupling: -90.0 }
    }

    /// Validated targets: finite, S > 0, C > 0 and SC > g² (a stable rod:
    /// no elastic wall can produce an indefinite law).
    pub fn new(stretch: f64, twist: f64, coupling: f64) -> Result<Self> {
        let t = DnaTargets { stretch, twist, coupling };
        t.validate()?;
        Ok(t)
    }

    fn validate(&self) -> Result<()> {
        error::positive("stretch", self.stretch)?;
        error::positive("twist", self.twist)?;
        error::finite("coupling", self.coupling)?;
        let det = self.stretch * self.twist - self.coupling * self.coupling;
        if det.is_nan() || det <= 0.0 {
            return Err(Error::new(
                Status::ErrNotPositiveDefinite,
                format!(
                    "target stretch-twist law is not positive definite: need g^2 < S*C, got S = {:e}, \
                     C = {:e}, g = {:e} (S*C - g^2 = {det:e}); no elastic wall fits it",
                    self.stretch, self.twist, self.coupling
                ),
            ));
        }
        Ok(())
    }

    /// [[S, g], [g, C]].
    pub fn matrix(&self) -> Matrix2<f64> {
        Matrix2::new(self.stretch, self.coupling, self.coupling, self.twist)
    }
}

impl Default for DnaTargets {
    fn default() -> Self {
        Self::literature()
    }
}

impl From<StretchTwist> for DnaTargets {
    fn from(st: StretchTwist) -> Self {
        DnaTargets { stretch: st.stretch, twist: st.twist, coupling: st.coupling }
    }
}

/// Intrinsic twist of reinforcement at helix angle α on radius R:
/// τ0 = tan(α)/R (1/nm). Positive = right-handed.
pub fn intrinsic_twist(mid_radius: f64, helix_angle: f64) -> f64 {
    helix_angle.tan() / mid_radius
}

/// Helix angle of a helix of radius R and pitch p: α = atan(2πR/p), rad.
/// Pass a negative pitch for a left-handed helix.
pub fn helix_angle_from_pitch(mid_radius: f64, pitch: f64) -> f64 {
    (2.0 * PI * mid_radius / pitch).atan()
}

/// Twist change per unit force of a free molecule (T = 0, p = 0), signed in
/// the fixed right-handed sense of ψ (for right-handed DNA, positive =
/// overwinding). Conversions, with h = [`RISE_PER_BP`] = 0.34 nm:
///
/// * per base pair: dψ/dF·h rad/pN, i.e. dψ/dF·h·180/π degrees per pN per bp;
/// * per 10 kbp (contour L = 10⁴·h = 3400 nm): dψ/dF·L/(2π) turns per pN.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwistRate {
    /// dψ/dF, rad/(pN·nm).
    pub rad_per_pn_nm: f64,
    /// dψ/dF·h·180/π, degrees per pN per base pair.
    pub degrees_per_pn_per_bp: f64,
    /// dψ/dF·(10⁴ h)/(2π), turns per pN per 10 kbp.
    pub turns_per_pn_per_10kbp: f64,
}

impl TwistRate {
    /// From dψ/dF in rad/(pN·nm).
    pub fn from_rad_per_pn_nm(dtwist_dforce: f64) -> Self {
        TwistRate {
            rad_per_pn_nm: dtwist_dforce,
            degrees_per_pn_per_bp: dtwist_dforce * RISE_PER_BP * 180.0 / PI,
            turns_per_pn_per_10kbp: dtwist_dforce * 1e4 * RISE_PER_BP / (2.0 * PI),
        }
    }
}

/// A fitted thin DNA wall and what it predicts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitResult {
    /// Fitted wall constants E1, E2, G12 (pN/nm²) and the prescribed ν12.
    pub material: OrthotropicSurface,
    /// Mid radius R, nm.
    pub mid_radius: f64,
    /// Wall thickness t, nm.
    pub thickness: f64,
    /// Helix angle α at the mid radius, rad (positive = right-handed).
    pub helix_angle: f64,
    /// τ0 = tan(α)/R, 1/nm.
    pub intrinsic_twist: f64,
    pub targets: DnaTargets,
    /// (S, C, g) of [`ThinTube`] with the fitted constants (recomputed after
    /// the last Newton step, not copied from the targets).
    pub achieved: StretchTwist,
    /// Newton iterations used (each a residual evaluation and a 3×3 solve).
    pub iterations: usize,
    /// Largest relative change of a compliance 1/E1, 1/E2, 1/G12 in the last
    /// iteration (≤ [`REL_TOL`]).
    pub last_step: f64,
    /// The full 3×3 coupling stiffness of the fitted thin tube.
    pub stiffness: CouplingStiffness,
    /// Free-tube response (T = 0, p = 0) per pN: dψ/dF = −g/(SC − g²).
    pub response: FreeTubeResponse,
    /// dψ/dF in biophysical units.
    pub twist_rate: TwistRate,
    /// `response.winding == Winding::Overwinds`.
    pub overwinds: bool,
}

impl FitResult {
    /// The fitted thin tube.
    pub fn tube(&self) -> ThinTube {
        ThinTube {
            mid_radius: self.mid_radius,
            thickness: self.thickness,
            intrinsic_twist: self.intrinsic_twist,
            material: self.material,
        }
    }
}

/// The Jacobian of (2) in the module docs: rows (S̄11, S̄16, S̄66), columns
/// (1/E1, 1/E2, 1/G12) at fixed ν12. Exact (the map is linear).
fn compliance_map(helix_angle: f64, nu12: f64) -> Matrix3<f64> {
    let (n, m) = helix_angle.sin_cos();
    let (c, s, mn) = (m * m, n * n, m * n);
    Matrix3::new(
        c * c - 2.0 * nu12 * c * s,
        s * s,
        c * s,
        mn * (2.0 * (1.0 + nu12) * c - 2.0 * nu12 * s),
        -2.0 * mn * s,
        -mn * (c - s),
        4.0 * c * s * (1.0 + 2.0 * nu12),
        4.0 * c * s,
        (c - s) * (c - s),
    )
}

/// (S̄11, S̄16, S̄66) of a condensed law, equation (1) of the module docs.
fn rotated_compliances(st: &DnaTargets, mid_radius: f64, thickness: f64) -> Vector3<f64> {
    let det = st.stretch * st.twist - st.coupling * st.coupling;
    let a = 2.0 * PI * mid_radius * thickness / det;
    Vector3::new(a * st.twist, -a * mid_radius * st.coupling, a * mid_radius * mid_radius * st.stretch)
}

/// Which physical constraint x = (1/E1, 1/E2, 1/G12) violates, if any.
fn physical(
    x: &Vector3<f64>,
    nu12: f64,
    thickness: f64,
    nu12_ok_msg: impl Fn() -> String,
) -> Result<OrthotropicSurface> {
    let names = ["E1", "E2", "G12"];
    for i in 0..3 {
        if x[i].is_nan() || x[i] <= 0.0 || !(1.0 / x[i]).is_finite() {
            return Err(Error::new(
                Status::ErrNotPositiveDefinite,
                format!(
                    "no physical thin-wall fit at thickness {thickness:e}, nu12 = {nu12:e}: the unique solution \
                     has {} = {:e} (must be positive and finite); {}",
                    names[i],
                    1.0 / x[i],
                    nu12_ok_msg()
                ),
            ));
        }
    }
    let (e1, e2, g12) = (1.0 / x[0], 1.0 / x[1], 1.0 / x[2]);
    if nu12 * nu12 * x[0] >= x[1] {
        return Err(Error::new(
            Status::ErrNotPositiveDefinite,
            format!(
                "no physical thin-wall fit at thickness {thickness:e}, nu12 = {nu12:e}: the unique solution \
                 E1 = {e1:e}, E2 = {e2:e}, G12 = {g12:e} violates nu12^2 < E1/E2 (nu12*nu21 = {:e} must be < 1); {}",
                nu12 * nu12 * e2 / e1,
                nu12_ok_msg()
            ),
        ));
    }
    OrthotropicSurface::new(e1, e2, nu12, g12)
}

/// The fit's equations in x = (1/E1, 1/E2, 1/G12) at fixed ν12: the
/// rotated compliances (1) of the thin model's condensed law with the
/// material x, minus the targets'. Outside the physical materials (a
/// modulus ≤ 0, ν12² ≥ E1/E2) there is no fit at all: an error.
struct FitEquations {
    tube: ThinTube,
    /// The x of `tube.material`.
    at: [f64; 3],
    nu12: f64,
    goal: Vector3<f64>,
}

impl Equations for FitEquations {
    fn dim(&self) -> usize {
        3
    }

    fn residual(&mut self, x: &[f64], f: &mut [f64]) -> Result<bool> {
        if x != self.at {
            error::finite_result("DNA fit compliances", x)?;
            let nu12 = self.nu12;
            let hint =
                || format!("nu12 = {nu12:e} is outside the physical range for these targets at this helix angle");
            self.tube.material = physical(&Vector3::from_column_slice(x), nu12, self.tube.thickness, hint)?;
            self.at.copy_from_slice(x);
        }
        let achieved = DnaTargets::from(self.tube.coupling_stiffness()?.stretch_twist());
        let r = rotated_compliances(&achieved, self.tube.mid_radius, self.tube.thickness) - self.goal;
        f.copy_from_slice(r.as_slice());
        Ok(true)
    }
}

/// Fit (E1, E2, G12) of a thin wall of thickness t, mid radius R and helix
/// angle α at prescribed ν12 so that the condensed law of
/// [`ThinTube::coupling_stiffness`]`().stretch_twist()` equals the targets
/// (S, C, g). Method, uniqueness and units: module docs.
///
/// Errors: invalid arguments (`ErrNotFinite`, `ErrNotPositive`,
/// `ErrInvalidGeometry` for t ≥ 2R); α not in (−90°, 0) ∪ (0, 90°), or
/// ν12 = −cot²α where (2) is singular: `ErrOutOfRange`; targets with
/// g² ≥ SC, or a unique solution that is not a physical material:
/// `ErrNotPositiveDefinite` (the message names the constraint);
/// Newton not reaching [`REL_TOL`] in [`MAX_ITERATIONS`] (only possible very
/// close to the degenerate ν12): `ErrNotConverged`.
pub fn fit_thin_wall(
    targets: DnaTargets,
    mid_radius: f64,
    helix_angle: f64,
    thickness: f64,
    nu12: f64,
) -> Result<FitResult> {
    targets.validate()?;
    error::positive("mid_radius", mid_radius)?;
    error::positive("thickness", thickness)?;
    error::finite("helix_angle", helix_angle)?;
    error::finite("nu12", nu12)?;
    if !(helix_angle != 0.0 && helix_angle.abs() < 0.5 * PI) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!(
                "argument `helix_angle` must lie in (-pi/2, 0) or (0, pi/2) (got {helix_angle:e}): axial or hoop \
                 reinforcement is mirror-symmetric and has no twist-stretch coupling to fit"
            ),
        ));
    }
    let tau0 = intrinsic_twist(mid_radius, helix_angle);
    // Degenerate ν12 = −cot²α: det (2) = 2mn³(m² + ν12 n²) vanishes.
    let (n, m) = helix_angle.sin_cos();
    let pivot = m * m + nu12 * n * n;
    if pivot.abs() <= 1e-10 * (m * m + nu12.abs() * n * n) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!(
                "argument `nu12` = {nu12:e} equals -cot^2(helix_angle) = {:e}: (S, C, g) do not determine \
                 (E1, E2, G12) there (the fit's determinant 2 m n^3 (m^2 + nu12 n^2) vanishes)",
                -(m * m) / (n * n)
            ),
        ));
    }
    let goal = rotated_compliances(&targets, mid_radius, thickness);
    // Isotropic-like start: S = 2πRt·E and C = 2πR³t·G for isotropy; E2
    // lowered if needed so that ν12² E2/E1 < 1.
    let e0 = targets.stretch / (2.0 * PI * mid_radius * thickness);
    let g0 = targets.twist / (2.0 * PI * mid_radius.powi(3) * thickness);
    let e2_0 = if nu12 * nu12 < 0.5 { e0 } else { 0.5 * e0 / (nu12 * nu12) };
    let start = OrthotropicSurface::new(e0, e2_0, nu12, g0)?;
    // ThinTube::new also checks the geometry (t < 2R).
    let tube = ThinTube::new(mid_radius, thickness, tau0, start)?;
    let mut x = [1.0 / start.e1, 1.0 / start.e2, 1.0 / start.g12];
    let mut fit = FitEquations { tube, at: x, nu12, goal };
    // Newton on (2) with its exact, constant Jacobian (the map is linear),
    // full steps, converged on the relative step.
    let jac = compliance_map(helix_angle, nu12);
    let constant = |_: &nalgebra::DVector<f64>, j: &mut nalgebra::DMatrix<f64>| {
        j.copy_from(&jac);
        true
    };
    let mut linear = DenseLu::new(vec![1.0; 3], Refresh::Never, Some(constant));
    let mut test = StepTest::new(Vec::new(), REL_TOL, f64::INFINITY, "DNA thin-wall fit");
    let solved = nonlinear::solve(&mut fit, &mut x, &mut linear, &mut FullStep::new(3), &mut test, MAX_ITERATIONS);
    let iterations = match solved {
        Ok(report) => report.iterations,
        Err(e) if e.status == Status::ErrNotConverged => {
            return Err(Error::new(
                Status::ErrNotConverged,
                format!(
                    "DNA thin-wall fit: last Newton step changed the moduli by {:e} (relative), above {REL_TOL:e} \
                     after {MAX_ITERATIONS} iterations (nu12 = {nu12:e} is close to the degenerate -cot^2(alpha) = {:e})",
                    test.last_step,
                    -(m * m) / (n * n)
                ),
            ));
        }
        Err(e) => return Err(e),
    };
    let last_step = test.last_step;
    let tube = fit.tube;
    let stiffness = tube.coupling_stiffness()?;
    let achieved = stiffness.stretch_twist();
    let response = stiffness.free_response()?;
    Ok(FitResult {
        material: tube.material,
        mid_radius,
        thickness,
        helix_angle,
        intrinsic_twist: tau0,
        targets,
        achieved,
        iterations,
        last_step,
        stiffness,
        response,
        twist_rate: TwistRate::from_rad_per_pn_nm(response.dtwist_dforce),
        overwinds: response.winding == Winding::Overwinds,
    })
}

/// The fit for every (t, ν12) pair, t-major: `(t, ν12, fit_thin_wall(...))`.
/// Since K depends on the wall only through t·Q, fits at different t share
/// t·E1, t·E2, t·G12 (moduli ∝ 1/t), while ν12 moves along the genuine
/// one-parameter family of materials at fixed t. Failures (no physical fit at
/// that ν12) are reported in place, not skipped.
pub fn fit_family(
    targets: DnaTargets,
    mid_radius: f64,
    helix_angle: f64,
    thicknesses: &[f64],
    nu12s: &[f64],
) -> Vec<(f64, f64, Result<FitResult>)> {
    let mut out = Vec::with_capacity(thicknesses.len() * nu12s.len());
    for &t in thicknesses {
        for &nu in nu12s {
            out.push((t, nu, fit_thin_wall(targets, mid_radius, helix_angle, t, nu)));
        }
    }
    out
}

/// The out-of-plane constants the thin fit cannot see, needed to evaluate the
/// same wall as a 3-D solid: E3 = e3_over_e2·E2, G13 = g13_over_g12·G12,
/// G23 = g23_over_g12·G12, and ν13, ν23 (axis 3 = e_R, the wall normal).
///
/// The documented default is [`OutOfPlane::default_for`]: **transversely
/// isotropic about the reinforcement** (the standard assumption for a
/// fibre-reinforced wall: the cross-section of the reinforcement has no
/// preferred direction), E3 = E2, ν13 = ν12, G13 = G12,
/// G23 = E2/(2(1 + ν23)), with **ν23 = ν12**. That last choice adds no new
/// parameter and makes the completion of an isotropic surface material the
/// isotropic 3-D material with the same (E, ν), so for isotropic walls the
/// thick–thin difference is geometry only. There is no measurement of these
/// constants for DNA; the thick–thin comparison should be read as "how much
/// the membrane idealisation matters", not as a prediction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutOfPlane {
    pub e3_over_e2: f64,
    pub nu13: f64,
    pub nu23: f64,
    pub g13_over_g12: f64,
    pub g23_over_g12: f64,
}

impl OutOfPlane {
    /// Transversely isotropic about axis 1 (the reinforcement) with the given
    /// ν23: E3 = E2, ν13 = ν12, G13 = G12, G23 = E2/(2(1 + ν23)).
    pub fn transversely_isotropic(surface: &OrthotropicSurface, nu23: f64) -> Self {
        OutOfPlane {
            e3_over_e2: 1.0,
            nu13: surface.nu12,
            nu23,
            g13_over_g12: 1.0,
            g23_over_g12: surface.e2 / (2.0 * (1.0 + nu23)) / surface.g12,
        }
    }

    /// The documented default: transversely isotropic with ν23 = ν12.
    pub fn default_for(surface: &OrthotropicSurface) -> Self {
        Self::transversely_isotropic(surface, surface.nu12)
    }

    /// The nine constants (validated by [`Orthotropic::new`]: a set that is
    /// not positive definite gives `ErrNotPositiveDefinite`).
    pub fn complete(&self, surface: &OrthotropicSurface) -> Result<Orthotropic> {
        for (name, v) in
            [("e3_over_e2", self.e3_over_e2), ("g13_over_g12", self.g13_over_g12), ("g23_over_g12", self.g23_over_g12)]
        {
            error::positive(name, v)?;
        }
        Orthotropic::new(
            surface.e1,
            surface.e2,
            self.e3_over_e2 * surface.e2,
            surface.nu12,
            self.nu13,
            self.nu23,
            surface.g12,
            self.g13_over_g12 * surface.g12,
            self.g23_over_g12 * surface.g12,
        )
    }
}

/// (thick − thin)/thin = thick/thin − 1 for each condensed modulus
/// (dimensionless; positive = same sign and larger in magnitude, which for
/// the negative g of DNA means more negative). When the thin
/// |g| is below 1e-12·√(SC) (no coupling, e.g. an isotropic wall) the
/// coupling difference is divided by √(SC) instead.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelativeDifference {
    pub stretch: f64,
    pub twist: f64,
    pub coupling: f64,
}

/// The fitted wall evaluated by the thick linear model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThickComparison {
    /// The 3-D material (fitted surface constants + out-of-plane completion).
    pub material: Orthotropic,
    /// The thick tube: A = R − t/2, B = R + t/2, same τ0, compressible.
    pub tube: ThickTube,
    /// Condensed law of the thin fit (= the targets to ≤ 1e-12).
    pub thin: StretchTwist,
    /// Condensed law of the thick tube (p = 0; independent of whether the
    /// hoop variable is taken at the inner or the mid radius).
    pub thick: StretchTwist,
    /// Error estimate of the thick K relative to max |K| (≤ [`THICK_REL_TOL`]).
    pub thick_error_estimate: f64,
    /// Chebyshev intervals used.
    pub intervals: usize,
    /// (thick − thin)/thin.
    pub relative_difference: RelativeDifference,
    /// Free thick tube (T = 0, p = 0) per pN.
    pub thick_response: FreeTubeResponse,
    pub thick_twist_rate: TwistRate,
}

/// Evaluate the fitted wall as a thick compressible tube with the same mid
/// radius, thickness and intrinsic twist (inner radius A = R − t/2, outer
/// B = R + t/2; the helix angle now varies through the wall,
/// α(r) = atan(τ0 r), from atan(τ0 A) inside to atan(τ0 B) outside), with
/// the out-of-plane constants from `out_of_plane` (use
/// [`OutOfPlane::default_for`]`(&fit.material)` for the documented default).
/// The geometry is taken from `fit`: the point is the same wall in a
/// different model.
pub fn thick_comparison(fit: &FitResult, out_of_plane: OutOfPlane) -> Result<ThickComparison> {
    let material = out_of_plane.complete(&fit.material)?;
    let half = 0.5 * fit.thickness;
    let tube = ThickTube::new(
        fit.mid_radius - half,
        fit.mid_radius + half,
        fit.intrinsic_twist,
        material,
        Compressibility::Compressible,
    )?;
    let k = tube.coupling_stiffness(THICK_REL_TOL)?;
    let thick = k.value.stretch_twist();
    let thin = fit.achieved;
    let thick_response = k.value.free_response()?;
    // g may vanish (isotropic walls, mirror-symmetric layouts): then measure
    // its difference against the Cauchy–Schwarz bound √(SC) instead.
    let bound = (thin.stretch * thin.twist).sqrt();
    let g_scale = if thin.coupling.abs() > 1e-12 * bound { thin.coupling } else { bound };
    let relative_difference = RelativeDifference {
        stretch: (thick.stretch - thin.stretch) / thin.stretch,
        twist: (thick.twist - thin.twist) / thin.twist,
        coupling: (thick.coupling - thin.coupling) / g_scale,
    };
    error::finite_result(
        "thick-thin relative differences",
        &[relative_difference.stretch, relative_difference.twist, relative_difference.coupling],
    )?;
    Ok(ThickComparison {
        material,
        tube,
        thin,
        thick,
        thick_error_estimate: k.error_estimate,
        intervals: k.intervals,
        relative_difference,
        thick_response,
        thick_twist_rate: TwistRate::from_rad_per_pn_nm(thick_response.dtwist_dforce),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: the library's own rotation S̄ = T(−α) S T(−α)ᵀ
    /// (`OrthotropicSurface::rotated_compliance`), independent of the hand
    /// expansion (2) used by the fit.
    #[test]
    fn hand_expanded_map_equals_rotated_compliance() {
        for &(e1, e2, nu, g, alpha) in
            &[(3.0, 0.7, 0.3, 0.4, 1.047), (1.0, 2.0, -0.2, 5.0, -0.4), (0.5, 0.5, 0.45, 0.1, 1.4)]
        {
            let mat = OrthotropicSurface::new(e1, e2, nu, g).unwrap();
            let sb = mat.rotated_compliance(alpha);
            let y = compliance_map(alpha, nu) * Vector3::new(1.0 / e1, 1.0 / e2, 1.0 / g);
            let reference = Vector3::new(sb[(0, 0)], sb[(0, 2)], sb[(2, 2)]);
            assert!((y - reference).amax() < 1e-14 * sb.amax(), "{y} vs {reference}");
        }
    }

    /// Reference: det of (2) = 2 m n³ (m² + ν12 n²), derived by hand (column
    /// operations: the ν12 part of column 1 is −2·column 3 + 2·e3).
    #[test]
    fn determinant_closed_form() {
        for &(alpha, nu) in &[(1.047f64, 0.3), (0.3, -0.5), (-1.2, 0.7), (0.9, 0.0)] {
            let (n, m) = alpha.sin_cos();
            let d = compliance_map(alpha, nu).determinant();
            let reference = 2.0 * m * n.powi(3) * (m * m + nu * n * n);
            assert!((d - reference).abs() < 1e-14, "{d} vs {reference}");
        }
    }
}

//! A tube problem as users pose it (physics.md §5 "only what a scene
//! requires"): geometry, one wall law, a model choice and a tolerance. With
//! [`TubeModel::Auto`] the cheap membrane (algebraic) is used when its own
//! error estimate meets the tolerance, the thick wall ODE otherwise, and the
//! model used is reported with every answer.

use crate::error::{self, Error, Result};
use crate::status::Status;
use crate::tube::coupling::{CouplingStiffness, StretchTwist};
use crate::tube::finite::{FiniteTube, Loading, SolveOptions, Sweep, TubeState};
use crate::tube::material::{FibreReinforced, NeoHookean, SaintVenantKirchhoff, WallMaterial};
use crate::tube::membrane::MembraneTube;
use crate::tube::orthotropic::Orthotropic;
use crate::tube::rod_law::RodStiffness;
use crate::tube::thick::{Compressibility, Estimated, ThickTube};

/// The wall laws of §1.3, owned (enum dispatch keeps a scene `Send + Sync`).
// SVK carries its 6×6 stiffness ℂ (the enum is 376 bytes, the other laws a few
// words): a scene holds one law, built once and never copied in a loop, and
// boxing the variant would change the public enum the C API and tests build.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum WallLaw {
    SaintVenantKirchhoff(SaintVenantKirchhoff),
    NeoHookean(NeoHookean),
    FibreReinforced(FibreReinforced),
}

impl WallLaw {
    /// Checks the law's constants: SVK's through [`Orthotropic::new`] (at
    /// construction), here μ > 0 and a positive bulk modulus 3λ_L + 2μ > 0
    /// (compressible), fibre stiffnesses k1, k2 > 0, finite angles, hands ±1.
    pub fn validate(&self) -> Result<()> {
        let check_nh = |m: &NeoHookean| -> Result<()> {
            error::positive("shear_modulus", m.shear_modulus)?;
            if !m.incompressible {
                error::finite("lame_lambda", m.lame_lambda)?;
                if !(3.0 * m.lame_lambda + 2.0 * m.shear_modulus > 0.0) {
                    return Err(Error::new(
                        Status::ErrNotPositiveDefinite,
                        format!(
                            "neo-Hookean law is not positive definite: bulk modulus λ_L + 2μ/3 = {:e} must be positive",
                            m.lame_lambda + 2.0 * m.shear_modulus / 3.0
                        ),
                    ));
                }
            }
            Ok(())
        };
        match self {
            WallLaw::SaintVenantKirchhoff(m) => error::finite("intrinsic_twist", m.intrinsic_twist).map(|_| ()),
            WallLaw::NeoHookean(m) => check_nh(m),
            WallLaw::FibreReinforced(f) => {
                check_nh(&f.matrix)?;
                error::finite("intrinsic_twist", f.intrinsic_twist)?;
                // Each family's fields by their C names, fibre1_… and
                // fibre2_… (one shared `fibre_k1` would not say which).
                for (i, fam) in f.families.iter().enumerate() {
                    let name = |field: &str| format!("fibre{}_{field}", i + 1);
                    error::positive(&name("k1"), fam.k1)?;
                    error::positive(&name("k2"), fam.k2)?;
                    match fam.angle {
                        crate::tube::material::fibre::FibreAngle::Helix { hand } => {
                            error::finite(&name("hand"), hand)?;
                            if hand != 1.0 && hand != -1.0 {
                                return Err(Error::new(
                                    Status::ErrOutOfRange,
                                    format!(
                                        "argument `{}` is out of range: it must be +1 or -1 (got {hand:e})",
                                        name("hand")
                                    ),
                                ));
                            }
                        }
                        crate::tube::material::fibre::FibreAngle::Fixed(a) => {
                            error::finite(&name("angle"), a)?;
                        }
                    }
                }
                Ok(())
            }
        }
    }

    /// The law as the material the wall solvers take.
    pub fn as_material(&self) -> &dyn WallMaterial {
        match self {
            WallLaw::SaintVenantKirchhoff(m) => m,
            WallLaw::NeoHookean(m) => m,
            WallLaw::FibreReinforced(m) => m,
        }
    }

    /// The small-strain material of the law (for the linear K): SVK is its
    /// own linearisation; neo-Hookean linearises to isotropic elasticity with
    /// E = μ(3λ_L + 2μ)/(λ_L + μ), ν = λ_L/(2(λ_L + μ)). Tension-only fibres
    /// have no symmetric linearisation (stiff when pulled, free when pushed).
    pub fn small_strain(&self) -> Result<(Orthotropic, Compressibility, f64)> {
        let comp = |inc: bool| if inc { Compressibility::Incompressible } else { Compressibility::Compressible };
        match self {
            WallLaw::SaintVenantKirchhoff(m) => Ok((m.material, comp(m.incompressible), m.intrinsic_twist)),
            WallLaw::NeoHookean(m) => {
                let (mu, lam) = (m.shear_modulus, m.lame_lambda);
                let iso = if m.incompressible {
                    // Any ν gives the same K under tr ε = 0; G = μ fixes E.
                    Orthotropic::isotropic(2.5 * mu, 0.25)?
                } else {
                    Orthotropic::isotropic(mu * (3.0 * lam + 2.0 * mu) / (lam + mu), lam / (2.0 * (lam + mu)))?
                };
                Ok((iso, comp(m.incompressible), 0.0))
            }
            WallLaw::FibreReinforced(_) => Err(Error::new(
                Status::ErrOutOfRange,
                "a fibre-reinforced wall has no linear stiffness at rest: its tension-only fibres are stiff when \
                 stretched and slack when compressed; use finite-strain solves about a pre-stretched state",
            )),
        }
    }
}

/// Which tube model answers (also the C enum RodkitTubeModel, for
/// `RodkitTubeSpec.model` and `RodkitTubeState.model`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TubeModel {
    /// The membrane when its error estimate meets the tolerance, else thick.
    Auto = 0,
    /// The wall ODE (Chebyshev collocation through the thickness).
    Thick = 1,
    /// The thin-wall membrane (algebraic).
    Membrane = 2,
}

/// A tube scene: geometry, law, model choice and tolerance.
#[derive(Clone, Debug, PartialEq)]
pub struct TubeScene {
    pub inner_radius: f64,
    pub outer_radius: f64,
    pub law: WallLaw,
    pub model: TubeModel,
    /// Requested accuracy of the states, in the solvers' scaled measures.
    pub rel_tol: f64,
    /// Fixed Chebyshev intervals for the thick model (None: adaptive).
    pub intervals: Option<usize>,
}

impl TubeScene {
    pub fn new(
        inner_radius: f64,
        outer_radius: f64,
        law: WallLaw,
        model: TubeModel,
        rel_tol: f64,
        intervals: Option<usize>,
    ) -> Result<Self> {
        // Geometry and law are validated by building both models once.
        law.validate()?;
        let scene = TubeScene { inner_radius, outer_radius, law, model, rel_tol, intervals };
        error::in_range("rel_tol", rel_tol, 1e-14, 1.0)?;
        if let Some(n) = intervals {
            error::count_in_range("intervals", n as i64, 4, 256)?;
        }
        scene.thick()?;
        if model == TubeModel::Membrane {
            scene.membrane()?;
        }
        Ok(scene)
    }

    fn thick(&self) -> Result<FiniteTube<'_>> {
        FiniteTube::new(self.inner_radius, self.outer_radius, self.law.as_material())
    }

    fn membrane(&self) -> Result<MembraneTube<'_>> {
        if self.inner_radius == 0.0 {
            return Err(Error::new(
                Status::ErrInvalidGeometry,
                "a solid cylinder has no membrane model: use the thick model",
            ));
        }
        MembraneTube::new(
            0.5 * (self.inner_radius + self.outer_radius),
            self.outer_radius - self.inner_radius,
            self.law.as_material(),
        )
    }

    fn options(&self) -> SolveOptions {
        SolveOptions { rel_tol: self.rel_tol, intervals: self.intervals }
    }

    /// The equilibrium under `loading` and the model that produced it; every
    /// returned field is checked finite and physical (see [`check_state`]).
    pub fn solve(&self, loading: &Loading) -> Result<(TubeState, TubeModel)> {
        let (state, model) = self.solve_unchecked(loading)?;
        check_state(&state)?;
        Ok((state, model))
    }

    fn solve_unchecked(&self, loading: &Loading) -> Result<(TubeState, TubeModel)> {
        match self.model {
            TubeModel::Thick => Ok((self.thick()?.solve(loading, &self.options())?, TubeModel::Thick)),
            TubeModel::Membrane => Ok((self.membrane()?.solve(loading)?, TubeModel::Membrane)),
            TubeModel::Auto => {
                if self.inner_radius > 0.0 {
                    if let Ok(s) = self.membrane()?.solve(loading) {
                        if s.error_estimate <= self.rel_tol {
                            return Ok((s, TubeModel::Membrane));
                        }
                    }
                }
                Ok((self.thick()?.solve(loading, &self.options())?, TubeModel::Thick))
            }
        }
    }

    /// A sweep along `loadings` with one model for all states (for Auto: the
    /// membrane if its estimate meets the tolerance at the last loading).
    pub fn sweep(
        &self,
        loadings: &[Loading],
        progress: impl FnMut(usize, &TubeState) -> bool,
    ) -> Result<(Sweep, TubeModel)> {
        let model = match (self.model, loadings.last()) {
            (TubeModel::Auto, Some(last)) => self.solve(last)?.1,
            (TubeModel::Auto, None) => TubeModel::Thick,
            (m, _) => m,
        };
        let sweep = match model {
            TubeModel::Membrane => self.membrane()?.sweep(loadings, progress)?,
            _ => self.thick()?.sweep(loadings, &self.options(), progress)?,
        };
        Ok((sweep, model))
    }

    /// Linear coupling stiffness K about the stress-free state, in the
    /// inner-radius variables (ε, ψ, ε_A) ↔ (F, T, 2πA²p) (§1.4), from the
    /// thick linear theory of the law's small-strain material.
    pub fn coupling_stiffness(&self) -> Result<Estimated<CouplingStiffness>> {
        let (mat, comp, tau0) = self.law.small_strain()?;
        ThickTube::new(self.inner_radius, self.outer_radius, tau0, mat, comp)?
            .coupling_stiffness(self.rel_tol.max(1e-12))
    }

    /// The tube section as a rod (§1.5 "effective rod law"): the condensed
    /// stretch–twist law [[S, g], [g, C]] at zero pressure, ready for the
    /// hemitropic rod of §2.2 (solid cylinders included).
    pub fn stretch_twist(&self) -> Result<StretchTwist> {
        if self.inner_radius > 0.0 {
            return self.coupling_stiffness()?.value.stretch_twist_checked();
        }
        let (mat, comp, tau0) = self.law.small_strain()?;
        let tube = ThickTube::new(0.0, self.outer_radius, tau0, mat, comp)?;
        let law = tube.stretch_twist_estimated(self.rel_tol.max(1e-12))?.value;
        law.check()?;
        Ok(law)
    }

    /// The section's 6×6 hemitropic rod law (u1, u2, u3, v1, v2, v3) ↔
    /// (m, n) of §2.2, from the thick theory (stretch–twist) and layer-wise
    /// thin-walled beam theory (bending, shear; see [`crate::tube::rod_law`]).
    pub fn rod_stiffness(&self) -> Result<Estimated<RodStiffness>> {
        let (mat, comp, tau0) = self.law.small_strain()?;
        ThickTube::new(self.inner_radius, self.outer_radius, tau0, mat, comp)?.rod_stiffness(self.rel_tol.max(1e-12))
    }
}

/// No silent wrong answers: a state is returned only with every scalar and
/// profile entry finite, a finite non-negative error estimate and deformed
/// radii of the right sign and order (0 ≤ a < b).
pub fn check_state(s: &TubeState) -> Result<()> {
    let scalars = [
        s.stretch,
        s.twist,
        s.wall_force,
        s.applied_force,
        s.torque,
        s.inner_pressure,
        s.outer_pressure,
        s.deformed_inner_radius,
        s.deformed_outer_radius,
        s.error_estimate,
    ];
    error::finite_result("tube state", &scalars)?;
    let p = &s.profile;
    for column in [&p.reference_radius, &p.radius, &p.sigma_rr, &p.sigma_tt, &p.sigma_zz, &p.sigma_tz] {
        error::finite_result("tube wall profile", column)?;
    }
    // A solid cylinder reports a deformed inner radius of 0, a tube a
    // positive one: negative is never physical.
    let radii_ok = s.deformed_inner_radius >= 0.0 && s.deformed_outer_radius > s.deformed_inner_radius;
    if !(s.error_estimate >= 0.0 && s.stretch > 0.0 && radii_ok) {
        return Err(Error::new(
            Status::ErrMaterialInstability,
            format!(
                "tube state is not physical: stretch {:e}, deformed radii {:e} and {:e}, error estimate {:e} \
                 (the section collapsed or inverted)",
                s.stretch, s.deformed_inner_radius, s.deformed_outer_radius, s.error_estimate
            ),
        ));
    }
    Ok(())
}

//! The DNA supercoiling scene (physics.md §3): a Kirchhoff rod in nm and pN,
//! clamped at both ends, pulled and turned (or torqued), with the effective
//! line charge of DNA screened by salt; its path — the straight rod to its
//! first buckling point, then the buckled branch towards a plectoneme — and
//! the observables users compare with magnetic-tweezers experiments
//! ([`Observables`]).

use super::branch::{continue_with, follow_on, hard_core_idle, switch, ChargedBranch, ListAnchor};
use super::rod::{ListRule, RodCharge};
use crate::continuation::anm::AnmOptions;
use crate::continuation::newton::Start;
use crate::continuation::stability::StabilityOptions;
use crate::continuation::{Options, Record, Stop};
use crate::error::{self, Error, Result};
use crate::rod::model::{unwrap_rotation, Rod, Supports};
use crate::status::Status;

/// What a state shows an experimentalist.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observables {
    /// End rotation φ / 2π.
    pub turns: f64,
    /// Extension z(L).
    pub extension: f64,
    /// Spatial end moment about the axis (the torque applied at s = L).
    pub torque: f64,
    /// Spatial axial end force.
    pub tension: f64,
    /// Twist and writhe (turns); Tw + Wr = turns for a clamped rod.
    pub twist: f64,
    pub writhe: f64,
}

/// Tolerance (turns) of the writhe in [`observables`]
/// ([`crate::geometry::writhe::writhe_within`]: panel pairs by separation,
/// Duffy's map at the Hermite centreline's C¹ nodes, closed-form rays).
/// Measured on the 1 kbp scene's states (100 elements, 301 profile points;
/// tests/writhe.rs `measure_dna_states`, benches/README.md):
/// ≤ 4e-10 from a 1e-10 reference, ~4 ms a state, where the former
/// Gauss(4) rule erred by 3.7e-6 in 46 ms (order 8: 3.3e-7 in 170 ms); on
/// a DNA-like 12-turn plectoneme through 301 points (Wr −6.6) 1e-11 from
/// Fuller's independent value, the old rule 2.1e-5. The writhe is then no
/// longer what limits |Tw + Wr − turns| (the states' own ~1e-6 is).
pub const WRITHE_TOLERANCE: f64 = 1e-6;

/// The observables of state `x` at end rotation `phi`.
pub fn observables(rod: &Rod, x: &[f64], phi: f64) -> Result<Observables> {
    let (n, m) = rod.spatial_force_moment(x, rod.elements);
    Ok(Observables {
        turns: phi / (2.0 * std::f64::consts::PI),
        extension: rod.tip(x)[2],
        torque: m[2],
        tension: n[2],
        twist: rod.twist(x),
        writhe: rod.writhe_within(x, WRITHE_TOLERANCE)?.value,
    })
}

/// A DNA supercoiling scene in nm and pN (physics.md §3): a Kirchhoff rod
/// clamped at both ends, pulled by `tension` and turned by the end
/// rotation, carrying the effective line charge of DNA screened by
/// monovalent salt.
#[derive(Clone, Debug, PartialEq)]
pub struct DnaScene {
    pub base_pairs: usize,
    /// Rise per base pair (nm): 0.34.
    pub rise: f64,
    /// Tension (pN).
    pub tension: f64,
    /// Monovalent salt concentration (mol/L).
    pub salt: f64,
    /// Effective charge per length ν (e/nm). Default 1/l_B, Manning's
    /// condensation limit (G. S. Manning, J. Chem. Phys. 51, 924 (1969)):
    /// the charge left on a line of bare spacing below l_B after counterion
    /// condensation, independent of the salt. Poisson–Boltzmann effective
    /// charges (Stigter's, used by Vologodskii & Cozzarelli) are larger and
    /// salt dependent; pass one here to use it.
    pub charge_per_length: f64,
    /// Radius a (nm): the near zone's excluded length and the crossing distance 2a.
    pub radius: f64,
    /// Bending and twist persistence lengths (nm): K_b = A k_BT, C = P k_BT.
    pub bending_persistence: f64,
    pub twist_persistence: f64,
    /// Temperature (K) and relative permittivity of water.
    pub temperature: f64,
    pub permittivity: f64,
}

impl Default for DnaScene {
    /// 1 kbp, 1 pN, 0.1 M NaCl, ν = 1/l_B, a = 1 nm, A = 50 nm, P = 95 nm, 298.15 K, ε_r = 78.4.
    fn default() -> Self {
        let mut s = DnaScene {
            base_pairs: 1000,
            rise: 0.34,
            tension: 1.0,
            salt: 0.1,
            charge_per_length: 0.0,
            radius: 1.0,
            bending_persistence: 50.0,
            twist_persistence: 95.0,
            temperature: 298.15,
            permittivity: 78.4,
        };
        s.charge_per_length = 1.0 / s.bjerrum_length();
        s
    }
}

impl DnaScene {
    /// k_BT in pN·nm.
    pub fn kt(&self) -> f64 {
        1.380_649e-23 * self.temperature * 1e21
    }

    /// l_B = e²/(4πε0 ε_r k_BT) in nm.
    pub fn bjerrum_length(&self) -> f64 {
        let e = 1.602_176_634e-19;
        let eps0 = 8.854_187_812_8e-12;
        e * e / (4.0 * std::f64::consts::PI * eps0 * self.permittivity * 1.380_649e-23 * self.temperature) * 1e9
    }

    /// κ = √(8π l_B n) for a 1:1 salt of number density n (nm⁻³).
    pub fn kappa(&self) -> f64 {
        let n = self.salt * 6.022_140_76e23 * 1e3 * 1e-27;
        (8.0 * std::f64::consts::PI * self.bjerrum_length() * n).sqrt()
    }

    pub fn length(&self) -> f64 {
        self.base_pairs as f64 * self.rise
    }

    pub fn validate(&self) -> Result<()> {
        error::count_in_range("base_pairs", self.base_pairs as i64, 10, 1 << 24)?;
        for (n, v) in [
            ("rise", self.rise),
            ("tension", self.tension),
            ("radius", self.radius),
            ("bending_persistence", self.bending_persistence),
            ("twist_persistence", self.twist_persistence),
            ("temperature", self.temperature),
            ("permittivity", self.permittivity),
        ] {
            error::positive(n, v)?;
        }
        error::finite("salt", self.salt)?;
        error::finite("charge_per_length", self.charge_per_length)?;
        if self.salt < 0.0 || self.charge_per_length < 0.0 {
            return Err(Error::new(Status::ErrOutOfRange, "salt and charge_per_length must be ≥ 0"));
        }
        Ok(())
    }

    /// The rod: Gauss(`stages`) collocation on `elements` elements, end
    /// rotation controlled at fixed tension.
    pub fn rod(&self, elements: usize, stages: usize) -> Result<Rod> {
        self.rod_controlled(elements, stages, EndControl::Rotation)
    }

    /// The rod with the end rotation ([`Supports::Twisted`]: the
    /// parameter is φ) or the end torque ([`Supports::Torqued`]: the
    /// parameter is M, pN nm) controlled, at fixed tension.
    pub fn rod_controlled(&self, elements: usize, stages: usize, control: EndControl) -> Result<Rod> {
        self.validate()?;
        let kt = self.kt();
        let law = crate::rod::RodLaw::kirchhoff(
            self.bending_persistence * kt,
            self.bending_persistence * kt,
            self.twist_persistence * kt,
        )?;
        let supports = match control {
            EndControl::Rotation => Supports::Twisted { tension: self.tension },
            EndControl::Torque => Supports::Torqued { tension: self.tension },
        };
        Rod::new(
            law,
            self.length(),
            crate::rod::Loads::default(),
            supports,
            crate::rod::scheme::Scheme::Gauss(stages),
            elements,
        )
    }

    /// The charge: λ² = k_BT l_B ν² (pN), κ from the salt (0: Coulomb).
    pub fn charge(&self) -> RodCharge {
        let lambda = (self.kt() * self.bjerrum_length()).sqrt() * self.charge_per_length;
        RodCharge::new(lambda, crate::electrostatics::Screening { kappa: self.kappa(), a: self.radius })
    }
}

/// What the experiment holds at the rod's end: the turns (magnetic
/// tweezers) or the torque (a torque clamp). The equilibria are the same;
/// the path is parametrised by φ or by M, and under torque control the
/// buckling transition is a fold in M (the torque overshoots, then drops to
/// the plectoneme's plateau) that the continuation passes by arc length.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum EndControl {
    #[default]
    Rotation,
    Torque,
}

/// The element length (nm) of the automatic mesh
/// ([`SupercoilSettings::elements`] 0). Measured on the 1 kbp, 1 pN, 0.1 M
/// curve, 0 → 5.5 turns, Gauss(2), against 150 elements of Gauss(3): torque
/// and extension on the plectoneme leg (0.05 turns from its fold on) within
/// 3.1e-3 and 2.9e-3 relative with 3.4 nm elements, 3.4e-4 and 3.3e-4 with
/// 2.27 nm, 2.9e-4 and 1.5e-4 with 1.7 nm (the reference's own error,
/// ~1e-4, is the floor): ~h⁴, and 2 nm is the longest with a margin under
/// the 1e-3 target for torque and extension (benches/README.md). At 0.2 M (Debye length 0.68 nm) 3.4 nm elements are
/// qualitatively wrong — the path folds at every element the end loop
/// crosses and stalls at 3 turns — while 2 nm reaches the plectoneme
/// (0 → 5.5 turns in 903 points) but is not within 1e-3 there: up to 7.5e-3
/// in torque from 150 elements of Gauss(3), oscillating along the
/// plectoneme leg. How short denser strands (higher salt or force) need the
/// elements is not determined yet.
pub const AUTO_ELEMENT_LENGTH: f64 = 2.0;

/// How the supercoiling path of a [`DnaScene`] is computed.
#[derive(Clone, Debug, PartialEq)]
pub struct SupercoilSettings {
    /// Elements of the rod; 0 (the default): the automatic mesh, elements
    /// of at most [`AUTO_ELEMENT_LENGTH`] (at least 8;
    /// [`SupercoilSettings::elements_for`]). The run's rod says which.
    pub elements: usize,
    pub stages: usize,
    /// Relative energy tolerance of the screening cutoff (None: every pair).
    pub cutoff_tolerance: Option<f64>,
    /// Hard-core stiffness (pN/nm⁴), None: none.
    pub hard_core: Option<f64>,
    /// Threads for the pair forces; with 2 or more, the buckled branch's
    /// records also take their determinant signs on a second thread while
    /// the next step is corrected, where they have a factorisation of
    /// their own ([`SupercoilSettings::separate_signs_from`]). Results are
    /// bitwise the same for any count: one thread factorises as two do.
    pub threads: usize,
    /// From this many unknowns of the rod, the buckled branch's points are
    /// factorised for their tangents only (block elimination) and their
    /// records' determinant signs taken from B's simplicial LU, a
    /// factorisation of their own ([`Options::overlap_records`]), which a
    /// second thread runs while the next step is corrected
    /// ([`SupercoilSettings::threads`] ≥ 2); below, each point's tangent
    /// and signs come from its own simplicial LU. Not a thread choice: the
    /// path is the same, bitwise, for any thread count. Default 3000,
    /// measured (benches/README.md): at 6645 unknowns (1 kbp,
    /// 170 elements) separate signs cost +2.6 % on one thread and two
    /// threads are 1.17× faster; at 950 (250 bp, 24 elements) they cost
    /// +16–19 % on one thread, and two threads did not beat one thread
    /// with the signs at the points.
    pub separate_signs_from: usize,
    /// Count every point's unstable modes on its own factorisation
    /// ([`Options::stability`]: the eigenvalues of the second variation
    /// nearest zero by shift-invert subspace iteration): the records'
    /// determinant signs then follow from the counts, and no record is
    /// factorised a second time (`separate_signs_from` does not apply).
    /// None: the signs from B's simplicial LU as before, and the stability
    /// from the parity rules of [`crate::charged::coexistence`].
    pub stability: Option<StabilityOptions>,
    /// The buckled branch stops past this many turns (or when turns fall
    /// to zero), at the step limit, or at a strand crossing.
    pub max_turns: f64,
    pub max_steps: usize,
    pub residual_tol: f64,
    /// The discrete base-pair model (charges at the scene's rise, the
    /// thesis's comparison; [`RodCharge::base_pairs`]) instead of the
    /// continuum line charge.
    pub base_pairs: bool,
    /// The continuum's far zone on this many Gauss–Legendre points per
    /// element (0: the stage points; [`RodCharge::far_points`]).
    pub far_points: usize,
    /// The near zone's least physical width (nm; [`RodCharge::near_width`]),
    /// None: the charge's default (4a).
    pub near_width: Option<f64>,
    /// Cut the near zone at exactly its width
    /// ([`RodCharge::exact_near_width`]; default false).
    pub exact_near_width: bool,
    /// A graded mesh: the nodes as fractions of the length, 0 … 1
    /// ([`Rod::graded`]; then `elements` is their count less one, or 0).
    /// Needs `exact_near_width` (the element-aligned near zone assumes equal
    /// elements). None (the default): equal elements.
    pub breakpoints: Option<Vec<f64>>,
    /// End rotation (default) or end torque as the continuation parameter.
    pub control: EndControl,
    /// Switch the hard core on by itself ([`auto_hard_core`]) when the
    /// buckled branch's strands cross without one (`hard_core` None), and
    /// go on from the point before the crossing; the run says so
    /// ([`SupercoilRun::hard_core_switch`]). Off: the branch stops there.
    pub hard_core_auto: bool,
    /// How the buckled branch is followed (the straight one always takes
    /// Newton steps with the Euler predictor: there the Jacobian changes
    /// fast with φ and a factorisation is cheap).
    pub engine: Engine,
    /// How the Newton corrections factorise (None: by structure —
    /// block elimination on a supernodal LU once a plectoneme's far pairs
    /// widen the Jacobian; see [`Options::lu_kind`]).
    pub lu_kind: Option<crate::linalg::LuKind>,
    /// The Newton iterations a step of the buckled branch is sized for by the
    /// Hermite engine ([`Options::corrector_aim`], 1–12; `Engine::Newton`
    /// keeps 3). A step costs its record's simplicial factorisation (its
    /// determinant signs: ~75 ms at 5–12 turns of the 1 kbp scene, 100
    /// elements) and a block elimination per correction (~22 ms), so aiming
    /// higher makes the steps longer and fewer — measured on that scene at
    /// 0.1 M, 0 → 12 turns (benches/README.md): aim 3 (the
    /// default), 572 buckled steps, 113 s; 4, 345 steps, 78 s; 5, 271 steps,
    /// 70.5 s (~25 points a turn). A step that carries stages so far past the
    /// Verlet skin that its point does not re-converge on the next pair list
    /// is taken again, shorter ([`crate::charged::branch`]). Not the default:
    /// analyses that interpolate the path (the torque-clamp comparison, a
    /// coexistence premise) want denser points. With aim 5 the 300 bp, 2 pN,
    /// 0.1 M scene's corrector landed on a solution with μ ≠ 0
    /// (μ = −1.1e-6 pN; a tilted state, a solution of the discretised
    /// equations only) at the buckled branch's point 51, which ended the run
    /// with an error; it is now taken again with half the step, once, and the
    /// branch goes on ([`SupercoilSettings::unfolding_retakes`],
    /// tests/supercoil_hard_core.rs).
    pub corrector_aim: f64,
    /// How often a point of the buckled branch that left the unfolding
    /// parameter μ = 0 (a corrector sliding onto the spurious straight
    /// family — straight state, any μ — or onto a tilted solution with
    /// μ ≠ 0 that only the discretised equations have; the run's error says
    /// which, `Rod::unfolding_failure`) is taken again from the point before,
    /// halving the step each time (4: down to 1/16 of the step), before the
    /// run ends there with the path so far ([`RunStop::Failed`]). With
    /// corrector aim 5 the 300 bp, 2 pN, 0.1 M scene's buckled branch needed
    /// one retake at its point 51 (tests/supercoil_hard_core.rs); the 1 kbp,
    /// 1 pN, 0.01 M one (100 elements, aim 3) two at its point 667, next to
    /// the straight rod, where it had slid onto that family and the run,
    /// after 339 s, returned only the error.
    pub unfolding_retakes: usize,
    /// The accuracy asked of the curve, relative (torque against the
    /// larger of its value and one turn's torque on the straight rod,
    /// 2πC/L). What it sets: the largest moment the buckled branch's
    /// unfolding couple may carry, a tenth of this of that torque
    /// ([`Options::unfolding_moment`]). μ on a tilted state of the
    /// followed branch is the scheme's violation of the axial-moment
    /// integral and grows with the plectoneme (1 kbp, 1 pN, 0.1 M at 170 ×
    /// Gauss(2): a moment of 6.8e-5 pN nm at 10 turns, where μ beyond 1e-6
    /// of its scale, the check before, ended the run). Default 1e-3, in
    /// (0, 0.1].
    pub tolerance: f64,
    /// When the branches rebuild their pair lists ([`ListRule`]: Verlet's
    /// half-skin displacement by default).
    pub list_rule: ListRule,
    /// The series' order and ε when `engine` is [`Engine::Anm`] (20 and
    /// 1e-4: on the 300 bp scene to 2.5 turns with coverage lists, 55
    /// buckled steps against 76 at 1e-6 and 109 at 1e-8, the same path
    /// within 5e-4 of M_b).
    pub anm: AnmOptions,
}

/// The predictor–corrector of the buckled branch. Both give points
/// converged to the same residual tolerance on the same branch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Engine {
    /// Euler predictor, Newton corrector with a factorisation per
    /// iteration, steps sized for 3 iterations: the original engine.
    Newton,
    /// Cubic Hermite extrapolation from the last two points and their
    /// tangents ([`Options::hermite_predictor`]), Newton corrector. On the
    /// 1 kbp scene's unstable leg (400 steps from buckling) 1.53 turns of
    /// path in 59 s against Newton's 0.6 turns in 24 s per 120 steps; on
    /// 300 bp at 0.01 M to 3 turns 66 steps and 13.8 s against 132 and
    /// 29.6 s.
    #[default]
    Hermite,
    /// The asymptotic numerical method: the Taylor series of the charged
    /// rod (pair forces included, [`crate::charged::rod`]'s series) from
    /// one factorisation a step, the step from the series' convergence
    /// ([`SupercoilSettings::anm`]) and the pair list's rule, the end
    /// point Newton-corrected (chords on the step's factorisation) when
    /// its residual is above the tolerance. The continuum model only.
    ///
    /// Not the default: measured on the 1 kbp, 1 pN, 0.1 M scene (100
    /// elements, ε 1e-4, pair lists by [`ListRule::Coverage`];
    /// benches/README.md) it is no faster — 0 → 5.5 turns 43.1 s
    /// against Hermite's 38.4 s; with Verlet's lists, which cut its steps
    /// at half the skin, slower still — because the series'
    /// radius stays ~0.1–0.3 (scaled arc length) on the plectoneme and
    /// collapses to 1e-3 next to the folds (singularities off the real
    /// path), so its steps are no longer than Hermite's, and its end points
    /// need ~4 chord iterations. A point that leaves μ = 0 ends its run
    /// (no point before it is kept to retake from): one did at 7.26 turns,
    /// where the Hermite engine with coverage lists lost its branch too.
    Anm,
}

impl SupercoilSettings {
    /// The elements a run of `scene` takes: `elements`, or with 0 the
    /// automatic mesh, ⌈L / [`AUTO_ELEMENT_LENGTH`]⌉ and at least 8 (170 for
    /// 1 kbp, 510 for 3 kbp). Refused (ErrOutOfRange) when that is more than
    /// 2¹⁸ elements, a mesh no run here could factorise (a 1 Mbp scene).
    pub fn elements_for(&self, scene: &DnaScene) -> Result<usize> {
        if let Some(t) = &self.breakpoints {
            let n = t.len().saturating_sub(1);
            if self.elements != 0 && self.elements != n {
                return Err(Error::new(
                    Status::ErrInvalidDimension,
                    format!(
                        "`elements` ({}) and the graded mesh's {n} elements differ: give one of them",
                        self.elements
                    ),
                ));
            }
            return Ok(n.max(1));
        }
        if self.elements > 0 {
            return Ok(self.elements);
        }
        // ⌈·⌉ less a rounding's worth: 3000 × 0.34 nm is 1020.0000000000001.
        let n = (scene.length() / AUTO_ELEMENT_LENGTH * (1.0 - 1e-12)).ceil().max(8.0);
        if !(n <= (1 << 18) as f64) {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!(
                    "the automatic mesh of a {:.4e} nm rod would take {n:.4e} elements of {AUTO_ELEMENT_LENGTH} nm, more \
                     than 2^18: give `elements`",
                    scene.length()
                ),
            ));
        }
        Ok(n as usize)
    }
}

/// The DNA scenes' neutral band ([`StabilityOptions::marginal`]): |σ| ≤
/// 3e-2 T²/K_b on the buckled branch. On the 1 kbp, 1 pN, 0.1 M scene
/// (170 × Gauss(2)) the formed plectoneme has one σ near zero whose sign
/// flips between consecutive points (det R_x with it): at −2e-3 … −1e-2
/// T²/K_b on the negative side, within what the model's own
/// approximations (a pair list cut off at 1e-4 of a line's energy, the
/// mesh) decide — a sign that is not the physics'. The modes that cross
/// zero at the branch's folds and bifurcations are beyond 4e-2 T²/K_b a
/// few steps away from their crossing.
pub const DNA_MARGINAL: f64 = 3e-2;

impl Default for SupercoilSettings {
    /// The automatic mesh (elements of 2 nm, Gauss(2): 170 for 1 kbp), cutoff 1e-4, no hard
    /// core, 1 thread, to 12 turns in at most 600 steps, scaled residual
    /// 1e-8 (forces to ~1e-8 of λ² ≈ 6 pN: Newton then converges in 2
    /// iterations and the step grows; at 1e-10 it always takes 3 and the
    /// step stays where it started: on 1 kbp at 0.1 M, 150 steps reach the
    /// fold at 3.46 turns, extension 172 nm, at 1e-8).
    fn default() -> Self {
        SupercoilSettings {
            elements: 0,
            stages: 2,
            cutoff_tolerance: Some(1e-4),
            hard_core: None,
            threads: 1,
            separate_signs_from: 3000,
            stability: Some(StabilityOptions { marginal: DNA_MARGINAL, ..Default::default() }),
            max_turns: 12.0,
            max_steps: 600,
            residual_tol: 1e-8,
            base_pairs: false,
            far_points: 0,
            near_width: None,
            exact_near_width: false,
            breakpoints: None,
            control: EndControl::Rotation,
            hard_core_auto: true,
            engine: Engine::default(),
            lu_kind: None,
            corrector_aim: 3.0,
            unfolding_retakes: 4,
            tolerance: 1e-3,
            list_rule: ListRule::Displacement,
            anm: AnmOptions { order: 20, epsilon: 1e-4, pade: false },
        }
    }
}

/// One point of the supercoiling path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathPoint {
    /// End rotation (rad), followed along the path.
    pub phi: f64,
    /// The continuation parameter Λ: φ (rotation control) or the end
    /// torque M (pN nm, torque control).
    pub parameter: f64,
    pub observables: Observables,
    /// 0: the straight branch, 1: the buckled one.
    pub branch: usize,
    pub residual: f64,
}

/// The supercoiling path of a scene: straight twisting up to the first
/// buckling point (located), then the buckled branch.
#[derive(Clone, Debug)]
pub struct SupercoilRun {
    pub scene: DnaScene,
    pub rod: Rod,
    pub charge: RodCharge,
    pub points: Vec<PathPoint>,
    pub states: Vec<Vec<f64>>,
    /// The located buckling point: end rotation and torque.
    pub buckling: Option<(f64, f64)>,
    pub straight: ChargedBranch,
    pub buckled: Option<ChargedBranch>,
    pub seconds: f64,
    /// Of which the observables of the points (the writhe above all;
    /// the branches' own work and times are in their counts).
    pub observables_seconds: f64,
    /// The hard core the scene switched on by itself, where
    /// ([`SupercoilSettings::hard_core_auto`]); `charge` is then the model
    /// with it.
    pub hard_core_switch: Option<HardCoreSwitch>,
    /// The settings it was run with ([`resume`] goes on with them), with
    /// the elements it took (the automatic mesh's count for `elements` 0).
    pub settings: SupercoilSettings,
    /// Whether the run went to its end, its progress callback stopped it,
    /// or the buckled branch failed partway.
    pub stop: RunStop,
    /// Where a cancelled run goes on ([`resume`]); None once finished.
    pub resume_at: Option<ResumeAt>,
}

/// Why a run returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RunStop {
    /// The path went to its end: the straight branch without a buckling
    /// point, or the buckled branch's own stop (`buckled.stop`, a strand
    /// crossing in `buckled.contact`).
    #[default]
    Finished,
    /// The progress callback asked to stop after the last point; the run
    /// holds the path so far and [`resume`] continues it.
    Cancelled,
    /// The buckled branch failed partway with `status` (its message:
    /// `buckled.failure`, [`SupercoilRun::failure`]): a point kept leaving
    /// μ = 0 however short the step ([`SupercoilSettings::unfolding_retakes`];
    /// ErrNotConverged), or a correction failed. The run holds the path up
    /// to its last good point; it cannot be resumed.
    Failed { status: Status },
}

/// Where a cancelled run goes on.
#[derive(Clone, Debug, PartialEq)]
pub enum ResumeAt {
    /// The straight branch's chunk `chunk` (0: the first, large steps)
    /// towards φ = `target`, `steps` taken in it, on the pair list of
    /// `anchor` (None: the chunk starts at the branch's resume point).
    Straight { chunk: usize, target: f64, steps: usize, anchor: Option<ListAnchor> },
    /// The straight branch is done: the buckled branch starts.
    Buckling,
    /// The buckled branch goes on from its resume point, on the pair list
    /// of `anchor`.
    Buckled { anchor: ListAnchor },
}

/// What the progress callback of [`run_scene_with`] and [`resume`] is
/// told after each converged point of the path (the point as the run keeps
/// it; the writhe and twist are computed once the branch returns).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointProgress {
    /// The point's index in the run's points (a resumed run goes on counting).
    pub index: usize,
    /// 0: the straight branch, 1: the buckled one.
    pub branch: usize,
    /// End rotation φ (rad) and its turns, the continuation parameter Λ.
    pub phi: f64,
    pub turns: f64,
    pub parameter: f64,
    /// Extension z(L) (nm), end torque M_z(L) (pN nm), axial force (pN).
    pub extension: f64,
    pub torque: f64,
    pub tension: f64,
    pub residual: f64,
    /// Angle (radians) between the tip tangent and e3.
    pub tip_rotation: f64,
}

/// Run a scene: the straight branch from φ = 0 in chunks of a quarter of
/// Greenhill's estimate φ_G = 2√(K_b T) L / C until the first buckling
/// point is located (at most 3φ_G), then the buckled branch from it (phase
/// condition, first step 0.02) until `max_turns`, the step limit or a
/// strand crossing. Under torque control the same, with the targets in M =
/// Cφ/L (the straight rod's torque: electrostatics exerts none on a
/// straight line) and the turns read from each state, followed by
/// continuity.
pub fn run_scene(scene: &DnaScene, settings: &SupercoilSettings) -> Result<SupercoilRun> {
    run_scene_with(scene, settings, |_| true)
}

/// [`run_scene`] telling `progress` each point of the path once, in order;
/// when it returns false the run stops after that point and is returned
/// with `stop` = [`RunStop::Cancelled`] ([`resume`] continues it). An error
/// of the buckled branch once it has points does not discard the path:
/// the run is returned with `stop` = [`RunStop::Failed`] and the points up
/// to the last good one (points of a segment whose engine failed were
/// told to `progress` and are not in it); errors before return as such.
pub fn run_scene_with(
    scene: &DnaScene,
    settings: &SupercoilSettings,
    mut progress: impl FnMut(&PointProgress) -> bool,
) -> Result<SupercoilRun> {
    let start = std::time::Instant::now();
    let rod = scene.rod_controlled(settings.elements_for(scene)?, settings.stages, settings.control)?;
    let rod = match &settings.breakpoints {
        Some(t) => rod.graded(t)?,
        None => rod,
    };
    // The automatic mesh resolved: the run's settings say the elements taken.
    let settings = &SupercoilSettings { elements: rod.elements, ..settings.clone() };
    let mut charge = scene.charge();
    charge.cutoff_tolerance = settings.cutoff_tolerance;
    charge.hard_core = settings.hard_core;
    charge.threads = settings.threads;
    charge.base_pairs = settings.base_pairs.then_some(scene.rise);
    charge.far_points = settings.far_points;
    charge.near_width = settings.near_width.or(charge.near_width);
    charge.exact_near_width = settings.exact_near_width;
    charge.list_rule = settings.list_rule;
    error::positive("max_turns", settings.max_turns)?;
    error::count_in_range("max_steps", settings.max_steps as i64, 1, 1 << 24)?;
    error::positive("residual_tol", settings.residual_tol)?;
    error::in_range("tolerance", settings.tolerance, f64::MIN_POSITIVE, 0.1)?;
    let torque = settings.control == EndControl::Torque;
    let mut tell = Reporter { rod: &rod, turns: Turns { torque, phi: 0.0 }, index: 0, branch: 0, user: &mut progress };
    let (straight, at) = straight_path(&rod, &charge, scene.tension, settings, None, &mut tell)?;
    let mut run = SupercoilRun {
        scene: scene.clone(),
        rod,
        charge,
        points: Vec::new(),
        states: Vec::new(),
        buckling: None,
        straight,
        buckled: None,
        seconds: 0.0,
        observables_seconds: 0.0,
        settings: settings.clone(),
        stop: RunStop::Finished,
        resume_at: None,
        hard_core_switch: None,
    };
    run.extend_points()?;
    if let Some(at) = at {
        return Ok(run.cancelled_at(at, start));
    }
    if !run.straight.bifurcations.is_empty() {
        run.go_on(ResumeAt::Buckling, &mut progress)?;
    }
    run.seconds = start.elapsed().as_secs_f64();
    Ok(run)
}

/// Continue a run its progress callback stopped ([`RunStop::Cancelled`];
/// a finished run is left as it is) with the settings it was run with, to
/// the same end as the uninterrupted run: in the straight phase the
/// straight branch resumed from its last point in the same chunk (the
/// engine's resume: the tangent recomputed there), in the buckled phase
/// the buckled branch resumed from its last point with its phase
/// condition, its tangent and step, on the same pair list. `progress` is
/// told the new points, their indices going on from the run's; it may stop
/// the run again. The run's `seconds` add up. On an error the run stays
/// valid, resumable from the last phase boundary or stop it reached.
pub fn resume(run: &mut SupercoilRun, mut progress: impl FnMut(&PointProgress) -> bool) -> Result<()> {
    let Some(at) = run.resume_at.clone() else {
        return Ok(());
    };
    let start = std::time::Instant::now();
    let result = run.go_on(at, &mut progress);
    run.seconds += start.elapsed().as_secs_f64();
    result
}

impl SupercoilRun {
    /// The run stopped by its callback at `at`.
    fn cancelled_at(mut self, at: ResumeAt, start: std::time::Instant) -> Self {
        self.stop = RunStop::Cancelled;
        self.resume_at = Some(at);
        self.seconds = start.elapsed().as_secs_f64();
        self
    }

    /// Where the run goes on (None: it is finished, or failed partway).
    fn stopped_at(&mut self, at: Option<ResumeAt>) {
        self.stop = match (self.failure(), at.is_some()) {
            (Some(e), _) => RunStop::Failed { status: e.status },
            (None, true) => RunStop::Cancelled,
            (None, false) => RunStop::Finished,
        };
        self.resume_at = at.filter(|_| self.failure().is_none());
    }

    /// Why the buckled branch failed partway ([`RunStop::Failed`]).
    pub fn failure(&self) -> Option<&Error> {
        self.buckled.as_ref().and_then(|b| b.failure.as_ref())
    }

    /// Follow the path from `at` to its end or the callback's stop; the
    /// branches change only when a part of them is complete.
    fn go_on(&mut self, mut at: ResumeAt, progress: &mut dyn FnMut(&PointProgress) -> bool) -> Result<()> {
        let settings = &self.settings.clone();
        let torque = settings.control == EndControl::Torque;
        let phi = self.points.last().map_or(0.0, |p| p.phi);
        let (rod, charge) = (&self.rod.clone(), &self.charge.clone());
        let mut tell =
            Reporter { rod, turns: Turns { torque, phi }, index: self.points.len(), branch: 0, user: progress };
        if let ResumeAt::Straight { chunk, target, steps, anchor } = at {
            let from = Some((self.straight.clone(), chunk, target, steps, anchor));
            let (straight, stopped) = straight_path(rod, charge, self.scene.tension, settings, from, &mut tell)?;
            self.straight = straight;
            let buckles = !self.straight.bifurcations.is_empty();
            // Not stopped: on to the buckled branch (a phase boundary).
            let more = stopped.is_none() && buckles;
            self.stopped_at(if more { Some(ResumeAt::Buckling) } else { stopped });
            self.extend_points()?;
            if !more {
                return Ok(());
            }
            at = ResumeAt::Buckling;
        }
        let anchor = match at {
            ResumeAt::Buckled { anchor } => Some(anchor),
            _ => {
                let bif = self.straight.bifurcations.first().expect("a buckling point");
                let (_, m) = rod.spatial_force_moment(&bif.x, rod.elements);
                let phi = self.points.last().map_or(0.0, |p| p.phi);
                let phi_b = Turns { torque, phi }.follow(rod, &bif.x, bif.lambda);
                self.buckling = Some((phi_b, m[2]));
                None
            }
        };
        let phi = self.points.last().filter(|p| p.branch == 1).map_or(self.buckling.expect("buckling").0, |p| p.phi);
        (tell.turns.phi, tell.branch) = (phi, 1);
        let from = self.buckled.as_ref().zip(anchor);
        let kt = self.scene.kt();
        let (b, anchor, switched) =
            buckled_path(rod, charge, &self.straight, settings, Turns { torque, phi }, from, &mut tell, kt)?;
        if let Some(sw) = switched {
            self.charge.hard_core = Some(sw.stiffness);
            self.hard_core_switch = Some(sw);
        }
        match self.buckled.as_mut() {
            Some(prev) => prev.append(b),
            None => self.buckled = Some(b),
        }
        self.stopped_at(anchor.map(|anchor| ResumeAt::Buckled { anchor }));
        self.extend_points()
    }

    /// The path points of the branches' records not yet in `points`.
    fn extend_points(&mut self) -> Result<()> {
        let observing = std::time::Instant::now();
        let torque = self.rod.torqued();
        let ns = self.straight.records.len();
        if self.points.len() < ns {
            let mut turns = Turns { torque, phi: self.points.last().map_or(0.0, |p| p.phi) };
            let from = self.points.len();
            turns.path(&self.rod, &self.straight, 0, from, &mut self.points, &mut self.states)?;
        }
        if let Some(b) = &self.buckled {
            let from = self.points.len() - ns;
            let phi =
                if from == 0 { self.buckling.expect("buckling").0 } else { self.points.last().expect("a point").phi };
            let mut turns = Turns { torque, phi };
            turns.path(&self.rod, b, 1, from, &mut self.points, &mut self.states)?;
        }
        self.observables_seconds += observing.elapsed().as_secs_f64();
        Ok(())
    }
}

/// Tells the progress callback each point of a path as it converges.
struct Reporter<'a> {
    rod: &'a Rod,
    /// φ followed along the points told.
    turns: Turns,
    index: usize,
    branch: usize,
    user: &'a mut dyn FnMut(&PointProgress) -> bool,
}

impl Reporter<'_> {
    /// Tell the point of record `rec` (outputs: the state first): whether to go on.
    fn tell(&mut self, rec: &Record) -> bool {
        let rod = self.rod;
        let x = &rec.outputs[..rod.unknowns()];
        let phi = self.turns.follow(rod, x, rec.lambda);
        let (n, m) = rod.spatial_force_moment(x, rod.elements);
        let p = PointProgress {
            index: self.index,
            branch: self.branch,
            phi,
            turns: phi / (2.0 * std::f64::consts::PI),
            parameter: rec.lambda,
            extension: rod.tip(x)[2],
            torque: m[2],
            tension: n[2],
            residual: rec.residual,
            tip_rotation: rod.tip_rotation(x),
        };
        self.index += 1;
        (self.user)(&p)
    }
}

/// The end rotation φ along a path: Λ itself under rotation control, or a
/// torque clamp's angle read from each state and followed from the previous
/// point (steps turn the end by far less than 2π).
#[derive(Clone, Copy)]
struct Turns {
    torque: bool,
    /// φ of the last point.
    phi: f64,
}

impl Turns {
    fn follow(&mut self, rod: &Rod, x: &[f64], lambda: f64) -> f64 {
        self.phi = if self.torque {
            unwrap_rotation(self.phi, rod.end_rotation(x, lambda).expect("torque clamp"))
        } else {
            lambda
        };
        self.phi
    }

    /// The path points of `b`'s records from `from` on (the rod's unknowns
    /// of each state: a phase condition's μ dropped) into `points` and
    /// `states`.
    fn path(
        &mut self,
        rod: &Rod,
        b: &ChargedBranch,
        branch: usize,
        from: usize,
        points: &mut Vec<PathPoint>,
        states: &mut Vec<Vec<f64>>,
    ) -> Result<()> {
        let n = rod.unknowns();
        for (r, x) in b.records.iter().zip(&b.states).skip(from) {
            let phi = self.follow(rod, &x[..n], r.lambda);
            let observables = observables(rod, &x[..n], phi)?;
            points.push(PathPoint { phi, parameter: r.lambda, observables, branch, residual: r.residual });
            states.push(x[..n].to_vec());
        }
        Ok(())
    }
}

/// The straight branch from φ = 0 in chunks of a quarter of Greenhill's
/// estimate φ_G = 2√(K_b T) L / C until the first buckling point is
/// located (at most 3φ_G). Under torque control the targets are in M =
/// Cφ/L (the straight rod's torque: electrostatics exerts none on a
/// straight line).
/// `from`: a stopped straight branch and where it stopped (chunk, target,
/// steps taken in it, anchor: [`ResumeAt::Straight`]). Returns the branch
/// and, when `tell` stopped it before the path's end, where it goes on.
fn straight_path(
    rod: &Rod,
    charge: &RodCharge,
    tension: f64,
    settings: &SupercoilSettings,
    from: Option<(ChargedBranch, usize, f64, usize, Option<ListAnchor>)>,
    tell: &mut Reporter,
) -> Result<(ChargedBranch, Option<ResumeAt>)> {
    let kb = rod.law.bending();
    let c = rod.law.stiffness[(2, 2)];
    let phi_g = 2.0 * (kb * tension.max(kb / (rod.length * rod.length))).sqrt() * rod.length / c;
    let chunk = 0.25 * phi_g;
    // The straight clamped rod buckles at a sequence of double points,
    // M_n ≈ √(4K_bT + (2πnK_b/L)²) for the uncharged rod (the roots of the
    // linearised clamped problem, K_b w'''' − iM w''' − T w'' = 0 with w =
    // w' = 0 at both ends: 28.947, 29.686, 30.908 pN nm for the default
    // scene, the formula 28.944, 29.683, 30.904), crowded just above
    // Greenhill's 2√(K_bT): 0.1 turn apart at 1 kbp. A double point does
    // not change the sign of the determinant; only a dip of σ_min shows it,
    // and steps of 2 rad jumped over the first three (the scene reported
    // the fourth, 4.50 turns instead of 4.01 uncharged). So: large steps up
    // to 0.95 φ_1 of the uncharged rod (charge only stiffens the straight
    // rod: φ_1 is a lower bound), then steps of a quarter of φ_2 − φ_1
    // (in the scaled arc length, which is ≈ φ on the straight branch).
    let tension = tension.max(0.0);
    let m_n = |n: f64| (4.0 * kb * tension + (2.0 * std::f64::consts::PI * n * kb / rod.length).powi(2)).sqrt();
    let (phi_1, phi_2) = (m_n(1.0) * rod.length / c, m_n(2.0) * rod.length / c);
    let fine_step = (0.25 * (phi_2 - phi_1)).clamp(1e-3, 2.0);
    // The parameter per radian on the straight branch. The steps stay in
    // scaled arc length, dominated there by the state's rotation (≈ φ)
    // under either control (M's own scale, a moment, is ~30× Cφ/L).
    let per_phi = if settings.control == EndControl::Torque { rod.torque_per_radian() } else { 1.0 };
    // The buckling point to 1e-7 in scaled arc length (φ to ~1e-7 rad):
    // golden section on a double point costs ~4 factorisations per
    // reduction, and 1e-10 would take twice the reductions for digits the
    // curves do not show.
    let mut opts = Options {
        residual_tol: settings.residual_tol,
        initial_step: 2.0,
        max_step: 2.0,
        detect_bifurcations: true,
        bifurcation_tol: 1e-7,
        max_steps: settings.max_steps,
        // The buckled branch leaves at the first point: the crowded double
        // points beyond it cost 5 of the 6 locations (benches/README.md).
        stop_at_bifurcation: true,
        lu_kind: settings.lu_kind,
        stability: settings.stability,
        // The shipped end-loop table's paths (Options::lean_monitor).
        lean_monitor: false,
        ..Default::default()
    };
    let (mut straight, mut index, mut target, mut steps, mut anchor) = match from {
        Some((b, index, target, steps, anchor)) => (Some(b), index, target, steps, anchor),
        None => (None, 0, 0.95 * phi_1, 0, None),
    };
    if index > 0 {
        opts.max_step = fine_step;
        opts.initial_step = fine_step;
    }
    let mut stopped = false;
    while target <= 3.0 * phi_g + 0.5 * chunk {
        opts.target_lambda = Some(per_phi * target);
        // The chunk's steps: a resumed chunk has taken `steps` of them.
        opts.max_steps = settings.max_steps - steps;
        let start = match &straight {
            None => Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true },
            Some(prev) => Start::Resume(prev.resume.clone()),
        };
        // A chunk continuing the branch starts at its last point, told.
        let mut first = straight.is_some();
        let told = |r: &Record| {
            if std::mem::take(&mut first) {
                return true;
            }
            let go = tell.tell(r);
            stopped |= !go;
            go
        };
        let (mut next, list) = follow_on(rod, charge, start, anchor.take().as_ref(), None, &opts, told, None)?;
        // Before the buckling point the run has no path worth keeping.
        if let Some(e) = next.failure.take() {
            return Err(e);
        }
        steps += next.records.len() - 1;
        let mut b = match straight.take() {
            Some(mut prev) => {
                prev.append(next);
                prev
            }
            None => next,
        };
        if stopped && b.stop == Stop::Cancelled && steps >= settings.max_steps {
            // Stopped at the chunk's last step: the uninterrupted chunk ends there.
            b.stop = Stop::MaxSteps;
        }
        let (found, stop) = (!b.bifurcations.is_empty(), b.stop);
        if stopped && stop == Stop::Cancelled && b.contact.is_none() {
            return Ok((b, Some(ResumeAt::Straight { chunk: index, target, steps, anchor: Some(list) })));
        }
        if found || stop != Stop::Target {
            return Ok((b, (stopped && found).then_some(ResumeAt::Buckling)));
        }
        straight = Some(b);
        target += chunk;
        index += 1;
        steps = 0;
        opts.max_step = fine_step;
        opts.initial_step = fine_step;
        if stopped {
            let at = ResumeAt::Straight { chunk: index, target, steps, anchor: None };
            return Ok((straight.expect("a chunk"), Some(at)));
        }
    }
    Ok((straight.expect("at least one chunk"), None))
}

/// The buckled branch from the straight one's first buckling point (phase
/// condition, first step 0.02) until `max_turns`, the step limit or a
/// strand crossing; `turns` holds φ at the buckling point. Rotation control
/// stops at the λ range; a torque clamp's turns are checked on each point
/// (its M has no such bound: the torque falls after buckling, then stays on
/// the plateau).
///
/// `from`: a stopped buckled branch and its last pair list's anchor; it is
/// resumed from its last point with its tangent and step (the
/// uninterrupted branch's own, not recomputed) and its continuation
/// returned (to append). Returns the branch and, when `tell` stopped it
/// before its end, its last pair list's anchor.
// The path's pieces, as the run holds them (no struct would group them).
#[allow(clippy::too_many_arguments)]
fn buckled_path(
    rod: &Rod,
    charge: &RodCharge,
    straight: &ChargedBranch,
    settings: &SupercoilSettings,
    mut turns: Turns,
    from: Option<(&ChargedBranch, ListAnchor)>,
    tell: &mut Reporter,
    kt: f64,
) -> Result<(ChargedBranch, Option<ListAnchor>, Option<HardCoreSwitch>)> {
    let max_phi = 2.0 * std::f64::consts::PI * settings.max_turns;
    let opts = Options {
        residual_tol: settings.residual_tol,
        initial_step: 0.3,
        max_step: 2.0,
        max_steps: settings.max_steps,
        lambda_range: if turns.torque { (0.0, f64::MAX) } else { (0.0, max_phi) },
        hermite_predictor: settings.engine == Engine::Hermite,
        corrector_aim: if settings.engine == Engine::Hermite { settings.corrector_aim } else { 3.0 },
        lu_kind: settings.lu_kind,
        // The same numbers on any thread count (c-api.md): the choice is
        // the rod's size, and one thread takes the records' signs as two
        // do, after each point.
        overlap_records: rod.unknowns() >= settings.separate_signs_from,
        overlap_thread: settings.threads >= 2,
        unfolding_retakes: settings.unfolding_retakes,
        unfolding_moment: Some(0.1 * settings.tolerance * 2.0 * std::f64::consts::PI * rod.torque_per_radian()),
        stability: settings.stability,
        lean_monitor: false,
        ..Default::default()
    };
    let n = rod.unknowns();
    // The buckled branch's engine (the straight one takes Newton steps).
    let anm = RodCharge { anm: (settings.engine == Engine::Anm).then_some(settings.anm), ..charge.clone() };
    let charge = &anm;
    let mut stopped = false;
    // A resumed branch's first record is the point it stopped at, told.
    let mut first = from.is_some();
    let mut check = |rec: &Record| {
        if std::mem::take(&mut first) {
            return true;
        }
        let phi = turns.follow(rod, &rec.outputs[..n], rec.lambda);
        let within = !turns.torque || (phi > 0.0 && phi < max_phi);
        let go = tell.tell(rec);
        stopped = within && !go;
        within && go
    };
    let done = from.as_ref().map_or(0, |(prev, _)| prev.records.len() - 1);
    let (mut b, mut anchor) = match from {
        None => switch(rod, charge, straight, 0, 0, 0.02, &opts, &mut check)?,
        Some((prev, anchor)) => {
            let opts = Options { max_steps: settings.max_steps - done, ..opts.clone() };
            // With the point before it (the Hermite predictor's history) the
            // engine's resume re-factorises as the uninterrupted run had
            // (bordered by that point's tangent): the same tangent, steps
            // and chord iterations. Without it, the stored tangent as is.
            let start = match prev.resume.previous {
                Some(_) => Start::Resume(prev.resume.clone()),
                None => Start::Switch(prev.resume.clone()),
            };
            // μ stays at zero: checked at each point as it comes (a point
            // that leaves it is taken again shorter, or ends the branch).
            follow_on(rod, charge, start, Some(&anchor), prev.phase, &opts, &mut check, None)?
        }
    };
    // The strands met: the scene needs the hard core (the optimal
    // superhelix is tighter than 2a). Switched on from the last point
    // where it exerts nothing (no pair within its range: that point is an
    // equilibrium with it too), the branch goes on; the points after it,
    // told already, are dropped, and it is told again.
    let mut switched = None;
    if let (Some(c), true) = (b.contact, settings.hard_core_auto && charge.hard_core.is_none()) {
        let k = (0..c.record).rev().find(|&k| hard_core_idle(rod, charge, &b.states[k])).unwrap_or(0);
        let stiffness = auto_hard_core(charge.screening.a, kt);
        let with_core = RodCharge { hard_core: Some(stiffness), ..charge.clone() };
        let parameter = b.records[k].lambda;
        let opts = Options { max_steps: settings.max_steps - done, ..opts.clone() };
        (b, anchor) = continue_with(rod, &with_core, b, k, &opts, &mut check)?;
        switched = Some(HardCoreSwitch { record: done + k, parameter, stiffness });
    }
    let steps = done + b.records.len() - 1;
    if stopped && b.stop == Stop::Cancelled && b.contact.is_none() && steps >= settings.max_steps {
        // Stopped at the last step: the uninterrupted branch ends there.
        b.stop = Stop::MaxSteps;
    }
    let go_on = stopped && b.stop == Stop::Cancelled && b.contact.is_none() && b.failure.is_none();
    Ok((b, go_on.then_some(anchor), switched))
}

/// The hard core a scene switches on by itself: P = k_hc (2.5a − d)³ with
/// k_hc = 4 k_BT / a⁵ (16.5 pN/nm⁴ at a = 1 nm). At d = 2a it pushes with
/// 3k_hc(a/2)² = 3 k_BT/a² per length² — the order of the contact force
/// density τ/R² ≈ 10 pN nm / (1 nm)² that a plectoneme's torque exerts on
/// its strands — so the axes stay near 2a instead of passing through each
/// other, and the pair stays a smooth (C²) part of the energy.
pub fn auto_hard_core(a: f64, kt: f64) -> f64 {
    4.0 * kt / a.powi(5)
}

/// Where a scene switched its hard core on by itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HardCoreSwitch {
    /// The buckled branch's record from which the hard core acts: the last
    /// point before the strands crossed where no pair was within its range
    /// (an equilibrium with and without it).
    pub record: usize,
    /// Its continuation parameter (φ, or M under a torque clamp).
    pub parameter: f64,
    /// k_hc (pN/nm⁴).
    pub stiffness: f64,
}

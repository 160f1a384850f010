//! The DNA supercoiling scene (physics.md §3, issue 5): a Kirchhoff rod in
//! nm and pN, clamped at both ends, pulled and turned (or torqued), with the
//! effective line charge of DNA screened by salt; its path — the straight
//! rod to its first buckling point, then the buckled branch towards a
//! plectoneme — and the observables users compare with magnetic-tweezers
//! experiments ([`Observables`]).

use super::branch::{follow, switch, ChargedBranch};
use super::rod::RodCharge;
use crate::continuation::newton::Start;
use crate::continuation::{Options, Stop};
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
/// tests/writhe.rs `measure_dna_states`, benches/README.md 2026-11-25):
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

/// A DNA supercoiling scene in nm and pN (physics.md §3, issue 5): a
/// Kirchhoff rod clamped at both ends, pulled by `tension` and turned by
/// the end rotation, carrying the effective line charge of DNA screened by
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

/// How the supercoiling path of a [`DnaScene`] is computed.
#[derive(Clone, Debug, PartialEq)]
pub struct SupercoilSettings {
    pub elements: usize,
    pub stages: usize,
    /// Relative energy tolerance of the screening cutoff (None: every pair).
    pub cutoff_tolerance: Option<f64>,
    /// Hard-core stiffness (pN/nm⁴), None: none.
    pub hard_core: Option<f64>,
    pub threads: usize,
    /// The buckled branch stops past this many turns (or when turns fall
    /// to zero), at the step limit, or at a strand crossing.
    pub max_turns: f64,
    pub max_steps: usize,
    pub residual_tol: f64,
    /// The discrete base-pair model (charges at the scene's rise, the
    /// thesis's comparison; [`RodCharge::base_pairs`]) instead of the
    /// continuum line charge.
    pub base_pairs: bool,
    /// End rotation (default) or end torque as the continuation parameter.
    pub control: EndControl,
}

impl Default for SupercoilSettings {
    /// 170 elements of Gauss(2) (2 nm for 1 kbp), cutoff 1e-4, no hard
    /// core, 1 thread, to 12 turns in at most 600 steps, scaled residual
    /// 1e-8 (forces to ~1e-8 of λ² ≈ 6 pN: Newton then converges in 2
    /// iterations and the step grows; at 1e-10 it always takes 3 and the
    /// step stays where it started: on 1 kbp at 0.1 M, 150 steps reach the
    /// fold at 3.46 turns, extension 172 nm, at 1e-8).
    fn default() -> Self {
        SupercoilSettings {
            elements: 170,
            stages: 2,
            cutoff_tolerance: Some(1e-4),
            hard_core: None,
            threads: 1,
            max_turns: 12.0,
            max_steps: 600,
            residual_tol: 1e-8,
            base_pairs: false,
            control: EndControl::Rotation,
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
    let start = std::time::Instant::now();
    let rod = scene.rod_controlled(settings.elements, settings.stages, settings.control)?;
    let mut charge = scene.charge();
    charge.cutoff_tolerance = settings.cutoff_tolerance;
    charge.hard_core = settings.hard_core;
    charge.threads = settings.threads;
    charge.base_pairs = settings.base_pairs.then_some(scene.rise);
    error::positive("max_turns", settings.max_turns)?;
    error::count_in_range("max_steps", settings.max_steps as i64, 1, 1 << 24)?;
    error::positive("residual_tol", settings.residual_tol)?;
    let straight = straight_path(&rod, &charge, scene.tension, settings)?;
    let mut turns = Turns { torque: settings.control == EndControl::Torque, phi: 0.0 };
    let (mut points, mut states) = (Vec::new(), Vec::new());
    let observing = std::time::Instant::now();
    turns.path(&rod, &straight, 0, &mut points, &mut states)?;
    let mut observables_seconds = observing.elapsed().as_secs_f64();
    let mut buckling = None;
    let mut buckled = None;
    if let Some(bif) = straight.bifurcations.first() {
        let (_, m) = rod.spatial_force_moment(&bif.x, rod.elements);
        let phi_b = turns.follow(&rod, &bif.x, bif.lambda);
        buckling = Some((phi_b, m[2]));
        let b = buckled_path(&rod, &charge, &straight, settings, turns)?;
        turns.phi = phi_b;
        let observing = std::time::Instant::now();
        turns.path(&rod, &b, 1, &mut points, &mut states)?;
        observables_seconds += observing.elapsed().as_secs_f64();
        buckled = Some(b);
    }
    Ok(SupercoilRun {
        scene: scene.clone(),
        rod,
        charge,
        points,
        states,
        buckling,
        straight,
        buckled,
        seconds: start.elapsed().as_secs_f64(),
        observables_seconds,
    })
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

    /// The path points of `b` (the rod's unknowns of each state: a phase
    /// condition's μ dropped) into `points` and `states`.
    fn path(
        &mut self,
        rod: &Rod,
        b: &ChargedBranch,
        branch: usize,
        points: &mut Vec<PathPoint>,
        states: &mut Vec<Vec<f64>>,
    ) -> Result<()> {
        let n = rod.unknowns();
        for (r, x) in b.records.iter().zip(&b.states) {
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
fn straight_path(rod: &Rod, charge: &RodCharge, tension: f64, settings: &SupercoilSettings) -> Result<ChargedBranch> {
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
        ..Default::default()
    };
    let mut straight: Option<ChargedBranch> = None;
    let mut target = 0.95 * phi_1;
    while target <= 3.0 * phi_g + 0.5 * chunk {
        opts.target_lambda = Some(per_phi * target);
        let start = match &straight {
            None => Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true },
            Some(prev) => Start::Resume(prev.resume.clone()),
        };
        let next = follow(rod, charge, start, None, &opts, |_| true)?;
        let b = match straight.take() {
            Some(mut prev) => {
                prev.append(next);
                prev
            }
            None => next,
        };
        let (found, stop) = (!b.bifurcations.is_empty(), b.stop);
        straight = Some(b);
        if found || stop != Stop::Target {
            break;
        }
        target += chunk;
        opts.max_step = fine_step;
        opts.initial_step = fine_step;
    }
    Ok(straight.expect("at least one chunk"))
}

/// The buckled branch from the straight one's first buckling point (phase
/// condition, first step 0.02) until `max_turns`, the step limit or a
/// strand crossing; `turns` holds φ at the buckling point. Rotation control
/// stops at the λ range; a torque clamp's turns are checked on each point
/// (its M has no such bound: the torque falls after buckling, then stays on
/// the plateau).
fn buckled_path(
    rod: &Rod,
    charge: &RodCharge,
    straight: &ChargedBranch,
    settings: &SupercoilSettings,
    mut turns: Turns,
) -> Result<ChargedBranch> {
    let max_phi = 2.0 * std::f64::consts::PI * settings.max_turns;
    let opts = Options {
        residual_tol: settings.residual_tol,
        initial_step: 0.3,
        max_step: 2.0,
        max_steps: settings.max_steps,
        lambda_range: if turns.torque { (0.0, f64::MAX) } else { (0.0, max_phi) },
        ..Default::default()
    };
    let n = rod.unknowns();
    switch(rod, charge, straight, 0, 0, 0.02, &opts, |rec| {
        let phi = turns.follow(rod, &rec.outputs[..n], rec.lambda);
        !turns.torque || (phi > 0.0 && phi < max_phi)
    })
}

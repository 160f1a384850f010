//! Supercoiling at finite temperature: the thermal two-phase model of a DNA
//! molecule in magnetic or angular-optical tweezers (doc/physics.md §3.7).
//!
//! A molecule of contour length L, pulled by a force F and turned by n
//! turns (its excess linking number), is shared between
//! * the **extended phase** ([`wlc`]): a stretched, twisted worm-like chain
//!   of grand free energy per length h_s(τ) = −g_e(F) − τ²/(2C_e) at end
//!   torque τ (g_e the WLC's force free energy, C_e the twist modulus
//!   softened by bending fluctuations and by the twist–stretch coupling);
//! * the **plectonemic phase** ([`superhelix`]): a superhelix of radius R
//!   and angle α minimising bending + electrostatics (rodkit's continuum
//!   Debye–Hückel energy on the superhelix) + entropic confinement −
//!   2πτ × writhe, h_p(τ) = min φ − τ²/(2K_t);
//! * **end loops**: each of the m plectonemes costs a nucleation grand free
//!   energy E_nuc(τ), taken from the zero-temperature full charged rod
//!   (an [`EndLoopSource`]) with its torque dependence from the elastic
//!   loop.
//!
//! A state is (m, ℓ_p): m plectonemes of total length ℓ_p. At linking n its
//! torque τ solves the linking balance
//!
//!   n = L_s τ/(2πC_e) + ℓ_p [w(τ) + τ/(2πK_t)] + m Lk_loop(τ),  L_s = L − ℓ_p,   (1)
//!
//! and its free energy is F = L_s h_s(τ) + ℓ_p h_p(τ) + m E_nuc(τ) + 2πτn.
//! The partition function at fixed n sums over m and integrates over ℓ_p,
//!
//!   Z(n) = e^{−F₀/kT} + Σ_{m≥1} ∫ dℓ_p/b (L_s/b)^m/m! (ℓ_p/b)^{m−1}/(m−1)! e^{−F/kT},   (2)
//!
//! the combinatorial factors counting the places of m plectonemes along the
//! extended chain and the ways to share ℓ_p among them, on the counting
//! length b (J. F. Marko, Phys. Rev. E 76, 021926 (2007); M. Emanuel, G.
//! Lanzani & H. Schiessel, Phys. Rev. E 88, 022706 (2013)). Thermal
//! averages of extension, torque, twist, writhe, plectoneme length and
//! number follow; the probability of m ≥ 1 is the buckled state's
//! population (the two-state hopping at buckling). At kT = 0 the sum is its
//! smallest term: the zero-temperature two-phase model with the full rod's
//! end loop, which is what rodkit's full rod computes.

pub mod charge;
pub mod cheb;
pub mod loop_fluct;
pub mod superhelix;
pub mod wlc;

use crate::error::{Error, Result};
use crate::status::Status;
use std::f64::consts::PI;
use superhelix::{Optimum, Plectoneme};

/// The 298.15 K water of the full rod's DNA scene
/// ([`crate::charged::dna::DnaScene`], whose constants these are): the
/// screening and the charges' pair energy stay those of room temperature
/// when the model's kT is varied (kT = 0 is a limit of the thermal terms,
/// as the zero-temperature rod keeps its screening).
fn room_water(salt: f64, permittivity: f64) -> crate::charged::dna::DnaScene {
    crate::charged::dna::DnaScene { salt, permittivity, temperature: 298.15, ..Default::default() }
}

/// k_BT at 298.15 K (pN nm).
pub fn kt_room() -> f64 {
    room_water(0.1, 78.4).kt()
}

/// e²/(4πε₀ε_r) in pN nm² (= k_BT·l_B at 298.15 K; 2.94 at ε_r = 78.4):
/// the pair energy of two elementary charges times their distance.
pub fn coulomb_constant(permittivity: f64) -> f64 {
    let w = room_water(0.1, permittivity);
    w.kt() * w.bjerrum_length()
}

/// κ_D (1/nm) of a 1:1 salt of molar concentration `salt` at 298.15 K and
/// permittivity ε_r: κ_D² = 8π l_B n ([`crate::charged::dna::DnaScene::kappa`]).
pub fn inverse_debye_length(salt: f64, permittivity: f64) -> f64 {
    room_water(salt, permittivity).kappa()
}

/// Where a plectoneme's nucleation energy comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum EndLoopSource {
    /// The built-in table ([`builtin_end_loops`]) where it covers the
    /// scene's force and salt; elsewhere the elastic loop, and the model
    /// says so ([`Model::end_loop_used`], [`Model::end_loop_note`]).
    Auto,
    /// Compute the scene's own entry with the full zero-temperature charged
    /// rod (`charged::end_loop::end_loop_entry` on the table's scene for
    /// this force and salt): minutes, on request only.
    Compute,
    /// Interpolated in a table computed by rodkit's full zero-temperature
    /// charged rod over force × salt: entries (force pN, salt M, the rod's
    /// plateau torque τ₀ pN nm, E_nuc(τ₀) pN nm).
    Table(Vec<EndLoopEntry>),
    /// The elastic (uncharged Kirchhoff) loop alone: E_nuc = ΔG_loop(τ).
    Elastic,
    /// A given E_nuc at torque τ₀ (the elastic loop's torque dependence).
    Value { torque: f64, energy: f64 },
}

/// Which end loop a model uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndLoopUsed {
    /// Interpolated in a table (the built-in one or the caller's).
    Table,
    /// The elastic loop alone.
    Elastic,
    /// The caller's value.
    Value,
    /// Computed for this scene by the full rod.
    Computed,
}

/// The end-loop table rodkit ships (src/charged/end_loops.csv, computed by
/// the full zero-temperature charged rod; its header says how to
/// regenerate it), as (force, salt, plateau torque τ₀, E_nuc(τ₀)).
pub fn builtin_end_loops() -> Vec<EndLoopEntry> {
    static TABLE: std::sync::OnceLock<Vec<EndLoopEntry>> = std::sync::OnceLock::new();
    TABLE
        .get_or_init(|| {
            // The shipped file parses (tests/charged_end_loop.rs); were it
            // not to, the table would be empty and Auto would say so.
            crate::charged::end_loop::parse_table(include_str!("../charged/end_loops.csv"))
                .unwrap_or_default()
                .iter()
                .map(|e| EndLoopEntry { force: e.force, salt: e.salt, torque: e.tau_plateau, energy: e.e_nuc })
                .collect()
        })
        .clone()
}

/// One entry of the end-loop table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndLoopEntry {
    pub force: f64,
    pub salt: f64,
    pub torque: f64,
    pub energy: f64,
}

/// The scene: molecule, conditions, material, model options.
#[derive(Clone, Debug, PartialEq)]
pub struct TweezersScene {
    /// Length in base pairs and rise per base pair (nm).
    pub base_pairs: f64,
    pub rise: f64,
    /// Pulling force (pN) and monovalent salt (mol/L, > 0).
    pub force: f64,
    pub salt: f64,
    /// Thermal energy kT (pN nm): 4.11 at 25 °C; 0 = the zero-temperature limit.
    pub kt: f64,
    /// Bending and twist moduli K_b = A kT, K_t = C kT (pN nm²).
    pub bending: f64,
    pub twist: f64,
    /// Effective line charge ν (e/nm); 0: the Poisson–Boltzmann effective
    /// charge of a 1 nm cylinder carrying 2 e per 0.34 nm at the scene's
    /// salt ([`charge::effective_charge`], 5.6 e/nm at 0.1 M, 2.4 at
    /// 0.01 M). And the relative permittivity.
    pub charge_per_length: f64,
    pub permittivity: f64,
    /// DNA radius a (nm): the electrostatics' arc-length cutoff and the
    /// strands' contact distance 2a.
    pub radius: f64,
    /// Stretch modulus S (pN; 0: inextensible) and twist–stretch coupling
    /// g (pN nm; needs S).
    pub stretch_modulus: f64,
    pub twist_stretch: f64,
    /// Confinement coefficient of the plectoneme's strands (0: off).
    pub confinement: f64,
    /// Hard core between the strands (pN/nm⁴; 0: none). Default: the full
    /// rod's 4 k_BT/a⁵ at 298.15 K ([`crate::charged::dna::auto_hard_core`]),
    /// kept fixed when `kt` varies, as the zero-temperature rod keeps it.
    pub hard_core: f64,
    /// Counting length b of (2) (nm); 0: √(K_b/F), the tensioned chain's
    /// correlation length, which is also the end loop's size.
    pub counting_length: f64,
    /// The largest number of plectonemes summed in (2) (1–64). The sum
    /// stops earlier by itself once more plectonemes only lower it; a
    /// point whose states at this cap still carry more than 1e-6 of the
    /// partition function is flagged out of range (the sum is truncated).
    pub max_plectonemes: usize,
    /// 0: the superhelix of [`superhelix`]. P > 0 (nm): J. F. Marko's
    /// phenomenological plectoneme instead, free energy ½ kT P (2π l)² per
    /// length at linking density l (Phys. Rev. E 76, 021926 (2007)): a
    /// reference with closed-form limits (doc/physics.md §3.7.5), no
    /// superhelix geometry (radius and angle reported as 0).
    pub marko_plectoneme: f64,
    pub end_loop: EndLoopSource,
}

impl Default for TweezersScene {
    /// 1 kbp at 1 pN in 0.1 M, kT 4.11 pN nm, A = 50 nm, C = 100 nm, the
    /// Poisson–Boltzmann effective charge, a = 1 nm, inextensible, the
    /// built-in end-loop table where it covers the scene (else the elastic
    /// loop, said so).
    fn default() -> Self {
        let kt = 4.11;
        TweezersScene {
            base_pairs: 1000.0,
            rise: 0.34,
            force: 1.0,
            salt: 0.1,
            kt,
            bending: 50.0 * kt,
            twist: 100.0 * kt,
            charge_per_length: 0.0,
            permittivity: 78.4,
            radius: 1.0,
            stretch_modulus: 0.0,
            twist_stretch: 0.0,
            confinement: superhelix::CONFINEMENT,
            hard_core: crate::charged::dna::auto_hard_core(1.0, kt_room()),
            counting_length: 0.0,
            max_plectonemes: MAX_PLECTONEMES,
            marko_plectoneme: 0.0,
            end_loop: EndLoopSource::Auto,
        }
    }
}

/// The elastic end loop: a localised loop of a Kirchhoff rod of bending
/// modulus K_b under tension F and twisting moment τ has, relative to the
/// straight rod at the same torque, the grand energy
/// ΔG = 8√(K_b F)√(1 − m²) − 4τ arccos m, m = τ/(2√(K_b F)), linking
/// Lk = −ΔG'(τ)/2π = (2/π) arccos m and extension deficit ∂ΔG/∂F =
/// 4√(K_b/F)√(1 − m²) (J. M. T. Thompson & A. R. Champneys, Proc. R. Soc.
/// A 452, 117 (1996); G. H. M. van der Heijden & J. M. T. Thompson,
/// Nonlinear Dyn. 21, 71 (2000)). Returns (ΔG, Lk, deficit); m ≥ 1 gives
/// (0, 0, 0) (the loop has shrunk to nothing at the straight rod's own
/// instability).
pub fn elastic_loop(kb: f64, force: f64, tau: f64) -> (f64, f64, f64) {
    let s = (kb * force).sqrt();
    let m = tau / (2.0 * s);
    if m >= 1.0 {
        return (0.0, 0.0, 0.0);
    }
    let m = m.max(-1.0);
    let root = (1.0 - m * m).sqrt();
    (8.0 * s * root - 4.0 * tau * m.acos(), 2.0 / PI * m.acos(), 4.0 * (kb / force).sqrt() * root)
}

/// The extended phase's constants at the scene's force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extended {
    /// g_e = g_WLC(F) + F²/2S (pN) and the relative extension at zero
    /// twist ζ + F/S.
    pub g: f64,
    pub zeta: f64,
    /// The twist modulus C_e = C_s − g²/S (pN nm²), the Moroz–Nelson C_s
    /// and dC_s/dF.
    pub twist: f64,
    pub softened: f64,
    pub softened_slope: f64,
}

/// A scene made ready: the phases' free energies as functions of torque.
#[derive(Clone, Debug)]
pub struct Model {
    pub scene: TweezersScene,
    /// The line charge used (e/nm): the scene's, or the Poisson–Boltzmann one.
    pub charge: f64,
    /// Contour length (nm).
    pub length: f64,
    pub extended: Extended,
    pub plectoneme: Plectoneme,
    /// The infinite molecule's coexistence torque τ* (h_s = h_p) and the
    /// superhelix there.
    pub coexistence: Optimum,
    /// |h_p(τ*)| of the tables minus its direct value (pN): the tables'
    /// interpolation error where it matters most.
    pub table_error: f64,
    /// The torque range tabulated for the plectoneme.
    pub torque_range: (f64, f64),
    hp: cheb::Series,
    w: cheb::Series,
    radius: cheb::Series,
    angle: cheb::Series,
    /// E_nuc(τ) = offset + ΔG_loop(τ) and the offset's dE/dF part of the
    /// loop's extension deficit.
    loop_offset: f64,
    loop_offset_slope: f64,
    counting: f64,
    /// The end loop's fluctuation factor ln g(m) (loop_fluct.rs (3)); None
    /// at kT = 0 or with a caller's counting length (whose plain
    /// combinatorial weights then stand alone, as in the references of (2)).
    loop_table: Option<&'static loop_fluct::LnG>,
    /// kT ln Φ(τ*) and kT ∂ln Φ/∂F there (pN nm, nm): the loop's thermal
    /// correction to its free energy and deficit (zero without a table).
    loop_shift: (f64, f64),
    /// The buckling turns, found once.
    buckling: std::sync::OnceLock<f64>,
    /// h_p, w and w' on Hermite grids for the partition sums.
    fast: Fast,
    end_loop_used: EndLoopUsed,
    end_loop_note: Option<String>,
}

/// The tables the partition sums read at every state, as Hermite grids of
/// 1024 intervals (their error against the series is below 1e-12 of the
/// values: h ≈ 0.03 pN nm).
#[derive(Clone, Debug)]
struct Fast {
    hp: cheb::Grid,
    w: cheb::Grid,
    dw: cheb::Grid,
}

/// The default and largest cap on the number of plectonemes: long
/// molecules at low salt or low force, where a loop costs a few kT, form
/// tens of them (the multiplectoneme phase); each loop needs ≥ 4ξ₀ of tail.
pub const MAX_PLECTONEMES: usize = 64;

/// Chebyshev degree of the plectoneme's tables in torque.
const DEGREE: usize = 32;

impl Model {
    /// Validate the scene and tabulate its phases.
    pub fn new(scene: &TweezersScene) -> Result<Self> {
        validate(scene)?;
        let s = scene;
        let length = s.base_pairs * s.rise;
        let fe = wlc::force_extension(s.bending, s.kt, s.force)?;
        let cs = wlc::moroz_nelson(s.twist, s.bending, s.kt, s.force)?;
        let (g_stretch, z_stretch, ts) = if s.stretch_modulus > 0.0 {
            (
                s.force * s.force / (2.0 * s.stretch_modulus),
                s.force / s.stretch_modulus,
                s.twist_stretch * s.twist_stretch / s.stretch_modulus,
            )
        } else {
            (0.0, 0.0, 0.0)
        };
        let extended = Extended {
            g: fe.g + g_stretch,
            zeta: fe.zeta + z_stretch,
            twist: cs - ts,
            softened: cs,
            softened_slope: wlc::moroz_nelson_slope(s.twist, s.bending, s.kt, s.force),
        };
        if !(extended.twist > 0.0) {
            return Err(Error::new(Status::ErrOutOfRange, "twist–stretch coupling g²/S exceeds the twist modulus"));
        }
        let kappa = inverse_debye_length(s.salt, s.permittivity);
        let nu = if s.charge_per_length > 0.0 {
            s.charge_per_length
        } else {
            let lb = room_water(s.salt, s.permittivity).bjerrum_length();
            charge::effective_charge(2.0 / 0.34, 1.0, kappa, lb)?
        };
        let plectoneme = Plectoneme {
            bending: s.bending,
            twist: s.twist,
            kt: s.kt,
            charge2: coulomb_constant(s.permittivity) * nu * nu,
            kappa,
            radius: s.radius,
            confinement: s.confinement,
            hard_core: s.hard_core,
        };
        let hs = |tau: f64| -extended.g - tau * tau / (2.0 * extended.twist);
        // The torque range: up to τ_cap = 2√(K_b F), the infinite straight
        // rod's instability (no end loop exists beyond it); down to where the
        // superhelix still has a minimum at a finite radius (below, φ → 0⁺
        // as R → ∞: no plectoneme), found going down from τ_cap/2 by
        // factors of 0.85 until R exceeds half the largest radius searched.
        let tau_cap = 2.0 * (s.bending * s.force).sqrt();
        let marko = s.marko_plectoneme;
        let (t_lo, vals, _nodes) = if marko > 0.0 {
            // h_p = −τ²/(2kTP) and linking per length τ/(2π kT P), i.e.
            // w = τ/(2π) (1/(kT P) − 1/K_t): quadratic and linear in τ, so
            // the tables are exact.
            let t_lo = 0.02 * tau_cap;
            let nodes = cheb::points(DEGREE, t_lo, tau_cap);
            let vals: Vec<[f64; 4]> = nodes
                .iter()
                .map(|&t| {
                    [-t * t / (2.0 * s.kt * marko), t / (2.0 * PI) * (1.0 / (s.kt * marko) - 1.0 / s.twist), 0.0, 0.0]
                })
                .collect();
            (t_lo, vals, nodes)
        } else {
            superhelix_tables(&plectoneme, tau_cap)?
        };
        let t_hi = tau_cap;
        let col = |i: usize| -> Vec<f64> { vals.iter().map(|v| v[i]).collect() };
        let hp = cheb::Series::interpolate(t_lo, t_hi, &col(0));
        let w = cheb::Series::interpolate(t_lo, t_hi, &col(1));
        let dw = w.derivative();
        let radius = cheb::Series::interpolate(t_lo, t_hi, &col(2));
        let angle = cheb::Series::interpolate(t_lo, t_hi, &col(3));
        // τ*: h_p − h_s decreases with τ (its derivative is −2π × the
        // plectoneme's extra linking per length): bisection on the tables,
        // then the superhelix there computed directly.
        let gap = |t: f64| hp.eval(t) - hs(t);
        if gap(t_hi) >= 0.0 {
            return Err(Error::new(
                Status::ErrNotConverged,
                format!(
                    "the plectoneme does not coexist with the extended chain below its instability torque {t_hi:.2} pN nm \
                     (force {} pN, salt {} M)",
                    s.force, s.salt
                ),
            ));
        }
        if gap(t_lo) <= 0.0 {
            return Err(Error::new(Status::ErrNotConverged, "the plectoneme is favoured at every torque of its range"));
        }
        let (mut a, mut b) = (t_lo, t_hi);
        for _ in 0..60 {
            let c = 0.5 * (a + b);
            if gap(c) > 0.0 {
                a = c;
            } else {
                b = c;
            }
        }
        let t_star = 0.5 * (a + b);
        let (star, table_error) = if marko > 0.0 {
            let o = Optimum {
                torque: t_star,
                radius: 0.0,
                angle: 0.0,
                phi: hp.eval(t_star) + t_star * t_star / (2.0 * s.twist),
                writhe: w.eval(t_star),
                bending: 0.0,
                electrostatic: 0.0,
                confinement: 0.0,
            };
            (o, 0.0)
        } else {
            let o = plectoneme.optimum(t_star, Some((radius.eval(a), angle.eval(a))))?;
            let e = (hp.eval(o.torque) - plectoneme.grand(&o)).abs();
            (o, e)
        };
        let fast = Fast {
            hp: cheb::Grid::new(&hp, &hp.derivative(), 1024),
            w: cheb::Grid::new(&w, &dw, 1024),
            dw: cheb::Grid::new(&dw, &dw.derivative(), 1024),
        };
        let (loop_offset, loop_offset_slope, end_loop_used, end_loop_note) = loop_offset(s)?;
        let counting = if s.counting_length > 0.0 { s.counting_length } else { (s.bending / s.force).sqrt() };
        let loop_table = if s.counting_length > 0.0 || s.kt == 0.0 { None } else { Some(loop_fluct::LnG::shipped()?) };
        let mut model = Model {
            charge: nu,
            scene: s.clone(),
            length,
            extended,
            plectoneme,
            coexistence: star,
            table_error,
            torque_range: (t_lo, t_hi),
            hp,
            w,
            radius,
            angle,
            loop_offset,
            loop_offset_slope,
            counting,
            loop_table,
            loop_shift: (0.0, 0.0),
            buckling: std::sync::OnceLock::new(),
            fast,
            end_loop_used,
            end_loop_note,
        };
        if let Some((ln_phi, dln_phi)) = model.loop_correction(model.coexistence.torque) {
            model.loop_shift = (s.kt * ln_phi, s.kt * dln_phi);
        }
        Ok(model)
    }

    /// The end loop's thermal correction used: kT ln Φ at the coexistence
    /// torque (pN nm; 0 at kT = 0 or with a caller's counting length).
    pub fn end_loop_correction(&self) -> f64 {
        self.loop_shift.0
    }

    /// Which end loop the model uses.
    pub fn end_loop_used(&self) -> EndLoopUsed {
        self.end_loop_used
    }

    /// Why the end loop is not the one asked for (the scene outside the
    /// built-in table), or how it was computed; None otherwise.
    pub fn end_loop_note(&self) -> Option<&str> {
        self.end_loop_note.as_deref()
    }

    /// The extended phase's grand free energy per length h_s(τ) (pN).
    pub fn extended_grand(&self, tau: f64) -> f64 {
        -self.extended.g - tau * tau / (2.0 * self.extended.twist)
    }

    /// The plectonemic phase's h_p(τ) and writhe per length w(τ) from the tables.
    pub fn plectoneme_grand(&self, tau: f64) -> (f64, f64) {
        (self.hp.eval(tau), self.w.eval(tau))
    }

    /// E_nuc(τ), the loop's zero-temperature grand energy, its linking and
    /// its extension deficit.
    pub fn end_loop(&self, tau: f64) -> (f64, f64, f64) {
        let (g, lk, deficit) = elastic_loop(self.scene.bending, self.scene.force, tau);
        (self.loop_offset + g, lk, deficit + self.loop_offset_slope)
    }

    /// The end loop's thermal correction at torque τ, loop_fluct.rs (3): ln Φ,
    /// Φ = (w ξ₀)(kT/√(K_b F))^{−3/2}(2π)^{−1/2} g(m) the factor its Gaussian
    /// fluctuations give each plectoneme (per (L_s/ξ₀)(dℓ_p/ξ₀)), and
    /// ∂ ln Φ/∂F at fixed τ. None at kT = 0, with a caller's counting
    /// length, or where the plectoneme's writhe per length is not positive.
    pub fn loop_correction(&self, tau: f64) -> Option<(f64, f64)> {
        let table = self.loop_table?;
        let w = self.fast.w.eval(tau);
        if !(w > 0.0) {
            return None;
        }
        let (kt, f) = (self.scene.kt, self.scene.force);
        let sk = (self.scene.bending * f).sqrt();
        let mu = tau / (2.0 * sk);
        let (lg, dlg) = table.eval(mu);
        let ln_phi = lg + (w * self.counting).ln() - 1.5 * (kt / sk).ln() - 0.5 * (2.0 * PI).ln();
        // ∂/∂F at fixed τ: ln(w ξ₀) → −1/(2F), −(3/2) ln(kT/√(K_b F)) →
        // 3/(4F), g(m) with dm/dF = −m/(2F).
        Some((ln_phi, (0.25 - 0.5 * mu * dlg) / f))
    }

    /// The end loop at finite temperature: its grand free energy, linking,
    /// dLk/dτ and extension deficit. The thermal correction −kT ln Φ is
    /// taken at the coexistence torque τ* and held constant in τ: across
    /// the plateau and the overshoot it varies by ~0.1 kT, while its
    /// τ-derivatives (a linking kT/2π · d ln Φ/dτ) diverge where the
    /// harmonic loop fails — at the tabulated torque's ends, where w → 0
    /// or the loop spreads out (m → 1). A constant keeps F(n) = −kT ln Z
    /// exact in dF/dn = 2π⟨τ⟩.
    fn thermal_loop(&self, tau: f64) -> (f64, f64, f64, f64) {
        let (enuc, lk, deficit) = self.end_loop(tau);
        let sk = (self.scene.bending * self.scene.force).sqrt();
        let mm = tau / (2.0 * sk);
        // dLk_loop/dτ = −(2/π)/√(1 − m²) · 1/(2√(K_b F)).
        let dlk = if mm.abs() < 1.0 { -(2.0 / PI) / (1.0 - mm * mm).sqrt() / (2.0 * sk) } else { 0.0 };
        (enuc - self.loop_shift.0, lk, dlk, deficit - self.loop_shift.1)
    }

    /// The extension per length of the extended phase at torque τ.
    fn extended_extension(&self, tau: f64) -> f64 {
        let e = &self.extended;
        let omega = tau / e.twist;
        let ts =
            if self.scene.stretch_modulus > 0.0 { self.scene.twist_stretch / self.scene.stretch_modulus } else { 0.0 };
        e.zeta - 0.5 * e.softened_slope * omega * omega - ts * omega
    }

    /// The state with m ≥ 1 plectonemes at torque τ, linking n: its ℓ_p
    /// from (1), free energy, log-weight of (2) per unit τ, and observables.
    fn state(&self, n: f64, m: usize, tau: f64) -> Option<State> {
        self.state_or_validity::<true>(n, m, tau)
    }

    /// Whether the state with m plectonemes at torque τ exists (the
    /// bisections for the ends of its τ interval need no more).
    fn valid(&self, n: f64, m: usize, tau: f64) -> bool {
        self.state_or_validity::<false>(n, m, tau).is_some()
    }

    /// [`Model::state`]; with `FULL` false only its validity (Some with the
    /// free energy and weight left 0: no h_p, w' or logarithms).
    fn state_or_validity<const FULL: bool>(&self, n: f64, m: usize, tau: f64) -> Option<State> {
        let l = self.length;
        let ce = self.extended.twist;
        let kt_mod = self.scene.twist;
        let w = self.fast.w.eval(tau);
        let weff = w + tau / (2.0 * PI) * (1.0 / kt_mod - 1.0 / ce);
        if !(weff > 0.0) {
            return None;
        }
        let (enuc, lk, dlk, deficit) = self.thermal_loop(tau);
        let mf = m as f64;
        let num = n - l * tau / (2.0 * PI * ce) - mf * lk;
        let lp = num / weff;
        let ls = l - lp;
        if !(lp > 0.0) || ls <= 0.0 {
            return None;
        }
        let sk = (self.scene.bending * self.scene.force).sqrt();
        let mm = tau / (2.0 * sk);
        // Each loop must fit in the tails: the elastic loop decays over
        // ξ = √(K_b/F)/√(1 − m²) on either side, so it takes ~4ξ of chain;
        // near the straight chain's instability (m → 1) ξ diverges and no
        // loop fits (the elastic loop's energy and deficit vanish there, and
        // without this bound loops would multiply for nothing).
        if mm >= 1.0 || ls < mf * 4.0 * (self.scene.bending / self.scene.force).sqrt() / (1.0 - mm * mm).sqrt() {
            return None;
        }
        let mut extension = ls * self.extended_extension(tau) - mf * deficit;
        if self.loop_table.is_some() {
            if !(w > 0.0) {
                return None;
            }
            // The counting on b = ξ₀ = √(K_b/F) depends on the force: its
            // m + (m − 1) + 1 powers of 1/ξ₀ add kT ∂ln W/∂F = kT m/F.
            extension += self.scene.kt * mf / self.scene.force;
        }
        // The tails must hold the loops: no state with a negative extension.
        if extension <= 0.0 {
            return None;
        }
        let writhe = lp * w + mf * lk;
        if !FULL {
            return Some(State { free: 0.0, log_weight: 0.0, tau, lp, extension, writhe });
        }
        let dw = self.fast.dw.eval(tau);
        let dweff = dw + (1.0 / kt_mod - 1.0 / ce) / (2.0 * PI);
        let dlp = (-l / (2.0 * PI * ce) - mf * dlk - lp * dweff) / weff;
        let hp = self.fast.hp.eval(tau);
        let free = ls * self.extended_grand(tau) + lp * hp + mf * enuc + 2.0 * PI * tau * n;
        let b = self.counting;
        let log_weight =
            mf * (ls / b).ln() - ln_factorial(m) + (mf - 1.0) * (lp / b).ln() - ln_factorial(m - 1) - b.ln()
                + dlp.abs().max(1e-300).ln();
        Some(State { free, log_weight, tau, lp, extension, writhe })
    }

    /// The unbuckled state at linking n.
    fn straight(&self, n: f64) -> State {
        let l = self.length;
        let tau = 2.0 * PI * n * self.extended.twist / l;
        let free = l * self.extended_grand(tau) + 2.0 * PI * tau * n;
        State { free, log_weight: 0.0, tau, lp: 0.0, extension: l * self.extended_extension(tau), writhe: 0.0 }
    }

    /// The τ interval of states with m plectonemes at linking n: from
    /// where the tails vanish (the bottom) to ℓ_p = 0 (the top, where the
    /// numerator of (1) for ℓ_p vanishes; it decreases with τ), clipped to
    /// the tables; None when empty.
    fn torque_interval(&self, n: f64, m: usize) -> Option<(f64, f64)> {
        let (lo, hi) = self.torque_range;
        let l = self.length;
        let ce = self.extended.twist;
        let num = |t: f64| n - l * t / (2.0 * PI * ce) - m as f64 * self.thermal_loop(t).1;
        if num(lo) <= 0.0 {
            return None;
        }
        let top = if num(hi) > 0.0 {
            hi
        } else {
            let (mut a, mut b) = (lo, hi);
            for _ in 0..48 {
                let c = 0.5 * (a + b);
                if num(c) > 0.0 {
                    a = c;
                } else {
                    b = c;
                }
            }
            a
        };
        let valid = |t: f64| self.valid(n, m, t);
        if !valid(top) {
            // Just below the top ℓ_p is tiny and the state valid unless the
            // tables' w_eff fails there: scan down for a valid τ.
            let k = 32;
            let found = (1..=k).map(|i| top - (top - lo) * i as f64 / k as f64).find(|&t| valid(t))?;
            return self.bottom(found, lo, &valid).map(|b| (b, found));
        }
        self.bottom(top, lo, &valid).map(|b| (b, top))
    }

    /// The lowest valid τ below a valid `top` (bisection; the valid set is
    /// an interval: ℓ_p grows monotonically as τ falls).
    fn bottom(&self, top: f64, lo: f64, valid: &dyn Fn(f64) -> bool) -> Option<f64> {
        if valid(lo) {
            return Some(lo);
        }
        let (mut a, mut b) = (top, lo);
        for _ in 0..24 {
            let c = 0.5 * (a + b);
            if valid(c) {
                a = c;
            } else {
                b = c;
            }
        }
        (a < top).then_some(a)
    }

    /// The thermal averages at linking n (turns).
    pub fn point(&self, n: f64) -> Result<Point> {
        if !n.is_finite() {
            return Err(Error::new(Status::ErrNotFinite, "turns must be finite"));
        }
        let kt = self.scene.kt;
        let s0 = self.straight(n);
        // Whether the states at the cap on m carry weight (kT > 0).
        let mut truncated = false;
        // Collect (log-integrand, state, quadrature weight) per m.
        let mut terms: Vec<(f64, State, usize)> = Vec::new();
        let mut best_buckled: Option<(f64, State, usize)> = None;
        // The peak log-integrand of each m so far: once a further
        // plectoneme lowers the peak and it lies 30 below the best
        // (e^{-30} ≈ 1e-13 of the sum, times the ratio of the terms' spreads
        // in τ, well below e^{10}: < 2e-9; measured < 2e-10 in ⟨z⟩ and ⟨τ⟩
        // against a cut at 60), more plectonemes only lower it
        // further (each costs another end loop) and the sum stops.
        let mut best_peak = -s0.free / kt.max(f64::MIN_POSITIVE);
        let mut last_peak = f64::NEG_INFINITY;
        for m in 1..=self.scene.max_plectonemes {
            let Some((t0, t1)) = self.torque_interval(n, m) else { continue };
            if kt == 0.0 {
                // The lowest state: golden section on F over [t0, t1]
                // after a scan (F is smooth and convex along (1) here).
                let k = 64;
                let mut best = (f64::INFINITY, t0);
                for i in 0..=k {
                    let t = t0 + (t1 - t0) * i as f64 / k as f64;
                    if let Some(st) = self.state(n, m, t) {
                        if st.free < best.0 {
                            best = (st.free, t);
                        }
                    }
                }
                let h = (t1 - t0) / k as f64;
                let (mut a, mut b) = ((best.1 - h).max(t0), (best.1 + h).min(t1));
                let g = 0.5 * (5f64.sqrt() - 1.0);
                let fval = |t: f64| self.state(n, m, t).map(|s| s.free).unwrap_or(f64::INFINITY);
                for _ in 0..80 {
                    let c = b - g * (b - a);
                    let d = a + g * (b - a);
                    if fval(c) < fval(d) {
                        b = d;
                    } else {
                        a = c;
                    }
                }
                if let Some(st) = self.state(n, m, 0.5 * (a + b)) {
                    if best_buckled.as_ref().is_none_or(|b| st.free < b.0) {
                        best_buckled = Some((st.free, st, m));
                    }
                }
                continue;
            }
            // The integral of (2) in τ over [t0, t1]: the log-integrand is
            // unimodal (the free energy along (1) is convex); its peak by
            // Brent's search (golden section with parabolic steps: the
            // log-integrand is smooth, nearly quadratic at its peak, so ~10
            // evaluations place it to 1e-8 of the interval where golden
            // section alone took 30 for 1e-6), its spread from the curvature
            // there (or the slope, at an end), then Gauss–Legendre on two
            // panels either side of the peak out to 10 spreads (e^{-50} of
            // the peak).
            let li = |t: f64| self.state(n, m, t).map_or(f64::NEG_INFINITY, |st| st.log_weight - st.free / kt);
            let (peak_in, li_in) = brent_max(&li, t0, t1, 1e-8 * (t1 - t0));
            let mut peak = peak_in;
            let mut top = li_in;
            for end in [t0, t1] {
                let v = li(end);
                if v > top {
                    (peak, top) = (end, v);
                }
            }
            if top == f64::NEG_INFINITY {
                continue;
            }
            if m >= 2 && top < last_peak && top < best_peak - 30.0 {
                break;
            }
            last_peak = top;
            best_peak = best_peak.max(top);
            let h = 1e-4 * (t1 - t0);
            let (lm, lp) = (li((peak - h).max(t0)), li((peak + h).min(t1)));
            let curv = (lp - 2.0 * top + lm) / (h * h);
            let slope = ((lp - lm) / (2.0 * h)).abs();
            let spread = if curv < 0.0 && curv.is_finite() {
                (1.0 / (-curv).sqrt()).min(t1 - t0)
            } else if slope > 0.0 && slope.is_finite() {
                (1.0 / slope).min(t1 - t0)
            } else {
                t1 - t0
            };
            let (ga, gb) = ((peak - 10.0 * spread).max(t0), (peak + 10.0 * spread).min(t1));
            let (gx, gw) = gauss();
            for (pa, pb) in [(ga, peak), (peak, gb)] {
                if pb <= pa {
                    continue;
                }
                let half = 0.5 * (pb - pa);
                for (xi, wi) in gx.iter().zip(gw.iter()) {
                    let t = pa + half * (1.0 + xi);
                    if let Some(st) = self.state(n, m, t) {
                        let v = st.log_weight - st.free / kt + (half * wi).ln();
                        terms.push((v, st, m));
                    }
                }
            }
        }
        let stats = if kt == 0.0 {
            let lowest = match best_buckled {
                Some((f, st, m)) if f < s0.free => Some((st, m)),
                _ => None,
            };
            let (st, m, pb) = match lowest {
                Some((st, m)) => (st, m as f64, 1.0),
                None => (s0, 0.0, 0.0),
            };
            Stats {
                free: st.free,
                z: st.extension,
                tau: st.tau,
                wr: st.writhe,
                lp: st.lp,
                m,
                pb,
                zb: if pb > 0.0 { Some(st.extension) } else { None },
                tb: st.tau,
            }
        } else {
            let l0 = -s0.free / kt;
            let top = terms.iter().map(|t| t.0).fold(l0, f64::max);
            let w0 = (l0 - top).exp();
            let mut z = w0;
            let (mut ez, mut et, mut ew, mut el, mut em) = (w0 * s0.extension, w0 * s0.tau, 0.0, 0.0, 0.0);
            let (mut zb, mut ezb, mut etb) = (0.0, 0.0, 0.0);
            for (v, st, m) in &terms {
                let wgt = (v - top).exp();
                z += wgt;
                zb += wgt;
                ez += wgt * st.extension;
                et += wgt * st.tau;
                ew += wgt * st.writhe;
                el += wgt * st.lp;
                em += wgt * *m as f64;
                ezb += wgt * st.extension;
                etb += wgt * st.tau;
            }
            let pb = zb / z;
            let cap = self.scene.max_plectonemes;
            let at_cap: f64 = terms.iter().filter(|t| t.2 == cap).map(|t| (t.0 - top).exp()).sum();
            truncated = at_cap > 1e-6 * z;
            Stats {
                free: -kt * (top + z.ln()),
                z: ez / z,
                tau: et / z,
                wr: ew / z,
                lp: el / z,
                m: em / z,
                pb,
                zb: (zb > 0.0).then(|| ezb / zb),
                tb: if zb > 0.0 { etb / zb } else { s0.tau },
            }
        };
        let tb = stats.tb.clamp(self.torque_range.0, self.torque_range.1);
        let point = Point {
            turns: n,
            extension: stats.z,
            torque: stats.tau,
            twist: n - stats.wr,
            writhe: stats.wr,
            plectoneme_length: stats.lp,
            plectonemes: stats.m,
            buckled_probability: stats.pb,
            extension_unbuckled: s0.extension,
            extension_buckled: stats.zb,
            superhelix_radius: self.radius.eval(tb),
            superhelix_angle: self.angle.eval(tb),
            free_energy: stats.free,
            in_range: true,
        };
        let point = Point { in_range: !truncated && self.in_range(&point, &s0), ..point };
        for v in [point.extension, point.torque, point.writhe, point.plectoneme_length, point.buckled_probability] {
            if !v.is_finite() {
                return Err(Error::new(
                    Status::ErrNonFiniteResult,
                    format!("thermal averages at {n} turns are not finite"),
                ));
            }
        }
        Ok(point)
    }

    /// Whether a point is inside the model's range (see [`Point::in_range`]).
    fn in_range(&self, p: &Point, s0: &State) -> bool {
        let cap = self.torque_range.1;
        let z_free = self.length * self.extended.zeta;
        let unbuckled_ok = p.buckled_probability > 0.5 || s0.tau <= cap;
        let buckled_ok = p.buckled_probability < 0.5 || p.torque < 0.98 * cap;
        unbuckled_ok && buckled_ok && p.extension > 0.05 * z_free
    }

    /// log Z_buckled − log Z_unbuckled at linking n (kT > 0), or
    /// (F₀ − min F_buckled) at kT = 0: positive where the buckled states win.
    pub fn buckling_balance(&self, n: f64) -> Result<f64> {
        let p = self.point(n)?;
        let kt = self.scene.kt;
        if kt == 0.0 {
            return Ok(if p.buckled_probability > 0.5 { 1.0 } else { -1.0 });
        }
        let pb = p.buckled_probability.clamp(1e-300, 1.0 - 1e-16);
        Ok((pb / (1.0 - pb)).ln())
    }
}

#[derive(Clone, Copy, Debug)]
struct State {
    free: f64,
    log_weight: f64,
    tau: f64,
    lp: f64,
    extension: f64,
    writhe: f64,
}

struct Stats {
    free: f64,
    z: f64,
    tau: f64,
    wr: f64,
    lp: f64,
    m: f64,
    pb: f64,
    zb: Option<f64>,
    tb: f64,
}

/// One point of a thermal curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Turns n (excess linking number).
    pub turns: f64,
    /// ⟨z⟩ (nm), ⟨τ⟩ (pN nm), ⟨Tw⟩ = n − ⟨Wr⟩, ⟨Wr⟩.
    pub extension: f64,
    pub torque: f64,
    pub twist: f64,
    pub writhe: f64,
    /// ⟨ℓ_p⟩ (nm) and ⟨m⟩.
    pub plectoneme_length: f64,
    pub plectonemes: f64,
    /// The buckled population P(m ≥ 1).
    pub buckled_probability: f64,
    /// The extension of the unbuckled state and the mean extension of the
    /// buckled states (None where there are none): the two levels a
    /// hopping molecule visits.
    pub extension_unbuckled: f64,
    pub extension_buckled: Option<f64>,
    /// The superhelix at the buckled states' mean torque (nm, rad).
    pub superhelix_radius: f64,
    pub superhelix_angle: f64,
    /// The free energy −kT ln Z(n) (pN nm; at kT = 0 the lowest state's F),
    /// relative to the straight relaxed chain's L·(−g_e): its slope in n is
    /// 2π⟨τ⟩ (the work theorem, held in tests/tweezers.rs).
    pub free_energy: f64,
    /// False where the model does not describe the molecule: the
    /// unbuckled chain beyond its instability torque τ_cap with no buckled
    /// state to take over, the buckled states pinned at the tables' top
    /// torque τ_cap, or the tails used up (⟨z⟩ below 5 % of the zero-turn
    /// extension). Such points carry the model's numbers but are not a
    /// prediction; summaries skip them.
    pub in_range: bool,
}

/// The maximum of a unimodal f on [a, b] by Brent's method (R. P. Brent,
/// Algorithms for Minimization without Derivatives (1973), ch. 5: golden
/// section safeguarding parabolic interpolation through the three best
/// points), to the absolute tolerance `tol` in the abscissa: (x, f(x)).
/// Values of −∞ (no state there) are taken as the lowest and never enter a
/// parabola.
fn brent_max(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> (f64, f64) {
    const C: f64 = 0.381_966_011_250_105_1; // (3 − √5)/2
    let g = |t: f64| -f(t);
    let (mut a, mut b) = (a, b);
    let mut x = a + C * (b - a);
    let (mut w, mut v) = (x, x);
    let mut fx = g(x);
    let (mut fw, mut fv) = (fx, fx);
    let (mut d, mut e): (f64, f64) = (0.0, 0.0);
    for _ in 0..100 {
        let xm = 0.5 * (a + b);
        let tol2 = 2.0 * tol;
        if (x - xm).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let golden = |x: f64| if x >= xm { a - x } else { b - x };
        let mut parabolic = false;
        if e.abs() > tol && fx.is_finite() && fw.is_finite() && fv.is_finite() {
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            let e_old = e;
            if p.abs() < (0.5 * q * e_old).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = tol.copysign(xm - x);
                }
                parabolic = true;
            }
        }
        if !parabolic {
            e = golden(x);
            d = C * e;
        }
        let u = if d.abs() >= tol { x + d } else { x + tol.copysign(d) };
        let fu = g(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv) = (w, fw);
            (w, fw) = (x, fx);
            (x, fx) = (u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv) = (w, fw);
                (w, fw) = (u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, -fx)
}

/// ln k! from a table (k ≤ [`MAX_PLECTONEMES`]; the partition sums call it
/// at every state).
fn ln_factorial(k: usize) -> f64 {
    static TABLE: std::sync::OnceLock<[f64; MAX_PLECTONEMES + 1]> = std::sync::OnceLock::new();
    let t = TABLE.get_or_init(|| {
        let mut t = [0.0; MAX_PLECTONEMES + 1];
        for i in 2..=MAX_PLECTONEMES {
            t[i] = t[i - 1] + (i as f64).ln();
        }
        t
    });
    t[k.min(MAX_PLECTONEMES)]
}

fn gauss() -> &'static (Vec<f64>, Vec<f64>) {
    use std::sync::OnceLock;
    static RULE: OnceLock<(Vec<f64>, Vec<f64>)> = OnceLock::new();
    RULE.get_or_init(|| crate::quadrature::gauss_legendre(20))
}

fn validate(s: &TweezersScene) -> Result<()> {
    let positive = [
        ("base_pairs", s.base_pairs),
        ("rise", s.rise),
        ("force", s.force),
        ("salt", s.salt),
        ("bending", s.bending),
        ("twist", s.twist),
        ("permittivity", s.permittivity),
        ("radius", s.radius),
    ];
    for (name, v) in positive {
        crate::error::positive(name, v)?;
    }
    for (name, v) in [
        ("kt", s.kt),
        ("charge_per_length", s.charge_per_length),
        ("stretch_modulus", s.stretch_modulus),
        ("confinement", s.confinement),
        ("hard_core", s.hard_core),
        ("counting_length", s.counting_length),
    ] {
        crate::error::finite(name, v)?;
        if v < 0.0 {
            return Err(Error::new(Status::ErrOutOfRange, format!("argument `{name}` must be ≥ 0 (got {v:e})")));
        }
    }
    crate::error::finite("twist_stretch", s.twist_stretch)?;
    crate::error::finite("marko_plectoneme", s.marko_plectoneme)?;
    if s.marko_plectoneme < 0.0 || (s.marko_plectoneme > 0.0 && s.kt == 0.0) {
        return Err(Error::new(Status::ErrOutOfRange, "Marko's plectoneme needs P ≥ 0 and kT > 0"));
    }
    if s.twist_stretch != 0.0 && s.stretch_modulus == 0.0 {
        return Err(Error::new(Status::ErrOutOfRange, "a twist–stretch coupling needs a stretch modulus"));
    }
    crate::error::count_in_range("max_plectonemes", s.max_plectonemes as i64, 1, MAX_PLECTONEMES as i64)?;
    crate::error::in_range("base_pairs", s.base_pairs, 50.0, 1e6)?;
    Ok(())
}

/// The superhelix's tables on [τ_lo, τ_cap]: τ_lo is where the superhelix
/// still has a minimum at a finite radius (below, φ → 0⁺ as R → ∞: no
/// plectoneme), found going down from τ_cap/2 by factors of 0.85 until R
/// exceeds half the largest radius searched; τ_cap = 2√(K_b F) is the
/// infinite straight rod's instability (no end loop exists beyond it).
/// Returns (τ_lo, [h_p, w, R, α] at the nodes, the nodes).
#[allow(clippy::type_complexity)]
fn superhelix_tables(plectoneme: &Plectoneme, tau_cap: f64) -> Result<(f64, Vec<[f64; 4]>, Vec<f64>)> {
    let r_far = 0.5 * plectoneme.max_radius();
    let first = plectoneme.optimum(0.5 * tau_cap, None)?;
    if first.radius >= r_far {
        return Err(Error::new(
            Status::ErrNotConverged,
            format!(
                "no superhelix at half the straight chain's instability torque ({:.2} pN nm): no plectoneme",
                0.5 * tau_cap
            ),
        ));
    }
    let mut t_lo = 0.5 * tau_cap;
    let mut start = (first.radius, first.angle);
    while t_lo > 0.02 * tau_cap {
        let t = 0.85 * t_lo;
        match plectoneme.optimum(t, Some(start)) {
            Ok(o) if o.radius < r_far => {
                t_lo = t;
                start = (o.radius, o.angle);
            }
            _ => break,
        }
    }
    let nodes = cheb::points(DEGREE, t_lo, tau_cap);
    let mut vals = vec![[0.0; 4]; nodes.len()];
    // From the top down (nodes descend), each optimum warm-starting the
    // next from the secant through the two before (in τ); the top one from
    // the optimum at τ_cap/2 (φ has one minimum at kT > 0, and at kT = 0
    // [`Plectoneme::optimum`] still compares a warm start with its grid).
    let mut prev: Vec<(f64, f64, f64)> = Vec::with_capacity(nodes.len());
    for (k, &t) in nodes.iter().enumerate() {
        let start = match prev.as_slice() {
            [.., (t1, r1, a1), (t2, r2, a2)] => {
                let x = (t - t2) / (t2 - t1);
                let r = r2 + x * (r2 - r1);
                Some((if r > plectoneme.radius { r } else { *r2 }, a2 + x * (a2 - a1)))
            }
            [(_, r, a)] => Some((*r, *a)),
            _ => Some((first.radius, first.angle)),
        };
        let o = plectoneme.optimum(t, start)?;
        prev.push((t, o.radius, o.angle));
        vals[k] = [plectoneme.grand(&o), o.writhe, o.radius, o.angle];
    }
    Ok((t_lo, vals, nodes))
}

/// The end loop's E_nuc offset (E_nuc = offset + ΔG_loop(τ)), the
/// offset's −d/dF (its part of the extension deficit), which source was
/// used and why, when it is not the one asked for.
fn loop_offset(s: &TweezersScene) -> Result<(f64, f64, EndLoopUsed, Option<String>)> {
    let table_at = |entries: &[EndLoopEntry], force: f64| -> Result<f64> {
        let (tau0, e) = interpolate_table(entries, force, s.salt)?;
        Ok(e - elastic_loop(s.bending, force, tau0).0)
    };
    // −d(offset)/dF by central differences across the table (0 where a
    // neighbour force leaves it).
    let slope_of = |entries: &[EndLoopEntry]| {
        let h = 1e-3 * s.force;
        match (table_at(entries, s.force + h), table_at(entries, s.force - h)) {
            (Ok(p), Ok(m)) => -(p - m) / (2.0 * h),
            _ => 0.0,
        }
    };
    match &s.end_loop {
        EndLoopSource::Elastic => Ok((0.0, 0.0, EndLoopUsed::Elastic, None)),
        EndLoopSource::Value { torque, energy } => {
            Ok((energy - elastic_loop(s.bending, s.force, *torque).0, 0.0, EndLoopUsed::Value, None))
        }
        EndLoopSource::Table(entries) => Ok((table_at(entries, s.force)?, slope_of(entries), EndLoopUsed::Table, None)),
        EndLoopSource::Auto => {
            let entries = builtin_end_loops();
            match table_at(&entries, s.force) {
                Ok(d) => Ok((d, slope_of(&entries), EndLoopUsed::Table, None)),
                Err(e) => {
                    Ok((0.0, 0.0, EndLoopUsed::Elastic, Some(format!("{}; the elastic end loop is used", e.message))))
                }
            }
        }
        EndLoopSource::Compute => {
            let (scene, settings) = crate::charged::end_loop::table_scene(s.force, s.salt);
            let e = crate::charged::end_loop::end_loop_entry(&scene, &settings)?;
            let d = e.e_nuc - elastic_loop(s.bending, s.force, e.tau_plateau).0;
            let note = format!(
                "end loop computed by the full rod for this scene: {} bp, E_nuc {:.2} pN nm at {:.3} pN nm, {:.0} s",
                e.base_pairs, e.e_nuc, e.tau_plateau, e.seconds
            );
            Ok((d, 0.0, EndLoopUsed::Computed, Some(note)))
        }
    }
}

/// Bilinear interpolation in (ln F, ln c) of the table's τ₀ and E_nuc on
/// its force × salt grid; a scene outside it is refused.
pub fn interpolate_table(entries: &[EndLoopEntry], force: f64, salt: f64) -> Result<(f64, f64)> {
    let mut forces: Vec<f64> = entries.iter().map(|e| e.force).collect();
    let mut salts: Vec<f64> = entries.iter().map(|e| e.salt).collect();
    forces.sort_by(|a, b| a.partial_cmp(b).unwrap());
    forces.dedup();
    salts.sort_by(|a, b| a.partial_cmp(b).unwrap());
    salts.dedup();
    let outside = || {
        Error::new(
            Status::ErrOutOfRange,
            format!(
                "force {force} pN, salt {salt} M lies outside the end-loop table (forces {:?} pN × salts {:?} M); \
                 EndLoopSource::Compute (C: RODKIT_TWEEZERS_END_LOOP_COMPUTED) computes its entry with the full rod \
                 (minutes)",
                forces, salts
            ),
        )
    };
    let bracket = |v: &[f64], x: f64| -> Option<(usize, usize, f64)> {
        if v.is_empty() || x < v[0] * (1.0 - 1e-12) || x > v[v.len() - 1] * (1.0 + 1e-12) {
            return None;
        }
        if v.len() == 1 {
            return Some((0, 0, 0.0));
        }
        let i = v.windows(2).position(|w| x <= w[1] * (1.0 + 1e-12)).unwrap_or(v.len() - 2);
        let t = ((x.ln() - v[i].ln()) / (v[i + 1].ln() - v[i].ln())).clamp(0.0, 1.0);
        Some((i, i + 1, t))
    };
    let (f0, f1, tf) = bracket(&forces, force).ok_or_else(outside)?;
    let (c0, c1, tc) = bracket(&salts, salt).ok_or_else(outside)?;
    let get = |f: f64, c: f64| entries.iter().find(|e| e.force == f && e.salt == c).map(|e| (e.torque, e.energy));
    // The four corners with their bilinear weights; a corner of weight 0
    // (the scene on a grid line) is not needed, so a hole beside a grid
    // line does not refuse a scene on it.
    let corners = [
        (get(forces[f0], salts[c0]), (1.0 - tf) * (1.0 - tc)),
        (get(forces[f1], salts[c0]), tf * (1.0 - tc)),
        (get(forces[f0], salts[c1]), (1.0 - tf) * tc),
        (get(forces[f1], salts[c1]), tf * tc),
    ];
    let (mut tau, mut energy) = (0.0, 0.0);
    for (value, weight) in corners {
        if weight == 0.0 {
            continue;
        }
        let Some((t, e)) = value else {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!(
                    "the end-loop table has a hole next to force {force} pN, salt {salt} M (an entry not computed or that the full rod could not compute)"
                ),
            ));
        };
        tau += weight * t;
        energy += weight * e;
    }
    Ok((tau, energy))
}

/// The numbers a tweezers experiment reports for one curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Summary {
    /// Turns where the buckled population reaches ½ (at kT = 0: where the
    /// lowest state changes, the coexistence point).
    pub buckling_turns: f64,
    /// The unbuckled state's torque there (pN nm): the peak a torque
    /// measurement sees before the plectoneme forms.
    pub buckling_torque: f64,
    /// The mean torque on the plectonemic range (pN nm) and its spread.
    pub plateau_torque: f64,
    pub plateau_torque_min: f64,
    pub plateau_torque_max: f64,
    /// buckling_torque − plateau_torque (pN nm). Negative when the buckled
    /// population passes ½ before the torque reaches the later plateau: a
    /// cheap nucleation (loop free energy of a few kT — low salt, long
    /// molecules, torques near the straight chain's 2√(K_b F)) gives a
    /// gradual transition through several small plectonemes, with no
    /// abrupt buckling to measure an overshoot on.
    pub overshoot: f64,
    /// The infinite molecule's coexistence torque τ* (pN nm).
    pub coexistence_torque: f64,
    /// dz/dn by least squares on the plectonemic range (nm/turn, negative).
    pub slope: f64,
    /// The two levels at buckling: unbuckled minus buckled extension (nm).
    pub extension_jump: f64,
    /// ⟨z⟩ at zero turns (nm).
    pub extension_zero_turns: f64,
    /// The superhelix at the plateau torque (nm, rad).
    pub superhelix_radius: f64,
    pub superhelix_angle: f64,
    /// E_nuc at the plateau torque (pN nm), zero-temperature, and the
    /// loop's thermal correction kT ln Φ(τ*) ([`Model::end_loop_correction`]):
    /// its free energy is the difference.
    pub end_loop_energy: f64,
    pub end_loop_correction: f64,
    /// The plectonemic range: turns (first, last) and its number of points.
    pub plateau_turns: (f64, f64),
    pub plateau_points: usize,
}

impl Model {
    /// The curve at the given turns.
    pub fn curve(&self, turns: &[f64]) -> Result<Vec<Point>> {
        turns.iter().map(|&n| self.point(n)).collect()
    }

    /// The buckling turns: the buckled population crosses ½ (bisection on
    /// its log-odds, or on the lowest state at kT = 0), searched from 0
    /// up to the turns where the straight chain reaches τ_cap.
    pub fn buckling_turns(&self) -> Result<f64> {
        if let Some(&nb) = self.buckling.get() {
            return Ok(nb);
        }
        let nb = self.find_buckling()?;
        Ok(*self.buckling.get_or_init(|| nb))
    }

    fn find_buckling(&self) -> Result<f64> {
        let n_cap = self.torque_range.1 * self.length / (2.0 * PI * self.extended.twist);
        let k = 16;
        let mut prev = (0.0, self.buckling_balance(0.0)?);
        if prev.1 > 0.0 {
            return Err(Error::new(Status::ErrNotConverged, "the molecule is buckled at zero turns"));
        }
        for i in 1..=k {
            let n = 1.5 * n_cap * i as f64 / k as f64;
            let b = self.buckling_balance(n)?;
            if b > 0.0 {
                // Regula falsi (Illinois) on the log-odds, which is smooth at
                // kT > 0; bisection on the lowest state's sign at kT = 0.
                let (mut lo, mut glo, mut hi, mut ghi) = (prev.0, prev.1, n, b);
                let smooth = self.scene.kt > 0.0;
                let mut side = 0;
                for _ in 0..100 {
                    let c = if smooth && glo.is_finite() && ghi.is_finite() && ghi != glo {
                        (hi - ghi * (hi - lo) / (ghi - glo)).clamp(lo + 1e-3 * (hi - lo), hi - 1e-3 * (hi - lo))
                    } else {
                        0.5 * (lo + hi)
                    };
                    let g = self.buckling_balance(c)?;
                    if g > 0.0 {
                        hi = c;
                        ghi = g;
                        if side == 1 {
                            glo *= 0.5;
                        }
                        side = 1;
                    } else {
                        lo = c;
                        glo = g;
                        if side == -1 {
                            ghi *= 0.5;
                        }
                        side = -1;
                    }
                    if hi - lo < 1e-10 * hi || (smooth && g.abs() < 1e-9) {
                        return Ok(c);
                    }
                }
                return Ok(0.5 * (lo + hi));
            }
            prev = (n, b);
        }
        Err(Error::new(
            Status::ErrNotConverged,
            format!("no buckling up to {:.2} turns (1.5 × the straight chain's instability)", 1.5 * n_cap),
        ))
    }

    /// `points` turns evenly from 0 to twice the buckling turns (the
    /// default curve).
    pub fn default_turns(&self, points: usize) -> Result<Vec<f64>> {
        crate::error::count_in_range("points", points as i64, 2, 1_000_000)?;
        let nb = self.buckling_turns()?;
        Ok((0..points).map(|i| 2.0 * nb * i as f64 / (points - 1) as f64).collect())
    }

    /// The summary of a curve computed by [`Model::curve`] (turns
    /// ascending, from 0): the plectonemic range is the points past
    /// buckling whose buckled population is ≥ 0.99 and whose extension is
    /// still ≥ 30 % of the zero-turn extension (long tails: the range
    /// tweezers fit their slope on).
    pub fn summarise(&self, points: &[Point]) -> Result<Summary> {
        if points.len() < 2 || points[0].turns != 0.0 {
            return Err(Error::new(
                Status::ErrOutOfRange,
                "a summary needs a curve from 0 turns with at least 2 points",
            ));
        }
        let nb = self.buckling_turns()?;
        let at = self.point(nb)?;
        let z0 = points[0].extension;
        let range: Vec<&Point> = points
            .iter()
            .filter(|p| p.turns > nb && p.buckled_probability >= 0.99 && p.extension >= 0.3 * z0)
            .collect();
        if range.len() < 3 {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!("the curve has {} points on the plectonemic range (past {nb:.3} turns, buckled, z ≥ 0.3 z(0)): extend it", range.len()),
            ));
        }
        let k = range.len() as f64;
        let mean_n = range.iter().map(|p| p.turns).sum::<f64>() / k;
        let mean_z = range.iter().map(|p| p.extension).sum::<f64>() / k;
        let sxy: f64 = range.iter().map(|p| (p.turns - mean_n) * (p.extension - mean_z)).sum();
        let sxx: f64 = range.iter().map(|p| (p.turns - mean_n).powi(2)).sum();
        let plateau = range.iter().map(|p| p.torque).sum::<f64>() / k;
        let tmin = range.iter().map(|p| p.torque).fold(f64::INFINITY, f64::min);
        let tmax = range.iter().map(|p| p.torque).fold(f64::NEG_INFINITY, f64::max);
        let sh = if self.scene.marko_plectoneme > 0.0 {
            self.coexistence
        } else {
            self.plectoneme.optimum(plateau, Some((self.coexistence.radius, self.coexistence.angle)))?
        };
        let buckling_torque = 2.0 * PI * nb * self.extended.twist / self.length;
        // The buckled level: the buckled states' mean extension at n_b (at
        // kT = 0 the lowest buckled state, just past n_b).
        let buckled_level = match at.extension_buckled {
            Some(z) if self.scene.kt > 0.0 => z,
            _ => self.point(nb * (1.0 + 1e-9) + 1e-12)?.extension_buckled.unwrap_or(at.extension_unbuckled),
        };
        Ok(Summary {
            buckling_turns: nb,
            buckling_torque,
            plateau_torque: plateau,
            plateau_torque_min: tmin,
            plateau_torque_max: tmax,
            overshoot: buckling_torque - plateau,
            coexistence_torque: self.coexistence.torque,
            slope: sxy / sxx,
            extension_jump: at.extension_unbuckled - buckled_level,
            extension_zero_turns: z0,
            superhelix_radius: sh.radius,
            superhelix_angle: sh.angle,
            end_loop_energy: self.end_loop(plateau).0,
            end_loop_correction: self.loop_shift.0,
            plateau_turns: (range[0].turns, range[range.len() - 1].turns),
            plateau_points: range.len(),
        })
    }
}

/// The CSV columns of [`write_csv`].
pub const CSV_HEADER: [&str; 15] = [
    "turns",
    "extension_nm",
    "torque_pNnm",
    "twist",
    "writhe",
    "plectoneme_length_nm",
    "plectonemes",
    "buckled_probability",
    "extension_unbuckled_nm",
    "extension_buckled_nm",
    "superhelix_radius_nm",
    "superhelix_angle_rad",
    "free_energy_pNnm",
    "in_range",
    "model_kt_pNnm",
];

/// Write a curve as CSV through the library's writer (atomically; an
/// empty cell where the buckled level does not exist), with the model's kT
/// in every row so a file says which model made it (kT = 0: the
/// zero-temperature limit).
pub fn write_csv(path: &std::path::Path, points: &[Point], kt: f64) -> Result<()> {
    let rows: Vec<Vec<Option<f64>>> = points
        .iter()
        .map(|p| {
            vec![
                Some(p.turns),
                Some(p.extension),
                Some(p.torque),
                Some(p.twist),
                Some(p.writhe),
                Some(p.plectoneme_length),
                Some(p.plectonemes),
                Some(p.buckled_probability),
                Some(p.extension_unbuckled),
                p.extension_buckled,
                Some(p.superhelix_radius),
                Some(p.superhelix_angle),
                Some(p.free_energy),
                Some(if p.in_range { 1.0 } else { 0.0 }),
                Some(kt),
            ]
        })
        .collect();
    crate::io::csv::write_cells(path, &CSV_HEADER, &rows)
}

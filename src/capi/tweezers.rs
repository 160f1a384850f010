//! DNA in magnetic or angular-optical tweezers at finite temperature from C
//! and Fortran: the thermal two-phase model of `crate::tweezers`
//! (physics.md §3.7). A spec makes a handle (the phases tabulated once);
//! the handle gives the default turns, the thermal curve at any turns into
//! a caller array, and the curve's summary (buckling, plateau torque, slope,
//! extension jump, superhelix).

use super::args::{arg_mut, arg_ref, c_enum, enum_arg, finite_fields, flag, free_handle, in_slice};
use super::args::{null_error, out_slice, qualify_argument};
use super::{guard, guard_value};
use crate::error::{self, Error, Result};
use crate::status::Status;
use crate::tweezers::{EndLoopSource, EndLoopUsed, Model, Point, TweezersScene};

/// Where a plectoneme's nucleation (end-loop) energy comes from
/// (`RodkitTweezersSpec.end_loop`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TweezersEndLoop {
    /// The table rodkit ships, computed with the full zero-temperature
    /// charged rod over force × salt, interpolated where it covers the
    /// scene; elsewhere the elastic loop, and the summary's `end_loop` says
    /// ELASTIC (in a spec: the default).
    BuiltinTable = 0,
    /// The elastic (uncharged Kirchhoff) end loop alone.
    Elastic = 1,
    /// A given nucleation energy `end_loop_energy` (pN nm) at the torque
    /// `end_loop_torque` (pN nm), with the elastic loop's torque dependence.
    Value = 2,
    /// This scene's own entry, computed by the full zero-temperature
    /// charged rod when the handle is made: minutes (a 300–1000 bp
    /// supercoiling run), on request only.
    Computed = 3,
}

c_enum!(
    TweezersEndLoop,
    "a RodkitTweezersEndLoop 0…3",
    [TweezersEndLoop::BuiltinTable, TweezersEndLoop::Elastic, TweezersEndLoop::Value, TweezersEndLoop::Computed]
);

/// Which model computed a supercoiling curve or summary.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SupercoilModel {
    /// The thermal two-phase model (extended chain, plectonemes, end
    /// loops; thermal averages over the number and length of
    /// plectonemes) at kT > 0: rodkit_tweezers_*.
    ThermalTwoPhase = 1,
    /// The same model's zero-temperature limit (kT = 0: the lowest state
    /// at each linking number): rodkit_tweezers_* with `kt` 0.
    ZeroTemperatureTwoPhase = 2,
    /// rodkit's full charged Kirchhoff rod at zero temperature
    /// (rodkit_dna_supercoil_run); no tweezers summary reports it.
    FullRod = 3,
}

/// A tweezers scene in nm, pN, mol/L. Call `rodkit_tweezers_spec_default`
/// first: 1 kbp of rise 0.34 nm, 1 pN, 0.1 M, kT = 4.11 pN nm (25 °C),
/// bending modulus 50 kT·nm and twist modulus 100 kT·nm (kT 4.11, pN nm²),
/// the Poisson–Boltzmann effective charge, ε_r 78.4, a = 1 nm,
/// inextensible, the default confinement and hard core, the automatic
/// counting length, up to 4 plectonemes, and the default end loop.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TweezersSpec {
    /// Length in base pairs (50 … 1e6) and rise per base pair (nm).
    pub base_pairs: f64,
    pub rise: f64,
    /// Pulling force (pN, > 0).
    pub force: f64,
    /// Monovalent salt (mol/L, > 0).
    pub salt: f64,
    /// Thermal energy kT (pN nm, ≥ 0): 4.11 at 25 °C; 0 = the
    /// zero-temperature limit (the lowest state at each linking number).
    /// The moduli below are in pN nm², not in units of kT: changing `kt`
    /// keeps them.
    pub kt: f64,
    /// Bending modulus K_b = A kT and twist modulus K_t = C kT (pN nm²).
    pub bending: f64,
    pub twist: f64,
    /// Effective line charge ν (e/nm, ≥ 0); 0 (the default): the
    /// Poisson–Boltzmann effective charge of a 1 nm cylinder carrying 2 e
    /// per 0.34 nm at the spec's salt. And the relative permittivity.
    pub charge_per_length: f64,
    pub permittivity: f64,
    /// DNA radius a (nm): the electrostatics' cutoff and the strands'
    /// contact distance 2a.
    pub radius: f64,
    /// Stretch modulus S (pN; 0: inextensible) and twist–stretch coupling
    /// g (pN nm; needs S).
    pub stretch_modulus: f64,
    pub twist_stretch: f64,
    /// Confinement coefficient of the plectoneme's strands (≥ 0; 0: off).
    pub confinement: f64,
    /// Hard core between the strands (pN/nm⁴, ≥ 0; 0: none).
    pub hard_core: f64,
    /// Counting length b of the partition function (nm, ≥ 0); 0: √(K_b/F)
    /// with the end loop's computed fluctuation factor (a given b turns
    /// the factor off).
    pub counting_length: f64,
    /// The largest number of plectonemes summed (1 … 64, default 64; the
    /// sum stops earlier by itself; points where states at the cap still
    /// weigh > 1e-6 of the sum are flagged out of range).
    pub max_plectonemes: i64,
    /// A RodkitTweezersEndLoop.
    pub end_loop: i32,
    /// RODKIT_TWEEZERS_END_LOOP_VALUE only (else ignored, but finite): the
    /// torque (pN nm, > 0) at which the nucleation energy `end_loop_energy`
    /// (pN nm) is given.
    pub end_loop_torque: f64,
    pub end_loop_energy: f64,
}

/// One point of a thermal curve: averages over the molecule's states at
/// the given turns (never NaN).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TweezersPoint {
    /// Turns n (the excess linking number).
    pub turns: f64,
    /// ⟨z⟩ (nm), ⟨τ⟩ (pN nm), ⟨Tw⟩ = n − ⟨Wr⟩ and ⟨Wr⟩ (turns).
    pub extension: f64,
    pub torque: f64,
    pub twist: f64,
    pub writhe: f64,
    /// ⟨ℓ_p⟩ (nm), the mean total plectoneme length, and ⟨m⟩, the mean
    /// number of plectonemes.
    pub plectoneme_length: f64,
    pub plectonemes: f64,
    /// The buckled population P(m ≥ 1) (0 … 1; at kT = 0, 0 or 1).
    pub buckled_probability: f64,
    /// The extension of the unbuckled state (nm): the upper level a
    /// hopping molecule visits.
    pub extension_unbuckled: f64,
    /// 1 when buckled states exist at these turns; then
    /// `extension_buckled` is their mean extension (nm, the lower level),
    /// else it is 0.
    pub has_buckled: i32,
    pub extension_buckled: f64,
    /// The superhelix at the buckled states' mean torque: radius (nm) and
    /// opening angle (rad).
    pub superhelix_radius: f64,
    pub superhelix_angle: f64,
    /// −kT ln Z(n) (pN nm; at kT = 0 the lowest state's free energy),
    /// relative to the relaxed straight chain: its slope in turns is 2π × torque.
    pub free_energy: f64,
    /// 1 inside the model's range; 0 where the model does not describe the
    /// molecule (the unbuckled chain beyond its instability torque with no
    /// buckled state to take over, the buckled states pinned at the top
    /// torque of the tables, or the tails used up: ⟨z⟩ below 5 % of the
    /// zero-turn extension): such a point carries the model's numbers but
    /// is not a prediction; rodkit_tweezers_summary skips it.
    pub in_range: i32,
}

/// The numbers a tweezers experiment reports for one curve
/// (rodkit_tweezers_summary; never NaN).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TweezersInfo {
    /// The model that computed the curve (THERMAL_TWO_PHASE, or
    /// ZERO_TEMPERATURE_TWO_PHASE at kT = 0) and the end-loop source it
    /// used.
    pub model: SupercoilModel,
    pub end_loop: TweezersEndLoop,
    /// The thermal energy (pN nm) of the handle's spec.
    pub kt: f64,
    /// Turns where the buckled population reaches ½ (at kT = 0: where the
    /// lowest state changes) and the unbuckled state's torque there
    /// (pN nm, the peak before the plectoneme forms).
    pub buckling_turns: f64,
    pub buckling_torque: f64,
    /// The mean torque on the plectonemic range (pN nm), its min and max,
    /// and buckling_torque − plateau_torque (the overshoot; negative for a
    /// gradual transition through several small plectonemes, when the
    /// loop's free energy is only a few kT: low salt, long molecules).
    pub plateau_torque: f64,
    pub plateau_torque_min: f64,
    pub plateau_torque_max: f64,
    pub overshoot: f64,
    /// The infinite molecule's coexistence torque τ* (pN nm).
    pub coexistence_torque: f64,
    /// dz/dn by least squares on the plectonemic range (nm/turn, negative).
    pub slope: f64,
    /// Unbuckled minus buckled extension at buckling (nm).
    pub extension_jump: f64,
    /// ⟨z⟩ at zero turns (nm).
    pub extension_zero_turns: f64,
    /// The superhelix at the plateau torque: radius (nm), angle (rad).
    pub superhelix_radius: f64,
    pub superhelix_angle: f64,
    /// The nucleation energy of one plectoneme at the plateau torque (pN nm),
    /// zero-temperature, and its thermal correction kT ln Φ (pN nm; 0 at
    /// kT = 0 or with a given counting length): the loop's free energy is
    /// end_loop_energy − end_loop_correction (doc/physics.md §3.7.3).
    pub end_loop_energy: f64,
    pub end_loop_correction: f64,
    /// The plectonemic range: its first and last turns and its points
    /// (buckled population ≥ 0.99, extension ≥ 0.3 z(0), past buckling).
    pub plateau_turns_from: f64,
    pub plateau_turns_to: f64,
    pub plateau_points: i64,
    /// The plectoneme tables' interpolation error at τ* (pN): a diagnostic.
    pub table_error: f64,
}

/// An opaque tweezers model (rodkit_tweezers_new / rodkit_tweezers_free):
/// the scene with its phases tabulated. Immutable after creation: it may be
/// moved between threads and used by several threads at once.
pub struct Tweezers {
    model: Model,
    end_loop: TweezersEndLoop,
}

/// State evaluations of the thermal sum per point and per plectoneme
/// number (the torque interval's bisections, the peak's golden section,
/// the Gauss panels; the kT = 0 scan and search are about as many): the
/// unit of [`MAX_TWEEZERS_EVALUATIONS`].
const EVALUATIONS_PER_STATE_SUM: f64 = 250.0;

/// The work bound of one rodkit_tweezers_curve call, in state evaluations
/// (a few tens of nanoseconds each: 200 000 points of 4 plectoneme numbers,
/// 6 to 20 s; 20 000 points took 0.6 s at kT 4.11, 1.9 s at kT 0).
const MAX_TWEEZERS_EVALUATIONS: f64 = 2e8;

fn spec_default() -> TweezersSpec {
    let d = TweezersScene::default();
    let (end_loop, end_loop_torque, end_loop_energy) = match d.end_loop {
        EndLoopSource::Auto | EndLoopSource::Table(_) => (TweezersEndLoop::BuiltinTable, 0.0, 0.0),
        EndLoopSource::Compute => (TweezersEndLoop::Computed, 0.0, 0.0),
        EndLoopSource::Elastic => (TweezersEndLoop::Elastic, 0.0, 0.0),
        EndLoopSource::Value { torque, energy } => (TweezersEndLoop::Value, torque, energy),
    };
    TweezersSpec {
        base_pairs: d.base_pairs,
        rise: d.rise,
        force: d.force,
        salt: d.salt,
        kt: d.kt,
        bending: d.bending,
        twist: d.twist,
        charge_per_length: d.charge_per_length,
        permittivity: d.permittivity,
        radius: d.radius,
        stretch_modulus: d.stretch_modulus,
        twist_stretch: d.twist_stretch,
        confinement: d.confinement,
        hard_core: d.hard_core,
        counting_length: d.counting_length,
        max_plectonemes: d.max_plectonemes as i64,
        end_loop: end_loop as i32,
        end_loop_torque,
        end_loop_energy,
    }
}

/// The scene of a spec (messages name the spec's fields without `spec.`)
/// and the end-loop source it asks for.
fn scene_of(s: &TweezersSpec) -> Result<TweezersScene> {
    finite_fields(&[
        ("base_pairs", s.base_pairs),
        ("rise", s.rise),
        ("force", s.force),
        ("salt", s.salt),
        ("kt", s.kt),
        ("bending", s.bending),
        ("twist", s.twist),
        ("charge_per_length", s.charge_per_length),
        ("permittivity", s.permittivity),
        ("radius", s.radius),
        ("stretch_modulus", s.stretch_modulus),
        ("twist_stretch", s.twist_stretch),
        ("confinement", s.confinement),
        ("hard_core", s.hard_core),
        ("counting_length", s.counting_length),
        ("end_loop_torque", s.end_loop_torque),
        ("end_loop_energy", s.end_loop_energy),
    ])?;
    error::count_in_range("max_plectonemes", s.max_plectonemes, 1, crate::tweezers::MAX_PLECTONEMES as i64)?;
    let kind = enum_arg::<TweezersEndLoop>("end_loop", s.end_loop)?;
    let end_loop = match kind {
        TweezersEndLoop::BuiltinTable => EndLoopSource::Auto,
        TweezersEndLoop::Computed => EndLoopSource::Compute,
        TweezersEndLoop::Elastic => EndLoopSource::Elastic,
        TweezersEndLoop::Value => {
            error::positive("end_loop_torque", s.end_loop_torque)?;
            EndLoopSource::Value { torque: s.end_loop_torque, energy: s.end_loop_energy }
        }
    };
    let scene = TweezersScene {
        base_pairs: s.base_pairs,
        rise: s.rise,
        force: s.force,
        salt: s.salt,
        kt: s.kt,
        bending: s.bending,
        twist: s.twist,
        charge_per_length: s.charge_per_length,
        permittivity: s.permittivity,
        radius: s.radius,
        stretch_modulus: s.stretch_modulus,
        twist_stretch: s.twist_stretch,
        confinement: s.confinement,
        hard_core: s.hard_core,
        counting_length: s.counting_length,
        max_plectonemes: s.max_plectonemes as usize,
        // Marko's phenomenological plectoneme is a Rust-side reference only.
        marko_plectoneme: 0.0,
        end_loop,
    };
    Ok(scene)
}

/// Refuse, before anything is computed, a curve of `points` whose thermal
/// sums would exceed [`MAX_TWEEZERS_EVALUATIONS`].
fn check_work(points: i64, max_plectonemes: usize) -> Result<()> {
    let evaluations = points as f64 * max_plectonemes as f64 * EVALUATIONS_PER_STATE_SUM;
    if evaluations > MAX_TWEEZERS_EVALUATIONS {
        return Err(Error::new(
            Status::ErrWorkLimit,
            format!(
                "the call would exceed its work bound: {points} points × {max_plectonemes} plectoneme numbers × \
                 ~{EVALUATIONS_PER_STATE_SUM:.0} state evaluations = {evaluations:.2e} (bound \
                 {MAX_TWEEZERS_EVALUATIONS:.0e}, 6 to 20 s); compute fewer points, in several calls, or lower \
                 `max_plectonemes`"
            ),
        ));
    }
    Ok(())
}

fn c_point(p: &Point) -> TweezersPoint {
    TweezersPoint {
        turns: p.turns,
        extension: p.extension,
        torque: p.torque,
        twist: p.twist,
        writhe: p.writhe,
        plectoneme_length: p.plectoneme_length,
        plectonemes: p.plectonemes,
        buckled_probability: p.buckled_probability,
        extension_unbuckled: p.extension_unbuckled,
        has_buckled: p.extension_buckled.is_some() as i32,
        extension_buckled: p.extension_buckled.unwrap_or(0.0),
        superhelix_radius: p.superhelix_radius,
        superhelix_angle: p.superhelix_angle,
        free_energy: p.free_energy,
        in_range: p.in_range as i32,
    }
}

/// A caller's point back into the model's (checked: finite, flag 0/1).
fn rust_point(p: &TweezersPoint, i: usize) -> Result<Point> {
    let name = |f: &str| format!("points[{i}].{f}");
    for (f, v) in [
        ("turns", p.turns),
        ("extension", p.extension),
        ("torque", p.torque),
        ("twist", p.twist),
        ("writhe", p.writhe),
        ("plectoneme_length", p.plectoneme_length),
        ("plectonemes", p.plectonemes),
        ("buckled_probability", p.buckled_probability),
        ("extension_unbuckled", p.extension_unbuckled),
        ("extension_buckled", p.extension_buckled),
        ("superhelix_radius", p.superhelix_radius),
        ("superhelix_angle", p.superhelix_angle),
        ("free_energy", p.free_energy),
    ] {
        error::finite(&name(f), v)?;
    }
    let buckled = flag(&name("has_buckled"), p.has_buckled)?;
    let in_range = flag(&name("in_range"), p.in_range)?;
    Ok(Point {
        turns: p.turns,
        extension: p.extension,
        torque: p.torque,
        twist: p.twist,
        writhe: p.writhe,
        plectoneme_length: p.plectoneme_length,
        plectonemes: p.plectonemes,
        buckled_probability: p.buckled_probability,
        extension_unbuckled: p.extension_unbuckled,
        extension_buckled: buckled.then_some(p.extension_buckled),
        superhelix_radius: p.superhelix_radius,
        superhelix_angle: p.superhelix_angle,
        free_energy: p.free_energy,
        in_range,
    })
}

/// Fill `spec` with the defaults above.
#[no_mangle]
pub unsafe extern "C" fn rodkit_tweezers_spec_default(spec: *mut TweezersSpec) -> i32 {
    guard(|| {
        *arg_mut("spec", spec)? = spec_default();
        Ok(Status::Ok)
    })
}

/// Validate the spec and tabulate its phases (the superhelix's optimum at
/// ~25 torques, milliseconds to a few tenths of a second): `*out` receives
/// a handle to free with rodkit_tweezers_free (NULL on every failure).
/// Failures: a field out of range (its name as `spec.<field>` in the
/// message), RODKIT_STATUS_ERR_NOT_CONVERGED when the scene has no
/// plectoneme (no superhelix coexists with the extended chain below its
/// instability torque, e.g. at too high a force for the salt).
#[no_mangle]
pub unsafe extern "C" fn rodkit_tweezers_new(spec: *const TweezersSpec, out: *mut *mut Tweezers) -> i32 {
    guard(|| {
        let out = arg_mut("out", out)?;
        *out = std::ptr::null_mut();
        let scene = scene_of(arg_ref("spec", spec)?).map_err(|e| qualify_argument(e, "spec."))?;
        let model = Model::new(&scene).map_err(|e| qualify_argument(e, "spec."))?;
        let end_loop = match model.end_loop_used() {
            EndLoopUsed::Table => TweezersEndLoop::BuiltinTable,
            EndLoopUsed::Elastic => TweezersEndLoop::Elastic,
            EndLoopUsed::Value => TweezersEndLoop::Value,
            EndLoopUsed::Computed => TweezersEndLoop::Computed,
        };
        *out = Box::into_raw(Box::new(Tweezers { model, end_loop }));
        Ok(Status::Ok)
    })
}

/// The default turns of a curve: `points` (2 … 1e6) values evenly from 0
/// to twice the buckling turns into `turns` (the buckling point is located
/// first: ~0.1 s). Failures: RODKIT_STATUS_ERR_OUT_OF_RANGE for `points`,
/// RODKIT_STATUS_ERR_NOT_CONVERGED when the molecule does not buckle.
/// cbindgen:fortran-arrays=[turns]
#[no_mangle]
pub unsafe extern "C" fn rodkit_tweezers_default_turns(tweezers: *const Tweezers, points: i64, turns: *mut f64) -> i32 {
    guard(|| {
        let t = arg_ref("tweezers", tweezers)?;
        error::count_in_range("points", points, 2, 1_000_000)?;
        let out = out_slice("turns", turns, points)?;
        let values = t.model.default_turns(points as usize)?;
        out.copy_from_slice(&values);
        Ok(Status::Ok)
    })
}

/// The thermal curve at `n` turns (each finite and ≥ 0, any order) into
/// `points[0 … n−1]`. Sized first: a call whose thermal sums would exceed
/// 2e8 state evaluations (n × max_plectonemes × ~250: 6 to 20 s) is
/// refused with RODKIT_STATUS_ERR_WORK_LIMIT, its cost in the message,
/// before anything is computed. Writes nothing on failure.
/// cbindgen:fortran-arrays=[turns, points]
#[no_mangle]
pub unsafe extern "C" fn rodkit_tweezers_curve(
    tweezers: *const Tweezers,
    turns: *const f64,
    n: i64,
    points: *mut TweezersPoint,
) -> i32 {
    guard(|| {
        let t = arg_ref("tweezers", tweezers)?;
        error::dimension("n", n, 1, i64::MAX / 1024)?;
        check_work(n, t.model.scene.max_plectonemes)?;
        let turns = in_slice("turns", turns, n)?;
        if let Some(i) = turns.iter().position(|&v| v < 0.0) {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!(
                    "argument `turns[{i}]` out of range: must be ≥ 0 (got {:e}): the model covers positive supercoiling",
                    turns[i]
                ),
            ));
        }
        let out = out_slice("points", points, n)?;
        let curve = t.model.curve(turns)?;
        let converted: Vec<TweezersPoint> = curve.iter().map(c_point).collect();
        for (i, p) in converted.iter().enumerate() {
            error::finite_result(
                &format!("the curve's point {i} ({} turns)", p.turns),
                &[
                    p.extension,
                    p.torque,
                    p.twist,
                    p.writhe,
                    p.plectoneme_length,
                    p.plectonemes,
                    p.buckled_probability,
                    p.extension_unbuckled,
                    p.extension_buckled,
                    p.superhelix_radius,
                    p.superhelix_angle,
                    p.free_energy,
                ],
            )?;
        }
        out.copy_from_slice(&converted);
        Ok(Status::Ok)
    })
}

/// The summary of a curve computed by rodkit_tweezers_curve on this handle
/// (`n` ≥ 2 points, turns ascending from exactly 0, e.g. the default
/// turns) into `*out`. Failures: RODKIT_STATUS_ERR_OUT_OF_RANGE when the
/// curve does not start at 0 turns or has fewer than 3 points on the
/// plectonemic range (extend it: the message says how many it has),
/// RODKIT_STATUS_ERR_NOT_CONVERGED when the molecule does not buckle.
/// cbindgen:fortran-arrays=[points]
#[no_mangle]
pub unsafe extern "C" fn rodkit_tweezers_summary(
    tweezers: *const Tweezers,
    points: *const TweezersPoint,
    n: i64,
    out: *mut TweezersInfo,
) -> i32 {
    guard(|| {
        let t = arg_ref("tweezers", tweezers)?;
        error::dimension("n", n, 2, i64::MAX / 1024)?;
        let out = arg_mut("out", out)?;
        if points.is_null() {
            return Err(null_error("points"));
        }
        let input = std::slice::from_raw_parts(points, n as usize);
        let curve = input.iter().enumerate().map(|(i, p)| rust_point(p, i)).collect::<Result<Vec<_>>>()?;
        if let Some(i) = curve.windows(2).position(|w| !(w[1].turns > w[0].turns)) {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!(
                    "argument `points[{}].turns` out of range: the turns must ascend (got {:e} after {:e})",
                    i + 1,
                    curve[i + 1].turns,
                    curve[i].turns
                ),
            ));
        }
        let s = t.model.summarise(&curve)?;
        let m = &t.model;
        let summary = TweezersInfo {
            model: if m.scene.kt > 0.0 {
                SupercoilModel::ThermalTwoPhase
            } else {
                SupercoilModel::ZeroTemperatureTwoPhase
            },
            end_loop: t.end_loop,
            kt: m.scene.kt,
            buckling_turns: s.buckling_turns,
            buckling_torque: s.buckling_torque,
            plateau_torque: s.plateau_torque,
            plateau_torque_min: s.plateau_torque_min,
            plateau_torque_max: s.plateau_torque_max,
            overshoot: s.overshoot,
            coexistence_torque: s.coexistence_torque,
            slope: s.slope,
            extension_jump: s.extension_jump,
            extension_zero_turns: s.extension_zero_turns,
            superhelix_radius: s.superhelix_radius,
            superhelix_angle: s.superhelix_angle,
            end_loop_energy: s.end_loop_energy,
            end_loop_correction: s.end_loop_correction,
            plateau_turns_from: s.plateau_turns.0,
            plateau_turns_to: s.plateau_turns.1,
            plateau_points: s.plateau_points as i64,
            table_error: m.table_error,
        };
        error::finite_result(
            "the summary",
            &[
                summary.buckling_turns,
                summary.buckling_torque,
                summary.plateau_torque,
                summary.plateau_torque_min,
                summary.plateau_torque_max,
                summary.overshoot,
                summary.coexistence_torque,
                summary.slope,
                summary.extension_jump,
                summary.extension_zero_turns,
                summary.superhelix_radius,
                summary.superhelix_angle,
                summary.end_loop_energy,
                summary.end_loop_correction,
                summary.plateau_turns_from,
                summary.plateau_turns_to,
                summary.table_error,
            ],
        )?;
        *out = summary;
        Ok(Status::Ok)
    })
}

/// Write `n` points of a curve (as rodkit_tweezers_curve filled them) to
/// `path` as CSV through the library's writer: a header row (turns,
/// extension_nm, torque_pNnm, twist, writhe, plectoneme_length_nm,
/// plectonemes, buckled_probability, extension_unbuckled_nm,
/// extension_buckled_nm — empty where has_buckled is 0 —,
/// superhelix_radius_nm, superhelix_angle_rad, free_energy_pNnm, in_range,
/// model_kt_pNnm), then one row per point; written atomically, nothing on
/// failure.
///
/// `kt` is the model's kT (pN nm, as RodkitTweezersInfo.kt), written in
/// every row so the file says which model made it.
///
/// # Safety
/// `points` an array of `n` points, `path` a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn rodkit_tweezers_write_csv(
    points: *const TweezersPoint,
    n: i64,
    kt: f64,
    path: *const std::ffi::c_char,
) -> i32 {
    guard(|| {
        error::dimension("n", n, 1, i64::MAX / 1024)?;
        error::finite("kt", kt)?;
        if kt < 0.0 {
            return Err(Error::new(Status::ErrOutOfRange, format!("argument `kt` must be ≥ 0 (got {kt:e})")));
        }
        if points.is_null() {
            return Err(null_error("points"));
        }
        let path = super::args::path_arg(path)?;
        let input = std::slice::from_raw_parts(points, n as usize);
        let curve = input.iter().enumerate().map(|(i, p)| rust_point(p, i)).collect::<Result<Vec<_>>>()?;
        crate::tweezers::write_csv(&path, &curve, kt)?;
        Ok(Status::Ok)
    })
}

/// Free a handle (NULL is ignored).
#[no_mangle]
pub unsafe extern "C" fn rodkit_tweezers_free(tweezers: *mut Tweezers) {
    guard_value((), || free_handle(tweezers));
}

#[cfg(test)]
mod tests {
    /// c-api.md: every export runs inside the guard (as mod.rs's
    /// `every_export_is_guarded` checks for the other files). Reference:
    /// this file's source.
    #[test]
    fn every_tweezers_export_is_guarded() {
        let src = include_str!("tweezers.rs");
        let mut exports = 0;
        for chunk in src.split("extern \"C\" fn ").skip(1) {
            exports += 1;
            let name = chunk.split('(').next().unwrap();
            let body = chunk.split("\n}\n").next().unwrap();
            assert!(body.contains("guard(") || body.contains("guard_value("), "{name} does not run inside guard()");
        }
        // The file's seven exports (spec_default, new, default_turns, curve,
        // summary, write_csv, free): the split found them all.
        assert_eq!(exports, 7);
    }
}

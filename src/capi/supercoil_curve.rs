//! A supercoiling run's equilibrium curve from C and Fortran: the energy
//! and stability of every point, and the summary a force × salt map
//! compares (instability, coexistence, plateau torque, slope dz/dn,
//! superhelix radius), each quantity with a RodkitSummaryFinding that
//! says whether it was determined. Both wrap `charged::coexistence` and
//! `charged::summary`; each call computes the curve afresh (the energies
//! of every point: both calls together took 1.8 s on a 621-point 1 kbp
//! path, 0.1 s on a 300 bp one).

use super::args::{arg_mut, arg_ref, copy_out};
use super::guard;
use super::supercoil::Supercoil;
use crate::charged::coexistence::{equilibrium_curve, EquilibriumCurve, Kind};
use crate::charged::dna::SupercoilRun;
use crate::charged::summary::{summarise_with, Finding, Summarised};
use crate::error::{Error, Result};
use crate::status::Status;

/// Whether a quantity of RodkitSupercoilCurveInfo was determined.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SummaryFinding {
    /// Determined by the equilibrium curve; its fields hold it.
    Found = 1,
    /// Measured on the computed branch whose stability could not be
    /// decided (a bifurcation on the buckled branch): its fields hold the
    /// branch's numbers, not known to be what an experiment sees.
    Unverified = 2,
    /// Stability unknown where it would be decided (or a torque-clamp
    /// run); its fields are 0.
    Undetermined = 3,
    /// The run ended before it exists; its fields are 0.
    NotReached = 4,
}

/// The stability of a point of the path at fixed end rotation.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StabilityKind {
    /// Stable and the lowest state at its turns (the default curve).
    Lowest = 1,
    /// Stable, but another stable state at the same turns is lower.
    Metastable = 2,
    /// A saddle (at least one negative mode).
    Unstable = 3,
    /// The stability rules do not decide.
    Undetermined = 4,
}

/// One point of the equilibrium curve (the order of rodkit_supercoil_points).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SupercoilCurvePoint {
    /// Turns, extension (nm), torque (pN nm) as rodkit_supercoil_points.
    pub turns: f64,
    pub extension: f64,
    pub torque: f64,
    /// G = E_elastic + E_electrostatic + E_hard_core − F z(L) (pN nm); dG/dφ = torque.
    pub energy: f64,
    /// RodkitStabilityKind.
    pub kind: i32,
    /// Negative modes of G at fixed end rotation; −1: undetermined.
    pub negative_modes: i64,
    /// 0: straight branch, 1: buckled branch.
    pub branch: i32,
    /// The point's count of negative eigenvalues σ of the second variation
    /// in its window, the neutral ones included (their sign is within the
    /// model's approximations); −1 where the run did not count or the
    /// count is not certified.
    pub negative_sigma: i64,
    /// The window's σ within the neutral band (|σ| ≤ 3e-2 T²/K_b on a
    /// localised buckled state), counted apart from the unstable modes; −1
    /// where the run did not count.
    pub neutral_modes: i64,
    /// The σ nearest zero of the point's window (pN/nm²: force per length²
    /// of the metric ∫|δr|² ds; σ < 0 unstable), when `has_sigma` is 1; 0
    /// otherwise (no count, or no σ in the window). Where `negative_modes`
    /// and `negative_sigma` differ, this says how near zero the neutral
    /// modes are.
    pub sigma_nearest: f64,
    pub has_sigma: i32,
}

/// The summary of one curve. Every `*_finding` is a RodkitSummaryFinding;
/// the fields after it hold numbers only when it is FOUND or UNVERIFIED,
/// and are 0 otherwise (never NaN).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SupercoilCurveInfo {
    /// The straight rod's first buckling point (the instability): turns, torque (pN nm).
    pub instability_finding: i32,
    pub instability_turns: f64,
    pub instability_torque: f64,
    /// Where the straight rod's and the plectoneme's energies cross (both
    /// stable): turns, both torques (the straight rod's overshoots), both
    /// extensions (nm) and the jump z_straight − z_plectoneme.
    pub coexistence_finding: i32,
    pub coexistence_turns: f64,
    pub coexistence_torque_straight: f64,
    pub coexistence_torque_plectoneme: f64,
    pub coexistence_extension_straight: f64,
    pub coexistence_extension_plectoneme: f64,
    pub coexistence_extension_jump: f64,
    /// On the plectonemic leg beyond coexistence (FOUND), or on the buckled
    /// branch's last leg beyond the instability (UNVERIFIED): the
    /// φ-averaged torque (1/Δφ)∫M dφ, its min and max over the leg, the
    /// least-squares slope dz/dn (nm per turn), the leg's turns and nodes.
    pub plateau_finding: i32,
    pub plateau_torque: f64,
    pub plateau_torque_min: f64,
    pub plateau_torque_max: f64,
    pub slope: f64,
    pub plateau_turns_from: f64,
    pub plateau_turns_to: f64,
    pub plateau_nodes: i64,
    /// At the run's last point (on the buckled branch): half the closest
    /// approach of distinct strands (nm), the approach itself, the pair's
    /// arc lengths (nm), and the point's turns.
    pub superhelix_finding: i32,
    pub superhelix_radius: f64,
    pub strand_distance: f64,
    pub strand_s1: f64,
    pub strand_s2: f64,
    pub superhelix_turns: f64,
}

fn finding_code(f: Finding) -> i32 {
    (match f {
        Finding::Found => SummaryFinding::Found,
        Finding::Unverified => SummaryFinding::Unverified,
        Finding::Undetermined => SummaryFinding::Undetermined,
        Finding::NotReached => SummaryFinding::NotReached,
    }) as i32
}

/// The finding's code and the value when there is one.
fn split<T: Copy>(q: &Summarised<T>) -> (i32, Option<T>) {
    (finding_code(q.finding), q.value)
}

/// The run's equilibrium curve, refused when a point's energy is not
/// finite (a state the fuzzer drove past what doubles hold): NaN and
/// infinities never leave the library.
fn finite_curve(run: &SupercoilRun) -> Result<EquilibriumCurve> {
    let curve = equilibrium_curve(run)?;
    if let Some(p) = curve.points.iter().find(|p| !p.energy.is_finite()) {
        return Err(Error::new(
            Status::ErrNonFiniteResult,
            format!("the energy of point {} ({} turns) is not finite ({})", p.index, p.turns, p.energy),
        ));
    }
    Ok(curve)
}

/// The summary of the run (its equilibrium curve is computed here: the
/// energies of every point). Statuses: 0, or a failure of that computation
/// (its message in rodkit_last_error_message), RODKIT_STATUS_ERR_NON_FINITE_RESULT
/// when a point's energy is not finite.
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_curve_summary(run: *const Supercoil, out: *mut SupercoilCurveInfo) -> i32 {
    guard(|| {
        let r = &arg_ref("run", run)?.run;
        let out = arg_mut("out", out)?;
        // A torque clamp's run has no stability rules: no curve.
        let curve = if r.rod.torqued() { None } else { Some(finite_curve(r)?) };
        let s = summarise_with(r, curve.as_ref());
        let mut c = SupercoilCurveInfo::default();
        let (f, v) = split(&s.instability);
        c.instability_finding = f;
        if let Some(v) = v {
            (c.instability_turns, c.instability_torque) = (v.turns, v.torque);
        }
        let (f, v) = split(&s.coexistence);
        c.coexistence_finding = f;
        if let Some(v) = v {
            c.coexistence_turns = v.turns;
            (c.coexistence_torque_straight, c.coexistence_torque_plectoneme) = (v.torque_straight, v.torque_plectoneme);
            c.coexistence_extension_straight = v.extension_straight;
            c.coexistence_extension_plectoneme = v.extension_plectoneme;
            c.coexistence_extension_jump = v.extension_jump;
        }
        let (f, v) = split(&s.plateau);
        c.plateau_finding = f;
        if let Some(v) = v {
            (c.plateau_torque, c.plateau_torque_min, c.plateau_torque_max) = (v.torque, v.torque_min, v.torque_max);
            (c.slope, c.plateau_turns_from, c.plateau_turns_to) = (v.slope, v.turns_from, v.turns_to);
            c.plateau_nodes = v.nodes as i64;
        }
        let (f, v) = split(&s.superhelix);
        c.superhelix_finding = f;
        if let Some(v) = v {
            (c.superhelix_radius, c.strand_distance) = (v.radius, v.distance);
            (c.strand_s1, c.strand_s2, c.superhelix_turns) = (v.s1, v.s2, v.turns);
        }
        *out = c;
        Ok(Status::Ok)
    })
}

/// Copy the equilibrium curve's points (at most `capacity`; `*count`
/// receives their number, that of rodkit_supercoil_points;
/// RODKIT_STATUS_INFO_TRUNCATED when they did not fit). Rotation control
/// only: a torque-clamp run gives RODKIT_STATUS_ERR_OUT_OF_RANGE (its
/// stability is not determined), RODKIT_STATUS_ERR_NON_FINITE_RESULT when a
/// point's energy is not finite.
/// cbindgen:fortran-arrays=[points]
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_curve_points(
    run: *const Supercoil,
    points: *mut SupercoilCurvePoint,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let r = &arg_ref("run", run)?.run;
        arg_mut("count", count)?;
        let curve = finite_curve(r)?;
        copy_out("points", points, capacity, count, &curve.points, |p| {
            let stability = crate::charged::coexistence::point_stability(r, p.index);
            let nearest = stability.and_then(|s| s.sigma.first().copied()).filter(|v| v.is_finite());
            SupercoilCurvePoint {
                turns: p.turns,
                extension: p.extension,
                torque: p.torque,
                energy: p.energy,
                kind: (match p.kind {
                    Kind::Lowest => StabilityKind::Lowest,
                    Kind::Metastable => StabilityKind::Metastable,
                    Kind::Unstable => StabilityKind::Unstable,
                    Kind::Undetermined => StabilityKind::Undetermined,
                }) as i32,
                negative_modes: p.negative_modes.map_or(-1, |m| m as i64),
                branch: p.branch as i32,
                negative_sigma: stability.and_then(|s| s.negative).map_or(-1, |m| m as i64),
                neutral_modes: stability.map_or(-1, |s| s.marginal as i64),
                sigma_nearest: nearest.unwrap_or(0.0),
                has_sigma: nearest.is_some() as i32,
            }
        })
    })
}

//! One supercoiling curve in the numbers a magnetic-tweezers map compares:
//! the instability (buckling) point, the coexistence of the straight rod
//! and the plectoneme, the plateau torque, the slope dz/dn of the
//! plectonemic leg and the superhelix radius.
//!
//! Every quantity carries a [`Finding`]: a number is given only when the
//! curve determines it ([`Finding::Found`]), or — for the plateau and the
//! slope — when it is read off a computed branch whose stability the rules
//! of [`super::coexistence`] could not decide ([`Finding::Unverified`],
//! flagged as such). Otherwise the quantity is [`Finding::Undetermined`]
//! or [`Finding::NotReached`] and carries no value: no quantity is made up,
//! and no NaN is returned.

use super::coexistence::{equilibrium_curve, EquilibriumCurve};
use super::dna::SupercoilRun;
use crate::error::Result;
use crate::geometry::vec3::distance;

/// How far a quantity of the summary is determined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Finding {
    /// Determined by the equilibrium curve.
    Found,
    /// Measured on the computed branch, but the stability rules did not
    /// decide whether that branch is stable there (a bifurcation on the
    /// buckled branch): the number is the branch's, not known to be the
    /// state an experiment sees.
    Unverified,
    /// The run went far enough, but its stability is unknown where the
    /// quantity would be decided (or the run is torque-controlled, whose
    /// stability rules are not implemented).
    Undetermined,
    /// The run ended before the quantity exists (no buckling point, no
    /// stable plectoneme crossing the straight rod, a straight last point).
    NotReached,
}

/// A quantity with its finding: `value` is Some exactly when the finding
/// is [`Finding::Found`] or [`Finding::Unverified`].
#[derive(Clone, Debug, PartialEq)]
pub struct Summarised<T> {
    pub finding: Finding,
    pub value: Option<T>,
}

impl<T> Summarised<T> {
    fn found(value: T) -> Self {
        Summarised { finding: Finding::Found, value: Some(value) }
    }

    fn without(finding: Finding) -> Self {
        Summarised { finding, value: None }
    }
}

/// The first buckling point of the straight rod (the end of its stable
/// range: the instability).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instability {
    pub turns: f64,
    /// End torque there (pN nm).
    pub torque: f64,
}

/// The coexistence point ([`super::coexistence::Coexistence`]) as a map
/// reports it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoexistencePoint {
    pub turns: f64,
    /// The straight rod's torque (the overshoot) and the plectoneme's (pN nm).
    pub torque_straight: f64,
    pub torque_plectoneme: f64,
    /// Extensions (nm) of both states and the jump z_straight − z_plectoneme.
    pub extension_straight: f64,
    pub extension_plectoneme: f64,
    pub extension_jump: f64,
}

/// The plectonemic leg a plateau torque and slope are measured on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plateau {
    /// The φ-average of the torque over the leg, (1/Δφ)∫M dφ by the
    /// trapezoid rule on its nodes (pN nm); = ΔG/Δφ along the leg, since
    /// dG/dφ = M there ([`super::coexistence`]).
    pub torque: f64,
    /// The torque's range over the leg's nodes: how flat the plateau is.
    pub torque_min: f64,
    pub torque_max: f64,
    /// Least-squares slope dz/dn of extension (nm) vs turns over the nodes
    /// (nm per turn, negative for a growing plectoneme).
    pub slope: f64,
    /// The leg's range in turns and its number of nodes (≥ 3).
    pub turns_from: f64,
    pub turns_to: f64,
    pub nodes: usize,
}

/// The superhelix of the last point: the closest approach of distinct
/// strands ([`strand_approach`]) and half of it, the superhelix radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Superhelix {
    /// Half the closest approach (nm): the radius of the superhelix on
    /// which the two strands' axes lie.
    pub radius: f64,
    /// The closest approach (nm) and the pair's arc lengths (nm).
    pub distance: f64,
    pub s1: f64,
    pub s2: f64,
    /// Turns of the point it is measured at (the run's last).
    pub turns: f64,
}

/// The summary of one supercoiling curve.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveSummary {
    pub instability: Summarised<Instability>,
    pub coexistence: Summarised<CoexistencePoint>,
    /// Plateau torque and slope dz/dn, measured on one leg.
    pub plateau: Summarised<Plateau>,
    pub superhelix: Summarised<Superhelix>,
    /// Why the coexistence point is not found (the equilibrium curve's
    /// reason), None when it is.
    pub note: Option<String>,
}

/// The summary of `run` (any control; its own equilibrium curve is
/// computed when the run is rotation-controlled, see [`summarise_with`]).
pub fn summarise(run: &SupercoilRun) -> Result<CurveSummary> {
    let curve = if run.rod.torqued() { None } else { Some(equilibrium_curve(run)?) };
    Ok(summarise_with(run, curve.as_ref()))
}

/// The summary of `run` given its equilibrium curve (None: a torque clamp's
/// run, whose stability is not determined).
///
/// - **Instability**: the located first buckling point (turns, torque).
/// - **Coexistence**: the curve's [`super::coexistence::Coexistence`];
///   without one, Undetermined when some buckled point's stability is
///   unknown (the crossing may lie there) or the curve is missing, else
///   NotReached (no buckling point, or no stable plectoneme overlapping and
///   crossing the straight rod within the run).
/// - **Plateau torque and slope** (Found): on the plectonemic leg of the
///   lowest curve beyond the coexistence point — the coexistence point
///   itself (φ_c, the plectoneme's interpolated torque and extension) and
///   the leg's path points past it, at least 3 nodes. The plateau torque is
///   the φ-average of M over that leg, (1/Δφ)∫M dφ = ΔG/Δφ. In the
///   two-phase picture (J. F. Marko, Phys. Rev. E 76, 021926 (2007)) the
///   plectoneme's torque is constant, τ_p, equal to the plectoneme's torque
///   at coexistence, while the straight rod there overshoots it by
///   √(2Cε/L) (ε the end-loop energy); on a short rod the computed
///   plectoneme's torque still rises along the leg (300 bp, 1 pN, 0.1 M:
///   8.2 → 14 pN nm, tests/supercoil_energy.rs), so the average lies above
///   `torque_plectoneme` and `torque_min`/`torque_max` say by how much.
///   (Unverified): when the coexistence is Undetermined, the same numbers
///   on the buckled branch's last leg monotone in φ (past its last fold),
///   over its points beyond the instability turns (where the straight rod
///   is no longer stable), at least 3. Else NotReached / Undetermined with
///   the coexistence.
/// - **Superhelix radius**: half the closest approach of distinct strands
///   ([`strand_approach`]) at the run's last point, when that point is on
///   the buckled branch and two strands approach; else NotReached.
pub fn summarise_with(run: &SupercoilRun, curve: Option<&EquilibriumCurve>) -> CurveSummary {
    let instability = match run.buckling {
        Some((phi, torque)) => Summarised::found(Instability { turns: phi / std::f64::consts::TAU, torque }),
        None => Summarised::without(Finding::NotReached),
    };
    let (coexistence, note) = coexistence_of(run, curve);
    let plateau = match (coexistence.finding, curve) {
        (Finding::Found, Some(curve)) => match plectoneme_nodes(curve) {
            Some(nodes) => Summarised::found(plateau_over(&nodes)),
            None => Summarised::without(Finding::NotReached),
        },
        (Finding::Undetermined, _) => match branch_tail(run) {
            Some(nodes) => Summarised { finding: Finding::Unverified, value: Some(plateau_over(&nodes)) },
            None => Summarised::without(Finding::Undetermined),
        },
        (finding, _) => Summarised::without(finding),
    };
    // Distinct, increasing φ at the nodes keeps every number finite; a
    // non-finite one (a state gone bad) is reported as undetermined.
    let plateau = match plateau.value {
        Some(p) if ![p.torque, p.torque_min, p.torque_max, p.slope].iter().all(|v| v.is_finite()) => {
            Summarised::without(Finding::Undetermined)
        }
        _ => plateau,
    };
    CurveSummary { instability, coexistence, plateau, superhelix: superhelix_of(run), note }
}

/// The coexistence quantity and, without it, why.
fn coexistence_of(
    run: &SupercoilRun,
    curve: Option<&EquilibriumCurve>,
) -> (Summarised<CoexistencePoint>, Option<String>) {
    if run.buckling.is_none() {
        return (Summarised::without(Finding::NotReached), Some("no buckling point reached".into()));
    }
    let Some(curve) = curve else {
        let why = "the run followed the end torque: its stability is not determined";
        return (Summarised::without(Finding::Undetermined), Some(why.into()));
    };
    if let Some(c) = curve.coexistence {
        let point = CoexistencePoint {
            turns: c.turns,
            torque_straight: c.torque_straight,
            torque_plectoneme: c.torque_plectoneme,
            extension_straight: c.extension_straight,
            extension_plectoneme: c.extension_plectoneme,
            extension_jump: c.extension_straight - c.extension_plectoneme,
        };
        return (Summarised::found(point), None);
    }
    let unknown = curve.points.iter().any(|p| p.branch == 1 && p.negative_modes.is_none());
    let finding = if unknown { Finding::Undetermined } else { Finding::NotReached };
    let mut note = curve.note.clone().unwrap_or_default();
    if unknown {
        let from = curve.points.iter().find(|p| p.negative_modes.is_none()).map_or(0.0, |p| p.turns);
        note = format!("{note}; stability undetermined on the buckled branch from {from:.4} turns");
    }
    (Summarised::without(finding), Some(note))
}

/// A node of a leg: (φ, turns, torque, extension).
type Node = (f64, f64, f64, f64);

/// The coexistence point and the plectoneme leg's points beyond it (≥ 3
/// nodes in all), by increasing φ.
fn plectoneme_nodes(curve: &EquilibriumCurve) -> Option<Vec<Node>> {
    let c = curve.coexistence?;
    let leg = &curve.legs[c.plectoneme_leg];
    let mut nodes = vec![(c.phi, c.turns, c.torque_plectoneme, c.extension_plectoneme)];
    let mut beyond: Vec<Node> = curve.points[leg.first..=leg.last]
        .iter()
        .filter(|p| p.phi > c.phi)
        .map(|p| (p.phi, p.turns, p.torque, p.extension))
        .collect();
    beyond.sort_by(|a, b| a.0.total_cmp(&b.0));
    nodes.extend(beyond);
    (nodes.len() >= 3).then_some(nodes)
}

/// The buckled branch's last leg monotone (increasing) in φ, its points
/// beyond the instability turns (≥ 3).
fn branch_tail(run: &SupercoilRun) -> Option<Vec<Node>> {
    let (phi_b, _) = run.buckling?;
    let ns = run.points.iter().take_while(|p| p.branch == 0).count();
    let b = &run.points[ns..];
    let mut start = b.len().checked_sub(1)?;
    while start > 0 && b[start - 1].phi < b[start].phi {
        start -= 1;
    }
    let nodes: Vec<Node> = b[start..]
        .iter()
        .filter(|p| p.phi >= phi_b)
        .map(|p| (p.phi, p.observables.turns, p.observables.torque, p.observables.extension))
        .collect();
    (nodes.len() >= 3).then_some(nodes)
}

/// Plateau torque, torque range and least-squares slope over `nodes` (≥ 3,
/// increasing φ).
fn plateau_over(nodes: &[Node]) -> Plateau {
    let work: f64 = nodes.windows(2).map(|w| 0.5 * (w[0].2 + w[1].2) * (w[1].0 - w[0].0)).sum();
    let (first, last) = (nodes[0], nodes[nodes.len() - 1]);
    let n = nodes.len() as f64;
    let (mx, my) = (nodes.iter().map(|p| p.1).sum::<f64>() / n, nodes.iter().map(|p| p.3).sum::<f64>() / n);
    let sxy: f64 = nodes.iter().map(|p| (p.1 - mx) * (p.3 - my)).sum();
    let sxx: f64 = nodes.iter().map(|p| (p.1 - mx).powi(2)).sum();
    Plateau {
        torque: work / (last.0 - first.0),
        torque_min: nodes.iter().map(|p| p.2).fold(f64::INFINITY, f64::min),
        torque_max: nodes.iter().map(|p| p.2).fold(f64::NEG_INFINITY, f64::max),
        slope: sxy / sxx,
        turns_from: first.1,
        turns_to: last.1,
        nodes: nodes.len(),
    }
}

/// The superhelix of the run's last point.
fn superhelix_of(run: &SupercoilRun) -> Summarised<Superhelix> {
    let (Some(last), Some(x)) = (run.points.last(), run.states.last()) else {
        return Summarised::without(Finding::NotReached);
    };
    if last.branch != 1 {
        return Summarised::without(Finding::NotReached);
    }
    let profile = run.rod.profile_offsets();
    let r: Vec<[f64; 3]> = profile.iter().map(|&(_, o)| [x[o], x[o + 1], x[o + 2]]).collect();
    let s: Vec<f64> = profile.iter().map(|p| p.0).collect();
    match strand_approach(&r, &s) {
        Some((d, i, j)) => Summarised::found(Superhelix {
            radius: 0.5 * d,
            distance: d,
            s1: s[i],
            s2: s[j],
            turns: last.observables.turns,
        }),
        None => Summarised::without(Finding::NotReached),
    }
}

/// The closest approach of distinct strands of a curve sampled at points
/// `r` with arc lengths `s` (increasing): the smallest |r_i − r_j| over the
/// pairs i < j where the distance from r_i, walked along the curve from i,
/// has already passed a maximum before j — the curve went away from r_i
/// and came back, so r_j lies on another strand (a plectoneme's opposite
/// strand, the far side of a loop), not on r_i's own stretch, whose
/// distance from r_i only grows. No arc-length gap is needed, so a tight
/// end loop does not count as an approach. Returns (distance, i, j), None
/// when the curve never comes back (a straight or gently bent rod).
pub fn strand_approach(r: &[[f64; 3]], s: &[f64]) -> Option<(f64, usize, usize)> {
    debug_assert_eq!(r.len(), s.len());
    let mut best: Option<(f64, usize, usize)> = None;
    for i in 0..r.len() {
        let mut farthest = 0.0_f64;
        let mut receded = false;
        for j in i + 1..r.len() {
            let d = distance(&r[i], &r[j]);
            if d < farthest {
                receded = true;
            }
            farthest = farthest.max(d);
            if receded && best.is_none_or(|(bd, _, _)| d < bd) {
                best = Some((d, i, j));
            }
        }
    }
    best
}

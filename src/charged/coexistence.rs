//! The equilibrium curve of a supercoiling path: the energy of every
//! point, its stability at fixed end rotation, and the curve an experiment
//! that stays in the lowest-energy state would follow, with the jump at
//! the coexistence of the straight rod and the plectoneme.
//!
//! **Energy.** At fixed tension F and fixed end rotation φ (magnetic
//! tweezers: the clamp holds φ, the magnet pulls with a constant force) the
//! equilibria of the charged Kirchhoff rod (physics.md §3.1, §3.4) are the
//! critical points of the potential energy
//!
//!   G[x; φ] = E_elastic + E_near + E_far + E_hard − F z(L)                 (1)
//!
//! over the shapes x that satisfy the clamps with end rotation φ: the
//! elastic energy ½∫(K_b(u1² + u2²) + C u3²) ds, the electrostatic energy
//! ½∫∫λ²Φ(|r(s) − r(t)|) ds dt split into its near zone and far pairs
//! (physics.md §3.1–3.2), the optional hard core, and the potential −F z(L)
//! of the dead load F on the end (a constant force is conservative: its
//! potential is minus its work, −F z). φ is a boundary condition, not a force, so no
//! −Mφ term: the torque M is the Lagrange multiplier of the end rotation,
//! and along any branch of equilibria dG/dφ = M (the work theorem — J. H.
//! Maddocks, Arch. Rational Mech. Anal. 99, 301 (1987), whose μ = ∂G/∂λ is
//! here the torque; checked for this rod in tests/charged_rod.rs,
//! `end_torque_is_the_derivative_of_the_energy`, and along whole paths in
//! tests/supercoil_energy.rs). (1) is the discrete energy of
//! [`ChargedRod::energy`] minus F z: the quantity whose stationarity the
//! collocation's residual expresses (up to its O(h⁴) non-variational part).
//!
//! **Stability** (rotation control). The number of negative modes of G's
//! second variation at fixed φ (the phase condition removing the buckled
//! branch's rotation about the axis, a zero mode) — i.e. 0 for a local
//! minimum. A run that counts them
//! ([`crate::charged::dna::SupercoilSettings::stability`], the default)
//! carries each point's count, from the eigenvalues nearest zero on its own
//! factorisation ([`crate::continuation::stability`], physics.md §3.4),
//! None where it is not certified; its neutral modes (near zero, their
//! sign within the model's own approximations) are not counted as
//! unstable — except where a fold in φ says which they are: a fold's
//! crossing mode inside the band is counted once it leaves the band below
//! zero, and undetermined while it stays in it
//! ([`hidden_fold_crossings`]). Without counts the number changes along a branch
//! only where the Jacobian is singular: at folds in φ and at bifurcations,
//! and these rules decide it ([`negative_modes`]):
//! - the straight rod has none up to its first buckling point, a double
//!   point (the rotational symmetry): `multiplicity` (2) beyond it;
//! - the buckled branch leaves the double point with one (the buckle's
//!   amplitude; the other zero mode becomes the rotation about the axis)
//!   when it leaves towards smaller φ (subcritical: it lies where the
//!   straight rod is stable and is the barrier between it and the buckled
//!   states), with none when it leaves towards larger φ (supercritical: the
//!   300 bp scene at 1 pN, 0.1 M, where its first point lies 7.1e-4 pN nm
//!   below the straight rod continued, as the torques predict);
//! - at a fold in φ the count changes by one, and (Maddocks 1987: the
//!   critical eigenvalue σ ∝ −dμ/dλ near a fold of the distinguished
//!   diagram, here μ = M, λ = φ) the leg with dM/dφ < 0 next to the fold is
//!   the more stable one. Derivation: with E_xx x' + E_xφ φ' = 0 along the
//!   branch and v the critical eigenvector (eigenvalue σ), vᵀ gives
//!   σ (v·x') = −(v·E_xφ) φ', while M' = E_φx·x' + E_φφ φ' ≈ (v·E_xφ)(v·x')
//!   next to the fold: σ ≈ −M' φ' / (v·x')², of the sign of −dM/dφ. In the
//!   (φ, G) plane the more stable leg is the lower one at the cusp.
//!
//! The rule is applied where the recorded sign of the Jacobian's
//! determinant (`Record::det_sign`) flips, which it does at folds and simple
//! bifurcations: a flip with a fold in φ next to it takes the fold rule; a
//! flip without one, a fold without a flip, a flip of the bordered
//! determinant (a simple bifurcation on the branch) or secant slopes that do
//! not resolve the fold leave the count undetermined from there on
//! ([`Kind::Undetermined`], never a guess).
//!
//! **Equilibrium curve.** The stable points of a branch between two changes
//! of stability or direction form a leg, monotone in φ, whose G(φ) is
//! interpolated by cubic Hermite with dG/dφ = M. A stable point is the
//! lowest state at its turns when no other stable leg is lower there, else
//! metastable; where two stable legs' energies cross, the lowest curve
//! jumps (a Maxwell point: at the crossing ∫M dφ along the path from one
//! state to the other vanishes, the equal-area rule). The jump from the
//! straight rod to a buckled leg is the coexistence point: a system that
//! finds its global minimum buckles there, and the straight rod's torque
//! there over the plectoneme's is the overshoot (J. F. Marko, Phys. Rev. E
//! 76, 021926 (2007); S. Forth et al., Phys. Rev. Lett. 100, 148301 (2008)).

use super::dna::SupercoilRun;
use super::rod::ChargedRod;
use crate::continuation::Record;
use crate::error::{Error, Result};
use crate::status::Status;

/// The potential energy (1) of every point of `run` (pN nm, the order of
/// `run.points`): E_elastic + E_near + E_far + E_hard − F z(L) with F the
/// scene's tension. The pair list is built at a point and reused for the
/// following ones while no stage has moved half the Verlet skin from where
/// it was built (the follower's own rule: the list then holds every pair
/// within the cutoff, so the energy does not depend on which list is used
/// beyond rounding); a point past that gets a new list. The run's control
/// does not matter: (1) is the energy at fixed φ whatever parameter the
/// path was followed in.
pub fn path_energies(run: &SupercoilRun) -> Result<Vec<f64>> {
    let tension = run.scene.tension;
    let half_skin = 0.5 * run.charge.skin;
    let mut list: Option<ChargedRod> = None;
    let mut out = Vec::with_capacity(run.states.len());
    for (x, p) in run.states.iter().zip(&run.points) {
        let stale = match &list {
            Some(l) => l.list_is_local() && l.displacement(x) > half_skin,
            None => true,
        };
        if stale {
            // The energy needs no phase condition: the rod's own unknowns.
            list = Some(ChargedRod::new(&run.rod, &run.charge, None, x)?);
        }
        let e = list.as_mut().expect("a list was built").energy(x);
        out.push(e.elastic + e.near + e.far + e.hard_core - tension * p.observables.extension);
    }
    Ok(out)
}

/// The energy (1) of one state `x` of `run`'s rod (the rod's unknowns, as
/// `run.states`) with a pair list built at `x` itself: the reference for
/// [`path_energies`]' reused lists, and the energy of a re-solved point.
pub fn state_energy(run: &SupercoilRun, x: &[f64]) -> Result<f64> {
    let n = run.rod.unknowns();
    let x = &x[..n.min(x.len())];
    let mut p = ChargedRod::new(&run.rod, &run.charge, None, x)?;
    let e = p.energy(x);
    Ok(e.elastic + e.near + e.far + e.hard_core - run.scene.tension * run.rod.tip(x)[2])
}

/// The stability counted at point `k` of `run` (the order of
/// `run.points`), None where the run did not count or has no such point.
pub fn point_stability(run: &SupercoilRun, k: usize) -> Option<&crate::continuation::stability::Stability> {
    let ns = run.straight.records.len();
    let rec = if k < ns { run.straight.records.get(k) } else { run.buckled.as_ref()?.records.get(k - ns) };
    rec?.stability.as_ref()
}

/// The records of `run`'s points, in the order of `run.points`.
fn records(run: &SupercoilRun) -> Vec<&Record> {
    let mut r: Vec<&Record> = run.straight.records.iter().collect();
    if let Some(b) = &run.buckled {
        r.extend(b.records.iter());
    }
    r
}

/// The number of negative modes of the second variation of (1) at fixed φ
/// at every point of `run` (the rules in the module documentation), None
/// where the rules do not determine it. Rotation control only: under a
/// torque clamp the recorded determinants are those of another problem
/// (whose folds are in M) and the run is refused.
pub fn negative_modes(run: &SupercoilRun) -> Result<Vec<Option<usize>>> {
    let mut out = parity_rules(run)?;
    // Counted on the point's own factors where the run counted
    // ([`crate::continuation::Options::stability`]): the count, None where
    // it was not certified. The rules stay for the points without one (a
    // switch's singular start) and for runs that did not count.
    let recs = records(run);
    for (o, rec) in out.iter_mut().zip(&recs) {
        if let Some(s) = &rec.stability {
            *o = s.unstable;
        }
    }
    let counts: Vec<Option<(usize, usize)>> =
        recs.iter().map(|r| r.stability.as_ref().and_then(|s| Some((s.negative?, s.unstable?)))).collect();
    let phi: Vec<f64> = run.points.iter().map(|p| p.phi).collect();
    let from = run.straight.records.len();
    for (o, hidden) in out.iter_mut().zip(hidden_fold_crossings(&phi, &counts, from)) {
        if let Some(mark) = hidden {
            *o = mark;
        }
    }
    carry_band_entries(&phi, &counts, &mut out, from);
    Ok(out)
}

/// Whether point `j` of a branch that starts at point `from` is a fold in
/// φ: φ_j an extremum of φ_{j−1}, φ_j, φ_{j+1} (the branch's first point,
/// where it leaves another branch, is none).
fn fold_at(phi: &[f64], from: usize, j: usize) -> bool {
    j > from && j + 1 < phi.len() && (phi[j] - phi[j - 1]) * (phi[j + 1] - phi[j]) < 0.0
}

/// Unstable modes that enter the neutral band from below stay counted:
/// between two points with as many negative σ (no sign changed) and no
/// fold, a point with fewer unstable modes than the point before's marks
/// has them inside the band, still negative — the band (the DNA scenes'
/// |σ| ≤ 3e-2 T²/K_b) is for modes whose sign flips within the model's
/// approximations, and these did not flip. The carried marks go on while
/// the negative count stays; where it changes while band modes are
/// carried (a σ crossed zero: the carried mode or another, which the
/// counts cannot tell), the point and the following ones with the same
/// counts are undetermined. A change of both counts with nothing carried
/// is a counted crossing and stands. On the 1 kbp, 1 pN, 0.1 M scene (170 ×
/// Gauss(2)) the buckled branch's mode at 3.77 turns (σ −1.2e-4 nm⁻²)
/// entered the band when the state became localised, and the returning
/// leg past the 10.011-turn fold carried its crossing mode into the band
/// at 8.24 turns: both were counted stable. `marks` are the points'
/// unstable counts so far (None: undetermined), changed in place.
pub fn carry_band_entries(phi: &[f64], counts: &[Option<(usize, usize)>], marks: &mut [Option<usize>], from: usize) {
    let n = phi.len().min(counts.len()).min(marks.len());
    let fold = |j: usize| fold_at(&phi[..n], from, j);
    let mut ambiguous: Option<(usize, usize)> = None;
    for k in from + 1..n {
        let (Some((n0, u0)), Some((n1, u1))) = (counts[k - 1], counts[k]) else {
            ambiguous = None;
            continue;
        };
        if marks[k] != Some(u1) {
            // The fold rule's mark stands.
            ambiguous = None;
            continue;
        }
        if ambiguous == Some((n1, u1)) && marks[k - 1].is_none() {
            marks[k] = None;
            continue;
        }
        ambiguous = None;
        let Some(carried) = marks[k - 1] else { continue };
        if carried <= u1 || fold(k - 1) || fold(k) {
            continue;
        }
        if n1 == n0 {
            marks[k] = Some(carried.min(n1));
        } else if carried > u0 {
            // Band modes were carried at k − 1 and a σ changed sign.
            marks[k] = None;
            ambiguous = Some((n1, u1));
        }
    }
}

/// The points whose counted stability a fold in φ contradicts, and what
/// they are: at a fold one σ of the fixed-φ second variation crosses zero
/// (the Jacobian at fixed φ is singular there), so the unstable counts on
/// its two sides differ by one. Where they do not, the crossing mode sat
/// in the neutral band ([`crate::continuation::stability::StabilityOptions::marginal`]),
/// counted in `negative` but not in `unstable`, and one side's count is
/// wrong: the side with more negative σ carries the crossing mode as a
/// neutral one (both sides when their negative counts agree: a crossing
/// missed altogether). That side's stretch runs from the fold while its
/// (negative, unstable) counts stay those next to the fold (with the fold
/// point when it has them too). Where the stretch ends in one more
/// unstable mode and as many negative ones, the crossing mode has left
/// the band below zero: it is that mode, and the stretch has one more
/// unstable mode (`Some(Some(u + 1))`). Otherwise — the mode went back
/// into or through the band, or the branch ended — its sign is within
/// what the band calls undecided and the stretch is undetermined
/// (`Some(None)`). `None`: the point's count stands. `counts` are each
/// point's (negative, unstable), None where not certified; the branch
/// starts at point `from` (its first point is no fold) and no stretch is
/// marked before it.
pub fn hidden_fold_crossings(
    phi: &[f64],
    counts: &[Option<(usize, usize)>],
    from: usize,
) -> Vec<Option<Option<usize>>> {
    let n = phi.len().min(counts.len());
    let mut hidden = vec![None; n];
    for j in from + 1..n.saturating_sub(1) {
        if !fold_at(&phi[..n], from, j) {
            continue;
        }
        let (Some((na, ua)), Some((nb, ub))) = (counts[j - 1], counts[j + 1]) else { continue };
        if ua.abs_diff(ub) == 1 {
            continue;
        }
        for (start, forward) in [(j - 1, false), (j + 1, true)] {
            let (ns, us) = if forward { (nb, ub) } else { (na, ua) };
            if ns < if forward { na } else { nb } {
                continue;
            }
            let mut stretch = vec![start];
            let mut k = start;
            let end = loop {
                let next = if forward { (k + 1 < n).then_some(k + 1) } else { (k > from).then_some(k - 1) };
                match next {
                    Some(m) if counts[m] == counts[start] => {
                        stretch.push(m);
                        k = m;
                    }
                    other => break other,
                }
            };
            if counts[j] == counts[start] {
                stretch.push(j);
            }
            let left_below = end.is_some_and(|m| counts[m] == Some((ns, us + 1)));
            let mark = if left_below { Some(us + 1) } else { None };
            for k in stretch {
                hidden[k] = Some(mark);
            }
        }
    }
    hidden
}

/// The stability rules in the module documentation, from the records'
/// determinant signs alone.
fn parity_rules(run: &SupercoilRun) -> Result<Vec<Option<usize>>> {
    if run.rod.torqued() {
        return Err(Error::new(
            Status::ErrOutOfRange,
            "the stability rules read the determinants of rotation control; this run followed the end torque",
        ));
    }
    let recs = records(run);
    let ns = run.straight.records.len();
    let mut out = Vec::with_capacity(run.points.len());
    // The straight rod: none up to the located buckling point, the double
    // point's multiplicity past it.
    let first = run.straight.bifurcations.first();
    for p in &run.points[..ns] {
        out.push(match (run.buckling, first) {
            (Some((phi_b, _)), Some(b)) if p.phi > phi_b => Some(b.multiplicity),
            _ => Some(0),
        });
    }
    if run.points.len() == ns {
        return Ok(out);
    }
    let phi_b = run.buckling.map(|(phi, _)| phi).unwrap_or(run.points[ns].phi);
    // Supercritical (leaves towards larger φ): none; subcritical: one.
    let mut modes = Some(if run.points[ns].phi >= phi_b { 0 } else { 1 });
    out.push(modes);
    let phis: Vec<f64> = run.points.iter().map(|p| p.phi).collect();
    let phi = |k: usize| phis[k];
    let torque = |k: usize| run.points[k].observables.torque;
    // A fold at j: φ_j an extremum of φ_{j−1}, φ_j, φ_{j+1} on the branch.
    let fold_at = |j: usize| fold_at(&phis, ns, j);
    let flip = |k: usize| k > ns && k < run.points.len() && recs[k].det_sign != recs[k - 1].det_sign;
    // A fold with no determinant flip next to it (two crossings within a
    // step, or a missed one) leaves the count undetermined from there.
    let unexplained = (ns + 1..run.points.len()).find(|&j| fold_at(j) && !flip(j) && !flip(j + 1));
    for k in ns + 1..run.points.len() {
        if recs[k].bordered_det_sign != recs[k - 1].bordered_det_sign || unexplained.is_some_and(|j| k >= j) {
            // A simple bifurcation on the buckled branch: not followed here.
            modes = None;
        } else if flip(k) {
            modes = match (modes, [k - 1, k].into_iter().find(|&j| fold_at(j))) {
                (Some(m), Some(j)) => {
                    let before = (torque(j) - torque(j - 1)) / (phi(j) - phi(j - 1));
                    let after = (torque(j + 1) - torque(j)) / (phi(j + 1) - phi(j));
                    if before.signum() == after.signum() || !before.is_finite() || !after.is_finite() {
                        None
                    } else if after < before {
                        // The leg after the fold is the more stable one.
                        m.checked_sub(1)
                    } else {
                        Some(m + 1)
                    }
                }
                // A flip without a fold: a bifurcation the rules do not cover.
                _ => None,
            };
        }
        out.push(modes);
    }
    Ok(out)
}

/// What a point of the equilibrium curve is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Stable, and no stable state at the same turns has a lower energy.
    Lowest,
    /// Stable, but another stable state at the same turns is lower.
    Metastable,
    /// At least one negative mode: a saddle of (1), not observed at rest.
    Unstable,
    /// The stability rules do not decide (a bifurcation on the buckled
    /// branch, an unresolved fold).
    Undetermined,
}

/// A point of the path on the equilibrium curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    /// End rotation φ (rad) and φ/2π.
    pub phi: f64,
    pub turns: f64,
    pub extension: f64,
    /// End torque (pN nm) = dG/dφ.
    pub torque: f64,
    /// The energy (1), pN nm.
    pub energy: f64,
    pub kind: Kind,
    /// Negative modes at fixed φ ([`negative_modes`]).
    pub negative_modes: Option<usize>,
    /// 0: straight, 1: buckled (as `PathPoint::branch`).
    pub branch: usize,
    /// Index into `run.points`.
    pub index: usize,
}

/// A stable leg: consecutive stable points of one branch, monotone in φ.
#[derive(Clone, Debug, PartialEq)]
pub struct Leg {
    /// 0: straight, 1: buckled.
    pub branch: usize,
    /// Its first and last point (indices into the curve's points, inclusive).
    pub first: usize,
    pub last: usize,
    /// The end rotations (rad) it covers, lo ≤ hi: its points', and on the
    /// straight rod up to the buckling point.
    pub phi_range: (f64, f64),
    /// Interpolation nodes, monotone in φ: the leg's points, and on the
    /// straight rod the first point past the buckling point (the branch is
    /// smooth through a bifurcation; only its stability changes there).
    nodes: Vec<usize>,
}

/// A leg's interpolated state at some φ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegValue {
    /// The energy (1): cubic Hermite in φ with dG/dφ = M at the nodes.
    pub energy: f64,
    /// dG/dφ of that interpolant.
    pub torque: f64,
    /// Linear in φ between the nodes.
    pub extension: f64,
}

impl Leg {
    /// The leg's state at end rotation `phi` (rad), None outside its range.
    pub fn at(&self, points: &[CurvePoint], phi: f64) -> Option<LegValue> {
        let (lo, hi) = self.phi_range;
        if !(phi >= lo && phi <= hi) {
            return None;
        }
        if self.nodes.len() == 1 {
            let p = &points[self.nodes[0]];
            return Some(LegValue { energy: p.energy, torque: p.torque, extension: p.extension });
        }
        // The node interval holding φ (nodes are monotone either way).
        let w = self.nodes.windows(2).find(|w| {
            let (a, b) = (points[w[0]].phi, points[w[1]].phi);
            phi >= a.min(b) && phi <= a.max(b)
        })?;
        let (p0, p1) = (&points[w[0]], &points[w[1]]);
        let h = p1.phi - p0.phi;
        let t = (phi - p0.phi) / h;
        let (t2, t3) = (t * t, t * t * t);
        // Cubic Hermite: exact for the straight rod's G = Cφ²/2L + const.
        let energy = (2.0 * t3 - 3.0 * t2 + 1.0) * p0.energy
            + (t3 - 2.0 * t2 + t) * h * p0.torque
            + (3.0 * t2 - 2.0 * t3) * p1.energy
            + (t3 - t2) * h * p1.torque;
        let torque = ((6.0 * t2 - 6.0 * t) * (p0.energy - p1.energy)) / h
            + (3.0 * t2 - 4.0 * t + 1.0) * p0.torque
            + (3.0 * t2 - 2.0 * t) * p1.torque;
        let extension = p0.extension + t * (p1.extension - p0.extension);
        Some(LegValue { energy, torque, extension })
    }
}

/// How the lowest curve changes state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JumpKind {
    /// Two stable legs' energies cross (a Maxwell point).
    Crossing,
    /// The lowest leg ends (a fold or the buckling point) with another
    /// stable leg present on the far side: the state it leaves is gone.
    LegEnd,
}

/// A jump of the lowest curve at end rotation `phi`, from leg `from`
/// (lowest at smaller φ) to leg `to` (indices into the curve's legs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jump {
    pub phi: f64,
    pub turns: f64,
    pub from: usize,
    pub to: usize,
    pub kind: JumpKind,
}

/// The coexistence point of the straight rod and a buckled leg (the
/// plectoneme): equal energies (1) at equal turns, both stable, neither
/// above another stable state there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coexistence {
    pub phi: f64,
    pub turns: f64,
    /// The common energy (pN nm).
    pub energy: f64,
    /// The straight rod's torque there (the overshoot over the plateau)
    /// and the buckled leg's.
    pub torque_straight: f64,
    pub torque_plectoneme: f64,
    pub extension_straight: f64,
    pub extension_plectoneme: f64,
    /// The two legs (indices into the curve's legs).
    pub straight_leg: usize,
    pub plectoneme_leg: usize,
}

/// The equilibrium curve of a run: every point with its energy and kind,
/// the stable legs, the lowest curve's jumps and the coexistence point.
#[derive(Clone, Debug, PartialEq)]
pub struct EquilibriumCurve {
    /// The run's points in its order.
    pub points: Vec<CurvePoint>,
    pub legs: Vec<Leg>,
    /// The lowest curve's jumps, by increasing φ.
    pub jumps: Vec<Jump>,
    pub coexistence: Option<Coexistence>,
    /// Why there is no coexistence point (None when there is one).
    pub note: Option<String>,
}

impl EquilibriumCurve {
    /// The lowest curve: the [`Kind::Lowest`] points by increasing turns.
    pub fn lowest(&self) -> Vec<CurvePoint> {
        let mut v: Vec<CurvePoint> = self.points.iter().copied().filter(|p| p.kind == Kind::Lowest).collect();
        v.sort_by(|a, b| a.phi.total_cmp(&b.phi));
        v
    }

    /// Leg `leg`'s state at end rotation `phi` (rad).
    pub fn leg_at(&self, leg: usize, phi: f64) -> Option<LegValue> {
        self.legs.get(leg)?.at(&self.points, phi)
    }

    /// The lowest energy among the stable legs other than `except` at
    /// `phi`, with its leg.
    fn lowest_other(&self, phi: f64, except: &[usize]) -> Option<(usize, f64)> {
        (0..self.legs.len())
            .filter(|l| !except.contains(l))
            .filter_map(|l| self.leg_at(l, phi).map(|v| (l, v.energy)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }
}

/// The equilibrium curve of `run` (rotation control, module
/// documentation): energies by [`path_energies`], stability by
/// [`negative_modes`], stable legs, each stable point Lowest or
/// Metastable against the other legs' interpolated energies at its turns,
/// the lowest curve's jumps, and the coexistence of the straight rod with
/// a buckled leg — None, with the reason in `note`, when the run did not
/// buckle, its buckled branch has no stable leg, the straight and buckled
/// stable legs do not overlap in turns, or their energies do not cross
/// where they overlap.
pub fn equilibrium_curve(run: &SupercoilRun) -> Result<EquilibriumCurve> {
    let energies = path_energies(run)?;
    let modes = negative_modes(run)?;
    let points: Vec<CurvePoint> = run
        .points
        .iter()
        .zip(energies.iter().zip(&modes))
        .enumerate()
        .map(|(index, (p, (&energy, &negative_modes)))| CurvePoint {
            phi: p.phi,
            turns: p.observables.turns,
            extension: p.observables.extension,
            torque: p.observables.torque,
            energy,
            kind: match negative_modes {
                Some(0) => Kind::Lowest,
                Some(_) => Kind::Unstable,
                None => Kind::Undetermined,
            },
            negative_modes,
            branch: p.branch,
            index,
        })
        .collect();
    let legs = stable_legs(&points, run.buckling.map(|(phi, _)| phi));
    let mut curve = EquilibriumCurve { points, legs, jumps: Vec::new(), coexistence: None, note: None };
    // Stable points above another stable leg at their turns: metastable.
    for l in 0..curve.legs.len() {
        for k in curve.legs[l].first..=curve.legs[l].last {
            let (phi, e) = (curve.points[k].phi, curve.points[k].energy);
            if curve.lowest_other(phi, &[l]).is_some_and(|(_, other)| other < e) {
                curve.points[k].kind = Kind::Metastable;
            }
        }
    }
    curve.jumps = jumps(&curve);
    match coexistence(&curve) {
        Ok(c) => curve.coexistence = Some(c),
        Err(why) => curve.note = Some(why),
    }
    Ok(curve)
}

/// The stable legs of `points`: maximal runs of consecutive stable points
/// of one branch, monotone in φ; the straight rod's leg extends to the
/// buckling point `phi_b` through the first point past it.
fn stable_legs(points: &[CurvePoint], phi_b: Option<f64>) -> Vec<Leg> {
    let mut legs: Vec<Leg> = Vec::new();
    let stable = |k: usize| points[k].negative_modes == Some(0);
    let mut k = 0;
    while k < points.len() {
        if !stable(k) {
            k += 1;
            continue;
        }
        let (first, branch) = (k, points[k].branch);
        let mut last = k;
        while last + 1 < points.len() && stable(last + 1) && points[last + 1].branch == branch {
            let (a, b) = (points[last].phi, points[last + 1].phi);
            let monotone = last == first || (b - a) * (a - points[last - 1].phi) > 0.0;
            if !monotone || b == a {
                break;
            }
            last += 1;
        }
        let mut nodes: Vec<usize> = (first..=last).collect();
        let (a, b) = (points[first].phi, points[last].phi);
        let mut phi_range = (a.min(b), a.max(b));
        let next = last + 1;
        if let (0, Some(phi_b), true) = (branch, phi_b, next < points.len() && points[next].branch == 0) {
            if points[next].phi > phi_b && phi_b > phi_range.1 {
                nodes.push(next);
                phi_range.1 = phi_b;
            }
        }
        legs.push(Leg { branch, first, last, phi_range, nodes });
        k = last + 1;
    }
    legs
}

/// Where the energies of stable legs `a` and `b` cross in their common
/// range: sign changes of G_a − G_b on the union of their nodes, refined by
/// bisection on the interpolants to rounding.
fn crossings(curve: &EquilibriumCurve, a: usize, b: usize) -> Vec<f64> {
    let (la, lb) = (&curve.legs[a], &curve.legs[b]);
    let (lo, hi) = (la.phi_range.0.max(lb.phi_range.0), la.phi_range.1.min(lb.phi_range.1));
    if !(lo < hi) {
        return Vec::new();
    }
    let diff = |phi: f64| -> Option<f64> { Some(curve.leg_at(a, phi)?.energy - curve.leg_at(b, phi)?.energy) };
    let mut grid: Vec<f64> =
        la.nodes.iter().chain(&lb.nodes).map(|&k| curve.points[k].phi).filter(|&p| p > lo && p < hi).collect();
    grid.push(lo);
    grid.push(hi);
    grid.sort_by(f64::total_cmp);
    grid.dedup();
    let mut out = Vec::new();
    for w in grid.windows(2) {
        let (Some(d0), Some(d1)) = (diff(w[0]), diff(w[1])) else { continue };
        if d0 == 0.0 {
            out.push(w[0]);
            continue;
        }
        if d0.signum() == d1.signum() || d1 == 0.0 {
            continue;
        }
        let (mut x0, mut x1, mut f0) = (w[0], w[1], d0);
        while x1 - x0 > 1e-13 * x1.abs().max(1.0) {
            let m = 0.5 * (x0 + x1);
            let fm = diff(m).expect("inside both ranges");
            if fm.signum() == f0.signum() {
                (x0, f0) = (m, fm);
            } else {
                x1 = m;
            }
        }
        out.push(0.5 * (x0 + x1));
    }
    if let Some(d) = diff(hi) {
        if d == 0.0 {
            out.push(hi);
        }
    }
    out
}

/// The jumps of the lowest curve: crossings of two stable legs where no
/// third is lower, and ends of a lowest leg with another stable leg on the
/// far side. By increasing φ.
fn jumps(curve: &EquilibriumCurve) -> Vec<Jump> {
    let n = curve.legs.len();
    let mut out = Vec::new();
    let jump = |phi: f64, from: usize, to: usize, kind: JumpKind| Jump {
        phi,
        turns: phi / (2.0 * std::f64::consts::PI),
        from,
        to,
        kind,
    };
    for a in 0..n {
        for b in a + 1..n {
            for phi in crossings(curve, a, b) {
                let e = curve.leg_at(a, phi).expect("in range").energy;
                if curve.lowest_other(phi, &[a, b]).is_some_and(|(_, other)| other < e) {
                    continue;
                }
                // Which of the two is lower just below the crossing.
                let below = |l: usize| curve.leg_at(l, phi - 1e-9 * phi.abs().max(1.0)).map(|v| v.energy);
                let a_first = match (below(a), below(b)) {
                    (Some(ea), Some(eb)) => ea < eb,
                    (Some(_), None) => true,
                    _ => false,
                };
                let (from, to) = if a_first { (a, b) } else { (b, a) };
                out.push(jump(phi, from, to, JumpKind::Crossing));
            }
        }
    }
    // A lowest leg that ends where another stable leg goes on.
    for l in 0..n {
        let (lo, hi) = curve.legs[l].phi_range;
        for (end, sign) in [(lo, -1.0), (hi, 1.0)] {
            let e = curve.leg_at(l, end).expect("its end").energy;
            if curve.lowest_other(end, &[l]).is_some_and(|(_, other)| other < e) {
                continue;
            }
            let beyond = end + sign * 1e-9 * end.abs().max(1.0);
            if let Some((other, _)) = curve.lowest_other(beyond, &[l]) {
                let (from, to) = if sign > 0.0 { (l, other) } else { (other, l) };
                out.push(jump(end, from, to, JumpKind::LegEnd));
            }
        }
    }
    out.sort_by(|a, b| a.phi.total_cmp(&b.phi));
    out
}

/// The coexistence of the straight rod with a buckled leg: the lowest
/// curve's crossing from a straight leg to a buckled one; otherwise why not.
fn coexistence(curve: &EquilibriumCurve) -> std::result::Result<Coexistence, String> {
    let straight: Vec<usize> = (0..curve.legs.len()).filter(|&l| curve.legs[l].branch == 0).collect();
    let buckled: Vec<usize> = (0..curve.legs.len()).filter(|&l| curve.legs[l].branch == 1).collect();
    if !curve.points.iter().any(|p| p.branch == 1) {
        return Err("the run has no buckled branch (no buckling point reached)".into());
    }
    if buckled.is_empty() {
        return Err("the buckled branch has no stable leg (the run stopped before the plectoneme is stable, \
                    or its stability is undetermined)"
            .into());
    }
    let span = |ls: &[usize]| {
        ls.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &l| {
            (lo.min(curve.legs[l].phi_range.0), hi.max(curve.legs[l].phi_range.1))
        })
    };
    let (s, b) = (span(&straight), span(&buckled));
    let turns = |phi: f64| phi / (2.0 * std::f64::consts::PI);
    if !(s.0.max(b.0) < s.1.min(b.1)) {
        return Err(format!(
            "the stable straight rod ({:.4}–{:.4} turns) and the stable buckled legs ({:.4}–{:.4} turns) do not overlap",
            turns(s.0),
            turns(s.1),
            turns(b.0),
            turns(b.1)
        ));
    }
    let j = curve
        .jumps
        .iter()
        .find(|j| j.kind == JumpKind::Crossing && curve.legs[j.from].branch == 0 && curve.legs[j.to].branch == 1)
        .ok_or_else(|| {
            let crossed = straight.iter().any(|&a| buckled.iter().any(|&b| !crossings(curve, a, b).is_empty()));
            format!(
                "{} where their stable legs overlap ({:.4}–{:.4} turns)",
                if crossed {
                    "the straight and buckled energies cross only above another stable state"
                } else {
                    "no crossing of the straight and buckled energies"
                },
                turns(s.0.max(b.0)),
                turns(s.1.min(b.1))
            )
        })?;
    let (vs, vp) = (curve.leg_at(j.from, j.phi).expect("in range"), curve.leg_at(j.to, j.phi).expect("in range"));
    Ok(Coexistence {
        phi: j.phi,
        turns: j.turns,
        energy: 0.5 * (vs.energy + vp.energy),
        torque_straight: vs.torque,
        torque_plectoneme: vp.torque,
        extension_straight: vs.extension,
        extension_plectoneme: vp.extension,
        straight_leg: j.from,
        plectoneme_leg: j.to,
    })
}

#[cfg(test)]
mod tests {
    use super::{carry_band_entries, hidden_fold_crossings};

    fn carried(phi: &[f64], counts: &[(usize, usize)]) -> Vec<Option<usize>> {
        let counts: Vec<_> = counts.iter().map(|&c| Some(c)).collect();
        let mut marks: Vec<_> = counts.iter().map(|c| c.map(|c| c.1)).collect();
        carry_band_entries(phi, &counts, &mut marks, 0);
        marks
    }

    #[test]
    fn an_unstable_mode_entering_the_band_stays_counted() {
        let phi = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        // (negative, unstable): the mode enters the band at 2, leaves it below at 4.
        let m = carried(&phi, &[(1, 1), (1, 1), (1, 0), (1, 0), (1, 1), (1, 1)]);
        assert_eq!(m, vec![Some(1); 6]);
        // A σ crosses zero inside the band at 4 (negative 1 → 0) while the
        // mode is carried: the counts cannot tell which σ crossed, so 4 and
        // the points with its counts after it are undetermined.
        let m = carried(&phi, &[(1, 1), (1, 1), (1, 0), (1, 0), (0, 0), (0, 0)]);
        assert_eq!(m, vec![Some(1), Some(1), Some(1), Some(1), None, None]);
        // A counted crossing (both counts drop, nothing carried) stands.
        let m = carried(&phi, &[(1, 1), (1, 1), (0, 0), (0, 0), (0, 0), (0, 0)]);
        assert_eq!(m, vec![Some(1), Some(1), Some(0), Some(0), Some(0), Some(0)]);
        // A neutral mode that was never counted (entered from above) is not carried.
        let m = carried(&phi, &[(0, 0), (1, 0), (1, 0), (0, 0), (0, 0), (0, 0)]);
        assert_eq!(m, vec![Some(0); 6]);
    }

    #[test]
    fn band_entries_at_a_fold_are_the_fold_rules() {
        let phi = [0.0, 1.0, 2.0, 1.5, 1.0, 0.5];
        let m = carried(&phi, &[(1, 1), (1, 1), (1, 1), (1, 0), (1, 0), (1, 0)]);
        // A drop next to a fold (point 2) is the fold rule's to judge (its
        // sides here are one apart): not carried.
        assert_eq!(m[3], Some(0));
    }

    /// A branch from point 0 with one fold at point 3 (φ rises, then
    /// falls). The sides' counts decide the marks as documented.
    fn marks(counts: [(usize, usize); 7]) -> Vec<Option<Option<usize>>> {
        let phi = [0.0, 1.0, 2.0, 3.0, 2.5, 2.0, 1.5];
        hidden_fold_crossings(&phi, &counts.map(Some), 0)
    }

    #[test]
    fn a_counted_crossing_stands() {
        assert!(marks([(0, 0), (0, 0), (0, 0), (0, 0), (1, 1), (1, 1), (1, 1)]).iter().all(|m| m.is_none()));
    }

    #[test]
    fn a_neutral_crossing_that_leaves_below_zero_is_counted() {
        // Past the fold the mode is negative inside the band (1, 0) for two
        // points, then counted (1, 1): those two points have it too.
        let m = marks([(0, 0), (0, 0), (0, 0), (0, 0), (1, 0), (1, 0), (1, 1)]);
        assert_eq!(m, vec![None, None, None, None, Some(Some(1)), Some(Some(1)), None]);
    }

    #[test]
    fn a_neutral_crossing_that_stays_in_the_band_is_undetermined() {
        // Before the fold the mode is negative inside the band from point 1
        // (the fold point too); it entered the band from above at point 1.
        let m = marks([(0, 0), (1, 0), (1, 0), (1, 0), (0, 0), (0, 0), (0, 0)]);
        assert_eq!(m, vec![None, Some(None), Some(None), Some(None), None, None, None]);
        // The branch ends inside the stretch: undetermined too.
        let m = marks([(0, 0), (0, 0), (0, 0), (0, 0), (1, 0), (1, 0), (1, 0)]);
        assert_eq!(m[4..], [Some(None), Some(None), Some(None)]);
    }

    #[test]
    fn a_missed_crossing_leaves_both_sides_undetermined() {
        let m = marks([(0, 0), (0, 0), (2, 2), (2, 2), (2, 2), (3, 3), (3, 3)]);
        assert_eq!(m, vec![None, None, Some(None), Some(None), Some(None), None, None]);
    }

    #[test]
    fn the_branch_start_is_no_fold() {
        // φ turns back between points 0 and 1 (the switch from the other
        // branch): no fold there, nothing marked from `from` = 1 on.
        let phi = [3.0, 2.0, 2.5, 3.0];
        let counts = [Some((2, 2)), Some((0, 0)), Some((0, 0)), Some((0, 0))];
        assert!(hidden_fold_crossings(&phi, &counts, 1).iter().all(|m| m.is_none()));
    }
}

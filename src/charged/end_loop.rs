//! The plectoneme's nucleation free energy from the full zero-temperature
//! charged rod: the grand (fixed-torque) energy of the end loop and the
//! tail/plectoneme junctions, tabulated over force × salt for the
//! finite-temperature two-phase model of supercoiling (`end_loops.csv`
//! next to this file).
//!
//! **Definition.** A supercoiling run of a [`DnaScene`] at tension F
//! ([`super::dna::run_scene`], rotation control) gives points with turns n = φ/2π,
//! end torque τ (= M), extension z, Tw, Wr and a branch (straight or
//! buckled); [`path_energies`] gives their potential energy
//!
//!   G = E_elastic + E_electrostatic + E_hard core − F z        (pN nm).
//!
//! Along any branch dG/dn = 2π τ (the work theorem, [`super::coexistence`]).
//! Its Legendre transform at fixed torque, the grand energy
//!
//!   Ψ = G − 2π τ n,   dΨ/dτ = −2π n   along a branch,           (1)
//!
//! is what a state costs when the end is held at torque τ.
//!
//! - **Straight branch.** Ψ_s(τ) := G − 2πτn on the straight points, a
//!   smooth function of τ (τ rises monotonically with n there). It is
//!   interpolated in τ by cubic Hermite with the exact slope
//!   dΨ_s/dτ = −2π n of (1) ([`StraightGrand`]); for the charged straight
//!   rod Ψ_s = E_es(line) − F L − L τ²/(2C), which the Hermite cubic
//!   reproduces exactly (tests/charged_end_loop.rs).
//! - **Buckled branch.** At every buckled point j whose torque lies in
//!   the straight branch's range,
//!
//!   E_nuc,j := G_j − 2π τ_j n_j − Ψ_s(τ_j)                         (2)
//!
//!   is the grand energy of the buckled state relative to the same
//!   molecule straight at the same torque ([`nucleation_energies`]). In
//!   the two-phase picture a buckled state is straight tails, a uniform
//!   plectoneme of length L_p with grand energy per length ω_p(τ) (the
//!   straight rod's: ω_s(τ)), and the end loop with the two junctions:
//!
//!   E_nuc(τ) = (ω_p(τ) − ω_s(τ)) L_p + E_end(τ).                   (3)
//!
//!   On the plectonemic plateau — the torque τ0 at which ω_p = ω_s — the
//!   length of the plectoneme drops out, which leaves E_end(τ0): the end
//!   loop and the two tail/plectoneme junctions, the nucleation free
//!   energy of the two-phase model at zero temperature. Where the computed
//!   torque drifts off τ0 (short tails, the first superhelical turns), (3)
//!   shows the drift as a spread of E_nuc: the entry reports its range. Before strands meet, (2) is the
//!   grand energy of the localized loop (for the uncharged rod on a long
//!   molecule, the Kirchhoff homoclinic ΔG(τ) = 8√(K_bF)√(1 − m²) −
//!   4τ arccos m, m = τ/(2√(K_bF)); the test checks it).
//!
//! **Plateau points** ([`plateau_points`]): the buckled points
//! - on the buckled branch's last stretch increasing in n (past its last
//!   fold in n: the plectonemic leg),
//! - not marked unstable or metastable by [`equilibrium_curve`] (points it
//!   marks lowest, and points whose stability it leaves undetermined — on
//!   long molecules the buckled branch's bifurcations leave it so past the
//!   first turns — are kept),
//! - with writhe Wr ≥ [`MIN_WRITHE`] (2.5: the end loop, Wr ≈ 1, plus
//!   about a superhelical turn and a half of plectoneme — while the first
//!   superhelical turns form, τ and E_nuc still swing: on 1 kbp at 1 pN,
//!   0.1 M, τ 8.67 → 7.96 → 8.31 pN nm and E_nuc 74.5 → 82.1 → 77.5 pN nm
//!   between Wr 1.64 and 2.23, then E_nuc 79.6–80.7 from Wr 2.65 to 6.4),
//! - with extension z ≥ [`MIN_EXTENSION_FRACTION`] L (0.3: the tails are
//!   not yet short, so the ends do not squeeze the plectoneme),
//! - with τ inside the straight branch's torque range (Ψ_s interpolated,
//!   never extrapolated).
//!
//! **Entry** ([`EndLoopEntry`], [`end_loop_entry`]): over the plateau
//! points, the mean, min and max of E_nuc and of τ (τ0 is the mean τ),
//! the least-squares slope dz/dn (nm per turn), the superhelix radius at
//! their middle point (half the closest approach of distinct strands,
//! [`strand_approach`], on the nodes and stage points of that state), the
//! base pairs, the turns the run reached, the number of points and the
//! wall time. A run with fewer than 3 plateau points is refused
//! (ErrNotConverged, saying what the buckled branch reached).

use super::coexistence::{equilibrium_curve, path_energies, Kind};
use super::dna::{run_scene_with, DnaScene, SupercoilRun, SupercoilSettings};
use super::summary::strand_approach;
use crate::error::{Error, Result};
use crate::status::Status;
use std::f64::consts::TAU;

/// Smallest writhe (turns) of a plateau point: the end loop (≈ 1) plus a
/// superhelical turn and a half, past the swings of the first turns
/// (module documentation).
pub const MIN_WRITHE: f64 = 2.5;

/// Smallest extension of a plateau point as a fraction of the contour
/// length: the tails still hold at least ~30 % of the molecule.
pub const MIN_EXTENSION_FRACTION: f64 = 0.3;

/// The straight branch's grand energy Ψ_s(τ) = G − 2πτn, a cubic Hermite
/// interpolant in τ through the straight points with dΨ_s/dτ = −2πn.
#[derive(Clone, Debug, PartialEq)]
pub struct StraightGrand {
    /// Nodes by strictly increasing τ: (τ, Ψ_s, −2πn).
    nodes: Vec<(f64, f64, f64)>,
}

impl StraightGrand {
    /// From the straight points of `run` and their energies (`energies[k]`
    /// for `run.points[k]`). Refused (ErrOutOfRange) when fewer than two
    /// straight points have distinct torques, or when τ does not increase
    /// with the turns along the straight branch.
    pub fn of_run(run: &SupercoilRun, energies: &[f64]) -> Result<Self> {
        let mut nodes: Vec<(f64, f64, f64)> = Vec::new();
        for (p, &g) in run.points.iter().zip(energies).filter(|(p, _)| p.branch == 0) {
            let (n, tau) = (p.observables.turns, p.observables.torque);
            let node = (tau, g - TAU * tau * n, -TAU * n);
            match nodes.last() {
                // A repeated point (a chunk's start) adds nothing.
                Some(last) if (tau - last.0).abs() <= 1e-12 * tau.abs().max(1.0) => {}
                Some(last) if tau < last.0 => {
                    return Err(Error::new(
                        Status::ErrOutOfRange,
                        format!("the straight branch's torque falls from {} to {tau} pN nm", last.0),
                    ))
                }
                _ => nodes.push(node),
            }
        }
        if nodes.len() < 2 {
            return Err(Error::new(Status::ErrOutOfRange, "the run has fewer than two straight points"));
        }
        Ok(StraightGrand { nodes })
    }

    /// The torques (pN nm) it covers.
    pub fn range(&self) -> (f64, f64) {
        (self.nodes[0].0, self.nodes[self.nodes.len() - 1].0)
    }

    /// Ψ_s(τ) (pN nm), None outside [`StraightGrand::range`].
    pub fn at(&self, tau: f64) -> Option<f64> {
        let (lo, hi) = self.range();
        if !(tau >= lo && tau <= hi) {
            return None;
        }
        let k = self.nodes.partition_point(|n| n.0 <= tau).clamp(1, self.nodes.len() - 1);
        let ((t0, p0, d0), (t1, p1, d1)) = (self.nodes[k - 1], self.nodes[k]);
        let h = t1 - t0;
        let t = (tau - t0) / h;
        let (t2, t3) = (t * t, t * t * t);
        Some(
            (2.0 * t3 - 3.0 * t2 + 1.0) * p0
                + (t3 - 2.0 * t2 + t) * h * d0
                + (3.0 * t2 - 2.0 * t3) * p1
                + (t3 - t2) * h * d1,
        )
    }
}

/// A buckled point with its nucleation energy (2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NucleationPoint {
    /// Index into `run.points`.
    pub index: usize,
    pub turns: f64,
    /// τ (pN nm), z (nm), Wr (turns).
    pub torque: f64,
    pub extension: f64,
    pub writhe: f64,
    /// G (pN nm).
    pub energy: f64,
    /// E_nuc = G − 2πτn − Ψ_s(τ) (pN nm).
    pub e_nuc: f64,
    /// Its stability by [`equilibrium_curve`] (None: not computed, or a
    /// torque-controlled run).
    pub kind: Option<Kind>,
}

/// E_nuc (2) at every buckled point of `run` whose torque lies in the
/// straight branch's range, in the order of `run.points` (`energies` as
/// [`path_energies`] gives them).
pub fn nucleation_energies(run: &SupercoilRun, energies: &[f64]) -> Result<Vec<NucleationPoint>> {
    let straight = StraightGrand::of_run(run, energies)?;
    Ok(run
        .points
        .iter()
        .zip(energies)
        .enumerate()
        .filter(|(_, (p, _))| p.branch == 1)
        .filter_map(|(index, (p, &g))| {
            let o = &p.observables;
            let psi = straight.at(o.torque)?;
            Some(NucleationPoint {
                index,
                turns: o.turns,
                torque: o.torque,
                extension: o.extension,
                writhe: o.writhe,
                energy: g,
                e_nuc: g - TAU * o.torque * o.turns - psi,
                kind: None,
            })
        })
        .collect())
}

/// [`nucleation_energies`] of `run` with the energies and stability of its
/// [`equilibrium_curve`] (rotation control; under a torque clamp the
/// energies of [`path_energies`] and no stability).
pub fn nucleation_points(run: &SupercoilRun) -> Result<Vec<NucleationPoint>> {
    if run.rod.torqued() {
        return nucleation_energies(run, &path_energies(run)?);
    }
    let curve = equilibrium_curve(run)?;
    let energies: Vec<f64> = curve.points.iter().map(|p| p.energy).collect();
    let mut nuc = nucleation_energies(run, &energies)?;
    for p in &mut nuc {
        p.kind = Some(curve.points[p.index].kind);
    }
    Ok(nuc)
}

/// Which buckled points count as the plectonemic plateau (module
/// documentation); the default is [`MIN_WRITHE`] and
/// [`MIN_EXTENSION_FRACTION`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlateauRule {
    /// Smallest writhe (turns).
    pub min_writhe: f64,
    /// Smallest extension over the contour length.
    pub min_extension_fraction: f64,
}

impl Default for PlateauRule {
    fn default() -> Self {
        PlateauRule { min_writhe: MIN_WRITHE, min_extension_fraction: MIN_EXTENSION_FRACTION }
    }
}

/// The plateau points among `nuc` by the default [`PlateauRule`].
pub fn plateau_points(run: &SupercoilRun, nuc: &[NucleationPoint]) -> Vec<usize> {
    plateau_points_by(run, nuc, &PlateauRule::default())
}

/// The plateau points among `nuc` (module documentation): on the buckled
/// branch's last stretch increasing in turns, not [`Kind::Unstable`] or
/// [`Kind::Metastable`], Wr ≥ `rule.min_writhe`, z ≥
/// `rule.min_extension_fraction` L. Returns indices into `nuc`.
pub fn plateau_points_by(run: &SupercoilRun, nuc: &[NucleationPoint], rule: &PlateauRule) -> Vec<usize> {
    let ns = run.points.iter().take_while(|p| p.branch == 0).count();
    let b = &run.points[ns..];
    // The last stretch of the buckled branch with increasing φ.
    let mut start = b.len().saturating_sub(1);
    while start > 0 && b[start - 1].phi < b[start].phi {
        start -= 1;
    }
    let first = ns + start;
    let length = run.scene.length();
    (0..nuc.len())
        .filter(|&k| {
            let p = &nuc[k];
            let stable = !matches!(p.kind, Some(Kind::Unstable | Kind::Metastable));
            p.index >= first
                && stable
                && p.writhe >= rule.min_writhe
                && p.extension >= rule.min_extension_fraction * length
        })
        .collect()
}

/// One row of the nucleation-energy table.
#[derive(Clone, Debug, PartialEq)]
pub struct EndLoopEntry {
    /// Tension F (pN) and monovalent salt (M).
    pub force: f64,
    pub salt: f64,
    pub base_pairs: usize,
    /// Plateau torque τ0: the mean τ over the plateau points, and its
    /// range (pN nm).
    pub tau_plateau: f64,
    pub tau_min: f64,
    pub tau_max: f64,
    /// Nucleation energy E_nuc: mean, min and max over the plateau points (pN nm).
    pub e_nuc: f64,
    pub e_nuc_min: f64,
    pub e_nuc_max: f64,
    /// Plateau points used.
    pub points: usize,
    /// Least-squares dz/dn over them (nm per turn).
    pub slope: f64,
    /// Superhelix radius at their middle point (nm).
    pub superhelix_radius: f64,
    /// The turns the run reached.
    pub turns: f64,
    /// Wall time of the run and the analysis (s).
    pub seconds: f64,
}

/// Run `scene` with `settings` until the tails are short ([`end_loop_run`])
/// and tabulate its end loop ([`entry_of_run`]).
pub fn end_loop_entry(scene: &DnaScene, settings: &SupercoilSettings) -> Result<EndLoopEntry> {
    let clock = std::time::Instant::now();
    let run = end_loop_run(scene, settings)?;
    let mut e = entry_of_run(&run)?;
    e.seconds = clock.elapsed().as_secs_f64();
    Ok(e)
}

/// The entry of a computed run (module documentation); `seconds` is the
/// run's own time plus the analysis. Refused with ErrNotConverged when the
/// run has fewer than 3 plateau points (the message says what its buckled
/// branch reached) or no two strands approach at their middle point.
pub fn entry_of_run(run: &SupercoilRun) -> Result<EndLoopEntry> {
    entry_of_run_by(run, &PlateauRule::default())
}

/// [`entry_of_run`] with the plateau points of `rule`.
pub fn entry_of_run_by(run: &SupercoilRun, rule: &PlateauRule) -> Result<EndLoopEntry> {
    let clock = std::time::Instant::now();
    let nuc = nucleation_points(run)?;
    let used: Vec<&NucleationPoint> = plateau_points_by(run, &nuc, rule).into_iter().map(|k| &nuc[k]).collect();
    let last_turns = run.points.last().map_or(0.0, |p| p.observables.turns);
    if used.len() < 3 {
        let b: Vec<_> = run.points.iter().filter(|p| p.branch == 1).collect();
        let max_wr = b.iter().map(|p| p.observables.writhe).fold(f64::NEG_INFINITY, f64::max);
        let why = if b.is_empty() {
            "the run has no buckled point".to_string()
        } else {
            format!(
                "{} buckled points to {last_turns:.3} turns, writhe up to {max_wr:.3}, extension down to {:.1} nm of \
                 L = {:.1} nm (a plateau point needs Wr ≥ {}, z ≥ {} L, the last \
                 stretch increasing in turns, not unstable, τ in the straight range)",
                b.len(),
                b.iter().map(|p| p.observables.extension).fold(f64::INFINITY, f64::min),
                run.scene.length(),
                rule.min_writhe,
                rule.min_extension_fraction
            )
        };
        return Err(Error::new(
            Status::ErrNotConverged,
            format!("{} plectonemic plateau points (at least 3 needed): {why}", used.len()),
        ));
    }
    let n = used.len() as f64;
    let mean = |f: &dyn Fn(&NucleationPoint) -> f64| used.iter().map(|p| f(p)).sum::<f64>() / n;
    let min = |f: &dyn Fn(&NucleationPoint) -> f64| used.iter().map(|p| f(p)).fold(f64::INFINITY, f64::min);
    let max = |f: &dyn Fn(&NucleationPoint) -> f64| used.iter().map(|p| f(p)).fold(f64::NEG_INFINITY, f64::max);
    let (mx, mz) = (mean(&|p| p.turns), mean(&|p| p.extension));
    let sxx: f64 = used.iter().map(|p| (p.turns - mx).powi(2)).sum();
    let sxz: f64 = used.iter().map(|p| (p.turns - mx) * (p.extension - mz)).sum();
    let slope = sxz / sxx;
    let middle = used[used.len() / 2].index;
    let x = &run.states[middle];
    let profile = run.rod.profile_offsets();
    let r: Vec<[f64; 3]> = profile.iter().map(|&(_, o)| [x[o], x[o + 1], x[o + 2]]).collect();
    let s: Vec<f64> = profile.iter().map(|p| p.0).collect();
    let Some((d, _, _)) = strand_approach(&r, &s) else {
        return Err(Error::new(Status::ErrNotConverged, "no two strands approach at the plateau's middle point"));
    };
    let superhelix_radius = 0.5 * d;
    if ![slope, superhelix_radius].iter().all(|v| v.is_finite()) {
        return Err(Error::new(Status::ErrNonFiniteResult, "the plateau's slope is not finite (its turns coincide)"));
    }
    Ok(EndLoopEntry {
        force: run.scene.tension,
        salt: run.scene.salt,
        base_pairs: run.scene.base_pairs,
        tau_plateau: mean(&|p| p.torque),
        tau_min: min(&|p| p.torque),
        tau_max: max(&|p| p.torque),
        e_nuc: mean(&|p| p.e_nuc),
        e_nuc_min: min(&|p| p.e_nuc),
        e_nuc_max: max(&|p| p.e_nuc),
        points: used.len(),
        slope,
        superhelix_radius,
        turns: last_turns,
        seconds: run.seconds + clock.elapsed().as_secs_f64(),
    })
}

/// The CSV columns of the table, in order.
pub const COLUMNS: &str = "force_pN,salt_M,base_pairs,tau_plateau_pNnm,tau_min,tau_max,e_nuc_pNnm,e_nuc_min,e_nuc_max,\
                           points,slope_nm_per_turn,superhelix_radius_nm,turns,seconds";

/// The table as CSV: `#` comment lines (units, the definition, the command
/// that regenerates it), the header [`COLUMNS`], one row per entry.
pub fn write_table(entries: &[EndLoopEntry]) -> String {
    write_table_with_notes(entries, &[])
}

/// [`write_table`] with extra `#` comment lines `notes` (e.g. the entries
/// left out and why) after the standard header comments.
pub fn write_table_with_notes(entries: &[EndLoopEntry], notes: &[String]) -> String {
    let mut out = String::new();
    for line in [
        "# Plectoneme nucleation (end loop + junctions) grand energies of the zero-temperature charged rod",
        "# (rodkit::charged::end_loop: E_nuc = G - 2 pi tau n - Psi_s(tau) on the plectonemic plateau points).",
        "# Units: force pN, salt mol/L, torques pN nm, energies pN nm, slope nm per turn, radius nm, turns, seconds.",
        "# tau_plateau/e_nuc: means over the plateau points; *_min/*_max their ranges; points: how many.",
        "# Scene: DnaScene defaults (nu = 1/l_B, a = 1 nm, A = 50 nm, P = 95 nm, 298.15 K) but base_pairs, tension,",
        "# salt; SupercoilSettings defaults (2 nm Gauss(2) elements, cutoff 1e-4, auto hard core) but max_turns,",
        "# max_steps (rodkit::charged::end_loop::table_scene), stopped once z < 0.285 L (end_loop_run). Plateau points:",
        "# the buckled branch's last stretch increasing in turns, not unstable/metastable, Wr >= 2.5, z >= 0.3 L.",
        "# Regenerate: RODKIT_END_LOOP_OUT=/tmp/end_loops.csv cargo test --release --test charged_end_loop -- \\",
        "#   --ignored --nocapture regenerate_table   (RODKIT_END_LOOP_GRID=F:S,F:S,... for a subset)",
    ] {
        out.push_str(line);
        out.push('\n');
    }
    for n in notes {
        out.push_str("# ");
        out.push_str(n);
        out.push('\n');
    }
    out.push_str(COLUMNS);
    out.push('\n');
    for e in entries {
        out.push_str(&format!(
            "{},{},{},{:.5},{:.5},{:.5},{:.4},{:.4},{:.4},{},{:.4},{:.5},{:.4},{:.1}\n",
            e.force,
            e.salt,
            e.base_pairs,
            e.tau_plateau,
            e.tau_min,
            e.tau_max,
            e.e_nuc,
            e.e_nuc_min,
            e.e_nuc_max,
            e.points,
            e.slope,
            e.superhelix_radius,
            e.turns,
            e.seconds
        ));
    }
    out
}

/// The rows of a table written by [`write_table`] (`#` lines and blank
/// lines skipped; the header must be [`COLUMNS`]). Refused (ErrOutOfRange)
/// on a missing or different header, a row with the wrong number of
/// fields, or a field that does not parse.
pub fn parse_table(csv: &str) -> Result<Vec<EndLoopEntry>> {
    let bad =
        |line: usize, why: String| Error::new(Status::ErrOutOfRange, format!("end-loop table line {line}: {why}"));
    let mut rows = csv.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let columns: String = COLUMNS.split_whitespace().collect();
    match rows.next() {
        Some((_, h)) if h.trim() == columns => {}
        Some((i, h)) => return Err(bad(i + 1, format!("header `{h}`, expected `{columns}`"))),
        None => return Err(Error::new(Status::ErrOutOfRange, "end-loop table: no header")),
    }
    let mut out = Vec::new();
    for (i, line) in rows {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        if f.len() != 14 {
            return Err(bad(i + 1, format!("{} fields, expected 14", f.len())));
        }
        let num = |k: usize| f[k].parse::<f64>().map_err(|e| bad(i + 1, format!("field {} `{}`: {e}", k + 1, f[k])));
        let count =
            |k: usize| f[k].parse::<usize>().map_err(|e| bad(i + 1, format!("field {} `{}`: {e}", k + 1, f[k])));
        out.push(EndLoopEntry {
            force: num(0)?,
            salt: num(1)?,
            base_pairs: count(2)?,
            tau_plateau: num(3)?,
            tau_min: num(4)?,
            tau_max: num(5)?,
            e_nuc: num(6)?,
            e_nuc_min: num(7)?,
            e_nuc_max: num(8)?,
            points: count(9)?,
            slope: num(10)?,
            superhelix_radius: num(11)?,
            turns: num(12)?,
            seconds: num(13)?,
        });
    }
    Ok(out)
}

/// The scene and settings of the table's entry at `force` (pN) and `salt`
/// (M): a molecule long enough for the end loop (size ~√(K_b/F)) plus a
/// plectoneme past Wr = [`MIN_WRITHE`] by about a superhelical turn with
/// tails ≥ 30 % of L, base_pairs = b(salt)·√(1 pN / F) rounded to 50 (at
/// least 300), b = 1000 at ≤ 0.01 M, 950 at ≤ 0.02 M, 750 at ≤ 0.05 M, 600
/// above (measured at 1 pN, 0.1 M on 1 kbp: the extension has fallen by
/// 113 nm at Wr 2.5 and falls 31 nm a turn on; at 0.01 M it falls about
/// twice as fast, doc/dna.md). The
/// turns and steps are only bounds: [`end_loop_run`] stops the run once the
/// tails are short.
pub fn table_scene(force: f64, salt: f64) -> (DnaScene, SupercoilSettings) {
    let b = if salt <= 0.01 + 1e-12 {
        1000.0
    } else if salt <= 0.02 + 1e-12 {
        950.0
    } else if salt <= 0.05 + 1e-12 {
        750.0
    } else {
        600.0
    };
    let base_pairs = ((b * (1.0 / force).sqrt() / 50.0).round() as usize * 50).max(300);
    let scene = DnaScene { base_pairs, tension: force, salt, ..Default::default() };
    let settings = SupercoilSettings { max_turns: 20.0, max_steps: 1500, ..Default::default() };
    (scene, settings)
}

/// The run an entry is read from: [`run_scene`] with `settings`, stopped
/// (its progress callback, [`super::dna::RunStop::Cancelled`]) after the
/// first buckled point whose extension falls below 0.95 ×
/// [`MIN_EXTENSION_FRACTION`] L — past it no plateau point can follow on
/// the plectonemic leg — or at `settings`' own turns and steps.
pub fn end_loop_run(scene: &DnaScene, settings: &SupercoilSettings) -> Result<SupercoilRun> {
    let floor = 0.95 * MIN_EXTENSION_FRACTION * scene.length();
    // The plateau's points are chosen by the parity rules' marks, as the
    // shipped table was: with counted modes the 300 bp, 4 pN, 0.05 M scene
    // on 40 elements marks every plectonemic point unstable (a mode the
    // rules do not see; not yet understood), and no entry is taken.
    let settings = &SupercoilSettings { stability: None, ..settings.clone() };
    run_scene_with(scene, settings, |p| !(p.branch == 1 && p.extension < floor))
}

//! The summary of a supercoiling curve (src/charged/summary.rs) on the
//! 300 bp scene of tests/supercoil_energy.rs (1 pN, 0.1 M, 40 elements, to
//! 1.7 turns: buckling at 1.316 turns, a coexistence point, a stable
//! plectoneme past it): the plateau, the slope and the superhelix radius
//! against references computed here; the instability and the coexistence
//! as the run's and the curve's own points (a wiring check, with the
//! straight rod's M = Cφ/L beside it); and the C ABI's
//! `rodkit_supercoil_curve_summary` against the Rust summary of the same
//! run (bitwise: the same code on the same deterministic path).

use rodkit::capi::supercoil::*;
use rodkit::capi::supercoil_curve::*;
use rodkit::charged::coexistence::{equilibrium_curve, EquilibriumCurve};
use rodkit::charged::dna::{self, DnaScene, SupercoilRun, SupercoilSettings};
use rodkit::charged::summary::{strand_approach, summarise_with, CurveSummary, Finding};
use std::f64::consts::TAU;
use std::sync::OnceLock;

const BASE_PAIRS: usize = 300;
const ELEMENTS: usize = 40;
const MAX_TURNS: f64 = 1.7;
const MAX_STEPS: usize = 300;

fn scene() -> &'static (SupercoilRun, EquilibriumCurve, CurveSummary) {
    static S: OnceLock<(SupercoilRun, EquilibriumCurve, CurveSummary)> = OnceLock::new();
    S.get_or_init(|| {
        let scene = DnaScene { base_pairs: BASE_PAIRS, ..Default::default() };
        let settings =
            SupercoilSettings { elements: ELEMENTS, max_turns: MAX_TURNS, max_steps: MAX_STEPS, ..Default::default() };
        let run = dna::run_scene(&scene, &settings).unwrap();
        let curve = equilibrium_curve(&run).unwrap();
        let summary = summarise_with(&run, Some(&curve));
        println!("{} points in {:.2} s; summary {summary:#?}", run.points.len(), run.seconds);
        (run, curve, summary)
    })
}

/// Instability and coexistence. Mostly a wiring check, and said so: the
/// summary must report the run's located buckling point and the
/// equilibrium curve's coexistence point exactly as computed (bitwise);
/// those points are held against physics elsewhere — the buckling torque
/// against the analytic roots in tests/charged_rod.rs, the coexistence by
/// the equal-area rule and the two-phase picture in
/// tests/supercoil_energy.rs. One independent check here: the straight
/// twisted rod's torque at the instability is M = Cφ/L (its twist
/// density is uniform), to the collocation's O((h u₃)⁴): measured 1.6e-7
/// on these 40 elements of 300 bp; asserted 2e-6.
/// And the jump z_s − z_p > 0 (the plectoneme is shorter).
#[test]
fn instability_and_coexistence_are_the_curves() {
    let (run, curve, s) = scene();
    let (phi_b, m_b) = run.buckling.unwrap();
    let i = s.instability.value.unwrap();
    assert_eq!(s.instability.finding, Finding::Found);
    assert_eq!((i.turns, i.torque), (phi_b / TAU, m_b));
    let (cc, l) = (run.scene.twist_persistence * run.scene.kt(), run.scene.length());
    let straight = (i.torque - cc * i.turns * TAU / l).abs() / i.torque;
    println!("instability torque against Cφ/L: {straight:e}");
    assert!(straight <= 2e-6, "{straight:e}");
    let c = curve.coexistence.expect("the scene has a coexistence point");
    let sc = s.coexistence.value.unwrap();
    assert_eq!(s.coexistence.finding, Finding::Found);
    assert_eq!((sc.turns, sc.torque_straight, sc.torque_plectoneme), (c.turns, c.torque_straight, c.torque_plectoneme));
    assert_eq!(sc.extension_jump, c.extension_straight - c.extension_plectoneme);
    assert!(sc.extension_jump > 0.0 && sc.torque_straight > sc.torque_plectoneme);
    assert!(s.note.is_none());
}

/// Plateau torque: the φ-average of M over the plectoneme leg beyond
/// coexistence equals ΔG/Δφ by the work theorem dG/dφ = M (Maddocks 1987;
/// src/charged/coexistence.rs), with G the independently computed energies
/// of the leg's last point and of the coexistence point. Tolerance: the
/// trapezoid rule's error, bounded by Σ h³ max|M''|/12 with M'' estimated
/// from the nodes' second differences (×2 for the estimate), plus the
/// energies' pair-list rounding (1e-6 pN nm, tests/supercoil_energy.rs).
/// And it lies within [torque_min, torque_max].
#[test]
fn plateau_torque_is_the_energy_slope_of_the_leg() {
    let (_, curve, s) = scene();
    let p = s.plateau.value.expect("a plateau");
    assert_eq!(s.plateau.finding, Finding::Found);
    let c = curve.coexistence.unwrap();
    let leg = &curve.legs[c.plectoneme_leg];
    let last = (leg.first..=leg.last).map(|k| &curve.points[k]).max_by(|a, b| a.phi.total_cmp(&b.phi)).unwrap();
    let dphi = last.phi - c.phi;
    let reference = (last.energy - c.energy) / dphi;
    // Nodes: the coexistence point and the leg's points past it.
    let mut nodes: Vec<(f64, f64)> = vec![(c.phi, c.torque_plectoneme)];
    nodes.extend((leg.first..=leg.last).map(|k| &curve.points[k]).filter(|q| q.phi > c.phi).map(|q| (q.phi, q.torque)));
    nodes.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert_eq!(nodes.len(), p.nodes);
    let mut bound = 0.0;
    for w in nodes.windows(3) {
        let (h0, h1) = (w[1].0 - w[0].0, w[2].0 - w[1].0);
        let m2 = 2.0 * ((w[2].1 - w[1].1) / h1 - (w[1].1 - w[0].1) / h0) / (h0 + h1);
        bound += 2.0 * m2.abs() * (h0.max(h1)).powi(3) / 12.0;
    }
    let tol = bound / dphi + 1e-6 / dphi;
    println!(
        "plateau {:.6} pN nm vs ΔG/Δφ {reference:.6} (diff {:e}, tolerance {tol:e}); torque {:.4}–{:.4} over {:.4}–{:.4} turns, {} nodes",
        p.torque,
        p.torque - reference,
        p.torque_min,
        p.torque_max,
        p.turns_from,
        p.turns_to,
        p.nodes
    );
    assert!((p.torque - reference).abs() <= tol);
    assert!(p.torque_min <= p.torque && p.torque <= p.torque_max);
    assert_eq!(p.turns_from, c.turns);
}

/// Slope dz/dn: a least-squares slope is a weighted mean of the pairwise
/// difference quotients (z_j − z_i)/(n_j − n_i), each a mean of the
/// consecutive ones, so it lies within the range of the consecutive
/// finite differences of the leg's points (exact bound); and it is within
/// 25 % of the end-to-end finite difference (the 300 bp leg is not a
/// straight line: the tolerance is the picture's, measured 8 %); and it is
/// the least-squares slope of those points, computed here.
#[test]
fn slope_is_bounded_by_the_finite_differences() {
    let (_, curve, s) = scene();
    let p = s.plateau.value.unwrap();
    let c = curve.coexistence.unwrap();
    let leg = &curve.legs[c.plectoneme_leg];
    let mut pts: Vec<(f64, f64)> = vec![(c.turns, c.extension_plectoneme)];
    pts.extend(
        (leg.first..=leg.last).map(|k| &curve.points[k]).filter(|q| q.phi > c.phi).map(|q| (q.turns, q.extension)),
    );
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let fd: Vec<f64> = pts.windows(2).map(|w| (w[1].1 - w[0].1) / (w[1].0 - w[0].0)).collect();
    let (lo, hi) = fd.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &d| (a.min(d), b.max(d)));
    let (a, b) = (pts[0], pts[pts.len() - 1]);
    let end_to_end = (b.1 - a.1) / (b.0 - a.0);
    println!("slope {:.4} nm/turn; consecutive differences {lo:.4}…{hi:.4}; end to end {end_to_end:.4}", p.slope);
    assert!(p.slope < 0.0, "the plectoneme shortens the rod");
    assert!(lo - 1e-9 * lo.abs() <= p.slope && p.slope <= hi + 1e-9 * hi.abs());
    assert!((p.slope - end_to_end).abs() <= 0.25 * end_to_end.abs());
    // The least-squares line through the same points, written here: the
    // summary's slope must be it (any other weighted mean of the differences
    // passes the bounds above), to rounding.
    let n = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|q| q.0).sum::<f64>() / n, pts.iter().map(|q| q.1).sum::<f64>() / n);
    let sxy: f64 = pts.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|q| (q.0 - mx).powi(2)).sum();
    let least_squares = sxy / sxx;
    println!("least squares here {least_squares:.10} vs summary {:.10}", p.slope);
    assert!((p.slope - least_squares).abs() <= 1e-10 * least_squares.abs(), "{} vs {least_squares}", p.slope);
}

/// Superhelix radius: the closest approach of distinct strands at the last
/// point against a brute force over all pairs of its profile points farther
/// apart along the rod than a gap G: for G = 5 and 10 nm (past a strand's
/// own neighbourhood, shorter than the end loop's path between the
/// strands) the same pair, so the same distance bitwise; and the radius is
/// above the rod radius a (the strands do not overlap: the hard core is
/// not on in this scene).
#[test]
fn superhelix_radius_is_the_closest_strand_approach() {
    let (run, _, s) = scene();
    let h = s.superhelix.value.expect("a superhelix");
    let x = run.states.last().unwrap();
    let prof = run.rod.profile_offsets();
    let r: Vec<[f64; 3]> = prof.iter().map(|&(_, o)| [x[o], x[o + 1], x[o + 2]]).collect();
    let sa: Vec<f64> = prof.iter().map(|q| q.0).collect();
    for gap in [5.0, 10.0] {
        let mut best = f64::INFINITY;
        for i in 0..r.len() {
            for j in i + 1..r.len() {
                if sa[j] - sa[i] > gap {
                    let d = ((r[i][0] - r[j][0]).powi(2) + (r[i][1] - r[j][1]).powi(2) + (r[i][2] - r[j][2]).powi(2))
                        .sqrt();
                    best = best.min(d);
                }
            }
        }
        println!("gap {gap} nm: brute force {best:.6} nm, summary {:.6} nm (radius {:.4})", h.distance, h.radius);
        assert!((best - h.distance).abs() <= 1e-12 * best);
    }
    assert_eq!(h.radius, 0.5 * h.distance);
    assert!(h.radius > run.scene.radius);
    assert_eq!(h.turns, run.points.last().unwrap().observables.turns);
}

/// strand_approach on curves with known answers: a straight line never
/// comes back (None); a hairpin of two parallel lines 2R apart joined by a
/// half circle has its closest distinct-strand approach 2R.
#[test]
fn strand_approach_on_known_curves() {
    let line: Vec<[f64; 3]> = (0..50).map(|i| [0.0, 0.0, i as f64]).collect();
    let s: Vec<f64> = (0..50).map(|i| i as f64).collect();
    assert!(strand_approach(&line, &s).is_none());
    let (rr, n) = (2.5, 40);
    let mut pts = Vec::new();
    for i in 0..n {
        pts.push([-rr, 0.0, i as f64]);
    }
    for k in 1..20 {
        let t = std::f64::consts::PI * k as f64 / 20.0;
        pts.push([-rr * t.cos(), 0.0, n as f64 - 1.0 + rr * t.sin()]);
    }
    for i in (0..n).rev() {
        pts.push([rr, 0.0, i as f64]);
    }
    let s: Vec<f64> = (0..pts.len()).map(|i| i as f64).collect();
    let (d, _, _) = strand_approach(&pts, &s).unwrap();
    assert!((d - 2.0 * rr).abs() <= 1e-12, "{d}");
}

/// The C summary of the same scene run through the C ABI equals the Rust
/// summary field by field, bitwise (the run is deterministic: same path).
#[test]
fn c_summary_equals_rust() {
    let (_, _, s) = scene();
    let mut spec = std::mem::MaybeUninit::<DnaSupercoilSpec>::uninit();
    assert_eq!(unsafe { rodkit_dna_supercoil_spec_default(spec.as_mut_ptr()) }, 0);
    let mut spec = unsafe { spec.assume_init() };
    (spec.base_pairs, spec.elements, spec.max_turns, spec.max_steps) =
        (BASE_PAIRS as i64, ELEMENTS as i64, MAX_TURNS, MAX_STEPS as i64);
    let mut run = std::ptr::null_mut();
    assert!(unsafe { rodkit_dna_supercoil_run(&spec, &mut run) } >= 0);
    let mut c = SupercoilCurveInfo::default();
    assert_eq!(unsafe { rodkit_supercoil_curve_summary(run, &mut c) }, 0);
    let (i, co, p, h) = (
        s.instability.value.unwrap(),
        s.coexistence.value.unwrap(),
        s.plateau.value.unwrap(),
        s.superhelix.value.unwrap(),
    );
    let found = SummaryFinding::Found as i32;
    assert_eq!((c.instability_finding, c.instability_turns, c.instability_torque), (found, i.turns, i.torque));
    assert_eq!(
        (c.coexistence_finding, c.coexistence_turns, c.coexistence_torque_straight, c.coexistence_torque_plectoneme),
        (found, co.turns, co.torque_straight, co.torque_plectoneme)
    );
    assert_eq!(
        (c.coexistence_extension_straight, c.coexistence_extension_plectoneme, c.coexistence_extension_jump),
        (co.extension_straight, co.extension_plectoneme, co.extension_jump)
    );
    assert_eq!(
        (c.plateau_finding, c.plateau_torque, c.plateau_torque_min, c.plateau_torque_max, c.slope),
        (found, p.torque, p.torque_min, p.torque_max, p.slope)
    );
    assert_eq!((c.plateau_turns_from, c.plateau_turns_to, c.plateau_nodes), (p.turns_from, p.turns_to, p.nodes as i64));
    assert_eq!(
        (c.superhelix_finding, c.superhelix_radius, c.strand_distance, c.strand_s1, c.strand_s2, c.superhelix_turns),
        (found, h.radius, h.distance, h.s1, h.s2, h.turns)
    );
    // The curve's points: as many as the path's, energies finite.
    let mut count = 0;
    // The size query: NULL buffer, capacity 0, INFO_TRUNCATED with the count.
    let truncated = rodkit::Status::InfoTruncated.code();
    assert_eq!(unsafe { rodkit_supercoil_curve_points(run, std::ptr::null_mut(), 0, &mut count) }, truncated);
    let mut pts = vec![SupercoilCurvePoint::default(); count as usize];
    assert_eq!(unsafe { rodkit_supercoil_curve_points(run, pts.as_mut_ptr(), count, &mut count) }, 0);
    let (r, curve, _) = scene();
    assert_eq!(pts.len(), curve.points.len());
    // Each point's σ: the run's own record (its window's negative count,
    // neutral count and σ nearest zero), read here from the branches'
    // records, not through the library's point lookup.
    let recs: Vec<_> = r.straight.records.iter().chain(r.buckled.iter().flat_map(|b| b.records.iter())).collect();
    let (mut with_sigma, mut neutral_negative) = (0, 0);
    for (a, b) in pts.iter().zip(&curve.points) {
        assert_eq!(
            (a.turns, a.energy, a.negative_modes),
            (b.turns, b.energy, b.negative_modes.map_or(-1, |m| m as i64))
        );
        let st = recs[b.index].stability.as_ref().unwrap();
        assert_eq!(a.negative_sigma, st.negative.map_or(-1, |m| m as i64));
        assert_eq!(a.neutral_modes, st.marginal as i64);
        assert_eq!((a.has_sigma, a.sigma_nearest), st.sigma.first().map_or((0, 0.0), |&v| (1, v)));
        // Unstable modes are among the negative σ; with none negative the
        // nearest σ is not below zero.
        if a.negative_modes >= 0 && a.negative_sigma >= 0 {
            assert!(a.negative_modes <= a.negative_sigma, "{a:?}");
            neutral_negative += (a.negative_modes < a.negative_sigma) as usize;
        }
        if a.negative_sigma == 0 && a.has_sigma == 1 {
            assert!(a.sigma_nearest >= 0.0, "{a:?}");
        }
        with_sigma += a.has_sigma as usize;
    }
    println!("{} points, {with_sigma} with a σ, {neutral_negative} with neutral negative σ", pts.len());
    assert!(with_sigma > pts.len() / 2);
    // NULL arguments are refused with a status, not a crash.
    assert!(unsafe { rodkit_supercoil_curve_summary(std::ptr::null(), &mut c) } < 0);
    assert!(unsafe { rodkit_supercoil_curve_summary(run, std::ptr::null_mut()) } < 0);
    unsafe { rodkit_supercoil_free(run) };
}

/// Without a buckling point (3 steps) every finding is NotReached and
/// carries no number; a run stopped on the buckled branch's unstable leg
/// (30 steps, before the fold where the plectoneme becomes stable:
/// tests/supercoil_energy.rs) reports the instability but no coexistence
/// point and no plateau, with the reason.
#[test]
fn nothing_made_up_before_the_plectoneme() {
    let scene = DnaScene { base_pairs: BASE_PAIRS, ..Default::default() };
    let settings = SupercoilSettings { elements: ELEMENTS, max_turns: MAX_TURNS, max_steps: 3, ..Default::default() };
    let run = dna::run_scene(&scene, &settings).unwrap();
    assert!(run.buckling.is_none());
    let s = summarise_with(&run, Some(&equilibrium_curve(&run).unwrap()));
    for f in [s.instability.finding, s.coexistence.finding, s.plateau.finding, s.superhelix.finding] {
        assert_eq!(f, Finding::NotReached);
    }
    assert!(s.instability.value.is_none() && s.plateau.value.is_none() && s.superhelix.value.is_none());
    let settings = SupercoilSettings { elements: ELEMENTS, max_turns: MAX_TURNS, max_steps: 30, ..Default::default() };
    let run = dna::run_scene(&scene, &settings).unwrap();
    let s = summarise_with(&run, Some(&equilibrium_curve(&run).unwrap()));
    assert_eq!(s.instability.finding, Finding::Found);
    assert_ne!(s.coexistence.finding, Finding::Found);
    assert!(s.coexistence.value.is_none() && s.plateau.value.is_none() && s.note.is_some());
}

/// 300 bp at 2 pN, 0.1 M to 2.2 turns (40 elements), stability by the
/// parity rules alone (no counts): the buckled branch's stability becomes
/// undetermined (a bifurcation on it), so the coexistence is Undetermined
/// — no number, a note saying why — and the plateau is Unverified:
/// measured on the branch's last leg increasing in turns, beyond the
/// instability. Reference: the test's own walk back from the last point
/// while φ decreases, and its own trapezoid φ-average and least-squares
/// slope over those points (relative 1e-12: the same sums in another
/// order). With the counts (the default) the same scene has its points
/// decided but where a mode in the neutral band is carried across a change
/// of the negative count (`carry_band_entries`: a point or two past the
/// last fold, depending on the steps taken), far fewer than the parity
/// rules leave, and the summary says what the curve shows instead.
#[test]
fn undetermined_stability_gives_an_unverified_plateau() {
    let scene = DnaScene { base_pairs: BASE_PAIRS, tension: 2.0, ..Default::default() };
    let settings = SupercoilSettings { elements: ELEMENTS, max_turns: 2.2, max_steps: MAX_STEPS, ..Default::default() };
    let counted = dna::run_scene(&scene, &settings).unwrap();
    let undecided = |run: &SupercoilRun| {
        rodkit::charged::coexistence::negative_modes(run).unwrap().iter().filter(|m| m.is_none()).count()
    };
    let s = summarise_with(&counted, Some(&equilibrium_curve(&counted).unwrap()));
    assert_ne!(s.coexistence.finding, Finding::Undetermined, "{:?}", s.note);
    let settings = SupercoilSettings { stability: None, ..settings };
    let run = dna::run_scene(&scene, &settings).unwrap();
    let (by_counts, by_rules) = (undecided(&counted), undecided(&run));
    println!(
        "undetermined points: {by_counts} of {} counted, {by_rules} of {} by the rules",
        counted.points.len(),
        run.points.len()
    );
    assert!(4 * by_counts < by_rules, "counted {by_counts}, rules {by_rules}");
    let curve = equilibrium_curve(&run).unwrap();
    let s = summarise_with(&run, Some(&curve));
    println!("2 pN: coexistence {:?}, note {:?}", s.coexistence.finding, s.note);
    assert_eq!(s.coexistence.finding, Finding::Undetermined);
    assert!(s.coexistence.value.is_none() && s.note.as_deref().unwrap().contains("undetermined"));
    assert!(curve.points.iter().any(|p| p.negative_modes.is_none()));
    assert_eq!(s.plateau.finding, Finding::Unverified);
    let p = s.plateau.value.unwrap();
    let (phi_b, _) = run.buckling.unwrap();
    let pts = &run.points;
    let mut k = pts.len() - 1;
    while pts[k - 1].branch == 1 && pts[k - 1].phi < pts[k].phi {
        k -= 1;
    }
    let leg: Vec<_> = pts[k..].iter().filter(|q| q.phi >= phi_b).collect();
    assert_eq!(leg.len(), p.nodes);
    let work: f64 =
        leg.windows(2).map(|w| 0.5 * (w[0].observables.torque + w[1].observables.torque) * (w[1].phi - w[0].phi)).sum();
    let mean = work / (leg[leg.len() - 1].phi - leg[0].phi);
    let n = leg.len() as f64;
    let (mx, my) =
        leg.iter().fold((0.0, 0.0), |(a, b), q| (a + q.observables.turns / n, b + q.observables.extension / n));
    let (sxy, sxx) = leg.iter().fold((0.0, 0.0), |(a, b), q| {
        let dx = q.observables.turns - mx;
        (a + dx * (q.observables.extension - my), b + dx * dx)
    });
    println!(
        "unverified plateau {:.5} (reference {mean:.5}), slope {:.4} (reference {:.4}), {} nodes",
        p.torque,
        p.slope,
        sxy / sxx,
        p.nodes
    );
    assert!((p.torque - mean).abs() <= 1e-12 * mean.abs());
    assert!((p.slope - sxy / sxx).abs() <= 1e-12 * p.slope.abs());
    assert_eq!(p.turns_from, leg[0].observables.turns);
}

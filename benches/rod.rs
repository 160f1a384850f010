//! Rod continuation benchmark (`cargo bench --bench rod [--features
//! sundials]`): the cubic ANM against Newton pseudo-arc-length continuation
//! on the same discretisation in the same process, SUNDIALS KINSOL
//! (natural-parameter continuation, with the feature) and the peer AUTO-07p
//! (run as a subprocess, timed by its own process CPU time — getrusage of
//! the child, start-up and files included; skipped with a message when not
//! installed).
//!
//! Scenes (physics.md §2.6): the cantilever K_b = 1, C = 1/1.3, GA = 1e4,
//! EA = 2.6e4, L = 1 with a tip force Λ(1, 0, 0), follower (body frame,
//! perpendicular to the tip tangent) or dead (transverse), α 0 → 10; and
//! Euler buckling + post-buckling of the clamped–free rod.
//! 1. tips at α = 1, 2, 5, 10 from one run (dense samples), error max
//!    |r(L) − r_ref(L)|/L against Gauss(4) × 64 at residual 1e−12;
//! 2. the branch densely (100 loads), ANM vs Newton factorisations;
//! 3. buckling, location, switch, post-buckled branch (AUTO's euler too);
//! 4. the ANM's knobs (P, ε).
//!
//! Time: median of REPS interleaved repetitions. Writes target/bench/rod/
//! {report.txt, tips.csv, dense.csv, post_buckling.csv, anm_knobs.csv,
//! follower_work_precision.svg}.

#[path = "support/auto07p.rs"]
mod auto07p;
#[path = "support/plot.rs"]
mod plot;
#[path = "support/timing.rs"]
mod timing;
use timing::{max_distance as err, median, ms};
#[cfg(feature = "sundials")]
#[path = "../tests/support/rod_band.rs"]
mod rod_band;
#[cfg(feature = "sundials")]
#[path = "../tests/support/sundials.rs"]
mod sundials;

/// KINSOL's work for one run: (iterations, Jacobian evaluations, residual
/// evaluations).
type KinsolCounts = (i64, i64, i64);

/// The tips at the four α from one KINSOL run, its counts and the times of
/// every repetition.
type KinsolRuns = (Vec<[f64; 3]>, KinsolCounts, Vec<Duration>);

/// The reference tips of a scene at the given loads.
type TipReference<'a> = dyn Fn(Scene, &[f64]) -> Vec<[f64; 3]> + 'a;

/// SUNDIALS as a peer (`--features sundials`): natural-parameter
/// continuation as a user without a continuation code would do it — α
/// stepped by 0.25 from 0 to 10 (through 1, 2, 5, 10), each KINSOL solve
/// (exact Newton, rodkit's analytic Jacobian, band direct solver on the
/// rows reordered to a band, scaled like rodkit's residual tolerance 1e−10)
/// started from the previous solution. Returns the tips at the four α,
/// (KINSOL iterations, Jacobian evaluations, residual evaluations), time.
#[cfg(feature = "sundials")]
fn run_kinsol(rod: &Rod, tol: f64) -> Result<(Vec<[f64; 3]>, KinsolCounts, Duration), String> {
    use rodkit::continuation::Problem;
    let t = Instant::now();
    let ctx = sundials::Context::new()?;
    let sys = rod.system().map_err(|e| e.message)?;
    let n = sys.dim();
    let pattern = sys.pattern().clone();
    let (order, upper, lower) = rod_band::band_layout(&pattern);
    let mut position = vec![0; n];
    for (new, &old) in order.iter().enumerate() {
        position[old] = new;
    }
    let eq = sys.equation_scales();
    let (us, _) = sys.unknown_scales();
    let sys = std::cell::RefCell::new(sys);
    let opts = sundials::KinsolOptions {
        func_norm_tol: tol,
        scaled_step_tol: 1e-16,
        max_setup_calls: 1,
        u_scale: Some(us.iter().map(|s| 1.0 / s).collect()),
        f_scale: Some(order.iter().map(|&i| 1.0 / eq[i]).collect()),
        ..Default::default()
    };
    let mut x = rod.straight_state();
    let mut tips = vec![];
    let mut totals = (0, 0, 0);
    let mut r = vec![0.0; n];
    let mut vals = vec![0.0; pattern.nnz()];
    let mut dl = vec![0.0; n];
    for step in 1..=40 {
        let lambda = 0.25 * step as f64;
        let residual = |u: &[f64], f: &mut [f64]| {
            sys.borrow_mut().residual(u, lambda, &mut r);
            for i in 0..n {
                f[position[i]] = r[i];
            }
        };
        let mut jac = |u: &[f64], m: &mut sundials::BandView| {
            sys.borrow_mut().jacobian(u, lambda, &mut vals, &mut dl);
            for j in 0..n {
                for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                    let i = position[pattern.row_idx[k]];
                    if j <= i + upper && i <= j + lower {
                        m.set(i, j, vals[k]);
                    }
                }
            }
        };
        let stats = sundials::kinsol_solve_band(&ctx, &mut x, residual, &mut jac, upper, lower, &opts)?;
        totals.0 += stats.iterations;
        totals.1 += stats.jacobian_evals;
        totals.2 += stats.residual_evals;
        if ALPHAS.contains(&lambda) {
            tips.push(rod.tip(&x));
        }
    }
    Ok((tips, totals, t.elapsed()))
}

use plotters::prelude::RGBColor;
use rodkit::continuation::anm::{continue_anm, AnmOptions};
use rodkit::continuation::newton::{continue_newton, Start};
use rodkit::continuation::{Branch, Counts, Options, Stop};
use rodkit::rod::branch::Method;
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::time::{Duration, Instant};

const ALPHAS: [f64; 4] = [1.0, 2.0, 5.0, 10.0];
const REPS: usize = 5;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scene {
    /// Tip force Λ(1, 0, 0) in the body frame: perpendicular to the tip tangent.
    Follower,
    /// Tip force Λ(1, 0, 0) fixed in space: transverse dead load.
    Dead,
}

fn rod(scene: Scene, scheme: Scheme, n: usize) -> Rod {
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let load = match scene {
        Scene::Follower => Load::follower([1.0, 0.0, 0.0]),
        Scene::Dead => Load::dead([1.0, 0.0, 0.0]),
    };
    let loads = Loads { tip_force: Some(load), ..Default::default() };
    Rod::new(law, 1.0, loads, Supports::Cantilever, scheme, n).unwrap()
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Engine {
    Anm { order: usize, epsilon: f64, pade: bool },
    Newton,
}

impl Engine {
    fn name(&self) -> String {
        match self {
            Engine::Anm { order, epsilon, pade } => {
                format!("rodkit ANM{} P={order} ε={epsilon:.0e}", if *pade { " Padé" } else { "" })
            }
            Engine::Newton => "rodkit Newton".into(),
        }
    }
}

/// One run α 0 → 10 delivering the tip at each of `loads` (dense output:
/// the ANM from its series, Newton from its interpolant, each corrected to
/// `tol`); the work done, the wall time (model set-up included).
fn run(rod: &Rod, engine: Engine, tol: f64, loads: &[f64]) -> (Vec<[f64; 3]>, Counts, Duration) {
    let t = Instant::now();
    let mut sys = rod.system().unwrap();
    let start = Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true };
    let opts = Options {
        target_lambda: Some(10.0),
        residual_tol: tol,
        initial_step: 0.2,
        max_step: 10.0,
        max_steps: 2000,
        samples: loads.to_vec(),
        ..Default::default()
    };
    let observe = |x: &[f64], _: f64| rod.tip(x).to_vec();
    let b: Branch = match engine {
        Engine::Anm { order, epsilon, pade } => {
            continue_anm(&mut sys, start, &opts, &AnmOptions { order, epsilon, pade }, observe, |_| true).unwrap()
        }
        Engine::Newton => continue_newton(&mut sys, start, &opts, observe, |_| true).unwrap(),
    };
    let elapsed = t.elapsed();
    assert_eq!(b.stop, Stop::Target, "{engine:?} did not reach α = 10");
    assert!(b.missed_samples.is_empty(), "{engine:?} missed samples {:?}", b.missed_samples);
    let tips: Vec<[f64; 3]> = b.samples.iter().map(|s| [s.outputs[0], s.outputs[1], s.outputs[2]]).collect();
    assert_eq!(
        tips.len(),
        loads.len(),
        "{engine:?}: samples {:?}",
        b.samples.iter().map(|s| s.lambda).collect::<Vec<_>>()
    );
    (tips, b.counts, elapsed)
}

struct Row {
    scene: Scene,
    method: String,
    disc: String,
    unknowns: usize,
    time: Duration,
    error: f64,
    counts: Option<Counts>,
    auto_steps: Option<(usize, usize)>,
}

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench/rod");
    fs::create_dir_all(&dir).unwrap();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "rodkit {} rod continuation benchmark (cantilever, tip force α 0 → 10; follower and dead load)",
        env!("CARGO_PKG_VERSION")
    );
    let dense: Vec<f64> = (1..=100).map(|k| 0.1 * k as f64).collect();
    let references = reference_tips(&mut out, &dense);
    let reference = |scene: Scene, loads: &[f64]| -> Vec<[f64; 3]> {
        let all = &references.iter().find(|r| r.0 == scene).unwrap().1;
        loads.iter().map(|&l| all[(l * 10.0).round() as usize - 1]).collect()
    };
    let setup = TipsSetup::new();
    let runs = setup.run(&mut out);
    let rows = setup.rows(&runs, &reference);
    if cfg!(not(feature = "sundials")) {
        let _ =
            writeln!(out, "SUNDIALS rows need `--features sundials` (natural-parameter KINSOL continuation): skipped");
    }
    if !setup.auto_ok {
        let _ = writeln!(out, "AUTO-07p not installed (apt-get install auto-07p): peer rows skipped");
    }
    let csv = write_tip_table(&mut out, &rows);
    write_tip_summaries(&mut out, &rows, &setup);
    section_dense(&mut out, &dir, &dense, &reference);
    section_post_buckling(&mut out, &dir, setup.auto_ok);
    section_anm_knobs(&mut out, &dir);
    print!("{out}");
    fs::write(dir.join("report.txt"), &out).unwrap();
    fs::write(dir.join("tips.csv"), &csv).unwrap();
    if let Err(e) = plot(&dir.join("follower_work_precision.svg"), &rows) {
        eprintln!("plot failed: {e}");
    }
}

/// References: Gauss(4) × 64 at residual 1e-12, Newton, tips at every load
/// of `dense` (which holds every load used), per scene.
fn reference_tips(out: &mut String, dense: &[f64]) -> Vec<(Scene, Vec<[f64; 3]>)> {
    let mut references = vec![];
    for scene in [Scene::Follower, Scene::Dead] {
        let fine = rod(scene, Scheme::Gauss(4), 64);
        let (tips, _, _) = run(&fine, Engine::Newton, 1e-12, dense);
        let _ = writeln!(
            out,
            "reference {scene:?}: Gauss(4) × 64, residual 1e-12: tips at α = 1, 2, 5, 10: {:?}",
            [tips[9], tips[19], tips[49], tips[99]]
        );
        references.push((scene, tips));
    }
    references
}

/// Section 1's grid: scenes × discretisations × engines (and KINSOL), and
/// AUTO-07p's meshes when it is installed; residual tolerance 1e-10.
struct TipsSetup {
    tol: f64,
    configs: Vec<(Scheme, usize)>,
    engines: [Engine; 3],
    scenes: [Scene; 2],
    auto_ntst: [usize; 3],
    auto_ok: bool,
}

/// What section 1's interleaved repetitions measured, indexed by
/// [`TipsSetup::key`] (KINSOL by scene and discretisation, AUTO by mesh).
struct TipRuns {
    times: Vec<Vec<Duration>>,
    results: Vec<Option<(Vec<[f64; 3]>, Counts)>>,
    auto_times: Vec<Vec<Duration>>,
    auto_results: Vec<Option<auto07p::AutoRun>>,
    kinsol_results: Vec<Option<KinsolRuns>>,
}

impl TipsSetup {
    fn new() -> Self {
        TipsSetup {
            tol: 1e-10,
            configs: vec![
                (Scheme::Midpoint, 16),
                (Scheme::Gauss(2), 4),
                (Scheme::Gauss(4), 4),
                (Scheme::Gauss(4), 8),
                (Scheme::Gauss(4), 16),
                (Scheme::Gauss(4), 32),
                (Scheme::Gauss(2), 16),
                (Scheme::Midpoint, 64),
            ],
            engines: [
                Engine::Anm { order: 20, epsilon: 1e-10, pade: false },
                Engine::Anm { order: 20, epsilon: 1e-10, pade: true },
                Engine::Newton,
            ],
            scenes: [Scene::Follower, Scene::Dead],
            auto_ntst: [4usize, 8, 16],
            auto_ok: auto07p::available(),
        }
    }

    fn key(&self, si: usize, ci: usize, ei: usize) -> usize {
        (si * self.configs.len() + ci) * self.engines.len() + ei
    }

    /// Section 1: tips at α = 1, 2, 5, 10, every engine, KINSOL and AUTO,
    /// REPS interleaved repetitions (failures of the peers reported in
    /// `out`).
    fn run(&self, out: &mut String) -> TipRuns {
        let (scenes, configs, engines, auto_ntst, tol) =
            (&self.scenes, &self.configs, &self.engines, &self.auto_ntst, self.tol);
        let mut times: Vec<Vec<Duration>> = vec![vec![]; scenes.len() * configs.len() * engines.len()];
        let mut results: Vec<Option<(Vec<[f64; 3]>, Counts)>> = vec![None; times.len()];
        let mut auto_times: Vec<Vec<Duration>> = vec![vec![]; auto_ntst.len()];
        let mut auto_results: Vec<Option<auto07p::AutoRun>> = vec![None; auto_ntst.len()];
        #[allow(unused_mut)] // filled only with the sundials feature
        let mut kinsol_results: Vec<Option<KinsolRuns>> = vec![None; scenes.len() * configs.len()];
        for _ in 0..REPS {
            for (si, &scene) in scenes.iter().enumerate() {
                for (ci, &(scheme, n)) in configs.iter().enumerate() {
                    let r = rod(scene, scheme, n);
                    for (ei, &engine) in engines.iter().enumerate() {
                        let (tips, counts, t) = run(&r, engine, tol, &ALPHAS);
                        times[self.key(si, ci, ei)].push(t);
                        results[self.key(si, ci, ei)] = Some((tips, counts));
                    }
                    #[cfg(feature = "sundials")]
                    match run_kinsol(&r, tol) {
                        Ok((tips, counts, t)) => {
                            let entry = kinsol_results[si * configs.len() + ci].get_or_insert((tips, counts, vec![]));
                            entry.2.push(t);
                        }
                        Err(e) => {
                            let _ = writeln!(out, "KINSOL {scene:?} {scheme:?} × {n} failed: {e}");
                        }
                    }
                }
            }
            if self.auto_ok {
                for (ai, &ntst) in auto_ntst.iter().enumerate() {
                    match auto07p::follower(ntst, tol) {
                        Ok(run) => {
                            auto_times[ai].push(run.cpu);
                            auto_results[ai] = Some(run);
                        }
                        Err(e) => {
                            let _ = writeln!(out, "AUTO-07p NTST {ntst} failed: {e}");
                        }
                    }
                }
            }
        }
        TipRuns { times, results, auto_times, auto_results, kinsol_results }
    }

    /// The table's rows: every engine and KINSOL per scene and
    /// discretisation, then AUTO's meshes (medians, tip errors against the
    /// reference).
    fn rows(&self, runs: &TipRuns, reference: &TipReference<'_>) -> Vec<Row> {
        let mut rows = vec![];
        for (si, &scene) in self.scenes.iter().enumerate() {
            for (ci, &(scheme, n)) in self.configs.iter().enumerate() {
                let unknowns = rod(scene, scheme, n).unknowns();
                for (ei, &engine) in self.engines.iter().enumerate() {
                    let k = self.key(si, ci, ei);
                    let (tips, counts) = runs.results[k].clone().unwrap();
                    rows.push(Row {
                        scene,
                        method: engine.name(),
                        disc: format!("{scheme:?} × {n}"),
                        unknowns,
                        time: median(runs.times[k].clone()),
                        error: err(&tips, &reference(scene, &ALPHAS)),
                        counts: Some(counts),
                        auto_steps: None,
                    });
                }
                if let Some((tips, (iters, jacs, res), times)) = &runs.kinsol_results[si * self.configs.len() + ci] {
                    rows.push(Row {
                        scene,
                        method: "SUNDIALS KINSOL band".into(),
                        disc: format!("{scheme:?} × {n}"),
                        unknowns,
                        time: median(times.clone()),
                        error: err(tips, &reference(scene, &ALPHAS)),
                        counts: Some(Counts {
                            steps: 40,
                            factorisations: *jacs as usize,
                            solves: *iters as usize,
                            residuals: *res as usize,
                            jacobians: *jacs as usize,
                            ..Default::default()
                        }),
                        auto_steps: None,
                    });
                }
            }
        }
        for (ai, &ntst) in self.auto_ntst.iter().enumerate() {
            if let Some(run) = &runs.auto_results[ai] {
                let tips: Vec<[f64; 3]> =
                    ALPHAS.iter().map(|&a| run.at_lambda(a).map(|p| p.tip_at(a)).unwrap_or([f64::NAN; 3])).collect();
                rows.push(Row {
                    scene: Scene::Follower,
                    method: "AUTO-07p".into(),
                    disc: format!("NTST {ntst} NCOL 4"),
                    unknowns: 13 * (4 * ntst + 1),
                    time: median(runs.auto_times[ai].clone()),
                    error: err(&tips, &reference(Scene::Follower, &ALPHAS)),
                    counts: None,
                    auto_steps: Some((run.steps, run.newton_iterations)),
                });
            }
        }
        rows
    }
}

/// AUTO-07p's row whose tip error is nearest to `e` (in log), among `autos`.
fn nearest_auto(autos: &[&Row], e: f64) -> Option<Duration> {
    autos.iter().min_by(|a, b| (a.error.ln() - e.ln()).abs().total_cmp(&(b.error.ln() - e.ln()).abs())).map(|r| r.time)
}

/// Section 1's table (one line per row, with the ratios to rodkit Newton,
/// the factorisation ratio and the ratio to AUTO at the nearest tip error);
/// returns tips.csv.
fn write_tip_table(out: &mut String, rows: &[Row]) -> String {
    let _ = writeln!(out, "\n1. Tips at α = 1, 2, 5, 10 (one run to α = 10; rodkit delivers them as dense samples), residual tolerance 1e-10 (scaled), medians of {REPS} interleaved runs.");
    let _ = writeln!(out, "   Ratios: time / rodkit Newton's on the same discretisation; factorisations Newton / ANM; time / AUTO's at the nearest tip error.");
    let _ = writeln!(
        out,
        "{:<9} {:<26} {:<16} {:>6} {:>10} {:>9} {:>6} {:>7} {:>7} {:>8} {:>7} {:>8} {:>9} {:>8}",
        "scene",
        "method",
        "discretisation",
        "n",
        "time",
        "tip err",
        "steps",
        "factor.",
        "Jacob.",
        "resid.",
        "orders",
        "/Newton",
        "fact.N/A",
        "/AUTO"
    );
    let mut csv = String::from("scene,method,discretisation,unknowns,time_s,tip_error,steps,factorisations,jacobians,residuals,series_orders\n");
    let autos: Vec<&Row> = rows.iter().filter(|r| r.method == "AUTO-07p").collect();
    for r in rows {
        let newton = rows.iter().find(|o| o.scene == r.scene && o.disc == r.disc && o.method == "rodkit Newton");
        let ratio = |base: Option<Duration>| {
            base.map_or("-".to_string(), |b| format!("{:.2}", r.time.as_secs_f64() / b.as_secs_f64()))
        };
        let (steps, fact, jac, res, ord) = match (&r.counts, r.auto_steps) {
            (Some(c), _) => (
                c.steps.to_string(),
                c.factorisations.to_string(),
                c.jacobians.to_string(),
                c.residuals.to_string(),
                c.series_orders.to_string(),
            ),
            (None, Some((s, newton_it))) => {
                (s.to_string(), format!("~{newton_it}"), "-".into(), "-".into(), "-".into())
            }
            _ => ("-".into(), "-".into(), "-".into(), "-".into(), "-".into()),
        };
        let fact_ratio = match (r.method.starts_with("rodkit ANM"), newton.and_then(|o| o.counts), r.counts) {
            (true, Some(nc), Some(ac)) => format!("{:.1}", nc.factorisations as f64 / ac.factorisations as f64),
            _ => "-".into(),
        };
        let _ = writeln!(
            out,
            "{:<9} {:<26} {:<16} {:>6} {:>8.2}ms {:>9.1e} {:>6} {:>7} {:>7} {:>8} {:>7} {:>8} {:>9} {:>8}",
            format!("{:?}", r.scene),
            r.method,
            r.disc,
            r.unknowns,
            ms(r.time),
            r.error,
            steps,
            fact,
            jac,
            res,
            ord,
            if r.method.starts_with("rodkit") || r.method.starts_with("SUNDIALS") {
                ratio(newton.map(|o| o.time))
            } else {
                "-".into()
            },
            fact_ratio,
            if r.scene == Scene::Follower { ratio(nearest_auto(&autos, r.error)) } else { "-".into() }
        );
        let _ = writeln!(
            csv,
            "{:?},{},{},{},{},{},{},{},{},{},{}",
            r.scene,
            r.method,
            r.disc,
            r.unknowns,
            r.time.as_secs_f64(),
            r.error,
            steps,
            fact,
            jac,
            res,
            ord
        );
    }
    let _ = writeln!(out, "(AUTO: follower only; 'factor.' is its Newton iteration count, each factorising its collocation matrix; tips moved to the exact α along AUTO's tangent.");
    let _ = writeln!(out, " KINSOL: natural-parameter continuation α += 0.25, band solver on rows reordered to a band; 'steps' = solves, 'factor.' = Jacobian evaluations)");
    csv
}

/// After section 1's table: the fastest rodkit against the fastest AUTO at
/// the two accuracies the issue names, and the cost per unknown of the
/// Gauss(4) rows against N.
fn write_tip_summaries(out: &mut String, rows: &[Row], setup: &TipsSetup) {
    let autos: Vec<&Row> = rows.iter().filter(|r| r.method == "AUTO-07p").collect();
    for target in [1e-6, 1e-8] {
        let best = rows
            .iter()
            .filter(|r| r.scene == Scene::Follower && r.method.starts_with("rodkit") && r.error <= target)
            .min_by_key(|r| r.time);
        let auto = autos.iter().filter(|r| r.error <= target).min_by_key(|r| r.time);
        match (best, auto) {
            (Some(b), Some(a)) => {
                let _ = writeln!(out, "tip error ≤ {target:.0e}: fastest rodkit {} {} {:.2} ms (error {:.1e}), fastest AUTO-07p {} {:.2} ms (error {:.1e}): AUTO / rodkit = {:.1} — AUTO at its fixed EPSL = EPSU = 1e-10, DSMAX 0.5, IAD 3, not its cheapest setting: see `cargo bench --bench rod_frontier`", b.method, b.disc, ms(b.time), b.error, a.disc, ms(a.time), a.error, a.time.as_secs_f64() / b.time.as_secs_f64());
            }
            _ => {
                let _ = writeln!(out, "tip error ≤ {target:.0e}: no rodkit or no AUTO row reaches it");
            }
        }
    }
    // Cost against N (Gauss(4) rows): time per unknown.
    for scene in setup.scenes {
        for engine in setup.engines {
            let pts: Vec<String> = rows
                .iter()
                .filter(|r| r.scene == scene && r.method == engine.name() && r.disc.starts_with("Gauss(4)"))
                .map(|r| format!("n {} {:.1} µs/unknown", r.unknowns, 1e6 * r.time.as_secs_f64() / r.unknowns as f64))
                .collect();
            let _ = writeln!(out, "cost vs N, {scene:?}, {}: {}", engine.name(), pts.join("; "));
        }
    }
}

/// Section 2: the whole branch densely — 100 evenly spaced loads α = 0.1 …
/// 10, each within the residual tolerance: ANM (series) against Newton
/// (interpolant + correction), factorisations and time as ratios.
fn section_dense(out: &mut String, dir: &Path, dense: &[f64], reference: &TipReference<'_>) {
    let _ = writeln!(
        out,
        "\n2. The branch densely: tips at 100 loads α = 0.1, 0.2, …, 10 in one run, residual 1e-10, medians of {REPS}"
    );
    let _ = writeln!(
        out,
        "{:<9} {:<16} {:<26} {:>9} {:>9} {:>7} {:>7} {:>8} {:>10} {:>10}",
        "scene", "discretisation", "method", "time", "max err", "steps", "factor.", "resid.", "fact. N/A", "time A/N"
    );
    let mut csv = String::from("scene,discretisation,method,time_s,max_error,steps,factorisations,residuals\n");
    for scene in [Scene::Follower, Scene::Dead] {
        for (scheme, n) in [(Scheme::Gauss(4), 8), (Scheme::Gauss(4), 16)] {
            let r = rod(scene, scheme, n);
            let engines = [
                Engine::Anm { order: 20, epsilon: 1e-10, pade: false },
                Engine::Anm { order: 20, epsilon: 1e-10, pade: true },
                Engine::Newton,
            ];
            let mut times = vec![vec![]; 3];
            let mut res = vec![None; 3];
            for _ in 0..REPS {
                for (k, &e) in engines.iter().enumerate() {
                    let (tips, counts, t) = run(&r, e, 1e-10, dense);
                    times[k].push(t);
                    res[k] = Some((tips, counts));
                }
            }
            let t: Vec<Duration> = times.into_iter().map(median).collect();
            let reference = reference(scene, dense);
            for (k, e) in engines.iter().enumerate() {
                let (tips, c) = res[k].clone().unwrap();
                let c_newton = res[2].as_ref().unwrap().1;
                let error = err(&tips, &reference);
                let ratio_f = if k < 2 {
                    format!("{:.1}", c_newton.factorisations as f64 / c.factorisations as f64)
                } else {
                    "-".into()
                };
                let ratio_t =
                    if k < 2 { format!("{:.2}", t[k].as_secs_f64() / t[2].as_secs_f64()) } else { "-".into() };
                let _ = writeln!(
                    out,
                    "{:<9} {:<16} {:<26} {:>7.2}ms {:>9.1e} {:>7} {:>7} {:>8} {:>10} {:>10}",
                    format!("{scene:?}"),
                    format!("{scheme:?} × {n}"),
                    e.name(),
                    ms(t[k]),
                    error,
                    c.steps,
                    c.factorisations,
                    c.residuals,
                    ratio_f,
                    ratio_t
                );
                let _ = writeln!(
                    csv,
                    "{scene:?},{scheme:?} × {n},{},{},{},{},{},{}",
                    e.name(),
                    t[k].as_secs_f64(),
                    error,
                    c.steps,
                    c.factorisations,
                    c.residuals
                );
            }
        }
    }
    let _ = fs::write(dir.join("dense.csv"), csv);
}

/// Section 3: Euler buckling and post-buckling of the clamped–free rod
/// (axial dead load Λ, K_b1 = 2 K_b2 so the buckling plane is fixed, as in
/// AUTO's euler.f90): the straight branch with detection, location of the
/// bifurcation, the switch, and the post-buckled branch to Λ = 14 (tip
/// rotation ≈ 169°). Error: critical load against §2.6's extensible
/// formula, post-buckled tips at Λ = 5, 10, 14 against Gauss(4) × 64.
fn section_post_buckling(out: &mut String, dir: &Path, auto_ok: bool) {
    let fine = euler_rod(Scheme::Gauss(4), 64);
    let (_, reference, _, _) = follow_euler(&fine, Method::Newton, 1e-12);
    let pcr = auto07p::euler_critical_load(1.0, 1.0, 1e4, 2.6e4);
    let _ = writeln!(out, "\n3. Euler buckling and post-buckling (clamped–free, axial dead load, K_b1 = 2 K_b2): straight branch with detection, location, switch, post-buckled branch to Λ = 14; medians of {REPS}");
    let _ = writeln!(
        out,
        "{:<16} {:<26} {:>9} {:>11} {:>10} {:>7} {:>7} {:>8} {:>9}",
        "discretisation", "method", "time", "P_cr err", "tip err", "steps", "factor.", "resid.", "/Newton"
    );
    let mut csv =
        String::from("discretisation,method,time_s,critical_load_error,tip_error,steps,factorisations,residuals\n");
    // The ANM at the default order and ε, and at the cheapest setting found
    // for this run (Padé P = 15, ε = 1e-6: the post-buckled branch in 6
    // steps instead of 16, its tips as accurate: the tip error column).
    let methods = [
        Method::Anm(AnmOptions { order: 20, epsilon: 1e-10, pade: false }),
        Method::Anm(AnmOptions { order: 15, epsilon: 1e-6, pade: true }),
        Method::Newton,
    ];
    let mut anm_times = vec![];
    for (scheme, n) in [(Scheme::Gauss(4), 8), (Scheme::Gauss(4), 16)] {
        let r = euler_rod(scheme, n);
        let mut times = vec![vec![]; methods.len()];
        let mut res = vec![None; methods.len()];
        for _ in 0..REPS {
            for (k, &m) in methods.iter().enumerate() {
                let (pc, tips, c, t) = follow_euler(&r, m, 1e-10);
                times[k].push(t);
                res[k] = Some((pc, tips, c));
            }
        }
        let t: Vec<Duration> = times.into_iter().map(median).collect();
        let newton = t[methods.len() - 1];
        anm_times.push((n, t[0], t[1]));
        for (k, m) in methods.iter().enumerate() {
            let (pc, tips, c) = res[k].clone().unwrap();
            let name = match m {
                Method::Anm(AnmOptions { pade: false, .. }) => "rodkit ANM P=20 ε=1e-10",
                Method::Anm(_) => "rodkit ANM Padé P=15 ε=1e-6",
                Method::Newton => "rodkit Newton",
            };
            let e = err(&tips, &reference);
            let _ = writeln!(
                out,
                "{:<16} {:<26} {:>7.2}ms {:>11.1e} {:>10.1e} {:>7} {:>7} {:>8} {:>9.2}",
                format!("{scheme:?} × {n}"),
                name,
                ms(t[k]),
                (pc - pcr).abs() / pcr,
                e,
                c.steps,
                c.factorisations,
                c.residuals,
                t[k].as_secs_f64() / newton.as_secs_f64()
            );
            let _ = writeln!(
                csv,
                "{scheme:?} × {n},{name},{},{},{},{},{},{}",
                t[k].as_secs_f64(),
                (pc - pcr).abs() / pcr,
                e,
                c.steps,
                c.factorisations,
                c.residuals
            );
        }
    }
    if auto_ok {
        auto_post_buckling(out, pcr, &anm_times);
    }
    let _ = fs::write(dir.join("post_buckling.csv"), csv);
}

/// Section 3's rod: clamped–free, axial dead tip load, K_b1 = 2 K_b2,
/// GA = 1e4, EA = 2.6e4.
fn euler_rod(scheme: Scheme, n: usize) -> Rod {
    let (ga, ea) = (1e4, 2.6e4);
    let k = nalgebra::Matrix6::from_diagonal(&nalgebra::Vector6::new(2.0, 1.0, 1.0 / 1.3, ga, ga, ea));
    let law = RodLaw::general(k, nalgebra::Vector3::zeros(), nalgebra::Vector3::new(0.0, 0.0, 1.0)).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() };
    Rod::new(law, 1.0, loads, Supports::Cantilever, scheme, n).unwrap()
}

/// Section 3's run: the straight branch with detection and location, the
/// switch and the post-buckled branch to Λ = 14 with samples at Λ = 5, 10,
/// 14. Returns the critical load, the sample tips (|x_tip|, 0, z_tip: the
/// buckle may go either way), the summed counts and the wall time.
fn follow_euler(rod: &Rod, method: Method, tol: f64) -> (f64, Vec<[f64; 3]>, Counts, Duration) {
    let loads = [5.0, 10.0, 14.0];
    let t = Instant::now();
    let opts = Options {
        target_lambda: Some(3.0),
        residual_tol: tol,
        initial_step: 0.2,
        max_step: 1.0,
        detect_bifurcations: true,
        bifurcation_tol: 1e-10,
        ..Default::default()
    };
    let straight = rod.continue_branch(None, 0.0, true, &opts, method, |_| true).unwrap();
    let bif = &straight.bifurcations[0];
    let opts = Options {
        target_lambda: Some(14.0),
        residual_tol: tol,
        max_step: 5.0,
        max_steps: 2000,
        samples: loads.to_vec(),
        ..Default::default()
    };
    let b = rod.switch_branch(&straight, 0, 0, 0.05, &opts, method, |_| true).unwrap();
    let elapsed = t.elapsed();
    let mut c = straight.counts;
    c.steps += b.counts.steps;
    c.factorisations += b.counts.factorisations;
    c.solves += b.counts.solves;
    c.residuals += b.counts.residuals;
    c.jacobians += b.counts.jacobians;
    c.series_orders += b.counts.series_orders;
    // The buckle may go either way: compare |x_tip| and z_tip.
    let tips = b
        .sample_states
        .iter()
        .map(|x| {
            let p = rod.tip(x);
            [p[0].hypot(p[1]), 0.0, p[2]]
        })
        .collect();
    (bif.lambda, tips, c, elapsed)
}

/// AUTO-07p's Euler runs (NTST 8 and 16, medians of REPS) as lines of
/// section 3's table: its own location of the branch point and switch.
fn auto_post_buckling(out: &mut String, pcr: f64, anm: &[(usize, Duration, Duration)]) {
    for ntst in [8usize, 16] {
        let mut times = vec![];
        let mut last = None;
        for _ in 0..REPS {
            match auto07p::euler(ntst, 1e-10) {
                Ok(run) => {
                    times.push(run.cpu);
                    last = Some(run);
                }
                Err(e) => {
                    let _ = writeln!(out, "AUTO-07p euler NTST {ntst} failed: {e}");
                    break;
                }
            }
        }
        if let Some(run) = last {
            let bp = run.branch_points()[0].lambda;
            let end = run.end_point().map(|p| (p.lambda, p.rotation_deg)).unwrap_or((f64::NAN, f64::NAN));
            let _ = writeln!(out, "{:<16} {:<26} {:>7.2}ms {:>11.1e} {:>10} {:>7} {:>7} {:>8} {:>9}   (AUTO: to tip rotation 170° at Λ = {:.4}; ~{} Newton iterations)",
                format!("NTST {ntst} NCOL 4"), "AUTO-07p", ms(median(times.clone())), (bp - pcr).abs() / pcr, "-", run.steps, "-", "-", "-", end.0, run.newton_iterations);
            // Against the ANM on as many elements (Gauss(4) × NTST: the
            // same collocation).
            if let Some((_, default, cheapest)) = anm.iter().find(|a| a.0 == ntst) {
                let auto = median(times.clone()).as_secs_f64();
                let _ = writeln!(
                    out,
                    "{:<16} AUTO-07p / rodkit: {:.2}× (ANM P=20 ε=1e-10), {:.2}× (ANM Padé P=15 ε=1e-6)",
                    "",
                    auto / default.as_secs_f64(),
                    auto / cheapest.as_secs_f64()
                );
            }
        }
    }
}

/// The ANM's own knobs (order P, ε, Padé) on Gauss(4) × 8: what each buys —
/// steps, factorisations, the series' end-point residual before the
/// correction (max over the steps), Newton correction iterations, time.
fn section_anm_knobs(out: &mut String, dir: &Path) {
    let r = rod(Scene::Follower, Scheme::Gauss(4), 8);
    let _ = writeln!(out, "\n4. ANM knobs on Gauss(4) × 8, α 0 → 10 in one run (residual tolerance 1e-10 after correction), medians of {REPS}");
    let _ = writeln!(
        out,
        "{:>5} {:>4} {:>8} {:>6} {:>8} {:>11} {:>16} {:>10} {:>10}",
        "Padé", "P", "ε", "steps", "factor.", "Padé steps", "max series res.", "Newton it.", "time"
    );
    let mut csv = String::from(
        "pade,order,epsilon,steps,factorisations,pade_steps,max_series_residual,newton_iterations,time_s\n",
    );
    for (pade, order) in [(false, 10), (false, 20), (false, 30), (false, 40), (true, 10), (true, 20), (true, 30)] {
        for epsilon in [1e-6, 1e-8, 1e-10, 1e-12] {
            let mut times = vec![];
            let mut summary = None;
            for _ in 0..REPS {
                let t = Instant::now();
                let mut sys = r.system().unwrap();
                let opts = Options {
                    target_lambda: Some(10.0),
                    residual_tol: 1e-10,
                    max_step: 5.0,
                    max_steps: 5000,
                    ..Default::default()
                };
                let start = Start::Point { x: r.straight_state(), lambda: 0.0, increasing: true };
                let b =
                    continue_anm(&mut sys, start, &opts, &AnmOptions { order, epsilon, pade }, |_, _| vec![], |_| true)
                        .unwrap();
                times.push(t.elapsed());
                let worst = b.records.iter().filter_map(|r| r.series_residual).fold(0.0, f64::max);
                let newton: usize = b.records.iter().map(|r| r.newton_iterations).sum();
                summary = Some((b.counts.steps, b.counts.factorisations, b.counts.pade_steps, worst, newton));
            }
            let (steps, fact, pade_steps, worst, newton) = summary.unwrap();
            let t = median(times);
            let _ = writeln!(out, "{:>5} {order:>4} {epsilon:>8.0e} {steps:>6} {fact:>8} {pade_steps:>11} {worst:>16.1e} {newton:>10} {:>8.2}ms", if pade { "yes" } else { "no" }, t.as_secs_f64() * 1e3);
            let _ = writeln!(
                csv,
                "{pade},{order},{epsilon},{steps},{fact},{pade_steps},{worst},{newton},{}",
                t.as_secs_f64()
            );
        }
    }
    let _ = fs::write(dir.join("anm_knobs.csv"), csv);
}

fn plot(path: &Path, rows: &[Row]) -> Result<(), Box<dyn std::error::Error>> {
    let pts = |f: &dyn Fn(&Row) -> bool| -> Vec<(f64, f64)> {
        rows.iter().filter(|r| f(r)).map(|r| (r.time.as_secs_f64() * 1e3, r.error.max(1e-14))).collect()
    };
    let follower = |r: &Row| r.scene == Scene::Follower;
    let series = [
        ("rodkit ANM", pts(&|r| r.method.starts_with("rodkit ANM") && follower(r)), RGBColor(214, 39, 40)),
        ("rodkit Newton", pts(&|r| r.method == "rodkit Newton" && follower(r)), RGBColor(31, 119, 180)),
        ("AUTO-07p", pts(&|r| r.method == "AUTO-07p"), RGBColor(44, 160, 44)),
        ("SUNDIALS KINSOL", pts(&|r| r.method.starts_with("SUNDIALS") && follower(r)), RGBColor(148, 103, 189)),
    ];
    plot::scatter_log_log(
        path,
        "Follower cantilever α 0→10: tip error vs time",
        "time (ms)",
        "max tip error / L",
        &series,
    )
}

//! Rod continuation benchmark (`cargo bench --bench rod`): the cubic ANM
//! against Newton pseudo-arc-length continuation on the same discretisation
//! in the same process, and against the peer AUTO-07p (run as a subprocess,
//! its executable timed alone; skipped with a message when not installed).
//!
//! Scene: the follower cantilever of physics.md §2.6 — K_b = 1, C = 1/1.3,
//! GA = 1e4, EA = 2.6e4, L = 1, clamped at s = 0, tip force Λ(1, 0, 0) in
//! the body frame (perpendicular to the tip tangent), continued from α = 0
//! through α = 1, 2, 5 to 10 (each a target stop, resumed from the last).
//! Error: max over those four α of |r(L) − r_ref(L)|/L with the reference
//! from rodkit on Gauss(4) × 32 elements at residual 1e−12, itself checked
//! against AUTO's finest run (printed). Time: median of REPS interleaved
//! repetitions. Writes target/bench/rod/{report.txt, follower.csv,
//! follower_work_precision.svg}.

#[path = "support/auto07p.rs"]
mod auto07p;
#[cfg(feature = "sundials")]
#[path = "../tests/support/sundials.rs"]
#[allow(dead_code)]
mod sundials;
#[cfg(feature = "sundials")]
#[path = "../tests/support/rod_band.rs"]
mod rod_band;

/// SUNDIALS as a peer (`--features sundials`): natural-parameter
/// continuation as a user without a continuation code would do it — α
/// stepped by 0.25 from 0 to 10 (through 1, 2, 5, 10), each KINSOL solve
/// (exact Newton, rodkit's analytic Jacobian, band direct solver on the
/// rows reordered to a band, scaled like rodkit's residual tolerance 1e−10)
/// started from the previous solution. Returns the tips at the four α,
/// (KINSOL iterations, Jacobian evaluations, residual evaluations), time.
#[cfg(feature = "sundials")]
fn run_kinsol(rod: &Rod, tol: f64) -> Result<(Vec<[f64; 3]>, (i64, i64, i64), Duration), String> {
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

use plotters::prelude::*;
use rodkit::continuation::anm::{continue_anm, AnmOptions};
use rodkit::continuation::newton::{continue_newton, Start};
use rodkit::continuation::{Branch, Counts, Options, Stop};
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::time::{Duration, Instant};

const ALPHAS: [f64; 4] = [1.0, 2.0, 5.0, 10.0];
const REPS: usize = 5;

fn rod(scheme: Scheme, n: usize) -> Rod {
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let loads = Loads { tip_force: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
    Rod::new(law, 1.0, loads, Supports::Cantilever, scheme, n).unwrap()
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Engine {
    Anm { order: usize, epsilon: f64 },
    Newton,
}

/// Tip positions at the four α, the work done, the wall time.
fn run(rod: &Rod, engine: Engine, tol: f64) -> (Vec<[f64; 3]>, Counts, Duration) {
    let t = Instant::now();
    let mut sys = rod.system().unwrap();
    let mut start = Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true };
    let mut tips = vec![];
    let mut total = Counts::default();
    for &alpha in &ALPHAS {
        let opts = Options { target_lambda: Some(alpha), residual_tol: tol, initial_step: 0.2, max_step: 2.0, max_steps: 2000, ..Default::default() };
        let b: Branch = match engine {
            Engine::Anm { order, epsilon } => continue_anm(&mut sys, start.clone(), &opts, &AnmOptions { order, epsilon }, |_, _| vec![], |_| true).unwrap(),
            Engine::Newton => continue_newton(&mut sys, start.clone(), &opts, |_, _| vec![], |_| true).unwrap(),
        };
        assert_eq!(b.stop, Stop::Target, "{engine:?} did not reach α = {alpha}");
        tips.push(rod.tip(&b.resume.x));
        let c = b.counts;
        total.steps += c.steps;
        total.factorisations += c.factorisations;
        total.solves += c.solves;
        total.residuals += c.residuals;
        total.jacobians += c.jacobians;
        total.series_orders += c.series_orders;
        start = Start::Resume(b.resume);
    }
    (tips, total, t.elapsed())
}

fn err(tips: &[[f64; 3]], reference: &[[f64; 3]]) -> f64 {
    tips.iter()
        .zip(reference)
        .map(|(a, b)| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt())
        .fold(0.0, f64::max)
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

struct Row {
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
    let _ = writeln!(out, "rodkit {} rod continuation benchmark (follower cantilever, α 0 → 1 → 2 → 5 → 10)", env!("CARGO_PKG_VERSION"));
    // Reference.
    let fine = rod(Scheme::Gauss(4), 32);
    let (reference, _, _) = run(&fine, Engine::Newton, 1e-12);
    let _ = writeln!(out, "reference: Gauss(4) × 32, residual 1e-12: tips {reference:?}");

    let tol = 1e-10;
    let configs: Vec<(Scheme, usize)> = vec![(Scheme::Gauss(4), 4), (Scheme::Gauss(4), 8), (Scheme::Gauss(4), 16), (Scheme::Gauss(2), 16), (Scheme::Midpoint, 64)];
    let engines = [Engine::Anm { order: 20, epsilon: 1e-10 }, Engine::Newton];
    let auto_ntst = [4usize, 8, 16];
    let auto_ok = auto07p::available();
    let mut times: Vec<Vec<Duration>> = vec![vec![]; configs.len() * engines.len() + auto_ntst.len()];
    let mut results: Vec<Option<(Vec<[f64; 3]>, Counts)>> = vec![None; configs.len() * engines.len()];
    let mut auto_results: Vec<Option<auto07p::AutoRun>> = vec![None; auto_ntst.len()];
    #[allow(unused_mut)]
    let mut kinsol_results: Vec<Option<(Vec<[f64; 3]>, (i64, i64, i64), Vec<Duration>)>> = vec![None; configs.len()];
    for _ in 0..REPS {
        for (ci, &(scheme, n)) in configs.iter().enumerate() {
            let r = rod(scheme, n);
            for (ei, &engine) in engines.iter().enumerate() {
                let (tips, counts, t) = run(&r, engine, tol);
                let k = ci * engines.len() + ei;
                times[k].push(t);
                results[k] = Some((tips, counts));
            }
        }
        #[cfg(feature = "sundials")]
        for (ci, &(scheme, n)) in configs.iter().enumerate() {
            match run_kinsol(&rod(scheme, n), tol) {
                Ok((tips, counts, t)) => {
                    let entry = kinsol_results[ci].get_or_insert((tips, counts, vec![]));
                    entry.2.push(t);
                }
                Err(e) => {
                    let _ = writeln!(out, "KINSOL {scheme:?} × {n} failed: {e}");
                }
            }
        }
        if auto_ok {
            for (ai, &ntst) in auto_ntst.iter().enumerate() {
                match auto07p::follower(ntst, tol) {
                    Ok(run) => {
                        times[configs.len() * engines.len() + ai].push(run.wall);
                        auto_results[ai] = Some(run);
                    }
                    Err(e) => {
                        let _ = writeln!(out, "AUTO-07p NTST {ntst} failed: {e}");
                    }
                }
            }
        }
    }
    let mut rows = vec![];
    for (ci, &(scheme, n)) in configs.iter().enumerate() {
        let r = rod(scheme, n);
        for (ei, &engine) in engines.iter().enumerate() {
            let k = ci * engines.len() + ei;
            let (tips, counts) = results[k].clone().unwrap();
            rows.push(Row {
                method: match engine {
                    Engine::Anm { order, epsilon } => format!("rodkit ANM P={order} ε={epsilon:.0e}"),
                    Engine::Newton => "rodkit Newton".into(),
                },
                disc: format!("{scheme:?} × {n}"),
                unknowns: r.unknowns(),
                time: median(times[k].clone()),
                error: err(&tips, &reference),
                counts: Some(counts),
                auto_steps: None,
            });
        }
    }
    for (ai, &ntst) in auto_ntst.iter().enumerate() {
        if let Some(run) = &auto_results[ai] {
            let tips: Vec<[f64; 3]> = ALPHAS.iter().map(|&a| run.at_lambda(a).map(|p| p.tip_at(a)).unwrap_or([f64::NAN; 3])).collect();
            let k = configs.len() * engines.len() + ai;
            rows.push(Row {
                method: "AUTO-07p".into(),
                disc: format!("NTST {ntst} NCOL 4"),
                unknowns: 13 * (4 * ntst + 1),
                time: median(times[k].clone()),
                error: err(&tips, &reference),
                counts: None,
                auto_steps: Some((run.steps, run.newton_iterations)),
            });
        }
    }
    for (ci, &(scheme, n)) in configs.iter().enumerate() {
        if let Some((tips, (iters, jacs, res), times)) = &kinsol_results[ci] {
            rows.push(Row {
                method: "SUNDIALS KINSOL band".into(),
                disc: format!("{scheme:?} × {n}"),
                unknowns: rod(scheme, n).unknowns(),
                time: median(times.clone()),
                error: err(tips, &reference),
                counts: Some(Counts { steps: 40, factorisations: *jacs as usize, solves: *iters as usize, residuals: *res as usize, jacobians: *jacs as usize, series_orders: 0 }),
                auto_steps: None,
            });
        }
    }
    if cfg!(not(feature = "sundials")) {
        let _ = writeln!(out, "SUNDIALS rows need `--features sundials` (natural-parameter KINSOL continuation): skipped");
    }
    if !auto_ok {
        let _ = writeln!(out, "AUTO-07p not installed (apt-get install auto-07p): peer rows skipped");
    }
    let _ = writeln!(out, "\nresidual tolerance 1e-10 (scaled), medians of {REPS} interleaved runs; ratios: time / time of Newton on the same discretisation, and / AUTO NTST 8");
    let _ = writeln!(out, "{:<26} {:<16} {:>6} {:>10} {:>9} {:>6} {:>7} {:>7} {:>8} {:>7} {:>8} {:>8}", "method", "discretisation", "n", "time", "tip err", "steps", "factor.", "Jacob.", "resid.", "orders", "/Newton", "/AUTO 8");
    let auto8 = rows.iter().find(|r| r.method == "AUTO-07p" && r.disc.starts_with("NTST 8 ")).map(|r| r.time);
    let mut csv = String::from("method,discretisation,unknowns,time_s,tip_error,steps,factorisations,jacobians,residuals,series_orders\n");
    for r in &rows {
        let newton = rows.iter().find(|o| o.disc == r.disc && o.method == "rodkit Newton").map(|o| o.time);
        let ratio = |base: Option<Duration>| base.map_or("-".to_string(), |b| format!("{:.2}", r.time.as_secs_f64() / b.as_secs_f64()));
        let (steps, fact, jac, res, ord) = match (&r.counts, r.auto_steps) {
            (Some(c), _) => (c.steps.to_string(), c.factorisations.to_string(), c.jacobians.to_string(), c.residuals.to_string(), c.series_orders.to_string()),
            (None, Some((s, newton_it))) => (s.to_string(), format!("~{newton_it}"), "-".into(), "-".into(), "-".into()),
            _ => ("-".into(), "-".into(), "-".into(), "-".into(), "-".into()),
        };
        let _ = writeln!(out, "{:<26} {:<16} {:>6} {:>8.2}ms {:>9.1e} {:>6} {:>7} {:>7} {:>8} {:>7} {:>8} {:>8}", r.method, r.disc, r.unknowns, r.time.as_secs_f64() * 1e3, r.error, steps, fact, jac, res, ord,
            if r.method != "AUTO-07p" { ratio(newton) } else { "-".into() }, ratio(auto8));
        let _ = writeln!(csv, "{},{},{},{},{},{},{},{},{},{}", r.method, r.disc, r.unknowns, r.time.as_secs_f64(), r.error, steps, fact, jac, res, ord);
    }
    let _ = writeln!(out, "(AUTO: 'factor.' column is its Newton iteration count; each iteration factorises its collocation matrix.");
    let _ = writeln!(out, " KINSOL: natural-parameter continuation α += 0.25, band solver on rows reordered to a band; 'steps' = solves, 'factor.' = Jacobian evaluations)");
    section_anm_knobs(&mut out, &dir);
    print!("{out}");
    fs::write(dir.join("report.txt"), &out).unwrap();
    fs::write(dir.join("follower.csv"), &csv).unwrap();
    if let Err(e) = plot(&dir.join("follower_work_precision.svg"), &rows) {
        eprintln!("plot failed: {e}");
    }
}

/// The ANM's own knobs (order P, ε) on Gauss(4) × 8: what each buys —
/// steps, factorisations, the series' end-point residual before the
/// correction (max over the steps), Newton correction iterations, time.
fn section_anm_knobs(out: &mut String, dir: &Path) {
    let r = rod(Scheme::Gauss(4), 8);
    let _ = writeln!(out, "\nANM knobs on Gauss(4) × 8, α 0 → 10 in one run (residual tolerance 1e-10 after correction), medians of {REPS}");
    let _ = writeln!(out, "{:>4} {:>8} {:>6} {:>8} {:>16} {:>10} {:>10}", "P", "ε", "steps", "factor.", "max series res.", "Newton it.", "time");
    let mut csv = String::from("order,epsilon,steps,factorisations,max_series_residual,newton_iterations,time_s\n");
    for order in [10, 20, 30, 40] {
        for epsilon in [1e-6, 1e-8, 1e-10, 1e-12] {
            let mut times = vec![];
            let mut summary = None;
            for _ in 0..REPS {
                let t = Instant::now();
                let mut sys = r.system().unwrap();
                let opts = Options { target_lambda: Some(10.0), residual_tol: 1e-10, max_step: 5.0, max_steps: 5000, ..Default::default() };
                let start = Start::Point { x: r.straight_state(), lambda: 0.0, increasing: true };
                let b = continue_anm(&mut sys, start, &opts, &AnmOptions { order, epsilon }, |_, _| vec![], |_| true).unwrap();
                times.push(t.elapsed());
                let worst = b.records.iter().filter_map(|r| r.series_residual).fold(0.0, f64::max);
                let newton: usize = b.records.iter().map(|r| r.newton_iterations).sum();
                summary = Some((b.counts.steps, b.counts.factorisations, worst, newton));
            }
            let (steps, fact, worst, newton) = summary.unwrap();
            let t = median(times);
            let _ = writeln!(out, "{order:>4} {epsilon:>8.0e} {steps:>6} {fact:>8} {worst:>16.1e} {newton:>10} {:>8.2}ms", t.as_secs_f64() * 1e3);
            let _ = writeln!(csv, "{order},{epsilon},{steps},{fact},{worst},{newton},{}", t.as_secs_f64());
        }
    }
    let _ = fs::write(dir.join("anm_knobs.csv"), csv);
}

fn plot(path: &Path, rows: &[Row]) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::new(path, (960, 640)).into_drawing_area();
    root.fill(&WHITE)?;
    let pts = |f: &dyn Fn(&Row) -> bool| -> Vec<(f64, f64)> { rows.iter().filter(|r| f(r)).map(|r| (r.time.as_secs_f64() * 1e3, r.error.max(1e-14))).collect() };
    let all: Vec<(f64, f64)> = pts(&|_| true);
    let (x0, x1) = all.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (y0, y1) = all.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let mut chart = ChartBuilder::on(&root)
        .caption("Follower cantilever α 0→10: tip error vs time", ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(56)
        .y_label_area_size(84)
        .build_cartesian_2d((x0 / 1.5..x1 * 1.5).log_scale(), (y0 / 3.0..y1 * 3.0).log_scale())?;
    chart.configure_mesh().x_desc("time (ms)").y_desc("max tip error / L").y_label_formatter(&|v| format!("{v:.0e}")).draw()?;
    for (name, color, f) in [
        ("rodkit ANM", RGBColor(214, 39, 40), Box::new(|r: &Row| r.method.starts_with("rodkit ANM")) as Box<dyn Fn(&Row) -> bool>),
        ("rodkit Newton", RGBColor(31, 119, 180), Box::new(|r: &Row| r.method == "rodkit Newton")),
        ("AUTO-07p", RGBColor(44, 160, 44), Box::new(|r: &Row| r.method == "AUTO-07p")),
        ("SUNDIALS KINSOL", RGBColor(148, 103, 189), Box::new(|r: &Row| r.method.starts_with("SUNDIALS"))),
    ] {
        let p = pts(&*f);
        chart.draw_series(p.iter().map(|&q| Circle::new(q, 5, color.filled())))?.label(name).legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
    }
    chart.configure_series_labels().background_style(WHITE.mix(0.9)).border_style(BLACK).draw()?;
    root.present()?;
    Ok(())
}

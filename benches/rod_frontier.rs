//! Work–precision frontier against AUTO-07p (`cargo bench --bench
//! rod_frontier`; issue 19, item 5): each side given its cheapest settings
//! that reach a tip error, not one fixed setting.
//!
//! Scenes: the cantilever of benches/rod.rs (K_b = 1, C = 1/1.3, GA = 1e4,
//! EA = 2.6e4, L = 1), tip force Λ e1 — follower (body frame) or dead
//! (space) — α 0 → 10, the tips at α = 1, 2, 5, 10 from one run (rodkit:
//! dense samples; AUTO: its UZ points, moved to the exact α along its
//! tangent). Error: max |r(L) − r_ref(L)|/L against Gauss(4) × 64 at
//! residual 1e−12 (Newton).
//!
//! Grids. rodkit: Gauss(2, 3, 4) × elements × mesh (uniform, or graded
//! geometrically from the clamp, each element 1.25 or 1.5 times the one
//! before) × engine (ANM P = 15 and 20:
//! the polynomial at ε 1e−10 and 1e−6, Padé at ε 1e−10, 1e−8 and 1e−6;
//! Newton) × residual tolerance (1e−7, 1e−9, 1e−11). AUTO-07p (benches/auto/{follower,dead}.f90): NTST × NCOL
//! (3, 4, 5, 7) × EPSL = EPSU (1e−4 … 1e−10) × DSMAX (0.5, 5) × IAD (0,
//! 3). Pass 1 runs every setting once (error and a first time); pass 2
//! times the six fastest settings of each side that reach each target
//! error (1e−6, 1e−8) in REPS interleaved repetitions (medians), and the
//! table names the fastest of each side with its settings and the ratio.
//! Timing, as each side's users run it:
//! - AUTO-07p: its executable's own process CPU time (user + system, from
//!   getrusage of the child: start-up, reading its constants and writing
//!   fort.7/8/9 included), its wall time beside;
//! - rodkit, two ways: warm repeated calls in this process (as a parameter
//!   sweep makes them; medians), and a first call in a fresh process (the
//!   bench binary re-run with `--first-call`: model set-up, first
//!   allocations and page faults included; medians of as many processes),
//!   with that process's whole CPU time beside.
//!
//! What other processes did meanwhile is measured (/proc/stat less this
//! process tree's CPU time): a target's ratios are withheld when other
//! jobs took more than a quarter of a core during its timing.
//!
//! Writes target/bench/rod_frontier/{report.txt, settings.csv,
//! frontier_follower.svg, frontier_dead.svg}.

#[path = "support/auto07p.rs"]
mod auto07p;
#[path = "support/machine.rs"]
mod machine;
#[path = "support/plot.rs"]
mod plot;
#[path = "support/timing.rs"]
mod timing;
use timing::{max_distance as error, median, ms};

use plotters::prelude::RGBColor;
use rodkit::continuation::anm::{continue_anm, AnmOptions};
use rodkit::continuation::newton::{continue_newton, Start};
use rodkit::continuation::{Counts, Options, Stop};
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::time::{Duration, Instant};

const LOADS: [f64; 4] = [1.0, 2.0, 5.0, 10.0];
const TARGETS: [f64; 2] = [1e-6, 1e-8];
const REPS: usize = 7;
/// Settings per side and target timed in pass 2. Pass 1 times each
/// setting once, and on this shared machine one timing varies by 10–40 %:
/// six finalists a side (the same for both) make the pick depend less on
/// that noise than four did.
const FINALISTS: usize = 6;
/// Cores other jobs may take during a target's timing before its ratios
/// are withheld.
const QUIET: f64 = 0.25;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scene {
    Follower,
    Dead,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Engine {
    Anm { order: usize, epsilon: f64, pade: bool },
    Newton,
}

#[derive(Clone, Debug)]
enum Setting {
    /// `grading`: each element's length over the one before it, from the
    /// clamp (1: uniform).
    Rodkit {
        stages: usize,
        elements: usize,
        grading: f64,
        engine: Engine,
        tol: f64,
    },
    Auto {
        ntst: usize,
        ncol: u32,
        tol: f64,
        dsmax: f64,
        iad: u32,
    },
}

impl Setting {
    fn side(&self) -> &'static str {
        match self {
            Setting::Rodkit { .. } => "rodkit",
            Setting::Auto { .. } => "AUTO-07p",
        }
    }

    fn label(&self) -> String {
        match self {
            Setting::Rodkit { stages, elements, grading, engine, tol } => {
                let e = match engine {
                    Engine::Anm { order, epsilon, pade } => {
                        format!("ANM P={order}{} ε={epsilon:.0e}", if *pade { " Padé" } else { "" })
                    }
                    Engine::Newton => "Newton".into(),
                };
                let mesh = if *grading == 1.0 { String::new() } else { format!(" graded {grading}") };
                format!("Gauss({stages})×{elements}{mesh} {e} tol {tol:.0e}")
            }
            Setting::Auto { ntst, ncol, tol, dsmax, iad } => {
                format!("NTST {ntst} NCOL {ncol} EPS {tol:.0e} DSMAX {dsmax} IAD {iad}")
            }
        }
    }
}

/// One run's tips, time and (rodkit) work. `time`: rodkit's call, AUTO's
/// process CPU; `wall`: AUTO's process wall time.
struct Outcome {
    tips: Vec<[f64; 3]>,
    time: Duration,
    wall: Duration,
    counts: Option<Counts>,
}

fn rod(scene: Scene, stages: usize, n: usize, grading: f64) -> Rod {
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let load = match scene {
        Scene::Follower => Load::follower([1.0, 0.0, 0.0]),
        Scene::Dead => Load::dead([1.0, 0.0, 0.0]),
    };
    let loads = Loads { tip_force: Some(load), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(stages), n).unwrap();
    if grading == 1.0 {
        return rod;
    }
    // Geometric grading from the clamp: element i has length ∝ grading^i.
    let lengths: Vec<f64> = (0..n).map(|i| grading.powi(i as i32)).collect();
    let total: f64 = lengths.iter().sum();
    let mut t: Vec<f64> = lengths.iter().scan(0.0, |s, l| Some(std::mem::replace(s, *s + l / total))).collect();
    t.push(1.0);
    rod.graded(&t).unwrap()
}

/// α 0 → 10 in one run, the tips at LOADS by dense output.
fn run_rodkit(
    scene: Scene,
    stages: usize,
    n: usize,
    grading: f64,
    engine: Engine,
    tol: f64,
) -> Result<Outcome, String> {
    let t = Instant::now();
    let rod = rod(scene, stages, n, grading);
    let mut sys = rod.system().map_err(|e| e.message)?;
    let start = Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true };
    let opts = Options {
        target_lambda: Some(10.0),
        residual_tol: tol,
        max_steps: 2000,
        samples: LOADS[..3].to_vec(),
        ..Default::default()
    };
    let observe = |x: &[f64], _: f64| rod.tip(x).to_vec();
    let b = match engine {
        Engine::Anm { order, epsilon, pade } => {
            continue_anm(&mut sys, start, &opts, &AnmOptions { order, epsilon, pade }, observe, |_| true)
        }
        Engine::Newton => continue_newton(&mut sys, start, &opts, observe, |_| true),
    }
    .map_err(|e| e.message)?;
    let time = t.elapsed();
    if b.stop != Stop::Target || !b.missed_samples.is_empty() {
        return Err(format!("stopped {:?}, missed {:?}", b.stop, b.missed_samples));
    }
    let mut tips: Vec<[f64; 3]> = b.samples.iter().map(|s| [s.outputs[0], s.outputs[1], s.outputs[2]]).collect();
    let last = &b.records.last().unwrap().outputs;
    tips.push([last[0], last[1], last[2]]);
    Ok(Outcome { tips, time, wall: time, counts: Some(b.counts) })
}

fn run_auto(scene: Scene, ntst: usize, ncol: u32, tol: f64, dsmax: f64, iad: u32) -> Result<Outcome, String> {
    let opt = auto07p::Options { ncol, iad, dsmax, epss: None };
    let run = match scene {
        Scene::Follower => auto07p::follower_with(ntst, tol, &opt)?,
        Scene::Dead => auto07p::dead_with(ntst, tol, &opt)?,
    };
    let tips = LOADS
        .iter()
        .map(|&l| run.at_lambda(l).map(|p| p.tip_at(l)).ok_or_else(|| format!("no UZ point at Λ = {l}")))
        .collect::<Result<_, _>>()?;
    Ok(Outcome { tips, time: run.cpu, wall: run.wall, counts: None })
}

fn run(scene: Scene, s: &Setting) -> Result<Outcome, String> {
    match *s {
        Setting::Rodkit { stages, elements, grading, engine, tol } => {
            run_rodkit(scene, stages, elements, grading, engine, tol)
        }
        Setting::Auto { ntst, ncol, tol, dsmax, iad } => run_auto(scene, ntst, ncol, tol, dsmax, iad),
    }
}

fn settings(auto: bool) -> Vec<Setting> {
    let mut all = vec![];
    // ANM: P 15 and 20, the polynomial at ε 1e-10 and 1e-6, Padé at ε
    // 1e-10, 1e-8 and 1e-6 (Padé reaches further per step; with P = 15 it
    // takes the dead-load cantilever in 3 steps where the polynomial takes
    // 5–8).
    let mut engines = vec![Engine::Newton];
    for order in [15, 20] {
        for (epsilon, pade) in [(1e-10, false), (1e-6, false), (1e-10, true), (1e-8, true), (1e-6, true)] {
            engines.push(Engine::Anm { order, epsilon, pade });
        }
    }
    for (stages, counts) in [(2, &[4usize, 8, 16, 24, 32][..]), (3, &[3, 4, 6, 8, 12, 16]), (4, &[2, 3, 4, 6, 8, 12])] {
        for &elements in counts {
            // Uniform, or graded towards the clamp (where a tip load's
            // moment is largest), as AUTO's grid has its mesh adaption.
            for grading in [1.0, 1.25, 1.5] {
                for &engine in &engines {
                    for tol in [1e-7, 1e-9, 1e-11] {
                        all.push(Setting::Rodkit { stages, elements, grading, engine, tol });
                    }
                }
            }
        }
    }
    if auto {
        for ntst in [2, 3, 4, 6, 8, 12, 16] {
            for ncol in [3, 4, 5, 7] {
                for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
                    for dsmax in [0.5, 5.0] {
                        for iad in [0, 3] {
                            all.push(Setting::Auto { ntst, ncol, tol, dsmax, iad });
                        }
                    }
                }
            }
        }
    }
    all
}

/// A rodkit setting's first call in a fresh process: (the call's time as
/// that process measured it, the process's whole CPU time).
fn first_call(scene: Scene, index: usize) -> Result<(Duration, Duration), String> {
    let cpu0 = timing::cpu_time(true);
    let out = std::process::Command::new(std::env::current_exe().map_err(|e| e.to_string())?)
        .args(["--first-call", &format!("{scene:?}"), &index.to_string()])
        .output()
        .map_err(|e| e.to_string())?;
    let cpu = timing::cpu_time(true).saturating_sub(cpu0);
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).into_owned());
    }
    let nanos: u64 = String::from_utf8_lossy(&out.stdout).trim().parse().map_err(|e| format!("{e}"))?;
    Ok((Duration::from_nanos(nanos), cpu))
}

fn main() {
    // A child of `first_call`: one rodkit call, its time printed in ns.
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--first-call") {
        let scene = if args[i + 1] == "Follower" { Scene::Follower } else { Scene::Dead };
        let setting = &settings(false)[args[i + 2].parse::<usize>().unwrap()];
        let o = run(scene, setting).unwrap();
        println!("{}", o.time.as_nanos());
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench/rod_frontier");
    fs::create_dir_all(&dir).unwrap();
    let auto = auto07p::available();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "rodkit {} work–precision frontier against AUTO-07p (cantilever α 0 → 10, tips at α = 1, 2, 5, 10); medians of {REPS}",
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        out,
        "machine: {} cores, load average {:.2} at the start (this bench included); time*: rodkit's warm call, \
         AUTO-07p's process CPU",
        machine::cores(),
        machine::load_average()
    );
    if !auto {
        let _ = writeln!(out, "AUTO-07p not installed (apt-get install auto-07p): rodkit's frontier only");
    }
    let all = settings(auto);
    let mut csv = String::from("scene,side,setting,error,time_s,steps,factorisations\n");
    for scene in [Scene::Follower, Scene::Dead] {
        let reference = run_rodkit(scene, 4, 64, 1.0, Engine::Newton, 1e-12).unwrap().tips;
        // Pass 1: every setting once.
        let mut first: Vec<(usize, f64, Duration, Option<Counts>)> = vec![];
        let mut failed = 0;
        for (i, s) in all.iter().enumerate() {
            match run(scene, s) {
                Ok(o) => {
                    let e = error(&o.tips, &reference);
                    let (steps, fact) = o.counts.as_ref().map_or((0, 0), |c| (c.steps, c.factorisations));
                    let _ = writeln!(
                        csv,
                        "{scene:?},{},{},{e:e},{},{steps},{fact}",
                        s.side(),
                        s.label(),
                        o.time.as_secs_f64()
                    );
                    first.push((i, e, o.time, o.counts));
                }
                Err(e) => {
                    failed += 1;
                    // One CSV field: no commas, quotes or line breaks.
                    let why: String =
                        e.chars().map(|c| if matches!(c, ',' | '"' | '\n' | '\r') { ' ' } else { c }).collect();
                    let _ = writeln!(csv, "{scene:?},{},{},failed: {why},,,", s.side(), s.label());
                }
            }
        }
        let _ = writeln!(
            out,
            "\n{scene:?} load: {} settings run once ({failed} did not reach α = 10 or a UZ point)",
            first.len()
        );
        let _ = writeln!(
            out,
            "{:<9} {:<9} {:<48} {:>10} {:>10} {:>6} {:>7}",
            "tip err ≤", "side", "cheapest setting", "time*", "error", "steps", "factor."
        );
        let mut frontier = vec![];
        for target in TARGETS {
            // Pass 2: the fastest FINALISTS of each side that reach the target.
            let mut finalists = vec![];
            for side in ["rodkit", "AUTO-07p"] {
                let mut c: Vec<&(usize, f64, Duration, Option<Counts>)> =
                    first.iter().filter(|r| all[r.0].side() == side && r.1 <= target).collect();
                c.sort_by_key(|r| r.2);
                finalists.extend(c.into_iter().take(FINALISTS).map(|r| r.0));
            }
            let mut times = vec![vec![]; finalists.len()];
            let mut walls = vec![vec![]; finalists.len()];
            let mut firsts: Vec<Vec<(Duration, Duration)>> = vec![vec![]; finalists.len()];
            let mut errors = vec![0.0; finalists.len()];
            let mut counts = vec![None; finalists.len()];
            let quiet = machine::Sample::now();
            for _ in 0..REPS {
                for (k, &i) in finalists.iter().enumerate() {
                    if let Ok(o) = run(scene, &all[i]) {
                        errors[k] = error(&o.tips, &reference);
                        times[k].push(o.time);
                        walls[k].push(o.wall);
                        counts[k] = o.counts;
                    }
                    if all[i].side() == "rodkit" {
                        if let Ok(f) = first_call(scene, i) {
                            firsts[k].push(f);
                        }
                    }
                }
            }
            let others = quiet.others_since(&machine::Sample::now());
            let mut best: Vec<(&str, Duration, Option<Duration>)> = vec![];
            for side in ["rodkit", "AUTO-07p"] {
                let pick = (0..finalists.len())
                    .filter(|&k| all[finalists[k]].side() == side && times[k].len() == REPS && errors[k] <= target)
                    .map(|k| (k, median(times[k].clone())))
                    .min_by_key(|p| p.1);
                match pick {
                    Some((k, t)) => {
                        let (steps, fact) = counts[k].as_ref().map_or(("-".into(), "-".into()), |c: &Counts| {
                            (c.steps.to_string(), c.factorisations.to_string())
                        });
                        let (first, detail) = if side == "rodkit" && firsts[k].len() == REPS {
                            let call = median(firsts[k].iter().map(|f| f.0).collect());
                            let process = median(firsts[k].iter().map(|f| f.1).collect());
                            (
                                Some(call),
                                format!("first call {:.2} ms (its process {:.1} ms CPU)", ms(call), ms(process)),
                            )
                        } else if side == "rodkit" {
                            (None, "first call failed".into())
                        } else {
                            (None, format!("wall {:.2} ms", ms(median(walls[k].clone()))))
                        };
                        let _ = writeln!(
                            out,
                            "{:<9.0e} {:<9} {:<48} {:>8.2}ms {:>10.1e} {:>6} {:>7}  {detail}",
                            target,
                            side,
                            all[finalists[k]].label(),
                            ms(t),
                            errors[k],
                            steps,
                            fact
                        );
                        best.push((side, t, first));
                        frontier.push((side, target, ms(t), errors[k]));
                    }
                    None => {
                        let _ = writeln!(out, "{target:<9.0e} {side:<9} none reaches it");
                    }
                }
            }
            if let [(_, warm, first), (_, auto, _)] = best[..] {
                if others > QUIET || others.is_nan() {
                    let _ = writeln!(
                        out,
                        "{:<9} ratios withheld: other jobs used {others:.2} cores while this target was timed",
                        ""
                    );
                } else {
                    let _ = writeln!(
                        out,
                        "{:<9} AUTO-07p process CPU / rodkit: {:.1}× warm, {} first call in a fresh process \
                         (other jobs {others:.2} cores)",
                        "",
                        auto.as_secs_f64() / warm.as_secs_f64(),
                        first.map_or("-".into(), |f| format!("{:.1}×", auto.as_secs_f64() / f.as_secs_f64())),
                        others = others.max(0.0),
                    );
                }
            }
        }
        let points: Vec<(&str, f64, f64)> = first.iter().map(|r| (all[r.0].side(), ms(r.2), r.1.max(1e-15))).collect();
        if let Err(e) = plot(&dir.join(format!("frontier_{scene:?}.svg").to_lowercase()), scene, &points) {
            eprintln!("plot failed: {e}");
        }
    }
    print!("{out}");
    fs::write(dir.join("report.txt"), &out).unwrap();
    fs::write(dir.join("settings.csv"), &csv).unwrap();
}

/// Every setting's (time, error) of pass 1, one colour per side.
fn plot(path: &Path, scene: Scene, points: &[(&str, f64, f64)]) -> Result<(), Box<dyn std::error::Error>> {
    let side = |name: &str| points.iter().filter(|p| p.0 == name).map(|p| (p.1, p.2)).collect::<Vec<_>>();
    let series =
        [("rodkit", side("rodkit"), RGBColor(214, 39, 40)), ("AUTO-07p", side("AUTO-07p"), RGBColor(44, 160, 44))];
    let title = format!("{scene:?} cantilever α 0→10: tip error vs time, every setting");
    plot::scatter_log_log(path, &title, "time (ms, one run)", "max tip error / L", &series)
}

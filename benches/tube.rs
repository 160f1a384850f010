//! Tube-model benchmark (`cargo bench --bench tube`): time, error,
//! factorisations and evaluations of the thin closed form and the thick-wall
//! collocation, with the baselines measured side by side in this process.
//!
//! 1. Thin K per call: Rust API vs the C ABI symbol, ABI overhead and ratio.
//! 2. Thick K work–precision: fixed grids (n = 4..=64) and the adaptive
//!    `coupling_stiffness(rel_tol)` against a 128-interval reference.
//! 3. Thin vs thick K as t/R goes from 1e−3 to 0.8 (physics.md §5: the
//!    cheapest model that meets the tolerance).
//! 4. Finite-strain state and sweep timings.
//! 5. Curves (not timings): the walls of tests/support/behaviour_cases.rs
//!    that overwind then unwind, and that deflate then inflate, under
//!    torsion-free stretching: CSV and SVG with the parameters in the CSV.
//!
//! Timing: std::time::Instant, single thread, each repetition times a batch
//! of calls lasting ≥ 1 ms, median (and min–max) over ≥ 7 repetitions; the
//! variants compared in one table are interleaved repetition by repetition so
//! that drift on the shared machine hits them alike. Tables go to stdout; CSV
//! and SVG plots to target/bench/tube/. Targets are reported as PASS/MISS
//! (informational: the exit code is 0 either way).

#[path = "support/plot.rs"]
mod plot;
use plot::line_plot;
#[path = "../tests/support/behaviour_cases.rs"]
mod behaviour_cases;

use nalgebra::{Matrix3, Vector3};
use plotters::prelude::*;
use rodkit::capi::thin_tube::ThinTubeSpec;
use rodkit::tube::{Compressibility, Orthotropic, OrthotropicSurface, ThickTube, ThinTube};
use std::fmt::Write as _;
use std::fs;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

// The C entry point, resolved by the linker to the #[no_mangle] symbol in the
// rodkit rlib: a real call through the C calling convention, as a C caller
// makes it (no cross-crate inlining is possible through this declaration).
extern "C" {
    fn rodkit_thin_tube_coupling_stiffness(spec: *const ThinTubeSpec, k: *mut f64, ldk: i64) -> i32;
}

const MIN_BATCH: Duration = Duration::from_millis(1);
const REPS: usize = 15;
/// Section 1: 11 repetitions of 10^5 calls, so each median rests on > 10^6 calls.
const THIN_REPS: usize = 11;
const THIN_BATCH: u64 = 100_000;

// ---------------------------------------------------------------- timing --

/// Seconds per call over the repetitions.
#[derive(Clone, Debug)]
struct Timing {
    samples: Vec<f64>,
    batch: u64,
}

impl Timing {
    fn median(&self) -> f64 {
        median(&self.samples)
    }
    fn min(&self) -> f64 {
        self.samples.iter().cloned().fold(f64::INFINITY, f64::min)
    }
    fn max(&self) -> f64 {
        self.samples.iter().cloned().fold(0.0, f64::max)
    }
    /// Half the min–max spread relative to the median, in percent.
    fn spread_pct(&self) -> f64 {
        50.0 * (self.max() - self.min()) / self.median()
    }
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

/// Smallest power-of-two batch lasting ≥ MIN_BATCH (also the warm-up).
fn calibrate(f: &mut dyn FnMut(u64)) -> u64 {
    let mut b = 1u64;
    loop {
        let t = Instant::now();
        f(b);
        if t.elapsed() >= MIN_BATCH || b >= 1 << 32 {
            return b;
        }
        b *= 2;
    }
}

/// Time several variants, interleaved repetition by repetition. `batch`:
/// calls per repetition, or None to calibrate each variant to ≥ 1 ms.
fn bench(fs: &mut [&mut dyn FnMut(u64)], reps: usize, batch: Option<u64>) -> Vec<Timing> {
    let batches: Vec<u64> = fs
        .iter_mut()
        .map(|f| {
            let b = calibrate(*f);
            batch.unwrap_or(b)
        })
        .collect();
    let mut out: Vec<Timing> =
        batches.iter().map(|&b| Timing { samples: Vec::with_capacity(reps), batch: b }).collect();
    for _ in 0..reps {
        for (f, t) in fs.iter_mut().zip(out.iter_mut()) {
            let start = Instant::now();
            f(t.batch);
            t.samples.push(start.elapsed().as_secs_f64() / t.batch as f64);
        }
    }
    out
}

// --------------------------------------------------------------- formats --

/// Time with a unit chosen for ~3 significant digits.
fn fmt_time(s: f64) -> String {
    if s < 1e-6 {
        format!("{:.1} ns", s * 1e9)
    } else if s < 1e-3 {
        format!("{:.2} µs", s * 1e6)
    } else {
        format!("{:.3} ms", s * 1e3)
    }
}

fn fmt_err(e: f64) -> String {
    format!("{e:.2e}")
}

/// A text table with right-aligned columns (width by chars, not bytes).
struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    fn new(header: &[&str]) -> Self {
        Table { header: header.iter().map(|s| s.to_string()).collect(), rows: Vec::new() }
    }
    fn row(&mut self, r: Vec<String>) {
        assert_eq!(r.len(), self.header.len());
        self.rows.push(r);
    }
    fn render(&self) -> String {
        let w: Vec<usize> = (0..self.header.len())
            .map(|j| {
                std::iter::once(&self.header[j])
                    .chain(self.rows.iter().map(|r| &r[j]))
                    .map(|s| s.chars().count())
                    .max()
                    .unwrap()
            })
            .collect();
        let line = |cells: &[String]| {
            let mut s = String::new();
            for (j, c) in cells.iter().enumerate() {
                let pad = w[j] - c.chars().count();
                s.push_str(&" ".repeat(pad + if j == 0 { 0 } else { 2 }));
                s.push_str(c);
            }
            s
        };
        let mut out = line(&self.header);
        out.push('\n');
        out.push_str(&"-".repeat(w.iter().sum::<usize>() + 2 * (w.len() - 1)));
        out.push('\n');
        for r in &self.rows {
            out.push_str(&line(r));
            out.push('\n');
        }
        out
    }
}

fn write_csv(dir: &Path, name: &str, header: &str, rows: &[String]) {
    let mut s = String::from(header);
    s.push('\n');
    for r in rows {
        s.push_str(r);
        s.push('\n');
    }
    fs::write(dir.join(name), s).expect("write csv");
}

// --------------------------------------------------------------- machine --

fn cpu_model() -> String {
    fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

fn cpu_mhz() -> String {
    fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("cpu MHz")).map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "?".into())
}

fn virtualised() -> &'static str {
    let flags = fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    if flags.lines().any(|l| l.starts_with("flags") && l.split_whitespace().any(|f| f == "hypervisor")) {
        " (virtual machine)"
    } else {
        ""
    }
}

fn load_average() -> String {
    fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_default()
}

/// UTC date and time from the system clock (civil-from-days, no dependency).
fn utc_now() -> String {
    let secs = SystemTime::now().duration_since(UNIX_EPOCH).map(|d| d.as_secs() as i64).unwrap_or(0);
    let (days, sod) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + if m <= 2 { 1 } else { 0 };
    format!("{y:04}-{m:02}-{d:02} {:02}:{:02} UTC", sod / 3600, (sod % 3600) / 60)
}

fn machine_header() -> String {
    let nproc = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(0);
    format!(
        "machine: {}{} | nproc {} | cpu MHz {} | load avg {} | {} | single thread, median of ≥{} reps of ≥1 ms batches",
        cpu_model(),
        virtualised(),
        nproc,
        cpu_mhz(),
        load_average(),
        utc_now(),
        REPS.min(THIN_REPS)
    )
}

// ------------------------------------------------------------------ tubes --

fn helical_material() -> Orthotropic {
    // Fibre-like wall, stiff along the helix (as tests/thick_tube.rs).
    Orthotropic::new(10.0, 2.0, 1.5, 0.35, 0.3, 0.4, 1.2, 0.8, 0.6).unwrap()
}

const TAU0: f64 = 1.7;

fn thick(a: f64, b: f64) -> ThickTube {
    ThickTube::new(a, b, TAU0, helical_material(), Compressibility::Compressible).unwrap()
}

/// Max-entry relative error, the measure of the thick model's estimator.
fn rel_err(k: &Matrix3<f64>, reference: &Matrix3<f64>) -> f64 {
    (k - reference).amax() / reference.amax()
}

/// Thin K (mid-radius variables) in the thick model's inner-radius variables:
/// ε_θ = (A/R) ε_A and 2πR²p = (R/A)·2πA²p, so K_inner = P K P, P = diag(1, 1, A/R).
fn thin_in_inner_variables(k_mid: &Matrix3<f64>, a: f64, r: f64) -> Matrix3<f64> {
    let p = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, a / r));
    p * k_mid * p
}

/// Collocation cost of one `coupling_stiffness_at(n)`: one dense LU of order
/// 2(n+1) (plus 3 solves and a 3×3 Cholesky), and n+1 evaluations of ℂ̄(R).
fn grid_cost(n: usize) -> (usize, usize) {
    (1, n + 1)
}

/// Cost of the adaptive `coupling_stiffness`, from its algorithm (grids n and
/// 1.5n, n = 8, 16, 32, … until the estimate passes): (LU factorisations,
/// ℂ̄ evaluations, largest LU order). Derived, not instrumented.
fn adaptive_cost(intervals_used: usize) -> (usize, usize, usize) {
    let (mut n, mut lus, mut evals) = (8, 0, 0);
    loop {
        let fine = n + n / 2;
        lus += 2;
        evals += (n + 1) + (fine + 1);
        if fine >= intervals_used {
            return (lus, evals, 2 * (fine + 1));
        }
        n *= 2;
    }
}

// ------------------------------------------------------------------ plots --

struct Series {
    label: String,
    points: Vec<(f64, f64)>,
    color: RGBColor,
    line: bool,
    marker: bool,
    dashed: bool,
}

/// The frame of a log–log chart: title, axis labels, dashed labelled guides
/// (horizontal at y, vertical at x) and where the legend goes.
struct LogLog<'a> {
    title: &'a str,
    xlabel: &'a str,
    ylabel: &'a str,
    hlines: Vec<(f64, String)>,
    vlines: Vec<(f64, String)>,
    legend: SeriesLabelPosition,
}

/// Log–log chart of `series` in the frame `frame`.
fn loglog(path: &Path, frame: &LogLog, series: &[Series]) -> Result<(), Box<dyn std::error::Error>> {
    let LogLog { title, xlabel, ylabel, hlines, vlines, legend } = frame;
    let (title, xlabel, ylabel, legend) = (*title, *xlabel, *ylabel, legend.clone());
    let pts = series.iter().flat_map(|s| s.points.iter()).filter(|(x, y)| *x > 0.0 && *y > 0.0);
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for &(x, y) in pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    for (y, _) in hlines {
        let y = *y;
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    for (x, _) in vlines {
        let x = *x;
        x0 = x0.min(x);
        x1 = x1.max(x);
    }
    // Pad by a quarter decade so the end points and their tick labels show.
    let pad = 10f64.powf(0.25);
    let (x0, x1, y0, y1) = (x0 / pad, x1 * pad, y0 / pad, y1 * pad);

    let root = SVGBackend::new(path, (960, 640)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(56)
        .y_label_area_size(84)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc(xlabel)
        .y_desc(ylabel)
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 15))
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(200, 200, 200))
        .draw()?;
    let guide = RGBColor(120, 120, 120);
    for (y, label) in hlines {
        let y = *y;
        chart.draw_series(DashedLineSeries::new(vec![(x0, y), (x1, y)], 6, 4, guide.stroke_width(1)))?;
        chart.draw_series(std::iter::once(Text::new(
            label.to_string(),
            (x0 * 1.15, y * 1.6),
            ("sans-serif", 14).into_font().color(&guide),
        )))?;
    }
    for (x, label) in vlines {
        let x = *x;
        chart.draw_series(DashedLineSeries::new(vec![(x, y0), (x, y1)], 6, 4, guide.stroke_width(1)))?;
        chart.draw_series(std::iter::once(Text::new(
            label.to_string(),
            (x * 1.1, y0 * 1.6),
            ("sans-serif", 14).into_font().color(&guide),
        )))?;
    }
    for s in series {
        let pts: Vec<(f64, f64)> = s.points.iter().cloned().filter(|(x, y)| *x > 0.0 && *y > 0.0).collect();
        let color = s.color;
        if s.line && s.dashed {
            chart
                .draw_series(DashedLineSeries::new(pts.clone(), 8, 5, color.stroke_width(2)))?
                .label(s.label.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2)));
        } else if s.line {
            chart
                .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))?
                .label(s.label.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2)));
        }
        if s.marker {
            let a = chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
            if !s.line {
                a.label(s.label.clone()).legend(move |(x, y)| Circle::new((x + 12, y), 4, color.filled()));
            }
        }
    }
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(legend)
        .draw()?;
    root.present()?;
    Ok(())
}

const BLUE_: RGBColor = RGBColor(31, 119, 180);
const ORANGE_: RGBColor = RGBColor(255, 127, 14);
const GREEN_: RGBColor = RGBColor(44, 160, 44);
const RED_: RGBColor = RGBColor(214, 39, 40);
const PURPLE_: RGBColor = RGBColor(148, 103, 189);
const BROWN_: RGBColor = RGBColor(140, 86, 75);

// ------------------------------------------------------------ section 1 --

struct ThinResult {
    rust_k: Timing,
    rust_spec: Timing,
    capi: Timing,
    overhead: f64,
}

fn spec_of(t: &ThinTube) -> ThinTubeSpec {
    ThinTubeSpec {
        mid_radius: t.mid_radius,
        thickness: t.thickness,
        intrinsic_twist: t.intrinsic_twist,
        e1: t.material.e1,
        e2: t.material.e2,
        nu12: t.material.nu12,
        g12: t.material.g12,
    }
}

fn section_thin(dir: &Path, report: &mut String) -> ThinResult {
    let tube = ThinTube::new(1.0, 0.05, TAU0, helical_material().surface()).unwrap();
    let spec = spec_of(&tube);

    // The C function and the Rust API must agree bitwise.
    let mut kc = [0.0f64; 9];
    let st = unsafe { rodkit_thin_tube_coupling_stiffness(&spec, kc.as_mut_ptr(), 3) };
    assert_eq!(st, 0, "C ABI returned status {st}");
    assert_eq!(kc, tube.coupling_stiffness().unwrap().column_major(), "C ABI and Rust API disagree");

    // (a) K of a prebuilt, validated tube.
    let mut rust_k = |b: u64| {
        for _ in 0..b {
            black_box(black_box(&tube).coupling_stiffness().unwrap());
        }
    };
    // (b) The work the C function does, in Rust: validate spec, build, K.
    let mut rust_spec = |b: u64| {
        for _ in 0..b {
            let s = black_box(&spec);
            let m = OrthotropicSurface::new(s.e1, s.e2, s.nu12, s.g12).unwrap();
            let t = ThinTube::new(s.mid_radius, s.thickness, s.intrinsic_twist, m).unwrap();
            black_box(t.coupling_stiffness().unwrap().column_major());
        }
    };
    // (c) The C ABI: same work plus guard (clear last error, catch_unwind),
    // pointer and ldk checks, strided write.
    let mut capi = |b: u64| {
        let mut k = [0.0f64; 9];
        let mut acc = 0i32;
        for _ in 0..b {
            acc |= unsafe {
                rodkit_thin_tube_coupling_stiffness(
                    black_box(&spec as *const _),
                    black_box(k.as_mut_ptr()),
                    black_box(3),
                )
            };
            black_box(&mut k);
        }
        assert_eq!(acc, 0);
    };
    let t = bench(&mut [&mut rust_k, &mut rust_spec, &mut capi], THIN_REPS, Some(THIN_BATCH));
    let (rust_k, rust_spec, capi) = (t[0].clone(), t[1].clone(), t[2].clone());
    // ABI overhead: median of the paired (same repetition) differences.
    let diffs: Vec<f64> = capi.samples.iter().zip(&rust_spec.samples).map(|(c, r)| c - r).collect();
    let overhead = median(&diffs);

    let mut tab =
        Table::new(&["variant", "median/call", "min", "max", "±spread", "calls", "× Rust K", "× Rust spec→K"]);
    let mut csv = Vec::new();
    for (name, tm) in [
        ("Rust: tube.coupling_stiffness()", &rust_k),
        ("Rust: spec → validate → K", &rust_spec),
        ("C ABI: rodkit_thin_tube_coupling_stiffness", &capi),
    ] {
        tab.row(vec![
            name.into(),
            fmt_time(tm.median()),
            fmt_time(tm.min()),
            fmt_time(tm.max()),
            format!("{:.1}%", tm.spread_pct()),
            format!("{}×{}", tm.samples.len(), tm.batch),
            format!("{:.3}", tm.median() / rust_k.median()),
            format!("{:.3}", tm.median() / rust_spec.median()),
        ]);
        csv.push(format!(
            "{name},{:e},{:e},{:e},{}",
            tm.median(),
            tm.min(),
            tm.max(),
            tm.samples.len() as u64 * tm.batch
        ));
    }
    write_csv(dir, "thin_k.csv", "variant,median_s,min_s,max_s,calls", &csv);
    let _ = writeln!(
        report,
        "\n== 1. Thin-tube K per call (R = 1, t = 0.05, τ0 = {TAU0}; 1 rotation Q̄(α), 1 Cholesky 3×3, 0 LU) =="
    );
    let _ = writeln!(report, "{}", tab.render());
    let _ = writeln!(
        report,
        "ABI overhead (C − Rust spec→K, median of {} paired reps): {:.1} ns ({:+.1}% of the Rust call)",
        diffs.len(),
        overhead * 1e9,
        100.0 * overhead / rust_spec.median()
    );
    ThinResult { rust_k, rust_spec, capi, overhead }
}

// ------------------------------------------------------------ section 2 --

struct WpResult {
    name: &'static str,
    /// (n, timing, true error)
    fixed: Vec<(usize, Timing, f64)>,
    /// (rel_tol, timing, intervals, estimate, true error)
    adaptive: Vec<(f64, Timing, usize, f64, f64)>,
    /// |K128 − K192| / max|K|: the reference's own round-off.
    ref_self: f64,
}

fn section_work_precision(dir: &Path, report: &mut String, thin_time: f64) -> Vec<WpResult> {
    let tubes = [
        ("thick A=0.6 B=1.4 (t/R=0.8)", thick(0.6, 1.4)),
        ("thin-ish A=0.975 B=1.025 (t/R=0.05)", thick(0.975, 1.025)),
    ];
    let mut results = Vec::new();
    let mut csv = Vec::new();
    for (name, tube) in tubes {
        let r = measure_work_precision(name, &tube, &mut csv);
        report_work_precision(report, &r, thin_time);
        results.push(r);
    }
    write_csv(
        dir,
        "work_precision.csv",
        "tube,method,n,rel_tol,median_s,min_s,max_s,intervals,estimate,true_error,lu_factorisations,cbar_evaluations",
        &csv,
    );
    plot_work_precision(dir, &results);
    results
}

/// One tube's work–precision: the true error of every fixed grid n = 4…64
/// and of the adaptive K at rel_tol 1e-4…1e-12 against 128 intervals, then
/// all of them timed in one interleaved run; their CSV lines into `csv`.
fn measure_work_precision(name: &'static str, tube: &ThickTube, csv: &mut Vec<String>) -> WpResult {
    let reference = tube.coupling_stiffness_at(128).unwrap().k;
    let check = tube.coupling_stiffness_at(192).unwrap().k;
    let ref_self = rel_err(&reference, &check);

    // Accuracy first, then every grid and tolerance timed in one
    // interleaved run, so drift on the shared machine hits them alike.
    let ns: Vec<usize> = (4..=64).collect();
    let tols: Vec<f64> = (4..=12).map(|e| 10f64.powi(-e)).collect();
    let errs: Vec<f64> = ns.iter().map(|&n| rel_err(&tube.coupling_stiffness_at(n).unwrap().k, &reference)).collect();
    let ests: Vec<_> = tols.iter().map(|&tol| tube.coupling_stiffness(tol).unwrap()).collect();
    let tube_ref = tube;
    let mut fs: Vec<Box<dyn FnMut(u64) + '_>> = Vec::new();
    for &n in &ns {
        fs.push(Box::new(move |b| {
            for _ in 0..b {
                black_box(black_box(tube_ref).coupling_stiffness_at(black_box(n)).unwrap());
            }
        }));
    }
    for &tol in &tols {
        fs.push(Box::new(move |b| {
            for _ in 0..b {
                black_box(black_box(tube_ref).coupling_stiffness(black_box(tol)).unwrap());
            }
        }));
    }
    let mut refs: Vec<&mut dyn FnMut(u64)> = fs.iter_mut().map(|f| &mut **f as &mut dyn FnMut(u64)).collect();
    let mut timings = bench(&mut refs, REPS, None).into_iter();
    drop(refs);

    let mut fixed = Vec::new();
    for (&n, &err) in ns.iter().zip(&errs) {
        let tm = timings.next().unwrap();
        let (lus, evals) = grid_cost(n);
        csv.push(format!(
            "{name},fixed,{n},,{:e},{:e},{:e},{n},,{:e},{lus},{evals}",
            tm.median(),
            tm.min(),
            tm.max(),
            err
        ));
        fixed.push((n, tm, err));
    }
    let mut adaptive = Vec::new();
    for (&tol, est) in tols.iter().zip(&ests) {
        let tm = timings.next().unwrap();
        let err = rel_err(&est.value.k, &reference);
        let (lus, evals, _) = adaptive_cost(est.intervals);
        csv.push(format!(
            "{name},adaptive,,{tol:e},{:e},{:e},{:e},{},{:e},{:e},{lus},{evals}",
            tm.median(),
            tm.min(),
            tm.max(),
            est.intervals,
            est.error_estimate,
            err
        ));
        adaptive.push((tol, tm, est.intervals, est.error_estimate, err));
    }

    WpResult { name, fixed, adaptive, ref_self }
}

/// Section 2's two tables for one tube: the fixed grids and the adaptive
/// tolerances, with costs, times and errors (marked * below the
/// reference's own round-off).
fn report_work_precision(report: &mut String, r: &WpResult, thin_time: f64) {
    let WpResult { name, fixed, adaptive, ref_self } = r;
    let ref_self = *ref_self;
    let _ = writeln!(report, "\n== 2. Thick K work–precision: {name}, τ0 = {TAU0}, compressible ==");
    let _ = writeln!(
        report,
        "reference: 128 intervals, its own round-off |K128 − K192|/max|K| = {ref_self:.1e} (errors below it, marked *, are\n\
         the reference's, not the grid's); error = max|K − Kref| / max|Kref|; thin K baseline {}",
        fmt_time(thin_time)
    );
    let mark = |e: f64| if e < ref_self { format!("{}*", fmt_err(e)) } else { fmt_err(e) };
    let mut tab = Table::new(&["n", "LU order", "ℂ̄ evals", "time/call", "±spread", "× thin K", "true error"]);
    for (n, tm, err) in fixed.iter() {
        if *n <= 16 || n % 8 == 0 {
            tab.row(vec![
                n.to_string(),
                (2 * (n + 1)).to_string(),
                (n + 1).to_string(),
                fmt_time(tm.median()),
                format!("{:.1}%", tm.spread_pct()),
                format!("{:.0}", tm.median() / thin_time),
                mark(*err),
            ]);
        }
    }
    let _ = writeln!(
        report,
        "fixed grid, coupling_stiffness_at(n) (n = 4..16 and every 8th; all n in the CSV):\n{}",
        tab.render()
    );
    let mut tab = Table::new(&[
        "rel_tol",
        "intervals",
        "LUs",
        "ℂ̄ evals",
        "time/call",
        "±spread",
        "× thin K",
        "estimate",
        "true error",
        "est ≥ true",
        "× cheapest fixed n meeting rel_tol",
    ]);
    for (tol, tm, n, est, err) in adaptive.iter() {
        let (lus, evals, _) = adaptive_cost(*n);
        // The price of not knowing the answer: the cheapest grid whose
        // true error meets rel_tol (undecidable below the reference's round-off).
        let cheapest =
            fixed.iter().filter(|(_, _, e)| e <= tol).map(|(_, t, _)| t.median()).fold(f64::INFINITY, f64::min);
        tab.row(vec![
            format!("{tol:.0e}"),
            n.to_string(),
            lus.to_string(),
            evals.to_string(),
            fmt_time(tm.median()),
            format!("{:.1}%", tm.spread_pct()),
            format!("{:.0}", tm.median() / thin_time),
            fmt_err(*est),
            mark(*err),
            if *err < ref_self {
                "n/a*"
            } else if est >= err {
                "yes"
            } else {
                "NO"
            }
            .into(),
            if cheapest.is_finite() && *tol >= ref_self {
                format!("{:.1}", tm.median() / cheapest)
            } else {
                "–".into()
            },
        ]);
    }
    let _ = writeln!(
        report,
        "adaptive, coupling_stiffness(rel_tol) (LUs / ℂ̄ evals derived from the algorithm):\n{}",
        tab.render()
    );
}

/// The work–precision plot of both tubes, fixed and adaptive, with the
/// targets and the references' round-off as guides.
fn plot_work_precision(dir: &Path, results: &[WpResult]) {
    let floor = 1e-17; // log plot: an exact match would be −∞
    let mut series = Vec::new();
    for (r, (c_fixed, c_adapt)) in results.iter().zip([(BLUE_, ORANGE_), (GREEN_, RED_)]) {
        series.push(Series {
            label: format!("{}: fixed n = 4…64", r.name),
            points: r.fixed.iter().map(|(_, t, e)| (t.median(), e.max(floor))).collect(),
            color: c_fixed,
            line: true,
            marker: true,
            dashed: false,
        });
        series.push(Series {
            label: format!("{}: adaptive, rel_tol 1e-4…1e-12", r.name),
            points: r.adaptive.iter().map(|(_, t, _, _, e)| (t.median(), e.max(floor))).collect(),
            color: c_adapt,
            line: false,
            marker: true,
            dashed: false,
        });
    }
    let frame = LogLog {
        title: "Thick-tube K work–precision (vs 128-interval reference)",
        xlabel: "time per call [s] (median)",
        ylabel: "relative error  max|K − Kref| / max|Kref|",
        hlines: vec![
            (1e-10, "target 1e-10".to_string()),
            (results[0].ref_self, format!("reference round-off, {}", results[0].name)),
            (results[1].ref_self, format!("reference round-off, {}", results[1].name)),
        ],
        vlines: vec![(200e-6, "target 200 µs".to_string())],
        legend: SeriesLabelPosition::UpperRight,
    };
    loglog(&dir.join("work_precision.svg"), &frame, &series).expect("plot work_precision.svg");
}

// ------------------------------------------------------------ section 3 --

/// One wall thickness of section 3: the thin and thick tubes, the thin
/// model's error per K entry and normed, and the thick model's grids at
/// 1e-10 and at the thin model's accuracy.
struct ThinThickCase {
    tr: f64,
    thin: ThinTube,
    tube: ThickTube,
    per_entry: Vec<f64>,
    normed: f64,
    match_tol: f64,
    n_accurate: usize,
    n_match: usize,
}

/// The K entries section 3 compares, (i, j) and their names.
const K_ENTRIES: [(usize, usize); 6] = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];
const K_NAMES: [&str; 6] = ["K_εε", "K_εψ", "K_εθ", "K_ψψ", "K_ψθ", "K_θθ"];
/// Section 3's accurate thick tolerance.
const THICK_TOL: f64 = 1e-10;

impl ThinThickCase {
    /// The tube of mid radius 1 and thickness t/R = `tr`.
    fn new(tr: f64) -> Self {
        let r = 1.0;
        let entries = K_ENTRIES;
        let thick_tol = THICK_TOL;
        let t = tr * r;
        let a = r - t / 2.0;
        let thin = ThinTube::new(r, t, TAU0, helical_material().surface()).unwrap();
        let tube = thick(a, r + t / 2.0);
        // Reference: a fixed 96-interval grid (converged to round-off; the
        // adaptive solver refuses 1e-12 below t/R ≈ 1e-2, where its floor
        // nε·B/t is above it).
        let converged = tube.coupling_stiffness_at(96).unwrap().k;
        let k_thin = thin_in_inner_variables(&thin.coupling_stiffness().unwrap().k, a, r);
        let per_entry: Vec<f64> =
            entries.iter().map(|&(i, j)| ((k_thin[(i, j)] - converged[(i, j)]) / converged[(i, j)]).abs()).collect();
        let normed = entries
            .iter()
            .map(|&(i, j)| (k_thin[(i, j)] - converged[(i, j)]).abs() / (converged[(i, i)] * converged[(j, j)]).sqrt())
            .fold(0.0, f64::max);
        // Thick at a tolerance matching the thin model's own error: what the
        // scene would pay for the thick model at the thin model's accuracy.
        let match_tol = normed.clamp(1e-12, 0.5);
        let n_accurate = tube.coupling_stiffness(thick_tol).unwrap().intervals;
        let n_match = tube.coupling_stiffness(match_tol).unwrap().intervals;
        ThinThickCase { tr, thin, tube, per_entry, normed, match_tol, n_accurate, n_match }
    }
}

/// Thin K, thick at 1e-10 and thick at the matched tolerance for every case,
/// timed in one interleaved run (three timings per case, in that order).
fn time_thin_thick(cases: &[ThinThickCase]) -> Vec<Timing> {
    let thick_tol = THICK_TOL;
    let mut fs: Vec<Box<dyn FnMut(u64) + '_>> = Vec::new();
    for c in cases {
        let (thin, tube, match_tol) = (&c.thin, &c.tube, c.match_tol);
        fs.push(Box::new(move |b| {
            for _ in 0..b {
                black_box(black_box(thin).coupling_stiffness().unwrap());
            }
        }));
        fs.push(Box::new(move |b| {
            for _ in 0..b {
                black_box(black_box(tube).coupling_stiffness(black_box(thick_tol)).unwrap());
            }
        }));
        fs.push(Box::new(move |b| {
            for _ in 0..b {
                black_box(black_box(tube).coupling_stiffness(black_box(match_tol)).unwrap());
            }
        }));
    }
    let mut refs: Vec<&mut dyn FnMut(u64)> = fs.iter_mut().map(|f| &mut **f as &mut dyn FnMut(u64)).collect();
    bench(&mut refs, REPS, None)
}

fn section_thin_vs_thick(dir: &Path, report: &mut String) {
    let ratios = [1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2, 0.1, 0.2, 0.5, 0.8];
    let mut tab = Table::new(&[
        "t/R",
        "K_εε",
        "K_εψ",
        "K_εθ",
        "K_ψψ",
        "K_ψθ",
        "K_θθ",
        "max normed",
        "thin",
        "thick 1e-10",
        "n",
        "× thin",
        "thick@thin err",
        "n",
        "× thin",
    ]);
    let mut csv = Vec::new();
    let mut err_series: Vec<Vec<(f64, f64)>> = vec![Vec::new(); 6];
    let mut normed_series = Vec::new();
    let cases: Vec<ThinThickCase> = ratios.iter().map(|&tr| ThinThickCase::new(tr)).collect();
    // Time thin, thick at 1e-10 and thick at the matched tolerance for every
    // t/R in one interleaved run.
    let timings = time_thin_thick(&cases);
    for (c, tm) in cases.iter().zip(timings.chunks(3)) {
        let (t_thin, t_thick, t_match) = (tm[0].median(), tm[1].median(), tm[2].median());
        for (s, e) in err_series.iter_mut().zip(&c.per_entry) {
            s.push((c.tr, *e));
        }
        normed_series.push((c.tr, c.normed));
        let mut row = vec![format!("{:.0e}", c.tr)];
        row.extend(c.per_entry.iter().map(|e| format!("{e:.1e}")));
        row.extend([
            format!("{:.1e}", c.normed),
            fmt_time(t_thin),
            fmt_time(t_thick),
            c.n_accurate.to_string(),
            format!("{:.0}", t_thick / t_thin),
            fmt_time(t_match),
            c.n_match.to_string(),
            format!("{:.0}", t_match / t_thin),
        ]);
        tab.row(row);
        csv.push(format!(
            "{:e},{},{:e},{t_thin:e},{t_thick:e},{},{:e},{t_match:e},{}",
            c.tr,
            c.per_entry.iter().map(|e| format!("{e:e}")).collect::<Vec<_>>().join(","),
            c.normed,
            c.n_accurate,
            c.match_tol,
            c.n_match
        ));
    }
    write_csv(
        dir,
        "thin_vs_thick.csv",
        "t_over_R,rel_err_Kee,rel_err_Kepsi,rel_err_Keth,rel_err_Kpsipsi,rel_err_Kpsith,rel_err_Kthth,max_normed_err,thin_s,thick_1e-10_s,thick_intervals,matched_tol,thick_matched_s,matched_intervals",
        &csv,
    );
    let _ = writeln!(report, "\n== 3. Thin closed form vs converged thick K (R = 1, τ0 = {TAU0}, inner-radius variables K_inner = P K_mid P) ==");
    let _ = writeln!(
        report,
        "per-entry |K_thin − K_thick| / |K_thick|; 'max normed' = max_ij |ΔK_ij| / √(K_ii K_jj); thick reference at rel_tol 1e-12;\n\
         timed: thin K, thick at rel_tol 1e-10, and thick at rel_tol = the thin model's 'max normed' error (same accuracy as thin)"
    );
    let _ = writeln!(report, "{}", tab.render());

    plot_thin_vs_thick(dir, err_series, normed_series);
}

/// Section 3's plot: the thin model's error per entry and normed against
/// t/R, with the guide error = t/R.
fn plot_thin_vs_thick(dir: &Path, err_series: Vec<Vec<(f64, f64)>>, normed_series: Vec<(f64, f64)>) {
    let colors = [BLUE_, ORANGE_, GREEN_, RED_, PURPLE_, BROWN_];
    let mut series: Vec<Series> = err_series
        .into_iter()
        .zip(K_NAMES.iter().zip(colors))
        .map(|(points, (name, color))| Series {
            label: format!("|ΔK|/|K| {name}"),
            points,
            color,
            line: true,
            marker: true,
            dashed: false,
        })
        .collect();
    series.push(Series {
        label: "max |ΔK_ij|/√(K_ii K_jj)".into(),
        points: normed_series,
        color: BLACK,
        line: true,
        marker: false,
        dashed: true,
    });
    series.push(Series {
        label: "guide: error = t/R".into(),
        points: vec![(1e-3, 1e-3), (0.8, 0.8)],
        color: RGBColor(160, 160, 160),
        line: true,
        marker: false,
        dashed: false,
    });
    let frame = LogLog {
        title: "Thin closed form vs converged thick K (τ0 = 1.7, helical orthotropic wall)",
        xlabel: "wall thickness t/R",
        ylabel: "relative error of the thin-tube K entry",
        hlines: vec![],
        vlines: vec![],
        legend: SeriesLabelPosition::LowerRight,
    };
    loglog(&dir.join("thin_vs_thick.svg"), &frame, &series).expect("plot thin_vs_thick.svg");
}

// ------------------------------------------------------------------ main --

// ------------------------------------------------------------ section 4 --

struct FiniteResult {
    state_1e10: f64,
    state_1e10_err: f64,
    sweep_100: f64,
}

/// Finite strain: one state of a thick helical SVK tube under torsion-free
/// stretching (λ = 1.2) per accuracy knob, the membrane side by side as the
/// cheap baseline, and a 100-point stretch sweep. True error against the
/// thick solve on 64 intervals (spectrally converged), in the solver's scales (ψB, radii per B).
fn section_finite(dir: &Path, report: &mut String) -> FiniteResult {
    use rodkit::tube::finite::{FiniteTube, Loading, SolveOptions, TubeState};
    use rodkit::tube::material::SaintVenantKirchhoff;
    use rodkit::tube::membrane::MembraneTube;
    let svk = SaintVenantKirchhoff::new(helical_material(), 1.7, false);
    let loading = Loading::torsion_free_stretch(1.2);
    let _ = writeln!(report, "\n== 4. Finite strain: torsion-free stretch λ = 1.2 of a helical SVK tube (τ0 = 1.7) ==");
    let _ = writeln!(
        report,
        "true error = max(|Δψ|·B, |Δb|/B, |Δa|/B) against the thick solve on a fixed 64-interval grid"
    );
    let _ = writeln!(
        report,
        "{:>10} {:>9} {:>8} {:>10} {:>9} {:>10} {:>11} {:>9}",
        "tube", "model", "rel_tol", "intervals", "Newton", "time", "estimate", "true err"
    );
    let mut rows = vec![];
    let mut out = FiniteResult { state_1e10: f64::NAN, state_1e10_err: f64::NAN, sweep_100: f64::NAN };
    for (name, a, b) in [("thick", 0.6, 1.4), ("t/R=0.05", 0.975, 1.025)] {
        let tube = FiniteTube::new(a, b, &svk).unwrap();
        let reference = tube.solve(&loading, &SolveOptions { rel_tol: 1e-12, intervals: Some(64) }).unwrap();
        let err = |s: &TubeState| {
            ((s.twist - reference.twist) * b)
                .abs()
                .max((s.deformed_outer_radius - reference.deformed_outer_radius).abs() / b)
                .max((s.deformed_inner_radius - reference.deformed_inner_radius).abs() / b)
        };
        for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
            let opts = SolveOptions { rel_tol: tol, intervals: None };
            let state = tube.solve(&loading, &opts).unwrap();
            let t = &bench(
                &mut [&mut |n: u64| {
                    for _ in 0..n {
                        std::hint::black_box(tube.solve(&loading, &opts).unwrap());
                    }
                }],
                7,
                None,
            )[0];
            let e = err(&state);
            let _ = writeln!(
                report,
                "{name:>10} {:>9} {tol:>8.0e} {:>10} {:>9} {:>10} {:>11.1e} {:>9.1e}",
                "thick",
                state.intervals,
                state.newton_iterations,
                fmt_time(t.median()),
                state.error_estimate,
                e
            );
            rows.push(format!(
                "{name},thick,{tol:e},{},{},{:e},{:e},{:e}",
                state.intervals,
                state.newton_iterations,
                t.median(),
                state.error_estimate,
                e
            ));
            if name == "thick" && tol == 1e-10 {
                out.state_1e10 = t.median();
                out.state_1e10_err = e;
            }
        }
        let membrane = MembraneTube::new(0.5 * (a + b), b - a, &svk).unwrap();
        let ms = membrane.solve(&loading).unwrap();
        let tm = &bench(
            &mut [&mut |n: u64| {
                for _ in 0..n {
                    std::hint::black_box(membrane.solve(&loading).unwrap());
                }
            }],
            7,
            None,
        )[0];
        let e = err(&ms);
        let _ = writeln!(
            report,
            "{name:>10} {:>9} {:>8} {:>10} {:>9} {:>10} {:>11.1e} {:>9.1e}",
            "membrane",
            "-",
            "-",
            ms.newton_iterations,
            fmt_time(tm.median()),
            ms.error_estimate,
            e
        );
        rows.push(format!(
            "{name},membrane,,0,{},{:e},{:e},{:e}",
            ms.newton_iterations,
            tm.median(),
            ms.error_estimate,
            e
        ));
    }
    let tube = FiniteTube::new(0.6, 1.4, &svk).unwrap();
    let loadings: Vec<Loading> = (0..100).map(|i| Loading::torsion_free_stretch(1.0 + 0.003 * i as f64)).collect();
    let opts = SolveOptions { rel_tol: 1e-10, intervals: None };
    let t = &bench(
        &mut [&mut |n: u64| {
            for _ in 0..n {
                std::hint::black_box(tube.sweep(&loadings, &opts, |_, _| true).unwrap());
            }
        }],
        7,
        None,
    )[0];
    out.sweep_100 = t.median();
    let _ = writeln!(
        report,
        "100-point torsion-free stretch sweep (λ 1 → 1.297, thick, rel_tol 1e-10): {} ({} per state)",
        fmt_time(t.median()),
        fmt_time(t.median() / 100.0)
    );
    rows.push(format!("thick,sweep100,1e-10,,,{:e},,", t.median()));
    write_csv(dir, "finite.csv", "tube,model,rel_tol,intervals,newton,time_s,estimate,true_error", &rows);
    out
}

/// Section 5: ψ(λ) and b(λ) of the behaviour cases (torsion-free sweeps
/// to rel_tol 1e−9), one CSV per case (parameters in its header) and two
/// SVGs: ψB against λ for the overwinding cases, b/B − 1 for the dips.
fn section_behaviour(dir: &Path, out: &mut String) {
    use rodkit::tube::finite::Loading;
    use rodkit::tube::scene::TubeScene;
    let _ = writeln!(out, "\n== 5. Finite-strain behaviours (curves; torsion-free stretching, rel_tol 1e-9) ==");
    let colors = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(148, 103, 189),
        RGBColor(255, 127, 14),
    ];
    let mut twist = vec![];
    let mut radius = vec![];
    for (k, case) in behaviour_cases::cases().iter().enumerate() {
        let dip = k >= 3;
        let lam_max: f64 = if dip { 1.4 } else { 1.2 };
        let lams: Vec<f64> =
            (0..=((lam_max - 1.0) / 0.0025).round() as usize).map(|i| 1.0 + 0.0025 * i as f64).collect();
        let loadings: Vec<Loading> = lams.iter().map(|&l| Loading::torsion_free_stretch(l)).collect();
        let scene =
            TubeScene::new(case.inner, case.outer, case.law.clone(), case.model, 1e-9, None).expect("case scene");
        let t = Instant::now();
        let states = match scene.sweep(&loadings, |_, _| true) {
            Ok((s, _)) => s.states,
            Err(e) => {
                let _ = writeln!(out, "{:<30} sweep failed: {}", case.name, e.message);
                continue;
            }
        };
        let secs = t.elapsed().as_secs_f64();
        let mut csv = format!(
            "# {} A={} B={} model={:?}\n# law: {:?}\nstretch,twist,outer_radius,inner_radius,applied_force\n",
            case.name, case.inner, case.outer, case.model, case.law
        );
        for s in &states {
            let _ = writeln!(
                csv,
                "{},{},{},{},{}",
                s.stretch, s.twist, s.deformed_outer_radius, s.deformed_inner_radius, s.applied_force
            );
        }
        let _ = fs::write(dir.join(format!("behaviour_{}.csv", case.name)), csv);
        let (key, scale, offset) =
            if dip { ("min b at λ", 1.0 / case.outer, 1.0) } else { ("ψ turns at λ", case.outer, 0.0) };
        let y: Vec<f64> = states
            .iter()
            .map(|s| if dip { s.deformed_outer_radius * scale - offset } else { s.twist * scale })
            .collect();
        let sense = if dip { -1.0 } else { y[1].signum() };
        let i = (0..y.len()).max_by(|&a, &b| (sense * y[a]).total_cmp(&(sense * y[b]))).unwrap();
        let _ = writeln!(
            out,
            "{:<30} {key} {:.4} ({} states in {:.0} ms)",
            case.name,
            states[i].stretch,
            states.len(),
            secs * 1e3
        );
        let pts: Vec<(f64, f64)> = states.iter().map(|s| s.stretch).zip(y).collect();
        if dip {
            radius.push((case.name, pts, colors[k]))
        } else {
            twist.push((case.name, pts, colors[k]))
        }
    }
    for (file, title, ylabel, series) in [
        ("behaviour_twist.svg", "Torsion-free stretching: overwinding, then unwinding", "twist ψB", &twist),
        ("behaviour_radius.svg", "Torsion-free stretching: deflation, then inflation", "outer radius b/B − 1", &radius),
    ] {
        if let Err(e) = line_plot(&dir.join(file), title, "stretch λ", ylabel, series) {
            let _ = writeln!(out, "plot {file} failed: {e}");
        }
    }
    let _ = writeln!(out, "curves: target/bench/tube/behaviour_*.csv, behaviour_twist.svg, behaviour_radius.svg");
}

fn main() {
    let wall = Instant::now();
    let dir: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench/tube");
    fs::create_dir_all(&dir).expect("create target/bench/tube");
    let mut report = String::new();
    let _ = writeln!(report, "rodkit {} tube benchmark", env!("CARGO_PKG_VERSION"));
    let _ = writeln!(report, "{}", machine_header());

    let thin = section_thin(&dir, &mut report);
    print!("{report}");
    let mut rest = String::new();
    let wp = section_work_precision(&dir, &mut rest, thin.rust_k.median());
    print!("{rest}");
    report.push_str(&rest);
    let mut rest = String::new();
    section_thin_vs_thick(&dir, &mut rest);
    print!("{rest}");
    report.push_str(&rest);
    let mut rest = String::new();
    let finite = section_finite(&dir, &mut rest);
    print!("{rest}");
    report.push_str(&rest);
    let mut rest = String::new();
    section_behaviour(&dir, &mut rest);
    print!("{rest}");
    report.push_str(&rest);

    // Targets (informational).
    let mut rest = String::new();
    let _ = writeln!(rest, "\n== Targets (informational; exit code 0 either way) ==");
    let pass = |ok: bool| if ok { "PASS" } else { "MISS" };
    let (tr, tc) = (thin.rust_spec.median(), thin.capi.median());
    let _ = writeln!(
        rest,
        "{}  thin K < 1 µs per call: Rust {} (prebuilt tube {}), C ABI {} (median of ≥10^6 calls)",
        pass(tr < 1e-6 && tc < 1e-6 && thin.rust_k.median() < 1e-6),
        fmt_time(tr),
        fmt_time(thin.rust_k.median()),
        fmt_time(tc)
    );
    let _ = writeln!(rest, "{}  ABI overhead ≤ 50 ns: {:.1} ns", pass(thin.overhead <= 50e-9), thin.overhead * 1e9);
    for r in &wp {
        let (_, tm, n, est, err) = r.adaptive.iter().find(|a| a.0 == 1e-10).unwrap();
        let best =
            r.fixed.iter().filter(|f| f.2 <= 1e-10).min_by(|a, b| a.1.median().partial_cmp(&b.1.median()).unwrap());
        let best = best
            .map(|(n, t, e)| {
                format!("cheapest fixed grid with true error ≤ 1e-10: n = {n}, {} ({e:.1e})", fmt_time(t.median()))
            })
            .unwrap_or("no fixed n ≤ 64 reaches 1e-10".into());
        let _ = writeln!(
            rest,
            "{}  thick K to 1e-10 < 200 µs, {}: coupling_stiffness(1e-10) {} at {n} intervals (estimate {est:.1e}, true {err:.1e}); {best}",
            pass(tm.median() < 200e-6 && *err <= 1e-10),
            r.name,
            fmt_time(tm.median())
        );
    }
    let _ = writeln!(
        rest,
        "{}  one thick finite-strain state to 1e-10 < 1 ms: {} (true error {:.1e})",
        pass(finite.state_1e10 < 1e-3 && finite.state_1e10_err <= 1e-10),
        fmt_time(finite.state_1e10),
        finite.state_1e10_err
    );
    let _ = writeln!(
        rest,
        "{}  100-point stretch sweep < 50 ms: {}",
        pass(finite.sweep_100 < 50e-3),
        fmt_time(finite.sweep_100)
    );
    let _ = writeln!(rest, "\nCSV and SVG in {}; bench wall time {:.1} s", dir.display(), wall.elapsed().as_secs_f64());
    print!("{rest}");
    report.push_str(&rest);
    fs::write(dir.join("report.txt"), report).expect("write report");
}

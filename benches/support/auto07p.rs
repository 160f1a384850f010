//! AUTO-07p as a benchmark peer (std only). Include from a bench binary with
//! `#[path = "support/auto07p.rs"] mod auto07p;`.
//!
//! The problems, constants templates and the shell runner live in `benches/auto/` (see its
//! README.md). This module
//! 1. compiles each problem once per process into a cached executable
//!    (`run.sh build`; build dir `$RODKIT_AUTO_BUILD`, default `<tmp>/rodkit-auto07p-build`,
//!    rebuilt only when a Fortran source is newer than the executable);
//! 2. writes the constants files for the requested NTST and tolerance (`run.sh prepare`);
//! 3. runs the executable itself, stdin = constants file, `OMP_NUM_THREADS=1`, timing the
//!    process alone with `Instant` (spawn to exit);
//! 4. parses AUTO's output:
//!    - `fort.7` (b-file, 11 significant digits): rows `BR PT TY LAB PAR(1) ...` with BR ≠ 0;
//!      the number of continuation steps of a branch is max|PT| − 1 (PT = 1 is the start point);
//!    - `fort.8` (s-file): every labelled solution (EP, UZ, BP) as a header of 16 integers
//!      `IBR NTOT ITP LAB NFPR ISW NTPL NAR NROWPR NTST NCOL NPAR ...` followed by NROWPR lines:
//!      NTPL rows of (t, U(1..NDIM)) [NDIM = NAR − 1], for BVPs (NTST > 0) then the NFPR free
//!      parameter indices, their derivatives RLDOT w.r.t. arclength, NTPL rows of U-dot, and
//!      finally PAR(1..NPAR). The tip is the row t = 1; PAR(5) is the tip rotation (degrees),
//!      PAR(6) = |q(L)|² − 1, both set in PVLS;
//!    - `fort.9` (diagnostics): Newton iterations are the rows `BR PT IT PAR L2-NORM` with IT ≥ 1
//!      (continuation steps and special-point location together).
//!
//! AUTO's step control decides where the computed points land; the fixed α are reached as user
//! zeros (UZR = {1: [1, 2, 5]}, UZSTOP = {1: 10}) located by AUTO to ~EPSS. The located Λ can be
//! off by more than that (seen: Λ = 2.00058 instead of 2 when the previous step ended 5e−5 short
//! of the target), so [`Point::tip_at`] moves the point to the exact Λ along the tangent stored in
//! the s-file (first order: error ½|r''|ΔΛ²); [`Point::offset`] reports ΔΛ.
#![allow(dead_code)]

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// AUTO point types (ITP modulo 10 in fort.7/fort.8).
pub fn type_name(itp: i64) -> &'static str {
    match itp {
        1 | 6 => "BP",
        2 | 5 => "LP",
        3 => "HB",
        4 => "RG",
        -4 => "UZ",
        7 => "PD",
        8 => "TR",
        9 | -9 => "EP",
        _ => "??",
    }
}

/// One labelled solution from the s-file.
#[derive(Clone, Debug)]
pub struct Point {
    pub branch: i64,
    /// Point number on its branch (|PT|).
    pub pt: i64,
    /// AUTO type code (6 = BP of a BVP, -4 = UZ, 9 = EP).
    pub itp: i64,
    pub label: i64,
    /// Load parameter Λ = PAR(1) (= α, since K_b = L = 1).
    pub lambda: f64,
    /// r(L) from the mesh point t = 1.
    pub tip: [f64; 3],
    /// q(L) = (q0, q1, q2, q3).
    pub q_tip: [f64; 4],
    /// Tip rotation about e2 in degrees, 2 atan2(q2, q0) (PAR(5)).
    pub rotation_deg: f64,
    /// |q(L)|² − 1 (PAR(6)).
    pub q_drift: f64,
    /// d r(L) / dΛ and d(rotation)/dΛ from the stored tangent (None where dΛ/ds = 0, e.g. at a BP
    /// approached along the trivial branch the tangent is still fine; at a fold it is not).
    pub dtip_dlambda: Option<[f64; 3]>,
    pub drot_dlambda: Option<f64>,
    /// All parameters PAR(1..NPAR) (stiffnesses in PAR(21..26)).
    pub par: Vec<f64>,
    /// Mesh intervals actually stored (NTST) and the mesh (t values).
    pub ntst: usize,
    pub mesh: Vec<f64>,
}

impl Point {
    pub fn type_name(&self) -> &'static str {
        type_name(self.itp)
    }
    /// Λ − target.
    pub fn offset(&self, target: f64) -> f64 {
        self.lambda - target
    }
    /// Tip position moved to Λ = target along the tangent (first order).
    pub fn tip_at(&self, target: f64) -> [f64; 3] {
        let d = target - self.lambda;
        match self.dtip_dlambda {
            Some(g) if d != 0.0 => [self.tip[0] + d * g[0], self.tip[1] + d * g[1], self.tip[2] + d * g[2]],
            _ => self.tip,
        }
    }
    /// Tip rotation (degrees) moved to Λ = target along the tangent (first order).
    pub fn rotation_at(&self, target: f64) -> f64 {
        let d = target - self.lambda;
        match self.drot_dlambda {
            Some(g) if d != 0.0 => self.rotation_deg + d * g,
            _ => self.rotation_deg,
        }
    }
}

/// Result of one AUTO computation (one executable run for `follower`, two for `euler`).
#[derive(Clone, Debug)]
pub struct AutoRun {
    /// Wall time of the executable(s) alone (sum over the runs of this computation).
    pub wall: Duration,
    /// Wall time of each executable run (euler: trivial branch, then post-buckled branch).
    pub wall_runs: Vec<Duration>,
    /// CPU time (user + system) of the executable(s) by their own process
    /// accounting, summed: what AUTO costs as its users run it.
    pub cpu: Duration,
    /// Continuation steps (Σ over branches of max|PT| − 1).
    pub steps: usize,
    /// Steps per branch, in branch order.
    pub steps_per_branch: Vec<usize>,
    /// Newton iterations reported in fort.9 (steps and special-point location).
    pub newton_iterations: usize,
    /// Labelled solutions of all runs, in output order.
    pub points: Vec<Point>,
    /// Directory that held fort.7/8/9 (and b./s./d.euler1) of this computation: removed after a
    /// successful parse unless `RODKIT_AUTO_KEEP` is set; kept (and named in the error) on failure.
    pub work_dir: PathBuf,
    pub ntst: usize,
    pub tol: f64,
}

impl AutoRun {
    /// Branch points (BP) found.
    pub fn branch_points(&self) -> Vec<&Point> {
        self.points.iter().filter(|p| p.itp == 6 || p.itp == 1).collect()
    }
    /// User-defined point (UZ) nearest to Λ = target, if within 1e−2 (relative to max(1, target)).
    pub fn at_lambda(&self, target: f64) -> Option<&Point> {
        self.points
            .iter()
            .filter(|p| p.itp == -4 && (p.lambda - target).abs() <= 1e-2 * target.abs().max(1.0))
            .min_by(|a, b| (a.lambda - target).abs().total_cmp(&(b.lambda - target).abs()))
    }
    /// Last labelled point (the end of the last branch).
    pub fn end_point(&self) -> Option<&Point> {
        self.points.last()
    }
}

/// Options beyond NTST and the tolerance (defaults are those of `run.sh`).
#[derive(Clone, Debug)]
pub struct Options {
    /// Collocation points per mesh interval (NCOL, 2…7). Default 4.
    pub ncol: u32,
    /// Mesh adaption every IAD steps (0 = fixed uniform mesh). Default 3.
    pub iad: u32,
    /// DSMAX. Default 0.5.
    pub dsmax: f64,
    /// EPSS; None = 10·tol.
    pub epss: Option<f64>,
}

impl Default for Options {
    fn default() -> Self {
        Options { ncol: 4, iad: 3, dsmax: 0.5, epss: None }
    }
}

fn auto_src_dir() -> PathBuf {
    if let Ok(d) = std::env::var("RODKIT_AUTO_SRC") {
        return PathBuf::from(d);
    }
    match option_env!("CARGO_MANIFEST_DIR") {
        Some(m) => Path::new(m).join("benches").join("auto"),
        None => PathBuf::from("benches/auto"),
    }
}

fn build_dir() -> PathBuf {
    match std::env::var("RODKIT_AUTO_BUILD") {
        Ok(d) => PathBuf::from(d),
        Err(_) => std::env::temp_dir().join("rodkit-auto07p-build"),
    }
}

fn run_sh(args: &[&str]) -> Result<String, String> {
    let script = auto_src_dir().join("run.sh");
    let out = Command::new("sh")
        .arg(&script)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("cannot run {}: {e}", script.display()))?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    } else {
        Err(format!(
            "{} {:?} failed: {}{}",
            script.display(),
            args,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

static BUILD: OnceLock<Result<PathBuf, String>> = OnceLock::new();

fn build() -> Result<PathBuf, String> {
    BUILD
        .get_or_init(|| {
            run_sh(&["check"]).map_err(|e| format!("AUTO-07p not available: {}", e.trim()))?;
            let dir = build_dir();
            run_sh(&["build", &dir.to_string_lossy()])?;
            Ok(dir)
        })
        .clone()
}

/// Ok(()) if AUTO-07p is installed and the problems compile; Err(message) otherwise.
pub fn availability() -> Result<(), String> {
    build().map(|_| ())
}

/// True if AUTO-07p can be used; otherwise prints why to stderr (the caller skips the peer).
pub fn available() -> bool {
    match availability() {
        Ok(()) => true,
        Err(e) => {
            eprintln!("auto07p: skipped ({e})");
            false
        }
    }
}

static COUNTER: AtomicUsize = AtomicUsize::new(0);

fn work_dir(problem: &str) -> Result<PathBuf, String> {
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let d = std::env::temp_dir().join(format!("rodkit-auto07p-{}-{}-{}", problem, std::process::id(), n));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).map_err(|e| format!("{}: {e}", d.display()))?;
    Ok(d)
}

fn cleanup(dir: &Path) {
    if std::env::var_os("RODKIT_AUTO_KEEP").is_none() {
        let _ = fs::remove_dir_all(dir);
    }
}

fn prepare(problem: &str, dir: &Path, ntst: usize, tol: f64, opt: &Options) -> Result<(), String> {
    let script = auto_src_dir().join("run.sh");
    let mut cmd = Command::new("sh");
    cmd.arg(&script)
        .args(["prepare", problem, &dir.to_string_lossy(), &ntst.to_string(), &format!("{tol:e}")])
        .env("AUTO_NCOL", opt.ncol.to_string())
        .env("AUTO_IAD", opt.iad.to_string())
        .env("AUTO_DSMAX", format!("{:e}", opt.dsmax));
    if let Some(e) = opt.epss {
        cmd.env("AUTO_EPSS", format!("{e:e}"));
    }
    let out = cmd.output().map_err(|e| format!("cannot run {}: {e}", script.display()))?;
    if !out.status.success() {
        return Err(format!("run.sh prepare failed: {}", String::from_utf8_lossy(&out.stderr)));
    }
    Ok(())
}

/// Runs one executable in `dir` with stdin = `constants`; returns the wall
/// time of the process and its own CPU time (the RUSAGE_CHILDREN difference
/// across its wait: the only child that ends in between).
fn run_exe(exe: &Path, dir: &Path, constants: &str) -> Result<(Duration, Duration), String> {
    let input = fs::File::open(dir.join(constants)).map_err(|e| format!("{constants}: {e}"))?;
    let output = fs::File::create(dir.join(format!("{constants}.stdout"))).map_err(|e| e.to_string())?;
    let cpu0 = crate::timing::cpu_time(true);
    let t0 = Instant::now();
    let status = Command::new(exe)
        .current_dir(dir)
        .env("OMP_NUM_THREADS", "1")
        .stdin(Stdio::from(input))
        .stdout(Stdio::from(output))
        .stderr(Stdio::piped())
        .status()
        .map_err(|e| format!("{}: {e}", exe.display()))?;
    let dt = t0.elapsed();
    let cpu = crate::timing::cpu_time(true).saturating_sub(cpu0);
    if !status.success() {
        return Err(format!("{} failed ({status}) in {}", exe.display(), dir.display()));
    }
    Ok((dt, cpu))
}

fn parse_f64(s: &str) -> Option<f64> {
    if let Ok(v) = s.parse::<f64>() {
        return Some(v);
    }
    // Fortran drops the 'E' when the exponent has 3 digits in a 2-digit field: 1.0-100.
    let b = s.as_bytes();
    for i in (1..b.len()).rev() {
        if (b[i] == b'+' || b[i] == b'-') && b[i - 1].is_ascii_digit() {
            return format!("{}E{}", &s[..i], &s[i..]).parse().ok();
        }
    }
    None
}

/// Parses every solution of an s-file (fort.8) into labelled points.
pub fn parse_s_file(text: &str) -> Result<Vec<Point>, String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut pts = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let hdr: Vec<i64> = match lines[i].split_whitespace().map(|t| t.parse::<i64>()).collect() {
            Ok(v) => v,
            Err(_) => return Err(format!("s-file: line {} is not a header: {:?}", i + 1, lines[i])),
        };
        if hdr.len() < 12 {
            return Err(format!("s-file: short header at line {}", i + 1));
        }
        let (ibr, ntot, itp, lab, nfpr) = (hdr[0], hdr[1], hdr[2], hdr[3], hdr[4] as usize);
        let (ntpl, nar, nrowpr, ntst, npar) =
            (hdr[6] as usize, hdr[7] as usize, hdr[8] as usize, hdr[9] as usize, hdr[11] as usize);
        let ndim = nar - 1;
        if i + 1 + nrowpr > lines.len() {
            return Err("s-file: truncated solution".into());
        }
        let mut v = Vec::with_capacity(nrowpr * 7);
        for l in &lines[i + 1..i + 1 + nrowpr] {
            for t in l.split_whitespace() {
                v.push(parse_f64(t).ok_or_else(|| format!("s-file: bad number {t:?}"))?);
            }
        }
        i += 1 + nrowpr;
        let need = ntpl * nar + if ntst > 0 { 2 * nfpr + ntpl * ndim } else { 0 } + npar;
        if v.len() != need || ndim < 7 {
            return Err(format!("s-file: solution {lab}: {} numbers, expected {need}", v.len()));
        }
        let grid = &v[..ntpl * nar];
        let mesh: Vec<f64> = (0..ntpl).map(|j| grid[j * nar]).collect();
        let last = &grid[(ntpl - 1) * nar + 1..ntpl * nar];
        let mut k = ntpl * nar;
        let (mut dtip, mut drot) = (None, None);
        if ntst > 0 {
            let rldot = &v[k + nfpr..k + 2 * nfpr];
            k += 2 * nfpr;
            let ud = &v[k + (ntpl - 1) * ndim..k + ntpl * ndim];
            k += ntpl * ndim;
            let dl = rldot[0];
            if dl.abs() > 1e-12 {
                dtip = Some([ud[0] / dl, ud[1] / dl, ud[2] / dl]);
                let (q0, q2) = (last[3], last[5]);
                let (dq0, dq2) = (ud[3] / dl, ud[5] / dl);
                drot = Some(2.0 * (q0 * dq2 - q2 * dq0) / (q0 * q0 + q2 * q2) * 180.0 / std::f64::consts::PI);
            }
        }
        let par = v[k..k + npar].to_vec();
        pts.push(Point {
            branch: ibr,
            pt: ntot.abs(),
            itp,
            label: lab,
            lambda: par[0],
            tip: [last[0], last[1], last[2]],
            q_tip: [last[3], last[4], last[5], last[6]],
            rotation_deg: par.get(4).copied().unwrap_or(f64::NAN),
            q_drift: par.get(5).copied().unwrap_or(f64::NAN),
            dtip_dlambda: dtip,
            drot_dlambda: drot,
            par,
            ntst,
            mesh,
        });
    }
    Ok(pts)
}

/// Steps per branch from a b-file (fort.7): max|PT| − 1 over rows with BR ≠ 0.
pub fn parse_b_steps(text: &str) -> Vec<(i64, usize)> {
    let mut out: Vec<(i64, usize)> = Vec::new();
    for l in text.lines() {
        let t: Vec<&str> = l.split_whitespace().collect();
        if t.len() < 5 {
            continue;
        }
        let (Ok(br), Ok(pt)) = (t[0].parse::<i64>(), t[1].parse::<i64>()) else { continue };
        if br == 0 {
            continue;
        }
        let s = (pt.unsigned_abs() as usize).saturating_sub(1);
        match out.iter_mut().find(|(b, _)| *b == br) {
            Some(e) => e.1 = e.1.max(s),
            None => out.push((br, s)),
        }
    }
    out
}

/// Newton iterations in a diagnostics file (fort.9): rows "BR PT IT PAR L2-NORM" with IT ≥ 1.
pub fn parse_d_newton(text: &str) -> usize {
    text.lines()
        .filter(|l| {
            let t: Vec<&str> = l.split_whitespace().collect();
            t.len() == 5
                && t[0].parse::<i64>().is_ok()
                && t[1].parse::<i64>().is_ok()
                && t[2].parse::<i64>().map(|it| it >= 1).unwrap_or(false)
                && t[3].contains('E')
        })
        .count()
}

fn read(dir: &Path, f: &str) -> Result<String, String> {
    fs::read_to_string(dir.join(f)).map_err(|e: io::Error| format!("{}: {e}", dir.join(f).display()))
}

fn collect(
    dir: &Path,
    pairs: &[(&str, &str, &str)],
    runs: Vec<(Duration, Duration)>,
    ntst: usize,
    tol: f64,
) -> Result<AutoRun, String> {
    let walls: Vec<Duration> = runs.iter().map(|r| r.0).collect();
    let mut points = Vec::new();
    let mut steps_per_branch = Vec::new();
    let mut newton = 0;
    for (b, s, d) in pairs {
        points.extend(parse_s_file(&read(dir, s)?)?);
        steps_per_branch.extend(parse_b_steps(&read(dir, b)?).into_iter().map(|(_, n)| n));
        newton += parse_d_newton(&read(dir, d)?);
    }
    Ok(AutoRun {
        wall: walls.iter().sum(),
        wall_runs: walls,
        cpu: runs.iter().map(|r| r.1).sum(),
        steps: steps_per_branch.iter().sum(),
        steps_per_branch,
        newton_iterations: newton,
        points,
        work_dir: dir.to_path_buf(),
        ntst,
        tol,
    })
}

/// Follower cantilever (benches/auto/follower.f90), Λ from 0 to 10 with UZ at 1, 2, 5, 10.
pub fn follower(ntst: usize, tol: f64) -> Result<AutoRun, String> {
    follower_with(ntst, tol, &Options::default())
}

pub fn follower_with(ntst: usize, tol: f64, opt: &Options) -> Result<AutoRun, String> {
    let bdir = build()?;
    let dir = work_dir("follower")?;
    prepare("follower", &dir, ntst, tol, opt)?;
    let t = run_exe(&bdir.join("follower.exe"), &dir, "c.follower")?;
    let run = collect(&dir, &[("fort.7", "fort.8", "fort.9")], vec![t], ntst, tol)?;
    if run.at_lambda(10.0).is_none() {
        return Err(format!("follower: Λ = 10 not reached (see {})", dir.display()));
    }
    cleanup(&dir);
    Ok(run)
}

/// Dead-load cantilever (benches/auto/follower.f90 with -DDEAD_LOAD): the tip force Λ e1 fixed
/// in space, Λ from 0 to 10 with UZ at 1, 2, 5, 10.
pub fn dead_with(ntst: usize, tol: f64, opt: &Options) -> Result<AutoRun, String> {
    let bdir = build()?;
    let dir = work_dir("dead")?;
    prepare("dead", &dir, ntst, tol, opt)?;
    let t = run_exe(&bdir.join("dead.exe"), &dir, "c.dead")?;
    let run = collect(&dir, &[("fort.7", "fort.8", "fort.9")], vec![t], ntst, tol)?;
    if run.at_lambda(10.0).is_none() {
        return Err(format!("dead: Λ = 10 not reached (see {})", dir.display()));
    }
    cleanup(&dir);
    Ok(run)
}

/// Euler buckling (benches/auto/euler.f90): run 1 along the straight branch to the first BP,
/// run 2 switches branch there (ISW = −1) and follows the post-buckled branch to a tip rotation
/// of ±170°. The BP is `branch_points()[0]`, the end `end_point()`.
pub fn euler(ntst: usize, tol: f64) -> Result<AutoRun, String> {
    euler_with(ntst, tol, &Options::default())
}

pub fn euler_with(ntst: usize, tol: f64, opt: &Options) -> Result<AutoRun, String> {
    let bdir = build()?;
    let exe = bdir.join("euler.exe");
    let dir = work_dir("euler")?;
    prepare("euler", &dir, ntst, tol, opt)?;
    let t1 = run_exe(&exe, &dir, "c.euler.1")?;
    for (from, to) in [("fort.7", "b.euler1"), ("fort.8", "s.euler1"), ("fort.9", "d.euler1")] {
        fs::rename(dir.join(from), dir.join(to)).map_err(|e| format!("{from}: {e}"))?;
    }
    let t2 = run_exe(&exe, &dir, "c.euler.2")?;
    let run = collect(
        &dir,
        &[("b.euler1", "s.euler1", "d.euler1"), ("fort.7", "fort.8", "fort.9")],
        vec![t1, t2],
        ntst,
        tol,
    )?;
    if run.branch_points().is_empty() {
        return Err(format!("euler: no branch point detected (see {})", dir.display()));
    }
    cleanup(&dir);
    Ok(run)
}

/// Critical load of the extensible, shearable clamped–free rod (physics.md §2.6):
/// P (1 + P (1/GA − 1/EA)) = π² K_b / (4 L²).
pub fn euler_critical_load(kb: f64, l: f64, ga: f64, ea: f64) -> f64 {
    let pe = std::f64::consts::PI.powi(2) * kb / (4.0 * l * l);
    let a = 1.0 / ga - 1.0 / ea;
    if a == 0.0 {
        pe
    } else {
        2.0 * pe / (1.0 + (1.0 + 4.0 * a * pe).sqrt())
    }
}

//! The MPI tube search (fortran_examples/mpi_tube_search.f90, issue 21),
//! built through the Makefile (`f_mpi_tube_search`, with mpif90) and run with
//! `mpirun --oversubscribe -np 1/2/4` on a small search (48 samples, seed 1,
//! chunks of 4; a few seconds per run on the 2-core machine):
//!   - the gathered CSVs are bitwise identical for 1, 2 and 4 ranks, whose
//!     chunks are dealt dynamically (each taken once, by more than one
//!     rank), and a shorter search (--samples 8, --chunk 3) reproduces the
//!     first rows;
//!   - the numbers are re-evaluated here with the Rust API (`rodkit::tube`),
//!     from the parameters read back from the CSV, by a classifier written
//!     here from the rules the driver documents;
//!   - a run killed part-way (SIGKILL to every process of its session, as a
//!     batch scheduler kills a job) restarts, says it skipped the finished
//!     chunks and gathers the same bytes as an uninterrupted run.
//!
//! Needs OpenMPI (`.ci/deps` installs libopenmpi-dev and openmpi-bin): the
//! tests fail, not skip, without it. mpirun runs as root here, so the
//! environment of every mpirun carries OMPI_ALLOW_RUN_AS_ROOT(_CONFIRM).

use rodkit::tube::finite::Loading;
use rodkit::tube::material::{FibreAngle, FibreFamily, FibreReinforced, NeoHookean, SaintVenantKirchhoff};
use rodkit::tube::scene::{TubeModel, TubeScene, WallLaw};
use rodkit::tube::Orthotropic;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{Mutex, MutexGuard, OnceLock};
use std::time::{Duration, Instant};

#[path = "support/native_build.rs"]
mod native_build;
use native_build::{build_lib_and_make, check, profile, ROOT};
/// The search every test runs (the reference is its 1-rank run).
const SEARCH: [&str; 6] = ["--samples", "48", "--seed", "1", "--chunk", "4"];
const SAMPLES: usize = 48;
const CHUNK: usize = 4;

fn out_root() -> PathBuf {
    Path::new(ROOT).join("target").join(profile()).join("mpi_tube_search")
}

/// The MPI runs share the 2 cores: one at a time.
fn serial() -> MutexGuard<'static, ()> {
    static LOCK: Mutex<()> = Mutex::new(());
    LOCK.lock().unwrap_or_else(|e| e.into_inner())
}

/// The library (release cdylib) and the driver, through the Makefile.
fn driver() -> &'static PathBuf {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(|| {
        for tool in ["mpif90", "mpirun"] {
            let found = Command::new("sh").args(["-c", &format!("command -v {tool}")]).output();
            assert!(
                found.is_ok_and(|o| o.status.success()),
                "{tool} is missing: install OpenMPI (.ci/deps installs libopenmpi-dev and openmpi-bin)"
            );
        }
        let exe = Path::new(ROOT).join("target").join(profile()).join("native").join("f_mpi_tube_search");
        build_lib_and_make(&[exe.to_str().unwrap()]);
        exe
    })
}

/// `mpirun --oversubscribe -np <np> f_mpi_tube_search <args> <dir>`, run by
/// `launcher` (e.g. setsid) when given.
fn mpirun(launcher: Option<&str>, np: usize, args: &[&str], dir: &Path) -> Command {
    let mut c = match launcher {
        Some(l) => {
            let mut c = Command::new(l);
            c.arg("mpirun");
            c
        }
        None => Command::new("mpirun"),
    };
    c.env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .args(["--oversubscribe", "-np", &np.to_string()])
        .arg(driver())
        .args(args)
        .arg(dir);
    c
}

/// A run from scratch into `name`: its report and its folder.
fn fresh_run(np: usize, args: &[&str], name: &str) -> (String, PathBuf) {
    let dir = out_root().join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(out_root()).unwrap();
    let t = Instant::now();
    let report = check(mpirun(None, np, args, &dir).output().expect("run mpirun"), &format!("mpirun -np {np}"));
    eprintln!("mpirun -np {np} {args:?}: {:.1} s\n{report}", t.elapsed().as_secs_f64());
    (report, dir)
}

/// The uninterrupted 1-rank run of SEARCH (made once).
fn reference() -> &'static (String, PathBuf) {
    static REF: OnceLock<(String, PathBuf)> = OnceLock::new();
    REF.get_or_init(|| fresh_run(1, &SEARCH, "np1"))
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// samples.csv as rows of named fields.
fn rows(dir: &Path) -> Vec<HashMap<String, String>> {
    let text = String::from_utf8(read(&dir.join("samples.csv"))).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(str::to_string).collect();
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), header.len(), "row with a wrong field count: {l}");
            header.iter().cloned().zip(f.iter().map(|s| s.to_string())).collect()
        })
        .collect()
}

fn num(r: &HashMap<String, String>, k: &str) -> f64 {
    let v = &r[k];
    v.parse::<f64>().unwrap_or_else(|e| panic!("field {k} = `{v}`: {e}"))
}

fn int(r: &HashMap<String, String>, k: &str) -> i64 {
    r[k].parse::<i64>().unwrap_or_else(|e| panic!("field {k} = `{}`: {e}", r[k]))
}

/// The `label <n>` number of a report line.
fn reported(report: &str, prefix: &str, label: &str) -> i64 {
    let line = report.lines().find(|l| l.starts_with(prefix)).unwrap_or_else(|| panic!("no `{prefix}` in\n{report}"));
    let rest = &line[line.find(label).unwrap_or_else(|| panic!("no `{label}` in `{line}`")) + label.len()..];
    rest.trim_start().split(|c: char| !c.is_ascii_digit()).next().unwrap().parse().unwrap()
}

/// The report's `chunks taken per rank: a b c` (rank order).
fn taken_per_rank(report: &str) -> Vec<usize> {
    let line = report.lines().find_map(|l| l.strip_prefix("chunks taken per rank:"));
    line.unwrap_or_else(|| panic!("no chunk counts in\n{report}"))
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect()
}

#[test]
fn gathered_csv_is_bitwise_identical_for_1_2_and_4_ranks() {
    let _g = serial();
    let (report, one) = reference();
    assert_eq!(taken_per_rank(report), vec![SAMPLES.div_ceil(CHUNK)]);
    for np in [2, 4] {
        let (report, dir) = fresh_run(np, &SEARCH, &format!("np{np}"));
        for f in ["samples.csv", "hits.csv"] {
            assert!(read(&one.join(f)) == read(&dir.join(f)), "{f}: -np {np} differs from -np 1");
        }
        // Dynamic balance: every chunk taken once, by more than one rank.
        let taken = taken_per_rank(&report);
        assert_eq!(taken.len(), np, "{report}");
        assert_eq!(taken.iter().sum::<usize>(), SAMPLES.div_ceil(CHUNK), "{report}");
        assert!(taken.iter().filter(|&&t| t > 0).count() >= 2, "one rank took every chunk: {taken:?}");
    }
    // Sample i is a function of (seed, i) alone: a shorter search with
    // other chunks gives the first rows byte for byte.
    let (_, short) = fresh_run(1, &["--samples", "8", "--seed", "1", "--chunk", "3"], "short");
    let full = String::from_utf8(read(&one.join("samples.csv"))).unwrap();
    let part = String::from_utf8(read(&short.join("samples.csv"))).unwrap();
    assert!(full.starts_with(&part), "the 8-sample search is not the head of the 48-sample one");

    // The report agrees with the CSV, and the search is not vacuous.
    let r = rows(one);
    assert_eq!(r.len(), SAMPLES);
    let count = |k: &str| r.iter().filter(|x| x[k] == "1").count() as i64;
    assert_eq!(reported(report, "overwind-then-unwind", "confirmed"), count("confirmed_rev"));
    assert_eq!(reported(report, "deflate-then-inflate", "confirmed"), count("confirmed_dip"));
    assert_eq!(reported(report, "overwind-then-unwind", "coarse"), count("coarse_rev"));
    assert_eq!(reported(report, "failed:", "failed:"), count("failed"));
    assert!(
        count("confirmed_rev") > 0 && count("confirmed_dip") > 0,
        "no hit of each kind: the checks below need them"
    );
    let hits = String::from_utf8(read(&one.join("hits.csv"))).unwrap();
    let n_hits = r.iter().filter(|x| x["confirmed_rev"] == "1" || x["confirmed_dip"] == "1").count();
    assert_eq!(hits.lines().count(), n_hits + 1, "hits.csv: header + the confirmed hits");
    assert!(report.contains("checkpoints: none found; computed 48 samples"), "{report}");
}

// ------------------------------------------------- the Rust re-evaluation --

/// The wall of a CSV row, rebuilt with the Rust API (E1 = 1, μ = 1 as the
/// driver documents).
fn law(r: &HashMap<String, String>) -> WallLaw {
    let inc = int(r, "incompressible") == 1;
    match r["class"].as_str() {
        "svk_thick" | "svk_thick_inc" => {
            let c: Vec<f64> =
                ["e2", "e3", "nu12", "nu13", "nu23", "g12", "g13", "g23"].iter().map(|k| num(r, k)).collect();
            let m = Orthotropic::new(1.0, c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]).unwrap();
            WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(m, num(r, "tau0"), inc))
        }
        class => {
            let matrix = NeoHookean {
                shear_modulus: 1.0,
                lame_lambda: if inc { 0.0 } else { num(r, "lame_lambda") },
                incompressible: inc,
            };
            let angle = |k: &str, hand: f64| {
                if class == "hgo_fixed" {
                    FibreAngle::Fixed(num(r, k))
                } else {
                    assert!(r[k].is_empty(), "{class}: {k} should be empty (helix)");
                    FibreAngle::Helix { hand }
                }
            };
            let families = vec![
                FibreFamily { angle: angle("fibre1_angle", 1.0), k1: num(r, "fibre1_k1"), k2: num(r, "fibre1_k2") },
                FibreFamily { angle: angle("fibre2_angle", -1.0), k1: num(r, "fibre2_k1"), k2: num(r, "fibre2_k2") },
            ];
            WallLaw::FibreReinforced(FibreReinforced { matrix, families, intrinsic_twist: num(r, "tau0") })
        }
    }
}

/// The driver's grids: 1 → lam_max by h1 up to 1.1, then by h2.
fn grid(lam_max: f64, h1: f64, h2: f64) -> Vec<f64> {
    let mut v = vec![1.0];
    let n1 = (0.1 / h1).round() as i64;
    let mut k = 0i64;
    while *v.last().unwrap() < lam_max - 1e-9 {
        k += 1;
        let l = if k <= n1 { 1.0 + k as f64 * h1 } else { 1.1 + (k - n1) as f64 * h2 };
        v.push(l.min(lam_max));
    }
    v
}

/// (λ, ψ, b) of a torque-free sweep up to where it stops.
fn curve(r: &HashMap<String, String>, intervals: usize, rel_tol: f64, lams: &[f64]) -> Vec<(f64, f64, f64)> {
    let scene =
        TubeScene::new(num(r, "inner"), num(r, "outer"), law(r), TubeModel::Thick, rel_tol, Some(intervals)).unwrap();
    let loadings: Vec<Loading> = lams.iter().map(|&l| Loading::torsion_free_stretch(l)).collect();
    let mut pts = vec![];
    let _ = scene.sweep(&loadings, |_, s| {
        pts.push((s.stretch, s.twist, s.deformed_outer_radius));
        true
    });
    pts
}

/// A turn of y(λ): (kind +1 max / −1 min, sample index, λ of the parabola
/// vertex, its value, prominence), from the driver's documented rules.
fn turn(lam: &[f64], y: &[f64], noise: f64) -> Option<(i32, usize, f64, f64, f64)> {
    // Walk the samples; a new extreme candidate each time y moves on in the
    // current direction; a turn once it moves back by more than `noise`.
    let mut ext = vec![];
    let (mut dir, mut cand) = (0i32, 0usize);
    for i in 1..y.len() {
        let d = y[i] - y[cand];
        if dir == 0 {
            if d.abs() > noise {
                dir = if d > 0.0 { 1 } else { -1 };
                cand = i;
            }
        } else if d * dir as f64 > 0.0 {
            cand = i;
        } else if -d * dir as f64 > noise {
            ext.push((cand, dir));
            if ext.len() == 2 {
                break;
            }
            dir = -dir;
            cand = i;
        }
    }
    let &(i, kind) = ext.first()?;
    let (mut l, mut v) = (lam[i], y[i]);
    if i > 0 && i + 1 < y.len() {
        // Vertex of the parabola through samples i−1, i, i+1 (Lagrange form).
        let (x0, x1, x2, y0, y1, y2) = (lam[i - 1], lam[i], lam[i + 1], y[i - 1], y[i], y[i + 1]);
        let (d01, d12) = ((y1 - y0) / (x1 - x0), (y2 - y1) / (x2 - x1));
        let c2 = (d12 - d01) / (x2 - x0);
        if c2 != 0.0 {
            let xs = 0.5 * (x0 + x1) - d01 / (2.0 * c2);
            if xs > x0 && xs < x2 {
                l = xs;
                v = y0 + d01 * (xs - x0) + c2 * (xs - x0) * (xs - x1);
            }
        }
    }
    let end = ext.get(1).map_or(y.len(), |e| e.0 + 1);
    let tail = y[i..end].iter().copied();
    let other = if kind > 0 { tail.fold(f64::INFINITY, f64::min) } else { tail.fold(f64::NEG_INFINITY, f64::max) };
    Some((kind, i, l, v, (v - other).abs()))
}

fn start(y: &[f64], noise: f64) -> i32 {
    y.iter().find(|v| (**v - y[0]).abs() > noise).map_or(0, |v| if *v > y[0] { 1 } else { -1 })
}

/// What a curve shows: (reversal: sense, λ, s·ψ·B) and (dip: λ, depth).
struct Found {
    sense: i32,
    rev: Option<(f64, f64)>,
    dip: Option<(f64, f64)>,
}

fn classify(pts: &[(f64, f64, f64)], outer: f64, fibre: bool) -> Found {
    let lam: Vec<f64> = pts.iter().map(|p| p.0).collect();
    let psi: Vec<f64> = pts.iter().map(|p| p.1).collect();
    let b: Vec<f64> = pts.iter().map(|p| p.2).collect();
    let scale = psi.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let noise = 1e-10 / outer + 1e-9 * scale;
    let s = start(&psi, noise);
    let rev = turn(&lam, &psi, noise)
        .filter(|&(kind, _, _, _, prom)| {
            s != 0 && s * kind > 0 && prom > 1e-3 * scale && prom * outer > 1e-7 && (fibre || s > 0)
        })
        .map(|(_, _, l, v, _)| (l, s as f64 * v * outer));
    let nb = 1e-10 * outer;
    let dip = turn(&lam, &b, nb)
        .filter(|&(kind, _, _, _, prom)| kind < 0 && start(&b, nb) < 0 && prom > 1e-6 * outer)
        .map(|(_, _, l, v, _)| (l, (outer - v) / outer));
    Found { sense: s, rev, dip }
}

/// Re-evaluates one gathered sample's coarse curve (and, for a confirmed
/// hit, its 24-interval fine curve) with the Rust API and compares. The
/// reference is rodkit's Rust solver on the parameters read back from the
/// CSV (17 significant digits: exact), classified here. Same solver and
/// inputs, so the curves agree to rounding: tolerance 1e-9 on the turn's λ
/// and 1e-9 relative on ψ·B and depth (measured: identical).
fn recheck(r: &HashMap<String, String>) {
    let tag = format!("sample {} ({})", r["index"], r["class"]);
    let outer = num(r, "outer");
    let fibre = r["class"].starts_with("hgo");
    let close = |a: f64, b: f64, tol: f64, what: &str| {
        eprintln!("{tag}: {what}: driver {a:e}, Rust {b:e}, difference {:e}", a - b);
        assert!((a - b).abs() <= tol * b.abs().max(1.0), "{tag}: {what}: driver {a}, Rust {b}");
    };
    let pts = curve(r, 16, 1e-7, &grid(1.5, 0.005, 0.01));
    assert_eq!(pts.len() as i64, int(r, "coarse_states"), "{tag}: states solved");
    close(num(r, "coarse_solved_to"), pts.last().unwrap().0, 0.0, "last stretch");
    let f = classify(&pts, outer, fibre);
    assert_eq!(int(r, "rev_sense"), f.sense as i64, "{tag}: sense");
    assert_eq!(int(r, "coarse_rev") == 1, f.rev.is_some(), "{tag}: coarse reversal");
    assert_eq!(int(r, "coarse_dip") == 1, f.dip.is_some(), "{tag}: coarse dip");
    if let Some((l, peak)) = f.rev {
        close(num(r, "coarse_rev_lam"), l, 1e-9, "coarse reversal λ");
        close(num(r, "coarse_rev_peak_psiB"), peak, 1e-9, "coarse ψ·B at the turn");
    }
    if let Some((l, depth)) = f.dip {
        close(num(r, "coarse_dip_lam"), l, 1e-9, "coarse dip λ");
        close(num(r, "coarse_dip_depth"), depth, 1e-9, "coarse dip depth");
    }
    if int(r, "checked") == 1 {
        let lam_max = num(r, "coarse_solved_to").min(1.5);
        let fine = curve(r, 24, 1e-9, &grid(lam_max, 0.0025, 0.005));
        assert_eq!(fine.len() as i64, int(r, "fine24_states"), "{tag}: fine states");
        let g = classify(&fine, outer, fibre);
        assert_eq!(int(r, "fine24_rev") == 1, g.rev.is_some(), "{tag}: fine reversal");
        assert_eq!(int(r, "fine24_dip") == 1, g.dip.is_some(), "{tag}: fine dip");
        if let Some((l, _)) = g.rev {
            close(num(r, "fine24_rev_lam"), l, 1e-9, "fine reversal λ");
        }
        if let Some((l, _)) = g.dip {
            close(num(r, "fine24_dip_lam"), l, 1e-9, "fine dip λ");
        }
        // A confirmed turn: the fine curve shows it where the coarse one
        // did (within 0.02 in λ: 2 coarse steps beyond 1.1).
        if int(r, "confirmed_rev") == 1 {
            close(num(r, "coarse_rev_lam"), g.rev.unwrap().0, 0.02, "confirmed reversal, coarse vs fine λ");
        }
        if int(r, "confirmed_dip") == 1 {
            close(num(r, "coarse_dip_lam"), g.dip.unwrap().0, 0.02, "confirmed dip, coarse vs fine λ");
        }
    }
}

#[test]
fn gathered_numbers_agree_with_the_rust_api() {
    let _g = serial();
    let (_, dir) = reference();
    let r = rows(dir);
    let first = |what: &str, p: &dyn Fn(&HashMap<String, String>) -> bool| {
        r.iter().find(|x| p(x)).unwrap_or_else(|| panic!("the search has no {what}: choose another seed"))
    };
    let picks = [
        first("confirmed SVK reversal", &|x| x["confirmed_rev"] == "1" && x["class"].starts_with("svk")),
        first("confirmed fibre-wall reversal", &|x| x["confirmed_rev"] == "1" && x["class"].starts_with("hgo")),
        first("confirmed dip", &|x| x["confirmed_dip"] == "1"),
        first("non-hit solved to 1.5", &|x| {
            x["coarse_rev"] == "0" && x["coarse_dip"] == "0" && x["coarse_states"] == "61"
        }),
        first("sweep stopped early", &|x| x["failed"] == "0" && int(x, "coarse_status") < 0),
    ];
    for p in picks {
        recheck(p);
    }
    // The draws: sample i's first two of its MINSTD block (x ← 48271 x mod
    // 2^31 − 1 from 48271^(256 i)·(1 + seed)) give A (log-uniform in
    // [0.02, 0.7]) and τ0 (uniform in [0.5, 6]) for the SVK classes.
    let (m, a) = (2147483647u64, 48271u64);
    for x in r.iter().filter(|x| x["class"].starts_with("svk")).take(4) {
        let i: u64 = x["index"].parse().unwrap();
        let mut s = 2u64; // 1 + seed
        for _ in 0..256 * i {
            s = s * a % m;
        }
        let mut u = || {
            s = s * a % m;
            s as f64 / m as f64
        };
        let inner = (0.02f64.ln() + (0.7f64.ln() - 0.02f64.ln()) * u()).exp();
        let tau0 = 0.5 + 5.5 * u();
        for (k, want) in [("inner", inner), ("tau0", tau0)] {
            let got = num(x, k);
            assert!((got - want).abs() <= 4.0 * f64::EPSILON * want, "sample {i}: {k} = {got}, generator gives {want}");
        }
    }
}

// ------------------------------------------------------ kill and restart --

/// Every process of session `sid` (the /proc stat field after ppid, pgrp).
fn session_members(sid: u32) -> Vec<u32> {
    let mut pids = vec![];
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = e.file_name().to_string_lossy().parse::<u32>() else { continue };
        let Ok(stat) = std::fs::read_to_string(e.path().join("stat")) else { continue };
        let Some(rest) = stat.rfind(')').map(|i| &stat[i + 2..]) else { continue };
        // state ppid pgrp session ...
        if rest.split(' ').nth(3).and_then(|s| s.parse::<u32>().ok()) == Some(sid) {
            pids.push(pid);
        }
    }
    pids
}

fn chunk_files(dir: &Path) -> usize {
    std::fs::read_dir(dir.join("checkpoints")).map_or(0, |d| {
        d.flatten()
            .filter(|e| {
                let n = e.file_name().to_string_lossy().into_owned();
                n.starts_with("chunk_") && n.ends_with(".bin")
            })
            .count()
    })
}

#[test]
fn killed_search_restarts_from_its_checkpoints() {
    let _g = serial();
    let (_, one) = reference();
    let dir = out_root().join("killed");
    let _ = std::fs::remove_dir_all(&dir);
    // mpirun in a session of its own (setsid execs it: pid = session id);
    // OpenMPI puts each rank in its own process group, so the job is killed
    // as a scheduler does: SIGKILL to every process of the session.
    let mut child = mpirun(Some("setsid"), 2, &SEARCH, &dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("setsid mpirun");
    let sid = child.id();
    let t = Instant::now();
    while !session_members(sid).contains(&sid) {
        assert!(t.elapsed() < Duration::from_secs(5), "setsid did not make mpirun a session leader");
        std::thread::sleep(Duration::from_millis(5));
    }
    let total = SAMPLES.div_ceil(CHUNK);
    loop {
        let n = chunk_files(&dir);
        if n >= 2 {
            assert!(n < total, "all {total} chunks finished before the kill: make the search longer");
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "the search ended before the kill");
        assert!(t.elapsed() < Duration::from_secs(60), "no checkpoint after 60 s");
        std::thread::sleep(Duration::from_millis(10));
    }
    for _ in 0..50 {
        let pids = session_members(sid);
        if pids.is_empty() {
            break;
        }
        let _ = Command::new("kill").arg("-KILL").args(pids.iter().map(|p| p.to_string())).status();
        let _ = child.try_wait();
        std::thread::sleep(Duration::from_millis(100));
    }
    let _ = child.wait();
    assert!(session_members(sid).is_empty(), "processes of the killed search survive");
    let done = chunk_files(&dir);
    assert!(done >= 2 && done < total, "{done} of {total} chunks after the kill");
    assert!(!dir.join("samples.csv").exists(), "the killed run gathered");

    let report = check(mpirun(None, 2, &SEARCH, &dir).output().expect("run mpirun"), "restart");
    eprintln!("restart after {done} chunks:\n{report}");
    let expect = format!("restart: skipped {} samples ({done} chunks) found in checkpoints", done * CHUNK);
    assert!(report.contains(&expect), "expected `{expect}` in\n{report}");
    for f in ["samples.csv", "hits.csv"] {
        assert!(
            read(&one.join(f)) == read(&dir.join(f)),
            "{f}: the restarted search differs from the uninterrupted one"
        );
    }
}

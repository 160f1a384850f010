//! AUTO-07p peer smoke run and measurement (`cargo bench --bench auto_smoke [-- options]`).
//! Skips (exit 0) when AUTO-07p is not installed. Needs only std, so it also builds alone:
//! `rustc -O --edition 2021 benches/auto_smoke.rs -o /tmp/auto_smoke` (run from the crate root).
//!
//! Options: --ntst 4,8,16,32,64  --reps 5  --tol 1e-10  --iad 3  --dsmax 0.5
//!
//! 1. Follower cantilever: tip r(L) at α = 1, 2, 5, 10 for each NTST (NCOL = 4), moved to the exact
//!    α along AUTO's tangent (see auto07p.rs), max-norm difference from the finest NTST
//!    (self-convergence), max |Λ_UZ − α| of the located user points, steps, Newton iterations,
//!    and the median wall time of the executable alone over --reps runs (OMP_NUM_THREADS=1).
//! 2. Euler buckling: AUTO's branch point vs P(1 + P(1/GA − 1/EA)) = π²K_b/(4L²), the end of the
//!    post-buckled branch (tip rotation 170°), median times of run 1 (to the BP) and run 1 + run 2.

#[path = "support/auto07p.rs"]
mod auto07p;
#[path = "support/timing.rs"]
mod timing;
use timing::{median, ms};

use std::time::Duration;

/// The run's settings (command-line options).
struct Settings {
    ntsts: Vec<usize>,
    reps: usize,
    tol: f64,
    opt: auto07p::Options,
}

/// One follower run: NTST, AUTO's first run, the median wall time.
type FollowerRow = (usize, auto07p::AutoRun, Duration);

/// The loads of the follower cantilever's tips.
const ALPHAS: [f64; 4] = [1.0, 2.0, 5.0, 10.0];

fn main() {
    let settings = parse_args();
    if !auto07p::available() {
        println!("auto_smoke: AUTO-07p not available, skipped");
        return;
    }
    let Settings { reps, tol, opt, .. } = &settings;
    println!(
        "AUTO-07p peer: NCOL = 4, EPSL = EPSU = {tol:e}, EPSS = {:e}, IAD = {}, DSMAX = {}, reps = {reps}",
        opt.epss.unwrap_or(10.0 * tol),
        opt.iad,
        opt.dsmax
    );
    // 1. Follower cantilever.
    let rows = follower_runs(&settings);
    print_follower_tips(&rows);
    print_follower_errors(&rows);
    print_self_convergence(&rows);
    euler_table(&settings);
}

/// --ntst 4,8,16,32,64  --reps 5  --tol 1e-10  --iad 3  --dsmax 0.5 (see
/// the module docs); unknown arguments (cargo's --bench) are skipped.
fn parse_args() -> Settings {
    let mut ntsts = vec![4usize, 8, 16, 32, 64];
    let mut reps = 5usize;
    let mut tol = 1e-10f64;
    let mut opt = auto07p::Options::default();
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let val = args.get(i + 1).cloned().unwrap_or_default();
        match args[i].as_str() {
            "--ntst" => ntsts = val.split(',').map(|s| s.trim().parse().expect("--ntst")).collect(),
            "--reps" => reps = val.parse().expect("--reps"),
            "--tol" => tol = val.parse().expect("--tol"),
            "--iad" => opt.iad = val.parse().expect("--iad"),
            "--dsmax" => opt.dsmax = val.parse().expect("--dsmax"),
            "--bench" => {
                i += 1;
                continue;
            }
            _ => {
                i += 1;
                continue;
            }
        }
        i += 2;
    }
    reps = reps.max(1);
    ntsts.sort();
    Settings { ntsts, reps, tol, opt }
}

/// The follower cantilever at every NTST, `reps` times (the first run kept,
/// the median time).
fn follower_runs(settings: &Settings) -> Vec<FollowerRow> {
    let Settings { ntsts, reps, tol, opt } = settings;
    let (reps, tol) = (*reps, *tol);
    let mut rows = Vec::new();
    for &n in ntsts {
        let mut times = Vec::new();
        let mut first = None;
        for _ in 0..reps {
            match auto07p::follower_with(n, tol, opt) {
                Ok(r) => {
                    times.push(r.wall);
                    if first.is_none() {
                        first = Some(r);
                    }
                }
                Err(e) => {
                    println!("follower NTST={n}: {e}");
                    break;
                }
            }
        }
        if let Some(r) = first {
            rows.push((n, r, median(times)));
        }
    }
    rows
}

/// The tips r(L) at α = 1, 2, 5, 10 per NTST.
fn print_follower_tips(rows: &[FollowerRow]) {
    let alphas = ALPHAS;
    println!("\nFollower cantilever (n_b(L) = (α, 0, 0), K_b = L = 1, GA = 1e4, EA = 2.6e4): tip r(L)");
    println!(
        "{:>5} {:>5} {:>7} {:>10} | {:>34} {:>34} {:>34} {:>34}",
        "NTST", "steps", "Newton", "time ms", "α=1 (x, z, θ°)", "α=2", "α=5", "α=10"
    );
    for (n, r, t) in rows {
        let mut s = format!("{n:>5} {:>5} {:>7} {:>10.3} |", r.steps, r.newton_iterations, ms(*t));
        for &a in &alphas {
            match r.at_lambda(a) {
                Some(p) => {
                    let x = p.tip_at(a);
                    s += &format!(" {:>11.8} {:>11.8} {:>10.5}", x[0], x[2], p.rotation_at(a));
                }
                None => s += &format!(" {:>34}", "-"),
            }
        }
        println!("{s}");
    }
}

/// The error of the tips against the IVP reference per NTST.
fn print_follower_errors(rows: &[FollowerRow]) {
    // Independent reference: the same ODEs as an initial value problem from the tip (the body-frame
    // balance laws do not involve r, q), RK4 with 4000 and 8000 steps agreeing to 1e-14
    // (benches/auto/follower_ref.py). (x, z) of r(L) at α = 1, 2, 5, 10.
    const REF: [(f64, f64, f64); 4] = [
        (1.0, 0.320733716958396, 0.935607133550777),
        (2.0, 0.573976059384911, 0.767222368120490),
        (5.0, 0.780543504306729, 0.171858340274402),
        (10.0, 0.546160066660168, -0.092243859973626),
    ];
    println!("\nError vs the IVP reference: max(|x − x_ref|, |y|, |z − z_ref|) at exact α (tangent-corrected)");
    println!("{:>5} {:>10} {:>10} {:>10} {:>10} {:>10}", "NTST", "α=1", "α=2", "α=5", "α=10", "time ms");
    for (n, r, t) in rows {
        let mut s = format!("{n:>5}");
        for &(a, xr, zr) in &REF {
            match r.at_lambda(a) {
                Some(p) => {
                    let x = p.tip_at(a);
                    let e = (x[0] - xr).abs().max(x[1].abs()).max((x[2] - zr).abs());
                    s += &format!(" {e:>10.2e}");
                }
                None => s += &format!(" {:>10}", "-"),
            }
        }
        println!("{s} {:>10.3}", ms(*t));
    }
}

/// Self-convergence against the finest NTST, and how far AUTO's user points
/// were from the exact α before the tangent correction.
fn print_self_convergence(rows: &[FollowerRow]) {
    let alphas = ALPHAS;
    if let Some((nref, rref, _)) = rows.last() {
        println!("\nSelf-convergence: max-norm |r(L) − r_ref(L)| with r_ref from NTST = {nref}; ΔΛ = max |Λ_UZ − α| before the tangent correction");
        println!(
            "{:>5} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
            "NTST", "α=1", "α=2", "α=5", "α=10", "ΔΛ", "time ms"
        );
        for (n, r, t) in rows {
            let mut s = format!("{n:>5}");
            let mut dl: f64 = 0.0;
            for &a in &alphas {
                match (r.at_lambda(a), rref.at_lambda(a)) {
                    (Some(p), Some(q)) => {
                        let (x, y) = (p.tip_at(a), q.tip_at(a));
                        let e = (0..3).map(|k| (x[k] - y[k]).abs()).fold(0.0, f64::max);
                        dl = dl.max(p.offset(a).abs());
                        s += &format!(" {e:>10.2e}");
                    }
                    _ => s += &format!(" {:>10}", "-"),
                }
            }
            println!("{s} {dl:>10.2e} {:>10.3}", ms(*t));
        }
    }
}

/// Euler buckling: AUTO's branch point against P_cr and the end of the
/// post-buckled branch against the IVP reference, per NTST.
fn euler_table(settings: &Settings) {
    let Settings { ntsts, reps, tol, opt } = settings;
    let (reps, tol) = (*reps, *tol);
    // 2. Euler buckling.
    println!("\nEuler buckling (clamped–free, dead axial load; K_b1 = 2, K_b2 = K_b = 1 fixes the plane)");
    let pcr = auto07p::euler_critical_load(1.0, 1.0, 1e4, 2.6e4);
    println!(
        "reference P_cr = {pcr:.12} (P(1 + P(1/GA − 1/EA)) = π²/4; inextensible π²/4 = {:.12})",
        std::f64::consts::PI.powi(2) / 4.0
    );
    // End of the post-buckled branch (θ = 170°): IVP from the tip + secant on P, RK4 with 2000 and
    // 4000 steps agreeing to 4e−12 (benches/auto/euler_ref.py): (P, x_tip, z_tip).
    const END_REF: (f64, f64, f64) = (14.691919500598, 0.519800200812, -0.472417468332);
    println!(
        "end of the post-buckled branch at θ = 170°: reference P = {}, r(L) = ({}, 0, {})",
        END_REF.0, END_REF.1, END_REF.2
    );
    println!(
        "{:>5} {:>16} {:>10} {:>6} {:>12} {:>12} {:>12} {:>9} {:>10} {:>10} {:>12} {:>12}",
        "NTST",
        "P_cr AUTO",
        "rel err",
        "steps",
        "Λ(170°)",
        "x_tip",
        "z_tip",
        "θ°",
        "ΔΛ(170°)",
        "Δr(170°)",
        "t run1 ms",
        "t total ms"
    );
    for &n in ntsts {
        let mut t1s = Vec::new();
        let mut ts = Vec::new();
        let mut first = None;
        for _ in 0..reps {
            match auto07p::euler_with(n, tol, opt) {
                Ok(r) => {
                    t1s.push(r.wall_runs[0]);
                    ts.push(r.wall);
                    if first.is_none() {
                        first = Some(r);
                    }
                }
                Err(e) => {
                    println!("euler NTST={n}: {e}");
                    break;
                }
            }
        }
        let Some(r) = first else { continue };
        let bp = r.branch_points()[0].clone();
        let end = r.end_point().unwrap();
        let dr = (end.tip[0] - END_REF.1).abs().max(end.tip[1].abs()).max((end.tip[2] - END_REF.2).abs());
        println!(
            "{n:>5} {:>16.12} {:>10.2e} {:>6} {:>12.8} {:>12.8} {:>12.8} {:>9.4} {:>10.2e} {:>10.2e} {:>12.3} {:>12.3}",
            bp.lambda,
            (bp.lambda - pcr) / pcr,
            r.steps,
            end.lambda,
            end.tip[0],
            end.tip[2],
            end.rotation_deg,
            (end.lambda - END_REF.0).abs(),
            dr,
            ms(median(t1s)),
            ms(median(ts))
        );
    }
}

//! `rodkit_curve_electrostatic_energy_within` as a C caller meets it
//! (`cargo bench --bench electrostatics`): every call on a curve of ≤ 100
//! nodes must answer or refuse within a second, for every excluded distance
//! a from 1e-9·L to L and every tolerance from 1e-3 to 1e-8. Curves: the
//! 41-node helix of radius 1, pitch 3, length 20 (the case that ran for
//! 96 s before refusing), a 100-node helix of length 50 and a 100-node
//! ring; κ = 1, 0 (Coulomb) and 10. Each call is timed three times (median:
//! the machine is shared); the table gives the status, the δ and order
//! chosen, the estimate and the time, then the slowest call.

use rodkit::capi::curve::{rodkit_curve_electrostatic_energy_within, ElectrostaticsSpec, EnergyWithin};
use std::f64::consts::PI;
use std::time::Instant;

struct Nodes {
    name: &'static str,
    s: Vec<f64>,
    xyz: Vec<f64>,
    tan: Vec<f64>,
    closed: i32,
}

fn helix(name: &'static str, l: f64, n: usize) -> Nodes {
    let (rho, c) = (1.0f64, 3.0 / (2.0 * PI));
    let w = (rho * rho + c * c).sqrt();
    let s: Vec<f64> = (0..n).map(|k| l * k as f64 / (n - 1) as f64).collect();
    let xyz = s.iter().flat_map(|&v| [rho * (v / w).cos(), rho * (v / w).sin(), c * v / w]).collect();
    let tan = s.iter().flat_map(|&v| [-rho * (v / w).sin() / w, rho * (v / w).cos() / w, c / w]).collect();
    Nodes { name, s, xyz, tan, closed: 0 }
}

fn ring(n: usize) -> Nodes {
    let s: Vec<f64> = (0..n).map(|k| 2.0 * PI * k as f64 / (n - 1) as f64).collect();
    let xyz = s.iter().flat_map(|&v| [v.cos(), v.sin(), 0.0]).collect();
    let tan = s.iter().flat_map(|&v| [-v.sin(), v.cos(), 0.0]).collect();
    Nodes { name: "ring, 100 nodes", s, xyz, tan, closed: 1 }
}

fn main() {
    let curves = [helix("helix L 20, 41 nodes", 20.0, 41), helix("helix L 50, 100 nodes", 50.0, 100), ring(100)];
    let mut slowest = (0.0f64, String::new());
    let mut statuses = std::collections::BTreeMap::new();
    println!("| curve | κ | a/L | tol | status | δ | order | estimate | time (ms) |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for c in &curves {
        let l = *c.s.last().unwrap();
        for kappa in [1.0, 0.0, 10.0] {
            for rel in [1e-9, 1e-7, 1e-5, 1e-3, 1e-1, 1.0] {
                for tol in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
                    let spec = ElectrostaticsSpec { line_charge: 1.0, kappa, a: rel * l, near_width: 0.0, order: 0 };
                    let mut out = EnergyWithin::default();
                    let mut times = Vec::new();
                    let mut st = 0;
                    for _ in 0..3 {
                        let t0 = Instant::now();
                        st = unsafe {
                            rodkit_curve_electrostatic_energy_within(
                                c.s.as_ptr(),
                                c.xyz.as_ptr(),
                                3,
                                c.tan.as_ptr(),
                                3,
                                c.s.len() as i64,
                                c.closed,
                                &spec,
                                tol,
                                &mut out,
                            )
                        };
                        times.push(t0.elapsed().as_secs_f64() * 1e3);
                    }
                    times.sort_by(f64::total_cmp);
                    let ms = times[1];
                    *statuses.entry(st).or_insert(0) += 1;
                    let label = format!("{}, κ {kappa}, a {rel:e} L, tol {tol:e}", c.name);
                    if ms > slowest.0 {
                        slowest = (ms, label);
                    }
                    println!(
                        "| {} | {kappa} | {rel:.0e} | {tol:.0e} | {st} | {:.3e} | {} | {:.2e} | {ms:.1} |",
                        c.name, out.near_width, out.order, out.estimate
                    );
                }
            }
        }
    }
    println!("\nstatuses (code: calls): {statuses:?}");
    println!("slowest call: {:.1} ms ({})", slowest.0, slowest.1);
}

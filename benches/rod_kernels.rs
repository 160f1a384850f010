//! The element kernels compiled against the tape interpreter (`cargo bench
//! --bench rod_kernels`): one evaluation of a whole rod system — residual,
//! Jacobian, a Taylor series to order P (each order's known part and its
//! commit, as the ANM makes them) and its tangent series — by the compiled
//! kernels (`Rod::system()`) and by the tapes (`.interpreted()`), medians
//! of 201 repetitions, for the cantilevers of benches/rod_frontier.rs and a
//! charged rod's stiffened elements (each element its own law).

use rodkit::continuation::system::AssembledSystem;
use rodkit::continuation::{Problem, SeriesProblem};
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use std::time::Instant;

const REPS: usize = 201;
const ORDER: usize = 20;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Median µs of `f` over REPS calls.
fn time(mut f: impl FnMut()) -> f64 {
    f();
    median(
        (0..REPS)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64() * 1e6
            })
            .collect(),
    )
}

/// (residual, Jacobian, series, tangent series) µs.
fn measure(sys: &mut AssembledSystem) -> [f64; 4] {
    let n = sys.dim();
    let x: Vec<f64> = (0..n).map(|i| ((i * 37 % 101) as f64 / 101.0 - 0.5) * 0.8).collect();
    let (mut r, mut jx, mut jl) = (vec![0.0; n], vec![0.0; sys.pattern().nnz()], vec![0.0; n]);
    let xp: Vec<f64> = x.iter().map(|v| 0.1 * v).collect();
    let residual = time(|| sys.residual(&x, 0.5, &mut r));
    let jacobian = time(|| sys.jacobian(&x, 0.5, &mut jx, &mut jl));
    let series = time(|| {
        sys.series_begin(&x, 0.5, ORDER);
        for p in 1..=ORDER {
            sys.series_order(p, &vec![0.0; n], 0.0, &mut r);
            sys.series_order(p, &xp, 0.01, &mut r);
        }
    });
    let tangent = time(|| {
        for p in 0..=ORDER {
            sys.series_tangent_order(p, &xp, 0.01, &mut r);
        }
    });
    [residual, jacobian, series, tangent]
}

fn main() {
    println!("series to order {ORDER}; medians of {REPS}; µs per evaluation of the whole system");
    println!(
        "{:<28} {:>8} {:>22} {:>22} {:>22} {:>22}",
        "system", "unknowns", "residual tape/comp", "Jacobian tape/comp", "series tape/comp", "tangent tape/comp"
    );
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let cases: Vec<(String, AssembledSystem, AssembledSystem)> = [
        ("follower Gauss(4)×4", Load::follower([1.0, 0.0, 0.0]), 4, 4),
        ("follower Gauss(4)×8", Load::follower([1.0, 0.0, 0.0]), 4, 8),
        ("dead Gauss(4)×6", Load::dead([1.0, 0.0, 0.0]), 4, 6),
        ("dead Gauss(2)×24", Load::dead([1.0, 0.0, 0.0]), 2, 24),
    ]
    .into_iter()
    .map(|(name, load, s, n)| {
        let loads = Loads { tip_force: Some(load), ..Default::default() };
        let rod = Rod::new(law.clone(), 1.0, loads, Supports::Cantilever, Scheme::Gauss(s), n).unwrap();
        (name.to_string(), rod.system().unwrap(), rod.system().unwrap().interpreted())
    })
    .collect();
    for (name, mut compiled, mut tape) in cases {
        let n = compiled.dim();
        let (c, t) = (measure(&mut compiled), measure(&mut tape));
        let cell = |k: usize| format!("{:.1}/{:.1} = {:.2}×", t[k], c[k], t[k] / c[k]);
        println!("{name:<28} {n:>8} {:>22} {:>22} {:>22} {:>22}", cell(0), cell(1), cell(2), cell(3));
    }
}

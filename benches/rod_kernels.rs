//! The element kernels compiled against the tape interpreter (`cargo bench
//! --bench rod_kernels`).
//!
//! 1. One evaluation of a whole rod system — residual, Jacobian, a Taylor
//!    series to order P (each order's known part and its commit, as the
//!    ANM makes them) and its tangent series — as `Rod::system()` makes
//!    it (compiled kernels for values and Jacobians, the shared tape for
//!    series) and by the tapes alone (`.interpreted()`), for the
//!    cantilevers of benches/rod_frontier.rs.
//! 2. One batch of four elements: the compiled series (`LaneSeries`)
//!    against the batched tape's — why the system keeps the tape for
//!    series where the lanes share one.
//!
//! Medians of 201 calls, taken in 5 interleaved rounds (the median of
//! the rounds' medians: the machine is shared).

use rodkit::continuation::system::{AssembledSystem, Block};
use rodkit::continuation::{Problem, SeriesProblem};
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use rodkit::taylor::batch::{BatchTaylorWork, Lanes, LANES};
use std::time::Instant;

const REPS: usize = 201;
const ROUNDS: usize = 5;
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
    let zero = vec![0.0; n];
    let xp: Vec<f64> = x.iter().map(|v| 0.1 * v).collect();
    let residual = time(|| sys.residual(&x, 0.5, &mut r));
    let jacobian = time(|| sys.jacobian(&x, 0.5, &mut jx, &mut jl));
    let series = time(|| {
        sys.series_begin(&x, 0.5, ORDER);
        for p in 1..=ORDER {
            sys.series_order(p, &zero, 0.0, &mut r);
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

/// The median over ROUNDS of each figure, `a` and `b` measured in turn.
fn interleaved<const K: usize>(
    mut a: impl FnMut() -> [f64; K],
    mut b: impl FnMut() -> [f64; K],
) -> ([f64; K], [f64; K]) {
    let (mut ra, mut rb) = (vec![], vec![]);
    for _ in 0..ROUNDS {
        ra.push(a());
        rb.push(b());
    }
    let med = |r: &[[f64; K]]| std::array::from_fn(|k| median(r.iter().map(|v| v[k]).collect()));
    (med(&ra), med(&rb))
}

/// (series, tangent series) µs of one element batch: the compiled kernel
/// or the batched tape.
fn batch_series(block: &Block, compiled: bool) -> [f64; 2] {
    let (nin, nout) = (block.tape.inputs(), block.tape.outputs());
    let x: Vec<Lanes> =
        (0..nin).map(|i| std::array::from_fn(|l| ((i * 7 + l * 13) % 17) as f64 / 17.0 - 0.5)).collect();
    let xp: Vec<Lanes> = x.iter().map(|v| v.map(|c| 0.1 * c)).collect();
    let zero = vec![[0.0; LANES]; nin];
    let mut out = vec![[0.0; LANES]; nout];
    if compiled {
        let kernel = block.kernel.as_ref().expect("a compiled element");
        let mut b = kernel.batch(&[kernel.as_ref(); LANES]);
        let series = time(|| {
            b.series_begin(&x, ORDER);
            for p in 1..=ORDER {
                b.series_order(p, &zero, &mut out);
                b.series_order(p, &xp, &mut out);
            }
        });
        let tangent = time(|| (0..=ORDER).for_each(|p| b.series_tangent_order(p, &xp, &mut out)));
        [series, tangent]
    } else {
        let mut w = BatchTaylorWork::default();
        let tape = &block.tape;
        let series = time(|| {
            w.begin(tape, &x, ORDER);
            for p in 1..=ORDER {
                w.order(tape, p, &zero, &mut out);
                w.order(tape, p, &xp, &mut out);
            }
        });
        let tangent = time(|| (0..=ORDER).for_each(|p| w.tangent_order(tape, p, &xp, &mut out)));
        [series, tangent]
    }
}

fn main() {
    println!("1. One evaluation of the whole system, µs (series to order {ORDER}); medians of {REPS} calls, median of {ROUNDS} interleaved rounds");
    println!(
        "{:<24} {:>8} {:>24} {:>24} {:>24} {:>24}",
        "system", "unknowns", "residual tape/comp", "Jacobian tape/comp", "series tape/system", "tangent tape/system"
    );
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let cases: Vec<(String, Rod)> = [
        ("follower Gauss(4)×4", Load::follower([1.0, 0.0, 0.0]), 4, 4),
        ("follower Gauss(4)×8", Load::follower([1.0, 0.0, 0.0]), 4, 8),
        ("dead Gauss(4)×6", Load::dead([1.0, 0.0, 0.0]), 4, 6),
        ("dead Gauss(2)×24", Load::dead([1.0, 0.0, 0.0]), 2, 24),
    ]
    .into_iter()
    .map(|(name, load, s, n)| {
        let loads = Loads { tip_force: Some(load), ..Default::default() };
        (name.to_string(), Rod::new(law.clone(), 1.0, loads, Supports::Cantilever, Scheme::Gauss(s), n).unwrap())
    })
    .collect();
    for (name, rod) in &cases {
        let (mut compiled, mut tape) = (rod.system().unwrap(), rod.system().unwrap().interpreted());
        let n = compiled.dim();
        let (c, t) = interleaved(|| measure(&mut compiled), || measure(&mut tape));
        let cell = |k: usize| format!("{:.1}/{:.1} = {:.2}×", t[k], c[k], t[k] / c[k]);
        println!("{name:<24} {n:>8} {:>24} {:>24} {:>24} {:>24}", cell(0), cell(1), cell(2), cell(3));
    }
    println!(
        "\n2. One batch of four elements, µs (series to order {ORDER}): the batched tape against the compiled series"
    );
    println!("{:<24} {:>8} {:>30} {:>30}", "element", "tape ops", "series tape/compiled", "tangent tape/compiled");
    for (name, rod) in cases.iter().filter(|(name, _)| name.contains("×4") || name.contains("×24")) {
        let sys = rod.system().unwrap();
        let block = &sys.blocks()[0];
        let (t, c) = interleaved(|| batch_series(block, false), || batch_series(block, true));
        let cell = |k: usize| format!("{:.1}/{:.1} = {:.2}×", t[k], c[k], t[k] / c[k]);
        println!("{name:<24} {:>8} {:>30} {:>30}", block.tape.len(), cell(0), cell(1));
    }
}

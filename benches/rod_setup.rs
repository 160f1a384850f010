//! What a rod costs before its first solve (`cargo bench --bench
//! rod_setup`): `Rod::new` and `Rod::system()` (the element tapes, the
//! pattern and the scatter maps), then the bordered tangent's set-up
//! (`Bordered::with_private_blocks`: the bordered pattern, the condensed
//! LU's block and kept structure, the kept system's symbolic analysis) —
//! what a first call pays before any factorisation. Three ways, medians
//! of fresh rods (a follower cantilever, as benches/rod_frontier.rs):
//! - first on a thread: nothing kept (each rod built on a new thread: its
//!   element tapes recorded, its structures built);
//! - structures built: the thread keeps the element tapes, the kept
//!   structures are forgotten before each rod (a sweep over meshes);
//! - structures kept: a rod of a shape the thread has built before (a
//!   sweep over loads or laws on one mesh).
//!
//! The target is 0.2 ms for ≤ 1000 unknowns.

use rodkit::continuation::system::forget_kept_structures;
use rodkit::continuation::tangent::Bordered;
use rodkit::continuation::Problem;
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use std::time::Instant;

/// One rod's set-up: (rod + system, tangent) in ms.
fn set_up(stages: usize, n: usize) -> (f64, f64) {
    let t = Instant::now();
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let loads = Loads { tip_force: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(stages), n).unwrap();
    let sys = rod.system().unwrap();
    let t2 = t.elapsed();
    let t = Instant::now();
    let b = Bordered::with_private_blocks(sys.pattern(), sys.trailing(), &sys.private_blocks()).unwrap();
    let t3 = t.elapsed();
    std::hint::black_box((&sys, &b));
    (t2.as_secs_f64() * 1e3, t3.as_secs_f64() * 1e3)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    println!(
        "{:<12} {:>8} {:>16} {:>29} {:>16}",
        "rod", "unknowns", "first on thread", "structures built (sys + tan)", "structures kept"
    );
    for (stages, n) in [(4usize, 4usize), (4, 8), (2, 24), (4, 12), (4, 16)] {
        let first: Vec<f64> = (0..21)
            .map(|_| {
                let (a, b) = std::thread::spawn(move || set_up(stages, n)).join().unwrap();
                a + b
            })
            .collect();
        let (mut sys, mut tan) = (vec![], vec![]);
        for _ in 0..41 {
            forget_kept_structures();
            let (a, b) = set_up(stages, n);
            sys.push(a);
            tan.push(b);
        }
        let built: Vec<f64> = sys.iter().zip(&tan).map(|(a, b)| a + b).collect();
        set_up(stages, n);
        let kept: Vec<f64> = (0..41)
            .map(|_| {
                let (a, b) = set_up(stages, n);
                a + b
            })
            .collect();
        println!(
            "{:<12} {:>8} {:>13.3} ms {:>8.3} ms ({:.3} + {:.3}) {:>13.3} ms",
            format!("Gauss({stages})×{n}"),
            13 * (n * (stages + 1) + 1),
            median(first),
            median(built),
            median(sys),
            median(tan),
            median(kept)
        );
    }
}

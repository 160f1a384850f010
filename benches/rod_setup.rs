//! What a rod costs before its first solve (`cargo bench --bench
//! rod_setup`): `Rod::new` and `Rod::system()` (the element tapes, the
//! pattern and the scatter maps), then the bordered tangent's set-up
//! (`Bordered::with_private_blocks`: the bordered pattern, the condensed
//! LU's block and kept structure, the kept system's symbolic analysis) —
//! what a first call pays before any factorisation. Minima and medians of
//! 41 fresh rods (a follower cantilever, as benches/rod_frontier.rs);
//! the target is 0.2 ms for ≤ 1000 unknowns.

use rodkit::continuation::tangent::Bordered;
use rodkit::continuation::Problem;
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use std::time::Instant;
fn main() {
    println!(
        "{:<14} {:>9} {:>24} {:>24} {:>24}",
        "rod", "unknowns", "rod + system (min/med)", "tangent set-up (min/med)", "total (min/med)"
    );
    for (stages, n) in [(4usize, 4usize), (4, 8), (2, 24), (4, 12), (4, 16)] {
        let (mut t_sys, mut t_sym) = (vec![], vec![]);
        for _ in 0..41 {
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
            t_sys.push(t2.as_secs_f64() * 1e3);
            t_sym.push(t3.as_secs_f64() * 1e3);
        }
        let total: Vec<f64> = t_sys.iter().zip(&t_sym).map(|(a, b)| a + b).collect();
        let stat = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            format!("{:.3} / {:.3} ms", v[0], v[v.len() / 2])
        };
        println!(
            "{:<14} {:>9} {:>24} {:>24} {:>24}",
            format!("Gauss({stages})×{n}"),
            13 * (n * (stages + 1) + 1),
            stat(t_sys),
            stat(t_sym),
            stat(total)
        );
    }
}

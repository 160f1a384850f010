//! The thermal two-phase model's speed (`cargo bench --bench tweezers`):
//! a scene's set-up (the superhelix's tables in torque, the
//! Poisson–Boltzmann charge), one default curve (200 points from 0 to twice
//! the buckling turns) with its summary, for 1–20 kbp; and a map of
//! 3 forces × 4 salts × 3 lengths. Medians of several runs, each from a
//! fresh model (the machine is shared).

#[path = "support/timing.rs"]
mod timing;

use rodkit::tweezers::{Model, TweezersScene};
use std::time::Instant;
use timing::{median, ms};

fn main() {
    let runs = 5;
    println!("one curve: 1 pN, 0.1 M, kT 4.11 pN nm, 200 points to 2 x buckling; median of {runs}");
    println!(
        "{:>6} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9} {:>9}",
        "kbp", "setup ms", "curve ms", "summ. ms", "total ms", "n_b", "tau_p", "slope"
    );
    for kbp in [1.0, 3.0, 10.0, 20.0] {
        let scene = TweezersScene { base_pairs: kbp * 1000.0, ..Default::default() };
        let (mut t_setup, mut t_curve, mut t_sum, mut t_all) = (vec![], vec![], vec![], vec![]);
        let mut last = None;
        for _ in 0..runs {
            let t0 = Instant::now();
            let m = Model::new(&scene).unwrap();
            let t1 = Instant::now();
            let turns = m.default_turns(200).unwrap();
            let pts = m.curve(&turns).unwrap();
            let t2 = Instant::now();
            let s = m.summarise(&pts).unwrap();
            let t3 = Instant::now();
            t_setup.push(t1 - t0);
            t_curve.push(t2 - t1);
            t_sum.push(t3 - t2);
            t_all.push(t3 - t0);
            last = Some(s);
        }
        let s = last.unwrap();
        println!(
            "{kbp:>6} {:>10.2} {:>10.2} {:>10.2} {:>10.2} {:>9.3} {:>9.3} {:>9.2}",
            ms(median(t_setup)),
            ms(median(t_curve)),
            ms(median(t_sum)),
            ms(median(t_all)),
            s.buckling_turns,
            s.plateau_torque,
            s.slope
        );
    }
    let forces = [0.5, 1.0, 2.0];
    let salts = [0.01, 0.05, 0.1, 0.2];
    let lengths = [1.0, 3.0, 10.0];
    let mut times = vec![];
    let mut failed = 0;
    for _ in 0..3 {
        let t0 = Instant::now();
        failed = 0;
        for &f in &forces {
            for &c in &salts {
                for &l in &lengths {
                    let scene = TweezersScene { force: f, salt: c, base_pairs: l * 1000.0, ..Default::default() };
                    let ok = Model::new(&scene).and_then(|m| {
                        let t = m.default_turns(200)?;
                        let p = m.curve(&t)?;
                        m.summarise(&p)
                    });
                    if ok.is_err() {
                        failed += 1;
                    }
                }
            }
        }
        times.push(t0.elapsed());
    }
    println!(
        "map: {} forces x {} salts x {} lengths (200 points each, with summaries): {:.1} ms (median of 3), {failed} curves refused",
        forces.len(),
        salts.len(),
        lengths.len(),
        ms(median(times))
    );
}

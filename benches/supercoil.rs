//! The DNA supercoiling curves (`cargo bench --bench supercoil`): the scene
//! of issue 5 (1 kbp, 1 pN, ν = 1/l_B, a = 1 nm) at 0.1 M and 0.01 M salt,
//! continued in the end rotation from the straight rod through its first
//! buckling point along the buckled branch (100 elements of Gauss(2),
//! cutoff 1e-4; steps from RODKIT_SUPERCOIL_STEPS, default 120; salts
//! from RODKIT_SUPERCOIL_SALTS, e.g. "0.1", default both). Writes
//! target/bench/supercoil/{path_<salt>M.csv, extension.svg, torque.svg,
//! twist_writhe.svg, report.txt}: the curves users compare with
//! magnetic-tweezers experiments (extension and torque vs turns) and the
//! twist/writhe partition, with the buckling point, the work and the time.

#[path = "support/plot.rs"]
mod plot;
use plot::line_plot;
use plotters::prelude::{RGBColor, BLUE, RED};
use rodkit::charged::dna::{run_scene, DnaScene, SupercoilSettings};
use std::fmt::Write as _;
use std::path::Path;

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench/supercoil");
    std::fs::create_dir_all(&dir).unwrap();
    let steps: usize = std::env::var("RODKIT_SUPERCOIL_STEPS").ok().and_then(|v| v.parse().ok()).unwrap_or(120);
    let mut report = String::new();
    let (mut ext, mut tor, mut tw) = (vec![], vec![], vec![]);
    let salts: Vec<f64> = std::env::var("RODKIT_SUPERCOIL_SALTS")
        .ok()
        .map_or(vec![0.1, 0.01], |v| v.split(',').filter_map(|s| s.trim().parse().ok()).collect());
    for (salt, color, light) in [(0.1, BLUE, RGBColor(120, 160, 255)), (0.01, RED, RGBColor(255, 140, 120))] {
        if !salts.contains(&salt) {
            continue;
        }
        let scene = DnaScene { salt, ..Default::default() };
        let settings = SupercoilSettings { elements: 100, max_steps: steps, ..Default::default() };
        let r = run_scene(&scene, &settings).unwrap();
        let two_pi = 2.0 * std::f64::consts::PI;
        let steps_done: usize = r.straight.counts.steps + r.buckled.as_ref().map_or(0, |b| b.counts.steps);
        let facts: usize = r.straight.counts.factorisations + r.buckled.as_ref().map_or(0, |b| b.counts.factorisations);
        let worst_lk = r
            .points
            .iter()
            .map(|p| (p.observables.twist + p.observables.writhe - p.observables.turns).abs())
            .fold(0.0, f64::max);
        let last = r.points.last().unwrap().observables;
        let _ = writeln!(report, "{salt} M: Debye length {:.3} nm, λ² = {:.4} pN, cutoff {:?}; buckling at {:.4} turns, torque {:.3} pN nm; {} points, {} steps, {} factorisations, {:.1} s; last point {:.4} turns, z {:.2} nm, M {:.3} pN nm, Wr {:.4}; crossing {:?}; worst |Tw + Wr − turns| {:.1e}",
            1.0 / scene.kappa(), r.charge.line_charge.powi(2), r.charge.cutoff(r.rod.length), r.buckling.map_or(f64::NAN, |b| b.0 / two_pi), r.buckling.map_or(f64::NAN, |b| b.1),
            r.points.len(), steps_done, facts, r.seconds, last.turns, last.extension, last.torque, last.writhe, r.buckled.as_ref().and_then(|b| b.contact), worst_lk);
        let mut csv = String::from("turns,extension_nm,torque_pN_nm,tension_pN,twist,writhe,branch\n");
        for p in &r.points {
            let o = p.observables;
            let _ = writeln!(
                csv,
                "{},{},{},{},{},{},{}",
                o.turns, o.extension, o.torque, o.tension, o.twist, o.writhe, p.branch
            );
        }
        std::fs::write(dir.join(format!("path_{salt}M.csv")), csv).unwrap();
        ext.push((
            format!("{salt} M"),
            r.points.iter().map(|p| (p.observables.turns, p.observables.extension)).collect(),
            color,
        ));
        tor.push((
            format!("{salt} M"),
            r.points.iter().map(|p| (p.observables.turns, p.observables.torque)).collect(),
            color,
        ));
        tw.push((
            format!("Tw, {salt} M"),
            r.points.iter().map(|p| (p.observables.turns, p.observables.twist)).collect(),
            color,
        ));
        tw.push((
            format!("Wr, {salt} M"),
            r.points.iter().map(|p| (p.observables.turns, p.observables.writhe)).collect(),
            light,
        ));
    }
    line_plot(&dir.join("extension.svg"), "1 kbp DNA at 1 pN: extension vs turns", "turns", "extension (nm)", &ext)
        .unwrap();
    line_plot(&dir.join("torque.svg"), "1 kbp DNA at 1 pN: torque vs turns", "turns", "torque (pN nm)", &tor).unwrap();
    line_plot(&dir.join("twist_writhe.svg"), "twist and writhe vs turns", "turns", "turns", &tw).unwrap();
    print!("{report}");
    std::fs::write(dir.join("report.txt"), report).unwrap();
}

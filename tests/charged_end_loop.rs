//! The plectoneme nucleation energy of the full charged rod
//! (src/charged/end_loop.rs): E_nuc = G − 2πτn − Ψ_s(τ) on buckled points,
//! checked against the Kirchhoff homoclinic loop of the uncharged rod, the
//! straight charged rod's closed-form grand energy, and the work theorem
//! along a charged plectoneme; the table's parser and writer.
//!
//! Run: `cargo test --release --test charged_end_loop -- --nocapture`.
//! The ignored `regenerate_table` computes table rows (minutes each).

use std::f64::consts::{PI, TAU};

use rodkit::charged::coexistence::path_energies;
use rodkit::charged::dna::{run_scene, DnaScene, SupercoilSettings};
use rodkit::charged::end_loop::{
    end_loop_run, entry_of_run, entry_of_run_by, nucleation_energies, nucleation_points, parse_table, plateau_points,
    plateau_points_by, table_scene, write_table, write_table_with_notes, PlateauRule, StraightGrand,
};
use rodkit::charged::summary::strand_approach;

/// Computes table rows: `RODKIT_END_LOOP_GRID` = `F:S[:bp[:turns[:steps]]]`
/// comma-separated (default: the table's grid by [`table_scene`]), rows
/// appended to `RODKIT_END_LOOP_OUT` (default /tmp/end_loops_rows.csv) and
/// every buckled point's E_nuc to `RODKIT_END_LOOP_DUMP`/points_F_S_bp.csv
/// when set. One run at a time.
#[test]
#[ignore]
fn regenerate_table() {
    let grid = std::env::var("RODKIT_END_LOOP_GRID").unwrap_or_else(|_| {
        let mut g = Vec::new();
        for f in ["1", "2", "4", "0.5"] {
            for s in ["0.1", "0.05", "0.15", "0.01"] {
                g.push(format!("{f}:{s}"));
            }
        }
        g.join(",")
    });
    let out = std::env::var("RODKIT_END_LOOP_OUT").unwrap_or_else(|_| "/tmp/end_loops_rows.csv".into());
    let dump = std::env::var("RODKIT_END_LOOP_DUMP").ok();
    let (mut entries, mut notes) = (Vec::new(), Vec::new());
    for spec in grid.split(',') {
        let f: Vec<&str> = spec.split(':').collect();
        let (force, salt): (f64, f64) = (f[0].parse().unwrap(), f[1].parse().unwrap());
        let (mut scene, mut settings) = table_scene(force, salt);
        if let Some(bp) = f.get(2) {
            scene.base_pairs = bp.parse().unwrap();
        }
        if let Some(t) = f.get(3) {
            settings.max_turns = t.parse().unwrap();
        }
        if let Some(s) = f.get(4) {
            settings.max_steps = s.parse().unwrap();
        }
        let clock = std::time::Instant::now();
        let full = std::env::var("RODKIT_END_LOOP_FULL").is_ok();
        let run = if full { run_scene(&scene, &settings) } else { end_loop_run(&scene, &settings) };
        let run = match run {
            Ok(run) => run,
            Err(e) => {
                notes.push(format!("left out F = {force} pN, S = {salt} M, {} bp: run failed: {e}", scene.base_pairs));
                println!("{}", notes.last().unwrap());
                continue;
            }
        };
        if let Some(e) = run.failure() {
            println!("F = {force}, S = {salt}: the run failed partway: {e}");
        }
        if let Some(dir) = &dump {
            let nuc = nucleation_points(&run).unwrap();
            let used = plateau_points(&run, &nuc);
            let loose = plateau_points_by(&run, &nuc, &PlateauRule { min_writhe: 1.5, ..Default::default() });
            let profile = run.rod.profile_offsets();
            let s: Vec<f64> = profile.iter().map(|p| p.0).collect();
            let radius = |k: usize| {
                let x = &run.states[k];
                let r: Vec<[f64; 3]> = profile.iter().map(|&(_, o)| [x[o], x[o + 1], x[o + 2]]).collect();
                strand_approach(&r, &s).map_or(f64::NAN, |(d, _, _)| 0.5 * d)
            };
            let mut csv =
                String::from("index,turns,torque,extension,writhe,energy,e_nuc,kind,plateau,plateau_wr1.5,radius\n");
            for (k, p) in nuc.iter().enumerate() {
                let r = if loose.contains(&k) { radius(p.index) } else { f64::NAN };
                csv.push_str(&format!(
                    "{},{},{},{},{},{},{},{:?},{},{},{}\n",
                    p.index,
                    p.turns,
                    p.torque,
                    p.extension,
                    p.writhe,
                    p.energy,
                    p.e_nuc,
                    p.kind,
                    used.contains(&k) as u8,
                    loose.contains(&k) as u8,
                    r
                ));
            }
            let path = format!("{dir}/points_F{force}_S{salt}_{}.csv", scene.base_pairs);
            std::fs::write(&path, csv).unwrap();
            if let (Some(&a), Some(&b)) = (used.first(), used.last()) {
                println!(
                    "plateau points: {} from {:.4} to {:.4} turns (Wr {:.3}–{:.3}, z {:.2}–{:.2} nm); run {} points, \
                     last {:.4} turns",
                    used.len(),
                    nuc[a].turns,
                    nuc[b].turns,
                    nuc[a].writhe,
                    nuc[b].writhe,
                    nuc[a].extension,
                    nuc[b].extension,
                    run.points.len(),
                    run.points.last().unwrap().observables.turns
                );
            }
        }
        match entry_of_run(&run) {
            Ok(mut e) => {
                e.seconds = clock.elapsed().as_secs_f64();
                let row = write_table(std::slice::from_ref(&e));
                let row = row.lines().last().unwrap().to_string();
                println!("{row}   (run stop {:?}, {} points)", run.stop, run.points.len());
                let mut old = std::fs::read_to_string(&out).unwrap_or_default();
                old.push_str(&row);
                old.push('\n');
                std::fs::write(&out, old).unwrap();
                entries.push(e);
            }
            Err(e) => {
                notes.push(format!("left out F = {force} pN, S = {salt} M, {} bp: {e}", scene.base_pairs));
                println!("{}", notes.last().unwrap());
            }
        }
    }
    println!("{}", write_table_with_notes(&entries, &notes));
}

/// K_b = A k_BT (pN nm²) and C = P k_BT of a scene.
fn stiffness(scene: &DnaScene) -> (f64, f64) {
    (scene.bending_persistence * scene.kt(), scene.twist_persistence * scene.kt())
}

/// The uncharged rod (ν = 0, no hard core): before its strands meet, the
/// buckled branch of a long clamped rod under tension F is the localized
/// loop, whose grand energy at end torque τ relative to the straight rod at
/// the same τ is the Kirchhoff homoclinic's (G. H. M. van der Heijden &
/// J. M. T. Thompson, Nonlinear Dyn. 21, 71 (2000); J. M. T. Thompson &
/// A. R. Champneys, Proc. R. Soc. A 452, 117 (1996)):
///
///   ΔG(τ) = 8√(K_bF)√(1 − m²) − 4τ arccos m,   m = τ / (2√(K_bF)),
///
/// with link Lk = (2/π) arccos m (dΔG/dτ = −2π Lk) and extension deficit
/// 4√(K_b/F)√(1 − m²). The finite rod (300 bp at 8 pN: L = 20 loop
/// lengths √(K_b/F) = 5.1 nm) differs by its tails' share, of order
/// e^{−(L/2)√(F/K_b)√(1−m²)} ≤ 1.3e-2 at m ≤ 0.9 in the link and the
/// extension and its square in the energy (stationary: first-order changes
/// of the shape leave it unchanged); the mesh (2 nm elements against the
/// 5.1 nm loop) by O(h⁴). Measured (2026-11-29): 6.5e-5 in E_nuc (of
/// 8√(K_bF)), 8.8e-4 in Lk, 6.3e-3 in Δz (of √(K_b/F)); on 450 bp (L/ℓ =
/// 30, 28× slower) 2.8e-5, 2.7e-5 and 2.7e-4, the finite-size share.
#[test]
fn uncharged_loop_is_the_kirchhoff_homoclinic() {
    let scene = DnaScene { base_pairs: 300, tension: 8.0, charge_per_length: 0.0, ..Default::default() };
    let settings = SupercoilSettings { hard_core_auto: false, max_turns: 12.0, max_steps: 200, ..Default::default() };
    let clock = std::time::Instant::now();
    let run = run_scene(&scene, &settings).unwrap();
    let energies = path_energies(&run).unwrap();
    let nuc = nucleation_energies(&run, &energies).unwrap();
    let (kb, c) = stiffness(&scene);
    let (f, l) = (scene.tension, scene.length());
    let scale = 8.0 * (kb * f).sqrt();
    let mut checked = 0;
    let (mut worst_g, mut worst_lk, mut worst_z) = (0.0_f64, 0.0_f64, 0.0_f64);
    for p in &nuc {
        let m = p.torque / (2.0 * (kb * f).sqrt());
        if !(0.3..=0.9).contains(&m) {
            continue;
        }
        let dg = scale * (1.0 - m * m).sqrt() - 4.0 * p.torque * m.acos();
        let lk = p.turns - p.torque * l / (TAU * c);
        let deficit = l - p.extension;
        worst_g = worst_g.max((p.e_nuc - dg).abs() / scale);
        worst_lk = worst_lk.max((lk - 2.0 / PI * m.acos()).abs());
        worst_z = worst_z.max((deficit - 4.0 * (kb / f).sqrt() * (1.0 - m * m).sqrt()).abs() / (kb / f).sqrt());
        checked += 1;
    }
    println!(
        "uncharged loop: {} points, {checked} with 0.3 ≤ m ≤ 0.9 in {:.1} s; worst |E_nuc − ΔG| / 8√(K_bF) = {worst_g:.2e}, \
         |Lk − (2/π) arccos m| = {worst_lk:.2e}, |Δz − 4√(K_b/F)√(1−m²)| / √(K_b/F) = {worst_z:.2e}",
        run.points.len(),
        clock.elapsed().as_secs_f64()
    );
    assert!(checked >= 5, "{checked} buckled points with 0.3 ≤ m ≤ 0.9");
    // The loop alone (its writhe 0.89 at most, up to the strand crossing) has
    // no plectonemic plateau: the entry is refused, with the reason.
    let refused = entry_of_run(&run).unwrap_err();
    println!("no plateau: {refused}");
    assert_eq!(refused.status, rodkit::Status::ErrNotConverged);
    assert!(worst_g < 2e-4, "E_nuc vs the homoclinic: {worst_g:.2e} of 8√(K_bF)");
    assert!(worst_lk < 2e-3, "the loop's link: {worst_lk:.2e}");
    assert!(worst_z < 1.5e-2, "the loop's extension deficit: {worst_z:.2e}");
}

/// The plateau rule on the small scene: its molecule is too short for the
/// table's Wr ≥ 2.5 with tails ≥ 30 % of L.
const SMALL_RULE: PlateauRule = PlateauRule { min_writhe: 1.5, min_extension_fraction: 0.3 };

/// The small charged scene of the tests: 300 bp at 4 pN, 0.05 M, on 40
/// elements of Gauss(2), run until its tails are short.
fn small_charged_run() -> rodkit::charged::dna::SupercoilRun {
    let scene = DnaScene { base_pairs: 300, tension: 4.0, salt: 0.05, ..Default::default() };
    let settings = SupercoilSettings { elements: 40, max_turns: 8.0, max_steps: 400, ..Default::default() };
    end_loop_run(&scene, &settings).unwrap()
}

/// On the charged scene: (a) the straight branch's interpolated grand
/// energy against its closed form — a straight line carries no
/// electrostatic torque, so Ψ_s(τ) = G(0) − Lτ²/(2C) exactly (G(0) the
/// untwisted rod's energy, E_es(line) − FL) and the Hermite cubic in τ
/// adds nothing to the states' own O(h⁴) error; (b) E_nuc's change along
/// the plateau against the work theorem alone, from the torques and turns
/// of the path (no energy evaluated): E_nuc(b) − E_nuc(a) = 2π∫τ dn −
/// 2π[τn]_a^b + L(τ_b² − τ_a²)/(2C), the integral by Simpson's rule on the
/// path's points (its error bounded by its difference from the trapezoid
/// rule's), to 1e-3 of E_nuc; (c) the entry against the numbers it gave when
/// this test was written (2026-11-29, this machine: a regression check of
/// the continuation, not an independent reference).
#[test]
fn charged_scene_entry() {
    let clock = std::time::Instant::now();
    let run = small_charged_run();
    let seconds = clock.elapsed().as_secs_f64();
    let entry = entry_of_run_by(&run, &SMALL_RULE).unwrap();
    let nuc = nucleation_points(&run).unwrap();
    let used = plateau_points_by(&run, &nuc, &SMALL_RULE);
    println!(
        "charged scene: {} points in {seconds:.1} s; {}",
        run.points.len(),
        write_table(std::slice::from_ref(&entry)).lines().last().unwrap()
    );
    let scene = &run.scene;
    let (_, c) = stiffness(scene);
    let l = scene.length();

    // (a) Ψ_s against its closed form: the interpolant adds nothing to the
    // states' own discretisation error (the collocated twisted rod is
    // straight to O(h⁴): z − L ∝ n⁴, −2e-3 nm at 5 turns on 300 bp), which
    // the nodes show; and that error is below 1e-4 of Lτ²/(2C).
    let energies = path_energies(&run).unwrap();
    let straight = StraightGrand::of_run(&run, &energies).unwrap();
    let g0 = energies[0];
    assert_eq!(run.points[0].observables.turns, 0.0);
    let closed = |tau: f64| g0 - l * tau * tau / (2.0 * c);
    let (lo, hi) = straight.range();
    let nodes = run
        .points
        .iter()
        .zip(&energies)
        .filter(|(p, _)| p.branch == 0)
        .map(|(p, g)| {
            let (n, tau) = (p.observables.turns, p.observables.torque);
            (g - TAU * tau * n - closed(tau)).abs()
        })
        .fold(0.0, f64::max);
    let mut worst_psi = 0.0_f64;
    for k in 0..=400 {
        let tau = lo + (hi - lo) * k as f64 / 400.0;
        worst_psi = worst_psi.max((straight.at(tau).unwrap() - closed(tau)).abs());
    }
    println!(
        "Ψ_s: worst |Hermite − (G(0) − Lτ²/2C)| = {worst_psi:.2e} pN nm over τ ∈ [{lo:.3}, {hi:.3}] (nodes {nodes:.2e}; \
         Lτ²/2C up to {:.1})",
        l * hi * hi / (2.0 * c)
    );
    assert!(worst_psi <= 1.01 * nodes + 1e-9 * g0.abs(), "the interpolant's own error: {worst_psi:.2e} > {nodes:.2e}");
    assert!(worst_psi < 1e-4 * l * hi * hi / (2.0 * c), "Ψ_s off its closed form by {worst_psi:.2e} pN nm");

    // (b) The plateau's E_nuc against the work theorem.
    let (a, b) = (nuc[used[0]], nuc[*used.last().unwrap()]);
    let path: Vec<(f64, f64)> =
        (a.index..=b.index).map(|k| (run.points[k].observables.turns, run.points[k].observables.torque)).collect();
    let trapezoid: f64 = path.windows(2).map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0)).sum();
    // Simpson on the pairs of intervals (nonuniform), the trapezoid on a last odd one.
    let mut simpson = 0.0;
    let mut k = 0;
    while k + 2 < path.len() {
        let ((x0, y0), (x1, y1), (x2, y2)) = (path[k], path[k + 1], path[k + 2]);
        let (h0, h1) = (x1 - x0, x2 - x1);
        simpson +=
            (h0 + h1) / 6.0 * (y0 * (2.0 - h1 / h0) + y1 * (h0 + h1) * (h0 + h1) / (h0 * h1) + y2 * (2.0 - h0 / h1));
        k += 2;
    }
    if k + 1 < path.len() {
        simpson += 0.5 * (path[k].1 + path[k + 1].1) * (path[k + 1].0 - path[k].0);
    }
    let work = |integral: f64| {
        TAU * integral - TAU * (b.torque * b.turns - a.torque * a.turns)
            + l * (b.torque * b.torque - a.torque * a.torque) / (2.0 * c)
    };
    let computed = b.e_nuc - a.e_nuc;
    let bound = (work(trapezoid) - work(simpson)).abs();
    println!(
        "E_nuc from {:.4} to {:.4} turns: {computed:.5} pN nm, work theorem {:.5} (trapezoid) / {:.5} (Simpson)",
        a.turns,
        b.turns,
        work(trapezoid),
        work(simpson)
    );
    // Measured (2026-11-29): 3.8e-2 pN nm apart over the plateau, 3.1e-4 of
    // E_nuc: the energy's pair cutoff is set for 1e-4 of the electrostatic
    // energy (the forces are the cutoff's, so the torques carry its error
    // too), and the collocation is variational only to O(h⁴); the quadrature
    // is 1.6e-3 off by its Simpson estimate.
    let off = (computed - work(simpson)).abs();
    assert!(off <= 1e-3 * entry.e_nuc.abs() + 2.0 * bound, "the work theorem: {off:.3e} pN nm apart");

    // (c) The entry as recorded (2026-11-29).
    let recorded = [
        (entry.tau_plateau, 22.47685),
        (entry.e_nuc, 123.3374),
        (entry.e_nuc_min, 113.8291),
        (entry.e_nuc_max, 128.7515),
        (entry.slope, -21.0146),
        (entry.superhelix_radius, 1.15032),
    ];
    for (x, r) in recorded {
        assert!((x - r).abs() <= 1e-4 * r.abs(), "{x} against {r} recorded");
    }
    assert!(entry.points.abs_diff(63) <= 2, "{} plateau points, 63 recorded", entry.points);
    assert!(entry.e_nuc_min <= entry.e_nuc && entry.e_nuc <= entry.e_nuc_max);
    assert!(entry.tau_min <= entry.tau_plateau && entry.tau_plateau <= entry.tau_max);
}

/// The committed table (src/charged/end_loops.csv): it parses, writes back
/// to the same numbers (to the digits it is printed with), each row is the
/// scene [`table_scene`] gives for its force and salt (the regeneration
/// command's), its means lie in their ranges, and its plateau torque lies
/// below the straight rod's buckling torque 2√(K_bF) (Greenhill's bound
/// for a long rod, the charge only stiffening the straight rod:
/// src/charged/dna.rs) and above zero, with E_nuc > 0 (the plateau's
/// buckled states cost more than the straight rod at their torque, or the
/// straight rod would not be metastable there).
#[test]
fn table_parses_and_is_consistent() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/charged/end_loops.csv");
    let csv = std::fs::read_to_string(path).unwrap();
    let rows = parse_table(&csv).unwrap();
    assert!(!rows.is_empty());
    let again = parse_table(&write_table(&rows)).unwrap();
    assert_eq!(rows.len(), again.len());
    for (r, s) in rows.iter().zip(&again) {
        let pairs = [
            (r.tau_plateau, s.tau_plateau),
            (r.tau_min, s.tau_min),
            (r.tau_max, s.tau_max),
            (r.e_nuc, s.e_nuc),
            (r.e_nuc_min, s.e_nuc_min),
            (r.e_nuc_max, s.e_nuc_max),
            (r.slope, s.slope),
            (r.superhelix_radius, s.superhelix_radius),
            (r.turns, s.turns),
        ];
        for (x, y) in pairs {
            assert!((x - y).abs() <= 1e-4, "{x} written back as {y}");
        }
        assert_eq!((r.force, r.salt, r.base_pairs, r.points), (s.force, s.salt, s.base_pairs, s.points));
        let (scene, _) = table_scene(r.force, r.salt);
        assert_eq!(r.base_pairs, scene.base_pairs, "F = {}, S = {}", r.force, r.salt);
        let (kb, _) = stiffness(&scene);
        let greenhill = 2.0 * (kb * r.force).sqrt();
        assert!(r.tau_min <= r.tau_plateau && r.tau_plateau <= r.tau_max);
        assert!(r.e_nuc_min <= r.e_nuc && r.e_nuc <= r.e_nuc_max);
        assert!(
            r.tau_min > 0.0 && r.tau_max < greenhill,
            "τ {}–{} against 2√(K_bF) = {greenhill}",
            r.tau_min,
            r.tau_max
        );
        assert!(r.e_nuc_min > 0.0 && r.slope < 0.0 && r.superhelix_radius > 0.0);
    }
    // A malformed row is refused with a status, not a panic.
    let bad = format!("{}\n1,0.1,600\n", rodkit::charged::end_loop::COLUMNS);
    assert_eq!(parse_table(&bad).unwrap_err().status, rodkit::Status::ErrOutOfRange);
}

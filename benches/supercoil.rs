//! The DNA supercoiling curves (`cargo bench --bench supercoil`): the scene
//! of issue 5 (1 kbp, 1 pN, ν = 1/l_B, a = 1 nm) at 0.1 M and 0.01 M salt,
//! continued in the end rotation from the straight rod through its first
//! buckling point along the buckled branch (the library's automatic mesh,
//! 2 nm elements of Gauss(2) — 170 for 1 kbp, within ~3e-4 of a converged
//! path at 0.1 M; before 2026-11-26 100 elements a kbp, ~3e-3 —, cutoff 1e-4; steps from RODKIT_SUPERCOIL_STEPS, default 120; salts
//! from RODKIT_SUPERCOIL_SALTS, e.g. "0.1", default both; the buckled
//! branch stops past RODKIT_SUPERCOIL_TURNS turns, default 12; the Newton
//! iterations its steps aim at from RODKIT_SUPERCOIL_AIM, default 3:
//! `SupercoilSettings::corrector_aim`; the scene from RODKIT_SUPERCOIL_BP
//! (length, default 1000), RODKIT_SUPERCOIL_FORCE (pN, default the
//! scene's 1), RODKIT_SUPERCOIL_ELEMENTS and RODKIT_SUPERCOIL_STAGES
//! (default the automatic mesh; RODKIT_SUPERCOIL_BASELINE=mesh runs a
//! reference with RODKIT_SUPERCOIL_REF_ELEMENTS / _REF_STAGES, default
//! twice the elements, as the baseline: the discretisation error) and
//! RODKIT_SUPERCOIL_DISCRETE=1, the discrete base-pair charges;
//! RODKIT_SUPERCOIL_THREADS, default 1: with 2 the records' signs are
//! taken on a second thread, `Options::overlap_thread`, the same path
//! bitwise: RODKIT_SUPERCOIL_BASELINE=serial shows a distance 0). Writes
//! target/bench/supercoil (or RODKIT_SUPERCOIL_OUT)/{path_<salt>M.csv (and the baseline's,
//! path_<salt>M_baseline.csv), mu_<salt>M.csv (μ at each buckled record),
//! extension.svg, torque.svg, twist_writhe.svg, report.txt}: the curves users compare with
//! magnetic-tweezers experiments (extension and torque vs turns) and the
//! twist/writhe partition, with the buckling point, the work and the time.
//! Also the run's profile (issue 18): per branch the steps, rejections,
//! factorisations (bifurcation location's apart), pair lists, the time by
//! kind of work, the Jacobian's size and LU fill at the start, the
//! buckling point and the last point (report.txt), and the step history
//! (steps_<salt>M.csv: arc length, Newton iterations and σ_min per point).
//! Each salt is run twice in one process, with the engine up to issue 18
//! (`Engine::Newton`, every factorisation simplicial) and the default
//! (`Engine::Hermite`, Newton corrections by block elimination on a
//! supernodal LU where the Jacobian is wide): time, steps and
//! factorisations as ratios, and the largest distance of the new path from
//! the baseline's (RODKIT_SUPERCOIL_BASELINE=0 skips the baseline, =lu
//! runs the default engine with the simplicial LU as the baseline,
//! =serial the same settings on one thread, =signs the records' signs from
//! their own factorisations and no stability counts).

#[path = "support/plot.rs"]
mod plot;
use plot::line_plot;
use plotters::prelude::{RGBColor, BLUE, GREEN, MAGENTA, RED};
use rodkit::charged::dna::{run_scene, DnaScene, Engine, SupercoilRun, SupercoilSettings};
use rodkit::charged::rod::{ChargedRod, ListRule};
use rodkit::continuation::anm::AnmOptions;
use rodkit::continuation::tangent::{Bordered, Factors};
use rodkit::continuation::{Counts, Problem, Scaling};
use rodkit::linalg::band::BandLu;
use rodkit::linalg::LuKind;
use std::fmt::Write as _;
use std::path::Path;

/// The bordered tangent at a state (x with μ under a phase condition),
/// bordered as the continuation does (W·t, t its tangent there): unknowns,
/// nnz of B, half-bandwidth, entries outside the rod's own band, pairs
/// listed, L + U, the column order, the first factorisation's time (with
/// the ordering's choice: a pair-list rebuild pays it) and the steady one
/// (best of 3); and for scale the same Jacobian's rod band alone
/// ([`BandLu`], the far pairs dropped: Newton–Krylov's preconditioner).
fn lu_size(r: &SupercoilRun, phase: Option<(usize, f64)>, x: &[f64], param: f64) -> String {
    let mut p = ChargedRod::new(&r.rod, &r.charge, phase, x).unwrap();
    let n = p.dim();
    let pat = p.pattern().clone();
    let band = p.local_band();
    let (mut hb, mut far) = (0, 0);
    for j in 0..n {
        for &i in &pat.row_idx[pat.col_ptr[j]..pat.col_ptr[j + 1]] {
            let d = i.abs_diff(j);
            // Not the boundary corner blocks (a clamped rod's end conditions)
            // nor the last unknowns (c = cos φ/2, μ), which reach across.
            if (i.min(j) < band && i.max(j) + band >= n) || i.max(j) >= r.rod.unknowns() {
                continue;
            }
            hb = hb.max(d);
            far += usize::from(d > band);
        }
    }
    let scaling = Scaling::of(&p);
    let mut b = Bordered::new(&pat).unwrap();
    let mut counts = Counts::default();
    let e_lambda = vec![0.0; n];
    b.factorise_at(&mut p, x, param, (&e_lambda, 1.0), &scaling, &mut counts, Factors::ForSolves).unwrap();
    let (tx, tl) = b.tangent(&scaling, &mut counts).unwrap();
    let mut fresh = Bordered::new(&pat).unwrap();
    let mut c1 = Counts::default();
    fresh.factorise_at(&mut p, x, param, (&tx, tl), &scaling, &mut c1, Factors::ForSolves).unwrap();
    let first = c1.times.factorisations.as_secs_f64();
    let steady = (0..3)
        .map(|_| {
            let mut c = Counts::default();
            fresh.factorise_at(&mut p, x, param, (&tx, tl), &scaling, &mut c, Factors::ForSolves).unwrap();
            c.times.factorisations.as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min);
    let how = if fresh.block_elimination() { "block elimination on A's supernodal LU" } else { "B's simplicial LU" };
    // A record's factorisation (simplicial: its determinant signs).
    let exact = (0..3)
        .map(|_| {
            let mut c = Counts::default();
            fresh.factorise_at(&mut p, x, param, (&tx, tl), &scaling, &mut c, Factors::Exact).unwrap();
            c.times.factorisations.as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min);
    let (mut jx, mut jl) = (vec![0.0; pat.nnz()], vec![0.0; n]);
    p.jacobian(x, param, &mut jx, &mut jl);
    let mut band_lu = BandLu::new(&pat, band, p.border()).unwrap();
    let band_time = (0..3)
        .map(|_| {
            let t = std::time::Instant::now();
            let _ = band_lu.factorise(&jx);
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min);
    format!(
        "n {n}, nnz(B) {}, half-band {hb} (rod band {band}, {far} entries outside it), {} pairs, L+U {} ({:.1}× nnz, {:?} order); \
         factorisation by {how} {:.1} ms (the first, with the ordering's choice, {:.1} ms), a record's (simplicial) {:.1} ms; \
         the rod band alone: nnz {}, L+U {}, {:.1} ms",
        fresh.nnz(),
        p.pairs(),
        fresh.fill(),
        fresh.fill() as f64 / fresh.nnz() as f64,
        fresh.column_order(),
        1e3 * steady,
        1e3 * first,
        1e3 * exact,
        band_lu.kept().0,
        band_lu.fill(),
        1e3 * band_time
    )
}

/// One branch's work and time.
fn profile_line(name: &str, c: &Counts, newton: usize, points: usize, lists: usize) -> String {
    let t = &c.times;
    let ms = |d: std::time::Duration| d.as_secs_f64();
    let per = |v: usize| v as f64 / c.steps.max(1) as f64;
    format!(
        "  {name}: {} steps ({} rejected), {} points, {} factorisations ({:.2}/step; {} in {} bifurcation locations; {} by block elimination, {:.2} s; {:.2} s on the records' signs, on their own thread with 2 threads), \
         {} corrector iterations on accepted points ({:.2}/point), {} solves ({} σ_min monitor, {} stability counts in {:.2} s), {} residuals, {} Jacobians, {} pair lists ({:.1} steps/list), {} series orders (ANM)\n    \
         time: residual {:.2} s, Jacobian {:.2} s, LU factorisation {:.2} s, solves {:.2} s, σ_min monitor {:.2} s, setup (pair lists, patterns) {:.2} s; location (inclusive) {:.2} s",
        c.steps,
        c.rejected_steps,
        points,
        c.factorisations,
        per(c.factorisations),
        c.location_factorisations,
        c.locations,
        c.block_eliminations,
        ms(c.block_time),
        ms(t.overlapped),
        newton,
        newton as f64 / points.max(1) as f64,
        c.solves,
        c.monitor_solves,
        c.stability_solves,
        ms(t.stability),
        c.residuals,
        c.jacobians,
        lists,
        c.steps as f64 / lists.max(1) as f64,
        c.series_orders,
        ms(t.residuals),
        ms(t.jacobians),
        ms(t.factorisations),
        ms(t.solves),
        ms(t.monitor),
        ms(t.setup),
        ms(t.location),
    )
}

/// What the run decided of its points' stability and what the summary
/// found from it: points whose count is undetermined, unstable and with
/// neutral modes (counted runs), the coexistence point and the plateau.
fn stability_line(run: &SupercoilRun) -> String {
    let modes = rodkit::charged::coexistence::negative_modes(run).unwrap_or_default();
    let undetermined = modes.iter().filter(|m| m.is_none()).count();
    let unstable = modes.iter().filter(|m| m.is_some_and(|m| m > 0)).count();
    let records = run.straight.records.iter().chain(run.buckled.iter().flat_map(|b| b.records.iter()));
    let neutral = records.filter(|r| r.stability.as_ref().is_some_and(|s| s.marginal > 0)).count();
    let summary = rodkit::charged::summary::summarise(run);
    let (coexistence, plateau) = match &summary {
        Ok(s) => (
            format!("{:?} {:?}", s.coexistence.finding, s.coexistence.value.map(|c| c.turns)),
            format!("{:?} {:?}", s.plateau.finding, s.plateau.value.map(|p| (p.torque, p.slope))),
        ),
        Err(e) => (e.message.clone(), String::new()),
    };
    format!(
        "stability of {} points: {undetermined} undetermined, {unstable} unstable, {neutral} with neutral modes; \
         coexistence {coexistence} turns; plateau {plateau} (pN nm, nm/turn)",
        modes.len()
    )
}

/// The largest distance of `new`'s points from `reference`'s path, as
/// (torque, extension) relative to the reference's buckling torque and
/// contour length: each point against the nearest point of the polyline
/// through the reference's points of the same branch, in (turns, M/M_b,
/// z/L) — the paths fold back in turns, so "at equal turns" is "on the
/// same curve". The polyline's chord error (O(h²) with the reference's
/// step h) is part of the figure: a reference with small steps keeps it
/// below the tolerance.
fn path_deviation(new: &SupercoilRun, reference: &SupercoilRun) -> (f64, f64) {
    let mb = reference.buckling.map_or(1.0, |b| b.1.abs()).max(1e-300);
    let l = reference.scene.length();
    let key = |p: &rodkit::charged::dna::PathPoint| {
        [p.observables.turns, p.observables.torque / mb, p.observables.extension / l]
    };
    let (mut worst_m, mut worst_z) = (0.0f64, 0.0f64);
    for p in &new.points {
        let q = key(p);
        let mut best = (f64::INFINITY, 0.0, 0.0);
        for w in reference.points.windows(2).filter(|w| w[0].branch == p.branch && w[1].branch == p.branch) {
            let (a, b) = (key(&w[0]), key(&w[1]));
            let ab: Vec<f64> = (0..3).map(|i| b[i] - a[i]).collect();
            let len2: f64 = ab.iter().map(|v| v * v).sum();
            let t = if len2 > 0.0 {
                ((0..3).map(|i| (q[i] - a[i]) * ab[i]).sum::<f64>() / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let c: Vec<f64> = (0..3).map(|i| a[i] + t * ab[i]).collect();
            let d2: f64 = (0..3).map(|i| (q[i] - c[i]).powi(2)).sum();
            if d2 < best.0 {
                best = (d2, (q[1] - c[1]).abs(), (q[2] - c[2]).abs());
            }
        }
        if best.0.is_finite() {
            worst_m = worst_m.max(best.1);
            worst_z = worst_z.max(best.2);
        }
    }
    (worst_m, worst_z)
}

fn main() {
    // RODKIT_SUPERCOIL_OUT: another output folder (runs side by side).
    let dir = std::env::var_os("RODKIT_SUPERCOIL_OUT")
        .map_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench/supercoil"), Into::into);
    std::fs::create_dir_all(&dir).unwrap();
    let steps: usize = std::env::var("RODKIT_SUPERCOIL_STEPS").ok().and_then(|v| v.parse().ok()).unwrap_or(120);
    let max_turns: f64 = std::env::var("RODKIT_SUPERCOIL_TURNS").ok().and_then(|v| v.parse().ok()).unwrap_or(12.0);
    let mut report = String::new();
    let (mut ext, mut tor, mut tw) = (vec![], vec![], vec![]);
    let salts: Vec<f64> = std::env::var("RODKIT_SUPERCOIL_SALTS")
        .ok()
        .map_or(vec![0.1, 0.01], |v| v.split(',').filter_map(|s| s.trim().parse().ok()).collect());
    // Any salts (mol/L); the curves' colours cycle.
    let palette = [
        (BLUE, RGBColor(120, 160, 255)),
        (RED, RGBColor(255, 140, 120)),
        (GREEN, RGBColor(120, 220, 120)),
        (MAGENTA, RGBColor(230, 130, 230)),
    ];
    for (k, &salt) in salts.iter().enumerate() {
        let (color, light) = palette[k % palette.len()];
        let knob = |name: &str| std::env::var(name).ok().and_then(|v| v.parse::<f64>().ok());
        // The scene (issue 18's other targets): length in base pairs,
        // tension (pN), elements (default the automatic mesh), and the
        // discrete base-pair charges instead of the line charge.
        let defaults = DnaScene::default();
        let bp = knob("RODKIT_SUPERCOIL_BP").map_or(1000, |v| v as usize);
        let tension = knob("RODKIT_SUPERCOIL_FORCE").unwrap_or(defaults.tension);
        let elements = knob("RODKIT_SUPERCOIL_ELEMENTS").map_or(0, |v| v as usize);
        let stages = knob("RODKIT_SUPERCOIL_STAGES").map_or(SupercoilSettings::default().stages, |v| v as usize);
        let discrete = knob("RODKIT_SUPERCOIL_DISCRETE").is_some_and(|v| v != 0.0);
        let scene = DnaScene { salt, base_pairs: bp, tension, ..defaults };
        // The automatic mesh resolved (0: 2 nm elements).
        let elements = SupercoilSettings { elements, ..Default::default() }.elements_for(&scene).unwrap();
        let aim = knob("RODKIT_SUPERCOIL_AIM").unwrap_or(3.0);
        let threads = knob("RODKIT_SUPERCOIL_THREADS").map_or(1, |v| v as usize);
        // RODKIT_SUPERCOIL_ENGINE=anm: the buckled branch by the ANM
        // (order RODKIT_SUPERCOIL_ANM_ORDER, ε RODKIT_SUPERCOIL_ANM_EPS).
        let anm_engine = std::env::var("RODKIT_SUPERCOIL_ENGINE").is_ok_and(|v| v == "anm");
        let d = SupercoilSettings::default().anm;
        let anm = AnmOptions {
            order: knob("RODKIT_SUPERCOIL_ANM_ORDER").map_or(d.order, |v| v as usize),
            epsilon: knob("RODKIT_SUPERCOIL_ANM_EPS").unwrap_or(d.epsilon),
            pade: false,
        };
        // RODKIT_SUPERCOIL_LISTS=coverage: pair lists rebuilt by coverage.
        let coverage = std::env::var("RODKIT_SUPERCOIL_LISTS").is_ok_and(|v| v == "coverage");
        let settings = SupercoilSettings {
            list_rule: if coverage { ListRule::Coverage } else { ListRule::Displacement },
            engine: if anm_engine { Engine::Anm } else { Engine::Hermite },
            anm,
            elements,
            stages,
            // RODKIT_SUPERCOIL_CUTOFF: the screening cutoff's relative
            // energy tolerance (0: every pair).
            cutoff_tolerance: knob("RODKIT_SUPERCOIL_CUTOFF")
                .map_or(SupercoilSettings::default().cutoff_tolerance, |v| (v > 0.0).then_some(v)),
            threads,
            max_steps: steps,
            max_turns,
            corrector_aim: aim,
            base_pairs: discrete,
            // RODKIT_SUPERCOIL_FAR_POINTS: the far zone on this many
            // Gauss–Legendre points per element (0: the stage points).
            far_points: knob("RODKIT_SUPERCOIL_FAR_POINTS").map_or(0, |v| v as usize),
            ..Default::default()
        };
        let _ = writeln!(
            report,
            "scene: {bp} bp, {tension} pN, {salt} M, {elements} elements of Gauss({stages}), {} charges{}",
            if discrete { "base-pair" } else { "line" },
            match settings.far_points {
                0 => String::new(),
                m => format!(", far zone on {m} Gauss points an element"),
            }
        );
        // Before and after in one process (issue 18): the engine up to
        // issue 18 (Euler predictor, Newton corrector, simplicial LU of
        // the bordered Jacobian throughout) and the default one.
        // RODKIT_SUPERCOIL_BASELINE=0 skips the baseline, =lu takes the
        // default engine with the simplicial LU throughout (the LU's own
        // share).
        let baseline_settings = match std::env::var("RODKIT_SUPERCOIL_BASELINE").as_deref() {
            Ok("0") => None,
            Ok("lu") => Some(SupercoilSettings { lu_kind: Some(LuKind::Simplicial), ..settings.clone() }),
            Ok("serial") => Some(SupercoilSettings { threads: 1, ..settings.clone() }),
            // The records' signs from B's own simplicial LU (on the second
            // thread with 2 threads) and stability by the parity rules, as
            // before the counted modes: what counting saves.
            Ok("signs") => Some(SupercoilSettings { stability: None, ..settings.clone() }),
            Ok("hermite") => Some(SupercoilSettings { engine: Engine::Hermite, ..settings.clone() }),
            Ok("verlet") => Some(SupercoilSettings { list_rule: ListRule::Displacement, ..settings.clone() }),
            // A reference discretisation (the path's own discretisation
            // error): RODKIT_SUPERCOIL_BASELINE=mesh with
            // RODKIT_SUPERCOIL_REF_ELEMENTS / _REF_STAGES.
            Ok("mesh") => Some(SupercoilSettings {
                elements: knob("RODKIT_SUPERCOIL_REF_ELEMENTS").map_or(2 * elements, |v| v as usize),
                stages: knob("RODKIT_SUPERCOIL_REF_STAGES").map_or(stages, |v| v as usize),
                far_points: knob("RODKIT_SUPERCOIL_REF_FAR_POINTS").map_or(settings.far_points, |v| v as usize),
                ..settings.clone()
            }),
            _ => Some(SupercoilSettings {
                engine: Engine::Newton,
                lu_kind: Some(LuKind::Simplicial),
                ..settings.clone()
            }),
        };
        let baseline = baseline_settings.as_ref().map(|b| run_scene(&scene, b).unwrap());
        let r = run_scene(&scene, &settings).unwrap();
        if let Some(b) = &baseline {
            let work = |r: &SupercoilRun| {
                let steps = r.straight.counts.steps + r.buckled.as_ref().map_or(0, |b| b.counts.steps);
                let facts =
                    r.straight.counts.factorisations + r.buckled.as_ref().map_or(0, |b| b.counts.factorisations);
                (steps, facts)
            };
            let ((s0, f0), (s1, f1)) = (work(b), work(&r));
            let (dm, dz) = path_deviation(&r, b);
            let last = |r: &SupercoilRun| r.points.last().map_or(f64::NAN, |p| p.observables.turns);
            let _ = writeln!(
                report,
                "{salt} M, engine {:?} (LU {:?}) against {:?} (LU {:?}) (same process): {:.1} s vs {:.1} s ({:.2}× faster), {s1} vs {s0} steps, \
                 {f1} vs {f0} factorisations ({:.2} vs {:.2} a step); last point {:.3} vs {:.3} turns; \
                 largest distance from the baseline's path: torque {:.1e} of M_b, extension {:.1e} of L",
                settings.engine,
                settings.lu_kind,
                baseline_settings.as_ref().map(|b| b.engine),
                baseline_settings.as_ref().and_then(|b| b.lu_kind),
                r.seconds,
                b.seconds,
                b.seconds / r.seconds,
                f1 as f64 / s1.max(1) as f64,
                f0 as f64 / s0.max(1) as f64,
                last(&r),
                last(b),
                dm,
                dz
            );
        }
        for (name, run) in [("baseline", baseline.as_ref()), ("run", Some(&r))] {
            if let Some(run) = run {
                let _ = writeln!(report, "  {name}: {}", stability_line(run));
            }
        }
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
        let _ = writeln!(
            report,
            "  stop: {:?} (buckled branch: {:?}){}",
            r.stop,
            r.buckled.as_ref().map(|b| b.stop),
            r.failure().map_or(String::new(), |e| format!("; failure: {e}"))
        );
        // The profile: per branch, then the total against the wall clock.
        let mut total = Counts::default();
        let mut steps_csv = String::from("branch,record,turns,step,newton_iterations,sigma_min,det_sign\n");
        let mut k = 0;
        for (name, b) in [("straight", Some(&r.straight)), ("buckled", r.buckled.as_ref())] {
            let Some(b) = b else { continue };
            let newton: usize = b.records.iter().map(|rec| rec.newton_iterations).sum();
            let _ = writeln!(report, "{}", profile_line(name, &b.counts, newton, b.records.len(), b.pair_lists));
            total.add(&b.counts);
            for (i, rec) in b.records.iter().enumerate() {
                let _ = writeln!(
                    steps_csv,
                    "{name},{i},{},{},{},{},{}",
                    r.points[k].observables.turns,
                    rec.step,
                    rec.newton_iterations,
                    rec.smallest_singular_value.unwrap_or(f64::NAN),
                    rec.det_sign
                );
                k += 1;
            }
        }
        let t = &total.times;
        let kernels = (t.residuals + t.jacobians + t.factorisations + t.solves + t.monitor + t.setup).as_secs_f64();
        let _ = writeln!(
            report,
            "  total {:.2} s: kernels {:.2} s ({:.0} %: residual {:.0} %, Jacobian {:.0} %, LU {:.0} %, solves {:.0} %, σ_min monitor {:.0} %, setup {:.0} %), \
             observables (writhe) {:.2} s ({:.0} %), other {:.2} s; bifurcation location {:.0} % (inclusive)",
            r.seconds,
            kernels,
            100.0 * kernels / r.seconds,
            100.0 * t.residuals.as_secs_f64() / r.seconds,
            100.0 * t.jacobians.as_secs_f64() / r.seconds,
            100.0 * t.factorisations.as_secs_f64() / r.seconds,
            100.0 * t.solves.as_secs_f64() / r.seconds,
            100.0 * t.monitor.as_secs_f64() / r.seconds,
            100.0 * t.setup.as_secs_f64() / r.seconds,
            r.observables_seconds,
            100.0 * r.observables_seconds / r.seconds,
            r.seconds - kernels - r.observables_seconds,
            100.0 * t.location.as_secs_f64() / r.seconds,
        );
        let _ = writeln!(
            report,
            "  Jacobian at the start: {}",
            lu_size(&r, None, &r.straight.states[0], r.straight.records[0].lambda)
        );
        if let Some(b) = r.buckled.as_ref() {
            let i = 1.min(b.records.len() - 1);
            let (x, rec) = (&b.states[i], &b.records[i]);
            let _ = writeln!(report, "  at buckling (phase condition): {}", lu_size(&r, b.phase, x, rec.lambda));
            // Along the branch (the LU's cost follows the pairs).
            let stride = (b.records.len() / 6).max(1);
            for i in (stride..b.records.len() - 1).step_by(stride) {
                let turns = r.points[r.straight.records.len() + i].observables.turns;
                let _ = writeln!(
                    report,
                    "  buckled point {i} ({turns:.3} turns): {}",
                    lu_size(&r, b.phase, &b.states[i], b.records[i].lambda)
                );
            }
            let (x, rec) = (b.states.last().unwrap(), b.records.last().unwrap());
            let _ = writeln!(report, "  at the last point: {}", lu_size(&r, b.phase, x, rec.lambda));
        }
        std::fs::write(dir.join(format!("steps_{salt}M.csv")), steps_csv).unwrap();
        // The path, and the baseline's beside it (path_<salt>M_baseline.csv).
        for (run, suffix) in [(Some(&r), ""), (baseline.as_ref(), "_baseline")] {
            let Some(run) = run else { continue };
            let mut csv = String::from("turns,extension_nm,torque_pN_nm,tension_pN,twist,writhe,branch\n");
            for p in &run.points {
                let o = p.observables;
                let _ = writeln!(
                    csv,
                    "{},{},{},{},{},{},{}",
                    o.turns, o.extension, o.torque, o.tension, o.twist, o.writhe, p.branch
                );
            }
            std::fs::write(dir.join(format!("path_{salt}M{suffix}.csv")), csv).unwrap();
            // μ, the unfolding parameter of the buckled branch's phase
            // condition (a distributed couple, pN), at each of its records.
            let n = run.rod.unknowns();
            if let Some(b) = &run.buckled {
                let mut mu = String::from("record,parameter,mu\n");
                for (k, (rec, x)) in b.records.iter().zip(&b.states).enumerate() {
                    let _ = writeln!(mu, "{k},{},{}", rec.lambda, x.get(n).copied().unwrap_or(0.0));
                }
                std::fs::write(dir.join(format!("mu_{salt}M{suffix}.csv")), mu).unwrap();
            }
        }
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

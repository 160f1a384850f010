//! Charged-rod electrostatics benchmark (`cargo bench --bench charged`):
//! the continuum energy (near-zone regularisation, far zone with the
//! screening cutoff and cell lists) against the discrete base-pair model,
//! all pairs (the thesis's comparison) and with the same cutoff and cell
//! lists, on DNA-like superhelices of 1, 3 and 10 kbp (0.34 nm per bp,
//! radius 3 nm, pitch 40 nm; κ = 1/0.96 nm⁻¹ ≈ 0.1 M salt, a = 1 nm, line
//! charge 1). Each model at 1e-4 relative energy error against its own
//! converged reference: the discrete cutoff against all pairs; the
//! continuum (8 nm panels, 3 Gauss points, δ = 4 nm, r_c from 1e-4 — the
//! cheapest of a few settings meeting the tolerance here) against 2 nm
//! panels, order 12, δ = 1.5 nm and no cutoff. Time per energy evaluation, medians of 3, as
//! ratios in the same run. Writes target/bench/charged/{report.txt,
//! energy.csv}.
//!
//! Second table, the coupled rod (src/electrostatics/rod.rs): the DNA scene
//! (1 pN, 0.1 M, ν = 1/l_B) on 3.4 nm elements of Gauss(2), twisted
//! straight state at φ = 2, with the continuum line charge and with the
//! discrete base-pair charges on the same rod (RodCharge::base_pairs),
//! each with a cutoff meeting 1e-4 force error on a superhelix against its
//! own every-pair reference: time per residual (continuum also with 2
//! threads), per Jacobian and per equilibrium (a Newton corrector φ = 2 →
//! 2.1) by the direct sparse Newton and by Newton–Krylov with the rod-band
//! preconditioner (src/continuation/krylov.rs; cold and warm), the
//! all-pairs base-pair baseline (residual; equilibria: direct with the
//! cutoff model's Jacobian, Newton–Krylov on its own residual) and the
//! continuum's every-pair residual, as ratios, at 1, 3 and 10 kbp, and the
//! continuum alone at 30 kbp (scaling past the cache step at 10 kbp);
//! per-doubling factors per segment and by least squares;
//! target/bench/charged/{rod.csv, rod_residual.svg, rod_equilibrium.svg}.

#[path = "support/plot.rs"]
mod plot;

use rodkit::electrostatics::{discrete, energy, Centerline, EnergyQuadrature, LineCharge, Screening};
use std::fmt::Write as _;
use std::time::{Duration, Instant};

struct Superhelix {
    l: f64,
    /// Panel (node) spacing of the continuum's quadrature.
    panel: f64,
}

impl Centerline for Superhelix {
    fn length(&self) -> f64 {
        self.l
    }
    fn closed(&self) -> bool {
        false
    }
    fn eval(&self, s: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let (rho, c) = (3.0, 40.0 / (2.0 * std::f64::consts::PI));
        let w = (rho * rho + c * c).sqrt();
        let th = s / w;
        let (sn, cs) = th.sin_cos();
        (
            [rho * cs, rho * sn, c * th],
            [-rho * sn / w, rho * cs / w, c / w],
            [-rho * cs / (w * w), -rho * sn / (w * w), 0.0],
        )
    }
    fn breakpoints(&self) -> Vec<f64> {
        let n = (self.l / self.panel).ceil() as usize;
        (1..n).map(|k| self.l * k as f64 / n as f64).collect()
    }
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn time<T>(reps: usize, mut f: impl FnMut() -> T) -> (T, Duration) {
    let mut times = vec![];
    let mut last = None;
    for _ in 0..reps {
        let t = Instant::now();
        last = Some(f());
        times.push(t.elapsed());
    }
    (last.unwrap(), median(times))
}

fn main() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bench/charged");
    std::fs::create_dir_all(&dir).unwrap();
    let scr = Screening { kappa: 1.0 / 0.96, a: 1.0 };
    let tol = 1e-4;
    let rc = discrete::screening_cutoff(scr.kappa, scr.a, tol, 1e4).unwrap();
    let q = LineCharge::Uniform(1.0);
    let mut out = String::new();
    let _ = writeln!(out, "rodkit {} electrostatics: continuum vs discrete base pairs (κ = {:.4}/nm, a = 1 nm, r_c = {rc:.3} nm for 1e-4)", env!("CARGO_PKG_VERSION"), scr.kappa);
    let _ = writeln!(
        out,
        "{:>6} {:>12} {:>10} {:>12} {:>10} {:>12} {:>10} {:>11} {:>11}",
        "kbp", "all pairs", "", "cutoff", "error", "continuum", "error", "all/cont", "cut/cont"
    );
    let mut csv = String::from("bp,all_pairs_s,cutoff_s,cutoff_error,continuum_s,continuum_error\n");
    let mut prev: Option<(f64, Duration)> = None;
    let mut scaling = vec![];
    for bp in [1000usize, 3000, 10000] {
        let curve = Superhelix { l: 0.34 * bp as f64, panel: 8.0 };
        let fine = Superhelix { l: 0.34 * bp as f64, panel: 2.0 };
        let (r, qs, s) = discrete::base_pairs(&curve, &q, 0.34).unwrap();
        let (all, t_all) = time(3, || discrete::energy(&r, &qs, &s, &scr, None));
        let ((cut, _), t_cut) = time(3, || discrete::energy_cutoff(&r, &qs, &s, &scr, rc, None, 1));
        let reference =
            energy(&fine, &q, &scr, &EnergyQuadrature { delta: 1.5, order: 12, cutoff: None }).unwrap().total;
        let (cont, t_cont) = time(3, || {
            energy(&curve, &q, &scr, &EnergyQuadrature { delta: 4.0, order: 3, cutoff: Some(rc) }).unwrap().total
        });
        let (e_cut, e_cont) = ((all - cut).abs() / all, (reference - cont).abs() / reference);
        let _ = writeln!(
            out,
            "{:>6} {:>10.2}ms {:>10} {:>10.2}ms {:>10.1e} {:>10.2}ms {:>10.1e} {:>11.1} {:>11.2}",
            bp as f64 / 1000.0,
            t_all.as_secs_f64() * 1e3,
            "",
            t_cut.as_secs_f64() * 1e3,
            e_cut,
            t_cont.as_secs_f64() * 1e3,
            e_cont,
            t_all.as_secs_f64() / t_cont.as_secs_f64(),
            t_cut.as_secs_f64() / t_cont.as_secs_f64()
        );
        let _ = writeln!(
            csv,
            "{bp},{},{},{e_cut},{},{e_cont}",
            t_all.as_secs_f64(),
            t_cut.as_secs_f64(),
            t_cont.as_secs_f64()
        );
        if let Some((pbp, pt)) = prev {
            let doublings = (bp as f64 / pbp).log2();
            scaling.push(format!(
                "{:.0} → {bp} bp: continuum ×{:.2} per doubling",
                pbp,
                (t_cont.as_secs_f64() / pt.as_secs_f64()).powf(1.0 / doublings)
            ));
        }
        prev = Some((bp as f64, t_cont));
    }
    let _ = writeln!(out, "{}", scaling.join("; "));
    let _ = writeln!(out, "(the continuum and discrete energies differ by the near-field term, O(b/a); each error is against its own reference)");
    rod_table(&mut out, &dir);
    print!("{out}");
    std::fs::write(dir.join("report.txt"), &out).unwrap();
    std::fs::write(dir.join("energy.csv"), &csv).unwrap();
}

/// A rod state whose nodes and stages lie on the superhelix (only the
/// positions matter for the pair forces).
fn superhelix_state(rod: &rodkit::rod::model::Rod) -> Vec<f64> {
    let curve = Superhelix { l: rod.length, panel: 8.0 };
    let h = rod.element_length();
    let c = [0.5 - 3f64.sqrt() / 6.0, 0.5 + 3f64.sqrt() / 6.0];
    let mut x = rod.straight_state();
    for e in 0..=rod.elements {
        let mut put = |o: usize, s: f64| x[o..o + 3].copy_from_slice(&curve.eval(s).0);
        put(rod.node(e), e as f64 * h);
        if e < rod.elements {
            for j in 0..2 {
                put(rod.node(e) + 13 * (1 + j), (e as f64 + c[j]) * h);
            }
        }
    }
    x
}

/// Newton on one residual with another problem's Jacobian: the all-pairs
/// discrete model's equilibrium, whose exact Jacobian is dense, with the
/// Jacobian of its pairs inside the cutoff (the dropped entries are below
/// the cutoff's tolerance, so Newton contracts by about that much per
/// iteration instead of quadratically).
struct Truncated<'a> {
    full: &'a mut rodkit::charged::rod::ChargedRod,
    cut: &'a mut rodkit::charged::rod::ChargedRod,
}

impl rodkit::continuation::Problem for Truncated<'_> {
    fn dim(&self) -> usize {
        self.cut.dim()
    }
    fn pattern(&self) -> &rodkit::linalg::sparse::Pattern {
        self.cut.pattern()
    }
    fn residual(&mut self, x: &[f64], lambda: f64, r: &mut [f64]) {
        self.full.residual(x, lambda, r)
    }
    fn jacobian(&mut self, x: &[f64], lambda: f64, jx: &mut [f64], jl: &mut [f64]) {
        self.cut.jacobian(x, lambda, jx, jl)
    }
    fn equation_scales(&self) -> Vec<f64> {
        self.cut.equation_scales()
    }
    fn unknown_scales(&self) -> (Vec<f64>, f64) {
        self.cut.unknown_scales()
    }
}

/// The largest difference of two force-density fields relative to the
/// largest force density of the reference.
fn force_error(f: &[[f64; 3]], reference: &[[f64; 3]]) -> f64 {
    let scale = reference.iter().flat_map(|v| v.iter()).fold(0.0f64, |m, v| m.max(v.abs()));
    f.iter().zip(reference).flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs())).fold(0.0, f64::max) / scale
}

fn rod_table(out: &mut String, dir: &std::path::Path) {
    use rodkit::charged::branch::follow;
    use rodkit::charged::dna::DnaScene;
    use rodkit::charged::rod::{ChargedRod, RodCharge};
    use rodkit::continuation::equilibrium::newton_krylov;
    use rodkit::continuation::newton::{continue_newton, Start};
    use rodkit::continuation::{Options, Problem};
    use rodkit::nonlinear::krylov::{BandPreconditioner, KrylovOptions};
    let _ = writeln!(out, "\ncoupled rod, continuum vs discrete base pairs (DNA scene: 0.1 M, ν = 1/l_B, 1 pN; h = 3.4 nm, Gauss(2); straight state at φ = 2)");
    let _ = writeln!(out, "time per residual and Jacobian (medians of 21 and 9) and per equilibrium (medians of 3 direct, 9 NK, 3 NK all pairs): Newton at φ = 2.1 from the continuum's equilibrium at φ = 2 (a continuation corrector) to a scaled residual of 1e-8, the DNA scene default,");
    let _ = writeln!(out, "  direct = sparse Newton of the continuation engine (exact Jacobian, full LU, symbolic analysis included); NK = Newton–Krylov (GMRES, central-difference products, preconditioner: LU of the Jacobian band |i − j| ≤ w, w = {} = one element's coupling for the continuum, twice that for base pairs, refreshed after > 10 GMRES iterations), cold (symbolic analysis, Jacobian and band LU included) and warm (band LU kept from a previous solve, as along a continuation);", 51);
    let _ = writeln!(out, "cutoffs with cell lists, continuum 3e-5 and base pairs 1e-4 (each meeting 1e-4 force error); force error on a superhelix (radius 3, pitch 40 nm) against the same model with every pair: max |p − p_ref| over the stage force densities, relative to max |p_ref| (base pairs) or to the continuum's whole electrostatic force density (its p is the far zone only)");
    let _ = writeln!(out, "all-pairs base pairs: direct = Newton on its residual with the cutoff model's Jacobian (its exact one is dense); NK = its own residual's products, preconditioner from the cutoff model's Jacobian");
    let _ = writeln!(
        out,
        "{:>4} {:>6} {:>22} {:>10} {:>10} {:>11} {:>10} {:>10} {:>4} {:>8}",
        "kbp", "n", "model", "residual", "Jacobian", "eq direct", "eq NK", "NK warm", "GMRES", "f error"
    );
    let mut csv = String::from("bp,n,model,residual_s,jacobian_s,equilibrium_direct_s,equilibrium_nk_s,equilibrium_nk_warm_s,krylov_iterations,force_error,residual_2threads_s,jacobian_2threads_s\n");
    let mut series: Vec<(&str, Vec<(f64, f64)>)> = vec![
        ("continuum, cutoff", vec![]),
        ("base pairs, cutoff", vec![]),
        ("base pairs, all pairs", vec![]),
        ("continuum, every pair", vec![]),
    ];
    let mut eq_series: Vec<(&str, Vec<(f64, f64)>)> = vec![
        ("continuum, NK", vec![]),
        ("base pairs, NK", vec![]),
        ("base pairs all pairs, NK", vec![]),
        ("continuum, direct", vec![]),
        ("base pairs, direct", vec![]),
    ];
    let mut scaling = vec![];
    let mut ratios = vec![];
    let mut prev: Option<(f64, f64, f64, f64, f64)> = None;
    let mut fit_points: Vec<(f64, [f64; 4])> = vec![];
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let eq_opts = Options { residual_tol: 1e-8, max_steps: 0, ..Default::default() };
    let nk_opts = KrylovOptions { residual_tol: 1e-8, ..Default::default() };
    // 30 kbp: the continuum only (the base pairs' direct equilibrium alone
    // would take ~15 s), to see the scaling past the 3 → 10 kbp step where
    // the Jacobian and band LU (≈ 36 MB at 10 kbp) outgrow the 32 MB L3.
    for bp in [1000usize, 3000, 10000, 30000] {
        let scene = DnaScene { base_pairs: bp, ..Default::default() };
        let rod = scene.rod(bp / 10, 2).unwrap();
        let with_discrete = bp <= 10_000;
        // Cutoffs meeting 1e-4 relative force error on the superhelix: the
        // continuum needs a tighter energy tolerance (3e-5: its force error
        // was 1.9e-4 at 1e-4) than the base pairs (1.4e-5 at 1e-4).
        let mut charge = scene.charge();
        charge.cutoff_tolerance = Some(3e-5);
        let mut discrete = charge.clone();
        discrete.cutoff_tolerance = Some(1e-4);
        discrete.base_pairs = Some(0.34);
        let opts = Options {
            target_lambda: Some(2.0),
            residual_tol: 1e-10,
            initial_step: 2.0,
            max_step: 2.0,
            ..Default::default()
        };
        let b = follow(
            &rod,
            &charge,
            Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true },
            None,
            &opts,
            |_| true,
        )
        .unwrap();
        let x = b.states.last().unwrap().clone();
        let xs = superhelix_state(&rod);
        // Newton–Krylov equilibria of `p` (preconditioner from `source` if
        // given): cold (everything built in the timing) and warm.
        let nk = |p: &mut dyn Problem, mut source: Option<&mut ChargedRod>, band: usize| {
            // The preconditioner is built on its source's pattern.
            let pattern = source.as_deref().map_or_else(|| p.pattern().clone(), |s| s.pattern().clone());
            // Medians of 9 (3 for the all-pairs rod, seconds per solve): the
            // cold solve's first band LU faults in fresh memory, and its time
            // moved by ±15 % between runs of 5 at 10 kbp.
            let reps = if source.is_some() { 3 } else { 9 };
            let mut solve = |pre: &mut BandPreconditioner| {
                let mut y = x.clone();
                newton_krylov(p, source.as_deref_mut().map(|s| s as &mut dyn Problem), pre, &mut y, 2.1, &nk_opts)
                    .unwrap()
            };
            let (rep, cold) = time(reps, || solve(&mut BandPreconditioner::new(&pattern, band).unwrap()));
            let mut pre = BandPreconditioner::new(&pattern, band).unwrap();
            solve(&mut pre);
            let (_, warm) = time(reps, || solve(&mut pre));
            (cold, warm, rep.linear_iterations)
        };
        // Times (residual, Jacobian, equilibria) and the force error of a model.
        let measure = |model: &RodCharge, every: Option<&RodCharge>, full: bool| {
            let mut p = ChargedRod::new(&rod, model, None, &x).unwrap();
            let n = p.dim();
            let mut r = vec![0.0; n];
            let (_, t_res) = time(21, || p.residual(&x, 2.0, &mut r));
            let mut jx = vec![0.0; p.pattern().nnz()];
            let mut jl = vec![0.0; n];
            let t_jac = time(9, || p.jacobian(&x, 2.0, &mut jx, &mut jl)).1;
            if !full {
                return (n, t_res, Some(t_jac), None, None, None, p);
            }
            let t_eq = time(3, || {
                let b = continue_newton(
                    &mut p,
                    Start::Point { x: x.clone(), lambda: 2.1, increasing: true },
                    &eq_opts,
                    |_, _| vec![],
                    |_| true,
                )
                .unwrap();
                assert!(!b.records.is_empty(), "no equilibrium");
            })
            .1;
            let band = p.local_band();
            let t_nk = nk(&mut p, None, band);
            let f_err = every.map(|e| {
                let mut ps = ChargedRod::new(&rod, model, None, &xs).unwrap();
                let mut pe = ChargedRod::new(&rod, e, None, &xs).unwrap();
                let (fs, fe) = (ps.force_densities(&xs), pe.force_densities(&xs));
                if model.base_pairs.is_some() {
                    force_error(&fs, &fe)
                } else {
                    // The continuum's p is the far zone only (the near zone is the
                    // bending stiffening): scale by the whole electrostatic force
                    // density of the converged continuum (electrostatics::force_density).
                    let curve = Superhelix { l: rod.length, panel: 2.0 };
                    let quad = EnergyQuadrature { delta: 2.0, order: 8, cutoff: None };
                    let total = (0..40)
                        .map(|k| {
                            rodkit::electrostatics::force_density(
                                &curve,
                                &LineCharge::Uniform(model.line_charge),
                                &model.screening,
                                &quad,
                                rod.length * (k as f64 + 0.5) / 40.0,
                            )
                            .unwrap()
                        })
                        .flat_map(|v| v.into_iter())
                        .fold(0.0f64, |m, v| m.max(v.abs()));
                    let far = fe.iter().flat_map(|v| v.iter()).fold(0.0f64, |m, v| m.max(v.abs()));
                    force_error(&fs, &fe) * far / total
                }
            });
            (n, t_res, Some(t_jac), Some(t_eq), Some(t_nk), f_err, p)
        };
        let small = bp <= 3000;
        let mut every = charge.clone();
        every.cutoff_tolerance = None;
        let mut every_bp = discrete.clone();
        every_bp.cutoff_tolerance = None;
        let (n, c_res, c_jac, c_eq, c_nk, c_err, mut cp) = measure(&charge, small.then_some(&every), true);
        // The preconditioner's rebuild alone (Jacobian + band LU, on memory
        // already touched by the solves above): linear in the length, so the
        // cold solve's excess at ≥ 10 kbp is the first touch of its memory.
        let t_refresh = {
            let mut pre = BandPreconditioner::new(cp.pattern(), cp.local_band()).unwrap();
            let mut at = rodkit::continuation::equilibrium::AtFixed::new(&mut cp, 2.1);
            pre.refresh(&mut at, &x).unwrap();
            time(9, || pre.refresh(&mut at, &x).unwrap()).1
        };
        let mut two = charge.clone();
        two.threads = 2;
        let (_, c_res2, c_jac2, ..) = measure(&two, None, false);
        let mut d = with_discrete.then(|| measure(&discrete, small.then_some(&every_bp), true));
        let d2 = with_discrete.then(|| {
            let mut two = discrete.clone();
            two.threads = 2;
            let (_, res, jac, ..) = measure(&two, None, false);
            (res, jac.unwrap())
        });
        // All-pairs discrete (1 and 3 kbp).
        let all = small.then(|| {
            let mut pa = ChargedRod::new(&rod, &every_bp, None, &x).unwrap();
            let mut r = vec![0.0; n];
            let (_, a_res) = time(3, || pa.residual(&x, 2.0, &mut r));
            let d_p = &mut d.as_mut().unwrap().6;
            let mut tr = Truncated { full: &mut pa, cut: d_p };
            let (_, a_eq) = time(3, || {
                let b = continue_newton(
                    &mut tr,
                    Start::Point { x: x.clone(), lambda: 2.1, increasing: true },
                    &eq_opts,
                    |_, _| vec![],
                    |_| true,
                )
                .unwrap();
                assert!(!b.records.is_empty(), "no all-pairs equilibrium");
            });
            let band = d_p.local_band();
            let a_nk = nk(&mut pa, Some(d_p), band);
            (a_res, a_eq, a_nk)
        });
        let e_res = small.then(|| {
            let mut pe = ChargedRod::new(&rod, &every, None, &x).unwrap();
            let mut r = vec![0.0; n];
            time(3, || pe.residual(&x, 2.0, &mut r)).1
        });
        let fmt_t = |t: Option<Duration>| t.map_or("-".to_string(), |t| format!("{:.2}ms", ms(t)));
        let fmt_e = |e: Option<f64>| e.map_or("-".to_string(), |e| format!("{e:.1e}"));
        let row = |out: &mut String,
                   kbp: String,
                   name: &str,
                   res: Option<Duration>,
                   jac: Option<Duration>,
                   eq: Option<Duration>,
                   nk: Option<(Duration, Duration, usize)>,
                   err: Option<f64>| {
            let _ = writeln!(
                out,
                "{:>4} {:>6} {:>22} {:>10} {:>10} {:>11} {:>10} {:>10} {:>4} {:>8}",
                kbp,
                n,
                name,
                fmt_t(res),
                fmt_t(jac),
                fmt_t(eq),
                fmt_t(nk.map(|v| v.0)),
                fmt_t(nk.map(|v| v.1)),
                nk.map_or("-".into(), |v| v.2.to_string()),
                fmt_e(err)
            );
        };
        row(out, format!("{}", bp as f64 / 1000.0), "continuum, cutoff", Some(c_res), c_jac, c_eq, c_nk, c_err);
        if let Some((_, d_res, d_jac, d_eq, d_nk, d_err, _)) = &d {
            row(out, "".into(), "base pairs, cutoff", Some(*d_res), *d_jac, *d_eq, *d_nk, *d_err);
        }
        if let Some((a_res, a_eq, a_nk)) = all {
            row(out, "".into(), "base pairs, all pairs", Some(a_res), None, Some(a_eq), Some(a_nk), None);
        }
        let _ = writeln!(
            out,
            "{:>4} {:>6} {:>22} {:>10} {:>10} (2 threads){}",
            "",
            "",
            "continuum, cutoff",
            fmt_t(Some(c_res2)),
            fmt_t(c_jac2),
            e_res.map_or(String::new(), |t| format!(
                "; every pair: residual {} ({:.1}× the cutoff's)",
                fmt_t(Some(t)),
                t.as_secs_f64() / c_res.as_secs_f64()
            ))
        );
        if let Some((res, jac)) = d2 {
            let _ = writeln!(
                out,
                "{:>4} {:>6} {:>22} {:>10} {:>10} (2 threads)",
                "",
                "",
                "base pairs, cutoff",
                fmt_t(Some(res)),
                fmt_t(Some(jac))
            );
        }
        let r = |a: Duration, b: Duration| a.as_secs_f64() / b.as_secs_f64();
        let c_nk = c_nk.unwrap();
        let mut line = format!("{:.0} kbp", bp as f64 / 1000.0);
        if let Some((_, d_res, _, d_eq, d_nk, ..)) = &d {
            let d_nk = d_nk.unwrap();
            let _ = write!(line, ", faster than the cutoff base pairs: residual {:.1}×, equilibrium direct {:.1}×, NK {:.1}× (warm {:.1}×)",
                r(*d_res, c_res), r(d_eq.unwrap(), c_eq.unwrap()), r(d_nk.0, c_nk.0), r(d_nk.1, c_nk.1));
        }
        if let Some((a_res, a_eq, a_nk)) = all {
            let _ = write!(
                line,
                "; than all-pairs base pairs: residual {:.0}×, equilibrium direct {:.1}×, NK {:.0}×",
                r(a_res, c_res),
                r(a_eq, c_eq.unwrap()),
                r(a_nk.0, c_nk.0)
            );
        }
        let _ = write!(
            line,
            "; continuum NK vs direct {:.1}× faster (warm {:.1}×)",
            r(c_eq.unwrap(), c_nk.0),
            r(c_eq.unwrap(), c_nk.1)
        );
        let _ = write!(
            line,
            "; preconditioner refresh (Jacobian + band LU) {:.2} ms = {:.0} ns per unknown",
            ms(t_refresh),
            t_refresh.as_secs_f64() * 1e9 / n as f64
        );
        ratios.push(line);
        let secs = |t: Option<Duration>| t.map_or(f64::NAN, |t| t.as_secs_f64());
        let _ = writeln!(
            csv,
            "{bp},{n},continuum_cutoff,{},{},{},{},{},{},{},{},{}",
            c_res.as_secs_f64(),
            secs(c_jac),
            secs(c_eq),
            c_nk.0.as_secs_f64(),
            c_nk.1.as_secs_f64(),
            c_nk.2,
            c_err.unwrap_or(f64::NAN),
            c_res2.as_secs_f64(),
            secs(c_jac2)
        );
        let _ = writeln!(csv, "{bp},{n},continuum_every_pair,{},,,,,,,,", secs(e_res));
        if let Some((_, d_res, d_jac, d_eq, d_nk, d_err, _)) = &d {
            let d_nk = d_nk.unwrap();
            let (res2, jac2) = d2.map_or((f64::NAN, f64::NAN), |(r, j)| (r.as_secs_f64(), j.as_secs_f64()));
            let _ = writeln!(
                csv,
                "{bp},{n},base_pairs_cutoff,{},{},{},{},{},{},{},{res2},{jac2}",
                d_res.as_secs_f64(),
                secs(*d_jac),
                secs(*d_eq),
                d_nk.0.as_secs_f64(),
                d_nk.1.as_secs_f64(),
                d_nk.2,
                d_err.unwrap_or(f64::NAN)
            );
        }
        if let Some((a_res, a_eq, a_nk)) = all {
            let _ = writeln!(
                csv,
                "{bp},{n},base_pairs_all,{},,{},{},{},{},,,",
                a_res.as_secs_f64(),
                a_eq.as_secs_f64(),
                a_nk.0.as_secs_f64(),
                a_nk.1.as_secs_f64(),
                a_nk.2
            );
        }
        let lb = (bp as f64).log10();
        series[0].1.push((lb, ms(c_res).log10()));
        eq_series[0].1.push((lb, ms(c_nk.0).log10()));
        eq_series[3].1.push((lb, ms(c_eq.unwrap()).log10()));
        if let Some((_, d_res, _, d_eq, d_nk, ..)) = &d {
            series[1].1.push((lb, ms(*d_res).log10()));
            eq_series[1].1.push((lb, ms(d_nk.unwrap().0).log10()));
            eq_series[4].1.push((lb, ms(d_eq.unwrap()).log10()));
        }
        if let Some((a_res, _, a_nk)) = all {
            series[2].1.push((lb, ms(a_res).log10()));
            eq_series[2].1.push((lb, ms(a_nk.0).log10()));
        }
        if let Some(t) = e_res {
            series[3].1.push((lb, ms(t).log10()));
        }
        let (cr, ce, cn, cw) = (c_res.as_secs_f64(), secs(c_eq), c_nk.0.as_secs_f64(), c_nk.1.as_secs_f64());
        if let Some((pbp, pr, pe, pn, pw)) = prev {
            let d = (bp as f64 / pbp).log2();
            scaling.push(format!("{pbp:.0} → {bp} bp: continuum residual ×{:.2}, equilibrium direct ×{:.2}, NK ×{:.2} (warm ×{:.2}) per doubling", (cr / pr).powf(1.0 / d), (ce / pe).powf(1.0 / d), (cn / pn).powf(1.0 / d), (cw / pw).powf(1.0 / d)));
        }
        prev = Some((bp as f64, cr, ce, cn, cw));
        fit_points.push((bp as f64, [cr, ce, cn, cw]));
    }
    // Least-squares slope of log t against log L over all lengths: the
    // per-doubling factor of the whole range, less sensitive than one
    // segment to a single extra Newton iteration or a noisy run.
    let slope = |k: usize| {
        let pts: Vec<(f64, f64)> = fit_points.iter().map(|(l, t)| (l.log2(), t[k].log2())).collect();
        let m = pts.len() as f64;
        let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / m, pts.iter().map(|p| p.1).sum::<f64>() / m);
        let num: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let den: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
        2f64.powf(num / den)
    };
    if fit_points.len() > 2 {
        scaling.push(format!("least squares over {:.0}–{:.0} bp: continuum residual ×{:.2}, equilibrium direct ×{:.2}, NK ×{:.2} (warm ×{:.2}) per doubling",
            fit_points[0].0, fit_points.last().unwrap().0, slope(0), slope(1), slope(2), slope(3)));
    }
    for l in ratios {
        let _ = writeln!(out, "{l}");
    }
    let _ = writeln!(out, "{}", scaling.join("; "));
    std::fs::write(dir.join("rod.csv"), &csv).unwrap();
    let colours = [
        plotters::style::RGBColor(0, 90, 200),
        plotters::style::RGBColor(200, 60, 0),
        plotters::style::RGBColor(120, 120, 120),
        plotters::style::RGBColor(0, 150, 80),
        plotters::style::RGBColor(150, 0, 150),
    ];
    let plot: Vec<_> = series
        .into_iter()
        .zip(colours)
        .filter(|((_, v), _)| !v.is_empty())
        .map(|((name, v), c)| (name, v, c))
        .collect();
    plot::line_plot(
        &dir.join("rod_residual.svg"),
        "time per residual (DNA rod, 0.1 M)",
        "log10 base pairs",
        "log10 ms",
        &plot,
    )
    .unwrap();
    let plot: Vec<_> = eq_series
        .into_iter()
        .zip(colours)
        .filter(|((_, v), _)| !v.is_empty())
        .map(|((name, v), c)| (name, v, c))
        .collect();
    plot::line_plot(
        &dir.join("rod_equilibrium.svg"),
        "time per equilibrium (DNA rod, 0.1 M)",
        "log10 base pairs",
        "log10 ms",
        &plot,
    )
    .unwrap();
}

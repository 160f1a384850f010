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
//! straight state at φ = 2 rad: time per residual (1 and 2 threads) and per
//! Jacobian with the cutoff (1e-4) and cell-list pair list, the residual
//! with every far pair as the baseline, and time per equilibrium (Newton at
//! fixed φ from a 1e-3 perturbation, the sparse LU's symbolic analysis
//! reused); target/bench/charged/rod.csv.

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
        ([rho * cs, rho * sn, c * th], [-rho * sn / w, rho * cs / w, c / w], [-rho * cs / (w * w), -rho * sn / (w * w), 0.0])
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
    let _ = writeln!(out, "{:>6} {:>12} {:>10} {:>12} {:>10} {:>12} {:>10} {:>11} {:>11}", "kbp", "all pairs", "", "cutoff", "error", "continuum", "error", "all/cont", "cut/cont");
    let mut csv = String::from("bp,all_pairs_s,cutoff_s,cutoff_error,continuum_s,continuum_error\n");
    let mut prev: Option<(f64, Duration)> = None;
    let mut scaling = vec![];
    for bp in [1000usize, 3000, 10000] {
        let curve = Superhelix { l: 0.34 * bp as f64, panel: 8.0 };
        let fine = Superhelix { l: 0.34 * bp as f64, panel: 2.0 };
        let (r, qs, s) = discrete::base_pairs(&curve, &q, 0.34).unwrap();
        let (all, t_all) = time(3, || discrete::energy(&r, &qs, &s, &scr, None));
        let ((cut, _), t_cut) = time(3, || discrete::energy_cutoff(&r, &qs, &s, &scr, rc, None, 1));
        let reference = energy(&fine, &q, &scr, &EnergyQuadrature { delta: 1.5, order: 12, cutoff: None }).unwrap().total;
        let (cont, t_cont) = time(3, || energy(&curve, &q, &scr, &EnergyQuadrature { delta: 4.0, order: 3, cutoff: Some(rc) }).unwrap().total);
        let (e_cut, e_cont) = ((all - cut).abs() / all, (reference - cont).abs() / reference);
        let _ = writeln!(out, "{:>6} {:>10.2}ms {:>10} {:>10.2}ms {:>10.1e} {:>10.2}ms {:>10.1e} {:>11.1} {:>11.2}", bp as f64 / 1000.0, t_all.as_secs_f64() * 1e3, "", t_cut.as_secs_f64() * 1e3, e_cut, t_cont.as_secs_f64() * 1e3, e_cont,
            t_all.as_secs_f64() / t_cont.as_secs_f64(), t_cut.as_secs_f64() / t_cont.as_secs_f64());
        let _ = writeln!(csv, "{bp},{},{},{e_cut},{},{e_cont}", t_all.as_secs_f64(), t_cut.as_secs_f64(), t_cont.as_secs_f64());
        if let Some((pbp, pt)) = prev {
            let doublings = (bp as f64 / pbp).log2();
            scaling.push(format!("{:.0} → {bp} bp: continuum ×{:.2} per doubling", pbp, (t_cont.as_secs_f64() / pt.as_secs_f64()).powf(1.0 / doublings)));
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

fn rod_table(out: &mut String, dir: &std::path::Path) {
    use rodkit::continuation::newton::{continue_newton, Start};
    use rodkit::continuation::{Options, Problem};
    use rodkit::electrostatics::rod::ChargedRod;
    use rodkit::electrostatics::supercoil::{DnaScene, follow};
    let _ = writeln!(out, "\ncoupled rod (DNA scene, h = 3.4 nm, Gauss(2), straight state at φ = 2): medians of 5");
    let _ = writeln!(out, "{:>6} {:>7} {:>7} {:>11} {:>11} {:>11} {:>13} {:>9} {:>13}", "kbp", "n", "pairs", "residual", "2 threads", "Jacobian", "all-pairs res", "all/cut", "equilibrium");
    let mut csv = String::from("bp,n,pairs,residual_s,residual_2threads_s,jacobian_s,all_pairs_residual_s,equilibrium_s\n");
    let mut prev: Option<(f64, f64)> = None;
    let mut scaling = vec![];
    for bp in [1000usize, 3000, 10000] {
        let scene = DnaScene { base_pairs: bp, ..Default::default() };
        let rod = scene.rod(bp / 10, 2).unwrap();
        let mut charge = scene.charge();
        charge.cutoff_tolerance = Some(1e-4);
        let opts = Options { target_lambda: Some(2.0), residual_tol: 1e-10, initial_step: 2.0, max_step: 2.0, ..Default::default() };
        let b = follow(&rod, &charge, Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true }, None, &opts, |_| true).unwrap();
        let x = b.states.last().unwrap().clone();
        let mut p = ChargedRod::new(&rod, &charge, None, &x).unwrap();
        let n = p.dim();
        let mut r = vec![0.0; n];
        let (_, t_res) = time(5, || p.residual(&x, 2.0, &mut r));
        let mut jx = vec![0.0; p.pattern().nnz()];
        let mut jl = vec![0.0; n];
        let (_, t_jac) = time(5, || p.jacobian(&x, 2.0, &mut jx, &mut jl));
        let mut c2 = charge.clone();
        c2.threads = 2;
        let mut p2 = ChargedRod::new(&rod, &c2, None, &x).unwrap();
        let (_, t_res2) = time(5, || p2.residual(&x, 2.0, &mut r));
        let t_all = if bp <= 3000 {
            let mut call = charge.clone();
            call.cutoff_tolerance = None;
            let mut pa = ChargedRod::new(&rod, &call, None, &x).unwrap();
            Some(time(3, || pa.residual(&x, 2.0, &mut r)).1)
        } else {
            None
        };
        let (us, _) = p.unknown_scales();
        let start: Vec<f64> = x.iter().zip(&us).enumerate().map(|(i, (v, s))| v + 1e-3 * s * (((i * 7919) % 97) as f64 / 48.5 - 1.0)).collect();
        let eq_opts = Options { residual_tol: 1e-10, max_steps: 0, ..Default::default() };
        let (_, t_eq) = time(3, || continue_newton(&mut p, Start::Point { x: start.clone(), lambda: 2.0, increasing: true }, &eq_opts, |_, _| vec![], |_| true).unwrap());
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        let _ = writeln!(out, "{:>6} {:>7} {:>7} {:>9.3}ms {:>9.3}ms {:>9.3}ms {:>11} {:>9} {:>11.1}ms", bp as f64 / 1000.0, n, p.pairs(), ms(t_res), ms(t_res2), ms(t_jac),
            t_all.map_or("-".into(), |t| format!("{:.3}ms", ms(t))), t_all.map_or("-".into(), |t| format!("{:.1}", t.as_secs_f64() / t_res.as_secs_f64())), ms(t_eq));
        let _ = writeln!(csv, "{bp},{n},{},{},{},{},{},{}", p.pairs(), t_res.as_secs_f64(), t_res2.as_secs_f64(), t_jac.as_secs_f64(), t_all.map_or(f64::NAN, |t| t.as_secs_f64()), t_eq.as_secs_f64());
        if let Some((pbp, pt)) = prev {
            let d = (bp as f64 / pbp).log2();
            scaling.push(format!("{:.0} → {bp} bp: residual ×{:.2}, equilibrium ×{:.2} per doubling", pbp, (t_res.as_secs_f64() / pt).powf(1.0 / d), 0.0));
        }
        prev = Some((bp as f64, t_res.as_secs_f64()));
        let _ = t_eq;
    }
    let _ = writeln!(out, "{}", scaling.join("; ").replace(", equilibrium ×0.00 per doubling", " per doubling"));
    std::fs::write(dir.join("rod.csv"), &csv).unwrap();
}

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
//! energy.csv}. The coupled rod (time per residual and per equilibrium)
//! is not there yet.

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
    print!("{out}");
    std::fs::write(dir.join("report.txt"), &out).unwrap();
    std::fs::write(dir.join("energy.csv"), &csv).unwrap();
}

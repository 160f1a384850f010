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
//! Second table, the coupled rod (src/charged/rod.rs): the DNA scene
//! (1 pN, 0.1 M, ν = 1/l_B) on 3.4 nm elements of Gauss(2), twisted
//! straight state at φ = 2, with the continuum line charge and with the
//! discrete base-pair charges on the same rod (RodCharge::base_pairs),
//! each with a cutoff meeting 1e-4 force error on a superhelix against its
//! own every-pair reference: time per residual (continuum also with 2
//! threads), per Jacobian and per equilibrium (a Newton corrector φ = 2 →
//! 2.1) by the direct sparse Newton and by Newton–Krylov with the rod-band
//! preconditioner (src/nonlinear/krylov.rs; cold and warm), the
//! all-pairs base-pair baseline (residual; equilibria: direct with the
//! cutoff model's Jacobian, Newton–Krylov on its own residual) and the
//! continuum's every-pair residual, as ratios, at 1, 3 and 10 kbp, and the
//! continuum alone at 30 kbp (scaling past the cache step at 10 kbp);
//! per-doubling factors per segment and by least squares;
//! target/bench/charged/{rod.csv, rod_residual.svg, rod_equilibrium.svg}.

#[path = "support/plot.rs"]
mod plot;
#[path = "support/timing.rs"]
mod timing;
use timing::{median, ms};

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

/// The median time of `reps` calls of f, and its last result. The call
/// goes through `black_box` both ways: the pair sums are pure (exp, sqrt),
/// and without it the compiler moved the all-pairs energy out of the timed
/// region (the 2026-11-25 figures of 0.37 / 3.7 / 35 ms at 1 / 3 / 10 kbp
/// were ~13× too fast; the function itself takes 4–7 / 47–51 ms there).
fn time<T>(reps: usize, mut f: impl FnMut() -> T) -> (T, Duration) {
    let mut times = vec![];
    let mut last = None;
    for _ in 0..reps {
        let call = std::hint::black_box(&mut f);
        let t = Instant::now();
        last = Some(std::hint::black_box(call()));
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
                put(rod.stage_offset(e, j), (e as f64 + c[j]) * h);
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

/// Seconds of an optional duration (NaN when absent, for the CSV).
fn secs(t: Option<Duration>) -> f64 {
    t.map_or(f64::NAN, |t| t.as_secs_f64())
}

/// One rod of the DNA scene at a length: its equilibrium at φ = 2 (the
/// start of every timed equilibrium), the superhelix state (the force
/// errors') and the solver options of the timings.
struct RodCase {
    rod: rodkit::rod::model::Rod,
    x: Vec<f64>,
    xs: Vec<f64>,
    eq_opts: rodkit::continuation::Options,
    nk_opts: rodkit::nonlinear::krylov::KrylovOptions,
}

/// Newton–Krylov timings: cold, warm, GMRES iterations.
type NkTimes = (Duration, Duration, usize);

/// What [`RodCase::measure`] found for one charge model.
struct Measured {
    n: usize,
    residual: Duration,
    jacobian: Option<Duration>,
    /// The direct sparse Newton's equilibrium.
    direct: Option<Duration>,
    nk: Option<NkTimes>,
    force_error: Option<f64>,
    problem: rodkit::charged::rod::ChargedRod,
}

impl RodCase {
    /// The DNA scene's rod of `bp` base pairs on 3.4 nm elements of
    /// Gauss(2), followed by the continuum `charge` from the straight state
    /// to φ = 2.
    fn new(scene: &rodkit::charged::dna::DnaScene, bp: usize, charge: &rodkit::charged::rod::RodCharge) -> Self {
        use rodkit::charged::branch::follow;
        use rodkit::continuation::newton::Start;
        use rodkit::continuation::Options;
        use rodkit::nonlinear::krylov::KrylovOptions;
        let rod = scene.rod(bp / 10, 2).unwrap();
        let opts = Options {
            target_lambda: Some(2.0),
            residual_tol: 1e-10,
            initial_step: 2.0,
            max_step: 2.0,
            ..Default::default()
        };
        let b = follow(
            &rod,
            charge,
            Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true },
            None,
            &opts,
            |_| true,
        )
        .unwrap();
        let x = b.states.last().unwrap().clone();
        let xs = superhelix_state(&rod);
        let eq_opts = Options { residual_tol: 1e-8, max_steps: 0, ..Default::default() };
        let nk_opts = KrylovOptions { residual_tol: 1e-8, ..Default::default() };
        RodCase { rod, x, xs, eq_opts, nk_opts }
    }

    /// Newton–Krylov equilibria of `p` at φ = 2.1 from x (preconditioner
    /// from `source` if given, else from `p`): cold (everything built in
    /// the timing) and warm (the band LU kept).
    fn newton_krylov_times(
        &self,
        p: &mut dyn rodkit::continuation::Problem,
        mut source: Option<&mut rodkit::charged::rod::ChargedRod>,
        band: usize,
    ) -> NkTimes {
        use rodkit::continuation::equilibrium::newton_krylov;
        use rodkit::continuation::Problem;
        use rodkit::nonlinear::krylov::BandPreconditioner;
        // The preconditioner is built on its source's pattern.
        let pattern = source.as_deref().map_or_else(|| p.pattern().clone(), |s| s.pattern().clone());
        // Medians of 9 (3 for the all-pairs rod, seconds per solve): the
        // cold solve's first band LU faults in fresh memory, and its time
        // moved by ±15 % between runs of 5 at 10 kbp.
        let reps = if source.is_some() { 3 } else { 9 };
        let mut solve = |pre: &mut BandPreconditioner| {
            let mut y = self.x.clone();
            newton_krylov(p, source.as_deref_mut().map(|s| s as &mut dyn Problem), pre, &mut y, 2.1, &self.nk_opts)
                .unwrap()
        };
        let (rep, cold) = time(reps, || solve(&mut BandPreconditioner::new(&pattern, band).unwrap()));
        let mut pre = BandPreconditioner::new(&pattern, band).unwrap();
        solve(&mut pre);
        let (_, warm) = time(reps, || solve(&mut pre));
        (cold, warm, rep.linear_iterations)
    }

    /// The direct sparse Newton's equilibrium of `p` at φ = 2.1 from x
    /// (medians of 3).
    fn direct_time<P: rodkit::continuation::Problem + ?Sized>(&self, p: &mut P, what: &str) -> Duration {
        use rodkit::continuation::newton::{continue_newton, Start};
        time(3, || {
            let b = continue_newton(
                p,
                Start::Point { x: self.x.clone(), lambda: 2.1, increasing: true },
                &self.eq_opts,
                |_, _| vec![],
                |_| true,
            )
            .unwrap();
            assert!(!b.records.is_empty(), "no {what}");
        })
        .1
    }

    /// Times (residual, Jacobian and, with `full`, the equilibria) and the
    /// force error against `every` (the same model with every pair).
    fn measure(
        &self,
        model: &rodkit::charged::rod::RodCharge,
        every: Option<&rodkit::charged::rod::RodCharge>,
        full: bool,
    ) -> Measured {
        use rodkit::charged::rod::ChargedRod;
        use rodkit::continuation::Problem;
        let x = &self.x;
        let mut p = ChargedRod::new(&self.rod, model, None, x).unwrap();
        let n = p.dim();
        let mut r = vec![0.0; n];
        let (_, t_res) = time(21, || p.residual(x, 2.0, &mut r));
        let mut jx = vec![0.0; p.pattern().nnz()];
        let mut jl = vec![0.0; n];
        let t_jac = time(9, || p.jacobian(x, 2.0, &mut jx, &mut jl)).1;
        if !full {
            return Measured {
                n,
                residual: t_res,
                jacobian: Some(t_jac),
                direct: None,
                nk: None,
                force_error: None,
                problem: p,
            };
        }
        let t_eq = self.direct_time(&mut p, "equilibrium");
        let band = p.local_band();
        let t_nk = self.newton_krylov_times(&mut p, None, band);
        let f_err = every.map(|e| self.force_error(model, e));
        Measured {
            n,
            residual: t_res,
            jacobian: Some(t_jac),
            direct: Some(t_eq),
            nk: Some(t_nk),
            force_error: f_err,
            problem: p,
        }
    }

    /// The force error of `model` against `every` on the superhelix: max
    /// |p − p_ref| over the stage force densities relative to max |p_ref|
    /// (base pairs) or to the continuum's whole electrostatic force density
    /// (its p is the far zone only).
    fn force_error(&self, model: &rodkit::charged::rod::RodCharge, every: &rodkit::charged::rod::RodCharge) -> f64 {
        use rodkit::charged::rod::ChargedRod;
        let (rod, xs) = (&self.rod, &self.xs);
        let mut ps = ChargedRod::new(rod, model, None, xs).unwrap();
        let mut pe = ChargedRod::new(rod, every, None, xs).unwrap();
        let (fs, fe) = (ps.force_densities(xs), pe.force_densities(xs));
        if model.base_pairs.is_some() {
            return force_error(&fs, &fe);
        }
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

    /// The preconditioner's rebuild alone (Jacobian + band LU) on `p`, on
    /// memory already touched by the solves before it.
    fn refresh_time(&self, p: &mut rodkit::charged::rod::ChargedRod) -> Duration {
        use rodkit::continuation::Problem;
        use rodkit::nonlinear::krylov::BandPreconditioner;
        let mut pre = BandPreconditioner::new(p.pattern(), p.local_band()).unwrap();
        let mut at = rodkit::continuation::equilibrium::AtFixed::new(p, 2.1);
        pre.refresh(&mut at, &self.x).unwrap();
        time(9, || pre.refresh(&mut at, &self.x).unwrap()).1
    }

    /// The all-pairs base-pair model (`every_bp`): its residual, its direct
    /// equilibrium with the cutoff model's Jacobian (`cut`) and its
    /// Newton–Krylov equilibrium preconditioned from `cut`.
    fn all_pairs(
        &self,
        every_bp: &rodkit::charged::rod::RodCharge,
        cut: &mut rodkit::charged::rod::ChargedRod,
    ) -> (Duration, Duration, NkTimes) {
        use rodkit::charged::rod::ChargedRod;
        use rodkit::continuation::Problem;
        let x = &self.x;
        let mut pa = ChargedRod::new(&self.rod, every_bp, None, x).unwrap();
        let mut r = vec![0.0; pa.dim()];
        let (_, a_res) = time(3, || pa.residual(x, 2.0, &mut r));
        let a_eq = self.direct_time(&mut Truncated { full: &mut pa, cut: &mut *cut }, "all-pairs equilibrium");
        let band = cut.local_band();
        let a_nk = self.newton_krylov_times(&mut pa, Some(cut), band);
        (a_res, a_eq, a_nk)
    }

    /// The continuum's residual with every pair (medians of 3).
    fn every_pair_residual(&self, every: &rodkit::charged::rod::RodCharge) -> Duration {
        use rodkit::charged::rod::ChargedRod;
        use rodkit::continuation::Problem;
        let mut pe = ChargedRod::new(&self.rod, every, None, &self.x).unwrap();
        let mut r = vec![0.0; pe.dim()];
        time(3, || pe.residual(&self.x, 2.0, &mut r)).1
    }
}

/// Everything measured at one length.
struct LengthRow {
    bp: usize,
    /// The continuum with the cutoff (one thread, then the residual and
    /// Jacobian on two).
    continuum: Measured,
    continuum_two: (Duration, Option<Duration>),
    refresh: Duration,
    /// The base pairs with the cutoff (≤ 10 kbp), and on two threads.
    base_pairs: Option<Measured>,
    base_pairs_two: Option<(Duration, Duration)>,
    /// All-pairs base pairs (≤ 3 kbp): residual, direct, Newton–Krylov.
    all_pairs: Option<(Duration, Duration, NkTimes)>,
    /// The continuum's residual with every pair (≤ 3 kbp).
    every_pair: Option<Duration>,
}

/// The measurements of the rod table at `bp` base pairs, in the order they
/// were always taken (cache and memory state carry from one to the next).
fn measure_length(bp: usize) -> LengthRow {
    use rodkit::charged::dna::DnaScene;
    let scene = DnaScene { base_pairs: bp, ..Default::default() };
    let with_discrete = bp <= 10_000;
    // Cutoffs meeting 1e-4 relative force error on the superhelix: the
    // continuum needs a tighter energy tolerance (3e-5: its force error
    // was 1.9e-4 at 1e-4) than the base pairs (1.4e-5 at 1e-4).
    let mut charge = scene.charge();
    charge.cutoff_tolerance = Some(3e-5);
    let mut discrete = charge.clone();
    discrete.cutoff_tolerance = Some(1e-4);
    discrete.base_pairs = Some(0.34);
    let case = RodCase::new(&scene, bp, &charge);
    let small = bp <= 3000;
    let mut every = charge.clone();
    every.cutoff_tolerance = None;
    let mut every_bp = discrete.clone();
    every_bp.cutoff_tolerance = None;
    let mut continuum = case.measure(&charge, small.then_some(&every), true);
    // Linear in the length, so the cold solve's excess at ≥ 10 kbp is the
    // first touch of its memory.
    let refresh = case.refresh_time(&mut continuum.problem);
    let mut two = charge.clone();
    two.threads = 2;
    let c2 = case.measure(&two, None, false);
    let mut base_pairs = with_discrete.then(|| case.measure(&discrete, small.then_some(&every_bp), true));
    let base_pairs_two = with_discrete.then(|| {
        let mut two = discrete.clone();
        two.threads = 2;
        let m = case.measure(&two, None, false);
        (m.residual, m.jacobian.unwrap())
    });
    let all_pairs = small.then(|| case.all_pairs(&every_bp, &mut base_pairs.as_mut().unwrap().problem));
    let every_pair = small.then(|| case.every_pair_residual(&every));
    LengthRow {
        bp,
        continuum,
        continuum_two: (c2.residual, c2.jacobian),
        refresh,
        base_pairs,
        base_pairs_two,
        all_pairs,
        every_pair,
    }
}

fn fmt_t(t: Option<Duration>) -> String {
    t.map_or("-".to_string(), |t| format!("{:.2}ms", ms(t)))
}

/// The columns of one model's line of the rod table ("-" where absent).
struct Columns {
    residual: Option<Duration>,
    jacobian: Option<Duration>,
    direct: Option<Duration>,
    nk: Option<NkTimes>,
    force_error: Option<f64>,
}

impl Measured {
    fn columns(&self) -> Columns {
        Columns {
            residual: Some(self.residual),
            jacobian: self.jacobian,
            direct: self.direct,
            nk: self.nk,
            force_error: self.force_error,
        }
    }
}

/// One model's line of the rod table.
fn model_row(out: &mut String, kbp: String, n: usize, name: &str, m: Columns) {
    let Columns { residual: res, jacobian: jac, direct: eq, nk, force_error: err } = m;
    let fmt_e = |e: Option<f64>| e.map_or("-".to_string(), |e| format!("{e:.1e}"));
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
}

/// The table's lines for one length: one per model, then the two-thread
/// timings.
fn write_rows(out: &mut String, row: &LengthRow) {
    let (c, n) = (&row.continuum, row.continuum.n);
    let kbp = format!("{}", row.bp as f64 / 1000.0);
    model_row(out, kbp, n, "continuum, cutoff", c.columns());
    if let Some(d) = &row.base_pairs {
        model_row(out, "".into(), n, "base pairs, cutoff", d.columns());
    }
    if let Some((a_res, a_eq, a_nk)) = row.all_pairs {
        let all =
            Columns { residual: Some(a_res), jacobian: None, direct: Some(a_eq), nk: Some(a_nk), force_error: None };
        model_row(out, "".into(), n, "base pairs, all pairs", all);
    }
    let (c_res2, c_jac2) = row.continuum_two;
    let _ = writeln!(
        out,
        "{:>4} {:>6} {:>22} {:>10} {:>10} (2 threads){}",
        "",
        "",
        "continuum, cutoff",
        fmt_t(Some(c_res2)),
        fmt_t(c_jac2),
        row.every_pair.map_or(String::new(), |t| format!(
            "; every pair: residual {} ({:.1}× the cutoff's)",
            fmt_t(Some(t)),
            t.as_secs_f64() / c.residual.as_secs_f64()
        ))
    );
    if let Some((res, jac)) = row.base_pairs_two {
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
}

/// The speed-up ratios at one length, as one line.
fn ratio_line(row: &LengthRow) -> String {
    let r = |a: Duration, b: Duration| a.as_secs_f64() / b.as_secs_f64();
    let c = &row.continuum;
    let (c_res, c_eq, c_nk) = (c.residual, c.direct.unwrap(), c.nk.unwrap());
    let mut line = format!("{:.0} kbp", row.bp as f64 / 1000.0);
    if let Some(d) = &row.base_pairs {
        let d_nk = d.nk.unwrap();
        let _ = write!(
            line,
            ", faster than the cutoff base pairs: residual {:.1}×, equilibrium direct {:.1}×, NK {:.1}× (warm {:.1}×)",
            r(d.residual, c_res),
            r(d.direct.unwrap(), c_eq),
            r(d_nk.0, c_nk.0),
            r(d_nk.1, c_nk.1)
        );
    }
    if let Some((a_res, a_eq, a_nk)) = row.all_pairs {
        let _ = write!(
            line,
            "; than all-pairs base pairs: residual {:.0}×, equilibrium direct {:.1}×, NK {:.0}×",
            r(a_res, c_res),
            r(a_eq, c_eq),
            r(a_nk.0, c_nk.0)
        );
    }
    let _ = write!(line, "; continuum NK vs direct {:.1}× faster (warm {:.1}×)", r(c_eq, c_nk.0), r(c_eq, c_nk.1));
    let _ = write!(
        line,
        "; preconditioner refresh (Jacobian + band LU) {:.2} ms = {:.0} ns per unknown",
        ms(row.refresh),
        row.refresh.as_secs_f64() * 1e9 / c.n as f64
    );
    line
}

/// The CSV lines of one length.
fn write_csv(csv: &mut String, row: &LengthRow) {
    let (bp, c) = (row.bp, &row.continuum);
    let n = c.n;
    let c_nk = c.nk.unwrap();
    let (c_res2, c_jac2) = row.continuum_two;
    let _ = writeln!(
        csv,
        "{bp},{n},continuum_cutoff,{},{},{},{},{},{},{},{},{}",
        c.residual.as_secs_f64(),
        secs(c.jacobian),
        secs(c.direct),
        c_nk.0.as_secs_f64(),
        c_nk.1.as_secs_f64(),
        c_nk.2,
        c.force_error.unwrap_or(f64::NAN),
        c_res2.as_secs_f64(),
        secs(c_jac2)
    );
    let _ = writeln!(csv, "{bp},{n},continuum_every_pair,{},,,,,,,,", secs(row.every_pair));
    if let Some(d) = &row.base_pairs {
        let d_nk = d.nk.unwrap();
        let (res2, jac2) = row.base_pairs_two.map_or((f64::NAN, f64::NAN), |(r, j)| (r.as_secs_f64(), j.as_secs_f64()));
        let _ = writeln!(
            csv,
            "{bp},{n},base_pairs_cutoff,{},{},{},{},{},{},{},{res2},{jac2}",
            d.residual.as_secs_f64(),
            secs(d.jacobian),
            secs(d.direct),
            d_nk.0.as_secs_f64(),
            d_nk.1.as_secs_f64(),
            d_nk.2,
            d.force_error.unwrap_or(f64::NAN)
        );
    }
    if let Some((a_res, a_eq, a_nk)) = row.all_pairs {
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
}

/// A named plot series of (log10 base pairs, log10 ms).
type LogSeries = (&'static str, Vec<(f64, f64)>);

/// Adds one length's points to the residual and equilibrium plots.
fn push_points(series: &mut [LogSeries], eq_series: &mut [LogSeries], row: &LengthRow) {
    let lb = (row.bp as f64).log10();
    let c = &row.continuum;
    series[0].1.push((lb, ms(c.residual).log10()));
    eq_series[0].1.push((lb, ms(c.nk.unwrap().0).log10()));
    eq_series[3].1.push((lb, ms(c.direct.unwrap()).log10()));
    if let Some(d) = &row.base_pairs {
        series[1].1.push((lb, ms(d.residual).log10()));
        eq_series[1].1.push((lb, ms(d.nk.unwrap().0).log10()));
        eq_series[4].1.push((lb, ms(d.direct.unwrap()).log10()));
    }
    if let Some((a_res, _, a_nk)) = row.all_pairs {
        series[2].1.push((lb, ms(a_res).log10()));
        eq_series[2].1.push((lb, ms(a_nk.0).log10()));
    }
    if let Some(t) = row.every_pair {
        series[3].1.push((lb, ms(t).log10()));
    }
}

/// The continuum's (residual, direct, NK cold, NK warm) seconds at each
/// length, and the per-doubling factors: per segment, and by least squares
/// of log t against log L over all lengths (less sensitive than one segment
/// to a single extra Newton iteration or a noisy run).
fn scaling_lines(fit_points: &[(f64, [f64; 4])]) -> Vec<String> {
    let mut scaling = vec![];
    for w in fit_points.windows(2) {
        let ((pbp, [pr, pe, pn, pw]), (bp, [cr, ce, cn, cw])) = (w[0], w[1]);
        let d = (bp / pbp).log2();
        scaling.push(format!("{pbp:.0} → {bp:.0} bp: continuum residual ×{:.2}, equilibrium direct ×{:.2}, NK ×{:.2} (warm ×{:.2}) per doubling", (cr / pr).powf(1.0 / d), (ce / pe).powf(1.0 / d), (cn / pn).powf(1.0 / d), (cw / pw).powf(1.0 / d)));
    }
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
    scaling
}

/// The two plots of the rod table: time per residual and per equilibrium.
fn rod_plots(dir: &std::path::Path, series: Vec<LogSeries>, eq_series: Vec<LogSeries>) {
    let colours = [
        plotters::style::RGBColor(0, 90, 200),
        plotters::style::RGBColor(200, 60, 0),
        plotters::style::RGBColor(120, 120, 120),
        plotters::style::RGBColor(0, 150, 80),
        plotters::style::RGBColor(150, 0, 150),
    ];
    for (file, title, series) in [
        ("rod_residual.svg", "time per residual (DNA rod, 0.1 M)", series),
        ("rod_equilibrium.svg", "time per equilibrium (DNA rod, 0.1 M)", eq_series),
    ] {
        let plot: Vec<_> = series
            .into_iter()
            .zip(colours)
            .filter(|((_, v), _)| !v.is_empty())
            .map(|((name, v), c)| (name, v, c))
            .collect();
        plot::line_plot(&dir.join(file), title, "log10 base pairs", "log10 ms", &plot).unwrap();
    }
}

/// The coupled-rod table (module docs): its header, one block of lines per
/// length, the ratios and scaling, rod.csv and the two plots.
fn rod_table(out: &mut String, dir: &std::path::Path) {
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
    let mut series: Vec<LogSeries> = vec![
        ("continuum, cutoff", vec![]),
        ("base pairs, cutoff", vec![]),
        ("base pairs, all pairs", vec![]),
        ("continuum, every pair", vec![]),
    ];
    let mut eq_series: Vec<LogSeries> = vec![
        ("continuum, NK", vec![]),
        ("base pairs, NK", vec![]),
        ("base pairs all pairs, NK", vec![]),
        ("continuum, direct", vec![]),
        ("base pairs, direct", vec![]),
    ];
    let mut ratios = vec![];
    let mut fit_points: Vec<(f64, [f64; 4])> = vec![];
    // 30 kbp: the continuum only (the base pairs' direct equilibrium alone
    // would take ~15 s), to see the scaling past the 3 → 10 kbp step where
    // the Jacobian and band LU (≈ 36 MB at 10 kbp) outgrow the 32 MB L3.
    for bp in [1000usize, 3000, 10000, 30000] {
        let row = measure_length(bp);
        write_rows(out, &row);
        ratios.push(ratio_line(&row));
        write_csv(&mut csv, &row);
        push_points(&mut series, &mut eq_series, &row);
        let c = &row.continuum;
        let (c_nk, c_eq) = (c.nk.unwrap(), secs(c.direct));
        fit_points.push((bp as f64, [c.residual.as_secs_f64(), c_eq, c_nk.0.as_secs_f64(), c_nk.1.as_secs_f64()]));
    }
    for l in ratios {
        let _ = writeln!(out, "{l}");
    }
    let _ = writeln!(out, "{}", scaling_lines(&fit_points).join("; "));
    std::fs::write(dir.join("rod.csv"), &csv).unwrap();
    rod_plots(dir, series, eq_series);
}

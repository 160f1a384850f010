//! The generic continuation engines on small polynomial systems with known
//! branches (references: their closed forms).

use rodkit::continuation::anm::{continue_anm, AnmOptions};
use rodkit::continuation::newton::{continue_newton, Start};
use rodkit::continuation::system::{AssembledSystem, Block, Slot};
use rodkit::continuation::{Options, Problem, SeriesProblem, Stop};
use rodkit::linalg::sparse::Pattern;
use rodkit::taylor::{Scalar, Tape};
use std::sync::Arc;

/// R1 = x1² + Λ² − 1, R2 = x2 − x1Λ (cubic term through x2's equation kept
/// quadratic; a third equation adds a cubic): R3 = x3 − x1·x2·Λ. Branch: the
/// unit circle in (x1, Λ), with a fold at Λ = 1 where x1 = 0.
fn circle() -> AssembledSystem {
    fn kernel<T: Scalar>(v: &[T]) -> Vec<T> {
        let (x1, x2, x3, l) = (v[0], v[1], v[2], v[3]);
        vec![x1 * x1 + l * l - 1.0, x2 - x1 * l, x3 - x1 * x2 * l]
    }
    let tape = Arc::new(Tape::record(4, kernel));
    let block =
        Block::new(tape, vec![Slot::Unknown(0), Slot::Unknown(1), Slot::Unknown(2), Slot::Lambda], vec![0, 1, 2]);
    AssembledSystem::new(3, vec![block])
}

fn on_circle(x: &[f64], l: f64) -> f64 {
    (x[0] * x[0] + l * l - 1.0).abs().max((x[1] - x[0] * l).abs()).max((x[2] - x[0] * x[0] * l * l).abs())
}

/// A system whose residual's first entry turns NaN wherever `poison(Λ)`
/// says (the engines' handling of a failed evaluation).
struct Poisoned<F: FnMut(f64) -> bool>(AssembledSystem, F);

impl<F: FnMut(f64) -> bool> Problem for Poisoned<F> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn pattern(&self) -> &Pattern {
        self.0.pattern()
    }
    fn residual(&mut self, x: &[f64], l: f64, r: &mut [f64]) {
        self.0.residual(x, l, r);
        if (self.1)(l) {
            r[0] = f64::NAN;
        }
    }
    fn jacobian(&mut self, x: &[f64], l: f64, jx: &mut [f64], jl: &mut [f64]) {
        self.0.jacobian(x, l, jx, jl);
    }
}

impl<F: FnMut(f64) -> bool> SeriesProblem for Poisoned<F> {
    fn series_begin(&mut self, x0: &[f64], lambda0: f64, max_order: usize) {
        self.0.series_begin(x0, lambda0, max_order)
    }
    fn series_order(&mut self, p: usize, xp: &[f64], lambda_p: f64, out: &mut [f64]) {
        self.0.series_order(p, xp, lambda_p, out)
    }
}

/// Options that take the circle from (1, 0) past its fold at Λ = 1 and
/// back below Λ = −0.5.
fn through_the_fold() -> Options {
    Options {
        max_steps: 400,
        residual_tol: 1e-12,
        initial_step: 0.05,
        max_step: 0.2,
        lambda_range: (-0.5, 2.0),
        ..Default::default()
    }
}

#[test]
fn both_engines_pass_the_fold_and_flag_it() {
    let opts = through_the_fold();
    let start = || Start::Point { x: vec![1.0, 0.0, 0.0], lambda: 0.0, increasing: true };
    let mut sys = circle();
    assert_eq!(sys.degree(), 3);
    let newton = continue_newton(&mut sys, start(), &opts, |x, _| x.to_vec(), |_| true).unwrap();
    let mut sys = circle();
    let anm = continue_anm(
        &mut sys,
        start(),
        &opts,
        &AnmOptions { order: 20, epsilon: 1e-10, pade: false },
        |x, _| x.to_vec(),
        |_| true,
    )
    .unwrap();
    for (name, b) in [("newton", &newton), ("anm", &anm)] {
        assert_eq!(b.stop, Stop::LambdaRange, "{name}");
        // Past the fold: x1 < 0 and Λ back below 0.
        let last = b.records.last().unwrap();
        assert!(
            last.outputs[0] < -0.5 && last.lambda < 0.0,
            "{name}: ended at x1 {} Λ {}",
            last.outputs[0],
            last.lambda
        );
        for r in &b.records {
            assert!(on_circle(&r.outputs, r.lambda) < 1e-11, "{name}: off the branch at Λ {}", r.lambda);
            assert!(r.residual <= 1e-12);
        }
        // det R_x = 2x1 (times 1): flips once, at the fold; the bordered
        // determinant does not (a fold is no bifurcation).
        let flips = b.records.windows(2).filter(|w| w[0].det_sign != w[1].det_sign).count();
        let bflips = b.records.windows(2).filter(|w| w[0].bordered_det_sign != w[1].bordered_det_sign).count();
        assert_eq!((flips, bflips), (1, 0), "{name}");
        let max_l = b.records.iter().map(|r| r.lambda).fold(f64::MIN, f64::max);
        assert!(max_l > 0.95 && max_l <= 1.0 + 1e-12, "{name}: {max_l}");
    }
    // The ANM covers the same arc in far fewer factorisations.
    println!("newton: {:?}\nanm: {:?}", newton.counts, anm.counts);
    assert!(anm.counts.factorisations * 3 < newton.counts.factorisations, "{:?} vs {:?}", anm.counts, newton.counts);
}

#[test]
fn target_lambda_is_hit_exactly_and_resume_continues() {
    let opts = Options {
        target_lambda: Some(0.6),
        residual_tol: 1e-12,
        initial_step: 0.05,
        max_step: 0.3,
        ..Default::default()
    };
    for engine in ["newton", "anm"] {
        let mut sys = circle();
        let start = Start::Point { x: vec![1.0, 0.0, 0.0], lambda: 0.0, increasing: true };
        let b = if engine == "newton" {
            continue_newton(&mut sys, start, &opts, |x, _| x.to_vec(), |_| true).unwrap()
        } else {
            continue_anm(&mut sys, start, &opts, &AnmOptions::default(), |x, _| x.to_vec(), |_| true).unwrap()
        };
        assert_eq!(b.stop, Stop::Target, "{engine}");
        let last = b.records.last().unwrap();
        assert_eq!(last.lambda, 0.6, "{engine}");
        assert!((last.outputs[0] - 0.8).abs() < 1e-12, "{engine}: x1 = {}", last.outputs[0]);
        // Resume towards Λ = 0.9 on the same branch.
        let opts2 = Options { target_lambda: Some(0.9), ..opts.clone() };
        let mut sys = circle();
        let b2 =
            continue_newton(&mut sys, Start::Resume(b.resume.clone()), &opts2, |x, _| x.to_vec(), |_| true).unwrap();
        assert_eq!(b2.stop, Stop::Target);
        assert!((b2.records.last().unwrap().outputs[0] - (1.0f64 - 0.81).sqrt()).abs() < 1e-12);
    }
}

/// Pitchfork R = x(Λ − x²) + 0·…: the trivial branch x = 0 crosses the
/// bifurcation at Λ = 0, where the bordered determinant changes sign and
/// the signed smallest singular value passes through 0 (reference: B = [[Λ, 0], [0, 1]]
/// along x = 0, σ_min = |Λ|).
#[test]
fn bifurcation_flips_the_bordered_determinant() {
    fn kernel<T: Scalar>(v: &[T]) -> Vec<T> {
        let (x, l) = (v[0], v[1]);
        vec![x * l - x * x * x]
    }
    let tape = Arc::new(Tape::record(2, kernel));
    let mut sys = AssembledSystem::new(1, vec![Block::new(tape, vec![Slot::Unknown(0), Slot::Lambda], vec![0])]);
    let opts = Options {
        target_lambda: Some(1.0),
        residual_tol: 1e-13,
        initial_step: 0.1,
        max_step: 0.1,
        track_singular: true,
        ..Default::default()
    };
    let b = continue_newton(
        &mut sys,
        Start::Point { x: vec![0.0], lambda: -1.0, increasing: true },
        &opts,
        |x, _| x.to_vec(),
        |_| true,
    )
    .unwrap();
    let flips: Vec<f64> = b
        .records
        .windows(2)
        .filter(|w| w[0].bordered_det_sign != w[1].bordered_det_sign)
        .map(|w| 0.5 * (w[0].lambda + w[1].lambda))
        .collect();
    assert_eq!(flips.len(), 1);
    assert!(flips[0].abs() < 0.06, "flip near Λ = {}", flips[0]);
    for r in &b.records {
        let s = r.smallest_singular_value.unwrap();
        // An estimate (8 inverse iterations at most, 1e−3 stopping test):
        // good to 1 % where the two singular values are close (|Λ| → 1),
        // sharp near the bifurcation where they separate.
        let exact = r.lambda.abs().min(1.0);
        assert!((s.abs() - exact).abs() < 0.01 * exact.max(1e-3), "σ_min {s} at Λ {}", r.lambda);
        // Signed by the crossing eigenvalue (Λ itself) where it is the smallest.
        if r.lambda.abs() < 0.9 && r.lambda != 0.0 {
            assert_eq!(s.signum(), r.lambda.signum(), "sign at Λ {}", r.lambda);
        }
        // The tangent on x = 0 is [[Λ, 0], [0, 1]]: one negative pivot (Λ)
        // below the bifurcation, none above.
        if r.lambda != 0.0 {
            assert_eq!(r.negative_pivots, Some(if r.lambda < 0.0 { 1 } else { 0 }), "at Λ {}", r.lambda);
        }
    }
}

/// Branch switching at a located (not exactly singular) pitchfork
/// R = y(Λ − 1 − y²), y = x − Λ: the trivial branch x = Λ is followed with
/// detection from Λ = 0, the point located near Λ = 1 (not exactly: R_x and
/// R_Λ are ~1e−10 there, so the bordered matrix factorises and its own
/// tangent is the old branch's), and Start::Switch leaves it along the null
/// direction; both engines then follow y² = Λ − 1 (closed form).
#[test]
fn switch_at_a_located_pitchfork_follows_the_new_branch() {
    use rodkit::continuation::bifurcation::branch_start;
    use rodkit::continuation::Scaling;
    fn kernel<T: Scalar>(v: &[T]) -> Vec<T> {
        let (x, l) = (v[0], v[1]);
        let y = x - l;
        vec![y * (l - 1.0) - y * y * y]
    }
    let tape = Arc::new(Tape::record(2, kernel));
    let mut sys = AssembledSystem::new(1, vec![Block::new(tape, vec![Slot::Unknown(0), Slot::Lambda], vec![0])]);
    let opts = Options {
        target_lambda: Some(2.0),
        residual_tol: 1e-13,
        initial_step: 0.13,
        max_step: 0.13,
        detect_bifurcations: true,
        ..Default::default()
    };
    let b = continue_newton(
        &mut sys,
        Start::Point { x: vec![0.0], lambda: 0.0, increasing: true },
        &opts,
        |x, _| x.to_vec(),
        |_| true,
    )
    .unwrap();
    assert_eq!(b.bifurcations.len(), 1);
    let bif = &b.bifurcations[0];
    assert!((bif.lambda - 1.0).abs() < 1e-9, "located at {}", bif.lambda);
    let scaling = Scaling { x: vec![1.0], lambda: 1.0 };
    let (nx, nl) = &bif.null_vectors[0];
    let start = branch_start(bif, (nx, *nl), 0.05, &scaling);
    let opts = Options { target_lambda: Some(1.5), residual_tol: 1e-13, max_step: 0.1, ..Default::default() };
    let engines: [&dyn Fn(&mut AssembledSystem) -> rodkit::continuation::Branch; 2] =
        [&|s| continue_newton(s, Start::Switch(start.clone()), &opts, |x, _| x.to_vec(), |_| true).unwrap(), &|s| {
            continue_anm(s, Start::Switch(start.clone()), &opts, &AnmOptions::default(), |x, _| x.to_vec(), |_| true)
                .unwrap()
        }];
    for follow in engines {
        let nb = follow(&mut sys);
        assert_eq!(nb.stop, Stop::Target);
        for r in nb.records.iter().filter(|r| r.lambda > 1.0 + 1e-3) {
            let y = r.outputs[0] - r.lambda;
            assert!((y * y - (r.lambda - 1.0)).abs() < 1e-12, "y = {y} at Λ {} (y² = Λ − 1 expected)", r.lambda);
        }
        let last = nb.records.last().unwrap();
        assert!(((last.outputs[0] - 1.5).abs() - 0.5f64.sqrt()).abs() < 1e-12, "{last:?}");
    }
}

/// A residual that turns NaN (Λ > 0.5 here) never passes a tolerance: the
/// branch ends with its valid records (no NaN among them).
#[test]
fn nan_residual_is_never_converged() {
    let mut p = Poisoned(circle(), |l| l > 0.5);
    let opts = Options { max_steps: 100, residual_tol: 1e-12, initial_step: 0.05, max_step: 0.2, ..Default::default() };
    let b = continue_newton(
        &mut p,
        Start::Point { x: vec![1.0, 0.0, 0.0], lambda: 0.0, increasing: true },
        &opts,
        |x, _| x.to_vec(),
        |_| true,
    )
    .unwrap();
    assert_eq!(b.stop, Stop::StepTooSmall);
    assert!(b.records.iter().all(|r| r.residual.is_finite() && r.residual <= 1e-12 && r.lambda <= 0.5));
    assert!(b.records.last().unwrap().lambda > 0.3, "stopped early at {}", b.records.last().unwrap().lambda);
}

/// The Newton engine's variants (issue 18): the Hermite predictor, chord
/// corrections (with the plane's border by Sherman–Morrison), both — each
/// stays on the closed-form branch (the unit circle) through the fold to
/// the same tolerance as the plain engine; the Hermite predictor's
/// O(ds⁴) prediction takes fewer steps than Euler's O(ds²) over the same
/// arc, and chord corrections fewer factorisations a step. A branch
/// stopped half-way and resumed (its `Resume` carries the point before)
/// takes bitwise the uninterrupted branch's steps.
#[test]
fn hermite_predictor_and_chord_corrections_stay_on_the_branch() {
    let base = Options {
        max_steps: 2000,
        residual_tol: 1e-12,
        initial_step: 0.05,
        max_step: 0.5,
        lambda_range: (-0.5, 2.0),
        ..Default::default()
    };
    let start = || Start::Point { x: vec![1.0, 0.0, 0.0], lambda: 0.0, increasing: true };
    let run = |opts: &Options| continue_newton(&mut circle(), start(), opts, |x, _| x.to_vec(), |_| true).unwrap();
    let plain = run(&base);
    let mut per_step = vec![];
    for (hermite_predictor, chord) in [(false, false), (true, false), (false, true), (true, true)] {
        let opts = Options { hermite_predictor, chord, ..base.clone() };
        let b = run(&opts);
        let name = format!("hermite {hermite_predictor}, chord {chord}");
        assert_eq!(b.stop, Stop::LambdaRange, "{name}");
        let last = b.records.last().unwrap();
        assert!(last.outputs[0] < -0.5 && last.lambda < 0.0, "{name}: ended at {:?}", last.outputs);
        for r in &b.records {
            assert!(on_circle(&r.outputs, r.lambda) < 1e-11, "{name}: off the branch at Λ {}", r.lambda);
        }
        per_step.push((b.counts.steps, b.counts.factorisations as f64 / b.counts.steps as f64));
        println!("{name}: {} steps, {:.2} factorisations a step", b.counts.steps, per_step.last().unwrap().1);
    }
    assert_eq!(per_step[0].0, plain.counts.steps);
    assert!(per_step[1].0 < per_step[0].0, "Hermite {:?} vs Euler {:?}", per_step[1], per_step[0]);
    assert!(per_step[2].1 < per_step[0].1, "chord {:?} vs Newton {:?}", per_step[2], per_step[0]);
    // Stopped after 7 records and resumed: the same records, bitwise.
    let opts = Options { hermite_predictor: true, chord: true, ..base.clone() };
    let whole = run(&opts);
    let mut told = 0;
    let first = continue_newton(
        &mut circle(),
        start(),
        &opts,
        |x, _| x.to_vec(),
        |_| {
            told += 1;
            told < 7
        },
    )
    .unwrap();
    assert_eq!(first.stop, Stop::Cancelled);
    assert!(first.resume.previous.is_some(), "the resume keeps the point before");
    let rest = continue_newton(&mut circle(), Start::Resume(first.resume.clone()), &opts, |x, _| x.to_vec(), |_| true)
        .unwrap();
    let joined: Vec<_> =
        first.records.iter().chain(&rest.records[1..]).map(|r| (r.lambda, r.outputs.clone())).collect();
    let reference: Vec<_> = whole.records.iter().map(|r| (r.lambda, r.outputs.clone())).collect();
    assert_eq!(joined, reference, "a resumed branch takes the uninterrupted one's steps");
}

/// Records' signs from their own factorisation (`Options::overlap_records`),
/// on a second thread and on the calling one (`Options::overlap_thread`),
/// against the run that reads them off each point's factorisation (the
/// reference): the circle through its fold (det R_x = 2x1 flips once
/// there; reference: the closed form) with every way a run ends — past
/// the Λ range, at a target, at the step limit, and stopped by the
/// callback after record k (the step corrected meanwhile is dropped: the
/// same records and resume point; at a start on its target the stop wins,
/// as without overlap). Two factorisation kinds:
/// - block elimination forced (`LuKind::Supernodal`): each record's signs
///   come from a simplicial LU of their own, on the second thread or here
///   (both counted: one factorisation more a record than the reference);
///   records equal the reference's to 1e-12 (the tangents differ only by
///   rounding; signs and pivots equal);
/// - B's own simplicial LU (the default on this 3×3): the signs are read
///   off the point's factorisation, no factorisation more.
///
/// With and without the thread, the same records and resume point,
/// bitwise (every f64 by its bits; c-api.md: results bitwise identical
/// for any thread count).
#[test]
fn signs_on_a_second_thread_give_the_one_thread_run() {
    use rodkit::continuation::Record;
    use rodkit::linalg::LuKind;
    fn bits(r: &Record) -> Vec<u64> {
        let mut v = [r.lambda, r.residual, r.step, r.det_sign, r.bordered_det_sign].map(f64::to_bits).to_vec();
        v.extend(r.outputs.iter().map(|x| x.to_bits()));
        v.extend(r.smallest_singular_value.map(f64::to_bits));
        v.extend([r.negative_pivots.map_or(u64::MAX, |p| p as u64), r.newton_iterations as u64]);
        v
    }
    let base = through_the_fold();
    let cases = [
        ("range", base.clone(), usize::MAX),
        ("target", Options { target_lambda: Some(0.9), ..base.clone() }, usize::MAX),
        ("max steps", Options { max_steps: 7, ..base.clone() }, usize::MAX),
        ("cancelled", base.clone(), 9),
        ("cancelled at a start on its target", Options { target_lambda: Some(0.0), ..base.clone() }, 0),
    ];
    for (kind, own_lu) in [(Some(LuKind::Supernodal), true), (None, false)] {
        for (name, opts, stop_after) in cases.clone() {
            let name = format!("{name}, {kind:?}");
            let run = |overlap_records: bool, overlap_thread: bool| {
                let mut sys = circle();
                let start = Start::Point { x: vec![1.0, 0.0, 0.0], lambda: 0.0, increasing: true };
                let opts = Options { overlap_records, overlap_thread, lu_kind: kind, ..opts.clone() };
                let mut told = 0;
                let b = continue_newton(
                    &mut sys,
                    start,
                    &opts,
                    |x, _| x.to_vec(),
                    |_| {
                        told += 1;
                        told <= stop_after
                    },
                )
                .unwrap();
                (b, told)
            };
            let ((one, told1), (two, told2)) = (run(false, false), run(true, true));
            let (here, told_here) = run(true, false);
            assert_eq!((here.stop, told_here), (two.stop, told2), "{name}: without the thread");
            let all = |b: &rodkit::continuation::Branch| b.records.iter().map(bits).collect::<Vec<_>>();
            assert!(all(&here) == all(&two), "{name}: the records differ without the second thread");
            assert_eq!(
                (here.resume.lambda.to_bits(), here.resume.step.to_bits(), &here.resume.x, &here.resume.tangent_x),
                (two.resume.lambda.to_bits(), two.resume.step.to_bits(), &two.resume.x, &two.resume.tangent_x),
                "{name}: resume point without the thread"
            );
            // Where the signs came from: their own factorisations (one a
            // record, timed) or the points' own. (A cancelled run with
            // overlap also corrected the step it then dropped.)
            let extra = if own_lu { two.records.len() } else { 0 };
            assert_eq!(here.counts.factorisations, two.counts.factorisations, "{name}: factorisations");
            if stop_after == usize::MAX {
                assert_eq!(two.counts.factorisations, one.counts.factorisations + extra, "{name}: factorisations");
            }
            for (b, how) in [(&two, "thread"), (&here, "here")] {
                assert_eq!(b.counts.times.overlapped > std::time::Duration::ZERO, own_lu, "{name} ({how})");
            }
            assert_eq!((one.stop, one.records.len(), told1), (two.stop, two.records.len(), told2), "{name}");
            assert_eq!(one.column_order, two.column_order, "{name}: the order carried on");
            assert_eq!(one.counts.times.overlapped, std::time::Duration::ZERO, "{name}");
            for (k, (a, b)) in one.records.iter().zip(&two.records).enumerate() {
                assert!((a.lambda - b.lambda).abs() < 1e-12, "{name} record {k}: Λ {} vs {}", a.lambda, b.lambda);
                for (p, q) in a.outputs.iter().zip(&b.outputs) {
                    assert!((p - q).abs() < 1e-12, "{name} record {k}: {p} vs {q}");
                }
                assert_eq!(
                    (a.det_sign, a.bordered_det_sign, a.negative_pivots),
                    (b.det_sign, b.bordered_det_sign, b.negative_pivots),
                    "{name} record {k}"
                );
            }
            let (r1, r2) = (&one.resume, &two.resume);
            assert!((r1.lambda - r2.lambda).abs() < 1e-12 && (r1.step - r2.step).abs() < 1e-12, "{name}: resume");
            // The reference itself: one flip of det R_x on the whole arc.
            if name.starts_with("range") {
                assert_eq!(one.records.windows(2).filter(|w| w[0].det_sign != w[1].det_sign).count(), 1, "{name}");
            }
        }
    }
}

/// The ANM's series bifurcation indicator (continuation::indicator) on a
/// curved primary branch with two pitchforks in closed form: R1 = u − Λ²,
/// R2 = y (u − 1)(u − c) − y³. On y = 0, u = Λ², the bordered tangent is
/// singular where (u − 1)(u − c) = 0: Λ = 1 and Λ = √c (Λ > 0). From Λ =
/// 0.1 to 3 with detection, both points are located to 1e-9 with the
/// indicator on and off; with it, each location starts in the short
/// bracket around a root of μ(a) (the root within 1e-3 of the step of the
/// point). With c = 4 and steps of at most 0.3 the points are in separate
/// steps; with c = 1.1025 (Λ = 1.05) and the series' own steps one step
/// holds both, det B flips twice over it (its ends' signs agree) and the
/// series' roots are the evidence that starts the search.
#[test]
fn the_series_indicator_puts_the_search_at_each_pitchfork() {
    let system = |c: f64| {
        let tape = Arc::new(Tape::record(3, |v| {
            let (u, y, l) = (v[0], v[1], v[2]);
            vec![u - l * l, y * (u - 1.0) * (u - c) - y * y * y]
        }));
        let inputs = vec![Slot::Unknown(0), Slot::Unknown(1), Slot::Lambda];
        AssembledSystem::new(2, vec![Block::new(tape, inputs, vec![0, 1])])
    };
    for (c, max_step, one_step) in [(4.0, 0.3, false), (1.1025f64, f64::INFINITY, true)] {
        let want = [1.0, c.sqrt()];
        let mut located = vec![];
        for indicator in [true, false] {
            let opts = Options {
                target_lambda: Some(3.0),
                residual_tol: 1e-13,
                initial_step: 0.05,
                max_step,
                detect_bifurcations: true,
                bifurcation_tol: 1e-11,
                series_indicator: indicator,
                ..Default::default()
            };
            let start = Start::Point { x: vec![0.01, 0.0], lambda: 0.1, increasing: true };
            let b = continue_anm(&mut system(c), start, &opts, &AnmOptions::default(), |x, _| x.to_vec(), |_| true)
                .unwrap();
            let points: Vec<f64> = b.bifurcations.iter().map(|p| p.lambda).collect();
            let name = format!("c {c}, indicator {indicator}");
            if indicator {
                assert_eq!(points.len(), 2, "{name}: {points:?}, unresolved {:?}", b.unresolved);
                for (p, w) in points.iter().zip(want) {
                    assert!((p - w).abs() < 1e-9, "{name}: {p} against {w}");
                }
                assert_eq!(b.counts.series_located, if one_step { 1 } else { 2 }, "{name}: {:?}", b.counts);
                let same_step = b.bifurcations[0].record == b.bifurcations[1].record;
                assert_eq!(same_step, one_step, "{name}: records {:?}", b.bifurcations);
                if one_step {
                    let r = b.bifurcations[0].record;
                    assert_eq!(b.records[r].bordered_det_sign, b.records[r + 1].bordered_det_sign);
                }
            } else {
                assert_eq!(b.counts.series_located, 0);
            }
            located.push(points);
        }
        println!("c {c}: indicator on {:?}, off {:?}", located[0], located[1]);
        if !one_step {
            assert_eq!(located[0].len(), located[1].len());
            for (a, b) in located[0].iter().zip(&located[1]) {
                assert!((a - b).abs() < 1e-9, "indicator on {a}, off {b}");
            }
        }
    }
}

/// The location meets its tolerance across the knob's range, in both
/// engines: on the trivial branch y = 0, u = Λ² of R = (u − Λ², y(u − 2) −
/// y³) the pitchfork is at Λ* = √2 exactly (closed form: R_y = u − 2 = 0),
/// where σ_min crosses zero linearly but not along a straight line in the
/// arc parameter (u − 2 = Λ² − 2). A point located to `bifurcation_tol` s
/// in scaled arc length has its Λ within s·|dΛ/ds| ≤ s of Λ* (Λ's scale is
/// 1: Options::detect_bifurcations). Steps of up to 0.4 leave a bracket
/// several hundred thousand times the tightest tolerance, so the location
/// and its stopping rules, not the steps, decide how close the point is.
#[test]
fn a_located_pitchfork_is_within_its_tolerance_from_1e_5_to_1e_13() {
    fn kernel<T: Scalar>(v: &[T]) -> Vec<T> {
        let (u, y, l) = (v[0], v[1], v[2]);
        vec![u - l * l, y * (u - 2.0) - y * y * y]
    }
    let system = || {
        let tape = Arc::new(Tape::record(3, kernel));
        AssembledSystem::new(
            2,
            vec![Block::new(tape, vec![Slot::Unknown(0), Slot::Unknown(1), Slot::Lambda], vec![0, 1])],
        )
    };
    let exact = 2f64.sqrt();
    for tol in [1e-5, 1e-7, 1e-9, 1e-11, 1e-13] {
        let opts = Options {
            target_lambda: Some(2.5),
            residual_tol: 1e-14,
            initial_step: 0.1,
            max_step: 0.4,
            detect_bifurcations: true,
            bifurcation_tol: tol,
            ..Default::default()
        };
        let start = || Start::Point { x: vec![0.25, 0.0], lambda: 0.5, increasing: true };
        let anm =
            continue_anm(&mut system(), start(), &opts, &AnmOptions::default(), |x, _| x.to_vec(), |_| true).unwrap();
        let newton = continue_newton(&mut system(), start(), &opts, |x, _| x.to_vec(), |_| true).unwrap();
        for (engine, b) in [("ANM", &anm), ("Newton", &newton)] {
            assert_eq!(b.bifurcations.len(), 1, "{engine}, tol {tol:e}: {:?}", b.unresolved);
            let p = &b.bifurcations[0];
            let error = (p.lambda - exact).abs();
            println!(
                "{engine} tol {tol:e}: Λ error {error:.1e}, {} trial factorisations",
                b.counts.location_factorisations
            );
            assert!(error <= tol, "{engine}, tol {tol:e}: Λ = {} is {error:e} from √2", p.lambda);
            assert_eq!(p.multiplicity, 1, "{engine}, tol {tol:e}");
        }
    }
}

/// An ANM step whose end point fails to correct is halved; the samples it
/// had delivered past the halved end are taken back and delivered once,
/// by the step that reaches them (reference: the circle's closed form,
/// x1 = √(1 − Λ²); each requested Λ exactly once, in order). The end
/// point's first correction past Λ = 0.3 is made to fail: its residual is
/// poisoned (NaN) at a Λ that is no sample's. Without the take-back the
/// samples between the halved end and the first end were listed twice.
#[test]
fn a_halved_anm_step_delivers_each_sample_once() {
    let targets: Vec<f64> = (1..90).map(|k| k as f64 / 100.0).collect();
    let opts = Options {
        max_steps: 200,
        residual_tol: 1e-12,
        initial_step: 0.05,
        max_step: 0.5,
        lambda_range: (-0.5, 0.9),
        samples: targets.clone(),
        ..Default::default()
    };
    let anm = AnmOptions { order: 20, epsilon: 1e-10, pade: false };
    // Two poisoned residuals: the end point's own and its correction's
    // first (one alone is corrected away).
    let left = std::cell::Cell::new(2);
    let mut p = Poisoned(circle(), |l: f64| {
        let on_grid = ((l * 100.0).round() - l * 100.0).abs() < 1e-9;
        let poison = left.get() > 0 && l > 0.3 && !on_grid;
        left.set(left.get() - usize::from(poison));
        poison
    });
    let start = Start::Point { x: vec![1.0, 0.0, 0.0], lambda: 0.0, increasing: true };
    let b = continue_anm(&mut p, start, &opts, &anm, |x, _| x.to_vec(), |_| true).unwrap();
    assert_eq!(left.get(), 0, "the end point's correction was never made to fail");
    assert_eq!(b.stop, Stop::LambdaRange);
    let got: Vec<f64> = b.samples.iter().map(|s| s.lambda).collect();
    assert_eq!(got, targets, "each requested Λ once, in order");
    for s in &b.samples {
        assert!(on_circle(&s.outputs, s.lambda) < 1e-11, "off the circle at Λ {}", s.lambda);
        assert!((s.outputs[0] - (1.0 - s.lambda * s.lambda).sqrt()).abs() < 1e-11);
    }
    assert!(b.missed_samples.is_empty(), "{:?}", b.missed_samples);
}

//! A supercoiling path's point re-solved under another model or solver
//! (src/electrostatics/equilibrium.rs): the same model reproduces the
//! path's point (the continuation's corrector is the reference); the
//! discrete base-pair model by Newton–Krylov equals it by the direct
//! sparse Newton (two independent solvers); all-pairs base pairs differ
//! from the cutoff's by about the cutoff tolerance.

use rodkit::charged::dna::{run_scene, DnaScene, SupercoilRun, SupercoilSettings};
use rodkit::charged::equilibrium::{solve_point, EquilibriumSolver};
use rodkit::status::Status;

fn small_run() -> SupercoilRun {
    // 300 bp, 0.1 M, 40 elements, 20 steps: buckled, the last point bent
    // (extension below 0.999 L, checked).
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let run = run_scene(&scene, &SupercoilSettings { elements: 40, max_steps: 20, ..Default::default() }).unwrap();
    assert!(run.buckled.is_some());
    assert!(run.points.last().unwrap().observables.extension < 0.999 * scene.length());
    run
}

fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt())
        .fold(0.0, f64::max)
}

#[test]
fn same_model_reproduces_the_path_and_solvers_agree_on_base_pairs() {
    let run = small_run();
    let last = run.points.len() - 1;
    let tol = 1e-10;
    // Same model, both solvers: the path's point (converged to 1e-8 by the
    // continuation) moves by at most ~1e-6 nm when tightened to 1e-10.
    for solver in [EquilibriumSolver::Direct, EquilibriumSolver::NewtonKrylov] {
        let p = solve_point(&run, last, &run.charge, solver, tol).unwrap();
        println!(
            "same model, {solver:?}: shift {:e} nm, {} Newton, {} GMRES, residual {:e}",
            p.shift, p.newton_iterations, p.linear_iterations, p.residual
        );
        assert!(p.residual <= tol);
        assert!(p.shift < 1e-5, "{solver:?}: shift {:e}", p.shift);
        let (a, b) = (p.observables, run.points[last].observables);
        assert!(
            (a.torque - b.torque).abs() < 1e-5 * b.torque.abs() && (a.extension - b.extension).abs() < 1e-5,
            "{a:?} vs {b:?}"
        );
    }
    // A straight-branch point (no phase condition).
    // The preconditioner keeps the rod band there (one element's coupling,
    // 13·(2 + 1) + 12 for Gauss(2)), the whole pattern on the buckled branch.
    let p = solve_point(&run, 1, &run.charge, EquilibriumSolver::NewtonKrylov, tol).unwrap();
    assert!(p.shift < 1e-5);
    assert_eq!(p.preconditioner_band, 51);
    // Base pairs at the scene's rise, cutoff 1e-4: Newton–Krylov = direct
    // (1e-10 scaled residual: positions to ~1e-8 nm; asserted 1e-6).
    let mut bp = run.charge.clone();
    bp.base_pairs = Some(run.scene.rise);
    let d = solve_point(&run, last, &bp, EquilibriumSolver::Direct, tol).unwrap();
    let k = solve_point(&run, last, &bp, EquilibriumSolver::NewtonKrylov, tol).unwrap();
    let (rd, rk) = (run.rod.positions(&d.state), run.rod.positions(&k.state));
    let gap = max_distance(&rd, &rk);
    println!("base pairs: direct {} Newton ({:.1} ms), NK {} Newton {} GMRES ({:.1} ms); solvers differ by {gap:e} nm; shift from the continuum {:e} nm; torque {} vs continuum {}",
        d.newton_iterations, d.seconds * 1e3, k.newton_iterations, k.linear_iterations, k.seconds * 1e3, k.shift, k.observables.torque, run.points[last].observables.torque);
    assert!(gap < 1e-6, "solvers differ by {gap:e} nm");
    assert_eq!(k.preconditioner_band, run.buckled.as_ref().unwrap().states[0].len());
    assert!((d.observables.torque - k.observables.torque).abs() < 1e-7 * d.observables.torque.abs());
    // The models differ (near-field terms): the shape moves, but by far less
    // than the radius (the buckling points differ by < 2e-3, tests/native.rs).
    assert!(k.shift > 1e-6 && k.shift < 0.5, "shift {:e}", k.shift);
    // Next to the buckling point (the second buckled point), where the
    // model change moves the soft buckled rod most: both solvers converge
    // (the direct one damped) and agree.
    let near = run.straight.records.len() + 1;
    let dn = solve_point(&run, near, &bp, EquilibriumSolver::Direct, tol).unwrap();
    let kn = solve_point(&run, near, &bp, EquilibriumSolver::NewtonKrylov, tol).unwrap();
    let gap_near = max_distance(&run.rod.positions(&dn.state), &run.rod.positions(&kn.state));
    println!(
        "next to buckling: shift {:e} nm, direct {} iterations, NK {} / {} GMRES, solvers differ by {gap_near:e} nm",
        dn.shift, dn.newton_iterations, kn.newton_iterations, kn.linear_iterations
    );
    assert!(gap_near < 1e-6, "{gap_near:e}");
    // Every pair (dense exact Jacobian; preconditioned by the 1e-4 cutoff
    // model's band): the cutoff at 1e-4 moves the shape by an order less
    // than the change of model did (measured 1.0e-3 vs 3.0e-2 nm).
    let mut all = bp.clone();
    all.cutoff_tolerance = None;
    let a = solve_point(&run, last, &all, EquilibriumSolver::NewtonKrylov, tol).unwrap();
    let gap_all = max_distance(&run.rod.positions(&a.state), &rk);
    println!(
        "all pairs: {} Newton {} GMRES, differs from cutoff by {gap_all:e} nm",
        a.newton_iterations, a.linear_iterations
    );
    assert!(a.residual <= tol && gap_all < 0.1 * k.shift, "all pairs vs cutoff {gap_all:e} (shift {:e})", k.shift);
}

#[test]
fn bad_points_are_statuses() {
    let run = small_run();
    let e = solve_point(&run, run.points.len(), &run.charge, EquilibriumSolver::Direct, 1e-10).unwrap_err();
    // An index out of range is ErrOutOfRange (issue 17: -8 is for array lengths).
    assert_eq!(e.status, Status::ErrOutOfRange, "{}", e.message);
    let e = solve_point(&run, 0, &run.charge, EquilibriumSolver::Direct, 0.0).unwrap_err();
    assert_eq!(e.status, Status::ErrNotPositive, "{}", e.message);
}

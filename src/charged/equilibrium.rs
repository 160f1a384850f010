//! One equilibrium of a supercoiling path re-solved under another
//! electrostatic model or with another solver, at the point's end rotation
//! and from its shape: the thesis's comparison of the continuum with the
//! discrete base-pair charges on the *same* plectoneme (what the continuum
//! path's shape becomes with base-pair charges, and how far it moves), and
//! the choice between the direct sparse Newton and Newton–Krylov (the
//! continuation keeps the direct solver, whose determinant signs locate
//! the buckling points; a single equilibrium is cheaper by Newton–Krylov —
//! benches/charged.rs measures both).

use super::dna::{observables, Observables, SupercoilRun};
use super::rod::{ChargedRod, RodCharge};
use crate::continuation::equilibrium::{damped_newton, newton_krylov};
use crate::continuation::{Counts, Problem};
use crate::error::{self, Error, Result};
use crate::geometry::vec3::distance;
use crate::nonlinear::krylov::{BandPreconditioner, KrylovOptions, KrylovReport};
use crate::rod::branch::Phase;
use crate::rod::model::unwrap_rotation;
use crate::status::Status;

/// How a single equilibrium is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EquilibriumSolver {
    /// Sparse Newton with the exact Jacobian and a full LU at fixed end
    /// rotation, damped (halving until the scaled residual falls).
    Direct,
    /// Newton–Krylov: GMRES with central-difference products,
    /// preconditioned by the LU of the Jacobian's one-element band
    /// (of the model with a 1e-4 cutoff when the model keeps every pair,
    /// whose own Jacobian is dense).
    NewtonKrylov,
}

/// Cutoff tolerance of the model that supplies the preconditioner's
/// Jacobian when the solved model keeps every pair (the benchmark's
/// all-pairs base-pair rod converges with it in 14–15 GMRES iterations).
pub const PRECONDITIONER_CUTOFF: f64 = 1e-4;

/// A re-solved point.
#[derive(Clone, Debug)]
pub struct PointEquilibrium {
    /// The rod's unknowns (as `SupercoilRun::states`).
    pub state: Vec<f64>,
    pub observables: Observables,
    /// Newton iterations (one factorisation each for the direct solver).
    pub newton_iterations: usize,
    /// GMRES iterations (0 for the direct solver; a failed attempt with the
    /// band preconditioner is not counted here, its time is in `seconds`).
    pub linear_iterations: usize,
    /// Final max |R_i| / d_i.
    pub residual: f64,
    pub counts: Counts,
    /// Pair lists built (more than one when the shape moved past half the
    /// Verlet skin and the point was re-solved on a new list).
    pub pair_lists: usize,
    /// Largest distance a node moved from the path's point (nm).
    pub shift: f64,
    /// Newton–Krylov's preconditioner: the half-bandwidth of the Jacobian
    /// band it kept (the dimension: the whole pattern, after the band
    /// failed); 0 for the direct solver.
    pub preconditioner_band: usize,
    pub seconds: f64,
}

/// Solve the equilibrium of `run`'s point `point` (index into
/// `run.points`) under `charge` with `solver`, to max |R_i|/d_i ≤
/// `residual_tol`. Points on the buckled branch keep its phase condition.
/// Non-convergence is ErrNotConverged (the state is then not returned).
pub fn solve_point(
    run: &SupercoilRun,
    point: usize,
    charge: &RodCharge,
    solver: EquilibriumSolver,
    residual_tol: f64,
) -> Result<PointEquilibrium> {
    let clock = std::time::Instant::now();
    error::count_in_range("point", point as i64, 0, run.points.len() as i64 - 1)?;
    error::positive("residual_tol", residual_tol)?;
    let rod = &run.rod;
    let n = rod.unknowns();
    let straight = run.straight.records.len();
    // The full unknowns (the buckled branch's carry the phase multiplier).
    let (mut x, phase) = if point < straight {
        (run.states[point].clone(), None)
    } else {
        let b = run.buckled.as_ref().ok_or_else(|| {
            Error::new(
                Status::ErrOutOfRange,
                "argument `point` lies beyond the straight branch of a run without a buckled one",
            )
        })?;
        (b.states[point - straight].clone(), b.phase)
    };
    // Λ of the point (φ, or the end torque of a torque clamp), and its φ.
    let (lambda, phi_path) = (run.points[point].parameter, run.points[point].phi);
    let mut counts = Counts::default();
    let (mut newton_iterations, mut linear_iterations) = (0, 0);
    let mut residual;
    let mut pair_lists = 0;
    let mut preconditioner_band = 0;
    let half_skin = 0.5 * charge.skin;
    // At most a few list rebuilds: a re-solve moves the shape by the models'
    // difference (0.03 nm between continuum and base pairs on the default
    // scene's buckled points, 0.9 nm next to the buckling point), below
    // half the skin (2 nm at 0.1 M); a shape that keeps moving past it is
    // not converging.
    for _ in 0..4 {
        let mut problem = ChargedRod::new(rod, charge, phase, &x)?;
        pair_lists += 1;
        match solver {
            EquilibriumSolver::Direct => {
                let (it, res) = damped_newton(&mut problem, &mut x, lambda, residual_tol, &mut counts)?;
                newton_iterations += it;
                residual = res;
            }
            EquilibriumSolver::NewtonKrylov => {
                let (rep, band) = krylov_point(&mut problem, charge, phase, &mut x, lambda, residual_tol)?;
                preconditioner_band = band;
                counts.add_work(&rep.counts);
                newton_iterations += rep.newton_iterations;
                linear_iterations += rep.linear_iterations;
                residual = rep.residual;
            }
        }
        if !problem.list_is_local() || problem.displacement(&x) <= half_skin {
            let path = rod.positions(&run.states[point]);
            let shift = rod.positions(&x[..n]).iter().zip(&path).map(|(a, b)| distance(a, b)).fold(0.0, f64::max);
            x.truncate(n);
            // A torque clamp's re-solved end angle, followed from the path's.
            let phi = if rod.torqued() {
                unwrap_rotation(phi_path, rod.end_rotation(&x, lambda).expect("torque clamp"))
            } else {
                lambda
            };
            return Ok(PointEquilibrium {
                observables: observables(rod, &x, phi)?,
                state: x,
                newton_iterations,
                linear_iterations,
                residual,
                counts,
                pair_lists,
                shift,
                preconditioner_band,
                seconds: clock.elapsed().as_secs_f64(),
            });
        }
    }
    Err(Error::new(
        Status::ErrNotConverged,
        format!("the shape kept moving past half the Verlet skin ({half_skin:.3} nm) over {pair_lists} pair lists"),
    ))
}

/// Newton–Krylov on one pair list: (the report, the preconditioner's band).
fn krylov_point(
    problem: &mut ChargedRod,
    charge: &RodCharge,
    phase: Phase,
    x: &mut [f64],
    lambda: f64,
    residual_tol: f64,
) -> Result<(KrylovReport, usize)> {
    let rod = &problem.rod().clone();
    let opts = KrylovOptions { residual_tol, ..Default::default() };
    // The preconditioner's Jacobian: the model's own, or with
    // every pair kept, the 1e-4 cutoff model's (same state).
    let mut cheap = None;
    if charge.cutoff_tolerance.is_none() {
        let mut c = charge.clone();
        c.cutoff_tolerance = Some(PRECONDITIONER_CUTOFF);
        cheap = Some(ChargedRod::new(rod, &c, phase, x)?);
    }
    // The preconditioner keeps the rod's band on the straight
    // branch (the benchmark's case: 5–8 GMRES iterations, an LU
    // 2–3× sparser than the whole one) and the whole pattern on
    // the buckled branch, whose soft modes feel the pairs a few
    // elements apart that the band drops: the default 1 kbp
    // scene's buckled point re-solved with base pairs failed
    // with the band (GMRES returned poor directions, the line
    // search gave up after 11 Newton iterations, 0.47 s) and
    // took 4 Newton / 44 GMRES iterations with the whole
    // pattern (0.16 s; direct Newton 0.21 s). A failure with
    // the band is retried with the whole pattern.
    let whole = x.len();
    let bands: &[usize] = if phase.is_none() { &[0, whole] } else { &[whole] };
    let start = x.to_vec();
    let mut result = Err(Error::new(Status::ErrNotConverged, "Newton–Krylov not run"));
    for &band in bands {
        // 0: the source's rod band.
        let (mut pre, band) = {
            let src = cheap.as_ref().unwrap_or(&*problem);
            let band = if band == 0 { src.local_band() } else { band };
            (BandPreconditioner::bordered(src.pattern(), band, src.border())?, band)
        };
        x.copy_from_slice(&start);
        let source = cheap.as_mut().map(|c| c as &mut dyn Problem);
        result = newton_krylov(&mut *problem, source, &mut pre, x, lambda, &opts).map(|rep| (rep, band));
        match &result {
            Err(e) if e.status == Status::ErrNotConverged => continue,
            _ => break,
        }
    }
    result
}

//! Single equilibria of a supercoiling path (physics.md §3.3): a point of a
//! `RodkitSupercoil` re-solved under another electrostatic model or with
//! another solver (`RodkitEquilibriumSpec` in, `RodkitEquilibrium` out).

use super::args::{arg_mut, arg_ref, c_enum, check_nodes, enum_arg, flag, qualify_argument, write_positions};
use super::guard;
use super::supercoil::Supercoil;
use crate::charged::equilibrium::{self, solve_point};
use crate::error::{self, Error};
use crate::status::Status;

/// How `rodkit_supercoil_solve_point` solves (`RodkitEquilibriumSpec.solver`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EquilibriumSolver {
    /// Sparse Newton, exact Jacobian, full LU (the continuation's corrector).
    Direct = 1,
    /// Newton–Krylov: GMRES with difference products, preconditioned by the
    /// LU of the Jacobian's band (cheaper for one equilibrium; the only
    /// practical solver for every pair on long rods).
    NewtonKrylov = 2,
}

c_enum!(
    EquilibriumSolver,
    "RODKIT_EQUILIBRIUM_SOLVER_DIRECT (1) or _NEWTON_KRYLOV (2)",
    [EquilibriumSolver::Direct, EquilibriumSolver::NewtonKrylov]
);

/// A point of a path re-solved under another electrostatic model or with
/// another solver (the scene, its salt, charge, radius, hard core and
/// threads stay the run's). Call `rodkit_equilibrium_spec_default` first:
/// continuum, cutoff tolerance 1e-4, Newton–Krylov, scaled residual 1e-10.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct EquilibriumSpec {
    /// 0: the continuum line charge; 1: discrete base-pair charges at the
    /// scene's rise (the thesis's comparison).
    pub discrete_base_pairs: i32,
    /// Relative energy tolerance of the screening cutoff; 0: every pair
    /// (with Newton–Krylov, preconditioned by the 1e-4 cutoff's band).
    pub cutoff_tolerance: f64,
    /// RODKIT_EQUILIBRIUM_SOLVER_DIRECT or ..._NEWTON_KRYLOV.
    pub solver: i32,
    /// Converged when max |R_i| / (equation scale) ≤ residual_tol.
    pub residual_tol: f64,
}

/// What `rodkit_supercoil_solve_point` found.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct Equilibrium {
    /// Observables as `RodkitSupercoilPoint`, of the re-solved state (under
    /// rotation control its turns are the point's; under a torque clamp the
    /// torque is, and the turns are read from the new shape).
    pub turns: f64,
    pub extension: f64,
    pub torque: f64,
    pub tension: f64,
    pub twist: f64,
    pub writhe: f64,
    /// Final scaled residual.
    pub residual: f64,
    /// Largest distance a node moved from the path's point (nm).
    pub shift: f64,
    pub seconds: f64,
    /// Newton iterations (direct: the corrector's factorisations).
    pub newton_iterations: i64,
    /// GMRES iterations (0 for the direct solver).
    pub linear_iterations: i64,
    pub factorisations: i64,
    pub residuals: i64,
    pub pair_lists: i64,
    /// Newton–Krylov's preconditioner band (half-bandwidth; the dimension
    /// when the whole Jacobian was used: always on the buckled branch, and
    /// after the band failed on the straight one); 0 for direct.
    pub preconditioner_band: i64,
}

/// Fill `spec` with the defaults above.
#[no_mangle]
pub unsafe extern "C" fn rodkit_equilibrium_spec_default(spec: *mut EquilibriumSpec) -> i32 {
    guard(|| {
        *arg_mut("spec", spec)? = EquilibriumSpec {
            discrete_base_pairs: 0,
            cutoff_tolerance: 1e-4,
            solver: EquilibriumSolver::NewtonKrylov as i32,
            residual_tol: 1e-10,
        };
        Ok(Status::Ok)
    })
}

/// Solve the equilibrium at point `point` of `run` (at its end rotation
/// under rotation control, at its end torque under a torque clamp; from
/// its shape) under the model of `spec`, into `out`; with `xyz` not NULL
/// also its node positions (nm) xyz[k + ld·i], i < nodes (nodes as
/// `RodkitSupercoilInfo.nodes`). Non-convergence is
/// RODKIT_STATUS_ERR_NOT_CONVERGED (nothing written). Reentrant; `run`
/// is only read.
/// cbindgen:fortran-arrays=[xyz]
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_solve_point(
    run: *const Supercoil,
    point: i64,
    spec: *const EquilibriumSpec,
    out: *mut Equilibrium,
    xyz: *mut f64,
    ld: i64,
    nodes: i64,
) -> i32 {
    guard(|| {
        let r = &arg_ref("run", run)?.run;
        let s = *arg_ref("spec", spec)?;
        let out = arg_mut("out", out)?;
        error::count_in_range("point", point, 0, r.points.len() as i64 - 1)?;
        let q = |e: Error| qualify_argument(e, "spec.");
        let solver = match enum_arg::<EquilibriumSolver>("spec.solver", s.solver)? {
            EquilibriumSolver::Direct => equilibrium::EquilibriumSolver::Direct,
            EquilibriumSolver::NewtonKrylov => equilibrium::EquilibriumSolver::NewtonKrylov,
        };
        // [0, 1]: 1 itself is refused by the model's own validation.
        error::in_range("cutoff_tolerance", s.cutoff_tolerance, 0.0, 1.0).map_err(q)?;
        error::positive("residual_tol", s.residual_tol).map_err(q)?;
        let mut charge = r.charge.clone();
        charge.cutoff_tolerance = (s.cutoff_tolerance > 0.0).then_some(s.cutoff_tolerance);
        charge.base_pairs = flag("discrete_base_pairs", s.discrete_base_pairs).map_err(q)?.then_some(r.scene.rise);
        if !xyz.is_null() {
            check_nodes(ld, nodes, r.rod.elements + 1)?;
        }
        let p = solve_point(r, point as usize, &charge, solver, s.residual_tol)?;
        let o = p.observables;
        *out = Equilibrium {
            turns: o.turns,
            extension: o.extension,
            torque: o.torque,
            tension: o.tension,
            twist: o.twist,
            writhe: o.writhe,
            residual: p.residual,
            shift: p.shift,
            seconds: p.seconds,
            newton_iterations: p.newton_iterations as i64,
            linear_iterations: p.linear_iterations as i64,
            factorisations: p.counts.factorisations as i64,
            residuals: p.counts.residuals as i64,
            pair_lists: p.pair_lists as i64,
            preconditioner_band: p.preconditioner_band as i64,
        };
        if !xyz.is_null() {
            write_positions(xyz, ld, &r.rod.positions(&p.state))?;
        }
        Ok(Status::Ok)
    })
}

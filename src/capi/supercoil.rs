//! DNA supercoiling from C and Fortran (issue 5): a charged Kirchhoff rod
//! clamped at both ends under fixed tension, continued in the end rotation
//! from the straight rod through its first buckling point along the
//! buckled branch. One call runs the scene into a handle; accessors copy
//! the path (turns, extension, torque, twist, writhe) and the shapes.

use super::{arg_mut, arg_ref, guard, null_error, qualify_argument};
use crate::charged::dna::{run_scene, DnaScene, SupercoilRun, SupercoilSettings};
use crate::error::{self, Error, Result};
use crate::status::Status;

/// A supercoiling scene in nm, pN, mol/L. Call
/// `rodkit_dna_supercoil_spec_default` first: 1 kbp, 1 pN, 0.1 M, ν = 1/l_B
/// (Manning), a = 1 nm, A = 50 nm, P = 95 nm, 298.15 K, ε_r = 78.4; 170
/// elements of Gauss(2); cutoff tolerance 1e-4; no hard core; 1 thread; to
/// 12 turns in at most 600 steps; scaled residual 1e-8; the continuum model.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DnaSupercoilSpec {
    pub base_pairs: i64,
    /// Rise per base pair (nm).
    pub rise: f64,
    /// Tension (pN).
    pub tension: f64,
    /// Monovalent salt (mol/L); 0: Coulomb.
    pub salt: f64,
    /// Effective charge per length ν (e/nm).
    pub charge_per_length: f64,
    /// Radius a (nm): near-zone exclusion, crossing distance 2a.
    pub radius: f64,
    pub bending_persistence: f64,
    pub twist_persistence: f64,
    pub temperature: f64,
    pub permittivity: f64,
    pub elements: i64,
    /// Gauss–Legendre stages (1…4).
    pub stages: i64,
    /// Screening cutoff's relative energy tolerance; 0: every pair.
    pub cutoff_tolerance: f64,
    /// Hard-core stiffness k_hc (pN/nm⁴) below 2.5a; 0: none.
    pub hard_core: f64,
    pub threads: i64,
    pub max_turns: f64,
    pub max_steps: i64,
    pub residual_tol: f64,
    /// 1: the discrete base-pair model (charges at `rise`, every pair
    /// farther apart along the rod than `radius`; the comparison of
    /// physics.md §3.3) instead of the continuum line charge (0).
    pub discrete_base_pairs: i32,
    /// RodkitEndControl: the end rotation (default) or the end torque as
    /// the continuation parameter (the same equilibria; points report both).
    pub end_control: i32,
}

/// What a supercoiling run controls at the rod's end
/// (`RodkitDnaSupercoilSpec.end_control`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndControl {
    /// The end rotation φ (magnetic tweezers' turns).
    Rotation = 1,
    /// The end torque M (a torque clamp); φ read from each state.
    Torque = 2,
}

/// What a run did.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct SupercoilInfo {
    /// Points of the path (straight, then buckled).
    pub points: i64,
    /// Points on the straight branch (the first ones).
    pub straight_points: i64,
    /// Nodes of the shapes (elements + 1).
    pub nodes: i64,
    /// 1 when a buckling point was located; its turns and torque (pN nm).
    pub buckled: i32,
    pub buckling_turns: f64,
    pub buckling_torque: f64,
    /// 1 when the buckled branch stopped at a strand crossing: distance
    /// (nm) and arc lengths of the pair.
    pub crossing: i32,
    pub crossing_distance: f64,
    pub crossing_s1: f64,
    pub crossing_s2: f64,
    /// Work: continuation steps, factorisations, residuals, pair lists.
    pub steps: i64,
    pub factorisations: i64,
    pub residuals: i64,
    pub pair_lists: i64,
    /// Inverse Debye length (1/nm), Bjerrum length (nm), λ² = k_BT l_B ν² (pN).
    pub kappa: f64,
    pub bjerrum_length: f64,
    pub line_charge_squared: f64,
    /// Screening cutoff switch (r_on, r_off) in nm; NaN: every pair.
    pub cutoff_on: f64,
    pub cutoff_off: f64,
    pub seconds: f64,
    /// The model used: 0 the continuum line charge, else the number of
    /// point charges of the discrete base-pair model.
    pub base_pair_charges: i64,
}

/// One point of the path.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct SupercoilPoint {
    /// End rotation (turns), extension z(L) (nm), torque M_z(L) (pN nm),
    /// axial force (pN), twist and writhe (turns; Tw + Wr = turns).
    pub turns: f64,
    pub extension: f64,
    pub torque: f64,
    pub tension: f64,
    pub twist: f64,
    pub writhe: f64,
    /// 0: straight branch, 1: buckled branch.
    pub branch: i32,
    pub residual: f64,
}

/// An opaque computed path.
pub struct Supercoil {
    run: SupercoilRun,
}

/// Fill `spec` with the defaults above.
#[no_mangle]
pub unsafe extern "C" fn rodkit_dna_supercoil_spec_default(spec: *mut DnaSupercoilSpec) -> i32 {
    guard(|| {
        let d = DnaScene::default();
        let s = SupercoilSettings::default();
        *arg_mut("spec", spec)? = DnaSupercoilSpec {
            base_pairs: d.base_pairs as i64,
            rise: d.rise,
            tension: d.tension,
            salt: d.salt,
            charge_per_length: d.charge_per_length,
            radius: d.radius,
            bending_persistence: d.bending_persistence,
            twist_persistence: d.twist_persistence,
            temperature: d.temperature,
            permittivity: d.permittivity,
            elements: s.elements as i64,
            stages: s.stages as i64,
            cutoff_tolerance: s.cutoff_tolerance.unwrap_or(0.0),
            hard_core: 0.0,
            threads: s.threads as i64,
            max_turns: s.max_turns,
            max_steps: s.max_steps as i64,
            residual_tol: s.residual_tol,
            discrete_base_pairs: 0,
            end_control: EndControl::Rotation as i32,
        };
        Ok(Status::Ok)
    })
}

/// A 0/1 switch of a spec.
fn flag(name: &str, v: i32) -> Result<bool> {
    match v {
        0 => Ok(false),
        1 => Ok(true),
        v => Err(Error::new(Status::ErrOutOfRange, format!("argument `{name}` must be 0 or 1 (got {v})"))),
    }
}

fn scene_of(s: &DnaSupercoilSpec) -> Result<(DnaScene, SupercoilSettings)> {
    error::count_in_range("base_pairs", s.base_pairs, 10, 1 << 24)?;
    error::count_in_range("elements", s.elements, 2, 1 << 18)?;
    error::count_in_range("stages", s.stages, 1, 4)?;
    error::count_in_range("threads", s.threads, 1, 256)?;
    error::count_in_range("max_steps", s.max_steps, 1, 1 << 24)?;
    for (n, v) in [("cutoff_tolerance", s.cutoff_tolerance), ("hard_core", s.hard_core)] {
        error::finite(n, v)?;
        if v < 0.0 {
            return Err(Error::new(Status::ErrOutOfRange, format!("argument `{n}` must be ≥ 0 (got {v:e})")));
        }
    }
    let scene = DnaScene {
        base_pairs: s.base_pairs as usize,
        rise: s.rise,
        tension: s.tension,
        salt: s.salt,
        charge_per_length: s.charge_per_length,
        radius: s.radius,
        bending_persistence: s.bending_persistence,
        twist_persistence: s.twist_persistence,
        temperature: s.temperature,
        permittivity: s.permittivity,
    };
    scene.validate()?;
    let settings = SupercoilSettings {
        elements: s.elements as usize,
        stages: s.stages as usize,
        cutoff_tolerance: (s.cutoff_tolerance > 0.0).then_some(s.cutoff_tolerance),
        hard_core: (s.hard_core > 0.0).then_some(s.hard_core),
        threads: s.threads as usize,
        max_turns: s.max_turns,
        max_steps: s.max_steps as usize,
        residual_tol: s.residual_tol,
        base_pairs: flag("discrete_base_pairs", s.discrete_base_pairs)?,
        control: match s.end_control {
            1 => crate::charged::dna::EndControl::Rotation,
            2 => crate::charged::dna::EndControl::Torque,
            v => {
                return Err(Error::new(
                    Status::ErrOutOfRange,
                    format!("argument `end_control` must be a RodkitEndControl 1…2 (got {v})"),
                ))
            }
        },
    };
    Ok((scene, settings))
}

/// Run the scene (`*out` receives a handle to free with
/// `rodkit_supercoil_free`). Returns RODKIT_STATUS_INFO_STRAND_CROSSING
/// when the buckled branch stopped at a strand crossing,
/// RODKIT_STATUS_INFO_STEP_LIMIT at the step limit, ..._INFO_STEP_TOO_SMALL
/// when it could not go on; the path so far is in the handle in each case.
#[no_mangle]
pub unsafe extern "C" fn rodkit_dna_supercoil_run(spec: *const DnaSupercoilSpec, out: *mut *mut Supercoil) -> i32 {
    guard(|| {
        let out = arg_mut("out", out)?;
        *out = std::ptr::null_mut();
        let (scene, settings) = scene_of(arg_ref("spec", spec)?).map_err(|e| qualify_argument(e, "spec."))?;
        let run = run_scene(&scene, &settings)?;
        let status = match &run.buckled {
            Some(b) if b.contact.is_some() => Status::InfoStrandCrossing,
            Some(b) => match b.stop {
                crate::continuation::Stop::MaxSteps => Status::InfoStepLimit,
                crate::continuation::Stop::StepTooSmall => Status::InfoStepTooSmall,
                _ => Status::Ok,
            },
            None => Status::Ok,
        };
        *out = Box::into_raw(Box::new(Supercoil { run }));
        Ok(status)
    })
}

/// Free a handle (NULL is ignored).
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_free(run: *mut Supercoil) {
    let _ = super::guard_value((), || {
        if !run.is_null() {
            drop(Box::from_raw(run));
        }
    });
}

/// Summary of a run.
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_summary(run: *const Supercoil, info: *mut SupercoilInfo) -> i32 {
    guard(|| {
        let r = &arg_ref("run", run)?.run;
        let out = arg_mut("info", info)?;
        let two_pi = 2.0 * std::f64::consts::PI;
        let mut i = SupercoilInfo {
            points: r.points.len() as i64,
            straight_points: r.points.iter().filter(|p| p.branch == 0).count() as i64,
            nodes: r.rod.elements as i64 + 1,
            buckled: r.buckling.is_some() as i32,
            buckling_turns: r.buckling.map_or(f64::NAN, |b| b.0 / two_pi),
            buckling_torque: r.buckling.map_or(f64::NAN, |b| b.1),
            crossing_distance: f64::NAN,
            crossing_s1: f64::NAN,
            crossing_s2: f64::NAN,
            kappa: r.charge.screening.kappa,
            bjerrum_length: r.scene.bjerrum_length(),
            line_charge_squared: r.charge.line_charge * r.charge.line_charge,
            cutoff_on: f64::NAN,
            cutoff_off: f64::NAN,
            seconds: r.seconds,
            base_pair_charges: r.charge.base_pairs.map_or(0, |b| ((r.rod.length / b).round() as i64).max(1)),
            ..Default::default()
        };
        if let Some((on, off)) = r.charge.cutoff(r.rod.length) {
            i.cutoff_on = on;
            i.cutoff_off = off;
        }
        for b in std::iter::once(&r.straight).chain(r.buckled.as_ref()) {
            i.steps += b.counts.steps as i64;
            i.factorisations += b.counts.factorisations as i64;
            i.residuals += b.counts.residuals as i64;
            i.pair_lists += b.pair_lists as i64;
        }
        if let Some(c) = r.buckled.as_ref().and_then(|b| b.contact) {
            i.crossing = 1;
            i.crossing_distance = c.distance;
            i.crossing_s1 = c.s1;
            i.crossing_s2 = c.s2;
        }
        *out = i;
        Ok(Status::Ok)
    })
}

/// Copy the path's points (at most `capacity`; `*count` receives the
/// number of points; RODKIT_STATUS_INFO_TRUNCATED when they did not fit).
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_points(
    run: *const Supercoil,
    points: *mut SupercoilPoint,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let r = &arg_ref("run", run)?.run;
        let count = arg_mut("count", count)?;
        error::count_in_range("capacity", capacity, 0, i64::MAX)?;
        *count = r.points.len() as i64;
        let k = (capacity as usize).min(r.points.len());
        if k > 0 {
            if points.is_null() {
                return Err(null_error("points"));
            }
            let out = std::slice::from_raw_parts_mut(points, k);
            for (o, p) in out.iter_mut().zip(&r.points) {
                let ob = p.observables;
                *o = SupercoilPoint {
                    turns: ob.turns,
                    extension: ob.extension,
                    torque: ob.torque,
                    tension: ob.tension,
                    twist: ob.twist,
                    writhe: ob.writhe,
                    branch: p.branch as i32,
                    residual: p.residual,
                };
            }
        }
        Ok(if k < r.points.len() { Status::InfoTruncated } else { Status::Ok })
    })
}

/// Node positions (nm) of point `point`: xyz[k + ld·i], i < nodes.
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_positions(
    run: *const Supercoil,
    point: i64,
    xyz: *mut f64,
    ld: i64,
    nodes: i64,
) -> i32 {
    guard(|| {
        let r = &arg_ref("run", run)?.run;
        error::count_in_range("point", point, 0, r.points.len() as i64 - 1)?;
        error::count_in_range("ld", ld, 3, i64::MAX / 64)?;
        let want = r.rod.elements as i64 + 1;
        if nodes != want {
            return Err(Error::new(
                Status::ErrInvalidDimension,
                format!("argument `nodes` must be {want} (got {nodes})"),
            ));
        }
        if xyz.is_null() {
            return Err(null_error("xyz"));
        }
        let len = (ld as usize) * (nodes as usize - 1) + 3;
        let out = std::slice::from_raw_parts_mut(xyz, len);
        for (i, p) in r.rod.positions(&r.states[point as usize]).iter().enumerate() {
            out[i * ld as usize..i * ld as usize + 3].copy_from_slice(p);
        }
        Ok(Status::Ok)
    })
}

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
        use crate::charged::equilibrium::{solve_point, EquilibriumSolver as Solver};
        let r = &arg_ref("run", run)?.run;
        let s = *arg_ref("spec", spec)?;
        let out = arg_mut("out", out)?;
        error::count_in_range("point", point, 0, r.points.len() as i64 - 1)?;
        let q = |e: Error| qualify_argument(e, "spec.");
        let solver = match s.solver {
            1 => Solver::Direct,
            2 => Solver::NewtonKrylov,
            v => return Err(Error::new(Status::ErrOutOfRange, format!("argument `spec.solver` must be RODKIT_EQUILIBRIUM_SOLVER_DIRECT (1) or _NEWTON_KRYLOV (2) (got {v})"))),
        };
        // [0, 1]: 1 itself is refused by the model's own validation.
        error::in_range("cutoff_tolerance", s.cutoff_tolerance, 0.0, 1.0).map_err(q)?;
        error::positive("residual_tol", s.residual_tol).map_err(q)?;
        let mut charge = r.charge.clone();
        charge.cutoff_tolerance = (s.cutoff_tolerance > 0.0).then_some(s.cutoff_tolerance);
        charge.base_pairs = flag("discrete_base_pairs", s.discrete_base_pairs).map_err(q)?.then_some(r.scene.rise);
        let want = r.rod.elements as i64 + 1;
        if !xyz.is_null() {
            error::count_in_range("ld", ld, 3, i64::MAX / 64)?;
            if nodes != want {
                return Err(Error::new(
                    Status::ErrInvalidDimension,
                    format!("argument `nodes` must be {want} (got {nodes})"),
                ));
            }
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
            let len = (ld as usize) * (nodes as usize - 1) + 3;
            let dst = std::slice::from_raw_parts_mut(xyz, len);
            for (i, v) in r.rod.positions(&p.state).iter().enumerate() {
                dst[i * ld as usize..i * ld as usize + 3].copy_from_slice(v);
            }
        }
        Ok(Status::Ok)
    })
}

//! DNA supercoiling from C and Fortran: a charged Kirchhoff rod clamped at
//! both ends under fixed tension, continued in the end rotation from the
//! straight rod through its first buckling point along the buckled branch.
//! One call runs the scene into a handle; accessors copy the path (turns,
//! extension, torque, twist, writhe) and the shapes.

use super::args::{arg_mut, arg_ref, c_enum, check_nodes, copy_out, enum_arg, flag, free_handle, non_negative};
use super::args::{finite_fields, qualify_argument, write_positions};
use super::branch::{BranchCallback, BranchProgress};
use super::error::copy_message;
use super::{guard, guard_value};
use crate::charged::dna::{self, run_scene_with, DnaScene, PointProgress, RunStop, SupercoilRun, SupercoilSettings};
use crate::continuation::Stop;
use crate::electrostatics::discrete::base_pair_count;
use crate::error::{self, Error, Result};
use crate::status::Status;
use std::ffi::{c_char, c_void};

/// A supercoiling scene in nm, pN, mol/L. Call
/// `rodkit_dna_supercoil_spec_default` first: 1 kbp, 1 pN, 0.1 M, ν = 1/l_B
/// (Manning), a = 1 nm, A = 50 nm, P = 95 nm, 298.15 K, ε_r = 78.4; the
/// automatic mesh (elements 0: 2 nm elements of Gauss(2), 170 for 1 kbp);
/// cutoff tolerance 1e-4; no hard core; 1 thread; to
/// 12 turns in at most 600 steps; scaled residual 1e-8; the continuum model;
/// tolerance 1e-3.
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
    /// Elements (2 … 2^18), or 0: the automatic mesh — elements of at most
    /// 2 nm (⌈L / 2 nm⌉, at least 8), within ~3e-4 of a converged curve's
    /// torque and extension at 1 pN, 0.1 M (not within 1e-3 at 0.2 M:
    /// ~7e-3); the result's `nodes` − 1 says how many were taken.
    pub elements: i64,
    /// Gauss–Legendre stages (1…4).
    pub stages: i64,
    /// Screening cutoff's relative energy tolerance; 0: every pair.
    pub cutoff_tolerance: f64,
    /// Hard-core stiffness k_hc (pN/nm⁴) below 2.5a. 0 (the default):
    /// none until the buckled branch's strands cross (axes closer than
    /// 2a), then switched on by itself at k_hc = 4 k_BT/a⁵ from the point
    /// before the crossing (the summary's `hard_core_switched_turns` says
    /// where); < 0: none, the run stops at a crossing with
    /// RODKIT_STATUS_INFO_STRAND_CROSSING.
    pub hard_core: f64,
    /// Threads (1…256) for the pair forces; with 2 or more the buckled
    /// branch's records also take their determinant signs on a second
    /// thread while the next step is corrected (rods of 3000 unknowns or
    /// more: 77 elements of Gauss(2), ~450 bp on the automatic mesh).
    /// Results are bitwise the same for any count. The progress callback
    /// is always called on the calling thread.
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
    /// The accuracy asked of the curve, relative (torque against the larger
    /// of its value and one turn's torque on the straight rod, 2πC/L), in
    /// (0, 0.1]; default 1e-3. What it sets today: the largest moment the
    /// buckled branch's unfolding couple may carry before a point is taken
    /// off the branch, a tenth of this of that torque (doc/physics.md §2).
    /// The mesh is not chosen from it yet: `elements` and `stages` are.
    pub tolerance: f64,
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
    /// The hard core the path ended with: k_hc (pN/nm⁴), 0 none; and
    /// whether the scene switched it on by itself (spec `hard_core` 0 and
    /// the strands crossed), from which turns.
    pub hard_core: f64,
    pub hard_core_switched: i32,
    pub hard_core_switched_turns: f64,
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

/// An opaque computed path. Immutable except through
/// rodkit_supercoil_resume, which extends it in place; a handle may move
/// between threads but is not to be used from two at once.
pub struct Supercoil {
    pub(super) run: SupercoilRun,
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
            tolerance: s.tolerance,
        };
        Ok(Status::Ok)
    })
}

c_enum!(EndControl, "a RodkitEndControl 1…2", [EndControl::Rotation, EndControl::Torque]);

fn scene_of(s: &DnaSupercoilSpec) -> Result<(DnaScene, SupercoilSettings)> {
    // Every double field finite, named by its C field.
    finite_fields(&[
        ("rise", s.rise),
        ("tension", s.tension),
        ("salt", s.salt),
        ("charge_per_length", s.charge_per_length),
        ("radius", s.radius),
        ("bending_persistence", s.bending_persistence),
        ("twist_persistence", s.twist_persistence),
        ("temperature", s.temperature),
        ("permittivity", s.permittivity),
        ("cutoff_tolerance", s.cutoff_tolerance),
        ("hard_core", s.hard_core),
        ("max_turns", s.max_turns),
        ("residual_tol", s.residual_tol),
    ])?;
    // A positive charge whose square underflows (λ² ∝ ν²) is neither the
    // uncharged rod nor a computable charged one (ν = 4.9e-324 panicked in
    // the charged Jacobian).
    if s.charge_per_length > 0.0 && s.charge_per_length < 1e-145 {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!(
                "argument `charge_per_length` out of range: must be 0 or at least 1e-145 (its square must be a normal \
                 double; got {:e})",
                s.charge_per_length
            ),
        ));
    }
    error::count_in_range("base_pairs", s.base_pairs, 10, 1 << 24)?;
    if s.elements != 0 {
        error::count_in_range("elements", s.elements, 2, 1 << 18)?;
    }
    error::count_in_range("stages", s.stages, 1, 4)?;
    error::count_in_range("threads", s.threads, 1, 256)?;
    error::count_in_range("max_steps", s.max_steps, 1, 1 << 24)?;
    error::finite("cutoff_tolerance", s.cutoff_tolerance)?;
    non_negative("cutoff_tolerance", s.cutoff_tolerance)?;
    error::finite("hard_core", s.hard_core)?;
    error::in_range("tolerance", s.tolerance, f64::MIN_POSITIVE, 0.1)?;
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
        hard_core_auto: s.hard_core == 0.0,
        threads: s.threads as usize,
        separate_signs_from: SupercoilSettings::default().separate_signs_from,
        stability: SupercoilSettings::default().stability,
        max_turns: s.max_turns,
        max_steps: s.max_steps as usize,
        residual_tol: s.residual_tol,
        base_pairs: flag("discrete_base_pairs", s.discrete_base_pairs)?,
        far_points: 0,
        near_width: SupercoilSettings::default().near_width,
        exact_near_width: SupercoilSettings::default().exact_near_width,
        breakpoints: None,
        control: match enum_arg::<EndControl>("end_control", s.end_control)? {
            EndControl::Rotation => dna::EndControl::Rotation,
            EndControl::Torque => dna::EndControl::Torque,
        },
        engine: dna::Engine::default(),
        lu_kind: None,
        corrector_aim: 3.0,
        unfolding_retakes: SupercoilSettings::default().unfolding_retakes,
        tolerance: s.tolerance,
        list_rule: Default::default(),
        anm: SupercoilSettings::default().anm,
    };
    Ok((scene, settings))
}

/// Run the scene (`*out` receives a handle to free with
/// `rodkit_supercoil_free`). Returns RODKIT_STATUS_INFO_STRAND_CROSSING
/// when the buckled branch stopped at a strand crossing,
/// RODKIT_STATUS_INFO_STEP_LIMIT at the step limit, ..._INFO_STEP_TOO_SMALL
/// when it could not go on, ..._INFO_FAILED_PARTWAY when the buckled
/// branch failed after it had points (a point kept leaving the branch's
/// unfolding parameter μ = 0 however short the step, or a correction
/// failed; rodkit_supercoil_failure gives the error and its message); the
/// path so far is in the handle in each case. A failure before the
/// buckled branch has a point returns its negative status, no handle.
#[no_mangle]
pub unsafe extern "C" fn rodkit_dna_supercoil_run(spec: *const DnaSupercoilSpec, out: *mut *mut Supercoil) -> i32 {
    // Guarded inside; the guard here keeps every export's body guarded.
    guard_value(Status::ErrInternal.code(), || rodkit_dna_supercoil_run_with(spec, None, std::ptr::null_mut(), out))
}

/// Why a supercoiling run returned (`rodkit_supercoil_stop`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SupercoilStop {
    /// The path went to its end (the run's status says how).
    Finished = 0,
    /// The progress callback stopped it: rodkit_supercoil_resume goes on.
    Cancelled = 1,
    /// The buckled branch failed partway (RODKIT_STATUS_INFO_FAILED_PARTWAY;
    /// rodkit_supercoil_failure gives the error): the path is kept up to
    /// its last good point; it cannot be resumed.
    Failed = 2,
}

/// The status of a run: its stop's.
fn run_status(run: &SupercoilRun) -> Status {
    match run.stop {
        RunStop::Cancelled => return Status::InfoCancelled,
        RunStop::Failed { .. } => return Status::InfoFailedPartway,
        RunStop::Finished => {}
    }
    match &run.buckled {
        Some(b) if b.contact.is_some() => Status::InfoStrandCrossing,
        Some(b) => match b.stop {
            Stop::MaxSteps => Status::InfoStepLimit,
            Stop::StepTooSmall => Status::InfoStepTooSmall,
            _ => Status::Ok,
        },
        None => Status::Ok,
    }
}

/// The run's progress closure forwarding each point to the C callback:
/// `points` counts the run's points, `lambda` is the continuation
/// parameter (φ in radians, or the end torque under a torque clamp).
///
/// # Safety
/// `cb`, when given, must be callable with `user_data`.
unsafe fn forward(cb: BranchCallback, user_data: *mut c_void) -> impl FnMut(&PointProgress) -> bool {
    move |p: &PointProgress| match cb {
        Some(cb) => {
            let told = BranchProgress {
                points: p.index as i64 + 1,
                lambda: p.parameter,
                residual: p.residual,
                tip_rotation: p.tip_rotation,
                branch: p.branch as i32,
                turns: p.turns,
                extension: p.extension,
                torque: p.torque,
            };
            cb(&told, user_data) == 0
        }
        None => true,
    }
}

/// rodkit_dna_supercoil_run with a progress callback (NULL: none), told
/// after each converged point of the path, in order, once: `points` (the
/// run's points so far), `lambda` (the continuation parameter: φ in
/// radians, or the end torque under a torque clamp), `residual`,
/// `tip_rotation`, and `branch` (0 straight, 1 buckled), `turns`,
/// `extension`, `torque`. A non-zero return stops the run after that
/// point: RODKIT_STATUS_INFO_CANCELLED with the path so far in `*out`
/// (rodkit_supercoil_resume continues it; a stop asked at the path's last
/// point changes nothing: the run has ended). The callback must not unwind
/// into rodkit (no C++ throw, no longjmp); it may call rodkit functions on
/// other handles. Other statuses as rodkit_dna_supercoil_run.
#[no_mangle]
pub unsafe extern "C" fn rodkit_dna_supercoil_run_with(
    spec: *const DnaSupercoilSpec,
    progress: BranchCallback,
    user_data: *mut c_void,
    out: *mut *mut Supercoil,
) -> i32 {
    guard(|| {
        let out = arg_mut("out", out)?;
        *out = std::ptr::null_mut();
        let (scene, settings) = scene_of(arg_ref("spec", spec)?).map_err(|e| qualify_argument(e, "spec."))?;
        let run = run_scene_with(&scene, &settings, forward(progress, user_data))?;
        let status = run_status(&run);
        *out = Box::into_raw(Box::new(Supercoil { run }));
        Ok(status)
    })
}

/// Continue, in place, a run its progress callback stopped, with the spec
/// it was run with, to the same end as the uninterrupted run (its points,
/// then the new ones; the buckled branch resumes with its own tangent,
/// step and pair list and gives the uninterrupted run's numbers; a run
/// stopped on the straight branch resumes by the continuation's resume,
/// its tangent recomputed there: the points then agree to the Newton
/// tolerance, not bitwise). `progress` as for
/// rodkit_dna_supercoil_run_with (its `points` go on counting), and may
/// stop the run again (RODKIT_STATUS_INFO_CANCELLED); it must not use
/// `run`. Returns the status of rodkit_dna_supercoil_run_with for the
/// resumed run; a finished run (or one that failed partway,
/// RODKIT_SUPERCOIL_STOP_FAILED) is left as it is and returns its status.
/// On a failure the handle stays valid and resumable.
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_resume(
    run: *mut Supercoil,
    progress: BranchCallback,
    user_data: *mut c_void,
) -> i32 {
    guard(|| {
        let r = &mut arg_mut("run", run)?.run;
        dna::resume(r, forward(progress, user_data))?;
        Ok(run_status(r))
    })
}

/// Why the run returned: a RodkitSupercoilStop into `*stop`.
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_stop(run: *const Supercoil, stop: *mut i32) -> i32 {
    guard(|| {
        let r = &arg_ref("run", run)?.run;
        *arg_mut("stop", stop)? = match r.stop {
            RunStop::Finished => SupercoilStop::Finished,
            RunStop::Cancelled => SupercoilStop::Cancelled,
            RunStop::Failed { .. } => SupercoilStop::Failed,
        } as i32;
        Ok(Status::Ok)
    })
}

/// Why a run failed partway (RODKIT_SUPERCOIL_STOP_FAILED): `*error`
/// receives the error's negative status (0 when the run did not fail) and
/// `buffer` (`capacity` ≥ 1 bytes) its message, always NUL-terminated
/// (empty when it did not fail); `length` (may be NULL) receives the full
/// message length in bytes, without the NUL. Returns RODKIT_STATUS_OK, or
/// RODKIT_STATUS_INFO_TRUNCATED when the message was cut to `capacity − 1`
/// bytes. The run's own report, kept with the handle (the call itself
/// succeeded, so rodkit_last_error_message is not its channel).
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_failure(
    run: *const Supercoil,
    error: *mut i32,
    buffer: *mut c_char,
    capacity: i64,
    length: *mut i64,
) -> i32 {
    guard(|| {
        let r = &arg_ref("run", run)?.run;
        let code = arg_mut("error", error)?;
        let failure = r.failure();
        let status = copy_message(failure.map_or(&b""[..], |e| e.message.as_bytes()), buffer, capacity, length)?;
        *code = failure.map_or(0, |e| e.status.code());
        Ok(status)
    })
}

/// Free a handle (NULL is ignored).
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_free(run: *mut Supercoil) {
    guard_value((), || free_handle(run));
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
            base_pair_charges: r.charge.base_pairs.map_or(0, |b| base_pair_count(r.rod.length, b) as i64),
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
        i.hard_core = r.charge.hard_core.unwrap_or(0.0);
        if let Some(sw) = r.hard_core_switch {
            i.hard_core_switched = 1;
            i.hard_core_switched_turns = r.points[i.straight_points as usize + sw.record].observables.turns;
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
/// cbindgen:fortran-arrays=[points]
#[no_mangle]
pub unsafe extern "C" fn rodkit_supercoil_points(
    run: *const Supercoil,
    points: *mut SupercoilPoint,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let r = &arg_ref("run", run)?.run;
        // A NULL `count` is reported before a bad `capacity` here, as always.
        arg_mut("count", count)?;
        copy_out("points", points, capacity, count, &r.points, |p| {
            let ob = p.observables;
            SupercoilPoint {
                turns: ob.turns,
                extension: ob.extension,
                torque: ob.torque,
                tension: ob.tension,
                twist: ob.twist,
                writhe: ob.writhe,
                branch: p.branch as i32,
                residual: p.residual,
            }
        })
    })
}

/// Node positions (nm) of point `point`: xyz[k + ld·i], i < nodes.
/// cbindgen:fortran-arrays=[xyz]
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
        check_nodes(ld, nodes, r.rod.elements + 1)?;
        write_positions(xyz, ld, &r.rod.positions(&r.states[point as usize]))?;
        Ok(Status::Ok)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run that failed partway reaches a C caller as such: the run's
    /// status RODKIT_STATUS_INFO_FAILED_PARTWAY (> 0: the path is valid),
    /// stop RODKIT_SUPERCOIL_STOP_FAILED, the error's status and message
    /// (copied whole, or cut with INFO_TRUNCATED and the full length), its
    /// points, and a resume that leaves it as it is. Reference: the Rust
    /// run itself (the reproducer of tests/supercoil_hard_core.rs with no
    /// retakes allowed: it ends at its 51st buckled point).
    #[test]
    fn a_run_that_failed_partway_reports_it_through_the_c_api() {
        let scene = DnaScene { base_pairs: 300, tension: 2.0, salt: 0.1, ..Default::default() };
        let settings = SupercoilSettings {
            elements: 40,
            max_steps: 110,
            max_turns: 3.0,
            corrector_aim: 5.0,
            hard_core_auto: false,
            unfolding_retakes: 0,
            ..Default::default()
        };
        let run = dna::run_scene(&scene, &settings).unwrap();
        let failure = run.failure().expect("failed partway").clone();
        let points = run.points.clone();
        let handle = Box::into_raw(Box::new(Supercoil { run }));
        unsafe {
            assert_eq!(run_status(&(*handle).run), Status::InfoFailedPartway);
            let mut stop = -1;
            assert_eq!(rodkit_supercoil_stop(handle, &mut stop), 0);
            assert_eq!(stop, SupercoilStop::Failed as i32);
            let (mut error, mut length) = (0, 0);
            let mut buffer = vec![1 as c_char; 1024];
            let st = rodkit_supercoil_failure(handle, &mut error, buffer.as_mut_ptr(), 1024, &mut length);
            let text = std::ffi::CStr::from_ptr(buffer.as_ptr()).to_str().unwrap();
            assert_eq!((st, error, text), (0, Status::ErrNotConverged.code(), failure.message.as_str()));
            assert_eq!(length, failure.message.len() as i64);
            let st = rodkit_supercoil_failure(handle, &mut error, buffer.as_mut_ptr(), 8, &mut length);
            assert_eq!((st, buffer[7], length), (Status::InfoTruncated.code(), 0, failure.message.len() as i64));
            let mut count = 0;
            let mut c_points = vec![SupercoilPoint::default(); points.len()];
            let st = rodkit_supercoil_points(handle, c_points.as_mut_ptr(), points.len() as i64, &mut count);
            assert_eq!((st, count), (0, points.len() as i64));
            assert_eq!(c_points.last().unwrap().turns, points.last().unwrap().observables.turns);
            assert_eq!(rodkit_supercoil_resume(handle, None, std::ptr::null_mut()), Status::InfoFailedPartway.code());
            assert_eq!((*handle).run.points, points);
            rodkit_supercoil_free(handle);
        }
    }
}

//! C ABI of the Cosserat rod and its continuation (physics.md §2): a rod
//! handle from a flat spec, continuation by the ANM or Newton into a branch
//! handle (records, states, node positions, bifurcations), resumption and
//! branch switching, and the discrete equations as plain `double*` kernels
//! for callers who drive their own solvers (SUNDIALS).

use super::{arg_mut, arg_ref, guard, null_error, qualify_argument};
use crate::continuation::anm::AnmOptions;
use crate::continuation::{Options, Problem, Record, Scaling, Stop};
use crate::error::{self, Error, Result};
use crate::rod::branch::{Method, RodBranch};
use crate::rod::model::{unwrap_rotation, Rod as Model, Supports};
use crate::rod::scheme::Scheme;
use crate::rod::{Frame, Load, Loads, RodLaw};
use crate::status::Status;
use nalgebra::{Matrix6, Vector3};
use std::ffi::c_void;

/// Supports of a rod (`RodkitRodSpec.supports`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RodSupports {
    /// s = 0 clamped at the origin along e3, s = L free (tip loads apply).
    Cantilever = 1,
    /// Both ends clamped; s = L at end_x…z + Λ·end_dx…dz with orientation
    /// end_q0…q3.
    Clamped = 2,
    /// Ball joints; an axial dead tip force (0, 0, P) only.
    Pinned = 3,
    /// Controlled end rotation (Greenhill): s = L on the axis, free to slide
    /// under the axial dead force `end_tension`, turned about e3 by φ with
    /// Λ = sin(φ/2) (records report φ in `end_rotation`). No tip loads.
    Twisted = 4,
    /// Controlled end moment (a torque clamp): as Twisted, but φ is free and
    /// Λ is the spatial end moment about e3 (records report φ in
    /// `end_rotation`, continuous along the branch). No tip loads.
    Torqued = 5,
}

/// How a load follows the rod (`*_frame` fields).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadFrame {
    /// No such load.
    None = 0,
    /// Fixed in space (spatial components).
    Dead = 1,
    /// Turns with the section (body components).
    Follower = 2,
}

/// Discretisation (`RodkitRodSpec.scheme`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RodScheme {
    /// Implicit midpoint rule, order 2.
    Midpoint = 1,
    /// Gauss–Legendre collocation with `stages` (2…4) stages, order 2·stages.
    Gauss = 2,
}

/// Continuation engine (`RodkitContinuationOptions.method`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContinuationMethod {
    /// Asymptotic numerical method: series of order anm_order per step.
    Anm = 1,
    /// Newton pseudo-arc-length continuation.
    Newton = 2,
}

/// Why a branch ended (`RodkitBranchInfo.stop`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BranchStop {
    /// Reached target_lambda (the last record is there).
    Target = 0,
    /// Λ left [lambda_min, lambda_max].
    LambdaRange = 1,
    /// max_steps reached.
    MaxSteps = 2,
    /// The progress callback asked to stop.
    Cancelled = 3,
    /// The step fell below min_step.
    StepTooSmall = 4,
}

/// A rod: law, length, supports, loads (each multiplied by the load
/// parameter Λ), discretisation. Initialise with `rodkit_rod_spec_default`.
/// Stiffness order (u1, u2, u3, v1, v2, v3) ↔ (m1, m2, m3, n1, n2, n3):
/// bending about d1, d2, twist, shear along d1, d2, stretch.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RodSpec {
    /// Length L > 0.
    pub length: f64,
    /// 1: Kirchhoff rod (inextensible, unshearable: only bending1, bending2,
    /// twist are used); 0: special Cosserat rod.
    pub kirchhoff: i32,
    pub bending1: f64,
    pub bending2: f64,
    pub twist: f64,
    pub shear1: f64,
    pub shear2: f64,
    pub stretch: f64,
    /// Hemitropic couplings (physics.md §2.2): twist–stretch g (u3·v3) and
    /// bend–shear c2 (u1·v1 and u2·v2). Default 0.
    pub twist_stretch: f64,
    pub bend_shear: f64,
    /// Intrinsic strains û (default 0) and v̂ (default (0, 0, 1)).
    pub intrinsic_u1: f64,
    pub intrinsic_u2: f64,
    pub intrinsic_u3: f64,
    pub intrinsic_v1: f64,
    pub intrinsic_v2: f64,
    pub intrinsic_v3: f64,
    /// RodkitRodSupports (default cantilever).
    pub supports: i32,
    /// Clamped: position and orientation (unit quaternion, scalar first) of
    /// the end s = L.
    pub end_x: f64,
    pub end_y: f64,
    pub end_z: f64,
    pub end_q0: f64,
    pub end_q1: f64,
    pub end_q2: f64,
    pub end_q3: f64,
    /// Clamped: the end moves by Λ·(end_dx, end_dy, end_dz) (default 0:
    /// fixed).
    pub end_dx: f64,
    pub end_dy: f64,
    pub end_dz: f64,
    /// Twisted and Torqued: the axial dead force at s = L (default 0).
    pub end_tension: f64,
    /// Loads: RodkitLoadFrame and vector (per length for distributed loads).
    pub tip_force_frame: i32,
    pub tip_force_x: f64,
    pub tip_force_y: f64,
    pub tip_force_z: f64,
    pub tip_moment_frame: i32,
    pub tip_moment_x: f64,
    pub tip_moment_y: f64,
    pub tip_moment_z: f64,
    pub distributed_force_frame: i32,
    pub distributed_force_x: f64,
    pub distributed_force_y: f64,
    pub distributed_force_z: f64,
    pub distributed_couple_frame: i32,
    pub distributed_couple_x: f64,
    pub distributed_couple_y: f64,
    pub distributed_couple_z: f64,
    /// RodkitRodScheme (default Gauss), stages (default 4), elements N
    /// (default 8).
    pub scheme: i32,
    pub stages: i64,
    pub elements: i64,
    /// Rod diameter for self-contact detection (0, the default: none).
    /// Branches report where non-neighbouring points come closer than it
    /// (RodkitBranchInfo.contact_*): the rod has no contact model.
    pub diameter: f64,
}

/// Continuation settings. Initialise with
/// `rodkit_continuation_options_default`. Arc length and relative
/// tolerances use the rod's scales (positions L, forces K_b/L², moments
/// K_b/L, Λ 1).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct ContinuationOptions {
    /// RodkitContinuationMethod (default ANM).
    pub method: i32,
    /// ANM series order P (2…60, default 20) and ε of the step rule
    /// (default 1e-10).
    pub anm_order: i64,
    pub anm_epsilon: f64,
    /// Stop exactly at this Λ (NaN, the default: no target).
    pub target_lambda: f64,
    /// Stop when Λ leaves [lambda_min, lambda_max] (default ±1e300).
    pub lambda_min: f64,
    pub lambda_max: f64,
    /// Step limit (default 1000).
    pub max_steps: i64,
    /// Residual tolerance of every returned point, relative to the
    /// equations' scales (default 1e-10).
    pub residual_tol: f64,
    /// Arc-length steps: first (Newton), minimum, maximum (defaults 0.05,
    /// 1e-10, 1).
    pub initial_step: f64,
    pub min_step: f64,
    pub max_step: f64,
    /// 1: detect and locate bifurcations (default 0), to bifurcation_tol in
    /// arc length (default 1e-10).
    pub detect_bifurcations: i32,
    pub bifurcation_tol: f64,
    /// 1: leave the start towards increasing Λ (default), 0: decreasing.
    pub increasing: i32,
    /// Dense output: `sample_count` loads Λ (borrowed for the call; NULL
    /// with 0, the default: none) at which the branch delivers points within
    /// residual_tol besides its records (rodkit_branch_samples). The ANM
    /// evaluates its series there (any Λ inside a step), Newton continuation
    /// interpolates and corrects.
    pub samples: *const f64,
    pub sample_count: i64,
    /// 1: the ANM steps on the series' Padé approximants where they reach
    /// further for the same ε (default 0: the polynomial).
    pub anm_pade: i32,
    /// Scaling override (borrowed for the call; NULL, the default: the
    /// rod's own — positions L, forces K_b/L², moments K_b/L, Λ 1): the
    /// typical magnitude of each of the rodkit_rod_unknowns unknowns, then
    /// of Λ (`scaling_count` = unknowns + 1, all positive). The arc length
    /// and every relative tolerance use it; with a phase condition μ keeps
    /// its own scale.
    pub scaling: *const f64,
    pub scaling_count: i64,
}

/// What the branch progress callback is told after each point.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct BranchProgress {
    /// Points so far (the start is point 1).
    pub points: i64,
    pub lambda: f64,
    pub residual: f64,
    /// Angle (radians) between the tip tangent and e3 at the point.
    pub tip_rotation: f64,
}

/// Branch progress callback: return 0 to continue, non-zero to stop
/// cleanly (the branch so far is returned with RODKIT_STATUS_INFO_CANCELLED).
/// It must not unwind into rodkit (no C++ throw, no longjmp); it may call
/// rodkit functions on other handles.
pub type BranchCallback = Option<unsafe extern "C" fn(progress: *const BranchProgress, user_data: *mut c_void) -> i32>;

/// One point of a branch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct BranchRecord {
    pub lambda: f64,
    /// Scaled residual max norm at the point.
    pub residual: f64,
    /// Arc length of the step that reached it.
    pub step: f64,
    /// sign det R_x (flips at folds and simple bifurcations) and sign det of
    /// the bordered tangent (flips at simple bifurcations only); 0 unknown.
    pub det_sign: f64,
    pub bordered_det_sign: f64,
    /// Signed smallest singular value of the bordered tangent (changes sign
    /// at every bifurcation); NaN when not tracked.
    pub test_function: f64,
    pub newton_iterations: i64,
    /// Negative pivots of the bordered tangent's LU factors (−1 unknown):
    /// with row pivoting on a non-symmetric tangent, not an inertia — its
    /// parity changes where the determinant signs do.
    pub negative_pivots: i64,
    /// Tip position r(L) and the angle (radians) between the tip tangent and e3.
    pub tip_x: f64,
    pub tip_y: f64,
    pub tip_z: f64,
    pub tip_rotation: f64,
    /// Spatial force and moment at s = 0 (the rod's internal force there).
    pub base_force_x: f64,
    pub base_force_y: f64,
    pub base_force_z: f64,
    pub base_moment_x: f64,
    pub base_moment_y: f64,
    pub base_moment_z: f64,
    /// The phase condition's unfolding parameter μ (0 without one).
    pub unfolding: f64,
    /// Twisted supports: the end rotation φ = 2 atan2(Λ, cos(φ/2))
    /// (radians, following the turns past π); torqued supports: φ, in
    /// (−2π, 2π] at the branch's first record and continuous from there
    /// (±4π unwrapped between records); 0 otherwise.
    pub end_rotation: f64,
}

/// Summary of a branch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct BranchInfo {
    pub records: i64,
    pub bifurcations: i64,
    /// RodkitBranchStop.
    pub stop: i32,
    /// 1 if followed with a phase condition (states carry μ last).
    pub phase_condition: i32,
    /// Length of each state (rodkit_rod_unknowns, + 1 with a phase condition).
    pub state_length: i64,
    /// Points delivered at the requested sample loads, and requested loads
    /// the branch crossed where the correction failed.
    pub samples: i64,
    pub missed_samples: i64,
    /// Work: steps, factorisations, linear solves, residual and Jacobian
    /// evaluations, ANM series orders.
    pub steps: i64,
    pub factorisations: i64,
    pub solves: i64,
    pub residuals: i64,
    pub jacobians: i64,
    pub series_orders: i64,
    /// Self-contact (with a diameter): the first record where
    /// non-neighbouring points are closer than the diameter (−1: none),
    /// that distance and the pair's arc lengths.
    pub contact_record: i64,
    pub contact_distance: f64,
    pub contact_s1: f64,
    pub contact_s2: f64,
}

/// A located bifurcation point.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct Bifurcation {
    pub lambda: f64,
    /// 1 simple, 2 double (rotational symmetry).
    pub multiplicity: i64,
    /// The three smallest singular values of the bordered tangent there.
    pub sigma1: f64,
    pub sigma2: f64,
    pub sigma3: f64,
    /// 1 if det of the bordered tangent changed sign across it.
    pub det_sign_change: i32,
    pub tip_x: f64,
    pub tip_y: f64,
    pub tip_z: f64,
}

/// Opaque rod handle. The continuation functions only read it (several
/// threads may continue the same rod at once); the kernel functions
/// (rodkit_rod_residual, _jacobian) use its work buffers: do not call them
/// on one handle from several threads at the same time.
pub struct Rod {
    model: Model,
    system: crate::continuation::system::AssembledSystem,
    /// Kernel outputs are computed here, checked finite, then copied: a
    /// failing call writes nothing, and no call allocates.
    scratch_r: Vec<f64>,
    scratch_values: Vec<f64>,
    scratch_dl: Vec<f64>,
}

/// Opaque branch handle (immutable once returned).
pub struct Branch {
    branch: RodBranch,
    records: Vec<BranchRecord>,
    samples: Vec<BranchRecord>,
    state_length: usize,
    /// The rod it was computed with: a branch handed back with another rod
    /// is refused (its states would be misread).
    model: Model,
}

fn frame(name: &str, v: i32) -> Result<Option<Frame>> {
    match v {
        0 => Ok(None),
        1 => Ok(Some(Frame::Dead)),
        2 => Ok(Some(Frame::Follower)),
        _ => {
            Err(Error::new(Status::ErrOutOfRange, format!("argument `{name}` must be a RodkitLoadFrame 0…2 (got {v})")))
        }
    }
}

fn load(name: &str, f: i32, x: f64, y: f64, z: f64) -> Result<Option<Load>> {
    Ok(match frame(&format!("{name}_frame"), f)? {
        None => None,
        Some(frame) => {
            for (c, v) in [("x", x), ("y", y), ("z", z)] {
                error::finite(&format!("{name}_{c}"), v)?;
            }
            Some(Load { frame, vector: [x, y, z] })
        }
    })
}

fn model_from(s: &RodSpec, general: Option<Matrix6<f64>>) -> Result<Model> {
    let intrinsic_u = Vector3::new(s.intrinsic_u1, s.intrinsic_u2, s.intrinsic_u3);
    let intrinsic_v = Vector3::new(s.intrinsic_v1, s.intrinsic_v2, s.intrinsic_v3);
    for (n, v) in [
        ("intrinsic_u1", s.intrinsic_u1),
        ("intrinsic_u2", s.intrinsic_u2),
        ("intrinsic_u3", s.intrinsic_u3),
        ("intrinsic_v1", s.intrinsic_v1),
        ("intrinsic_v2", s.intrinsic_v2),
        ("intrinsic_v3", s.intrinsic_v3),
    ] {
        error::finite(n, v)?;
    }
    let kirchhoff = match s.kirchhoff {
        0 => false,
        1 => true,
        v => return Err(Error::new(Status::ErrOutOfRange, format!("argument `kirchhoff` must be 0 or 1 (got {v})"))),
    };
    let law = if let Some(k) = general {
        let mut law = RodLaw::general(k, intrinsic_u, intrinsic_v)?;
        law.kirchhoff = kirchhoff;
        law
    } else if kirchhoff {
        let mut law = RodLaw::kirchhoff(s.bending1, s.bending2, s.twist)?;
        law.intrinsic_u = intrinsic_u;
        law.intrinsic_v = intrinsic_v;
        law
    } else {
        for (n, v) in [
            ("bending1", s.bending1),
            ("bending2", s.bending2),
            ("twist", s.twist),
            ("shear1", s.shear1),
            ("shear2", s.shear2),
            ("stretch", s.stretch),
        ] {
            error::positive(n, v)?;
        }
        error::finite("twist_stretch", s.twist_stretch)?;
        error::finite("bend_shear", s.bend_shear)?;
        let mut k = Matrix6::from_diagonal(&nalgebra::Vector6::new(
            s.bending1, s.bending2, s.twist, s.shear1, s.shear2, s.stretch,
        ));
        for (i, j, v) in [(2, 5, s.twist_stretch), (0, 3, s.bend_shear), (1, 4, s.bend_shear)] {
            k[(i, j)] = v;
            k[(j, i)] = v;
        }
        RodLaw::general(k, intrinsic_u, intrinsic_v)?
    };
    let supports = match s.supports {
        1 => Supports::Cantilever,
        2 => Supports::Clamped {
            end_position: [s.end_x, s.end_y, s.end_z],
            end_rotation: [s.end_q0, s.end_q1, s.end_q2, s.end_q3],
            end_displacement: [s.end_dx, s.end_dy, s.end_dz],
        },
        3 => Supports::Pinned,
        4 => Supports::Twisted { tension: s.end_tension },
        5 => Supports::Torqued { tension: s.end_tension },
        v => {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!("argument `supports` must be a RodkitRodSupports 1…5 (got {v})"),
            ))
        }
    };
    let loads = Loads {
        tip_force: load("tip_force", s.tip_force_frame, s.tip_force_x, s.tip_force_y, s.tip_force_z)?,
        tip_moment: load("tip_moment", s.tip_moment_frame, s.tip_moment_x, s.tip_moment_y, s.tip_moment_z)?,
        distributed_force: load(
            "distributed_force",
            s.distributed_force_frame,
            s.distributed_force_x,
            s.distributed_force_y,
            s.distributed_force_z,
        )?,
        distributed_couple: load(
            "distributed_couple",
            s.distributed_couple_frame,
            s.distributed_couple_x,
            s.distributed_couple_y,
            s.distributed_couple_z,
        )?,
    };
    let scheme = match s.scheme {
        1 => Scheme::Midpoint,
        2 => {
            error::count_in_range("stages", s.stages, 2, 4)?;
            Scheme::Gauss(s.stages as usize)
        }
        v => {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!("argument `scheme` must be a RodkitRodScheme 1…2 (got {v})"),
            ))
        }
    };
    error::count_in_range("elements", s.elements, 1, 1 << 20)?;
    let model = Model::new(law, s.length, loads, supports, scheme, s.elements as usize)?;
    if s.diameter == 0.0 {
        Ok(model)
    } else {
        model.with_diameter(s.diameter)
    }
}

unsafe fn options_from(o: &ContinuationOptions, unknowns: usize) -> Result<(Options, Method, bool)> {
    let method = match o.method {
        1 => {
            if !(2..=60).contains(&o.anm_order) {
                return Err(Error::new(
                    Status::ErrOutOfRange,
                    format!("argument `anm_order` must lie in [2, 60] (got {})", o.anm_order),
                ));
            }
            error::in_range("anm_epsilon", o.anm_epsilon, 1e-15, 1e-1)?;
            let pade = match o.anm_pade {
                0 => false,
                1 => true,
                v => {
                    return Err(Error::new(
                        Status::ErrOutOfRange,
                        format!("argument `anm_pade` must be 0 or 1 (got {v})"),
                    ))
                }
            };
            Method::Anm(AnmOptions { order: o.anm_order as usize, epsilon: o.anm_epsilon, pade })
        }
        2 => Method::Newton,
        v => {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!("argument `method` must be a RodkitContinuationMethod 1…2 (got {v})"),
            ))
        }
    };
    error::finite("lambda_min", o.lambda_min)?;
    error::finite("lambda_max", o.lambda_max)?;
    if !(o.lambda_min < o.lambda_max) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!("need lambda_min ({:e}) < lambda_max ({:e})", o.lambda_min, o.lambda_max),
        ));
    }
    error::count_in_range("max_steps", o.max_steps, 0, 1 << 30)?;
    let target = if o.target_lambda.is_nan() { None } else { Some(error::finite("target_lambda", o.target_lambda)?) };
    let flag = |name: &str, v: i32| match v {
        0 => Ok(false),
        1 => Ok(true),
        _ => Err(Error::new(Status::ErrOutOfRange, format!("argument `{name}` must be 0 or 1 (got {v})"))),
    };
    let opts = Options {
        target_lambda: target,
        lambda_range: (o.lambda_min, o.lambda_max),
        max_steps: o.max_steps as usize,
        residual_tol: o.residual_tol,
        initial_step: o.initial_step,
        min_step: o.min_step,
        max_step: o.max_step,
        track_singular: false,
        detect_bifurcations: flag("detect_bifurcations", o.detect_bifurcations)?,
        bifurcation_tol: o.bifurcation_tol,
        scaling: if o.scaling.is_null() && o.scaling_count == 0 {
            None
        } else {
            check_len("scaling_count", o.scaling_count, unknowns as i64 + 1)?;
            let s = in_slice("scaling", o.scaling, o.scaling_count)?;
            if let Some(k) = s.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
                return Err(Error::new(
                    Status::ErrNotPositive,
                    format!("argument `scaling[{k}]` must be positive and finite (got {:e})", s[k]),
                ));
            }
            Some(Scaling { x: s[..unknowns].to_vec(), lambda: s[unknowns] })
        },
        samples: if o.sample_count == 0 && o.samples.is_null() {
            Vec::new()
        } else {
            error::count_in_range("sample_count", o.sample_count, 0, 1 << 24)?;
            let s = in_slice("samples", o.samples, o.sample_count)?;
            error::finite_result("samples", s)?;
            s.to_vec()
        },
    };
    Ok((opts, method, flag("increasing", o.increasing)?))
}

fn status_of(stop: Stop) -> Status {
    match stop {
        Stop::Target => Status::Ok,
        Stop::LambdaRange => Status::InfoLambdaRange,
        Stop::MaxSteps => Status::InfoStepLimit,
        Stop::Cancelled => Status::InfoCancelled,
        Stop::StepTooSmall => Status::InfoStepTooSmall,
    }
}

fn stop_code(stop: Stop) -> BranchStop {
    match stop {
        Stop::Target => BranchStop::Target,
        Stop::LambdaRange => BranchStop::LambdaRange,
        Stop::MaxSteps => BranchStop::MaxSteps,
        Stop::Cancelled => BranchStop::Cancelled,
        Stop::StepTooSmall => BranchStop::StepTooSmall,
    }
}

fn record_of(model: &Model, n: usize, lambda: f64, x: &[f64]) -> BranchRecord {
    let tip = model.tip(x);
    let (f, m) = model.spatial_force_moment(x, 0);
    BranchRecord {
        lambda,
        tip_x: tip[0],
        tip_y: tip[1],
        tip_z: tip[2],
        tip_rotation: model.tip_rotation(x),
        base_force_x: f[0],
        base_force_y: f[1],
        base_force_z: f[2],
        base_moment_x: m[0],
        base_moment_y: m[1],
        base_moment_z: m[2],
        unfolding: if x.len() > n { x[n] } else { 0.0 },
        end_rotation: model.end_rotation(x, lambda).unwrap_or(0.0),
        ..Default::default()
    }
}

/// The branch for C. `previous`: the end rotation (continuous) of the
/// point a resumed or switched branch leaves from, so that a torque
/// clamp's φ (known mod 4π from the state) continues across branches.
fn wrap(model: &Model, branch: RodBranch, previous: Option<f64>) -> Branch {
    let n = model.unknowns();
    let mut records: Vec<BranchRecord> = branch
        .records
        .iter()
        .zip(&branch.states)
        .map(|(r, x)| BranchRecord {
            residual: r.residual,
            step: r.step,
            det_sign: r.det_sign,
            bordered_det_sign: r.bordered_det_sign,
            test_function: r.smallest_singular_value.unwrap_or(f64::NAN),
            newton_iterations: r.newton_iterations as i64,
            negative_pivots: r.negative_pivots.map_or(-1, |v| v as i64),
            ..record_of(model, n, r.lambda, x)
        })
        .collect();
    let mut samples: Vec<BranchRecord> = branch
        .samples
        .iter()
        .zip(&branch.sample_states)
        .map(|(s, x)| BranchRecord {
            residual: s.residual,
            test_function: f64::NAN,
            newton_iterations: s.newton_iterations as i64,
            negative_pivots: -1,
            ..record_of(model, n, s.lambda, x)
        })
        .collect();
    if model.torqued() {
        // A torque clamp's φ from (cos φ/2, sin φ/2) is known mod 4π: turns
        // followed by continuity along the records (a step turns the end by
        // less than 2π), from the point the branch left if it is a resumed
        // or switched one; each sample from the record that starts its step
        // (samples at loads far apart may be turns apart from each other).
        let mut last = previous;
        for r in records.iter_mut() {
            if let Some(p) = last {
                r.end_rotation = unwrap_rotation(p, r.end_rotation);
            }
            last = Some(r.end_rotation);
        }
        for (rec, s) in samples.iter_mut().zip(&branch.samples) {
            if let Some(from) = records.get(s.record) {
                rec.end_rotation = unwrap_rotation(from.end_rotation, rec.end_rotation);
            }
        }
    }
    let state_length = n + branch.phase.is_some() as usize;
    Branch { branch, records, samples, state_length, model: model.clone() }
}

/// The branch, checked to belong to `rod`.
fn same_rod<'a>(rod: &Rod, branch: &'a Branch) -> Result<&'a Branch> {
    if branch.model != rod.model {
        return Err(Error::new(Status::ErrOutOfRange, "argument `branch` was computed with another rod than `rod`"));
    }
    Ok(branch)
}

/// Run `f` with a Rust progress closure forwarding to the C callback.
unsafe fn with_progress<T>(
    model: &Model,
    cb: BranchCallback,
    user_data: *mut c_void,
    f: impl FnOnce(&mut dyn FnMut(&Record) -> bool) -> Result<T>,
) -> Result<T> {
    let mut points = 0i64;
    let mut forward = |r: &Record| -> bool {
        points += 1;
        match cb {
            Some(cb) => {
                // The branch's records carry the state as their outputs.
                let tip_rotation =
                    if r.outputs.len() >= model.unknowns() { model.tip_rotation(&r.outputs) } else { f64::NAN };
                cb(&BranchProgress { points, lambda: r.lambda, residual: r.residual, tip_rotation }, user_data) == 0
            }
            None => true,
        }
    };
    f(&mut forward)
}

/// Fill `spec` with defaults: every physical field NaN (unset), couplings
/// and intrinsic curvature 0, v̂ = (0, 0, 1), cantilever, no loads,
/// Gauss–Legendre with 4 stages on 8 elements.
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_spec_default(spec: *mut RodSpec) -> i32 {
    guard(|| {
        let n = f64::NAN;
        *arg_mut("spec", spec)? = RodSpec {
            length: n,
            kirchhoff: 0,
            bending1: n,
            bending2: n,
            twist: n,
            shear1: n,
            shear2: n,
            stretch: n,
            twist_stretch: 0.0,
            bend_shear: 0.0,
            intrinsic_u1: 0.0,
            intrinsic_u2: 0.0,
            intrinsic_u3: 0.0,
            intrinsic_v1: 0.0,
            intrinsic_v2: 0.0,
            intrinsic_v3: 1.0,
            supports: RodSupports::Cantilever as i32,
            end_x: n,
            end_y: n,
            end_z: n,
            end_q0: 1.0,
            end_q1: 0.0,
            end_q2: 0.0,
            end_q3: 0.0,
            end_dx: 0.0,
            end_dy: 0.0,
            end_dz: 0.0,
            end_tension: 0.0,
            tip_force_frame: 0,
            tip_force_x: 0.0,
            tip_force_y: 0.0,
            tip_force_z: 0.0,
            tip_moment_frame: 0,
            tip_moment_x: 0.0,
            tip_moment_y: 0.0,
            tip_moment_z: 0.0,
            distributed_force_frame: 0,
            distributed_force_x: 0.0,
            distributed_force_y: 0.0,
            distributed_force_z: 0.0,
            distributed_couple_frame: 0,
            distributed_couple_x: 0.0,
            distributed_couple_y: 0.0,
            distributed_couple_z: 0.0,
            scheme: RodScheme::Gauss as i32,
            stages: 4,
            elements: 8,
            diameter: 0.0,
        };
        Ok(Status::Ok)
    })
}

/// Fill `options` with the defaults documented on its fields.
#[no_mangle]
pub unsafe extern "C" fn rodkit_continuation_options_default(options: *mut ContinuationOptions) -> i32 {
    guard(|| {
        let d = Options::default();
        *arg_mut("options", options)? = ContinuationOptions {
            method: ContinuationMethod::Anm as i32,
            anm_order: 20,
            anm_epsilon: 1e-10,
            target_lambda: f64::NAN,
            lambda_min: -1e300,
            lambda_max: 1e300,
            max_steps: d.max_steps as i64,
            residual_tol: d.residual_tol,
            initial_step: d.initial_step,
            min_step: d.min_step,
            max_step: d.max_step,
            detect_bifurcations: 0,
            bifurcation_tol: d.bifurcation_tol,
            increasing: 1,
            samples: std::ptr::null(),
            sample_count: 0,
            anm_pade: 0,
            scaling: std::ptr::null(),
            scaling_count: 0,
        };
        Ok(Status::Ok)
    })
}

unsafe fn store_rod(model: Model, out: *mut *mut Rod) -> Result<Status> {
    let slot = arg_mut("out", out)?;
    *slot = std::ptr::null_mut();
    let system = model.system()?;
    let n = model.unknowns();
    let nnz = system.pattern().nnz();
    *slot = Box::into_raw(Box::new(Rod {
        model,
        system,
        scratch_r: vec![0.0; n],
        scratch_values: vec![0.0; nnz],
        scratch_dl: vec![0.0; n],
    }));
    Ok(Status::Ok)
}

/// Create a rod from `spec` (validated: a message names the bad field).
/// On failure `*out` is NULL.
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_new(spec: *const RodSpec, out: *mut *mut Rod) -> i32 {
    guard(|| {
        if let Some(o) = out.as_mut() {
            *o = std::ptr::null_mut();
        }
        let spec = arg_ref("spec", spec)?;
        let model = model_from(spec, None).map_err(|e| qualify_argument(e, "spec."))?;
        store_rod(model, out)
    })
}

/// As rodkit_rod_new with a general symmetric positive-definite 6×6
/// stiffness (column-major, leading dimension `ldk` ≥ 6, order (u, v)) in
/// place of the spec's moduli (bending1…bend_shear are ignored).
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_new_general(
    spec: *const RodSpec,
    stiffness: *const f64,
    ldk: i64,
    out: *mut *mut Rod,
) -> i32 {
    guard(|| {
        if let Some(o) = out.as_mut() {
            *o = std::ptr::null_mut();
        }
        let spec = arg_ref("spec", spec)?;
        error::count_in_range("ldk", ldk, 6, i64::MAX / 64)?;
        if stiffness.is_null() {
            return Err(null_error("stiffness"));
        }
        let a = std::slice::from_raw_parts(stiffness, ldk as usize * 5 + 6);
        let k = Matrix6::from_fn(|i, j| a[i + j * ldk as usize]);
        let model = model_from(spec, Some(k)).map_err(|e| qualify_argument(e, "spec."))?;
        store_rod(model, out)
    })
}

/// Free a rod (NULL is accepted).
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_free(rod: *mut Rod) {
    super::guard_value((), || {
        if !rod.is_null() {
            drop(Box::from_raw(rod));
        }
    })
}

/// Number of unknowns n of the discrete system (the state x; Λ apart).
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_unknowns(rod: *const Rod, n: *mut i64) -> i32 {
    guard(|| {
        *arg_mut("n", n)? = arg_ref("rod", rod)?.model.unknowns() as i64;
        Ok(Status::Ok)
    })
}

/// The straight stress-free state (length n = rodkit_rod_unknowns).
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_straight_state(rod: *const Rod, x: *mut f64, n: i64) -> i32 {
    guard(|| {
        let rod = arg_ref("rod", rod)?;
        let want = rod.model.unknowns() as i64;
        check_len("n", n, want)?;
        let x = out_slice("x", x, n)?;
        x.copy_from_slice(&rod.model.straight_state());
        Ok(Status::Ok)
    })
}

fn check_len(name: &str, got: i64, want: i64) -> Result<()> {
    if got != want {
        return Err(Error::new(Status::ErrInvalidDimension, format!("argument `{name}` must be {want} (got {got})")));
    }
    Ok(())
}

unsafe fn in_slice<'a>(name: &str, p: *const f64, n: i64) -> Result<&'a [f64]> {
    if p.is_null() {
        return Err(null_error(name));
    }
    let s = std::slice::from_raw_parts(p, n as usize);
    error::finite_result(name, s).map_err(|e| Error::new(Status::ErrNotFinite, e.message))?;
    Ok(s)
}

unsafe fn out_slice<'a>(name: &str, p: *mut f64, n: i64) -> Result<&'a mut [f64]> {
    if p.is_null() {
        return Err(null_error(name));
    }
    Ok(std::slice::from_raw_parts_mut(p, n as usize))
}

unsafe fn store_branch(rod: &Rod, b: RodBranch, previous: Option<f64>, out: *mut *mut Branch) -> Result<Status> {
    let status = status_of(b.stop);
    *arg_mut("out", out)? = Box::into_raw(Box::new(wrap(&rod.model, b, previous)));
    Ok(status)
}

/// A torque clamp's continuous end rotation at bifurcation `index` of
/// `from`: its φ (mod 4π) unwrapped against the record nearest to it.
fn rotation_at_bifurcation(model: &Model, from: &Branch, index: usize) -> Option<f64> {
    let bif = from.branch.bifurcations.get(index)?;
    let raw = model.end_rotation(&bif.x, bif.lambda)?;
    let n = model.unknowns().min(bif.x.len());
    let distance = |x: &[f64]| x[..n].iter().zip(&bif.x[..n]).map(|(a, b)| (a - b) * (a - b)).sum::<f64>();
    let nearest = from.branch.states.iter().enumerate().min_by(|a, b| distance(a.1).total_cmp(&distance(b.1)))?.0;
    Some(unwrap_rotation(from.records.get(nearest)?.end_rotation, raw))
}

/// Follow a branch from the state `x0` (length n; NULL: the straight
/// state) at `lambda0`. Returns 0 when the target was reached, a positive
/// RODKIT_STATUS_INFO_* when the branch ended otherwise (the branch is
/// returned in every non-negative case), a negative status on failure
/// (`*out` NULL). `progress` may be NULL.
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_continue(
    rod: *const Rod,
    x0: *const f64,
    n: i64,
    lambda0: f64,
    options: *const ContinuationOptions,
    progress: BranchCallback,
    user_data: *mut c_void,
    out: *mut *mut Branch,
) -> i32 {
    guard(|| {
        if let Some(o) = out.as_mut() {
            *o = std::ptr::null_mut();
        }
        let rod = arg_ref("rod", rod)?;
        let (opts, method, increasing) = options_from(arg_ref("options", options)?, rod.model.unknowns())
            .map_err(|e| qualify_argument(e, "options."))?;
        let x0 = if x0.is_null() {
            None
        } else {
            check_len("n", n, rod.model.unknowns() as i64)?;
            Some(in_slice("x0", x0, n)?)
        };
        let b = with_progress(&rod.model, progress, user_data, |cb| {
            rod.model.continue_branch(x0, lambda0, increasing, &opts, method, cb)
        })?;
        store_branch(rod, b, None, out)
    })
}

/// Continue `branch` (of `rod`) from where it ended, with new options.
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_resume(
    rod: *const Rod,
    branch: *const Branch,
    options: *const ContinuationOptions,
    progress: BranchCallback,
    user_data: *mut c_void,
    out: *mut *mut Branch,
) -> i32 {
    guard(|| {
        if let Some(o) = out.as_mut() {
            *o = std::ptr::null_mut();
        }
        let rod = arg_ref("rod", rod)?;
        let from = same_rod(rod, arg_ref("branch", branch)?)?;
        let (opts, method, _) = options_from(arg_ref("options", options)?, rod.model.unknowns())
            .map_err(|e| qualify_argument(e, "options."))?;
        let b = with_progress(&rod.model, progress, user_data, |cb| {
            rod.model.resume_branch(&from.branch, &opts, method, cb)
        })?;
        let previous = rod.model.torqued().then(|| from.records.last().map(|r| r.end_rotation)).flatten();
        store_branch(rod, b, previous, out)
    })
}

/// Leave `branch` at its bifurcation `index` (0-based) along null direction
/// `direction` (0-based, < multiplicity) with first arc-length step
/// `first_step`. A double point of a symmetric rod is followed with a phase
/// condition (the branch's states then carry the unfolding parameter μ
/// last; see RodkitBranchInfo.phase_condition).
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_switch(
    rod: *const Rod,
    branch: *const Branch,
    index: i64,
    direction: i64,
    first_step: f64,
    options: *const ContinuationOptions,
    progress: BranchCallback,
    user_data: *mut c_void,
    out: *mut *mut Branch,
) -> i32 {
    guard(|| {
        if let Some(o) = out.as_mut() {
            *o = std::ptr::null_mut();
        }
        let rod = arg_ref("rod", rod)?;
        let from = same_rod(rod, arg_ref("branch", branch)?)?;
        error::count_in_range("index", index, 0, i64::MAX)?;
        error::count_in_range("direction", direction, 0, i64::MAX)?;
        let (opts, method, _) = options_from(arg_ref("options", options)?, rod.model.unknowns())
            .map_err(|e| qualify_argument(e, "options."))?;
        let b = with_progress(&rod.model, progress, user_data, |cb| {
            rod.model.switch_branch(&from.branch, index as usize, direction as usize, first_step, &opts, method, cb)
        })?;
        let previous = rod.model.torqued().then(|| rotation_at_bifurcation(&rod.model, from, index as usize)).flatten();
        store_branch(rod, b, previous, out)
    })
}

/// Free a branch (NULL is accepted).
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_free(branch: *mut Branch) {
    super::guard_value((), || {
        if !branch.is_null() {
            drop(Box::from_raw(branch));
        }
    })
}

/// Summary of a branch.
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_summary(branch: *const Branch, info: *mut BranchInfo) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        let c = b.branch.counts;
        *arg_mut("info", info)? = BranchInfo {
            records: b.records.len() as i64,
            bifurcations: b.branch.bifurcations.len() as i64,
            stop: stop_code(b.branch.stop) as i32,
            phase_condition: b.branch.phase.is_some() as i32,
            state_length: b.state_length as i64,
            samples: b.samples.len() as i64,
            missed_samples: b.branch.missed_samples.len() as i64,
            steps: c.steps as i64,
            factorisations: c.factorisations as i64,
            solves: c.solves as i64,
            residuals: c.residuals as i64,
            jacobians: c.jacobians as i64,
            series_orders: c.series_orders as i64,
            contact_record: b.branch.contact.map_or(-1, |c| c.record as i64),
            contact_distance: b.branch.contact.map_or(0.0, |c| c.distance),
            contact_s1: b.branch.contact.map_or(0.0, |c| c.s1),
            contact_s2: b.branch.contact.map_or(0.0, |c| c.s2),
        };
        Ok(Status::Ok)
    })
}

/// Copy up to `capacity` records into `records`; `count` receives the
/// number of records of the branch. Fewer than that copied:
/// RODKIT_STATUS_INFO_TRUNCATED (capacity 0 with records NULL is a size query).
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_records(
    branch: *const Branch,
    records: *mut BranchRecord,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        error::count_in_range("capacity", capacity, 0, i64::MAX)?;
        let total = b.records.len();
        *arg_mut("count", count)? = total as i64;
        let k = total.min(capacity as usize);
        if k > 0 {
            if records.is_null() {
                return Err(null_error("records"));
            }
            std::slice::from_raw_parts_mut(records, k).copy_from_slice(&b.records[..k]);
        }
        Ok(if k < total { Status::InfoTruncated } else { Status::Ok })
    })
}

/// Copy up to `capacity` of the points delivered at the requested sample
/// loads (RodkitContinuationOptions.samples), in branch order, as records
/// (step, determinant signs 0; test_function NaN: not tracked); `count`
/// receives their number. Truncation and size queries as for
/// rodkit_branch_records.
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_samples(
    branch: *const Branch,
    samples: *mut BranchRecord,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        error::count_in_range("capacity", capacity, 0, i64::MAX)?;
        let total = b.samples.len();
        *arg_mut("count", count)? = total as i64;
        let k = total.min(capacity as usize);
        if k > 0 {
            if samples.is_null() {
                return Err(null_error("samples"));
            }
            std::slice::from_raw_parts_mut(samples, k).copy_from_slice(&b.samples[..k]);
        }
        Ok(if k < total { Status::InfoTruncated } else { Status::Ok })
    })
}

/// The full state x of sample `sample` (length RodkitBranchInfo.state_length).
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_sample_state(branch: *const Branch, sample: i64, x: *mut f64, n: i64) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        error::count_in_range("sample", sample, 0, b.samples.len() as i64 - 1)?;
        check_len("n", n, b.state_length as i64)?;
        out_slice("x", x, n)?.copy_from_slice(&b.branch.sample_states[sample as usize]);
        Ok(Status::Ok)
    })
}

/// Copy up to `capacity` located bifurcations; `count` receives their number.
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_bifurcations(
    branch: *const Branch,
    rod: *const Rod,
    out: *mut Bifurcation,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let rod = arg_ref("rod", rod)?;
        let b = same_rod(rod, arg_ref("branch", branch)?)?;
        error::count_in_range("capacity", capacity, 0, i64::MAX)?;
        let total = b.branch.bifurcations.len();
        *arg_mut("count", count)? = total as i64;
        let k = total.min(capacity as usize);
        if k > 0 {
            if out.is_null() {
                return Err(null_error("out"));
            }
            let dst = std::slice::from_raw_parts_mut(out, k);
            for (d, bif) in dst.iter_mut().zip(&b.branch.bifurcations) {
                let tip = rod.model.tip(&bif.x);
                let s = |i: usize| bif.singular_values.get(i).copied().unwrap_or(f64::NAN);
                *d = Bifurcation {
                    lambda: bif.lambda,
                    multiplicity: bif.multiplicity as i64,
                    sigma1: s(0),
                    sigma2: s(1),
                    sigma3: s(2),
                    det_sign_change: bif.det_sign_change as i32,
                    tip_x: tip[0],
                    tip_y: tip[1],
                    tip_z: tip[2],
                };
            }
        }
        Ok(if k < total { Status::InfoTruncated } else { Status::Ok })
    })
}

/// The full state x at record `record` (length RodkitBranchInfo.state_length).
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_state(branch: *const Branch, record: i64, x: *mut f64, n: i64) -> i32 {
    guard(|| {
        let b = arg_ref("branch", branch)?;
        error::count_in_range("record", record, 0, b.records.len() as i64 - 1)?;
        check_len("n", n, b.state_length as i64)?;
        out_slice("x", x, n)?.copy_from_slice(&b.branch.states[record as usize]);
        Ok(Status::Ok)
    })
}

/// Node positions r(s_i), i = 0…N, of record `record`: xyz[k + ld·i]
/// (ld ≥ 3), for `nodes` = N + 1 nodes (the rod's elements + 1).
#[no_mangle]
pub unsafe extern "C" fn rodkit_branch_positions(
    branch: *const Branch,
    rod: *const Rod,
    record: i64,
    xyz: *mut f64,
    ld: i64,
    nodes: i64,
) -> i32 {
    guard(|| {
        let rod = arg_ref("rod", rod)?;
        let b = same_rod(rod, arg_ref("branch", branch)?)?;
        error::count_in_range("record", record, 0, b.records.len() as i64 - 1)?;
        error::count_in_range("ld", ld, 3, i64::MAX / 64)?;
        check_len("nodes", nodes, rod.model.elements as i64 + 1)?;
        let p = rod.model.positions(&b.branch.states[record as usize]);
        let len = ld.checked_mul(nodes - 1).and_then(|v| v.checked_add(3)).ok_or_else(|| {
            Error::new(Status::ErrOutOfRange, format!("argument `ld` ({ld}) times the nodes overflows"))
        })?;
        let out = out_slice("xyz", xyz, len)?;
        for (i, r) in p.iter().enumerate() {
            out[i * ld as usize..i * ld as usize + 3].copy_from_slice(r);
        }
        Ok(Status::Ok)
    })
}

/// Residual R(x, Λ) of the discrete equations (length n each), in the
/// form SUNDIALS' KINSOL calls: a user's KINSysFn wraps it with
/// N_VGetArrayPointer. Not thread-safe on one handle (work buffers).
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_residual(rod: *mut Rod, x: *const f64, n: i64, lambda: f64, r: *mut f64) -> i32 {
    guard(|| {
        let rod = arg_mut("rod", rod)?;
        check_len("n", n, rod.model.unknowns() as i64)?;
        error::finite("lambda", lambda)?;
        let x = in_slice("x", x, n)?;
        let out = out_slice("r", r, n)?;
        rod.system.residual(x, lambda, &mut rod.scratch_r);
        error::finite_result("residual", &rod.scratch_r)?;
        out.copy_from_slice(&rod.scratch_r);
        Ok(Status::Ok)
    })
}

/// The Jacobian's sparsity in compressed columns: col_ptr (n + 1 entries)
/// and row_idx (nnz entries, sorted within each column). `nnz` receives
/// the count; with capacity < nnz only the count is written
/// (RODKIT_STATUS_INFO_TRUNCATED; row_idx may then be NULL).
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_jacobian_pattern(
    rod: *const Rod,
    col_ptr: *mut i64,
    row_idx: *mut i64,
    capacity: i64,
    nnz: *mut i64,
) -> i32 {
    guard(|| {
        let rod = arg_ref("rod", rod)?;
        error::count_in_range("capacity", capacity, 0, i64::MAX)?;
        let p = rod.system.pattern();
        *arg_mut("nnz", nnz)? = p.nnz() as i64;
        if (capacity as usize) < p.nnz() {
            return Ok(Status::InfoTruncated);
        }
        if col_ptr.is_null() {
            return Err(null_error("col_ptr"));
        }
        if row_idx.is_null() {
            return Err(null_error("row_idx"));
        }
        let cp = std::slice::from_raw_parts_mut(col_ptr, p.n + 1);
        for (d, s) in cp.iter_mut().zip(&p.col_ptr) {
            *d = *s as i64;
        }
        let ri = std::slice::from_raw_parts_mut(row_idx, p.nnz());
        for (d, s) in ri.iter_mut().zip(&p.row_idx) {
            *d = *s as i64;
        }
        Ok(Status::Ok)
    })
}

/// ∂R/∂x at (x, Λ) in the order of rodkit_rod_jacobian_pattern (`values`,
/// `nnz` entries) and ∂R/∂Λ (`d_lambda`, n entries; may be NULL).
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_jacobian(
    rod: *mut Rod,
    x: *const f64,
    n: i64,
    lambda: f64,
    values: *mut f64,
    nnz: i64,
    d_lambda: *mut f64,
) -> i32 {
    guard(|| {
        let rod = arg_mut("rod", rod)?;
        check_len("n", n, rod.model.unknowns() as i64)?;
        check_len("nnz", nnz, rod.system.pattern().nnz() as i64)?;
        error::finite("lambda", lambda)?;
        let x = in_slice("x", x, n)?;
        let v = out_slice("values", values, nnz)?;
        let dl = if d_lambda.is_null() { None } else { Some(out_slice("d_lambda", d_lambda, n)?) };
        rod.system.jacobian(x, lambda, &mut rod.scratch_values, &mut rod.scratch_dl);
        error::finite_result("Jacobian", &rod.scratch_values)?;
        error::finite_result("d_lambda", &rod.scratch_dl)?;
        v.copy_from_slice(&rod.scratch_values);
        if let Some(dl) = dl {
            dl.copy_from_slice(&rod.scratch_dl);
        }
        Ok(Status::Ok)
    })
}

/// The rod ODE's right-hand side y' = f(y, Λ) (physics.md §2.1) for
/// y = (r, q, n_b, m_b) (13 entries each), without distributed loads'
/// dependence on s: for IDA-based shooting (IDAResFn: F = y' − f(y)).
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_rhs(rod: *const Rod, y: *const f64, lambda: f64, dy: *mut f64) -> i32 {
    guard(|| {
        let rod = arg_ref("rod", rod)?;
        error::finite("lambda", lambda)?;
        let y = in_slice("y", y, 13)?;
        let f = rod.model.rhs(y, lambda);
        error::finite_result("dy", &f)?;
        out_slice("dy", dy, 13)?.copy_from_slice(&f);
        Ok(Status::Ok)
    })
}

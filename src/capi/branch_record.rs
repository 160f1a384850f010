//! What a branch reports to C: `RodkitBranchRecord` (one point),
//! `RodkitBranchInfo` (the summary), `RodkitBifurcation` and
//! `RodkitBranchStop`, and their construction from a rod branch.

use crate::continuation::Stop;
use crate::rod::branch::RodBranch;
use crate::rod::model::Rod as Model;
use crate::status::Status;

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

/// A located bifurcation point with its place on the branch and the
/// evidence for it (rodkit_branch_bifurcation_points).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct BifurcationPoint {
    pub lambda: f64,
    /// The end rotation φ there (radians; continuous along the branch as
    /// the records' end_rotation is), under rotation control and under a
    /// torque clamp; 0 for a rod without one.
    pub end_rotation: f64,
    /// The record it follows: it lies between records `record` and
    /// `record + 1` (0-based).
    pub record: i64,
    /// 1 simple, 2 double (rotational symmetry).
    pub multiplicity: i64,
    /// The three smallest singular values of the bordered tangent there.
    pub sigma1: f64,
    pub sigma2: f64,
    pub sigma3: f64,
    /// Evidence: 1 if det of the bordered tangent changed sign across it;
    /// 1 if the records' test function (signed σ_min) changed sign over
    /// its bracket (0 for both: found as a dip of σ_min).
    pub det_sign_change: i32,
    pub test_function_change: i32,
    /// Tip position there.
    pub tip_x: f64,
    pub tip_y: f64,
    pub tip_z: f64,
}

/// The older record of a point: its first fields.
impl From<BifurcationPoint> for Bifurcation {
    fn from(p: BifurcationPoint) -> Self {
        Bifurcation {
            lambda: p.lambda,
            multiplicity: p.multiplicity,
            sigma1: p.sigma1,
            sigma2: p.sigma2,
            sigma3: p.sigma3,
            det_sign_change: p.det_sign_change,
            tip_x: p.tip_x,
            tip_y: p.tip_y,
            tip_z: p.tip_z,
        }
    }
}

/// A bracket of records where det of the bordered tangent or the test
/// function changed sign (or σ_min dipped) but no bifurcation accounting
/// for it was located (rodkit_branch_unresolved): the branch cannot vouch
/// for its bifurcations between these records.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct UnresolvedBifurcation {
    /// The bracket's first and last records (0-based) and their Λ.
    pub record_first: i64,
    pub record_last: i64,
    pub lambda_first: f64,
    pub lambda_last: f64,
    /// What asked for a location (1 each: det of the bordered tangent, the
    /// test function, changed sign over the bracket).
    pub det_sign_change: i32,
    pub test_function_change: i32,
}

/// The status of a branch's stop; a complete branch with unresolved
/// brackets says so (RODKIT_STATUS_INFO_UNRESOLVED_BIFURCATION).
pub(super) fn branch_status(branch: &RodBranch) -> Status {
    match status_of(branch.stop) {
        Status::Ok if !branch.unresolved.is_empty() => Status::InfoUnresolvedBifurcation,
        s => s,
    }
}

pub(super) fn status_of(stop: Stop) -> Status {
    match stop {
        Stop::Target => Status::Ok,
        Stop::LambdaRange => Status::InfoLambdaRange,
        Stop::MaxSteps => Status::InfoStepLimit,
        Stop::Cancelled => Status::InfoCancelled,
        Stop::StepTooSmall => Status::InfoStepTooSmall,
        // Not asked for through the C API (rod branches run to their end).
        Stop::Bifurcation => Status::Ok,
    }
}

pub(super) fn stop_code(stop: Stop) -> BranchStop {
    match stop {
        Stop::Target => BranchStop::Target,
        Stop::LambdaRange => BranchStop::LambdaRange,
        Stop::MaxSteps => BranchStop::MaxSteps,
        Stop::Cancelled => BranchStop::Cancelled,
        Stop::StepTooSmall => BranchStop::StepTooSmall,
        Stop::Bifurcation => BranchStop::Target,
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
        ..Default::default()
    }
}

/// The records and samples of `branch` for C. `previous`: the end rotation
/// (continuous) of the point a resumed or switched branch leaves from, so
/// that a torque clamp's φ (known mod 4π from the state) continues across
/// branches.
pub(super) fn record_lists(
    model: &Model,
    branch: &RodBranch,
    previous: Option<f64>,
) -> (Vec<BranchRecord>, Vec<BranchRecord>) {
    let n = model.unknowns();
    let (record_phi, sample_phi) = branch.end_rotations(model, previous);
    let records = (branch.records.iter().zip(&branch.states).zip(record_phi))
        .map(|((r, x), end_rotation)| BranchRecord {
            residual: r.residual,
            step: r.step,
            det_sign: r.det_sign,
            bordered_det_sign: r.bordered_det_sign,
            test_function: r.smallest_singular_value.unwrap_or(f64::NAN),
            newton_iterations: r.newton_iterations as i64,
            negative_pivots: r.negative_pivots.map_or(-1, |v| v as i64),
            end_rotation,
            ..record_of(model, n, r.lambda, x)
        })
        .collect();
    let samples = (branch.samples.iter().zip(&branch.sample_states).zip(sample_phi))
        .map(|((s, x), end_rotation)| BranchRecord {
            residual: s.residual,
            test_function: f64::NAN,
            newton_iterations: s.newton_iterations as i64,
            negative_pivots: -1,
            end_rotation,
            ..record_of(model, n, s.lambda, x)
        })
        .collect();
    (records, samples)
}

//! `RodkitContinuationOptions`: how a branch is followed (engine, stops,
//! tolerances, steps, bifurcations, dense output, scaling), its defaults
//! and its translation into the continuation engines' options.

use super::args::{arg_mut, c_enum, check_len, enum_arg, finite_fields, flag, in_slice};
use super::guard;
use crate::continuation::anm::AnmOptions;
use crate::continuation::{Options, Scaling};
use crate::error::{self, Error, Result};
use crate::rod::branch::Method;
use crate::status::Status;

/// Continuation engine (`RodkitContinuationOptions.method`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContinuationMethod {
    /// Asymptotic numerical method: series of order anm_order per step.
    Anm = 1,
    /// Newton pseudo-arc-length continuation.
    Newton = 2,
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
    /// Arc-length steps: first (Newton), minimum (defaults 0.05, 1e-10).
    pub initial_step: f64,
    pub min_step: f64,
    /// The largest arc-length step; 0 (the default): the engine's own —
    /// 1 for Newton continuation, none for the ANM, whose step is its
    /// series' radius (or its Padé approximants' reach).
    pub max_step: f64,
    /// 1: detect and locate bifurcations (default 0), to bifurcation_tol in
    /// scaled arc length (default 1e-10): the critical Λ to about
    /// bifurcation_tol·|dΛ/ds| (at most bifurcation_tol times Λ's scale, 1
    /// unless `scaling` says otherwise). Its discretisation error:
    /// rodkit_branch_bifurcation_errors. The ANM also uses its series'
    /// bifurcation indicator (where to search, and which σ_min sign changes
    /// need none).
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

c_enum!(ContinuationMethod, "a RodkitContinuationMethod 1…2", [ContinuationMethod::Anm, ContinuationMethod::Newton]);

/// The engine of the options.
fn method_from(o: &ContinuationOptions) -> Result<Method> {
    Ok(match enum_arg::<ContinuationMethod>("method", o.method)? {
        ContinuationMethod::Anm => {
            error::count_in_range("anm_order", o.anm_order, 2, 60)?;
            error::in_range("anm_epsilon", o.anm_epsilon, 1e-15, 1e-1)?;
            let pade = flag("anm_pade", o.anm_pade)?;
            Method::Anm(AnmOptions { order: o.anm_order as usize, epsilon: o.anm_epsilon, pade })
        }
        ContinuationMethod::Newton => Method::Newton,
    })
}

/// The scaling override of the options (None: the rod's own).
///
/// # Safety
/// `o.scaling` must be NULL or point to `o.scaling_count` doubles.
unsafe fn scaling_from(o: &ContinuationOptions, unknowns: usize) -> Result<Option<Scaling>> {
    if o.scaling.is_null() && o.scaling_count == 0 {
        return Ok(None);
    }
    check_len("scaling_count", o.scaling_count, unknowns as i64 + 1)?;
    let s = in_slice("scaling", o.scaling, o.scaling_count)?;
    if let Some(k) = s.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
        return Err(Error::new(
            Status::ErrNotPositive,
            format!("argument `scaling[{k}]` must be positive and finite (got {:e})", s[k]),
        ));
    }
    Ok(Some(Scaling { x: s[..unknowns].to_vec(), lambda: s[unknowns] }))
}

/// The requested sample loads of the options.
///
/// # Safety
/// `o.samples` must be NULL or point to `o.sample_count` doubles.
unsafe fn samples_from(o: &ContinuationOptions) -> Result<Vec<f64>> {
    if o.sample_count == 0 && o.samples.is_null() {
        return Ok(Vec::new());
    }
    error::count_in_range("sample_count", o.sample_count, 0, 1 << 24)?;
    let s = in_slice("samples", o.samples, o.sample_count)?;
    error::finite_result("samples", s)?;
    Ok(s.to_vec())
}

/// The engine options, the engine and the direction (`increasing`) of the
/// C options, for a rod of `unknowns` unknowns (field names unqualified:
/// the caller adds `options.`).
///
/// # Safety
/// The options' `scaling` and `samples` must be NULL or valid for their counts.
pub(super) unsafe fn options_from(o: &ContinuationOptions, unknowns: usize) -> Result<(Options, Method, bool)> {
    // Every double field finite (ERR_NOT_FINITE naming the C field, here
    // rather than in the engines, which do not know the C names);
    // target_lambda NaN means "no target", an infinity is refused.
    finite_fields(&[
        ("lambda_min", o.lambda_min),
        ("lambda_max", o.lambda_max),
        ("residual_tol", o.residual_tol),
        ("initial_step", o.initial_step),
        ("min_step", o.min_step),
        ("max_step", o.max_step),
        ("bifurcation_tol", o.bifurcation_tol),
    ])?;
    if o.method == ContinuationMethod::Anm as i32 {
        finite_fields(&[("anm_epsilon", o.anm_epsilon)])?;
    }
    if o.target_lambda.is_infinite() {
        finite_fields(&[("target_lambda", o.target_lambda)])?;
    }
    let method = method_from(o)?;
    if o.lambda_min >= o.lambda_max {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!("need lambda_min ({:e}) < lambda_max ({:e})", o.lambda_min, o.lambda_max),
        ));
    }
    error::count_in_range("max_steps", o.max_steps, 0, 1 << 30)?;
    let target = if o.target_lambda.is_nan() { None } else { Some(error::finite("target_lambda", o.target_lambda)?) };
    let opts = Options {
        target_lambda: target,
        lambda_range: (o.lambda_min, o.lambda_max),
        max_steps: o.max_steps as usize,
        residual_tol: o.residual_tol,
        initial_step: o.initial_step,
        min_step: o.min_step,
        // 0: the engine's own bound (∞ in Options); negative or NaN refused there.
        max_step: if o.max_step == 0.0 { f64::INFINITY } else { o.max_step },
        track_singular: false,
        detect_bifurcations: flag("detect_bifurcations", o.detect_bifurcations)?,
        bifurcation_tol: o.bifurcation_tol,
        scaling: scaling_from(o, unknowns)?,
        samples: samples_from(o)?,
        ..Options::default()
    };
    Ok((opts, method, flag("increasing", o.increasing)?))
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
            max_step: 0.0,
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

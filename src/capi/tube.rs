//! The tube handle `RodkitTube` (physics.md §1.2–1.5): a tube from its
//! geometry and wall material (`wall_material`), loadings, states, profiles
//! through the wall, sweeps with a progress callback, the linear coupling
//! stiffness and the section's rod law.

use super::args::{arg_mut, arg_ref, c_enum, capacity_arg, enum_arg, flag, free_handle, null_error};
use super::args::{qualify_argument, write_matrix};
use super::wall_material::{law, nan_default_material, WallMaterialSpec};
use super::{guard, guard_value};
use crate::error::{self, Error, Result};
use crate::status::Status;
use crate::tube::finite::{Axial, Ends, Loading, Torsion, TubeState as State};
pub use crate::tube::scene::TubeModel;
use crate::tube::scene::{TubeModel as Model, TubeScene};
use std::ffi::c_void;

/// A tube: geometry, wall material, model choice and tolerance.
/// Initialise with `rodkit_tube_spec_default`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct TubeSpec {
    /// Inner radius A ≥ 0 (0: solid cylinder) and outer radius B > A.
    pub inner_radius: f64,
    pub outer_radius: f64,
    pub material: WallMaterialSpec,
    /// RodkitTubeModel (default RODKIT_TUBE_MODEL_AUTO).
    pub model: i32,
    /// Requested accuracy (default 1e−8): radii per B, λ, ψB, F per μπB²,
    /// T per μπB³ for the thick model; the membrane's estimate is in the same
    /// measure (twice its difference from the thick wall on a coarse grid,
    /// plus that grid's own error), so AUTO takes the membrane only where it
    /// meets rel_tol.
    pub rel_tol: f64,
    /// Fixed Chebyshev intervals for the thick model, 4…256; 0: adaptive.
    pub intervals: i64,
}

/// How the axial direction is loaded.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AxialControl {
    /// `axial` is the stretch λ > 0.
    Stretch = 0,
    /// `axial` is the applied force F (besides the pressure on closed ends).
    Force = 1,
}

/// How the torsion is loaded.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TorsionControl {
    /// `torsion` is the twist per reference length ψ.
    Twist = 0,
    /// `torsion` is the torque T.
    Torque = 1,
}

/// A loading. Initialise with `rodkit_tube_loading_default` (λ = 1, ψ = 0,
/// no pressure, open ends).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct TubeLoading {
    /// RodkitAxialControl and its value.
    pub axial_control: i32,
    pub axial: f64,
    /// RodkitTorsionControl and its value.
    pub torsion_control: i32,
    pub torsion: f64,
    /// Pressure on the inner and outer surfaces.
    pub inner_pressure: f64,
    pub outer_pressure: f64,
    /// 1: closed (capped) ends, the wall also carries πa²p − πb²p_o; 0: open.
    pub closed_ends: i32,
}

/// An equilibrium state.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct TubeState {
    pub stretch: f64,
    pub twist: f64,
    /// Axial force carried by the wall, 2π∫σ_zz r dr.
    pub wall_force: f64,
    /// Axial force applied besides the cap pressure (= wall_force when open).
    pub applied_force: f64,
    pub torque: f64,
    pub inner_pressure: f64,
    pub outer_pressure: f64,
    pub deformed_inner_radius: f64,
    pub deformed_outer_radius: f64,
    /// The answering model's error estimate (see RodkitTubeSpec.rel_tol).
    pub error_estimate: f64,
    /// Chebyshev intervals (thick) or 0 (membrane).
    pub intervals: i64,
    pub newton_iterations: i64,
    /// RodkitTubeModel that produced the state (thick or membrane).
    pub model: i32,
}

/// What a progress callback is told.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Items done so far (1…total) and their total.
    pub done: i64,
    pub total: i64,
}

/// Progress callback: return 0 to continue, non-zero to stop cleanly. It must
/// not unwind into rodkit (no C++ throw, no longjmp); it may call rodkit
/// functions (rodkit holds no locks while it runs).
pub type ProgressCallback = Option<unsafe extern "C" fn(progress: *const Progress, user_data: *mut c_void) -> i32>;

/// Opaque tube handle (rodkit_tube_new / rodkit_tube_free). Immutable after
/// creation: it may be moved between threads and used by several threads at
/// once.
pub struct Tube {
    scene: TubeScene,
}

c_enum!(TubeModel, "a RodkitTubeModel 0…2", [TubeModel::Auto, TubeModel::Thick, TubeModel::Membrane]);
c_enum!(AxialControl, "0 (stretch) or 1 (force)", [AxialControl::Stretch, AxialControl::Force]);
c_enum!(TorsionControl, "0 (twist) or 1 (torque)", [TorsionControl::Twist, TorsionControl::Torque]);

pub(super) fn loading(l: &TubeLoading) -> Result<Loading> {
    let axial = match enum_arg::<AxialControl>("axial_control", l.axial_control)? {
        AxialControl::Stretch => Axial::Stretch(l.axial),
        AxialControl::Force => Axial::Force(l.axial),
    };
    let torsion = match enum_arg::<TorsionControl>("torsion_control", l.torsion_control)? {
        TorsionControl::Twist => Torsion::Twist(l.torsion),
        TorsionControl::Torque => Torsion::Torque(l.torsion),
    };
    let ends = if flag("closed_ends", l.closed_ends)? { Ends::Closed } else { Ends::Open };
    match axial {
        Axial::Stretch(v) => error::positive("axial", v)?,
        Axial::Force(v) => error::finite("axial", v)?,
    };
    error::finite("torsion", l.torsion)?;
    error::finite("inner_pressure", l.inner_pressure)?;
    error::finite("outer_pressure", l.outer_pressure)?;
    Ok(Loading { axial, torsion, inner_pressure: l.inner_pressure, outer_pressure: l.outer_pressure, ends })
}

fn state(s: &State, model: Model) -> TubeState {
    TubeState {
        stretch: s.stretch,
        twist: s.twist,
        wall_force: s.wall_force,
        applied_force: s.applied_force,
        torque: s.torque,
        inner_pressure: s.inner_pressure,
        outer_pressure: s.outer_pressure,
        deformed_inner_radius: s.deformed_inner_radius,
        deformed_outer_radius: s.deformed_outer_radius,
        error_estimate: s.error_estimate,
        intervals: s.intervals as i64,
        newton_iterations: s.newton_iterations as i64,
        model: model as i32,
    }
}

/// Fill `spec` with defaults: radii NaN (unset), material as
/// `rodkit_wall_material_spec_default`, model Auto, rel_tol 1e−8, adaptive grid.
#[no_mangle]
pub unsafe extern "C" fn rodkit_tube_spec_default(spec: *mut TubeSpec) -> i32 {
    guard(|| {
        *arg_mut("spec", spec)? = TubeSpec {
            inner_radius: f64::NAN,
            outer_radius: f64::NAN,
            material: nan_default_material(),
            model: Model::Auto as i32,
            rel_tol: 1e-8,
            intervals: 0,
        };
        Ok(Status::Ok)
    })
}

/// Fill `loading` with the unloaded state: stretch 1, twist 0, no pressure,
/// open ends.
#[no_mangle]
pub unsafe extern "C" fn rodkit_tube_loading_default(loading: *mut TubeLoading) -> i32 {
    guard(|| {
        *arg_mut("loading", loading)? = TubeLoading {
            axial_control: AxialControl::Stretch as i32,
            axial: 1.0,
            torsion_control: TorsionControl::Twist as i32,
            torsion: 0.0,
            inner_pressure: 0.0,
            outer_pressure: 0.0,
            closed_ends: 0,
        };
        Ok(Status::Ok)
    })
}

/// Validate `spec` and create a tube. On success `*out` owns a new handle
/// (free it with `rodkit_tube_free`); on failure `*out` is set to NULL.
#[no_mangle]
pub unsafe extern "C" fn rodkit_tube_new(spec: *const TubeSpec, out: *mut *mut Tube) -> i32 {
    guard(|| {
        let out = arg_mut("out", out)?;
        *out = std::ptr::null_mut();
        let spec = arg_ref("spec", spec)?;
        let model = enum_arg::<Model>("spec.model", spec.model)?;
        let intervals = match spec.intervals {
            0 => None,
            n => Some(error::count_in_range("spec.intervals", n, 4, 256)? as usize),
        };
        let scene = TubeScene::new(
            spec.inner_radius,
            spec.outer_radius,
            law(&spec.material).map_err(|e| qualify_argument(e, "spec."))?,
            model,
            spec.rel_tol,
            intervals,
        )
        .map_err(|e| qualify_argument(e, "spec."))?;
        *out = Box::into_raw(Box::new(Tube { scene }));
        Ok(Status::Ok)
    })
}

/// Destroy a tube created by `rodkit_tube_new`; NULL is accepted.
#[no_mangle]
pub unsafe extern "C" fn rodkit_tube_free(tube: *mut Tube) {
    guard_value((), || free_handle(tube))
}

/// The equilibrium of `tube` under `loading`, written to `*out`.
#[no_mangle]
pub unsafe extern "C" fn rodkit_tube_solve(tube: *const Tube, loading: *const TubeLoading, out: *mut TubeState) -> i32 {
    guard(|| {
        let tube = arg_ref("tube", tube)?;
        let l = self::loading(arg_ref("loading", loading)?).map_err(|e| qualify_argument(e, "loading."))?;
        let out = arg_mut("out", out)?;
        let (s, model) = tube.scene.solve(&l)?;
        *out = state(&s, model);
        Ok(Status::Ok)
    })
}

/// Stresses through the wall (Cauchy, deformed cylindrical basis) at the
/// answering model's nodes: reference radius R, deformed radius r, σ_rr,
/// σ_θθ, σ_zz, σ_θz. `*count` receives the number of nodes. Size query:
/// with `capacity` 0 the six arrays may be NULL and only `*count` is written.
/// Otherwise each array needs `capacity` ≥ that count.
/// cbindgen:fortran-arrays=[reference_radius, radius, sigma_rr, sigma_tt, sigma_zz, sigma_tz]
#[no_mangle]
pub unsafe extern "C" fn rodkit_tube_profile(
    tube: *const Tube,
    loading: *const TubeLoading,
    capacity: i64,
    reference_radius: *mut f64,
    radius: *mut f64,
    sigma_rr: *mut f64,
    sigma_tt: *mut f64,
    sigma_zz: *mut f64,
    sigma_tz: *mut f64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let tube = arg_ref("tube", tube)?;
        let l = self::loading(arg_ref("loading", loading)?).map_err(|e| qualify_argument(e, "loading."))?;
        let count = arg_mut("count", count)?;
        let capacity = capacity_arg(capacity)?;
        let (s, _) = tube.scene.solve(&l)?;
        let p = &s.profile;
        let n = p.radius.len();
        *count = n as i64;
        if capacity == 0 {
            return Ok(Status::Ok);
        }
        if capacity < n {
            return Err(Error::new(
                Status::ErrInvalidDimension,
                format!("argument `capacity` ({capacity}) is below the {n} nodes of the profile"),
            ));
        }
        let columns: [(&str, *mut f64, &Vec<f64>); 6] = [
            ("reference_radius", reference_radius, &p.reference_radius),
            ("radius", radius, &p.radius),
            ("sigma_rr", sigma_rr, &p.sigma_rr),
            ("sigma_tt", sigma_tt, &p.sigma_tt),
            ("sigma_zz", sigma_zz, &p.sigma_zz),
            ("sigma_tz", sigma_tz, &p.sigma_tz),
        ];
        if let Some((name, _, _)) = columns.iter().find(|c| c.1.is_null()) {
            return Err(null_error(name));
        }
        for (_, ptr, values) in columns {
            std::slice::from_raw_parts_mut(ptr, n).copy_from_slice(values);
        }
        Ok(Status::Ok)
    })
}

/// Equilibria along `count` loadings of the same kind (same controls and
/// ends; e.g. stretches at zero torque, or pressures), each continued from the
/// previous one, into `states[0 … count−1]`. `*completed` (may be NULL)
/// receives the number of states written. `progress` (may be NULL) is called
/// after each state with `user_data`; a non-zero return stops the sweep and
/// the function returns RODKIT_STATUS_INFO_CANCELLED (> 0) with the states so
/// far. On a failure the states before it are written and `*completed` says
/// how many.
/// cbindgen:fortran-arrays=[loadings, states]
#[no_mangle]
pub unsafe extern "C" fn rodkit_tube_sweep(
    tube: *const Tube,
    loadings: *const TubeLoading,
    count: i64,
    states: *mut TubeState,
    progress: ProgressCallback,
    user_data: *mut c_void,
    completed: *mut i64,
) -> i32 {
    if let Some(c) = completed.as_mut() {
        *c = 0;
    }
    guard(|| {
        let tube = arg_ref("tube", tube)?;
        error::dimension("count", count, 1, 1 << 40)?;
        if loadings.is_null() {
            return Err(null_error("loadings"));
        }
        if states.is_null() {
            return Err(null_error("states"));
        }
        let n = count as usize;
        let input = std::slice::from_raw_parts(loadings, n);
        let list = input
            .iter()
            .enumerate()
            .map(|(i, l)| self::loading(l).map_err(|e| qualify_argument(e, &format!("loadings[{i}]."))))
            .collect::<Result<Vec<_>>>()?;
        let out = std::slice::from_raw_parts_mut(states, n);
        let mut written = 0usize;
        // Each state is written as soon as it exists, so a later failure
        // leaves the earlier ones valid.
        let result = tube.scene.sweep(&list, |i, s| {
            out[i] = state(s, Model::Thick);
            written = i + 1;
            match progress {
                Some(cb) => cb(&Progress { done: i as i64 + 1, total: count }, user_data) == 0,
                None => true,
            }
        });
        if let Some(c) = completed.as_mut() {
            *c = written as i64;
        }
        let (sweep, model) = result?;
        for s in out.iter_mut().take(written) {
            s.model = model as i32;
        }
        Ok(if sweep.cancelled { Status::InfoCancelled } else { Status::Ok })
    })
}

/// Write the n×n matrix `column_major` into `k` (leading dimension `ldk`)
/// and, when `error_estimate` is not NULL, its relative error estimate.
///
/// # Safety
/// As [`write_matrix`]; `error_estimate` NULL or writable.
unsafe fn write_estimated(
    k: *mut f64,
    ldk: i64,
    n: usize,
    column_major: &[f64],
    estimate: f64,
    error_estimate: *mut f64,
) -> Result<Status> {
    write_matrix("k", k, ldk, "ldk", n, n, column_major)?;
    if let Some(e) = error_estimate.as_mut() {
        *e = estimate;
    }
    Ok(Status::Ok)
}

/// Linear coupling stiffness about the stress-free state (physics.md §1.4),
/// thick theory, in the inner-radius variables: (F, T, 2πA²p) = K (ε, ψ,
/// ε_A). `k` receives the 3×3 matrix column-major with leading dimension
/// `ldk` ≥ 3; `error_estimate` (may be NULL) its relative error estimate.
/// Fibre-reinforced walls have none (tension-only fibres): ERR_OUT_OF_RANGE.
/// cbindgen:fortran-arrays=[k]
#[no_mangle]
pub unsafe extern "C" fn rodkit_tube_coupling_stiffness(
    tube: *const Tube,
    k: *mut f64,
    ldk: i64,
    error_estimate: *mut f64,
) -> i32 {
    guard(|| {
        let tube = arg_ref("tube", tube)?;
        let est = tube.scene.coupling_stiffness()?;
        write_estimated(k, ldk, 3, &est.value.column_major(), est.error_estimate, error_estimate)
    })
}

/// The section as a rod: the condensed stretch–twist law at zero pressure,
/// (F, T) = [[S, g], [g, C]] (ε, ψ), ready for a hemitropic rod (§2.2).
/// `s` receives the 2×2 matrix column-major with leading dimension `lds` ≥ 2.
/// cbindgen:fortran-arrays=[s]
#[no_mangle]
pub unsafe extern "C" fn rodkit_tube_stretch_twist(tube: *const Tube, s: *mut f64, lds: i64) -> i32 {
    guard(|| {
        let tube = arg_ref("tube", tube)?;
        let law = tube.scene.stretch_twist()?;
        write_matrix("s", s, lds, "lds", 2, 2, law.matrix().as_slice())?;
        Ok(Status::Ok)
    })
}

/// The section as a hemitropic rod (physics.md §2.2): the symmetric 6×6
/// stiffness K with (m1, m2, m3, n1, n2, n3) = K (u1, u2, u3, v1, v2, v3 − 1)
/// in the rod's body frame (d3 along the tube axis): u1, u2 bending
/// curvatures, u3 twist per length (1/length); v1, v2 shear strains, v3 the
/// axial stretch (v3 − 1 the axial strain); m1, m2 bending moments, m3 the
/// torque; n1, n2 shear forces, n3 the axial force. Nonzero entries (1-based):
/// K11 = K22 bending, K33 twist C, K44 = K55 shear, K66 stretch S, K36 = K63
/// twist–stretch g, K14 = K41 = K25 = K52 bend–shear; see
/// rodkit_thin_tube_rod_stiffness for their thin-wall closed forms. Written
/// column-major into `k` with leading dimension `ldk` ≥ 6. Stretch–twist block from the
/// thick theory (as rodkit_tube_stretch_twist); bending and shear from
/// layer-wise thin-walled beam theory (exact Euler–Bernoulli bending; shear
/// with the thin-tube coefficient 1/2, low for thick walls). Needs a law with
/// a linearisation at rest (not tension-only fibres). `error_estimate` (may
/// be NULL) receives the estimated relative error.
/// cbindgen:fortran-arrays=[k]
#[no_mangle]
pub unsafe extern "C" fn rodkit_tube_rod_stiffness(
    tube: *const Tube,
    k: *mut f64,
    ldk: i64,
    error_estimate: *mut f64,
) -> i32 {
    guard(|| {
        let tube = arg_ref("tube", tube)?;
        let est = tube.scene.rod_stiffness()?;
        write_estimated(k, ldk, 6, &est.value.column_major(), est.error_estimate, error_estimate)
    })
}

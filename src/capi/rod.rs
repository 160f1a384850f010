//! The rod handle `RodkitRod` (physics.md §2): made from a
//! `RodkitRodSpec`, queried for its unknowns and straight state, and its
//! discrete equations as plain `double*` kernels for callers who drive
//! their own solvers (SUNDIALS: residual, sparse Jacobian, the ODEs'
//! right-hand side). Its continuation is in `branch`.

use super::args::{arg_mut, arg_ref, capacity_arg, check_len, clear_handle, free_handle, in_array, in_slice};
use super::args::{copy_out, out_slice, qualify_argument};
use super::rod_spec::{model_from, RodSpec};
use super::{guard, guard_value};
use crate::continuation::system::AssembledSystem;
use crate::continuation::Problem;
use crate::error::{self, Error, Result};
use crate::rod::model::Rod as Model;
use crate::status::Status;
use nalgebra::Matrix6;

/// Opaque rod handle. The continuation functions only read it (several
/// threads may continue the same rod at once); the kernel functions
/// (rodkit_rod_residual, _jacobian) use its work buffers: do not call them
/// on one handle from several threads at the same time.
pub struct Rod {
    pub(super) model: Model,
    system: AssembledSystem,
    /// Kernel outputs are computed here, checked finite, then copied: a
    /// failing call writes nothing, and no call allocates.
    scratch_r: Vec<f64>,
    scratch_values: Vec<f64>,
    scratch_dl: Vec<f64>,
    /// The end rotation branches of this rod stop at
    /// (rodkit_rod_set_target_rotation).
    pub(super) target_rotation: Option<f64>,
}

/// Hand a rod made from `model` to C in `*out` (NULL on failure).
///
/// # Safety
/// `out` must be NULL or writable.
pub(super) unsafe fn store_rod(model: Model, out: *mut *mut Rod) -> Result<Status> {
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
        target_rotation: None,
    }));
    Ok(Status::Ok)
}

/// Create a rod from `spec` (validated: a message names the bad field).
/// On failure `*out` is NULL.
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_new(spec: *const RodSpec, out: *mut *mut Rod) -> i32 {
    guard(|| {
        clear_handle(out);
        let spec = arg_ref("spec", spec)?;
        let model = model_from(spec, None).map_err(|e| qualify_argument(e, "spec."))?;
        store_rod(model, out)
    })
}

/// As rodkit_rod_new with a general symmetric positive-definite 6×6
/// stiffness K, (m, n) = K (u − û, v − v̂) in the symbols of RodkitRodSpec
/// (column-major, leading dimension `ldk` ≥ 6, order (u1, u2, u3, v1, v2,
/// v3)), in place of the spec's moduli (bending1…bend_shear are ignored).
/// Entries must be finite (ERR_NOT_FINITE naming `stiffness[i + ldk·j]`);
/// a condition number above 1e13 is refused (ERR_NOT_POSITIVE_DEFINITE,
/// "ill-conditioned").
/// cbindgen:fortran-arrays=[stiffness]
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_new_general(
    spec: *const RodSpec,
    stiffness: *const f64,
    ldk: i64,
    out: *mut *mut Rod,
) -> i32 {
    guard(|| {
        clear_handle(out);
        let spec = arg_ref("spec", spec)?;
        error::dimension("ldk", ldk, 6, i64::MAX / 64)?;
        let a = in_array("stiffness", stiffness, ldk * 5 + 6)?;
        let k = Matrix6::from_fn(|i, j| a[i + j * ldk as usize]);
        // The 36 entries read (the padding rows are not): a NaN or an
        // infinity is the caller's argument, named with its index.
        if let Some(i) = (0..36).find(|&i| !k[i].is_finite()) {
            error::finite(&format!("stiffness[{}]", i % 6 + (i / 6) * ldk as usize), k[i])?;
        }
        let model = model_from(spec, Some(k)).map_err(|e| qualify_argument(e, "spec."))?;
        store_rod(model, out)
    })
}

/// Stop every branch followed on `rod` from now on (rodkit_rod_continue,
/// rodkit_branch_resume, rodkit_branch_switch,
/// rodkit_rod_continue_to_tolerance) exactly where its end rotation φ
/// reaches `phi` (radians, counted continuously from the straight state:
/// 25 is four turns on; a resumed or switched branch counts on from the
/// point it leaves). Under rotation control Λ = sin(φ/2) takes every value
/// again each turn, so options.target_lambda cannot say this; a torque
/// clamp's φ is an output. The branch's last record is then at φ = `phi`
/// (RODKIT_STATUS_OK, as for a target Λ); one that ends first (its target
/// Λ, range, step limit, a callback's stop) ends as it would without.
/// NaN clears the target. Refused for a rod without end rotation control
/// or torque clamp (RODKIT_STATUS_ERR_OUT_OF_RANGE) and for an infinity.
/// Set it before following branches, not while another thread follows
/// one on this handle.
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_set_target_rotation(rod: *mut Rod, phi: f64) -> i32 {
    guard(|| {
        let rod = arg_mut("rod", rod)?;
        if phi.is_nan() {
            rod.target_rotation = None;
            return Ok(Status::Ok);
        }
        error::finite("phi", phi)?;
        if !(rod.model.twisted() || rod.model.torqued()) {
            return Err(Error::new(
                Status::ErrOutOfRange,
                "argument `rod`: a target end rotation needs end rotation control or a torque clamp (RODKIT_SUPPORTS_TWISTED, _TWISTED_AT_DISTANCE or _TORQUED)",
            ));
        }
        rod.target_rotation = Some(phi);
        Ok(Status::Ok)
    })
}

/// Free a rod (NULL is accepted).
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_free(rod: *mut Rod) {
    guard_value((), || free_handle(rod))
}

/// Number of unknowns n of the discrete system (the state x; Λ apart).
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_unknowns(rod: *const Rod, n: *mut i64) -> i32 {
    guard(|| {
        *arg_mut("n", n)? = arg_ref("rod", rod)?.model.unknowns() as i64;
        Ok(Status::Ok)
    })
}

/// The rod's mesh: the arc lengths s_0 = 0 < s_1 < … < s_N = L of its
/// nodes (node i of rodkit_rod_node_state), N its elements — uniform as
/// made by rodkit_rod_new; graded where the branch varies fast (and
/// symmetric about the middle for a rod held at both ends) on the rod
/// rodkit_rod_continue_to_tolerance chose. Up to `capacity` of them are
/// copied to `s` (NULL with capacity 0 to ask); `*count` receives N + 1
/// (RODKIT_STATUS_INFO_TRUNCATED when capacity is smaller).
/// cbindgen:fortran-arrays=[s]
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_node_positions(
    rod: *const Rod,
    s: *mut f64,
    capacity: i64,
    count: *mut i64,
) -> i32 {
    guard(|| {
        let rod = arg_ref("rod", rod)?;
        copy_out("s", s, capacity, count, &rod.model.node_positions(), |v| *v)
    })
}

/// The straight stress-free state (length n = rodkit_rod_unknowns).
/// cbindgen:fortran-arrays=[x]
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_straight_state(rod: *const Rod, x: *mut f64, n: i64) -> i32 {
    guard(|| {
        let rod = arg_ref("rod", rod)?;
        let want = rod.model.unknowns() as i64;
        check_len("n", n, want)?;
        let x = out_slice("x", x, n)?;
        // rodkit_rod_new refuses lengths whose scales overflow; this keeps
        // any other overflow from leaving as OK with infinite entries.
        let state = rod.model.straight_state();
        error::finite_result("straight state", &state)?;
        x.copy_from_slice(&state);
        Ok(Status::Ok)
    })
}

/// Node `node` (0 at s = 0 … the rod's elements at the tip) of the state
/// x (length n: rodkit_rod_unknowns, or one more on a branch followed with
/// a phase condition, μ last): its position r (3), quaternion q = (q0,
/// q1, q2, q3), scalar first, d_k = R(q) e_k (4), and the internal force
/// and moment in the spatial frame, R(q) n and R(q) m (3 each). Any output
/// may be NULL (not wanted). The state layout itself: for each node i,
/// its 13 values (r, q, n and m in the body frame) and then those of its
/// element's stage points (none after the last node); end-control
/// unknowns last — read it through this accessor rather than by offsets.
/// cbindgen:fortran-arrays=[x, position, quaternion, force, moment]
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_node_state(
    rod: *const Rod,
    x: *const f64,
    n: i64,
    node: i64,
    position: *mut f64,
    quaternion: *mut f64,
    force: *mut f64,
    moment: *mut f64,
) -> i32 {
    guard(|| {
        let (m, x, node) = node_args(rod, x, n, node)?;
        let y = m.node_state(x, node);
        let (f, mm) = m.spatial_force_moment(x, node);
        for (name, p, v) in [
            ("position", position, &y[0..3]),
            ("quaternion", quaternion, &y[3..7]),
            ("force", force, &f[..]),
            ("moment", moment, &mm[..]),
        ] {
            if !p.is_null() {
                out_slice(name, p, v.len() as i64)?.copy_from_slice(v);
            }
        }
        Ok(Status::Ok)
    })
}

/// The rotation vector θ·n of node `node`'s frame (0 … elements; the tip
/// is `elements`) in the state `x` (length rodkit_rod_unknowns, or one
/// more with μ last): the shortest rotation from the straight rod's frame,
/// θ ∈ [0, π], so its components are signed angles (radians) — the tip
/// rotation of a cantilever bent in the (e1, e3) plane towards +e1 is
/// `rotation[1]`, positive, accurate at small angles (computed by atan2
/// from the quaternion). A path through θ = π flips n; follow it by
/// continuity there. RodkitBranchRecord.tip_rotation is the unsigned angle
/// of the tip tangent.
/// cbindgen:fortran-arrays=[x, rotation]
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_node_rotation(
    rod: *const Rod,
    x: *const f64,
    n: i64,
    node: i64,
    rotation: *mut f64,
) -> i32 {
    guard(|| {
        let (m, x, node) = node_args(rod, x, n, node)?;
        let out = out_slice("rotation", rotation, 3)?;
        let r = m.rotation_vector(x, node);
        error::finite_result("rotation", &r)?;
        out.copy_from_slice(&r);
        Ok(Status::Ok)
    })
}

/// The node accessors' arguments: the rod's model, its state `x` of
/// length `n` (the unknowns, or one more with μ last) and a node 0 …
/// elements.
///
/// # Safety
/// `rod` must be NULL or valid, `x` NULL or `n` readable doubles.
unsafe fn node_args<'a>(rod: *const Rod, x: *const f64, n: i64, node: i64) -> Result<(&'a Model, &'a [f64], usize)> {
    let m = &arg_ref("rod", rod)?.model;
    let unknowns = m.unknowns() as i64;
    if n != unknowns && n != unknowns + 1 {
        return Err(Error::new(
            Status::ErrInvalidDimension,
            format!("argument `n` must be {unknowns} (or {} with μ last; got {n})", unknowns + 1),
        ));
    }
    error::count_in_range("node", node, 0, m.elements as i64)?;
    Ok((m, in_slice("x", x, n)?, node as usize))
}

/// Residual R(x, Λ) of the discrete equations (length n each), in the
/// form SUNDIALS' KINSOL calls: a user's KINSysFn wraps it with
/// N_VGetArrayPointer. Not thread-safe on one handle (work buffers).
/// cbindgen:fortran-arrays=[x, r]
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
/// cbindgen:fortran-arrays=[col_ptr, row_idx]
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
        let capacity = capacity_arg(capacity)?;
        let p = rod.system.pattern();
        *arg_mut("nnz", nnz)? = p.nnz() as i64;
        if capacity < p.nnz() {
            return Ok(Status::InfoTruncated);
        }
        let cp = out_slice("col_ptr", col_ptr, p.n as i64 + 1)?;
        let ri = out_slice("row_idx", row_idx, p.nnz() as i64)?;
        for (d, s) in cp.iter_mut().zip(&p.col_ptr).chain(ri.iter_mut().zip(&p.row_idx)) {
            *d = *s as i64;
        }
        Ok(Status::Ok)
    })
}

/// ∂R/∂x at (x, Λ) in the order of rodkit_rod_jacobian_pattern (`values`,
/// `nnz` entries) and ∂R/∂Λ (`d_lambda`, n entries; may be NULL).
/// cbindgen:fortran-arrays=[x, values, d_lambda]
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
/// cbindgen:fortran-arrays=[y, dy]
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

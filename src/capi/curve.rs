//! Electrostatics and writhe of a given curve (physics.md §3.2–3.4) from C
//! and Fortran: the curve is given by its nodes — arc lengths s[nodes],
//! positions and unit tangents as 3 × nodes column-major arrays with
//! leading dimensions — and interpolated by C¹ cubic Hermite pieces.

use super::args::{arg_mut, arg_ref, flag, in_array, non_negative, null_error, qualify_argument};
use super::guard;
use crate::electrostatics::{self, discrete, EnergyQuadrature, HermiteCurve, LineCharge, Screening};
use crate::error::{self, Error, Result};
use crate::geometry::writhe::writhe;
use crate::geometry::Centerline;
use crate::status::Status;

/// Line charge and interaction. Call `rodkit_electrostatics_spec_default`
/// first (physical fields NaN = unset). Energies are in units of
/// 1/(4πε0εr) times the charge's units squared (k_BT·l_B per e² for a
/// charge in e per length).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct ElectrostaticsSpec {
    /// Uniform line charge density λ.
    pub line_charge: f64,
    /// Inverse Debye length κ ≥ 0 (0: Coulomb).
    pub kappa: f64,
    /// Excluded arc-length distance a > 0 (the rod's radius scale).
    pub a: f64,
    /// Near-zone half-width δ (a < δ < L, < L/2 on a closed curve;
    /// the result is independent of it to O(δ⁴)).
    pub near_width: f64,
    /// Gauss–Legendre points per panel (2…32; default 10).
    pub order: i64,
}

/// Energy and its split into the analytic near zone and the quadrature
/// far zone.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct ElectrostaticEnergy {
    pub total: f64,
    pub near: f64,
    pub far: f64,
}

/// Fill `spec` with defaults: λ, κ, a, δ NaN (unset), order 10.
#[no_mangle]
pub unsafe extern "C" fn rodkit_electrostatics_spec_default(spec: *mut ElectrostaticsSpec) -> i32 {
    guard(|| {
        *arg_mut("spec", spec)? =
            ElectrostaticsSpec { line_charge: f64::NAN, kappa: f64::NAN, a: f64::NAN, near_width: f64::NAN, order: 10 };
        Ok(Status::Ok)
    })
}

unsafe fn matrix_columns(name: &str, p: *const f64, ld: i64, nodes: usize) -> Result<Vec<[f64; 3]>> {
    if p.is_null() {
        return Err(null_error(name));
    }
    error::dimension(&format!("ld of {name}"), ld, 3, i64::MAX / 8)?;
    let len = (ld as usize)
        .checked_mul(nodes - 1)
        .and_then(|v| v.checked_add(3))
        .ok_or_else(|| Error::new(Status::ErrOutOfRange, format!("argument `{name}`: size overflows")))?;
    let v = std::slice::from_raw_parts(p, len);
    let cols: Vec<[f64; 3]> =
        (0..nodes).map(|i| [v[i * ld as usize], v[i * ld as usize + 1], v[i * ld as usize + 2]]).collect();
    error::finite_result(name, cols.as_flattened())?;
    Ok(cols)
}

unsafe fn curve_from(
    s: *const f64,
    xyz: *const f64,
    ldx: i64,
    tangents: *const f64,
    ldt: i64,
    nodes: i64,
    closed: i32,
) -> Result<HermiteCurve> {
    error::count_in_range("nodes", nodes, 2, 1 << 26)?;
    let n = nodes as usize;
    let s = in_array("s", s, nodes)?.to_vec();
    error::finite_result("s", &s)?;
    let r = matrix_columns("xyz", xyz, ldx, n)?;
    let mut t = matrix_columns("tangents", tangents, ldt, n)?;
    for (i, v) in t.iter_mut().enumerate() {
        let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        // Finite columns: the norm is never NaN.
        if norm <= 0.0 {
            return Err(Error::new(Status::ErrOutOfRange, format!("argument `tangents`: column {i} is zero")));
        }
        v.iter_mut().for_each(|c| *c /= norm);
    }
    HermiteCurve::new(s, r, t, flag("closed", closed)?)
}

fn settings(spec: &ElectrostaticsSpec) -> Result<(LineCharge, Screening, EnergyQuadrature)> {
    error::finite("line_charge", spec.line_charge)?;
    error::finite("kappa", spec.kappa)?;
    error::finite("a", spec.a)?;
    error::finite("near_width", spec.near_width)?;
    error::count_in_range("order", spec.order, 2, 32)?;
    non_negative("kappa", spec.kappa)?;
    error::positive("a", spec.a)?;
    if spec.near_width <= spec.a {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!("argument `near_width` ({:e}) must exceed a ({:e})", spec.near_width, spec.a),
        ));
    }
    Ok((
        LineCharge::Uniform(spec.line_charge),
        Screening { kappa: spec.kappa, a: spec.a },
        EnergyQuadrature { delta: spec.near_width, order: spec.order as usize, cutoff: None },
    ))
}

/// The continuum electrostatic self-energy of the curve (nodes ≥ 2;
/// `closed` 1: the last node repeats the first and the curve is periodic).
#[no_mangle]
pub unsafe extern "C" fn rodkit_curve_electrostatic_energy(
    s: *const f64,
    xyz: *const f64,
    ldx: i64,
    tangents: *const f64,
    ldt: i64,
    nodes: i64,
    closed: i32,
    spec: *const ElectrostaticsSpec,
    energy: *mut ElectrostaticEnergy,
) -> i32 {
    guard(|| {
        let curve = curve_from(s, xyz, ldx, tangents, ldt, nodes, closed)?;
        let (charge, screening, quad) = settings(arg_ref("spec", spec)?).map_err(|e| qualify_argument(e, "spec."))?;
        let out = arg_mut("energy", energy)?;
        let e = electrostatics::energy(&curve, &charge, &screening, &quad)?;
        *out = ElectrostaticEnergy { total: e.total, near: e.near, far: e.far };
        Ok(Status::Ok)
    })
}

/// The discrete base-pair energy of the same curve: charges λ·b at spacing
/// b (≈ `spacing`, adjusted to divide the length) at the midpoints, all
/// pairs with |s_i − s_j| > a (the thesis's comparison, O(N²)).
#[no_mangle]
pub unsafe extern "C" fn rodkit_curve_base_pair_energy(
    s: *const f64,
    xyz: *const f64,
    ldx: i64,
    tangents: *const f64,
    ldt: i64,
    nodes: i64,
    closed: i32,
    spec: *const ElectrostaticsSpec,
    spacing: f64,
    energy: *mut f64,
) -> i32 {
    guard(|| {
        let curve = curve_from(s, xyz, ldx, tangents, ldt, nodes, closed)?;
        let (charge, screening, _) = settings(arg_ref("spec", spec)?).map_err(|e| qualify_argument(e, "spec."))?;
        let out = arg_mut("energy", energy)?;
        let (r, q, sp) = discrete::base_pairs(&curve, &charge, spacing)?;
        let period = curve.closed.then(|| curve.length());
        let e = discrete::energy(&r, &q, &sp, &screening, period);
        error::finite("energy", e)?;
        *out = e;
        Ok(Status::Ok)
    })
}

/// The writhe of the curve (turns): the Gauss double integral, an open
/// curve closed by rays along its end tangents; `order` Gauss points per
/// panel (2…32).
#[no_mangle]
pub unsafe extern "C" fn rodkit_curve_writhe(
    s: *const f64,
    xyz: *const f64,
    ldx: i64,
    tangents: *const f64,
    ldt: i64,
    nodes: i64,
    closed: i32,
    order: i64,
    writhe_out: *mut f64,
) -> i32 {
    guard(|| {
        let curve = curve_from(s, xyz, ldx, tangents, ldt, nodes, closed)?;
        error::count_in_range("order", order, 2, 32)?;
        let out = arg_mut("writhe", writhe_out)?;
        *out = writhe(&curve, order as usize)?;
        Ok(Status::Ok)
    })
}

/// What `rodkit_curve_electrostatic_energy_within` chose and delivered.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct EnergyWithin {
    pub total: f64,
    pub near: f64,
    pub far: f64,
    /// 0: no electrostatics (zero charge), 1: the regularised continuum.
    pub model: i32,
    /// Its settings: near-zone width δ, Gauss order, screening cutoff
    /// (NaN: every pair).
    pub near_width: f64,
    pub order: i64,
    pub cutoff: f64,
    /// Estimated relative error (two resolutions plus the cutoff's tail).
    pub estimate: f64,
}

/// Only what the scene requires: the energy of the curve within the
/// relative `tolerance` (1e-14…0.1) by the cheapest continuum settings
/// whose error estimate meets it, and which settings were used.
/// `spec.near_width` and `spec.order` are ignored (chosen here).
#[no_mangle]
pub unsafe extern "C" fn rodkit_curve_electrostatic_energy_within(
    s: *const f64,
    xyz: *const f64,
    ldx: i64,
    tangents: *const f64,
    ldt: i64,
    nodes: i64,
    closed: i32,
    spec: *const ElectrostaticsSpec,
    tolerance: f64,
    out: *mut EnergyWithin,
) -> i32 {
    guard(|| {
        let curve = curve_from(s, xyz, ldx, tangents, ldt, nodes, closed)?;
        let spec = arg_ref("spec", spec)?;
        let inner = || -> Result<(LineCharge, Screening)> {
            error::finite("line_charge", spec.line_charge)?;
            error::finite("kappa", spec.kappa)?;
            error::positive("a", spec.a)?;
            non_negative("kappa", spec.kappa)?;
            Ok((LineCharge::Uniform(spec.line_charge), Screening { kappa: spec.kappa, a: spec.a }))
        };
        let (charge, screening) = inner().map_err(|e| qualify_argument(e, "spec."))?;
        let out = arg_mut("out", out)?;
        let r = electrostatics::energy_within(&curve, &charge, &screening, tolerance)?;
        let (model, q) = match r.model {
            electrostatics::ElectrostaticModel::None => (0, None),
            electrostatics::ElectrostaticModel::Continuum(q) => (1, Some(q)),
        };
        *out = EnergyWithin {
            total: r.energy.total,
            near: r.energy.near,
            far: r.energy.far,
            model,
            near_width: q.map_or(f64::NAN, |q| q.delta),
            order: q.map_or(0, |q| q.order as i64),
            cutoff: q.and_then(|q| q.cutoff).unwrap_or(f64::NAN),
            estimate: r.estimate,
        };
        Ok(Status::Ok)
    })
}

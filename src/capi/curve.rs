//! Electrostatics and writhe of a given curve (physics.md §3.2–3.4) from C
//! and Fortran.
//!
//! The curve, the model and the work bounds are documented on
//! [`ElectrostaticsSpec`] (it reaches the C header).

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
///
/// The curve: nodes i = 0 … nodes−1 with arc lengths s[i] (strictly
/// increasing, any start: the curve's arc length is s − s[0]), positions
/// and tangents as 3 × nodes column-major arrays with leading dimensions
/// (tangents are normalised here). Between two nodes the curve is the
/// cubic Hermite piece in arc length through both positions with the unit
/// tangents times the piece length as end derivatives: C¹ at the nodes,
/// its curvature jumps there (quadrature panels break at every node).
/// Checked on entry: every entry finite (ERR_NOT_FINITE naming `s[i]`,
/// `xyz[ld*i+k]`, `tangents[ld*i+k]`); s must be the arc length of the
/// positions — no chord longer than s[i+1] − s[i] by more than 1e-9
/// relative, each Hermite piece's own length within 1 % of
/// s[i+1] − s[i] (true arc lengths pass up to ≈ 1.7 rad of turning per
/// piece; else ERR_OUT_OF_RANGE naming `s`); `closed` = 1 requires
/// the last node to repeat the first within 1e-9·L in position and 1e-6 in
/// unit tangent (else ERR_OUT_OF_RANGE naming `closed`).
///
/// The energy, E = ½∫∫_{|s−t|>a} λ² Φ(|r(s) − r(t)|) ds dt with
/// Φ(d) = e^{−κd}/d, is split at |s − t| = δ (`spec.near_width`): for
/// a < |h| < δ the chord is expanded about s with the curve's own speed
/// v = |r'| (a cubic through nodes is not exactly parametrised by its arc
/// length), d = v|h|(1 + αh + βh² + O(h³)), and integrated analytically;
/// beyond δ Gauss–Legendre of `spec.order` points on panels of the curve's
/// own scale (its shortest piece, its smallest radius of curvature, 4/κ),
/// graded toward δ. The dropped terms make the near zone O(δ⁴) relative in
/// the interior of a smooth arc-length curve (Coulomb ring:
/// 7δ⁴/(23040 R⁴ ln cot(a/4R)), 5e-6 for a helix of radius 5, pitch 10,
/// a = 1 at δ = 1.5), O(δ³) within δ of an open curve's end, about O(δ²)
/// where the near zone crosses a node of the cubics; nothing on a straight
/// one. δ is best kept below a quarter of a piece.
///
/// Work bounds (ERR_WORK_LIMIT, refused before anything is allocated, the
/// message states the cost and the bound): 1e9 far-zone kernel evaluations
/// and 4e6 stored quadrature points per continuum evaluation (about 20 s
/// and 200 MB), 4e7 kernel evaluations (about a second) per `_within`
/// call, 1e9 pair evaluations for the base-pair sum.
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

/// The 3 × nodes columns of a column-major array with leading dimension
/// `ld`; a non-finite entry is ERR_NOT_FINITE naming it as `name[ld*i+k]`.
unsafe fn matrix_columns(name: &str, p: *const f64, ld_name: &str, ld: i64, nodes: usize) -> Result<Vec<[f64; 3]>> {
    if p.is_null() {
        return Err(null_error(name));
    }
    error::dimension(ld_name, ld, 3, i64::MAX / 8)?;
    let len = (ld as usize)
        .checked_mul(nodes - 1)
        .and_then(|v| v.checked_add(3))
        .ok_or_else(|| Error::new(Status::ErrInvalidDimension, format!("argument `{name}`: size overflows")))?;
    let v = std::slice::from_raw_parts(p, len);
    let ld = ld as usize;
    let cols: Vec<[f64; 3]> = (0..nodes).map(|i| [v[i * ld], v[i * ld + 1], v[i * ld + 2]]).collect();
    if let Some(j) = cols.as_flattened().iter().position(|x| !x.is_finite()) {
        let (i, k) = (j / 3, j % 3);
        return Err(Error::new(
            Status::ErrNotFinite,
            format!(
                "argument `{name}[{}]` (node {i}, component {k}, leading dimension {ld}) must be finite (got {})",
                i * ld + k,
                cols[i][k]
            ),
        ));
    }
    Ok(cols)
}

/// Relative tolerance of the closure check: on a closed curve the last
/// node must repeat the first within 1e-9·L in position and 1e-6 in the
/// unit tangent (the curve is periodic and C¹ there).
const CLOSURE_TOLERANCE: (f64, f64) = (1e-9, 1e-6);
/// Arc-length check: no chord may exceed its arc length by more than
/// 1e-9 relative (a chord never exceeds its arc), and each Hermite piece's
/// own arc length (8-point Gauss–Legendre of its speed) must lie within
/// 1 % of s_{i+1} − s_i (the energy integrates ds dt as if the speed were
/// 1; a piece whose speed is off by more is not parametrised by arc length).
/// A Hermite piece of a unit circle is short by 1.3e-7, 5.1e-4, 1.3e-3,
/// 6.4e-3, 1.9e-2 of its arc at 0.1, 0.785, 1, 1.5, 2 rad (computed by the
/// midpoint rule, 2e4 points): true arc lengths pass up to ≈ 1.7 rad of
/// turning per piece.
const ARC_TOLERANCE: (f64, f64) = (1e-9, 1e-2);

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
    if let Some(i) = s.iter().position(|v| !v.is_finite()) {
        return Err(Error::new(Status::ErrNotFinite, format!("argument `s[{i}]` must be finite (got {})", s[i])));
    }
    if let Some(i) = s.windows(2).position(|w| !(w[1] > w[0])) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!("argument `s` must increase: s[{}] = {:e} ≥ s[{}] = {:e}", i, s[i], i + 1, s[i + 1]),
        ));
    }
    // Any start: the curve's own arc length is s − s[0].
    let s: Vec<f64> = s.iter().map(|v| v - s[0]).collect();
    let r = matrix_columns("xyz", xyz, "ldx", ldx, n)?;
    let mut t = matrix_columns("tangents", tangents, "ldt", ldt, n)?;
    for (i, v) in t.iter_mut().enumerate() {
        let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        // Finite columns: the norm is never NaN.
        if norm <= 0.0 {
            return Err(Error::new(Status::ErrOutOfRange, format!("argument `tangents`: column {i} is zero")));
        }
        v.iter_mut().for_each(|c| *c /= norm);
    }
    let closed = flag("closed", closed)?;
    let length = s[n - 1];
    if closed {
        let gap = crate::geometry::vec3::distance(&r[0], &r[n - 1]);
        let turn = crate::geometry::vec3::distance(&t[0], &t[n - 1]);
        if !(gap <= CLOSURE_TOLERANCE.0 * length && turn <= CLOSURE_TOLERANCE.1) {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!(
                    "argument `closed` is 1 but the last node does not repeat the first: position gap {gap:e} \
                     (allowed {:e}·L = {:e}), unit-tangent difference {turn:e} (allowed {:e})",
                    CLOSURE_TOLERANCE.0,
                    CLOSURE_TOLERANCE.0 * length,
                    CLOSURE_TOLERANCE.1
                ),
            ));
        }
    }
    let curve = HermiteCurve::new(s, r, t, closed)?;
    check_arc_length(&curve)?;
    Ok(curve)
}

/// [`ARC_TOLERANCE`] on every piece.
fn check_arc_length(curve: &HermiteCurve) -> Result<()> {
    let (gx, gw) = crate::quadrature::gauss_legendre(8);
    for i in 0..curve.s.len() - 1 {
        let (s0, s1) = (curve.s[i], curve.s[i + 1]);
        let h = s1 - s0;
        let chord = crate::geometry::vec3::distance(&curve.r[i], &curve.r[i + 1]);
        let arc: f64 = gx
            .iter()
            .zip(&gw)
            .map(|(x, w)| {
                let d = curve.eval(s0 + 0.5 * h * (1.0 + x)).1;
                0.5 * h * w * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
            })
            .sum();
        if !(chord <= h * (1.0 + ARC_TOLERANCE.0) && (arc - h).abs() <= ARC_TOLERANCE.1 * h) {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!(
                    "argument `s` is not the arc length of the positions: s[{}] − s[{i}] = {h:e}, but the chord \
                     is {chord:e} and the Hermite piece through xyz and tangents is {arc:e} long (allowed: chord \
                     ≤ Δs·(1 + {:e}), piece within {:e}·Δs)",
                    i + 1,
                    ARC_TOLERANCE.0,
                    ARC_TOLERANCE.1
                ),
            ));
        }
    }
    Ok(())
}

/// The Rust API names the settings by their mathematical names; the C
/// caller knows them as fields of `spec` (every message names the C
/// field).
fn c_names(mut e: Error) -> Error {
    for (rust, c) in [
        ("`delta`", "`spec.near_width`"),
        ("`order`", "`spec.order`"),
        ("`kappa`", "`spec.kappa`"),
        ("`a`", "`spec.a`"),
        ("`line charge`", "`spec.line_charge`"),
        ("`length`", "`s` (its span s[nodes-1] − s[0], the curve's length)"),
    ] {
        e.message = e.message.replace(&format!("argument {rust}"), &format!("argument {c}"));
    }
    e
}

/// The base-pair sum's bound: at most this many pair evaluations (all
/// pairs, N(N − 1)/2 for N charges: ≈ 45 000 charges; 10–30 s at 10–30 ns
/// a pair). The same figure as the continuum's kernel-evaluation bound.
pub const MAX_BASE_PAIR_EVALUATIONS: f64 = electrostatics::MAX_KERNEL_EVALUATIONS;

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

/// The continuum electrostatic self-energy of the curve at the caller's
/// settings (`spec.near_width` δ, `spec.order`) — without an error
/// estimate: the result carries the near-zone truncation of its δ (see
/// RodkitElectrostaticsSpec: O(δ⁴) relative in the interior, O(δ³) at open ends) and
/// the quadrature error of its order. For an energy with a measured
/// error, use `rodkit_curve_electrostatic_energy_within`.
/// nodes 2…2²⁶; `closed` 1: the last node repeats the first and the curve
/// is periodic. Statuses: ERR_NULL_POINTER; ERR_NOT_FINITE (an entry of
/// s, xyz, tangents or a `spec` field); ERR_INVALID_DIMENSION (a leading
/// dimension < 3); ERR_OUT_OF_RANGE (nodes, `spec.order` outside 2…32,
/// `spec.near_width` not in (a, L) — (a, L/2) closed —, s not increasing
/// or not the arc length, `closed` not 0/1 or not closed, a zero tangent);
/// ERR_WORK_LIMIT (above the work bounds, e.g. κ = 1e7 on a length of 20:
/// panels of 4e-7); ERR_NON_FINITE_RESULT. Nothing is written on failure.
/// cbindgen:fortran-arrays=[s, xyz, tangents]
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
        let e = electrostatics::energy(&curve, &charge, &screening, &quad).map_err(c_names)?;
        *out = ElectrostaticEnergy { total: e.total, near: e.near, far: e.far };
        Ok(Status::Ok)
    })
}

/// The discrete base-pair energy of the same curve: charges λ·b at spacing
/// b (≈ `spacing`, adjusted to divide the length) at the midpoints, all
/// pairs with |s_i − s_j| > a (the thesis's comparison, O(N²)).
/// `spec.near_width` and `spec.order` are checked but unused. Statuses as
/// `rodkit_curve_electrostatic_energy`, and ERR_WORK_LIMIT when the
/// N(N − 1)/2 pairs exceed 1e9 (N = round(L/spacing): about 45 000
/// charges).
/// cbindgen:fortran-arrays=[s, xyz, tangents]
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
        error::positive("spacing", spacing)?;
        // Sized before anything is allocated: N charges, N(N − 1)/2 pairs.
        let count = (curve.length() / spacing).round().max(1.0);
        let pairs = 0.5 * count * (count - 1.0);
        if pairs > MAX_BASE_PAIR_EVALUATIONS {
            return Err(Error::new(
                Status::ErrWorkLimit,
                format!(
                    "the call would exceed its work bound: {count:.3e} charges at `spacing` {spacing:e} give \
                     {pairs:.3e} pair evaluations (bound {MAX_BASE_PAIR_EVALUATIONS:.0e}); raise the spacing or use \
                     the continuum energy"
                ),
            ));
        }
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
/// panel (2…32). Work: about ½(nodes·order)² kernel evaluations; above 1e9
/// (10–30 s) the call is refused with RODKIT_STATUS_ERR_WORK_LIMIT stating the
/// cost.
/// cbindgen:fortran-arrays=[s, xyz, tangents]
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
        let out = arg_mut("writhe_out", writhe_out)?;
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
    /// Estimated relative error: near-zone truncation (measured from two
    /// near-zone widths) + quadrature (two Gauss orders) + the cutoff's
    /// tail (two cutoffs) + round-off.
    pub estimate: f64,
}

/// Only what the scene requires: the energy of the curve within the
/// relative `tolerance` (1e-14…0.1), the settings used and the estimate
/// (`out->estimate` ≤ tolerance on success). `spec.near_width` and
/// `spec.order` are ignored (chosen here).
/// How: δ starts at a quarter of the curve's own scale (its shortest piece,
/// its smallest radius of curvature; at least 4a), whatever a is. At each
/// δ the Gauss order is raised by 4 (3 or 6…32) until two orders agree to
/// tol/4; δ then moves toward a (δ − a divided by r ≥ 4). The near-zone
/// truncation T grows convexly from T = 0 at δ = a, so
/// |T(δ')| ≤ |E(δ) − E(δ')|/(r − 1): counted twice in the estimate. Under
/// screening, far pairs beyond a cutoff r_c are dropped and the tail is
/// measured against a wider cutoff, whose value is returned.
/// Measured (tests/electrostatics_estimates.rs): true error ≤ estimate ≤
/// tolerance for 1e-2…1e-12 on straight segments, Coulomb and
/// Debye–Hückel rings and a helix, and for 1e-3…1e-8 on Hermite curves
/// through nodes with a from 1e-9·L to 0.1·L. On curves of ≤ 100 nodes a
/// call answers or refuses within about a second (benches/README.md).
/// Statuses: those of `rodkit_curve_electrostatic_energy` (without
/// `spec.near_width`/`spec.order`); ERR_TOLERANCE_UNREACHABLE when the
/// tolerance is below what round-off (8ε·N^{1/4} for N kernel evaluations;
/// ≈ 3e-14 on a ring of 16 nodes) or Gauss order 32 reach; ERR_WORK_LIMIT
/// before a step that would take the call past 4e7 kernel evaluations
/// (about a second; or past an evaluation's bounds), naming that step's
/// cost. Both messages state the best estimate reached; `out` is not
/// written then.
/// cbindgen:fortran-arrays=[s, xyz, tangents]
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
        let r = electrostatics::energy_within(&curve, &charge, &screening, tolerance).map_err(c_names)?;
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

//! Electrostatic self-interaction of a charged rod's centreline
//! (physics.md §3): the continuum line charge with the near-field
//! regularisation of §3.2 and, for comparison, the discrete base-pair
//! model of §3.3.
//!
//! Energy, in units of 1/(4πε0εr) (multiply by k_BT·l_B per e² for
//! physical units):
//!   E = ½ ∫∫_{|s−t|>a} λ(s) λ(t) Φ(|r(s) − r(t)|) ds dt,  Φ(d) = e^{−κd}/d,
//! κ = 0 being Coulomb. Written E = ∫ e(s) ds with the energy density
//! e(s) = ½ λ(s) ∫_{|t−s|>a} λ(t) Φ dt, whose inner integral is split at
//! |t − s| = δ:
//! * near zone a < |h| < δ (h = t − s): the geometry is expanded about s,
//!   d = |h| (1 − c²h²/24 + O(h³)) with c = |r''(s)| the curvature, so
//!   Φ(d) = e^{−κ|h|}/|h| · [1 + c²h²/24 + κc²|h|³/24 + (odd in h) + O(h⁴)],
//!   and the charge λ(s + h) = λ + λ'h + ½λ''h² + …; every term is then
//!   integrated exactly in h with e^{−κ|h|} kept whole ([`special::j`]:
//!   exponential integrals at high salt, a series as κ → 0). Interior
//!   points have two sides of length δ and the odd terms cancel; within δ
//!   of an end of an open rod the side is one-sided (length s or L − s) and
//!   the λ'-term stays. Truncation: O(δ⁴) for a uniform charge in the
//!   interior, O(δ³) with a varying charge or at the ends (the odd
//!   geometric term r''·r''' h³ is not included). Nothing singular reaches
//!   a division: the |h| < a part is excluded and the near integrals are
//!   analytic.
//!   On a curve not parametrised by its arc length (a cubic through nodes)
//!   the chord is expanded with the curve's own speed ([`Chord`]).
//! * far zone |h| ≥ δ: Gauss–Legendre of the chosen order on global panels
//!   of the curve's own scale ([`far_panel`]) that break at its nodes, and
//!   within two panels of s on local panels graded at |h| = δ, 2δ, 4δ, …
//!   (the integrand varies like 1/h there), and δ + 2^k/κ under strong
//!   screening.
//!
//! The outer integral over s uses the same rule on panels broken at the
//! nodes and where the near zone changes shape (s = a, δ from each end),
//! graded at a + 2^k/κ (a boundary layer of width 1/κ at high salt).
//!
//! Measured (tests/electrostatics.rs): straight segments to 1e-13 of the
//! §3.5 closed forms at any δ (no curvature, nothing truncated); the
//! Coulomb ring's error equals the first dropped term 2πR·7δ⁴/(23040R⁴)
//! within 0.1 %, falling at order 4.00; the OSF stiffness 1/(4κ²) from
//! rings at κR = 20, 40; the base-pair sum converging at O(b).
//!
//! Force: [`force_density`] (the regularised f(s) of §3.1, r''·ln(δ/a) and
//! λλ'd3·ln(δ/a) near-zone terms, one-sided at the ends; O(δ²), checked on
//! rings against the exact virial) and [`energy_gradient`] (the exact
//! derivative of the quadrature energy for a Hermite centreline).
//!
//! This module is the field of a centreline only: the curve itself and its
//! writhe are [`crate::geometry`]; the charged rod — this field as a term
//! of a rod's equations, its branches and the DNA scene — is
//! [`crate::charged`].

pub mod discrete;
pub mod special;

use crate::error::{self, Error, Result};
use crate::geometry::vec3::{dot, sub};
pub use crate::geometry::{Centerline, HermiteCurve};
use crate::quadrature::{gauss_legendre, panels};
use crate::status::Status;

/// The line charge density λ(s) with its first two derivatives.
#[derive(Clone)]
pub enum LineCharge {
    Uniform(f64),
    /// λ(s) → (λ, λ', λ'').
    Profile(std::sync::Arc<dyn Fn(f64) -> (f64, f64, f64) + Send + Sync>),
}

impl LineCharge {
    pub fn at(&self, s: f64) -> (f64, f64, f64) {
        match self {
            LineCharge::Uniform(q) => (*q, 0.0, 0.0),
            LineCharge::Profile(f) => f(s),
        }
    }
}

/// The interaction: inverse Debye length κ (0: Coulomb) and the excluded
/// arc-length distance a (the rod's radius scale).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Screening {
    pub kappa: f64,
    pub a: f64,
}

/// Quadrature of the continuum energy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyQuadrature {
    /// Near-zone half-width δ (> a).
    pub delta: f64,
    /// Gauss–Legendre points per panel (2…32).
    pub order: usize,
    /// Screening cutoff r_c: far-zone pairs farther apart in space are
    /// dropped (neighbours by cell lists, so an evaluation costs O(N));
    /// None keeps every pair (Coulomb needs that). See
    /// [`discrete::screening_cutoff`] for r_c from a tolerance.
    pub cutoff: Option<f64>,
}

/// The energy and its split.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Energy {
    pub total: f64,
    /// ∫ of the near-zone (analytic) part and of the far-zone part.
    pub near: f64,
    pub far: f64,
    /// Far-zone kernel evaluations (the cost: O(N) with a cutoff, O(N²)
    /// without).
    pub far_evaluations: usize,
}

fn validate(curve: &dyn Centerline, screening: &Screening, quad: &EnergyQuadrature) -> Result<()> {
    error::positive("length", curve.length())?;
    error::finite("kappa", screening.kappa)?;
    if screening.kappa < 0.0 {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!("argument `kappa` must be ≥ 0 (got {:e})", screening.kappa),
        ));
    }
    error::positive("a", screening.a)?;
    error::finite("delta", quad.delta)?;
    if !(quad.delta > screening.a) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!("argument `delta` ({:e}) must exceed a ({:e})", quad.delta, screening.a),
        ));
    }
    let l = curve.length();
    let max_delta = if curve.closed() { 0.5 * l } else { l };
    if !(quad.delta < max_delta) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!(
                "argument `delta` ({:e}) must be below {} ({max_delta:e})",
                quad.delta,
                if curve.closed() { "L/2 on a closed curve" } else { "L" }
            ),
        ));
    }
    error::count_in_range("order", quad.order as i64, 2, 32)?;
    Ok(())
}

/// The near-zone part of ½∫λ(t)Φ dt at s, one side of length ℓ (≥ a).
/// J₋₁, J₀, J₁, J₂ on [a, ℓ] (computed once for full sides ℓ = δ).
fn near_integrals(l: f64, s: &Screening) -> [f64; 4] {
    if l <= s.a {
        return [0.0; 4];
    }
    [
        special::j(-1, s.a, l, s.kappa),
        special::j(0, s.a, l, s.kappa),
        special::j(1, s.a, l, s.kappa),
        special::j(2, s.a, l, s.kappa),
    ]
}

/// The chord about s on a curve whose parameter is not exactly its arc
/// length (a cubic through nodes: its speed v = |r'| departs from 1 between
/// nodes). From |r(s+h) − r(s)|² = v²h² + (r'·r'')h³ + (|r''|²/4 + r'·r'''/3)h⁴,
///   d = v|h| (1 + αh + βh² + O(h³)),  α = r'·r''/(2v²),  β = (Q − α²)/2,
/// with Q = −|r''|²/(12v²): r'·r''' is taken as −|r''|², its value for a
/// curve of constant speed. The cubic's own r''' is first-order accurate
/// only and jumps at every node, so across a near zone wider than an
/// element it would move β by O(h) (measured: a Hermite helix's energy at
/// fixed δ then stalled at 1.7e-6 instead of converging at order ≥ 3).
/// At v = 1: α = 0, β = −c²/24, the expansion of the module docs. The
/// speed itself matters at first order: without it the leading term
/// ∫ dh/(v|h|) is off by (1/v − 1)·ln(δ/a), which no δ above a removes (a
/// 41-node Hermite helix's energy moved by 8e-6 relative per fourfold δ).
#[derive(Clone, Copy, Debug)]
struct Chord {
    v: f64,
    alpha: f64,
    beta: f64,
    q: f64,
}

impl Chord {
    fn new(r1: [f64; 3], r2: [f64; 3]) -> Chord {
        let vv = dot(r1, r1);
        let alpha = dot(r1, r2) / (2.0 * vv);
        let q = -dot(r2, r2) / (12.0 * vv);
        Chord { v: vv.sqrt(), alpha, beta: 0.5 * (q - alpha * alpha), q }
    }
}

/// One side of the near zone on a curve of speed v ([`Chord`]): with
/// h = σu and K_m = ∫_a^ℓ u^m e^{−κvu} du (`j`, computed at κv),
///   ∫ λ(s+h) e^{−κd}/d du = (1/v)[λK₋₁ + σ(λ' − λα)K₀ + (½λ'' + λ(α² − β) − λ'α)K₁]
///                           − σκαλK₁ − κ(β − α²)λK₂ − κα λ' K₂ + O(h³),
/// the products of the expansions of 1/d, e^{−κd} and λ kept to the order
/// of the arc-length form, to which it reduces at v = 1 — except one term of
/// that order when κu counts as order 0, +½κ²vα²λK₃ (the square of the
/// exponent's αh part), left out: α = r'·r''/2v² is the speed's own
/// variation, small on a cubic through nodes, and without the term the
/// truncation is O(δ²) rather than O(δ³) where κδ is not small (measured on
/// an exact chord); `energy_within` measures the truncation either way.
fn near_side(lambda: (f64, f64, f64), sign: f64, ch: &Chord, j: &[f64; 5], kappa: f64) -> f64 {
    let (q, dq, ddq) = lambda;
    let Chord { v, alpha: al, beta: be, .. } = *ch;
    (q * j[0] + sign * (dq - q * al) * j[1] + (0.5 * ddq + q * (al * al - be) - dq * al) * j[2]) / v
        - sign * kappa * al * q * j[2]
        - kappa * (be - al * al) * q * j[3]
        - kappa * al * dq * j[3]
}

/// The near zone at one point (both sides) per unit factor ½λ(s), and its
/// derivatives with respect to r' and r''.
struct NearValue {
    value: f64,
    d1: [f64; 3],
    d2: [f64; 3],
}

/// Both sides of the near zone ([`near_side`]; `k[side]` = K₋₁ … K₃ at κv,
/// K₃ needed only for the derivatives), and with `derivatives` the exact
/// derivatives of that formula with respect to r' and r'' through
/// V = r'·r', P = r'·r'', C = r''·r'' (v = √V, α = P/2V, Q = −C/12V,
/// β = (Q − α²)/2; ∂K_m/∂v = −κK_{m+1}).
fn near_zone(
    lambda: (f64, f64, f64),
    ch: &Chord,
    r: [[f64; 3]; 2],
    k: &[[f64; 5]; 2],
    kappa: f64,
    derivatives: bool,
) -> NearValue {
    let (q, dq, ddq) = lambda;
    let Chord { v, alpha: al, beta: be, q: qq } = *ch;
    let mut value = 0.0;
    let (mut f_v, mut f_a, mut f_b) = (0.0, 0.0, 0.0);
    for (kk, sign) in k.iter().zip([-1.0, 1.0]) {
        value += near_side(lambda, sign, ch, kk, kappa);
        if !derivatives {
            continue;
        }
        let c2 = 0.5 * ddq + q * (al * al - be) - dq * al;
        let bracket = q * kk[0] + sign * (dq - q * al) * kk[1] + c2 * kk[2];
        let bracket_v = -kappa * (q * kk[1] + sign * (dq - q * al) * kk[2] + c2 * kk[3]);
        f_v += -bracket / (v * v)
            + bracket_v / v
            + kappa * kappa * (sign * al * q * kk[3] + (be - al * al) * q * kk[4] + al * dq * kk[4]);
        f_a += (-sign * q * kk[1] + (2.0 * q * al - dq) * kk[2]) / v - sign * kappa * q * kk[2]
            + 2.0 * kappa * al * q * kk[3]
            - kappa * dq * kk[3];
        f_b += -q * kk[2] / v - kappa * q * kk[3];
    }
    if !derivatives {
        return NearValue { value, d1: [0.0; 3], d2: [0.0; 3] };
    }
    let vv = v * v;
    let f_vv = f_v / (2.0 * v) - f_a * al / vv + f_b * (2.0 * al * al - qq) / (2.0 * vv);
    let f_p = (f_a - f_b * al) / (2.0 * vv);
    let f_c = -f_b / (24.0 * vv);
    let [r1, r2] = r;
    NearValue {
        value,
        d1: std::array::from_fn(|i| 2.0 * r1[i] * f_vv + r2[i] * f_p),
        d2: std::array::from_fn(|i| r1[i] * f_p + 2.0 * r2[i] * f_c),
    }
}

/// The continuum electrostatic energy of `curve` carrying `charge`.
pub fn energy(
    curve: &dyn Centerline,
    charge: &LineCharge,
    screening: &Screening,
    quad: &EnergyQuadrature,
) -> Result<Energy> {
    energy_core(curve, charge, screening, quad, None)
}

/// Where the energy's sensitivities go: for every evaluation point s, ∂E
/// with respect to r(s), r'(s) and r''(s) (the near zone sees the speed
/// and the curvature).
type Sink<'a> = Option<&'a mut dyn FnMut(f64, [[f64; 3]; 3])>;

/// The quadrature of [`energy`]; with a sink, also the derivative of the
/// quadrature formula itself (positions at the quadrature points and
/// r'' at the outer points; the points' arc lengths are fixed).
fn energy_core(
    curve: &dyn Centerline,
    charge: &LineCharge,
    screening: &Screening,
    quad: &EnergyQuadrature,
    mut sink: Sink<'_>,
) -> Result<Energy> {
    validate(curve, screening, quad)?;
    check_work(&energy_work(curve, screening, quad))?;
    let l = curve.length();
    let closed = curve.closed();
    let delta = quad.delta;
    let kappa = screening.kappa;
    let (gx, gw) = gauss_legendre(quad.order);
    let nodes = curve.breakpoints();
    // Φ(d) and Φ'(d)/d.
    let phi = |d: f64| -> (f64, f64) {
        if kappa == 0.0 {
            (1.0 / d, -1.0 / (d * d * d))
        } else {
            let e = (-kappa * d).exp() / d;
            (e, -e * (kappa + 1.0 / d) / d)
        }
    };
    // Outer panels: nodes, and where the near zone changes shape.
    let mut outer_breaks = nodes.clone();
    // e(s) has a kink where the far zone's edge s ± δ crosses a node (the
    // curve is only C¹ there, C² in its speed): breaking the outer panels
    // there keeps the outer rule's geometric convergence in the order.
    // A closed curve's closing node (s = 0 ≡ L) is no breakpoint, yet its
    // edges δ and L − δ are kinks too.
    let closing: &[f64] = if closed { &[0.0] } else { &[] };
    for &b in nodes.iter().chain(closing) {
        for edge in [b - delta, b + delta] {
            outer_breaks.push(if closed { edge.rem_euclid(l) } else { edge });
        }
    }
    if !closed {
        outer_breaks.extend([screening.a, delta, l - delta, l - screening.a]);
        // Near an end e(s) varies like ln(s/a) on [a, δ] (the one-sided
        // near integral) and like ln(s/δ) beyond (the far side's length):
        // both singular at s = 0, so panels graded geometrically from each
        // end (a·2^k below δ, δ·2^k up to L/2). Without them one Gauss
        // panel spanned [δ, first node] and a Coulomb segment of length
        // 1e4 on 8 nodes came out 4.5e-5 off, before these panels.
        outer_breaks.extend(end_grading(screening.a, delta, l));
        // Strong screening: within δ of an end, e(s) has a boundary layer
        // of width 1/κ next to s = a (the one-sided near integral starts
        // there): panels graded at a + 2^k/κ.
        if kappa > 0.0 {
            let mut d = 0.25 / kappa;
            while screening.a + d < delta {
                outer_breaks.extend([screening.a + d, l - screening.a - d]);
                d *= 2.0;
            }
        }
    }
    let (mut near_total, mut far_total) = (0.0, 0.0);
    let mut inner_points: Vec<(f64, f64, [f64; 3])> = Vec::new();
    let mut scratch = Vec::new();
    let mut evaluations = 0;
    let far = FarZone::new(curve, delta, kappa, quad.cutoff, &gx, &gw);
    let full_side = near_integrals(delta, screening);
    for (s0, s1) in panels(0.0, l, &outer_breaks) {
        let half = 0.5 * (s1 - s0);
        for (xi, wi) in gx.iter().zip(&gw) {
            let s = s0 + half * (1.0 + xi);
            let w = half * wi;
            let (r, r1, r2) = curve.eval(s);
            let lam = charge.at(s);
            // Near zone: the two sides (one-sided within δ of an end).
            let (left, right) = if closed { (delta, delta) } else { (s.min(delta), (l - s).min(delta)) };
            // The near zone and, with a sink, its sensitivities to r' and r''.
            let want = sink.is_some();
            let ch = Chord::new(r1, r2);
            // The integrals at κv; at unit speed (or without screening) the
            // full sides' are precomputed.
            let unit = kappa == 0.0 || (ch.v - 1.0).abs() <= 4.0 * f64::EPSILON;
            let scaled = Screening { kappa: kappa * ch.v, a: screening.a };
            let side = |len: f64| -> [f64; 5] {
                let j = if len == delta && unit { full_side } else { near_integrals(len, &scaled) };
                // K₃ only for the derivative in v (∂K_m/∂v = −κK_{m+1}).
                let k3 = if want && kappa > 0.0 && len > screening.a {
                    special::j(3, screening.a, len, scaled.kappa)
                } else {
                    0.0
                };
                [j[0], j[1], j[2], j[3], k3]
            };
            let near = near_zone(lam, &ch, [r1, r2], &[side(left), side(right)], kappa, want);
            far.points_for(curve, s, &r, &mut inner_points, &mut scratch);
            let mut far = 0.0;
            let mut grad_s = [0.0; 3];
            evaluations += inner_points.len();
            for &(t, wt, rt) in &inner_points {
                let dv = sub(r, rt);
                let d = dot(dv, dv).sqrt();
                if d > 0.0 {
                    let (f, g) = phi(d);
                    let lt = charge.at(t).0;
                    far += wt * lt * f;
                    if let Some(sink) = sink.as_deref_mut() {
                        // ∂/∂r(s) of w·½λ(s)·wt·λ(t)·Φ(d) is c·(r(s) − r(t)), −that for r(t).
                        let c = w * 0.5 * lam.0 * wt * lt * g;
                        let gv = [c * dv[0], c * dv[1], c * dv[2]];
                        for i in 0..3 {
                            grad_s[i] += gv[i];
                        }
                        sink(t, [[-gv[0], -gv[1], -gv[2]], [0.0; 3], [0.0; 3]]);
                    }
                }
            }
            if let Some(sink) = sink.as_deref_mut() {
                let c = w * 0.5 * lam.0;
                let scale = |v: [f64; 3]| [c * v[0], c * v[1], c * v[2]];
                sink(s, [grad_s, scale(near.d1), scale(near.d2)]);
            }
            near_total += w * 0.5 * lam.0 * near.value;
            far_total += w * 0.5 * lam.0 * far;
        }
    }
    let total = near_total + far_total;
    if !total.is_finite() {
        return Err(Error::new(Status::ErrNonFiniteResult, "electrostatic energy is not finite"));
    }
    Ok(Energy { total, near: near_total, far: far_total, far_evaluations: evaluations })
}

/// Outer breaks graded geometrically toward both ends of an open curve of
/// length `l`: a·2^k inside (a, δ) and δ·2^k inside (δ, L/2), mirrored.
fn end_grading(a: f64, delta: f64, l: f64) -> Vec<f64> {
    let mut b = Vec::new();
    let mut x = 2.0 * a;
    while x < delta {
        b.extend([x, l - x]);
        x *= 2.0;
    }
    let mut x = 2.0 * delta;
    while x < 0.5 * l {
        b.extend([x, l - x]);
        x *= 2.0;
    }
    b
}

/// The work bound of one continuum evaluation ([`energy`],
/// [`energy_gradient`], each step of [`energy_within`]): at most
/// [`MAX_KERNEL_EVALUATIONS`] far-zone kernel evaluations (≈ 10–30 s at
/// 10–30 ns each) and at most [`MAX_FAR_POINTS`] stored far-zone
/// quadrature points (48 bytes each: ≈ 200 MB). Beyond either the call is
/// refused with ErrWorkLimit before anything is allocated.
pub const MAX_KERNEL_EVALUATIONS: f64 = 1e9;
/// See [`MAX_KERNEL_EVALUATIONS`].
pub const MAX_FAR_POINTS: f64 = 4e6;

/// The size of one evaluation, computed up front from the panel counts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Work {
    /// Stored far-zone quadrature points (global panels × order).
    pub far_points: f64,
    /// Outer quadrature points (outer panels × order).
    pub outer_points: f64,
    /// Far-zone kernel evaluations: outer points × (far points seen from
    /// each; with a cutoff, the largest sampled fraction of the curve
    /// within r_c in space — plus the local window).
    pub evaluations: f64,
}

/// The work of one [`energy`] evaluation at these settings, an upper bound
/// (tests/electrostatics.rs holds it against the energy's own count); it
/// allocates only the global panel edges.
pub fn energy_work(curve: &dyn Centerline, screening: &Screening, quad: &EnergyQuadrature) -> Work {
    let l = curve.length();
    let delta = quad.delta;
    let o = quad.order as f64;
    let panel = far_panel(curve, delta, screening.kappa);
    let edges = global_edges(curve, panel);
    let global = (edges.len() - 1) as f64;
    let mut nodes = curve.breakpoints();
    nodes.push(l);
    // Outer panels: the node intervals plus the end grading and the
    // screening layer (≤ 2 log2 of the ratios each), as in energy_core.
    let log2 = |r: f64| if r > 1.0 { r.log2().ceil() } else { 0.0 };
    // Nodes, and node ± δ (where the far zone's edge crosses a node).
    let mut outer = 3.0 * nodes.len() as f64;
    if !curve.closed() {
        outer += 4.0 + 2.0 * log2(delta / screening.a) + 2.0 * log2(0.5 * l / delta);
        if screening.kappa > 0.0 {
            outer += 2.0 * log2(4.0 * screening.kappa * delta);
        }
    }
    // The local window (FarZone::points_for): the global panels meeting
    // |t − s| < 2G, i.e. at most the global edges within any stretch of
    // 2·2G + 2G (cyclic when closed) — many more than a few where nodes lie
    // closer than G — each side then graded from δ (δ, 3δ, 7δ, … up to the
    // side's length ≤ 3G) and, under screening, at 2^k/(4κ) below δ.
    let reach = 2.0 * panel;
    let span = 2.0 * reach + 2.0 * panel;
    let mut cyclic = edges.clone();
    if curve.closed() {
        cyclic.extend(edges.iter().skip(1).map(|e| e + l));
    }
    let (mut most, mut lo) = (0usize, 0usize);
    for hi in 0..cyclic.len() {
        while cyclic[hi] - cyclic[lo] > span {
            lo += 1;
        }
        most = most.max(hi - lo + 1);
    }
    let most = (most as f64).min(global + 1.0);
    let grading = log2((reach + panel) / delta + 1.0) + 1.0 + log2(4.0 * screening.kappa * delta) + 1.0;
    let window = (most + 2.0 * (grading + 1.0)) * o;
    let far_points = global * o;
    let per_point = match quad.cutoff {
        None => far_points,
        Some(rc) => far_points.min(cutoff_fraction(curve, rc) * far_points + o),
    };
    let outer_points = outer * o;
    Work { far_points, outer_points, evaluations: outer_points * (per_point + window) }
}

/// The largest fraction of the curve within r_c (in space) of one of its
/// points, sampled: 16 points against 256 (each counted with half a
/// sample's arc length of margin). On a straight rod it is 2r_c/L; on a
/// coiled one much more (a helix of pitch 3 packs 2.3 units of arc into a
/// unit of height), which the arc-length estimate 2r_c/L missed by 25 %.
fn cutoff_fraction(curve: &dyn Centerline, rc: f64) -> f64 {
    const M: usize = 256;
    let l = curve.length();
    let at = |k: usize, n: usize| curve.eval((k as f64 + 0.5) * l / n as f64).0;
    let targets: Vec<[f64; 3]> = (0..M).map(|k| at(k, M)).collect();
    let reach = rc + 0.5 * l / M as f64;
    (0..16)
        .map(|i| {
            let p = at(i, 16);
            let near = targets.iter().filter(|t| dot(sub(p, **t), sub(p, **t)) <= reach * reach).count();
            (near + 1) as f64 / M as f64
        })
        .fold(0.0, f64::max)
        .min(1.0)
}

fn check_work(work: &Work) -> Result<()> {
    if work.far_points > MAX_FAR_POINTS || work.evaluations > MAX_KERNEL_EVALUATIONS {
        return Err(Error::new(
            Status::ErrWorkLimit,
            format!(
                "the call would exceed its work bound: {:.2e} far-zone kernel evaluations on {:.2e} stored points \
                 (bounds {MAX_KERNEL_EVALUATIONS:.0e} evaluations, {MAX_FAR_POINTS:.0e} points); the far zone is \
                 paneled at the curve's own scale (its shortest element, its smallest radius of curvature, 4/κ, \
                 at least 2δ) and graded toward δ and a: use fewer nodes, a smoother curve, or a wider near zone",
                work.evaluations, work.far_points
            ),
        ));
    }
    Ok(())
}

/// The length G of the far zone's global panels: the curve's own scale
/// ([`geometric_scale`]: its shortest element and smallest radius of
/// curvature), at most 4/κ (the screened kernel's), never below 2δ. Beyond
/// the window |t − s| ≥ 2G the integrand varies on scales ≥ G, so a panel of
/// G keeps Gauss's geometric convergence; tying the panels to 2δ instead made
/// an evaluation cost O((L/δ)²) and the narrow widths that accuracy needs
/// unaffordable.
/// The far zone's global panel edges, ascending from 0 to L: each node
/// interval cut into equal panels of at most `panel`.
fn global_edges(curve: &dyn Centerline, panel: f64) -> Vec<f64> {
    let l = curve.length();
    let mut edges = vec![0.0];
    let mut nodes = curve.breakpoints();
    nodes.push(l);
    let mut last = 0.0;
    for &b in &nodes {
        if b <= last {
            continue;
        }
        let pieces = ((b - last) / panel).ceil().max(1.0) as usize;
        for k in 1..=pieces {
            edges.push(last + (b - last) * k as f64 / pieces as f64);
        }
        last = b;
    }
    edges
}

fn far_panel(curve: &dyn Centerline, delta: f64, kappa: f64) -> f64 {
    let mut g = geometric_scale(curve);
    if kappa > 0.0 {
        g = g.min(4.0 / kappa);
    }
    g.max(2.0 * delta)
}

/// The far-zone quadrature (t, weight) for any point s: t with
/// |t − s| ≥ δ (periodic distance when closed). Fixed global panels (the
/// curve's node intervals, cut to at most G, [`far_panel`]) carry Gauss
/// points once for all s; around s, the panels meeting |t − s| < 2G form a
/// window whose part beyond δ is integrated on local panels graded from
/// |t − s| = δ (2δ, 4δ, …, and δ + 2^k/κ), where the integrand varies like
/// 1/h. With a cutoff, global points farther than r_c in space are
/// dropped, found by a cell list: O(1) points per s.
struct FarZone {
    l: f64,
    closed: bool,
    delta: f64,
    kappa: f64,
    /// The global panels' length ([`far_panel`]).
    panel: f64,
    /// Global panel edges, ascending from 0 to L.
    edges: Vec<f64>,
    /// Global points: (t, weight, panel index, position).
    points: Vec<(f64, f64, usize, [f64; 3])>,
    cutoff: Option<(f64, crate::geometry::proximity::CellList, Vec<[f64; 3]>)>,
    gx: Vec<f64>,
    gw: Vec<f64>,
}

impl FarZone {
    fn new(curve: &dyn Centerline, delta: f64, kappa: f64, cutoff: Option<f64>, gx: &[f64], gw: &[f64]) -> Self {
        let l = curve.length();
        let panel = far_panel(curve, delta, kappa);
        let edges = global_edges(curve, panel);
        let mut points = Vec::with_capacity((edges.len() - 1) * gx.len());
        for (p, w) in edges.windows(2).enumerate() {
            let hh = 0.5 * (w[1] - w[0]);
            for (xj, wj) in gx.iter().zip(gw) {
                let t = w[0] + hh * (1.0 + xj);
                points.push((t, hh * wj, p, curve.eval(t).0));
            }
        }
        let cutoff = cutoff.map(|rc| {
            let pos: Vec<[f64; 3]> = points.iter().map(|p| p.3).collect();
            (rc, crate::geometry::proximity::CellList::new(&pos, rc), pos)
        });
        FarZone {
            l,
            closed: curve.closed(),
            delta,
            kappa,
            panel,
            edges,
            points,
            cutoff,
            gx: gx.to_vec(),
            gw: gw.to_vec(),
        }
    }

    /// The far-zone points for s at position r into `out` (t, weight,
    /// r(t)): the global points' positions are stored once, the window's
    /// evaluated on `curve`.
    fn points_for(
        &self,
        curve: &dyn Centerline,
        s: f64,
        r: &[f64; 3],
        out: &mut Vec<(f64, f64, [f64; 3])>,
        scratch: &mut Vec<usize>,
    ) {
        out.clear();
        let (l, delta) = (self.l, self.delta);
        let np = self.edges.len() - 1;
        // The window: global panels meeting |t − s| < 2G, G the global
        // panel length (at least 4δ; periodic when closed).
        let panel_of = |t: f64| -> usize {
            match self.edges.binary_search_by(|e| e.total_cmp(&t)) {
                Ok(i) => i.min(np - 1),
                Err(i) => (i.max(1) - 1).min(np - 1),
            }
        };
        let reach = 2.0 * self.panel;
        // The window as a (cyclic) range of panel indices, and its ends
        // unwrapped about s.
        // The window spans at most the reach and one global panel on each
        // side: where that covers the ring, the ring is one window (else the
        // two local ranges would overlap modulo L and count points twice).
        let whole_ring = self.closed && 2.0 * reach + 2.0 * self.panel >= l;
        let (p_lo, p_hi, w0, w1) = if self.closed {
            let p_lo = panel_of((s - reach).rem_euclid(l));
            let p_hi = panel_of((s + reach).rem_euclid(l));
            let mut w0 = self.edges[p_lo];
            if w0 > s {
                w0 -= l;
            }
            let mut w1 = self.edges[p_hi + 1];
            if w1 < s {
                w1 += l;
            }
            (p_lo, p_hi, w0, w1)
        } else {
            let p_lo = panel_of((s - reach).max(0.0));
            let p_hi = panel_of((s + reach).min(l));
            (p_lo, p_hi, self.edges[p_lo], self.edges[p_hi + 1])
        };
        let in_window = |p: usize| -> bool {
            if p_lo <= p_hi {
                p >= p_lo && p <= p_hi
            } else {
                p >= p_lo || p <= p_hi
            }
        };
        // Local graded panels on the window beyond δ.
        let mut add_range = |t0: f64, t1: f64, grade_start: bool, grade_end: bool| {
            if t1 <= t0 {
                return;
            }
            // The global edges inside [t0, t1] (shifted by ±L when closed):
            // found by binary search, so a point costs O(its window).
            let mut breaks: Vec<f64> = Vec::new();
            for shift in
                if self.closed { [-l, 0.0, l] } else { [0.0, 0.0, 0.0] }.iter().take(if self.closed { 3 } else { 1 })
            {
                let (lo, hi) = (t0 - shift, t1 - shift);
                let start = self.edges.partition_point(|&e| e <= lo);
                for &e in self.edges[start..].iter().take_while(|&&e| e < hi) {
                    breaks.push(e + shift);
                }
            }
            let mut steps = vec![];
            let mut k = delta;
            while k < t1 - t0 {
                steps.push(k);
                k = 2.0 * k + delta;
            }
            if self.kappa > 0.0 {
                let mut k = 0.25 / self.kappa;
                while k < (t1 - t0).min(delta) {
                    steps.push(k);
                    k *= 2.0;
                }
            }
            for k in steps {
                if grade_start {
                    breaks.push(t0 + k);
                }
                if grade_end {
                    breaks.push(t1 - k);
                }
            }
            for (p0, p1) in panels(t0, t1, &breaks) {
                let hh = 0.5 * (p1 - p0);
                for (xj, wj) in self.gx.iter().zip(&self.gw) {
                    let t = p0 + hh * (1.0 + xj);
                    let t = if self.closed { t.rem_euclid(l) } else { t };
                    out.push((t, hh * wj, curve.eval(t).0));
                }
            }
        };
        if whole_ring {
            add_range(s + delta, s + l - delta, true, true);
            return;
        }
        add_range(w0, s - delta, false, true);
        add_range(s + delta, w1, true, false);
        // Global points outside the window (within the cutoff).
        match &self.cutoff {
            None => {
                for &(t, w, p, rt) in &self.points {
                    if !in_window(p) {
                        out.push((t, w, rt));
                    }
                }
            }
            Some((rc, cells, pos)) => {
                cells.neighbours_within(pos, r, *rc, scratch);
                for &i in scratch.iter() {
                    let (t, w, p, rt) = self.points[i];
                    if !in_window(p) {
                        out.push((t, w, rt));
                    }
                }
            }
        }
    }
}

/// The electrostatic force density at s (spatial, per unit length):
///   f(s) = λ(s) ∫_{|t−s|>a} λ(t) g(d) (r(s) − r(t)) dt,  g = −Φ'(d)/d,
/// minus the functional derivative of [`energy`] at fixed arc lengths.
/// Near zone (a < |h| < δ), with r(s) − r(s+h) = −(h r' + ½h² r'' + …):
/// per side of length ℓ, −½λ r''(J₋₁ + κJ₀) − λ' r'(J₋₁ + κJ₀) (the
/// curvature's r''·ln(δ/a) and the varying charge's tangential term of
/// §3.2) and, where the side is cut short by an end, the odd term
/// ∓λ r'(e^{−κa}/a − e^{−κℓ}/ℓ), which cancels between two equal sides.
/// Truncation: O(δ²) in the interior, O(δ) within δ of an end.
pub fn force_density(
    curve: &dyn Centerline,
    charge: &LineCharge,
    screening: &Screening,
    quad: &EnergyQuadrature,
    s: f64,
) -> Result<[f64; 3]> {
    validate(curve, screening, quad)?;
    let l = curve.length();
    error::finite("s", s)?;
    if !(0.0..=l).contains(&s) {
        return Err(Error::new(Status::ErrOutOfRange, format!("argument `s` ({s:e}) outside [0, {l:e}]")));
    }
    let closed = curve.closed();
    let (delta, kappa, a) = (quad.delta, screening.kappa, screening.a);
    let (gx, gw) = gauss_legendre(quad.order);
    let (r, r1, r2) = curve.eval(s);
    let (q, dq, _) = charge.at(s);
    let (left, right) = if closed { (delta, delta) } else { (s.min(delta), (l - s).min(delta)) };
    let mut f = [0.0; 3];
    for (side, sign) in [(left, -1.0), (right, 1.0)] {
        if side <= a {
            continue;
        }
        let jj = special::j(-1, a, side, kappa) + kappa * special::j(0, a, side, kappa);
        let odd = (-kappa * a).exp() / a - (-kappa * side).exp() / side;
        for i in 0..3 {
            f[i] += -0.5 * q * r2[i] * jj - dq * r1[i] * jj - sign * q * r1[i] * odd;
        }
    }
    let mut pts = Vec::new();
    FarZone::new(curve, delta, kappa, quad.cutoff, &gx, &gw).points_for(curve, s, &r, &mut pts, &mut Vec::new());
    for (t, w, rt) in pts {
        let dv = sub(r, rt);
        let d = dot(dv, dv).sqrt();
        if d > 0.0 {
            let g = (-kappa * d).exp() * (1.0 + kappa * d) / (d * d * d);
            let c = w * charge.at(t).0 * g;
            for i in 0..3 {
                f[i] += c * dv[i];
            }
        }
    }
    let f = [q * f[0], q * f[1], q * f[2]];
    error::finite_result("force density", &f)?;
    Ok(f)
}

/// An energy with its gradient with respect to the node positions and to
/// the node tangents of a [`HermiteCurve`].
pub type EnergyGradient = (Energy, Vec<[f64; 3]>, Vec<[f64; 3]>);

/// The energy of a [`HermiteCurve`] and its gradient with respect to the
/// node positions and node tangents (the exact derivative of the
/// quadrature formula: minus it is the discrete electrostatic force).
pub fn energy_gradient(
    curve: &HermiteCurve,
    charge: &LineCharge,
    screening: &Screening,
    quad: &EnergyQuadrature,
) -> Result<EnergyGradient> {
    let m = curve.s.len();
    let mut gr = vec![[0.0; 3]; m];
    let mut gt = vec![[0.0; 3]; m];
    let mut sink = |s: f64, d: [[f64; 3]; 3]| {
        let (k, h, b) = curve.basis(s);
        // r⁽ⁿ⁾(s) = (b_n0 r_k + b_n1 h t_k + b_n2 r_{k+1} + b_n3 h t_{k+1})/hⁿ,
        // b_n the basis' n-th derivatives in u.
        for (n, (bn, dn)) in b.iter().zip(&d).enumerate() {
            let hn = h.powi(n as i32);
            for i in 0..3 {
                gr[k][i] += bn[0] / hn * dn[i];
                gt[k][i] += h * bn[1] / hn * dn[i];
                gr[k + 1][i] += bn[2] / hn * dn[i];
                gt[k + 1][i] += h * bn[3] / hn * dn[i];
            }
        }
    };
    let e = energy_core(curve, charge, screening, quad, Some(&mut sink))?;
    if !gr.iter().chain(&gt).flatten().all(|v| v.is_finite()) {
        return Err(Error::new(Status::ErrNonFiniteResult, "electrostatic energy gradient is not finite"));
    }
    Ok((e, gr, gt))
}

/// Which electrostatic model a scene got.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ElectrostaticModel {
    /// Zero charge: no electrostatics at all.
    None,
    /// The continuum with the near-zone regularisation and these settings.
    Continuum(EnergyQuadrature),
}

/// An energy delivered to a requested tolerance, with the model used and
/// the error estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyReport {
    pub energy: Energy,
    pub model: ElectrostaticModel,
    /// Estimated relative error of `energy`: near-zone truncation (measured
    /// by moving δ toward a, see [`energy_within`]) + quadrature (two Gauss
    /// orders at the final δ) + the cutoff's tail + round-off.
    pub estimate: f64,
}

/// The kernel evaluations [`energy_within`] may spend over all its steps
/// (the per-evaluation bounds [`MAX_KERNEL_EVALUATIONS`] and
/// [`MAX_FAR_POINTS`] hold as well).
/// About a second of kernel evaluations (~20 ns each on one core): a
/// caller who asks for an energy to a tolerance gets it, or a refusal that
/// names the cost, within that time. More work is for
/// [`energy`] at the δ and order the refusal names.
pub const MAX_WITHIN_EVALUATIONS: f64 = 4e7;

/// The length below which a curve's own geometry changes: the smallest
/// radius of curvature |r'|²/|r''| (sampled at the breakpoints' midpoints and
/// at 64 points) and the shortest interval between breakpoints (a cubic
/// through nodes changes its r'' and its speed at every node). The near
/// zone's expansion about s holds within a fraction of it.
fn geometric_scale(curve: &dyn Centerline) -> f64 {
    let l = curve.length();
    let mut knots = vec![0.0];
    knots.extend(curve.breakpoints());
    knots.push(l);
    let mut scale = l;
    let mut samples: Vec<f64> = (0..64).map(|k| (k as f64 + 0.5) * l / 64.0).collect();
    for w in knots.windows(2) {
        scale = scale.min(w[1] - w[0]);
        samples.push(0.5 * (w[0] + w[1]));
    }
    for s in samples {
        let (_, r1, r2) = curve.eval(s);
        let (speed2, bend) = (dot(r1, r1), dot(r2, r2).sqrt());
        if bend > 0.0 {
            scale = scale.min(speed2 / bend);
        }
    }
    scale
}

/// "Only what the scene requires" (physics.md §5): a continuum energy whose
/// estimated relative error is within `tolerance`, no electrostatics for a
/// zero charge.
///
/// The estimate has two measured parts.
/// * Quadrature: at a fixed δ the Gauss order p is raised by 4 (from 3 at
///   tolerances ≥ 1e-5, from 6 below: half the time at loose tolerances
///   with every estimate still bounding, tests/electrostatics_estimates.rs;
///   up to 32) until |E(δ, p+4) − E(δ, p)| ≤ tol/4; the p+4 value is kept and
///   that difference is its estimate q (Gauss converges geometrically, so
///   it overestimates).
/// * Near-zone truncation: the near-zone expansion drops terms whose
///   integral over a < |h| < δ is T(x), x = δ − a, with T(0) = 0 (no near
///   zone, nothing dropped) and |T| convex in x (it integrates |h|^p,
///   p ≥ 2). For convex T, T(x/r) ≤ T(x)/r, hence
///   |T(x/r)| ≤ |E(x) − E(x/r)|/(r − 1): two δ's give a bound, not a guess.
///   It is counted twice (the bound assumes one sign and convexity), with
///   both q's added to the difference: t = 2(|ΔE| + q + q')/(r − 1).
///   δ starts from the curve's own scale, a quarter of
///   [`geometric_scale`] (the expansion holds well inside it, whatever a
///   is: ln(δ/a) is integrated exactly), at least 4a, and larger while the
///   first two widths would cost more than 40 % of the call's work bound. x is then divided by r = max(4, 4t/tol) until the sum is within
///   tol. δ tends to a, where the model is the plain double integral: there
///   is no floor below which the truncation goes unmeasured.
///
/// Refused: ErrWorkLimit before any step that would take the call past
/// [`MAX_WITHIN_EVALUATIONS`] (about a second) or past an evaluation's own
/// bound, naming that step's cost;
/// ErrToleranceUnreachable when order 32 does not resolve the quadrature,
/// or when round-off (8ε·N^{1/4} for N kernel evaluations: nested sums of
/// positive terms) is above tol/4 — the steps then aim at four times the
/// round-off and the refusal reports the estimate reached there. Both
/// messages state the best estimate reached (with its energy and δ).
pub fn energy_within(
    curve: &dyn Centerline,
    charge: &LineCharge,
    screening: &Screening,
    tolerance: f64,
) -> Result<EnergyReport> {
    error::in_range("tolerance", tolerance, 1e-14, 1e-1)?;
    if let LineCharge::Uniform(q) = charge {
        error::finite("line charge", *q)?;
        if *q == 0.0 {
            let zero = Energy { total: 0.0, near: 0.0, far: 0.0, far_evaluations: 0 };
            return Ok(EnergyReport { energy: zero, model: ElectrostaticModel::None, estimate: 0.0 });
        }
    }
    error::positive("length", curve.length())?;
    error::finite("kappa", screening.kappa)?;
    error::positive("a", screening.a)?;
    let a = screening.a;
    let l = curve.length();
    let max_delta = if curve.closed() { 0.5 * l } else { l };
    if !(a < max_delta) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!(
                "argument `a` ({a:e}) must be below {} ({max_delta:e}): no pair is farther apart than a",
                if curve.closed() { "L/2 on a closed curve" } else { "L" }
            ),
        ));
    }
    // The screening cutoff: its tail is measured, not assumed. The
    // straight-line estimate of discrete::screening_cutoff is no bound for
    // a coiled curve (more arc length per unit distance: a helix of radius
    // 5 and pitch 10 dropped 3× the estimate), so the steps run
    // at the cutoff for 1e-3·tol and the result is the one at the cutoff
    // for 1e-6·tol, whose remaining tail is bounded by ten times the line
    // ratio E1(κr_wide)/E1(κr_c) of the measured difference.
    let line_cutoff = |t: f64| discrete::screening_cutoff(screening.kappa, a, t, 1e6 * l.max(a));
    let search = Within {
        curve,
        charge,
        screening,
        tolerance,
        cutoff: line_cutoff(1e-3 * tolerance),
        wide_cutoff: line_cutoff(1e-6 * tolerance),
        spent: 0.0,
        target: tolerance,
        best: None,
    };
    // The largest δ allowed: strictly inside (a, max_delta).
    let delta_cap = a + 0.5 * (max_delta - a);
    let order = if tolerance >= 1e-5 { 3 } else { 6 };
    let mut delta0 = (0.25 * geometric_scale(curve)).max(4.0 * a).min(delta_cap);
    // The first two widths (δ0 and a + (δ0 − a)/4) at both orders.
    let first_pair = |d: f64| {
        let second = a + 0.25 * (d - a);
        [(d, order), (d, order + 4), (second, order), (second, order + 4)]
            .iter()
            .map(|&(d, o)| energy_work(curve, screening, &search.settings(d, o)).evaluations)
            .sum::<f64>()
    };
    while delta0 < delta_cap && first_pair(delta0) > 0.4 * MAX_WITHIN_EVALUATIONS {
        delta0 = (2.0 * delta0).min(delta_cap);
    }
    search.run(delta0, order)
}

/// Round-off of an energy summed over N kernel evaluations: 8ε·N^{1/4}
/// (nested sums of positive terms).
fn roundoff(e: &Energy) -> f64 {
    8.0 * f64::EPSILON * (e.far_evaluations.max(1) as f64).powf(0.25)
}

/// |x − y|/|x|.
fn rel(x: f64, y: f64) -> f64 {
    (x - y).abs() / x.abs().max(f64::MIN_POSITIVE)
}

/// The state of one [`energy_within`] search.
struct Within<'c> {
    curve: &'c dyn Centerline,
    charge: &'c LineCharge,
    screening: &'c Screening,
    tolerance: f64,
    /// The cutoff the steps run at, and the wider one of the result.
    cutoff: Option<f64>,
    wide_cutoff: Option<f64>,
    /// Kernel evaluations spent so far.
    spent: f64,
    /// What is aimed at: the tolerance, or — when round-off is above it —
    /// four times the round-off, so that a refusal reports the best the
    /// model reaches, not the first estimate measured.
    target: f64,
    /// The best result so far: (energy, settings, estimate).
    best: Option<(Energy, EnergyQuadrature, f64)>,
}

impl Within<'_> {
    fn settings(&self, delta: f64, order: usize) -> EnergyQuadrature {
        EnergyQuadrature { delta, order, cutoff: self.cutoff }
    }

    fn best_text(&self) -> String {
        match &self.best {
            Some((e, q, est)) => format!(
                "best reachable: estimate {est:.2e} (energy {:.15e} at δ {:e}, order {})",
                e.total, q.delta, q.order
            ),
            None => "best reachable: none measured (a truncation estimate needs two near-zone widths)".to_string(),
        }
    }

    /// The energy at `q`, its work checked against the bounds first.
    fn energy(&mut self, q: &EnergyQuadrature) -> Result<Energy> {
        let w = energy_work(self.curve, self.screening, q);
        if self.spent + w.evaluations > MAX_WITHIN_EVALUATIONS
            || w.evaluations > MAX_KERNEL_EVALUATIONS
            || w.far_points > MAX_FAR_POINTS
        {
            return Err(Error::new(
                Status::ErrWorkLimit,
                format!(
                    "the call would exceed its work bound: the next step (δ {:e}, order {}) costs {:.2e} kernel \
                     evaluations on {:.2e} points after {:.2e} spent (bounds {MAX_WITHIN_EVALUATIONS:.1e} per \
                     call, {MAX_KERNEL_EVALUATIONS:.0e} per step, {MAX_FAR_POINTS:.0e} points) for the relative \
                     tolerance {:e}; {}",
                    q.delta,
                    q.order,
                    w.evaluations,
                    w.far_points,
                    self.spent,
                    self.tolerance,
                    self.best_text()
                ),
            ));
        }
        self.spent += w.evaluations;
        energy(self.curve, self.charge, self.screening, q)
    }

    /// [`Self::energy`], raising the target to four times its round-off.
    fn aimed_energy(&mut self, q: &EnergyQuadrature) -> Result<Energy> {
        let e = self.energy(q)?;
        self.target = self.target.max(4.0 * roundoff(&e));
        Ok(e)
    }

    /// (E at order p+4, q) at one δ, the order raised by 4 until the
    /// difference q of the last two orders is within a quarter of the target.
    fn resolved(&mut self, delta: f64, order: &mut usize) -> Result<(Energy, f64)> {
        let mut coarse = self.aimed_energy(&self.settings(delta, *order))?;
        loop {
            let o2 = (*order + 4).min(32);
            let fine = self.aimed_energy(&self.settings(delta, o2))?;
            let q = rel(fine.total, coarse.total);
            if q <= 0.25 * self.target || o2 == 32 {
                return Ok((fine, q));
            }
            (*order, coarse) = (o2, fine);
        }
    }

    fn unreachable(&self, why: String) -> Error {
        Error::new(
            Status::ErrToleranceUnreachable,
            format!(
                "electrostatic energy: the relative tolerance {:e} is below what the model reaches ({why}); {}",
                self.tolerance,
                self.best_text()
            ),
        )
    }

    /// The result at the wide cutoff once the steps' estimate meets the
    /// target: its estimate adds the remaining tail, ten times the line
    /// ratio E1(κr_wide)/E1(κr_c) of the measured difference.
    fn widened(&mut self, e: Energy, quad: EnergyQuadrature, estimate: f64, trunc_and_q: f64) -> Result<Reached> {
        let (Some(rc), Some(wide)) = (self.cutoff, self.wide_cutoff) else {
            return Ok((e, quad, estimate));
        };
        let wide_quad = EnergyQuadrature { cutoff: Some(wide), ..quad };
        let ew = self.energy(&wide_quad)?;
        let kappa = self.screening.kappa;
        let e1 = |r: f64| if kappa * r > 700.0 { 0.0 } else { special::e1(kappa * r) };
        let ratio = (10.0 * e1(wide) / e1(rc)).min(1.0);
        let estimate = trunc_and_q + roundoff(&ew) + ratio * rel(ew.total, e.total);
        Ok((ew, wide_quad, estimate))
    }

    /// δ = a + x, x divided by r ≥ 4 each step until the estimate meets the
    /// tolerance (see [`energy_within`]).
    fn run(mut self, delta0: f64, mut order: usize) -> Result<EnergyReport> {
        let a = self.screening.a;
        let mut x = delta0 - a;
        let mut prev: Option<(Energy, f64, f64)> = None;
        loop {
            let delta = a + x;
            let (e, q) = self.resolved(delta, &mut order)?;
            let quad = self.settings(delta, (order + 4).min(32));
            let mut next_ratio = 4.0;
            if let Some((ep, qp, xp)) = prev {
                let r = xp / x;
                let trunc = 2.0 * (rel(e.total, ep.total) + q + qp) / (r - 1.0);
                let mut result = (e, quad, trunc + q + roundoff(&e));
                if result.2 <= self.target {
                    result = self.widened(e, quad, result.2, trunc + q)?;
                }
                let (energy, quad, estimate) = result;
                if self.best.as_ref().is_none_or(|b| estimate < b.2) {
                    self.best = Some(result);
                }
                if estimate <= self.tolerance {
                    return Ok(EnergyReport { energy, model: ElectrostaticModel::Continuum(quad), estimate });
                }
                if estimate <= self.target {
                    let why = format!(
                        "round-off {:.2e} for {} kernel evaluations",
                        roundoff(&energy),
                        energy.far_evaluations
                    );
                    return Err(self.unreachable(why));
                }
                next_ratio = (4.0 * trunc / self.target).clamp(4.0, 1e6);
            }
            if q > 0.25 * self.target {
                let why = format!("Gauss order 32 leaves a quadrature difference {q:.2e} at δ {delta:e}");
                return Err(self.unreachable(why));
            }
            if x / next_ratio < 1e-12 * a {
                return Err(self.unreachable("δ − a would fall below 1e-12·a".to_string()));
            }
            prev = Some((e, q, x));
            x /= next_ratio;
        }
    }
}

/// An energy reached, its settings and its estimate.
type Reached = (Energy, EnergyQuadrature, f64);

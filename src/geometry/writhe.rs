//! Writhe by the Gauss double integral (physics.md §3.4):
//!   Wr = (1/4π) ∫∫ (r'(s) × r'(t)) · (r(s) − r(t)) / |r(s) − r(t)|³ ds dt.
//! The integrand is bounded — it tends to (1/12)|h| (r'×r'')·r''' as
//! h = t − s → 0 — so no regularisation is needed, only panels that break
//! at the diagonal (a kink in |h|) and at the curve's nodes; it is
//! parametrisation-invariant, so any [`Centerline`] whose `eval` returns
//! dr/ds for its own parameter works. An open rod is closed by straight
//! rays along its end tangents (the clamp axes), r(0) + σ r̂'(0), σ ≤ 0,
//! and r(L) + σ r̂'(L), σ ≥ 0; the ray integrals are mapped to finite
//! intervals (σ = ℓu/(1 − u)), exact as the rays go to infinity.

use super::vec3::{cross, dot, sub};
use super::Centerline;
use crate::error::{self, Error, Result};
use crate::quadrature::{gauss_legendre, panels};
use crate::status::Status;

/// The kernel evaluations one [`writhe`] may spend (≈ 10–30 s at 10–30 ns
/// each, the bound of one continuum energy evaluation): the cost grows
/// like (nodes · order)², so a caller's 10⁵ nodes at order 32 would run
/// for hours (issue 17: every call whose cost depends on inputs is sized
/// first).
pub const MAX_WRITHE_EVALUATIONS: f64 = 1e9;

/// Refuses with ErrWorkLimit, stating the cost, a writhe whose curve–curve
/// integral would exceed [`MAX_WRITHE_EVALUATIONS`]: (outer panels · p) ×
/// (inner panels · p) / 2, the inner panels being the nodes plus the
/// geometric grading at t = s (≈ 2 log2(10⁶) = 40).
fn check_work(outer_panels: usize, nodes: usize, order: usize) -> Result<()> {
    let p = order as f64;
    let evaluations = 0.5 * (outer_panels as f64 * p) * ((nodes as f64 + 40.0) * p);
    if evaluations > MAX_WRITHE_EVALUATIONS {
        return Err(Error::new(
            Status::ErrWorkLimit,
            format!(
                "writhe: the call would exceed its work bound: {evaluations:.2e} kernel evaluations on {nodes} nodes \
                 at order {order} (bound {MAX_WRITHE_EVALUATIONS:.0e}); lower `order` or use fewer nodes"
            ),
        ));
    }
    Ok(())
}

/// The Gauss integrand for points p, q with tangents tp, tq (0 at p = q).
fn kernel(p: [f64; 3], tp: [f64; 3], q: [f64; 3], tq: [f64; 3]) -> f64 {
    let d = sub(p, q);
    let r2 = dot(d, d);
    if r2 == 0.0 {
        return 0.0;
    }
    dot(cross(tp, tq), d) / (r2 * r2.sqrt())
}

/// Panels of [lo, hi] broken at `breaks` and graded geometrically towards
/// `lo` and `hi` (to width `finest`) where `grade` says.
fn graded_panels(lo: f64, hi: f64, breaks: &[f64], grade: (bool, bool), finest: f64) -> Vec<(f64, f64)> {
    let mut pts = breaks.to_vec();
    let mut w = finest;
    while w < 0.5 * (hi - lo) {
        if grade.0 {
            pts.push(lo + w);
        }
        if grade.1 {
            pts.push(hi - w);
        }
        w *= 2.0;
    }
    panels(lo, hi, &pts)
}

/// Writhe of `curve` (closed, or open and closed by rays along its end
/// tangents), Gauss–Legendre of `order` points per panel.
pub fn writhe(curve: &dyn Centerline, order: usize) -> Result<f64> {
    error::count_in_range("order", order as i64, 2, 32)?;
    let l = curve.length();
    error::positive("length", l)?;
    let (gx, gw) = gauss_legendre(order);
    let nodes = curve.breakpoints();
    let finest = 1e-6 * l;
    let closed = curve.closed();
    let outer = graded_panels(0.0, l, &nodes, (!closed, !closed), finest);
    check_work(outer.len(), nodes.len(), order)?;
    let mut total = 0.0;
    // Node breaks for the inner panels (shifted by a period when closed).
    let shifted: Vec<f64> = nodes.iter().flat_map(|&b| [b, b + l]).collect();
    // Curve–curve: the integrand is symmetric, K(s, t) = K(t, s), so for
    // each s only t on one side is integrated and the result doubled:
    // t ∈ (s, L) when open, t ∈ (s, s + L/2) when closed (periodic: the
    // pair (s, s + u), u > L/2, is the pair (t, t + L − u)). Panels break
    // at t = s (graded there) and at the nodes. Half the kernel
    // evaluations of integrating over every t (the writhe is evaluated at
    // every point of a supercoiling path).
    for &(s0, s1) in &outer {
        let hs = 0.5 * (s1 - s0);
        for (xi, wi) in gx.iter().zip(&gw) {
            let s = s0 + hs * (1.0 + xi);
            let (p, tp, _) = curve.eval(s);
            let mut inner = 0.0;
            let (t0, t1, g1) = if closed { (s, s + 0.5 * l, false) } else { (s, l, true) };
            for (p0, p1) in graded_panels(t0, t1, &shifted, (true, g1), finest) {
                let ht = 0.5 * (p1 - p0);
                for (xj, wj) in gx.iter().zip(&gw) {
                    let t = p0 + ht * (1.0 + xj);
                    let tt = if closed { t.rem_euclid(l) } else { t };
                    let (q, tq, _) = curve.eval(tt);
                    inner += ht * wj * kernel(p, tp, q, tq);
                }
            }
            inner *= 2.0;
            // Curve–rays (both orders of each pair: twice).
            if !closed {
                inner += 2.0 * ray_integral(p, tp, &curve.eval(0.0), -1.0, l, &gx, &gw);
                inner += 2.0 * ray_integral(p, tp, &curve.eval(l), 1.0, l, &gx, &gw);
            }
            total += hs * wi * inner;
        }
    }
    if !closed {
        // Ray–ray (twice), each ray against itself is straight: 0.
        let (a, ta, _) = curve.eval(0.0);
        let (b, tb, _) = curve.eval(l);
        let ua = unit(ta);
        let mut rr = 0.0;
        for (u0, u1) in ray_panels() {
            let hu = 0.5 * (u1 - u0);
            for (xi, wi) in gx.iter().zip(&gw) {
                let u = u0 + hu * (1.0 + xi);
                let sigma = l * u / (1.0 - u);
                let jac = l / ((1.0 - u) * (1.0 - u));
                let p = [a[0] - sigma * ua[0], a[1] - sigma * ua[1], a[2] - sigma * ua[2]];
                rr += hu * wi * jac * ray_integral(p, ua, &(b, tb, [0.0; 3]), 1.0, l, &gx, &gw);
            }
        }
        total += 2.0 * rr;
    }
    let wr = total / (4.0 * std::f64::consts::PI);
    if !wr.is_finite() {
        return Err(error::Error::new(crate::status::Status::ErrNonFiniteResult, "writhe is not finite"));
    }
    Ok(wr)
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = dot(v, v).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

/// Panels on u ∈ [0, 1) for a ray σ = ℓu/(1 − u): graded towards both ends.
fn ray_panels() -> Vec<(f64, f64)> {
    graded_panels(0.0, 1.0, &[], (true, true), 1e-7)
}

/// ∫ over the ray from `end` = (r, r', _) in direction `sign`·r̂' of the
/// Gauss integrand against (p, tp), the ray's tangent oriented with the
/// curve (it enters at s = 0, leaves at s = L).
fn ray_integral(
    p: [f64; 3],
    tp: [f64; 3],
    end: &([f64; 3], [f64; 3], [f64; 3]),
    sign: f64,
    l: f64,
    gx: &[f64],
    gw: &[f64],
) -> f64 {
    let t = unit(end.1);
    let mut sum = 0.0;
    for (u0, u1) in ray_panels() {
        let hu = 0.5 * (u1 - u0);
        for (xi, wi) in gx.iter().zip(gw) {
            let u = u0 + hu * (1.0 + xi);
            let sigma = l * u / (1.0 - u);
            let jac = l / ((1.0 - u) * (1.0 - u));
            let q = [end.0[0] + sign * sigma * t[0], end.0[1] + sign * sigma * t[1], end.0[2] + sign * sigma * t[2]];
            sum += hu * wi * jac * kernel(p, tp, q, t);
        }
    }
    sum
}

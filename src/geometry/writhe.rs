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
//!
//! Two rules: [`writhe`], Gauss of a fixed order on every panel pair (its
//! error falls only like order^−3.5 on a C¹ curve: where s and t straddle
//! a node beside the diagonal the integrand is bounded but not smooth),
//! and [`writhe_within`], to a tolerance with an error estimate: pairs of
//! smooth pieces at orders chosen by their separation, Duffy's map at the
//! nodes, the rays in closed form — about 10× cheaper than `writhe` at
//! order 4 on a rod's centreline and 1e4× more accurate
//! (benches/README.md).

use super::vec3::{cross, dot, sub};
use super::Centerline;
use crate::error::{self, Error, Result};
use crate::quadrature::{gauss_legendre, panels};
use crate::status::Status;

/// The kernel evaluations one [`writhe`] may spend (≈ 10–30 s at 10–30 ns
/// each, the bound of one continuum energy evaluation): the cost grows
/// like (nodes · order)², so a caller's 10⁵ nodes at order 32 would run
/// for hours (every call whose cost depends on its inputs is sized
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
/// tangents), Gauss–Legendre of `order` points per panel (the C API's
/// rule; [`writhe_within`] is faster and converges).
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

// ---------------------------------------------------------------------
// The error-controlled rule: panel pairs by separation.
// ---------------------------------------------------------------------

/// Largest Gauss order of the far-pair tables (every segment sampled once
/// at orders 1..=FAR_ORDER before the pair loop).
const FAR_ORDER: usize = 8;
/// Largest Gauss order of a near pair (evaluated directly); a nearer pair
/// is cut into up to MAX_PIECES pieces a side instead.
const NEAR_ORDER: usize = 16;
const MAX_PIECES: usize = 32;
/// Gauss order of the Duffy rule on the squares of adjacent segments
/// and of the self segments' triangles, and of the ray integrals of the
/// segments touching a ray's start; the estimate compares it with
/// CORNER_ORDER − CORNER_STEP.
const CORNER_ORDER: usize = 10;
const CORNER_STEP: usize = 3;
/// Smallest tolerance [`writhe_within`] accepts (rounding in the sum).
pub const MIN_WRITHE_TOLERANCE: f64 = 1e-13;

/// What [`writhe_within`] returns: the writhe (turns), its error estimate
/// and the kernel evaluations spent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WritheEstimate {
    pub value: f64,
    /// Sum of the absolute modelled errors of every pair of pieces (the
    /// model of the private `side`, its constant measured), plus
    /// |rule − lower rule| on the adjacent and self pairs and the rays
    /// touching the ends (an estimate of the lower rule: a floor of
    /// ~1e-8–1e-6 on coarse curves whatever `tol`). Conservative: on the
    /// test plectonemes and rod states the true error was 1e2–1e5 times
    /// smaller (benches/README.md).
    pub estimate: f64,
    pub evaluations: f64,
}

/// The curve as smooth pieces in a local parameter u ∈ [0, 1]: position
/// and dr/du. Cubic pieces (a [`HermiteCurve`](super::HermiteCurve)) are evaluated from their
/// coefficients, any other [`Centerline`] through `eval`.
trait Pieces {
    fn count(&self) -> usize;
    fn at(&self, i: usize, u: f64) -> ([f64; 3], [f64; 3]);
}

/// A [`Centerline`] cut at parameter bounds.
struct Sampled<'a> {
    curve: &'a dyn Centerline,
    bounds: Vec<(f64, f64)>,
}

impl Pieces for Sampled<'_> {
    fn count(&self) -> usize {
        self.bounds.len()
    }
    #[inline]
    fn at(&self, i: usize, u: f64) -> ([f64; 3], [f64; 3]) {
        let (lo, hi) = self.bounds[i];
        let (p, t, _) = self.curve.eval(lo + (hi - lo) * u);
        (p, scale(t, hi - lo))
    }
}

/// Cubic pieces c0 + c1 u + c2 u² + c3 u³.
struct Cubics(Vec<[[f64; 3]; 4]>);

impl Pieces for Cubics {
    fn count(&self) -> usize {
        self.0.len()
    }
    #[inline]
    fn at(&self, i: usize, u: f64) -> ([f64; 3], [f64; 3]) {
        let [c0, c1, c2, c3] = &self.0[i];
        let mut p = [0.0; 3];
        let mut t = [0.0; 3];
        for k in 0..3 {
            p[k] = c0[k] + u * (c1[k] + u * (c2[k] + u * c3[k]));
            t[k] = c1[k] + u * (2.0 * c2[k] + u * 3.0 * c3[k]);
        }
        (p, t)
    }
}

/// The cubic in u ∈ [0, 1] with end values p0, p1 and end derivatives m0, m1.
fn hermite_cubic(p0: [f64; 3], m0: [f64; 3], p1: [f64; 3], m1: [f64; 3]) -> [[f64; 3]; 4] {
    let mut c = [p0, m0, [0.0; 3], [0.0; 3]];
    for k in 0..3 {
        c[2][k] = 3.0 * (p1[k] - p0[k]) - 2.0 * m0[k] - m1[k];
        c[3][k] = 2.0 * (p0[k] - p1[k]) + m0[k] + m1[k];
    }
    c
}

/// The pieces of a curve: a Hermite curve's own cubics, else its
/// breakpoint intervals; each cut into equal parts so that a closed curve
/// has ≥ 4 (the adjacency the rule relies on).
fn pieces_of(curve: &dyn Centerline) -> (Option<Cubics>, Sampled<'_>) {
    let l = curve.length();
    let mut cuts = vec![0.0];
    cuts.extend(curve.breakpoints().into_iter().filter(|&b| b > 0.0 && b < l));
    cuts.push(l);
    let parts = if curve.closed() { 4usize.div_ceil(cuts.len() - 1) } else { 1 };
    let mut bounds = Vec::with_capacity((cuts.len() - 1) * parts);
    for w in cuts.windows(2) {
        for k in 0..parts {
            let f = |k: usize| w[0] + (w[1] - w[0]) * k as f64 / parts as f64;
            bounds.push((f(k), f(k + 1)));
        }
    }
    let sampled = Sampled { curve, bounds };
    let cubics = curve.as_hermite().filter(|h| h.s.len() - 1 == cuts.len() - 1).map(|h| {
        let mut c = Vec::with_capacity(sampled.bounds.len());
        for k in 0..h.s.len() - 1 {
            let hk = h.s[k + 1] - h.s[k];
            let whole = hermite_cubic(h.r[k], scale(h.t[k], hk), h.r[k + 1], scale(h.t[k + 1], hk));
            let piece = Cubics(vec![whole]);
            for j in 0..parts {
                let (u0, u1) = (j as f64 / parts as f64, (j + 1) as f64 / parts as f64);
                let ((p0, t0), (p1, t1)) = (piece.at(0, u0), piece.at(0, u1));
                c.push(hermite_cubic(p0, scale(t0, u1 - u0), p1, scale(t1, u1 - u0)));
            }
        }
        Cubics(c)
    });
    (cubics, sampled)
}

/// A part [u0, u1] of piece `piece`: its chord (a → b) and how far it
/// bulges from it.
#[derive(Clone, Copy, Debug)]
struct Segment {
    piece: usize,
    u0: f64,
    u1: f64,
    a: [f64; 3],
    b: [f64; 3],
    /// Bound on the distance of the part from its chord (sampled at the
    /// FAR_ORDER Gauss points, × 1.25).
    bulge: f64,
    /// Bounding sphere about the chord's midpoint: |b − a|/2 + bulge.
    mid: [f64; 3],
    radius: f64,
    /// |b1|, |b2|, |b3| of the part as a cubic b0 + b1 z + b2 z² + b3 z³ in
    /// z ∈ [−1, 1] (interpolated at z = ±1, ±1/3: exact for a cubic).
    coef: [f64; 3],
}

/// Gauss–Legendre rules on [0, 1] for orders 1..=NEAR_ORDER.
struct Rules(Vec<(Vec<f64>, Vec<f64>)>);

impl Rules {
    fn new() -> Self {
        Rules(
            (1..=NEAR_ORDER.max(CORNER_ORDER))
                .map(|q| {
                    let (x, w) = gauss_legendre(q);
                    (x.iter().map(|x| 0.5 * (1.0 + x)).collect(), w.iter().map(|w| 0.5 * w).collect())
                })
                .collect(),
        )
    }
    fn get(&self, q: usize) -> (&[f64], &[f64]) {
        let (x, w) = &self.0[q - 1];
        (x, w)
    }
}

/// (position, dr/du × Gauss weight) at the Gauss points of every order
/// 1..=FAR_ORDER of every piece, as the pieces produce them.
type Samples = Vec<Vec<([f64; 3], [f64; 3])>>;

/// The same laid out for the far loop: tables[q − 1][6 q i ..][..6 q] holds
/// piece i's x, y, z, x', y', z' of its q points, component after
/// component (the inner loop runs over contiguous points).
type Tables = Vec<Vec<f64>>;

fn scale(v: [f64; 3], c: f64) -> [f64; 3] {
    [v[0] * c, v[1] * c, v[2] * c]
}

fn axpy(a: [f64; 3], c: f64, d: [f64; 3]) -> [f64; 3] {
    [a[0] + c * d[0], a[1] + c * d[1], a[2] + c * d[2]]
}

/// The part [u0, u1] of piece i, bulge from its FAR_ORDER Gauss points;
/// `table` receives (position, dr/du × weight) at orders 1..=FAR_ORDER
/// when given (whole pieces only).
fn segment<P: Pieces>(
    pc: &P,
    i: usize,
    (u0, u1): (f64, f64),
    rules: &Rules,
    mut table: Option<&mut Samples>,
) -> Segment {
    let (a, b) = (pc.at(i, u0).0, pc.at(i, u1).0);
    let d = sub(b, a);
    let mut bulge = 0.0f64;
    for q in 1..=FAR_ORDER {
        if table.is_none() && q < FAR_ORDER {
            continue;
        }
        let (x, w) = rules.get(q);
        for (xi, wi) in x.iter().zip(w) {
            let (p, tp) = pc.at(i, u0 + (u1 - u0) * xi);
            if let Some(t) = table.as_deref_mut() {
                t[q - 1].push((p, scale(tp, *wi)));
            }
            bulge = bulge.max(segment_distance(p, [0.0; 3], a, d, 1.0));
        }
    }
    let bulge = 1.25 * bulge;
    let (m, p) = (pc.at(i, u0 + (u1 - u0) / 3.0).0, pc.at(i, u0 + 2.0 * (u1 - u0) / 3.0).0);
    let mut b1 = [0.0; 3];
    let mut b2 = [0.0; 3];
    let mut b3 = [0.0; 3];
    for k in 0..3 {
        let (s1, d1, s3, d3) = (b[k] + a[k], b[k] - a[k], p[k] + m[k], p[k] - m[k]);
        b2[k] = 9.0 * (s1 - s3) / 16.0;
        b1[k] = (27.0 * d3 - d1) / 16.0;
        b3[k] = 0.5 * d1 - b1[k];
    }
    let coef = [dot(b1, b1).sqrt(), dot(b2, b2).sqrt(), dot(b3, b3).sqrt()];
    Segment { piece: i, u0, u1, a, b, bulge, mid: axpy(a, 0.5, d), radius: 0.5 * dot(d, d).sqrt() + bulge, coef }
}

/// Every whole piece and the far tables.
fn segments<P: Pieces>(pc: &P, rules: &Rules) -> (Vec<Segment>, Tables) {
    let n = pc.count();
    let mut samples: Samples = (1..=FAR_ORDER).map(|q| Vec::with_capacity(q * n)).collect();
    let segs = (0..n).map(|i| segment(pc, i, (0.0, 1.0), rules, Some(&mut samples))).collect();
    let tables = samples
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let q = k + 1;
            let mut t = vec![0.0; 6 * v.len()];
            for (m, (p, tp)) in v.iter().enumerate() {
                let (i, j) = (m / q, m % q);
                for c in 0..3 {
                    t[6 * q * i + c * q + j] = p[c];
                    t[6 * q * i + (3 + c) * q + j] = tp[c];
                }
            }
            t
        })
        .collect();
    (segs, tables)
}

/// Distance between the segments p0 + u d1 (u ∈ [0, 1]) and q0 + v d2
/// (v ∈ [0, vmax], vmax may be ∞: a ray), by the closest points (C. Ericson,
/// Real-Time Collision Detection, 2005, §5.1.9).
fn segment_distance(p0: [f64; 3], d1: [f64; 3], q0: [f64; 3], d2: [f64; 3], vmax: f64) -> f64 {
    let r = sub(p0, q0);
    let (a, e, f) = (dot(d1, d1), dot(d2, d2), dot(d2, r));
    let tiny = 1e-300;
    let (s, t) = if a <= tiny && e <= tiny {
        (0.0, 0.0)
    } else if a <= tiny {
        (0.0, (f / e).clamp(0.0, vmax))
    } else {
        let c = dot(d1, r);
        if e <= tiny {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = dot(d1, d2);
            let denom = a * e - b * b;
            let s = if denom > 0.0 { ((b * f - c * e) / denom).clamp(0.0, 1.0) } else { 0.0 };
            let t = (b * s + f) / e;
            if t < 0.0 {
                ((-c / a).clamp(0.0, 1.0), 0.0)
            } else if t > vmax {
                (((b * vmax - c) / a).clamp(0.0, 1.0), vmax)
            } else {
                (s, t)
            }
        }
    };
    let gap = sub(axpy(p0, s, d1), axpy(q0, t, d2));
    dot(gap, gap).sqrt()
}

/// Lower bound on the distance between two segments' points: their
/// spheres' gap when far apart, else their chords' distance less the bulges.
fn separation(x: &Segment, y: &Segment) -> f64 {
    let centres = sub(x.mid, y.mid);
    let gap = dot(centres, centres).sqrt() - x.radius - y.radius;
    if gap > 2.0 * (x.radius + y.radius) {
        return gap;
    }
    let chords = segment_distance(x.a, sub(x.b, x.a), y.a, sub(y.b, y.a), 1.0);
    gap.max(chords - x.bulge - y.bulge)
}

/// How one side of a pair is integrated: Gauss order, pieces, modelled error.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Side {
    q: usize,
    m: usize,
    err: f64,
}

/// The constant of the pair error model of [`side`]: the worst ratio of
/// the true error of a q × q rule (q = 2…6, against 16 × 16) to
/// mag · (ρ_s^(−2q) + ρ_t^(−2q)) over every non-adjacent pair of four test
/// curves (toroidal helices, DNA-like plectonemes through 101 and 301
/// nodes; `pair_model_bounds_the_gauss_error`) was 10; 3× that.
const MODEL_FACTOR: f64 = 30.0;

/// How far (in z ∈ [−1, 1] units) a part's complexified cubic b0 + b1 z +
/// b2 z² + b3 z³ reaches before |r(z) − p|² can vanish for a point p at
/// distance d: at z = iy the linear term alone gives −|b1|²y² against d²
/// (y = d/|b1|, exact for a straight part); the higher ones enter the
/// square mainly through 2 (r(0) − p)·b_k y^k, so the root y of
/// |b1| y + 2|b2| y² + 2|b3| y³ = d (Newton from above).
fn reach(c: [f64; 3], d: f64) -> f64 {
    let c = [c[0], 2.0 * c[1], 2.0 * c[2]];
    let mut y = if c[0] > 0.0 { d / c[0] } else { (d / (c[1] + c[2]).max(f64::MIN_POSITIVE)).sqrt().min(1e300) };
    for _ in 0..30 {
        let g = y * (c[0] + y * (c[1] + y * c[2])) - d;
        let dg = c[0] + y * (2.0 * c[1] + 3.0 * y * c[2]);
        if !(dg > 0.0) {
            break;
        }
        let step = g / dg;
        y -= step;
        if step.abs() <= 1e-3 * y {
            break;
        }
    }
    y.max(0.0)
}

/// The coefficients of one of `m` equal parts of a part with `c`
/// (bounds: re-centring adds the higher terms to the lower ones).
fn scaled(c: [f64; 3], m: usize) -> [f64; 3] {
    let m = m as f64;
    [(c[0] + 2.0 * c[1] + 3.0 * c[2]) / m, (c[1] + 3.0 * c[2]) / (m * m), c[2] / (m * m * m)]
}

/// ρ² of a side (see [`side`]), whose modelled n-point error is
/// MODEL_FACTOR · mag · ρ^(−2n).
fn rho2(c: [f64; 3], d: f64) -> f64 {
    let eta = reach(c, d);
    let rho = eta + (1.0 + eta * eta).sqrt();
    rho * rho
}

/// The Gauss order (and pieces) for a side with coefficients `c` at
/// distance `d` from the other side, for an integrand of size `mag` to
/// error `eps`. An n-point Gauss rule on a function analytic inside the
/// Bernstein ellipse E_ρ errs by ≤ (64/15) M ρ^(−2n)/(ρ² − 1), M = max |f|
/// on E_ρ (Trefethen, Approximation Theory and Approximation Practice,
/// Thm 19.3). The kernel is singular where |r(z) − r_other|² = 0 for
/// complex z; a straight part reaches that at z = iη, η = d/|b1|, a curved
/// one sooner, where its complexified cubic has moved by d ([`reach`]):
/// ρ = η + √(1 + η²), η = reach. The model is
/// err = MODEL_FACTOR · mag · ρ^(−2n), mag = 4 R_s R_t / d², n ≥ 2 (the
/// midpoint rule's error is the numerator's variation more than the
/// kernel's: not modelled, not used); the constant is measured. One piece
/// up to NEAR_ORDER points, else the fewest pieces that need no more.
fn side(c: [f64; 3], d: f64, mag: f64, eps: f64) -> Side {
    let need = MODEL_FACTOR * mag / eps;
    let mut best = Side { q: NEAR_ORDER, m: MAX_PIECES, err: f64::INFINITY };
    for m in 1..=MAX_PIECES {
        let r2 = rho2(scaled(c, m), d);
        // The smallest q ≥ 2 with ρ^(2q) ≥ need, by products.
        let mut pw = r2 * r2;
        let mut q = 2;
        while pw < need && q < NEAR_ORDER {
            pw *= r2;
            q += 1;
        }
        if pw >= need || m == MAX_PIECES {
            return Side { q, m, err: MODEL_FACTOR * mag / pw };
        }
        best.err = MODEL_FACTOR * mag / pw;
    }
    best
}

/// The plan of a non-adjacent pair: each side's order and pieces.
fn plan(x: &Segment, y: &Segment, eps: f64) -> (Side, Side) {
    let d = separation(x, y);
    if !(d > 0.0) {
        let s = Side { q: NEAR_ORDER, m: MAX_PIECES, err: f64::INFINITY };
        return (s, s);
    }
    let mag = 4.0 * x.radius * y.radius / (d * d);
    (side(x.coef, d, mag, 0.5 * eps), side(y.coef, d, mag, 0.5 * eps))
}

/// The Gauss integrand with the weights folded into the tangents.
#[inline(always)]
fn kernel_w(p: &[f64; 3], tp: &[f64; 3], q: &[f64; 3], tq: &[f64; 3]) -> f64 {
    let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let c = [tp[1] * tq[2] - tp[2] * tq[1], tp[2] * tq[0] - tp[0] * tq[2], tp[0] * tq[1] - tp[1] * tq[0]];
    (c[0] * d[0] + c[1] * d[1] + c[2] * d[2]) / (r2 * r2.sqrt())
}

/// A far pair from the tables, dispatched on the t side's order so that
/// the inner loop has a fixed length (unrolled, two points a vector).
fn far_pair(tables: &Tables, i: usize, j: usize, s: &Side, t: &Side) -> f64 {
    let (qs, qt) = (s.q, t.q);
    let a = &tables[qs - 1][6 * qs * i..6 * qs * (i + 1)];
    let b = &tables[qt - 1][6 * qt * j..6 * qt * (j + 1)];
    match qt {
        1 => far_block::<1>(a, qs, b),
        2 => far_block::<2>(a, qs, b),
        3 => far_block::<3>(a, qs, b),
        4 => far_block::<4>(a, qs, b),
        5 => far_block::<5>(a, qs, b),
        6 => far_block::<6>(a, qs, b),
        7 => far_block::<7>(a, qs, b),
        _ => far_block::<8>(a, qs, b),
    }
}

/// The q_s × QT kernel sum of a far pair: `a` holds the s side's qs points
/// and `b` the t side's QT (component after component), one accumulator
/// per t point.
#[inline(always)]
fn far_block<const QT: usize>(a: &[f64], qs: usize, b: &[f64]) -> f64 {
    let col = |k: usize| -> &[f64; QT] { b[k * QT..(k + 1) * QT].try_into().expect("table block") };
    let (bx, by, bz, ux, uy, uz) = (col(0), col(1), col(2), col(3), col(4), col(5));
    let mut acc = [0.0f64; QT];
    for k in 0..qs {
        let (px, py, pz) = (a[k], a[qs + k], a[2 * qs + k]);
        let (tx, ty, tz) = (a[3 * qs + k], a[4 * qs + k], a[5 * qs + k]);
        for l in 0..QT {
            let (dx, dy, dz) = (px - bx[l], py - by[l], pz - bz[l]);
            let r2 = dx * dx + dy * dy + dz * dz;
            let (cx, cy, cz) = (ty * uz[l] - tz * uy[l], tz * ux[l] - tx * uz[l], tx * uy[l] - ty * ux[l]);
            acc[l] += (cx * dx + cy * dy + cz * dz) / (r2 * r2.sqrt());
        }
    }
    acc.iter().sum()
}

/// A near pair by direct evaluation on pieces, the t side's points kept
/// in `buf` (the caller's, reused: ≥ NEAR_ORDER · MAX_PIECES long).
fn near_pair<P: Pieces>(
    pc: &P,
    rules: &Rules,
    (x, y): (&Segment, &Segment),
    s: &Side,
    t: &Side,
    buf: &mut [([f64; 3], [f64; 3])],
) -> f64 {
    let mut n = 0;
    let (tx, tw) = rules.get(t.q);
    let ht = (y.u1 - y.u0) / t.m as f64;
    for k in 0..t.m {
        for (xi, wi) in tx.iter().zip(tw) {
            let (q, tq) = pc.at(y.piece, y.u0 + ht * (k as f64 + xi));
            buf[n] = (q, scale(tq, wi * ht));
            n += 1;
        }
    }
    let (sx, sw) = rules.get(s.q);
    let hs = (x.u1 - x.u0) / s.m as f64;
    let mut sum = 0.0;
    for k in 0..s.m {
        for (xi, wi) in sx.iter().zip(sw) {
            let (p, tp) = pc.at(x.piece, x.u0 + hs * (k as f64 + xi));
            let tp = scale(tp, wi * hs);
            sum += buf[..n].iter().map(|(q, tq)| kernel_w(&p, &tp, q, tq)).sum::<f64>();
        }
    }
    sum
}

/// ∫ over the ray from `o` along the unit `e` (tangent e) of the Gauss
/// integrand against (p, tp), in closed form: with d = p − o, β = d·e,
/// (tp × e)·d ∫₀^∞ dσ / |d − σe|³ = (tp × e)·d / (|d| (|d| − β)), where
/// |d| − β = |d × e|² / (|d| + β) when β > 0 (no cancellation far along
/// the ray).
fn ray_exact(p: &[f64; 3], tp: &[f64; 3], o: &[f64; 3], e: &[f64; 3]) -> f64 {
    let d = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
    let r = dot(d, d).sqrt();
    let num = dot(cross(*tp, *e), d);
    if r == 0.0 || num == 0.0 {
        return 0.0;
    }
    let beta = dot(d, *e);
    let gap = if beta <= 0.0 {
        r - beta
    } else {
        let c = cross(d, *e);
        dot(c, c) / (r + beta)
    };
    num / (r * gap)
}

/// The ends of an open curve: positions and unit tangents.
struct Ends {
    r0: [f64; 3],
    e0: [f64; 3],
    r1: [f64; 3],
    e1: [f64; 3],
}

/// The square of two adjacent pieces (x ends where y begins) by Duffy's
/// map from their common corner: u_x = 1 − α, u_y = β, the triangles
/// α ≥ β (α = u, β = uv) and β > α (β = u, α = uv), Jacobian u. Near the
/// corner the integrand of a curve only C¹ there is a bounded function of
/// α/β (the curvature jumps); in (u, v) it is analytic.
fn corner<P: Pieces>(pc: &P, rules: &Rules, x: usize, y: usize, q: usize) -> f64 {
    let (g, w) = rules.get(q);
    let mut sum = 0.0;
    for (u, wu) in g.iter().zip(w) {
        let (p, tp) = pc.at(x, 1.0 - u);
        let tp = scale(tp, u * wu);
        let (q, tq) = pc.at(y, *u);
        let tq = scale(tq, u * wu);
        for (v, wv) in g.iter().zip(w) {
            let (q2, tq2) = pc.at(y, u * v);
            sum += kernel_w(&p, &tp, &q2, &scale(tq2, *wv));
            let (p2, tp2) = pc.at(x, 1.0 - u * v);
            sum += kernel_w(&p2, &scale(tp2, *wv), &q, &tq);
        }
    }
    sum
}

/// The triangle u_t > u_s of a piece with itself (half its square: the
/// integrand is symmetric): u_t = u_s + (1 − u_s)v. Within one smooth
/// piece the integrand is (t − s) times an analytic function.
fn own<P: Pieces>(pc: &P, rules: &Rules, x: usize, q: usize) -> f64 {
    let (g, w) = rules.get(q);
    let mut sum = 0.0;
    for (s, ws) in g.iter().zip(w) {
        let (p, tp) = pc.at(x, *s);
        let tp = scale(tp, ws * (1.0 - s));
        for (v, wv) in g.iter().zip(w) {
            let (q, tq) = pc.at(x, s + (1.0 - s) * v);
            sum += kernel_w(&p, &tp, &q, &scale(tq, *wv));
        }
    }
    sum
}

/// One segment against the ray from `o` along unit `e` (`sign` −1: the
/// start ray r(0) − σ e0, tangent e0, is minus the ray from r(0) along
/// −e0) on `sd.m` parts of `sd.q` points.
fn ray_segment<P: Pieces>(pc: &P, rules: &Rules, x: &Segment, ray: (&[f64; 3], &[f64; 3], f64), sd: &Side) -> f64 {
    let (g, w) = rules.get(sd.q);
    let h = (x.u1 - x.u0) / sd.m as f64;
    let mut sum = 0.0;
    for k in 0..sd.m {
        for (xi, wi) in g.iter().zip(w) {
            let (p, tp) = pc.at(x.piece, x.u0 + h * (k as f64 + xi));
            sum += ray_exact(&p, &scale(tp, wi * h), ray.0, ray.1);
        }
    }
    ray.2 * sum
}

/// Curve–ray terms of segment x (value, estimate, evaluations): each ray
/// by Gauss on its closed-form integral, planned by the segment's distance
/// from the ray like a pair, or — the first and last piece, touching a
/// ray's start — at CORNER_ORDER (the integrand stays analytic there) with
/// the estimate |rule − lower rule|.
fn rays_of<P: Pieces>(pc: &P, rules: &Rules, x: &Segment, ends: &Ends, eps: f64) -> (f64, f64, f64) {
    let back = scale(ends.e0, -1.0);
    let last = pc.count() - 1;
    let (mut val, mut est, mut evals) = (0.0, 0.0, 0.0);
    for (o, e, sign) in [(&ends.r1, &ends.e1, 1.0), (&ends.r0, &back, -1.0)] {
        let d = segment_distance(x.a, sub(x.b, x.a), *o, *e, f64::INFINITY) - x.bulge;
        let touching = (x.piece == 0 && sign < 0.0) || (x.piece == last && sign > 0.0);
        if touching || !(d > 0.0) {
            let hi = Side { q: CORNER_ORDER, m: 1, err: 0.0 };
            let lo = Side { q: CORNER_ORDER - CORNER_STEP, m: 1, err: 0.0 };
            let v = ray_segment(pc, rules, x, (o, e, sign), &hi);
            est += (v - ray_segment(pc, rules, x, (o, e, sign), &lo)).abs();
            val += v;
            evals += (2 * CORNER_ORDER - CORNER_STEP) as f64;
        } else {
            let sd = side(x.coef, d, 2.0 * x.radius / d, eps);
            val += ray_segment(pc, rules, x, (o, e, sign), &sd);
            est += sd.err;
            evals += (sd.q * sd.m) as f64;
        }
    }
    (val, est, evals)
}

/// Ray–ray: ∫ over the start ray, r(0) − σ e0 (tangent e0, σ = ℓu/(1 − u)),
/// of the end ray's closed form, at order 16 on panels graded to both ends
/// of u; the estimate is |order 16 − order 8|.
fn ray_ray(ends: &Ends, ell: f64) -> (f64, f64) {
    let mut out = [0.0; 2];
    for (slot, q) in out.iter_mut().zip([16, 8]) {
        let (g, w) = gauss_legendre(q);
        for (u0, u1) in ray_panels() {
            let hu = 0.5 * (u1 - u0);
            for (xi, wi) in g.iter().zip(&w) {
                let u = u0 + hu * (1.0 + xi);
                let sigma = ell * u / (1.0 - u);
                let jac = ell / ((1.0 - u) * (1.0 - u));
                let p = axpy(ends.r0, -sigma, ends.e0);
                *slot += hu * wi * jac * ray_exact(&p, &ends.e0, &ends.r1, &ends.e1);
            }
        }
    }
    (out[0], (out[0] - out[1]).abs())
}

/// Refuses with ErrWorkLimit, stating the cost, a stage of
/// [`writhe_within`] that would exceed [`MAX_WRITHE_EVALUATIONS`].
fn check_stage(what: &str, evaluations: f64, segments: usize, tol: f64) -> Result<()> {
    if evaluations > MAX_WRITHE_EVALUATIONS {
        return Err(Error::new(
            Status::ErrWorkLimit,
            format!(
                "writhe: the call would exceed its work bound: {what} would take {evaluations:.2e} kernel \
                 evaluations on {segments} segments at tolerance {tol:e} (bound {MAX_WRITHE_EVALUATIONS:.0e}); \
                 raise the tolerance or use fewer nodes"
            ),
        ));
    }
    Ok(())
}

/// A near pair's work: its (part) segments and sides.
struct Near {
    x: Segment,
    y: Segment,
    s: Side,
    t: Side,
}

/// Records a near pair; one whose plan misses its budget (the separation
/// bound of the two capsules is too small or not positive) is cut into
/// SPLIT × SPLIT parts, each planned on its own, tighter, bounds with the
/// pair's budget shared, to `depth` levels. Returns the modelled error.
fn push_near<P: Pieces>(
    pc: &P,
    rules: &Rules,
    pair: (&Segment, &Segment),
    sides: (Side, Side),
    eps: f64,
    depth: usize,
    near: &mut Vec<Near>,
) -> f64 {
    const SPLIT: usize = 4;
    let (x, y) = pair;
    let err = sides.0.err + sides.1.err;
    if err <= eps || depth == 0 {
        near.push(Near { x: *x, y: *y, s: sides.0, t: sides.1 });
        return err;
    }
    let part = |g: &Segment, k: usize| {
        let h = (g.u1 - g.u0) / SPLIT as f64;
        segment(pc, g.piece, (g.u0 + h * k as f64, g.u0 + h * (k + 1) as f64), rules, None)
    };
    let eps = eps / (SPLIT * SPLIT) as f64;
    let mut est = 0.0;
    for k in 0..SPLIT {
        let xk = part(x, k);
        for j in 0..SPLIT {
            let yj = part(y, j);
            let sides = plan(&xk, &yj, eps);
            est += push_near(pc, rules, (&xk, &yj), sides, eps, depth - 1, near);
        }
    }
    est
}

/// Per piece and order q ≤ FAR_ORDER, the smallest distance (on a grid of
/// ratio 2^(1/4), rounded up) at which a q-point side meets its share of
/// the budget, eps/2, with mag taken at the largest radius for the other
/// side, and the modelled error there: a far pair needs two look-ups
/// instead of two plans.
type Thresholds = Vec<[(f64, f64); FAR_ORDER]>;

fn thresholds(segs: &[Segment], eps: f64) -> Thresholds {
    let rmax = segs.iter().map(|x| x.radius).fold(0.0, f64::max);
    let extent: f64 = 2.0 * segs.iter().map(|x| x.radius).sum::<f64>();
    let ratio = 2f64.powf(0.25);
    segs.iter()
        .map(|x| {
            let mut thr = [(f64::INFINITY, 0.0); FAR_ORDER];
            let mut d = 0.25 * x.radius;
            let mut open = FAR_ORDER;
            while open > 0 && d <= 2.0 * extent {
                let mag = 4.0 * x.radius * rmax / (d * d);
                let r2 = rho2(x.coef, d);
                let mut pw = r2;
                // q = 1 (the midpoint rule) is never used: its error is the
                // numerator's variation more than the kernel's (measured).
                for slot in thr.iter_mut().skip(1) {
                    pw *= r2;
                    let err = MODEL_FACTOR * mag / pw;
                    if slot.0.is_infinite() && err <= 0.5 * eps {
                        *slot = (d, err);
                        open -= 1;
                    }
                }
                d *= ratio;
            }
            thr
        })
        .collect()
}

/// The far-table order of a side at distance d (None: beyond the tables),
/// and its modelled error (scaled from the threshold's by (threshold/d)²).
#[inline]
fn look_up(thr: &[(f64, f64); FAR_ORDER], d: f64) -> Option<Side> {
    thr.iter().position(|t| d >= t.0).map(|k| Side { q: k + 1, m: 1, err: thr[k].1 * (thr[k].0 / d).powi(2) })
}

/// The non-adjacent pairs: the far ones summed from the tables, the near
/// ones returned for the next stage. (sum, estimate, evaluations, near).
fn pair_stage<P: Pieces>(
    pc: &P,
    rules: &Rules,
    segs: &[Segment],
    tables: &Tables,
    closed: bool,
    eps: f64,
) -> (f64, f64, f64, Vec<Near>) {
    let n = segs.len();
    let thr = thresholds(segs, eps);
    let (mut total, mut est, mut evals) = (0.0, 0.0, 0.0);
    let mut near = Vec::with_capacity(4 * n);
    for i in 0..n {
        // j = i + 1 is adjacent; so is (0, n − 1) when closed.
        let end = if closed && i == 0 { n - 1 } else { n };
        let (x, tx) = (&segs[i], &thr[i]);
        for j in i + 2..end {
            let (y, ty) = (&segs[j], &thr[j]);
            let c = sub(x.mid, y.mid);
            let mut d = dot(c, c).sqrt() - x.radius - y.radius;
            let far = tx[FAR_ORDER - 1].0.max(ty[FAR_ORDER - 1].0);
            if d < far {
                d = separation(x, y);
            }
            if d >= far {
                if let (Some(s), Some(t)) = (look_up(tx, d), look_up(ty, d)) {
                    total += far_pair(tables, i, j, &s, &t);
                    est += s.err + t.err;
                    evals += (s.q * t.q) as f64;
                    continue;
                }
            }
            let sides = plan(x, y, eps);
            est += push_near(pc, rules, (x, y), sides, eps, 3, &mut near);
        }
    }
    (total, est, evals, near)
}

/// The whole rule on pieces: (writhe × 4π, estimate × 4π, evaluations).
fn within_on<P: Pieces>(pc: &P, closed: bool, tol: f64) -> Result<(f64, f64, f64)> {
    let rules = Rules::new();
    let (segs, tables) = segments(pc, &rules);
    let n = segs.len();
    let pairs = (n * n.saturating_sub(1) / 2).max(1) as f64;
    let eps = 4.0 * std::f64::consts::PI * tol / (2.0 * pairs);
    let (mut total, mut est, mut evals, near) = pair_stage(pc, &rules, &segs, &tables, closed, eps);
    let near_cost: f64 = near.iter().map(|w| ((w.s.q * w.s.m + 1) * w.t.q * w.t.m) as f64).sum();
    let lower = CORNER_ORDER - CORNER_STEP;
    let corner_cost = 3.0 * n as f64 * ((CORNER_ORDER.pow(2) + lower.pow(2)) as f64);
    check_stage("the near pairs", near_cost + corner_cost, n, tol)?;
    let mut buf = vec![([0.0; 3], [0.0; 3]); NEAR_ORDER * MAX_PIECES];
    for w in &near {
        total += near_pair(pc, &rules, (&w.x, &w.y), &w.s, &w.t, &mut buf);
    }
    evals += near_cost + corner_cost;
    // Self and adjacent pairs at CORNER_ORDER, estimated against a lower order.
    for i in 0..n {
        let (a, b) = (own(pc, &rules, i, CORNER_ORDER), own(pc, &rules, i, lower));
        total += a;
        est += (a - b).abs();
        let j = if i + 1 < n {
            i + 1
        } else if closed {
            0
        } else {
            continue;
        };
        let (a, b) = (corner(pc, &rules, i, j, CORNER_ORDER), corner(pc, &rules, i, j, lower));
        total += a;
        est += (a - b).abs();
    }
    // Symmetry: every unordered pair of pieces counted twice.
    total *= 2.0;
    est *= 2.0;
    if !closed {
        let ((r0, t0), (r1, t1)) = (pc.at(0, 0.0), pc.at(n - 1, 1.0));
        let ends = Ends { r0, e0: unit(t0), r1, e1: unit(t1) };
        for x in &segs {
            let (v, e, c) = rays_of(pc, &rules, x, &ends, eps);
            total += 2.0 * v;
            est += 2.0 * e;
            evals += c;
        }
        let ell = segs.iter().map(|x| 2.0 * x.radius).sum::<f64>();
        let (v, e) = ray_ray(&ends, ell);
        total += 2.0 * v;
        est += 2.0 * e;
    }
    Ok((total, est, evals))
}

/// Writhe of `curve` (closed, or open and closed by rays along its end
/// tangents) to about `tol` turns, with an error estimate.
///
/// The double integral is summed over pairs of the curve's smooth pieces
/// (between its breakpoints; a [`HermiteCurve`](super::HermiteCurve)'s cubics are evaluated
/// from their coefficients). Each non-adjacent pair is integrated by
/// tensor Gauss with orders chosen a priori per side from the pair's
/// separation (the private `side`) so that its modelled error stays below
/// 4π tol / (2 · number of pairs): far pairs from tables of each piece's
/// Gauss points (2–4 points a side on a rod), near ones by direct
/// evaluation, cut into parts when one would need more than NEAR_ORDER
/// points. The square of two adjacent pieces — where a C¹ curve's
/// integrand has a bounded jump at the common node — is integrated by
/// Duffy's map from the node, a piece with itself on its triangle, both at
/// CORNER_ORDER; the rays' inner integrals are in closed form.
///
/// Work: the far stage is bounded by ½ (pieces · FAR_ORDER)² and refused
/// above [`MAX_WRITHE_EVALUATIONS`] before it starts; the near pairs are
/// counted during it and their stage is refused likewise before it starts.
pub fn writhe_within(curve: &dyn Centerline, tol: f64) -> Result<WritheEstimate> {
    error::in_range("tol", tol, MIN_WRITHE_TOLERANCE, 1.0)?;
    let l = curve.length();
    error::positive("length", l)?;
    let (cubics, sampled) = pieces_of(curve);
    let n = sampled.count();
    check_stage("the far pairs", 0.5 * (n as f64 * FAR_ORDER as f64).powi(2), n, tol)?;
    let closed = curve.closed();
    let (total, est, evals) = match &cubics {
        Some(c) => within_on(c, closed, tol)?,
        None => within_on(&sampled, closed, tol)?,
    };
    let four_pi = 4.0 * std::f64::consts::PI;
    let value = total / four_pi;
    if !value.is_finite() {
        return Err(Error::new(Status::ErrNonFiniteResult, "writhe is not finite"));
    }
    Ok(WritheEstimate { value, estimate: est / four_pi, evaluations: evals })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::HermiteCurve;

    /// A Hermite curve through `nodes` + 1 points of a toroidal helix
    /// winding `n` times round the unit circle at amplitude `eps` (closed).
    fn toroidal(n: f64, eps: f64, nodes: usize) -> HermiteCurve {
        let f = |p: f64| {
            let (sp, cp) = p.sin_cos();
            let (sn, cn) = (n * p).sin_cos();
            let rho = 1.0 + eps * cn;
            let drho = -eps * n * sn;
            ([rho * cp, rho * sp, eps * sn], [drho * cp - rho * sp, drho * sp + rho * cp, eps * n * cn])
        };
        let ps: Vec<f64> = (0..=nodes).map(|k| 2.0 * std::f64::consts::PI * k as f64 / nodes as f64).collect();
        let r = ps.iter().map(|&p| f(p).0).collect();
        let t = ps.iter().map(|&p| unit(f(p).1)).collect();
        HermiteCurve::new(ps, r, t, true).unwrap()
    }

    /// The pair error model of [`side`] against the truth: on every
    /// non-adjacent pair of pieces of two toroidal helices (through 60 and
    /// 150 nodes: pieces from 1/10 to 1/3 of a winding), the error of q × q
    /// points (q = 2…6; the midpoint rule is never used) against 16 × 16 (converged: the pairs are apart)
    /// stays below MODEL_FACTOR · mag · (ρ_s^(−2q) + ρ_t^(−2q)), plus a
    /// rounding floor of 1e-14 (mag + |pair|). Measured worst ratio (error / model
    /// without the factor): printed; the plectoneme of tests/writhe.rs at
    /// 100–400 nodes gave ≤ 14 (the reason for the factor 30).
    /// A Hermite curve through `nodes` + 1 points of a plectoneme-like
    /// hairpin (tests/writhe.rs): strands x = ∓ρ, a half-circle loop below
    /// z = 0, rotated about z by ψ = 2π n S(z/h) (S the C² smoothstep),
    /// tails of length 15 above h; DNA-like sizes (ρ 3, h 100, n 6).
    fn hairpin(nodes: usize) -> HermiteCurve {
        let (rho, h, tail, n) = (3.0, 100.0, 15.0, 6.0);
        let pi = std::f64::consts::PI;
        let f = |tau: f64| {
            let (top, lp) = (h + tail, pi * rho);
            let (x, z, dx, dz) = if tau < top {
                (-rho, top - tau, 0.0, -1.0)
            } else if tau < top + lp {
                let th = (tau - top) / rho;
                (-rho * th.cos(), -rho * th.sin(), th.sin(), -th.cos())
            } else {
                (rho, tau - top - lp, 0.0, 1.0)
            };
            let u = (z / h).clamp(0.0, 1.0);
            let psi = 2.0 * pi * n * u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
            let dpsi = if z > 0.0 && z < h { 60.0 * pi * n * u * u * (1.0 - u) * (1.0 - u) / h } else { 0.0 };
            let (sp, cp) = psi.sin_cos();
            let w = dpsi * dz;
            ([x * cp, x * sp, z], [dx * cp - x * sp * w, dx * sp + x * cp * w, dz])
        };
        let len = 2.0 * (h + tail) + pi * rho;
        let ps: Vec<f64> = (0..=nodes).map(|k| len * k as f64 / nodes as f64).collect();
        let r = ps.iter().map(|&p| f(p).0).collect();
        let t = ps.iter().map(|&p| unit(f(p).1)).collect();
        HermiteCurve::new(ps, r, t, false).unwrap()
    }

    #[test]
    fn pair_model_bounds_the_gauss_error() {
        let rules = Rules::new();
        let curves = [toroidal(8.0, 0.25, 60), toroidal(10.0, 0.1, 150), hairpin(100), hairpin(300)];
        for (k, c) in curves.iter().enumerate() {
            let (cubics, _) = pieces_of(c);
            let pc = cubics.unwrap();
            let (segs, _) = segments(&pc, &rules);
            let mut worst = 0.0f64;
            for i in 0..segs.len() {
                for j in i + 2..segs.len() - usize::from(i == 0 && c.closed) {
                    let (x, y) = (&segs[i], &segs[j]);
                    let d = separation(x, y);
                    if !(d > 0.0) {
                        continue;
                    }
                    let mag = 4.0 * x.radius * y.radius / (d * d);
                    let full = Side { q: 16, m: 1, err: 0.0 };
                    let mut buf = vec![([0.0; 3], [0.0; 3]); NEAR_ORDER * MAX_PIECES];
                    let reference = near_pair(&pc, &rules, (x, y), &full, &full, &mut buf);
                    for q in 2..=6 {
                        let sd = Side { q, m: 1, err: 0.0 };
                        let err = (near_pair(&pc, &rules, (x, y), &sd, &sd, &mut buf) - reference).abs();
                        let model = mag * (rho2(x.coef, d).powi(-(q as i32)) + rho2(y.coef, d).powi(-(q as i32)));
                        let floor = 1e-14 * (mag + reference.abs());
                        assert!(err <= MODEL_FACTOR * model + floor, "pair {i} {j} q {q}: {err:e} vs model {model:e}");
                        if err > floor {
                            worst = worst.max(err / model);
                        }
                    }
                }
            }
            println!("curve {k}: worst error / model {worst:.2}");
        }
    }
}

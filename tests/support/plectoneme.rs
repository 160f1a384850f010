//! Plectoneme-like test curves and Fuller's reference for their writhe
//! (shared by tests/writhe.rs and benches/writhe.rs): an analytic
//! interwound hairpin, its Hermite curve in the rod's profile layout, and
//! Fuller's (1978) integral against its planar projection.
#![allow(dead_code)]

use rodkit::electrostatics::Centerline;
use rodkit::geometry::HermiteCurve;
use std::f64::consts::PI;

/// The unit tangent of a curve with derivative d1 and second derivative d2,
/// and its derivative.
pub fn unit_and_derivative(d1: [f64; 3], d2: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let n = (d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]).sqrt();
    let t = [d1[0] / n, d1[1] / n, d1[2] / n];
    let td2 = t[0] * d2[0] + t[1] * d2[1] + t[2] * d2[2];
    (t, [(d2[0] - t[0] * td2) / n, (d2[1] - t[1] * td2) / n, (d2[2] - t[2] * td2) / n])
}

/// v / |v|.
pub fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / n, v[1] / n, v[2] / n]
}

/// A plectoneme-like curve (analytic, C²): a hairpin — strand A down
/// x = −ρ from z = H + T to 0, a half circle of radius ρ below z = 0,
/// strand B up x = +ρ — rotated about z by ψ(z) = 2π n S(z/H) (S the C²
/// smoothstep, ψ = 0 below 0 and 2πn above H): two strands interwound n
/// times (2n crossings), an end loop, and straight tails along z of length
/// T above H in the plane y = 0. Returns (r, dr/dτ) at τ ∈ [0, 2(H + T) + πρ].
pub fn plectoneme(tau: f64, shape: &Shape) -> ([f64; 3], [f64; 3]) {
    let Shape { rho, h, tail, n } = *shape;
    let top = h + tail;
    let loop_len = PI * rho;
    // The untwisted hairpin (x, 0, z) and its derivative in τ.
    let (x, z, dx, dz) = if tau < top {
        (-rho, top - tau, 0.0, -1.0)
    } else if tau < top + loop_len {
        let th = (tau - top) / rho;
        (-rho * th.cos(), -rho * th.sin(), th.sin(), -th.cos())
    } else {
        (rho, tau - top - loop_len, 0.0, 1.0)
    };
    let u = (z / h).clamp(0.0, 1.0);
    let psi = 2.0 * PI * n * u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
    let dpsi = if z > 0.0 && z < h { 2.0 * PI * n * 30.0 * u * u * (1.0 - u) * (1.0 - u) / h } else { 0.0 };
    let (sp, cp) = psi.sin_cos();
    let w = dpsi * dz;
    ([x * cp, x * sp, z], [dx * cp - x * sp * w, dx * sp + x * cp * w, dz])
}

/// A Hermite curve through `elements` × (node + the two Gauss(2) stage
/// points, c = ½ ∓ √3/6, the rod's profile layout) + 1 points of `f` in
/// τ ∈ [0, len], at arc lengths (16-point Gauss of |f'| per interval) with
/// unit tangents (closed: f periodic in len, the last node repeats the first).
pub fn hermite_through(
    f: &dyn Fn(f64) -> ([f64; 3], [f64; 3]),
    len: f64,
    elements: usize,
    closed: bool,
) -> HermiteCurve {
    let c = 3f64.sqrt() / 6.0;
    let mut taus = Vec::new();
    for e in 0..elements {
        let (a, b) = (len * e as f64 / elements as f64, len * (e + 1) as f64 / elements as f64);
        taus.extend([a, a + (0.5 - c) * (b - a), a + (0.5 + c) * (b - a)]);
    }
    taus.push(len);
    let (g, w) = rodkit::quadrature::gauss_legendre(16);
    let mut s = vec![0.0];
    for k in 1..taus.len() {
        let (a, b) = (taus[k - 1], taus[k]);
        let arc: f64 = g
            .iter()
            .zip(&w)
            .map(|(x, wi)| {
                let d = f(0.5 * (a + b) + 0.5 * (b - a) * x).1;
                0.5 * (b - a) * wi * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
            })
            .sum();
        s.push(s[k - 1] + arc);
    }
    let r = taus.iter().map(|&t| f(t).0).collect();
    let t = taus.iter().map(|&t| unit(f(t).1)).collect();
    HermiteCurve::new(s, r, t, closed).unwrap()
}

/// The comparison curve of [`fuller_hermite`]: (r', r'') at s, given the
/// Hermite curve's (r', r'') there.
pub type Companion<'a> = dyn Fn(f64, [f64; 3], [f64; 3]) -> ([f64; 3], [f64; 3]) + 'a;

/// Fuller's integral (as [`fuller`]) between the Hermite curve `c` and the
/// curve `c0` given at the same parameter s, per Hermite segment (the
/// integrand is smooth within one: the curve's r'' jumps at the nodes) on
/// 4 panels of 20 Gauss points — converged to rounding.
pub fn fuller_hermite(c: &HermiteCurve, c0: &Companion<'_>) -> f64 {
    let (g, w) = rodkit::quadrature::gauss_legendre(20);
    let mut sum = 0.0;
    for k in 1..c.s.len() {
        for p in 0..4 {
            let h = (c.s[k] - c.s[k - 1]) / 4.0;
            let a = c.s[k - 1] + p as f64 * h;
            for (gi, wi) in g.iter().zip(&w) {
                let s = a + 0.5 * h * (1.0 + gi);
                let (_, b1, b2) = c.eval(s);
                let (a1, a2) = c0(s, b1, b2);
                let (t0, dt0) = unit_and_derivative(a1, a2);
                let (t1, dt1) = unit_and_derivative(b1, b2);
                let x = [t0[1] * t1[2] - t0[2] * t1[1], t0[2] * t1[0] - t0[0] * t1[2], t0[0] * t1[1] - t0[1] * t1[0]];
                let num = x[0] * (dt0[0] + dt1[0]) + x[1] * (dt0[1] + dt1[1]) + x[2] * (dt0[2] + dt1[2]);
                let den = 1.0 + t0[0] * t1[0] + t0[1] * t1[1] + t0[2] * t1[2];
                sum += 0.5 * h * wi * num / den;
            }
        }
    }
    sum / (2.0 * PI)
}

/// The plectoneme's dimensions: superhelix radius ρ, height H, tail T,
/// n turns (2n crossings).
#[derive(Clone, Copy)]
pub struct Shape {
    pub rho: f64,
    pub h: f64,
    pub tail: f64,
    pub n: f64,
}

/// The test plectoneme: ρ 1, H 20, T 5, 5 turns (10 crossings).
pub const TEST: Shape = Shape { rho: 1.0, h: 20.0, tail: 5.0, n: 5.0 };
/// A DNA-like one in nm: 1 kbp (341 nm), superhelix radius 3 nm, 100 nm
/// high, 6 turns (12 crossings), tails 15 nm — the shape of the 1 kbp
/// scene near 12 turns of end rotation (Wr ≈ 10).
pub const DNA: Shape = Shape { rho: 3.0, h: 100.0, tail: 15.0, n: 6.0 };

/// The plectoneme's Hermite curve on `elements` elements (3·elements + 1 nodes).
pub fn plectoneme_curve(elements: usize, shape: &Shape) -> HermiteCurve {
    let len = 2.0 * (shape.h + shape.tail) + PI * shape.rho;
    hermite_through(&|t| plectoneme(t, shape), len, elements, false)
}

/// Fuller's reference for the plectoneme's Hermite curve C1: C0 = its
/// projection on the plane y = 0 (tails and rays included: they lie in it),
/// planar, so Wr(C0) = 0; T0 = P T1/|P T1| is never antipodal to T1
/// (T0·T1 = |P T1| > 0, checked > 0.05 along the curve). C0 crosses itself
/// where the projection of the strands does, so the deformation
/// C_λ = (x, λy, z) passes through crossings at λ = 0: the writhe of C1 is
/// Fuller's integral plus an integer (the signed crossings of the
/// projection). Returns Fuller's integral.
pub fn plectoneme_fuller(c: &HermiteCurve) -> f64 {
    let m = 20_000;
    let worst = (0..=m)
        .map(|k| {
            let t = c.eval(c.s[c.s.len() - 1] * k as f64 / m as f64).1;
            (t[0] * t[0] + t[2] * t[2]).sqrt() / (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt()
        })
        .fold(f64::INFINITY, f64::min);
    assert!(worst > 0.05, "the projection's tangent nearly vanishes: {worst}");
    fuller_hermite(c, &|_, d1, d2| ([d1[0], 0.0, d1[2]], [d2[0], 0.0, d2[2]]))
}

//! Curve geometry shared by rods and electrostatics: the centreline of a
//! rod as a curve in space ([`Centerline`], [`HermiteCurve`]), its writhe
//! ([`writhe`]), spatial proximity of its points (cell lists, closest
//! approach: [`proximity`]) and the small 3-vector algebra they use
//! ([`vec3`]). Nothing here knows about rods or charges: the rod's twist and
//! linking number are in `crate::rod::topology`, the electrostatic field of
//! a centreline in `crate::electrostatics`.

pub mod proximity;
pub mod vec3;
pub mod writhe;

use crate::error::{Error, Result};
use crate::status::Status;

/// A smooth centreline parametrised by arc length s ∈ [0, L].
pub trait Centerline {
    fn length(&self) -> f64;
    /// A closed curve (r(L) = r(0), periodic): no ends.
    fn closed(&self) -> bool;
    /// r(s), r'(s), r''(s).
    fn eval(&self, s: f64) -> ([f64; 3], [f64; 3], [f64; 3]);
    /// Arc lengths where the curve is only C¹ (element nodes), ascending,
    /// inside (0, L); quadrature panels break there.
    fn breakpoints(&self) -> Vec<f64>;
    /// The curve as a [`HermiteCurve`] when it is one: the writhe then
    /// evaluates its cubics from their coefficients.
    fn as_hermite(&self) -> Option<&HermiteCurve> {
        None
    }
}

/// A C¹ centreline through nodes: cubic Hermite in arc length from node
/// positions and unit tangents (the rod's nodes and d3), open or closed.
#[derive(Clone, Debug, PartialEq)]
pub struct HermiteCurve {
    pub s: Vec<f64>,
    pub r: Vec<[f64; 3]>,
    pub t: Vec<[f64; 3]>,
    pub closed: bool,
}

impl HermiteCurve {
    pub fn new(s: Vec<f64>, r: Vec<[f64; 3]>, t: Vec<[f64; 3]>, closed: bool) -> Result<Self> {
        if s.len() < 2 || r.len() != s.len() || t.len() != s.len() {
            return Err(Error::new(
                Status::ErrInvalidDimension,
                "a Hermite curve needs ≥ 2 nodes with one position and one tangent each",
            ));
        }
        if !s.windows(2).all(|w| w[1] > w[0]) || s[0] != 0.0 {
            return Err(Error::new(Status::ErrOutOfRange, "node arc lengths must start at 0 and increase"));
        }
        Ok(HermiteCurve { s, r, t, closed })
    }

    /// The element k holding s (s_k ≤ s < s_{k+1}; the last element for
    /// s = L), its length h and the local coordinate u.
    fn locate(&self, s: f64) -> (usize, f64, f64) {
        let n = self.s.len() - 1;
        let last = self.s[n];
        let s = s.clamp(0.0, last);
        // A rod's nodes are (nearly) uniform: start from the uniform guess
        // and walk a few nodes; otherwise bisect. The writhe's double
        // integral evaluates the curve ~10⁵ times per path point, and the
        // bisection alone was 10 % of a supercoiling run.
        let mut k = (((s / last) * n as f64) as usize).min(n - 1);
        let mut found = false;
        for _ in 0..4 {
            if k > 0 && self.s[k] > s {
                k -= 1;
            } else if k + 1 < n && self.s[k + 1] <= s {
                k += 1;
            } else {
                found = true;
                break;
            }
        }
        if !found {
            k = match self.s.binary_search_by(|v| v.total_cmp(&s)) {
                Ok(i) => i.min(n - 1),
                Err(i) => (i.max(1) - 1).min(n - 1),
            };
        }
        let h = self.s[k + 1] - self.s[k];
        (k, h, (s - self.s[k]) / h)
    }

    /// (k, h, weights) of the Hermite basis (h00, h10, h01, h11) at s: its
    /// values and its first and second derivatives in u.
    pub(crate) fn basis(&self, s: f64) -> (usize, f64, [[f64; 4]; 3]) {
        let (k, h, u) = self.locate(s);
        (k, h, [hermite_values(u), hermite_first_derivatives(u), hermite_second_derivatives(u)])
    }
}

/// The cubic Hermite basis (h00, h10, h01, h11) at u ∈ [0, 1]: weights of
/// p0, h·m0, p1, h·m1.
fn hermite_values(u: f64) -> [f64; 4] {
    [
        2.0 * u * u * u - 3.0 * u * u + 1.0,
        u * u * u - 2.0 * u * u + u,
        -2.0 * u * u * u + 3.0 * u * u,
        u * u * u - u * u,
    ]
}

/// The basis' first derivatives in u.
fn hermite_first_derivatives(u: f64) -> [f64; 4] {
    [6.0 * u * u - 6.0 * u, 3.0 * u * u - 4.0 * u + 1.0, -6.0 * u * u + 6.0 * u, 3.0 * u * u - 2.0 * u]
}

/// The basis' second derivatives in u.
fn hermite_second_derivatives(u: f64) -> [f64; 4] {
    [12.0 * u - 6.0, 6.0 * u - 4.0, -12.0 * u + 6.0, 6.0 * u - 2.0]
}

impl Centerline for HermiteCurve {
    fn length(&self) -> f64 {
        *self.s.last().expect("≥ 2 nodes")
    }
    fn closed(&self) -> bool {
        self.closed
    }
    fn eval(&self, s: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let (k, h, u) = self.locate(s);
        let [h00, h10, h01, h11] = hermite_values(u);
        let [d00, d10, d01, d11] = hermite_first_derivatives(u);
        let [e00, e10, e01, e11] = hermite_second_derivatives(u);
        let mut out = ([0.0; 3], [0.0; 3], [0.0; 3]);
        for i in 0..3 {
            let (p0, p1, m0, m1) = (self.r[k][i], self.r[k + 1][i], h * self.t[k][i], h * self.t[k + 1][i]);
            out.0[i] = h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1;
            out.1[i] = (d00 * p0 + d10 * m0 + d01 * p1 + d11 * m1) / h;
            out.2[i] = (e00 * p0 + e10 * m0 + e01 * p1 + e11 * m1) / (h * h);
        }
        out
    }
    fn breakpoints(&self) -> Vec<f64> {
        self.s[1..self.s.len() - 1].to_vec()
    }
    fn as_hermite(&self) -> Option<&HermiteCurve> {
        Some(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The element search (uniform guess + walk, else bisection) against a
    /// plain linear scan (the reference: the last node ≤ s, the last element
    /// at s = L), on uniform, geometrically graded and jittered nodes, at
    /// the nodes themselves, between them and at the ends.
    #[test]
    fn locate_finds_the_element_holding_s() {
        let uniform: Vec<f64> = (0..=50).map(|i| 3.4 * i as f64).collect();
        let graded: Vec<f64> = (0..=30).map(|i| 2f64.powi(i) - 1.0).collect();
        let jittered: Vec<f64> = (0..=40)
            .map(|i| i as f64 + if i % 2 == 1 { 0.45 } else { 0.0 } * if i % 3 == 0 { -1.0 } else { 1.0 })
            .collect();
        for s in [uniform, graded, jittered] {
            let n = s.len();
            let curve = HermiteCurve::new(s.clone(), vec![[0.0; 3]; n], vec![[0.0, 0.0, 1.0]; n], false).unwrap();
            let last = s[n - 1];
            let mut probes: Vec<f64> = s.clone();
            probes.extend((0..=997).map(|i| last * i as f64 / 997.0));
            probes.extend(s.windows(2).map(|w| 0.5 * (w[0] + w[1])));
            probes.extend([-1.0, last + 1.0, last * (1.0 - 1e-15)]);
            for &p in &probes {
                let c = p.clamp(0.0, last);
                let expect = (0..n - 1).rev().find(|&k| s[k] <= c).unwrap_or(0).min(n - 2);
                let (k, h, u) = curve.locate(p);
                assert_eq!(k, expect, "s = {p}");
                assert_eq!(h, s[k + 1] - s[k]);
                assert!((0.0..=1.0).contains(&u), "u = {u} at s = {p}");
            }
        }
    }
}

//! Twist and writhe of a rod state (physics.md §3.4): the linking number
//! of the ribbon (r, d1) of a rod clamped along its end tangents,
//! Lk = Tw + Wr (Călugăreanu–White; the open rod closed by rays along the
//! clamp axes), which a supercoiling path must keep equal to the end
//! rotation over 2π.
//!
//! * Tw = (1/2π) ∫ d1'·d2 ds = (1/2π) ∫ u3 ds (Kirchhoff rods: r' = d3),
//!   integrated with the collocation's own weights on the stage values —
//!   the scheme applied to θ' = u3, so accurate at its order 2s.
//! * Wr by the Gauss double integral ([`crate::geometry::writhe`]: at a
//!   fixed order, or to a tolerance) on a C¹ cubic Hermite centreline
//!   through every node and stage point with tangents d3, each interval cut
//!   in [`WRITHE_PARTS`] at points of the quintic Hermite through its ends
//!   (r'' from the tangents): the cubic through the profile points alone
//!   is O(Δ⁴) in their spacing and limited |Tw + Wr − Lk| on coarse meshes.

use super::kinematics::{rotation, strains};
use super::model::Rod;
use crate::error::{Error, Result};
use crate::geometry::vec3::dot;
use crate::geometry::writhe::{writhe, writhe_within, WritheEstimate};
use crate::geometry::HermiteCurve;
use crate::status::Status;

impl Rod {
    /// The states along the rod: (arc length, 13-vector) at every node and
    /// stage point, in order.
    fn profile<'a>(&self, x: &'a [f64]) -> Vec<(f64, &'a [f64])> {
        self.profile_offsets().into_iter().map(|(s, o)| (s, &x[o..o + 13])).collect()
    }

    /// Tw = (1/2π) ∫ u3 ds (turns).
    pub fn twist(&self, x: &[f64]) -> f64 {
        let data = self.rhs_data();
        let tab = self.tableau();
        let u3 = |y: &[f64]| {
            let (u, _) = strains::<f64, f64>(&data, &[y[10], y[11], y[12]], &[y[7], y[8], y[9]]);
            u[2]
        };
        let mut total = 0.0;
        for i in 0..self.elements {
            let h = self.element_h(i);
            match self.scheme.stages() {
                // Implicit midpoint: its one stage is the midpoint, weight 1.
                0 => {
                    let (a, b) = (self.node_state(x, i), self.node_state(x, i + 1));
                    let mid: Vec<f64> = a.iter().zip(b).map(|(p, q)| 0.5 * (p + q)).collect();
                    total += h * u3(&mid);
                }
                s => {
                    for j in 0..s {
                        let o = self.stage_offset(i, j);
                        total += h * tab.b[j] * u3(&x[o..o + 13]);
                    }
                }
            }
        }
        total / (2.0 * std::f64::consts::PI)
    }

    /// Wr of the centreline closed by rays along the end tangents (turns),
    /// Gauss–Legendre of `order` points per panel ([`writhe`]).
    pub fn writhe(&self, x: &[f64], order: usize) -> Result<f64> {
        writhe(&self.centerline(x, WRITHE_PARTS)?, order)
    }

    /// Wr of the centreline closed by rays along the end tangents (turns)
    /// to about `tol`, with an error estimate ([`writhe_within`]), on the
    /// profile refined [`WRITHE_PARTS`] times.
    pub fn writhe_within(&self, x: &[f64], tol: f64) -> Result<WritheEstimate> {
        writhe_within(&self.centerline(x, WRITHE_PARTS)?, tol)
    }

    /// [`Rod::writhe_within`] with each profile interval cut into `parts`
    /// pieces (1: the cubic Hermite through the profile points alone;
    /// 1..=16).
    pub fn writhe_within_parts(&self, x: &[f64], tol: f64, parts: usize) -> Result<WritheEstimate> {
        crate::error::count_in_range("parts", parts as i64, 1, 16)?;
        writhe_within(&self.centerline(x, parts)?, tol)
    }

    /// The writhe's centreline: C¹ cubic Hermite pieces through every node
    /// and stage point with tangents d3, each interval cut into
    /// [`WRITHE_PARTS`] pieces at points of the quintic Hermite through its
    /// ends (positions, tangents and r'' estimated from the tangents of the
    /// five nearest profile points, [`tangent_derivatives`]).
    fn centerline(&self, x: &[f64], parts: usize) -> Result<HermiteCurve> {
        let pts = self.profile(x);
        let mut s = Vec::with_capacity(pts.len());
        let mut r = Vec::with_capacity(pts.len());
        let mut t = Vec::with_capacity(pts.len());
        for (si, y) in pts {
            let q = [y[3], y[4], y[5], y[6]];
            let n2 = q.iter().map(|v| v * v).sum::<f64>();
            if !(n2 > 0.0 && n2.is_finite()) {
                return Err(Error::new(
                    Status::ErrNonFiniteResult,
                    "writhe: a quaternion of the state is zero or not finite",
                ));
            }
            let rot = rotation(&q);
            let d3 = [rot[0][2] / n2, rot[1][2] / n2, rot[2][2] / n2];
            let norm = dot(d3, d3).sqrt();
            s.push(si);
            r.push([y[0], y[1], y[2]]);
            t.push([d3[0] / norm, d3[1] / norm, d3[2] / norm]);
        }
        if parts <= 1 || s.len() < 5 {
            return HermiteCurve::new(s, r, t, false);
        }
        let a = tangent_derivatives(&s, &t);
        let n = s.len() - 1;
        let (mut fs, mut fr, mut ft) =
            (Vec::with_capacity(n * parts + 1), Vec::with_capacity(n * parts + 1), Vec::with_capacity(n * parts + 1));
        for k in 0..n {
            let h = s[k + 1] - s[k];
            for j in 0..parts {
                let u = j as f64 / parts as f64;
                let (p, d) = quintic_hermite(u, h, [r[k], t[k], a[k]], [r[k + 1], t[k + 1], a[k + 1]]);
                let norm = dot(d, d).sqrt();
                fs.push(s[k] + u * h);
                fr.push(p);
                ft.push([d[0] / norm, d[1] / norm, d[2] / norm]);
            }
        }
        fs.push(s[n]);
        fr.push(r[n]);
        ft.push(t[n]);
        HermiteCurve::new(fs, fr, ft, false)
    }
}

/// Pieces each profile interval is cut into for the writhe's centreline:
/// the cubic Hermite through the profile points alone is O(Δ⁴) in their
/// spacing Δ, and |Tw + Wr − Lk| followed it (the twist is the scheme's,
/// O(h^2s)): 1.1e-4 at 12 turns on 40 elements of Gauss(4) (gaps up to 2.9
/// nm), 1.3e-5 on 70, 7.7e-6 on 170 of Gauss(2). Cut in 2: 2.4e-6 on 40 ×
/// Gauss(4) (3: 3.7e-6, the rest is the states'), the writhe 2.2× the
/// cost of the profile's own (3.4 s against 1.5 s of a 118 s run; 3: 4.3×).
pub const WRITHE_PARTS: usize = 2;

/// r'' = t' at every profile point: the derivative of the Lagrange
/// polynomial through the tangents of the five nearest points (one-sided
/// at the ends), O(Δ⁴).
fn tangent_derivatives(s: &[f64], t: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let n = s.len();
    (0..n)
        .map(|k| {
            let j0 = k.saturating_sub(2).min(n - 5);
            let nodes = &s[j0..j0 + 5];
            let x = s[k];
            let mut out = [0.0; 3];
            for i in 0..5 {
                // ℓ_i'(x) = Σ_{m≠i} 1/(x_i − x_m) Π_{l≠i,m} (x − x_l)/(x_i − x_l).
                let mut w = 0.0;
                for m in (0..5).filter(|&m| m != i) {
                    let mut prod = 1.0 / (nodes[i] - nodes[m]);
                    for l in (0..5).filter(|&l| l != i && l != m) {
                        prod *= (x - nodes[l]) / (nodes[i] - nodes[l]);
                    }
                    w += prod;
                }
                for c in 0..3 {
                    out[c] += w * t[j0 + i][c];
                }
            }
            out
        })
        .collect()
}

/// Position and derivative d/ds at u ∈ [0, 1] of the quintic Hermite on an
/// interval of length h with end (position, tangent, second derivative).
fn quintic_hermite(u: f64, h: f64, a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> ([f64; 3], [f64; 3]) {
    let (u2, u3, u4, u5) = (u * u, u * u * u, u * u * u * u, u * u * u * u * u);
    let v = [
        1.0 - 10.0 * u3 + 15.0 * u4 - 6.0 * u5,
        u - 6.0 * u3 + 8.0 * u4 - 3.0 * u5,
        0.5 * u2 - 1.5 * u3 + 1.5 * u4 - 0.5 * u5,
        10.0 * u3 - 15.0 * u4 + 6.0 * u5,
        -4.0 * u3 + 7.0 * u4 - 3.0 * u5,
        0.5 * u3 - u4 + 0.5 * u5,
    ];
    let d = [
        -30.0 * u2 + 60.0 * u3 - 30.0 * u4,
        1.0 - 18.0 * u2 + 32.0 * u3 - 15.0 * u4,
        u - 4.5 * u2 + 6.0 * u3 - 2.5 * u4,
        30.0 * u2 - 60.0 * u3 + 30.0 * u4,
        -12.0 * u2 + 28.0 * u3 - 15.0 * u4,
        1.5 * u2 - 4.0 * u3 + 2.5 * u4,
    ];
    let (mut p, mut dp) = ([0.0; 3], [0.0; 3]);
    for c in 0..3 {
        let coef = [a[0][c], h * a[1][c], h * h * a[2][c], b[0][c], h * b[1][c], h * h * b[2][c]];
        for i in 0..6 {
            p[c] += v[i] * coef[i];
            dp[c] += d[i] * coef[i] / h;
        }
    }
    (p, dp)
}

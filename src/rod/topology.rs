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
//!   fixed order, or to a tolerance) on the C¹ cubic Hermite centreline
//!   through every node and stage point with tangents d3 (O(h⁴)).

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
        let h = self.element_length();
        let tab = self.tableau();
        let u3 = |y: &[f64]| {
            let (u, _) = strains::<f64>(&data, &[y[10], y[11], y[12]], &[y[7], y[8], y[9]]);
            u[2]
        };
        let mut total = 0.0;
        for i in 0..self.elements {
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
        writhe(&self.centerline(x)?, order)
    }

    /// Wr of the centreline closed by rays along the end tangents (turns)
    /// to about `tol`, with an error estimate ([`writhe_within`]).
    pub fn writhe_within(&self, x: &[f64], tol: f64) -> Result<WritheEstimate> {
        writhe_within(&self.centerline(x)?, tol)
    }

    /// The C¹ cubic Hermite centreline through every node and stage point
    /// with tangents d3.
    fn centerline(&self, x: &[f64]) -> Result<HermiteCurve> {
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
        HermiteCurve::new(s, r, t, false)
    }
}

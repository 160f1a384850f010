//! The discrete base-pair model (physics.md §3.3): point charges q_i at
//! arc lengths s_i along the centreline, pairwise Φ(d) = e^{−κd}/d over
//! i < j with |s_i − s_j| > a (the same exclusion as the continuum), in
//! units of 1/(4πε0εr). All pairs: the thesis's comparison, O(N²).

use super::{Centerline, LineCharge, Screening};
use crate::error::{self, Result};

/// Charges at the midpoints s_i = (i + ½)·b of a spacing b (the number of
/// base pairs N = round(L/b), b adjusted to L/N), q_i = λ(s_i)·b: the
/// midpoint Riemann sum of the continuum integral.
pub fn base_pairs(curve: &dyn Centerline, charge: &LineCharge, spacing: f64) -> Result<(Vec<[f64; 3]>, Vec<f64>, Vec<f64>)> {
    error::positive("spacing", spacing)?;
    let l = curve.length();
    let n = ((l / spacing).round() as usize).max(1);
    error::count_in_range("base pairs", n as i64, 1, 10_000_000)?;
    let b = l / n as f64;
    let s: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5) * b).collect();
    let r = s.iter().map(|&si| curve.eval(si).0).collect();
    let q = s.iter().map(|&si| charge.at(si).0 * b).collect();
    Ok((r, q, s))
}

/// ½ Σ_{i≠j, |s_i − s_j| > a} q_i q_j Φ(|r_i − r_j|) (arc-length distance
/// periodic on a closed curve of length `period`).
pub fn energy(r: &[[f64; 3]], q: &[f64], s: &[f64], screening: &Screening, period: Option<f64>) -> f64 {
    let mut e = 0.0;
    for i in 0..r.len() {
        let mut row = 0.0;
        for j in i + 1..r.len() {
            let mut ds = (s[j] - s[i]).abs();
            if let Some(p) = period {
                ds = ds.min(p - ds);
            }
            if ds <= screening.a {
                continue;
            }
            let d = ((r[i][0] - r[j][0]).powi(2) + (r[i][1] - r[j][1]).powi(2) + (r[i][2] - r[j][2]).powi(2)).sqrt();
            row += q[j] * (-screening.kappa * d).exp() / d;
        }
        e += q[i] * row;
    }
    e
}

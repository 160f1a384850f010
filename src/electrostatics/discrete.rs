//! The discrete base-pair model (physics.md §3.3): point charges q_i at
//! arc lengths s_i along the centreline, pairwise Φ(d) = e^{−κd}/d over
//! i < j with |s_i − s_j| > a (the same exclusion as the continuum), in
//! units of 1/(4πε0εr). All pairs: the thesis's comparison, O(N²).

use super::{Centerline, LineCharge, Screening};
use crate::error::{self, Result};
use crate::geometry::proximity::CellList;
use crate::geometry::vec3::distance;

/// The number of base pairs of a rod of length `length` at the requested
/// `spacing`: N = round(L/b), at least one (the spacing is then adjusted to
/// L/N).
pub fn base_pair_count(length: f64, spacing: f64) -> usize {
    ((length / spacing).round() as usize).max(1)
}

/// Point charges along a centreline: positions r_i, charges q_i and arc
/// lengths s_i.
pub type PointCharges = (Vec<[f64; 3]>, Vec<f64>, Vec<f64>);

/// Charges at the midpoints s_i = (i + ½)·b of a spacing b (the number of
/// base pairs N = round(L/b), b adjusted to L/N), q_i = λ(s_i)·b: the
/// midpoint Riemann sum of the continuum integral.
pub fn base_pairs(curve: &dyn Centerline, charge: &LineCharge, spacing: f64) -> Result<PointCharges> {
    error::positive("spacing", spacing)?;
    let l = curve.length();
    let n = base_pair_count(l, spacing);
    error::count_in_range("base pairs", n as i64, 1, 10_000_000)?;
    let b = l / n as f64;
    let s: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5) * b).collect();
    let r = s.iter().map(|&si| curve.eval(si).0).collect();
    let q = s.iter().map(|&si| charge.at(si).0 * b).collect();
    Ok((r, q, s))
}

/// The pair sums' data: charges q_i at r_i, arc lengths s_i (periodic with
/// `period` on a closed curve).
struct Pairs<'a> {
    r: &'a [[f64; 3]],
    q: &'a [f64],
    s: &'a [f64],
    screening: &'a Screening,
    period: Option<f64>,
}

impl Pairs<'_> {
    /// q_j Φ(|r_i − r_j|), or None for a pair within the excluded arc
    /// length |s_i − s_j| ≤ a (the same exclusion as the continuum's).
    #[inline]
    fn term(&self, i: usize, j: usize) -> Option<f64> {
        let mut ds = (self.s[j] - self.s[i]).abs();
        if let Some(p) = self.period {
            ds = ds.min(p - ds);
        }
        if ds <= self.screening.a {
            return None;
        }
        let d = distance(&self.r[i], &self.r[j]);
        Some(self.q[j] * (-self.screening.kappa * d).exp() / d)
    }
}

/// ½ Σ_{i≠j, |s_i − s_j| > a} q_i q_j Φ(|r_i − r_j|) (arc-length distance
/// periodic on a closed curve of length `period`).
pub fn energy(r: &[[f64; 3]], q: &[f64], s: &[f64], screening: &Screening, period: Option<f64>) -> f64 {
    let pairs = Pairs { r, q, s, screening, period };
    let mut e = 0.0;
    for i in 0..r.len() {
        let mut row = 0.0;
        for j in i + 1..r.len() {
            if let Some(t) = pairs.term(i, j) {
                row += t;
            }
        }
        e += q[i] * row;
    }
    e
}

/// The screening cutoff for a relative energy tolerance: the distance r_c
/// with E1(κ r_c) = tol·E1(κ a), i.e. the pairs of a straight line beyond
/// r_c carry the fraction tol of its energy per length (the defined
/// estimator; compact shapes have fewer far pairs, so it errs on the safe
/// side — checked against the true error in tests). None for Coulomb
/// (κ = 0: no cutoff is accurate) and when no r_c below `max` meets it.
pub fn screening_cutoff(kappa: f64, a: f64, tolerance: f64, max: f64) -> Option<f64> {
    // κa > 0, not only κ > 0: a denormal κ times a underflows to 0, where
    // E1 is infinite (it used to panic here); a screening that weak is
    // Coulomb for any length this library can integrate.
    if !(kappa * a > 0.0 && tolerance > 0.0 && tolerance < 1.0 && max.is_finite()) {
        return None;
    }
    let target = tolerance * super::special::e1(kappa * a);
    // E1(x) < e^{−x}/x underflows beyond x ≈ 700 (and κr may overflow).
    let tail = |r: f64| if kappa * r > 700.0 { 0.0 } else { super::special::e1(kappa * r) };
    if tail(max) > target {
        return None;
    }
    let (mut lo, mut hi) = (a, max);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if tail(mid) > target {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-12 * hi {
            break;
        }
    }
    Some(hi)
}

/// [`energy`] with the pairs beyond the cutoff `rc` dropped, neighbours
/// found with a cell list: O(N) for a rod of bounded density. `threads`
/// (≥ 1) splits the points into fixed chunks; each point's row sum is
/// formed in ascending j, the rows are added in index order, so the result
/// is bitwise identical for any thread count. Returns (energy, pairs
/// evaluated).
pub fn energy_cutoff(
    r: &[[f64; 3]],
    q: &[f64],
    s: &[f64],
    screening: &Screening,
    rc: f64,
    period: Option<f64>,
    threads: usize,
) -> (f64, usize) {
    let cells = CellList::new(r, rc);
    let n = r.len();
    let pairs = Pairs { r, q, s, screening, period };
    let rows = |range: std::ops::Range<usize>| -> Vec<(f64, usize)> {
        let mut nb = Vec::new();
        range
            .map(|i| {
                cells.neighbours_after(r, i, rc, &mut nb);
                let mut row = 0.0;
                let mut count = 0;
                for &j in &nb {
                    if let Some(t) = pairs.term(i, j) {
                        row += t;
                        count += 1;
                    }
                }
                (q[i] * row, count)
            })
            .collect()
    };
    let threads = threads.clamp(1, 64);
    let per_point: Vec<(f64, usize)> = if threads == 1 || n < 2 * threads {
        rows(0..n)
    } else {
        let chunk = n.div_ceil(threads);
        std::thread::scope(|scope| {
            let handles: Vec<_> = (0..threads)
                .map(|t| {
                    let range = (t * chunk).min(n)..((t + 1) * chunk).min(n);
                    scope.spawn(move || rows(range))
                })
                .collect();
            handles.into_iter().flat_map(|h| h.join().expect("a worker panicked")).collect()
        })
    };
    per_point.iter().fold((0.0, 0), |(e, p), &(v, k)| (e + v, p + k))
}

#[cfg(test)]
mod tests {
    use super::base_pair_count;

    /// Reference: N = round(L/b) by hand — 1 kbp of DNA at 0.34 nm per base
    /// pair, 1 nm (2.94 → 3), and a rod shorter than half a spacing (one
    /// charge, not none).
    #[test]
    fn base_pair_count_rounds_and_keeps_one() {
        assert_eq!(base_pair_count(340.0, 0.34), 1000);
        assert_eq!(base_pair_count(1.0, 0.34), 3);
        assert_eq!(base_pair_count(0.1, 0.34), 1);
    }
}

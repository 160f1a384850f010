//! Graded meshes for rod branches: elements placed where a branch's
//! solutions vary fast, as AUTO-07p's mesh adaption places its
//! collocation intervals (Doedel et al., AUTO-07p manual §"mesh
//! adaption"; Russell & Christiansen, SIAM J. Numer. Anal. 15 (1978)):
//! equidistribute a monitor built from the solution's highest resolved
//! derivative.
//!
//! The monitor of element i is ω_i = max over the given states and the 13
//! components (each over its state scale) of |y^(p)|^(1/p), y^(p) from the
//! top divided difference of the element's own profile points (its two
//! nodes and s Gauss stages: p = s + 1; the implicit midpoint borrows a
//! neighbour's node, p = 2). The scheme's local error on element i grows
//! like (h_i ω_i)^order, so a mesh with h_i ω_i equal everywhere spends
//! its elements where they are needed; for a solution whose derivatives
//! scale alike (y^(p) ~ k^p y) the exponent 1/p makes ω the local rate k
//! whatever p is. ω is floored at 1/16 of its largest value, so no element
//! grows more than ~16× the finest.
//!
//! A graded rod's elements share one recorded tape with h as an input
//! (`Slot::Param`), so they are still evaluated four at a time.

use super::model::Rod;
use super::scheme::Scheme;

/// The monitor's floor relative to its largest value.
const FLOOR: f64 = 1.0 / 16.0;

/// ω_i per element of `rod` (1/length): see the module notes. All zero
/// where every state is a polynomial of degree < p in s (the straight rod).
pub fn density(rod: &Rod, states: &[&[f64]]) -> Vec<f64> {
    let profile = rod.profile_offsets();
    let stages = rod.scheme.stages();
    let per = stages + 1; // profile points per element before the next node
    let scales = rod.state_scales();
    let (n, midpoint) = (rod.elements, rod.scheme == Scheme::Midpoint);
    let mut omega = vec![0.0f64; n];
    for (i, w) in omega.iter_mut().enumerate() {
        // The element's points; the midpoint takes a neighbour's node.
        let (lo, hi) = if midpoint && n > 1 {
            if i + 2 <= n {
                (i, i + 2)
            } else {
                (i - 1, i + 1)
            }
        } else {
            (i * per, i * per + per)
        };
        let pts = &profile[lo..=hi];
        let p = pts.len() - 1;
        // Top divided difference weights: Σ_j y_j / Π_{m≠j}(s_j − s_m).
        let weights: Vec<f64> =
            (0..=p).map(|j| 1.0 / (0..=p).filter(|&m| m != j).map(|m| pts[j].0 - pts[m].0).product::<f64>()).collect();
        let factorial: f64 = (1..=p).map(|k| k as f64).product();
        let span = pts[p].0 - pts[0].0;
        for x in states {
            for (c, scale) in scales.iter().enumerate() {
                let dd: f64 = pts.iter().zip(&weights).map(|(&(_, o), w)| w * x[o + c]).sum();
                // (h ω)^p: the component's p-th order change over the
                // element; below 1e-12 it is rounding, not variation.
                let change = factorial * dd.abs() / scale * span.powi(p as i32);
                if change.is_finite() && change > 1e-12 {
                    *w = w.max(change.powf(1.0 / p as f64) / span);
                }
            }
        }
    }
    let peak = omega.iter().copied().fold(0.0, f64::max);
    omega.iter_mut().for_each(|w| *w = w.max(FLOOR * peak));
    omega
}

/// Θ = Σ ω_i h_i and max_i ω_i h_i of `rod`'s elements: a mesh that
/// equidistributes ω on N′ elements has ω h = Θ/N′ on each, the current
/// one's worst element max ω h.
pub fn resolution(rod: &Rod, omega: &[f64]) -> (f64, f64) {
    omega.iter().enumerate().fold((0.0, 0.0), |(sum, peak), (i, w)| {
        let wh = w * rod.element_h(i);
        (sum + wh, f64::max(peak, wh))
    })
}

/// Breakpoints (fractions of the length, 0 … 1) of `elements` elements
/// equidistributing ω (piecewise constant on `rod`'s elements). A zero ω
/// gives the uniform mesh.
pub fn equidistribute(rod: &Rod, omega: &[f64], elements: usize) -> Vec<f64> {
    let t: Vec<f64> = rod.node_positions().iter().map(|s| s / rod.length).collect();
    equidistribute_pieces(&t, omega, elements)
}

/// Breakpoints from t[0] to t[M] of `elements` elements equidistributing
/// ω (ω[i] on [t[i], t[i+1]]).
fn equidistribute_pieces(t: &[f64], omega: &[f64], elements: usize) -> Vec<f64> {
    let n = omega.len();
    let (start, end) = (t[0], t[n]);
    let mut theta = vec![0.0; n + 1];
    for i in 0..n {
        theta[i + 1] = theta[i] + omega[i] * (t[i + 1] - t[i]);
    }
    let total = theta[n];
    let elements = elements.max(1);
    if !(total > 0.0) {
        return (0..=elements).map(|k| start + (end - start) * k as f64 / elements as f64).collect();
    }
    // Θ^{-1}(k Θ/N′), Θ linear on each piece.
    let mut equal = Vec::with_capacity(elements + 1);
    let mut i = 0;
    for k in 0..=elements {
        let target = total * k as f64 / elements as f64;
        while i + 1 < n && theta[i + 1] < target {
            i += 1;
        }
        let u = if omega[i] > 0.0 { (target - theta[i]) / omega[i] } else { 0.0 };
        equal.push((t[i] + u).clamp(t[i], t[i + 1]));
    }
    equal[elements] = end;
    equal
}

/// ω mirrored about the rod's middle, max(ω(t), ω(1 − t)), on the pieces
/// of [0, 1/2] cut by the nodes and their mirror images.
fn mirrored(rod: &Rod, omega: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let t: Vec<f64> = rod.node_positions().iter().map(|s| s / rod.length).collect();
    let mut cuts: Vec<f64> = t.iter().flat_map(|&v| [v, 1.0 - v]).filter(|&v| v < 0.5).collect();
    cuts.push(0.5);
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() < 1e-14);
    let at = |v: f64| omega[t.partition_point(|&x| x <= v).clamp(1, omega.len()) - 1];
    let w = cuts
        .windows(2)
        .map(|c| {
            let m = 0.5 * (c[0] + c[1]);
            at(m).max(at(1.0 - m))
        })
        .collect();
    (cuts, w)
}

/// Whether the rod is held at both ends (clamps, a twist or torque clamp,
/// a pin): its continuum problem is then symmetric under s → L − s, and
/// a mesh that is not breaks the symmetry a twisted straight rod's double
/// points rest on (det's pair of modes no longer meets zero together —
/// the branch misses the point by the mesh error). Such rods are graded
/// symmetrically.
fn held_at_both_ends(rod: &Rod) -> bool {
    !matches!(rod.supports, super::model::Supports::Cantilever)
}

/// A graded mesh for `rod`'s solutions `states` whose worst element's
/// ω h is `factor` times smaller than `rod`'s (factor > 1: the resolution
/// asked of the next mesh): ω equidistributed on Θ/(max ω h / factor)
/// elements (made even, at least 4). Never more elements than `rod`'s
/// count × factor (Θ ≤ N max ω h), fewer where ω varies, but not fewer
/// than half that (an under-resolved monitor). A rod held at
/// both ends gets a mesh symmetric about its middle (ω mirrored, the
/// breakpoints of one half reflected). None where ω vanishes
/// (nothing to grade); Err(count) where more than `most` elements would
/// be needed.
pub fn graded_mesh(rod: &Rod, states: &[&[f64]], factor: f64, most: usize) -> Option<Result<Rod, usize>> {
    let omega = density(rod, states);
    let (_, peak) = resolution(rod, &omega);
    let symmetric = held_at_both_ends(rod);
    let (cuts, w) = if symmetric {
        mirrored(rod, &omega)
    } else {
        (rod.node_positions().iter().map(|s| s / rod.length).collect(), omega.clone())
    };
    let theta: f64 = (symmetric as u8 + 1) as f64
        * rod.length
        * w.iter().zip(cuts.windows(2)).map(|(w, c)| w * (c[1] - c[0])).sum::<f64>();
    if !(peak > 0.0 && theta.is_finite()) {
        return None;
    }
    // At least half the uniform refinement's count: a monitor taken on a
    // mesh that does not resolve the solution (divided differences of an
    // under-resolved state) can pile ω into a few elements and ask for far
    // too few — a wasted try (measured: a follower cantilever at α = 1000
    // from 8 elements asked for 16 where 130 were needed).
    let wanted = (theta / peak).max(0.5 * rod.elements as f64) * factor;
    let elements = ((wanted * (1.0 - 1e-12)).ceil() as usize).max(4).div_ceil(2) * 2;
    if elements > most {
        return Some(Err(elements));
    }
    let t = if symmetric {
        let half = equidistribute_pieces(&cuts, &w, elements / 2);
        let mut t = half.clone();
        t.extend(half.iter().rev().skip(1).map(|v| 1.0 - v));
        t
    } else {
        equidistribute_pieces(&cuts, &w, elements)
    };
    Some(rod.clone().graded(&t).map_err(|_| elements))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rod::model::Supports;
    use crate::rod::{Loads, RodLaw};

    fn rod(scheme: Scheme, n: usize) -> Rod {
        let law = RodLaw::isotropic(1.0, 1.0, 1e4, 1e4).unwrap();
        Rod::new(law, 1.0, Loads::default(), Supports::Cantilever, scheme, n).unwrap()
    }

    /// A state whose x-coordinate is e^{k s} at every profile point (all
    /// other components 0): its p-th derivative is k^p e^{ks}, so the
    /// monitor is k e^{ks/p} to the divided difference's O(h) accuracy
    /// (closed form).
    #[test]
    fn density_is_the_local_rate() {
        for scheme in [Scheme::Gauss(2), Scheme::Gauss(4), Scheme::Midpoint] {
            let r = rod(scheme, 40);
            let k = 3.0;
            let mut x = vec![0.0; r.unknowns()];
            for (s, o) in r.profile_offsets() {
                x[o] = (k * s).exp();
            }
            let omega = density(&r, &[&x]);
            let p = if scheme == Scheme::Midpoint { 2.0 } else { scheme.stages() as f64 + 1.0 };
            for (i, w) in omega.iter().enumerate() {
                let mid = r.node_position(i) + 0.5 * r.element_h(i);
                let expect = k * (k * mid / p).exp();
                assert!((w - expect).abs() < 0.1 * expect, "{scheme:?} element {i}: {w} vs {expect}");
            }
        }
    }

    /// Equidistribution of a step density (ω = 4 on the first fifth, 1
    /// elsewhere: half of Θ on each side of s = 1/5) puts half the
    /// elements on the first fifth, each 1/4 the length of the others; on
    /// that mesh ω h is equal everywhere.
    #[test]
    fn equidistribution_follows_a_step() {
        let r = rod(Scheme::Gauss(2), 10);
        let omega = [4.0, 4.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0];
        let t = equidistribute(&r, &omega, 16);
        assert_eq!(t.len(), 17);
        for k in 0..16 {
            let expect = if k < 8 { 0.2 / 8.0 } else { 0.8 / 8.0 };
            assert!((t[k + 1] - t[k] - expect).abs() < 1e-14, "element {k}: {}", t[k + 1] - t[k]);
        }
        let graded = r.clone().graded(&t).unwrap();
        let fine: Vec<f64> = (0..16).map(|k| if k < 8 { 4.0 } else { 1.0 }).collect();
        let (theta, peak) = resolution(&graded, &fine);
        assert!((theta - 1.6).abs() < 1e-14 && (peak - 0.1).abs() < 1e-14, "{theta} {peak}");
    }

    /// A uniform rod's solution graded: the new count is the uniform one
    /// (N × factor) where ω is constant, fewer where it varies — here
    /// e^{ks} with k = 3 on 20 elements: Θ/max ω h = (1 − e^{−k/p})/(k/p)·N
    /// with p = 3 (Gauss(2)), the closed form of ∫ω over its peak.
    #[test]
    fn graded_counts_follow_the_monitor() {
        let r = rod(Scheme::Gauss(2), 20);
        let k: f64 = 3.0;
        let mut x = vec![0.0; r.unknowns()];
        for (s, o) in r.profile_offsets() {
            x[o] = (k * s).exp();
        }
        let g = graded_mesh(&r, &[&x], 2.0, 1024).unwrap().unwrap();
        let expect = (1.0 - (-k / 3.0).exp()) / (k / 3.0) * 20.0 * 2.0;
        assert!((g.elements as f64 - expect).abs() <= 3.0, "{} vs {expect}", g.elements);
        // Finer where the solution varies fast (s = 1).
        assert!(g.element_h(g.elements - 1) < 0.6 * g.element_h(0));
        // Too many refused with the count.
        assert!(matches!(graded_mesh(&r, &[&x], 2.0, 8), Some(Err(n)) if n > 8));
        // Nothing to grade on the straight state.
        assert!(graded_mesh(&r, &[&r.straight_state()], 2.0, 1024).is_none());
    }

    /// A rod held at both ends is graded symmetrically about its middle
    /// (t_{N−k} = 1 − t_k to rounding) even where its solution is not (e^{ks}),
    /// finer at both ends alike; the count is the mirrored ω's.
    #[test]
    fn a_rod_held_at_both_ends_is_graded_symmetrically() {
        let law = RodLaw::kirchhoff(1.0, 1.0, 1.0).unwrap();
        let r = Rod::new(law, 1.0, Loads::default(), Supports::Torqued { tension: 0.0 }, Scheme::Gauss(2), 20).unwrap();
        let mut x = vec![0.0; r.unknowns()];
        for (s, o) in r.profile_offsets() {
            x[o] = (3.0 * s).exp();
        }
        let g = graded_mesh(&r, &[&x], 2.0, 1024).unwrap().unwrap();
        let t = g.breakpoints.as_ref().unwrap();
        let n = g.elements;
        for k in 0..=n {
            assert!((t[n - k] - (1.0 - t[k])).abs() <= 1.2e-16, "breakpoint {k}");
        }
        assert!(g.element_h(0) < 0.9 * g.element_h(n / 2 - 1));
        // Mirrored ω: 2∫_{1/2}^1 e^{s} ds / (e^{1} · h) × factor elements (p = 3).
        let expect = 2.0 * (1.0 - (-0.5f64).exp()) * 20.0 * 2.0;
        assert!((n as f64 - expect).abs() <= 3.0, "{n} vs {expect}");
    }
}

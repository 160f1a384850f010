//! Padé approximants of the ANM series with a common scalar denominator
//! (Cochelin, Damil & Potier-Ferry 1994; Najah et al. 1998): a rational
//! representation of the same step that stays accurate further than the
//! truncated polynomial, so a step can be longer for the same ε.
//!
//! With U(a) = U0 + Σ_{p=1..P} a^p U_p, orthonormalise U_1, …, U_{P−1} in
//! ⟨·,·⟩_W (Gram–Schmidt, U_i = Σ_{j≤i} α_ij U*_j). The denominator
//! D(a) = Σ_{i=0..P−1} d_i a^i (d_0 = 1) is chosen so that the order-P
//! term of D(a)(U(a) − U0), Σ_i d_i U_{P−i}, has no component along
//! U*_1 … U*_{P−1}: for j = P−1 down to 1,
//!   d_{P−j} = −(Σ_{i=0..P−j−1} d_i α_{P−i, j}) / α_{jj}
//! (derived here from that condition; j = P−1 gives the classical
//! d_1 = −α_{P,P−1}/α_{P−1,P−1}). The approximant is then
//!   U_Padé(a) = U0 + Σ_{p=1..P−1} a^p U_p · D_{P−1−p}(a) / D_{P−1}(a),
//! D_k the truncation of D to degree k; it agrees with the series to
//! O(a^P). The step: the largest a (up to a few times the series' own
//! step) where the Padé approximants built from P and from P − 1 terms
//! differ by at most ε relative to U_Padé(a) − U0, before any pole.

use super::Scaling;
use crate::linalg::dense::dot4;

/// The highest series order the engines accept.
pub(crate) const MAX_ORDER: usize = 60;

/// The curve of one ANM step: the truncated series or its Padé form.
pub(crate) enum Curve<'a> {
    Series(&'a [Vec<f64>]),
    /// The series and the denominator d_0 … d_{P−1} (d_0 = 1).
    Pade(&'a [Vec<f64>], &'a [f64]),
}

/// Weights w_p(t) (and dw_p/dt) with U(t) = Σ_p w_p(t) U_p (w_0 = 1),
/// for the series (w_p = t^p) or the Padé form of denominator `d`
/// (w_p = t^p D_{P'−1−p}(t)/D_{P'−1}(t), P' = d.len(), p < P').
/// The derivatives only when asked for (Λ(t) alone is wanted at each of a
/// root search's points, the weights alone at each candidate step).
fn pade_weights(d: &[f64], t: f64, w: &mut [f64], mut dw: Option<&mut [f64]>) {
    let m = d.len(); // P′: uses U_1 … U_{P′−1}
                     // D_k(t) = Σ_{i≤k} d_i t^i and D_k′(t) = Σ_{1≤i≤k} i d_i t^{i−1}, k < m
                     // (on the stack: the engine's orders are at most MAX_ORDER).
    let mut dk = [0.0; MAX_ORDER + 1];
    let mut dk_prime = [0.0; MAX_ORDER + 1];
    let (mut s, mut sp, mut tp, mut tpm) = (0.0, 0.0, 1.0, 0.0);
    for i in 0..m {
        s += d[i] * tp;
        sp += i as f64 * d[i] * tpm;
        dk[i] = s;
        dk_prime[i] = sp;
        tpm = tp;
        tp *= t;
    }
    let (den, den_p) = (dk[m - 1], dk_prime[m - 1]);
    w.iter_mut().for_each(|v| *v = 0.0);
    if let Some(dw) = dw.as_deref_mut() {
        dw.iter_mut().for_each(|v| *v = 0.0);
    }
    w[0] = 1.0;
    let mut tpm = 1.0; // t^{p−1}
    for p in 1..m {
        let (num, num_p) = (dk[m - 1 - p], dk_prime[m - 1 - p]);
        let tp = tpm * t; // t^p
        let f = num / den;
        w[p] = tp * f;
        if let Some(dw) = dw.as_deref_mut() {
            let f_p = (num_p * den - num * den_p) / (den * den);
            dw[p] = p as f64 * tpm * f + tp * f_p;
        }
        tpm = tp;
    }
}

impl Curve<'_> {
    fn series(&self) -> &[Vec<f64>] {
        match self {
            Curve::Series(s) | Curve::Pade(s, _) => s,
        }
    }

    /// Weights of the coefficients at t.
    pub(crate) fn weights(&self, t: f64, w: &mut [f64], dw: &mut [f64]) {
        match self {
            Curve::Series(_) => {
                let (mut tp, mut tpm) = (1.0, 0.0);
                for p in 0..w.len() {
                    w[p] = tp;
                    dw[p] = p as f64 * tpm;
                    tpm = tp;
                    tp *= t;
                }
            }
            Curve::Pade(_, d) => pade_weights(d, t, w, Some(dw)),
        }
    }

    /// Λ at t.
    pub(crate) fn lambda(&self, t: f64) -> f64 {
        let s = self.series();
        let n = s[0].len() - 1;
        match self {
            Curve::Series(_) => s.iter().rev().fold(0.0, |acc, c| acc * t + c[n]),
            Curve::Pade(_, d) => {
                let mut w = [0.0; MAX_ORDER + 1];
                pade_weights(d, t, &mut w[..s.len()], None);
                s.iter().zip(&w).map(|(c, w)| w * c[n]).sum()
            }
        }
    }

    /// X(t) into `x` (n entries) and dX/dt into `d` (n + 1 entries, Λ last).
    pub(crate) fn evaluate(&self, t: f64, x: &mut [f64], d: Option<&mut [f64]>) {
        let s = self.series();
        let (mut w, mut dw) = ([0.0; MAX_ORDER + 1], [0.0; MAX_ORDER + 1]);
        self.weights(t, &mut w[..s.len()], &mut dw[..s.len()]);
        let n = x.len();
        x.iter_mut().for_each(|v| *v = 0.0);
        for (c, &wp) in s.iter().zip(&w) {
            if wp != 0.0 {
                for i in 0..n {
                    x[i] += wp * c[i];
                }
            }
        }
        if let Some(d) = d {
            d.iter_mut().for_each(|v| *v = 0.0);
            for (c, &dp) in s.iter().zip(&dw) {
                if dp != 0.0 {
                    for i in 0..=n {
                        d[i] += dp * c[i];
                    }
                }
            }
        }
    }
}

/// The W-coordinates of the series terms U_1 … U_m by modified
/// Gram–Schmidt: U_i = Σ_{j≤i} α_ij U*_j with U*_1 … U*_{m−1}
/// ⟨·,·⟩_W-orthonormal and U*_m the direction of U_m's remainder (α_mm its
/// norm, possibly 0). Every combination of the terms then has its W-norm
/// as the Euclidean norm of its coordinates, so the Padé step's scan runs
/// in O(m²) a point where the vectors themselves would cost O(m n).
struct Coordinates {
    m: usize,
    /// α_ij at i (m + 1) + j, rows 1 … m.
    alpha: Vec<f64>,
}

impl Coordinates {
    /// None when a term vanishes or is not finite, or when U_i (i < m) is
    /// within 1e-10 of the span of the terms before it (a series with
    /// vanishing terms: the polynomial is then the better form).
    fn of(series: &[Vec<f64>], m: usize, scaling: &Scaling) -> Option<Self> {
        if m < 2 || m > series.len() - 1 {
            return None;
        }
        let n = series[0].len() - 1;
        // ⟨a, b⟩_W = Σ a_i b_i ω_i: Gram–Schmidt runs on the terms scaled by
        // √ω_i, where it is the plain dot product.
        debug_assert_eq!(scaling.x.len(), n, "one scale per unknown");
        let nx = n.max(1) as f64;
        let root_omega: Vec<f64> = scaling
            .x
            .iter()
            .map(|s| 1.0 / (s.abs() * nx.sqrt()))
            .chain(std::iter::once(1.0 / scaling.lambda.abs()))
            .collect();
        let w = m + 1;
        let mut alpha = vec![0.0; w * w];
        let mut basis: Vec<f64> = Vec::with_capacity((m - 1) * (n + 1));
        let mut v = vec![0.0; n + 1];
        for i in 1..=m {
            v.iter_mut().zip(&series[i]).zip(&root_omega).for_each(|((v, u), r)| *v = u * r);
            let norm0 = dot4(&v, &v).sqrt();
            if !(norm0.is_finite() && norm0 > 0.0) {
                return None;
            }
            for (j, b) in basis.chunks_exact(n + 1).enumerate() {
                let c = dot4(&v, b);
                alpha[i * w + j + 1] = c;
                v.iter_mut().zip(b).for_each(|(vi, bi)| *vi -= c * bi);
            }
            let r = dot4(&v, &v).sqrt();
            alpha[i * w + i] = r;
            if i < m {
                if !(r > 1e-10 * norm0) {
                    return None;
                }
                basis.extend(v.iter().map(|a| a / r));
            }
        }
        Some(Coordinates { m, alpha })
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.alpha[i * (self.m + 1) + j]
    }

    /// The denominator d_0 … d_{k−1} of the Padé form built from U_1 … U_k
    /// (2 ≤ k ≤ m; Gram–Schmidt is sequential, so the first k − 1
    /// directions are those of U_1 … U_{k−1} alone).
    fn denominator(&self, k: usize) -> Option<Vec<f64>> {
        let mut d = vec![0.0; k];
        d[0] = 1.0;
        for j in (1..k).rev() {
            let q = k - j;
            let s: f64 = (0..q).map(|i| d[i] * self.at(k - i, j)).sum();
            d[q] = -s / self.at(j, j);
        }
        d.iter().all(|v| v.is_finite()).then_some(d)
    }

    /// ‖Σ_q c_q U_q‖_W from the coordinates (c_0 ignored).
    fn norm(&self, c: &[f64]) -> f64 {
        let mut s = 0.0;
        for j in 1..=self.m {
            let cj: f64 = (j..=self.m).map(|q| c[q] * self.at(q, j)).sum();
            s += cj * cj;
        }
        s.sqrt()
    }
}

/// ‖Σ_q c_q U_q‖_W computed on the vectors themselves (c_0 ignored): the
/// check of a step chosen on the coordinates.
fn direct_norm(series: &[Vec<f64>], c: &[f64], scaling: &Scaling, work: &mut [f64]) -> f64 {
    let n = work.len() - 1;
    work.iter_mut().for_each(|v| *v = 0.0);
    for (u, &cq) in series.iter().zip(c).skip(1) {
        if cq != 0.0 {
            work.iter_mut().zip(u).for_each(|(w, a)| *w += cq * a);
        }
    }
    scaling.norm(&work[..n], work[n])
}

/// Grid points of the Padé step's scan, and of its scan for poles per
/// series step in its range.
const STEP_GRID: usize = 48;
const POLE_POINTS: usize = 32;

/// The Padé step: the largest t in [a_series, cap] on a geometric grid
/// where the approximants from P and P − 1 terms differ by at most ε
/// relative to U(t) − U0, with no pole of either denominator up to t.
/// Returns the step and the denominator to use, or None (keep the series).
pub(crate) fn step(
    series: &[Vec<f64>],
    scaling: &Scaling,
    epsilon: f64,
    a_series: f64,
    cap: f64,
) -> Option<(f64, Vec<f64>)> {
    let p = series.len() - 1;
    let coords = Coordinates::of(series, p, scaling)?;
    let d_hi = coords.denominator(p)?;
    let d_lo = coords.denominator(p - 1)?;
    let poly = |d: &[f64], t: f64| d.iter().rev().fold(0.0, |acc, c| acc * t + c);
    let positive = |t: f64| poly(&d_hi, t) > 0.0 && poly(&d_lo, t) > 0.0;
    // No pole: both denominators keep the sign they have at 0 (= 1) up to
    // t — checked at t and on a uniform scan of [0, top] whose spacing,
    // top/(32⌈top/a_series⌉) ≤ a_series/32, is at most t/32 for every
    // candidate t (the step was first checked at t·i/16, i = 1…16).
    let ratio = (cap / a_series).max(1.0);
    let top = a_series * ratio;
    let points = POLE_POINTS * ratio.ceil().min(1e6) as usize;
    let pole = (1..=points).map(|i| top * i as f64 / points as f64).find(|&s| !positive(s)).unwrap_or(f64::INFINITY);
    let (mut w_hi, mut w_lo) = ([0.0; MAX_ORDER + 1], [0.0; MAX_ORDER + 1]);
    let (mut diff, mut incr) = ([0.0; MAX_ORDER + 1], [0.0; MAX_ORDER + 1]);
    let grid = |k: usize| a_series * ratio.powf(k as f64 / STEP_GRID as f64);
    let mut weights = |t: f64, diff: &mut [f64], incr: &mut [f64]| {
        // The weights alone (Curve::weights' values, without derivatives).
        pade_weights(&d_hi, t, &mut w_hi[..=p], None);
        pade_weights(&d_lo, t, &mut w_lo[..=p], None);
        for q in 0..=p {
            diff[q] = w_hi[q] - w_lo[q];
            incr[q] = w_hi[q];
        }
    };
    let mut best = None;
    for k in 0..=STEP_GRID {
        let t = grid(k);
        if t >= pole || !positive(t) {
            break;
        }
        weights(t, &mut diff, &mut incr);
        if !(coords.norm(&diff[..=p]) <= epsilon * coords.norm(&incr[..=p])) {
            break;
        }
        best = Some(k);
    }
    // The coordinates are exact only as far as Gram–Schmidt kept its basis
    // orthogonal: the step taken is checked on the vectors themselves, and
    // shortened along the grid until it passes.
    let n = series[0].len() - 1;
    let mut work = vec![0.0; n + 1];
    let mut k = best?;
    loop {
        let t = grid(k);
        weights(t, &mut diff, &mut incr);
        let e = direct_norm(series, &diff[..=p], scaling, &mut work);
        let size = direct_norm(series, &incr[..=p], scaling, &mut work);
        if e <= epsilon * size {
            return Some((t, d_hi));
        }
        k = k.checked_sub(1)?;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seven functions 1/(1 − a/ρ_k) (ρ = 1 … 8, the first with its pole
    /// at a = 1) as one vector series of order 8: the common denominator
    /// of degree 7 is Π(1 − a/ρ_k), so the Padé form is exact — beyond the
    /// series' radius, where the truncated series is far off — and its
    /// derivative too.
    #[test]
    fn pade_of_geometric_series_is_exact() {
        let p = 8;
        let rho: [f64; 7] = [1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0];
        let series: Vec<Vec<f64>> = (0..=p)
            .map(|k| {
                let mut v: Vec<f64> = rho.iter().map(|r| r.powi(-(k as i32))).collect();
                v.push(0.0);
                v
            })
            .collect();
        let scaling = Scaling { x: vec![1.0; 7], lambda: 1.0 };
        let d = Coordinates::of(&series, p, &scaling).unwrap().denominator(p).unwrap();
        let curve = Curve::Pade(&series, &d);
        let mut x = [0.0; 7];
        let mut dx = [0.0; 8];
        for &t in &[0.1, 0.5, 0.9] {
            curve.evaluate(t, &mut x, Some(&mut dx));
            for k in 0..7 {
                let exact = 1.0 / (1.0 - t / rho[k]);
                let exact_d = 1.0 / (rho[k] * (1.0 - t / rho[k]).powi(2));
                assert!((x[k] - exact).abs() < 1e-8 * exact, "t {t}, k {k}: {} vs {exact}", x[k]);
                assert!((dx[k] - exact_d).abs() < 1e-6 * exact_d, "t {t}, k {k}: d {} vs {exact_d}", dx[k]);
            }
        }
        // The truncated series at t = 0.9 misses 0.9^9/(1 − 0.9) ≈ 3.9 of the first.
        Curve::Series(&series).evaluate(0.9, &mut x, None);
        assert!((x[0] - 10.0).abs() > 3.0);
    }

    /// The step's scan on Gram–Schmidt coordinates against the same scan on
    /// the vectors (the reference: every candidate's difference and
    /// increment summed from the terms, poles checked at t·i/16, as the
    /// scan was first written; its denominators are the coordinates', equal
    /// to the former separate Gram–Schmidts' up to rounding): the same grid
    /// point, on series without a pole up to the cap and with one inside it
    /// (the step then ends before it), and the coordinates' norms equal the
    /// vectors' to 1e-12.
    #[test]
    fn the_step_on_coordinates_is_the_step_on_vectors() {
        // Reference scan: direct norms at each geometric grid point,
        // poles checked on t·i/16.
        fn reference(series: &[Vec<f64>], scaling: &Scaling, eps: f64, a: f64, cap: f64) -> Option<f64> {
            let p = series.len() - 1;
            let c = Coordinates::of(series, p, scaling)?;
            let (d_hi, d_lo) = (c.denominator(p)?, c.denominator(p - 1)?);
            let (hi, lo) = (Curve::Pade(series, &d_hi), Curve::Pade(series, &d_lo));
            let poly = |d: &[f64], t: f64| d.iter().rev().fold(0.0, |acc, c| acc * t + c);
            let n = series[0].len() - 1;
            let ratio = (cap / a).max(1.0);
            let mut best = None;
            for k in 0..=STEP_GRID {
                let t = a * ratio.powf(k as f64 / STEP_GRID as f64);
                if (1..=16).any(|i| {
                    let s = t * i as f64 / 16.0;
                    poly(&d_hi, s) <= 0.0 || poly(&d_lo, s) <= 0.0
                }) {
                    break;
                }
                let (mut wh, mut wl, mut dw) = (vec![0.0; p + 1], vec![0.0; p + 1], vec![0.0; p + 1]);
                hi.weights(t, &mut wh, &mut dw);
                lo.weights(t, &mut wl, &mut dw);
                let (mut diff, mut incr) = (vec![0.0; n + 1], vec![0.0; n + 1]);
                for q in 1..=p {
                    for i in 0..=n {
                        diff[i] += (wh[q] - wl[q]) * series[q][i];
                        incr[i] += wh[q] * series[q][i];
                    }
                }
                if !(scaling.norm(&diff[..n], diff[n]) <= eps * scaling.norm(&incr[..n], incr[n])) {
                    break;
                }
                best = Some(t);
            }
            best
        }
        // Terms of Σ_k c_k /(1 − a/ρ_k) plus a polynomial part, over more
        // functions than the denominator's degree (so the Padé form is not
        // exact), with unequal scales.
        let series_of = |rho: &[f64], p: usize| -> Vec<Vec<f64>> {
            let n = 40;
            (0..=p)
                .map(|k| {
                    let mut v: Vec<f64> = (0..=n)
                        .map(|i| {
                            let r = rho[i % rho.len()] * (1.0 + 0.01 * i as f64);
                            let poly = if k <= 2 { 0.3 * (i as f64).sin() } else { 0.0 };
                            (1.0 + 0.1 * i as f64) * r.powi(-(k as i32)) + poly
                        })
                        .collect();
                    v[n] *= 0.5;
                    v
                })
                .collect()
        };
        let scaling = Scaling { x: (0..40).map(|i| 1.0 + 0.05 * i as f64).collect(), lambda: 2.0 };
        let (mut longer, mut before_pole) = (0, 0);
        for (rho, a) in [
            (&[1.2, -2.0, 3.5, 5.0][..], 0.2),
            (&[0.8, 1.7, -2.5, 4.0, 9.0][..], 0.1),
            (&[-1.0, 2.0][..], 0.3),
            // Poles at 0.5 … 0.7, inside (a, 4a).
            (&[0.5, -2.0, 3.0][..], 0.2),
        ] {
            // The ANM's reach, and half of it (the grid and the pole scan
            // depend on the cap's ratio).
            for (p, eps, reach) in
                [(8, 1e-6, 4.0), (12, 1e-8, 4.0), (15, 1e-10, 4.0), (15, 1e-6, super::super::anm::PADE_REACH)]
            {
                let series = series_of(rho, p);
                let ours = step(&series, &scaling, eps, a, reach * a).map(|(t, _)| t);
                let theirs = reference(&series, &scaling, eps, a, reach * a);
                assert_eq!(ours, theirs, "ρ {rho:?}, P {p}, ε {eps:e}, reach {reach}");
                longer += ours.is_some_and(|t| t > a) as usize;
                if rho[0] == 0.5 {
                    assert!(ours.is_none_or(|t| t < 0.5), "ρ {rho:?}, P {p}: step {ours:?} past the pole");
                    before_pole += ours.is_some_and(|t| t > a) as usize;
                }
                // The coordinates' norm of a combination is its W-norm.
                let c = Coordinates::of(&series, p, &scaling).unwrap();
                let w: Vec<f64> =
                    (0..=p).map(|q| (0.7f64).powi(q as i32) * if q % 3 == 0 { -1.0 } else { 1.0 }).collect();
                let mut work = vec![0.0; series[0].len()];
                let (ours, theirs) = (c.norm(&w), direct_norm(&series, &w, &scaling, &mut work));
                assert!((ours - theirs).abs() <= 1e-12 * theirs, "{ours} vs {theirs}");
            }
        }
        // Steps longer than the series' own were found, one of them short
        // of a pole inside the cap.
        assert!(longer >= 3, "{longer} longer steps");
        assert!(before_pole >= 1, "no longer step short of the pole");
    }
}

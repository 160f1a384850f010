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
fn pade_weights(d: &[f64], t: f64, w: &mut [f64], dw: &mut [f64]) {
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
    dw.iter_mut().for_each(|v| *v = 0.0);
    w[0] = 1.0;
    let mut tpm = 1.0; // t^{p−1}
    for p in 1..m {
        let (num, num_p) = (dk[m - 1 - p], dk_prime[m - 1 - p]);
        let tp = tpm * t; // t^p
        let f = num / den;
        let f_p = (num_p * den - num * den_p) / (den * den);
        w[p] = tp * f;
        dw[p] = p as f64 * tpm * f + tp * f_p;
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
            Curve::Pade(_, d) => pade_weights(d, t, w, dw),
        }
    }

    /// Λ at t.
    pub(crate) fn lambda(&self, t: f64) -> f64 {
        let s = self.series();
        let n = s[0].len() - 1;
        match self {
            Curve::Series(_) => s.iter().rev().fold(0.0, |acc, c| acc * t + c[n]),
            Curve::Pade(..) => {
                let (mut w, mut dw) = ([0.0; MAX_ORDER + 1], [0.0; MAX_ORDER + 1]);
                self.weights(t, &mut w[..s.len()], &mut dw[..s.len()]);
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

/// The denominator d_0 … d_{m−1} of the Padé form built from U_1 … U_m
/// (m ≤ P), or None when the terms are (nearly) linearly dependent (a
/// series with vanishing terms: the polynomial is then the better form).
pub(crate) fn denominator(series: &[Vec<f64>], m: usize, scaling: &Scaling) -> Option<Vec<f64>> {
    if m < 2 || m > series.len() - 1 {
        return None;
    }
    let n = series[0].len() - 1;
    let dot = |a: &[f64], b: &[f64]| scaling.dot(&a[..n], a[n], &b[..n], b[n]);
    // Modified Gram–Schmidt on U_1 … U_{m−1}; α[i][j] = ⟨U_i, U*_j⟩ for
    // i = 1 … m, j = 1 … min(i, m−1).
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(m - 1);
    let mut alpha = vec![vec![0.0; m]; m + 1];
    for i in 1..=m {
        let mut v = series[i].clone();
        let norm0 = dot(&v, &v).sqrt();
        if !(norm0.is_finite() && norm0 > 0.0) {
            return None;
        }
        for (j, b) in basis.iter().enumerate() {
            let c = dot(&v, b);
            alpha[i][j + 1] = c;
            for (vi, bi) in v.iter_mut().zip(b) {
                *vi -= c * bi;
            }
        }
        if i < m {
            let r = dot(&v, &v).sqrt();
            if !(r > 1e-10 * norm0) {
                return None;
            }
            alpha[i][i] = r;
            basis.push(v.iter().map(|a| a / r).collect());
        }
    }
    let mut d = vec![0.0; m];
    d[0] = 1.0;
    for j in (1..m).rev() {
        let k = m - j;
        let s: f64 = (0..k).map(|i| d[i] * alpha[m - i][j]).sum();
        d[k] = -s / alpha[j][j];
    }
    d.iter().all(|v| v.is_finite()).then_some(d)
}

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
    let d_hi = denominator(series, p, scaling)?;
    let d_lo = denominator(series, p - 1, scaling)?;
    let n = series[0].len() - 1;
    let (hi, lo) = (Curve::Pade(series, &d_hi), Curve::Pade(series, &d_lo));
    let mut w_hi = vec![0.0; p + 1];
    let mut w_lo = vec![0.0; p + 1];
    let mut scratch = vec![0.0; p + 1];
    let poly = |d: &[f64], t: f64| d.iter().rev().fold(0.0, |acc, c| acc * t + c);
    let mut best = None;
    let steps = 48;
    let ratio = (cap / a_series).max(1.0);
    let mut diff = vec![0.0; n + 1];
    let mut incr = vec![0.0; n + 1];
    for k in 0..=steps {
        let t = a_series * ratio.powf(k as f64 / steps as f64);
        // No pole: the denominators keep the sign they have at 0 (= 1),
        // checked on a fine scan up to t.
        let fine = 16;
        let pole = (1..=fine).any(|i| {
            let s = t * i as f64 / fine as f64;
            poly(&d_hi, s) <= 0.0 || poly(&d_lo, s) <= 0.0
        });
        if pole {
            break;
        }
        hi.weights(t, &mut w_hi, &mut scratch);
        lo.weights(t, &mut w_lo, &mut scratch);
        diff.iter_mut().for_each(|v| *v = 0.0);
        incr.iter_mut().for_each(|v| *v = 0.0);
        for q in 1..=p {
            let (a, b) = (w_hi[q], w_lo[q]);
            if a == 0.0 && b == 0.0 {
                continue;
            }
            for i in 0..=n {
                diff[i] += (a - b) * series[q][i];
                incr[i] += a * series[q][i];
            }
        }
        let e = scaling.norm(&diff[..n], diff[n]);
        let size = scaling.norm(&incr[..n], incr[n]);
        if !(e <= epsilon * size) {
            break;
        }
        best = Some(t);
    }
    best.map(|t| (t, d_hi))
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
        let d = denominator(&series, p, &scaling).unwrap();
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
}

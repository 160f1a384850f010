//! Gauss–Legendre quadrature and composite panels: the one rule behind the
//! rod's collocation tableaux ([`crate::rod::scheme::Tableau::gauss`]), the
//! electrostatic energy's near/far-zone integrals and the writhe's double
//! integral.

/// (P_n(x), P_n'(x)) by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
        p0 = p1;
        p1 = p2;
    }
    if n == 0 {
        (1.0, 0.0)
    } else {
        (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
    }
}

/// Gauss–Legendre nodes (descending) and weights on [−1, 1]: the roots of
/// P_n by Newton from Chebyshev-like guesses, w_i = 2 / ((1 − x_i²) P_n'(x_i)²).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (p, dp) = legendre(n, z);
            let dz = p / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                let (_, dpn) = legendre(n, z);
                x[i] = z;
                w[i] = 2.0 / ((1.0 - z * z) * dpn * dpn);
                break;
            }
        }
    }
    (x, w)
}

/// Panels of [lo, hi] broken at those of `breaks` that lie inside (sorted,
/// breaks closer than 1e-14 of the interval merged, empty panels dropped).
pub fn panels(lo: f64, hi: f64, breaks: &[f64]) -> Vec<(f64, f64)> {
    let mut pts = vec![lo];
    pts.extend(breaks.iter().copied().filter(|&b| b > lo && b < hi));
    pts.push(hi);
    pts.sort_by(f64::total_cmp);
    pts.dedup_by(|a, b| (*a - *b).abs() <= 1e-14 * (hi - lo).abs().max(1.0));
    pts.windows(2).map(|w| (w[0], w[1])).filter(|(a, b)| b > a).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: an n-point rule integrates x^k exactly for k ≤ 2n − 1
    /// (∫_{−1}^{1} x^k = 2/(k + 1) for even k, 0 for odd), and the 2-point
    /// nodes are ±1/√3 with weights 1 (by hand).
    #[test]
    fn rules_are_exact_to_degree_2n_minus_1() {
        for n in 1..=32 {
            let (x, w) = gauss_legendre(n);
            for k in 0..2 * n {
                let q: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
                let exact = if k % 2 == 0 { 2.0 / (k + 1) as f64 } else { 0.0 };
                assert!((q - exact).abs() < 2e-14, "n {n} degree {k}: {q} vs {exact}");
            }
        }
        let (x, w) = gauss_legendre(2);
        assert!((x[0] - 1.0 / 3f64.sqrt()).abs() < 1e-15 && (x[1] + 1.0 / 3f64.sqrt()).abs() < 1e-15);
        assert!((w[0] - 1.0).abs() < 1e-15 && (w[1] - 1.0).abs() < 1e-15);
    }

    #[test]
    fn panels_break_inside_only_and_merge_near_duplicates() {
        assert_eq!(
            panels(0.0, 3.0, &[-1.0, 2.0, 1.0, 1.0 + 1e-16, 3.0, 5.0]),
            vec![(0.0, 1.0), (1.0, 2.0), (2.0, 3.0)]
        );
        assert_eq!(panels(1.0, 2.0, &[]), vec![(1.0, 2.0)]);
    }
}

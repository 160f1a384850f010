//! Dense vector kernels on slices (the Krylov and singular-value loops).

/// Σ a_i b_i.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Σ a_i b_i in four interleaved partial sums (i mod 4), added pairwise at
/// the end: four independent chains of additions, so a short dot product
/// costs its loads, not four cycles of add latency per entry (the
/// triangular solves with transposed factors). Rounding differs from
/// [`dot`]'s sequential sum, not its accuracy.
pub fn dot4(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut s = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            s[k] += x[k] * y[k];
        }
    }
    for (k, (x, y)) in ra.iter().zip(rb).enumerate() {
        s[k] += x * y;
    }
    (s[0] + s[1]) + (s[2] + s[3])
}

/// a − b, entry by entry.
pub fn sub(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// ‖v‖₂.
pub fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// max(a, b) that keeps NaN (f64::max drops it: a NaN residual would score
/// 0 and pass every tolerance).
pub fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// Modified Gram–Schmidt, in place (zero vectors left as they are).
pub fn orthonormalise(v: &mut [Vec<f64>]) {
    for i in 0..v.len() {
        for j in 0..i {
            let (head, tail) = v.split_at_mut(i);
            let c = dot(&tail[0], &head[j]);
            for (a, b) in tail[0].iter_mut().zip(&head[j]) {
                *a -= c * b;
            }
        }
        let norm = dot(&v[i], &v[i]).sqrt();
        if norm > 0.0 {
            v[i].iter_mut().for_each(|a| *a /= norm);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernels_by_hand() {
        assert_eq!(dot(&[1.0, 2.0, 3.0], &[4.0, 5.0, 6.0]), 32.0);
        assert_eq!(norm2(&[3.0, 4.0]), 5.0);
        assert!(nan_max(1.0, f64::NAN).is_nan() && nan_max(f64::NAN, 1.0).is_nan());
        assert_eq!(nan_max(1.0, 2.0), 2.0);
        // (1, 1), (1, 0) → (1, 1)/√2, (1, −1)/√2.
        let mut v = vec![vec![1.0, 1.0], vec![1.0, 0.0]];
        orthonormalise(&mut v);
        let h = 0.5f64.sqrt();
        assert!((v[0][0] - h).abs() < 1e-15 && (v[0][1] - h).abs() < 1e-15);
        assert!((v[1][0] - h).abs() < 1e-15 && (v[1][1] + h).abs() < 1e-15);
    }

    /// Reference: the sequential sum, exact here (small integers): every
    /// length around the four-wide chunks, remainders included, and
    /// unequal lengths (the shorter one counts).
    #[test]
    fn dot4_equals_the_sequential_sum_on_exact_data() {
        for n in 0..=13 {
            let a: Vec<f64> = (0..n).map(|i| (i as f64) - 3.0).collect();
            let b: Vec<f64> = (0..n + 2).map(|i| (2 * i + 1) as f64).collect();
            assert_eq!(dot4(&a, &b), dot(&a, &b[..n]), "n = {n}");
            assert_eq!(dot4(&b, &a), dot(&a, &b[..n]), "n = {n}, swapped");
        }
    }
}

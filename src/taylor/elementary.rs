//! Order-p Taylor coefficients of elementary functions of a series — the
//! standard recurrences of automatic differentiation in Taylor mode
//! (Griewank & Walther, *Evaluating Derivatives*, 2nd ed., §13.2, table
//! 13.2): for y = f(x(a)) with x(a) = Σ a^k x_k, the coefficient y_p follows
//! from x_0…x_p and y_0…y_{p−1} in O(p) operations, so a series of order P
//! costs O(P²) per function. Slices hold the coefficients in order (index
//! k = coefficient of a^k); only the entries up to p are read.
//!
//! Each function returns y_p for p ≥ 1; order 0 is the function's value
//! (the caller's). The recurrences are linear in x_p, which the asymptotic
//! numerical method relies on: its order-p unknown enters every node's
//! order-p coefficient through the Jacobian at the expansion point.

/// z_p of z = x·y: the Cauchy product Σ_{m=0..p} x_m y_{p−m}.
#[inline]
pub fn product(x: &[f64], y: &[f64], p: usize) -> f64 {
    let mut z = 0.0;
    for m in 0..=p {
        z += x[m] * y[p - m];
    }
    z
}

/// y_p of y = √x (y_0 > 0): from y² = x, 2y_0 y_p = x_p − Σ_{m=1..p−1} y_m y_{p−m}.
#[inline]
pub fn sqrt(x: &[f64], y: &[f64], p: usize) -> f64 {
    let mut s = x[p];
    for m in 1..p {
        s -= y[m] * y[p - m];
    }
    s / (2.0 * y[0])
}

/// y_p of y = 1/x (x_0 ≠ 0): from x·y = 1, x_0 y_p = −Σ_{m=1..p} x_m y_{p−m}.
#[inline]
pub fn recip(x: &[f64], y: &[f64], p: usize) -> f64 {
    let mut s = 0.0;
    for m in 1..=p {
        s += x[m] * y[p - m];
    }
    -s / x[0]
}

/// y_p of y = exp(c·x): from y' = c x' y, p y_p = c Σ_{m=1..p} m x_m y_{p−m}.
#[inline]
pub fn exp(c: f64, x: &[f64], y: &[f64], p: usize) -> f64 {
    let mut s = 0.0;
    for m in 1..=p {
        s += m as f64 * x[m] * y[p - m];
    }
    c * s / p as f64
}

/// (s_p, c_p) of s = sin(k·x), c = cos(k·x): from s' = k x' c and
/// c' = −k x' s, p s_p = k Σ m x_m c_{p−m}, p c_p = −k Σ m x_m s_{p−m}.
#[inline]
pub fn sin_cos(k: f64, x: &[f64], s: &[f64], c: &[f64], p: usize) -> (f64, f64) {
    let (mut a, mut b) = (0.0, 0.0);
    for m in 1..=p {
        let w = m as f64 * x[m];
        a += w * c[p - m];
        b += w * s[p - m];
    }
    (k * a / p as f64, -k * b / p as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fills y_0…y_P of y = f(x) by the recurrence `next` and returns them.
    fn series(x: &[f64], y0: f64, next: impl Fn(&[f64], &[f64], usize) -> f64) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        y[0] = y0;
        for p in 1..x.len() {
            y[p] = next(x, &y, p);
        }
        y
    }

    fn binomial(alpha: f64, k: usize) -> f64 {
        (0..k).fold(1.0, |c, j| c * (alpha - j as f64) / (j + 1) as f64)
    }

    // References: the binomial and exponential series in closed form, and
    // the rule that a truncated series evaluated at small a matches the
    // function to O(a^{P+1}).
    #[test]
    fn sqrt_and_recip_of_one_plus_a_are_the_binomial_series() {
        let mut x = vec![0.0; 12];
        x[0] = 1.0;
        x[1] = 1.0;
        let y = series(&x, 1.0, sqrt);
        let z = series(&x, 1.0, recip);
        for k in 0..12 {
            assert!((y[k] - binomial(0.5, k)).abs() <= 1e-15, "√: order {k}: {} vs {}", y[k], binomial(0.5, k));
            assert!((z[k] - binomial(-1.0, k)).abs() <= 1e-15, "1/x: order {k}");
        }
    }

    #[test]
    fn exp_sin_cos_and_products_match_their_functions_to_the_truncation_order() {
        // x(a) = 0.3 + 0.7a − 0.2a² + 0.05a³ (a polynomial path).
        let p_max = 14;
        let mut x = vec![0.0; p_max + 1];
        x[..4].copy_from_slice(&[0.3, 0.7, -0.2, 0.05]);
        let xa = |a: f64| 0.3 + a * (0.7 + a * (-0.2 + a * 0.05));
        let k = -1.7;
        let e = series(&x, (k * x[0]).exp(), |x, y, p| exp(k, x, y, p));
        let (mut s, mut c) = (vec![0.0; p_max + 1], vec![0.0; p_max + 1]);
        (s[0], c[0]) = ((2.0 * x[0]).sin(), (2.0 * x[0]).cos());
        for p in 1..=p_max {
            (s[p], c[p]) = sin_cos(2.0, &x, &s, &c, p);
        }
        let prod: Vec<f64> = (0..=p_max).map(|p| product(&e, &s, p)).collect();
        // √ and 1/x of 1 + x(a) (every order of the input non-zero up to 3).
        let mut y = x.clone();
        y[0] += 1.0;
        let root = series(&y, y[0].sqrt(), sqrt);
        let inv = series(&y, 1.0 / y[0], recip);
        let eval = |y: &[f64], a: f64| y.iter().rev().fold(0.0, |acc, v| acc * a + v);
        for a in [0.05_f64, 0.1] {
            let tol = 10.0 * a.powi(p_max as i32 + 1) + 1e-15;
            let (ee, ss, cc) = ((k * xa(a)).exp(), (2.0 * xa(a)).sin(), (2.0 * xa(a)).cos());
            assert!((eval(&e, a) - ee).abs() <= tol, "exp at {a}");
            assert!((eval(&s, a) - ss).abs() <= tol, "sin at {a}");
            assert!((eval(&c, a) - cc).abs() <= tol, "cos at {a}");
            assert!((eval(&prod, a) - ee * ss).abs() <= tol, "product at {a}");
            assert!((eval(&root, a) - (1.0 + xa(a)).sqrt()).abs() <= tol, "√ at {a}");
            assert!((eval(&inv, a) - 1.0 / (1.0 + xa(a))).abs() <= tol, "1/x at {a}");
        }
    }
}

//! The one-dimensional integrals of the near zone (physics.md §3.2):
//! J_n(a, ℓ; κ) = ∫_a^ℓ hⁿ e^{−κh} dh for n = −1, 0, 1, 2, and the
//! exponential integral E1 they need. e^{−κh} is integrated exactly — at
//! high salt κℓ is not small — with a power series where κℓ ≤ 1 (no
//! cancellation as κ → 0, Coulomb at κ = 0 exactly) and the closed forms
//! otherwise.

/// E1(x) = ∫_x^∞ e^{−t}/t dt for x > 0: the power series for x ≤ 1,
/// the continued fraction (modified Lentz) above.
pub fn e1(x: f64) -> f64 {
    assert!(x > 0.0, "E1 needs x > 0 (got {x})");
    const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;
    if x <= 1.0 {
        // E1 = −γ − ln x − Σ_{k≥1} (−x)^k / (k·k!)
        let mut sum = 0.0;
        let mut term = 1.0;
        for k in 1..60 {
            term *= -x / k as f64;
            let add = term / k as f64;
            sum += add;
            if add.abs() < 1e-18 * sum.abs().max(1e-300) {
                break;
            }
        }
        -EULER_GAMMA - x.ln() - sum
    } else {
        // e^{−x} / (x + 1 − 1²/(x + 3 − 2²/(x + 5 − …)))
        let tiny = 1e-300;
        let mut b = x + 1.0;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..200 {
            let a = -((i * i) as f64);
            b += 2.0;
            d = 1.0 / (a * d + b);
            c = b + a / c;
            let del = c * d;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        h * (-x).exp()
    }
}

/// J_n(a, ℓ; κ) = ∫_a^ℓ hⁿ e^{−κh} dh, n ∈ {−1, 0, 1, 2, 3}, 0 < a ≤ ℓ, κ ≥ 0.
pub fn j(n: i32, a: f64, l: f64, kappa: f64) -> f64 {
    debug_assert!((-1..=3).contains(&n) && a > 0.0 && l >= a && kappa >= 0.0);
    if l <= a {
        return 0.0;
    }
    if kappa * l <= 1.0 {
        // Σ_j (−κ)^j/j! ∫_a^ℓ h^{n+j} dh; the j with n + j = −1 is ln(ℓ/a).
        let mut sum = 0.0;
        let mut c = 1.0; // (−κ)^j / j!
        for jj in 0..40 {
            let p = n + jj + 1;
            let integral = if p == 0 { (l / a).ln() } else { (l.powi(p) - a.powi(p)) / p as f64 };
            let add = c * integral;
            sum += add;
            if jj > 2 && add.abs() <= 1e-17 * sum.abs() {
                break;
            }
            c *= -kappa / (jj + 1) as f64;
        }
        sum
    } else {
        let k = kappa;
        // Antiderivatives −F(h): ∫ hⁿ e^{−κh} = −e^{−κh} Σ_{i≤n} n!/i! h^i/κ^{n−i+1}.
        let f = |h: f64| -> f64 {
            let e = (-k * h).exp();
            match n {
                0 => e / k,
                1 => e * (h / k + 1.0 / (k * k)),
                2 => e * (h * h / k + 2.0 * h / (k * k) + 2.0 / (k * k * k)),
                3 => e * (h * h * h / k + 3.0 * h * h / (k * k) + 6.0 * h / (k * k * k) + 6.0 / (k * k * k * k)),
                _ => unreachable!(),
            }
        };
        match n {
            -1 => {
                if k * a > 1.0 {
                    e1(k * a) - e1(k * l)
                } else {
                    // E1(κa) − E1(1/…): split at h = 1/κ to keep both parts accurate.
                    j(-1, a, 1.0 / k, k) + (e1(1.0) - e1(k * l))
                }
            }
            _ => f(a) - f(l),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// E1 against tabulated values (Abramowitz & Stegun, Table 5.1:
    /// E1(0.5) = 0.5597735948, E1(1) = 0.2193839344, E1(2) = 0.04890051071,
    /// E1(5) = 1.148295591e−3) and the two forms agreeing across x = 1.
    #[test]
    fn e1_matches_tables() {
        for (x, v) in [(0.5, 0.5597735948), (1.0, 0.2193839344), (2.0, 0.04890051071), (5.0, 1.148295591e-3)] {
            assert!((e1(x) - v).abs() < 1e-9 * v, "E1({x}) = {} vs {v}", e1(x));
        }
        assert!((e1(1.0 - 1e-12) - e1(1.0 + 1e-12)).abs() < 1e-11);
    }

    /// J_n against composite Gauss–Legendre quadrature on a fine grid
    /// (independent), over κ from 0 (Coulomb) through the series/closed-form
    /// switch to κℓ = 50.
    #[test]
    fn near_integrals_match_quadrature() {
        let gl = |f: &dyn Fn(f64) -> f64, a: f64, b: f64| -> f64 {
            // 2-point Gauss on 20000 panels, geometric in h (1/h near a).
            let m = 20000;
            let (x1, x2) = (0.5 - 0.5 / 3f64.sqrt(), 0.5 + 0.5 / 3f64.sqrt());
            let r = (b / a).powf(1.0 / m as f64);
            let mut s = 0.0;
            let mut lo = a;
            for _ in 0..m {
                let hi = lo * r;
                let w = hi - lo;
                s += 0.5 * w * (f(lo + x1 * w) + f(lo + x2 * w));
                lo = hi;
            }
            s
        };
        for kappa in [0.0, 1e-6, 0.3, 1.0, 3.0, 50.0] {
            for n in -1..=3 {
                let (a, l) = (0.05, 1.0);
                let exact = gl(&|h: f64| h.powi(n) * (-kappa * h).exp(), a, l);
                let got = j(n, a, l, kappa);
                assert!((got - exact).abs() < 1e-10 * exact.abs().max(1e-30), "J_{n}(κ = {kappa}) = {got} vs {exact}");
            }
        }
    }
}

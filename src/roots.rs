//! Scalar root finding: every sign change of a function on an interval
//! (a scan then bisection: the loads a continuation step crosses, possibly
//! twice past a fold) and a bracketed root by safeguarded regula falsi (the
//! radii where a fibre family switches on inside a tube wall).

/// Every root of g on (0, b] (sign changes over 64 pieces, bisected): a
/// step that passes a fold crosses a load twice.
pub fn all_roots(g: impl Fn(f64) -> f64, b: f64) -> Vec<f64> {
    let mut roots = Vec::new();
    let mut lo = 0.0;
    while let Some(t) = first_root(|s| g(lo + s), b - lo) {
        roots.push(lo + t);
        lo += t * (1.0 + 1e-12) + f64::EPSILON;
        if lo >= b {
            break;
        }
    }
    roots
}

/// The first root of g on (0, b]: a scan in 64 pieces then bisection.
pub fn first_root(g: impl Fn(f64) -> f64, b: f64) -> Option<f64> {
    let pieces = 64;
    let mut a0 = 0.0;
    let mut g0 = g(0.0);
    if g0 == 0.0 {
        return None; // starting on the target: not a crossing
    }
    for k in 1..=pieces {
        let a1 = b * k as f64 / pieces as f64;
        let g1 = g(a1);
        if g0 * g1 <= 0.0 {
            let (mut lo, mut hi, mut glo) = (a0, a1, g0);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    // Adjacent doubles: no further halving moves the bracket.
                    break;
                }
                let gm = g(mid);
                if gm == 0.0 {
                    return Some(mid);
                }
                if gm * glo < 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                    glo = gm;
                }
            }
            return Some(0.5 * (lo + hi));
        }
        (a0, g0) = (a1, g1);
    }
    None
}

/// Root of g in [a, b] with g(a) = ga, g(b) = gb of opposite signs: Illinois
/// regula falsi, with a bisection whenever the bracket fails to halve, to
/// 1e−15 of the bracket (or an exact zero).
pub fn bracketed_root(g: impl Fn(f64) -> f64, mut a: f64, mut b: f64, mut ga: f64, mut gb: f64) -> f64 {
    let tol = 1e-15 * (a.abs() + b.abs());
    let mut side = 0i8;
    for _ in 0..200 {
        let width = b - a;
        if width <= tol {
            break;
        }
        let mut c = (a * gb - b * ga) / (gb - ga);
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        let gc = g(c);
        if gc == 0.0 {
            return c;
        }
        if gc.signum() == ga.signum() {
            (a, ga) = (c, gc);
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        } else {
            (b, gb) = (c, gc);
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        }
        if b - a > 0.5 * width {
            // Slow side: bisect once.
            let mid = 0.5 * (a + b);
            let gm = g(mid);
            if gm == 0.0 {
                return mid;
            }
            if gm.signum() == ga.signum() {
                (a, ga) = (mid, gm);
            } else {
                (b, gb) = (mid, gm);
            }
            side = 0;
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// References by hand: cos on (0, 10] vanishes at π/2, 3π/2, 5π/2; x² − 2
    /// at √2; a function with no sign change has no root, nor one that
    /// starts on its root (not a crossing).
    #[test]
    fn roots_of_known_functions() {
        let r = all_roots(f64::cos, 10.0);
        assert_eq!(r.len(), 3);
        for (k, x) in r.iter().enumerate() {
            assert!((x - (k as f64 + 0.5) * std::f64::consts::PI).abs() < 1e-12, "{x}");
        }
        assert!(first_root(f64::sin, 1.0).is_none());
        assert!((first_root(|x| x * x - 2.0, 3.0).unwrap() - 2f64.sqrt()).abs() < 1e-14);
        assert!(first_root(|x| x * x + 1.0, 3.0).is_none());
        let g = |x: f64| x * x * x - 2.0;
        assert!((bracketed_root(g, 0.0, 2.0, g(0.0), g(2.0)) - 2f64.cbrt()).abs() < 1e-14);
    }
}

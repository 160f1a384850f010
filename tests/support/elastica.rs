//! Euler's elastica in closed form (the inextensible cantilever under an
//! axial dead load P, K_b = L = 1): the references of the post-buckling
//! tests.

use std::f64::consts::PI;

/// Complete elliptic integrals K(k), E(k) of modulus k by the AGM
/// (Abramowitz & Stegun 17.6).
pub fn elliptic(k: f64) -> (f64, f64) {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    let mut sum = 0.5 * k * k;
    let mut pow = 0.5;
    for _ in 0..40 {
        let c = 0.5 * (a - b);
        let (an, bn) = (0.5 * (a + b), (a * b).sqrt());
        pow *= 2.0;
        sum += pow * c * c;
        (a, b) = (an, bn);
        if c.abs() < 1e-17 {
            break;
        }
    }
    let kk = PI / (2.0 * a);
    (kk, kk * (1.0 - sum))
}

/// The post-buckled elastica at load `p` (> P_cr = π²/4): the modulus k =
/// sin(θ0/2) (θ0 the tip rotation) from P = P_cr (2K(k)/π)² by bisection
/// (P grows with k), the tip's axial position 2E/K − 1 and its lateral
/// deflection 2k/K.
pub fn at_load(p: f64) -> (f64, f64, f64) {
    let pcr = PI * PI / 4.0;
    let (mut lo, mut hi) = (0.0f64, 1.0 - 1e-15);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if pcr * (2.0 * elliptic(mid).0 / PI).powi(2) < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let k = 0.5 * (lo + hi);
    let (kk, ee) = elliptic(k);
    (k, 2.0 * ee / kk - 1.0, 2.0 * k / kk)
}

//! An independent buckling analysis of the straight, twisted, charged
//! Kirchhoff rod clamped at both ends, written from the energy of
//! physics.md §3.1 and §3.4 and sharing no code with rodkit.
//!
//! The lateral displacement w = x + iy of the centreline (w = w′ = 0 at
//! both clamps) has the quadratic energy, at tension F and end torque
//! M = Cφ/L (the straight state's):
//!
//!   E₂ = ½∫(K|w″|² + F|w′|²) ds − ½M∫(x′y″ − y′x″) ds + δ²E_es,
//!
//! the twist term being −M·2πWr with Fuller's writhe of a nearly straight
//! curve (an infinite rod gives Kk⁴ + Fk² − Mk³: Greenhill's M = 2√(KF)).
//! With inextensibility z(s) − z(t) = h − ½∫_t^s|w′|² (h = s − t), the
//! Coulomb energy ∫∫_{h>a} λ²/|r(s) − r(t)| has the second variation
//!
//!   δ²E_es = −½λ² ∫∫_{h>a} [|w(s) − w(t)|² − h∫_t^s|w′|²] / h³ dt ds
//!          = −½λ² [∫∫_{h>a} |Δw|²/h³ − ∫ W(u)|w′(u)|² du],
//!
//! W(u) = ∫_a^L ℓ(u, h)/h² dh, ℓ the length of the t with t < u < t + h
//! inside the rod: the self-repulsion's axial tension, in closed form. Both
//! parts are integrated to rounding (the first in h on panels graded from
//! a, in t exactly; the second on panels broken at its kinks).
//!
//! w is expanded in b_j(s) = x²(1 − x)²P_j(2x − 1), x = s/L (P_j Legendre):
//! every b_j is clamped, and the expansion converges spectrally. The first
//! buckling is the smallest M where the Hessian H₀ + M·S is singular.
#![allow(dead_code)]

use nalgebra::DMatrix;
use rodkit::quadrature::gauss_legendre;

/// The straight rod: length L, bending K, twist C, tension F, line charge
/// λ (energy ½λ²∫∫Φ, Coulomb Φ = 1/d) and the excluded arc length a.
#[derive(Clone, Copy, Debug)]
pub struct StraightChargedRod {
    pub length: f64,
    pub bending: f64,
    pub twist: f64,
    pub tension: f64,
    pub line_charge: f64,
    pub a: f64,
}

/// Σ f(s)·weight over Gauss–Legendre of `n` points on each panel of `breaks`.
fn panels(breaks: &[f64], n: usize, mut f: impl FnMut(f64, f64)) {
    let (x, w) = gauss_legendre(n);
    for p in breaks.windows(2) {
        let (c, h) = (0.5 * (p[0] + p[1]), 0.5 * (p[1] - p[0]));
        for (xi, wi) in x.iter().zip(&w) {
            f(c + h * xi, h * wi);
        }
    }
}

impl StraightChargedRod {
    /// b_j, b_j′ and b_j″ (in s) at s, j < n.
    fn basis(&self, n: usize, s: f64, b: &mut [f64], db: &mut [f64], d2b: &mut [f64]) {
        let l = self.length;
        let x = s / l;
        let xi = 2.0 * x - 1.0;
        let g = x * x * (1.0 - x) * (1.0 - x);
        let dg = 2.0 * x * (1.0 - x) * (1.0 - 2.0 * x);
        let d2g = 2.0 * (1.0 - 6.0 * x + 6.0 * x * x);
        // P_j(ξ) and its ξ-derivatives by the three-term recurrence.
        let (mut p, mut dp, mut d2p) = (vec![0.0; n.max(2)], vec![0.0; n.max(2)], vec![0.0; n.max(2)]);
        p[0] = 1.0;
        p[1] = xi;
        dp[1] = 1.0;
        for k in 1..n.max(2) - 1 {
            let kf = k as f64;
            p[k + 1] = ((2.0 * kf + 1.0) * xi * p[k] - kf * p[k - 1]) / (kf + 1.0);
            dp[k + 1] = dp[k - 1] + (2.0 * kf + 1.0) * p[k];
            d2p[k + 1] = d2p[k - 1] + (2.0 * kf + 1.0) * dp[k];
        }
        for j in 0..n {
            // d/dx of P_j(2x − 1) is 2P_j′; d/ds = (1/L) d/dx.
            b[j] = g * p[j];
            db[j] = (dg * p[j] + 2.0 * g * dp[j]) / l;
            d2b[j] = (d2g * p[j] + 4.0 * dg * dp[j] + 4.0 * g * d2p[j]) / (l * l);
        }
    }

    /// W(u) = ∫_a^L ℓ(u, h)/h² dh with ℓ = min(h, m) for h ≤ M and L − h
    /// beyond (m, M the shorter and longer distance from u to the ends).
    fn tension_weight(&self, u: f64) -> f64 {
        let (l, a) = (self.length, self.a);
        let (m, big) = (u.min(l - u), u.max(l - u));
        // ∫_lo^hi of 1/h, of m/h² and of (L − h)/h², each over its range ∩ [a, L].
        let log = |lo: f64, hi: f64| if hi > lo { (hi / lo).ln() } else { 0.0 };
        let inv = |lo: f64, hi: f64| if hi > lo { 1.0 / lo - 1.0 / hi } else { 0.0 };
        let (lo1, hi1) = (a, m);
        let (lo2, hi2) = (a.max(m), big);
        let (lo3, hi3) = (a.max(big), l);
        log(lo1, hi1) + m * inv(lo2, hi2) + (l * inv(lo3, hi3) - log(lo3, hi3))
    }

    /// The Hessian blocks of E₂ = ½vᵀ(H₀ + M·S)v with v = (x coefficients,
    /// y coefficients): returns (H_xx = H_yy without the torque, the
    /// antisymmetric torque block D with H_xy = −½M·D).
    fn blocks(&self, n: usize) -> (DMatrix<f64>, DMatrix<f64>) {
        let l = self.length;
        let (mut b, mut db, mut d2b) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let (mut b2, mut db2, mut d2b2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut hxx = DMatrix::zeros(n, n);
        let mut d = DMatrix::zeros(n, n);
        // Elastic and torque parts: polynomials of degree ≤ 2n + 6.
        let mut f1 = DMatrix::zeros(n, n);
        let mut f2 = DMatrix::zeros(n, n);
        panels(&[0.0, l], n + 8, |s, w| {
            self.basis(n, s, &mut b, &mut db, &mut d2b);
            for i in 0..n {
                for j in 0..n {
                    hxx[(i, j)] += w * (self.bending * d2b[i] * d2b[j] + self.tension * db[i] * db[j]);
                    d[(i, j)] += w * (db[i] * d2b[j] - db[j] * d2b[i]);
                }
            }
        });
        if self.line_charge != 0.0 {
            // ∫ W|w′|²: W has kinks at a, L/2 and L − a, and ln-like growth.
            let mut breaks = vec![0.0, l];
            for k in 0..=8 {
                let q = 2f64.powi(k) * self.a;
                if q < 0.5 * l {
                    breaks.push(q);
                    breaks.push(l - q);
                }
            }
            breaks.push(0.5 * l);
            breaks.sort_by(f64::total_cmp);
            breaks.dedup();
            panels(&breaks, 24, |u, w| {
                self.basis(n, u, &mut b, &mut db, &mut d2b);
                let ww = w * self.tension_weight(u);
                for i in 0..n {
                    for j in 0..n {
                        f2[(i, j)] += ww * db[i] * db[j];
                    }
                }
            });
            // ∫_a^L dh h⁻³ ∫_0^{L−h} Δb_i Δb_j dt: h on panels a·2^k, t exact.
            let mut hb = vec![self.a];
            while 2.0 * hb[hb.len() - 1] < l {
                let next = 2.0 * hb[hb.len() - 1];
                hb.push(next);
            }
            hb.push(l);
            let (tx, tw) = gauss_legendre(n + 8);
            panels(&hb, 24, |h, wh| {
                let span = l - h;
                for (xi, wi) in tx.iter().zip(&tw) {
                    let t = 0.5 * span * (1.0 + xi);
                    self.basis(n, t, &mut b, &mut db, &mut d2b);
                    self.basis(n, t + h, &mut b2, &mut db2, &mut d2b2);
                    let weight = wh * 0.5 * span * wi / (h * h * h);
                    for i in 0..n {
                        let di = b2[i] - b[i];
                        for j in 0..n {
                            f1[(i, j)] += weight * di * (b2[j] - b[j]);
                        }
                    }
                }
            });
        }
        let lambda2 = self.line_charge * self.line_charge;
        hxx -= lambda2 * (f1 - f2);
        (hxx, d)
    }

    /// The first buckling end rotation φ_c = M_c L / C (rad), from `n`
    /// basis functions: the smallest M > 0 with H₀ + M·S singular, i.e.
    /// 1/M the largest eigenvalue of −L⁻¹SL⁻ᵀ (H₀ = LLᵀ).
    pub fn buckling_rotation(&self, n: usize) -> f64 {
        let (hxx, d) = self.blocks(n);
        let mut h0 = DMatrix::zeros(2 * n, 2 * n);
        let mut s = DMatrix::zeros(2 * n, 2 * n);
        h0.view_mut((0, 0), (n, n)).copy_from(&hxx);
        h0.view_mut((n, n), (n, n)).copy_from(&hxx);
        let sxy = -0.5 * &d;
        s.view_mut((0, n), (n, n)).copy_from(&sxy);
        s.view_mut((n, 0), (n, n)).copy_from(&sxy.transpose());
        let chol = h0.cholesky().expect("the unloaded straight rod is stable");
        let linv = chol.l().try_inverse().expect("a Cholesky factor is invertible");
        let m = -(&linv * s * linv.transpose());
        let m = 0.5 * (&m + m.transpose());
        let top = m.symmetric_eigenvalues().iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert!(top > 0.0, "no buckling under torque");
        self.length / (top * self.twist)
    }
}

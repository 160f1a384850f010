//! Chebyshev spectral collocation on an interval: nodes, differentiation and
//! integration. The generic engine behind the thick-tube wall solvers: their
//! coefficients (helix angle α(R) = atan(τ0 R), hyperelastic stresses) are
//! analytic in R, so the error falls exponentially with the node count, and
//! two node counts give a reliable error estimate.
//!
//! The matrices are dense because spectral differentiation couples every node
//! to every other: n stays small (≤ 64 in practice), so this is the cheapest
//! exact-to-round-off discretisation of a one-dimensional wall problem.
//! References: L. N. Trefethen, *Spectral Methods in MATLAB* (2000), ch. 6 and
//! 12 (`cheb`, `clencurt`), with the negative-sum trick for the diagonal.

use nalgebra::{DMatrix, DVector};
use std::f64::consts::PI;

/// Chebyshev–Gauss–Lobatto grid of n + 1 nodes on [a, b], ascending.
#[derive(Clone, Debug)]
pub struct ChebyshevGrid {
    /// Nodes x_0 = a < x_1 < … < x_n = b.
    pub nodes: DVector<f64>,
    /// Differentiation matrix: (D f)(x_i) = f'(x_i) for polynomials of degree ≤ n.
    pub diff: DMatrix<f64>,
    /// Clenshaw–Curtis weights: Σ w_i f(x_i) = ∫_a^b f, exact for degree ≤ n.
    pub weights: DVector<f64>,
}

impl ChebyshevGrid {
    /// n ≥ 2 intervals, a < b.
    pub fn new(n: usize, a: f64, b: f64) -> Self {
        assert!(n >= 2 && a < b, "ChebyshevGrid::new(n = {n}, a = {a}, b = {b})");
        let half = 0.5 * (b - a);
        // Reference nodes t_j = −cos(πj/n) ∈ [−1, 1], ascending.
        let t: Vec<f64> = (0..=n).map(|j| -(PI * j as f64 / n as f64).cos()).collect();
        let nodes = DVector::from_iterator(n + 1, t.iter().map(|&tj| a + half * (tj + 1.0)));

        // Off-diagonal entries c_i/c_j (−1)^(i+j)/(t_i − t_j), c = 2 at the ends;
        // the sign pattern is that of the standard descending grid, re-indexed.
        let c = |i: usize| if i == 0 || i == n { 2.0 } else { 1.0 };
        let mut diff = DMatrix::zeros(n + 1, n + 1);
        for i in 0..=n {
            let mut row_sum = 0.0;
            for j in 0..=n {
                if i != j {
                    let sign = if (i + j) % 2 == 0 { 1.0 } else { -1.0 };
                    let v = c(i) / c(j) * sign / (t[i] - t[j]);
                    diff[(i, j)] = v / half;
                    row_sum += v;
                }
            }
            // Negative-sum trick: exact differentiation of constants.
            diff[(i, i)] = -row_sum / half;
        }

        // Clenshaw–Curtis weights on [−1, 1] (Trefethen's clencurt), scaled.
        let mut w = vec![0.0; n + 1];
        let theta = |j: usize| PI * j as f64 / n as f64;
        let inner = |j: usize| {
            let mut v = 1.0;
            if n % 2 == 0 {
                for k in 1..n / 2 {
                    v -= 2.0 * (2.0 * k as f64 * theta(j)).cos() / (4 * k * k - 1) as f64;
                }
                v -= (n as f64 * theta(j)).cos() / (n * n - 1) as f64;
            } else {
                for k in 1..=(n - 1) / 2 {
                    v -= 2.0 * (2.0 * k as f64 * theta(j)).cos() / (4 * k * k - 1) as f64;
                }
            }
            v
        };
        let ends = if n % 2 == 0 { 1.0 / (n * n - 1) as f64 } else { 1.0 / (n * n) as f64 };
        w[0] = ends;
        w[n] = ends;
        for (j, wj) in w.iter_mut().enumerate().take(n).skip(1) {
            *wj = 2.0 * inner(j) / n as f64;
        }
        let weights = DVector::from_iterator(n + 1, w.into_iter().map(|x| x * half));
        ChebyshevGrid { nodes, diff, weights }
    }

    /// Grid uniform in ln x on [a, b], 0 < a < b: nodes x_j = exp(ξ_j) for a
    /// Chebyshev grid ξ_j on [ln a, ln b], with d/dx = (1/x) d/dξ and
    /// ∫ f dx = ∫ f x dξ. Fields like C/x near a small hole (a ≪ b) are
    /// analytic in ξ, so the error stays spectral however large b/a is;
    /// for b/a → 1 it tends to the plain grid.
    pub fn logarithmic(n: usize, a: f64, b: f64) -> Self {
        assert!(a > 0.0 && a < b, "ChebyshevGrid::logarithmic(a = {a}, b = {b})");
        let xi = Self::new(n, a.ln(), b.ln());
        let nodes = xi.nodes.map(f64::exp);
        let mut diff = xi.diff;
        for i in 0..=n {
            for j in 0..=n {
                diff[(i, j)] /= nodes[i];
            }
        }
        // Pin the end nodes to a and b exactly (exp(ln a) may differ by an ulp).
        let mut nodes = nodes;
        nodes[0] = a;
        nodes[n] = b;
        let weights = xi.weights.component_mul(&nodes);
        ChebyshevGrid { nodes, diff, weights }
    }

    /// Number of intervals n (the grid has n + 1 nodes).
    pub fn intervals(&self) -> usize {
        self.nodes.len() - 1
    }

    /// ∫_a^b f for nodal values f.
    pub fn integrate(&self, f: &DVector<f64>) -> f64 {
        self.weights.dot(f)
    }

    /// Cumulative integral F(x_i) = ∫_a^{x_i} f, spectrally accurate: solves
    /// D F = f with F(a) = 0 (the interpolant's exact antiderivative).
    pub fn cumulative_integral(&self, f: &DVector<f64>) -> DVector<f64> {
        let n = self.intervals();
        let mut d = self.diff.clone();
        let mut rhs = f.clone();
        for j in 0..=n {
            d[(0, j)] = if j == 0 { 1.0 } else { 0.0 };
        }
        rhs[0] = 0.0;
        d.lu().solve(&rhs).expect("cumulative integration matrix is nonsingular")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_for_polynomials_and_spectral_for_analytic() {
        // Reference: calculus. p(x) = x^5 − 3x^2 + 1 on [0.5, 2.0].
        let g = ChebyshevGrid::new(8, 0.5, 2.0);
        let p = g.nodes.map(|x| x.powi(5) - 3.0 * x * x + 1.0);
        let dp = &g.diff * &p;
        for (i, &x) in g.nodes.iter().enumerate() {
            assert!((dp[i] - (5.0 * x.powi(4) - 6.0 * x)).abs() < 1e-11, "x = {x}");
        }
        let exact = (2f64.powi(6) - 0.5f64.powi(6)) / 6.0 - (8.0 - 0.125) + 1.5;
        assert!((g.integrate(&p) - exact).abs() < 1e-13);
        // Odd n too.
        let g = ChebyshevGrid::new(7, -1.0, 3.0);
        let p = g.nodes.map(|x| x.powi(7));
        assert!((g.integrate(&p) - (3f64.powi(8) - 1.0) / 8.0).abs() < 1e-10);
        // exp on [0, 1]: 16 intervals reach round-off.
        let g = ChebyshevGrid::new(16, 0.0, 1.0);
        let e = g.nodes.map(f64::exp);
        assert!((g.integrate(&e) - (1f64.exp() - 1.0)).abs() < 1e-14);
        // Logarithmic grid on [0.01, 1]: f = 1/x + x is analytic in ln x.
        let lg = ChebyshevGrid::logarithmic(24, 0.01, 1.0);
        let f = lg.nodes.map(|x| 1.0 / x + x);
        let df = &lg.diff * &f;
        for (i, &x) in lg.nodes.iter().enumerate() {
            assert!((df[i] - (1.0 - 1.0 / (x * x))).abs() < 1e-9 * (1.0 / (x * x)), "x = {x}");
        }
        assert!((lg.integrate(&f) - (100f64.ln() + 0.5 * (1.0 - 1e-4))).abs() < 1e-12);
        let cum = g.cumulative_integral(&e);
        for (i, &x) in g.nodes.iter().enumerate() {
            assert!((cum[i] - (x.exp() - 1.0)).abs() < 1e-14, "x = {x}");
        }
        assert!(((&g.diff * &e) - &e).amax() < 1e-11);
    }
}

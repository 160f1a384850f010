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
            if n.is_multiple_of(2) {
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
        let ends = if n.is_multiple_of(2) { 1.0 / (n * n - 1) as f64 } else { 1.0 / (n * n) as f64 };
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

/// Chebyshev pieces joined at breakpoints, for fields that are analytic
/// between known points but only C¹ across them (a fibre family switching on
/// inside a tube wall makes the stress's derivative jump): one Chebyshev grid
/// per piece keeps the convergence spectral where a single grid would fall
/// to an algebraic rate. Each interface node appears twice (last node of the
/// left piece, first of the right one); the caller imposes continuity there.
/// A single piece is an ordinary [`ChebyshevGrid`].
#[derive(Clone, Debug)]
pub struct PiecewiseGrid {
    /// All nodes, piece after piece (interface nodes repeated), ascending.
    pub nodes: DVector<f64>,
    /// Block-diagonal differentiation: each piece's own matrix.
    pub diff: DMatrix<f64>,
    /// Composite Clenshaw–Curtis weights.
    pub weights: DVector<f64>,
    pieces: Vec<Piece>,
}

#[derive(Clone, Debug)]
struct Piece {
    start: usize,
    grid: ChebyshevGrid,
    logarithmic: bool,
}

impl PiecewiseGrid {
    /// Pieces on [a, b] split at the interior `breaks` (ascending, strictly
    /// inside), sharing about `n` intervals in proportion to their lengths
    /// (in ln x when `logarithmic`), at least `min_piece` each.
    pub fn new(n: usize, a: f64, b: f64, breaks: &[f64], logarithmic: bool, min_piece: usize) -> Self {
        let coord = |x: f64| if logarithmic { x.ln() } else { x };
        let mut ends = vec![a];
        ends.extend(breaks.iter().copied().filter(|&x| x > a && x < b));
        ends.push(b);
        let total = coord(b) - coord(a);
        let mut pieces = Vec::with_capacity(ends.len() - 1);
        let mut start = 0;
        for w in ends.windows(2) {
            let share = (n as f64 * (coord(w[1]) - coord(w[0])) / total).round() as usize;
            let ni = share.max(min_piece).max(2);
            let grid = if logarithmic {
                ChebyshevGrid::logarithmic(ni, w[0], w[1])
            } else {
                ChebyshevGrid::new(ni, w[0], w[1])
            };
            pieces.push(Piece { start, grid, logarithmic });
            start += ni + 1;
        }
        let mut nodes = DVector::zeros(start);
        let mut diff = DMatrix::zeros(start, start);
        let mut weights = DVector::zeros(start);
        for p in &pieces {
            let m = p.grid.nodes.len();
            nodes.rows_mut(p.start, m).copy_from(&p.grid.nodes);
            weights.rows_mut(p.start, m).copy_from(&p.grid.weights);
            diff.view_mut((p.start, p.start), (m, m)).copy_from(&p.grid.diff);
        }
        PiecewiseGrid { nodes, diff, weights, pieces }
    }

    /// Intervals summed over the pieces.
    pub fn intervals(&self) -> usize {
        self.pieces.iter().map(|p| p.grid.intervals()).sum()
    }

    /// Interior breakpoints.
    pub fn breaks(&self) -> Vec<f64> {
        self.pieces.iter().skip(1).map(|p| p.grid.nodes[0]).collect()
    }

    /// Index of the left copy of each interface node (the right copy is the
    /// next index).
    pub fn interfaces(&self) -> Vec<usize> {
        self.pieces.iter().skip(1).map(|p| p.start - 1).collect()
    }

    /// ∫_a^b f for nodal values f.
    pub fn integrate(&self, f: &DVector<f64>) -> f64 {
        self.weights.dot(f)
    }

    /// F(x_i) = ∫_a^{x_i} f, piece by piece.
    pub fn cumulative_integral(&self, f: &DVector<f64>) -> DVector<f64> {
        let mut out = DVector::zeros(f.len());
        let mut offset = 0.0;
        for p in &self.pieces {
            let m = p.grid.nodes.len();
            let local = p.grid.cumulative_integral(&f.rows(p.start, m).into_owned());
            for j in 0..m {
                out[p.start + j] = offset + local[j];
            }
            offset += local[m - 1];
        }
        out
    }

    /// The piecewise interpolant of nodal `values` at x ∈ [a, b]
    /// (barycentric formula on each piece's Chebyshev points, in ln x on
    /// logarithmic pieces).
    pub fn interpolate(&self, values: &DVector<f64>, x: f64) -> f64 {
        let p = self
            .pieces
            .iter()
            .find(|p| x <= p.grid.nodes[p.grid.nodes.len() - 1])
            .unwrap_or_else(|| self.pieces.last().expect("a grid has a piece"));
        let n = p.grid.intervals();
        let coord = |v: f64| if p.logarithmic { v.ln() } else { v };
        let t = coord(x);
        let (mut num, mut den) = (0.0, 0.0);
        for j in 0..=n {
            let d = t - coord(p.grid.nodes[j]);
            let f = values[p.start + j];
            if d == 0.0 {
                return f;
            }
            let mut w = if j % 2 == 0 { 1.0 } else { -1.0 };
            if j == 0 || j == n {
                w *= 0.5;
            }
            num += w * f / d;
            den += w / d;
        }
        num / den
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

    #[test]
    fn piecewise_grid_is_spectral_across_a_kink() {
        // Reference: calculus. f(x) = |x − 0.3|³ + eˣ on [−1, 1] has a jump
        // in its third derivative at 0.3; a break there keeps every operation
        // exact to round-off with 2 × 16 intervals, a single grid of 32 not.
        let f = |x: f64| (x - 0.3f64).abs().powi(3) + x.exp();
        let df = |x: f64| 3.0 * (x - 0.3) * (x - 0.3f64).abs() + x.exp();
        let exact = 0.7f64.powi(4) / 4.0 + 1.3f64.powi(4) / 4.0 + 1f64.exp() - (-1f64).exp();
        let g = PiecewiseGrid::new(32, -1.0, 1.0, &[0.3], false, 4);
        assert_eq!(g.intervals(), 32);
        assert_eq!(g.interfaces().len(), 1);
        let v = g.nodes.map(f);
        assert!((g.integrate(&v) - exact).abs() < 1e-13);
        let dv = &g.diff * &v;
        for (i, &x) in g.nodes.iter().enumerate() {
            assert!((dv[i] - df(x)).abs() < 1e-11, "x = {x}");
        }
        let cum = g.cumulative_integral(&v);
        assert!((cum[cum.len() - 1] - exact).abs() < 1e-13);
        for x in [-0.9, 0.1, 0.3, 0.31, 0.77] {
            assert!((g.interpolate(&v, x) - f(x)).abs() < 1e-13, "x = {x}");
        }
        let single = ChebyshevGrid::new(32, -1.0, 1.0);
        let err = (single.integrate(&single.nodes.map(f)) - exact).abs();
        assert!(err > 1e-7, "a single grid would not need the break: {err:e}");
        // Logarithmic pieces interpolate in ln x: x^(1/3) on [0.01, 1].
        let g = PiecewiseGrid::new(30, 0.01, 1.0, &[0.2], true, 4);
        let v = g.nodes.map(f64::cbrt);
        assert!((g.interpolate(&v, 0.05) - 0.05f64.cbrt()).abs() < 1e-13);
    }
}

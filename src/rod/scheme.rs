//! Discretisations of the rod ODE on an element of length h (physics.md
//! §2.3): the implicit midpoint rule and Gauss–Legendre collocation with s
//! stages (order 2s at the nodes). Both keep the algebraic system cubic and
//! conserve |q| exactly (quadratic invariants are preserved by Gauss
//! methods; the midpoint rule is the Cayley map for q).

use nalgebra::DMatrix;

/// The discretisation of an element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// y_{i+1} − y_i = h f((y_i + y_{i+1})/2): second order, no stage unknowns.
    Midpoint,
    /// Gauss–Legendre collocation with the given number of stages (2..=4):
    /// order 2s, the s stage values are extra unknowns.
    Gauss(usize),
}

impl Scheme {
    /// Stage unknowns per element (13 each).
    pub fn stages(&self) -> usize {
        match self {
            Scheme::Midpoint => 0,
            Scheme::Gauss(s) => *s,
        }
    }

    /// Order of convergence at the nodes.
    pub fn order(&self) -> usize {
        match self {
            Scheme::Midpoint => 2,
            Scheme::Gauss(s) => 2 * s,
        }
    }
}

/// Butcher tableau of Gauss–Legendre collocation: nodes c, weights b,
/// matrix a (a_ij = ∫_0^{c_i} ℓ_j, b_j = ∫_0^1 ℓ_j with ℓ_j the Lagrange
/// polynomials on c).
#[derive(Clone, Debug, PartialEq)]
pub struct Tableau {
    pub c: Vec<f64>,
    pub b: Vec<f64>,
    pub a: Vec<Vec<f64>>,
}

impl Tableau {
    pub fn gauss(s: usize) -> Tableau {
        assert!((1..=8).contains(&s), "Gauss–Legendre with {s} stages");
        // The Gauss–Legendre nodes on [−1, 1], mapped to [0, 1].
        let mut c: Vec<f64> = crate::quadrature::gauss_legendre(s).0.iter().map(|z| 0.5 * (1.0 - z)).collect();
        c.sort_by(f64::total_cmp);
        // Lagrange basis in monomials: solve V coeffs = I with V_kj = c_k^j.
        let v = DMatrix::from_fn(s, s, |k, j| c[k].powi(j as i32));
        let coeffs = v.try_inverse().expect("distinct Gauss nodes"); // column j: ℓ_j's monomial coefficients
        let integral = |j: usize, upper: f64| {
            (0..s).map(|m| coeffs[(m, j)] * upper.powi(m as i32 + 1) / (m as f64 + 1.0)).sum::<f64>()
        };
        let b = (0..s).map(|j| integral(j, 1.0)).collect();
        let a = (0..s).map(|i| (0..s).map(|j| integral(j, c[i])).collect()).collect();
        Tableau { c, b, a }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: the order conditions of collocation (B(2s): Σ b_j c_j^{k−1}
    /// = 1/k, k ≤ 2s; C(s): Σ_j a_ij c_j^{k−1} = c_i^k/k, k ≤ s) and the
    /// known 2-stage nodes 1/2 ∓ √3/6.
    #[test]
    fn gauss_tableaux_satisfy_the_order_conditions() {
        for s in 1..=4 {
            let t = Tableau::gauss(s);
            for k in 1..=2 * s {
                let q: f64 = (0..s).map(|j| t.b[j] * t.c[j].powi(k as i32 - 1)).sum();
                assert!((q - 1.0 / k as f64).abs() < 1e-14, "s {s} B({k})");
            }
            for i in 0..s {
                for k in 1..=s {
                    let q: f64 = (0..s).map(|j| t.a[i][j] * t.c[j].powi(k as i32 - 1)).sum();
                    assert!((q - t.c[i].powi(k as i32) / k as f64).abs() < 1e-14, "s {s} C({k}) row {i}");
                }
            }
        }
        let t = Tableau::gauss(2);
        assert!((t.c[0] - (0.5 - 3f64.sqrt() / 6.0)).abs() < 1e-15);
    }
}

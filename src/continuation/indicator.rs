//! The ANM's series bifurcation indicator, after
//! Boutyour, Zahrouni, Potier-Ferry & Boudi, "Bifurcation points and
//! bifurcated branches by an asymptotic numerical method and Padé
//! approximants", Int. J. Numer. Meth. Engng 60 (2004): a fictitious
//! perturbation f is applied along the step's series X(a), and μ(a) is
//! the load factor that keeps the perturbed tangent problem solvable,
//!
//!   B(a) W(a) = μ(a) f,   ⟨W(a) − W_0, W_0⟩_W = 0,
//!
//! with B(a) = [[R_X(X(a))], [vᵀW]] the bordered tangent along the series
//! (v the step's border). μ vanishes where B(a) is singular — at every
//! bifurcation, simple or double (B⁻¹ f grows as 1/(a − a*) there, so μ
//! crosses zero even where two eigenvalues cross together and det B keeps
//! its sign) and nowhere else (a fold leaves the bordered B regular).
//! Expanding W and μ in a with the step's one factorisation B_0:
//!
//!   order 0: g = B_0⁻¹ f, W_0 = g/‖g‖_W, μ_0 = 1/‖g‖_W;
//!   order p: B_0 W_p = μ_p f − [K_p, 0], K_p = Σ_{r≥1} (R_X)_r W_{p−r}
//!            (the tangent series' known part, [`SeriesProblem::
//!            series_tangent_order`]); W_p = μ_p g − h_p with h_p =
//!            B_0⁻¹ [K_p, 0], and ⟨W_p, W_0⟩_W = 0 gives μ_p =
//!            ⟨h_p, W_0⟩_W / ‖g‖_W.
//!
//! One more solve per order and no factorisation: the roots of the
//! polynomial μ(a) inside the step say where a bifurcation lies, so its
//! location starts from a short bracket around them with the series'
//! own points as predictors ([`super::bifurcation::locate`]).

use super::run::Context;
use super::SeriesProblem;

/// The indicator's series for one step, with its buffers.
pub(crate) struct Indicator {
    /// The fixed perturbation f (n + 1: Λ's row, the border's, is 0).
    f: Vec<f64>,
    g: Vec<f64>,
    w0: Vec<f64>,
    h: Vec<f64>,
    wp: Vec<f64>,
    known: Vec<f64>,
    zeros: Vec<f64>,
    /// μ_p, p = 0…P.
    pub mu: Vec<f64>,
}

impl Indicator {
    /// For `n` unknowns and series order `order`. The perturbation is a
    /// fixed pseudo-random vector (a golden-ratio sequence in (−1, 1),
    /// scaled by the equation scales): generic, so that it is not
    /// orthogonal to a null direction, and the same every run.
    pub fn new(n: usize, order: usize, equation_scales: &[f64]) -> Self {
        let golden = 0.5 * (5f64.sqrt() - 1.0);
        let mut f: Vec<f64> =
            (0..n).map(|i| (2.0 * ((i as f64 + 1.0) * golden).fract() - 1.0) * equation_scales[i]).collect();
        f.push(0.0);
        Indicator {
            f,
            g: vec![0.0; n + 1],
            w0: vec![0.0; n + 1],
            h: vec![0.0; n + 1],
            wp: vec![0.0; n + 1],
            known: vec![0.0; n],
            zeros: vec![0.0; n],
            mu: vec![0.0; order + 1],
        }
    }

    /// μ_p for the series the problem has committed (every order), from
    /// the context's current factorisation (the step's B_0). False when a
    /// coefficient is not finite (no hint from this step).
    pub fn compute<P: SeriesProblem + ?Sized>(&mut self, ctx: &mut Context, problem: &mut P) -> bool {
        let n = self.known.len();
        self.g.copy_from_slice(&self.f);
        ctx.bordered.solve(&mut self.g, &mut ctx.counts);
        let norm = ctx.scaling.norm(&self.g[..n], self.g[n]);
        if !(norm > 0.0 && norm.is_finite()) {
            return false;
        }
        for (w, g) in self.w0.iter_mut().zip(&self.g) {
            *w = g / norm;
        }
        self.mu[0] = 1.0 / norm;
        problem.series_tangent_order(0, &self.w0[..n], self.w0[n], &mut self.known);
        for p in 1..self.mu.len() {
            problem.series_tangent_order(p, &self.zeros, 0.0, &mut self.known);
            self.h[..n].copy_from_slice(&self.known);
            self.h[n] = 0.0;
            ctx.bordered.solve(&mut self.h, &mut ctx.counts);
            let mu = ctx.scaling.dot(&self.h[..n], self.h[n], &self.w0[..n], self.w0[n]) / norm;
            if !mu.is_finite() {
                return false;
            }
            self.mu[p] = mu;
            for i in 0..=n {
                self.wp[i] = mu * self.g[i] - self.h[i];
            }
            problem.series_tangent_order(p, &self.wp[..n], self.wp[n], &mut self.known);
        }
        true
    }

    /// μ(a) (Horner).
    pub fn at(&self, a: f64) -> f64 {
        self.mu.iter().rev().fold(0.0, |s, c| s * a + c)
    }

    /// The roots of μ on (0, a].
    pub fn roots(&self, a: f64) -> Vec<f64> {
        crate::roots::all_roots(|t| self.at(t), a)
    }

    /// Whether μ certainly has no root on [0, a]: the polynomial keeps
    /// |μ| at least ten times its truncation estimate (its last two terms
    /// at a, the ANM's own radius rule) at 65 points of the step and
    /// changes by less than that between them (|μ'| h/2 bounded by the
    /// derivative polynomial's largest value on the samples) — the series'
    /// error cannot hide a zero there.
    pub fn clear_of_roots(&self, a: f64) -> bool {
        let p = self.mu.len() - 1;
        if p < 2 || !(a > 0.0) {
            return false;
        }
        let truncation = self.mu[p].abs() * a.powi(p as i32) + self.mu[p - 1].abs() * a.powi(p as i32 - 1);
        let derivative = |t: f64| (1..=p).rev().fold(0.0, |s, k| s * t + k as f64 * self.mu[k]);
        let samples = 64;
        let h = a / samples as f64;
        let slope = (0..=samples).map(|i| derivative(i as f64 * h).abs()).fold(0.0, f64::max);
        let low = (0..=samples).map(|i| self.at(i as f64 * h).abs()).fold(f64::INFINITY, f64::min);
        low.is_finite() && low > 10.0 * truncation + slope * h
    }
}

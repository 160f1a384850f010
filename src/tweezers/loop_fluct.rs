//! The end loop's thermal correction: the Gaussian fluctuation free energy of
//! the localised loop of a rod under tension F and torque τ, relative to the
//! straight rod, with the loop's two zero modes (its place along the chain
//! and its turn about the force axis) taken as collective coordinates
//! (doc/physics.md §3.7.3).
//!
//! At fixed torque the twist of an isotropic rod is a Gaussian field
//! independent of the centreline, so it cancels between the loop and the
//! straight rod; the centreline's grand energy is then, with the tangent t,
//!
//!   G[t] = ∫ [K_b/2 |t'|² − F t_z] ds − τ ∫ (t × t')_z/(1 + t_z) ds,        (1)
//!
//! the last term 2πτ times Fuller's writhe relative to the force axis (valid
//! while t avoids −ẑ, which the loop does for m = τ/(2√(K_b F)) > 0: its
//! lowest t_z is 2m² − 1). In the units ξ₀ = √(K_b/F) of length and √(K_b F)
//! of energy, (1) depends on m alone. The loop is the homoclinic
//! cos θ = 1 − 2(1 − m²) sech²(√(1 − m²) s), φ' = 2m/(1 + cos θ).
//!
//! Harmonic fluctuations about it, with the translation s₀ ∈ [0, L_s) and the
//! rotation φ₀ ∈ [0, 2π) integrated as collective coordinates (Jacobians
//! J_s = ‖∂t/∂s₀‖, J_φ = ‖∂t/∂φ₀‖), give the ratio of partition functions
//!
//!   Z_loop/Z_straight = e^{−ΔG/kT} (L_s/ξ₀) (√(K_b F)/kT) g(m),
//!   g(m) = J_s J_φ √(det H_straight / det′ H_loop),                           (2)
//!
//! H the Hessians of (1) on a discretised chain, det′ without the two zero
//! modes; g is a number of the continuum limit (the discretisation's powers
//! of h cancel between the Jacobians and the two missing eigenvalues). So
//! the loop's free energy is ΔG − kT ln(L_s/ξ₀) − kT ln(√(K_b F)/kT) −
//! kT ln g(m): the first log is the positional entropy already in the
//! partition function (counting length ξ₀), the others are the correction.
//!
//! The chain: sites at s_i = −S + (i + 1)h, i = 0..N, clamped to ẑ beyond
//! both ends; links carry |Δt|²/(2h) − 2m (t_a × t_b)_z/(1 + (t_a,z + t_b,z)/2)
//! (the midpoint rule for the writhe density, (t̄ × Δt)_z = (t_a × t_b)_z),
//! sites carry −h t_z. Each site's tangent moves in its own tangent plane,
//! t(x) = (t̄ + x₁e₁ + x₂e₂)/|…|, so the Hessian is block tridiagonal (2 × 2
//! blocks) and its determinant and inertia come from a block LDLᵀ.

use crate::error::{Error, Result};
use crate::status::Status;

type V3 = [f64; 3];
/// A 2 × 2 block of the Hessian in two sites' tangent planes.
type Block = [[f64; 2]; 2];

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: V3, b: V3) -> V3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn unit(a: V3) -> V3 {
    scale(a, 1.0 / dot(a, a).sqrt())
}

/// An orthonormal basis (e₁, e₂) of the plane normal to the unit vector t.
fn frame(t: V3) -> (V3, V3) {
    let helper = if t[0].abs() < 0.6 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
    let e1 = unit(add(helper, scale(t, -dot(helper, t))));
    (e1, cross(t, e1))
}

/// The discretised loop: reference tangents, their planes, and the scene.
#[derive(Clone)]
struct Chain {
    m: f64,
    h: f64,
    t: Vec<V3>,
    e: Vec<(V3, V3)>,
}

const Z: V3 = [0.0, 0.0, 1.0];

impl Chain {
    fn new(m: f64, h: f64, half_span: f64, loop_shape: bool) -> Self {
        let n = (2.0 * half_span / h).round() as usize - 1;
        let k = (1.0 - m * m).sqrt();
        let mut t = Vec::with_capacity(n);
        let mut phi = 0.0;
        let mut prev = -half_span;
        for i in 0..n {
            let s = -half_span + (i + 1) as f64 * h;
            if !loop_shape {
                t.push(Z);
                continue;
            }
            // φ' = 2m/(1 + cos θ), integrated by the midpoint rule (only a
            // starting guess: Newton below makes the discrete chain stationary).
            let mid = 0.5 * (s + prev);
            let cmid = 1.0 - 2.0 * k * k / (k * mid).cosh().powi(2);
            phi += (s - prev) * 2.0 * m / (1.0 + cmid);
            prev = s;
            let c = 1.0 - 2.0 * k * k / (k * s).cosh().powi(2);
            let sn = (1.0 - c * c).max(0.0).sqrt();
            t.push([sn * phi.cos(), sn * phi.sin(), c]);
        }
        let e = t.iter().map(|&ti| frame(ti)).collect();
        Chain { m, h, t, e }
    }

    fn moved(&self, i: usize, x: [f64; 2]) -> V3 {
        let (e1, e2) = self.e[i];
        unit(add(self.t[i], add(scale(e1, x[0]), scale(e2, x[1]))))
    }

    fn link(&self, a: V3, b: V3) -> f64 {
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        dot(d, d) / (2.0 * self.h) - 2.0 * self.m * cross(a, b)[2] / (1.0 + 0.5 * (a[2] + b[2]))
    }

    fn site(&self, a: V3) -> f64 {
        -self.h * a[2]
    }

    /// The chain's energy (1) in units of √(K_b F).
    fn energy(&self) -> f64 {
        let n = self.t.len();
        let mut e = self.link(Z, self.t[0]) + self.link(self.t[n - 1], Z);
        for i in 0..n {
            e += self.site(self.t[i]);
            if i + 1 < n {
                e += self.link(self.t[i], self.t[i + 1]);
            }
        }
        e
    }

    /// Fuller's writhe relative to ẑ, (1/2π) Σ_links N/D.
    fn writhe(&self) -> f64 {
        let n = self.t.len();
        let w = |a: V3, b: V3| cross(a, b)[2] / (1.0 + 0.5 * (a[2] + b[2]));
        let mut s = w(Z, self.t[0]) + w(self.t[n - 1], Z);
        for i in 0..n - 1 {
            s += w(self.t[i], self.t[i + 1]);
        }
        s / (2.0 * std::f64::consts::PI)
    }

    /// Gradient and Hessian in R³ × R³ of a link's energy, analytic:
    /// bending |b − a|²/(2h) and the writhe density c N/D with
    /// N = (a × b)_z, D = 1 + (a_z + b_z)/2, c = −2m.
    fn link_derivatives(&self, a: V3, b: V3) -> ([f64; 6], [[f64; 6]; 6]) {
        let c = -2.0 * self.m;
        let n = a[0] * b[1] - a[1] * b[0];
        let dd = 1.0 + 0.5 * (a[2] + b[2]);
        let dn = [b[1], -b[0], 0.0, -a[1], a[0], 0.0];
        let ddv = [0.0, 0.0, 0.5, 0.0, 0.0, 0.5];
        let mut g = [0.0; 6];
        let mut hm = [[0.0; 6]; 6];
        for p in 0..6 {
            let bend = if p < 3 { (a[p] - b[p]) / self.h } else { (b[p - 3] - a[p - 3]) / self.h };
            g[p] = bend + c * (dn[p] / dd - n * ddv[p] / (dd * dd));
            for q in 0..6 {
                let sign = if (p < 3) == (q < 3) { 1.0 } else { -1.0 };
                let bend = if p % 3 == q % 3 { sign / self.h } else { 0.0 };
                // ∂²N: ∂a_x∂b_y = 1, ∂a_y∂b_x = −1 (and symmetric).
                let d2n = match (p, q) {
                    (0, 4) | (4, 0) => 1.0,
                    (1, 3) | (3, 1) => -1.0,
                    _ => 0.0,
                };
                let w = d2n / dd - (dn[p] * ddv[q] + ddv[p] * dn[q]) / (dd * dd)
                    + 2.0 * n * ddv[p] * ddv[q] / (dd * dd * dd);
                hm[p][q] = bend + c * w;
            }
        }
        (g, hm)
    }

    /// Gradient (2 per site) and block-tridiagonal Hessian (diagonal blocks
    /// and the blocks coupling i to i + 1) at the reference (x = 0). With
    /// t(x) = (t̄ + x₁e₁ + x₂e₂)/|…|, ∂t/∂x_p = e_p and ∂²t/∂x_p∂x_q =
    /// −δ_pq t̄ at x = 0, so H_pq = e_pᵀ ∇²E e_q − δ_pq t̄·∇E.
    fn derivatives(&self) -> (Vec<f64>, Vec<Block>, Vec<Block>) {
        let n = self.t.len();
        // R³ gradient per site, R³ Hessian blocks (diagonal and i → i + 1).
        let mut g3 = vec![[0.0; 3]; n];
        let mut d3 = vec![[[0.0; 3]; 3]; n];
        let mut o3 = vec![[[0.0; 3]; 3]; n.saturating_sub(1)];
        for gi in g3.iter_mut() {
            gi[2] -= self.h;
        }
        // Links to the clamped ends (only the free side's derivatives).
        let (g, hm) = self.link_derivatives(Z, self.t[0]);
        for p in 0..3 {
            g3[0][p] += g[3 + p];
            for q in 0..3 {
                d3[0][p][q] += hm[3 + p][3 + q];
            }
        }
        let (g, hm) = self.link_derivatives(self.t[n - 1], Z);
        for p in 0..3 {
            g3[n - 1][p] += g[p];
            for q in 0..3 {
                d3[n - 1][p][q] += hm[p][q];
            }
        }
        for i in 0..n.saturating_sub(1) {
            let (g, hm) = self.link_derivatives(self.t[i], self.t[i + 1]);
            for p in 0..3 {
                g3[i][p] += g[p];
                g3[i + 1][p] += g[3 + p];
                for q in 0..3 {
                    d3[i][p][q] += hm[p][q];
                    d3[i + 1][p][q] += hm[3 + p][3 + q];
                    o3[i][p][q] += hm[p][3 + q];
                }
            }
        }
        let project = |m3: &[[f64; 3]; 3], u: (V3, V3), v: (V3, V3)| {
            let us = [u.0, u.1];
            let vs = [v.0, v.1];
            let mut r = [[0.0; 2]; 2];
            for p in 0..2 {
                for q in 0..2 {
                    let mut s = 0.0;
                    for k in 0..3 {
                        for l in 0..3 {
                            s += us[p][k] * m3[k][l] * vs[q][l];
                        }
                    }
                    r[p][q] = s;
                }
            }
            r
        };
        let mut g2 = vec![0.0; 2 * n];
        let mut d2 = vec![[[0.0; 2]; 2]; n];
        let mut o2 = vec![[[0.0; 2]; 2]; n.saturating_sub(1)];
        for i in 0..n {
            let (e1, e2) = self.e[i];
            g2[2 * i] = dot(g3[i], e1);
            g2[2 * i + 1] = dot(g3[i], e2);
            d2[i] = project(&d3[i], self.e[i], self.e[i]);
            let tg = dot(self.t[i], g3[i]);
            d2[i][0][0] -= tg;
            d2[i][1][1] -= tg;
            if i + 1 < n {
                o2[i] = project(&o3[i], self.e[i], self.e[i + 1]);
            }
        }
        (g2, d2, o2)
    }

    /// The gradient of Fuller's writhe (1/2π) Σ N/D in the tangent planes.
    fn writhe_gradient(&self) -> Vec<f64> {
        let n = self.t.len();
        let mut g3 = vec![[0.0; 3]; n];
        let mut add_link = |ia: Option<usize>, ib: Option<usize>| {
            let a = ia.map_or(Z, |i| self.t[i]);
            let b = ib.map_or(Z, |i| self.t[i]);
            let nn = a[0] * b[1] - a[1] * b[0];
            let dd = 1.0 + 0.5 * (a[2] + b[2]);
            let dn = [b[1], -b[0], 0.0, -a[1], a[0], 0.0];
            let ddv = [0.0, 0.0, 0.5, 0.0, 0.0, 0.5];
            for p in 0..6 {
                let v = (dn[p] / dd - nn * ddv[p] / (dd * dd)) / (2.0 * std::f64::consts::PI);
                match (p < 3, ia, ib) {
                    (true, Some(i), _) => g3[i][p] += v,
                    (false, _, Some(i)) => g3[i][p - 3] += v,
                    _ => {}
                }
            }
        };
        add_link(None, Some(0));
        add_link(Some(n - 1), None);
        for i in 0..n - 1 {
            add_link(Some(i), Some(i + 1));
        }
        let mut g = vec![0.0; 2 * n];
        for i in 0..n {
            g[2 * i] = dot(g3[i], self.e[i].0);
            g[2 * i + 1] = dot(g3[i], self.e[i].1);
        }
        g
    }

    /// Move every site by its local step and refresh the planes.
    fn step(&mut self, x: &[f64]) {
        for i in 0..self.t.len() {
            self.t[i] = self.moved(i, [x[2 * i], x[2 * i + 1]]);
            self.e[i] = frame(self.t[i]);
        }
    }
}

fn det2(a: &[[f64; 2]; 2]) -> f64 {
    a[0][0] * a[1][1] - a[0][1] * a[1][0]
}

fn inv2(a: &[[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let d = det2(a);
    [[a[1][1] / d, -a[0][1] / d], [-a[1][0] / d, a[0][0] / d]]
}

fn mul2(a: &[[f64; 2]; 2], b: &[[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let mut c = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j];
        }
    }
    c
}

fn mv2(a: &[[f64; 2]; 2], x: [f64; 2]) -> [f64; 2] {
    [a[0][0] * x[0] + a[0][1] * x[1], a[1][0] * x[0] + a[1][1] * x[1]]
}

fn tr2(a: &[[f64; 2]; 2]) -> [[f64; 2]; 2] {
    [[a[0][0], a[1][0]], [a[0][1], a[1][1]]]
}

/// Block LDLᵀ of the symmetric block-tridiagonal H − σI (diagonal blocks
/// `d`, super-diagonal blocks `off`): the pivots D_i = A_i − B_{i−1}ᵀ
/// D_{i−1}⁻¹ B_{i−1}. Sylvester's law: H − σI has as many negative
/// eigenvalues as the pivots.
struct BlockLdl {
    piv: Vec<Block>,
    /// D_i⁻¹, formed once here for the eliminations and every solve.
    inv: Vec<Block>,
    off: Vec<Block>,
}

impl BlockLdl {
    fn new(d: &[Block], off: &[Block], sigma: f64) -> Result<Self> {
        let mut piv = Vec::with_capacity(d.len());
        let mut inv: Vec<Block> = Vec::with_capacity(d.len());
        for i in 0..d.len() {
            let mut a = d[i];
            a[0][0] -= sigma;
            a[1][1] -= sigma;
            if i > 0 {
                let b = off[i - 1];
                let s = mul2(&tr2(&b), &mul2(&inv[i - 1], &b));
                for p in 0..2 {
                    for q in 0..2 {
                        a[p][q] -= s[p][q];
                    }
                }
            }
            if !(det2(&a).abs() > 0.0) || !det2(&a).is_finite() {
                return Err(Error::new(Status::ErrNotConverged, "loop Hessian: a singular pivot block"));
            }
            inv.push(inv2(&a));
            piv.push(a);
        }
        Ok(BlockLdl { piv, inv, off: off.to_vec() })
    }

    /// ln |det| and the number of negative eigenvalues.
    fn log_det(&self) -> (f64, usize) {
        let mut l = 0.0;
        let mut neg = 0;
        for p in &self.piv {
            let dt = det2(p);
            l += dt.abs().ln();
            let tr = p[0][0] + p[1][1];
            neg += if dt < 0.0 {
                1
            } else if tr < 0.0 {
                2
            } else {
                0
            };
        }
        (l, neg)
    }

    /// Solve (H − σI) x = b in place.
    fn solve(&self, b: &mut [f64]) {
        let n = self.piv.len();
        // Forward: y_i = b_i − B_{i−1}ᵀ D_{i−1}⁻¹ y_{i−1}.
        for i in 1..n {
            let w = mv2(&self.inv[i - 1], [b[2 * i - 2], b[2 * i - 1]]);
            let c = mv2(&tr2(&self.off[i - 1]), w);
            b[2 * i] -= c[0];
            b[2 * i + 1] -= c[1];
        }
        // Backward: x_i = D_i⁻¹ (y_i − B_i x_{i+1}).
        for i in (0..n).rev() {
            let mut r = [b[2 * i], b[2 * i + 1]];
            if i + 1 < n {
                let c = mv2(&self.off[i], [b[2 * i + 2], b[2 * i + 3]]);
                r[0] -= c[0];
                r[1] -= c[1];
            }
            let x = mv2(&self.inv[i], r);
            b[2 * i] = x[0];
            b[2 * i + 1] = x[1];
        }
    }
}

fn matvec(d: &[[[f64; 2]; 2]], off: &[[[f64; 2]; 2]], x: &[f64]) -> Vec<f64> {
    let n = d.len();
    let mut y = vec![0.0; 2 * n];
    for i in 0..n {
        let a = mv2(&d[i], [x[2 * i], x[2 * i + 1]]);
        y[2 * i] += a[0];
        y[2 * i + 1] += a[1];
        if i + 1 < n {
            let b = mv2(&off[i], [x[2 * i + 2], x[2 * i + 3]]);
            y[2 * i] += b[0];
            y[2 * i + 1] += b[1];
            let c = mv2(&tr2(&off[i]), [x[2 * i], x[2 * i + 1]]);
            y[2 * i + 2] += c[0];
            y[2 * i + 3] += c[1];
        }
    }
    y
}

/// The loop's fluctuation factor, its ingredients and checks.
#[derive(Clone, Copy, Debug)]
pub struct LoopFluctuation {
    /// ln g(m) of (3): J_s J_φ √(det H_straight / det″ H_loop)/|∇Wr·v|.
    pub ln_g: f64,
    /// The discrete loop's grand energy relative to the straight chain, in
    /// units of √(K_b F) (the continuum: 8√(1 − m²) − 8m arccos m).
    pub energy: f64,
    /// The loop's writhe (the continuum: (2/π) arccos m).
    pub writhe: f64,
    /// The two eigenvalues taken as zero modes, the growth mode's (negative)
    /// and the smallest kept one (units √(K_b F)).
    pub zero_modes: [f64; 2],
    pub growth: f64,
    pub smallest_kept: f64,
    /// Negative eigenvalues of the loop's Hessian besides the growth mode
    /// (0 for a loop that is a nucleus: one unstable direction only).
    pub unstable: usize,
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn inner(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Compute g(m) on a chain of spacing h over [−S, S] (units ξ₀). Newton
/// makes the discrete loop stationary first, so the Hessian is the second
/// variation (no gradient term in the tangent planes).
///
/// At fixed torque the loop is a saddle: one direction (it tightens,
/// absorbing writhe, or opens back to the straight rod) lowers G. That
/// direction is the plectoneme's growth, which the two-phase partition
/// function integrates as its length ℓ_p; so it leaves the Gaussian
/// product with the zero modes and enters as a collective coordinate c
/// along its unit eigenvector v, dc = dWr/|∇Wr·v| = w dℓ_p/|∇Wr·v| (w the
/// plectoneme's writhe per length). Per loop, the partition function gains
///
///   (L_s/ξ₀)(dℓ_p/ξ₀) · (w ξ₀) (kT/√(K_b F))^{−3/2} (2π)^{−1/2} g(m),        (3)
///
/// g(m) as in [`LoopFluctuation::ln_g`], a continuum number (the powers of h
/// cancel: J_s J_φ ∝ h⁻¹, ∇Wr·v ∝ h^{1/2}, three eigenvalues ∝ h each).
pub fn fluctuation(m: f64, h: f64, half_span: f64) -> Result<LoopFluctuation> {
    if !(m > 0.0 && m < 1.0 && h > 0.0 && half_span > 10.0 * h && half_span / h <= 1e6) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!("loop fluctuation: need 0 < m < 1, h > 0, 10h < S < 1e6 h (m {m}, h {h}, S {half_span})"),
        ));
    }
    let mut chain = Chain::new(m, h, half_span, true);
    let mut converged = false;
    for _ in 0..60 {
        let (g, d, off) = chain.derivatives();
        if norm(&g) < 1e-11 {
            converged = true;
            break;
        }
        // Levenberg shift: the two zero modes make H singular; a small shift
        // leaves the step along them negligible (their gradient is zero).
        // The loop is a saddle, so the merit is the gradient's norm: halve
        // the step until it falls.
        let ldl = BlockLdl::new(&d, &off, -1e-7)?;
        let mut x: Vec<f64> = g.iter().map(|v| -v).collect();
        ldl.solve(&mut x);
        let g0 = norm(&g);
        let mut trial = chain.clone();
        for _ in 0..20 {
            trial.t.clone_from(&chain.t);
            trial.e.clone_from(&chain.e);
            trial.step(&x);
            if norm(&trial.derivatives().0) < g0 {
                break;
            }
            x.iter_mut().for_each(|v| *v *= 0.5);
        }
        std::mem::swap(&mut chain, &mut trial);
    }
    if !converged {
        return Err(Error::new(
            Status::ErrNotConverged,
            format!("loop fluctuation: Newton did not converge at m = {m}"),
        ));
    }
    let (_, d, off) = chain.derivatives();
    let n = chain.t.len();
    let count = |sigma: f64| -> Result<usize> { Ok(BlockLdl::new(&d, &off, sigma)?.log_det().1) };
    // The zero modes by subspace inverse iteration on a factorisation
    // shifted just below them, started from the continuum modes ∂t/∂s and
    // ẑ × t, Rayleigh–Ritz on the pair.
    let sigma = -1e-8;
    let ldl = BlockLdl::new(&d, &off, sigma)?;
    let mut tx = vec![0.0; 2 * n];
    let mut ty = vec![0.0; 2 * n];
    for i in 0..n {
        let prev = if i == 0 { Z } else { chain.t[i - 1] };
        let next = if i + 1 == n { Z } else { chain.t[i + 1] };
        let ds = scale(add(next, scale(prev, -1.0)), 0.5 / h);
        let rot = cross(Z, chain.t[i]);
        let (e1, e2) = chain.e[i];
        tx[2 * i] = dot(ds, e1);
        tx[2 * i + 1] = dot(ds, e2);
        ty[2 * i] = dot(rot, e1);
        ty[2 * i + 1] = dot(rot, e2);
    }
    let (j_s, j_phi) = (norm(&tx), norm(&ty));
    let (mut u, mut v) = (tx, ty);
    for _ in 0..4 {
        ldl.solve(&mut u);
        ldl.solve(&mut v);
        let nu = norm(&u);
        u.iter_mut().for_each(|x| *x /= nu);
        let p = inner(&u, &v);
        v.iter_mut().zip(&u).for_each(|(b, a)| *b -= p * a);
        let nv = norm(&v);
        v.iter_mut().for_each(|x| *x /= nv);
    }
    let (hu, hv) = (matvec(&d, &off, &u), matvec(&d, &off, &v));
    let (a11, a22, a12) = (inner(&u, &hu), inner(&v, &hv), inner(&u, &hv));
    let mean = 0.5 * (a11 + a22);
    let rad = (0.25 * (a11 - a22).powi(2) + a12 * a12).sqrt();
    let zero = [mean - rad, mean + rad];
    let (ln_det_shifted, neg) = ldl.log_det();
    // The growth mode: the most negative eigenvalue, bracketed by
    // bisection on the inertia (Sylvester) below the zero modes, then its
    // vector by inverse iteration.
    let below_zero = neg - zero.iter().filter(|&&z| z < sigma).count();
    if below_zero == 0 {
        return Err(Error::new(Status::ErrNotConverged, format!("loop fluctuation: no growth mode at m = {m}")));
    }
    let (mut lo, mut hi) = (-(8.0 / h + 4.0 * h + 8.0), -1e-6);
    if count(lo)? != 0 || count(hi)? == 0 {
        return Err(Error::new(Status::ErrNotConverged, "loop fluctuation: the growth mode is not bracketed"));
    }
    for _ in 0..80 {
        let c = 0.5 * (lo + hi);
        if count(c)? == 0 {
            lo = c;
        } else {
            hi = c;
        }
        if hi - lo < 1e-13 * hi.abs() {
            break;
        }
    }
    let shift = lo - 1e-6 * lo.abs();
    let gl = BlockLdl::new(&d, &off, shift)?;
    let mut w: Vec<f64> = (0..2 * n).map(|i| 1.0 + ((i * 7919) % 101) as f64 / 101.0).collect();
    for _ in 0..6 {
        gl.solve(&mut w);
        let nw = norm(&w);
        w.iter_mut().for_each(|x| *x /= nw);
    }
    let growth = inner(&w, &matvec(&d, &off, &w));
    let dwr = inner(&chain.writhe_gradient(), &w).abs();
    // The smallest kept eigenvalue (a check that the kept spectrum is
    // positive and resolved): inverse iteration deflated of the three.
    let mut k: Vec<f64> = (0..2 * n).map(|i| ((i * 104729) % 97) as f64 / 97.0 - 0.5).collect();
    let mut kept = 0.0;
    for _ in 0..30 {
        for q in [&u, &v, &w] {
            let p = inner(&k, q);
            k.iter_mut().zip(q.iter()).for_each(|(a, b)| *a -= p * b);
        }
        let nk = norm(&k);
        k.iter_mut().for_each(|x| *x /= nk);
        kept = inner(&k, &matvec(&d, &off, &k));
        ldl.solve(&mut k);
    }
    // det″ H = det(H − σI)/Π_removed (λ − σ) · Π_kept λ/(λ − σ); the last
    // product is 1 − O(σ Σ 1/λ), below 1e-8 here.
    let ln_det_loop =
        ln_det_shifted - (zero[0] - sigma).abs().ln() - (zero[1] - sigma).abs().ln() - (growth - sigma).abs().ln();
    let straight = Chain::new(m, h, half_span, false);
    let (_, d0, off0) = straight.derivatives();
    let (ln_det_straight, neg0) = BlockLdl::new(&d0, &off0, sigma)?.log_det();
    if neg0 != 0 {
        return Err(Error::new(Status::ErrNotConverged, "loop fluctuation: the straight chain is unstable"));
    }
    let energy = chain.energy() - straight.energy();
    let writhe = chain.writhe();
    let ln_g = j_s.ln() + j_phi.ln() + 0.5 * (ln_det_straight - ln_det_loop) - dwr.ln();
    if !ln_g.is_finite() {
        return Err(Error::new(Status::ErrNotFinite, "loop fluctuation: non-finite determinant"));
    }
    Ok(LoopFluctuation {
        ln_g,
        energy,
        writhe,
        zero_modes: zero,
        growth,
        smallest_kept: kept,
        unstable: below_zero - 1,
    })
}

/// The shipped table of ln g over the loop's m: Chebyshev–Lobatto nodes in
/// x = ln √(1 − m²) (g ∝ (1 − m²)^{7/4} as m → 1, smooth in x), each value
/// the Richardson extrapolation 2 g(h) − g(2h) of h = 0.01, 0.02 (the
/// discretisation error is first order in h), with its error estimated as
/// the difference from the extrapolation of h = 0.02, 0.04. Regenerated by
/// `cargo test --release --test tweezers_loop -- --ignored regenerate_loop_table`.
pub const TABLE_CSV: &str = include_str!("loop_fluct.csv");

/// The table's range in m (outside: the end values, see [`LnG::eval`]).
pub const M_MIN: f64 = 0.1;
pub const M_MAX: f64 = 0.99;
/// Chebyshev degree of the table.
pub const TABLE_DEGREE: usize = 20;

/// The table's variable x = ln √(1 − m²).
fn table_variable(m: f64) -> f64 {
    (1.0 - m * m).sqrt().ln()
}

/// The table's nodes m_j (descending in x = ln √(1 − m²), i.e. ascending in m).
pub fn table_nodes() -> Vec<f64> {
    let x = table_variable;
    super::cheb::points(TABLE_DEGREE, x(M_MAX), x(M_MIN)).into_iter().map(|x| (1.0 - (2.0 * x).exp()).sqrt()).collect()
}

/// One table row: (m, ln g, error estimate).
pub fn table_row(m: f64) -> Result<(f64, f64, f64)> {
    let span = 24.0 / (1.0 - m * m).sqrt();
    let g = |h: f64| fluctuation(m, h, span).map(|f| f.ln_g);
    let (g4, g2, g1) = (g(0.04)?, g(0.02)?, g(0.01)?);
    let fine = 2.0 * g1 - g2;
    Ok((m, fine, (fine - (2.0 * g2 - g4)).abs()))
}

/// The table as CSV text (the shipped file's format).
pub fn table_csv() -> Result<String> {
    let mut s = String::from(
        "# ln g(m) of the end loop's fluctuation factor (src/tweezers/loop_fluct.rs, eq. (3)), at the\n\
         # Chebyshev-Lobatto nodes in ln sqrt(1 - m^2); Richardson 2 g(0.01) - g(0.02) on [-24/k, 24/k];\n\
         # err = |that - (2 g(0.02) - g(0.04))|. Regenerate: cargo test --release --test tweezers_loop\n\
         # -- --ignored regenerate_loop_table\nm,ln_g,err\n",
    );
    for m in table_nodes() {
        let (m, v, e) = table_row(m)?;
        s.push_str(&format!("{m:.15e},{v:.12e},{e:.3e}\n"));
    }
    Ok(s)
}

/// ln g(m) from the shipped table: a Chebyshev series in x = ln √(1 − m²).
#[derive(Clone, Debug)]
pub struct LnG {
    series: super::cheb::Series,
    slope: super::cheb::Series,
    /// The largest error estimate in the table.
    pub error: f64,
}

impl LnG {
    /// Parse the shipped table (the nodes must be [`table_nodes`]).
    pub fn shipped() -> Result<&'static LnG> {
        static TABLE: std::sync::OnceLock<std::result::Result<LnG, String>> = std::sync::OnceLock::new();
        TABLE
            .get_or_init(|| LnG::parse(TABLE_CSV).map_err(|e| e.to_string()))
            .as_ref()
            .map_err(|e| Error::new(Status::ErrInternal, format!("the shipped loop table: {e}")))
    }

    pub fn parse(text: &str) -> Result<LnG> {
        let bad = |why: &str| Error::new(Status::ErrIo, format!("loop fluctuation table: {why}"));
        let mut vals = Vec::new();
        let mut error: f64 = 0.0;
        for line in text.lines().filter(|l| !l.starts_with('#') && !l.starts_with('m') && !l.trim().is_empty()) {
            let c: Vec<f64> = line
                .split(',')
                .map(|x| x.trim().parse::<f64>())
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| bad("a number does not parse"))?;
            if c.len() != 3 || !c.iter().all(|v| v.is_finite()) {
                return Err(bad("a row is not three finite numbers"));
            }
            vals.push((c[0], c[1]));
            error = error.max(c[2]);
        }
        let nodes = table_nodes();
        if vals.len() != nodes.len() || vals.iter().zip(&nodes).any(|(v, m)| (v.0 - m).abs() > 1e-12) {
            return Err(bad("the rows are not the table's nodes"));
        }
        let x = table_variable;
        let values: Vec<f64> = vals.iter().map(|v| v.1).collect();
        let series = super::cheb::Series::interpolate(x(M_MAX), x(M_MIN), &values);
        Ok(LnG { slope: series.derivative(), series, error })
    }

    /// ln g and d ln g/dm. Below M_MIN, the value at M_MIN (Fuller's writhe
    /// needs the tangent away from −ẑ, whose distance 2m² vanishes there;
    /// such loops carry low torque and negligible weight); above M_MAX, the
    /// series continued linearly in ln √(1 − m²) (g → 0 as the loop spreads
    /// out and vanishes at m = 1).
    pub fn eval(&self, m: f64) -> (f64, f64) {
        let m = m.max(M_MIN);
        let x = table_variable;
        // dx/dm = −m/(1 − m²).
        if m >= M_MAX {
            let (x0, s) = (x(M_MAX), self.slope.eval(x(M_MAX)));
            if m >= 1.0 {
                return (f64::NEG_INFINITY, 0.0);
            }
            return (self.series.eval(x0) + s * (x(m) - x0), s * (-m / (1.0 - m * m)));
        }
        if m <= M_MIN {
            return (self.series.eval(x(M_MIN)), 0.0);
        }
        (self.series.eval(x(m)), self.slope.eval(x(m)) * (-m / (1.0 - m * m)))
    }
}

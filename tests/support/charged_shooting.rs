//! The charged Kirchhoff rod's equilibrium from the other side: the
//! continuous equations of physics.md §3.1–3.2 written here from the text,
//! integrated by IDA in s and shot by KINSOL, with the electrostatic force
//! density computed here from the previous trajectory and iterated to a
//! fixed point. Nothing of rodkit's residual, Jacobian or quadrature is
//! used; rodkit's state only supplies the first trajectory (the fixed point
//! owes it nothing else).
//!
//! The model is rodkit's, as physics.md defines it, for a uniform charge,
//! Debye–Hückel without a cutoff and the near zone cut at exactly δ:
//! - K_b(s) = K_b + ΔK(s), ΔK = (λ²/24)Σ_sides [J₁(a, ℓ) + κJ₂(a, ℓ)],
//!   ℓ = min(δ, the side's length to the end), J_n = ∫_a^ℓ hⁿe^{−κh}dh (the
//!   near zone's expansion, one-sided within δ of an end);
//! - f(s) = λ² ∫_{|t−s|>δ} g(d)(r(s) − r(t)) dt, g = e^{−κd}(1 + κd)/d³, the
//!   far zone's force density with the exact kernel (Φ = e^{−κd}/d);
//! - r′ = d₃, d_i′ = ω × d_i with ω = u₁d₁ + u₂d₂ + u₃d₃, u₁,₂ = m·d₁,₂/K_b(s),
//!   u₃ = m·d₃/C; n′ = −f, m′ = −d₃ × n;
//! - clamped at s = 0 (r = 0, d_i = e_i); at s = L on the axis (x = y = 0),
//!   rotated by φ about it (d₃ = e₃, d₁ ⟂ (−sin φ, cos φ, 0)), axial force F.
#![allow(dead_code)]

use crate::sundials::{ida_solve, kinsol_solve, Context, IdaOptions, KinsolOptions, Strategy};
use rodkit::quadrature::gauss_legendre;

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// A centreline on a grid of arc lengths: positions and unit tangents,
/// read between grid points as the cubic Hermite interpolant.
#[derive(Clone, Debug)]
pub struct Trajectory {
    pub s: Vec<f64>,
    pub r: Vec<[f64; 3]>,
    pub t: Vec<[f64; 3]>,
}

impl Trajectory {
    /// From positions at increasing arc lengths `s` (any spacing, ≥ 6):
    /// values and tangents on `grid` from the local six-point Lagrange
    /// interpolant.
    pub fn from_points(s: &[f64], r: &[[f64; 3]], grid: &[f64]) -> Self {
        let mut out = Trajectory { s: grid.to_vec(), r: vec![], t: vec![] };
        for &x in grid {
            let k = s.partition_point(|&v| v < x);
            let lo = k.saturating_sub(3).min(s.len() - 6);
            let w = &s[lo..lo + 6];
            let (mut p, mut dp) = ([0.0; 3], [0.0; 3]);
            for j in 0..6 {
                let mut l = 1.0;
                let mut dl = 0.0;
                for m in (0..6).filter(|&m| m != j) {
                    let mut term = 1.0 / (w[j] - w[m]);
                    for q in (0..6).filter(|&q| q != j && q != m) {
                        term *= (x - w[q]) / (w[j] - w[q]);
                    }
                    dl += term;
                    l *= (x - w[m]) / (w[j] - w[m]);
                }
                for c in 0..3 {
                    p[c] += l * r[lo + j][c];
                    dp[c] += dl * r[lo + j][c];
                }
            }
            out.r.push(p);
            out.t.push(dp);
        }
        out
    }

    fn at(&self, x: f64) -> [f64; 3] {
        let k = self.s.partition_point(|&v| v < x).clamp(1, self.s.len() - 1);
        let (s0, s1) = (self.s[k - 1], self.s[k]);
        let h = s1 - s0;
        let u = (x - s0) / h;
        let (h00, h10, h01, h11) = (
            2.0 * u * u * u - 3.0 * u * u + 1.0,
            u * u * u - 2.0 * u * u + u,
            -2.0 * u * u * u + 3.0 * u * u,
            u * u * u - u * u,
        );
        let mut p = [0.0; 3];
        for c in 0..3 {
            p[c] = h00 * self.r[k - 1][c] + h10 * h * self.t[k - 1][c] + h01 * self.r[k][c] + h11 * h * self.t[k][c];
        }
        p
    }
}

/// The model's constants (nm, pN).
#[derive(Clone, Copy, Debug)]
pub struct ChargedRodModel {
    pub length: f64,
    pub bending: f64,
    pub twist: f64,
    pub tension: f64,
    /// λ with the energy ½λ²∫∫Φ.
    pub line_charge: f64,
    pub kappa: f64,
    pub a: f64,
    /// The near zone's width δ.
    pub delta: f64,
}

/// A converged shot: the state (r, d₁, d₂, d₃, n, m) at the requested arc
/// lengths, and how far the last fixed-point iteration moved the centreline.
pub struct Shot {
    pub states: Vec<[f64; 18]>,
    pub last_change: f64,
    pub iterations: usize,
}

impl ChargedRodModel {
    /// ∫_a^ℓ h e^{−κh} dh and ∫_a^ℓ h² e^{−κh} dh (0 when ℓ ≤ a).
    fn j12(&self, l: f64) -> (f64, f64) {
        let (k, a) = (self.kappa, self.a);
        if l <= a {
            return (0.0, 0.0);
        }
        let p1 = |h: f64| -(-k * h).exp() * (k * h + 1.0) / (k * k);
        let p2 = |h: f64| -(-k * h).exp() * (k * k * h * h + 2.0 * k * h + 2.0) / (k * k * k);
        (p1(l) - p1(a), p2(l) - p2(a))
    }

    /// K_b + ΔK(s).
    pub fn bending_at(&self, s: f64) -> f64 {
        let mut dk = 0.0;
        for side in [s, self.length - s] {
            let (j1, j2) = self.j12(side.min(self.delta));
            dk += j1 + self.kappa * j2;
        }
        self.bending + self.line_charge * self.line_charge / 24.0 * dk
    }

    /// The far-zone force density at s on trajectory `tr`.
    fn far_force(&self, tr: &Trajectory, s: f64, gl: &(Vec<f64>, Vec<f64>)) -> [f64; 3] {
        let rs = tr.at(s);
        let mut f = [0.0; 3];
        for (lo, hi) in [(0.0, s - self.delta), (s + self.delta, self.length)] {
            if hi <= lo {
                continue;
            }
            let panels = ((hi - lo) / 0.5).ceil().max(1.0) as usize;
            let w = (hi - lo) / panels as f64;
            for p in 0..panels {
                let c = lo + (p as f64 + 0.5) * w;
                for (x, wx) in gl.0.iter().zip(&gl.1) {
                    let rt = tr.at(c + 0.5 * w * x);
                    let dr = sub(rs, rt);
                    let d = dot(dr, dr).sqrt();
                    let g = (-self.kappa * d).exp() * (1.0 + self.kappa * d) / (d * d * d);
                    for k in 0..3 {
                        f[k] += 0.5 * w * wx * g * dr[k];
                    }
                }
            }
        }
        let l2 = self.line_charge * self.line_charge;
        [l2 * f[0], l2 * f[1], l2 * f[2]]
    }

    /// y′ for y = (r, d₁, d₂, d₃, n, m) under the force density `f`.
    fn rates(&self, s: f64, y: &[f64], f: [f64; 3], out: &mut [f64]) {
        let v = |i: usize| [y[i], y[i + 1], y[i + 2]];
        let (d1, d2, d3, n, m) = (v(3), v(6), v(9), v(12), v(15));
        let kb = self.bending_at(s);
        let (u1, u2, u3) = (dot(m, d1) / kb, dot(m, d2) / kb, dot(m, d3) / self.twist);
        let omega = [0, 1, 2].map(|c| u1 * d1[c] + u2 * d2[c] + u3 * d3[c]);
        out[0..3].copy_from_slice(&d3);
        out[3..6].copy_from_slice(&cross(omega, d1));
        out[6..9].copy_from_slice(&cross(omega, d2));
        out[9..12].copy_from_slice(&cross(omega, d3));
        out[12..15].copy_from_slice(&[-f[0], -f[1], -f[2]]);
        out[15..18].copy_from_slice(&cross(n, d3));
    }

    /// Integrate from the clamp with base force and moment `nm` under the
    /// tabulated force, returning the states at `at` (increasing, > 0).
    fn integrate(&self, ctx: &Context, nm: &[f64; 6], force: &ForceTable, at: &[f64]) -> Result<Vec<Vec<f64>>, String> {
        let mut y0 = vec![0.0; 18];
        (y0[3], y0[7], y0[11]) = (1.0, 1.0, 1.0);
        y0[12..18].copy_from_slice(nm);
        let mut yp0 = vec![0.0; 18];
        self.rates(0.0, &y0, force.at(0.0), &mut yp0);
        let mut rate = vec![0.0; 18];
        let residual = |s: f64, y: &[f64], yp: &[f64], res: &mut [f64]| {
            self.rates(s, y, force.at(s), &mut rate);
            for k in 0..18 {
                res[k] = yp[k] - rate[k];
            }
        };
        let opts = IdaOptions { rtol: 1e-12, atol: 1e-12, ..Default::default() };
        Ok(ida_solve(ctx, 0.0, &y0, &yp0, &[1.0; 18], residual, None, &opts, at)?.y)
    }

    /// The fixed point: from trajectory `first`, base force and moment
    /// `guess` and end rotation `phi`, alternately tabulate the force on
    /// the last trajectory and shoot (KINSOL on the six end conditions),
    /// until the centreline moves by less than `tol` (nm) at the grid.
    /// Returns the states at `at`.
    pub fn solve(
        &self,
        ctx: &Context,
        first: Trajectory,
        guess: [f64; 6],
        phi: f64,
        tol: f64,
        at: &[f64],
    ) -> Result<Shot, String> {
        let grid = first.s.clone();
        let gl = gauss_legendre(8);
        let (f_scale, m_scale) = (self.tension, (self.bending * self.tension).sqrt());
        let ell = (self.bending / self.tension).sqrt();
        let mut u: Vec<f64> = (0..6).map(|k| if k < 3 { guess[k] / f_scale } else { guess[k] / m_scale }).collect();
        let unpack =
            |u: &[f64]| -> [f64; 6] { [0, 1, 2, 3, 4, 5].map(|k| u[k] * if k < 3 { f_scale } else { m_scale }) };
        let flat = |tr: &Trajectory| -> Vec<f64> { tr.r.iter().chain(&tr.t).flat_map(|v| *v).collect() };
        let unflat = |v: &[f64]| -> Trajectory {
            let n = grid.len();
            let vec3 = |k: usize| [v[3 * k], v[3 * k + 1], v[3 * k + 2]];
            Trajectory { s: grid.clone(), r: (0..n).map(vec3).collect(), t: (n..2 * n).map(vec3).collect() }
        };
        let mut x = flat(&first);
        // Anderson acceleration of the fixed point x = G(x) (G: tabulate the
        // force on x, shoot, read the new trajectory): the plain iteration
        // contracts by only ~0.8 a step on buckled states near the
        // bifurcation, where the soft mode barely resists the repulsion.
        let mut history: Vec<(Vec<f64>, Vec<f64>)> = vec![];
        let mut last_change = f64::INFINITY;
        for iteration in 1..=MAX_ITERATIONS {
            let tr = unflat(&x);
            let force = ForceTable::new(self, &tr, &gl);
            let ends = |u: &[f64], f: &mut [f64]| {
                let y = self.integrate(ctx, &unpack(u), &force, &[self.length]).expect("IDA integrates");
                let y = &y[0];
                f[0] = y[0] / ell;
                f[1] = y[1] / ell;
                f[2] = (y[14] - self.tension) / f_scale;
                f[3] = y[9];
                f[4] = y[10];
                f[5] = -phi.sin() * y[3] + phi.cos() * y[4];
            };
            // Full Newton steps (from the last fixed-point iterate the start
            // is close; a line search only stalls on the IDA-computed ends'
            // ~1e-10 noise).
            let opts = KinsolOptions {
                strategy: Strategy::None,
                func_norm_tol: 3e-9,
                scaled_step_tol: 1e-15,
                max_setup_calls: 1,
                ..Default::default()
            };
            kinsol_solve(ctx, &mut u, ends, None, &opts).map_err(|e| format!("iteration {iteration}: {e}"))?;
            let ys = self.integrate(ctx, &unpack(&u), &force, &grid[1..])?;
            let mut next = Trajectory { s: grid.clone(), r: vec![[0.0; 3]], t: vec![[0.0, 0.0, 1.0]] };
            for y in &ys {
                next.r.push([y[0], y[1], y[2]]);
                next.t.push([y[9], y[10], y[11]]);
            }
            last_change =
                next.r.iter().zip(&tr.r).map(|(p, q)| dot(sub(*p, *q), sub(*p, *q)).sqrt()).fold(0.0, f64::max);
            if last_change < tol {
                let states = self
                    .integrate(ctx, &unpack(&u), &force, at)?
                    .into_iter()
                    .map(|y| std::array::from_fn(|k| y[k]))
                    .collect();
                return Ok(Shot { states, last_change, iterations: iteration });
            }
            let g = flat(&next);
            history.push((x.clone(), g.clone()));
            if history.len() > MEMORY + 1 {
                history.remove(0);
            }
            x = anderson(&history);
        }
        Err(format!("no fixed point in {MAX_ITERATIONS} iterations (last change {last_change:e} nm)"))
    }
}

/// Fixed-point iterations at most, and the Anderson memory.
const MAX_ITERATIONS: usize = 30;
const MEMORY: usize = 4;

/// The next Anderson iterate from the history of (x_k, G(x_k)): with
/// f = G(x) − x, γ minimises |f_k − Σ_j γ_j (f_{j+1} − f_j)| and the iterate is
/// G(x_k) − Σ_j γ_j (G(x_{j+1}) − G(x_j)).
fn anderson(history: &[(Vec<f64>, Vec<f64>)]) -> Vec<f64> {
    let last = history.len() - 1;
    let f = |k: usize| -> Vec<f64> { history[k].1.iter().zip(&history[k].0).map(|(g, x)| g - x).collect() };
    if last == 0 {
        return history[0].1.clone();
    }
    let n = history[0].0.len();
    let fk = f(last);
    let mut df = nalgebra::DMatrix::zeros(n, last);
    let mut dg = nalgebra::DMatrix::zeros(n, last);
    for j in 0..last {
        let (a, b) = (f(j), f(j + 1));
        for i in 0..n {
            df[(i, j)] = b[i] - a[i];
            dg[(i, j)] = history[j + 1].1[i] - history[j].1[i];
        }
    }
    let rhs = nalgebra::DVector::from_vec(fk);
    let gamma = df.svd(true, true).solve(&rhs, 1e-12).expect("a least-squares solve");
    let step = dg * gamma;
    history[last].1.iter().zip(step.iter()).map(|(g, s)| g - s).collect()
}

/// The far-zone force density on a grid (with the near zone's edges δ and
/// L − δ, where it has kinks), read by four-point Lagrange interpolation
/// within the piece between kinks.
struct ForceTable {
    s: Vec<f64>,
    f: Vec<[f64; 3]>,
    breaks: [f64; 2],
}

impl ForceTable {
    fn new(model: &ChargedRodModel, tr: &Trajectory, gl: &(Vec<f64>, Vec<f64>)) -> Self {
        let breaks = [model.delta, model.length - model.delta];
        let mut s: Vec<f64> = tr.s.clone();
        s.extend(breaks);
        s.sort_by(f64::total_cmp);
        s.dedup_by(|p, q| (*p - *q).abs() < 1e-12);
        let f = s.iter().map(|&x| model.far_force(tr, x, gl)).collect();
        ForceTable { s, f, breaks }
    }

    fn at(&self, x: f64) -> [f64; 3] {
        // The piece [lo, hi] between kinks that holds x, and its grid points.
        let lo = self.breaks.iter().copied().filter(|&b| b <= x).fold(0.0, f64::max);
        let hi = self.breaks.iter().copied().filter(|&b| b > x).fold(f64::INFINITY, f64::min);
        let first = self.s.partition_point(|&v| v < lo - 1e-12);
        let last = self.s.partition_point(|&v| v <= hi + 1e-12);
        let piece = &self.s[first..last];
        let k = piece.partition_point(|&v| v < x);
        let start = k.saturating_sub(2).min(piece.len().saturating_sub(4));
        // (No allocation: this runs in every IDA residual evaluation.)
        let idx = start..(start + 4).min(piece.len());
        let mut out = [0.0; 3];
        for j in idx.clone() {
            let mut l = 1.0;
            for m in idx.clone().filter(|&m| m != j) {
                l *= (x - piece[m]) / (piece[j] - piece[m]);
            }
            for c in 0..3 {
                out[c] += l * self.f[first + j][c];
            }
        }
        out
    }
}

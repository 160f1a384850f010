//! The charged rod's Taylor series along a path — the asymptotic numerical
//! method (physics.md §2.4) for a residual that is not polynomial (the
//! thesis's ANM and its charged rods joined).
//!
//! The rod's own system (stiffened near zone included) is cubic and takes
//! its series from its tapes ([`crate::taylor`]). What is added here:
//!
//! * the far-zone pair forces p_j = −Σ_k w_k P'(d_jk)/d_jk Δ_jk, Δ = r_j − r_k
//!   (and the exact near zone's gap points, Δ = r_j − Σ ℓ_i r_i on the
//!   stage interpolant, their forces shared among its stages: [`super::gap`]),
//!   by the elementary recurrences of [`crate::taylor::elementary`] along
//!   d² = Δ·Δ → d = √ → 1/d, e^{−κd}, f0 = e/d, A = f0/d, B = A(1 + κd)
//!   (P' = λ²(−B S + f0 S') with the C² switch S a quintic in
//!   x = (d − r_on)/(r_off − r_on), its powers by products), the hard core
//!   −3k_hc g², g = 2.5a − d, and c = −w_k P'/d: O(P²) per pair for a series
//!   of order P, every intermediate's coefficients stored;
//! * their rows R(q_j)ᵀp_j, R(q) quadratic in the quaternion (products of
//!   the quaternion's series, [`crate::rod::kinematics::rotation`]'s
//!   formula);
//! * under rotation control the rod's Λ = sin(φ/2) and its row
//!   c − cos(φ/2), by the sine–cosine recurrence.
//!
//! Each pair's piece of the potential (inside r_on, in the switch, beyond
//! r_off; the hard core's range) is the one it is in at the expansion
//! point: the series is that piece's, analytic. A pair that crosses a
//! piece's edge within a step leaves a residual of the order of the
//! switch's third derivative times the crossing's cube (the switch is C²;
//! beyond r_off P is below the cutoff's tolerance), which the step's end
//! point check sees and its Newton correction removes, as for any series
//! evaluated near its radius. The base-pair model has no series (its
//! continuation is Newton's).

use super::{ChargedRod, Gap, HARD_CORE_RANGE};
use crate::continuation::SeriesProblem;
use crate::taylor::elementary::{exp, product, recip, sin_cos, sqrt};

/// The slots of a pair's stored series.
const S2: usize = 0; // d²
const D: usize = 1;
const INV: usize = 2; // 1/d
const E: usize = 3; // e^{−κd}
const F0: usize = 4; // e/d
const A: usize = 5; // e/d²
const B: usize = 6; // A (1 + κd)
const X2: usize = 7; // x², x³, x⁴ of the switch's argument
const X3: usize = 8;
const X4: usize = 9;
const SW: usize = 10; // S
const SD: usize = 11; // S'
const PP: usize = 12; // P'(d)
const C: usize = 13; // −w_k P'/d
const SLOTS: usize = 14;

/// Which piece of the pair potential a pair is in at the expansion point.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Piece {
    /// Beyond r_off (or at d = 0, which no far pair reaches): no screened force.
    Off,
    /// Inside r_on (or no cutoff): the full e^{−κd}/d.
    Full,
    /// In the switch r_on < d < r_off.
    Switch,
}

/// The stored series of one expansion (reused from step to step).
#[derive(Default)]
pub(super) struct Series {
    stride: usize,
    /// φ, sin(φ/2), cos(φ/2) under rotation control.
    phi: Vec<f64>,
    sin: Vec<f64>,
    cos: Vec<f64>,
    /// Per stage: r (3), q (4), R(q) (9 entries, row-major), p (3) series.
    r: Vec<f64>,
    q: Vec<f64>,
    rot: Vec<f64>,
    p: Vec<f64>,
    /// Per pair (the CSR list's order): SLOTS series, its piece and whether
    /// the hard core acts.
    pair: Vec<f64>,
    piece: Vec<Piece>,
    hard: Vec<bool>,
    /// Scratch: Δ (3 series), the switch's x and the hard core's g.
    delta: Vec<f64>,
    x: Vec<f64>,
    g: Vec<f64>,
}

impl ChargedRod {
    /// The continuation parameter's order-p Λ of the rod (rotation
    /// control: sin(φ/2), and cos(φ/2) for its row; otherwise Λ itself).
    fn lambda_order(&mut self, p: usize, lambda_p: f64) -> f64 {
        let s = self.series.as_mut().expect("series begun");
        if self.twisted_phi.is_none() {
            return lambda_p;
        }
        s.phi[p] = lambda_p;
        (s.sin[p], s.cos[p]) = sin_cos(0.5, &s.phi, &s.sin, &s.cos, p);
        s.sin[p]
    }

    /// Every stage's r, q and the pairs' and stages' series at order p
    /// (p = 0: the values at x), then their rows' order-p coefficients
    /// added to `out`.
    fn pair_series_order(&mut self, p: usize, x: &[f64], out: &mut [f64]) {
        let mut s = self.series.take().expect("series begun");
        let st = s.stride;
        for (j, pt) in self.points.iter().enumerate() {
            for c in 0..3 {
                s.r[(3 * j + c) * st + p] = x[pt.offset + c];
            }
            for c in 0..4 {
                s.q[(4 * j + c) * st + p] = x[pt.offset + 3 + c];
            }
        }
        for j in 0..self.points.len() {
            let mut pj = [0.0; 3];
            for a in self.adj_ptr[j]..self.adj_ptr[j + 1] {
                let k = self.adj[a];
                let f = self.pair_order(&mut s, a, j, k, p);
                for c in 0..3 {
                    pj[c] += f[c];
                }
            }
            for c in 0..3 {
                s.p[(3 * j + c) * st + p] = pj[c];
            }
        }
        if let Some(gap) = &self.gap {
            let na = self.adj.len();
            for g in 0..gap.points() {
                self.gap_order(&mut s, gap, g, na + g, p);
            }
        }
        let nb = self.tab.b.len();
        for (j, pt) in self.points.iter().enumerate() {
            let rot = rotation_order(&s.q[4 * j * st..4 * (j + 1) * st], st, p);
            for (e, v) in rot.iter().flatten().enumerate() {
                s.rot[(9 * j + e) * st + p] = *v;
            }
            // fb_p = Σ_m R_mᵀ p_{p−m}.
            let mut fb = [0.0; 3];
            for m in 0..=p {
                for c in 0..3 {
                    for i in 0..3 {
                        fb[c] += s.rot[(9 * j + 3 * i + c) * st + m] * s.p[(3 * j + i) * st + p - m];
                    }
                }
            }
            for rb in 0..=nb {
                let coef = self.coefficient(rb, pt);
                for c in 0..3 {
                    out[self.n_row(pt.element, rb, c)] += coef * fb[c];
                }
            }
        }
        self.series = Some(s);
    }

    /// Pair (j, k), list entry `a`: its series' order p (order 0 chooses its
    /// piece), and its force's order-p coefficient on j, Σ_m c_m Δ_{p−m}.
    fn pair_order(&self, s: &mut Series, a: usize, j: usize, k: usize, p: usize) -> [f64; 3] {
        let st = s.stride;
        for c in 0..3 {
            for m in 0..=p {
                s.delta[c * st + m] = s.r[(3 * j + c) * st + m] - s.r[(3 * k + c) * st + m];
            }
        }
        self.delta_order(s, a, p, self.points[k].w, self.hard_pair(j, k))
    }

    /// Gap point g (slot `a`): Δ = r_j − Σ ℓ_i r_i, and its force's
    /// order-p coefficient −(½ w_j ω_g) (P'/d Δ)_p on the unit stage weight;
    /// the members' shares go to their p series ([`super::gap`]).
    fn gap_order(&self, s: &mut Series, gap: &Gap, g: usize, a: usize, p: usize) {
        let st = s.stride;
        let (_, factor, along, stages, coef) = gap.point(g, &self.weights);
        for c in 0..3 {
            for m in 0..=p {
                s.delta[c * st + m] =
                    stages.iter().zip(&coef).map(|(&x, &l)| l * s.r[(3 * x + c) * st + m]).sum::<f64>();
            }
        }
        let f = self.delta_order(s, a, p, factor, self.hard_gap(along));
        for (&x, &l) in stages.iter().zip(&coef) {
            if l != 0.0 {
                for c in 0..3 {
                    s.p[(3 * x + c) * st + p] += l * f[c] / self.weights[x];
                }
            }
        }
    }

    /// The series of the pair potential's force along Δ (in `s.delta`),
    /// slot `a`, order p (order 0 chooses its piece; the hard core acts
    /// when `hard_pair`): Σ_m C_m Δ_{p−m} with C = −`weight` P'(d)/d.
    fn delta_order(&self, s: &mut Series, a: usize, p: usize, weight: f64, hard_pair: bool) -> [f64; 3] {
        let st = s.stride;
        let pair = &mut s.pair[a * SLOTS * st..(a + 1) * SLOTS * st];
        let slot = |i: usize| i * st..(i + 1) * st;
        let d2 = (0..3).map(|c| product(&s.delta[slot(c)], &s.delta[slot(c)], p)).sum::<f64>();
        pair[S2 * st + p] = d2;
        if p == 0 {
            let d = d2.sqrt();
            let hard = d > 0.0 && hard_pair && d < HARD_CORE_RANGE * self.charge.screening.a;
            let l2 = self.charge.line_charge * self.charge.line_charge;
            s.piece[a] = match self.cutoff {
                _ if d == 0.0 || l2 == 0.0 => Piece::Off,
                None => Piece::Full,
                Some((_, off)) if d >= off => Piece::Off,
                Some((on, _)) if d <= on => Piece::Full,
                Some(_) => Piece::Switch,
            };
            s.hard[a] = hard;
        }
        let (piece, hard) = (s.piece[a], s.hard[a]);
        if piece == Piece::Off && !hard {
            pair[C * st + p] = 0.0;
            return [0.0; 3];
        }
        let (d_p, inv_p) = if p == 0 {
            let d = d2.sqrt();
            (d, 1.0 / d)
        } else {
            let d_p = sqrt(&pair[slot(S2)], &pair[slot(D)], p);
            pair[D * st + p] = d_p;
            (d_p, recip(&pair[slot(D)], &pair[slot(INV)], p))
        };
        pair[D * st + p] = d_p;
        pair[INV * st + p] = inv_p;
        let kappa = self.charge.screening.kappa;
        let mut pp = 0.0;
        if piece != Piece::Off {
            let e_p = if p == 0 { (-kappa * d_p).exp() } else { exp(-kappa, &pair[slot(D)], &pair[slot(E)], p) };
            pair[E * st + p] = e_p;
            pair[F0 * st + p] = product(&pair[slot(E)], &pair[slot(INV)], p);
            pair[A * st + p] = product(&pair[slot(F0)], &pair[slot(INV)], p);
            pair[B * st + p] = pair[A * st + p] + kappa * product(&pair[slot(A)], &pair[slot(D)], p);
            let l2 = self.charge.line_charge * self.charge.line_charge;
            pp = match (piece, self.cutoff) {
                (Piece::Switch, Some((on, off))) => {
                    let w = off - on;
                    for m in 0..=p {
                        s.x[m] = (pair[D * st + m] - if m == 0 { on } else { 0.0 }) / w;
                    }
                    let x = &s.x[..st];
                    pair[X2 * st + p] = product(x, x, p);
                    pair[X3 * st + p] = product(&pair[slot(X2)], x, p);
                    pair[X4 * st + p] = product(&pair[slot(X3)], x, p);
                    let x5 = product(&pair[slot(X4)], x, p);
                    let (x2, x3, x4) = (pair[X2 * st + p], pair[X3 * st + p], pair[X4 * st + p]);
                    // S = 1 − x³(10 − 15x + 6x²), S' = −30x²(1 − x)²/w (physics.md §3.1's switch).
                    pair[SW * st + p] = if p == 0 { 1.0 } else { 0.0 } - 10.0 * x3 + 15.0 * x4 - 6.0 * x5;
                    pair[SD * st + p] = (-30.0 * x2 + 60.0 * x3 - 30.0 * x4) / w;
                    l2 * (product(&pair[slot(F0)], &pair[slot(SD)], p) - product(&pair[slot(B)], &pair[slot(SW)], p))
                }
                _ => -l2 * pair[B * st + p],
            };
        }
        if hard {
            let khc = self.charge.hard_core.expect("hard pairs have a core");
            let range = HARD_CORE_RANGE * self.charge.screening.a;
            for m in 0..=p {
                s.g[m] = if m == 0 { range } else { 0.0 } - pair[D * st + m];
            }
            pp += -3.0 * khc * product(&s.g[..st], &s.g[..st], p);
        }
        pair[PP * st + p] = pp;
        pair[C * st + p] = -weight * product(&pair[slot(PP)], &pair[slot(INV)], p);
        let cs = &pair[slot(C)];
        [0, 1, 2].map(|c| product(cs, &s.delta[slot(c)], p))
    }
}

/// The order-p coefficient of R(q) from the quaternion's series q (4
/// series of `stride`): [`crate::rod::kinematics::rotation`]'s quadratic
/// form with each product q_i q_k replaced by its Cauchy product.
fn rotation_order(q: &[f64], stride: usize, p: usize) -> [[f64; 3]; 3] {
    let qs = |i: usize| &q[i * stride..(i + 1) * stride];
    let m = |i: usize, k: usize| product(qs(i), qs(k), p);
    let (q00, q11, q22, q33) = (m(0, 0), m(1, 1), m(2, 2), m(3, 3));
    let (q01, q02, q03, q12, q13, q23) = (m(0, 1), m(0, 2), m(0, 3), m(1, 2), m(1, 3), m(2, 3));
    [
        [q00 + q11 - q22 - q33, 2.0 * (q12 - q03), 2.0 * (q13 + q02)],
        [2.0 * (q12 + q03), q00 - q11 + q22 - q33, 2.0 * (q23 - q01)],
        [2.0 * (q13 - q02), 2.0 * (q23 + q01), q00 - q11 - q22 + q33],
    ]
}

impl SeriesProblem for ChargedRod {
    fn series_begin(&mut self, x0: &[f64], lambda0: f64, max_order: usize) {
        let st = max_order + 1;
        let np = self.points.len();
        // Pair slots: the list's pairs, then the exact near zone's gap points.
        let na = self.adj.len() + self.gap_points();
        let s = self.series.get_or_insert_with(Default::default);
        s.stride = st;
        for (v, len) in [
            (&mut s.phi, st),
            (&mut s.sin, st),
            (&mut s.cos, st),
            (&mut s.r, 3 * np * st),
            (&mut s.q, 4 * np * st),
            (&mut s.rot, 9 * np * st),
            (&mut s.p, 3 * np * st),
            (&mut s.pair, SLOTS * na * st),
            (&mut s.delta, 3 * st),
            (&mut s.x, st),
            (&mut s.g, st),
        ] {
            v.clear();
            v.resize(len, 0.0);
        }
        s.piece.clear();
        s.piece.resize(na, Piece::Off);
        s.hard.clear();
        s.hard.resize(na, false);
        (s.phi[0], s.sin[0], s.cos[0]) = (lambda0, (0.5 * lambda0).sin(), (0.5 * lambda0).cos());
        let (lambda, _) = self.rod_lambda(lambda0);
        self.sys.series_begin(x0, lambda, max_order);
        if self.has_pairs() && self.sites.is_none() {
            let mut scratch = vec![0.0; self.n];
            self.pair_series_order(0, x0, &mut scratch);
        }
    }

    /// The pair list holds along the step: under
    /// [`super::ListRule::Coverage`] while no far pair missing from it comes
    /// within the potential's range ([`super::coverage`]); under Verlet's
    /// rule while no stage moves half the skin from where it was built. The
    /// step is cut where the series' stage points (the polynomials r_j(a))
    /// would break that, by bisection.
    fn series_reach(&mut self, a: f64) -> f64 {
        let Some(s) = self.series.as_ref() else { return a };
        if !self.list_local || self.sites.is_some() {
            return a;
        }
        let st = s.stride;
        let points = |t: f64| -> Vec<[f64; 3]> {
            (0..self.points.len())
                .map(|j| {
                    [0, 1, 2].map(|c| {
                        s.r[(3 * j + c) * st..(3 * j + c + 1) * st].iter().rev().fold(0.0, |acc, x| acc * t + x)
                    })
                })
                .collect()
        };
        let half_skin = 0.5 * self.charge.skin;
        // ≥ 0 where the list holds.
        let holds = |t: f64| -> f64 {
            let r = points(t);
            match &self.list_coverage {
                Some(cover) => cover.gap_at(&r),
                None => half_skin - self.moved(&r),
            }
        };
        if holds(0.0) < 0.0 {
            return a;
        }
        // The first of 16 points along the step where the list fails (a
        // pair may come into range mid-step and leave again), then
        // bisection before it.
        let Some(fail) = (1..=16).map(|i| a * i as f64 / 16.0).find(|&t| holds(t) < 0.0) else {
            return a;
        };
        let (mut lo, mut hi) = (fail - a / 16.0, fail);
        for _ in 0..30 {
            let mid = 0.5 * (lo + hi);
            if holds(mid) >= 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    fn series_order(&mut self, p: usize, xp: &[f64], lambda_p: f64, out: &mut [f64]) {
        self.order_or_commit(p, xp, lambda_p, out, false);
    }

    /// The elastic rod commits its cone alone ([`crate::continuation::system::AssembledSystem`]'s
    /// commit); the pairs' and the phase row's series are committed as by
    /// `series_order` (their state is what later orders read).
    fn series_commit(&mut self, p: usize, xp: &[f64], lambda_p: f64, scratch: &mut [f64]) {
        self.order_or_commit(p, xp, lambda_p, scratch, true);
    }
}

impl ChargedRod {
    /// [`SeriesProblem::series_order`], or its commit (`out` then
    /// scratch).
    fn order_or_commit(&mut self, p: usize, xp: &[f64], lambda_p: f64, out: &mut [f64], commit: bool) {
        let rod_lambda = self.lambda_order(p, lambda_p);
        if commit {
            self.sys.series_commit(p, xp, rod_lambda, out);
        } else {
            self.sys.series_order(p, xp, rod_lambda, out);
        }
        if let Some(c) = self.twisted_phi {
            // The row c − cos(φ/2) (see `residual`).
            out[c] = xp[c] - self.series.as_ref().expect("series begun").cos[p];
        }
        if self.has_pairs() && self.sites.is_some() {
            // The base-pair model has no series: a non-finite term, which
            // the ANM turns into a zero step (StepTooSmall), never a
            // plausible one. Its drivers refuse the ANM before this.
            out.fill(f64::NAN);
        } else if self.has_pairs() {
            self.pair_series_order(p, xp, out);
        }
    }
}

#[cfg(test)]
mod tests {
    // Tested through the residual itself in tests/charged_series.rs: the
    // series of R(X(a)) along a polynomial path matches R evaluated on the
    // path to O(a^{P+1}).
    #[test]
    fn the_rotation_series_at_order_zero_is_the_rotation() {
        // Reference: kinematics::rotation, the formula this one repeats.
        let q = [0.9, -0.2, 0.3, 0.25];
        let series: Vec<f64> = q.iter().flat_map(|&v| [v, 0.0]).collect();
        let r = super::rotation_order(&series, 2, 0);
        let exact = crate::rod::kinematics::rotation(&q);
        for i in 0..3 {
            for k in 0..3 {
                assert!((r[i][k] - exact[i][k]).abs() <= 1e-15);
            }
        }
    }
}

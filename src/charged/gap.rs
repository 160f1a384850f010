//! The near zone cut at exactly δ ([`super::rod::RodCharge::exact_near_width`]).
//!
//! The stage quadrature's far zone runs over whole elements more than m
//! apart, so a stage's near zone reaches the element boundaries, sides
//! between mh and (m+1)h rather than δ. The near zone is §3.2's expansion
//! in the curvature, truncated after c²: its error grows like the side's
//! fourth power, so with element-aligned sides the *model* moves with the
//! mesh (the sides step by up to h; on the buckled branch the mesh
//! convergence falls to first order and a half/double-mesh estimate
//! undershoots). Cut exactly, every stage's near zone is [s − δ, s + δ]
//! (one-sided at the ends) whatever the mesh, and the strip between δ and
//! the element boundary (the gap) is integrated with the exact kernel:
//!
//!   E_gap = ½ Σ_j w_j Σ_g ω_g P(|r_j − R(t_g)|),
//!
//! the inner integral of the outer stage rule over each gap by
//! Gauss–Legendre points t_g (s + 2 per element piece), R(t) on the
//! six-point Lagrange interpolant of the stage positions
//! ([`super::sites::REFINED_STENCIL`], the refined far zone's). The pair
//! potential P is the far zone's (the cutoff's switch and the hard core
//! between points farther apart along the rod than its range). Its exact
//! gradient gives force densities on r_j and, through the interpolant, on
//! the stencil's stages; the Jacobian is exact (blocks ∂p_x/∂r_y between
//! stages at most the near zone and a stencil apart), and its Taylor
//! series along a path (the ANM) is the far pairs' with Δ's series the
//! same linear combination of the stages' (src/charged/rod/series.rs).

use super::assembly::Point;
use super::sites::REFINED_STENCIL;
use crate::quadrature::gauss_legendre;

/// The gap points of every stage and the Jacobian blocks they make.
pub(super) struct Gap {
    /// Per gap point: its outer stage, weight ω, distance along the rod
    /// |t − s_j| (the hard core's test), first stencil stage and basis.
    outer: Vec<usize>,
    weight: Vec<f64>,
    along: Vec<f64>,
    stencil: Vec<usize>,
    basis: Vec<f64>,
    /// Blocks ∂p_x/∂r_y in CSR over x (columns y ascending).
    pub(super) block_ptr: Vec<usize>,
    pub(super) block_col: Vec<usize>,
    pub(super) blocks: Vec<[f64; 9]>,
    /// Per gap point, the block of each (member, member) pair, members
    /// being the outer stage then the stencil (row-major).
    slot: Vec<usize>,
}

/// Members of a gap point: its outer stage and its stencil.
pub(super) const MEMBERS: usize = 1 + REFINED_STENCIL;

impl Gap {
    /// The gaps of stage points `points` (their stage count `stages` per
    /// element) on a mesh with nodes at `nodes`, each element's near run
    /// `runs` ([`super::assembly::near_runs`]) and the zone cut at `delta`.
    /// None when no stage has a gap (δ on an element boundary of every
    /// stage's run).
    pub(super) fn new(
        points: &[Point],
        stages: usize,
        nodes: &[f64],
        runs: &[(usize, usize)],
        delta: f64,
    ) -> Option<Self> {
        let s = stages;
        let (gx, gw) = gauss_legendre(s + 2);
        let stage_s: Vec<f64> = points.iter().map(|p| p.s).collect();
        let ns = stage_s.len();
        let order = REFINED_STENCIL.min(ns);
        let mut gap = Gap {
            outer: Vec::new(),
            weight: Vec::new(),
            along: Vec::new(),
            stencil: Vec::new(),
            basis: Vec::new(),
            block_ptr: Vec::new(),
            block_col: Vec::new(),
            blocks: Vec::new(),
            slot: Vec::new(),
        };
        // Pieces shorter than this are rounding (δ on an element boundary).
        let tiny = 1e-12 * nodes[nodes.len() - 1];
        for (j, pt) in points.iter().enumerate() {
            let (first, last) = runs[pt.element];
            let (lo, hi) = (nodes[first], nodes[last + 1]);
            for (from, to) in [(lo, pt.s - delta), (pt.s + delta, hi)] {
                if to - from <= tiny {
                    continue;
                }
                // Pieces split at element boundaries, one stencil per
                // piece (centred on its middle): R(t) is then one
                // polynomial on each piece and the piece's Gauss rule keeps
                // its order (a stencil per point would switch polynomials
                // at every stage abscissa inside the piece).
                let mut a = from;
                while to - a > tiny {
                    let next = nodes.partition_point(|&v| v <= a + tiny);
                    let b = nodes.get(next).copied().unwrap_or(to).min(to);
                    let half = 0.5 * (b - a);
                    let centre = stage_s.partition_point(|&v| v < a + half);
                    let j0 = centre.saturating_sub(order / 2).min(ns - order);
                    let nodes = &stage_s[j0..j0 + order];
                    for (x, w) in gx.iter().zip(&gw) {
                        let t = a + half * (1.0 + x);
                        for i in 0..order {
                            gap.basis.push(
                                (0..order)
                                    .filter(|&k| k != i)
                                    .map(|k| (t - nodes[k]) / (nodes[i] - nodes[k]))
                                    .product::<f64>(),
                            );
                        }
                        gap.basis.extend(std::iter::repeat_n(0.0, REFINED_STENCIL - order));
                        gap.outer.push(j);
                        gap.weight.push(half * w);
                        gap.along.push((t - pt.s).abs());
                        gap.stencil.push(j0);
                    }
                    a = b;
                }
            }
        }
        if gap.outer.is_empty() {
            return None;
        }
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); ns];
        for g in 0..gap.outer.len() {
            let mm = gap.members(g, ns);
            for &x in &mm {
                cols[x].extend_from_slice(&mm);
            }
        }
        gap.block_ptr.push(0);
        for c in cols.iter_mut() {
            c.sort_unstable();
            c.dedup();
            gap.block_col.extend_from_slice(c);
            gap.block_ptr.push(gap.block_col.len());
        }
        gap.blocks = vec![[0.0; 9]; gap.block_col.len()];
        for g in 0..gap.outer.len() {
            let mm = gap.members(g, ns);
            for &x in &mm {
                let row = &gap.block_col[gap.block_ptr[x]..gap.block_ptr[x + 1]];
                for &y in &mm {
                    let at = row.binary_search(&y).expect("every member pair has a block");
                    gap.slot.push(gap.block_ptr[x] + at);
                }
            }
        }
        Some(gap)
    }

    /// Gap points (their count: the cost).
    pub(super) fn points(&self) -> usize {
        self.outer.len()
    }

    /// Gap point g's outer stage j, the factor ½ w_j ω_g of its pair
    /// potential, its distance along the rod and its members' stages and
    /// coefficients in Δ = r_j − R(t_g) = Σ_k coef_k r_{stage_k} (those of a
    /// short stencil's padding are 0).
    pub(super) fn point(&self, g: usize, w: &[f64]) -> (usize, f64, f64, [usize; MEMBERS], [f64; MEMBERS]) {
        let j = self.outer[g];
        let mut coef = [1.0; MEMBERS];
        for (c, l) in coef[1..].iter_mut().zip(&self.basis[g * REFINED_STENCIL..(g + 1) * REFINED_STENCIL]) {
            *c = -l;
        }
        (j, 0.5 * w[j] * self.weight[g], self.along[g], self.members(g, w.len()), coef)
    }

    /// Gap point g's members among `stages` stage points: its outer stage,
    /// then its stencil (a stencil shorter than six, on tiny rods, repeats
    /// its last stage with a zero basis weight).
    fn members(&self, g: usize, stages: usize) -> [usize; MEMBERS] {
        let mut out = [self.outer[g]; MEMBERS];
        for (i, m) in out[1..].iter_mut().enumerate() {
            *m = (self.stencil[g] + i).min(stages - 1);
        }
        out
    }

    /// Δ = r_j − R(t_g) from the members' positions.
    fn delta(stages: &[usize; MEMBERS], coef: &[f64; MEMBERS], r: &[[f64; 3]]) -> [f64; 3] {
        let mut dv = [0.0; 3];
        for (&x, &l) in stages.iter().zip(coef) {
            for c in 0..3 {
                dv[c] += l * r[x][c];
            }
        }
        dv
    }

    /// Adds the gap's force densities p_x = −(1/w_x) ∂E_gap/∂r_x to `p`
    /// (stage positions `r`, stage weights `w`) and, with `jacobian`,
    /// computes the blocks ∂p_x/∂r_y. `pair(d, along)` is (P'(d), P''(d)).
    pub(super) fn forces(
        &mut self,
        r: &[[f64; 3]],
        w: &[f64],
        pair: &dyn Fn(f64, f64) -> (f64, f64),
        p: &mut [[f64; 3]],
        jacobian: bool,
    ) {
        if jacobian {
            self.blocks.iter_mut().for_each(|b| *b = [0.0; 9]);
        }
        for g in 0..self.outer.len() {
            let (_, scale, along, stages, coef) = self.point(g, w);
            let dv = Self::delta(&stages, &coef, r);
            let d = (dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]).sqrt();
            if d <= 0.0 {
                continue;
            }
            let (p1, p2) = pair(d, along);
            // ∂E/∂Δ = ½ w_j ω P'(d) Δ/d, and ∂Δ/∂r_x = coef_x I.
            let f = scale * p1 / d;
            for (&x, &l) in stages.iter().zip(&coef) {
                if l == 0.0 {
                    continue;
                }
                let c = -l * f / w[x];
                for i in 0..3 {
                    p[x][i] += c * dv[i];
                }
            }
            if jacobian {
                // ∂²E/∂Δ² = ½ w_j ω [P'/d I + (P'' − P'/d) ΔΔᵀ/d²].
                let (a0, a1) = (scale * p1 / d, scale * (p2 - p1 / d) / (d * d));
                let mut hess = [0.0; 9];
                for a in 0..3 {
                    for b in 0..3 {
                        hess[3 * a + b] = a1 * dv[a] * dv[b] + if a == b { a0 } else { 0.0 };
                    }
                }
                for (kx, &x) in stages.iter().enumerate() {
                    for ky in 0..MEMBERS {
                        let c = -coef[kx] * coef[ky] / w[x];
                        if c == 0.0 {
                            continue;
                        }
                        let block = &mut self.blocks[self.slot[g * MEMBERS * MEMBERS + kx * MEMBERS + ky]];
                        for i in 0..9 {
                            block[i] += c * hess[i];
                        }
                    }
                }
            }
        }
    }

    /// E_gap, split into the pair potential's `(electrostatic, hard core)`
    /// parts `potential(d, along)`.
    pub(super) fn energy(&self, r: &[[f64; 3]], w: &[f64], potential: &dyn Fn(f64, f64) -> (f64, f64)) -> (f64, f64) {
        let (mut e, mut hard) = (0.0, 0.0);
        for g in 0..self.outer.len() {
            let (_, scale, along, stages, coef) = self.point(g, w);
            let dv = Self::delta(&stages, &coef, r);
            let d = (dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]).sqrt();
            if d > 0.0 {
                let (pe, ph) = potential(d, along);
                e += scale * pe;
                hard += scale * ph;
            }
        }
        (e, hard)
    }
}

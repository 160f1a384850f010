//! The discrete base-pair model (physics.md §3.3) coupled to the rod: the
//! thesis's comparison, solved with the same unknowns, engine and
//! Jacobian machinery as the continuum coupling of [`super::rod`].
//!
//! Point charges q = λb at s_k = (k + ½)b (b = L/round(L/b₀)) sit on the
//! centreline interpolated from the rod's stage positions: R_k = Σ_j ℓ_j(s_k)
//! r_j, Lagrange on the [`STENCIL`] stage points nearest in arc length
//! (across element ends). Cubic, so sites follow a curved rod to O(h⁴) and
//! neighbouring sites share their stencil: the distances of near pairs,
//! whose curvature dependence is the electrostatic bending stiffness, are
//! those of a smooth curve (a linear interpolant between two Gauss points
//! would kink at every element end). The energy is
//! ½ Σ_{k≠l, |s_k − s_l| > a} q_k q_l Φ(|R_k − R_l|) (the exclusion of
//! [`super::discrete::energy`]) with the continuum's C² cutoff switch, and
//! since R is linear in the stage positions its exact gradient is a force
//! on each stage, F_j = Σ_k ℓ_j(s_k) F_k, i.e. the force density
//! p_j = F_j / w_j that the continuum coupling also puts in the stage and
//! update rows: the residual is again the gradient of one discrete energy
//! and the Jacobian exact. There is no near zone: the discrete sum has no
//! singularity (b > 0) and every pair farther apart along the rod than a
//! is summed.
//!
//! Site pairs within r_off + skin of the reference are found by cell lists.
//! Stage j's Jacobian blocks ∂p_j/∂r_i run over the stencils of the
//! partners of every site whose stencil holds j (and those sites' own
//! stencils). Without a cutoff every pair is kept (a dense Jacobian).
//! Sequential (the caller's thread count applies to the continuum).

use super::discrete::CellList;

/// Stage points in each site's interpolation stencil (cubic).
pub const STENCIL: usize = 4;

/// The sites of a discretised rod, their pair list and the Jacobian's
/// stage-block structure.
pub(super) struct BasePairSites {
    spacing: f64,
    site_s: Vec<f64>,
    /// First stage of each site's stencil, and ℓ over the stencil (site-major).
    stencil: Vec<usize>,
    basis: Vec<f64>,
    /// Directed site pairs (CSR).
    pair_ptr: Vec<usize>,
    pair: Vec<usize>,
    /// Stage columns of each site's force: sorted stages of its partners'
    /// stencils and its own (CSR).
    col_ptr: Vec<usize>,
    col: Vec<usize>,
    /// Sites whose stencil holds stage j (CSR, ascending).
    holder_ptr: Vec<usize>,
    holder: Vec<usize>,
    /// Stage j's partner stages: the union of its holders' columns (CSR, sorted).
    partner_ptr: Vec<usize>,
    partner: Vec<usize>,
    reference: Vec<[f64; 3]>,
    // Scratch.
    sites: Vec<[f64; 3]>,
    force: Vec<[f64; 3]>,
    slot: Vec<usize>,
    blocks: Vec<[f64; 9]>,
}

/// P'(d), P''(d) of the (switched) pair potential at distance d between
/// sites `gap` apart along the rod (the hard core acts only between
/// sites far apart along it), from the charged rod.
pub(super) type PairFn<'a> = &'a dyn Fn(f64, f64) -> (f64, f64);

fn sorted_union(lists: impl Iterator<Item = usize>) -> Vec<usize> {
    let mut v: Vec<usize> = lists.collect();
    v.sort_unstable();
    v.dedup();
    v
}

impl BasePairSites {
    /// Sites of spacing ≈ `spacing` on a rod of `length` whose stage points
    /// are at arc lengths `stage_s` (ascending) and positions `stages`;
    /// pairs within `radius` of each other there (None: every pair),
    /// excluding pairs at most `a` apart along the rod.
    pub(super) fn new(stage_s: &[f64], length: f64, spacing: f64, a: f64, stages: &[[f64; 3]], radius: Option<f64>) -> Self {
        let ns = stage_s.len();
        let order = STENCIL.min(ns);
        let count = ((length / spacing).round() as usize).max(1);
        let b = length / count as f64;
        let mut site_s = Vec::with_capacity(count);
        let mut stencil = Vec::with_capacity(count);
        let mut basis = Vec::with_capacity(count * order);
        for k in 0..count {
            let sk = (k as f64 + 0.5) * b;
            let next = stage_s.partition_point(|&v| v < sk);
            let j0 = next.saturating_sub(order / 2).min(ns - order);
            let nodes = &stage_s[j0..j0 + order];
            for j in 0..order {
                basis.push((0..order).filter(|&m| m != j).map(|m| (sk - nodes[m]) / (nodes[j] - nodes[m])).product::<f64>());
            }
            site_s.push(sk);
            stencil.push(j0);
        }
        let mut this = BasePairSites {
            spacing: b,
            site_s,
            stencil,
            basis,
            pair_ptr: vec![0],
            pair: Vec::new(),
            col_ptr: vec![0],
            col: Vec::new(),
            holder_ptr: vec![0],
            holder: Vec::new(),
            partner_ptr: vec![0],
            partner: Vec::new(),
            reference: Vec::new(),
            sites: vec![[0.0; 3]; count],
            force: vec![[0.0; 3]; count],
            slot: vec![usize::MAX; ns],
            blocks: Vec::new(),
        };
        this.interpolate(stages);
        this.reference = this.sites.clone();
        let far = |k: usize, l: usize| k != l && (this.site_s[k] - this.site_s[l]).abs() > a;
        match radius {
            Some(radius) => {
                let cells = CellList::new(&this.reference, radius);
                let mut found = Vec::new();
                for k in 0..count {
                    cells.neighbours_within(&this.reference, &this.reference[k], radius, &mut found);
                    this.pair.extend(found.iter().copied().filter(|&l| far(k, l)));
                    this.pair_ptr.push(this.pair.len());
                }
            }
            None => {
                for k in 0..count {
                    this.pair.extend((0..count).filter(|&l| far(k, l)));
                    this.pair_ptr.push(this.pair.len());
                }
            }
        }
        let span = |k: usize| this.stencil[k]..this.stencil[k] + order;
        for k in 0..count {
            let cols = sorted_union(this.pair[this.pair_ptr[k]..this.pair_ptr[k + 1]].iter().flat_map(|&l| span(l)).chain(span(k)));
            this.col.extend(cols);
            this.col_ptr.push(this.col.len());
        }
        let mut holders = vec![Vec::new(); ns];
        for k in 0..count {
            for j in span(k) {
                holders[j].push(k);
            }
        }
        for (j, h) in holders.iter().enumerate() {
            this.holder.extend(h);
            this.holder_ptr.push(this.holder.len());
            let partners = sorted_union(h.iter().flat_map(|&k| this.col[this.col_ptr[k]..this.col_ptr[k + 1]].iter().copied()).chain(std::iter::once(j)));
            this.partner.extend(partners);
            this.partner_ptr.push(this.partner.len());
        }
        this.blocks = vec![[0.0; 9]; this.col.len()];
        this
    }

    /// Sites (charges) in the model.
    pub(super) fn count(&self) -> usize {
        self.site_s.len()
    }

    /// The spacing b actually used (L divided into whole base pairs).
    pub(super) fn spacing(&self) -> f64 {
        self.spacing
    }

    /// Directed site pairs in the list.
    pub(super) fn site_pairs(&self) -> usize {
        self.pair.len()
    }

    /// The stages whose positions stage j's force depends on (sorted; j included).
    pub(super) fn partners(&self, j: usize) -> &[usize] {
        &self.partner[self.partner_ptr[j]..self.partner_ptr[j + 1]]
    }

    fn order(&self) -> usize {
        self.basis.len() / self.count()
    }

    /// R_k = Σ_j ℓ_j(s_k) r_j.
    fn site(&self, k: usize, stages: &[[f64; 3]]) -> [f64; 3] {
        let order = self.order();
        let mut r = [0.0; 3];
        for j in 0..order {
            let (l, rj) = (self.basis[k * order + j], stages[self.stencil[k] + j]);
            for c in 0..3 {
                r[c] += l * rj[c];
            }
        }
        r
    }

    fn interpolate(&mut self, stages: &[[f64; 3]]) {
        for k in 0..self.sites.len() {
            self.sites[k] = self.site(k, stages);
        }
    }

    /// The largest distance a site at `stages` is from the list's reference.
    pub(super) fn displacement(&self, stages: &[[f64; 3]]) -> f64 {
        (0..self.count()).map(|k| {
            let (r, r0) = (self.site(k, stages), self.reference[k]);
            ((r[0] - r0[0]).powi(2) + (r[1] - r0[1]).powi(2) + (r[2] - r0[2]).powi(2)).sqrt()
        }).fold(0.0, f64::max)
    }

    /// ½ Σ b² P(d) over the pair list, with `potential` = P(d) (λ² included).
    /// (electrostatic, hard-core) energies: Σ b² P(d)/2 over directed
    /// pairs, `potential(d, gap)` giving both parts' P.
    pub(super) fn energy(&mut self, stages: &[[f64; 3]], potential: &dyn Fn(f64, f64) -> (f64, f64)) -> (f64, f64) {
        self.interpolate(stages);
        let b2 = self.spacing * self.spacing;
        let (mut e, mut h) = (0.0, 0.0);
        for k in 0..self.count() {
            let rk = self.sites[k];
            for &l in &self.pair[self.pair_ptr[k]..self.pair_ptr[k + 1]] {
                let rl = self.sites[l];
                let d = ((rk[0] - rl[0]).powi(2) + (rk[1] - rl[1]).powi(2) + (rk[2] - rl[2]).powi(2)).sqrt();
                if d > 0.0 {
                    let (pe, ph) = potential(d, (self.site_s[k] - self.site_s[l]).abs());
                    e += 0.5 * b2 * pe;
                    h += 0.5 * b2 * ph;
                }
            }
        }
        (e, h)
    }

    /// Stage force densities p_j = (1/w_j) Σ_k ℓ_j(s_k) F_k at the stage
    /// positions `stages` (weights `w`), and with `out` the Jacobian blocks
    /// ∂p_j/∂r_i for every stage j and each of its [`Self::partners`] i,
    /// stage-major.
    pub(super) fn forces(&mut self, stages: &[[f64; 3]], w: &[f64], pair: PairFn, p: &mut [[f64; 3]], mut out: Option<&mut [[f64; 9]]>) {
        self.interpolate(stages);
        let order = self.order();
        let b = self.spacing;
        let jacobian = out.is_some();
        // Site forces per length f_k = −Σ_l b P'(d) Δ/d, and (Jacobian) the
        // blocks ∂f_k/∂r_i over the site's stage columns: Σ_l g_kl ℓ_i(s_l)
        // − (Σ_l g_kl) ℓ_i(s_k), g_kl = b [P'/d I + (P'' − P'/d) ΔΔᵀ/d²].
        for k in 0..self.count() {
            let (c0, c1) = (self.col_ptr[k], self.col_ptr[k + 1]);
            if jacobian {
                for (t, &i) in self.col[c0..c1].iter().enumerate() {
                    self.slot[i] = c0 + t;
                }
                self.blocks[c0..c1].iter_mut().for_each(|v| *v = [0.0; 9]);
            }
            let rk = self.sites[k];
            let mut fk = [0.0; 3];
            let mut dk = [0.0; 9];
            for &l in &self.pair[self.pair_ptr[k]..self.pair_ptr[k + 1]] {
                let rl = self.sites[l];
                let dv = [rk[0] - rl[0], rk[1] - rl[1], rk[2] - rl[2]];
                let d = (dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]).sqrt();
                if d == 0.0 {
                    // Coincident charges (strands through each other): no direction, no force.
                    continue;
                }
                let (p1, p2) = pair(d, (self.site_s[k] - self.site_s[l]).abs());
                let c = -b * p1 / d;
                for i in 0..3 {
                    fk[i] += c * dv[i];
                }
                if jacobian {
                    let (a0, a1) = (b * p1 / d, b * (p2 - p1 / d) / (d * d));
                    let mut g = [0.0; 9];
                    for r in 0..3 {
                        for q in 0..3 {
                            g[3 * r + q] = a1 * dv[r] * dv[q] + if r == q { a0 } else { 0.0 };
                        }
                    }
                    for m in 0..9 {
                        dk[m] -= g[m];
                    }
                    for i in 0..order {
                        let (li, at) = (self.basis[l * order + i], self.slot[self.stencil[l] + i]);
                        let blk = &mut self.blocks[at];
                        for m in 0..9 {
                            blk[m] += li * g[m];
                        }
                    }
                }
            }
            self.force[k] = fk;
            if jacobian {
                for i in 0..order {
                    let (li, at) = (self.basis[k * order + i], self.slot[self.stencil[k] + i]);
                    let blk = &mut self.blocks[at];
                    for m in 0..9 {
                        blk[m] += li * dk[m];
                    }
                }
                for &i in &self.col[c0..c1] {
                    self.slot[i] = usize::MAX;
                }
            }
        }
        // Stage j: F_j = Σ_{k holds j} b ℓ_j(s_k) f_k, p_j = F_j / w_j.
        let mut at = 0;
        for j in 0..p.len() {
            let (h0, h1) = (self.holder_ptr[j], self.holder_ptr[j + 1]);
            let (q0, q1) = (self.partner_ptr[j], self.partner_ptr[j + 1]);
            if let Some(out) = out.as_deref_mut() {
                for (t, &i) in self.partner[q0..q1].iter().enumerate() {
                    self.slot[i] = at + t;
                    out[at + t] = [0.0; 9];
                }
            }
            let mut pj = [0.0; 3];
            let inv = 1.0 / w[j];
            for &k in &self.holder[h0..h1] {
                let lj = b * inv * self.basis[k * order + (j - self.stencil[k])];
                for c in 0..3 {
                    pj[c] += lj * self.force[k][c];
                }
                if let Some(out) = out.as_deref_mut() {
                    for (cp, &i) in (self.col_ptr[k]..self.col_ptr[k + 1]).zip(&self.col[self.col_ptr[k]..self.col_ptr[k + 1]]) {
                        let (src, dst) = (self.blocks[cp], &mut out[self.slot[i]]);
                        for m in 0..9 {
                            dst[m] += lj * src[m];
                        }
                    }
                }
            }
            p[j] = pj;
            if out.is_some() {
                for &i in &self.partner[q0..q1] {
                    self.slot[i] = usize::MAX;
                }
                at += q1 - q0;
            }
        }
    }
}

//! Charge sites on the stage interpolant: the far-pair sums of the charged
//! rod evaluated at points other than its stage points, with the same
//! unknowns, engine and Jacobian machinery as the stage-point coupling of
//! [`super::rod`]. Two uses:
//!
//! * **The discrete base-pair model** (physics.md §3.3), the thesis's
//!   comparison ([`Sites::base_pairs`]): point charges q = λb at
//!   s_k = (k + ½)b (b = L/round(L/b₀)), energy
//!   ½ Σ_{k≠l, |s_k − s_l| > a} q_k q_l Φ(|R_k − R_l|) (the exclusion of
//!   [`crate::electrostatics::discrete::energy`]). There is no near zone: the
//!   discrete sum has no singularity (b > 0) and every pair farther apart
//!   along the rod than a is summed. Cubic stencil ([`STENCIL`]).
//! * **The continuum's far zone on a finer quadrature**
//!   ([`Sites::refined`], [`super::rod::RodCharge::far_points`]): the far
//!   double integral ½∫∫λ²Φ over element pairs more than `near_elements`
//!   apart by M Gauss–Legendre points per element instead of the s stage
//!   points; the near zone stays the analytic expansion of [`super::rod`].
//!   Why (benches/README.md): the stage quadrature's error on
//!   a plectoneme follows the points' spacing (~h⁴): across it
//!   (r ≈ 4–5 nm, 1/κ ≈ 1 nm at 0.1 M) the integrand e^{−κr}/r varies
//!   along a strand on a ~√(r/κ) ≈ 2 nm scale, finer than the rod's own
//!   shape needs. Quintic stencil ([`REFINED_STENCIL`]): the cubic one was
//!   measured too coarse here (a helix of radius 5 nm on 1.7 nm stage
//!   spacing: far energy 2.5e-4 off with four points, 3.6e-6 with six;
//!   tests/charged_far_quadrature.rs). Site–site pairs (the gradient of
//!   one symmetric energy), not each stage's force density against refined
//!   partner sites: that pointwise form breaks action and reaction (its
//!   outer rule is the stage points') and was measured worse on the
//!   plectoneme than no refinement at all (1 kbp, 0.1 M: 3.9e-3 against
//!   3.1e-3 on 100 × Gauss(2), 9.7e-3 on 40 × Gauss(4)).
//!
//! Either way a site's position is R_k = Σ_j ℓ_j(s_k) r_j, Lagrange on the
//! stencil's stage points nearest in arc length (across element ends), so
//! sites follow a curved rod to high order and neighbouring sites share
//! their stencil: the distances of near pairs, whose curvature dependence
//! is the electrostatic bending stiffness, are those of a smooth curve (a
//! linear interpolant between two Gauss points would kink at every
//! element end). With site weights ω_k (b, or h times the Gauss–Legendre
//! weight) the energy is ½ Σ ω_k ω_l P(|R_k − R_l|) with the continuum's C²
//! cutoff switch, and since R is linear in the stage positions its exact
//! gradient is a force on each stage, F_j = Σ_k ω_k ℓ_j(s_k) f_k, i.e. the
//! force density p_j = F_j / w_j that the stage-point coupling also puts in
//! the stage and update rows: the residual is again the gradient of one
//! discrete energy and the Jacobian exact.
//!
//! Site pairs within r_off + skin of the reference are found by cell lists.
//! Stage j's Jacobian blocks ∂p_j/∂r_i run over the stencils of the
//! partners of every site whose stencil holds j (and those sites' own
//! stencils). Without a cutoff every pair is kept (a dense Jacobian).
//! The forces run on the caller's threads (RodCharge::threads), bitwise
//! identical for any count; the energy (reporting only) is sequential.

use crate::geometry::proximity::CellList;
use crate::geometry::vec3::distance;

/// Stage points in a base-pair site's interpolation stencil (cubic).
pub const STENCIL: usize = 4;

/// Stage points in a refined far-zone site's stencil (quintic).
pub const REFINED_STENCIL: usize = 6;

/// The sites of a discretised rod, their pair list and the Jacobian's
/// stage-block structure.
pub(super) struct Sites {
    /// The base-pair model's spacing b (None: the continuum's refined far zone).
    spacing: Option<f64>,
    site_s: Vec<f64>,
    /// Quadrature weight (charge per λ) of each site: b, or h w_GL.
    weight: Vec<f64>,
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
    /// One stage-indexed scratch per thread (usize::MAX between uses).
    slots: Vec<Vec<usize>>,
    blocks: Vec<[f64; 9]>,
}

/// P'(d), P''(d) of the (switched) pair potential at distance d between
/// sites `gap` apart along the rod (the hard core acts only between
/// sites far apart along it), from the charged rod.
pub(super) type PairFn<'a> = &'a (dyn Fn(f64, f64) -> (f64, f64) + Sync);

fn sorted_union(lists: impl Iterator<Item = usize>) -> Vec<usize> {
    let mut v: Vec<usize> = lists.collect();
    v.sort_unstable();
    v.dedup();
    v
}

impl Sites {
    /// The base-pair model: sites of spacing ≈ `spacing` on a rod of
    /// `length` whose stage points are at arc lengths `stage_s` (ascending)
    /// and positions `stages`; pairs within `radius` of each other there
    /// (None: every pair), excluding pairs at most `a` apart along the rod;
    /// scratch for `threads` threads.
    pub(super) fn base_pairs(
        stage_s: &[f64],
        length: f64,
        spacing: f64,
        a: f64,
        stages: &[[f64; 3]],
        radius: Option<f64>,
        threads: usize,
    ) -> Self {
        let count = crate::electrostatics::discrete::base_pair_count(length, spacing);
        let b = length / count as f64;
        let site_s: Vec<f64> = (0..count).map(|k| (k as f64 + 0.5) * b).collect();
        let at = site_s.clone();
        let far = move |k: usize, l: usize| (at[k] - at[l]).abs() > a;
        Self::build(stage_s, STENCIL, Some(b), site_s, vec![b; count], &far, stages, radius, threads)
    }

    /// The continuum's far zone on `per_element` Gauss–Legendre points in
    /// each of the `elements` elements of length `h` (stage points and
    /// positions as in [`Self::base_pairs`]): pairs of sites whose elements
    /// are more than `near_elements` apart (the stage quadrature's
    /// exclusion, so the near zone's analytic expansion covers the rest).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn refined(
        stage_s: &[f64],
        elements: usize,
        h: f64,
        per_element: usize,
        near_elements: usize,
        stages: &[[f64; 3]],
        radius: Option<f64>,
        threads: usize,
    ) -> Self {
        let (z, w) = crate::quadrature::gauss_legendre(per_element);
        let mut local: Vec<(f64, f64)> = z.iter().zip(&w).map(|(&z, &w)| (0.5 * (1.0 + z), 0.5 * w)).collect();
        local.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (mut site_s, mut weight) = (Vec::new(), Vec::new());
        for e in 0..elements {
            for &(c, b) in &local {
                site_s.push((e as f64 + c) * h);
                weight.push(h * b);
            }
        }
        // Site k lies in element k / per_element.
        let far = |k: usize, l: usize| (k / per_element).abs_diff(l / per_element) > near_elements;
        Self::build(stage_s, REFINED_STENCIL, None, site_s, weight, &far, stages, radius, threads)
    }

    /// Sites at arc lengths `site_s` (ascending) with weights `weight`
    /// on `order`-point stencils, pairs k ≠ l with `far(k, l)` within
    /// `radius` at `stages`.
    #[allow(clippy::too_many_arguments)]
    fn build(
        stage_s: &[f64],
        order: usize,
        spacing: Option<f64>,
        site_s: Vec<f64>,
        weight: Vec<f64>,
        far: &dyn Fn(usize, usize) -> bool,
        stages: &[[f64; 3]],
        radius: Option<f64>,
        threads: usize,
    ) -> Self {
        let ns = stage_s.len();
        let order = order.min(ns);
        let count = site_s.len();
        let mut stencil = Vec::with_capacity(count);
        let mut basis = Vec::with_capacity(count * order);
        for &sk in &site_s {
            let next = stage_s.partition_point(|&v| v < sk);
            let j0 = next.saturating_sub(order / 2).min(ns - order);
            let nodes = &stage_s[j0..j0 + order];
            for j in 0..order {
                basis.push(
                    (0..order).filter(|&m| m != j).map(|m| (sk - nodes[m]) / (nodes[j] - nodes[m])).product::<f64>(),
                );
            }
            stencil.push(j0);
        }
        let mut this = Sites {
            spacing,
            site_s,
            weight,
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
            slots: vec![vec![usize::MAX; ns]; threads.max(1)],
            blocks: Vec::new(),
        };
        this.interpolate(stages);
        this.reference = this.sites.clone();
        let far = |k: usize, l: usize| k != l && far(k, l);
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
            let cols = sorted_union(
                this.pair[this.pair_ptr[k]..this.pair_ptr[k + 1]].iter().flat_map(|&l| span(l)).chain(span(k)),
            );
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
            let partners = sorted_union(
                h.iter()
                    .flat_map(|&k| this.col[this.col_ptr[k]..this.col_ptr[k + 1]].iter().copied())
                    .chain(std::iter::once(j)),
            );
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

    /// The base-pair model's spacing b actually used (L divided into
    /// whole base pairs); None for the continuum's refined far zone.
    pub(super) fn spacing(&self) -> Option<f64> {
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
        (0..self.count())
            .map(|k| {
                let (r, r0) = (self.site(k, stages), self.reference[k]);
                distance(&r, &r0)
            })
            .fold(0.0, f64::max)
    }

    /// (electrostatic, hard-core) energies: ½ Σ ω_k ω_l P(d) over directed
    /// pairs (λ² included), `potential(d, gap)` giving both parts' P.
    pub(super) fn energy(&mut self, stages: &[[f64; 3]], potential: &dyn Fn(f64, f64) -> (f64, f64)) -> (f64, f64) {
        self.interpolate(stages);
        let (mut e, mut h) = (0.0, 0.0);
        for k in 0..self.count() {
            let rk = self.sites[k];
            for &l in &self.pair[self.pair_ptr[k]..self.pair_ptr[k + 1]] {
                let rl = self.sites[l];
                let d = distance(&rk, &rl);
                if d > 0.0 {
                    let (pe, ph) = potential(d, (self.site_s[k] - self.site_s[l]).abs());
                    let ww = 0.5 * self.weight[k] * self.weight[l];
                    e += ww * pe;
                    h += ww * ph;
                }
            }
        }
        (e, h)
    }

    /// Stage force densities p_j = (1/w_j) Σ_k ℓ_j(s_k) F_k at the stage
    /// positions `stages` (weights `w`), and with `out` the Jacobian blocks
    /// ∂p_j/∂r_i for every stage j and each of its [`Self::partners`] i,
    /// stage-major. With a `pool`, both passes (sites, then stages) run in
    /// one contiguous chunk per thread: each site's and each stage's sum is
    /// the same sequence of operations whatever the chunking, so the results
    /// are bitwise those of one thread.
    pub(super) fn forces(
        &mut self,
        stages: &[[f64; 3]],
        w: &[f64],
        pair: PairFn,
        p: &mut [[f64; 3]],
        out: Option<&mut [[f64; 9]]>,
        pool: Option<&rayon::ThreadPool>,
    ) {
        self.interpolate(stages);
        let jacobian = out.is_some();
        let (mut force, mut blocks, mut slots) =
            (std::mem::take(&mut self.force), std::mem::take(&mut self.blocks), std::mem::take(&mut self.slots));
        let this = &*self;
        let threads = pool.map_or(1, |p| p.current_num_threads()).clamp(1, slots.len());
        // Pass 1, sites: f_k and the blocks ∂f_k/∂r_i (k's own column range).
        let count = this.count();
        run_chunks(
            pool,
            threads,
            count,
            &mut slots,
            |ks, slot, parts: &mut (&mut [[f64; 3]], &mut [[f64; 9]])| {
                this.site_forces(ks, pair, parts.0, jacobian.then_some(&mut *parts.1), slot)
            },
            |ks| (ks.len(), if jacobian { this.col_ptr[ks.end] - this.col_ptr[ks.start] } else { 0 }),
            (&mut force[..], &mut blocks[..]),
        );
        // Pass 2, stages: p_j and ∂p_j/∂r_i (j's own partner range).
        let ns = p.len();
        let mut empty: [[f64; 9]; 0] = [];
        let out = out.unwrap_or(&mut empty[..]);
        run_chunks(
            pool,
            threads,
            ns,
            &mut slots,
            |js, slot, parts: &mut (&mut [[f64; 3]], &mut [[f64; 9]])| {
                this.stage_forces(js, w, (&force, &blocks), parts.0, jacobian.then_some(&mut *parts.1), slot)
            },
            |js| (js.len(), if jacobian { this.partner_ptr[js.end] - this.partner_ptr[js.start] } else { 0 }),
            (p, out),
        );
        self.force = force;
        self.blocks = blocks;
        self.slots = slots;
    }

    /// Site forces per length f_k = −Σ_l ω_l P'(d) Δ/d for k in `ks` (into
    /// `force`, indexed from ks.start), and (Jacobian) the blocks ∂f_k/∂r_i
    /// over the site's stage columns, Σ_l g_kl ℓ_i(s_l) − (Σ_l g_kl) ℓ_i(s_k),
    /// g_kl = ω_l [P'/d I + (P'' − P'/d) ΔΔᵀ/d²] (into `blocks`, indexed from
    /// col_ptr[ks.start]); `slot`: all usize::MAX on entry and exit.
    fn site_forces(
        &self,
        ks: std::ops::Range<usize>,
        pair: PairFn,
        force: &mut [[f64; 3]],
        mut blocks: Option<&mut [[f64; 9]]>,
        slot: &mut [usize],
    ) {
        let order = self.order();
        let (k0, base) = (ks.start, self.col_ptr[ks.start]);
        for k in ks {
            let (c0, c1) = (self.col_ptr[k] - base, self.col_ptr[k + 1] - base);
            if let Some(blocks) = blocks.as_deref_mut() {
                for (t, &i) in self.col[c0 + base..c1 + base].iter().enumerate() {
                    slot[i] = c0 + t;
                }
                blocks[c0..c1].iter_mut().for_each(|v| *v = [0.0; 9]);
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
                let b = self.weight[l];
                let c = -b * p1 / d;
                for i in 0..3 {
                    fk[i] += c * dv[i];
                }
                if let Some(blocks) = blocks.as_deref_mut() {
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
                        let (li, at) = (self.basis[l * order + i], slot[self.stencil[l] + i]);
                        let blk = &mut blocks[at];
                        for m in 0..9 {
                            blk[m] += li * g[m];
                        }
                    }
                }
            }
            force[k - k0] = fk;
            if let Some(blocks) = blocks.as_deref_mut() {
                for i in 0..order {
                    let (li, at) = (self.basis[k * order + i], slot[self.stencil[k] + i]);
                    let blk = &mut blocks[at];
                    for m in 0..9 {
                        blk[m] += li * dk[m];
                    }
                }
                for &i in &self.col[c0 + base..c1 + base] {
                    slot[i] = usize::MAX;
                }
            }
        }
    }

    /// Stage j in `js`: F_j = Σ_{k holds j} ω_k ℓ_j(s_k) f_k, p_j = F_j / w_j
    /// (into `p`, indexed from js.start), and (Jacobian) ∂p_j/∂r_i over j's
    /// partners (into `out`, indexed from partner_ptr[js.start]), from every
    /// site's `force` and `blocks`; `slot` as in [`Self::site_forces`].
    fn stage_forces(
        &self,
        js: std::ops::Range<usize>,
        w: &[f64],
        (force, blocks): (&[[f64; 3]], &[[f64; 9]]),
        p: &mut [[f64; 3]],
        mut out: Option<&mut [[f64; 9]]>,
        slot: &mut [usize],
    ) {
        let order = self.order();
        let (j0, base) = (js.start, self.partner_ptr[js.start]);
        for j in js {
            let (h0, h1) = (self.holder_ptr[j], self.holder_ptr[j + 1]);
            let (q0, q1) = (self.partner_ptr[j], self.partner_ptr[j + 1]);
            if let Some(out) = out.as_deref_mut() {
                for (t, &i) in self.partner[q0..q1].iter().enumerate() {
                    slot[i] = q0 - base + t;
                    out[q0 - base + t] = [0.0; 9];
                }
            }
            let mut pj = [0.0; 3];
            let inv = 1.0 / w[j];
            for &k in &self.holder[h0..h1] {
                let lj = self.weight[k] * inv * self.basis[k * order + (j - self.stencil[k])];
                for c in 0..3 {
                    pj[c] += lj * force[k][c];
                }
                if let Some(out) = out.as_deref_mut() {
                    for (cp, &i) in
                        (self.col_ptr[k]..self.col_ptr[k + 1]).zip(&self.col[self.col_ptr[k]..self.col_ptr[k + 1]])
                    {
                        let (src, dst) = (blocks[cp], &mut out[slot[i]]);
                        for m in 0..9 {
                            dst[m] += lj * src[m];
                        }
                    }
                }
            }
            p[j - j0] = pj;
            if out.is_some() {
                for &i in &self.partner[q0..q1] {
                    slot[i] = usize::MAX;
                }
            }
        }
    }
}

/// Run `work(range, slot, parts)` over 0..n: in one call without a pool,
/// else in `threads` contiguous chunks on the pool, each with its own slot
/// scratch and its own disjoint parts of the two output slices (`sizes`
/// gives a range's lengths in each).
fn run_chunks<'a, W, S>(
    pool: Option<&rayon::ThreadPool>,
    threads: usize,
    n: usize,
    slots: &mut [Vec<usize>],
    work: W,
    sizes: S,
    parts: (&'a mut [[f64; 3]], &'a mut [[f64; 9]]),
) where
    W: Fn(std::ops::Range<usize>, &mut [usize], &mut (&mut [[f64; 3]], &mut [[f64; 9]])) + Sync,
    S: Fn(std::ops::Range<usize>) -> (usize, usize) + Sync,
{
    let (mut a, mut b) = parts;
    match pool {
        Some(pool) if threads > 1 && n >= 64 => {
            let chunk = n.div_ceil(threads);
            pool.scope(|scope| {
                let mut start = 0;
                for slot in slots.iter_mut().take(threads) {
                    if start >= n {
                        break;
                    }
                    let end = (start + chunk).min(n);
                    let (na, nb) = sizes(start..end);
                    let (a0, a1) = std::mem::take(&mut a).split_at_mut(na);
                    let (b0, b1) = std::mem::take(&mut b).split_at_mut(nb);
                    a = a1;
                    b = b1;
                    let work = &work;
                    scope.spawn(move |_| work(start..end, slot, &mut (a0, b0)));
                    start = end;
                }
            });
        }
        _ => work(0..n, &mut slots[0], &mut (a, b)),
    }
}

//! The charged rod's assembly (see [`super::rod`]): its stage points, the
//! near zone's stiffening per stage, the far-pair list built at a reference
//! state, and the Jacobian's pattern with where the pair terms go in it.

use super::gap::Gap;
use super::rod::{RodCharge, HARD_CORE_RANGE};
use super::sites::Sites;
use crate::continuation::system::AssembledSystem;
use crate::continuation::Problem;
use crate::electrostatics::special;
use crate::error::{Error, Result};
use crate::geometry::proximity::CellList;
use crate::linalg::Pattern;
use crate::rod::model::Rod;
use crate::rod::scheme::{Scheme, Tableau};
use crate::status::Status;

/// One stage point of the rod.
#[derive(Clone, Copy, Debug)]
pub(super) struct Point {
    pub(super) element: usize,
    pub(super) stage: usize,
    /// Offset of the stage's state in x.
    pub(super) offset: usize,
    pub(super) s: f64,
    pub(super) w: f64,
}

/// Each element's near run (first, last element): the elements whose stage
/// pairs with it are not far. On a uniform mesh the m = max(`near_elements`,
/// ⌈δ/h⌉) elements on each side ([`RodCharge::near_elements_for`]). On a
/// graded mesh (only with the exact near zone, whose gap integrates the rest
/// of the run with the exact kernel) every element nearer than δ, and at
/// least `near_elements` on each side: element f is far from e when
/// |e − f| > `near_elements` and the arc between them is at least δ, which is
/// the uniform rule where h is constant. Contiguous, as the arc between e
/// and f grows with |e − f|.
pub(super) fn near_runs(rod: &Rod, charge: &RodCharge) -> Vec<(usize, usize)> {
    let ne = rod.elements;
    if rod.breakpoints.is_none() {
        let m = charge.near_elements_for(rod.element_length(), ne);
        return (0..ne).map(|e| (e.saturating_sub(m), (e + m).min(ne - 1))).collect();
    }
    let nodes = rod.node_positions();
    let delta = charge.near_width.unwrap_or(0.0) * (1.0 - 1e-12);
    let k = charge.near_elements;
    (0..ne)
        .map(|e| {
            let mut first = e.saturating_sub(k);
            while first > 0 && nodes[e] - nodes[first] < delta {
                first -= 1;
            }
            let mut last = (e + k).min(ne - 1);
            while last + 1 < ne && nodes[last + 1] - nodes[e + 1] < delta {
                last += 1;
            }
            (first, last)
        })
        .collect()
}

/// The rod a charge can be put on: a straight Kirchhoff rod with
/// uncoupled bending axes and a Gauss scheme (its stage points carry the
/// charge); a graded mesh only with the exact near zone (its sides do not
/// depend on the elements) and the stage points' far zone. Returns the
/// stage count.
pub(super) fn check_rod(rod: &Rod, charge: &RodCharge) -> Result<usize> {
    let s = match rod.scheme {
        Scheme::Gauss(s) => s,
        Scheme::Midpoint => {
            return Err(Error::new(
                Status::ErrOutOfRange,
                "a charged rod needs a Gauss scheme (its stage points carry the charge)",
            ))
        }
    };
    if !rod.law.kirchhoff {
        return Err(Error::new(
            Status::ErrOutOfRange,
            "a charged rod must be a Kirchhoff rod (the near zone's curvature is |u × e3|)",
        ));
    }
    if rod.law.stiffness[(0, 1)] != 0.0 || rod.law.intrinsic_u != nalgebra::Vector3::zeros() {
        return Err(Error::new(Status::ErrOutOfRange, "a charged rod must be straight with uncoupled bending axes"));
    }
    // The element-aligned near zone's sides, the refined far zone's sites
    // and the base pairs' stencils assume equal elements.
    if rod.breakpoints.is_some() && (!charge.exact_near_width || charge.far_points > 0 || charge.base_pairs.is_some()) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            "a charged rod on a graded mesh needs the exact near zone (exact_near_width), \
             the stage points' far zone (far_points 0) and the continuum (no base_pairs)",
        ));
    }
    Ok(s)
}

/// The stage points and, per stage, the near zone's bending stiffening
/// λ²/24 (J₁ + κJ₂) and its curvature-free energy ½λ²J₋₁ over the sides
/// within the near zone's elements (none for base-pair charges, whose
/// discrete sum has no near zone).
pub(super) struct NearZone {
    pub(super) points: Vec<Point>,
    pub(super) stiffening: Vec<f64>,
    pub(super) constant: Vec<f64>,
}

impl NearZone {
    pub(super) fn new(rod: &Rod, charge: &RodCharge, tab: &Tableau, runs: &[(usize, usize)]) -> Self {
        let (s, ne) = (tab.b.len(), rod.elements);
        let uniform = rod.breakpoints.is_none();
        let (kappa, a) = (charge.screening.kappa, charge.screening.a);
        let l2 = charge.line_charge * charge.line_charge;
        let mut near = NearZone {
            points: Vec::with_capacity(ne * s),
            stiffening: Vec::with_capacity(ne * s),
            constant: Vec::with_capacity(ne * s),
        };
        for e in 0..ne {
            let h = rod.element_h(e);
            let (first, last) = runs[e];
            for j in 0..s {
                let (sj, lo, hi) = if uniform {
                    ((e as f64 + tab.c[j]) * h, first as f64 * h, (last + 1) as f64 * h)
                } else {
                    (rod.node_position(e) + tab.c[j] * h, rod.node_position(first), rod.node_position(last + 1))
                };
                let (mut dk, mut c0) = (0.0, 0.0);
                // Cut at exactly δ: the rest of [lo, hi] is the gap's
                // (super::gap), integrated with the exact kernel.
                let exact = |side: f64| match (charge.exact_near_width, charge.near_width) {
                    (true, Some(delta)) => side.min(delta),
                    _ => side,
                };
                for side in [exact(sj - lo), exact(hi - sj)] {
                    if side > a && charge.base_pairs.is_none() {
                        let j1 = special::j(1, a, side, kappa);
                        let j2 = special::j(2, a, side, kappa);
                        dk += l2 / 24.0 * (j1 + kappa * j2);
                        c0 += 0.5 * l2 * special::j(-1, a, side, kappa);
                    }
                }
                near.points.push(Point {
                    element: e,
                    stage: j,
                    offset: rod.stage_offset(e, j),
                    s: sj,
                    w: h * tab.b[j],
                });
                near.stiffening.push(dk);
                near.constant.push(c0);
            }
        }
        near
    }
}

/// The far pairs of stage points (elements outside each other's near
/// runs, [`near_runs`]) within r_off + skin of each other in the reference state (all
/// of them without a cutoff; none without charge or hard core), in CSR
/// form; for charge sites (base pairs, the refined far zone), each stage's
/// partner stages.
pub(super) struct PairList {
    pub(super) adj_ptr: Vec<usize>,
    pub(super) adj: Vec<usize>,
    /// Base pairs or the continuum's refined far zone
    /// ([`RodCharge::far_points`]): then `adj` lists each stage's partner stages.
    pub(super) sites: Option<Sites>,
    /// Whether any pair interacts.
    pub(super) any: bool,
    /// The list holds only pairs within a radius (it goes stale as the
    /// shape moves).
    pub(super) local: bool,
}

impl PairList {
    pub(super) fn new(
        rod: &Rod,
        charge: &RodCharge,
        points: &[Point],
        reference_r: &[[f64; 3]],
        cutoff: Option<(f64, f64)>,
        runs: &[(usize, usize)],
    ) -> Result<Self> {
        let (m, a) = (charge.near_elements_for(rod.element_length(), rod.elements), charge.screening.a);
        let l2 = charge.line_charge * charge.line_charge;
        let far = |j: usize, k: usize| {
            let (first, last) = runs[points[j].element];
            points[k].element < first || points[k].element > last
        };
        let any = l2 != 0.0 || charge.hard_core.is_some();
        let radius = match (cutoff, charge.hard_core) {
            (Some((_, off)), hc) => Some(off.max(if hc.is_some() { HARD_CORE_RANGE * a } else { 0.0 }) + charge.skin),
            (None, Some(_)) if l2 == 0.0 => Some(HARD_CORE_RANGE * a + charge.skin),
            _ => None,
        };
        let stage_s: Vec<f64> = points.iter().map(|p| p.s).collect();
        let sites = match (charge.base_pairs, charge.far_points) {
            _ if l2 == 0.0 => None,
            (Some(b), _) => Some(Sites::base_pairs(&stage_s, rod.length, b, a, reference_r, radius, charge.threads)),
            (None, 0) => None,
            (None, per_element) => Some(Sites::refined(
                &stage_s,
                rod.elements,
                rod.element_length(),
                per_element,
                m,
                reference_r,
                radius,
                charge.threads,
            )),
        };
        let mut adj_ptr = vec![0];
        let mut adj = Vec::new();
        if let Some(sites) = &sites {
            for j in 0..points.len() {
                adj.extend_from_slice(sites.partners(j));
                adj_ptr.push(adj.len());
            }
        } else if any {
            let cells = radius.map(|r| CellList::new(reference_r, r));
            let mut found = Vec::new();
            for j in 0..points.len() {
                match (&cells, radius) {
                    (Some(cells), Some(r)) => {
                        cells.neighbours_within(reference_r, &reference_r[j], r, &mut found);
                        adj.extend(found.iter().copied().filter(|&k| far(j, k)));
                    }
                    _ => adj.extend((0..points.len()).filter(|&k| far(j, k))),
                }
                adj_ptr.push(adj.len());
            }
        } else {
            adj_ptr.resize(points.len() + 1, 0);
        }
        Ok(PairList { adj_ptr, adj, sites, any, local: any && radius.is_some() })
    }

    pub(super) fn partners(&self, j: usize) -> &[usize] {
        &self.adj[self.adj_ptr[j]..self.adj_ptr[j + 1]]
    }
}

/// The charged rod's Jacobian pattern — the rod's, plus each stage's
/// element n-rows × (r_j, q_j) and × each partner's r_k — and where the
/// pair terms go in it.
pub(super) struct Layout {
    pub(super) pattern: Pattern,
    /// Position of each of the rod's entries.
    pub(super) rod_map: Vec<usize>,
    /// Positions of element(j)'s 3(s+1) n-rows × (r_j: 3, q_j: 4).
    pub(super) diag_pos: Vec<usize>,
    /// First n-row position of element(j)'s rows in the columns r_k (3).
    pub(super) adj_pos: Vec<[usize; 3]>,
    /// Base pairs: the positions of each partner block in the n-rows.
    pub(super) full_pos: Vec<usize>,
    /// The exact near zone's gap blocks (x, y): positions of element(x)'s
    /// 3(s+1) n-rows × r_y (3), block-major.
    pub(super) gap_pos: Vec<usize>,
}

impl Layout {
    pub(super) fn new(
        rod: &Rod,
        sys: &AssembledSystem,
        points: &[Point],
        list: &PairList,
        gap: Option<&Gap>,
    ) -> Result<Self> {
        let n = sys.dim();
        let s = rod.scheme.stages();
        // Element e's n-rows: its stages' force rows and the next node's.
        let n_rows = |e: usize| -> Vec<usize> {
            let mut rows: Vec<usize> =
                (0..s).flat_map(|i| (0..3).map(move |c| rod.stage_offset(e, i) + 7 + c)).collect();
            rows.extend((0..3).map(|c| rod.node(e + 1) + 7 + c));
            rows
        };
        let rp = sys.pattern();
        let mut entries: Vec<(usize, usize)> = Vec::with_capacity(rp.nnz() + 27 * list.adj.len());
        for col in 0..n {
            for &row in &rp.row_idx[rp.col_ptr[col]..rp.col_ptr[col + 1]] {
                entries.push((row, col));
            }
        }
        if list.any {
            for (j, pt) in points.iter().enumerate() {
                let rows = n_rows(pt.element);
                for &row in &rows {
                    entries.extend((0..7).map(|c| (row, pt.offset + c)));
                }
                for &k in list.partners(j) {
                    for &row in &rows {
                        entries.extend((0..3).map(|c| (row, points[k].offset + c)));
                    }
                }
            }
        }
        if let Some(gap) = gap {
            for (x, pt) in points.iter().enumerate() {
                let rows = n_rows(pt.element);
                for &y in &gap.block_col[gap.block_ptr[x]..gap.block_ptr[x + 1]] {
                    for &row in &rows {
                        entries.extend((0..3).map(|c| (row, points[y].offset + c)));
                    }
                }
            }
        }
        let pattern = Pattern::from_entries(n, entries);
        let internal = |what: &str| Error::new(Status::ErrInternal, format!("charged rod pattern: {what}"));
        let position = |row: usize, col: usize, what: &str| pattern.position(row, col).ok_or_else(|| internal(what));
        let mut rod_map = Vec::with_capacity(rp.nnz());
        for col in 0..n {
            for &row in &rp.row_idx[rp.col_ptr[col]..rp.col_ptr[col + 1]] {
                rod_map.push(position(row, col, "rod entry missing")?);
            }
        }
        let (mut diag_pos, mut adj_pos, mut full_pos) = (Vec::new(), Vec::with_capacity(list.adj.len()), Vec::new());
        for (j, pt) in points.iter().enumerate().filter(|_| list.any) {
            let rows = n_rows(pt.element);
            for &row in &rows {
                for c in 0..7 {
                    diag_pos.push(position(row, pt.offset + c, "diagonal entry missing")?);
                }
            }
            for &k in list.partners(j) {
                if list.sites.is_some() {
                    for &row in &rows {
                        for c in 0..3 {
                            full_pos.push(position(row, points[k].offset + c, "site block entry missing")?);
                        }
                    }
                    continue;
                }
                let mut base = [0; 3];
                for (c, b) in base.iter_mut().enumerate() {
                    let col = points[k].offset + c;
                    *b = position(rows[0], col, "pair entry missing")?;
                    // The element's n-rows are consecutive in a partner's column.
                    for (i, &row) in rows.iter().enumerate() {
                        if pattern.position(row, col) != Some(*b + i) {
                            return Err(internal("pair rows not consecutive"));
                        }
                    }
                }
                adj_pos.push(base);
            }
        }
        let mut gap_pos = Vec::new();
        if let Some(gap) = gap {
            for (x, pt) in points.iter().enumerate() {
                let rows = n_rows(pt.element);
                for &y in &gap.block_col[gap.block_ptr[x]..gap.block_ptr[x + 1]] {
                    for &row in &rows {
                        for c in 0..3 {
                            gap_pos.push(position(row, points[y].offset + c, "gap block entry missing")?);
                        }
                    }
                }
            }
        }
        Ok(Layout { pattern, rod_map, diag_pos, adj_pos, full_pos, gap_pos })
    }
}

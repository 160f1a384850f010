//! The LU of a sparse matrix whose unknowns are partly private to small
//! blocks — the stage unknowns of a collocated element, each coupled only
//! to its own stage equations and to the element's two nodes — by static
//! condensation, as AUTO-07p and COLSYS factorise collocation systems:
//! each block's unknowns are eliminated by a dense LU of its own square
//! block, the Schur complement on the kept unknowns (the nodes) is a much
//! smaller sparse matrix with the same band, and a solve runs the blocks,
//! the kept system and the blocks again.
//!
//! With the private unknowns L (one set per block, the same indices as
//! their equations) and the kept ones K, after the symmetric permutation
//! that puts L first,
//!   A = [[A_LL, A_LK], [A_KL, A_KK]],  S = A_KK − A_KL A_LL⁻¹ A_LK,
//! A_LL block diagonal. A symmetric permutation leaves the determinant
//! alone, so det A = Π_e det A_LL,e · det S: the sign is read off the
//! blocks' pivots and S's factors (what the continuation's bifurcation
//! monitor needs, which faer's supernodal LU cannot give).
//!
//! Work on a Gauss(4) rod element (52 stage unknowns, 13 + 13 node ones):
//! a 52² dense LU, 14 solves with it and a 13×52×14 product per element,
//! then the LU of a 13(N + 1)-unknown band: dense up to [`DENSE_KEPT`]
//! unknowns, simplicial above — about a third of the flops of the whole
//! matrix's banded LU, in cache-sized dense loops.

use super::dense::dot4;
use super::sparse::{group_by_key, ColumnOrder, Pattern, SparseLu};
use crate::error::{Error, Result};
use crate::status::Status;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::{factor as dense_factor, solve as dense_solves};
use faer::perm::PermRef;
use faer::{Accum, Conj, MatMut, MatRef, Par};
use std::sync::Arc;

/// [`CondensedStructure::new`]'s mark of a kept index (not in a block).
const KEPT: u32 = u32::MAX;

/// One block's private unknowns (= its equations) and where its entries
/// of A go: the part of its elimination fixed by the pattern.
struct BlockMaps {
    /// Private indices, m of them (rows and columns of A_LL,e).
    local: Vec<usize>,
    /// Kept columns its rows reach (positions in the kept numbering), and
    /// kept rows its columns reach.
    kcols: Vec<usize>,
    krows: Vec<usize>,
    /// (position in A's values, index in the dense array) of A_LL,e
    /// (m×m), A_LK,e (m×kc) and A_KL,e (kr×m).
    /// (32 bits: half the memory a gather streams; a pattern of 2³² or
    /// more entries is refused.)
    ll: Vec<(u32, u32)>,
    lk: Vec<(u32, u32)>,
    kl: Vec<(u32, u32)>,
    /// Position in S's values of (krows[i], kcols[j]), at i + kr·j.
    update: Vec<u32>,
}

/// One block's dense arrays, column-major.
struct Block {
    /// LU of A_LL,e in place (unit L below the diagonal; faer's blocked
    /// dense LU) and its row permutation (row k of P A is row perm[k]).
    lu: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    /// The LU's rows, for transposed solves.
    rows: Rows,
    /// A_KL X (kr×kc).
    product: Vec<f64>,
    /// A_LK,e, then X = A_LL⁻¹ A_LK (m×kc); A_KL,e (kr×m).
    lk_values: Vec<f64>,
    x: Vec<f64>,
    kl_values: Vec<f64>,
    /// Scratch for solves (m; max(kr, kc)).
    t: Vec<f64>,
    u: Vec<f64>,
    u2: Vec<f64>,
}

impl Block {
    fn new(maps: &BlockMaps) -> Self {
        let (m, kc, kr) = (maps.local.len(), maps.kcols.len(), maps.krows.len());
        Block {
            lu: vec![0.0; m * m],
            perm: vec![0; m],
            perm_inv: vec![0; m],
            rows: Rows::default(),
            product: vec![0.0; kr * kc],
            lk_values: vec![0.0; m * kc],
            x: vec![0.0; m * kc],
            kl_values: vec![0.0; kr * m],
            t: vec![0.0; m],
            u: vec![0.0; kr.max(kc)],
            u2: vec![0.0; m],
        }
    }
}

/// What a [`CondensedLu`] takes from A's pattern, its blocks and trailing
/// count alone — the index sets, the gather maps, S's pattern — shared by
/// the LUs of one pattern ([`CondensedLu::from_structure`]): building it
/// is most of a rod's tangent set-up.
pub struct CondensedStructure {
    maps: Vec<BlockMaps>,
    /// Kept indices in increasing order.
    kept: Vec<usize>,
    /// (position in A's values, position in S's) of the kept×kept entries:
    /// in S's sparse values, or its dense column-major array (i + nk·j)
    /// when S is factorised dense (then it has no sparse pattern: S's
    /// entries are accumulated in the dense array the LU works in).
    kk: Vec<(u32, u32)>,
    /// S's pattern when S is sparse, and its trailing unknowns.
    spattern: Option<Arc<Pattern>>,
    trailing_kept: usize,
    /// faer's dense work space.
    req: StackReq,
}

pub struct CondensedLu {
    structure: Arc<CondensedStructure>,
    blocks: Vec<Block>,
    schur: Kept,
    schur_values: Vec<f64>,
    /// sign Π det A_LL,e and the blocks' negative pivots.
    blocks_sign: f64,
    blocks_negative: usize,
    factorised: bool,
    /// Scratch: the kept right-hand side; faer's dense work space.
    rhs_kept: Vec<f64>,
    buffer: MemBuffer,
    /// Scratch of the solves of two right-hand sides at once (sized on
    /// the first).
    pair: PairScratch,
    pub factorisations: usize,
    pub solves: usize,
}

/// The rows of a sorted column that lie in lo..lo + m (a contiguous
/// block's own): one run, as a range of the column. Found by walking in
/// from both ends over the rows outside it (the few kept rows, which the
/// caller visits anyway): a binary search's chain of dependent loads
/// took a third of the structure's build.
fn own_run(rows: &[usize], lo: usize, m: usize) -> std::ops::Range<usize> {
    let mut a = 0;
    while a < rows.len() && rows[a] < lo {
        a += 1;
    }
    let mut c = rows.len();
    while c > a && rows[c - 1] >= lo + m {
        c -= 1;
    }
    a..c
}

/// Kept row `pi`'s position in block `e`'s krows: `row_at` keeps the block
/// that last asked and the answer (a block's columns reach the same kept
/// rows: one search per block and row, not per entry).
fn kept_rank(row_at: &mut [(u32, u32)], krows: &[usize], e: u32, pi: u32) -> u32 {
    match row_at[pi as usize] {
        (f, r) if f == e => r,
        _ => {
            let r = krows.binary_search(&(pi as usize)).expect("kept row") as u32;
            row_at[pi as usize] = (e, r);
            r
        }
    }
}

/// The kept system's pattern, merged column by column from sorted lists:
/// column c of S holds A's kept rows of kept column c (`kk`, (row, column)
/// in A's column order), the kept rows of every block whose kept columns
/// include c, and c. Returns it with each kk entry's position and each
/// block's update map (position of (krows[i], kcols[j]) at i + kr·j);
/// None if a list is out of order (a pattern whose rows are not sorted).
fn kept_pattern(
    nk: usize,
    kk: &[(u32, u32)],
    kcols: &[Vec<usize>],
    krows: &[Vec<usize>],
) -> Option<(Pattern, Vec<u32>, Vec<Vec<u32>>)> {
    // The blocks reaching each kept column: (block, the column's index in
    // its kcols).
    let (start, reach) = group_by_key(
        nk,
        kcols
            .iter()
            .enumerate()
            .flat_map(|(e, cols)| cols.iter().enumerate().map(move |(j, &c)| (c, (e as u32, j as u32)))),
    );
    let mut updates: Vec<Vec<u32>> = kcols.iter().zip(krows).map(|(c, r)| vec![0; c.len() * r.len()]).collect();
    let fill: usize = updates.iter().map(Vec::len).sum();
    let mut kk_at = vec![0u32; kk.len()];
    let mut col_ptr = Vec::with_capacity(nk + 1);
    let mut row_idx = Vec::with_capacity(kk.len() + fill + nk);
    col_ptr.push(0);
    let mut t = 0;
    let mut cursor: Vec<usize> = Vec::new();
    for c in 0..nk {
        let kk_end = t + kk[t..].iter().take_while(|&&(_, j)| j as usize == c).count();
        let blocks = &reach[start[c]..start[c + 1]];
        cursor.clear();
        cursor.resize(blocks.len(), 0);
        let begin = row_idx.len();
        let mut diagonal_placed = false;
        loop {
            // The least head of the lists (the diagonal one of them).
            let mut row = if t < kk_end { kk[t].0 as usize } else { usize::MAX };
            for (&(e, _), &at) in blocks.iter().zip(&cursor) {
                if let Some(&r) = krows[e as usize].get(at) {
                    row = row.min(r);
                }
            }
            if !diagonal_placed && c < row {
                row = c;
            }
            if row == usize::MAX {
                break;
            }
            if row_idx.len() > begin && row_idx[row_idx.len() - 1] >= row {
                return None;
            }
            let at = row_idx.len() as u32;
            row_idx.push(row);
            diagonal_placed |= row == c;
            while t < kk_end && kk[t].0 as usize == row {
                kk_at[t] = at;
                t += 1;
            }
            for (&(e, j), k) in blocks.iter().zip(cursor.iter_mut()) {
                let rows = &krows[e as usize];
                if rows.get(*k) == Some(&row) {
                    updates[e as usize][*k + rows.len() * j as usize] = at;
                    *k += 1;
                }
            }
        }
        if t != kk_end {
            return None;
        }
        col_ptr.push(row_idx.len());
    }
    (t == kk.len()).then_some((Pattern { n: nk, col_ptr, row_idx }, kk_at, updates))
}

impl CondensedStructure {
    /// [`CondensedLu::with_dense_limit`]'s structure. Two passes over A's
    /// pattern: the first finds each block's kept columns and rows and
    /// counts its entries of each kind, the second writes the gather maps
    /// into arrays of their final size (no growth, no copy).
    pub fn new(pattern: &Pattern, blocks: &[Vec<usize>], trailing: usize, dense_limit: usize) -> Result<Self> {
        // Pattern's invariant (its fields are public), on which the gather's
        // runs of a block's own rows rely: each column's rows increasing
        // and in range.
        let n = pattern.n;
        let sorted = pattern.col_ptr.len() == n + 1
            && (0..n).all(|j| {
                let rows = &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]];
                rows.windows(2).all(|w| w[0] < w[1]) && rows.last().is_none_or(|&i| i < n)
            });
        if !sorted {
            return Err(Error::new(
                Status::ErrInvalidDimension,
                "condensed LU: the pattern's rows are not increasing and in range in every column",
            ));
        }
        Self::of_sorted(pattern, blocks, trailing, dense_limit)
    }

    /// [`CondensedStructure::new`] for a pattern whose rows are known
    /// increasing and in range (a bordered LU's, checked as it is built).
    pub(crate) fn of_sorted(
        pattern: &Pattern,
        blocks: &[Vec<usize>],
        trailing: usize,
        dense_limit: usize,
    ) -> Result<Self> {
        let n = pattern.n;
        let invalid = |why: String| Error::new(Status::ErrInvalidDimension, format!("condensed LU: {why}"));
        if pattern.nnz() >= u32::MAX as usize || n >= u32::MAX as usize {
            return Err(invalid(format!("{} entries exceed the 32-bit gather maps", pattern.nnz())));
        }
        // Per index: (its block, its place in the block), or (KEPT, its
        // place among the kept): one load per entry instead of three.
        let mut slot = vec![(KEPT, 0u32); n];
        for (e, b) in blocks.iter().enumerate() {
            if b.is_empty() {
                return Err(invalid(format!("block {e} is empty")));
            }
            for (k, &i) in b.iter().enumerate() {
                if i >= n || slot[i].0 != KEPT {
                    return Err(invalid(format!("index {i} of block {e} is out of range or in two blocks")));
                }
                slot[i] = (e as u32, k as u32);
            }
        }
        if slot[n.saturating_sub(trailing)..].iter().any(|s| s.0 != KEPT) {
            return Err(invalid("a trailing unknown is private to a block".into()));
        }
        let mut kept = Vec::new();
        for (i, s) in slot.iter_mut().enumerate() {
            if s.0 == KEPT {
                s.1 = kept.len() as u32;
                kept.push(i);
            }
        }
        if kept.is_empty() {
            return Err(invalid("no unknown is kept".into()));
        }
        // Each block's kept columns (from its rows) and kept rows (from its
        // columns), and its entries of each kind; an entry joining two
        // different blocks breaks the form.
        // A block whose indices run lo, lo + 1, …: its start (a rod's
        // element: its stage unknowns).
        let contiguous: Vec<Option<usize>> =
            blocks.iter().map(|b| b.windows(2).all(|w| w[1] == w[0] + 1).then_some(b[0])).collect();
        let mut kcols: Vec<Vec<usize>> = vec![Vec::new(); blocks.len()];
        let mut krows: Vec<Vec<usize>> = vec![Vec::new(); blocks.len()];
        let mut counts = vec![[0usize; 3]; blocks.len()];
        let mut kk_entries = Vec::new();
        // A's kept–kept entries in pattern order (p, for the gather map).
        let mut kk_sources = Vec::new();
        // A kept row already listed for a block (the block that listed it
        // last): the rows repeat for each of a block's columns.
        let mut listed = vec![KEPT; kept.len()];
        for j in 0..n {
            let (oj, pj) = slot[j];
            let range = pattern.col_ptr[j]..pattern.col_ptr[j + 1];
            if oj == KEPT {
                for p in range {
                    let (oi, pi) = slot[pattern.row_idx[p]];
                    if oi == KEPT {
                        kk_entries.push((pi, pj));
                        kk_sources.push(p as u32);
                    } else {
                        let e = oi as usize;
                        // Columns come in order: a repeat is the last one.
                        if kcols[e].last() != Some(&(pj as usize)) {
                            kcols[e].push(pj as usize);
                        }
                        counts[e][1] += 1;
                    }
                }
            } else {
                let e = oj as usize;
                // A contiguous block's own rows are one run of the column:
                // counted whole, the rows around it looked up.
                let (own, others) = match contiguous[e] {
                    Some(lo) => {
                        let run = own_run(&pattern.row_idx[range.clone()], lo, blocks[e].len());
                        counts[e][0] += run.len();
                        let (a, b) = (range.start + run.start, range.start + run.end);
                        (true, [range.start..a, b..range.end])
                    }
                    None => (false, [range, 0..0]),
                };
                for p in others.into_iter().flatten() {
                    let (oi, pi) = slot[pattern.row_idx[p]];
                    if oi == KEPT {
                        if listed[pi as usize] != oj {
                            listed[pi as usize] = oj;
                            krows[e].push(pi as usize);
                        }
                        counts[e][2] += 1;
                    } else if oi == oj && !own {
                        counts[e][0] += 1;
                    } else {
                        let i = pattern.row_idx[p];
                        return Err(invalid(format!("entry ({i}, {j}) joins blocks {oi} and {oj}")));
                    }
                }
            }
        }
        // kcols are sorted and distinct; a kept row may have been listed
        // again after another block's.
        for v in krows.iter_mut() {
            v.sort_unstable();
            v.dedup();
        }
        // A block's dense arrays are indexed in 32 bits too.
        for (e, b) in blocks.iter().enumerate() {
            let widest = b.len() * b.len().max(kcols[e].len()).max(krows[e].len());
            if widest >= u32::MAX as usize {
                return Err(invalid(format!("block {e}'s dense arrays ({widest} entries) exceed 32-bit indices")));
            }
        }
        // S's pattern: A's kept–kept entries, each block's fill krows ×
        // kcols, the diagonal (a zero there is still a pivot slot).
        let nk = kept.len();
        // (A dense S indexed in 32 bits: nk ≤ 65535; a sparse one's entries
        // at most A's kept ones, the fill and the diagonal.)
        let dense = nk <= dense_limit && nk * nk < u32::MAX as usize;
        let fill: usize = kcols.iter().zip(&krows).map(|(c, r)| c.len() * r.len()).sum();
        if !dense && kk_entries.len() + fill + nk >= u32::MAX as usize {
            return Err(invalid(format!(
                "a kept system of up to {} entries exceeds 32-bit positions",
                kk_entries.len() + fill + nk
            )));
        }
        let (spattern, kk_at, updates) = match dense {
            true => {
                let kk_at = kk_entries.iter().map(|&(i, j)| i + nk as u32 * j).collect();
                let updates = kcols
                    .iter()
                    .zip(&krows)
                    .map(|(c, r)| c.iter().flat_map(|&j| r.iter().map(move |&i| (i + nk * j) as u32)).collect())
                    .collect();
                (None, kk_at, updates)
            }
            false => {
                let (p, kk_at, updates) = kept_pattern(nk, &kk_entries, &kcols, &krows)
                    .ok_or_else(|| invalid("the pattern's rows are not in increasing order".into()))?;
                (Some(Arc::new(p)), kk_at, updates)
            }
        };
        let kk: Vec<(u32, u32)> = kk_sources.into_iter().zip(kk_at).collect();
        let mut out: Vec<BlockMaps> = blocks
            .iter()
            .zip(kcols)
            .zip(krows)
            .zip(updates)
            .zip(&counts)
            .map(|((((local, kcols), krows), update), &[ll, lk, kl])| BlockMaps {
                local: local.clone(),
                kcols,
                krows,
                ll: Vec::with_capacity(ll),
                lk: Vec::with_capacity(lk),
                kl: Vec::with_capacity(kl),
                update,
            })
            .collect();
        // The gather maps, A's entries in pattern order ([`kept_rank`]).
        let mut row_at = vec![(KEPT, 0u32); kept.len()];
        for j in 0..n {
            let (oj, pj) = slot[j];
            let range = pattern.col_ptr[j]..pattern.col_ptr[j + 1];
            if oj == KEPT {
                // One search per block the column reaches (its entries of
                // one block are consecutive: the block's rows are).
                let mut last: Option<(u32, u32)> = None;
                for p in range {
                    let (oi, pi) = slot[pattern.row_idx[p]];
                    if oi == KEPT {
                        continue;
                    }
                    let b = &mut out[oi as usize];
                    let c = match last {
                        Some((f, c)) if f == oi => c,
                        _ => b.kcols.binary_search(&(pj as usize)).expect("kept column") as u32,
                    };
                    last = Some((oi, c));
                    let m = b.local.len() as u32;
                    b.lk.push((p as u32, pi + m * c));
                }
            } else {
                let e = oj as usize;
                let b = &mut out[e];
                let (m, kr) = (b.local.len() as u32, b.krows.len() as u32);
                match contiguous[e] {
                    // The run of own rows straight into A_LL's map; the
                    // rows around it are kept (checked by the first pass).
                    Some(lo) => {
                        let run = own_run(&pattern.row_idx[range.clone()], lo, m as usize);
                        let (a, c) = (range.start + run.start, range.start + run.end);
                        for p in (range.start..a).chain(c..range.end) {
                            let r = kept_rank(&mut row_at, &b.krows, oj, slot[pattern.row_idx[p]].1);
                            b.kl.push((p as u32, r + kr * pj));
                        }
                        b.ll.extend((a..c).map(|q| (q as u32, (pattern.row_idx[q] - lo) as u32 + m * pj)));
                    }
                    None => {
                        for p in range {
                            let (oi, pi) = slot[pattern.row_idx[p]];
                            if oi == KEPT {
                                let r = kept_rank(&mut row_at, &b.krows, oj, pi);
                                b.kl.push((p as u32, r + kr * pj));
                            } else {
                                b.ll.push((p as u32, pi + m * pj));
                            }
                        }
                    }
                }
            }
        }
        let widest = out.iter().map(|b| (b.local.len(), b.kcols.len())).max().unwrap_or((0, 0));
        let req = StackReq::any_of(&[
            dense_factor::lu_in_place_scratch::<usize, f64>(widest.0, widest.0, Par::Seq, Default::default()),
            dense_solves::solve_in_place_scratch::<usize, f64>(widest.0, widest.1.max(1), Par::Seq),
        ]);
        let trailing_kept = trailing.min(kept.len());
        Ok(CondensedStructure { maps: out, kept, kk, spattern, trailing_kept, req })
    }
}

impl CondensedLu {
    /// For A with `pattern`, each entry of `blocks` a set of unknowns that
    /// are private to it: their columns reach only their own rows and kept
    /// rows, and their rows only their own columns and kept columns. The
    /// last `trailing` unknowns (multipliers reaching across A) must be
    /// kept. Err (ErrInvalidDimension) if the pattern does not have that
    /// structure or nothing would be kept. The kept system is factorised
    /// dense up to [`DENSE_KEPT`] unknowns.
    pub fn new(pattern: &Pattern, blocks: &[Vec<usize>], trailing: usize) -> Result<Self> {
        Self::with_dense_limit(pattern, blocks, trailing, DENSE_KEPT)
    }

    /// As [`CondensedLu::new`], the kept system dense up to `dense_limit`
    /// unknowns, sparse above.
    pub fn with_dense_limit(
        pattern: &Pattern,
        blocks: &[Vec<usize>],
        trailing: usize,
        dense_limit: usize,
    ) -> Result<Self> {
        Self::from_structure(Arc::new(CondensedStructure::new(pattern, blocks, trailing, dense_limit)?))
    }

    /// The LU of matrices with `structure`'s pattern.
    pub fn from_structure(structure: Arc<CondensedStructure>) -> Result<Self> {
        let s = &*structure;
        let nk = s.kept.len();
        let schur = match &s.spattern {
            None => Kept::Dense(DenseKept::new(nk)),
            Some(p) => Kept::Sparse(Box::new(SparseLu::shared(p.clone(), s.trailing_kept)?)),
        };
        let req = match &schur {
            Kept::Dense(_) => StackReq::any_of(&[
                s.req,
                dense_factor::lu_in_place_scratch::<usize, f64>(nk, nk, Par::Seq, Default::default()),
            ]),
            Kept::Sparse(_) => s.req,
        };
        Ok(CondensedLu {
            // Sized by the first factorisation, which overwrites them
            // (~50 kB a Gauss(4) element: zeroing them here as well was a
            // tenth of a new rod's set-up).
            blocks: Vec::new(),
            schur_values: vec![0.0; s.spattern.as_ref().map_or(0, |p| p.nnz())],
            schur,
            blocks_sign: 1.0,
            blocks_negative: 0,
            factorised: false,
            rhs_kept: vec![0.0; nk],
            buffer: MemBuffer::new(req),
            pair: PairScratch::default(),
            factorisations: 0,
            solves: 0,
            structure,
        })
    }

    /// Unknowns of the kept system S.
    pub fn kept(&self) -> usize {
        self.structure.kept.len()
    }

    /// The column order of S's LU: a dense one takes S's columns in their
    /// natural order.
    pub fn column_order(&self) -> ColumnOrder {
        self.schur.column_order()
    }

    /// Whether S is factorised as one dense matrix ([`DENSE_KEPT`]).
    pub fn dense_kept(&self) -> bool {
        matches!(self.schur, Kept::Dense(_))
    }

    /// Whether the last factorisation succeeded.
    pub fn factorised(&self) -> bool {
        self.factorised
    }

    /// Factorise A from `values` in its pattern's order. A singular block
    /// or S is ErrNotConverged, a non-finite entry ErrNonFiniteResult.
    pub fn factorise(&mut self, values: &[f64]) -> Result<()> {
        self.factorised = false;
        if self.blocks.len() != self.structure.maps.len() {
            self.blocks = self.structure.maps.iter().map(Block::new).collect();
        }
        for b in &mut self.blocks {
            b.rows.ready = false;
        }
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(Error::new(
                Status::ErrNonFiniteResult,
                format!("condensed LU: matrix entry {k} is not finite"),
            ));
        }
        // S accumulates where its LU works: the dense array, or its sparse
        // values.
        let schur: &mut [f64] = match &mut self.schur {
            Kept::Dense(d) => d.zeroed(),
            Kept::Sparse(_) => {
                self.schur_values.fill(0.0);
                &mut self.schur_values
            }
        };
        for &(p, q) in &self.structure.kk {
            schur[q as usize] += values[p as usize];
        }
        let (mut sign, mut negative) = (1.0, 0);
        for (e, (b, s)) in self.blocks.iter_mut().zip(&self.structure.maps).enumerate() {
            let m = s.local.len();
            b.lu.fill(0.0);
            for &(p, q) in &s.ll {
                b.lu[q as usize] += values[p as usize];
            }
            b.lk_values.fill(0.0);
            for &(p, q) in &s.lk {
                b.lk_values[q as usize] += values[p as usize];
            }
            b.kl_values.fill(0.0);
            for &(p, q) in &s.kl {
                b.kl_values[q as usize] += values[p as usize];
            }
            let (kr, kc) = (s.krows.len(), s.kcols.len());
            let stack = MemStack::new(&mut self.buffer);
            let (block_sign, neg) = factor_block(m, &mut b.lu, &mut b.perm, &mut b.perm_inv, stack)
                .ok_or_else(|| Error::new(Status::ErrNotConverged, format!("condensed LU: block {e} is singular")))?;
            sign *= block_sign;
            negative += neg;
            // X = A_LL⁻¹ A_LK, then S[kr, kc] −= A_KL X.
            b.x.copy_from_slice(&b.lk_values);
            let lu = MatRef::from_column_major_slice(&b.lu, m, m);
            let perm = PermRef::new_checked(&b.perm, &b.perm_inv, m);
            let stack = MemStack::new(&mut self.buffer);
            let x = MatMut::from_column_major_slice_mut(&mut b.x, m, kc);
            dense_solves::solve_in_place_with_conj(lu, lu, perm, Conj::No, x, Par::Seq, stack);
            faer::linalg::matmul::matmul(
                MatMut::from_column_major_slice_mut(&mut b.product, kr, kc),
                Accum::Replace,
                MatRef::from_column_major_slice(&b.kl_values, kr, m),
                MatRef::from_column_major_slice(&b.x, m, kc),
                1.0,
                Par::Seq,
            );
            for (&q, v) in s.update.iter().zip(&b.product) {
                schur[q as usize] -= v;
            }
        }
        self.schur.factorise(&self.schur_values, MemStack::new(&mut self.buffer))?;
        self.blocks_sign = sign;
        self.blocks_negative = negative;
        self.factorised = true;
        self.factorisations += 1;
        Ok(())
    }

    /// Solve A z = rhs in place.
    pub fn solve(&mut self, rhs: &mut [f64]) {
        assert!(self.factorised, "solve before a successful factorisation");
        // Eliminate each block: t = A_LL⁻¹ f_L, f_K[kr] −= A_KL t.
        self.gather_kept(rhs);
        for (b, s) in self.blocks.iter_mut().zip(&self.structure.maps) {
            let m = s.local.len();
            for (t, &i) in b.t.iter_mut().zip(&s.local) {
                *t = rhs[i];
            }
            dense_solve(m, &b.lu, &b.perm, &mut b.t, &mut b.u2);
            // u = A_KL t by columns (contiguous), then scattered.
            let kr = s.krows.len();
            let u = &mut b.u[..kr];
            u.fill(0.0);
            for (col, tk) in b.kl_values.chunks_exact(kr).zip(&b.t) {
                for (ui, a) in u.iter_mut().zip(col) {
                    *ui += a * tk;
                }
            }
            for (&r, ui) in s.krows.iter().zip(u.iter()) {
                self.rhs_kept[r] -= ui;
            }
        }
        self.schur.solve(&mut self.rhs_kept, false);
        self.scatter_kept(rhs);
        // Back: z_L = t − X z_K[kc], by X's columns.
        for (b, s) in self.blocks.iter_mut().zip(&self.structure.maps) {
            for (col, &kc) in b.x.chunks_exact(s.local.len()).zip(&s.kcols) {
                let z = self.rhs_kept[kc];
                for (t, x) in b.t.iter_mut().zip(col) {
                    *t -= x * z;
                }
            }
            for (t, &i) in b.t.iter().zip(&s.local) {
                rhs[i] = *t;
            }
        }
        self.solves += 1;
    }

    /// Solve Aᵀ z = rhs in place (Sᵀ is the Schur complement of Aᵀ).
    pub fn solve_transpose(&mut self, rhs: &mut [f64]) {
        assert!(self.factorised, "solve before a successful factorisation");
        self.gather_kept(rhs);
        // t = A_LL⁻ᵀ f_L, f_K[kc] −= A_LKᵀ t.
        for (b, s) in self.blocks.iter_mut().zip(&self.structure.maps) {
            let m = s.local.len();
            for (t, &i) in b.t.iter_mut().zip(&s.local) {
                *t = rhs[i];
            }
            dense_solve_transpose(m, b.rows.of(m, &b.lu), &b.perm, &mut b.t, &mut b.u2);
            for (c, &kc) in s.kcols.iter().enumerate() {
                let col = &b.lk_values[m * c..m * (c + 1)];
                self.rhs_kept[kc] -= dot4(col, &b.t);
            }
        }
        self.schur.solve(&mut self.rhs_kept, true);
        self.scatter_kept(rhs);
        // Back: z_L = A_LL⁻ᵀ (f_L − A_KLᵀ z_K[kr]).
        for (b, s) in self.blocks.iter_mut().zip(&self.structure.maps) {
            let (m, kr) = (s.local.len(), s.krows.len());
            for (l, &i) in s.local.iter().enumerate() {
                let mut w = rhs[i];
                for (r, &k) in s.krows.iter().enumerate() {
                    w -= b.kl_values[r + kr * l] * self.rhs_kept[k];
                }
                b.t[l] = w;
            }
            dense_solve_transpose(m, b.rows.of(m, &b.lu), &b.perm, &mut b.t, &mut b.u2);
            for (t, &i) in b.t.iter().zip(&s.local) {
                rhs[i] = *t;
            }
        }
        self.solves += 1;
    }

    /// Solve A z = a and A z' = b (or with Aᵀ) in place: each with the
    /// operations of [`CondensedLu::solve`] ([`CondensedLu::solve_transpose`])
    /// in their order, the two side by side, so that each entry of the
    /// factors is read once for both — a rod's blocks and dense kept system
    /// outgrow the cache, and the solves stream them (the σ_min monitor's
    /// subspace iteration solves its two columns together).
    pub fn solve_pair(&mut self, a: &mut [f64], b: &mut [f64], transpose: bool) {
        assert!(self.factorised, "solve before a successful factorisation");
        let s = &*self.structure;
        let sc = &mut self.pair;
        sc.size(s);
        for (v, &i) in sc.kept.iter_mut().zip(&s.kept) {
            *v = [a[i], b[i]];
        }
        for ((blk, maps), t) in self.blocks.iter_mut().zip(&s.maps).zip(&mut sc.t) {
            let m = maps.local.len();
            for (t, &i) in t.iter_mut().zip(&maps.local) {
                *t = [a[i], b[i]];
            }
            if transpose {
                // t = A_LL⁻ᵀ f_L, f_K[kc] −= A_LKᵀ t.
                dense_solve_transpose_pair(m, blk.rows.of(m, &blk.lu), &blk.perm, t, &mut sc.w);
                for (c, &kc) in maps.kcols.iter().enumerate() {
                    let d = dot4_pair(&blk.lk_values[m * c..m * (c + 1)], t);
                    sc.kept[kc] = [sc.kept[kc][0] - d[0], sc.kept[kc][1] - d[1]];
                }
            } else {
                // t = A_LL⁻¹ f_L, f_K[kr] −= A_KL t (by A_KL's columns).
                dense_solve_pair(m, &blk.lu, &blk.perm, t, &mut sc.w);
                let kr = maps.krows.len();
                let u = &mut sc.u[..kr];
                u.fill([0.0; 2]);
                for (col, tk) in blk.kl_values.chunks_exact(kr).zip(t.iter()) {
                    for (ui, x) in u.iter_mut().zip(col) {
                        ui[0] += x * tk[0];
                        ui[1] += x * tk[1];
                    }
                }
                for (&r, ui) in maps.krows.iter().zip(u.iter()) {
                    sc.kept[r] = [sc.kept[r][0] - ui[0], sc.kept[r][1] - ui[1]];
                }
            }
        }
        self.schur.solve_pair(&mut sc.kept, transpose, &mut sc.w, &mut sc.split);
        for (v, &i) in sc.kept.iter().zip(&s.kept) {
            (a[i], b[i]) = (v[0], v[1]);
        }
        for ((blk, maps), t) in self.blocks.iter_mut().zip(&s.maps).zip(&mut sc.t) {
            let m = maps.local.len();
            if transpose {
                // z_L = A_LL⁻ᵀ (f_L − A_KLᵀ z_K[kr]).
                let kr = maps.krows.len();
                for (l, &i) in maps.local.iter().enumerate() {
                    let mut w = [a[i], b[i]];
                    for (r, &k) in maps.krows.iter().enumerate() {
                        let x = blk.kl_values[r + kr * l];
                        w = [w[0] - x * sc.kept[k][0], w[1] - x * sc.kept[k][1]];
                    }
                    t[l] = w;
                }
                dense_solve_transpose_pair(m, blk.rows.of(m, &blk.lu), &blk.perm, t, &mut sc.w);
            } else {
                // z_L = t − X z_K[kc], by X's columns.
                for (col, &kc) in blk.x.chunks_exact(m).zip(&maps.kcols) {
                    let z = sc.kept[kc];
                    for (t, x) in t.iter_mut().zip(col) {
                        *t = [t[0] - x * z[0], t[1] - x * z[1]];
                    }
                }
            }
            for (t, &i) in t.iter().zip(&maps.local) {
                (a[i], b[i]) = (t[0], t[1]);
            }
        }
        self.solves += 2;
    }

    /// The kept entries of `rhs` into the kept system's right-hand side.
    fn gather_kept(&mut self, rhs: &[f64]) {
        for (v, &i) in self.rhs_kept.iter_mut().zip(&self.structure.kept) {
            *v = rhs[i];
        }
    }

    /// The kept system's solution back into `rhs`.
    fn scatter_kept(&self, rhs: &mut [f64]) {
        for (v, &i) in self.rhs_kept.iter().zip(&self.structure.kept) {
            rhs[i] = *v;
        }
    }

    /// sign det A (±1) of the last factorisation.
    pub fn determinant_sign(&mut self) -> f64 {
        assert!(self.factorised, "determinant before a successful factorisation");
        self.blocks_sign * self.schur.determinant_sign()
    }

    /// Negative pivots of the blocks' and S's factors (row pivoting: only
    /// the parity, with the permutations', is meaningful — see
    /// [`SparseLu::negative_pivots`]).
    pub fn negative_pivots(&mut self) -> usize {
        assert!(self.factorised, "pivots before a successful factorisation");
        self.blocks_negative + self.schur.negative_pivots()
    }

    /// Entries of the factors: the blocks' dense LUs and X, S's L + U.
    pub fn fill(&self) -> usize {
        let s = &*self.structure;
        s.maps.iter().map(|b| b.local.len() * (b.local.len() + b.kcols.len())).sum::<usize>() + self.schur.fill()
    }
}

/// Kept systems of at most this many unknowns are factorised as one dense
/// matrix. A rod's S (13 unknowns a node, the border last) is a band of
/// width ~2·13 with a dense border: up to about 24 elements the dense
/// LU's (2/3)n³ flops in faer's blocked kernels and its plain triangular
/// solves take less time than the simplicial LU's indexed column updates
/// and solves (a whole ANM run, kept systems of 66 to 430 unknowns:
/// `benches/README.md`).
pub const DENSE_KEPT: usize = 320;

/// S's LU: simplicial sparse, or dense when S is small.
enum Kept {
    Sparse(Box<SparseLu>),
    Dense(DenseKept),
}

impl Kept {
    /// A sparse S from its `values`; a dense one from its own array
    /// ([`DenseKept::zeroed`], accumulated since).
    fn factorise(&mut self, values: &[f64], stack: &mut MemStack) -> Result<()> {
        match self {
            Kept::Sparse(lu) => lu.factorise_exact(values),
            Kept::Dense(d) => d.factorise(stack),
        }
    }

    /// S z = b (or Sᵀ z = b) in place.
    fn solve(&mut self, b: &mut [f64], transpose: bool) {
        match (self, transpose) {
            (Kept::Sparse(lu), false) => lu.solve(b),
            (Kept::Sparse(lu), true) => lu.solve_transpose(b),
            (Kept::Dense(d), false) => dense_solve(d.n, &d.lu, &d.perm, b, &mut d.w),
            (Kept::Dense(d), true) => dense_solve_transpose(d.n, d.rows.of(d.n, &d.lu), &d.perm, b, &mut d.w),
        }
    }

    /// The two columns of `b` solved at once (dense; a sparse S solves
    /// them in turn through `split`). `w`: scratch, S's order at least.
    fn solve_pair(&mut self, b: &mut [Pair], transpose: bool, w: &mut [Pair], split: &mut [Vec<f64>; 2]) {
        match (self, transpose) {
            (Kept::Dense(d), false) => dense_solve_pair(d.n, &d.lu, &d.perm, b, w),
            (Kept::Dense(d), true) => dense_solve_transpose_pair(d.n, d.rows.of(d.n, &d.lu), &d.perm, b, w),
            (kept, _) => {
                for (c, v) in split.iter_mut().enumerate() {
                    v.clear();
                    v.extend(b.iter().map(|p| p[c]));
                    kept.solve(v, transpose);
                }
                for (p, (x, y)) in b.iter_mut().zip(split[0].iter().zip(&split[1])) {
                    *p = [*x, *y];
                }
            }
        }
    }

    fn determinant_sign(&mut self) -> f64 {
        match self {
            Kept::Sparse(lu) => lu.determinant_sign_and_log().0,
            Kept::Dense(d) => d.sign,
        }
    }

    fn negative_pivots(&mut self) -> usize {
        match self {
            Kept::Sparse(lu) => lu.negative_pivots(),
            Kept::Dense(d) => d.negative,
        }
    }

    fn fill(&self) -> usize {
        match self {
            Kept::Sparse(lu) => lu.fill(),
            Kept::Dense(d) => d.n * d.n,
        }
    }

    /// A dense LU takes S's columns in their natural order.
    fn column_order(&self) -> ColumnOrder {
        match self {
            Kept::Sparse(lu) => lu.column_order(),
            Kept::Dense(_) => ColumnOrder::Natural,
        }
    }
}

/// S as one dense column-major matrix, factorised in place by
/// [`factor_block`] (row partial pivoting: as stable as the sparse LU's,
/// and exact elimination, so S's determinant sign is read off the same).
struct DenseKept {
    n: usize,
    lu: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    /// The LU's rows, for transposed solves.
    rows: Rows,
    sign: f64,
    negative: usize,
    /// Scratch for solves (n).
    w: Vec<f64>,
}

impl DenseKept {
    fn new(n: usize) -> Self {
        // The arrays are sized by the first factorisation.
        DenseKept {
            n,
            lu: Vec::new(),
            perm: Vec::new(),
            perm_inv: Vec::new(),
            rows: Rows::default(),
            sign: 1.0,
            negative: 0,
            w: Vec::new(),
        }
    }

    /// The dense array zeroed (sized on first use), for S's entries to be
    /// accumulated in before [`DenseKept::factorise`].
    fn zeroed(&mut self) -> &mut [f64] {
        self.rows.ready = false;
        let n = self.n;
        if self.lu.len() != n * n {
            (self.lu, self.perm, self.perm_inv, self.w) = (vec![0.0; n * n], vec![0; n], vec![0; n], vec![0.0; n]);
        } else {
            self.lu.fill(0.0);
        }
        &mut self.lu
    }

    /// Factorise S in place (accumulated since [`DenseKept::zeroed`];
    /// finite: A's entries were checked). A zero pivot is ErrNotConverged.
    fn factorise(&mut self, stack: &mut MemStack) -> Result<()> {
        let (sign, negative) = factor_block(self.n, &mut self.lu, &mut self.perm, &mut self.perm_inv, stack)
            .ok_or_else(|| Error::new(Status::ErrNotConverged, "condensed LU: the kept system is singular"))?;
        (self.sign, self.negative) = (sign, negative);
        Ok(())
    }
}

/// Factorise the m×m column-major block `a` in place with faer's dense
/// LU (row partial pivoting, P A = L U): (sign det, negative entries of
/// U's diagonal), None if a pivot is zero or not finite.
fn factor_block(
    m: usize,
    a: &mut [f64],
    perm: &mut [usize],
    perm_inv: &mut [usize],
    stack: &mut MemStack,
) -> Option<(f64, usize)> {
    let (info, _) = dense_factor::lu_in_place(
        MatMut::from_column_major_slice_mut(a, m, m),
        perm,
        perm_inv,
        Par::Seq,
        stack,
        Default::default(),
    );
    let mut sign = if info.transposition_count % 2 == 1 { -1.0 } else { 1.0 };
    let mut negative = 0;
    for k in 0..m {
        let pivot = a[k + m * k];
        if !(pivot != 0.0 && pivot.is_finite()) {
            return None;
        }
        if pivot < 0.0 {
            negative += 1;
            sign = -sign;
        }
    }
    Some((sign, negative))
}

/// Solve A z = b in place with [`factor_block`]'s factors (`w` scratch, m).
fn dense_solve(m: usize, lu: &[f64], perm: &[usize], b: &mut [f64], w: &mut [f64]) {
    for (wi, &p) in w.iter_mut().zip(perm) {
        *wi = b[p];
    }
    // L y = P b (unit lower), column-oriented.
    for k in 0..m {
        let wk = w[k];
        if wk != 0.0 {
            for (v, l) in w[k + 1..].iter_mut().zip(&lu[k + 1 + m * k..m * (k + 1)]) {
                *v -= l * wk;
            }
        }
    }
    // U z = y.
    for k in (0..m).rev() {
        w[k] /= lu[k + m * k];
        let wk = w[k];
        if wk != 0.0 {
            for (v, u) in w[..k].iter_mut().zip(&lu[m * k..m * k + k]) {
                *v -= u * wk;
            }
        }
    }
    b.copy_from_slice(&w[..m]);
}

/// A dense LU's rows, copied out of its column-major factors on the first
/// transposed solve after a factorisation (allocated then too): with them
/// the transposed triangular solves run by columns of Uᵀ and Lᵀ — axpys,
/// as the plain solve — instead of dot products, each of which waits for
/// the one before (a chain of reductions: twice the time on a rod's 52×52
/// blocks).
#[derive(Default)]
struct Rows {
    /// Row-major m×m: `lut[m·i + j]` is the LU's (i, j).
    lut: Vec<f64>,
    ready: bool,
}

impl Rows {
    /// The rows of the m×m column-major `lu`.
    fn of(&mut self, m: usize, lu: &[f64]) -> &[f64] {
        if !self.ready {
            self.lut.resize(m * m, 0.0);
            for (j, col) in lu.chunks_exact(m).enumerate() {
                for (i, v) in col.iter().enumerate() {
                    self.lut[m * i + j] = *v;
                }
            }
            self.ready = true;
        }
        &self.lut
    }
}

/// Solve Aᵀ z = b in place with [`factor_block`]'s factors given by rows
/// ([`Rows`]; Aᵀ = Uᵀ Lᵀ P; `w` scratch, m).
fn dense_solve_transpose(m: usize, lut: &[f64], perm: &[usize], b: &mut [f64], w: &mut [f64]) {
    // Uᵀ y = b, forward by Uᵀ's columns: column k is U's row k.
    for k in 0..m {
        let row = &lut[m * k..m * (k + 1)];
        b[k] /= row[k];
        let bk = b[k];
        if bk != 0.0 {
            for (v, u) in b[k + 1..m].iter_mut().zip(&row[k + 1..]) {
                *v -= u * bk;
            }
        }
    }
    // Lᵀ v = y (unit), backward by Lᵀ's columns: column k is L's row k.
    for k in (0..m).rev() {
        let bk = b[k];
        if bk != 0.0 {
            for (v, l) in b[..k].iter_mut().zip(&lut[m * k..m * k + k]) {
                *v -= l * bk;
            }
        }
    }
    // z = Pᵀ v.
    for (k, &p) in perm.iter().enumerate() {
        w[p] = b[k];
    }
    b.copy_from_slice(&w[..m]);
}

/// Two right-hand sides, entry by entry ([`CondensedLu::solve_pair`]).
type Pair = [f64; 2];

/// The scratch of [`CondensedLu::solve_pair`]: the kept right-hand sides,
/// each block's t (kept from the forward sweep to the back one), a dense
/// solve's work column and A_KL t; a sparse S's two columns.
#[derive(Default)]
struct PairScratch {
    sized: bool,
    kept: Vec<Pair>,
    t: Vec<Vec<Pair>>,
    w: Vec<Pair>,
    u: Vec<Pair>,
    split: [Vec<f64>; 2],
}

impl PairScratch {
    fn size(&mut self, s: &CondensedStructure) {
        if self.sized {
            return;
        }
        self.sized = true;
        let widest = s.maps.iter().map(|m| m.local.len()).max().unwrap_or(0);
        let reach = s.maps.iter().map(|m| m.krows.len().max(m.kcols.len())).max().unwrap_or(0);
        self.kept = vec![[0.0; 2]; s.kept.len()];
        self.t = s.maps.iter().map(|m| vec![[0.0; 2]; m.local.len()]).collect();
        self.w = vec![[0.0; 2]; widest.max(s.kept.len())];
        self.u = vec![[0.0; 2]; reach];
    }
}

/// v −= a·s for each column of the pair, a column whose s is zero left
/// alone (as the one-column solves skip it: the same operations).
#[inline(always)]
fn axpy_pair(v: &mut [Pair], a: &[f64], s: Pair) {
    match (s[0] != 0.0, s[1] != 0.0) {
        (true, true) => {
            for (v, x) in v.iter_mut().zip(a) {
                *v = [v[0] - x * s[0], v[1] - x * s[1]];
            }
        }
        (true, false) => v.iter_mut().zip(a).for_each(|(v, x)| v[0] -= x * s[0]),
        (false, true) => v.iter_mut().zip(a).for_each(|(v, x)| v[1] -= x * s[1]),
        (false, false) => {}
    }
}

/// [`dense_solve`] on two right-hand sides at once.
fn dense_solve_pair(m: usize, lu: &[f64], perm: &[usize], b: &mut [Pair], w: &mut [Pair]) {
    for (wi, &p) in w.iter_mut().zip(perm) {
        *wi = b[p];
    }
    for k in 0..m {
        let wk = w[k];
        axpy_pair(&mut w[k + 1..m], &lu[k + 1 + m * k..m * (k + 1)], wk);
    }
    for k in (0..m).rev() {
        let d = lu[k + m * k];
        w[k] = [w[k][0] / d, w[k][1] / d];
        let wk = w[k];
        axpy_pair(&mut w[..k], &lu[m * k..m * k + k], wk);
    }
    b[..m].copy_from_slice(&w[..m]);
}

/// [`dense_solve_transpose`] on two right-hand sides at once.
fn dense_solve_transpose_pair(m: usize, lut: &[f64], perm: &[usize], b: &mut [Pair], w: &mut [Pair]) {
    for k in 0..m {
        let row = &lut[m * k..m * (k + 1)];
        b[k] = [b[k][0] / row[k], b[k][1] / row[k]];
        let bk = b[k];
        axpy_pair(&mut b[k + 1..m], &row[k + 1..], bk);
    }
    for k in (0..m).rev() {
        let bk = b[k];
        axpy_pair(&mut b[..k], &lut[m * k..m * k + k], bk);
    }
    for (k, &p) in perm.iter().enumerate() {
        w[p] = b[k];
    }
    b[..m].copy_from_slice(&w[..m]);
}

/// [`dot4`] of `a` with each column of `b`, in its order.
fn dot4_pair(a: &[f64], b: &[Pair]) -> Pair {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut s = [[0.0; 4]; 2];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            s[0][k] += x[k] * y[k][0];
            s[1][k] += x[k] * y[k][1];
        }
    }
    for (k, (x, y)) in ra.iter().zip(rb).enumerate() {
        s[0][k] += x * y[0];
        s[1][k] += x * y[1];
    }
    [(s[0][0] + s[0][1]) + (s[0][2] + s[0][3]), (s[1][0] + s[1][1]) + (s[1][2] + s[1][3])]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A block-bidiagonal "collocation" matrix: per element a private block
    /// of `m` unknowns between kept nodes of `k`, plus a boundary row pair
    /// coupling the first and last nodes; pseudo-random values.
    fn collocation(elements: usize, m: usize, k: usize, seed: u64) -> (Pattern, Vec<f64>, Vec<Vec<usize>>) {
        let bs = k + m;
        let n = elements * bs + k;
        let mut state = seed;
        let mut rnd = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let mut entries = Vec::new();
        let mut blocks = Vec::new();
        for e in 0..elements {
            let base = e * bs;
            let local: Vec<usize> = (base + k..base + bs).collect();
            // Stage rows: node e and the stages; next node's rows: node e,
            // stages, node e + 1.
            for &r in &local {
                entries.extend((base..base + bs).map(|c| (r, c)));
            }
            for r in base + bs..base + bs + k {
                entries.extend((base..base + bs + k).map(|c| (r, c)));
            }
            blocks.push(local);
        }
        // Boundary rows (node 0's) reach node 0 and the last node.
        for r in 0..k {
            entries.extend((0..k).map(|c| (r, c)));
            entries.extend((n - k..n).map(|c| (r, c)));
        }
        let pattern = Pattern::from_entries(n, entries);
        let mut values: Vec<f64> = (0..pattern.nnz()).map(|_| rnd()).collect();
        for i in 0..n {
            values[pattern.position(i, i).unwrap()] += 4.0;
        }
        (pattern, values, blocks)
    }

    /// The condensation's determinant sign is the whole LU's, and its
    /// solves with A and Aᵀ agree with the whole LU's to 1e-12 relative
    /// (both factorised from the same values).
    fn solves_like_the_whole_lu(whole: &mut SparseLu, cond: &mut CondensedLu, what: &str) {
        assert_eq!(cond.determinant_sign(), whole.determinant_sign_and_log().0, "{what}");
        let n = whole.pattern().n;
        for transpose in [false, true] {
            let b: Vec<f64> = (0..n).map(|i| ((i * 7 + 3) % 11) as f64 - 5.0).collect();
            let (mut z1, mut z2) = (b.clone(), b.clone());
            if transpose {
                whole.solve_transpose(&mut z1);
                cond.solve_transpose(&mut z2);
            } else {
                whole.solve(&mut z1);
                cond.solve(&mut z2);
            }
            let scale = z1.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let diff = z1.iter().zip(&z2).fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            assert!(diff <= 1e-12 * scale, "{what}, transpose {transpose}: {diff:e}");
        }
    }

    /// Reference: the simplicial LU of the whole matrix (faer), its
    /// solves and determinant sign; agreement to 1e-12 relative.
    #[test]
    fn condensation_solves_like_the_whole_lu_and_keeps_the_determinant_sign() {
        let cases = [(1, 4, 3, 1), (5, 8, 3, 2), (8, 52, 13, 3), (3, 6, 2, 4)];
        for ((elements, m, k, seed), dense) in cases.into_iter().flat_map(|c| [(c, false), (c, true)]) {
            let (pattern, mut values, blocks) = collocation(elements, m, k, seed);
            let n = pattern.n;
            let mut whole = SparseLu::new(pattern.clone()).unwrap();
            let limit = if dense { usize::MAX } else { 0 };
            let mut cond = CondensedLu::with_dense_limit(&pattern, &blocks, 0, limit).unwrap();
            assert_eq!(cond.dense_kept(), dense);
            assert_eq!(cond.kept(), (elements + 1) * k);
            for flip in 0..3 {
                if flip > 0 {
                    // Negate one private row and one kept row: det changes
                    // sign each time.
                    let row = if flip == 1 { blocks[0][0] } else { 0 };
                    for j in 0..n {
                        if let Some(p) = pattern.position(row, j) {
                            values[p] = -values[p];
                        }
                    }
                }
                whole.factorise(&values).unwrap();
                cond.factorise(&values).unwrap();
                solves_like_the_whole_lu(&mut whole, &mut cond, &format!("case {elements}×{m} {dense}"));
            }
        }
    }

    /// The same collocation matrix with its unknowns renumbered by a
    /// pseudo-random permutation (each block's indices scattered, so the
    /// general, non-contiguous gather is taken) and with a block's indices
    /// listed backwards: the condensation still solves like the whole
    /// sparse LU of the permuted matrix (reference, 1e-12) and keeps its
    /// determinant sign; and the kept system's merged pattern and update
    /// positions are those of the counting-sort construction
    /// (`Pattern::with_positions_and_diagonal` on the kept–kept and fill
    /// entries).
    #[test]
    fn scattered_blocks_condense_like_the_whole_lu() {
        for (elements, m, k, seed) in [(5, 8, 3, 2), (3, 6, 2, 4), (8, 52, 13, 3)] {
            let (pattern, values, blocks) = collocation(elements, m, k, seed);
            let n = pattern.n;
            // perm[i]: the new index of unknown i.
            let mut perm: Vec<usize> = (0..n).collect();
            let mut state = seed.wrapping_add(17);
            for i in (1..n).rev() {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                perm.swap(i, (state >> 33) as usize % (i + 1));
            }
            let entries: Vec<(usize, usize)> =
                (0..n).flat_map(|j| (pattern.col_ptr[j]..pattern.col_ptr[j + 1]).map(move |p| (p, j))).collect();
            let permuted = Pattern::from_entries(n, entries.iter().map(|&(p, j)| (perm[pattern.row_idx[p]], perm[j])));
            let mut pvalues = vec![0.0; permuted.nnz()];
            for &(p, j) in &entries {
                pvalues[permuted.position(perm[pattern.row_idx[p]], perm[j]).unwrap()] = values[p];
            }
            let mut pblocks: Vec<Vec<usize>> = blocks.iter().map(|b| b.iter().map(|&i| perm[i]).collect()).collect();
            pblocks[0].reverse();
            // Trailing kept unknowns must stay kept: none here.
            let mut whole = SparseLu::new(permuted.clone()).unwrap();
            whole.factorise(&pvalues).unwrap();
            for limit in [0, usize::MAX] {
                let mut cond = CondensedLu::with_dense_limit(&permuted, &pblocks, 0, limit).unwrap();
                cond.factorise(&pvalues).unwrap();
                solves_like_the_whole_lu(&mut whole, &mut cond, &format!("{elements}×{m}, limit {limit}"));
            }
            // The kept system's structure against the counting sort's.
            for (pat, blk) in [(&pattern, &blocks), (&permuted, &pblocks)] {
                // A sparse S (dense limit 0): the one with a pattern.
                let s = CondensedStructure::new(pat, blk, 0, 0).unwrap();
                let kept_pos = |i: usize| s.kept.binary_search(&i).unwrap();
                let mut list = Vec::new();
                for j in 0..pat.n {
                    for p in pat.col_ptr[j]..pat.col_ptr[j + 1] {
                        let i = pat.row_idx[p];
                        if s.kept.binary_search(&i).is_ok() && s.kept.binary_search(&j).is_ok() {
                            list.push((kept_pos(i), kept_pos(j)));
                        }
                    }
                }
                let kk = list.len();
                for b in &s.maps {
                    for &c in &b.kcols {
                        list.extend(b.krows.iter().map(|&r| (r, c)));
                    }
                }
                let (reference, at) = Pattern::with_positions_and_diagonal(s.kept.len(), &list);
                assert_eq!(**s.spattern.as_ref().unwrap(), reference);
                assert_eq!(s.kk.iter().map(|&(_, q)| q).collect::<Vec<_>>(), at[..kk]);
                let updates: Vec<u32> = s.maps.iter().flat_map(|b| b.update.iter().copied()).collect();
                assert_eq!(updates, at[kk..]);
            }
        }
    }

    /// Two right-hand sides solved together are each bitwise the one-column
    /// solve's (the same operations in their order; a column with exact
    /// zeros where the other has none exercises the skipped updates), with
    /// A and Aᵀ, a dense and a sparse kept system; and within 1e-12 of the
    /// whole matrix's sparse LU (the independent reference).
    #[test]
    fn a_pair_of_solves_is_two_single_ones() {
        for (elements, m, k, seed) in [(5, 8, 3, 2), (8, 52, 13, 3), (3, 6, 2, 4), (0, 6, 2, 4)] {
            for limit in [0, usize::MAX] {
                // The last case: no blocks at all, every unknown kept.
                let (pattern, values, blocks) = match elements {
                    0 => {
                        let (pattern, values, _) = collocation(3, m, k, seed);
                        (pattern, values, vec![])
                    }
                    _ => collocation(elements, m, k, seed),
                };
                let n = pattern.n;
                let mut whole = SparseLu::new(pattern.clone()).unwrap();
                whole.factorise(&values).unwrap();
                let mut cond = CondensedLu::with_dense_limit(&pattern, &blocks, 0, limit).unwrap();
                cond.factorise(&values).unwrap();
                for transpose in [false, true] {
                    let a: Vec<f64> = (0..n).map(|i| ((i * 7 + 3) % 11) as f64 - 5.0).collect();
                    let b: Vec<f64> =
                        (0..n).map(|i| if i % 3 == 0 { 0.0 } else { ((i * 5 + 1) % 13) as f64 - 6.0 }).collect();
                    let (mut pa, mut pb) = (a.clone(), b.clone());
                    cond.solve_pair(&mut pa, &mut pb, transpose);
                    for (rhs, pair) in [(&a, &pa), (&b, &pb)] {
                        let (mut one, mut reference) = (rhs.clone(), rhs.clone());
                        if transpose {
                            cond.solve_transpose(&mut one);
                            whole.solve_transpose(&mut reference);
                        } else {
                            cond.solve(&mut one);
                            whole.solve(&mut reference);
                        }
                        let what = format!("{elements}×{m}, dense limit {limit}, transpose {transpose}");
                        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                        assert_eq!(bits(pair), bits(&one), "{what}");
                        let scale = reference.iter().fold(0.0f64, |s, v| s.max(v.abs()));
                        let diff = reference.iter().zip(pair.iter()).fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
                        assert!(diff <= 1e-12 * scale, "{what}: {diff:e}");
                    }
                }
            }
        }
    }

    /// A zero kept row (node 0's boundary row, which reaches no private
    /// column) makes S exactly singular: both kinds of kept LU say so
    /// (ErrNotConverged, the status on which the bordered LU falls back
    /// to B's own), and factorise again once the row is restored.
    #[test]
    fn a_singular_kept_system_is_refused_by_either_kind() {
        let (pattern, values, blocks) = collocation(3, 6, 2, 7);
        let n = pattern.n;
        let mut zeroed = values.clone();
        for j in 0..n {
            if let Some(p) = pattern.position(0, j) {
                zeroed[p] = 0.0;
            }
        }
        for limit in [0, usize::MAX] {
            let mut cond = CondensedLu::with_dense_limit(&pattern, &blocks, 0, limit).unwrap();
            let err = cond.factorise(&zeroed).expect_err("singular S");
            assert_eq!(err.status, Status::ErrNotConverged, "{}", err.message);
            assert!(!cond.factorised());
            cond.factorise(&values).unwrap();
            assert!(cond.factorised());
        }
    }

    /// A block whose private unknowns reach another block's rows is
    /// refused, as is a trailing unknown that is private.
    #[test]
    fn a_pattern_without_the_form_is_refused() {
        let (pattern, _, mut blocks) = collocation(3, 4, 2, 5);
        assert!(CondensedLu::new(&pattern, &blocks, 0).is_ok());
        let n = pattern.n;
        assert!(CondensedLu::new(&pattern, &[vec![n - 1]], 1).is_err());
        // Merge node 1 (rows reach elements 0 and 1) into block 0.
        blocks[0].extend(6..8);
        let err = CondensedLu::new(&pattern, &blocks, 0).err().unwrap();
        assert_eq!(err.status, Status::ErrInvalidDimension);
        // A column whose rows are out of order (Pattern's fields are
        // public): refused, not gathered as if kept row 2 were the block's.
        let unsorted = Pattern { n: 3, col_ptr: vec![0, 3, 5, 8], row_idx: vec![0, 2, 1, 0, 1, 0, 1, 2] };
        let err = CondensedLu::new(&unsorted, &[vec![0, 1]], 0).err().unwrap();
        assert_eq!(err.status, Status::ErrInvalidDimension);
        let sorted = Pattern { n: 3, col_ptr: vec![0, 3, 5, 8], row_idx: vec![0, 1, 2, 0, 1, 0, 1, 2] };
        assert!(CondensedLu::new(&sorted, &[vec![0, 1]], 0).is_ok());
    }

    /// Reference: a 3×3 by hand (det = −2 by cofactors), and its solves.
    #[test]
    fn dense_lu_by_hand() {
        // A = [[0, 1, 2], [1, 0, 3], [4, −3, 8]] column-major.
        let mut a = vec![0.0, 1.0, 4.0, 1.0, 0.0, -3.0, 2.0, 3.0, 8.0];
        let orig = a.clone();
        let (mut perm, mut inv, mut w) = (vec![0; 3], vec![0; 3], vec![0.0; 3]);
        let mut buffer =
            MemBuffer::new(dense_factor::lu_in_place_scratch::<usize, f64>(3, 3, Par::Seq, Default::default()));
        let (sign, _) = factor_block(3, &mut a, &mut perm, &mut inv, MemStack::new(&mut buffer)).unwrap();
        assert_eq!(sign, -1.0);
        let x = [1.0, 2.0, 3.0];
        let mut b: Vec<f64> = (0..3).map(|i| (0..3).map(|j| orig[i + 3 * j] * x[j]).sum()).collect();
        dense_solve(3, &a, &perm, &mut b, &mut w);
        assert!(b.iter().zip(&x).all(|(u, v)| (u - v).abs() < 1e-14), "{b:?}");
        let mut bt: Vec<f64> = (0..3).map(|j| (0..3).map(|i| orig[i + 3 * j] * x[i]).sum()).collect();
        dense_solve_transpose(3, Rows::default().of(3, &a), &perm, &mut bt, &mut w);
        assert!(bt.iter().zip(&x).all(|(u, v)| (u - v).abs() < 1e-14), "{bt:?}");
    }
}

//! Sparse matrices with a fixed pattern and their LU factorisation (faer).
//!
//! A continuation factorises the same pattern hundreds of times: the fill-
//! reducing column ordering (COLAMD) is computed once per pattern
//! ([`SparseLu::new`]) and every numeric factorisation reuses it and its
//! buffers (no allocation once the first factorisation has sized them).
//! faer's simplicial left-looking LU with partial pivoting is used directly
//! (rather than its high-level `Lu`) because the continuation needs the sign
//! of the determinant, which takes U's diagonal and the permutations' parity.
//! Patterns whose factors are wide (a charged rod's plectoneme: ~250
//! entries per column) are factorised for solves by faer's supernodal LU
//! ([`super::supernodal`], ~3.5× faster there); their determinant comes
//! from a simplicial factorisation of the same matrix, on request
//! ([`LuKind`], [`SparseLu::factorise_exact`]).
//! Everything runs with `Par::Seq`: rodkit starts no threads unless asked.

use super::supernodal::Supernodal;
use crate::error::{Error, Result};
use crate::status::Status;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::lu::{self, simplicial::SimplicialLu, LuSymbolicParams};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};
use std::sync::Arc;

/// Items grouped by their key in 0..keys, each group in the items' order
/// (a counting sort): where each key's group starts (keys + 1 offsets),
/// and the items.
pub(crate) fn group_by_key<T: Copy + Default>(
    keys: usize,
    items: impl Iterator<Item = (usize, T)> + Clone,
) -> (Vec<usize>, Vec<T>) {
    let mut start = vec![0usize; keys + 1];
    for (k, _) in items.clone() {
        start[k + 1] += 1;
    }
    for k in 0..keys {
        start[k + 1] += start[k];
    }
    let mut next = start.clone();
    let mut grouped = vec![T::default(); start[keys]];
    for (k, t) in items {
        grouped[next[k]] = t;
        next[k] += 1;
    }
    (start, grouped)
}

/// One column of a pattern being written: its rows pushed in increasing
/// order (a repeat merged with the one before), column j's diagonal placed
/// among them when asked (a zero there is still a pivot slot).
pub(crate) struct ColumnWriter {
    begin: usize,
    j: usize,
    diagonal_due: bool,
}

impl ColumnWriter {
    pub(crate) fn new(row_idx: &[usize], j: usize, diagonal: bool) -> Self {
        ColumnWriter { begin: row_idx.len(), j, diagonal_due: diagonal }
    }

    /// Row i (≥ the last pushed) into `row_idx`: its position there.
    #[inline]
    pub(crate) fn push(&mut self, row_idx: &mut Vec<usize>, i: usize) -> usize {
        self.diagonal_before(row_idx, i);
        if row_idx.len() == self.begin || row_idx[row_idx.len() - 1] != i {
            row_idx.push(i);
        }
        row_idx.len() - 1
    }

    /// [`ColumnWriter::push`] of a row known above the last pushed (no
    /// repeat to look for: a column's rows from one block).
    #[inline]
    pub(crate) fn push_new(&mut self, row_idx: &mut Vec<usize>, i: usize) -> usize {
        self.diagonal_before(row_idx, i);
        row_idx.push(i);
        row_idx.len() - 1
    }

    #[inline]
    fn diagonal_before(&mut self, row_idx: &mut Vec<usize>, i: usize) {
        if self.diagonal_due && i >= self.j {
            if i > self.j {
                row_idx.push(self.j);
            }
            self.diagonal_due = false;
        }
    }

    /// The diagonal, if every row was above it.
    pub(crate) fn finish(self, row_idx: &mut Vec<usize>) {
        if self.diagonal_due {
            row_idx.push(self.j);
        }
    }
}

/// A square sparsity pattern in compressed columns (row indices sorted).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pattern {
    pub n: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
}

impl Pattern {
    /// From (row, col) pairs (duplicates merged).
    pub fn from_entries(n: usize, entries: impl IntoIterator<Item = (usize, usize)>) -> Self {
        let entries: Vec<(usize, usize)> = entries.into_iter().collect();
        Self::with_positions(n, &entries).0
    }

    /// [`Pattern::from_entries`], also returning each entry's position in
    /// the value array (repeated entries share one): an assembly's scatter
    /// map without a search per entry. One counting sort by column; a
    /// column whose rows do not arrive in order is sorted (an assembly's
    /// blocks mostly give them in order: a rod's set-up sorts only its
    /// boundary columns), then deduplicated; 32-bit work arrays (a rod's
    /// element blocks give ~5000 entries each, and what a first call
    /// allocates it also faults in).
    pub fn with_positions(n: usize, entries: &[(usize, usize)]) -> (Self, Vec<u32>) {
        Self::build(n, entries, false)
    }

    /// [`Pattern::with_positions`] with every diagonal entry in the
    /// pattern too (a zero there is still a pivot slot), placed as each
    /// column is compacted rather than sorted in.
    pub fn with_positions_and_diagonal(n: usize, entries: &[(usize, usize)]) -> (Self, Vec<u32>) {
        Self::build(n, entries, true)
    }

    fn build(n: usize, entries: &[(usize, usize)], diagonal: bool) -> (Self, Vec<u32>) {
        assert!(entries.len() < u32::MAX as usize && n < u32::MAX as usize, "pattern too large for 32-bit positions");
        let mut col_ptr = vec![0u32; n + 1];
        for &(i, j) in entries {
            assert!(i < n && j < n, "entry ({i}, {j}) outside a {n}×{n} pattern");
            col_ptr[j + 1] += 1;
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        let mut next = col_ptr.clone();
        // (row, entry index) by column, in the entries' order.
        let mut by_column = vec![(0u32, 0u32); entries.len()];
        for (e, &(i, j)) in entries.iter().enumerate() {
            by_column[next[j] as usize] = (i as u32, e as u32);
            next[j] += 1;
        }
        let mut row_idx = Vec::with_capacity(entries.len() + if diagonal { n } else { 0 });
        let mut compact = Vec::with_capacity(n + 1);
        let mut positions = vec![0u32; entries.len()];
        compact.push(0);
        for j in 0..n {
            let c = &mut by_column[col_ptr[j] as usize..col_ptr[j + 1] as usize];
            if c.windows(2).any(|w| w[0].0 > w[1].0) {
                c.sort_unstable();
            }
            let mut column = ColumnWriter::new(&row_idx, j, diagonal);
            for &(i, e) in c.iter() {
                positions[e as usize] = column.push(&mut row_idx, i as usize) as u32;
            }
            column.finish(&mut row_idx);
            compact.push(row_idx.len());
        }
        (Pattern { n, col_ptr: compact, row_idx }, positions)
    }

    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Position of entry (i, j) in the value array.
    pub fn position(&self, i: usize, j: usize) -> Option<usize> {
        let (a, b) = (self.col_ptr[j], self.col_ptr[j + 1]);
        self.row_idx[a..b].binary_search(&i).ok().map(|k| a + k)
    }

    /// y = A x for values in pattern order.
    pub fn mul_vec(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for j in 0..self.n {
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                y[self.row_idx[k]] += values[k] * x[j];
            }
        }
    }

    /// y = Aᵀ x for values in pattern order.
    pub fn mul_vec_transpose(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        for (j, yj) in y.iter_mut().enumerate().take(self.n) {
            *yj = (self.col_ptr[j]..self.col_ptr[j + 1]).map(|k| values[k] * x[self.row_idx[k]]).sum();
        }
    }
}

/// faer's LU state for one index type: the pattern's indices, the
/// permutations, the factors and the scratch.
struct Factors<I: faer::Index> {
    col_ptr: Vec<I>,
    row_idx: Vec<I>,
    perm: Permutations<I>,
    lu: SimplicialLu<I, f64>,
    buffer: MemBuffer,
    many: ManyScratch,
}

impl<I: faer::Index> Factors<I> {
    fn new(pattern: &Pattern) -> Self {
        let n = pattern.n;
        let cast = |v: &[usize]| v.iter().map(|&i| I::truncate(i)).collect::<Vec<I>>();
        let natural: Vec<usize> = (0..n).collect();
        let req = lu::simplicial::factorize_simplicial_numeric_lu_scratch::<I, f64>(n, n)
            .or(lu::simplicial::solve_in_place_scratch::<I, f64>(n, 1, Par::Seq));
        Factors {
            col_ptr: cast(&pattern.col_ptr),
            row_idx: cast(&pattern.row_idx),
            perm: Permutations::with_columns(&natural),
            lu: SimplicialLu::new(),
            buffer: MemBuffer::new(req),
            many: ManyScratch::default(),
        }
    }

    fn n(&self) -> usize {
        self.col_ptr.len() - 1
    }

    fn numeric(&mut self, values: &[f64]) -> Result<()> {
        let n = self.n();
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let a = SparseColMatRef::new(sym, values);
        let (row_perm_fwd, row_perm_inv, col_perm) = self.perm.pivoting();
        let stack = MemStack::new(&mut self.buffer);
        lu::simplicial::factorize_simplicial_numeric_lu(row_perm_fwd, row_perm_inv, &mut self.lu, a, col_perm, stack)
            .map_err(|e| Error::new(Status::ErrNotConverged, format!("sparse LU: singular matrix ({e:?})")))
    }

    fn fill(&self) -> usize {
        self.lu.l_factor_unsorted().compute_nnz() + self.lu.u_factor_unsorted().compute_nnz()
    }

    fn col_perm(&self) -> Vec<usize> {
        self.perm.column_order()
    }

    fn set_col_perm(&mut self, fwd: &[usize]) {
        self.perm.set_columns(fwd);
    }

    /// COLAMD's column ordering of the pattern (None if the analysis fails).
    fn colamd(&self) -> Option<Vec<usize>> {
        let n = self.n();
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let params = LuSymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..Default::default()
        };
        let symbolic = lu::factorize_symbolic_lu(sym, params).ok()?;
        Some(symbolic.col_perm().arrays().0.iter().map(|i| i.zx()).collect())
    }

    fn diagonal(&self, j: usize) -> f64 {
        let u = self.lu.u_factor_unsorted();
        let rows = u.row_idx_of_col_raw(j);
        let vals = u.val_of_col(j);
        rows.iter().zip(vals).find(|(i, _)| i.zx() == j).map_or(0.0, |(_, &v)| v)
    }

    fn solve_with(&mut self, b: &mut [f64], transpose: bool) {
        self.perm.solve(&self.lu, b, 1, transpose, MemStack::new(&mut self.buffer));
    }

    /// Solve A X = B in place for the k columns of `b` (column-major, n×k).
    fn solve_many(&mut self, b: &mut [f64], k: usize) {
        let stack = self.many.stack::<I, SimplicialLu<I, f64>>(self.perm.len(), k);
        self.perm.solve(&self.lu, b, k, false, stack);
    }

    /// Parity of the row and column permutations together.
    fn permutation_parity(&self) -> f64 {
        self.perm.parity()
    }
}

/// The row and column permutations of faer's sparse LU, P A Q = L U (the
/// rows' from partial pivoting, the columns' the chosen order), forward
/// and inverse on the factors' index type, and the solves that take them:
/// the simplicial factors ([`Factors`]) and the supernodal ones
/// ([`Supernodal`]) keep and use them alike.
pub(super) struct Permutations<I: faer::Index> {
    row_fwd: Vec<I>,
    row_inv: Vec<I>,
    col_fwd: Vec<I>,
    col_inv: Vec<I>,
}

impl<I: faer::Index> Permutations<I> {
    /// Columns taken in the order `order` (`order[k]` the column taken
    /// k-th); the rows are set by each numeric factorisation.
    pub(super) fn with_columns(order: &[usize]) -> Self {
        let n = order.len();
        let mut p = Permutations {
            row_fwd: vec![I::truncate(0); n],
            row_inv: vec![I::truncate(0); n],
            col_fwd: vec![],
            col_inv: vec![],
        };
        p.set_columns(order);
        p
    }

    pub(super) fn set_columns(&mut self, order: &[usize]) {
        self.col_fwd = order.iter().map(|&i| I::truncate(i)).collect();
        let mut inv = vec![I::truncate(0); order.len()];
        for (k, &j) in order.iter().enumerate() {
            inv[j] = I::truncate(k);
        }
        self.col_inv = inv;
    }

    pub(super) fn column_order(&self) -> Vec<usize> {
        self.col_fwd.iter().map(|i| i.zx()).collect()
    }

    pub(super) fn len(&self) -> usize {
        self.col_fwd.len()
    }

    pub(super) fn rows(&self) -> PermRef<'_, I> {
        PermRef::new_checked(&self.row_fwd, &self.row_inv, self.len())
    }

    pub(super) fn columns(&self) -> PermRef<'_, I> {
        PermRef::new_checked(&self.col_fwd, &self.col_inv, self.len())
    }

    /// The column permutation, beside the row arrays a numeric
    /// factorisation fills by partial pivoting (forward, inverse).
    pub(super) fn pivoting(&mut self) -> (&mut [I], &mut [I], PermRef<'_, I>) {
        let n = self.len();
        (&mut self.row_fwd, &mut self.row_inv, PermRef::new_checked(&self.col_fwd, &self.col_inv, n))
    }

    /// Parity of the row and column permutations together.
    fn parity(&self) -> f64 {
        parity(&self.row_fwd) * parity(&self.col_fwd)
    }

    /// Solve A X = B (Aᵀ X = B when `transpose`) in place for the k
    /// columns of `b` (column-major, n×k) with the factors `lu` of A taken
    /// under these permutations.
    pub(super) fn solve<L: PermutedLu<I>>(
        &self,
        lu: &L,
        b: &mut [f64],
        k: usize,
        transpose: bool,
        stack: &mut MemStack,
    ) {
        let rhs = MatMut::from_column_major_slice_mut(b, self.len(), k);
        if transpose {
            lu.solve_transpose_in_place(self, rhs, stack);
        } else {
            lu.solve_in_place(self, rhs, stack);
        }
    }
}

/// faer's simplicial and supernodal LU factors: their solves are the same
/// calls, which faer gathers in no trait.
pub(super) trait PermutedLu<I: faer::Index> {
    /// The scratch of a solve with k right-hand sides of length n.
    fn solve_scratch(n: usize, k: usize) -> StackReq;
    fn solve_in_place(&self, perm: &Permutations<I>, rhs: MatMut<'_, f64>, stack: &mut MemStack);
    fn solve_transpose_in_place(&self, perm: &Permutations<I>, rhs: MatMut<'_, f64>, stack: &mut MemStack);
}

impl<I: faer::Index> PermutedLu<I> for SimplicialLu<I, f64> {
    fn solve_scratch(n: usize, k: usize) -> StackReq {
        lu::simplicial::solve_in_place_scratch::<I, f64>(n, k, Par::Seq)
    }
    fn solve_in_place(&self, perm: &Permutations<I>, rhs: MatMut<'_, f64>, stack: &mut MemStack) {
        self.solve_in_place_with_conj(perm.rows(), perm.columns(), Conj::No, rhs, Par::Seq, stack);
    }
    fn solve_transpose_in_place(&self, perm: &Permutations<I>, rhs: MatMut<'_, f64>, stack: &mut MemStack) {
        self.solve_transpose_in_place_with_conj(perm.rows(), perm.columns(), Conj::No, rhs, Par::Seq, stack);
    }
}

/// Scratch of multi-column solves and the column count it is sized for
/// (grown on demand, kept: the factors' own buffer is sized for one
/// column).
pub(super) struct ManyScratch {
    columns: usize,
    buffer: MemBuffer,
}

impl Default for ManyScratch {
    fn default() -> Self {
        ManyScratch { columns: 0, buffer: MemBuffer::new(StackReq::EMPTY) }
    }
}

impl ManyScratch {
    /// The scratch of a solve with `L`'s factors of k right-hand sides of
    /// length n.
    pub(super) fn stack<I: faer::Index, L: PermutedLu<I>>(&mut self, n: usize, k: usize) -> &mut MemStack {
        if self.columns < k {
            self.buffer = MemBuffer::new(L::solve_scratch(n, k));
            self.columns = k;
        }
        MemStack::new(&mut self.buffer)
    }
}

/// The factors on 32-bit indices when L + U provably fit them, else on
/// usize ones; Pending until the first factorisation sizes them (their
/// index copies, scratch and the fill bound that picks the width are a
/// sizeable part of a small rod's set-up, and a bordered LU whose
/// condensation always succeeds never needs them).
enum Indexed {
    Pending,
    Narrow(Factors<u32>),
    Wide(Factors<usize>),
}

/// Run `$body` with `$f` bound to the factors whatever their index type
/// (built: every caller runs after [`SparseLu::build_factors`]).
macro_rules! with_factors {
    ($self:expr, $f:ident => $body:expr) => {
        match $self {
            Indexed::Narrow($f) => $body,
            Indexed::Wide($f) => $body,
            Indexed::Pending => unreachable!("the factors are built before they are used"),
        }
    };
}

/// LU factorisation of matrices sharing one [`Pattern`].
///
/// The factors are kept on u32 indices (faer's LU is generic over the
/// index type) when [`fill_bound`] proves that L + U fit them: the row
/// indices of L + U are as many as their values, so halving them cut the
/// factorisations and solves of long rods by ~20 % (they stream from
/// memory once they outgrow the cache). faer narrows its positions to the
/// index type without a check, so past 2³² entries u32 factors would be
/// corrupt: patterns whose bound exceeds that (a dense border on a long
/// rod, distant pairs in a plectoneme's pattern) get usize indices.
pub struct SparseLu {
    /// Shared with the other LUs of one pattern ([`SparseLu::shared`]).
    pattern: Arc<Pattern>,
    factors: Indexed,
    factorised: bool,
    /// Whether the column ordering has been chosen (on the first matrix).
    ordered: bool,
    /// The last unknowns whose rows and columns reach across the matrix
    /// (borders, multipliers): ordered last by a reordering.
    trailing: usize,
    /// The order to take on the first matrix without trying the others
    /// (None: choose by fill), and the one taken.
    preferred: Option<ColumnOrder>,
    chosen: ColumnOrder,
    /// The factorisation kind to take without the structural choice
    /// (None: [`SparseLu::choose_kind`]), whether the choice is made, and
    /// the supernodal factors when it took them.
    preferred_kind: Option<LuKind>,
    by_structure: bool,
    kind_chosen: bool,
    supernodal: Option<Supernodal<usize>>,
    /// Whether the supernodal factors hold the last matrix (solves use
    /// them), else the simplicial ones do.
    fast: bool,
    /// Whether the simplicial factors hold the last matrix (the source of
    /// the determinant and the pivots), its values (their input when a
    /// determinant is asked of supernodal factors) and the simplicial
    /// factors' fill when last computed.
    exact: bool,
    values: Vec<f64>,
    simplicial_fill: usize,
    /// ‖A‖∞ and ‖A‖₁ of the last supernodal matrix, and the scratch of
    /// its solves' refinement (the right-hand side, the residual).
    norms: (f64, f64),
    refine: (Vec<f64>, Vec<f64>),
    /// Numeric factorisations done (the cost unit of a continuation).
    pub factorisations: usize,
    /// Solves done (each with one right-hand side).
    pub solves: usize,
}

/// A column order of the LU, by kind (the permutation itself is the
/// pattern's): what a sequence of patterns of one problem — a charged rod's
/// pair lists — can carry from one to the next instead of trying the
/// orders on each (the trials cost 5–10 factorisations of a plectoneme).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColumnOrder {
    Natural,
    /// Reverse Cuthill–McKee ([`super::ordering`]).
    Rcm,
    Colamd,
}

/// How a matrix is factorised: faer's simplicial LU (column by column;
/// the determinant and pivots are read off U's diagonal), its supernodal
/// LU (dense blocks; solves only — a determinant asked of it comes from a
/// simplicial factorisation of the same matrix), or — a continuation's
/// bordered tangent of a problem with unknowns private to its kernels (a
/// rod's stage unknowns, [`crate::continuation::Problem::private_blocks`])
/// — static condensation of those ([`super::condensed`]) under a block
/// elimination of the border. A [`SparseLu`] asked for `Condensed` is
/// simplicial.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LuKind {
    Simplicial,
    Supernodal,
    Condensed,
}

/// The supernodal LU is taken when the Cholesky factor of AᵀA in the
/// chosen column order has at least this many entries per column (half
/// of George and Ng's bound on L + U per column): measured on this
/// machine, a rod's band (Gauss(2–4), ~20–60 per column) is
/// factorised faster simplicially, a charged rod's plectoneme (RCM order,
/// ~200–400 per column) ~4× faster by supernodes.
pub const SUPERNODAL_COUNTS_PER_COLUMN: usize = 100;

/// The largest L + U that the u32 factors may hold.
const NARROW_LIMIT: u128 = u32::MAX as u128;

impl SparseLu {
    /// For matrices with `pattern`. The column ordering is chosen on the
    /// first matrix (natural, or COLAMD's computed then only if the
    /// natural order fills too much: for the banded matrices of collocated
    /// ODEs it is never needed, and computing it cost ~40 % of one numeric
    /// factorisation).
    pub fn new(pattern: Pattern) -> Result<Self> {
        Self::with_trailing(pattern, 0)
    }

    /// As [`SparseLu::new`], the last `trailing` unknowns being borders or
    /// multipliers whose rows and columns reach across the matrix (kept
    /// last by any reordering).
    pub fn with_trailing(pattern: Pattern, trailing: usize) -> Result<Self> {
        Self::shared(Arc::new(pattern), trailing)
    }

    /// As [`SparseLu::with_trailing`] on a pattern shared with others (a
    /// bordered tangent's, kept for the rods a sweep rebuilds).
    pub fn shared(pattern: Arc<Pattern>, trailing: usize) -> Result<Self> {
        Ok(SparseLu {
            pattern,
            factors: Indexed::Pending,
            factorised: false,
            ordered: false,
            trailing,
            preferred: None,
            chosen: ColumnOrder::Natural,
            preferred_kind: None,
            by_structure: false,
            kind_chosen: false,
            supernodal: None,
            fast: false,
            exact: false,
            values: Vec::new(),
            simplicial_fill: 0,
            norms: (0.0, 0.0),
            refine: (Vec::new(), Vec::new()),
            factorisations: 0,
            solves: 0,
        })
    }

    /// As [`SparseLu::new`] with the index width given (tests compare the
    /// two).
    #[cfg(test)]
    fn indexed(pattern: Pattern, wide: bool) -> Result<Self> {
        let mut lu = Self::new(pattern)?;
        lu.factors =
            if wide { Indexed::Wide(Factors::new(&lu.pattern)) } else { Indexed::Narrow(Factors::new(&lu.pattern)) };
        Ok(lu)
    }

    /// Build the factors' storage on first use, u32 when [`fill_bound`]
    /// proves L + U fit them.
    fn build_factors(&mut self) {
        if matches!(self.factors, Indexed::Pending) {
            self.factors = match self.wide_indices() {
                false => Indexed::Narrow(Factors::new(&self.pattern)),
                true => Indexed::Wide(Factors::new(&self.pattern)),
            };
        }
    }

    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// The pattern, shared.
    pub fn shared_pattern(&self) -> &Arc<Pattern> {
        &self.pattern
    }

    /// Take `order` on the first matrix instead of choosing by fill (a
    /// preference given after the first factorisation changes nothing).
    /// A natural preference still tries the others when it fills more
    /// than 8×, as the choice would.
    pub fn prefer(&mut self, order: ColumnOrder) {
        self.preferred = Some(order);
    }

    /// The column order taken (Natural before the first factorisation).
    pub fn column_order(&self) -> ColumnOrder {
        self.chosen
    }

    /// Factorise every matrix the way `kind` says instead of choosing by
    /// structure (given after the first factorisation it changes nothing).
    pub fn prefer_kind(&mut self, kind: LuKind) {
        self.preferred_kind = Some(kind);
    }

    /// Choose the kind by structure ([`SparseLu::choose_kind`]) instead
    /// of simplicial always (the default). Taken by the continuation's
    /// block elimination, whose solves are refined against the bordered
    /// matrix and whose paths are tested against the simplicial ones
    /// (tests/supercoil_lu.rs); the other users (direct equilibrium
    /// solves, preconditioners) keep the simplicial LU they were measured
    /// and tested with.
    pub fn allow_supernodal(&mut self) {
        self.by_structure = true;
    }

    /// The factorisation kind of the last matrix (Simplicial before the
    /// first).
    pub fn kind(&self) -> LuKind {
        if self.fast {
            LuKind::Supernodal
        } else {
            LuKind::Simplicial
        }
    }

    /// Whether the last factorisation succeeded (solves need one).
    pub fn factorised(&self) -> bool {
        self.factorised
    }

    /// Whether the factors are on usize indices (their L + U could exceed
    /// the u32 range), not u32.
    pub fn wide_indices(&self) -> bool {
        match self.factors {
            Indexed::Pending => fill_bound(&self.pattern, None) >= NARROW_LIMIT,
            Indexed::Narrow(_) => false,
            Indexed::Wide(_) => true,
        }
    }

    /// Entries of L + U of the last simplicial factorisation (0 before
    /// the first): of the last matrix unless the factors are supernodal
    /// (whose dense blocks hold explicit zeros besides; 0 when no
    /// simplicial factorisation of the pattern was done, as with a
    /// preferred column order).
    pub fn fill(&self) -> usize {
        if self.factorised {
            self.simplicial_fill
        } else {
            0
        }
    }

    /// Whether the columns are factorised in their natural order (chosen
    /// on the first matrix), not RCM's or COLAMD's.
    pub fn natural_order(&self) -> bool {
        self.chosen == ColumnOrder::Natural
    }

    /// Numeric factorisation of the matrix with `values` in pattern order,
    /// of the kind chosen for the pattern ([`LuKind`]): the factorisation
    /// of solves (Newton corrections).
    /// A (numerically) singular matrix is ErrNotConverged: a continuation
    /// treats it as a failed step, not a number.
    pub fn factorise(&mut self, values: &[f64]) -> Result<()> {
        self.factorise_as(values, false)
    }

    /// As [`SparseLu::factorise`], always simplicial: the factorisation of
    /// a point whose determinant sign and pivots are read (a
    /// continuation's record), which supernodal factors would have to
    /// repeat. Solves use it until the next factorisation.
    pub fn factorise_exact(&mut self, values: &[f64]) -> Result<()> {
        self.factorise_as(values, true)
    }

    fn factorise_as(&mut self, values: &[f64], exact: bool) -> Result<()> {
        assert_eq!(values.len(), self.pattern.nnz(), "values do not match the pattern");
        self.factorised = false;
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(Error::new(Status::ErrNonFiniteResult, format!("sparse LU: matrix entry {k} is not finite")));
        }
        self.build_factors();
        let in_place = !self.ordered && self.choose_ordering(values);
        if !self.kind_chosen {
            self.choose_kind();
        }
        self.exact = in_place;
        self.fast = false;
        if let Some(sn) = self.supernodal.as_mut().filter(|_| !exact) {
            // Supernodal factors even when the ordering's trial left
            // simplicial ones of this matrix in place: every matrix of a
            // pattern is factorised one way (a resumed run repeats the
            // uninterrupted one bitwise).
            sn.numeric(values, &self.pattern)?;
            if in_place {
                self.simplicial_fill = with_factors!(&self.factors, f => f.fill());
            }
            self.values.clear();
            self.values.extend_from_slice(values);
            self.norms = norms(&self.pattern, values, &mut self.refine.1);
            self.factorisations += 1;
            self.fast = true;
            self.factorised = true;
            return Ok(());
        }
        if !in_place {
            with_factors!(&mut self.factors, f => f.numeric(values))?;
            self.exact = true;
        }
        self.simplicial_fill = with_factors!(&self.factors, f => f.fill());
        self.factorisations += 1;
        self.check_pivots()?;
        self.factorised = true;
        Ok(())
    }

    /// A zero or non-finite pivot of the simplicial factors is a singular
    /// matrix.
    fn check_pivots(&self) -> Result<()> {
        for j in 0..self.pattern.n {
            let d = with_factors!(&self.factors, f => f.diagonal(j));
            if !(d.is_finite() && d != 0.0) {
                return Err(Error::new(
                    Status::ErrNotConverged,
                    format!("sparse LU: pivot {j} is {d:e} (singular matrix)"),
                ));
            }
        }
        Ok(())
    }

    /// Supernodal or simplicial, by structure (deterministic: one pattern
    /// and order, one kind): supernodal when the Cholesky factor of AᵀA in
    /// the chosen order has at least [`SUPERNODAL_COUNTS_PER_COLUMN`]
    /// entries per column (George–Ng's bound, [`george_ng_bound`], at
    /// least twice that per column). Measured: a plain rod's band 39–52
    /// (Gauss(2–4), 2–16 k unknowns), a 1 kbp charged rod 155 (straight)
    /// to 265 (plectoneme).
    fn choose_kind(&mut self) {
        self.kind_chosen = true;
        let n = self.pattern.n;
        let perm = with_factors!(&self.factors, f => f.col_perm());
        let forced = match self.preferred_kind {
            Some(LuKind::Simplicial | LuKind::Condensed) => return,
            Some(LuKind::Supernodal) => true,
            None if !self.by_structure => return,
            None => false,
        };
        // A dense row makes the AᵀA factor dense (the bound ~n²): its
        // supernodes would be one dense LU of the whole matrix.
        let (low, high) = (2 * SUPERNODAL_COUNTS_PER_COLUMN * n, (n as u128) * (n as u128) / 2);
        if forced || george_ng_bound(&self.pattern, Some(&perm)).is_some_and(|b| b >= low as u128 && b < high) {
            self.supernodal = Supernodal::new(&self.pattern, &perm);
        }
    }

    /// Make the simplicial factors hold the last matrix (a determinant or
    /// the pivots asked of supernodal factors).
    fn ensure_exact(&mut self) -> Result<()> {
        if !self.exact {
            let values = std::mem::take(&mut self.values);
            let result = with_factors!(&mut self.factors, f => f.numeric(&values));
            self.values = values;
            result?;
            self.simplicial_fill = with_factors!(&self.factors, f => f.fill());
            self.check_pivots()?;
            self.exact = true;
        }
        Ok(())
    }

    /// On the first matrix: factorise with the natural order; keep it when
    /// its fill (entries of L + U) is at most 8× the matrix's, else try
    /// reverse Cuthill–McKee's ([`super::ordering`]; kept when it is within
    /// 8×) and then COLAMD's, and keep the one with least fill. For the
    /// block-banded matrices of collocated ODEs with stage unknowns the
    /// natural (banded) order has ~2.5–5× the matrix's entries while COLAMD
    /// can have 8× more again (rod, Gauss(4) × 32: 98 k against 771 k) —
    /// and a trial factorisation that dense costs more than the whole
    /// continuation; COLAMD wins on general patterns. A charged rod's
    /// plectoneme couples its two strands ~n apart: natural 13.4×, RCM
    /// 8.5×, COLAMD 11× at 7.5 turns of the 1 kbp DNA scene (RCM's stays
    /// ~8.5× as the plectoneme grows, the natural order's grows to 21.7× at
    /// 12 turns). On u32 factors, an order is tried only if its fill bound
    /// fits them too.
    /// Returns whether the factorisation of `values` with the chosen
    /// ordering is already in place.
    fn choose_ordering(&mut self, values: &[f64]) -> bool {
        self.ordered = true;
        let preferred = match self.preferred {
            Some(ColumnOrder::Rcm) => {
                Some((ColumnOrder::Rcm, super::ordering::reverse_cuthill_mckee(&self.pattern, self.trailing)))
            }
            Some(ColumnOrder::Colamd) => {
                with_factors!(&self.factors, f => f.colamd()).map(|p| (ColumnOrder::Colamd, p))
            }
            _ => None,
        };
        if let Some((kind, perm)) = preferred {
            if self.wide_indices() || fill_bound(&self.pattern, Some(&perm)) < NARROW_LIMIT {
                with_factors!(&mut self.factors, f => f.set_col_perm(&perm));
                self.chosen = kind;
                return false;
            }
        }
        self.choose_by_fill(values)
    }

    /// [`SparseLu::choose_ordering`] by trial factorisations.
    fn choose_by_fill(&mut self, values: &[f64]) -> bool {
        let n = self.pattern.n;
        let identity: Vec<usize> = (0..n).collect();
        with_factors!(&mut self.factors, f => f.set_col_perm(&identity));
        let natural = with_factors!(&mut self.factors, f => f.numeric(values).ok().map(|_| f.fill()));
        let limit = 8 * self.pattern.nnz();
        self.chosen = ColumnOrder::Natural;
        if natural.is_some_and(|fill| fill <= limit) {
            return true;
        }
        let mut best = (natural, identity, ColumnOrder::Natural);
        // Reverse Cuthill–McKee first (a band again, whatever the shape),
        // COLAMD only if that still fills too much.
        let rcm = super::ordering::reverse_cuthill_mckee(&self.pattern, self.trailing);
        if let Some(fill) = self.try_order(values, &rcm, best.0) {
            best = (Some(fill), rcm, ColumnOrder::Rcm);
            if fill <= limit {
                self.chosen = ColumnOrder::Rcm;
                return true;
            }
        }
        if let Some(colamd) = with_factors!(&self.factors, f => f.colamd()) {
            if self.try_order(values, &colamd, best.0).is_some() {
                self.chosen = ColumnOrder::Colamd;
                return true;
            }
        }
        let (fill, order, kind) = best;
        self.chosen = kind;
        self.simplicial_fill = fill.unwrap_or(0);
        with_factors!(&mut self.factors, f => f.set_col_perm(&order));
        false
    }

    /// Factorise `values` in column order `perm` and return the fill when
    /// it is less than `best`'s (None: more, singular, or a fill the u32
    /// factors could not hold). The factors are left in an unspecified
    /// order: the caller sets the one it keeps.
    fn try_order(&mut self, values: &[f64], perm: &[usize], best: Option<usize>) -> Option<usize> {
        if !self.wide_indices() && fill_bound(&self.pattern, Some(perm)) >= NARROW_LIMIT {
            return None;
        }
        with_factors!(&mut self.factors, f => f.set_col_perm(perm));
        let fill = with_factors!(&mut self.factors, f => f.numeric(values).ok().map(|_| f.fill()))?;
        best.is_none_or(|b| fill < b).then_some(fill)
    }

    /// Solve A x = b in place.
    pub fn solve(&mut self, b: &mut [f64]) {
        self.solve_with(b, false)
    }

    /// Solve Aᵀ x = b in place.
    pub fn solve_transpose(&mut self, b: &mut [f64]) {
        self.solve_with(b, true)
    }

    fn solve_with(&mut self, b: &mut [f64], transpose: bool) {
        assert!(self.factorised, "solve before a successful factorisation");
        if self.fast {
            self.refined_solve(b, transpose);
        } else {
            with_factors!(&mut self.factors, f => f.solve_with(b, transpose));
        }
        self.solves += 1;
    }

    /// Solve A X = B in place for the k columns of `b` (column-major, n×k)
    /// with the factors of the last matrix, whichever kind, in one pass
    /// through them (the factors stream from memory once for all k) and
    /// without refinement: for uses that need a backward-stable solve, not
    /// a residual at rounding level (a subspace iteration, whose Ritz
    /// values and residuals are measured afterwards).
    pub fn solve_many_unrefined(&mut self, b: &mut [f64], k: usize) {
        assert!(self.factorised, "solve before a successful factorisation");
        assert_eq!(b.len(), self.pattern.n * k, "right-hand sides do not match the matrix");
        if k == 0 {
            return;
        }
        match self.supernodal.as_mut().filter(|_| self.fast) {
            Some(sn) => sn.solve_many(b, k),
            None => with_factors!(&mut self.factors, f => f.solve_many(b, k)),
        }
        self.solves += k;
    }

    /// A solve on the supernodal factors, refined against A until the
    /// residual is at rounding level (‖b − Ax‖∞ ≤ 1e-14 (‖A‖‖x‖∞ +
    /// ‖b‖∞)), at most three times (faer's supernodal LU pivots within
    /// each supernode's front: cheap insurance, one solve and one product
    /// each, against a factor less accurate than the simplicial one).
    fn refined_solve(&mut self, b: &mut [f64], transpose: bool) {
        let Some(sn) = self.supernodal.as_mut() else { return };
        let (rhs, res) = &mut self.refine;
        rhs.clear();
        rhs.extend_from_slice(b);
        res.resize(b.len(), 0.0);
        sn.solve_with(b, transpose);
        let norm = if transpose { self.norms.1 } else { self.norms.0 };
        // Short of rounding level after three corrections, the solve stands
        // as refined (the callers' own residual tests judge it).
        refine((&self.pattern, &self.values, transpose), (norm, 1e-14, 3), rhs, b, res, |d| {
            sn.solve_with(d, transpose)
        });
    }

    /// Sign of det A (±1) and log|det A| of the last factorisation (with
    /// supernodal factors, from a simplicial factorisation of the same
    /// matrix, done on the first request: (0, −∞) if that one finds it
    /// singular).
    /// Whether the last successful factorisation left simplicial factors
    /// (its determinant sign and pivots then cost nothing more).
    pub fn exact_in_hand(&self) -> bool {
        self.factorised && self.exact
    }

    pub fn determinant_sign_and_log(&mut self) -> (f64, f64) {
        assert!(self.factorised, "determinant before a successful factorisation");
        if self.ensure_exact().is_err() {
            return (0.0, f64::NEG_INFINITY);
        }
        let (mut sign, mut log) = (with_factors!(&self.factors, f => f.permutation_parity()), 0.0);
        for j in 0..self.pattern.n {
            let d = with_factors!(&self.factors, f => f.diagonal(j));
            sign *= d.signum();
            log += d.abs().ln();
        }
        (sign, log)
    }

    /// Negative diagonal entries of U (the pivots). With row pivoting the
    /// count itself depends on the pivot order; its parity times the
    /// permutations' parity is sign det.
    pub fn negative_pivots(&mut self) -> usize {
        assert!(self.factorised, "pivots before a successful factorisation");
        if self.ensure_exact().is_err() {
            return 0;
        }
        (0..self.pattern.n).filter(|&j| with_factors!(&self.factors, f => f.diagonal(j)) < 0.0).count()
    }
}

/// An upper bound on the entries of L + U of the LU with row partial
/// pivoting of any matrix with `pattern`, its columns taken in the order
/// `perm` (None: natural): the smaller of [`profile_bound`] and
/// [`george_ng_bound`] (both rigorous; the profile's is the tighter on a
/// plain band, George–Ng's where a few rows or columns reach far — the
/// corner blocks of a clamped–clamped rod's band, whose running profile
/// spans the whole matrix).
fn fill_bound(pattern: &Pattern, perm: Option<&[usize]>) -> u128 {
    let profile = profile_bound(pattern, perm);
    if profile < NARROW_LIMIT {
        return profile;
    }
    george_ng_bound(pattern, perm).map_or(profile, |g| g.min(profile))
}

/// George and Ng's bound (SIAM J. Sci. Stat. Comput. 8, 1987): whatever
/// rows partial pivoting picks, the structures of L and Uᵀ lie within that
/// of the Cholesky factor of AᵀA, so L + U has at most twice its entries,
/// counted by faer's column counts of AᵀA (column elimination tree,
/// postorder; AᵀA is never formed). None if the analysis is refused.
fn george_ng_bound(pattern: &Pattern, perm: Option<&[usize]>) -> Option<u128> {
    use faer::sparse::linalg::qr;
    let n = pattern.n;
    if n == 0 {
        return Some(0);
    }
    // Aᵀ in compressed columns (A's rows).
    let (t_ptr, t_idx, _) = super::supernodal::transpose(pattern);
    let (fwd, inv) = match perm {
        Some(p) => {
            let mut inv = vec![0usize; n];
            for (k, &j) in p.iter().enumerate() {
                inv[j] = k;
            }
            (p.to_vec(), inv)
        }
        None => ((0..n).collect(), (0..n).collect()),
    };
    let col_perm = PermRef::new_checked(&fwd, &inv, n);
    let a = SymbolicSparseColMatRef::new_checked(n, n, &pattern.col_ptr, None, &pattern.row_idx);
    let at = SymbolicSparseColMatRef::new_checked(n, n, &t_ptr, None, &t_idx);
    let req = StackReq::any_of(&[
        qr::col_etree_scratch::<usize>(n, n),
        qr::postorder_scratch::<usize>(n),
        qr::column_counts_aat_scratch::<usize>(n, n),
    ]);
    let mut buffer = MemBuffer::try_new(req).ok()?;
    let stack = MemStack::new(&mut buffer);
    let mut etree = vec![0usize; n];
    let tree = qr::col_etree(a, Some(col_perm), &mut etree, stack);
    let mut post = vec![0usize; n];
    qr::postorder(&mut post, tree, stack);
    let (mut counts, mut min_col) = (vec![0usize; n], vec![0usize; n]);
    qr::column_counts_ata(&mut counts, &mut min_col, at, Some(col_perm), tree, &post, stack);
    Some(2 * counts.iter().map(|&c| c as u128).sum::<u128>())
}

/// The profile bound on the entries of L + U (diagonals counted in both)
/// of the LU with row partial pivoting, columns in the order `perm`
/// (None: natural). With m(j) the last
/// row holding an entry in the first j + 1 columns (at least j) and c(r)
/// the last column holding an entry in the first r + 1 rows (at least r):
/// column j of L can only hold rows ≤ m(j) not yet pivoted, m(j) − j + 1
/// of them; the i-th pivot row is an original row ≤ m(i), updated by
/// earlier pivot rows, so row i of U lies in columns i..=c(m(i)). A band
/// of half-width b gives n(3b + 2), the classical bound of banded LU with
/// pivoting. O(nnz).
fn profile_bound(pattern: &Pattern, perm: Option<&[usize]>) -> u128 {
    let n = pattern.n;
    if n == 0 {
        return 0;
    }
    let mut last_row = vec![0usize; n];
    let mut last_col_of_row = vec![0usize; n];
    for (jp, last) in last_row.iter_mut().enumerate() {
        let j = perm.map_or(jp, |p| p[jp]);
        for &i in &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]] {
            *last = (*last).max(i);
            last_col_of_row[i] = last_col_of_row[i].max(jp);
        }
    }
    let (mut m, mut c) = (0usize, 0usize);
    for (k, (r, col)) in last_row.iter_mut().zip(last_col_of_row.iter_mut()).enumerate() {
        m = m.max(*r).max(k);
        *r = m;
        c = c.max(*col).max(k);
        *col = c;
    }
    (0..n).map(|j| (last_row[j] - j + 1) as u128 + (last_col_of_row[last_row[j]] - j + 1) as u128).sum()
}

/// Iterative refinement against A (`values` in `pattern`; Aᵀ when the
/// flag says so): x, solved from A x = f, is corrected by `solve` (in
/// place, on the residual) until ‖f − Ax‖∞ ≤ tol (norm ‖x‖∞ + ‖f‖∞),
/// norm being ‖A‖ in the matching norm, at most `corrections` times;
/// `res` is scratch of x's length. Returns whether it got there (false
/// also for a non-finite residual).
pub(super) fn refine(
    (pattern, values, transpose): (&Pattern, &[f64], bool),
    (norm, tol, corrections): (f64, f64, usize),
    f: &[f64],
    x: &mut [f64],
    res: &mut [f64],
    mut solve: impl FnMut(&mut [f64]),
) -> bool {
    let max_abs = |v: &[f64]| v.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    let f_norm = max_abs(f);
    for step in 0..=corrections {
        if transpose {
            pattern.mul_vec_transpose(values, x, res);
        } else {
            pattern.mul_vec(values, x, res);
        }
        for (r, fi) in res.iter_mut().zip(f) {
            *r = fi - *r;
        }
        let residual = max_abs(res);
        if !residual.is_finite() {
            return false;
        }
        if residual <= tol * (norm * max_abs(x) + f_norm) {
            return true;
        }
        if step == corrections {
            break;
        }
        solve(res);
        for (xi, d) in x.iter_mut().zip(res.iter()) {
            *xi += d;
        }
    }
    false
}

/// (‖A‖∞, ‖A‖₁): the largest row and column sums of |entries| (the row
/// sums accumulated in `rows`, scratch resized to n).
pub(super) fn norms(pattern: &Pattern, values: &[f64], rows: &mut Vec<f64>) -> (f64, f64) {
    rows.clear();
    rows.resize(pattern.n, 0.0);
    let mut col_max = 0.0f64;
    for j in 0..pattern.n {
        let mut col = 0.0;
        for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
            rows[pattern.row_idx[k]] += values[k].abs();
            col += values[k].abs();
        }
        col_max = col_max.max(col);
    }
    (rows.iter().fold(0.0, |m, &r| m.max(r)), col_max)
}

/// +1 for an even permutation, −1 for an odd one (cycle count).
fn parity<I: faer::Index>(p: &[I]) -> f64 {
    let mut seen = vec![false; p.len()];
    let mut sign = 1.0;
    for start in 0..p.len() {
        if seen[start] {
            continue;
        }
        let mut len = 0;
        let mut i = start;
        while !seen[i] {
            seen[i] = true;
            i = p[i].zx();
            len += 1;
        }
        if len % 2 == 0 {
            sign = -sign;
        }
    }
    sign
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// With the diagonal: the pattern is the sorted set of the entries and
    /// the diagonal (reference: a BTreeSet), for entries in any order and
    /// for entries whose columns arrive already ordered (the path that
    /// sorts nothing), each entry's position holding its own row.
    #[test]
    fn pattern_with_diagonal_is_the_set_of_entries_and_diagonal() {
        let n = 29;
        let mut state = 777u64;
        let mut random = vec![];
        for _ in 0..600 {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            random.push((((state >> 33) % n as u64) as usize, ((state >> 13) % n as u64) as usize));
        }
        let mut ordered = random.clone();
        ordered.sort_by_key(|&(i, j)| (j, i));
        for entries in [random, ordered] {
            for diagonal in [false, true] {
                let (p, positions) = if diagonal {
                    Pattern::with_positions_and_diagonal(n, &entries)
                } else {
                    Pattern::with_positions(n, &entries)
                };
                let mut set: std::collections::BTreeSet<(usize, usize)> =
                    entries.iter().map(|&(i, j)| (j, i)).collect();
                if diagonal {
                    set.extend((0..n).map(|i| (i, i)));
                }
                let listed: Vec<(usize, usize)> = (0..n)
                    .flat_map(|j| p.row_idx[p.col_ptr[j]..p.col_ptr[j + 1]].iter().map(move |&i| (j, i)))
                    .collect();
                assert_eq!(listed, set.into_iter().collect::<Vec<_>>(), "diagonal {diagonal}");
                for (&(i, j), &q) in entries.iter().zip(&positions) {
                    assert!(
                        q as usize >= p.col_ptr[j] && (q as usize) < p.col_ptr[j + 1] && p.row_idx[q as usize] == i
                    );
                }
            }
        }
    }

    /// The pattern of repeated, unordered entries is the sorted set of
    /// distinct (row, column) pairs (reference: a BTreeSet, column-major),
    /// and every entry's position holds its own row in its own column.
    #[test]
    fn pattern_positions_point_at_each_entry() {
        let n = 37;
        let mut entries = vec![];
        let mut state = 12345u64;
        for _ in 0..900 {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            entries.push((((state >> 33) % n as u64) as usize, ((state >> 13) % n as u64) as usize));
        }
        entries.extend(entries.clone().into_iter().take(50));
        let (p, positions) = Pattern::with_positions(n, &entries);
        let set: std::collections::BTreeSet<(usize, usize)> = entries.iter().map(|&(i, j)| (j, i)).collect();
        let listed: Vec<(usize, usize)> =
            (0..n).flat_map(|j| p.row_idx[p.col_ptr[j]..p.col_ptr[j + 1]].iter().map(move |&i| (j, i))).collect();
        assert_eq!(listed, set.into_iter().collect::<Vec<_>>());
        for (&(i, j), &q) in entries.iter().zip(&positions) {
            assert!(q as usize >= p.col_ptr[j] && (q as usize) < p.col_ptr[j + 1] && p.row_idx[q as usize] == i);
            assert_eq!(p.position(i, j), Some(q as usize));
        }
        assert_eq!(Pattern::from_entries(n, entries.iter().copied()).row_idx, p.row_idx);
    }

    /// Reference: nalgebra's dense LU on the same random sparse matrices.
    #[test]
    fn solves_and_determinant_match_dense_lu() {
        let n = 40;
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        // Block-bidiagonal plus a dense last row and column (a bordered tangent).
        let mut entries = vec![];
        for i in 0..n {
            for j in 0..n {
                if (i as i64 - j as i64).abs() <= 2 || i == n - 1 || j == n - 1 || (i + j) % 11 == 0 {
                    entries.push((i, j));
                }
            }
        }
        let pattern = Pattern::from_entries(n, entries);
        let mut lu = SparseLu::new(pattern.clone()).unwrap();
        for trial in 0..3 {
            let values: Vec<f64> = (0..pattern.nnz()).map(|_| rnd()).collect();
            let dense = dense_of(&pattern, &values);
            lu.factorise(&values).unwrap();
            let b: Vec<f64> = (0..n).map(|_| rnd()).collect();
            matches_dense(&mut lu, &dense, &b, trial);
        }
        assert_eq!(lu.factorisations, 3);
        // A singular matrix is a status.
        let zeros = vec![0.0; pattern.nnz()];
        assert_eq!(lu.factorise(&zeros).unwrap_err().status, Status::ErrNotConverged);
    }

    /// `lu` (holding `dense`'s values) against nalgebra's dense LU of the
    /// same matrix (the reference): A x = b and Aᵀ x = b to 1e-11, sign
    /// det exact and log |det| to 1e-9. Returns x and the dense det.
    fn matches_dense(lu: &mut SparseLu, dense: &nalgebra::DMatrix<f64>, b: &[f64], trial: usize) -> (Vec<f64>, f64) {
        let mut x = b.to_vec();
        lu.solve(&mut x);
        let y = dense * nalgebra::DVector::from_vec(x.clone());
        let res = y.iter().zip(b).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(res < 1e-11, "trial {trial}: residual {res:e}");
        let mut xt = b.to_vec();
        lu.solve_transpose(&mut xt);
        let yt = dense.transpose() * nalgebra::DVector::from_vec(xt);
        assert!(yt.iter().zip(b).all(|(a, b)| (a - b).abs() < 1e-11), "trial {trial}: transposed solve");
        let det = dense.clone().lu().determinant();
        let (sign, log) = lu.determinant_sign_and_log();
        assert_eq!(sign, det.signum(), "trial {trial}");
        assert!((log - det.abs().ln()).abs() < 1e-9, "trial {trial}: log |det|");
        (x, det)
    }

    /// The supernodal factors against nalgebra's dense LU (the reference)
    /// on a random block band with far entries and a dense border (a
    /// charged rod's bordered Jacobian in miniature): solves and transposed
    /// solves to rounding, the determinant (from the simplicial
    /// factorisation done on request) exact in sign and to 1e-9 in log;
    /// factorise_exact switches the solves to simplicial factors with the
    /// same answer; a singular matrix is a status with either kind; two
    /// LUs of one pattern give bitwise equal solves (no history in the
    /// factors).
    #[test]
    fn supernodal_factors_match_dense_lu() {
        let n = 120;
        let mut seed = 4242u64;
        let far: Vec<(usize, usize)> = (0..200).map(|k| ((k * 37 + 11) % n, (k * 53 + 7) % n)).collect();
        let pattern = Pattern::from_entries(
            n,
            (0..n)
                .flat_map(|i| (i.saturating_sub(6)..(i + 7).min(n)).map(move |j| (i, j)))
                .chain(far.iter().copied())
                .chain((0..n).flat_map(|i| [(n - 1, i), (i, n - 1)])),
        );
        let mut lu = SparseLu::with_trailing(pattern.clone(), 1).unwrap();
        lu.prefer_kind(LuKind::Supernodal);
        let mut twin = SparseLu::with_trailing(pattern.clone(), 1).unwrap();
        twin.prefer_kind(LuKind::Supernodal);
        for trial in 0..3 {
            let values = random_values(&pattern, &mut seed);
            let dense = dense_of(&pattern, &values);
            lu.factorise(&values).unwrap();
            assert_eq!(lu.kind(), LuKind::Supernodal);
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
            let (x, det) = matches_dense(&mut lu, &dense, &b, trial);
            // Solves still on the supernodal factors after the determinant.
            let mut again = b.clone();
            lu.solve(&mut again);
            assert_eq!(again, x);
            twin.factorise(&values).unwrap();
            let mut xw = b.clone();
            twin.solve(&mut xw);
            assert_eq!(xw, x, "trial {trial}: two LUs of one pattern differ");
            lu.factorise_exact(&values).unwrap();
            assert_eq!(lu.kind(), LuKind::Simplicial);
            let mut xe = b.clone();
            lu.solve(&mut xe);
            assert!(xe.iter().zip(&x).all(|(a, b)| (a - b).abs() < 1e-10 * (1.0 + b.abs())));
            assert_eq!(lu.determinant_sign_and_log().0, det.signum());
        }
        let zeros = vec![0.0; pattern.nnz()];
        assert_eq!(lu.factorise(&zeros).unwrap_err().status, Status::ErrNotConverged);
    }

    /// The kind chosen by structure: a narrow band (half-width 3, ~10
    /// AᵀA-factor entries per column) stays simplicial, a wide one
    /// (half-width 120, ~240 per column, a plectoneme's) goes supernodal;
    /// both solve to rounding.
    #[test]
    fn lu_kind_is_chosen_by_structure() {
        let n = 2000;
        let band = |b: usize| {
            Pattern::from_entries(
                n,
                (0..n).flat_map(move |i| (i.saturating_sub(b)..(i + b + 1).min(n)).map(move |j| (i, j))),
            )
        };
        for (b, kind) in [(3, LuKind::Simplicial), (120, LuKind::Supernodal)] {
            let pattern = band(b);
            let values = random_values(&pattern, &mut 31u64);
            let mut lu = SparseLu::new(pattern.clone()).unwrap();
            lu.allow_supernodal();
            lu.factorise(&values).unwrap();
            assert_eq!(lu.kind(), kind, "half-width {b}");
            let mut plain = SparseLu::new(pattern.clone()).unwrap();
            plain.factorise(&values).unwrap();
            assert_eq!(plain.kind(), LuKind::Simplicial, "simplicial unless allowed");
            let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).cos()).collect();
            let mut x = rhs.clone();
            lu.solve(&mut x);
            let mut y = vec![0.0; n];
            pattern.mul_vec(&values, &x, &mut y);
            let res = y.iter().zip(&rhs).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(res < 1e-9, "half-width {b}: residual {res:e}");
        }
    }

    /// The ordering choice: an arrowhead matrix (dense first row and column)
    /// fills completely in its natural order, so COLAMD (which moves the
    /// dense column last) is kept; a banded matrix keeps its natural order.
    /// Both solve to rounding.
    #[test]
    fn ordering_is_chosen_by_fill() {
        let n = 300;
        let arrow = Pattern::from_entries(n, (0..n).flat_map(|i| [(i, i), (0, i), (i, 0)]));
        let band =
            Pattern::from_entries(n, (0..n).flat_map(|i| (i.saturating_sub(3)..(i + 4).min(n)).map(move |j| (i, j))));
        for (pattern, natural) in [(arrow, false), (band, true)] {
            let mut lu = SparseLu::new(pattern.clone()).unwrap();
            // Diagonally dominant values: no pivoting needed.
            let values: Vec<f64> = (0..n)
                .flat_map(|j| (pattern.col_ptr[j]..pattern.col_ptr[j + 1]).map(move |k| (j, k)))
                .map(|(j, k)| if pattern.row_idx[k] == j { 10.0 * n as f64 } else { 1.0 })
                .collect();
            lu.factorise(&values).unwrap();
            assert_eq!(lu.natural_order(), natural);
            // Without fill blow-up: L + U within a few times A's entries
            // (the arrowhead in natural order would have ~n² = 90 000).
            assert!(lu.fill() <= 4 * pattern.nnz(), "fill {} for nnz {}", lu.fill(), pattern.nnz());
            let b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
            let mut x = b.clone();
            lu.solve(&mut x);
            let mut y = vec![0.0; n];
            pattern.mul_vec(&values, &x, &mut y);
            assert!(y.iter().zip(&b).all(|(a, b)| (a - b).abs() < 1e-12));
        }
    }

    /// The matrix with `values` in `pattern`, dense (the reference LU's).
    fn dense_of(pattern: &Pattern, values: &[f64]) -> DMatrix<f64> {
        let mut dense = DMatrix::zeros(pattern.n, pattern.n);
        for j in 0..pattern.n {
            for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                dense[(pattern.row_idx[k], j)] = values[k];
            }
        }
        dense
    }

    fn random_values(pattern: &Pattern, seed: &mut u64) -> Vec<f64> {
        (0..pattern.nnz())
            .map(|_| {
                *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                ((*seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
            })
            .collect()
    }

    /// The fill bound against the fill faer's LU actually produces (the
    /// reference), with pivoting (random values), in the natural and in
    /// COLAMD's orders: a block band with random far entries and a dense
    /// border, an arrowhead, a plain band (bound ≤ n(3b + 2), the banded
    /// LU's). A bound below the true fill would let u32 factors overflow.
    #[test]
    fn fill_bound_bounds_the_fill() {
        let n = 200;
        let mut seed = 99u64;
        let mut far = Vec::new();
        for k in 0..300 {
            let (i, j) = ((k * 37 + 11) % n, (k * 53 + 7) % n);
            far.push((i, j));
        }
        let band = |b: usize| {
            Pattern::from_entries(
                n,
                (0..n).flat_map(move |i| (i.saturating_sub(b)..(i + b + 1).min(n)).map(move |j| (i, j))),
            )
        };
        let mixed = Pattern::from_entries(
            n,
            (0..n)
                .flat_map(|i| (i.saturating_sub(4)..(i + 5).min(n)).map(move |j| (i, j)))
                .chain(far.iter().copied())
                .chain((0..n).flat_map(|i| [(n - 1, i), (i, n - 1)])),
        );
        let arrow = Pattern::from_entries(n, (0..n).flat_map(|i| [(i, i), (0, i), (i, 0)]));
        for (name, pattern) in [("band 5", band(5)), ("mixed", mixed), ("arrow", arrow)] {
            let mut lu = SparseLu::new(pattern.clone()).unwrap();
            let values = random_values(&pattern, &mut seed);
            let mut f = Factors::<usize>::new(&pattern);
            f.numeric(&values).unwrap();
            let natural = f.fill() as u128;
            for bound in [profile_bound(&pattern, None), george_ng_bound(&pattern, None).unwrap()] {
                assert!(natural <= bound, "{name}: natural fill {natural} above the bound {bound}");
            }
            if let Some(perm) = f.colamd() {
                f.set_col_perm(&perm);
                f.numeric(&values).unwrap();
                let fill = f.fill() as u128;
                for bound in [profile_bound(&pattern, Some(&perm)), george_ng_bound(&pattern, Some(&perm)).unwrap()] {
                    assert!(fill <= bound, "{name}: COLAMD fill {fill} above the bound {bound}");
                }
            }
            lu.factorise(&values).unwrap();
            assert!(!lu.wide_indices());
        }
        let b = 5;
        assert!(fill_bound(&band(b), None) <= (n * (3 * b + 2)) as u128);
    }

    /// u32 and usize factors are the same computation: bitwise equal
    /// solves, determinant and fill (the reference is the other width).
    #[test]
    fn narrow_and_wide_indices_agree() {
        let n = 150;
        let pattern = Pattern::from_entries(
            n,
            (0..n)
                .flat_map(|i| (i.saturating_sub(3)..(i + 4).min(n)).map(move |j| (i, j)))
                .chain((0..n).flat_map(|i| [(n - 1, i), (i, n - 1)])),
        );
        let values = random_values(&pattern, &mut 7u64);
        let (mut narrow, mut wide) =
            (SparseLu::indexed(pattern.clone(), false).unwrap(), SparseLu::indexed(pattern.clone(), true).unwrap());
        assert!(!narrow.wide_indices() && wide.wide_indices());
        narrow.factorise(&values).unwrap();
        wide.factorise(&values).unwrap();
        assert_eq!(narrow.fill(), wide.fill());
        assert_eq!(narrow.determinant_sign_and_log(), wide.determinant_sign_and_log());
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).cos()).collect();
        let (mut x1, mut x2) = (b.clone(), b.clone());
        narrow.solve(&mut x1);
        wide.solve(&mut x2);
        assert_eq!(x1, x2);
        narrow.solve_transpose(&mut x1);
        wide.solve_transpose(&mut x2);
        assert_eq!(x1, x2);
    }

    /// The width chosen from the bound: a 70 000-unknown arrowhead could
    /// fill n(n + 1) ≈ 4.9e9 > 2³² entries in its natural order → usize;
    /// a band of the same size stays on u32.
    #[test]
    fn wide_indices_when_the_fill_could_pass_u32() {
        let n = 70_000;
        let arrow = Pattern::from_entries(n, (0..n).flat_map(|i| [(i, i), (0, i), (i, 0)]));
        assert_eq!(fill_bound(&arrow, None), (n as u128) * (n as u128 + 1));
        assert!(SparseLu::new(arrow).unwrap().wide_indices());
        let band =
            Pattern::from_entries(n, (0..n).flat_map(|i| (i.saturating_sub(3)..(i + 4).min(n)).map(move |j| (i, j))));
        assert!(!SparseLu::new(band).unwrap().wide_indices());
        // A clamped–clamped rod's band with its corner blocks (the 30 kbp
        // DNA rod's preconditioner: n = 117 014, half-width 51): the running
        // profile spans the matrix (bound ≈ n² > 2³²), George–Ng's does not.
        let (n, b) = (117_014, 51);
        let corner = Pattern::from_entries(
            n,
            (0..n)
                .flat_map(|i| (i.saturating_sub(b)..(i + b + 1).min(n)).map(move |j| (i, j)))
                .chain((0..b).flat_map(|i| (n - b..n).flat_map(move |j| [(i, j), (j, i)]))),
        );
        assert!(profile_bound(&corner, None) > NARROW_LIMIT);
        let gn = george_ng_bound(&corner, None).unwrap();
        assert!(gn < NARROW_LIMIT / 10, "{gn}");
        assert!(!SparseLu::new(corner).unwrap().wide_indices());
    }
}

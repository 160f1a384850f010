//! faer's supernodal sparse LU with partial pivoting, in the column order
//! [`super::SparseLu`] chose: the factorisation of the charged rod's
//! plectoneme Jacobians, whose L + U fill ~8.5× the matrix (~250 entries
//! per column) — a simplicial (column-by-column, scalar) LU spends ~100 ms
//! on one at 5–12 turns of the 1 kbp DNA scene, the supernodal one, on
//! dense blocks, ~4× less (measured).
//!
//! What faer's supernodal factors do not give is U's diagonal (its fields
//! are private), so no determinant: [`super::SparseLu`] computes the
//! determinant sign and the negative pivots on demand with the simplicial
//! LU of the same matrix — once per accepted continuation point, where a
//! record wants them, while the Newton corrections in between use these
//! factors only for solves.
//!
//! The symbolic analysis (column elimination tree, its postorder, the
//! column counts of AᵀA and the supernodes) is done once per pattern and
//! column order; a numeric factorisation also needs Aᵀ's values, gathered
//! through a fixed map (no allocation per factorisation).

use crate::error::{Error, Result};
use crate::status::Status;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::lu::supernodal::{self, SupernodalLu, SymbolicSupernodalLu};
use faer::sparse::linalg::qr;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};

use super::sparse::{ManyScratch, Pattern, Permutations, PermutedLu};

/// The supernodal LU of matrices with one pattern, in one column order.
pub(super) struct Supernodal<I: faer::Index> {
    col_ptr: Vec<I>,
    row_idx: Vec<I>,
    /// Aᵀ's pattern and, for each of its entries, the position of the same
    /// entry in A's values.
    t_ptr: Vec<I>,
    t_idx: Vec<I>,
    t_map: Vec<usize>,
    t_values: Vec<f64>,
    /// Scratch of the check solve: ones and A·1.
    ones: Vec<f64>,
    check: Vec<f64>,
    perm: Permutations<I>,
    symbolic: SymbolicSupernodalLu<I>,
    lu: SupernodalLu<I, f64>,
    buffer: MemBuffer,
    many: ManyScratch,
}

impl<I: faer::Index> Supernodal<I> {
    /// The symbolic analysis of `pattern` with its columns in the order
    /// `perm` (`perm[k]` the column taken k-th). None if faer refuses it.
    pub(super) fn new(pattern: &Pattern, perm: &[usize]) -> Option<Self> {
        let n = pattern.n;
        let cast = |v: &[usize]| v.iter().map(|&i| I::truncate(i)).collect::<Vec<I>>();
        let (col_ptr, row_idx) = (cast(&pattern.col_ptr), cast(&pattern.row_idx));
        let (t_ptr, t_idx, t_map) = transpose(pattern);
        let (t_ptr, t_idx) = (cast(&t_ptr), cast(&t_idx));
        let perm = Permutations::with_columns(perm);
        let a = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let at = SymbolicSparseColMatRef::new_checked(n, n, &t_ptr, None, &t_idx);
        let col_perm = perm.columns();
        let req = StackReq::any_of(&[
            qr::col_etree_scratch::<I>(n, n),
            qr::postorder_scratch::<I>(n),
            qr::column_counts_aat_scratch::<I>(n, n),
            supernodal::factorize_supernodal_symbolic_lu_scratch::<I>(n, n),
        ]);
        let mut scratch = MemBuffer::try_new(req).ok()?;
        let stack = MemStack::new(&mut scratch);
        let mut etree = vec![I::truncate(0); n];
        let tree = qr::col_etree(a, Some(col_perm), &mut etree, stack);
        let mut post = vec![I::truncate(0); n];
        qr::postorder(&mut post, tree, stack);
        let (mut counts, mut min_col) = (vec![I::truncate(0); n], vec![I::truncate(0); n]);
        qr::column_counts_ata(&mut counts, &mut min_col, at, Some(col_perm), tree, &post, stack);
        let symbolic = supernodal::factorize_supernodal_symbolic_lu(
            a,
            Some(col_perm),
            &min_col,
            tree,
            &counts,
            stack,
            Default::default(),
        )
        .ok()?;
        let req = supernodal::factorize_supernodal_numeric_lu_scratch::<I, f64>(&symbolic, Default::default())
            .or(supernodal::solve_in_place_scratch::<I, f64>(n, 1, Par::Seq))
            .or(supernodal::solve_transpose_in_place_scratch::<I, f64>(n, 1, Par::Seq));
        let nnz = pattern.nnz();
        Some(Supernodal {
            col_ptr,
            row_idx,
            t_ptr,
            t_idx,
            t_map,
            t_values: vec![0.0; nnz],
            ones: vec![1.0; n],
            check: vec![0.0; n],
            perm,
            symbolic,
            lu: SupernodalLu::new(),
            buffer: MemBuffer::try_new(req).ok()?,
            many: ManyScratch::default(),
        })
    }

    pub(super) fn dim(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// Numeric factorisation of the matrix with `values` (pattern order).
    /// faer reports no pivots: a zero one shows as a non-finite solve, so
    /// one solve of A v = A 1 checks the factors (the simplicial LU's
    /// criterion, a zero or non-finite pivot, in effect).
    pub(super) fn numeric(&mut self, values: &[f64], pattern: &Pattern) -> Result<()> {
        let n = self.dim();
        for (t, &k) in self.t_values.iter_mut().zip(&self.t_map) {
            *t = values[k];
        }
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let a = SparseColMatRef::new(sym, values);
        let tsym = SymbolicSparseColMatRef::new_checked(n, n, &self.t_ptr, None, &self.t_idx);
        let at = SparseColMatRef::new(tsym, &self.t_values);
        let (row_perm_fwd, row_perm_inv, col_perm) = self.perm.pivoting();
        let stack = MemStack::new(&mut self.buffer);
        supernodal::factorize_supernodal_numeric_lu(
            row_perm_fwd,
            row_perm_inv,
            &mut self.lu,
            a,
            at,
            col_perm,
            &self.symbolic,
            Par::Seq,
            stack,
            Default::default(),
        )
        .map_err(|e| Error::new(Status::ErrNotConverged, format!("sparse LU: singular matrix ({e:?})")))?;
        let mut check = std::mem::take(&mut self.check);
        pattern.mul_vec(values, &self.ones, &mut check);
        self.solve_with(&mut check, false);
        let bad = check.iter().position(|v| !v.is_finite());
        self.check = check;
        if let Some(k) = bad {
            return Err(Error::new(
                Status::ErrNotConverged,
                format!("sparse LU: the supernodal factors give a non-finite solve (entry {k}): singular matrix"),
            ));
        }
        Ok(())
    }

    pub(super) fn solve_with(&mut self, b: &mut [f64], transpose: bool) {
        self.perm.solve(&self.lu, b, 1, transpose, MemStack::new(&mut self.buffer));
    }
}

impl<I: faer::Index> Supernodal<I> {
    /// Solve A X = B in place for the k columns of `b` (column-major, n×k),
    /// unrefined.
    pub(super) fn solve_many(&mut self, b: &mut [f64], k: usize) {
        let stack = self.many.stack::<I, SupernodalLu<I, f64>>(self.dim(), k);
        self.perm.solve(&self.lu, b, k, false, stack);
    }
}

impl<I: faer::Index> PermutedLu<I> for SupernodalLu<I, f64> {
    fn solve_scratch(n: usize, k: usize) -> StackReq {
        supernodal::solve_in_place_scratch::<I, f64>(n, k, Par::Seq)
    }
    fn solve_in_place(&self, perm: &Permutations<I>, rhs: MatMut<'_, f64>, stack: &mut MemStack) {
        self.solve_in_place_with_conj(perm.rows(), perm.columns(), Conj::No, rhs, Par::Seq, stack);
    }
    fn solve_transpose_in_place(&self, perm: &Permutations<I>, rhs: MatMut<'_, f64>, stack: &mut MemStack) {
        self.solve_transpose_in_place_with_conj(perm.rows(), perm.columns(), Conj::No, rhs, Par::Seq, stack);
    }
}

/// Aᵀ's pattern in compressed columns (A's rows) and, per entry of Aᵀ,
/// the position of the same entry in A's values.
pub(super) fn transpose(pattern: &Pattern) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let n = pattern.n;
    let mut t_ptr = vec![0usize; n + 1];
    for &i in &pattern.row_idx {
        t_ptr[i + 1] += 1;
    }
    for k in 0..n {
        t_ptr[k + 1] += t_ptr[k];
    }
    let mut next = t_ptr.clone();
    let mut t_idx = vec![0usize; pattern.nnz()];
    let mut t_map = vec![0usize; pattern.nnz()];
    for j in 0..n {
        for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
            let i = pattern.row_idx[k];
            t_idx[next[i]] = j;
            t_map[next[i]] = k;
            next[i] += 1;
        }
    }
    (t_ptr, t_idx, t_map)
}

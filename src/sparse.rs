//! Sparse matrices with a fixed pattern and their LU factorisation (faer).
//!
//! A continuation factorises the same pattern hundreds of times: the fill-
//! reducing column ordering (COLAMD) is computed once per pattern
//! ([`SparseLu::new`]) and every numeric factorisation reuses it and its
//! buffers (no allocation once the first factorisation has sized them).
//! faer's simplicial left-looking LU with partial pivoting is used directly
//! (rather than its high-level `Lu`) because the continuation needs the sign
//! of the determinant, which takes U's diagonal and the permutations' parity.
//! Everything runs with `Par::Seq`: rodkit starts no threads unless asked.

use crate::error::{Error, Result};
use crate::status::Status;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::lu::{self, simplicial::SimplicialLu, LuSymbolicParams};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};

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
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (i, j) in entries {
            assert!(i < n && j < n, "entry ({i}, {j}) outside a {n}×{n} pattern");
            cols[j].push(i);
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for c in &mut cols {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(c);
            col_ptr.push(row_idx.len());
        }
        Pattern { n, col_ptr, row_idx }
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
}

/// LU factorisation of matrices sharing one [`Pattern`].
pub struct SparseLu {
    pattern: Pattern,
    /// The pattern's indices as u32 (faer's LU is generic over the index
    /// type): half the memory of L + U's row indices, which are as many as
    /// their values — the solves and factorisations of long rods stream
    /// them from memory once they outgrow the cache.
    col_ptr32: Vec<u32>,
    row_idx32: Vec<u32>,
    col_perm_fwd: Vec<u32>,
    col_perm_inv: Vec<u32>,
    row_perm_fwd: Vec<u32>,
    row_perm_inv: Vec<u32>,
    lu: SimplicialLu<u32, f64>,
    buffer: MemBuffer,
    factorised: bool,
    /// Whether the column ordering has been chosen (on the first matrix).
    ordered: bool,
    /// Numeric factorisations done (the cost unit of a continuation).
    pub factorisations: usize,
    /// Solves done (each with one right-hand side).
    pub solves: usize,
}

impl SparseLu {
    /// For matrices with `pattern`. The column ordering is chosen on the
    /// first matrix (natural, or COLAMD's computed then only if the
    /// natural order fills too much: for the banded matrices of collocated
    /// ODEs it is never needed, and computing it cost ~40 % of one numeric
    /// factorisation).
    pub fn new(pattern: Pattern) -> Result<Self> {
        let n = pattern.n;
        // L + U of a pattern this size may hold several times its entries.
        if pattern.nnz() >= (u32::MAX / 16) as usize {
            return Err(Error::new(Status::ErrInvalidDimension, format!("sparse LU: {} entries is beyond the u32 indices' range", pattern.nnz())));
        }
        let to32 = |v: &[usize]| v.iter().map(|&i| i as u32).collect::<Vec<u32>>();
        let (col_ptr32, row_idx32) = (to32(&pattern.col_ptr), to32(&pattern.row_idx));
        let (col_perm_fwd, col_perm_inv) = ((0..n as u32).collect(), (0..n as u32).collect());
        let req = lu::simplicial::factorize_simplicial_numeric_lu_scratch::<u32, f64>(n, n)
            .or(lu::simplicial::solve_in_place_scratch::<u32, f64>(n, 1, Par::Seq));
        Ok(SparseLu {
            pattern,
            col_ptr32,
            row_idx32,
            col_perm_fwd,
            col_perm_inv,
            row_perm_fwd: vec![0; n],
            row_perm_inv: vec![0; n],
            lu: SimplicialLu::new(),
            buffer: MemBuffer::new(req),
            factorised: false,
            ordered: false,
            factorisations: 0,
            solves: 0,
        })
    }

    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// Entries of L + U of the last factorisation (0 before the first).
    pub fn fill(&self) -> usize {
        if self.factorised {
            self.lu.l_factor_unsorted().compute_nnz() + self.lu.u_factor_unsorted().compute_nnz()
        } else {
            0
        }
    }

    /// Whether the columns are factorised in their natural order (chosen
    /// on the first matrix), not COLAMD's.
    pub fn natural_order(&self) -> bool {
        self.col_perm_fwd.iter().enumerate().all(|(i, &j)| i == j as usize)
    }

    /// Numeric factorisation of the matrix with `values` in pattern order.
    /// A (numerically) singular matrix is ErrNotConverged: a continuation
    /// treats it as a failed step, not a number.
    pub fn factorise(&mut self, values: &[f64]) -> Result<()> {
        assert_eq!(values.len(), self.pattern.nnz(), "values do not match the pattern");
        let n = self.pattern.n;
        self.factorised = false;
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(Error::new(Status::ErrNonFiniteResult, format!("sparse LU: matrix entry {k} is not finite")));
        }
        let in_place = !self.ordered && self.choose_ordering(values);
        if !in_place {
            self.numeric(values)?;
        }
        self.factorisations += 1;
        // A zero or non-finite pivot is a singular matrix.
        let u = self.lu.u_factor_unsorted();
        for j in 0..n {
            let d = self.diagonal_of(u, j);
            if !(d.is_finite() && d != 0.0) {
                return Err(Error::new(Status::ErrNotConverged, format!("sparse LU: pivot {j} is {d:e} (singular matrix)")));
            }
        }
        self.factorised = true;
        Ok(())
    }

    fn numeric(&mut self, values: &[f64]) -> Result<()> {
        let n = self.pattern.n;
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr32, None, &self.row_idx32);
        let a = SparseColMatRef::new(sym, values);
        let col_perm = PermRef::new_checked(&self.col_perm_fwd, &self.col_perm_inv, n);
        let stack = MemStack::new(&mut self.buffer);
        lu::simplicial::factorize_simplicial_numeric_lu(&mut self.row_perm_fwd, &mut self.row_perm_inv, &mut self.lu, a, col_perm, stack)
            .map_err(|e| Error::new(Status::ErrNotConverged, format!("sparse LU: singular matrix ({e:?})")))
    }

    /// On the first matrix: factorise with the natural order; keep it when
    /// its fill (entries of L + U) is at most 8× the matrix's, else try
    /// COLAMD's ordering too and keep the one with less fill. For the
    /// block-banded matrices of collocated ODEs with stage unknowns the
    /// natural (banded) order has ~2.5–5× the matrix's entries while COLAMD
    /// can have 8× more again (rod, Gauss(4) × 32: 98 k against 771 k) —
    /// and a trial factorisation that dense costs more than the whole
    /// continuation; COLAMD wins on general patterns.
    /// Returns whether the factorisation of `values` with the chosen
    /// ordering is already in place.
    fn choose_ordering(&mut self, values: &[f64]) -> bool {
        self.ordered = true;
        let fill = |lu: &SimplicialLu<u32, f64>| lu.l_factor_unsorted().compute_nnz() + lu.u_factor_unsorted().compute_nnz();
        let n = self.pattern.n;
        self.col_perm_fwd = (0..n as u32).collect();
        self.col_perm_inv = (0..n as u32).collect();
        let natural = self.numeric(values).ok().map(|_| fill(&self.lu));
        if let Some(f) = natural {
            if f <= 8 * self.pattern.nnz() {
                return true;
            }
        }
        let Some(colamd_perm) = self.colamd() else {
            return false;
        };
        let natural_perm = (std::mem::take(&mut self.col_perm_fwd), std::mem::take(&mut self.col_perm_inv));
        (self.col_perm_fwd, self.col_perm_inv) = colamd_perm;
        let colamd = self.numeric(values).ok().map(|_| fill(&self.lu));
        let keep_colamd = match (colamd, natural) {
            (Some(c), Some(nat)) => c < nat,
            (Some(_), None) => true,
            _ => false,
        };
        if keep_colamd {
            return true;
        }
        (self.col_perm_fwd, self.col_perm_inv) = natural_perm;
        false
    }

    /// COLAMD's column ordering of the pattern (None if the analysis fails:
    /// the natural order is then kept).
    fn colamd(&self) -> Option<(Vec<u32>, Vec<u32>)> {
        let n = self.pattern.n;
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr32, None, &self.row_idx32);
        let params = LuSymbolicParams { supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL, ..Default::default() };
        let symbolic = lu::factorize_symbolic_lu(sym, params).ok()?;
        let (fwd, inv) = symbolic.col_perm().arrays();
        Some((fwd.to_vec(), inv.to_vec()))
    }

    fn diagonal_of(&self, u: SparseColMatRef<'_, u32, f64>, j: usize) -> f64 {
        let rows = u.row_idx_of_col_raw(j);
        let vals = u.val_of_col(j);
        rows.iter().zip(vals).find(|(&i, _)| i as usize == j).map_or(0.0, |(_, &v)| v)
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
        let n = self.pattern.n;
        let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
        let row_perm = PermRef::new_checked(&self.row_perm_fwd, &self.row_perm_inv, n);
        let col_perm = PermRef::new_checked(&self.col_perm_fwd, &self.col_perm_inv, n);
        let stack = MemStack::new(&mut self.buffer);
        if transpose {
            self.lu.solve_transpose_in_place_with_conj(row_perm, col_perm, Conj::No, rhs, Par::Seq, stack);
        } else {
            self.lu.solve_in_place_with_conj(row_perm, col_perm, Conj::No, rhs, Par::Seq, stack);
        }
        self.solves += 1;
    }

    /// Sign of det A (±1) and log|det A| of the last factorisation.
    pub fn determinant_sign_and_log(&self) -> (f64, f64) {
        assert!(self.factorised, "determinant before a successful factorisation");
        let u = self.lu.u_factor_unsorted();
        let (mut sign, mut log) = (parity(&self.row_perm_fwd) * parity(&self.col_perm_fwd), 0.0);
        for j in 0..self.pattern.n {
            let d = self.diagonal_of(u, j);
            sign *= d.signum();
            log += d.abs().ln();
        }
        (sign, log)
    }

    /// Negative diagonal entries of U (the pivots). With row pivoting the
    /// count itself depends on the pivot order; its parity times the
    /// permutations' parity is sign det.
    pub fn negative_pivots(&self) -> usize {
        assert!(self.factorised, "pivots before a successful factorisation");
        let u = self.lu.u_factor_unsorted();
        (0..self.pattern.n).filter(|&j| self.diagonal_of(u, j) < 0.0).count()
    }
}

/// +1 for an even permutation, −1 for an odd one (cycle count).
fn parity(p: &[u32]) -> f64 {
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
            i = p[i] as usize;
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
            let mut dense = DMatrix::zeros(n, n);
            for j in 0..n {
                for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                    dense[(pattern.row_idx[k], j)] = values[k];
                }
            }
            lu.factorise(&values).unwrap();
            let b: Vec<f64> = (0..n).map(|_| rnd()).collect();
            let mut x = b.clone();
            lu.solve(&mut x);
            let mut y = vec![0.0; n];
            pattern.mul_vec(&values, &x, &mut y);
            let res = y.iter().zip(&b).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(res < 1e-11, "trial {trial}: residual {res:e}");
            let mut xt = b.clone();
            lu.solve_transpose(&mut xt);
            let yt = dense.transpose() * nalgebra::DVector::from_vec(xt);
            assert!(yt.iter().zip(&b).all(|(a, b)| (a - b).abs() < 1e-11));
            let det = dense.clone().lu().determinant();
            let (sign, log) = lu.determinant_sign_and_log();
            assert_eq!(sign, det.signum(), "trial {trial}");
            assert!((log - det.abs().ln()).abs() < 1e-9);
        }
        assert_eq!(lu.factorisations, 3);
        // A singular matrix is a status.
        let zeros = vec![0.0; pattern.nnz()];
        assert_eq!(lu.factorise(&zeros).unwrap_err().status, Status::ErrNotConverged);
    }

    /// The ordering choice: an arrowhead matrix (dense first row and column)
    /// fills completely in its natural order, so COLAMD (which moves the
    /// dense column last) is kept; a banded matrix keeps its natural order.
    /// Both solve to rounding.
    #[test]
    fn ordering_is_chosen_by_fill() {
        let n = 300;
        let arrow = Pattern::from_entries(n, (0..n).flat_map(|i| [(i, i), (0, i), (i, 0)]));
        let band = Pattern::from_entries(n, (0..n).flat_map(|i| (i.saturating_sub(3)..(i + 4).min(n)).map(move |j| (i, j))));
        for (pattern, natural) in [(arrow, false), (band, true)] {
            let mut lu = SparseLu::new(pattern.clone()).unwrap();
            // Diagonally dominant values: no pivoting needed.
            let values: Vec<f64> = (0..n).flat_map(|j| (pattern.col_ptr[j]..pattern.col_ptr[j + 1]).map(move |k| (j, k))).map(|(j, k)| if pattern.row_idx[k] == j { 10.0 * n as f64 } else { 1.0 }).collect();
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
}

//! The sparse LU of the banded part of a matrix — entries with |i − j| ≤ w,
//! plus the two corner blocks (min(i, j) < w, max(i, j) ≥ n − w) where a
//! two-point boundary value problem's end conditions couple its first and
//! last unknowns, and optionally the last rows and columns whole (a
//! border). For a rod ordered along its arc length, w = one element's
//! coupling keeps the elastic rod whole and drops the electrostatic far
//! pairs, whose entries widen the band several-fold (the LU's cost grows
//! as n w²): the lagged preconditioner of Newton–Krylov
//! ([`crate::nonlinear::krylov`]).

use super::sparse::{Pattern, SparseLu};
use crate::error::{Error, Result};
use crate::status::Status;

/// [`BandLu`]'s mark of a full-pattern entry outside the band.
const DROPPED: u32 = u32::MAX;

/// The band of matrices with one pattern, its symbolic analysis done once.
pub struct BandLu {
    n: usize,
    band: usize,
    /// For each entry of the full pattern, its position in the band's
    /// values (DROPPED: not kept). u32, not Option<usize>: 4 bytes an entry
    /// instead of 16 (12 MB at 10 kbp on the DNA rod, all of it touched —
    /// page faults — by every cold solve).
    map: Vec<u32>,
    values: Vec<f64>,
    lu: SparseLu,
}

impl BandLu {
    /// For matrices with `pattern`, keeping |i − j| ≤ `band`, the boundary
    /// corner blocks and the last `border` rows and columns whole:
    /// unknowns appended to a banded problem (a phase condition's
    /// multiplier, a continuation's parameter) whose equations reach
    /// mid-band — without them the banded matrix is singular.
    pub fn new(pattern: &Pattern, band: usize, border: usize) -> Result<Self> {
        let n = pattern.n;
        if pattern.nnz() >= DROPPED as usize {
            return Err(Error::new(
                Status::ErrInvalidDimension,
                format!("band preconditioner: {} entries is beyond the u32 positions' range", pattern.nnz()),
            ));
        }
        let keep = |i: usize, j: usize| {
            i.abs_diff(j) <= band || (i.min(j) < band && i.max(j) + band >= n) || i.max(j) + border >= n
        };
        // The kept entries in the full pattern's (sorted, compressed-column)
        // order are already the band's: one pass, no sort or search.
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let mut map = Vec::with_capacity(pattern.nnz());
        col_ptr.push(0);
        for j in 0..n {
            for &i in &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]] {
                map.push(if keep(i, j) {
                    row_idx.push(i);
                    (row_idx.len() - 1) as u32
                } else {
                    DROPPED
                });
            }
            col_ptr.push(row_idx.len());
        }
        let small = Pattern { n, col_ptr, row_idx };
        let values = vec![0.0; small.nnz()];
        Ok(BandLu { n, band, map, values, lu: SparseLu::new(small)? })
    }

    pub fn dim(&self) -> usize {
        self.n
    }

    pub fn band(&self) -> usize {
        self.band
    }

    /// (Entries kept, entries of the full pattern.)
    pub fn kept(&self) -> (usize, usize) {
        (self.values.len(), self.map.len())
    }

    /// Entries of the banded matrix's L + U (0 before the first factorisation).
    pub fn fill(&self) -> usize {
        self.lu.fill()
    }

    /// Factorise the band of the matrix whose values (in the full
    /// pattern's order) are `full`.
    pub fn factorise(&mut self, full: &[f64]) -> Result<()> {
        if full.len() != self.map.len() {
            return Err(Error::new(
                Status::ErrInvalidDimension,
                "band preconditioner: the Jacobian's pattern is not the one it was built for",
            ));
        }
        self.values.fill(0.0);
        for (&m, &v) in self.map.iter().zip(full) {
            if m != DROPPED {
                self.values[m as usize] = v;
            }
        }
        self.lu.factorise(&self.values)
    }

    /// v ← M⁻¹ v with M the factorised band.
    pub fn solve(&mut self, v: &mut [f64]) {
        self.lu.solve(v);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tridiagonal matrix with a far entry (0, 4) and a corner (4, 0):
    /// band 1 keeps the tridiagonal part and the corners (both within the
    /// first and last unknown), drops nothing else here; band 0 with the
    /// corners drops the off-diagonals. The kept matrix's solve is checked
    /// against a dense solve of the same kept entries (nalgebra).
    #[test]
    fn keeps_the_band_and_corners_and_solves_them() {
        let n = 5;
        let mut entries: Vec<(usize, usize)> = (0..n).map(|i| (i, i)).collect();
        entries.extend((0..n - 1).flat_map(|i| [(i, i + 1), (i + 1, i)]));
        entries.extend([(0, 4), (4, 0), (1, 3)]);
        let pattern = Pattern::from_entries(n, entries);
        let mut lu = BandLu::new(&pattern, 1, 0).unwrap();
        let all = pattern.nnz();
        assert_eq!(lu.kept(), (all - 1, all), "(1, 3) lies outside band 1 and the corners");
        let value = |i: usize, j: usize| if i == j { 4.0 + i as f64 } else { 1.0 / (1.0 + (i + 2 * j) as f64) };
        let mut full = vec![0.0; all];
        let mut dense = nalgebra::DMatrix::zeros(n, n);
        for j in 0..n {
            for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                let i = pattern.row_idx[k];
                full[k] = value(i, j);
                if (i, j) != (1, 3) {
                    dense[(i, j)] = value(i, j);
                }
            }
        }
        lu.factorise(&full).unwrap();
        let b: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let mut x = b.clone();
        lu.solve(&mut x);
        let reference = dense.lu().solve(&nalgebra::DVector::from_vec(b)).unwrap();
        for i in 0..n {
            assert!((x[i] - reference[i]).abs() < 1e-14, "{i}: {} vs {}", x[i], reference[i]);
        }
        assert!(lu.factorise(&full[1..]).is_err());
    }
}

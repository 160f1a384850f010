//! A sparse n×n matrix A bordered by one dense column c, row r and corner
//! d, B = [[A, c], [rᵀ, d]], and its sparse LU: the extended systems of
//! continuation (the bordered tangent), of bifurcation location and of
//! phase conditions. The border is stored dense (O(n) fill at most); the
//! pattern is fixed, so the column ordering is computed once.
//!
//! Besides solves, B's determinant sign, the negative pivots of its
//! factors and estimates of its smallest singular values (inverse
//! iteration on BᵀB with the factors) — the indicators a continuation
//! watches for folds and bifurcations — in the scaled matrix
//! Ã = diag(row) B diag(col) ([`BorderedLu::set_scales`]), so that they do
//! not depend on the model's units.

use super::bordering::BlockElimination;
use super::condensed::{CondensedLu, CondensedStructure, DENSE_KEPT};
use super::dense::{dot, orthonormalise};
use super::sparse::{ColumnOrder, LuKind, Pattern, SparseLu};
use crate::error::{Error, Result};
use crate::kept::Recent;
use crate::status::Status;
use std::sync::Arc;

/// What a subspace iteration is for ([`BorderedLu::smallest_singular_vectors`]).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Subspace {
    Monitor(Settle),
    Vectors,
}

/// When the σ_min monitor ([`BorderedLu::signed_smallest_singular_value`])
/// stops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Settle {
    /// When σ_1's Ritz value has settled to the tolerance: what the
    /// monitor reads.
    First,
    /// When every Ritz value of its two-column block has: the same σ_1 to
    /// the tolerance at more solves (a fifth more on a rod's branch), kept
    /// for runs whose recorded results were computed with it.
    All,
}

/// Where a subspace iteration for singular vectors starts
/// ([`BorderedLu::smallest_singular_vectors`],
/// [`BorderedLu::signed_smallest_singular_value`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    /// Fixed pseudo-random vectors: the result depends on the matrix alone
    /// (a branch's records, whose σ_min a path's detections read).
    Fixed,
    /// The previous iteration's Ritz vectors, the fixed ones filling any
    /// column they leave: for a sequence of nearby matrices known to hold
    /// the direction sought (the trial points of a location inside one
    /// bracket), where they converge in a few solves.
    Previous,
}

/// A converged leading singular pair is locked (deflated) when it lies
/// this far below the next ([`BorderedLu::smallest_singular_vectors`]):
/// below it the round-off it feeds the other directions, O(ε κ (σ_2/σ_1)²)
/// relative, would be felt.
pub const LOCK_GAP: f64 = 1e-4;

/// How [`BorderedLu::factorise`] factorises: not yet decided (on its
/// first matrix), B's own (simplicial) LU, block elimination on A's
/// supernodal LU ([`super::bordering`]), or B's static condensation
/// ([`super::condensed`]: A's private blocks eliminated, the border kept
/// with the rest).
enum Fast {
    Undecided,
    Whole,
    Blocks(Box<BlockElimination>),
    Condensed(Box<CondensedLu>),
}

/// What a [`BorderedLu`] takes from A's pattern, its trailing count and
/// private blocks alone: B's pattern, where A's entries and the border go
/// in it, the condensation's structure. Kept per thread ([`structure`]):
/// the rods of a sweep rebuild tangents of one pattern.
struct Structure {
    /// A's trailing count and blocks (A's pattern is B's without its
    /// last row and column: [`Structure::inner`]).
    trailing: usize,
    blocks: Vec<Vec<usize>>,
    /// B's pattern: column j < n is A's column j then row n, column n is
    /// rows 0..=n (so A's entry p is B's p + j, [`BorderedLu::assemble`]).
    big: Arc<Pattern>,
    /// The condensation's structure, when A's blocks have its form.
    condensed: Option<Arc<CondensedStructure>>,
}

impl Structure {
    fn new(pattern: &Pattern, trailing: usize, blocks: &[Vec<usize>]) -> Result<Self> {
        let n = pattern.n;
        let nnz = pattern.nnz();
        // B's pattern written directly: column j < n is A's column j (rows
        // sorted, all < n) then row n; column n is rows 0..=n. Each of A's
        // entries moves down by its column index.
        let mut col_ptr = Vec::with_capacity(n + 2);
        let mut row_idx = Vec::with_capacity(nnz + 2 * n + 1);
        for j in 0..n {
            col_ptr.push(row_idx.len());
            let rows = &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]];
            // Pattern's invariant (its fields are public): B's rows are
            // A's, in order, with no repeat.
            if rows.windows(2).any(|w| w[0] >= w[1]) || rows.last().is_some_and(|&r| r >= n) {
                return Err(Error::new(
                    Status::ErrInvalidDimension,
                    format!("bordered LU: column {j} of the pattern has rows out of order, repeated or out of range"),
                ));
            }
            row_idx.extend_from_slice(rows);
            row_idx.push(n);
        }
        col_ptr.push(row_idx.len());
        row_idx.extend(0..=n);
        col_ptr.push(row_idx.len());
        let big = Pattern { n: n + 1, col_ptr, row_idx };
        // The border row and column reach every block: kept.
        let condensed = match blocks.is_empty() {
            true => None,
            // B's rows were checked sorted and in range above.
            false => CondensedStructure::of_sorted(&big, blocks, trailing + 1, DENSE_KEPT).ok().map(Arc::new),
        };
        Ok(Structure { trailing, blocks: blocks.to_vec(), big: Arc::new(big), condensed })
    }
}

impl Structure {
    /// Whether B borders A's `pattern`: column j of B is A's column j,
    /// then row n (one pass over A's indices, no copy of A's pattern kept).
    fn borders(&self, pattern: &Pattern) -> bool {
        let big = &*self.big;
        let n = pattern.n;
        big.n == n + 1
            && (0..n).all(|j| {
                let (p, q) = (pattern.col_ptr[j], pattern.col_ptr[j + 1]);
                big.col_ptr[j] == p + j
                    && big.col_ptr[j + 1] == q + j + 1
                    && big.row_idx[p + j..q + j] == pattern.row_idx[p..q]
            })
    }

    /// A's pattern: B's without its last row and column.
    fn inner(&self) -> Pattern {
        let big = &*self.big;
        let n = big.n - 1;
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(big.nnz() - 2 * n - 1);
        col_ptr.push(0);
        for j in 0..n {
            row_idx.extend_from_slice(&big.row_idx[big.col_ptr[j]..big.col_ptr[j + 1] - 1]);
            col_ptr.push(row_idx.len());
        }
        Pattern { n, col_ptr, row_idx }
    }
}

/// Structures kept on this thread: at most [`KEPT_STRUCTURES`], the least
/// recently used dropped first, each of a pattern of at most
/// [`KEPT_ENTRIES`] entries (~17 bytes an entry with B's pattern and the
/// condensation's 32-bit maps: ≤ 2.2 MB apiece; a larger system's set-up
/// is small beside its factorisations).
const KEPT_STRUCTURES: usize = 8;
const KEPT_ENTRIES: usize = 1 << 17;

thread_local! {
    static STRUCTURES: Recent<Structure> = const { Recent::new(KEPT_STRUCTURES) };
}

/// The structure of B for A's `pattern`, kept or built. Finding it
/// compares the patterns (one pass over A's indices) against the several
/// passes, sorts and searches of a build.
fn structure(pattern: &Pattern, trailing: usize, blocks: &[Vec<usize>]) -> Result<Arc<Structure>> {
    let fits = |s: &Structure| s.trailing == trailing && s.blocks == blocks && s.borders(pattern);
    if let Some(s) = STRUCTURES.try_with(|kept| kept.find(fits)).ok().flatten() {
        return Ok(s);
    }
    let s = Arc::new(Structure::new(pattern, trailing, blocks)?);
    if pattern.nnz() <= KEPT_ENTRIES {
        let _ = STRUCTURES.try_with(|kept| kept.keep(s.clone()));
    }
    Ok(s)
}

/// Drop the bordered structures kept on this thread (their memory; a
/// benchmark of a first set-up).
pub fn forget_kept_structures() {
    let _ = STRUCTURES.try_with(|kept| kept.clear());
}

/// Bordered structures kept on this thread.
#[cfg(test)]
fn kept_structures() -> usize {
    STRUCTURES.with(|kept| kept.len())
}

pub struct BorderedLu {
    n: usize,
    lu: SparseLu,
    values: Vec<f64>,
    /// B's pattern and maps (shared).
    structure: Arc<Structure>,
    /// The singular-value estimates work on Ã = R B C (ones until
    /// [`BorderedLu::set_scales`]): in raw units (pN, nm for DNA) a mode of
    /// a badly scaled row can sit below every buckling mode and hide their
    /// zero crossings.
    row_scale: Vec<f64>,
    col_scale: Vec<f64>,
    fast: Fast,
    /// Whether the last factorisation is the block elimination's or the
    /// condensation's (solves use it), else B's LU.
    blocks_active: bool,
    preferred: Option<ColumnOrder>,
    preferred_kind: Option<LuKind>,
    /// See [`BorderedLu::records_take`].
    records_order: Option<ColumnOrder>,
    /// B⁻¹e_{n+1} = (v, ν) of the current matrix, for solves with A
    /// through B ([`BorderedLu::solve_inner_many`]), and whether it is
    /// known (reset when a matrix is assembled).
    inner_column: Vec<f64>,
    inner_known: bool,
    /// Scratch of those solves: k columns of n + 1 (grown on demand).
    inner_scratch: Vec<f64>,
    /// The last subspace iteration's Ritz vectors (scaled space, unit):
    /// [`Start::Previous`].
    ritz: Vec<Vec<f64>>,
}

impl BorderedLu {
    /// For A with `pattern` (n×n): B is (n + 1)×(n + 1).
    pub fn new(pattern: &Pattern) -> Result<Self> {
        Self::with_trailing(pattern, 0)
    }

    /// As [`BorderedLu::new`], A's last `trailing` unknowns being
    /// multipliers whose rows and columns reach across it (ordered last
    /// with the border by any reordering: [`SparseLu::with_trailing`]).
    pub fn with_trailing(pattern: &Pattern, trailing: usize) -> Result<Self> {
        Self::from_structure(structure(pattern, trailing, &[])?)
    }

    fn from_structure(structure: Arc<Structure>) -> Result<Self> {
        let n = structure.big.n - 1;
        let trailing = structure.trailing;
        Ok(BorderedLu {
            n,
            lu: {
                // B's dense border row makes its AᵀA factor dense: B is
                // always factorised simplicially (supernodes go to A).
                let mut lu = SparseLu::shared(structure.big.clone(), trailing + 1)?;
                lu.prefer_kind(LuKind::Simplicial);
                lu
            },
            // Sized by the first assembly, which writes it whole.
            values: Vec::new(),
            row_scale: vec![1.0; n + 1],
            col_scale: vec![1.0; n + 1],
            fast: match &structure.condensed {
                Some(c) => Fast::Condensed(Box::new(CondensedLu::from_structure(c.clone())?)),
                None => Fast::Undecided,
            },
            structure,
            blocks_active: false,
            preferred: None,
            preferred_kind: None,
            records_order: None,
            inner_column: vec![0.0; n + 1],
            inner_known: false,
            inner_scratch: Vec::new(),
            ritz: Vec::new(),
        })
    }

    /// As [`BorderedLu::with_trailing`], A's unknowns in each of `blocks`
    /// private to it ([`CondensedLu::new`]'s form; the border row and
    /// column reach every block, and are kept): B is factorised by static
    /// condensation, blocks by dense LU, the kept system (the nodes and
    /// the border) by a simplicial LU — exact elimination with pivoting
    /// throughout, no bordering algorithm to refine, and det B's sign from
    /// the factors. If a block or the kept system is singular, B's own LU
    /// decides that matrix. Without blocks, or if the pattern does not
    /// have that form, as [`BorderedLu::with_trailing`].
    pub fn with_private_blocks(pattern: &Pattern, trailing: usize, blocks: &[Vec<usize>]) -> Result<Self> {
        Self::from_structure(structure(pattern, trailing, blocks)?)
    }

    /// Whether B is factorised by condensation
    /// ([`BorderedLu::with_private_blocks`]).
    pub fn condensed(&self) -> bool {
        matches!(self.fast, Fast::Condensed(_))
    }

    /// Whether the last factorisation is the condensation's (not B's own
    /// LU, taken when a block or the kept system was singular).
    pub fn last_condensed(&self) -> bool {
        self.blocks_active && self.condensed()
    }

    /// n (B is one larger).
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Assemble B from A's values (in its pattern's order), c, r and d, and
    /// factorise it. A singular B is ErrNotConverged (from [`SparseLu`]).
    /// For solves: when A's pattern takes supernodal factors
    /// ([`LuKind`], decided on the first matrix), block elimination on
    /// them ([`super::bordering`]), else B's own LU. If A's factorisation
    /// or the border's Schur scalar fails, B's own LU decides.
    pub fn factorise(&mut self, a: &[f64], c: &[f64], r: &[f64], d: f64) -> Result<()> {
        self.check_lengths(a, c, r)?;
        self.assemble(a, c, r, d);
        self.blocks_active = false;
        if let Fast::Condensed(lu) = &mut self.fast {
            if lu.factorise(&self.values).is_ok() {
                self.blocks_active = true;
                return Ok(());
            }
            return self.lu.factorise(&self.values);
        }
        // A's first factorisation decides (A then factorised).
        let fresh = matches!(self.fast, Fast::Undecided);
        if fresh {
            self.fast = self.first_blocks(a);
        }
        if let Fast::Blocks(blocks) = &mut self.fast {
            let factorised = if fresh { Ok(()) } else { blocks.a.factorise(a) };
            if factorised.and_then(|_| blocks.border(c, r, d, self.lu.pattern(), &self.values)).is_ok() {
                self.blocks_active = true;
                return Ok(());
            }
        }
        self.lu.factorise(&self.values)
    }

    /// Block elimination when A alone takes supernodal factors (tried on
    /// its first matrix), else B's LU for good.
    fn first_blocks(&mut self, a: &[f64]) -> Fast {
        // Once: the first matrix decides `fast` for good.
        let Ok(mut blocks) = BlockElimination::new(self.structure.inner(), self.structure.trailing) else {
            return Fast::Whole;
        };
        if let Some(order) = self.preferred {
            blocks.a.prefer(order);
        }
        if let Some(kind) = self.preferred_kind {
            blocks.a.prefer_kind(kind);
        }
        match blocks.a.factorise(a) {
            Ok(()) if blocks.a.kind() == LuKind::Supernodal => Fast::Blocks(Box::new(blocks)),
            _ => Fast::Whole,
        }
    }

    /// As [`BorderedLu::factorise`], simplicial whatever the pattern
    /// ([`SparseLu::factorise_exact`]): for a point whose determinant sign
    /// and pivots are read.
    pub fn factorise_exact(&mut self, a: &[f64], c: &[f64], r: &[f64], d: f64) -> Result<()> {
        // The condensed factors give the sign and pivots themselves.
        if self.condensed() {
            return self.factorise(a, c, r, d);
        }
        self.check_lengths(a, c, r)?;
        self.assemble(a, c, r, d);
        self.blocks_active = false;
        self.lu.factorise_exact(&self.values)
    }

    /// B's own LU of the last matrix in place of the block elimination's
    /// (for a determinant, or a solve that did not refine): false if B is
    /// singular.
    fn factorise_whole(&mut self) -> bool {
        if self.blocks_active {
            self.blocks_active = false;
            return self.lu.factorise_exact(&self.values).is_ok();
        }
        true
    }

    /// Solve with B or Bᵀ from whichever factors hold the last matrix.
    fn solve_with(&mut self, rhs: &mut [f64], transpose: bool) {
        if self.blocks_active {
            let solved = match &mut self.fast {
                Fast::Condensed(lu) if transpose => {
                    lu.solve_transpose(rhs);
                    true
                }
                Fast::Condensed(lu) => {
                    lu.solve(rhs);
                    true
                }
                Fast::Blocks(blocks) => blocks.solve(self.lu.pattern(), &self.values, rhs, transpose).is_ok(),
                _ => false,
            };
            if solved {
                return;
            }
            if !self.factorise_whole() {
                rhs.fill(f64::NAN);
                return;
            }
        }
        if transpose {
            self.lu.solve_transpose(rhs);
        } else {
            self.lu.solve(rhs);
        }
    }

    /// A's values (its pattern's length) and the border's (n each).
    fn check_lengths(&self, a: &[f64], c: &[f64], r: &[f64]) -> Result<()> {
        let nnz = self.structure.big.nnz() - 2 * self.n - 1;
        if a.len() != nnz || c.len() != self.n || r.len() != self.n {
            return Err(Error::new(
                Status::ErrInvalidDimension,
                format!(
                    "bordered LU: {} matrix values and borders of {} and {} (want {nnz} and {})",
                    a.len(),
                    c.len(),
                    r.len(),
                    self.n
                ),
            ));
        }
        Ok(())
    }

    fn assemble(&mut self, a: &[f64], c: &[f64], r: &[f64], d: f64) {
        self.inner_known = false;
        // B's layout (Structure::big): every entry written, column by column.
        let (n, big) = (self.n, &*self.structure.big);
        if self.values.len() != big.nnz() {
            self.values = vec![0.0; big.nnz()];
        }
        // A's column j is B's, shifted down by j, less its last entry.
        for j in 0..n {
            let (p, q) = (big.col_ptr[j], big.col_ptr[j + 1] - 1);
            self.values[p..q].copy_from_slice(&a[p - j..q - j]);
            self.values[q] = r[j];
        }
        let last = big.col_ptr[n];
        self.values[last..last + n].copy_from_slice(&c[..n]);
        self.values[last + n] = d;
    }

    /// See [`SparseLu::prefer`].
    pub fn prefer(&mut self, order: ColumnOrder) {
        self.lu.prefer(order);
        self.preferred = Some(order);
    }

    /// How [`BorderedLu::factorise`] factorises instead of deciding by
    /// A's structure: Simplicial, B's own LU always; Supernodal, block
    /// elimination on A's supernodal LU whatever its structure. Given
    /// after the first factorisation it changes nothing.
    /// Condensed keeps the condensation where the problem has private
    /// blocks (else as no preference).
    pub fn prefer_kind(&mut self, kind: LuKind) {
        if self.factorisations() > 0 {
            return;
        }
        match kind {
            LuKind::Simplicial => self.fast = Fast::Whole,
            LuKind::Supernodal if self.condensed() => self.fast = Fast::Undecided,
            _ => {}
        }
        if matches!(self.fast, Fast::Undecided) {
            self.preferred_kind = Some(kind);
        }
    }

    /// See [`SparseLu::column_order`].
    pub fn column_order(&self) -> ColumnOrder {
        match &self.fast {
            Fast::Blocks(blocks) if self.lu.factorisations == 0 => {
                self.records_order.unwrap_or(blocks.a.column_order())
            }
            Fast::Condensed(lu) if self.lu.factorisations == 0 => lu.column_order(),
            _ => self.lu.column_order(),
        }
    }

    /// The order B's simplicial factors took on another thread
    /// ([`BorderedLu::exact_twin`]'s), reported by [`BorderedLu::column_order`]
    /// while B's own LU has not factorised: as it would have, had it taken
    /// the records' factorisations itself.
    pub fn records_take(&mut self, order: ColumnOrder) {
        self.records_order = Some(order);
    }

    /// Whether the last factorisation succeeded.
    pub fn factorised(&self) -> bool {
        self.blocks_active || self.lu.factorised()
    }

    /// Solve B z = rhs in place (n + 1 entries). Non-finite entries if B
    /// is singular after all (a block elimination that did not refine and
    /// B's own LU then finding it singular).
    pub fn solve(&mut self, rhs: &mut [f64]) {
        self.solve_with(rhs, false);
    }

    /// Solve A Z = F in place for the k columns of `rhs` (column-major,
    /// n×k), A being B's inner matrix, with whichever factors hold the last
    /// matrix, unrefined (a subspace iteration needs backward-stable
    /// solves, and measures its own residuals). A block elimination holds
    /// A's own LU: one k-column pass through it. B's own LU or its
    /// condensation hold only B; then the bordered identity: with
    /// B (w, ω) = (f, 0) and B (v, ν) = (0, 1),
    ///   A w + c ω = f,  A v + c ν = 0  ⇒  A (w − (ω/ν) v) = f,
    /// where ν = (B⁻¹)_{n+1,n+1} = det A / det B (Cramer), zero exactly
    /// where A is singular (a fold). (v, ν) is solved once per matrix.
    /// Returns false, `rhs` unspecified, when there are no factors or ν is
    /// zero or not finite (A singular to working precision through B).
    pub fn solve_inner_many(&mut self, rhs: &mut [f64], k: usize) -> bool {
        let n = self.n;
        assert_eq!(rhs.len(), n * k, "right-hand sides do not match A");
        if !self.factorised() {
            return false;
        }
        if let (true, Fast::Blocks(blocks)) = (self.blocks_active, &mut self.fast) {
            blocks.a.solve_many_unrefined(rhs, k);
            return true;
        }
        if !self.inner_known {
            let mut v = std::mem::take(&mut self.inner_column);
            v.fill(0.0);
            v[n] = 1.0;
            self.solve_whole_many(&mut v, 1);
            self.inner_column = v;
            self.inner_known = true;
        }
        let nu = self.inner_column[n];
        if !(nu.is_finite() && nu != 0.0) {
            return false;
        }
        let mut cols = std::mem::take(&mut self.inner_scratch);
        if cols.len() < (n + 1) * k {
            cols.resize((n + 1) * k, 0.0);
        }
        for (col, f) in cols.chunks_exact_mut(n + 1).zip(rhs.chunks_exact(n)) {
            col[..n].copy_from_slice(f);
            col[n] = 0.0;
        }
        self.solve_whole_many(&mut cols[..(n + 1) * k], k);
        let v = &self.inner_column[..n];
        for (col, z) in cols.chunks_exact(n + 1).zip(rhs.chunks_exact_mut(n)) {
            let ratio = col[n] / nu;
            for ((z, w), v) in z.iter_mut().zip(&col[..n]).zip(v) {
                *z = w - ratio * v;
            }
        }
        self.inner_scratch = cols;
        true
    }

    /// B Z = F in place for k columns of n + 1 with B's own LU or the
    /// condensation (not a block elimination), unrefined.
    fn solve_whole_many(&mut self, cols: &mut [f64], k: usize) {
        match &mut self.fast {
            Fast::Condensed(lu) if self.blocks_active => {
                // The condensation solves one column at a time.
                for col in cols.chunks_exact_mut(self.n + 1) {
                    lu.solve(col);
                }
            }
            _ => self.lu.solve_many_unrefined(cols, k),
        }
    }

    /// sign det B of the current factorisation (0 if B's own LU, called
    /// for by a block elimination, finds it singular).
    pub fn determinant_sign(&mut self) -> f64 {
        if let (true, Fast::Condensed(lu)) = (self.blocks_active, &mut self.fast) {
            return lu.determinant_sign();
        }
        if !self.factorise_whole() {
            return 0.0;
        }
        self.lu.determinant_sign_and_log().0
    }

    /// Whether B's own simplicial factors hold the last matrix (not a
    /// block elimination, not a condensation, not B's supernodal LU): its
    /// [`BorderedLu::determinant_sign`] and pivots are read off them.
    pub fn signs_in_hand(&self) -> bool {
        !self.blocks_active && self.lu.exact_in_hand()
    }

    /// Negative pivots of the current factors (see
    /// [`SparseLu::negative_pivots`]; B's own LU's).
    pub fn negative_pivots(&mut self) -> usize {
        if let (true, Fast::Condensed(lu)) = (self.blocks_active, &mut self.fast) {
            return lu.negative_pivots();
        }
        if !self.factorise_whole() {
            return 0;
        }
        self.lu.negative_pivots()
    }

    /// B's entries of the last matrix, in its pattern's order.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// A simplicial LU of B's pattern in B's column order (that of B's own
    /// LU once it has factorised; else the preferred one; else chosen on
    /// its first matrix): the determinant sign and pivots of
    /// [`BorderedLu::values`] taken elsewhere — on a second thread while
    /// this one goes on ([`crate::continuation::Options::overlap_records`])
    /// — exactly as [`BorderedLu::determinant_sign`] takes them here.
    pub fn exact_twin(&self) -> Result<SparseLu> {
        let mut lu = SparseLu::shared(self.lu.shared_pattern().clone(), self.structure.trailing + 1)?;
        lu.prefer_kind(LuKind::Simplicial);
        if self.lu.factorisations > 0 {
            lu.prefer(self.lu.column_order());
        } else if let Some(order) = self.preferred {
            lu.prefer(order);
        }
        Ok(lu)
    }

    /// Whether the last factorisation is a block elimination on A's
    /// supernodal LU ([`super::bordering`]).
    pub fn block_elimination(&self) -> bool {
        self.blocks_active && matches!(self.fast, Fast::Blocks(_))
    }

    /// Entries of L + U of the last factorisation (0 before the first;
    /// A's when a block elimination).
    pub fn fill(&self) -> usize {
        match &self.fast {
            Fast::Blocks(blocks) if self.blocks_active => blocks.a.fill(),
            Fast::Condensed(lu) if self.blocks_active => lu.fill(),
            _ => self.lu.fill(),
        }
    }

    /// Whether the columns are factorised in their natural order (chosen
    /// on the first matrix), not COLAMD's.
    pub fn natural_order(&self) -> bool {
        self.column_order() == ColumnOrder::Natural
    }

    /// Entries of B (A's pattern with the dense border).
    pub fn nnz(&self) -> usize {
        self.lu.pattern().nnz()
    }

    /// Numeric factorisations so far.
    pub fn factorisations(&self) -> usize {
        self.lu.factorisations
            + match &self.fast {
                Fast::Blocks(blocks) => blocks.a.factorisations,
                Fast::Condensed(lu) => lu.factorisations,
                _ => 0,
            }
    }

    /// The row and column scales of Ã = diag(row) B diag(col), n + 1 each.
    pub fn set_scales(&mut self, row: &[f64], col: &[f64]) {
        self.row_scale.copy_from_slice(row);
        self.col_scale.copy_from_slice(col);
    }

    /// (ÃᵀÃ)⁻¹ w = C⁻¹ B⁻¹ R⁻² B⁻ᵀ C⁻¹ w, in place (two solves), the locked
    /// pairs of [`BorderedLu::subspace_iteration`] projected out: Ã⁻ᵀ w =
    /// R⁻¹ B⁻ᵀ C⁻¹ w less its components along the `left` vectors, then
    /// Ã⁻¹ of that less its components along the `right` ones. With none
    /// locked R⁻² is applied at once, as before deflation existed (the
    /// monitor's digits, on which continuation paths depend, unchanged).
    fn inverse_normal(&mut self, w: &mut [f64], right: &[Vec<f64>], left: &[Vec<f64>], solves: &mut usize) {
        unscale(w, &self.col_scale);
        self.solve_with(w, true);
        self.between_solves(w, left);
        self.solve_with(w, false);
        unscale(w, &self.col_scale);
        project_out(w, right);
        *solves += 2;
    }

    /// [`BorderedLu::inverse_normal`] on two vectors, the same operations
    /// on each, their solves taken together where the factors allow
    /// ([`CondensedLu::solve_pair`]: each factor entry read once for both).
    fn inverse_normal_pair(
        &mut self,
        (v, w): (&mut [f64], &mut [f64]),
        right: &[Vec<f64>],
        left: &[Vec<f64>],
        solves: &mut usize,
    ) {
        unscale(v, &self.col_scale);
        unscale(w, &self.col_scale);
        self.solve_pair_with((v, w), true);
        self.between_solves(v, left);
        self.between_solves(w, left);
        self.solve_pair_with((v, w), false);
        for u in [v, w] {
            unscale(u, &self.col_scale);
            project_out(u, right);
        }
        *solves += 4;
    }

    /// Between the two solves of (ÃᵀÃ)⁻¹ w: R⁻², or R⁻¹, the locked `left`
    /// vectors out, R⁻¹ ([`BorderedLu::inverse_normal`]).
    fn between_solves(&self, w: &mut [f64], left: &[Vec<f64>]) {
        if left.is_empty() {
            for (a, r) in w.iter_mut().zip(&self.row_scale) {
                *a /= r * r;
            }
        } else {
            unscale(w, &self.row_scale);
            project_out(w, left);
            unscale(w, &self.row_scale);
        }
    }

    /// [`BorderedLu::solve_with`] on two right-hand sides: together by the
    /// condensation's factors, else one after the other.
    fn solve_pair_with(&mut self, (v, w): (&mut [f64], &mut [f64]), transpose: bool) {
        if let (true, Fast::Condensed(lu)) = (self.blocks_active, &mut self.fast) {
            lu.solve_pair(v, w, transpose);
            return;
        }
        self.solve_with(v, transpose);
        self.solve_with(w, transpose);
    }

    /// ε‖Ã‖_F: below it Ã is singular to working precision, and the
    /// singular values beside such a σ_1 cannot be resolved by solves with
    /// it — each solve's round-off, amplified by 1/σ_1 along a direction of
    /// its own, swamps them (the located point's vectors,
    /// [`BorderedLu::smallest_singular_vectors`], then come out wrong:
    /// callers take them beside the point).
    pub fn singular_floor(&self) -> f64 {
        f64::EPSILON * self.scaled_frobenius()
    }

    /// ‖Ã‖_F of the current matrix.
    fn scaled_frobenius(&self) -> f64 {
        let p = self.lu.pattern();
        // (No matrix assembled yet: its values are sized by the first.)
        if self.values.len() != p.nnz() {
            return 0.0;
        }
        let mut sum = 0.0;
        for j in 0..p.n {
            for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                let a = self.row_scale[p.row_idx[k]] * self.values[k] * self.col_scale[j];
                sum += a * a;
            }
        }
        sum.sqrt()
    }

    /// Ã v into w.
    fn scaled_mul(&self, v: &[f64], w: &mut [f64]) {
        let cv: Vec<f64> = v.iter().zip(&self.col_scale).map(|(a, c)| a * c).collect();
        self.lu.pattern().mul_vec(&self.values, &cv, w);
        for (a, r) in w.iter_mut().zip(&self.row_scale) {
            *a *= r;
        }
    }

    /// Smallest singular value of Ã by inverse iteration on ÃᵀÃ (a few
    /// steps from a fixed start; an estimate, good to a few digits, which
    /// is what a bifurcation monitor needs). `solves` counts the solves.
    pub fn smallest_singular_value(&mut self, solves: &mut usize) -> f64 {
        let m = self.n + 1;
        let mut v: Vec<f64> = (0..m).map(|i| 1.0 + 0.37 * ((i * 7919) % 101) as f64 / 101.0).collect();
        let mut sigma = f64::INFINITY;
        for _ in 0..8 {
            let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
            v.iter_mut().for_each(|a| *a /= norm);
            let mut w = v.clone();
            self.inverse_normal(&mut w, &[], &[], solves);
            // ‖(ÃᵀÃ)⁻¹ v‖ → 1/σ_min² for the dominant direction.
            let growth = w.iter().map(|a| a * a).sum::<f64>().sqrt();
            let next = 1.0 / growth.sqrt();
            let converged = (next - sigma).abs() <= 1e-3 * next;
            sigma = next;
            v = w;
            if converged {
                break;
            }
        }
        sigma
    }

    /// The k smallest singular values of Ã (ascending) and B's right
    /// singular vectors for them (x = C ṽ, ṽ unit in the Euclidean norm,
    /// n + 1 long), by subspace inverse iteration on ÃᵀÃ with a
    /// Rayleigh–Ritz step, to the Ritz values' relative tolerance `tol` or
    /// `max_iterations` (a monitor needs a few digits; the null vectors of
    /// a located point need many).
    pub fn smallest_singular_vectors(
        &mut self,
        k: usize,
        (tol, max_iterations): (f64, usize),
        start: Start,
        solves: &mut usize,
    ) -> (Vec<f64>, Vec<Vec<f64>>) {
        self.subspace_iteration(k, (tol, max_iterations), (Subspace::Vectors, start), solves)
    }

    /// [`BorderedLu::smallest_singular_vectors`] (`Vectors`), or the
    /// monitor's σ_min (`Monitor`: no deflation, σ_1's Ritz value to `tol`,
    /// or with [`Settle::All`] every Ritz value).
    ///
    /// Deflation. Where σ_1 is many orders below σ_2 (a located
    /// bifurcation: σ_1 ~ 1e-14), (ÃᵀÃ)⁻¹ weighs the null direction by
    /// 1/σ_1², and each solve's round-off, O(ε‖Ã‖/σ_1) in that direction,
    /// is amplified once more by the second solve: the other columns are
    /// swamped and their Ritz values never converge (a 2 % error in σ_2 in
    /// the tests, and the iteration cap spent). So the leading Ritz pairs
    /// that have converged and lie [`LOCK_GAP`] below the next value are
    /// locked: their right vectors v and left vectors u ∝ Ã⁻ᵀ v are
    /// projected out of every later solve's intermediate and result, which
    /// leaves the others' round-off at O(ε‖Ã‖/σ_next).
    ///
    /// The monitor reads σ_1 only, to four digits: it runs the plain
    /// iteration (no deflation) and stops when σ_1's Ritz value has
    /// settled; its second column is there to speed σ_1 up (the rate is
    /// (σ_1/σ_3)², not (σ_1/σ_2)², which is near 1 where two modes come
    /// close, as rods' bending pairs do).
    fn subspace_iteration(
        &mut self,
        k: usize,
        (tol, max_iterations): (f64, usize),
        (kind, start): (Subspace, Start),
        solves: &mut usize,
    ) -> (Vec<f64>, Vec<Vec<f64>>) {
        let m = self.n + 1;
        let previous = match start {
            Start::Fixed => vec![],
            Start::Previous => std::mem::take(&mut self.ritz),
        };
        let mut v: Vec<Vec<f64>> = previous.into_iter().filter(|p| p.len() == m).take(k).collect();
        v.extend(
            (v.len()..k).map(|c| (0..m).map(|i| (((i + 1) * (c + 3) * 7919) % 1009) as f64 / 1009.0 - 0.5).collect()),
        );
        orthonormalise(&mut v);
        // A Ritz value settles to within round-off of Ã's size, not below:
        // at a point singular to the last bit (σ_1 ~ 1e-17, a location by
        // Newton continuation) σ_1's Ritz value is noise, changing by a
        // tenth between iterations, and without this floor never counted
        // as converged, so never locked, and the others stayed swamped to
        // the cap. The monitor keeps its plain test (its digits steer
        // paths).
        let floor = match kind {
            Subspace::Vectors => self.singular_floor(),
            Subspace::Monitor(_) => 0.0,
        };
        // Locked pairs: right vectors, left vectors (unit, Euclidean).
        let (mut right, mut left): (Vec<Vec<f64>>, Vec<Vec<f64>>) = (vec![], vec![]);
        let mut sigma = vec![f64::INFINITY; k];
        for _ in 0..max_iterations {
            let mut w = v.clone();
            for pair in w.chunks_mut(2) {
                match pair {
                    [a, b] => self.inverse_normal_pair((a, b), &right, &left, solves),
                    [a] => self.inverse_normal(a, &right, &left, solves),
                    _ => {}
                }
            }
            let ka = v.len();
            // Rayleigh–Ritz on (ÃᵀÃ)⁻¹: G = Vᵀ W.
            let g = nalgebra::DMatrix::from_fn(ka, ka, |a, b| dot(&v[a], &w[b]));
            let eig = nalgebra::SymmetricEigen::new((&g + g.transpose()) * 0.5);
            let mut order: Vec<usize> = (0..ka).collect();
            order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
            let next: Vec<f64> = order.iter().map(|&i| 1.0 / eig.eigenvalues[i].max(1e-300).sqrt()).collect();
            // Rotate W into the Ritz basis, then orthonormalise.
            let mut rotated: Vec<Vec<f64>> = order
                .iter()
                .map(|&i| (0..m).map(|r| (0..ka).map(|c| w[c][r] * eig.eigenvectors[(c, i)]).sum()).collect())
                .collect();
            orthonormalise(&mut rotated);
            let active = &sigma[right.len()..];
            let done = |i: usize| (next[i] - active[i]).abs() <= tol * next[i].max(1e-300) + floor;
            let converged = match kind {
                Subspace::Monitor(Settle::First) => done(0),
                Subspace::Monitor(Settle::All) | Subspace::Vectors => (0..ka).all(done),
            };
            // Lock the leading cluster (one null vector, or two at a double
            // point) that has converged far below the next value.
            let lock = match kind {
                Subspace::Monitor(_) => 0,
                Subspace::Vectors => {
                    (1..ka).filter(|&l| (0..l).all(done) && next[l - 1] < LOCK_GAP * next[l]).max().unwrap_or(0)
                }
            };
            sigma.splice(right.len().., next.iter().copied());
            v = rotated;
            if converged {
                break;
            }
            for vi in v.drain(..lock) {
                let u = self.left_vector(&vi, &left, solves);
                right.push(vi);
                left.push(u);
            }
        }
        right.append(&mut v);
        let v = right;
        self.ritz.clone_from(&v);
        // The Ritz values of (ÃᵀÃ)⁻¹ lose the larger singular values to
        // round-off when the smallest are near zero (entries ~1/σ_min²):
        // measure each converged vector directly, σ_i = ‖Ã v_i‖.
        let mut w = vec![0.0; m];
        for (s, vi) in sigma.iter_mut().zip(&v) {
            self.scaled_mul(vi, &mut w);
            *s = dot(&w, &w).sqrt();
        }
        // Back to the unknowns' own units (x = C ṽ).
        let v = v.into_iter().map(|vi| vi.iter().zip(&self.col_scale).map(|(a, c)| a * c).collect()).collect();
        (sigma, v)
    }

    /// The left singular vector u ∝ Ã⁻ᵀ v of a locked right vector v
    /// (unit, orthogonal to the `left` already locked): one transposed
    /// solve, whose result is dominated by u/σ_1.
    fn left_vector(&mut self, v: &[f64], left: &[Vec<f64>], solves: &mut usize) -> Vec<f64> {
        let mut y: Vec<f64> = v.iter().zip(&self.col_scale).map(|(a, c)| a / c).collect();
        self.solve_with(&mut y, true);
        *solves += 1;
        for (a, r) in y.iter_mut().zip(&self.row_scale) {
            *a /= r;
        }
        project_out(&mut y, left);
        let norm = dot(&y, &y).sqrt();
        if norm > 0.0 {
            y.iter_mut().for_each(|a| *a /= norm);
        }
        y
    }

    /// σ_min signed by the alignment of its left and right singular
    /// vectors: near a real eigenvalue crossing zero, B v ≈ λ v, so the sign
    /// is sign(λ) and the function changes sign at every bifurcation,
    /// double ones included (where det B keeps its sign).
    pub fn signed_smallest_singular_value(&mut self, (start, settle): (Start, Settle), solves: &mut usize) -> f64 {
        // Four digits: the monitor looks for sign changes and dips.
        let (sigma, v) = self.subspace_iteration(2, (1e-4, 30), (Subspace::Monitor(settle), start), solves);
        let mut w = vec![0.0; self.n + 1];
        let scaled: Vec<f64> = v[0].iter().zip(&self.col_scale).map(|(a, c)| a / c).collect();
        self.scaled_mul(&scaled, &mut w);
        let align: f64 = w.iter().zip(&scaled).map(|(a, b)| a * b).sum();
        if align < 0.0 {
            -sigma[0]
        } else {
            sigma[0]
        }
    }
}

/// w entry by entry divided by `scale`.
fn unscale(w: &mut [f64], scale: &[f64]) {
    for (a, c) in w.iter_mut().zip(scale) {
        *a /= c;
    }
}

/// w less its components along the orthonormal `basis` (one Gram–Schmidt
/// sweep).
fn project_out(w: &mut [f64], basis: &[Vec<f64>]) {
    for u in basis {
        let c = dot(u, w);
        w.iter_mut().zip(u).for_each(|(a, b)| *a -= c * b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// B = [[2, 0, 1], [0, 3, 0], [1, 1, 0]] (A = diag(2, 3), c = (1, 0),
    /// r = (1, 1), d = 0): det B = −3 − 2 = −5 (cofactors, by hand), and
    /// B z = (3, 3, 2) has z = (1, 1, 1). Its singular values are those of
    /// nalgebra's SVD of the same matrix (the independent reference).
    #[test]
    fn bordered_solve_sign_and_singular_values() {
        let pattern = Pattern::from_entries(2, [(0, 0), (1, 1)]);
        let mut b = BorderedLu::new(&pattern).unwrap();
        b.factorise(&[2.0, 3.0], &[1.0, 0.0], &[1.0, 1.0], 0.0).unwrap();
        let mut z = vec![3.0, 3.0, 2.0];
        b.solve(&mut z);
        assert!(z.iter().all(|v| (v - 1.0).abs() < 1e-15), "{z:?}");
        assert_eq!(b.determinant_sign(), -1.0);
        let dense = nalgebra::Matrix3::new(2.0, 0.0, 1.0, 0.0, 3.0, 0.0, 1.0, 1.0, 0.0);
        let mut reference: Vec<f64> = dense.singular_values().iter().copied().collect();
        reference.sort_by(f64::total_cmp);
        let mut solves = 0;
        let (sigma, _) = b.smallest_singular_vectors(2, (1e-12, 200), Start::Fixed, &mut solves);
        for k in 0..2 {
            assert!((sigma[k] - reference[k]).abs() < 1e-10 * reference[2], "σ{k} {} vs {}", sigma[k], reference[k]);
        }
        assert!((b.smallest_singular_value(&mut solves) - reference[0]).abs() < 1e-2 * reference[0]);
        assert!(solves > 0);
    }

    /// B = diag(A, 1) factorised, A = Q diag(d) Qᵀ with Q from the QR of a
    /// fixed full matrix (so A is full and its singular values are |d|):
    /// (Q, A, B).
    fn rotated_diagonal(d: [f64; 4]) -> (nalgebra::Matrix4<f64>, nalgebra::Matrix4<f64>, BorderedLu) {
        let q =
            nalgebra::Matrix4::from_fn(|i, j| 1.0 / (1.0 + i as f64 + 2.0 * j as f64) + (i == j) as u8 as f64).qr().q();
        let pattern = Pattern::from_entries(4, (0..4).flat_map(|i| (0..4).map(move |j| (i, j))));
        let mut b = BorderedLu::new(&pattern).unwrap();
        let a = refactorise_rotated(&mut b, &q, d);
        (q, a, b)
    }

    /// B = diag(Q diag(d) Qᵀ, 1) factorised into `b` (its pattern full
    /// 4×4, as [`rotated_diagonal`]'s): A.
    fn refactorise_rotated(b: &mut BorderedLu, q: &nalgebra::Matrix4<f64>, d: [f64; 4]) -> nalgebra::Matrix4<f64> {
        let a = q * nalgebra::Matrix4::from_diagonal(&nalgebra::Vector4::from(d)) * q.transpose();
        let values: Vec<f64> = (0..4).flat_map(|j| (0..4).map(move |i| a[(i, j)])).collect();
        b.factorise(&values, &[0.0; 4], &[0.0; 4], 1.0).unwrap();
        a
    }

    /// At an (almost exactly) singular point — a located bifurcation — the
    /// null vector dominates (ÃᵀÃ)⁻¹ by 1/σ_1² and the round-off of every
    /// solve swamps the other directions unless they are deflated. B =
    /// diag(A, 1), A = Q diag(σ_1, 0.5, 0.7, 5) Qᵀ with σ_1 = 3e-16 (a
    /// quarter of [`BorderedLu::singular_floor`], about the least that is
    /// resolved: 1e-16 takes the cap, 1e-17 fails), 1e-14 and 1e-9: the
    /// three smallest singular values (σ_1, 0.5, 0.7) to 1e-9
    /// relative (the second and third) and the null vector to 1e-9, against
    /// the construction (nalgebra's SVD cannot resolve σ_1 = 1e-14 either).
    #[test]
    fn singular_values_beside_a_null_vector_are_resolved() {
        for s1 in [3e-16, 1e-14, 1e-9] {
            let (q, _, mut b) = rotated_diagonal([s1, 0.5, 0.7, 5.0]);
            let mut solves = 0;
            let (sigma, vectors) = b.smallest_singular_vectors(3, (1e-10, 30), Start::Fixed, &mut solves);
            assert!(sigma[0] < 1e-8, "σ_1 = {s1}: {sigma:?}");
            for (k, exact) in [(1, 0.5), (2, 0.7)] {
                assert!((sigma[k] - exact).abs() < 1e-9 * exact, "σ_1 = {s1}: σ{k} = {} vs {exact}", sigma[k]);
            }
            // The null vector: Q's first column (sign free), 0 on the border.
            let v = &vectors[0];
            let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            let along: f64 = (0..4).map(|i| v[i] * q[(i, 0)]).sum::<f64>() / norm;
            assert!((along.abs() - 1.0).abs() < 1e-9 && v[4].abs() < 1e-9 * norm, "σ_1 = {s1}: {v:?}");
            // Converged, not stopped by the cap (30 iterations × 3 columns
            // × 2 solves = 180, where the undeflated iteration ended).
            assert!(solves < 120, "σ_1 = {s1}: {solves} solves");
        }
    }

    /// A double null space (a double bifurcation point) is locked as one
    /// cluster: A = Q diag(1e-14, 2e-14, 0.5, 5) Qᵀ in B = diag(A, 1); the
    /// third value 0.5 to 1e-9, the two null vectors spanning Q's first two
    /// columns to 1e-9 (reference: the construction).
    #[test]
    fn a_double_null_space_is_deflated_as_one() {
        let (q, _, mut b) = rotated_diagonal([1e-14, 2e-14, 0.5, 5.0]);
        let mut solves = 0;
        let (sigma, vectors) = b.smallest_singular_vectors(3, (1e-10, 30), Start::Fixed, &mut solves);
        assert!(sigma[0] < 1e-8 && sigma[1] < 1e-8, "{sigma:?}");
        assert!((sigma[2] - 0.5).abs() < 1e-9 * 0.5, "{sigma:?}");
        for v in &vectors[..2] {
            let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            let inside: f64 =
                (0..2).map(|c| ((0..4).map(|i| v[i] * q[(i, c)]).sum::<f64>() / norm).powi(2)).sum::<f64>();
            assert!((inside - 1.0).abs() < 1e-9, "{v:?}: {inside}");
        }
        assert!(solves < 120, "{solves} solves");
    }

    /// The monitor's signed σ_min. B = diag(A, 1) with A = Q diag(2, μ,
    /// 0.07, 5) Qᵀ ([`rotated_diagonal`]): σ_min = |μ| (0.05, 0.069), with the
    /// sign of the eigenvalue μ (B v = μ v), and the next value 0.07 close
    /// enough that an unconverged iterate would show. Reference:
    /// nalgebra's SVD of the same matrix.
    #[test]
    fn signed_smallest_singular_value_has_the_eigenvalues_sign() {
        // ±0.069: σ_1 within 1.5 % of σ_2 (a bending pair), which the
        // second column carries.
        for mu in [-0.05, 0.05, -0.069, 0.069] {
            let (_, a, mut b) = rotated_diagonal([2.0, mu, 0.07, 5.0]);
            let reference = a.singular_values().min();
            for settle in [Settle::First, Settle::All] {
                let sigma = b.signed_smallest_singular_value((Start::Fixed, settle), &mut 0);
                assert_eq!(sigma.signum(), mu.signum(), "μ = {mu}, {settle:?}: σ = {sigma}");
                assert!(
                    (sigma.abs() - reference).abs() < 1e-4 * reference,
                    "μ = {mu}, {settle:?}: σ = {sigma}, SVD {reference}"
                );
            }
        }
    }

    /// A location's trial points: B(μ) = diag(A(μ), 1), A(μ) = Q diag(2, μ,
    /// 0.07, 5) Qᵀ, with μ stepping through zero as a bracket's trials do.
    /// Started from the previous call's Ritz vectors the monitor gives the
    /// signed σ_min of a fixed start — sign, and |σ| to its 1e-4 against
    /// nalgebra's SVD of A (the independent reference) — in fewer solves.
    #[test]
    fn a_warm_start_gives_the_fixed_starts_monitor_in_fewer_solves() {
        // Two LUs: each call keeps its Ritz vectors for the next.
        let (q, _, mut b_fixed) = rotated_diagonal([2.0, 0.05, 0.07, 5.0]);
        let (_, _, mut b_warm) = rotated_diagonal([2.0, 0.05, 0.07, 5.0]);
        let (mut fixed, mut warm) = (0, 0);
        b_warm.signed_smallest_singular_value((Start::Fixed, Settle::First), &mut 0);
        for mu in [0.03, -0.02, 0.004, -0.001, 2e-4, -3e-5] {
            let a = refactorise_rotated(&mut b_fixed, &q, [2.0, mu, 0.07, 5.0]);
            refactorise_rotated(&mut b_warm, &q, [2.0, mu, 0.07, 5.0]);
            let reference = a.singular_values().min();
            let s_fixed = b_fixed.signed_smallest_singular_value((Start::Fixed, Settle::First), &mut fixed);
            let s_warm = b_warm.signed_smallest_singular_value((Start::Previous, Settle::First), &mut warm);
            for s in [s_fixed, s_warm] {
                assert_eq!(s.signum(), mu.signum(), "μ = {mu}: σ = {s}");
                assert!((s.abs() - reference).abs() < 1e-4 * reference, "μ = {mu}: σ = {s}, SVD {reference}");
            }
        }
        println!("warm {warm} solves, fixed {fixed}");
        assert!(warm < fixed, "warm {warm} solves, fixed {fixed}");
    }
}

#[cfg(test)]
mod block_tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// The bordered pattern is written from A's without normalising it: a
    /// pattern whose rows break `Pattern`'s invariant (its fields are
    /// public) is refused with ErrInvalidDimension, not built wrong; the
    /// same matrix in order is accepted (reference: `Pattern::from_entries`).
    #[test]
    fn a_pattern_out_of_order_is_refused() {
        let entries = [(0, 0), (2, 0), (1, 1), (0, 2), (2, 2)];
        let good = Pattern::from_entries(3, entries);
        assert!(BorderedLu::new(&good).is_ok());
        for rows in [vec![2, 0, 1, 0, 2], vec![0, 0, 1, 0, 2], vec![0, 3, 1, 0, 2]] {
            let bad = Pattern { n: 3, col_ptr: good.col_ptr.clone(), row_idx: rows.clone() };
            let err = BorderedLu::new(&bad).err().map(|e| e.status);
            assert_eq!(err, Some(Status::ErrInvalidDimension), "rows {rows:?}");
        }
        // Values of the wrong lengths are refused, not sliced past their end;
        // before any matrix, the singular-value floor is zero.
        let mut lu = BorderedLu::new(&good).unwrap();
        assert_eq!(lu.singular_floor(), 0.0);
        let (a, c) = (vec![2.0, 1.0, 1.0, 1.0, 3.0], vec![1.0; 3]);
        for (a, c, r) in [(&a[..4], &c[..], &c[..]), (&a[..], &c[..2], &c[..]), (&a[..], &c[..], &c[..2])] {
            let err = lu.factorise(a, c, r, 0.0).err().map(|e| e.status);
            assert_eq!(err, Some(Status::ErrInvalidDimension));
            let err = lu.factorise_exact(a, c, r, 0.0).err().map(|e| e.status);
            assert_eq!(err, Some(Status::ErrInvalidDimension));
        }
        assert!(lu.factorise(&a, &c, &c, 0.0).is_ok());
    }

    fn random(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    }

    /// A random band of half-width `hw` (n×n, entries uniform in
    /// [−½, ½)) with a random dense border (c, r) and corner d = 0.3: the
    /// matrices of the tests below.
    struct Banded {
        pattern: Pattern,
        a: Vec<f64>,
        c: Vec<f64>,
        r: Vec<f64>,
        d: f64,
    }

    fn banded(n: usize, hw: usize, seed: u64) -> Banded {
        let pattern = Pattern::from_entries(
            n,
            (0..n).flat_map(|i| (i.saturating_sub(hw)..(i + hw + 1).min(n)).map(move |j| (i, j))),
        );
        let mut seed = seed;
        let a: Vec<f64> = (0..pattern.nnz()).map(|_| random(&mut seed)).collect();
        let c: Vec<f64> = (0..n).map(|_| random(&mut seed)).collect();
        let r: Vec<f64> = (0..n).map(|_| random(&mut seed)).collect();
        Banded { pattern, a, c, r, d: 0.3 }
    }

    /// A alone, dense.
    fn dense_inner(m: &Banded) -> DMatrix<f64> {
        let n = m.pattern.n;
        let mut dense = DMatrix::zeros(n, n);
        for j in 0..n {
            for k in m.pattern.col_ptr[j]..m.pattern.col_ptr[j + 1] {
                dense[(m.pattern.row_idx[k], j)] = m.a[k];
            }
        }
        dense
    }

    /// A wide random band (n = 800, half-width 60: ~150 AᵀA-factor
    /// entries per column, so A takes supernodal factors and B is solved by
    /// block elimination) with a dense border, against nalgebra's dense LU
    /// of B (the reference): solves and transposed solves to 1e-9 relative,
    /// the determinant's sign (from B's own LU, called for by the request).
    /// Then A made nearly singular (one column scaled by 1e-13: a fold,
    /// where B stays regular): the refined block elimination, or B's own LU
    /// when it does not refine, still solves to 1e-9.
    #[test]
    fn block_elimination_matches_dense_lu() {
        let n = 800;
        let Banded { pattern, mut a, c, r, d } = banded(n, 60, 77);
        for case in ["regular", "near-singular A"] {
            if case == "near-singular A" {
                let j = n / 2;
                for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                    a[k] *= 1e-13;
                }
            }
            let mut dense = DMatrix::zeros(n + 1, n + 1);
            for j in 0..n {
                for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                    dense[(pattern.row_idx[k], j)] = a[k];
                }
                dense[(j, n)] = c[j];
                dense[(n, j)] = r[j];
            }
            dense[(n, n)] = d;
            let mut lu = BorderedLu::new(&pattern).unwrap();
            lu.factorise(&a, &c, &r, d).unwrap();
            if case == "regular" {
                assert!(lu.block_elimination(), "A should take supernodal factors");
            }
            let f: Vec<f64> = (0..=n).map(|i| (i as f64 * 0.21).sin()).collect();
            let dense_lu = dense.clone().lu();
            let reference = dense_lu.solve(&DVector::from_vec(f.clone())).unwrap();
            let reference_t = dense.transpose().lu().solve(&DVector::from_vec(f.clone())).unwrap();
            let scale = reference.amax().max(reference_t.amax());
            let mut z = f.clone();
            lu.solve(&mut z);
            let err = z.iter().zip(reference.iter()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(err < 1e-9 * scale, "{case}: solve error {err:e} (scale {scale:e})");
            let mut zt = f.clone();
            lu.solve_with(&mut zt, true);
            let err = zt.iter().zip(reference_t.iter()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(err < 1e-9 * scale, "{case}: transposed solve error {err:e}");
            assert_eq!(lu.determinant_sign(), dense_lu.determinant().signum(), "{case}");
        }
    }

    /// solve_inner_many (A Z = F for 5 columns) against nalgebra's dense
    /// LU of A itself (the reference, independent of B and its border), in
    /// each way B can be factorised: block elimination (A's supernodal LU,
    /// the 800 × half-width 60 band above); B's own simplicial LU (the same
    /// matrix, simplicial preferred; then the bordered identity through
    /// B); the same B's own LU after a determinant request took over from
    /// the block elimination; and the condensation (a half-width-2 band of
    /// 210 with private blocks {7m+2, 7m+3, 7m+4}, which no other block's
    /// rows or columns reach). Tolerance 1e-10 of max|Z|: unrefined solves
    /// of these random matrices measured ≤ 4e-14 of max|Z|.
    #[test]
    fn inner_solves_match_dense_inverse() {
        let k = 5;
        let check = |lu: &mut BorderedLu, m: &Banded, case: &str| {
            let n = m.pattern.n;
            let f: Vec<f64> = (0..n * k).map(|i| (i as f64 * 0.37).sin() + 0.1 * (i % 7) as f64).collect();
            let reference = dense_inner(m).lu().solve(&DMatrix::from_column_slice(n, k, &f)).unwrap();
            let mut z = f.clone();
            assert!(lu.solve_inner_many(&mut z, k), "{case}: solve refused");
            let scale = reference.amax();
            let err = z.iter().zip(reference.iter()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            println!("{case}: max error {:.1e} of max|Z| {scale:.1e}", err);
            assert!(err < 1e-10 * scale, "{case}: error {err:e} (scale {scale:e})");
        };
        let wide = banded(800, 60, 77);
        let mut lu = BorderedLu::new(&wide.pattern).unwrap();
        lu.factorise(&wide.a, &wide.c, &wide.r, wide.d).unwrap();
        assert!(lu.block_elimination());
        check(&mut lu, &wide, "block elimination");
        lu.determinant_sign();
        assert!(!lu.block_elimination());
        check(&mut lu, &wide, "B's own LU after a determinant");
        let mut lu = BorderedLu::new(&wide.pattern).unwrap();
        lu.prefer_kind(LuKind::Simplicial);
        lu.factorise(&wide.a, &wide.c, &wide.r, wide.d).unwrap();
        assert!(!lu.block_elimination() && !lu.last_condensed());
        check(&mut lu, &wide, "B's own LU");
        let narrow = banded(210, 2, 5);
        let blocks: Vec<Vec<usize>> = (0..30).map(|m| (7 * m + 2..7 * m + 5).collect()).collect();
        let mut lu = BorderedLu::with_private_blocks(&narrow.pattern, 0, &blocks).unwrap();
        lu.factorise(&narrow.a, &narrow.c, &narrow.r, narrow.d).unwrap();
        assert!(lu.last_condensed(), "the condensation should hold B");
        check(&mut lu, &narrow, "condensation");
    }

    /// B for `m` as one dense matrix (the reference of the kept-structure
    /// test).
    fn dense_bordered(m: &Banded) -> DMatrix<f64> {
        let n = m.pattern.n;
        let mut dense = DMatrix::zeros(n + 1, n + 1);
        dense.view_mut((0, 0), (n, n)).copy_from(&dense_inner(m));
        for j in 0..n {
            dense[(j, n)] = m.c[j];
            dense[(n, j)] = m.r[j];
        }
        dense[(n, n)] = m.d;
        dense
    }

    /// Two bordered LUs of one pattern share a kept structure (the count
    /// of kept structures does not grow) and stay independent: factorised
    /// on two different matrices, then solved in turn, each gives bitwise
    /// the solves of an LU built afresh after the kept structures are
    /// forgotten (the reference), and each matches nalgebra's dense LU of B
    /// to 1e-10 of max|z|. Cases: a band of 210 with private blocks
    /// {7k+2, 7k+3, 7k+4} (the kept system of 121 unknowns dense), a band
    /// of 700 with 100 such blocks (401 kept: the kept system's sparse LU
    /// on the shared pattern), and no blocks (B's own LU). A pattern one
    /// entry larger, another trailing count or no blocks each take a
    /// structure of their own; at most KEPT_STRUCTURES are kept. In a
    /// thread of its own: the count is the thread's.
    #[test]
    fn a_kept_structure_factorises_as_a_fresh_one() {
        std::thread::spawn(|| {
            type Solved = (Vec<f64>, Vec<f64>, f64, bool);
            let run = |lu: &mut BorderedLu, m: &Banded| {
                lu.factorise(&m.a, &m.c, &m.r, m.d).unwrap();
            };
            let solve = |lu: &mut BorderedLu, m: &Banded| -> Solved {
                let f: Vec<f64> = (0..=m.pattern.n).map(|i| (i as f64 * 0.3).cos()).collect();
                let (mut z, mut zt) = (f.clone(), f.clone());
                lu.solve(&mut z);
                lu.solve_with(&mut zt, true);
                let dense = dense_bordered(m);
                let reference = dense.clone().lu().solve(&DVector::from_vec(f.clone())).unwrap();
                let reference_t = dense.transpose().lu().solve(&DVector::from_vec(f)).unwrap();
                let scale = reference.amax().max(reference_t.amax());
                let err = z.iter().zip(reference.iter()).chain(zt.iter().zip(reference_t.iter()));
                let err = err.map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                assert!(err < 1e-10 * scale, "solve error {err:e} (scale {scale:e})");
                (z, zt, lu.determinant_sign(), lu.last_condensed())
            };
            let other_values = |m: &Banded| Banded {
                pattern: m.pattern.clone(),
                a: m.a.iter().enumerate().map(|(k, v)| v + 0.01 * (k % 5) as f64).collect(),
                c: m.c.clone(),
                r: m.r.clone(),
                d: 0.5,
            };
            let build =
                |m: &Banded, blocks: &[Vec<usize>]| BorderedLu::with_private_blocks(&m.pattern, 0, blocks).unwrap();
            let block_sets =
                |count: usize| (0..count).map(|k| (7 * k + 2..7 * k + 5).collect()).collect::<Vec<Vec<usize>>>();
            for (n, blocks, condensed) in
                [(210, block_sets(30), true), (700, block_sets(100), true), (210, vec![], false)]
            {
                let (m1, blocks) = (banded(n, 2, 5), blocks);
                let m2 = other_values(&m1);
                forget_kept_structures();
                let (mut lu1, mut lu2) = (build(&m1, &blocks), build(&m1, &blocks));
                assert_eq!(kept_structures(), 1, "n = {n}: the second LU should take the first's structure");
                run(&mut lu1, &m1);
                run(&mut lu2, &m2);
                let (s1, s2) = (solve(&mut lu1, &m1), solve(&mut lu2, &m2));
                assert_eq!(s1.3, condensed, "n = {n}: condensed");
                forget_kept_structures();
                for (m, kept) in [(&m1, s1), (&m2, s2)] {
                    let mut fresh = build(m, &blocks);
                    run(&mut fresh, m);
                    assert_eq!(solve(&mut fresh, m), kept, "n = {n}: kept and fresh LUs differ");
                }
            }
            // Structures of their own: no blocks, another trailing count, one
            // entry more ((0, 209), both kept).
            let (m, blocks) = (banded(210, 2, 5), block_sets(30));
            forget_kept_structures();
            build(&m, &blocks);
            BorderedLu::new(&m.pattern).unwrap();
            assert_eq!(kept_structures(), 2);
            BorderedLu::with_private_blocks(&m.pattern, 1, &blocks).unwrap();
            assert_eq!(kept_structures(), 3);
            let mut entries: Vec<(usize, usize)> = (0..210)
                .flat_map(|j| (m.pattern.col_ptr[j]..m.pattern.col_ptr[j + 1]).map(move |k| (k, j)))
                .map(|(k, j)| (m.pattern.row_idx[k], j))
                .collect();
            entries.push((0, 209));
            let pattern = Pattern::from_entries(210, entries.iter().copied());
            let a = (0..210)
                .flat_map(|j| (pattern.col_ptr[j]..pattern.col_ptr[j + 1]).map(move |k| (k, j)))
                .map(|(k, j)| m.pattern.position(pattern.row_idx[k], j).map_or(0.7, |p| m.a[p]))
                .collect();
            let larger = Banded { pattern, a, c: m.c.clone(), r: m.r.clone(), d: m.d };
            let mut lu = build(&larger, &blocks);
            assert_eq!(kept_structures(), 4);
            run(&mut lu, &larger);
            assert!(solve(&mut lu, &larger).3);
            for seed in 0..2 * KEPT_STRUCTURES as u64 {
                BorderedLu::new(&banded(20 + seed as usize, 1, seed).pattern).unwrap();
            }
            assert_eq!(kept_structures(), KEPT_STRUCTURES);
        })
        .join()
        .unwrap();
    }
}

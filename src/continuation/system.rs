//! A global system assembled from polynomial kernels (blocks): each block
//! is a recorded [`Tape`] whose inputs are global unknowns, Λ or fixed
//! parameters, and whose outputs add into global equations. Models (a rod's
//! elements and boundary conditions) describe themselves as blocks; this
//! type turns them into a [`Problem`] and a [`SeriesProblem`]: residual,
//! sparse Jacobian (pattern from the tapes' structural dependencies, values
//! by forward mode per block) and Taylor coefficients.
//!
//! A block may also carry its kernel compiled ([`LaneKernel`]): the same
//! polynomial as its tape, run as native code on [`LANES`] blocks at once.
//! Blocks whose kernels are compatible (same code; per-lane constants may
//! differ, as a charged rod's elements' stiffenings do) are then batched
//! and evaluated by it; the tape is kept for the structure (the Jacobian's
//! pattern, the degree) and as the reference the compiled kernel is
//! tested against.

use super::{Problem, SeriesProblem};
use crate::kept::Recent;
use crate::linalg::sparse::{group_by_key, ColumnWriter, Pattern};
use crate::taylor::batch::{
    eval_lanes, give_back, grow_pooled, jacobian_lanes, BatchJacobianWork, BatchTaylorWork, Lanes, LANES,
};
use crate::taylor::{JacobianWork, Tape, TaylorWork};
use std::any::Any;
use std::sync::Arc;

/// What feeds one input of a block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Slot {
    /// Global unknown x_i.
    Unknown(usize),
    /// The load parameter Λ.
    Lambda,
    /// A fixed value (element length, load direction, …).
    Param(f64),
}

impl Slot {
    /// This input's Taylor coefficient of an order p ≥ 1, from the
    /// unknowns' (`xp`) and Λ's (`lambda_p`): a fixed value's is 0.
    fn series_coefficient(self, xp: &[f64], lambda_p: f64) -> f64 {
        match self {
            Slot::Unknown(g) => xp[g],
            Slot::Lambda => lambda_p,
            Slot::Param(_) => 0.0,
        }
    }
}

/// One kernel instance.
#[derive(Clone, Debug)]
pub struct Block {
    pub tape: Arc<Tape>,
    pub inputs: Vec<Slot>,
    /// Global equation each output adds into.
    pub rows: Vec<usize>,
    /// The tape's polynomial compiled, if the model has it (evaluated in
    /// its place; the tape remains the structure).
    pub kernel: Option<Arc<dyn LaneKernel>>,
}

impl Block {
    /// A block evaluated by its tape alone.
    pub fn new(tape: Arc<Tape>, inputs: Vec<Slot>, rows: Vec<usize>) -> Self {
        Block { tape, inputs, rows, kernel: None }
    }
}

/// A block's kernel compiled: it computes what the block's tape computes
/// (values, local Jacobian, Taylor series and their tangents) on
/// [`LANES`] blocks at once.
pub trait LaneKernel: Send + Sync + std::fmt::Debug + Any {
    /// Whether `other` runs the same code (and so can share a batch).
    fn compatible(&self, other: &dyn LaneKernel) -> bool;
    /// The evaluator of a batch of `members` (1..=LANES, each compatible
    /// with `self`, lane l for members[l]; unused lanes compute on
    /// whatever their inputs hold).
    fn batch(&self, members: &[&dyn LaneKernel]) -> Box<dyn LaneBatch>;
    fn as_any(&self) -> &dyn Any;
}

/// The evaluations of [`LaneKernel`] on one batch, lane arrays in the
/// tape's input and output order; as [`eval_lanes`], [`jacobian_lanes`]
/// and [`BatchTaylorWork`] (the local Jacobian row-major, outputs ×
/// inputs: its structural entries — [`Tape::dependencies`] — are read,
/// the others may hold anything).
pub trait LaneBatch: Send + Sync + std::fmt::Debug {
    fn eval(&mut self, x: &[Lanes], out: &mut [Lanes]);
    fn jacobian(&mut self, x: &[Lanes], out: &mut [Lanes], jac: &mut [Lanes]);
    fn series_begin(&mut self, x0: &[Lanes], max_order: usize);
    fn series_order(&mut self, p: usize, xp: &[Lanes], out: &mut [Lanes]);
    fn series_tangent_order(&mut self, p: usize, wp: &[Lanes], out: &mut [Lanes]);
}

/// Per-block evaluation storage.
#[derive(Clone, Debug, Default)]
struct BlockWork {
    local_in: Vec<f64>,
    local_out: Vec<f64>,
    /// The local Jacobian (outputs × inputs, row-major), sized at its first
    /// use: a block whose Jacobian comes from its batch never needs one.
    local_jac: Vec<f64>,
    taylor: TaylorWork,
}

/// A system's pattern and where each block's entries go in it: a function
/// of the blocks' structure alone (their tapes' dependencies, which inputs
/// are which unknowns, their rows), so the systems a sweep rebuilds with
/// new loads or laws on one mesh share it ([`structure`]).
#[derive(Debug)]
struct Structure {
    pattern: Pattern,
    /// Per block, the pattern position of each (output k, input j) the
    /// tape says output k depends on, in the order of
    /// [`Tape::dependencies`] (outputs in turn), or u32::MAX (Λ,
    /// params): one entry per structural nonzero, not outputs × inputs
    /// (32 bits: half what the Jacobian's scatter streams).
    positions: Vec<Vec<u32>>,
    /// What it was built from: per block, its tape (for its
    /// dependencies), the unknown behind each input (None for Λ and
    /// params) and its rows.
    key: Vec<BlockKey>,
}

/// A block's part of a [`Structure`]'s key: tape, input unknowns, rows.
type BlockKey = (Arc<Tape>, Vec<Option<usize>>, Vec<usize>);

impl Structure {
    /// Whether `blocks` of an n-unknown system have the structure this
    /// was built from.
    fn fits(&self, n: usize, blocks: &[Block]) -> bool {
        self.pattern.n == n
            && self.key.len() == blocks.len()
            && self.key.iter().zip(blocks).all(|((tape, unknowns, rows), b)| {
                *rows == b.rows
                    && unknowns.len() == b.inputs.len()
                    && unknowns.iter().zip(&b.inputs).all(|(&u, s)| u == unknown(s))
                    && tape.same_dependencies(&b.tape)
            })
    }

    /// Column by column: each column's rows come from the blocks that read
    /// its unknown (a rod's column: one element, or two at a node), through
    /// each block tape's dependencies by input (computed once per distinct
    /// tape: a rod's elements share one). Every structural entry lands in
    /// its final place once — no list of all entries, no counting sort —
    /// and a column's rows arrive sorted unless two blocks' rows interleave
    /// (then that column alone is sorted). The pattern is that of
    /// [`Pattern::with_positions_and_diagonal`] on the blocks' entries.
    fn build(n: usize, blocks: &[Block]) -> Self {
        assert!(n < u32::MAX as usize, "system too large for 32-bit rows");
        let mut covered = vec![false; n];
        for b in blocks {
            assert_eq!(b.inputs.len(), b.tape.inputs(), "block inputs do not match its tape");
            assert_eq!(b.rows.len(), b.tape.outputs(), "block rows do not match its tape");
            for &row in &b.rows {
                assert!(row < n, "block row {row} outside a {n}-unknown system");
                covered[row] = true;
            }
            for s in &b.inputs {
                if let Slot::Unknown(c) = *s {
                    assert!(c < n, "block input unknown {c} outside a {n}-unknown system");
                }
            }
        }
        if let Some(row) = covered.iter().position(|c| !c) {
            panic!("equation {row} receives no block output");
        }
        // (block, input) of each column's readers, in block order.
        let (start, readers) = group_by_key(
            n,
            blocks.iter().enumerate().flat_map(|(e, b)| {
                b.inputs.iter().enumerate().filter_map(move |(j, s)| unknown(s).map(|c| (c, (e as u32, j as u32))))
            }),
        );
        // Each distinct tape's dependencies by input.
        let mut tapes: Vec<(&Tape, ByInput)> = Vec::new();
        let which: Vec<usize> = blocks
            .iter()
            .map(|b| match tapes.iter().position(|(t, _)| std::ptr::eq(*t, &*b.tape)) {
                Some(t) => t,
                None => {
                    tapes.push((&b.tape, ByInput::new(&b.tape)));
                    tapes.len() - 1
                }
            })
            .collect();
        // Blocks whose rows strictly increase: their outputs' rows in a
        // column come in order.
        let increasing: Vec<bool> = blocks.iter().map(|b| b.rows.windows(2).all(|w| w[0] < w[1])).collect();
        let mut positions: Vec<Vec<u32>> = which.iter().map(|&t| vec![u32::MAX; tapes[t].1.entries.len()]).collect();
        let unknown_entries: usize =
            readers.iter().map(|&(e, j)| tapes[which[e as usize]].1.of(j as usize).len()).sum();
        assert!(unknown_entries + n < u32::MAX as usize, "system too large for 32-bit positions");
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(unknown_entries + n);
        col_ptr.push(0);
        // A column's (row, block, index in the block's dependency order).
        let mut column: Vec<(u32, u32, u32)> = Vec::new();
        for c in 0..n {
            let readers = &readers[start[c]..start[c + 1]];
            // One block reads the column and its rows increase (a rod's
            // stage unknowns): the column's rows are that block's, in
            // order (no gather into a list, no sort).
            if let [(e, j)] = *readers {
                let (e, j) = (e as usize, j as usize);
                if increasing[e] {
                    let rows = &blocks[e].rows;
                    let at = &mut positions[e];
                    let mut column = ColumnWriter::new(&row_idx, c, true);
                    for &(k, d) in tapes[which[e]].1.of(j) {
                        at[d as usize] = column.push_new(&mut row_idx, rows[k as usize]) as u32;
                    }
                    column.finish(&mut row_idx);
                    col_ptr.push(row_idx.len());
                    continue;
                }
            }
            column.clear();
            for &(e, j) in readers {
                let rows = &blocks[e as usize].rows;
                let by_input = &tapes[which[e as usize]].1;
                column.extend(by_input.of(j as usize).iter().map(|&(k, d)| (rows[k as usize] as u32, e, d)));
            }
            if column.windows(2).any(|w| w[0].0 > w[1].0) {
                column.sort_unstable();
            }
            let mut writer = ColumnWriter::new(&row_idx, c, true);
            for &(i, e, d) in &column {
                positions[e as usize][d as usize] = writer.push(&mut row_idx, i as usize) as u32;
            }
            writer.finish(&mut row_idx);
            col_ptr.push(row_idx.len());
        }
        let key =
            blocks.iter().map(|b| (b.tape.clone(), b.inputs.iter().map(unknown).collect(), b.rows.clone())).collect();
        Structure { pattern: Pattern { n, col_ptr, row_idx }, positions, key }
    }
}

/// A tape's dependencies by input: for input j, each output k that depends
/// on it with the entry's index in [`Tape::dependencies`] order (outputs
/// in turn), k increasing.
struct ByInput {
    start: Vec<usize>,
    entries: Vec<(u32, u32)>,
}

impl ByInput {
    fn new(tape: &Tape) -> Self {
        let in_order =
            (0..tape.outputs()).flat_map(|k| tape.dependencies(k).iter().map(move |&j| (j as usize, k as u32)));
        let (start, entries) = group_by_key(tape.inputs(), in_order.enumerate().map(|(d, (j, k))| (j, (k, d as u32))));
        ByInput { start, entries }
    }

    fn of(&self, j: usize) -> &[(u32, u32)] {
        &self.entries[self.start[j]..self.start[j + 1]]
    }
}

/// The unknown an input slot reads (None: Λ or a parameter).
fn unknown(slot: &Slot) -> Option<usize> {
    match *slot {
        Slot::Unknown(g) => Some(g),
        Slot::Lambda | Slot::Param(_) => None,
    }
}

/// Structures kept on this thread: at most [`KEPT_STRUCTURES`], the least
/// recently used dropped first, each of at most [`KEPT_ENTRIES`] pattern
/// entries (~12 bytes each with the positions: ≤ 1.6 MB apiece; a larger
/// system's set-up is small beside its solves).
const KEPT_STRUCTURES: usize = 8;
const KEPT_ENTRIES: usize = 1 << 17;

thread_local! {
    static STRUCTURES: Recent<Structure> = const { Recent::new(KEPT_STRUCTURES) };
}

/// Drop the structures kept on this thread, the systems' and the
/// bordered tangents' ([`crate::linalg::bordered::forget_kept_structures`]):
/// their memory back, or a benchmark's first set-up. The element tapes a
/// rod records stay.
pub fn forget_kept_structures() {
    let _ = STRUCTURES.try_with(|kept| kept.clear());
    crate::linalg::bordered::forget_kept_structures();
}

/// System structures kept on this thread.
#[cfg(test)]
fn kept_structures() -> usize {
    STRUCTURES.with(|kept| kept.len())
}

/// The structure of `blocks`, kept or built. Finding it compares each
/// block's rows and input unknowns, and its tape's dependencies with the
/// kept one's unless they are the same tape (a rod's elements share the
/// thread's recorded tape; a tape recorded anew, for another law, is
/// compared whole for each block: O(entries) then, still without the
/// counting sort and scatter of a build, a third of a rod's set-up).
fn structure(n: usize, blocks: &[Block]) -> Arc<Structure> {
    if let Some(s) = STRUCTURES.try_with(|kept| kept.find(|s| s.fits(n, blocks))).ok().flatten() {
        return s;
    }
    let s = Arc::new(Structure::build(n, blocks));
    if s.pattern.nnz() <= KEPT_ENTRIES {
        let _ = STRUCTURES.try_with(|kept| kept.keep(s.clone()));
    }
    s
}

/// Blocks whose residuals, Jacobians and Taylor series are taken
/// together: a rod's elements, [`LANES`] at a time, by their compiled
/// kernel, or when they share a tape and have none, by the tape
/// ([`BatchTaylorWork`], [`jacobian_lanes`]: values and Jacobians bitwise
/// those of the blocks one by one).
#[derive(Debug)]
struct Batch {
    /// The blocks, one per lane (1..=LANES; unused lanes compute on zeros).
    blocks: Vec<usize>,
    engine: Engine,
    inputs: Vec<Lanes>,
    outputs: Vec<Lanes>,
    /// Local Jacobians of the lanes (outputs × inputs; the first that many
    /// entries of an array from the thread's pool, which may be longer).
    local_jac: Vec<Lanes>,
}

/// A system is often built for one solve (a sweep makes one per point): a
/// batch's local Jacobian (~110 kB for a Gauss(3) element's 68 inputs and
/// 52 outputs, four lanes) is returned to the thread's pool of lane arrays
/// ([`crate::taylor::batch::grow_pooled`]), so that the next system takes
/// it warm instead of faulting in fresh pages of a heap the allocator had
/// trimmed.
impl Drop for Batch {
    fn drop(&mut self) {
        give_back(std::mem::take(&mut self.local_jac));
    }
}

/// How a batch is evaluated. Values and Jacobians: by the compiled kernel
/// when the blocks have one. Taylor series: by the batched tape when every
/// lane shares one (the interpreter, vectorised over lanes, is faster
/// there: its per-op dispatch is small beside the O(p) Cauchy products,
/// and the compiled series reloads its arena at every op —
/// benches/rod_kernels.rs), else by the compiled kernel (lanes of
/// different laws: the alternative is one scalar tape per block).
#[derive(Debug)]
struct Engine {
    compiled: Option<Box<dyn LaneBatch>>,
    /// Present when every lane runs the same tape.
    taylor: Option<BatchTaylorWork>,
    jacobian: BatchJacobianWork,
}

pub struct AssembledSystem {
    n: usize,
    blocks: Vec<Block>,
    work: Vec<BlockWork>,
    /// Batched series ([`Batch`]), and whether each block is in one (else
    /// its own [`TaylorWork`]).
    batches: Vec<Batch>,
    batched: Vec<bool>,
    /// See [`AssembledSystem::with_private_blocks`].
    private: Vec<Vec<usize>>,
    structure: Arc<Structure>,
    nodes: Vec<f64>,
    jwork: JacobianWork,
    equation_scales: Vec<f64>,
    unknown_scales: (Vec<f64>, f64),
}

impl AssembledSystem {
    /// [`SeriesProblem::series_order`] into `out`, or (None) its commit.
    fn order_or_commit(&mut self, p: usize, xp: &[f64], lambda_p: f64, mut out: Option<&mut [f64]>) {
        if let Some(out) = out.as_deref_mut() {
            out.fill(0.0);
        }
        for batch in &mut self.batches {
            Self::gather_lanes(&self.blocks, batch, |g| xp[g], lambda_p, |_| 0.0);
            let tape = &self.blocks[batch.blocks[0]].tape;
            match (&mut batch.engine, out.is_some()) {
                (Engine { taylor: Some(t), .. }, true) => t.order(tape, p, &batch.inputs, &mut batch.outputs),
                (Engine { taylor: Some(t), .. }, false) => t.commit(tape, p, &batch.inputs),
                (Engine { compiled: Some(k), .. }, _) => k.series_order(p, &batch.inputs, &mut batch.outputs),
                _ => unreachable!("a batch has a shared tape or a compiled kernel"),
            }
            if let Some(out) = out.as_deref_mut() {
                Self::scatter_lanes(&self.blocks, batch, out);
            }
        }
        for ((b, w), _) in self.blocks.iter().zip(&mut self.work).zip(&self.batched).filter(|(_, &t)| !t) {
            let inputs = &b.inputs;
            let coefficient = |i: usize| inputs[i].series_coefficient(xp, lambda_p);
            w.taylor.order(&b.tape, p, coefficient, &mut w.local_out);
            if let Some(out) = out.as_deref_mut() {
                for (&row, v) in b.rows.iter().zip(&w.local_out) {
                    out[row] += v;
                }
            }
        }
    }

    /// `n` unknowns and equations; every equation must receive an output of
    /// some block (else the system is singular by construction: panics, a
    /// model bug). Scales default to 1.
    pub fn new(n: usize, blocks: Vec<Block>) -> Self {
        let structure = structure(n, &blocks);
        let work = blocks
            .iter()
            .map(|b| BlockWork {
                local_in: vec![0.0; b.tape.inputs()],
                local_out: vec![0.0; b.tape.outputs()],
                local_jac: Vec::new(),
                taylor: TaylorWork::default(),
            })
            .collect();
        let (batches, batched) = Self::batches(&blocks);
        AssembledSystem {
            n,
            blocks,
            work,
            batches,
            batched,
            private: Vec::new(),
            structure,
            nodes: Vec::new(),
            jwork: JacobianWork::default(),
            equation_scales: vec![1.0; n],
            unknown_scales: (vec![1.0; n], 1.0),
        }
    }

    /// Blocks with compatible compiled kernels, LANES at a time (a lone
    /// one too: compiled lanes beat the interpreted tape); blocks without
    /// one on a shared tape, LANES at a time, a group's last single block
    /// (and a tape's only one) keeping its own series.
    fn batches(blocks: &[Block]) -> (Vec<Batch>, Vec<bool>) {
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let same = |a: &Block, b: &Block| match (&a.kernel, &b.kernel) {
            (Some(ka), Some(kb)) => ka.compatible(kb.as_ref()),
            (None, None) => Arc::ptr_eq(&a.tape, &b.tape),
            _ => false,
        };
        for (b, block) in blocks.iter().enumerate() {
            match groups.iter_mut().find(|g| same(&blocks[g[0]], block)) {
                Some(g) => g.push(b),
                None => groups.push(vec![b]),
            }
        }
        let mut batched = vec![false; blocks.len()];
        let mut batches = Vec::new();
        for g in groups {
            let compiled = blocks[g[0]].kernel.is_some();
            for chunk in g.chunks(LANES).filter(|c| compiled || c.len() >= 2) {
                let tape = &blocks[chunk[0]].tape;
                chunk.iter().for_each(|&b| batched[b] = true);
                let compiled = blocks[chunk[0]].kernel.as_ref().map(|k| {
                    let members: Vec<&dyn LaneKernel> =
                        chunk.iter().map(|&b| blocks[b].kernel.as_deref().expect("compiled group")).collect();
                    k.batch(&members)
                });
                let shared = chunk.iter().all(|&b| Arc::ptr_eq(&blocks[b].tape, tape));
                let engine = Engine {
                    compiled,
                    taylor: shared.then(BatchTaylorWork::default),
                    jacobian: BatchJacobianWork::default(),
                };
                batches.push(Batch {
                    blocks: chunk.to_vec(),
                    engine,
                    inputs: vec![[0.0; LANES]; tape.inputs()],
                    outputs: vec![[0.0; LANES]; tape.outputs()],
                    local_jac: Vec::new(),
                });
            }
        }
        (batches, batched)
    }

    /// The system with every block evaluated by its tape (the reference
    /// a compiled kernel is held against, and the interpreted baseline of
    /// the benchmarks).
    pub fn interpreted(mut self) -> Self {
        for b in &mut self.blocks {
            b.kernel = None;
        }
        (self.batches, self.batched) = Self::batches(&self.blocks);
        self
    }

    /// Each batch's lane inputs from `value(global unknown)`, Λ's
    /// `lambda` (params: `param(v)`, v their value).
    fn gather_lanes(
        blocks: &[Block],
        batch: &mut Batch,
        value: impl Fn(usize) -> f64,
        lambda: f64,
        param: impl Fn(f64) -> f64,
    ) {
        for (l, &b) in batch.blocks.iter().enumerate() {
            for (slot, input) in blocks[b].inputs.iter().zip(&mut batch.inputs) {
                input[l] = match *slot {
                    Slot::Unknown(g) => value(g),
                    Slot::Lambda => lambda,
                    Slot::Param(v) => param(v),
                };
            }
        }
    }

    /// Add block `b`'s local Jacobian (`local(k·inputs + j)`, row-major)
    /// into ∂R/∂x at its pattern `positions` and ∂R/∂Λ: only the inputs
    /// each output depends on (structural).
    fn scatter_jacobian(b: &Block, positions: &[u32], local: impl Fn(usize) -> f64, jx: &mut [f64], jl: &mut [f64]) {
        let nin = b.inputs.len();
        let mut at = positions.iter();
        for (k, &row) in b.rows.iter().enumerate() {
            for &j in b.tape.dependencies(k) {
                let e = k * nin + j as usize;
                let p = *at.next().expect("one position per dependency");
                match b.inputs[j as usize] {
                    Slot::Unknown(_) => jx[p as usize] += local(e),
                    Slot::Lambda => jl[row] += local(e),
                    Slot::Param(_) => {}
                }
            }
        }
    }

    /// Add each lane's outputs into its block's rows.
    fn scatter_lanes(blocks: &[Block], batch: &Batch, out: &mut [f64]) {
        for (l, &b) in batch.blocks.iter().enumerate() {
            for (&row, v) in blocks[b].rows.iter().zip(&batch.outputs) {
                out[row] += v[l];
            }
        }
    }

    /// Declare sets of unknowns private to one block each (a collocated
    /// element's stage unknowns: read by its kernel alone, their
    /// equations written by it alone) whose square blocks the model knows
    /// to be regular: the continuation condenses them
    /// ([`Problem::private_blocks`]). A set that breaks the form is
    /// caught when the tangent is built, which then factorises whole.
    pub fn with_private_blocks(mut self, sets: Vec<Vec<usize>>) -> Self {
        self.private = sets;
        self
    }

    pub fn with_scales(mut self, equations: Vec<f64>, unknowns: Vec<f64>, lambda: f64) -> Self {
        assert_eq!(equations.len(), self.n);
        assert_eq!(unknowns.len(), self.n);
        self.equation_scales = equations;
        self.unknown_scales = (unknowns, lambda);
        self
    }

    pub fn blocks(&self) -> &[Block] {
        &self.blocks
    }

    /// Highest degree of the system in (x, Λ) (3 for the cubic rod).
    pub fn degree(&self) -> u32 {
        // Once per distinct tape and set of parameter slots (a rod's
        // elements share one tape).
        let mut seen: Vec<(*const Tape, Vec<bool>)> = Vec::new();
        let mut degree = 0;
        for b in &self.blocks {
            let variable: Vec<bool> = b.inputs.iter().map(|s| !matches!(s, Slot::Param(_))).collect();
            let key = (Arc::as_ptr(&b.tape), variable);
            if !seen.contains(&key) {
                degree = degree.max(b.tape.degree_in(&key.1));
                seen.push(key);
            }
        }
        degree
    }

    fn gather(inputs: &[Slot], x: &[f64], lambda: f64, out: &mut [f64]) {
        for (o, s) in out.iter_mut().zip(inputs) {
            *o = match *s {
                Slot::Unknown(i) => x[i],
                Slot::Lambda => lambda,
                Slot::Param(v) => v,
            };
        }
    }
}

impl Problem for AssembledSystem {
    fn dim(&self) -> usize {
        self.n
    }

    fn pattern(&self) -> &Pattern {
        &self.structure.pattern
    }

    fn residual(&mut self, x: &[f64], lambda: f64, r: &mut [f64]) {
        r.fill(0.0);
        for batch in &mut self.batches {
            Self::gather_lanes(&self.blocks, batch, |g| x[g], lambda, |v| v);
            let tape = &self.blocks[batch.blocks[0]].tape;
            match &mut batch.engine {
                Engine { compiled: Some(k), .. } => k.eval(&batch.inputs, &mut batch.outputs),
                Engine { jacobian, .. } => eval_lanes(tape, &batch.inputs, jacobian, &mut batch.outputs),
            }
            Self::scatter_lanes(&self.blocks, batch, r);
        }
        for ((b, w), _) in self.blocks.iter().zip(&mut self.work).zip(&self.batched).filter(|(_, &t)| !t) {
            Self::gather(&b.inputs, x, lambda, &mut w.local_in);
            b.tape.eval(&w.local_in, &mut self.nodes, &mut w.local_out);
            for (&row, v) in b.rows.iter().zip(&w.local_out) {
                r[row] += v;
            }
        }
    }

    fn jacobian(&mut self, x: &[f64], lambda: f64, jx: &mut [f64], jl: &mut [f64]) {
        jx.fill(0.0);
        jl.fill(0.0);
        for batch in &mut self.batches {
            Self::gather_lanes(&self.blocks, batch, |g| x[g], lambda, |v| v);
            let tape = &self.blocks[batch.blocks[0]].tape;
            let len = tape.inputs() * tape.outputs();
            if batch.local_jac.is_empty() {
                // The compiled kernel writes the structural nonzeros only:
                // the rest must be zero (a pooled array is stale).
                grow_pooled(&mut batch.local_jac, len);
                batch.local_jac[..len].fill([0.0; LANES]);
            }
            let jac = &mut batch.local_jac[..len];
            match &mut batch.engine {
                Engine { compiled: Some(k), .. } => k.jacobian(&batch.inputs, &mut batch.outputs, jac),
                Engine { jacobian, .. } => jacobian_lanes(tape, &batch.inputs, jacobian, &mut batch.outputs, jac),
            }
            for (l, &bi) in batch.blocks.iter().enumerate() {
                let local = |e: usize| batch.local_jac[e][l];
                Self::scatter_jacobian(&self.blocks[bi], &self.structure.positions[bi], local, jx, jl);
            }
        }
        for (((b, w), _), positions) in self
            .blocks
            .iter()
            .zip(&mut self.work)
            .zip(&self.batched)
            .zip(&self.structure.positions)
            .filter(|((_, &t), _)| !t)
        {
            Self::gather(&b.inputs, x, lambda, &mut w.local_in);
            if w.local_jac.is_empty() {
                w.local_jac = vec![0.0; b.tape.inputs() * b.tape.outputs()];
            }
            b.tape.jacobian(&w.local_in, &mut self.jwork, &mut w.local_out, &mut w.local_jac);
            Self::scatter_jacobian(b, positions, |e| w.local_jac[e], jx, jl);
        }
    }

    fn equation_scales(&self) -> Vec<f64> {
        self.equation_scales.clone()
    }

    /// The private blocks the model declared
    /// ([`AssembledSystem::with_private_blocks`]).
    fn private_blocks(&self) -> Vec<Vec<usize>> {
        self.private.clone()
    }

    fn unknown_scales(&self) -> (Vec<f64>, f64) {
        self.unknown_scales.clone()
    }
}

impl SeriesProblem for AssembledSystem {
    fn series_begin(&mut self, x0: &[f64], lambda0: f64, max_order: usize) {
        for batch in &mut self.batches {
            Self::gather_lanes(&self.blocks, batch, |g| x0[g], lambda0, |v| v);
            let tape = &self.blocks[batch.blocks[0]].tape;
            match &mut batch.engine {
                Engine { taylor: Some(t), .. } => t.begin(tape, &batch.inputs, max_order),
                Engine { compiled: Some(k), .. } => k.series_begin(&batch.inputs, max_order),
                _ => unreachable!("a batch has a shared tape or a compiled kernel"),
            }
        }
        for ((b, w), _) in self.blocks.iter().zip(&mut self.work).zip(&self.batched).filter(|(_, &t)| !t) {
            Self::gather(&b.inputs, x0, lambda0, &mut w.local_in);
            w.taylor.begin(&b.tape, &w.local_in, max_order);
        }
    }

    fn series_order(&mut self, p: usize, xp: &[f64], lambda_p: f64, out: &mut [f64]) {
        self.order_or_commit(p, xp, lambda_p, Some(out));
    }

    /// Batches of one shared tape commit the tape's cone of history nodes
    /// alone ([`BatchTaylorWork::commit`]); compiled batches and lone
    /// blocks run their whole order (their outputs left unread).
    fn series_commit(&mut self, p: usize, xp: &[f64], lambda_p: f64, _scratch: &mut [f64]) {
        self.order_or_commit(p, xp, lambda_p, None);
    }

    fn has_series_tangent(&self) -> bool {
        true
    }

    fn series_tangent_order(&mut self, p: usize, wp: &[f64], w_lambda_p: f64, out: &mut [f64]) {
        out.fill(0.0);
        for batch in &mut self.batches {
            Self::gather_lanes(&self.blocks, batch, |g| wp[g], w_lambda_p, |_| 0.0);
            let tape = &self.blocks[batch.blocks[0]].tape;
            match &mut batch.engine {
                Engine { taylor: Some(t), .. } => t.tangent_order(tape, p, &batch.inputs, &mut batch.outputs),
                Engine { compiled: Some(k), .. } => k.series_tangent_order(p, &batch.inputs, &mut batch.outputs),
                _ => unreachable!("a batch has a shared tape or a compiled kernel"),
            }
            Self::scatter_lanes(&self.blocks, batch, out);
        }
        for ((b, w), _) in self.blocks.iter().zip(&mut self.work).zip(&self.batched).filter(|(_, &t)| !t) {
            let inputs = &b.inputs;
            let coefficient = |i: usize| inputs[i].series_coefficient(wp, w_lambda_p);
            w.taylor.tangent_order(&b.tape, p, coefficient, &mut w.local_out);
            for (&row, v) in b.rows.iter().zip(&w.local_out) {
                out[row] += v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// out0 = a·x0·x1 and out1 = b·x2 + x0: dependencies {0, 1} and
    /// {0, 2}; `swap` records x0·x2 and x1 instead ({0, 2} and {1}).
    fn tape(a: f64, b: f64, swap: bool) -> Arc<Tape> {
        Arc::new(Tape::record(3, |v| match swap {
            false => vec![v[0] * v[1] * a, v[2] * b + v[0]],
            true => vec![v[0] * v[2], v[1] * 1.0],
        }))
    }

    /// Two blocks over 4 unknowns: rows 0, 1 from x0..x2, rows 2, 3 from
    /// (x2, x3, third).
    fn system(t: &Arc<Tape>, third: Slot) -> AssembledSystem {
        let blocks = vec![
            Block::new(t.clone(), vec![Slot::Unknown(0), Slot::Unknown(1), Slot::Unknown(2)], vec![0, 1]),
            Block::new(t.clone(), vec![Slot::Unknown(2), Slot::Unknown(3), third], vec![2, 3]),
        ];
        AssembledSystem::new(4, blocks)
    }

    /// ∂R/∂x at a fixed point, in pattern order.
    fn jacobian(s: &mut AssembledSystem) -> Vec<f64> {
        let (mut jx, mut jl) = (vec![0.0; s.pattern().nnz()], vec![0.0; 4]);
        s.jacobian(&[0.3, -1.1, 0.7, 1.9], 0.4, &mut jx, &mut jl);
        jx
    }

    /// A system whose blocks have a kept structure (same tape
    /// dependencies, input unknowns and rows; coefficients, Λ and params
    /// may differ) shares it, and its pattern and Jacobian are those of a
    /// system built with nothing kept (the reference: the same blocks after
    /// the kept structures are forgotten; the Jacobian's entries also
    /// against the kernel's derivatives by hand). Another tape structure or
    /// another input unknown takes a structure of its own; at most
    /// KEPT_STRUCTURES are kept. In a thread of its own: the count is the
    /// thread's.
    #[test]
    fn a_kept_structure_is_the_one_a_build_gives() {
        std::thread::spawn(|| {
            forget_kept_structures();
            let mut first = system(&tape(2.0, 3.0, false), Slot::Lambda);
            assert_eq!(kept_structures(), 1);
            // Other coefficients, a parameter for Λ: the same structure.
            let mut second = system(&tape(5.0, -1.0, false), Slot::Param(0.25));
            assert_eq!(kept_structures(), 1);
            assert!(std::ptr::eq(first.pattern(), second.pattern()), "the structure should be shared");
            forget_kept_structures();
            let mut fresh = system(&tape(5.0, -1.0, false), Slot::Param(0.25));
            assert!(!std::ptr::eq(fresh.pattern(), second.pattern()));
            assert_eq!(fresh.pattern(), second.pattern());
            assert_eq!(jacobian(&mut fresh), jacobian(&mut second));
            // By hand, second's kernel at x = (0.3, −1.1, 0.7, 1.9):
            // rows 0, 1: (5x1, 5x0, 0 | 1, 0, −1); rows 2, 3 on (x2, x3):
            // (5x3, 5x2 | 1, 0).
            let p = second.pattern().clone();
            let jx = jacobian(&mut second);
            let at = |i: usize, j: usize| jx[p.position(i, j).unwrap()];
            let want = [(0, 0, -5.5), (0, 1, 1.5), (1, 0, 1.0), (1, 2, -1.0), (2, 2, 9.5), (2, 3, 3.5), (3, 2, 1.0)];
            for (i, j, v) in want {
                assert!((at(i, j) - v).abs() < 1e-14, "∂R{i}/∂x{j} = {} (want {v})", at(i, j));
            }
            // first (a = 2, b = 3, Λ third): ∂R0/∂x0 = 2x1, ∂R2/∂x3 = 2x2; and
            // ∂R3/∂Λ = 3 (R3 = 3Λ + x2), the Λ column through the kept
            // positions' u32::MAX.
            let (mut jx, mut jl) = (vec![0.0; p.nnz()], vec![0.0; 4]);
            first.jacobian(&[0.3, -1.1, 0.7, 1.9], 0.4, &mut jx, &mut jl);
            assert!((jx[p.position(0, 0).unwrap()] + 2.2).abs() < 1e-14, "∂R0/∂x0 = {}", jx[p.position(0, 0).unwrap()]);
            assert!((jx[p.position(2, 3).unwrap()] - 1.4).abs() < 1e-14);
            assert_eq!(jl, [0.0, 0.0, 0.0, 3.0]);
            // Another dependency structure: its own pattern (rows 0, 1 on
            // {x0, x2} and {x1}).
            let swapped = system(&tape(1.0, 1.0, true), Slot::Lambda);
            assert_eq!(kept_structures(), 2);
            let q = swapped.pattern();
            assert!(q.position(0, 2).is_some() && q.position(0, 1).is_none() && q.position(1, 0).is_none());
            // The second block reading x1 where it read x3: its own.
            let t = tape(2.0, 3.0, false);
            let blocks = vec![
                Block::new(t.clone(), vec![Slot::Unknown(0), Slot::Unknown(1), Slot::Unknown(2)], vec![0, 1]),
                Block::new(t.clone(), vec![Slot::Unknown(2), Slot::Unknown(1), Slot::Lambda], vec![2, 3]),
            ];
            let moved = AssembledSystem::new(4, blocks);
            assert_eq!(kept_structures(), 3);
            assert!(moved.pattern().position(2, 1).is_some() && moved.pattern().position(2, 3).is_none());
            for k in 0..2 * KEPT_STRUCTURES {
                let t = tape(1.0, 1.0, false);
                let block = |rows: Vec<usize>, u: usize| {
                    Block::new(t.clone(), vec![Slot::Unknown(u), Slot::Unknown(u + 1), Slot::Lambda], rows)
                };
                // k + 2 copies of the first block's shape: k + 2 blocks.
                let mut blocks = vec![block(vec![0, 1], 0)];
                blocks.extend((0..=k).map(|_| block(vec![0, 1], 0)));
                AssembledSystem::new(2, blocks);
            }
            assert_eq!(kept_structures(), KEPT_STRUCTURES);
        })
        .join()
        .unwrap();
    }

    /// The column-by-column build gives the pattern and positions of the
    /// entry-list construction it replaced (reference: every block entry
    /// listed, `Pattern::with_positions_and_diagonal`, positions read back
    /// in dependency order), on 300 random systems: tapes shared or not,
    /// rows in order or shuffled and shared between blocks, inputs
    /// repeated, Λ and parameters among them, element-like chains whose
    /// private columns take the one-reader path.
    #[test]
    fn a_built_structure_is_the_pattern_of_its_blocks_entries() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |m: usize| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % m as u64) as usize
        };
        for case in 0..300 {
            let n = 4 + next(40);
            // A few tapes: each output a sum of products over a random,
            // non-empty set of inputs.
            let tapes: Vec<Arc<Tape>> = (0..1 + next(3))
                .map(|_| {
                    let (m, q) = (1 + next(6), 1 + next(5));
                    let sets: Vec<Vec<usize>> = (0..q).map(|_| (0..1 + next(m)).map(|_| next(m)).collect()).collect();
                    Arc::new(Tape::record(m, |v| {
                        sets.iter().map(|set| set.iter().fold(v[set[0]] * 0.5, |acc, &j| acc + v[j] * v[j])).collect()
                    }))
                })
                .collect();
            let chain = case % 2 == 0;
            let mut blocks = Vec::new();
            let mut covered = vec![false; n];
            let mut b = 0;
            while blocks.len() < 2 + next(6) || covered.iter().any(|c| !c) {
                let t = tapes[next(tapes.len())].clone();
                let (m, q) = (t.inputs(), t.outputs());
                // Rows: distinct, increasing in a chain, else shuffled.
                let first = if chain { b % n } else { next(n) };
                let mut rows: Vec<usize> = (0..q).map(|k| (first + k) % n).collect();
                rows.sort_unstable();
                rows.dedup();
                if rows.len() < q {
                    rows = (0..q).map(|k| (first + k * 7 + 1) % n).collect();
                    rows.sort_unstable();
                    rows.dedup();
                }
                if rows.len() < q {
                    b += 1;
                    continue;
                }
                if !chain && next(2) == 0 {
                    rows.reverse();
                }
                for &r in &rows {
                    covered[r] = true;
                }
                let inputs = (0..m)
                    .map(|j| match next(12) {
                        0 => Slot::Lambda,
                        1 => Slot::Param(0.5),
                        _ if chain => Slot::Unknown((first + j) % n),
                        _ => Slot::Unknown(next(n)),
                    })
                    .collect();
                blocks.push(Block::new(t, inputs, rows));
                b += q;
            }
            let built = Structure::build(n, &blocks);
            // The reference.
            let mut entries = Vec::new();
            for b in &blocks {
                for (k, &row) in b.rows.iter().enumerate() {
                    for &j in b.tape.dependencies(k) {
                        if let Slot::Unknown(col) = b.inputs[j as usize] {
                            entries.push((row, col));
                        }
                    }
                }
            }
            let (pattern, found) = Pattern::with_positions_and_diagonal(n, &entries);
            assert_eq!(built.pattern, pattern, "case {case}: pattern");
            let mut found = found.iter();
            for (e, b) in blocks.iter().enumerate() {
                let mut d = 0;
                for k in 0..b.rows.len() {
                    for &j in b.tape.dependencies(k) {
                        let want = match b.inputs[j as usize] {
                            Slot::Unknown(_) => *found.next().unwrap(),
                            _ => u32::MAX,
                        };
                        assert_eq!(built.positions[e][d], want, "case {case}: block {e}, output {k}, input {j}");
                        d += 1;
                    }
                }
                assert_eq!(built.positions[e].len(), d);
            }
        }
    }
}

//! A global system assembled from polynomial kernels (blocks): each block
//! is a recorded [`Tape`] whose inputs are global unknowns, Λ or fixed
//! parameters, and whose outputs add into global equations. Models (a rod's
//! elements and boundary conditions) describe themselves as blocks; this
//! type turns them into a [`Problem`] and a [`SeriesProblem`]: residual,
//! sparse Jacobian (pattern from the tapes' structural dependencies, values
//! by forward mode per block) and Taylor coefficients.

use super::{Problem, SeriesProblem};
use crate::linalg::sparse::Pattern;
use crate::taylor::{JacobianWork, Tape, TaylorWork};
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

/// One kernel instance.
#[derive(Clone, Debug)]
pub struct Block {
    pub tape: Arc<Tape>,
    pub inputs: Vec<Slot>,
    /// Global equation each output adds into.
    pub rows: Vec<usize>,
}

/// Per-block evaluation storage.
#[derive(Clone, Debug, Default)]
struct BlockWork {
    local_in: Vec<f64>,
    local_out: Vec<f64>,
    local_jac: Vec<f64>,
    /// Pattern position of (output k, input j), or usize::MAX (Λ, params,
    /// structural zero).
    positions: Vec<usize>,
    taylor: TaylorWork,
}

pub struct AssembledSystem {
    n: usize,
    blocks: Vec<Block>,
    work: Vec<BlockWork>,
    pattern: Pattern,
    nodes: Vec<f64>,
    jwork: JacobianWork,
    equation_scales: Vec<f64>,
    unknown_scales: (Vec<f64>, f64),
}

impl AssembledSystem {
    /// `n` unknowns and equations; every equation must receive an output of
    /// some block (else the system is singular by construction: panics, a
    /// model bug). Scales default to 1.
    pub fn new(n: usize, blocks: Vec<Block>) -> Self {
        let mut covered = vec![false; n];
        let mut entries = Vec::new();
        for b in &blocks {
            assert_eq!(b.inputs.len(), b.tape.inputs(), "block inputs do not match its tape");
            assert_eq!(b.rows.len(), b.tape.outputs(), "block rows do not match its tape");
            for (k, &row) in b.rows.iter().enumerate() {
                covered[row] = true;
                for &j in b.tape.dependencies(k) {
                    if let Slot::Unknown(col) = b.inputs[j as usize] {
                        entries.push((row, col));
                    }
                }
            }
        }
        if let Some(row) = covered.iter().position(|c| !c) {
            panic!("equation {row} receives no block output");
        }
        // Keep the diagonal in the pattern: a zero there is still a pivot slot.
        entries.extend((0..n).map(|i| (i, i)));
        let pattern = Pattern::from_entries(n, entries);
        let work = blocks
            .iter()
            .map(|b| {
                let (nin, nout) = (b.tape.inputs(), b.tape.outputs());
                let mut positions = vec![usize::MAX; nin * nout];
                for (k, &row) in b.rows.iter().enumerate() {
                    for j in 0..nin {
                        if let Slot::Unknown(col) = b.inputs[j] {
                            if let Some(p) = pattern.position(row, col) {
                                positions[k * nin + j] = p;
                            }
                        }
                    }
                }
                BlockWork {
                    local_in: vec![0.0; nin],
                    local_out: vec![0.0; nout],
                    local_jac: vec![0.0; nin * nout],
                    positions,
                    taylor: TaylorWork::default(),
                }
            })
            .collect();
        AssembledSystem {
            n,
            blocks,
            work,
            pattern,
            nodes: Vec::new(),
            jwork: JacobianWork::default(),
            equation_scales: vec![1.0; n],
            unknown_scales: (vec![1.0; n], 1.0),
        }
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
        self.blocks
            .iter()
            .map(|b| {
                let variable: Vec<bool> = b.inputs.iter().map(|s| !matches!(s, Slot::Param(_))).collect();
                b.tape.degree_in(&variable)
            })
            .max()
            .unwrap_or(0)
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
        &self.pattern
    }

    fn residual(&mut self, x: &[f64], lambda: f64, r: &mut [f64]) {
        r.fill(0.0);
        for (b, w) in self.blocks.iter().zip(&mut self.work) {
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
        for (b, w) in self.blocks.iter().zip(&mut self.work) {
            Self::gather(&b.inputs, x, lambda, &mut w.local_in);
            b.tape.jacobian(&w.local_in, &mut self.jwork, &mut w.local_out, &mut w.local_jac);
            let nin = b.inputs.len();
            for (k, &row) in b.rows.iter().enumerate() {
                // Only the inputs this output depends on (structural).
                for &j in b.tape.dependencies(k) {
                    let j = j as usize;
                    let v = w.local_jac[k * nin + j];
                    match &b.inputs[j] {
                        Slot::Unknown(_) => {
                            let p = w.positions[k * nin + j];
                            if p != usize::MAX {
                                jx[p] += v;
                            }
                        }
                        Slot::Lambda => jl[row] += v,
                        Slot::Param(_) => {}
                    }
                }
            }
        }
    }

    fn equation_scales(&self) -> Vec<f64> {
        self.equation_scales.clone()
    }

    fn unknown_scales(&self) -> (Vec<f64>, f64) {
        self.unknown_scales.clone()
    }
}

impl SeriesProblem for AssembledSystem {
    fn series_begin(&mut self, x0: &[f64], lambda0: f64, max_order: usize) {
        for (b, w) in self.blocks.iter().zip(&mut self.work) {
            Self::gather(&b.inputs, x0, lambda0, &mut w.local_in);
            w.taylor.begin(&b.tape, &w.local_in, max_order);
        }
    }

    fn series_order(&mut self, p: usize, xp: &[f64], lambda_p: f64, out: &mut [f64]) {
        out.fill(0.0);
        for (b, w) in self.blocks.iter().zip(&mut self.work) {
            let inputs = &b.inputs;
            let coefficient = |i: usize| match inputs[i] {
                Slot::Unknown(g) => xp[g],
                Slot::Lambda => lambda_p,
                Slot::Param(_) => 0.0,
            };
            w.taylor.order(&b.tape, p, coefficient, &mut w.local_out);
            for (&row, v) in b.rows.iter().zip(&w.local_out) {
                out[row] += v;
            }
        }
    }

    fn has_series_tangent(&self) -> bool {
        true
    }

    fn series_tangent_order(&mut self, p: usize, wp: &[f64], w_lambda_p: f64, out: &mut [f64]) {
        out.fill(0.0);
        for (b, w) in self.blocks.iter().zip(&mut self.work) {
            let inputs = &b.inputs;
            let coefficient = |i: usize| match inputs[i] {
                Slot::Unknown(g) => wp[g],
                Slot::Lambda => w_lambda_p,
                Slot::Param(_) => 0.0,
            };
            w.taylor.tangent_order(&b.tape, p, coefficient, &mut w.local_out);
            for (&row, v) in b.rows.iter().zip(&w.local_out) {
                out[row] += v;
            }
        }
    }
}

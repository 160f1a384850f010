//! Polynomial kernels written once and evaluated three ways: values,
//! derivatives (Jacobian blocks) and Taylor series along a path (the
//! asymptotic numerical method, physics.md §2.4).
//!
//! A model writes a kernel — a function of its local unknowns, generic over
//! [`Scalar`] — with the four operations +, −, ×, negation and constants.
//! Recorded once with [`Tape::record`], the kernel becomes a straight-line
//! program (a tape). Because a polynomial kernel has no branches, one tape
//! serves every evaluation point:
//!
//! * [`Tape::eval`]: the values;
//! * [`Tape::jacobian`]: ∂outputs/∂inputs by forward mode over the tape;
//! * [`TaylorWork`]: the order-p Taylor coefficient of every node along a
//!   series X(a) = Σ a^k X_k. Products are Cauchy products over the stored
//!   coefficients of their operands, z_p = Σ_{i=0..p} x_i y_{p−i}, so order
//!   p costs O(p) per product and a whole series of order P costs O(P²) per
//!   node — the intermediate products (R(q), q∘u, R(q)v, …) are series in
//!   their own right, and the O(P³) triple sum of the cubic recursion is
//!   never formed. For a cubic residual R(X) = c0 + L X + Q(X, X) + C(X, X, X),
//!   the order-p coefficient of R with X_p = 0 is exactly the right-hand
//!   side of the ANM recursion (minus sign aside), and with the true X_p it
//!   is zero.
//!
//! The tape also reports the polynomial degree of each output, so a model
//! can assert that its residual is cubic. Non-polynomial parts (the charged
//! rod's pair forces) take their series by the elementary recurrences of
//! [`elementary`] instead.

pub mod batch;
pub mod elementary;
pub mod lanes;

use std::cell::RefCell;
use std::ops::{Add, Mul, Neg, Sub};

/// Arithmetic a kernel may use. Implemented for `f64` (direct evaluation)
/// and [`Var`] (recording).
pub trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
{
    fn constant(c: f64) -> Self;
}

/// A constant a kernel multiplies by: one number, or one per lane of a
/// batch ([`batch::Lanes`]). A zero coefficient is skipped by the kernels
/// that test it, so a recorded tape holds only the couplings a law has.
pub trait Coefficient: Copy {
    fn is_zero(&self) -> bool;
}

impl Coefficient for f64 {
    #[inline]
    fn is_zero(&self) -> bool {
        *self == 0.0
    }
}

impl Coefficient for batch::Lanes {
    #[inline]
    fn is_zero(&self) -> bool {
        self.iter().all(|c| *c == 0.0)
    }
}

impl Scalar for f64 {
    #[inline]
    fn constant(c: f64) -> Self {
        c
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Input(u32),
    Const(f64),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Neg(u32),
    /// c·a
    Scale(f64, u32),
    /// a + c
    Shift(f64, u32),
}

impl Op {
    /// The nodes this op reads (none for an input or a constant).
    fn operands(self) -> impl Iterator<Item = u32> {
        let (a, b) = match self {
            Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) => (Some(a), Some(b)),
            Op::Neg(a) | Op::Scale(_, a) | Op::Shift(_, a) => (Some(a), None),
            Op::Input(_) | Op::Const(_) => (None, None),
        };
        a.into_iter().chain(b)
    }

    /// The same op reading `to(a)` for each operand a.
    fn with_operands(self, to: impl Fn(u32) -> u32) -> Op {
        match self {
            Op::Input(_) | Op::Const(_) => self,
            Op::Add(a, b) => Op::Add(to(a), to(b)),
            Op::Sub(a, b) => Op::Sub(to(a), to(b)),
            Op::Mul(a, b) => Op::Mul(to(a), to(b)),
            Op::Neg(a) => Op::Neg(to(a)),
            Op::Scale(c, a) => Op::Scale(c, to(a)),
            Op::Shift(c, a) => Op::Shift(c, to(a)),
        }
    }
}

thread_local! {
    static RECORDING: RefCell<Option<Vec<Op>>> = const { RefCell::new(None) };
}

fn push(op: Op) -> Var {
    RECORDING.with(|r| {
        let mut r = r.borrow_mut();
        let ops = r.as_mut().expect("tape variables are used only inside Tape::record");
        ops.push(op);
        Var((ops.len() - 1) as u32)
    })
}

/// A node of the tape being recorded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Var(u32);

impl Add for Var {
    type Output = Var;
    fn add(self, o: Var) -> Var {
        push(Op::Add(self.0, o.0))
    }
}
impl Sub for Var {
    type Output = Var;
    fn sub(self, o: Var) -> Var {
        push(Op::Sub(self.0, o.0))
    }
}
impl Mul for Var {
    type Output = Var;
    fn mul(self, o: Var) -> Var {
        push(Op::Mul(self.0, o.0))
    }
}
impl Neg for Var {
    type Output = Var;
    fn neg(self) -> Var {
        push(Op::Neg(self.0))
    }
}
impl Add<f64> for Var {
    type Output = Var;
    fn add(self, c: f64) -> Var {
        if c == 0.0 {
            self
        } else {
            push(Op::Shift(c, self.0))
        }
    }
}
impl Sub<f64> for Var {
    type Output = Var;
    fn sub(self, c: f64) -> Var {
        self + (-c)
    }
}
impl Mul<f64> for Var {
    type Output = Var;
    fn mul(self, c: f64) -> Var {
        if c == 1.0 {
            self
        } else {
            push(Op::Scale(c, self.0))
        }
    }
}
impl Scalar for Var {
    fn constant(c: f64) -> Self {
        push(Op::Const(c))
    }
}

/// A recorded polynomial kernel: `inputs` → `outputs`.
#[derive(Clone, Debug)]
pub struct Tape {
    ops: Vec<Op>,
    inputs: usize,
    outputs: Vec<u32>,
    /// Polynomial degree of each node in the inputs.
    degree: Vec<u32>,
    /// The sorted local inputs each node depends on, node k's at
    /// deps[start[k]..start[k + 1]].
    deps: Vec<u32>,
    /// Sparse forward mode: node k's gradient lives at grad[start[k]..start[k+1]]
    /// over its own dependencies; for a binary node, `scatter` holds, from
    /// scatter_start[k], the position in node k's list of each dependency of
    /// its first operand, then of its second.
    start: Vec<usize>,
    scatter_start: Vec<usize>,
    scatter: Vec<u32>,
    /// Where the batched series ([`batch::BatchTaylorWork`]) keeps each
    /// node's coefficients.
    series: SeriesLayout,
}

/// The batched series' storage of a tape's nodes. Only a product reads
/// its operands' lower orders (z_p = Σ x_i y_{p−i}); every other op reads
/// order p alone. The products' operands (the history nodes) take slots
/// 0..history and every other node a slot above; order p's coefficients
/// lie at p·history + slot. Orders overlap: order p's non-history slots
/// share the memory of the history of orders p + 1, p + 2, … — dead
/// values once order p is done, and written again before a later order
/// reads them. A pass then touches (P + 1)·history + (nodes − history)
/// coefficients instead of (P + 1)·nodes: a Gauss(4) rod element's 1136
/// nodes have 92 product operands (at P = 15, 80 kB a batch of four
/// lanes instead of 580 kB — a fresh process pays a page fault per 4 kB).
#[derive(Clone, Debug)]
struct SeriesLayout {
    history: usize,
    /// The ops with their operands' slots, and each op's own slot.
    ops: Vec<Op>,
    slot: Vec<u32>,
    /// The outputs' slots.
    outputs: Vec<u32>,
    /// The ops (as `ops`, `slot`) that a commit of order p computes: the
    /// history nodes and what they are computed from. Later orders read
    /// no other node's order p (a Gauss(4) rod element: 184 of 1136).
    cone_ops: Vec<Op>,
    cone_slot: Vec<u32>,
}

impl SeriesLayout {
    fn of(ops: &[Op], outputs: &[u32]) -> Self {
        let mut product_operand = vec![false; ops.len()];
        for op in ops {
            if let Op::Mul(a, b) = *op {
                product_operand[a as usize] = true;
                product_operand[b as usize] = true;
            }
        }
        // The history nodes' ancestors, walking the tape backwards.
        let mut cone = product_operand.clone();
        for (k, op) in ops.iter().enumerate().rev() {
            if cone[k] {
                for a in op.operands() {
                    cone[a as usize] = true;
                }
            }
        }
        let history = product_operand.iter().filter(|&&h| h).count();
        let (mut low, mut high) = (0u32, history as u32);
        let slot: Vec<u32> = product_operand
            .iter()
            .map(|&h| {
                let s = if h { &mut low } else { &mut high };
                *s += 1;
                *s - 1
            })
            .collect();
        let at = |i: u32| slot[i as usize];
        let ops: Vec<Op> = ops.iter().map(|op| op.with_operands(at)).collect();
        let outputs = outputs.iter().map(|&o| at(o)).collect();
        let (cone_ops, cone_slot) =
            ops.iter().zip(&slot).zip(&cone).filter(|(_, &c)| c).map(|((&o, &s), _)| (o, s)).unzip();
        SeriesLayout { history, ops, slot, outputs, cone_ops, cone_slot }
    }

    /// Coefficients held for orders 0..=max_order.
    fn len(&self, max_order: usize) -> usize {
        max_order * self.history + self.slot.len()
    }
}

impl Tape {
    /// Record `kernel` on `inputs` variables. The kernel must be a
    /// polynomial: the four operations and constants only.
    pub fn record(inputs: usize, kernel: impl FnOnce(&[Var]) -> Vec<Var>) -> Tape {
        RECORDING.with(|r| {
            let mut r = r.borrow_mut();
            assert!(r.is_none(), "Tape::record does not nest");
            *r = Some((0..inputs).map(|i| Op::Input(i as u32)).collect());
        });
        // A kernel that panics must not leave the thread recording (every
        // later recording would then fail): the guard ends it on unwind.
        struct EndRecording;
        impl Drop for EndRecording {
            fn drop(&mut self) {
                RECORDING.with(|r| r.borrow_mut().take());
            }
        }
        let guard = EndRecording;
        let vars: Vec<Var> = (0..inputs as u32).map(Var).collect();
        let outputs = kernel(&vars);
        let ops = RECORDING.with(|r| r.borrow_mut().take().expect("recording in progress"));
        drop(guard);
        let mut degree: Vec<u32> = Vec::with_capacity(ops.len());
        let (deps, start, scatter_start, scatter) = if inputs <= 128 {
            Self::structure_by_masks(&ops, &mut degree)
        } else {
            Self::structure_by_lists(&ops, &mut degree)
        };
        let outputs: Vec<u32> = outputs.into_iter().map(|v| v.0).collect();
        let series = SeriesLayout::of(&ops, &outputs);
        Tape { ops, inputs, outputs, series, degree, deps, start, scatter_start, scatter }
    }

    /// Each node's degree and sorted dependencies (flat, node k's at
    /// deps[start[k]..start[k + 1]]) and the scatter positions of its
    /// operands' dependencies in its own (see [`Tape`]), with the inputs
    /// as bits of a u128: a union is an OR and a dependency's position in
    /// a node's list the count of the node's bits below it.
    #[allow(clippy::type_complexity)]
    fn structure_by_masks(ops: &[Op], degree: &mut Vec<u32>) -> (Vec<u32>, Vec<usize>, Vec<usize>, Vec<u32>) {
        let mut mask: Vec<u128> = Vec::with_capacity(ops.len());
        for op in ops {
            let (d, m) = match *op {
                Op::Input(i) => (1, 1u128 << i),
                Op::Const(_) => (0, 0),
                Op::Add(a, b) | Op::Sub(a, b) => {
                    (degree[a as usize].max(degree[b as usize]), mask[a as usize] | mask[b as usize])
                }
                Op::Mul(a, b) => (degree[a as usize] + degree[b as usize], mask[a as usize] | mask[b as usize]),
                Op::Neg(a) | Op::Scale(_, a) | Op::Shift(_, a) => (degree[a as usize], mask[a as usize]),
            };
            degree.push(d);
            mask.push(m);
        }
        let bits = |mut m: u128| {
            std::iter::from_fn(move || {
                (m != 0).then(|| {
                    let d = m.trailing_zeros();
                    m &= m - 1;
                    d
                })
            })
        };
        let total: usize = mask.iter().map(|m| m.count_ones() as usize).sum();
        let mut deps = Vec::with_capacity(total);
        let mut start = Vec::with_capacity(ops.len() + 1);
        let mut scatter_start = Vec::with_capacity(ops.len() + 1);
        let mut scatter = Vec::new();
        for (k, op) in ops.iter().enumerate() {
            start.push(deps.len());
            deps.extend(bits(mask[k]));
            scatter_start.push(scatter.len());
            if let Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) = *op {
                for operand in [a, b] {
                    for d in bits(mask[operand as usize]) {
                        scatter.push((mask[k] & ((1u128 << d) - 1)).count_ones());
                    }
                }
            }
        }
        start.push(deps.len());
        scatter_start.push(scatter.len());
        (deps, start, scatter_start, scatter)
    }

    /// [`Tape::structure_by_masks`] for tapes of more than 128 inputs:
    /// sorted lists merged node by node.
    #[allow(clippy::type_complexity)]
    fn structure_by_lists(ops: &[Op], degree: &mut Vec<u32>) -> (Vec<u32>, Vec<usize>, Vec<usize>, Vec<u32>) {
        let mut lists: Vec<Vec<u32>> = Vec::with_capacity(ops.len());
        for op in ops {
            let (d, s) = match *op {
                Op::Input(i) => (1, vec![i]),
                Op::Const(_) => (0, vec![]),
                Op::Add(a, b) | Op::Sub(a, b) => {
                    (degree[a as usize].max(degree[b as usize]), merge(&lists[a as usize], &lists[b as usize]))
                }
                Op::Mul(a, b) => {
                    (degree[a as usize] + degree[b as usize], merge(&lists[a as usize], &lists[b as usize]))
                }
                Op::Neg(a) | Op::Scale(_, a) | Op::Shift(_, a) => (degree[a as usize], lists[a as usize].clone()),
            };
            degree.push(d);
            lists.push(s);
        }
        let mut deps = Vec::new();
        let mut start = Vec::with_capacity(ops.len() + 1);
        let mut scatter_start = Vec::with_capacity(ops.len() + 1);
        let mut scatter = Vec::new();
        for (k, op) in ops.iter().enumerate() {
            start.push(deps.len());
            deps.extend_from_slice(&lists[k]);
            scatter_start.push(scatter.len());
            if let Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) = *op {
                for operand in [a, b] {
                    for d in &lists[operand as usize] {
                        scatter.push(lists[k].binary_search(d).expect("operand dependency is a dependency") as u32);
                    }
                }
            }
        }
        start.push(deps.len());
        scatter_start.push(scatter.len());
        (deps, start, scatter_start, scatter)
    }

    pub fn inputs(&self) -> usize {
        self.inputs
    }

    pub fn outputs(&self) -> usize {
        self.outputs.len()
    }

    /// Number of recorded operations (the cost unit of every evaluation).
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Highest polynomial degree of the outputs.
    pub fn degree(&self) -> u32 {
        self.outputs.iter().map(|&o| self.degree[o as usize]).max().unwrap_or(0)
    }

    /// Highest polynomial degree of the outputs in the inputs flagged in
    /// `variable` (the others count as constants: element length, a fixed
    /// load direction, …).
    pub fn degree_in(&self, variable: &[bool]) -> u32 {
        let mut deg: Vec<u32> = Vec::with_capacity(self.ops.len());
        for op in &self.ops {
            let d = match *op {
                Op::Input(i) => variable[i as usize] as u32,
                Op::Const(_) => 0,
                Op::Add(a, b) | Op::Sub(a, b) => deg[a as usize].max(deg[b as usize]),
                Op::Mul(a, b) => deg[a as usize] + deg[b as usize],
                Op::Neg(a) | Op::Scale(_, a) | Op::Shift(_, a) => deg[a as usize],
            };
            deg.push(d);
        }
        self.outputs.iter().map(|&o| deg[o as usize]).max().unwrap_or(0)
    }

    /// Whether `other` has the same inputs, outputs and structural
    /// dependencies of each output (what a Jacobian's pattern is built
    /// from), whatever its coefficients.
    pub fn same_dependencies(&self, other: &Tape) -> bool {
        std::ptr::eq(self, other)
            || (self.inputs == other.inputs
                && self.outputs.len() == other.outputs.len()
                && (0..self.outputs.len()).all(|k| self.dependencies(k) == other.dependencies(k)))
    }

    /// The inputs output `k` depends on (structural, sorted).
    pub fn dependencies(&self, k: usize) -> &[u32] {
        let o = self.outputs[k] as usize;
        &self.deps[self.start[o]..self.start[o + 1]]
    }

    /// Values of the outputs; `work` holds one value per node.
    pub fn eval(&self, x: &[f64], work: &mut Vec<f64>, out: &mut [f64]) {
        work.clear();
        work.reserve(self.ops.len());
        for op in &self.ops {
            let v = match *op {
                Op::Input(i) => x[i as usize],
                Op::Const(c) => c,
                Op::Add(a, b) => work[a as usize] + work[b as usize],
                Op::Sub(a, b) => work[a as usize] - work[b as usize],
                Op::Mul(a, b) => work[a as usize] * work[b as usize],
                Op::Neg(a) => -work[a as usize],
                Op::Scale(c, a) => c * work[a as usize],
                Op::Shift(c, a) => work[a as usize] + c,
            };
            work.push(v);
        }
        for (o, &i) in out.iter_mut().zip(&self.outputs) {
            *o = work[i as usize];
        }
    }

    /// Values and the dense local Jacobian ∂out_k/∂x_j, stored row-major in
    /// `jac` (outputs × inputs), by forward mode in which each node carries
    /// its gradient over its own dependencies only (a rod element's rotation
    /// matrix depends on 4 of its ~80 inputs): the cost is the sum of the
    /// nodes' dependency counts, not nodes × inputs.
    pub fn jacobian(&self, x: &[f64], work: &mut JacobianWork, out: &mut [f64], jac: &mut [f64]) {
        let n = self.inputs;
        work.val.clear();
        work.val.reserve(self.ops.len());
        work.grad.clear();
        work.grad.resize(self.start[self.ops.len()], 0.0);
        for (k, op) in self.ops.iter().enumerate() {
            let (head, tail) = work.grad.split_at_mut(self.start[k]);
            let g = &mut tail[..self.start[k + 1] - self.start[k]];
            let gv = |i: u32| &head[self.start[i as usize]..self.start[i as usize + 1]];
            let sc = &self.scatter[self.scatter_start[k]..self.scatter_start[k + 1]];
            let val = &work.val;
            let v = match *op {
                Op::Input(i) => {
                    g[0] = 1.0;
                    x[i as usize]
                }
                Op::Const(c) => c,
                Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) => {
                    let (ga, gb) = (gv(a), gv(b));
                    let (va, vb) = (val[a as usize], val[b as usize]);
                    let (ca, cb, v) = match *op {
                        Op::Add(..) => (1.0, 1.0, va + vb),
                        Op::Sub(..) => (1.0, -1.0, va - vb),
                        _ => (vb, va, va * vb),
                    };
                    let (sa, sb) = sc.split_at(ga.len());
                    for (d, &p) in ga.iter().zip(sa) {
                        g[p as usize] += ca * d;
                    }
                    for (d, &p) in gb.iter().zip(sb) {
                        g[p as usize] += cb * d;
                    }
                    v
                }
                Op::Neg(a) => {
                    for (gi, ai) in g.iter_mut().zip(gv(a)) {
                        *gi = -ai;
                    }
                    -val[a as usize]
                }
                Op::Scale(c, a) => {
                    for (gi, ai) in g.iter_mut().zip(gv(a)) {
                        *gi = c * ai;
                    }
                    c * val[a as usize]
                }
                Op::Shift(c, a) => {
                    g.copy_from_slice(gv(a));
                    val[a as usize] + c
                }
            };
            work.val.push(v);
        }
        jac[..n * self.outputs.len()].fill(0.0);
        for (k, &i) in self.outputs.iter().enumerate() {
            out[k] = work.val[i as usize];
            let g = &work.grad[self.start[i as usize]..self.start[i as usize + 1]];
            for (d, &j) in g.iter().zip(&self.deps[self.start[i as usize]..self.start[i as usize + 1]]) {
                jac[k * n + j as usize] = *d;
            }
        }
    }
}

fn merge(a: &[u32], b: &[u32]) -> Vec<u32> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        let next = match (a.get(i), b.get(j)) {
            (Some(&x), Some(&y)) if x == y => {
                i += 1;
                j += 1;
                x
            }
            (Some(&x), Some(&y)) if x < y => {
                i += 1;
                x
            }
            (Some(_), Some(&y)) => {
                j += 1;
                y
            }
            (Some(&x), None) => {
                i += 1;
                x
            }
            (None, Some(&y)) => {
                j += 1;
                y
            }
            (None, None) => unreachable!(),
        };
        out.push(next);
    }
    out
}

/// Reusable storage for [`Tape::jacobian`].
#[derive(Clone, Debug, Default)]
pub struct JacobianWork {
    val: Vec<f64>,
    grad: Vec<f64>,
}

/// Taylor coefficients of every node of one tape along a series of its
/// inputs, up to a maximal order: `coef[node·(P+1) + k]`.
#[derive(Clone, Debug, Default)]
pub struct TaylorWork {
    order: usize,
    coef: Vec<f64>,
    /// The order last computed and the input coefficients it used: a second
    /// call at the same order only propagates the change of the inputs,
    /// which is linear (O(1) per node instead of O(p)).
    last: Option<usize>,
    last_x: Vec<f64>,
    delta: Vec<f64>,
    /// The directional derivative's coefficients along a second series
    /// W(a) ([`TaylorWork::tangent_order`]): `tangent[node·(P+1) + k]`.
    tangent: Vec<f64>,
}

/// `v` at least `len` long, its contents kept (the series' passes write
/// every coefficient they later read: no zeroing between series).
pub(crate) fn grow<T: Copy>(v: &mut Vec<T>, len: usize, fill: T) {
    if v.len() < len {
        v.resize(len, fill);
    }
}

impl TaylorWork {
    /// Start a series at the point `x0` (order 0), for orders up to `max_order`.
    pub fn begin(&mut self, tape: &Tape, x0: &[f64], max_order: usize) {
        let stride = max_order + 1;
        self.order = max_order;
        // Not cleared: every pass writes its whole order before a later
        // one reads it.
        grow(&mut self.coef, tape.ops.len() * stride, 0.0);
        self.pass(tape, 0, &|i| x0[i]);
        self.last = Some(0);
        self.last_x.clear();
        self.last_x.resize(tape.inputs, 0.0);
    }

    /// Order-p coefficients of the outputs when the inputs' order-p
    /// coefficients are `xp` (orders below p must have been committed). Call
    /// with xp = 0 for the known part (the ANM right-hand side), then again
    /// with the solved xp to commit order p.
    pub fn order(&mut self, tape: &Tape, p: usize, xp: impl Fn(usize) -> f64, out: &mut [f64]) {
        assert!(p >= 1 && p <= self.order, "Taylor order {p} outside 1..={}", self.order);
        if self.last == Some(p) {
            self.update(tape, p, &xp);
        } else {
            self.pass(tape, p, &xp);
            self.last = Some(p);
        }
        for (i, v) in self.last_x.iter_mut().enumerate() {
            *v = xp(i);
        }
        let stride = self.order + 1;
        for (o, &i) in out.iter_mut().zip(&tape.outputs) {
            *o = self.coef[i as usize * stride + p];
        }
    }

    /// The order-p coefficient of the directional derivative of the
    /// outputs, J(X(a)) W(a), along the committed series X (every order
    /// up to the maximum) when W's order-p coefficients are `wp` (orders
    /// below p committed by earlier calls; p = 0 starts a new W). Linear
    /// in `wp`: call with wp = 0 for the known part, again with the solved
    /// wp to commit. Each node's derivative is propagated by the product
    /// rule on Cauchy products, d(xy)_p = Σ_i (dx_i y_{p−i} + x_i dy_{p−i}):
    /// O(p) per product, as the series itself (the ANM's bifurcation
    /// indicator, [`crate::continuation::anm`]).
    pub fn tangent_order(&mut self, tape: &Tape, p: usize, wp: impl Fn(usize) -> f64, out: &mut [f64]) {
        assert!(p <= self.order, "Taylor order {p} outside 0..={}", self.order);
        let stride = self.order + 1;
        if p == 0 {
            grow(&mut self.tangent, tape.ops.len() * stride, 0.0);
        }
        let (c, d) = (&self.coef, &mut self.tangent);
        for (k, op) in tape.ops.iter().enumerate() {
            let at = |i: u32, q: usize| i as usize * stride + q;
            let v = match *op {
                Op::Input(i) => wp(i as usize),
                Op::Const(_) => 0.0,
                Op::Add(a, b) => d[at(a, p)] + d[at(b, p)],
                Op::Sub(a, b) => d[at(a, p)] - d[at(b, p)],
                Op::Mul(a, b) => {
                    let (ab, bb) = (a as usize * stride, b as usize * stride);
                    let mut s = 0.0;
                    for i in 0..=p {
                        s += d[ab + i] * c[bb + p - i] + c[ab + i] * d[bb + p - i];
                    }
                    s
                }
                Op::Neg(a) => -d[at(a, p)],
                Op::Scale(sc, a) => sc * d[at(a, p)],
                Op::Shift(_, a) => d[at(a, p)],
            };
            d[k * stride + p] = v;
        }
        for (o, &i) in out.iter_mut().zip(&tape.outputs) {
            *o = d[i as usize * stride + p];
        }
    }

    /// The order-k coefficient of output `j` (committed orders only).
    pub fn output(&self, tape: &Tape, j: usize, k: usize) -> f64 {
        self.coef[tape.outputs[j] as usize * (self.order + 1) + k]
    }

    /// Order p again with new input coefficients: every node's order-p
    /// coefficient is affine in them (x_p enters products only through
    /// x_0·y_p + x_p·y_0), so the change propagates linearly.
    fn update(&mut self, tape: &Tape, p: usize, xp: &impl Fn(usize) -> f64) {
        let stride = self.order + 1;
        let c = &mut self.coef;
        // Every node's change is written before a later node reads it.
        let d = &mut self.delta;
        grow(d, tape.ops.len(), 0.0);
        for (k, op) in tape.ops.iter().enumerate() {
            let v = match *op {
                Op::Input(i) => xp(i as usize) - self.last_x[i as usize],
                Op::Const(_) => 0.0,
                Op::Add(a, b) => d[a as usize] + d[b as usize],
                Op::Sub(a, b) => d[a as usize] - d[b as usize],
                Op::Mul(a, b) => c[a as usize * stride] * d[b as usize] + d[a as usize] * c[b as usize * stride],
                Op::Neg(a) => -d[a as usize],
                Op::Scale(s, a) => s * d[a as usize],
                Op::Shift(_, a) => d[a as usize],
            };
            d[k] = v;
            c[k * stride + p] += v;
        }
    }

    fn pass(&mut self, tape: &Tape, p: usize, xp: &impl Fn(usize) -> f64) {
        let stride = self.order + 1;
        let c = &mut self.coef;
        for (k, op) in tape.ops.iter().enumerate() {
            let at = |i: u32, q: usize| i as usize * stride + q;
            let v = match *op {
                Op::Input(i) => xp(i as usize),
                Op::Const(v) => {
                    if p == 0 {
                        v
                    } else {
                        0.0
                    }
                }
                Op::Add(a, b) => c[at(a, p)] + c[at(b, p)],
                Op::Sub(a, b) => c[at(a, p)] - c[at(b, p)],
                Op::Mul(a, b) => {
                    // z_p = Σ_{i=0..p} x_i y_{p−i}, with four partial sums
                    // (independent chains the CPU can overlap).
                    let (ab, bb) = (a as usize * stride, b as usize * stride);
                    let x = &c[ab..ab + p + 1];
                    let y = &c[bb..bb + p + 1];
                    let mut s = [0.0; 4];
                    let mut i = 0;
                    while i + 4 <= p + 1 {
                        for k in 0..4 {
                            s[k] += x[i + k] * y[p - i - k];
                        }
                        i += 4;
                    }
                    while i <= p {
                        s[0] += x[i] * y[p - i];
                        i += 1;
                    }
                    (s[0] + s[1]) + (s[2] + s[3])
                }
                Op::Neg(a) => -c[at(a, p)],
                Op::Scale(s, a) => s * c[at(a, p)],
                Op::Shift(s, a) => {
                    if p == 0 {
                        c[at(a, 0)] + s
                    } else {
                        c[at(a, p)]
                    }
                }
            };
            c[k * stride + p] = v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A generic kernel: f(x, y, z) = (x·y·z + 2x − 1, y² − z·x + 3, −x).
    fn kernel<T: Scalar>(v: &[T]) -> Vec<T> {
        let (x, y, z) = (v[0], v[1], v[2]);
        vec![x * y * z + x * 2.0 - 1.0, y * y - z * x + 3.0, -x]
    }

    /// The batched series' layout, against the tape read directly: the
    /// history slots are exactly the products' operands, the slots are a
    /// permutation of the nodes, each op reads its operands' slots, the
    /// commit's cone holds the history and what it is computed from, and
    /// the storage is P·history + nodes.
    #[test]
    fn series_layout_packs_the_products_operands_first() {
        let tape = Tape::record(3, kernel);
        let layout = &tape.series;
        let n = tape.ops.len();
        let operands: std::collections::BTreeSet<u32> = tape
            .ops
            .iter()
            .filter_map(|op| if let Op::Mul(a, b) = *op { Some([a, b]) } else { None })
            .flatten()
            .collect();
        assert_eq!(layout.history, operands.len());
        assert!(layout.history > 0 && layout.history < n);
        let mut seen = vec![false; n];
        for (k, &s) in layout.slot.iter().enumerate() {
            assert!(!seen[s as usize], "slot {s} twice");
            seen[s as usize] = true;
            assert_eq!((s as usize) < layout.history, operands.contains(&(k as u32)), "node {k}");
        }
        let at = |i: u32| layout.slot[i as usize];
        for (op, mapped) in tape.ops.iter().zip(&layout.ops) {
            assert_eq!(*mapped, op.with_operands(at));
        }
        let outputs: Vec<u32> = tape.outputs.iter().map(|&o| at(o)).collect();
        assert_eq!(layout.outputs, outputs);
        // The cone: every history slot, closed under its ops' operands,
        // in the tape's order.
        let cone: std::collections::BTreeSet<u32> = layout.cone_slot.iter().copied().collect();
        assert!((0..layout.history as u32).all(|s| cone.contains(&s)));
        for op in &layout.cone_ops {
            assert!(op.operands().all(|a| cone.contains(&a)), "{op:?} reads outside the cone");
        }
        let order: Vec<usize> =
            layout.cone_slot.iter().map(|&s| layout.slot.iter().position(|&t| t == s).unwrap()).collect();
        assert!(order.windows(2).all(|w| w[0] < w[1]));
        for (&k, op) in order.iter().zip(&layout.cone_ops) {
            assert_eq!(layout.ops[k], *op);
        }
        assert!(layout.cone_ops.len() < n, "the output −x is outside the cone");
        assert_eq!(layout.len(9), 9 * layout.history + n);
        // A product of sums: its operands' ancestors (the inputs) join the
        // cone though they are no product's operand.
        let tape = Tape::record(3, |v: &[Var]| vec![(v[0] + v[1]) * (v[2] - 1.0), -v[0]]);
        let layout = &tape.series;
        assert_eq!(layout.history, 2);
        let cone: std::collections::BTreeSet<u32> = layout.cone_slot.iter().copied().collect();
        for input in 0..3 {
            assert!(cone.contains(&layout.slot[input]), "input {input} outside the cone");
        }
        assert_eq!(layout.cone_ops.len(), 5, "x, y, z, x + y, z − 1");
    }

    /// The tangent series of J(X(a)) W(a) against the same product formed
    /// from the Jacobian at points along the path (closed form of the
    /// polynomial path, exact to rounding): the series evaluated at a = 0.3
    /// equals J(X(0.3)) W(0.3).
    #[test]
    fn the_tangent_series_is_the_jacobian_along_the_path() {
        let tape = Tape::record(3, kernel);
        let order = 8;
        let xs = [[0.7, -1.3, 2.1], [0.2, 0.5, -0.4], [0.1, -0.3, 0.25], [0.05, 0.0, -0.1]];
        let ws = [[1.0, 0.5, -0.2], [-0.3, 0.4, 0.1], [0.2, 0.0, 0.3]];
        let mut t = TaylorWork::default();
        t.begin(&tape, &xs[0], order);
        let mut out = [0.0; 3];
        for p in 1..=order {
            let xp = |i: usize| xs.get(p).map_or(0.0, |x| x[i]);
            t.order(&tape, p, xp, &mut out);
        }
        let mut series = vec![[0.0; 3]; order + 1];
        for (p, s) in series.iter_mut().enumerate() {
            t.tangent_order(&tape, p, |i| ws.get(p).map_or(0.0, |w| w[i]), s);
        }
        let a: f64 = 0.3;
        let at = |c: &[[f64; 3]]| -> [f64; 3] {
            let mut v = [0.0; 3];
            for (p, ci) in c.iter().enumerate() {
                for i in 0..3 {
                    v[i] += ci[i] * a.powi(p as i32);
                }
            }
            v
        };
        let (x, w) = (at(&xs), at(&ws));
        let mut jw = JacobianWork::default();
        let mut jac = [0.0; 9];
        tape.jacobian(&x, &mut jw, &mut out, &mut jac);
        let got = at(&series);
        for r in 0..3 {
            let want: f64 = (0..3).map(|j| jac[r * 3 + j] * w[j]).sum();
            assert!((got[r] - want).abs() < 1e-13 * (1.0 + want.abs()), "row {r}: {} against {want}", got[r]);
        }
    }

    #[test]
    fn values_derivatives_and_degree_match_direct_evaluation() {
        let tape = Tape::record(3, kernel);
        assert_eq!(tape.degree(), 3);
        assert_eq!(tape.dependencies(2), &[0]);
        let x = [0.7, -1.3, 2.1];
        let direct = kernel(&x);
        let mut work = Vec::new();
        let mut out = [0.0; 3];
        tape.eval(&x, &mut work, &mut out);
        assert_eq!(out.to_vec(), direct);
        // Reference: the hand derivative.
        let mut jw = JacobianWork::default();
        let mut jac = [0.0; 9];
        tape.jacobian(&x, &mut jw, &mut out, &mut jac);
        let (a, b, c) = (x[0], x[1], x[2]);
        let want = [b * c + 2.0, a * c, a * b, -c, 2.0 * b, -a, -1.0, 0.0, 0.0];
        for (g, w) in jac.iter().zip(want) {
            assert!((g - w).abs() < 1e-15);
        }
    }

    /// Taylor coefficients along a polynomial path X(a) = x0 + a x1 + a² x2
    /// equal those of the composed polynomial (reference: expanding f(X(a))
    /// by sampling at 12 points and solving the Vandermonde system is
    /// ill-conditioned, so use exact rational-free checks: order 1 is J x1,
    /// and the full series summed at a = 0.3 reproduces f(X(0.3))).
    #[test]
    fn taylor_series_reproduces_the_composition() {
        let tape = Tape::record(3, kernel);
        let x0 = [0.7, -1.3, 2.1];
        let xs = [[0.2, 0.1, -0.4], [0.05, -0.3, 0.1]];
        let max = 6;
        let mut tw = TaylorWork::default();
        tw.begin(&tape, &x0, max);
        let mut series = vec![[0.0; 3]; max + 1];
        tape.eval(&x0, &mut Vec::new(), &mut series[0]);
        for p in 1..=max {
            let xp = |i: usize| if p <= 2 { xs[p - 1][i] } else { 0.0 };
            let mut out = [0.0; 3];
            tw.order(&tape, p, xp, &mut out);
            series[p] = out;
        }
        // Order 1 = J x1.
        let mut jac = [0.0; 9];
        tape.jacobian(&x0, &mut JacobianWork::default(), &mut [0.0; 3], &mut jac);
        for k in 0..3 {
            let jx: f64 = (0..3).map(|j| jac[k * 3 + j] * xs[0][j]).sum();
            assert!((series[1][k] - jx).abs() < 1e-14);
        }
        // A cubic of a quadratic path has degree 6: the series is exact.
        let a = 0.3f64;
        let xa: Vec<f64> = (0..3).map(|i| x0[i] + a * xs[0][i] + a * a * xs[1][i]).collect();
        let direct = kernel(&xa);
        for k in 0..3 {
            let summed: f64 = (0..=max).map(|p| series[p][k] * a.powi(p as i32)).sum();
            assert!((summed - direct[k]).abs() < 1e-14, "output {k}: {summed} vs {}", direct[k]);
        }
        // Committed orders are kept: re-reading order 1 of output 0.
        assert_eq!(tw.output(&tape, 0, 1), series[1][0]);
    }

    /// The structure from bit masks (tapes of ≤ 128 inputs) equals the one
    /// from merged sorted lists (the general path, the reference) on a
    /// kernel of 100 inputs mixing sums, products, scalings and constants,
    /// with inputs above 64 (the mask's upper word).
    #[test]
    fn structure_by_masks_equals_structure_by_lists() {
        let tape = Tape::record(100, |v| {
            let mut out = Vec::new();
            let mut acc = v[0] * v[99];
            for k in 1..100 {
                let t = (v[k] + v[(k * 37) % 100] * 2.0) * v[(k * 53 + 7) % 100] - 1.5;
                acc = if k % 3 == 0 { acc + t } else { (acc - t) * 0.5 };
                if k % 7 == 0 {
                    out.push(acc * v[k] + Var::constant(2.0));
                    acc = -t;
                }
            }
            out.push(acc);
            out
        });
        let (mut d1, mut d2) = (Vec::new(), Vec::new());
        let masks = Tape::structure_by_masks(&tape.ops, &mut d1);
        let lists = Tape::structure_by_lists(&tape.ops, &mut d2);
        assert_eq!(masks, lists);
        assert_eq!(d1, d2);
        assert!(tape.dependencies(0).iter().any(|&d| d >= 64), "the kernel reaches the mask's upper word");
    }

    /// A kernel that panics while recording leaves the thread able to
    /// record again (the guard ends the recording on unwind).
    #[test]
    fn a_panicking_kernel_does_not_poison_recording() {
        let caught = std::panic::catch_unwind(|| Tape::record(3, |_| panic!("kernel bug")));
        assert!(caught.is_err());
        let tape = Tape::record(3, kernel);
        let mut work = Vec::new();
        let mut out = [0.0; 3];
        tape.eval(&[1.0, 2.0, 3.0], &mut work, &mut out);
        assert_eq!(out, [1.0 * 2.0 * 3.0 + 2.0 - 1.0, 4.0 - 3.0 + 3.0, -1.0]);
    }
}

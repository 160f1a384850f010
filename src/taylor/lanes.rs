//! Number types that run a kernel as compiled code on [`LANES`] instances
//! at once, the tape's three evaluations without its interpreter: a kernel
//! written generic over [`Scalar`] is monomorphised for each type, so its
//! straight-line code is the program and every operation is inlined at
//! its call site (no per-op dispatch, constants folded in).
//!
//! * values: [`LaneValue`];
//! * derivatives: [`LaneDual`], values and the gradient over up to [`SEEDS`] seeded
//!   inputs (forward mode, dense over the seeds: a rod's right-hand side
//!   depends on 12 numbers, q, n_b, m_b, Λ and μ).
//! * series: [`LaneSeries`], Taylor coefficients order by order, as
//!   [`super::batch::BatchTaylorWork`] computes them. A straight-line
//!   kernel creates its intermediate values in the same order at every
//!   call, so the k-th value created is node k of a [`SeriesArena`] that
//!   keeps every node's lower-order coefficients between calls: the
//!   Cauchy product at order p costs O(p), as on the tape.
//!
//! Where lanes share one tape, the batched interpreter computes series
//! faster than [`LaneSeries`] (its dispatch is small beside the O(p)
//! Cauchy products; the arena's nodes are reached through a reference at
//! every op): [`crate::continuation::system`] takes series from the tape
//! there and from this type where the lanes' laws differ.
//!
//! Each type also multiplies by a lane array ([`Lanes`]), a constant that
//! differs between lanes (one element's law in each).
//!
//! The arithmetic is the tape's, operation by operation and in the same
//! order (the Cauchy sums too), except that [`LaneSeries`] folds
//! constants (c·x is a scaling, not a Cauchy product with a constant
//! series): for finite values, values and series equal the batched
//! tape's (a zero's sign, or 0·∞, may differ). The dual's gradient sums
//! the chain rule in another order than the tape's sparse forward mode,
//! so Jacobians equal it to rounding.

use super::batch::{map1, map2, Lanes, LANES};
use super::Scalar;
use std::cell::Cell;
use std::ops::{Add, Mul, Neg, Sub};

/// A [`Scalar`] that can also be multiplied by one constant per lane.
pub trait LaneScalar: Scalar + Mul<Lanes, Output = Self> {}

// ---------------------------------------------------------------- values

/// One value per lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneValue(pub Lanes);

impl Add for LaneValue {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        LaneValue(map2(self.0, o.0, |a, b| a + b))
    }
}
impl Sub for LaneValue {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        LaneValue(map2(self.0, o.0, |a, b| a - b))
    }
}
impl Mul for LaneValue {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        LaneValue(map2(self.0, o.0, |a, b| a * b))
    }
}
impl Neg for LaneValue {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        LaneValue(map1(self.0, |a| -a))
    }
}
impl Add<f64> for LaneValue {
    type Output = Self;
    #[inline(always)]
    fn add(self, c: f64) -> Self {
        LaneValue(map1(self.0, |a| a + c))
    }
}
impl Sub<f64> for LaneValue {
    type Output = Self;
    #[inline(always)]
    fn sub(self, c: f64) -> Self {
        // As the tape: x − c is recorded as x + (−c).
        LaneValue(map1(self.0, |a| a + -c))
    }
}
impl Mul<f64> for LaneValue {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: f64) -> Self {
        LaneValue(map1(self.0, |a| c * a))
    }
}
impl Mul<Lanes> for LaneValue {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: Lanes) -> Self {
        LaneValue(map2(self.0, c, |a, c| c * a))
    }
}
impl Scalar for LaneValue {
    #[inline(always)]
    fn constant(c: f64) -> Self {
        LaneValue([c; LANES])
    }
}
impl LaneScalar for LaneValue {}

// ------------------------------------------------------------------ duals

/// Seeded inputs a [`LaneDual`] carries derivatives for.
pub const SEEDS: usize = 12;

/// A value and its derivatives along [`SEEDS`] seeded inputs, per lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneDual {
    pub v: Lanes,
    pub d: [Lanes; SEEDS],
}

impl LaneDual {
    /// Input `seed` (its derivative 1 along itself), or a constant input
    /// when `seed` is None.
    #[inline(always)]
    pub fn input(v: Lanes, seed: Option<usize>) -> Self {
        let mut d = [[0.0; LANES]; SEEDS];
        if let Some(s) = seed {
            d[s] = [1.0; LANES];
        }
        LaneDual { v, d }
    }
}

impl Add for LaneDual {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        LaneDual {
            v: map2(self.v, o.v, |a, b| a + b),
            d: std::array::from_fn(|k| map2(self.d[k], o.d[k], |a, b| a + b)),
        }
    }
}
impl Sub for LaneDual {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        LaneDual {
            v: map2(self.v, o.v, |a, b| a - b),
            d: std::array::from_fn(|k| map2(self.d[k], o.d[k], |a, b| a - b)),
        }
    }
}
impl Mul for LaneDual {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        LaneDual {
            v: map2(self.v, o.v, |a, b| a * b),
            d: std::array::from_fn(|k| std::array::from_fn(|l| o.v[l] * self.d[k][l] + self.v[l] * o.d[k][l])),
        }
    }
}
impl Neg for LaneDual {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        LaneDual { v: map1(self.v, |a| -a), d: std::array::from_fn(|k| map1(self.d[k], |a| -a)) }
    }
}
impl Add<f64> for LaneDual {
    type Output = Self;
    #[inline(always)]
    fn add(self, c: f64) -> Self {
        LaneDual { v: map1(self.v, |a| a + c), d: self.d }
    }
}
impl Sub<f64> for LaneDual {
    type Output = Self;
    #[inline(always)]
    fn sub(self, c: f64) -> Self {
        LaneDual { v: map1(self.v, |a| a + -c), d: self.d }
    }
}
impl Mul<f64> for LaneDual {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: f64) -> Self {
        LaneDual { v: map1(self.v, |a| c * a), d: std::array::from_fn(|k| map1(self.d[k], |a| c * a)) }
    }
}
impl Mul<Lanes> for LaneDual {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: Lanes) -> Self {
        LaneDual { v: map2(self.v, c, |a, c| c * a), d: std::array::from_fn(|k| map2(self.d[k], c, |a, c| c * a)) }
    }
}
impl Scalar for LaneDual {
    #[inline(always)]
    fn constant(c: f64) -> Self {
        LaneDual::input([c; LANES], None)
    }
}
impl LaneScalar for LaneDual {}

// ----------------------------------------------------------------- series

/// What a run of the kernel over a [`SeriesArena`] computes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    /// Only number the nodes (the arena learns the kernel's size).
    Count,
    /// Every node's order-p coefficient from its operands' orders ≤ p.
    Pass(usize),
    /// Order p again after the inputs' order-p coefficients changed: the
    /// change is linear (x_p enters a product only as x_0 y_p + x_p y_0).
    Update(usize),
    /// Order p of the directional derivative along a second series.
    Tangent(usize),
}

/// Inputs a [`SeriesArena`] kernel may have.
pub const MAX_INPUTS: usize = 96;

/// The Taylor coefficients of every node of one kernel on [`LANES`]
/// instances, order-major (`coef[p·nodes + node]`, every order of every
/// node), kept between the order-by-order calls of one series.
#[derive(Clone, Debug, Default)]
pub struct SeriesArena {
    inputs: usize,
    nodes: usize,
    order: usize,
    coef: Vec<Lanes>,
    delta: Vec<Lanes>,
    tangent: Vec<Lanes>,
    last: Option<usize>,
    last_x: Vec<Lanes>,
}

/// One run of a kernel over an arena: the arena's storage seen as cells,
/// so that the kernel's values (Copy, as [`Scalar`] asks) can write their
/// node's coefficient through a shared reference.
#[derive(Debug)]
pub struct Run<'a> {
    mode: Mode,
    next: Cell<u32>,
    nodes: usize,
    coef: &'a [Cell<Lanes>],
    delta: &'a [Cell<Lanes>],
    tangent: &'a [Cell<Lanes>],
}

/// A value in a kernel run over a [`SeriesArena`]: a constant (folded,
/// no node: its series is itself in order 0 and zero above), or a node.
/// Whether a value is a constant depends on the kernel's code alone, not
/// on its data, so every run creates the same nodes.
#[derive(Clone, Copy, Debug)]
pub enum LaneSeries<'a> {
    Const(Lanes),
    Node(&'a Run<'a>, u32),
}

fn cells(v: &mut [Lanes]) -> &[Cell<Lanes>] {
    Cell::from_mut(v).as_slice_of_cells()
}

impl SeriesArena {
    /// An arena for a kernel of `inputs` inputs; `count` runs the kernel
    /// once on the input nodes (no value is computed) to learn how many
    /// nodes it creates.
    pub fn new(inputs: usize, count: impl FnOnce(&[LaneSeries<'_>])) -> Self {
        assert!(inputs <= MAX_INPUTS, "a compiled series kernel has at most {MAX_INPUTS} inputs");
        let mut arena = SeriesArena { inputs, ..Default::default() };
        arena.nodes = arena.run(Mode::Count, count);
        arena
    }

    /// Number the input nodes 0..inputs, run the kernel in `mode`; the
    /// number of nodes it created.
    fn run(&mut self, mode: Mode, kernel: impl FnOnce(&[LaneSeries<'_>])) -> usize {
        let run = Run {
            mode,
            next: Cell::new(self.inputs as u32),
            nodes: self.nodes,
            coef: cells(&mut self.coef),
            delta: cells(&mut self.delta),
            tangent: cells(&mut self.tangent),
        };
        {
            // The input nodes on the stack (a rod element has at most 81).
            let vars: [LaneSeries<'_>; MAX_INPUTS] = std::array::from_fn(|id| LaneSeries::Node(&run, id as u32));
            kernel(&vars[..self.inputs]);
        }
        let created = run.next.get() as usize;
        assert!(
            mode == Mode::Count || created == self.nodes,
            "a compiled kernel created {created} nodes, {} when counted: it is not straight-line",
            self.nodes
        );
        created
    }

    /// Start the lanes' series at `x0`, orders up to `max_order`; the
    /// kernel reads its outputs with [`LaneSeries::value`].
    pub fn begin(&mut self, x0: &[Lanes], max_order: usize, kernel: impl FnOnce(&[LaneSeries<'_>])) {
        self.order = max_order;
        super::grow(&mut self.coef, self.nodes * (max_order + 1), [0.0; LANES]);
        super::grow(&mut self.delta, self.nodes, [0.0; LANES]);
        self.coef[..self.inputs].copy_from_slice(&x0[..self.inputs]);
        self.run(Mode::Pass(0), kernel);
        self.last = Some(0);
        self.last_x.clear();
        self.last_x.resize(self.inputs, [0.0; LANES]);
    }

    /// Order p with the inputs' order-p coefficients `xp` (orders below p
    /// committed): the first call at an order computes it, a second one
    /// (the commit after the solve) updates it linearly.
    pub fn order(&mut self, p: usize, xp: &[Lanes], kernel: impl FnOnce(&[LaneSeries<'_>])) {
        assert!(p >= 1 && p <= self.order, "Taylor order {p} outside 1..={}", self.order);
        let n = self.nodes;
        if self.last == Some(p) {
            for (i, x) in xp.iter().enumerate().take(self.inputs) {
                let d = map2(*x, self.last_x[i], |a, b| a - b);
                self.delta[i] = d;
                let c = &mut self.coef[p * n + i];
                *c = map2(*c, d, |a, b| a + b);
            }
            self.run(Mode::Update(p), kernel);
        } else {
            self.coef[p * n..p * n + self.inputs].copy_from_slice(&xp[..self.inputs]);
            self.run(Mode::Pass(p), kernel);
            self.last = Some(p);
        }
        self.last_x.copy_from_slice(&xp[..self.inputs]);
    }

    /// Order p of the directional derivative along W (p = 0 starts it),
    /// W's order-p coefficients `wp`; the committed series X is used.
    pub fn tangent_order(&mut self, p: usize, wp: &[Lanes], kernel: impl FnOnce(&[LaneSeries<'_>])) {
        assert!(p <= self.order, "Taylor order {p} outside 0..={}", self.order);
        let n = self.nodes;
        super::grow(&mut self.tangent, n * (self.order + 1), [0.0; LANES]);
        self.tangent[p * n..p * n + self.inputs].copy_from_slice(&wp[..self.inputs]);
        self.run(Mode::Tangent(p), kernel);
    }
}

impl<'a> Run<'a> {
    /// A new node, its order-p coefficient (or update, or tangent) from
    /// `pass`, `update`, `tangent`.
    #[inline(always)]
    fn push(
        &'a self,
        pass: impl FnOnce(&Self, usize, usize) -> Lanes,
        update: impl FnOnce(&Self) -> Lanes,
        tangent: impl FnOnce(&Self, usize, usize) -> Lanes,
    ) -> LaneSeries<'a> {
        let id = self.next.get();
        self.next.set(id + 1);
        let k = id as usize;
        let n = self.nodes;
        match self.mode {
            Mode::Pass(p) => self.coef[p * n + k].set(pass(self, p, n)),
            Mode::Update(p) => {
                let d = update(self);
                self.delta[k].set(d);
                let c = &self.coef[p * n + k];
                c.set(map2(c.get(), d, |a, b| a + b));
            }
            Mode::Tangent(p) => self.tangent[p * n + k].set(tangent(self, p, n)),
            Mode::Count => {}
        }
        LaneSeries::Node(self, id)
    }

    /// A node linear in one operand (negation, scaling): `f` applied to
    /// the operand's coefficient in every mode.
    #[inline(never)]
    fn linear1(&'a self, a: u32, f: impl Fn(Lanes) -> Lanes + Copy) -> LaneSeries<'a> {
        let a = a as usize;
        self.push(
            |s, p, n| f(s.coef[p * n + a].get()),
            |s| f(s.delta[a].get()),
            |s, p, n| f(s.tangent[p * n + a].get()),
        )
    }

    /// A node linear in two operands (sum, difference).
    #[inline(never)]
    fn linear2(&'a self, a: u32, b: u32, f: impl Fn(Lanes, Lanes) -> Lanes + Copy) -> LaneSeries<'a> {
        let (a, b) = (a as usize, b as usize);
        self.push(
            |s, p, n| f(s.coef[p * n + a].get(), s.coef[p * n + b].get()),
            |s| f(s.delta[a].get(), s.delta[b].get()),
            |s, p, n| f(s.tangent[p * n + a].get(), s.tangent[p * n + b].get()),
        )
    }

    /// x·sign + c with c in order 0 only (a shift, or c − x).
    #[inline(never)]
    fn shift(&'a self, a: u32, sign: f64, c: Lanes) -> LaneSeries<'a> {
        let a = a as usize;
        self.push(
            |s, p, n| {
                let x = map1(s.coef[p * n + a].get(), |v| sign * v);
                if p == 0 {
                    map2(x, c, |v, c| v + c)
                } else {
                    x
                }
            },
            |s| map1(s.delta[a].get(), |v| sign * v),
            |s, p, n| map1(s.tangent[p * n + a].get(), |v| sign * v),
        )
    }

    #[inline(never)]
    fn product(&'a self, a: u32, b: u32) -> LaneSeries<'a> {
        let (a, b) = (a as usize, b as usize);
        self.push(
            // z_p = Σ_{i=0..p} x_i y_{p−i}, lane by lane, in the tape's order.
            |s, p, n| {
                let mut acc = [0.0; LANES];
                for i in 0..=p {
                    let (x, y) = (s.coef[i * n + a].get(), s.coef[(p - i) * n + b].get());
                    for l in 0..LANES {
                        acc[l] += x[l] * y[l];
                    }
                }
                acc
            },
            |s| {
                let (ca, cb) = (s.coef[a].get(), s.coef[b].get());
                let (da, db) = (s.delta[a].get(), s.delta[b].get());
                std::array::from_fn(|l| ca[l] * db[l] + da[l] * cb[l])
            },
            |s, p, n| {
                let mut acc = [0.0; LANES];
                for i in 0..=p {
                    let (da, cb) = (s.tangent[i * n + a].get(), s.coef[(p - i) * n + b].get());
                    let (ca, db) = (s.coef[i * n + a].get(), s.tangent[(p - i) * n + b].get());
                    for l in 0..LANES {
                        acc[l] += da[l] * cb[l] + ca[l] * db[l];
                    }
                }
                acc
            },
        )
    }
}

impl<'a> LaneSeries<'a> {
    /// The order-p coefficient the run computed: of the series, or of
    /// its tangent in a tangent run (`tangent`); a constant's own.
    #[inline]
    pub fn value(self, p: usize, tangent: bool) -> Lanes {
        match self {
            LaneSeries::Const(c) => {
                if p == 0 && !tangent {
                    c
                } else {
                    [0.0; LANES]
                }
            }
            LaneSeries::Node(run, id) => {
                let i = p * run.nodes + id as usize;
                if tangent {
                    run.tangent[i].get()
                } else {
                    run.coef[i].get()
                }
            }
        }
    }
}

impl<'a> Add for LaneSeries<'a> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        use LaneSeries::*;
        match (self, o) {
            (Const(a), Const(b)) => Const(map2(a, b, |x, y| x + y)),
            (Node(s, a), Const(c)) | (Const(c), Node(s, a)) => s.shift(a, 1.0, c),
            (Node(s, a), Node(_, b)) => s.linear2(a, b, |x, y| map2(x, y, |a, b| a + b)),
        }
    }
}
impl<'a> Sub for LaneSeries<'a> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        use LaneSeries::*;
        match (self, o) {
            (Const(a), Const(b)) => Const(map2(a, b, |x, y| x - y)),
            (Node(s, a), Const(c)) => s.shift(a, 1.0, map1(c, |v| -v)),
            (Const(c), Node(s, a)) => s.shift(a, -1.0, c),
            (Node(s, a), Node(_, b)) => s.linear2(a, b, |x, y| map2(x, y, |a, b| a - b)),
        }
    }
}
impl<'a> Mul for LaneSeries<'a> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        use LaneSeries::*;
        match (self, o) {
            (Const(a), Const(b)) => Const(map2(a, b, |x, y| x * y)),
            (Node(s, a), Const(c)) | (Const(c), Node(s, a)) => s.linear1(a, move |x| map2(x, c, |v, c| c * v)),
            (Node(s, a), Node(_, b)) => s.product(a, b),
        }
    }
}
impl<'a> Neg for LaneSeries<'a> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        match self {
            LaneSeries::Const(c) => LaneSeries::Const(map1(c, |v| -v)),
            LaneSeries::Node(s, a) => s.linear1(a, |x| map1(x, |v| -v)),
        }
    }
}
impl<'a> Mul<f64> for LaneSeries<'a> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: f64) -> Self {
        self * [c; LANES]
    }
}
impl<'a> Mul<Lanes> for LaneSeries<'a> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: Lanes) -> Self {
        match self {
            LaneSeries::Const(a) => LaneSeries::Const(map2(a, c, |x, c| c * x)),
            LaneSeries::Node(s, a) => s.linear1(a, move |x| map2(x, c, |v, c| c * v)),
        }
    }
}
impl<'a> Add<f64> for LaneSeries<'a> {
    type Output = Self;
    #[inline(always)]
    fn add(self, c: f64) -> Self {
        self + LaneSeries::Const([c; LANES])
    }
}
impl<'a> Sub<f64> for LaneSeries<'a> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, c: f64) -> Self {
        self + LaneSeries::Const([-c; LANES])
    }
}
impl<'a> Scalar for LaneSeries<'a> {
    #[inline(always)]
    fn constant(c: f64) -> Self {
        LaneSeries::Const([c; LANES])
    }
}
impl<'a> LaneScalar for LaneSeries<'a> {}

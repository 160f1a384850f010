//! [`super::TaylorWork`] on [`LANES`] instances of one tape at once: a
//! rod's elements share one recorded kernel, so their Taylor passes are
//! the same straight-line program on different inputs. The coefficients
//! are stored order-major and lane by lane (`coef[k·history + slot][lane]`,
//! the tape's [`super::SeriesLayout`]: only the products' operands keep
//! their lower orders): the interpretive dispatch of an op is paid once
//! for all lanes, the arithmetic on a lane array is vectorised, and a
//! pass at order p (or its linear update) writes one contiguous slab and
//! reads the products' operands' histories, which are packed together —
//! with node-major storage every operand of every op was a cache line of
//! its own.
//!
//! The arithmetic is that of the scalar work, lane by lane, except the
//! order of the Cauchy products' partial sums: results agree with it to
//! rounding, not bitwise.

use super::{Op, SeriesLayout, Tape};
use std::cell::RefCell;

/// Tape instances evaluated together.
pub const LANES: usize = 4;

/// One value per lane.
pub type Lanes = [f64; LANES];

#[derive(Clone, Debug, Default)]
pub struct BatchTaylorWork {
    order: usize,
    coef: Vec<Lanes>,
    /// As [`super::TaylorWork`]: the order last computed and its input
    /// coefficients, for the linear update of a second call.
    last: Option<usize>,
    last_x: Vec<Lanes>,
    delta: Vec<Lanes>,
    tangent: Vec<Lanes>,
}

/// Coefficient arrays of dropped works, kept for the next series on this
/// thread. A sweep of rod solves builds a new system each time, and a fresh
/// array (history × orders + nodes, times lanes) costs a page fault at the
/// first touch of each page. A work takes the smallest pooled array long
/// enough for its series; its contents are stale, which the passes allow
/// (a pass writes every slot of its order, a commit every slot of the cone,
/// before anything reads them).
/// Bounded: [`POOL_ARRAYS`] arrays of at most [`POOL_ARRAY_BYTES`] each
/// (by capacity); a full pool keeps the larger arrays.
const POOL_ARRAYS: usize = 8;
const POOL_ARRAY_BYTES: usize = 16 << 20;

thread_local! {
    static POOL: RefCell<Vec<Vec<Lanes>>> = const { RefCell::new(Vec::new()) };
}

/// `v` at least `len` long: grown in place, or swapped for a pooled array
/// that is long enough (v's own array goes back to the pool). A pooled
/// array's contents are stale.
pub(crate) fn grow_pooled(v: &mut Vec<Lanes>, len: usize) {
    if v.len() >= len {
        return;
    }
    let pooled = POOL
        .try_with(|pool| {
            let mut pool = pool.borrow_mut();
            let best = (0..pool.len()).filter(|&i| pool[i].len() >= len).min_by_key(|&i| pool[i].len());
            best.map(|i| pool.swap_remove(i))
        })
        .ok()
        .flatten();
    match pooled {
        Some(array) => give_back(std::mem::replace(v, array)),
        None => super::grow(v, len, [0.0; LANES]),
    }
}

/// Return an array to the pool. Dropped when it is larger than the bound
/// or the thread is ending; a full pool drops its smallest array instead
/// when this one is larger (a sweep's small arrays must not hold the places
/// of a later sweep's larger ones).
pub(crate) fn give_back(v: Vec<Lanes>) {
    if v.is_empty() || v.capacity() * std::mem::size_of::<Lanes>() > POOL_ARRAY_BYTES {
        return;
    }
    let _ = POOL.try_with(|pool| {
        let mut pool = pool.borrow_mut();
        if pool.len() < POOL_ARRAYS {
            pool.push(v);
        } else if let Some(i) = (0..pool.len()).min_by_key(|&i| pool[i].len()).filter(|&i| pool[i].len() < v.len()) {
            pool[i] = v;
        }
    });
}

impl Drop for BatchTaylorWork {
    fn drop(&mut self) {
        give_back(std::mem::take(&mut self.coef));
        give_back(std::mem::take(&mut self.tangent));
    }
}

/// `f` lane by lane on two lane arrays.
#[inline(always)]
pub(super) fn map2(a: Lanes, b: Lanes, f: impl Fn(f64, f64) -> f64) -> Lanes {
    std::array::from_fn(|l| f(a[l], b[l]))
}

/// `f` lane by lane on one lane array.
#[inline(always)]
pub(super) fn map1(a: Lanes, f: impl Fn(f64) -> f64) -> Lanes {
    std::array::from_fn(|l| f(a[l]))
}

impl BatchTaylorWork {
    /// Start the lanes' series at `x0` (one lane array per input), orders
    /// up to `max_order`. The coefficients are stored as the tape's
    /// [`super::SeriesLayout`] says: order p of slot s at p·history + s.
    pub fn begin(&mut self, tape: &Tape, x0: &[Lanes], max_order: usize) {
        self.order = max_order;
        // Not cleared: a pass writes its whole order (a commit the cone)
        // before a later one reads it (zeroing the arrays each step was
        // ~10 % of a small run).
        let layout = &tape.series;
        grow_pooled(&mut self.coef, layout.len(max_order));
        self.pass(layout, (&layout.ops, &layout.slot), 0, x0);
        self.last = Some(0);
        self.last_x.clear();
        self.last_x.resize(tape.inputs, [0.0; LANES]);
    }

    /// As [`super::TaylorWork::order`], on every lane: `xp` the inputs'
    /// order-p coefficients, `out` the outputs'.
    pub fn order(&mut self, tape: &Tape, p: usize, xp: &[Lanes], out: &mut [Lanes]) {
        assert!(p >= 1 && p <= self.order, "Taylor order {p} outside 1..={}", self.order);
        let layout = &tape.series;
        if self.last == Some(p) {
            self.update(layout, (&layout.ops, &layout.slot), p, xp);
        } else {
            self.pass(layout, (&layout.ops, &layout.slot), p, xp);
            self.last = Some(p);
        }
        self.last_x.copy_from_slice(xp);
        let slab = &self.coef[p * tape.series.history..];
        for (o, &i) in out.iter_mut().zip(&tape.series.outputs) {
            *o = slab[i as usize];
        }
    }

    /// Commit order p with the inputs' coefficients `xp`, as a second
    /// [`BatchTaylorWork::order`] call does, without the outputs: only
    /// the tape's cone of history nodes is computed (the nodes a later
    /// order reads). The other nodes' order p is then stale: a later call
    /// at order p runs a whole pass.
    pub fn commit(&mut self, tape: &Tape, p: usize, xp: &[Lanes]) {
        assert!(p >= 1 && p <= self.order, "Taylor order {p} outside 1..={}", self.order);
        let layout = &tape.series;
        let cone = (&layout.cone_ops[..], &layout.cone_slot[..]);
        if self.last == Some(p) {
            self.update(layout, cone, p, xp);
        } else {
            self.pass(layout, cone, p, xp);
        }
        self.last = None;
    }

    /// As [`super::TaylorWork::tangent_order`], on every lane. Orders are
    /// taken in sequence from 0 (the tangent's storage overlaps as the
    /// series').
    pub fn tangent_order(&mut self, tape: &Tape, p: usize, wp: &[Lanes], out: &mut [Lanes]) {
        assert!(p <= self.order, "Taylor order {p} outside 0..={}", self.order);
        let layout = &tape.series;
        let h = layout.history;
        if p == 0 {
            grow_pooled(&mut self.tangent, layout.len(self.order));
        }
        let (c, d) = (&self.coef, &mut self.tangent);
        for (op, &k) in layout.ops.iter().zip(&layout.slot) {
            let at = |i: u32| p * h + i as usize;
            let v = match *op {
                Op::Input(i) => wp[i as usize],
                Op::Const(_) => [0.0; LANES],
                Op::Add(a, b) => map2(d[at(a)], d[at(b)], |x, y| x + y),
                Op::Sub(a, b) => map2(d[at(a)], d[at(b)], |x, y| x - y),
                Op::Mul(a, b) => {
                    // As the pass's products: the operands' histories,
                    // whole slabs, one bounds check each.
                    let (a, b) = (a as usize, b as usize);
                    let cs = c[..(p + 1) * h].chunks_exact(h);
                    let ds = d[..(p + 1) * h].chunks_exact(h);
                    let mut s = [0.0; LANES];
                    for ((cx, dx), (cy, dy)) in cs.clone().zip(ds.clone()).zip(cs.rev().zip(ds.rev())) {
                        let (da, cb, ca, db) = (dx[a], cy[b], cx[a], dy[b]);
                        for l in 0..LANES {
                            s[l] += da[l] * cb[l] + ca[l] * db[l];
                        }
                    }
                    s
                }
                Op::Neg(a) => map1(d[at(a)], |x| -x),
                Op::Scale(sc, a) => map1(d[at(a)], |x| sc * x),
                Op::Shift(_, a) => d[at(a)],
            };
            d[p * h + k as usize] = v;
        }
        for (o, &i) in out.iter_mut().zip(&layout.outputs) {
            *o = d[p * h + i as usize];
        }
    }

    /// Order p again with new input coefficients: the change propagates
    /// linearly (see [`super::TaylorWork`]); the products read their
    /// operands' order 0, a history.
    ///
    /// `ops` (with their `slots`): the whole tape, or a commit's cone.
    fn update(&mut self, layout: &SeriesLayout, (ops, slots): (&[Op], &[u32]), p: usize, xp: &[Lanes]) {
        let (h, nodes) = (layout.history, layout.slot.len());
        let (c0, cp) = self.coef.split_at_mut(p * h);
        let (c0, cp) = (&c0[..h], &mut cp[..nodes]);
        // Every node's change is written before a later node reads it.
        let d = &mut self.delta;
        super::grow(d, nodes, [0.0; LANES]);
        for (op, &k) in ops.iter().zip(slots) {
            let v = match *op {
                Op::Input(i) => map2(xp[i as usize], self.last_x[i as usize], |x, y| x - y),
                Op::Const(_) => [0.0; LANES],
                Op::Add(a, b) => map2(d[a as usize], d[b as usize], |x, y| x + y),
                Op::Sub(a, b) => map2(d[a as usize], d[b as usize], |x, y| x - y),
                Op::Mul(a, b) => {
                    let (ca, cb, da, db) = (c0[a as usize], c0[b as usize], d[a as usize], d[b as usize]);
                    std::array::from_fn(|l| ca[l] * db[l] + da[l] * cb[l])
                }
                Op::Neg(a) => map1(d[a as usize], |x| -x),
                Op::Scale(s, a) => map1(d[a as usize], |x| s * x),
                Op::Shift(_, a) => d[a as usize],
            };
            let k = k as usize;
            d[k] = v;
            let slot = &mut cp[k];
            *slot = map2(*slot, v, |x, y| x + y);
        }
    }

    /// `ops` (with their `slots`): the whole tape, or a commit's cone.
    fn pass(&mut self, layout: &SeriesLayout, (ops, slots): (&[Op], &[u32]), p: usize, xp: &[Lanes]) {
        let h = layout.history;
        let c = &mut self.coef;
        for (op, &k) in ops.iter().zip(slots) {
            let at = |i: u32| p * h + i as usize;
            let v = match *op {
                Op::Input(i) => xp[i as usize],
                Op::Const(v) => [if p == 0 { v } else { 0.0 }; LANES],
                Op::Add(a, b) => map2(c[at(a)], c[at(b)], |x, y| x + y),
                Op::Sub(a, b) => map2(c[at(a)], c[at(b)], |x, y| x - y),
                Op::Mul(a, b) => {
                    // z_p = Σ_{i=0..p} x_i y_{p−i}, lane by lane, over the
                    // operands' histories (orders `history` apart): walked
                    // by strided iterators, which check their bounds once
                    // (indexing checked each of the 2(p + 1) reads).
                    let (a, b) = (a as usize, b as usize);
                    let slabs = c[..(p + 1) * h].chunks_exact(h);
                    let mut s = [0.0; LANES];
                    for (sx, sy) in slabs.clone().zip(slabs.rev()) {
                        let (xi, yi) = (sx[a], sy[b]);
                        for l in 0..LANES {
                            s[l] += xi[l] * yi[l];
                        }
                    }
                    s
                }
                Op::Neg(a) => map1(c[at(a)], |x| -x),
                Op::Scale(s, a) => map1(c[at(a)], |x| s * x),
                Op::Shift(s, a) => {
                    if p == 0 {
                        map1(c[at(a)], |x| x + s)
                    } else {
                        c[at(a)]
                    }
                }
            };
            c[p * h + k as usize] = v;
        }
    }
}

/// Reusable storage for [`eval_lanes`] and [`jacobian_lanes`].
#[derive(Clone, Debug, Default)]
pub struct BatchJacobianWork {
    val: Vec<Lanes>,
    grad: Vec<Lanes>,
}

/// [`Tape::eval`] on every lane: `x` one lane array per input.
pub fn eval_lanes(tape: &Tape, x: &[Lanes], work: &mut BatchJacobianWork, out: &mut [Lanes]) {
    let val = &mut work.val;
    val.clear();
    val.reserve(tape.ops.len());
    for op in &tape.ops {
        let v = match *op {
            Op::Input(i) => x[i as usize],
            Op::Const(c) => [c; LANES],
            Op::Add(a, b) => map2(val[a as usize], val[b as usize], |p, q| p + q),
            Op::Sub(a, b) => map2(val[a as usize], val[b as usize], |p, q| p - q),
            Op::Mul(a, b) => map2(val[a as usize], val[b as usize], |p, q| p * q),
            Op::Neg(a) => map1(val[a as usize], |p| -p),
            Op::Scale(c, a) => map1(val[a as usize], |p| c * p),
            Op::Shift(c, a) => map1(val[a as usize], |p| p + c),
        };
        val.push(v);
    }
    for (o, &i) in out.iter_mut().zip(&tape.outputs) {
        *o = val[i as usize];
    }
}

/// [`Tape::jacobian`] on every lane: the outputs' values and the dense
/// local Jacobians, row-major (outputs × inputs), lane by lane — the same
/// sparse forward mode, each node's gradient over its own dependencies.
pub fn jacobian_lanes(tape: &Tape, x: &[Lanes], work: &mut BatchJacobianWork, out: &mut [Lanes], jac: &mut [Lanes]) {
    let n = tape.inputs;
    work.val.clear();
    work.val.reserve(tape.ops.len());
    work.grad.clear();
    work.grad.resize(tape.start[tape.ops.len()], [0.0; LANES]);
    for (k, op) in tape.ops.iter().enumerate() {
        let (head, tail) = work.grad.split_at_mut(tape.start[k]);
        let g = &mut tail[..tape.start[k + 1] - tape.start[k]];
        let gv = |i: u32| &head[tape.start[i as usize]..tape.start[i as usize + 1]];
        let sc = &tape.scatter[tape.scatter_start[k]..tape.scatter_start[k + 1]];
        let val = &work.val;
        let v = match *op {
            Op::Input(i) => {
                g[0] = [1.0; LANES];
                x[i as usize]
            }
            Op::Const(c) => [c; LANES],
            Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) => {
                let (ga, gb) = (gv(a), gv(b));
                let (va, vb) = (val[a as usize], val[b as usize]);
                let (ca, cb, v) = match *op {
                    Op::Add(..) => ([1.0; LANES], [1.0; LANES], map2(va, vb, |p, q| p + q)),
                    Op::Sub(..) => ([1.0; LANES], [-1.0; LANES], map2(va, vb, |p, q| p - q)),
                    _ => (vb, va, map2(va, vb, |p, q| p * q)),
                };
                let (sa, sb) = sc.split_at(ga.len());
                for (d, &p) in ga.iter().zip(sa) {
                    let slot = &mut g[p as usize];
                    *slot = std::array::from_fn(|l| slot[l] + ca[l] * d[l]);
                }
                for (d, &p) in gb.iter().zip(sb) {
                    let slot = &mut g[p as usize];
                    *slot = std::array::from_fn(|l| slot[l] + cb[l] * d[l]);
                }
                v
            }
            Op::Neg(a) => {
                for (gi, ai) in g.iter_mut().zip(gv(a)) {
                    *gi = map1(*ai, |p| -p);
                }
                map1(val[a as usize], |p| -p)
            }
            Op::Scale(c, a) => {
                for (gi, ai) in g.iter_mut().zip(gv(a)) {
                    *gi = map1(*ai, |p| c * p);
                }
                map1(val[a as usize], |p| c * p)
            }
            Op::Shift(c, a) => {
                g.copy_from_slice(gv(a));
                map1(val[a as usize], |p| p + c)
            }
        };
        work.val.push(v);
    }
    jac[..n * tape.outputs.len()].fill([0.0; LANES]);
    for (k, &i) in tape.outputs.iter().enumerate() {
        out[k] = work.val[i as usize];
        let g = &work.grad[tape.start[i as usize]..tape.start[i as usize + 1]];
        for (d, &j) in g.iter().zip(&tape.deps[tape.start[i as usize]..tape.start[i as usize + 1]]) {
            jac[k * n + j as usize] = *d;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Scalar, TaylorWork};
    use super::*;

    fn kernel<T: Scalar>(v: &[T]) -> Vec<T> {
        let (x, y, z) = (v[0], v[1], v[2]);
        vec![x * y * z + x * 2.0 - 1.0, y * y - z * x + 3.0, -(x * (y + 0.5)) * (z - 2.0)]
    }

    /// The tangent series of every order, batched against the scalar work
    /// on each lane (W's coefficients `lanes(p + 20)`), to 1e-13 relative.
    fn tangents_agree(
        tape: &Tape,
        batch: &mut BatchTaylorWork,
        scalar: &mut [TaylorWork],
        order: usize,
        lanes: &dyn Fn(usize) -> Vec<Lanes>,
    ) {
        let (mut out, mut one) = (vec![[0.0; LANES]; 3], vec![0.0; 3]);
        for p in 0..=order {
            let wp = lanes(p + 20);
            batch.tangent_order(tape, p, &wp, &mut out);
            for (l, w) in scalar.iter_mut().enumerate() {
                w.tangent_order(tape, p, |i| wp[i][l], &mut one);
                for j in 0..3 {
                    let (a, b) = (out[j][l], one[j]);
                    assert!((a - b).abs() <= 1e-13 * (1.0 + b.abs()), "tangent order {p} lane {l}: {a} vs {b}");
                }
            }
        }
    }

    /// Reference: the scalar [`Tape::eval`] and [`Tape::jacobian`] on each
    /// lane's inputs, equal bitwise (the same operations in the same
    /// order, lane by lane).
    #[test]
    fn every_lane_is_the_scalar_value_and_jacobian() {
        let tape = Tape::record(3, kernel);
        let x: Vec<Lanes> = (0..3).map(|i| std::array::from_fn(|l| (l * 3 + i) as f64 * 0.37 - 1.1)).collect();
        let mut work = BatchJacobianWork::default();
        let (mut out, mut jac) = (vec![[0.0; LANES]; 3], vec![[0.0; LANES]; 9]);
        jacobian_lanes(&tape, &x, &mut work, &mut out, &mut jac);
        let mut values = vec![[0.0; LANES]; 3];
        eval_lanes(&tape, &x, &mut work, &mut values);
        for l in 0..LANES {
            let xl: Vec<f64> = x.iter().map(|v| v[l]).collect();
            let (mut o, mut j) = (vec![0.0; 3], vec![0.0; 9]);
            tape.jacobian(&xl, &mut super::super::JacobianWork::default(), &mut o, &mut j);
            for k in 0..3 {
                assert_eq!(out[k][l], o[k], "lane {l} output {k}");
                assert_eq!(values[k][l], o[k], "lane {l} value {k}");
            }
            for k in 0..9 {
                assert_eq!(jac[k][l], j[k], "lane {l} entry {k}");
            }
        }
    }

    /// Reference: the scalar [`TaylorWork`] on each lane's inputs, the
    /// series, its commit and the tangent series; to 1e-13 relative.
    #[test]
    fn every_lane_is_the_scalar_series() {
        let tape = Tape::record(3, kernel);
        let order = 9;
        let input = |lane: usize, i: usize, k: usize| ((lane * 31 + i * 7 + k * 13) % 17) as f64 / 8.0 - 1.0;
        let mut batch = BatchTaylorWork::default();
        let mut scalar: Vec<TaylorWork> = vec![TaylorWork::default(); LANES];
        let lanes = |k: usize| -> Vec<Lanes> { (0..3).map(|i| std::array::from_fn(|l| input(l, i, k))).collect() };
        batch.begin(&tape, &lanes(0), order);
        for (l, w) in scalar.iter_mut().enumerate() {
            w.begin(&tape, &(0..3).map(|i| input(l, i, 0)).collect::<Vec<_>>(), order);
        }
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * (1.0 + b.abs());
        let (mut out, mut one) = (vec![[0.0; LANES]; 3], vec![0.0; 3]);
        for p in 1..=order {
            // The known part (inputs zero), then the commit.
            for xp in [vec![[0.0; LANES]; 3], lanes(p)] {
                batch.order(&tape, p, &xp, &mut out);
                for (l, w) in scalar.iter_mut().enumerate() {
                    w.order(&tape, p, |i| xp[i][l], &mut one);
                    for j in 0..3 {
                        assert!(close(out[j][l], one[j]), "order {p} lane {l} output {j}: {} vs {}", out[j][l], one[j]);
                    }
                }
            }
        }
        tangents_agree(&tape, &mut batch, &mut scalar, order, &lanes);
    }

    /// A kernel without a product: no history, every order in one slab.
    fn linear<T: Scalar>(v: &[T]) -> Vec<T> {
        let (x, y, z) = (v[0], v[1], v[2]);
        vec![x * 2.0 + y - 1.0, -z + x, (y - z) * 0.5]
    }

    /// Reference: the scalar [`TaylorWork`], each order's known part and
    /// a second `order` call with the inputs' coefficients, to 1e-13
    /// relative. The batched work commits instead
    /// ([`BatchTaylorWork::commit`]: the cone alone): right after `begin`
    /// at order 1 and without a known part at order 5 (a pass of the
    /// cone), after the known part elsewhere (an update of the cone); at
    /// even orders it then calls `order` with the same coefficients, which
    /// must see the whole committed order (a whole pass), not the cone's
    /// nodes alone. Then the tangent series. On the kernel with products
    /// and on one without (no history at all).
    #[test]
    fn a_commit_is_the_second_order_call() {
        for tape in [Tape::record(3, kernel), Tape::record(3, linear)] {
            let order = 8;
            let input = |lane: usize, i: usize, k: usize| ((lane * 29 + i * 5 + k * 11) % 19) as f64 / 9.0 - 1.0;
            let lanes = |k: usize| -> Vec<Lanes> { (0..3).map(|i| std::array::from_fn(|l| input(l, i, k))).collect() };
            let mut batch = BatchTaylorWork::default();
            let mut scalar: Vec<TaylorWork> = vec![TaylorWork::default(); LANES];
            batch.begin(&tape, &lanes(0), order);
            for (l, w) in scalar.iter_mut().enumerate() {
                w.begin(&tape, &(0..3).map(|i| input(l, i, 0)).collect::<Vec<_>>(), order);
            }
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * (1.0 + b.abs());
            let (mut out, mut one) = (vec![[0.0; LANES]; 3], vec![0.0; 3]);
            let check =
                |out: &[Lanes], scalar: &mut [TaylorWork], p: usize, xp: &[Lanes], one: &mut [f64], what: &str| {
                    for (l, w) in scalar.iter_mut().enumerate() {
                        w.order(&tape, p, |i| xp[i][l], one);
                        for j in 0..3 {
                            assert!(
                                close(out[j][l], one[j]),
                                "{what} {p} lane {l} output {j}: {} vs {}",
                                out[j][l],
                                one[j]
                            );
                        }
                    }
                };
            for p in 1..=order {
                if p != 1 && p != 5 {
                    let zeros = vec![[0.0; LANES]; 3];
                    batch.order(&tape, p, &zeros, &mut out);
                    check(&out, &mut scalar, p, &zeros, &mut one, "known part");
                }
                batch.commit(&tape, p, &lanes(p));
                if p % 2 == 0 {
                    batch.order(&tape, p, &lanes(p), &mut out);
                    check(&out, &mut scalar, p, &lanes(p), &mut one, "order after its commit");
                } else {
                    for (l, w) in scalar.iter_mut().enumerate() {
                        w.order(&tape, p, |i| lanes(p)[i][l], &mut one);
                    }
                }
            }
            tangents_agree(&tape, &mut batch, &mut scalar, order, &lanes);
        }
    }

    /// A work given pooled arrays full of NaN computes bitwise what a work
    /// on fresh zeroed arrays computes (the reference): the passes and
    /// commits never read a coefficient they have not written in this
    /// series.
    #[test]
    fn pooled_stale_arrays_change_nothing() {
        let tape = Tape::record(3, kernel);
        let order = 7;
        let lanes = |k: usize| -> Vec<Lanes> {
            (0..3).map(|i| std::array::from_fn(|l| ((l * 5 + i * 3 + k * 11) % 13) as f64 / 6.0 - 1.0)).collect()
        };
        let run = |work: &mut BatchTaylorWork| -> Vec<f64> {
            let mut all = vec![];
            let mut out = vec![[0.0; LANES]; 3];
            work.begin(&tape, &lanes(0), order);
            for p in 1..=order {
                // Order 1 committed right after `begin` (the cone's pass),
                // every third order committed after its known part (the
                // cone's update), the others by a second `order` call.
                if p > 1 {
                    work.order(&tape, p, &[[0.0; LANES]; 3], &mut out);
                    all.extend(out.iter().flatten());
                }
                if p == 1 || p % 3 == 0 {
                    work.commit(&tape, p, &lanes(p));
                } else {
                    work.order(&tape, p, &lanes(p), &mut out);
                    all.extend(out.iter().flatten());
                }
            }
            for p in 0..=order {
                work.tangent_order(&tape, p, &lanes(p + 20), &mut out);
                all.extend(out.iter().flatten());
            }
            all
        };
        let mut fresh = BatchTaylorWork::default();
        let reference = run(&mut fresh);
        std::mem::forget(fresh); // not into the pool
        let len = tape.series.len(order);
        POOL.with(|pool| {
            let mut pool = pool.borrow_mut();
            pool.clear();
            pool.push(vec![[f64::NAN; LANES]; len + 5]);
            pool.push(vec![[f64::NAN; LANES]; len]);
        });
        let mut pooled = BatchTaylorWork::default();
        let got = run(&mut pooled);
        // Both arrays (coefficients and tangent) came from the pool.
        assert_eq!(POOL.with(|pool| pool.borrow().len()), 0);
        assert!(reference.iter().all(|v| v.is_finite()));
        assert_eq!(got.len(), reference.len());
        for (k, (a, b)) in got.iter().zip(&reference).enumerate() {
            assert_eq!(a.to_bits(), b.to_bits(), "value {k}: {a} vs {b}");
        }
        // Dropped, both go back.
        drop(pooled);
        assert_eq!(POOL.with(|pool| pool.borrow().len()), 2);
        // A full pool of small arrays takes a larger one in place of its
        // smallest, and drops a smaller one.
        POOL.with(|pool| {
            let mut pool = pool.borrow_mut();
            pool.clear();
            pool.extend((1..=POOL_ARRAYS).map(|k| vec![[0.0; LANES]; k]));
        });
        give_back(vec![[0.0; LANES]; 100]);
        give_back(vec![[0.0; LANES]; 1]);
        let mut lens: Vec<usize> = POOL.with(|pool| pool.borrow().iter().map(Vec::len).collect());
        lens.sort_unstable();
        assert_eq!(lens, [2, 3, 4, 5, 6, 7, 8, 100]);
    }
}

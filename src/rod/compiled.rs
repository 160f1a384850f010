//! The rod's element kernels compiled: the collocation residual of
//! physics.md §2.3 on the quaternion equations of §2.1
//! ([`super::model::gauss_kernel`], [`super::model::midpoint_kernel`]),
//! the same generic code the element's tape records, monomorphised for
//! the lane number types of [`crate::taylor::lanes`] and run on
//! [`LANES`] elements at once:
//!
//! * values: the kernel on [`LaneValue`];
//! * the local Jacobian: the right-hand side f on [`LaneDual`] at each
//!   stage (f depends on q, n_b, m_b, Λ and μ: 12 seeds), then the rows'
//!   linear combination of the stages differentiated by hand (a row is
//!   start − y0 − h Σ_j w_j f_j);
//! * Taylor series and their tangents: the kernel on [`LaneSeries`].
//!
//! The lanes' laws may differ (a charged rod's stiffening per stage and
//! element): the compliance is a lane array ([`RhsData<Lanes>`]), all else
//! is shared by a batch.

use super::kinematics::RhsData;
use super::model::{field, gauss_kernel, midpoint_kernel};
use super::scheme::{Scheme, Tableau};
use crate::continuation::system::{LaneBatch, LaneKernel};
use crate::taylor::batch::{Lanes, LANES};
use crate::taylor::lanes::{LaneDual, LaneScalar, LaneSeries, LaneValue, SeriesArena, MAX_INPUTS};
use std::any::Any;

/// What every element of a batch shares: the scheme, h (None: an input,
/// a graded rod), whether μ is the last input.
#[derive(Clone, Debug, PartialEq)]
struct Code {
    scheme: Scheme,
    tab: Tableau,
    h: Option<f64>,
    unfold: bool,
    inputs: usize,
    outputs: usize,
}

impl Code {
    fn stages(&self) -> usize {
        self.scheme.stages().max(1)
    }

    /// Run the kernel on `v`, its outputs in order to `emit`.
    #[inline(always)]
    fn run<T: LaneScalar>(&self, data: &[RhsData<Lanes>], v: &[T], emit: &mut impl FnMut(T)) {
        match self.scheme {
            Scheme::Midpoint => midpoint_kernel(&data[0], self.h, v, self.unfold, emit),
            Scheme::Gauss(_) => gauss_kernel(data, self.h, &self.tab, v, self.unfold, emit),
        }
    }

    /// Run the kernel over a series arena, each output's order-p
    /// coefficient (of the series, or of its tangent) into `out`.
    fn coefficients(&self, data: &[RhsData<Lanes>], v: &[LaneSeries<'_>], p: usize, tangent: bool, out: &mut [Lanes]) {
        let mut k = 0;
        self.run(data, v, &mut |t: LaneSeries<'_>| {
            out[k] = t.value(p, tangent);
            k += 1;
        });
    }

    /// Where stage j's state starts among the inputs (the midpoint's
    /// single evaluation is at (a + b)/2: the caller averages).
    fn stage(&self, j: usize) -> usize {
        13 * (1 + j)
    }

    fn lambda(&self) -> usize {
        match self.scheme {
            Scheme::Midpoint => 26,
            Scheme::Gauss(s) => 13 * (2 + s),
        }
    }
}

/// One element's kernel: the shared code and its law per stage.
#[derive(Debug)]
pub(crate) struct ElementKernel {
    code: Code,
    data: Vec<RhsData>,
}

impl ElementKernel {
    /// The kernel of an element of `scheme` with per-stage data `data`
    /// (one entry for the midpoint rule); None where the compiled form
    /// does not apply (more stages than it holds).
    pub(crate) fn new(
        scheme: Scheme,
        tab: Tableau,
        h: Option<f64>,
        unfold: bool,
        data: Vec<RhsData>,
        inputs: usize,
    ) -> Option<Self> {
        let stages = scheme.stages().max(1);
        if scheme.stages() > 4 || data.len() != stages || inputs > MAX_INPUTS {
            return None;
        }
        let outputs = 13 * (scheme.stages() + 1);
        Some(ElementKernel { code: Code { scheme, tab, h, unfold, inputs, outputs }, data })
    }
}

/// Two laws that differ at most in their compliance.
fn same_but_compliance(a: &RhsData, b: &RhsData) -> bool {
    a.intrinsic_u == b.intrinsic_u
        && a.intrinsic_v == b.intrinsic_v
        && a.kirchhoff == b.kirchhoff
        && a.force == b.force
        && a.couple == b.couple
}

impl LaneKernel for ElementKernel {
    fn compatible(&self, other: &dyn LaneKernel) -> bool {
        other.as_any().downcast_ref::<ElementKernel>().is_some_and(|o| {
            o.code.scheme == self.code.scheme
                && o.code.h.map(f64::to_bits) == self.code.h.map(f64::to_bits)
                && o.code.unfold == self.code.unfold
                && o.code.inputs == self.code.inputs
                && o.data.len() == self.data.len()
                && o.data.iter().zip(&self.data).all(|(a, b)| same_but_compliance(a, b))
        })
    }

    fn batch(&self, members: &[&dyn LaneKernel]) -> Box<dyn LaneBatch> {
        let members: Vec<&ElementKernel> = members
            .iter()
            .map(|m| m.as_any().downcast_ref::<ElementKernel>().expect("a batch of compatible element kernels"))
            .collect();
        // Unused lanes repeat the last member's law (their results are
        // never read).
        let law = |l: usize| members[l.min(members.len() - 1)];
        let data: Vec<RhsData<Lanes>> = (0..self.data.len())
            .map(|j| {
                let d = &self.data[j];
                RhsData {
                    compliance: std::array::from_fn(|r| {
                        std::array::from_fn(|c| std::array::from_fn(|l| law(l).data[j].compliance[r][c]))
                    }),
                    intrinsic_u: d.intrinsic_u,
                    intrinsic_v: d.intrinsic_v,
                    kirchhoff: d.kirchhoff,
                    force: d.force,
                    couple: d.couple,
                }
            })
            .collect();
        let duals = vec![[LaneDual::input([0.0; LANES], None); 13]; self.code.stages()];
        Box::new(ElementBatch { code: self.code.clone(), data, arena: None, duals })
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

#[derive(Debug)]
struct ElementBatch {
    code: Code,
    data: Vec<RhsData<Lanes>>,
    /// Made at the first series (a batch whose lanes share a tape takes
    /// its series from the tape and never needs one).
    arena: Option<SeriesArena>,
    /// f and its derivatives at each stage (the Jacobian's work space).
    duals: Vec<[LaneDual; 13]>,
}

impl LaneBatch for ElementBatch {
    fn eval(&mut self, x: &[Lanes], out: &mut [Lanes]) {
        let v: [LaneValue; MAX_INPUTS] = std::array::from_fn(|i| LaneValue(x.get(i).copied().unwrap_or([0.0; LANES])));
        let mut k = 0;
        self.code.run(&self.data, &v[..self.code.inputs], &mut |t| {
            out[k] = t.0;
            k += 1;
        });
    }

    fn jacobian(&mut self, x: &[Lanes], out: &mut [Lanes], jac: &mut [Lanes]) {
        let code = &self.code;
        let nin = code.inputs;
        let lam = code.lambda();
        let graded = code.h.is_none();
        let mu = code.unfold.then(|| nin - 1);
        let hcol = lam + 1;
        // f and its derivatives at each stage (the midpoint's at (a + b)/2).
        let stages = code.stages();
        // On the heap (a C host's thread may have a small stack): the
        // stages' duals are ~22 kB. The right-hand side on duals still
        // takes ~55 kB of stack (its frames, measured in a release
        // build), bounded and well inside a 128 kB thread.
        let f = &mut self.duals;
        for (j, fj) in f.iter_mut().enumerate().take(stages) {
            let y: [LaneDual; 15] = std::array::from_fn(|m| match m {
                0..=12 => {
                    let v = match code.scheme {
                        Scheme::Midpoint => std::array::from_fn(|l| (x[m][l] + x[13 + m][l]) * 0.5),
                        Scheme::Gauss(_) => x[code.stage(j) + m],
                    };
                    LaneDual::input(v, (m >= 3).then(|| m - 3))
                }
                13 => LaneDual::input(x[lam], Some(10)),
                _ => LaneDual::input(mu.map_or([0.0; LANES], |i| x[i]), Some(11)),
            });
            let v = if code.unfold { &y[..15] } else { &y[..14] };
            *fj = field(&self.data[j], &y[..13], y[13], v, code.unfold);
        }
        let neg = |a: Lanes| -> Lanes { std::array::from_fn(|l| -a[l]) };
        let at = |r: usize, c: usize| r * nin + c;
        match code.scheme {
            Scheme::Midpoint => {
                let h = if graded { x[hcol] } else { [code.h.unwrap_or(0.0); LANES] };
                for k in 0..13 {
                    let d = &f[0][k].d;
                    let fv = f[0][k].v;
                    out[k] = std::array::from_fn(|l| x[13 + k][l] - x[k][l] - fv[l] * h[l]);
                    for m in 3..13 {
                        let e: Lanes = std::array::from_fn(|l| -(h[l] * (d[m - 3][l] * 0.5)));
                        jac[at(k, m)] = e;
                        jac[at(k, 13 + m)] = e;
                    }
                    let (a, b) = (jac[k * nin + k], jac[k * nin + 13 + k]);
                    let (a, b): (Lanes, Lanes) = if k >= 3 {
                        (std::array::from_fn(|l| a[l] - 1.0), std::array::from_fn(|l| b[l] + 1.0))
                    } else {
                        ([-1.0; LANES], [1.0; LANES])
                    };
                    jac[at(k, k)] = a;
                    jac[at(k, 13 + k)] = b;
                    jac[at(k, lam)] = std::array::from_fn(|l| -(h[l] * d[10][l]));
                    if let Some(mu) = mu {
                        jac[at(k, mu)] = std::array::from_fn(|l| -(h[l] * d[11][l]));
                    }
                    if graded {
                        jac[at(k, hcol)] = neg(fv);
                    }
                }
            }
            Scheme::Gauss(s) => {
                let tab = &code.tab;
                for i in 0..=s {
                    let w = if i < s { &tab.a[i] } else { &tab.b };
                    let start = code.stage(i);
                    for k in 0..13 {
                        let r = 13 * i + k;
                        // Value, as the kernel forms it.
                        out[r] = match code.h {
                            Some(h) => {
                                let mut e: Lanes = std::array::from_fn(|l| x[start + k][l] - x[k][l]);
                                for j in 0..s {
                                    let c = h * w[j];
                                    e = std::array::from_fn(|l| e[l] - c * f[j][k].v[l]);
                                }
                                e
                            }
                            None => {
                                let h = x[hcol];
                                let mut sum: Lanes = std::array::from_fn(|l| w[0] * f[0][k].v[l]);
                                for j in 1..s {
                                    sum = std::array::from_fn(|l| sum[l] + w[j] * f[j][k].v[l]);
                                }
                                jac[at(r, hcol)] = neg(sum);
                                std::array::from_fn(|l| x[start + k][l] - x[k][l] - sum[l] * h[l])
                            }
                        };
                        // ∂/∂ stage j: −h w_j ∂f_j/∂y; Λ and μ summed over the stages.
                        let (mut dl, mut dm) = ([0.0; LANES], [0.0; LANES]);
                        for j in 0..s {
                            let c: Lanes = match code.h {
                                Some(h) => [h * w[j]; LANES],
                                None => std::array::from_fn(|l| x[hcol][l] * w[j]),
                            };
                            let d = &f[j][k].d;
                            for m in 3..13 {
                                jac[at(r, code.stage(j) + m)] = std::array::from_fn(|l| -(c[l] * d[m - 3][l]));
                            }
                            dl = std::array::from_fn(|l| dl[l] - c[l] * d[10][l]);
                            dm = std::array::from_fn(|l| dm[l] - c[l] * d[11][l]);
                        }
                        jac[at(r, lam)] = dl;
                        if let Some(mu) = mu {
                            jac[at(r, mu)] = dm;
                        }
                        jac[at(r, k)] = [-1.0; LANES];
                        // The row's own start (a stage, or y1): +1, on top
                        // of the stage term when the two coincide.
                        let col = start + k;
                        let own = if i < s && k >= 3 { jac[r * nin + col] } else { [0.0; LANES] };
                        jac[at(r, col)] = std::array::from_fn(|l| own[l] + 1.0);
                    }
                }
            }
        }
    }

    fn series_begin(&mut self, x0: &[Lanes], max_order: usize) {
        let (code, data) = (&self.code, &self.data);
        let arena = self.arena.get_or_insert_with(|| SeriesArena::new(code.inputs, |v| code.run(data, v, &mut |_| {})));
        arena.begin(x0, max_order, |v| code.run(data, v, &mut |_| {}));
    }

    fn series_order(&mut self, p: usize, xp: &[Lanes], out: &mut [Lanes]) {
        let (code, data) = (&self.code, &self.data);
        let arena = self.arena.as_mut().expect("series_order after series_begin");
        arena.order(p, xp, |v| code.coefficients(data, v, p, false, out));
    }

    fn series_tangent_order(&mut self, p: usize, wp: &[Lanes], out: &mut [Lanes]) {
        let (code, data) = (&self.code, &self.data);
        let arena = self.arena.as_mut().expect("series_tangent_order after series_begin");
        arena.tangent_order(p, wp, |v| code.coefficients(data, v, p, true, out));
    }
}

#[cfg(test)]
mod tests {
    use crate::continuation::system::AssembledSystem;
    use crate::continuation::{Problem, SeriesProblem};
    use crate::rod::model::{Rod, Supports};
    use crate::rod::scheme::Scheme;
    use crate::rod::{Load, Loads, RodLaw};
    use crate::taylor::batch::{BatchTaylorWork, Lanes, LANES};
    use nalgebra::{Matrix6, Vector3};

    /// A deterministic point in [−1, 1) (no random crate needed).
    fn noise(i: usize, k: usize) -> f64 {
        let h = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (k as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
        let h = h ^ (h >> 29);
        (h.wrapping_mul(0xBF58_476D_1CE4_E5B9) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    /// `|a − b| ≤ tol·(1 + |b|)` entry by entry, the largest such ratio.
    fn worst(a: &[f64], b: &[f64]) -> f64 {
        a.iter().zip(b).map(|(x, y)| (x - y).abs() / (1.0 + y.abs())).fold(0.0, f64::max)
    }

    /// The compiled system against the interpreted one (every block on its
    /// tape, the reference) at a point off any solution: residual,
    /// Jacobian, a Taylor series of order 12 (each order's known part and
    /// its commit) and its tangent series. Values are the same operations
    /// in the same order, measured bitwise equal on every law here (the
    /// Jacobian within 3e-16: its chain-rule sums run in another order);
    /// asserted to 1e-15 relative. Where a batch's lanes share one tape
    /// both systems take series from it, so this compares the compiled
    /// series only for the stiffened rod (lanes of different laws); the
    /// compiled series of every law, scheme, mesh and phase condition is
    /// held against the batched tape by [`same_series`].
    fn same(mut compiled: AssembledSystem, mut tape: AssembledSystem, what: &str) {
        same_series(&compiled, what);
        let n = compiled.dim();
        let x: Vec<f64> = (0..n).map(|i| noise(i, 1)).collect();
        let lambda = 0.7;
        let (mut ra, mut rb) = (vec![0.0; n], vec![0.0; n]);
        compiled.residual(&x, lambda, &mut ra);
        tape.residual(&x, lambda, &mut rb);
        assert!(worst(&ra, &rb) <= 1e-15, "{what}: residual {:e}", worst(&ra, &rb));
        let nnz = compiled.pattern().nnz();
        let (mut ja, mut jb, mut la, mut lb) = (vec![0.0; nnz], vec![0.0; nnz], vec![0.0; n], vec![0.0; n]);
        compiled.jacobian(&x, lambda, &mut ja, &mut la);
        tape.jacobian(&x, lambda, &mut jb, &mut lb);
        assert!(worst(&ja, &jb) <= 1e-15, "{what}: Jacobian {:e}", worst(&ja, &jb));
        assert!(worst(&la, &lb) <= 1e-15, "{what}: ∂R/∂Λ {:e}", worst(&la, &lb));
        let order = 12;
        compiled.series_begin(&x, lambda, order);
        tape.series_begin(&x, lambda, order);
        for p in 1..=order {
            let xp: Vec<f64> = (0..n).map(|i| 0.3 * noise(i, 10 + p)).collect();
            for (xs, lp) in [(vec![0.0; n], 0.0), (xp, 0.1 * noise(0, p))] {
                compiled.series_order(p, &xs, lp, &mut ra);
                tape.series_order(p, &xs, lp, &mut rb);
                assert!(worst(&ra, &rb) <= 1e-15, "{what}: order {p} {:e}", worst(&ra, &rb));
            }
        }
        for p in 0..=order {
            let wp: Vec<f64> = (0..n).map(|i| noise(i, 40 + p)).collect();
            compiled.series_tangent_order(p, &wp, 0.2, &mut ra);
            tape.series_tangent_order(p, &wp, 0.2, &mut rb);
            assert!(worst(&ra, &rb) <= 1e-15, "{what}: tangent order {p} {:e}", worst(&ra, &rb));
        }
    }

    /// The compiled series of the first element block on [`LANES`] lanes
    /// against the batched tape ([`BatchTaylorWork`]: the system takes
    /// its series from the tape where the lanes share one, so this is
    /// where the compiled series meets it): the same operations in the
    /// same order, measured bitwise equal; asserted to 1e-15 relative.
    /// A third work commits each order ([`BatchTaylorWork::commit`]: the
    /// tape's cone of history nodes alone) where the others take a second
    /// `order` call: its later orders' known parts and its tangent series
    /// are bitwise the tape's.
    fn same_series(system: &AssembledSystem, what: &str) {
        let block = &system.blocks()[0];
        let kernel = block.kernel.as_ref().expect("an element block has a compiled kernel");
        let mut compiled = kernel.batch(&[kernel.as_ref(); LANES]);
        let mut tape = BatchTaylorWork::default();
        let mut committed = BatchTaylorWork::default();
        let (nin, nout) = (block.tape.inputs(), block.tape.outputs());
        let lanes = |k: usize, scale: f64| -> Vec<Lanes> {
            (0..nin).map(|i| std::array::from_fn(|l| scale * noise(i * LANES + l, k))).collect()
        };
        let order = 12;
        compiled.series_begin(&lanes(0, 1.0), order);
        tape.begin(&block.tape, &lanes(0, 1.0), order);
        committed.begin(&block.tape, &lanes(0, 1.0), order);
        let (mut a, mut b, mut c) = (vec![[0.0; LANES]; nout], vec![[0.0; LANES]; nout], vec![[0.0; LANES]; nout]);
        let flat = |v: &[Lanes]| v.iter().flatten().copied().collect::<Vec<f64>>();
        let bits = |v: &[Lanes]| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<u64>>();
        for p in 1..=order {
            for (k, xp) in [vec![[0.0; LANES]; nin], lanes(p, 0.3)].into_iter().enumerate() {
                compiled.series_order(p, &xp, &mut a);
                tape.order(&block.tape, p, &xp, &mut b);
                let e = worst(&flat(&a), &flat(&b));
                assert!(e <= 1e-15, "{what}: lanes order {p} {e:e}");
                if k == 0 {
                    committed.order(&block.tape, p, &xp, &mut c);
                    assert_eq!(bits(&c), bits(&b), "{what}: known part of order {p} after commits");
                } else {
                    committed.commit(&block.tape, p, &xp);
                }
            }
        }
        for p in 0..=order {
            let wp = lanes(30 + p, 1.0);
            compiled.series_tangent_order(p, &wp, &mut a);
            tape.tangent_order(&block.tape, p, &wp, &mut b);
            let e = worst(&flat(&a), &flat(&b));
            assert!(e <= 1e-15, "{what}: lanes tangent order {p} {e:e}");
            committed.tangent_order(&block.tape, p, &wp, &mut c);
            assert_eq!(bits(&c), bits(&b), "{what}: tangent order {p} after commits");
        }
    }

    fn laws() -> Vec<(&'static str, RodLaw)> {
        // A general 6×6 law: symmetric positive definite with every
        // coupling present, and intrinsic strains.
        let mut k = Matrix6::from_fn(|i, j| 0.05 * (1.0 + ((i * 7 + j * 3) % 5) as f64));
        k = k.transpose() * k + Matrix6::from_diagonal(&nalgebra::Vector6::new(1.0, 1.3, 0.8, 50.0, 60.0, 200.0));
        let general = RodLaw::general(k, Vector3::new(0.3, -0.2, 0.5), Vector3::new(0.01, -0.02, 1.05)).unwrap();
        let mut intrinsic = RodLaw::isotropic(1.0, 0.77, 1e4, 2.6e4).unwrap();
        intrinsic.intrinsic_u = Vector3::new(0.0, 0.4, 1.2);
        vec![
            ("isotropic", RodLaw::isotropic(1.0, 0.77, 1e4, 2.6e4).unwrap()),
            ("hemitropic", RodLaw::hemitropic(1.0, 0.77, 1e4, 2.6e4, 0.2, 0.1).unwrap()),
            ("Kirchhoff", RodLaw::kirchhoff(1.0, 1.4, 0.7).unwrap()),
            ("general 6×6", general),
            ("intrinsic strains", intrinsic),
        ]
    }

    fn loads() -> Vec<(&'static str, Loads)> {
        let mut follower = Loads::default();
        follower.tip_force = Some(Load::follower([1.0, 0.0, 0.0]));
        follower.distributed_force = Some(Load::follower([0.3, -0.2, 0.1]));
        follower.distributed_couple = Some(Load::follower([0.0, 0.1, -0.2]));
        let mut dead = Loads::default();
        dead.tip_force = Some(Load::dead([0.0, 0.0, -1.0]));
        dead.distributed_force = Some(Load::dead([0.1, 0.4, -0.3]));
        dead.distributed_couple = Some(Load::dead([0.2, 0.0, 0.1]));
        vec![("follower", follower), ("dead", dead)]
    }

    /// Every law × load × scheme, uniform and graded meshes, with and
    /// without the unfolding parameter (a phase condition).
    #[test]
    fn compiled_kernels_equal_the_tape_on_every_law() {
        for (law_name, law) in laws() {
            for (load_name, loads) in loads() {
                for scheme in [Scheme::Midpoint, Scheme::Gauss(2), Scheme::Gauss(3), Scheme::Gauss(4)] {
                    // 6 elements: a full batch of four and a lone pair.
                    let rod = Rod::new(law.clone(), 1.3, loads, Supports::Cantilever, scheme, 6).unwrap();
                    let what = format!("{law_name}, {load_name}, {scheme:?}");
                    same(rod.system().unwrap(), rod.system().unwrap().interpreted(), &what);
                    let graded = rod.clone().graded(&[0.0, 0.1, 0.25, 0.5, 0.7, 0.9, 1.0]).unwrap();
                    same(graded.system().unwrap(), graded.system().unwrap().interpreted(), &format!("{what}, graded"));
                    let phase = rod.system_with_phase(3, 0.4).unwrap();
                    same(phase, rod.system_with_phase(3, 0.4).unwrap().interpreted(), &format!("{what}, phase"));
                }
            }
        }
    }

    /// A batch's local Jacobian comes from the thread's pool of lane
    /// arrays, stale ([`crate::taylor::batch::grow_pooled`]), and the
    /// compiled kernel writes its structural nonzeros only, so the system
    /// zeroes it first (the scatter reads the pattern's entries alone,
    /// which the kernel writes: either keeps stale values out). Here the
    /// pool holds arrays of ones longer than any element's local Jacobian,
    /// which each batch takes; each rod's Jacobian must be bitwise that of
    /// the same rod on a fresh thread (an empty pool: new zeroed arrays).
    #[test]
    fn a_stale_pooled_local_jacobian_leaves_no_trace() {
        let jacobian = |rod: &Rod| {
            let mut system = rod.system().unwrap();
            let n = system.dim();
            let x: Vec<f64> = (0..n).map(|i| noise(i, 3)).collect();
            let (mut jx, mut jl) = (vec![0.0; system.pattern().nnz()], vec![0.0; n]);
            system.jacobian(&x, 0.7, &mut jx, &mut jl);
            (jx, jl)
        };
        for scheme in [Scheme::Midpoint, Scheme::Gauss(2), Scheme::Gauss(3), Scheme::Gauss(4)] {
            let (_, law) = laws().swap_remove(3);
            let rod = Rod::new(law, 1.3, loads()[1].1, Supports::Cantilever, scheme, 5).unwrap();
            let fresh = {
                let rod = rod.clone();
                std::thread::spawn(move || jacobian(&rod)).join().unwrap()
            };
            for _ in 0..8 {
                crate::taylor::batch::give_back(vec![[1.0; LANES]; 20_000]);
            }
            let pooled = jacobian(&rod);
            let bits = |v: &[f64]| v.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&pooled.0), bits(&fresh.0), "{scheme:?}: R_x");
            assert_eq!(bits(&pooled.1), bits(&fresh.1), "{scheme:?}: R_Λ");
        }
    }

    /// A charged rod's elastic part: each element stiffened by its own
    /// near zone (stage by stage), the lanes' laws differing (so the
    /// system's series are the compiled ones), on uniform and graded
    /// meshes, with and without the phase condition's μ.
    #[test]
    fn compiled_kernels_equal_the_tape_with_stiffening_per_element() {
        for law in [RodLaw::isotropic(1.0, 0.77, 1e4, 2.6e4).unwrap(), RodLaw::kirchhoff(1.0, 1.0, 0.7).unwrap()] {
            let rod =
                Rod::new(law, 2.0, Loads::default(), Supports::Torqued { tension: 1.0 }, Scheme::Gauss(3), 7).unwrap();
            let extra: Vec<Vec<f64>> = (0..7)
                .map(|i| (0..3).map(|j| if i == 2 { 0.0 } else { 0.1 + 0.05 * noise(i, j).abs() }).collect())
                .collect();
            same(
                rod.system_stiffened(&extra).unwrap(),
                rod.system_stiffened(&extra).unwrap().interpreted(),
                "stiffened",
            );
            let phase = |r: &Rod| r.system_with_phase_stiffened(4, 0.3, &extra).unwrap();
            same(phase(&rod), phase(&rod).interpreted(), "stiffened, phase");
            let graded = rod.clone().graded(&[0.0, 0.05, 0.2, 0.4, 0.5, 0.7, 0.85, 1.0]).unwrap();
            let stiffened = |r: &Rod| r.system_stiffened(&extra).unwrap();
            same(stiffened(&graded), stiffened(&graded).interpreted(), "stiffened, graded");
            same(phase(&graded), phase(&graded).interpreted(), "stiffened, graded, phase");
        }
    }
}

//! The discretised rod as a cubic system R(x, Λ) = 0 (physics.md §2.3).
//!
//! Unknowns, element by element: the node state y_i = (r, q, n_b, m_b) (13)
//! followed by the element's stage states (13 each, Gauss–Legendre only),
//! then the last node: 13(N + 1) + 13sN unknowns. Equations: per element,
//! its stage equations Y_j = y_i + h Σ_k a_jk f(Y_k) and the node update
//! y_{i+1} = y_i + h Σ_j b_j f(Y_j) (midpoint: y_{i+1} − y_i =
//! h f((y_i + y_{i+1})/2)); 13 boundary conditions. Every kernel is
//! recorded once (uniform mesh: one element tape) and is at most cubic in
//! (x, Λ), which [`Rod::system`] checks.
//!
//! The reference configuration: s ∈ [0, L] along e3 from the origin, with
//! q = (1, 0, 0, 0) (scalar first) for a straight rod.

use super::compiled::ElementKernel;
use super::kinematics::{self, RhsData};
use super::scheme::{Scheme, Tableau};
use super::{Frame, Load, Loads, RodLaw};
use crate::continuation::system::LaneKernel;
use crate::continuation::system::{AssembledSystem, Block, Slot};
use crate::error::{self, Error, Result};
use crate::rod::branch::Phase;
use crate::status::Status;
use crate::taylor::{Coefficient, Scalar, Tape, Var};
use std::ops::Mul;
use std::sync::Arc;

/// Supports of the two ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Supports {
    /// s = 0 clamped at the origin along e3 (7 conditions: r, q); s = L
    /// free, with the tip loads as n_b(L), m_b(L) (6).
    Cantilever,
    /// Both ends clamped: s = 0 as above; s = L at `end_position` with the
    /// orientation `end_rotation` (unit quaternion): 3 position and 3
    /// rotation conditions (the vector part of q̄_end ∘ q(L); the 4th would
    /// be redundant since the scheme conserves |q|). Tip loads are reactions
    /// and must be None.
    /// The end may be moved with the load parameter: r(L) = end_position +
    /// Λ·end_displacement (displacement control, e.g. compression).
    Clamped { end_position: [f64; 3], end_rotation: [f64; 4], end_displacement: [f64; 3] },
    /// Ball joints (physics.md §2.3): s = 0: r = 0, m_b1 = m_b2 = 0, no
    /// twist (q3 = 0), |q|² = 1; s = L: r_x = r_y = 0, the axial component
    /// of the spatial force equal to Λ times the tip force's (dead, along
    /// e3), m_b = 0.
    Pinned,
    /// Controlled end rotation (Greenhill's problem, physics.md §2.6): s = 0
    /// clamped; s = L kept on the axis (r_x = r_y = 0), pulled by the axial
    /// dead force `tension` (free to slide along e3), its section turned
    /// about e3 by φ with Λ = sin(φ/2). The cosine c = cos(φ/2) is one more
    /// unknown (index [`Rod::end_cosine`]) with c² + Λ² = 1, which keeps the
    /// system polynomial (cubic) for the ANM; φ = 2 atan2(Λ, c) follows the
    /// turns through φ = π (a fold of Λ, passed by arc length).
    Twisted { tension: f64 },
    /// As [`Supports::Twisted`], but the end is held on the axis at the
    /// end-to-end distance `distance` (r(L) = distance·e3, the axial force a
    /// reaction): the fixed-extension protocol of a supercoiling
    /// experiment, where [`Supports::Twisted`] is the fixed-force one.
    TwistedAtDistance { distance: f64 },
    /// Controlled end moment (a torque clamp, as in magnetic torque
    /// tweezers): as [`Supports::Twisted`] — s = 0 clamped, s = L on the
    /// axis, pulled by the axial dead force `tension`, its section turned
    /// about e3 only — but the angle φ is free and the spatial moment about
    /// e3 at s = L equals Λ: the load parameter is the end torque. φ enters
    /// through c = cos(φ/2), s = sin(φ/2), two more unknowns
    /// ([`Rod::end_angle`]) with c² + s² = 1 (the system stays cubic);
    /// φ = 2 atan2(s, c) is unwrapped along a path by continuity. Same
    /// equilibria as [`Supports::Twisted`], the curve (φ, M) parametrised
    /// by M instead of φ (its folds in M are the torque's extrema).
    Torqued { tension: f64 },
}

/// A discretised rod.
#[derive(Clone, Debug, PartialEq)]
pub struct Rod {
    pub law: RodLaw,
    pub length: f64,
    pub loads: Loads,
    pub supports: Supports,
    pub scheme: Scheme,
    pub elements: usize,
    /// A graded mesh: the nodes' arc lengths as fractions of the length,
    /// 0 = t_0 < t_1 < … < t_N = 1 (N + 1 of them, N = `elements`). None:
    /// uniform, h = L/N. Set with [`Rod::graded`] (and back with
    /// [`Rod::uniform`]) — a struct update that changes `elements` alone
    /// leaves them inconsistent, refused when the system is built;
    /// [`accuracy`](super::accuracy) grades a mesh where the solution's
    /// derivatives ask.
    pub breakpoints: Option<std::sync::Arc<[f64]>>,
    /// Rod diameter for self-contact detection (physics.md §2.4: the rod has
    /// no contact model; a branch reports where non-neighbouring points come
    /// closer than this). None: not checked.
    pub diameter: Option<f64>,
}

/// An element's recorded tape and compiled kernel.
type Recorded = (Arc<Tape>, Option<Arc<dyn LaneKernel>>);

/// Elements recorded on this thread, by the numbers their kernel depends
/// on; at most [`RECORDED`] (the oldest dropped first).
const RECORDED: usize = 16;

thread_local! {
    static ELEMENTS: std::cell::RefCell<Vec<(Vec<u64>, Recorded)>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The element recorded under `key`, recording it with `record` if absent.
fn recorded_element(key: Vec<u64>, record: impl FnOnce() -> Recorded) -> Recorded {
    let found =
        ELEMENTS.try_with(|e| e.borrow().iter().find(|(k, _)| *k == key).map(|(_, r)| r.clone())).ok().flatten();
    if let Some(r) = found {
        return r;
    }
    let r = record();
    let _ = ELEMENTS.try_with(|e| {
        let mut e = e.borrow_mut();
        if e.len() == RECORDED {
            e.remove(0);
        }
        e.push((key, r.clone()));
    });
    r
}

impl Rod {
    pub fn new(
        law: RodLaw,
        length: f64,
        loads: Loads,
        supports: Supports,
        scheme: Scheme,
        elements: usize,
    ) -> Result<Self> {
        error::positive("length", length)?;
        // 2^18 elements: ~17 million unknowns with 4 Gauss stages, the most a
        // 24 GiB machine factorises; more would abort on allocation.
        error::count_in_range("elements", elements as i64, 1, 1 << 18)?;
        if let Scheme::Gauss(s) = scheme {
            error::count_in_range("Gauss stages", s as i64, 1, 4)?;
        }
        for (name, l) in [
            ("tip_force", loads.tip_force),
            ("tip_moment", loads.tip_moment),
            ("distributed_force", loads.distributed_force),
            ("distributed_couple", loads.distributed_couple),
        ] {
            if let Some(l) = l {
                error::finite_result(name, &l.vector)?;
            }
        }
        match supports {
            Supports::Clamped { end_position, end_rotation, end_displacement } => {
                error::finite_result("end_position", &end_position)?;
                error::finite_result("end_displacement", &end_displacement)?;
                error::finite_result("end_rotation", &end_rotation)?;
                let norm = end_rotation.iter().map(|v| v * v).sum::<f64>().sqrt();
                if (norm - 1.0).abs() > 1e-12 {
                    return Err(Error::new(
                        Status::ErrOutOfRange,
                        format!("end_rotation must be a unit quaternion (|q| = {norm:e})"),
                    ));
                }
                if loads.tip_force.is_some() || loads.tip_moment.is_some() {
                    return Err(Error::new(
                        Status::ErrOutOfRange,
                        "a clamped end takes no tip load (its force and moment are reactions)",
                    ));
                }
            }
            Supports::Pinned => {
                if loads.tip_moment.is_some() {
                    return Err(Error::new(
                        Status::ErrOutOfRange,
                        "a pinned end carries no moment: tip_moment must be None",
                    ));
                }
                if let Some(f) = loads.tip_force {
                    if f.frame != Frame::Dead || f.vector[0] != 0.0 || f.vector[1] != 0.0 {
                        return Err(Error::new(
                            Status::ErrOutOfRange,
                            "a pinned rod takes an axial dead tip force (0, 0, P) only",
                        ));
                    }
                }
            }
            Supports::TwistedAtDistance { distance } => {
                error::positive("distance", distance)?;
                if !(distance <= length) {
                    return Err(Error::new(
                        Status::ErrOutOfRange,
                        format!(
                            "argument `distance` ({distance:e}) exceeds the length of an inextensible rod ({length:e})"
                        ),
                    ));
                }
                if loads.tip_force.is_some() || loads.tip_moment.is_some() {
                    return Err(Error::new(
                        Status::ErrOutOfRange,
                        "a rod with a controlled end rotation takes no tip load",
                    ));
                }
            }
            Supports::Twisted { tension } | Supports::Torqued { tension } => {
                error::finite("tension", tension)?;
                if loads.tip_force.is_some() || loads.tip_moment.is_some() {
                    return Err(Error::new(
                        Status::ErrOutOfRange,
                        "a rod with a controlled end rotation takes no tip load (set its tension)",
                    ));
                }
            }
            Supports::Cantilever => {}
        }
        Ok(Rod { law, length, loads, supports, scheme, elements, breakpoints: None, diameter: None })
    }

    /// The same rod on a graded mesh: node i at arc length L·t_i, with
    /// 0 = t_0 < t_1 < … < t_N = 1 (N ≥ 1 elements, at most as many as
    /// [`Rod::new`] allows; each element at least 1e-9 of the length).
    /// A uniform `t` gives the uniform rod's equations.
    pub fn graded(mut self, t: &[f64]) -> Result<Self> {
        error::count_in_range("breakpoints", t.len() as i64, 2, (1 << 18) + 1)?;
        error::finite_result("breakpoints", t)?;
        let ordered = t.windows(2).all(|w| w[1] - w[0] >= 1e-9);
        if t[0] != 0.0 || t[t.len() - 1] != 1.0 || !ordered {
            return Err(Error::new(
                Status::ErrOutOfRange,
                "breakpoints must run from 0 to 1 (fractions of the length), each element at least 1e-9 long",
            ));
        }
        self.elements = t.len() - 1;
        self.breakpoints = Some(t.into());
        Ok(self)
    }

    /// The same rod on the uniform mesh of `elements` elements.
    pub fn uniform(&self, elements: usize) -> Self {
        Rod { elements, breakpoints: None, ..self.clone() }
    }

    /// The same mesh with every element cut into `k` equal parts (a
    /// reference that keeps every node of this one).
    pub fn subdivided(&self, k: usize) -> Result<Self> {
        let k = k.max(1);
        // Sized before anything is allocated (Rod::new's limit).
        error::count_in_range("elements", self.elements.saturating_mul(k).min(i64::MAX as usize) as i64, 1, 1 << 18)?;
        match &self.breakpoints {
            None => Ok(self.uniform(self.elements * k)),
            Some(t) => {
                let mut fine: Vec<f64> = t
                    .windows(2)
                    .flat_map(|w| (0..k).map(move |j| w[0] + (w[1] - w[0]) * j as f64 / k as f64))
                    .collect();
                fine.push(1.0);
                self.clone().graded(&fine)
            }
        }
    }

    /// The nodes' arc lengths s_0 = 0 … s_N = L.
    pub fn node_positions(&self) -> Vec<f64> {
        (0..=self.elements).map(|i| self.node_position(i)).collect()
    }

    /// Node i's arc length.
    pub fn node_position(&self, i: usize) -> f64 {
        match &self.breakpoints {
            Some(t) => self.length * t[i],
            None => i as f64 * self.element_length(),
        }
    }

    /// Element i's length h_i.
    pub fn element_h(&self, i: usize) -> f64 {
        match &self.breakpoints {
            Some(t) => self.length * (t[i + 1] - t[i]),
            None => self.element_length(),
        }
    }

    /// The same rod with a diameter for self-contact detection.
    pub fn with_diameter(mut self, diameter: f64) -> Result<Self> {
        error::positive("diameter", diameter)?;
        self.diameter = Some(diameter);
        Ok(self)
    }

    /// Self-contact in the state x: the closest pair of nodes (and stages)
    /// closer than the diameter whose arc-length separation exceeds π/2
    /// diameters (closer points are neighbours along the rod, not
    /// contacts), with the pair's arc lengths. None without a diameter or
    /// when no pair is that close.
    pub fn closest_approach(&self, x: &[f64]) -> Option<(f64, f64, f64)> {
        let d = self.diameter?;
        let pts = self.profile_offsets();
        // Pairs closer than the diameter only (cell lists, O(N)): farther
        // ones are no contact.
        let gap = 0.5 * std::f64::consts::PI * d;
        let r: Vec<[f64; 3]> = pts.iter().map(|&(_, o)| [x[o], x[o + 1], x[o + 2]]).collect();
        let s: Vec<f64> = pts.iter().map(|p| p.0).collect();
        crate::geometry::proximity::closest_pair_within(&r, &s, d, gap).map(|(dist, i, j)| (dist, s[i], s[j]))
    }

    /// The uniform mesh's element length h = L/N (a graded rod's mean).
    pub fn element_length(&self) -> f64 {
        self.length / self.elements as f64
    }

    pub(crate) fn block_size(&self) -> usize {
        13 * (1 + self.scheme.stages())
    }

    /// Number of unknowns (excluding Λ): the node and stage states, and the
    /// end rotation's cosine for [`Supports::Twisted`] (its cosine and sine
    /// for [`Supports::Torqued`]).
    pub fn unknowns(&self) -> usize {
        self.block_size() * self.elements + 13 + self.boundary_unknowns()
    }

    fn boundary_unknowns(&self) -> usize {
        self.twisted() as usize + 2 * self.torqued() as usize
    }

    /// Controlled end rotation (either axial condition).
    pub fn twisted(&self) -> bool {
        matches!(self.supports, Supports::Twisted { .. } | Supports::TwistedAtDistance { .. })
    }

    /// Controlled end moment ([`Supports::Torqued`]).
    pub fn torqued(&self) -> bool {
        matches!(self.supports, Supports::Torqued { .. })
    }

    /// The straight rod's end torque per radian of end rotation, C/L: the
    /// scale that makes a torque clamp's parameter comparable with φ.
    pub fn torque_per_radian(&self) -> f64 {
        self.law.stiffness[(2, 2)] / self.length
    }

    /// Index of c = cos(φ/2) in x for [`Supports::Twisted`].
    pub fn end_cosine(&self) -> Option<usize> {
        self.twisted().then(|| self.block_size() * self.elements + 13)
    }

    /// Indices of (cos(φ/2), sin(φ/2)) in x for [`Supports::Torqued`].
    pub fn end_angle(&self) -> Option<(usize, usize)> {
        let at = self.block_size() * self.elements + 13;
        self.torqued().then_some((at, at + 1))
    }

    /// The end rotation φ = 2 atan2(Λ, c) of a [`Supports::Twisted`] rod,
    /// 2 atan2(s, c) ∈ (−2π, 2π] of a [`Supports::Torqued`] one (unwrap
    /// along a path with [`unwrap_rotation`]).
    pub fn end_rotation(&self, x: &[f64], lambda: f64) -> Option<f64> {
        if let Some((c, s)) = self.end_angle() {
            return Some(2.0 * x[s].atan2(x[c]));
        }
        self.end_cosine().map(|i| 2.0 * lambda.atan2(x[i]))
    }

    /// Offset of node i's state y_i in x.
    pub fn node(&self, i: usize) -> usize {
        i * self.block_size()
    }

    /// Node i's state (r, q, n_b, m_b).
    pub fn node_state<'a>(&self, x: &'a [f64], i: usize) -> &'a [f64] {
        &x[self.node(i)..self.node(i) + 13]
    }

    /// The rod's profile: (arc length, offset in x) of every node and stage
    /// state in order along the rod, the nodes at s_i and the stages at
    /// s_i + c_j·h_i.
    pub fn profile_offsets(&self) -> Vec<(f64, usize)> {
        let tab = self.tableau();
        let mut out = Vec::with_capacity(self.unknowns() / 13);
        for i in 0..=self.elements {
            let s = self.node_position(i);
            out.push((s, self.node(i)));
            if i < self.elements {
                let h = self.element_h(i);
                for j in 0..self.scheme.stages() {
                    out.push((s + tab.c[j] * h, self.stage_offset(i, j)));
                }
            }
        }
        out
    }

    /// Tip position r(L).
    pub fn tip(&self, x: &[f64]) -> [f64; 3] {
        let y = self.node_state(x, self.elements);
        [y[0], y[1], y[2]]
    }

    /// The straight, stress-free state (exact at Λ = 0 for a straight rod
    /// with v̂ = e3 and no intrinsic curvature; a starting guess otherwise):
    /// r = s·v̂3·e3, q = 1, n = m = 0 at nodes and stages.
    pub fn straight_state(&self) -> Vec<f64> {
        let mut x = vec![0.0; self.unknowns()];
        if let Some(i) = self.end_cosine().or(self.end_angle().map(|(c, _)| c)) {
            x[i] = 1.0;
        }
        let stretch = self.law.intrinsic_v[2];
        for (s, off) in self.profile_offsets() {
            x[off + 2] = stretch * s;
            x[off + 3] = 1.0;
        }
        x
    }

    /// y' = f(y, Λ) of the rod's ODE at one state y (13 entries).
    pub fn rhs(&self, y: &[f64], lambda: f64) -> [f64; 13] {
        kinematics::rhs(&self.rhs_data(), y, lambda)
    }

    pub(crate) fn tableau(&self) -> Tableau {
        match self.scheme {
            Scheme::Midpoint => Tableau::gauss(1),
            Scheme::Gauss(s) => Tableau::gauss(s),
        }
    }

    pub(crate) fn rhs_data(&self) -> RhsData {
        self.rhs_data_stiffened(0.0)
    }

    /// The right-hand side's data with `extra_bending` added to both bending
    /// stiffnesses (K11, K22): the local electrostatic (OSF-like) stiffening
    /// of a charged rod's near zone (crate::charged::rod).
    pub(crate) fn rhs_data_stiffened(&self, extra_bending: f64) -> RhsData {
        let c = if extra_bending == 0.0 {
            self.law.compliance()
        } else {
            let mut law = self.law.clone();
            law.stiffness[(0, 0)] += extra_bending;
            law.stiffness[(1, 1)] += extra_bending;
            law.compliance()
        };
        let mut compliance = [[0.0; 6]; 6];
        for (i, row) in compliance.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                // Round-off couplings of a diagonal law stay exact zeros.
                *v = if c[(i, j)].abs() > 1e-15 * c.amax() { c[(i, j)] } else { 0.0 };
            }
        }
        let frame = |l: Option<Load>| l.map(|l| (l.frame == Frame::Dead, l.vector));
        RhsData {
            compliance,
            intrinsic_u: self.law.intrinsic_u.into(),
            intrinsic_v: self.law.intrinsic_v.into(),
            kirchhoff: self.law.kirchhoff,
            force: frame(self.loads.distributed_force),
            couple: frame(self.loads.distributed_couple),
        }
    }

    /// Scales: force K_b/L², moment K_b/L, positions L, quaternions 1.
    pub(crate) fn state_scales(&self) -> [f64; 13] {
        let (l, f) = (self.length, self.law.bending() / (self.length * self.length));
        let mut s = [0.0; 13];
        for i in 0..3 {
            s[i] = l;
            s[7 + i] = f;
            s[10 + i] = f * l;
        }
        s[3..7].fill(1.0);
        s
    }

    /// The cubic system, with scales for the continuation (unknowns: the
    /// state scales; equations: h × the scale of y' for element rows, the
    /// state scales for boundary rows; Λ: 1).
    pub fn system(&self) -> Result<AssembledSystem> {
        self.build(None, None)
    }

    /// The system with extra bending stiffness `extra[i][j]` at stage j of
    /// element i (Gauss schemes): a charged rod's near-zone stiffening
    /// (crate::charged::rod). Elements with equal stiffening share
    /// one recorded kernel.
    pub(crate) fn system_stiffened(&self, extra: &[Vec<f64>]) -> Result<AssembledSystem> {
        self.check_stiffening(extra)?;
        self.build(None, Some(extra))
    }

    /// [`Rod::system_with_phase`] with the stiffening of [`Rod::system_stiffened`].
    pub(crate) fn system_with_phase_stiffened(
        &self,
        node: usize,
        azimuth: f64,
        extra: &[Vec<f64>],
    ) -> Result<AssembledSystem> {
        self.check_phase(node, azimuth)?;
        self.check_stiffening(extra)?;
        self.build(Some((node, azimuth)), Some(extra))
    }

    /// A phase condition's node is interior (1..=N) and its azimuth finite.
    fn check_phase(&self, node: usize, azimuth: f64) -> Result<()> {
        error::count_in_range("phase node", node as i64, 1, self.elements as i64)?;
        error::finite("azimuth", azimuth)?;
        Ok(())
    }

    /// Stiffening needs a Gauss scheme and one value per stage of every
    /// element.
    fn check_stiffening(&self, extra: &[Vec<f64>]) -> Result<()> {
        if extra.len() != self.elements
            || extra.iter().any(|e| e.len() != self.scheme.stages())
            || self.scheme == Scheme::Midpoint
        {
            return Err(Error::new(
                Status::ErrInvalidDimension,
                "stiffening needs a Gauss scheme and one value per stage of every element",
            ));
        }
        Ok(())
    }

    /// The system with a phase condition for rotationally symmetric rods
    /// (equal bending stiffnesses, loads along the axis): one more unknown,
    /// the unfolding parameter μ (index [`Rod::unknowns`], zero at every
    /// solution), in y' = f(y) + μB(y) (see [`kinematics::rhs_unfolded`]),
    /// and one more equation: the lateral displacement of node `node` has no
    /// component across the azimuth `azimuth` (−sin φ r_x + cos φ r_y = 0),
    /// which fixes the orientation of a buckled shape about the axis. Off
    /// the symmetric (straight) branch this makes the Jacobian regular where
    /// the symmetry would make it singular.
    pub fn system_with_phase(&self, node: usize, azimuth: f64) -> Result<AssembledSystem> {
        self.check_phase(node, azimuth)?;
        self.build(Some((node, azimuth)), None)
    }

    /// The assembled cubic system: the element blocks, the boundary block,
    /// the phase condition's block if any, and the scales.
    fn build(&self, phase: Phase, extra: Option<&[Vec<f64>]>) -> Result<AssembledSystem> {
        if self.breakpoints.as_ref().is_some_and(|t| t.len() != self.elements + 1) {
            return Err(Error::new(
                Status::ErrInternal,
                "a graded rod's breakpoints do not match its element count (make it with Rod::graded or Rod::uniform)",
            ));
        }
        let mut blocks = self.element_blocks(phase.is_some(), extra);
        blocks.push(self.boundary_block());
        let mu = self.unknowns();
        if let Some((node, azimuth)) = phase {
            let (s, c) = azimuth.sin_cos();
            let tape = Arc::new(Tape::record(2, |v| vec![v[1] * c - v[0] * s]));
            let at = self.node(node);
            blocks.push(Block::new(tape, vec![Slot::Unknown(at), Slot::Unknown(at + 1)], vec![mu]));
        }
        let n = self.unknowns() + phase.is_some() as usize;
        let (equations, unknowns, lambda_scale) = self.scales(n);
        // Each element's stage unknowns are private to it, their block
        // I − h(a ⊗ ∂f/∂y) regular for the step sizes the scheme converges
        // at (and where it is not, the tangent factorises whole).
        let stages = 13 * self.scheme.stages();
        let private = (0..self.elements)
            .filter(|_| stages > 0)
            .map(|i| (self.node(i) + 13..self.node(i) + 13 + stages).collect())
            .collect();
        let sys =
            AssembledSystem::new(n, blocks).with_scales(equations, unknowns, lambda_scale).with_private_blocks(private);
        let degree = sys.degree();
        if degree > 3 {
            return Err(Error::new(Status::ErrInternal, format!("rod system has degree {degree} (> 3)")));
        }
        Ok(sys)
    }

    /// One block per element: its kernel on the element's node, stages and
    /// next node, Λ (and μ when `unfold`), writing the stage rows at the
    /// stage slots and the update at the next node's. A uniform rod records
    /// one tape with h a constant; a graded one, one tape with h an input
    /// (a `Slot::Param` per element: every element still shares the tape,
    /// so they are evaluated four at a time in AssembledSystem's batches).
    /// With `extra` stiffening, one tape per distinct set of stage values.
    fn element_blocks(&self, unfold: bool, extra: Option<&[Vec<f64>]>) -> Vec<Block> {
        let data = self.rhs_data();
        let bs = self.block_size();
        let stages = self.scheme.stages();
        let tab = self.tableau();
        let graded = self.breakpoints.is_some();
        // The tapes' inputs: [node, stages, next node, Λ, (h), (μ)].
        let extra_in = unfold as usize + graded as usize;
        let h = (!graded).then(|| self.element_length());
        let uniform: Vec<RhsData> = vec![data.clone(); stages.max(1)];
        let inputs = bs + 14 + extra_in;
        // The tape (the structure, and the reference) and the same kernel
        // compiled, which evaluates it.
        let record = |per_stage: &[RhsData]| -> (Arc<Tape>, Option<Arc<dyn LaneKernel>>) {
            let tape = Arc::new(match self.scheme {
                Scheme::Midpoint => Tape::record(27 + extra_in, |v| {
                    let mut out = Vec::with_capacity(13);
                    midpoint_kernel(&per_stage[0], h, v, unfold, &mut |t| out.push(t));
                    out
                }),
                Scheme::Gauss(_) => Tape::record(13 * (stages + 2) + 1 + extra_in, |v| {
                    let mut out = Vec::with_capacity(13 * (stages + 1));
                    gauss_kernel(per_stage, h, &tab, v, unfold, &mut |t| out.push(t));
                    out
                }),
            });
            let kernel = ElementKernel::new(self.scheme, tab.clone(), h, unfold, per_stage.to_vec(), inputs)
                .map(|k| Arc::new(k) as Arc<dyn LaneKernel>);
            (tape, kernel)
        };
        // The uniform element's tape and kernel depend on nothing but these
        // numbers: a sweep that rebuilds the rod (new tip loads, supports,
        // element counts at one h) finds them recorded.
        // The key covers every argument of `record`: the scheme (stages and
        // order; the tableau follows), h (None on a graded mesh, where h is
        // an input), `unfold`, the input count (from the stages and those)
        // and the whole of RhsData, destructured so that a new field cannot
        // be left out.
        let key = {
            let RhsData { compliance, intrinsic_u, intrinsic_v, kirchhoff, force, couple } = &data;
            let mut k = vec![stages as u64, self.scheme.order() as u64, unfold as u64];
            k.push(h.map_or(u64::MAX, f64::to_bits));
            k.extend(compliance.iter().flatten().map(|v| v.to_bits()));
            k.extend(intrinsic_u.iter().chain(intrinsic_v).map(|v| v.to_bits()));
            k.push(*kirchhoff as u64);
            for load in [*force, *couple] {
                match load {
                    None => k.push(0),
                    Some((dead, v)) => {
                        k.push(1 + dead as u64);
                        k.extend(v.iter().map(|c| c.to_bits()));
                    }
                }
            }
            k
        };
        let element = recorded_element(key, || record(&uniform));
        // Stiffened elements: one tape per distinct set of stage values.
        let mut tapes: std::collections::HashMap<Vec<u64>, Recorded> = std::collections::HashMap::new();
        let mu = self.unknowns();
        let mut blocks = Vec::with_capacity(self.elements + 1);
        for i in 0..self.elements {
            let (tape, kernel) = match extra {
                Some(e) if e[i].iter().any(|v| *v != 0.0) => {
                    let key: Vec<u64> = e[i].iter().map(|v| v.to_bits()).collect();
                    tapes
                        .entry(key)
                        .or_insert_with(|| {
                            let per_stage: Vec<RhsData> = e[i].iter().map(|v| self.rhs_data_stiffened(*v)).collect();
                            record(&per_stage)
                        })
                        .clone()
                }
                _ => element.clone(),
            };
            let base = self.node(i);
            let mut inputs: Vec<Slot> = (0..bs + 13).map(|k| Slot::Unknown(base + k)).collect();
            inputs.push(Slot::Lambda);
            if graded {
                inputs.push(Slot::Param(self.element_h(i)));
            }
            if unfold {
                inputs.push(Slot::Unknown(mu));
            }
            // Stage rows at the stage slots, the update at the next node's.
            let mut rows: Vec<usize> = (0..13 * stages).map(|k| base + 13 + k).collect();
            rows.extend((0..13).map(|k| base + bs + k));
            debug_assert_eq!(inputs.len(), tape.inputs());
            blocks.push(Block { tape, inputs, rows, kernel });
        }
        blocks
    }

    /// The boundary conditions in node 0's rows (7 at s = 0, 6 at s = L),
    /// and the end-rotation unknowns' equations in their own rows.
    fn boundary_block(&self) -> Block {
        let (y0, yl) = (self.node(0), self.node(self.elements));
        let bc = Arc::new(self.boundary_tape());
        let mut inputs: Vec<Slot> = (0..13).map(|k| Slot::Unknown(y0 + k)).collect();
        inputs.extend((0..13).map(|k| Slot::Unknown(yl + k)));
        inputs.push(Slot::Lambda);
        let mut rows: Vec<usize> = (0..13).map(|k| y0 + k).collect();
        if let Some(c) = self.end_cosine() {
            inputs.push(Slot::Unknown(c));
            rows.push(c);
        }
        if let Some((c, s)) = self.end_angle() {
            inputs.extend([Slot::Unknown(c), Slot::Unknown(s)]);
            rows.extend([c, s]);
        }
        Block::new(bc, inputs, rows)
    }

    /// (equation scales, unknown scales, Λ's scale) of a system of `n`
    /// unknowns: the state scales for the unknowns, h × the scale of y' for
    /// element rows and the state scales for boundary rows; the end angle's
    /// cosine and sine 1; μ a distributed couple (moment per length, K_b/L²)
    /// with its phase row per length; a torque clamp's moment row and its Λ
    /// (the end torque) moments.
    fn scales(&self, n: usize) -> (Vec<f64>, Vec<f64>, f64) {
        let bs = self.block_size();
        let mu = self.unknowns();
        let ss = self.state_scales();
        // μ is a distributed couple: moment per length, K_b/L².
        let cosine = self.end_cosine();
        let angle = self.end_angle();
        let is_angle = |k: usize| Some(k) == cosine || angle.is_some_and(|(c, s)| k == c || k == s);
        let unknowns: Vec<f64> = (0..n)
            .map(|k| {
                if k == mu {
                    ss[10] / self.length
                } else if is_angle(k) {
                    1.0
                } else {
                    ss[k % 13]
                }
            })
            .collect();
        let scale_q = 1.0 / self.length;
        let rate = |k: usize| match k {
            0..=2 => 1.0,
            3..=6 => scale_q,
            _ => ss[k] / self.length,
        };
        let mut equations: Vec<f64> = (0..n)
            .map(|k| {
                if k == mu {
                    self.length
                } else if is_angle(k) {
                    1.0
                } else {
                    // Element e's rows: its stages' and node e + 1's.
                    let e = (k.saturating_sub(13) / bs).min(self.elements - 1);
                    self.element_h(e) * rate(k % 13)
                }
            })
            .collect();
        let bc_scales = self.boundary_scales();
        equations[..13].copy_from_slice(&bc_scales);
        // A torque clamp's moment row and its Λ (the end torque): moments.
        let lambda_scale = if let Some((_, s)) = angle {
            equations[s] = ss[10];
            ss[10]
        } else {
            1.0
        };
        (equations, unknowns, lambda_scale)
    }

    fn boundary_scales(&self) -> [f64; 13] {
        let ss = self.state_scales();
        let mut s = [0.0; 13];
        // s = 0: r (3), q (4) or the pinned set; s = L: 6 of force/moment or position/rotation.
        match self.supports {
            Supports::Cantilever => {
                s[..7].copy_from_slice(&ss[..7]);
                s[7..13].copy_from_slice(&ss[7..13]);
            }
            Supports::Clamped { .. } => {
                s[..7].copy_from_slice(&ss[..7]);
                s[7..10].copy_from_slice(&ss[0..3]);
                s[10..13].fill(1.0);
            }
            Supports::Twisted { .. } | Supports::TwistedAtDistance { .. } | Supports::Torqued { .. } => {
                s[..7].copy_from_slice(&ss[..7]);
                s[7] = ss[0];
                s[8] = ss[1];
                s[9] = if matches!(self.supports, Supports::TwistedAtDistance { .. }) { ss[2] } else { ss[9] };
                s[10..13].fill(1.0);
            }
            Supports::Pinned => {
                s[..3].copy_from_slice(&ss[..3]);
                s[3] = ss[10];
                s[4] = ss[11];
                s[5] = 1.0;
                s[6] = 1.0;
                s[7] = ss[0];
                s[8] = ss[1];
                s[9] = ss[9];
                s[10..13].copy_from_slice(&ss[10..13]);
            }
        }
        s
    }

    /// The 13 boundary conditions (7 at s = 0, 6 at s = L) and those of the
    /// end-rotation unknowns, recorded on the inputs (y(0), y(L), Λ, then
    /// c = cos(φ/2) for a twisted rod or (c, s) for a torqued one).
    fn boundary_tape(&self) -> Tape {
        let loads = self.loads;
        let supports = self.supports;
        let inputs = 27 + self.boundary_unknowns();
        Tape::record(inputs, move |v| {
            let y0 = &v[0..13];
            let yl = &v[13..26];
            let lambda = v[26];
            let mut out: Vec<Var> = Vec::with_capacity(13);
            start_conditions(supports, y0, &mut out);
            let end = End { y: yl, q: [yl[3], yl[4], yl[5], yl[6]], lambda };
            match supports {
                Supports::Cantilever => end.free(&loads, &mut out),
                Supports::Clamped { end_position, end_rotation, end_displacement } => {
                    end.clamped(end_position, end_rotation, end_displacement, &mut out)
                }
                Supports::Twisted { .. } | Supports::TwistedAtDistance { .. } => end.turned(supports, v[27], &mut out),
                Supports::Torqued { tension } => end.torqued(tension, (v[27], v[28]), &mut out),
                Supports::Pinned => end.pinned(&loads, &mut out),
            }
            out
        })
    }
}

/// The 7 conditions at s = 0: clamped at the origin along e3 (r = 0,
/// q = (1, 0, 0, 0)), or for a ball joint r = 0, m_b1 = m_b2 = 0, no twist
/// (q3 = 0) and |q|² = 1.
fn start_conditions(supports: Supports, y0: &[Var], out: &mut Vec<Var>) {
    match supports {
        Supports::Cantilever
        | Supports::Clamped { .. }
        | Supports::Twisted { .. }
        | Supports::TwistedAtDistance { .. }
        | Supports::Torqued { .. } => {
            out.extend_from_slice(&y0[0..3]);
            out.push(y0[3] - 1.0);
            out.extend_from_slice(&y0[4..7]);
        }
        Supports::Pinned => {
            out.extend_from_slice(&y0[0..3]);
            out.push(y0[10]);
            out.push(y0[11]);
            out.push(y0[6]);
            out.push(y0[3] * y0[3] + y0[4] * y0[4] + y0[5] * y0[5] + y0[6] * y0[6] - 1.0);
        }
    }
}

/// The state at s = L on the tape: y(L), its quaternion q(L) and Λ; each
/// support's conditions there (6, plus those of the end-rotation unknowns).
struct End<'v> {
    y: &'v [Var],
    q: [Var; 4],
    lambda: Var,
}

impl End<'_> {
    /// Free end: n_b(L) and m_b(L) equal to Λ times the tip force and
    /// moment (follower: body components as given; dead: turned into the
    /// body frame by R(q)ᵀ).
    fn free(&self, loads: &Loads, out: &mut Vec<Var>) {
        let (yl, lambda) = (self.y, self.lambda);
        let end = |l: Option<Load>, at: usize, out: &mut Vec<Var>| {
            let applied: [Option<Var>; 3] = match l {
                None => [None; 3],
                Some(Load { frame: Frame::Follower, vector }) => vector.map(|c| (c != 0.0).then(|| lambda * c)),
                Some(Load { frame: Frame::Dead, vector }) => {
                    let b = kinematics::to_body(&self.q, &vector);
                    [Some(b[0] * lambda), Some(b[1] * lambda), Some(b[2] * lambda)]
                }
            };
            for k in 0..3 {
                out.push(match applied[k] {
                    Some(a) => yl[at + k] - a,
                    None => yl[at + k],
                });
            }
        };
        end(loads.tip_force, 7, out);
        end(loads.tip_moment, 10, out);
    }

    /// Clamped end: r(L) = end position + Λ·end displacement, and the vector
    /// part of q̄_end ∘ q(L) zero.
    fn clamped(&self, position: [f64; 3], rotation: [f64; 4], displacement: [f64; 3], out: &mut Vec<Var>) {
        let (yl, lambda) = (self.y, self.lambda);
        for k in 0..3 {
            let moved = if displacement[k] != 0.0 {
                lambda * displacement[k] + position[k]
            } else {
                Var::constant(position[k])
            };
            out.push(yl[k] - moved);
        }
        let conj = [rotation[0], -rotation[1], -rotation[2], -rotation[3]];
        let c = [Var::constant(conj[0]), Var::constant(conj[1]), Var::constant(conj[2]), Var::constant(conj[3])];
        let rel = kinematics::quat_mul(&c, &self.q);
        out.extend_from_slice(&rel[1..4]);
    }

    /// Controlled end rotation ([`Supports::Twisted`], [`Supports::TwistedAtDistance`]):
    /// on the axis, the spatial axial force equal to the tension (or r_z(L)
    /// equal to the distance), the section turned about e3 by φ: vector part
    /// of q̄_t ∘ q(L) zero with q_t = (c, 0, 0, Λ), and c² + Λ² = 1.
    fn turned(&self, supports: Supports, c: Var, out: &mut Vec<Var>) {
        let (yl, lambda, ql) = (self.y, self.lambda, &self.q);
        out.push(yl[0]);
        out.push(yl[1]);
        if let Supports::Twisted { tension } = supports {
            let rot = kinematics::rotation(ql);
            let nz = rot[2][0] * yl[7] + rot[2][1] * yl[8] + rot[2][2] * yl[9];
            out.push(nz - tension);
        } else if let Supports::TwistedAtDistance { distance } = supports {
            out.push(yl[2] - distance);
        }
        // Vector part of q̄_t ∘ q(L), q_t = (c, 0, 0, Λ).
        let zero = Var::constant(0.0);
        let conj = [c, zero, zero, -lambda];
        let rel = kinematics::quat_mul(&conj, ql);
        out.extend_from_slice(&rel[1..4]);
        out.push(c * c + lambda * lambda - 1.0);
    }

    /// Controlled end moment ([`Supports::Torqued`]): on the axis, pulled by
    /// the tension, the section turned about e3 by the free angle φ (q_t =
    /// (c, 0, 0, s), c² + s² = 1) and the end torque m_b3(L) = Λ.
    fn torqued(&self, tension: f64, (c, s): (Var, Var), out: &mut Vec<Var>) {
        let (yl, lambda) = (self.y, self.lambda);
        out.push(yl[0]);
        out.push(yl[1]);
        // The end section turns about e3 only (q(L) ∥ q_t below), so
        // R e3 = e3 and the spatial axial force and moment are the
        // body ones, n_b3 and m_b3. Written so: (R(q) m_b)_z would
        // also carry |q(L)|² (R is quadratic in q, exactly 1 at a
        // solution: Gauss collocation conserves |q|), and near a
        // solution the drift of |q| along the rod, pinned only at
        // s = 0, could then trade against m_b3 at a cost ∝ 1/M:
        // σ_min of the straight DNA rod fell as 1/M (0.004 at
        // buckling) and hid the buckling points' dips.
        out.push(yl[9] - tension);
        // Vector part of q̄_t ∘ q(L), q_t = (c, 0, 0, s).
        let zero = Var::constant(0.0);
        let rel = kinematics::quat_mul(&[c, zero, zero, -s], &self.q);
        out.extend_from_slice(&rel[1..4]);
        out.push(c * c + s * s - 1.0);
        // The end torque: m_b3(L) = Λ.
        out.push(yl[12] - lambda);
    }

    /// Ball joint at s = L: on the axis (r_x = r_y = 0), the spatial axial
    /// force (R(q) n_b)_z = Λ P (P the dead tip force's axial component) and
    /// m_b = 0.
    fn pinned(&self, loads: &Loads, out: &mut Vec<Var>) {
        let (yl, lambda) = (self.y, self.lambda);
        out.push(yl[0]);
        out.push(yl[1]);
        // Spatial axial force (R(q) n_b)_z = Λ P.
        let rot = kinematics::rotation(&self.q);
        let nz = rot[2][0] * yl[7] + rot[2][1] * yl[8] + rot[2][2] * yl[9];
        let p = loads.tip_force.map_or(0.0, |l| l.vector[2]);
        out.push(if p != 0.0 { nz - lambda * p } else { nz });
        out.extend_from_slice(&yl[10..13]);
    }
}

/// The end rotation φ (mod 4π, as from [`Rod::end_rotation`] of a
/// [`Supports::Torqued`] rod) shifted by a multiple of 4π to the nearest of
/// `previous`: turns tracked along a path whose steps turn the end by less
/// than 2π.
pub fn unwrap_rotation(previous: f64, phi: f64) -> f64 {
    let period = 4.0 * std::f64::consts::PI;
    phi + period * ((previous - phi) / period).round()
}

/// f, or f + μA with the unfolding parameter as the kernel's last input.
pub(super) fn field<T: Scalar + Mul<C, Output = T>, C: Coefficient>(
    data: &RhsData<C>,
    y: &[T],
    lambda: T,
    v: &[T],
    unfold: bool,
) -> [T; 13] {
    if unfold {
        kinematics::rhs_unfolded(data, y, lambda, v[v.len() - 1])
    } else {
        kinematics::rhs(data, y, lambda)
    }
}

/// The element length h in a kernel: a uniform rod's constant, or a
/// graded rod's input (right after Λ).
#[derive(Clone, Copy)]
enum Step<T> {
    Fixed(f64),
    Input(T),
}

/// h given (`Some`), else the input at `at`.
fn step<T: Scalar>(h: Option<f64>, v: &[T], at: usize) -> Step<T> {
    match h {
        Some(h) => Step::Fixed(h),
        None => Step::Input(v[at]),
    }
}

/// The implicit midpoint rule on one element: its 13 rows, in order, to
/// `emit`.
pub(super) fn midpoint_kernel<T: Scalar + Mul<C, Output = T>, C: Coefficient>(
    data: &RhsData<C>,
    h: Option<f64>,
    v: &[T],
    unfold: bool,
    emit: &mut impl FnMut(T),
) {
    let (a, b, lambda) = (&v[0..13], &v[13..26], v[26]);
    let mid: [T; 13] = std::array::from_fn(|k| (a[k] + b[k]) * 0.5);
    let f = field(data, &mid, lambda, v, unfold);
    match step(h, v, 27) {
        Step::Fixed(h) => (0..13).for_each(|k| emit(b[k] - a[k] - f[k] * h)),
        Step::Input(h) => (0..13).for_each(|k| emit(b[k] - a[k] - f[k] * h)),
    }
}

/// Stages an element kernel holds on the stack (the tableau's largest:
/// `Tableau::gauss` takes 1..=8).
const MAX_STAGES: usize = 8;

/// Gauss collocation on one element; `data[j]` is stage j's right-hand side
/// (equal for an uncharged rod, stiffened per stage for a charged one).
/// With h an input (a graded rod), each row's increment is Σ_j a_ij f_j
/// times h: one product per row.
pub(super) fn gauss_kernel<T: Scalar + Mul<C, Output = T>, C: Coefficient>(
    data: &[RhsData<C>],
    h: Option<f64>,
    tab: &Tableau,
    v: &[T],
    unfold: bool,
    emit: &mut impl FnMut(T),
) {
    let s = tab.c.len();
    assert!(s <= MAX_STAGES, "a Gauss tableau of {s} stages (at most {MAX_STAGES})");
    let y0 = &v[0..13];
    let stage = |j: usize| &v[13 * (1 + j)..13 * (2 + j)];
    let y1 = &v[13 * (1 + s)..13 * (2 + s)];
    let lambda = v[13 * (2 + s)];
    let f: [Option<[T; 13]>; MAX_STAGES] =
        std::array::from_fn(|j| (j < s).then(|| field(&data[j], stage(j), lambda, v, unfold)));
    let f = |j: usize| f[j].as_ref().expect("a stage of the tableau");
    let step = step(h, v, 13 * (2 + s) + 1);
    // Row k of start − y0 − h Σ_j w_j f_j.
    let mut row = |start: T, k: usize, w: &[f64]| match step {
        Step::Fixed(h) => {
            let mut e = start - y0[k];
            for j in 0..s {
                e = e - f(j)[k] * (h * w[j]);
            }
            emit(e);
        }
        Step::Input(h) => {
            let mut sum = f(0)[k] * w[0];
            for j in 1..s {
                sum = sum + f(j)[k] * w[j];
            }
            emit(start - y0[k] - sum * h);
        }
    };
    for i in 0..s {
        for k in 0..13 {
            row(stage(i)[k], k, &tab.a[i]);
        }
    }
    for k in 0..13 {
        row(y1[k], k, &tab.b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rod(bending2: f64, elements: usize) -> Rod {
        let law = RodLaw::isotropic(1.0, bending2, 1e4, 2.6e4).unwrap();
        let loads = Loads { tip_force: Some(Load::dead([1.0, 0.0, 0.0])), ..Default::default() };
        Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), elements).unwrap()
    }

    /// The element cache: a rebuilt rod shares its element's recorded tape
    /// and kernel; a changed law or element length records its own; and the
    /// shared tape evaluates bitwise as one recorded afresh (the reference:
    /// the cache emptied first).
    #[test]
    fn a_rebuilt_rod_reuses_its_recorded_element() {
        let first = rod(0.77, 4).element_blocks(false, None);
        let again = rod(0.77, 4).element_blocks(false, None);
        assert!(Arc::ptr_eq(&first[0].tape, &again[0].tape));
        assert!(Arc::ptr_eq(&first[0].tape, &again[3].tape));
        assert!(!Arc::ptr_eq(&first[0].tape, &rod(0.78, 4).element_blocks(false, None)[0].tape));
        assert!(!Arc::ptr_eq(&first[0].tape, &rod(0.77, 5).element_blocks(false, None)[0].tape));
        ELEMENTS.with(|e| e.borrow_mut().clear());
        let fresh = rod(0.77, 4).element_blocks(false, None);
        assert!(!Arc::ptr_eq(&first[0].tape, &fresh[0].tape));
        let (a, b) = (&first[0].tape, &fresh[0].tape);
        assert_eq!(a.inputs(), b.inputs());
        let x: Vec<f64> = (0..a.inputs()).map(|i| ((i * 37 % 11) as f64 - 5.0) / 7.0).collect();
        let outputs = a.outputs();
        let (mut oa, mut ob, mut w) = (vec![0.0; outputs], vec![0.0; outputs], vec![]);
        a.eval(&x, &mut w, &mut oa);
        b.eval(&x, &mut w, &mut ob);
        assert!(oa.iter().all(|v| v.is_finite()));
        assert_eq!(
            oa.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            ob.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        // Bounded: RECORDED entries at most.
        for k in 0..2 * RECORDED {
            rod(0.5 + 0.01 * k as f64, 2).element_blocks(false, None);
        }
        assert_eq!(ELEMENTS.with(|e| e.borrow().len()), RECORDED);
    }
}

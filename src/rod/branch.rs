//! Branches of rod equilibria: continuation from a state, resumption, and
//! switching at a located bifurcation — the phase condition chosen for the
//! caller when the point is double (rotational symmetry). What the C ABI
//! and the drivers use; the generic engines do the work.

use super::model::Rod;
use crate::continuation::anm::{continue_anm, AnmOptions};
use crate::continuation::bifurcation::{branch_start, Bifurcation};
use crate::continuation::corrector::correct;
use crate::continuation::newton::{continue_newton, Start};
use crate::continuation::system::AssembledSystem;
use crate::continuation::tangent::Bordered;
use crate::continuation::{Counts, Options, Problem, Record, Resume, Sample, Scaling, Stop};
use crate::error::{self, Error, Result};
use crate::status::Status;

/// Which engine follows the branch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    Anm(AnmOptions),
    Newton,
}

/// A followed branch with the full state at every record.
#[derive(Clone, Debug)]
pub struct RodBranch {
    pub records: Vec<Record>,
    /// x at each record (with the unfolding parameter μ last on a branch
    /// followed with a phase condition).
    pub states: Vec<Vec<f64>>,
    pub bifurcations: Vec<Bifurcation>,
    pub stop: Stop,
    pub counts: Counts,
    pub resume: Resume,
    /// The phase condition (node, azimuth) the branch was followed with.
    pub phase: Option<(usize, f64)>,
    /// Self-contact (with a rod diameter): the first record where
    /// non-neighbouring points are closer than the diameter, with that
    /// distance and the pair's arc lengths. The rod has no contact model:
    /// records past it pass through themselves.
    pub contact: Option<Contact>,
    /// Points at the requested loads (`Options::samples`), their outputs
    /// moved into `sample_states`.
    pub samples: Vec<Sample>,
    pub sample_states: Vec<Vec<f64>>,
    /// Requested loads crossed where no point within the tolerance was found.
    pub missed_samples: Vec<f64>,
}

/// Where a branch first passes through itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    pub record: usize,
    pub distance: f64,
    pub s1: f64,
    pub s2: f64,
}

impl Rod {
    fn system_for(&self, phase: Option<(usize, f64)>) -> Result<AssembledSystem> {
        match phase {
            Some((node, azimuth)) => self.system_with_phase(node, azimuth),
            None => self.system(),
        }
    }

    /// The options for the system followed: a caller's scaling is for the
    /// rod's n unknowns; with a phase condition the unfolding parameter μ
    /// is appended with its own scale.
    fn options_for(&self, opts: &Options, sys: &AssembledSystem) -> Options {
        match &opts.scaling {
            Some(s) if s.x.len() + 1 == sys.dim() => {
                let mut x = s.x.clone();
                x.push(*sys.unknown_scales().0.last().expect("a phase system has μ"));
                Options { scaling: Some(Scaling { x, lambda: s.lambda }), ..opts.clone() }
            }
            _ => opts.clone(),
        }
    }

    fn follow(
        &self,
        start: Start,
        phase: Option<(usize, f64)>,
        opts: &Options,
        method: Method,
        mut progress: impl FnMut(&Record) -> bool,
    ) -> Result<RodBranch> {
        let mut sys = self.system_for(phase)?;
        let opts = &self.options_for(opts, &sys);
        let mut states = Vec::new();
        let observe = |x: &[f64], _: f64| x.to_vec();
        let mut cb = |r: &Record| progress(r);
        let b = match method {
            Method::Anm(a) => continue_anm(&mut sys, start, opts, &a, observe, &mut cb)?,
            Method::Newton => continue_newton(&mut sys, start, opts, observe, &mut cb)?,
        };
        let mut records = b.records;
        for r in &mut records {
            states.push(std::mem::take(&mut r.outputs));
        }
        let contact = self.diameter.and_then(|d| {
            states.iter().enumerate().find_map(|(k, x)| {
                let (distance, s1, s2) = self.closest_approach(x)?;
                (distance < d).then_some(Contact { record: k, distance, s1, s2 })
            })
        });
        let mut samples = b.samples;
        let sample_states = samples.iter_mut().map(|s| std::mem::take(&mut s.outputs)).collect();
        Ok(RodBranch {
            records,
            states,
            bifurcations: b.bifurcations,
            stop: b.stop,
            counts: b.counts,
            resume: b.resume,
            phase,
            contact,
            samples,
            sample_states,
            missed_samples: b.missed_samples,
        })
    }

    /// A branch from the state `x0` at `lambda0` (None: the straight state),
    /// leaving towards increasing Λ when `increasing`.
    pub fn continue_branch(
        &self,
        x0: Option<&[f64]>,
        lambda0: f64,
        increasing: bool,
        opts: &Options,
        method: Method,
        progress: impl FnMut(&Record) -> bool,
    ) -> Result<RodBranch> {
        error::finite("lambda0", lambda0)?;
        let x = match x0 {
            Some(x) => {
                error::count_in_range("state length", x.len() as i64, self.unknowns() as i64, self.unknowns() as i64)?;
                error::finite_result("x0", x)?;
                x.to_vec()
            }
            None => self.straight_state(),
        };
        self.follow(Start::Point { x, lambda: lambda0, increasing }, None, opts, method, progress)
    }

    /// Continue `branch` from where it stopped (same phase condition).
    pub fn resume_branch(
        &self,
        branch: &RodBranch,
        opts: &Options,
        method: Method,
        progress: impl FnMut(&Record) -> bool,
    ) -> Result<RodBranch> {
        self.follow(Start::Resume(branch.resume.clone()), branch.phase, opts, method, progress)
    }

    /// Leave `branch` at its bifurcation `index` along null direction
    /// `direction`. At a double point of a symmetric rod the new branch is
    /// followed with a phase condition: the node of largest deflection in
    /// that direction (the tip of a cantilever, the middle node otherwise)
    /// keeps no displacement across the direction's azimuth.
    pub fn switch_branch(
        &self,
        branch: &RodBranch,
        index: usize,
        direction: usize,
        first_step: f64,
        opts: &Options,
        method: Method,
        progress: impl FnMut(&Record) -> bool,
    ) -> Result<RodBranch> {
        let bif = branch.bifurcations.get(index).ok_or_else(|| {
            Error::new(
                Status::ErrOutOfRange,
                format!("bifurcation index {index} out of range (the branch has {})", branch.bifurcations.len()),
            )
        })?;
        let (nx, nl) = bif.null_vectors.get(direction).ok_or_else(|| {
            Error::new(
                Status::ErrOutOfRange,
                format!(
                    "direction {direction} out of range (the point has {} null directions)",
                    bif.null_vectors.len()
                ),
            )
        })?;
        error::positive("first_step", first_step)?;
        let (phase, bif, direction) = if branch.phase.is_none() && bif.multiplicity >= 2 {
            let (node, azimuth) = self.phase_for(nx)?;
            let mut aug = bif.clone();
            aug.x.push(0.0);
            aug.tangent_x.push(0.0);
            let mut d = nx.clone();
            d.push(0.0);
            (Some((node, azimuth)), aug, d)
        } else {
            (branch.phase, bif.clone(), nx.clone())
        };
        let sys = self.system_for(phase)?;
        let (sx, sl) = sys.unknown_scales();
        let mu_scale = sx.last().copied().unwrap_or(1.0);
        crate::continuation::newton::validate(&sys, &Options { scaling: None, ..opts.clone() })?;
        let opts = &self.options_for(opts, &sys);
        let scaling = opts.scaling.clone().unwrap_or(Scaling { x: sx, lambda: sl });
        let mut start = branch_start(&bif, (&direction, *nl), first_step, &scaling);
        if let Some((node, azimuth)) = phase {
            let mut sys = self.system_for(phase)?;
            start = self.amplitude_start(
                &mut sys,
                &scaling,
                &start,
                (node, azimuth),
                first_step,
                opts.residual_tol,
                &mut Counts::default(),
            )?;
        }
        // Without a phase condition the start is the (near-)singular point
        // itself: a switch start keeps the null direction for the first step.
        let first = if phase.is_some() { Start::Resume(start) } else { Start::Switch(start) };
        let b = self.follow(first, phase, opts, method, progress)?;
        if phase.is_some() {
            self.check_unfolding(&b.states, mu_scale)?;
        }
        Ok(b)
    }

    /// The phase condition for leaving a double point along null direction
    /// `nx`: the node where its lateral displacement is largest (the tip of
    /// a cantilever, mid-span between clamps — where the buckle's azimuth
    /// is best determined) and that azimuth.
    pub(crate) fn phase_for(&self, nx: &[f64]) -> Result<(usize, f64)> {
        let lateral = |i: usize| {
            let at = self.node(i);
            nx[at].hypot(nx[at + 1])
        };
        let node = (1..=self.elements).fold(0, |best, i| if lateral(i) > lateral(best) { i } else { best });
        if node == 0 || lateral(node) == 0.0 {
            return Err(Error::new(
                Status::ErrOutOfRange,
                "a phase condition needs a null direction with a lateral displacement (and at least 2 elements)",
            ));
        }
        let at = self.node(node);
        Ok((node, nx[at + 1].atan2(nx[at])))
    }

    /// The first point of a branch switched with a phase condition, taken at
    /// a fixed buckle amplitude instead of the arc length: ⟨X − X_pred, e⟩ =
    /// 0 with e the phase node's displacement along the azimuth. Straight
    /// states (amplitude 0), where the unfolding vanishes and μ would be
    /// free, are excluded. `problem` is the rod's system with that phase
    /// condition (charged or not); returns the point with its secant tangent.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn amplitude_start<P: crate::continuation::Problem + ?Sized>(
        &self,
        problem: &mut P,
        scaling: &Scaling,
        start: &Resume,
        (node, azimuth): (usize, f64),
        first_step: f64,
        residual_tol: f64,
        counts: &mut Counts,
    ) -> Result<Resume> {
        let mut bordered = Bordered::new(problem.pattern())?;
        let eq = problem.equation_scales();
        let mut e = vec![0.0; start.x.len()];
        let at = self.node(node);
        e[at] = azimuth.cos();
        e[at + 1] = azimuth.sin();
        let mut x: Vec<f64> = start.x.iter().zip(&start.tangent_x).map(|(a, t)| a + first_step * t).collect();
        let mut l = start.lambda + first_step * start.tangent_lambda;
        let anchor = x.clone();
        let al = l;
        correct(
            problem,
            &mut bordered,
            scaling,
            &eq,
            &mut x,
            &mut l,
            (&anchor, al),
            (&e, 0.0),
            residual_tol,
            false,
            counts,
        )?;
        let dx: Vec<f64> = x.iter().zip(&start.x).map(|(a, b)| a - b).collect();
        let norm = scaling.norm(&dx, l - start.lambda);
        Ok(Resume {
            tangent_x: dx.iter().map(|v| v / norm).collect(),
            tangent_lambda: (l - start.lambda) / norm,
            x,
            lambda: l,
            step: first_step,
        })
    }

    /// μ = 0 on every tilted solution, but the unfolding vanishes on the
    /// straight branch, where (straight state, any μ) also solves the
    /// augmented system: a corrector can slide onto that spurious family
    /// (seen with twist–stretch coupling). Refuse such a branch (μ, the
    /// entry after the rod's unknowns, beyond 1e-6 of its scale).
    pub(crate) fn check_unfolding(&self, states: &[Vec<f64>], mu_scale: f64) -> Result<()> {
        let n = self.unknowns();
        if let Some((k, x)) = states.iter().enumerate().find(|(_, x)| x[n].abs() > 1e-6 * mu_scale) {
            return Err(Error::new(
                Status::ErrNotConverged,
                format!(
                    "branch switching with a phase condition left the unfolding parameter at μ = {:e} (point {k}): it followed the spurious straight family, not the buckled branch; try another first_step",
                    x[n]
                ),
            ));
        }
        Ok(())
    }

    /// The angle between the tip tangent d3(L) and e3 (radians, 0…π).
    pub fn tip_rotation(&self, x: &[f64]) -> f64 {
        let y = self.node_state(x, self.elements);
        let n2 = y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6];
        let d3z = (y[3] * y[3] - y[4] * y[4] - y[5] * y[5] + y[6] * y[6]) / n2;
        d3z.clamp(-1.0, 1.0).acos()
    }

    /// Spatial force and moment at node i: R(q) n_b, R(q) m_b.
    pub fn spatial_force_moment(&self, x: &[f64], i: usize) -> ([f64; 3], [f64; 3]) {
        let y = self.node_state(x, i);
        let q = [y[3], y[4], y[5], y[6]];
        let r = super::kinematics::rotation(&q);
        let n = super::kinematics::mat_vec(&r, &[y[7], y[8], y[9]]);
        let m = super::kinematics::mat_vec(&r, &[y[10], y[11], y[12]]);
        (n, m)
    }

    /// Node positions r(s_i), i = 0…N.
    pub fn positions(&self, x: &[f64]) -> Vec<[f64; 3]> {
        (0..=self.elements)
            .map(|i| {
                let y = self.node_state(x, i);
                [y[0], y[1], y[2]]
            })
            .collect()
    }
}

//! The continuation's corrections, as the one Newton iteration of
//! [`crate::nonlinear`] on the bordered tangent ([`Bordered`]):
//!
//! * [`correct`]: Newton on [R(x, Λ) = 0, ⟨(x, Λ) − anchor, v⟩_W = 0] —
//!   the pseudo-arc-length corrector, the fixed-Λ correction (v = e_Λ) and
//!   the bifurcation location's trial points — undamped, with a fresh
//!   factorisation per iteration or chord iterations on the caller's;
//! * [`deliver_sample`]: a point at a fixed load from a prediction by
//!   chord iterations on the step's factorisation, projected onto ΔΛ = 0,
//!   falling back to [`correct`] at fixed Λ.

use super::equilibrium::AtFixed;
use super::run::{Context, Factors};
use super::tangent::Bordered;
use super::{Counts, Problem, Scaling};
use crate::error::{Error, Result};
use crate::nonlinear::{self, Equations, FullStep, Iterate, LinearSolve, LinearStep, ResidualTest, Stall};
use crate::status::Status;

/// The corrector's equations in X = (x, Λ): F(X) = (R(x, Λ), ⟨X − anchor, v⟩_W).
struct Arclength<'a, P: ?Sized> {
    problem: &'a mut P,
    scaling: &'a Scaling,
    anchor: (&'a [f64], f64),
    v: (&'a [f64], f64),
    dx: Vec<f64>,
    residuals: usize,
    residual_time: std::time::Duration,
}

impl<P: Problem + ?Sized> Equations for Arclength<'_, P> {
    fn dim(&self) -> usize {
        self.dx.len() + 1
    }

    fn residual(&mut self, x: &[f64], f: &mut [f64]) -> Result<bool> {
        let n = self.dx.len();
        let t = std::time::Instant::now();
        self.problem.residual(&x[..n], x[n], &mut f[..n]);
        self.residual_time += t.elapsed();
        self.residuals += 1;
        for i in 0..n {
            self.dx[i] = x[i] - self.anchor.0[i];
        }
        f[n] = self.scaling.dot(&self.dx, x[n] - self.anchor.1, self.v.0, self.v.1);
        Ok(true)
    }
}

/// The Newton step of [`Arclength`] from the bordered tangent with border
/// v: a fresh factorisation at every iteration, or (chord) the current one
/// while the residual at least halves per iteration and a fresh one (then
/// kept) when it does not.
struct BorderedStep<'a> {
    bordered: &'a mut Bordered,
    chord: bool,
    /// Factorise at the first iterate even with a factorisation in hand.
    fresh_first: bool,
    counts: Counts,
}

/// How [`correct`] uses the context's factorisation of the bordered
/// tangent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Reuse {
    /// Newton: a fresh factorisation at every iterate.
    No,
    /// Chord iterations on the factorisation in hand, refactorised when
    /// the residual does not halve.
    Chord,
    /// As `Chord`, from a fresh factorisation at the first iterate (the
    /// one in hand was taken elsewhere).
    ChordFromFresh,
}

impl Reuse {
    /// `Chord` when `chord`, else `No`.
    pub(crate) fn chord_if(chord: bool) -> Self {
        if chord {
            Reuse::Chord
        } else {
            Reuse::No
        }
    }
}

impl<P: Problem + ?Sized> LinearSolve<Arclength<'_, P>> for BorderedStep<'_> {
    fn step(
        &mut self,
        eq: &mut Arclength<'_, P>,
        x: &[f64],
        f: &[f64],
        it: &Iterate,
        delta: &mut [f64],
    ) -> Result<LinearStep> {
        let n = x.len() - 1;
        // A chord step needs a factorisation in hand (none at a switch's
        // start, or after a failed one).
        let fresh = !self.chord
            || (self.fresh_first && it.iteration == 0)
            || it.norm > 0.5 * it.previous
            || !self.bordered.factorised();
        if fresh {
            self.bordered.factorise_at(
                eq.problem,
                &x[..n],
                x[n],
                eq.v,
                eq.scaling,
                &mut self.counts,
                Factors::ForSolves,
            )?;
        }
        for (d, v) in delta.iter_mut().zip(f) {
            *d = -v;
        }
        if fresh {
            self.bordered.solve(delta, &mut self.counts);
        } else {
            // A kept factorisation, bordered by an older tangent: solved
            // with this plane's border.
            self.bordered.solve_with_border(delta, eq.v, eq.scaling, &mut self.counts);
        }
        Ok(LinearStep { eta: 0.0, fresh })
    }
}

/// The equation scales with the arc-length row left out of the test.
fn with_free_border(equation_scales: &[f64]) -> Vec<f64> {
    let mut d = equation_scales.to_vec();
    d.push(f64::INFINITY);
    d
}

/// The hyperplane ⟨(x, Λ) − anchor, v⟩_W = 0 a correction stays on.
#[derive(Clone, Copy)]
pub(crate) struct Plane<'a> {
    pub anchor: (&'a [f64], f64),
    /// v; None: e_Λ (the correction at fixed Λ).
    pub normal: Option<(&'a [f64], f64)>,
}

impl<'a> Plane<'a> {
    pub fn new(anchor: (&'a [f64], f64), normal: (&'a [f64], f64)) -> Self {
        Plane { anchor, normal: Some(normal) }
    }

    /// Λ fixed at `lambda`.
    pub fn fixed(anchor: &'a [f64], lambda: f64) -> Self {
        Plane { anchor: (anchor, lambda), normal: None }
    }
}

/// Newton on [R(x, Λ) = 0, ⟨(x, Λ) − anchor, v⟩_W = 0] (`plane`) in place,
/// to max |R_i|/e_i ≤ `tol`. `reuse` ([`Reuse`]): with chord iterations on
/// the context's factorisation of the bordered tangent (border v),
/// refactorised when the residual does not halve, a stall after a fresh
/// factorisation (from the third iteration) fails. At most 12 iterations
/// (20 with chord: they converge linearly, more of them, each a residual and
/// a solve, before a fresh factorisation is worth it). Returns (iterations,
/// final residual).
pub(crate) fn correct<P: Problem + ?Sized>(
    problem: &mut P,
    ctx: &mut Context,
    x: &mut [f64],
    lambda: &mut f64,
    plane: Plane<'_>,
    tol: f64,
    reuse: Reuse,
) -> Result<(usize, f64)> {
    let (reuse, fresh_first) = (reuse != Reuse::No, reuse == Reuse::ChordFromFresh);
    let n = x.len();
    let e_lambda;
    let v = match plane.normal {
        Some(v) => v,
        None => {
            e_lambda = vec![0.0; n];
            (&e_lambda[..], 1.0)
        }
    };
    let mut xl = x.to_vec();
    xl.push(*lambda);
    let Context { scaling, eq: equation_scales, bordered, counts, patient } = ctx;
    let mut eq = Arclength {
        problem,
        scaling,
        anchor: plane.anchor,
        v,
        dx: vec![0.0; n],
        residuals: 0,
        residual_time: Default::default(),
    };
    let mut linear = BorderedStep { bordered, chord: reuse, fresh_first, counts: Counts::default() };
    let mut test = ResidualTest::new(with_free_border(equation_scales), tol, "Newton correction");
    test.non_finite = Status::ErrNotConverged;
    test.stall = if reuse || *patient { Stall::TwiceAfterFresh } else { Stall::AfterFresh };
    let max_iterations = if reuse { 20 } else { 12 };
    let result = nonlinear::solve(&mut eq, &mut xl, &mut linear, &mut FullStep::new(n + 1), &mut test, max_iterations);
    counts.residuals += eq.residuals;
    counts.times.residuals += eq.residual_time;
    counts.add(&linear.counts);
    x.copy_from_slice(&xl[..n]);
    *lambda = xl[n];
    result.map(|r| (r.iterations, r.norm))
}

/// Chord steps at fixed Λ on the current bordered factorisation (taken
/// near the point, with tangent t): B z = (−R, 0) solves the linearised
/// equations on the hyperplane ⟨·, v⟩ = 0, and z − (z_Λ / t_Λ) t is the
/// step with ΔΛ = 0 (R_x t_x + R_Λ t_Λ = 0).
struct ProjectedChord<'a> {
    bordered: &'a mut Bordered,
    tangent: (&'a [f64], f64),
    z: Vec<f64>,
    steps: usize,
    counts: Counts,
}

impl<E: Equations + ?Sized> LinearSolve<E> for ProjectedChord<'_> {
    fn step(&mut self, _eq: &mut E, _x: &[f64], f: &[f64], _it: &Iterate, delta: &mut [f64]) -> Result<LinearStep> {
        let (tx, tl) = self.tangent;
        // A nearly vertical tangent (a fold) cannot be projected.
        if tl.abs() < 1e-8 {
            return Err(Error::new(Status::ErrNotConverged, "sample: the tangent is vertical (a fold)"));
        }
        let n = f.len();
        for i in 0..n {
            self.z[i] = -f[i];
        }
        self.z[n] = 0.0;
        self.bordered.solve(&mut self.z, &mut self.counts);
        let c = self.z[n] / tl;
        for i in 0..n {
            delta[i] = self.z[i] - c * tx[i];
        }
        self.steps += 1;
        Ok(LinearStep { eta: 0.0, fresh: true })
    }
}

/// A point at the fixed load `target` from the prediction `xs` (in place):
/// chord iterations ([`ProjectedChord`]) on the current factorisation of
/// the context's bordered tangent (taken near xs, with tangent t = (t_x,
/// t_Λ) from it), at most 12, stopping at the first that does not halve the
/// residual. When the chord stalls or the tangent is nearly vertical (a
/// fold), Newton at fixed Λ with fresh factorisations takes over from the
/// prediction and `refactorised` is set (the caller's factorisation is
/// gone) — unless `defer`: then None, `xs` back at the prediction and the
/// chord's iterations in `spent` (the caller retries on a nearer
/// factorisation). Returns (iterations, final residual).
#[allow(clippy::too_many_arguments)]
pub(crate) fn deliver_sample<P: Problem + ?Sized>(
    problem: &mut P,
    ctx: &mut Context,
    xs: &mut [f64],
    target: f64,
    tangent: (&[f64], f64),
    tol: f64,
    refactorised: &mut bool,
    (defer, spent): (bool, &mut usize),
) -> Result<Option<(usize, f64)>> {
    let n = xs.len();
    let prediction = xs.to_vec();
    let mut chord = ProjectedChord {
        bordered: &mut ctx.bordered,
        tangent,
        z: vec![0.0; n + 1],
        steps: 0,
        counts: Counts::default(),
    };
    let mut eq = AtFixed::new(problem, target);
    let mut test = ResidualTest::new(ctx.eq.clone(), tol, "sample");
    test.stall = Stall::Immediate;
    let result = nonlinear::solve(&mut eq, xs, &mut chord, &mut FullStep::new(n), &mut test, 12);
    let steps = chord.steps;
    ctx.counts.residuals += eq.residuals;
    ctx.counts.add(&chord.counts);
    if let Ok(r) = result {
        return Ok(Some((*spent + r.iterations, r.norm)));
    }
    xs.copy_from_slice(&prediction);
    *spent += steps;
    if defer {
        return Ok(None);
    }
    *refactorised = true;
    let (it, res) = newton_sample(problem, ctx, xs, target, tol)?;
    Ok(Some((*spent + it, res)))
}

/// A point at the fixed load `target` by Newton from the prediction `xs`
/// (in place), fresh factorisations throughout: (iterations, residual).
pub(crate) fn newton_sample<P: Problem + ?Sized>(
    problem: &mut P,
    ctx: &mut Context,
    xs: &mut [f64],
    target: f64,
    tol: f64,
) -> Result<(usize, f64)> {
    let prediction = xs.to_vec();
    let mut l = target;
    correct(problem, ctx, xs, &mut l, Plane::fixed(&prediction, target), tol, Reuse::No)
}

//! SUNDIALS cross-check of the finite-strain thick tube (physics.md §1.2–1.3,
//! §4), of the kind "the equations from the other side": the radial
//! equilibrium written here (only the wall law's stress is rodkit's),
//! integrated through the wall by IDA in a
//! shooting method, with KINSOL on the shooting residual, against
//! `FiniteTube::solve` (Chebyshev collocation + Newton).
//!
//! Equations (R ∈ [A, B] the reference radius; σ the Cauchy stress of the
//! law at the local strain a = dr/dR, b = r/R, λ, γ = rψ):
//!
//! - Compressible laws: a semi-explicit index-1 DAE with differential states
//!   r, s = σ_rr and the running resultants F(R) = 2π∫σ_zz r a dR,
//!   T(R) = 2π∫σ_θz r² a dR, and the algebraic state a defined by
//!   σ_rr(a, r/R, λ, rψ) − s = 0:
//!   r' = a,  s' = (σ_θθ − s)·a/r,  F' = 2πσ_zz r a,  T' = 2πσ_θz r² a.
//!   The consistent a at R = A comes from a scalar Newton on σ_rr(a) = −p.
//! - Incompressible laws: r² = a_in² + (R² − A²)/λ is explicit, r' = R/(λr);
//!   an ODE for s = σ_rr and the resultants, with σ̂ the multiplier-free
//!   stress the trait returns: s' = (σ̂_θθ − σ̂_rr)·r'/r,
//!   F' = 2π(σ̂_zz − σ̂_rr + s) r r', T' = 2πσ̂_θz r² r'.
//!
//! Shooting unknowns: r(A) (compressible) or a_in (incompressible), plus λ if
//! the force is prescribed and ψ if the torque is; s(A) = −p_in. Residual:
//! s(B) + p_out, (applied force − target), (T(B) − target). KINSOL solves it
//! with exact Newton (a Jacobian every iteration, by difference quotients)
//! and explicit tolerances, continued in the load from the stress-free state
//! (so its start owes nothing to the collocation solver).
//!
//! Everything is integrated in the tube's own scales (r/B, s/μ, F/(μπB²),
//! T/(μπB³), with μ a stated stress scale of each law) so one scalar IDA
//! absolute tolerance suits every component.
//!
//! Run: `cargo test --release --features sundials --test sundials_tube -- --nocapture`
#![cfg(feature = "sundials")]

#[path = "support/sundials.rs"]
mod sundials;

use std::f64::consts::PI;
use std::time::Instant;

use rodkit::tube::finite::{Axial, Ends, FiniteTube, Loading, SolveOptions, Torsion, TubeState};
use rodkit::tube::material::fibre::{FibreAngle, FibreFamily};
use rodkit::tube::material::{FibreReinforced, NeoHookean, SaintVenantKirchhoff, WallMaterial, WallStrain};
use rodkit::tube::Orthotropic;
use sundials::{ida_solve, kinsol_solve, Context, IdaOptions, InitialCondition, KinsolOptions, Strategy};

// ---------------------------------------------------------------------------
// Tolerances
// ---------------------------------------------------------------------------

/// IDA tolerances of the final shots, on the scaled states (all O(1)). IDA
/// controls the local error; the global error of BDF at rtol = 1e−12 on these
/// smooth radial problems is ≈ 1e−11, three orders below the agreement
/// asserted. Each final solve is redone at 10× looser IDA tolerances and the
/// change (`self_check`, measured ≤ 3.2e−10) must stay under AGREEMENT/10.
const IDA_RTOL: f64 = 1e-12;
const IDA_ATOL: f64 = 1e-14;
/// Looser IDA tolerances for the intermediate load steps of the continuation
/// (they only provide starting points for the next step).
const IDA_RTOL_PATH: f64 = 1e-9;
const IDA_ATOL_PATH: f64 = 1e-11;
/// KINSOL function-norm tolerance (max norm of the scaled shooting residual)
/// at the final load and along the path. The final one is §4's "scaled
/// residual ≤ 1e−12"; the IDA-computed residual jitters at 1e−13–1e−12 as
/// the step-size sequence changes with the unknowns, so it cannot be tighter.
const KIN_FTOL: f64 = 1e-12;
const KIN_FTOL_PATH: f64 = 1e-8;
/// The collocation side: its two-grid error estimate is held to 1e−12.
const FINITE_TOL: f64 = 1e-12;
/// Asserted agreement: §4 expects 1e−9–1e−8 relative once both sides have
/// converged to ≤ 1e−12. Measured: ≤ 1.7e−11 on every quantity of every
/// state (the shooting side's global error dominates), so 1e−8 leaves a
/// margin of ≥ 500 for other platforms and compilers while still catching
/// any modelling difference (a wrong sign or cap term shows at ≥ 1e−3).
const AGREEMENT: f64 = 1e-8;

// ---------------------------------------------------------------------------
// The wall ODE/DAE integrated by IDA
// ---------------------------------------------------------------------------

/// A tube wall: the law, the reference radii, and the stress scale μ used to
/// make stresses and resultants dimensionless.
struct Wall<'m> {
    material: &'m dyn WallMaterial,
    inner: f64,
    outer: f64,
    stress: f64,
}

/// The end values of one integration through the wall.
#[derive(Clone, Copy, Debug)]
struct Through {
    r_in: f64,
    r_out: f64,
    /// σ_rr(B).
    s_out: f64,
    /// Wall force 2π∫σ_zz r dr and torque 2π∫σ_θz r² dr.
    wall_force: f64,
    torque: f64,
    ida_steps: i64,
}

#[derive(Clone, Copy, Debug)]
struct Tolerances {
    rtol: f64,
    atol: f64,
}

impl<'m> Wall<'m> {
    fn sigma(&self, big: f64, a: f64, r: f64, lambda: f64, psi: f64) -> [f64; 4] {
        let s = self.material.cauchy(big, &WallStrain { radial: a, hoop: r / big, axial: lambda, shear: r * psi });
        [s[(0, 0)], s[(1, 1)], s[(2, 2)], s[(1, 2)]]
    }

    /// The radial stretch a at R with σ_rr(a, r/R, λ, rψ) = s (compressible
    /// laws): Newton with a central-difference slope, from a = r/R.
    fn radial_stretch(&self, big: f64, r: f64, lambda: f64, psi: f64, s: f64) -> Result<f64, String> {
        let mut a = r / big;
        let g = |a: f64| (self.sigma(big, a, r, lambda, psi)[0] - s) / self.stress;
        for _ in 0..60 {
            let ga = g(a);
            if !ga.is_finite() {
                return Err(format!("σ_rr not finite at a = {a}"));
            }
            let h = 1e-6 * a;
            let slope = (g(a + h) - g(a - h)) / (2.0 * h);
            if !(slope > 0.0) {
                return Err(format!("σ_rr not increasing in a at a = {a} (slope {slope:e})"));
            }
            let mut step = ga / slope;
            while a - step <= 0.0 {
                step *= 0.5;
            }
            a -= step;
            if step.abs() <= 4.0 * f64::EPSILON * a {
                return Ok(a);
            }
        }
        Err(format!("no consistent radial stretch at R = {big} (r = {r})"))
    }

    /// Integrates the wall from A to B with r(A) = `start` (compressible) or
    /// deformed inner radius `start` (incompressible), s(A) = −p_in.
    fn integrate(
        &self,
        ctx: &Context,
        start: f64,
        lambda: f64,
        psi: f64,
        p_in: f64,
        tol: Tolerances,
    ) -> Result<Through, String> {
        if !(start > 0.0 && lambda > 0.0 && start.is_finite() && psi.is_finite()) {
            return Err(format!("shooting unknowns outside the domain: start {start}, λ {lambda}, ψ {psi}"));
        }
        if self.material.incompressible() {
            self.integrate_incompressible(ctx, start, lambda, psi, p_in, tol)
        } else {
            self.integrate_compressible(ctx, start, lambda, psi, p_in, tol)
        }
    }

    fn ida_options(tol: Tolerances) -> IdaOptions {
        IdaOptions {
            rtol: tol.rtol,
            atol: tol.atol,
            initial_condition: InitialCondition::AsGiven,
            ..IdaOptions::default()
        }
    }

    /// y = (r/B, s/μ, F/(μπB²), T/(μπB³), a); id = (1, 1, 1, 1, 0).
    fn integrate_compressible(
        &self,
        ctx: &Context,
        r0: f64,
        lambda: f64,
        psi: f64,
        p_in: f64,
        tol: Tolerances,
    ) -> Result<Through, String> {
        let (aa, bb, mu) = (self.inner, self.outer, self.stress);
        let rates = |big: f64, r: f64, s: f64, a: f64| -> ([f64; 4], f64) {
            let [srr, stt, szz, stz] = self.sigma(big, a, r, lambda, psi);
            (
                [
                    a / bb,
                    (stt - s) / mu * a / r,
                    2.0 * szz * r * a / (mu * bb * bb),
                    2.0 * stz * r * r * a / (mu * bb * bb * bb),
                ],
                srr,
            )
        };
        let s0 = -p_in;
        let a0 = self.radial_stretch(aa, r0, lambda, psi, s0)?;
        let (d0, _) = rates(aa, r0, s0, a0);
        let y0 = [r0 / bb, s0 / mu, 0.0, 0.0, a0];
        let yp0 = [d0[0], d0[1], d0[2], d0[3], 0.0];
        let id = [1.0, 1.0, 1.0, 1.0, 0.0];
        let residual = |big: f64, y: &[f64], yp: &[f64], res: &mut [f64]| {
            let (r, s, a) = (y[0] * bb, y[1] * mu, y[4]);
            let (d, srr) = rates(big, r, s, a);
            for k in 0..4 {
                res[k] = yp[k] - d[k];
            }
            res[4] = srr / mu - y[1];
        };
        let sol = ida_solve(ctx, aa, &y0, &yp0, &id, residual, None, &Self::ida_options(tol), &[bb])?;
        let y = &sol.y[0];
        Ok(Through {
            r_in: r0,
            r_out: y[0] * bb,
            s_out: y[1] * mu,
            wall_force: y[2] * mu * PI * bb * bb,
            torque: y[3] * mu * PI * bb * bb * bb,
            ida_steps: sol.stats.steps,
        })
    }

    /// y = (s/μ, F/(μπB²), T/(μπB³)), all differential; r(R) explicit.
    fn integrate_incompressible(
        &self,
        ctx: &Context,
        a_in: f64,
        lambda: f64,
        psi: f64,
        p_in: f64,
        tol: Tolerances,
    ) -> Result<Through, String> {
        let (aa, bb, mu) = (self.inner, self.outer, self.stress);
        let radius = |big: f64| (a_in * a_in + (big * big - aa * aa) / lambda).sqrt();
        let rates = |big: f64, s: f64| -> [f64; 3] {
            let r = radius(big);
            let dr = big / (lambda * r);
            let [srr, stt, szz, stz] = self.sigma(big, dr, r, lambda, psi);
            [
                (stt - srr) / mu * dr / r,
                2.0 * (szz - srr + s) * r * dr / (mu * bb * bb),
                2.0 * stz * r * r * dr / (mu * bb * bb * bb),
            ]
        };
        let y0 = [-p_in / mu, 0.0, 0.0];
        let yp0 = rates(aa, -p_in);
        let residual = |big: f64, y: &[f64], yp: &[f64], res: &mut [f64]| {
            let d = rates(big, y[0] * mu);
            for k in 0..3 {
                res[k] = yp[k] - d[k];
            }
        };
        let sol = ida_solve(ctx, aa, &y0, &yp0, &[1.0; 3], residual, None, &Self::ida_options(tol), &[bb])?;
        let y = &sol.y[0];
        Ok(Through {
            r_in: a_in,
            r_out: radius(bb),
            s_out: y[0] * mu,
            wall_force: y[1] * mu * PI * bb * bb,
            torque: y[2] * mu * PI * bb * bb * bb,
            ida_steps: sol.stats.steps,
        })
    }
}

// ---------------------------------------------------------------------------
// Shooting with KINSOL
// ---------------------------------------------------------------------------

/// The loading a fraction `f` of the way from the stress-free state
/// (λ = 1 or F = 0, ψ = 0 or T = 0, no pressure) to `to`.
fn partial_load(to: &Loading, f: f64) -> Loading {
    Loading {
        axial: match to.axial {
            Axial::Stretch(l) => Axial::Stretch(1.0 + f * (l - 1.0)),
            Axial::Force(x) => Axial::Force(f * x),
        },
        torsion: match to.torsion {
            Torsion::Twist(p) => Torsion::Twist(f * p),
            Torsion::Torque(t) => Torsion::Torque(f * t),
        },
        inner_pressure: f * to.inner_pressure,
        outer_pressure: f * to.outer_pressure,
        ends: to.ends,
    }
}

/// Unknowns u = (start/B, [λ], [ψB]) and the scaled residual.
struct Shooting<'w, 'm> {
    wall: &'w Wall<'m>,
    loading: Loading,
}

impl Shooting<'_, '_> {
    /// (start, λ, ψ) from u.
    fn unpack(&self, u: &[f64]) -> (f64, f64, f64) {
        let b = self.wall.outer;
        let mut k = 1;
        let mut next = || {
            k += 1;
            u[k - 1]
        };
        let lambda = match self.loading.axial {
            Axial::Stretch(l) => l,
            Axial::Force(_) => next(),
        };
        let psi = match self.loading.torsion {
            Torsion::Twist(p) => p,
            Torsion::Torque(_) => next() / b,
        };
        (u[0] * b, lambda, psi)
    }

    fn applied_force(&self, t: &Through) -> f64 {
        let l = &self.loading;
        match l.ends {
            Ends::Open => t.wall_force,
            Ends::Closed => {
                t.wall_force - PI * t.r_in * t.r_in * l.inner_pressure + PI * t.r_out * t.r_out * l.outer_pressure
            }
        }
    }

    fn residual(&self, ctx: &Context, u: &[f64], f: &mut [f64], tol: Tolerances) -> Result<Through, String> {
        let (start, lambda, psi) = self.unpack(u);
        let w = self.wall;
        let t = w.integrate(ctx, start, lambda, psi, self.loading.inner_pressure, tol)?;
        let (b, mu) = (w.outer, w.stress);
        f[0] = (t.s_out + self.loading.outer_pressure) / mu;
        let mut k = 1;
        if let Axial::Force(target) = self.loading.axial {
            f[k] = (self.applied_force(&t) - target) / (mu * PI * b * b);
            k += 1;
        }
        if let Torsion::Torque(target) = self.loading.torsion {
            f[k] = (t.torque - target) / (mu * PI * b * b * b);
        }
        Ok(t)
    }
}

/// The SUNDIALS solution of one loading, in the quantities `TubeState` reports.
#[derive(Clone, Copy, Debug)]
struct ShotState {
    r_in: f64,
    r_out: f64,
    stretch: f64,
    twist: f64,
    applied_force: f64,
    torque: f64,
    /// Max norm of the scaled shooting residual at the returned unknowns.
    residual: f64,
    kinsol_iterations: i64,
    ida_steps: i64,
    /// Change of the state when the final solve is redone with 10× looser
    /// IDA tolerances (the comparison's measure).
    self_check: f64,
}

/// One KINSOL solve of the shooting problem for `loading` from `u` (exact
/// Newton, difference-quotient Jacobian); the last integration's end values
/// and the iteration count.
fn kinsol_shooting(
    ctx: &Context,
    wall: &Wall<'_>,
    loading: &Loading,
    u: &mut [f64],
    tol: Tolerances,
    final_solve: bool,
) -> Result<(ShotState, i64), String> {
    let problem = Shooting { wall, loading: *loading };
    let opts = KinsolOptions {
        // Full Newton steps for the final solve (its start is the predicted
        // continuation of a converged step): a line search only stalls on
        // the jitter of the IDA-computed residual there.
        strategy: if final_solve { Strategy::None } else { Strategy::LineSearch },
        func_norm_tol: if final_solve { KIN_FTOL } else { KIN_FTOL_PATH },
        scaled_step_tol: 1e-15,
        max_iters: 50,
        max_setup_calls: 1,
        ..KinsolOptions::default()
    };
    let stats = kinsol_solve(
        ctx,
        u,
        |x, f| {
            // The wrapper turns a panic into a clean KINSOL error carrying
            // this message (an IDA failure has no recoverable path here).
            if let Err(e) = problem.residual(ctx, x, f, tol) {
                panic!("shooting residual at {x:?}: {e}");
            }
        },
        None,
        &opts,
    )?;
    let mut f = vec![0.0; u.len()];
    let t = problem.residual(ctx, u, &mut f, tol)?;
    let (_, stretch, twist) = problem.unpack(u);
    let state = ShotState {
        r_in: t.r_in,
        r_out: t.r_out,
        stretch,
        twist,
        applied_force: problem.applied_force(&t),
        torque: t.torque,
        residual: f.iter().fold(0.0, |m, v| m.max(v.abs())),
        kinsol_iterations: stats.iterations,
        ida_steps: t.ida_steps,
        self_check: 0.0,
    };
    Ok((state, stats.iterations))
}

/// KINSOL on the shooting residual, continued in `steps` equal load
/// increments from the stress-free state (secant predictor), loose along the
/// path and tight at the end. The final solve is repeated with 10× looser IDA
/// tolerances: the change (in the comparison's measure) estimates the
/// shooting side's own error (`self_check`).
fn shoot(
    ctx: &Context,
    wall: &Wall<'_>,
    loading: &Loading,
    steps: usize,
    scales: &Scales,
) -> Result<ShotState, String> {
    let n =
        1 + matches!(loading.axial, Axial::Force(_)) as usize + matches!(loading.torsion, Torsion::Torque(_)) as usize;
    // The stress-free state: r(A) = A (or a_in = A), λ = 1, ψ = 0.
    let mut u = vec![0.0; n];
    u[0] = wall.inner / wall.outer;
    if matches!(loading.axial, Axial::Force(_)) {
        u[1] = 1.0;
    }
    let mut previous: Option<Vec<f64>> = None;
    let mut iterations = 0;
    for k in 1..=steps {
        let last = k == steps;
        let current = u.clone();
        if let Some(p) = &previous {
            for i in 0..n {
                u[i] = 2.0 * current[i] - p[i];
            }
        }
        let tol = if last {
            Tolerances { rtol: IDA_RTOL, atol: IDA_ATOL }
        } else {
            Tolerances { rtol: IDA_RTOL_PATH, atol: IDA_ATOL_PATH }
        };
        let part = partial_load(loading, k as f64 / steps as f64);
        let (state, it) =
            kinsol_shooting(ctx, wall, &part, &mut u, tol, last).map_err(|e| format!("load step {k}/{steps}: {e}"))?;
        iterations += it;
        previous = Some(current);
        if last {
            let mut v = u.clone();
            let loose = Tolerances { rtol: 10.0 * IDA_RTOL, atol: 10.0 * IDA_ATOL };
            let (check, _) =
                kinsol_shooting(ctx, wall, loading, &mut v, loose, true).map_err(|e| format!("self-check: {e}"))?;
            let self_check = scales.errors(&state, &check).iter().fold(0.0f64, |m, &e| m.max(e));
            return Ok(ShotState { kinsol_iterations: iterations, self_check, ..state });
        }
    }
    unreachable!("steps >= 1")
}

// ---------------------------------------------------------------------------
// Cases
// ---------------------------------------------------------------------------

fn helical() -> Orthotropic {
    Orthotropic::new(10.0, 2.0, 1.5, 0.35, 0.3, 0.4, 1.2, 0.8, 0.6).unwrap()
}

/// Two helical fibre families of opposite hand and unequal stiffness (so
/// torque-free loading twists the tube), HGO-type, in a neo-Hookean matrix.
fn artery(incompressible: bool) -> FibreReinforced {
    let fam = |hand: f64, k1: f64| FibreFamily { angle: FibreAngle::Helix { hand }, k1, k2: 0.8 };
    FibreReinforced {
        matrix: NeoHookean { shear_modulus: 0.3, lame_lambda: 3.0, incompressible },
        families: vec![fam(1.0, 2.3), fam(-1.0, 1.2)],
        intrinsic_twist: 0.9,
    }
}

struct Case {
    name: &'static str,
    material: Box<dyn WallMaterial>,
    inner: f64,
    outer: f64,
    /// Stress scale μ (for the scaled residuals and the absolute comparison
    /// of quantities prescribed to be zero): the shear modulus of
    /// neo-Hookean and HGO walls, E1 = 10 (the stiffest modulus, as in
    /// FiniteTube's own residual scaling) for SVK.
    stress: f64,
    loading: Loading,
    /// Load increments of the SUNDIALS continuation from rest.
    steps: usize,
}

fn loading(axial: Axial, torsion: Torsion, p_in: f64, p_out: f64, ends: Ends) -> Loading {
    Loading { axial, torsion, inner_pressure: p_in, outer_pressure: p_out, ends }
}

fn cases() -> Vec<Case> {
    let svk = |inc| Box::new(SaintVenantKirchhoff::new(helical(), 1.7, inc)) as Box<dyn WallMaterial>;
    let nh = |mu, lame, inc| {
        Box::new(NeoHookean { shear_modulus: mu, lame_lambda: lame, incompressible: inc }) as Box<dyn WallMaterial>
    };
    use Axial::{Force, Stretch};
    use Ends::{Closed, Open};
    use Torsion::{Torque, Twist};
    vec![
        Case {
            name: "SVK thick, λ ψ p",
            material: svk(false),
            inner: 0.6,
            outer: 1.4,
            stress: 10.0,
            loading: loading(Stretch(1.15), Twist(0.3), 0.1, 0.0, Open),
            steps: 3,
        },
        Case {
            name: "SVK thick, torsion-free λ",
            material: svk(false),
            inner: 0.6,
            outer: 1.4,
            stress: 10.0,
            loading: loading(Stretch(1.2), Torque(0.0), 0.0, 0.0, Open),
            steps: 3,
        },
        Case {
            name: "SVK thin-ish, F T=0 p closed",
            material: svk(false),
            inner: 0.95,
            outer: 1.05,
            stress: 10.0,
            loading: loading(Force(0.3), Torque(0.0), 0.02, 0.0, Closed),
            steps: 3,
        },
        Case {
            name: "NH comp, λ=2 ψB=1 p",
            material: nh(1.0, 3.0, false),
            inner: 0.5,
            outer: 1.0,
            stress: 1.0,
            loading: loading(Stretch(2.0), Twist(1.0), 0.1, 0.0, Open),
            steps: 6,
        },
        Case {
            name: "NH comp, F T p_in p_out closed",
            material: nh(1.0, 5.0, false),
            inner: 0.7,
            outer: 1.0,
            stress: 1.0,
            loading: loading(Force(1.0), Torque(0.3), 0.15, 0.05, Closed),
            steps: 4,
        },
        Case {
            name: "NH inc, F ψ p closed",
            material: nh(1.0, 0.0, true),
            inner: 0.5,
            outer: 1.0,
            stress: 1.0,
            loading: loading(Force(1.5), Twist(0.8), 0.3, 0.0, Closed),
            steps: 4,
        },
        Case {
            name: "SVK inc thick, torsion-free λ p",
            material: svk(true),
            inner: 0.6,
            outer: 1.4,
            stress: 10.0,
            loading: loading(Stretch(1.1), Torque(0.0), 0.2, 0.0, Open),
            steps: 3,
        },
        Case {
            name: "SVK inc thin-ish, F ψ p closed",
            material: svk(true),
            inner: 0.95,
            outer: 1.05,
            stress: 10.0,
            loading: loading(Force(0.3), Twist(0.2), 0.02, 0.0, Closed),
            steps: 3,
        },
        Case {
            name: "HGO inc artery, F T=0 p closed",
            material: Box::new(artery(true)),
            inner: 0.8,
            outer: 1.0,
            stress: 0.3,
            loading: loading(Force(0.05), Torque(0.0), 0.1, 0.0, Closed),
            steps: 4,
        },
        Case {
            name: "HGO comp artery, λ T=0 p closed",
            material: Box::new(artery(false)),
            inner: 0.8,
            outer: 1.0,
            stress: 0.3,
            loading: loading(Stretch(1.1), Torque(0.0), 0.1, 0.0, Closed),
            steps: 4,
        },
    ]
}

// ---------------------------------------------------------------------------
// Comparison
// ---------------------------------------------------------------------------

/// How two states are compared: relative to the reference value, except for
/// quantities prescribed to be exactly zero (a torque-free T, a force-free
/// F), which are compared absolutely against their natural scale (μπB³,
/// μπB²): their relative error means nothing.
struct Scales {
    force: Option<f64>,
    torque: Option<f64>,
}

impl Scales {
    fn new(case: &Case) -> Self {
        let (b, mu) = (case.outer, case.stress);
        Scales {
            force: matches!(case.loading.axial, Axial::Force(f) if f == 0.0).then_some(mu * PI * b * b),
            torque: matches!(case.loading.torsion, Torsion::Torque(t) if t == 0.0).then_some(mu * PI * b * b * b),
        }
    }

    /// Disagreement in (a, b, λ, ψ, F, T).
    fn errors(&self, x: &ShotState, reference: &ShotState) -> [f64; 6] {
        let rel = |x: f64, r: f64| (x - r).abs() / r.abs();
        let zero_or_rel = |x: f64, r: f64, scale: Option<f64>| match scale {
            Some(s) => (x - r).abs() / s,
            None => rel(x, r),
        };
        [
            rel(x.r_in, reference.r_in),
            rel(x.r_out, reference.r_out),
            rel(x.stretch, reference.stretch),
            rel(x.twist, reference.twist),
            zero_or_rel(x.applied_force, reference.applied_force, self.force),
            zero_or_rel(x.torque, reference.torque, self.torque),
        ]
    }
}

/// The collocation state in the shooting side's terms.
fn as_shot(t: &TubeState) -> ShotState {
    ShotState {
        r_in: t.deformed_inner_radius,
        r_out: t.deformed_outer_radius,
        stretch: t.stretch,
        twist: t.twist,
        applied_force: t.applied_force,
        torque: t.torque,
        residual: 0.0,
        kinsol_iterations: 0,
        ida_steps: 0,
        self_check: 0.0,
    }
}

struct Row {
    name: &'static str,
    errors: [f64; 6],
    shot: ShotState,
    finite: TubeState,
    seconds: f64,
}

fn compare(case: &Case, ctx: &Context) -> Row {
    let t0 = Instant::now();
    let tube = FiniteTube::new(case.inner, case.outer, case.material.as_ref()).unwrap();
    let finite = tube
        .solve(&case.loading, &SolveOptions { rel_tol: FINITE_TOL, intervals: None })
        .unwrap_or_else(|e| panic!("{}: FiniteTube failed: {e}", case.name));
    let wall = Wall { material: case.material.as_ref(), inner: case.inner, outer: case.outer, stress: case.stress };
    let scales = Scales::new(case);
    let shot = shoot(ctx, &wall, &case.loading, case.steps, &scales)
        .unwrap_or_else(|e| panic!("{}: SUNDIALS shooting failed: {e}", case.name));
    let errors = scales.errors(&shot, &as_shot(&finite));
    Row { name: case.name, errors, shot, finite, seconds: t0.elapsed().as_secs_f64() }
}

/// physics.md §4: the finite-strain tube against IDA shooting + KINSOL on
/// ten states (compressible and incompressible, thick and thin-ish, large
/// stretch and twist, stretch/force and twist/torque control, open and
/// closed ends, inner and outer pressure; SVK helical orthotropic,
/// neo-Hookean, two-family HGO). Prints the table of disagreements.
#[test]
fn finite_tube_agrees_with_ida_shooting_and_kinsol() {
    let ctx = Context::new().unwrap();
    let t0 = Instant::now();
    eprintln!(
        "SUNDIALS {}: FiniteTube (rel_tol {FINITE_TOL:e}) vs IDA shooting + KINSOL; relative disagreement \
         (zero targets T = 0, F = 0: absolute per μπB³, μπB²)",
        sundials::sundials_version()
    );
    eprintln!(
        "{:<32} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} | {:>8} {:>8} {:>3} {:>4} | {:>3} {:>8} | {:>5}",
        "state", "a", "b", "λ", "ψ", "F", "T", "max", "self-chk", "shot res", "kin", "ida", "n", "est", "s"
    );
    let mut rows = Vec::new();
    for case in cases() {
        let row = compare(&case, &ctx);
        let max = row.errors.iter().fold(0.0f64, |m, &e| m.max(e));
        let e = &row.errors;
        eprintln!(
            "{:<32} {:>8.1e} {:>8.1e} {:>8.1e} {:>8.1e} {:>8.1e} {:>8.1e} {:>8.1e} | {:>8.1e} {:>8.1e} {:>3} {:>4} | {:>3} {:>8.1e} | {:>5.2}",
            row.name, e[0], e[1], e[2], e[3], e[4], e[5], max,
            row.shot.self_check, row.shot.residual, row.shot.kinsol_iterations, row.shot.ida_steps,
            row.finite.intervals, row.finite.error_estimate, row.seconds
        );
        rows.push(row);
    }
    eprintln!("total {:.2} s", t0.elapsed().as_secs_f64());
    eprintln!("states (FiniteTube): a, b, λ, ψ, F, T");
    for row in &rows {
        let f = &row.finite;
        eprintln!(
            "  {:<32} {:.10} {:.10} {:.10} {:+.10} {:+.10e} {:+.10e}",
            row.name, f.deformed_inner_radius, f.deformed_outer_radius, f.stretch, f.twist, f.applied_force, f.torque
        );
    }
    for row in &rows {
        assert!(row.shot.residual <= KIN_FTOL, "{}: shooting residual {:e}", row.name, row.shot.residual);
        // The shooting side must itself be well inside the asserted band.
        assert!(row.shot.self_check <= 0.1 * AGREEMENT, "{}: shooting self-check {:e}", row.name, row.shot.self_check);
        for (e, q) in row.errors.iter().zip(["a", "b", "λ", "ψ", "F", "T"]) {
            assert!(*e <= AGREEMENT, "{}: {q} disagrees by {e:e} (> {AGREEMENT:e})", row.name);
        }
    }
}

/// A tension-only fibre family that switches on inside the wall (I4 = 1 at
/// an interior radius: with τ0 = 1.8 the helix angle runs from 55° at A to
/// 61° at B, and under λ = 1.2 the fibres are taut near A and slack near B).
/// The stress is then only C⁰ in R at that radius. IDA shooting handles it
/// with its step control (self-check ≈ 3e−10); FiniteTube puts a Chebyshev
/// breakpoint at each switch radius (without it: algebraic convergence,
/// ErrNotConverged at rel_tol 1e−12 after 135 intervals).
#[test]
fn fibre_switching_inside_the_wall() {
    let ctx = Context::new().unwrap();
    for incompressible in [false, true] {
        let fam = |hand: f64, k1: f64| FibreFamily { angle: FibreAngle::Helix { hand }, k1, k2: 0.8 };
        let material = FibreReinforced {
            matrix: NeoHookean { shear_modulus: 0.3, lame_lambda: 3.0, incompressible },
            families: vec![fam(1.0, 2.3), fam(-1.0, 1.2)],
            intrinsic_twist: 1.8,
        };
        let case = Case {
            name: "HGO, fibre switching in the wall",
            material: Box::new(material),
            inner: 0.8,
            outer: 1.0,
            stress: 0.3,
            loading: loading(Axial::Stretch(1.2), Torsion::Torque(0.0), 0.0, 0.0, Ends::Open),
            steps: 4,
        };
        let row = compare(&case, &ctx);
        for (e, q) in row.errors.iter().zip(["a", "b", "λ", "ψ", "F", "T"]) {
            assert!(*e <= AGREEMENT, "incompressible {incompressible}: {q} disagrees by {e:e}");
        }
    }
}

/// The torque-free states of `wall` at the stretches `lambdas` (increasing
/// from 1), each shot from the one before (KINSOL from the stress-free
/// state at the first), at the final tolerances.
fn torque_free_sweep(ctx: &Context, wall: &Wall<'_>, lambdas: &[f64], u: &mut [f64]) -> Vec<ShotState> {
    let tight = Tolerances { rtol: IDA_RTOL, atol: IDA_ATOL };
    lambdas
        .iter()
        .map(|&l| {
            let loading = loading(Axial::Stretch(l), Torsion::Torque(0.0), 0.0, 0.0, Ends::Open);
            kinsol_shooting(ctx, wall, &loading, u, tight, true).unwrap_or_else(|e| panic!("λ = {l}: {e}")).0
        })
        .collect()
}

/// The deflation-then-inflation walls of tests/tube_behaviour.rs: the
/// stretch λ* where the torque-free outer radius is least, found here from
/// the IDA + KINSOL shooting solution alone (no rodkit solver): the root of
/// db/dλ, by the five-point difference quotient (step [`STEP`]) and the
/// secant method from the least of a 0.01 grid. Measured: λ* moves by
/// ≤ 2e-7 between steps 1e-3 and 2e-3 (the quotient's O(h⁴) bias and the
/// shooting's ~1e-11 noise in b). tests/tube_behaviour.rs holds rodkit's
/// sweep to these values; asserted against them here to 1e-6.
#[test]
fn deflation_minimum_by_ida_shooting() {
    // The cases' `model` is tube_behaviour.rs's; this test shoots the thick wall.
    #[allow(dead_code)]
    #[path = "support/behaviour_cases.rs"]
    mod behaviour_cases;
    let ctx = Context::new().unwrap();
    for (name, reference) in
        [("svk_thick_compressible_dip", DIP_COMPRESSIBLE), ("svk_thick_incompressible_dip", DIP_INCOMPRESSIBLE)]
    {
        let all = behaviour_cases::cases();
        let case = all.iter().find(|c| c.name == name).unwrap();
        let wall = Wall { material: case.law.as_material(), inner: case.inner, outer: case.outer, stress: 1.0 };
        let mut u = vec![case.inner / case.outer, 0.0];
        let grid: Vec<f64> = (0..=40).map(|i| 1.0 + 0.01 * i as f64).collect();
        let states = torque_free_sweep(&ctx, &wall, &grid, &mut u);
        let k = (1..grid.len() - 1).min_by(|&a, &b| states[a].r_out.total_cmp(&states[b].r_out)).unwrap();
        assert!(k > 1 && k < grid.len() - 2, "{name}: least radius at the grid's end");
        // Continue from the grid's state at λ_k for the difference quotients.
        let mut at = vec![0.0; 2];
        let mut slope = |l: f64, from: &[f64]| {
            let h = STEP;
            at.copy_from_slice(from);
            let s = torque_free_sweep(&ctx, &wall, &[l - 2.0 * h, l - h, l + h, l + 2.0 * h], &mut at);
            (s[0].r_out - 8.0 * s[1].r_out + 8.0 * s[2].r_out - s[3].r_out) / (12.0 * h)
        };
        let start = {
            let mut v = vec![case.inner / case.outer, 0.0];
            torque_free_sweep(&ctx, &wall, &grid[..=k], &mut v);
            v
        };
        let (mut l0, mut l1) = (grid[k] - 0.005, grid[k] + 0.005);
        let (mut g0, mut g1) = (slope(l0, &start), slope(l1, &start));
        for _ in 0..30 {
            let l2 = l1 - g1 * (l1 - l0) / (g1 - g0);
            (l0, g0) = (l1, g1);
            l1 = l2;
            g1 = slope(l1, &start);
            if (l1 - l0).abs() < 1e-9 {
                break;
            }
        }
        println!("{name}: least outer radius at λ* = {l1:.7} (db/dλ there {g1:e})");
        assert!((l1 - reference).abs() < 1e-6, "{name}: λ* = {l1} vs {reference}");
    }
}

/// The stretches of least outer radius found by
/// `deflation_minimum_by_ida_shooting` (copied from its output; it asserts
/// them), repeated in tests/tube_behaviour.rs.
const DIP_COMPRESSIBLE: f64 = 1.2546845;
/// The difference quotient's step in λ (4e-3 lost the secant iteration).
const STEP: f64 = 2e-3;
const DIP_INCOMPRESSIBLE: f64 = 1.2675706;

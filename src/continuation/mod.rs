//! Continuation of solution branches of R(x, Λ) = 0, x ∈ ℝⁿ, n equations:
//! generic engines, not tied to rods (physics.md §2.4–2.5).
//!
//! * [`Problem`]: residual and sparse Jacobian; [`SeriesProblem`] adds the
//!   Taylor coefficients of R along a series, which the cubic ANM needs.
//!   [`system::AssembledSystem`] provides both for any model written as
//!   polynomial kernels ([`crate::taylor`]).
//! * [`newton::continue_newton`]: Newton pseudo-arc-length continuation
//!   (predictor–corrector with step control), the baseline.
//! * [`anm::continue_anm`]: the asymptotic numerical method, series of order
//!   P per step from one factorisation, with a Newton correction at each step
//!   end when a residual tolerance is requested.
//!
//! * [`krylov::newton_krylov`]: equilibria at fixed Λ by Jacobian-free
//!   Newton–Krylov with a lagged banded-LU preconditioner.
//!
//! Both continuation engines work on the bordered tangent [[R_x, R_Λ], [vᵀW]] (sparse, pattern
//! fixed, symbolic analysis once), measure arc length in the scaled inner
//! product ⟨a, b⟩_W = (1/n)Σ a_i b_i / s_i² + a_Λ b_Λ / s_Λ² ([`Scaling`]), return
//! the branch as [`Record`]s, stop at a target Λ, a step limit or a
//! callback's request, and can resume from the returned [`Resume`].

pub mod anm;
pub mod bifurcation;
pub mod corrector;
pub mod equilibrium;
pub mod indicator;
pub mod newton;
mod overlap;
mod pade;
pub(crate) mod run;
pub mod stability;
pub mod system;
pub mod tangent;

use crate::linalg::dense::nan_max;
use crate::linalg::Pattern;

/// A system of n equations in n unknowns x and the parameter Λ.
pub trait Problem {
    /// n: unknowns (excluding Λ) = equations.
    fn dim(&self) -> usize;
    /// Structure of ∂R/∂x (fixed for the problem's life).
    fn pattern(&self) -> &Pattern;
    fn residual(&mut self, x: &[f64], lambda: f64, r: &mut [f64]);
    /// ∂R/∂x in pattern order and ∂R/∂Λ (dense).
    fn jacobian(&mut self, x: &[f64], lambda: f64, jx: &mut [f64], jl: &mut [f64]);
    /// Typical magnitude of each equation (residual tolerances are relative
    /// to them). Default 1.
    fn equation_scales(&self) -> Vec<f64> {
        vec![1.0; self.dim()]
    }
    /// Typical magnitude of each unknown and of Λ (the default scaling).
    fn unknown_scales(&self) -> (Vec<f64>, f64) {
        (vec![1.0; self.dim()], 1.0)
    }
    /// How many of the last unknowns are multipliers or parameters whose
    /// equations reach across the Jacobian (a phase condition's μ): a
    /// reordering of the factorisation keeps them last. Default 0.
    fn trailing(&self) -> usize {
        0
    }
    /// Sets of unknowns private to one kernel: each set's columns reach
    /// only its own equations (the same indices) and kept ones, and its
    /// equations only its own and kept unknowns — a collocated element's
    /// stage unknowns. The continuation's bordered tangent then eliminates
    /// them element by element ([`crate::linalg::condensed`]) and
    /// factorises only the kept system. Default none.
    fn private_blocks(&self) -> Vec<Vec<usize>> {
        Vec::new()
    }
    /// The metric of the stability count at state x
    /// ([`stability::Metric`]): the stage positions, their weights and how
    /// a dead force density enters the rows. None (the default): the
    /// problem's stability is not counted.
    fn stability_metric(&self, _x: &[f64]) -> Option<stability::Metric> {
        None
    }
}

/// Taylor coefficients of R along X(a) = Σ a^k X_k (the cubic ANM).
pub trait SeriesProblem: Problem {
    /// Start a series at (x0, Λ0), orders up to `max_order`.
    fn series_begin(&mut self, x0: &[f64], lambda0: f64, max_order: usize);
    /// Order-p coefficient of R(X(a)) when X_p = (xp, Λp), orders below p
    /// committed. Called with X_p = 0 it is the known part (the right-hand
    /// side of the recursion); called again with the solved X_p it commits
    /// order p. Orders are taken in increasing sequence from 1: computing
    /// order q again may overwrite what orders above q kept, which must
    /// then be computed again, in sequence.
    fn series_order(&mut self, p: usize, xp: &[f64], lambda_p: f64, out: &mut [f64]);
    /// Commit order p with the solved X_p = (xp, Λp) when its coefficient
    /// is not wanted: `scratch` (dim long) is overwritten with unspecified
    /// values. A problem may then compute only what later orders (and
    /// [`SeriesProblem::series_tangent_order`]) read; a later
    /// [`SeriesProblem::series_order`] call at order p must still be
    /// right. By default the second `series_order` call.
    fn series_commit(&mut self, p: usize, xp: &[f64], lambda_p: f64, scratch: &mut [f64]) {
        self.series_order(p, xp, lambda_p, scratch)
    }
    /// The longest step a' ≤ `a` along the committed series over which the
    /// problem's own approximations hold (a charged rod's pair list: no
    /// stage moves past half its skin); `a` when nothing limits it.
    fn series_reach(&mut self, a: f64) -> f64 {
        a
    }
    /// Whether [`SeriesProblem::series_tangent_order`] is available (the
    /// ANM's series bifurcation indicator is computed only then).
    fn has_series_tangent(&self) -> bool {
        false
    }
    /// Order-p coefficient of R_X(X(a)) W(a) — the Jacobian (Λ column
    /// included) along the committed series X applied to a second series
    /// W = (w, w_Λ), whose order-p coefficient is (wp, w_lambda_p), orders
    /// below committed by earlier calls (p = 0 starts W). Linear in
    /// (wp, w_lambda_p): called with zeros it is the known part. Only
    /// called when [`SeriesProblem::has_series_tangent`] says so, with X
    /// committed to order p or beyond and W's orders below p given by the
    /// calls before (a call out of that sequence reads coefficients that
    /// were never written: stale values, not zeros).
    fn series_tangent_order(&mut self, _p: usize, _wp: &[f64], _w_lambda_p: f64, _out: &mut [f64]) {
        unreachable!("series_tangent_order without has_series_tangent")
    }
}

/// Typical magnitudes of the unknowns and Λ: the arc-length inner product
/// and every relative tolerance use them.
#[derive(Clone, Debug, PartialEq)]
pub struct Scaling {
    pub x: Vec<f64>,
    pub lambda: f64,
}

impl Scaling {
    /// The problem's own scales.
    pub fn of<P: Problem + ?Sized>(problem: &P) -> Self {
        let (x, lambda) = problem.unknown_scales();
        Scaling { x, lambda }
    }

    /// ⟨a, b⟩_W = (1/n) Σ a_i b_i / s_i² + a_Λ b_Λ / s_Λ² over (x, Λ) pairs:
    /// the mean over the unknowns, so that the arc length of a discretised
    /// field does not grow with the mesh (a continuous L² norm, as AUTO's).
    pub fn dot(&self, ax: &[f64], al: f64, bx: &[f64], bl: f64) -> f64 {
        let mut s = 0.0;
        for ((a, b), w) in ax.iter().zip(bx).zip(&self.x) {
            s += a * b / (w * w);
        }
        s / self.x.len().max(1) as f64 + al * bl / (self.lambda * self.lambda)
    }

    pub fn norm(&self, x: &[f64], l: f64) -> f64 {
        self.dot(x, l, x, l).sqrt()
    }

    /// max_i |x_i| / s_i (with Λ): the scaled max norm of a change.
    pub fn max_norm(&self, x: &[f64], l: f64) -> f64 {
        x.iter().zip(&self.x).map(|(a, w)| (a / w).abs()).fold((l / self.lambda).abs(), nan_max)
    }
}

/// A point of a branch with its unit tangent (in ⟨·,·⟩_W): where a
/// continuation stopped, and where another may resume.
#[derive(Clone, Debug, PartialEq)]
pub struct Resume {
    pub x: Vec<f64>,
    pub lambda: f64,
    pub tangent_x: Vec<f64>,
    pub tangent_lambda: f64,
    /// The last step length (arc length in ⟨·,·⟩_W).
    pub step: f64,
    /// The point before this one (its `step`: the arc length between
    /// them), when the engine keeps one: Newton continuation's Hermite
    /// predictor extrapolates from both, and a resume factorises here with
    /// its tangent as the border, as the uninterrupted run did — so a
    /// resumed branch takes the same steps (bitwise on the same problem).
    pub previous: Option<Box<Resume>>,
    /// With [`Options::stability`]: the count's state at this point (its
    /// Ritz vectors, the branch's reference determinant sign, the deepest
    /// σ counted), so that a resume or the next pair list's segment
    /// counts as the uninterrupted branch would.
    pub modes: Option<std::sync::Arc<stability::ModeCarry>>,
}

/// One converged point of a branch.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    pub lambda: f64,
    /// What the caller's observer chose to keep (tip position, …).
    pub outputs: Vec<f64>,
    /// max_i |R_i| / (equation scale_i) at the returned point.
    pub residual: f64,
    /// Arc length of the step that reached it.
    pub step: f64,
    /// sign det(R_x): flips at folds and at simple bifurcation points.
    pub det_sign: f64,
    /// sign det of the bordered tangent [[R_x, R_Λ], [tᵀW]]: flips at simple
    /// bifurcation points only (not at folds).
    pub bordered_det_sign: f64,
    /// Smallest singular value of the bordered tangent, when requested,
    /// signed by the alignment of its singular vectors: it passes through
    /// zero at every bifurcation, double ones (symmetry) included, where no
    /// determinant changes sign.
    pub smallest_singular_value: Option<f64>,
    /// Negative pivots of the bordered tangent's LU factors at the point:
    /// the stability count codes in the thesis's tradition print. The
    /// tangent of this first-order system is not symmetric and is factorised
    /// with row pivoting, so the count is not an inertia; only its change of
    /// parity (with the determinant signs above) marks a crossing. None at a
    /// singular start.
    pub negative_pivots: Option<usize>,
    /// Newton iterations (correction) for this point.
    pub newton_iterations: usize,
    /// ANM: the scaled residual of the series' end point before the Newton
    /// correction (what ε bought); None for Newton continuation.
    pub series_residual: Option<f64>,
    /// With [`Options::stability`]: the number of unstable modes of the
    /// second variation at the point, counted on its own factors
    /// ([`stability::count_unstable`]); the determinant signs above are
    /// then derived from it (sign det R_x = s_ref·(−1)^count, s_ref the
    /// branch's one exact sign) and `negative_pivots` is None.
    pub stability: Option<stability::Stability>,
}

/// A point of the branch delivered at a requested load ([`Options::samples`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    pub lambda: f64,
    /// Index in the branch's records of the point that starts the step
    /// holding the sample (it lies between that record and the next): a
    /// quantity known only modulo a period (a torque clamp's end rotation)
    /// is followed by continuity from there.
    pub record: usize,
    /// The observer's outputs, as for records.
    pub outputs: Vec<f64>,
    /// Scaled residual max |R_i| / e_i (≤ the tolerance).
    pub residual: f64,
    /// Newton iterations its correction took (0: the series' or the
    /// interpolant's value was already within the tolerance).
    pub newton_iterations: usize,
}

/// Why a continuation returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Reached the target Λ exactly (last record).
    Target,
    /// Λ left the allowed range.
    LambdaRange,
    /// The step limit.
    MaxSteps,
    /// The callback asked to stop.
    Cancelled,
    /// The step length fell below its minimum (a fold it could not pass, a
    /// singular tangent, …): the records so far are valid.
    StepTooSmall,
    /// A bifurcation was located and [`Options::stop_at_bifurcation`]
    /// asked to stop there (the last record is the first past it).
    Bifurcation,
}

/// Options common to both engines. Tolerances are relative to the scales
/// (equations: [`Problem::equation_scales`]; unknowns: [`Scaling`]).
#[derive(Clone, Debug)]
pub struct Options {
    /// Stop exactly at this Λ when the branch reaches it.
    pub target_lambda: Option<f64>,
    /// Stop when Λ leaves [min, max].
    pub lambda_range: (f64, f64),
    pub max_steps: usize,
    /// Residual tolerance of every returned point (scaled max norm).
    pub residual_tol: f64,
    /// Newton: first and minimal arc-length steps.
    pub initial_step: f64,
    pub min_step: f64,
    /// The largest arc-length step; ∞ (the default): the engine's own —
    /// [`NEWTON_MAX_STEP`] for Newton continuation, none for the ANM, whose
    /// step is its series' radius (or its Padé approximants' reach).
    pub max_step: f64,
    /// Estimate the smallest singular value of the bordered tangent at each
    /// point (a few extra solves).
    pub track_singular: bool,
    /// Detect and locate bifurcation points (implies `track_singular`);
    /// located to `bifurcation_tol` in scaled arc length: the bracket's
    /// width s, so the critical Λ is known to about s·|dΛ/ds| (≤ s times
    /// Λ's scale, 1 by default; less where the branch turns away from Λ)
    /// — the discretisation's own error in it is another matter, estimated
    /// by [`crate::rod::accuracy::estimate_bifurcation_errors`].
    pub detect_bifurcations: bool,
    pub bifurcation_tol: f64,
    /// Scaling (None: the problem's own).
    pub scaling: Option<Scaling>,
    /// Dense output: the loads Λ at which to deliver points of the branch
    /// (every crossing, within `residual_tol`), besides the records. The
    /// ANM evaluates its series there (any Λ inside a step) and corrects on
    /// the step's factorisation; Newton continuation interpolates between
    /// its points (cubic Hermite) and corrects.
    pub samples: Vec<f64>,
    /// Newton continuation: chord corrections — the corrector starts on
    /// the factorisation already in hand (the last point's tangent, solved
    /// with the corrector plane's border by Sherman–Morrison) and
    /// refactorises only when an iteration does not halve the residual;
    /// the step is then sized for [`CHORD_AIM`] iterations instead of 3.
    /// About one factorisation a step where the Jacobian changes slowly
    /// along the branch (the circle of tests/continuation.rs: 1.0 against
    /// 4.0). Not on the charged rod's buckled branch: there the Jacobian
    /// changes within a step (4 factorisations a step either way on the 1
    /// kbp DNA scene), and at 0.01 M on 300 bp the chord's first step
    /// after a branch switch converged onto the spurious straight family.
    pub chord: bool,
    /// Stop after the first located bifurcation ([`Stop::Bifurcation`]):
    /// a caller that leaves the branch there need not pay for the ones
    /// beyond (the straight DNA rod's crowded double points).
    pub stop_at_bifurcation: bool,
    /// Newton continuation: predict by extrapolating the cubic Hermite
    /// interpolant of the last two points and their tangents (error
    /// O(ds⁴)) instead of the Euler step along the tangent (O(ds²)):
    /// longer steps where the branch curves smoothly in the state — a
    /// plectoneme's end loop travelling along the rod.
    pub hermite_predictor: bool,
    /// The LU's column order, taken on the first factorisation without
    /// trying the others (None: chosen by fill; [`Branch::column_order`]
    /// says which was taken): a branch continued on a new pattern of the
    /// same problem (a charged rod's next pair list) keeps its order.
    pub column_order: Option<crate::linalg::sparse::ColumnOrder>,
    /// How the Newton corrections factorise (None: by the pattern's
    /// structure, [`crate::linalg::LuKind`] — supernodal block elimination
    /// for a plectoneme's Jacobian; Some(Simplicial): B's own simplicial
    /// LU throughout, as before block elimination was introduced). Records
    /// are factorised simplicially either way (their determinant signs).
    pub lu_kind: Option<crate::linalg::LuKind>,
    /// The Newton corrector iterations a step is sized for (3: each step
    /// grows or shrinks by √(aim / iterations), within [0.5, 2]). More
    /// pays where a point's own factorisation costs several corrections'
    /// (a charged rod's record, simplicial, against block eliminations:
    /// [`crate::charged::dna::SupercoilSettings::corrector_aim`]).
    pub corrector_aim: f64,
    /// Newton continuation without bifurcation detection, σ_min tracking
    /// or samples: each point is factorised for solves only (the pattern's
    /// fastest kind, block elimination on a supernodal LU where it takes
    /// one; its tangent comes from there) and its record's determinant
    /// signs and pivots from B's own simplicial LU, a factorisation of its
    /// own — on a second thread while the next step is corrected with
    /// [`Options::overlap_thread`] — unless the point's factorisation is
    /// that LU already (a pattern too narrow for block elimination), whose
    /// signs are read off it. The record is told (and may stop the
    /// run) once the next step is done, whose point is then dropped. The
    /// same records, bitwise, with or without the thread; against false,
    /// the same signs and pivots, the tangents equal to rounding. Worth it
    /// with a core to spare.
    pub overlap_records: bool,
    /// With [`Options::overlap_records`]: the records' sign factorisations
    /// run on a second thread (true, the default) or on the calling one,
    /// after each point (the same numbers; one thread's wall clock).
    pub overlap_thread: bool,
    /// How often a point of a charged rod's branch followed with a phase
    /// condition that left μ = 0 is taken again, each time from the point
    /// before with half the step, before the branch ends there
    /// ([`crate::charged::branch`]; the plain rod's switch refuses such a
    /// branch instead, [`crate::rod::branch::switch`]).
    pub unfolding_retakes: usize,
    /// A charged branch with a phase condition: the largest moment its
    /// unfolding couple may carry on a tilted state, |μ|∫|Rᵀe3 − e3| ds
    /// (the rod's moment units), once μ is beyond 1e-6 of its scale — and
    /// then only if μ has not jumped from the point before (`Rod`'s
    /// `off_branch`). None: μ beyond 1e-6 of its scale leaves the branch
    /// (the strict check, kept for straight states either way).
    pub unfolding_moment: Option<f64>,
    /// The ANM with bifurcation detection computes the series bifurcation
    /// indicator μ(a) of each step ([`indicator`]): its roots are where a
    /// search starts (and evidence for one), and a σ_min sign change
    /// without det B's is dismissed where μ certainly has no root in the
    /// step (default true; false: the records' det B and σ_min alone, as
    /// Newton continuation). On the series' own steps, not Padé's, and
    /// only for problems that give the tangent series
    /// ([`SeriesProblem::has_series_tangent`]: the plain rod; not the
    /// charged rod, whose pair forces are not a polynomial tape).
    pub series_indicator: bool,
    /// Count each record's unstable modes on the point's own factors
    /// ([`stability::count_unstable`]; the problem must give a metric,
    /// [`Problem::stability_metric`], else records carry none). The
    /// records' determinant signs are then derived from the count: no
    /// factorisation of their own ([`Options::overlap_records`] is not
    /// used), one exact sign per branch.
    pub stability: Option<stability::StabilityOptions>,
    /// The σ_min monitor's economy (default true): it stops when σ_1 has
    /// settled to its four digits, and a location's trial points and
    /// located point start their iterations from the last trial's vectors
    /// (two iterations a trial instead of three to six); a located point
    /// whose monitor σ_1 is below working precision has its other singular
    /// values and null vectors taken beside it at once, at a step sized by
    /// the bracket's slope (the classic monitor first computes them at the
    /// point, where they cannot be resolved). false: every
    /// Ritz value of its block settled and fixed starts, the monitor of
    /// earlier releases — σ_1 the same to its tolerance, but a run's path
    /// follows σ_1's lower digits through its detections and steps, and
    /// the DNA supercoiling scene keeps false so that its shipped
    /// end-loop table (`src/charged/end_loops.csv`, plateau means over
    /// path points) reproduces: the lean monitor moves that table's checked
    /// entry by 1.5e-4 in E_nuc and its plateau from 63 to 70 points.
    pub lean_monitor: bool,
}

/// The corrector iterations a chord step is sized for (each a residual and
/// a solve; a fresh factorisation only when the contraction is poor).
pub const CHORD_AIM: f64 = 6.0;

/// Newton continuation's largest arc-length step when [`Options::max_step`]
/// is left at ∞: its step grows by up to 2× a step where the corrector
/// converges fast, and without a bound it outruns its predictor on long
/// nearly straight stretches (the ANM needs none: its series says how far
/// it holds).
pub const NEWTON_MAX_STEP: f64 = 1.0;

impl Options {
    /// Newton continuation's step bound: `max_step`, or when that is left
    /// at ∞ [`NEWTON_MAX_STEP`] — raised to the first and minimal steps
    /// asked for (a bound below them would contradict them).
    pub fn newton_max_step(&self) -> f64 {
        if self.max_step.is_finite() {
            self.max_step
        } else {
            NEWTON_MAX_STEP.max(self.initial_step).max(self.min_step)
        }
    }
}

impl Default for Options {
    fn default() -> Self {
        Options {
            target_lambda: None,
            lambda_range: (f64::NEG_INFINITY, f64::INFINITY),
            max_steps: 1000,
            residual_tol: 1e-10,
            initial_step: 0.05,
            min_step: 1e-10,
            max_step: f64::INFINITY,
            track_singular: false,
            detect_bifurcations: false,
            bifurcation_tol: 1e-10,
            scaling: None,
            samples: Vec::new(),
            chord: false,
            stop_at_bifurcation: false,
            hermite_predictor: false,
            column_order: None,
            lu_kind: None,
            corrector_aim: 3.0,
            overlap_records: false,
            overlap_thread: true,
            unfolding_retakes: 4,
            unfolding_moment: None,
            series_indicator: true,
            stability: None,
            lean_monitor: true,
        }
    }
}

/// Work counts of a run (the benchmarks' cost measures).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub steps: usize,
    pub factorisations: usize,
    /// Solves with the factors (the σ_min monitor's included).
    pub solves: usize,
    pub residuals: usize,
    pub jacobians: usize,
    /// Series orders computed (ANM).
    pub series_orders: usize,
    /// ANM steps taken on the Padé approximant (longer than the series').
    pub pade_steps: usize,
    /// Newton continuation: corrector failures (the step halved and
    /// retried); their factorisations are in `factorisations`.
    pub rejected_steps: usize,
    /// Bifurcation locations run (each a search along the branch) and the
    /// factorisations they took (part of `factorisations`).
    pub locations: usize,
    pub location_factorisations: usize,
    /// ANM with the series indicator ([`indicator`]): locations that began
    /// in the short bracket around a root of μ(a) and found the point
    /// there, and sign changes of the records' σ_min dismissed because μ
    /// has no root in the step (no location run).
    pub series_located: usize,
    pub series_dismissed: usize,
    /// Solves of the σ_min monitor (part of `solves`).
    pub monitor_solves: usize,
    /// ANM dense output: samples whose chord iterations on their step's
    /// factorisation stalled, corrected on the next point's instead.
    pub deferred_samples: usize,
    /// Factorisations by block elimination on a supernodal LU (part of
    /// `factorisations`; [`Options::lu_kind`]) and the time they took
    /// (part of `times.factorisations`): the rest are simplicial.
    pub block_eliminations: usize,
    pub block_time: std::time::Duration,
    /// Factorisations by condensation of the problem's private blocks
    /// (part of `factorisations`; [`Problem::private_blocks`],
    /// [`crate::linalg::condensed`]).
    pub condensed: usize,
    /// Single-column solves of the records' stability counts (part of
    /// `solves`; [`Options::stability`]).
    pub stability_solves: usize,
    /// Where the time went (wall clock).
    pub times: Times,
}

/// Wall-clock time of a run by kind of work (the run's profile). The
/// first five are disjoint kernels; `location` is inclusive (its
/// corrections' residuals, Jacobians, factorisations and monitor are also
/// in those), and `setup` is what a caller adds for building problems (a
/// charged rod's pair lists and patterns). Not compared by the tests:
/// [`Counts`] equality includes them, so compare the counts' fields.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Times {
    pub residuals: std::time::Duration,
    pub jacobians: std::time::Duration,
    /// Numeric LU factorisations (with the first one's ordering choice).
    pub factorisations: std::time::Duration,
    pub solves: std::time::Duration,
    /// σ_min estimates (inverse iteration with the factors).
    pub monitor: std::time::Duration,
    /// Bifurcation location (inclusive).
    pub location: std::time::Duration,
    /// Records' sign factorisations ([`Options::overlap_records`]): on a
    /// second thread ([`Options::overlap_thread`]) they overlap the rest
    /// and are not part of its wall clock; on the calling thread they are.
    pub overlapped: std::time::Duration,
    /// The records' stability counts (their solves included).
    pub stability: std::time::Duration,
    /// Problem construction reported by the caller (pair lists, patterns).
    pub setup: std::time::Duration,
}

impl Times {
    pub fn add(&mut self, o: &Times) {
        self.residuals += o.residuals;
        self.jacobians += o.jacobians;
        self.factorisations += o.factorisations;
        self.solves += o.solves;
        self.monitor += o.monitor;
        self.location += o.location;
        self.overlapped += o.overlapped;
        self.stability += o.stability;
        self.setup += o.setup;
    }
}

impl Counts {
    /// Add another run's work (a branch continued in segments).
    pub fn add(&mut self, other: &Counts) {
        self.steps += other.steps;
        self.factorisations += other.factorisations;
        self.solves += other.solves;
        self.residuals += other.residuals;
        self.jacobians += other.jacobians;
        self.series_orders += other.series_orders;
        self.pade_steps += other.pade_steps;
        self.rejected_steps += other.rejected_steps;
        self.locations += other.locations;
        self.location_factorisations += other.location_factorisations;
        self.series_located += other.series_located;
        self.series_dismissed += other.series_dismissed;
        self.monitor_solves += other.monitor_solves;
        self.deferred_samples += other.deferred_samples;
        self.block_eliminations += other.block_eliminations;
        self.condensed += other.condensed;
        self.block_time += other.block_time;
        self.stability_solves += other.stability_solves;
        self.times.add(&other.times);
    }

    /// Add a nonlinear solve's work.
    pub fn add_work(&mut self, work: &crate::nonlinear::Work) {
        self.residuals += work.residuals;
        self.jacobians += work.jacobians;
        self.factorisations += work.factorisations;
        self.solves += work.solves;
    }
}

/// A branch: the records, why it stopped, where to resume, and the work done.
#[derive(Clone, Debug)]
pub struct Branch {
    pub records: Vec<Record>,
    /// Bifurcation points located on the branch (with `detect_bifurcations`).
    pub bifurcations: Vec<bifurcation::Bifurcation>,
    /// Brackets where det B or the test function changed sign (or a dip
    /// was searched) but the location failed or found no singular point
    /// that accounts for the change: the branch cannot vouch for its
    /// bifurcations there.
    pub unresolved: Vec<bifurcation::Unresolved>,
    pub stop: Stop,
    pub resume: Resume,
    pub counts: Counts,
    /// Points at the requested loads, in branch order.
    pub samples: Vec<Sample>,
    /// Requested loads the branch crossed but where no point within the
    /// tolerance was found (the correction did not converge).
    pub missed_samples: Vec<f64>,
    /// The column order the LU took ([`Options::column_order`]).
    pub column_order: crate::linalg::sparse::ColumnOrder,
}

//! A charged Kirchhoff rod (physics.md §3.1): the electrostatic
//! self-energy of the rod's uniform line charge added to the collocation
//! system of [`crate::rod`] — a term of the rod, not a second rod.
//!
//! One discrete energy, its exact gradient in the residual and its exact
//! Jacobian (so Newton converges quadratically and the continuation's
//! determinants mean what they say):
//!
//! * The quadrature points of both integrals of E = ½∫∫λ²Φ are the rod's
//!   Gauss stage points s_j with weights w_j = h b_j. For a stage of
//!   element e the near zone is the run of elements e − m … e + m
//!   (m = [`RodCharge::near_elements`]; sides δ₋, δ₊ between mh and (m+1)h,
//!   one-sided at the ends) and the far zone every stage of every other
//!   element: the far double sum is Gauss–Legendre on whole elements at
//!   least mh away (a smooth integrand) and the exclusion is symmetric.
//!   With [`RodCharge::exact_near_width`] the near zone is cut at exactly
//!   δ and the strip between δ and those elements is integrated with the
//!   exact kernel (src/charged/gap.rs): the model no longer moves with the mesh.
//!   Optionally ([`RodCharge::far_points`]) the far double sum runs on M
//!   Gauss–Legendre sites per element on the stage interpolant instead
//!   ([`super::sites`]): same exclusion, same unknowns, a finer rule where
//!   the interaction across a plectoneme varies faster than the shape.
//! * Near zone: §3.2's expansion for a uniform charge (see the parent
//!   module), e_near = ½λ² Σ_sides [J₋₁ + c²/24 (J₁ + κJ₂)] with
//!   c² = u1² + u2² (a Kirchhoff rod's |r''|² = |u × e3|²): a constant plus
//!   ½ΔK_j c². The near zone is a local bending stiffening
//!   ΔK_j = (λ²/24) Σ_sides (J₁ + κJ₂) (→ the Odijk–Skolnick–Fixman
//!   λ²/(4κ²) when κδ ≫ 1), added to the law at each stage
//!   ([`Rod`]'s stiffened system) — that part stays polynomial.
//! * Far zone: the force density at stage j, p_j = −(1/w_j)∂E_far/∂r_j =
//!   −Σ_k w_k P'(d_jk)(r_j − r_k)/d_jk, is a distributed spatial force in
//!   n' + p = 0, i.e. −R(q_j)ᵀp_j in the body-frame n-equation: the stage
//!   rows get +h a_ij R(q_j)ᵀp_j and the update rows +h b_j R(q_j)ᵀp_j.
//! * Near-zone pairs of an inextensible rod keep their distances to the
//!   expansion's order and do no work: their tangential stress is absorbed
//!   by n (a Lagrange multiplier). Shapes, end force and end moment are
//!   those of the full energy; n inside the rod is the contact force less
//!   that stress.
//!
//! Screening cutoff: P = λ²Φ·S with S a C² switch from r_on (the
//! tolerance's cutoff, [`super::discrete::screening_cutoff`]) to
//! r_off = r_on + 1/κ. Pairs within r_off + skin of a reference state are
//! found by cell lists (a Verlet list): they fix the Jacobian's pattern
//! (symbolic factorisation reused) while no stage has moved skin/2 from
//! the reference ([`ChargedRod::displacement`]; the branch driver rebuilds
//! the list there and re-converges that point) or, by [`ListRule::Coverage`],
//! while no far pair missing from the list has come within half the skin
//! of the potential's range ([`ChargedRod::coverage`]). Coulomb (κ = 0):
//! every far pair.
//! Optional hard core: P += k_hc (2.5a − d)³ for d < 2.5a between stages
//! farther apart along the rod than 1.25πa (strands repel before they
//! touch and cannot pass; neighbours on one strand are not pushed apart).
//!
//! Linear algebra, a sparse Jacobian or Newton–Krylov with a banded
//! preconditioner, measured (benches/charged.rs): the far pairs widen the
//! Jacobian's band ~3.5× (0.1 M) and the full LU dominates a direct Newton
//! equilibrium. Both are kept, each where it wins: continuation uses the
//! exact sparse Jacobian and its LU (the bordered determinant signs and
//! σ_min find the buckling points); single equilibria
//! ([`super::equilibrium::solve_point`]) offer
//! [`crate::continuation::equilibrium::newton_krylov`] with the LU of the
//! rod band ([`ChargedRod::local_band`], the far pairs dropped) as a lagged
//! preconditioner — 5–9× faster cold, ~20× warm on straight 1–10 kbp rods —
//! and the damped direct Newton, as fast on 1 kbp buckled shapes.
//! In a plectoneme the far pairs fill the LU ~8.5× (RCM order): there the
//! continuation's Newton corrections use block elimination on the
//! supernodal LU of the Jacobian (~25 ms against ~90 ms for the simplicial
//! LU of the bordered matrix at 5–7.5 turns of the 1 kbp scene, 100
//! elements; [`crate::linalg::LuKind`]), and only a record's factorisation,
//! whose determinant signs are read, stays simplicial.

mod coverage;
mod series;

pub use coverage::ListCoverage;

use super::assembly::{check_rod, near_runs, Layout, NearZone, PairList, Point};
use super::gap::Gap;
use super::sites::Sites;
use crate::continuation::system::AssembledSystem;
use crate::continuation::Problem;
use crate::electrostatics::discrete::screening_cutoff;
use crate::electrostatics::Screening;
use crate::error::{self, Error, Result};
use crate::geometry::vec3::distance;
use crate::linalg::Pattern;
use crate::rod::branch::Phase;
use crate::rod::kinematics::rotation;
use crate::rod::model::{Rod, Supports};
use crate::rod::scheme::Tableau;
use crate::status::Status;

/// The hard core acts below this many radii (2.5a): it starts before the
/// strands touch (2a), so a stiff one keeps them apart and the crossing
/// check (distance < 2a) does not fire on its own penetration.
pub const HARD_CORE_RANGE: f64 = 2.5;

/// The charge of a rod and how its interaction is evaluated.
#[derive(Clone, Debug, PartialEq)]
pub struct RodCharge {
    /// λ with λ² = the energy per length² of the pair interaction
    /// (k_BT·l_B·ν² for ν charges per length, l_B the Bjerrum length).
    pub line_charge: f64,
    pub screening: Screening,
    /// Near zone: at least the stage's element and this many on each side
    /// (≥ 1), and at least `near_width`.
    pub near_elements: usize,
    /// The near zone's least physical width δ (length) on each side: m =
    /// max(`near_elements`, ⌈δ/h⌉) elements ([`RodCharge::near_elements_for`]),
    /// so every stage's sides are at least δ on any mesh. Why: with a
    /// count alone the near zone shrinks with the elements, and once its
    /// sides fall below the radius a (h < a/2 with 2 elements) the
    /// expansion has nothing left to integrate (it starts at a) while the
    /// far zone's Gauss rule meets the kernel 1/d at d < a: the model
    /// itself changes under refinement (the 300 bp scene's buckling point
    /// moved by 1.7e-4 relative from 208 to 312 elements of Gauss(2)).
    /// Default 4a (4 nm for DNA: two elements of the 2 nm automatic mesh,
    /// so that mesh's model is unchanged). None: the count alone.
    pub near_width: Option<f64>,
    /// Cut every stage's near zone at exactly `near_width` (one-sided
    /// within it of an end) and integrate the rest of its elements, out to
    /// the far zone's whole elements, with the exact kernel
    /// (src/charged/gap.rs). false (the default): the near zone's sides reach
    /// the element boundaries (between mh and (m+1)h). Why: the near
    /// zone's expansion is truncated after the curvature, so its error
    /// grows with the side; with sides that step with the mesh the model
    /// itself moves under refinement, and on a buckled rod the mesh
    /// convergence falls to first order (a half/double-mesh estimate then
    /// undershoots the error). Exact, the model is the mesh's limit and
    /// the discretisation converges at the stage rule's order. It also
    /// admits graded meshes ([`Rod::graded`]: fine in a plectoneme, coarse
    /// on the tails), whose near runs are the elements nearer than δ
    /// (src/charged/assembly.rs, `near_runs`). Needs `near_width`; not with
    /// `base_pairs` (no near zone).
    pub exact_near_width: bool,
    /// Relative energy tolerance of the screening cutoff (None: every
    /// pair; Coulomb always keeps every pair).
    pub cutoff_tolerance: Option<f64>,
    /// Verlet skin (length): the pair list holds pairs within r_off + skin.
    pub skin: f64,
    /// Hard-core stiffness k_hc (energy/length⁵): P += k_hc(2.5a − d)³ below 2.5a.
    pub hard_core: Option<f64>,
    /// Threads for the pair forces (1: none started). Results are bitwise
    /// identical for any count (each stage's sum in a fixed order).
    pub threads: usize,
    /// The discrete base-pair model instead of the continuum (physics.md
    /// §3.3): point charges λb at this spacing b (e.g. 0.34 nm), every pair
    /// farther apart along the rod than a, with the same cutoff, skin and
    /// cell lists ([`super::sites`]; threads as the continuum's). The hard core
    /// then acts between the charges (b² k_hc(2.5a − d)³ per pair, the
    /// continuum's double integral as a sum over the sites).
    pub base_pairs: Option<f64>,
    /// The continuum's far zone on this many Gauss–Legendre points per
    /// element instead of the stage points (0, the default: the stage
    /// points), their positions on a six-point Lagrange interpolant of the
    /// stage positions ([`super::sites`]): the far double integral's quadrature refined
    /// without new unknowns. The near zone, the exclusion (elements more
    /// than `near_elements` apart), cutoff, skin and hard core are the
    /// stage quadrature's. Measured (benches/README.md): the
    /// stage quadrature's error on a plectoneme follows the stage spacing,
    /// not the rod's shape. Not with `base_pairs` or `anm`.
    pub far_points: usize,
    /// Follow this rod's branches by the asymptotic numerical method (the
    /// series of the pair forces, src/charged/rod/series.rs: one
    /// factorisation a step, the step from the series' own convergence, cut
    /// where the pair list would stop holding by its [`ListRule`]) instead
    /// of Newton continuation
    /// (None, the default). The continuum model only (the base-pair model
    /// is refused).
    pub anm: Option<crate::continuation::anm::AnmOptions>,
    /// When a branch rebuilds its pair list ([`ListRule`]).
    pub list_rule: ListRule,
}

/// When a branch's pair list is rebuilt. Both keep every point an
/// equilibrium of the full model (no interacting pair missing).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ListRule {
    /// Verlet's rule: once a stage has moved half the skin from where the
    /// list was built.
    #[default]
    Displacement,
    /// Once a far pair missing from the list comes within half the skin of
    /// the potential's range ([`ChargedRod::coverage`]): lists last longer
    /// where the shape slides as a whole. Measured mixed, so not the
    /// default (benches/README.md): 1 kbp, 1 pN, 0 → 12 turns at
    /// 0.1 M, aim 3, 75.9 s against 90.1 s (2 threads; 77 lists against
    /// 166); at 0.01 M, aim 5, 605 s against 463 s (more rejected steps);
    /// at 0.1 M, aim 5, a step at 1.75 turns hopped onto a solution with
    /// μ ≠ 0 (μ/scale 1.2e-7, drifting to the unfolding check's 1e-6 at
    /// 7.27 turns, where the run ended) where Verlet's lists pass.
    /// The base-pair model keeps [`ListRule::Displacement`].
    Coverage,
}

impl RodCharge {
    /// Defaults: a near zone of at least 2 elements and 4a, cutoff at 1e-6, skin max(2a, 4/κ), no
    /// hard core, 1 thread.
    pub fn new(line_charge: f64, screening: Screening) -> Self {
        let skin =
            if screening.kappa > 0.0 { (2.0 * screening.a).max(4.0 / screening.kappa) } else { 2.0 * screening.a };
        RodCharge {
            line_charge,
            screening,
            near_elements: 2,
            near_width: Some(4.0 * screening.a),
            exact_near_width: false,
            cutoff_tolerance: Some(1e-6),
            skin,
            hard_core: None,
            threads: 1,
            base_pairs: None,
            far_points: 0,
            anm: None,
            list_rule: ListRule::Displacement,
        }
    }

    fn validate(&self) -> Result<()> {
        error::finite("line_charge", self.line_charge)?;
        error::finite("kappa", self.screening.kappa)?;
        if self.screening.kappa < 0.0 {
            return Err(Error::new(
                Status::ErrOutOfRange,
                format!("argument `kappa` must be ≥ 0 (got {:e})", self.screening.kappa),
            ));
        }
        error::positive("a", self.screening.a)?;
        error::count_in_range("near_elements", self.near_elements as i64, 1, 64)?;
        if let Some(w) = self.near_width {
            error::positive("near_width", w)?;
        }
        if let Some(t) = self.cutoff_tolerance {
            if !(t > 0.0 && t < 1.0) {
                return Err(Error::new(
                    Status::ErrOutOfRange,
                    format!("argument `cutoff_tolerance` must be in (0, 1) (got {t:e})"),
                ));
            }
        }
        error::positive("skin", self.skin)?;
        if let Some(k) = self.hard_core {
            error::positive("hard_core", k)?;
        }
        error::count_in_range("threads", self.threads as i64, 1, 256)?;
        error::count_in_range("far_points", self.far_points as i64, 0, 32)?;
        if self.far_points > 0 && (self.base_pairs.is_some() || self.anm.is_some()) {
            return Err(Error::new(
                Status::ErrOutOfRange,
                "far_points refines the continuum's far zone for Newton continuation: not with base_pairs or anm",
            ));
        }
        if self.exact_near_width && (self.near_width.is_none() || self.base_pairs.is_some()) {
            return Err(Error::new(
                Status::ErrOutOfRange,
                "exact_near_width cuts the continuum's near zone at near_width: it needs near_width, and not base_pairs",
            ));
        }
        if let Some(b) = self.base_pairs {
            error::positive("base_pairs", b)?;
            if self.anm.is_some() {
                return Err(Error::new(
                    Status::ErrOutOfRange,
                    "the base-pair model has no series: its branches are followed by Newton continuation (anm None)",
                ));
            }
        }
        Ok(())
    }

    /// The near zone's elements on each side of a stage's own on a mesh of
    /// `elements` elements of length `h`: max(`near_elements`, ⌈δ/h⌉) with
    /// δ = `near_width` (less a rounding's worth; at most the mesh, beyond
    /// which no pair is far).
    pub fn near_elements_for(&self, h: f64, elements: usize) -> usize {
        let width = self.near_width.map_or(0.0, |w| ((w / h) * (1.0 - 1e-12)).ceil().min(elements as f64));
        self.near_elements.max(width as usize)
    }

    /// The switch region (r_on, r_off) of the screening cutoff, None when
    /// every pair is kept.
    pub fn cutoff(&self, length: f64) -> Option<(f64, f64)> {
        let kappa = self.screening.kappa;
        let tol = self.cutoff_tolerance?;
        let on = screening_cutoff(kappa, self.screening.a, tol, 2.0 * length)?;
        let off = on + 1.0 / kappa;
        (off < length).then_some((on, off))
    }
}

/// The split of the electrostatic energy of a state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RodEnergy {
    /// Near zone: the curvature-free constant plus ½ΣwΔK c².
    pub near: f64,
    /// Far pairs (with the cutoff's switch).
    pub far: f64,
    /// Hard-core pairs.
    pub hard_core: f64,
    /// The elastic energy ½Σw (K_b(u1² + u2²) + C u3²) of the uncharged law.
    pub elastic: f64,
}

/// The charged rod as a [`Problem`]: the rod's system (stiffened near
/// zone) plus the far-zone pair forces, for a fixed pair list. The
/// continuation parameter is the rod's Λ, except for rods with a
/// controlled end rotation, where it is the end rotation φ itself
/// (radians, any number of turns): the rod's Λ = sin(φ/2) and the row
/// c² + Λ² = 1 becomes c = cos(φ/2).
pub struct ChargedRod {
    rod: Rod,
    charge: RodCharge,
    sys: AssembledSystem,
    n: usize,
    pattern: Pattern,
    rod_map: Vec<usize>,
    rod_jx: Vec<f64>,
    tab: Tableau,
    h: f64,
    points: Vec<Point>,
    stiffening: Vec<f64>,
    near_constant: Vec<f64>,
    cutoff: Option<(f64, f64)>,
    /// Pair list in CSR form: partners of stage j at adj[adj_ptr[j]..adj_ptr[j+1]].
    adj_ptr: Vec<usize>,
    adj: Vec<usize>,
    /// First n-row position of element(j)'s rows in the columns r_k (3).
    adj_pos: Vec<[usize; 3]>,
    /// Positions of element(j)'s 3(s+1) n-rows × (r_j: 3, q_j: 4).
    diag_pos: Vec<usize>,
    reference: Vec<[f64; 3]>,
    list_local: bool,
    twisted_phi: Option<usize>,
    /// Whether the rod's phase condition (and its unfolding μ) is on:
    /// the stability metric's zero mode.
    phased: bool,
    /// The caller's threads (threads > 1): a pool kept for the problem's
    /// life (a thread spawn per residual costs more than the work).
    pool: Option<rayon::ThreadPool>,
    /// The discrete base-pair model or the continuum's refined far zone
    /// (then `adj` lists, for each stage, every stage its force depends on,
    /// itself included, and `full_pos` the positions of each block in the
    /// element's n-rows).
    sites: Option<Sites>,
    full_pos: Vec<usize>,
    /// The exact near zone's gap ([`RodCharge::exact_near_width`]) and its
    /// blocks' positions ([`Layout::gap_pos`]).
    gap: Option<Gap>,
    gap_pos: Vec<usize>,
    /// Each element's near run ([`near_runs`]).
    runs: Vec<(usize, usize)>,
    weights: Vec<f64>,
    /// The stored Taylor series of the last expansion (the ANM, [`series`]).
    series: Option<series::Series>,
    /// The list's coverage check (None: every pair listed, or base pairs).
    list_coverage: Option<ListCoverage>,
    // Scratch (no allocation per evaluation).
    r: Vec<[f64; 3]>,
    p: Vec<[f64; 3]>,
    g: Vec<[f64; 9]>,
    dsum: Vec<[f64; 9]>,
}

impl ChargedRod {
    /// The charged rod with its pair list built at `reference` (a state of
    /// the rod, μ appended with a phase condition), optionally with the
    /// rod's phase condition (node, azimuth) of a symmetric buckle.
    pub fn new(rod: &Rod, charge: &RodCharge, phase: Phase, reference: &[f64]) -> Result<Self> {
        charge.validate()?;
        let s = check_rod(rod, charge)?;
        let runs = near_runs(rod, charge);
        let h = rod.element_length();
        let tab = Tableau::gauss(s);
        let near = NearZone::new(rod, charge, &tab, &runs);
        let ne = rod.elements;
        let extra: Vec<Vec<f64>> = (0..ne).map(|e| near.stiffening[e * s..(e + 1) * s].to_vec()).collect();
        let sys = match phase {
            Some((node, azimuth)) => rod.system_with_phase_stiffened(node, azimuth, &extra)?,
            None => rod.system_stiffened(&extra)?,
        };
        let n = sys.dim();
        if reference.len() != n {
            return Err(Error::new(
                Status::ErrInvalidDimension,
                format!("reference state has {} entries, the charged rod {n}", reference.len()),
            ));
        }
        error::finite_result("reference", reference)?;
        let points = near.points;
        let l2 = charge.line_charge * charge.line_charge;
        let cutoff = if l2 == 0.0 { None } else { charge.cutoff(rod.length) };
        let reference_r: Vec<[f64; 3]> =
            points.iter().map(|p| [reference[p.offset], reference[p.offset + 1], reference[p.offset + 2]]).collect();
        let list = PairList::new(rod, charge, &points, &reference_r, cutoff, &runs)?;
        let gap = match (charge.exact_near_width, charge.near_width) {
            (true, Some(delta)) if l2 != 0.0 => Gap::new(&points, s, &rod.node_positions(), &runs, delta),
            _ => None,
        };
        let layout = Layout::new(rod, &sys, &points, &list, gap.as_ref())?;
        let twisted_phi = rod.twisted().then(|| rod.end_cosine().expect("twisted rods have c"));
        let (np, na) = (points.len(), list.adj.len());
        let weights = points.iter().map(|p| p.w).collect();
        let pool = match charge.threads {
            0 | 1 => None,
            threads => Some(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .map_err(|e| Error::new(Status::ErrInternal, format!("thread pool: {e}")))?,
            ),
        };
        let mut problem = ChargedRod {
            rod: rod.clone(),
            charge: charge.clone(),
            rod_jx: vec![0.0; sys.pattern().nnz()],
            sys,
            n,
            pattern: layout.pattern,
            rod_map: layout.rod_map,
            tab,
            h,
            points,
            stiffening: near.stiffening,
            near_constant: near.constant,
            cutoff,
            adj_ptr: list.adj_ptr,
            adj: list.adj,
            adj_pos: layout.adj_pos,
            diag_pos: layout.diag_pos,
            reference: reference_r,
            list_local: list.local,
            twisted_phi,
            phased: phase.is_some(),
            pool,
            weights,
            sites: list.sites,
            full_pos: layout.full_pos,
            gap,
            gap_pos: layout.gap_pos,
            runs,
            series: None,
            list_coverage: None,
            r: vec![[0.0; 3]; np],
            p: vec![[0.0; 3]; np],
            g: vec![[0.0; 9]; na],
            dsum: vec![[0.0; 9]; np],
        };
        problem.list_coverage = problem.coverage();
        Ok(problem)
    }

    pub fn rod(&self) -> &Rod {
        &self.rod
    }

    pub fn charge(&self) -> &RodCharge {
        &self.charge
    }

    /// Half-bandwidth of the rod's own Jacobian entries (an element's
    /// equations couple its first node, its stages and the next node: 13
    /// unknowns per point): the band that [`crate::continuation::krylov`]'s
    /// preconditioner keeps to drop the electrostatic far pairs. With
    /// base-pair charges, twice that: a site's position interpolates four
    /// stage points across an element end, so its neighbours' pairs couple
    /// stencils about an element apart. Measured (Newton–Krylov, 1e-8):
    /// on the straight 1 and 3 kbp rods 15–16 GMRES iterations per solve
    /// with the one-element band, 8 with this one (50 → 40 ms, 169 → 125
    /// ms); on a buckled 300 bp rod 151 → 37 (134 → 41 ms); 2 elements +
    /// 12 (90) kept too little (13 and 97 iterations), wider bands gained
    /// ≤ 10 % on the buckled rod and lost as much on the straight ones.
    pub fn local_band(&self) -> usize {
        let one = self.rod.block_size() + 12;
        // The refined far zone's pairs are more than `near_elements` apart:
        // outside the band, as the stage points' are.
        if self.base_pairs().is_some() {
            2 * one
        } else {
            one
        }
    }

    /// Unknowns appended after the rod's own (the phase condition's
    /// multiplier on a buckled branch, 0 otherwise): their rows and columns
    /// couple to mid-rod nodes, so a band preconditioner keeps them whole
    /// ([`crate::continuation::krylov::BandPreconditioner::bordered`]).
    pub fn border(&self) -> usize {
        self.n - self.rod.unknowns()
    }

    /// The screening cutoff's switch region (r_on, r_off), None: every pair.
    pub fn cutoff(&self) -> Option<(f64, f64)> {
        self.cutoff
    }

    /// Pairs in the list (each counted once per direction).
    pub fn pairs(&self) -> usize {
        self.adj.len()
    }

    /// The near-zone bending stiffening ΔK at every stage point (element-major).
    pub fn stiffening(&self) -> &[f64] {
        &self.stiffening
    }

    /// Stage points (arc length, weight), element-major.
    pub fn stage_points(&self) -> Vec<(f64, f64)> {
        self.points.iter().map(|p| (p.s, p.w)).collect()
    }

    /// Whether the pair list is limited by a radius (else it holds every
    /// far pair and never needs rebuilding).
    pub fn list_is_local(&self) -> bool {
        self.list_local
    }

    /// The largest distance a stage point of `x` has moved from the pair
    /// list's reference: the list is exact while it is below skin/2.
    pub fn displacement(&self, x: &[f64]) -> f64 {
        if let Some(sites) = &self.sites {
            let stages: Vec<[f64; 3]> =
                self.points.iter().map(|p| [x[p.offset], x[p.offset + 1], x[p.offset + 2]]).collect();
            return sites.displacement(&stages);
        }
        let r: Vec<[f64; 3]> = self.points.iter().map(|p| [x[p.offset], x[p.offset + 1], x[p.offset + 2]]).collect();
        self.moved(&r)
    }

    /// The largest distance of the stage points `r` from where the list
    /// was built (Verlet's measure; [`ChargedRod::displacement`] and the
    /// ANM's reach along a series).
    fn moved(&self, r: &[[f64; 3]]) -> f64 {
        r.iter().zip(&self.reference).map(|(p, r0)| distance(p, r0)).fold(0.0, f64::max)
    }

    /// The rod's Λ for the continuation parameter.
    fn rod_lambda(&self, param: f64) -> (f64, f64) {
        match self.twisted_phi {
            Some(_) => ((0.5 * param).sin(), 0.5 * (0.5 * param).cos()),
            None => (param, 1.0),
        }
    }

    /// Whether the hard core acts between stages j and k: only when they are
    /// farther apart along the rod than half the circumference of a circle
    /// of diameter 2.5a (nearer points are neighbours on one strand, as
    /// close in space as along the rod, and must not repel).
    fn hard_pair(&self, j: usize, k: usize) -> bool {
        self.hard_gap((self.points[j].s - self.points[k].s).abs())
    }

    /// Whether the hard core acts between points `gap` apart along the rod.
    fn hard_gap(&self, gap: f64) -> bool {
        self.charge.hard_core.is_some() && gap > 0.5 * std::f64::consts::PI * HARD_CORE_RANGE * self.charge.screening.a
    }

    /// The hard core's P(d) (0 beyond 2.5a).
    fn hard_potential(&self, d: f64) -> f64 {
        match self.charge.hard_core {
            Some(khc) if d < HARD_CORE_RANGE * self.charge.screening.a => {
                khc * (HARD_CORE_RANGE * self.charge.screening.a - d).powi(3)
            }
            _ => 0.0,
        }
    }

    /// P'(d) and P''(d) of the pair potential (switched Φ and, for `hard`
    /// pairs, the hard core).
    fn pair(&self, d: f64, hard: bool) -> (f64, f64) {
        let (kappa, a) = (self.charge.screening.kappa, self.charge.screening.a);
        let l2 = self.charge.line_charge * self.charge.line_charge;
        let (mut p1, mut p2) = (0.0, 0.0);
        if l2 != 0.0 {
            let e = (-kappa * d).exp();
            let (f0, f1, f2) = (
                e / d,
                -e * (1.0 + kappa * d) / (d * d),
                e * (2.0 + 2.0 * kappa * d + kappa * kappa * d * d) / (d * d * d),
            );
            let (s0, s1, s2) = match self.cutoff {
                None => (1.0, 0.0, 0.0),
                Some((_, off)) if d >= off => (0.0, 0.0, 0.0),
                Some((on, _)) if d <= on => (1.0, 0.0, 0.0),
                Some((on, off)) => {
                    let wdt = off - on;
                    let x = (d - on) / wdt;
                    (
                        1.0 - x * x * x * (10.0 - 15.0 * x + 6.0 * x * x),
                        -30.0 * x * x * (1.0 - x) * (1.0 - x) / wdt,
                        -60.0 * x * (1.0 - x) * (1.0 - 2.0 * x) / (wdt * wdt),
                    )
                }
            };
            p1 += l2 * (f1 * s0 + f0 * s1);
            p2 += l2 * (f2 * s0 + 2.0 * f1 * s1 + f0 * s2);
        }
        if let (Some(k), true) = (self.charge.hard_core, hard) {
            if d < HARD_CORE_RANGE * a {
                let g = HARD_CORE_RANGE * a - d;
                p1 += -3.0 * k * g * g;
                p2 += 6.0 * k * g;
            }
        }
        (p1, p2)
    }

    /// Far-zone force densities p_j (and, with `jacobian`, the pair
    /// blocks G_jk = ∂(−P'Δ/d)/∂r_k and their sums) at the positions in
    /// self.r, threads by chunks of stages.
    fn forces(&mut self, jacobian: bool) {
        self.far_forces(jacobian);
        if let Some(mut gap) = self.gap.take() {
            let mut p = std::mem::take(&mut self.p);
            let pair = |d: f64, along: f64| self.pair(d, self.hard_gap(along));
            gap.forces(&self.r, &self.weights, &pair, &mut p, jacobian);
            self.p = p;
            self.gap = Some(gap);
        }
    }

    /// The far zone's part of [`Self::forces`].
    fn far_forces(&mut self, jacobian: bool) {
        if let Some(mut sites) = self.sites.take() {
            let (mut p, mut g) = (std::mem::take(&mut self.p), std::mem::take(&mut self.g));
            let pair = |d: f64, gap: f64| self.pair(d, self.hard_gap(gap));
            sites.forces(&self.r, &self.weights, &pair, &mut p, jacobian.then_some(&mut g[..]), self.pool.as_ref());
            self.p = p;
            self.g = g;
            self.sites = Some(sites);
            return;
        }
        let np = self.points.len();
        let threads = self.charge.threads.min(np.max(1));
        let mut p = std::mem::take(&mut self.p);
        let mut g = std::mem::take(&mut self.g);
        let mut dsum = std::mem::take(&mut self.dsum);
        let this = &*self;
        let work = |range: std::ops::Range<usize>, p: &mut [[f64; 3]], g: &mut [[f64; 9]], dsum: &mut [[f64; 9]]| {
            let g_base = this.adj_ptr[range.start];
            for (jj, j) in range.enumerate() {
                let rj = this.r[j];
                let mut pj = [0.0; 3];
                let mut dj = [0.0; 9];
                for a in this.adj_ptr[j]..this.adj_ptr[j + 1] {
                    let k = this.adj[a];
                    let dv = [rj[0] - this.r[k][0], rj[1] - this.r[k][1], rj[2] - this.r[k][2]];
                    let d = (dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]).sqrt();
                    let wk = this.points[k].w;
                    let (p1, p2) = if d > 0.0 { this.pair(d, this.hard_pair(j, k)) } else { (0.0, 0.0) };
                    let c = -wk * p1 / d.max(f64::MIN_POSITIVE);
                    for i in 0..3 {
                        pj[i] += c * dv[i];
                    }
                    if jacobian {
                        // ∂p_j/∂r_k = w_k [P'/d I + (P'' − P'/d) ΔΔᵀ/d²] =: w_k G.
                        let mut gk = [0.0; 9];
                        if d > 0.0 {
                            let (a0, a1) = (p1 / d, (p2 - p1 / d) / (d * d));
                            for r in 0..3 {
                                for q in 0..3 {
                                    gk[3 * r + q] = wk * (a1 * dv[r] * dv[q] + if r == q { a0 } else { 0.0 });
                                }
                            }
                        }
                        for i in 0..9 {
                            dj[i] -= gk[i];
                        }
                        g[a - g_base] = gk;
                    }
                }
                p[jj] = pj;
                if jacobian {
                    dsum[jj] = dj;
                }
            }
        };
        if threads <= 1 || np < 64 || self.pool.is_none() {
            work(0..np, &mut p, &mut g, &mut dsum);
        } else {
            let chunk = np.div_ceil(threads);
            let pool = this.pool.as_ref().expect("a pool when threads > 1");
            pool.scope(|scope| {
                let (mut pr, mut gr, mut dr) = (&mut p[..], &mut g[..], &mut dsum[..]);
                let mut start = 0;
                while start < np {
                    let end = (start + chunk).min(np);
                    let na = this.adj_ptr[end] - this.adj_ptr[start];
                    let (p0, p1) = pr.split_at_mut(end - start);
                    let (g0, g1) = gr.split_at_mut(na);
                    let (d0, d1) = dr.split_at_mut(end - start);
                    pr = p1;
                    gr = g1;
                    dr = d1;
                    let work = &work;
                    scope.spawn(move |_| work(start..end, p0, g0, d0));
                    start = end;
                }
            });
        }
        self.p = p;
        self.g = g;
        self.dsum = dsum;
    }

    fn gather(&mut self, x: &[f64]) {
        for (r, p) in self.r.iter_mut().zip(&self.points) {
            *r = [x[p.offset], x[p.offset + 1], x[p.offset + 2]];
        }
    }

    /// Row coefficients of a stage point's body force in its element's
    /// 3(s+1) n-rows: h_e a_i,stage for the stage rows, h_e b_stage for the
    /// update (h_e its element's length).
    fn coefficient(&self, row_block: usize, point: &Point) -> f64 {
        let s = self.tab.b.len();
        let h = if self.rod.breakpoints.is_some() { self.rod.element_h(point.element) } else { self.h };
        if row_block < s {
            h * self.tab.a[row_block][point.stage]
        } else {
            h * self.tab.b[point.stage]
        }
    }

    fn n_row(&self, element: usize, row_block: usize, c: usize) -> usize {
        let s = self.tab.b.len();
        if row_block < s {
            self.rod.stage_offset(element, row_block) + 7 + c
        } else {
            self.rod.node(element + 1) + 7 + c
        }
    }

    /// (f, √f) of [`Self::rescale`] (f ≥ 1).
    fn force_moment_factors(&self) -> (f64, f64) {
        let kb = self.rod.law.bending();
        let l = self.rod.length;
        let base = kb / (l * l);
        let tension = match self.rod.supports {
            Supports::Twisted { tension } | Supports::Torqued { tension } => tension.abs(),
            _ => 0.0,
        };
        let f = (base.max(tension).max(self.charge.line_charge * self.charge.line_charge) / base).max(1.0);
        (f, f.sqrt())
    }

    /// The rod's force and moment scales are K_b/L² and K_b/L; a charged
    /// rod under tension T carries forces of order F = max(K_b/L², |T|, λ²)
    /// (λ² is a force: energy per length²), 10²–10³ times more for DNA, and
    /// residual tolerances relative to K_b/L² would sit below the rounding
    /// of the pair sums. Forces scale by f = F L²/K_b, moments by √f (the
    /// length √(K_b/F) replacing L).
    fn rescale(&self, v: &mut [f64], equations: bool) {
        let (f, fm) = self.force_moment_factors();
        if f <= 1.0 {
            return;
        }
        let body = self.rod.node(self.rod.elements) + 13;
        for (k, v) in v.iter_mut().enumerate() {
            if k < 13 && equations {
                // Boundary rows: only the axial-force condition of a
                // tension-controlled end is a force.
                if k == 9 && matches!(self.rod.supports, Supports::Twisted { .. } | Supports::Torqued { .. }) {
                    *v *= f;
                }
                continue;
            }
            if k >= body {
                // c = cos(φ/2) (scale 1), a torque clamp's (c, s) (scale 1;
                // its moment row: equation_scales), or the unfolding μ (a
                // couple per length).
                if k == self.rod.unknowns() {
                    *v *= fm;
                }
                continue;
            }
            match k % 13 {
                7..=9 => *v *= f,
                10..=12 => *v *= fm,
                _ => {}
            }
        }
    }

    fn has_pairs(&self) -> bool {
        self.charge.line_charge != 0.0 || self.charge.hard_core.is_some()
    }

    /// The electrostatic (and hard-core) energy of a state and the elastic
    /// energy of the uncharged law, by the stage quadrature.
    pub fn energy(&mut self, x: &[f64]) -> RodEnergy {
        self.gather(x);
        let data = self.rod.rhs_data();
        let (kb, c) = (self.rod.law.stiffness[(0, 0)], self.rod.law.stiffness[(2, 2)]);
        let kb2 = self.rod.law.stiffness[(1, 1)];
        let l2 = self.charge.line_charge * self.charge.line_charge;
        let (mut near, mut far, mut hard, mut elastic) = (0.0, 0.0, 0.0, 0.0);
        for (j, pt) in self.points.iter().enumerate() {
            let y = &x[pt.offset..pt.offset + 13];
            let (u, _) =
                crate::rod::kinematics::strains::<f64, f64>(&data, &[y[10], y[11], y[12]], &[y[7], y[8], y[9]]);
            // u of the stiffened law: m = (K + ΔK) u.
            let dk = self.stiffening[j];
            let u1 = u[0] * kb / (kb + dk);
            let u2 = u[1] * kb2 / (kb2 + dk);
            let c2 = u1 * u1 + u2 * u2;
            near += pt.w * (self.near_constant[j] + 0.5 * dk * c2);
            elastic += pt.w * 0.5 * (kb * u1 * u1 + kb2 * u2 * u2 + c * u[2] * u[2]);
            if self.sites.is_some() {
                continue;
            }
            for &k in &self.adj[self.adj_ptr[j]..self.adj_ptr[j + 1]] {
                let rk = self.r[k];
                let rj = self.r[j];
                let d = distance(&rj, &rk);
                let ww = 0.5 * pt.w * self.points[k].w;
                if l2 != 0.0 {
                    far += ww * self.potential(d);
                }
                if self.hard_pair(j, k) {
                    hard += ww * self.hard_potential(d);
                }
            }
        }
        if let Some(mut sites) = self.sites.take() {
            (far, hard) = sites.energy(&self.r, &|d, gap| {
                (self.potential(d), if self.hard_gap(gap) { self.hard_potential(d) } else { 0.0 })
            });
            self.sites = Some(sites);
        }
        if let Some(gap) = &self.gap {
            let (e, h) = gap.energy(&self.r, &self.weights, &|d, along| {
                (self.potential(d), if self.hard_gap(along) { self.hard_potential(d) } else { 0.0 })
            });
            far += e;
            hard += h;
        }
        RodEnergy { near, far, hard_core: hard, elastic }
    }

    /// P(d) = λ²Φ(d)·S(d), the switched pair potential.
    fn potential(&self, d: f64) -> f64 {
        let s = match self.cutoff {
            None => 1.0,
            Some((on, _)) if d <= on => 1.0,
            Some((_, off)) if d >= off => 0.0,
            Some((on, off)) => {
                let t = (d - on) / (off - on);
                1.0 - t * t * t * (10.0 - 15.0 * t + 6.0 * t * t)
            }
        };
        self.charge.line_charge * self.charge.line_charge * (-self.charge.screening.kappa * d).exp() / d * s
    }

    /// The base-pair model's (sites, spacing b used, directed site pairs),
    /// None for the continuum.
    pub fn base_pairs(&self) -> Option<(usize, f64, usize)> {
        self.sites.as_ref().and_then(|s| s.spacing().map(|b| (s.count(), b, s.site_pairs())))
    }

    /// The exact near zone's gap points ([`RodCharge::exact_near_width`];
    /// 0 without).
    pub fn gap_points(&self) -> usize {
        self.gap.as_ref().map_or(0, Gap::points)
    }

    /// The refined far zone's (sites, directed site pairs), None on the
    /// stage points or base pairs ([`RodCharge::far_points`]).
    pub fn far_sites(&self) -> Option<(usize, usize)> {
        self.sites.as_ref().filter(|s| s.spacing().is_none()).map(|s| (s.count(), s.site_pairs()))
    }

    /// The far-zone force density at every stage point of `x` (spatial).
    pub fn force_densities(&mut self, x: &[f64]) -> Vec<[f64; 3]> {
        self.gather(x);
        if self.has_pairs() {
            self.forces(false);
        } else {
            self.p.iter_mut().for_each(|p| *p = [0.0; 3]);
        }
        self.p.clone()
    }
}

impl Problem for ChargedRod {
    fn trailing(&self) -> usize {
        self.border()
    }

    /// The rod's stage metric ([`Rod::stage_metric`]): its injection is
    /// the far pairs' (the same rows, h a_ij and h b_j, R(q_j)ᵀ), so a
    /// dead force density enters the charged rod's rows as the pair
    /// forces do.
    fn stability_metric(&self, x: &[f64]) -> Option<crate::continuation::stability::Metric> {
        self.rod.stage_metric(x, self.phased)
    }

    fn dim(&self) -> usize {
        self.n
    }

    fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    fn residual(&mut self, x: &[f64], param: f64, r: &mut [f64]) {
        let (lambda, _) = self.rod_lambda(param);
        self.sys.residual(x, lambda, r);
        if let Some(c) = self.twisted_phi {
            r[c] = x[c] - (0.5 * param).cos();
        }
        if !self.has_pairs() {
            return;
        }
        self.gather(x);
        self.forces(false);
        let s = self.tab.b.len();
        for (j, pt) in self.points.iter().enumerate() {
            let q = [x[pt.offset + 3], x[pt.offset + 4], x[pt.offset + 5], x[pt.offset + 6]];
            let rot = rotation(&q);
            let p = self.p[j];
            let fb = [0, 1, 2].map(|c| rot[0][c] * p[0] + rot[1][c] * p[1] + rot[2][c] * p[2]);
            for rb in 0..=s {
                let coef = self.coefficient(rb, pt);
                for c in 0..3 {
                    r[self.n_row(pt.element, rb, c)] += coef * fb[c];
                }
            }
        }
    }

    fn jacobian(&mut self, x: &[f64], param: f64, jx: &mut [f64], jl: &mut [f64]) {
        let (lambda, dlambda) = self.rod_lambda(param);
        let mut rod_jx = std::mem::take(&mut self.rod_jx);
        self.sys.jacobian(x, lambda, &mut rod_jx, jl);
        jx.fill(0.0);
        for (v, &p) in rod_jx.iter().zip(&self.rod_map) {
            jx[p] += v;
        }
        self.rod_jx = rod_jx;
        if let Some(c) = self.twisted_phi {
            jl.iter_mut().for_each(|v| *v *= dlambda);
            let pos = self.pattern.position(c, c).expect("diagonal");
            // Row c was c² + Λ² − 1 (entries (c, c) only, and Λ): now c − cos(φ/2).
            jx[pos] = 1.0;
            jl[c] = 0.5 * (0.5 * param).sin();
        }
        if !self.has_pairs() {
            return;
        }
        self.gather(x);
        self.forces(true);
        let s = self.tab.b.len();
        for (j, pt) in self.points.iter().enumerate() {
            let q = [x[pt.offset + 3], x[pt.offset + 4], x[pt.offset + 5], x[pt.offset + 6]];
            let rot = rotation(&q);
            let p = self.p[j];
            // ∂(Rᵀp)/∂q_i, exact by central differences (R is quadratic in q).
            let mut dq = [[0.0; 4]; 3];
            for i in 0..4 {
                let (mut qp, mut qm) = (q, q);
                qp[i] += 1.0;
                qm[i] -= 1.0;
                let (rp, rm) = (rotation(&qp), rotation(&qm));
                for c in 0..3 {
                    dq[c][i] = 0.5
                        * ((rp[0][c] - rm[0][c]) * p[0] + (rp[1][c] - rm[1][c]) * p[1] + (rp[2][c] - rm[2][c]) * p[2]);
                }
            }
            // ∂(Rᵀp)/∂r_j = Rᵀ D_j.
            let d = self.dsum[j];
            let rt_mul = |m: &[f64; 9]| -> [[f64; 3]; 3] {
                let mut out = [[0.0; 3]; 3];
                for c in 0..3 {
                    for col in 0..3 {
                        out[c][col] = rot[0][c] * m[col] + rot[1][c] * m[3 + col] + rot[2][c] * m[6 + col];
                    }
                }
                out
            };
            let dr = rt_mul(&d);
            let base = j * 3 * (s + 1) * 7;
            for rb in 0..=s {
                let coef = self.coefficient(rb, pt);
                for c in 0..3 {
                    let at = base + (rb * 3 + c) * 7;
                    for col in 0..3 {
                        jx[self.diag_pos[at + col]] += coef * dr[c][col];
                    }
                    for i in 0..4 {
                        jx[self.diag_pos[at + 3 + i]] += coef * dq[c][i];
                    }
                }
            }
            // Block k of a list whose every block has its own positions
            // (element(j)'s 3(s+1) n-rows × 3 columns, row-major): the
            // gap's, and the sites' (base pairs, the refined far zone,
            // whose partners include the stage itself).
            let rows = 3 * (s + 1);
            let scatter = |jx: &mut [f64], block: &[f64; 9], pos: &[usize], k: usize| {
                let block = rt_mul(block);
                for rb in 0..=s {
                    let coef = self.coefficient(rb, pt);
                    for c in 0..3 {
                        for col in 0..3 {
                            jx[pos[(k * rows + rb * 3 + c) * 3 + col]] += coef * block[c][col];
                        }
                    }
                }
            };
            if let Some(gap) = &self.gap {
                for b in gap.block_ptr[j]..gap.block_ptr[j + 1] {
                    scatter(jx, &gap.blocks[b], &self.gap_pos, b);
                }
            }
            if self.sites.is_some() {
                for a in self.adj_ptr[j]..self.adj_ptr[j + 1] {
                    scatter(jx, &self.g[a], &self.full_pos, a);
                }
                continue;
            }
            for a in self.adj_ptr[j]..self.adj_ptr[j + 1] {
                let block = rt_mul(&self.g[a]);
                let pos = self.adj_pos[a];
                for rb in 0..=s {
                    let coef = self.coefficient(rb, pt);
                    for c in 0..3 {
                        for col in 0..3 {
                            jx[pos[col] + rb * 3 + c] += coef * block[c][col];
                        }
                    }
                }
            }
        }
    }

    fn equation_scales(&self) -> Vec<f64> {
        let mut e = self.sys.equation_scales();
        self.rescale(&mut e, true);
        if let Some((_, s)) = self.rod.end_angle() {
            // A torque clamp's moment row m_b3(L) − Λ in Λ's scale, the
            // straight rod's torque per radian C/L (see unknown_scales):
            // twisting the whole rod at fixed M leaves a residual in this
            // row only, and in the moments' √f K_b/L (30× C/L for DNA) that
            // direction was soft (σ_min 0.007 on the 1 kbp scene against
            // 0.034) and hid the buckling points' dips of σ_min.
            e[s] = self.rod.torque_per_radian();
        }
        e
    }

    fn unknown_scales(&self) -> (Vec<f64>, f64) {
        let (mut x, l) = self.sys.unknown_scales();
        self.rescale(&mut x, false);
        // Λ: φ itself (rotation control); the end torque by the straight
        // rod's torque per radian C/L, so that the scaled arc length is ≈ φ
        // on the straight branch under either control and the same steps
        // suit both (with the moment scale √f K_b/L the state's rotation
        // dominated and a step turned the end 7× further); or the rod's own.
        let lambda = if self.twisted_phi.is_some() {
            1.0
        } else if self.rod.torqued() {
            self.rod.torque_per_radian()
        } else {
            l
        };
        (x, lambda)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::charged::dna::DnaScene;

    /// The stability metric's injection is the far pairs' own: for every
    /// stage point and row block, the same first n-row and coefficient as
    /// the residual's pair-force loop ([`ChargedRod::n_row`],
    /// [`ChargedRod::coefficient`]), and R(q_j) of the state, on a
    /// charged 100 bp DNA rod of 6 Gauss(3) elements at a state whose
    /// quaternions are perturbed. Exact equality (same arithmetic).
    #[test]
    fn metric_rows_are_the_far_pairs_rows() {
        let scene = DnaScene { base_pairs: 100, ..Default::default() };
        let rod = scene.rod(6, 3).unwrap();
        let mut x = rod.straight_state();
        for (k, v) in x.iter_mut().enumerate() {
            *v += 0.01 * ((k as f64) * 0.37).cos();
        }
        let problem = ChargedRod::new(&rod, &scene.charge(), None, &x).unwrap();
        let metric = problem.stability_metric(&x).unwrap();
        let s = problem.tab.b.len();
        assert_eq!((metric.points(), metric.rows_per_point, metric.dim), (problem.points.len(), s + 1, problem.n));
        for (j, pt) in problem.points.iter().enumerate() {
            assert_eq!(metric.coords[j], pt.offset);
            let q = [x[pt.offset + 3], x[pt.offset + 4], x[pt.offset + 5], x[pt.offset + 6]];
            assert_eq!(metric.rotations[j], rotation(&q));
            for rb in 0..=s {
                let at = j * (s + 1) + rb;
                assert_eq!(metric.rows[at], problem.n_row(pt.element, rb, 0));
                assert_eq!(metric.coefs[at], problem.coefficient(rb, pt));
            }
        }
        assert!(metric.zero_modes.is_empty());
    }
}

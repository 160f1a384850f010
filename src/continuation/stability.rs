//! The stability of an equilibrium from its Jacobian's factors: the
//! number of negative eigenvalues of the second variation δ²G under the
//! problem's end constraints.
//!
//! A rod's Jacobian R_x is that of a first-order (mixed) boundary-value
//! problem, not a symmetric Hessian: its own eigenvalues depend on how its
//! rows are scaled and mean nothing. The eigenproblem that does is
//! δ²G[v, ·] = σ⟨v, ·⟩_M with the metric M = ∫|δr|² ds. The Euler–Lagrange
//! equation of G − ½σ∫|δr|² is the linearised equilibrium under an extra
//! dead force density σ·δr (a Winkler foundation of stiffness −σ), which
//! the discrete rows take exactly as they take any distributed spatial
//! force p: Σ_j coef·R(q_j)ᵀ p_j added to the n-rows. With that injection
//! M′ (a [`Metric`]),
//!   (R_x + σ M′) v = 0.
//! Eliminating every unknown but the stage positions gives the compliance
//! operator on them,
//!   K = E_r R_x⁻¹ M′,  K δr = θ δr,  θ = −1/σ,
//! E_r the stage positions' rows. So σ < 0 (unstable) ⇔ θ > 0, and σ = ∞
//! (directions the metric does not see: the axial ones of an inextensible
//! rod) is θ = 0, out of the way. K is self-adjoint in the inner product
//! W = diag(h b_j) ⊗ I₃ (the stage quadrature of ∫|δr|²) up to the
//! scheme's non-variational O(h^{2s}).
//!
//! Counting on δr alone is exact: what the elimination removes at fixed r
//! is the twist with α(0) = α(L) = 0, whose energy C∫α′² is positive for
//! the isotropic rods this is built for.

use nalgebra::{DMatrix, SymmetricEigen};

/// The metric's data for one state of a problem (built by the model,
/// [`crate::continuation::Problem::stability_metric`]): where the stage
/// positions sit in x, their quadrature weights, how a dead force density
/// at them enters the rows, and the zero modes of a symmetry the problem
/// breaks by a phase condition.
#[derive(Clone, Debug, PartialEq)]
pub struct Metric {
    /// The problem's unknowns (= equations), the length of x and of M′w.
    pub dim: usize,
    /// Offset in x of each stage point's position r (three entries).
    pub coords: Vec<usize>,
    /// W's weight of each stage point: h_e b_j.
    pub weights: Vec<f64>,
    /// Row blocks each point's force enters (s + 1 for Gauss(s): the
    /// element's s stage rows and its update row).
    pub rows_per_point: usize,
    /// First of the three n-rows of each (point, row block), and its
    /// coefficient (h a_ij for a stage row i, h b_j for the update row).
    pub rows: Vec<usize>,
    pub coefs: Vec<f64>,
    /// R(q_j) at each stage point, as the rows evaluate it (quaternion
    /// not normalised): a spatial force p enters as R(q_j)ᵀ p.
    pub rotations: Vec<[[f64; 3]; 3]>,
    /// Zero modes in the coordinates (three per point), W-orthonormal:
    /// a rotation about the axis, e3 × r_j, when a phase condition fixes
    /// it. The eigen solver works on their W-orthogonal complement.
    pub zero_modes: Vec<Vec<f64>>,
    /// Where in x (and in a solve's result) the unfolding parameter μ of
    /// the phase condition sits, when there is one: the bordered system
    /// [[H, b], [cᵀ, 0]] (b the unfolding column, c the phase row) gives
    /// μ = ℓᵀM′w / ℓᵀb for a force density w, ℓ the left null vector of H.
    /// With H's symmetry ℓ is the zero mode (up to the scheme's
    /// non-variational part), so μ vanishes for w ⊥_W the zero modes:
    /// [`unstable_modes`] checks it.
    pub unfolding: Option<usize>,
    /// The state's own unit of σ (force per length² for a rod): the
    /// largest of K_b/L⁴, F²/K_b and M⁴/K_b³, F and M the end forces and
    /// moments. A straight rod under tension F and torque M has
    /// σ ≥ min_k (K_b k⁴ − M k³ + F k²) ≥ −(27/256)M⁴/K_b³ (its Rayleigh
    /// quotient, Plancherel), and σ of a buckled one are of the same
    /// order; the window of the engines' counts starts at −`scale`
    /// ([`StabilityOptions::floor`]).
    pub scale: f64,
    /// The unit of the neutral band ([`StabilityOptions::marginal`]):
    /// max(K_b/L⁴, F²/K_b), the tension's own scale without the torque's
    /// (a sliding mode's σ scales with the tails' tension, not the twist);
    /// 0 on a state without a localised structure (no neutral band).
    pub neutral_scale: f64,
}

impl Metric {
    /// Stage points.
    pub fn points(&self) -> usize {
        self.coords.len()
    }

    /// Coordinates of K's space: three per stage point.
    pub fn coordinates(&self) -> usize {
        3 * self.coords.len()
    }

    /// `out` = M′w: the spatial force density w (three per point) injected
    /// into the rows, coef·R(q_j)ᵀ w_j in each of the point's n-rows.
    pub fn inject(&self, w: &[f64], out: &mut [f64]) {
        assert_eq!(w.len(), self.coordinates(), "force density of the wrong length");
        assert_eq!(out.len(), self.dim, "rows of the wrong length");
        out.fill(0.0);
        let blocks = self.rows_per_point;
        for (p, (rot, f)) in self.rotations.iter().zip(w.chunks_exact(3)).enumerate() {
            let fb = [0, 1, 2].map(|c| rot[0][c] * f[0] + rot[1][c] * f[1] + rot[2][c] * f[2]);
            for (&row, &coef) in self.rows[p * blocks..(p + 1) * blocks].iter().zip(&self.coefs[p * blocks..]) {
                for c in 0..3 {
                    out[row + c] += coef * fb[c];
                }
            }
        }
    }

    /// `w` = E_r z: the stage positions of a full vector z.
    pub fn gather(&self, z: &[f64], w: &mut [f64]) {
        for (&o, wp) in self.coords.iter().zip(w.chunks_exact_mut(3)) {
            wp.copy_from_slice(&z[o..o + 3]);
        }
    }

    /// ⟨a, b⟩_W = Σ_j h b_j a_j·b_j.
    pub fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        self.weights
            .iter()
            .zip(a.chunks_exact(3).zip(b.chunks_exact(3)))
            .map(|(w, (a, b))| w * (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]))
            .sum()
    }

    /// w minus its W-projection on the zero modes.
    pub fn project(&self, w: &mut [f64]) {
        for z in &self.zero_modes {
            let t = self.dot(z, w);
            for (a, b) in w.iter_mut().zip(z) {
                *a -= t * b;
            }
        }
    }

    /// The zero mode of rotations about e3, δr_j = e3 × r_j at the
    /// points' positions `r`, W-normalised; none when it vanishes to
    /// rounding (r on the axis: a straight rod, where the rotation moves
    /// nothing). `length` sets the scale of that test.
    pub(crate) fn axial_rotation_mode(&self, r: &[[f64; 3]], length: f64) -> Option<Vec<f64>> {
        let mode: Vec<f64> = r.iter().flat_map(|p| [-p[1], p[0], 0.0]).collect();
        let norm = self.dot(&mode, &mode).sqrt();
        // |e3 × r| ~ L over a W-measure ~ L: the norm's scale is L^{3/2}.
        (norm > 1e-14 * length.powf(1.5)).then(|| mode.iter().map(|v| v / norm).collect())
    }
}

/// How [`unstable_modes`] iterates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilityOptions {
    /// Columns iterated together: the window's modes, one beyond it that
    /// closes it, and the guards.
    pub block: usize,
    /// The block's last columns, never used to decide: subspace iteration
    /// converges the i-th Ritz pair at the rate |θ_{block+1}/θ_i| per
    /// solve, so the guards keep the decided ones from converging at the
    /// rate of their neighbours.
    pub guard: usize,
    /// Multi-column solves at most (each is one application of K).
    pub max_iterations: usize,
    /// Converged when, for the window and its closer, the part of Kx
    /// outside the subspace (‖Kx_c − Σ_k x_k G_kc‖_W, G the Ritz matrix in
    /// the Ritz basis) is below `tol`·|θ₁| (θ₁ the largest: σ nearest
    /// zero). The Ritz values are then accurate to ~tol²|θ₁|²/gap.
    pub tol: f64,
    /// The largest unfolding parameter μ a solve may return, relative to
    /// the μ of the (W-normalised) zero mode itself ([`Stability::unfolding`]):
    /// above it the iteration's columns are not ⊥ the symmetry's true zero
    /// mode (a wrong metric, an anisotropic law) and the count is refused.
    /// The level μ sits at on a right zero mode is that of the scheme's
    /// non-variational part (the discrete left null vector is Wv₀ only to
    /// O(h^{2s})), which the Ritz matrix's skew part measures: μ/skew was
    /// 0.5–2 on the Greenhill rods, but up to 2.3e-2 (against a skew of
    /// ~1e-4) on the 1 kbp DNA scene's buckled branch at 170 × Gauss(2),
    /// where a sliding mode is nearly neutral; a zero mode about an axis
    /// 0.05 L off gave 0.29 (and σ₁ 0.4 % off). So the default bound is
    /// 0.1, or 10 × the skew part when that is larger.
    pub unfolding_tol: f64,
    /// [`count_unstable`]: the window's floor σ_floor = −`floor`·scale
    /// ([`Metric::scale`]), lowered to twice the deepest σ counted at the
    /// branch's last point when that is below it.
    pub floor: f64,
    /// Neutral modes: σ with |σ| ≤ `marginal`·neutral_scale
    /// ([`Metric::neutral_scale`]) on a state with a zero mode (off the
    /// straight rod: a localised structure) are counted apart
    /// ([`Stability::marginal`]) and not as unstable. A localised
    /// structure on long tails (a plectoneme, a loop) has modes whose σ
    /// fall toward zero as it localises (its sliding along the tails, at
    /// a cost ∝ e^{−L_tail/ξ}, and others): once they are within what the
    /// model's own approximations decide (a pair list's cutoff, the mesh)
    /// their sign flips from point to point and says nothing of the
    /// physics (physics.md §3.4). Default 0 (every negative σ counts): a scene that knows its neutral
    /// modes sets it ([`crate::charged::dna::SupercoilSettings::stability`]).
    pub marginal: f64,
    /// [`count_unstable`]: the block grows (doubling, warm) up to this
    /// many columns while the window does not close within it.
    pub max_block: usize,
}

impl Default for StabilityOptions {
    fn default() -> Self {
        StabilityOptions {
            block: 12,
            guard: 3,
            max_iterations: 8,
            tol: 1e-6,
            unfolding_tol: 0.1,
            floor: 1.0,
            marginal: 0.0,
            max_block: 96,
        }
    }
}

/// The eigenvectors of K from the last point, the warm start of the next
/// (coordinate space: independent of the problem's other unknowns).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModeBasis {
    /// Coordinates (3 per stage point) of each column; 0: no basis yet.
    pub coordinates: usize,
    /// W-orthonormal Ritz vectors, column-major, by |σ| ascending.
    pub vectors: Vec<f64>,
    /// σ of the last point ([`Stability::sigma`]).
    pub sigma: Vec<f64>,
}

impl ModeBasis {
    /// Columns held.
    pub fn columns(&self) -> usize {
        self.vectors.len().checked_div(self.coordinates).unwrap_or(0)
    }
}

/// What a branch's stability count carries from one point to the next
/// (and through a [`crate::continuation::Resume`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModeCarry {
    /// The last point's Ritz vectors: the next point's warm start.
    pub basis: ModeBasis,
    /// sign det R_x · (−1)^count, the same at every point of a branch
    /// (det R_x changes sign exactly where an eigenvalue σ crosses zero):
    /// taken once from an exact factorisation, then the records' signs
    /// follow from their counts. None until then.
    pub reference_sign: Option<f64>,
    /// The most negative σ counted at the last point (0: none): the next
    /// floor is at most twice it, so that a mode deepening along the
    /// branch is not lost below a fixed floor.
    pub deepest: f64,
}

/// The scratch blocks of [`unstable_modes`], kept between calls (sized on
/// the first, so that the iteration itself does not allocate).
#[derive(Clone, Debug, Default)]
pub struct ModeWork {
    /// M′Q, then A⁻¹M′Q: n × block.
    rows: Vec<f64>,
    /// Q, KQ, the Ritz vectors X = QS and KX = (KQ)S: coordinates × block.
    q: Vec<f64>,
    kq: Vec<f64>,
    x: Vec<f64>,
    kx: Vec<f64>,
    /// Ritz values by |θ| descending, their residuals ‖Kx − θx‖_W.
    theta: Vec<f64>,
    rho: Vec<f64>,
    order: Vec<usize>,
    /// One column's residual.
    res: Vec<f64>,
    /// Each stage point's arclength (the cold start's shapes).
    arclength: Vec<f64>,
}

impl ModeWork {
    pub fn new() -> Self {
        Self::default()
    }

    fn size(&mut self, n: usize, m: usize, b: usize) {
        self.rows.resize(n * b, 0.0);
        for v in [&mut self.q, &mut self.kq, &mut self.x, &mut self.kx] {
            v.resize(m * b, 0.0);
        }
        for v in [&mut self.theta, &mut self.rho] {
            v.resize(b, 0.0);
        }
        self.order.resize(b, 0);
        self.res.resize(m, 0.0);
        self.arclength.resize(m / 3, 0.0);
    }
}

/// The count of unstable modes at one point, or why there is none.
#[derive(Clone, Debug, PartialEq)]
pub struct Stability {
    /// Eigenvalues σ of δ²G with σ_floor ≤ σ < 0 (the window's θ > 0);
    /// None when the count is not certified (no factors, the window not
    /// closed within the block, or a Ritz value too close to the floor's
    /// t = −1/σ_floor for its bound, `certificate`): never a guess.
    pub unstable: Option<usize>,
    /// The certified count of all σ in [σ_floor, 0), the marginal ones
    /// included: det R_x changes sign where any σ crosses zero, so its
    /// sign follows this count's parity.
    pub negative: Option<usize>,
    /// σ of the window with |σ| ≤ `marginal`·scale
    /// ([`StabilityOptions::marginal`]): neutral, in `negative` when below
    /// zero but not in `unstable`.
    pub marginal: usize,
    /// σ = −1/θ of the window's Ritz pairs and of the one closing it (all
    /// decided ones if it did not close), by |σ| ascending (nearest zero
    /// first), in the metric's units (force per length² for a rod with
    /// M = ∫|δr|² ds).
    pub sigma: Vec<f64>,
    /// ‖G − Gᵀ‖_F/‖G‖_F of the last Ritz matrix G = QᵀWKQ: K's departure
    /// from W-self-adjointness on the subspace (the scheme's
    /// non-variational part), which the certification adds to its bound.
    pub skew: f64,
    /// The certificate's bound, dimensionless: the skew coupling across
    /// t and the window's residual, each relative to the Ritz values'
    /// distance from t ([`unstable_modes`]); the count is certified when
    /// it is below 1 (infinite when the window did not close).
    pub certificate: f64,
    /// Applications of K (multi-column solves), and single solves.
    pub iterations: usize,
    pub solves: usize,
    /// With a phase condition: max over the solves' columns q (W-unit,
    /// ⊥_W the zero modes) of |μ(q)|/|μ(v₀)|, v₀ the metric's first zero
    /// mode. μ is a linear functional of the injected force density,
    /// ∝ ⟨v₀, w⟩_W when the zero mode is right ([`Metric::unfolding`]), so
    /// this is the cosine between the columns and the true zero mode as
    /// the rows see it; 0 without a phase condition.
    pub unfolding: f64,
    /// Columns iterated, and whether the window was still open after two
    /// iterations (more σ within the floor than the block decides: the
    /// iteration stopped there, for a larger block to take over).
    pub block: usize,
    pub open: bool,
    /// The window closed and the projection held, but a Ritz value sat
    /// too near the floor's t for the bound (the closer, or one of the
    /// window's): another floor decides it ([`count_unstable`] lowers it).
    pub near_floor: bool,
    /// The floor the count was taken above.
    pub floor: f64,
}

/// Unstable modes of δ²G at a point from its Jacobian's factors: block
/// subspace iteration on the compliance operator K = E_r A⁻¹M′ (module
/// doc), whose eigenvalues θ = −1/σ of largest |θ| are the σ nearest zero
/// — shift-invert at σ = 0 without any factorisation of its own.
///
/// `solve(F, k)` solves A Z = F in place for the k columns of F (n × k,
/// column-major), unrefined — [`crate::linalg::bordered::BorderedLu::solve_inner_many`]
/// on the step's own factors — false if A is singular. `sigma_floor` < 0
/// is a lower bound of the *physical* spectrum (a Rayleigh-quotient bound
/// of the loads: for a twisted rod −27M⁴/(256K_b³)): only σ ∈ [σ_floor, 0)
/// are counted, because once twisted the discrete K also has pairs of
/// tiny positive θ (σ → −∞ as the mesh is refined), the scheme's
/// non-variational part lifting the metric's blind θ = 0 directions
/// (twist, axial) off zero. They sit far below any physical bound; a
/// count over all θ > 0 would count them.
///
/// Each iteration: Q (W-orthonormal, ⊥_W the zero modes) → KQ (inject,
/// one k-column solve, gather, project) → Rayleigh–Ritz in W: G = QᵀWKQ,
/// symmetrised (K is W-self-adjoint up to the skew part reported), its
/// eigenpairs (θ_i, s_i) by |θ| descending, Ritz vectors x_i = Qs_i with
/// Kx_i = (KQ)s_i exactly and residuals ρ_i = ‖Kx_i − Σ_k x_k G_ki‖_W
/// (G = Θ + Ñ in the Ritz basis, Ñ its skew part: what iterating
/// reduces; the skew part is K's own); the next Q is KX orthonormalised.
///
/// Certification. The window is closed by the first Ritz value with
/// |θ_p| < t = −1/σ_floor: every eigenvalue the iteration has not found
/// has |θ| below the block's (the premise of subspace iteration, its
/// start not deficient in them), so all θ ≥ t are among θ_1…θ_{p−1}
/// when |θ_p| plus the window's residual is below t. The Ritz values'
/// classification against t is certified by a bound (`certificate` < 1)
/// on what can move an eigenvalue of K across t: the window's residuals
/// ρ_i (Kahan's theorem — Parlett, *The Symmetric
/// Eigenvalue Problem*, 11.5 — Weinstein's one-vector bound made to hold
/// for clusters such as the straight rod's exact pairs) relative to the
/// nearest distance |θ_i − t|, and the Ritz matrix's skew coupling across
/// t scaled by those distances (derivation at its computation: a skew
/// coupling between modes far from t, or on the same side of it, moves
/// no real part across t). The count is then #{i < p: θ_i ≥ t}: σ in
/// [σ_floor, 0) is θ ≥ t.
///
/// The zero modes. With a phase condition the iteration runs on V₁ =
/// v₀^⊥W (every column projected): there the bordered operator is K of
/// the symmetric problem on V₁, and since v₀ is in δ²G's radical the
/// count on V₁ is the count on the whole space with the zero removed.
/// Without the projection the phase-bordered pencil is a non-symmetric
/// rank-one modification whose eigenvalues may pass through ∞ and change
/// sign. That the projection removed the true zero mode is checked on
/// every solve: the unfolding parameter μ it returns must be ~0
/// ([`Stability::unfolding`] ≤ `unfolding_tol`), else the count is None.
///
/// The start: `basis` (the last point's Ritz vectors) when its size
/// matches, completed by smooth shapes sin(kπs/L)·sin(πs/L) in x and y
/// with a small deterministic all-direction component (no mode exactly
/// missed). On return `basis` holds this point's Ritz vectors.
pub fn unstable_modes(
    mut solve: impl FnMut(&mut [f64], usize) -> bool,
    metric: &Metric,
    sigma_floor: f64,
    basis: &mut ModeBasis,
    work: &mut ModeWork,
    options: &StabilityOptions,
) -> Stability {
    assert!(sigma_floor < 0.0 && sigma_floor.is_finite(), "the floor σ_floor must be negative and finite");
    let StabilityOptions { block: b, guard, max_iterations, tol, unfolding_tol, .. } = *options;
    assert!(b > guard + 1, "a block needs a decided column and one to close the window beside the guards");
    let (n, m) = (metric.dim, metric.coordinates());
    let decided = b - guard;
    let t = -1.0 / sigma_floor;
    work.size(n, m, b);
    let mut stability = Stability {
        unstable: None,
        negative: None,
        marginal: 0,
        sigma: Vec::new(),
        skew: 0.0,
        certificate: f64::INFINITY,
        iterations: 0,
        solves: 0,
        unfolding: 0.0,
        block: b,
        open: false,
        near_floor: false,
        floor: sigma_floor,
    };

    // μ of the zero mode itself: the unit the columns' μ are measured in.
    // One extra single solve a point.
    let mu_of_zero = match (metric.unfolding, metric.zero_modes.first()) {
        (Some(at), Some(v0)) => {
            let rows = &mut work.rows[..n];
            metric.inject(v0, rows);
            stability.solves += 1;
            if !solve(rows, 1) {
                return stability;
            }
            Some((at, rows[at].abs()))
        }
        _ => None,
    };

    // The start, W-orthonormal and ⊥_W the zero modes.
    let warm = if basis.coordinates == m { basis.columns().min(b) } else { 0 };
    work.q[..m * warm].copy_from_slice(&basis.vectors[..m * warm]);
    arclengths(metric, &mut work.arclength);
    for c in warm..b {
        cold_column(metric, &work.arclength, c, &mut work.q[c * m..(c + 1) * m]);
    }
    if !w_orthonormalise(metric, &mut work.q, m, b, &work.arclength) {
        return stability;
    }

    let mut g = DMatrix::<f64>::zeros(b, b);
    let (mut skew, mut ritz_skew, mut g_full) = (g.clone(), g.clone(), g.clone());
    let mut closing = None;
    let mut residual = f64::INFINITY;
    for iteration in 1..=max_iterations {
        // KQ: inject each column, one k-column solve, gather, project.
        for (qc, rc) in work.q.chunks_exact(m).zip(work.rows.chunks_exact_mut(n)) {
            metric.inject(qc, rc);
        }
        stability.iterations = iteration;
        stability.solves += b;
        if !solve(&mut work.rows, b) {
            return stability;
        }
        if let Some((at, unit)) = mu_of_zero {
            let largest = work.rows.chunks_exact(n).fold(0.0f64, |m, rc| m.max(rc[at].abs()));
            stability.unfolding = stability.unfolding.max(largest / unit);
        }
        for (rc, kc) in work.rows.chunks_exact(n).zip(work.kq.chunks_exact_mut(m)) {
            metric.gather(rc, kc);
            metric.project(kc);
        }

        // Rayleigh–Ritz in W: G = QᵀWKQ, its skew part N = (G − Gᵀ)/2
        // kept apart, the symmetric part's eigenpairs by |θ| descending.
        let mut norm2 = 0.0;
        for i in 0..b {
            for j in 0..b {
                g[(i, j)] = metric.dot(&work.q[i * m..(i + 1) * m], &work.kq[j * m..(j + 1) * m]);
                norm2 += g[(i, j)].powi(2);
            }
        }
        for i in 0..b {
            for j in 0..b {
                skew[(i, j)] = 0.5 * (g[(i, j)] - g[(j, i)]);
            }
        }
        stability.skew = 2.0 * skew.norm() / norm2.sqrt();
        g_full.copy_from(&g);
        g -= &skew;
        // The b×b Ritz problem's own small allocations are nalgebra's.
        let eig = SymmetricEigen::new(g.clone());
        for (c, o) in work.order.iter_mut().enumerate() {
            *o = c;
        }
        work.order.sort_by(|&a, &c| eig.eigenvalues[c].abs().total_cmp(&eig.eigenvalues[a].abs()));
        for c in 0..b {
            work.theta[c] = eig.eigenvalues[work.order[c]];
        }
        // Ñ = SᵀNS: the skew part in the Ritz basis (SᵀGS = Θ + Ñ).
        for c in 0..b {
            for d in 0..b {
                let (sc, sd) = (eig.eigenvectors.column(work.order[c]), eig.eigenvectors.column(work.order[d]));
                ritz_skew[(c, d)] = (0..b).map(|k| sc[k] * (0..b).map(|l| skew[(k, l)] * sd[l]).sum::<f64>()).sum();
            }
        }
        // Ritz vectors X = QS and KX = (KQ)S.
        for c in 0..b {
            let e = work.order[c];
            let (xc, kxc) = (&mut work.x[c * m..(c + 1) * m], &mut work.kx[c * m..(c + 1) * m]);
            xc.fill(0.0);
            kxc.fill(0.0);
            for k in 0..b {
                let sk = eig.eigenvectors[(k, e)];
                for ((xv, kv), (qv, yv)) in
                    xc.iter_mut().zip(kxc.iter_mut()).zip(work.q[k * m..].iter().zip(&work.kq[k * m..]))
                {
                    *xv += sk * qv;
                    *kv += sk * yv;
                }
            }
        }

        // The window and its convergence: the part of Kx_c outside the
        // subspace, R_c = Kx_c − Σ_k x_k (Θ + Ñ)_kc (W-orthogonal to Q,
        // as KQ − QG is), is what iterating reduces; the skew part Ñ is
        // K's own and is not.
        closing = work.theta[..decided].iter().position(|th| th.abs() < t);
        let Some(p) = closing else {
            stability.certificate = f64::INFINITY;
            // Ritz values of largest |θ| grow toward the eigenvalues as
            // the iteration goes on: a window still open after two
            // iterations stays open, and a larger block must decide it.
            if iteration == max_iterations || iteration >= 2 {
                stability.open = true;
                break;
            }
            // The next subspace: KX (Ritz order kept for the warm start).
            std::mem::swap(&mut work.q, &mut work.kx);
            if !w_orthonormalise(metric, &mut work.q, m, b, &work.arclength) {
                return stability;
            }
            continue;
        };
        for c in 0..=p {
            work.res.copy_from_slice(&work.kx[c * m..(c + 1) * m]);
            for k in 0..b {
                let coef = ritz_skew[(k, c)] + if k == c { work.theta[c] } else { 0.0 };
                work.res.iter_mut().zip(&work.x[k * m..(k + 1) * m]).for_each(|(r, x)| *r -= coef * x);
            }
            work.rho[c] = metric.dot(&work.res, &work.res).sqrt();
        }
        let converged = work.rho[..=p].iter().all(|r| *r <= tol * work.theta[0].abs());

        // The certificate (dimensionless, < 1 certifies). In the Ritz
        // basis G = Θ + Ñ. Only the skew coupling N_o *across* t can move
        // an eigenvalue's real part across t: with Δ = |Θ − t|,
        //   Θ − t − iy + Ñ = Δ^½ (J − iyΔ⁻¹ + Δ^-½ÑΔ^-½) Δ^½,  J = sign(Θ − t),
        // and the within-side part J − iyΔ⁻¹ + Δ^-½N_dΔ^-½ has Hermitian
        // part ±I on each side, so its inverse has norm ≤ 1: no eigenvalue
        // of G has real part t while ‖Δ^-½N_oΔ^-½‖₂ < 1 (along the whole
        // homotopy Θ + τÑ, so the count above t is Θ's). Far-apart
        // couplings weigh little, as they move eigenvalues at second order
        // only. The residual R of the window's columns adds ‖R‖_F/min Δ
        // (Kahan: its Ritz values are that close to eigenvalues of K).
        let mut across = 0.0;
        for c in 0..b {
            for k in 0..b {
                if (work.theta[k] >= t) != (work.theta[c] >= t) {
                    across += ritz_skew[(k, c)].powi(2) / ((work.theta[k] - t).abs() * (work.theta[c] - t).abs());
                }
            }
        }
        residual = work.rho[..=p].iter().map(|r| r * r).sum::<f64>().sqrt();
        let nearest = work.theta[..=p].iter().fold(f64::INFINITY, |d, th| d.min((th - t).abs()));
        stability.certificate = across.sqrt() + residual / nearest;
        if converged || iteration == max_iterations {
            break;
        }
        std::mem::swap(&mut work.q, &mut work.kx);
        if !w_orthonormalise(metric, &mut work.q, m, b, &work.arclength) {
            return stability;
        }
    }

    // The window's σ and the one closing it (the σ nearest zero even when
    // the window is empty).
    // They are reported from the eigenvalues of G itself, K's on the
    // subspace; the symmetrised θ differ from them by O(‖Ñ‖²/gap) and
    // serve the certificate only. A complex pair (the skew part large
    // against a pair's splitting) gives Re(−1/λ).
    let window = closing.map_or(decided, |p| p + 1);
    let mut lambda: Vec<_> = g_full.complex_eigenvalues().iter().copied().collect();
    lambda.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    stability.sigma = lambda[..window].iter().map(|l| -l.inv().re).collect();
    basis.coordinates = m;
    basis.vectors.clear();
    basis.vectors.extend_from_slice(&work.x);
    basis.sigma.clone_from(&stability.sigma);
    // Certified: every Ritz value of the window (and the closer) at least
    // the bound from t, and the closer's |θ| below t by the bound, so that
    // what the subspace has not found (|θ| below the block's) is below t
    // too. Unstable modes are then the θ ≥ t: σ_floor ≤ σ < 0.
    // A solve that moved μ means the projection did not remove the
    // symmetry's zero mode: the operator iterated is not the symmetric
    // one on V₁ = v₀^⊥ and its count is not certified (NaN refuses too).
    let unfolded = !(stability.unfolding <= unfolding_tol.max(10.0 * stability.skew));
    if let (Some(p), false) = (closing, unfolded) {
        stability.near_floor = !(stability.certificate < 1.0 && work.theta[p].abs() + residual < t);
        if !stability.near_floor {
            let negative = work.theta[..p].iter().filter(|&&th| th >= t).count();
            // The neutral ones, by the reported σ (the window's, nearest
            // zero first).
            let localised = !metric.zero_modes.is_empty();
            let level = if localised { options.marginal * metric.neutral_scale } else { 0.0 };
            let marginal = stability.sigma.iter().filter(|s| s.abs() <= level);
            let neutral_negative = marginal.clone().filter(|s| **s < 0.0).count();
            stability.marginal = marginal.count();
            stability.negative = Some(negative);
            stability.unstable = Some(negative.saturating_sub(neutral_negative));
        }
    }
    stability
}

/// The count of [`unstable_modes`] with the block sized to the window:
/// started at the basis' size (the last point's, at least
/// `options.block`), doubled (warm: the Ritz vectors found so far kept)
/// while the window stays open, up to `options.max_block`; a count is
/// None when even that does not close it. The solves of every attempt are
/// counted in the result. A window that closes too near the floor for its
/// bound is taken again with the floor twice as low (twice at most).
pub fn count_unstable(
    mut solve: impl FnMut(&mut [f64], usize) -> bool,
    metric: &Metric,
    sigma_floor: f64,
    basis: &mut ModeBasis,
    work: &mut ModeWork,
    options: &StabilityOptions,
) -> Stability {
    // The last point's window and closer, with guards and spares: the
    // block it needed, or less when its window narrowed.
    let warm = if basis.coordinates == metric.coordinates() { basis.sigma.len() + options.guard + 2 } else { 0 };
    let mut block = warm.clamp(options.block, options.max_block.max(options.block));
    let (mut solves, mut iterations, mut floor, mut lowered) = (0, 0, sigma_floor, 0);
    loop {
        let opts = StabilityOptions { block, ..*options };
        let mut s = unstable_modes(&mut solve, metric, floor, basis, work, &opts);
        solves += s.solves;
        iterations += s.iterations;
        let next = (2 * block).min(options.max_block);
        // A window that closed too near its floor: any floor below the
        // physical spectrum counts the same, so the floor is lowered
        // (twice at most; the block grows with it when it must).
        if s.near_floor && lowered < 2 {
            floor *= 2.0;
            lowered += 1;
            continue;
        }
        if !s.open || next <= block {
            (s.solves, s.iterations) = (solves, iterations);
            return s;
        }
        block = next;
    }
}

/// The arclength of each stage point, from the weights (the stage
/// quadrature's h_e b_j): the cumulative weight to the point's middle.
fn arclengths(metric: &Metric, out: &mut [f64]) {
    let mut s = 0.0;
    for (w, at) in metric.weights.iter().zip(out) {
        *at = s + 0.5 * w;
        s += w;
    }
}

/// Cold start column c: sin(kπs/L)·sin(πs/L), k = c/2 + 1, in x (c even)
/// or y (odd) — the clamped rod's bending shapes, roughly — plus a small
/// deterministic component in every direction, so that no mode is
/// exactly orthogonal to the start.
fn cold_column(metric: &Metric, arclength: &[f64], c: usize, out: &mut [f64]) {
    let length = metric.weights.iter().sum::<f64>();
    let k = (c / 2 + 1) as f64;
    let mut seed = 0x9e37_79b9_7f4a_7c15u64 ^ (c as u64).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    for (s, p) in arclength.iter().zip(out.chunks_exact_mut(3)) {
        let u = std::f64::consts::PI * s / length;
        let shape = (k * u).sin() * u.sin();
        for (d, v) in p.iter_mut().enumerate() {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            let noise = ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5;
            *v = if d == c % 2 { shape } else { 0.0 } + 0.05 * noise;
        }
    }
}

/// Modified Gram–Schmidt in W, twice (the second pass restores the
/// orthogonality the first loses to rounding when KQ's columns are
/// nearly parallel: they all lean toward the dominant mode), each column
/// first projected ⊥_W the zero modes. A column that collapses (its
/// norm falls by 1e-10: dependent on the others) is replaced by a cold
/// one of a fresh index; false if b columns cannot be found that way (the
/// space is smaller than the block).
fn w_orthonormalise(metric: &Metric, q: &mut [f64], m: usize, b: usize, arclength: &[f64]) -> bool {
    let mut fresh = b;
    let mut c = 0;
    while c < b {
        let (done, rest) = q.split_at_mut(c * m);
        let col = &mut rest[..m];
        metric.project(col);
        let before = metric.dot(col, col).sqrt();
        for _ in 0..2 {
            for prev in done.chunks_exact(m) {
                let d = metric.dot(prev, col);
                col.iter_mut().zip(prev).for_each(|(a, p)| *a -= d * p);
            }
        }
        let norm = metric.dot(col, col).sqrt();
        if !(norm > 1e-10 * before && norm.is_finite()) {
            if fresh >= 4 * b {
                return false;
            }
            cold_column(metric, arclength, fresh, col);
            fresh += 1;
            continue;
        }
        col.iter_mut().for_each(|a| *a /= norm);
        c += 1;
    }
    true
}

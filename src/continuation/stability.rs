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

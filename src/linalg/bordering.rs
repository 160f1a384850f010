//! Solves with a bordered matrix B = [[A, c], [rᵀ, d]] by block
//! elimination on A's own LU, refined against B: the way B is factorised
//! for Newton corrections when A's pattern calls for supernodal factors
//! (a charged rod's plectoneme, [`super::LuKind`]).
//!
//! Why not the supernodal LU of B itself: faer's supernodal structure is
//! that of the Cholesky factor of BᵀB, which one dense row — the tangent
//! border rᵀ — makes dense (the 1 kbp plectoneme's bordered Jacobian
//! became a 3916² dense LU, seconds per factorisation). A alone keeps its
//! band-like structure.
//!
//! Block elimination (Keller's bordering algorithm): with y = A⁻¹c and the
//! Schur scalar s = d − rᵀy, B z = f is z_n = (f_n − rᵀA⁻¹f₁)/s,
//! z₁ = A⁻¹f₁ − y z_n. A is singular at the folds of a branch where B is
//! regular, so near a fold the plain algorithm loses digits; Govaerts and
//! Pryce (BIT 30, 1990) show that block elimination followed by iterative
//! refinement on B's residual is backward stable unless A is singular to
//! working precision. Every solve is therefore refined against B until its
//! residual is at rounding level (‖f − Bz‖∞ ≤ 1e-13 (‖B‖∞‖z‖∞ + ‖f‖∞)),
//! at most [`MAX_REFINEMENTS`] times; a solve that does not get there is
//! reported, and [`super::bordered::BorderedLu`] then factorises B itself
//! (simplicial) and solves with that — never a less accurate answer.

use super::dense::dot;
use super::sparse::{norms, refine, Pattern, SparseLu};
use crate::error::{Error, Result};
use crate::status::Status;

/// Refinement steps a solve may take before B's own LU is called for.
pub const MAX_REFINEMENTS: usize = 3;

/// Relative residual a refined solve must reach.
const RESIDUAL_TOL: f64 = 1e-13;

pub(super) struct BlockElimination {
    n: usize,
    /// A's LU (its own column order and kind).
    pub(super) a: SparseLu,
    c: Vec<f64>,
    r: Vec<f64>,
    d: f64,
    /// A⁻¹c, A⁻ᵀr (on the first transposed solve), s = d − rᵀA⁻¹c.
    y: Vec<f64>,
    w: Vec<f64>,
    w_known: bool,
    schur: f64,
    /// ‖B‖∞ of the factorised matrix.
    norm: f64,
    /// Scratch: the right-hand side, the residual (the correction).
    f: Vec<f64>,
    res: Vec<f64>,
}

impl BlockElimination {
    /// For A with `pattern` (its last `trailing` unknowns reaching across
    /// it).
    pub(super) fn new(pattern: Pattern, trailing: usize) -> Result<Self> {
        let n = pattern.n;
        Ok(BlockElimination {
            n,
            a: {
                let mut a = SparseLu::with_trailing(pattern, trailing)?;
                a.allow_supernodal();
                a
            },
            c: vec![0.0; n],
            r: vec![0.0; n],
            d: 0.0,
            y: vec![0.0; n],
            w: vec![0.0; n],
            w_known: false,
            schur: 0.0,
            norm: 0.0,
            f: vec![0.0; n + 1],
            res: vec![0.0; n + 1],
        })
    }

    /// Prepare the border on A's factorisation (done on `self.a` by the
    /// caller); B's entries are `values` in `pattern` (for ‖B‖∞).
    /// ErrNotConverged when the Schur scalar is zero or not finite (B may
    /// still be regular: the caller then factorises B).
    pub(super) fn border(&mut self, c: &[f64], r: &[f64], d: f64, pattern: &Pattern, values: &[f64]) -> Result<()> {
        self.c.copy_from_slice(c);
        self.r.copy_from_slice(r);
        self.d = d;
        // ‖B‖∞ (its row sums in the residual's scratch).
        self.norm = norms(pattern, values, &mut self.res).0;
        self.y.copy_from_slice(c);
        self.a.solve(&mut self.y);
        self.w_known = false;
        self.schur = d - dot(r, &self.y);
        if !(self.schur.is_finite() && self.schur != 0.0) {
            return Err(Error::new(
                Status::ErrNotConverged,
                format!("bordered LU: Schur complement {:e} of the border", self.schur),
            ));
        }
        Ok(())
    }

    /// Solve B z = rhs (or Bᵀ z = rhs) in place, refined against B, whose
    /// entries are `values` in `pattern` (B's). Err when the refinement
    /// does not reach rounding level: rhs is then restored.
    pub(super) fn solve(&mut self, pattern: &Pattern, values: &[f64], rhs: &mut [f64], transpose: bool) -> Result<()> {
        if transpose && !self.w_known {
            self.w.copy_from_slice(&self.r);
            self.a.solve_transpose(&mut self.w);
            self.w_known = true;
        }
        self.f.copy_from_slice(rhs);
        self.block(rhs, transpose);
        let (f, mut res) = (std::mem::take(&mut self.f), std::mem::take(&mut self.res));
        let bound = (self.norm, RESIDUAL_TOL, MAX_REFINEMENTS);
        let refined = refine((pattern, values, transpose), bound, &f, rhs, &mut res, |d| self.block(d, transpose));
        if !refined {
            rhs.copy_from_slice(&f);
        }
        (self.f, self.res) = (f, res);
        if refined {
            Ok(())
        } else {
            Err(Error::new(Status::ErrNotConverged, "bordered LU: block elimination did not refine to rounding level"))
        }
    }

    /// One block-elimination solve in place (no refinement).
    fn block(&mut self, v: &mut [f64], transpose: bool) {
        let n = self.n;
        let last = v[n];
        let (head, _) = v.split_at_mut(n);
        let (other, col) = if transpose {
            self.a.solve_transpose(head);
            (&self.c, &self.w)
        } else {
            self.a.solve(head);
            (&self.r, &self.y)
        };
        let zn = (last - dot(other, head)) / self.schur;
        for (z, y) in head.iter_mut().zip(col) {
            *z -= y * zn;
        }
        v[n] = zn;
    }
}

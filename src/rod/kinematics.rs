//! The special Cosserat rod's equations in quaternion form (physics.md
//! §2.1), written once, generic over [`Scalar`] so the same code gives
//! values, Jacobians and Taylor series (see [`crate::taylor`]):
//!
//!   r'   = R(q) v                  (cubic)
//!   q'   = ½ q ∘ (0, u)            (quadratic; |q| is a first integral)
//!   n_b' = −u × n_b − f_b
//!   m_b' = −u × m_b − v × n_b − l_b
//!
//! with body-frame force and moment and the linear law
//! [u; v] = [û; v̂] + K⁻¹[m_b; n_b]. R(q) is the homogeneous quadratic form
//! (q0² + q1² − q2² − q3², …), equal to the rotation matrix on |q| = 1.
//! Kirchhoff rods: v ≡ v̂ = e3, u = û + K_bt⁻¹ m_b, n_b a reaction.

use crate::taylor::{Coefficient, Scalar};
use std::ops::Mul;

pub type V3<T> = [T; 3];

pub fn cross<T: Scalar>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// R(q) (row-major), quadratic in q.
pub fn rotation<T: Scalar>(q: &[T; 4]) -> [[T; 3]; 3] {
    let [q0, q1, q2, q3] = *q;
    let (q00, q11, q22, q33) = (q0 * q0, q1 * q1, q2 * q2, q3 * q3);
    let (q01, q02, q03, q12, q13, q23) = (q0 * q1, q0 * q2, q0 * q3, q1 * q2, q1 * q3, q2 * q3);
    [
        [q00 + q11 - q22 - q33, (q12 - q03) * 2.0, (q13 + q02) * 2.0],
        [(q12 + q03) * 2.0, q00 - q11 + q22 - q33, (q23 - q01) * 2.0],
        [(q13 - q02) * 2.0, (q23 + q01) * 2.0, q00 - q11 - q22 + q33],
    ]
}

pub fn mat_vec<T: Scalar>(r: &[[T; 3]; 3], v: &V3<T>) -> V3<T> {
    [
        r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
        r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
        r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
    ]
}

pub fn mat_t_vec<T: Scalar>(r: &[[T; 3]; 3], v: &V3<T>) -> V3<T> {
    [
        r[0][0] * v[0] + r[1][0] * v[1] + r[2][0] * v[2],
        r[0][1] * v[0] + r[1][1] * v[1] + r[2][1] * v[2],
        r[0][2] * v[0] + r[1][2] * v[1] + r[2][2] * v[2],
    ]
}

/// R(q)ᵀ w for a constant w (a dead load in body components), cubic with Λ.
pub fn to_body<T: Scalar>(q: &[T; 4], w: &[f64; 3]) -> V3<T> {
    let r = rotation(q);
    [
        r[0][0] * w[0] + r[1][0] * w[1] + r[2][0] * w[2],
        r[0][1] * w[0] + r[1][1] * w[1] + r[2][1] * w[2],
        r[0][2] * w[0] + r[1][2] * w[1] + r[2][2] * w[2],
    ]
}

/// Hamilton product a ∘ b.
pub fn quat_mul<T: Scalar>(a: &[T; 4], b: &[T; 4]) -> [T; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// q ∘ (0, u) without the zero terms.
pub fn quat_mul_pure<T: Scalar>(q: &[T; 4], u: &V3<T>) -> [T; 4] {
    [
        -(q[1] * u[0] + q[2] * u[1] + q[3] * u[2]),
        q[0] * u[0] + q[2] * u[2] - q[3] * u[1],
        q[0] * u[1] - q[1] * u[2] + q[3] * u[0],
        q[0] * u[2] + q[1] * u[1] - q[2] * u[0],
    ]
}

/// The constant data of the right-hand side. The compliance is one
/// number per entry (`C = f64`), or one per lane of a batch of elements
/// whose laws differ (`C = Lanes`: a charged rod's elements, each
/// stiffened by its own near zone; [`crate::rod::compiled`]).
#[derive(Clone, Debug, PartialEq)]
pub struct RhsData<C = f64> {
    /// Compliance K⁻¹ (6×6, row-major, order (u, v) ↔ (m, n)); for a
    /// Kirchhoff rod only the (u, m) block is used.
    pub compliance: [[C; 6]; 6],
    pub intrinsic_u: [f64; 3],
    pub intrinsic_v: [f64; 3],
    pub kirchhoff: bool,
    /// Distributed force and couple per length, scaled by Λ: (dead?, vector).
    pub force: Option<(bool, [f64; 3])>,
    pub couple: Option<(bool, [f64; 3])>,
}

/// Strains (u, v) from (m_b, n_b).
pub fn strains<T: Scalar + Mul<C, Output = T>, C: Coefficient>(d: &RhsData<C>, m: &V3<T>, n: &V3<T>) -> (V3<T>, V3<T>) {
    let c = &d.compliance;
    // Zero compliance entries are skipped: the tape (and the Jacobian's
    // pattern) then only holds the couplings the law has.
    let src = [m[0], m[1], m[2], n[0], n[1], n[2]];
    let lin = |row: usize| -> Option<T> {
        let mut acc: Option<T> = None;
        for (k, s) in src.iter().enumerate().take(if d.kirchhoff { 3 } else { 6 }) {
            if !c[row][k].is_zero() {
                let term = *s * c[row][k];
                acc = Some(acc.map_or(term, |a| a + term));
            }
        }
        acc
    };
    let with = |row: usize, hat: f64| lin(row).map_or(T::constant(hat), |a| a + hat);
    let u = [with(0, d.intrinsic_u[0]), with(1, d.intrinsic_u[1]), with(2, d.intrinsic_u[2])];
    let v = if d.kirchhoff {
        [T::constant(d.intrinsic_v[0]), T::constant(d.intrinsic_v[1]), T::constant(d.intrinsic_v[2])]
    } else {
        [with(3, d.intrinsic_v[0]), with(4, d.intrinsic_v[1]), with(5, d.intrinsic_v[2])]
    };
    (u, v)
}

/// y' = f(y, Λ) + μ B(y): the unfolding that goes with a phase condition
/// for rods with rotational symmetry about e3 (equal bending stiffnesses,
/// in-plane isotropic shear and couplings, loads along e3; physics.md §2.4
/// "Symmetry"). For such rods
///   J(y) = e3·(r × R n_b + R m_b) − m_b3
/// (the axial moment about the origin minus the body twisting moment: the
/// Noether quantity of rotating space about e3 while counter-rotating the
/// section labels, which keeps a clamp q(0) = 1) is a first integral of f:
/// ∇J·f ≡ 0 for every y. With B = ∂J/∂m_b = Rᵀe3 − e3 added to the moment
/// equation, dJ/ds = μ|Rᵀe3 − e3|² along a solution; the boundary
/// conditions give J(0) = J(L) = 0 (clamped or pinned base, free or pinned
/// tip under an axial load), so μ∫|Rᵀe3 − e3|² = 0: μ = 0 on any tilted
/// solution, up to the scheme's (small) violation of the cubic invariant J.
/// B is quadratic in q, so μB keeps the system cubic. (The symmetry
/// generator itself would not do: it is W-orthogonal to the adjoint null
/// vector, and μ would stay undetermined.)
pub fn rhs_unfolded<T: Scalar + Mul<C, Output = T>, C: Coefficient>(
    d: &RhsData<C>,
    y: &[T],
    lambda: T,
    mu: T,
) -> [T; 13] {
    let mut f = rhs(d, y, lambda);
    let b = unfolding_direction(&[y[3], y[4], y[5], y[6]]);
    f[10] = f[10] + mu * b[0];
    f[11] = f[11] + mu * b[1];
    f[12] = f[12] + mu * b[2];
    f
}

/// B(q) = R(q)ᵀe3 − e3, the unfolding's direction in the moment equation
/// ([`rhs_unfolded`]): the section's tilt from the axis, zero on a straight
/// state.
pub fn unfolding_direction<T: Scalar>(q: &[T; 4]) -> [T; 3] {
    let r = rotation(q);
    [r[2][0], r[2][1], r[2][2] - 1.0]
}

/// y' = f(y, Λ), y = (r, q, n_b, m_b).
pub fn rhs<T: Scalar + Mul<C, Output = T>, C: Coefficient>(d: &RhsData<C>, y: &[T], lambda: T) -> [T; 13] {
    let q = [y[3], y[4], y[5], y[6]];
    let n = [y[7], y[8], y[9]];
    let m = [y[10], y[11], y[12]];
    let (u, v) = strains(d, &m, &n);
    let rot = rotation(&q);
    let dr = mat_vec(&rot, &v);
    let dq = quat_mul_pure(&q, &u);
    let load = |spec: &Option<(bool, [f64; 3])>| -> Option<V3<T>> {
        spec.map(|(dead, w)| {
            let body = if dead { to_body(&q, &w) } else { [T::constant(w[0]), T::constant(w[1]), T::constant(w[2])] };
            [body[0] * lambda, body[1] * lambda, body[2] * lambda]
        })
    };
    let un = cross(&u, &n);
    let um = cross(&u, &m);
    let vn = cross(&v, &n);
    let f = load(&d.force);
    let l = load(&d.couple);
    let mut out = [dr[0]; 13];
    for i in 0..3 {
        out[i] = dr[i];
        out[7 + i] = -un[i];
        out[10 + i] = -um[i] - vn[i];
        if let Some(f) = &f {
            out[7 + i] = out[7 + i] - f[i];
        }
        if let Some(l) = &l {
            out[10 + i] = out[10 + i] - l[i];
        }
    }
    for i in 0..4 {
        out[3 + i] = dq[i] * 0.5;
    }
    out
}

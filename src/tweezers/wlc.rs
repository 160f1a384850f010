//! The extended phase: a stretched, twisted worm-like chain (doc/physics.md
//! §3.7.1).
//!
//! **Force–extension, numerically exact.** The free energy per length of an
//! inextensible WLC of bending modulus K_b at temperature kT under a force F
//! is −g(F) with g = kT·Λ(F), Λ the largest eigenvalue of the transfer
//! operator of the tangent's random walk on the sphere,
//!
//!   Λ ψ = (1/2A) ∇²ψ + (F/kT) cos θ ψ,   A = K_b/kT,                      (1)
//!
//! (J. F. Marko & E. D. Siggia, Macromolecules 28, 8759 (1995), eq. 9;
//! C. Bouchiat et al., Biophys. J. 76, 409 (1999)). In the Legendre basis
//! P_l(cos θ) (m = 0: the ground state is axisymmetric) A·(1) is the
//! symmetric tridiagonal matrix
//!
//!   H_ll = −l(l+1)/2,   H_l,l+1 = f (l+1)/√((2l+1)(2l+3)),   f = F A/kT,   (2)
//!
//! whose largest eigenvalue μ(f) gives g = (kT/A) μ and the relative
//! extension ζ = dg/dF = dμ/df = ⟨cos θ⟩ by Hellmann–Feynman (the ground
//! state's expectation of the off-diagonal part over f). The basis is
//! truncated where doubling it changes μ by less than 1e-14 (the ground
//! state's width in l grows like f^{1/4}). Large-f limit: μ = f − √f + ¼ + …,
//! i.e. g = F − √(kT F/A) and ζ = 1 − ½√(kT/(A F)) (the spec's forms); at
//! kT = 0 exactly g = F, ζ = 1.
//!
//! **Twist softened by bending fluctuations** (Moroz & Nelson, PNAS 94,
//! 14418 (1997); Phys. Rev. Lett. 80, 2749 (1998)): to leading order in
//! √(kT/(A F)),
//!
//!   C_s(F) = K_t [1 − (K_t/4K_b) · kT/√(K_b F)]                          (3)
//!
//! (K_t/kT = C the twist persistence: the spec's C[1 − (C/4A)√(kT/(AF))]).
//! (3) is an expansion: it is used where its correction is ≤ ½, i.e. F ≥
//! (K_t kT/(2K_b))²/K_b (0.06 pN for A = 50, C = 100 nm), and refused below.
//! Its force dependence also shortens a twisted chain: z = −∂G/∂F gains
//! −½ C_s'(F) ω² per length.
//!
//! **Twist–stretch coupling** (optional; J. F. Marko, Europhys. Lett. 38,
//! 183 (1997); J. Gore et al., Nature 442, 836 (2006)): with stretch modulus
//! S and coupling g_ts the extended phase's energy per length
//! ½Sε² + g_ts εω + ½C_s ω² − Fε, minimised over the strain ε, is
//! −F²/2S + (g_ts F/S) ω + ½(C_s − g_ts²/S) ω². The linear term only moves
//! the torque-free twist (the turns are counted from it, as tweezers count
//! them from the torque-free state at each force), so the phase is a chain
//! of twist modulus C_s − g_ts²/S whose extension per length gains F/S and
//! −(g_ts/S) ω. Twist–bend coupling is not included.

use crate::error::{Error, Result};
use crate::status::Status;

/// The WLC's free energy and extension at one force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceExtension {
    /// g(F) (pN): minus the free energy per length, relative to the
    /// unstretched random coil's reference (the free energy of (1)).
    pub g: f64,
    /// ζ = dg/dF: the mean extension per length (inextensible chain).
    pub zeta: f64,
    /// Legendre modes used.
    pub modes: usize,
}

/// The largest eigenvalue of (2) on `n` modes and its f-derivative
/// (Hellmann–Feynman: vᵀ(∂H/∂f)v for the unit eigenvector v).
fn ground_state(f: f64, n: usize, v: &mut Vec<f64>) -> (f64, f64) {
    let diag = |l: usize| -((l * (l + 1)) as f64) / 2.0;
    let off = |l: usize| (l + 1) as f64 / (((2 * l + 1) * (2 * l + 3)) as f64).sqrt();
    // Sturm count of eigenvalues below x (LDLᵀ pivots of H − x).
    let below = |x: f64| -> usize {
        let mut count = 0;
        let mut d = diag(0) - x;
        if d < 0.0 {
            count += 1;
        }
        for l in 1..n {
            let e = f * off(l - 1);
            let dd = if d == 0.0 { 1e-300 } else { d };
            d = diag(l) - x - e * e / dd;
            if d < 0.0 {
                count += 1;
            }
        }
        count
    };
    // Gershgorin bounds; the largest eigenvalue is the n-th.
    let mut hi = f + 1.0;
    let mut lo = diag(n - 1) - 2.0 * f - 1.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if below(mid) >= n {
            hi = mid;
        } else {
            lo = mid;
        }
        if hi - lo <= 1e-15 * hi.abs().max(1.0) {
            break;
        }
    }
    let mu = hi;
    // Eigenvector by the three-term recurrence from the top-left corner
    // (stable for the largest eigenvalue: (μ − H_ll) grows with l, so the
    // components decay), normalised.
    v.clear();
    v.resize(n, 0.0);
    if f == 0.0 {
        v[0] = 1.0;
        return (0.0, 0.0);
    }
    // Solve from the bottom up (backward recurrence is the stable
    // direction for the decaying ground state): ratios r_l = v_l / v_{l−1}.
    let mut ratios = vec![0.0; n];
    let mut r = 0.0;
    for l in (1..n).rev() {
        // (H_ll − μ) v_l + e_{l−1} v_{l−1} + e_l v_{l+1} = 0.
        let e_prev = f * off(l - 1);
        let e_next = if l + 1 < n { f * off(l) } else { 0.0 };
        let denom = mu - diag(l) - e_next * r;
        r = e_prev / denom;
        ratios[l] = r;
    }
    v[0] = 1.0;
    for l in 1..n {
        v[l] = v[l - 1] * ratios[l];
    }
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    for x in v.iter_mut() {
        *x /= norm;
    }
    let mut dmu = 0.0;
    for l in 0..n - 1 {
        dmu += 2.0 * v[l] * v[l + 1] * off(l);
    }
    (mu, dmu)
}

/// g(F) and ζ(F) of the inextensible WLC (1)–(2): bending modulus `kb`
/// (pN nm²), temperature `kt` (pN nm, 0: the zero-temperature rod, g = F),
/// force `force` (pN, > 0).
pub fn force_extension(kb: f64, kt: f64, force: f64) -> Result<ForceExtension> {
    if !(force > 0.0 && force.is_finite() && kb > 0.0 && kb.is_finite() && kt >= 0.0 && kt.is_finite()) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!("WLC: force ({force:e} pN), K_b ({kb:e}) must be positive and kT ({kt:e}) ≥ 0"),
        ));
    }
    if kt == 0.0 {
        return Ok(ForceExtension { g: force, zeta: 1.0, modes: 0 });
    }
    let a = kb / kt;
    let f = force * a / kt;
    if f > 1e12 {
        // μ = f − √f + ¼ + O(f^{-1/2}) (measured on the basis: the
        // constant is 0.2500016 at f = 1e8), exact to rounding here.
        let s = f.sqrt();
        let mu = f - s + 0.25;
        return Ok(ForceExtension { g: kt / a * mu, zeta: 1.0 - 0.5 / s, modes: 0 });
    }
    let mut v = Vec::new();
    let mut n = 16 + (4.0 * f.powf(0.25)) as usize;
    let (mut mu, mut dmu) = ground_state(f, n, &mut v);
    loop {
        let m = 2 * n;
        let (mu2, dmu2) = ground_state(f, m, &mut v);
        let converged = (mu2 - mu).abs() <= 1e-14 * mu2.abs().max(1.0) && (dmu2 - dmu).abs() <= 1e-13;
        mu = mu2;
        dmu = dmu2;
        n = m;
        if converged || n > 4096 {
            break;
        }
    }
    if !(mu.is_finite() && dmu.is_finite()) {
        return Err(Error::new(Status::ErrNonFiniteResult, "WLC ground state is not finite"));
    }
    Ok(ForceExtension { g: kt / a * mu, zeta: dmu, modes: n })
}

/// The relative extension of J. F. Marko & E. D. Siggia's interpolation
/// formula, F A/kT = ζ + 1/(4(1 − ζ)²) − ¼ (Macromolecules 28, 8759
/// (1995), eq. 7), solved for ζ: an independent approximation (within 10 %
/// of (1)) the tests compare with.
pub fn marko_siggia_zeta(kb: f64, kt: f64, force: f64) -> f64 {
    let target = force * kb / (kt * kt);
    let h = |z: f64| z + 0.25 / ((1.0 - z) * (1.0 - z)) - 0.25 - target;
    crate::roots::bracketed_root(h, 0.0, 1.0 - 1e-12, h(0.0), h(1.0 - 1e-12))
}

/// Moroz–Nelson's softened twist modulus (3), pN nm², with the range check.
pub fn moroz_nelson(kt_mod: f64, kb: f64, kt: f64, force: f64) -> Result<f64> {
    if kt == 0.0 {
        return Ok(kt_mod);
    }
    let correction = kt_mod / (4.0 * kb) * kt / (kb * force).sqrt();
    if correction > 0.5 {
        return Err(Error::new(
            Status::ErrOutOfRange,
            format!(
                "force {force:e} pN is below the range of the Moroz–Nelson twist softening (its correction {correction:.2} > 0.5; \
                 it holds for F ≥ {:.3} pN here)",
                (kt_mod * kt / (2.0 * kb)).powi(2) / kb
            ),
        ));
    }
    Ok(kt_mod * (1.0 - correction))
}

/// dC_s/dF of (3) (pN nm² per pN).
pub fn moroz_nelson_slope(kt_mod: f64, kb: f64, kt: f64, force: f64) -> f64 {
    if kt == 0.0 {
        return 0.0;
    }
    // C_s = K_t − K_t² kT/(4 K_b^{3/2}) F^{-1/2}.
    kt_mod * kt_mod * kt / (8.0 * kb.powf(1.5)) * force.powf(-1.5)
}

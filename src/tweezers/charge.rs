//! The effective line charge of DNA in a 1:1 salt from the nonlinear
//! Poisson–Boltzmann equation (D. Stigter, J. Colloid Interface Sci. 53,
//! 296 (1975); Biopolymers 16, 1435 (1977)), doc/physics.md §3.7.2.
//!
//! A cylinder of radius a carrying the bare charge ν₀ (2 e per 0.34 nm)
//! in a 1:1 electrolyte of inverse Debye length κ has the reduced potential
//! ψ = eφ/kT solving
//!
//!   ψ'' + ψ'/r = κ² sinh ψ  (r > a),  ψ'(a) = −2 l_B ν₀ / a,  ψ(∞) = 0.   (1)
//!
//! Far away (1) is linear and ψ = A K₀(κr): the field of a Debye–Hückel
//! line charge ν_eff = A / (2 l_B) on the axis. ν_eff is the charge the
//! line-charge electrostatics of physics.md §3.1 must carry to give the
//! nonlinear cylinder's far field — counterion condensation and the
//! saturation of the near field included, no parameter fitted. (1) is
//! solved by shooting: from r = a + 30/κ on the decaying solution A K₀(κr)
//! inward to a with RK4 in ln r, A adjusted by Newton's method in ln A
//! (inside a bracket) until the boundary condition at a holds (ψ'(a) is
//! monotone in A).

use crate::error::{Error, Result};
use crate::status::Status;

/// Modified Bessel functions K₀(x), K₁(x) by the integral
/// K_ν(x) = ∫₀^∞ e^{−x cosh t} cosh(νt) dt (trapezoid in t, exponentially
/// convergent for this analytic, doubly decaying integrand; 1e-15 relative
/// for x ≥ 1e-3 with step 0.02).
pub fn bessel_k01(x: f64) -> (f64, f64) {
    let h = 0.02;
    let (mut k0, mut k1) = (0.5 * (-x).exp(), 0.5 * (-x).exp());
    let mut t: f64 = h;
    loop {
        let e = (-x * t.cosh()).exp();
        k0 += e;
        k1 += e * t.cosh();
        if e < 1e-300 || e * t.cosh() < 1e-18 * k1 * h {
            break;
        }
        t += h;
    }
    (k0 * h, k1 * h)
}

/// ν_eff (e/nm) of a cylinder of radius `a` (nm) with bare charge `bare`
/// (e/nm) in salt of inverse Debye length `kappa` (1/nm), Bjerrum length
/// `lb` (nm).
pub fn effective_charge(bare: f64, a: f64, kappa: f64, lb: f64) -> Result<f64> {
    let positive = |v: f64| v > 0.0 && v.is_finite();
    if ![bare, a, kappa, lb].into_iter().all(positive) {
        return Err(Error::new(
            Status::ErrOutOfRange,
            "effective charge: bare charge, radius, κ and l_B must be positive",
        ));
    }
    let target = -2.0 * lb * bare / a;
    // Newton in x = ln A on H(x) = −1/ψ'(a) + 1/target, with H' from the
    // sensitivity equations, kept inside a bracket. H falls from +∞ (A → 0)
    // to 0 where the inward solution blows up at a (ψ'(a) → −∞; past it a
    // shot returns None) and is close to convex in x (e^{−x} in the linear
    // regime; the blow-up's pole is a plain zero of H): Newton converges
    // from either side in 3–5 shots. On ψ'(a) itself it took ~10 near the
    // pole, where ψ'(a) is steep.
    // The linear (Debye–Hückel) cylinder's amplitude A_lin = 2 l_B ν₀ /
    // (κa K₁(κa)) bounds A from above: sinh ψ ≥ ψ makes the
    // inward-integrated |ψ'(a)| at least the linear one. Condensation puts
    // the root at A_lin/e^{0.45…1.2} for 0.005–0.5 M: the start is
    // A_lin/e^{1.5}.
    let (_, k1a) = bessel_k01(kappa * a);
    let x_lin = (2.0 * lb * bare / (kappa * a * k1a)).ln();
    let (mut lo, mut hi) = (f64::NEG_INFINITY, x_lin);
    let mut x = x_lin - 1.5;
    let h_target = -1.0 / target;
    let mut converged = false;
    // Far from the root a shot need not be exact: 375 steps until Newton's
    // steps fall below 1e-3 (ν_eff to ~1e-4), then the full 1500.
    let mut steps = STEPS / 4;
    for _ in 0..60 {
        if x < -60.0 {
            return Err(Error::new(Status::ErrNotConverged, "effective charge: no amplitude small enough"));
        }
        let fine = steps == STEPS;
        let mut newton_step = false;
        let next = match shot(x.exp(), a, kappa, steps) {
            Some((slope, dslope)) => {
                let f = -1.0 / slope - h_target;
                if f > 0.0 {
                    lo = x;
                } else {
                    hi = x;
                }
                let newton = x - f / (dslope / (slope * slope));
                if newton > lo && newton < hi {
                    newton_step = true;
                    newton
                } else if lo.is_finite() {
                    0.5 * (lo + hi)
                } else {
                    x - 2.0
                }
            }
            None => {
                hi = x;
                if lo.is_finite() {
                    0.5 * (lo + hi)
                } else {
                    x - 2.0
                }
            }
        };
        // Newton converges quadratically: after a step below 1e-7 (in
        // ln A, i.e. relative in ν_eff) from a full shot the error is
        // ~1e-13.
        let step = next - x;
        x = next;
        if fine && newton_step && step.abs() < 1e-7 {
            converged = true;
            break;
        }
        // A coarse shot's root is ~1e-4 off the full one's: the full shots
        // start from the widest bracket.
        if !fine && step.abs() < 1e-3 {
            steps = STEPS;
            (lo, hi) = (f64::NEG_INFINITY, x_lin);
        }
    }
    if !converged {
        return Err(Error::new(Status::ErrNotConverged, "effective charge: the shooting did not converge"));
    }
    let nu = x.exp() / (2.0 * lb);
    if !nu.is_finite() {
        return Err(Error::new(Status::ErrNonFiniteResult, "effective charge is not finite"));
    }
    Ok(nu)
}

/// RK4 steps of a shot (in ln r from a + 30/κ to a): ν_eff to ~3e-6 (the
/// discretisation's error, against a converged shot), the accuracy the
/// model's results were established with. An adaptive Dormand–Prince shot
/// in r reaches 1e-9 with ~400 steps, but moves ν_eff by that 3e-6, and
/// the curves' sharpest features near τ_cap (∂ ln z/∂ ln ν ~ 150 at 4 pN,
/// 0.01 M) by more than the 1e-4 the model's figures are held to.
const STEPS: usize = 1500;

/// One shot of (1) for the amplitude A with `steps` classical RK4 steps:
/// (ψ'(a), ∂ψ'(a)/∂ln A), or None where ψ blows up before a (A beyond the
/// root). In x = ln r, u = ψ, v = rψ': u' = v, v' = κ²r² sinh u, and the
/// sensitivities p = ∂u/∂ln A, q = ∂v/∂ln A: p' = q, q' = κ²r² cosh u p
/// (at the start they equal u, v, which are linear in A there). One
/// exponential per step (r² at the stages from e^{2x} by constant
/// factors) and one expm1 per stage (sinh and cosh from it, exact for the
/// far field's tiny ψ).
fn shot(amp: f64, a: f64, kappa: f64, steps: usize) -> Option<(f64, f64)> {
    let k2 = kappa * kappa;
    let r0 = a + 30.0 / kappa;
    let (k0, k1) = bessel_k01(kappa * r0);
    let mut y = [amp * k0, -amp * kappa * r0 * k1, amp * k0, -amp * kappa * r0 * k1];
    let (x0, x1) = (r0.ln(), a.ln());
    let h = (x1 - x0) / steps as f64;
    let (e_half, e_full) = (h.exp(), (2.0 * h).exp());
    let f = |s: f64, y: &[f64; 4]| -> [f64; 4] {
        let em = y[0].exp_m1();
        let q = em / (1.0 + em);
        [y[1], s * 0.5 * (em + q), y[3], s * (1.0 + 0.5 * em * q) * y[2]]
    };
    let add = |y: &[f64; 4], c: f64, k: &[f64; 4]| -> [f64; 4] { std::array::from_fn(|i| y[i] + c * k[i]) };
    let mut x = x0;
    for _ in 0..steps {
        let s0 = k2 * (2.0 * x).exp();
        let (s1, s2) = (s0 * e_half, s0 * e_full);
        let k1 = f(s0, &y);
        let k2 = f(s1, &add(&y, 0.5 * h, &k1));
        let k3 = f(s1, &add(&y, 0.5 * h, &k2));
        let k4 = f(s2, &add(&y, h, &k3));
        for i in 0..4 {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        x += h;
        if !(y[0].abs() < 700.0) {
            return None;
        }
    }
    Some((y[1] / a, y[3] / a))
}

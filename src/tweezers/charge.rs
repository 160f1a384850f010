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
//! inward to a with RK4 in ln r, A adjusted by bisection in ln A until the
//! boundary condition at a holds (ψ'(a) is monotone in A).

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
    // ψ'(a) for amplitude A: integrate (1) as a system in x = ln r:
    // u = ψ, v = r ψ' → u' = v, v' = κ² r² sinh u.
    let slope_at_a = |amp: f64| -> f64 {
        let r0 = a + 30.0 / kappa;
        let (k0, k1) = bessel_k01(kappa * r0);
        let mut u = amp * k0;
        let mut v = -amp * kappa * r0 * k1;
        let (x0, x1) = (r0.ln(), a.ln());
        let steps = 1500;
        let h = (x1 - x0) / steps as f64;
        let f = |x: f64, u: f64, v: f64| -> (f64, f64) {
            let r = x.exp();
            (v, kappa * kappa * r * r * u.sinh())
        };
        let mut x = x0;
        for _ in 0..steps {
            let (a1, b1) = f(x, u, v);
            let (a2, b2) = f(x + 0.5 * h, u + 0.5 * h * a1, v + 0.5 * h * b1);
            let (a3, b3) = f(x + 0.5 * h, u + 0.5 * h * a2, v + 0.5 * h * b2);
            let (a4, b4) = f(x + h, u + h * a3, v + h * b3);
            u += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
            v += h / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4);
            x += h;
            if !u.is_finite() || u.abs() > 700.0 {
                return f64::NEG_INFINITY;
            }
        }
        v / a
    };
    // ψ'(a) → 0⁻ as A → 0 and grows in magnitude with A: bracket in ln A
    // by doubling, then regula falsi (Illinois) on g = ψ'(a) − target.
    let g = |la: f64| slope_at_a(la.exp()) - target;
    let (mut lo, mut glo) = (-3.0f64, g(-3.0));
    while glo <= 0.0 {
        lo -= 3.0;
        glo = g(lo);
        if lo < -60.0 {
            return Err(Error::new(Status::ErrNotConverged, "effective charge: no amplitude small enough"));
        }
    }
    let (mut hi, mut ghi) = (lo + 3.0, g(lo + 3.0));
    while ghi > 0.0 {
        lo = hi;
        glo = ghi;
        hi += 3.0;
        ghi = g(hi);
        if hi > 60.0 {
            return Err(Error::new(Status::ErrNotConverged, "effective charge: no amplitude large enough"));
        }
    }
    let mut side = 0;
    for _ in 0..100 {
        let mid = if ghi.is_finite() { hi - ghi * (hi - lo) / (ghi - glo) } else { 0.5 * (lo + hi) };
        let gm = g(mid);
        if gm > 0.0 {
            lo = mid;
            glo = gm;
            if side == -1 && ghi.is_finite() {
                ghi *= 0.5;
            }
            side = -1;
        } else {
            hi = mid;
            ghi = gm;
            if side == 1 {
                glo *= 0.5;
            }
            side = 1;
        }
        if (hi - lo).abs() < 1e-12 || gm.abs() < 1e-12 * target.abs() {
            break;
        }
    }
    let amp = (if glo.abs() < ghi.abs() { lo } else { hi }).exp();
    let nu = amp / (2.0 * lb);
    if !nu.is_finite() {
        return Err(Error::new(Status::ErrNonFiniteResult, "effective charge is not finite"));
    }
    Ok(nu)
}

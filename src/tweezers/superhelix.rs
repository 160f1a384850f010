//! The plectonemic phase: two strands wound about each other as an ideal
//! superhelix of radius R and opening angle α (the angle between a strand's
//! tangent and the superhelix axis), doc/physics.md §3.7.2.
//!
//! Strand 1 at arc length s is r₁(s) = (R cos ks, R sin ks, s cos α),
//! k = sin α / R; strand 2 is strand 1 turned by π about the axis. Per unit
//! length of DNA in the plectoneme (both strands), at end torque τ:
//!
//! * bending: K_b κ²/2 with the strands' curvature κ = sin²α / R;
//! * electrostatics — the continuum Debye–Hückel energy of physics.md
//!   §3.1–3.2 (line charge ν, pair energy ℓ_c ν² e^{−κ_D d}/d with
//!   ℓ_c = e²/(4πε₀ε_r), arc-length cutoff |s − t| > a) of the infinite
//!   superhelix, per length, minus the same energy of the straight rod.
//!   Every point of an ideal superhelix is equivalent, so the energy density
//!   e(s) of physics.md §3.2 is one number: with h = t − s,
//!
//!     Δe = ℓ_c ν² { ∫_a^∞ [e^{−κ_D d_s}/d_s − e^{−κ_D h}/h] dh + ∫_0^∞ e^{−κ_D d_c}/d_c dh },   (1)
//!
//!   d_s² = 4R² sin²(kh/2) + h² cos²α (the strand's own other points),
//!   d_c² = 4R² cos²(kh/2) + h² cos²α (the other strand). The self part is
//!   the strand's curvature term (the near zone of §3.2 expands it; here the
//!   integrand is smooth for h ≥ a and is integrated to rounding, so no
//!   near-zone truncation enters); the cross part is the strands'
//!   repulsion. Both converge only with screening (κ_D > 0): an infinite
//!   Coulomb superhelix has no energy per length.
//! * entropic confinement of each strand's undulations by the other (T. Odijk,
//!   Macromolecules 16, 1340 (1983); J. F. Marko & E. D. Siggia, Phys. Rev. E
//!   52, 2912 (1995); J. Ubbink & T. Odijk, Biophys. J. 76, 2502 (1999)):
//!   c kT (kT/K_b)^{1/3} D^{−2/3} per length, undulations confined in one
//!   direction (towards the other strand) to the room D = 2(R − a) between
//!   the strand's contact with the other strand and its mirror position;
//!   c = 0.5518, half the square channel's 1.1036 (T. W. Burkhardt, J. Phys.
//!   A 30, L167 (1997); the two transverse directions contribute equally and
//!   independently); zero at kT = 0;
//! * writhe: each unit length of plectoneme carries writhe sin 2α / (4πR)
//!   (F. B. Fuller, PNAS 68, 815 (1971); as in N. Clauvelin, B. Audoly &
//!   S. Neukirch, Macromolecules 41, 4479 (2008) and S. Neukirch & J. F.
//!   Marko, Phys. Rev. Lett. 106, 138104 (2011); checked through the
//!   zero-temperature slope −ζ/w_eff, which matches the full rod's measured
//!   slope to 0.2 % in tests/tweezers.rs);
//! * twist: ½ K_t ω², τ = K_t ω (the bare modulus: the strands are not
//!   under tension, so no Moroz–Nelson softening).
//!
//! At torque τ, R and α minimise
//!
//!   φ(R, α; τ) = K_b sin⁴α/(2R²) + Δe(R, α) + f_conf(R) − 2πτ sin 2α/(4πR)       (2)
//!
//! and the phase's grand free energy per length (its free energy minus
//! 2πτ × its linking per length) is h_p(τ) = min φ − τ²/(2K_t). By the
//! envelope theorem its linking per length is −h_p'(τ)/2π = w + τ/(2πK_t),
//! w = sin 2α/(4πR) at the minimum.

use crate::error::{Error, Result};
use crate::quadrature::gauss_legendre;
use crate::status::Status;
use std::f64::consts::PI;

/// Burkhardt's confinement coefficient for one confined direction.
pub const CONFINEMENT: f64 = 0.5518;

/// The physics of the plectonemic phase.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plectoneme {
    /// Bending and twist moduli K_b, K_t (pN nm²).
    pub bending: f64,
    pub twist: f64,
    /// Thermal energy kT (pN nm); 0 for the zero-temperature limit.
    pub kt: f64,
    /// ℓ_c ν² (pN): the line charges' pair energy prefactor.
    pub charge2: f64,
    /// Inverse Debye length κ_D (1/nm), > 0.
    pub kappa: f64,
    /// The rod's radius a (nm): the arc-length cutoff of (1) and the
    /// contact distance 2a of the strands.
    pub radius: f64,
    /// The confinement coefficient c (0 switches the term off).
    pub confinement: f64,
    /// The hard core's stiffness k_hc (pN/nm⁴; 0: none): the full rod's
    /// pair potential k_hc (2.5a − d)³ for d < 2.5a
    /// ([`crate::charged::dna::auto_hard_core`]), integrated over the
    /// other strand like the electrostatics in (1).
    pub hard_core: f64,
}

/// The optimal superhelix at one torque.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Optimum {
    pub torque: f64,
    /// Superhelix radius R (nm) and opening angle α (rad).
    pub radius: f64,
    pub angle: f64,
    /// min φ of (2) (pN).
    pub phi: f64,
    /// Writhe per length w = sin 2α/(4πR) (1/nm).
    pub writhe: f64,
    /// The terms of the free energy per length at the optimum (pN):
    /// bending, electrostatics, confinement plus hard core.
    pub bending: f64,
    pub electrostatic: f64,
    pub confinement: f64,
}

/// Gauss points per panel of (1).
const POINTS: usize = 6;

impl Plectoneme {
    pub fn validate(&self) -> Result<()> {
        for (name, v) in
            [("bending", self.bending), ("twist", self.twist), ("kappa", self.kappa), ("radius", self.radius)]
        {
            if !(v > 0.0 && v.is_finite()) {
                return Err(Error::new(
                    Status::ErrOutOfRange,
                    format!("plectoneme: `{name}` must be positive and finite (got {v:e}); an unscreened (Coulomb) superhelix has no energy per length"),
                ));
            }
        }
        for (name, v) in [
            ("kt", self.kt),
            ("charge2", self.charge2),
            ("confinement", self.confinement),
            ("hard_core", self.hard_core),
        ] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(Error::new(
                    Status::ErrOutOfRange,
                    format!("plectoneme: `{name}` must be ≥ 0 and finite (got {v:e})"),
                ));
            }
        }
        Ok(())
    }

    /// The electrostatic integrals of (1) (dimensionless; Δe = charge2 × the sum):
    /// (self part, cross part).
    pub fn electrostatic_integrals(&self, r: f64, alpha: f64) -> (f64, f64) {
        let s = self.integrals::<false>(r, alpha);
        (s[0], s[1])
    }

    /// The integrals of (1) on Gauss panels: [self part, cross part] and,
    /// with `DERIVS`, the derivatives of their sum in (R, α): [∂_R, ∂_α,
    /// ∂_RR, ∂_Rα, ∂_αα] (the panels' own motion with R and α is not
    /// differentiated: it changes the sums only at the quadrature's error).
    ///
    /// The derivatives: both distances are d² = D = 2R²(1 + σ cos ϑ) +
    /// h² cos²α with ϑ = kh = h sin α/R, σ = −1 for the strand's own points
    /// and +1 for the other strand's. With ϑ_R = −ϑ/R and R ϑ_α = h cos α,
    ///
    ///   D_R  = 4R(1 + σ cos ϑ) + 2σRϑ sin ϑ,
    ///   D_α  = −2σRh cos α sin ϑ − 2h² sin α cos α,
    ///   D_RR = 4(1 + σ cos ϑ) + 4σϑ sin ϑ − 2σϑ² cos ϑ,
    ///   D_Rα = 2σh cos α (ϑ cos ϑ − sin ϑ),
    ///   D_αα = 2σRh sin α sin ϑ − 2σh² cos²α cos ϑ − 2h²(cos²α − sin²α),
    ///
    /// and for the pair term f(d) = e^{−κ_D d}/d, with d_p = D_p/(2d) and
    /// d_pq = (D_pq − 2 d_p d_q)/(2d): ∂_pq f = f''(d) d_p d_q + f'(d) d_pq,
    /// f' = −e^{−κ_D d}(1 + κ_D d)/d², f'' = e^{−κ_D d}(2 + 2κ_D d + κ_D²d²)/d³.
    /// The straight reference's part does not depend on (R, α): its
    /// subtracted integral plus its exact tail is E₁(κ_D a) for any reach.
    fn integrals<const DERIVS: bool>(&self, r: f64, alpha: f64) -> [f64; 7] {
        let (sa, ca) = alpha.sin_cos();
        let k = sa / r;
        let kd = self.kappa;
        let a = self.radius;
        let (gx, gw) = gauss_rule();
        // Panels: geometric from 0 to 2R (the cross integrand's width is R,
        // the self difference varies on h ~ R), then of length ≤ 1/κ_D and
        // ≤ an eighth of the helical period 2π/k, until e^{−κ_D h cos α}
        // is below 1e-12 of the integrals' scale.
        let period = 2.0 * PI / k;
        let reach = (28.0 / (kd * ca.max(1e-3))).max(4.0 * r) + a;
        let mut sums = [0.0; 7];
        // The pair term's derivatives from D's: adds wt × ∂f to sums[2..].
        let pair = |sums: &mut [f64; 7], wt: f64, d: f64, e: f64, dd: [f64; 5]| {
            let kdd = kd * d;
            let f1 = -e * (1.0 + kdd) / (d * d);
            let f2 = e * (2.0 + kdd * (2.0 + kdd)) / (d * d * d);
            let inv = 0.5 / d;
            let (dr, da) = (dd[0] * inv, dd[1] * inv);
            let drr = (dd[2] - 2.0 * dr * dr) * inv;
            let dra = (dd[3] - 2.0 * dr * da) * inv;
            let daa = (dd[4] - 2.0 * da * da) * inv;
            sums[2] += wt * f1 * dr;
            sums[3] += wt * f1 * da;
            sums[4] += wt * (f2 * dr * dr + f1 * drr);
            sums[5] += wt * (f2 * dr * da + f1 * dra);
            sums[6] += wt * (f2 * da * da + f1 * daa);
        };
        // One Gauss panel [h0, h1] of both integrals (the self part from a).
        let mut panel = |h0: f64, h1: f64| {
            let half = 0.5 * (h1 - h0);
            for (xi, wi) in gx.iter().zip(gw.iter()) {
                let h = h0 + half * (1.0 + xi);
                let wt = half * wi;
                let (sh, ch) = (0.5 * k * h).sin_cos();
                let hc = h * ca;
                let dc = (4.0 * r * r * ch * ch + hc * hc).sqrt();
                let ec = (-kd * dc).exp();
                sums[1] += wt * ec / dc;
                let self_part = h0 >= a;
                let mut ds = 0.0;
                let mut es = 0.0;
                if self_part {
                    ds = (4.0 * r * r * sh * sh + hc * hc).sqrt();
                    es = (-kd * ds).exp();
                    sums[0] += wt * (es / ds - (-kd * h).exp() / h);
                }
                if DERIVS {
                    // sin ϑ, cos ϑ of ϑ = kh from the half angle's.
                    let (sv, cv) = (2.0 * sh * ch, ch * ch - sh * sh);
                    for sigma in [1.0, -1.0] {
                        if sigma < 0.0 && !self_part {
                            continue;
                        }
                        let dd = distance_derivatives(sigma, r, h, sa, ca, sv, cv);
                        let (d, e) = if sigma > 0.0 { (dc, ec) } else { (ds, es) };
                        pair(&mut sums, wt, d, e, dd);
                    }
                }
            }
        };
        // The panels in ascending order, made as they are integrated (no
        // list: this runs ~2000 times a scene), split at h = a where the
        // self part starts.
        let mut prev = 0.0;
        let mut close = |b: f64, panel: &mut dyn FnMut(f64, f64)| {
            if b <= prev {
                return;
            }
            if prev < a && a < b {
                panel(prev, a);
                panel(a, b);
            } else {
                panel(prev, b);
            }
            prev = b;
        };
        let mut x = a.min(0.25 * r);
        while x < 2.0 * r {
            close(x, &mut panel);
            x *= 2.0;
        }
        // Beyond 2R panels grow with h (the integrands flatten like 1/h) but
        // stay below 3/κ_D (e^{−3} across a panel) and a sixth of the
        // helical period.
        let mut x = 2.0 * r;
        while x < reach {
            close(x, &mut panel);
            x += (0.5 * x).min(3.0 / kd).min(period / 6.0).max(1e-3 * r);
        }
        close(reach, &mut panel);
        // Tails beyond `reach`: the straight reference's ∫ e^{−κh}/h is
        // subtracted exactly; the superhelix's own tail is below e^{-28} ≈ 7e-13.
        sums[0] -= crate::electrostatics::special::e1(kd * reach);
        sums
    }

    /// The hard core's energy per length (pN): ∫₀^∞ k_hc (2.5a − d_c)³₊ dh
    /// over the other strand (the strand's own points are farther than
    /// 2.5a beyond the rod's 1.25πa exclusion for every superhelix with
    /// R ≥ a).
    pub fn hard_core_energy(&self, r: f64, alpha: f64) -> f64 {
        self.hard_core_terms::<false>(r, alpha)[0]
    }

    /// The hard core's energy and, with `DERIVS`, its derivatives in
    /// (R, α) [∂_R, ∂_α, ∂_RR, ∂_Rα, ∂_αα]: those of (2.5a − d_c)³ under
    /// the integral (the moving end of the support adds nothing: the
    /// integrand vanishes there to third order), with d_c's from
    /// [`distance_derivatives`].
    fn hard_core_terms<const DERIVS: bool>(&self, r: f64, alpha: f64) -> [f64; 6] {
        let mut out = [0.0; 6];
        let range = crate::charged::rod::HARD_CORE_RANGE * self.radius;
        if self.hard_core == 0.0 || 2.0 * r >= range {
            return out;
        }
        let (sa, ca) = alpha.sin_cos();
        let k = sa / r;
        // d_c(h) increases with h on the first half period while below the
        // range; its support ends where d_c = 2.5a: bisection.
        let dc = |h: f64| {
            let c = (0.5 * k * h).cos();
            (4.0 * r * r * c * c + h * h * ca * ca).sqrt()
        };
        let (mut lo, mut hi) = (0.0, (range / ca.max(1e-6)).min(PI / k));
        if dc(hi) < range {
            hi = range / ca.max(1e-6);
        }
        for _ in 0..60 {
            let m = 0.5 * (lo + hi);
            if dc(m) < range {
                lo = m;
            } else {
                hi = m;
            }
        }
        let (gx, gw) = gauss_rule();
        let half = 0.5 * lo;
        for (xi, wi) in gx.iter().zip(gw.iter()) {
            let h = half * (1.0 + xi);
            let d = dc(h);
            let g = (range - d).max(0.0);
            let wt = half * wi;
            out[0] += wt * g * g * g;
            if DERIVS && g > 0.0 {
                let (sh, ch) = (0.5 * k * h).sin_cos();
                let dd = distance_derivatives(1.0, r, h, sa, ca, 2.0 * sh * ch, ch * ch - sh * sh);
                let inv = 0.5 / d;
                let (dr, da) = (dd[0] * inv, dd[1] * inv);
                let drr = (dd[2] - 2.0 * dr * dr) * inv;
                let dra = (dd[3] - 2.0 * dr * da) * inv;
                let daa = (dd[4] - 2.0 * da * da) * inv;
                let (f1, f2) = (-3.0 * g * g, 6.0 * g);
                out[1] += wt * f1 * dr;
                out[2] += wt * f1 * da;
                out[3] += wt * (f2 * dr * dr + f1 * drr);
                out[4] += wt * (f2 * dr * da + f1 * dra);
                out[5] += wt * (f2 * da * da + f1 * daa);
            }
        }
        out.map(|v| self.hard_core * v)
    }

    /// Δe of (1) (pN).
    pub fn electrostatic(&self, r: f64, alpha: f64) -> f64 {
        if self.charge2 == 0.0 {
            return 0.0;
        }
        let (s, c) = self.electrostatic_integrals(r, alpha);
        self.charge2 * (s + c)
    }

    /// The confinement free energy per length (pN) at radius r.
    pub fn confinement_energy(&self, r: f64) -> f64 {
        if self.kt == 0.0 || self.confinement == 0.0 {
            return 0.0;
        }
        let room = 2.0 * (r - self.radius);
        if room <= 0.0 {
            return f64::INFINITY;
        }
        self.confinement * self.kt * (self.kt / self.bending).cbrt() * room.powf(-2.0 / 3.0)
    }

    /// φ of (2) with its terms (bending, electrostatic, confinement).
    pub fn phi(&self, tau: f64, r: f64, alpha: f64) -> (f64, [f64; 3]) {
        let s = alpha.sin();
        let bend = self.bending * s.powi(4) / (2.0 * r * r);
        let el = self.electrostatic(r, alpha);
        let conf = self.confinement_energy(r) + self.hard_core_energy(r, alpha);
        let writhe_work = tau * (2.0 * alpha).sin() / (2.0 * r);
        (bend + el + conf - writhe_work, [bend, el, conf])
    }

    /// φ of (2) in the minimisation's unknowns u = ln(R − a) and α, with
    /// its gradient [∂_u, ∂_α] and Hessian [∂_uu, ∂_uα, ∂_αα], all
    /// analytic: in R the bending K_b s⁴/(2R²) and the writhe work
    /// τ sin 2α/(2R) are differentiated by hand, the electrostatics and the
    /// hard core under their integrals (the panels of (1)); the
    /// confinement is C e^{−2u/3}. Then ∂_u = ρ∂_R, ∂_uu = ρ∂_R + ρ²∂_RR,
    /// ∂_uα = ρ∂_Rα with ρ = dR/du = R − a. The value is [`Plectoneme::phi`]'s.
    pub fn phi_derivatives(&self, tau: f64, u: f64, alpha: f64) -> (f64, [f64; 2], [f64; 3]) {
        let rho = u.exp();
        let r = self.radius + rho;
        let (sa, ca) = alpha.sin_cos();
        let (s2, c2) = (2.0 * sa * ca, ca * ca - sa * sa);
        let (r2, r3) = (r * r, r * r * r);
        let s3 = sa * sa * sa;
        let kb = self.bending;
        // [∂_R, ∂_α, ∂_RR, ∂_Rα, ∂_αα] in (R, α): bending and writhe work,
        // then the electrostatics and the hard core.
        let mut t = [
            -kb * s3 * sa / r3 + tau * s2 / (2.0 * r2),
            2.0 * kb * s3 * ca / r2 - tau * c2 / r,
            3.0 * kb * s3 * sa / (r3 * r) - tau * s2 / r3,
            -4.0 * kb * s3 * ca / r3 + tau * c2 / r2,
            2.0 * kb * sa * sa * (3.0 * ca * ca - sa * sa) / r2 + 2.0 * tau * s2 / r,
        ];
        let mut el = 0.0;
        if self.charge2 != 0.0 {
            let e = self.integrals::<true>(r, alpha);
            el = self.charge2 * (e[0] + e[1]);
            for i in 0..5 {
                t[i] += self.charge2 * e[i + 2];
            }
        }
        let hc = self.hard_core_terms::<true>(r, alpha);
        for i in 0..5 {
            t[i] += hc[i + 1];
        }
        let conf = self.confinement_energy(r);
        // The value summed as [`Plectoneme::phi`] sums it, to the bit (the
        // minimisation compares the two).
        let bend = kb * sa.powi(4) / (2.0 * r * r);
        let writhe_work = tau * (2.0 * alpha).sin() / (2.0 * r);
        let value = bend + el + (conf + hc[0]) - writhe_work;
        let grad = [rho * t[0] - 2.0 / 3.0 * conf, t[1]];
        let hess = [rho * t[0] + rho * rho * t[2] + 4.0 / 9.0 * conf, rho * t[3], t[4]];
        (value, grad, hess)
    }

    /// The optimum of (2) at torque `tau`, from the start (R, α) if given,
    /// else from a coarse grid. R is kept above the contact radius a.
    pub fn optimum(&self, tau: f64, start: Option<(f64, f64)>) -> Result<Optimum> {
        self.validate()?;
        // At kT = 0 φ can have two minima in R (a wide one held by the
        // electrostatics and a tight one held by the hard core, at low salt
        // and high torque): there a warm start that lands above the coarse
        // grid's best is retried from the grid. At kT > 0 the confinement
        // (∝ (R − a)^{−2/3}) removes the tight one (tests/tweezers.rs holds
        // warm-started tables against grid-started optima at 0.1 and 0.01 M).
        // A warm start that fails is always retried from the grid.
        match (start, self.descend(tau, start)) {
            (Some(_), Ok(o)) if self.kt > 0.0 => Ok(o),
            (Some(_), Ok(o)) => {
                let (best, r, al) = self.coarse(tau);
                if best < o.phi - 1e-9 * o.phi.abs().max(1e-12) {
                    match self.descend(tau, Some((r, al))) {
                        Ok(g) if g.phi < o.phi => Ok(g),
                        _ => Ok(o),
                    }
                } else {
                    Ok(o)
                }
            }
            (Some(_), Err(_)) => self.descend(tau, None),
            (None, r) => r,
        }
    }

    /// The best of φ on a coarse grid: R geometric from 1.02a to the
    /// largest radius searched (12 values), α from 6° to 78° (7 values).
    fn coarse(&self, tau: f64) -> (f64, f64, f64) {
        let a = self.radius;
        let top = self.max_radius();
        let mut best = (f64::INFINITY, 0.0, 0.0);
        for i in 0..12 {
            let r = a + (0.02 * a) * ((top - a) / (0.02 * a)).powf(i as f64 / 11.0);
            for j in 0..7 {
                let al = (6.0 + 12.0 * j as f64).to_radians();
                let v = self.phi(tau, r.min(top * 0.999), al).0;
                if v < best.0 {
                    best = (v, r.min(top * 0.999), al);
                }
            }
        }
        best
    }

    fn descend(&self, tau: f64, start: Option<(f64, f64)>) -> Result<Optimum> {
        let a = self.radius;
        // Unknowns u = ln(R − a) (R > a: the strands do not pass through
        // each other) and α ∈ (0, π/2).
        // R is searched below R_max = max(30 nm, 15/κ_D): beyond it the
        // strands no longer interact and a minimum there means no
        // plectoneme at this torque ([`Optimum::radius`] at the bound).
        let u_max = (self.max_radius() - a).ln();
        let inside = |u: f64, al: f64| al > 1e-4 && al < 0.5 * PI - 1e-4 && u <= u_max && u >= -30.0;
        let f = |u: f64, al: f64| -> f64 {
            if !inside(u, al) {
                return f64::INFINITY;
            }
            self.phi(tau, a + u.exp(), al).0
        };
        let (mut u, mut al) = match start {
            // A start far out (R ≫ a: no plectoneme below the coexistence
            // torque, φ → 0⁺ as R → ∞) is no guide: search the grid.
            Some((r, al)) if r > a && r < 0.5 * self.max_radius() => ((r - a).ln(), al),
            _ => {
                let (_, r, al) = self.coarse(tau);
                ((r - a).ln(), al)
            }
        };
        // Damped Newton on the analytic gradient and Hessian
        // ([`Plectoneme::phi_derivatives`]), backtracking on φ; gradient
        // steps where the Hessian is not positive. A full step is tried with
        // the derivatives (it is the next iterate), a shortened one with φ
        // alone.
        let (mut fc, mut grad, mut hess) =
            if inside(u, al) { self.phi_derivatives(tau, u, al) } else { (f64::INFINITY, [0.0; 2], [0.0; 3]) };
        if !fc.is_finite() {
            return Err(Error::new(
                Status::ErrNotConverged,
                format!("superhelix at torque {tau:.4} pN nm: no finite start"),
            ));
        }
        let mut converged = false;
        for _ in 0..80 {
            let [gu, ga] = grad;
            let [huu, hua, haa] = hess;
            let det = huu * haa - hua * hua;
            let newton = huu > 0.0 && det > 0.0;
            let (mut du, mut da) = if newton {
                (-(haa * gu - hua * ga) / det, -(huu * ga - hua * gu) / det)
            } else {
                let g2 = (gu * gu + ga * ga).sqrt().max(1e-300);
                (-0.1 * gu / g2, -0.1 * ga / g2)
            };
            // A full Newton step below 1e-6 leaves an error ~1e-12 (quadratic
            // convergence): it is taken as it is, the last one. (The
            // decrease of φ it brings, ~1e-12 × φ'', is below φ's rounding:
            // testing it only rejected good steps.)
            if newton && du.abs() < 1e-6 && da.abs() < 1e-6 {
                if inside(u + du, al + da) {
                    u += du;
                    al += da;
                }
                converged = true;
                break;
            }
            // Bound the step (a trust region of 1 in ln(R − a), 0.2 rad).
            let scale = (du.abs() / 1.0).max(da.abs() / 0.2).max(1.0);
            du /= scale;
            da /= scale;
            let mut t = 1.0;
            let mut moved = false;
            let mut stale = false;
            for _ in 0..30 {
                let (un, an) = (u + t * du, al + t * da);
                if t == 1.0 && inside(un, an) {
                    let (fnew, gn, hn) = self.phi_derivatives(tau, un, an);
                    if fnew.is_finite() && fnew <= fc {
                        (u, al, fc, grad, hess) = (un, an, fnew, gn, hn);
                        moved = true;
                        break;
                    }
                } else {
                    let fnew = f(un, an);
                    if fnew.is_finite() && fnew <= fc {
                        (u, al, fc) = (un, an, fnew);
                        moved = true;
                        stale = true;
                        break;
                    }
                }
                t *= 0.5;
            }
            if !moved || ((t * du).abs() < 1e-9 && (t * da).abs() < 1e-9) {
                converged = true;
                break;
            }
            if stale {
                (_, grad, hess) = self.phi_derivatives(tau, u, al);
            }
        }
        if !converged {
            return Err(Error::new(
                Status::ErrNotConverged,
                format!("superhelix at torque {tau:.4} pN nm: the minimisation over (R, α) did not converge"),
            ));
        }
        let r = a + u.exp();
        let (phi, terms) = self.phi(tau, r, al);
        if !phi.is_finite() {
            return Err(Error::new(Status::ErrNonFiniteResult, "superhelix free energy is not finite"));
        }
        Ok(Optimum {
            torque: tau,
            radius: r,
            angle: al,
            phi,
            writhe: (2.0 * al).sin() / (4.0 * PI * r),
            bending: terms[0],
            electrostatic: terms[1],
            confinement: terms[2],
        })
    }

    /// The largest superhelix radius searched (nm).
    pub fn max_radius(&self) -> f64 {
        (30.0f64).max(15.0 / self.kappa) + self.radius
    }

    /// h_p(τ) = min φ − τ²/(2K_t) at an optimum.
    pub fn grand(&self, o: &Optimum) -> f64 {
        o.phi - o.torque * o.torque / (2.0 * self.twist)
    }
}

/// The derivatives [D_R, D_α, D_RR, D_Rα, D_αα] of a squared distance
/// D = 2R²(1 + σ cos ϑ) + h² cos²α, ϑ = h sin α/R, between the superhelix's
/// points h apart (σ = −1: the same strand; +1: the other one), from
/// sin α, cos α, sin ϑ, cos ϑ (`Plectoneme::integrals` derives them).
fn distance_derivatives(sigma: f64, r: f64, h: f64, sa: f64, ca: f64, sv: f64, cv: f64) -> [f64; 5] {
    let th = h * sa / r;
    let h2 = h * h;
    [
        4.0 * r * (1.0 + sigma * cv) + 2.0 * sigma * r * th * sv,
        -2.0 * sigma * r * h * ca * sv - 2.0 * h2 * sa * ca,
        4.0 * (1.0 + sigma * cv) + 4.0 * sigma * th * sv - 2.0 * sigma * th * th * cv,
        2.0 * sigma * h * ca * (th * cv - sv),
        2.0 * sigma * r * h * sa * sv - 2.0 * sigma * h2 * ca * ca * cv - 2.0 * h2 * (ca * ca - sa * sa),
    ]
}

/// The Gauss rule of (1)'s panels (computed once per thread).
fn gauss_rule() -> &'static (Vec<f64>, Vec<f64>) {
    use std::sync::OnceLock;
    static RULE: OnceLock<(Vec<f64>, Vec<f64>)> = OnceLock::new();
    RULE.get_or_init(|| gauss_legendre(POINTS))
}

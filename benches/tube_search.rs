//! Numerical search (physics.md §1.5): does torsion-free (T = 0),
//! pressure-free, open-ended stretching of a tube, λ from 1 to 1.5 (or until
//! the solver stops), ever
//!   (a) overwind first, then unwind (a maximum of s·ψ(λ), s the reference
//!       sense), ideally early (λ ≈ 1.03–1.05) and followed by rapid
//!       unwinding, as DNA does, or
//!   (b) deflate first, then inflate (a minimum of a radius vs λ)?
//!
//! Model classes (random samples; sample i of a class is reproduced from its
//! class name and i, and every reported case is printed with its full
//! parameters, shortest round-trip decimals, and as Rust code):
//!   svk_membrane      thin compressible orthotropic SVK membrane (control)
//!   svk_membrane_inc  the same, incompressible variant (control)
//!   svk_thick         thick compressible orthotropic SVK, α(R) = atan(τ0 R)
//!   svk_thick_nearinc the same, Poisson ratios 0.5–0.999 of the way to the
//!                     orthotropic incompressibility limit (ν12 + ν13 = 1, …)
//!   svk_thick_inc     thick incompressible SVK (J = 1)
//!   hgo_fixed         neo-Hookean matrix + two fibre families of opposite
//!                     hand at fixed (different) angles, different k1, k2
//!   hgo_helix         two families following τ0 (β = ±atan(τ0 R)) in a thick
//!                     wall, different k1, k2
//!   hgo_one           one helical family (control)
//!   hgo_membrane      two fixed-angle families, membrane model
//!
//! Reference sense s for "overwinding": sign(τ0) = +1 for SVK (τ0 > 0 is
//! sampled). Fibre walls: family 0 has hand +1 and family 1 hand −1; a twist
//! reversal is "overwind→unwind" w.r.t. the family whose sense the initial
//! twist follows, so for fibre walls every reversal is counted (and printed
//! with which family is the reference).
//!
//! Phases: (1) coarse sweeps on a fixed 16-interval grid, λ step 0.005 to
//! 1.1 then 0.01; (2) confirmation of the best candidates on 24- and
//! 48-interval grids and adaptively (rel_tol 1e-7), λ step 0.0025, with wall
//! stretches, the torsional stiffness dT/dψ at fixed λ (stability of the
//! torque-free state) and, for membranes, the thick solver on the same thin
//! wall; (3) a local random search (hill climbing) from the confirmed best
//! towards the DNA-like target; (4) probes of solver behaviour.
//!
//! Run: `cargo bench --bench tube_search` (a few minutes; a parameter search,
//! not a timing benchmark: it lives here because it is a long run that CI
//! does not need). The cases it confirmed are tests/support/behaviour_cases.rs.
//! Environment: TUBE_SEARCH_SCALE (default 1) multiplies the sample counts;
//! TUBE_SEARCH_ONLY=class runs one class; TUBE_SEARCH_CSV=dir (default
//! target/tube_search) receives one CSV row per coarse sample.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rodkit::tube::finite::{Axial, Ends, Loading, Torsion, TubeState};
use rodkit::tube::material::fibre::{FibreAngle, FibreFamily};
use rodkit::tube::material::{FibreReinforced, NeoHookean, SaintVenantKirchhoff, WallMaterial, WallStrain};
use rodkit::tube::scene::{TubeModel, TubeScene, WallLaw};
use rodkit::tube::Orthotropic;
use std::fmt::Write as _;
use std::sync::Mutex;

// ------------------------------------------------------------ parameters --

/// The parameters of one candidate (everything needed to rebuild it).
#[derive(Clone, Debug)]
enum Params {
    /// Orthotropic SVK, constants in the order of `Orthotropic::new`.
    Svk { inner: f64, outer: f64, tau0: f64, c: [f64; 9], incompressible: bool, membrane: bool },
    /// Neo-Hookean matrix (μ = 1; lame None: incompressible) plus families
    /// (angle, k1, k2).
    Hgo { inner: f64, outer: f64, tau0: f64, lame: Option<f64>, fams: Vec<(FibreAngle, f64, f64)>, membrane: bool },
}

impl Params {
    fn radii(&self) -> (f64, f64) {
        match self {
            Params::Svk { inner, outer, .. } | Params::Hgo { inner, outer, .. } => (*inner, *outer),
        }
    }
    fn membrane(&self) -> bool {
        match self {
            Params::Svk { membrane, .. } | Params::Hgo { membrane, .. } => *membrane,
        }
    }
    fn is_fibre(&self) -> bool {
        matches!(self, Params::Hgo { .. })
    }

    fn law(&self) -> Option<WallLaw> {
        match self {
            Params::Svk { tau0, c, incompressible, .. } => {
                let m = Orthotropic::new(c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8]).ok()?;
                Some(WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(m, *tau0, *incompressible)))
            }
            Params::Hgo { tau0, lame, fams, .. } => {
                let matrix = match lame {
                    None => NeoHookean { shear_modulus: 1.0, lame_lambda: 0.0, incompressible: true },
                    Some(l) => NeoHookean { shear_modulus: 1.0, lame_lambda: *l, incompressible: false },
                };
                let families = fams.iter().map(|&(angle, k1, k2)| FibreFamily { angle, k1, k2 }).collect();
                Some(WallLaw::FibreReinforced(FibreReinforced { matrix, families, intrinsic_twist: *tau0 }))
            }
        }
    }

    fn model(&self) -> TubeModel {
        if self.membrane() {
            TubeModel::Membrane
        } else {
            TubeModel::Thick
        }
    }

    /// An intrinsic twist rate for relative measures: τ0, or for fixed-angle
    /// fibres tan|β|/R_mid of family `reference`.
    fn reference_twist(&self, reference: usize) -> f64 {
        let (a, b) = self.radii();
        match self {
            Params::Svk { tau0, .. } => *tau0,
            Params::Hgo { tau0, fams, .. } => match fams.get(reference).map(|f| f.0) {
                Some(FibreAngle::Fixed(beta)) => beta.abs().tan() / (0.5 * (a + b)),
                _ => *tau0,
            },
        }
    }

    /// Human-readable, with shortest round-trip decimals.
    fn describe(&self) -> String {
        match self {
            Params::Svk { inner, outer, tau0, c, incompressible, membrane } => format!(
                "{} A={inner} B={outer} tau0={tau0} (alpha_in={:.2}deg alpha_out={:.2}deg) SVK-{} E1={} E2={} E3={} nu12={} nu13={} nu23={} G12={} G13={} G23={}",
                if *membrane { "MEMBRANE" } else { "THICK" },
                (tau0 * inner).atan().to_degrees(),
                (tau0 * outer).atan().to_degrees(),
                if *incompressible { "incompressible" } else { "compressible" },
                c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8]
            ),
            Params::Hgo { inner, outer, tau0, lame, fams, membrane } => {
                let mut s = format!(
                    "{} A={inner} B={outer} tau0={tau0} NH(mu=1, {}) families=[",
                    if *membrane { "MEMBRANE" } else { "THICK" },
                    lame.map_or("incompressible".to_string(), |l| format!("lame_lambda={l}"))
                );
                for (i, (angle, k1, k2)) in fams.iter().enumerate() {
                    let ang = match angle {
                        FibreAngle::Helix { hand } => format!("Helix(hand {hand:+}; {:.2}..{:.2}deg)", hand * (tau0 * inner).atan().to_degrees(), hand * (tau0 * outer).atan().to_degrees()),
                        FibreAngle::Fixed(b) => format!("Fixed({b} rad = {:.3}deg)", b.to_degrees()),
                    };
                    let _ = write!(s, "{}#{i}: {ang}, k1={k1}, k2={k2}", if i > 0 { "; " } else { "" });
                }
                s.push(']');
                s
            }
        }
    }

    /// The same case as Rust code (for turning into a test).
    fn rust(&self) -> String {
        let (a, b) = self.radii();
        let model = if self.membrane() { "TubeModel::Membrane" } else { "TubeModel::Thick" };
        let law = match self {
            Params::Svk { tau0, c, incompressible, .. } => format!(
                "WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(Orthotropic::new({:?}, {:?}, {:?}, {:?}, {:?}, {:?}, {:?}, {:?}, {:?}).unwrap(), {tau0:?}, {incompressible}))",
                c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8]
            ),
            Params::Hgo { tau0, lame, fams, .. } => {
                let matrix = match lame {
                    None => "NeoHookean { shear_modulus: 1.0, lame_lambda: 0.0, incompressible: true }".to_string(),
                    Some(l) => format!("NeoHookean {{ shear_modulus: 1.0, lame_lambda: {l:?}, incompressible: false }}"),
                };
                let fs: Vec<String> = fams
                    .iter()
                    .map(|(angle, k1, k2)| {
                        let ang = match angle {
                            FibreAngle::Helix { hand } => format!("FibreAngle::Helix {{ hand: {hand:?} }}"),
                            FibreAngle::Fixed(b) => format!("FibreAngle::Fixed({b:?})"),
                        };
                        format!("FibreFamily {{ angle: {ang}, k1: {k1:?}, k2: {k2:?} }}")
                    })
                    .collect();
                format!("WallLaw::FibreReinforced(FibreReinforced {{ matrix: {matrix}, families: vec![{}], intrinsic_twist: {tau0:?} }})", fs.join(", "))
            }
        };
        format!("TubeScene::new({a:?}, {b:?}, {law}, {model}, 1e-7, None)")
    }

    /// A nearby candidate (hill climbing): log-normal steps for moduli,
    /// stiffnesses and τ0, additive steps for Poisson ratios and angles.
    fn perturb(&self, rng: &mut ChaCha8Rng, step: f64) -> Params {
        let mut ln = |x: f64, s: f64| x * (step * s * normal(rng)).exp();
        match self.clone() {
            Params::Svk { inner, outer, tau0, mut c, incompressible, membrane } => {
                let inner = if membrane { inner } else { ln(inner, 0.3).min(0.95 * outer) };
                let tau0 = ln(tau0, 0.3);
                for k in [1, 2, 6, 7, 8] {
                    c[k] = ln(c[k], 0.5);
                }
                let mut r2 = ChaCha8Rng::seed_from_u64(rng.random());
                for k in [3, 4, 5] {
                    c[k] += step * 0.05 * normal(&mut r2);
                }
                Params::Svk { inner, outer, tau0, c, incompressible, membrane }
            }
            Params::Hgo { inner, outer, tau0, lame, mut fams, membrane } => {
                let inner = if membrane { inner } else { ln(inner, 0.3).min(0.97 * outer) };
                let tau0 = if tau0 > 0.0 { ln(tau0, 0.3) } else { 0.0 };
                let lame = lame.map(|l| ln(l, 0.5));
                let mut r2 = ChaCha8Rng::seed_from_u64(rng.random());
                for f in fams.iter_mut() {
                    if let FibreAngle::Fixed(b) = f.0 {
                        let nb = (b.abs() + step * 3f64.to_radians() * normal(&mut r2))
                            .clamp(0.2f64.to_radians(), 89.5f64.to_radians());
                        f.0 = FibreAngle::Fixed(nb * b.signum());
                    }
                    f.1 *= (step * 0.4 * normal(&mut r2)).exp();
                    f.2 *= (step * 0.4 * normal(&mut r2)).exp();
                }
                Params::Hgo { inner, outer, tau0, lame, fams, membrane }
            }
        }
    }
}

fn normal(rng: &mut ChaCha8Rng) -> f64 {
    // Box–Muller.
    let u: f64 = rng.random_range(1e-12..1.0);
    let v: f64 = rng.random();
    (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
}

fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    rng.random_range(lo.ln()..hi.ln()).exp()
}

/// Orthotropic constants with E1 = 1, sampled until positive definite.
fn random_orthotropic(rng: &mut ChaCha8Rng, near_incompressible: bool) -> [f64; 9] {
    loop {
        let e2 = log_uniform(rng, 0.01, 10.0);
        let e3 = log_uniform(rng, 0.01, 10.0);
        let (nu12, nu13, nu23) = if near_incompressible {
            // Incompressible limit of the normal compliance (rows sum to 0):
            // ν12 + ν13 = 1, ν12·E2/E1 + ν23 = 1, ν13·E3/E1 + ν23·E3/E2 = 1,
            // then scaled towards 0 by f ∈ (0.5, 0.999).
            let (x, y) = (e2, e3); // E1 = 1
                                   // From the first two: ν13 = 1 − ν12, ν23 = 1 − ν12 x; third:
                                   // (1 − ν12) y + (1 − ν12 x) y / x = 1 → ν12 = (y + y/x − 1)/(2y).
            let n12 = (y + y / x - 1.0) / (2.0 * y);
            let f = 1.0 - log_uniform(rng, 0.001, 0.5);
            (f * n12, f * (1.0 - n12), f * (1.0 - n12 * x))
        } else {
            (rng.random_range(-0.8..1.2), rng.random_range(-0.5..0.9), rng.random_range(-0.5..0.9))
        };
        let g12 = log_uniform(rng, 0.003, 3.0);
        let g13 = log_uniform(rng, 0.003, 3.0);
        let g23 = log_uniform(rng, 0.003, 3.0);
        let c = [1.0, e2, e3, nu12, nu13, nu23, g12, g13, g23];
        if Orthotropic::new(c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8]).is_ok() {
            return c;
        }
    }
}

fn random_matrix(rng: &mut ChaCha8Rng) -> Option<f64> {
    if rng.random_bool(0.4) {
        None
    } else {
        Some(log_uniform(rng, 0.3, 300.0))
    }
}

fn random_k(rng: &mut ChaCha8Rng) -> (f64, f64) {
    (log_uniform(rng, 0.05, 500.0), log_uniform(rng, 0.01, 30.0))
}

fn seed(class: &str, index: usize) -> u64 {
    let h = class.bytes().fold(0xcbf29ce484222325u64, |h, c| (h ^ c as u64).wrapping_mul(0x100000001b3));
    h ^ (index as u64).wrapping_mul(0x9e3779b97f4a7c15)
}

/// Sample `index` of `class`.
fn sample(class: &str, index: usize) -> Params {
    let rng = &mut ChaCha8Rng::seed_from_u64(seed(class, index));
    match class {
        "svk_membrane" | "svk_membrane_inc" => {
            let c = random_orthotropic(rng, false);
            Params::Svk {
                inner: 0.95,
                outer: 1.05,
                tau0: rng.random_range(0.1..4.0),
                c,
                incompressible: class.ends_with("inc"),
                membrane: true,
            }
        }
        "svk_thick" | "svk_thick_inc" | "svk_thick_nearinc" => {
            let c = random_orthotropic(rng, class == "svk_thick_nearinc");
            let inner = log_uniform(rng, 0.02, 0.7);
            Params::Svk {
                inner,
                outer: 1.0,
                tau0: rng.random_range(0.5..6.0),
                c,
                incompressible: class == "svk_thick_inc",
                membrane: false,
            }
        }
        "hgo_fixed" | "hgo_membrane" => {
            let lame = random_matrix(rng);
            let b0 = rng.random_range(1f64..88.0).to_radians();
            let b1 = rng.random_range(1f64..88.0).to_radians();
            let (k10, k20) = random_k(rng);
            let (k11, k21) = random_k(rng);
            let membrane = class == "hgo_membrane";
            let (inner, outer) = if membrane { (0.95, 1.05) } else { (rng.random_range(0.3..0.95), 1.0) };
            Params::Hgo {
                inner,
                outer,
                tau0: 0.0,
                lame,
                fams: vec![(FibreAngle::Fixed(b0), k10, k20), (FibreAngle::Fixed(-b1), k11, k21)],
                membrane,
            }
        }
        "hgo_helix" | "hgo_one" => {
            let lame = random_matrix(rng);
            let tau0 = rng.random_range(0.3..6.0);
            let mut fams = vec![];
            let (k1, k2) = random_k(rng);
            fams.push((FibreAngle::Helix { hand: 1.0 }, k1, k2));
            if class == "hgo_helix" {
                let (k1, k2) = random_k(rng);
                fams.push((FibreAngle::Helix { hand: -1.0 }, k1, k2));
            }
            Params::Hgo { inner: log_uniform(rng, 0.05, 0.9), outer: 1.0, tau0, lame, fams, membrane: false }
        }
        _ => unreachable!("unknown class {class}"),
    }
}

// ---------------------------------------------------------------- curves --

#[derive(Clone, Copy, Debug)]
struct Pt {
    lam: f64,
    psi: f64,
    a: f64,
    b: f64,
    force: f64,
    /// Smallest hoop stretch r/R and radial stretch dr/dR in the wall.
    hoop_min: f64,
    radial_min: f64,
}

impl Pt {
    fn of(s: &TubeState, inner: f64, outer: f64) -> Pt {
        let p = &s.profile;
        let (hoop_min, radial_min) = if p.radius.len() == 1 {
            (p.radius[0] / p.reference_radius[0], (s.deformed_outer_radius - s.deformed_inner_radius) / (outer - inner))
        } else {
            let hoop = p
                .radius
                .iter()
                .zip(&p.reference_radius)
                .filter(|(_, rr)| **rr > 0.0)
                .map(|(r, rr)| r / rr)
                .fold(f64::INFINITY, f64::min);
            let radial = p
                .radius
                .windows(2)
                .zip(p.reference_radius.windows(2))
                .map(|(r, rr)| (r[1] - r[0]) / (rr[1] - rr[0]))
                .fold(f64::INFINITY, f64::min);
            (hoop, radial)
        };
        Pt {
            lam: s.stretch,
            psi: s.twist,
            a: s.deformed_inner_radius,
            b: s.deformed_outer_radius,
            force: s.applied_force,
            hoop_min,
            radial_min,
        }
    }
}

#[derive(Clone, Debug, Default)]
struct Curve {
    pts: Vec<Pt>,
    /// Why the sweep stopped before the last loading (status: message).
    error: Option<String>,
}

/// Stretches 1 → lam_max: step h_fine up to 1.1, then h_coarse.
fn stretch_grid(lam_max: f64, h_fine: f64, h_coarse: f64) -> Vec<f64> {
    let mut v = vec![1.0];
    let mut l = 1.0f64;
    while l < lam_max - 1e-9 {
        l += if l < 1.1 - 1e-9 { h_fine } else { h_coarse };
        v.push(((l * 1e9).round() / 1e9).min(lam_max));
    }
    v
}

fn scene_of(p: &Params, intervals: Option<usize>, rel_tol: f64) -> Result<TubeScene, String> {
    let (a, b) = p.radii();
    let law = p.law().ok_or("not positive definite")?;
    let iv = if p.membrane() { None } else { intervals };
    TubeScene::new(a, b, law, p.model(), rel_tol, iv).map_err(|e| format!("{:?}: {}", e.status, e.message))
}

/// Torsion-free sweep; the states reached before a failure are kept.
fn trace_scene(scene: &TubeScene, lams: &[f64]) -> Curve {
    let loadings: Vec<Loading> = lams.iter().map(|&l| Loading::torsion_free_stretch(l)).collect();
    let mut pts = Vec::new();
    let (a, b) = (scene.inner_radius, scene.outer_radius);
    let res = scene.sweep(&loadings, |_, s| {
        pts.push(Pt::of(s, a, b));
        true
    });
    Curve { pts, error: res.err().map(|e| format!("{:?}: {}", e.status, e.message)) }
}

fn trace(p: &Params, intervals: Option<usize>, rel_tol: f64, lams: &[f64]) -> Curve {
    match scene_of(p, intervals, rel_tol) {
        Ok(s) => trace_scene(&s, lams),
        Err(e) => Curve { pts: vec![], error: Some(format!("scene: {e}")) },
    }
}

// -------------------------------------------------------------- analysis --

/// A turning point of a sampled curve y(λ).
#[derive(Clone, Copy, Debug)]
struct Turn {
    /// Sample index of the extremum.
    idx: usize,
    /// λ and value of the extremum (parabola through the samples around it).
    lam: f64,
    value: f64,
    /// +1: maximum, −1: minimum.
    kind: f64,
    /// |value − extreme value after it, up to the next turn or the end|.
    prominence: f64,
}

/// Turning points of y, ignoring steps below `noise`.
fn turns(lam: &[f64], y: &[f64], noise: f64) -> Vec<Turn> {
    let n = y.len();
    if n < 3 {
        return vec![];
    }
    let mut dir = 0.0f64;
    let mut ext: Vec<(usize, f64)> = vec![];
    let mut cand = 0usize;
    for i in 1..n {
        let d = y[i] - y[cand];
        if dir == 0.0 {
            if d.abs() > noise {
                dir = d.signum();
                cand = i;
            }
            continue;
        }
        if d * dir > 0.0 {
            cand = i;
        } else if -d * dir > noise {
            ext.push((cand, dir));
            dir = -dir;
            cand = i;
        }
    }
    let mut out = vec![];
    for (k, &(i, kind)) in ext.iter().enumerate() {
        let (mut l, mut v) = (lam[i], y[i]);
        if i > 0 && i + 1 < n {
            let (x0, x1, x2) = (lam[i - 1], lam[i], lam[i + 1]);
            let (y0, y1, y2) = (y[i - 1], y[i], y[i + 1]);
            let d01 = (y1 - y0) / (x1 - x0);
            let d12 = (y2 - y1) / (x2 - x1);
            let c2 = (d12 - d01) / (x2 - x0);
            if c2 != 0.0 {
                let xs = 0.5 * (x0 + x1) - d01 / (2.0 * c2);
                if xs > x0 && xs < x2 {
                    l = xs;
                    v = y0 + d01 * (xs - x0) + c2 * (xs - x0) * (xs - x1);
                }
            }
        }
        let end = if k + 1 < ext.len() { ext[k + 1].0 + 1 } else { n };
        let tail = &y[i..end];
        let next = if kind > 0.0 {
            tail.iter().cloned().fold(f64::INFINITY, f64::min)
        } else {
            tail.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        };
        out.push(Turn { idx: i, lam: l, value: v, kind, prominence: (v - next).abs() });
    }
    out
}

fn start_dir(y: &[f64], noise: f64) -> f64 {
    y.iter().skip(1).find(|v| (**v - y[0]).abs() > noise).map_or(0.0, |v| (v - y[0]).signum())
}

/// Twist reversal in the sense of the initial twist ("overwind→unwind" with
/// the reference sense chosen as the initial one), with DNA-like measures.
#[derive(Clone, Debug)]
struct Reversal {
    /// Sense of the initial twist (+1: sense of τ0 / family 0).
    sense: f64,
    turn: Turn,
    /// s·ψ at the turn (rad per reference length) — the overwinding.
    peak: f64,
    /// λ where s·ψ is back to 0 (the overwinding undone), if reached.
    lam_zero: Option<f64>,
    /// s·ψ at the end of the curve.
    end: f64,
    /// max(−s dψ/dλ) after the turn over max(s dψ/dλ) before it.
    rapidity: f64,
    /// Smallest hoop and radial stretch in the wall at the turn.
    hoop_at_turn: f64,
    radial_at_turn: f64,
}

/// Deflation then inflation of one radius.
#[derive(Clone, Debug)]
struct Dip {
    turn: Turn,
    /// (R0 − r_min)/R0 and (r_end − r_min)/R0.
    depth: f64,
    rise: f64,
}

#[derive(Clone, Debug, Default)]
struct Outcome {
    solved_to: f64,
    error: Option<String>,
    psi_turns: Vec<Turn>,
    psi_scale: f64,
    psi_start: f64,
    reversal: Option<Reversal>,
    /// Dips of the inner, outer and mid radius.
    dips: [Option<Dip>; 3],
    starts: [f64; 3],
    /// Smallest hoop / radial stretch along the curve, and the smallest
    /// force increment (negative: an axial limit point).
    hoop_min: f64,
    radial_min: f64,
    min_df: f64,
    /// Largest jump of ψB or b/B between samples (continuity).
    max_jump: f64,
    /// min over λ ≤ 1.1 of s·dψ/dλ over its initial value (s the initial
    /// sense): a continuous measure of how close a monotone ψ(λ) comes to
    /// turning back early (< 0 once it does).
    slope_ratio: f64,
}

fn analyse(c: &Curve, inner: f64, outer: f64) -> Outcome {
    let lam: Vec<f64> = c.pts.iter().map(|p| p.lam).collect();
    let psi: Vec<f64> = c.pts.iter().map(|p| p.psi).collect();
    let mut o =
        Outcome { solved_to: lam.last().copied().unwrap_or(f64::NAN), error: c.error.clone(), ..Default::default() };
    if c.pts.len() < 3 {
        return o;
    }
    o.psi_scale = psi.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let noise_psi = 1e-10 / outer + 1e-9 * o.psi_scale;
    let noise_r = 1e-10 * outer;
    o.psi_turns = turns(&lam, &psi, noise_psi);
    o.psi_start = start_dir(&psi, noise_psi);
    if let Some(&t) = o.psi_turns.first() {
        // Significant: prominence above 1e-3 of the ψ range and ψB > 1e-7.
        let s = o.psi_start;
        if t.prominence > 1e-3 * o.psi_scale && t.prominence * outer > 1e-7 && s * t.kind > 0.0 {
            let sp: Vec<f64> = psi.iter().map(|v| s * v).collect();
            let lam_zero = (t.idx..sp.len()).find(|&i| sp[i] <= 0.0).map(|i| {
                let (l0, l1, y0, y1) = (lam[i - 1], lam[i], sp[i - 1], sp[i]);
                l0 + (l1 - l0) * y0 / (y0 - y1)
            });
            let slope = |i: usize| (sp[i + 1] - sp[i]) / (lam[i + 1] - lam[i]);
            let before = (0..t.idx).map(slope).fold(0.0f64, f64::max);
            let after = (t.idx..sp.len() - 1).map(|i| -slope(i)).fold(0.0f64, f64::max);
            let pt = c.pts[t.idx];
            o.reversal = Some(Reversal {
                sense: s,
                turn: t,
                peak: s * t.value,
                lam_zero,
                end: *sp.last().unwrap(),
                rapidity: after / before.max(1e-300),
                hoop_at_turn: pt.hoop_min,
                radial_at_turn: pt.radial_min,
            });
        }
    }
    let radii: [Vec<f64>; 3] = [
        c.pts.iter().map(|p| p.a).collect(),
        c.pts.iter().map(|p| p.b).collect(),
        c.pts.iter().map(|p| 0.5 * (p.a + p.b)).collect(),
    ];
    let r0 = [inner, outer, 0.5 * (inner + outer)];
    for k in 0..3 {
        let y = &radii[k];
        o.starts[k] = start_dir(y, noise_r);
        let ts = turns(&lam, y, noise_r);
        if let Some(&t) = ts.first() {
            if t.kind < 0.0 && o.starts[k] < 0.0 && t.prominence > 1e-6 * r0[k] && r0[k] > 0.0 {
                let rmin = t.value;
                o.dips[k] =
                    Some(Dip { turn: t, depth: (r0[k] - rmin) / r0[k], rise: (y.last().unwrap() - rmin) / r0[k] });
            }
        }
    }
    o.hoop_min = c.pts.iter().map(|p| p.hoop_min).fold(f64::INFINITY, f64::min);
    o.radial_min = c.pts.iter().map(|p| p.radial_min).fold(f64::INFINITY, f64::min);
    o.min_df = c.pts.windows(2).map(|w| w[1].force - w[0].force).fold(f64::INFINITY, f64::min);
    if o.psi_start != 0.0 {
        let sl: Vec<(f64, f64)> =
            c.pts.windows(2).map(|w| (w[1].lam, o.psi_start * (w[1].psi - w[0].psi) / (w[1].lam - w[0].lam))).collect();
        let s0 = sl[0].1;
        if s0 > 0.0 {
            o.slope_ratio = sl.iter().filter(|p| p.0 <= 1.1 + 1e-9).map(|p| p.1 / s0).fold(f64::INFINITY, f64::min);
        }
    }
    o.max_jump = c
        .pts
        .windows(2)
        .map(|w| ((w[1].psi - w[0].psi) * outer).abs().max((w[1].b - w[0].b).abs() / outer))
        .fold(0.0, f64::max);
    o
}

/// DNA-likeness of a reversal: the overwinding ψ_peak·B (log) if the turn
/// lies in [1.03, 1.05] and the overwinding is undone within Δλ ≤ 0.15,
/// with penalties outside that window.
fn dna_score(o: &Outcome, outer: f64) -> f64 {
    let Some(r) = &o.reversal else { return f64::NEG_INFINITY };
    if !(r.sense > 0.0 || o.psi_start != 0.0) {
        return f64::NEG_INFINITY;
    }
    let mut s = (r.peak * outer).ln();
    s -= 3.0 * ((r.turn.lam - 1.04).abs() - 0.01).max(0.0) / 0.01;
    match r.lam_zero {
        Some(l0) => s -= 3.0 * ((l0 - r.turn.lam) - 0.15).max(0.0) / 0.05,
        None => s -= 6.0,
    }
    s
}

/// For hill climbing: any early reversal ranks above every monotone curve
/// (dna_score clamped to ≥ −14.9); monotone curves rank by how far their
/// slope drops before λ = 1.1 (−20 … −15); a curve that starts by unwinding
/// (in the sense of τ0, for SVK) ranks last.
fn climb_score(o: &Outcome, outer: f64, fibre: bool) -> f64 {
    if let Some(r) = &o.reversal {
        if fibre || r.sense > 0.0 {
            return dna_score(o, outer).max(-14.9);
        }
    }
    if (o.psi_start > 0.0 || (fibre && o.psi_start != 0.0)) && o.slope_ratio.is_finite() {
        return -20.0 + 5.0 * (1.0 - o.slope_ratio).clamp(0.0, 0.999);
    }
    -30.0
}

/// Deflate→inflate score on the outer radius: the smaller of the depth and
/// the re-inflation (log).
fn dip_score(o: &Outcome) -> f64 {
    o.dips[1].as_ref().map_or(f64::NEG_INFINITY, |d| d.depth.min(d.rise).ln())
}

// ---------------------------------------------------------- confirmation --

/// A candidate re-examined on finer grids.
#[derive(Clone, Debug)]
struct Check {
    /// Each re-run's findings.
    runs: Vec<Rerun>,
    /// dT/dψ at fixed λ at the turn (positive: the torque-free state is
    /// torsionally stable there) and the torque at ψ itself (same branch).
    dtdpsi_turn: Option<(f64, f64)>,
    dtdpsi_end: Option<(f64, f64)>,
    fine: Outcome,
    fine_curve: Curve,
    fibre: bool,
}

/// What one re-run of a candidate found.
#[derive(Clone, Debug)]
struct Rerun {
    label: String,
    /// λ of the ψ turn, if any.
    psi_turn: Option<f64>,
    /// λ of the outer-radius turn, if any.
    radius_turn: Option<f64>,
    /// The λ the sweep reached.
    solved_to: f64,
    /// Why it stopped early, if it did.
    error: Option<String>,
}

fn torsional_stiffness(scene: &TubeScene, lam: f64, psi: f64, outer: f64) -> Option<(f64, f64)> {
    let at = |p: f64| {
        let l = Loading {
            axial: Axial::Stretch(lam),
            torsion: Torsion::Twist(p),
            inner_pressure: 0.0,
            outer_pressure: 0.0,
            ends: Ends::Open,
        };
        scene.solve(&l).ok().map(|(s, _)| s.torque)
    };
    let h = 1e-4 / outer;
    let (tp, tm, t0) = (at(psi + h)?, at(psi - h)?, at(psi)?);
    Some(((tp - tm) / (2.0 * h), t0))
}

fn confirm(p: &Params, coarse: &Outcome) -> Check {
    let (_, outer) = p.radii();
    let lam_max = if coarse.solved_to.is_finite() { coarse.solved_to.min(1.5) } else { 1.5 };
    let lams = stretch_grid(lam_max, 0.0025, 0.005);
    let mut runs = vec![];
    let mut fine = Outcome::default();
    let mut fine_curve = Curve::default();
    let configs: Vec<(String, Option<usize>, f64, bool)> = if p.membrane() {
        vec![
            ("membrane".into(), None, 1e-7, false),
            ("thick-same-wall n=24".into(), Some(24), 1e-7, true),
            ("thick-same-wall adaptive".into(), None, 1e-7, true),
        ]
    } else if p.is_fibre() {
        // More grids: the stability check misfires near fibre activation on
        // some grids (see probe [1]), so agreement is judged on the others.
        vec![
            ("n=24".into(), Some(24), 1e-7, false),
            ("n=20".into(), Some(20), 1e-7, false),
            ("n=32".into(), Some(32), 1e-7, false),
            ("n=40".into(), Some(40), 1e-7, false),
            ("n=48".into(), Some(48), 1e-7, false),
            ("adaptive 1e-7".into(), None, 1e-7, false),
        ]
    } else {
        vec![
            ("n=24".into(), Some(24), 1e-7, false),
            ("n=48".into(), Some(48), 1e-7, false),
            ("adaptive 1e-7".into(), None, 1e-7, false),
        ]
    };
    for (k, (label, iv, tol, as_thick)) in configs.into_iter().enumerate() {
        let c = if as_thick {
            let (a, b) = p.radii();
            match TubeScene::new(a, b, p.law().unwrap(), TubeModel::Thick, tol, iv) {
                Ok(s) => trace_scene(&s, &lams),
                Err(e) => Curve { pts: vec![], error: Some(format!("{:?}: {}", e.status, e.message)) },
            }
        } else {
            trace(p, iv, tol, &lams)
        };
        let (a, b) = p.radii();
        let mut o = analyse(&c, a, b);
        // An adaptive sweep fails as a whole if its last point fails: retry shorter.
        if c.pts.is_empty() && iv.is_none() && !p.membrane() {
            let short = stretch_grid((1.0 + 0.8 * (lam_max - 1.0)).max(1.02), 0.0025, 0.005);
            let c2 = trace(p, None, tol, &short);
            o = analyse(&c2, a, b);
        }
        runs.push(Rerun {
            label,
            psi_turn: o.reversal.as_ref().map(|r| r.turn.lam),
            radius_turn: o.dips[1].as_ref().map(|d| d.turn.lam),
            solved_to: o.solved_to,
            error: o.error.clone(),
        });
        if k == 0 {
            fine = o;
            fine_curve = c;
        }
    }
    let mut dt_turn = None;
    let mut dt_end = None;
    if let Ok(scene) = scene_of(p, if p.membrane() { None } else { Some(24) }, 1e-7) {
        if let Some(r) = &fine.reversal {
            let pt = fine_curve.pts[r.turn.idx];
            dt_turn = torsional_stiffness(&scene, pt.lam, pt.psi, outer);
        } else if let Some(d) = &fine.dips[1] {
            let pt = fine_curve.pts[d.turn.idx];
            dt_turn = torsional_stiffness(&scene, pt.lam, pt.psi, outer);
        }
        if let Some(pt) = fine_curve.pts.last() {
            dt_end = torsional_stiffness(&scene, pt.lam, pt.psi, outer);
        }
    }
    Check { runs, dtdpsi_turn: dt_turn, dtdpsi_end: dt_end, fine, fine_curve, fibre: p.is_fibre() && !p.membrane() }
}

/// Whether the re-runs agree on the turn (within 0.01 in λ) and the curve
/// is continuous and torsionally stable at the turn.
fn confirmed(ch: &Check, twist: bool, coarse_jump: f64) -> bool {
    // Runs stopped by ErrMaterialInstability before λ = 1.02 are left out
    // (for fibre walls a misfiring check, probe [1]); at least two must agree.
    let lams: Vec<Option<f64>> = ch
        .runs
        .iter()
        .filter(|r| {
            !(r.solved_to < 1.02 && r.error.as_deref().is_some_and(|e| e.contains("MaterialInstability")) && ch.fibre)
        })
        .map(|r| if twist { r.psi_turn } else { r.radius_turn })
        .collect();
    let Some(Some(l0)) = lams.first().copied() else { return false };
    let agree = lams.len() >= 2 && lams.iter().all(|l| l.is_some_and(|l| (l - l0).abs() < 0.01));
    let stable = ch.dtdpsi_turn.is_some_and(|(k, _)| k > 0.0);
    // A continuous curve's largest step shrinks with the λ step (0.0025
    // here against 0.005–0.01 coarse); a jump between branches does not.
    let continuous = ch.fine.max_jump < 0.02 || ch.fine.max_jump < 0.7 * coarse_jump;
    agree && stable && continuous
}

// ---------------------------------------------------------------- output --

fn print_reversal(r: &Reversal, p: &Params, outer: f64, indent: &str) {
    let reference = if p.is_fibre() {
        if r.sense > 0.0 {
            0
        } else {
            1
        }
    } else {
        0
    };
    let tau = p.reference_twist(reference);
    println!(
        "{indent}ψ overwind→unwind (reference: {}): turn at λ = {:.4} (wall stretches there: min hoop {:.3}, min radial {:.3}); overwinding ψ_peak = {:.4e} rad/length, ψ_peak·B = {:.4e} rad = {:.4} deg, ψ_peak/τ_ref = {:.3e} (τ_ref = {:.4}); back through 0 at λ = {}; s·ψ at end = {:.4e} (= {:.1} × peak); rapidity {:.2}",
        if p.is_fibre() { format!("sense of family #{reference} (hand {:+})", if reference == 0 { 1 } else { -1 }) } else { "sense of τ0".into() },
        r.turn.lam,
        r.hoop_at_turn,
        r.radial_at_turn,
        r.peak,
        r.peak * outer,
        (r.peak * outer).to_degrees(),
        r.peak / tau,
        tau,
        r.lam_zero.map_or("not reached".into(), |l| format!("{l:.4}")),
        r.end,
        r.end / r.peak,
        r.rapidity
    );
}

fn print_dips(o: &Outcome, indent: &str) {
    for (k, name) in ["inner", "outer", "mid"].iter().enumerate() {
        if let Some(d) = &o.dips[k] {
            println!(
                "{indent}{name} radius deflate→inflate: min at λ = {:.4}, r_min = {:.6}, depth {:.3e}, re-inflation to end {:.3e} (relative to the reference radius)",
                d.turn.lam, d.turn.value, d.depth, d.rise
            );
        }
    }
}

fn print_case(tag: &str, p: &Params, o: &Outcome, check: Option<&Check>) {
    let (_, outer) = p.radii();
    println!("    [{tag}] {}", p.describe());
    println!("      rust: {}", p.rust());
    println!(
        "      solved to λ = {:.4}{}; wall stretches min hoop {:.3}, min radial {:.3}; min ΔF {:.2e}",
        o.solved_to,
        o.error.as_ref().map_or(String::new(), |e| format!(" (stopped: {})", &e[..e.len().min(220)])),
        o.hoop_min,
        o.radial_min,
        o.min_df
    );
    if let Some(r) = &o.reversal {
        print_reversal(r, p, outer, "      ");
    }
    print_dips(o, "      ");
    if let Some(ch) = check {
        for Rerun { label, psi_turn: lt, radius_turn: lb, solved_to: to, error: err } in &ch.runs {
            println!(
                "      re-run {label}: ψ turn {} | outer-radius min {} | to λ {:.4}{}",
                lt.map_or("none".into(), |l| format!("{l:.4}")),
                lb.map_or("none".into(), |l| format!("{l:.4}")),
                to,
                err.as_ref().map_or(String::new(), |e| format!(" (stopped: {})", &e[..e.len().min(160)]))
            );
        }
        let fmt = |v: Option<(f64, f64)>| v.map_or("failed".into(), |(k, t)| format!("{k:.4e} (T at ψ: {t:.1e})"));
        println!(
            "      dT/dψ at fixed λ: at the turn {}, at the end {}; max jump {:.2e}",
            fmt(ch.dtdpsi_turn),
            fmt(ch.dtdpsi_end),
            ch.fine.max_jump
        );
        if let Some(r) = &ch.fine.reversal {
            print_reversal(r, p, outer, "      fine: ");
        }
        print_dips(&ch.fine, "      fine: ");
    }
}

fn print_curve(c: &Curve, every: usize) {
    println!("      λ        ψ (rad/len)     a           b           F");
    for (i, p) in c.pts.iter().enumerate() {
        if i % every == 0 || i + 1 == c.pts.len() {
            println!("      {:.4}  {:+.6e}  {:.7}  {:.7}  {:.5e}", p.lam, p.psi, p.a, p.b, p.force);
        }
    }
}

// ---------------------------------------------------------------- driver --

fn parallel<T: Send, F: Fn(usize) -> T + Sync>(n: usize, f: F) -> Vec<T> {
    let threads = std::thread::available_parallelism().map_or(2, |v| v.get()).min(16);
    let next = Mutex::new(0usize);
    let out: Mutex<Vec<(usize, T)>> = Mutex::new(Vec::with_capacity(n));
    std::thread::scope(|sc| {
        for _ in 0..threads {
            sc.spawn(|| loop {
                let i = {
                    let mut g = next.lock().unwrap();
                    let i = *g;
                    *g += 1;
                    i
                };
                if i >= n {
                    break;
                }
                let r = f(i);
                out.lock().unwrap().push((i, r));
            });
        }
    });
    let mut v = out.into_inner().unwrap();
    v.sort_by_key(|p| p.0);
    v.into_iter().map(|p| p.1).collect()
}

struct Found {
    index: usize,
    params: Params,
    outcome: Outcome,
}

const COARSE_INTERVALS: usize = 16;

fn coarse(p: &Params, lams: &[f64]) -> Outcome {
    let (a, b) = p.radii();
    analyse(&trace(p, Some(COARSE_INTERVALS), 1e-7, lams), a, b)
}

/// Hill climbing from `start` on `score` (coarse sweeps, then the winner
/// confirmed by the caller).
fn climb(
    start: &Params,
    score: &dyn Fn(&Outcome, f64) -> f64,
    lams: &[f64],
    iters: usize,
    rng_seed: u64,
) -> (Params, Outcome, f64) {
    let mut rng = ChaCha8Rng::seed_from_u64(rng_seed);
    let (_, outer) = start.radii();
    let mut best = start.clone();
    let mut best_o = coarse(&best, lams);
    let mut best_s = score(&best_o, outer);
    let mut step = 1.0;
    let mut fails = 0;
    for _ in 0..iters {
        let cand = best.perturb(&mut rng, step);
        if cand.law().is_none() {
            continue;
        }
        let o = coarse(&cand, lams);
        let s = score(&o, outer);
        if s > best_s {
            best = cand;
            best_o = o;
            best_s = s;
            fails = 0;
        } else {
            fails += 1;
            if fails % 15 == 0 {
                step = (step * 0.6).max(0.05);
            }
        }
    }
    (best, best_o, best_s)
}

fn main() {
    let scale: f64 = std::env::var("TUBE_SEARCH_SCALE").ok().and_then(|v| v.parse().ok()).unwrap_or(1.0);
    let only = std::env::var("TUBE_SEARCH_ONLY").ok();
    let csv_dir = std::env::var("TUBE_SEARCH_CSV")
        .unwrap_or_else(|_| concat!(env!("CARGO_MANIFEST_DIR"), "/target/tube_search").to_string());
    let _ = std::fs::create_dir_all(&csv_dir);
    let lams = stretch_grid(1.5, 0.005, 0.01);
    let classes: [(&'static str, usize); 9] = [
        ("svk_membrane", 1500),
        ("svk_membrane_inc", 1000),
        ("svk_thick_inc", 1500),
        ("svk_thick", 2500),
        ("svk_thick_nearinc", 1500),
        ("hgo_fixed", 2000),
        ("hgo_helix", 1500),
        ("hgo_one", 600),
        ("hgo_membrane", 1500),
    ];
    let t_all = std::time::Instant::now();
    let mut summary = vec![];
    let mut seeds: Vec<(String, Params)> = vec![];
    for (class, n0) in classes {
        if only.as_deref().is_some_and(|o| o != class) {
            continue;
        }
        let n = ((n0 as f64) * scale).round().max(1.0) as usize;
        let t0 = std::time::Instant::now();
        let found: Vec<Found> = parallel(n, |i| {
            let params = sample(class, i);
            let outcome = coarse(&params, &lams);
            Found { index: i, params, outcome }
        });
        let line = report_class(class, &found, t0.elapsed().as_secs_f64(), &csv_dir, &lams, scale, &mut seeds);
        summary.push(line);
    }
    println!("\n=================== SUMMARY ({:.0} s)", t_all.elapsed().as_secs_f64());
    for l in &summary {
        println!("{l}");
    }
    if only.is_none() || only.as_deref() == Some("probes") {
        probes(&seeds);
    }
}

fn report_class(
    class: &str,
    found: &[Found],
    secs: f64,
    csv_dir: &str,
    lams: &[f64],
    scale: f64,
    seeds: &mut Vec<(String, Params)>,
) -> String {
    let n = found.len();
    let stats = class_summary(class, found, secs);
    let (complete, is_fibre) = (stats.complete, stats.is_fibre);
    let (rev, dips) = (&stats.reversals, &stats.dips);
    let picks = candidates(found, rev);
    let confirmed = confirm_candidates(class, found, &picks);
    let (best_rev, best_dip) = (confirmed.best_reversal, confirmed.best_dip);
    let (n_conf_rev, n_conf_dip) = (confirmed.reversals, confirmed.dips);
    // Local search towards the DNA-like target: from the best confirmed
    // reversal, else from the sample whose twist comes closest to turning
    // back early; for compressible SVK also from the best incompressible SVK
    // case made compressible (Poisson ratios 0.97 of the way to the
    // orthotropic incompressibility limit).
    let iters = ((120.0 * scale.sqrt()).round() as usize).max(10);
    let starts = climb_starts(class, found, best_rev, is_fibre, seeds);
    let (best_climb, climbed) = dna_search(class, &starts, lams, iters, is_fibre);
    let best_seed = match (best_climb, best_rev) {
        (Some((_, p)), _) => Some(p),
        (None, Some((i, _))) => Some(found[i].params.clone()),
        _ => None,
    };
    if let Some(p) = best_seed {
        seeds.push((class.to_string(), p));
    }
    if let Some(best) = best_dip {
        dip_search(class, found, best, lams, iters);
    }
    write_class_csv(class, found, csv_dir);
    format!(
        "{class:18} n={n:5}  complete={complete:5}  reversals={:4} (confirmed {n_conf_rev} of those re-run)  outer-dips={:4} (confirmed {n_conf_dip})  inner-dips={:4}{climbed}",
        rev.len(),
        dips[1],
        dips[0]
    )
}

/// A class's coarse statistics (printed by [`class_summary`]).
struct ClassStats<'a> {
    complete: usize,
    is_fibre: bool,
    /// The ψ reversals in the sense that counts (any sense for fibres).
    reversals: Vec<&'a Found>,
    /// Deflate→inflate counts of the inner, outer and mid radius.
    dips: Vec<usize>,
}

/// Prints a class's coarse statistics: samples, complete sweeps, early
/// stops by cause, reversals and dips.
fn class_summary<'a>(class: &str, found: &'a [Found], secs: f64) -> ClassStats<'a> {
    let n = found.len();
    let complete = found.iter().filter(|f| f.outcome.error.is_none()).count();
    let empty = found.iter().filter(|f| f.outcome.psi_turns.is_empty() && f.outcome.solved_to.is_nan()).count();
    let mut errs: std::collections::BTreeMap<String, usize> = Default::default();
    for f in found {
        if let Some(e) = &f.outcome.error {
            *errs.entry(e.split(':').next().unwrap_or("").to_string()).or_default() += 1;
        }
    }
    let is_fibre = found.first().is_some_and(|f| f.params.is_fibre());
    let rev: Vec<&Found> =
        found.iter().filter(|f| f.outcome.reversal.as_ref().is_some_and(|r| is_fibre || r.sense > 0.0)).collect();
    let uo = found.iter().filter(|f| f.outcome.reversal.as_ref().is_some_and(|r| r.sense < 0.0)).count();
    let dips: Vec<usize> = (0..3).map(|k| found.iter().filter(|f| f.outcome.dips[k].is_some()).count()).collect();
    println!("\n=== class {class}: {n} samples, {secs:.1} s; swept to λ = 1.5: {complete}; no state at all: {empty}");
    for (k, v) in &errs {
        println!("    stopped early: {v} × {k}");
    }
    if is_fibre {
        println!("    ψ reversals (any sense; the reference family is the one the initial twist follows): {} (initial sense of family #0: {}, of family #1: {uo})", rev.len(), rev.len() - uo);
    } else {
        println!("    ψ overwind→unwind (sense of τ0): {}; unwind→overwind: {uo}", rev.len());
    }
    println!("    deflate→inflate: inner radius {}, outer radius {}, mid radius {}", dips[0], dips[1], dips[2]);

    ClassStats { complete, is_fibre, reversals: rev, dips }
}

/// Candidates for confirmation: the best DNA-like, the earliest turns, the
/// largest overwinding, and the largest dips (index into `found`, why).
fn candidates(found: &[Found], rev: &[&Found]) -> Vec<(usize, &'static str)> {
    let rev = rev.to_vec();
    let mut picks: Vec<(usize, &'static str)> = vec![];
    let mut add = |list: &mut Vec<&Found>, key: &dyn Fn(&Found) -> f64, m: usize, why: &'static str| {
        let k = |f: &Found| {
            let v = key(f);
            if v.is_nan() {
                f64::NEG_INFINITY
            } else {
                v
            }
        };
        list.sort_by(|a, b| k(b).total_cmp(&k(a)));
        for f in list.iter().take(m) {
            if !picks.iter().any(|p| p.0 == f.index) {
                picks.push((f.index, why));
            }
        }
    };
    let outer_of = |f: &Found| f.params.radii().1;
    add(&mut rev.clone(), &|f| dna_score(&f.outcome, outer_of(f)), 4, "DNA-like score");
    add(&mut rev.clone(), &|f| -f.outcome.reversal.as_ref().unwrap().turn.lam, 2, "earliest turn");
    add(&mut rev.clone(), &|f| f.outcome.reversal.as_ref().unwrap().peak * outer_of(f), 2, "largest overwinding");
    let mut dl: Vec<&Found> = found.iter().filter(|f| f.outcome.dips[1].is_some()).collect();
    add(&mut dl, &|f| dip_score(&f.outcome), 4, "outer-radius dip");
    picks
}

/// What the confirmation runs found: the best confirmed reversal and dip
/// (index, score) and how many of each were confirmed.
struct Confirmed {
    best_reversal: Option<(usize, f64)>,
    best_dip: Option<(usize, f64)>,
    reversals: usize,
    dips: usize,
}

/// Re-runs the candidates on finer grids (in parallel) and prints each.
fn confirm_candidates(class: &str, found: &[Found], picks: &[(usize, &'static str)]) -> Confirmed {
    let outer_of = |f: &Found| f.params.radii().1;
    let checks: Vec<(usize, &'static str, Check)> = parallel(picks.len(), |k| {
        let f = &found[picks[k].0];
        (picks[k].0, picks[k].1, confirm(&f.params, &f.outcome))
    });
    let mut best_rev: Option<(usize, f64)> = None;
    let mut best_dip: Option<(usize, f64)> = None;
    let mut n_conf_rev = 0;
    let mut n_conf_dip = 0;
    for (i, why, ch) in &checks {
        let f = &found[*i];
        let twist_ok = confirmed(ch, true, f.outcome.max_jump) && f.outcome.reversal.is_some();
        let dip_ok = confirmed(ch, false, f.outcome.max_jump) && f.outcome.dips[1].is_some();
        println!("  -- candidate ({why}); confirmed: twist reversal {twist_ok}, outer-radius dip {dip_ok}");
        print_case(&format!("{class} #{i}"), &f.params, &f.outcome, Some(ch));
        let outer = outer_of(f);
        if twist_ok {
            n_conf_rev += 1;
            let s = dna_score(&ch.fine, outer);
            if best_rev.is_none_or(|b| s > b.1) {
                best_rev = Some((*i, s));
            }
        }
        if dip_ok {
            n_conf_dip += 1;
            let s = dip_score(&ch.fine);
            if best_dip.is_none_or(|b| s > b.1) {
                best_dip = Some((*i, s));
            }
        }
    }
    Confirmed { best_reversal: best_rev, best_dip, reversals: n_conf_rev, dips: n_conf_dip }
}

/// Where the DNA-like local search starts (see [`report_class`]).
fn climb_starts(
    class: &str,
    found: &[Found],
    best_rev: Option<(usize, f64)>,
    is_fibre: bool,
    seeds: &[(String, Params)],
) -> Vec<(String, Params)> {
    let outer_of = |f: &Found| f.params.radii().1;
    let mut starts: Vec<(String, Params)> = vec![];
    match best_rev {
        Some((i, _)) => starts.push((format!("confirmed #{i}"), found[i].params.clone())),
        None => {
            let best = found.iter().max_by(|a, b| {
                let (sa, sb) =
                    (climb_score(&a.outcome, outer_of(a), is_fibre), climb_score(&b.outcome, outer_of(b), is_fibre));
                let nz = |v: f64| if v.is_nan() { f64::NEG_INFINITY } else { v };
                nz(sa).total_cmp(&nz(sb))
            });
            if let Some(f) = best {
                starts.push((format!("closest to turning #{}", f.index), f.params.clone()));
            }
        }
    }
    if class == "svk_thick" || class == "svk_thick_nearinc" {
        if let Some(Params::Svk { inner, outer, tau0, c, .. }) =
            seeds.iter().find(|s| s.0 == "svk_thick_inc").map(|s| s.1.clone())
        {
            let (x, y) = (c[1] / c[0], c[2] / c[0]);
            let n12 = (y + y / x - 1.0) / (2.0 * y);
            for f in [0.97, 0.9, 0.8, 0.6, 0.3] {
                let mut cc = c;
                cc[3] = f * n12;
                cc[4] = f * (1.0 - n12);
                cc[5] = f * (1.0 - n12 * x);
                let p = Params::Svk { inner, outer, tau0, c: cc, incompressible: false, membrane: false };
                if p.law().is_some() {
                    starts.push((
                        format!("best svk_thick_inc case made compressible (ν = {f} × incompressible limit)"),
                        p,
                    ));
                    break;
                }
            }
        }
    }
    starts
}

/// The DNA-like local search from each start, each result confirmed and
/// printed; the best confirmed (score, params) and its summary for the
/// class line.
fn dna_search(
    class: &str,
    starts: &[(String, Params)],
    lams: &[f64],
    iters: usize,
    is_fibre: bool,
) -> (Option<(f64, Params)>, String) {
    let mut climbed = String::new();
    let mut best_climb: Option<(f64, Params)> = None;
    for (k, (from, start)) in starts.iter().enumerate() {
        let s0 = climb_score(&coarse(start, lams), start.radii().1, is_fibre);
        let (p, o, s) = climb(start, &|o, outer| climb_score(o, outer, is_fibre), lams, iters, seed(class, k) ^ 1);
        let ch = confirm(&p, &o);
        let ok = confirmed(&ch, true, o.max_jump) && o.reversal.is_some();
        println!("  -- DNA-like local search from {from} ({iters} steps): score {s0:.3} → {s:.3}; twist reversal confirmed {ok}");
        print_case(&format!("{class} climbed"), &p, &o, Some(&ch));
        print_curve(&ch.fine_curve, 8);
        if let Some(r) = ch.fine.reversal.as_ref().filter(|_| ok) {
            let sc = dna_score(&ch.fine, p.radii().1);
            if best_climb.as_ref().is_none_or(|b| sc > b.0) {
                best_climb = Some((sc, p.clone()));
                climbed = format!(
                    "; DNA-like search: turn λ = {:.4}, ψ_peak·B = {:.3e} rad, undone at λ = {}",
                    r.turn.lam,
                    r.peak * p.radii().1,
                    r.lam_zero.map_or("—".into(), |l| format!("{l:.4}"))
                );
            }
        }
    }
    (best_climb, climbed)
}

/// The deflate→inflate local search from the best confirmed dip (its index
/// in `found` and its score), confirmed and printed.
fn dip_search(class: &str, found: &[Found], (i, s0): (usize, f64), lams: &[f64], iters: usize) {
    let f = &found[i];
    let (p, o, s) = climb(&f.params, &|o, _| dip_score(o), lams, iters, seed(class, i) ^ 2);
    let ch = confirm(&p, &o);
    println!(
        "  -- deflate→inflate local search from #{i} ({iters} steps): score {s0:.3} → {s:.3}; confirmed {}",
        confirmed(&ch, false, o.max_jump)
    );
    print_case(&format!("{class} climbed from #{i}"), &p, &o, Some(&ch));
    print_curve(&ch.fine_curve, 8);
}

/// The CSV of every coarse sample of a class, `{csv_dir}/{class}.csv`.
fn write_class_csv(class: &str, found: &[Found], csv_dir: &str) {
    let mut s = String::from("class,index,solved_to,error,psi_start,reversal_sense,turn_lam,peak_psi,peak_psiB,lam_zero,end_psi,rapidity,a_dip_lam,a_depth,a_rise,b_dip_lam,b_depth,b_rise,m_dip_lam,m_depth,m_rise,hoop_min,radial_min,params\n");
    for f in found {
        let o = &f.outcome;
        let rv = o.reversal.as_ref().map_or(",,,,,,".to_string(), |r| {
            format!(
                "{},{},{},{},{},{},{}",
                r.sense,
                r.turn.lam,
                r.peak,
                r.peak * f.params.radii().1,
                r.lam_zero.map_or(String::new(), |l| l.to_string()),
                r.end,
                r.rapidity
            )
        });
        let dp: Vec<String> = o
            .dips
            .iter()
            .map(|d| d.as_ref().map_or(",,".to_string(), |d| format!("{},{},{}", d.turn.lam, d.depth, d.rise)))
            .collect();
        let _ = writeln!(
            s,
            "{class},{},{},\"{}\",{},{rv},{},{},{},\"{}\"",
            f.index,
            o.solved_to,
            o.error.as_deref().unwrap_or("").replace('"', "'"),
            o.psi_start,
            dp.join(","),
            o.hoop_min,
            o.radial_min,
            f.params.describe()
        );
    }
    let _ = std::fs::write(format!("{csv_dir}/{class}.csv"), s);
}

// ---------------------------------------------------------------- probes --

/// Hessian of W in the local modes (a, b, λ, γ) by the second differences
/// FiniteTube::check_stability uses (h = 1e-4), and its eigenvalues.
fn fd_hessian(m: &dyn WallMaterial, radius: f64, x0: [f64; 4], h: f64) -> nalgebra::Matrix4<f64> {
    let w = |x: &[f64; 4]| {
        m.energy(radius, &WallStrain { radial: x[0], hoop: x[1], axial: x[2], shear: x[3] }.right_cauchy_green())
    };
    nalgebra::Matrix4::from_fn(|k, l| {
        let at = |dk: f64, dl: f64| {
            let mut x = x0;
            x[k] += dk;
            x[l] += dl;
            w(&x)
        };
        (at(h, h) - at(h, -h) - at(-h, h) + at(-h, -h)) / (4.0 * h * h)
    })
}

/// Solver behaviour worth reporting.
fn probes(seeds: &[(String, Params)]) {
    println!("\n=================== PROBES");
    probe_fibre_activation();
    probe_membrane_minimiser(seeds);
    // 3. No stability check for incompressible laws or the membrane.
    println!("  [3] note: FiniteTube::check_stability returns Ok for incompressible laws, and MembraneTube has no stability check;");
    println!(
        "      the membrane solves every point from rest, so a sweep can jump between branches (see 'max jump' above)."
    );
}

/// The angle β(R) of a fibre family from the axis: the helix atan(τ0 R)
/// with its hand, or fixed.
fn fibre_angle(law: &FibreReinforced, f: &FibreFamily, r: f64) -> f64 {
    match f.angle {
        FibreAngle::Helix { hand } => hand * (law.intrinsic_twist * r).atan(),
        FibreAngle::Fixed(b) => b,
    }
}

/// I4 of a fibre family at radius r in the local modes x = (a, b, λ, γ):
/// the squared stretch along the fibre, (sin β b + cos β γ)² + (cos β λ)².
fn fibre_i4(law: &FibreReinforced, f: &FibreFamily, r: f64, x: [f64; 4]) -> f64 {
    let (sn, cs) = fibre_angle(law, f, r).sin_cos();
    (sn * x[1] + cs * x[3]).powi(2) + (cs * x[2]).powi(2)
}

/// Probe [1]: spurious ErrMaterialInstability in fibre walls at tiny
/// strain — the traces on four grids, the difference Hessian at the state
/// the n = 48 message names, and a scan through the fibres' activation.
fn probe_fibre_activation() {
    let p = sample("hgo_helix", 16);
    println!("  [1] {}", p.describe());
    for iv in [16usize, 24, 32, 48] {
        let c = trace(&p, Some(iv), 1e-7, &[1.0, 1.0025, 1.005, 1.01, 1.02]);
        println!(
            "      n = {iv}: reached λ = {:.4}; stop: {}",
            c.pts.last().map_or(f64::NAN, |q| q.lam),
            c.error.as_deref().map_or("none".to_string(), |e| e[..e.len().min(200)].to_string())
        );
    }
    if let Some(WallLaw::FibreReinforced(law)) = p.law() {
        // The state named in the n = 48 message, and a scan of the FD Hessian
        // through the activation of each family there.
        let x0 = [1.0017, 0.9954, 1.0025, 0.0065];
        let r = 0.6565293459241843;
        for h in [1e-4, 1e-5, 1e-3] {
            let ev = fd_hessian(&law, r, x0, h).symmetric_eigenvalues();
            let mut e: Vec<f64> = ev.iter().copied().collect();
            e.sort_by(|a, b| a.partial_cmp(b).unwrap());
            println!("      FD Hessian (h = {h:e}) at R = {r:.4}, (a, b, λ, γ) = {x0:?}: eigenvalues {:.3e} {:.3e} {:.3e} {:.3e}", e[0], e[1], e[2], e[3]);
        }
        for (k, f) in law.families.iter().enumerate() {
            let (beta, i4) = (fibre_angle(&law, f, r), fibre_i4(&law, f, r, x0));
            println!(
                "      family #{k}: β(R) = {:.3} deg, I4 − 1 = {:.3e} at that state (k1 = {}, k2 = {})",
                beta.to_degrees(),
                i4 - 1.0,
                f.k1,
                f.k2
            );
        }
        // Scan: move the shear so that family #1's I4 − 1 runs through 0.
        println!("      scan of the smallest FD-Hessian eigenvalue (h = 1e-4) as the shear γ moves the state through fibre activation:");
        for k in -6..=6 {
            let g = x0[3] + 0.0015 * k as f64;
            let x = [x0[0], x0[1], x0[2], g];
            let ev = fd_hessian(&law, r, x, 1e-4).symmetric_eigenvalues();
            let min = ev.iter().copied().fold(f64::INFINITY, f64::min);
            let i4s: Vec<String> =
                law.families.iter().map(|f| format!("{:+.2e}", fibre_i4(&law, f, r, x) - 1.0)).collect();
            let nh = fd_hessian(&law.matrix, r, x, 1e-4)
                .symmetric_eigenvalues()
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            println!(
                "        γ = {g:+.4}: I4 − 1 = [{}], min eigenvalue {min:+.3e} (matrix alone {nh:+.3e})",
                i4s.join(", ")
            );
        }
    }
}

/// Probe [2]: an independent check of an incompressible SVK membrane
/// reversal by minimising the energy alone.
fn probe_membrane_minimiser(seeds: &[(String, Params)]) {
    // Independent check of an incompressible SVK membrane reversal: minimise
    // W(a = 1/(bλ), b, λ, γ = bRψ) over (b, ψ) at each λ (Newton on
    // central differences of the energy alone; no solver code).
    let mem = seeds
        .iter()
        .find(|s| s.0 == "svk_membrane_inc")
        .map(|s| s.1.clone())
        .unwrap_or_else(|| sample("svk_membrane_inc", 9));
    if let (Some(WallLaw::SaintVenantKirchhoff(law)), Params::Svk { inner, outer, .. }) = (mem.law(), &mem) {
        let rm = 0.5 * (inner + outer);
        println!("  [2] energy minimisation check of: {}", mem.describe());
        let lams = stretch_grid(1.3, 0.005, 0.01);
        let solver = trace(&mem, None, 1e-7, &lams);
        let f = |lam: f64, y: [f64; 2]| {
            let b = y[0];
            law.energy(
                rm,
                &WallStrain { radial: 1.0 / (b * lam), hoop: b, axial: lam, shear: b * rm * y[1] }.right_cauchy_green(),
            )
        };
        let grad = |lam: f64, y: [f64; 2]| {
            let h = 1e-6;
            let mut g = [0.0; 2];
            for k in 0..2 {
                let (mut p, mut m) = (y, y);
                p[k] += h;
                m[k] -= h;
                g[k] = (f(lam, p) - f(lam, m)) / (2.0 * h);
            }
            g
        };
        let mut y = [1.0, 0.0];
        let mut maxdiff: f64 = 0.0;
        let mut psis = vec![];
        let mut all_pd = true;
        for (i, &lam) in lams.iter().enumerate() {
            let mut hm = nalgebra::Matrix2::zeros();
            for _ in 0..50 {
                let g = grad(lam, y);
                let h = 1e-4;
                hm = nalgebra::Matrix2::from_fn(|k, l| {
                    let (mut p, mut m) = (y, y);
                    p[l] += h;
                    m[l] -= h;
                    (grad(lam, p)[k] - grad(lam, m)[k]) / (2.0 * h)
                });
                let Some(d) = hm.lu().solve(&nalgebra::Vector2::new(-g[0], -g[1])) else { break };
                y = [y[0] + d[0], y[1] + d[1]];
                if d.amax() < 1e-13 {
                    break;
                }
            }
            all_pd &= hm.cholesky().is_some();
            psis.push(y[1]);
            if let Some(q) = solver.pts.get(i) {
                maxdiff = maxdiff.max((q.psi - y[1]).abs() * outer);
            }
        }
        let ts = turns(&lams, &psis, 1e-12);
        println!(
            "      minimiser: ψ turns at λ = {:?}; Hessian positive definite at every λ (local minimum): {all_pd}; max |ψ_min − ψ_solver|·B = {maxdiff:.2e} over {} stretches",
            ts.iter().map(|t| format!("{:.4} ({})", t.lam, if t.kind > 0.0 { "max" } else { "min" })).collect::<Vec<_>>(),
            lams.len()
        );
    }
}

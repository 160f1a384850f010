//! Issue 17, "honest estimates": `energy_within` (the cheapest continuum
//! settings for a requested relative tolerance) over the whole tolerance
//! range 1e-2 … 1e-12 on the cases of the issue, each against an
//! independent reference: the straight segment's closed form (§3.5), the
//! Coulomb ring's closed form (§3.5), and for the Debye–Hückel ring and the
//! helix the double integral reduced to one dimension (both are symmetric:
//! the chord depends on |s − t| only) and integrated by composite
//! Gauss–Legendre on a geometric grid. Every result must have
//! true error ≤ estimate ≤ tolerance, or be refused with
//! ERR_TOLERANCE_UNREACHABLE / ERR_WORK_LIMIT (whose message gives the best
//! reachable), and the refusal may only come below 1e-10.

use rodkit::electrostatics::{energy_within, Centerline, LineCharge, Screening};
use rodkit::Status;
use std::f64::consts::PI;

struct Segment {
    l: f64,
    nodes: usize,
}
struct Circle {
    r: f64,
    nodes: usize,
}
struct Helix {
    radius: f64,
    pitch: f64,
    l: f64,
    nodes: usize,
}

fn breaks(l: f64, n: usize) -> Vec<f64> {
    (1..n).map(|k| k as f64 * l / n as f64).collect()
}

impl Centerline for Segment {
    fn length(&self) -> f64 {
        self.l
    }
    fn closed(&self) -> bool {
        false
    }
    fn eval(&self, s: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
        ([0.0, 0.0, s], [0.0, 0.0, 1.0], [0.0; 3])
    }
    fn breakpoints(&self) -> Vec<f64> {
        breaks(self.l, self.nodes)
    }
}

impl Centerline for Circle {
    fn length(&self) -> f64 {
        2.0 * PI * self.r
    }
    fn closed(&self) -> bool {
        true
    }
    fn eval(&self, s: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let (sn, cs) = (s / self.r).sin_cos();
        ([self.r * cs, self.r * sn, 0.0], [-sn, cs, 0.0], [-cs / self.r, -sn / self.r, 0.0])
    }
    fn breakpoints(&self) -> Vec<f64> {
        breaks(self.length(), self.nodes)
    }
}

impl Helix {
    fn speed(&self) -> f64 {
        (self.radius * self.radius + (self.pitch / (2.0 * PI)).powi(2)).sqrt()
    }
    /// |r(s + h) − r(s)| (no cancellation: 2ρ sin(θ/2)).
    fn chord(&self, h: f64) -> f64 {
        let w = self.speed();
        let c = self.pitch / (2.0 * PI);
        let th = h / w;
        ((2.0 * self.radius * (0.5 * th).sin()).powi(2) + (c * th).powi(2)).sqrt()
    }
}

impl Centerline for Helix {
    fn length(&self) -> f64 {
        self.l
    }
    fn closed(&self) -> bool {
        false
    }
    fn eval(&self, s: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let w = self.speed();
        let c = self.pitch / (2.0 * PI);
        let th = s / w;
        let (sn, cs) = th.sin_cos();
        let rho = self.radius;
        (
            [rho * cs, rho * sn, c * th],
            [-rho * sn / w, rho * cs / w, c / w],
            [-rho * cs / (w * w), -rho * sn / (w * w), 0.0],
        )
    }
    fn breakpoints(&self) -> Vec<f64> {
        breaks(self.l, self.nodes)
    }
}

/// ∫_lo^hi f by 10-point Gauss–Legendre on `m` panels graded geometrically
/// from lo (f varies like 1/h there) — written out here, independent of the
/// library's rules.
fn integrate(f: &dyn Fn(f64) -> f64, lo: f64, hi: f64, m: usize) -> f64 {
    const X: [f64; 5] =
        [0.1488743389816312, 0.4333953941292472, 0.6794095682990244, 0.8650633666889845, 0.9739065285171717];
    const W: [f64; 5] =
        [0.2955242247147529, 0.2692667193099963, 0.219086362515982, 0.1494513491505806, 0.0666713443086881];
    let ratio = (hi / lo).powf(1.0 / m as f64);
    let mut sum = 0.0;
    let mut a = lo;
    for k in 0..m {
        let b = if k + 1 == m { hi } else { a * ratio };
        let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
        let mut p = 0.0;
        for (x, w) in X.iter().zip(&W) {
            p += w * (f(c - h * x) + f(c + h * x));
        }
        sum += h * p;
        a = b;
    }
    sum
}

fn phi(kappa: f64, d: f64) -> f64 {
    (-kappa * d).exp() / d
}

/// A reference by [`integrate`] at two resolutions, checked to agree to
/// 1e-14 relative (so it is exact at the tolerances tested).
fn converged(f: &dyn Fn(usize) -> f64) -> f64 {
    let (coarse, fine) = (f(2000), f(4000));
    assert!((coarse - fine).abs() <= 1e-14 * fine.abs(), "reference not converged: {coarse} vs {fine}");
    fine
}

/// Straight segment (§3.5): L[E1(κa) − E1(κL)] − (e^{−κa} − e^{−κL})/κ, i.e.
/// 2·½∫_a^L (L − h) Φ(h) dh; Coulomb L ln(L/a) − (L − a).
fn segment_reference(l: f64, kappa: f64, a: f64) -> f64 {
    if kappa == 0.0 {
        return l * (l / a).ln() - (l - a);
    }
    converged(&|m| integrate(&|h| (l - h) * phi(kappa, h), a, l, m))
}

/// A ring of radius R: E = 2πR ∫_a^{πR} Φ(2R sin(h/2R)) dh.
fn ring_reference(r: f64, kappa: f64, a: f64) -> f64 {
    if kappa == 0.0 {
        return 2.0 * PI * r * (1.0 / (a / (4.0 * r)).tan()).ln();
    }
    converged(&|m| 2.0 * PI * r * integrate(&|h| phi(kappa, 2.0 * r * (h / (2.0 * r)).sin()), a, PI * r, m))
}

/// An open helix: E = ∫_a^L (L − h) Φ(chord(h)) dh.
fn helix_reference(h: &Helix, kappa: f64, a: f64) -> f64 {
    converged(&|m| integrate(&|x| (h.l - x) * phi(kappa, h.chord(x)), a, h.l, m))
}

struct Case {
    name: &'static str,
    curve: Box<dyn Centerline>,
    screening: Screening,
    exact: f64,
}

fn cases() -> Vec<Case> {
    let helix = Helix { radius: 5.0, pitch: 10.0, l: 100.0, nodes: 100 };
    let helix_exact = helix_reference(&helix, 1.0, 1.0);
    vec![
        Case {
            name: "helix L 100, ρ 5, pitch 10, κ 1, a 1",
            curve: Box::new(helix),
            screening: Screening { kappa: 1.0, a: 1.0 },
            exact: helix_exact,
        },
        Case {
            name: "Debye–Hückel ring R 1, κ 1, a 0.1",
            curve: Box::new(Circle { r: 1.0, nodes: 16 }),
            screening: Screening { kappa: 1.0, a: 0.1 },
            exact: ring_reference(1.0, 1.0, 0.1),
        },
        Case {
            name: "Coulomb ring R 1, a 0.1",
            curve: Box::new(Circle { r: 1.0, nodes: 16 }),
            screening: Screening { kappa: 0.0, a: 0.1 },
            exact: ring_reference(1.0, 0.0, 0.1),
        },
        Case {
            name: "Coulomb ring R 1, a 0.02",
            curve: Box::new(Circle { r: 1.0, nodes: 64 }),
            screening: Screening { kappa: 0.0, a: 0.02 },
            exact: ring_reference(1.0, 0.0, 0.02),
        },
        Case {
            name: "segment L 10, κ 1, a 0.1",
            curve: Box::new(Segment { l: 10.0, nodes: 8 }),
            screening: Screening { kappa: 1.0, a: 0.1 },
            exact: segment_reference(10.0, 1.0, 0.1),
        },
        Case {
            name: "Coulomb segment L 1e4 on 8 nodes, a 1",
            curve: Box::new(Segment { l: 1e4, nodes: 8 }),
            screening: Screening { kappa: 0.0, a: 1.0 },
            exact: segment_reference(1e4, 0.0, 1.0),
        },
        Case {
            name: "Coulomb segment L 10, a 1e-6",
            curve: Box::new(Segment { l: 10.0, nodes: 8 }),
            screening: Screening { kappa: 0.0, a: 1e-6 },
            exact: segment_reference(10.0, 0.0, 1e-6),
        },
    ]
}

/// The tolerance sweep: true error ≤ estimate ≤ tolerance, or a refusal
/// (only below 1e-10) that names the best reachable.
#[test]
fn energy_within_estimates_bound_the_true_error() {
    let mut failures = vec![];
    for case in cases() {
        for k in 2..=12 {
            let tol = 10f64.powi(-k);
            match energy_within(case.curve.as_ref(), &LineCharge::Uniform(1.0), &case.screening, tol) {
                Ok(rep) => {
                    let true_error = (rep.energy.total - case.exact).abs() / case.exact.abs();
                    println!(
                        "{}: tol {tol:.0e}: true {true_error:.2e}, estimate {:.2e}, {:?}",
                        case.name, rep.estimate, rep.model
                    );
                    if !(true_error <= rep.estimate && rep.estimate <= tol) {
                        failures.push(format!(
                            "{} tol {tol:e}: true error {true_error:e}, estimate {:e}",
                            case.name, rep.estimate
                        ));
                    }
                }
                Err(e) => {
                    println!("{}: tol {tol:.0e}: {:?}: {}", case.name, e.status, e.message);
                    let refusal = matches!(e.status, Status::ErrToleranceUnreachable | Status::ErrWorkLimit);
                    if !(refusal && tol < 1e-10 && e.message.contains("best")) {
                        failures.push(format!("{} tol {tol:e}: {:?} {}", case.name, e.status, e.message));
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Refusal where the tolerance is genuinely out of reach: 1e-14 on the
/// Coulomb ring (R 1, a 0.1) is below round-off (8ε·N^{1/4} ≈ 3e-14 for
/// N ≈ 1e5 kernel evaluations, nested sums of positive terms), so
/// ERR_TOLERANCE_UNREACHABLE; the best energy the message reports must be
/// within its stated estimate of the §3.5 closed form 2πR ln cot(a/4R).
#[test]
fn unreachable_tolerance_reports_an_honest_best() {
    let ring = Circle { r: 1.0, nodes: 16 };
    let exact = ring_reference(1.0, 0.0, 0.1);
    let e = energy_within(&ring, &LineCharge::Uniform(1.0), &Screening { kappa: 0.0, a: 0.1 }, 1e-14).unwrap_err();
    assert_eq!(e.status, Status::ErrToleranceUnreachable, "{}", e.message);
    let number_after = |key: &str| -> f64 {
        let rest = &e.message[e.message.find(key).unwrap_or_else(|| panic!("{key} in {}", e.message)) + key.len()..];
        rest.split([' ', ')']).next().unwrap().parse().unwrap()
    };
    let (best, energy) = (number_after("best reachable: estimate "), number_after("(energy "));
    let true_error = (energy - exact).abs() / exact;
    println!("{}: true {true_error:e}", e.message);
    assert!(true_error <= best && best > 1e-14 && best < 1e-12, "true {true_error:e}, best {best:e}");
}

/// A C caller's curve: cubic Hermite pieces through nodes (positions, unit
/// tangents), evaluated here from the textbook basis, independent of the
/// library's `HermiteCurve`. Its parameter is not its arc length: the
/// speed |r'| departs from 1 between nodes.
struct Cubics {
    s: Vec<f64>,
    r: Vec<[f64; 3]>,
    t: Vec<[f64; 3]>,
    closed: bool,
}

impl Cubics {
    fn helix(radius: f64, pitch: f64, l: f64, nodes: usize) -> Cubics {
        let c = pitch / (2.0 * PI);
        let w = (radius * radius + c * c).sqrt();
        let s: Vec<f64> = (0..nodes).map(|k| l * k as f64 / (nodes - 1) as f64).collect();
        let r = s.iter().map(|&v| [radius * (v / w).cos(), radius * (v / w).sin(), c * v / w]).collect();
        let t = s.iter().map(|&v| [-radius * (v / w).sin() / w, radius * (v / w).cos() / w, c / w]).collect();
        Cubics { s, r, t, closed: false }
    }
    /// A unit circle through `nodes` nodes, the last repeating the first.
    fn ring(nodes: usize) -> Cubics {
        let s: Vec<f64> = (0..=nodes).map(|k| 2.0 * PI * k as f64 / nodes as f64).collect();
        let r = s.iter().map(|&v| [v.cos(), v.sin(), 0.0]).collect();
        let t = s.iter().map(|&v| [-v.sin(), v.cos(), 0.0]).collect();
        Cubics { s, r, t, closed: true }
    }
    fn length(&self) -> f64 {
        *self.s.last().unwrap()
    }
    fn position(&self, v: f64) -> [f64; 3] {
        let l = self.length();
        let v = if self.closed { v.rem_euclid(l) } else { v.clamp(0.0, l) };
        let k = (self.s.partition_point(|&x| x <= v).max(1) - 1).min(self.s.len() - 2);
        let h = self.s[k + 1] - self.s[k];
        let u = (v - self.s[k]) / h;
        let (h00, h10, h01, h11) = (
            2.0 * u.powi(3) - 3.0 * u * u + 1.0,
            u.powi(3) - 2.0 * u * u + u,
            -2.0 * u.powi(3) + 3.0 * u * u,
            u.powi(3) - u * u,
        );
        std::array::from_fn(|i| {
            h00 * self.r[k][i] + h10 * h * self.t[k][i] + h01 * self.r[k + 1][i] + h11 * h * self.t[k + 1][i]
        })
    }
    /// The element holding v ∈ [0, L] (the last for v = L).
    fn element(&self, v: f64) -> usize {
        (self.s.partition_point(|&x| x <= v).max(1) - 1).min(self.s.len() - 2)
    }
    /// r(x + step) − r(x) on element k (step may be negative), from the
    /// cubic's power form in u = (· − s_k)/h: with du = step/h,
    /// du·[c₁ + c₂(2u + du) + c₃(3u² + 3u·du + du²)]. The step enters as a
    /// length, never as the difference of two arc lengths: t = s + 1e-8 at
    /// s ≈ 10 keeps only 8 digits of the step.
    fn piece(&self, k: usize, x: f64, step: f64) -> [f64; 3] {
        let h = self.s[k + 1] - self.s[k];
        let (u, du) = ((x - self.s[k]) / h, step / h);
        std::array::from_fn(|i| {
            let (p0, p1, m0, m1) = (self.r[k][i], self.r[k + 1][i], h * self.t[k][i], h * self.t[k + 1][i]);
            let (c1, c2, c3) = (m0, -3.0 * p0 - 2.0 * m0 + 3.0 * p1 - m1, 2.0 * p0 + m0 - 2.0 * p1 + m1);
            du * (c1 + c2 * (2.0 * u + du) + c3 * (3.0 * u * u + 3.0 * u * du + du * du))
        })
    }
    /// |r(s + σu) − r(s)| for u ≥ 0 (wrapping when closed): within two
    /// shortest elements summed piece by piece along the elements it
    /// crosses, beyond by subtracting the two positions.
    fn chord(&self, s: f64, u: f64, sign: f64) -> f64 {
        let l = self.length();
        let h_min = self.s.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min);
        let d = if u >= 2.0 * h_min {
            let (p, q) = (self.position(s), self.position(s + sign * u));
            [q[0] - p[0], q[1] - p[1], q[2] - p[2]]
        } else {
            let (mut x, mut left, mut sum) = (s, u, [0.0; 3]);
            while left > 0.0 {
                if self.closed {
                    x = x.rem_euclid(l);
                }
                // The element the walk enters from x in direction σ.
                let k = if sign > 0.0 {
                    self.element(x)
                } else {
                    let k = self.element(x);
                    if x > self.s[k] {
                        k
                    } else if k > 0 {
                        k - 1
                    } else {
                        self.s.len() - 2
                    }
                };
                let x0 = if sign < 0.0 && x == 0.0 { l } else { x };
                let room = if sign > 0.0 { self.s[k + 1] - x0 } else { x0 - self.s[k] };
                let step = room.min(left);
                let part = self.piece(k, x0, sign * step);
                for i in 0..3 {
                    sum[i] += part[i];
                }
                left -= step;
                x = x0 + sign * step;
            }
            sum
        };
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
    }
    fn library(&self) -> rodkit::electrostatics::HermiteCurve {
        rodkit::electrostatics::HermiteCurve::new(self.s.clone(), self.r.clone(), self.t.clone(), self.closed).unwrap()
    }
}

/// Gauss–Legendre of `order` (5 or 7 point pairs, i.e. 10 or 14 points) on
/// [lo, hi] broken at `breaks`.
fn gauss_on(f: &dyn Fn(f64) -> f64, lo: f64, hi: f64, breaks: &mut Vec<f64>, order: usize) -> f64 {
    const X10: [f64; 5] =
        [0.1488743389816312, 0.4333953941292472, 0.6794095682990244, 0.8650633666889845, 0.9739065285171717];
    const W10: [f64; 5] =
        [0.2955242247147529, 0.2692667193099963, 0.219086362515982, 0.1494513491505806, 0.0666713443086881];
    const X14: [f64; 7] = [
        0.1080549487073437,
        0.3191123689278897,
        0.5152486363581541,
        0.6872929048116855,
        0.827201315069765,
        0.9284348836635735,
        0.9862838086968124,
    ];
    const W14: [f64; 7] = [
        0.2152638534631579,
        0.2051984637212957,
        0.1855383974779379,
        0.1572031671581936,
        0.1215185706879033,
        0.0801580871597600,
        0.0351194603317517,
    ];
    let (x, w): (&[f64], &[f64]) = if order == 10 { (&X10, &W10) } else { (&X14, &W14) };
    breaks.retain(|&b| b > lo && b < hi);
    breaks.push(lo);
    breaks.push(hi);
    breaks.sort_by(f64::total_cmp);
    breaks.dedup_by(|p, q| (*p - *q).abs() <= 1e-15 * hi.abs().max(1.0));
    let mut sum = 0.0;
    for p in breaks.windows(2) {
        let (c, h) = (0.5 * (p[0] + p[1]), 0.5 * (p[1] - p[0]));
        for (xi, wi) in x.iter().zip(w) {
            sum += h * wi * (f(c - h * xi) + f(c + h * xi));
        }
    }
    sum
}

/// The model's exact value for a Hermite curve, E = ½∫∫_{|s−t|≥a} Φ ds dt
/// (λ = 1), by iterated Gauss–Legendre: the inner integral over u = |t − s|
/// on panels graded geometrically from a (Φ ~ 1/u) and broken where t
/// crosses a node; the outer one graded geometrically toward every node
/// from node ± a (the excluded strip's edge crossing the node) and toward a
/// and L − a (the one-sided ends). Returned with the difference of the 10- and 14-point
/// rules, which the tests require ≤ 1e-13 relative.
fn cubics_reference(c: &Cubics, kappa: f64, a: f64) -> (f64, f64) {
    let l = c.length();
    let phi = |d: f64| (-kappa * d).exp() / d;
    let run = |order: usize| -> f64 {
        let density = |s: f64| -> f64 {
            // Sides: u ∈ [a, reach] with t = s ± u.
            let sides: Vec<(f64, f64)> = if c.closed { vec![(1.0, l - a)] } else { vec![(1.0, l - s), (-1.0, s)] };
            let mut e = 0.0;
            for (sign, reach) in sides {
                if reach <= a {
                    continue;
                }
                let mut breaks: Vec<f64> = Vec::new();
                let mut g = 2.0 * a;
                while g < reach {
                    breaks.push(g);
                    if c.closed {
                        breaks.push(l - g);
                    }
                    g *= 2.0;
                }
                for &node in &c.s {
                    let u = if c.closed { (node - s).rem_euclid(l) } else { sign * (node - s) };
                    breaks.push(u);
                }
                e += gauss_on(&|u: f64| phi(c.chord(s, u, sign)), a, reach, &mut breaks, order);
            }
            e
        };
        // At a distance e ≥ a from a node the inner integral runs across
        // the node, where r'' jumps: e(s) carries e·ln e there, so the outer
        // panels are graded geometrically toward each node from a.
        let half = c.s.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min) / 2.0;
        let mut breaks: Vec<f64> = Vec::new();
        for &node in &c.s {
            let mut g = a;
            let mut offsets = vec![0.0];
            while g < half {
                offsets.extend([g, -g]);
                g *= 2.0;
            }
            for o in offsets {
                breaks.push(if c.closed { (node + o).rem_euclid(l) } else { node + o });
            }
        }
        if !c.closed {
            let mut g = a;
            while g < 0.5 * l {
                breaks.extend([g, l - g]);
                g *= 2.0;
            }
        }
        0.5 * gauss_on(&density, 0.0, l, &mut breaks, order)
    };
    let (coarse, fine) = (run(10), run(14));
    (fine, (coarse - fine).abs() / fine.abs())
}

/// `energy_within` on curves as a C caller builds them (Hermite cubics
/// through nodes, parameter ≠ arc length): the 41-node helix of radius 1,
/// pitch 3 and length 20, for the excluded distance a from 1e-9·L to 0.1·L,
/// screened (κ = 1) and Coulomb, and a closed 16-node ring, over the
/// tolerances 1e-3 … 1e-8. Every answer must have true error ≤ estimate ≤
/// tolerance against [`cubics_reference`] (the double integral of the same
/// cubics, converged to 1e-13); every case here must be answered (no
/// refusal: the curve's own scales fix the near-zone width, so the work is
/// ~1e6 kernel evaluations a step whatever a). Before the near zone used
/// the curve's speed, the energy of these cubics moved by 8e-6 relative per
/// fourfold δ and a = 1e-5 ran for 96 s before refusing. a = L is refused
/// as out of range.
#[test]
fn hermite_curves_get_honest_estimates_for_any_excluded_distance() {
    let helix = Cubics::helix(1.0, 3.0, 20.0, 41);
    let mut cases: Vec<(String, &Cubics, f64, f64)> = Vec::new();
    for rel in [1e-9, 1e-6, 1e-3, 0.1] {
        for kappa in [1.0, 0.0] {
            cases.push((format!("helix a {rel:e} L, κ {kappa}"), &helix, kappa, rel * 20.0));
        }
    }
    let ring = Cubics::ring(16);
    cases.push(("ring of 16 nodes, κ 1, a 0.01".into(), &ring, 1.0, 0.01));
    let mut failures = vec![];
    for (name, cubics, kappa, a) in &cases {
        let (exact, spread) = cubics_reference(cubics, *kappa, *a);
        assert!(spread < 1e-13, "{name}: reference not converged ({spread:e})");
        let curve = cubics.library();
        for tol in [1e-3, 1e-6, 1e-8] {
            let screening = Screening { kappa: *kappa, a: *a };
            match energy_within(&curve, &LineCharge::Uniform(1.0), &screening, tol) {
                Ok(rep) => {
                    let true_error = (rep.energy.total - exact).abs() / exact;
                    println!("{name}: tol {tol:.0e}: true {true_error:.2e}, estimate {:.2e}", rep.estimate);
                    if !(true_error <= rep.estimate && rep.estimate <= tol) {
                        failures.push(format!("{name} tol {tol:e}: true {true_error:e}, estimate {:e}", rep.estimate));
                    }
                }
                Err(e) => failures.push(format!("{name} tol {tol:e}: refused {:?}: {}", e.status, e.message)),
            }
        }
    }
    let at_length =
        energy_within(&helix.library(), &LineCharge::Uniform(1.0), &Screening { kappa: 1.0, a: 20.0 }, 1e-6)
            .unwrap_err();
    assert_eq!(at_length.status, Status::ErrOutOfRange, "{}", at_length.message);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

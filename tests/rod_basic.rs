//! The discretised Cosserat rod against closed forms (physics.md §2.2,
//! §2.6): pure end moment (circular arc, closing into a ring at m = 2π), the
//! convergence orders 2s of the schemes, |q| = 1 to round-off, the straight
//! hemitropic rod's twist under tension.

use rodkit::continuation::anm::{continue_anm, AnmOptions};
use rodkit::continuation::newton::{continue_newton, Start};
use rodkit::continuation::{Options, Problem, Stop};
use rodkit::rod::model::{Rod, Supports};
use rodkit::rod::scheme::Scheme;
use rodkit::rod::{Load, Loads, RodLaw};
use std::f64::consts::PI;

fn law() -> RodLaw {
    // K_b = 1, C = 1/1.3, G = 1e4, S = 2.6e4 (L = 1): moderately extensible.
    RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap()
}

/// Tip of the arc of curvature m/L about e1: (0, −(1 − cos m)/m, sin m/m)·L.
fn arc_tip(m: f64) -> [f64; 3] {
    [0.0, -(1.0 - m.cos()) / m, m.sin() / m]
}

fn solve_at(rod: &Rod, lambda: f64) -> Vec<f64> {
    let mut sys = rod.system().unwrap();
    let opts = Options {
        target_lambda: Some(lambda),
        residual_tol: 1e-12,
        initial_step: 0.5,
        max_step: 2.0,
        ..Default::default()
    };
    let b = continue_newton(
        &mut sys,
        Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true },
        &opts,
        |x, _| x.to_vec(),
        |_| true,
    )
    .unwrap();
    assert_eq!(b.stop, Stop::Target);
    b.records.last().unwrap().outputs.clone()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[test]
fn pure_end_moment_rolls_the_rod_into_a_ring() {
    let loads = Loads { tip_moment: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
    for (scheme, n, tol) in [(Scheme::Gauss(4), 8, 1e-9), (Scheme::Gauss(2), 16, 1e-5), (Scheme::Midpoint, 64, 2e-3)] {
        let rod = Rod::new(law(), 1.0, loads, Supports::Cantilever, scheme, n).unwrap();
        for engine in ["newton", "anm"] {
            let mut sys = rod.system().unwrap();
            let opts = Options {
                target_lambda: Some(2.0 * PI),
                residual_tol: 1e-11,
                initial_step: 0.3,
                max_step: 2.0,
                ..Default::default()
            };
            let start = Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true };
            let observe = |x: &[f64], _: f64| x.to_vec();
            let b = if engine == "newton" {
                continue_newton(&mut sys, start, &opts, observe, |_| true).unwrap()
            } else {
                continue_anm(
                    &mut sys,
                    start,
                    &opts,
                    &AnmOptions { order: 20, epsilon: 1e-10, pade: false },
                    observe,
                    |_| true,
                )
                .unwrap()
            };
            assert_eq!(b.stop, Stop::Target, "{scheme:?} {engine}");
            for r in &b.records {
                let x = &r.outputs;
                let err = dist(rod.tip(x), arc_tip(r.lambda.max(1e-12)));
                assert!(err < tol, "{scheme:?} {engine}: tip error {err:e} at m = {}", r.lambda);
                // |q| = 1 at every node: the schemes conserve it exactly, so
                // what remains is the Newton residual (1e−11) and round-off.
                for i in 0..=rod.elements {
                    let q = &rod.node_state(x, i)[3..7];
                    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
                    assert!((norm - 1.0).abs() < 1e-12, "|q| − 1 = {:e}", norm - 1.0);
                }
            }
            let closed = dist(rod.tip(&b.records.last().unwrap().outputs), [0.0; 3]);
            assert!(closed < tol, "{scheme:?} {engine}: ring not closed ({closed:e})");
            println!("{scheme:?} N={n} {engine}: {:?}", b.counts);
        }
    }
}

/// Tip error of the bent arc at m = 2 against N: the observed order is 2s
/// (2 for the midpoint rule). Reference: the closed-form arc.
#[test]
fn schemes_converge_at_their_order() {
    let loads = Loads { tip_moment: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
    for (scheme, ns) in [
        (Scheme::Midpoint, [8, 16, 32]),
        (Scheme::Gauss(2), [2, 4, 8]),
        (Scheme::Gauss(3), [2, 3, 4]),
        (Scheme::Gauss(4), [1, 2, 3]),
    ] {
        let errs: Vec<f64> = ns
            .iter()
            .map(|&n| {
                let rod = Rod::new(law(), 1.0, loads, Supports::Cantilever, scheme, n).unwrap();
                dist(rod.tip(&solve_at(&rod, 2.0)), arc_tip(2.0))
            })
            .collect();
        let rate = (errs[1] / errs[2]).ln() / (ns[2] as f64 / ns[1] as f64).ln();
        println!("{scheme:?}: errors {errs:?}, rate {rate:.2}");
        assert!((rate - scheme.order() as f64).abs() < 0.3, "{scheme:?}: rate {rate} (errors {errs:?})");
    }
}

/// A straight hemitropic rod pulled by F (no torque) twists by
/// Δu3 = −gF/(CS − g²) and stretches by ε = CF/(CS − g²) (physics.md §2.2):
/// the tip turns by Δu3·L about e3 and moves to (1 + ε)L.
#[test]
fn hemitropic_rod_twists_when_pulled() {
    let (s, c, g, f) = (1000.0, 400.0, -90.0, 30.0);
    let law = RodLaw::hemitropic(200.0, c, 500.0, s, g, 0.0).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, 1.0])), ..Default::default() };
    let rod = Rod::new(law, 2.0, loads, Supports::Cantilever, Scheme::Gauss(2), 4).unwrap();
    let x = solve_at(&rod, f);
    let det = c * s - g * g;
    let (du3, eps) = (-g * f / det, c * f / det);
    let tip = rod.node_state(&x, rod.elements);
    let phi = 2.0 * tip[6].atan2(tip[3]);
    assert!((phi - du3 * 2.0).abs() < 1e-12, "twist {phi} vs {}", du3 * 2.0);
    assert!((tip[2] - (1.0 + eps) * 2.0).abs() < 1e-12);
    assert!(tip[0].abs() < 1e-14 && tip[1].abs() < 1e-14);
    // The residual is at round-off and the problem is cubic.
    let mut sys = rod.system().unwrap();
    let mut r = vec![0.0; sys.dim()];
    sys.residual(&x, f, &mut r);
    assert!(r.iter().all(|v| v.abs() < 1e-11));
}

/// Cantilever under a transverse dead tip load, α = PL²/K_b = 1: tip
/// deflection 0.30172 L and shortening 0.05643 L for the inextensible
/// elastica (physics.md §2.6; Bisshopp & Drucker 1945, Mattiasson 1981, to
/// the 5 digits quoted). The Kirchhoff rod is inextensible: it must match to
/// the table's rounding (5e−6); the extensible rod with EA = GA = 1e8 K_b/L²
/// differs from it by O(α/EA) ≈ 1e−8.
#[test]
fn transverse_dead_tip_load() {
    let loads = Loads { tip_force: Some(Load::dead([0.0, 1.0, 0.0])), ..Default::default() };
    let kirchhoff = RodLaw::kirchhoff(1.0, 1.0, 1.0 / 1.3).unwrap();
    let stiff = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e8, 1e8).unwrap();
    let mut tips = vec![];
    for (name, law) in [("kirchhoff", kirchhoff), ("extensible", stiff)] {
        let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 8).unwrap();
        let tip = rod.tip(&solve_at(&rod, 1.0));
        assert!((tip[1] - 0.30172).abs() < 5e-6, "{name}: deflection {}", tip[1]);
        assert!((1.0 - tip[2] - 0.05643).abs() < 5e-6, "{name}: shortening {}", 1.0 - tip[2]);
        assert!(tip[0].abs() < 1e-14);
        tips.push(tip);
    }
    assert!(dist(tips[0], tips[1]) < 3e-8, "extensible vs inextensible: {:e}", dist(tips[0], tips[1]));
    println!("α = 1: tip {:?}", tips[0]);
}

/// Distributed loads: a cantilever under a uniform transverse load q per
/// length, dead or follower, at a small load: the tip deflection is the
/// Timoshenko beam's w = q(L⁴/(8K_b) + L²/(2G)) (G the shear stiffness;
/// reference: strength of materials) up to O(q³) (the response is odd in q),
/// i.e. within 1e−7 relative at qL³/K_b = 1e−3; a uniform distributed couple
/// c about d1 bends it like an end moment growing along the rod:
/// tip rotation cL²/(2K_b).
#[test]
fn distributed_loads_at_small_amplitude() {
    let (kb, g) = (2.0, 500.0);
    let law = RodLaw::isotropic(kb, 1.5, g, 3e3).unwrap();
    let q = 1e-3;
    for load in [Load::dead([0.0, 1.0, 0.0]), Load::follower([0.0, 1.0, 0.0])] {
        let loads = Loads { distributed_force: Some(load), ..Default::default() };
        let rod = Rod::new(law.clone(), 1.0, loads, Supports::Cantilever, Scheme::Gauss(3), 6).unwrap();
        let tip = rod.tip(&solve_at(&rod, q));
        let w = q * (1.0 / (8.0 * kb) + 1.0 / (2.0 * g));
        assert!((tip[1] - w).abs() < 1e-7 * w, "{load:?}: {} vs {w}", tip[1]);
    }
    let loads = Loads { distributed_couple: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(3), 6).unwrap();
    let x = solve_at(&rod, q);
    let y = rod.node_state(&x, rod.elements);
    let rotation = 2.0 * y[4].atan2(y[3]);
    let want = q / (2.0 * kb);
    assert!((rotation - want).abs() < 1e-7 * want, "{rotation} vs {want}");
}

/// A uniform helix is an equilibrium of an isotropic Kirchhoff rod: constant
/// body strains u (curvature √(u1² + u2²), twist u3) need m_b = K u and, from
/// n_b' = −u × n_b = 0 and m_b' = −u × m_b − e3 × n_b = 0, n_b = (C − K_b)u3·u
/// (derived here; the force lies along the helix axis R u). A cantilever
/// loaded at the tip by exactly that follower force and moment (× Λ, Λ → 1)
/// must take the helix: r(L) = L e3 + (1 − cos ωL)/ω û×e3 + (L − sin ωL/ω)
/// û×(û×e3), ω = |u| (Rodrigues' formula integrated), and m_b = K u at
/// every node.
#[test]
fn uniform_helix_is_an_equilibrium() {
    let (kb, c, l) = (1.0, 0.7, 2.0);
    let u = [0.8, 0.0, 1.5];
    let m = [kb * u[0], kb * u[1], c * u[2]];
    let nb = [(c - kb) * u[2] * u[0], (c - kb) * u[2] * u[1], (c - kb) * u[2] * u[2]];
    let loads =
        Loads { tip_force: Some(Load::follower(nb)), tip_moment: Some(Load::follower(m)), ..Default::default() };
    let rod =
        Rod::new(RodLaw::kirchhoff(kb, kb, c).unwrap(), l, loads, Supports::Cantilever, Scheme::Gauss(4), 12).unwrap();
    let x = solve_at(&rod, 1.0);
    let w = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
    let uh = [u[0] / w, u[1] / w, u[2] / w];
    let cross =
        |a: [f64; 3], b: [f64; 3]| [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    let e3 = [0.0, 0.0, 1.0];
    let (a1, a2) = (cross(uh, e3), cross(uh, cross(uh, e3)));
    let (c1, c2) = ((1.0 - (w * l).cos()) / w, l - (w * l).sin() / w);
    let want =
        [l * e3[0] + c1 * a1[0] + c2 * a2[0], l * e3[1] + c1 * a1[1] + c2 * a2[1], l * e3[2] + c1 * a1[2] + c2 * a2[2]];
    let tip = rod.tip(&x);
    assert!(dist(tip, want) < 1e-9, "tip {tip:?} vs helix {want:?}");
    for i in 0..=rod.elements {
        let y = rod.node_state(&x, i);
        for k in 0..3 {
            assert!(
                (y[10 + k] - m[k]).abs() < 1e-9 && (y[7 + k] - nb[k]).abs() < 1e-9,
                "node {i}: m {:?} n {:?}",
                &y[10..13],
                &y[7..10]
            );
        }
    }
}

/// Self-contact detection (physics.md §2.4): rolled by an end moment the rod
/// closes into a ring, and with a diameter d = 0.05 L the branch reports the
/// first record where its ends come closer than d. Reference: the arc's
/// chord |r(L) − r(0)| = (2L/m)|sin(m/2)| (closed form; the closest
/// non-neighbouring pair near closure is the two ends).
#[test]
fn self_contact_is_reported() {
    let loads = Loads { tip_moment: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
    let rod =
        Rod::new(law(), 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 8).unwrap().with_diameter(0.05).unwrap();
    let opts = Options {
        target_lambda: Some(2.0 * PI),
        residual_tol: 1e-11,
        initial_step: 0.05,
        max_step: 0.05,
        ..Default::default()
    };
    let b = rod.continue_branch(None, 0.0, true, &opts, rodkit::rod::branch::Method::Newton, |_| true).unwrap();
    let c = b.contact.expect("the ring closes: contact");
    let chord = |m: f64| (2.0 / m) * (0.5 * m).sin().abs();
    let m = b.records[c.record].lambda;
    assert!(
        c.distance < 0.05 && (c.distance - chord(m)).abs() < 1e-6,
        "contact at m = {m}: {} vs chord {}",
        c.distance,
        chord(m)
    );
    assert!(chord(b.records[c.record - 1].lambda) >= 0.05, "an earlier record was already in contact");
    assert!(c.s1 < 1e-12 && (c.s2 - 1.0).abs() < 1e-12, "pair ({}, {})", c.s1, c.s2);
    // Without a diameter nothing is checked.
    let plain = Rod::new(law(), 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 8).unwrap();
    assert!(plain
        .continue_branch(None, 0.0, true, &opts, rodkit::rod::branch::Method::Newton, |_| true)
        .unwrap()
        .contact
        .is_none());
}

/// ANM orders: P = 40 works, takes no more steps than P = 20 (longer
/// series, longer steps) and both land on the same follower-cantilever
/// state at α = 10 as Newton continuation (reference: the Newton branch on
/// the same discretisation, residual 1e−12).
#[test]
fn anm_high_order_takes_longer_steps() {
    use rodkit::continuation::anm::AnmOptions;
    use rodkit::rod::branch::Method;
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let loads = Loads { tip_force: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(3), 8).unwrap();
    let run = |method: Method| {
        let opts = Options { target_lambda: Some(10.0), residual_tol: 1e-12, max_step: 5.0, ..Default::default() };
        let b = rod.continue_branch(None, 0.0, true, &opts, method, |_| true).unwrap();
        (rod.tip(b.states.last().unwrap()), b.counts.steps)
    };
    let (reference, _) = run(Method::Newton);
    let (t20, s20) = run(Method::Anm(AnmOptions { order: 20, epsilon: 1e-10, pade: false }));
    let (t40, s40) = run(Method::Anm(AnmOptions { order: 40, epsilon: 1e-10, pade: false }));
    println!("steps: P = 20 → {s20}, P = 40 → {s40}");
    assert!(dist(t20, reference) < 1e-10 && dist(t40, reference) < 1e-10);
    assert!(s40 <= s20, "P = 40 took {s40} steps, P = 20 {s20}");
    // Padé approximants of the same series reach further for the same ε
    // (they continue the series past its radius of convergence), at the
    // same accuracy once corrected.
    for (order, epsilon) in [(10, 1e-8), (10, 1e-10), (15, 1e-10), (20, 1e-10)] {
        let (tp, sp) = run(Method::Anm(AnmOptions { order, epsilon, pade: true }));
        let (ts, ss) = run(Method::Anm(AnmOptions { order, epsilon, pade: false }));
        println!("P = {order}, ε = {epsilon:e}: steps {ss} (series) → {sp} (Padé)");
        assert!(dist(tp, reference) < 1e-10 && dist(ts, reference) < 1e-10);
        assert!(sp <= ss, "Padé took {sp} steps, the series {ss}");
    }
}

/// The shooting reference of [`follower_cantilever_against_planar_shooting`]
/// (its doc): continued in α by 0.25 to 10, the tips at every α (`dense`)
/// and, at α = 1, 2, 5, 10, with the tip angle θ(L) (`reference`).
#[allow(clippy::type_complexity)]
fn planar_shooting(kb: f64, ga: f64, ea: f64) -> (Vec<(f64, [f64; 3], f64)>, Vec<(f64, [f64; 3])>) {
    let integrate = |alpha: f64, theta_l: f64, m0: f64| -> [f64; 4] {
        let n = [alpha * theta_l.cos(), -alpha * theta_l.sin()]; // (n_x, n_z) = α d1(L)
        let f = |y: [f64; 4]| -> [f64; 4] {
            let (s, c) = y[2].sin_cos();
            let (d1, d3) = ([c, -s], [s, c]);
            let (n1, n3) = (n[0] * d1[0] + n[1] * d1[1], n[0] * d3[0] + n[1] * d3[1]);
            let (v1, v3) = (n1 / ga, 1.0 + n3 / ea);
            let rp = [v1 * d1[0] + v3 * d3[0], v1 * d1[1] + v3 * d3[1]];
            [rp[0], rp[1], y[3] / kb, -(rp[1] * n[0] - rp[0] * n[1])]
        };
        let steps = 20000;
        let h = 1.0 / steps as f64;
        let mut y = [0.0, 0.0, 0.0, m0];
        let add =
            |a: [f64; 4], b: [f64; 4], t: f64| [a[0] + t * b[0], a[1] + t * b[1], a[2] + t * b[2], a[3] + t * b[3]];
        for _ in 0..steps {
            let k1 = f(y);
            let k2 = f(add(y, k1, 0.5 * h));
            let k3 = f(add(y, k2, 0.5 * h));
            let k4 = f(add(y, k3, h));
            for i in 0..4 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        y
    };
    // Shooting residual (θ(L) − θ_L, m(L)); Newton with central differences.
    let mut u = [0.0f64, 0.0];
    let mut reference = vec![];
    let mut dense = vec![];
    let targets = [1.0, 2.0, 5.0, 10.0];
    let mut alpha = 0.0;
    while alpha < 10.0 - 1e-12 {
        alpha += 0.25;
        for _ in 0..30 {
            let res = |u: [f64; 2]| {
                let y = integrate(alpha, u[0], u[1]);
                [y[2] - u[0], y[3]]
            };
            let r = res(u);
            if r[0].abs().max(r[1].abs()) < 1e-14 {
                break;
            }
            let h = 1e-7;
            let mut j = [[0.0; 2]; 2];
            for k in 0..2 {
                let (mut up, mut um) = (u, u);
                up[k] += h;
                um[k] -= h;
                let (rp, rm) = (res(up), res(um));
                j[0][k] = (rp[0] - rm[0]) / (2.0 * h);
                j[1][k] = (rp[1] - rm[1]) / (2.0 * h);
            }
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            u[0] -= (j[1][1] * r[0] - j[0][1] * r[1]) / det;
            u[1] -= (-j[1][0] * r[0] + j[0][0] * r[1]) / det;
        }
        let y = integrate(alpha, u[0], u[1]);
        dense.push((alpha, [y[0], 0.0, y[1]]));
        if targets.iter().any(|t| (t - alpha).abs() < 1e-12) {
            reference.push((alpha, [y[0], 0.0, y[1]], u[0]));
        }
    }
    (reference, dense)
}

/// Follower cantilever against our own planar-rod shooting reference
/// (physics.md §2.6; independent code written here): the planar extensible,
/// shearable rod in the x–z plane, tangent d3 = (sin θ, cos θ), d1 =
/// (cos θ, −sin θ), θ' = m/K_b, r' = (n·d1/GA) d1 + (1 + n·d3/EA) d3,
/// m' = −(r'_z n_x − r'_x n_z), with the constant spatial force n = α d1(L)
/// (the follower force perpendicular to the tip tangent). Shooting on
/// (θ(L), m(0)) with RK4 (20000 steps, error ~1e−15) and Newton, continued in
/// α from 0; rodkit (Gauss(4) × 16, ANM) agrees within 1e−9 up to α = 10,
/// where the tip has curled past 90°.
#[test]
fn follower_cantilever_against_planar_shooting() {
    let (kb, ga, ea) = (1.0, 1e4, 2.6e4);
    let (reference, dense) = planar_shooting(kb, ga, ea);
    let law = RodLaw::isotropic(kb, 1.0 / 1.3, ga, ea).unwrap();
    let loads = Loads { tip_force: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 16).unwrap();
    let mut branch: Option<rodkit::rod::branch::RodBranch> = None;
    for (alpha, tip_ref, theta_l) in reference {
        let opts = Options { target_lambda: Some(alpha), residual_tol: 1e-12, max_step: 2.0, ..Default::default() };
        let method = rodkit::rod::branch::Method::Anm(rodkit::continuation::anm::AnmOptions::default());
        let b = match &branch {
            None => rod.continue_branch(None, 0.0, true, &opts, method, |_| true).unwrap(),
            Some(b) => rod.resume_branch(b, &opts, method, |_| true).unwrap(),
        };
        let x = b.states.last().unwrap();
        let tip = rod.tip(x);
        let e = dist(tip, tip_ref);
        println!(
            "α = {alpha}: rodkit {tip:?}, shooting {tip_ref:?}, tip rotation {:.2}°, difference {e:e}",
            theta_l.to_degrees()
        );
        assert!(e < 1e-9, "α = {alpha}: {e:e}");
        assert!((rod.tip_rotation(x) - theta_l).abs() < 1e-9);
        branch = Some(b);
    }
    // Dense output in one run: the 40 loads α = 0.25 … 10 delivered by each
    // engine from its own steps (the ANM from its series, Newton from its
    // Hermite interpolant), each corrected to the tolerance and within 1e−9
    // of the shooting reference.
    let loads: Vec<f64> = dense.iter().map(|d| d.0).collect();
    let opts = Options {
        target_lambda: Some(10.0),
        residual_tol: 1e-12,
        max_step: 2.0,
        samples: loads.clone(),
        ..Default::default()
    };
    let mut factorisations = vec![];
    for method in [
        rodkit::rod::branch::Method::Anm(rodkit::continuation::anm::AnmOptions {
            order: 20,
            epsilon: 1e-10,
            pade: false,
        }),
        rodkit::rod::branch::Method::Newton,
    ] {
        let b = rod.continue_branch(None, 0.0, true, &opts, method, |_| true).unwrap();
        assert!(b.missed_samples.is_empty());
        let got: Vec<f64> = b.samples.iter().map(|s| s.lambda).collect();
        assert_eq!(got, loads, "{method:?}: every load once, in order");
        let mut worst = 0.0f64;
        for ((s, x), (_, tip_ref)) in b.samples.iter().zip(&b.sample_states).zip(&dense) {
            assert!(s.residual <= 1e-12);
            worst = worst.max(dist(rod.tip(x), *tip_ref));
        }
        println!(
            "{method:?}: {} records, {} samples, worst tip error {worst:e}, {:?}",
            b.records.len(),
            b.samples.len(),
            b.counts
        );
        assert!(worst < 1e-9, "{method:?}: dense tip error {worst:e}");
        factorisations.push(b.counts.factorisations);
    }
    // The series is the ANM's advantage: 40 loads cost it few factorisations.
    assert!(
        factorisations[0] * 4 < factorisations[1],
        "factorisations ANM {} vs Newton {}",
        factorisations[0],
        factorisations[1]
    );
}

/// Dense output where the series' step is long (Padé, P = 15, ε = 1e-6):
/// a sample late in a step is not reached by chord iterations on the
/// step's start factorisation, and is corrected on the next point's
/// instead (`Counts::deferred_samples`). Every load is delivered once, in
/// order, to the residual tolerance, and its tip is within 1e-9 of the
/// same rod's point by Newton continuation at 1e-13 (an independent
/// engine; the two differ by the correction tolerance's share of the
/// state). A run that leaves its λ range inside the step that deferred a
/// sample still delivers it (by fresh Newton), never drops it.
#[test]
fn samples_a_step_start_cannot_reach_are_corrected_on_the_next_point() {
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([1.0, 0.0, 0.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 4).unwrap();
    let wanted: Vec<f64> = (1..=19).map(|k| 0.5 * k as f64).collect();
    let start = || Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true };
    let reference = {
        let opts =
            Options { target_lambda: Some(10.0), residual_tol: 1e-13, samples: wanted.clone(), ..Default::default() };
        let mut sys = rod.system().unwrap();
        continue_newton(&mut sys, start(), &opts, |x, _| rod.tip(x).to_vec(), |_| true).unwrap()
    };
    assert!(reference.missed_samples.is_empty());
    let anm = AnmOptions { order: 15, epsilon: 1e-6, pade: true };
    let tol = 1e-9;
    let opts = Options { target_lambda: Some(10.0), residual_tol: tol, samples: wanted.clone(), ..Default::default() };
    let mut sys = rod.system().unwrap();
    let b = continue_anm(&mut sys, start(), &opts, &anm, |x, _| rod.tip(x).to_vec(), |_| true).unwrap();
    println!("{} records, {:?}", b.records.len(), b.counts);
    assert!(b.counts.deferred_samples > 0, "no sample deferred: the test does not reach its path");
    assert!(b.missed_samples.is_empty(), "missed {:?}", b.missed_samples);
    let got: Vec<f64> = b.samples.iter().map(|s| s.lambda).collect();
    assert_eq!(got, wanted, "every load once, in order");
    for (s, r) in b.samples.iter().zip(&reference.samples) {
        assert!(s.residual <= tol, "Λ = {}: residual {:e}", s.lambda, s.residual);
        let e = dist(s.outputs[..3].try_into().unwrap(), r.outputs[..3].try_into().unwrap());
        assert!(e <= 1e-9, "Λ = {}: tip {e:e} from Newton's", s.lambda);
    }
    // Stopped by the λ range inside the step whose late samples were
    // deferred: they are delivered before the run returns.
    let last = b.records.iter().map(|r| r.lambda).find(|&l| l > 0.0).unwrap();
    let last_in_step = wanted.iter().copied().rfind(|&l| l < last).unwrap();
    let opts =
        Options { lambda_range: (-1.0, last - 1e-3), samples: wanted.clone(), residual_tol: tol, ..Default::default() };
    let mut sys = rod.system().unwrap();
    let s = continue_anm(&mut sys, start(), &opts, &anm, |x, _| rod.tip(x).to_vec(), |_| true).unwrap();
    assert_eq!(s.stop, Stop::LambdaRange);
    assert!(s.counts.deferred_samples > 0, "{:?}", s.counts);
    assert!(s.missed_samples.is_empty(), "missed {:?}", s.missed_samples);
    let got: Vec<f64> = s.samples.iter().map(|s| s.lambda).collect();
    assert_eq!(got.last(), Some(&last_in_step), "{got:?}");
    for (x, r) in s.samples.iter().zip(&reference.samples) {
        assert!(
            x.residual <= tol && dist(x.outputs[..3].try_into().unwrap(), r.outputs[..3].try_into().unwrap()) <= 1e-9
        );
    }
}

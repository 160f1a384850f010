//! The charged Kirchhoff rod (issue 5, physics.md §3.1): the electrostatic
//! term in the rod's collocation residual (src/electrostatics/rod.rs) and
//! the supercoiling branch driver (src/electrostatics/supercoil.rs).

#[path = "support/charged.rs"]
mod charged;

use charged::{coiled_state, small_scene};
use rodkit::charged::branch::{self, ChargedBranch};
use rodkit::charged::dna::{self, DnaScene};
use rodkit::charged::rod::{ChargedRod, RodCharge};
use rodkit::continuation::newton::Start;
use rodkit::continuation::{Options, Problem};
use rodkit::electrostatics::{energy, EnergyQuadrature, HermiteCurve, LineCharge};
use rodkit::rod::kinematics::rotation;
use rodkit::rod::model::Rod;

/// The Jacobian (rod + near-zone stiffening + far pairs with the cutoff's
/// switch + hard core + the end-rotation parameter) equals central
/// differences of the residual, column by column, to 1e-6 of the largest
/// entry of its row (differences of step 1e-6·scale: error ~1e-10).
#[test]
fn jacobian_matches_finite_differences() {
    let (rod, charge) = small_scene();
    let x = coiled_state(&rod, 3.0, 3.0);
    let mut p = ChargedRod::new(&rod, &charge, None, &x).unwrap();
    assert!(p.pairs() > 100, "pairs {}", p.pairs());
    let phi = 7.3;
    let worst = charged::jacobian_fd_error(&mut p, &x, phi);
    println!("worst relative Jacobian error {worst:e}");
}

/// The pair forces are minus the gradient of the discrete energy: w_j p_j =
/// −∂(E_far + E_hard)/∂r_j by central differences (step 1e-6 nm, relative
/// 1e-6), on the coiled state with the switch and the hard core active.
#[test]
fn force_is_minus_the_energy_gradient() {
    let (rod, charge) = small_scene();
    let x = coiled_state(&rod, 3.0, 3.0);
    let mut p = ChargedRod::new(&rod, &charge, None, &x).unwrap();
    let (on, off) = p.cutoff().unwrap();
    let f = p.force_densities(&x);
    let pts = p.stage_points();
    let offsets: Vec<usize> = (0..rod.elements).flat_map(|e| [rod.node(e) + 13, rod.node(e) + 26]).collect();
    // Pair distances span the switch and the hard core.
    let r: Vec<[f64; 3]> = offsets.iter().map(|&o| [x[o], x[o + 1], x[o + 2]]).collect();
    let dist = |i: usize, j: usize| {
        ((r[i][0] - r[j][0]).powi(2) + (r[i][1] - r[j][1]).powi(2) + (r[i][2] - r[j][2]).powi(2)).sqrt()
    };
    let n = r.len();
    let far_pairs: Vec<f64> = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .filter(|&(i, j)| i / 2 + 2 < j / 2)
        .map(|(i, j)| dist(i, j))
        .collect();
    assert!(far_pairs.iter().any(|&d| d > on && d < off), "no pair in the switch ({on}, {off})");
    assert!(
        far_pairs.iter().any(|&d| d < rodkit::charged::rod::HARD_CORE_RANGE * charge.screening.a),
        "no pair in the hard core"
    );
    let mut worst = 0.0f64;
    for (j, &o) in offsets.iter().enumerate() {
        for c in 0..3 {
            let eps = 1e-6;
            let mut xp = x.clone();
            let mut xm = x.clone();
            xp[o + c] += eps;
            xm[o + c] -= eps;
            let (ep, em) = (p.energy(&xp), p.energy(&xm));
            let grad = ((ep.far + ep.hard_core) - (em.far + em.hard_core)) / (2.0 * eps);
            let scale = f.iter().map(|v| v[c].abs()).fold(0.0, f64::max) * pts[j].1;
            let e = (pts[j].1 * f[j][c] + grad).abs() / scale;
            worst = worst.max(e);
            assert!(e < 1e-6, "stage {j}, component {c}: w p = {:e}, −∂E = {:e}", pts[j].1 * f[j][c], -grad);
        }
    }
    println!("force vs −gradient: worst {worst:e}");
}

/// Threads split the stages (continuum; base pairs: the sites, then the
/// stages) in fixed chunks and each stage or site sums its pairs in list
/// order: residual and Jacobian bitwise identical for 1, 2 and 3 threads,
/// for both charge models.
#[test]
fn threads_give_bitwise_identical_results() {
    for base_pairs in [None, Some(0.34)] {
        threads_identical(base_pairs);
    }
}

fn threads_identical(base_pairs: Option<f64>) {
    let scene = DnaScene { base_pairs: 400, salt: 0.01, ..Default::default() };
    let rod = scene.rod(40, 2).unwrap();
    let x = coiled_state(&rod, 3.0, 3.4);
    let mut out = Vec::new();
    for threads in [1, 2, 3] {
        let mut charge = scene.charge();
        charge.threads = threads;
        charge.base_pairs = base_pairs;
        let mut p = ChargedRod::new(&rod, &charge, None, &x).unwrap();
        let n = p.dim();
        let mut r = vec![0.0; n];
        p.residual(&x, 4.0, &mut r);
        let mut jx = vec![0.0; p.pattern().nnz()];
        let mut jl = vec![0.0; n];
        p.jacobian(&x, 4.0, &mut jx, &mut jl);
        out.push((r, jx));
    }
    for k in 1..3 {
        assert!(
            out[k].0.iter().zip(&out[0].0).all(|(a, b)| a.to_bits() == b.to_bits()),
            "{base_pairs:?}: residual differs with {} threads",
            k + 1
        );
        assert!(
            out[k].1.iter().zip(&out[0].1).all(|(a, b)| a.to_bits() == b.to_bits()),
            "{base_pairs:?}: Jacobian differs with {} threads",
            k + 1
        );
    }
}

/// A small DNA scene: 300 bp (102 nm) at 1 pN and 0.1 M, 60 elements.
fn scene_300() -> (DnaScene, Rod, RodCharge) {
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let rod = scene.rod(60, 2).unwrap();
    let charge = scene.charge();
    (scene, rod, charge)
}

fn straight_branch(rod: &Rod, charge: &RodCharge, to: f64) -> ChargedBranch {
    let opts = Options {
        target_lambda: Some(to),
        residual_tol: 1e-11,
        initial_step: 0.5,
        max_step: 1.0,
        detect_bifurcations: true,
        max_steps: 200,
        ..Default::default()
    };
    branch::follow(
        rod,
        charge,
        Start::Point { x: rod.straight_state(), lambda: 0.0, increasing: true },
        None,
        &opts,
        |_| true,
    )
    .unwrap()
}

/// Zero charge is the uncharged rod: the same residual (the rod's system at
/// Λ = sin(φ/2)), and the same first buckling point as Rod's own
/// continuation in Λ (φ = 2 atan2(Λ, c)), to 1e-8.
#[test]
fn zero_charge_is_the_uncharged_rod() {
    let (_, rod, mut charge) = scene_300();
    charge.line_charge = 0.0;
    let x = coiled_state(&rod, 3.0, 3.4);
    let mut p = ChargedRod::new(&rod, &charge, None, &x).unwrap();
    let mut sys = rod.system().unwrap();
    let n = p.dim();
    let (mut r1, mut r2) = (vec![0.0; n], vec![0.0; n]);
    let phi = 2.5;
    p.residual(&x, phi, &mut r1);
    sys.residual(&x, (0.5 * phi).sin(), &mut r2);
    let c = rod.end_cosine().unwrap();
    for i in 0..n {
        if i != c {
            assert_eq!(r1[i], r2[i], "row {i}");
        }
    }
    assert_eq!(r1[c], x[c] - (0.5 * phi).cos());
    let charged = straight_branch(&rod, &charge, 40.0);
    let opts = Options {
        target_lambda: Some(0.999),
        residual_tol: 1e-11,
        initial_step: 0.1,
        max_step: 0.2,
        detect_bifurcations: true,
        max_steps: 400,
        ..Default::default()
    };
    let plain = rod.continue_branch(None, 0.0, true, &opts, rodkit::rod::branch::Method::Newton, |_| true).unwrap();
    // φ = 2 atan2(Λ, c) is known modulo 4π (Λ = sin(φ/2) passed its fold at φ = π).
    let phi_plain = rod
        .end_rotation(&plain.bifurcations[0].x, plain.bifurcations[0].lambda)
        .unwrap()
        .rem_euclid(4.0 * std::f64::consts::PI);
    let phi_charged = charged.bifurcations[0].lambda;
    println!("buckling: uncharged solver φ = {phi_plain}, charged solver with λ = 0: {phi_charged}");
    assert!((phi_plain - phi_charged).abs() < 1e-8 * phi_plain, "{phi_plain} vs {phi_charged}");
}
/// The buckled branch of the 300 bp scene (charged), shared by the tests
/// below: switched at the first (double) buckling point, 40 steps.
fn buckled_300() -> &'static (ChargedBranch, ChargedBranch) {
    static B: std::sync::OnceLock<(ChargedBranch, ChargedBranch)> = std::sync::OnceLock::new();
    B.get_or_init(|| {
        let (_, rod, charge) = scene_300();
        let straight = straight_branch(&rod, &charge, 12.0);
        let opts =
            Options { residual_tol: 1e-11, initial_step: 0.05, max_step: 0.5, max_steps: 40, ..Default::default() };
        let b = branch::switch(&rod, &charge, &straight, 0, 0, 0.02, &opts, |_| true).unwrap().0;
        (straight, b)
    })
}

/// G(φ) = E_elastic + E_electrostatic − T z(L) at fixed φ (Newton from `x`).
fn gibbs_at(rod: &Rod, charge: &RodCharge, phase: Option<(usize, f64)>, x: &[f64], phi: f64, tension: f64) -> f64 {
    let mut p = ChargedRod::new(rod, charge, phase, x).unwrap();
    let opts = Options { residual_tol: 1e-12, max_steps: 0, ..Default::default() };
    let b = rodkit::continuation::newton::continue_newton(
        &mut p,
        Start::Point { x: x.to_vec(), lambda: phi, increasing: true },
        &opts,
        |x, _| x.to_vec(),
        |_| true,
    )
    .unwrap();
    let y = &b.records[0].outputs;
    let e = p.energy(y);
    e.elastic + e.near + e.far + e.hard_core - tension * rod.tip(y)[2]
}

/// The residual is the gradient of one energy: along the buckled branch the
/// end torque equals dG/dφ, G = E_elastic + E_es − T z(L) (work theorem
/// at fixed tension; central differences of G at φ ± 1e-4, re-solved).
/// Independent of the residual's assembly: G only sums energies. Agreement
/// within 2e-5 of the torque (the collocation is not exactly variational:
/// O(h⁴)).
#[test]
fn end_torque_is_the_derivative_of_the_energy() {
    let (scene, rod, charge) = scene_300();
    let (_, b) = buckled_300();
    for k in [5, 20, b.records.len() - 1] {
        let (x, phi) = (&b.states[k], b.records[k].lambda);
        let eps = 1e-4;
        let dg = (gibbs_at(&rod, &charge, b.phase, x, phi + eps, scene.tension)
            - gibbs_at(&rod, &charge, b.phase, x, phi - eps, scene.tension))
            / (2.0 * eps);
        let o = dna::observables(&rod, x, phi).unwrap();
        let err = (dg - o.torque).abs() / o.torque.abs();
        println!("φ {phi:.5}: torque {:.8} pN nm, dG/dφ {dg:.8}, relative {err:e}", o.torque);
        assert!(err < 2e-5, "φ {phi}: torque {} vs dG/dφ {dg}", o.torque);
    }
}

/// ΔLk = ΔTw + ΔWr = φ/2π along the charged supercoiling path (straight and
/// buckled): Tw by the collocation's own quadrature of u3, Wr by the Gauss
/// integral with rays (`writhe_within`, ~1e-10). What remains is the
/// twist's quadrature and the state's discretisation: measured 5.8e-7 turns
/// at worst on this path; asserted within 5e-6.
#[test]
fn linking_number_is_the_end_rotation() {
    let (_, rod, _) = scene_300();
    let (straight, b) = buckled_300();
    let mut worst = 0.0f64;
    for (r, x) in
        straight.records.iter().zip(&straight.states).step_by(3).chain(b.records.iter().zip(&b.states).step_by(4))
    {
        let o = dna::observables(&rod, x, r.lambda).unwrap();
        let e = (o.twist + o.writhe - o.turns).abs();
        worst = worst.max(e);
        assert!(e < 5e-6, "φ {}: Tw {} + Wr {} vs {} turns", r.lambda, o.twist, o.writhe, o.turns);
    }
    println!("worst |Tw + Wr − turns| {worst:e}");
    let last = b.states.last().unwrap();
    let o = dna::observables(&rod, last, b.records.last().unwrap().lambda).unwrap();
    assert!(o.writhe > 0.3, "the branch barely writhes: Wr {}", o.writhe);
    println!("worst |Tw + Wr − φ/2π| {worst:e}; last point Tw {} Wr {}", o.twist, o.writhe);
}

/// The continuum energy (electrostatics::energy on the Hermite centreline
/// through nodes and stages with tangents d3; δ = 2 nm, order 8, no cutoff).
fn continuum_energy(rod: &Rod, charge: &RodCharge, x: &[f64]) -> f64 {
    let h = rod.element_length();
    let c = [0.5 - 3f64.sqrt() / 6.0, 0.5 + 3f64.sqrt() / 6.0];
    let (mut s, mut r, mut t) = (vec![], vec![], vec![]);
    for i in 0..=rod.elements {
        let mut push = |o: usize, si: f64| {
            let q = [x[o + 3], x[o + 4], x[o + 5], x[o + 6]];
            let rot = rotation(&q);
            s.push(si);
            r.push([x[o], x[o + 1], x[o + 2]]);
            t.push([rot[0][2], rot[1][2], rot[2][2]]);
        };
        push(rod.node(i), i as f64 * h);
        if i < rod.elements {
            for j in 0..2 {
                push(rod.node(i) + 13 * (1 + j), (i as f64 + c[j]) * h);
            }
        }
    }
    let curve = HermiteCurve::new(s, r, t, false).unwrap();
    energy(
        &curve,
        &LineCharge::Uniform(charge.line_charge),
        &charge.screening,
        &EnergyQuadrature { delta: 2.0, order: 8, cutoff: None },
    )
    .unwrap()
    .total
}

/// The rod's discrete electrostatic energy (stage quadrature, near zone by
/// element runs, cutoff 1e-6) against the continuum energy of the same
/// shapes. The straight rod against §3.5's closed form λ²{L[E1(κa) −
/// E1(κL)] − (e^{−κa} − e^{−κL})/κ}: within 1e-3 (the outer Gauss rule
/// across the kinks of the inner integral at a from each end — a constant
/// of the inextensible rod, no force). The energy of buckling, E(buckled)
/// − E(straight), which is what the mechanics sees (0.3 pN nm of 119 here):
/// within 1e-4 of the total energy of the continuum's (measured 1.8e-5 of
/// the total, 0.7 % of the difference: Gauss(2) on the far elements nearest
/// the near zone, 1.7 nm elements, against a converged continuum rule).
#[test]
fn rod_energy_matches_the_continuum_energy() {
    let (_, rod, charge) = scene_300();
    let (straight, b) = buckled_300();
    let x = b.states.last().unwrap();
    let x0 = &straight.states[0];
    let mut p = ChargedRod::new(&rod, &charge, b.phase, x).unwrap();
    let e = p.energy(x);
    let mut p0 = ChargedRod::new(&rod, &charge, None, x0).unwrap();
    let e0 = p0.energy(x0);
    let (kappa, a, l) = (charge.screening.kappa, charge.screening.a, rod.length);
    let e1 = rodkit::electrostatics::special::e1;
    let exact0 = charge.line_charge.powi(2)
        * (l * (e1(kappa * a) - e1(kappa * l)) - ((-kappa * a).exp() - (-kappa * l).exp()) / kappa);
    let err0 = (e0.near + e0.far - exact0).abs() / exact0;
    let (c1, c0) = (continuum_energy(&rod, &charge, x), continuum_energy(&rod, &charge, x0));
    let (d_rod, d_ref) = (e.near + e.far - e0.near - e0.far, c1 - c0);
    let err = (d_rod - d_ref).abs() / c0.abs();
    println!(
        "straight: rod {} vs exact {exact0} ({err0:e}); buckling energy: rod {d_rod} vs continuum {d_ref} ({err:e})",
        e0.near + e0.far
    );
    assert!(err0 < 1e-3, "{err0:e}");
    assert!(err < 1e-4, "{err:e}");
}

/// Strand crossing: without charge nothing keeps the strands of the loop
/// that forms after buckling apart; with a crossing radius a = 3 nm the
/// buckled branch of the 300 bp rod stops with `crossing` set where
/// non-neighbouring stage points come closer than 2a (independently
/// re-measured here by brute force over all pairs). A stiff hard core
/// (k_hc = 10 pN/nm⁴ below 2.5a) on the same rod keeps every pair farther
/// than 2a over as many steps, so the branch runs on without a crossing.
#[test]
fn strand_crossing_stops_the_branch_and_a_hard_core_prevents_it() {
    let scene = DnaScene { base_pairs: 300, radius: 3.0, ..Default::default() };
    let rod = scene.rod(60, 2).unwrap();
    let mut charge = scene.charge();
    charge.line_charge = 0.0;
    let run = |charge: &RodCharge| {
        let straight = straight_branch(&rod, charge, 12.0);
        let opts =
            Options { residual_tol: 1e-10, initial_step: 0.2, max_step: 1.0, max_steps: 100, ..Default::default() };
        branch::switch(&rod, charge, &straight, 0, 0, 0.02, &opts, |_| true).unwrap().0
    };
    let b = run(&charge);
    let c = b.contact.expect("the uncharged loop crosses itself");
    assert_eq!(b.stop, rodkit::continuation::Stop::Cancelled);
    assert_eq!(c.record, b.records.len() - 1);
    // Brute force over all stage pairs with arc-length gap > πa.
    let closest = |x: &[f64]| {
        let pts: Vec<(f64, [f64; 3])> = (0..rod.elements)
            .flat_map(|e| (0..2).map(move |j| (e, j)))
            .map(|(e, j)| {
                let o = rod.node(e) + 13 * (1 + j);
                let s = (e as f64 + [0.5 - 3f64.sqrt() / 6.0, 0.5 + 3f64.sqrt() / 6.0][j]) * rod.element_length();
                (s, [x[o], x[o + 1], x[o + 2]])
            })
            .collect();
        let mut best = f64::INFINITY;
        for (i, p) in pts.iter().enumerate() {
            for q in &pts[i + 1..] {
                if (q.0 - p.0).abs() > std::f64::consts::PI * scene.radius {
                    best = best.min(
                        ((p.1[0] - q.1[0]).powi(2) + (p.1[1] - q.1[1]).powi(2) + (p.1[2] - q.1[2]).powi(2)).sqrt(),
                    );
                }
            }
        }
        best
    };
    let d = closest(&b.states[c.record]);
    assert!((d - c.distance).abs() < 1e-12 && d < 2.0 * scene.radius, "crossing at {} (brute force {d})", c.distance);
    assert!(closest(&b.states[c.record - 1]) >= 2.0 * scene.radius, "the previous point already crossed");
    println!(
        "uncharged: crossing after {} points at distance {:.3} nm (s = {:.1}, {:.1})",
        b.records.len(),
        c.distance,
        c.s1,
        c.s2
    );
    charge.hard_core = Some(10.0);
    let h = run(&charge);
    assert!(h.contact.is_none(), "hard core crossed: {:?}", h.contact);
    assert!(h.records.len() > b.records.len(), "the hard-core branch stopped early ({:?})", h.stop);
    let dmin = h.states.iter().map(|x| closest(x)).fold(f64::INFINITY, f64::min);
    println!("hard core: {} points, closest approach {dmin:.3} nm (2a = {})", h.records.len(), 2.0 * scene.radius);
    assert!(dmin > 2.0 * scene.radius);
}

/// The buckling torques of the straight clamped rod under tension T and
/// end moment M: the roots of the linearised problem K w'''' − iM w''' −
/// T w'' = 0 (w = x + iy), w = w' = 0 at both ends — w = A + Bs + C e^{ik₊s} +
/// D e^{ik₋s}, k± = (M ± √(M² − 4KT))/2K, and the 4×4 determinant of the
/// end conditions, times e^{−i(k₊+k₋)L/2}, is imaginary: its sign changes,
/// bisected, are the double buckling points (Greenhill's problem with
/// clamped ends; independent of the rod solver).
fn clamped_buckling_torques(k: f64, t: f64, l: f64, count: usize) -> Vec<f64> {
    use nalgebra::{Complex, Matrix4};
    let f = |m: f64| {
        let d = (m * m - 4.0 * k * t).sqrt();
        let (kp, km) = ((m + d) / (2.0 * k), (m - d) / (2.0 * k));
        let (i, one, zero) = (Complex::new(0.0, 1.0), Complex::new(1.0, 0.0), Complex::new(0.0, 0.0));
        let (ep, em) = ((i * kp * l).exp(), (i * km * l).exp());
        #[rustfmt::skip]
        let a = Matrix4::new(
            one, zero, one, one,
            zero, one, i * kp, i * km,
            one, Complex::new(l, 0.0), ep, em,
            zero, one, i * kp * ep, i * km * em,
        );
        (a.determinant() * (-i * 0.5 * (kp + km) * l).exp()).im
    };
    let m0 = 2.0 * (k * t).sqrt();
    let mut roots = vec![];
    let (mut a, mut fa) = (m0 * (1.0 + 1e-9), f(m0 * (1.0 + 1e-9)));
    let dm = m0 * 1e-4;
    while roots.len() < count {
        let (b, fb) = (a + dm, f(a + dm));
        if fa * fb < 0.0 {
            let (mut lo, mut hi, mut flo) = (a, b, fa);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                let fm = f(mid);
                if fm * flo < 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                    flo = fm;
                }
            }
            roots.push(0.5 * (lo + hi));
        }
        (a, fa) = (b, fb);
    }
    roots
}

/// The DNA scene finds the *first* buckling point of the straight rod: the
/// double points crowd above Greenhill's 2√(KT) (0.1 turn apart at 1 kbp;
/// the determinant's sign does not change at a double point, and large
/// steps once jumped over three of them). Uncharged, the scene's buckling
/// torque is the first analytic root above (28.946 pN nm) to 1e-7
/// (measured 1e-8 on 50 elements); charged (0.1 M), it lies between the
/// uncharged rod's first and second roots (charge stiffens the rod by
/// ~0.3 % here), and the buckling turns are M L / (2π C) of the straight
/// twisted rod.
#[test]
fn dna_scene_finds_the_first_buckling_point() {
    let base = DnaScene::default();
    let kt = base.kt();
    let (k, c) = (base.bending_persistence * kt, base.twist_persistence * kt);
    let l = base.base_pairs as f64 * base.rise;
    let roots = clamped_buckling_torques(k, base.tension, l, 2);
    let settings = dna::SupercoilSettings { elements: 50, max_steps: 30, ..Default::default() };
    let uncharged = DnaScene { charge_per_length: 0.0, ..base.clone() };
    let (phi0, m0) = dna::run_scene(&uncharged, &settings).unwrap().buckling.expect("uncharged buckling");
    let (phi1, m1) = dna::run_scene(&base, &settings).unwrap().buckling.expect("charged buckling");
    println!("analytic roots {roots:?}; scene uncharged M {m0} (φ {phi0}), charged M {m1} (φ {phi1})");
    // The critical torque of Gauss(2) on 50 elements carries the scheme's
    // O(h⁴) error (measured 9.7e-9 relative); 1e-7 leaves 10× for it and
    // for the location's own tolerance.
    assert!((m0 - roots[0]).abs() < 1e-7 * roots[0], "uncharged {m0} vs {}", roots[0]);
    // φ = ML/C of the straight twisted rod up to the collocation of the
    // rotation, O((h u₃)⁴): measured 5.6e-6 on 50 elements (both rods).
    let (d0, d1) = ((phi0 - m0 * l / c).abs() / phi0, (phi1 - m1 * l / c).abs() / phi1);
    println!("φ against ML/C: {d0:e} uncharged, {d1:e} charged");
    assert!(d0 < 2e-5 && d1 < 2e-5);
    assert!(m1 > roots[0] && m1 < roots[1], "charged {m1} not between {roots:?}");
}

/// The charged DNA scene under a torque clamp (EndControl::Torque: the end
/// moment is the parameter) against the same scene under rotation control
/// (an independent continuation along another parametrisation): the
/// buckling point to 1e-6 in φ and M (both located to 1e-7 in arc length),
/// and every torque-clamp buckled point on the rotation-controlled path from
/// the buckling torque down to the plateau's minimum, where M decreases
/// monotonically along it: φ(M) and the extension z(M) of that path by
/// 4-point Lagrange interpolation in M (the path's points up to 1.7 pN nm
/// apart; not within 0.5 pN nm of the minimum, a fold of M) within 2e-3
/// rad and 0.1 nm. Past buckling the end turns further
/// while the torque falls, then φ folds back with M still falling (a
/// regular point for the clamp), down to the plateau.
#[test]
fn torque_clamp_follows_the_rotation_controlled_path() {
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    // Steps aimed at 3 Newton iterations: the torque-clamp points dense
    // enough to compare (~20 before the plateau's minimum).
    let base = dna::SupercoilSettings {
        elements: 40,
        max_steps: 60,
        max_turns: 2.2,
        corrector_aim: 3.0,
        ..Default::default()
    };
    // The reference path by the Euler-predictor engine: its shorter steps
    // keep the 4-point interpolation below (the reference's own error) at
    // ~1e-4 rad; the Hermite engine's points are 2× farther apart.
    let rotation =
        dna::run_scene(&scene, &dna::SupercoilSettings { engine: dna::Engine::Newton, ..base.clone() }).unwrap();
    let torque = dna::run_scene(
        &scene,
        &dna::SupercoilSettings { control: dna::EndControl::Torque, max_steps: 40, ..base.clone() },
    )
    .unwrap();
    let (br, bt) = (rotation.buckling.unwrap(), torque.buckling.unwrap());
    println!("buckling: rotation control φ {} M {}; torque clamp φ {} M {}", br.0, br.1, bt.0, bt.1);
    assert!((br.0 - bt.0).abs() < 1e-6 * br.0 && (br.1 - bt.1).abs() < 1e-6 * br.1, "{br:?} vs {bt:?}");
    // A clamp point's parameter is the torque its shape exerts (the end
    // moment computed from the state), and under either control the turns
    // (φ from the end rotation; under the clamp read from the state and
    // followed by continuity) are the linking number Tw + Wr of the shape
    // (twist from the strains, writhe by the Gauss integral: independent;
    // the writhe to ~1e-10, the twist's quadrature and the discretisation
    // leave 2.9e-6 turns at worst on these paths, measured; asserted 2e-5).
    for p in &torque.points {
        assert!(
            (p.parameter - p.observables.torque).abs() < 1e-6 * p.parameter.abs().max(1.0),
            "Λ {} vs torque {}",
            p.parameter,
            p.observables.torque
        );
    }
    let mut worst_lk = 0.0f64;
    for p in rotation.points.iter().chain(&torque.points) {
        let lk = p.observables.twist + p.observables.writhe;
        worst_lk = worst_lk.max((lk - p.phi / (2.0 * std::f64::consts::PI)).abs());
        assert!(
            (lk - p.phi / (2.0 * std::f64::consts::PI)).abs() < 2e-5,
            "Tw + Wr {lk} vs turns {}",
            p.phi / (2.0 * std::f64::consts::PI)
        );
    }
    println!("worst |Tw + Wr − turns| {worst_lk:e}");
    // The rotation-controlled buckled path while M falls: (M, φ, z).
    let mut path: Vec<(f64, f64, f64)> = vec![];
    for p in rotation.points.iter().filter(|p| p.branch == 1) {
        if path.last().is_some_and(|q| p.observables.torque >= q.0) {
            break;
        }
        path.push((p.observables.torque, p.phi, p.observables.extension));
    }
    assert!(path.len() > 20 && path.last().unwrap().0 < 0.2 * br.1, "the rotation path's falling torque: {path:?}");
    let lagrange = |m: f64, k: usize, f: fn(&(f64, f64, f64)) -> f64| -> f64 {
        let pts = &path[k..k + 4];
        (0..4)
            .map(|i| {
                f(&pts[i]) * (0..4).filter(|&j| j != i).map(|j| (m - pts[j].0) / (pts[i].0 - pts[j].0)).product::<f64>()
            })
            .sum()
    };
    let mut compared = 0;
    let mut worst: (f64, f64) = (0.0, 0.0);
    let mut previous = f64::INFINITY;
    for p in torque.points.iter().filter(|p| p.branch == 1) {
        let m = p.observables.torque;
        if m >= previous {
            break; // past the plateau's minimum
        }
        previous = m;
        // The four path points around m (M falls along the path).
        // Not next to the fold of M at the plateau's minimum, where φ(M)
        // has a square-root singularity that no polynomial follows.
        if m < path.last().unwrap().0 + 0.5 {
            continue;
        }
        let Some(i) = path.windows(2).position(|w| w[0].0 >= m && m >= w[1].0) else { continue };
        let k = i.saturating_sub(1).min(path.len() - 4);
        let (phi, z) = (lagrange(m, k, |q| q.1), lagrange(m, k, |q| q.2));
        worst = (worst.0.max((p.phi - phi).abs()), worst.1.max((p.observables.extension - z).abs()));
        assert!((p.phi - phi).abs() < 2e-3, "M {m}: φ {} (clamp) vs {phi} (rotation control)", p.phi);
        assert!((p.observables.extension - z).abs() < 0.1, "M {m}: extension {} vs {z}", p.observables.extension);
        compared += 1;
    }
    println!(
        "{compared} torque-clamp points on the rotation-controlled path (worst {:.1e} rad, {:.1e} nm)",
        worst.0, worst.1
    );
    assert!(compared >= 20, "only {compared} comparable points");
}

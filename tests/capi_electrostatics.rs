//! The curve electrostatics/writhe C ABI from Rust: results equal the Rust
//! API's on a ring (and the §3.5 Coulomb ring formula to the near-zone
//! truncation), validation by name, nothing written on failure.

use rodkit::capi::curve::*;
use rodkit::capi::error::rodkit_last_error_message;
use rodkit::Status;
use std::f64::consts::PI;
use std::ffi::CStr;

fn last_error() -> String {
    unsafe { CStr::from_ptr(rodkit_last_error_message()) }.to_string_lossy().into_owned()
}

/// `rodkit_dna_supercoil_spec_default`'s spec.
fn supercoil_spec() -> rodkit::capi::supercoil::DnaSupercoilSpec {
    use rodkit::capi::supercoil::*;
    let mut spec = std::mem::MaybeUninit::<DnaSupercoilSpec>::uninit();
    assert_eq!(unsafe { rodkit_dna_supercoil_spec_default(spec.as_mut_ptr()) }, 0);
    unsafe { spec.assume_init() }
}

/// The summary of a C run and its points, as many as the summary counts.
fn supercoil_points(
    run: *mut rodkit::capi::supercoil::Supercoil,
) -> (rodkit::capi::supercoil::SupercoilInfo, Vec<rodkit::capi::supercoil::SupercoilPoint>) {
    use rodkit::capi::supercoil::*;
    let mut info = SupercoilInfo::default();
    assert_eq!(unsafe { rodkit_supercoil_summary(run, &mut info) }, 0);
    let mut points = vec![SupercoilPoint::default(); info.points as usize];
    let mut count = 0;
    assert_eq!(unsafe { rodkit_supercoil_points(run, points.as_mut_ptr(), info.points, &mut count) }, 0);
    assert_eq!(count, info.points);
    (info, points)
}

#[test]
fn ring_energy_writhe_and_validation() {
    // A unit ring through 201 nodes (the last repeats the first), tangents exact.
    let n = 201;
    let s: Vec<f64> = (0..n).map(|k| 2.0 * PI * k as f64 / (n - 1) as f64).collect();
    let xyz: Vec<f64> = s.iter().flat_map(|&v| [v.cos(), v.sin(), 0.0]).collect();
    let tan: Vec<f64> = s.iter().flat_map(|&v| [-v.sin(), v.cos(), 0.0]).collect();
    let mut spec = std::mem::MaybeUninit::<ElectrostaticsSpec>::uninit();
    assert_eq!(unsafe { rodkit_electrostatics_spec_default(spec.as_mut_ptr()) }, 0);
    let mut spec = unsafe { spec.assume_init() };
    let mut out = ElectrostaticEnergy::default();
    // The energy of this ring through the C ABI, with arc lengths `s` (NULL
    // allowed) and the closed flag.
    let energy = |s: *const f64, closed: i32, spec: &ElectrostaticsSpec, out: &mut ElectrostaticEnergy| unsafe {
        rodkit_curve_electrostatic_energy(s, xyz.as_ptr(), 3, tan.as_ptr(), 3, n as i64, closed, spec, out)
    };
    // Unset fields are refused by name.
    assert_eq!(energy(s.as_ptr(), 1, &spec, &mut out), Status::ErrNotFinite.code());
    assert!(last_error().contains("spec.line_charge"), "{}", last_error());
    (spec.line_charge, spec.kappa, spec.a, spec.near_width) = (1.0, 0.0, 0.02, 0.1);
    assert_eq!(energy(s.as_ptr(), 1, &spec, &mut out), 0, "{}", last_error());
    // §3.5 Coulomb ring 2πR ln cot(a/4R), less the dropped near-zone term
    // 2πR·7δ⁴/(23040R⁴) (tests/electrostatics.rs), Hermite nodes adding O(h⁴).
    let exact =
        2.0 * PI * (1.0 / (0.02f64 / 4.0).tan()).ln() - 2.0 * PI * 7.0 * (0.1f64.powi(4) - 0.02f64.powi(4)) / 23040.0;
    assert!((out.total - exact).abs() < 1e-6 * exact, "{} vs {exact}", out.total);
    assert!((out.near + out.far - out.total).abs() < 1e-12 * out.total);
    let mut wr = f64::NAN;
    assert_eq!(
        unsafe { rodkit_curve_writhe(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, n as i64, 1, 8, &mut wr) },
        0
    );
    assert!(wr.abs() < 1e-12, "{wr}");
    let mut e_bp = f64::NAN;
    assert_eq!(
        unsafe {
            rodkit_curve_base_pair_energy(
                s.as_ptr(),
                xyz.as_ptr(),
                3,
                tan.as_ptr(),
                3,
                n as i64,
                1,
                &spec,
                0.002,
                &mut e_bp,
            )
        },
        0
    );
    // The base-pair sum differs from the continuum at O(b/a) (5 % at b = a/2).
    assert!((e_bp - out.total).abs() < 0.02 * out.total, "{e_bp} vs {}", out.total);
    // Validation: near zone inside the excluded distance, NULL, closed flag,
    // too few nodes, a zero tangent, a short leading dimension; nothing written.
    let before = out;
    spec.near_width = 0.01;
    assert_eq!(energy(s.as_ptr(), 1, &spec, &mut out), Status::ErrOutOfRange.code());
    assert!(last_error().contains("spec.near_width"), "{}", last_error());
    spec.near_width = 0.1;
    assert_eq!(energy(std::ptr::null(), 1, &spec, &mut out), Status::ErrNullPointer.code());
    assert_eq!(energy(s.as_ptr(), 2, &spec, &mut out), Status::ErrOutOfRange.code());
    assert!(last_error().contains("closed"));
    assert!(unsafe { rodkit_curve_writhe(s.as_ptr(), xyz.as_ptr(), 3, tan.as_ptr(), 3, 1, 1, 8, &mut wr) } < 0);
    assert!(last_error().contains("nodes"));
    let mut bad = tan.clone();
    bad[3..6].fill(0.0);
    assert_eq!(
        unsafe { rodkit_curve_writhe(s.as_ptr(), xyz.as_ptr(), 3, bad.as_ptr(), 3, n as i64, 1, 8, &mut wr) },
        Status::ErrOutOfRange.code()
    );
    assert!(last_error().contains("tangents"));
    assert!(unsafe { rodkit_curve_writhe(s.as_ptr(), xyz.as_ptr(), 2, tan.as_ptr(), 3, n as i64, 1, 8, &mut wr) } < 0);
    assert_eq!((out.total, out.near, out.far), (before.total, before.near, before.far));
}

/// `rodkit_supercoil_solve_point` from Rust on a small run made through the
/// C ABI (300 bp, 40 elements, 20 steps): its result equals the Rust API's
/// `solve_point` on the same scene (same arithmetic, 1e-12), the shape is
/// written when asked, and bad arguments are statuses naming the argument.
#[test]
fn supercoil_solve_point_through_the_c_abi() {
    use rodkit::capi::equilibrium::*;
    use rodkit::capi::supercoil::*;
    use rodkit::charged::dna::{run_scene, DnaScene, SupercoilSettings};
    use rodkit::charged::equilibrium::{solve_point, EquilibriumSolver as Solver};
    let mut spec = supercoil_spec();
    (spec.base_pairs, spec.elements, spec.max_steps) = (300, 40, 20);
    let mut run: *mut Supercoil = std::ptr::null_mut();
    assert!(unsafe { rodkit_dna_supercoil_run(&spec, &mut run) } >= 0, "{}", last_error());
    let mut info = SupercoilInfo::default();
    assert_eq!(unsafe { rodkit_supercoil_summary(run, &mut info) }, 0);
    let last = info.points - 1;
    let mut es = std::mem::MaybeUninit::<EquilibriumSpec>::uninit();
    assert_eq!(unsafe { rodkit_equilibrium_spec_default(es.as_mut_ptr()) }, 0);
    let mut es = unsafe { es.assume_init() };
    es.discrete_base_pairs = 1;
    let mut out = Equilibrium::default();
    let mut xyz = vec![0.0; 3 * info.nodes as usize];
    assert_eq!(
        unsafe { rodkit_supercoil_solve_point(run, last, &es, &mut out, xyz.as_mut_ptr(), 3, info.nodes) },
        0,
        "{}",
        last_error()
    );
    // The Rust API on the same scene.
    let r = run_scene(
        &DnaScene { base_pairs: 300, ..Default::default() },
        &SupercoilSettings { elements: 40, max_steps: 20, ..Default::default() },
    )
    .unwrap();
    let mut charge = r.charge.clone();
    charge.base_pairs = Some(r.scene.rise);
    let p = solve_point(&r, last as usize, &charge, Solver::NewtonKrylov, 1e-10).unwrap();
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(
        rel(out.torque, p.observables.torque) < 1e-12 && rel(out.extension, p.observables.extension) < 1e-12,
        "{out:?} vs {p:?}"
    );
    assert_eq!(
        (out.newton_iterations, out.linear_iterations),
        (p.newton_iterations as i64, p.linear_iterations as i64)
    );
    // Buckled: the whole Jacobian preconditions (src/electrostatics/equilibrium.rs).
    assert_eq!(out.preconditioner_band as usize, r.buckled.as_ref().unwrap().states[0].len());
    let tip = r.rod.positions(&p.state).last().copied().unwrap();
    assert!(
        (xyz[xyz.len() - 1] - tip[2]).abs() < 1e-12 * tip[2].abs()
            && (xyz[xyz.len() - 1] - out.extension).abs() < 1e-12
    );
    // The direct solver agrees (7e-10 nm measured on the shape).
    es.solver = EquilibriumSolver::Direct as i32;
    let mut direct = Equilibrium::default();
    assert_eq!(
        unsafe { rodkit_supercoil_solve_point(run, last, &es, &mut direct, std::ptr::null_mut(), 0, 0) },
        0,
        "{}",
        last_error()
    );
    assert!(rel(direct.torque, out.torque) < 1e-9 && direct.linear_iterations == 0 && direct.preconditioner_band == 0);
    // Validation by name; nothing written on failure.
    let before = out;
    es.solver = 7;
    assert_eq!(
        unsafe { rodkit_supercoil_solve_point(run, last, &es, &mut out, std::ptr::null_mut(), 0, 0) },
        Status::ErrOutOfRange.code()
    );
    assert!(last_error().contains("spec.solver"), "{}", last_error());
    es.solver = EquilibriumSolver::NewtonKrylov as i32;
    es.residual_tol = f64::NAN;
    assert!(unsafe { rodkit_supercoil_solve_point(run, last, &es, &mut out, std::ptr::null_mut(), 0, 0) } < 0);
    assert!(last_error().contains("spec.residual_tol"), "{}", last_error());
    es.residual_tol = 1e-10;
    es.discrete_base_pairs = 2;
    assert_eq!(
        unsafe { rodkit_supercoil_solve_point(run, last, &es, &mut out, std::ptr::null_mut(), 0, 0) },
        Status::ErrOutOfRange.code()
    );
    es.discrete_base_pairs = 1;
    assert_eq!(
        unsafe { rodkit_supercoil_solve_point(run, info.points, &es, &mut out, std::ptr::null_mut(), 0, 0) },
        // An index out of range is ErrOutOfRange (issue 17: -8 is for array lengths).
        Status::ErrOutOfRange.code()
    );
    assert!(last_error().contains("point"), "{}", last_error());
    assert_eq!(
        unsafe { rodkit_supercoil_solve_point(run, last, &es, &mut out, xyz.as_mut_ptr(), 3, info.nodes - 1) },
        Status::ErrInvalidDimension.code()
    );
    assert_eq!(
        unsafe { rodkit_supercoil_solve_point(std::ptr::null(), last, &es, &mut out, std::ptr::null_mut(), 0, 0) },
        Status::ErrNullPointer.code()
    );
    assert_eq!(
        unsafe { rodkit_supercoil_solve_point(run, last, std::ptr::null(), &mut out, std::ptr::null_mut(), 0, 0) },
        Status::ErrNullPointer.code()
    );
    assert_eq!((out.torque, out.shift), (before.torque, before.shift));
    unsafe { rodkit_supercoil_free(run) };
}

/// A torque clamp through the C ABI (`end_control` = TORQUE): the run equals
/// the Rust API's under EndControl::Torque (1e-12: same arithmetic), its
/// points report the turns read from each state, the same buckling point
/// as rotation control (1e-6; tests/charged_rod.rs compares the paths);
/// `rodkit_supercoil_solve_point` re-solves a torque-clamp point at its
/// torque (same model: the same shape, 1e-6 nm, and torque); a bad
/// `end_control` is a status naming it.
#[test]
fn torque_clamp_supercoil_through_the_c_abi() {
    use rodkit::capi::equilibrium::*;
    use rodkit::capi::supercoil::*;
    use rodkit::charged::dna::{run_scene, DnaScene, EndControl as Control, SupercoilSettings};
    let mut spec = supercoil_spec();
    assert_eq!(spec.end_control, EndControl::Rotation as i32);
    (spec.base_pairs, spec.elements, spec.max_steps) = (300, 40, 25);
    let mut run: *mut Supercoil = std::ptr::null_mut();
    spec.end_control = 3;
    assert_eq!(unsafe { rodkit_dna_supercoil_run(&spec, &mut run) }, Status::ErrOutOfRange.code());
    assert!(last_error().contains("end_control"), "{}", last_error());
    assert!(run.is_null());
    spec.end_control = EndControl::Torque as i32;
    assert!(unsafe { rodkit_dna_supercoil_run(&spec, &mut run) } >= 0, "{}", last_error());
    let (info, points) = supercoil_points(run);
    let settings = SupercoilSettings { elements: 40, max_steps: 25, ..Default::default() };
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let r = run_scene(&scene, &SupercoilSettings { control: Control::Torque, ..settings.clone() }).unwrap();
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
    assert_eq!(points.len(), r.points.len());
    for (c, p) in points.iter().zip(&r.points) {
        assert!(
            rel(c.turns, p.observables.turns) < 1e-12 && rel(c.torque, p.observables.torque) < 1e-12,
            "{c:?} vs {p:?}"
        );
        // The torque clamp's turns (read from the end rotation, followed by
        // continuity) are the shape's linking number (writhe quadrature 1e-4).
        assert!((c.twist + c.writhe - c.turns).abs() < 1e-4, "Tw + Wr {} vs turns {}", c.twist + c.writhe, c.turns);
    }
    let (phi_b, m_b) = r.buckling.unwrap();
    assert!(
        rel(info.buckling_turns, phi_b / (2.0 * std::f64::consts::PI)) < 1e-12
            && rel(info.buckling_torque, m_b) < 1e-12
    );
    let rot = run_scene(&scene, &SupercoilSettings { max_steps: 5, ..settings }).unwrap().buckling.unwrap();
    assert!(rel(phi_b, rot.0) < 1e-6 && rel(m_b, rot.1) < 1e-6, "torque clamp {:?} vs rotation {rot:?}", (phi_b, m_b));
    // A buckled point re-solved at its torque, same model: the one whose
    // torque is midway between the buckling torque and the branch's
    // smallest (the torque clamp's Jacobian is singular at that minimum, a
    // fold in M, where a re-solve moves the shape by far more than the
    // residual tolerance: 4.6e-6 nm at the 25th step's 5.53 pN nm).
    let m_min = points.iter().filter(|p| p.branch == 1).map(|p| p.torque).fold(f64::INFINITY, f64::min);
    let mid = 0.5 * (m_b + m_min);
    let last = (0..info.points)
        .filter(|&k| points[k as usize].branch == 1)
        .min_by(|&a, &b| (points[a as usize].torque - mid).abs().total_cmp(&(points[b as usize].torque - mid).abs()))
        .expect("a buckled point");
    let mut es = std::mem::MaybeUninit::<EquilibriumSpec>::uninit();
    assert_eq!(unsafe { rodkit_equilibrium_spec_default(es.as_mut_ptr()) }, 0);
    let mut es = unsafe { es.assume_init() };
    es.solver = EquilibriumSolver::Direct as i32;
    let mut out = Equilibrium::default();
    assert_eq!(
        unsafe { rodkit_supercoil_solve_point(run, last, &es, &mut out, std::ptr::null_mut(), 0, 0) },
        0,
        "{}",
        last_error()
    );
    let p = points[last as usize];
    assert_eq!(p.branch, 1);
    println!(
        "re-solved: shift {:e} nm, turns {} vs {}, torque {} vs {}",
        out.shift, out.turns, p.turns, out.torque, p.torque
    );
    assert!(
        out.shift < 1e-6 && (out.turns - p.turns).abs() < 1e-8 && rel(out.torque, p.torque) < 1e-8,
        "{out:?} vs {p:?}"
    );
    unsafe { rodkit_supercoil_free(run) };
}

/// The automatic mesh (`elements` 0, the default of both APIs): ⌈L / 2 nm⌉
/// elements, at least 8 — closed form: 1 kbp (340 nm) 170, 3 kbp 510, 300
/// bp (102 nm) 51, 20 bp (6.8 nm) 8 — the count a run took in its rod, its
/// settings and (C) its shapes' nodes, and a mesh past 2^18 elements
/// refused before any work with a status saying what it would take.
#[test]
fn the_automatic_mesh_takes_2_nm_elements_and_says_how_many() {
    use rodkit::capi::supercoil::*;
    use rodkit::charged::dna::{run_scene, DnaScene, SupercoilSettings};
    let auto = SupercoilSettings::default();
    assert_eq!(auto.elements, 0);
    for (bp, n) in [(1000, 170), (3000, 510), (300, 51), (20, 8)] {
        assert_eq!(auto.elements_for(&DnaScene { base_pairs: bp, ..Default::default() }).unwrap(), n, "{bp} bp");
    }
    let huge = auto.elements_for(&DnaScene { base_pairs: 2_000_000, ..Default::default() }).unwrap_err();
    assert_eq!(huge.status, rodkit::Status::ErrOutOfRange);
    assert!(huge.message.contains("2^18") && huge.message.contains("give `elements`"), "{}", huge.message);
    // A short run of the 300 bp scene on the automatic mesh (straight
    // branch only: 3 steps).
    let r = run_scene(
        &DnaScene { base_pairs: 300, ..Default::default() },
        &SupercoilSettings { max_steps: 3, ..Default::default() },
    )
    .unwrap();
    assert_eq!((r.rod.elements, r.settings.elements), (51, 51));
    // The C default is the automatic mesh too, and the result's nodes say
    // which mesh was taken.
    let mut spec = supercoil_spec();
    assert_eq!(spec.elements, 0);
    (spec.base_pairs, spec.max_steps) = (300, 3);
    let mut run: *mut Supercoil = std::ptr::null_mut();
    assert!(unsafe { rodkit_dna_supercoil_run(&spec, &mut run) } >= 0, "{}", last_error());
    let mut info = SupercoilInfo::default();
    assert_eq!(unsafe { rodkit_supercoil_summary(run, &mut info) }, 0);
    assert_eq!(info.nodes, 52);
    unsafe { rodkit_supercoil_free(run) };
    spec.base_pairs = 2_000_000;
    let mut run: *mut Supercoil = std::ptr::null_mut();
    assert_eq!(unsafe { rodkit_dna_supercoil_run(&spec, &mut run) }, rodkit::Status::ErrOutOfRange.code());
    assert!(run.is_null() && last_error().contains("2^18"), "{}", last_error());
    spec.elements = 1;
    assert_eq!(unsafe { rodkit_dna_supercoil_run(&spec, &mut run) }, rodkit::Status::ErrOutOfRange.code());
}

/// `RodkitDnaSupercoilSpec.tolerance` (the curve's relative accuracy; what
/// it sets today is the unfolding check's moment bound, a tenth of it of
/// one turn's torque): the default is the Rust default (1e-3); outside
/// (0, 0.1] it is a status naming it, before any work; inside, the C run
/// equals the Rust run with the same tolerance (1e-12: the same
/// arithmetic). The bound acts only once |μ| passes 1e-6 of its scale
/// (the 1 kbp plectoneme past ~10 turns), so on this short scene every
/// tolerance gives the same path; the check itself is tested in
/// tests/supercoil_hard_core.rs.
#[test]
fn tolerance_through_the_c_abi() {
    use rodkit::capi::supercoil::*;
    use rodkit::charged::dna::{run_scene, DnaScene, SupercoilSettings};
    let mut spec = supercoil_spec();
    assert_eq!(spec.tolerance, SupercoilSettings::default().tolerance);
    assert_eq!(spec.tolerance, 1e-3);
    (spec.base_pairs, spec.elements, spec.max_turns, spec.max_steps) = (300, 40, 1.5, 40);
    let mut run: *mut Supercoil = std::ptr::null_mut();
    for (bad, status) in [
        (0.2, Status::ErrOutOfRange),
        (0.0, Status::ErrOutOfRange),
        (-1e-3, Status::ErrOutOfRange),
        (f64::NAN, Status::ErrNotFinite),
    ] {
        spec.tolerance = bad;
        assert_eq!(unsafe { rodkit_dna_supercoil_run(&spec, &mut run) }, status.code(), "{bad}");
        assert!(last_error().contains("tolerance"), "{}", last_error());
        assert!(run.is_null());
    }
    spec.tolerance = 0.05;
    // The step limit (an INFO status, ≥ 0) ends both runs alike.
    assert!(unsafe { rodkit_dna_supercoil_run(&spec, &mut run) } >= 0, "{}", last_error());
    let (_, points) = supercoil_points(run);
    unsafe { rodkit_supercoil_free(run) };
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let settings =
        SupercoilSettings { elements: 40, max_turns: 1.5, max_steps: 40, tolerance: 0.05, ..Default::default() };
    let r = run_scene(&scene, &settings).unwrap();
    assert_eq!(points.len(), r.points.len());
    assert!(r.buckled.is_some());
    for (c, p) in points.iter().zip(&r.points) {
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
        assert!(
            rel(c.torque, p.observables.torque) < 1e-12 && rel(c.turns, p.observables.turns) < 1e-12,
            "{c:?} vs {p:?}"
        );
    }
}

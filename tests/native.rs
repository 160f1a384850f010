//! The C, C++ and Fortran drivers, built (through the Makefile) against the
//! shared and the static library and run; their printed numbers are compared
//! with the Rust API on the inputs they echo, and the C drivers are run under
//! valgrind. Needs gcc, g++, gfortran, make and valgrind (`.ci/deps`).

use rodkit::tube::{OrthotropicSurface, ThinTube};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

#[path = "support/native_build.rs"]
mod native_build;
use native_build::{check, profile, ROOT};

/// The library, then the drivers, in this test build's target directory.
fn drivers() -> &'static PathBuf {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(|| native_build::build_in_test_target(&["drivers"]))
}

fn run(exe: &str, args: &[&str]) -> String {
    let out = Command::new(drivers().join(exe)).args(args).current_dir(ROOT).output().expect(exe);
    check(out, exe)
}

/// A driver with `--values`: its short report and every result as a
/// `name = value` line (the channel these tests read).
fn run_values(exe: &str, args: &[&str]) -> String {
    let mut all = vec!["--values"];
    all.extend_from_slice(args);
    run(exe, &all)
}

/// Every `name = number` line of a driver's output.
fn values(text: &str) -> BTreeMap<String, f64> {
    text.lines()
        .filter_map(|l| {
            let (k, v) = l.split_once(" = ")?;
            let k = k.trim();
            let v = v.trim().parse::<f64>().ok()?;
            (!k.starts_with('#')).then(|| (k.to_string(), v))
        })
        .collect()
}

/// The Rust API's answers for the inputs a driver echoed.
fn expected(v: &BTreeMap<String, f64>) -> BTreeMap<String, f64> {
    let g = |k: &str| *v.get(k).unwrap_or_else(|| panic!("driver did not print `{k}`"));
    let mat = OrthotropicSurface::new(g("e1"), g("e2"), g("nu12"), g("g12")).unwrap();
    let tube = ThinTube::new(g("mid_radius"), g("thickness"), g("intrinsic_twist"), mat).unwrap();
    let c = tube.coupling_stiffness().unwrap();
    let mut e = BTreeMap::new();
    let names = ["strain", "twist", "hoop"];
    for i in 0..3 {
        for j in 0..3 {
            e.insert(format!("K_{}_{}", names[i], names[j]), c.k[(i, j)]);
        }
    }
    let law = c.stretch_twist();
    e.insert("stretch_modulus_S".into(), law.stretch);
    e.insert("twist_stretch_g".into(), law.coupling);
    e.insert("twist_modulus_C".into(), law.twist);
    let rod = tube.rod_stiffness().unwrap();
    e.insert("rod_bending".into(), rod.bending());
    e.insert("rod_twist".into(), rod.twist());
    e.insert("rod_shear".into(), rod.shear());
    e.insert("rod_stretch".into(), rod.stretch());
    e.insert("rod_twist_stretch".into(), rod.twist_stretch());
    e.insert("rod_bend_shear".into(), rod.bend_shear());
    let r = c.free_response().unwrap();
    e.insert("dstrain_dforce".into(), r.dstrain_dforce);
    e.insert("dtwist_dforce".into(), r.dtwist_dforce);
    e.insert("dhoop_dforce".into(), r.dhoop_dforce);
    e.insert("winding".into(), r.winding as i32 as f64);
    e.insert("helix_angle_deg".into(), tube.helix_angle().to_degrees());
    e
}

/// Printed with 17 significant digits, a value round-trips exactly; allow
/// 2 ulp for the degree conversion done in the driver.
fn assert_matches_rust(driver: &str, text: &str) {
    let got = values(text);
    let want = expected(&got);
    for (k, w) in &want {
        let v = got.get(k).unwrap_or_else(|| panic!("{driver}: missing `{k}` in\n{text}"));
        assert!((v - w).abs() <= 4.0 * f64::EPSILON * w.abs(), "{driver}: {k} = {v}, Rust gives {w}");
    }
}

#[test]
fn c_driver_shared_and_static_match_rust() {
    let shared = run_values("c_tube_stiffness_shared", &[]);
    assert_matches_rust("c shared", &shared);
    assert_eq!(values(&shared)["winding"], 1.0, "the bundled DNA-like tube overwinds");
    let stat = run_values("c_tube_stiffness_static", &["c_examples/data/dna_tube.txt"]);
    assert_eq!(shared, stat, "shared and static builds print the same");
}

#[test]
fn c_driver_reads_another_input() {
    let dir = std::env::temp_dir().join(format!("rodkit-native-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let input = dir.join("iso.txt");
    std::fs::write(&input, "mid_radius = 2.5\nthickness = 0.01 # thin\nintrinsic_twist = -0.3\ne1 = 70e3\ne2 = 70e3\nnu12 = 0.33\ng12 = 26315.789473684212\n").unwrap();
    let out = run_values("c_tube_stiffness_shared", &[input.to_str().unwrap()]);
    assert_matches_rust("c shared, isotropic input", &out);
    assert_eq!(values(&out)["winding"], 0.0, "an isotropic tube does not twist when pulled");
}

#[test]
fn cpp_driver_matches_rust() {
    let out = run("cpp_tube_stiffness", &[]);
    let got = values(&out);
    let mat = OrthotropicSurface::new(300.0, 900.0, 0.3, 100.0).unwrap();
    let tube = ThinTube::new(1.0, 0.4, got["intrinsic_twist"], mat).unwrap();
    let k = tube.coupling_stiffness().unwrap().k;
    assert!((got["K_strain_twist"] - k[(0, 1)]).abs() <= 4.0 * f64::EPSILON * k[(0, 1)].abs());
    assert!((got["K_hoop_hoop"] - k[(2, 2)]).abs() <= 4.0 * f64::EPSILON * k[(2, 2)]);
    let mut rows = 0;
    for line in out.lines().filter(|l| l.starts_with("sweep ")) {
        let f: Vec<f64> = line.split_whitespace().skip(1).map(|x| x.parse().unwrap()).collect();
        let tau0 = f[0].to_radians().tan();
        let c = ThinTube::new(1.0, 0.4, tau0, mat).unwrap().coupling_stiffness().unwrap();
        // Printed with 7 significant digits.
        assert!((f[1] - c.k[(0, 1)]).abs() <= 1e-6 * c.k[(0, 1)].abs().max(1e-300), "{line}");
        assert!((f[2] - c.stretch_twist().coupling).abs() <= 1e-6 * c.k.amax(), "{line}");
        assert_eq!(f[3], c.free_response().unwrap().winding as i32 as f64, "{line}");
        rows += 1;
    }
    assert_eq!(rows, 18);
    assert_eq!(got["error_caught"], 1.0);
}

/// The C++ FE embedding example (c_examples/fe_beam.cpp): a beam program
/// with its own load stepping, Newton loop and sparse LU on rodkit's rod
/// kernels, with the section law of a thick helically reinforced tube.
/// References, each independent of the program's own arithmetic:
/// - section: the Rust scene's rod law for the same wall (the code behind
///   rodkit_tube_rod_stiffness, so to 4 ulp: it guards the transport through
///   the ABI, order and layout of the 6×6), and the thin-wall closed form at
///   the mid radius (physics.md §1.4: thick → thin at rate ≥ 1 in t/R; here
///   t/R = 0.26 and every entry within 0.5·t/R);
/// - large deflection (Λ = 5): the program's own comparison with
///   rodkit_rod_continue (ANM) and, here, the Rust API's Newton
///   continuation on a rod built from the printed 6×6 — the same discrete
///   equations, so the tips agree to the solvers' tolerances (1e−9 L);
/// - small load (Λ = 1e−4): linear beam theory with the printed K_b, G and
///   bend–shear coupling c2, computed here (x(L) = PL³G/(3D) + PL·K_b/D,
///   θ2 = PL²G/(2D), θ1 = −c2PL/D, D = K_b·G − c2²; Gauss collocation is
///   exact on this cubic, so only the O(Λ²) geometric nonlinearity is left:
///   1e−7 relative), with guards that the check sees both the shear term and
///   the coupling.
#[test]
fn cpp_fe_beam_embeds_the_rod_kernels() {
    use rodkit::continuation::Options;
    use rodkit::rod::branch::Method;
    use rodkit::rod::model::{Rod, Supports};
    use rodkit::rod::scheme::Scheme;
    use rodkit::rod::{Load, Loads, RodLaw};
    use rodkit::tube::material::SaintVenantKirchhoff;
    use rodkit::tube::scene::{TubeModel, TubeScene, WallLaw};
    use rodkit::tube::Orthotropic;
    let out = run("cpp_fe_beam", &["--values"]);
    let got = values(&out);
    let g = |k: &str| *got.get(k).unwrap_or_else(|| panic!("cpp_fe_beam did not print `{k}`:\n{out}"));

    // Section law: the wall the program states (units mm, MPa).
    let (a, b, tau0) = (10.0, 13.0, (std::f64::consts::PI / 6.0).tan() / 11.5);
    assert_eq!((g("inner_radius"), g("outer_radius"), g("intrinsic_twist")), (a, b, tau0));
    let o = Orthotropic::new(1000.0, 20.0, 20.0, 0.45, 0.45, 0.45, 5.0, 5.0, 20.0 / 2.9).unwrap();
    let law = WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(o, tau0, false));
    let scene = TubeScene::new(a, b, law, TubeModel::Thick, 1e-10, None).unwrap();
    let thick = scene.rod_stiffness().unwrap();
    let thin = ThinTube::new(0.5 * (a + b), b - a, tau0, OrthotropicSurface::new(1000.0, 20.0, 0.45, 5.0).unwrap())
        .unwrap()
        .rod_stiffness()
        .unwrap();
    let names = ["u1", "u2", "u3", "v1", "v2", "v3"];
    let mut k = nalgebra::Matrix6::<f64>::zeros();
    for i in 0..6 {
        for j in i..6 {
            let key = format!("K_{}_{}", names[i], names[j]);
            let want = thick.value.k[(i, j)];
            let v = got.get(&key).copied().unwrap_or(0.0);
            assert!((v - want).abs() <= 4.0 * f64::EPSILON * want.abs(), "{key} = {v}, Rust scene gives {want}");
            let thin_v = thin.k[(i, j)];
            assert!((v - thin_v).abs() <= 0.5 * (b - a) / (0.5 * (a + b)) * thin_v.abs(), "{key} = {v}, thin {thin_v}");
            k[(i, j)] = v;
            k[(j, i)] = v;
        }
    }
    assert!(g("section_error_estimate") <= 1e-10);
    assert!(k[(0, 3)] < 0.0 && k[(2, 5)] > 0.0, "chiral: bend–shear and twist–stretch couplings");

    // Large deflection: the program's comparison with rodkit's ANM, and the
    // Rust API's Newton continuation on the same rod.
    let (length, p_ref, lambda_max) = (g("length"), g("load_per_lambda"), g("lambda_max"));
    assert!(g("tip_position_difference") <= 1e-9 && g("tip_rotation_difference") <= 1e-9, "{out}");
    for c in ["x", "y", "z"] {
        let (fe, anm) = (g(&format!("fe_tip_{c}")), g(&format!("anm_tip_{c}")));
        assert!((fe - anm).abs() <= 1e-9 * length, "tip {c}: FE {fe}, ANM {anm}");
    }
    let law = RodLaw::general(k, nalgebra::Vector3::zeros(), nalgebra::Vector3::new(0.0, 0.0, 1.0)).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([p_ref, 0.0, 0.0])), ..Default::default() };
    let rod = Rod::new(law, length, loads, Supports::Cantilever, Scheme::Gauss(4), g("elements") as usize).unwrap();
    let opts = Options { target_lambda: Some(lambda_max), residual_tol: 1e-12, ..Default::default() };
    let branch = rod.continue_branch(None, 0.0, true, &opts, Method::Newton, |_| true).unwrap();
    let tip = rod.tip(branch.states.last().unwrap());
    for (c, name) in ["x", "y", "z"].iter().enumerate() {
        let fe = g(&format!("fe_tip_{name}"));
        assert!((fe - tip[c]).abs() <= 1e-9 * length, "tip {name}: FE {fe}, Rust Newton continuation {}", tip[c]);
    }
    assert!(g("fe_tip_rot2") > 1.0 && g("fe_tip_x") > 0.5 * length, "a large deflection (over 57°, half the length)");

    // The program's Newton statistics: one small step and 10 load steps, no
    // cuts, quadratic convergence (≤ 6 iterations a step), its residual test met.
    assert_eq!((g("newton_steps"), g("step_cuts")), (11.0, 0.0));
    assert!(g("newton_iterations") <= 66.0 && g("final_residual") <= 1e-12, "{out}");
    assert_eq!(g("factorisations"), g("newton_iterations") + g("newton_steps"), "one predictor per step");

    // Small load against linear theory, computed here from the printed law.
    let p = g("lambda_linear") * p_ref;
    let (kb, gs, c2) = (k[(0, 0)], k[(3, 3)], k[(0, 3)]);
    let d = kb * gs - c2 * c2;
    let x_lin = p * length.powi(3) * gs / (3.0 * d) + p * length * kb / d;
    let rot2 = p * length * length * gs / (2.0 * d);
    let rot1 = -c2 * p * length / d;
    let rel = |v: f64, w: f64| (v - w).abs() / w.abs();
    assert!(rel(g("fe_linear_tip_x"), x_lin) <= 1e-7, "{} vs {x_lin}", g("fe_linear_tip_x"));
    assert!(rel(g("fe_linear_rot2"), rot2) <= 1e-7, "{} vs {rot2}", g("fe_linear_rot2"));
    assert!(rel(g("fe_linear_rot1"), rot1) <= 1e-7, "{} vs {rot1}", g("fe_linear_rot1"));
    assert!(g("fe_linear_tip_y").abs() <= 1e-7 * x_lin);
    // The check resolves what it claims: the shear term is ≫ 1e−7 of the
    // deflection, and ignoring the coupling would miss by far more.
    assert!(p * length * kb / d / x_lin > 1e-4);
    assert!(rel(p * length.powi(3) / (3.0 * kb) + p * length / gs, x_lin) > 0.5);
}

/// The FE example under valgrind (memcheck, as the C drivers): no invalid
/// access, no definite leak, its checks still passing — on 8 elements and 4
/// load steps (about 5 s; the default run takes about 14 s under valgrind).
#[test]
fn cpp_fe_beam_is_clean_under_valgrind() {
    let out = Command::new("valgrind")
        .args(["-q", "--error-exitcode=99", "--leak-check=full", "--errors-for-leak-kinds=definite"])
        .args(["--show-leak-kinds=definite"])
        .arg(drivers().join("cpp_fe_beam"))
        .args(["--values", "8", "4"])
        .current_dir(ROOT)
        .output()
        .expect("run valgrind");
    let text = check(out, "valgrind cpp_fe_beam");
    let got = values(&text);
    assert_eq!((got["elements"], got["newton_steps"]), (8.0, 5.0));
    assert!(got["tip_position_difference"] <= 1e-9 && got["linear_relative_error"] <= 1e-7, "{text}");
}

#[test]
fn fortran_driver_shared_and_static_match_rust() {
    let shared = run("f_tube_stiffness_shared", &[]);
    assert_matches_rust("fortran shared", &shared);
    assert_eq!(values(&shared)["error_caught"], 1.0);
    let stat = run("f_tube_stiffness_static", &["fortran_examples/dna_tube.nml"]);
    assert_eq!(shared, stat);
    // Same tube as the C driver's default input: same numbers.
    let c = values(&run_values("c_tube_stiffness_shared", &[]));
    for (k, v) in values(&shared) {
        if let Some(cv) = c.get(&k) {
            assert_eq!(*cv, v, "C and Fortran differ on {k}");
        }
    }
}

/// The error-handling driver's checks pass, and its deliberate panic
/// (rodkit_diagnostic_panic) reaches it as a status and a message only:
/// nothing on stderr, not even with RUST_BACKTRACE=1 (the caught panic's
/// place is in the message instead).
#[test]
fn bad_input_driver_passes_all_checks() {
    for exe in ["c_bad_input_shared", "c_bad_input_static"] {
        let cmd = |args: &[&str]| {
            Command::new(drivers().join(exe)).args(args).current_dir(ROOT).env("RUST_BACKTRACE", "1").output().unwrap()
        };
        let out = cmd(&["--values"]);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        let out = check(out, exe);
        assert!(!out.contains("FAIL"), "{exe}:\n{out}");
        assert!(out.lines().any(|l| l == "14 passed, 0 failed"), "{exe}:\n{out}");
        assert!(!stderr.contains("panicked") && !stderr.contains("backtrace"), "{exe} stderr:\n{stderr}");
        // Without --values, the report: the same count, two lines, quiet.
        let out = cmd(&[]);
        assert!(out.stderr.is_empty(), "{exe} stderr:\n{}", String::from_utf8_lossy(&out.stderr));
        let out = check(out, exe);
        assert!(out.starts_with("Error handling: 14 of 14 bad calls") && out.lines().count() == 2, "{exe}:\n{out}");
    }
}

/// No invalid access and no definite leak in the C drivers (valgrind's
/// memcheck; exit code 99 on any error).
#[test]
fn c_drivers_are_clean_under_valgrind() {
    // c_rod_buckling exercises the rod and branch handles (two branches,
    // switching, records, positions): ~30 s under valgrind.
    // c_dna_supercoil on a tiny scene (60 bp, 8 elements, 4 steps) covers
    // the supercoil handle, its points and positions; c_dna_map the curve
    // summary and points.
    let dir = std::env::temp_dir().join(format!("rodkit-vg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (csv, vtk) = (dir.join("v.csv").display().to_string(), dir.join("v.vtk").display().to_string());
    let dna_args = vec!["0.1".to_string(), "4".into(), csv, vtk, "8".into(), "60".into()];
    for exe in [
        "c_tube_stiffness_shared",
        "c_tube_stiffness_static",
        "c_bad_input_shared",
        "c_bad_input_static",
        "c_artery_shared",
        "c_rod_buckling_shared",
        "c_dna_supercoil_shared",
        "c_dna_supercoil_resume_shared",
        "c_dna_map_shared",
    ] {
        // c_dna_supercoil_resume: 60 bp, 8 elements, 4 steps, stopped after 3 points.
        let resume_args: Vec<String> = ["60", "8", "4", "3"].iter().map(|s| s.to_string()).collect();
        // c_dna_map: one curve of 150 bp, 12 elements, 20 steps (buckled,
        // summarised, written as CSV and SVG).
        let map_dir = dir.join("map").display().to_string();
        let map_args: Vec<String> = [
            "--model",
            "full-rod",
            "--bp",
            "150",
            "--elements",
            "12",
            "--steps",
            "20",
            "--turns",
            "1.5",
            "--forces",
            "1",
        ]
        .iter()
        .chain(&["--salts", "0.1"])
        .map(|s| s.to_string())
        .chain([map_dir])
        .collect();
        let args: &[String] = match exe {
            "c_dna_supercoil_shared" => &dna_args,
            "c_dna_supercoil_resume_shared" => &resume_args,
            "c_dna_map_shared" => &map_args,
            _ => &[],
        };
        let out = Command::new("valgrind")
            .args([
                "-q",
                "--error-exitcode=99",
                "--leak-check=full",
                "--errors-for-leak-kinds=definite",
                "--show-leak-kinds=definite",
            ])
            .arg(drivers().join(exe))
            .args(args)
            .current_dir(ROOT)
            .env("RUST_BACKTRACE", "0")
            .output()
            .expect("run valgrind");
        check(out, &format!("valgrind {exe}"));
    }
}

/// The artery driver's CSV equals the Rust scene's sweep on the same input
/// (reference: TubeScene::sweep, the same code path, so bitwise).
#[test]
fn artery_driver_matches_rust_sweep() {
    use rodkit::tube::finite::{Axial, Ends, Loading, Torsion};
    use rodkit::tube::material::fibre::{FibreAngle, FibreFamily};
    use rodkit::tube::material::{FibreReinforced, NeoHookean};
    use rodkit::tube::scene::{TubeModel, TubeScene, WallLaw};
    let dir = std::env::temp_dir().join(format!("rodkit-artery-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("artery.csv");
    let out = run_values("c_artery_shared", &[csv.to_str().unwrap()]);
    assert_eq!(values(&out)["states"], 31.0);
    let deg = std::f64::consts::PI / 180.0;
    let fam = |angle: f64| FibreFamily { angle: FibreAngle::Fixed(angle), k1: 2.3632, k2: 0.8393 };
    let law = WallLaw::FibreReinforced(FibreReinforced {
        matrix: NeoHookean { shear_modulus: 3.0, lame_lambda: 0.0, incompressible: true },
        families: vec![fam(29.0 * deg), fam(-29.0 * deg)],
        intrinsic_twist: 0.0,
    });
    let scene = TubeScene::new(0.71, 0.71 + 0.26, law, TubeModel::Thick, 1e-10, None).unwrap();
    let loadings: Vec<Loading> = (0..31)
        .map(|i| Loading {
            axial: Axial::Stretch(1.0 + 0.01 * i as f64),
            torsion: Torsion::Torque(0.0),
            inner_pressure: 13.33,
            outer_pressure: 0.0,
            ends: Ends::Closed,
        })
        .collect();
    let (sweep, _) = scene.sweep(&loadings, |_, _| true).unwrap();
    // rodkit_tube_sweep_write_csv's columns, found by their headers (units
    // mm and mN); the state columns full, the load_force and load_twist
    // cells empty (stretch and torque control).
    let text = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let col =
        |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no `{name}` in {header:?}"));
    let (stretch, force, twist, inner) =
        (col("stretch [1]"), col("applied_force [mN]"), col("twist [rad/mm]"), col("inner_radius [mm]"));
    let (load_force, load_twist) = (col("load_force [mN]"), col("load_twist [rad/mm]"));
    let rows: Vec<Vec<Option<f64>>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| (!v.is_empty()).then(|| v.parse().unwrap())).collect())
        .collect();
    assert_eq!(rows.len(), 31);
    for (row, s) in rows.iter().zip(&sweep.states) {
        assert_eq!(row[stretch], Some(s.stretch));
        assert_eq!(row[force], Some(s.applied_force));
        assert_eq!(row[inner], Some(s.deformed_inner_radius));
        assert!(row[twist].unwrap().abs() < 1e-12, "± families: no twist");
        assert_eq!((row[load_force], row[load_twist]), (None, None));
    }
    let rows: Vec<Vec<f64>> =
        rows.iter().map(|r| vec![r[stretch].unwrap(), r[force].unwrap(), 0.0, 0.0, r[inner].unwrap()]).collect();
    // Stretching at fixed pressure narrows the lumen and raises the force.
    assert!(rows.windows(2).all(|w| w[1][4] < w[0][4] && w[1][1] > w[0][1]));
    let stat = run_values("c_artery_static", &[csv.to_str().unwrap()]);
    assert_eq!(values(&stat), values(&out));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Fortran torsion-free stretch sweep equals the Rust scene's sweep.
#[test]
fn fortran_stretch_sweep_matches_rust() {
    use rodkit::tube::finite::Loading;
    use rodkit::tube::material::SaintVenantKirchhoff;
    use rodkit::tube::scene::{TubeModel, TubeScene, WallLaw};
    use rodkit::tube::Orthotropic;
    let dir = std::env::temp_dir().join(format!("rodkit-stretch-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("sweep.csv");
    let csv_arg = csv.to_str().unwrap();
    let out = run_values("f_stretch_sweep_shared", &[csv_arg]);
    let got = values(&out);
    let o = Orthotropic::new(467.2, 516.2, 516.2, 0.3, 0.3, 0.3, 139.8, 139.8, 516.2 / 2.6).unwrap();
    let tau0 = (std::f64::consts::PI / 3.0).tan();
    let scene = TubeScene::new(
        0.8,
        1.2,
        WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(o, tau0, false)),
        TubeModel::Thick,
        1e-10,
        None,
    )
    .unwrap();
    let loadings: Vec<Loading> = (0..26).map(|i| Loading::torsion_free_stretch(1.0 + 0.002 * i as f64)).collect();
    let (sweep, _) = scene.sweep(&loadings, |_, _| true).unwrap();
    let last = sweep.states.last().unwrap();
    for (k, want) in
        [("twist", last.twist), ("applied_force", last.applied_force), ("outer_radius", last.deformed_outer_radius)]
    {
        assert!((got[k] - want).abs() <= 4.0 * f64::EPSILON * want.abs(), "{k}: {} vs {want}", got[k]);
    }
    assert!(got["twist"] > 0.0, "the DNA-like wall overwinds (τ0 > 0)");
    assert_eq!(out.matches("# progress").count(), 5);
    // The CSV rodkit wrote from Fortran: every state of the Rust sweep,
    // bitwise (nm, pN in the header).
    let text = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let col =
        |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no `{name}` in {header:?}"));
    let (stretch, twist, force) = (col("stretch [1]"), col("twist [rad/nm]"), col("applied_force [pN]"));
    let rows: Vec<Vec<&str>> = text.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), sweep.states.len());
    for (row, s) in rows.iter().zip(&sweep.states) {
        let v = |c: usize| row[c].parse::<f64>().unwrap();
        assert_eq!((v(stretch), v(twist), v(force)), (s.stretch, s.twist, s.applied_force));
    }
    assert_eq!(run_values("f_stretch_sweep_static", &[csv_arg]), out);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The DNA scene driver's fit and thick evaluation equal the Rust DNA module
/// (reference: rodkit::tube::dna, the same code), and the fit reproduces the
/// requested law.
#[test]
fn dna_driver_matches_rust_fit() {
    use rodkit::tube::dna::{fit_thin_wall, thick_comparison, DnaTargets, OutOfPlane};
    let dir = std::env::temp_dir().join(format!("rodkit-dna-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("dna.csv");
    let got = values(&run_values("c_dna_tube_shared", &[csv.to_str().unwrap()]));
    let fit = fit_thin_wall(DnaTargets::literature(), 1.0, std::f64::consts::PI / 3.0, 0.4, 0.3).unwrap();
    let thick = thick_comparison(&fit, OutOfPlane::default_for(&fit.material)).unwrap();
    for (k, want) in [
        ("e1", fit.material.e1),
        ("e2", fit.material.e2),
        ("g12", fit.material.g12),
        ("turns_per_pn_per_10kbp", fit.twist_rate.turns_per_pn_per_10kbp),
        ("thick_stretch_S", thick.thick.stretch),
        ("thick_coupling_g", thick.thick.coupling),
    ] {
        assert!((got[k] - want).abs() <= 4.0 * f64::EPSILON * want.abs(), "{k}: {} vs {want}", got[k]);
    }
    for (k, want) in [("stretch_S", 1100.0), ("twist_C", 440.0), ("coupling_g", -90.0)] {
        assert!((got[k] - want).abs() < 1e-10 * want.abs(), "{k}: {}", got[k]);
    }
    assert_eq!(got["overwinds"], 1.0);
    // The rod law's stretch–twist block is the thick law (reference: the
    // thick comparison above, computed by the DNA module at its own grid).
    for (k, want) in [
        ("rod_stretch", thick.thick.stretch),
        ("rod_twist", thick.thick.twist),
        ("rod_twist_stretch", thick.thick.coupling),
    ] {
        assert!((got[k] - want).abs() <= 1e-8 * want.abs(), "{k}: {} vs {want}", got[k]);
    }
    assert!(got["rod_error_estimate"] <= 1e-10);
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count() - 1;
    assert_eq!(rows, 41);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The C rod-buckling driver: its critical load equals the extensible
/// Euler formula (independent closed form, physics.md §2.6) to 1e−9 and the
/// Rust API's own answer for the same rod to round-off; its buckled branch
/// reaches 170° with μ at round-off, the callback saw every point, and the
/// CSV/VTK files are written.
#[test]
fn c_rod_buckling_driver() {
    use rodkit::continuation::Options;
    use rodkit::rod::branch::Method;
    use rodkit::rod::model::{Rod, Supports};
    use rodkit::rod::scheme::Scheme;
    use rodkit::rod::{Load, Loads, RodLaw};
    let dir = std::env::temp_dir().join(format!("rodkit-rod-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (csv, vtk) = (dir.join("b.csv"), dir.join("b.vtk"));
    let out = run_values("c_rod_buckling_shared", &[csv.to_str().unwrap(), vtk.to_str().unwrap()]);
    let got = values(&out);
    let formula = got["extensible_euler_formula"];
    assert!((got["critical_load"] - formula).abs() < 1e-9 * formula, "{out}");
    assert_eq!(got["multiplicity"], 2.0);
    // The same continuation through the Rust API.
    let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 300.0, 1000.0).unwrap();
    let loads = Loads { tip_force: Some(Load::dead([0.0, 0.0, -1.0])), ..Default::default() };
    let rod = Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), 16).unwrap();
    let opts = Options {
        target_lambda: Some(3.0),
        initial_step: 0.2,
        max_step: 0.5,
        residual_tol: 1e-12,
        detect_bifurcations: true,
        bifurcation_tol: 1e-11,
        ..Default::default()
    };
    let b = rod.continue_branch(None, 0.0, true, &opts, Method::Newton, |_| true).unwrap();
    assert!((b.bifurcations[0].lambda - got["critical_load"]).abs() < 1e-13 * formula);
    // Its place and evidence through rodkit_branch_bifurcation_points:
    // the record it follows (as Rust's), its load between that record's
    // and the next, found by σ_min (a double point: det B keeps its sign),
    // nothing unresolved.
    assert_eq!(got["bifurcation_record"], b.bifurcations[0].record as f64);
    assert!(got["bracket_lambda_low"] <= got["critical_load"] && got["critical_load"] <= got["bracket_lambda_high"]);
    assert_eq!((got["det_sign_change"], got["unresolved"]), (0.0, 0.0));
    assert_eq!(got["test_function_change"], b.bifurcations[0].test_function_change as u8 as f64);
    assert!(got["final_tip_rotation_deg"] > 170.0 && got["final_tip_rotation_deg"] < 172.0);
    assert!(got["callback_calls"] >= got["points_to_170_deg"]);
    // Every record of the buckled branch (rodkit_branch_write_csv), the
    // unfolding parameter its last column.
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.lines().next().unwrap().ends_with(",unfolding"));
    let rows = text.lines().count() - 1;
    assert_eq!(rows as f64, got["records"]);
    assert!(got["records"] > got["points_to_170_deg"], "the branch goes past 170 degrees");
    for line in std::fs::read_to_string(&csv).unwrap().lines().skip(1) {
        let mu: f64 = line.rsplit(',').next().unwrap().parse().unwrap();
        assert!(mu.abs() < 1e-9, "unfolding parameter {mu}");
    }
    let vtk_text = std::fs::read_to_string(&vtk).unwrap();
    assert!(
        vtk_text.starts_with("# vtk DataFile")
            && vtk_text.contains("POINTS 136 double")
            && vtk_text.contains("LINES 8 144")
    );
    assert_eq!(run_values("c_rod_buckling_static", &[csv.to_str().unwrap(), vtk.to_str().unwrap()]), out);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Fortran follower-cantilever driver equals the Rust API (same
/// continuation) to round-off at α = 1, 2, 5, 10, and is within 1e−8 of a
/// converged solution (Gauss(4) × 32, residual 1e−12; its agreement with
/// AUTO-07p to 1e−11 is shown by `cargo bench --bench rod`).
#[test]
fn fortran_follower_cantilever_driver() {
    use rodkit::continuation::anm::AnmOptions;
    use rodkit::continuation::Options;
    use rodkit::rod::branch::Method;
    use rodkit::rod::model::{Rod, Supports};
    use rodkit::rod::scheme::Scheme;
    use rodkit::rod::{Load, Loads, RodLaw};
    let dir = std::env::temp_dir().join(format!("rodkit-follower-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let vtk = dir.join("shapes.vtk");
    let csv = dir.join("samples.csv");
    let out = run_values("f_follower_cantilever_shared", &[vtk.to_str().unwrap(), csv.to_str().unwrap()]);
    let got = values(&out);
    let rod = |n| {
        let law = RodLaw::isotropic(1.0, 1.0 / 1.3, 1e4, 2.6e4).unwrap();
        let loads = Loads { tip_force: Some(Load::follower([1.0, 0.0, 0.0])), ..Default::default() };
        Rod::new(law, 1.0, loads, Supports::Cantilever, Scheme::Gauss(4), n).unwrap()
    };
    let path = |r: &Rod, tol: f64, method: Method| {
        let mut tips = vec![];
        let mut branch = None;
        for a in [1.0, 2.0, 5.0, 10.0] {
            let opts = Options { target_lambda: Some(a), residual_tol: tol, max_step: 2.0, ..Default::default() };
            let b = match &branch {
                None => r.continue_branch(None, 0.0, true, &opts, method, |_| true).unwrap(),
                Some(b) => r.resume_branch(b, &opts, method, |_| true).unwrap(),
            };
            tips.push(r.tip(b.states.last().unwrap()));
            branch = Some(b);
        }
        tips
    };
    let same = path(&rod(8), 1e-10, Method::Anm(AnmOptions { order: 20, epsilon: 1e-10, pade: false }));
    let fine = path(&rod(32), 1e-12, Method::Newton);
    for (k, a) in ["1", "2", "5", "10"].iter().enumerate() {
        for (c, name) in ["x", "y", "z"].iter().enumerate() {
            let v = got[&format!("tip_{name}_{a}")];
            assert!((v - same[k][c]).abs() < 1e-13, "α = {a}: tip {name} {v} vs Rust {}", same[k][c]);
            assert!((v - fine[k][c]).abs() < 1e-8, "α = {a}: tip {name} {v} vs converged {}", fine[k][c]);
        }
    }
    // The dense run's shapes at α = 1, 2, 5, 10 as VTK polydata (written by
    // rodkit_branch_write_samples_vtk): 4 polylines of 9 nodes, λ as cell
    // data, the last node of the last at the printed dense tip (the same
    // state, 1e-15) and so within 1e-8 of the targeted tip (as below).
    let text = std::fs::read_to_string(&vtk).unwrap();
    assert!(
        text.starts_with("# vtk DataFile")
            && text.contains("POINTS 36 double")
            && text.contains("LINES 4 40")
            && text.contains("CELL_DATA 4")
    );
    let points: Vec<Vec<f64>> =
        text.lines().skip(5).take(36).map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect()).collect();
    let (tx, tz) = (got["dense_tip_x_10"], got["dense_tip_z_10"]);
    assert!((points[35][0] - tx).abs() < 1e-15 && (points[35][2] - tz).abs() < 1e-15);
    assert!((points[35][0] - got["tip_x_10"]).abs() < 1e-8 && (points[35][2] - got["tip_z_10"]).abs() < 1e-8);
    let lambda: Vec<f64> = text
        .lines()
        .skip_while(|l| !l.starts_with("SCALARS lambda"))
        .skip(2)
        .take(4)
        .map(|l| l.parse().unwrap())
        .collect();
    assert_eq!(lambda, [1.0, 2.0, 5.0, 10.0]);
    // Every sample as CSV (rodkit_branch_write_samples_csv): 20 rows at
    // α = 0.5, 1, …, 10, the last one's tip the printed dense tip.
    let rows: Vec<Vec<f64>> = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 20);
    assert!(rows.iter().enumerate().all(|(k, r)| r[0] == 0.5 * (k + 1) as f64));
    assert!((rows[19][2] - tx).abs() < 1e-15 && (rows[19][4] - tz).abs() < 1e-15);
    // Dense output in one run (20 loads, Padé): every load delivered within
    // the tolerance, the ones at α = 5 and 10 equal to the targeted points
    // (same discrete equations, residual 1e-10 each) and to the converged tip.
    assert_eq!((got["dense_samples"], got["dense_missed"]), (20.0, 0.0));
    assert!(got["dense_max_residual"] <= 1e-10);
    assert!(got["dense_factorisations"] < got["factorisations"], "one dense run costs less than four targeted ones");
    for (a, k) in [("5", 2), ("10", 3)] {
        for (c, name) in [(0, "x"), (2, "z")] {
            let v = got[&format!("dense_tip_{name}_{a}")];
            assert!((v - same[k][c]).abs() < 1e-8, "dense α = {a}: tip {name} {v} vs targeted {}", same[k][c]);
            assert!((v - fine[k][c]).abs() < 1e-8, "dense α = {a}: tip {name} {v} vs converged {}", fine[k][c]);
        }
    }
    // To a tolerance (1e-6, ANM defaults, from 8 elements): the same
    // choice as Rust's continue_to_tolerance with the same options, every
    // record estimated within the tolerance, the tip within it of the
    // converged one (32 elements, Newton 1e-12), and the tip frame read
    // through rodkit_rod_node_state equal to the state's quaternion.
    let opts = Options { target_lambda: Some(10.0), residual_tol: 1e-12, ..Default::default() };
    let method = Method::Anm(AnmOptions { order: 20, epsilon: 1e-10, pade: false });
    let acc = rodkit::rod::accuracy::continue_to_tolerance(&rod(8), 1e-6, (0.0, true), &opts, method).unwrap();
    assert_eq!(got["tolerance_elements"], acc.rod.elements as f64);
    assert_eq!(got["tolerance_records"], acc.branch.records.len() as f64);
    assert_eq!(got["tolerance_estimated"], got["tolerance_records"]);
    assert!(got["tolerance_worst_estimate"] <= 1e-6 && (got["tolerance_worst_estimate"] - acc.worst).abs() < 1e-18);
    let last = acc.branch.states.last().unwrap();
    let tip = acc.rod.node_state(last, acc.rod.elements);
    for (key, want) in [("tolerance_tip_x_10", tip[0]), ("tolerance_tip_z_10", tip[2]), ("tolerance_tip_rx_10", tip[0])]
    {
        assert!((got[key] - want).abs() < 1e-13, "{key} {} vs Rust {want}", got[key]);
    }
    assert!((got["tolerance_tip_q0_10"] - tip[3]).abs() < 1e-13 && (got["tolerance_tip_q2_10"] - tip[5]).abs() < 1e-13);
    // The signed tip rotation about e2: Rust's rotation vector, and the
    // quaternion's own angle, 2 atan2(q2, q0) wrapped to (−π, π].
    let signed = acc.rod.rotation_vector(last, acc.rod.elements)[1];
    assert!((got["tolerance_tip_rotation_e2_10"] - signed).abs() < 1e-13);
    let from_q = {
        let a = 2.0 * tip[5].atan2(tip[3]);
        a - 2.0 * std::f64::consts::PI * (a / (2.0 * std::f64::consts::PI)).round()
    };
    assert!((signed - from_q).abs() < 1e-12, "signed {signed} against {from_q}");
    assert!(
        (got["tolerance_tip_x_10"] - fine[3][0]).abs() < 1e-6 && (got["tolerance_tip_z_10"] - fine[3][2]).abs() < 1e-6
    );
    assert_eq!(run_values("f_follower_cantilever_static", &[vtk.to_str().unwrap(), csv.to_str().unwrap()]), out);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Fortran Greenhill driver (rotation control to φ = 25 exactly through
/// rodkit_rod_set_target_rotation, elements chosen for 1e-6 with
/// detection): the same element count, records and critical twists as
/// Rust's refine_until with until_rotation and the same options (to
/// 1e-12), ending at φ = 25, and each critical φ within its estimate and
/// the tolerance of Greenhill's closed form θ_k (tan(θ/2) = θ/2, the
/// roots 8.98682, 15.45050, 21.80824).
#[test]
fn fortran_greenhill_driver() {
    use rodkit::continuation::{Options, Record};
    use rodkit::rod::branch::{Method, Plain};
    use rodkit::rod::model::{Rod, Supports};
    use rodkit::rod::scheme::Scheme;
    use rodkit::rod::target::until_rotation;
    use rodkit::rod::{Loads, RodLaw};
    let out = run_values("f_greenhill_shared", &[]);
    let got = values(&out);
    let template = Rod::new(
        RodLaw::kirchhoff(1.0, 1.0, 1.0).unwrap(),
        1.0,
        Loads::default(),
        Supports::Twisted { tension: 0.0 },
        Scheme::Gauss(4),
        4,
    )
    .unwrap();
    let opts = Options {
        residual_tol: 1e-12,
        initial_step: 0.05,
        max_step: 1.0,
        max_steps: 2000,
        detect_bifurcations: true,
        bifurcation_tol: 1e-9,
        ..Default::default()
    };
    let acc = rodkit::rod::accuracy::refine_until(&template, 1e-6, 1e-12, |rod| {
        let follow =
            |cb: &mut dyn FnMut(&Record) -> bool| rod.continue_branch(None, 0.0, true, &opts, Method::Newton, cb);
        until_rotation(&Plain { rod, method: Method::Newton }, 25.0, None, &mut |_| true, follow)
    })
    .unwrap();
    assert_eq!(got["elements"], acc.rod.elements as f64);
    assert_eq!(got["records"], acc.branch.records.len() as f64);
    assert_eq!(got["points"], 3.0);
    assert!((got["final_end_rotation"] - 25.0).abs() < 1e-12);
    let (phis, _) = acc.branch.end_rotations(&acc.rod, None);
    for (k, theta) in [8.986818915818128, 15.450503673875414, 21.808243318857798].iter().enumerate() {
        let key = |name: &str| got[&format!("{name}_{}", k + 1)];
        let rust = acc.branch.rotation_at_bifurcation(&acc.rod, k, &phis).unwrap();
        assert!((key("critical_phi") - rust).abs() < 1e-12, "root {k}: {} vs Rust {rust}", key("critical_phi"));
        assert_eq!((key("critical_estimated"), key("critical_multiplicity")), (1.0, 2.0));
        assert_eq!(key("critical_record"), acc.branch.bifurcations[k].record as f64);
        let truth = (key("critical_phi") - theta).abs();
        assert!(truth <= key("critical_phi_estimate") && truth <= 1e-6 * theta, "root {k}: true {truth:e}");
    }
    assert!(got["worst_critical_estimate"] <= 1e-6);
    assert_eq!(run_values("f_greenhill_static", &[]), out);
}

/// The C driver that solves the follower cantilever at α = 5 with its own
/// SUNDIALS code through rodkit's kernels: IDA shooting (rodkit_rod_rhs)
/// agrees with the ANM within the collocation error (Gauss(4) × 16: ~1e−12,
/// bounded here by 1e−9), KINSOL on rodkit_rod_residual/_jacobian with the
/// ANM state to 1e−10.
#[test]
fn c_rod_sundials_driver() {
    let got = values(&run_values("c_rod_sundials_shared", &[]));
    // Recomputed from the printed tips, not taken from the driver's own
    // difference (a NaN tip would fail here).
    let tip = (got["ida_tip_x"] - got["anm_tip_x"]).hypot(got["ida_tip_z"] - got["anm_tip_z"]);
    assert!(tip < 1e-9, "IDA vs ANM tip {tip:e}: {got:?}");
    // The driver's own figure (printed to 4 digits) says the same.
    assert!((tip - got["tip_difference_ida_vs_anm"]).abs() <= 0.01 * tip + 2e-15, "{got:?}");
    assert!(got["state_difference_kinsol_vs_anm"] < 1e-10, "{got:?}");
    assert!(got["kinsol_discrete_iterations"] <= 5.0);
    assert!(
        (got["anm_tip_x"] - 0.7805435043).abs() < 1e-9,
        "the follower tip at α = 5 (benches/rod.rs reference 0.780543504307)"
    );
}

/// The Fortran driver for the electrostatics and writhe of a given curve:
/// every printed number against the Rust API on the same curve (1e-12),
/// the near-zone width not mattering (0.8 vs 0.4: 1e-4, the O(δ⁴) term),
/// the base-pair model within 2 % of the continuum (spacing 0.05: O(b)),
/// and the closed toroidal helix's writhe against Fuller's value
/// (−2.9245397422, tests/writhe.rs) to the Hermite centreline's error.
#[test]
fn fortran_charged_curve_driver() {
    use rodkit::electrostatics::{discrete, energy, EnergyQuadrature, HermiteCurve, LineCharge, Screening};
    use rodkit::geometry::writhe::writhe;
    let out = run_values("f_charged_curve_shared", &[]);
    let got = values(&out);
    let (radius, pitch, length, n) = (1.0f64, 3.0f64, 20.0f64, 81usize);
    let c = pitch / (2.0 * std::f64::consts::PI);
    let w = (radius * radius + c * c).sqrt();
    let s: Vec<f64> = (0..n).map(|k| length * k as f64 / (n - 1) as f64).collect();
    let r = s
        .iter()
        .map(|&v| {
            let th = v / w;
            [radius * th.cos(), radius * th.sin(), c * th]
        })
        .collect();
    let t = s
        .iter()
        .map(|&v| {
            let th = v / w;
            [-radius * th.sin() / w, radius * th.cos() / w, c / w]
        })
        .collect();
    let helix = HermiteCurve::new(s, r, t, false).unwrap();
    let scr = Screening { kappa: 1.0, a: 0.3 };
    let e = energy(&helix, &LineCharge::Uniform(1.0), &scr, &EnergyQuadrature { delta: 0.8, order: 12, cutoff: None })
        .unwrap();
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(
        rel(got["energy"], e.total) < 1e-12
            && rel(got["energy_near"], e.near) < 1e-12
            && rel(got["energy_far"], e.far) < 1e-12,
        "{got:?} vs {e:?}"
    );
    assert!(rel(got["energy_narrow_near_zone"], got["energy"]) < 1e-4);
    let (pr, pq, ps) = discrete::base_pairs(&helix, &LineCharge::Uniform(1.0), 0.05).unwrap();
    assert!(rel(got["base_pair_energy"], discrete::energy(&pr, &pq, &ps, &scr, None)) < 1e-12);
    assert!(rel(got["base_pair_energy"], got["energy"]) < 0.02);
    assert!(rel(got["helix_writhe"], writhe(&helix, 10).unwrap()) < 1e-12);
    assert!((got["toroidal_writhe"] - (-2.9245397422)).abs() < 1e-5, "{}", got["toroidal_writhe"]);
    assert_eq!(run_values("f_charged_curve_static", &[]), out);
}

/// The Fortran DNA-supercoiling driver (300 bp, 40 elements, 20 steps; the
/// bind(c) types of the supercoil handle and rodkit_supercoil_solve_point
/// exercised at run time): its path and its last point re-solved with
/// base pairs equal the Rust API's on the same scene (1e-12); both solvers
/// agree (1e-9); the static build prints the same.
#[test]
fn fortran_dna_supercoil_driver() {
    use rodkit::charged::dna::{run_scene, DnaScene, SupercoilSettings};
    use rodkit::charged::equilibrium::{solve_point, EquilibriumSolver};
    let out = run("f_dna_supercoil_shared", &[]);
    let got = values(&out);
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let r = run_scene(&scene, &SupercoilSettings { elements: 40, max_steps: 20, ..Default::default() }).unwrap();
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
    assert_eq!(got["points"], r.points.len() as f64, "{out}");
    assert!(rel(got["buckling_turns"], r.buckling.unwrap().0 / (2.0 * std::f64::consts::PI)) < 1e-12, "{out}");
    let last = r.points.last().unwrap().observables;
    assert!(
        rel(got["last_torque_pN_nm"], last.torque) < 1e-12 && rel(got["last_extension_nm"], last.extension) < 1e-12,
        "{out}"
    );
    let mut bp = r.charge.clone();
    bp.base_pairs = Some(scene.rise);
    let p = solve_point(&r, r.points.len() - 1, &bp, EquilibriumSolver::NewtonKrylov, 1e-10).unwrap();
    assert!(
        rel(got["base_pair_torque_pN_nm"], p.observables.torque) < 1e-12
            && rel(got["base_pair_shift_nm"], p.shift) < 1e-9,
        "{out}"
    );
    assert_eq!(got["gmres_iterations"], p.linear_iterations as f64);
    assert!(rel(got["direct_torque_pN_nm"], got["base_pair_torque_pN_nm"]) < 1e-9, "{out}");
    // The curve's summary and energies through the Fortran types: the
    // Rust summary and energies of the same run (same arithmetic, 1e-12).
    let s = rodkit::charged::summary::summarise(&r).unwrap();
    let energies = rodkit::charged::coexistence::path_energies(&r).unwrap();
    assert_eq!(got["curve_instability_finding"], 1.0, "{out}");
    assert!(rel(got["curve_instability_turns"], s.instability.value.unwrap().turns) < 1e-12, "{out}");
    let code = |f: rodkit::charged::summary::Finding| {
        use rodkit::charged::summary::Finding::*;
        match f {
            Found => 1.0,
            Unverified => 2.0,
            Undetermined => 3.0,
            NotReached => 4.0,
        }
    };
    assert_eq!(got["curve_coexistence_finding"], code(s.coexistence.finding), "{out}");
    assert_eq!(got["curve_superhelix_finding"], code(s.superhelix.finding), "{out}");
    assert_eq!(got["curve_points"], r.points.len() as f64);
    assert!(rel(got["curve_last_energy_pN_nm"], *energies.last().unwrap()) < 1e-12, "{out}");
    assert_eq!(got["curve_last_branch"], r.points.last().unwrap().branch as f64);
    assert!(rel(got["direct_tip_z_nm"], got["base_pair_extension_nm"]) < 1e-9, "{out}");
    // Stopped by the Fortran callback after 15 points, then resumed: the
    // uninterrupted path's end (bitwise on the buckled branch, 1e-8 if
    // stopped on the straight one: tests/supercoil_resume.rs says why),
    // every point told once, in order.
    assert_eq!((got["cancel_status"], got["cancelled_stop"], got["cancelled_points"]), (2.0, 1.0, 15.0), "{out}");
    assert_eq!((got["resumed_stop"], got["resumed_points"]), (0.0, r.points.len() as f64), "{out}");
    assert_eq!((got["told_points"], got["told_in_order"]), (r.points.len() as f64, 1.0), "{out}");
    let tol = if got["cancelled_branch"] == 1.0 { 1e-15 } else { 1e-8 };
    assert!(
        rel(got["resumed_last_extension_nm"], last.extension) < tol
            && rel(got["resumed_last_torque_pN_nm"], last.torque) < tol,
        "{out}"
    );
    assert_eq!(run("f_dna_supercoil_static", &[]), out);
}

/// The C driver of the supercoiling run's progress and resume (issue 18):
/// stopped by its C callback after 20 points (on the buckled branch of the
/// 300 bp scene, 30 elements, 25 steps), INFO_CANCELLED with the path so
/// far, resumed to the uninterrupted run's path bitwise (its status, its
/// points; tests/supercoil_resume.rs says why bitwise), every point told
/// once, in order; stopped after 4 points (on the straight branch) within
/// 1e-8 (the Newton tolerance; why: tests/supercoil_resume.rs). The
/// uninterrupted run is the driver's own `rodkit_dna_supercoil_run`; its
/// point count is the Rust API's. The static build prints the same.
#[test]
fn c_dna_supercoil_resume_driver() {
    use rodkit::charged::dna::{run_scene, DnaScene, SupercoilSettings};
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let settings = SupercoilSettings { elements: 30, max_steps: 25, max_turns: 2.5, ..Default::default() };
    let r = run_scene(&scene, &settings).unwrap();
    for (k, branch, tol) in [("20", 1.0, 0.0), ("4", 0.0, 1e-8)] {
        let out = run("c_dna_supercoil_resume_shared", &["300", "30", "25", k]);
        let got = values(&out);
        let k: f64 = k.parse().unwrap();
        assert_eq!((got["cancel_status"], got["cancelled_stop"]), (2.0, 1.0), "{out}");
        assert_eq!((got["cancelled_points"], got["cancelled_branch"]), (k, branch), "{out}");
        assert_eq!((got["resumed_stop"], got["resumed_status"]), (0.0, got["uninterrupted_status"]), "{out}");
        let n = r.points.len() as f64;
        assert_eq!((got["uninterrupted_points"], got["resumed_points"], got["told_points"]), (n, n, n), "{out}");
        assert_eq!(got["told_in_order"], 1.0, "{out}");
        assert!(got["worst_relative_difference"] <= tol, "{out}");
        // The resumed path against the Rust API's uninterrupted run,
        // recomputed here from the printed points (not the driver's own
        // difference, which once read a NaN as 0): bitwise after a stop on
        // the buckled branch, the Newton tolerance after one on the straight.
        let mut worst = 0.0f64;
        for (i, p) in r.points.iter().enumerate() {
            let o = &p.observables;
            for (name, want) in
                [("turns", o.turns), ("extension", o.extension), ("torque", o.torque), ("writhe", o.writhe)]
            {
                let key = format!("resumed_{name}_{i}");
                let v = *got.get(&key).unwrap_or_else(|| panic!("no {key} in {out}"));
                let d = (v - want).abs() / want.abs().max(1.0);
                assert!(d <= tol, "{key}: {v} vs Rust {want}");
                worst = worst.max(d);
            }
        }
        println!("stop after {k} points: resumed path vs Rust, worst {worst:e}");
        assert_eq!(run("c_dna_supercoil_resume_static", &["300", "30", "25", &format!("{k}")]), out);
    }
}

/// The C DNA-supercoiling driver on a small scene (300 bp, 40 elements, 20
/// steps): its buckling point, last point and linking check equal the Rust
/// API's run of the same scene (same arithmetic, to 1e-12), also with base
/// pairs and under a torque clamp; Tw + Wr = turns
/// along the path to 1e-4; the CSV has every point and the VTK the shapes;
/// the static build prints the same.
#[test]
fn c_dna_supercoil_driver() {
    use rodkit::charged::dna::{run_scene, DnaScene, SupercoilSettings};
    let dir = std::env::temp_dir().join(format!("rodkit-supercoil-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (csv, vtk) = (dir.join("d.csv"), dir.join("d.vtk"));
    let args = ["0.1", "20", csv.to_str().unwrap(), vtk.to_str().unwrap(), "40", "300"];
    let out = run_values("c_dna_supercoil_shared", &args);
    let got = values(&out);
    let scene = DnaScene { base_pairs: 300, ..Default::default() };
    let settings = SupercoilSettings { elements: 40, max_steps: 20, ..Default::default() };
    let r = run_scene(&scene, &settings).unwrap();
    let two_pi = 2.0 * std::f64::consts::PI;
    let (phi_b, m_b) = r.buckling.unwrap();
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
    assert!(rel(got["buckling_turns"], phi_b / two_pi) < 1e-12, "{out}");
    assert!(rel(got["buckling_torque_pN_nm"], m_b) < 1e-12);
    let last = r.points.last().unwrap().observables;
    assert_eq!(got["points"], r.points.len() as f64);
    assert!(
        rel(got["last_extension_nm"], last.extension) < 1e-12 && rel(got["last_torque_pN_nm"], last.torque) < 1e-12
    );
    assert!(got["worst_linking_error"] < 1e-4, "{out}");
    assert!(got["last_extension_nm"] < 0.999 * scene.length(), "the path did not leave the straight rod: {out}");
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count() - 1;
    assert_eq!(rows as f64, got["points"]);
    let v = std::fs::read_to_string(&vtk).unwrap();
    assert!(v.starts_with("# vtk DataFile") && v.contains("LINES ") && v.contains("SCALARS turns"));
    // Timing aside, the static build prints the same.
    let untimed = |t: &str| t.lines().filter(|l| !l.starts_with("seconds")).collect::<Vec<_>>().join("\n");
    assert_eq!(untimed(&run_values("c_dna_supercoil_static", &args)), untimed(&out));
    assert_eq!(got["base_pair_charges"], 0.0, "the continuum is the default model");
    // The last point re-solved with base-pair charges: the Rust API's
    // solve_point (1e-12); Newton–Krylov and the direct solver agree; the
    // shape moves, by far less than the radius (3.0e-2 nm measured).
    {
        use rodkit::charged::equilibrium::{solve_point, EquilibriumSolver};
        let mut bp = r.charge.clone();
        bp.base_pairs = Some(scene.rise);
        // The driver's tolerance (1e-9: Newton–Krylov's rounding floor).
        let p = solve_point(&r, r.points.len() - 1, &bp, EquilibriumSolver::NewtonKrylov, 1e-9).unwrap();
        assert_eq!(got["direct_status"], 0.0, "{out}");
        assert!(rel(got["other_model_torque_pN_nm"], p.observables.torque) < 1e-12, "{out}");
        assert!(rel(got["other_model_tip_z_nm"], p.observables.extension) < 1e-12);
        assert!(got["solver_torque_difference"].abs() < 1e-7 * p.observables.torque, "{out}");
        assert!(got["other_model_shift_nm"] > 1e-6 && got["other_model_shift_nm"] < 0.5, "{out}");
    }
    // The discrete base-pair model through the same driver: 300 point
    // charges, the Rust API's buckling point to 1e-12, and within 2e-3 of
    // the continuum's (the models differ by near-field terms).
    let args_d = ["0.1", "10", csv.to_str().unwrap(), vtk.to_str().unwrap(), "40", "300", "discrete"];
    let got_d = values(&run_values("c_dna_supercoil_shared", &args_d));
    let rd =
        run_scene(&scene, &SupercoilSettings { elements: 40, max_steps: 10, base_pairs: true, ..Default::default() })
            .unwrap();
    assert_eq!(got_d["base_pair_charges"], 300.0);
    assert!(rel(got_d["buckling_turns"], rd.buckling.unwrap().0 / two_pi) < 1e-12);
    assert!(
        rel(got_d["buckling_turns"], got["buckling_turns"]) < 2e-3,
        "discrete {} vs continuum {}",
        got_d["buckling_turns"],
        got["buckling_turns"]
    );
    // Its last point re-solved with the continuum: both solvers agree.
    assert!(got_d["solver_torque_difference"].abs() < 1e-7 * got_d["other_model_torque_pN_nm"], "{got_d:?}");
    // Under a torque clamp: the Rust API's torque-controlled run (1e-12),
    // the same buckling point as rotation control (1e-6).
    let args_t = ["0.1", "20", csv.to_str().unwrap(), vtk.to_str().unwrap(), "40", "300", "continuum", "torque"];
    let out_t = run_values("c_dna_supercoil_shared", &args_t);
    assert!(out_t.contains("continued in the end torque"), "{out_t}");
    let got_t = values(&out_t);
    let settings_t = SupercoilSettings { control: rodkit::charged::dna::EndControl::Torque, ..settings };
    let rt = run_scene(&scene, &settings_t).unwrap();
    let last_t = rt.points.last().unwrap().observables;
    assert_eq!(got_t["points"], rt.points.len() as f64);
    assert!(
        rel(got_t["last_torque_pN_nm"], last_t.torque) < 1e-12
            && rel(got_t["last_extension_nm"], last_t.extension) < 1e-12,
        "{out_t}"
    );
    assert!(
        rel(got_t["buckling_turns"], got["buckling_turns"]) < 1e-6 && rel(got_t["buckling_torque_pN_nm"], m_b) < 1e-6,
        "{out_t}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The force × salt map driver (c_examples/dna_map.c, issue 18 deliverable
/// 5) with `--model full-rod` (the map's default is the thermal model since
/// issue 37) on a small map: 300 bp, 1 pN × 0.1 and 0.05 M, to 1.7 turns (40
/// elements, 300 steps; ~12 s). It writes its files into the one folder
/// given: one CSV per curve with every path point (the count of the Rust
/// run of the same scene), summary.csv with one row per curve and the
/// SVG families (parsed as XML: one polyline per curve). The 1 pN, 0.1 M
/// row equals the Rust summary of the same scene (tests/supercoil_summary.rs
/// checks that summary against independent references) to the CSV's 10
/// significant digits (relative 1e-9); cells of quantities not determined
/// are empty, never numbers.
#[test]
fn c_dna_map_driver() {
    use rodkit::charged::dna::{run_scene, DnaScene, SupercoilSettings};
    use rodkit::charged::summary::{summarise, Finding};
    let dir = std::env::temp_dir().join(format!("rodkit-dna-map-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out_dir = dir.join("nested/map");
    let args = [
        "--model",
        "full-rod",
        "--bp",
        "300",
        "--forces",
        "1",
        "--salts",
        "0.1,0.05",
        "--turns",
        "1.7",
        "--elements",
        "40",
        "--steps",
        "300",
    ];
    let mut all: Vec<&str> = args.to_vec();
    all.push(out_dir.to_str().unwrap());
    let out = run_values("c_dna_map_shared", &all);
    let got = values(&out);
    assert_eq!((got["curves"], got["failed_curves"]), (2.0, 0.0), "{out}");
    assert!(out.contains(&format!("{}/", out_dir.canonicalize().unwrap().display())), "{out}");
    let summary = std::fs::read_to_string(out_dir.join("summary.csv")).unwrap();
    let mut lines = summary.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<BTreeMap<&str, &str>> =
        lines.map(|l| header.iter().copied().zip(l.split(',')).collect::<BTreeMap<_, _>>()).collect();
    assert_eq!(rows.len(), 2);
    for r in &rows {
        assert_eq!(r.len(), header.len(), "a short row: {r:?}");
        // The model behind the row (issue 37): the full rod at zero temperature.
        assert_eq!((r["model"], r["kT_pN_nm"], r["end_loop"]), ("full_rod", "0", ""), "{r:?}");
    }
    let table: Vec<&str> = out.lines().filter(|l| l.starts_with("  ") && l.contains('|')).collect();
    assert!(table.len() == 2 && table.iter().all(|l| l.ends_with("| full_rod")), "{out}");
    let row = rows.iter().find(|r| r["salt_M"] == "0.1").expect("the 0.1 M row");
    let scene = DnaScene { base_pairs: 300, tension: 1.0, salt: 0.1, ..Default::default() };
    let settings = SupercoilSettings { elements: 40, max_turns: 1.7, max_steps: 300, ..Default::default() };
    let run_ = run_scene(&scene, &settings).unwrap();
    let s = summarise(&run_).unwrap();
    let num = |k: &str| row[k].parse::<f64>().unwrap_or_else(|_| panic!("{k} = {:?}", row[k]));
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1e-12);
    assert_eq!(num("points"), run_.points.len() as f64);
    let i = s.instability.value.unwrap();
    assert!(row["instability_finding"] == "found" && close(num("instability_turns"), i.turns));
    assert!(close(num("instability_torque_pN_nm"), i.torque));
    let c = s.coexistence.value.unwrap();
    assert!(row["coexistence_finding"] == "found" && close(num("coexistence_turns"), c.turns));
    assert!(close(num("coexistence_torque_straight_pN_nm"), c.torque_straight));
    assert!(close(num("coexistence_extension_jump_nm"), c.extension_jump));
    let p = s.plateau.value.unwrap();
    assert_eq!(row["plateau_finding"], "found");
    assert!(close(num("plateau_torque_pN_nm"), p.torque) && close(num("slope_nm_per_turn"), p.slope));
    assert!(close(num("superhelix_radius_nm"), s.superhelix.value.unwrap().radius));
    // Findings without numbers leave their cells empty.
    for r in &rows {
        for (f, cells) in [
            ("coexistence_finding", &["coexistence_turns", "coexistence_torque_plectoneme_pN_nm"][..]),
            ("plateau_finding", &["plateau_torque_pN_nm", "slope_nm_per_turn"][..]),
            ("superhelix_finding", &["superhelix_radius_nm"][..]),
        ] {
            let has = matches!(r[f], "found" | "unverified");
            assert!(["found", "unverified", "undetermined", "not_reached"].contains(&r[f]), "{f} = {}", r[f]);
            for k in cells {
                assert_eq!(r[k].is_empty(), !has, "{k} with {f} = {}", r[f]);
            }
        }
    }
    assert_eq!(s.coexistence.finding, Finding::Found);
    // One CSV per curve, every point (the 0.1 M one: the Rust run's count).
    let curve = std::fs::read_to_string(out_dir.join("curve_F1_S0.1.csv")).unwrap();
    assert_eq!(curve.lines().count() - 1, run_.points.len());
    assert!(curve.lines().next().unwrap().contains("energy_pN_nm") && curve.contains(",lowest,"));
    assert!(out_dir.join("curve_F1_S0.05.csv").exists());
    for svg in ["extension_vs_turns.svg", "torque_vs_turns.svg"] {
        let text = std::fs::read_to_string(out_dir.join(svg)).unwrap();
        assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"));
        assert_eq!(text.matches("<polyline").count(), 2, "{svg}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `make run` as a user sees it (its reports, `make run-drivers`, on the
/// drivers built above), started from an empty temporary directory with
/// `make -C <repo>` and OUT elsewhere: one section per capability, no
/// `name = value` dump, every file a report names is under OUT and exists,
/// nothing is written to the working directory, and nothing on stderr (the
/// error demo is quiet). The DNA runs are shrunk (150 bp; the variables the
/// Makefile offers for that) to keep this test short (~15 s on an idle machine).
#[test]
fn make_run_reports_from_any_directory() {
    drivers();
    let tmp = std::env::temp_dir().join(format!("rodkit-make-run-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let (cwd, out_dir) = (tmp.join("elsewhere"), tmp.join("out"));
    std::fs::create_dir_all(&cwd).unwrap();
    let out = Command::new("make")
        .current_dir(&cwd)
        .args(["-s", "--no-print-directory", "-C", ROOT, "run-drivers", &format!("PROFILE={}", profile())])
        .arg(format!("TARGET_DIR={}", native_build::test_target_dir().display()))
        .arg(format!("OUT={}", out_dir.display()))
        .arg("DNA_MAP_SUBSET=--bp 150 --elements 12 --steps 20 --turns 1.5 --forces 1 --salts 0.1")
        .args(["DNA_SUPERCOIL_STEPS=10", "DNA_SUPERCOIL_SCENE=20 150"])
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("run make");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let text = check(out, "make run-drivers");
    assert!(stderr.is_empty(), "stderr:\n{stderr}");
    for section in ["== Tubes", "== Rods", "== DNA", "== Errors"] {
        assert_eq!(text.matches(section).count(), 1, "{section}:\n{text}");
    }
    assert!(values(&text).is_empty(), "name = value lines in the report:\n{text}");
    // The reports' figures: the extensible Euler load (physics.md §2.6,
    // 2.4533568605 to the printed 10 decimals) and Greenhill's first root.
    assert!(text.contains("critical load 2.4533568605"), "{text}");
    assert!(text.contains("8.986819"), "{text}");
    // The thermal model beside the tweezers data (issue 37): the table
    // names the data file, its sources and the unverified rows.
    for want in
        ["model vs data", "tests/data/tweezers/buckling_torque.csv", "Lee2023", "spec_unverified", "thermal_two_phase"]
    {
        assert!(text.contains(want), "{want}:\n{text}");
    }
    // Every path a report names lies under OUT and exists; the folders the
    // Makefile promises hold what the drivers wrote.
    let out_str = out_dir.display().to_string();
    let named: Vec<&str> = text
        .split_whitespace()
        .filter(|w| w.starts_with('/') && !w.contains("c_examples/data"))
        .map(|w| w.trim_end_matches(['/', ':', ')', ',']))
        .filter(|w| !w.is_empty())
        .collect();
    assert!(named.len() >= 10, "{named:?}");
    for p in &named {
        assert!(p.starts_with(&out_str), "{p} is outside {out_str}");
        assert!(Path::new(p).exists(), "{p} is named but missing");
    }
    for f in [
        "tubes/artery_stretch.csv",
        "tubes/dna_tube_stretch.csv",
        "tubes/dna_wall_stretch.csv",
        "rods/buckling.csv",
        "rods/buckling.vtk",
        "rods/follower.vtk",
        "rods/follower_samples.csv",
        "dna/supercoil.csv",
        "dna/supercoil.vtk",
        "dna/map/summary.csv",
        "dna/map/extension_vs_turns.svg",
        "dna/plateau/summary.csv",
        "dna/plateau/plateau_torque_vs_force.svg",
    ] {
        assert!(out_dir.join(f).is_file(), "{f} missing under {out_str}");
    }
    assert_eq!(std::fs::read_dir(&cwd).unwrap().count(), 0, "files in the working directory");
    let _ = std::fs::remove_dir_all(&tmp);
}

//! The C, C++ and Fortran drivers, built (through the Makefile) against the
//! shared and the static library and run; their printed numbers are compared
//! with the Rust API on the inputs they echo, and the C drivers are run under
//! valgrind. Needs gcc, g++, gfortran, make and valgrind (`.ci/deps`).

use rodkit::tube::{OrthotropicSurface, ThinTube};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn profile() -> &'static str {
    if cfg!(debug_assertions) { "debug" } else { "release" }
}

fn build_dir() -> PathBuf {
    Path::new(ROOT).join("target").join(profile()).join("native")
}

/// `cargo test` builds only the rlib: build the cdylib and staticlib with the
/// same profile and features (a no-op when current), then the drivers.
fn drivers() -> &'static PathBuf {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(|| {
        let mut cargo = Command::new(env!("CARGO"));
        cargo.current_dir(ROOT).args(["build", "--lib", "--quiet"]);
        if profile() == "release" {
            cargo.arg("--release");
        }
        if cfg!(feature = "sundials") {
            cargo.args(["--features", "sundials"]);
        }
        check(cargo.output().expect("run cargo build"), "cargo build --lib");
        let make = Command::new("make")
            .current_dir(ROOT)
            .args(["--no-print-directory", "-s", "drivers", &format!("PROFILE={}", profile())])
            .output()
            .expect("run make");
        check(make, "make drivers");
        build_dir()
    })
}

fn check(out: Output, what: &str) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{what} failed ({}):\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

fn run(exe: &str, args: &[&str]) -> String {
    let out = Command::new(drivers().join(exe)).args(args).current_dir(ROOT).output().expect(exe);
    check(out, exe)
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
    let shared = run("c_tube_stiffness_shared", &[]);
    assert_matches_rust("c shared", &shared);
    assert_eq!(values(&shared)["winding"], 1.0, "the bundled DNA-like tube overwinds");
    let stat = run("c_tube_stiffness_static", &["c_examples/data/dna_tube.txt"]);
    assert_eq!(shared, stat, "shared and static builds print the same");
}

#[test]
fn c_driver_reads_another_input() {
    let dir = std::env::temp_dir().join(format!("rodkit-native-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let input = dir.join("iso.txt");
    std::fs::write(&input, "mid_radius = 2.5\nthickness = 0.01 # thin\nintrinsic_twist = -0.3\ne1 = 70e3\ne2 = 70e3\nnu12 = 0.33\ng12 = 26315.789473684212\n").unwrap();
    let out = run("c_tube_stiffness_shared", &[input.to_str().unwrap()]);
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

#[test]
fn fortran_driver_shared_and_static_match_rust() {
    let shared = run("f_tube_stiffness_shared", &[]);
    assert_matches_rust("fortran shared", &shared);
    assert_eq!(values(&shared)["error_caught"], 1.0);
    let stat = run("f_tube_stiffness_static", &["fortran_examples/dna_tube.nml"]);
    assert_eq!(shared, stat);
    // Same tube as the C driver's default input: same numbers.
    let c = values(&run("c_tube_stiffness_shared", &[]));
    for (k, v) in values(&shared) {
        if let Some(cv) = c.get(&k) {
            assert_eq!(*cv, v, "C and Fortran differ on {k}");
        }
    }
}

#[test]
fn bad_input_driver_passes_all_checks() {
    for exe in ["c_bad_input_shared", "c_bad_input_static"] {
        let out = run(exe, &[]);
        assert!(!out.contains("FAIL"), "{exe}:\n{out}");
        assert!(out.lines().any(|l| l == "14 passed, 0 failed"), "{exe}:\n{out}");
    }
}

/// No invalid access and no definite leak in the C drivers (valgrind's
/// memcheck; exit code 99 on any error).
#[test]
fn c_drivers_are_clean_under_valgrind() {
    for exe in ["c_tube_stiffness_shared", "c_tube_stiffness_static", "c_bad_input_shared", "c_bad_input_static", "c_artery_shared"] {
        let out = Command::new("valgrind")
            .args(["-q", "--error-exitcode=99", "--leak-check=full", "--errors-for-leak-kinds=definite", "--show-leak-kinds=definite"])
            .arg(drivers().join(exe))
            .current_dir(ROOT)
            .env("RUST_BACKTRACE", "0")
            .output()
            .expect("run valgrind");
        check(out, &format!("valgrind {exe}"));
    }
}

/// `make install` writes a working pkg-config file: a C program compiles and
/// links with `pkg-config --cflags --libs rodkit` (shared) and with the
/// static archive plus `pkg-config --static --libs-only-l` flags.
#[test]
fn installed_library_links_through_pkg_config() {
    drivers();
    let prefix = std::env::temp_dir().join(format!("rodkit-install-{}", std::process::id()));
    let make = Command::new("make")
        .current_dir(ROOT)
        .args(["--no-print-directory", "-s", "install", &format!("PROFILE={}", profile())])
        .arg(format!("PREFIX={}", prefix.display()))
        .arg("CARGO=true") // the library is already built
        .output()
        .unwrap();
    check(make, "make install");
    let pc = prefix.join("lib/pkgconfig");
    let flags = |args: &[&str]| {
        let out = Command::new("pkg-config").args(args).arg("rodkit").env("PKG_CONFIG_PATH", &pc).output().unwrap();
        check(out, "pkg-config").split_whitespace().map(String::from).collect::<Vec<_>>()
    };
    assert_eq!(flags(&["--modversion"]), vec![env!("CARGO_PKG_VERSION").to_string()]);
    let src = Path::new(ROOT).join("c_examples/tube_stiffness.c");
    let exe = prefix.join("ts_pkgconfig");
    let mut gcc = Command::new("gcc");
    gcc.arg("-std=c11").arg(&src).args(flags(&["--cflags", "--libs"]));
    gcc.arg(format!("-Wl,-rpath,{}", prefix.join("lib").display())).arg("-lm").arg("-o").arg(&exe);
    check(gcc.output().unwrap(), "gcc with pkg-config");
    let exe_static = prefix.join("ts_pkgconfig_static");
    let mut gcc = Command::new("gcc");
    gcc.arg("-std=c11").arg(&src).args(flags(&["--cflags"])).arg(prefix.join("lib/librodkit.a"));
    gcc.args(flags(&["--static", "--libs-only-l"]).into_iter().filter(|f| f != "-lrodkit")).arg("-o").arg(&exe_static);
    check(gcc.output().unwrap(), "gcc static with pkg-config");
    for exe in [&exe, &exe_static] {
        let out = Command::new(exe).current_dir(ROOT).output().unwrap();
        assert_matches_rust("installed", &check(out, "installed driver"));
    }
    let _ = std::fs::remove_dir_all(&prefix);
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
    let out = run("c_artery_shared", &[csv.to_str().unwrap()]);
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
        .map(|i| Loading { axial: Axial::Stretch(1.0 + 0.01 * i as f64), torsion: Torsion::Torque(0.0), inner_pressure: 13.33, outer_pressure: 0.0, ends: Ends::Closed })
        .collect();
    let (sweep, _) = scene.sweep(&loadings, |_, _| true).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<Vec<f64>> = text.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), 31);
    for (row, s) in rows.iter().zip(&sweep.states) {
        assert_eq!(row[0], s.stretch);
        assert_eq!(row[1], s.applied_force);
        assert_eq!(row[4], s.deformed_inner_radius);
        assert!(row[3].abs() < 1e-12, "± families: no twist");
    }
    // Stretching at fixed pressure narrows the lumen and raises the force.
    assert!(rows.windows(2).all(|w| w[1][4] < w[0][4] && w[1][1] > w[0][1]));
    let stat = run("c_artery_static", &[csv.to_str().unwrap()]);
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
    let out = run("f_stretch_sweep_shared", &[]);
    let got = values(&out);
    let o = Orthotropic::new(467.2, 516.2, 516.2, 0.3, 0.3, 0.3, 139.8, 139.8, 516.2 / 2.6).unwrap();
    let tau0 = (std::f64::consts::PI / 3.0).tan();
    let scene = TubeScene::new(0.8, 1.2, WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(o, tau0, false)), TubeModel::Thick, 1e-10, None).unwrap();
    let loadings: Vec<Loading> = (0..26).map(|i| Loading::torsion_free_stretch(1.0 + 0.002 * i as f64)).collect();
    let (sweep, _) = scene.sweep(&loadings, |_, _| true).unwrap();
    let last = sweep.states.last().unwrap();
    for (k, want) in [("twist", last.twist), ("applied_force", last.applied_force), ("outer_radius", last.deformed_outer_radius)] {
        assert!((got[k] - want).abs() <= 4.0 * f64::EPSILON * want.abs(), "{k}: {} vs {want}", got[k]);
    }
    assert!(got["twist"] > 0.0, "the DNA-like wall overwinds (τ0 > 0)");
    assert_eq!(out.matches("# progress").count(), 5);
    assert_eq!(run("f_stretch_sweep_static", &[]), out);
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
    let got = values(&run("c_dna_tube_shared", &[csv.to_str().unwrap()]));
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
    for (k, want) in [("rod_stretch", thick.thick.stretch), ("rod_twist", thick.thick.twist), ("rod_twist_stretch", thick.thick.coupling)] {
        assert!((got[k] - want).abs() <= 1e-8 * want.abs(), "{k}: {} vs {want}", got[k]);
    }
    assert!(got["rod_error_estimate"] <= 1e-10);
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count() - 1;
    assert_eq!(rows, 41);
    let _ = std::fs::remove_dir_all(&dir);
}

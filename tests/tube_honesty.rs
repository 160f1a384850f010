//! Issue 17, "no silent wrong answers", tube part: every error estimate bounds
//! the error it claims to bound, AUTO meets its tolerance, and a state that is
//! not finite or not physical is a status, never OK.

// Only the laws of the cases are used here (their geometry and model are
// tests/tube_behaviour.rs's business).
#[allow(dead_code)]
#[path = "support/behaviour_cases.rs"]
mod behaviour_cases;

use rodkit::capi::error::rodkit_last_error_message;
use rodkit::capi::thin_tube::*;
use rodkit::capi::tube::*;
use rodkit::capi::wall_material::*;
use rodkit::tube::finite::{
    state_difference, stress_scale, Axial, Ends, FiniteTube, Loading, SolveOptions, Torsion, TubeState,
};
use rodkit::tube::material::{FibreAngle, FibreFamily, FibreReinforced, NeoHookean, SaintVenantKirchhoff};
use rodkit::tube::scene::{TubeModel, TubeScene, WallLaw};
use rodkit::tube::Orthotropic;
use rodkit::Status;
use std::ffi::CStr;
use std::ptr;

fn last_error() -> String {
    unsafe { CStr::from_ptr(rodkit_last_error_message()) }.to_string_lossy().into_owned()
}

/// The thick model's error measure and its stress scale are the library's
/// own definitions (`finite::state_difference`: radii per B, λ, ψB, F per
/// μπB², T per μπB³; `finite::stress_scale`: the law's small-strain stress
/// at the mid radius): the test compares states in the units the estimates
/// are stated in.
fn modulus(law: &WallLaw, r: f64) -> f64 {
    stress_scale(law.as_material(), r).unwrap()
}

fn helical() -> Orthotropic {
    Orthotropic::new(10.0, 2.0, 1.5, 0.35, 0.3, 0.4, 1.2, 0.8, 0.6).unwrap()
}

/// Every wall law of tests/support/behaviour_cases.rs and six more: SVK
/// compressible and incompressible, neo-Hookean both ways, fibre walls with
/// fixed angles and with helical families.
fn laws() -> Vec<(String, WallLaw)> {
    let mut out: Vec<(String, WallLaw)> =
        behaviour_cases::cases().into_iter().map(|c| (c.name.into(), c.law)).collect();
    let fam = |hand| FibreFamily { angle: FibreAngle::Helix { hand }, k1: 2.3, k2: 0.8 };
    out.extend([
        ("svk".into(), WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(helical(), 1.7, false))),
        ("svk_inc".into(), WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(helical(), 1.7, true))),
        ("nh".into(), WallLaw::NeoHookean(NeoHookean { shear_modulus: 1.0, lame_lambda: 5.0, incompressible: false })),
        (
            "nh_inc".into(),
            WallLaw::NeoHookean(NeoHookean { shear_modulus: 1.0, lame_lambda: 0.0, incompressible: true }),
        ),
        (
            "hgo_helix".into(),
            WallLaw::FibreReinforced(FibreReinforced {
                matrix: NeoHookean { shear_modulus: 0.3, lame_lambda: 30.0, incompressible: false },
                families: vec![fam(1.0), fam(-1.0)],
                intrinsic_twist: 0.9,
            }),
        ),
    ]);
    out
}

/// Stretch, inner pressure (closed ends), outer pressure (free ends) and
/// twist; pressures scale with t/R so the hoop strain stays O(0.1).
fn loadings(t: f64) -> [(&'static str, Loading); 4] {
    [
        ("stretch", Loading::torsion_free_stretch(1.3)),
        (
            "p_in",
            Loading {
                axial: Axial::Stretch(1.1),
                torsion: Torsion::Torque(0.0),
                inner_pressure: 0.1 * t,
                outer_pressure: 0.0,
                ends: Ends::Closed,
            },
        ),
        (
            "p_out",
            Loading {
                axial: Axial::Force(0.0),
                torsion: Torsion::Torque(0.0),
                inner_pressure: 0.0,
                outer_pressure: 0.05 * t,
                ends: Ends::Open,
            },
        ),
        (
            "twist",
            Loading {
                axial: Axial::Force(0.0),
                torsion: Torsion::Twist(0.3),
                inner_pressure: 0.0,
                outer_pressure: 0.0,
                ends: Ends::Open,
            },
        ),
    ]
}

/// The reference: the thick wall at a tight tolerance (its two-grid
/// estimate, itself checked in `thick_estimate_bounds_a_finer_grid`), 1e−11,
/// or 1e−9 for walls thinner than 2e−3 whose round-off floor (nε·B/t) is
/// above 1e−11.
fn reference(law: &WallLaw, r: f64, t: f64, l: &Loading) -> Option<TubeState> {
    let tol = if t < 2e-3 { 1e-9 } else { 1e-11 };
    let m: &dyn rodkit::tube::material::WallMaterial = match law {
        WallLaw::SaintVenantKirchhoff(m) => m,
        WallLaw::NeoHookean(m) => m,
        WallLaw::FibreReinforced(m) => m,
    };
    FiniteTube::new(r - t / 2.0, r + t / 2.0, m).ok()?.solve(l, &SolveOptions { rel_tol: tol, intervals: None }).ok()
}

/// Finding 1: the membrane's estimate bounds its true error (thick wall at a
/// tight tolerance as reference) for t/R from 1e−4 to 0.5, over every law and
/// four loadings, and AUTO's answer meets its tolerance against the same
/// reference. Before issue 17 the estimate was 7e−15 for the fixed-angle
/// fibre wall at t/R = 0.1 (true 1.5e−3) and 2.4e−7 for an incompressible
/// neo-Hookean wall under inner pressure at t/R = 0.01 (true 1.4e−4).
/// Tolerance: true ≤ estimate exactly (the estimate carries its own safety
/// factor 2, membrane.rs); measured true/estimate ≤ 0.52 over this grid.
#[test]
fn membrane_estimate_bounds_the_thick_wall_and_auto_meets_rel_tol() {
    let r = 1.0;
    let (mut checked, mut unverified, mut worst) = (0, Vec::new(), 0.0f64);
    let (mut answered, mut refused) = (0, Vec::new());
    for (name, law) in laws() {
        let mu = modulus(&law, r);
        for t in [1e-4, 1e-3, 1e-2, 0.1, 0.3, 0.5] {
            for (lname, l) in loadings(t) {
                let what = format!("{name} {lname} t/R {t:e}");
                let scene =
                    |model, tol| TubeScene::new(r - t / 2.0, r + t / 2.0, law.clone(), model, tol, None).unwrap();
                let membrane = scene(TubeModel::Membrane, 1.0).solve(&l);
                let Some(reference) = reference(&law, r, t, &l) else {
                    // No reference: the membrane may not claim an answer
                    // either unless its own thick check solved (recorded).
                    unverified.push(what);
                    continue;
                };
                if let Ok((m, _)) = &membrane {
                    // Less the reference's own error (its estimate, ≤ 1e−9).
                    let true_err =
                        (state_difference(m, &reference, r + t / 2.0, mu) - reference.error_estimate).max(0.0);
                    assert!(
                        true_err <= m.error_estimate,
                        "{what}: true {true_err:e} > estimate {:e}",
                        m.error_estimate
                    );
                    worst = worst.max(true_err / m.error_estimate);
                    checked += 1;
                }
                for tol in [1e-3, 1e-6] {
                    match scene(TubeModel::Auto, tol).solve(&l) {
                        Ok((s, model)) => {
                            let err =
                                (state_difference(&s, &reference, r + t / 2.0, mu) - reference.error_estimate).max(0.0);
                            assert!(err <= tol, "{what}: AUTO ({model:?}) at rel_tol {tol:e} is off by {err:e}");
                            answered += 1;
                            if let Ok((m, _)) = &membrane {
                                // AUTO takes the membrane only where its estimate meets rel_tol.
                                assert_eq!(model == TubeModel::Membrane, m.error_estimate <= tol, "{what}");
                            }
                        }
                        Err(e) => {
                            assert_eq!(e.status, Status::ErrToleranceUnreachable, "{what}: AUTO {e}");
                            refused.push(format!("{what} at {tol:e}"));
                        }
                    }
                }
            }
        }
    }
    // 10 laws × 6 walls × 4 loadings = 240. Without a reference (measured:
    // 14): the SVK wall of the behaviour cases with a compressive dip, which
    // is unstable under outer pressure, twist and thick-wall stretch (a
    // status), and the helical fibre wall under outer pressure or twist at
    // t/R ≤ 1e−2 (its fibres are slack at rest, a kink Newton does not pass).
    assert!(checked >= 200, "only {checked} cases checked; unverified: {unverified:?}");
    assert!(unverified.len() <= 16, "{unverified:?}");
    assert!(worst <= 1.0 / 1.9, "largest true/estimate {worst}");
    // AUTO could refuse a tolerance with ErrToleranceUnreachable, never
    // answer wrongly; but every refusal here would be a capability lost:
    // 1e-3 and 1e-6 are far above these walls' round-off. Measured: 452
    // answered, 0 refused — so none may be.
    assert!(refused.is_empty(), "AUTO refused {} of {} cases: {refused:?}", refused.len(), answered + refused.len());
    assert!(answered >= 2 * 200, "AUTO answered only {answered}");
}

/// Finding 1, the case of the issue: a fixed-angle fibre wall at t/R = 0.3
/// stretched to λ = 1.3 with zero torque. The thick wall (reference, 1e−11)
/// and the membrane disagree on the twist; AUTO at rel_tol 1e−3 must answer
/// with the thick wall and its twist (tolerance 1e−3 in ψB).
#[test]
fn auto_does_not_take_the_membrane_for_a_thick_fibre_wall() {
    let law = behaviour_cases::cases().into_iter().find(|c| c.name == "hgo_two_fixed_families").unwrap().law;
    let (r, t) = (1.0, 0.3);
    let l = Loading::torsion_free_stretch(1.3);
    let thick = reference(&law, r, t, &l).unwrap();
    let scene = TubeScene::new(r - t / 2.0, r + t / 2.0, law.clone(), TubeModel::Auto, 1e-3, None).unwrap();
    let (auto, model) = scene.solve(&l).unwrap();
    assert_eq!(model, TubeModel::Thick);
    assert!((auto.twist - thick.twist).abs() * (r + t / 2.0) <= 1e-3, "{} vs {}", auto.twist, thick.twist);
    let mem =
        TubeScene::new(r - t / 2.0, r + t / 2.0, law, TubeModel::Membrane, 1e-3, None).unwrap().solve(&l).unwrap().0;
    let off = (mem.twist - thick.twist).abs() * (r + t / 2.0);
    assert!(off > 1e-3 && mem.error_estimate >= off, "membrane off by {off:e}, estimate {:e}", mem.error_estimate);
}

/// The thick model's own estimate (difference of two grids) bounds its
/// error against a finer solve (rel_tol 1e−11; 1e−9 below t/R = 2e−3):
/// true ≤ estimate, over the laws, walls and loadings above at rel_tol 1e−5.
#[test]
fn thick_estimate_bounds_a_finer_grid() {
    let r = 1.0;
    let mut checked = 0;
    for (name, law) in laws() {
        let mu = modulus(&law, r);
        for t in [1e-3, 0.1, 0.5] {
            for (lname, l) in loadings(t) {
                let Some(fine) = reference(&law, r, t, &l) else { continue };
                let scene =
                    TubeScene::new(r - t / 2.0, r + t / 2.0, law.clone(), TubeModel::Thick, 1e-5, None).unwrap();
                let (s, _) = scene.solve(&l).unwrap();
                // The reference's own error (its estimate) is part of the
                // comparison: at the 1e−12 level the difference is round-off.
                let err = state_difference(&s, &fine, r + t / 2.0, mu);
                let bound = s.error_estimate + fine.error_estimate;
                assert!(
                    err <= bound,
                    "{name} {lname} t/R {t:e}: {err:e} > {:e} + {:e}",
                    s.error_estimate,
                    fine.error_estimate
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 100, "{checked}");
}

/// Finding 4: a wall of t/R = 1e−6 asked for rel_tol 1e−10 is refused as
/// ErrToleranceUnreachable (was ErrNotConverged) with the best reachable in
/// the message, without solving. At t/R = 1e−4 (where the wall ODE still
/// solves) the best reachable it names for rel_tol 1e−12 is then met
/// (reference: the same solver at that tolerance, whose estimate must not
/// exceed it).
#[test]
fn round_off_floor_is_named_and_reachable() {
    let law = NeoHookean { shear_modulus: 1.0, lame_lambda: 5.0, incompressible: false };
    let l = Loading::torsion_free_stretch(1.1);
    let tube = FiniteTube::new(1.0 - 5e-7, 1.0 + 5e-7, &law).unwrap();
    let e = tube.solve(&l, &SolveOptions { rel_tol: 1e-10, intervals: None }).unwrap_err();
    assert_eq!(e.status, Status::ErrToleranceUnreachable, "{e}");
    assert!(e.message.contains("best reachable"), "{e}");
    let tube = FiniteTube::new(1.0 - 5e-5, 1.0 + 5e-5, &law).unwrap();
    let e = tube.solve(&l, &SolveOptions { rel_tol: 1e-12, intervals: None }).unwrap_err();
    assert_eq!(e.status, Status::ErrToleranceUnreachable, "{e}");
    let best: f64 = e.message.split("about ").nth(1).unwrap().parse().unwrap();
    assert!(best > 1e-12 && best < 1e-9, "{}", e.message);
    let s = tube.solve(&l, &SolveOptions { rel_tol: 2.0 * best, intervals: None }).unwrap();
    assert!(s.error_estimate <= 2.0 * best);
}

/// Finding 4: SVK (isotropic, E = 1, ν = 0.3) in uniaxial tension: the
/// lateral Green strain −ν(λ² − 1)/2 reaches −1/2 (lateral stretch 0) at
/// λ = √(1 + 1/ν) = 2.082 (reference: the closed form of SVK's uniaxial
/// stress). Below it the thin membrane's lateral stretch is √(1 − ν(λ² − 1))
/// (tolerance 1e−9: an algebraic solve); past it the answer is
/// ErrMaterialInstability (it was ErrNotConverged, -9), for both models.
#[test]
fn svk_past_its_stretch_limit_is_material_instability() {
    let nu = 0.3;
    let law =
        WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(Orthotropic::isotropic(1.0, nu).unwrap(), 0.0, false));
    let membrane = TubeScene::new(0.99, 1.01, law.clone(), TubeModel::Membrane, 1.0, None).unwrap();
    let lambda = 2.0;
    let (s, _) = membrane.solve(&Loading::torsion_free_stretch(lambda)).unwrap();
    let lateral = (1.0 - nu * (lambda * lambda - 1.0)).sqrt();
    let hoop = (s.deformed_inner_radius + s.deformed_outer_radius) / 2.0;
    assert!((hoop - lateral).abs() < 1e-9, "{hoop} vs {lateral}");
    for model in [TubeModel::Membrane, TubeModel::Thick, TubeModel::Auto] {
        let scene = TubeScene::new(0.99, 1.01, law.clone(), model, 1e-6, None).unwrap();
        let e = scene.solve(&Loading::torsion_free_stretch(2.2)).unwrap_err();
        assert_eq!(e.status, Status::ErrMaterialInstability, "{model:?}: {e}");
    }
}

/// Finding 2: strong pressures on a membrane: before issue 17 it returned OK
/// with a negative deformed inner radius. Now either a status, or a state
/// with 0 < inner < outer radius that agrees with the thick wall (reference,
/// 1e−9) within its own estimate.
#[test]
fn membrane_under_strong_pressure_is_physical_or_a_status() {
    let laws = [
        WallLaw::NeoHookean(NeoHookean { shear_modulus: 1.0, lame_lambda: 5.0, incompressible: false }),
        WallLaw::NeoHookean(NeoHookean { shear_modulus: 1.0, lame_lambda: 0.0, incompressible: true }),
        WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(Orthotropic::isotropic(1.0, 0.3).unwrap(), 0.0, false)),
    ];
    let mut statuses = 0;
    for law in laws {
        for (p_in, p_out) in [(0.0, 0.05), (0.0, 0.5), (0.0, 5.0), (1.0, 0.0), (5.0, 0.0), (50.0, 0.0)] {
            let l = Loading {
                axial: Axial::Force(0.0),
                torsion: Torsion::Torque(0.0),
                inner_pressure: p_in,
                outer_pressure: p_out,
                ends: Ends::Open,
            };
            let scene = TubeScene::new(0.9, 1.1, law.clone(), TubeModel::Membrane, 1.0, None).unwrap();
            match scene.solve(&l) {
                Ok((s, _)) => {
                    assert!(s.deformed_inner_radius > 0.0 && s.deformed_outer_radius > s.deformed_inner_radius);
                    assert!(s.error_estimate.is_finite());
                    let thick = reference(&law, 1.0, 0.2, &l).expect("a thick reference where the membrane answered");
                    let err = state_difference(&s, &thick, 1.1, modulus(&law, 1.0));
                    assert!(err <= s.error_estimate, "p {p_in} / {p_out}: {err:e} > {:e}", s.error_estimate);
                }
                Err(e) => {
                    statuses += 1;
                    assert!(
                        matches!(e.status, Status::ErrMaterialInstability | Status::ErrNotConverged),
                        "p {p_in} / {p_out}: {e}"
                    );
                }
            }
        }
    }
    assert!(statuses >= 1, "the strongest pressures collapse or burst the section");
}

fn thin_spec(modulus: f64, mid_radius: f64) -> ThinTubeSpec {
    let mut s = std::mem::MaybeUninit::<ThinTubeSpec>::uninit();
    assert_eq!(unsafe { rodkit_thin_tube_spec_default(s.as_mut_ptr()) }, 0);
    let mut s = unsafe { s.assume_init() };
    (s.mid_radius, s.thickness, s.intrinsic_twist) = (mid_radius, 0.1 * mid_radius, 0.7 / mid_radius);
    (s.e1, s.e2, s.nu12, s.g12) = (3.0 * modulus, modulus, 0.3, 0.4 * modulus);
    s
}

/// The five thin-tube outputs for one spec: each Ok(values) or Err(status).
fn thin_outputs(spec: &ThinTubeSpec) -> Vec<Result<Vec<f64>, i32>> {
    let wrap = |st: i32, v: Vec<f64>| if st == 0 { Ok(v) } else { Err(st) };
    let mut alpha = 0.0;
    let st = unsafe { rodkit_thin_tube_helix_angle(spec, &mut alpha) };
    let mut out = vec![wrap(st, vec![alpha])];
    let mut k = [0.0; 9];
    let st = unsafe { rodkit_thin_tube_coupling_stiffness(spec, k.as_mut_ptr(), 3) };
    out.push(wrap(st, k.to_vec()));
    let mut s = [0.0; 4];
    let st = unsafe { rodkit_thin_tube_stretch_twist(spec, s.as_mut_ptr(), 2) };
    out.push(wrap(st, s.to_vec()));
    let mut r = std::mem::MaybeUninit::<FreeTubeResponse>::zeroed();
    let st = unsafe { rodkit_thin_tube_free_response(spec, r.as_mut_ptr()) };
    let r = unsafe { r.assume_init() };
    out.push(wrap(st, vec![r.dstrain_dforce, r.dtwist_dforce, r.dhoop_dforce]));
    let mut k6 = [0.0; 36];
    let st = unsafe { rodkit_thin_tube_rod_stiffness(spec, k6.as_mut_ptr(), 6) };
    out.push(wrap(st, k6.to_vec()));
    out
}

/// Finding 2: moduli 1e187…1e198 and a mid radius of 5.8e91 gave −Inf/NaN
/// with OK. Now each output is a failure status, or finite and equal to the
/// unit-modulus answer scaled (reference: the outputs are homogeneous of
/// degree 1 in the moduli for K, S and the rod law, −1 for the response, 0 for
/// the angle; tolerance 1e−12 relative to each output's largest entry).
#[test]
fn thin_tube_outputs_are_finite_or_a_status() {
    let unit = thin_outputs(&thin_spec(1.0, 1.0));
    let degree = [0, 1, 1, -1, 1];
    let mut refused = 0;
    for e in [1e187, 1e190, 1e194, 1e198, 1e300, 1e-300] {
        for (i, got) in thin_outputs(&thin_spec(e, 1.0)).into_iter().enumerate() {
            match got {
                Ok(v) => {
                    let want = unit[i].as_ref().unwrap();
                    let scale = e.powi(degree[i]);
                    let big = want.iter().fold(0.0f64, |m, w| m.max(w.abs()));
                    for (g, w) in v.iter().zip(want) {
                        assert!(g.is_finite(), "output {i} at E {e:e}: {v:?}");
                        assert!(
                            (g / scale - w).abs() <= 1e-12 * big,
                            "output {i} at E {e:e}: {g:e} vs {w:e}·{scale:e}"
                        );
                    }
                }
                Err(st) => {
                    refused += 1;
                    assert!(
                        st == Status::ErrNonFiniteResult.code() || st == Status::ErrNotPositiveDefinite.code(),
                        "output {i} at E {e:e}: {st} {}",
                        last_error()
                    );
                }
            }
        }
    }
    // Measured: with the condensation formed without overflow every output
    // at these moduli is finite and matches the scaling (none refused).
    assert_eq!(refused, 0);
    for got in thin_outputs(&thin_spec(1.0, 5.8e91)) {
        match got {
            Ok(v) => assert!(v.iter().all(|x| x.is_finite()), "{v:?}"),
            Err(st) => assert_eq!(st, Status::ErrNonFiniteResult.code(), "{}", last_error()),
        }
    }
}

fn tube_spec() -> TubeSpec {
    let mut spec = std::mem::MaybeUninit::<TubeSpec>::uninit();
    assert_eq!(unsafe { rodkit_tube_spec_default(spec.as_mut_ptr()) }, 0);
    let mut spec = unsafe { spec.assume_init() };
    (spec.inner_radius, spec.outer_radius) = (0.95, 1.05);
    let m = &mut spec.material;
    m.law = WallLawKind::SaintVenantKirchhoff as i32;
    m.intrinsic_twist = 1.7;
    (m.e1, m.e2, m.e3, m.nu12, m.nu13, m.nu23, m.g12, m.g13, m.g23) = (10.0, 2.0, 1.5, 0.35, 0.3, 0.4, 1.2, 0.8, 0.6);
    spec.model = TubeModel::Membrane as i32;
    spec
}

fn new_tube(spec: &TubeSpec) -> Result<*mut Tube, (i32, String)> {
    let mut t = ptr::null_mut();
    let st = unsafe { rodkit_tube_new(spec, &mut t) };
    if st < 0 {
        Err((st, last_error()))
    } else {
        Ok(t)
    }
}

/// Finding 3: a tiny or denormal g13 or g23 panicked ("a positive-definite
/// block is invertible") in rodkit_tube_new and the membrane solve. Now
/// ErrNotPositiveDefinite naming the field (reference: the status list).
#[test]
fn tiny_shear_moduli_are_refused_by_name() {
    for v in [1e-300, 5e-324, 1e-13] {
        for field in ["g13", "g23"] {
            let mut s = tube_spec();
            if field == "g13" {
                s.material.g13 = v;
            } else {
                s.material.g23 = v;
            }
            let (st, msg) = new_tube(&s).unwrap_err();
            assert_eq!(st, Status::ErrNotPositiveDefinite.code(), "{field} = {v:e}: {msg}");
            assert!(msg.contains(&format!("`spec.material.{field}`")), "{msg}");
        }
    }
    // Just inside the limit (1.5e−12 of e1) the tube is built and a membrane
    // solve returns a state or a status, never a caught panic (ErrInternal).
    let mut s = tube_spec();
    s.material.g13 = 1.5e-11;
    let t = new_tube(&s).unwrap();
    let mut l = std::mem::MaybeUninit::<TubeLoading>::uninit();
    assert_eq!(unsafe { rodkit_tube_loading_default(l.as_mut_ptr()) }, 0);
    let mut l = unsafe { l.assume_init() };
    l.axial = 1.01;
    let mut out = rodkit::capi::tube::TubeState::default();
    let st = unsafe { rodkit_tube_solve(t, &l, &mut out) };
    assert_ne!(st, Status::ErrInternal.code(), "{}", last_error());
    if st == 0 {
        assert!(out.stretch == 1.01 && out.deformed_inner_radius > 0.0 && out.error_estimate.is_finite());
    }
    unsafe { rodkit_tube_free(t) };
}

fn fibre_spec() -> TubeSpec {
    let mut s = tube_spec();
    let m = &mut s.material;
    m.law = WallLawKind::FibreReinforced as i32;
    (m.shear_modulus, m.lame_lambda) = (1.0, 2.0);
    m.fibre_families = 2;
    (m.fibre1_k1, m.fibre1_k2, m.fibre1_angle) = (2.0, 1.0, 0.3);
    (m.fibre2_k1, m.fibre2_k2, m.fibre2_angle) = (2.0, 1.0, -0.3);
    s
}

/// Finding 5: messages name the C field exactly (family included), a NaN is
/// ErrNotFinite, numbers are printed in exponent form, and an out-of-range
/// family count is ErrOutOfRange saying "out of range" (reference: the
/// status list and the field names of RodkitWallMaterialSpec).
#[test]
fn fibre_fields_are_named_exactly() {
    assert!(new_tube(&fibre_spec()).is_ok());
    let mut s = fibre_spec();
    s.material.fibre2_k1 = -1.0;
    let (st, msg) = new_tube(&s).unwrap_err();
    assert_eq!(st, Status::ErrNotPositive.code());
    assert!(msg.contains("`spec.material.fibre2_k1`"), "{msg}");
    let mut s = fibre_spec();
    s.material.fibre1_k2 = 0.0;
    assert!(new_tube(&s).unwrap_err().1.contains("`spec.material.fibre1_k2`"));
    let mut s = fibre_spec();
    s.material.fibre2_angle = f64::NAN; // helical: the hand is used
    s.material.fibre2_hand = 1e308;
    let (st, msg) = new_tube(&s).unwrap_err();
    assert_eq!(st, Status::ErrOutOfRange.code(), "{msg}");
    assert!(msg.contains("`spec.material.fibre2_hand`") && msg.contains("1e308") && msg.len() < 200, "{msg}");
    let mut s = fibre_spec();
    s.material.fibre1_hand = f64::NAN;
    let (st, msg) = new_tube(&s).unwrap_err();
    assert_eq!(st, Status::ErrNotFinite.code(), "{msg}");
    assert!(msg.contains("`spec.material.fibre1_hand`"), "{msg}");
    for n in [-1, 3, 1 << 40] {
        let mut s = fibre_spec();
        s.material.fibre_families = n;
        let (st, msg) = new_tube(&s).unwrap_err();
        assert_eq!(st, Status::ErrOutOfRange.code());
        assert!(msg.contains("out of range") && msg.contains("material.fibre_families"), "{msg}");
    }
}

//! Tube walls with the finite-strain behaviours the thesis reports for DNA
//! (physics.md §1.5), found by the random search in benches/tube_search.rs.
//! Shared by tests/tube_behaviour.rs (which checks them) and benches/tube.rs
//! (which draws their curves). Parameters in shortest round-trip decimals.

use rodkit::tube::material::{FibreAngle, FibreFamily, FibreReinforced, NeoHookean, SaintVenantKirchhoff};
use rodkit::tube::scene::{TubeModel, WallLaw};
use rodkit::tube::Orthotropic;

pub struct Case {
    pub name: &'static str,
    pub inner: f64,
    pub outer: f64,
    pub law: WallLaw,
    pub model: TubeModel,
}

fn svk(tau0: f64, c: [f64; 9], incompressible: bool) -> WallLaw {
    let m = Orthotropic::new(c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8]).unwrap();
    WallLaw::SaintVenantKirchhoff(SaintVenantKirchhoff::new(m, tau0, incompressible))
}

/// Overwinding then unwinding: the first three; deflation then inflation:
/// the last two.
pub fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "svk_membrane_incompressible",
            inner: 0.95,
            outer: 1.05,
            law: svk(
                0.6847864087805343,
                [
                    1.0,
                    0.054396281299099694,
                    0.2346080374747139,
                    -0.7339228824095344,
                    -0.4356189099590801,
                    -0.3277543169275636,
                    1.6198471629203384,
                    0.007117395145704021,
                    0.041062016466891615,
                ],
                true,
            ),
            model: TubeModel::Membrane,
        },
        Case {
            name: "svk_thick_incompressible",
            inner: 0.05326153850885582,
            outer: 1.0,
            law: svk(
                1.9325262870782816,
                [
                    1.0,
                    0.12011774414329189,
                    0.08341554418974609,
                    0.5032731736996703,
                    0.9056316153495163,
                    -0.2643547837623323,
                    0.013951530973861944,
                    0.02911503825072541,
                    1.8537330851301574,
                ],
                true,
            ),
            model: TubeModel::Thick,
        },
        Case {
            name: "hgo_two_fixed_families",
            inner: 0.4019688295342947,
            outer: 1.0,
            law: WallLaw::FibreReinforced(FibreReinforced {
                matrix: NeoHookean { shear_modulus: 1.0, lame_lambda: 1.6241460068761024, incompressible: false },
                families: vec![
                    FibreFamily {
                        angle: FibreAngle::Fixed(0.10844915684163606),
                        k1: 21.497382082111226,
                        k2: 1.6422213218950554,
                    },
                    FibreFamily {
                        angle: FibreAngle::Fixed(-0.28063544517888944),
                        k1: 4.8144595009238955,
                        k2: 16.40177761765187,
                    },
                ],
                intrinsic_twist: 0.0,
            }),
            model: TubeModel::Thick,
        },
        Case {
            name: "svk_thick_compressible_dip",
            inner: 0.95,
            outer: 1.0,
            law: svk(
                1.4155068812155835,
                [
                    1.0,
                    21.703458493620523,
                    0.3725955590969147,
                    -0.14970820106295166,
                    0.7014956303309042,
                    -0.46895910019071746,
                    0.0901458752822471,
                    0.4272150882911797,
                    0.32860365108397777,
                ],
                false,
            ),
            model: TubeModel::Thick,
        },
        Case {
            name: "svk_thick_incompressible_dip",
            inner: 0.8944626911190109,
            outer: 1.0,
            law: svk(
                1.7613041621354448,
                [
                    1.0,
                    6.89701563125212,
                    3.8090170644815413,
                    -0.26365597849830774,
                    0.13054541593590976,
                    0.5655002691154039,
                    0.04428709825230609,
                    0.278765690673535,
                    0.38913671533210537,
                ],
                true,
            ),
            model: TubeModel::Thick,
        },
    ]
}

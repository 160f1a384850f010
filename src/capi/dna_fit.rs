//! C ABI of the DNA wall fit (physics.md §1.5, `rodkit::tube::dna`).

use super::args::{arg_mut, finite_fields};
use super::guard;
use super::thin_tube::ThinTubeSpec;
use crate::status::Status;
use crate::tube::dna::{fit_thin_wall, thick_comparison, DnaTargets, OutOfPlane};

/// A thin-wall fit to a stretch–twist law, its predictions, and the same
/// material evaluated with the thick wall model.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DnaFit {
    /// The fitted thin tube (geometry as requested, E1, E2, G12 fitted, ν12
    /// as given): usable with the rodkit_thin_tube_* functions.
    pub spec: ThinTubeSpec,
    /// The condensed law the fitted wall achieves: S, g, C.
    pub stretch: f64,
    pub coupling: f64,
    pub twist: f64,
    /// Free-molecule twist rate dψ/dF, rad/(pN·nm), and in turns per pN per
    /// 10 kbp (contour 10⁴ × 0.34 nm).
    pub twist_rate: f64,
    pub turns_per_pn_per_10kbp: f64,
    /// 1 if the fitted tube overwinds when pulled (twists further in the sense
    /// of τ0), else 0.
    pub overwinds: i32,
    /// Status of the thick-wall evaluation of the same material (3-D
    /// constants completed transversely isotropically about the helix:
    /// E3 = E2, ν13 = ν23 = ν12, G13 = G12, G23 = E2/(2(1+ν23))), with
    /// A = R − t/2, B = R + t/2. When it is negative (e.g. the completion is
    /// not positive definite) the thick_* fields are 0.
    pub thick_status: i32,
    /// The thick wall's condensed law and twist rate.
    pub thick_stretch: f64,
    pub thick_coupling: f64,
    pub thick_twist: f64,
    pub thick_turns_per_pn_per_10kbp: f64,
}

/// Fit the thin-wall constants (E1, E2, G12) of a tube of mid radius R,
/// helix angle α (radians, > 0 = right-handed) and thickness t, with the
/// given ν12, so that its condensed stretch–twist law is [[S, g], [g, C]]
/// (pN, pN·nm, pN·nm² for DNA). The fit is unique; when it is not physical
/// (a modulus ≤ 0 or a non-positive-definite wall) the status is
/// RODKIT_STATUS_ERR_NOT_POSITIVE_DEFINITE and the message says which
/// constraint failed. The family of fits is obtained by varying t and ν12.
#[no_mangle]
pub unsafe extern "C" fn rodkit_dna_fit_thin_wall(
    stretch: f64,
    twist: f64,
    coupling: f64,
    mid_radius: f64,
    helix_angle: f64,
    thickness: f64,
    nu12: f64,
    out: *mut DnaFit,
) -> i32 {
    guard(|| {
        let out = arg_mut("out", out)?;
        // Every argument finite, named, before the fit's own checks.
        finite_fields(&[
            ("stretch", stretch),
            ("twist", twist),
            ("coupling", coupling),
            ("mid_radius", mid_radius),
            ("helix_angle", helix_angle),
            ("thickness", thickness),
            ("nu12", nu12),
        ])?;
        let targets = DnaTargets::new(stretch, twist, coupling)?;
        let fit = fit_thin_wall(targets, mid_radius, helix_angle, thickness, nu12)?;
        let m = fit.material;
        let mut result = DnaFit {
            spec: ThinTubeSpec {
                mid_radius: fit.mid_radius,
                thickness: fit.thickness,
                intrinsic_twist: fit.intrinsic_twist,
                e1: m.e1,
                e2: m.e2,
                nu12: m.nu12,
                g12: m.g12,
            },
            stretch: fit.achieved.stretch,
            coupling: fit.achieved.coupling,
            twist: fit.achieved.twist,
            twist_rate: fit.twist_rate.rad_per_pn_nm,
            turns_per_pn_per_10kbp: fit.twist_rate.turns_per_pn_per_10kbp,
            overwinds: fit.overwinds as i32,
            thick_status: 0,
            thick_stretch: 0.0,
            thick_coupling: 0.0,
            thick_twist: 0.0,
            thick_turns_per_pn_per_10kbp: 0.0,
        };
        match thick_comparison(&fit, OutOfPlane::default_for(&m)) {
            Ok(t) => {
                result.thick_stretch = t.thick.stretch;
                result.thick_coupling = t.thick.coupling;
                result.thick_twist = t.thick.twist;
                result.thick_turns_per_pn_per_10kbp = t.thick_twist_rate.turns_per_pn_per_10kbp;
            }
            Err(e) => result.thick_status = e.status.code(),
        }
        *out = result;
        Ok(Status::Ok)
    })
}

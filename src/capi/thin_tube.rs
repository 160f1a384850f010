//! C ABI of the thin tube (`physics.md` §1.4): `RodkitThinTubeSpec` and the
//! `rodkit_thin_tube_*` functions, each a closed form of the spec.

use super::args::{arg_mut, arg_ref, qualify_argument, write_matrix};
use super::guard;
use crate::error::{self, Result};
use crate::status::Status;
use crate::tube::{OrthotropicSurface, ThinTube};

/// A thin helically reinforced tube in its stress-free state (physics.md
/// §1.4): geometry, intrinsic twist and in-surface orthotropic constants.
/// Units are the caller's, used consistently (e.g. nm and pN/nm²).
///
/// Initialise with `rodkit_thin_tube_spec_default`, which sets every field to
/// NaN ("unset": a forgotten field is rejected by name), then set them all.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct ThinTubeSpec {
    /// Mid-surface radius R > 0.
    pub mid_radius: f64,
    /// Wall thickness t, 0 < t < 2R.
    pub thickness: f64,
    /// Intrinsic twist τ0 (1/length; any sign = handedness): the reinforcement
    /// follows a helix at angle atan(τ0·R) from the axis.
    pub intrinsic_twist: f64,
    /// Young's modulus along the reinforcement, E1 > 0.
    pub e1: f64,
    /// Young's modulus across the reinforcement (in the surface), E2 > 0.
    pub e2: f64,
    /// Major Poisson ratio ν12, with ν12² < E1/E2 (positive definiteness).
    pub nu12: f64,
    /// In-surface shear modulus G12 > 0.
    pub g12: f64,
}

/// Response of a free thin tube (zero torque, zero pressure) to an axial force
/// F, per unit force.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct FreeTubeResponse {
    /// dε/dF: axial strain per force.
    pub dstrain_dforce: f64,
    /// dψ/dF: twist per length per force.
    pub dtwist_dforce: f64,
    /// dε_θ/dF: hoop strain per force (> 0: inflates when stretched).
    pub dhoop_dforce: f64,
    /// RodkitWinding: +1 overwinds (twists further in the sense of τ0),
    /// −1 unwinds, 0 neither (τ0 = 0 or no coupling).
    pub winding: i32,
}

fn thin_tube(spec: &ThinTubeSpec) -> Result<ThinTube> {
    let material =
        OrthotropicSurface::new(spec.e1, spec.e2, spec.nu12, spec.g12).map_err(|e| qualify_argument(e, "spec."))?;
    ThinTube::new(spec.mid_radius, spec.thickness, spec.intrinsic_twist, material)
        .map_err(|e| qualify_argument(e, "spec."))
}

/// Fill `spec` with its defaults: every field NaN (unset). Set all of them.
#[no_mangle]
pub unsafe extern "C" fn rodkit_thin_tube_spec_default(spec: *mut ThinTubeSpec) -> i32 {
    guard(|| {
        *arg_mut("spec", spec)? = ThinTubeSpec {
            mid_radius: f64::NAN,
            thickness: f64::NAN,
            intrinsic_twist: f64::NAN,
            e1: f64::NAN,
            e2: f64::NAN,
            nu12: f64::NAN,
            g12: f64::NAN,
        };
        Ok(Status::Ok)
    })
}

/// Helix angle α = atan(τ0·R) of the reinforcement at the mid surface, in
/// radians from the tube axis. Validates `spec` like the functions below.
#[no_mangle]
pub unsafe extern "C" fn rodkit_thin_tube_helix_angle(spec: *const ThinTubeSpec, alpha: *mut f64) -> i32 {
    guard(|| {
        let tube = thin_tube(arg_ref("spec", spec)?)?;
        let angle = tube.helix_angle();
        error::finite_result("helix angle", &[angle])?;
        *arg_mut("alpha", alpha)? = angle;
        Ok(Status::Ok)
    })
}

/// Linear coupling stiffness K (physics.md §1.4), symmetric positive definite:
/// (F, T, 2πR²p) = K (ε, ψ, ε_θ), with ε the axial strain, ψ the twist per
/// length, ε_θ the mid-surface hoop strain, F the axial force carried by the
/// wall (open ends), T the torque and p the inner pressure.
///
/// `k` receives the 3×3 matrix column-major with leading dimension `ldk` ≥ 3
/// (entries k[i + j·ldk]; the array needs 2·ldk + 3 doubles).
/// cbindgen:fortran-arrays=[k]
#[no_mangle]
pub unsafe extern "C" fn rodkit_thin_tube_coupling_stiffness(spec: *const ThinTubeSpec, k: *mut f64, ldk: i64) -> i32 {
    guard(|| {
        let stiffness = thin_tube(arg_ref("spec", spec)?)?.coupling_stiffness()?;
        write_matrix("k", k, ldk, "ldk", 3, 3, &stiffness.column_major())?;
        Ok(Status::Ok)
    })
}

/// Condensed stretch–twist law at zero pressure (inflation eliminated):
/// (F, T) = [[S, g], [g, C]] (ε, ψ) — the hemitropic rod coupling of §2.2.
/// `s` receives the 2×2 matrix column-major with leading dimension `lds` ≥ 2.
/// cbindgen:fortran-arrays=[s]
#[no_mangle]
pub unsafe extern "C" fn rodkit_thin_tube_stretch_twist(spec: *const ThinTubeSpec, s: *mut f64, lds: i64) -> i32 {
    guard(|| {
        let law = thin_tube(arg_ref("spec", spec)?)?.coupling_stiffness()?.stretch_twist_checked()?;
        write_matrix("s", s, lds, "lds", 2, 2, law.matrix().as_slice())?;
        Ok(Status::Ok)
    })
}

/// Response of the free tube (T = 0, p = 0) to an axial force, and whether it
/// over- or unwinds (decided by the condensed coupling g, not by K_εψ alone).
#[no_mangle]
pub unsafe extern "C" fn rodkit_thin_tube_free_response(
    spec: *const ThinTubeSpec,
    response: *mut FreeTubeResponse,
) -> i32 {
    guard(|| {
        let r = thin_tube(arg_ref("spec", spec)?)?.coupling_stiffness()?.free_response()?;
        *arg_mut("response", response)? = FreeTubeResponse {
            dstrain_dforce: r.dstrain_dforce,
            dtwist_dforce: r.dtwist_dforce,
            dhoop_dforce: r.dhoop_dforce,
            winding: r.winding as i32,
        };
        Ok(Status::Ok)
    })
}

/// The section as a hemitropic rod (physics.md §2.2), thin-walled beam
/// theory: the symmetric positive-definite 6×6 stiffness K with
///
///   (m1, m2, m3, n1, n2, n3) = K (u1, u2, u3, v1, v2, v3 − 1)
///
/// in the rod's body frame (d1, d2 across the section, d3 along the tube
/// axis; the straight unstressed tube has u = 0, v = (0, 0, 1)):
/// u1, u2 bending curvatures and u3 twist per length (1/length; u3 is the ψ
/// of rodkit_thin_tube_coupling_stiffness); v1, v2 shear strains and v3 the
/// axial stretch (dimensionless; v3 − 1 is the axial strain ε); m1, m2
/// bending moments and m3 the torque (force·length); n1, n2 shear forces and
/// n3 the axial force (force). Entries, rows and columns numbered 1…6 in that
/// order, with R = `mid_radius`, t = `thickness`:
///
///   K11 = K22 = πR³t·a (bending),     K33 = 2πR³t·c (twist C),
///   K44 = K55 = πRt·c (shear),        K66 = 2πRt·a (stretch S),
///   K36 = K63 = 2πR²t·b (twist–stretch g),
///   K14 = K41 = K25 = K52 = −πR²t·b = −g/2 (bend–shear), all others 0,
///
/// where [a, b; b, c] (stress units) is the wall's in-surface stiffness
/// relating (σ_zz, σ_zθ) to (ε_zz, γ_zθ) (γ the engineering shear strain)
/// with the hoop stress zero: the plane-stress stiffness of (e1, e2, nu12,
/// g12) rotated to the helix angle atan(τ0·R) and the hoop strain condensed
/// out. The shear entries use the thin-tube shear coefficient 1/2. The
/// (u3, v3) block [[C, g], [g, S]] is rodkit_thin_tube_stretch_twist's
/// [[S, g], [g, C]] reordered. `k` receives the matrix column-major with
/// leading dimension `ldk` ≥ 6 (entries k[i + j·ldk], 0-based).
/// cbindgen:fortran-arrays=[k]
#[no_mangle]
pub unsafe extern "C" fn rodkit_thin_tube_rod_stiffness(spec: *const ThinTubeSpec, k: *mut f64, ldk: i64) -> i32 {
    guard(|| {
        let law = thin_tube(arg_ref("spec", spec)?)?.rod_stiffness()?;
        write_matrix("k", k, ldk, "ldk", 6, 6, &law.column_major())?;
        Ok(Status::Ok)
    })
}

//! `RodkitWallMaterialSpec`: the wall's constitutive law (physics.md §1.3)
//! as a flat C struct — orthotropic Saint Venant–Kirchhoff, neo-Hookean or
//! fibre-reinforced — its defaults and its translation into the tube's wall
//! law.

use super::args::{arg_mut, enum_arg, flag, qualify_argument, CEnum};
use super::guard;
use crate::error::{self, Error, Result};
use crate::status::Status;
use crate::tube::material::fibre::{FibreAngle, FibreFamily};
use crate::tube::material::{FibreReinforced, NeoHookean, SaintVenantKirchhoff};
use crate::tube::orthotropic::Orthotropic;
use crate::tube::scene::WallLaw as Law;

/// Constitutive law of the wall (physics.md §1.3), for
/// `RodkitWallMaterialSpec.law`.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WallLawKind {
    /// Unset (rejected): set `law` explicitly.
    Unset = 0,
    /// Orthotropic Saint Venant–Kirchhoff with the nine constants e1…g23,
    /// principal axis 1 along the helix atan(τ0 R), axis 3 radial.
    SaintVenantKirchhoff = 1,
    /// Isotropic neo-Hookean: shear_modulus μ and (compressible) lame_lambda.
    NeoHookean = 2,
    /// Neo-Hookean matrix plus fibre families (Holzapfel–Gasser–Ogden type).
    FibreReinforced = 3,
}

/// The wall material. Initialise with `rodkit_wall_material_spec_default`
/// (law unset, every constant NaN, no fibres), then set the fields of the
/// chosen law; fields of other laws are ignored.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct WallMaterialSpec {
    /// RodkitWallLawKind.
    pub law: i32,
    /// 1: incompressible (J = 1, pressure multiplier); 0: compressible.
    pub incompressible: i32,
    /// Intrinsic twist τ0 (1/length): helix angle atan(τ0 R) of the
    /// reinforcement (SVK axis 1, helical fibre families).
    pub intrinsic_twist: f64,
    /// SVK: Young's moduli along the helix, across it in the surface, radial.
    pub e1: f64,
    pub e2: f64,
    pub e3: f64,
    /// SVK: Poisson ratios ν_ij (contraction along j per extension along i).
    pub nu12: f64,
    pub nu13: f64,
    pub nu23: f64,
    /// SVK: shear moduli.
    pub g12: f64,
    pub g13: f64,
    pub g23: f64,
    /// Neo-Hookean (and the fibre-reinforced matrix): shear modulus μ > 0.
    pub shear_modulus: f64,
    /// Neo-Hookean: Lamé λ_L (compressible only), λ_L + 2μ/3 > 0.
    pub lame_lambda: f64,
    /// Fibre-reinforced: number of fibre families, 0, 1 or 2.
    pub fibre_families: i64,
    /// Family 1: W_f = k1/(2k2)(exp(k2(I4−1)²) − 1), tension only.
    pub fibre1_k1: f64,
    pub fibre1_k2: f64,
    /// Family 1 direction: a fixed angle from the axis (rad), or NaN to follow
    /// the helix atan(τ0 R) with handedness `fibre1_hand` (+1 or −1).
    pub fibre1_angle: f64,
    pub fibre1_hand: f64,
    /// Family 2, as family 1.
    pub fibre2_k1: f64,
    pub fibre2_k2: f64,
    pub fibre2_angle: f64,
    pub fibre2_hand: f64,
}

/// Its message lists the laws (Unset is refused where a law is built).
impl CEnum for WallLawKind {
    const ALL: &'static [Self] = &[Self::Unset, Self::SaintVenantKirchhoff, Self::NeoHookean, Self::FibreReinforced];
    const WHAT: &'static str = "a RodkitWallLawKind";
    fn code(self) -> i32 {
        self as i32
    }
    fn invalid(name: &str, v: i32) -> Error {
        Error::new(
            Status::ErrOutOfRange,
            format!(
                "argument `{name}` out of range: must be a RodkitWallLawKind (1 SVK, 2 neo-Hookean, 3 fibre-reinforced; got {v})"
            ),
        )
    }
}

pub(super) fn nan_default_material() -> WallMaterialSpec {
    let n = f64::NAN;
    WallMaterialSpec {
        law: WallLawKind::Unset as i32,
        incompressible: 0,
        intrinsic_twist: 0.0,
        e1: n,
        e2: n,
        e3: n,
        nu12: n,
        nu13: n,
        nu23: n,
        g12: n,
        g13: n,
        g23: n,
        shear_modulus: n,
        lame_lambda: n,
        fibre_families: 0,
        fibre1_k1: n,
        fibre1_k2: n,
        fibre1_angle: n,
        fibre1_hand: 1.0,
        fibre2_k1: n,
        fibre2_k2: n,
        fibre2_angle: n,
        fibre2_hand: -1.0,
    }
}

/// The wall law of `m` (field names as `material.…`).
pub(super) fn law(m: &WallMaterialSpec) -> Result<Law> {
    let inc = flag("material.incompressible", m.incompressible)?;
    let nh = || NeoHookean {
        shear_modulus: m.shear_modulus,
        lame_lambda: if inc { 0.0 } else { m.lame_lambda },
        incompressible: inc,
    };
    let l = match enum_arg::<WallLawKind>("material.law", m.law)? {
        WallLawKind::Unset => return Err(WallLawKind::invalid("material.law", m.law)),
        WallLawKind::SaintVenantKirchhoff => {
            let o = Orthotropic::new(m.e1, m.e2, m.e3, m.nu12, m.nu13, m.nu23, m.g12, m.g13, m.g23)
                .map_err(|e| qualify_argument(e, "material."))?;
            Law::SaintVenantKirchhoff(SaintVenantKirchhoff::new(o, m.intrinsic_twist, inc))
        }
        WallLawKind::NeoHookean => Law::NeoHookean(nh()),
        WallLawKind::FibreReinforced => {
            if !(0..=2).contains(&m.fibre_families) {
                return Err(Error::new(
                    Status::ErrOutOfRange,
                    format!(
                        "argument `material.fibre_families` out of range: must be 0, 1 or 2 (got {})",
                        m.fibre_families
                    ),
                ));
            }
            // A NaN hand is an unset number, not a hand out of range (-3,
            // named), even where a fixed angle makes the hand unused.
            let hands = [("material.fibre1_hand", m.fibre1_hand), ("material.fibre2_hand", m.fibre2_hand)];
            for &(name, hand) in &hands[..m.fibre_families as usize] {
                error::finite(name, hand)?;
            }
            let fam = |k1: f64, k2: f64, angle: f64, hand: f64| FibreFamily {
                angle: if angle.is_nan() { FibreAngle::Helix { hand } } else { FibreAngle::Fixed(angle) },
                k1,
                k2,
            };
            let all = [
                fam(m.fibre1_k1, m.fibre1_k2, m.fibre1_angle, m.fibre1_hand),
                fam(m.fibre2_k1, m.fibre2_k2, m.fibre2_angle, m.fibre2_hand),
            ];
            Law::FibreReinforced(FibreReinforced {
                matrix: nh(),
                families: all[..m.fibre_families as usize].to_vec(),
                intrinsic_twist: m.intrinsic_twist,
            })
        }
    };
    l.validate().map_err(|e| qualify_argument(e, "material."))?;
    Ok(l)
}

/// Fill `spec` with defaults: law unset, compressible, τ0 = 0, every
/// constant NaN (unset), no fibres, fibre hands +1 and −1.
#[no_mangle]
pub unsafe extern "C" fn rodkit_wall_material_spec_default(spec: *mut WallMaterialSpec) -> i32 {
    guard(|| {
        *arg_mut("spec", spec)? = nan_default_material();
        Ok(Status::Ok)
    })
}

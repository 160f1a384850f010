//! `RodkitRodSpec`: a rod's law, length, supports, loads and
//! discretisation as a flat C struct, its defaults, and its translation
//! into the rod model (physics.md §2) with every field checked by name.

use super::args::{arg_mut, c_enum, enum_arg, finite_fields, flag};
use super::guard;
use crate::error::{self, Error, Result};
use crate::rod::model::{Rod as Model, Supports};
use crate::rod::scheme::Scheme;
use crate::rod::{Frame, Load, Loads, Moduli, RodLaw};
use crate::status::Status;
use nalgebra::{Matrix6, Vector3};

/// Supports of a rod (`RodkitRodSpec.supports`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RodSupports {
    /// s = 0 clamped at the origin along e3, s = L free (tip loads apply).
    Cantilever = 1,
    /// Both ends clamped; s = L at end_x…z + Λ·end_dx…dz with orientation
    /// end_q0…q3.
    Clamped = 2,
    /// Ball joints; an axial dead tip force (0, 0, P) only.
    Pinned = 3,
    /// Controlled end rotation (Greenhill): s = L on the axis, free to slide
    /// under the axial dead force `end_tension`, turned about e3 by φ with
    /// Λ = sin(φ/2) (records report φ in `end_rotation`). No tip loads.
    Twisted = 4,
    /// Controlled end moment (a torque clamp): as Twisted, but φ is free and
    /// Λ is the spatial end moment about e3 (records report φ in
    /// `end_rotation`, continuous along the branch). No tip loads.
    Torqued = 5,
}

/// How a load follows the rod (`*_frame` fields).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadFrame {
    /// No such load.
    None = 0,
    /// Fixed in space (spatial components).
    Dead = 1,
    /// Turns with the section (body components).
    Follower = 2,
}

/// Discretisation (`RodkitRodSpec.scheme`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RodScheme {
    /// Implicit midpoint rule, order 2.
    Midpoint = 1,
    /// Gauss–Legendre collocation with `stages` (2…4) stages, order 2·stages.
    Gauss = 2,
}

/// A rod: law, length, supports, loads (each multiplied by the load
/// parameter Λ), discretisation. Initialise with `rodkit_rod_spec_default`.
///
/// Symbols (physics.md §2.1): s is the arc length of the stress-free rod,
/// r(s) the centreline, d1, d2, d3 the section's orthonormal directors (d1,
/// d2 its principal axes, d3 its normal, e3 at s = 0); u = (u1, u2, u3) are
/// the body components of the directors' rotation rate d_k' = u × d_k
/// (bending about d1, d2 and twist), v = (v1, v2, v3) those of r' (shear
/// along d1, d2 and stretch); m and n are the body components of the
/// internal moment and force. The law is linear,
/// (m, n) = K (u − û, v − v̂) with û, v̂ the intrinsic strains below, K the
/// symmetric positive-definite 6×6 stiffness in the order
/// (u1, u2, u3, v1, v2, v3) ↔ (m1, m2, m3, n1, n2, n3): diagonal bending1,
/// bending2, twist, shear1, shear2, stretch; couplings twist_stretch and
/// bend_shear.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RodSpec {
    /// Length L > 0.
    pub length: f64,
    /// 1: Kirchhoff rod (inextensible, unshearable: only bending1, bending2,
    /// twist are used); 0: special Cosserat rod.
    pub kirchhoff: i32,
    pub bending1: f64,
    pub bending2: f64,
    pub twist: f64,
    pub shear1: f64,
    pub shear2: f64,
    pub stretch: f64,
    /// Hemitropic couplings (physics.md §2.2): twist–stretch g (u3·v3) and
    /// bend–shear c2 (u1·v1 and u2·v2). Default 0.
    pub twist_stretch: f64,
    pub bend_shear: f64,
    /// Intrinsic strains û (default 0) and v̂ (default (0, 0, 1)).
    pub intrinsic_u1: f64,
    pub intrinsic_u2: f64,
    pub intrinsic_u3: f64,
    pub intrinsic_v1: f64,
    pub intrinsic_v2: f64,
    pub intrinsic_v3: f64,
    /// RodkitRodSupports (default cantilever).
    pub supports: i32,
    /// Clamped: position and orientation (unit quaternion, scalar first) of
    /// the end s = L.
    pub end_x: f64,
    pub end_y: f64,
    pub end_z: f64,
    pub end_q0: f64,
    pub end_q1: f64,
    pub end_q2: f64,
    pub end_q3: f64,
    /// Clamped: the end moves by Λ·(end_dx, end_dy, end_dz) (default 0:
    /// fixed).
    pub end_dx: f64,
    pub end_dy: f64,
    pub end_dz: f64,
    /// Twisted and Torqued: the axial dead force at s = L (default 0).
    pub end_tension: f64,
    /// Loads: RodkitLoadFrame and vector (per length for distributed loads).
    pub tip_force_frame: i32,
    pub tip_force_x: f64,
    pub tip_force_y: f64,
    pub tip_force_z: f64,
    pub tip_moment_frame: i32,
    pub tip_moment_x: f64,
    pub tip_moment_y: f64,
    pub tip_moment_z: f64,
    pub distributed_force_frame: i32,
    pub distributed_force_x: f64,
    pub distributed_force_y: f64,
    pub distributed_force_z: f64,
    pub distributed_couple_frame: i32,
    pub distributed_couple_x: f64,
    pub distributed_couple_y: f64,
    pub distributed_couple_z: f64,
    /// RodkitRodScheme (default Gauss), stages (default 4), elements N
    /// (default 8).
    pub scheme: i32,
    pub stages: i64,
    pub elements: i64,
    /// Rod diameter for self-contact detection (0, the default: none).
    /// Branches report where non-neighbouring points come closer than it
    /// (RodkitBranchInfo.contact_*): the rod has no contact model.
    pub diameter: f64,
}

c_enum!(
    RodSupports,
    "a RodkitRodSupports 1…5",
    [RodSupports::Cantilever, RodSupports::Clamped, RodSupports::Pinned, RodSupports::Twisted, RodSupports::Torqued]
);
c_enum!(LoadFrame, "a RodkitLoadFrame 0…2", [LoadFrame::None, LoadFrame::Dead, LoadFrame::Follower]);
c_enum!(RodScheme, "a RodkitRodScheme 1…2", [RodScheme::Midpoint, RodScheme::Gauss]);

/// A load of the spec: its frame `{name}_frame` and vector `{name}_x…z`.
fn load(name: &str, f: i32, x: f64, y: f64, z: f64) -> Result<Option<Load>> {
    let frame = match enum_arg::<LoadFrame>(&format!("{name}_frame"), f)? {
        LoadFrame::None => return Ok(None),
        LoadFrame::Dead => Frame::Dead,
        LoadFrame::Follower => Frame::Follower,
    };
    for (c, v) in [("x", x), ("y", y), ("z", z)] {
        error::finite(&format!("{name}_{c}"), v)?;
    }
    Ok(Some(Load { frame, vector: [x, y, z] }))
}

/// The law of the spec: `general` (rodkit_rod_new_general) or the spec's
/// moduli, Kirchhoff or not, with the intrinsic strains.
fn law_from(s: &RodSpec, general: Option<Matrix6<f64>>) -> Result<RodLaw> {
    let intrinsic_u = Vector3::new(s.intrinsic_u1, s.intrinsic_u2, s.intrinsic_u3);
    let intrinsic_v = Vector3::new(s.intrinsic_v1, s.intrinsic_v2, s.intrinsic_v3);
    for (n, v) in [
        ("intrinsic_u1", s.intrinsic_u1),
        ("intrinsic_u2", s.intrinsic_u2),
        ("intrinsic_u3", s.intrinsic_u3),
        ("intrinsic_v1", s.intrinsic_v1),
        ("intrinsic_v2", s.intrinsic_v2),
        ("intrinsic_v3", s.intrinsic_v3),
    ] {
        error::finite(n, v)?;
    }
    let kirchhoff = flag("kirchhoff", s.kirchhoff)?;
    Ok(if let Some(k) = general {
        let mut law = RodLaw::general(k, intrinsic_u, intrinsic_v)?;
        law.kirchhoff = kirchhoff;
        law
    } else if kirchhoff {
        let mut law = RodLaw::kirchhoff(s.bending1, s.bending2, s.twist)?;
        law.intrinsic_u = intrinsic_u;
        law.intrinsic_v = intrinsic_v;
        law
    } else {
        let moduli = Moduli {
            bending1: s.bending1,
            bending2: s.bending2,
            twist: s.twist,
            shear1: s.shear1,
            shear2: s.shear2,
            stretch: s.stretch,
            twist_stretch: s.twist_stretch,
            bend_shear: s.bend_shear,
        };
        RodLaw::from_moduli(&moduli, intrinsic_u, intrinsic_v)?
    })
}

fn supports_from(s: &RodSpec) -> Result<Supports> {
    Ok(match enum_arg::<RodSupports>("supports", s.supports)? {
        RodSupports::Cantilever => Supports::Cantilever,
        RodSupports::Clamped => Supports::Clamped {
            end_position: [s.end_x, s.end_y, s.end_z],
            end_rotation: [s.end_q0, s.end_q1, s.end_q2, s.end_q3],
            end_displacement: [s.end_dx, s.end_dy, s.end_dz],
        },
        RodSupports::Pinned => Supports::Pinned,
        RodSupports::Twisted => Supports::Twisted { tension: s.end_tension },
        RodSupports::Torqued => Supports::Torqued { tension: s.end_tension },
    })
}

fn loads_from(s: &RodSpec) -> Result<Loads> {
    Ok(Loads {
        tip_force: load("tip_force", s.tip_force_frame, s.tip_force_x, s.tip_force_y, s.tip_force_z)?,
        tip_moment: load("tip_moment", s.tip_moment_frame, s.tip_moment_x, s.tip_moment_y, s.tip_moment_z)?,
        distributed_force: load(
            "distributed_force",
            s.distributed_force_frame,
            s.distributed_force_x,
            s.distributed_force_y,
            s.distributed_force_z,
        )?,
        distributed_couple: load(
            "distributed_couple",
            s.distributed_couple_frame,
            s.distributed_couple_x,
            s.distributed_couple_y,
            s.distributed_couple_z,
        )?,
    })
}

/// Every double of the spec the rod uses must be finite: a NaN or an
/// infinity is ERR_NOT_FINITE naming its C field, before any check that
/// would report it under another name or status. Fields the configuration
/// ignores (the moduli a Kirchhoff or general law does not read, the
/// clamped end of another support, the vector of an absent load) are not
/// read.
fn check_finite(s: &RodSpec, general: bool) -> Result<()> {
    finite_fields(&[("length", s.length), ("diameter", s.diameter)])?;
    if !general {
        finite_fields(&[("bending1", s.bending1), ("bending2", s.bending2), ("twist", s.twist)])?;
        if s.kirchhoff != 1 {
            finite_fields(&[
                ("shear1", s.shear1),
                ("shear2", s.shear2),
                ("stretch", s.stretch),
                ("twist_stretch", s.twist_stretch),
                ("bend_shear", s.bend_shear),
            ])?;
        }
    }
    match s.supports {
        x if x == RodSupports::Clamped as i32 => finite_fields(&[
            ("end_x", s.end_x),
            ("end_y", s.end_y),
            ("end_z", s.end_z),
            ("end_q0", s.end_q0),
            ("end_q1", s.end_q1),
            ("end_q2", s.end_q2),
            ("end_q3", s.end_q3),
            ("end_dx", s.end_dx),
            ("end_dy", s.end_dy),
            ("end_dz", s.end_dz),
        ]),
        x if x == RodSupports::Twisted as i32 || x == RodSupports::Torqued as i32 => {
            finite_fields(&[("end_tension", s.end_tension)])
        }
        _ => Ok(()),
    }
}

/// The rod's scales (positions L·|v̂|, moments K_b/L, forces K_b/L²: the
/// continuation measures its steps and tolerances in them) must be finite
/// and normal, else the length is out of range (a length of DBL_MAX gave
/// a straight state with infinite entries and status OK).
fn check_scales(law: &RodLaw, length: f64) -> Result<()> {
    let kb = law.bending();
    let scales = [length * law.intrinsic_v.norm().max(1.0), kb / length, kb / (length * length)];
    if scales.iter().all(|v| v.is_finite() && v.abs() >= f64::MIN_POSITIVE) {
        return Ok(());
    }
    Err(Error::new(
        Status::ErrOutOfRange,
        format!(
            "argument `length` out of range (got {length:e}): the rod's scales L·|v̂| = {:e}, K_b/L = {:e}, K_b/L² = {:e} \
             must be finite and normal doubles",
            scales[0], scales[1], scales[2]
        ),
    ))
}

/// The rod model of a spec (field names unqualified: the caller adds
/// `spec.`), with `general` in place of the spec's moduli when given.
pub(super) fn model_from(s: &RodSpec, general: Option<Matrix6<f64>>) -> Result<Model> {
    check_finite(s, general.is_some())?;
    let law = law_from(s, general)?;
    error::positive("length", s.length)?;
    check_scales(&law, s.length)?;
    let supports = supports_from(s)?;
    let loads = loads_from(s)?;
    let scheme = match enum_arg::<RodScheme>("scheme", s.scheme)? {
        RodScheme::Midpoint => Scheme::Midpoint,
        RodScheme::Gauss => {
            error::count_in_range("stages", s.stages, 2, 4)?;
            Scheme::Gauss(s.stages as usize)
        }
    };
    error::count_in_range("elements", s.elements, 1, 1 << 18)?;
    let model = Model::new(law, s.length, loads, supports, scheme, s.elements as usize)?;
    if s.diameter == 0.0 {
        Ok(model)
    } else {
        model.with_diameter(s.diameter)
    }
}

/// Fill `spec` with defaults: every physical field NaN (unset), couplings
/// and intrinsic curvature 0, v̂ = (0, 0, 1), cantilever, no loads,
/// Gauss–Legendre with 4 stages on 8 elements.
#[no_mangle]
pub unsafe extern "C" fn rodkit_rod_spec_default(spec: *mut RodSpec) -> i32 {
    guard(|| {
        let n = f64::NAN;
        *arg_mut("spec", spec)? = RodSpec {
            length: n,
            kirchhoff: 0,
            bending1: n,
            bending2: n,
            twist: n,
            shear1: n,
            shear2: n,
            stretch: n,
            twist_stretch: 0.0,
            bend_shear: 0.0,
            intrinsic_u1: 0.0,
            intrinsic_u2: 0.0,
            intrinsic_u3: 0.0,
            intrinsic_v1: 0.0,
            intrinsic_v2: 0.0,
            intrinsic_v3: 1.0,
            supports: RodSupports::Cantilever as i32,
            end_x: n,
            end_y: n,
            end_z: n,
            end_q0: 1.0,
            end_q1: 0.0,
            end_q2: 0.0,
            end_q3: 0.0,
            end_dx: 0.0,
            end_dy: 0.0,
            end_dz: 0.0,
            end_tension: 0.0,
            tip_force_frame: 0,
            tip_force_x: 0.0,
            tip_force_y: 0.0,
            tip_force_z: 0.0,
            tip_moment_frame: 0,
            tip_moment_x: 0.0,
            tip_moment_y: 0.0,
            tip_moment_z: 0.0,
            distributed_force_frame: 0,
            distributed_force_x: 0.0,
            distributed_force_y: 0.0,
            distributed_force_z: 0.0,
            distributed_couple_frame: 0,
            distributed_couple_x: 0.0,
            distributed_couple_y: 0.0,
            distributed_couple_z: 0.0,
            scheme: RodScheme::Gauss as i32,
            stages: 4,
            elements: 8,
            diameter: 0.0,
        };
        Ok(Status::Ok)
    })
}

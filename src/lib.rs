//! rodkit: mechanics of elastic tubes and rods with a stable C ABI.
//!
//! The physics follows `../shared/spec/physics.md`; the C conventions
//! `../shared/spec/c-api.md`. All code that opts out of the lint below lives in [`capi`], which is
//! the only place allowed to opt out of the lint below.
#![deny(unsafe_code)]

pub mod chebyshev;
pub mod continuation;
pub mod electrostatics;
pub mod error;
pub mod newton;
pub mod rod;
pub mod sparse;
pub mod status;
pub mod taylor;
pub mod tube;
pub mod version;

pub mod capi;

pub use error::{Error, Result};
pub use status::Status;

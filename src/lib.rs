//! rodkit: mechanics of elastic tubes and rods with a stable C ABI.
//!
//! The physics follows `doc/physics.md` (the reference the header cites as
//! physics.md §N.M); the C conventions `../shared/spec/c-api.md`. The layout (one idea per module, models →
//! engines → linear algebra, the C boundary on top) is mapped in the
//! source map of doc/development.md. Unsafe code is denied everywhere except in
//! [`capi`], the C boundary.
#![deny(unsafe_code)]

// Infrastructure.
pub mod error;
mod kept;
pub mod status;
pub mod version;

// Numerical building blocks, independent of any model.
pub mod chebyshev;
pub mod linalg;
pub mod quadrature;
pub mod roots;
pub mod taylor;

// Engines: nonlinear solves and continuation.
pub mod continuation;
pub mod nonlinear;

// Geometry and physics.
pub mod charged;
pub mod electrostatics;
pub mod geometry;
pub mod rod;
pub mod tube;
pub mod tweezers;

// Files for other tools (VTK shapes, CSV tables), written on request.
pub mod io;

pub mod capi;

pub use error::{Error, Result};
pub use status::Status;

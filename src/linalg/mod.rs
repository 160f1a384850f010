//! Linear algebra under every solver of rodkit, independent of the models
//! and engines above it:
//!
//! * [`sparse`]: square sparsity patterns and their LU (faer), the ordering
//!   and symbolic analysis done once per pattern;
//! * [`bordered`]: a sparse matrix bordered by one dense row and column (a
//!   continuation's tangent, a phase condition), its LU — its own, or block
//!   elimination on the inner matrix's supernodal LU refined against it
//!   (`bordering`) —, determinant sign, negative pivots and smallest
//!   singular values;
//! * [`band`]: the LU of a matrix's band plus its boundary corners — the
//!   lagged preconditioner of a rod's Newton–Krylov solves;
//! * [`gmres`]: restarted, right-preconditioned GMRES(m) on any operator;
//! * [`dense`]: the few dense-vector kernels the above share.

pub mod band;
pub mod bordered;
mod bordering;
pub mod condensed;
pub mod dense;
pub mod gmres;
pub mod ordering;
pub mod sparse;
mod supernodal;

pub use sparse::{LuKind, Pattern, SparseLu};

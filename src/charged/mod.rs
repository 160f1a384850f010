//! The charged rod (physics.md §3): a Kirchhoff rod whose centreline
//! carries a screened line charge — continuous ([`rod`], the near zone
//! regularised into a local bending stiffening, the far zone as pair forces)
//! or the discrete base-pair charges ([`sites`], the thesis's
//! comparison) — as a continuation problem with an exact sparse Jacobian;
//! its branches with pair lists rebuilt as the shape moves ([`branch`]);
//! single equilibria re-solved under another model or solver
//! ([`equilibrium`]); the DNA supercoiling scene ([`dna`]), its equilibrium
//! curve ([`coexistence`]) and a curve's summary for a force × salt map
//! ([`summary`]). The field of a centreline itself is
//! [`crate::electrostatics`].

mod assembly;
pub mod branch;
pub mod coexistence;
pub mod dna;
pub mod end_loop;
pub mod equilibrium;
mod gap;
pub mod rod;
mod sites;
pub mod summary;

//! Helically reinforced tubes: coupled extension–torsion–inflation
//! (`doc/physics.md` §1).
//!
//! So far: the linear theory about the stress-free state in the thin-tube
//! (membrane) limit, §1.4. The coupling stiffness and what follows from it
//! (condensed stretch–twist law, free-tube response) live in [`coupling`] so
//! the thick-wall model can report through the same type.

pub mod coupling;
pub mod dna;
pub mod finite;
pub mod material;
pub mod membrane;
pub mod orthotropic;
pub mod rod_law;
pub mod scene;
pub mod thick;
pub mod thin;

pub use coupling::{CouplingStiffness, FreeTubeResponse, StretchTwist, Winding};
pub use orthotropic::{Orthotropic, OrthotropicSurface};
pub use rod_law::RodStiffness;
pub use thick::{Compressibility, Estimated, ThickTube};
pub use thin::ThinTube;

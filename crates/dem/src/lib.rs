//! hopperflow's DEM engine: Hertz–Mindlin spheres with rolling friction, walls of any shape
//! (planes, polygons, cylinders and cones, triangle meshes), still or moving,
//! a Verlet neighbour list and velocity-Verlet integration.
//!
//! The engine knows nothing of hoppers, files or fits. Its contract is in docs/physics.md §1–6:
//! contact laws (`contact`), materials and mixing (`material`), walls (`wall`), storage
//! (`particles`), neighbour search (`neighbour`), velocity Verlet (`integrator`), the
//! simulation that owns the state (`simulation`) and the view of it between steps (`watch`).

// Input checks are written `!(x > 0.0)` on purpose: unlike `x <= 0.0`, they also refuse NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::nonminimal_bool)]
#![warn(missing_docs)]

mod body_view;
mod capacity;
pub mod clump;
pub mod contact;
mod contacts;
mod error;
mod forces;
pub(crate) mod history;
mod integrator;
pub mod material;
pub(crate) mod neighbour;
pub mod particles;
mod ranges;
mod reach;
mod region_force;
mod simulation;
pub(crate) mod team;
pub mod timescale;
mod timing;
pub mod wall;
mod watch;

pub use body_view::Bodies;
pub use contact::liquid_bridge::LARGEST_VOLUME_RATIO as LARGEST_BRIDGE_VOLUME_RATIO;
pub use contact::{Cohesion, ContactLaws, RollingLaw, TangentialLaw};
pub use contacts::{Contacts, PairContact, WallContact, SLIP_MARGIN};
pub use error::DemError;
pub use forces::loads::{ElementLoad, SurfaceLoads, WallLoad};
pub use forces::ContactCount;
pub use glam::{DQuat, DVec3};
pub use material::{
    Interaction, Material, MaterialEntry, MaterialTable, MaterialTableError, PairEntry,
    WallMaterial,
};
pub use particles::{
    MaterialId, ParticleInit, ParticleSet, ParticleTag, FLAG_CLUMP_MEMBER, FLAG_FROZEN,
    FLAG_ROTATION_LOCKED, NO_CLUMP,
};
pub use region_force::{ForceRegion, RegionForce};
pub use simulation::{
    Energy, MaterialIds, RemovedParticle, Simulation, SimulationConfig, SimulationState,
};
pub use team::Team;
pub use timing::PhaseTimes;
pub use wall::{Wall, WallId, WallMotion, WallShape};
pub use watch::Watched;

/// The machinery behind the API, reachable only for the crate's own benchmarks
/// (`benches/`), which time the contact kernel and the cell grid on their own. Not part of
/// the API: it changes with the engine's layout.
#[doc(hidden)]
pub mod internals {
    pub use crate::forces::kernel::{Batch, BATCH};
    pub use crate::neighbour::CellGrid;
}

//! The hopper case: walls, filling, settling and discharge (docs/physics.md §5, §7).

pub mod builder;
pub mod fill;
pub mod setup;

pub use builder::{build_walls, outline, HopperWalls};
pub use setup::{contact_laws, hopper_simulation, lattice_bed, sample_radius};

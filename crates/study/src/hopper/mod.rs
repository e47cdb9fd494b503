//! The containers of a case (the slab hopper, the cylindrical silo): walls, filling,
//! settling and discharge (docs/physics.md §5, §7).

pub mod builder;
pub mod container;
pub mod draw;
pub mod fill;
pub mod packing;
mod packing_vtu;
pub mod setup;
pub mod silo_fill;
pub mod silo_walls;

pub use builder::{build_walls, outline, HopperWalls};
pub use container::{adopt_walls, build_container_walls, ContainerWalls, WALL_NAMES};
pub use draw::{Draw, ParticleDraws};
pub use packing::{
    read_packing, PackedParticle, Packing, PackingError, PackingPlace, PackingProblem,
    PACKING_COLUMNS, PACKING_OVERLAP_FRACTION, RADIUS_TOLERANCE,
};
pub use setup::{
    case_simulation, case_simulation_by_component, contact_laws, hopper_simulation, lattice_bed,
    sample_radius,
};
pub use silo_walls::{build_silo_walls, silo_outline, silo_wall_polygons, SiloWalls};

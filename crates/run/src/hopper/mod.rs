//! The containers of a case (the slab hopper, the cylindrical and rectangular silos, STL
//! walls): walls, filling, settling and discharge (docs/physics.md §5, §7).

pub mod box_walls;
pub mod builder;
pub mod container;
pub mod cut;
pub mod draw;
pub mod fill;
pub mod mesh_walls;
pub mod packing;
mod packing_vtu;
pub mod setup;
pub mod silo_fill;
pub mod silo_walls;

pub use box_walls::{box_outline, box_wall_polygons, build_box_walls, BoxWalls};
pub use builder::{build_walls, outline, HopperWalls};
pub use container::{
    adopt_walls, build_container_walls, wall_names, ContainerWalls, MESH_WALL_INDEX, WALL_NAMES,
};
pub use cut::vertical_cut;
pub use draw::{Draw, ParticleDraws};
pub use mesh_walls::{build_mesh_walls, gate_outline, mesh_outline, mesh_wall_polygons, MeshWalls};
pub use packing::{
    packing_count, read_packing, PackedParticle, Packing, PackingError, PackingPlace,
    PackingProblem, PACKING_COLUMNS, PACKING_OVERLAP_FRACTION, RADIUS_TOLERANCE,
    REQUIRED_PACKING_COLUMNS,
};
pub use setup::{
    case_simulation, case_simulation_by_component, contact_laws, hopper_simulation, lattice_bed,
    sample_radius,
};
pub use silo_walls::{build_silo_walls, silo_outline, silo_wall_polygons, SiloWalls};

//! The walls of each container kind (the slab hopper, the cylinder, the cuboid, STL walls, the
//! heap test's lifted cylinder and plate),
//! built into an engine simulation, named as `wall_forces.csv` names them and drawn in the
//! vertical plane (docs/physics.md §5).

mod cuboid;
mod cut;
mod cylinder;
mod heap;
mod mesh;
mod slab;
mod walls;

pub use cuboid::{build_cuboid_walls, cuboid_outline, cuboid_wall_polygons, CuboidWalls};
pub use cut::vertical_cut;
pub use cylinder::{build_cylinder_walls, cylinder_outline, cylinder_wall_polygons, CylinderWalls};
pub use heap::{build_heap_walls, heap_outline, heap_wall_polygons, HeapWalls};
pub use mesh::{build_mesh_walls, gate_outline, mesh_outline, mesh_wall_polygons, MeshWalls};
pub use slab::{build_slab_walls, slab_outline, SlabWalls};
pub use walls::{
    adopt_walls, build_container_walls, wall_names, ContainerWalls, MESH_WALL_INDEX, WALL_NAMES,
};

//! The walls of any container kind, as the run protocol sees them: a gate to open (for the
//! heap test, the cylinder to lift) and the walls whose loads it records.

use dem::{DemError, Interaction, Simulation, WallId, WallMaterial};
use serde::{Deserialize, Serialize};

use super::cuboid::{build_cuboid_walls, CuboidWalls};
use super::cylinder::{build_cylinder_walls, CylinderWalls};
use super::heap::{build_heap_walls, HeapWalls};
use super::mesh::{build_mesh_walls, MeshWalls};
use super::slab::{build_slab_walls, SlabWalls};
use case::Geometry;

/// The names of walls in `wall_forces.csv`, indexed by [`ContainerWalls::named`]; a mesh
/// container's walls follow from [`MESH_WALL_INDEX`] on, named by the case ([`wall_names`]).
pub const WALL_NAMES: [&str; 12] = [
    "left",
    "right",
    "plate_left",
    "plate_right",
    "gate",
    "cylinder",
    "hopper",
    "bottom",
    "front",
    "back",
    "plate_front",
    "plate_back",
];

/// The index of a mesh container's first STL wall among the names of `wall_forces.csv`.
pub const MESH_WALL_INDEX: u8 = WALL_NAMES.len() as u8;

/// Handles of a container's walls in the simulation.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContainerWalls {
    /// The slab hopper's walls.
    Slab(SlabWalls),
    /// A cylindrical silo's walls.
    Silo(CylinderWalls),
    /// A rectangular silo's walls.
    Box(CuboidWalls),
    /// The STL walls of a mesh container.
    Mesh(MeshWalls),
    /// The heap test's cylinder and plate.
    Heap(HeapWalls),
}

impl ContainerWalls {
    /// The wall whose removal starts the test: the removable plate under the outlet, or the
    /// heap test's cylinder (which its protocol lifts first; removing it at once is a lift
    /// infinitely fast).
    pub fn gate(&self) -> WallId {
        match self {
            Self::Slab(w) => w.gate,
            Self::Silo(w) => w.gate,
            Self::Box(w) => w.gate,
            Self::Mesh(w) => w.gate,
            Self::Heap(w) => w.cylinder,
        }
    }

    /// The name of wall `id` among these walls: a [`WALL_NAMES`] entry, `front` and `back`
    /// for a slab's faces, or an STL wall's own name; `None` for a handle that is none of them.
    pub fn name_of(&self, id: WallId) -> Option<String> {
        match self {
            Self::Slab(w) => {
                if let Some(k) = w.faces.iter().position(|f| *f == id) {
                    return Some(["front", "back"][k].to_string());
                }
            }
            Self::Mesh(w) => {
                if let Some(k) = w.walls.iter().position(|f| *f == id) {
                    return Some(w.names[k].clone());
                }
            }
            Self::Silo(_) | Self::Box(_) | Self::Heap(_) => {}
        }
        self.named()
            .into_iter()
            .find(|(_, wall)| *wall == Some(id))
            .and_then(|(k, _)| WALL_NAMES.get(k as usize))
            .map(|name| name.to_string())
    }

    /// Every wall of the container, the gate included.
    pub fn all(&self) -> Vec<WallId> {
        match self {
            Self::Slab(w) => {
                let mut walls = vec![w.sides[0], w.sides[1], w.faces[0], w.faces[1]];
                walls.extend(w.plates.iter().flatten());
                walls.push(w.gate);
                walls
            }
            Self::Silo(w) => vec![w.cylinder, w.bottom, w.gate],
            Self::Heap(w) => vec![w.cylinder, w.plate],
            Self::Box(w) => {
                let mut walls = w.sides.to_vec();
                walls.extend(w.plates.iter().flatten());
                walls.extend(w.bottom);
                walls.push(w.gate);
                walls
            }
            Self::Mesh(w) => {
                let mut walls = w.walls.clone();
                walls.push(w.gate);
                walls
            }
        }
    }

    /// The walls that may record loads, each with its index into [`wall_names`]; absent
    /// walls (a plate where the outlet touches the side wall) are `None`.
    pub fn named(&self) -> Vec<(u8, Option<WallId>)> {
        match self {
            Self::Slab(w) => vec![
                (0, Some(w.sides[0])),
                (1, Some(w.sides[1])),
                (2, w.plates[0]),
                (3, w.plates[1]),
                (4, Some(w.gate)),
            ],
            Self::Silo(w) => vec![
                (5, Some(w.cylinder)),
                (if w.conical { 6 } else { 7 }, Some(w.bottom)),
                (4, Some(w.gate)),
            ],
            Self::Box(w) => vec![
                (0, Some(w.sides[0])),
                (1, Some(w.sides[1])),
                (8, Some(w.sides[2])),
                (9, Some(w.sides[3])),
                (2, w.plates[0]),
                (3, w.plates[1]),
                (10, w.plates[2]),
                (11, w.plates[3]),
                (7, w.bottom),
                (4, Some(w.gate)),
            ],
            // The plate under the heap is its bottom.
            Self::Heap(w) => vec![(5, Some(w.cylinder)), (7, Some(w.plate))],
            Self::Mesh(w) => w
                .walls
                .iter()
                .enumerate()
                .map(|(k, id)| (MESH_WALL_INDEX + k as u8, Some(*id)))
                .chain(std::iter::once((4, Some(w.gate))))
                .collect(),
        }
    }
}

/// The names of the walls of `wall_forces.csv` for a case of `geometry`, indexed as
/// [`ContainerWalls::named`] indexes them: [`WALL_NAMES`], then a mesh container's wall names.
pub fn wall_names(geometry: &Geometry) -> Vec<String> {
    let mut names: Vec<String> = WALL_NAMES.iter().map(|n| n.to_string()).collect();
    if let Geometry::Mesh(g) = geometry {
        names.extend(g.walls.iter().map(|w| w.name.clone()));
    }
    names
}

/// Adds the walls of `geometry`, gate closed, to `sim`.
pub fn build_container_walls(
    sim: &mut Simulation,
    geometry: &Geometry,
    material: WallMaterial,
    interaction: Interaction,
) -> Result<ContainerWalls, DemError> {
    Ok(match geometry {
        Geometry::Slab(g) => ContainerWalls::Slab(build_slab_walls(sim, g, material, interaction)?),
        Geometry::Cylinder(g) => {
            ContainerWalls::Silo(build_cylinder_walls(sim, g, material, interaction)?)
        }
        Geometry::Cuboid(g) => {
            ContainerWalls::Box(build_cuboid_walls(sim, g, material, interaction)?)
        }
        Geometry::Mesh(g) => ContainerWalls::Mesh(build_mesh_walls(sim, g, material, interaction)?),
        Geometry::Heap(g) => ContainerWalls::Heap(build_heap_walls(sim, g, material, interaction)?),
        // The draw-down test is the box it carries.
        Geometry::DrawDown(g) => ContainerWalls::Box(build_cuboid_walls(
            sim,
            &g.container,
            material,
            interaction,
        )?),
    })
}

/// Makes the walls of `sim` those of `target`, handle by handle, keeping the particles: a
/// container rebuilt around a settled bed for another outlet (`run --from-bed`,
/// docs/user-guide.md §5).
///
/// A wall equal to `target`'s under the same handle stays as it is, with the histories of
/// its contacts, its time-integrated load and its element loads; a wall that differs is
/// replaced ([`Simulation::replace_wall`]: its contacts start without history), one that
/// `target` has removed is removed, and one only `target` has is added. The particles and
/// every particle–particle history are untouched. Returns the handles that changed.
///
/// `target` must hold no removed wall beyond `sim`'s handles (a freshly built container
/// holds none), since a handle cannot be given out empty.
pub fn adopt_walls(sim: &mut Simulation, target: &Simulation) -> Result<Vec<WallId>, DemError> {
    let mut changed = Vec::new();
    for k in 0..sim.wall_slots().max(target.wall_slots()) {
        let id = WallId(k as u32);
        let (old, new) = (sim.wall(id), target.wall(id));
        if old == new {
            continue;
        }
        changed.push(id);
        match new {
            Some(wall) if k < sim.wall_slots() => sim.replace_wall(id, wall.clone())?,
            Some(wall) => {
                let added = sim.add_wall(wall.clone())?;
                debug_assert_eq!(added, id);
            }
            None if k < sim.wall_slots() => {
                sim.remove_wall(id)?;
            }
            None => {
                return Err(DemError::InvalidInput(format!(
                    "wall {k} is removed in the target but was never added here"
                )))
            }
        }
    }
    Ok(changed)
}

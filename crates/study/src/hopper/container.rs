//! The walls of any container kind, as the run protocol sees them: a gate to open and the
//! walls whose loads it records.

use dem::{DemError, Interaction, Simulation, WallId, WallMaterial};
use serde::{Deserialize, Serialize};

use super::builder::{build_walls, HopperWalls};
use super::silo_walls::{build_silo_walls, SiloWalls};
use crate::config::Geometry;

/// The names of walls in `wall_forces.csv`, indexed by [`ContainerWalls::named`].
pub const WALL_NAMES: [&str; 8] = [
    "left",
    "right",
    "plate_left",
    "plate_right",
    "gate",
    "cylinder",
    "hopper",
    "bottom",
];

/// Handles of a container's walls in the simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContainerWalls {
    /// The slab hopper's walls.
    Slab(HopperWalls),
    /// A cylindrical silo's walls.
    Silo(SiloWalls),
}

impl ContainerWalls {
    /// The removable plate under the outlet.
    pub fn gate(&self) -> WallId {
        match self {
            Self::Slab(w) => w.gate,
            Self::Silo(w) => w.gate,
        }
    }

    /// The name of wall `id` among these walls: a [`WALL_NAMES`] entry, or `front` and
    /// `back` for a slab's faces; `None` for a handle that is none of them.
    pub fn name_of(&self, id: WallId) -> Option<&'static str> {
        if let Self::Slab(w) = self {
            if let Some(k) = w.faces.iter().position(|f| *f == id) {
                return Some(["front", "back"][k]);
            }
        }
        self.named()
            .into_iter()
            .find(|(_, wall)| *wall == Some(id))
            .map(|(k, _)| WALL_NAMES[k as usize])
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
        }
    }

    /// The walls that may record loads, each with its index into [`WALL_NAMES`]; absent
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
        }
    }
}

/// Adds the walls of `geometry`, gate closed, to `sim`.
pub fn build_container_walls(
    sim: &mut Simulation,
    geometry: &Geometry,
    material: WallMaterial,
    interaction: Interaction,
) -> Result<ContainerWalls, DemError> {
    Ok(match geometry {
        Geometry::Slab(g) => ContainerWalls::Slab(build_walls(sim, g, material, interaction)?),
        Geometry::Cylinder(g) => {
            ContainerWalls::Silo(build_silo_walls(sim, g, material, interaction)?)
        }
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

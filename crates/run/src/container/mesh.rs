//! The walls of a container of STL walls (docs/physics.md §5.8): one engine mesh per file, in
//! the case's order, and a gate over the orifice in the plane z = 0.

use std::f64::consts::PI;

use dem::{DVec3, DemError, Interaction, Simulation, Wall, WallId, WallMaterial};
use serde::{Deserialize, Serialize};

use super::cut::vertical_cut;
use case::{MeshGeometry, MeshOutlet};

/// Handles of a mesh container's walls in the simulation.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct MeshWalls {
    /// One wall per STL file, in the case's order.
    pub walls: Vec<WallId>,
    /// Their names (`geometry.walls[i].name`).
    pub names: Vec<String>,
    /// The removable plate over the orifice.
    pub gate: WallId,
}

fn invalid(e: impl std::fmt::Display) -> DemError {
    DemError::InvalidInput(e.to_string())
}

/// The gate's outline in the plane z = 0, counter-clockwise seen from above: the rectangle
/// itself, or the regular polygon of `segments` sides circumscribing the disc (its edges touch
/// the circle, so it covers the whole orifice; the cylinder kind's gate under a cone is built
/// the same way).
pub fn gate_outline(outlet: &MeshOutlet) -> Vec<DVec3> {
    match outlet {
        MeshOutlet::Disc {
            centre,
            radius,
            segments,
        } => {
            let corner = radius / (PI / *segments as f64).cos();
            stl::shapes::ring_hole(0.0, *centre, corner, *segments)
        }
        MeshOutlet::Rectangle { centre, size } => {
            let (hx, hy) = (0.5 * size[0], 0.5 * size[1]);
            vec![
                DVec3::new(centre[0] - hx, centre[1] - hy, 0.0),
                DVec3::new(centre[0] + hx, centre[1] - hy, 0.0),
                DVec3::new(centre[0] + hx, centre[1] + hy, 0.0),
                DVec3::new(centre[0] - hx, centre[1] + hy, 0.0),
            ]
        }
    }
}

/// Adds the container's walls, gate closed, to `sim`: each file's triangles as one mesh, as
/// the case read them (the same triangles give the same walls, bit for bit), then the gate.
pub fn build_mesh_walls(
    sim: &mut Simulation,
    container: &MeshGeometry,
    material: WallMaterial,
    interaction: Interaction,
) -> Result<MeshWalls, DemError> {
    let mut walls = Vec::with_capacity(container.walls.len());
    for wall in &container.walls {
        let mesh = Wall::mesh(&wall.triangles, material, interaction)
            .map_err(|e| invalid(format!("{}: {e}", wall.file.display())))?;
        walls.push(sim.add_wall(mesh)?);
    }
    let gate =
        Wall::polygon(gate_outline(&container.outlet), material, interaction).map_err(invalid)?;
    let gate = sim.add_wall(gate)?;
    let names = container.walls.iter().map(|w| w.name.clone()).collect();
    Ok(MeshWalls { walls, names, gate })
}

/// Every triangle of the container's walls [m], for the VTU output.
pub fn mesh_wall_polygons(container: &MeshGeometry) -> Vec<Vec<[f64; 3]>> {
    container
        .walls
        .iter()
        .flat_map(|w| w.triangles.iter())
        .map(|t| t.iter().map(|v| v.to_array()).collect())
        .collect()
}

/// Segments (x, z) [m] of the walls in the vertical plane through the orifice's centre,
/// y = y_c: what a frame of a vertical cut draws.
pub fn mesh_outline(container: &MeshGeometry) -> Vec<[(f64, f64); 2]> {
    vertical_cut(&mesh_wall_polygons(container), container.outlet.centre()[1])
}

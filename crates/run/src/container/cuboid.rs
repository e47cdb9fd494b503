//! The walls of a rectangular silo (docs/physics.md §5.7): the faces of its convex polyhedron
//! (side walls, the wedge's or pyramid's plates) as exact polygons or as triangle meshes, a flat
//! bottom around the orifice as one mesh of exact planes, and a gate that closes the orifice.

use dem::{DVec3, DemError, Interaction, Simulation, Wall, WallId, WallMaterial};
use serde::{Deserialize, Serialize};

use super::cut::vertical_cut;
use case::{CuboidFace, CuboidGeometry, WallSurface};

/// Handles of a rectangular silo's walls in the simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct CuboidWalls {
    /// The side walls x = −W/2, x = +W/2, y = −B/2, y = +B/2 (left, right, front, back).
    pub sides: [WallId; 4],
    /// The plates rising from the orifice's edges toward the same walls; absent where there
    /// is none (a wedge has no front and back plates, a flat bottom none at all).
    pub plates: [Option<WallId>; 4],
    /// The flat bottom around the orifice (absent under a hopper).
    pub bottom: Option<WallId>,
    /// The removable plate over the orifice.
    pub gate: WallId,
}

fn invalid(e: impl std::fmt::Display) -> DemError {
    DemError::InvalidInput(e.to_string())
}

/// The triangles of a convex polygon, as a fan from its first vertex.
fn fan(polygon: &[DVec3]) -> Vec<stl::Triangle> {
    (1..polygon.len() - 1)
        .map(|k| [polygon[0], polygon[k], polygon[k + 1]])
        .collect()
}

/// The flat bottom z = 0 between the walls and the orifice as triangles, counter-clockwise
/// seen from above. A slot leaves two rectangles beside it; a square leaves a frame of four
/// trapezoids, each split into two triangles that share the frame's corners, so that the mesh
/// has no corner in the middle of another triangle's edge (a T-junction would give a sphere on
/// the seam a face and an edge contact at once, docs/physics.md §5.3).
fn flat_bottom(silo: &CuboidGeometry) -> Vec<stl::Triangle> {
    let (hw, hb) = (0.5 * silo.width, 0.5 * silo.depth);
    let hole = silo.orifice();
    let p = |x: f64, y: f64| DVec3::new(x, y, 0.0);
    let (left, right) = (hole[0].x, hole[1].x);
    let mut triangles = Vec::new();
    match silo.outlet {
        case::CuboidOutlet::Slot => {
            for (a, b) in [(-hw, left), (right, hw)] {
                triangles.extend(fan(&[p(a, -hb), p(b, -hb), p(b, hb), p(a, hb)]));
            }
        }
        case::CuboidOutlet::Square => {
            let outer = [p(-hw, -hb), p(hw, -hb), p(hw, hb), p(-hw, hb)];
            for k in 0..4 {
                let next = (k + 1) % 4;
                triangles.push([hole[k], outer[k], outer[next]]);
                triangles.push([hole[k], outer[next], hole[next]]);
            }
        }
    }
    triangles
}

/// The wall polygons of the silo as (face, polygon): every face of the polyhedron but its top
/// and its bottom (the orifice plane, which [`build_cuboid_walls`] covers with the gate and, for a
/// flat bottom, the bottom mesh).
fn wall_faces(silo: &CuboidGeometry) -> Vec<(CuboidFace, Vec<DVec3>)> {
    silo.faces(silo.height)
        .into_iter()
        .filter(|(face, _)| !matches!(face, CuboidFace::Top | CuboidFace::Bottom))
        .collect()
}

/// Index of a side wall or plate in [`CuboidWalls`]' arrays.
fn slot_of(face: CuboidFace) -> (bool, usize) {
    match face {
        CuboidFace::Left => (true, 0),
        CuboidFace::Right => (true, 1),
        CuboidFace::Front => (true, 2),
        CuboidFace::Back => (true, 3),
        CuboidFace::PlateLeft => (false, 0),
        CuboidFace::PlateRight => (false, 1),
        CuboidFace::PlateFront => (false, 2),
        CuboidFace::PlateBack => (false, 3),
        CuboidFace::Bottom | CuboidFace::Top => unreachable!("not a wall face"),
    }
}

/// Adds a rectangular silo's walls, gate closed, to `sim`: the side walls and plates in the
/// order left, right, front, back, then the plates, then a flat bottom, then the gate.
///
/// The faces meet only at concave edges (plate against wall, plate against plate), where a
/// sphere touching both needs both contacts, so one wall per face is right (§5). With
/// `walls = "meshed"` each face is the fan of its polygon's triangles instead.
pub fn build_cuboid_walls(
    sim: &mut Simulation,
    silo: &CuboidGeometry,
    material: WallMaterial,
    interaction: Interaction,
) -> Result<CuboidWalls, DemError> {
    let mut sides = [None; 4];
    let mut plates = [None; 4];
    for (face, polygon) in wall_faces(silo) {
        let wall = match silo.walls {
            WallSurface::Smooth => Wall::polygon(polygon, material, interaction),
            WallSurface::Meshed => Wall::mesh(&fan(&polygon), material, interaction),
        }
        .map_err(invalid)?;
        let id = sim.add_wall(wall)?;
        match slot_of(face) {
            (true, k) => sides[k] = Some(id),
            (false, k) => plates[k] = Some(id),
        }
    }
    let bottom = if silo.is_flat() {
        let mesh = Wall::mesh(&flat_bottom(silo), material, interaction).map_err(invalid)?;
        Some(sim.add_wall(mesh)?)
    } else {
        None
    };
    let gate =
        sim.add_wall(Wall::polygon(silo.orifice(), material, interaction).map_err(invalid)?)?;
    let side = |k: usize| {
        sides[k].ok_or_else(|| invalid(format!("the box's side wall {k} has no area below H")))
    };
    Ok(CuboidWalls {
        sides: [side(0)?, side(1)?, side(2)?, side(3)?],
        plates,
        bottom,
        gate,
    })
}

/// The silo's walls as polygons [m] for the VTU output: the faces and, for a flat bottom, the
/// bottom's triangles (the gate is not drawn).
pub fn cuboid_wall_polygons(silo: &CuboidGeometry) -> Vec<Vec<[f64; 3]>> {
    let mut polygons: Vec<Vec<[f64; 3]>> = wall_faces(silo)
        .into_iter()
        .map(|(_, p)| p.iter().map(|v| v.to_array()).collect())
        .collect();
    if silo.is_flat() {
        polygons.extend(
            flat_bottom(silo)
                .iter()
                .map(|t| t.iter().map(|v| v.to_array()).collect()),
        );
    }
    polygons
}

/// Segments (x, z) [m] of the silo's outline in the vertical plane y = 0: what a frame of a
/// vertical cut draws.
pub fn cuboid_outline(silo: &CuboidGeometry) -> Vec<[(f64, f64); 2]> {
    vertical_cut(&cuboid_wall_polygons(silo), 0.0)
}

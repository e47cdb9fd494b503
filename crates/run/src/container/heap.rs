//! The walls of the angle-of-repose test (docs/physics.md §5.9): a cylinder open at both ends
//! standing on a round plate. The cylinder is the engine's exact frustum, lifted by the protocol
//! and removed once clear of the heap; the plate is a regular polygon, so that grains rolling
//! past its edge fall off it, given to the engine as a mesh of the triangles fanning out from
//! its centre: a heap spreads over the whole plate, and each grain on a mesh meets only the
//! triangles near it, where a polygon of 96 sides costs every contact all its edges.

use std::f64::consts::PI;

use dem::{DVec3, DemError, Interaction, Simulation, Wall, WallId, WallMaterial};
use serde::{Deserialize, Serialize};

use case::{HeapGeometry, DEFAULT_MESH_SEGMENTS};

/// Handles of the heap test's walls in the simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct HeapWalls {
    /// The cylinder, from the plate up to H; lifted, then removed.
    pub cylinder: WallId,
    /// The base plate at z = 0.
    pub plate: WallId,
}

fn invalid(e: impl std::fmt::Display) -> DemError {
    DemError::InvalidInput(e.to_string())
}

/// The plate's outline: the regular polygon of [`DEFAULT_MESH_SEGMENTS`] sides inscribed in
/// the circle of radius R_p (its edges lie at most R_p (1 − cos(π/96)) ≈ 0.05 % of R_p inside
/// the circle), counter-clockwise seen from above.
fn plate_outline(test: &HeapGeometry) -> Vec<DVec3> {
    stl::shapes::ring_hole(0.0, [0.0, 0.0], test.plate_radius, DEFAULT_MESH_SEGMENTS)
}

/// Adds the heap test's walls to `sim`: the cylinder, then the plate.
pub fn build_heap_walls(
    sim: &mut Simulation,
    test: &HeapGeometry,
    material: WallMaterial,
    interaction: Interaction,
) -> Result<HeapWalls, DemError> {
    let cylinder = Wall::cylinder(
        DVec3::ZERO,
        DVec3::Z,
        test.height,
        test.cylinder_radius,
        material,
        interaction,
    )
    .map_err(invalid)?;
    let cylinder = sim.add_wall(cylinder)?;
    let outline = plate_outline(test);
    let fan: Vec<stl::Triangle> = (0..outline.len())
        .map(|i| [DVec3::ZERO, outline[i], outline[(i + 1) % outline.len()]])
        .collect();
    let plate = Wall::mesh(&fan, material, interaction).map_err(invalid)?;
    let plate = sim.add_wall(plate)?;
    Ok(HeapWalls { cylinder, plate })
}

/// Segments (x, z) [m] of the test's outline in the vertical plane y = 0: the cylinder's two
/// sides where it stands before the lift, and the plate.
pub fn heap_outline(test: &HeapGeometry) -> Vec<[(f64, f64); 2]> {
    let (r, h, rp) = (test.cylinder_radius, test.height, test.plate_radius);
    vec![
        [(-r, 0.0), (-r, h)],
        [(r, 0.0), (r, h)],
        [(-rp, 0.0), (rp, 0.0)],
    ]
}

/// The walls as polygons [m] for the VTU output: quadrilaterals around the cylinder where it
/// stands before the lift, and the plate.
pub fn heap_wall_polygons(test: &HeapGeometry) -> Vec<Vec<[f64; 3]>> {
    let k = DEFAULT_MESH_SEGMENTS;
    let (r, h) = (test.cylinder_radius, test.height);
    let at = |i: usize, z: f64| {
        let (sin, cos) = (2.0 * PI * (i % k) as f64 / k as f64).sin_cos();
        [r * cos, r * sin, z]
    };
    let mut polygons: Vec<Vec<[f64; 3]>> = (0..k)
        .map(|i| vec![at(i, 0.0), at(i + 1, 0.0), at(i + 1, h), at(i, h)])
        .collect();
    polygons.push(plate_outline(test).iter().map(|v| v.to_array()).collect());
    polygons
}

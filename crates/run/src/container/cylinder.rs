//! The walls of a cylindrical silo (docs/physics.md §5.6): the cylinder, a conical hopper or a
//! flat bottom with the orifice, and a gate that closes the orifice until the discharge.

use std::f64::consts::PI;

use dem::{DVec3, DemError, Interaction, Simulation, Wall, WallId, WallMaterial};
use serde::{Deserialize, Serialize};

use case::{CylinderGeometry, WallSurface};

/// Handles of a cylindrical silo's walls in the simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct CylinderWalls {
    /// The cylinder, from the top of the cone (or the bottom) up to H.
    pub cylinder: WallId,
    /// The conical hopper, or the flat bottom around the orifice.
    pub bottom: WallId,
    /// Whether `bottom` is a cone (false: a flat bottom).
    pub conical: bool,
    /// The removable plate under the orifice.
    pub gate: WallId,
}

/// How far the flat bottom's mesh reaches beyond the cylinder, as a fraction of R: its outer
/// edge then lies outside the container, where no particle can meet it.
const BOTTOM_OVERHANG: f64 = 0.05;

fn invalid(e: impl std::fmt::Display) -> DemError {
    DemError::InvalidInput(e.to_string())
}

/// Adds a cylindrical silo's walls, gate closed, to `sim`.
///
/// The cylinder and cone are the engine's exact frusta, or meshes of `mesh_segments` strips
/// with their rings matching where they meet. A flat bottom is always a mesh (a flat ring:
/// its faces are exact planes). The gate is a polygon in the orifice plane: for a flat bottom
/// the ring's own hole polygon, so that the two tile the plane without overlap; under a cone,
/// the polygon circumscribing the orifice, whose corners lie under the cone, outside the silo.
pub fn build_cylinder_walls(
    sim: &mut Simulation,
    silo: &CylinderGeometry,
    material: WallMaterial,
    interaction: Interaction,
) -> Result<CylinderWalls, DemError> {
    let (r, h, ro) = (silo.radius, silo.height, silo.outlet_radius());
    let hc = silo.cone_height();
    let k = silo.mesh_segments;
    let mesh = |t: Vec<stl::Triangle>| Wall::mesh(&t, material, interaction).map_err(invalid);
    let cylinder = match silo.walls {
        WallSurface::Smooth => Wall::cylinder(
            DVec3::new(0.0, 0.0, hc),
            DVec3::Z,
            h - hc,
            r,
            material,
            interaction,
        )
        .map_err(invalid)?,
        WallSurface::Meshed => mesh(
            stl::shapes::cylinder_side(
                DVec3::new(0.0, 0.0, hc),
                DVec3::new(0.0, 0.0, h - hc),
                r,
                k,
            )
            .map_err(invalid)?,
        )?,
    };
    let cylinder = sim.add_wall(cylinder)?;
    let conical = !silo.is_flat();
    let bottom = if conical {
        match silo.walls {
            WallSurface::Smooth => {
                Wall::frustum(DVec3::ZERO, DVec3::Z, hc, [ro, r], material, interaction)
                    .map_err(invalid)?
            }
            WallSurface::Meshed => mesh(
                stl::shapes::frustum_side(DVec3::ZERO, DVec3::new(0.0, 0.0, hc), ro, r, k)
                    .map_err(invalid)?,
            )?,
        }
    } else {
        mesh(
            stl::shapes::flat_ring(
                0.0,
                r * (1.0 + BOTTOM_OVERHANG),
                [silo.outlet_offset, 0.0],
                ro,
                k,
            )
            .map_err(invalid)?,
        )?
    };
    let bottom = sim.add_wall(bottom)?;
    let outline: Vec<DVec3> = if conical {
        // The circumscribed polygon: its edges touch the circle of radius r_o.
        let corner = ro / (PI / k as f64).cos();
        stl::shapes::ring_hole(0.0, [0.0, 0.0], corner, k)
    } else {
        stl::shapes::ring_hole(0.0, [silo.outlet_offset, 0.0], ro, k)
    };
    let gate = sim.add_wall(Wall::polygon(outline, material, interaction).map_err(invalid)?)?;
    Ok(CylinderWalls {
        cylinder,
        bottom,
        conical,
        gate,
    })
}

/// Segments (x, z) [m] of the silo's outline in the vertical plane y = 0 through its axis:
/// the cylinder's two sides and the cone's or the flat bottom's two halves beside the
/// orifice. What a frame of a vertical cut draws.
pub fn cylinder_outline(silo: &CylinderGeometry) -> Vec<[(f64, f64); 2]> {
    let (r, h, hc) = (silo.radius, silo.height, silo.cone_height());
    let (left, right) = (
        silo.outlet_offset - silo.outlet_radius(),
        silo.outlet_offset + silo.outlet_radius(),
    );
    vec![
        [(-r, hc), (-r, h)],
        [(r, hc), (r, h)],
        [(-r, hc), (left, 0.0)],
        [(right, 0.0), (r, hc)],
    ]
}

/// The silo's walls as polygons [m] for the VTU output: `segments` quadrilaterals around
/// the cylinder, around the cone, and between the bottom's outer edge and the orifice.
pub fn cylinder_wall_polygons(silo: &CylinderGeometry) -> Vec<Vec<[f64; 3]>> {
    let k = silo.mesh_segments;
    let (r, h, hc, ro) = (
        silo.radius,
        silo.height,
        silo.cone_height(),
        silo.outlet_radius(),
    );
    let at = |centre: f64, radius: f64, i: usize, z: f64| {
        let (sin, cos) = (2.0 * PI * (i % k) as f64 / k as f64).sin_cos();
        [centre + radius * cos, radius * sin, z]
    };
    let mut polygons = Vec::with_capacity(2 * k);
    for i in 0..k {
        polygons.push(vec![
            at(0.0, r, i, hc),
            at(0.0, r, i + 1, hc),
            at(0.0, r, i + 1, h),
            at(0.0, r, i, h),
        ]);
        let (inner, outer, top) = if silo.is_flat() {
            (silo.outlet_offset, r, 0.0)
        } else {
            (0.0, r, hc)
        };
        polygons.push(vec![
            at(inner, ro, i, 0.0),
            at(inner, ro, i + 1, 0.0),
            at(0.0, outer, i + 1, top),
            at(0.0, outer, i, top),
        ]);
    }
    polygons
}

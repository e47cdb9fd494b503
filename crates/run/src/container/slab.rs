//! The hopper's walls (docs/physics.md §5): side walls, front and back walls, two bottom plates
//! inclined at α from the orifice edges to the side walls, and a gate under the orifice.

use dem::{DVec3, DemError, Interaction, Simulation, Wall, WallId, WallMaterial};

use case::SlabGeometry;

/// Handles of the hopper's walls in the simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct SlabWalls {
    /// Left and right side walls (x = ∓L/2).
    pub sides: [WallId; 2],
    /// Front (y = 0) and back (y = Z) walls.
    pub faces: [WallId; 2],
    /// Left and right bottom plates; absent where the outlet touches the side wall.
    pub plates: [Option<WallId>; 2],
    /// The removable plate under the orifice.
    pub gate: WallId,
}

/// A rectangle in the x–z plane spanning the slab in y, from (x0, z0) to (x1, z1).
///
/// It reaches one slab thickness beyond the front and back walls so that no particle can
/// meet its y-edges (one contact per primitive is then correct, docs/physics.md §5).
fn slab_rectangle(a: (f64, f64), b: (f64, f64), thickness: f64) -> Vec<DVec3> {
    let (y0, y1) = (-thickness, 2.0 * thickness);
    vec![
        DVec3::new(a.0, y0, a.1),
        DVec3::new(b.0, y0, b.1),
        DVec3::new(b.0, y1, b.1),
        DVec3::new(a.0, y1, a.1),
    ]
}

/// In-plane (x, z) segments of the hopper outline: side walls and bottom plates [m].
pub fn slab_outline(geometry: &SlabGeometry) -> Vec<[(f64, f64); 2]> {
    let half = 0.5 * geometry.width;
    let (xl, xr) = geometry.outlet_edges();
    let (run_l, run_r) = geometry.plate_runs();
    let rise = |run: f64| {
        if geometry.hopper_angle_deg >= 90.0 {
            0.0
        } else {
            run / geometry.hopper_angle().tan()
        }
    };
    let (zl, zr) = (rise(run_l), rise(run_r));
    let mut segments = vec![
        [(-half, zl), (-half, geometry.height)],
        [(half, zr), (half, geometry.height)],
    ];
    if run_l > 0.0 {
        segments.push([(-half, zl), (xl, 0.0)]);
    }
    if run_r > 0.0 {
        segments.push([(xr, 0.0), (half, zr)]);
    }
    segments
}

/// Adds the hopper's walls, gate closed, to `sim`.
pub fn build_slab_walls(
    sim: &mut Simulation,
    geometry: &SlabGeometry,
    material: WallMaterial,
    interaction: Interaction,
) -> Result<SlabWalls, DemError> {
    let z = geometry.thickness;
    let wall = |v: Vec<DVec3>| {
        Wall::polygon(v, material, interaction).map_err(|e| DemError::InvalidInput(e.to_string()))
    };
    let segs = slab_outline(geometry);
    let left = sim.add_wall(wall(slab_rectangle(segs[0][0], segs[0][1], z))?)?;
    let right = sim.add_wall(wall(slab_rectangle(segs[1][0], segs[1][1], z))?)?;
    let plane = |p: DVec3, n: DVec3| {
        Wall::plane(p, n, material, interaction).map_err(|e| DemError::InvalidInput(e.to_string()))
    };
    // The faces touch nearly every particle of a quasi-2D slab and no output reads their
    // load: it is not summed (`Wall::sums_load`).
    let face = |p: DVec3, n: DVec3| {
        plane(p, n).map(|mut w| {
            w.sums_load = false;
            w
        })
    };
    let front = sim.add_wall(face(DVec3::ZERO, DVec3::Y)?)?;
    let back = sim.add_wall(face(DVec3::new(0.0, z, 0.0), -DVec3::Y)?)?;
    let (run_l, run_r) = geometry.plate_runs();
    let mut plates = [None, None];
    let mut k = 2;
    if run_l > 0.0 {
        plates[0] = Some(sim.add_wall(wall(slab_rectangle(segs[k][0], segs[k][1], z))?)?);
        k += 1;
    }
    if run_r > 0.0 {
        plates[1] = Some(sim.add_wall(wall(slab_rectangle(segs[k][0], segs[k][1], z))?)?);
    }
    // The gate spans exactly the orifice at the outlet plane. Overlapping the plates would
    // give particles resting on the overlap two floor contacts.
    let (xl, xr) = geometry.outlet_edges();
    let gate = sim.add_wall(wall(slab_rectangle((xl, 0.0), (xr, 0.0), z))?)?;
    Ok(SlabWalls {
        sides: [left, right],
        faces: [front, back],
        plates,
        gate,
    })
}

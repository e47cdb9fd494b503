//! The mesh-floor benchmark: one settled bed of Table-1 spheres timed twice, on its
//! analytic floor plane and on a floor of `triangles` small triangles in the same place,
//! which prices a triangle-mesh wall against the plane it replaces (docs/physics.md §5.3).
//!
//! The bed is the monodisperse bed of the bidisperse benchmark (ratio 1), settled on its
//! plane. The mesh floor then takes the plane's place under the same bed: a square a sphere
//! diameter wider than the bed on each side, of n × n squares of two triangles each.

use dem::{DVec3, Interaction, Material, Simulation, Wall, WallId, WallMaterial};

use super::{settled_bidisperse_bed, time_steps, BenchResult, BidisperseBed, SMALL_DIAMETER};
use crate::RunError;

/// The floor under the particles of `sim`: a square a diameter wider than their footprint,
/// at z = 0, of at least `triangles` triangles.
fn floor_under(sim: &Simulation, triangles: usize) -> Vec<[DVec3; 3]> {
    let p = sim.particles().positions();
    let lo = p.iter().fold(DVec3::INFINITY, |a, b| a.min(*b)) - DVec3::splat(SMALL_DIAMETER);
    let hi = p.iter().fold(DVec3::NEG_INFINITY, |a, b| a.max(*b)) + DVec3::splat(SMALL_DIAMETER);
    let n = ((triangles as f64 / 2.0).sqrt().ceil() as usize).max(1);
    let step = (hi - lo) / n as f64;
    let at =
        |i: usize, j: usize| DVec3::new(lo.x + i as f64 * step.x, lo.y + j as f64 * step.y, 0.0);
    let mut out = Vec::with_capacity(2 * n * n);
    for i in 0..n {
        for j in 0..n {
            out.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            out.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    out
}

/// Times `steps` steps of the settled bed of `particles` spheres on its plane floor, then
/// the same bed on a mesh floor of at least `triangles` triangles; `settle_steps` and
/// `cache` as for [`settled_bidisperse_bed`].
pub fn mesh_floor_benchmark(
    particles: usize,
    triangles: usize,
    threads: usize,
    (settle_steps, steps): (u64, u64),
    cache: Option<&std::path::Path>,
) -> Result<Vec<BenchResult>, RunError> {
    let bed = BidisperseBed {
        ratio: 1,
        particles,
    };
    let mut on_plane = settled_bidisperse_bed(bed, threads, settle_steps, cache)?;
    let state = on_plane.state().clone();
    let plane = time_steps(&mut on_plane, steps, "bed on its floor plane", threads)?;

    let mut on_mesh = Simulation::from_state(state, threads)?;
    // The floor is the bed's first wall (`bidisperse_bed`).
    on_mesh.remove_wall(WallId(0))?;
    let floor = floor_under(&on_mesh, triangles);
    let wall = Wall::mesh(
        &floor,
        WallMaterial::Elastic(Material::fan2023()),
        Interaction::fan2023(),
    )
    .map_err(|e| dem::DemError::InvalidInput(e.to_string()))?;
    on_mesh.add_wall(wall)?;
    let name = format!("bed on a floor of {} triangles", floor.len());
    let mesh = time_steps(&mut on_mesh, steps, &name, threads)?;
    Ok(vec![plane, mesh])
}

//! Filling a 3D container (a cylindrical or rectangular silo, the fill box of STL walls):
//! random sequential insertion in a band of the container, in batches that fall under gravity
//! (the same protocol as the slab's, docs/physics.md §10.8), with a cell grid for the overlap
//! test so that a batch of 10⁴–10⁵ spheres costs O(n).

use std::collections::HashMap;

use dem::{DVec3, Simulation};
use rand::Rng;

use super::batch::{insert_batch, overlaps, Placed, GAP};
use super::draw::{Draw, ParticleDraws};
use super::slab::Inserted;
use case::{CuboidGeometry, CylinderGeometry, HeapGeometry, MeshGeometry};

/// Where spheres may be inserted: a box of candidate centres and the test that keeps a sphere
/// inside the container.
pub trait FillRegion {
    /// The ranges [x0, x1), [y0, y1) and [z0, z1] [m] that candidate centres are drawn from
    /// (z0, z1 narrowing the insertion band).
    fn draw_ranges(&self) -> ([f64; 2], [f64; 2], [f64; 2]);
    /// Whether a sphere of radius `r` [m] at (x, y, z) lies inside with clearance `gap` [m].
    fn holds(&self, x: f64, y: f64, z: f64, r: f64, gap: f64) -> bool;
}

impl FillRegion for CylinderGeometry {
    fn draw_ranges(&self) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let reach = self.radius;
        ([-reach, reach], [-reach, reach], [0.0, self.height])
    }

    fn holds(&self, x: f64, y: f64, z: f64, r: f64, gap: f64) -> bool {
        CylinderGeometry::holds(self, x, y, z, r, gap)
    }
}

impl FillRegion for CuboidGeometry {
    fn draw_ranges(&self) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let (hw, hb) = (0.5 * self.width, 0.5 * self.depth);
        ([-hw, hw], [-hb, hb], [0.0, self.height])
    }

    fn holds(&self, x: f64, y: f64, z: f64, r: f64, gap: f64) -> bool {
        CuboidGeometry::holds(self, x, y, z, r, gap)
    }
}

impl FillRegion for HeapGeometry {
    fn draw_ranges(&self) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let reach = self.cylinder_radius;
        ([-reach, reach], [-reach, reach], [0.0, self.height])
    }

    fn holds(&self, x: f64, y: f64, z: f64, r: f64, gap: f64) -> bool {
        HeapGeometry::holds(self, x, y, z, r, gap)
    }
}

impl FillRegion for MeshGeometry {
    fn draw_ranges(&self) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let (lo, hi) = (self.fill_min, self.fill_max);
        ([lo[0], hi[0]], [lo[1], hi[1]], [lo[2], hi[2]])
    }

    fn holds(&self, x: f64, y: f64, z: f64, r: f64, gap: f64) -> bool {
        MeshGeometry::holds(self, x, y, z, r, gap)
    }
}

/// Spheres already placed, binned in cubic cells at least one largest diameter wide.
struct Cells {
    cell: f64,
    cells: HashMap<(i64, i64, i64), Vec<(DVec3, f64)>>,
}

impl Cells {
    fn new(cell: f64) -> Self {
        Self {
            cell,
            cells: HashMap::new(),
        }
    }

    fn key(&self, x: DVec3) -> (i64, i64, i64) {
        let k = |v: f64| (v / self.cell).floor() as i64;
        (k(x.x), k(x.y), k(x.z))
    }
}

impl Placed for Cells {
    /// Whether a sphere at `x` of radius `r` keeps the gap to every placed sphere: with cells
    /// one largest diameter wide, any sphere it could touch has its centre in a neighbour cell.
    fn is_free(&self, x: DVec3, r: f64) -> bool {
        let (i, j, k) = self.key(x);
        for di in -1..=1 {
            for dj in -1..=1 {
                for dk in -1..=1 {
                    if let Some(list) = self.cells.get(&(i + di, j + dj, k + dk)) {
                        if list.iter().any(|(q, rq)| overlaps(x, r, *q, *rq)) {
                            return false;
                        }
                    }
                }
            }
        }
        true
    }

    fn add(&mut self, x: DVec3, r: f64) {
        let key = self.key(x);
        self.cells.entry(key).or_default().push((x, r));
    }
}

/// Random sequential insertion of up to `count` spheres drawn by `draws` into the band
/// z ∈ [`band.0`, `band.1`] [m] of the region (narrowed to its own z range), avoiding every
/// particle already in `sim`; each starts with velocity `v0` [m/s]. Returns the particles
/// inserted. A draw that does not fit is kept until it is placed, as in
/// [`super::fill::insert_slab_batch`].
#[allow(clippy::too_many_arguments)]
pub fn insert_silo_batch(
    sim: &mut Simulation,
    region: &dyn FillRegion,
    rng: &mut impl Rng,
    count: usize,
    draws: &ParticleDraws,
    pending: &mut Option<Draw>,
    band: (f64, f64),
    v0: DVec3,
    max_attempts: usize,
) -> Result<Vec<Inserted>, dem::DemError> {
    let ([x0, x1], [y0, y1], [z0, z1]) = region.draw_ranges();
    // A band inside the region's z range is drawn from as it is (a silo's band always is).
    let band = (band.0.max(z0), band.1.min(z1));
    // The farthest a grain reaches from its centre: the largest radius for spheres, more
    // for elongated clumps, whose members are recorded one by one.
    let reach = draws.max_reach();
    let mut placed = Cells::new(2.0 * reach + GAP);
    let p = sim.particles();
    for (x, r) in p.positions().iter().zip(p.radii()) {
        if x.z + r > band.0 - 2.0 * reach && x.z - r < band.1 + 2.0 * reach {
            placed.add(*x, *r);
        }
    }
    if band.0 >= band.1 {
        return Ok(Vec::new());
    }
    insert_batch(
        sim,
        rng,
        count,
        draws,
        pending,
        v0,
        max_attempts,
        &mut placed,
        |rng, r| {
            let x = rng.gen_range(x0..x1);
            let y = rng.gen_range(y0..y1);
            let z = rng.gen_range(band.0..band.1);
            region.holds(x, y, z, r, GAP).then(|| DVec3::new(x, y, z))
        },
    )
}

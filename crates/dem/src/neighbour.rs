//! Neighbour search: a cell list feeding a Verlet list with a skin (physics.md §6.2).
//!
//! Candidate pairs are all pairs closer than R_i + R_j + skin, and wall candidates all bodies
//! closer than R_i + skin to a wall. The lists are rebuilt only when the bodies' motion since
//! the last build could have closed one of those gaps (`Simulation::lists_may_miss`: the
//! bodies' relative displacements against the skin for pairs, their own against it for
//! walls), so no contact can be missed in between. Contact history lives in arrays parallel
//! to the pair list and is carried over every rebuild, by index when particles kept their
//! indices and by tag otherwise.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::contact::ContactHistory;
use crate::history::{HistoryArrays, NO_SOURCE};
use crate::particles::ParticleSet;
use crate::wall::{Wall, WallShape};

/// A uniform grid of cells at least as wide as the interaction cutoff.
#[derive(Debug, Clone, Default)]
pub struct CellGrid {
    origin: DVec3,
    inv_cell: f64,
    dims: [usize; 3],
    /// Cell of each particle.
    cell_of: Vec<u32>,
    /// Particles sorted by cell (stable).
    sorted: Vec<u32>,
    /// `sorted[start[c]..start[c+1]]` are the particles of cell c.
    start: Vec<u32>,
    /// Scratch of the counting sort: the next free slot of each cell (kept for its allocation).
    fill: Vec<u32>,
}

impl CellGrid {
    /// Bins `positions` into cells of width at least `cell` [m].
    pub fn build(positions: &[DVec3], cell: f64) -> Self {
        let mut grid = Self::default();
        grid.rebuild(positions, cell);
        grid
    }

    /// Re-bins in place, reusing the allocations.
    pub fn rebuild(&mut self, positions: &[DVec3], cell: f64) {
        let n = positions.len();
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for p in positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        if n == 0 {
            lo = DVec3::ZERO;
            hi = DVec3::ZERO;
        }
        // A runaway particle must not blow up the grid: widen the cells until the grid has
        // at most max(8N, 4096) cells. Correctness needs only cell ≥ cutoff.
        let max_cells = (8 * n).max(4096) as f64;
        let mut width = cell;
        let extent = hi - lo;
        loop {
            let d = (extent / width).floor() + DVec3::ONE;
            if d.x * d.y * d.z <= max_cells {
                break;
            }
            width *= 1.5;
        }
        self.origin = lo;
        self.inv_cell = 1.0 / width;
        let d = (extent * self.inv_cell).floor() + DVec3::ONE;
        self.dims = [d.x as usize, d.y as usize, d.z as usize];
        let ncells = self.dims[0] * self.dims[1] * self.dims[2];
        let mut cell_of = std::mem::take(&mut self.cell_of);
        cell_of.clear();
        cell_of.extend(positions.iter().map(|p| self.cell_index(*p) as u32));
        self.cell_of = cell_of;
        self.start.clear();
        self.start.resize(ncells + 1, 0);
        for &c in &self.cell_of {
            self.start[c as usize + 1] += 1;
        }
        for c in 0..ncells {
            self.start[c + 1] += self.start[c];
        }
        self.sorted.clear();
        self.sorted.resize(n, 0);
        self.fill.clear();
        self.fill.extend_from_slice(&self.start[..ncells]);
        for (i, &c) in self.cell_of.iter().enumerate() {
            self.sorted[self.fill[c as usize] as usize] = i as u32;
            self.fill[c as usize] += 1;
        }
    }

    fn coords(&self, p: DVec3) -> [usize; 3] {
        let c = ((p - self.origin) * self.inv_cell).floor();
        [
            (c.x.max(0.0) as usize).min(self.dims[0] - 1),
            (c.y.max(0.0) as usize).min(self.dims[1] - 1),
            (c.z.max(0.0) as usize).min(self.dims[2] - 1),
        ]
    }

    fn cell_index(&self, p: DVec3) -> usize {
        let [x, y, z] = self.coords(p);
        (z * self.dims[1] + y) * self.dims[0] + x
    }

    /// Particle indices in cell order: sorting particles by it improves memory locality.
    pub fn cell_order(&self) -> &[u32] {
        &self.sorted
    }

    /// Calls `visit(row)` with the particles of each run of up to three cells along x in
    /// the 27 cells around `p` (the cells of one row are contiguous in `sorted`).
    #[inline]
    fn for_each_row_near(&self, p: DVec3, mut visit: impl FnMut(&[u32])) {
        let [x, y, z] = self.coords(p);
        let range = |c: usize, d: usize| c.saturating_sub(1)..=(c + 1).min(d - 1);
        let xs = range(x, self.dims[0]);
        for cz in range(z, self.dims[2]) {
            for cy in range(y, self.dims[1]) {
                let row = (cz * self.dims[1] + cy) * self.dims[0];
                let (a, b) = (
                    self.start[row + xs.start()] as usize,
                    self.start[row + xs.end() + 1] as usize,
                );
                visit(&self.sorted[a..b]);
            }
        }
    }
}

/// Candidate particle pairs (i < j by index) with their contact history.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct PairList {
    pub(crate) i: Vec<u32>,
    pub(crate) j: Vec<u32>,
    pub(crate) history: HistoryArrays,
}

/// Candidate particle–wall pairs with their contact history.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct WallPairList {
    pub(crate) particle: Vec<u32>,
    pub(crate) wall: Vec<u32>,
    pub(crate) history: HistoryArrays,
}

impl WallPairList {
    /// True when sorted by (wall, particle), the order `build_lists` writes.
    pub(crate) fn is_wall_major(&self) -> bool {
        self.wall
            .iter()
            .zip(&self.particle)
            .zip(self.wall.iter().zip(&self.particle).skip(1))
            .all(|(a, b)| a <= b)
    }

    /// The same candidates sorted by (wall, particle). Lists in checkpoints written before
    /// this order was introduced are particle-major; the force loop and `build_lists` need
    /// wall-major ones.
    pub(crate) fn into_wall_major(self) -> Self {
        if self.is_wall_major() {
            return self;
        }
        let mut order: Vec<usize> = (0..self.particle.len()).collect();
        order.sort_unstable_by_key(|&k| (self.wall[k], self.particle[k]));
        self.permuted(&order)
    }

    /// The candidates in the order `order` (indices into this list) gives.
    fn permuted(&self, order: &[usize]) -> Self {
        Self {
            particle: order.iter().map(|&k| self.particle[k]).collect(),
            wall: order.iter().map(|&k| self.wall[k]).collect(),
            history: order.iter().map(|&k| self.history.get(k)).collect(),
        }
    }
}

impl PairList {
    /// Number of candidate pairs.
    pub fn len(&self) -> usize {
        self.i.len()
    }
    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.i.is_empty()
    }
}

/// Histories keyed by particle tags, to carry contact memory across a change of indices.
#[derive(Debug, Default)]
pub(crate) struct TaggedHistory {
    pairs: Vec<(u64, u64, ContactHistory)>,
    walls: Vec<(u64, u32, ContactHistory)>,
}

impl TaggedHistory {
    /// Collects every non-empty history, oriented so that the smaller tag comes first.
    pub(crate) fn collect(particles: &ParticleSet, pairs: &PairList, walls: &WallPairList) -> Self {
        let tag = &particles.tag;
        let mut out = Self::default();
        for k in 0..pairs.len() {
            let h = pairs.history.get(k);
            if h.is_empty() {
                continue;
            }
            let (a, b) = (tag[pairs.i[k] as usize], tag[pairs.j[k] as usize]);
            if a < b {
                out.pairs.push((a, b, h));
            } else {
                out.pairs.push((b, a, negate(h)));
            }
        }
        for k in 0..walls.particle.len() {
            let h = walls.history.get(k);
            if !h.is_empty() {
                out.walls
                    .push((tag[walls.particle[k] as usize], walls.wall[k], h));
            }
        }
        out.pairs.sort_unstable_by_key(|&(a, b, _)| (a, b));
        out.walls.sort_unstable_by_key(|&(a, w, _)| (a, w));
        out
    }

    fn pair(&self, a: u64, b: u64) -> ContactHistory {
        let (lo, hi, flip) = if a < b { (a, b, false) } else { (b, a, true) };
        match self
            .pairs
            .binary_search_by_key(&(lo, hi), |&(x, y, _)| (x, y))
        {
            Ok(k) if flip => negate(self.pairs[k].2),
            Ok(k) => self.pairs[k].2,
            Err(_) => ContactHistory::default(),
        }
    }

    fn wall(&self, a: u64, w: u32) -> ContactHistory {
        match self
            .walls
            .binary_search_by_key(&(a, w), |&(x, y, _)| (x, y))
        {
            Ok(k) => self.walls[k].2,
            Err(_) => ContactHistory::default(),
        }
    }
}

/// Sorts a few indices in place: insertion sort, as the lists of one particle's new
/// neighbours hold a handful.
#[inline]
fn sort_small(v: &mut [u32]) {
    for k in 1..v.len() {
        let x = v[k];
        let mut m = k;
        while m > 0 && v[m - 1] > x {
            v[m] = v[m - 1];
            m -= 1;
        }
        v[m] = x;
    }
}

/// Fills `history` for the new candidates `ids`, a list sorted by its two columns: from
/// `by_tag(a, b)` when indices changed (a re-sort, tag-keyed history), or else from the
/// previous list `old` (its columns and histories, sorted the same way), in one merge.
fn carry_histories(
    history: &mut HistoryArrays,
    ids: (&[u32], &[u32]),
    old: ((&[u32], &[u32]), &HistoryArrays),
    by_tag: Option<impl Fn(u32, u32) -> ContactHistory>,
) {
    match by_tag {
        Some(by_tag) => {
            history.clear();
            for (&a, &b) in ids.0.iter().zip(ids.1) {
                history.push(by_tag(a, b));
            }
        }
        None => {
            let source = matching(keys(ids), keys(old.0));
            history.carry_from(old.1, &source);
        }
    }
}

/// The keys (a, b) of a list sorted by (a, b), as ascending numbers.
fn keys<'a>((a, b): (&'a [u32], &'a [u32])) -> impl Iterator<Item = u64> + 'a {
    a.iter()
        .zip(b)
        .map(|(&a, &b)| (u64::from(a) << 32) | u64::from(b))
}

/// For each of the ascending keys `new`, the index of the same key among the ascending keys
/// `old`, or [`NO_SOURCE`]: one merge, the old cursor only moving forward.
fn matching(new: impl Iterator<Item = u64>, old: impl Iterator<Item = u64>) -> Vec<u32> {
    let mut old = old.enumerate().peekable();
    new.map(|key| {
        while old.next_if(|&(_, k)| k < key).is_some() {}
        match old.peek() {
            Some(&(c, k)) if k == key => c as u32,
            _ => NO_SOURCE,
        }
    })
    .collect()
}

/// History of j relative to i is minus that of i relative to j (ξ and the rolling torque on i).
fn negate(h: ContactHistory) -> ContactHistory {
    ContactHistory {
        tangential: -h.tangential,
        rolling: -h.rolling,
    }
}

/// Builds the candidate lists from a binned grid.
///
/// `carry` decides where history comes from: `None` means indices are unchanged since the
/// previous lists `old_pairs`/`old_walls` (merged by index), `Some` gives tag-keyed history.
#[allow(clippy::too_many_arguments)]
pub(crate) fn build_lists(
    grid: &CellGrid,
    particles: &ParticleSet,
    walls: &[Option<Wall>],
    skin: f64,
    old_pairs: &PairList,
    old_walls: &WallPairList,
    carry: Option<&TaggedHistory>,
    pairs: &mut PairList,
    wall_pairs: &mut WallPairList,
) {
    let pos = &particles.position;
    let rad = &particles.radius;
    let n = pos.len();
    // The histories are written whole by `carry_histories`, after the candidates.
    pairs.i.clear();
    pairs.j.clear();
    let (pos, rad) = (&pos[..n], &rad[..n]);
    let mut buf: Vec<u32> = vec![0; 64];
    for i in 0..n {
        let (xi, ri) = (pos[i], rad[i]);
        let mut count = 0;
        grid.for_each_row_near(xi, |row| {
            if buf.len() < count + row.len() {
                buf.resize(2 * (count + row.len()), 0);
            }
            for &j in row {
                let cut = ri + rad[j as usize] + skin;
                let d2 = (pos[j as usize] - xi).length_squared();
                buf[count] = j;
                count += usize::from((j as usize > i) & (d2 < cut * cut));
            }
        });
        let near = &mut buf[..count];
        sort_small(near);
        pairs.i.extend(std::iter::repeat_n(i as u32, count));
        pairs.j.extend_from_slice(near);
    }
    let tag = &particles.tag;
    carry_histories(
        &mut pairs.history,
        (&pairs.i, &pairs.j),
        ((&old_pairs.i, &old_pairs.j), &old_pairs.history),
        carry.map(|t| move |i: u32, j: u32| t.pair(tag[i as usize], tag[j as usize])),
    );

    wall_pairs.particle.clear();
    wall_pairs.wall.clear();
    // Wall-major, particles in index order within a wall: the force loop then treats one
    // wall at a time, and each particle still meets its walls in increasing order.
    debug_assert!(old_walls.is_wall_major());
    for (w, wall) in walls.iter().enumerate() {
        let Some(wall) = wall else { continue };
        let before = wall_pairs.particle.len();
        match wall.shape() {
            // Every particle is tested, without a branch on the outcome: the slab's faces
            // keep nearly all of them, other planes few, and a branch would be
            // mispredicted at the edge of every run.
            WallShape::Plane { .. } => {
                wall_pairs.particle.resize(before + n, 0);
                let out = &mut wall_pairs.particle[before..];
                let mut count = 0;
                for i in 0..n {
                    let (_, dist) = wall.closest_point(pos[i]);
                    out[count] = i as u32;
                    count += usize::from((dist < rad[i] + skin) & (dist > -rad[i]));
                }
                wall_pairs.particle.truncate(before + count);
            }
            WallShape::Polygon { .. } => {
                for i in 0..n {
                    if wall.certainly_beyond(pos[i], rad[i] + skin) {
                        continue;
                    }
                    if wall.closest_point(pos[i]).1 < rad[i] + skin {
                        wall_pairs.particle.push(i as u32);
                    }
                }
            }
        }
        let added = wall_pairs.particle.len() - before;
        wall_pairs.wall.extend(std::iter::repeat_n(w as u32, added));
    }
    carry_histories(
        &mut wall_pairs.history,
        (&wall_pairs.wall, &wall_pairs.particle),
        ((&old_walls.wall, &old_walls.particle), &old_walls.history),
        carry.map(|t| move |w: u32, i: u32| t.wall(tag[i as usize], w)),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn cell_list_finds_exactly_the_pairs_of_a_brute_force_search() {
        // Exact set equality: any missed or extra pair is a bug.
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
        let mut set = ParticleSet::default();
        for _ in 0..400 {
            let p = DVec3::new(rng.gen::<f64>(), rng.gen::<f64>() * 0.1, rng.gen::<f64>());
            let init = crate::particles::ParticleInit::at_rest(
                p,
                0.01 + 0.01 * rng.gen::<f64>(),
                crate::particles::MaterialId(0),
            );
            set.push(&init, 1000.0);
        }
        let skin = 0.005;
        let grid = CellGrid::build(&set.position, 0.04 + skin);
        let (mut pairs, mut walls) = (PairList::default(), WallPairList::default());
        build_lists(
            &grid,
            &set,
            &[],
            skin,
            &PairList::default(),
            &WallPairList::default(),
            None,
            &mut pairs,
            &mut walls,
        );
        let mut brute = Vec::new();
        for i in 0..set.len() {
            for j in i + 1..set.len() {
                let cut = set.radius[i] + set.radius[j] + skin;
                if set.position[i].distance_squared(set.position[j]) < cut * cut {
                    brute.push((i as u32, j as u32));
                }
            }
        }
        let found: Vec<(u32, u32)> = pairs
            .i
            .iter()
            .copied()
            .zip(pairs.j.iter().copied())
            .collect();
        assert_eq!(found, brute);
    }

    #[test]
    fn a_rebuild_carries_each_pairs_history_by_index_and_starts_new_pairs_empty() {
        // Exact: a carried history is the old one bit for bit, as `get` reads it (zero where
        // it was not live), and a pair the old list lacked starts from zero. The reference is
        // a map from (i, j) to the old history; the particles then move by up to a tenth of
        // their radius, so that pairs both persist and appear.
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(9);
        let mut set = ParticleSet::default();
        for _ in 0..300 {
            let p = DVec3::new(rng.gen::<f64>(), rng.gen::<f64>() * 0.1, rng.gen::<f64>()) * 0.2;
            let init =
                crate::particles::ParticleInit::at_rest(p, 0.01, crate::particles::MaterialId(0));
            set.push(&init, 1000.0);
        }
        let skin = 0.002;
        let build = |set: &ParticleSet, old: &PairList| {
            let grid = CellGrid::build(&set.position, 0.02 + skin);
            let (mut p, mut w) = (PairList::default(), WallPairList::default());
            build_lists(
                &grid,
                set,
                &[],
                skin,
                old,
                &WallPairList::default(),
                None,
                &mut p,
                &mut w,
            );
            p
        };
        let mut first = build(&set, &PairList::default());
        for k in 0..first.len() {
            let h = &mut first.history;
            h.tangential[k] = DVec3::new(k as f64 + 1.0, 0.5, -0.25);
            h.rolling[k] = DVec3::new(0.0, k as f64 + 2.0, 0.0);
            if k % 3 == 0 {
                h.live[k] = 0;
            }
        }
        let old: std::collections::HashMap<(u32, u32), ContactHistory> = (0..first.len())
            .map(|k| ((first.i[k], first.j[k]), first.history.get(k)))
            .collect();
        for x in &mut set.position {
            *x += DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 0.002 - 0.001;
        }
        let again = build(&set, &first);
        let (mut carried, mut fresh) = (0, 0);
        for k in 0..again.len() {
            let key = (again.i[k], again.j[k]);
            let want = old.get(&key).copied().unwrap_or_default();
            assert_eq!(again.history.get(k), want, "pair {key:?}");
            assert_eq!(again.history.live[k], crate::history::LIVE);
            match old.get(&key) {
                Some(h) if !h.is_empty() => carried += 1,
                Some(_) => {}
                None => fresh += 1,
            }
        }
        assert!(carried > 10 && fresh > 10, "carried {carried}, new {fresh}");
    }

    #[test]
    fn wall_candidates_are_wall_major_and_carry_history_from_either_order() {
        // Particles along a box of four planes: each particle is a candidate of several
        // walls. The list must come out sorted by (wall, particle), and a rebuild must carry
        // every history exactly, whether the old list is wall-major or particle-major (the
        // order of lists in checkpoints written before the change) and sorted on restore.
        use crate::material::{Interaction, Material, WallMaterial};
        let mut set = ParticleSet::default();
        for k in 0..50 {
            let x = DVec3::new(0.001 + 0.0005 * (k % 10) as f64, 0.0017, 0.0005 * k as f64);
            let init =
                crate::particles::ParticleInit::at_rest(x, 0.0015, crate::particles::MaterialId(0));
            set.push(&init, 1000.0);
        }
        let m = WallMaterial::Elastic(Material::fan2023());
        let i = Interaction::fan2023();
        let walls: Vec<Option<Wall>> = vec![
            Some(Wall::plane(DVec3::ZERO, DVec3::X, m, i).unwrap()),
            None,
            Some(Wall::plane(DVec3::ZERO, DVec3::Y, m, i).unwrap()),
            Some(Wall::plane(DVec3::new(0.0, 0.0034, 0.0), -DVec3::Y, m, i).unwrap()),
        ];
        let skin = 3e-4;
        let grid = CellGrid::build(&set.position, 0.003 + skin);
        let build = |old: &WallPairList| {
            let (mut p, mut w) = (PairList::default(), WallPairList::default());
            build_lists(
                &grid,
                &set,
                &walls,
                skin,
                &PairList::default(),
                old,
                None,
                &mut p,
                &mut w,
            );
            w
        };
        let mut first = build(&WallPairList::default());
        assert!(first.is_wall_major());
        let walls_seen: std::collections::BTreeSet<u32> = first.wall.iter().copied().collect();
        assert_eq!(walls_seen.len(), 3, "every present wall has candidates");
        for (k, t) in first.history.tangential.iter_mut().enumerate() {
            *t = DVec3::new(k as f64 + 1.0, 0.0, 0.0);
        }
        let particle_major = {
            let mut order: Vec<usize> = (0..first.particle.len()).collect();
            order.sort_by_key(|&k| (first.particle[k], first.wall[k]));
            first.permuted(&order)
        };
        assert!(!particle_major.is_wall_major());
        let sorted = particle_major.into_wall_major();
        for old in [&first, &sorted] {
            let again = build(old);
            assert_eq!(again.particle, first.particle);
            assert_eq!(again.wall, first.wall);
            assert_eq!(again.history, first.history, "history lost in the carry");
        }
    }
}

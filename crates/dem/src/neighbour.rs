//! Neighbour search: a cell list feeding a Verlet list with a skin (physics.md §6.2).
//!
//! Candidate pairs are all pairs closer than R_i + R_j + skin, and wall candidates all bodies
//! closer than R_i + skin to a wall. The lists are rebuilt only when the bodies' motion since
//! the last build could have closed one of those gaps (`Simulation::lists_may_miss`: the
//! bodies' relative displacements against the skin for pairs, their own against it for
//! walls), so no contact can be missed in between. Contact history lives in arrays parallel
//! to the pair list and is carried over every rebuild, by index when particles kept their
//! indices and through the map from new to old indices otherwise ([`Carry`]).

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

/// Where a list build finds the contacts' histories.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Carry<'a> {
    /// The bodies kept their indices since the previous lists (bodies may have been
    /// appended): merged by index.
    Same,
    /// The bodies' indices changed (a re-sort, bodies removed): new body k was body
    /// `origin[k]` of the previous lists.
    Moved(&'a [u32]),
}

/// The working arrays of a list build, kept by the caller from build to build, so that
/// the builds allocate nothing once these have grown. Allocated afresh at every build,
/// arrays of their sizes went back to the allocator, and some of them to the system, to be
/// faulted in again at the next build. (Whether that cost time on the hopper could not be
/// told from the host's noise; thirtieth session.)
#[derive(Debug, Clone, Default)]
pub(crate) struct ListScratch {
    /// Positions [m] and radii [m] in the grid's order.
    cells: Vec<(DVec3, f64)>,
    /// Pairs found, as (min, max) index keys.
    found: Vec<u64>,
    /// Counts and starts by body or by row.
    first: Vec<u32>,
    /// Next free slot by body, or a table by body.
    fill: Vec<u32>,
}

/// A carried history as the bodies' identities define it: none when it reads as empty
/// (zero, whatever the signs of its zeros), and negated when the pair's order of bodies
/// turned round (ξ and the rolling torque of j relative to i are minus those of i
/// relative to j). Until the thirtieth session histories crossed a change of indices by
/// the bodies' tags, which stored only non-empty ones and oriented them by tag; this keeps
/// every bit of what that store gave.
#[inline]
fn carried(h: ContactHistory, flipped: bool) -> ContactHistory {
    if h.is_empty() {
        ContactHistory::default()
    } else if flipped {
        negate(h)
    } else {
        h
    }
}

/// The histories of the new pairs `ids` (i < j, sorted) after the bodies' indices changed
/// (new body k was old body `origin[k]`), from the old pairs (i < j, sorted) and their
/// histories `old`. The old list's rows by i are found by counting, and each new pair's
/// old row, which holds a handful of entries, is scanned for its partner: no sort and no
/// search by tag. (The tag-keyed store this replaced cost about 0.9 ms a build on the
/// paper's hopper, where every outflow of particles and every sixteenth build moves the
/// indices; thirtieth session.)
fn carry_moved_pairs(
    history: &mut HistoryArrays,
    ids: (&[u32], &[u32]),
    (old_i, old_j): (&[u32], &[u32]),
    old: &HistoryArrays,
    (origin, row): (&[u32], &mut Vec<u32>),
) {
    // Old bodies that appear in the old list: i < j, so the largest j bounds them.
    let bodies = old_j.iter().max().map_or(0, |&j| j as usize + 1);
    // Old entries with i = x are `row[x]..row[x + 1]`.
    row.clear();
    row.resize(bodies + 1, 0);
    for &x in old_i {
        row[x as usize + 1] += 1;
    }
    for x in 0..bodies {
        row[x + 1] += row[x];
    }
    history.clear();
    for (&a, &b) in ids.0.iter().zip(ids.1) {
        let (x, y) = (origin[a as usize], origin[b as usize]);
        let (lo, hi) = (x.min(y) as usize, x.max(y));
        let h = match row.get(lo..lo + 2) {
            Some(&[start, end]) => {
                let run = start as usize..end as usize;
                old_j[run.clone()]
                    .iter()
                    .position(|&j| j == hi)
                    .map_or_else(ContactHistory::default, |k| old.get(run.start + k))
            }
            _ => ContactHistory::default(),
        };
        history.push(carried(h, x > y));
    }
}

/// As [`carry_moved_pairs`], for wall candidates (wall, particle), wall-major: each wall's
/// old run is spread into a table by old body index while the new run reads it.
fn carry_moved_walls(
    history: &mut HistoryArrays,
    (walls, bodies): (&[u32], &[u32]),
    (old_walls, old_bodies): (&[u32], &[u32]),
    old: &HistoryArrays,
    (origin, slot): (&[u32], &mut Vec<u32>),
) {
    let size = old_bodies.iter().max().map_or(0, |&x| x as usize + 1);
    slot.clear();
    slot.resize(size, NO_SOURCE);
    let mut current: Option<(u32, std::ops::Range<usize>)> = None;
    history.clear();
    for (&w, &a) in walls.iter().zip(bodies) {
        if current.as_ref().is_none_or(|(v, _)| *v != w) {
            if let Some((_, run)) = current.take() {
                for &x in &old_bodies[run] {
                    slot[x as usize] = NO_SOURCE;
                }
            }
            let run = old_walls.partition_point(|&v| v < w)..old_walls.partition_point(|&v| v <= w);
            for (k, &x) in old_bodies[run.clone()].iter().enumerate() {
                slot[x as usize] = (run.start + k) as u32;
            }
            current = Some((w, run));
        }
        let h = match slot.get(origin[a as usize] as usize) {
            Some(&k) if k != NO_SOURCE => old.get(k as usize),
            _ => ContactHistory::default(),
        };
        history.push(carried(h, false));
    }
}

/// For each entry of the list `new`, sorted by its two columns, the index of the same entry
/// in the list `old`, sorted the same way, or [`NO_SOURCE`]: one merge.
///
/// Without a branch on the comparisons: each round advances the new cursor, the old one,
/// or both on a match, and writes the new entry's source, which a later round overwrites
/// while the old cursor is still behind. The lists change in a scattered few entries
/// between builds, so a branch on each comparison was mispredicted at every change.
fn matching((a, b): (&[u32], &[u32]), (oa, ob): (&[u32], &[u32]), source: &mut Vec<u32>) {
    let key = |x: u32, y: u32| (u64::from(x) << 32) | u64::from(y);
    let (new_len, old_len) = (a.len().min(b.len()), oa.len().min(ob.len()));
    source.clear();
    source.resize(new_len, NO_SOURCE);
    let (mut k, mut c) = (0, 0);
    while k < new_len && c < old_len {
        let (here, there) = (key(a[k], b[k]), key(oa[c], ob[c]));
        source[k] = if here == there { c as u32 } else { NO_SOURCE };
        k += usize::from(here <= there);
        c += usize::from(there <= here);
    }
}

/// History of j relative to i is minus that of i relative to j (ξ and the rolling torque on i).
fn negate(h: ContactHistory) -> ContactHistory {
    ContactHistory {
        tangential: -h.tangential,
        rolling: -h.rolling,
    }
}

/// The candidate pairs of the bodies binned in `grid`: every pair (i, j), i < j, closer
/// than R_i + R_j + `skin` [m], into `i` and `j`, sorted by i and then j.
///
/// Each unordered pair of cells is visited once (a cell with itself, and with the 13 of
/// its 26 neighbours that come after it in the grid's order: the next cell of its row, and
/// the three-cell runs of the rows after its own), so each pair of bodies is tested once,
/// from the cell-ordered copies of the positions and radii, which the runs read
/// contiguously. Until the thirtieth session every body looked at all 27 cells around it
/// and kept the partners of higher index: twice the tests, each through an index.
///
/// The test itself is that of any order of the two bodies: (R_a + R_b) + skin and the
/// squared components of x_b − x_a do not depend on which comes first, so the list is the
/// one the per-body search gave, bit for bit. The pairs come out by cell and are put in
/// (i, j) order by counting on i, then a few insertion steps within each i.
fn pair_candidates(
    grid: &CellGrid,
    (pos, rad): (&[DVec3], &[f64]),
    skin: f64,
    (i_out, j_out): (&mut Vec<u32>, &mut Vec<u32>),
    scratch: &mut ListScratch,
) {
    let n = pos.len();
    let sorted = &grid.sorted[..n];
    let start = &grid.start;
    // Positions and radii in the grid's order.
    let body = |k: usize| {
        let b = sorted[k] as usize;
        (pos[b], rad[b])
    };
    let ListScratch {
        cells,
        found,
        first,
        fill,
    } = scratch;
    cells.clear();
    cells.extend((0..n).map(body));
    let cells = &cells[..];
    let [nx, ny, nz] = grid.dims;
    let mut count = 0;
    // The bodies of slots `a` (one body) against the slots of `run`, appending those in
    // reach as (min, max) index keys, without a branch on the outcome.
    let test = |a: usize, run: std::ops::Range<usize>, found: &mut [u64], mut count: usize| {
        let (xa, ra) = cells[a];
        let ia = u64::from(sorted[a]);
        for (&(xb, rb), &ib) in cells[run.clone()].iter().zip(&sorted[run]) {
            let cut = ra + rb + skin;
            let d2 = (xb - xa).length_squared();
            let ib = u64::from(ib);
            found[count] = (ia.min(ib) << 32) | ia.max(ib);
            count += usize::from(d2 < cut * cut);
        }
        count
    };
    // The slots of cells x − 1 ..= x + 1 of row (y, z), clipped to the grid.
    let run = |x: usize, y: usize, z: usize| {
        let row = (z * ny + y) * nx;
        start[row + x.saturating_sub(1)] as usize..start[row + (x + 1).min(nx - 1) + 1] as usize
    };
    for z in 0..nz {
        for y in 0..ny {
            let row = (z * ny + y) * nx;
            for x in 0..nx {
                let own = start[row + x] as usize..start[row + x + 1] as usize;
                if own.is_empty() {
                    continue;
                }
                // The rows after this one among its neighbours: (y + 1, z), and
                // (y − 1 ..= y + 1, z + 1), clipped to the grid.
                let mut later: [std::ops::Range<usize>; 4] = Default::default();
                let mut rows = 0;
                if y + 1 < ny {
                    later[rows] = run(x, y + 1, z);
                    rows += 1;
                }
                if z + 1 < nz {
                    for yy in y.saturating_sub(1)..=(y + 1).min(ny - 1) {
                        later[rows] = run(x, yy, z + 1);
                        rows += 1;
                    }
                }
                let later = &later[..rows];
                // This cell's later bodies and the next cell of the row.
                let next_end = start[row + (x + 2).min(nx)] as usize;
                let reach: usize =
                    next_end - own.start + later.iter().map(ExactSizeIterator::len).sum::<usize>();
                if found.len() < count + own.len() * reach {
                    found.resize(2 * (count + own.len() * reach), 0);
                }
                for a in own {
                    count = test(a, a + 1..next_end, found, count);
                    for r in later {
                        count = test(a, r.clone(), found, count);
                    }
                }
            }
        }
    }
    let found = &found[..count];

    // By i, counting; then j ascending within each i.
    first.clear();
    first.resize(n + 1, 0);
    for &key in found {
        first[(key >> 32) as usize + 1] += 1;
    }
    for i in 0..n {
        first[i + 1] += first[i];
    }
    i_out.clear();
    j_out.clear();
    j_out.resize(count, 0);
    fill.clear();
    fill.extend_from_slice(first);
    for &key in found {
        let slot = &mut fill[(key >> 32) as usize];
        j_out[*slot as usize] = key as u32;
        *slot += 1;
    }
    for i in 0..n {
        let row = first[i] as usize..first[i + 1] as usize;
        sort_small(&mut j_out[row.clone()]);
        i_out.extend(std::iter::repeat_n(i as u32, row.len()));
    }
}

/// Builds the candidate lists from a binned grid.
///
/// `carry` says how the bodies' indices relate to those of the previous lists
/// `old_pairs`/`old_walls`, whose histories the new lists take over ([`Carry`]).
#[allow(clippy::too_many_arguments)]
pub(crate) fn build_lists(
    grid: &CellGrid,
    particles: &ParticleSet,
    walls: &[Option<Wall>],
    skin: f64,
    old_pairs: &PairList,
    old_walls: &WallPairList,
    carry: Carry<'_>,
    (pairs, wall_pairs): (&mut PairList, &mut WallPairList),
    scratch: &mut ListScratch,
) {
    let pos = &particles.position;
    let rad = &particles.radius;
    let n = pos.len();
    // The histories are written whole after the candidates: where the bodies kept their
    // indices by one merge with the old list, otherwise through the map to the old bodies.
    pair_candidates(
        grid,
        (&pos[..n], &rad[..n]),
        skin,
        (&mut pairs.i, &mut pairs.j),
        scratch,
    );
    let (ids, old_ids) = (
        (&pairs.i[..], &pairs.j[..]),
        (&old_pairs.i[..], &old_pairs.j[..]),
    );
    let old = &old_pairs.history;
    match carry {
        Carry::Same => {
            matching(ids, old_ids, &mut scratch.first);
            pairs.history.carry_from(old, &scratch.first);
        }
        Carry::Moved(origin) => carry_moved_pairs(
            &mut pairs.history,
            ids,
            old_ids,
            old,
            (origin, &mut scratch.first),
        ),
    }

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
    let ids = (&wall_pairs.wall[..], &wall_pairs.particle[..]);
    let old_ids = (&old_walls.wall[..], &old_walls.particle[..]);
    let old = &old_walls.history;
    match carry {
        Carry::Same => {
            matching(ids, old_ids, &mut scratch.first);
            wall_pairs.history.carry_from(old, &scratch.first);
        }
        Carry::Moved(origin) => carry_moved_walls(
            &mut wall_pairs.history,
            ids,
            old_ids,
            old,
            (origin, &mut scratch.first),
        ),
    }
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
            Carry::Same,
            (&mut pairs, &mut walls),
            &mut ListScratch::default(),
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
                Carry::Same,
                (&mut p, &mut w),
                &mut ListScratch::default(),
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
                Carry::Same,
                (&mut p, &mut w),
                &mut ListScratch::default(),
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
    #[test]
    fn histories_follow_their_bodies_when_indices_move() {
        // After a re-sort and a removal (new body k was body origin[k]), each new pair's and
        // wall candidate's history must be the one its two bodies had, keyed here by the
        // bodies' tags in a map: negated when the pair's order of bodies turned round, zero
        // (+0.0) when absent, not live, or zero with a negative sign. Compared bit for bit,
        // so that a lost sign of zero fails too. The reference is a map by tag, the
        // mechanism the engine used before (thirtieth session), and it checks every entry.
        use crate::material::{Interaction, Material, WallMaterial};
        use std::collections::HashMap;
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(30);
        let mut set = ParticleSet::default();
        for _ in 0..400 {
            let p = DVec3::new(
                rng.gen::<f64>(),
                0.011 + 0.002 * rng.gen::<f64>(),
                rng.gen::<f64>(),
            ) * DVec3::new(0.2, 1.0, 0.2);
            let init =
                crate::particles::ParticleInit::at_rest(p, 0.01, crate::particles::MaterialId(0));
            set.push(&init, 1000.0);
        }
        let m = WallMaterial::Elastic(Material::fan2023());
        let i = Interaction::fan2023();
        let walls: Vec<Option<Wall>> = vec![
            Some(Wall::plane(DVec3::ZERO, DVec3::Y, m, i).unwrap()),
            None,
            Some(Wall::plane(DVec3::new(0.0, 0.025, 0.0), -DVec3::Y, m, i).unwrap()),
            Some(Wall::plane(DVec3::ZERO, DVec3::X, m, i).unwrap()),
        ];
        let skin = 0.002;
        let build = |set: &ParticleSet, old: (&PairList, &WallPairList), carry: Carry<'_>| {
            let grid = CellGrid::build(&set.position, 0.02 + skin);
            let (mut p, mut w) = (PairList::default(), WallPairList::default());
            let mut scratch = ListScratch::default();
            let lists = (&mut p, &mut w);
            build_lists(
                &grid,
                set,
                &walls,
                skin,
                old.0,
                old.1,
                carry,
                lists,
                &mut scratch,
            );
            (p, w)
        };
        let none = (&PairList::default(), &WallPairList::default());
        let (mut pairs, mut wall_pairs) = build(&set, none, Carry::Same);
        // Histories of every kind: ordinary, not live, zero with negative signs, zero.
        let mut fill = |h: &mut HistoryArrays| {
            for k in 0..h.len() {
                let v = DVec3::new(rng.gen(), rng.gen(), rng.gen()) - 0.5;
                (h.tangential[k], h.rolling[k]) = match k % 5 {
                    0 => (DVec3::new(-0.0, 0.0, -0.0), DVec3::splat(-0.0)),
                    1 => (DVec3::ZERO, DVec3::ZERO),
                    _ => (v, v * 0.25),
                };
                h.live[k] = if k % 7 == 3 { 0 } else { crate::history::LIVE };
            }
        };
        fill(&mut pairs.history);
        fill(&mut wall_pairs.history);
        let tag = set.tag.clone();
        let old_pairs: HashMap<_, _> = (0..pairs.len())
            .map(|k| {
                (
                    (tag[pairs.i[k] as usize], tag[pairs.j[k] as usize]),
                    pairs.history.get(k),
                )
            })
            .collect();
        let old_walls: HashMap<_, _> = (0..wall_pairs.particle.len())
            .map(|k| {
                let key = (wall_pairs.wall[k], tag[wall_pairs.particle[k] as usize]);
                (key, wall_pairs.history.get(k))
            })
            .collect();

        // Remove one body in eight, shuffle the rest, and move them a little.
        let keep: Vec<bool> = (0..set.len()).map(|k| k % 8 != 5).collect();
        let kept: Vec<u32> = (0..set.len() as u32)
            .filter(|&k| keep[k as usize])
            .collect();
        set.retain_mask(&keep);
        let mut order: Vec<u32> = (0..set.len() as u32).collect();
        for k in (1..order.len()).rev() {
            order.swap(k, rng.gen_range(0..=k));
        }
        set.permute(&order);
        let origin: Vec<u32> = order.iter().map(|&k| kept[k as usize]).collect();
        for x in &mut set.position {
            *x += (DVec3::new(rng.gen(), 0.0, rng.gen()) - 0.5) * 0.002;
        }
        let (new_pairs, new_walls) = build(&set, (&pairs, &wall_pairs), Carry::Moved(&origin));

        let bits = |h: ContactHistory| {
            let v = |x: DVec3| x.to_array().map(f64::to_bits);
            (v(h.tangential), v(h.rolling))
        };
        let expect = |h: Option<&ContactHistory>, flip: bool| match h {
            Some(h) if !h.is_empty() => {
                if flip {
                    negate(*h)
                } else {
                    *h
                }
            }
            _ => ContactHistory::default(),
        };
        let (mut carried, mut flipped, mut fresh) = (0, 0, 0);
        let tag = &set.tag;
        for k in 0..new_pairs.len() {
            let (a, b) = (tag[new_pairs.i[k] as usize], tag[new_pairs.j[k] as usize]);
            let want = match (old_pairs.get(&(a, b)), old_pairs.get(&(b, a))) {
                (Some(h), _) => expect(Some(h), false),
                (None, Some(h)) => {
                    flipped += usize::from(!h.is_empty());
                    expect(Some(h), true)
                }
                (None, None) => {
                    fresh += 1;
                    ContactHistory::default()
                }
            };
            carried += usize::from(!want.is_empty());
            assert_eq!(bits(new_pairs.history.get(k)), bits(want), "pair {k}");
            assert_eq!(new_pairs.history.live[k], crate::history::LIVE);
        }
        let mut carried_walls = 0;
        for k in 0..new_walls.particle.len() {
            let key = (new_walls.wall[k], tag[new_walls.particle[k] as usize]);
            let want = expect(old_walls.get(&key), false);
            carried_walls += usize::from(!want.is_empty());
            assert_eq!(
                bits(new_walls.history.get(k)),
                bits(want),
                "wall candidate {k}"
            );
        }
        // The cases must all occur, or the test would pass on a carry that drops them.
        assert!(
            carried > 100 && flipped > 20 && fresh > 10,
            "{carried} {flipped} {fresh}"
        );
        assert!(carried_walls > 30, "{carried_walls}");
    }
}

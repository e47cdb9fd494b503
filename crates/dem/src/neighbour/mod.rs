//! Neighbour search: a cell list feeding a Verlet list with a skin (docs/physics.md §6.2).
//!
//! Candidate pairs are all pairs closer than R_i + R_j + skin, and wall candidates all bodies
//! closer than R_i + skin to a wall. The lists are rebuilt only when the bodies' motion since
//! the last build could have closed one of those gaps (`Simulation::lists_may_miss`: the
//! bodies' relative displacements against the skin for pairs, their own against it for
//! walls), so no contact can be missed in between. Bodies whose radii lie within a factor
//! 2.5 are binned in one grid sized by the largest; wider size distributions in a grid per size
//! class ([`SizeClasses`]), which gives the same list with far fewer tests. Contact history
//! lives in arrays parallel to the pair list and is carried over every rebuild, by index when
//! particles kept their indices and through the map from new to old indices otherwise
//! ([`Carry`]).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::contact::ContactHistory;
use crate::history::{HistoryArrays, SurfaceSlot, NO_SOURCE};
use crate::particles::ParticleSet;
use crate::wall::Wall;

mod carry;
mod class_pairs;
mod grid;
mod pairs;
mod size_classes;
#[cfg(test)]
mod tests;
mod walls;

use carry::*;
use class_pairs::*;
pub use grid::CellGrid;
use pairs::*;
pub(crate) use size_classes::SizeClasses;
use size_classes::*;
use walls::*;

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
    /// The remembered contacts of each candidate of a curved, meshed or spinning wall
    /// (`forces::surfaces`), index-aligned with the list; empty while there is no such wall.
    pub(crate) surfaces: Vec<SurfaceSlot>,
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

    /// The candidates of every wall but `wall`: what a wall put in another's place
    /// ([`crate::Simulation::replace_wall`]) starts from, so that the next build finds its
    /// candidates without a history to carry. The others keep theirs, in the same order.
    pub(crate) fn without_wall(self, wall: u32) -> Self {
        if !self.wall.contains(&wall) {
            return self;
        }
        let keep: Vec<usize> = (0..self.wall.len())
            .filter(|&k| self.wall[k] != wall)
            .collect();
        self.permuted(&keep)
    }

    /// The candidates in the order `order` (indices into this list) gives.
    fn permuted(&self, order: &[usize]) -> Self {
        Self {
            particle: order.iter().map(|&k| self.particle[k]).collect(),
            wall: order.iter().map(|&k| self.wall[k]).collect(),
            history: order.iter().map(|&k| self.history.get(k)).collect(),
            surfaces: order
                .iter()
                .filter_map(|&k| self.surfaces.get(k).cloned())
                .collect(),
        }
    }
}

impl PairList {
    /// Number of candidate pairs.
    pub fn len(&self) -> usize {
        self.i.len()
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
/// the builds allocate nothing once these have grown: allocated afresh at every build,
/// arrays of their sizes would go back to the allocator, some of them to the system, to be
/// faulted in again at the next build.
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

/// Where the candidate search finds the bodies binned: the two give the same list.
#[derive(Debug, Clone, Copy)]
pub(crate) enum PairSearch<'a> {
    /// One grid with cells at least 2 R_max + skin wide, for radii within a factor
    /// [`size_classes::SPLIT_RATIO`] of each other.
    Cells(&'a CellGrid),
    /// A grid per size class, for wider size distributions.
    Classes(&'a SizeClasses),
}

/// Builds the candidate lists from the bodies binned for `search`.
///
/// `carry` says how the bodies' indices relate to those of the previous lists
/// `old_pairs`/`old_walls`, whose histories the new lists take over ([`Carry`]); the
/// remembered contacts of curved and meshed walls are moved out of `old_walls`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn build_lists(
    search: PairSearch<'_>,
    particles: &ParticleSet,
    walls: &[Option<Wall>],
    skin: f64,
    old_pairs: &PairList,
    old_walls: &mut WallPairList,
    carry: Carry<'_>,
    (pairs, wall_pairs): (&mut PairList, &mut WallPairList),
    scratch: &mut ListScratch,
) {
    let pos = &particles.position;
    let rad = &particles.radius;
    let n = pos.len();
    // The histories are written whole after the candidates: where the bodies kept their
    // indices by one merge with the old list, otherwise through the map to the old bodies.
    let ids = (&mut pairs.i, &mut pairs.j);
    match search {
        PairSearch::Cells(grid) => {
            pair_candidates(grid, (&pos[..n], &rad[..n]), skin, ids, scratch)
        }
        PairSearch::Classes(classes) => class_pair_candidates(classes, n, skin, ids, scratch),
    }
    // A scan of 4 bytes a body, against the search's tens of candidates a body.
    if particles
        .clump
        .iter()
        .any(|&c| c != crate::particles::NO_CLUMP)
    {
        drop_clump_pairs(&particles.clump, (&mut pairs.i, &mut pairs.j));
    }
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
        wall_candidates(wall, (&pos[..n], &rad[..n]), skin, &mut wall_pairs.particle);
        let added = wall_pairs.particle.len() - before;
        wall_pairs.wall.extend(std::iter::repeat_n(w as u32, added));
    }
    let ids = (&wall_pairs.wall[..], &wall_pairs.particle[..]);
    let old_ids = (&old_walls.wall[..], &old_walls.particle[..]);
    let surfaces = crate::wall::any_resolved_one_by_one(walls);
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
            surfaces.then_some(&mut scratch.fill),
        ),
    }
    // The remembered contacts of curved and meshed walls follow their candidates: from the
    // old entry each new one continues (`scratch.first` or `scratch.fill` above).
    wall_pairs.surfaces.clear();
    if surfaces {
        let source = match carry {
            Carry::Same => &scratch.first,
            Carry::Moved(_) => &scratch.fill,
        };
        // Each old candidate is the source of one new one at most: moved, not copied.
        let old = &mut old_walls.surfaces;
        wall_pairs.surfaces.extend(source.iter().map(|&c| {
            old.get_mut(c as usize)
                .map(std::mem::take)
                .unwrap_or_default()
        }));
    }
}

/// Drops the candidate pairs of two members of one clump (`clump`: each particle's clump,
/// [`crate::particles::NO_CLUMP`] for none): a rigid body's members never touch each other
/// (docs/physics.md §11.4). Keeps the others in order.
fn drop_clump_pairs(clump: &[u32], (pi, pj): (&mut Vec<u32>, &mut Vec<u32>)) {
    let mut kept = 0;
    for k in 0..pi.len() {
        let (i, j) = (pi[k], pj[k]);
        let c = clump[i as usize];
        if c == crate::particles::NO_CLUMP || c != clump[j as usize] {
            pi[kept] = i;
            pj[kept] = j;
            kept += 1;
        }
    }
    pi.truncate(kept);
    pj.truncate(kept);
}

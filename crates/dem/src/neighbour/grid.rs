//! The cell grid the candidate search bins the bodies in: cells at least as wide as the
//! interaction cutoff, so that a body's partners lie in its own cell and the 26 around it.

use super::*;

/// A uniform grid of cells at least as wide as the interaction cutoff.
#[derive(Debug, Clone, Default)]
pub struct CellGrid {
    /// Lowest corner of the grid: the smallest coordinates of the bodies [m].
    pub(super) origin: DVec3,
    /// One over the cell width [1/m].
    pub(super) inv_cell: f64,
    pub(super) dims: [usize; 3],
    /// Cell of each particle.
    cell_of: Vec<u32>,
    /// Particles sorted by cell (stable).
    pub(super) sorted: Vec<u32>,
    /// `sorted[start[c]..start[c+1]]` are the particles of cell c.
    pub(super) start: Vec<u32>,
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

    pub(super) fn coords(&self, p: DVec3) -> [usize; 3] {
        let c = ((p - self.origin) * self.inv_cell).floor();
        [
            (c.x.max(0.0) as usize).min(self.dims[0] - 1),
            (c.y.max(0.0) as usize).min(self.dims[1] - 1),
            (c.z.max(0.0) as usize).min(self.dims[2] - 1),
        ]
    }

    pub(super) fn cell_index(&self, p: DVec3) -> usize {
        let [x, y, z] = self.coords(p);
        (z * self.dims[1] + y) * self.dims[0] + x
    }

    /// Particle indices in cell order: sorting particles by it improves memory locality.
    pub fn cell_order(&self) -> &[u32] {
        &self.sorted
    }
}

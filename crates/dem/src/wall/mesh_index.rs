//! A uniform grid over a mesh's triangles, so that the triangles near a sphere are found
//! without looking at the others: the cost of a query depends on the triangles within reach,
//! not on the size of the mesh (docs/physics.md §5.3).

use glam::DVec3;

/// Cells a mesh may have per triangle: a grid finer than this is coarsened, so that a mesh
/// of few large triangles in a large box does not allocate a huge, nearly empty grid.
const CELLS_PER_TRIANGLE: f64 = 4.0;

/// Triangles binned by the cells their bounding boxes overlap.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct TriangleGrid {
    /// Corner of cell (0, 0, 0) [m].
    origin: DVec3,
    /// Edge of a cubic cell [m].
    cell: f64,
    /// Cells along x, y and z.
    dims: [usize; 3],
    /// Triangles of cell c: `triangles[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    triangles: Vec<u32>,
    /// Each triangle's range of cells, lowest and highest index along each axis: a query
    /// visits a triangle only in the first cell it shares with the query's box, so that
    /// each triangle is tested once without a mark per triangle.
    range: Vec<[[u32; 3]; 2]>,
    /// Each triangle's axis-aligned bounds [m], for the exact box test of a query.
    bounds: Vec<(DVec3, DVec3)>,
}

impl TriangleGrid {
    /// The grid over triangles with the axis-aligned bounds `bounds` (each triangle's lowest
    /// and highest corner) inside the box `lo..hi`, with cells about as wide as the median
    /// triangle's larger extent.
    pub(super) fn new(bounds: &[(DVec3, DVec3)], (lo, hi): (DVec3, DVec3)) -> Self {
        let n = bounds.len();
        let mut sizes: Vec<f64> = bounds
            .iter()
            .map(|(a, b)| (*b - *a).max_element())
            .collect();
        sizes.sort_by(f64::total_cmp);
        let span = (hi - lo).max(DVec3::splat(1e-12));
        let mut cell = sizes
            .get(n / 2)
            .copied()
            .unwrap_or(1.0)
            .max(span.max_element() * 1e-6);
        let cells = |c: f64| ((span / c).floor() + DVec3::ONE).to_array();
        while cells(cell).iter().product::<f64>() > CELLS_PER_TRIANGLE * n as f64 + 64.0 {
            cell *= 1.25;
        }
        let dims = cells(cell).map(|d| d as usize);
        let at = |x: DVec3| {
            let c = ((x - lo) / cell).floor();
            [0, 1, 2].map(|a| (c[a].max(0.0) as usize).min(dims[a] - 1) as u32)
        };
        let range: Vec<[[u32; 3]; 2]> = bounds.iter().map(|(a, b)| [at(*a), at(*b)]).collect();
        let index =
            |[i, j, k]: [u32; 3]| (i as usize) + dims[0] * (j as usize + dims[1] * k as usize);
        let total = dims.iter().product::<usize>();
        let mut start = vec![0u32; total + 1];
        let each = |r: &[[u32; 3]; 2], f: &mut dyn FnMut(usize)| {
            for k in r[0][2]..=r[1][2] {
                for j in r[0][1]..=r[1][1] {
                    for i in r[0][0]..=r[1][0] {
                        f(index([i, j, k]));
                    }
                }
            }
        };
        for r in &range {
            each(r, &mut |c| start[c + 1] += 1);
        }
        for c in 0..total {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut triangles = vec![0u32; start[total] as usize];
        for (t, r) in range.iter().enumerate() {
            each(r, &mut |c| {
                triangles[fill[c] as usize] = t as u32;
                fill[c] += 1;
            });
        }
        Self {
            origin: lo,
            cell,
            dims,
            start,
            triangles,
            range,
            bounds: bounds.to_vec(),
        }
    }

    /// Calls `visit(t)` once for every triangle whose bounding box comes closer than
    /// `reach` [m] to `x`, until a call returns true.
    #[inline]
    pub(super) fn near(&self, x: DVec3, reach: f64, mut visit: impl FnMut(u32) -> bool) {
        let dims = self.dims;
        let mut lo = [0u32; 3];
        let mut hi = [0u32; 3];
        for a in 0..3 {
            let first = ((x[a] - reach - self.origin[a]) / self.cell).floor();
            let last = ((x[a] + reach - self.origin[a]) / self.cell).floor();
            // `!(≥)` also leaves on NaN.
            if !(last >= 0.0) || !(first < dims[a] as f64) {
                return;
            }
            lo[a] = first.max(0.0) as u32;
            hi[a] = (last as usize).min(dims[a] - 1) as u32;
        }
        let reach2 = reach * reach;
        for k in lo[2]..=hi[2] {
            for j in lo[1]..=hi[1] {
                for i in lo[0]..=hi[0] {
                    let c = i as usize + dims[0] * (j as usize + dims[1] * k as usize);
                    let here = [i, j, k];
                    for &t in &self.triangles[self.start[c] as usize..self.start[c + 1] as usize] {
                        // Visited only in the first cell it shares with the query's box.
                        let r = &self.range[t as usize];
                        if !(0..3).all(|a| here[a] == r[0][a].max(lo[a])) {
                            continue;
                        }
                        let (a, b) = self.bounds[t as usize];
                        let gap = (a - x).max(x - b).max(DVec3::ZERO);
                        if gap.length_squared() < reach2 && visit(t) {
                            return;
                        }
                    }
                }
            }
        }
    }
}

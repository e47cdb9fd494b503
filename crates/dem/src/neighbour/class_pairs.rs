//! The particle–particle candidates over size classes ([`SizeClasses`]): pairs within a
//! class from the class's own grid, pairs across classes from the grid of the smaller
//! class, searched by each body of the larger class over the cells its reach touches.

use super::*;

/// Margin added to a body's reach in cell units when choosing the cells to search: covers
/// the rounding of cell coordinates (about 1e-13 of a cell) many times over, at the price
/// of a row now and then that holds no partner.
const REACH_MARGIN_CELLS: f64 = 1e-6;

/// The candidate pairs of the `n` bodies binned in `classes`: every pair (i, j), i < j,
/// closer than R_i + R_j + `skin` [m], into `i` and `j`, sorted by i and then j: the same
/// list, bit for bit, as [`pair_candidates`] gives from one grid, since each pair is tested
/// once with the same expression and the order is then fixed by the indices alone.
///
/// Each unordered pair of bodies is tested from exactly one side: within a class by the
/// half stencil of the class's grid ([`same_grid_pairs`]), across two classes by the body
/// of the larger class ([`cross_class_pairs`]). A small body thus tests partners no larger
/// than its own class within cells sized for its class, and only the few large bodies
/// search wide, over the small bodies in their reach.
pub(super) fn class_pair_candidates(
    classes: &SizeClasses,
    n: usize,
    skin: f64,
    (i_out, j_out): (&mut Vec<u32>, &mut Vec<u32>),
    scratch: &mut ListScratch,
) {
    let ListScratch {
        found, first, fill, ..
    } = scratch;
    let classes = classes.classes();
    let mut count = 0;
    for (k, class) in classes.iter().enumerate() {
        count = same_grid_pairs(&class.grid, (&class.cells, &class.ids), skin, found, count);
        for smaller in &classes[..k] {
            count = cross_class_pairs(class, smaller, skin, found, count);
        }
    }
    into_pair_order(&found[..count], n, (first, fill), (i_out, j_out));
}

/// Appends to `found` (from slot `count`) every pair of a body of `large` and a body of
/// `small` closer than R_a + R_b + `skin` [m], as (min, max) index keys, and returns the new
/// count.
///
/// A body of `large` with radius R_a reaches c = R_a + R_max(small) + skin. In the cell
/// units of `small`'s grid it searches the rows of cells whose distance across (y, z) from
/// it is below c, and in each row the run of cells within √(c² − d_y² − d_z²) along x: the
/// cells that meet the sphere of radius c about it, read as contiguous runs of slots.
pub(super) fn cross_class_pairs(
    large: &SizeClass,
    small: &SizeClass,
    skin: f64,
    found: &mut Vec<u64>,
    mut count: usize,
) -> usize {
    let grid = &small.grid;
    let (start, cells, ids) = (&grid.start, &small.cells, &small.ids);
    let [nx, ny, nz] = grid.dims.map(|d| d as i64);
    let inv = grid.inv_cell;
    // Distance in cells along one axis from coordinate u to the cells [c, c + 1).
    let gap = |u: f64, c: i64| (c as f64 - u).max(u - (c + 1) as f64).max(0.0);
    // The cells c with floor(u − h) ≤ c ≤ floor(u + h), clipped to 0..n.
    let span = |u: f64, h: f64, n: i64| {
        let lo = ((u - h).floor().max(0.0) as i64).min(n);
        let hi = ((u + h).floor().min((n - 1) as f64) as i64).max(-1);
        lo..hi + 1
    };
    for (&(xa, ra), &ia) in large.cells.iter().zip(&large.ids) {
        let reach = (ra + small.r_max + skin) * inv + REACH_MARGIN_CELLS;
        let u = (xa - grid.origin) * inv;
        let ia = u64::from(ia);
        for z in span(u.z, reach, nz) {
            let dz = gap(u.z, z);
            for y in span(u.y, reach, ny) {
                let dy = gap(u.y, y);
                let h2 = reach * reach - dy * dy - dz * dz;
                if h2 < 0.0 {
                    continue;
                }
                let xs = span(u.x, h2.sqrt(), nx);
                if xs.is_empty() {
                    continue;
                }
                let row = ((z * ny + y) * nx) as usize;
                let run =
                    start[row + xs.start as usize] as usize..start[row + xs.end as usize] as usize;
                if found.len() < count + run.len() {
                    found.resize(2 * (count + run.len()), 0);
                }
                for (&(xb, rb), &ib) in cells[run.clone()].iter().zip(&ids[run]) {
                    let cut = ra + rb + skin;
                    let d2 = (xb - xa).length_squared();
                    let ib = u64::from(ib);
                    found[count] = (ia.min(ib) << 32) | ia.max(ib);
                    count += usize::from(d2 < cut * cut);
                }
            }
        }
    }
    count
}

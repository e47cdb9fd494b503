//! The particle–particle candidates: every pair closer than R_i + R_j + skin, found cell
//! pair by cell pair and put in (i, j) order.

use super::*;
use crate::capacity::reserve_total;

/// Sorts a few indices in place: insertion sort, as the lists of one particle's new
/// neighbours hold a handful.
#[inline]
pub(super) fn sort_small(v: &mut [u32]) {
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

/// Rows of candidates longer than this are sorted by the standard library's sort instead of
/// insertion: the rows of large bodies among small ones hold tens to hundreds of partners.
const INSERTION_SORT_MAX: usize = 32;

/// The candidate pairs of the bodies binned in `grid`: every pair (i, j), i < j, closer
/// than R_i + R_j + `skin` [m], into `i` and `j`, sorted by i and then j.
///
/// Each unordered pair of cells is visited once ([`same_grid_pairs`]), from the
/// cell-ordered copies of the positions and radii, and the pairs found are put in (i, j)
/// order ([`into_pair_order`]).
pub(super) fn pair_candidates(
    grid: &CellGrid,
    (pos, rad): (&[DVec3], &[f64]),
    skin: f64,
    (i_out, j_out): (&mut Vec<u32>, &mut Vec<u32>),
    scratch: &mut ListScratch,
) {
    let n = pos.len();
    let sorted = &grid.sorted[..n];
    let ListScratch {
        cells,
        found,
        first,
        fill,
    } = scratch;
    // Positions and radii in the grid's order.
    cells.clear();
    cells.extend(sorted.iter().map(|&b| (pos[b as usize], rad[b as usize])));
    let count = same_grid_pairs(grid, (&cells[..], sorted), skin, found, 0);
    into_pair_order(&found[..count], n, (first, fill), (i_out, j_out));
}

/// Appends to `found` (from slot `count`) the pairs of bodies binned in `grid` closer than
/// R_a + R_b + `skin` [m], as (min, max) index keys, and returns the new count. `cells`
/// holds the bodies' positions [m] and radii [m] in the grid's order and `ids` their indices;
/// the grid's cells must be at least as wide as the largest such cutoff among its bodies.
///
/// Each unordered pair of cells is visited once (a cell with itself, and with the 13 of
/// its 26 neighbours that come after it in the grid's order: the next cell of its row, and
/// the three-cell runs of the rows after its own), so each pair of bodies is tested once,
/// from the cell-ordered copies, which the runs read contiguously: half the tests of a
/// search in which every body looks at all 27 cells around it and keeps the partners of
/// higher index, and none through an index.
///
/// The test itself is that of any order of the two bodies: (R_a + R_b) + skin and the
/// squared components of x_b − x_a do not depend on which comes first, so the list is the
/// one the per-body search gave, bit for bit.
pub(super) fn same_grid_pairs(
    grid: &CellGrid,
    (cells, ids): (&[(DVec3, f64)], &[u32]),
    skin: f64,
    found: &mut Vec<u64>,
    mut count: usize,
) -> usize {
    let start = &grid.start;
    let [nx, ny, nz] = grid.dims;
    // The bodies of slots `a` (one body) against the slots of `run`, appending those in
    // reach as (min, max) index keys, without a branch on the outcome.
    let test = |a: usize, run: std::ops::Range<usize>, found: &mut [u64], mut count: usize| {
        let (xa, ra) = cells[a];
        let ia = u64::from(ids[a]);
        for (&(xb, rb), &ib) in cells[run.clone()].iter().zip(&ids[run]) {
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
    count
}

/// Writes the pairs `found`, (min, max) index keys of `n` bodies in any order, into `i_out`
/// and `j_out` sorted by i and then j: counting on i, then sorting each i's row of j.
/// `first` and `fill` are working arrays.
pub(super) fn into_pair_order(
    found: &[u64],
    n: usize,
    (first, fill): (&mut Vec<u32>, &mut Vec<u32>),
    (i_out, j_out): (&mut Vec<u32>, &mut Vec<u32>),
) {
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
    reserve_total(i_out, found.len());
    reserve_total(j_out, found.len());
    j_out.resize(found.len(), 0);
    fill.clear();
    fill.extend_from_slice(first);
    for &key in found {
        let slot = &mut fill[(key >> 32) as usize];
        j_out[*slot as usize] = key as u32;
        *slot += 1;
    }
    for i in 0..n {
        let row = first[i] as usize..first[i + 1] as usize;
        let js = &mut j_out[row.clone()];
        if js.len() > INSERTION_SORT_MAX {
            js.sort_unstable();
        } else {
            sort_small(js);
        }
        i_out.extend(std::iter::repeat_n(i as u32, row.len()));
    }
}

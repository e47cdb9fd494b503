//! Size classes for wide size distributions: the bodies split by radius into classes whose
//! radii lie within a factor [`CLASS_WIDTH`] of each other, each class binned in a grid of
//! its own with cells sized by its own largest radius (the idea of LAMMPS's "multi"
//! neighbour style). A single grid must be sized by the largest sphere, so that with radii
//! a factor 3 apart each small sphere would search some 16 times the volume it needs.

use super::*;

/// Largest over smallest radius that one class may span [-]. Classes start at the smallest
/// radius present and double: [R_min, 2 R_min), [2 R_min, 4 R_min), …
pub(crate) const CLASS_WIDTH: f64 = 2.0;

/// Relative padding of a class grid's cells beyond the cutoff 2 R_max + skin, so that two
/// bodies closer than the cutoff are never found two cells apart by the rounding of their
/// cell coordinates (about 1e-13 of a cell).
const CELL_PADDING: f64 = 1e-6;

/// The bodies of one size class, binned.
#[derive(Debug, Clone, Default)]
pub(crate) struct SizeClass {
    /// Largest radius in the class [m].
    pub(super) r_max: f64,
    /// The class's grid, over the class's bodies only (slot k is `members[k]`).
    pub(super) grid: CellGrid,
    /// Positions [m] and radii [m] in the grid's order.
    pub(super) cells: Vec<(DVec3, f64)>,
    /// Body indices in the grid's order.
    pub(super) ids: Vec<u32>,
    /// Body indices of the class in increasing order.
    members: Vec<u32>,
    /// Positions of the members [m], the grid's input.
    positions: Vec<DVec3>,
}

/// The bodies split into size classes, each binned in its own grid; reused from build to
/// build for its allocations.
#[derive(Debug, Clone, Default)]
pub(crate) struct SizeClasses {
    /// The non-empty classes, smallest radii first; only the first `used` are current.
    classes: Vec<SizeClass>,
    used: usize,
}

/// Largest over smallest radius from which the search by size class is used [-]. Measured
/// on settling 3D beds of two sizes in equal volumes (docs/performance.md, "Polydisperse
/// beds"): at 1:2 the list builds by class cost the same as one grid's, at 1:3 they took 0.6
/// of its time, at 1:4 0.35, at 1:10 0.15.
pub(crate) const SPLIT_RATIO: f64 = 2.5;

/// The smallest and largest of `rad` [m]; (∞, 0) for none.
fn radius_range(rad: &[f64]) -> (f64, f64) {
    rad.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &r| {
        (lo.min(r), hi.max(r))
    })
}

impl SizeClasses {
    /// Whether radii `rad` [m] spread widely enough for the search by size class to pay:
    /// R_max ≥ [`SPLIT_RATIO`] R_min. Narrower spreads are searched as fast by one grid.
    pub(crate) fn pays_for(rad: &[f64]) -> bool {
        let (r_min, r_max) = radius_range(rad);
        r_min > 0.0 && r_max >= SPLIT_RATIO * r_min
    }

    /// Splits the bodies at `pos` [m] with radii `rad` [m] into size classes and bins each
    /// class for a list build with `skin` [m]. Any radii may be split (one class where they
    /// lie within [`CLASS_WIDTH`]); [`SizeClasses::pays_for`] says when it is worth it.
    pub(crate) fn rebuild(&mut self, pos: &[DVec3], rad: &[f64], skin: f64) {
        let (r_min, r_max) = radius_range(rad);
        // `!(r_min > 0)` also keeps an empty set and NaN radii (refused on insertion) out of
        // the class arithmetic.
        if !(r_min > 0.0) {
            self.used = 0;
            return;
        }
        // Class k holds radii in [R_min W^k, R_min W^(k+1)); found by repeated products, so
        // that a radius on a class bound lands in the class the bound opens.
        let class_of = |r: f64| {
            let (mut k, mut bound) = (0, CLASS_WIDTH * r_min);
            while r >= bound {
                k += 1;
                bound *= CLASS_WIDTH;
            }
            k
        };
        let count = class_of(r_max) + 1;
        if self.classes.len() < count {
            self.classes.resize_with(count, SizeClass::default);
        }
        for class in &mut self.classes[..count] {
            class.members.clear();
            class.r_max = 0.0;
        }
        for (b, &r) in rad.iter().enumerate() {
            let class = &mut self.classes[class_of(r)];
            class.members.push(b as u32);
            class.r_max = class.r_max.max(r);
        }
        // Empty classes (radii with gaps between them) are dropped, the order kept.
        let mut used = 0;
        for k in 0..count {
            if !self.classes[k].members.is_empty() {
                self.classes.swap(used, k);
                used += 1;
            }
        }
        self.used = used;
        for class in &mut self.classes[..used] {
            class.bin(pos, rad, skin);
        }
    }

    /// The current classes, smallest radii first.
    pub(super) fn classes(&self) -> &[SizeClass] {
        &self.classes[..self.used]
    }
}

impl SizeClass {
    /// Bins the members in cells of width (2 R_max + skin)(1 + padding), and copies their
    /// positions, radii and indices in the grid's order.
    fn bin(&mut self, pos: &[DVec3], rad: &[f64], skin: f64) {
        self.positions.clear();
        self.positions
            .extend(self.members.iter().map(|&b| pos[b as usize]));
        let cell = (2.0 * self.r_max + skin) * (1.0 + CELL_PADDING);
        self.grid.rebuild(&self.positions, cell);
        let members = &self.members;
        self.ids.clear();
        self.ids
            .extend(self.grid.sorted.iter().map(|&k| members[k as usize]));
        self.cells.clear();
        self.cells
            .extend(self.ids.iter().map(|&b| (pos[b as usize], rad[b as usize])));
    }
}

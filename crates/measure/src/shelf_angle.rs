//! The angles of the material left on the two shelves of a draw-down box (docs/physics.md
//! §7.11): beside a slot D wide centred in a box W wide, the surface left on each shelf, the
//! highest particle top per bin of distance u from the slot's edge, in strips across the depth,
//! and in each strip the line h(u) = h₀ + u tan θ fitted to its slope (the bins between 20 %
//! and 80 % of the shelf's highest top, `FLANK_BAND`: the toe at the slot's edge and the
//! plateau of material that never moved are left out).
//!
//! Each side's angle is the mean over its strips; the shelf angle is the mean over every
//! strip of both sides, its error the standard error over them combined with the fits' own
//! errors (`surface_fit::mean_angle`).

use serde::{Deserialize, Serialize};

use super::error::MeasureError;
use super::surface_fit::{
    check_length, check_particles, fit_flank, mean_angle, top_surface, FlankFit, SurfaceBin,
};

/// Fewest bin widths across a strip of the depth: narrower strips would hold too few grains
/// per bin to show the surface.
pub const MIN_STRIP_BINS: f64 = 3.0;

/// Where the shelves lie and how their surface is binned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShelfBinning {
    /// Inner width W of the box along x [m], centred on x = 0.
    pub width: f64,
    /// Depth B of the box along y [m], centred on y = 0.
    pub depth: f64,
    /// Width D of the slot along x [m], centred on x = 0.
    pub slot_width: f64,
    /// Width of the bins along x [m] (one mean diameter).
    pub bin_width: f64,
}

impl ShelfBinning {
    /// Strips across the depth: as many as fit at least [`MIN_STRIP_BINS`] bin widths
    /// each, at least one.
    pub fn strips(&self) -> usize {
        ((self.depth / (MIN_STRIP_BINS * self.bin_width)).floor() as usize).max(1)
    }
}

/// One side of the slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Shelf {
    /// x < −D/2.
    Left,
    /// x > D/2.
    Right,
}

/// One strip of one shelf: its surface and the line fitted to it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShelfStrip {
    /// Which shelf.
    pub shelf: Shelf,
    /// The strip's index across the depth, from y = −B/2.
    pub strip: usize,
    /// The surface: the highest top per bin (`position` is the distance u from the slot's
    /// edge [m]).
    pub surface: Vec<SurfaceBin>,
    /// The line fitted to its slope; `None` with too few bins on it.
    pub fit: Option<FlankFit>,
}

/// The shelf angles of a drained draw-down box.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShelfAngles {
    /// The mean over every fitted strip of both shelves [°].
    pub angle_deg: f64,
    /// Its standard error [°].
    pub angle_error_deg: f64,
    /// The left shelf's angle, the mean over its strips [°].
    pub left_angle_deg: f64,
    /// The right shelf's angle, the mean over its strips [°].
    pub right_angle_deg: f64,
    /// Strips whose slope was fitted, of both shelves.
    pub fitted_strips: usize,
    /// Every strip of both shelves, fitted or not.
    pub strips: Vec<ShelfStrip>,
}

/// Measures the material left on the shelves by the particles at `positions` [m] of radii
/// `radii` [m]: those with their centres above the floor z = 0 and over a shelf.
pub fn shelf_angles(
    positions: &[[f64; 3]],
    radii: &[f64],
    binning: &ShelfBinning,
) -> Result<ShelfAngles, MeasureError> {
    check_particles(positions, radii)?;
    check_length("width", binning.width)?;
    check_length("depth", binning.depth)?;
    check_length("bin_width", binning.bin_width)?;
    if !(binning.slot_width >= 0.0 && binning.slot_width < binning.width) {
        return Err(MeasureError::InvalidParameter {
            name: "slot_width",
            value: binning.slot_width,
            reason: "must lie in [0, width)",
        });
    }
    let n = binning.strips();
    let half_slot = 0.5 * binning.slot_width;
    // (shelf, strip) → (u, top) of its grains.
    let mut tops: Vec<Vec<(f64, f64)>> = vec![Vec::new(); 2 * n];
    let mut heights = [f64::NAN; 2];
    for (p, &r) in positions.iter().zip(radii) {
        let (x, y, z) = (p[0], p[1], p[2]);
        if !(z >= 0.0) || x.abs() < half_slot {
            continue;
        }
        let side = usize::from(x > 0.0);
        let strip =
            (((y + 0.5 * binning.depth) / binning.depth * n as f64).floor() as usize).min(n - 1);
        let top = z + r;
        tops[side * n + strip].push((x.abs() - half_slot, top));
        if !(heights[side] >= top) {
            heights[side] = top;
        }
    }
    let strips: Vec<ShelfStrip> = tops
        .into_iter()
        .enumerate()
        .map(|(k, tops)| {
            let (side, strip) = (k / n, k % n);
            let surface = top_surface(tops.into_iter(), 0.0, binning.bin_width);
            let fit = fit_flank(&surface, heights[side], 1.0);
            ShelfStrip {
                shelf: if side == 0 { Shelf::Left } else { Shelf::Right },
                strip,
                surface,
                fit,
            }
        })
        .collect();
    let fits_of = |shelf: Option<Shelf>| -> Vec<FlankFit> {
        strips
            .iter()
            .filter(|s| shelf.is_none_or(|side| s.shelf == side))
            .filter_map(|s| s.fit)
            .collect()
    };
    let all = fits_of(None);
    let (angle_deg, angle_error_deg) = mean_angle(&all);
    Ok(ShelfAngles {
        angle_deg,
        angle_error_deg,
        left_angle_deg: mean_angle(&fits_of(Some(Shelf::Left))).0,
        right_angle_deg: mean_angle(&fits_of(Some(Shelf::Right))).0,
        fitted_strips: all.len(),
        strips,
    })
}

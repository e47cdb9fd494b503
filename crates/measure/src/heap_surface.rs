//! The angle of repose of a heap on a plate (the lifted-cylinder test, docs/physics.md §7.10):
//! the heap's free surface, the highest particle top per bin of radius about its axis in each
//! of several azimuthal sectors, and in each sector the line h(r) = h₀ − r tan θ fitted to its
//! flank (the bins between 20 % and 80 % of the heap's height, `FLANK_BAND`).
//!
//! The angle is the sectors' mean, its error the standard error over the sectors combined with
//! the fits' own errors (`surface_fit::mean_angle`). Fitting sector by sector, rather than
//! all the surface at once, makes a lopsided heap show as a larger error instead of a
//! confident mean.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use super::error::MeasureError;
use super::surface_fit::{
    check_length, check_particles, fit_flank, mean_angle, top_surface, FlankFit, SurfaceBin,
};

/// Azimuthal sectors the heap is cut into by default: 8 sectors of 45°, each wide enough at
/// the flank's middle (a few diameters of radius) to hold several grains per bin.
pub const HEAP_SECTORS: usize = 8;

/// How the heap's surface is binned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeapBinning {
    /// The heap's axis (x, y) [m].
    pub axis: [f64; 2],
    /// Width of the radial bins [m] (one mean diameter: each bin then holds a grain of the
    /// surface).
    pub bin_width: f64,
    /// Azimuthal sectors, ≥ 1.
    pub sectors: usize,
}

/// One sector's surface and fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HeapSector {
    /// The sector's index, counter-clockwise from the −x direction.
    pub sector: usize,
    /// The surface: the highest top per radial bin (`position` is the radius r [m]).
    pub surface: Vec<SurfaceBin>,
    /// The line fitted to its flank; `None` with too few bins on it.
    pub fit: Option<FlankFit>,
}

/// The heap's angle of repose and its shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HeapAngle {
    /// θ, the mean over the fitted sectors [°].
    pub angle_deg: f64,
    /// Its standard error [°] (the scatter over sectors and the fits' errors in quadrature).
    pub angle_error_deg: f64,
    /// The heap's height: its highest particle top above the plate [m].
    pub height: f64,
    /// Where the fitted flanks meet the plate, h₀/tan θ, averaged over the sectors whose line
    /// meets it within their grains (θ > 0 and no farther out than their outermost bin and
    /// two bin widths: the bin's half width and the staircase of a packing's surface) [m];
    /// NaN where none does: a flank flattened to a layer extrapolates its toe without bound.
    pub base_radius: f64,
    /// Sectors whose flank was fitted.
    pub fitted_sectors: usize,
    /// Every sector, fitted or not.
    pub sectors: Vec<HeapSector>,
}

/// Measures the heap formed by the particles at `positions` [m] of radii `radii` [m] on a
/// plate at z = 0: the grains whose centres lie above the plate (those falling past its edge
/// are not part of the heap).
pub fn heap_angle(
    positions: &[[f64; 3]],
    radii: &[f64],
    binning: &HeapBinning,
) -> Result<HeapAngle, MeasureError> {
    check_particles(positions, radii)?;
    check_length("bin_width", binning.bin_width)?;
    if binning.sectors == 0 {
        return Err(MeasureError::InvalidParameter {
            name: "sectors",
            value: 0.0,
            reason: "must be ≥ 1",
        });
    }
    let s = binning.sectors;
    let [cx, cy] = binning.axis;
    let mut by_sector: Vec<Vec<(f64, f64)>> = vec![Vec::new(); s];
    let mut height = f64::NAN;
    for (p, &r) in positions.iter().zip(radii) {
        if !(p[2] >= 0.0) {
            continue;
        }
        let (x, y) = (p[0] - cx, p[1] - cy);
        let phi = y.atan2(x) + PI;
        let k = ((phi / (2.0 * PI) * s as f64) as usize).min(s - 1);
        let top = p[2] + r;
        by_sector[k].push((x.hypot(y), top));
        if !(height >= top) {
            height = top;
        }
    }
    let sectors: Vec<HeapSector> = by_sector
        .into_iter()
        .enumerate()
        .map(|(sector, tops)| {
            let surface = top_surface(tops.into_iter(), 0.0, binning.bin_width);
            let fit = fit_flank(&surface, height, -1.0);
            HeapSector {
                sector,
                surface,
                fit,
            }
        })
        .collect();
    let fits: Vec<FlankFit> = sectors.iter().filter_map(|s| s.fit).collect();
    let (angle_deg, angle_error_deg) = mean_angle(&fits);
    let toes: Vec<f64> = sectors
        .iter()
        .filter_map(|s| {
            let f = s.fit?;
            let toe = f.intercept / f.angle_deg.to_radians().tan();
            let outermost = s.surface.last()?.position + 2.0 * binning.bin_width;
            (f.angle_deg > 0.0 && toe.is_finite() && toe <= outermost).then_some(toe)
        })
        .collect();
    let base_radius = if toes.is_empty() {
        f64::NAN
    } else {
        toes.iter().sum::<f64>() / toes.len() as f64
    };
    Ok(HeapAngle {
        angle_deg,
        angle_error_deg,
        height,
        base_radius,
        fitted_sectors: fits.len(),
        sectors,
    })
}

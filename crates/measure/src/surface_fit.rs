//! The free surface of a pile as the highest particle top per bin, and the straight line
//! fitted to its flank, shared by the heap of the lifted cylinder (`heap_surface`) and the
//! shelves of the draw-down test (`shelf_angle`) (docs/physics.md §7.10–7.11).
//!
//! The flank is where the surface is a slope: the bins whose top lies between
//! [`FLANK_BAND`]`.0` and `.1` of the pile's height. Below it lies the toe, where the slope
//! bends into the grains that rolled out onto the floor, and above it the cap (a heap's
//! rounded summit, a shelf's plateau of material that never moved); both would bend the line.

use analysis::fit::fit_line;

use super::error::MeasureError;
use serde::{Deserialize, Serialize};

/// The band of heights, as fractions of the pile's height, over which the flank is fitted:
/// 20 % to 80 %, the middle of the slope, as the image analyses of lab heaps leave out its
/// foot and its top.
pub const FLANK_BAND: (f64, f64) = (0.2, 0.8);

/// Fewest surface bins on a flank for a fit: a line through three points has one degree of
/// freedom left to estimate its error from.
pub const MIN_FLANK_BINS: usize = 3;

/// The top of the surface in one bin: its position along the fit's abscissa [m] and the
/// highest particle top in it above the floor [m].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SurfaceBin {
    /// The bin's centre along the abscissa (a radius about the heap's axis, a distance from the
    /// slot's edge) [m].
    pub position: f64,
    /// The highest particle top z + r in the bin above the floor [m].
    pub height: f64,
}

/// A straight line h = h₀ ± u tan θ fitted to a flank, the sign such that θ > 0 is a pile
/// falling toward its toe.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FlankFit {
    /// The slope's angle θ from the horizontal [°].
    pub angle_deg: f64,
    /// The standard error of θ from the fit's slope error, δθ = δs/(1 + s²) [°].
    pub angle_error_deg: f64,
    /// The line's height at the abscissa 0 [m].
    pub intercept: f64,
    /// The bins the line was fitted to.
    pub bins: usize,
    /// The abscissae of the first and last bins fitted [m]: the flank.
    pub range: [f64; 2],
    /// The band of heights fitted [m]: `FLANK_BAND` times the pile's height.
    pub band: [f64; 2],
}

impl FlankFit {
    /// Whether `bin` was one of the bins fitted.
    pub fn fitted(&self, bin: &SurfaceBin) -> bool {
        bin.position >= self.range[0]
            && bin.position <= self.range[1]
            && bin.height >= self.band[0]
            && bin.height <= self.band[1]
    }
}

/// Refuses particle arrays of different lengths: a radius for each position.
pub(crate) fn check_particles(positions: &[[f64; 3]], radii: &[f64]) -> Result<(), MeasureError> {
    if positions.len() == radii.len() {
        Ok(())
    } else {
        Err(MeasureError::LengthMismatch {
            field: "radii",
            expected: positions.len(),
            found: radii.len(),
        })
    }
}

/// Refuses a length parameter `name` that is not finite and > 0.
pub(crate) fn check_length(name: &'static str, value: f64) -> Result<(), MeasureError> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(MeasureError::InvalidParameter {
            name,
            value,
            reason: "must be a finite length > 0",
        })
    }
}

/// The highest top in bins of width `width` [m] from `start` [m] up, of the particles given as
/// (abscissa [m], top z + r [m]); those before `start` and the bins that hold no particle are
/// left out.
pub(crate) fn top_surface(
    tops: impl Iterator<Item = (f64, f64)>,
    start: f64,
    width: f64,
) -> Vec<SurfaceBin> {
    let mut highest: Vec<f64> = Vec::new();
    for (u, top) in tops {
        let k = ((u - start) / width).floor();
        if !(k >= 0.0) {
            continue;
        }
        let k = k as usize;
        if highest.len() <= k {
            highest.resize(k + 1, f64::NAN);
        }
        if !(highest[k] >= top) {
            highest[k] = top;
        }
    }
    highest
        .iter()
        .enumerate()
        .filter(|(_, h)| h.is_finite())
        .map(|(k, &height)| SurfaceBin {
            position: start + (k as f64 + 0.5) * width,
            height,
        })
        .collect()
}

/// Fits h = h₀ + s u to the bins whose heights lie in `FLANK_BAND` × `pile_height` [m], on
/// the toe's side of the surface's highest bin, and gives θ = atan(`falling` · s), `falling` being −1 where the pile falls as u grows (a heap
/// about its axis) and +1 where it rises (a shelf from the slot to the wall); `None` with
/// fewer than [`MIN_FLANK_BINS`] bins or a degenerate fit.
pub(crate) fn fit_flank(bins: &[SurfaceBin], pile_height: f64, falling: f64) -> Option<FlankFit> {
    let (lo, hi) = (FLANK_BAND.0 * pile_height, FLANK_BAND.1 * pile_height);
    // Only the side of this surface's highest bin that slopes down to the toe: beyond the
    // summit of a heap a sector's bins are small and may hold no grain of the surface, which
    // would put a low point on the far side of the cap.
    let peak = bins
        .iter()
        .max_by(|a, b| a.height.total_cmp(&b.height))?
        .position;
    let (u, h): (Vec<f64>, Vec<f64>) = bins
        .iter()
        .filter(|b| (b.position - peak) * falling <= 0.0)
        .filter(|b| b.height >= lo && b.height <= hi)
        .map(|b| (b.position, b.height))
        .unzip();
    if u.len() < MIN_FLANK_BINS {
        return None;
    }
    let fit = fit_line(&u, &h, 0.95).ok()?;
    let s = falling * fit.slope.value;
    let angle = s.atan();
    Some(FlankFit {
        angle_deg: angle.to_degrees(),
        angle_error_deg: (fit.slope.standard_error / (1.0 + s * s)).to_degrees(),
        intercept: fit.intercept.value,
        bins: u.len(),
        range: [
            u.iter().copied().fold(f64::INFINITY, f64::min),
            u.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        ],
        band: [lo, hi],
    })
}

/// The mean angle of several flanks [°] and its error [°]: the standard error of the mean over
/// the flanks, s/√n, combined in quadrature with the fits' own errors propagated to the mean,
/// √(Σ δθ_k²)/n. The first holds the scatter from flank to flank, the second what each fit
/// leaves unknown; their sum in quadrature counts the fits' noise twice where the scatter
/// already shows it, which errs on the safe side. With one flank, only its fit error.
pub(crate) fn mean_angle(fits: &[FlankFit]) -> (f64, f64) {
    let n = fits.len() as f64;
    if fits.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let mean = fits.iter().map(|f| f.angle_deg).sum::<f64>() / n;
    let fit_part = fits
        .iter()
        .map(|f| f.angle_error_deg.powi(2))
        .sum::<f64>()
        .sqrt()
        / n;
    let scatter = if fits.len() > 1 {
        let var = fits
            .iter()
            .map(|f| (f.angle_deg - mean).powi(2))
            .sum::<f64>()
            / (n - 1.0);
        var / n
    } else {
        0.0
    };
    (mean, (scatter + fit_part * fit_part).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tops on a line of known slope are fitted to it exactly, with a zero error; the bins
    /// outside the band are left out (a plateau above it would flatten the line).
    #[test]
    fn a_straight_flank_gives_its_angle() {
        let tan = 35f64.to_radians().tan();
        let mut bins: Vec<SurfaceBin> = (0..20)
            .map(|k| {
                let u = 0.001 * k as f64;
                SurfaceBin {
                    position: u,
                    height: 0.001 + u * tan,
                }
            })
            .collect();
        let top = bins.last().unwrap().height;
        // A plateau at the pile's height beyond the slope.
        bins.extend((20..30).map(|k| SurfaceBin {
            position: 0.001 * k as f64,
            height: top,
        }));
        let fit = fit_flank(&bins, top, 1.0).unwrap();
        assert!((fit.angle_deg - 35.0).abs() < 1e-9, "{fit:?}");
        assert!(fit.angle_error_deg < 1e-9);
        let (mean, error) = mean_angle(&[
            fit,
            FlankFit {
                angle_deg: 37.0,
                ..fit
            },
        ]);
        // Two flanks of 35° and 37°: mean 36°, standard error of the mean 1°.
        assert!((mean - 36.0).abs() < 1e-9 && (error - 1.0).abs() < 1e-9);
    }

    /// Each bin keeps its highest top; empty bins are left out.
    #[test]
    fn the_surface_is_the_highest_top_per_bin() {
        let tops = [
            (0.0005, 0.01),
            (0.0007, 0.02),
            (0.0025, 0.005),
            (-0.001, 1.0),
        ];
        let bins = top_surface(tops.into_iter(), 0.0, 0.001);
        assert_eq!(bins.len(), 2);
        assert_eq!((bins[0].position, bins[0].height), (0.0005, 0.02));
        assert_eq!((bins[1].position, bins[1].height), (0.0025, 0.005));
    }
}

//! Outlet profiles over a circular orifice as functions of the radial coordinate r
//! (docs/physics.md §7.6): v(r) from the crossings, and φ(r), the 3D volume fraction on the
//! slab |z − z_o| ≤ h/2 from the exact volumes of sphere ∩ slab ∩ annulus.
//!
//! The bins are annuli of equal width over 0 ≤ r < R about the orifice's centre. A bin's
//! position is its area-weighted mean radius, (2/3)(r₂³ − r₁³)/(r₂² − r₁²), not its middle:
//! an annulus averages over r dr, and for the innermost bin the two differ by a third.
//! Errors are batch-means over [`super::ERROR_BLOCKS`] time blocks of the window, as for the slot's
//! profiles (`block_error`).

use analysis::geometry3d::radial_volume_fractions;
use serde::{Deserialize, Serialize};

use super::block_error::BlockSums;
use super::crossing::CrossingRecord;
use super::error::MeasureError;
use super::snapshot::{Snapshot, TimeWindow};

/// Equal-width annuli over the orifice disc.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RadialBins {
    /// Orifice centre (x, y) [m].
    pub centre: [f64; 2],
    /// Orifice radius R [m].
    pub radius: f64,
    /// Number of annuli.
    pub count: usize,
}

impl RadialBins {
    /// Annuli of about `width` [m] (rounded to a whole number, at least 2) over the orifice.
    pub fn with_width(centre: [f64; 2], radius: f64, width: f64) -> Result<Self, MeasureError> {
        for (name, value) in [("radius", radius), ("width", width)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(MeasureError::InvalidParameter {
                    name,
                    value,
                    reason: "must be finite and > 0",
                });
            }
        }
        let count = ((radius / width).round() as usize).max(2);
        Ok(Self {
            centre,
            radius,
            count,
        })
    }

    /// Bin edges r_0 = 0 < … < r_n = R [m].
    pub fn edges(&self) -> Vec<f64> {
        (0..=self.count)
            .map(|i| self.radius * i as f64 / self.count as f64)
            .collect()
    }

    /// Radial distance of (x, y) from the orifice centre [m].
    pub fn distance(&self, x: f64, y: f64) -> f64 {
        (x - self.centre[0]).hypot(y - self.centre[1])
    }

    /// The bin of a point at (x, y), if it lies over the orifice.
    pub fn index_of(&self, x: f64, y: f64) -> Option<usize> {
        let r = self.distance(x, y) / self.radius;
        (r < 1.0).then(|| ((r * self.count as f64) as usize).min(self.count - 1))
    }

    /// Area-weighted mean radius of bin `i` [m]: (2/3)(r₂³ − r₁³)/(r₂² − r₁²).
    pub fn mean_radius(&self, i: usize) -> f64 {
        let width = self.radius / self.count as f64;
        let (a, b) = (width * i as f64, width * (i + 1) as f64);
        2.0 / 3.0 * (b.powi(3) - a.powi(3)) / (b * b - a * a)
    }
}

/// One annulus of the radial profiles.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RadialBin {
    /// Area-weighted mean radius over R, r* [-].
    pub r_star: f64,
    /// Area-weighted mean radius r [m].
    pub r: f64,
    /// Mean downward speed of the crossings through the annulus [m/s] (NaN if none).
    pub velocity: f64,
    /// Its batch-means standard error [m/s] (NaN when unknown).
    pub velocity_error: f64,
    /// Crossings through the annulus in the window.
    pub crossings: u64,
    /// Mean 3D volume fraction on the slab over the annulus [-] (NaN without frames).
    pub volume_fraction: f64,
    /// Its batch-means standard error [-] (NaN when unknown).
    pub volume_fraction_error: f64,
}

/// Per-frame volume fractions of each annulus on the outlet slab, kept so that the
/// averaging window is chosen after the run. Part of the checkpointed run state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RadialPackingProbe {
    bins: RadialBins,
    /// Outlet plane z_o [m].
    outlet_height: f64,
    /// Slab height h [m], centred on z_o.
    slab_height: f64,
    /// Frame times [s].
    times: Vec<f64>,
    /// φ of each annulus per frame, frame-major.
    fractions: Vec<f64>,
}

impl RadialPackingProbe {
    /// A probe over `bins` on the slab of height `slab_height` [m] about `outlet_height` [m].
    pub fn new(
        bins: RadialBins,
        outlet_height: f64,
        slab_height: f64,
    ) -> Result<Self, MeasureError> {
        if !(slab_height.is_finite() && slab_height > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "slab_height",
                value: slab_height,
                reason: "must be finite and > 0",
            });
        }
        Ok(Self {
            bins,
            outlet_height,
            slab_height,
            times: Vec::new(),
            fractions: Vec::new(),
        })
    }

    /// The annuli.
    pub fn bins(&self) -> &RadialBins {
        &self.bins
    }

    /// Measures one frame: the particles that reach into the slab count with the part of
    /// their volume inside each annulus.
    pub fn observe(&mut self, frame: &Snapshot<'_>) -> Result<(), MeasureError> {
        frame.validate()?;
        let (lower, upper) = (
            self.outlet_height - 0.5 * self.slab_height,
            self.outlet_height + 0.5 * self.slab_height,
        );
        let [cx, cy] = self.bins.centre;
        let mut centres = Vec::new();
        let mut radii = Vec::new();
        for (p, &r) in frame.positions.iter().zip(frame.radii) {
            if p[2] + r > lower && p[2] - r < upper {
                centres.push([p[0] - cx, p[1] - cy, p[2]]);
                radii.push(r);
            }
        }
        let phi = radial_volume_fractions(&centres, &radii, lower, upper, &self.bins.edges())
            .map_err(|e| MeasureError::Analysis(e.to_string()))?;
        self.times.push(frame.time);
        self.fractions.extend_from_slice(&phi);
        Ok(())
    }

    /// Mean φ of each annulus over the frames in `window`, with batch-means errors.
    pub fn profile(&self, window: TimeWindow) -> Vec<(f64, Option<f64>)> {
        let n = self.bins.count;
        let mut blocks = BlockSums::new(n, window);
        let mut sum = vec![0.0; n];
        let mut frames = 0u64;
        for (k, &t) in self.times.iter().enumerate() {
            if !window.contains(t) {
                continue;
            }
            frames += 1;
            for (i, s) in sum.iter_mut().enumerate() {
                let phi = self.fractions[k * n + i];
                *s += phi;
                blocks.add(i, t, phi);
            }
        }
        sum.iter()
            .enumerate()
            .map(|(i, s)| {
                if frames == 0 {
                    return (f64::NAN, None);
                }
                let mean = s / frames as f64;
                (mean, blocks.standard_error(i, mean))
            })
            .collect()
    }
}

/// The radial profiles over `window`: v(r) from `record`'s crossings and φ(r) from `packing`.
pub fn radial_profiles(
    record: &CrossingRecord,
    packing: &RadialPackingProbe,
    window: TimeWindow,
) -> Vec<RadialBin> {
    let bins = *packing.bins();
    let mut blocks = BlockSums::new(bins.count, window);
    let mut sum = vec![0.0; bins.count];
    let mut count = vec![0u64; bins.count];
    for e in record.events.iter().filter(|e| window.contains(e.time)) {
        if let Some(i) = bins.index_of(e.x, e.y) {
            let speed = -e.velocity_z;
            sum[i] += speed;
            count[i] += 1;
            blocks.add(i, e.time, speed);
        }
    }
    let phi = packing.profile(window);
    (0..bins.count)
        .map(|i| {
            let velocity = if count[i] > 0 {
                sum[i] / count[i] as f64
            } else {
                f64::NAN
            };
            let r = bins.mean_radius(i);
            RadialBin {
                r_star: r / bins.radius,
                r,
                velocity,
                velocity_error: if count[i] > 0 {
                    blocks.standard_error(i, velocity).unwrap_or(f64::NAN)
                } else {
                    f64::NAN
                },
                crossings: count[i],
                volume_fraction: phi[i].0,
                volume_fraction_error: phi[i].1.unwrap_or(f64::NAN),
            }
        })
        .collect()
}

//! Outlet profiles along x over a slot or a rectangular orifice of a 3D container (a box, STL
//! walls; docs/physics.md §7.8), from the crossings alone:
//!
//! - v(x): the mean downward speed of the centres crossing each x-bin of the orifice, as for
//!   the slab (§7.2);
//! - φ(x): the volume fraction from the number flux of centres. Centres of number density n
//!   falling at v cross an area A of the orifice plane n v A times per unit time, so over a
//!   window of duration T, n = Σ 1/|v_z| / (T A) over the crossings, and with each sphere's
//!   volume V_k, φ = Σ V_k/|v_z,k| / (T Δx L_y) for a bin Δx wide and L_y deep (the slot's
//!   depth or the rectangle's side along y). It is the 3D counterpart of the slab's
//!   crossing area fraction (`CrossingDensityProfile`).
//!
//! Only crossings inside the orifice count. Errors are batch means over [`super::ERROR_BLOCKS`]
//! time blocks of the window, as for the other profiles.

use serde::{Deserialize, Serialize};

use super::block_error::{BlockSums, ERROR_BLOCKS};
use super::crossing::CrossingRecord;
use super::geometry::OutletBins;
use super::snapshot::TimeWindow;

/// One x-bin of the profiles of a 3D slot or rectangle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct XProfileBin {
    /// Bin centre in x* = (x − x_c)/R [-].
    pub x_star: f64,
    /// Bin centre x [m].
    pub x: f64,
    /// Mean downward speed of the crossings [m/s] (NaN if none).
    pub velocity: f64,
    /// Its batch-means standard error [m/s] (NaN when unknown).
    pub velocity_error: f64,
    /// Crossings through the bin in the window.
    pub crossings: u64,
    /// Volume fraction from the number flux, Σ V/|v_z| / (T Δx L_y) [-] (NaN if none).
    pub volume_fraction: f64,
    /// Its standard error: the spread of the blocks' own fractions over √blocks [-] (NaN when
    /// unknown).
    pub volume_fraction_error: f64,
}

/// The profiles along x over `window` of the crossings in `record`, in `bins` across an
/// orifice `depth` [m] deep in y.
pub fn x_profiles(
    record: &CrossingRecord,
    bins: &OutletBins,
    depth: f64,
    window: TimeWindow,
) -> Vec<XProfileBin> {
    let n = bins.count;
    let mut speed_sum = vec![0.0; n];
    let mut count = vec![0u64; n];
    let mut speed_blocks = BlockSums::new(n, window);
    let mut volume_sum = vec![0.0; n];
    let mut volume_blocks = vec![0.0; n * ERROR_BLOCKS];
    let block_duration = window.duration() / ERROR_BLOCKS as f64;
    for e in record
        .events
        .iter()
        .filter(|e| window.contains(e.time) && e.inside_outlet)
    {
        let Some(i) = bins.index_of(e.x) else {
            continue;
        };
        let speed = -e.velocity_z;
        speed_sum[i] += speed;
        count[i] += 1;
        speed_blocks.add(i, e.time, speed);
        if speed > 0.0 {
            let volume = 4.0 / 3.0 * std::f64::consts::PI * e.radius.powi(3) / speed;
            volume_sum[i] += volume;
            let block = (((e.time - window.start) / block_duration).floor().max(0.0) as usize)
                .min(ERROR_BLOCKS - 1);
            volume_blocks[i * ERROR_BLOCKS + block] += volume;
        }
    }
    let area = bins.width() * depth;
    let scale = 1.0 / (window.duration() * area);
    let block_scale = 1.0 / (block_duration * area);
    (0..n)
        .map(|i| {
            let (velocity, velocity_error, volume_fraction, volume_fraction_error) =
                if count[i] == 0 {
                    (f64::NAN, f64::NAN, f64::NAN, f64::NAN)
                } else {
                    let v = speed_sum[i] / count[i] as f64;
                    let phi = volume_sum[i] * scale;
                    let g = ERROR_BLOCKS as f64;
                    let spread: f64 = volume_blocks[i * ERROR_BLOCKS..(i + 1) * ERROR_BLOCKS]
                        .iter()
                        .map(|b| (b * block_scale - phi).powi(2))
                        .sum();
                    (
                        v,
                        speed_blocks.standard_error(i, v).unwrap_or(f64::NAN),
                        phi,
                        (spread / (g - 1.0) / g).sqrt(),
                    )
                };
            XProfileBin {
                x_star: bins.x_star_centre(i),
                x: bins.x_centre(i),
                velocity,
                velocity_error,
                crossings: count[i],
                volume_fraction,
                volume_fraction_error,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{CrossingEvent, CrossingTally, OutletGeometry, OutletShape};

    /// Spheres of volume V falling at v through a bin of area A, k per second, carry the volume
    /// fraction k V/(v A): a uniform stream gives it in every bin.
    #[test]
    fn uniform_stream_gives_its_volume_fraction() {
        let geometry = OutletGeometry {
            outlet_height: 0.0,
            centre: 0.0,
            half_width: 0.01,
            particle_diameter: 0.002,
            shape: OutletShape::Slot,
        };
        let bins = OutletBins::across(&geometry, 4).unwrap();
        let (r, v, depth, per_bin_rate) = (0.001, 2.0, 0.03, 1000.0);
        let mut events = Vec::new();
        // 1000 crossings per second in each bin for one second.
        for k in 0..1000 {
            for i in 0..4 {
                events.push(CrossingEvent {
                    time: (k as f64 + 0.5) / per_bin_rate,
                    x: bins.x_centre(i),
                    velocity_z: -v,
                    mass: 1.0,
                    inside_outlet: true,
                    velocity_x: 0.0,
                    radius: r,
                    id: (4 * k + i) as u64,
                    y: 0.0,
                });
            }
        }
        let record = CrossingRecord {
            geometry,
            first_time: Some(0.0),
            last_time: Some(1.0),
            events,
            upward: CrossingTally::default(),
        };
        let window = TimeWindow::new(0.0, 1.0).unwrap();
        let rows = x_profiles(&record, &bins, depth, window);
        let volume = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        let expected = per_bin_rate * volume / (v * bins.width() * depth);
        for row in &rows {
            assert_eq!(row.crossings, 1000);
            assert!((row.velocity - v).abs() < 1e-12);
            assert!((row.volume_fraction - expected).abs() < 1e-12 * expected);
            // Every block holds exactly a tenth: no spread.
            assert!(row.volume_fraction_error < 1e-9 * expected);
        }
    }
}

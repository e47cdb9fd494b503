//! Bulk volume fraction and bed height of a settled bed in an axisymmetric silo or a
//! rectangular one (docs/physics.md §7.6), the 3D counterpart of the slab's `bulk` probe:
//!
//! - **Bed height** h_bed: the disc ρ < R − d about the axis is cut into square columns d
//!   wide; in each column that holds a particle the free surface is the highest sphere top
//!   max(z + r); h_bed is the mean over the occupied columns.
//! - **Cut height** h_cut = h_bed − 2d, which keeps the loose top layer out.
//! - **φ_B** = V_p(h_cut)/V(h_cut): V_p counts each sphere's exact slice below the cut
//!   (spherical caps, no centre-counting bias) and V is the container's volume below it. The
//!   looser layers along the walls are included: this is the bulk density of the silo's
//!   contents, what the Beverloo and Janssen laws take as ρ_b.

use std::collections::BTreeMap;

use super::bulk::{sphere_volume_below, BulkMeasurement};
use super::error::MeasureError;

/// Measures the bed of spheres (`centres` [m], `radii` [m]) in a silo of radius `radius`
/// [m] whose volume below a height is `volume_below` [m³], with columns and cut depth set by
/// `diameter` [m]. Fails without particles or when the cut falls to the orifice plane.
pub fn silo_bulk(
    centres: &[[f64; 3]],
    radii: &[f64],
    radius: f64,
    diameter: f64,
    volume_below: impl Fn(f64) -> f64,
) -> Result<BulkMeasurement, MeasureError> {
    let reach = radius - diameter;
    bed_bulk(
        centres,
        radii,
        |x, y| x.hypot(y) < reach,
        diameter,
        volume_below,
    )
}

/// [`silo_bulk`] for any container: the columns are those whose particles' centres (x, y)
/// satisfy `in_columns` (the floor plan less a diameter along the walls), the rest as there.
/// A rectangular silo uses it with its rectangle (docs/physics.md §7.6).
pub fn bed_bulk(
    centres: &[[f64; 3]],
    radii: &[f64],
    in_columns: impl Fn(f64, f64) -> bool,
    diameter: f64,
    volume_below: impl Fn(f64) -> f64,
) -> Result<BulkMeasurement, MeasureError> {
    if !(diameter.is_finite() && diameter > 0.0) {
        return Err(MeasureError::InvalidParameter {
            name: "diameter",
            value: diameter,
            reason: "must be finite and > 0",
        });
    }
    // Columns keyed by their integer cell: a BTreeMap keeps the mean's summation order fixed.
    let mut tops: BTreeMap<(i64, i64), f64> = BTreeMap::new();
    for (c, r) in centres.iter().zip(radii) {
        if in_columns(c[0], c[1]) && c[2] > 0.0 {
            let key = (
                (c[0] / diameter).floor() as i64,
                (c[1] / diameter).floor() as i64,
            );
            let top = tops.entry(key).or_insert(f64::NEG_INFINITY);
            *top = top.max(c[2] + r);
        }
    }
    if tops.is_empty() {
        return Err(MeasureError::InvalidParameter {
            name: "particles above the orifice plane",
            value: 0.0,
            reason: "the bed is empty",
        });
    }
    let bed_height = tops.values().sum::<f64>() / tops.len() as f64;
    let cut_height = bed_height - 2.0 * diameter;
    if cut_height <= 0.0 {
        return Err(MeasureError::InvalidParameter {
            name: "cut height",
            value: cut_height,
            reason: "the bed is less than two diameters deep",
        });
    }
    let particle_volume: f64 = centres
        .iter()
        .zip(radii)
        .map(|(c, &r)| sphere_volume_below(r, cut_height - c[2]) - sphere_volume_below(r, -c[2]))
        .sum();
    let container_volume = volume_below(cut_height);
    Ok(BulkMeasurement {
        bed_height,
        cut_height,
        particle_volume,
        container_volume,
        volume_fraction: particle_volume / container_volume,
        area_fraction: f64::NAN,
        columns: tops.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A simple cubic lattice of touching spheres filling a flat-bottomed cylinder has
    /// φ = π/6 in the bulk; the measured φ_B is lower by the wall layer, whose share is
    /// about 2·(d/2)/R of the volume here, and the bed height is the lattice's top.
    #[test]
    fn cubic_lattice_in_a_cylinder() {
        let (d, radius, layers) = (0.004, 0.1, 30);
        let mut centres = Vec::new();
        let n = (radius / d) as i64;
        for k in 0..layers {
            for i in -n..=n {
                for j in -n..=n {
                    let (x, y) = ((i as f64 + 0.5) * d, (j as f64 + 0.5) * d);
                    if x.hypot(y) + 0.5 * d <= radius {
                        centres.push([x, y, (k as f64 + 0.5) * d]);
                    }
                }
            }
        }
        let radii = vec![0.5 * d; centres.len()];
        let volume = |h: f64| std::f64::consts::PI * radius * radius * h;
        let b = silo_bulk(&centres, &radii, radius, d, volume).unwrap();
        // Every column's top is the lattice top, 30 d, to round-off.
        assert!((b.bed_height - layers as f64 * d).abs() < 1e-12);
        assert!((b.cut_height - (layers as f64 - 2.0) * d).abs() < 1e-12);
        let bulk = std::f64::consts::PI / 6.0;
        // The ring within half a cell of the wall is partly empty: a relative deficit of
        // the order of 2·(d/2)/R = 4 %; the bound allows 8 %.
        assert!(
            b.volume_fraction < bulk && b.volume_fraction > 0.92 * bulk,
            "{}",
            b.volume_fraction
        );
    }

    /// An empty bed and a bed shallower than the cut are refused, not measured.
    #[test]
    fn shallow_and_empty_beds_are_refused() {
        let volume = |h: f64| h;
        assert!(silo_bulk(&[], &[], 0.1, 0.004, volume).is_err());
        let one = [[0.0, 0.0, 0.002]];
        assert!(silo_bulk(&one, &[0.002], 0.1, 0.004, volume).is_err());
    }
}

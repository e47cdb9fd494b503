//! Bulk volume fraction φ_B, bed height and the container cross-section.

use measure::{
    sphere_volume_below, BulkProbe, ContainerOutline, CrossSection, OutletGeometry, Snapshot,
};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

const D: f64 = 3.0e-3;
const RHO: f64 = 2500.0;
const L: f64 = 0.09;

fn outlet() -> OutletGeometry {
    OutletGeometry {
        outlet_height: 0.0,
        centre: 0.0,
        half_width: 0.01,
        particle_diameter: D,
        shape: measure::OutletShape::Slot,
    }
}

#[test]
fn hopper_outline_area_matches_the_trapezoid_below_and_the_box_above_the_plates() {
    // α = 45°: plates rise 1:1 from the orifice edges (±R) to the walls (±L/2), a rise of
    // L/2 − R = 0.035 m. Below that the section is 2R + 2z wide: A = 2R h + h²; above it the
    // full width L is added. Polygon clipping is exact, so only round-off remains.
    let hopper = ContainerOutline::hopper(L, &outlet(), FRAC_PI_4, 0.3).unwrap();
    let r = 0.01;
    for h in [0.0, 0.01, 0.035, 0.05, 0.3, 0.5] {
        let rise = 0.5 * L - r;
        let expected = if h <= rise {
            2.0 * r * h + h * h
        } else {
            2.0 * r * rise + rise * rise + L * (h.min(0.3) - rise)
        };
        assert!(
            (hopper.area_below(h) - expected).abs() < 1e-15,
            "h = {h}: {} vs {expected}",
            hopper.area_below(h)
        );
    }
    // A flat bottom is a rectangle.
    let flat = ContainerOutline::hopper(L, &outlet(), FRAC_PI_2, 0.3).unwrap();
    assert!((flat.area_below(0.1) - L * 0.1).abs() < 1e-15);
    assert!(ContainerOutline::hopper(0.015, &outlet(), FRAC_PI_2, 0.3).is_err());
}

#[test]
fn sphere_volume_below_a_plane_is_zero_half_and_whole() {
    let r = 0.5 * D;
    let whole = 4.0 / 3.0 * PI * r * r * r;
    assert_eq!(sphere_volume_below(r, -2.0 * r), 0.0);
    assert!((sphere_volume_below(r, 0.0) / whole - 0.5).abs() < 1e-15);
    assert!((sphere_volume_below(r, r) / whole - 1.0).abs() < 1e-15);
    // Cap of height r/2: π (r/2)² (3r − r/2)/3 = 5π r³/24.
    assert!((sphere_volume_below(r, -0.5 * r) / (5.0 * PI * r * r * r / 24.0) - 1.0).abs() < 1e-14);
}

/// Spheres on a square lattice of spacing d in a flat-bottomed box: `rows` full rows resting
/// on the floor z = 0, plus one discharged particle below the floor.
fn square_packing(rows: usize) -> Vec<[f64; 3]> {
    let columns = (L / D).round() as usize;
    let mut positions = Vec::new();
    for j in 0..rows {
        for i in 0..columns {
            positions.push([
                -0.5 * L + (i as f64 + 0.5) * D,
                0.5 * D,
                (j as f64 + 0.5) * D,
            ]);
        }
    }
    positions.push([0.0, 0.5 * D, -0.05]);
    positions
}

fn frame(positions: &[[f64; 3]]) -> (Vec<u64>, Vec<[f64; 3]>, Vec<f64>) {
    let n = positions.len();
    ((0..n as u64).collect(), vec![[0.0; 3]; n], vec![0.5 * D; n])
}

#[test]
fn square_monolayer_gives_two_thirds_of_the_disc_fraction_as_volume_fraction() {
    // Square packing: area fraction π/4; a sphere fills 2/3 of its circumscribed cylinder,
    // so in a slab Z = 1.01 d: φ_B = (2/3)(π/4)(d/Z). The bed top is exactly rows·d, the cut
    // 2d lower falls on a row boundary, and caps are sliced exactly, so both are exact to
    // round-off (1e-12).
    let rows = 20;
    let positions = square_packing(rows);
    let (ids, velocities, radii) = frame(&positions);
    let view = Snapshot {
        time: 0.0,
        ids: &ids,
        positions: &positions,
        velocities: &velocities,
        radii: &radii,
        density: RHO,
        masses: None,
    };
    let outline = ContainerOutline::hopper(L, &outlet(), FRAC_PI_2, 0.4).unwrap();
    let (x_range, floor) = (outline.x_range(), outline.floor());
    let z = 1.01 * D;
    let probe = BulkProbe::new(outline, z, x_range, floor, D).unwrap();
    let bulk = probe.measure(&view).unwrap();
    assert!((bulk.bed_height - rows as f64 * D).abs() < 1e-15);
    assert!((bulk.cut_height - (rows - 2) as f64 * D).abs() < 1e-15);
    assert_eq!(bulk.columns, 30);
    assert!((bulk.area_fraction - FRAC_PI_4).abs() < 1e-12);
    assert!((bulk.volume_fraction - 2.0 / 3.0 * FRAC_PI_4 * D / z).abs() < 1e-12);
}

#[test]
fn closure_cross_section_and_cut_depth_are_honoured() {
    // Same packing, a closure for the rectangular section and no cut: the cut is the bed top
    // (rows·d) and the result is unchanged, since the top row is complete.
    let rows = 10;
    let positions = square_packing(rows);
    let (ids, velocities, radii) = frame(&positions);
    let view = Snapshot {
        time: 0.0,
        ids: &ids,
        positions: &positions,
        velocities: &velocities,
        radii: &radii,
        density: RHO,
        masses: None,
    };
    let section = |h: f64| L * h.max(0.0);
    let probe = BulkProbe::new(section, D, (-0.5 * L, 0.5 * L), 0.0, D)
        .unwrap()
        .with_cut_depth(0.0)
        .unwrap();
    let bulk = probe.measure(&view).unwrap();
    assert!((bulk.cut_height - rows as f64 * D).abs() < 1e-15);
    assert!((bulk.volume_fraction - PI / 6.0).abs() < 1e-12);
    // A bed shallower than the cut depth is an error, not a negative volume.
    let shallow = BulkProbe::new(section, D, (-0.5 * L, 0.5 * L), 0.0, D)
        .unwrap()
        .with_cut_depth(0.5)
        .unwrap();
    assert!(shallow.measure(&view).is_err());
}

#[test]
fn bed_height_is_the_mean_of_column_tops() {
    // Half the columns hold 10 rows, half 14: the mean surface is 12 d above the floor.
    let columns = (L / D).round() as usize;
    let mut positions = Vec::new();
    for i in 0..columns {
        let rows = if i < columns / 2 { 10 } else { 14 };
        for j in 0..rows {
            positions.push([
                -0.5 * L + (i as f64 + 0.5) * D,
                0.5 * D,
                (j as f64 + 0.5) * D,
            ]);
        }
    }
    let (ids, velocities, radii) = frame(&positions);
    let view = Snapshot {
        time: 0.0,
        ids: &ids,
        positions: &positions,
        velocities: &velocities,
        radii: &radii,
        density: RHO,
        masses: None,
    };
    let section = |h: f64| L * h.max(0.0);
    let probe = BulkProbe::new(section, D, (-0.5 * L, 0.5 * L), 0.0, D).unwrap();
    let bulk = probe.measure(&view).unwrap();
    assert!((bulk.bed_height - 12.0 * D).abs() < 1e-14);
}

//! Coarse-grained velocity field: uniform flows, mass conservation and window selection.

use measure::{
    FieldGrid, Kernel, MeasureError, OutletGeometry, Snapshot, TimeWindow, VelocityFieldProbe,
    DEFAULT_BLOCK_DURATION,
};
use std::f64::consts::PI;

/// Owned frame arrays: ids, positions [m], velocities [m/s], radii [m].
type Arrays = (Vec<u64>, Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<f64>);

const D: f64 = 3.0e-3;
const RHO: f64 = 2500.0;

fn mass() -> f64 {
    RHO * PI * D * D * D / 6.0
}

/// A square lattice of spacing `spacing` filling [−0.02, 0.02] × [0, 0.04] m, all at `velocity`.
fn lattice(spacing: f64, velocity: [f64; 3]) -> Arrays {
    let n = (0.04 / spacing).round() as usize;
    let mut positions = Vec::new();
    for j in 0..n {
        for i in 0..n {
            positions.push([
                -0.02 + (i as f64 + 0.5) * spacing,
                1.515e-3,
                (j as f64 + 0.5) * spacing,
            ]);
        }
    }
    let count = positions.len();
    (
        (0..count as u64).collect(),
        positions,
        vec![velocity; count],
        vec![0.5 * D; count],
    )
}

fn observe(probe: &mut VelocityFieldProbe, t: f64, spacing: f64, velocity: [f64; 3]) {
    let (ids, positions, velocities, radii) = lattice(spacing, velocity);
    probe
        .observe(&Snapshot {
            time: t,
            ids: &ids,
            positions: &positions,
            velocities: &velocities,
            radii: &radii,
            density: RHO,
            masses: None,
        })
        .unwrap();
}

#[test]
fn uniform_flow_gives_the_same_velocity_in_every_occupied_cell_for_both_kernels() {
    // V = Σ m v W / Σ m W is exactly v when every particle has velocity v, whatever the
    // weights: only round-off remains (1e-12 relative).
    let grid = FieldGrid::new(-0.02, 0.02, 0.0, 0.04, D).unwrap();
    for kernel in [Kernel::Box, Kernel::Gaussian { width: 0.5 * D }] {
        let mut probe = VelocityFieldProbe::new(grid, kernel, DEFAULT_BLOCK_DURATION).unwrap();
        observe(&mut probe, 0.0, 1.1 * D, [0.1, 0.0, -0.5]);
        let field = probe
            .record()
            .field(TimeWindow::new(0.0, 1.0).unwrap())
            .unwrap();
        let occupied: Vec<_> = field.cells.iter().filter_map(|c| c.velocity).collect();
        assert!(occupied.len() > grid.len() / 2, "{kernel:?}");
        for [vx, vz] in occupied {
            assert!(
                (vx - 0.1).abs() < 1e-12 && (vz + 0.5).abs() < 1e-12,
                "{kernel:?}"
            );
        }
    }
}

#[test]
fn box_kernel_mass_density_integrates_to_the_particle_mass() {
    // Each particle's mass lands in one cell with weight 1/h², so Σ ρ h² is the total mass
    // inside the grid exactly (round-off only).
    let grid = FieldGrid::new(-0.02, 0.02, 0.0, 0.04, D).unwrap();
    let mut probe = VelocityFieldProbe::new(grid, Kernel::Box, DEFAULT_BLOCK_DURATION).unwrap();
    let spacing = 1.1 * D;
    observe(&mut probe, 0.0, spacing, [0.0; 3]);
    let field = probe
        .record()
        .field(TimeWindow::new(0.0, 1.0).unwrap())
        .unwrap();
    let total: f64 = field.cells.iter().map(|c| c.mass_density * D * D).sum();
    let particles = lattice(spacing, [0.0; 3]).0.len() as f64;
    assert!((total / (particles * mass()) - 1.0).abs() < 1e-12);
}

#[test]
fn gaussian_kernel_conserves_mass_to_its_quadrature_error() {
    // One particle in the middle of a fine grid (h = w/4). The truncated kernel integrates to
    // one; sampling it at cell centres adds a boundary error of at most the mass in one cell
    // ring at the 3w cut, ≈ 3 (h/w) e^{−4.5} ≈ 8e-3 of m, and less when the ring errors
    // cancel; 1e-2 is that bound.
    let width = 0.5 * D;
    let grid = FieldGrid::new(-0.01, 0.01, 0.01, 0.03, 0.25 * width).unwrap();
    let mut probe =
        VelocityFieldProbe::new(grid, Kernel::Gaussian { width }, DEFAULT_BLOCK_DURATION).unwrap();
    probe
        .observe(&Snapshot {
            time: 0.0,
            ids: &[1],
            positions: &[[0.0003, 1.5e-3, 0.0201]],
            velocities: &[[0.0, 0.0, -1.0]],
            radii: &[0.5 * D],
            density: RHO,
            masses: None,
        })
        .unwrap();
    let field = probe
        .record()
        .field(TimeWindow::new(0.0, 1.0).unwrap())
        .unwrap();
    let h = grid.cell_size;
    let total: f64 = field.cells.iter().map(|c| c.mass_density * h * h).sum();
    assert!((total / mass() - 1.0).abs() < 1e-2, "{}", total / mass());
}

#[test]
fn window_picks_the_blocks_of_each_flow_phase() {
    // 0–0.04 s falling at 1 m/s, 0.04–0.08 s at 0.2 m/s, frames every 1 ms, 0.02 s blocks:
    // a window on either phase sees only that phase's velocity (to round-off).
    let grid = FieldGrid::new(-0.02, 0.02, 0.0, 0.04, 2.0 * D).unwrap();
    let mut probe = VelocityFieldProbe::new(grid, Kernel::Box, 0.02).unwrap();
    for k in 0..80 {
        let t = k as f64 * 1e-3;
        let v = if t < 0.04 { -1.0 } else { -0.2 };
        observe(&mut probe, t, 1.1 * D, [0.0, 0.0, v]);
    }
    let record = probe.record();
    assert_eq!(record.blocks.len(), 4);
    for (window, expected, frames) in [((0.0, 0.04), -1.0, 40), ((0.04, 0.08), -0.2, 40)] {
        let field = record
            .field(TimeWindow::new(window.0, window.1).unwrap())
            .unwrap();
        assert_eq!(field.frames, frames);
        for cell in field.cells.iter().filter_map(|c| c.velocity) {
            assert!((cell[1] - expected).abs() < 1e-12);
        }
    }
    assert!(matches!(
        record.field(TimeWindow::new(1.0, 2.0).unwrap()),
        Err(MeasureError::NoFramesInWindow { .. })
    ));
}

#[test]
fn outlet_grid_spans_the_hopper_width_and_two_widths_above_the_outlet() {
    let g = OutletGeometry {
        outlet_height: 0.01,
        centre: 0.0,
        half_width: 0.015,
        particle_diameter: D,
        shape: measure::OutletShape::Slot,
    };
    let grid = FieldGrid::around_outlet(&g, 0.1).unwrap();
    // 0.1 m / 3 mm → 34 columns (last overhangs); (3d + 0.2 m)/3 mm → 70 rows.
    assert_eq!((grid.columns, grid.rows), (34, 70));
    assert!((grid.z_min - (0.01 - 3.0 * D)).abs() < 1e-15);
    assert!(VelocityFieldProbe::new(grid, Kernel::Gaussian { width: -1.0 }, 0.02).is_err());
    assert!(VelocityFieldProbe::new(grid, Kernel::Box, 0.0).is_err());
}

//! Strip area fraction φ(x), ⟨φ v⟩ and the snapshot speed on synthetic packings with known answers.

use measure::{
    MeasureError, OutletBins, OutletGeometry, Snapshot, StripConfig, StripProbe, TimeWindow,
};
use std::f64::consts::PI;

const D: f64 = 3.0e-3;
const RHO: f64 = 2500.0;
const Y_MID: f64 = 1.515e-3;

fn geometry() -> OutletGeometry {
    OutletGeometry {
        outlet_height: 0.04,
        centre: 0.002,
        half_width: 0.015,
        particle_diameter: D,
        shape: measure::OutletShape::Slot,
    }
}

/// Owned particle arrays for building a `Snapshot`.
struct Particles {
    ids: Vec<u64>,
    positions: Vec<[f64; 3]>,
    velocities: Vec<[f64; 3]>,
    radii: Vec<f64>,
}

impl Particles {
    fn new(positions: Vec<[f64; 3]>, velocity: [f64; 3]) -> Self {
        let n = positions.len();
        Self {
            ids: (0..n as u64).collect(),
            velocities: vec![velocity; n],
            radii: vec![0.5 * D; n],
            positions,
        }
    }

    fn view(&self, time: f64) -> Snapshot<'_> {
        Snapshot {
            time,
            ids: &self.ids,
            positions: &self.positions,
            velocities: &self.velocities,
            radii: &self.radii,
            density: RHO,
            masses: None,
        }
    }
}

/// Touching discs of diameter d on a hexagonal lattice (rows √3 d/2 apart, alternate rows
/// shifted by d/2) covering the outlet region generously, shifted by (dx, dz).
fn hexagonal_lattice(g: &OutletGeometry, dx: f64, dz: f64) -> Vec<[f64; 3]> {
    let row = 3f64.sqrt() / 2.0 * D;
    let mut positions = Vec::new();
    for j in -8i32..=8 {
        for i in -16i32..=16 {
            let shift = if j.rem_euclid(2) == 1 { 0.5 * D } else { 0.0 };
            positions.push([
                g.centre + dx + shift + i as f64 * D,
                Y_MID,
                g.outlet_height + dz + j as f64 * row,
            ]);
        }
    }
    positions
}

const CLOSE_PACKED: f64 = PI / (2.0 * 1.732_050_807_568_877_2);

#[test]
fn hexagonal_monolayer_fills_each_lattice_cell_bin_at_the_close_packed_fraction() {
    // A bin d wide and √3 d tall is a fundamental domain of the hexagonal lattice (periods
    // (d, 0) and (0, √3 d), two discs each), so it holds exactly two discs' worth of area for
    // any lattice offset: φ = π/(2√3) with only round-off error (touching discs never overlap).
    let g = geometry();
    let bins = OutletBins::with_width(&g, D).unwrap();
    assert_eq!(bins.count, 10);
    let config = StripConfig {
        strip_height: 3f64.sqrt() * D,
        ..StripConfig::new(g, bins)
    };
    for (k, (dx, dz)) in [(0.0, 0.0), (0.37e-3, 1.1e-3), (-1.2e-3, -0.45e-3)]
        .into_iter()
        .enumerate()
    {
        let mut probe = StripProbe::new(config).unwrap();
        let particles = Particles::new(hexagonal_lattice(&g, dx, dz), [0.0, 0.0, -0.7]);
        probe.observe(&particles.view(0.0)).unwrap();
        let profile = probe
            .record()
            .area_fraction_profile(TimeWindow::new(-1.0, 1.0).unwrap())
            .unwrap();
        for entry in &profile.entries {
            assert!(
                (entry.area_fraction - CLOSE_PACKED).abs() < 1e-12,
                "offset {k}, x* = {}: {}",
                entry.x_star,
                entry.area_fraction
            );
            // Uniform velocity: ⟨φ v⟩ = φ v exactly, downward positive.
            assert!((entry.area_fraction_speed - 0.7 * CLOSE_PACKED).abs() < 1e-12);
        }
    }
}

#[test]
fn default_strip_averaged_over_lattice_translations_gives_the_close_packed_fraction() {
    // With h = d and bins d/2 wide a single frame depends on the lattice phase; averaging over
    // a uniform N × N grid of translations across one lattice cell is a periodic Riemann sum,
    // whose error for this piecewise-smooth (C¹) function of the offset falls like N⁻² or
    // faster: N = 32 gives < 1e-3 with margin.
    let g = geometry();
    let bins = OutletBins::with_width(&g, 0.5 * D).unwrap();
    let mut probe = StripProbe::new(StripConfig::new(g, bins)).unwrap();
    let n = 32;
    let mut frame = 0;
    for a in 0..n {
        for b in 0..n {
            let dx = a as f64 / n as f64 * D;
            let dz = b as f64 / n as f64 * 3f64.sqrt() * D;
            let particles = Particles::new(hexagonal_lattice(&g, dx, dz), [0.0, 0.0, -1.0]);
            probe.observe(&particles.view(frame as f64 * 1e-3)).unwrap();
            frame += 1;
        }
    }
    let profile = probe
        .record()
        .area_fraction_profile(TimeWindow::new(0.0, 10.0).unwrap())
        .unwrap();
    assert_eq!(profile.frames, n * n);
    for entry in &profile.entries {
        assert!(
            (entry.area_fraction - CLOSE_PACKED).abs() < 1e-3,
            "x* = {}: {}",
            entry.x_star,
            entry.area_fraction
        );
        // Every translation holds centres within d/2 of z_o in every bin, all at 1 m/s.
        assert!((entry.snapshot_speed.unwrap() - 1.0).abs() < 1e-12);
    }
    let centre = profile.centre_area_fraction().unwrap();
    assert!((centre - CLOSE_PACKED).abs() < 1e-3);
}

#[test]
fn mid_plane_section_shrinks_discs_of_off_plane_spheres() {
    // One sphere at z_o, 0.6 r off the mid-plane: its section has radius 0.8 r. A single bin
    // spanning the whole orifice holds the entire section disc, so covered area = π (0.8 r)².
    let g = geometry();
    let bins = OutletBins::across(&g, 1).unwrap();
    let config = StripConfig {
        mid_plane: Some(Y_MID),
        ..StripConfig::new(g, bins)
    };
    let r = 0.5 * D;
    let mut particles =
        Particles::new(vec![[g.centre, Y_MID + 0.6 * r, g.outlet_height]], [0.0; 3]);
    let mut probe = StripProbe::new(config).unwrap();
    probe.observe(&particles.view(0.0)).unwrap();
    let covered = probe.record().frames[0].covered_area[0];
    assert!((covered / (PI * 0.64 * r * r) - 1.0).abs() < 1e-12);
    // Without the mid-plane rule the full radius is used.
    let mut full = StripProbe::new(StripConfig::new(g, bins)).unwrap();
    particles.positions[0][1] = Y_MID + 0.6 * r;
    full.observe(&particles.view(0.0)).unwrap();
    assert!((full.record().frames[0].covered_area[0] / (PI * r * r) - 1.0).abs() < 1e-12);
}

#[test]
fn window_selects_frames_and_an_empty_window_is_an_error() {
    // An empty strip for t < 0.01 s and a lattice afterwards: the late window sees the packing.
    let g = geometry();
    let bins = OutletBins::with_width(&g, D).unwrap();
    let config = StripConfig {
        strip_height: 3f64.sqrt() * D,
        ..StripConfig::new(g, bins)
    };
    let mut probe = StripProbe::new(config).unwrap();
    let empty = Particles::new(Vec::new(), [0.0; 3]);
    let full = Particles::new(hexagonal_lattice(&g, 0.0, 0.0), [0.0; 3]);
    for k in 0..20 {
        let t = k as f64 * 1e-3;
        let frame = if t < 0.0095 {
            empty.view(t)
        } else {
            full.view(t)
        };
        probe.observe(&frame).unwrap();
    }
    let record = probe.record();
    let early = record
        .area_fraction_profile(TimeWindow::new(0.0, 0.0095).unwrap())
        .unwrap();
    let late = record
        .area_fraction_profile(TimeWindow::new(0.0095, 1.0).unwrap())
        .unwrap();
    assert_eq!((early.frames, late.frames), (10, 10));
    assert!(early.entries.iter().all(|e| e.area_fraction == 0.0));
    assert!(late
        .entries
        .iter()
        .all(|e| (e.area_fraction - CLOSE_PACKED).abs() < 1e-12));
    // Identical (empty) frames have no spread across frames.
    assert_eq!(early.entries[0].area_fraction_standard_error, Some(0.0));
    assert!(matches!(
        record.area_fraction_profile(TimeWindow::new(5.0, 6.0).unwrap()),
        Err(MeasureError::NoFramesInWindow { .. })
    ));
}

#[test]
fn maximum_area_fraction_is_located_in_the_densest_bin() {
    // A single disc centred in bin 3 of 10 (bins d wide, strip d tall): that bin alone is
    // covered, at π r²/(d·d) = π/4.
    let g = geometry();
    let bins = OutletBins::with_width(&g, D).unwrap();
    let mut probe = StripProbe::new(StripConfig::new(g, bins)).unwrap();
    let particles = Particles::new(vec![[bins.x_centre(3), Y_MID, g.outlet_height]], [0.0; 3]);
    probe.observe(&particles.view(0.0)).unwrap();
    let profile = probe
        .record()
        .area_fraction_profile(TimeWindow::new(0.0, 1.0).unwrap())
        .unwrap();
    let (phi_max, x_star) = profile.max_area_fraction().unwrap();
    assert!((phi_max - PI / 4.0).abs() < 1e-12);
    assert!((x_star - bins.x_star_centre(3)).abs() < 1e-15);
    assert_eq!(profile.centre_area_fraction(), Some(0.0));
}

#[test]
fn invalid_strip_configuration_is_rejected() {
    let g = geometry();
    let bins = OutletBins::across(&g, 4).unwrap();
    let config = StripConfig {
        strip_height: 0.0,
        ..StripConfig::new(g, bins)
    };
    assert!(StripProbe::new(config).is_err());
    assert!(OutletBins::across(&g, 0).is_err());
}

//! Outlet crossings: interpolation, the velocity profile, tallies and the discharge series.

use measure::{CrossingProbe, MeasureError, OutletBins, OutletGeometry, Snapshot, TimeWindow};
use std::f64::consts::PI;

const D: f64 = 3.0e-3;
const RHO: f64 = 2500.0;

fn geometry() -> OutletGeometry {
    OutletGeometry {
        outlet_height: 0.05,
        centre: -0.01,
        half_width: 0.015,
        particle_diameter: D,
        shape: measure::OutletShape::Slot,
    }
}

fn mass() -> f64 {
    RHO * PI * D * D * D / 6.0
}

/// Particles moving at constant velocity: state at time `t` from (id, x0, z0, vx, vz) at t = 0.
struct Ballistic {
    ids: Vec<u64>,
    positions: Vec<[f64; 3]>,
    velocities: Vec<[f64; 3]>,
    radii: Vec<f64>,
}

impl Ballistic {
    fn at(particles: &[(u64, f64, f64, f64, f64)], t: f64) -> Self {
        Self {
            ids: particles.iter().map(|p| p.0).collect(),
            positions: particles
                .iter()
                .map(|p| [p.1 + p.3 * t, 1.515e-3, p.2 + p.4 * t])
                .collect(),
            velocities: particles.iter().map(|p| [p.3, 0.0, p.4]).collect(),
            radii: vec![0.5 * D; particles.len()],
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

fn observe_at(probe: &mut CrossingProbe, particles: &[(u64, f64, f64, f64, f64)], t: f64) -> usize {
    let state = Ballistic::at(particles, t);
    probe.observe(&state.view(t)).expect("valid frame")
}

#[test]
fn crossing_time_position_and_velocity_are_interpolated_exactly_for_uniform_motion() {
    // z(t) = 0.0512 − 0.9 t crosses z_o = 0.05 at t* = 0.0012/0.9; x(t) = −0.004 + 0.3 t.
    let particles = [(7, -0.004, 0.0512, 0.3, -0.9)];
    let mut probe = CrossingProbe::new(geometry()).unwrap();
    assert_eq!(observe_at(&mut probe, &particles, 0.0), 0);
    assert_eq!(observe_at(&mut probe, &particles, 0.002), 1);
    let event = probe.record().events[0];
    let t_star = 0.0012 / 0.9;
    // Linear motion makes linear interpolation exact up to round-off (~1e-16 relative).
    assert!((event.time - t_star).abs() < 1e-15);
    assert!((event.x - (-0.004 + 0.3 * t_star)).abs() < 1e-15);
    assert!((event.velocity_z + 0.9).abs() < 1e-14);
    assert!((event.mass / mass() - 1.0).abs() < 1e-14);
    assert!(event.inside_outlet);
}

#[test]
fn velocity_profile_recovers_known_bin_means_and_standard_errors() {
    let g = geometry();
    let bins = OutletBins::across(&g, 10).unwrap();
    // Three crossings in bin 2 at speeds 1.0, 1.2, 1.4 m/s and one in bin 7 at 0.5 m/s.
    let x2 = bins.x_centre(2);
    let x7 = bins.x_centre(7);
    let particles = [
        (1, x2, 0.0505, 0.0, -1.0),
        (2, x2 + 0.3 * bins.width(), 0.0509, 0.0, -1.2),
        (3, x2 - 0.3 * bins.width(), 0.0501, 0.0, -1.4),
        (4, x7, 0.0501, 0.0, -0.5),
    ];
    let mut probe = CrossingProbe::new(g).unwrap();
    observe_at(&mut probe, &particles, 0.0);
    assert_eq!(observe_at(&mut probe, &particles, 0.001), 4);
    // The window's ten time blocks are 0.1 ms long, and bin 2's crossings (at 0.07, 0.50
    // and 0.75 ms) fall into three different blocks: one sample per block, so the block
    // error is the plain one.
    let profile = probe
        .record()
        .velocity_profile(TimeWindow::new(0.0, 0.001).unwrap(), &bins);
    let b2 = profile.entries[2];
    assert_eq!(b2.count, 3);
    // Mean 1.2 and sample standard deviation 0.2 ⇒ standard error 0.2/√3; round-off only.
    assert!((b2.mean_speed.unwrap() - 1.2).abs() < 1e-12);
    assert!((b2.standard_error.unwrap() - 0.2 / 3f64.sqrt()).abs() < 1e-12);
    // Over a window ten times longer all three share its first block: no spread between
    // blocks can be seen, so no error is claimed.
    let long = probe
        .record()
        .velocity_profile(TimeWindow::new(0.0, 0.01).unwrap(), &bins);
    assert_eq!(long.entries[2].mean_speed, b2.mean_speed);
    assert_eq!(long.entries[2].standard_error, None);
    let b7 = profile.entries[7];
    assert_eq!(b7.count, 1);
    assert!((b7.mean_speed.unwrap() - 0.5).abs() < 1e-12);
    assert_eq!(b7.standard_error, None, "one crossing has no spread");
    for (i, entry) in profile.entries.iter().enumerate() {
        if i != 2 && i != 7 {
            assert_eq!(entry.count, 0);
            assert_eq!(entry.mean_speed, None);
        }
    }
    // Central bins (|x*| < 0.1 ⇒ bins 4 and 5 of 10) are empty here.
    assert_eq!(profile.centre_speed(), None);
}

#[test]
fn window_excludes_crossings_outside_it() {
    let g = geometry();
    let bins = OutletBins::across(&g, 4).unwrap();
    // Particle 1 crosses at t = 0.001, particle 2 at t = 0.011.
    let particles = [
        (1, g.centre, 0.051, 0.0, -1.0),
        (2, g.centre, 0.061, 0.0, -1.0),
    ];
    let mut probe = CrossingProbe::new(g).unwrap();
    for k in 0..=12 {
        observe_at(&mut probe, &particles, k as f64 * 0.0015);
    }
    let early = probe
        .record()
        .velocity_profile(TimeWindow::new(0.0, 0.005).unwrap(), &bins);
    let total: u64 = early.entries.iter().map(|e| e.count).sum();
    assert_eq!(total, 1);
    let crossing_times: Vec<f64> = probe.record().events.iter().map(|e| e.time).collect();
    assert!((crossing_times[0] - 0.001).abs() < 1e-14 && (crossing_times[1] - 0.011).abs() < 1e-14);
}

#[test]
fn crossings_outside_the_orifice_are_tallied_but_not_profiled() {
    let g = geometry();
    let bins = OutletBins::across(&g, 6).unwrap();
    let outside_x = g.centre + 1.5 * g.half_width;
    let particles = [
        (1, outside_x, 0.0502, 0.0, -1.0),
        (2, g.centre, 0.0502, 0.0, -1.0),
    ];
    let mut probe = CrossingProbe::new(g).unwrap();
    observe_at(&mut probe, &particles, 0.0);
    observe_at(&mut probe, &particles, 0.001);
    let record = probe.record();
    assert_eq!(record.events.len(), 2);
    assert_eq!(record.outside_outlet().count, 1);
    let profile = record.velocity_profile(TimeWindow::new(0.0, 1.0).unwrap(), &bins);
    assert_eq!(profile.entries.iter().map(|e| e.count).sum::<u64>(), 1);
    // Rates over a 1 s window: one particle mass per second inside, two overall.
    let window = TimeWindow::new(0.0, 1.0).unwrap();
    assert!((record.mean_discharge_rate_inside(window) / mass() - 1.0).abs() < 1e-12);
    assert!((record.mean_discharge_rate(window) / mass() - 2.0).abs() < 1e-12);
}

#[test]
fn upward_crossings_are_tallied_and_never_counted_as_discharge() {
    let g = geometry();
    let particles = [(1, g.centre, 0.0498, 0.0, 1.0)];
    let mut probe = CrossingProbe::new(g).unwrap();
    observe_at(&mut probe, &particles, 0.0);
    observe_at(&mut probe, &particles, 0.001);
    assert!(probe.record().events.is_empty());
    assert_eq!(probe.record().upward.count, 1);
}

#[test]
fn a_particle_that_vanishes_is_forgotten_and_not_counted_on_return() {
    let g = geometry();
    let above = [(1, g.centre, 0.0502, 0.0, 0.0)];
    let below = [(1, g.centre, 0.0498, 0.0, 0.0)];
    let mut probe = CrossingProbe::new(g).unwrap();
    observe_at(&mut probe, &above, 0.0);
    // A frame without particle 1 (removed), then it reappears below the line.
    let empty = Ballistic::at(&[], 0.001);
    probe.observe(&empty.view(0.001)).unwrap();
    observe_at(&mut probe, &below, 0.002);
    assert!(probe.record().events.is_empty());
}

#[test]
fn discharge_series_bins_mass_and_finds_the_steady_window_by_mass() {
    let g = geometry();
    // Ten particles crossing at t = 0.005, 0.015, …, 0.095 s (one per 0.01 s).
    let particles: Vec<_> = (0..10)
        .map(|k| {
            (
                k as u64,
                g.centre,
                0.05 + 0.005 + 0.01 * k as f64,
                0.0,
                -1.0,
            )
        })
        .collect();
    let mut probe = CrossingProbe::new(g).unwrap();
    for step in 0..=100 {
        observe_at(&mut probe, &particles, step as f64 * 0.001);
    }
    let record = probe.record();
    let series = record.discharged_mass_series(0.02).unwrap();
    // 0.1 s of observation in 0.02 s bins: 5 bins, two crossings each.
    assert_eq!(series.mass.len(), 5);
    for (k, m) in series.mass.iter().enumerate() {
        assert!((m / mass() - 2.0).abs() < 1e-12, "bin {k}");
        assert!((series.rate[k] - 2.0 * mass() / 0.02).abs() < 1e-9 * series.rate[k]);
    }
    assert!((series.cumulative_mass[4] / mass() - 10.0).abs() < 1e-12);
    // 20 % and 70 % of ten masses are reached by the 2nd and 7th crossings.
    let window = record
        .window_between_discharged_masses(2.0 * mass(), 7.0 * mass())
        .unwrap();
    assert!((window.start - 0.015).abs() < 1e-12 && (window.end - 0.065).abs() < 1e-12);
    assert!(matches!(
        record.time_when_discharged(11.0 * mass()),
        Err(MeasureError::MassNotReached { .. })
    ));
}

#[test]
fn frames_out_of_order_or_inconsistent_are_rejected() {
    let g = geometry();
    let particles = [(1, g.centre, 0.06, 0.0, -1.0)];
    let mut probe = CrossingProbe::new(g).unwrap();
    observe_at(&mut probe, &particles, 0.01);
    let state = Ballistic::at(&particles, 0.005);
    assert!(matches!(
        probe.observe(&state.view(0.005)),
        Err(MeasureError::TimeNotIncreasing { .. })
    ));
    let bad = Snapshot {
        radii: &[],
        ..state.view(0.02)
    };
    assert!(matches!(
        probe.observe(&bad),
        Err(MeasureError::LengthMismatch { field: "radii", .. })
    ));
    assert!(CrossingProbe::new(OutletGeometry {
        half_width: -1.0,
        ..g
    })
    .is_err());
}

#[test]
fn record_survives_a_json_round_trip_and_gives_the_same_profile() {
    // Windows are chosen after the run, possibly from a saved record: the reloaded record
    // must reproduce the profile. serde_json's default float parser may be off by one ulp,
    // hence 1e-15 relative rather than bit equality.
    let g = geometry();
    let bins = OutletBins::across(&g, 5).unwrap();
    let particles = [
        (1, g.centre, 0.0503, 0.1, -1.1),
        (2, g.centre + 0.004, 0.0507, 0.0, -0.9),
    ];
    let mut probe = CrossingProbe::new(g).unwrap();
    for k in 0..4 {
        observe_at(&mut probe, &particles, k as f64 * 4e-4);
    }
    let record = probe.into_record();
    let text = serde_json::to_string(&record).unwrap();
    let reloaded: measure::CrossingRecord = serde_json::from_str(&text).unwrap();
    assert_eq!(reloaded.events.len(), 2);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-15 * a.abs().max(b.abs());
    for (a, b) in reloaded.events.iter().zip(&record.events) {
        assert!(close(a.time, b.time) && close(a.x, b.x) && close(a.velocity_z, b.velocity_z));
        assert!(close(a.mass, b.mass) && a.inside_outlet == b.inside_outlet);
    }
    let window = TimeWindow::new(0.0, 1.0).unwrap();
    let before = record.velocity_profile(window, &bins);
    let after = reloaded.velocity_profile(window, &bins);
    for (a, b) in after.entries.iter().zip(&before.entries) {
        assert_eq!(a.count, b.count);
        match (a.mean_speed, b.mean_speed) {
            (Some(x), Some(y)) => assert!(close(x, y)),
            (x, y) => assert_eq!(x, y),
        }
    }
}

#[test]
fn crossing_density_profile_recovers_the_area_fraction_of_a_falling_lattice() {
    // Columns of centres, one per bin centre (bins 3 mm wide), fall through the outlet line.
    // Bins 1–8: rows 4 mm apart at 0.8 m/s, areal density n = 1/(3 mm · 4 mm), so
    // φ_n = n π r² = π (1.5 mm)²/12 mm² = 0.589. Bin 0: rows 8 mm apart at 1.6 m/s, the
    // same flux of centres but half the density: φ_n = 0.295, which a plain count of
    // crossings (a flux) could not tell from bins 1–8. Bin 9 stays empty.
    let g = geometry();
    let bins = OutletBins::across(&g, 10).unwrap();
    let z_o = g.outlet_height;
    let mut particles = Vec::new();
    let mut id = 0;
    for bin in 0..9 {
        let speed = if bin == 0 { 1.6 } else { 0.8 };
        for k in 0..10 {
            // Crossing at 2.5 ms + 5 ms · k: one per column in each of the window's ten
            // 5 ms blocks.
            let t_cross = 2.5e-3 + 5.0e-3 * k as f64;
            particles.push((id, bins.x_centre(bin), z_o + speed * t_cross, 0.0, -speed));
            id += 1;
        }
    }
    let mut probe = CrossingProbe::new(g).unwrap();
    for frame in 0..=50 {
        observe_at(&mut probe, &particles, 1.0e-3 * frame as f64);
    }
    assert_eq!(probe.record().events.len(), 90);
    let profile = probe
        .record()
        .crossing_density_profile(TimeWindow::new(0.0, 0.05).unwrap(), &bins);
    let r = 0.5 * D;
    let dense = PI * r * r / (bins.width() * 4.0e-3);
    // Sums of ten equal terms and a few products: round-off only (1e-12 relative).
    for bin in 1..9 {
        let phi = profile.area_fraction[bin].unwrap();
        assert!(
            (phi / dense - 1.0).abs() < 1e-12,
            "bin {bin}: {phi} vs {dense}"
        );
        // Every block holds the same crossing, so the blocks do not scatter.
        assert!(profile.standard_error[bin].unwrap() < 1e-12 * dense);
    }
    let sparse = profile.area_fraction[0].unwrap();
    assert!((sparse / (0.5 * dense) - 1.0).abs() < 1e-12, "{sparse}");
    assert_eq!(profile.area_fraction[9], None);
    assert_eq!(profile.standard_error[9], None);
    // The events carry what crossings.csv writes: identifier, radius and v_x.
    let first = probe.record().events[0];
    assert_eq!(first.radius, r);
    assert_eq!(first.velocity_x, 0.0);
    assert!(first.id < 90);
}

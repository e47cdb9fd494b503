//! The two calibration tests end to end, small (docs/physics.md §5.9–5.10, §7.10–7.11): the
//! heap of a lifted cylinder comes to rest at an angle of repose, and the draw-down box drains
//! leaving slopes on both shelves. Spheres of 3 mm with the rolling friction a calibration
//! starts from (0.1, particles and walls), Δt = 5 µs (0.19 Rayleigh times).

use crate::run_dir::{self, table};

use case::parse_case;
use files::StopReason;

/// The shared keys: `count` spheres of 3 mm, μ_r = 0.1, a settling threshold of 1e-8 J (a
/// sphere of 3.5e-5 kg moving at 2.4 cm/s), no checkpoints or pictures.
fn settings(count: usize) -> String {
    format!(
        "[particles]\ncount = {count}\ndiameter = 0.003\n[time]\ntime_step = 5.0e-6\n\
         [contact]\nrolling_friction = 0.1\n[wall]\nrolling_friction = 0.1\n\
         [protocol]\ntime_limit = 3.0\nsettle_kinetic_energy = 1.0e-8\n\
         [output]\ncheckpoint_interval = 0.0\nvtu_interval = 0.0\n"
    )
}

/// 500 spheres in a cylinder of 30 mm (10 d) lifted at 50 mm/s leave a heap at rest on the
/// plate, and its fitted angle lies between 10° and 45° with a finite, positive error below
/// 10°. Why that range: dry spheres of μ_s = 0.5 and μ_r = 0.1 stand at about 17° in the
/// default test (docs/physics.md §7.10); this heap is half as tall (some 5 diameters), so its
/// angle is rougher, but spheres without rolling resistance would spread below 10°, and only
/// cohesion stands a dry heap above 45°.
#[test]
fn a_lifted_cylinder_leaves_a_heap_at_its_angle_of_repose() {
    let text = format!(
        "version = 1\nseed = 3\n[geometry]\nkind = \"heap\"\ncylinder_radius = 0.015\n\
         height = 0.06\nplate_radius = 0.05\nlift_speed = 0.05\n{}",
        settings(500)
    );
    let case = parse_case(&text, "heap.toml", &[]).expect("a valid heap case");
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("heap");
    let summary = run_dir::finished(&case, &dir, 1, false);
    assert_eq!(summary.stop_reason, StopReason::AtRest);
    let repose = summary.repose.expect("a heap has its angle");
    assert!(
        repose.angle_deg > 10.0 && repose.angle_deg < 45.0,
        "θ = {} ± {}",
        repose.angle_deg,
        repose.angle_error_deg
    );
    assert!(repose.angle_error_deg > 0.0 && repose.angle_error_deg < 10.0);
    // Most sectors had a flank to fit; the heap is lower than the fill stood in the cylinder
    // (about 20 mm) and wider than the cylinder.
    assert!(repose.sectors >= 6, "{repose:?}");
    assert!(
        repose.height < 0.02 && repose.base_radius > 0.015,
        "{repose:?}"
    );
    // heap_surface.csv: sector, r, top, fit, fitted; the fitted bins lie on the flank.
    let surface = table(&dir.join("heap_surface.csv"));
    let fitted: Vec<&Vec<f64>> = surface.iter().filter(|row| row[4] == 1.0).collect();
    assert!(
        fitted.len() >= 3 * repose.sectors,
        "{} fitted bins",
        fitted.len()
    );
    for row in fitted {
        assert!(row[2] >= 0.2 * repose.height && row[2] <= 0.8 * repose.height);
    }
    // The summary reads back with its section (what `hopperflow calibrate` reads).
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["repose"]["angle_deg"].as_f64(), Some(repose.angle_deg));
}

/// 700 spheres in a box 66 mm × 12 mm over an 18 mm slot (6 d) drain: the flow stops with
/// material left on both shelves, each sloping between 15° and 60°. Why that range: the
/// default test's drained slopes of these spheres stand at about 38° (docs/physics.md §7.11);
/// a box only 4 diameters deep holds them steeper by its front and back walls' friction, but
/// a slope at the friction angle itself, atan 0.5 ≈ 27°, plus that support stays well below 60°,
/// and spheres that roll freely leave no slope above 15°.
#[test]
fn a_draw_down_box_drains_leaving_slopes_on_both_shelves() {
    let text = format!(
        "version = 1\nseed = 4\n[geometry]\nkind = \"draw_down\"\nwidth = 0.066\n\
         depth = 0.012\nheight = 0.06\nslot_width = 0.018\n{}",
        settings(700)
    );
    let case = parse_case(&text, "dd.toml", &[]).expect("a valid draw-down case");
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("dd");
    let summary = run_dir::finished(&case, &dir, 1, false);
    assert_eq!(summary.stop_reason, StopReason::Drained);
    assert!(
        summary.discharge_rate > 0.0,
        "W = {}",
        summary.discharge_rate
    );
    let shelves = summary.draw_down.expect("a draw-down test has its shelves");
    for angle in [shelves.left_angle_deg, shelves.right_angle_deg] {
        assert!(angle > 15.0 && angle < 60.0, "{shelves:?}");
    }
    assert!(shelves.shelf_angle_error_deg > 0.0 && shelves.shelf_angle_error_deg.is_finite());
    // What is left is what did not leave: the fill's mass less the mass discharged.
    let fill = 700.0 * 2500.0 * std::f64::consts::PI / 6.0 * 0.003f64.powi(3);
    assert!(shelves.residual_mass > 0.1 * fill, "{shelves:?}");
    assert!((shelves.residual_mass + summary.discharged_mass - fill).abs() < 0.02 * fill);
    assert!(dir.join("shelf_surface.csv").is_file());
}

/// Rods cannot roll: 250 rods of aspect ratio 2 (3 mm equal-volume diameter, three beads)
/// without rolling friction stand as a heap on the plate, where spheres without it spread
/// over the plate and off its edge. Measured with this case: rods 12.5° ± 1.9°, 235 of the
/// 250 kept on the plate; the same case of 250 spheres leaves 68 on it, one layer with no
/// flank to fit. The bounds, an angle above 5° (four errors below the rods') and four fifths
/// of the grains on the plate, lie between the two. The heap counts grains, not member
/// spheres (750 here), and its surface is fitted to the members' tops.
#[test]
fn rods_without_rolling_friction_stand_as_a_heap_where_spheres_spread() {
    let text = "version = 1\nseed = 3\n[geometry]\nkind = \"heap\"\ncylinder_radius = 0.012\n\
         height = 0.06\nplate_radius = 0.04\nlift_speed = 0.05\n[particles]\ncount = 250\n\
         diameter = 0.003\nshape = { kind = \"rod\", aspect_ratio = 2.0 }\n\
         [time]\ntime_step = 3.8e-6\n[contact]\nrolling_friction = 0.0\n\
         [wall]\nrolling_friction = 0.0\n[protocol]\ntime_limit = 3.0\n\
         settle_kinetic_energy = 1.0e-8\n[output]\ncheckpoint_interval = 0.0\n\
         vtu_interval = 0.0\n";
    let case = parse_case(text, "rods-heap.toml", &[]).expect("a valid heap of rods");
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("rods-heap");
    let summary = run_dir::finished(&case, &dir, 1, false);
    assert_eq!(summary.stop_reason, StopReason::AtRest);
    let repose = summary.repose.expect("a heap has its angle");
    assert!(repose.angle_deg > 5.0, "{repose:?}");
    assert!(
        repose.particles <= 250 && repose.particles >= 200,
        "{repose:?}"
    );
}

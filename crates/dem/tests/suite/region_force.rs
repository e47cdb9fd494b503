//! The external force on a region's particles (docs/physics.md §6.4): π r² τ on each free
//! particle whose centre lies inside, nothing on the others, and nothing once removed.

use dem::{
    DVec3, ForceRegion, Interaction, Material, ParticleInit, RegionForce, Simulation,
    SimulationConfig,
};

const RADIUS: f64 = 1.5e-3;

/// Two free spheres far apart, no walls: one inside a box around the origin, one 50 mm
/// away. Returns the simulation and their tags (inside, outside).
fn two_spheres() -> (Simulation, u64, u64) {
    let mut sim = Simulation::new(SimulationConfig::new(2.5e-6)).expect("valid configuration");
    let id = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .expect("valid material");
    let inside = sim
        .add_particle(ParticleInit::at_rest(DVec3::ZERO, RADIUS, id))
        .expect("valid particle");
    let outside = sim
        .add_particle(ParticleInit::at_rest(
            DVec3::new(0.05, 0.0, 0.0),
            RADIUS,
            id,
        ))
        .expect("valid particle");
    (sim, inside, outside)
}

#[test]
fn the_region_force_accelerates_only_the_particles_inside() {
    let (mut sim, inside, outside) = two_spheres();
    let mass = sim.particles().masses()[0];
    // Three times the weight, upward, on a sphere of the region: net 2 g up.
    let traction = 3.0 * mass * 9.81 / (std::f64::consts::PI * RADIUS * RADIUS);
    let force = RegionForce {
        region: ForceRegion::Box {
            min: DVec3::splat(-0.01),
            max: DVec3::splat(0.01),
        },
        traction: DVec3::new(0.0, 0.0, traction),
    };
    sim.set_region_force(Some(force)).expect("a valid force");
    let v = |sim: &Simulation, tag: u64| {
        let k = sim.particles().index_of(tag).expect("present");
        sim.particles().velocities()[k].z
    };
    // The force enters from the first evaluation after it was set: the step after the call
    // gives its first half kick with the forces evaluated before it. From then on every
    // half kick carries it.
    sim.run(1).expect("free flight");
    let (vi, vo) = (v(&sim, inside), v(&sim, outside));
    let steps = 400;
    sim.run(steps).expect("free flight");
    let t = steps as f64 * 2.5e-6;
    // Constant accelerations: velocity Verlet is exact for them up to rounding, so 1e-9
    // relative leaves only the rounding of 400 additions.
    let (up, down) = (2.0 * 9.81 * t, -9.81 * t);
    let (dvi, dvo) = (v(&sim, inside) - vi, v(&sim, outside) - vo);
    assert!((dvi - up).abs() < 1e-9 * up, "inside: {dvi} vs {up}");
    assert!((dvo - down).abs() < 1e-9 * up, "outside: {dvo} vs {down}");
    // Removed, the force stops acting: the sphere inside decelerates at g.
    sim.set_region_force(None).expect("removal");
    sim.run(1).expect("free flight");
    let vi = v(&sim, inside);
    sim.run(steps).expect("free flight");
    let dvi = v(&sim, inside) - vi;
    assert!((dvi - down).abs() < 1e-9 * up, "removed: {dvi} vs {down}");
}

#[test]
fn a_cylinder_region_holds_its_axis_and_not_beyond_its_radius() {
    let region = ForceRegion::Cylinder {
        axis: [0.0, 0.0],
        radius: 0.01,
        bottom: -0.001,
        top: 0.02,
    };
    assert!(region.contains(DVec3::new(0.0, 0.0, 0.0)));
    assert!(region.contains(DVec3::new(0.007, 0.007, 0.019)));
    assert!(
        !region.contains(DVec3::new(0.0075, 0.0075, 0.0)),
        "outside the radius"
    );
    assert!(
        !region.contains(DVec3::new(0.0, 0.0, -0.002)),
        "below the bottom"
    );
}

#[test]
fn bad_region_forces_are_refused_and_change_nothing() {
    let (mut sim, _, _) = two_spheres();
    let empty = RegionForce {
        region: ForceRegion::Box {
            min: DVec3::ZERO,
            max: DVec3::new(0.01, 0.0, 0.01),
        },
        traction: DVec3::Z,
    };
    let infinite = RegionForce {
        region: ForceRegion::Cylinder {
            axis: [0.0, 0.0],
            radius: 0.01,
            bottom: 0.0,
            top: 0.01,
        },
        traction: DVec3::new(0.0, 0.0, f64::INFINITY),
    };
    for bad in [empty, infinite] {
        assert!(sim.set_region_force(Some(bad)).is_err(), "{bad:?}");
        assert!(sim.region_force().is_none());
    }
}

/// A rod of aspect ratio 3 (five overlapping beads) wholly inside the region receives the
/// force of the sphere of its volume, not the sum of its beads' cross-sections (about twice
/// as much, counting their overlaps): with a traction of three of its equal-volume sphere's
/// weights it rises at 2 g, like a sphere of that volume, and, lying level and symmetric
/// about its centre, keeps its orientation.
#[test]
fn a_clump_inside_receives_the_force_of_its_equal_volume_sphere() {
    let mut sim = Simulation::new(SimulationConfig::new(2.5e-6)).expect("valid configuration");
    let id = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .expect("valid material");
    let rod = dem::clump::ClumpShape::rod(3.0, 5, 2.0 * RADIUS).expect("a rod");
    sim.add_clump(
        &rod,
        id,
        (DVec3::ZERO, dem::DQuat::IDENTITY),
        (DVec3::ZERO, DVec3::ZERO),
    )
    .expect("valid clump");
    let body = rod.body(Material::fan2023().density);
    let equal = (0.75 * body.volume / std::f64::consts::PI).cbrt();
    // The rod has the volume of the sphere of diameter 2 RADIUS (the shape's scaling).
    assert!((equal / RADIUS - 1.0).abs() < 1e-9, "r_v = {equal}");
    let squares: f64 = body.members.iter().map(|&(_, r)| r * r).sum();
    assert!(
        squares > 1.5 * equal * equal,
        "the beads' cross-sections overlap"
    );
    let traction = 3.0 * body.mass * 9.81 / (std::f64::consts::PI * equal * equal);
    sim.set_region_force(Some(RegionForce {
        region: ForceRegion::Box {
            min: DVec3::splat(-0.01),
            max: DVec3::splat(0.01),
        },
        traction: DVec3::new(0.0, 0.0, traction),
    }))
    .expect("a valid force");
    sim.run(1).expect("free flight");
    let v0 = sim.clumps().velocities()[0].z;
    let q0 = sim.clumps().orientations()[0];
    let steps = 400;
    sim.run(steps).expect("free flight");
    let t = steps as f64 * 2.5e-6;
    // Constant acceleration: exact to the rounding of 400 additions, as for the sphere.
    let (dv, up) = (sim.clumps().velocities()[0].z - v0, 2.0 * 9.81 * t);
    assert!((dv - up).abs() < 1e-9 * up, "{dv} vs {up}");
    // The beads' shares are symmetric about the centre: no torque beyond rounding.
    let turned = sim.clumps().orientations()[0].angle_between(q0);
    assert!(turned < 1e-9, "turned by {turned} rad");
}

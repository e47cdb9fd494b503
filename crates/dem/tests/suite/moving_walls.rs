//! Walls that move (docs/physics.md §5.4) and curved and meshed walls on several threads:
//! a displaced wall carries a sphere with it, a turning wall turns by ω t, a spinning
//! surface drags a sphere along ω × r, and a pile in a silo of a cylinder, a cone and a mesh
//! floor gives the same bits, wall loads included, on one and two threads. The silo golden
//! (`golden_silo.rs`) pins a larger silo's bits on one, two and four threads, its bodies cut
//! into several ranges, under both tangential laws.

use crate::common;

use common::RADIUS;
use dem::{
    DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig, Wall, WallId,
    WallMaterial, WallMotion, WallShape,
};

fn one_sphere(wall: Wall, position: DVec3) -> (Simulation, WallId) {
    let mut config = SimulationConfig::new(2.5e-6);
    config.resort_every = 0;
    let mut sim = Simulation::new(config).unwrap();
    let m = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .unwrap();
    let id = sim.add_wall(wall).unwrap();
    sim.add_particle(ParticleInit::at_rest(position, RADIUS, m))
        .unwrap();
    (sim, id)
}

fn floor() -> Wall {
    Wall::plane(
        DVec3::ZERO,
        DVec3::Z,
        WallMaterial::Rigid,
        Interaction::fan2023(),
    )
    .unwrap()
}

#[test]
fn a_rising_floor_lifts_the_sphere_resting_on_it() {
    // An elevator: the floor moves up at 0.02 m/s for 0.05 s. The plane's offset must be
    // v t up to round-off of the 20 000 additions (1e-15 relative each), and the sphere
    // resting on it must have risen by the same 1 mm within its contact's change of
    // overlap, which the constant extra force m v̇ = 0 leaves at the weight's (≈ 1e-7 m).
    let (mut sim, id) = one_sphere(floor(), DVec3::new(0.0, 0.0, RADIUS - 1e-7));
    sim.run(4000).unwrap(); // settle on the plane at rest
    let z0 = sim.particles().positions()[0].z;
    sim.set_wall_motion(
        id,
        WallMotion {
            velocity: DVec3::new(0.0, 0.0, 0.02),
            displaced: true,
            ..WallMotion::default()
        },
    )
    .unwrap();
    sim.run(20_000).unwrap();
    let WallShape::Plane(p) = sim.wall(id).unwrap().shape() else {
        panic!("a plane")
    };
    assert!((p.point().z - 1e-3).abs() < 1e-12, "{}", p.point().z);
    let rise = sim.particles().positions()[0].z - z0;
    assert!((rise - 1e-3).abs() < 2e-7, "rose {rise}");
}

#[test]
fn a_turning_wall_turns_by_omega_t_about_its_centre() {
    // A plane through (1, 0, 0) with normal z, displaced at ω = 2 rad/s about the y axis
    // through the origin, for 0.01 s (4000 steps): its normal is turned by 0.02 rad, its
    // point carried on the circle of radius 1. Round-off of 4000 small rotations: 1e-12.
    let (mut sim, id) = one_sphere(floor(), DVec3::new(5.0, 5.0, 5.0));
    sim.translate_wall(id, DVec3::X).unwrap();
    sim.set_wall_motion(
        id,
        WallMotion {
            angular_velocity: DVec3::new(0.0, 2.0, 0.0),
            displaced: true,
            ..WallMotion::default()
        },
    )
    .unwrap();
    sim.run(4000).unwrap();
    let WallShape::Plane(p) = sim.wall(id).unwrap().shape() else {
        panic!("a plane")
    };
    let angle = 0.02f64;
    let normal = DVec3::new(angle.sin(), 0.0, angle.cos());
    assert!(p.normal().distance(normal) < 1e-12, "{}", p.normal());
    let point = DVec3::new(angle.cos(), 0.0, -angle.sin());
    assert!(p.point().distance(point) < 1e-12, "{}", p.point());
}

#[test]
fn a_spinning_turntable_drags_a_sphere_along_omega_cross_r() {
    // A turntable: the floor spins at 5 rad/s about z without being displaced. A sphere at
    // rest 2 cm from the axis is dragged along ω × r = (0, 0.1, 0) m/s: after 1 ms of
    // sliding its velocity points along +y (within 1 % in angle: the surface velocity's
    // direction changes by 0.5 mrad over the sphere's travel) and has not left the floor.
    let x = DVec3::new(0.02, 0.0, RADIUS - 1e-7);
    let (mut sim, id) = one_sphere(floor(), x);
    sim.set_wall_motion(
        id,
        WallMotion {
            angular_velocity: DVec3::new(0.0, 0.0, 5.0),
            ..WallMotion::default()
        },
    )
    .unwrap();
    sim.run(400).unwrap();
    let v = sim.particles().velocities()[0];
    assert!(v.y > 1e-3, "dragged along +y: {v}");
    assert!(v.x.abs() < 0.01 * v.y, "{v}");
    assert!(sim.contacts().particle_wall == 1);
}

/// A small silo: a cylinder over a cone over a mesh floor, with 12 layers of spheres on a
/// square lattice of side 5, less the lattice points farther than 9.5 radii from the axis.
fn silo(threads: usize) -> (Simulation, [WallId; 3]) {
    let (layers, half) = (12, 2);
    let mut config = SimulationConfig::new(2.5e-6);
    config.threads = threads;
    let mut sim = Simulation::new(config).unwrap();
    let i = Interaction::fan2023();
    let m = sim.add_material(Material::fan2023(), i).unwrap();
    let r = 12.0 * RADIUS;
    let cyl = Wall::cylinder(
        DVec3::new(0.0, 0.0, 4.0 * RADIUS),
        DVec3::Z,
        60.0 * RADIUS,
        r,
        WallMaterial::Rigid,
        i,
    )
    .unwrap();
    let cone = Wall::frustum(
        DVec3::ZERO,
        DVec3::Z,
        4.0 * RADIUS,
        [0.6 * r, r],
        WallMaterial::Rigid,
        i,
    )
    .unwrap();
    let tiles = common::square_floor(r, 12);
    let mesh = Wall::mesh(&tiles, WallMaterial::Rigid, i).unwrap();
    let ids = [
        sim.add_wall(cyl).unwrap(),
        sim.add_wall(cone).unwrap(),
        sim.add_wall(mesh).unwrap(),
    ];
    let mut k = 0;
    for layer in 0..layers {
        for p in -half..=half {
            for q in -half..=half {
                if ((p * p + q * q) as f64).sqrt() * 2.6 > 9.5 {
                    continue;
                }
                let x = DVec3::new(p as f64, q as f64, 0.0) * 2.6 * RADIUS
                    + DVec3::new(0.1 * (k % 7) as f64, 0.07 * (k % 5) as f64, 0.0) * RADIUS
                    + DVec3::new(0.0, 0.0, (6.0 + 2.6 * layer as f64) * RADIUS);
                sim.add_particle(ParticleInit::at_rest(x, RADIUS, m))
                    .unwrap();
                k += 1;
            }
        }
    }
    (sim, ids)
}

#[test]
fn a_silo_of_curved_and_meshed_walls_gives_the_same_bits_on_one_and_two_threads() {
    // 300 spheres fall into the silo and pile up for 0.15 s: every position, velocity and
    // spin bit and every wall's load must agree between one thread and two.
    let (mut one, ids) = silo(1);
    let (mut two, _) = silo(2);
    // The cylinder and the cone book their element loads in bands along the axis.
    for sim in [&mut one, &mut two] {
        for &id in &ids[..2] {
            sim.set_wall_bands(id, 7).unwrap();
        }
    }
    for _ in 0..60 {
        one.run(1000).unwrap();
        two.run(1000).unwrap();
    }
    assert!(
        one.contacts().particle_wall > 50,
        "the pile must rest on the walls"
    );
    assert_eq!(common::bits_by_tag(&one), common::bits_by_tag(&two));
    for id in ids {
        let (a, b) = (one.wall_load(id).unwrap(), two.wall_load(id).unwrap());
        assert_eq!(a, b);
        // Per band and per triangle too: the several threads' bookings are replayed in
        // the one thread's order.
        let (a, b) = (
            one.surface_loads(id).unwrap(),
            two.surface_loads(id).unwrap(),
        );
        assert_eq!(a, b);
        assert!(a.elements.iter().any(|e| e.normal_impulse > 0.0) || id == ids[0]);
    }
    // The floor and the cone carry load, and the loads are the floor's weight's order.
    let floor = one.wall_load(ids[2]).unwrap().force.z;
    assert!(floor < 0.0, "the pile presses the floor down: {floor}");
}

//! A wall put in another's place (`Simulation::replace_wall`, what a container rebuilt
//! around a settled bed uses): the contacts with the replaced wall forget their history,
//! while those with every other wall, and the particles, continue bit for bit.

use crate::common;

use common::RADIUS;
use dem::{
    DVec3, DemError, Interaction, Material, ParticleInit, Simulation, SimulationConfig, Wall,
    WallId, WallMaterial,
};

fn plane(point: DVec3, normal: DVec3) -> Wall {
    Wall::plane(point, normal, WallMaterial::Rigid, Interaction::fan2023()).unwrap()
}

/// A sphere at rest on a floor (wall 0) beside a side wall it does not touch (wall 1),
/// under gravity tilted by 0.3 % of g along x: static friction holds it, so its contact
/// with the floor stores a tangential displacement.
fn resting_sphere() -> Simulation {
    let mut config = SimulationConfig::new(2.5e-6);
    config.resort_every = 0;
    config.gravity = DVec3::new(0.03, 0.0, -9.81);
    let mut sim = Simulation::new(config).unwrap();
    let m = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .unwrap();
    sim.add_wall(plane(DVec3::ZERO, DVec3::Z)).unwrap();
    sim.add_wall(plane(DVec3::new(0.05, 0.0, 0.0), -DVec3::X))
        .unwrap();
    sim.add_particle(ParticleInit::at_rest(
        DVec3::new(0.0, 0.0, RADIUS - 1e-7),
        RADIUS,
        m,
    ))
    .unwrap();
    sim.run(20_000).unwrap();
    sim
}

/// Position, velocity and spin of the sphere, as bits.
fn motion(sim: &Simulation) -> [DVec3; 3] {
    let p = sim.particles();
    [
        p.positions()[0],
        p.velocities()[0],
        p.angular_velocities()[0],
    ]
}

#[test]
fn replacing_a_wall_resets_only_its_own_contacts_history() {
    let settled = resting_sphere();
    assert!(
        settled.wall_impulse(WallId(0)).unwrap().force.z < 0.0,
        "the sphere must rest on the floor"
    );
    let copy = || Simulation::from_state(settled.state().clone(), 1).unwrap();

    let mut reference = copy();
    reference.run(2_000).unwrap();

    // The side wall has no contact: putting an equal wall in its place changes no bit of
    // the sphere's motion (the list rebuild it forces carries the floor's history exactly).
    let mut side = copy();
    side.replace_wall(WallId(1), plane(DVec3::new(0.05, 0.0, 0.0), -DVec3::X))
        .unwrap();
    assert_eq!(side.wall_slots(), 2);
    side.run(2_000).unwrap();
    assert_eq!(motion(&side), motion(&reference));

    // An equal floor in the floor's place: the contact starts without its tangential
    // displacement, so friction holds less until the spring has built up again, and the
    // sphere, which creeps down the tilt (the rolling law's chatter, docs/physics.md §4.2),
    // slips further than with its history kept.
    let mut floor = copy();
    floor
        .replace_wall(WallId(0), plane(DVec3::ZERO, DVec3::Z))
        .unwrap();
    assert_eq!(
        floor.wall_impulse(WallId(0)).unwrap().force,
        DVec3::ZERO,
        "the new floor's load integral starts from nothing"
    );
    floor.run(2_000).unwrap();
    let (moved, held) = (motion(&floor)[0], motion(&reference)[0]);
    assert!(
        moved.x > held.x,
        "without its spring the contact must let the sphere slip further down the tilt: \
         x = {} m against {} m",
        moved.x,
        held.x
    );
    // It still rests on the new floor: the normal contact needs no history (the overlap,
    // some 1e-7 m, is the same within a thousandth).
    assert!(
        (moved.z - held.z).abs() < 1e-10,
        "{} against {}",
        moved.z,
        held.z
    );
}

#[test]
fn replacing_a_wall_that_was_never_added_is_refused() {
    let mut sim = resting_sphere();
    let err = sim
        .replace_wall(WallId(2), plane(DVec3::ZERO, DVec3::Z))
        .unwrap_err();
    assert!(matches!(err, DemError::UnknownWall(2)), "{err:?}");
    // A removed wall's handle can take a wall again.
    sim.remove_wall(WallId(1)).unwrap();
    sim.replace_wall(WallId(1), plane(DVec3::new(0.05, 0.0, 0.0), -DVec3::X))
        .unwrap();
    assert!(sim.wall(WallId(1)).is_some());
    sim.run(10).unwrap();
}

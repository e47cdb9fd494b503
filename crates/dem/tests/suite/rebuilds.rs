//! When the neighbour lists are rebuilt (`Simulation::lists_may_miss`): never so late that a
//! contact is missing from them, and not before the bodies' relative motion asks for it.

use crate::common;

use common::{bits_by_tag, RADIUS};
use dem::{
    DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig, Wall, WallMaterial,
};

/// The skin of the hopper study, 0.1 d [m].
const SKIN: f64 = 0.3e-3;

/// The 1000-sphere pile of `determinism.rs` (random velocities up to 0.5 m/s, gravity, a
/// closed box of six planes), with the given skin and without re-sorting, so that the
/// bodies keep their indices whatever the list builds.
fn pile(skin: f64) -> Simulation {
    let mut config = SimulationConfig::new(2.5e-6);
    config.skin = skin;
    config.resort_every = 0;
    common::pile(config).build()
}

/// Lists rebuilt by the skin's bounds must hold every contact that lists rebuilt at every
/// step hold. With a skin of 1 fm every displacement of the bodies fires a build, so that
/// run is the reference. Without re-sorting the forces do not depend on which candidates a
/// list holds beyond the touching ones (they are filtered out, and the touching ones are
/// resolved in the same order), so a list that missed a contact, even for one step, would
/// change the trajectory; the comparison is exact.
#[test]
fn late_builds_miss_no_contact_of_builds_at_every_step() {
    let (mut lazy, mut eager) = (pile(SKIN), pile(1e-15));
    let (contacts, _) = compare(&mut lazy, &mut eager, (20, 100));
    // The comparison means something only if bodies collided and the lazy lists were kept
    // across many steps: at most one build per 10 steps (the speeds reach 0.5 m/s plus the
    // fall, 1.25 µm a step, so 2 max |Δx| reaches the 0.3 mm skin after at least 120 steps).
    assert!(contacts > 100, "{contacts} contacts: the pile must collide");
    assert!(
        lazy.rebuilds() * 10 < lazy.steps() && eager.rebuilds() + 10 > eager.steps(),
        "lazy {} and eager {} builds in {} steps",
        lazy.rebuilds(),
        eager.rebuilds(),
        lazy.steps()
    );
}

/// Gap between the surfaces that approach in the head-on tests [m]: more than the skin, so
/// that the first lists do not hold the contact.
const GAP: f64 = 0.4e-3;

/// Speed of the head-on tests' bodies [m/s].
const SPEED: f64 = 0.5;

/// A square layer of 8 × 8 spheres 3.2 mm apart (no two touching, every neighbour within
/// the 3.3 mm cutoff) at height `z` [m], moving along z at `vz` [m/s].
fn layer(sim: &mut Simulation, material: dem::MaterialId, z: f64, vz: f64) {
    for k in 0..64 {
        let at = DVec3::new((k % 8) as f64 * 3.2e-3, (k / 8) as f64 * 3.2e-3, z);
        let mut init = ParticleInit::at_rest(at, RADIUS, material);
        init.velocity = DVec3::new(0.0, 0.0, vz);
        sim.add_particle(init).expect("valid particle");
    }
}

/// An empty simulation without gravity, skin `skin` [m], no re-sorting, one material.
fn empty(skin: f64) -> (Simulation, dem::MaterialId) {
    let mut config = SimulationConfig::new(2.5e-6);
    config.skin = skin;
    config.resort_every = 0;
    config.gravity = DVec3::ZERO;
    let mut sim = Simulation::new(config).expect("valid configuration");
    let material = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .expect("valid material");
    (sim, material)
}

/// Runs `lazy` and `eager` side by side, `rounds` runs of `steps` steps each, and asserts
/// after each that they are bit-identical; returns the largest pair and wall contact
/// counts seen.
fn compare(
    lazy: &mut Simulation,
    eager: &mut Simulation,
    (rounds, steps): (u64, u64),
) -> (usize, usize) {
    let (mut pairs, mut walls) = (0, 0);
    for _ in 0..rounds {
        lazy.run(steps).expect("lazy run");
        eager.run(steps).expect("eager run");
        pairs = pairs.max(lazy.contacts().particle_particle);
        walls = walls.max(lazy.contacts().particle_wall);
        assert!(
            bits_by_tag(lazy) == bits_by_tag(eager),
            "runs diverged by t = {} s",
            lazy.time()
        );
    }
    (pairs, walls)
}

/// Two layers meeting head-on, 2R + 0.4 mm apart at 1 m/s: the pair bound (the box of the
/// displacements, ±v t along z, has diagonal 2 v t) must rebuild the lists before the gap
/// closes after 160 steps. A bound three times too loose misses the first contacts.
#[test]
fn layers_meeting_head_on_are_listed_before_they_touch() {
    let build = |skin| {
        let (mut sim, material) = empty(skin);
        layer(&mut sim, material, 0.0, SPEED);
        layer(&mut sim, material, 2.0 * RADIUS + GAP, -SPEED);
        sim
    };
    let (pairs, _) = compare(&mut build(SKIN), &mut build(1e-15), (40, 10));
    assert!(
        pairs >= 64,
        "{pairs} pair contacts: the layers must collide"
    );
}

/// A layer moving as a whole onto a floor 0.4 mm below it: the box of its displacements
/// has no extent, so only the wall bound, max |Δx| + wall drift > s, can rebuild the lists
/// before the layer lands after 320 steps. A bound three times too loose misses the landing.
#[test]
fn a_layer_moving_onto_a_wall_is_listed_before_it_lands() {
    let build = |skin| {
        let (mut sim, material) = empty(skin);
        let floor = Wall::plane(
            DVec3::ZERO,
            DVec3::Z,
            WallMaterial::Elastic(Material::fan2023()),
            Interaction::fan2023(),
        )
        .expect("valid plane");
        sim.add_wall(floor).expect("valid wall");
        layer(&mut sim, material, RADIUS + GAP, -SPEED);
        sim
    };
    let (_, walls) = compare(&mut build(SKIN), &mut build(1e-15), (60, 10));
    assert!(walls >= 64, "{walls} wall contacts: the layer must land");
}

/// A packing that translates as a whole has no relative motion, so its lists stay valid
/// however far it goes: the box of its displacements has no extent. The usual bound,
/// 2 max |Δx| > s, would rebuild them every 0.15 mm. There are no walls, whose bound does
/// depend on the bodies' own displacement.
#[test]
fn a_packing_in_rigid_translation_keeps_its_lists() {
    let mut config = SimulationConfig::new(2.5e-6);
    config.skin = SKIN;
    config.gravity = DVec3::ZERO;
    let mut sim = Simulation::new(config).expect("valid configuration");
    let material = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .expect("valid material");
    // 5 × 5 × 5 spheres 3.2 mm apart: every neighbour within the 3.3 mm cutoff, none touching.
    let velocity = DVec3::new(0.6, -0.3, 0.2);
    for k in 0..125 {
        let site = DVec3::new((k % 5) as f64, ((k / 5) % 5) as f64, (k / 25) as f64);
        let mut init = ParticleInit::at_rest(site * 3.2e-3, RADIUS, material);
        init.velocity = velocity;
        sim.add_particle(init).expect("valid particle");
    }
    // 2000 steps at 0.7 m/s: 3.5 mm, about 23 skins.
    sim.run(2000).expect("run");
    let moved = sim.particles().positions()[0].length();
    assert!(moved > 10.0 * SKIN, "moved {moved} m");
    // Exactly the first build: the spheres move in lockstep (the same velocity, added to
    // positions by the same products), so every displacement is the same and the box's
    // diagonal is zero, or a few roundings of 3.5 mm, far below the skin.
    assert_eq!(sim.rebuilds(), 1, "the lists were rebuilt");
    assert_eq!(
        sim.contacts().particle_particle,
        0,
        "no sphere touches another"
    );
}

/// The bounds that spare the displacement measures on one thread (`reach.rs`) must leave
/// every list build where the measures at every step put it. Two threads measure at every
/// step, so the builds of the two runs must fall at the same steps, and the runs must agree
/// to the bit. The pile is jolted (one sphere thrown at 3 m/s, so that a step's reach
/// outruns the pass's guess of it) and a wall moves by 2 µm a step for a while (the wall
/// branch of the test).
#[test]
fn bounded_measures_build_the_lists_at_the_steps_of_measures_at_every_step() {
    let build = |threads| {
        let mut config = SimulationConfig::new(2.5e-6);
        config.skin = SKIN;
        config.threads = threads;
        common::pile(config).build()
    };
    let (mut bounded, mut measured) = (build(1), build(2));
    let wall = dem::WallId(0);
    for step in 0..1500 {
        if step == 400 {
            for sim in [&mut bounded, &mut measured] {
                sim.set_particle_motion(17, DVec3::new(0.0, 0.0, 3.0), DVec3::ZERO);
            }
        }
        if (800..1000).contains(&step) {
            for sim in [&mut bounded, &mut measured] {
                sim.translate_wall(wall, DVec3::new(2e-6, 0.0, 0.0))
                    .expect("the wall moves");
            }
        }
        bounded.run(1).expect("one thread");
        measured.run(1).expect("two threads");
        assert_eq!(
            bounded.rebuilds(),
            measured.rebuilds(),
            "builds differ after step {step}"
        );
    }
    // Exact equality, as in determinism.rs.
    assert!(bits_by_tag(&bounded) == bits_by_tag(&measured));
    // Enough builds for the comparison to mean something: the pile's spread of speeds
    // alone builds about every 100 steps.
    assert!(bounded.rebuilds() > 10, "{} builds", bounded.rebuilds());
}

/// A sphere thrown from rest, at 200 m/s (0.5 mm a step, more than the 0.3 mm skin), must
/// set a list build off in the very step it moves, although the pass, guessing its reach
/// from the steps before (nothing moved), left the measures out: the bounds then fail and
/// the displacements are measured after all. Two threads, which measure at every step,
/// give the reference.
#[test]
fn a_sudden_throw_is_measured_in_the_step_it_happens() {
    let build = |threads| {
        let (mut sim, material) = empty(SKIN);
        sim.set_threads(threads)
            .expect("a pool of this size starts");
        for x in [0.0, 0.01] {
            let init = ParticleInit::at_rest(DVec3::new(x, 0.0, 0.0), RADIUS, material);
            sim.add_particle(init).expect("valid particle");
        }
        sim.run(50).expect("at rest");
        sim.set_particle_motion(1, DVec3::new(200.0, 0.0, 0.0), DVec3::ZERO);
        sim
    };
    let (mut bounded, mut measured) = (build(1), build(2));
    let before = bounded.rebuilds();
    assert_eq!(before, measured.rebuilds());
    bounded.run(1).expect("one thread");
    measured.run(1).expect("two threads");
    assert_eq!(measured.rebuilds(), before + 1, "the throw needs a build");
    assert_eq!(
        bounded.rebuilds(),
        measured.rebuilds(),
        "the build was missed"
    );
}

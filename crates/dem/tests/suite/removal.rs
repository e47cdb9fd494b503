//! Removing particles mid-run keeps the contact memory of the survivors: their tangential and
//! rolling histories are carried across the change of indices by tag.

use crate::common;

use common::bits_by_tag;
use dem::{
    DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig, Wall, WallMaterial,
};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

const RADIUS: f64 = 1.5e-3;

/// A pile of 60 Table-1 spheres settled on a floor under gravity tilted by 10° (so every contact
/// carries a tangential load), plus one unrelated sphere resting on the floor 50 mm away.
/// Returns the simulation and the unrelated sphere's tag. Re-sorting is off so that the
/// survivors' force sums keep their order and the comparison can be exact.
fn settled_pile() -> (Simulation, u64) {
    let mut config = SimulationConfig::new(2.5e-6);
    let tilt = 10.0_f64.to_radians();
    config.gravity = 9.81 * DVec3::new(tilt.sin(), 0.0, -tilt.cos());
    config.resort_every = 0;
    let mut sim = Simulation::new(config).expect("valid configuration");
    let material = Material::fan2023();
    let id = sim
        .add_material(material, Interaction::fan2023())
        .expect("valid material");
    let wall = |p: DVec3, n: DVec3| {
        Wall::plane(
            p,
            n,
            WallMaterial::Elastic(material),
            Interaction::fan2023(),
        )
        .expect("valid plane")
    };
    sim.add_wall(wall(DVec3::ZERO, DVec3::Z))
        .expect("valid wall");
    // A downhill stop, so the pile rests against it rather than sliding away.
    sim.add_wall(wall(DVec3::new(0.012, 0.0, 0.0), -DVec3::X))
        .expect("valid wall");
    // Side walls keep the three rows from spreading sideways.
    sim.add_wall(wall(DVec3::new(0.0, -1.7e-3, 0.0), DVec3::Y))
        .expect("valid wall");
    sim.add_wall(wall(DVec3::new(0.0, 8.5e-3, 0.0), -DVec3::Y))
        .expect("valid wall");
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    for k in 0..60 {
        let (i, j, l) = (k % 4, (k / 4) % 3, k / 12);
        let jitter = DVec3::new(rng.gen_range(-0.1..0.1), rng.gen_range(-0.1..0.1), 0.0) * RADIUS;
        let p = DVec3::new(i as f64, j as f64, l as f64 + 0.5) * 3.4e-3 + jitter;
        sim.add_particle(ParticleInit::at_rest(p, RADIUS, id))
            .expect("valid particle");
    }
    let far = sim
        .add_particle(ParticleInit::at_rest(
            DVec3::new(-0.05, 0.0, RADIUS),
            RADIUS,
            id,
        ))
        .expect("valid particle");
    sim.run(80_000).expect("the pile settles");
    (sim, far)
}

fn without(bits: Vec<(u64, [u64; 9])>, tag: u64) -> Vec<(u64, [u64; 9])> {
    bits.into_iter().filter(|e| e.0 != tag).collect()
}

#[test]
fn removing_an_unrelated_particle_keeps_the_survivors_contact_history() {
    let (sim, far) = settled_pile();
    assert!(
        sim.contacts().particle_particle > 60,
        "the pile must be in contact ({:?})",
        sim.contacts()
    );
    let mut kept = Simulation::from_state(sim.state().clone(), 1).expect("restores");
    let mut pruned = Simulation::from_state(sim.state().clone(), 1).expect("restores");
    let removed = pruned.remove_particles(|k, p| p.tags()[k] == far);
    assert_eq!(removed.len(), 1);
    assert_eq!(removed[0].tag, far);
    kept.run(4000).expect("runs");
    pruned.run(4000).expect("runs");
    // Exact equality: the far sphere never touches the pile, so only lost or misassigned
    // history could change the survivors' bits.
    assert!(
        without(bits_by_tag(&kept), far) == bits_by_tag(&pruned),
        "the survivors diverged after the removal"
    );
}

#[test]
fn the_pile_depends_on_its_contact_history() {
    // Control for the test above: the same pile rebuilt from positions and velocities alone
    // (all contact memory lost) does not follow the same trajectory, so a removal that dropped
    // the history would have been caught.
    let (sim, far) = settled_pile();
    let mut kept = Simulation::from_state(sim.state().clone(), 1).expect("restores");
    let mut fresh = Simulation::new(*sim.config()).expect("valid configuration");
    let material = Material::fan2023();
    let id = fresh
        .add_material(material, Interaction::fan2023())
        .expect("valid material");
    let wall = |p: DVec3, n: DVec3| {
        Wall::plane(
            p,
            n,
            WallMaterial::Elastic(material),
            Interaction::fan2023(),
        )
        .expect("valid plane")
    };
    fresh
        .add_wall(wall(DVec3::ZERO, DVec3::Z))
        .expect("valid wall");
    fresh
        .add_wall(wall(DVec3::new(0.012, 0.0, 0.0), -DVec3::X))
        .expect("valid wall");
    fresh
        .add_wall(wall(DVec3::new(0.0, -1.7e-3, 0.0), DVec3::Y))
        .expect("valid wall");
    fresh
        .add_wall(wall(DVec3::new(0.0, 8.5e-3, 0.0), -DVec3::Y))
        .expect("valid wall");
    let p = sim.particles();
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_by_key(|&k| p.tags()[k]);
    for k in order {
        let mut init = ParticleInit::at_rest(p.positions()[k], p.radii()[k], id);
        init.velocity = p.velocities()[k];
        init.angular_velocity = p.angular_velocities()[k];
        fresh.add_particle(init).expect("valid particle");
    }
    kept.run(4000).expect("runs");
    fresh.run(4000).expect("runs");
    let (a, b) = (kept.particles(), fresh.particles());
    let mut moved: f64 = 0.0;
    for k in 0..a.len() {
        let tag = a.tags()[k];
        if tag == far {
            continue;
        }
        let j = b.index_of(tag).expect("same tags");
        moved = moved.max(a.positions()[k].distance(b.positions()[j]));
    }
    // Losing the tangential and rolling springs lets every loaded contact slip by about its
    // spring stretch before it re-sticks, and the pile rearranges a little. (Measured: the
    // largest difference after 4000 steps is 1.3e-6 m.) 1e-7 m is far above round-off
    // (positions ≈ 1e-2 m carry 2e-18 m ulps) and well below the measured effect.
    assert!(
        moved > 1e-7,
        "history had no effect ({moved:e} m): the removal test would be blind"
    );
}

//! A checkpoint (the serialised `SimulationState`) restores a run exactly: continuing from it
//! is bit-identical to never having stopped.

use crate::common;

use common::{bits_by_tag, Gas};
use dem::{
    DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig, SimulationState,
    Wall, WallMaterial,
};

fn pile() -> Gas {
    let config = SimulationConfig::new(2.5e-6);
    Gas {
        count: 343,
        spacing: 3.1e-3,
        speed: 0.5,
        interaction: Interaction::fan2023(),
        config,
        seed: 9,
    }
}

#[test]
fn checkpoint_round_trip_continues_bit_identically() {
    let mut uninterrupted = pile().build();
    uninterrupted.run(3000).expect("reference run");

    let mut first = pile().build();
    first.run(1234).expect("first leg");
    assert!(
        first.contacts().particle_particle > 0,
        "the checkpoint must hold live contact history"
    );
    // postcard stores f64 as its raw bits, so the round trip itself is exact.
    let bytes = postcard::to_allocvec(first.state()).expect("state serialises");
    drop(first);
    let state: SimulationState = postcard::from_bytes(&bytes).expect("state deserialises");
    let mut resumed = Simulation::from_state(state, 1).expect("state restores");
    resumed.run(3000 - 1234).expect("second leg");

    assert_eq!(resumed.steps(), uninterrupted.steps());
    assert_eq!(resumed.time().to_bits(), uninterrupted.time().to_bits());
    // Exact equality: any lost history, force or list state would change the bits.
    assert!(
        bits_by_tag(&resumed) == bits_by_tag(&uninterrupted),
        "resumed run diverged"
    );
}

#[test]
fn wall_loads_after_a_restore_have_the_uninterrupted_bits() {
    // Four spheres thrown down from about 20 mm onto a floor through the origin. The torque
    // quantum of the fixed-point load sums depends on how far from the origin the
    // particles were when they were added (24 mm); when the checkpoint is taken they rest
    // within 15 mm. The restored run must keep the quanta it saved.
    let build = || {
        let mut sim = Simulation::new(SimulationConfig::new(2.5e-6)).expect("valid config");
        let material = Material::fan2023();
        let id = sim
            .add_material(material, Interaction::fan2023())
            .expect("valid material");
        let floor = Wall::plane(
            DVec3::ZERO,
            DVec3::Z,
            WallMaterial::Elastic(material),
            Interaction::fan2023(),
        )
        .expect("valid plane");
        let floor = sim.add_wall(floor).expect("valid wall");
        // Apart from each other, at unequal heights and distances from the origin, so that
        // their loads round differently.
        for k in 0..4 {
            let k = k as f64;
            let x = DVec3::new(1.1e-3 + 3.7e-3 * k, 0.3e-3 + 0.7e-3 * k, 0.02 - 1.3e-3 * k);
            let mut init = ParticleInit::at_rest(x, 1.5e-3, id);
            init.velocity = DVec3::new(0.0, 0.0, -0.5);
            sim.add_particle(init).expect("valid particle");
        }
        (sim, floor)
    };
    // 100 ms: the fall takes under 30 ms, and the bounces die out in the rest.
    let (first_leg, second_leg) = (36_000, 4_000);
    let (mut uninterrupted, floor) = build();
    uninterrupted
        .run(first_leg + second_leg)
        .expect("reference run");

    let (mut first, _) = build();
    first.run(first_leg).expect("first leg");
    let reach = first
        .particles()
        .positions()
        .iter()
        .map(|x| x.length())
        .fold(0.0, f64::max);
    assert!(reach < 0.015, "the spheres rest near the origin: {reach} m");
    let bytes = postcard::to_allocvec(first.state()).expect("state serialises");
    let state: SimulationState = postcard::from_bytes(&bytes).expect("state deserialises");
    let mut resumed = Simulation::from_state(state, 1).expect("state restores");
    resumed.run(second_leg).expect("second leg");

    let (a, b) = (
        uninterrupted.wall_load(floor).expect("the floor"),
        resumed.wall_load(floor).expect("the floor"),
    );
    // The spheres press the floor down with their weight.
    assert!(a.force.z < 0.0, "the floor is loaded: {a:?}");
    let bits = |v: DVec3| v.to_array().map(f64::to_bits);
    assert_eq!(bits(a.force), bits(b.force), "force after the restore");
    assert_eq!(bits(a.torque), bits(b.torque), "torque after the restore");
}

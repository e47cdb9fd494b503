//! A checkpoint (the serialised `SimulationState`) restores a run exactly: continuing from it
//! is bit-identical to never having stopped.

mod common;

use common::{bits_by_tag, Gas};
use dem::{Interaction, Simulation, SimulationConfig, SimulationState};

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

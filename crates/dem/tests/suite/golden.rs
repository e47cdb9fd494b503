//! The engine's trajectories, pinned: a short run of the determinism pile must reproduce the
//! recorded state bit for bit. This turns "the same bits" after a change of layout or speed
//! into a test.
//!
//! When an issue changes the physics on purpose (a force law, the integrator, the order of
//! a sum), this test fails. Then, and only then:
//! 1. run `cargo test -p hopperflow-dem --test suite golden:: -- --nocapture` and take the new
//!    values from the failure message;
//! 2. replace the constants below;
//! 3. say in the commit message that the golden values were regenerated and which change
//!    of physics moved them.
//!
//! The golden of a whole hopper run (summary and output files) is in
//! `crates/study/tests/suite/golden.rs`.

use crate::common;

use common::{bits_by_tag, fnv1a, pile};
use dem::SimulationConfig;

/// Steps run: 2000 steps of 2.5 µs, 5 ms of simulated time, in which the lattice's random
/// velocities make a few hundred contacts (330; at least 100 is checked below), so every
/// sub-model acts.
const STEPS: u64 = 2000;

/// FNV-1a (64 bit) over the state's bits by tag: any change of any bit of any position,
/// velocity or spin changes it (with a chance of 2⁻⁶⁴ of a collision).
const GOLDEN_STATE_HASH: u64 = 0x0610_bd80_cff1_c1ea;
/// Particle–particle contacts after the run (a coarse, readable companion of the hash).
const GOLDEN_CONTACTS: usize = 330;

#[test]
fn pile_run_reproduces_its_golden_state() {
    golden_state(1);
}

#[test]
fn pile_run_on_two_threads_reproduces_the_same_golden_state() {
    golden_state(2);
}

fn golden_state(threads: usize) {
    let mut config = SimulationConfig::new(2.5e-6);
    config.threads = threads;
    let mut sim = pile(config).build();
    sim.run(STEPS).expect("the pile runs");
    let bits = bits_by_tag(&sim);
    let hash = fnv1a(
        bits.iter()
            .flat_map(|(tag, b)| std::iter::once(*tag).chain(b.iter().copied())),
    );
    let contacts = sim.contacts().particle_particle;
    assert!(
        contacts > 100,
        "the pile must collide for the golden to pin the contact laws ({contacts} contacts)"
    );
    assert!(
        hash == GOLDEN_STATE_HASH && contacts == GOLDEN_CONTACTS,
        "the pile's state after {STEPS} steps on {threads} thread(s) changed: hash {hash:#018x} (golden \
         {GOLDEN_STATE_HASH:#018x}), {contacts} contacts (golden {GOLDEN_CONTACTS}). \
         If the physics was changed on purpose, regenerate as the header of this file says."
    );
}

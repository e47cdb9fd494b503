//! `Simulation::run_watched` leaves each look's second half kick pending and adds it in the
//! view: what a caller sees, and where the run ends, must be the bits of `run` repeated
//! with a look after each.

use crate::common;

use common::{bits_by_tag, Gas};
use dem::{DemError, Simulation, SimulationConfig, Watched, FLAG_FROZEN, FLAG_ROTATION_LOCKED};

/// The pile of the determinism tests on `threads` threads.
fn pile(threads: usize) -> Gas {
    let mut config = SimulationConfig::new(2.5e-6);
    config.threads = threads;
    common::pile(config)
}

/// Time, and each body's tag, position and velocity, as raw bits.
type Look = (u64, Vec<(u64, [u64; 6])>);

/// What a caller sees of `w`.
fn look(w: &Watched<'_>) -> Look {
    let bodies = (0..w.len())
        .map(|k| {
            let (x, v) = (w.positions()[k], w.velocity(k));
            (
                w.tags()[k],
                [x.x, x.y, x.z, v.x, v.y, v.z].map(f64::to_bits),
            )
        })
        .collect();
    (w.time().to_bits(), bodies)
}

/// What `run(every)` repeated shows after each run, up to `n` steps.
fn looks_between_runs(sim: &mut Simulation, n: u64, every: u64) -> Vec<Look> {
    let (mut done, mut seen) = (0, Vec::new());
    while done < n {
        let m = every.min(n - done);
        sim.run(m).expect("plain run");
        done += m;
        seen.push(look(&sim.watched()));
    }
    seen
}

/// Two bodies flagged, so that the kicks take their per-body path (and one body does not
/// move at all), or none.
fn flagged(mut sim: Simulation, flags: bool) -> Simulation {
    if flags {
        sim.set_particle_flags(3, FLAG_FROZEN);
        sim.set_particle_flags(7, FLAG_ROTATION_LOCKED);
    }
    sim
}

#[test]
fn a_watched_run_sees_and_ends_with_the_bits_of_runs_between_looks() {
    for (threads, flags) in [(1, false), (2, false), (1, true)] {
        let mut watched = flagged(pile(threads).build(), flags);
        let mut plain = flagged(pile(1).build(), flags);
        let mut seen = Vec::new();
        watched
            .run_watched(1000, 97, |w| -> Result<(), DemError> {
                seen.push(look(w));
                Ok(())
            })
            .expect("watched run");
        let expected = looks_between_runs(&mut plain, 1000, 97);
        // Exact equality: the view adds the pending kick with the kick's own arithmetic.
        assert_eq!(
            seen.len(),
            11,
            "a look every 97 steps and one after the last"
        );
        assert!(
            seen == expected,
            "threads {threads}, flags {flags}: the looks differ"
        );
        assert!(
            bits_by_tag(&watched) == bits_by_tag(&plain),
            "the end states differ"
        );
        assert!(
            plain.contacts().particle_particle > 100,
            "the pile must collide"
        );
    }
}

#[test]
fn a_look_that_fails_stops_the_run_with_every_kick_done() {
    // The third look fails: the run stops there, in the state `run(97)` three times leaves
    // (velocities at the full step), and the simulation goes on as that one does.
    let mut watched = pile(1).build();
    let mut plain = pile(1).build();
    let mut looks = 0;
    let stopped = watched.run_watched(1000, 97, |_| {
        looks += 1;
        if looks == 3 {
            Err(DemError::InvalidInput("stop".into()))
        } else {
            Ok(())
        }
    });
    assert!(
        matches!(stopped, Err(DemError::InvalidInput(_))),
        "{stopped:?}"
    );
    assert_eq!(looks, 3);
    looks_between_runs(&mut plain, 3 * 97, 97);
    assert!(
        bits_by_tag(&watched) == bits_by_tag(&plain),
        "state at the failed look"
    );
    watched.run(200).expect("the run goes on");
    plain.run(200).expect("the run goes on");
    assert!(
        bits_by_tag(&watched) == bits_by_tag(&plain),
        "state after going on"
    );
}

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

/// The largest disagreement, over the bodies, between each body's force in the step and
/// its weight plus the recomputed contacts on it, relative to the largest contact force on
/// that body; and the same for each wall's load against its contacts' forces.
fn contact_sums_against_the_step(w: &Watched<'_>, gravity: dem::DVec3) -> (f64, f64, usize) {
    let contacts = w.contacts().expect("lists are current after a step");
    let n = w.len();
    let mut sum = vec![dem::DVec3::ZERO; n];
    let mut largest = vec![0.0f64; n];
    for c in &contacts.pairs {
        sum[c.i] += c.force;
        sum[c.j] -= c.force;
        largest[c.i] = largest[c.i].max(c.force.length());
        largest[c.j] = largest[c.j].max(c.force.length());
    }
    let mut on_wall = std::collections::BTreeMap::new();
    for c in &contacts.walls {
        sum[c.particle] += c.force;
        largest[c.particle] = largest[c.particle].max(c.force.length());
        *on_wall.entry(c.wall.0).or_insert(dem::DVec3::ZERO) -= c.force;
    }
    let bodies = (0..n)
        .filter(|&k| largest[k] > 0.0)
        .map(|k| (w.force(k) - w.masses()[k] * gravity - sum[k]).length() / largest[k])
        .fold(0.0, f64::max);
    let walls = on_wall
        .iter()
        .map(|(&id, f)| {
            let load = w.wall_load(dem::WallId(id)).expect("wall present").force;
            (load - *f).length() / f.length().max(1e-12)
        })
        .fold(0.0, f64::max);
    (bodies, walls, contacts.pairs.len() + contacts.walls.len())
}

#[test]
fn the_recomputed_contacts_sum_to_each_body_s_force_and_each_wall_s_load() {
    // The pile in its box, its spheres colliding and settling: every look's contacts,
    // recomputed from the state, must add up to the force the step gave each body (less
    // its weight) and to the load it gave each wall, both at the looks with the kick
    // pending and at the last, after it. Tolerance 1e-9 of the body's largest contact force
    // (of the wall's load): the batched kernel and the scalar laws agree to a few ulps, the
    // spring is read 1e-12 longer (`dem::SLIP_MARGIN`), and the velocities after the kick
    // are unkicked to round-off; the walls' loads are fixed-point sums with quanta far
    // below 1e-9 of these loads. Without the margin, the collisions' sliding first steps
    // miss by tens of per cent; with full-step velocities, by about 15 %.
    let mut sim = pile(1).build();
    let gravity = sim.config().gravity;
    assert!(
        sim.watched().contacts().is_none(),
        "no lists before the first step"
    );
    let mut seen = Vec::new();
    sim.run_watched(3000, 1000, |w| -> Result<(), DemError> {
        seen.push(contact_sums_against_the_step(w, gravity));
        Ok(())
    })
    .expect("watched run");
    let before = bits_by_tag(&sim);
    let mut plain = pile(1).build();
    plain.run(3000).expect("plain run");
    assert!(
        before == bits_by_tag(&plain),
        "asking for contacts changed the run"
    );
    assert!(
        seen.iter().all(|s| s.2 > 100),
        "the pile has contacts: {seen:?}"
    );
    assert!(seen.iter().all(|s| s.0 < 1e-9 && s.1 < 1e-9), "{seen:?}");
}

#[test]
fn contacts_follow_a_removal_and_wait_for_a_step_after_an_addition() {
    // A removal rebuilds the lists at once, carrying each survivor's histories: the view
    // must give the same contacts less the removed body's, by tag, to the bit (the state of
    // every survivor is unchanged). An addition leaves the lists stale until the next step:
    // the view must say so rather than pair the wrong bodies.
    let mut sim = pile(1).build();
    sim.run(2000).expect("run");
    let by_tag = |sim: &Simulation| {
        let w = sim.watched();
        let tags = w.tags();
        let mut pairs: Vec<_> = w
            .contacts()
            .expect("current lists")
            .pairs
            .iter()
            .map(|c| (tags[c.i], tags[c.j], c.force.to_array().map(f64::to_bits)))
            .collect();
        pairs.sort();
        pairs
    };
    let before = by_tag(&sim);
    let index = sim.particles().index_of(before[0].0).expect("present");
    let removed = sim.remove_particles(|k, _| k == index);
    assert_eq!(removed.len(), 1);
    let expected: Vec<_> = before
        .iter()
        .filter(|c| c.0 != before[0].0 && c.1 != before[0].0)
        .cloned()
        .collect();
    assert!(
        expected.len() < before.len(),
        "the removed body had a contact"
    );
    assert_eq!(by_tag(&sim), expected);
    let material = dem::MaterialId(0);
    sim.add_particle(dem::ParticleInit::at_rest(
        removed[0].position,
        7.5e-4,
        material,
    ))
    .expect("added");
    assert!(sim.watched().contacts().is_none());
    sim.run(1).expect("run");
    assert!(sim.watched().contacts().is_some());
}

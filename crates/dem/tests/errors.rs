//! The engine refuses or stops runs it cannot integrate, with errors that name the particle and
//! the likely cause: excessive overlap, non-finite state, and a time step above the Rayleigh guard.

mod common;

use common::Gas;
use dem::timescale::rayleigh_time;
use dem::{
    DVec3, DemError, Interaction, Material, MaterialId, ParticleInit, Simulation, SimulationConfig,
};

const RADIUS: f64 = 1.5e-3;

/// A simulation of Table-1 spheres without gravity; five spectators far away take tags 0–4, so
/// the particles under test have tags that cannot be confused with indices or counts.
fn with_spectators(config: SimulationConfig) -> (Simulation, dem::MaterialId) {
    let mut sim = Simulation::new(config).expect("valid configuration");
    let id = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .expect("valid material");
    for k in 0..5 {
        sim.add_particle(ParticleInit::at_rest(
            DVec3::new(0.1 + 0.01 * k as f64, 0.1, 0.1),
            RADIUS,
            id,
        ))
        .expect("valid particle");
    }
    (sim, id)
}

fn no_gravity(time_step: f64) -> SimulationConfig {
    let mut c = SimulationConfig::new(time_step);
    c.gravity = DVec3::ZERO;
    c
}

#[test]
fn nan_or_huge_overlap_stops_the_run_with_a_named_particle() {
    // Two spheres inserted overlapping by 30 % of the radius: three times the 10 % limit.
    let (mut sim, id) = with_spectators(no_gravity(2.5e-6));
    let a = sim
        .add_particle(ParticleInit::at_rest(DVec3::ZERO, RADIUS, id))
        .expect("valid particle");
    let b = sim
        .add_particle(ParticleInit::at_rest(
            DVec3::new(1.7 * RADIUS, 0.0, 0.0),
            RADIUS,
            id,
        ))
        .expect("valid particle");
    let err = sim.step().expect_err("a 30 % overlap must stop the run");
    let message = err.to_string();
    match err {
        DemError::ExcessiveOverlap { tag, fraction, .. } => {
            assert!(
                tag == a || tag == b,
                "the error names tag {tag}, not one of the pair {a}, {b}"
            );
            // δ/R = 0.3 up to the drift of one step at rest (none): 1e-9 is round-off room.
            assert!((fraction - 0.3).abs() < 1e-9, "overlap fraction {fraction}");
            assert!(message.contains(&format!("particle {tag}")), "{message}");
        }
        other => panic!("expected ExcessiveOverlap, got {other:?}"),
    }
    assert!(
        message.contains("time step"),
        "the message must suggest the time step: {message}"
    );
}

#[test]
fn a_step_that_failed_half_done_refuses_every_later_one() {
    // The step that finds the 30 % overlap has already kicked and drifted every body, so
    // the state is no longer one instant's: stepping on would integrate from it as if it
    // were. Every later step must be refused, naming the first error, and leave the bodies
    // where the failed step left them.
    let (mut sim, id) = with_spectators(no_gravity(2.5e-6));
    sim.add_particle(ParticleInit::at_rest(DVec3::ZERO, RADIUS, id))
        .expect("valid particle");
    sim.add_particle(ParticleInit::at_rest(
        DVec3::new(1.7 * RADIUS, 0.0, 0.0),
        RADIUS,
        id,
    ))
    .expect("valid particle");
    let first = sim.step().expect_err("a 30 % overlap must stop the run");
    assert!(
        matches!(first, DemError::ExcessiveOverlap { .. }),
        "{first:?}"
    );
    let positions = sim.particles().positions().to_vec();
    for again in [sim.step(), sim.run(10)] {
        match again.expect_err("a half-done step must refuse the next ones") {
            DemError::AfterFailure { time, cause } => {
                assert_eq!(*cause, first, "the refusal must carry the first error");
                assert_eq!(time, 0.0, "no step was completed");
            }
            other => panic!("expected AfterFailure, got {other:?}"),
        }
    }
    assert_eq!(sim.steps(), 0, "refused steps must not count");
    assert!(
        sim.particles().positions() == positions.as_slice(),
        "refused steps must not move the bodies"
    );
    let message = DemError::AfterFailure {
        time: 0.0,
        cause: Box::new(first.clone()),
    }
    .to_string();
    assert!(
        message.contains("checkpoint") && message.contains(&first.to_string()),
        "the message must say what to do and why: {message}"
    );
}

#[test]
fn far_too_large_time_step_stops_a_collision_with_a_named_particle() {
    // Δt = 5 t_R with the guard raised to let it through: two spheres meeting at 3 m/s move
    // 0.4 mm (a quarter radius) per step, so the first overlap step already exceeds the 10 % limit
    // or the state blows up; either way the run must stop and say why.
    let t_r = rayleigh_time(&Material::fan2023(), RADIUS);
    let mut config = no_gravity(5.0 * t_r);
    config.max_rayleigh_fraction = 10.0;
    let (mut sim, id) = with_spectators(config);
    let mut left = ParticleInit::at_rest(DVec3::new(-1.2 * RADIUS, 0.0, 0.0), RADIUS, id);
    left.velocity = DVec3::new(1.5, 0.0, 0.0);
    let mut right = ParticleInit::at_rest(DVec3::new(1.2 * RADIUS, 0.0, 0.0), RADIUS, id);
    right.velocity = DVec3::new(-1.5, 0.0, 0.0);
    let pair = [
        sim.add_particle(left).expect("valid"),
        sim.add_particle(right).expect("valid"),
    ];
    let err = sim
        .run(100)
        .expect_err("the collision cannot be integrated at 5 t_R");
    let message = err.to_string();
    let tag = match err {
        DemError::ExcessiveOverlap { tag, .. } | DemError::NonFinite { tag, .. } => tag,
        other => panic!("expected ExcessiveOverlap or NonFinite, got {other:?}"),
    };
    assert!(
        pair.contains(&tag),
        "the error names tag {tag}, not one of the colliding pair {pair:?}"
    );
    assert!(message.contains(&format!("particle {tag}")), "{message}");
    assert!(
        message.contains("time step"),
        "the message must suggest the time step: {message}"
    );
}

#[test]
fn rayleigh_guard_refuses_a_too_large_step() {
    let t_r = rayleigh_time(&Material::fan2023(), RADIUS);
    // 0.3 t_R against the default limit of 0.25 t_R.
    let (mut sim, _) = with_spectators(no_gravity(0.3 * t_r));
    match sim.step() {
        Err(DemError::TimeStepTooLarge {
            fraction,
            max_fraction,
            rayleigh_time,
            ..
        }) => {
            // The reported ratio is Δt/t_R = 0.3 up to round-off.
            assert!((fraction - 0.3).abs() < 1e-12, "fraction {fraction}");
            assert_eq!(max_fraction, 0.25);
            assert!((rayleigh_time - t_r).abs() <= 1e-15 * t_r);
        }
        other => panic!("expected TimeStepTooLarge, got {other:?}"),
    }
    assert_eq!(sim.steps(), 0, "a refused step must not advance the run");
    // Just under the limit the same set-up runs.
    let (mut sim, _) = with_spectators(no_gravity(0.24 * t_r));
    assert!(sim.step().is_ok());
}

#[test]
fn a_large_one_thread_run_stops_on_an_overlap_before_moving_the_pair() {
    // Past 2^15 bodies a one-thread `run` moves each chunk of bodies on inside the
    // evaluation (forces/chunked.rs), after checking the chunk's overlaps. 40 000 spheres on
    // a lattice 3.1 mm apart (no contacts), moving at up to 0.5 m/s, and two spheres at rest
    // added on empty sites of the 35³ lattice, 1.7 R apart: 30 % overlap, the only contact
    // beyond the 10 % limit. The run must stop with that pair, at the position the overlap
    // was found at (the sphere still there: a check after the move would have pushed it
    // apart), exactly as two threads, which check after the whole evaluation, report it.
    let stopped = |threads: usize| {
        let mut config = no_gravity(2.5e-6);
        config.threads = threads;
        let gas = Gas {
            count: 40_000,
            spacing: 3.1e-3,
            speed: 0.5,
            interaction: Interaction::fan2023(),
            config,
            seed: 3,
        };
        let mut sim = gas.build();
        // Site (32, 22, 31); sites from index 40 000, (32, 22, 30), on are empty.
        let site = (DVec3::new(32.0, 22.0, 31.0) + DVec3::splat(0.5)) * gas.spacing;
        let id = MaterialId(0);
        let a = sim
            .add_particle(ParticleInit::at_rest(site, RADIUS, id))
            .expect("valid particle");
        let b = sim
            .add_particle(ParticleInit::at_rest(
                site + DVec3::new(0.0, 0.0, 1.7 * RADIUS),
                RADIUS,
                id,
            ))
            .expect("valid particle");
        let err = sim.run(3).expect_err("a 30 % overlap must stop the run");
        (sim, err, [a, b])
    };
    let (sim, err, pair) = stopped(1);
    let (_, two, _) = stopped(2);
    match &err {
        DemError::ExcessiveOverlap {
            tag,
            position,
            fraction,
            ..
        } => {
            assert!(pair.contains(tag), "tag {tag}, not one of {pair:?}");
            // δ/R = 0.3: the pair is at rest until its first force. 1e-9 is round-off room.
            assert!((fraction - 0.3).abs() < 1e-9, "overlap fraction {fraction}");
            let p = sim.particles();
            let k = p.tags().iter().position(|t| t == tag).expect("still there");
            // Exact: the body must not have moved since the check.
            assert_eq!(p.positions()[k], *position);
        }
        other => panic!("expected ExcessiveOverlap, got {other:?}"),
    }
    assert_eq!(format!("{err:?}"), format!("{two:?}"));
}

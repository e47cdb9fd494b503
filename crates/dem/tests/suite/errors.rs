//! The engine refuses or stops runs it cannot integrate, with errors that name the particle and
//! the likely cause: excessive overlap, non-finite state, and a time step above the Rayleigh guard;
//! and it refuses set-ups it cannot use (invalid input, materials without an interaction, wall
//! handles that do not exist) with errors that name the offending value or id. Every variant of
//! `DemError` that a caller can provoke is matched here with its fields.

use crate::common;

use common::Gas;
use dem::timescale::rayleigh_time;
use dem::{
    DVec3, DemError, Interaction, Material, MaterialId, ParticleInit, Simulation, SimulationConfig,
    Wall, WallId, WallMaterial,
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

/// Index of the body tagged `tag` (list builds re-sort the bodies, so indices move).
fn index_of(sim: &Simulation, tag: u64) -> usize {
    sim.particles()
        .tags()
        .iter()
        .position(|&t| t == tag)
        .expect("the body is still in the simulation")
}

#[test]
fn an_excessive_overlap_stops_the_run_with_a_named_particle() {
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
        DemError::ExcessiveOverlap {
            tag,
            other,
            position,
            fraction,
            limit,
            time,
        } => {
            assert!(
                tag == a || tag == b,
                "the error names tag {tag}, not one of the pair {a}, {b}"
            );
            // The other body of the pair is named as what it overlaps.
            let partner = if tag == a { b } else { a };
            assert_eq!(other, format!("particle {partner}"));
            // δ/R = 0.3 up to the drift of one step at rest (none): 1e-9 is round-off room.
            assert!((fraction - 0.3).abs() < 1e-9, "overlap fraction {fraction}");
            assert_eq!(limit, 0.1, "the default limit is 10 % of the radius");
            // The pair is at rest without gravity: the named body is where it was put, and
            // the step that found the overlap is the first one (t = 0).
            let expected = if tag == a {
                DVec3::ZERO
            } else {
                DVec3::new(1.7 * RADIUS, 0.0, 0.0)
            };
            assert_eq!(position, expected);
            assert_eq!(time, 0.0);
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

#[test]
fn a_sphere_pressed_into_a_wall_stops_the_run_naming_the_wall() {
    // A sphere whose centre is 0.7 R above a floor overlaps it by 30 % of its radius. The
    // error must name the wall by its handle, so that a hopper run can tell the gate from
    // the floor; the floor is the second wall added (handle 1), so a handle confused with
    // a count or a first index would show.
    let (mut sim, id) = with_spectators(no_gravity(2.5e-6));
    let plane = |z: f64| {
        Wall::plane(
            DVec3::new(0.0, 0.0, z),
            DVec3::Z,
            WallMaterial::Elastic(Material::fan2023()),
            Interaction::fan2023(),
        )
        .expect("valid plane")
    };
    // A far-away floor below everything, then the floor under the test sphere.
    sim.add_wall(plane(-1.0)).expect("valid wall");
    let floor = sim.add_wall(plane(0.0)).expect("valid wall");
    assert_eq!(floor, WallId(1));
    let tag = sim
        .add_particle(ParticleInit::at_rest(
            DVec3::new(0.0, 0.0, 0.7 * RADIUS),
            RADIUS,
            id,
        ))
        .expect("valid particle");
    match sim
        .step()
        .expect_err("a 30 % wall overlap must stop the run")
    {
        DemError::ExcessiveOverlap {
            tag: named,
            other,
            fraction,
            limit,
            ..
        } => {
            assert_eq!(named, tag);
            assert_eq!(other, "wall 1");
            // δ/R = 0.3: the sphere is at rest until its first force. 1e-9 is round-off room.
            assert!((fraction - 0.3).abs() < 1e-9, "overlap fraction {fraction}");
            assert_eq!(limit, 0.1);
        }
        other => panic!("expected ExcessiveOverlap, got {other:?}"),
    }
}

#[test]
fn a_nan_velocity_stops_the_first_step_at_a_non_finite_position() {
    // A NaN in one component of a velocity reaches the position in the first drift. The
    // step must stop there, naming the body, the quantity found non-finite ("position": the
    // drift is where the NaN first shows in the state that a run keeps), and t = 0.
    let (mut sim, id) = with_spectators(no_gravity(2.5e-6));
    let start = DVec3::new(0.02, 0.0, 0.0);
    let tag = sim
        .add_particle(ParticleInit::at_rest(start, RADIUS, id))
        .expect("valid particle");
    let k = index_of(&sim, tag);
    sim.set_particle_motion(k, DVec3::new(f64::NAN, 0.0, 0.0), DVec3::ZERO);
    let err = sim.step().expect_err("a NaN velocity must stop the run");
    let message = err.to_string();
    match err {
        DemError::NonFinite {
            tag: named,
            position,
            quantity,
            time,
        } => {
            assert_eq!(named, tag, "the body with the NaN velocity must be named");
            assert_eq!(quantity, "position");
            assert_eq!(time, 0.0, "the first step has found it");
            // Only x was NaN: y and z drifted by exactly 0 and are reported as they were.
            assert!(position.x.is_nan(), "{position}");
            assert_eq!((position.y, position.z), (start.y, start.z));
        }
        other => panic!("expected NonFinite, got {other:?}"),
    }
    assert!(
        message.contains(&format!("particle {tag}")) && message.contains("non-finite position"),
        "{message}"
    );
    assert!(
        message.contains("time step"),
        "the message must suggest the likely cause: {message}"
    );
}

#[test]
fn a_nan_spin_stops_the_step_with_a_non_finite_velocity() {
    // A spin does not move the body, so a NaN spin leaves every position finite and can
    // only be caught as a non-finite velocity (velocity and spin are checked together).
    // `step` finds it after its second half kick, at the step's start time t = 0; `run`
    // defers that kick to the next step's pass and so reports it one step later, at
    // t = Δt (the documented half-step delay of `Simulation::run`). The position in the
    // error is the body's own, finite and unmoved: it is at rest without gravity.
    let dt = 2.5e-6;
    let start = DVec3::new(0.02, 0.0, 0.0);
    let nan_spin = |sim: &mut Simulation, id: MaterialId| {
        let tag = sim
            .add_particle(ParticleInit::at_rest(start, RADIUS, id))
            .expect("valid particle");
        let k = index_of(sim, tag);
        sim.set_particle_motion(k, DVec3::ZERO, DVec3::new(0.0, f64::NAN, 0.0));
        tag
    };
    for (how, expected_time) in [("step", 0.0), ("run", dt)] {
        let (mut sim, id) = with_spectators(no_gravity(dt));
        let tag = nan_spin(&mut sim, id);
        let err = match how {
            "step" => sim.step(),
            _ => sim.run(5),
        }
        .expect_err("a NaN spin must stop the run");
        match err {
            DemError::NonFinite {
                tag: named,
                position,
                quantity,
                time,
            } => {
                assert_eq!(named, tag, "{how}");
                assert_eq!(quantity, "velocity", "{how}");
                assert_eq!(time, expected_time, "{how}");
                assert_eq!(position, start, "{how}");
            }
            other => panic!("{how}: expected NonFinite, got {other:?}"),
        }
    }
}

#[test]
fn a_velocity_that_overflows_in_a_step_stops_it_naming_the_body() {
    // A finite state whose velocity the step itself makes infinite. The body moves along z
    // at the largest float below f64::MAX, and gravity along z adds a = Δt/2 · g = 3/4 of
    // that float's spacing u = 2^971 per half kick. The first half kick rounds to f64::MAX
    // (MAX − u/4 is nearest to it), the drift moves the body by Δt · MAX ≈ 4.5e302 m
    // (finite), and the second half kick overflows (MAX + 3u/4 rounds to infinity). The
    // step must stop with a non-finite *velocity*, naming the body, at t = 0, and report a
    // finite position: the last one the body had. (Along z, because the spectators, which
    // fall too, keep their x spacing: at z ≈ 1e286 a spacing along z would round away and
    // make them overlap.)
    let dt = 2.5e-6;
    let u = 2f64.powi(971);
    let mut config = SimulationConfig::new(dt);
    config.gravity = DVec3::new(0.0, 0.0, 0.75 * u / (0.5 * dt));
    let (mut sim, id) = with_spectators(config);
    let mut init = ParticleInit::at_rest(DVec3::ZERO, RADIUS, id);
    init.velocity = DVec3::new(0.0, 0.0, f64::MAX - u);
    let tag = sim
        .add_particle(init)
        .expect("a finite state is valid input");
    match sim
        .step()
        .expect_err("an overflowing velocity must stop the run")
    {
        DemError::NonFinite {
            tag: named,
            position,
            quantity,
            time,
        } => {
            assert_eq!(named, tag, "the overflowing body must be named");
            assert_eq!(quantity, "velocity");
            assert_eq!(time, 0.0);
            assert!(position.is_finite(), "{position}");
            // It has drifted by Δt · MAX; 1e-12 is round-off room on that product.
            let drift = dt * f64::MAX;
            assert!(
                (position.z - drift).abs() <= 1e-12 * drift,
                "{position} after a drift of {drift:e} m"
            );
        }
        other => panic!("expected NonFinite velocity, got {other:?}"),
    }
}

/// `Simulation::new(config)`'s refusal, which must be `InvalidInput` naming `fragments`.
fn assert_config_refused(config: SimulationConfig, fragments: &[&str]) {
    match Simulation::new(config) {
        Err(DemError::InvalidInput(message)) => {
            for fragment in fragments {
                assert!(
                    message.contains(fragment),
                    "the message lacks `{fragment}`: {message}"
                );
            }
        }
        Err(other) => panic!("expected InvalidInput for {config:?}, got {other:?}"),
        Ok(_) => panic!("{config:?} must be refused"),
    }
}

#[test]
fn invalid_configurations_are_refused_naming_the_setting_and_value() {
    // Each setting that makes a run meaningless is refused with its name and value, so a
    // caller can say which of its inputs is wrong. NaN is tried for every limit: it passes
    // every `>` comparison's negation unnoticed unless refused on purpose, and a NaN limit
    // would silently switch its guard off.
    for dt in [0.0, -1e-6, f64::NAN, f64::INFINITY] {
        assert_config_refused(SimulationConfig::new(dt), &["time step", &dt.to_string()]);
    }
    let base = SimulationConfig::new(2.5e-6);
    let mut c = base;
    c.gravity = DVec3::new(0.0, f64::NAN, -9.81);
    assert_config_refused(c, &["gravity", "NaN"]);
    for skin in [-1e-4, f64::NAN, f64::INFINITY] {
        let mut c = base;
        c.skin = skin;
        assert_config_refused(c, &["skin", &skin.to_string()]);
    }
    for limit in [0.0, -0.1, f64::NAN] {
        let mut c = base;
        c.max_overlap_fraction = limit;
        assert_config_refused(c, &["max_overlap_fraction", &limit.to_string()]);
        let mut c = base;
        c.max_rayleigh_fraction = limit;
        assert_config_refused(c, &["max_rayleigh_fraction", &limit.to_string()]);
    }
    // The defaults around a valid step are accepted: the refusals above are the settings'.
    assert!(Simulation::new(base).is_ok());
}

#[test]
fn unphysical_materials_interactions_and_particles_are_refused_and_leave_nothing_behind() {
    let (mut sim, id) = with_spectators(no_gravity(2.5e-6));
    let refused = |result: Result<(), DemError>, fragments: &[&str]| match result {
        Err(DemError::InvalidInput(message)) => {
            for fragment in fragments {
                assert!(
                    message.contains(fragment),
                    "the message lacks `{fragment}`: {message}"
                );
            }
        }
        other => panic!("expected InvalidInput naming {fragments:?}, got {other:?}"),
    };

    // Materials: each property out of its range, named with its value.
    let with = |f: fn(&mut Material)| {
        let mut m = Material::fan2023();
        f(&mut m);
        m
    };
    let bad_materials: [(Material, &[&str]); 5] = [
        (with(|m| m.density = 0.0), &["density", "0"]),
        (with(|m| m.density = f64::INFINITY), &["density", "inf"]),
        (
            with(|m| m.youngs_modulus = -1e7),
            &["Young's modulus", "-10000000"],
        ),
        (
            with(|m| m.poisson_ratio = 0.5),
            &["Poisson ratio", "0.5", "(-1, 0.5)"],
        ),
        (
            with(|m| m.poisson_ratio = f64::NAN),
            &["Poisson ratio", "NaN"],
        ),
    ];
    for (material, fragments) in bad_materials {
        refused(
            sim.add_material(material, Interaction::fan2023())
                .map(|_| ()),
            fragments,
        );
    }
    // Interactions: friction, rolling friction and restitution out of range.
    let interaction = |f: fn(&mut Interaction)| {
        let mut i = Interaction::fan2023();
        f(&mut i);
        i
    };
    let bad_interactions = [
        interaction(|i| i.friction = -0.1),
        interaction(|i| i.rolling_friction = f64::NAN),
        interaction(|i| i.restitution = 0.0),
        interaction(|i| i.restitution = 1.5),
    ];
    for i in bad_interactions {
        refused(
            sim.add_material(Material::fan2023(), i).map(|_| ()),
            &["restitution in (0, 1]", &format!("{i:?}")],
        );
        refused(sim.set_interaction(id, id, i), &["restitution in (0, 1]"]);
    }
    // No refused material was registered: the next one takes id 1.
    let second = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .expect("valid material");
    assert_eq!(second, MaterialId(1));
    // Unknown material ids, named with how many exist.
    refused(
        sim.set_interaction(id, MaterialId(7), Interaction::fan2023()),
        &["unknown material 7", "2 material(s)"],
    );
    refused(
        sim.add_particle(ParticleInit::at_rest(DVec3::ZERO, RADIUS, MaterialId(2)))
            .map(|_| ()),
        &["unknown material 2", "2 material(s)"],
    );
    // Particles: radius and state.
    let mut spinning_nan = ParticleInit::at_rest(DVec3::ZERO, RADIUS, id);
    spinning_nan.angular_velocity = DVec3::new(f64::NAN, 0.0, 0.0);
    let mut fast_inf = ParticleInit::at_rest(DVec3::ZERO, RADIUS, id);
    fast_inf.velocity = DVec3::new(0.0, f64::INFINITY, 0.0);
    for init in [
        ParticleInit::at_rest(DVec3::ZERO, 0.0, id),
        ParticleInit::at_rest(DVec3::ZERO, -RADIUS, id),
        ParticleInit::at_rest(DVec3::new(f64::NAN, 0.0, 0.0), RADIUS, id),
        fast_inf,
        spinning_nan,
    ] {
        refused(sim.add_particle(init).map(|_| ()), &["radius", "finite"]);
    }
    // Only the five spectators are there, and they still run.
    assert_eq!(sim.particles().len(), 5);
    sim.step().expect("the refusals left a valid simulation");
}

#[test]
fn two_materials_without_an_interaction_are_refused_once_both_are_present() {
    // Three materials, each with only its self-interaction. Material 1 never gets a
    // particle, so its missing pairs do not matter; spheres of 0 and 2 meet only through
    // the pair (0, 2), which must be named, ids in order. The refusal comes before any
    // motion: nothing has moved or counted, and once the pair is defined the same
    // simulation steps.
    let (mut sim, zero) = with_spectators(no_gravity(2.5e-6));
    for _ in 0..2 {
        sim.add_material(Material::fan2023(), Interaction::fan2023())
            .expect("valid material");
    }
    let two = MaterialId(2);
    sim.add_particle(ParticleInit::at_rest(
        DVec3::new(0.0, 0.05, 0.0),
        RADIUS,
        two,
    ))
    .expect("valid particle");
    let positions = sim.particles().positions().to_vec();
    let err = sim
        .step()
        .expect_err("materials 0 and 2 have no interaction");
    assert_eq!(err, DemError::MissingInteraction(0, 2));
    assert_eq!(
        err.to_string(),
        "no interaction defined between materials 0 and 2"
    );
    assert_eq!(sim.steps(), 0, "a refused step must not count");
    assert!(sim.particles().positions() == positions.as_slice());
    sim.set_interaction(zero, two, Interaction::fan2023())
        .expect("valid interaction");
    sim.step()
        .expect("with the interaction defined the set-up runs");
}

#[test]
fn handles_of_walls_that_do_not_exist_are_refused_with_their_id() {
    // Two cases: a handle never issued, and one whose wall was removed. Every operation on
    // a wall handle must refuse both with that handle's id, and leave the other wall alone.
    let (mut sim, _) = with_spectators(no_gravity(2.5e-6));
    let plane = || {
        Wall::plane(
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::Z,
            WallMaterial::Elastic(Material::fan2023()),
            Interaction::fan2023(),
        )
        .expect("valid plane")
    };
    let kept = sim.add_wall(plane()).expect("valid wall");
    let gate = sim.add_wall(plane()).expect("valid wall");
    sim.remove_wall(gate).expect("the gate exists");
    let kept_before = sim.wall(kept).cloned();
    for id in [WallId(7), gate] {
        assert_eq!(
            sim.remove_wall(id).map(|_| ()),
            Err(DemError::UnknownWall(id.0))
        );
        assert_eq!(
            sim.translate_wall(id, DVec3::X),
            Err(DemError::UnknownWall(id.0))
        );
        assert_eq!(
            sim.set_wall_velocity(id, DVec3::X),
            Err(DemError::UnknownWall(id.0))
        );
        assert!(sim.wall(id).is_none());
        assert_eq!(
            DemError::UnknownWall(id.0).to_string(),
            format!("no wall with id {}", id.0)
        );
    }
    assert_eq!(sim.wall(kept).cloned(), kept_before);
    assert!(kept_before.is_some());
    sim.step().expect("the refusals left a valid simulation");
}

//! Rigid clumps in the engine (docs/physics.md §11.4): free flight, an impact on a plane
//! against rigid-body impact theory, a pile of clumps with the same bits on one and two
//! threads and after a checkpoint, and the removal of a clump whole.

use dem::clump::ClumpShape;
use dem::{
    DQuat, DVec3, Interaction, Material, MaterialId, Simulation, SimulationConfig, Wall,
    WallMaterial,
};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::common::RADIUS;

fn dumbbell() -> ClumpShape {
    ClumpShape::new(vec![
        (DVec3::new(-RADIUS, 0.0, 0.0), RADIUS),
        (DVec3::new(RADIUS, 0.0, 0.0), RADIUS),
    ])
    .expect("a dumbbell")
}

fn l_shape() -> ClumpShape {
    ClumpShape::new(vec![
        (DVec3::ZERO, RADIUS),
        (DVec3::new(1.5 * RADIUS, 0.0, 0.0), RADIUS),
        (DVec3::new(0.0, 1.5 * RADIUS, 0.0), 0.8 * RADIUS),
    ])
    .expect("an L")
}

fn simulation(
    interaction: Interaction,
    gravity: DVec3,
    threads: usize,
) -> (Simulation, MaterialId) {
    let mut config = SimulationConfig::new(2.5e-6);
    config.gravity = gravity;
    config.threads = threads;
    let mut sim = Simulation::new(config).expect("a simulation");
    let id = sim
        .add_material(Material::fan2023(), interaction)
        .expect("a material");
    (sim, id)
}

#[test]
fn a_free_clump_flies_on_its_parabola_spinning_with_constant_momentum_and_shape() {
    // No walls, no other body: the centre of mass must follow x0 + v0 t + g t²/2 (velocity
    // Verlet is exact for a constant force, so to round-off: 1e-12 m over 4000 steps of
    // sums of millimetres), the angular momentum must not change at all (the members'
    // contact forces are m g − m g = 0 exactly), and the members keep their distances
    // (1e-15 m: their placement is one rotation of fixed offsets).
    let g = DVec3::new(0.0, 0.0, -9.81);
    let (mut sim, id) = simulation(Interaction::fan2023(), g, 1);
    let (x0, v0, w0) = (
        DVec3::new(0.01, -0.02, 0.5),
        DVec3::new(0.3, 0.1, 1.0),
        DVec3::new(40.0, -70.0, 120.0),
    );
    let q0 = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    sim.add_clump(&l_shape(), id, (x0, q0), (v0, w0))
        .expect("a clump");
    let distances = |sim: &Simulation| {
        let x = sim.particles().positions();
        [
            x[0].distance(x[1]),
            x[0].distance(x[2]),
            x[1].distance(x[2]),
        ]
    };
    let before = distances(&sim);
    let l0 = sim.clumps().angular_momenta()[0];
    let steps = 4000;
    for _ in 0..steps {
        sim.step().expect("a step");
    }
    let t = steps as f64 * 2.5e-6;
    let want = x0 + v0 * t + 0.5 * g * t * t;
    let got = sim.clumps().positions()[0];
    assert!((got - want).length() <= 1e-12, "{got} {want}");
    assert_eq!(sim.clumps().angular_momenta()[0], l0);
    for (a, b) in before.iter().zip(distances(&sim)) {
        assert!((a - b).abs() <= 1e-15, "{a} {b}");
    }
    // The members move with the body: each one's velocity is v + ω × r.
    let (v, w) = (
        sim.clumps().velocities()[0],
        sim.clumps().angular_velocity(0),
    );
    let p = sim.particles();
    for k in 0..3 {
        let rigid = v + w.cross(p.positions()[k] - got);
        assert!((p.velocities()[k] - rigid).length() <= 1e-12, "{k}");
    }
}

#[test]
fn a_tilted_dumbbell_rebounds_from_a_smooth_plane_as_rigid_body_impact_theory_says() {
    // A dumbbell tilted 30° falls at 0.5 m/s, without spin or gravity, onto a plane with
    // e = 1 and μ = 0: only its lower bead touches. The impulse J along the normal n through
    // that bead's centre (r from the centre of mass) makes the contact point's normal speed
    // change sign: J = 2 m_eff u, 1/m_eff = 1/M + |r × n|²/I_across. So v_z' = −u + J/M and
    // ω' = (r × n) J / I_across. The contact lasts about 10 µs, in which the body turns by
    // about 2·10⁻³ rad and its lever by as much: the rows allow 1 %. Energy is elastic: the
    // kinetic energy after must equal that before within Verlet's error at this step, 1e-4.
    let interaction = Interaction {
        friction: 0.0,
        rolling_friction: 0.0,
        restitution: 1.0,
        ..Interaction::fan2023()
    };
    let (mut sim, id) = simulation(interaction, DVec3::ZERO, 1);
    let plane = Wall::plane(
        DVec3::ZERO,
        DVec3::Z,
        WallMaterial::Elastic(Material::fan2023()),
        interaction,
    )
    .expect("a plane");
    sim.add_wall(plane).expect("the plane");
    let tilt = 30f64.to_radians();
    let q = DQuat::from_rotation_y(tilt);
    let u = 0.5;
    let height = RADIUS * tilt.sin() + RADIUS + 1e-5;
    sim.add_clump(
        &dumbbell(),
        id,
        (DVec3::new(0.0, 0.0, height), q),
        (DVec3::new(0.0, 0.0, -u), DVec3::ZERO),
    )
    .expect("a dumbbell");
    let e0 = sim.energy().translational + sim.energy().rotational;
    let mut touched = false;
    for _ in 0..20_000 {
        sim.step().expect("a step");
        let touching = sim.contacts().particle_wall > 0;
        touched |= touching;
        if touched && !touching {
            break;
        }
    }
    assert!(
        touched && sim.contacts().particle_wall == 0,
        "the dumbbell met the plane and left it"
    );
    let body = sim.clumps().body(0);
    let (mass, across) = (body.mass, body.principal_inertia.z);
    let r = q * DVec3::new(-RADIUS, 0.0, 0.0); // the lower bead (it is at −x, tilted down)
    let r = if r.z < 0.0 { r } else { -r };
    let arm = r.cross(DVec3::Z);
    let m_eff = 1.0 / (1.0 / mass + arm.length_squared() / across);
    let j = 2.0 * m_eff * u;
    let v_want = -u + j / mass;
    let w_want = arm * (j / across);
    let v = sim.clumps().velocities()[0];
    let w = sim.clumps().angular_velocity(0);
    assert!(
        (v.z - v_want).abs() <= 0.01 * v_want.abs(),
        "v_z {} against {v_want}",
        v.z
    );
    assert!(
        (w - w_want).length() <= 0.01 * w_want.length(),
        "ω {w} against {w_want}"
    );
    let e1 = sim.energy().translational + sim.energy().rotational;
    assert!(((e1 - e0) / e0).abs() <= 1e-4, "{e0} {e1}");
}

/// Clumps of both shapes dropped into a box with random orientations and spins.
fn pile(threads: usize) -> Simulation {
    let g = DVec3::new(0.0, 0.0, -9.81);
    let (mut sim, id) = simulation(Interaction::fan2023(), g, threads);
    let spacing = 5.0 * RADIUS;
    let per_edge = 6;
    let edge = (per_edge as f64 + 0.2) * spacing;
    let material = WallMaterial::Elastic(Material::fan2023());
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        for (point, normal) in [(DVec3::ZERO, axis), (edge * axis, -axis)] {
            let wall =
                Wall::plane(point, normal, material, Interaction::fan2023()).expect("a plane");
            sim.add_wall(wall).expect("a wall");
        }
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
    for a in 0..per_edge {
        for b in 0..per_edge {
            for c in 0..per_edge {
                let x = DVec3::new(a as f64 + 0.6, b as f64 + 0.6, c as f64 + 0.6) * spacing;
                let axis = DVec3::new(
                    rng.gen_range(-1.0..1.0),
                    rng.gen_range(-1.0..1.0),
                    rng.gen_range(-1.0..1.0),
                );
                let q = DQuat::from_axis_angle(axis.normalize(), rng.gen_range(0.0..6.0));
                let v = DVec3::new(
                    rng.gen_range(-1.0..1.0),
                    rng.gen_range(-1.0..1.0),
                    rng.gen_range(-1.0..1.0),
                );
                let w = DVec3::new(rng.gen_range(-50.0..50.0), rng.gen_range(-50.0..50.0), 0.0);
                let shape = if (a + b + c) % 2 == 0 {
                    dumbbell()
                } else {
                    l_shape()
                };
                sim.add_clump(&shape, id, (x, q), (v, w)).expect("a clump");
            }
        }
    }
    sim
}

fn clump_bits(sim: &Simulation) -> Vec<u64> {
    let c = sim.clumps();
    let mut out = Vec::new();
    for k in 0..c.len() {
        let q = c.orientations()[k];
        for v in [c.positions()[k], c.velocities()[k], c.angular_momenta()[k]] {
            out.extend(v.to_array().map(f64::to_bits));
        }
        out.extend(q.to_array().map(f64::to_bits));
    }
    out
}

#[test]
fn a_pile_of_clumps_collides_and_keeps_its_bits_on_two_threads_and_across_a_checkpoint() {
    // 216 clumps (dumbbells and L shapes) in a 46.5 mm box, at up to 1 m/s, 6000 steps: they
    // meet each other and the walls. On two threads the clumps' own pass is shared too (108
    // clumps a thread, over its 64). The clumps' states must be the same bits on one and two threads, and a
    // simulation restored from the state saved half way must end on the same bits.
    let run = |threads: usize| {
        let mut sim = pile(threads);
        let mut met = 0;
        for _ in 0..6000 {
            sim.step().expect("a step");
            met += sim.contacts().particle_particle;
        }
        // Contacts last some 40 steps: this is hundreds of meetings.
        assert!(met > 10_000, "the clumps must meet: {met} contact-steps");
        clump_bits(&sim)
    };
    let one = run(1);
    assert!(one == run(2), "two threads changed the clumps' bits");
    let mut sim = pile(1);
    for _ in 0..3000 {
        sim.step().expect("a step");
    }
    let bytes = postcard::to_allocvec(sim.state()).expect("the state serialises");
    let state = postcard::from_bytes(&bytes).expect("and reads back");
    let mut restored = Simulation::from_state(state, 1).expect("a restored simulation");
    for _ in 0..3000 {
        restored.step().expect("a step");
    }
    assert!(
        one == clump_bits(&restored),
        "the restored pile's clumps moved differently"
    );
}

#[test]
fn removing_one_member_removes_its_clump_whole_and_the_others_go_on() {
    // Remove the particle at index 0: its clump's members all go, the clump count drops by
    // one, no particle points to a clump that is gone, and the rest step on.
    let mut sim = pile(1);
    let (clumps, particles) = (sim.clumps().len(), sim.particles().len());
    let members = sim
        .clumps()
        .body(sim.particles().clump_indices()[0] as usize)
        .members
        .len();
    let c = sim.particles().clump_indices()[0] as usize;
    let (tag, mass, centre) = (
        sim.clumps().first_tags()[c],
        sim.clumps().body(c).mass,
        sim.clumps().positions()[c],
    );
    let removed = sim.remove_particles(|k, _| k == 0);
    // One entry for the body: its first member's tag, its centre of mass, its mass once.
    assert_eq!(removed.len(), 1);
    assert_eq!(
        (removed[0].tag, removed[0].mass, removed[0].position),
        (tag, mass, centre)
    );
    assert_eq!(sim.clumps().len(), clumps - 1);
    assert_eq!(sim.particles().len(), particles - members);
    assert!(sim
        .particles()
        .clump_indices()
        .iter()
        .all(|&c| (c as usize) < clumps - 1));
    for _ in 0..200 {
        sim.step().expect("a step");
    }
}

#[test]
fn a_member_stays_a_member_whatever_flags_are_set_and_a_free_sphere_cannot_become_one() {
    // Membership is the clump's: clearing a member's flags keeps FLAG_CLUMP_MEMBER, and
    // setting it on a free sphere leaves that sphere free (its other flags are set).
    let (mut sim, id) = simulation(Interaction::fan2023(), DVec3::ZERO, 1);
    sim.add_clump(
        &dumbbell(),
        id,
        (DVec3::ZERO, DQuat::IDENTITY),
        (DVec3::ZERO, DVec3::ZERO),
    )
    .expect("a dumbbell");
    sim.add_particle(dem::ParticleInit::at_rest(DVec3::X * 0.05, RADIUS, id))
        .expect("a sphere");
    sim.set_particle_flags(0, 0);
    sim.set_particle_flags(2, dem::FLAG_CLUMP_MEMBER | dem::FLAG_FROZEN);
    let flags = sim.particles().flags();
    assert_eq!(flags[0], dem::FLAG_CLUMP_MEMBER);
    assert_eq!(flags[2], dem::FLAG_FROZEN);
}

#[test]
fn bodies_are_removed_by_their_centre_of_mass_and_counted_once() {
    // A dumbbell standing on end across the plane z = 0 (one member below, its centre of
    // mass above) stays when bodies below z = 0 are removed; a free sphere below goes; a
    // second dumbbell wholly below goes once, as one body with its whole mass. Scaled by 2,
    // a clump has 8 times the mass of the unscaled one.
    let (mut sim, id) = simulation(Interaction::fan2023(), DVec3::ZERO, 1);
    let up = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2);
    let across = sim
        .add_clump(
            &dumbbell(),
            id,
            (DVec3::new(0.0, 0.0, 0.1 * RADIUS), up),
            (DVec3::ZERO, DVec3::ZERO),
        )
        .expect("a clump");
    let below = sim
        .add_scaled_clump(
            (&dumbbell(), 2.0),
            id,
            (DVec3::new(0.01, 0.0, -0.01), DQuat::IDENTITY),
            (DVec3::ZERO, DVec3::ZERO),
        )
        .expect("a scaled clump");
    let sphere = sim
        .add_particle(dem::ParticleInit {
            position: DVec3::new(-0.01, 0.0, -0.005),
            velocity: DVec3::ZERO,
            angular_velocity: DVec3::ZERO,
            radius: RADIUS,
            material: id,
            flags: 0,
        })
        .expect("a sphere");
    let members_z: Vec<f64> = sim.particles().positions()[..2]
        .iter()
        .map(|x| x.z)
        .collect();
    assert!(
        members_z[0] < 0.0 || members_z[1] < 0.0,
        "a member of the first reaches below: {members_z:?}"
    );
    let masses = (
        sim.clumps().body(across).mass,
        sim.clumps().body(below).mass,
    );
    assert!((masses.1 / masses.0 - 8.0).abs() < 1e-12, "{masses:?}");
    // The grains' view: three bodies, each clump once with its whole mass and the radius of
    // its volume (a dumbbell of touching balls has twice one ball's volume: 2^(1/3) r).
    let bodies = sim.watched().bodies(|_| true);
    assert_eq!((bodies.len(), sim.watched().body_count()), (3, 3));
    assert_eq!(bodies.masses[1..], [masses.0, masses.1]);
    assert!((bodies.radii[1] / (2f64.cbrt() * RADIUS) - 1.0).abs() < 1e-12);
    assert!((bodies.radii[2] / bodies.radii[1] - 2.0).abs() < 1e-12);
    let tag_below = sim.clumps().first_tags()[below];
    let removed = sim.remove_bodies(|centre| centre.z < 0.0);
    let mut got: Vec<(u64, f64)> = removed.iter().map(|r| (r.tag, r.mass)).collect();
    got.sort_by_key(|r| r.0);
    assert_eq!(got.len(), 2, "the scaled clump and the sphere: {got:?}");
    assert_eq!(got[0], (tag_below, masses.1));
    assert_eq!(got[1].0, sphere);
    assert_eq!(sim.clumps().len(), 1);
    assert_eq!(sim.particles().len(), 2);
}

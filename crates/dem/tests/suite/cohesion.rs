//! Cohesion in whole simulations (docs/physics.md §2.4–2.7): bonds that act across a gap
//! behind every wall shape, neighbour lists that keep a bond farther than the skin, and the
//! same bits at any thread count and across a checkpoint.

use crate::common;

use common::{bits_by_tag, Gas};
use dem::contact::{jkr, liquid_bridge};
use dem::material::effective_youngs_modulus;
use dem::{
    Cohesion, DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig,
    SimulationState, Wall, WallId, WallMaterial, WallMotion, FLAG_FROZEN,
};

/// Table 1's sphere material.
fn table1() -> Material {
    Material::fan2023()
}

/// Frictionless, elastic, with `cohesion`.
fn sticky(cohesion: Cohesion) -> Interaction {
    Interaction {
        friction: 0.0,
        rolling_friction: 0.0,
        restitution: 1.0,
        cohesion,
    }
}

/// A held sphere of radius 1.5 mm at the origin, of Table 1's material meeting `wall` with
/// `interaction`, no gravity, Δt = 0.1 µs; returns the simulation and the wall's handle.
fn held_sphere(wall: Wall, interaction: Interaction) -> (Simulation, WallId) {
    let mut config = SimulationConfig::new(1e-7);
    config.gravity = DVec3::ZERO;
    let mut sim = Simulation::new(config).expect("valid configuration");
    let id = sim
        .add_material(table1(), interaction)
        .expect("valid material");
    let wall = sim.add_wall(wall).expect("valid wall");
    sim.add_particle(ParticleInit {
        flags: FLAG_FROZEN,
        ..ParticleInit::at_rest(DVec3::ZERO, common::RADIUS, id)
    })
    .expect("valid particle");
    (sim, wall)
}

/// A held sphere of radius 1.5 mm at the origin with `wall` (rigid, through the sphere's
/// surface below it at contact, moving away along −z at 1 mm/s); returns the surface gap
/// [m] at the last step where the sphere felt a force, within 1 µm of travel.
fn last_bonded_gap(wall: Wall, cohesion: Cohesion) -> f64 {
    let (mut sim, wall) = held_sphere(wall, sticky(cohesion));
    // One step at rest touches and bonds; then the wall pulls away.
    sim.step().expect("step");
    assert!(sim.particles().forces()[0].z != 0.0, "the contact formed");
    sim.set_wall_motion(
        wall,
        WallMotion {
            velocity: DVec3::new(0.0, 0.0, -1e-3),
            displaced: true,
            ..WallMotion::default()
        },
    )
    .expect("moving wall");
    let mut last = f64::NAN;
    for _ in 0..10_000 {
        sim.step().expect("step");
        let (_, dist) = sim.wall(wall).expect("wall").closest_point(DVec3::ZERO);
        if sim.particles().forces()[0].length() > 0.0 {
            last = dist - common::RADIUS;
        }
    }
    last
}

/// Three rigid floors at height `z0` [m] under a sphere at the origin, of `interaction`:
/// a plane, the low side of a cylinder of radius 1 m along x (flat to 1e-6 m over a contact)
/// and a mesh of two triangles of the plane.
fn floors(z0: f64, interaction: Interaction) -> [(&'static str, Wall); 3] {
    let plane = Wall::plane(
        DVec3::new(0.0, 0.0, z0),
        DVec3::Z,
        WallMaterial::Rigid,
        interaction,
    )
    .expect("plane");
    let cylinder = Wall::cylinder(
        DVec3::new(-0.5, 0.0, z0 + 1.0),
        DVec3::X,
        1.0,
        1.0,
        WallMaterial::Rigid,
        interaction,
    )
    .expect("cylinder");
    let s = 0.01;
    let c = [
        DVec3::new(-s, -s, z0),
        DVec3::new(s, -s, z0),
        DVec3::new(s, s, z0),
        DVec3::new(-s, s, z0),
    ];
    let mesh = Wall::mesh(
        &[[c[0], c[1], c[2]], [c[0], c[2], c[3]]],
        WallMaterial::Rigid,
        interaction,
    )
    .expect("mesh");
    [("plane", plane), ("cylinder", cylinder), ("mesh", mesh)]
}

#[test]
fn a_bond_breaks_at_the_same_gap_behind_a_plane_a_cylinder_and_a_mesh() {
    // The plane goes through the general wall loop, the cylinder and the mesh through the
    // surface pass, which searches out to the cohesion's reach: all three must hold the bond
    // to the same gap (`floors`).
    let r = common::RADIUS;
    let w = 2.0;
    let cohesion = Cohesion::Jkr {
        work_of_adhesion: w,
    };
    let e_star = effective_youngs_modulus(&table1(), None);
    let breaking = -jkr::breaking_overlap(e_star, r, w);
    // The first step sits just inside contact, so the contact forms.
    let z0 = -r + 1e-9;
    let interaction = sticky(cohesion);
    // Each step moves the wall 1e-10 m: the last bonded gap is δ_c within that.
    for (name, wall) in floors(z0, interaction) {
        let gap = last_bonded_gap(wall, cohesion);
        assert!(
            (gap - breaking).abs() <= 2e-10,
            "{name}: bond broke at a gap of {gap:e} m, δ_c = {breaking:e} m"
        );
    }
}

#[test]
fn the_simplified_jkr_pulls_alike_on_a_plane_a_cylinder_and_a_mesh() {
    // The plane's contact goes through the batched wall loop, the cylinder's and the mesh's
    // through the surface batch: each adds the attraction k_c π(2Rδ − δ²) to the same dry
    // force, so a held sphere 1 µm into each feels the same force, to the 1e-9 relative
    // that the cylinder's curvature (radius 1 m) leaves in the overlap's computation.
    let r = common::RADIUS;
    let k = 1e6;
    let interaction = sticky(Cohesion::SimplifiedJkr { energy_density: k });
    let z0 = -r + 1e-6;
    let force_on = |wall: Wall| {
        let (mut sim, _) = held_sphere(wall, interaction);
        sim.step().expect("step");
        sim.particles().forces()[0].z
    };
    let e_star = effective_youngs_modulus(&table1(), None);
    let d: f64 = 1e-6;
    let expected = 4.0 / 3.0 * e_star * r.sqrt() * d.powf(1.5)
        - k * std::f64::consts::PI * (2.0 * r * d - d * d);
    for (name, wall) in floors(z0, interaction) {
        let f = force_on(wall);
        assert!(
            (f - expected).abs() <= 1e-9 * expected.abs(),
            "{name}: {f} N against {expected} N"
        );
    }
}

#[test]
fn a_bridge_longer_than_the_skin_holds_until_its_rupture_distance() {
    // V = 0.1 R³ and θ = 0: S_c = V^{1/3} = 0.464 R, more than twice the default skin
    // (0.2 R). Two spheres parting at 0.5 m/s, four times the speed whose kinetic energy
    // the bridge would take (about 0.12 m/s), so they part: the last gap
    // at which they feel a force must be S_c within one step's travel, so the lists kept
    // the pair out to S_c.
    let r = common::RADIUS;
    let volume = 0.1 * r.powi(3);
    let cohesion = Cohesion::LiquidBridge {
        volume,
        surface_tension: 0.072,
        contact_angle: 0.0,
    };
    let s_c = liquid_bridge::rupture_distance(volume, 0.0);
    assert!(s_c > 2.0 * 0.2 * r);
    let dt = 1e-6;
    let mut config = SimulationConfig::new(dt);
    config.gravity = DVec3::ZERO;
    let mut sim = Simulation::new(config).expect("valid configuration");
    let id = sim
        .add_material(table1(), sticky(cohesion))
        .expect("valid material");
    // Overlapping by 2 µm, four steps' travel, so that the bridge forms on the first step.
    let x = r - 1e-6;
    for sign in [-1.0, 1.0] {
        sim.add_particle(ParticleInit {
            velocity: DVec3::new(sign * 0.25, 0.0, 0.0),
            ..ParticleInit::at_rest(DVec3::new(sign * x, 0.0, 0.0), r, id)
        })
        .expect("valid particle");
    }
    let mut last = f64::NAN;
    let mut speed = 0.0;
    for _ in 0..20_000 {
        sim.step().expect("step");
        let p = sim.particles();
        let gap = (p.positions()[1] - p.positions()[0]).length() - 2.0 * r;
        speed = (p.velocities()[1] - p.velocities()[0]).length();
        if p.forces()[0].length() > 0.0 {
            last = gap;
        }
        if gap > 2.0 * s_c {
            break;
        }
    }
    assert!(
        (last - s_c).abs() <= speed * dt,
        "last bridged gap {last:e} m, S_c = {s_c:e} m"
    );
}

/// A pile of Table-1 spheres whose contacts are `cohesion`, settling in a closed box.
fn cohesive_pile(cohesion: Cohesion, threads: usize) -> Gas {
    let mut config = SimulationConfig::new(2.5e-6);
    config.threads = threads;
    Gas {
        count: 512,
        spacing: 3.05e-3,
        speed: 0.3,
        interaction: Interaction::fan2023().with_cohesion(cohesion),
        config,
        seed: 4,
    }
}

/// The three laws, strong enough to matter for 3 mm Table-1 spheres (each bond holds
/// several times the sphere's weight, 3.5e-4 N).
fn laws() -> [Cohesion; 3] {
    [
        Cohesion::Jkr {
            work_of_adhesion: 0.5,
        },
        Cohesion::SimplifiedJkr {
            energy_density: 2e5,
        },
        Cohesion::LiquidBridge {
            volume: 1e-3 * common::RADIUS.powi(3),
            surface_tension: 0.072,
            contact_angle: 0.3,
        },
    ]
}

#[test]
fn a_cohesive_pile_has_the_same_bits_on_one_and_two_threads() {
    for cohesion in laws() {
        let mut one = cohesive_pile(cohesion, 1).build();
        let mut two = cohesive_pile(cohesion, 2).build();
        one.run(1500).expect("one thread");
        two.run(1500).expect("two threads");
        assert!(
            one.contacts().particle_particle > 0,
            "{cohesion:?}: no contacts"
        );
        assert!(
            bits_by_tag(&one) == bits_by_tag(&two),
            "{cohesion:?}: one and two threads diverged"
        );
    }
}

#[test]
fn a_checkpoint_keeps_the_bonds() {
    // The bonds live in the contact histories: a restored run that lost them would drop
    // the bridges and JKR contacts across gaps and diverge.
    for cohesion in laws() {
        let mut uninterrupted = cohesive_pile(cohesion, 1).build();
        uninterrupted.run(2000).expect("reference run");
        let mut first = cohesive_pile(cohesion, 1).build();
        first.run(777).expect("first leg");
        let bytes = postcard::to_allocvec(first.state()).expect("state serialises");
        let state: SimulationState = postcard::from_bytes(&bytes).expect("state deserialises");
        let mut resumed = Simulation::from_state(state, 1).expect("state restores");
        resumed.run(2000 - 777).expect("second leg");
        assert!(
            bits_by_tag(&resumed) == bits_by_tag(&uninterrupted),
            "{cohesion:?}: resumed run diverged"
        );
    }
}

#[test]
fn cohesion_holds_a_pile_that_a_dry_one_would_not() {
    // A JKR bond of w = 0.5 J/m² between 3 mm spheres pulls off at F_c = (3/2)π w R* =
    // 1.8e-3 N, five times a sphere's weight: after the same steps the cohesive pile has
    // more contacts carrying force than the dry one, which rebounds and spreads.
    let mut dry = cohesive_pile(Cohesion::None, 1).build();
    let mut wet = cohesive_pile(laws()[0], 1).build();
    dry.run(4000).expect("dry");
    wet.run(4000).expect("wet");
    assert!(
        wet.contacts().particle_particle > dry.contacts().particle_particle,
        "wet {} vs dry {}",
        wet.contacts().particle_particle,
        dry.contacts().particle_particle
    );
}

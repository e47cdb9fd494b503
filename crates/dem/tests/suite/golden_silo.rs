//! The engine's silo paths, pinned: a short run of a small silo of a cylinder over a cone
//! over a meshed floor must reproduce the recorded state and per-element wall loads bit for
//! bit, on one thread, on two (the bodies cut into two ranges) and on four (four ranges),
//! under the default laws and under Mindlin–Deresiewicz.
//!
//! What it runs, so that a change in any of these moves the golden:
//! - curved walls: the exact cylinder and cone contacts (docs/physics.md §5.2) and their
//!   band loads; the meshed floor's face, edge and corner contacts (§5.3) and its triangle
//!   loads;
//! - moving walls (§5.4): the floor translates along its normal, then turns about a
//!   horizontal axis, both displacing it; the cone's surface spins about the axis for part of
//!   the run while its shape stays;
//! - a material table (§1.2): two particle materials and a wall material, every pair listed
//!   but the two particle materials', which is mixed;
//! - two radii 1:3, past the split ratio of the size-class search (2.5), so the pairs are
//!   found by size classes;
//! - the tangential laws: Mindlin no-slip (the default) and Mindlin–Deresiewicz (§3).
//!
//! When an issue changes the physics on purpose, this test fails. Then, and only then:
//! 1. run `cargo test -p hopperflow-dem --test suite golden_silo:: -- --nocapture` and take the new
//!    values from the failure message;
//! 2. replace the constants below;
//! 3. say in the commit message that the golden values were regenerated and which change of
//!    physics moved them.

use crate::common;

use dem::{
    ContactLaws, DVec3, Interaction, MaterialEntry, MaterialTable, PairEntry, ParticleInit,
    Simulation, SimulationConfig, TangentialLaw, Wall, WallId, WallMaterial, WallMotion,
};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// Radius of the cylinder [m].
const SILO_RADIUS: f64 = 0.02;
/// Height of the cone, from the floor at z = 0 to the cylinder [m]; the cone's half-angle is
/// 45°, from radius 8 mm at the floor to the cylinder's.
const CONE_HEIGHT: f64 = 0.012;
/// Height of the cylinder above the cone [m].
const CYLINDER_HEIGHT: f64 = 0.03;
/// The small and the large radius [m]: 1:3.
const RADII: [f64; 2] = [1.0e-3, 3.0e-3];
/// Spheres: 1300, one in eight large, enough for four threads to cut a range each (ranges
/// hold at least 256 bodies).
const COUNT: usize = 1300;
/// Time step [s]: 9 % of the small spheres' Rayleigh time under the table's stiffer
/// material.
const TIME_STEP: f64 = 2.5e-6;

/// FNV-1a (64 bit) of the state's bits by tag, then of every wall's load and element loads
/// (see [`fingerprint`]), under the default laws and under Mindlin–Deresiewicz.
const GOLDEN_HASH: [u64; 2] = [0x75c2_8abe_a2dc_84bd, 0x2e50_ca54_2c58_2672];
/// Particle–particle and particle–wall contacts at the end, under each law (a coarse,
/// readable companion of the hash).
const GOLDEN_CONTACTS: [[usize; 2]; 2] = [[1555, 274], [1508, 270]];

/// The table: two glass-like particle materials, "a" stiffer and denser than "b", and a
/// steel wall. Every pair is listed but (a, b), which the mixing rules give.
fn table() -> MaterialTable {
    let pair = |a: &str, b: &str, restitution: f64, friction: f64, rolling_friction: f64| {
        PairEntry::new(
            a,
            b,
            Interaction {
                friction,
                rolling_friction,
                restitution,
                cohesion: dem::Cohesion::None,
            },
        )
    };
    MaterialTable::new()
        .with_material("a", MaterialEntry::from_youngs_modulus(1.0e8, 0.25, 2500.0))
        .with_material("b", MaterialEntry::from_youngs_modulus(5.0e7, 0.3, 1500.0))
        .with_material(
            "steel",
            MaterialEntry::from_youngs_modulus(2.0e11, 0.3, 7800.0),
        )
        .with_pair(pair("a", "a", 0.6, 0.4, 0.05))
        .with_pair(pair("b", "b", 0.3, 0.6, 0.1))
        .with_pair(pair("a", "steel", 0.5, 0.3, 0.02))
        .with_pair(pair("b", "steel", 0.4, 0.5, 0.04))
        .with_pair(pair("steel", "steel", 0.7, 0.2, 0.0))
}

/// The silo's walls: the cylinder, the cone and the meshed floor, in that order.
struct Silo {
    sim: Simulation,
    walls: [WallId; 3],
}

/// The silo filled with [`COUNT`] spheres ([`packed_spheres`], seed 17) with random
/// velocities up to 0.3 m/s, under `laws` on `threads` threads.
fn silo(threads: usize, laws: ContactLaws) -> Silo {
    let mut config = SimulationConfig::new(TIME_STEP);
    config.threads = threads;
    config.laws = laws;
    let mut sim = Simulation::new(config).expect("a valid configuration");
    let table = table();
    let ids = sim
        .add_material_table(&table, &["a", "b"])
        .expect("the table installs");
    let placeholder = Interaction::fan2023();
    let cylinder = Wall::cylinder(
        DVec3::new(0.0, 0.0, CONE_HEIGHT),
        DVec3::Z,
        CYLINDER_HEIGHT,
        SILO_RADIUS,
        WallMaterial::Rigid,
        placeholder,
    )
    .expect("a valid cylinder");
    let cone = Wall::frustum(
        DVec3::ZERO,
        DVec3::Z,
        CONE_HEIGHT,
        [SILO_RADIUS - CONE_HEIGHT, SILO_RADIUS],
        WallMaterial::Rigid,
        placeholder,
    )
    .expect("a valid cone");
    let tiles = common::square_floor(SILO_RADIUS, 12);
    let floor = Wall::mesh(&tiles, WallMaterial::Rigid, placeholder).expect("a valid mesh");
    let walls = [
        sim.add_wall(cylinder).expect("the cylinder"),
        sim.add_wall(cone).expect("the cone"),
        sim.add_wall(floor).expect("the floor"),
    ];
    for wall in walls {
        sim.set_wall_from_table(wall, &table, &ids, "steel")
            .expect("steel walls");
    }
    for wall in &walls[..2] {
        sim.set_wall_bands(*wall, 5).expect("bands");
    }
    let materials = [ids.get("a").expect("a"), ids.get("b").expect("b")];
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(17);
    let placed = packed_spheres(&mut rng);
    for (k, (position, radius)) in placed.into_iter().enumerate() {
        let velocity = common::velocity_in_ball(&mut rng, 0.3);
        // Materials alternate independently of size (one in eight is large, one in two "a"),
        // so every pair of materials meets at both sizes.
        let mut init = ParticleInit::at_rest(position, radius, materials[k % 2]);
        init.velocity = velocity;
        sim.add_particle(init).expect("a valid sphere");
    }
    Silo { sim, walls }
}

/// [`COUNT`] sphere centres and radii, layer by layer from the floor up: cubes of side
/// 3 s (s = 2.1 mm) hold one large sphere (each cube by an even draw from `rng`) or 27 small
/// ones on a lattice of spacing s, about 0.45 of the volume either way, 0.1 mm or more apart.
/// A sphere goes where it clears the floor, the cone and the cylinder by a tenth of its
/// radius; a large one that does not fit leaves its cube to small ones.
fn packed_spheres(rng: &mut Xoshiro256PlusPlus) -> Vec<(DVec3, f64)> {
    const SPACING: f64 = 2.1e-3;
    let fits = |x: DVec3, radius: f64| {
        let rho = x.truncate().length();
        let clear = 1.1 * radius;
        // The cone's inner surface is at 45°: a point's distance to it is (r_cone(z) − ρ)/√2.
        let cone_radius = SILO_RADIUS - CONE_HEIGHT + x.z.min(CONE_HEIGHT);
        x.z >= clear
            && rho + clear <= SILO_RADIUS
            && (x.z > CONE_HEIGHT + clear
                || (cone_radius - rho) / std::f64::consts::SQRT_2 >= clear)
    };
    let mut placed = Vec::with_capacity(COUNT);
    let side = 3.0 * SPACING;
    let cubes = (SILO_RADIUS / side).ceil() as i32;
    for layer in 0.. {
        for a in -cubes..=cubes {
            for b in -cubes..=cubes {
                let centre = DVec3::new(
                    f64::from(a) * side,
                    f64::from(b) * side,
                    RADII[0] + SPACING + f64::from(layer) * side,
                );
                if rng.gen_bool(0.5) && fits(centre, RADII[1]) {
                    placed.push((centre, RADII[1]));
                } else {
                    for i in -1..=1 {
                        for j in -1..=1 {
                            for k in -1..=1 {
                                let x = centre + DVec3::new(i as f64, j as f64, k as f64) * SPACING;
                                if fits(x, RADII[0]) {
                                    placed.push((x, RADII[0]));
                                }
                            }
                        }
                    }
                }
                if placed.len() >= COUNT {
                    placed.truncate(COUNT);
                    return placed;
                }
            }
        }
    }
    unreachable!("the layers go on until the spheres are placed")
}

/// Runs the silo's script: 24 000 steps (60 ms) in which the floor rises at 10 mm/s
/// (steps 0–8000), the cone's surface spins at 20 rad/s about the axis (steps 6000–16 000)
/// and the floor turns at 0.25 rad/s about the x axis through its centre, risen by 0.2 mm
/// (steps 12 000–20 000).
fn run_script(silo: &mut Silo) {
    let [_, cone, floor] = silo.walls;
    let sim = &mut silo.sim;
    let rise = WallMotion {
        velocity: DVec3::new(0.0, 0.0, 0.01),
        displaced: true,
        ..WallMotion::default()
    };
    let spin = WallMotion {
        angular_velocity: DVec3::new(0.0, 0.0, 20.0),
        ..WallMotion::default()
    };
    let tilt = WallMotion {
        angular_velocity: DVec3::new(0.25, 0.0, 0.0),
        centre: DVec3::new(0.0, 0.0, 2.0e-4),
        displaced: true,
        ..WallMotion::default()
    };
    let segments: [(u64, Option<(WallId, WallMotion)>); 6] = [
        (0, Some((floor, rise))),
        (6000, Some((cone, spin))),
        (8000, Some((floor, WallMotion::default()))),
        (12_000, Some((floor, tilt))),
        (16_000, Some((cone, WallMotion::default()))),
        (20_000, Some((floor, WallMotion::default()))),
    ];
    for (k, (start, change)) in segments.iter().enumerate() {
        if let Some((wall, motion)) = change {
            sim.set_wall_motion(*wall, *motion).expect("a valid motion");
        }
        let end = segments.get(k + 1).map_or(24_000, |s| s.0);
        sim.run(end - start).expect("the silo runs");
    }
}

/// The run's fingerprint: every position, velocity and spin bit by tag, then for each wall
/// its last step's force and torque and every element's impulse, normal and shear impulse
/// since the start.
fn fingerprint(silo: &Silo) -> u64 {
    let state = common::bits_by_tag(&silo.sim)
        .into_iter()
        .flat_map(|(tag, b)| std::iter::once(tag).chain(b));
    let mut loads = Vec::new();
    for wall in silo.walls {
        let load = silo.sim.wall_load(wall).expect("a wall");
        loads.extend(load.force.to_array().map(f64::to_bits));
        loads.extend(load.torque.to_array().map(f64::to_bits));
        for element in &silo.sim.surface_loads(wall).expect("a surface").elements {
            loads.extend(element.impulse.to_array().map(f64::to_bits));
            loads.push(element.normal_impulse.to_bits());
            loads.push(element.shear_impulse.to_bits());
        }
    }
    common::fnv1a(state.chain(loads))
}

fn golden(law: usize) {
    let laws = [
        ContactLaws::default(),
        ContactLaws {
            tangential: TangentialLaw::MindlinDeresiewicz,
            ..ContactLaws::default()
        },
    ][law];
    let mut found = Vec::new();
    for threads in [1, 2, 4] {
        let mut silo = silo(threads, laws);
        run_script(&mut silo);
        let contacts = silo.sim.contacts();
        // The pile must lean on every wall and on itself for the golden to pin the wall
        // contacts, the element loads and the pair laws.
        for wall in silo.walls {
            let pressed = silo
                .sim
                .surface_loads(wall)
                .expect("a surface")
                .elements
                .iter()
                .filter(|e| e.normal_impulse > 0.0)
                .count();
            assert!(pressed >= 3, "wall {wall:?}: {pressed} elements loaded");
        }
        assert!(
            contacts.particle_particle > 500 && contacts.particle_wall > 50,
            "{contacts:?}"
        );
        found.push((
            threads,
            fingerprint(&silo),
            [contacts.particle_particle, contacts.particle_wall],
        ));
    }
    let moved: Vec<String> = found
        .iter()
        .filter(|(_, hash, contacts)| {
            *hash != GOLDEN_HASH[law] || *contacts != GOLDEN_CONTACTS[law]
        })
        .map(|(threads, hash, contacts)| {
            format!("{threads} thread(s): hash {hash:#018x}, contacts {contacts:?}")
        })
        .collect();
    assert!(
        moved.is_empty(),
        "the silo's state or wall loads under {laws:?} changed (golden {:#018x}, contacts \
         {:?}). If the physics was changed on purpose, regenerate as the header of this \
         file says. Moved:\n{}",
        GOLDEN_HASH[law],
        GOLDEN_CONTACTS[law],
        moved.join("\n")
    );
}

#[test]
fn silo_run_reproduces_its_golden_state_and_wall_loads_on_one_two_and_four_threads() {
    golden(0);
}

#[test]
fn silo_run_under_mindlin_deresiewicz_reproduces_its_golden_state_and_wall_loads() {
    golden(1);
}

//! The triangle meshes and the one-sphere set-up the wall cases share (W1–W6), and the
//! round-off bound of the rebounds W2 and W3 compare.

use dem::contact::normal::max_overlap;
use dem::material::effective_youngs_modulus;
use dem::{
    DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig, Wall, WallId,
    WallMaterial,
};

use crate::impact::sphere_mass;
use crate::VerifyError;

/// Table-1 particle radius [m].
pub const RADIUS: f64 = 1.5e-3;
/// Production time step [s] (docs/physics.md §6.1).
pub const TIME_STEP: f64 = 2.5e-6;

/// The square [−half, half]² of the plane z = `z` cut into n × n squares, each split into two
/// triangles along alternating diagonals, so that corners are shared by four or eight
/// triangles and the edges run along x, y and both diagonals; normals +z.
pub fn floor(half: f64, n: usize, z: f64) -> Vec<[DVec3; 3]> {
    let a = 2.0 * half / n as f64;
    let at = |i: usize, j: usize| DVec3::new(-half + i as f64 * a, -half + j as f64 * a, z);
    let mut out = Vec::with_capacity(2 * n * n);
    for i in 0..n {
        for j in 0..n {
            let (p, q, r, s) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if (i + j) % 2 == 0 {
                out.push([p, q, r]);
                out.push([p, r, s]);
            } else {
                out.push([p, q, s]);
                out.push([q, r, s]);
            }
        }
    }
    out
}

/// The closed axis-aligned box `lo..hi` as 12 triangles, normals outwards.
pub fn cube(lo: DVec3, hi: DVec3) -> Vec<[DVec3; 3]> {
    let c = |i: usize| {
        DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    // Each face as a quad of corner indices, counter-clockwise seen from outside.
    let faces = [
        [0, 2, 3, 1], // z = lo
        [4, 5, 7, 6], // z = hi
        [0, 1, 5, 4], // y = lo
        [2, 6, 7, 3], // y = hi
        [0, 4, 6, 2], // x = lo
        [1, 3, 7, 5], // x = hi
    ];
    faces
        .iter()
        .flat_map(|f| [[c(f[0]), c(f[1]), c(f[2])], [c(f[0]), c(f[2]), c(f[3])]])
        .collect()
}

/// A simulation of one Table-1 sphere (index 0) at `position` with `velocity` and `spin`
/// and the walls `walls`, all with `interaction`; gravity `gravity` [m/s²].
pub fn one_sphere(
    walls: Vec<Wall>,
    interaction: Interaction,
    gravity: DVec3,
    (position, velocity, spin): (DVec3, DVec3, DVec3),
) -> Result<(Simulation, Vec<WallId>), VerifyError> {
    let mut config = SimulationConfig::new(TIME_STEP);
    config.gravity = gravity;
    config.resort_every = 0;
    let mut sim = Simulation::new(config)?;
    let id = sim.add_material(Material::fan2023(), interaction)?;
    let ids = walls
        .into_iter()
        .map(|w| sim.add_wall(w))
        .collect::<Result<_, _>>()?;
    sim.add_particle(ParticleInit {
        position,
        velocity,
        angular_velocity: spin,
        radius: RADIUS,
        material: id,
        flags: 0,
    })?;
    Ok((sim, ids))
}

/// A rigid-walled mesh of `triangles` with `interaction`.
pub fn mesh_wall(triangles: &[[DVec3; 3]], interaction: Interaction) -> Result<Wall, VerifyError> {
    Ok(Wall::mesh(triangles, WallMaterial::Rigid, interaction)?)
}

/// The rigid plane z = 0 with normal +z and `interaction`.
pub fn plane_wall(interaction: Interaction) -> Result<Wall, VerifyError> {
    Ok(Wall::plane(
        DVec3::ZERO,
        DVec3::Z,
        WallMaterial::Rigid,
        interaction,
    )?)
}

/// Position, velocity and spin of sphere 0.
pub fn motion(sim: &Simulation) -> (DVec3, DVec3, DVec3) {
    let p = sim.particles();
    (
        p.positions()[0],
        p.velocities()[0],
        p.angular_velocities()[0],
    )
}

/// The largest of |a − b| over the three vectors of two motions, relative to `scale`.
pub fn motion_gap(a: (DVec3, DVec3, DVec3), b: (DVec3, DVec3, DVec3), scale: [f64; 3]) -> f64 {
    [
        a.0.distance(b.0) / scale[0],
        a.1.distance(b.1) / scale[1],
        a.2.distance(b.2) / scale[2],
    ]
    .into_iter()
    .fold(0.0, f64::max)
}

/// Table 1's contact without rolling friction: Eq. 8's constant torque turns with the sign
/// of ω, which for a sphere that does not spin a round-off tilt of the normal (1e-16)
/// decides, and would make two shapes differ by that decision, not by their geometry.
pub fn no_rolling() -> Interaction {
    Interaction {
        rolling_friction: 0.0,
        ..Interaction::fan2023()
    }
}

/// (1/m)∫|∂F_n/∂δ| dt over a Table-1 rebound under [`no_rolling`] (e = 0.2), in units of
/// v/δ_max with δ_max the elastic peak overlap [-]: 6.01 by integrating the Hertz law with its
/// dashpot (docs/physics.md §2.1) through the contact, rounded up (4.16 for e = 1).
const REBOUND_SENSITIVITY: f64 = 6.1;

/// Round-off bound on |v − v_plane| / v of two [`rebound`]s of the Table-1 sphere at `speed`
/// [m/s] on rigid walls, one computed at coordinates up to `reach` [m] from the origin and the
/// other on the plane z = 0 from `plane_start` [m].
///
/// The overlap R − |x − p| is a difference of coordinates of size L (the distance from the
/// origin): four roundings (the closest point, the difference, its length, R minus it) of at
/// most ε L/2 each (ε the machine epsilon) make its error η ≤ 2 ε L. Each step's normal force
/// then errs by at most |∂F_n/∂δ| η, and summed over the contact the rebound velocity by
/// η (1/m)∫|∂F_n/∂δ| dt = [`REBOUND_SENSITIVITY`] η v/δ_max. Each run errs so, with its own L.
pub fn rebound_round_off(reach: f64, plane_start: DVec3, speed: f64) -> f64 {
    let material = Material::fan2023();
    let e_star = effective_youngs_modulus(&material, None);
    let peak = max_overlap(e_star, RADIUS, sphere_mass(&material, RADIUS), speed);
    REBOUND_SENSITIVITY * 2.0 * f64::EPSILON * (reach + plane_start.length()) / peak
}

/// Sends the only sphere from `start` at `velocity` onto `walls` without gravity, under
/// [`no_rolling`]; returns its velocity once it has left the contact, and the most wall
/// contacts it had in a step.
pub fn rebound(
    walls: Vec<Wall>,
    start: DVec3,
    velocity: DVec3,
) -> Result<(DVec3, usize), VerifyError> {
    let at_start = (start, velocity, DVec3::ZERO);
    let (mut sim, _) = one_sphere(walls, no_rolling(), DVec3::ZERO, at_start)?;
    let (mut most, mut touched) = (0, false);
    const STEPS: u64 = 400_000;
    for _ in 0..STEPS {
        sim.step()?;
        let c = sim.contacts().particle_wall;
        most = most.max(c);
        touched |= c > 0;
        if touched && c == 0 {
            return Ok((motion(&sim).1, most));
        }
    }
    Err(VerifyError::NoEvent {
        what: "the rebound",
        steps: STEPS,
    })
}

//! Set-ups shared by the engine's integration tests: a closed box of six planes and a lattice
//! of Table-1 spheres with seeded random velocities.

#![allow(dead_code)]

use dem::{
    DVec3, Interaction, Material, MaterialId, ParticleInit, Simulation, SimulationConfig, Wall,
    WallMaterial,
};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// Table-1 particle radius [m].
pub const RADIUS: f64 = 1.5e-3;

/// A gas or pile of Table-1 spheres in a closed cubic box.
pub struct Gas {
    /// Number of spheres [-].
    pub count: usize,
    /// Lattice spacing of the initial positions [m].
    pub spacing: f64,
    /// Largest initial speed [m/s]; velocities are uniform in the ball of this radius.
    pub speed: f64,
    /// Contact coefficients, the same for sphere–sphere and sphere–wall.
    pub interaction: Interaction,
    /// Engine settings.
    pub config: SimulationConfig,
    /// Random seed of the velocities.
    pub seed: u64,
}

impl Gas {
    /// Number of lattice sites per edge [-].
    pub fn sites(&self) -> usize {
        (self.count as f64).cbrt().ceil() as usize
    }

    /// Edge of the box [m]: the lattice plus half a spacing on every side.
    pub fn edge(&self) -> f64 {
        self.sites() as f64 * self.spacing
    }

    /// Builds the simulation: six same-material planes enclosing [0, edge]³, spheres on the
    /// lattice sites (k + 1/2) spacing with random velocities.
    pub fn build(&self) -> Simulation {
        let mut sim = Simulation::new(self.config).expect("valid configuration");
        let material = Material::fan2023();
        let id = sim
            .add_material(material, self.interaction)
            .expect("valid material");
        let edge = self.edge();
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            for (point, normal) in [(DVec3::ZERO, axis), (edge * axis, -axis)] {
                let wall = Wall::plane(
                    point,
                    normal,
                    WallMaterial::Elastic(material),
                    self.interaction,
                )
                .expect("valid plane");
                sim.add_wall(wall).expect("valid wall");
            }
        }
        self.fill(&mut sim, id);
        sim
    }

    fn fill(&self, sim: &mut Simulation, id: MaterialId) {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(self.seed);
        let n = self.sites();
        let mut placed = 0;
        'outer: for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    if placed == self.count {
                        break 'outer;
                    }
                    let position = (DVec3::new(i as f64, j as f64, k as f64) + DVec3::splat(0.5))
                        * self.spacing;
                    let velocity = velocity_in_ball(&mut rng, self.speed);
                    let mut init = ParticleInit::at_rest(position, RADIUS, id);
                    init.velocity = velocity;
                    sim.add_particle(init).expect("valid particle");
                    placed += 1;
                }
            }
        }
    }
}

/// 1000 Table-1 spheres on a cubic lattice 3.1 mm apart with random velocities up to
/// 0.5 m/s (seed 5), in a closed box, with friction, rolling friction and e = 0.2: the pile
/// that the determinism and list-build tests run under `config`.
pub fn pile(config: SimulationConfig) -> Gas {
    Gas {
        count: 1000,
        spacing: 3.1e-3,
        speed: 0.5,
        interaction: Interaction::fan2023(),
        config,
        seed: 5,
    }
}

/// Positions, velocities and spins of every particle, sorted by tag, as raw bits.
pub fn bits_by_tag(sim: &Simulation) -> Vec<(u64, [u64; 9])> {
    let p = sim.particles();
    let mut out: Vec<(u64, [u64; 9])> = (0..p.len())
        .map(|k| {
            let (x, v, w) = (
                p.positions()[k],
                p.velocities()[k],
                p.angular_velocities()[k],
            );
            let b = [x.x, x.y, x.z, v.x, v.y, v.z, w.x, w.y, w.z].map(f64::to_bits);
            (p.tags()[k], b)
        })
        .collect();
    out.sort_by_key(|e| e.0);
    out
}

/// A velocity uniform in the ball of radius `speed` [m/s]: three draws in (−1, 1) from `rng`,
/// repeated until they fall in the unit ball, times `speed`.
pub fn velocity_in_ball(rng: &mut Xoshiro256PlusPlus, speed: f64) -> DVec3 {
    loop {
        let v = DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        );
        if v.length_squared() <= 1.0 {
            return v * speed;
        }
    }
}

/// A flat floor at z = 0: the square [−`half`, `half`]² [m] cut into `n` × `n` squares of two
/// triangles each.
pub fn square_floor(half: f64, n: usize) -> Vec<[DVec3; 3]> {
    let side = 2.0 * half / n as f64;
    let at = |p: usize, q: usize| DVec3::new(-half + p as f64 * side, -half + q as f64 * side, 0.0);
    (0..n)
        .flat_map(|p| (0..n).map(move |q| (p, q)))
        .flat_map(|(p, q)| {
            [
                [at(p, q), at(p + 1, q), at(p + 1, q + 1)],
                [at(p, q), at(p + 1, q + 1), at(p, q + 1)],
            ]
        })
        .collect()
}

/// FNV-1a (64 bit) over `words`: the goldens' hash of a state's bits.
pub fn fnv1a(words: impl Iterator<Item = u64>) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    for word in words {
        for byte in word.to_le_bytes() {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    hash
}

//! The system's energy by kind (docs/physics.md §2.2), the check that a run conserves what it
//! should.

use super::*;

/// Energy budget of the system [J].
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Energy {
    /// Σ ½ m v² [J].
    pub translational: f64,
    /// Σ ½ I ω² [J].
    pub rotational: f64,
    /// Σ −m g·x [J] (zero at the origin).
    pub gravitational: f64,
    /// Elastic energy of the normal Hertz springs, Σ (8/15) E* √R* δ^{5/2} [J].
    pub elastic: f64,
}

impl Energy {
    /// Total mechanical energy [J].
    pub fn total(&self) -> f64 {
        self.translational + self.rotational + self.gravitational + self.elastic
    }
}

impl Simulation {
    /// The energy budget at the current positions and (full-step) velocities.
    pub fn energy(&self) -> Energy {
        let s = &self.state;
        let p = &s.particles;
        let mut e = Energy::default();
        for k in 0..p.len() {
            if p.clump[k] != crate::particles::NO_CLUMP {
                continue; // its clump's energy is counted below
            }
            e.translational += 0.5 * p.mass[k] * p.velocity[k].length_squared();
            e.rotational += 0.5 * p.inertia[k] * p.omega[k].length_squared();
            e.gravitational -= p.mass[k] * s.config.gravity.dot(p.position[k]);
        }
        let clumps = &s.clumps;
        for c in 0..clumps.len() {
            let mass = clumps.body(c).mass;
            e.translational += 0.5 * mass * clumps.velocity[c].length_squared();
            e.rotational += 0.5 * clumps.angular_velocity(c).dot(clumps.momentum[c]);
            e.gravitational -= mass * s.config.gravity.dot(clumps.position[c]);
        }
        let n = s.materials.len();
        let coeffs = |a: u16, b: u16| match s
            .interactions
            .get(a as usize * n + b as usize)
            .copied()
            .flatten()
        {
            Some(i) => {
                PairCoefficients::new(&s.materials[a as usize], Some(&s.materials[b as usize]), &i)
                    .e_star
            }
            None => 0.0,
        };
        for k in 0..s.pairs.len() {
            let (i, j) = (s.pairs.i[k] as usize, s.pairs.j[k] as usize);
            let overlap = p.radius[i] + p.radius[j] - p.position[i].distance(p.position[j]);
            if overlap > 0.0 {
                e.elastic += hertz_energy(
                    coeffs(p.material[i], p.material[j]),
                    harmonic(p.radius[i], p.radius[j]),
                    overlap,
                );
            }
        }
        for k in 0..s.wall_pairs.particle.len() {
            let i = s.wall_pairs.particle[k] as usize;
            if let Some(w) = &s.walls[s.wall_pairs.wall[k] as usize] {
                let overlap = p.radius[i] - w.closest_point(p.position[i]).1;
                if overlap > 0.0 {
                    let c = PairCoefficients::with_wall(
                        &s.materials[p.material[i] as usize],
                        &w.material,
                        &w.interaction,
                    );
                    e.elastic += hertz_energy(c.e_star, p.radius[i], overlap);
                }
            }
        }
        e
    }
}

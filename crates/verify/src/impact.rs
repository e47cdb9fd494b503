//! The single-impact harness shared by the CO and P cases: one sphere against a plane, or two
//! identical spheres head-on, stepped through one contact while the contact is recorded.
//!
//! Gravity is off. The contact starts and ends where the overlap crosses zero; both instants
//! are interpolated linearly between the two steps that bracket the crossing (the overlap is
//! linear in time there, because the force vanishes at δ = 0), so the measured duration is not
//! quantised to Δt. Velocities are read on the first step without overlap: that step applies no
//! contact force, so they are the post-impact velocities, as in the reference integrator of
//! docs/physics.md Appendix B.

use dem::contact::normal::hertz;
use dem::material::{effective_youngs_modulus, harmonic};
use dem::timescale::hertz_contact_time;
use dem::{
    ContactLaws, DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig, Wall,
    WallMaterial,
};

use crate::VerifyError;

/// What the sphere hits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// A plane z = 0 with normal +z, made of this material.
    Plane(WallMaterial),
    /// An identical sphere coming the other way with the opposite velocity and spin.
    Twin,
}

/// One impact to run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// Sphere material.
    pub material: Material,
    /// Sphere radius [m].
    pub radius: f64,
    /// Friction, rolling friction and restitution of the contact.
    pub interaction: Interaction,
    /// Contact sub-models.
    pub laws: ContactLaws,
    /// What the sphere hits.
    pub target: Target,
    /// Sphere velocity before impact [m/s]. For `Plane` the normal part is −z; for `Twin` the
    /// approach is along +x (the twin moves with the opposite velocity).
    pub velocity: DVec3,
    /// Sphere angular velocity before impact [rad/s].
    pub angular_velocity: DVec3,
    /// Time steps per elastic Hertz contact duration at the approach speed [-].
    pub steps_per_contact: f64,
}

/// What was recorded during one impact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactRecord {
    /// Contact duration, zero-crossing to zero-crossing of the overlap [s].
    pub duration: f64,
    /// Largest overlap [m].
    pub peak_overlap: f64,
    /// Largest normal contact force [N].
    pub peak_force: f64,
    /// Largest |F_n − F_Hertz(δ)| / F_Hertz(δ) over the contact [-]; only meaningful for e = 1.
    pub hertz_deviation: f64,
    /// Sphere velocity after separation [m/s].
    pub velocity: DVec3,
    /// Sphere angular velocity after separation [rad/s].
    pub angular_velocity: DVec3,
    /// Normal approach speed before impact [m/s] (relative, for `Twin`).
    pub approach_speed: f64,
    /// Normal separation speed after impact [m/s] (relative, for `Twin`).
    pub separation_speed: f64,
    /// Time step used [s].
    pub time_step: f64,
    /// Steps with non-zero overlap [-].
    pub steps_in_contact: u64,
}

impl ImpactRecord {
    /// Normal coefficient of restitution, separation over approach speed [-].
    pub fn restitution(&self) -> f64 {
        self.separation_speed / self.approach_speed
    }
}

impl Impact {
    /// Effective Young's modulus E* of the contact [Pa].
    pub fn effective_modulus(&self) -> f64 {
        match self.target {
            Target::Plane(WallMaterial::Rigid) => effective_youngs_modulus(&self.material, None),
            Target::Plane(WallMaterial::Elastic(w)) => {
                effective_youngs_modulus(&self.material, Some(&w))
            }
            Target::Twin => effective_youngs_modulus(&self.material, Some(&self.material)),
        }
    }

    /// Sphere mass [kg].
    pub fn mass(&self) -> f64 {
        self.material.density * 4.0 / 3.0 * std::f64::consts::PI * self.radius.powi(3)
    }

    /// Effective radius R* and mass m* [m, kg].
    fn effective_radius_and_mass(&self) -> (f64, f64) {
        match self.target {
            Target::Plane(_) => (self.radius, self.mass()),
            Target::Twin => (
                harmonic(self.radius, self.radius),
                harmonic(self.mass(), self.mass()),
            ),
        }
    }

    /// Normal approach speed [m/s].
    fn approach_speed(&self) -> f64 {
        match self.target {
            Target::Plane(_) => -self.velocity.z,
            Target::Twin => 2.0 * self.velocity.x,
        }
    }

    /// The time step that resolves the elastic contact with `steps_per_contact` steps [s].
    pub fn time_step(&self) -> f64 {
        let (r, m) = self.effective_radius_and_mass();
        hertz_contact_time(self.effective_modulus(), r, m, self.approach_speed())
            / self.steps_per_contact
    }

    /// Runs the impact and records it.
    pub fn run(&self) -> Result<ImpactRecord, VerifyError> {
        let dt = self.time_step();
        let approach = self.approach_speed();
        let mut config = SimulationConfig::new(dt);
        config.gravity = DVec3::ZERO;
        config.laws = self.laws;
        // Two particles at most: re-sorting would only shuffle indices.
        config.resort_every = 0;
        let mut sim = Simulation::new(config)?;
        let mat = sim.add_material(self.material, self.interaction)?;
        // Start two steps of travel short of touching, so the approach is free flight.
        let gap = 2.0 * approach * dt;
        let (tag, twin) = match self.target {
            Target::Plane(wall_material) => {
                sim.add_wall(Wall::plane(
                    DVec3::ZERO,
                    DVec3::Z,
                    wall_material,
                    self.interaction,
                )?)?;
                let init = ParticleInit {
                    position: DVec3::new(0.0, 0.0, self.radius + gap),
                    velocity: self.velocity,
                    angular_velocity: self.angular_velocity,
                    radius: self.radius,
                    material: mat,
                    flags: 0,
                };
                (sim.add_particle(init)?, None)
            }
            Target::Twin => {
                let x = self.radius + 0.5 * gap;
                let a = ParticleInit {
                    position: DVec3::new(-x, 0.0, 0.0),
                    velocity: self.velocity,
                    angular_velocity: self.angular_velocity,
                    radius: self.radius,
                    material: mat,
                    flags: 0,
                };
                let b = ParticleInit {
                    position: DVec3::new(x, 0.0, 0.0),
                    velocity: -self.velocity,
                    angular_velocity: -self.angular_velocity,
                    ..a
                };
                let ta = sim.add_particle(a)?;
                (ta, Some(sim.add_particle(b)?))
            }
        };
        let (r_eff, _) = self.effective_radius_and_mass();
        let e_star = self.effective_modulus();
        // Overlap, unit normal (towards the sphere), normal relative speed, sphere index.
        let probe = |sim: &Simulation| -> (f64, DVec3, f64, usize) {
            let p = sim.particles();
            let i = p.index_of(tag).unwrap_or(0);
            match twin {
                None => {
                    let z = p.positions()[i].z;
                    (self.radius - z, DVec3::Z, p.velocities()[i].z, i)
                }
                Some(t) => {
                    let j = p.index_of(t).unwrap_or(0);
                    let d = p.positions()[i] - p.positions()[j];
                    let dist = d.length();
                    let n = d / dist;
                    (
                        2.0 * self.radius - dist,
                        n,
                        (p.velocities()[i] - p.velocities()[j]).dot(n),
                        i,
                    )
                }
            }
        };
        let budget = (100.0 * self.steps_per_contact) as u64 + 10;
        let mut previous = probe(&sim).0;
        let mut start = None;
        let mut record = ImpactRecord {
            duration: 0.0,
            peak_overlap: 0.0,
            peak_force: 0.0,
            hertz_deviation: 0.0,
            velocity: DVec3::ZERO,
            angular_velocity: DVec3::ZERO,
            approach_speed: approach,
            separation_speed: 0.0,
            time_step: dt,
            steps_in_contact: 0,
        };
        for _ in 0..budget {
            let t_before = sim.time();
            sim.step()?;
            let (overlap, n, v_n, i) = probe(&sim);
            // Crossing instant by linear interpolation between the bracketing steps.
            let crossing = t_before + dt * previous / (previous - overlap);
            if overlap > 0.0 {
                if start.is_none() {
                    start = Some(crossing);
                }
                record.steps_in_contact += 1;
                record.peak_overlap = record.peak_overlap.max(overlap);
                // Gravity is off, so the force on the sphere is the contact force alone.
                let f_n = sim.particles().forces()[i].dot(n);
                record.peak_force = record.peak_force.max(f_n);
                let elastic = hertz(e_star, r_eff, overlap).force;
                if elastic > 0.0 {
                    record.hertz_deviation =
                        record.hertz_deviation.max((f_n - elastic).abs() / elastic);
                }
            } else if let Some(t0) = start {
                record.duration = crossing - t0;
                let p = sim.particles();
                record.velocity = p.velocities()[i];
                record.angular_velocity = p.angular_velocities()[i];
                record.separation_speed = v_n;
                return Ok(record);
            }
            previous = overlap;
        }
        Err(VerifyError::NoEvent {
            what: "separation after impact",
            steps: budget,
        })
    }
}

/// Post-impact state of an oblique impact on a rigid plane, in the sign convention of
/// docs/physics.md Appendix B: motion along +x, spin ω with contact-point slip v_x + ωR.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oblique {
    /// Centre tangential velocity after impact [m/s].
    pub tangential: f64,
    /// Normal velocity after impact (positive, away from the plane) [m/s].
    pub normal: f64,
    /// Spin after impact, Appendix-B sign (−ω_y of the engine's right-handed frame) [rad/s].
    pub spin: f64,
    /// Contact-point tangential velocity after impact, v_x + spin·R [m/s].
    pub contact_tangential: f64,
}

/// An oblique impact on a rigid plane with the Appendix-B sign convention: `tangential` and
/// `normal` are the incoming centre velocities along +x and towards the plane [m/s], `spin`
/// the incoming spin with contact-point slip v_x + spin·R [rad/s].
#[allow(clippy::too_many_arguments)]
pub fn oblique_on_rigid_plane(
    material: Material,
    radius: f64,
    interaction: Interaction,
    laws: ContactLaws,
    tangential: f64,
    normal: f64,
    spin: f64,
    steps_per_contact: f64,
) -> Result<Oblique, VerifyError> {
    // The engine's contact point lies at −R ẑ, so its slip is v_x − R ω_y: ω_y = −spin.
    let record = Impact {
        material,
        radius,
        interaction,
        laws,
        target: Target::Plane(WallMaterial::Rigid),
        velocity: DVec3::new(tangential, 0.0, -normal),
        angular_velocity: DVec3::new(0.0, -spin, 0.0),
        steps_per_contact,
    }
    .run()?;
    let spin_after = -record.angular_velocity.y;
    Ok(Oblique {
        tangential: record.velocity.x,
        normal: record.velocity.z,
        spin: spin_after,
        contact_tangential: record.velocity.x + spin_after * radius,
    })
}

/// The three Hertz rows of an elastic impact (CO1, CO2): peak overlap [m], peak normal force
/// [N] and contact duration [s] against their closed forms, each at 1 % (docs/physics.md §9 CO1).
pub fn hertz_rows(
    test: &str,
    name: &str,
    record: &ImpactRecord,
    (overlap, force, duration): (f64, f64, f64),
) -> [crate::Row; 3] {
    use crate::Row;
    [
        Row::relative(
            test,
            format!("{name}: peak overlap [m]"),
            overlap,
            record.peak_overlap,
            0.01,
        ),
        Row::relative(
            test,
            format!("{name}: peak normal force [N]"),
            force,
            record.peak_force,
            0.01,
        ),
        Row::relative(
            test,
            format!("{name}: contact duration [s]"),
            duration,
            record.duration,
            0.01,
        ),
    ]
}

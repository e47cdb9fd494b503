//! The single-impact harness shared by the CO, P and H cases: one sphere against a plane, two
//! identical spheres head-on, or two spheres of any radii and materials head-on, stepped
//! through one contact while the contact is recorded.
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
    ContactLaws, DVec3, Interaction, Material, MaterialId, ParticleInit, ParticleTag, Simulation,
    SimulationConfig, Wall, WallMaterial,
};

use crate::VerifyError;

/// What the sphere hits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// A plane z = 0 with normal +z, made of this material.
    Plane(WallMaterial),
    /// An identical sphere coming the other way with the opposite velocity and spin.
    Twin,
    /// A sphere of its own radius and material on the +x side, in line with the first.
    Sphere(Partner),
}

/// The second sphere of a head-on impact of unequal or dissimilar spheres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Partner {
    /// Its material; the pair's interaction is the impact's `interaction`.
    pub material: Material,
    /// Its radius [m].
    pub radius: f64,
    /// Its velocity before impact [m/s]; the approach is along +x, so `velocity.x` is below
    /// the first sphere's.
    pub velocity: DVec3,
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
    /// Velocity of the second sphere after separation [m/s]; zero for a plane.
    pub partner_velocity: DVec3,
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
            Target::Sphere(other) => {
                effective_youngs_modulus(&self.material, Some(&other.material))
            }
        }
    }

    /// Sphere mass [kg].
    pub fn mass(&self) -> f64 {
        sphere_mass(&self.material, self.radius)
    }

    /// The twin of the first sphere and its spin: the same sphere with the opposite motion.
    fn twin(&self) -> (Partner, DVec3) {
        let other = Partner {
            material: self.material,
            radius: self.radius,
            velocity: -self.velocity,
        };
        (other, -self.angular_velocity)
    }

    /// The second sphere, if the target is one, and its spin before impact.
    fn partner(&self) -> Option<(Partner, DVec3)> {
        match self.target {
            Target::Plane(_) => None,
            Target::Twin => Some(self.twin()),
            Target::Sphere(other) => Some((other, DVec3::ZERO)),
        }
    }

    /// Effective radius R* and mass m* [m, kg].
    fn effective_radius_and_mass(&self) -> (f64, f64) {
        match self.partner() {
            None => (self.radius, self.mass()),
            Some((other, _)) => (
                harmonic(self.radius, other.radius),
                harmonic(self.mass(), sphere_mass(&other.material, other.radius)),
            ),
        }
    }

    /// Normal approach speed [m/s].
    fn approach_speed(&self) -> f64 {
        match self.partner() {
            None => -self.velocity.z,
            Some((other, _)) => self.velocity.x - other.velocity.x,
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
        let first = ParticleInit {
            position: DVec3::ZERO,
            velocity: self.velocity,
            angular_velocity: self.angular_velocity,
            radius: self.radius,
            material: mat,
            flags: 0,
        };
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
                    ..first
                };
                (sim.add_particle(init)?, None)
            }
            // A twin shares the first sphere's material.
            Target::Twin => {
                let (other, spin) = self.twin();
                head_on(&mut sim, first, gap, (other, spin, mat))?
            }
            // Another sphere gets its own material, meeting the first with the impact's
            // interaction.
            Target::Sphere(other) => {
                let id = sim.add_material(other.material, self.interaction)?;
                sim.set_interaction(mat, id, self.interaction)?;
                head_on(&mut sim, first, gap, (other, DVec3::ZERO, id))?
            }
        };
        let (r_eff, _) = self.effective_radius_and_mass();
        let e_star = self.effective_modulus();
        // Overlap, unit normal (towards the sphere), normal relative speed, sphere index,
        // second sphere's velocity.
        let probe = |sim: &Simulation| -> (f64, DVec3, f64, usize, DVec3) {
            let p = sim.particles();
            let i = p.index_of(tag).unwrap_or(0);
            match twin {
                None => {
                    let z = p.positions()[i].z;
                    (
                        self.radius - z,
                        DVec3::Z,
                        p.velocities()[i].z,
                        i,
                        DVec3::ZERO,
                    )
                }
                Some((t, other_radius)) => {
                    let j = p.index_of(t).unwrap_or(0);
                    let d = p.positions()[i] - p.positions()[j];
                    let dist = d.length();
                    let n = d / dist;
                    (
                        self.radius + other_radius - dist,
                        n,
                        (p.velocities()[i] - p.velocities()[j]).dot(n),
                        i,
                        p.velocities()[j],
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
            partner_velocity: DVec3::ZERO,
            approach_speed: approach,
            separation_speed: 0.0,
            time_step: dt,
            steps_in_contact: 0,
        };
        for _ in 0..budget {
            let t_before = sim.time();
            sim.step()?;
            let (overlap, n, v_n, i, partner_velocity) = probe(&sim);
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
                record.partner_velocity = partner_velocity;
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

/// Places `first` and the second sphere (its description, spin and material id) on the x
/// axis, their surfaces `gap` [m] apart about the origin; returns the first's tag and the
/// second's tag and radius [m].
fn head_on(
    sim: &mut Simulation,
    first: ParticleInit,
    gap: f64,
    (other, spin, material): (Partner, DVec3, MaterialId),
) -> Result<(ParticleTag, Option<(ParticleTag, f64)>), VerifyError> {
    let a = ParticleInit {
        position: DVec3::new(-(first.radius + 0.5 * gap), 0.0, 0.0),
        ..first
    };
    let b = ParticleInit {
        position: DVec3::new(other.radius + 0.5 * gap, 0.0, 0.0),
        velocity: other.velocity,
        angular_velocity: spin,
        radius: other.radius,
        material,
        flags: 0,
    };
    let ta = sim.add_particle(a)?;
    Ok((ta, Some((sim.add_particle(b)?, other.radius))))
}

/// Mass of a sphere of `material` and `radius` [m]: ρ (4/3) π R³ [kg].
pub fn sphere_mass(material: &Material, radius: f64) -> f64 {
    material.density * 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
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

//! The set-ups shared by the cohesion cases J1–J4 (docs/physics.md §2.4–2.6, §9): a sphere
//! held still while a rigid plane presses into it and pulls away at a constant speed (the
//! force–separation curve, measured quasi-statically), and two identical free spheres meeting
//! head-on (the dynamics of a bond). Gravity is off and the contact frictionless and elastic
//! (e = 1): the force is the cohesive law's alone.

use std::f64::consts::PI;

use dem::material::{effective_youngs_modulus, harmonic};
use dem::{
    Cohesion, ContactLaws, DVec3, Interaction, Material, ParticleInit, Simulation,
    SimulationConfig, Wall, WallMaterial, WallMotion, FLAG_FROZEN,
};

use crate::impact::sphere_mass;
use crate::VerifyError;

/// A soft solid, so that adhesion is strong against the elastic forces: E = 10⁸ Pa,
/// ν = 0.3, ρ = 2500 kg/m³.
pub const SOFT: Material = Material {
    density: 2500.0,
    youngs_modulus: 1.0e8,
    poisson_ratio: 0.3,
};

/// Sphere radius R [m].
pub const RADIUS: f64 = 0.5e-3;

/// Frictionless and elastic, with cohesion `cohesion`.
pub fn adhesive(cohesion: Cohesion) -> Interaction {
    Interaction {
        friction: 0.0,
        rolling_friction: 0.0,
        restitution: 1.0,
        cohesion,
    }
}

/// E* of the sphere against the rigid plane [Pa].
pub fn plane_modulus() -> f64 {
    effective_youngs_modulus(&SOFT, None)
}

/// E* of two spheres [Pa].
pub fn pair_modulus() -> f64 {
    effective_youngs_modulus(&SOFT, Some(&SOFT))
}

/// m* of two spheres [kg].
pub fn pair_mass() -> f64 {
    let m = sphere_mass(&SOFT, RADIUS);
    harmonic(m, m)
}

/// The JKR closed forms J1 and J2 check the engine against, written out here rather than
/// taken from `dem::contact::jkr` (Johnson 1985, §5.5), for E* `e` [Pa], R* `r` [m] and work
/// of adhesion `w` [J/m²].
pub struct JkrReference {
    /// Pull-off force F_c = (3/2)π w R* [N].
    pub pull_off: f64,
    /// Breaking overlap δ_c = −(3/4)(π² w² R*/E*²)^{1/3} [m].
    pub breaking_overlap: f64,
    /// The loop's energy ∫_{δ_c}^{0} (−F) dδ [J]: ∫ F δ'(a) da between the breaking radius
    /// a_f = (πwR*²/(8E*))^{1/3} and the touching radius a_1 = (2πwR*²/E*)^{1/3}, with F δ' a
    /// polynomial in √a.
    pub loop_energy: f64,
}

impl JkrReference {
    /// The closed forms for E* `e` [Pa], R* `r` [m] and w `w` [J/m²].
    pub fn new(e: f64, r: f64, w: f64) -> Self {
        let (ca, cb, cc) = (
            4.0 * e / (3.0 * r),
            (8.0 * PI * w * e).sqrt(),
            (2.0 * PI * w / e).sqrt(),
        );
        let primitive = |a: f64| {
            2.0 * ca / (5.0 * r) * a.powi(5)
                - (ca * cc / 2.0 + 2.0 * cb / r) * (2.0 / 7.0) * a.powf(3.5)
                + cb * cc / 4.0 * a * a
        };
        let a_touch = (2.0 * PI * w * r * r / e).cbrt();
        let a_break = (PI * w * r * r / (8.0 * e)).cbrt();
        Self {
            pull_off: 1.5 * PI * w * r,
            breaking_overlap: -0.75 * (PI * PI * w * w * r / (e * e)).cbrt(),
            loop_energy: primitive(a_break) - primitive(a_touch),
        }
    }
}

/// One sample of a quasi-static cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Overlap δ = R − distance to the plane [m] (negative across a gap).
    pub overlap: f64,
    /// Normal force on the sphere [N], positive when repulsive.
    pub force: f64,
    /// True while the plane pulls away.
    pub unloading: bool,
}

/// A plane that starts `start` [m] of overlap from the held sphere (negative: a gap), moves
/// into it at `speed` [m/s] until the overlap is `deepest` [m], then pulls away until the
/// overlap is `end` [m]; one sample per step of `dt` [s].
pub fn pressed(
    cohesion: Cohesion,
    (start, deepest, end): (f64, f64, f64),
    speed: f64,
    dt: f64,
) -> Result<Vec<Sample>, VerifyError> {
    let interaction = adhesive(cohesion);
    let mut config = SimulationConfig::new(dt);
    config.gravity = DVec3::ZERO;
    config.laws = ContactLaws::default();
    config.resort_every = 0;
    let mut sim = Simulation::new(config)?;
    let id = sim.add_material(SOFT, interaction)?;
    let wall = sim.add_wall(Wall::plane(
        DVec3::new(0.0, 0.0, -RADIUS + start),
        DVec3::Z,
        WallMaterial::Rigid,
        interaction,
    )?)?;
    sim.add_particle(ParticleInit {
        flags: FLAG_FROZEN,
        ..ParticleInit::at_rest(DVec3::ZERO, RADIUS, id)
    })?;
    let moving = |velocity: f64| WallMotion {
        velocity: DVec3::new(0.0, 0.0, velocity),
        displaced: true,
        ..WallMotion::default()
    };
    sim.set_wall_motion(wall, moving(speed))?;
    let travel = (deepest - start) + (deepest - end);
    let budget = (travel / (speed * dt) * 1.01) as usize + 10;
    let mut samples = Vec::with_capacity(budget);
    let mut unloading = false;
    for _ in 0..budget {
        sim.step()?;
        let (_, dist) = sim
            .wall(wall)
            .expect("the plane stays")
            .closest_point(DVec3::ZERO);
        let overlap = RADIUS - dist;
        samples.push(Sample {
            overlap,
            force: sim.particles().forces()[0].z,
            unloading,
        });
        if !unloading && overlap >= deepest {
            unloading = true;
            sim.set_wall_motion(wall, moving(-speed))?;
        } else if unloading && overlap <= end {
            return Ok(samples);
        }
    }
    Err(VerifyError::NoEvent {
        what: "the end of the pull-away",
        steps: budget as u64,
    })
}

/// What a head-on meeting of two free spheres came to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Meeting {
    /// The spheres parted: their surfaces ended farther apart than `apart` with the
    /// relative speed below.
    pub parted: bool,
    /// Relative speed of separation at the end [m/s] (positive when they move apart).
    pub separation_speed: f64,
}

/// Two identical spheres, surfaces `gap` [m] apart, approaching each other at relative speed
/// `speed` [m/s]; stepped with `dt` [s] until their surfaces are `apart` [m] apart or
/// `steps` steps have gone.
pub fn meeting(
    cohesion: Cohesion,
    speed: f64,
    (gap, apart): (f64, f64),
    dt: f64,
    steps: u64,
) -> Result<Meeting, VerifyError> {
    let interaction = adhesive(cohesion);
    let mut config = SimulationConfig::new(dt);
    config.gravity = DVec3::ZERO;
    config.resort_every = 0;
    let mut sim = Simulation::new(config)?;
    let id = sim.add_material(SOFT, interaction)?;
    let half = RADIUS + 0.5 * gap;
    for (x, v) in [(-half, 0.5 * speed), (half, -0.5 * speed)] {
        sim.add_particle(ParticleInit {
            velocity: DVec3::new(v, 0.0, 0.0),
            ..ParticleInit::at_rest(DVec3::new(x, 0.0, 0.0), RADIUS, id)
        })?;
    }
    let state = |sim: &Simulation| {
        let p = sim.particles();
        let (x, v) = (p.positions(), p.velocities());
        // Index order does not matter: both the distance and the speed are symmetric.
        let d = x[1] - x[0];
        let n = d / d.length();
        (d.length() - 2.0 * RADIUS, (v[1] - v[0]).dot(n))
    };
    for _ in 0..steps {
        sim.step()?;
        let (surface_gap, separation_speed) = state(&sim);
        if surface_gap > apart {
            return Ok(Meeting {
                parted: true,
                separation_speed,
            });
        }
    }
    let (_, separation_speed) = state(&sim);
    Ok(Meeting {
        parted: false,
        separation_speed,
    })
}

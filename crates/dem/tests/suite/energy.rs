//! Energy bookkeeping of the integrator: an elastic, frictionless gas conserves its total energy
//! (kinetic + Hertz elastic), a damped, frictional gas never gains energy, and a piston's
//! work is what the gas gains, and dissipates when it can.

use crate::common;

use common::Gas;
use dem::{DVec3, Interaction, RollingLaw, SimulationConfig, WallId, WallMotion};

/// The elastic gas: 500 Table-1 spheres at up to 1 m/s in a 36 mm box (solid fraction 0.15),
/// no gravity, Δt = 1 µs. The fastest binary impacts (≈ 3 m/s relative) then last ≈ 70 µs,
/// i.e. ≥ 70 steps per contact, so velocity Verlet's energy error stays small.
fn elastic_gas() -> Gas {
    let mut config = SimulationConfig::new(1.0e-6);
    config.gravity = DVec3::ZERO;
    config.laws.rolling = RollingLaw::None;
    Gas {
        count: 500,
        spacing: 4.5e-3,
        speed: 1.0,
        interaction: Interaction {
            friction: 0.0,
            rolling_friction: 0.0,
            restitution: 1.0,
            cohesion: dem::Cohesion::None,
        },
        config,
        seed: 11,
    }
}

#[test]
fn elastic_gas_conserves_energy() {
    let mut sim = elastic_gas().build();
    let e0 = sim.energy().total();
    let mut worst: f64 = 0.0;
    let mut collided = false;
    for _ in 0..1000 {
        sim.run(100).expect("the elastic gas runs");
        let e = sim.energy();
        worst = worst.max((e.total() - e0).abs() / e0);
        collided |= sim.contacts().particle_particle > 0 && e.elastic > 0.0;
    }
    // Velocity Verlet is symplectic: over 1e5 steps the energy only fluctuates with the
    // O((Δt/t_c)²) error of the contacts in progress and the small kicks at contact onset,
    // where the Hertz force is not smooth. 1e-4 relative (docs/physics.md: ≥ 50 steps per
    // contact) would be exceeded by a missing half kick, a wrong elastic energy or a force/
    // energy mismatch. (Measured: 6.6e-6.)
    assert!(worst < 1e-4, "largest relative energy error {worst:e}");
    assert!(
        collided,
        "the gas must actually collide for the check to mean anything"
    );
}

#[test]
fn damped_gas_never_gains_energy() {
    let mut gas = elastic_gas();
    gas.interaction = Interaction {
        friction: 0.5,
        rolling_friction: 0.01,
        restitution: 0.2,
        cohesion: dem::Cohesion::None,
    };
    gas.config.laws.rolling = RollingLaw::ConstantTorque { limiter: false };
    let mut sim = gas.build();
    let e0 = sim.energy().total();
    let mut previous = e0;
    let mut worst_rise: f64 = 0.0;
    for _ in 0..300 {
        sim.run(100).expect("the damped gas runs");
        let e = sim.energy().total();
        worst_rise = worst_rise.max((e - previous) / e0);
        previous = e;
    }
    // Damping, Coulomb sliding and rolling friction only remove energy. The measured total may
    // still rise by the integrator's symplectic fluctuation, measured in the elastic gas above
    // at 6.6e-6 of E0, so that is the allowance (rounded up to 1e-5). The release of tangential
    // spring energy, which sim.energy() does not count, could also show as a rise, but the
    // normal dashpot dissipates far more over the same contact. (Measured: the largest rise
    // between checks is 1e-15 of E0, round-off.) A sign error in a dashpot, or a rolling torque
    // that feeds spin, adds energy at the rate of the dissipation itself, ≫ 1e-5 per 100 steps.
    assert!(
        worst_rise < 1e-5,
        "energy rose by {worst_rise:e} of E0 between checks"
    );
    assert!(
        previous < 0.9 * e0,
        "a gas with e = 0.2 must lose energy ({previous:e} of {e0:e})"
    );
}

/// The gas of [`elastic_gas`] under gravity, squeezed by its lid: the top plane of the box
/// moves down along its normal at 0.2 m/s for 10 ms (2 mm of the 36 mm box), displaced every
/// step. Returns the lid's work on the spheres, W = −v · J, J being the impulse the spheres
/// exerted on it [J], and the total energy before and after [J].
fn squeezed(gas: &Gas) -> (f64, f64, f64) {
    let mut sim = gas.build();
    // The box's planes are added x, y, z, each lower then upper: the lid is the sixth.
    let lid = WallId(5);
    let speed = 0.2;
    let velocity = DVec3::new(0.0, 0.0, -speed);
    sim.set_wall_motion(
        lid,
        WallMotion {
            velocity,
            displaced: true,
            ..WallMotion::default()
        },
    )
    .expect("the lid moves");
    let e0 = sim.energy().total();
    let j0 = sim.wall_impulse(lid).expect("the lid").force;
    sim.run(10_000).expect("the squeezed gas runs");
    let j = sim.wall_impulse(lid).expect("the lid").force - j0;
    assert!(
        j.z > 0.0,
        "the spheres push the lid up as it comes down: J = {j} N s"
    );
    (-velocity.dot(j), e0, sim.energy().total())
}

#[test]
fn a_piston_does_the_work_the_elastic_gas_gains_and_no_less_than_a_damped_gas_gains() {
    // Work–energy theorem for a wall displaced along its normal (docs/physics.md §5.4): the
    // lid's force on the spheres times its velocity, summed step by step, is the work done on
    // them. In the elastic, frictionless gas nothing dissipates, so that work is the change of
    // kinetic, gravitational and Hertz elastic energy. The two sides differ by velocity
    // Verlet's energy fluctuation (6.6e-6 of E0 in `elastic_gas_conserves_energy`, 1e-4 of W
    // here) and by the impulse's half step at each end of the window: 1e-3 of W. A lid whose
    // load is booked with the wrong sign or on the wrong step, or whose motion is not seen by
    // the contact law, breaks the balance by the order of W itself. (Measured: W = 6.572e-4
    // J, ΔE = 6.571e-4 J, 2.1e-4 apart.)
    let mut gas = elastic_gas();
    gas.config.gravity = DVec3::new(0.0, 0.0, -9.81);
    let (work, e0, e1) = squeezed(&gas);
    assert!(
        work > 0.01 * e0,
        "the lid must do work of the order of the gas's energy: W = {work:e} J, E0 = {e0:e} J"
    );
    let gained = e1 - e0;
    assert!(
        (work - gained).abs() <= 1e-3 * work,
        "the lid did {work:e} J, the elastic gas gained {gained:e} J"
    );

    // With e = 0.2, friction and rolling friction the gas dissipates: the lid's work covers
    // the energy gained and more, never less (up to the same fluctuation, 1e-5 of E0).
    // (Measured: W = 2.04e-4 J while the gas lost 4.04e-3 J: 4.25e-3 J dissipated.)
    gas.interaction = Interaction {
        friction: 0.5,
        rolling_friction: 0.01,
        restitution: 0.2,
        cohesion: dem::Cohesion::None,
    };
    gas.config.laws.rolling = RollingLaw::ConstantTorque { limiter: false };
    let (work, e0, e1) = squeezed(&gas);
    let dissipated = work - (e1 - e0);
    assert!(
        dissipated > 1e-5 * e0,
        "the damped gas dissipates: W = {work:e} J, ΔE = {:e} J",
        e1 - e0
    );
}

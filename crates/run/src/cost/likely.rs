//! How long a run will likely take, beside the upper bound of [`super::time_left`]: the
//! settling as long as the last poured spheres take to land and the bed to calm, the
//! discharge as the mass in the container over the Beverloo rate of its orifice (docs/user-guide.md, "What a run costs").
//!
//! Where no law applies (the heap test, an orifice narrow enough to clog, an orifice the law
//! gives no flow through) the discharge keeps its bound, and [`DischargeModel::bounded`]
//! says why.

use serde::Serialize;

use super::steps::{fall_time, PhaseTimes};
use crate::protocol::{fill_band, CHECK_INTERVAL, MIN_SETTLE_AFTER_FILL};
use case::{Case, CuboidOutlet, Geometry, MeshOutlet};

/// Beverloo's discharge coefficient C [-]: the paper's fit (Fig. 2b) and the classic value
/// for spheres through circular orifices (docs/physics.md §8.1, §8.3).
pub const BEVERLOO_C: f64 = 0.58;
/// Beverloo's k for a slot [-]: the paper's fit, k d = 4.65 mm for d = 3 mm (§8.1).
pub const SLOT_K: f64 = 1.55;
/// Beverloo's k for a circular orifice [-]: spheres (Nedderman et al. 1982, §8.3).
pub const ORIFICE_K: f64 = 1.5;
/// Bulk volume fraction φ_B that turns the particle density into the bulk density ρ_b of the
/// law [-]: the paper's static fraction of the angle series (§8.2, ρ_b = 1475 kg/m³ for
/// glass).
pub const BULK_FRACTION: f64 = 0.59;
/// Orifices narrower than this many mean diameters may clog at random (the paper's study
/// loses cases at 6 d) and the law fails there (§8.3, D/d ≲ 6): their discharge keeps its
/// bound [-].
pub const MIN_ORIFICE_DIAMETERS: f64 = 6.0;

/// The discharge rate that the likely discharge time is reckoned with.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DischargeModel {
    /// The law used: "beverloo_2d" (a slot across the container, per unit of its length),
    /// "beverloo_3d" (a circular orifice); `None` where the bound is kept.
    pub law: Option<&'static str>,
    /// Predicted mass discharge rate W [kg/s]; NaN where no law applies.
    pub rate: f64,
    /// Mass in the container when the gate opens [kg].
    pub mass: f64,
    /// Fraction of that mass the run waits to leave [-]: 1, or `protocol.stop_fraction`
    /// (at least `measure.steady_end_fraction`, where the steady window ends).
    pub fraction: f64,
    /// Time that fraction takes to leave at the rate [s]; NaN where no law applies. The
    /// likely discharge adds `protocol.clog_timeout` to it when the run waits for the whole
    /// mass (stagnant zones end it by that timeout), and never exceeds its bound.
    pub flowing: f64,
    /// Why the discharge keeps its bound (no law applies, or it may clog); `None` where the
    /// law sets it.
    pub bounded: Option<String>,
}

/// The likely cost of a run: its simulated time, particle-steps and wall time by part.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LikelyCost {
    /// Likely simulated time of each part [s]: the fill as estimated, the settling and the
    /// discharge by their models, never over their bounds.
    pub simulated: PhaseTimes,
    /// Likely particle-steps of each part [-]: the discharge's at the mean count in the
    /// container while the mass leaves at a steady rate.
    pub particle_steps: PhaseTimes,
    /// Likely wall time of each part on this machine [s].
    pub wall_time: PhaseTimes,
    /// How the discharge was reckoned.
    pub discharge: DischargeModel,
}

/// Time a 3D bed takes to calm down after its last poured spheres have landed [s]: measured
/// settlings of the reduced benchmark silo took 0.30 s (20 000 spheres) and 0.48 s (5000
/// spheres over a 30 mm orifice) from the end of the pour, 0.14 s of it the last batch's fall.
/// The quasi-2D slab, whose front and back walls take the spheres' energy, calms as they land
/// (the base case: 0.11 s after the pour, against a fall of 0.20 s).
pub const CALM_TIME_3D: f64 = 0.3;

/// A slab thinner than this many mean diameters is quasi-2D and calms as its spheres land
/// [-] (the paper's is 1.01 d thick).
const QUASI_2D_DIAMETERS: f64 = 2.0;

/// The settling after a pour [s]: the time for a sphere poured at `protocol.fill_speed` from
/// the top of the insertion band to fall to the outlet plane (the bed's surface lies
/// somewhere below the band, so this errs long), plus [`CALM_TIME_3D`] for a 3D bed; within
/// the first check and `protocol.max_settle_time`.
pub(crate) fn likely_settle_once(case: &Case) -> f64 {
    let (_, top) = fill_band(case);
    let quasi_2d = case
        .slab()
        .is_some_and(|s| s.thickness < QUASI_2D_DIAMETERS * case.particles.mean_diameter());
    let calm = if quasi_2d { 0.0 } else { CALM_TIME_3D };
    (fall_time(case, top) + calm).clamp(MIN_SETTLE_AFTER_FILL, case.protocol.max_settle_time)
        + CHECK_INTERVAL
}

/// The orifice of `case` and the Beverloo rate through it [kg/s], or why no law applies.
fn discharge_rate(case: &Case, mass_per_volume: f64) -> Result<(&'static str, f64), String> {
    let d = case.particles.mean_diameter();
    let g = case.gravity;
    let rho_b = BULK_FRACTION * mass_per_volume;
    // A slot of width `width` across the whole `length` of the container: the 2D law per unit
    // length, no end correction (the slot ends at walls).
    let slot = |width: f64, length: f64| {
        (
            "beverloo_2d",
            width,
            analysis::beverloo::beverloo_2d_rate(BEVERLOO_C, rho_b, width, SLOT_K, d, length, g),
        )
    };
    let orifice = |diameter: f64| {
        (
            "beverloo_3d",
            diameter,
            analysis::beverloo3d::beverloo_3d_rate(BEVERLOO_C, rho_b, diameter, ORIFICE_K, d, g),
        )
    };
    let (law, width, rate) = match &case.geometry {
        Geometry::Slab(s) => {
            // Brown's hopper-angle factor of the paper (Eq. 3, docs/physics.md §8.4).
            let (law, width, rate) = slot(s.outlet_width, s.thickness);
            let brown = analysis::flowrate::brown_ratio(s.hopper_angle()).unwrap_or(1.0);
            (law, width, rate * brown)
        }
        Geometry::Cylinder(c) => orifice(c.outlet_diameter),
        Geometry::Cuboid(b) | Geometry::DrawDown(case::DrawDownGeometry { container: b }) => {
            match b.outlet {
                CuboidOutlet::Slot => slot(b.outlet_width, b.depth),
                // A square orifice as the slot form over its side.
                CuboidOutlet::Square => slot(b.outlet_width, b.outlet_width),
            }
        }
        Geometry::Mesh(m) => match m.outlet {
            MeshOutlet::Disc { radius, .. } => orifice(2.0 * radius),
            MeshOutlet::Rectangle { size, .. } => slot(size[0].min(size[1]), size[0].max(size[1])),
        },
        Geometry::Heap(_) => {
            return Err(
                "the heap test has no orifice: its lift and rest are counted to \
                        protocol.time_limit"
                    .to_string(),
            )
        }
    };
    // Relative 1e-9 below the threshold: a width given as 6 d (18 mm for 3 mm spheres) reads
    // a rounding under 6 d and still counts as 6 d.
    if width < MIN_ORIFICE_DIAMETERS * d * (1.0 - 1e-9) {
        return Err(format!(
            "the orifice, {:.1} mm, is under {MIN_ORIFICE_DIAMETERS} particle diameters \
             ({:.1} mm) and may clog: the discharge is counted to protocol.time_limit",
            width * 1e3,
            MIN_ORIFICE_DIAMETERS * d * 1e3
        ));
    }
    if !(rate > 0.0 && rate.is_finite()) {
        return Err(format!(
            "the Beverloo law gives no flow through the orifice of {:.1} mm: the discharge \
             is counted to protocol.time_limit",
            width * 1e3
        ));
    }
    Ok((law, rate))
}

/// The likely cost of a run of `case` with `particles` spheres whose bounds are `bound`
/// (simulated time by part [s]), at `ns_per_particle_step` [ns]; `filled` says whether the
/// settling follows a pour (else it starts from a packing at rest).
pub(crate) fn likely_cost(
    case: &Case,
    particles: usize,
    bound: PhaseTimes,
    filled: bool,
    ns_per_particle_step: f64,
) -> LikelyCost {
    let n = particles as f64;
    let steps = |t: f64| super::steps_of(case.time_step, t);
    // The settling: after a pour, until the last batch has landed; from a packing at rest,
    // the first check. A wall slip adds its own time and a second, short settling.
    let once = if filled {
        likely_settle_once(case)
    } else {
        MIN_SETTLE_AFTER_FILL + CHECK_INTERVAL
    };
    let slip = super::steps::slip_time(case);
    let settle_model = once
        + if slip > 0.0 {
            slip + MIN_SETTLE_AFTER_FILL + CHECK_INTERVAL
        } else {
            0.0
        };
    let settle = if bound.settle > 0.0 {
        settle_model.min(bound.settle)
    } else {
        0.0
    };
    // The discharge: the mass over the rate, at the mean count while it leaves.
    let mass = case.particles.total_mass() * n / case.particles.count.max(1) as f64;
    let p = &case.protocol;
    let fraction = if p.stop_fraction < 1.0 {
        p.stop_fraction
            .max(case.measure.steady_end_fraction)
            .min(1.0)
    } else {
        1.0
    };
    let model = discharge_rate(case, case.particles.density());
    let (discharge, discharge_ps, model) = match model {
        Ok((law, rate)) => {
            let flowing = fraction * mass / rate;
            // A run that waits for the whole mass ends when the container is empty, or
            // `protocol.clog_timeout` after the last crossing when stagnant zones stay.
            let tail = if fraction >= 1.0 { p.clog_timeout } else { 0.0 };
            let total = (flowing + tail + CHECK_INTERVAL).min(bound.discharge);
            let flow = flowing.min(total);
            // What has left by the end of the flow, as a fraction of the count.
            let out = if flowing > 0.0 {
                fraction * flow / flowing
            } else {
                0.0
            };
            let ps = n * (1.0 - 0.5 * out) * steps(flow) + n * (1.0 - out) * steps(total - flow);
            let model = DischargeModel {
                law: Some(law),
                rate,
                mass,
                fraction,
                flowing,
                bounded: None,
            };
            (total, ps, model)
        }
        Err(why) => (
            bound.discharge,
            n * steps(bound.discharge),
            DischargeModel {
                law: None,
                rate: f64::NAN,
                mass,
                fraction,
                flowing: f64::NAN,
                bounded: Some(why),
            },
        ),
    };
    let simulated = PhaseTimes {
        fill: bound.fill,
        settle,
        discharge,
    };
    let particle_steps = PhaseTimes {
        fill: 0.5 * n * steps(bound.fill),
        settle: n * steps(settle),
        discharge: discharge_ps,
    };
    let seconds = |ps: f64| ps * ns_per_particle_step * 1e-9;
    LikelyCost {
        simulated,
        wall_time: PhaseTimes {
            fill: seconds(particle_steps.fill),
            settle: seconds(particle_steps.settle),
            discharge: seconds(particle_steps.discharge),
        },
        particle_steps,
        discharge: model,
    }
}

//! H1 — head-on impacts of unequal and of dissimilar spheres against Hertz theory
//! (Hertz 1882; Johnson 1985, *Contact Mechanics*, §4.2 and §11.4; docs/physics.md §1, §2, §9).
//!
//! Set-up: no gravity, no friction, the two centres on the x axis.
//! - Unequal spheres, one material: a Table-1 sphere (R1 = 1.5 mm) at 1 m/s onto a Table-1
//!   sphere three times as large (R2 = 4.5 mm, 27 times the mass) at rest; e = 1, then
//!   Table 1's e = 0.2. Radii 2.5 or more apart are paired by the engine's search by size
//!   class, so this pair is found by it.
//! - Dissimilar spheres: glass (E = 4.8e10 Pa, ν = 0.20, ρ = 2800 kg/m³, R1 = 5 mm) at +3 m/s
//!   against limestone (E = 2.0e10 Pa, ν = 0.25, ρ = 2500 kg/m³, R2 = 10 mm) at −1 m/s, the
//!   materials of Chung & Ooi's test 1. The pair comes from a `MaterialTable` that lists only
//!   the two self-pairs, so its restitution is mixed (docs/physics.md §1.2): e = 1 from two
//!   elastic self-pairs, then √(0.9 × 0.4) = 0.6.
//!
//! Expected (Hertz theory with R* = R1R2/(R1+R2), m* = m1m2/(m1+m2) and
//! 1/E* = (1−ν1²)/E1 + (1−ν2²)/E2, written out here rather than taken from the engine; v the
//! relative speed): δ_max = (15 m* v²/(16 E*√R*))^{2/5}, F_max = (4/3) E*√R* δ_max^{3/2},
//! t_c = 2.9433 δ_max/v = 2.8683 (m*²/(R* E*² v))^{1/5}, and an elastic rebound at the
//! approach speed (docs/physics.md §9 lists the values). With damping, the rebound is the
//! configured e: the 2√(5/6)β dashpot (docs/physics.md §2.1, the law of EDEM and LIGGGHTS,
//! whose δ^{1/4} damping goes back to Tsuji et al., Powder Technol. 71 (1992) 239) gives e
//! exactly for the Hertz equation of motion (§2.3). The total momentum m1v1 + m2v2 is conserved: the pair's forces are
//! equal and opposite.
//!
//! Tolerances, from the time step Δt = t_c/N (N steps per elastic contact: 1000 fast, 2000 full):
//! - velocity Verlet on a spring of frequency ω errs by (ωΔt)²/8 in amplitude and (ωΔt)²/24
//!   in period (the harmonic oscillator's exact discrete solution). The stiffest point of a
//!   Hertz contact is its peak, S_n = (3/2) F_max/δ_max = (15/8) m* v²/δ_max², so
//!   ω_max t_c = 2.9433 √(15/8) = 4.030 and (ω_max Δt)² = 16.24/N²;
//! - δ_max: that amplitude error, 2.03/N², plus the peak falling between two steps, at most
//!   ½|δ̈|(Δt/2)² = (5/32)(v Δt)²/δ_max, which is 1.35/N² relative: 3.4/N² in all; F_max,
//!   going as δ^{3/2}: 1.5 times that, 5.1/N²; t_c: the period error, 0.68/N² (the ends,
//!   interpolated where δ crosses zero and δ is linear in t to O(Δt^{5/2}), add less);
//! - the elastic rebound: 2.03/N², the amplitude error, bounds the energy the scheme can lose
//!   or gain in contact (it returns it at separation, where the force and its slope vanish,
//!   so the measured gap is far smaller);
//! - the damped rebound: the dashpot sees the half-step velocity (§2.3, §6.2), a first-order
//!   bias. The Appendix-B integrator gives N |e_N − e| ≤ 0.21 for e = 0.2 and ≤ 0.06 for
//!   e = 0.6 at every N from 250 to 64000 (it does not settle to a constant, because the
//!   dashpot goes as δ^{1/4} at the contact's ends); 0.3/N bounds both;
//! - momentum: only rounding. Each of the steps in contact kicks each sphere twice, each kick
//!   rounding the sum v + Δv (ε/2 of |v|) and Δv = F Δt/(2m) (three roundings); the engine's
//!   and this file's masses differ by up to ten roundings. With ε the machine epsilon that is
//!   at most ε [(steps + 2) Σ m|v| + 8 J], J = (1 + e) m* v the impulse.

use dem::contact::normal::{hertz, max_overlap};
use dem::{
    ContactLaws, DVec3, DemError, Interaction, Material, MaterialEntry, MaterialTable, PairEntry,
};

use crate::impact::{sphere_mass, Impact, ImpactRecord, Partner, Target};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "H1";

/// Johnson's (1985, §11.4) contact-time factor: t_c = T δ_max / v with
/// T = 2 ∫₀¹ dx/√(1 − x^{5/2}) = (4/5) Γ(2/5) Γ(1/2) / Γ(9/10) [-]. Four digits (2.943) would
/// already be off by 1e-4, far more than the duration's tolerance.
pub const CONTACT_TIME_FACTOR: f64 = 2.943_275_184_324_705;

/// (ω_max t_c)² of a Hertz contact: the peak stiffness (15/8) m* v²/δ_max² over m*, times
/// t_c² = (T δ_max / v)² [-].
const PEAK_STIFFNESS: f64 = 15.0 / 8.0 * CONTACT_TIME_FACTOR * CONTACT_TIME_FACTOR;

/// The peak falling between steps: (5/32)(v Δt/δ_max)² = (5/32) T²/N², as a multiple of 1/N² [-].
const PEAK_SAMPLING: f64 = 5.0 / 32.0 * CONTACT_TIME_FACTOR * CONTACT_TIME_FACTOR;

/// Largest N |e_N − e| of the half-step dashpot for e = 0.2 and 0.6 (module documentation) [-].
const DASHPOT_BIAS: f64 = 0.3;

/// Glass of Chung & Ooi's test 1.
const GLASS: Material = Material {
    density: 2800.0,
    youngs_modulus: 4.8e10,
    poisson_ratio: 0.20,
};

/// Limestone of Chung & Ooi's test 1.
const LIMESTONE: Material = Material {
    density: 2500.0,
    youngs_modulus: 2.0e10,
    poisson_ratio: 0.25,
};

/// Hertz's closed forms of a head-on impact of two spheres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzImpact {
    /// Largest overlap δ_max [m].
    pub overlap: f64,
    /// Largest normal force F_max [N].
    pub force: f64,
    /// Contact duration t_c [s].
    pub duration: f64,
}

/// The closed forms for spheres (material, radius [m]) `a` and `b` meeting at relative
/// speed `speed` [m/s], with R*, m* and E* from both spheres.
pub fn hertz_impact(a: (&Material, f64), b: (&Material, f64), speed: f64) -> HertzImpact {
    let compliance = |m: &Material| (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus;
    let e_star = 1.0 / (compliance(a.0) + compliance(b.0));
    let r_star = a.1 * b.1 / (a.1 + b.1);
    let (ma, mb) = (sphere_mass(a.0, a.1), sphere_mass(b.0, b.1));
    let m_star = ma * mb / (ma + mb);
    let overlap = max_overlap(e_star, r_star, m_star, speed);
    HertzImpact {
        overlap,
        force: hertz(e_star, r_star, overlap).force,
        duration: CONTACT_TIME_FACTOR * overlap / speed,
    }
}

/// One head-on pair: the first sphere and its velocity, the second, and the pair's
/// interaction with e = 1 and with damping.
struct Pair {
    name: &'static str,
    material: Material,
    radius: f64,
    velocity: DVec3,
    other: Partner,
    elastic: Interaction,
    damped: Interaction,
}

impl Pair {
    fn impact(&self, interaction: Interaction, steps_per_contact: f64) -> Impact {
        Impact {
            material: self.material,
            radius: self.radius,
            interaction,
            laws: ContactLaws::default(),
            target: Target::Sphere(self.other),
            velocity: self.velocity,
            angular_velocity: DVec3::ZERO,
            steps_per_contact,
        }
    }

    /// Masses of the two spheres [kg].
    fn masses(&self) -> (f64, f64) {
        (
            sphere_mass(&self.material, self.radius),
            sphere_mass(&self.other.material, self.other.radius),
        )
    }

    /// Total momentum along x before the impact and after it [kg m/s], and its round-off
    /// bound (module documentation) [kg m/s].
    fn momentum(&self, record: &ImpactRecord, restitution: f64) -> (f64, f64, f64) {
        let (m1, m2) = self.masses();
        let before = m1 * self.velocity.x + m2 * self.other.velocity.x;
        let after = m1 * record.velocity.x + m2 * record.partner_velocity.x;
        // Each sphere's speed moves monotonically from its value before to its value after.
        let moving = m1 * self.velocity.x.abs().max(record.velocity.x.abs())
            + m2 * self
                .other
                .velocity
                .x
                .abs()
                .max(record.partner_velocity.x.abs());
        let impulse = (1.0 + restitution) * m1 * m2 / (m1 + m2) * record.approach_speed;
        let bound =
            f64::EPSILON * ((record.steps_in_contact as f64 + 2.0) * moving + 8.0 * impulse);
        (before, after, bound)
    }
}

/// The two pairs of the module documentation.
fn pairs() -> Result<[Pair; 2], VerifyError> {
    let frictionless = |restitution| Interaction {
        friction: 0.0,
        rolling_friction: 0.0,
        restitution,
        cohesion: dem::Cohesion::None,
    };
    let table1 = Material::fan2023();
    let unequal = Pair {
        name: "Table-1 spheres 1:3",
        material: table1,
        radius: 1.5e-3,
        velocity: DVec3::new(1.0, 0.0, 0.0),
        other: Partner {
            material: table1,
            radius: 4.5e-3,
            velocity: DVec3::ZERO,
        },
        elastic: frictionless(1.0),
        damped: frictionless(Interaction::fan2023().restitution),
    };
    // A table of the two materials with only their self-pairs: the pair is mixed.
    let mixed = |e_glass: f64, e_limestone: f64| -> Result<Interaction, VerifyError> {
        let table = MaterialTable::new()
            .with_material(
                "glass",
                MaterialEntry::from_youngs_modulus(4.8e10, 0.20, 2800.0),
            )
            .with_material(
                "limestone",
                MaterialEntry::from_youngs_modulus(2.0e10, 0.25, 2500.0),
            )
            .with_pair(PairEntry::new("glass", "glass", frictionless(e_glass)))
            .with_pair(PairEntry::new(
                "limestone",
                "limestone",
                frictionless(e_limestone),
            ));
        let interaction = table.interaction("glass", "limestone");
        Ok(interaction.map_err(DemError::from)?)
    };
    let dissimilar = Pair {
        name: "glass 5 mm on limestone 10 mm",
        material: GLASS,
        radius: 5.0e-3,
        velocity: DVec3::new(3.0, 0.0, 0.0),
        other: Partner {
            material: LIMESTONE,
            radius: 10.0e-3,
            velocity: DVec3::new(-1.0, 0.0, 0.0),
        },
        elastic: mixed(1.0, 1.0)?,
        damped: mixed(0.9, 0.4)?,
    };
    Ok([unequal, dissimilar])
}

/// Restitution of the damped glass–limestone pair by the mixing rule e = √(e_aa e_bb)
/// (docs/physics.md §1.2) from the self-pairs 0.9 and 0.4 [-].
const MIXED_RESTITUTION: f64 = 0.6;

/// Runs H1.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let n = resolution.steps_per_contact();
    let verlet = PEAK_STIFFNESS / 8.0 / (n * n);
    let overlap_tolerance = verlet + PEAK_SAMPLING / (n * n);
    let mut rows = Vec::new();
    for (pair, damped_e) in pairs()?.iter().zip([0.2, MIXED_RESTITUTION]) {
        let name = pair.name;
        let r = pair.impact(pair.elastic, n).run()?;
        let hertz = hertz_impact(
            (&pair.material, pair.radius),
            (&pair.other.material, pair.other.radius),
            r.approach_speed,
        );
        rows.push(Row::relative(
            TEST,
            format!("{name}, e = 1: peak overlap [m]"),
            hertz.overlap,
            r.peak_overlap,
            overlap_tolerance,
        ));
        rows.push(Row::relative(
            TEST,
            format!("{name}, e = 1: peak normal force [N]"),
            hertz.force,
            r.peak_force,
            1.5 * overlap_tolerance,
        ));
        rows.push(Row::relative(
            TEST,
            format!("{name}, e = 1: contact duration [s]"),
            hertz.duration,
            r.duration,
            PEAK_STIFFNESS / 24.0 / (n * n),
        ));
        rows.push(Row::absolute(
            TEST,
            format!("{name}, e = 1: restitution [-]"),
            1.0,
            r.restitution(),
            verlet,
        ));
        let (before, after, bound) = pair.momentum(&r, 1.0);
        rows.push(Row::absolute(
            TEST,
            format!("{name}, e = 1: total momentum after [kg m/s]"),
            before,
            after,
            bound,
        ));
        let r = pair.impact(pair.damped, n).run()?;
        rows.push(Row::absolute(
            TEST,
            format!("{name}, e = {damped_e}: restitution [-]"),
            damped_e,
            r.restitution(),
            DASHPOT_BIAS / n,
        ));
        let (before, after, bound) = pair.momentum(&r, damped_e);
        rows.push(Row::absolute(
            TEST,
            format!("{name}, e = {damped_e}: total momentum after [kg m/s]"),
            before,
            after,
            bound,
        ));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contact_time_factor_is_the_integral() {
        // T = 2 ∫₀¹ dx/√(1 − x^{5/2}); with x = 1 − u² the integrand 4u/√(1 − (1 − u²)^{5/2})
        // is smooth on [0, 1] (it tends to 4/√(5/2) at u = 0), and 1 − (1 − u²)^{5/2} is
        // taken as −expm1(2.5 ln(1 − u²)) to keep its digits at small u. Simpson's rule on
        // 2000 panels of width h errs by h⁴/2880 max|f⁗| ≈ 2e-17 max|f⁗|; 1e-12 leaves room
        // for f⁗ and the summed rounding of 2000 terms (2000 ε ≈ 5e-13 relative at worst).
        let f = |u: f64| {
            if u == 0.0 {
                4.0 / 2.5f64.sqrt()
            } else {
                4.0 * u / (-(2.5 * (-u * u).ln_1p()).exp_m1()).sqrt()
            }
        };
        // Simpson's rule panel by panel: (f(a) + 4 f(mid) + f(b)) h/6.
        let panels = 2000;
        let h = 1.0 / panels as f64;
        let integral: f64 = (0..panels)
            .map(|k| {
                let (a, b) = (k as f64 * h, (k + 1) as f64 * h);
                (f(a) + 4.0 * f(0.5 * (a + b)) + f(b)) * h / 6.0
            })
            .sum();
        assert!(
            (integral - CONTACT_TIME_FACTOR).abs() <= 1e-12 * CONTACT_TIME_FACTOR,
            "{integral}"
        );
        // Johnson's other form: t_c = 2.868 (m*²/(R* E*² v))^{1/5}, T (15/16)^{2/5} = 2.8683.
        let other = CONTACT_TIME_FACTOR * (15.0f64 / 16.0).powf(0.4);
        assert!((other - 2.8683).abs() < 5e-5, "{other}");
    }

    #[test]
    fn closed_forms_reproduce_the_identical_sphere_tables() {
        // The CO1 and P1 values of docs/physics.md §9, computed independently, to their four
        // printed digits (half a unit of the last digit, relative: ≤ 5e-4 of the value).
        let cases = [
            (&GLASS, 0.010, 20.0, (274.1e-6, 10.70e3, 40.34e-6)),
            (&LIMESTONE, 0.010, 20.0, (368.3e-6, 7.108e3, 54.20e-6)),
            (
                &Material::fan2023(),
                1.5e-3,
                1.0,
                (29.02e-6, 0.7612, 85.41e-6),
            ),
        ];
        for (m, r, v, (d, f, t)) in cases {
            let h = hertz_impact((m, r), (m, r), v);
            for (got, want) in [(h.overlap, d), (h.force, f), (h.duration, t)] {
                assert!((got / want - 1.0).abs() <= 5e-4, "{got} against {want}");
            }
        }
    }

    #[test]
    fn closed_forms_reproduce_the_h1_table() {
        // docs/physics.md §9 H1, printed to four digits: as above, ≤ 5e-4 of the value.
        let t1 = Material::fan2023();
        let cases = [
            (
                hertz_impact((&t1, 1.5e-3), (&t1, 4.5e-3), 1.0),
                (34.80e-6, 1.224, 102.4e-6),
            ),
            (
                hertz_impact((&GLASS, 5.0e-3), (&LIMESTONE, 10.0e-3), 4.0),
                (54.91e-6, 468.4, 40.41e-6),
            ),
        ];
        for (h, (d, f, t)) in cases {
            for (got, want) in [(h.overlap, d), (h.force, f), (h.duration, t)] {
                assert!((got / want - 1.0).abs() <= 5e-4, "{got} against {want}");
            }
        }
    }

    #[test]
    fn the_mixed_pair_has_the_geometric_mean_restitution() {
        // The damped glass–limestone row expects √(0.9 × 0.4) = 0.6; the table must give it
        // (to the last bits of a product and a square root).
        let pairs = pairs().ok();
        let e = pairs.map_or(f64::NAN, |p| p[1].damped.restitution);
        assert!((e - MIXED_RESTITUTION).abs() <= 4.0 * f64::EPSILON, "{e}");
    }

    #[test]
    fn the_peak_force_row_fails_when_the_second_sphere_takes_the_first_ones_material() {
        // The expectation is built from both materials. Glass on glass has a stiffer E* and a
        // lighter partner than glass on limestone: the peak force must then miss the
        // glass–limestone closed form by far more than the row's tolerance at N = 1000.
        let dissimilar = pairs().ok().map(|[_, p]| p);
        let off = dissimilar.map_or(f64::NAN, |p| {
            let wrong = Pair {
                other: Partner {
                    material: GLASS,
                    ..p.other
                },
                ..p
            };
            let force = wrong.impact(wrong.elastic, 1000.0).run();
            let expected = hertz_impact((&GLASS, 5.0e-3), (&LIMESTONE, 10.0e-3), 4.0).force;
            force.map_or(f64::NAN, |r| (r.peak_force / expected - 1.0).abs())
        });
        let tolerance = 1.5 * (PEAK_STIFFNESS / 8.0 + PEAK_SAMPLING) / 1.0e6;
        assert!(off > 100.0 * tolerance, "{off}");
    }
}

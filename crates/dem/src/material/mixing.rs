//! Mixing rules for the interaction of two different materials when a pair table does not
//! list it: each coefficient is mixed from the two materials' self-interactions
//! (docs/physics.md §1.2).
//!
//! - Restitution: the geometric mean e_ab = √(e_aa e_bb). The dashpot is built from ln e
//!   (β = ln e / √(ln² e + π²), §2.1), and ln e_ab is the mean of ln e_aa and ln e_bb, so the
//!   mixed damping lies between the two; e_ab stays in (0, 1] and is 1 only when both
//!   materials are elastic.
//! - Sliding and rolling friction: the harmonic mean 2μ_aa μ_bb / (μ_aa + μ_bb), the rule of
//!   MercuryDPM's default mixed species (`BaseSpecies::average`). It lies between the two,
//!   nearer the smaller, and is 0 when either is 0: a frictionless surface stays frictionless
//!   against every material.
//! - Cohesion: JKR works of adhesion and simplified-JKR energy densities mix by the
//!   geometric mean, the combining rule of surface energies w_ab = √(w_aa w_bb) (Israelachvili
//!   2011, Intermolecular and Surface Forces §17.3), which is 0 when either surface is dry.
//!   Two different laws, or liquid bridges that differ, have no rule: such a pair must be
//!   listed.

use super::Interaction;
use crate::contact::Cohesion;

/// Restitution of an unlisted pair from the two self-pairs' restitutions [-]:
/// e_ab = √(e_aa e_bb).
pub fn mixed_restitution(e_aa: f64, e_bb: f64) -> f64 {
    (e_aa * e_bb).sqrt()
}

/// Sliding or rolling friction of an unlisted pair from the two self-pairs' coefficients [-]:
/// the harmonic mean 2μ_aa μ_bb / (μ_aa + μ_bb), and 0 when either is 0.
pub fn mixed_friction(mu_aa: f64, mu_bb: f64) -> f64 {
    if mu_aa == 0.0 || mu_bb == 0.0 {
        0.0
    } else {
        2.0 * mu_aa * mu_bb / (mu_aa + mu_bb)
    }
}

/// Cohesion of an unlisted pair from the two self-pairs' cohesions, or `None` where no rule
/// mixes them (two different laws, unequal liquid bridges, a bridge and a dry surface).
pub fn mixed_cohesion(aa: &Cohesion, bb: &Cohesion) -> Option<Cohesion> {
    use Cohesion::*;
    match (*aa, *bb) {
        (None, None) => Some(None),
        (
            Jkr {
                work_of_adhesion: a,
            },
            Jkr {
                work_of_adhesion: b,
            },
        ) => Some(Jkr {
            work_of_adhesion: (a * b).sqrt(),
        }),
        (SimplifiedJkr { energy_density: a }, SimplifiedJkr { energy_density: b }) => {
            Some(SimplifiedJkr {
                energy_density: (a * b).sqrt(),
            })
        }
        (None, Jkr { .. } | SimplifiedJkr { .. }) | (Jkr { .. } | SimplifiedJkr { .. }, None) => {
            Some(None)
        }
        (a @ LiquidBridge { .. }, b @ LiquidBridge { .. }) if a == b => Some(a),
        _ => Option::None,
    }
}

/// The interaction of two materials mixed from their self-interactions `aa` and `bb`, or
/// `None` where their cohesions do not mix ([`mixed_cohesion`]).
pub fn mixed_interaction(aa: &Interaction, bb: &Interaction) -> Option<Interaction> {
    Some(Interaction {
        friction: mixed_friction(aa.friction, bb.friction),
        rolling_friction: mixed_friction(aa.rolling_friction, bb.rolling_friction),
        restitution: mixed_restitution(aa.restitution, bb.restitution),
        cohesion: mixed_cohesion(&aa.cohesion, &bb.cohesion)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    // The expected values are exact decimals or square roots computed by hand; 1e-15 is
    // room for the last bit of a product, a sum and a square root.
    const ROUND_OFF: f64 = 1e-15;

    #[test]
    fn restitution_is_the_geometric_mean_of_the_self_pairs() {
        // √(0.5 × 0.2) = √0.1 = 0.316227766…; √(0.4 × 0.9) = √0.36 = 0.6 exactly.
        assert_relative_eq!(
            mixed_restitution(0.5, 0.2),
            0.316_227_766_016_837_94,
            max_relative = ROUND_OFF
        );
        assert_relative_eq!(mixed_restitution(0.4, 0.9), 0.6, max_relative = ROUND_OFF);
        // Equal self-pairs mix to themselves; two elastic materials stay elastic.
        assert_eq!(mixed_restitution(0.3, 0.3), 0.3);
        assert_eq!(mixed_restitution(1.0, 1.0), 1.0);
    }

    #[test]
    fn friction_is_the_harmonic_mean_and_zero_when_either_is_zero() {
        // 2 × 0.3 × 0.6 / 0.9 = 0.4; 2 × 0.2 × 0.5 / 0.7 = 0.2/0.7 = 0.285714…
        assert_relative_eq!(mixed_friction(0.3, 0.6), 0.4, max_relative = ROUND_OFF);
        assert_relative_eq!(
            mixed_friction(0.2, 0.5),
            0.2 / 0.7,
            max_relative = ROUND_OFF
        );
        assert_eq!(mixed_friction(0.0, 0.5), 0.0);
        assert_eq!(mixed_friction(0.5, 0.0), 0.0);
        assert_eq!(mixed_friction(0.0, 0.0), 0.0);
        assert_eq!(mixed_friction(0.25, 0.25), 0.25);
    }

    #[test]
    fn an_interaction_mixes_each_coefficient_by_its_rule() {
        let aa = Interaction {
            friction: 0.3,
            rolling_friction: 0.02,
            restitution: 0.5,
            cohesion: crate::contact::Cohesion::None,
        };
        let bb = Interaction {
            friction: 0.6,
            rolling_friction: 0.0,
            restitution: 0.2,
            cohesion: crate::contact::Cohesion::None,
        };
        let ab = mixed_interaction(&aa, &bb).unwrap();
        assert_relative_eq!(ab.friction, 0.4, max_relative = ROUND_OFF);
        assert_eq!(ab.rolling_friction, 0.0);
        assert_relative_eq!(ab.restitution, 0.1f64.sqrt(), max_relative = ROUND_OFF);
        // Symmetric: the order of the two materials does not matter.
        assert_eq!(mixed_interaction(&bb, &aa), Some(ab));
    }

    #[test]
    fn cohesion_mixes_by_the_geometric_mean_or_not_at_all() {
        // √(0.04 × 0.09) = 0.06 and √(1e5 × 4e5) = 2e5: exact up to the square root.
        let jkr = |w| Cohesion::Jkr {
            work_of_adhesion: w,
        };
        assert_eq!(mixed_cohesion(&jkr(0.04), &jkr(0.09)), Some(jkr(0.06)));
        let sjkr = |k| Cohesion::SimplifiedJkr { energy_density: k };
        assert_eq!(mixed_cohesion(&sjkr(1e5), &sjkr(4e5)), Some(sjkr(2e5)));
        // A dry surface makes a dry pair; different laws do not mix.
        assert_eq!(
            mixed_cohesion(&jkr(0.04), &Cohesion::None),
            Some(Cohesion::None)
        );
        assert_eq!(mixed_cohesion(&jkr(0.04), &sjkr(1e5)), None);
        let bridge = |v| Cohesion::LiquidBridge {
            volume: v,
            surface_tension: 0.072,
            contact_angle: 0.0,
        };
        assert_eq!(
            mixed_cohesion(&bridge(1e-12), &bridge(1e-12)),
            Some(bridge(1e-12))
        );
        assert_eq!(mixed_cohesion(&bridge(1e-12), &bridge(2e-12)), None);
        assert_eq!(mixed_cohesion(&bridge(1e-12), &Cohesion::None), None);
    }
}

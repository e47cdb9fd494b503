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

use super::Interaction;

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

/// The interaction of two materials mixed from their self-interactions `aa` and `bb`.
pub fn mixed_interaction(aa: &Interaction, bb: &Interaction) -> Interaction {
    Interaction {
        friction: mixed_friction(aa.friction, bb.friction),
        rolling_friction: mixed_friction(aa.rolling_friction, bb.rolling_friction),
        restitution: mixed_restitution(aa.restitution, bb.restitution),
    }
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
        };
        let bb = Interaction {
            friction: 0.6,
            rolling_friction: 0.0,
            restitution: 0.2,
        };
        let ab = mixed_interaction(&aa, &bb);
        assert_relative_eq!(ab.friction, 0.4, max_relative = ROUND_OFF);
        assert_eq!(ab.rolling_friction, 0.0);
        assert_relative_eq!(ab.restitution, 0.1f64.sqrt(), max_relative = ROUND_OFF);
        // Symmetric: the order of the two materials does not matter.
        assert_eq!(mixed_interaction(&bb, &aa), ab);
    }
}

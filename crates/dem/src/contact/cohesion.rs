//! The cohesion of a material pair (docs/physics.md §2.4–2.6): none, JKR adhesion, the
//! simplified JKR of LIGGGHTS, or a pendular liquid bridge. Each law is a pure function in
//! its own file ([`super::jkr`], [`super::sjkr`], [`super::liquid_bridge`]); this file holds
//! the choice, its parameters' allowed ranges and how far beyond contact it reaches.

use serde::{Deserialize, Serialize};

use super::normal::hertz;
use super::{jkr, liquid_bridge, sjkr, ContactGeometry};
use crate::material::PairCoefficients;

/// How two surfaces stick.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum Cohesion {
    /// Dry, cohesionless contact.
    #[default]
    None,
    /// Johnson–Kendall–Roberts adhesion ([`super::jkr`]): the contact forms on touching,
    /// holds in tension and breaks at δ_c < 0.
    Jkr {
        /// Work of adhesion w = Δγ [J/m²], > 0 (2γ for like surfaces of surface energy γ).
        work_of_adhesion: f64,
    },
    /// Simplified JKR ([`super::sjkr`]): an attraction k_c A while the surfaces overlap.
    SimplifiedJkr {
        /// Cohesion energy density k_c [J/m³], > 0.
        energy_density: f64,
    },
    /// A pendular liquid bridge ([`super::liquid_bridge`]), formed on touching and broken at
    /// the rupture distance.
    LiquidBridge {
        /// Volume of liquid in the bridge V [m³], > 0.
        volume: f64,
        /// Surface tension of the liquid γ [N/m], > 0.
        surface_tension: f64,
        /// Contact angle θ of the liquid on the solid [rad], in [0, π/2].
        contact_angle: f64,
    },
}

impl Cohesion {
    /// True for a dry contact.
    #[inline(always)]
    pub fn is_none(&self) -> bool {
        matches!(self, Cohesion::None)
    }

    /// True when the law acts beyond contact, so that a pair must remember whether it is
    /// bonded (JKR and liquid bridges).
    #[inline(always)]
    pub fn bonds(&self) -> bool {
        matches!(self, Cohesion::Jkr { .. } | Cohesion::LiquidBridge { .. })
    }

    /// The largest surface separation [m] at which a bonded pair of effective modulus
    /// `e_star` [Pa] and effective radius up to `r_eff` [m] still interacts: |δ_c| for JKR
    /// (which grows with R*), S_c for a bridge, 0 for the others.
    pub fn reach(&self, e_star: f64, r_eff: f64) -> f64 {
        match *self {
            Cohesion::None | Cohesion::SimplifiedJkr { .. } => 0.0,
            Cohesion::Jkr { work_of_adhesion } => {
                -jkr::breaking_overlap(e_star, r_eff, work_of_adhesion)
            }
            Cohesion::LiquidBridge {
                volume,
                contact_angle,
                ..
            } => liquid_bridge::rupture_distance(volume, contact_angle),
        }
    }

    /// The law for parcels of `factor` κ ≥ 1 times the grains' size (coarse-grained DEM,
    /// docs/physics.md §2.8), scaled so that a parcel contact's cohesive force is κ² times the
    /// grains' at the same relative overlap, as its Hertz force is with the grains' elastic
    /// constants: the stress a bulk of parcels carries is then the grains' (Feng & Owen 2014,
    /// Comp. Part. Mech. 1, 159, exact scaling; Thakur, Ooi & Ahmadian 2016, Powder Technol.
    /// 293, 130, the adhesive force scaling with the square of the particle size).
    ///
    /// - JKR: F = 4E*a³/(3R*) − √(8π w E* a³) scales as κ² with a and R* as κ when w → κw.
    /// - Simplified JKR: k_c A scales as κ² with A, so k_c (a stress) is kept.
    /// - Bridges: Willett's F = 2πRγ cos θ f(Ŝ), Ŝ = (S/2)√(R/V), scales as κ² when γ → κγ
    ///   and V → κ³V, which keeps Ŝ and V/R³ and makes the rupture distance κ S_c.
    pub fn coarse_grained(&self, factor: f64) -> Cohesion {
        match *self {
            Cohesion::None => Cohesion::None,
            Cohesion::Jkr { work_of_adhesion } => Cohesion::Jkr {
                work_of_adhesion: work_of_adhesion * factor,
            },
            Cohesion::SimplifiedJkr { energy_density } => {
                Cohesion::SimplifiedJkr { energy_density }
            }
            Cohesion::LiquidBridge {
                volume,
                surface_tension,
                contact_angle,
            } => Cohesion::LiquidBridge {
                volume: volume * factor * factor * factor,
                surface_tension: surface_tension * factor,
                contact_angle,
            },
        }
    }

    /// Each parameter's key, value and allowed range where it is out of range, for the
    /// table checks: (key, value, allowed).
    pub fn problems(&self) -> Vec<(&'static str, f64, &'static str)> {
        let mut out = Vec::new();
        let mut need = |key, value: f64, ok: bool, allowed| {
            if !(value.is_finite() && ok) {
                out.push((key, value, allowed));
            }
        };
        match *self {
            Cohesion::None => {}
            Cohesion::Jkr { work_of_adhesion } => need(
                "work_of_adhesion",
                work_of_adhesion,
                work_of_adhesion > 0.0,
                "> 0 J/m²",
            ),
            Cohesion::SimplifiedJkr { energy_density } => need(
                "energy_density",
                energy_density,
                energy_density > 0.0,
                "> 0 J/m³",
            ),
            Cohesion::LiquidBridge {
                volume,
                surface_tension,
                contact_angle,
            } => {
                need("volume", volume, volume > 0.0, "> 0 m³");
                need(
                    "surface_tension",
                    surface_tension,
                    surface_tension > 0.0,
                    "> 0 N/m",
                );
                need(
                    "contact_angle",
                    contact_angle,
                    (0.0..=std::f64::consts::FRAC_PI_2).contains(&contact_angle),
                    "[0, π/2] rad",
                );
            }
        }
        out
    }
}

/// The normal stage of a contact (docs/physics.md §2): what the dashpot, the tangential and
/// the rolling laws read, for a dry or a cohesive contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalStage {
    /// Elastic normal force [N], positive when repulsive (Hertz, or the JKR curve).
    pub elastic: f64,
    /// Stiffness S_n [N/m] the dashpot is built from.
    pub stiffness: f64,
    /// Contact radius a [m] of the tangential stiffness.
    pub contact_radius: f64,
    /// Normal load [N] that caps friction and rolling resistance: the elastic force, and for
    /// JKR F + 2F_c (Thornton & Yin 1991, Powder Technol. 65, 153).
    pub load: f64,
    /// The overlap [m] of a Hertz contact of that radius, a²/R*, for the laws that read an
    /// overlap (Mindlin–Deresiewicz's slip distance, EPSD's stiffness); the overlap itself
    /// when dry.
    pub overlap: f64,
    /// Cohesive attraction [N] subtracted from the normal force after the dashpot (the
    /// simplified JKR and a bridge over touching surfaces).
    pub pull: f64,
    /// Least normal force [N] that the optional clamp allows: 0, or for JKR the elastic force
    /// where it is tensile, so that the clamp limits the dashpot only.
    pub floor: f64,
}

/// What the cohesion makes of a candidate contact at its current overlap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NormalOutcome {
    /// The surfaces bear on each other (or, for JKR, are bonded): the full pipeline runs.
    Contact(NormalStage),
    /// Only a liquid bridge acts across a gap: a pure attraction [N] along the normal.
    BridgeOnly(f64),
    /// The bond has broken, or there never was one: no force, no memory.
    Apart,
}

/// The normal stage of a contact of geometry `g` with coefficients `c`. A dry contact must
/// overlap; a cohesive one may be apart, and `bonded` tells whether it bonded earlier.
#[inline(always)]
pub fn normal_stage(g: &ContactGeometry, c: &PairCoefficients, bonded: bool) -> NormalOutcome {
    let touching = g.overlap > 0.0;
    let dry = |pull: f64| {
        let h = hertz(c.e_star, g.r_eff, g.overlap);
        NormalStage {
            elastic: h.force,
            stiffness: h.stiffness,
            contact_radius: h.contact_radius,
            load: h.force,
            overlap: g.overlap,
            pull,
            floor: 0.0,
        }
    };
    match c.cohesion {
        // A dry pair apart (flagged bonded by an earlier table with cohesion) has nothing.
        Cohesion::None if touching => NormalOutcome::Contact(dry(0.0)),
        Cohesion::SimplifiedJkr { energy_density } if touching => {
            let area = sjkr::intersection_area(g.radius[0], g.radius[1], g.overlap);
            NormalOutcome::Contact(dry(sjkr::sjkr_force(energy_density, area)))
        }
        Cohesion::Jkr { work_of_adhesion } if touching || bonded => {
            match jkr::jkr(c.e_star, g.r_eff, work_of_adhesion, g.overlap) {
                Some(j) => NormalOutcome::Contact(NormalStage {
                    elastic: j.force,
                    stiffness: j.stiffness,
                    contact_radius: j.contact_radius,
                    load: j.force + 2.0 * jkr::pull_off_force(work_of_adhesion, g.r_eff),
                    overlap: j.contact_radius * j.contact_radius / g.r_eff,
                    pull: 0.0,
                    floor: j.force.min(0.0),
                }),
                None => NormalOutcome::Apart,
            }
        }
        Cohesion::LiquidBridge {
            volume,
            surface_tension,
            contact_angle,
        } if touching || bonded => {
            let pull = liquid_bridge::bridge_force(
                g.r_eff,
                volume,
                surface_tension,
                contact_angle,
                -g.overlap,
            );
            if touching {
                NormalOutcome::Contact(dry(pull))
            } else if pull > 0.0 {
                NormalOutcome::BridgeOnly(pull)
            } else {
                NormalOutcome::Apart
            }
        }
        _ => NormalOutcome::Apart,
    }
}

/// Which bonding law a material pair has, as the batched kernel's lanes read it
/// ([`BondConstants::law`]): none (dry, or the simplified JKR, which the kernel adds apart).
pub const LAW_DRY: u8 = 0;
/// JKR ([`BondConstants::law`]).
pub const LAW_JKR: u8 = 1;
/// A liquid bridge ([`BondConstants::law`]).
pub const LAW_BRIDGE: u8 = 2;

/// Stands for a batch whose lanes have different laws ([`bonded_stage_lane`]'s `LAWS`).
pub const LAWS_MIXED: u8 = 3;

/// A material pair's bonding law in plain numbers, formed once per pair: the law and its
/// constants ([`jkr::JkrPair`], [`liquid_bridge::BridgePair`]), for [`bonded_stage_lane`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BondConstants {
    /// [`LAW_DRY`], [`LAW_JKR`] or [`LAW_BRIDGE`].
    pub law: u8,
    /// The JKR curve's constants (meaningful for [`LAW_JKR`]).
    pub jkr: jkr::JkrPair,
    /// The bridge's constants (meaningful for [`LAW_BRIDGE`]).
    pub bridge: liquid_bridge::BridgePair,
}

impl BondConstants {
    /// The constants of the pair with coefficients `c`.
    pub fn of(c: &PairCoefficients) -> Self {
        match c.cohesion {
            Cohesion::Jkr { work_of_adhesion } => Self {
                law: LAW_JKR,
                jkr: jkr::JkrPair::new(c.e_star, work_of_adhesion),
                ..Self::default()
            },
            Cohesion::LiquidBridge {
                volume,
                surface_tension,
                contact_angle,
            } => Self {
                law: LAW_BRIDGE,
                bridge: liquid_bridge::BridgePair::new(volume, surface_tension, contact_angle),
                ..Self::default()
            },
            Cohesion::None | Cohesion::SimplifiedJkr { .. } => Self::default(),
        }
    }
}

/// What a lane's cohesion makes of its contact ([`StageLane::outcome`]): the bond broke, or
/// there was none; the full pipeline runs.
pub const OUTCOME_APART: u8 = 0;
const _: () = assert!(OUTCOME_APART == 0 && OUTCOME_CONTACT == 1 && OUTCOME_BRIDGE_ONLY == 2);
/// See [`OUTCOME_APART`]: the surfaces bear on each other, or a JKR bond holds them.
pub const OUTCOME_CONTACT: u8 = 1;
/// See [`OUTCOME_APART`]: only a liquid bridge acts across a gap, a pure attraction.
pub const OUTCOME_BRIDGE_ONLY: u8 = 2;

/// [`NormalStage`] as a lane of the batched kernel computes it, with the outcome as a
/// number ([`NormalOutcome`]'s three cases).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StageLane {
    /// Elastic normal force [N] ([`NormalStage::elastic`]).
    pub elastic: f64,
    /// Dashpot stiffness [N/m] ([`NormalStage::stiffness`]).
    pub stiffness: f64,
    /// Contact radius [m] ([`NormalStage::contact_radius`]).
    pub contact_radius: f64,
    /// Normal load [N] of friction and rolling resistance ([`NormalStage::load`]).
    pub load: f64,
    /// Attraction [N] subtracted after the dashpot ([`NormalStage::pull`]); for
    /// [`OUTCOME_BRIDGE_ONLY`] the whole force's magnitude.
    pub pull: f64,
    /// [`OUTCOME_APART`], [`OUTCOME_CONTACT`] or [`OUTCOME_BRIDGE_ONLY`].
    pub outcome: u8,
}

/// [`normal_stage`] without a branch, for a lane of the batched kernel: the contact of a
/// pair with bonding law `bond`, effective modulus `e_star` [Pa] and radius `r_eff` [m], at
/// overlap `overlap` [m], which touches or is bonded (the kernel's filter lists no other).
/// Every law's numbers are formed and the pair's are selected, so the numbers of a law
/// a lane does not have may be meaningless (a root of a negative number); the selected ones
/// are [`normal_stage`]'s, bit for bit, where the outcome is a contact, and its force where
/// the outcome is a bridge alone.
///
/// `LAWS` is [`LAW_JKR`] or [`LAW_BRIDGE`] where every lane of the loop has that law (the
/// compiler then drops the other laws' numbers), else [`LAWS_MIXED`]; the lanes' numbers
/// are the same either way.
#[inline(always)]
pub fn bonded_stage_lane<const LAWS: u8>(
    bond: &BondConstants,
    e_star: f64,
    r_eff: f64,
    overlap: f64,
) -> StageLane {
    let dry = hertz(e_star, r_eff, overlap);
    let glued = bond.jkr.force(r_eff, overlap);
    let holds = bond.jkr.holds(r_eff, overlap);
    let wet = bond.bridge.force(r_eff, -overlap);
    let (is_jkr, is_bridge) = match LAWS {
        LAW_JKR => (true, false),
        LAW_BRIDGE => (false, true),
        _ => (bond.law == LAW_JKR, bond.law == LAW_BRIDGE),
    };
    let touching = overlap > 0.0;
    let pick = |jkr: f64, other: f64| if is_jkr { jkr } else { other };
    // The outcomes as arithmetic on the tests (APART 0, CONTACT 1, BRIDGE_ONLY 2), which
    // the compiler keeps in vector lanes where nested selects become branches.
    let bridge_outcome = u8::from(touching) + 2 * u8::from(!touching & (wet > 0.0));
    let jkr_outcome = u8::from(holds);
    let dry_outcome = u8::from(touching);
    StageLane {
        elastic: pick(glued.force, dry.force),
        stiffness: pick(glued.stiffness, dry.stiffness),
        contact_radius: pick(glued.contact_radius, dry.contact_radius),
        load: pick(
            glued.force + 2.0 * bond.jkr.pull_off_force(r_eff),
            dry.force,
        ),
        pull: if is_bridge { wet } else { 0.0 },
        outcome: if is_jkr {
            jkr_outcome
        } else if is_bridge {
            bridge_outcome
        } else {
            dry_outcome
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_jkr_and_bridges_reach_beyond_contact() {
        let jkr = Cohesion::Jkr {
            work_of_adhesion: 0.05,
        };
        assert!(jkr.bonds() && jkr.reach(1e8, 1e-3) > 0.0);
        let bridge = Cohesion::LiquidBridge {
            volume: 1e-12,
            surface_tension: 0.072,
            contact_angle: 0.0,
        };
        // S_c = V^{1/3} at θ = 0: 10⁻⁴ m, exact up to the cube root's rounding.
        assert!((bridge.reach(1e8, 1e-3) - 1e-4).abs() < 1e-18);
        let sjkr = Cohesion::SimplifiedJkr {
            energy_density: 1e5,
        };
        assert!(!sjkr.bonds() && sjkr.reach(1e8, 1e-3) == 0.0);
        assert!(!Cohesion::None.bonds() && Cohesion::None.is_none());
    }

    #[test]
    fn coarse_grained_laws_pull_kappa_squared_times_harder_at_the_same_relative_overlap() {
        // A pair of 1 mm spheres and its parcels of κ = 2.5 at the same overlap over radius:
        // every law's force is κ² times the grains' (the scaling's definition), to rounding,
        // and JKR breaks and a bridge ruptures κ times as far out.
        use crate::material::{Interaction, Material};
        let kappa = 2.5;
        let m = Material::fan2023();
        let laws = [
            Cohesion::Jkr {
                work_of_adhesion: 0.5,
            },
            Cohesion::SimplifiedJkr {
                energy_density: 1e5,
            },
            Cohesion::LiquidBridge {
                volume: 1e-12,
                surface_tension: 0.072,
                contact_angle: 0.3,
            },
        ];
        for law in laws {
            let grains =
                PairCoefficients::new(&m, Some(&m), &Interaction::fan2023().with_cohesion(law));
            let parcels = PairCoefficients::new(
                &m,
                Some(&m),
                &Interaction::fan2023().with_cohesion(law.coarse_grained(kappa)),
            );
            let (r, e_star) = (0.5e-3, grains.e_star);
            let reach = law.reach(e_star, r / 2.0);
            // The simplified JKR acts in contact only: no reach to scale.
            let scaled = law.coarse_grained(kappa).reach(e_star, kappa * r / 2.0);
            assert!(
                (scaled - kappa * reach).abs() <= 1e-12 * scaled,
                "{law:?}: the reach {scaled:e} against κ × {reach:e}"
            );
            // Overlaps of the grains from just inside the reach to 1 % of the radius.
            for overlap in [-0.9 * reach, -0.3 * reach, 1e-7, 1e-6, 5e-6] {
                let force = |c: &PairCoefficients, scale: f64| {
                    let g = ContactGeometry {
                        normal: glam::DVec3::X,
                        overlap: scale * overlap,
                        r_eff: scale * r / 2.0,
                        m_eff: 1e-6,
                        arm_i: scale * r,
                        arm_j: scale * r,
                        inertia: [1.0; 2],
                        mass_radius2: [1.0; 2],
                        radius: [scale * r; 2],
                    };
                    match normal_stage(&g, c, true) {
                        NormalOutcome::Contact(s) => s.elastic - s.pull,
                        NormalOutcome::BridgeOnly(pull) => -pull,
                        NormalOutcome::Apart => 0.0,
                    }
                };
                let (f1, fk) = (force(&grains, 1.0), force(&parcels, kappa));
                assert!(
                    (fk - kappa * kappa * f1).abs() <= 1e-9 * fk.abs().max(1e-30),
                    "{law:?} at {overlap:e}: {fk:e} against κ² × {f1:e}"
                );
            }
        }
        assert_eq!(Cohesion::None.coarse_grained(kappa), Cohesion::None);
    }

    #[test]
    fn the_lane_form_is_the_normal_stage_bit_for_bit() {
        // Overlaps from −0.2 mm (beyond every reach here) to 20 µm of compression, for a
        // dry, a JKR and a wet pair of 1 mm spheres: where `normal_stage` finds a contact
        // (touching, or bonded), the lane's numbers are its numbers exactly; where a bridge
        // alone acts, its pull; and the outcomes agree.
        use crate::material::{Interaction, Material};
        let m = Material::fan2023();
        let laws = [
            Cohesion::None,
            Cohesion::Jkr {
                work_of_adhesion: 5.0,
            },
            Cohesion::LiquidBridge {
                volume: 1e-12,
                surface_tension: 0.072,
                contact_angle: 0.35,
            },
        ];
        let (mut contacts, mut bridges, mut apart) = (0, 0, 0);
        for law in laws {
            let c = PairCoefficients::new(&m, Some(&m), &Interaction::fan2023().with_cohesion(law));
            let bond = BondConstants::of(&c);
            let r_eff = 5e-4;
            for k in 0..=2200 {
                let overlap = -2e-4 + 1e-7 * k as f64;
                let g = ContactGeometry {
                    normal: glam::DVec3::X,
                    overlap,
                    r_eff,
                    m_eff: 1e-6,
                    arm_i: 1e-3,
                    arm_j: 1e-3,
                    inertia: [1.0; 2],
                    mass_radius2: [1.0; 2],
                    radius: [1e-3; 2],
                };
                let lane = bonded_stage_lane::<LAWS_MIXED>(&bond, c.e_star, r_eff, overlap);
                match normal_stage(&g, &c, true) {
                    NormalOutcome::Contact(s) => {
                        contacts += 1;
                        assert_eq!(lane.outcome, OUTCOME_CONTACT, "{law:?} at {overlap}");
                        let picked = [
                            lane.elastic,
                            lane.stiffness,
                            lane.contact_radius,
                            lane.load,
                            lane.pull,
                        ];
                        let staged = [s.elastic, s.stiffness, s.contact_radius, s.load, s.pull];
                        for (a, b) in picked.iter().zip(staged) {
                            assert_eq!(a.to_bits(), b.to_bits(), "{law:?} at {overlap}");
                        }
                    }
                    NormalOutcome::BridgeOnly(pull) => {
                        bridges += 1;
                        assert_eq!(lane.outcome, OUTCOME_BRIDGE_ONLY);
                        assert_eq!(lane.pull.to_bits(), pull.to_bits());
                    }
                    NormalOutcome::Apart => {
                        apart += 1;
                        assert_eq!(lane.outcome, OUTCOME_APART, "{law:?} at {overlap}");
                    }
                }
            }
        }
        assert!(contacts > 0 && bridges > 0 && apart > 0);
    }

    #[test]
    fn out_of_range_parameters_are_named() {
        let bad = Cohesion::LiquidBridge {
            volume: -1.0,
            surface_tension: 0.07,
            contact_angle: 2.0,
        };
        let keys: Vec<_> = bad.problems().iter().map(|p| p.0).collect();
        assert_eq!(keys, ["volume", "contact_angle"]);
        assert!(
            Cohesion::Jkr {
                work_of_adhesion: f64::NAN
            }
            .problems()
            .len()
                == 1
        );
    }
}

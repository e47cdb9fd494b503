//! The bonding laws of a batch's contacts (JKR, liquid bridges; docs/physics.md §2.4,
//! §2.6), one array over the slots per constant, as the kernel's lanes read them
//! ([`crate::contact::cohesion::bonded_stage_lane`]), and what the kernel made of each slot.

use super::kernel::BATCH;
use crate::contact::cohesion::{BondConstants, LAWS_MIXED, LAW_BRIDGE, LAW_JKR};
use crate::contact::jkr::JkrPair;
use crate::contact::liquid_bridge::BridgePair;
use crate::material::PairCoefficients;

/// Each material pair's and each wall–material pair's bonding constants ([`BondConstants`]:
/// a cosine and a cube root each), formed once with the coefficient tables they come from
/// and indexed as they are, rather than at every pair loop and wall run of every step.
#[derive(Clone, Debug, Default)]
pub(crate) struct BondTables {
    /// By material pair, as the pair coefficients.
    pub pair: Vec<BondConstants>,
    /// By wall and material, as the wall coefficients.
    pub wall: Vec<BondConstants>,
}

impl BondTables {
    /// The constants of the coefficient tables `pair` and `wall`.
    pub(crate) fn of(pair: &[PairCoefficients], wall: &[PairCoefficients]) -> Self {
        Self {
            pair: pair.iter().map(BondConstants::of).collect(),
            wall: wall.iter().map(BondConstants::of).collect(),
        }
    }
}

/// [`BondConstants`] of each slot, structure of arrays.
#[derive(Clone, Debug)]
pub struct BondRows {
    /// The pair's law ([`crate::contact::cohesion::LAW_DRY`], [`LAW_JKR`], [`LAW_BRIDGE`]).
    pub law: [u8; BATCH],
    /// JKR's c = √(2π w/E*) [m^{1/2}].
    pub c: [f64; BATCH],
    /// JKR's (3/2) π w [N/m].
    pub pull_off: [f64; BATCH],
    /// JKR's (27/64)(π w/E*)² [m²].
    pub break_cubed: [f64; BATCH],
    /// JKR's 8π w E* [N²/m³].
    pub adhesion: [f64; BATCH],
    /// The bridge's volume [m³].
    pub volume: [f64; BATCH],
    /// The liquid's surface tension [N/m].
    pub surface_tension: [f64; BATCH],
    /// cos θ of the contact angle [-].
    pub cos_angle: [f64; BATCH],
    /// The bridge's rupture distance [m].
    pub rupture: [f64; BATCH],
    /// Output: what the cohesion made of each slot
    /// ([`crate::contact::cohesion::OUTCOME_APART`] and the others).
    pub outcome: [u8; BATCH],
}

impl Default for BondRows {
    fn default() -> Self {
        let z = [0.0; BATCH];
        Self {
            law: [0; BATCH],
            c: z,
            pull_off: z,
            break_cubed: z,
            adhesion: z,
            volume: z,
            surface_tension: z,
            cos_angle: z,
            rupture: z,
            outcome: [0; BATCH],
        }
    }
}

/// The constants a lane of another law computes with and never selects: a JKR curve of
/// w = 0.05 J/m² and a bridge of 1 m³ without tension, so that every lane's numbers are
/// well scaled (no subnormal numbers, which cost some processors a hundred cycles each).
fn stand_ins(b: &BondConstants, e_star: f64) -> BondConstants {
    BondConstants {
        law: b.law,
        jkr: if b.law == LAW_JKR {
            b.jkr
        } else {
            JkrPair::new(e_star, 0.05)
        },
        bridge: if b.law == LAW_BRIDGE {
            b.bridge
        } else {
            BridgePair::new(1.0, 0.0, 0.0)
        },
    }
}

impl BondRows {
    /// Sets slot `m` to the constants `b` of a pair of effective modulus `e_star` [Pa].
    #[inline(always)]
    pub fn set(&mut self, m: usize, b: &BondConstants, e_star: f64) {
        let b = stand_ins(b, e_star);
        self.law[m] = b.law;
        self.c[m] = b.jkr.c;
        self.pull_off[m] = b.jkr.pull_off;
        self.break_cubed[m] = b.jkr.break_cubed;
        self.adhesion[m] = b.jkr.adhesion;
        self.volume[m] = b.bridge.volume;
        self.surface_tension[m] = b.bridge.surface_tension;
        self.cos_angle[m] = b.bridge.cos_angle;
        self.rupture[m] = b.bridge.rupture;
    }

    /// Sets every slot to the constants `b` of a pair of effective modulus `e_star` [Pa].
    pub fn fill(&mut self, b: &BondConstants, e_star: f64) {
        for m in 0..BATCH {
            self.set(m, b, e_star);
        }
    }

    /// The law every slot of `0..len` shares ([`LAW_JKR`], [`LAW_BRIDGE`] or
    /// [`crate::contact::cohesion::LAW_DRY`]), or [`LAWS_MIXED`], for the kernel's choice of
    /// loop.
    #[inline(always)]
    pub fn laws(&self, len: usize) -> u8 {
        let laws = &self.law[..len.min(BATCH)];
        match laws.first() {
            Some(&first) if laws.iter().all(|&l| l == first) => first,
            _ => LAWS_MIXED,
        }
    }

    /// The constants of slot `k`, whose pair has effective modulus `e_star` [Pa].
    #[inline(always)]
    pub fn constants(&self, k: usize, e_star: f64) -> BondConstants {
        BondConstants {
            law: self.law[k],
            jkr: JkrPair {
                e_star,
                c: self.c[k],
                pull_off: self.pull_off[k],
                break_cubed: self.break_cubed[k],
                adhesion: self.adhesion[k],
            },
            bridge: BridgePair {
                volume: self.volume[k],
                surface_tension: self.surface_tension[k],
                cos_angle: self.cos_angle[k],
                rupture: self.rupture[k],
            },
        }
    }
}

//! A material table: named materials and a list of pair entries, with the mixing rules of
//! [`super::mixing`] for the pairs it does not list (docs/physics.md §1.2). It is plain data,
//! deserialisable from a case file; [`crate::Simulation::add_material_table`] installs it.
//!
//! Each material gives ρ, ν and one of E or G (E = 2G(1+ν)); both may be given when they
//! agree to [`MODULUS_TOLERANCE`], and then E is used. Each pair entry names two materials
//! and gives e, μ_s and optionally μ_r (absent means 0: no rolling resistance). A pair may be
//! listed once, in either order.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::mixing::mixed_interaction;
use super::table_error::{MaterialTableError, MODULUS_TOLERANCE};
use super::{Interaction, Material, PairCoefficients, WallMaterial};
use crate::contact::Cohesion;

/// One named material of a [`MaterialTable`]; every property is optional here so that an
/// absent one is reported with its key instead of failing to parse.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialEntry {
    /// Young's modulus E [Pa], > 0; this or `shear_modulus` is required.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub youngs_modulus: Option<f64>,
    /// Shear modulus G [Pa], > 0; this or `youngs_modulus` is required.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_modulus: Option<f64>,
    /// Poisson's ratio ν [-], in (−1, 0.5); required.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson_ratio: Option<f64>,
    /// Density ρ [kg/m³], > 0; required.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
}

impl MaterialEntry {
    /// A material given by Young's modulus E [Pa], Poisson's ratio ν [-] and density ρ [kg/m³].
    pub fn from_youngs_modulus(youngs_modulus: f64, poisson_ratio: f64, density: f64) -> Self {
        Self {
            youngs_modulus: Some(youngs_modulus),
            shear_modulus: None,
            poisson_ratio: Some(poisson_ratio),
            density: Some(density),
        }
    }

    /// A material given by shear modulus G [Pa], Poisson's ratio ν [-] and density ρ [kg/m³].
    pub fn from_shear_modulus(shear_modulus: f64, poisson_ratio: f64, density: f64) -> Self {
        Self {
            youngs_modulus: None,
            shear_modulus: Some(shear_modulus),
            poisson_ratio: Some(poisson_ratio),
            density: Some(density),
        }
    }
}

/// One entry of a [`MaterialTable`]'s pair list: how two materials (or one with itself) meet.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PairEntry {
    /// The two materials' names, in either order; the same name twice is a self-pair.
    pub materials: [String; 2],
    /// Coefficient of restitution e [-], in (0, 1]; required.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// Sliding friction coefficient μ_s [-], ≥ 0; required.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// Rolling friction coefficient μ_r [-], ≥ 0; absent means 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rolling_friction: Option<f64>,
    /// How the two surfaces stick (docs/physics.md §2.4–2.6); dry by default.
    #[serde(default, skip_serializing_if = "Cohesion::is_none")]
    pub cohesion: Cohesion,
}

impl PairEntry {
    /// The entry for materials `a` and `b` with the coefficients of `interaction`.
    pub fn new(a: &str, b: &str, interaction: Interaction) -> Self {
        Self {
            materials: [a.to_owned(), b.to_owned()],
            restitution: Some(interaction.restitution),
            friction: Some(interaction.friction),
            rolling_friction: Some(interaction.rolling_friction),
            cohesion: interaction.cohesion,
        }
    }

    /// The entry's coefficients; call only on an entry the table's check accepted.
    fn interaction(&self) -> Interaction {
        Interaction {
            friction: self.friction.unwrap_or(0.0),
            rolling_friction: self.rolling_friction.unwrap_or(0.0),
            restitution: self.restitution.unwrap_or(1.0),
            cohesion: self.cohesion,
        }
    }
}

/// Particle and wall materials by name, and the coefficients of their pairs.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialTable {
    /// The materials, by name.
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialEntry>,
    /// The pair entries; pairs not listed are mixed from their self-pairs.
    #[serde(default)]
    pub pairs: Vec<PairEntry>,
}

const DENSITY_RANGE: &str = "> 0 kg/m³";
const MODULUS_RANGE: &str = "> 0 Pa";
const POISSON_RANGE: &str = "(-1, 0.5)";
const RESTITUTION_RANGE: &str = "(0, 1]";
const FRICTION_RANGE: &str = "≥ 0";

/// Checks the optional value at `key`: absent (when `required`), non-finite or outside
/// `allowed` (tested by `in_range`) adds a problem; returns the value when it is usable.
fn checked(
    key: String,
    value: Option<f64>,
    required: bool,
    allowed: &'static str,
    in_range: fn(f64) -> bool,
    problems: &mut Vec<MaterialTableError>,
) -> Option<f64> {
    match value {
        None if required => {
            problems.push(MaterialTableError::Missing { key, allowed });
            None
        }
        None => None,
        Some(value) if !value.is_finite() => {
            problems.push(MaterialTableError::NotFinite {
                key,
                value,
                allowed,
            });
            None
        }
        Some(value) if !in_range(value) => {
            problems.push(MaterialTableError::OutOfRange {
                key,
                value,
                allowed,
            });
            None
        }
        Some(value) => Some(value),
    }
}

/// The material of a valid entry, and the problems of an invalid one.
fn material_of(name: &str, entry: &MaterialEntry) -> Result<Material, Vec<MaterialTableError>> {
    let key = format!("materials.{name}");
    let mut problems = Vec::new();
    let p = &mut problems;
    let youngs = checked(
        format!("{key}.youngs_modulus"),
        entry.youngs_modulus,
        false,
        MODULUS_RANGE,
        |v| v > 0.0,
        p,
    );
    let shear = checked(
        format!("{key}.shear_modulus"),
        entry.shear_modulus,
        false,
        MODULUS_RANGE,
        |v| v > 0.0,
        p,
    );
    let nu = checked(
        format!("{key}.poisson_ratio"),
        entry.poisson_ratio,
        true,
        POISSON_RANGE,
        |v| v > -1.0 && v < 0.5,
        p,
    );
    let density = checked(
        format!("{key}.density"),
        entry.density,
        true,
        DENSITY_RANGE,
        |v| v > 0.0,
        p,
    );
    if entry.youngs_modulus.is_none() && entry.shear_modulus.is_none() {
        problems.push(MaterialTableError::MissingModulus { key: key.clone() });
    }
    if let (Some(e), Some(g), Some(nu)) = (youngs, shear, nu) {
        let implied = 2.0 * g * (1.0 + nu);
        let relative_difference = (implied - e).abs() / e;
        if !(relative_difference <= MODULUS_TOLERANCE) {
            problems.push(MaterialTableError::InconsistentModuli {
                key: key.clone(),
                youngs_modulus: e,
                shear_modulus: g,
                poisson_ratio: nu,
                implied_youngs_modulus: implied,
                relative_difference,
                tolerance: MODULUS_TOLERANCE,
            });
        }
    }
    match (youngs, shear, nu, density) {
        _ if !problems.is_empty() => Err(problems),
        (Some(e), _, Some(nu), Some(density)) => Ok(Material {
            density,
            youngs_modulus: e,
            poisson_ratio: nu,
        }),
        (None, Some(g), Some(nu), Some(density)) => {
            Ok(Material::from_shear_modulus(density, g, nu))
        }
        // Not reached: each absent or refused value has added a problem above.
        _ => Err(vec![MaterialTableError::MissingModulus { key }]),
    }
}

impl MaterialTable {
    /// An empty table.
    pub fn new() -> Self {
        Self::default()
    }

    /// The table with material `name` added (or replaced).
    pub fn with_material(mut self, name: &str, entry: MaterialEntry) -> Self {
        self.materials.insert(name.to_owned(), entry);
        self
    }

    /// The table with `pair` appended to the pair list.
    pub fn with_pair(mut self, pair: PairEntry) -> Self {
        self.pairs.push(pair);
        self
    }

    /// The materials of the open DEM benchmark silo (Dosta et al. 2024, Comput. Phys.
    /// Commun. 296, 109066): particles M1 and M2 and steel walls, every pair listed, no
    /// rolling resistance.
    pub fn dosta2024() -> Self {
        let pair = |a: &str, b: &str, restitution: f64, friction: f64| {
            PairEntry::new(
                a,
                b,
                Interaction {
                    friction,
                    rolling_friction: 0.0,
                    restitution,
                    cohesion: crate::contact::Cohesion::None,
                },
            )
        };
        Self::new()
            .with_material("M1", MaterialEntry::from_youngs_modulus(1.0e9, 0.2, 2500.0))
            .with_material("M2", MaterialEntry::from_youngs_modulus(0.5e9, 0.2, 2000.0))
            .with_material(
                "steel",
                MaterialEntry::from_youngs_modulus(210.0e9, 0.2, 7200.0),
            )
            .with_pair(pair("M1", "M1", 0.5, 0.3))
            .with_pair(pair("M1", "M2", 0.45, 0.2))
            .with_pair(pair("M1", "steel", 0.4, 0.2))
            .with_pair(pair("M2", "M2", 0.4, 0.4))
            .with_pair(pair("M2", "steel", 0.4, 0.2))
            .with_pair(pair("steel", "steel", 0.6, 0.5))
    }

    /// The material names, in the table's (sorted) order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.materials.keys().map(String::as_str)
    }

    /// Every problem of the table, materials first (by name), then the pairs in order; empty
    /// when the table can be used.
    pub fn problems(&self) -> Vec<MaterialTableError> {
        let mut problems = Vec::new();
        for (name, entry) in &self.materials {
            if let Err(mut p) = material_of(name, entry) {
                problems.append(&mut p);
            }
        }
        let mut seen: BTreeMap<[&str; 2], usize> = BTreeMap::new();
        for (i, pair) in self.pairs.iter().enumerate() {
            let key = format!("pairs[{i}]");
            for name in &pair.materials {
                if let Err(e) = self.known(&key, name) {
                    problems.push(e);
                }
            }
            let [a, b] = &pair.materials;
            let unordered = if a <= b { [&**a, &**b] } else { [&**b, &**a] };
            if let Some(&first) = seen.get(&unordered) {
                problems.push(MaterialTableError::DuplicatePair {
                    key: key.clone(),
                    a: a.clone(),
                    b: b.clone(),
                    first: format!("pairs[{first}]"),
                });
            } else {
                seen.insert(unordered, i);
            }
            let p = &mut problems;
            checked(
                format!("{key}.restitution"),
                pair.restitution,
                true,
                RESTITUTION_RANGE,
                |v| v > 0.0 && v <= 1.0,
                p,
            );
            checked(
                format!("{key}.friction"),
                pair.friction,
                true,
                FRICTION_RANGE,
                |v| v >= 0.0,
                p,
            );
            checked(
                format!("{key}.rolling_friction"),
                pair.rolling_friction,
                false,
                FRICTION_RANGE,
                |v| v >= 0.0,
                p,
            );
            for (name, value, allowed) in pair.cohesion.problems() {
                problems.push(if value.is_finite() {
                    MaterialTableError::OutOfRange {
                        key: format!("{key}.cohesion.{name}"),
                        value,
                        allowed,
                    }
                } else {
                    MaterialTableError::NotFinite {
                        key: format!("{key}.cohesion.{name}"),
                        value,
                        allowed,
                    }
                });
            }
        }
        problems
    }

    /// The table's first problem, if it has one ([`MaterialTable::problems`] lists all).
    pub fn check(&self) -> Result<(), MaterialTableError> {
        match self.problems().into_iter().next() {
            Some(problem) => Err(problem),
            None => Ok(()),
        }
    }

    /// Refuses `name` used at `key` unless it is one of the table's materials.
    pub fn known(&self, key: &str, name: &str) -> Result<(), MaterialTableError> {
        if self.materials.contains_key(name) {
            Ok(())
        } else {
            Err(MaterialTableError::UnknownMaterial {
                key: key.to_owned(),
                name: name.to_owned(),
                defined: self.names().collect::<Vec<_>>().join(", "),
            })
        }
    }

    /// The material `name`, E derived from G where only G is given.
    pub fn material(&self, name: &str) -> Result<Material, MaterialTableError> {
        self.check()?;
        self.known("material", name)?;
        material_of(name, &self.materials[name]).map_err(|mut p| p.remove(0))
    }

    /// A wall made of the material `name`.
    pub fn wall_material(&self, name: &str) -> Result<WallMaterial, MaterialTableError> {
        self.material(name).map(WallMaterial::Elastic)
    }

    /// The listed entry for the pair (a, b) in either order.
    fn listed(&self, a: &str, b: &str) -> Option<Interaction> {
        self.pairs
            .iter()
            .find(|p| {
                let [x, y] = &p.materials;
                (x == a && y == b) || (x == b && y == a)
            })
            .map(PairEntry::interaction)
    }

    /// How materials `a` and `b` interact: their pair entry, or else the mixing rules applied
    /// to their two self-pairs (docs/physics.md §1.2).
    pub fn interaction(&self, a: &str, b: &str) -> Result<Interaction, MaterialTableError> {
        self.check()?;
        let key = format!("pair ({a}, {b})");
        self.known(&key, a)?;
        self.known(&key, b)?;
        if let Some(listed) = self.listed(a, b) {
            return Ok(listed);
        }
        let self_pair = |m: &str| {
            self.listed(m, m)
                .ok_or_else(|| MaterialTableError::UnlistedPair {
                    key: "pairs".to_owned(),
                    a: a.to_owned(),
                    b: b.to_owned(),
                    missing: m.to_owned(),
                })
        };
        let (aa, bb) = (self_pair(a)?, self_pair(b)?);
        mixed_interaction(&aa, &bb).ok_or_else(|| MaterialTableError::UnmixableCohesion {
            key: "pairs".to_owned(),
            a: a.to_owned(),
            b: b.to_owned(),
        })
    }

    /// Everything the contact law needs about the pair (a, b): E*, G* from the two materials
    /// and the pair's interaction.
    pub fn coefficients(&self, a: &str, b: &str) -> Result<PairCoefficients, MaterialTableError> {
        let interaction = self.interaction(a, b)?;
        Ok(PairCoefficients::new(
            &self.material(a)?,
            Some(&self.material(b)?),
            &interaction,
        ))
    }
}

//! The Bond number of a case, Bo = F_c/(m g): the force that pulls two of its grains apart
//! over one grain's weight (docs/physics.md §7.12). The one place where hopperflow computes
//! it; the report reads it from each case's resolved `case.toml`, not from the engine.
//!
//! F_c for two equal spheres of diameter d (R = d/2, R* = d/4), per law:
//! - JKR (Johnson, Kendall & Roberts 1971): the pull-off force F_c = (3/2)π w R*;
//! - liquid bridge (Willett et al. 2000, as `dem`'s `liquid_bridge.rs` writes it): the force
//!   at contact F(0) = 2π R̃ γ cos θ with R̃ = 2R* = R;
//! - simplified JKR (LIGGGHTS' `sjkr`): the attraction k_c π a² is zero at touching, so there
//!   is no pull-off force of the attraction alone; the pair's force, Hertz minus attraction,
//!   (4/3)E*√R* δ^{3/2} − 2π k_c R* δ for a ≪ R, has a least value at δ_m = π² k_c² R*/E*²,
//!   and that tension is what a slow pull must overcome: F_c = (2/3)π³ k_c³ R*²/E*².
//!   It is the same definition as JKR's F_c, the least force on the quasi-static curve.

use std::f64::consts::PI;

/// How two grains stick, as a case file's `cohesion` table gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GrainCohesion {
    /// No cohesion (no table, or `law = "none"`).
    Dry,
    /// JKR with a work of adhesion w [J/m²].
    Jkr {
        /// w [J/m²].
        work_of_adhesion: f64,
    },
    /// Simplified JKR with a cohesion energy density k_c [J/m³].
    SimplifiedJkr {
        /// k_c [J/m³].
        energy_density: f64,
    },
    /// A pendular liquid bridge.
    LiquidBridge {
        /// V [m³].
        volume: f64,
        /// γ [N/m].
        surface_tension: f64,
        /// θ [rad].
        contact_angle: f64,
    },
}

impl GrainCohesion {
    /// The `law` word of the case file.
    pub fn law(&self) -> &'static str {
        match self {
            Self::Dry => "dry",
            Self::Jkr { .. } => "jkr",
            Self::SimplifiedJkr { .. } => "sjkr",
            Self::LiquidBridge { .. } => "liquid_bridge",
        }
    }

    /// The law's parameters as the report prints them.
    pub fn parameters(&self) -> String {
        match *self {
            Self::Dry => String::new(),
            Self::Jkr { work_of_adhesion } => format!("w = {work_of_adhesion} J/m²"),
            Self::SimplifiedJkr { energy_density } => format!("k_c = {energy_density:e} J/m³"),
            Self::LiquidBridge {
                volume,
                surface_tension,
                contact_angle,
            } => format!(
                "V = {volume:e} m³, γ = {surface_tension} N/m, θ = {:.1}°",
                contact_angle.to_degrees()
            ),
        }
    }
}

/// The grains of a case as far as the Bond number needs them: monodisperse spheres of one
/// material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grains {
    /// Their cohesion with each other.
    pub cohesion: GrainCohesion,
    /// Diameter d [m].
    pub diameter: f64,
    /// Density ρ_p [kg/m³].
    pub density: f64,
    /// E* [Pa] of two of them, 1/E* = 2(1 − ν²)/E.
    pub effective_modulus: f64,
    /// g [m/s²].
    pub gravity: f64,
}

/// The force [N] that pulls two equal spheres of diameter `diameter` [m] and effective
/// modulus `effective_modulus` E* [Pa] apart (see the module's text); zero when dry.
pub fn pull_off_force(cohesion: &GrainCohesion, diameter: f64, effective_modulus: f64) -> f64 {
    let r_eff = 0.25 * diameter;
    match *cohesion {
        GrainCohesion::Dry => 0.0,
        GrainCohesion::Jkr { work_of_adhesion } => 1.5 * PI * work_of_adhesion * r_eff,
        GrainCohesion::SimplifiedJkr { energy_density } => {
            (2.0 / 3.0) * PI.powi(3) * energy_density.powi(3) * r_eff * r_eff
                / (effective_modulus * effective_modulus)
        }
        GrainCohesion::LiquidBridge {
            surface_tension,
            contact_angle,
            ..
        } => 2.0 * PI * (2.0 * r_eff) * surface_tension * contact_angle.cos(),
    }
}

/// Bo = F_c/(m g) [-] of `grains`, m = ρ_p π d³/6; zero when dry.
pub fn bond_number(grains: &Grains) -> f64 {
    let d = grains.diameter;
    let weight = grains.density * PI * d * d * d / 6.0 * grains.gravity;
    pull_off_force(&grains.cohesion, d, grains.effective_modulus) / weight
}

/// A number of a TOML table, float or integer.
fn number(table: &toml::Table, key: &str) -> Option<f64> {
    match table.get(key)? {
        toml::Value::Float(x) => Some(*x),
        toml::Value::Integer(x) => Some(*x as f64),
        _ => None,
    }
}

/// A case file's `cohesion` table (absent: dry), as `crates/case` reads it; the contact
/// angle in radians (`contact_angle`, what a resolved case writes) or degrees.
pub fn read_cohesion(value: Option<&toml::Value>) -> Result<GrainCohesion, String> {
    let Some(value) = value else {
        return Ok(GrainCohesion::Dry);
    };
    let table = value
        .as_table()
        .ok_or_else(|| "`cohesion` is not a table".to_string())?;
    let need = |key: &str| {
        number(table, key).ok_or_else(|| format!("`cohesion.{key}` is missing or not a number"))
    };
    match table.get("law").and_then(|l| l.as_str()) {
        Some("none") => Ok(GrainCohesion::Dry),
        Some("jkr") => Ok(GrainCohesion::Jkr {
            work_of_adhesion: need("work_of_adhesion")?,
        }),
        Some("sjkr") => Ok(GrainCohesion::SimplifiedJkr {
            energy_density: need("energy_density")?,
        }),
        Some("liquid_bridge") => {
            let contact_angle = match number(table, "contact_angle") {
                Some(rad) => rad,
                None => need("contact_angle_deg")?.to_radians(),
            };
            Ok(GrainCohesion::LiquidBridge {
                volume: need("volume")?,
                surface_tension: need("surface_tension")?,
                contact_angle,
            })
        }
        Some(other) => Err(format!("unknown cohesion law \"{other}\"")),
        None => Err("`cohesion.law` is missing".into()),
    }
}

/// E* [Pa] of two spheres of a material table (`youngs_modulus` or `shear_modulus`, with
/// `poisson_ratio`): E = 2G(1 + ν) when only G is given, 1/E* = 2(1 − ν²)/E.
fn effective_modulus(material: &toml::Table) -> Result<f64, String> {
    let nu = number(material, "poisson_ratio").ok_or("no poisson_ratio")?;
    let e = match number(material, "youngs_modulus") {
        Some(e) => e,
        None => 2.0 * number(material, "shear_modulus").ok_or("no modulus")? * (1.0 + nu),
    };
    Ok(e / (2.0 * (1.0 - nu * nu)))
}

/// The grains of the resolved case `case` (a parsed `case.toml`) under gravity `gravity`
/// [m/s²], or why the Bond number is not defined for them: a mixture or a size
/// distribution has no one pair whose pull-off force it would be.
pub fn case_grains(case: &toml::Table, gravity: f64) -> Result<Grains, String> {
    let particles = case
        .get("particles")
        .and_then(|p| p.as_table())
        .ok_or("no [particles]")?;
    if particles.contains_key("components") {
        return Err("a mixture of components: Bo is defined for one kind of grain".into());
    }
    let diameter = number(particles, "diameter")
        .ok_or("a size distribution: Bo is defined for equal spheres")?;
    let (material, cohesion) = match particles.get("material") {
        // A named material: its coefficients and its self-pair from the material table.
        Some(toml::Value::String(name)) => {
            let material = case
                .get("materials")
                .and_then(|m| m.get(name))
                .and_then(|m| m.as_table())
                .ok_or_else(|| format!("material \"{name}\" is not in [materials]"))?;
            let pair = case
                .get("pairs")
                .and_then(|p| p.as_array())
                .into_iter()
                .flatten()
                .find(|pair| is_self_pair(pair, name));
            let cohesion = read_cohesion(pair.and_then(|p| p.get("cohesion")))?;
            (material, cohesion)
        }
        Some(toml::Value::Table(material)) => {
            let cohesion = read_cohesion(case.get("contact").and_then(|c| c.get("cohesion")))?;
            (material, cohesion)
        }
        _ => return Err("no particle material".into()),
    };
    Ok(Grains {
        cohesion,
        diameter,
        density: number(material, "density").ok_or("no particle density")?,
        effective_modulus: effective_modulus(material)?,
        gravity,
    })
}

/// Whether the `[[pairs]]` entry `pair` is the pair of material `name` with itself.
pub(crate) fn is_self_pair(pair: &toml::Value, name: &str) -> bool {
    pair.get("materials")
        .and_then(|m| m.as_array())
        .is_some_and(|m| m.len() == 2 && m.iter().all(|x| x.as_str() == Some(name)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Table 1's grains: 3 mm glass, ρ = 2500 kg/m³, G = 1e8 Pa, ν = 0.25, under 9.81 m/s².
    fn glass(cohesion: GrainCohesion) -> Grains {
        Grains {
            cohesion,
            diameter: 3e-3,
            density: 2500.0,
            effective_modulus: 2.0 * 1e8 * 1.25 / (2.0 * (1.0 - 0.0625)),
            gravity: 9.81,
        }
    }

    #[test]
    fn the_cohesion_bond_preset_spans_bo_1_to_30() {
        // cases/cohesion-bond.toml chose w = 0.0981 Bo J/m² for these grains (m g =
        // 3.467e-4 N); its w = 0.098, 0.98 and 2.94 J/m² are Bo = 0.999, 9.99 and 30.0 to
        // the three digits the preset states.
        for (w, bo) in [(0.098, 0.999), (0.98, 9.99), (2.94, 30.0)] {
            let got = bond_number(&glass(GrainCohesion::Jkr {
                work_of_adhesion: w,
            }));
            assert!((got - bo).abs() < 0.0051 * bo, "w = {w}: Bo = {got}");
        }
        assert_eq!(bond_number(&glass(GrainCohesion::Dry)), 0.0);
    }

    #[test]
    fn the_sjkr_pull_off_force_is_the_least_force_of_hertz_minus_the_attraction() {
        // Scan the quasi-static force of the pair, Hertz minus k_c π a² with the exact
        // intersection area of two equal spheres (a² = Rδ − δ²/4), over overlaps around
        // the minimum: its least value is −F_c. The closed form drops the δ² term, of
        // relative size δ_m/(4R) ~ 1e-5 here, so they agree to 1e-4.
        let k = 3e5;
        let g = glass(GrainCohesion::SimplifiedJkr { energy_density: k });
        let (r, r_eff, e) = (1.5e-3, 0.75e-3, g.effective_modulus);
        let force =
            |d: f64| (4.0 / 3.0) * e * (r_eff * d).sqrt() * d - k * PI * (r * d - d * d / 4.0);
        let least = (1..=20_000)
            .map(|i| force(1e-11 * i as f64))
            .fold(f64::INFINITY, f64::min);
        let fc = pull_off_force(&g.cohesion, g.diameter, e);
        assert!((least + fc).abs() < 1e-4 * fc, "least {least}, F_c {fc}");
    }

    #[test]
    fn a_liquid_bridge_pulls_with_its_force_at_contact() {
        // Water on the 3 mm grains, θ = 0: F = 2π R γ = 2π · 1.5 mm · 0.072 N/m = 0.679 mN,
        // about twice the weight.
        let g = glass(GrainCohesion::LiquidBridge {
            volume: 1e-12,
            surface_tension: 0.072,
            contact_angle: 0.0,
        });
        let f = 2.0 * PI * 1.5e-3 * 0.072;
        assert!((pull_off_force(&g.cohesion, 3e-3, 1.0) - f).abs() < 1e-15);
        assert!((bond_number(&g) - 1.958).abs() < 1e-3);
    }

    #[test]
    fn mixtures_and_size_distributions_have_no_bond_number() {
        let case: toml::Table = toml::from_str(
            "[particles]\ncount = 10\n[particles.size_distribution]\nkind = \"uniform\"\n",
        )
        .unwrap();
        assert!(case_grains(&case, 9.81).unwrap_err().contains("size"));
        let case: toml::Table =
            toml::from_str("[particles]\ncount = 10\n[[particles.components]]\nname = \"a\"\n")
                .unwrap();
        assert!(case_grains(&case, 9.81).unwrap_err().contains("mixture"));
    }

    #[test]
    fn a_named_material_takes_its_self_pair_cohesion() {
        let case: toml::Table = toml::from_str(
            r#"
[materials.glass]
density = 2500.0
youngs_modulus = 2.5e8
poisson_ratio = 0.25
[[pairs]]
materials = ["glass", "steel"]
cohesion = { law = "jkr", work_of_adhesion = 5.0 }
[[pairs]]
materials = ["glass", "glass"]
cohesion = { law = "jkr", work_of_adhesion = 0.98 }
[particles]
count = 10
material = "glass"
diameter = 0.003
"#,
        )
        .unwrap();
        let grains = case_grains(&case, 9.81).unwrap();
        assert_eq!(
            grains.cohesion,
            GrainCohesion::Jkr {
                work_of_adhesion: 0.98
            }
        );
        assert!((bond_number(&grains) - 9.99).abs() < 0.01);
    }
}

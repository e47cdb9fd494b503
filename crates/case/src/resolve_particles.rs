//! Validation of the `[particles]` table: count, diameters or size distribution, material,
//! or a mixture of components (`[[particles.components]]`, each with its size, material and
//! fraction).

use super::document::NodeValue;
use super::error::{number, rounded, ConfigError, ErrorKind};
use super::limits::{MAX_COARSE_GRAINING, MAX_PARTICLE_COUNT};
use super::particles::{
    parcel_count, Component, FractionBasis, MaterialSpec, ParticleSpec, SizeDistribution,
};
use std::path::Path;

use super::reader::{Located, Section};
use super::resolve_materials::NamedMaterials;
use super::resolve_shape::read_shape;
use super::sources::{source, MaterialSources, ParticleSources};

/// Reads a material table (density, shear modulus, Poisson's ratio).
pub(crate) fn read_material(
    section: &mut Section<'_>,
    default: MaterialSpec,
    errors: &mut Vec<ConfigError>,
) -> Option<(MaterialSpec, MaterialSources)> {
    let density = section.float_or("density", "kg/m³", default.density, errors);
    let poisson = section.float_or("poisson_ratio", "", default.poisson_ratio, errors);
    // G or E: the benchmark tables give Young's modulus, the paper gives G.
    let youngs = section.float("youngs_modulus", "Pa", errors);
    let given_shear = section.float("shear_modulus", "Pa", errors);
    let mut ok = density.require_positive(errors);
    // A stable isotropic solid has −1 < ν < 0.5; ν = 0.5 would make the bulk modulus infinite.
    if !(poisson.value > -1.0 && poisson.value < 0.5) {
        errors.push(poisson.error(ErrorKind::Invalid, "must lie in (−1, 0.5)"));
        ok = false;
    }
    let shear = match (given_shear, youngs) {
        (Some(g), Some(e)) => {
            errors.push(e.error(
                ErrorKind::Conflict,
                format!("give either {} or {}, not both", g.key, e.key),
            ));
            ok = false;
            g
        }
        (Some(g), None) => {
            ok &= g.require_positive(errors);
            g
        }
        (None, Some(e)) => {
            ok &= e.require_positive(errors);
            // G = E / (2 (1 + ν)); the key stays E's, so messages name what was written.
            e.with_value(e.value / (2.0 * (1.0 + poisson.value)))
        }
        (None, None) => section.default_value("shear_modulus", default.shear_modulus, "Pa"),
    };
    section.finish(
        &[
            "density",
            "shear_modulus",
            "youngs_modulus",
            "poisson_ratio",
        ],
        errors,
    );
    ok.then(|| {
        (
            MaterialSpec {
                density: density.value,
                shear_modulus: shear.value,
                poisson_ratio: poisson.value,
            },
            MaterialSources {
                density: source(&density),
                shear_modulus: source(&shear),
                poisson_ratio: source(&poisson),
            },
        )
    })
}

/// The material of the particles (or a component): its properties, where they were set,
/// and its name in the case's `[materials]` table when it has one.
type MaterialChoice = (MaterialSpec, MaterialSources, Option<String>);

/// Most components a case may have: a component's index is kept in one byte per particle.
pub(crate) const MAX_COMPONENTS: usize = 255;

/// Reads `particles.material`: a table of properties (no `[materials]` in the case), or the
/// name of a `[materials]` entry. `None` when absent with a table (each component must then
/// name its own) or invalid.
fn read_particle_material(
    section: &mut Section<'_>,
    named: Option<&NamedMaterials>,
    errors: &mut Vec<ConfigError>,
) -> Option<MaterialChoice> {
    let is_word = section
        .entry("material")
        .is_some_and(|e| matches!(e.node.value, NodeValue::String(_)));
    match named {
        _ if is_word => {
            let word = section.string("material", errors)?;
            named_material(&word, named, errors)
        }
        None => read_material(
            &mut section.section("material", errors),
            MaterialSpec::fan2023(),
            errors,
        )
        .map(|(material, sources)| (material, sources, None)),
        Some(named) => {
            if let Some(entry) = section.entry("material") {
                errors.push(ConfigError::new(
                    ErrorKind::Conflict,
                    entry.key_location.clone(),
                    section.key("material"),
                    None,
                    format!(
                        "the case defines [materials]: name one of them (material = \"NAME\"; \
                         defined: {}) instead of giving a table",
                        named.defined()
                    ),
                ));
            }
            None
        }
    }
}

/// The material `word` names, which must be defined in the case's `[materials]`.
fn named_material(
    word: &Located<String>,
    named: Option<&NamedMaterials>,
    errors: &mut Vec<ConfigError>,
) -> Option<MaterialChoice> {
    let Some(named) = named else {
        errors.push(word.error(
            ErrorKind::Invalid,
            "names a material, but the case has no [materials] table; define it as \
             [materials.NAME] (density, youngs_modulus or shear_modulus, poisson_ratio), or \
             give the properties in a [particles.material] table",
        ));
        return None;
    };
    if !named.require_known(word, errors) {
        return None;
    }
    // An invalid material is reported by the table's checks.
    let (material, sources) = named.materials.get(&word.value)?.clone();
    Some((material, sources, Some(word.value.clone())))
}

/// A component read, with where its sizes and material were set.
struct ReadComponent {
    component: Component,
    sizes: SizesWithSources,
    material: MaterialSources,
}

pub(crate) fn read_particles(
    section: &mut Section<'_>,
    named: Option<&NamedMaterials>,
    dir: Option<&Path>,
    errors: &mut Vec<ConfigError>,
) -> Option<(ParticleSpec, ParticleSources)> {
    let paper = ParticleSpec::paper();
    let count = section.integer_or("count", paper.count as i64, errors);
    let mut ok = true;
    if !(1..=MAX_PARTICLE_COUNT).contains(&count.value) {
        errors.push(count.error(
            ErrorKind::Invalid,
            format!("must be an integer in [1, {MAX_PARTICLE_COUNT}]"),
        ));
        ok = false;
    }
    let coarse = section.float_or("coarse_graining", "", 1.0, errors);
    if !(1.0..=MAX_COARSE_GRAINING).contains(&coarse.value) {
        errors.push(coarse.error(
            ErrorKind::Invalid,
            format!(
                "must lie in [1, {}]: the parcels' diameter over the grains' (κ, 1 for the \
                 grains themselves)",
                number(MAX_COARSE_GRAINING)
            ),
        ));
        ok = false;
    } else if count.value >= 1 && parcel_count(count.value as usize, coarse.value) == 0 {
        errors.push(coarse.error(
            ErrorKind::Invalid,
            format!(
                "leaves fewer than one parcel: particles.count = {} grains over κ³ = {} \
                 grains a parcel",
                count.value,
                number(coarse.value.powi(3))
            ),
        ));
        ok = false;
    }
    let material = read_particle_material(section, named, errors);
    let read = if section.has("components") {
        for other in ["diameter", "size_distribution"] {
            if let Some(entry) = section.entry(other) {
                errors.push(ConfigError::new(
                    ErrorKind::Conflict,
                    entry.key_location.clone(),
                    section.key(other),
                    None,
                    format!(
                        "give either {} (one size) or {} (a mixture, each with its own size), \
                         not both",
                        section.key(other),
                        section.key("components")
                    ),
                ));
                ok = false;
            }
        }
        if let Some(entry) = section.entry("shape") {
            errors.push(ConfigError::new(
                ErrorKind::Conflict,
                entry.key_location.clone(),
                section.key("shape"),
                None,
                format!(
                    "a mixture gives each component its own shape: put it in the {} entries",
                    section.key("components")
                ),
            ));
            ok = false;
        }
        read_components(section, material.as_ref(), named, dir, errors)
    } else {
        if let Some(entry) = section.entry("fraction_by") {
            errors.push(ConfigError::new(
                ErrorKind::Invalid,
                entry.key_location.clone(),
                section.key("fraction_by"),
                Some(entry.node.value.to_string()),
                format!(
                    "counts the fractions of {}; a case of one size distribution has none",
                    section.key("components")
                ),
            ));
            ok = false;
        }
        let size = read_size(section, Some(3.0e-3), errors);
        let shape = read_shape(section, dir, errors);
        if material.is_none() && named.is_some() && !section.has("material") {
            errors.push(ConfigError::new(
                ErrorKind::Missing,
                section.location().clone(),
                section.key("material"),
                None,
                format!(
                    "required with [materials]: the particles' material, one of {}",
                    named.map(NamedMaterials::defined).unwrap_or_default()
                ),
            ));
        }
        match (size, material, shape) {
            (Some(sizes), Some((material, sources, name)), Ok(shape)) => Some((
                vec![ReadComponent {
                    component: Component {
                        name: "c1".to_string(),
                        size: sizes.0.clone(),
                        material,
                        material_name: name,
                        fraction: 1.0,
                        shape,
                    },
                    sizes,
                    material: sources,
                }],
                FractionBasis::Number,
            )),
            _ => None,
        }
    };
    section.finish(
        &[
            "count",
            "diameter",
            "size_distribution",
            "material",
            "components",
            "fraction_by",
            "coarse_graining",
            "shape",
        ],
        errors,
    );
    let (components, fraction_by) = read?;
    if !ok {
        return None;
    }
    let grains = ParticleSpec {
        count: count.value as usize,
        components: components.iter().map(|c| c.component.clone()).collect(),
        fraction_by,
        coarse_graining: None,
    };
    // Parcels: every check and default after this reads their diameters, which the
    // messages name as the grains' key times κ.
    let kappa = coarse.value;
    let spec = if kappa > 1.0 {
        grains.coarse_grained(kappa)
    } else {
        grains
    };
    let parcel = |key: &String| {
        if kappa > 1.0 {
            format!("{key} × {}", source(&coarse))
        } else {
            key.clone()
        }
    };
    // The inputs of the limits: the component of the shortest Rayleigh time (its material
    // and smallest diameter) and the component of the largest diameter.
    let shortest = components
        .iter()
        .min_by(|a, b| {
            a.component
                .rayleigh_time()
                .total_cmp(&b.component.rayleigh_time())
        })
        .expect("at least one component");
    let largest = components
        .iter()
        .max_by(|a, b| {
            a.component
                .size
                .max_diameter()
                .total_cmp(&b.component.size.max_diameter())
        })
        .expect("at least one component");
    let sources = ParticleSources {
        material: shortest.material.clone(),
        smallest_diameter: match &shortest.component.shape {
            // The smallest sphere the contact laws meet is a member of a shaped grain.
            Some(shape) => format!(
                "{} × {} (the smallest member's diameter over the grain's equal-volume \
                 diameter, {})",
                parcel(&shortest.sizes.1),
                rounded(shape.smallest_member_diameter()),
                shape.describe()
            ),
            None => parcel(&shortest.sizes.1),
        },
        largest_diameter: parcel(&largest.sizes.2),
    };
    Some((spec, sources))
}

/// Reads the size of the particles or of a component: `diameter` (monodisperse) or a
/// `size_distribution` table, not both; absent both, `default` [m] or an error.
fn read_size(
    section: &mut Section<'_>,
    default: Option<f64>,
    errors: &mut Vec<ConfigError>,
) -> Option<SizesWithSources> {
    if section.has("diameter") && section.has("size_distribution") {
        let entry = section.entry("size_distribution");
        section.entry("diameter");
        errors.push(ConfigError::new(
            ErrorKind::Conflict,
            entry.map_or_else(
                || section.default_location().clone(),
                |e| e.key_location.clone(),
            ),
            section.key("size_distribution"),
            None,
            format!(
                "give either {} (monodisperse) or a size distribution, not both",
                section.key("diameter")
            ),
        ));
        None
    } else if section.has("size_distribution") {
        read_distribution(&mut section.section("size_distribution", errors), errors)
    } else {
        let d = match default {
            Some(default) => section.float_or("diameter", "m", default, errors),
            None if section.has("diameter") => section.float("diameter", "m", errors)?,
            None => {
                errors.push(missing(
                    section,
                    "diameter",
                    "required: a diameter [m] or a size_distribution table",
                ));
                return None;
            }
        };
        d.require_positive(errors).then(|| {
            (
                SizeDistribution::Monodisperse { diameter: d.value },
                source(&d),
                source(&d),
            )
        })
    }
}

/// Reads `[[particles.components]]` and `particles.fraction_by`; `shared` is the material
/// of `particles.material`, which a component without its own `material` has.
fn read_components(
    section: &mut Section<'_>,
    shared: Option<&MaterialChoice>,
    named: Option<&NamedMaterials>,
    dir: Option<&Path>,
    errors: &mut Vec<ConfigError>,
) -> Option<(Vec<ReadComponent>, FractionBasis)> {
    let fraction_by = section.choice(
        "fraction_by",
        &[
            ("number", FractionBasis::Number),
            ("mass", FractionBasis::Mass),
        ],
        FractionBasis::Number,
        errors,
    );
    let components_location = section
        .entry("components")
        .map(|e| e.key_location.clone())
        .unwrap_or_else(|| section.location().clone());
    let tables = section.tables("components", errors)?;
    let mut ok = true;
    if tables.is_empty() || tables.len() > MAX_COMPONENTS {
        errors.push(ConfigError::new(
            ErrorKind::Invalid,
            components_location.clone(),
            section.key("components"),
            Some(format!("{} entries", tables.len())),
            format!("must hold 1 to {MAX_COMPONENTS} components"),
        ));
        return None;
    }
    let mut read = Vec::with_capacity(tables.len());
    let mut fractions = Vec::with_capacity(tables.len());
    let mut names: Vec<Located<String>> = Vec::new();
    for (i, mut table) in tables.into_iter().enumerate() {
        let name = table.string("name", errors);
        let name_value = match &name {
            Some(word) => {
                let valid = !word.value.is_empty()
                    && word
                        .value
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
                if !valid {
                    errors.push(word.error(
                        ErrorKind::Invalid,
                        "a component's name must be letters, digits, `_` or `-` (it heads \
                         columns of composition.csv)",
                    ));
                    ok = false;
                } else if let Some(first) = names.iter().find(|n| n.value == word.value) {
                    errors.push(word.error(
                        ErrorKind::Conflict,
                        format!("the name is given twice (first as {})", first.key),
                    ));
                    ok = false;
                }
                names.push(word.clone());
                word.value.clone()
            }
            None => format!("c{}", i + 1),
        };
        let size = read_size(&mut table, None, errors);
        let shape = read_shape(&mut table, dir, errors);
        let material = if table.has("material") {
            table
                .string("material", errors)
                .and_then(|word| named_material(&word, named, errors))
        } else {
            if shared.is_none() && named.is_some() && !section.has("material") {
                errors.push(missing(
                    &table,
                    "material",
                    &format!(
                        "required with [materials] unless particles.material names one: the \
                         component's material, one of {}",
                        named.map(NamedMaterials::defined).unwrap_or_default()
                    ),
                ));
            }
            shared.cloned()
        };
        let fraction = if table.has("fraction") {
            table.float("fraction", "", errors)
        } else {
            errors.push(missing(
                &table,
                "fraction",
                "required: the component's share of the particles, by number or by mass as \
                 particles.fraction_by says",
            ));
            None
        };
        table.finish(
            &[
                "name",
                "diameter",
                "size_distribution",
                "material",
                "fraction",
                "shape",
            ],
            errors,
        );
        let Some(fraction) = fraction else {
            ok = false;
            continue;
        };
        if !(fraction.value.is_finite() && (0.0..=1.0).contains(&fraction.value)) {
            errors.push(fraction.error(ErrorKind::Invalid, "must lie in [0, 1]"));
            ok = false;
        }
        fractions.push(fraction.clone());
        match (size, material, shape) {
            (Some(sizes), Some((material, sources, material_name)), Ok(shape)) => {
                read.push(ReadComponent {
                    component: Component {
                        name: name_value,
                        size: sizes.0.clone(),
                        material,
                        material_name,
                        fraction: fraction.value,
                        shape,
                    },
                    sizes,
                    material: sources,
                });
            }
            _ => ok = false,
        }
    }
    if !ok {
        return None;
    }
    let sum: f64 = fractions.iter().map(|f| f.value).sum();
    // Fractions are written by hand; 1e-6 forgives rounding in the last printed digit.
    if (sum - 1.0).abs() > 1e-6 {
        let basis = match fraction_by {
            FractionBasis::Number => "number",
            FractionBasis::Mass => "mass",
        };
        errors.push(fractions[0].error(
            ErrorKind::Invalid,
            format!(
                "the components' {basis} fractions must sum to 1 (they sum to {})",
                rounded(sum)
            ),
        ));
        return None;
    }
    Some((read, fraction_by))
}

/// A size distribution with where its smallest and largest diameters were set.
type SizesWithSources = (SizeDistribution, String, String);

fn read_distribution(
    section: &mut Section<'_>,
    errors: &mut Vec<ConfigError>,
) -> Option<SizesWithSources> {
    let kinds = [
        ("monodisperse", 0u8),
        ("uniform", 1),
        ("normal", 2),
        ("discrete", 3),
    ];
    if !section.has("kind") {
        errors.push(missing(
            section,
            "kind",
            "required: \"monodisperse\", \"uniform\", \"normal\" or \"discrete\"",
        ));
        section.finish(&["kind"], errors);
        return None;
    }
    let kind = section.choice("kind", &kinds, u8::MAX, errors);
    match kind {
        0 => {
            let d = required(section, "diameter", errors);
            section.finish(&["kind", "diameter"], errors);
            let d = d?;
            d.require_positive(errors).then(|| {
                (
                    SizeDistribution::Monodisperse { diameter: d.value },
                    source(&d),
                    source(&d),
                )
            })
        }
        1 => {
            let min = required(section, "min", errors);
            let max = required(section, "max", errors);
            section.finish(&["kind", "min", "max"], errors);
            let (min, max) = (min?, max?);
            let ok = min.require_positive(errors) & max.require_positive(errors);
            if ok && max.value <= min.value {
                errors.push(max.error(
                    ErrorKind::Invalid,
                    format!("must be > {} ({} m)", min.key, number(min.value)),
                ));
                return None;
            }
            ok.then(|| {
                (
                    SizeDistribution::Uniform {
                        min: min.value,
                        max: max.value,
                    },
                    source(&min),
                    source(&max),
                )
            })
        }
        2 => read_normal(section, errors),
        3 => read_discrete(section, errors),
        _ => {
            section.finish(&[], errors);
            None
        }
    }
}

fn read_normal(
    section: &mut Section<'_>,
    errors: &mut Vec<ConfigError>,
) -> Option<SizesWithSources> {
    let mean = required(section, "mean", errors);
    let std_dev = required(section, "std_dev", errors);
    let min = section.float("min", "m", errors);
    let max = section.float("max", "m", errors);
    section.finish(&["kind", "mean", "std_dev", "min", "max"], errors);
    let (mean, std_dev) = (mean?, std_dev?);
    if !(mean.require_positive(errors) & std_dev.require_positive(errors)) {
        return None;
    }
    // Truncation defaults to mean ± 3σ, which keeps 99.7 % of a normal distribution.
    let truncation = |given: &Option<Located<f64>>, sign: f64, end: &str| match given {
        Some(value) => source(value),
        None => format!(
            "{} (default mean {} 3 std_dev = {} m, from {} and {})",
            section.key(end),
            if sign < 0.0 { "−" } else { "+" },
            rounded(mean.value + sign * 3.0 * std_dev.value),
            source(&mean),
            source(&std_dev)
        ),
    };
    let (smallest, largest) = (truncation(&min, -1.0, "min"), truncation(&max, 1.0, "max"));
    let min = min.unwrap_or_else(|| mean.with_value(mean.value - 3.0 * std_dev.value));
    let max = max.unwrap_or_else(|| mean.with_value(mean.value + 3.0 * std_dev.value));
    let mut ok = true;
    if !(min.value > 0.0 && min.value <= mean.value) {
        errors.push(min.error(
            ErrorKind::Invalid,
            "the smallest diameter (default mean − 3 std_dev) must be > 0 and ≤ mean; set min",
        ));
        ok = false;
    }
    if !(max.value.is_finite() && max.value >= mean.value && max.value > min.value) {
        errors.push(max.error(ErrorKind::Invalid, "must be ≥ mean and > min"));
        ok = false;
    }
    ok.then_some((
        SizeDistribution::Normal {
            mean: mean.value,
            std_dev: std_dev.value,
            min: min.value,
            max: max.value,
        },
        smallest,
        largest,
    ))
}

fn read_discrete(
    section: &mut Section<'_>,
    errors: &mut Vec<ConfigError>,
) -> Option<SizesWithSources> {
    let diameters = section.float_array("diameters", "m", errors);
    let fractions = section.float_array("fractions", "", errors);
    for (key, present) in [
        ("diameters", diameters.is_some()),
        ("fractions", fractions.is_some()),
    ] {
        if !present && !section.has(key) {
            errors.push(missing(section, key, "required for kind = \"discrete\""));
        }
    }
    section.finish(&["kind", "diameters", "fractions"], errors);
    let (diameters, fractions) = (diameters?, fractions?);
    let mut ok = true;
    if diameters.is_empty() || diameters.len() != fractions.len() {
        errors.push(missing(
            section,
            "fractions",
            "diameters and fractions must be non-empty and of equal length",
        ));
        return None;
    }
    for d in &diameters {
        ok &= d.require_positive(errors);
    }
    for f in &fractions {
        ok &= f.require_non_negative(errors);
    }
    let sum: f64 = fractions.iter().map(|f| f.value).sum();
    // Fractions are written by hand; 1e-6 forgives rounding in the last printed digit.
    if ok && (sum - 1.0).abs() > 1e-6 {
        errors.push(fractions[0].error(
            ErrorKind::Invalid,
            format!(
                "number fractions must sum to 1 (they sum to {})",
                rounded(sum)
            ),
        ));
        ok = false;
    }
    let smallest = diameters.iter().min_by(|a, b| a.value.total_cmp(&b.value));
    let largest = diameters.iter().max_by(|a, b| a.value.total_cmp(&b.value));
    let (smallest, largest) = (smallest.map(source)?, largest.map(source)?);
    ok.then(|| {
        (
            SizeDistribution::Discrete {
                diameters: diameters.iter().map(|d| d.value).collect(),
                fractions: fractions.iter().map(|f| f.value).collect(),
            },
            smallest,
            largest,
        )
    })
}

/// A number that must be present.
fn required(
    section: &mut Section<'_>,
    key: &str,
    errors: &mut Vec<ConfigError>,
) -> Option<Located<f64>> {
    if !section.has(key) {
        errors.push(missing(section, key, "required"));
        return None;
    }
    section.float(key, "m", errors)
}

fn missing(section: &Section<'_>, key: &str, message: &str) -> ConfigError {
    section.missing(key, message)
}

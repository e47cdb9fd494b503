//! Validation of the `[particles]` table: count, diameters or size distribution, material.

use super::error::{number, rounded, ConfigError, ErrorKind};
use super::particles::{Material, ParticleSpec, SizeDistribution};
use super::reader::{Located, Section};
use super::resolve::MAX_PARTICLE_COUNT;

/// Where a value that a limit derives from was set: `key = value unit`, marked
/// `(default)` when the user did not write it.
pub(crate) fn source(value: &Located<f64>) -> String {
    format!("{} = {}", value.key, value.shown())
}

/// Where the properties of a material table were set (see [`source`]).
#[derive(Clone, Debug)]
pub(crate) struct MaterialSources {
    pub density: String,
    pub shear_modulus: String,
    pub poisson_ratio: String,
}

/// Where the particle properties that limits derive from were set, so that a check on a
/// derived quantity (the Rayleigh time, D ≥ 3 d, Z ≥ d, …) can name its inputs.
#[derive(Clone, Debug)]
pub(crate) struct ParticleSources {
    /// The material's density, shear modulus and Poisson's ratio.
    pub material: MaterialSources,
    /// The key that sets the smallest diameter, with its value.
    pub smallest_diameter: String,
    /// The key that sets the largest diameter, with its value.
    pub largest_diameter: String,
}

/// Reads a material table (density, shear modulus, Poisson's ratio).
pub(crate) fn read_material(
    section: &mut Section<'_>,
    default: Material,
    errors: &mut Vec<ConfigError>,
) -> Option<(Material, MaterialSources)> {
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
            Material {
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

pub(crate) fn read_particles(
    section: &mut Section<'_>,
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
    let size = if section.has("diameter") && section.has("size_distribution") {
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
        let d = section.float_or("diameter", "m", 3.0e-3, errors);
        d.require_positive(errors).then(|| {
            (
                SizeDistribution::Monodisperse { diameter: d.value },
                source(&d),
                source(&d),
            )
        })
    };
    let material = read_material(
        &mut section.section("material", errors),
        paper.material,
        errors,
    );
    section.finish(
        &["count", "diameter", "size_distribution", "material"],
        errors,
    );
    match (ok, size, material) {
        (true, Some((size, smallest, largest)), Some((material, material_sources))) => Some((
            ParticleSpec {
                count: count.value as usize,
                size,
                material,
            },
            ParticleSources {
                material: material_sources,
                smallest_diameter: smallest,
                largest_diameter: largest,
            },
        )),
        _ => None,
    }
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
    ConfigError::new(
        ErrorKind::Missing,
        section.location().clone(),
        section.key(key),
        None,
        message,
    )
}

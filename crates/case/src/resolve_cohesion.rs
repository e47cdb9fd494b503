//! Reads a `cohesion` table, of `[contact]`, `[wall]` or a `[[pairs]]` entry, into the
//! engine's [`dem::Cohesion`] (docs/physics.md §2.4–2.6, docs/case-files.md):
//!
//! ```toml
//! cohesion = { law = "jkr", work_of_adhesion = 0.05 }    # J/m²
//! cohesion = { law = "sjkr", energy_density = 3.0e5 }    # J/m³
//! # m³, N/m, degrees:
//! cohesion = { law = "liquid_bridge", volume = 1.0e-12, surface_tension = 0.072, contact_angle_deg = 20.0 }
//! ```
//!
//! `contact_angle` in radians may stand for `contact_angle_deg`; a resolved case writes it.
//! No table, or `law = "none"`, is a dry contact. A bridge's volume is checked against the
//! case's smallest sphere once the particles are known ([`check_bridge_volumes`]).

use dem::Cohesion;

use crate::error::{ConfigError, ErrorKind};
use crate::reader::{Located, Section};

/// The cohesion laws a case may name.
const LAWS: &[&str] = &["none", "jkr", "sjkr", "liquid_bridge"];

/// Reads the `cohesion` sub-table of `section`; the volumes of liquid bridges, with where
/// they were written, go to `volumes` for [`check_bridge_volumes`]. `None` when it is
/// invalid (its errors recorded).
pub(crate) fn read_cohesion(
    section: &mut Section<'_>,
    volumes: &mut Vec<Located<f64>>,
    errors: &mut Vec<ConfigError>,
) -> Option<Cohesion> {
    if !section.has("cohesion") {
        return Some(Cohesion::None);
    }
    let before = errors.len();
    let mut table = section.section("cohesion", errors);
    let law = table.string("law", errors);
    let cohesion = match law.as_ref().map(|w| w.value.as_str()) {
        None => {
            if !table.has("law") {
                errors.push(ConfigError::new(
                    ErrorKind::Missing,
                    table.location().clone(),
                    table.key("law"),
                    None,
                    format!("required: one of {}", quoted(LAWS)),
                ));
            }
            None
        }
        Some("none") => {
            table.finish(&["law"], errors);
            Some(Cohesion::None)
        }
        Some("jkr") => {
            let w = positive(&mut table, "work_of_adhesion", "J/m²", errors);
            table.finish(&["law", "work_of_adhesion"], errors);
            w.map(|w| Cohesion::Jkr {
                work_of_adhesion: w,
            })
        }
        Some("sjkr") => {
            let k = positive(&mut table, "energy_density", "J/m³", errors);
            table.finish(&["law", "energy_density"], errors);
            k.map(|k| Cohesion::SimplifiedJkr { energy_density: k })
        }
        Some("liquid_bridge") => {
            let volume = table.float("volume", "m³", errors);
            let volume_ok = required(&table, "volume", &volume, "> 0 m³", errors)
                && volume.as_ref().is_some_and(|v| v.require_positive(errors));
            let tension = positive(&mut table, "surface_tension", "N/m", errors);
            let angle = contact_angle(&mut table, errors);
            table.finish(
                &[
                    "law",
                    "volume",
                    "surface_tension",
                    "contact_angle",
                    "contact_angle_deg",
                ],
                errors,
            );
            match (volume, tension, angle) {
                (Some(v), Some(t), Some(angle)) if volume_ok => {
                    volumes.push(v.clone());
                    Some(Cohesion::LiquidBridge {
                        volume: v.value,
                        surface_tension: t,
                        contact_angle: angle,
                    })
                }
                _ => None,
            }
        }
        Some(_) => {
            let word = law.as_ref().expect("a word was read");
            errors.push(word.error(
                ErrorKind::Invalid,
                format!("must be one of {}", quoted(LAWS)),
            ));
            None
        }
    };
    cohesion.filter(|_| errors.len() == before)
}

/// Refuses every liquid bridge volume larger than [`dem::LARGEST_BRIDGE_VOLUME_RATIO`] R³,
/// R the radius of the case's smallest sphere `d_min / 2` [m]: a bridge that could not fit
/// in the pendular regime the force law was fitted to.
pub(crate) fn check_bridge_volumes(
    volumes: &[Located<f64>],
    d_min: f64,
    errors: &mut Vec<ConfigError>,
) {
    let r = 0.5 * d_min;
    let largest = dem::LARGEST_BRIDGE_VOLUME_RATIO * r * r * r;
    for v in volumes {
        if v.value > largest {
            errors.push(v.error(
                ErrorKind::Invalid,
                format!(
                    "a pendular bridge between the smallest spheres (R = {} m) holds at most \
                     {} R³; allowed: (0, {largest:.4e}] m³",
                    crate::error::number(r),
                    dem::LARGEST_BRIDGE_VOLUME_RATIO,
                ),
            ));
        }
    }
}

/// The contact angle θ [rad], given as `contact_angle` [rad] in [0, π/2] or
/// `contact_angle_deg` [°] in [0°, 90°] (one of them); `None` with an error otherwise. A
/// resolved case writes radians, which read back to the same bits.
fn contact_angle(table: &mut Section<'_>, errors: &mut Vec<ConfigError>) -> Option<f64> {
    let radians = table.float("contact_angle", "rad", errors);
    let degrees = table.float("contact_angle_deg", "°", errors);
    let why = "the liquid must wet the grains: a contact angle above 90° makes no pendular bridge";
    match (radians, degrees) {
        (Some(_), Some(d)) => {
            errors.push(d.error(
                ErrorKind::Conflict,
                format!(
                    "give one of {} and {}",
                    table.key("contact_angle"),
                    table.key("contact_angle_deg")
                ),
            ));
            None
        }
        (Some(r), None) => {
            let ok = (0.0..=std::f64::consts::FRAC_PI_2).contains(&r.value);
            if !ok {
                errors.push(r.error(
                    ErrorKind::Invalid,
                    format!("must lie in [0, π/2] rad: {why}"),
                ));
            }
            ok.then_some(r.value)
        }
        (None, Some(d)) => {
            let ok = (0.0..=90.0).contains(&d.value);
            if !ok {
                errors.push(d.error(ErrorKind::Invalid, format!("must lie in [0°, 90°]: {why}")));
            }
            ok.then(|| d.value.to_radians())
        }
        (None, None) => {
            if !table.has("contact_angle") && !table.has("contact_angle_deg") {
                errors.push(ConfigError::new(
                    ErrorKind::Missing,
                    table.location().clone(),
                    table.key("contact_angle_deg"),
                    None,
                    "required by this law (or contact_angle in radians); allowed: [0°, 90°]",
                ));
            }
            None
        }
    }
}

/// A required, finite, positive number at `key`; `None` with an error otherwise.
fn positive(
    table: &mut Section<'_>,
    key: &str,
    unit: &'static str,
    errors: &mut Vec<ConfigError>,
) -> Option<f64> {
    let value = table.float(key, unit, errors);
    let allowed = format!("> 0 {unit}");
    (required(table, key, &value, &allowed, errors)
        && value.as_ref().is_some_and(|v| v.require_positive(errors)))
    .then(|| value.expect("checked").value)
}

/// Records an error when `key` is absent (a mistyped value is reported by the reader).
fn required(
    table: &Section<'_>,
    key: &str,
    value: &Option<Located<f64>>,
    allowed: &str,
    errors: &mut Vec<ConfigError>,
) -> bool {
    if value.is_some() {
        return true;
    }
    if !table.has(key) {
        errors.push(ConfigError::new(
            ErrorKind::Missing,
            table.location().clone(),
            table.key(key),
            None,
            format!("required by this law; allowed: {allowed}"),
        ));
    }
    false
}

/// `"a", "b"` for messages.
fn quoted(words: &[&str]) -> String {
    words
        .iter()
        .map(|w| format!("\"{w}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

//! Why a material table was refused. Every error names the key of the offending entry,
//! relative to the table (`materials.M1.poisson_ratio`, `pairs[3]`), so that a layer that
//! reads the table from a file can prefix it with the file, the table's own key and the line.

/// Relative disagreement allowed between a Young's modulus and a shear modulus given together
/// for one material, measured as |2G(1+ν) − E| / E [-]: one part in 10⁶ accepts a derived
/// modulus written to seven significant digits, and refuses any real disagreement.
pub const MODULUS_TOLERANCE: f64 = 1e-6;

/// A material table that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MaterialTableError {
    /// A required property is absent.
    #[error("{key}: missing; required, {allowed}")]
    Missing {
        /// The absent key.
        key: String,
        /// What it must be, with its unit.
        allowed: &'static str,
    },
    /// A value is NaN or infinite.
    #[error("{key}: {value} is not a finite number; allowed: {allowed}")]
    NotFinite {
        /// The key of the value.
        key: String,
        /// The value given.
        value: f64,
        /// The allowed range, with its unit.
        allowed: &'static str,
    },
    /// A finite value outside its range.
    #[error("{key}: {value} is outside the allowed range {allowed}")]
    OutOfRange {
        /// The key of the value.
        key: String,
        /// The value given.
        value: f64,
        /// The allowed range, with its unit.
        allowed: &'static str,
    },
    /// A material with neither a Young's nor a shear modulus.
    #[error(
        "{key}: neither youngs_modulus nor shear_modulus is given; give one of them [Pa] \
         (E = 2G(1 + ν))"
    )]
    MissingModulus {
        /// The material's key (`materials.NAME`).
        key: String,
    },
    /// A material with both moduli, which disagree beyond round-off.
    #[error(
        "{key}: youngs_modulus {youngs_modulus:e} Pa and shear_modulus {shear_modulus:e} Pa \
         disagree: with poisson_ratio {poisson_ratio}, E = 2G(1 + ν) = {implied_youngs_modulus:e} Pa, \
         a relative difference of {relative_difference:.3e} beyond the allowed {tolerance:e}; \
         give only one of them"
    )]
    InconsistentModuli {
        /// The material's key (`materials.NAME`).
        key: String,
        /// Young's modulus given [Pa].
        youngs_modulus: f64,
        /// Shear modulus given [Pa].
        shear_modulus: f64,
        /// Poisson's ratio given [-].
        poisson_ratio: f64,
        /// 2G(1+ν) [Pa].
        implied_youngs_modulus: f64,
        /// |2G(1+ν) − E| / E [-].
        relative_difference: f64,
        /// The allowed relative difference, [`MODULUS_TOLERANCE`] [-].
        tolerance: f64,
    },
    /// A name that is not among the table's materials.
    #[error("{key}: material \"{name}\" is not defined (defined: {defined})")]
    UnknownMaterial {
        /// Where the name was used.
        key: String,
        /// The name.
        name: String,
        /// The defined names, comma-separated in the table's order.
        defined: String,
    },
    /// A pair listed twice, in either order.
    #[error("{key}: the pair ({a}, {b}) is given twice (first as {first})")]
    DuplicatePair {
        /// The key of the second entry (`pairs[i]`).
        key: String,
        /// The first material of the second entry.
        a: String,
        /// The second material of the second entry.
        b: String,
        /// The key of the first entry.
        first: String,
    },
    /// A pair neither listed nor mixable, because a self-pair is not listed either.
    #[error(
        "{key}: the pair ({a}, {b}) is not listed, and it cannot be mixed from the self-pairs \
         because ({missing}, {missing}) is not listed either; list one of them"
    )]
    UnlistedPair {
        /// The key of the pair list (`pairs`).
        key: String,
        /// The first material.
        a: String,
        /// The second material.
        b: String,
        /// The material whose self-pair is missing.
        missing: String,
    },
    /// An unlisted pair whose self-pairs' cohesions have no mixing rule.
    #[error(
        "{key}: the pair ({a}, {b}) is not listed and the cohesions of ({a}, {a}) and ({b}, {b}) \
         do not mix (different laws, or liquid bridges that differ); list the pair"
    )]
    UnmixableCohesion {
        /// The key of the pair list (`pairs`).
        key: String,
        /// The first material.
        a: String,
        /// The second material.
        b: String,
    },
    /// A name given twice where each must appear once (a list of particle materials).
    #[error("{key}: material \"{name}\" is named twice (first as {first})")]
    RepeatedName {
        /// The key of the second mention.
        key: String,
        /// The name.
        name: String,
        /// The key of the first mention.
        first: String,
    },
}

//! Where the values that a limit derives from were set, so that a check on a derived
//! quantity (the Rayleigh time, D ≥ 3 d, Z ≥ d, …) names the keys and values behind it.
//! The readers of the particles, the materials and each container kind all use these.

use super::reader::Located;

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

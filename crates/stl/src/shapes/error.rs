//! Why a shape builder refused its arguments.

use glam::DVec3;
use thiserror::Error;

/// A builder argument outside its allowed range; the message names the shape, the argument,
/// its value and the range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ShapeError {
    /// A point or vector argument with a non-finite component, or a zero vector.
    #[error("{shape}: {parameter} = ({}, {}, {}) m: must be {allowed}", .value.x, .value.y, .value.z)]
    Vector {
        /// The builder.
        shape: &'static str,
        /// The argument.
        parameter: &'static str,
        /// Its value [m].
        value: DVec3,
        /// What is allowed.
        allowed: &'static str,
    },
    /// A length argument that is non-finite or out of range.
    #[error("{shape}: {parameter} = {value} m: must be {allowed}")]
    Length {
        /// The builder.
        shape: &'static str,
        /// The argument.
        parameter: &'static str,
        /// Its value [m].
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// A number of divisions or segments below the minimum.
    #[error("{shape}: {parameter} = {value}: must be at least {minimum}")]
    Count {
        /// The builder.
        shape: &'static str,
        /// The argument.
        parameter: &'static str,
        /// Its value.
        value: usize,
        /// The smallest allowed value.
        minimum: usize,
    },
    /// More triangles than [`crate::shapes::MAX_TRIANGLES`].
    #[error(
        "{shape}: {per_unit} × {units} triangles exceed the limit of {} triangles",
        crate::shapes::MAX_TRIANGLES
    )]
    TooMany {
        /// The builder.
        shape: &'static str,
        /// Triangles per division or segment.
        per_unit: usize,
        /// Divisions or segments.
        units: usize,
    },
    /// Arguments that make a triangle the reader would reject (e.g. parallel edge vectors).
    #[error("{shape}: triangle {triangle} (counting from 1) would be unusable: {reason} (coordinates in m)")]
    Degenerate {
        /// The builder.
        shape: &'static str,
        /// The triangle, counted from 1.
        triangle: usize,
        /// The defect, as the reader would report it.
        reason: String,
    },
}

/// Rejects a point with a non-finite component.
pub(super) fn finite_point(
    shape: &'static str,
    parameter: &'static str,
    value: DVec3,
) -> Result<DVec3, ShapeError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ShapeError::Vector {
            shape,
            parameter,
            value,
            allowed: "finite",
        })
    }
}

/// Rejects a vector with a non-finite component or of zero length.
pub(super) fn nonzero_vector(
    shape: &'static str,
    parameter: &'static str,
    value: DVec3,
) -> Result<DVec3, ShapeError> {
    if value.is_finite() && value != DVec3::ZERO {
        Ok(value)
    } else {
        Err(ShapeError::Vector {
            shape,
            parameter,
            value,
            allowed: "finite and non-zero",
        })
    }
}

/// Rejects a count below `minimum`.
pub(super) fn at_least(
    shape: &'static str,
    parameter: &'static str,
    value: usize,
    minimum: usize,
) -> Result<usize, ShapeError> {
    if value >= minimum {
        Ok(value)
    } else {
        Err(ShapeError::Count {
            shape,
            parameter,
            value,
            minimum,
        })
    }
}

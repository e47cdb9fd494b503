//! The map from file coordinates to metres: scale, then rotation, then translation.

use glam::{DMat3, DVec3};
use thiserror::Error;

/// A similarity transform from file units to metres, applied in this order:
/// `p_m = translation + R(axis, angle) · (scale · p_file)`.
///
/// The rotation is given as an axis and an angle rather than a 3×3 matrix: every finite,
/// non-zero axis and finite angle is a rotation, whereas a matrix would have to be checked for
/// orthonormality against a tolerance, and an axis with an angle is what a case file states.
/// The fields are private so that every `Transform` has passed [`Transform::new`]'s checks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    scale: f64,
    axis: DVec3,
    angle: f64,
    rotation: DMat3,
    translation: DVec3,
}

/// A [`Transform`] parameter outside its allowed range.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
pub enum TransformError {
    /// The scale is NaN, infinite, zero or negative.
    #[error(
        "transform scale = {value}: must be finite and > 0 (metres per file unit, e.g. 0.001 for millimetres)"
    )]
    Scale {
        /// The rejected scale [m per file unit].
        value: f64,
    },
    /// The rotation axis has a non-finite component or no length to normalise.
    #[error(
        "transform rotation axis = ({}, {}, {}): must be finite and non-zero",
        .value.x, .value.y, .value.z
    )]
    Axis {
        /// The rejected axis (any length; only its direction is used).
        value: DVec3,
    },
    /// The rotation angle is NaN or infinite.
    #[error("transform rotation angle = {value} rad: must be finite")]
    Angle {
        /// The rejected angle [rad].
        value: f64,
    },
    /// The translation has a non-finite component.
    #[error(
        "transform translation = ({}, {}, {}) m: must be finite",
        .value.x, .value.y, .value.z
    )]
    Translation {
        /// The rejected translation [m].
        value: DVec3,
    },
}

impl Transform {
    /// The transform that keeps file coordinates as they are (the file is in metres).
    pub fn identity() -> Self {
        Self {
            scale: 1.0,
            axis: DVec3::Z,
            angle: 0.0,
            rotation: DMat3::IDENTITY,
            translation: DVec3::ZERO,
        }
    }

    /// Scale [m per file unit], then rotation by `angle` [rad] about `axis` (right-hand rule;
    /// any length, only the direction is used), then `translation` [m].
    ///
    /// Fails if `scale` is not finite and > 0, `axis` is not finite and non-zero, `angle` is
    /// not finite, or `translation` is not finite.
    pub fn new(
        scale: f64,
        axis: DVec3,
        angle: f64,
        translation: DVec3,
    ) -> Result<Self, TransformError> {
        if !(scale.is_finite() && scale > 0.0) {
            return Err(TransformError::Scale { value: scale });
        }
        let unit_axis = unit_axis(axis).ok_or(TransformError::Axis { value: axis })?;
        if !angle.is_finite() {
            return Err(TransformError::Angle { value: angle });
        }
        if !translation.is_finite() {
            return Err(TransformError::Translation { value: translation });
        }
        Ok(Self {
            scale,
            axis: unit_axis,
            angle,
            rotation: DMat3::from_axis_angle(unit_axis, angle),
            translation,
        })
    }

    /// Only a scale [m per file unit], e.g. `Transform::scaled(0.001)` for a file in
    /// millimetres. Fails as [`Transform::new`] does for the scale.
    pub fn scaled(scale: f64) -> Result<Self, TransformError> {
        Self::new(scale, DVec3::Z, 0.0, DVec3::ZERO)
    }

    /// The scale [m per file unit].
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The rotation axis, of unit length.
    pub fn axis(&self) -> DVec3 {
        self.axis
    }

    /// The rotation angle [rad].
    pub fn angle(&self) -> f64 {
        self.angle
    }

    /// The translation [m].
    pub fn translation(&self) -> DVec3 {
        self.translation
    }

    /// Maps a point in file units to metres: scale, rotate, translate.
    pub fn apply(&self, point: DVec3) -> DVec3 {
        self.translation + self.rotation * (self.scale * point)
    }
}

impl Default for Transform {
    fn default() -> Self {
        Self::identity()
    }
}

/// The axis scaled to unit length, or `None` if it is non-finite or zero. Dividing by the
/// largest component first keeps tiny axes (e.g. 1e-200) from underflowing to zero length.
fn unit_axis(axis: DVec3) -> Option<DVec3> {
    let largest = axis.abs().max_element();
    if axis.is_finite() && largest > 0.0 {
        (axis / largest).try_normalize()
    } else {
        None
    }
}

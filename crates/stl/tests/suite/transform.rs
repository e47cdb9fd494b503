//! The transform: its order (scale, rotate, translate) and the check of every parameter.

use glam::DVec3;
use stl::Transform;

#[test]
fn scale_then_rotate_then_translate() {
    let transform = Transform::new(
        2.0,
        DVec3::new(0.0, 0.0, 5.0),
        std::f64::consts::PI,
        DVec3::new(10.0, 0.0, 0.0),
    )
    .unwrap();
    // (1, 0, 0) ×2 → (2, 0, 0), half a turn about z → (−2, 0, 0), + (10, 0, 0) → (8, 0, 0).
    // Translating before scaling would give (−22, 0, 0). Tolerance: sin(π) evaluates to 1.2e-16.
    assert!(
        transform
            .apply(DVec3::X)
            .abs_diff_eq(DVec3::new(8.0, 0.0, 0.0), 1e-14),
        "{}",
        transform.apply(DVec3::X)
    );
    assert_eq!(transform.axis(), DVec3::Z, "the axis is normalised");
}

#[test]
fn identity_and_default_leave_points_alone() {
    let p = DVec3::new(0.1, -2.5, 3e-7);
    assert_eq!(Transform::identity().apply(p), p);
    assert_eq!(Transform::default(), Transform::identity());
}

#[test]
fn a_tiny_axis_is_still_a_direction() {
    let transform = Transform::new(1.0, DVec3::new(0.0, 1e-200, 0.0), 0.5, DVec3::ZERO).unwrap();
    assert_eq!(transform.axis(), DVec3::Y);
}

#[test]
fn each_bad_parameter_is_named_with_its_value() {
    let cases = [
        (
            Transform::new(-1.0, DVec3::Z, 0.0, DVec3::ZERO),
            "transform scale = -1: must be finite and > 0 (metres per file unit, e.g. 0.001 for \
             millimetres)",
        ),
        (
            Transform::scaled(f64::NAN),
            "transform scale = NaN: must be finite and > 0 (metres per file unit, e.g. 0.001 for \
             millimetres)",
        ),
        (
            Transform::new(0.0, DVec3::Z, 0.0, DVec3::ZERO),
            "transform scale = 0: must be finite and > 0 (metres per file unit, e.g. 0.001 for \
             millimetres)",
        ),
        (
            Transform::new(1.0, DVec3::ZERO, 0.0, DVec3::ZERO),
            "transform rotation axis = (0, 0, 0): must be finite and non-zero",
        ),
        (
            Transform::new(1.0, DVec3::new(1.0, f64::INFINITY, 0.0), 0.0, DVec3::ZERO),
            "transform rotation axis = (1, inf, 0): must be finite and non-zero",
        ),
        (
            Transform::new(1.0, DVec3::Z, f64::INFINITY, DVec3::ZERO),
            "transform rotation angle = inf rad: must be finite",
        ),
        (
            Transform::new(1.0, DVec3::Z, 0.0, DVec3::new(0.0, f64::NAN, 0.0)),
            "transform translation = (0, NaN, 0) m: must be finite",
        ),
    ];
    for (result, expected) in cases {
        assert_eq!(result.unwrap_err().to_string(), expected);
    }
}

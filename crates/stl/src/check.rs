//! The checks every triangle passes before it is transformed into metres: distinct vertices,
//! an area that is not negligible, coordinates that stay finite.

use glam::DVec3;

use crate::error::{Location, StlError};
use crate::mesh::Triangle;
use crate::transform::Transform;

/// The smallest allowed ratio of a triangle's area to the square of its longest edge,
/// `area / L²` (dimensionless). An equilateral triangle has √3/4 ≈ 0.433. At 1e-12 the cross
/// product that gives the triangle's normal is still ten thousand times larger than its
/// double-precision rounding (about 1e-16 · L²), so the normal's direction is good to about
/// 1e-4; collinear corners, written to any precision, fall below it.
pub const DEGENERACY_RATIO: f64 = 1e-12;

/// Where a triangle came from, for its error messages.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Origin<'a> {
    /// The file's source name.
    pub file: &'a str,
    /// The triangle, counted from 1.
    pub triangle: usize,
    /// The facet's first line or the record's offset.
    pub location: Location,
}

/// Checks a triangle in file units and maps it to metres: no two vertices equal, the area at
/// least [`DEGENERACY_RATIO`] · L², every transformed coordinate finite. Coordinates are
/// already known to be finite.
pub(crate) fn accept(
    origin: Origin<'_>,
    vertices: Triangle,
    transform: &Transform,
) -> Result<Triangle, StlError> {
    if let Some(defect) = defect(&vertices) {
        return Err(defect.located(origin));
    }
    to_metres(origin, &vertices, transform)
}

/// Why a triangle of finite vertices is unusable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Defect {
    /// Vertices `first` and `second` (counted from 1) are the same `point`.
    Repeated {
        first: usize,
        second: usize,
        point: DVec3,
    },
    /// `area / L²` is below [`DEGENERACY_RATIO`]; `longest_edge` is L.
    Degenerate { area_ratio: f64, longest_edge: f64 },
    /// An edge whose components are beyond the double range (coordinates of opposite sign
    /// near ±1.8e308).
    EdgeOverflow,
}

impl Defect {
    /// The reader's error for this defect at `origin`.
    fn located(self, origin: Origin<'_>) -> StlError {
        let file = origin.file.into();
        let (triangle, location) = (origin.triangle, origin.location);
        match self {
            Defect::Repeated {
                first,
                second,
                point,
            } => StlError::RepeatedVertex {
                file,
                triangle,
                location,
                first,
                second,
                point,
            },
            Defect::Degenerate {
                area_ratio,
                longest_edge,
            } => StlError::Degenerate {
                file,
                triangle,
                location,
                area_ratio,
                longest_edge,
            },
            Defect::EdgeOverflow => StlError::EdgeOverflow {
                file,
                triangle,
                location,
            },
        }
    }
}

impl std::fmt::Display for Defect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Defect::Repeated {
                first,
                second,
                point,
            } => write!(
                f,
                "vertices {first} and {second} are the same point ({}, {}, {})",
                point.x, point.y, point.z
            ),
            Defect::Degenerate {
                area_ratio,
                longest_edge,
            } => write!(
                f,
                "degenerate: area / L² = {area_ratio:e} with longest edge L = {longest_edge}; \
                 allowed: area / L² ≥ {DEGENERACY_RATIO:e}"
            ),
            Defect::EdgeOverflow => {
                write!(f, "an edge is beyond the double range")
            }
        }
    }
}

/// The first defect of a triangle with finite vertices: repeated vertices, then overflowing
/// edges, then an area below [`DEGENERACY_RATIO`] · L².
pub(crate) fn defect(v: &Triangle) -> Option<Defect> {
    for (first, second) in [(0, 1), (0, 2), (1, 2)] {
        if v[first] == v[second] {
            return Some(Defect::Repeated {
                first: first + 1,
                second: second + 1,
                point: v[first],
            });
        }
    }
    // Edges divided by their largest component, so that squares and cross products stay
    // finite for any finite edge; only an edge beyond the double range itself overflows.
    let edges = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let unit = edges
        .iter()
        .map(|e| e.abs().max_element())
        .fold(0.0, f64::max);
    if !unit.is_finite() {
        return Some(Defect::EdgeOverflow);
    }
    let scaled = edges.map(|e| e / unit);
    let longest_squared = scaled
        .iter()
        .map(|e| e.length_squared())
        .fold(0.0, f64::max);
    let area = 0.5 * scaled[0].cross(scaled[2]).length();
    let area_ratio = area / longest_squared;
    (area_ratio < DEGENERACY_RATIO).then(|| Defect::Degenerate {
        area_ratio,
        longest_edge: unit * longest_squared.sqrt(),
    })
}

/// The vertices in metres, or an error naming the first vertex the transform makes non-finite.
fn to_metres(
    origin: Origin<'_>,
    v: &Triangle,
    transform: &Transform,
) -> Result<Triangle, StlError> {
    let metres = v.map(|p| transform.apply(p));
    match metres.iter().position(|p| !p.is_finite()) {
        None => Ok(metres),
        Some(vertex) => Err(StlError::Overflow {
            file: origin.file.into(),
            triangle: origin.triangle,
            location: origin.location,
            vertex: vertex + 1,
            scale: transform.scale(),
        }),
    }
}

/// Whether every coordinate of `point` is finite; the first one that is not, as
/// (axis letter, index) otherwise.
pub(crate) fn first_non_finite(point: DVec3) -> Option<(char, usize)> {
    ['x', 'y', 'z']
        .into_iter()
        .enumerate()
        .find(|&(i, _)| !point[i].is_finite())
        .map(|(i, axis)| (axis, i))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_ratio_of_a_right_triangle_at_any_size() {
        // Legs a and a: area a²/2, longest edge a·√2, so area / L² = 1/4 at every size, even
        // where a² itself overflows (1e200) or underflows (1e-200).
        for a in [1.0, 1e200, 1e-200] {
            let v = [DVec3::ZERO, a * DVec3::X, a * DVec3::Y];
            assert_eq!(defect(&v), None);
            let sliver = [DVec3::ZERO, a * DVec3::X, a * DVec3::new(0.5, 1e-13, 0.0)];
            match defect(&sliver) {
                Some(Defect::Degenerate {
                    area_ratio,
                    longest_edge,
                }) => {
                    // 1e-13 / 2, up to the rounding of the scaled cross product.
                    assert!((area_ratio / 5e-14 - 1.0).abs() < 1e-12, "{area_ratio}");
                    assert_eq!(longest_edge, a);
                }
                other => panic!("size {a}: {other:?}"),
            }
        }
    }

    #[test]
    fn first_non_finite_names_the_axis() {
        assert_eq!(
            first_non_finite(DVec3::new(1.0, f64::NAN, 2.0)),
            Some(('y', 1))
        );
        assert_eq!(first_non_finite(DVec3::ONE), None);
    }
}

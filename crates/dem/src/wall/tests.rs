//! Tests of the wall shapes: closest points of a polygon's face, edges and corners, the
//! refusal of bad shapes, and the cheap far test against the exact distance.

use super::*;
use approx::assert_relative_eq;

fn square() -> Wall {
    // Unit square in the z = 0 plane.
    let v = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
    ];
    Wall::polygon(v, WallMaterial::Rigid, Interaction::fan2023()).unwrap()
}

// Closest points are exact geometry; 1e-14 covers round-off of unit-sized coordinates.
const GEOM_TOL: f64 = 1e-14;

#[test]
fn polygon_face_edge_and_corner_contacts_use_the_closest_point() {
    let w = square();
    let (p, d) = w.closest_point(DVec3::new(0.3, 0.4, 0.2));
    assert_relative_eq!(
        p.distance(DVec3::new(0.3, 0.4, 0.0)),
        0.0,
        epsilon = GEOM_TOL
    );
    assert_relative_eq!(d, 0.2, epsilon = GEOM_TOL);
    let (p, d) = w.closest_point(DVec3::new(1.3, 0.5, 0.4));
    assert_relative_eq!(
        p.distance(DVec3::new(1.0, 0.5, 0.0)),
        0.0,
        epsilon = GEOM_TOL
    );
    assert_relative_eq!(d, 0.5, epsilon = GEOM_TOL);
    let (p, d) = w.closest_point(DVec3::new(-0.3, -0.4, 0.0));
    assert_relative_eq!(p.distance(DVec3::ZERO), 0.0, epsilon = GEOM_TOL);
    assert_relative_eq!(d, 0.5, epsilon = GEOM_TOL);
    let n = w.contact_normal(DVec3::new(-0.3, -0.4, 0.0), p, d);
    assert_relative_eq!(
        n.distance(DVec3::new(-0.6, -0.8, 0.0)),
        0.0,
        epsilon = GEOM_TOL
    );
}

#[test]
fn triangles_and_planes_are_accepted_and_non_convex_polygons_refused() {
    let tri = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
    assert!(Wall::polygon(tri, WallMaterial::Rigid, Interaction::fan2023()).is_ok());
    let dart = vec![
        DVec3::ZERO,
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(1.0, 0.2, 0.0),
        DVec3::new(1.0, 2.0, 0.0),
    ];
    assert!(matches!(
        Wall::polygon(dart, WallMaterial::Rigid, Interaction::fan2023()),
        Err(WallError::NotConvexPlanar(_))
    ));
    assert!(Wall::plane(
        DVec3::ZERO,
        DVec3::ZERO,
        WallMaterial::Rigid,
        Interaction::fan2023()
    )
    .is_err());
    let plane = Wall::plane(
        DVec3::ZERO,
        DVec3::new(0.0, 0.0, 2.0),
        WallMaterial::Rigid,
        Interaction::fan2023(),
    )
    .unwrap();
    assert_relative_eq!(
        plane.closest_point(DVec3::new(5.0, 1.0, 0.25)).1,
        0.25,
        epsilon = GEOM_TOL
    );
}

#[test]
fn translating_a_wall_moves_its_closest_point() {
    let mut w = square();
    w.translate(DVec3::new(0.0, 0.0, -0.5));
    assert_relative_eq!(
        w.closest_point(DVec3::new(0.5, 0.5, 0.0)).1,
        0.5,
        epsilon = GEOM_TOL
    );
}

#[test]
fn the_plane_test_never_rejects_a_point_within_reach_of_a_polygon() {
    // `certainly_beyond` may only skip points whose true distance is at least `reach`;
    // points all around a tilted quadrilateral, at distances on both sides of the reach,
    // must each be skipped only when `closest_point` puts them that far. Some must be
    // skipped, or the test would pass with a test that never skips.
    use rand::{Rng, SeedableRng};
    let w = Wall::polygon(
        vec![
            DVec3::new(0.0, 0.0, 0.2),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.2),
        ],
        WallMaterial::Rigid,
        Interaction::fan2023(),
    )
    .unwrap();
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(3);
    let mut skipped = 0;
    for _ in 0..20_000 {
        let x = DVec3::new(
            3.0 * rng.gen::<f64>() - 1.0,
            3.0 * rng.gen::<f64>() - 1.0,
            2.0 * rng.gen::<f64>() - 1.0,
        );
        let reach = 0.5 * rng.gen::<f64>();
        if w.certainly_beyond(x, reach) {
            skipped += 1;
            assert!(w.closest_point(x).1 >= reach, "{x} skipped within {reach}");
        }
    }
    assert!(skipped > 1000, "only {skipped} skipped");
    let plane = Wall::plane(
        DVec3::ZERO,
        DVec3::Z,
        WallMaterial::Rigid,
        Interaction::fan2023(),
    )
    .unwrap();
    assert!(!plane.certainly_beyond(DVec3::new(0.0, 0.0, 9.0), 1.0));
}

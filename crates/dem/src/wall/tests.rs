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

/// The square [0, 1]² of the plane z = 0 as n × n squares of two triangles each.
fn tiles(n: usize) -> Vec<[DVec3; 3]> {
    let a = 1.0 / n as f64;
    let at = |i: usize, j: usize| DVec3::new(i as f64 * a, j as f64 * a, 0.0);
    (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .flat_map(|(i, j)| {
            [
                [at(i, j), at(i + 1, j), at(i + 1, j + 1)],
                [at(i, j), at(i + 1, j + 1), at(i, j + 1)],
            ]
        })
        .collect()
}

fn mesh_of(triangles: &[[DVec3; 3]]) -> Mesh {
    Mesh::new(triangles).unwrap()
}

#[test]
fn a_mesh_welds_shared_corners() {
    // 4 × 4 squares: 5 × 5 grid points, whatever the 32 triangles repeat.
    let m = mesh_of(&tiles(4));
    assert_eq!((m.len(), m.vertex_count()), (32, 25));
}

#[test]
fn bad_meshes_are_refused_naming_the_triangle() {
    assert_eq!(Mesh::new(&[]).unwrap_err(), WallError::EmptyMesh);
    let mut t = tiles(2);
    t[5][1] = DVec3::new(f64::NAN, 0.0, 0.0);
    let e = Mesh::new(&t).unwrap_err().to_string();
    assert!(e.contains("triangle 5") && e.contains("not finite"), "{e}");
    let mut t = tiles(2);
    t[3] = [DVec3::ZERO, DVec3::X, 2.0 * DVec3::X];
    let e = Mesh::new(&t).unwrap_err().to_string();
    assert!(e.contains("triangle 3") && e.contains("degenerate"), "{e}");
}

#[test]
fn a_flat_mesh_gives_one_contact_anywhere_and_a_fold_one_per_face() {
    // Over a fine flat mesh: a single contact, along +z, at the plane's distance, at faces,
    // edges and corners alike (exact coordinates in binary fractions).
    let m = mesh_of(&tiles(8));
    let (mut scratch, mut out) = (MeshScratch::default(), Vec::new());
    for (x, y) in [
        (0.3, 0.2),
        (0.25, 0.1),
        (0.25, 0.25),
        (0.375, 0.5),
        (0.31, 0.31),
    ] {
        m.contacts(DVec3::new(x, y, 0.2), 0.25, &mut scratch, &mut out);
        assert_eq!(out.len(), 1, "at ({x}, {y})");
        assert_relative_eq!(out[0].distance, 0.2, epsilon = GEOM_TOL);
        assert_relative_eq!(out[0].normal.distance(DVec3::Z), 0.0, epsilon = GEOM_TOL);
    }
    // A floor meeting a wall x = 0 (a concave fold): a sphere in the corner touches both.
    let mut fold = tiles(2);
    fold.extend(
        tiles(2)
            .iter()
            .map(|t| t.map(|v| DVec3::new(0.0, v.y, v.x))),
    );
    let m = mesh_of(&fold);
    m.contacts(DVec3::new(0.1, 0.5, 0.1), 0.15, &mut scratch, &mut out);
    let mut normals: Vec<DVec3> = out.iter().map(|c| c.normal).collect();
    normals.sort_by(|a, b| a.x.total_cmp(&b.x));
    assert_eq!(normals.len(), 2);
    assert_relative_eq!(normals[0].distance(DVec3::Z), 0.0, epsilon = GEOM_TOL);
    assert_relative_eq!(normals[1].distance(DVec3::X), 0.0, epsilon = GEOM_TOL);
    // The same fold seen from outside (a convex ridge): the sphere beyond the edge touches
    // the edge alone, along the line from the edge to its centre.
    m.contacts(DVec3::new(-0.1, 0.5, -0.1), 0.15, &mut scratch, &mut out);
    assert_eq!(out.len(), 1);
    let diagonal = DVec3::new(-1.0, 0.0, -1.0).normalize();
    assert_relative_eq!(out[0].normal.distance(diagonal), 0.0, epsilon = GEOM_TOL);
}

#[test]
fn the_index_finds_what_a_search_of_every_triangle_finds() {
    // Distances from random points (a fixed generator) to a mesh of 512 triangles, by the
    // index and by every triangle: equal wherever the nearest lies within reach.
    let m = mesh_of(&tiles(16));
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..500 {
        let x = DVec3::new(1.4 * next() - 0.2, 1.4 * next() - 0.2, 0.4 * next() - 0.2);
        let reach = 0.05 + 0.1 * next();
        let exact = (0..m.len())
            .map(|t| {
                let (p, _) = super::triangle::closest_point(x, m.triangle(t));
                p.distance(x)
            })
            .fold(f64::INFINITY, f64::min);
        let indexed = m.distance_within(x, reach);
        if exact < reach {
            assert_relative_eq!(indexed, exact, epsilon = GEOM_TOL);
        } else {
            assert!(indexed >= reach - GEOM_TOL);
        }
        assert_eq!(m.comes_within(x, reach), exact < reach);
    }
}

#[test]
fn long_slanted_triangles_are_found_as_by_a_search_of_every_triangle() {
    // A 45° cone from an orifice of radius 0.3 to a rim of radius 1, one strip of two
    // triangles per segment (as CAD exports give): the triangles' bounding boxes reach deep
    // into the cone, and the index's plane test must refuse exactly the triangles that the
    // closest point would, also for points within rounding of a plane at the reach.
    let k = 24;
    let ring = |r: f64, z: f64| -> Vec<DVec3> {
        (0..k)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / k as f64;
                DVec3::new(r * a.cos(), r * a.sin(), z)
            })
            .collect()
    };
    let (low, high) = (ring(0.3, 0.0), ring(1.0, 0.7));
    let cone: Vec<[DVec3; 3]> = (0..k)
        .flat_map(|i| {
            let j = (i + 1) % k;
            [[low[i], low[j], high[j]], [low[i], high[j], high[i]]]
        })
        .collect();
    let m = mesh_of(&cone);
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let brute = |x: DVec3, reach: f64| -> Vec<u32> {
        (0..m.len())
            .filter(|&t| {
                let (p, _) = super::triangle::closest_point(x, m.triangle(t));
                (x - p).length_squared() < reach * reach
            })
            .map(|t| t as u32)
            .collect()
    };
    let mut out = Vec::new();
    let mut points: Vec<(DVec3, f64)> = (0..2000)
        .map(|_| {
            let x = DVec3::new(2.2 * next() - 1.1, 2.2 * next() - 1.1, 0.9 * next() - 0.1);
            (x, 0.02 + 0.1 * next())
        })
        .collect();
    // Points off a face's centre by the reach itself, a hair inside and a hair outside it.
    for t in 0..m.len() {
        let c = m.triangle(t);
        let centre = (c[0] + c[1] + c[2]) / 3.0;
        let normal = (c[1] - c[0]).cross(c[2] - c[0]).normalize();
        for factor in [1.0 - 1e-12, 1.0, 1.0 + 1e-12, -1.0] {
            points.push((centre + normal * 0.05 * factor, 0.05));
        }
    }
    let mut found = 0;
    for (x, reach) in points {
        m.triangles_near(x, reach, &mut out);
        let indexed: Vec<u32> = out.iter().map(|n| n.triangle).collect();
        assert_eq!(indexed, brute(x, reach), "at {x} within {reach}");
        assert_eq!(m.comes_within(x, reach), !indexed.is_empty(), "at {x}");
        found += indexed.len();
    }
    // The random points must meet the wall often enough for the comparison to mean something.
    assert!(found > 500, "only {found} triangles found near the points");
}

#[test]
fn a_turned_and_moved_mesh_answers_in_the_world() {
    // Turned a quarter turn about x (z goes to +y) and moved up by 2: the floor z = 0
    // becomes the wall y = 0 over z ∈ [1, 2]; a point 0.1 in front of it touches along +y.
    let mut m = mesh_of(&tiles(4));
    m.rotate_about(
        DVec3::ZERO,
        glam::DQuat::from_rotation_x(-std::f64::consts::FRAC_PI_2),
    );
    m.translate(DVec3::new(0.0, 0.0, 2.0));
    let (mut scratch, mut out) = (MeshScratch::default(), Vec::new());
    m.contacts(DVec3::new(0.5, 0.1, 1.5), 0.2, &mut scratch, &mut out);
    assert_eq!(out.len(), 1);
    assert_relative_eq!(out[0].distance, 0.1, epsilon = 1e-12);
    assert_relative_eq!(
        out[0].point.distance(DVec3::new(0.5, 0.0, 1.5)),
        0.0,
        epsilon = 1e-12
    );
    assert_relative_eq!(out[0].normal.distance(DVec3::Y), 0.0, epsilon = 1e-12);
}

#[test]
fn walls_survive_a_checkpoint_round_trip_with_their_motion() {
    // Every shape and a motion: the stored form must give back an equal wall.
    let i = Interaction::fan2023();
    let mut mesh = Wall::mesh(&tiles(3), WallMaterial::Rigid, i).unwrap();
    mesh.set_motion(WallMotion {
        velocity: DVec3::X,
        angular_velocity: DVec3::new(0.0, 0.0, 2.0),
        centre: DVec3::Y,
        displaced: true,
    })
    .unwrap();
    mesh.translate(DVec3::splat(0.25));
    let walls = [
        mesh,
        Wall::cylinder(DVec3::ZERO, DVec3::Z, 2.0, 0.5, WallMaterial::Rigid, i).unwrap(),
        Wall::frustum(
            DVec3::ZERO,
            DVec3::X,
            1.0,
            [0.5, 0.2],
            WallMaterial::Rigid,
            i,
        )
        .unwrap(),
        square(),
    ];
    for w in walls {
        let bytes = postcard::to_allocvec(&w).unwrap();
        let back: Wall = postcard::from_bytes(&bytes).unwrap();
        assert_eq!(back, w);
    }
}
